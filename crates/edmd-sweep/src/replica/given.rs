//! A replica's start from a configuration in a file (`init.from`): the file's particles, checked
//! against the replica's grid point (N, dimension, box) before anything runs.

use edmd_core::{EdmdError, InitParams, ParticleInit, Vector};

use crate::configuration::{load, spin_width};
use crate::spec::{FromSpec, Replica};

/// Sets replica `r`'s start (`p.given`, `p.given_spins`) to the file's particles: positions and
/// velocities from the file, radii and masses from it where it has them, else the replica's own;
/// its spins where it has them and the grains are rough (smooth grains carry none).
pub(super) fn start_from<const D: usize>(
    from: &FromSpec,
    r: &Replica,
    p: &mut InitParams<D>,
) -> Result<(), EdmdError> {
    let refuse = |why: String| EdmdError::invalid("init.from", &from.file, why);
    let c = load(from, D).map_err(refuse)?;
    if c.n() != r.n {
        return Err(refuse(format!(
            "the file holds {} particles, the grid point N = {}: give the grid the file's N (n, or phi and box that make it)",
            c.n(),
            r.n
        )));
    }
    let sides = r.sides();
    if let Some(b) = &c.box_len {
        let differs = b.len() != D
            || b.iter()
                .zip(&sides)
                .any(|(x, y)| (x - y).abs() > 1e-9 * y.abs().max(1.0));
        if differs {
            return Err(refuse(format!(
                "the file's box is {b:?}, the grid point's {sides:?}: give the grid the file's phi or box"
            )));
        }
    }
    let vector = |v: &[f64], i: usize| Vector::<D>::from_fn(|a, _| v[i * D + a]);
    let width = spin_width(D);
    p.given_spins = c.spin.as_ref().filter(|_| r.rough()).map(|w| {
        w.chunks(width)
            .map(|x| {
                if D == 2 {
                    [0.0, 0.0, x[0]]
                } else {
                    [x[0], x[1], x[2]]
                }
            })
            .collect()
    });
    let particles = (0..r.n)
        .map(|i| {
            let radius = c
                .radius
                .as_ref()
                .map(|x| x[i])
                .or_else(|| p.radii.as_ref().map(|x| x[i]))
                .unwrap_or(p.radius);
            let mass = c
                .mass
                .as_ref()
                .map(|x| x[i])
                .or_else(|| p.masses.as_ref().map(|x| x[i]))
                .unwrap_or(p.mass * (radius / p.radius).powi(D as i32));
            ParticleInit {
                pos: vector(&c.position, i),
                vel: vector(&c.velocity, i),
                radius,
                mass,
            }
        })
        .collect();
    p.given = Some(particles);
    Ok(())
}

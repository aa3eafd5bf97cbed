//! The stress of a sheared box over one `run` call, as the runner samples it between two samples
//! (`replica/shear.rs`): the kinetic pressure tensor Σ m V_a V_b / V of the peculiar velocities at
//! the end, plus the collisional one, the engine's virial sums over the interval / (V Δt); and the
//! dissipation rate per unit volume.

use edmd_core::Engine;

/// (P_ab as D rows, dissipation rate) of the interval of length `dt` since the engine's shear sums
/// were restarted.
pub(crate) fn sheared_stress<const D: usize>(e: &dyn Engine<D>, dt: f64) -> (Vec<Vec<f64>>, f64) {
    let volume: f64 = e.box_len().iter().product();
    let c = e.counters();
    let mut p = vec![vec![0.0; D]; D];
    for (v, m) in e.peculiar_velocities().iter().zip(e.masses()) {
        for (a, row) in p.iter_mut().enumerate() {
            for (b, x) in row.iter_mut().enumerate() {
                *x += m * v[a] * v[b] / volume;
            }
        }
    }
    for (a, row) in p.iter_mut().enumerate() {
        for (b, x) in row.iter_mut().enumerate() {
            *x += c.virial_tensor[a][b] / (volume * dt);
        }
    }
    (p, c.dissipated / (volume * dt))
}

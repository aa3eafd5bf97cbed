//! Initial states: random non-overlapping placement in O(N), centred lattices for dense states, and
//! velocities (uniform in (−v, v) as in the thesis, or Maxwellian) with zero total momentum and the
//! exact target temperature.

use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::calendar::{Calendar, PaulCalendar};
use crate::cells::{CellGrid, NONE};
use crate::{
    Boundary, CollisionRule, EdmdError, Elastic, ParticleInit, SimParams, Simulation, Stop, Vector,
};

/// How particles are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Placement {
    /// Random sequential addition through the cell grid (2D up to φ ≈ 0.45, 3D up to ≈ 0.3).
    Random,
    /// A centred lattice (2D up to φ ≈ 0.9, 3D up to ≈ 0.68), then melted elastically.
    Lattice,
    /// Random below φ = 0.4 (2D) or 0.25 (3D), lattice above.
    Auto,
}

/// Velocity distribution before momentum removal and temperature scaling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Velocities {
    /// Each component uniform in (−1, 1), as in the thesis (kurtosis 1.4 in 2D instead of 2).
    Uniform,
    /// Maxwell–Boltzmann.
    Maxwell,
}

/// Parameters of an initial state of monodisperse (or, with `radii`, polydisperse) particles.
#[derive(Debug, Clone, PartialEq)]
pub struct InitParams<const D: usize> {
    /// Number of particles.
    pub n: usize,
    /// Box sides.
    pub box_len: Vector<D>,
    /// Radius of every particle (default 0.5, i.e. σ = 1), unless `radii` is set.
    pub radius: f64,
    /// Per-particle radii (polydisperse); overrides `radius`.
    pub radii: Option<Vec<f64>>,
    /// Mass of a particle of radius `radius` (default 1); with `radii`, masses scale as r^D.
    pub mass: f64,
    /// Placement method (default `Auto`).
    pub placement: Placement,
    /// Velocity distribution (default `Maxwell`).
    pub velocities: Velocities,
    /// Target temperature T0 (default 1).
    pub temperature: f64,
    /// Seed of the random stream.
    pub seed: u64,
    /// Elastic collisions per particle run after placement (default 0 for random placement, 20 for a
    /// lattice); counters are reset afterwards.
    pub melt_tau: Option<f64>,
    /// Event-loop settings (default: tuned to the density).
    pub sim: Option<SimParams>,
}

impl<const D: usize> InitParams<D> {
    /// `n` particles of diameter 1 at packing fraction `phi` in a square (cubic) box.
    pub fn with_packing(n: usize, phi: f64) -> Result<Self, EdmdError> {
        if n == 0 {
            return Err(EdmdError::invalid("N", n, "need at least one particle"));
        }
        if !(phi > 0.0 && phi < 1.0) {
            return Err(EdmdError::invalid(
                "phi",
                phi,
                "packing fraction must lie in (0, 1)",
            ));
        }
        let side = (n as f64 * unit_volume::<D>(0.5) / phi).powf(1.0 / D as f64);
        Ok(Self::in_box(n, Vector::<D>::repeat(side)))
    }

    /// `n` particles of diameter 1 in a given box.
    pub fn in_box(n: usize, box_len: Vector<D>) -> Self {
        InitParams {
            n,
            box_len,
            radius: 0.5,
            radii: None,
            mass: 1.0,
            placement: Placement::Auto,
            velocities: Velocities::Maxwell,
            temperature: 1.0,
            seed: 0,
            melt_tau: None,
            sim: None,
        }
    }

    /// Packing fraction of the state.
    pub fn packing_fraction(&self) -> f64 {
        let vol: f64 = match &self.radii {
            Some(r) => r.iter().map(|&r| unit_volume::<D>(r)).sum(),
            None => self.n as f64 * unit_volume::<D>(self.radius),
        };
        vol / self.box_len.iter().product::<f64>()
    }

    fn validate(&self) -> Result<(), EdmdError> {
        if self.n < 2 {
            return Err(EdmdError::invalid(
                "N",
                self.n,
                "need at least two particles (momentum is set to zero)",
            ));
        }
        if !(self.radius > 0.0 && self.radius.is_finite()) {
            return Err(EdmdError::invalid(
                "radius",
                self.radius,
                "must be positive",
            ));
        }
        if let Some(r) = &self.radii {
            if r.len() != self.n {
                return Err(EdmdError::invalid(
                    "radii",
                    r.len(),
                    format!("need one radius per particle (N = {})", self.n),
                ));
            }
            if let Some(bad) = r.iter().find(|&&r| !(r > 0.0 && r.is_finite())) {
                return Err(EdmdError::invalid(
                    "radii",
                    bad,
                    "every radius must be positive",
                ));
            }
        }
        if !(self.mass > 0.0 && self.mass.is_finite()) {
            return Err(EdmdError::invalid("mass", self.mass, "must be positive"));
        }
        if !(self.temperature > 0.0 && self.temperature.is_finite()) {
            return Err(EdmdError::invalid(
                "temperature",
                self.temperature,
                "must be positive",
            ));
        }
        if let Some(m) = self.melt_tau {
            if !(m >= 0.0 && m.is_finite()) {
                return Err(EdmdError::invalid("melt_tau", m, "must be ≥ 0"));
            }
        }
        let phi = self.packing_fraction();
        if !(phi < 1.0) {
            return Err(EdmdError::invalid(
                "phi",
                phi,
                "packing fraction must be below 1",
            ));
        }
        Ok(())
    }

    /// Builds the simulation: places particles, draws velocities, melts a lattice elastically, sets
    /// zero momentum and the exact temperature, and resets the counters.
    pub fn build<B: Boundary, R: CollisionRule>(
        &self,
        rule: R,
    ) -> Result<Simulation<D, B, R>, EdmdError> {
        self.build_with_calendar::<B, R, PaulCalendar>(rule)
    }

    /// [`Self::build`] with a chosen event calendar (e.g. [`crate::HeapCalendar`] as an oracle).
    pub fn build_with_calendar<B: Boundary, R: CollisionRule, C: Calendar>(
        &self,
        rule: R,
    ) -> Result<Simulation<D, B, R, C>, EdmdError> {
        self.validate()?;
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(self.seed);
        let radii: Vec<f64> = self
            .radii
            .clone()
            .unwrap_or_else(|| vec![self.radius; self.n]);
        let phi = self.packing_fraction();
        let lattice = match self.placement {
            Placement::Random => false,
            Placement::Lattice => true,
            Placement::Auto => phi > if D == 2 { 0.4 } else { 0.25 },
        };
        let positions = if lattice {
            if self.radii.is_some() {
                return Err(EdmdError::invalid(
                    "placement",
                    "lattice",
                    "lattice starts need equal radii; use random placement",
                ));
            }
            lattice_positions::<D, B>(self.n, &self.box_len, self.radius, phi, &mut rng)?
        } else {
            random_positions::<D, B>(&radii, &self.box_len, phi, &mut rng)?
        };
        let masses: Vec<f64> = radii
            .iter()
            .map(|&r| self.mass * (r / self.radius).powi(D as i32))
            .collect();
        let velocities = draw_velocities::<D>(&masses, self.velocities, self.temperature, &mut rng);
        let particles: Vec<ParticleInit<D>> = (positions.into_iter().zip(velocities))
            .zip(radii.into_iter().zip(masses))
            .map(|((pos, vel), (radius, mass))| ParticleInit {
                pos,
                vel,
                radius,
                mass,
            })
            .collect();
        // The random stream of random collision rules derives from the state's seed.
        let params = self.sim.unwrap_or_else(|| SimParams {
            seed: self.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 1,
            ..SimParams::for_density::<D>(phi)
        });
        let melt = self.melt_tau.unwrap_or(if lattice { 20.0 } else { 0.0 });
        let sim = if melt > 0.0 {
            let mut sim =
                Simulation::<D, B, Elastic, C>::new(self.box_len, particles, Elastic, params)?;
            sim.run(Stop::Tau(melt));
            sim.with_rule(rule)
        } else {
            Simulation::<D, B, R, C>::new(self.box_len, particles, rule, params)?
        };
        let mut sim = sim;
        let t = sim.temperature();
        if melt > 0.0 && t > 0.0 {
            sim.scale_velocities((self.temperature / t).sqrt());
        }
        sim.reset_counters();
        Ok(sim)
    }
}

/// Volume of a D-ball of radius r.
pub fn unit_volume<const D: usize>(r: f64) -> f64 {
    if D == 2 {
        std::f64::consts::PI * r * r
    } else {
        4.0 / 3.0 * std::f64::consts::PI * r.powi(3)
    }
}

/// Random sequential addition, checking overlaps through a cell grid: O(N) for moderate φ.
fn random_positions<const D: usize, B: Boundary>(
    radii: &[f64],
    box_len: &Vector<D>,
    phi: f64,
    rng: &mut Xoshiro256PlusPlus,
) -> Result<Vec<Vector<D>>, EdmdError> {
    const ATTEMPTS: usize = 10_000;
    let max_d = 2.0 * radii.iter().cloned().fold(0.0, f64::max);
    let mut grid = CellGrid::<D>::new(box_len, max_d, max_d, radii.len())?;
    // Largest particles first: they are the hardest to fit.
    let mut order: Vec<usize> = (0..radii.len()).collect();
    order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]));
    let mut placed = vec![Vector::<D>::zeros(); radii.len()];
    let mut links = vec![NONE; radii.len()];
    for (count, &i) in order.iter().enumerate() {
        let r = radii[i];
        let mut ok = false;
        for _ in 0..ATTEMPTS {
            let mut x = Vector::<D>::zeros();
            for a in 0..D {
                x[a] = if B::is_wall(a) {
                    r + rng.random::<f64>() * (box_len[a] - 2.0 * r)
                } else {
                    rng.random::<f64>() * box_len[a]
                };
            }
            if !overlaps_any::<D, B>(&grid, &links, &placed, radii, box_len, &x, r) {
                placed[i] = x;
                let idx = grid.index(&grid.coords_of(&x));
                grid.insert(&mut links, i as u32, idx);
                ok = true;
                break;
            }
        }
        if !ok {
            return Err(EdmdError::TooDense {
                method: "random",
                phi,
                max: count as f64 / radii.len() as f64 * phi,
            });
        }
    }
    Ok(placed)
}

fn overlaps_any<const D: usize, B: Boundary>(
    grid: &CellGrid<D>,
    links: &[u32],
    placed: &[Vector<D>],
    radii: &[f64],
    box_len: &Vector<D>,
    x: &Vector<D>,
    r: f64,
) -> bool {
    let c = grid.coords_of(x);
    for code in 0..3usize.pow(D as u32) {
        let mut rest = code;
        let mut idx = 0;
        let mut inside = true;
        for a in 0..D {
            let off = (rest % 3) as i32 - 1;
            rest /= 3;
            let n = grid.n[a] as i32;
            let y = c[a] as i32 + off;
            if (y < 0 || y >= n) && B::is_wall(a) {
                inside = false;
                break;
            }
            idx += y.rem_euclid(n) as usize * grid.stride[a];
        }
        if !inside {
            continue;
        }
        let mut k = grid.first(idx);
        while k != NONE {
            let mut dr = x - placed[k as usize];
            for a in 0..D {
                if !B::is_wall(a) {
                    dr[a] -= box_len[a] * (dr[a] / box_len[a]).round();
                }
            }
            let s = r + radii[k as usize];
            if dr.norm_squared() < s * s {
                return true;
            }
            k = links[k as usize];
        }
    }
    false
}

/// A centred lattice (two sites per cell: corner and body centre; hexagonal in 2D at the right
/// aspect, body-centred cubic in 3D) with the cell counts that maximise the nearest-neighbour
/// distance; vacancies are spread at random when there are more sites than particles.
fn lattice_positions<const D: usize, B: Boundary>(
    n: usize,
    box_len: &Vector<D>,
    radius: f64,
    phi: f64,
    rng: &mut Xoshiro256PlusPlus,
) -> Result<Vec<Vector<D>>, EdmdError> {
    // On a walled axis the sites span [r, L − r] and the last body-centre site touches the far end.
    let span = |a: usize| {
        if B::is_wall(a) {
            box_len[a] - 2.0 * radius
        } else {
            box_len[a]
        }
    };
    let spacing = |a: usize, cells: usize| {
        if B::is_wall(a) {
            span(a) / (cells as f64 - 0.5)
        } else {
            span(a) / cells as f64
        }
    };
    let min_dist = |cells: &[usize; D]| {
        let mut sq = 0.0;
        let mut best = f64::INFINITY;
        for a in 0..D {
            let s = spacing(a, cells[a]);
            sq += s * s;
            // A walled axis with one cell has no same-sublattice neighbour along it.
            if !(B::is_wall(a) && cells[a] == 1) {
                best = f64::min(best, s);
            }
        }
        best.min(0.5 * sq.sqrt())
    };
    let target = n.div_ceil(2);
    let guess = (target as f64).powf(1.0 / D as f64);
    let hi = (guess * 4.0).ceil() as usize + 2;
    let mut best: Option<([usize; D], f64)> = None;
    let mut cells = [1usize; D];
    // Enumerate the first D − 1 counts; the last is the smallest that fits the particles.
    let outer = hi.pow(D as u32 - 1);
    for code in 0..outer {
        let mut rest = code;
        let mut prod = 1usize;
        for a in 0..D - 1 {
            cells[a] = rest % hi + 1;
            rest /= hi;
            prod *= cells[a];
        }
        cells[D - 1] = target.div_ceil(prod).max(1);
        let d = min_dist(&cells);
        if best.is_none_or(|b| d > b.1) {
            best = Some((cells, d));
        }
    }
    let (cells, dist) = best.expect("at least one lattice");
    if dist < 2.0 * radius * (1.0 + 1e-9) {
        // φ scales as (σ/dist)^D at fixed sites: the largest φ this lattice reaches.
        let max = phi * (dist / (2.0 * radius)).powi(D as i32);
        return Err(EdmdError::TooDense {
            method: "lattice",
            phi,
            max,
        });
    }
    let mut sites: Vec<Vector<D>> = Vec::with_capacity(2 * cells.iter().product::<usize>());
    let total: usize = cells.iter().product();
    for code in 0..total {
        let mut rest = code;
        let mut idx = [0usize; D];
        for a in 0..D {
            idx[a] = rest % cells[a];
            rest /= cells[a];
        }
        for b in 0..2 {
            let mut x = Vector::<D>::zeros();
            for a in 0..D {
                let u = idx[a] as f64 + 0.5 * b as f64;
                x[a] = if B::is_wall(a) {
                    // The far site can land one ulp beyond L − r.
                    (radius + u * spacing(a, cells[a])).min(box_len[a] - radius)
                } else {
                    (u + 0.25) * spacing(a, cells[a])
                };
            }
            sites.push(x);
        }
    }
    // Keep a random subset of n sites.
    for i in 0..n {
        let j = rng.random_range(i..sites.len());
        sites.swap(i, j);
    }
    sites.truncate(n);
    Ok(sites)
}

/// Draws velocities, removes the centre-of-mass velocity and scales to temperature `t0` exactly.
pub fn draw_velocities<const D: usize>(
    masses: &[f64],
    dist: Velocities,
    t0: f64,
    rng: &mut impl Rng,
) -> Vec<Vector<D>> {
    let mut v: Vec<Vector<D>> = masses
        .iter()
        .map(|_| {
            Vector::<D>::from_fn(|_, _| match dist {
                Velocities::Uniform => rng.random::<f64>() * 2.0 - 1.0,
                Velocities::Maxwell => rng.sample::<f64, _>(StandardNormal),
            })
        })
        .collect();
    let mtot: f64 = masses.iter().sum();
    let vcm = v
        .iter()
        .zip(masses)
        .fold(Vector::<D>::zeros(), |acc, (v, m)| acc + v * *m)
        / mtot;
    let mut ke2 = 0.0;
    for (v, m) in v.iter_mut().zip(masses) {
        *v -= vcm;
        ke2 += m * v.norm_squared();
    }
    let t = ke2 / (D as f64 * masses.len() as f64);
    let s = (t0 / t).sqrt();
    for v in &mut v {
        *v *= s;
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Periodic, Walls};

    #[test]
    fn random_start_has_exact_temperature_and_no_momentum() {
        let mut p = InitParams::<2>::with_packing(500, 0.2).unwrap();
        p.velocities = Velocities::Uniform;
        p.temperature = 1.0 / 3.0;
        let sim = p.build::<Periodic, _>(Elastic).unwrap();
        let o = sim.observe();
        assert!((o.temperature - 1.0 / 3.0).abs() < 1e-14);
        assert!(o.momentum.norm() < 1e-13 * o.momentum_scale);
        assert!(sim.deepest_overlap().unwrap().2 < 0.0);
    }

    #[test]
    fn lattice_reaches_dense_states() {
        for (phi, walls) in [(0.7, false), (0.7, true)] {
            let mut p = InitParams::<2>::with_packing(400, phi).unwrap();
            p.melt_tau = Some(0.0);
            let sim = if walls {
                p.build::<Walls, _>(Elastic).map(|s| s.deepest_overlap())
            } else {
                p.build::<Periodic, _>(Elastic).map(|s| s.deepest_overlap())
            };
            assert!(sim.unwrap().unwrap().2 <= 1e-12, "phi {phi} walls {walls}");
        }
        let mut p = InitParams::<3>::with_packing(1000, 0.5).unwrap();
        p.melt_tau = Some(0.0);
        assert!(
            p.build::<Periodic, _>(Elastic)
                .unwrap()
                .deepest_overlap()
                .unwrap()
                .2
                <= 1e-12
        );
    }

    #[test]
    fn too_dense_is_an_error_naming_the_limit() {
        let mut p = InitParams::<2>::with_packing(400, 0.6).unwrap();
        p.placement = Placement::Random;
        let e = p.build::<Periodic, _>(Elastic).unwrap_err();
        assert!(
            matches!(
                e,
                EdmdError::TooDense {
                    method: "random",
                    ..
                }
            ),
            "{e}"
        );
        let p = InitParams::<2>::with_packing(400, 0.95).unwrap();
        let e = p.build::<Periodic, _>(Elastic).unwrap_err().to_string();
        assert!(e.contains("lattice") && e.contains("0.9500"), "{e}");
    }

    #[test]
    fn bad_parameters_name_the_field() {
        let e = InitParams::<2>::with_packing(0, 0.2)
            .unwrap_err()
            .to_string();
        assert!(e.contains("N = 0"), "{e}");
        let e = InitParams::<2>::with_packing(10, 1.2)
            .unwrap_err()
            .to_string();
        assert!(e.contains("phi = 1.2"), "{e}");
        let mut p = InitParams::<2>::with_packing(10, 0.1).unwrap();
        p.radius = -1.0;
        let e = p.build::<Periodic, _>(Elastic).unwrap_err().to_string();
        assert!(e.contains("radius = -1"), "{e}");
        let p = InitParams::<2>::in_box(10, Vector::<2>::new(2.5, 10.0));
        let e = p.build::<Periodic, _>(Elastic).unwrap_err().to_string();
        assert!(e.contains("Lx = 2.5"), "{e}");
    }
}

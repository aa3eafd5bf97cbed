//! The observables of a sheared (Lees–Edwards) replica, sampled beside the common ones: the pressure
//! tensor (kinetic and collisional), the collision frequency, the dissipation rate, the stream
//! velocity and density profiles, and the images' offset (PHYSICS.md §7, docs/output.md).

use edmd_core::Engine;

use crate::classify::{Class, Classification};

/// Bins of a profile along a box side: about one per diameter, at most 32 (a profile is an
/// average over the bins' grains; 32 bins keep N/32 of them in each).
pub fn profile_bins(side: f64) -> usize {
    (side.floor() as usize).clamp(1, 32)
}

/// The clock and collision count at the previous sample; the engine's shear sums (stress and
/// dissipation) restart there, so that each interval is summed at its own precision.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
struct Mark {
    time: f64,
    collisions: u64,
}

/// Per sample of a sheared replica (empty elsewhere). Tensors are D × D, row-major.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShearSeries {
    /// P_ab = P^k_ab + P^c_ab (NaN at the first sample, whose collisional part has no interval).
    pub pressure_tensor: Vec<Vec<f64>>,
    /// P^k_ab = Σ m V_a V_b / V with the peculiar velocities V, at the sample.
    pub pressure_tensor_kinetic: Vec<Vec<f64>>,
    /// Collisions per particle and unit time, 2 ΔC/(N Δt), since the previous sample.
    pub collision_frequency: Vec<f64>,
    /// Kinetic energy the collisions removed per unit volume and time since the previous sample; in
    /// a steady flow it equals the shear's work −a P_xy.
    pub dissipation_rate: Vec<f64>,
    /// Mean v_x (lab frame) in bins along y: the stream profile u_x(y) = a (y − L_y/2) of a
    /// homogeneous flow (NaN in an empty bin).
    pub velocity_profile: Vec<Vec<f64>>,
    /// Number density in bins along y.
    pub density_profile_y: Vec<Vec<f64>>,
    /// Number density in bins along x.
    pub density_profile_x: Vec<Vec<f64>>,
    /// Displacement Δ along x of the images above the box, in [0, L_x).
    pub box_offset: Vec<f64>,
    mark: Option<Mark>,
}

impl ShearSeries {
    /// Samples `sim` now (masses in the original particle order).
    pub(super) fn sample<const D: usize>(&mut self, sim: &mut dyn Engine<D>, masses: &[f64]) {
        let sides = *sim.box_len();
        let volume: f64 = sides.iter().product();
        let n = sim.len() as f64;
        let mut kinetic = vec![0.0; D * D];
        for (v, m) in sim.peculiar_velocities().iter().zip(masses) {
            for a in 0..D {
                for b in 0..D {
                    kinetic[a * D + b] += m * v[a] * v[b] / volume;
                }
            }
        }
        let c = *sim.counters();
        let now = sim.time();
        let (collisional, frequency, dissipation) = match self.mark {
            Some(m) if now > m.time => {
                let dt = now - m.time;
                let mut p = vec![0.0; D * D];
                for a in 0..D {
                    for b in 0..D {
                        p[a * D + b] = c.virial_tensor[a][b] / (volume * dt);
                    }
                }
                (
                    p,
                    2.0 * (c.pair_collisions - m.collisions) as f64 / (n * dt),
                    c.dissipated / (volume * dt),
                )
            }
            _ => (vec![f64::NAN; D * D], f64::NAN, f64::NAN),
        };
        // A second sample at the same time keeps the sums for the next interval.
        if self.mark.is_none_or(|m| now > m.time) {
            self.mark = Some(Mark {
                time: now,
                collisions: c.pair_collisions,
            });
            sim.restart_shear_sums();
        }
        self.pressure_tensor.push(
            kinetic
                .iter()
                .zip(&collisional)
                .map(|(k, c)| k + c)
                .collect(),
        );
        self.pressure_tensor_kinetic.push(kinetic);
        self.collision_frequency.push(frequency);
        self.dissipation_rate.push(dissipation);

        let (bx, by) = (profile_bins(sides[0]), profile_bins(sides[1]));
        let (wx, wy) = (sides[0] / bx as f64, sides[1] / by as f64);
        let (mut count_x, mut count_y, mut vx_y) = (vec![0.0; bx], vec![0.0; by], vec![0.0; by]);
        for (x, v) in sim.positions().iter().zip(sim.velocities()) {
            let i = ((x[0] / wx) as usize).min(bx - 1);
            let j = ((x[1] / wy) as usize).min(by - 1);
            count_x[i] += 1.0;
            count_y[j] += 1.0;
            vx_y[j] += v[0];
        }
        self.velocity_profile.push(
            vx_y.iter()
                .zip(&count_y)
                .map(|(s, &k)| if k > 0.0 { s / k } else { f64::NAN })
                .collect(),
        );
        let slab = |w: f64, side: f64| volume * w / side;
        self.density_profile_y
            .push(count_y.iter().map(|k| k / slab(wy, sides[1])).collect());
        self.density_profile_x
            .push(count_x.iter().map(|k| k / slab(wx, sides[0])).collect());
        self.box_offset.push(sim.shear_offset());
    }
}

/// The excess density contrast of one profile: the variance of n_b / n̄ over its B bins less the
/// (B − 1)/N that N grains placed independently give (0 ± √(2/B)·B/N for a uniform gas; about 1 for
/// a band holding most grains in a third of the box).
pub fn contrast(profile: &[f64], n: usize) -> f64 {
    let b = profile.len() as f64;
    let mean = profile.iter().sum::<f64>() / b;
    if mean <= 0.0 {
        return f64::NAN;
    }
    let var = profile
        .iter()
        .map(|x| (x / mean - 1.0).powi(2))
        .sum::<f64>()
        / b;
    var - (b - 1.0) / n as f64
}

/// Homogeneous or inhomogeneous shear flow, from the density profiles along y (bands parallel to
/// the flow) and along x (clusters), each averaged over the last half of the samples: inhomogeneous
/// when either excess contrast reaches `threshold` (the classifier's `cluster_density`: the same
/// Poisson-corrected density variance, PHYSICS.md §7.3).
pub fn classify(s: &ShearSeries, n: usize, threshold: f64) -> Classification {
    let late = |rows: &[Vec<f64>]| {
        let from = rows.len() / 2;
        let c: Vec<f64> = rows[from..].iter().map(|p| contrast(p, n)).collect();
        c.iter().sum::<f64>() / c.len().max(1) as f64
    };
    let (cy, cx) = (late(&s.density_profile_y), late(&s.density_profile_x));
    let class = if s.density_profile_y.is_empty() {
        Class::Failed
    } else if cy >= threshold || cx >= threshold {
        Class::Inhomogeneous
    } else {
        Class::Homogeneous
    };
    Classification {
        class,
        shear_onset: f64::NAN,
        cluster_onset: f64::NAN,
        haff_deviation: Vec::new(),
        note: format!(
            "density contrast over the last half: {cy:.3} along y, {cx:.3} along x (threshold {threshold})"
        ),
    }
}

//! Order parameters of the free-cooling regimes (PHYSICS.md §5.1), in O(N) from one configuration.
//!
//! All are scale-free (invariant under a common scaling of the velocities), so they can be evaluated
//! on the simulation's internal velocities at any depth of cooling.
//!
//! * **f_flow**: the noise-corrected share of kinetic energy in the coarse-grained flow on a G^D grid,
//!   `(K_flow/K − f₀)/(1 − f₀)` with `K_flow = Σ_c |P_c|²/(2 M_c)` and `f₀` = occupied cells / N.
//! * **S⊥(k₁)**: the transverse velocity structure factor at the smallest wavevector,
//!   `|Σ v_b e^{−i k r_a}|² / (N T/m)`, maximised over the axis `a` of k and the transverse axis `b`.
//!   On a walled axis the free-slip shear mode `cos(π r_a / L_a)` replaces the plane wave (and the sum
//!   is doubled so that uncorrelated velocities give 1 in both cases).
//! * **δ²ρ**: the Poisson-corrected variance of the cell counts, `(Var N_c − ⟨N_c⟩)/⟨N_c⟩²`.
//! * **f₂ₓ**: the fraction of particles in cells holding more than twice the mean count.
//! * **S_ρ(k₁)**: the density structure factor at the smallest wavevector, `|Σ e^{−i k r_a}|²/N`
//!   (walled axes: `2|Σ cos(π r_a/L_a)|²/N`), maximised over the axes.

use crate::Vector;

/// The order parameters of one configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrderParameters {
    /// Noise-corrected flow-energy fraction.
    pub f_flow: f64,
    /// Transverse velocity structure factor at k₁ (1 for uncorrelated velocities).
    pub s_perp: f64,
    /// Poisson-corrected density contrast (0 for an ideal gas; slightly negative for hard disks).
    pub delta_rho2: f64,
    /// Fraction of particles in cells with more than twice the mean count.
    pub f_2x: f64,
    /// Density structure factor at k₁.
    pub s_rho: f64,
}

/// Computes the order parameters on a grid of `grid` cells per axis.
///
/// `walls[a]` says whether axis `a` has walls (sine/cosine modes) or is periodic (plane waves).
/// Positions must lie in the box. Velocities may carry any common scale factor.
pub fn order_parameters<const D: usize>(
    positions: &[Vector<D>],
    velocities: &[Vector<D>],
    masses: &[f64],
    box_len: &Vector<D>,
    walls: [bool; D],
    grid: usize,
) -> OrderParameters {
    let n = positions.len();
    assert!(n > 0 && velocities.len() == n && masses.len() == n);
    assert!(grid >= 1);
    let cells = grid.pow(D as u32);
    let mut count = vec![0u32; cells];
    let mut mass_c = vec![0.0f64; cells];
    let mut mom_c = vec![Vector::<D>::zeros(); cells];
    let mut kinetic = 0.0;
    let mut cell_of = Vec::with_capacity(n);
    for ((r, v), &m) in positions.iter().zip(velocities).zip(masses) {
        let mut c = 0usize;
        for a in (0..D).rev() {
            let x = ((r[a] / box_len[a]) * grid as f64).floor();
            let i = (x.max(0.0) as usize).min(grid - 1);
            c = c * grid + i;
        }
        cell_of.push(c);
        count[c] += 1;
        mass_c[c] += m;
        mom_c[c] += v * m;
        kinetic += 0.5 * m * v.norm_squared();
    }
    // Flow energy.
    let mut k_flow = 0.0;
    let mut occupied = 0usize;
    for c in 0..cells {
        if count[c] > 0 {
            occupied += 1;
            k_flow += mom_c[c].norm_squared() / (2.0 * mass_c[c]);
        }
    }
    let f0 = occupied as f64 / n as f64;
    let f_raw = if kinetic > 0.0 { k_flow / kinetic } else { 0.0 };
    let f_flow = if f0 < 1.0 {
        (f_raw - f0) / (1.0 - f0)
    } else {
        0.0
    };
    // Density contrast.
    let mean = n as f64 / cells as f64;
    let var = count
        .iter()
        .map(|&c| (c as f64 - mean).powi(2))
        .sum::<f64>()
        / cells as f64;
    let delta_rho2 = (var - mean) / (mean * mean);
    let dense: usize = cell_of
        .iter()
        .filter(|&&c| count[c] as f64 > 2.0 * mean)
        .count();
    let f_2x = dense as f64 / n as f64;
    // Structure factors at the smallest wavevector of each axis.
    let temperature_m = 2.0 * kinetic / (D as f64 * n as f64); // T (with the masses folded in)
    let (s_perp, s_rho) =
        structure_factors(positions, velocities, masses, box_len, walls, temperature_m);
    OrderParameters {
        f_flow,
        s_perp,
        delta_rho2,
        f_2x,
        s_rho,
    }
}

/// The largest transverse-momentum (S⊥) and density structure factors at the smallest wavevector
/// of each axis (sine and cosine modes along walled axes, plane waves along periodic ones);
/// `temperature_m` is T with the masses folded in.
fn structure_factors<const D: usize>(
    positions: &[Vector<D>],
    velocities: &[Vector<D>],
    masses: &[f64],
    box_len: &Vector<D>,
    walls: [bool; D],
    temperature_m: f64,
) -> (f64, f64) {
    let n = positions.len();
    let mut s_perp: f64 = 0.0;
    let mut s_rho: f64 = 0.0;
    for a in 0..D {
        let phase = |r: &Vector<D>| -> (f64, f64) {
            let x = r[a] / box_len[a];
            if walls[a] {
                (
                    (std::f64::consts::PI * x).cos() * std::f64::consts::SQRT_2,
                    0.0,
                )
            } else {
                let t = 2.0 * std::f64::consts::PI * x;
                (t.cos(), -t.sin())
            }
        };
        let mut rho = (0.0, 0.0);
        let mut trans = [(0.0f64, 0.0f64); D];
        for ((r, v), &m) in positions.iter().zip(velocities).zip(masses) {
            let (c, s) = phase(r);
            rho.0 += c;
            rho.1 += s;
            let w = m.sqrt();
            for b in 0..D {
                trans[b].0 += w * v[b] * c;
                trans[b].1 += w * v[b] * s;
            }
        }
        s_rho = s_rho.max((rho.0 * rho.0 + rho.1 * rho.1) / n as f64);
        if temperature_m > 0.0 {
            for (b, t) in trans.iter().enumerate() {
                if b != a {
                    s_perp = s_perp.max((t.0 * t.0 + t.1 * t.1) / (n as f64 * temperature_m));
                }
            }
        }
    }
    (s_perp, s_rho)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_distr::StandardNormal;
    use rand_xoshiro::Xoshiro256PlusPlus;

    type V2 = Vector<2>;

    /// Points on a square lattice of `m × m` nodes filling a box of side `l`.
    fn lattice(m: usize, l: f64) -> Vec<V2> {
        (0..m * m)
            .map(|i| {
                V2::new(
                    ((i % m) as f64 + 0.5) * l / m as f64,
                    ((i / m) as f64 + 0.5) * l / m as f64,
                )
            })
            .collect()
    }

    #[test]
    fn uncorrelated_gas_reads_zero_flow_and_unit_structure_factors() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let (n, l, reps) = (4096, 100.0, 200);
        let (mut f, mut d2, mut sp, mut sr) = (0.0, 0.0, 0.0, 0.0);
        for _ in 0..reps {
            let pos: Vec<V2> = (0..n)
                .map(|_| V2::new(rng.random::<f64>() * l, rng.random::<f64>() * l))
                .collect();
            let vel: Vec<V2> = (0..n)
                .map(|_| V2::new(rng.sample(StandardNormal), rng.sample(StandardNormal)))
                .collect();
            let o = order_parameters(&pos, &vel, &vec![1.0; n], &V2::new(l, l), [false, false], 8);
            f += o.f_flow;
            d2 += o.delta_rho2;
            sp += o.s_perp;
            sr += o.s_rho;
        }
        let r = reps as f64;
        // Means over 200 draws; each value's spread is ≲ 1/√(cells) for f and δ², O(1) for S.
        assert!((f / r).abs() < 0.01, "f_flow {}", f / r);
        assert!((d2 / r).abs() < 0.01, "delta_rho2 {}", d2 / r);
        // The max of two independent unit exponentials has mean 1.5.
        assert!((sp / r - 1.5).abs() < 0.15, "s_perp {}", sp / r);
        assert!((sr / r - 1.5).abs() < 0.15, "s_rho {}", sr / r);
    }

    #[test]
    fn pure_shear_wave_matches_closed_forms() {
        // v_y = U sin(2πx/L) on a lattice: S⊥ = N exactly, and the grid-averaged flow keeps the
        // fraction (sin(π/G)/(π/G))² of the energy (cell averages of a sine).
        let (m, l, g) = (64, 64.0, 8);
        let pos = lattice(m, l);
        let n = pos.len();
        let k = 2.0 * std::f64::consts::PI / l;
        let vel: Vec<V2> = pos
            .iter()
            .map(|r| V2::new(0.0, 0.7 * (k * r[0]).sin()))
            .collect();
        let o = order_parameters(&pos, &vel, &vec![1.0; n], &V2::new(l, l), [false, false], g);
        assert!(
            (o.s_perp / n as f64 - 1.0).abs() < 1e-10,
            "s_perp {}",
            o.s_perp
        );
        let x = std::f64::consts::PI / g as f64;
        // Lattice sums replace the integral: per cell 8 columns sampled at their midpoints.
        let sampled: f64 = {
            let cols = m / g;
            let avg = |c: usize| -> f64 {
                (0..cols)
                    .map(|j| (k * ((c * cols + j) as f64 + 0.5)).sin())
                    .sum::<f64>()
                    / cols as f64
            };
            let num: f64 = (0..g).map(|c| avg(c).powi(2)).sum::<f64>() / g as f64;
            num / 0.5
        };
        assert!((sampled - (x.sin() / x).powi(2)).abs() < 0.01);
        let f0 = (g * g) as f64 / n as f64;
        let expect = (sampled - f0) / (1.0 - f0);
        assert!(
            (o.f_flow - expect).abs() < 1e-10,
            "f_flow {} vs {expect}",
            o.f_flow
        );
        assert!(
            o.delta_rho2 < 0.0 && o.f_2x == 0.0,
            "a lattice is not clustered"
        );
    }

    #[test]
    fn a_dense_quarter_reads_as_clustered() {
        // Every particle in the lower-left quarter: 16 of 64 cells hold n/16 each.
        let (m, l, g) = (32, 64.0, 8);
        let pos: Vec<V2> = lattice(m, l / 2.0);
        let n = pos.len() as f64;
        let vel = vec![V2::new(1.0, 0.0); pos.len()];
        let o = order_parameters(
            &pos,
            &vel,
            &vec![1.0; pos.len()],
            &V2::new(l, l),
            [false, false],
            g,
        );
        let mean = n / 64.0;
        let var = (16.0 * (n / 16.0 - mean).powi(2) + 48.0 * mean * mean) / 64.0;
        assert!((o.delta_rho2 - (var - mean) / (mean * mean)).abs() < 1e-12);
        assert_eq!(o.f_2x, 1.0);
        assert!(o.s_rho > 0.3 * n, "s_rho {}", o.s_rho);
        assert!(
            o.f_flow.abs() < 1e-12 || o.f_flow > 0.99,
            "uniform motion is all flow"
        );
    }

    #[test]
    fn walled_axes_use_the_free_slip_mode() {
        // v_y = U cos(πx/L) with walls along x: the real mode holds the whole amplitude, S⊥ = 2N
        // (a periodic wave splits it between ±k: S⊥ = N).
        let (m, l) = (48, 48.0);
        let pos = lattice(m, l);
        let n = pos.len();
        let vel: Vec<V2> = pos
            .iter()
            .map(|r| V2::new(0.0, (std::f64::consts::PI * r[0] / l).cos()))
            .collect();
        let o = order_parameters(&pos, &vel, &vec![1.0; n], &V2::new(l, l), [true, true], 8);
        assert!(
            (o.s_perp / n as f64 - 2.0).abs() < 1e-10,
            "s_perp {}",
            o.s_perp
        );
    }
}

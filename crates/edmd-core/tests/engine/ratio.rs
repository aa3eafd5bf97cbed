//! The ratio of two fluctuating sums (R/T, T_light/T_heavy) measured over seeds without the bias of
//! averaging ratios: E[X/Y] exceeds E[X]/E[Y] by about var(Y)/E[Y]², which is 2/(d N) for a
//! temperature of N particles (1–2 % at N ≈ 100). The seeds are split into `GROUPS` groups; in each,
//! X and Y are summed over the group's seeds at every sample point before they are divided, which
//! divides that bias by the seeds per group; the groups' spread gives the standard error.

/// Groups the seeds are split into.
pub const GROUPS: usize = 8;

/// Mean relative deviation of X/Y from `reference` (one value per sample point) and its standard
/// error. `per_seed[s][t]` holds (X, Y) of seed `s` at sample point `t`.
pub fn deviation(per_seed: &[Vec<(f64, f64)>], reference: &[f64]) -> (f64, f64) {
    assert!(
        per_seed.len() >= 2 * GROUPS,
        "need at least {} seeds",
        2 * GROUPS
    );
    let points = reference.len();
    let devs: Vec<f64> = (0..GROUPS)
        .map(|g| {
            let mut sum = 0.0;
            for t in 0..points {
                let (mut x, mut y) = (0.0, 0.0);
                for s in per_seed.iter().skip(g).step_by(GROUPS) {
                    x += s[t].0;
                    y += s[t].1;
                }
                sum += x / y / reference[t] - 1.0;
            }
            sum / points as f64
        })
        .collect();
    let m = devs.iter().sum::<f64>() / GROUPS as f64;
    let var = devs.iter().map(|d| (d - m).powi(2)).sum::<f64>() / (GROUPS as f64 - 1.0);
    (m, (var / GROUPS as f64).sqrt())
}

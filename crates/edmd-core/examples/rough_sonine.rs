//! The stationary R/T of rough grains at ε = 0.9: the two-temperature (Maxwellian) theory beside its
//! first Sonine correction, the cumulants, and the quadrature error (spread over four seeds).
//!
//!     cargo run --release -p edmd-core --example rough_sonine

use edmd_core::theory::{RoughCooling, RoughSonine};

fn main() {
    println!(
        "d  beta   Maxwellian  Sonine   (diff)    a20      a02      a11      b        seed spread"
    );
    for (d, q, beta) in [
        (2, 0.5, -0.5),
        (2, 0.5, 0.0),
        (2, 0.5, 0.5),
        (2, 0.5, 1.0),
        (3, 0.4, 0.0),
    ] {
        let maxwell = RoughCooling::new(d, 0.9, beta, q).stationary_ratio();
        let runs: Vec<_> = (1..=4)
            .map(|seed| {
                RoughSonine::new(d, 0.9, beta, q)
                    .with_samples(1 << 21, seed)
                    .solve()
            })
            .collect();
        let mean = runs.iter().map(|s| s.ratio).sum::<f64>() / 4.0;
        let var = runs.iter().map(|s| (s.ratio - mean).powi(2)).sum::<f64>() / 3.0;
        let s = runs[0];
        println!(
            "{d}  {beta:+.1}   {maxwell:.4}      {:.4}   ({:+.2} %)  {:+.4}  {:+.4}  {:+.4}  {:+.4}  {:.2} %",
            s.ratio,
            100.0 * (s.ratio / maxwell - 1.0),
            s.a20,
            s.a02,
            s.a11,
            s.b,
            100.0 * var.sqrt() / mean
        );
    }
}

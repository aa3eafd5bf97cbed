//! Unit tests of `replica::shear`.

use edmd_sweep::classify::Class;
use edmd_sweep::replica::{classify_shear as classify, density_contrast as contrast, ShearSeries};

fn series(profile: Vec<f64>) -> ShearSeries {
    let mut s = ShearSeries::default();
    s.density_profile_y = vec![profile; 4];
    s.density_profile_x = vec![vec![1.0; 8]; 4];
    s
}

/// A flat profile and one of Poisson noise are homogeneous; a band of twice the density over a
/// third of the box is not.
#[test]
fn bands_are_inhomogeneous_and_noise_is_not() {
    let flat = classify(&series(vec![1.0; 30]), 3000, 0.15);
    assert_eq!(flat.class, Class::Homogeneous, "{}", flat.note);
    // ±√(N/B) counts around N/B = 100: relative variance 1/100 = (B − 1)/N, excess 0.
    let noisy: Vec<f64> = (0..30)
        .map(|b| if b % 2 == 0 { 1.1 } else { 0.9 })
        .collect();
    let c = contrast(&noisy, 3000);
    assert!((c - (0.01 - 29.0 / 3000.0)).abs() < 1e-12, "{c}");
    assert_eq!(
        classify(&series(noisy), 3000, 0.15).class,
        Class::Homogeneous
    );
    let band: Vec<f64> = (0..30)
        .map(|b| if (10..20).contains(&b) { 2.0 } else { 0.5 })
        .collect();
    let banded = classify(&series(band), 3000, 0.15);
    assert_eq!(banded.class, Class::Inhomogeneous, "{}", banded.note);
}

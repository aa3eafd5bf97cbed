//! Small geometric facts used across the project, written once: the volume of a ball and the
//! densest packing of equal disks and spheres.

use std::f64::consts::PI;

/// Volume (area in 2D) of a `d`-ball of radius `r`; `ball_volume(d, 0.5)` is the volume of one
/// particle of unit diameter (π/4 and π/6, to the last bit).
pub fn ball_volume(d: usize, r: f64) -> f64 {
    if d == 2 {
        PI * r * r
    } else {
        4.0 / 3.0 * PI * r.powi(3)
    }
}

/// Densest packing fraction of equal disks (hexagonal, π/(2√3)) or spheres (fcc, π/(3√2)).
pub fn close_packing(d: usize) -> f64 {
    if d == 2 {
        PI / (2.0 * 3f64.sqrt())
    } else {
        PI / (3.0 * 2f64.sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_diameter_volumes_are_exact() {
        assert_eq!(ball_volume(2, 0.5), PI / 4.0);
        assert_eq!(ball_volume(3, 0.5), PI / 6.0);
        assert!((close_packing(2) - 0.9069).abs() < 1e-4);
        assert!((close_packing(3) - 0.7405).abs() < 1e-4);
    }
}

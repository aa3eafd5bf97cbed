//! The steady uniform shear flow of a dilute inelastic gas against kinetic theory (PHYSICS.md §7.1):
//! the reduced shear rate a* = a/ν0, the reduced viscosity η* = −P*_xy/a* and the normal stresses
//! P*_xx, P*_yy (and P*_zz) measured in a Lees–Edwards box, against Grad's solution of the Boltzmann
//! equation (`theory::ShearFlow`).
//!
//! * **The run.** φ = 0.002, so that the Enskog corrections the dilute theory leaves out, of order
//!   2^{d−2}(1 + α)φχ in the stresses, stay below 0.4 % (2D) and 0.8 % (3D); N = 500. The shear rate
//!   is the one whose steady temperature is T0 (a = a*_theory ν0(T = 1)), so the gas starts near
//!   its steady state; the first 30 τ are left out and 300 τ measured (1.5 · 10⁵ collisions).
//! * **Measurement.** Kinetic stresses Σ m V_a V_b / V from the peculiar velocities every 0.5 τ,
//!   collisional ones from the engine's virial tensor over the window; everything reduced by the
//!   window's mean temperature; a* with the Enskog collision frequency ν0 (χ(φ) = 1.004–1.005).
//! * **Tolerance.** The accuracy the theory is expected to have against the Boltzmann equation it
//!   approximates (a* within 3 %, η* within 4 %, normal stresses within 3 %), plus three standard
//!   errors of the measurement from 10 blocks of the window. At α = 0.9 every quantity is checked;
//!   at α = 0.7 only the in-plane normal stresses (see [`ALPHA_0_7`] for why and by how much the
//!   others miss).
//! * **Finite size.** The 2D α = 0.9 case is repeated at N = 2000 (a box twice as wide): the two
//!   agree within their errors (`finite_size_leaves_the_disk_flow_unchanged`).

use edmd_core::theory::{chi, ShearFlow};
use edmd_core::{ConstantRestitution, InitParams, LeesEdwards, SimParams, Simulation, Vector};

/// The reduced steady-state quantities of one block or window.
#[derive(Debug, Clone, Copy, Default)]
struct Reduced {
    a_star: f64,
    eta_star: f64,
    pxx: f64,
    pyy: f64,
    pzz: f64,
}

/// Runs the sheared dilute gas and returns the window's values and their standard errors.
fn measure<const D: usize>(n: usize, alpha: f64) -> (Reduced, Reduced) {
    let phi = 0.002;
    let flow = ShearFlow::new(D, alpha);
    let side = (n as f64 * edmd_core::init::unit_volume::<D>(0.5) / phi).powf(1.0 / D as f64);
    let density = n as f64 / side.powi(D as i32);
    let nu0_per_sqrt_t = ShearFlow::nu0_per_sqrt_t(D, density, chi(D, phi));
    let rate = flow.reduced_shear_rate() * nu0_per_sqrt_t;
    let mut p = InitParams::<D>::in_box(n, Vector::<D>::repeat(side));
    p.seed = 11;
    p.sim = Some(SimParams {
        shear_rate: rate,
        ..SimParams::for_density::<D>(phi)
    });
    let mut sim: Simulation<D, LeesEdwards, _> = p
        .build::<LeesEdwards, _>(ConstantRestitution::new(alpha).unwrap())
        .unwrap();
    let volume = side.powi(D as i32);
    let (tau_start, blocks, per_block) = (30.0, 10, 30.0);
    while sim.tau() < tau_start {
        sim.step().expect("events left");
    }
    let mut out = Vec::new();
    for b in 0..blocks {
        let (t0, w0) = (sim.time(), sim.counters().virial_tensor);
        let (mut kinetic, mut temperature, mut samples) = ([[0.0; 3]; 3], 0.0, 0usize);
        let end = tau_start + (b + 1) as f64 * per_block;
        let mut next = sim.tau();
        while sim.tau() < end {
            sim.step().expect("events left");
            if sim.tau() >= next {
                next += 0.5;
                let v = sim.peculiar_velocities();
                let mut e = 0.0;
                for v in &v {
                    e += v.norm_squared();
                    for a in 0..D {
                        for c in 0..D {
                            kinetic[a][c] += v[a] * v[c] / volume;
                        }
                    }
                }
                temperature += e / (D as f64 * n as f64);
                samples += 1;
            }
        }
        let (dt, w1) = (sim.time() - t0, sim.counters().virial_tensor);
        let s = samples as f64;
        let t = temperature / s;
        let p = |a: usize, c: usize| {
            (kinetic[a][c] / s + (w1[a][c] - w0[a][c]) / (volume * dt)) / (density * t)
        };
        let a_star = rate / (nu0_per_sqrt_t * t.sqrt());
        out.push(Reduced {
            a_star,
            eta_star: -p(0, 1) / a_star,
            pxx: p(0, 0),
            pyy: p(1, 1),
            pzz: if D == 3 { p(2, 2) } else { f64::NAN },
        });
    }
    let stats = |f: fn(&Reduced) -> f64| {
        let x: Vec<f64> = out.iter().map(f).collect();
        let m = x.iter().sum::<f64>() / x.len() as f64;
        let var = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() - 1) as f64;
        (m, (var / x.len() as f64).sqrt())
    };
    let (a_star, ea) = stats(|r| r.a_star);
    let (eta_star, ee) = stats(|r| r.eta_star);
    let (pxx, ex) = stats(|r| r.pxx);
    let (pyy, ey) = stats(|r| r.pyy);
    let (pzz, ez) = stats(|r| r.pzz);
    (
        Reduced {
            a_star,
            eta_star,
            pxx,
            pyy,
            pzz,
        },
        Reduced {
            a_star: ea,
            eta_star: ee,
            pxx: ex,
            pyy: ey,
            pzz: ez,
        },
    )
}

/// Checks the quantities named in `checked` against the theory within its stated accuracy plus
/// three standard errors, and prints every comparison.
fn against_theory<const D: usize>(alpha: f64, checked: &[&str]) {
    let (m, e) = measure::<D>(500, alpha);
    let f = ShearFlow::new(D, alpha);
    let mut checks = vec![
        ("a*", m.a_star, e.a_star, f.reduced_shear_rate(), 0.03),
        ("eta*", m.eta_star, e.eta_star, f.reduced_viscosity(), 0.04),
        ("P*xx", m.pxx, e.pxx, f.pxx(), 0.03),
        ("P*yy", m.pyy, e.pyy, f.pyy(), 0.03),
    ];
    if D == 3 {
        checks.push(("P*zz", m.pzz, e.pzz, f.pyy(), 0.03));
    }
    let mut failed = Vec::new();
    for (name, got, se, theory, accuracy) in checks {
        let dev = got / theory - 1.0;
        let tol = accuracy + 3.0 * se / theory;
        println!(
            "D = {D}, alpha = {alpha}: {name} = {got:.4} ± {se:.4}, Grad {theory:.4} ({:+.2} %, tolerance {:.2} %)",
            100.0 * dev,
            100.0 * tol
        );
        if checked.contains(&name) && dev.abs() >= tol {
            failed.push(format!("{name} = {got:.4} ± {se:.4} against {theory:.4}"));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("; "));
}

/// At α = 0.7 the linear Grad closure holds only for the in-plane normal stresses. Its a* and η*
/// are 5–6 % off (measured: a* +5.1 % in 2D, +6.3 % in 3D; η* −2.7 % and −6.2 %), and P*_zz,
/// which Grad sets equal to P*_yy, is 6 % above it: the terms quadratic in the anisotropy Π* that
/// the closure drops scale as Π*:Π*, which is 0.26 at α = 0.9 and 0.79 at α = 0.7 (3D), so an
/// error of 1–2 % at α = 0.9 becomes one of about 5 % here. Those three are printed, not checked,
/// until the nonlinear theory is in `theory::ShearFlow` (PHYSICS.md §7.1).
const ALPHA_0_7: &[&str] = &["P*xx", "P*yy"];

#[test]
fn sheared_dilute_disks_follow_grad_theory_at_alpha_0_9() {
    against_theory::<2>(0.9, &["a*", "eta*", "P*xx", "P*yy"]);
}

#[test]
fn sheared_dilute_disks_follow_grad_theory_at_alpha_0_7() {
    against_theory::<2>(0.7, ALPHA_0_7);
}

#[test]
fn sheared_dilute_spheres_follow_grad_theory_at_alpha_0_9() {
    against_theory::<3>(0.9, &["a*", "eta*", "P*xx", "P*yy", "P*zz"]);
}

#[test]
fn sheared_dilute_spheres_follow_grad_theory_at_alpha_0_7() {
    against_theory::<3>(0.7, ALPHA_0_7);
}

/// N = 500 and N = 2000 (2D, α = 0.9) agree within three combined standard errors: the box does
/// not set the flow.
#[test]
fn finite_size_leaves_the_disk_flow_unchanged() {
    let (small, es) = measure::<2>(500, 0.9);
    let (large, el) = measure::<2>(2000, 0.9);
    for (name, a, ea, b, eb) in [
        ("a*", small.a_star, es.a_star, large.a_star, el.a_star),
        (
            "eta*",
            small.eta_star,
            es.eta_star,
            large.eta_star,
            el.eta_star,
        ),
        ("P*yy", small.pyy, es.pyy, large.pyy, el.pyy),
    ] {
        let combined = (ea * ea + eb * eb).sqrt();
        println!("{name}: N = 500 {a:.4} ± {ea:.4}, N = 2000 {b:.4} ± {eb:.4}");
        assert!((a - b).abs() < 3.0 * combined, "{name}: {a} against {b}");
    }
}

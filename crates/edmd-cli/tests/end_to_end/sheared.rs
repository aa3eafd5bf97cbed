//! The sheared gas from a spec (`"boundary": "lees-edwards"`, `grid.shear_rate`): its files, its
//! steady state, bad specs, and resume after kill -9.

use std::time::{Duration, Instant};

use crate::common::{assert_same_output, edmd, listing, read, run, run_spec, write};

fn attr(path: &std::path::Path, name: &str) -> f64 {
    let file = hdf5::File::open(path).unwrap();
    let p = file.group("parameters").unwrap();
    p.attr(name).unwrap().read_scalar::<f64>().unwrap()
}

/// An inelastic sheared gas in 2D and 3D (ε = 0.9, φ = 0.1, N = 400), to τ = 150: the files hold the
/// pressure tensor as (samples, D, D), the profiles, the offset of the images with every snapshot
/// and the theory's parameters. Over the steady second half the shear's work −a P_xy equals the
/// dissipation rate within 3 % (the kinetic stress is sampled every 2 τ, not integrated, which the
/// engine test does to 0.14 %), the stream profile is a line of slope a within 5 %, and the
/// temperature is the peculiar one.
#[test]
fn a_sheared_gas_from_a_spec_reaches_a_balanced_steady_state() {
    let tmp = tempfile::tempdir().unwrap();
    for dim in [2usize, 3] {
        let spec = format!(
            r#"{{"name": "shear{dim}", "grid": {{"dim": {dim}, "boundary": "lees-edwards", "shear_rate": 0.1,
                 "eps": 0.9, "phi": 0.1, "n": 400}}, "stop": {{"tau_max": 150}},
                 "samples": {{"every": 2, "per_decade": 0}}, "snapshots": {{"at": [0, 50, 100]}},
                 "classify": {{}}}}"#
        );
        let out = run_spec(tmp.path(), &format!("out{dim}"), &spec);
        let f = out.join("replicas/r00000.h5");
        let (shape, p) = read(&f, "observables/pressure_tensor/value");
        let s = shape[0];
        assert_eq!(shape, [s, dim, dim]);
        assert!(
            p[..dim * dim].iter().all(|x| x.is_nan()),
            "first sample has no interval"
        );
        let (_, diss) = read(&f, "observables/dissipation_rate/value");
        let (_, t) = read(&f, "observables/temperature/value");
        let half = s / 2;
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let pxy: Vec<f64> = (half..s).map(|k| p[k * dim * dim + 1]).collect();
        let work = -0.1 * mean(&pxy);
        let dissipation = mean(&diss[half..]);
        println!(
            "D = {dim}: work {work:.5}, dissipation {dissipation:.5}, T {:.3}",
            mean(&t[half..])
        );
        assert!(
            (work / dissipation - 1.0).abs() < 0.03,
            "work {work} against dissipation {dissipation}"
        );
        // The stream profile, averaged over the second half: slope a.
        let (pshape, u) = read(&f, "observables/velocity_profile/value");
        let (_, y) = read(&f, "observables/velocity_profile/position");
        let bins = pshape[1];
        let ubar: Vec<f64> = (0..bins)
            .map(|b| mean(&(half..s).map(|k| u[k * bins + b]).collect::<Vec<_>>()))
            .collect();
        let (my, mu) = (mean(&y), mean(&ubar));
        let slope = y
            .iter()
            .zip(&ubar)
            .map(|(y, u)| (y - my) * (u - mu))
            .sum::<f64>()
            / y.iter().map(|y| (y - my).powi(2)).sum::<f64>();
        assert!((slope / 0.1 - 1.0).abs() < 0.05, "profile slope {slope}");
        // The temperature is the peculiar one: the lab frame's, from the final snapshot, exceeds it
        // by the flow's a² L_y²/(12 d) (the cross term Σ V_x (y − L_y/2) is a few percent of it).
        let ly = attr(&f, "box_side");
        let (vshape, v) = read(&f, "particles/gas/velocity/value");
        let last = &v[(vshape[0] - 1) * 400 * dim..];
        let t_lab = last.iter().map(|x| x * x).sum::<f64>() / (dim as f64 * 400.0);
        let flow = 0.01 * ly * ly / (12.0 * dim as f64);
        let excess = t_lab - t[s - 1];
        assert!(
            (excess / flow - 1.0).abs() < 0.1,
            "T_lab − T = {excess}, flow {flow}"
        );
        // Snapshots carry the offset of the images, in [0, L_x) and growing with time as a L_y t.
        let (oshape, offset) = read(&f, "particles/gas/box/offset/value");
        let (_, time) = read(&f, "particles/gas/box/offset/time");
        assert_eq!(oshape, [4]);
        for (o, t) in offset.iter().zip(&time) {
            let expected = (0.1 * ly * t).rem_euclid(ly);
            assert!(
                (o - expected).abs() < 1e-6 * ly,
                "offset {o} at t {t}: {expected}"
            );
        }
        assert_eq!(attr(&f, "shear_rate"), 0.1);
        assert!(attr(&f, "shear_theory_reduced_rate") > 0.3);
        let class: hdf5::types::VarLenUnicode = hdf5::File::open(&f)
            .unwrap()
            .group("parameters")
            .unwrap()
            .attr("class")
            .unwrap()
            .read_scalar()
            .unwrap();
        assert_eq!(
            class.as_str(),
            "homogeneous",
            "a small box keeps the uniform flow"
        );
        let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
        assert!(summary.contains(",lees-edwards,0.9,"), "{summary}");
    }
}

/// A shear rate without the sliding box, and the sliding box with walls' parameters, are refused
/// with one line naming the field; nothing is written.
#[test]
fn shear_specs_that_cannot_run_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    for (grid, needle) in [
        (
            r#""boundary": "periodic", "shear_rate": 0.1"#,
            "grid.shear_rate = [0.1]: needs boundary \"lees-edwards\"",
        ),
        (
            r#""boundary": "lees-edwards", "wall_eps": 0.5"#,
            "grid.wall_eps = [0.5]: needs walls on the last axis",
        ),
        (
            r#""boundary": "lees-edwards", "shear_rate": -1"#,
            "grid.shear_rate = -1",
        ),
    ] {
        let spec = write(
            tmp.path(),
            "bad.json",
            &format!(
                r#"{{"name": "bad", "grid": {{"eps": 0.9, "phi": 0.1, "n": 64, {grid}}}, "stop": {{"tau_max": 1}}}}"#
            ),
        );
        let out = tmp.path().join("out");
        let o = run(&["run", spec.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert!(e.contains(needle), "{e}");
        assert_eq!(e.trim().lines().count(), 1, "{e}");
        assert!(!out.exists());
    }
}

/// SIGKILL in the middle of a sheared sweep, rerun: the output equals an uninterrupted run (the
/// dense 3D replicas, φ = 0.45, on neighbour lists).
#[test]
fn a_killed_sheared_sweep_resumes_to_the_same_output() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        r#"{"name": "kill", "seed": 3,
            "grid": {"dim": [2, 3], "boundary": "lees-edwards", "shear_rate": [0.05, 0.1],
                     "eps": [0.9, 0.8], "phi": [0.1, 0.45], "n": 300, "seeds": 2},
            "stop": {"tau_max": 100}, "samples": {"every": 5, "per_decade": 0},
            "snapshots": {"at": [0, 50], "final": true}}"#,
    );
    let spec = spec.to_str().unwrap();
    let killed = tmp.path().join("killed");
    let mut child = edmd()
        .args(["run", spec, "-o", killed.to_str().unwrap(), "-j", "2", "-q"])
        .spawn()
        .unwrap();
    let replicas = killed.join("replicas");
    let deadline = Instant::now() + Duration::from_secs(120);
    let done = |d: &std::path::Path| listing(d).iter().filter(|f| f.ends_with(".h5")).count();
    while done(&replicas) < 3 {
        assert!(Instant::now() < deadline, "sweep made no progress");
        assert!(
            child.try_wait().unwrap().is_none(),
            "sweep ended before the kill"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(done(&replicas) < 32, "the sweep finished before the kill");
    let o = run(&["run", spec, "-o", killed.to_str().unwrap(), "-j", "2", "-q"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let clean = run_spec(
        tmp.path(),
        "clean",
        &std::fs::read_to_string(tmp.path().join("s.json")).unwrap(),
    );
    assert_same_output(&killed, &clean);
}

/// The sheared box with every kind of grain and law: rough grains (β = 0.5), a binary mixture, the
/// viscoelastic law and the TC remedy each reach a steady state in which the shear's work −a P_xy
/// (the whole impulse in the collisional stress, tangential parts included) equals the dissipation
/// (translational and rotational) within 3 %, as for smooth grains; rough spheres also at φ 0.45,
/// on neighbour lists.
#[test]
fn every_grain_and_law_shears_with_balanced_energy() {
    let tmp = tempfile::tempdir().unwrap();
    // Disks at φ 0.1 (cells), and rough spheres at φ 0.45, which run on neighbour lists under shear
    // (mixtures cannot be placed that dense).
    let disks = r#""dim": 2, "phi": 0.1, "n": 400, "shear_rate": 0.1"#;
    let dense = r#""dim": 3, "phi": 0.45, "n": 500, "shear_rate": 1"#;
    for (name, grid, extra, rule) in [
        (
            "rough",
            disks,
            r#", "beta": 0.5"#,
            r#"{"kind": "constant"}"#,
        ),
        (
            "rough-lists",
            dense,
            r#", "beta": 0.5"#,
            r#"{"kind": "constant"}"#,
        ),
        (
            "mixture",
            disks,
            r#", "species": [{"fraction": 0.5, "diameter": 1}, {"fraction": 0.5, "diameter": 1.4, "mass": 2}]"#,
            r#"{"kind": "constant"}"#,
        ),
        (
            "viscoelastic",
            disks,
            "",
            r#"{"kind": "viscoelastic", "speed": 1}"#,
        ),
        (
            "tc",
            disks,
            r#", "remedy": {"kind": "tc", "tc": 0.001}"#,
            r#"{"kind": "constant"}"#,
        ),
    ] {
        let spec = format!(
            r#"{{"name": "{name}", "grid": {{"boundary": "lees-edwards", "eps": 0.9, {grid}{extra}}},
                 "rule": {rule}, "stop": {{"tau_max": 150}}, "samples": {{"every": 1, "per_decade": 0}}}}"#
        );
        let (dim, rate) = if grid == dense { (3, 1.0) } else { (2, 0.1) };
        let out = run_spec(tmp.path(), name, &spec);
        let f = out.join("replicas/r00000.h5");
        let (shape, p) = read(&f, "observables/pressure_tensor/value");
        let (_, diss) = read(&f, "observables/dissipation_rate/value");
        let s = shape[0];
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let pxy: Vec<f64> = (s / 2..s).map(|k| p[k * dim * dim + 1]).collect();
        let work = -rate * mean(&pxy);
        let dissipation = mean(&diss[s / 2..]);
        println!("{name}: work {work:.5}, dissipation {dissipation:.5}");
        assert!(
            (work / dissipation - 1.0).abs() < 0.03,
            "{name}: work {work} against dissipation {dissipation}"
        );
    }
}

/// Elastic grains with the rotation remedy in a sheared box (hardening case 1: N 300, φ 0.2, a 0.2,
/// θ_max 90°, τ 30): the remedy rotates the relative velocity of the pair's image, so it removes
/// nothing, and the gas heats by the shear's work alone. Rotating the lab-frame difference across a
/// sliding face (which carries ±a L_y) created energy: `dissipation_rate` negative in most samples,
/// T at τ 30 7.9 against 5.6 without the remedy.
#[test]
fn the_rotation_remedy_creates_no_energy_in_a_sheared_box() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = r#"{"name": "rot", "grid": {"boundary": "lees-edwards", "shear_rate": 0.2, "eps": 1,
        "phi": 0.2, "n": 300, "remedy": {"kind": "rotation", "theta_max_deg": 90}},
        "stop": {"tau_max": 30}, "samples": {"every": 0.5, "per_decade": 0}}"#;
    let out = run_spec(tmp.path(), "rot", spec);
    let f = out.join("replicas/r00000.h5");
    let (_, diss) = read(&f, "observables/dissipation_rate/value");
    let (_, t) = read(&f, "observables/temperature/value");
    let (_, time) = read(&f, "observables/dissipation_rate/time");
    let side = attr(&f, "box_side");
    // Energy removed over the run, against the final kinetic energy (N d T / 2).
    let removed: f64 = (1..diss.len())
        .map(|k| diss[k] * side * side * (time[k] - time[k - 1]))
        .sum();
    let energy = 300.0 * t[t.len() - 1];
    println!("removed {removed:e} of a final energy {energy}");
    assert!(
        removed.abs() < 1e-9 * energy,
        "an elastic remedy removed {removed:e} (final energy {energy})"
    );
}

/// A gas sheared at a = 10⁻⁸ (hardening case 5: ε 0.9, φ 0.1, N 200, samples every 50 τ to 2000):
/// past τ ≈ 350 it is in the shear's steady state at T ≈ 4·10⁻¹⁵, where the dissipation per unit
/// volume is ~10⁻²⁴. `dissipation_rate` is summed per sample interval, so every sample after the
/// first resolves it (a running total rounded it to exactly 0 next to the early losses), and over
/// the steady samples its mean ratio to the shear's work −a P_xy is 1 within four standard errors
/// of that mean.
#[test]
fn the_dissipation_rate_resolves_a_tiny_shear_rate() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = r#"{"name": "tiny", "grid": {"boundary": "lees-edwards", "shear_rate": 1e-8,
        "eps": 0.9, "phi": 0.1, "n": 200}, "stop": {"tau_max": 2000},
        "samples": {"every": 50, "per_decade": 0}}"#;
    let out = run_spec(tmp.path(), "tiny", spec);
    let f = out.join("replicas/r00000.h5");
    let (_, diss) = read(&f, "observables/dissipation_rate/value");
    let (_, p) = read(&f, "observables/pressure_tensor/value");
    assert!(
        diss[1..].iter().all(|&d| d > 0.0),
        "unresolved dissipation: {diss:?}"
    );
    let ratios: Vec<f64> = (10..diss.len())
        .map(|k| diss[k] / (-1e-8 * p[k * 4 + 1]))
        .collect();
    let n = ratios.len() as f64;
    let mean = ratios.iter().sum::<f64>() / n;
    let se = (ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
    println!("dissipation / work over {n} steady samples: {mean:.4} ± {se:.4}");
    assert!(se < 0.1, "too noisy: {se}");
    assert!(
        (mean - 1.0).abs() < 4.0 * se,
        "dissipation / work = {mean} ± {se}"
    );
}

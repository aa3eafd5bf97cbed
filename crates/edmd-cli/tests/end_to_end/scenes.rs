//! End-to-end tests of scenes beyond the smooth monodisperse gas, run from a spec: rough grains,
//! mixtures, gravity with a thermal floor, wall restitution and rectangular boxes.

use crate::common::{read, run_spec};

/// Perfectly rough elastic grains (ε = β = 1) conserve the total kinetic energy, translational plus
/// rotational: d T + d_rot T_rot = d T0 at every sample, to round-off (2D: d_rot = 1, ω_z stored as
/// (N, 1); 3D: d_rot = 3, ω as (N, 3)). This checks the normalisation of the rotational temperature
/// Σ I ω² / (d_rot N) with I = q m (σ/2)², for a non-uniform q too. Spins start at zero and the gas
/// shares its energy with them, so T_rot rises from 0 while T falls: the exchange is exercised.
#[test]
fn rough_elastic_grains_conserve_translational_plus_rotational_energy() {
    let tmp = tempfile::tempdir().unwrap();
    for (dim, inertia) in [(2, 0.5), (3, 0.4), (2, 0.25)] {
        let spec = format!(
            r#"{{"name": "rough{dim}", "grid": {{"dim": {dim}, "eps": 1, "beta": [1, 0.2], "inertia": {inertia},
                 "phi": 0.2, "n": 500}}, "stop": {{"tau_max": 20}},
                 "samples": {{"every": 2, "per_decade": 0}}, "snapshots": {{"at": [0, 10]}}}}"#
        );
        let out = run_spec(tmp.path(), &format!("out{dim}-{inertia}"), &spec);
        let d = dim as f64;
        let d_rot = if dim == 2 { 1.0 } else { 3.0 };
        // Replica 0: beta = 1 (energy conserved); replica 1: beta = 0.2 (rotational energy is lost).
        for (k, conserved) in [(0, true), (1, false)] {
            let f = out.join(format!("replicas/r{k:05}.h5"));
            let (_, t) = read(&f, "observables/temperature/value");
            let (_, tr) = read(&f, "observables/rotational_temperature/value");
            assert_eq!(t.len(), tr.len());
            assert_eq!(tr[0], 0.0, "spins start at rest");
            let most = tr.iter().copied().fold(0.0, f64::max);
            assert!(most > 0.05, "the spins took no energy: {tr:?}");
            let total: Vec<f64> = t.iter().zip(&tr).map(|(a, b)| d * a + d_rot * b).collect();
            let drift = total
                .iter()
                .map(|e| (e / total[0] - 1.0).abs())
                .fold(0.0, f64::max);
            if conserved {
                assert!(drift < 1e-9, "D={dim} q={inertia}: energy drift {drift:e}");
            } else {
                assert!(
                    drift > 1e-2,
                    "D={dim}: beta = 0.2 lost no energy ({drift:e})"
                );
            }
            let (shape, w) = read(&f, "particles/gas/angular_velocity/value");
            assert_eq!(shape, [3, 500, if dim == 2 { 1 } else { 3 }]);
            // The stored ω of the last snapshot gives back the last T_rot: Σ q m r² ω² / (d_rot N).
            let per = shape[2];
            let last = &w[2 * 500 * per..];
            let t_rot: f64 =
                last.iter().map(|x| inertia * 0.25 * x * x).sum::<f64>() / (d_rot * 500.0);
            let rel = (t_rot / tr[tr.len() - 1] - 1.0).abs();
            assert!(
                rel < 1e-9,
                "D={dim}: T_rot from the snapshot {t_rot} vs {}",
                tr[tr.len() - 1]
            );
        }
        // Smooth grains store neither.
        let out = run_spec(
            tmp.path(),
            "smooth",
            r#"{"name": "smooth", "grid": {"eps": 0.9, "phi": 0.2, "n": 100}, "stop": {"tau_max": 2}}"#,
        );
        let file = hdf5::File::open(out.join("replicas/r00000.h5")).unwrap();
        assert!(!file.link_exists("observables/rotational_temperature"));
        assert!(!file.link_exists("particles/gas/angular_velocity"));
        std::fs::remove_dir_all(&out).unwrap();
    }
}

/// A mixture from a spec (an axis of two mixtures, 3 species in one, a given mass in the other):
/// N is split by the fractions (largest remainders), species k takes its diameter and its mass
/// (σ^D by default), φ counts every species, and `species_temperature` is Σ_{a∈k} m v²/(d N_k) of the
/// stored velocities, whose N-weighted mean is the temperature. The phase table names the mixtures.
#[test]
fn mixtures_from_a_spec() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = r#"{"name": "mix", "grid": {"dim": [2, 3], "eps": 0.9, "phi": 0.1, "n": 301,
        "species": [[{"fraction": 0.5, "diameter": 1}, {"fraction": 0.3, "diameter": 1.4},
                     {"fraction": 0.2, "diameter": 0.7}],
                    [{"fraction": 0.25, "diameter": 1, "mass": 8}, {"fraction": 0.75, "diameter": 1}]]},
        "stop": {"tau_max": 6}, "samples": {"every": 2, "per_decade": 0}, "snapshots": {"at": [4]}}"#;
    let out = run_spec(tmp.path(), "out", spec);
    // (fraction, diameter, mass if given) per species.
    type Mixture<'a> = &'a [(f64, f64, Option<f64>)];
    let cases: [(usize, Mixture); 4] = [
        (2, &[(0.5, 1.0, None), (0.3, 1.4, None), (0.2, 0.7, None)]),
        (2, &[(0.25, 1.0, Some(8.0)), (0.75, 1.0, None)]),
        (3, &[(0.5, 1.0, None), (0.3, 1.4, None), (0.2, 0.7, None)]),
        (3, &[(0.25, 1.0, Some(8.0)), (0.75, 1.0, None)]),
    ];
    for (k, (dim, mixture)) in cases.iter().enumerate() {
        let f = out.join(format!("replicas/r{k:05}.h5"));
        let file = hdf5::File::open(&f).unwrap();
        let species = file
            .dataset("particles/gas/species")
            .unwrap()
            .read_raw::<i64>()
            .unwrap();
        let (_, diameter) = read(&f, "particles/gas/diameter");
        let (_, mass) = read(&f, "particles/gas/mass");
        let n = species.len();
        assert_eq!(n, 301);
        // 301 × (0.5, 0.3, 0.2) = 150.5, 90.3, 60.2 → 151, 90, 60; 301 × (0.25, 0.75) → 75, 226.
        let expect: Vec<usize> = if mixture.len() == 3 {
            vec![151, 90, 60]
        } else {
            vec![75, 226]
        };
        let mut volume = 0.0;
        for (s, &(_, sigma, m)) in mixture.iter().enumerate() {
            let members: Vec<usize> = (0..n).filter(|&a| species[a] == s as i64).collect();
            assert_eq!(members.len(), expect[s], "species {s} of replica {k}");
            let m = m.unwrap_or(sigma.powi(*dim as i32));
            for &a in &members {
                assert_eq!(diameter[a], sigma);
                assert!((mass[a] / m - 1.0).abs() < 1e-12);
            }
            let unit = if *dim == 2 {
                std::f64::consts::PI / 4.0
            } else {
                std::f64::consts::PI / 6.0
            };
            volume += members.len() as f64 * unit * sigma.powi(*dim as i32);
        }
        let (_, edges) = read(&f, "particles/gas/box/edges");
        let phi = volume / edges.iter().product::<f64>();
        assert!((phi / 0.1 - 1.0).abs() < 1e-9, "phi {phi}");
        // The snapshot at τ = 4 gives back that sample's species temperatures.
        let (shape, ts) = read(&f, "observables/species_temperature/value");
        assert_eq!(shape[1], mixture.len());
        let (_, tau) = read(&f, "observables/tau/value");
        let (_, t) = read(&f, "observables/temperature/value");
        let row = tau.iter().position(|&x| (x - 4.0).abs() < 0.01).unwrap();
        let (_, v) = read(&f, "particles/gas/velocity/value");
        let mut e = vec![0.0; mixture.len()];
        let mut c = vec![0usize; mixture.len()];
        for a in 0..n {
            let s = species[a] as usize;
            let v2: f64 = v[a * dim..(a + 1) * dim].iter().map(|x| x * x).sum();
            e[s] += mass[a] * v2;
            c[s] += 1;
        }
        let mut mean = 0.0;
        for s in 0..mixture.len() {
            let from_snapshot = e[s] / (*dim as f64 * c[s] as f64);
            let stored = ts[row * mixture.len() + s];
            assert!(
                (from_snapshot / stored - 1.0).abs() < 1e-9,
                "{from_snapshot} vs {stored}"
            );
            mean += c[s] as f64 * stored / n as f64;
        }
        assert!((mean / t[row] - 1.0).abs() < 1e-9);
    }
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(
        summary.contains("0.5:1:1+0.3:1.4:1.96+0.2:0.7:0.49"),
        "{summary}"
    );
    assert!(summary.contains("0.25:1:8+0.75:1:1"), "{summary}");
}

/// A heated column from a spec: a channel 200 × 120 (`box` 120, `aspect` [5/3, 1]), gravity 0.1, a
/// thermal floor at 2, elastic and inelastic grains. The box edges follow the aspect; the density
/// profile n(z) holds every grain at each sample (Σ n Δz A = N); the class is not_applicable with
/// the reason; the parameters carry gravity, wall_eps, floor_temperature and box_sides; the phase
/// table names the scene. The elastic column ends near the floor's temperature (the engine's tests
/// check the profile and the temperature against theory).
#[test]
fn heated_column_from_a_spec() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = r#"{"name": "column", "grid": {"boundary": "channel", "eps": [1, 0.9], "n": 250, "box": 120,
        "aspect": [1.6666666666666667, 1], "gravity": 0.1, "floor_temperature": 2, "wall_eps": 0.8},
        "stop": {"tau_max": 300}, "samples": {"every": 20, "per_decade": 0}, "classify": {}}"#;
    let out = run_spec(tmp.path(), "out", spec);
    for k in 0..2 {
        let f = out.join(format!("replicas/r{k:05}.h5"));
        let (_, edges) = read(&f, "particles/gas/box/edges");
        assert!(
            (edges[0] - 200.0).abs() < 1e-9 && edges[1] == 120.0,
            "{edges:?}"
        );
        let (shape, profile) = read(&f, "observables/density_profile/value");
        let (_, centres) = read(&f, "observables/density_profile/position");
        assert_eq!(shape[1], 120);
        assert_eq!(centres.len(), 120);
        for row in profile.chunks(shape[1]) {
            let total: f64 = row.iter().map(|n| n * 1.0 * edges[0]).sum();
            assert!((total - 250.0).abs() < 1e-9, "profile holds {total} grains");
        }
        let file = hdf5::File::open(&f).unwrap();
        let params = file.group("parameters").unwrap();
        let attr = |name: &str| params.attr(name).unwrap().read_scalar::<f64>().unwrap();
        assert_eq!(attr("gravity"), 0.1);
        assert_eq!(attr("floor_temperature"), 2.0);
        assert_eq!(attr("wall_eps"), 0.8);
        let class: hdf5::types::VarLenUnicode =
            params.attr("class").unwrap().read_scalar().unwrap();
        assert_eq!(class.as_str(), "not_applicable");
        if k == 0 {
            let (_, t) = read(&f, "observables/temperature/value");
            let late = &t[t.len() / 2..];
            let mean = late.iter().sum::<f64>() / late.len() as f64;
            assert!(
                (mean / 2.0 - 1.0).abs() < 0.1,
                "elastic column at T = {mean}"
            );
        }
    }
    // The index carries the scene's axes (gravity, shear_rate, wall_eps, floor_temperature,
    // white_noise, shake_s, shake_gamma, shaken_state, aspect).
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(
        summary.contains(",0.1,0.0,0.8,2.0,0.0,0.0,0.0,,1.6666666666666667x1,"),
        "{summary}"
    );
    // The phase table names the scene in one column.
    let phase = std::fs::read_to_string(out.join("phase.json")).unwrap();
    assert!(
        phase.contains("g=0.1 wall_eps=0.8 floor_T=2 aspect=1.6666666666666667x1"),
        "{phase}"
    );
}

/// Snapshot grids: `snapshots.every` (linear from τ = 0) and `per_decade` from `log_from` merge with
/// `at` and the final state; every snapshot is also a sample, taken after the first collision count
/// ≥ τ N. Stopping for the extra snapshots does not change the trajectory: the final state equals,
/// bit for bit, that of the same replica run with one snapshot.
#[test]
fn snapshot_grids_store_the_merged_times_and_leave_the_trajectory_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let n = 300usize;
    let base = |snaps: &str| {
        format!(
            r#"{{"name": "grid", "grid": {{"eps": 0.9, "phi": 0.2, "n": {n}}}, "stop": {{"tau_max": 10}},
                 "samples": {{"every": 4, "per_decade": 0}}, "snapshots": {snaps}}}"#
        )
    };
    let grid = run_spec(
        tmp.path(),
        "grids",
        &base(r#"{"at": [0], "every": 2.5, "per_decade": 2, "log_from": 1}"#),
    );
    let plain = run_spec(tmp.path(), "plain", &base(r#"{"at": []}"#));
    let f = grid.join("replicas/r00000.h5");
    let file = hdf5::File::open(&f).unwrap();
    let steps: Vec<i64> = file
        .dataset("particles/gas/position/step")
        .unwrap()
        .read_raw()
        .unwrap();
    // at 0; linear 0, 2.5, 5, 7.5, 10; logarithmic 1, 10^0.5, 10; the final state is τ = 10.
    let taus = [0.0, 1.0, 2.5, 10f64.sqrt(), 5.0, 7.5, 10.0];
    let expected: Vec<i64> = taus.iter().map(|t| (t * n as f64).ceil() as i64).collect();
    assert_eq!(steps, expected);
    let (shape, _) = read(&f, "particles/gas/position/value");
    assert_eq!(shape, [taus.len(), n, 2]);
    let sampled: Vec<i64> = file
        .dataset("observables/temperature/step")
        .unwrap()
        .read_raw()
        .unwrap();
    for s in &steps {
        assert!(
            sampled.contains(s),
            "snapshot step {s} not sampled: {sampled:?}"
        );
    }
    let (_, with_grid) = read(&f, "particles/gas/position/value");
    let (pshape, alone) = read(
        &plain.join("replicas/r00000.h5"),
        "particles/gas/position/value",
    );
    assert_eq!(
        pshape,
        [1, n, 2],
        "the plain run stores only its final state"
    );
    assert_eq!(&with_grid[with_grid.len() - 2 * n..], &alone[..]);
}

/// Runs `spec` into `dir/name`, killed after `limit` seconds; returns whether it ended in time, its
/// exit status and stderr.
fn run_within(dir: &std::path::Path, name: &str, spec: &str, limit: f64) -> (bool, String) {
    use std::time::{Duration, Instant};
    let path = crate::common::write(dir, &format!("{name}.json"), spec);
    let out = dir.join(name);
    let mut child = crate::common::edmd()
        .args([
            "run",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs_f64() > limit {
            child.kill().unwrap();
            child.wait().unwrap();
            return (false, String::new());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = child.wait_with_output().unwrap();
    (true, String::from_utf8_lossy(&output.stderr).into_owned())
}

/// Columns compressed far below a grain (hardening case 3): gravity 10⁶ on a floor at T 10⁻¹²
/// (ℓ = T/(mg) = 10⁻¹⁸) hung in the barometric theory, whose integration took steps of ℓ/2000;
/// gravity 1 on a floor at 0.01 spent 33 s writing its files. The theory's cost is now set by
/// the heights it is sampled on: the first ends within seconds as stalled, naming the floor's
/// cascade, the second writes its files at once. Both had a minute; each needs well under one second.
#[test]
fn columns_far_thinner_than_a_grain_end_at_once() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = |name: &str, g: &str, floor: &str| {
        format!(
            r#"{{"name": "{name}", "grid": {{"boundary": "channel", "gravity": {g}, "floor_temperature": {floor},
                "eps": 1, "phi": 0.05, "n": 200}}, "stop": {{"tau_max": 50}}, "samples": {{"every": 5}}}}"#
        )
    };
    let (ended, stderr) = run_within(
        tmp.path(),
        "pressed",
        &spec("pressed", "1e6", "1e-12"),
        60.0,
    );
    assert!(
        ended,
        "gravity 1e6 on a floor at 1e-12 did not end within a minute"
    );
    assert!(stderr.contains("stalled"), "{stderr}");
    let (ended, stderr) = run_within(tmp.path(), "thin", &spec("thin", "1", "0.01"), 60.0);
    assert!(
        ended,
        "gravity 1 on a floor at 0.01 did not end within a minute"
    );
    assert!(!stderr.contains("error"), "{stderr}");
}

/// Mixtures at exactly the documented limit of random placement, φ = 0.4 in 2D and 0.25 in 3D,
/// run: their φ, counted from whole grains, can lie a hair above the limit, which chose a lattice
/// start that a mixture cannot have ("invalid placement = lattice", hardening round 3).
#[test]
fn mixtures_at_the_random_placement_limit_run() {
    let tmp = tempfile::tempdir().unwrap();
    for (dim, phi) in [(2, 0.4), (3, 0.25)] {
        let spec = format!(
            r#"{{"name": "mix{dim}", "grid": {{"dim": {dim}, "eps": 0.9, "phi": {phi}, "n": 200,
                "species": [{{"fraction": 0.5, "diameter": 1, "mass": 1}},
                            {{"fraction": 0.5, "diameter": 2, "mass": 4}}]}},
                "stop": {{"tau_max": 2}}}}"#
        );
        run_spec(tmp.path(), &format!("mix{dim}"), &spec);
    }
}

//! End-to-end tests of scenes beyond the smooth monodisperse gas, run from a spec: rough grains.

mod common;

use common::{run, write};

fn read(path: &std::path::Path, dataset: &str) -> (Vec<usize>, Vec<f64>) {
    let file = hdf5::File::open(path).unwrap();
    let ds = file.dataset(dataset).unwrap();
    (ds.shape(), ds.read_raw::<f64>().unwrap())
}

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
        let p = write(tmp.path(), &format!("r{dim}-{inertia}.json"), &spec);
        let out = tmp.path().join(format!("out{dim}-{inertia}"));
        let o = run(&[
            "run",
            p.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
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
        let p = write(
            tmp.path(),
            "smooth.json",
            r#"{"name": "smooth", "grid": {"eps": 0.9, "phi": 0.2, "n": 100}, "stop": {"tau_max": 2}}"#,
        );
        let out = tmp.path().join("smooth");
        assert!(run(&[
            "run",
            p.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q"
        ])
        .status
        .success());
        let file = hdf5::File::open(out.join("replicas/r00000.h5")).unwrap();
        assert!(!file.link_exists("observables/rotational_temperature"));
        assert!(!file.link_exists("particles/gas/angular_velocity"));
        std::fs::remove_dir_all(&out).unwrap();
    }
}

//! A bed on a vibrating floor from a spec (PHYSICS.md §8.3): `shake_s` and `shake_gamma` become the
//! floor's amplitude and frequency, the files carry them with the floor's work and the grains' mean
//! height, every grain of the final snapshot is above the floor, the bed's state is labelled, and the
//! index names the scene and the state.

use crate::common::{read, run_spec};

/// 200 disks in a channel 50 wide and 100 high (4 layers), g = 1, shaken at S = 10, Γ = 4: A = S d/Γ
/// = 2.5 and ω = √(Γ g/A) = √1.6. The floor heats the bed, so its work grows from sample to sample
/// on the whole; the floor moves as A (1 − cos ωt) in the box.
#[test]
fn a_shaken_bed_from_a_spec() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = r#"{"name": "shaken", "grid": {"boundary": "channel", "eps": 0.9, "n": 200, "box": 100,
        "aspect": [0.5, 1], "gravity": 1, "wall_eps": 0.9, "remedy": {"kind": "tc", "tc": 0.001},
        "shake_s": 10, "shake_gamma": 4}, "stop": {"tau_max": 100},
        "samples": {"every": 10, "per_decade": 0}}"#;
    let out = run_spec(tmp.path(), "out", spec);
    let f = out.join("replicas/r00000.h5");
    let file = hdf5::File::open(&f).unwrap();
    let params = file.group("parameters").unwrap();
    let attr = |name: &str| params.attr(name).unwrap().read_scalar::<f64>().unwrap();
    let (amplitude, omega) = (attr("floor_amplitude"), attr("floor_omega"));
    assert_eq!((attr("shake_s"), attr("shake_gamma")), (10.0, 4.0));
    assert!((amplitude - 2.5).abs() < 1e-12 && (omega - 1.6f64.sqrt()).abs() < 1e-12);
    let (_, work) = read(&f, "observables/floor_work/value");
    let (_, heights) = read(&f, "observables/centre_of_mass_height/value");
    assert_eq!(work.len(), heights.len());
    assert!(work.last().unwrap() > &work[1], "floor work {work:?}");
    assert!(heights.iter().all(|&h| h > 0.5 && h < 100.0), "{heights:?}");
    // The final snapshot: every grain above the floor, at the snapshot's time.
    let (shape, position) = read(&f, "particles/gas/position/value");
    let (_, times) = read(&f, "particles/gas/position/time");
    let t = *times.last().unwrap();
    let floor = amplitude * (1.0 - (omega * t).cos());
    let last = &position[position.len() - shape[1] * shape[2]..];
    let lowest = last
        .chunks(2)
        .map(|x| x[1] - 0.5)
        .fold(f64::INFINITY, f64::min);
    assert!(
        lowest >= floor - 1e-9,
        "a grain at {lowest}, the floor at {floor}"
    );
    // The bed's state, from its density profile (`replica/shaken.rs`), in the file and the index.
    let state: hdf5::types::VarLenUnicode =
        params.attr("shaken_state").unwrap().read_scalar().unwrap();
    let labels = [
        "solid",
        "bouncing_bed",
        "undulations",
        "leidenfrost",
        "convection",
        "gas",
        "undetermined",
    ];
    assert!(labels.contains(&state.as_str()), "{state}");
    // The uniform-time samples (replica/bed_meter.rs): 16 per period over the second half, in
    // height bins of one diameter and columns of two.
    let samples = attr("shaken_samples");
    let (_, clock) = read(&f, "observables/temperature/time");
    let periods = (clock.last().unwrap() - clock[0]) * omega / std::f64::consts::TAU;
    assert!(
        samples > 16.0 * 0.4 * periods && samples < 16.0 * 0.6 * periods,
        "{samples}"
    );
    let contact = attr("shaken_contact_fraction");
    assert!((0.0..=1.0).contains(&contact) && attr("shaken_convection") >= 0.0);
    let (shape, packing) = read(&f, "bed/packing");
    assert_eq!(shape, vec![100]);
    assert!(
        packing.iter().all(|&p| (0.0..0.95).contains(&p)),
        "{packing:?}"
    );
    let total: f64 = packing.iter().sum::<f64>() * 50.0 / (std::f64::consts::PI / 4.0);
    assert!((total - 200.0).abs() < 1e-6, "{total} grains");
    assert_eq!(read(&f, "bed/phase_packing").0, vec![16, 100]);
    assert_eq!(read(&f, "bed/vertical_velocity").0, vec![100, 25]);
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let columns = format!(",1.0,0.0,0.9,0.0,0.0,10.0,4.0,{},0.5x1,", state.as_str());
    assert!(summary.contains(&columns), "{summary}");
    let phase = std::fs::read_to_string(out.join("phase.json")).unwrap();
    assert!(phase.contains("S=10, Gamma=4"), "{phase}");
}

//! Unit tests of `record`.

use edmd_sweep::record::*;

#[test]
fn status_names_round_trip() {
    for s in Status::ALL {
        assert_eq!(s.name().parse::<Status>(), Ok(s));
        assert_eq!(serde_json::to_string(&s).unwrap(), format!("\"{s}\""));
    }
    assert!("finished".parse::<Status>().is_err());
}

#[test]
fn csv_header_is_the_field_list_and_fields_are_quoted() {
    let r = Record {
        index: 3,
        file: "r00003.h5".into(),
        status: Status::Failed,
        message: "a, \"quoted\" message".into(),
        dim: 2,
        boundary: "periodic".into(),
        eps: 0.9,
        beta: -1.0,
        species: String::new(),
        gravity: 0.0,
        shear_rate: 0.0,
        wall_eps: 1.0,
        floor_temperature: 0.0,
        white_noise: 0.0,
        shake_s: 0.0,
        shake_gamma: 0.0,
        shaken_state: String::new(),
        aspect: String::new(),
        phi: 0.25,
        box_side: 56.7,
        n: 1024,
        seed_index: 1,
        seed: 42,
        remedy: "none".into(),
        tau: 1.5,
        time: f64::NAN,
        ln_temperature_ratio: -1.0,
        collisions: 7,
        collapse_tau: f64::NAN,
        class: "failed".into(),
        shear_onset_tau: f64::NAN,
        cluster_onset_tau: f64::NAN,
        f_flow: 0.0,
        s_perp: 0.0,
        delta_rho2: 0.0,
        wall_s: 0.5,
        resumes: 0,
    };
    let csv = Record::to_csv(&[r]);
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), Record::COLUMNS.join(","));
    let row = lines.next().unwrap();
    assert!(
        row.starts_with("3,r00003.h5,failed,\"a, \"\"quoted\"\" message\",2,"),
        "{row}"
    );
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    let back: Record = reader.deserialize().next().unwrap().unwrap();
    assert_eq!(back.message, "a, \"quoted\" message");
    assert_eq!(back.status, Status::Failed);
    assert!(back.time.is_nan());
    assert_eq!(Record::to_csv(&[]).trim_end(), Record::COLUMNS.join(","));
}

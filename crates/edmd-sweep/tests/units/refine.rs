use edmd_sweep::record::{Record, Status};
use edmd_sweep::refine::*;
use edmd_sweep::spec::{RefineAxis, Spec};

fn spec(grid: &str) -> Spec {
    Spec::from_json(&format!(
        r#"{{"name": "t", "grid": {grid}, "stop": {{"tau_max": 10}}, "classify": {{}}}}"#
    ))
    .unwrap()
}

/// Records whose classes follow `label(eps, box)`.
fn records(spec: &Spec, label: impl Fn(f64, f64) -> &'static str) -> Vec<Record> {
    spec.replicas()
        .iter()
        .map(|r| {
            let mut rec = Record::missing(r);
            rec.status = Status::Done;
            rec.class = label(r.eps, r.side()).into();
            rec
        })
        .collect()
}

#[test]
fn midpoints_are_linear_or_geometric_and_tidy() {
    assert_eq!(midpoint(RefineAxis::Eps, 0.8, 0.9), Some(0.85));
    assert_eq!(midpoint(RefineAxis::Box, 20.0, 80.0), Some(40.0));
    assert_eq!(midpoint(RefineAxis::N, 100.0, 400.0), Some(200.0));
    assert_eq!(midpoint(RefineAxis::N, 100.0, 101.0), None);
    // Two bisections of [0.6, 1] land on the grid of spacing 0.1, exactly.
    let m = midpoint(RefineAxis::Eps, 0.6, 1.0).unwrap();
    assert_eq!(midpoint(RefineAxis::Eps, 0.6, m), Some(0.7));
}

#[test]
fn only_pairs_that_disagree_are_bisected() {
    let s = spec(r#"{"eps": [0.6, 0.8, 1.0], "phi": 0.25, "box": [20, 40, 80]}"#);
    // Kinetic at eps > 0.9, else clustering for L > 30, shearing below.
    let label = |e: f64, l: f64| {
        if e > 0.9 {
            "kinetic"
        } else if l > 30.0 {
            "clustering"
        } else {
            "shearing"
        }
    };
    let pts = points(&s, &records(&s, label));
    assert_eq!(pts.len(), 9);
    let round = plan(&pts, &[RefineAxis::Eps, RefineAxis::Box], 100);
    let got: Vec<(f64, f64)> = round
        .iter()
        .map(|g| (g.eps.values()[0], g.box_len.as_ref().unwrap().values()[0]))
        .collect();
    // Along eps: (0.8, 1.0) differs on every box line; along box: (20, 40) at eps 0.6 and 0.8.
    assert_eq!(
        got,
        vec![
            (0.9, 20.0),
            (0.9, 40.0),
            (0.9, 80.0),
            (0.6, 28.28427125),
            (0.8, 28.28427125)
        ]
    );
    // The budget stops the round in order.
    assert_eq!(plan(&pts, &[RefineAxis::Eps, RefineAxis::Box], 2).len(), 2);
    let b = boundary(&pts, &[RefineAxis::Eps]);
    assert_eq!(b.len(), 3);
    assert_eq!(
        b[0].regimes,
        ["kinetic".to_string(), "shearing".to_string()]
    );
    assert_eq!(
        (b[0].lower, b[0].upper, b[0].at, b[0].half_width),
        (0.8, 1.0, 0.9, 0.09999999999999998)
    );
    assert_eq!(b[0].below, "shearing");
}

#[test]
fn a_round_extends_the_spec_and_keeps_the_hash() {
    let s = spec(r#"{"eps": [0.6, 1.0], "n": 100, "phi": 0.1}"#);
    let pts = points(
        &s,
        &records(&s, |e, _| if e > 0.9 { "kinetic" } else { "clustering" }),
    );
    let round = plan(&pts, &[RefineAxis::Eps], 10);
    let t = with_round(&s, &[RefineAxis::Eps], round);
    assert_eq!(t.hash(), s.hash());
    assert_eq!(t.replicas().len(), 3);
    assert_eq!(t.replicas()[2].eps, 0.8);
    assert_eq!(t.replicas()[2].seed, s.replicas()[0].seed);
    // The spec with its refinement reads back as it was written.
    assert_eq!(Spec::from_json(&t.canonical_json()).unwrap(), t);
    assert_eq!(full_grid_replicas(&s, &[RefineAxis::Eps], 2), 5);
}

#[test]
fn axes_must_vary() {
    let s = spec(r#"{"eps": [0.6, 1.0], "n": 100, "phi": 0.1}"#);
    assert_eq!(choose_axes(&s, None).unwrap(), vec![RefineAxis::Eps]);
    let e = choose_axes(&s, Some(&[RefineAxis::Box])).unwrap_err();
    assert!(e.to_string().contains("--axes box"), "{e}");
}

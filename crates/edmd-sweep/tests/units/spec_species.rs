//! Unit tests of `spec::species`.

use edmd_sweep::spec::{species_counts as counts, species_label as label, Species, SpeciesAxis};

fn s(fraction: f64) -> Species {
    Species {
        fraction,
        diameter: 1.0,
        mass: None,
    }
}

#[test]
fn labels_are_short() {
    let m = [
        s(0.5),
        Species {
            fraction: 0.5,
            diameter: 1.4,
            mass: None,
        },
    ];
    assert_eq!(label(&m, 2), "0.5:1:1+0.5:1.4:1.96");
}

#[test]
fn counts_sum_to_n() {
    assert_eq!(counts(&[s(0.5), s(0.5)], 7), vec![4, 3]);
    assert_eq!(counts(&[s(0.2), s(0.3), s(0.5)], 10), vec![2, 3, 5]);
    assert_eq!(
        counts(&[s(1.0 / 3.0), s(1.0 / 3.0), s(1.0 / 3.0)], 100),
        vec![34, 33, 33]
    );
    assert_eq!(counts(&[s(0.999), s(0.001)], 100), vec![100, 0]);
}

#[test]
fn one_mixture_or_an_axis() {
    let one: SpeciesAxis = serde_json::from_str(
        r#"[{"fraction": 0.5, "diameter": 1}, {"fraction": 0.5, "diameter": 1.4, "mass": 2}]"#,
    )
    .unwrap();
    assert_eq!(one.0.len(), 1);
    assert_eq!(one.0[0][1].mass, Some(2.0));
    let back = serde_json::to_string(&one).unwrap();
    assert!(back.starts_with("[{"), "{back}");
    let axis: SpeciesAxis = serde_json::from_str(
        r#"[[{"fraction": 1, "diameter": 1}], [{"fraction": 1, "diameter": 2}]]"#,
    )
    .unwrap();
    assert_eq!(axis.0.len(), 2);
    let err = serde_json::from_str::<SpeciesAxis>(r#"[{"fraction": 1, "diam": 1}]"#).unwrap_err();
    assert!(err.to_string().contains("unknown field `diam`"), "{err}");
}

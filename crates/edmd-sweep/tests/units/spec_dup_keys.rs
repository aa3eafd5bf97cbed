//! Unit tests of the spec's duplicate-key check (through `Spec::from_json`, which runs it first).

use edmd_sweep::spec::Spec;

/// The message of reading `text` as a spec.
fn error(text: &str) -> String {
    Spec::from_json(text).unwrap_err().to_string()
}

#[test]
fn repeated_keys_are_found_at_any_depth() {
    // No repeated key: whatever else is wrong, not that.
    assert!(!error(r#"{"grid": {"eps": [1, 0.9]}, "name": "x"}"#).contains("duplicate key"));
    let e = error(r#"{"grid": {"eps": [1, 0.95, 0.9], "eps": 0.5}}"#);
    assert!(
        e.contains("grid.eps: duplicate key `eps` (a key may appear once in an object)"),
        "{e}"
    );
    let e = error(r#"{"grid": [{"species": [{"mass": 1, "mass": 2}]}]}"#);
    assert!(e.contains("grid[0].species[0].mass: duplicate key"), "{e}");
    // Text that is not JSON is left to the parser, which names it.
    assert!(!error("not json").contains("duplicate key"));
}

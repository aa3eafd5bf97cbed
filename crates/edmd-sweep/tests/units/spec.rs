//! Unit tests of the spec types.

use edmd_sweep::spec::Spec;

/// The committed schema is the one the types generate: regenerate it with
/// `cargo run -p edmd-cli -- spec-schema > docs/sweep-spec.schema.json` after changing a type.
#[test]
fn committed_schema_matches_the_types() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/sweep-spec.schema.json"
    );
    let committed = std::fs::read_to_string(path).expect("docs/sweep-spec.schema.json");
    assert!(
        committed == Spec::json_schema_text(),
        "docs/sweep-spec.schema.json differs from the spec types: run \
         `cargo run -p edmd-cli -- spec-schema > docs/sweep-spec.schema.json`"
    );
}

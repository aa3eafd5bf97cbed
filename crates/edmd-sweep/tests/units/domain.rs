//! Unit tests of `domain`.

use edmd_sweep::domain::*;
use serde_json::json;

#[test]
fn domains_include_and_exclude_their_ends() {
    assert!(RESTITUTION.contains(0.0) && RESTITUTION.contains(1.0));
    assert!(!RESTITUTION.contains(1.0 + 1e-12) && !RESTITUTION.contains(f64::NAN));
    assert!(!TAU_MAX.contains(0.0) && TAU_MAX.contains(1e-300));
    assert!(!TAU_MAX.contains(f64::INFINITY));
    assert!(N.contains(2.0) && !N.contains(1.0) && !N.contains(2.5));
    assert!(!TEMPERATURE_RATIO.contains(1.0) && TEMPERATURE_RATIO.contains(0.5));
    assert_eq!(
        RESTITUTION.value(),
        json!({"type": "number", "minimum": 0, "maximum": 1})
    );
    assert_eq!(
        TAU_MAX.value(),
        json!({"type": "number", "exclusiveMinimum": 0})
    );
    assert_eq!(
        N.value(),
        json!({"type": "integer", "minimum": 2, "maximum": 2147483647})
    );
}

//! Unit tests of `lock`.

use edmd_sweep::lock::*;
use edmd_sweep::spec::Shard;

#[test]
fn exclusive_excludes_everything_and_shards_exclude_only_themselves() {
    let tmp = tempfile::tempdir().unwrap();
    let root = tmp.path();
    let s = |k, n| LockMode::Shard(Shard { k, n });
    let a = lock(root, s(0, 2)).unwrap();
    let b = lock(root, s(1, 2)).unwrap();
    let again = lock(root, s(1, 2)).unwrap_err().to_string();
    assert!(
        again.contains("in use by another edmd run (shard 1/2, PID "),
        "{again}"
    );
    let excl = lock(root, LockMode::Exclusive).unwrap_err().to_string();
    assert!(excl.contains("shard 0/2, PID"), "{excl}");
    assert!(excl.contains("shard 1/2, PID"), "{excl}");
    drop((a, b));
    let held = lock(root, LockMode::Exclusive).unwrap();
    let pid = std::process::id();
    let other = lock(root, s(0, 2)).unwrap_err().to_string();
    assert!(other.contains(&format!("(PID {pid})")), "{other}");
    assert_eq!(running(root), Some(format!("PID {pid}")));
    drop(held);
    assert_eq!(running(root), None);
    let shard = lock(root, s(0, 2)).unwrap();
    assert_eq!(running(root), Some(format!("shard 0/2, PID {pid}")));
    drop(shard);
}

//! Unit tests of `files`.

use edmd_sweep::files::*;

#[test]
fn a_link_is_never_written_through() {
    let tmp = tempfile::tempdir().unwrap();
    let target = tmp.path().join("precious");
    std::fs::write(&target, "keep me\n").unwrap();
    let link = tmp.path().join("link");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let e = open_no_follow(&link).unwrap_err().to_string();
    assert!(e.contains("is a symbolic link"), "{e}");
    // A fresh file replaces the link itself.
    use std::io::Write;
    create_fresh(&link).unwrap().write_all(b"new").unwrap();
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep me\n");
    assert_eq!(std::fs::read_to_string(&link).unwrap(), "new");
    assert!(!std::fs::symlink_metadata(&link).unwrap().is_symlink());
    // A dangling link is seen and removed.
    let dangling = tmp.path().join("dangling");
    std::os::unix::fs::symlink(tmp.path().join("nowhere"), &dangling).unwrap();
    assert!(entry_exists(&dangling) && !dangling.exists());
    create_fresh(&dangling).unwrap();
    assert!(!tmp.path().join("nowhere").exists());
}

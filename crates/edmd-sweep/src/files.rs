//! Files the runner creates in an output directory, opened without following symbolic links.
//!
//! An output directory can be shared (a cluster's scratch space, a directory another user can
//! write to). A symbolic link planted under one of our names (`OUT/.lock` pointing at a system
//! file, say) must never make `edmd` write through it: every file we create or rewrite is opened
//! with `O_NOFOLLOW`, and a new file is created exclusively (`O_CREAT | O_EXCL`), so that the
//! name we write is the file we made.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};

use crate::SweepError;

/// The error for a symbolic link (or any other non-file) found where a file of ours belongs.
fn refused(path: &Path, what: &str) -> SweepError {
    SweepError::Output(format!(
        "refusing {}: it is {what}, not a regular file (edmd never writes through links in an output directory); remove it and run again",
        path.display()
    ))
}

/// Maps the `ELOOP` of an `O_NOFOLLOW` open to [`refused`].
fn nofollow_error(path: &Path, action: &'static str, e: io::Error) -> SweepError {
    if e.raw_os_error() == Some(libc::ELOOP) {
        refused(path, "a symbolic link")
    } else {
        SweepError::io(action, path, e)
    }
}

/// Opens `path` for reading and writing, creating it when missing, never through a symbolic link;
/// refuses anything but a regular file. Used for lock files, which live as long as the directory.
pub fn open_no_follow(path: &Path) -> Result<File, SweepError> {
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .custom_flags(libc::O_NOFOLLOW)
        .open(path)
        .map_err(|e| nofollow_error(path, "cannot open", e))?;
    let meta = file
        .metadata()
        .map_err(|e| SweepError::io("cannot open", path, e))?;
    if !meta.is_file() {
        return Err(refused(path, "not a regular file"));
    }
    Ok(file)
}

/// Removes what is at `path` when it is a file or a symbolic link (the link itself, never its
/// target); a missing path is fine. A directory is left and reported.
pub fn remove_stale(path: &Path) -> Result<(), SweepError> {
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(SweepError::io("cannot inspect", path, e)),
        Ok(m) if m.is_dir() => Err(refused(path, "a directory")),
        Ok(_) => std::fs::remove_file(path).map_err(|e| SweepError::io("cannot remove", path, e)),
    }
}

/// Whether anything (a file, a link, even a dangling one) is at `path`.
pub fn entry_exists(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok()
}

/// Creates `path` as a new, empty regular file for writing: a stale file or link under that name
/// (a killed run's temporary file, a planted link) is removed first, and the new file is created
/// exclusively and without following links.
pub fn create_fresh(path: &Path) -> Result<File, SweepError> {
    remove_stale(path)?;
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .custom_flags(libc::O_NOFOLLOW)
        .open(path)
        .map_err(|e| nofollow_error(path, "cannot create", e))
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, so that a
/// reader never sees a half-written file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), SweepError> {
    write_atomic_parts(path, &[bytes])
}

/// [`write_atomic`] of the concatenation of `parts`, without copying them into one buffer.
pub fn write_atomic_parts(path: &Path, parts: &[&[u8]]) -> Result<(), SweepError> {
    let tmp = tmp_path(path);
    let mut file = create_fresh(&tmp)?;
    let result = parts
        .iter()
        .try_for_each(|p| file.write_all(p))
        .and_then(|_| file.sync_all())
        .and_then(|_| fs::rename(&tmp, path))
        .and_then(
            |_| match path.parent().filter(|d| !d.as_os_str().is_empty()) {
                Some(dir) => fs::File::open(dir)?.sync_all(),
                None => fs::File::open(".")?.sync_all(),
            },
        );
    result.map_err(|e| {
        let _ = fs::remove_file(&tmp);
        SweepError::io("cannot write", path, e)
    })
}

/// A temporary name beside `path`, unique to this process.
pub(crate) fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp{}", std::process::id()));
    path.with_file_name(name)
}

//! The advisory lock on an output directory (`OUT/.lock`, `flock` through [`std::fs::File::try_lock`]).
//!
//! An unsharded `run` and `merge` hold `OUT/.lock` exclusively; a shard `K/N` holds it shared (the
//! shards of one Slurm array write into one directory at the same time) and holds
//! `OUT/.lock.shard-K-of-N` exclusively, so that the same shard never runs twice at once. Each holder
//! writes its PID into the file it holds exclusively; a refused run names that PID. The lock is
//! released when the process ends, however it ends (the kernel drops `flock` locks with the file).

use std::fs::{File, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

use crate::spec::Shard;
use crate::SweepError;

/// How a process uses an output directory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LockMode {
    /// Alone: an unsharded run, or a merge.
    Exclusive,
    /// One shard of a sharded run, beside the other shards.
    Shard(Shard),
}

/// A held lock; dropping it releases it.
#[derive(Debug)]
pub struct OutLock {
    _main: File,
    _shard: Option<File>,
}

/// Opens a lock file, never through a symbolic link ([`crate::files`]).
fn open(path: &Path) -> Result<File, SweepError> {
    crate::files::open_no_follow(path)
}

/// The PID written into a lock file, if any.
fn holder(path: &Path) -> Option<u32> {
    let mut text = String::new();
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NOFOLLOW)
        .open(path)
        .ok()?
        .take(64)
        .read_to_string(&mut text)
        .ok()?;
    text.trim().parse().ok()
}

fn write_pid(file: &mut File, path: &Path) -> Result<(), SweepError> {
    file.set_len(0)
        .and_then(|_| file.rewind())
        .and_then(|_| writeln!(file, "{}", std::process::id()))
        .and_then(|_| file.flush())
        .map_err(|e| SweepError::io("cannot write lock file", path, e))
}

/// Shard lock files of `root` whose lock is held now, with their PIDs.
fn shard_holders(root: &Path) -> Vec<(String, Option<u32>)> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(root) else {
        return out;
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(shard) = name.strip_prefix(".lock.shard-") else {
            continue;
        };
        let Ok(f) = crate::files::open_no_follow(&entry.path()) else {
            continue;
        };
        if let Err(TryLockError::WouldBlock) = f.try_lock_shared() {
            out.push((shard.replace("-of-", "/"), holder(&entry.path())));
        }
    }
    out.sort();
    out
}

fn busy(root: &Path, who: String) -> SweepError {
    SweepError::Output(format!(
        "output {} is in use by another edmd run ({who}); wait for it to end or choose another -o",
        root.display()
    ))
}

fn pid(p: Option<u32>) -> String {
    p.map_or("PID unknown".to_string(), |p| format!("PID {p}"))
}

/// Who is running in `root` now, if anyone: the exclusive holder's PID, or the shards that hold
/// their locks (for `status`, which takes no lock). `None` when no run or merge holds `OUT/.lock`.
pub fn running(root: &Path) -> Option<String> {
    let main_path = root.join(".lock");
    use std::os::unix::fs::OpenOptionsExt;
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NOFOLLOW)
        .open(&main_path)
        .ok()?;
    match file.try_lock_shared() {
        Ok(()) => {
            // Free for a shared lock: no exclusive holder, but shards may be running.
            let shards = shard_holders(root);
            (!shards.is_empty()).then(|| {
                let list: Vec<String> = shards
                    .iter()
                    .map(|(s, p)| format!("shard {s}, {}", pid(*p)))
                    .collect();
                list.join("; ")
            })
        }
        Err(TryLockError::WouldBlock) => Some(pid(holder(&main_path))),
        Err(TryLockError::Error(_)) => None,
    }
}

/// Takes the lock of the output directory `root` (which must exist) in `mode`, or says who holds it.
pub fn lock(root: &Path, mode: LockMode) -> Result<OutLock, SweepError> {
    let main_path = root.join(".lock");
    let mut main = open(&main_path)?;
    let refused = |e: TryLockError, exclusive_wanted: bool| match e {
        TryLockError::WouldBlock => {
            let shards = shard_holders(root);
            let who = if exclusive_wanted && !shards.is_empty() {
                let list: Vec<String> = shards
                    .iter()
                    .map(|(s, p)| format!("shard {s}, {}", pid(*p)))
                    .collect();
                list.join("; ")
            } else {
                pid(holder(&main_path))
            };
            busy(root, who)
        }
        TryLockError::Error(e) => SweepError::io("cannot lock", &main_path, e),
    };
    match mode {
        LockMode::Exclusive => {
            main.try_lock().map_err(|e| refused(e, true))?;
            write_pid(&mut main, &main_path)?;
            Ok(OutLock {
                _main: main,
                _shard: None,
            })
        }
        LockMode::Shard(s) => {
            main.try_lock_shared().map_err(|e| refused(e, false))?;
            let shard_path: PathBuf = root.join(format!(".lock.shard-{}-of-{}", s.k, s.n));
            let mut shard = open(&shard_path)?;
            shard.try_lock().map_err(|e| match e {
                TryLockError::WouldBlock => busy(
                    root,
                    format!("shard {}/{}, {}", s.k, s.n, pid(holder(&shard_path))),
                ),
                TryLockError::Error(e) => SweepError::io("cannot lock", &shard_path, e),
            })?;
            write_pid(&mut shard, &shard_path)?;
            Ok(OutLock {
                _main: main,
                _shard: Some(shard),
            })
        }
    }
}

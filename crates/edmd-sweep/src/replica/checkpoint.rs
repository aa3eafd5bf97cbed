//! Checkpoints of running replicas: when one is due, what it holds, and its file.
//!
//! A replica in flight saves its whole state every `checkpoint.every_s` seconds of wall time (and,
//! if asked, whenever τ passes a multiple of `checkpoint.every_tau`), and at once when the run is
//! interrupted (SIGTERM, SIGINT, SIGUSR1). The next `edmd run` into the same directory goes on from
//! it: the engine's state is kept verbatim (`edmd_core::Simulation::save_state`) and so is the
//! runner's (the series and snapshots so far, the sample point it was heading for, the virial
//! meter, the stall window), so the final file is bit for bit the one an uninterrupted run writes.
//! A checkpoint is taken between two chunks of events, where the runner holds nothing else.
//!
//! The file, `states/rNNNNN.ckpt`, written under a temporary name, synced and renamed:
//! ```text
//! "EDMDCKPT" | u64 LE header length | header (JSON, [`Header`]) | u64 LE runner length
//!            | runner state (postcard) | engine state (the rest)
//! ```
//! The header alone tells `edmd status` and Python how far the replica got.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use serde::{Deserialize, Serialize};

use edmd_core::{Counters, VirialMeter};

use super::bed_meter::BedMeter;
use super::{Series, Snapshot};
use crate::files::write_atomic_parts;
use crate::spec::Spec;

const MAGIC: &[u8; 8] = b"EDMDCKPT";
/// The version of the runner's part of the layout (the engine's carries its own).
pub const FORMAT: u32 = 3;

/// What a checkpoint says about itself, readable without the state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// [`FORMAT`] of the file.
    pub format: u32,
    /// The hash of the spec whose replica this is.
    pub spec_hash: String,
    /// The replica's index.
    pub replica: usize,
    /// τ reached.
    pub tau: f64,
    /// Pair collisions reached.
    pub collisions: u64,
    /// Wall-clock seconds the replica had run, over all its runs.
    pub wall_s: f64,
    /// When it was written, in seconds since the Unix epoch.
    pub written: f64,
    /// Why: "interval", "tau" or "signal".
    pub reason: String,
}

/// The runner's state between two chunks of events.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct RunnerState {
    pub series: Series,
    pub snapshots: Vec<Snapshot>,
    /// A final state keeps its snapshots in the replica's file only: the first this many of it.
    pub snapshots_in_file: usize,
    /// The sample point the run is heading for, and the next snapshot time.
    pub point: f64,
    pub next_snapshot: Option<f64>,
    pub sampled_at: Option<u64>,
    /// The counters at the start of the stall window.
    pub window: Counters,
    /// The sampler's initial temperature, its running virial meter and its counters at the start.
    pub t0: f64,
    pub meter: Option<VirialMeter>,
    pub start: Counters,
    pub wall_s: f64,
    pub resumes: u64,
    /// A shaken bed's uniform-time samples so far.
    pub bed: Option<BedMeter>,
}

/// [`RunnerState`] as it is written: borrowed from the running replica (no copy of its series and
/// snapshots), the same fields in the same order.
#[derive(Debug, Serialize)]
pub(crate) struct RunnerSaving<'a> {
    pub series: &'a Series,
    pub snapshots: &'a [Snapshot],
    pub snapshots_in_file: usize,
    pub point: f64,
    pub next_snapshot: Option<f64>,
    pub sampled_at: Option<u64>,
    pub window: Counters,
    pub t0: f64,
    pub meter: Option<VirialMeter>,
    pub start: Counters,
    pub wall_s: f64,
    pub resumes: u64,
    pub bed: Option<&'a BedMeter>,
}

/// A replica's state as a checkpoint holds it.
#[derive(Debug, Clone)]
pub(crate) struct Saved {
    pub runner: RunnerState,
    pub engine: Vec<u8>,
}

/// A replica's state encoded for a checkpoint: the runner's part, its wall seconds, the engine's.
#[derive(Debug)]
pub(crate) struct Encoded {
    pub runner: Vec<u8>,
    pub wall_s: f64,
    pub engine: Vec<u8>,
}

impl Encoded {
    /// Encodes a runner state ([`RunnerState`] or [`RunnerSaving`]) beside the engine's bytes.
    pub(crate) fn new(runner: &impl Serialize, wall_s: f64, engine: Vec<u8>) -> Self {
        Encoded {
            runner: postcard::to_allocvec(runner).expect("the runner state serialises"),
            wall_s,
            engine,
        }
    }
}

/// How a run checkpoints its replicas: the settings, the interrupt flag and the first write error.
#[derive(Debug)]
pub struct Checkpoints<'a> {
    every_s: f64,
    every_tau: Option<f64>,
    keep_final: bool,
    spec_hash: String,
    dir: PathBuf,
    interrupt: &'a AtomicBool,
    /// What went wrong with checkpoints: one that could not be written (its replica went on
    /// without it) or one that could not be used (its replica started over).
    pub notices: Mutex<Vec<String>>,
    resumed: AtomicUsize,
    /// The pair collisions the resumed replicas had run before.
    resumed_collisions: AtomicU64,
    /// Checkpoints written, and the nanoseconds spent on them (the state gathered, written, synced).
    written: AtomicU64,
    writing_ns: AtomicU64,
}

impl<'a> Checkpoints<'a> {
    /// Checkpoints of `spec`'s replicas into `dir`, taken at once when `interrupt` is set.
    pub fn new(spec: &Spec, dir: PathBuf, interrupt: &'a AtomicBool) -> Self {
        let c = spec.checkpoint.clone().unwrap_or_default();
        Checkpoints {
            every_s: c.every_s,
            every_tau: c.every_tau,
            keep_final: c.keep_final,
            spec_hash: spec.hash(),
            dir,
            interrupt,
            notices: Mutex::new(Vec::new()),
            resumed: AtomicUsize::new(0),
            resumed_collisions: AtomicU64::new(0),
            written: AtomicU64::new(0),
            writing_ns: AtomicU64::new(0),
        }
    }

    /// Whether replicas keep their final state for `edmd extend`.
    pub fn keep_final(&self) -> bool {
        self.keep_final
    }

    /// Whether the run was interrupted.
    pub fn interrupted(&self) -> bool {
        self.interrupt.load(Ordering::Relaxed)
    }

    /// The checkpoint of replica `index`.
    pub fn path(&self, index: usize) -> PathBuf {
        file_in(&self.dir, index)
    }

    /// The saved state of replica `index`, when a checkpoint of this spec's replica is there and
    /// whole; `Err` names what is wrong with one that is there but cannot be used.
    pub(crate) fn load(&self, index: usize) -> Result<Option<Saved>, String> {
        let path = self.path(index);
        if !path.exists() {
            return Ok(None);
        }
        let (header, saved) = read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        if header.spec_hash != self.spec_hash || header.replica != index {
            return Err(format!(
                "{}: of spec {} replica {}, not of this one",
                path.display(),
                header.spec_hash,
                header.replica
            ));
        }
        self.resumed.fetch_add(1, Ordering::Relaxed);
        self.resumed_collisions
            .fetch_add(header.collisions, Ordering::Relaxed);
        Ok(Some(saved))
    }

    /// Replicas that went on from a checkpoint.
    pub fn resumed(&self) -> usize {
        self.resumed.load(Ordering::Relaxed)
    }

    /// The pair collisions the resumed replicas had run before their checkpoints.
    pub fn resumed_collisions(&self) -> u64 {
        self.resumed_collisions.load(Ordering::Relaxed)
    }

    /// Checkpoints written, and the seconds they took (summed over the replicas).
    pub fn written(&self) -> (u64, f64) {
        (
            self.written.load(Ordering::Relaxed),
            self.writing_ns.load(Ordering::Relaxed) as f64 * 1e-9,
        )
    }

    /// Counts a checkpoint that took `seconds`, from gathering the state to its rename.
    pub(crate) fn count(&self, seconds: f64) {
        self.written.fetch_add(1, Ordering::Relaxed);
        self.writing_ns
            .fetch_add((seconds * 1e9) as u64, Ordering::Relaxed);
    }

    /// Tells the run's user about a checkpoint (at the end of the run).
    pub(crate) fn notice(&self, message: String) {
        self.notices.lock().expect("lock").push(message);
    }

    /// Writes replica `index`'s checkpoint; a failure becomes a notice, not an error.
    pub(crate) fn save(&self, index: usize, tau: f64, collisions: u64, why: &str, s: &Encoded) {
        self.write(&self.path(index), index, tau, collisions, why, s);
    }

    /// Writes replica `index`'s final state (`rNNNNN.final`), from which `edmd extend` goes on.
    pub(crate) fn save_final(&self, index: usize, tau: f64, collisions: u64, s: &Encoded) {
        self.write(
            &final_in(&self.dir, index),
            index,
            tau,
            collisions,
            "final",
            s,
        );
    }

    fn write(&self, path: &Path, index: usize, tau: f64, collisions: u64, why: &str, s: &Encoded) {
        if let Err(e) = std::fs::create_dir_all(&self.dir) {
            self.notice(format!(
                "checkpoint not written, the replica goes on: {}: {e}",
                self.dir.display()
            ));
            return;
        }
        let header = Header {
            format: FORMAT,
            spec_hash: self.spec_hash.clone(),
            replica: index,
            tau,
            collisions,
            wall_s: s.wall_s,
            written: SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0.0, |d| d.as_secs_f64()),
            reason: why.into(),
        };
        let head = serde_json::to_vec(&header).expect("a header serialises");
        let runner = &s.runner;
        let head_len = (head.len() as u64).to_le_bytes();
        let runner_len = (runner.len() as u64).to_le_bytes();
        let parts: [&[u8]; 6] = [MAGIC, &head_len, &head, &runner_len, runner, &s.engine];
        let written = write_atomic_parts(path, &parts);
        if let Err(e) = written {
            self.notice(format!("checkpoint not written, the replica goes on: {e}"));
        }
    }
}

/// The checkpoint of replica `index` in the replicas' directory `dir`: `rNNNNN.ckpt`.
pub fn file_in(dir: &Path, index: usize) -> PathBuf {
    dir.join(format!("r{index:05}.ckpt"))
}

/// The final state of replica `index` in the replicas' directory `dir`: `rNNNNN.final`.
pub fn final_in(dir: &Path, index: usize) -> PathBuf {
    dir.join(format!("r{index:05}.final"))
}

/// When the next checkpoint of one replica is due.
#[derive(Debug)]
pub(crate) struct Timer {
    last: Instant,
    next_tau: f64,
}

impl Timer {
    pub(crate) fn new(c: &Checkpoints, tau: f64) -> Self {
        Timer {
            last: Instant::now(),
            next_tau: c.every_tau.map_or(f64::INFINITY, |e| next_multiple(tau, e)),
        }
    }

    /// Why a checkpoint is due at τ = `tau`, if one is; the timer starts over.
    pub(crate) fn due(&mut self, c: &Checkpoints, tau: f64) -> Option<&'static str> {
        let why = if c.interrupted() {
            "signal"
        } else if tau >= self.next_tau {
            "tau"
        } else if c.every_s > 0.0 && self.last.elapsed().as_secs_f64() >= c.every_s {
            "interval"
        } else {
            return None;
        };
        self.last = Instant::now();
        if let Some(e) = c.every_tau {
            self.next_tau = next_multiple(tau, e);
        }
        Some(why)
    }
}

/// The first multiple of `every` above `tau`.
fn next_multiple(tau: f64, every: f64) -> f64 {
    ((tau / every).floor() + 1.0) * every
}

fn bad(what: impl Into<String>) -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::InvalidData, what.into())
}

fn read_section(f: &mut File, limit: u64) -> std::io::Result<Vec<u8>> {
    let mut len = [0u8; 8];
    f.read_exact(&mut len)?;
    let len = u64::from_le_bytes(len);
    if len > limit {
        return Err(bad(format!("a section of {len} bytes, beyond the file")));
    }
    let mut v = vec![0u8; len as usize];
    f.read_exact(&mut v)?;
    Ok(v)
}

/// Opens a checkpoint and reads its header.
fn open(path: &Path) -> std::io::Result<(File, Header, u64)> {
    let mut f = File::open(path)?;
    let size = f.metadata()?.len();
    let mut magic = [0u8; 8];
    f.read_exact(&mut magic)?;
    if &magic != MAGIC {
        return Err(bad("not an edmd checkpoint"));
    }
    let head = read_section(&mut f, size)?;
    let header: Header = serde_json::from_slice(&head).map_err(|e| bad(format!("header: {e}")))?;
    if header.format != FORMAT {
        return Err(bad(format!(
            "format {}, this build reads {FORMAT}",
            header.format
        )));
    }
    Ok((f, header, size))
}

/// The header of the checkpoint at `path`.
pub fn read_header(path: &Path) -> std::io::Result<Header> {
    open(path).map(|(_, h, _)| h)
}

/// The header and the saved state of the checkpoint at `path`.
pub(crate) fn read(path: &Path) -> std::io::Result<(Header, Saved)> {
    let (mut f, header, size) = open(path)?;
    let runner = read_section(&mut f, size)?;
    let runner: RunnerState =
        postcard::from_bytes(&runner).map_err(|e| bad(format!("runner state: {e}")))?;
    let mut engine = Vec::new();
    f.read_to_end(&mut engine)?;
    Ok((header, Saved { runner, engine }))
}

//! Up-front resource estimates: the memory a replica and a run need, computed from the spec alone and
//! checked against the machine's memory (or an explicit limit) before anything is written or allocated.
//!
//! The estimate is an upper bound built from measured sizes, not an exact account: the engine's peak
//! heap per particle (docs/benchmarks.md: 118-196 bytes in 2D, 180-375 in 3D with neighbour lists,
//! rounded up here to leave room for the observables' per-particle buffers), the snapshots held until
//! the file is written (positions and velocities, plus the copy the writer makes of one of them), the
//! sample columns and the classifier's grid.

use std::fmt;

use crate::spec::{Density, Replica, Spec};
use crate::SweepError;

/// Engine heap per particle in 2D and 3D (bytes), measured peaks rounded up.
const ENGINE_BYTES: [f64; 2] = [320.0, 640.0];
/// Bytes per sample: every observable and order-parameter column is one f64 per sample.
const SAMPLE_BYTES: f64 = 32.0 * 8.0;
/// Bytes per cell of the classifier's order-parameter grid (density, momentum, their transforms).
const CLASSIFY_CELL_BYTES: f64 = 16.0 * 8.0;

/// Where the memory of one replica goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplicaBytes {
    /// Engine state (positions, velocities, cells, calendar, lists).
    pub engine: f64,
    /// Snapshots held until the file is written.
    pub snapshots: f64,
    /// Observable columns.
    pub samples: f64,
    /// Order-parameter grid of the classifier.
    pub classify: f64,
}

impl ReplicaBytes {
    /// The total.
    pub fn total(&self) -> f64 {
        self.engine + self.snapshots + self.samples + self.classify
    }
}

/// Snapshots a replica stores at most (the `at` list, the linear and logarithmic grids, the final
/// state, and τ = 0 of a collapse).
pub fn snapshots_per_replica(spec: &Spec) -> usize {
    spec.snapshots.count_to(spec.stop.tau_max) as usize + spec.snapshots.last as usize + 1
}

/// The memory of one replica of `spec`.
pub fn replica_bytes(spec: &Spec, r: &Replica) -> ReplicaBytes {
    let n = r.n as f64;
    let d = r.dim as f64;
    let engine = ENGINE_BYTES[usize::from(r.dim == 3)] * n;
    // Positions and velocities of every snapshot, and the writer's flat copy of one trajectory.
    let snapshots = snapshots_per_replica(spec) as f64 * n * d * 8.0 * 3.0;
    let samples = spec.samples_per_replica() * SAMPLE_BYTES;
    let classify = spec.classify.as_ref().map_or(0.0, |c| {
        (c.grid_for(r.n, r.dim) as f64).powi(r.dim as i32) * CLASSIFY_CELL_BYTES
    });
    ReplicaBytes {
        engine,
        snapshots,
        samples,
        classify,
    }
}

/// Bytes as `1.5 GiB`.
#[derive(Debug, Clone, Copy)]
pub struct Bytes(pub f64);

impl fmt::Display for Bytes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let units = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
        let mut v = self.0;
        let mut k = 0;
        while v >= 1024.0 && k + 1 < units.len() {
            v /= 1024.0;
            k += 1;
        }
        if k == units.len() - 1 && v >= 1024.0 {
            write!(f, "{:.2e} B", self.0)
        } else if k == 0 {
            write!(f, "{v:.0} B")
        } else {
            write!(f, "{v:.1} {}", units[k])
        }
    }
}

/// The memory this process may use: the smaller of the machine's (`MemTotal` in /proc/meminfo) and
/// of its cgroup's limit (a container, a Slurm job), or `None` where neither can be read.
pub fn machine_memory() -> Option<u64> {
    let total = std::fs::read_to_string("/proc/meminfo").ok().and_then(|t| {
        t.lines()
            .find(|l| l.starts_with("MemTotal:"))
            .and_then(|l| l.split_whitespace().nth(1)?.parse::<u64>().ok())
            .map(|kib| kib * 1024)
    });
    let cgroup = [
        "/sys/fs/cgroup/memory.max",
        "/sys/fs/cgroup/memory/memory.limit_in_bytes",
    ]
    .iter()
    .find_map(|p| std::fs::read_to_string(p).ok()?.trim().parse::<u64>().ok());
    match (total, cgroup) {
        (Some(t), Some(c)) => Some(t.min(c)),
        (t, c) => t.or(c),
    }
}

/// The limit a run is checked against, and where it comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemoryLimit {
    /// Bytes.
    pub bytes: u64,
    /// True when given by the caller (`--max-memory`), false when read from the machine.
    pub explicit: bool,
}

impl MemoryLimit {
    /// `max` when given, else the machine's memory (`None` where it cannot be read: no check).
    pub fn new(max: Option<u64>) -> Option<MemoryLimit> {
        match max {
            Some(bytes) => Some(MemoryLimit {
                bytes,
                explicit: true,
            }),
            None => machine_memory().map(|bytes| MemoryLimit {
                bytes,
                explicit: false,
            }),
        }
    }

    fn describe(&self) -> String {
        if self.explicit {
            format!("the --max-memory of {}", Bytes(self.bytes as f64))
        } else {
            format!(
                "this machine's {} of memory (--max-memory sets another limit)",
                Bytes(self.bytes as f64)
            )
        }
    }
}

/// What a run of some replicas needs.
#[derive(Debug, Clone)]
pub struct Estimate {
    /// The replica that needs the most memory, and its bytes.
    pub largest: Option<(Replica, ReplicaBytes)>,
    /// Replicas running at once.
    pub threads: usize,
    /// Bytes of the `threads` largest replicas together: the run's peak.
    pub run_bytes: f64,
}

/// The memory of running `replicas` of `spec` on `threads` threads, checked against `limit`: an
/// error names the field that makes one replica too large (`grid.n`, `grid.box`, `snapshots.at`,
/// `classify.grid`) with the estimate, or `--threads` when only the replicas at once are too many.
pub fn check_memory(
    spec: &Spec,
    replicas: &[Replica],
    threads: usize,
    limit: Option<MemoryLimit>,
) -> Result<Estimate, SweepError> {
    let mut sizes: Vec<(f64, usize)> = replicas
        .iter()
        .enumerate()
        .map(|(i, r)| (replica_bytes(spec, r).total(), i))
        .collect();
    sizes.sort_by(|a, b| b.0.total_cmp(&a.0));
    let threads = threads.clamp(1, replicas.len().max(1));
    let run_bytes: f64 = sizes.iter().take(threads).map(|s| s.0).sum();
    let largest = sizes.first().map(|&(_, i)| {
        let r = replicas[i].clone();
        let b = replica_bytes(spec, &r);
        (r, b)
    });
    let estimate = Estimate {
        largest,
        threads,
        run_bytes,
    };
    let Some(limit) = limit else {
        return Ok(estimate);
    };
    let cap = limit.bytes as f64;
    if let Some((r, b)) = &estimate.largest {
        if b.total() > cap {
            let parts = [
                (b.engine, "engine"),
                (b.snapshots, "snapshots"),
                (b.samples, "samples"),
                (b.classify, "classifier grid"),
            ];
            let (_, top) =
                parts
                    .iter()
                    .copied()
                    .fold((f64::MIN, ""), |a, p| if p.0 > a.0 { p } else { a });
            let field = match (top, r.density) {
                ("snapshots", _) => match spec.snapshots.every {
                    Some(e) => format!(
                        "snapshots.every = {e} ({} snapshots)",
                        snapshots_per_replica(spec)
                    ),
                    None if spec.snapshots.per_decade > 0 => format!(
                        "snapshots.per_decade = {} ({} snapshots)",
                        spec.snapshots.per_decade,
                        snapshots_per_replica(spec)
                    ),
                    None => format!("snapshots.at = {} times", spec.snapshots.at.len()),
                },
                ("samples", _) => "samples".to_string(),
                ("classifier grid", _) => format!(
                    "classify.grid = {}",
                    spec.classify
                        .as_ref()
                        .map(|c| c.grid_for(r.n, r.dim))
                        .unwrap_or(0)
                ),
                (_, Density::Side(l)) if grid_n_absent(spec) => {
                    format!("grid.box = {l} (N = {})", r.n)
                }
                _ => format!("grid.n = {}", r.n),
            };
            let detail: Vec<String> = parts
                .iter()
                .filter(|p| p.0 > 0.0)
                .map(|p| format!("{} {}", p.1, Bytes(p.0)))
                .collect();
            return Err(SweepError::Spec(format!(
                "{field}: {r} needs about {} of memory ({}), above {}",
                Bytes(b.total()),
                detail.join(", "),
                limit.describe()
            )));
        }
    }
    if run_bytes > cap {
        let fit = sizes
            .iter()
            .scan(0.0, |acc, s| {
                *acc += s.0;
                Some(*acc)
            })
            .take_while(|&acc| acc <= cap)
            .count()
            .max(1);
        return Err(SweepError::Usage(format!(
            "--threads {threads}: {threads} replicas at once need about {}, above {}; use --threads {fit} or fewer",
            Bytes(run_bytes),
            limit.describe()
        )));
    }
    Ok(estimate)
}

/// Whether some grid of `spec` gives N through φ and the box (no `n` axis).
fn grid_n_absent(spec: &Spec) -> bool {
    spec.grid.values().iter().any(|g| g.n.is_none())
}

//! Signals that stop a run cleanly: SIGTERM (a scheduler's stop), SIGINT (Ctrl-C) and SIGUSR1
//! (what Slurm's `--signal` sends before a time limit) set one flag; every replica in flight then
//! writes its checkpoint and returns, and the command exits with [`EXIT_INTERRUPTED`]. A second
//! SIGINT or SIGTERM ends the process at once.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use signal_hook::consts::{SIGINT, SIGTERM, SIGUSR1};
use signal_hook::flag;

/// Exit status of a run stopped by a signal with its checkpoints written (BSD's EX_TEMPFAIL: run
/// the same command again to go on).
pub const EXIT_INTERRUPTED: u8 = 75;

/// The flag the signals set.
pub fn on_signals() -> anyhow::Result<Arc<AtomicBool>> {
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [SIGINT, SIGTERM] {
        // Registered first, so that it sees the flag as the previous signal left it.
        flag::register_conditional_shutdown(sig, 128 + sig, Arc::clone(&stop))?;
        flag::register(sig, Arc::clone(&stop))?;
    }
    flag::register(SIGUSR1, Arc::clone(&stop))?;
    Ok(stop)
}

/// A run that a signal stopped, `0` of its replicas left with a checkpoint or not started.
#[derive(Debug)]
pub struct Interrupted(pub usize);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "interrupted: {} replica(s) unfinished, those in flight saved as checkpoints; run the same command again to go on",
            self.0
        )
    }
}

impl std::error::Error for Interrupted {}

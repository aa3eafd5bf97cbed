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

/// A run that a signal stopped: its replicas left unfinished (with a checkpoint or not started),
/// and the checkpoints its output directory holds to go on from (none where the signal came
/// between replicas or between refinement rounds).
#[derive(Debug)]
pub struct Interrupted {
    pub unfinished: usize,
    pub saved: usize,
}

impl Interrupted {
    /// `unfinished` replicas of the run into `dir`, counting the checkpoints there.
    pub fn in_dir(unfinished: usize, dir: &edmd_sweep::output::OutDir) -> Self {
        let saved = std::fs::read_dir(dir.states_dir()).map_or(0, |entries| {
            entries
                .filter_map(Result::ok)
                .filter(|e| e.path().extension().is_some_and(|x| x == "ckpt"))
                .count()
        });
        Interrupted { unfinished, saved }
    }
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "interrupted: {} replica(s) unfinished, {} checkpoint(s) to go on from (those in flight were saved); run the same command again to go on",
            self.unfinished, self.saved
        )
    }
}

impl std::error::Error for Interrupted {}

//! How `Simulation.run` cuts a run into chunks: short enough that Ctrl-C is honoured within a
//! fraction of a second, and, when running until a temperature, ever shorter as the gas nears it,
//! so that the run stops within a few collisions of where T first falls to the target.

/// Pair collisions per chunk between two looks at Ctrl-C (about a tenth of a second).
const CHUNK_COLLISIONS: f64 = 2e5;
/// The first chunk towards a temperature, in τ: long enough to measure the cooling rate.
const PROBE_TAU: f64 = 0.1;
/// The finest chunk near a target temperature, in pair collisions.
const FINEST_COLLISIONS: f64 = 10.0;

/// The stops of one `run` call.
#[derive(Debug)]
pub(crate) struct Chunks {
    n: f64,
    /// τ and ln T at the start, for the mean cooling rate in τ (constant while homogeneous).
    start: (f64, f64),
    at: f64,
    ln_t: f64,
    limit: f64,
    ln_target: Option<f64>,
    done: bool,
}

impl Chunks {
    /// From τ `now` at temperature `temperature` to τ `limit`, or until T ≤ `target`.
    pub(crate) fn new(
        n: usize,
        now: f64,
        temperature: f64,
        limit: f64,
        target: Option<f64>,
    ) -> Self {
        let ln_t = temperature.ln();
        Chunks {
            n: n as f64,
            start: (now, ln_t),
            at: now,
            ln_t,
            limit,
            ln_target: target.map(f64::ln),
            done: target.is_some_and(|t| temperature <= t),
        }
    }

    /// The τ to run to next, or None when the run is over.
    pub(crate) fn next_stop(&self) -> Option<f64> {
        if self.done || self.at >= self.limit {
            return None;
        }
        let coarse = CHUNK_COLLISIONS / self.n;
        let step = match self.ln_target {
            None => coarse,
            Some(_) if self.at == self.start.0 => PROBE_TAU.min(coarse),
            Some(ln_target) => {
                let rate = (self.start.1 - self.ln_t) / (self.at - self.start.0);
                if rate > 0.0 {
                    (0.5 * (self.ln_t - ln_target) / rate).clamp(FINEST_COLLISIONS / self.n, coarse)
                } else {
                    PROBE_TAU.min(coarse) // not cooling (yet): look again soon
                }
            }
        };
        Some((self.at + step).min(self.limit))
    }

    /// Records the chunk that ran to `reached` (asked for `next`) at `temperature`; false when
    /// the run is over: the target reached, or the gas stopped short (no events, a collapse).
    pub(crate) fn advance(&mut self, next: f64, reached: f64, temperature: f64) -> bool {
        self.at = reached;
        self.ln_t = temperature.ln();
        if reached < next || self.ln_target.is_some_and(|t| self.ln_t <= t) {
            self.done = true;
        }
        !self.done
    }
}

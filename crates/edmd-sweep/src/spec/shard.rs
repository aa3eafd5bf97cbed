//! Shards: which replicas of a sweep one `edmd run --shard K/N` takes.

use crate::SweepError;

/// Which replicas a shard runs: `K/N` takes every replica whose index is `K` modulo `N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, 0-based.
    pub k: usize,
    /// Number of shards.
    pub n: usize,
}

impl Shard {
    /// Parses `K/N` with 0 ≤ K < N.
    pub fn parse(s: &str) -> Result<Shard, SweepError> {
        let err = || {
            SweepError::Usage(format!(
                "--shard {s}: expected K/N with 0 <= K < N, e.g. 0/4"
            ))
        };
        let (k, n) = s.split_once('/').ok_or_else(err)?;
        let k: usize = k.trim().parse().map_err(|_| err())?;
        let n: usize = n.trim().parse().map_err(|_| err())?;
        if n == 0 || k >= n {
            return Err(err());
        }
        Ok(Shard { k, n })
    }

    /// Whether the shard runs replica `index`.
    pub fn contains(&self, index: usize) -> bool {
        index % self.n == self.k
    }
}

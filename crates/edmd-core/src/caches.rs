//! What the machine's caches hold, for the switches that depend on it: the look-ahead of large
//! systems turns on when the engine's arrays are well beyond the per-core L2 (docs/benchmarks.md,
//! "Where the look-ahead pays, by state size").
//!
//! The L2 is read once from Linux's sysfs (`/sys/devices/system/cpu/cpu0/cache/index*/`); the L3 is
//! not used, because virtual machines report L3 sizes the guest does not have.

use std::sync::OnceLock;

/// The look-ahead switches on above this many times the per-core L2 (64 MiB with a 2 MiB L2): below,
/// its hints cost more than they save (docs/benchmarks.md, "Where the look-ahead pays").
pub const LOOK_AHEAD_L2_MULTIPLE: usize = 32;

/// The threshold where no L2 size can be read (other systems): that of a 2 MiB L2.
pub const LOOK_AHEAD_FALLBACK: usize = 64 << 20;

/// Bounds of the threshold, whatever a system reports (an absurd L2 size must not switch it).
const LOOK_AHEAD_RANGE: (usize, usize) = (16 << 20, 256 << 20);

/// Bytes of engine arrays above which the large-system look-ahead is on.
pub fn look_ahead_threshold() -> usize {
    static THRESHOLD: OnceLock<usize> = OnceLock::new();
    *THRESHOLD.get_or_init(|| threshold_for(l2_bytes()))
}

/// The per-core L2 where the system does not say: 1 MiB. The switches below compare a working set
/// with the L2 ([`l2_or_fallback`]).
pub const L2_FALLBACK: usize = 1 << 20;

/// The per-core L2 in bytes, or [`L2_FALLBACK`] where unknown.
pub fn l2_or_fallback() -> usize {
    static L2: OnceLock<usize> = OnceLock::new();
    *L2.get_or_init(|| l2_bytes().unwrap_or(L2_FALLBACK))
}

/// The switches of cache-resident work (partner hints, deferred filings) turn on above this many
/// times the per-core L2: while the working set is cached they only add instructions
/// (docs/benchmarks.md, "The small-system switches at twice the L2").
pub const SWITCH_L2_MULTIPLE: usize = 2;

/// The bytes above which a cache-resident switch turns on, for an L2 of `l2` bytes.
fn switch_for(l2: usize) -> usize {
    l2.saturating_mul(SWITCH_L2_MULTIPLE)
}

/// Bytes of particle records above which list scans ask for their partners' records ahead: twice
/// the L2, below which the records are cached anyway (docs/benchmarks.md, "The four-wide list
/// scan").
pub fn partner_hints_threshold() -> usize {
    switch_for(l2_or_fallback())
}

/// Bytes of calendar buckets and per-particle records (which hold the calendar entries) above which
/// the Paul calendar defers its filings into later buckets: twice the L2. Below it the bucket lines
/// are cached and deferring only adds work (docs/benchmarks.md, "Deferral by size").
pub fn calendar_deferral_threshold() -> usize {
    switch_for(l2_or_fallback())
}

/// The threshold for an L2 of `l2` bytes (`None`: unknown).
fn threshold_for(l2: Option<usize>) -> usize {
    l2.map_or(LOOK_AHEAD_FALLBACK, |b| {
        b.saturating_mul(LOOK_AHEAD_L2_MULTIPLE)
            .clamp(LOOK_AHEAD_RANGE.0, LOOK_AHEAD_RANGE.1)
    })
}

/// The per-core unified level-2 cache of CPU 0, in bytes, where the system says.
pub fn l2_bytes() -> Option<usize> {
    (0..8).find_map(|k| {
        let dir = format!("/sys/devices/system/cpu/cpu0/cache/index{k}");
        let read = |f: &str| std::fs::read_to_string(format!("{dir}/{f}")).ok();
        let level = read("level")?;
        let kind = read("type")?;
        (level.trim() == "2" && kind.trim() != "Instruction")
            .then(|| read("size").and_then(|s| parse_size(&s)))
            .flatten()
    })
}

/// A sysfs cache size: `2048K`, `32M`, `1G` or plain bytes.
fn parse_size(text: &str) -> Option<usize> {
    let t = text.trim();
    let (digits, unit) = match t.char_indices().find(|(_, c)| !c.is_ascii_digit()) {
        Some((i, _)) => t.split_at(i),
        None => (t, ""),
    };
    let n: usize = digits.parse().ok()?;
    let scale = match unit.trim() {
        "" => 1,
        "K" | "k" => 1 << 10,
        "M" | "m" => 1 << 20,
        "G" | "g" => 1 << 30,
        _ => return None,
    };
    n.checked_mul(scale)
}

#[cfg(test)]
mod tests {
    use super::{parse_size, switch_for, threshold_for, LOOK_AHEAD_FALLBACK};

    #[test]
    fn sysfs_sizes_parse() {
        assert_eq!(parse_size("2048K\n"), Some(2 << 20));
        assert_eq!(parse_size("32M"), Some(32 << 20));
        assert_eq!(parse_size("1G"), Some(1 << 30));
        assert_eq!(parse_size("512"), Some(512));
        assert_eq!(parse_size("12Q"), None);
        assert_eq!(parse_size(""), None);
    }

    /// A 2 MiB L2 gives 64 MiB; small and absurd L2 sizes stay within the bounds; an unknown one
    /// falls back to 64 MiB.
    #[test]
    fn thresholds_follow_the_l2_within_bounds() {
        assert_eq!(threshold_for(Some(2 << 20)), 64 << 20);
        assert_eq!(threshold_for(Some(1 << 20)), 32 << 20);
        assert_eq!(threshold_for(Some(256 << 10)), 16 << 20);
        assert_eq!(threshold_for(Some(1 << 30)), 256 << 20);
        assert_eq!(threshold_for(None), LOOK_AHEAD_FALLBACK);
    }

    /// The small-system switches: off up to twice the L2 (3D N 10 976's 0.7 MB of records on a
    /// 512 KiB L2), on beyond.
    #[test]
    fn small_system_switches_at_twice_the_l2() {
        assert_eq!(switch_for(512 << 10), 1 << 20);
        assert!(10_976 * 64 < switch_for(512 << 10));
        assert!(20_000 * 64 > switch_for(512 << 10));
        assert_eq!(switch_for(2 << 20), 4 << 20);
        assert_eq!(switch_for(usize::MAX), usize::MAX);
    }
}

//! Why a replica stopped colliding before its stop: the message of a `stalled` replica.

use edmd_core::Counters;

use crate::spec::Replica;

/// Why a replica stopped colliding before its stop, from the counters at the start (`from`) and the
/// end (`to`) of the window in which fewer than one event in [`super::simulate::STALL_EVENTS_PER_COLLISION`] was a
/// pair collision.
pub(super) fn stall_reason(r: &Replica, from: &Counters, to: &Counters, tau: f64) -> String {
    let events = to.events - from.events;
    let pairs = to.pair_collisions - from.pair_collisions;
    let walls = to.wall_collisions - from.wall_collisions;
    let head =
        format!("stalled at tau = {tau:.4}: {pairs} pair collisions in the last {events} events");
    if 2 * walls > events {
        let mut losses = Vec::new();
        if r.wall_eps < 1.0 {
            losses.push(format!("inelastic walls (wall_eps = {})", r.wall_eps));
        }
        if r.floor_temperature > 0.0 {
            losses.push(format!("a floor at T = {:e}", r.floor_temperature));
        }
        let cause = if losses.is_empty() {
            String::new()
        } else {
            format!("; energy lost to {}", losses.join(" and "))
        };
        let gravity = if r.gravity > 0.0 {
            "; the grains bounce ever lower on the floor"
        } else {
            ""
        };
        format!("{head}, {walls} of them wall collisions: a wall-collision cascade{cause}{gravity}")
    } else {
        format!(
            "{head}, {} of them cell crossings: collisions ceased (the gas streams in lanes)",
            to.crossings - from.crossings
        )
    }
}

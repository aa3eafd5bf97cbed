//! Regression: a pair in contact whose approach speed was pure round-off collided at the same
//! instant forever. In a strongly inelastic channel (ε = 0.3, φ = 0.3, N = 2000) the clock froze after
//! about 9000 collisions: the impulse was too small to change the velocities, the pair was predicted
//! to collide again at `t = now`, and so on. Prediction and collision now share one approach test
//! (`predict::approaching`) that ignores approach speeds below round-off.

use edmd_core::{Channel, ConstantRestitution, InitParams, Stop};

#[test]
fn the_clock_keeps_moving_in_a_collapsing_channel() {
    let p = InitParams::<2>::with_packing(2000, 0.3).unwrap();
    let mut sim = p
        .build::<Channel, _>(edmd_core::Rule::new(ConstantRestitution::new(0.3).unwrap()))
        .unwrap();
    let mut last = sim.time();
    for chunk in 0..6 {
        sim.run(Stop::Events(50_000));
        assert!(
            sim.time() > last,
            "clock stuck at t = {last} in chunk {chunk}"
        );
        last = sim.time();
    }
}

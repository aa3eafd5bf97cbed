//! [`Engine`]: what a driver of a run asks of a simulation, as an object-safe trait.
//!
//! The event loop is generic over the scene, the rule's grain kind and the calendar, and is
//! compiled once per combination. Everything around it (set-up, sampling on a schedule,
//! classification, output) needs only this small interface, so it is written once against
//! `&mut dyn Engine<D>` and compiled once per dimension: a facade over a small generic core.

use super::{Collapse, Counters, RunEnd, Simulation, Stop};
use crate::calendar::Calendar;
use crate::observe::Observables;
use crate::{Boundary, CollisionRule, Vector};

/// A running simulation in `D` dimensions, whatever its scene, rule and calendar.
pub trait Engine<const D: usize>: Send {
    /// Runs until `stop` (see [`Simulation::run`]).
    fn run(&mut self, stop: Stop) -> RunEnd;
    /// All bulk observables now.
    fn observe(&self) -> Observables<D>;
    /// Event counters.
    fn counters(&self) -> &Counters;
    /// Physical time.
    fn time(&self) -> f64;
    /// τ = C/N.
    fn tau(&self) -> f64;
    /// Particles.
    fn len(&self) -> usize;
    /// True without particles (a simulation always has some).
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Granular temperature (physical units).
    fn temperature(&self) -> f64;
    /// ln T, finite however deep the cooling.
    fn ln_temperature(&self) -> f64;
    /// Box sides.
    fn box_len(&self) -> &Vector<D>;
    /// Masses, in the original particle order.
    fn masses(&self) -> Vec<f64>;
    /// Radii, in the original particle order.
    fn radii(&self) -> Vec<f64>;
    /// Replaces the rule's law and remedy between runs (see [`Simulation::set_law`]).
    fn set_law(&mut self, law: crate::Law, remedy: crate::Remedy) -> Result<(), crate::EdmdError>;
    /// Positions now, in the original particle order, wrapped into the box.
    fn positions(&self) -> Vec<Vector<D>>;
    /// Physical velocities now, in the original particle order.
    fn velocities(&self) -> Vec<Vector<D>>;
    /// Velocities in the simulation's own units (ratios and directions only).
    fn velocities_internal(&self) -> Vec<Vector<D>>;
    /// True for rough grains (they carry spin).
    fn rough(&self) -> bool;
    /// Angular velocities, in the original particle order (zero for smooth grains).
    fn spins(&self) -> Vec<[f64; 3]>;
    /// Rotational kinetic energy (0 for smooth grains).
    fn rotational_energy(&self) -> f64;
    /// Whether axis `a` has walls.
    fn has_walls(&self, a: usize) -> bool;
    /// The inelastic collapse detected so far.
    fn collapse(&self) -> Option<Collapse>;
    /// The displacement along x of the images above the box, in [0, L_x) (0 where not sheared).
    fn shear_offset(&self) -> f64;
    /// Peculiar velocities V = v − a (y − L_y/2) e_x of a sheared scene (the physical velocities
    /// elsewhere), in the original particle order.
    fn peculiar_velocities(&self) -> Vec<Vector<D>>;
    /// Zeroes the sheared scene's interval sums (the collisional stress and the dissipated energy).
    fn restart_shear_sums(&mut self);
    /// The complete dynamic state as bytes (see [`Simulation::save_state`]).
    fn save_state(&self) -> Vec<u8>;
    /// Goes on from a state [`Engine::save_state`] wrote (see [`Simulation::load_state`]).
    fn load_state(&mut self, bytes: &[u8]) -> Result<(), crate::EdmdError>;
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar + Send> Engine<D>
    for Simulation<D, B, R, C>
{
    fn run(&mut self, stop: Stop) -> RunEnd {
        Simulation::run(self, stop)
    }
    fn observe(&self) -> Observables<D> {
        Simulation::observe(self)
    }
    fn counters(&self) -> &Counters {
        Simulation::counters(self)
    }
    fn time(&self) -> f64 {
        Simulation::time(self)
    }
    fn tau(&self) -> f64 {
        Simulation::tau(self)
    }
    fn len(&self) -> usize {
        Simulation::len(self)
    }
    fn temperature(&self) -> f64 {
        Simulation::temperature(self)
    }
    fn ln_temperature(&self) -> f64 {
        Simulation::ln_temperature(self)
    }
    fn box_len(&self) -> &Vector<D> {
        Simulation::box_len(self)
    }
    fn masses(&self) -> Vec<f64> {
        Simulation::masses(self)
    }
    fn radii(&self) -> Vec<f64> {
        Simulation::radii(self)
    }
    fn set_law(&mut self, law: crate::Law, remedy: crate::Remedy) -> Result<(), crate::EdmdError> {
        Simulation::set_law(self, law, remedy)
    }
    fn positions(&self) -> Vec<Vector<D>> {
        Simulation::positions(self)
    }
    fn velocities(&self) -> Vec<Vector<D>> {
        Simulation::velocities(self)
    }
    fn velocities_internal(&self) -> Vec<Vector<D>> {
        Simulation::velocities_internal(self)
    }
    fn rough(&self) -> bool {
        R::ROUGH
    }
    fn spins(&self) -> Vec<[f64; 3]> {
        Simulation::spins(self)
    }
    fn rotational_energy(&self) -> f64 {
        Simulation::rotational_energy(self)
    }
    fn has_walls(&self, a: usize) -> bool {
        B::WALL_MASK & (1 << a) != 0
    }
    fn collapse(&self) -> Option<Collapse> {
        Simulation::collapse(self)
    }
    fn shear_offset(&self) -> f64 {
        Simulation::shear_offset(self)
    }
    fn peculiar_velocities(&self) -> Vec<Vector<D>> {
        Simulation::peculiar_velocities(self)
    }
    fn restart_shear_sums(&mut self) {
        Simulation::restart_shear_sums(self)
    }
    fn save_state(&self) -> Vec<u8> {
        Simulation::save_state(self)
    }
    fn load_state(&mut self, bytes: &[u8]) -> Result<(), crate::EdmdError> {
        Simulation::load_state(self, bytes)
    }
}

//! The event loop.
//!
//! Each particle owns one pending event, the earlier of
//! * its best **collision candidate** `(time, partner, partner's collision counter)`, and
//! * its **auxiliary event**: the next cell crossing, or, in the outermost cell of a walled axis, the
//!   wall contact.
//!
//! The calendar holds one entry per particle. A candidate whose partner has collided since it was
//! predicted is stale: its time is still a lower bound, so it is popped in order and the particle is
//! simply predicted again (Smallenburg's single-event scheme; no searching of the queue). After a
//! collision both partners are predicted against their whole 3^D neighbourhood; after a crossing the
//! particle keeps its still-valid candidate and searches only the 3^(D−1) newly adjacent cells.
//!
//! With neighbour lists ([`crate::sim::neighbours`]) the auxiliary event is the exit from the particle's shell
//! (or a wall contact), and a full prediction scans the particle's list instead of its cells.
//!
//! Time is a local clock, rebased to zero every few `N` events together with a re-tuning of the
//! calendar's bucket width; [`Simulation::time`] adds the rebased epochs back.

use std::marker::PhantomData;

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::calendar::{Calendar, Entry, HasEntry, PaulCalendar};
use crate::{Boundary, CollisionRule, EdmdError, Particle, ParticleInit, Vector};

mod checks;
mod collapse;
mod contact;
mod cooling;
mod engine;
mod event;
pub(crate) mod neighbours;
mod params;
mod persist;
mod prefetch;
mod query;
mod run;
mod scene;
mod shear;
mod system;
mod thermostat;
mod upkeep;
mod vibrating_floor;

use collapse::CollapseMonitor;
use neighbours::{neighbour_search, CellGrid, Cells, Lists, NeighbourLists, Search, NONE};
use shear::Shear;
use system::SystemEvent;
use thermostat::Thermostat;
use vibrating_floor::VibratingFloor;

pub use collapse::{Collapse, CollapseReason};
pub use engine::Engine;
pub use event::EventKind;
pub use params::SimParams;
pub use persist::STATE_VERSION;
pub use run::{RunEnd, Stop};
pub(crate) use scene::{check_scene, lists_possible};

/// A particle's next event other than a collision, as the slot stores it: decoded once, where it
/// is predicted, and matched once, where it is handled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub(crate) enum Aux {
    /// Into the neighbouring cell along `axis`, upwards if `up` (cell mode).
    Crossing {
        /// The axis.
        axis: u8,
        /// Towards the upper face.
        up: bool,
    },
    /// Contact with the wall normal to `axis` (the upper one if `up`).
    Wall {
        /// The axis.
        axis: u8,
        /// The upper wall.
        up: bool,
    },
    /// Out of the particle's shell (neighbour-list mode).
    ShellExit,
    /// An event of the whole system, in a slot after the particles' (`sim/system.rs`).
    System(SystemEvent),
}

/// Per-particle pending event.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub(crate) struct EventSlot {
    pub coll_t: f64,
    pub aux_t: f64,
    pub partner: u32,
    pub partner_count: u32,
}

impl EventSlot {
    const EMPTY: EventSlot = EventSlot {
        coll_t: f64::INFINITY,
        aux_t: f64::INFINITY,
        partner: NONE,
        partner_count: 0,
    };
}

/// Per-particle bookkeeping kept together so that one cache line serves an event.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub(crate) struct Meta<const D: usize> {
    pub ev: EventSlot,
    pub mass: f64,
    /// Original index of the particle (slots are renumbered in cell order for locality).
    pub id: u32,
    /// Cell coordinates, 16 bits per axis (the grid has at most [`crate::sim::neighbours::MAX_PER_AXIS`]
    /// cells per axis), so that a 3D record, too, fills one cache line: [`Meta::cell`].
    #[serde(with = "persist::array")]
    pub cell: [u16; D],
    /// The event at `ev.aux_t` (here rather than in `ev`, so that it shares the padding after
    /// `cell`).
    pub aux: Aux,
    /// The particle's place in the calendar: the record doubles as the calendar's event node, so
    /// that popping, filing and removing the particle's event touch the line its event reads
    /// anyway, instead of a line of a separate array.
    pub entry: Entry,
}

impl<const D: usize> HasEntry for Meta<D> {
    #[inline(always)]
    fn entry(&self) -> &Entry {
        &self.entry
    }
    #[inline(always)]
    fn entry_mut(&mut self) -> &mut Entry {
        &mut self.entry
    }
}

impl<const D: usize> Meta<D> {
    /// The cell coordinates.
    #[inline(always)]
    pub fn cell(&self) -> [u32; D] {
        self.cell.map(u32::from)
    }

    /// Sets the cell coordinates (each below [`crate::sim::neighbours::MAX_PER_AXIS`]).
    #[inline(always)]
    pub fn set_cell(&mut self, c: [u32; D]) {
        debug_assert!(c
            .iter()
            .all(|&x| (x as usize) < crate::sim::neighbours::MAX_PER_AXIS));
        self.cell = c.map(|x| x as u16);
    }
}

// A 2D or 3D record in exactly one cache line (the arrays of 4 KiB or more start on a line:
// `LineAligned`).
const _: () = assert!(std::mem::size_of::<Meta<2>>() == 64);
const _: () = assert!(std::mem::size_of::<Meta<3>>() == 64);

/// Running counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Counters {
    /// Events processed (all kinds).
    pub events: u64,
    /// Pair collisions (`C`).
    pub pair_collisions: u64,
    /// Particle–wall collisions.
    pub wall_collisions: u64,
    /// Cell crossings (with neighbour lists: shell exits, each renewing the particle's list).
    pub crossings: u64,
    /// Stale pops: collision candidates whose partner had collided since; the particle is
    /// predicted again and nothing moves.
    pub stale: u64,
    /// System events (`sim/system.rs`): the shear shift of a sheared box.
    pub system_events: u64,
    /// Calendar re-tunings by the event count (`sim/upkeep.rs`): the clock rebased, every entry
    /// filed again, no prediction renewed.
    pub maintenances: u64,
    /// Full re-predictions of every particle ([`Simulation::restart_events`]): after a deep-cooling
    /// rescale, a drift removal, or a caller's change of the velocities.
    pub restarts: u64,
    /// Deep-cooling rescales of the velocity scale (each followed by a restart).
    pub rescales: u64,
    /// Σ over pair collisions of `r_ij · Δp_i` (the collision virial), in the simulation's units.
    pub virial: f64,
    /// Sheared scenes: Σ over pair collisions of `(Δp_i)_a (r_ij)_b` (the whole impulse: normal,
    /// tangential of rough grains, a remedy's rotation), row a, column b, the first D × D entries
    /// used; the collisional pressure tensor times the volume and the time (0 elsewhere): the flux
    /// of a-momentum along b, asymmetric where impulses leave the line of centres. Entry [0][1] is
    /// the collisional shear stress whose product with −a is the shear's work. Summed since the start or the last
    /// [`Simulation::restart_shear_sums`].
    pub virial_tensor: [[f64; 3]; 3],
    /// Sheared scenes: the kinetic energy (translational and rotational) the collisions removed
    /// (0 elsewhere), since the start or the last [`Simulation::restart_shear_sums`]: a sum over
    /// one sample interval keeps the interval's own precision, where a running total would round
    /// away the small losses of a cold gas against the large ones of its start.
    pub dissipated: f64,
    /// A vibrating floor's work: the kinetic energy its contacts gave the grains (negative where
    /// they took more than they gave), since the start, in the simulation's units.
    pub floor_work: f64,
}

/// An event-driven simulation of hard disks (`D = 2`) or spheres (`D = 3`) in a box with boundary
/// `B`, collision rule `R` and calendar `C`.
#[derive(Debug, Clone)]
pub struct Simulation<const D: usize, B: Boundary, R: CollisionRule, C: Calendar = PaulCalendar> {
    pub(crate) particles: Vec<Particle<D>>,
    /// Per-particle bookkeeping, touched when the particle itself has an event.
    pub(crate) meta: Vec<Meta<D>>,
    /// Per-particle memory of the collision rule (zero-sized, so free, for memoryless rules).
    pub(crate) rule_state: Vec<R::State>,
    pub(crate) grid: CellGrid<D>,
    /// Neighbour lists, when they replace cell crossings ([`SimParams::neighbour_skin`]).
    pub(crate) nl: Option<NeighbourLists<D>>,
    pub(crate) calendar: C,
    pub(crate) rule: R,
    pub(crate) box_len: Vector<D>,
    pub(crate) half_box: Vector<D>,
    pub(crate) now: f64,
    /// Simulated time of the local clock's origin, in the current velocity units.
    pub(crate) epoch: f64,
    /// Deep cooling: simulated velocities are the physical ones times `exp(ln_scale)`.
    pub(crate) ln_scale: f64,
    /// `exp(−ln_scale)`: converts simulated speeds to physical ones.
    pub(crate) inv_scale: f64,
    /// `exp(ln_scale)`: converts simulated times to physical ones (∞ beyond 1e308).
    scale: f64,
    /// Simulated temperature to which the velocities are rescaled.
    t_ref: f64,
    pub(crate) counters: Counters,
    params: SimParams,
    /// Random stream of the rules that need one (random rotation), seeded from `SimParams::seed`.
    rng: Xoshiro256PlusPlus,
    monitor: CollapseMonitor,
    next_maintenance: u64,
    last_maintenance: (u64, f64),
    /// The large-system look-ahead (`sim/prefetch.rs`): on when the state is far larger than a cache.
    look_ahead: prefetch::LookAhead,
    /// Sheared scenes: the sliding images ([`crate::LeesEdwards`]).
    pub(crate) shear: Shear,
    /// The white-noise thermostat's kicks (none by default).
    pub(crate) thermostat: Thermostat,
    /// Gravity scenes: the floor's vibration (still by default).
    pub(crate) vibration: VibratingFloor,
    _boundary: PhantomData<B>,
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Builds a simulation from explicit particles. Errors if a parameter is invalid, a particle lies
    /// outside the box (or inside a wall), or two particles overlap.
    pub fn new(
        box_len: Vector<D>,
        particles: Vec<ParticleInit<D>>,
        rule: R,
        params: SimParams,
    ) -> Result<Self, EdmdError> {
        let n = particles.len();
        scene::check_scene::<D, B>(n, &box_len, &params)?;
        let max_d = checks::particles::<D, B>(&particles, &box_len)?;
        let (grid, nl) = neighbour_search::<D, B>(&box_len, &particles, &params, max_d)?;
        let meta: Vec<Meta<D>> = particles
            .iter()
            .enumerate()
            .map(|(i, p)| Meta {
                ev: EventSlot::EMPTY,
                mass: p.mass,
                id: i as u32,
                cell: [0; D],
                aux: Aux::Crossing { axis: 0, up: false },
                entry: Entry::EMPTY,
            })
            .chain(SystemEvent::ALL.map(SystemEvent::record))
            .collect();
        let vibration = VibratingFloor::new(
            params.floor_amplitude,
            params.floor_omega,
            0.5 * max_d,
            grid.side[D - 1],
        );
        let mut sim = Simulation {
            // Same size and alignment: the conversion reuses the allocation.
            particles: particles
                .into_iter()
                .map(|p| Particle {
                    r0: p.pos,
                    vel: p.vel,
                    radius: p.radius,
                    next_in_cell: NONE,
                    counter: 0,
                })
                .collect(),
            meta,
            rule_state: vec![R::State::default(); n],
            grid,
            nl,
            calendar: C::with_capacity(n + SystemEvent::ALL.len()),
            rule,
            box_len,
            half_box: box_len / 2.0,
            now: 0.0,
            epoch: 0.0,
            ln_scale: 0.0,
            inv_scale: 1.0,
            scale: 1.0,
            t_ref: 0.0,
            counters: Counters::default(),
            rng: Xoshiro256PlusPlus::seed_from_u64(params.seed),
            params,
            monitor: CollapseMonitor::default(),
            next_maintenance: 0,
            last_maintenance: (0, 0.0),
            look_ahead: prefetch::LookAhead::default(),
            shear: Shear::default(),
            thermostat: Thermostat::new(
                params.white_noise,
                params.kick_interval,
                params.kick_conserves_momentum,
            ),
            vibration,
            _boundary: PhantomData,
        };
        sim.shear = Shear::new::<B>(sim.params.shear_rate, box_len[1], sim.grid.side[0]);
        for i in 0..n {
            let c = sim.grid.coords_of(&sim.particles[i].r0);
            sim.meta[i].set_cell(c);
            let idx = sim.grid.index(&c);
            sim.file_in_cell(i as u32, idx);
        }
        if let Some((i, j, overlap)) = sim.deepest_overlap().filter(|o| o.2 > 1e-12) {
            return Err(EdmdError::Overlap { i, j, overlap });
        }
        sim.build_lists();
        sim.restart_events();
        // Beyond the caches the look-ahead's hints hide memory latency; below, they cost more than
        // they hide (`crate::caches`, docs/benchmarks.md).
        sim.set_look_ahead(sim.heap_bytes() > crate::caches::look_ahead_threshold());
        Ok(sim)
    }

    /// Replaces the collision rule, keeping the state (e.g. after an elastic melt).
    pub fn with_rule<R2: CollisionRule>(self, rule: R2) -> Simulation<D, B, R2, C> {
        Simulation {
            particles: self.particles,
            rule_state: vec![R2::State::default(); self.rule_state.len()],
            meta: self.meta,
            grid: self.grid,
            nl: self.nl,
            calendar: self.calendar,
            rule,
            box_len: self.box_len,
            half_box: self.half_box,
            now: self.now,
            epoch: self.epoch,
            ln_scale: self.ln_scale,
            inv_scale: self.inv_scale,
            scale: self.scale,
            t_ref: self.t_ref,
            counters: self.counters,
            params: self.params,
            rng: self.rng,
            monitor: self.monitor,
            next_maintenance: self.next_maintenance,
            last_maintenance: self.last_maintenance,
            look_ahead: self.look_ahead,
            shear: self.shear,
            thermostat: self.thermostat,
            vibration: self.vibration,
            _boundary: PhantomData,
        }
    }
}

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
//! With neighbour lists ([`crate::nlist`]) the auxiliary event is the exit from the particle's shell
//! (or a wall contact), and a full prediction scans the particle's list instead of its cells.
//!
//! Time is a local clock, rebased to zero every few `N` events together with a re-tuning of the
//! calendar's bucket width; [`Simulation::time`] adds the rebased epochs back.

use std::marker::PhantomData;

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::calendar::{Calendar, PaulCalendar};
use crate::cells::{CellGrid, NONE};
use crate::nlist::NeighbourLists;
use crate::predict::{approaching, fall_time, pair_time, reach_time, rise_time};
use crate::{Boundary, CollisionRule, EdmdError, Particle, ParticleInit, Vector};

const WALL: u8 = 0x80;
/// Aux code of a shell exit (neighbour-list mode).
const SHELL: u8 = 0x40;
const EVENTS_PER_BUCKET: f64 = 2.0;

/// Per-particle pending event.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EventSlot {
    pub coll_t: f64,
    pub aux_t: f64,
    pub partner: u32,
    pub partner_count: u32,
    /// `axis << 1 | positive`, plus [`WALL`] for a wall contact.
    pub aux: u8,
}

impl EventSlot {
    const EMPTY: EventSlot = EventSlot {
        coll_t: f64::INFINITY,
        aux_t: f64::INFINITY,
        partner: NONE,
        partner_count: 0,
        aux: 0,
    };
}

/// Per-particle bookkeeping kept together so that one cache line serves an event.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Meta<const D: usize> {
    pub ev: EventSlot,
    pub mass: f64,
    /// Collisions suffered; a partner's stored count that differs marks a stale candidate.
    pub counter: u32,
    /// Original index of the particle (slots are renumbered in cell order for locality).
    pub id: u32,
    pub cell: [u32; D],
}

/// Inelastic collapse: infinitely many collisions in a finite time (PHYSICS.md §6.4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Collapse {
    /// Physical time when it was detected.
    pub time: f64,
    /// τ = C/N when it was detected.
    pub tau: f64,
    /// Which criterion fired.
    pub reason: CollapseReason,
}

/// The collapse criteria of PHYSICS.md §6.4.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CollapseReason {
    /// The clock advanced by less than 1e-10 of its value over 10 N pair collisions.
    ClockStalled,
    /// The same pair collided more than 100 times with no other collision in between.
    RepeatedPair,
}

/// State of the collapse monitor.
#[derive(Debug, Clone, Copy)]
struct CollapseMonitor {
    pair: (u32, u32),
    repeats: u32,
    next_check: u64,
    check_time: f64,
    found: Option<Collapse>,
}

impl Default for CollapseMonitor {
    fn default() -> Self {
        CollapseMonitor {
            pair: (NONE, NONE),
            repeats: 0,
            next_check: 0,
            check_time: 0.0,
            found: None,
        }
    }
}

/// What an event was, with original particle indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// A pair collision between two particles.
    Collision(u32, u32),
    /// A collision candidate whose partner had changed; the particle was predicted again.
    Stale(u32),
    /// A particle moved to a neighbouring cell.
    CellCrossing(u32),
    /// A particle hit a wall.
    Wall(u32),
}

/// Running counters.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Counters {
    /// Events processed (all kinds).
    pub events: u64,
    /// Pair collisions (`C`).
    pub pair_collisions: u64,
    /// Particle–wall collisions.
    pub wall_collisions: u64,
    /// Cell crossings (with neighbour lists: shell exits, each renewing the particle's list).
    pub crossings: u64,
    /// Σ over pair collisions of `r_ij · Δp_i` (the collision virial), in the simulation's units.
    pub virial: f64,
}

/// Settings of the event loop. Every field has a default that suits typical runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimParams {
    /// Target cell side in units of the largest diameter (≥ 1; default 1). Larger cells mean fewer
    /// crossings and more neighbours; dilute gases gain from values above 1.
    pub cell_factor: f64,
    /// Events between rebasing the clock and re-tuning the calendar, per particle (default 8).
    pub rebase_events_per_particle: f64,
    /// Normal restitution of particle–wall collisions, in [0, 1] (default 1: elastic walls).
    pub wall_epsilon: f64,
    /// Deep cooling: when the simulated temperature falls below this fraction of its starting value
    /// (checked every rebase), all velocities are scaled back up and the factor is tracked
    /// (default 1e-4; 0 disables). Reported quantities stay in physical units.
    pub rescale_below: f64,
    /// Seed of the random stream used by random collision rules (default 0).
    pub seed: u64,
    /// Gravitational acceleration towards the floor of the last axis, for gravity scenes
    /// ([`crate::GravityAxes`]); must be 0 elsewhere (default 0).
    pub gravity: f64,
    /// Wall contacts slower than this normal speed are elastic (default 0: off). Under gravity it keeps
    /// grains resting on the floor from bouncing ever faster (a collapse against the wall): their
    /// bounces keep a height of at least ~ε_w²δ²/(2g).
    pub wall_threshold: f64,
    /// Neighbour lists instead of cell crossings (0, the default, for cells): the skin `δ` in units
    /// of the largest diameter (see [`crate::nlist`]). Pays in dense packings, where particles need
    /// many collisions to move `δ/2`; ignored under gravity and where the box holds fewer than three
    /// cells of side `σ + δ`.
    pub neighbour_skin: f64,
}

impl Default for SimParams {
    fn default() -> Self {
        SimParams {
            cell_factor: 1.0,
            rebase_events_per_particle: 8.0,
            wall_epsilon: 1.0,
            rescale_below: 1e-4,
            seed: 0,
            gravity: 0.0,
            wall_threshold: 0.0,
            neighbour_skin: 0.0,
        }
    }
}

impl SimParams {
    /// Checks every field against its domain; the error names the field and the value.
    pub fn validate(&self) -> Result<(), EdmdError> {
        let checks: [(&'static str, f64, bool, &str); 7] = [
            (
                "cell_factor",
                self.cell_factor,
                self.cell_factor >= 1.0 && self.cell_factor.is_finite(),
                "must be ≥ 1",
            ),
            (
                "wall_epsilon",
                self.wall_epsilon,
                (0.0..=1.0).contains(&self.wall_epsilon),
                "restitution must lie in [0, 1]",
            ),
            (
                "gravity",
                self.gravity,
                self.gravity >= 0.0 && self.gravity.is_finite(),
                "must be ≥ 0 and finite",
            ),
            (
                "wall_threshold",
                self.wall_threshold,
                self.wall_threshold >= 0.0 && self.wall_threshold.is_finite(),
                "must be ≥ 0 and finite",
            ),
            (
                "rescale_below",
                self.rescale_below,
                (0.0..1.0).contains(&self.rescale_below),
                "must lie in [0, 1)",
            ),
            (
                "neighbour_skin",
                self.neighbour_skin,
                self.neighbour_skin >= 0.0 && self.neighbour_skin.is_finite(),
                "must be ≥ 0 and finite",
            ),
            (
                "rebase_events_per_particle",
                self.rebase_events_per_particle,
                self.rebase_events_per_particle > 0.0,
                "must be > 0",
            ),
        ];
        match checks.into_iter().find(|c| !c.2) {
            Some((field, value, _, reason)) => Err(EdmdError::invalid(field, value, reason)),
            None => Ok(()),
        }
    }

    /// A cell factor that balances crossings against neighbour checks for a packing fraction `phi`.
    pub fn for_density<const D: usize>(phi: f64) -> Self {
        // Measured (edmd-core/examples/profile): cells of one diameter are fastest at φ ≥ 0.3; dilute
        // gases keep about 0.4 particles per cell, so crossings do not dominate.
        let per_cell_volume = if D == 2 {
            std::f64::consts::PI / 4.0
        } else {
            std::f64::consts::PI / 6.0
        };
        let side = (0.4 * per_cell_volume / phi.max(1e-12)).powf(1.0 / D as f64);
        // Neighbour lists pay in dense 3D packings (measured at N = 10^4 with examples/profile, skin
        // 0.45 against cells: φ = 0.35 1.00×, 0.4 1.12×, 0.45 1.4×, 0.5 1.65×; skins 0.35-0.5 within
        // 3 % of each other). In 2D, cells win up to φ = 0.5 and lists gain at most ~10 % at 0.7-0.75.
        let neighbour_skin = if D == 3 && phi >= 0.38 { 0.45 } else { 0.0 };
        SimParams {
            cell_factor: side.max(1.0),
            neighbour_skin,
            ..Default::default()
        }
    }
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
        if n == 0 {
            return Err(EdmdError::invalid("N", 0, "need at least one particle"));
        }
        if n >= NONE as usize {
            return Err(EdmdError::invalid("N", n, "at most 2^32 − 2 particles"));
        }
        for a in 0..D {
            if !(box_len[a] > 0.0 && box_len[a].is_finite()) {
                return Err(EdmdError::invalid(
                    crate::error::AXIS_NAMES[a],
                    box_len[a],
                    "box side must be positive and finite",
                ));
            }
        }
        params.validate()?;
        if params.gravity != 0.0 && !B::GRAVITY {
            return Err(EdmdError::invalid(
                "gravity",
                params.gravity,
                "this scene has no gravity: use a GravityAxes scene",
            ));
        }
        if B::GRAVITY && !B::is_wall(D - 1) {
            return Err(EdmdError::invalid(
                "scene",
                B::NAME,
                "gravity needs walls (a floor) on the last axis",
            ));
        }
        let mut max_d: f64 = 0.0;
        for (i, p) in particles.iter().enumerate() {
            if !(p.radius > 0.0 && p.radius.is_finite()) {
                return Err(EdmdError::invalid(
                    "radius",
                    p.radius,
                    format!("particle {i}: radius must be positive"),
                ));
            }
            if !(p.mass > 0.0 && p.mass.is_finite()) {
                return Err(EdmdError::invalid(
                    "mass",
                    p.mass,
                    format!("particle {i}: mass must be positive"),
                ));
            }
            for a in 0..D {
                let (lo, hi) = if B::is_wall(a) {
                    (p.radius, box_len[a] - p.radius)
                } else {
                    (0.0, box_len[a])
                };
                let x = p.pos[a];
                if !(x >= lo && x <= hi) || (!B::is_wall(a) && x >= hi) {
                    return Err(EdmdError::invalid(
                        "position",
                        x,
                        format!("particle {i}, axis {a}: outside [{lo}, {hi}]"),
                    ));
                }
                if !p.vel[a].is_finite() {
                    return Err(EdmdError::invalid(
                        "velocity",
                        p.vel[a],
                        format!("particle {i}: not finite"),
                    ));
                }
            }
            max_d = max_d.max(2.0 * p.radius);
        }
        let skin = params.neighbour_skin * max_d;
        let list_grid = (skin > 0.0 && !B::GRAVITY)
            .then(|| CellGrid::new(&box_len, max_d + skin, max_d * params.cell_factor, n).ok())
            .flatten();
        let (grid, nl) = match list_grid {
            Some(g) => (g, Some(NeighbourLists::new(n, skin, max_d))),
            None => (
                CellGrid::new(&box_len, max_d, max_d * params.cell_factor, n)?,
                None,
            ),
        };
        let meta = particles
            .iter()
            .enumerate()
            .map(|(i, p)| Meta {
                ev: EventSlot::EMPTY,
                mass: p.mass,
                counter: 0,
                id: i as u32,
                cell: [0; D],
            })
            .collect();
        let mut sim = Simulation {
            // Same size and alignment: the conversion reuses the allocation.
            particles: particles
                .into_iter()
                .map(|p| Particle {
                    r0: p.pos,
                    vel: p.vel,
                    radius: p.radius,
                    next_in_cell: NONE,
                })
                .collect(),
            meta,
            rule_state: vec![R::State::default(); n],
            grid,
            nl,
            calendar: C::with_capacity(n),
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
            _boundary: PhantomData,
        };
        for i in 0..n {
            let c = sim.grid.coords_of(&sim.particles[i].r0);
            sim.meta[i].cell = c;
            let idx = sim.grid.index(&c);
            sim.grid.insert(&mut sim.particles, i as u32, idx);
        }
        if let Some((i, j, overlap)) = sim.deepest_overlap().filter(|o| o.2 > 1e-12) {
            return Err(EdmdError::Overlap { i, j, overlap });
        }
        sim.build_lists();
        sim.restart_events();
        Ok(sim)
    }

    /// Replaces the collision rule, keeping the state (e.g. after an elastic melt).
    pub fn with_rule<R2: CollisionRule>(self, rule: R2) -> Simulation<D, B, R2, C> {
        Simulation {
            particles: self.particles,
            rule_state: vec![R2::State::default(); self.meta.len()],
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
            _boundary: PhantomData,
        }
    }

    /// Predicts every particle's event from scratch and sizes the calendar's buckets from them.
    pub fn restart_events(&mut self) {
        let n = self.particles.len();
        self.rebase_clock();
        self.sort_by_cell();
        let mut sum = 0.0;
        let mut count = 0usize;
        for i in 0..n {
            let (coll_t, partner) = self.search(i, None, (f64::INFINITY, NONE));
            let t = self.set_event(i, coll_t, partner);
            if t.is_finite() {
                sum += t - self.now;
                count += 1;
            }
        }
        // Each event renews about 1.5 predictions: the mean time between events is ≈ ⟨Δt⟩ / (0.7 N).
        let width = if count > 0 && sum > 0.0 {
            EVENTS_PER_BUCKET * sum / count as f64 / (0.7 * n as f64)
        } else {
            1.0
        };
        self.reschedule_all(width);
        self.next_maintenance = self.counters.events + n.max(64) as u64;
        self.last_maintenance = (self.counters.events, self.now);
    }

    fn reschedule_all(&mut self, width: f64) {
        self.calendar.reset(self.now, width);
        for i in 0..self.particles.len() {
            let e = &self.meta[i].ev;
            self.calendar.schedule(i as u32, e.coll_t.min(e.aux_t));
        }
    }

    /// Renumbers the slots in cell order so that neighbours sit close in memory. The event slots'
    /// partners are renumbered; the calendar must be rebuilt by the caller.
    fn sort_by_cell(&mut self) {
        let n = self.particles.len();
        let cells: Vec<u32> = self
            .meta
            .iter()
            .map(|m| self.grid.index(&m.cell) as u32)
            .collect();
        if cells.windows(2).all(|w| w[0] <= w[1]) {
            return;
        }
        // Counting sort: perm[new] = old.
        let mut start = vec![0u32; self.grid.len() + 1];
        for &c in &cells {
            start[c as usize + 1] += 1;
        }
        for k in 1..start.len() {
            start[k] += start[k - 1];
        }
        let mut perm = vec![0u32; n];
        for (old, &c) in cells.iter().enumerate() {
            let slot = &mut start[c as usize];
            perm[*slot as usize] = old as u32;
            *slot += 1;
        }
        let mut inv = vec![0u32; n];
        for (new, &old) in perm.iter().enumerate() {
            inv[old as usize] = new as u32;
        }
        // In place, following cycles (no second copy of the big arrays): slot `new` takes `perm[new]`.
        fn permute<T: Copy>(v: &mut [T], perm: &[u32], done: &mut [bool]) {
            done.fill(false);
            for start in 0..v.len() {
                if done[start] {
                    continue;
                }
                let first = v[start];
                let mut cur = start;
                loop {
                    done[cur] = true;
                    let src = perm[cur] as usize;
                    if src == start {
                        v[cur] = first;
                        break;
                    }
                    v[cur] = v[src];
                    cur = src;
                }
            }
        }
        let mut done = vec![false; n];
        permute(&mut self.particles, &perm, &mut done);
        permute(&mut self.meta, &perm, &mut done);
        if std::mem::size_of::<R::State>() > 0 {
            permute(&mut self.rule_state, &perm, &mut done);
        }
        for m in &mut self.meta {
            if m.ev.partner != NONE {
                m.ev.partner = inv[m.ev.partner as usize];
            }
        }
        if let Some(nl) = &mut self.nl {
            nl.permute(&perm, &inv);
        }
        self.grid.clear();
        for s in (0..n).rev() {
            let idx = self.grid.index(&self.meta[s].cell);
            self.grid.insert(&mut self.particles, s as u32, idx);
        }
    }

    /// Moves the origin of the local clock to now: trajectories and pending event times are shifted,
    /// the epoch absorbs the elapsed time. The caller rebuilds the calendar.
    fn rebase_clock(&mut self) {
        let now = self.now;
        if now == 0.0 {
            return;
        }
        let g = self.params.gravity;
        for p in &mut self.particles {
            p.r0 += p.vel * now;
            if B::GRAVITY {
                p.r0[D - 1] -= 0.5 * g * now * now;
                p.vel[D - 1] -= g * now;
            }
        }
        for m in &mut self.meta {
            m.ev.coll_t -= now;
            m.ev.aux_t -= now;
        }
        self.epoch += now;
        self.now = 0.0;
    }

    /// Processes the next event. Returns `None` when nothing will ever happen again (all at rest).
    #[inline]
    pub fn step(&mut self) -> Option<EventKind> {
        let (i, t) = self.calendar.pop()?;
        if let Some(next) = self.calendar.next_hint() {
            crate::prefetch::prefetch(&self.particles[next as usize]);
            crate::prefetch::prefetch(&self.meta[next as usize]);
        }
        debug_assert!(t >= self.now, "event in the past: {t} < {}", self.now);
        self.now = t;
        self.counters.events += 1;
        let i = i as usize;
        let e = self.meta[i].ev;
        let kind = if e.coll_t <= e.aux_t {
            let j = e.partner as usize;
            if self.meta[j].counter == e.partner_count {
                self.collide(i, j);
                self.predict(i);
                self.predict(j);
                self.watch_collapse(i as u32, j as u32);
                EventKind::Collision(self.meta[i].id, self.meta[j].id)
            } else {
                self.predict(i);
                EventKind::Stale(self.meta[i].id)
            }
        } else if e.aux & WALL != 0 {
            self.wall(i, (e.aux & 0x7f) as usize >> 1);
            self.predict(i);
            self.monitor.pair = (NONE, NONE);
            EventKind::Wall(self.meta[i].id)
        } else if e.aux & SHELL != 0 {
            self.renew_list(i);
            EventKind::CellCrossing(self.meta[i].id)
        } else {
            self.cross(i, (e.aux >> 1) as usize, e.aux & 1 != 0);
            EventKind::CellCrossing(self.meta[i].id)
        };
        if self.counters.events >= self.next_maintenance {
            self.maintenance();
        }
        Some(kind)
    }

    /// The collapse criteria of PHYSICS.md §6.4, after a pair collision of slots `i` and `j`.
    #[inline]
    fn watch_collapse(&mut self, i: u32, j: u32) {
        let pair = (i.min(j), i.max(j));
        let t = self.time();
        let m = &mut self.monitor;
        if pair == m.pair {
            m.repeats += 1;
            if m.repeats > 100 && m.found.is_none() {
                m.found = Some(Collapse {
                    time: t,
                    tau: 0.0,
                    reason: CollapseReason::RepeatedPair,
                });
            }
        } else {
            m.pair = pair;
            m.repeats = 0;
        }
        if self.counters.pair_collisions >= m.next_check {
            if m.next_check > 0 && t - m.check_time < 1e-10 * t.abs() && m.found.is_none() {
                m.found = Some(Collapse {
                    time: t,
                    tau: 0.0,
                    reason: CollapseReason::ClockStalled,
                });
            }
            m.next_check = self.counters.pair_collisions + 10 * self.particles.len() as u64;
            m.check_time = t;
        }
        if let Some(c) = &mut m.found {
            c.tau = self.counters.pair_collisions as f64 / self.particles.len() as f64;
        }
    }

    /// The inelastic collapse detected so far, if any; runs stop with [`RunEnd::Collapsed`].
    pub fn collapse(&self) -> Option<Collapse> {
        self.monitor.found
    }

    /// Full prediction for particle `i` (already advanced to now), then reschedule it.
    #[inline]
    fn predict(&mut self, i: usize) {
        let (coll_t, partner) = self.search(i, None, (f64::INFINITY, NONE));
        self.store(i, coll_t, partner);
    }

    #[inline]
    fn store(&mut self, i: usize, coll_t: f64, partner: u32) {
        let t = self.set_event(i, coll_t, partner);
        self.calendar.schedule(i as u32, t);
    }

    /// Records particle `i`'s collision candidate and its next crossing or wall contact; returns the
    /// earlier of the two.
    #[inline]
    fn set_event(&mut self, i: usize, coll_t: f64, partner: u32) -> f64 {
        let (aux_t, aux) = self.aux_event(i);
        let partner_count = if partner == NONE {
            0
        } else {
            self.meta[partner as usize].counter
        };
        self.meta[i].ev = EventSlot {
            coll_t,
            aux_t,
            partner,
            partner_count,
            aux,
        };
        coll_t.min(aux_t)
    }

    /// Earliest contact of particle `i` (at now) with the members of its neighbour cells; with
    /// `only = Some((axis, dir))`, just the cells at offset `dir` along `axis`.
    #[inline]
    fn search(&self, i: usize, only: Option<(usize, i32)>, mut best: (f64, u32)) -> (f64, u32) {
        if let Some(nl) = &self.nl {
            return self.search_list(nl, i, best);
        }
        let pi = self.particles[i];
        let pos_i = pi.r0 + pi.vel * self.now;
        let ci = self.meta[i].cell;
        if self.grid.is_interior(&ci) {
            // Interior cell (the common case): fixed offsets, no periodic images.
            let center = self.grid.index(&ci) as isize;
            let offsets = match only {
                None => &self.grid.full,
                Some((axis, dir)) => &self.grid.partial[2 * axis + (dir > 0) as usize],
            };
            for &o in offsets {
                best = self.scan_cell((center + o) as usize, i, &pi, &pos_i, best);
            }
            return best;
        }
        // Per axis: the neighbour rows to visit, as linear-index contribution and image shift.
        let mut lin = [[0usize; 3]; D];
        let mut sh = [[0.0f64; 3]; D];
        let mut count = [0usize; D];
        for a in 0..D {
            let n = self.grid.n[a] as i32;
            for off in -1..=1 {
                if matches!(only, Some((axis, dir)) if axis == a && off != dir) {
                    continue;
                }
                let mut x = ci[a] as i32 + off;
                let mut s = 0.0;
                if x < 0 {
                    if B::is_wall(a) {
                        continue;
                    }
                    x += n;
                    s = -self.box_len[a];
                } else if x >= n {
                    if B::is_wall(a) {
                        continue;
                    }
                    x -= n;
                    s = self.box_len[a];
                }
                lin[a][count[a]] = x as usize * self.grid.stride[a];
                sh[a][count[a]] = s;
                count[a] += 1;
            }
            if count[a] == 0 {
                return best;
            }
        }
        let mut digit = [0usize; D];
        loop {
            let mut idx = 0;
            let mut ri = pos_i;
            for a in 0..D {
                idx += lin[a][digit[a]];
                ri[a] -= sh[a][digit[a]];
            }
            best = self.scan_cell(idx, i, &pi, &ri, best);
            let mut a = 0;
            loop {
                digit[a] += 1;
                if digit[a] < count[a] {
                    break;
                }
                digit[a] = 0;
                a += 1;
                if a == D {
                    return best;
                }
            }
        }
    }

    /// Earliest contact of particle `i` (state `pi`, position image `ri`) with the members of cell `idx`.
    #[inline(always)]
    fn scan_cell(
        &self,
        idx: usize,
        i: usize,
        pi: &Particle<D>,
        ri: &Vector<D>,
        mut best: (f64, u32),
    ) -> (f64, u32) {
        let now = self.now;
        let vi2 = pi.vel.norm_squared();
        let mut k = self.grid.first(idx);
        while k != NONE {
            let pk = &self.particles[k as usize];
            let next = pk.next_in_cell;
            if next != NONE {
                crate::prefetch::prefetch(&self.particles[next as usize]);
            }
            let dr = ri - (pk.r0 + pk.vel * now);
            let dv = pi.vel - pk.vel;
            let t = now + pair_time(&dr, &dv, pi.radius + pk.radius, vi2 + pk.vel.norm_squared());
            if t < best.0 && k as usize != i {
                best = (t, k);
            }
            k = next;
        }
        best
    }

    /// Next cell crossing or wall contact of particle `i` (at now).
    #[inline]
    fn aux_event(&self, i: usize) -> (f64, u8) {
        if let Some(nl) = &self.nl {
            return self.aux_event_list(nl, i);
        }
        let p = &self.particles[i];
        let c = &self.meta[i].cell;
        let mut best = (f64::INFINITY, 0u8);
        if B::GRAVITY {
            // The last axis: a parabola, which may turn before the upper face and always falls.
            let a = D - 1;
            let g = self.params.gravity;
            let now = self.now;
            let x = p.r0[a] + p.vel[a] * now - 0.5 * g * now * now;
            let u = p.vel[a] - g * now;
            let top = c[a] as usize + 1 == self.grid.n[a];
            let (up_target, up_code) = if top {
                (self.box_len[a] - p.radius, WALL | (a as u8) << 1 | 1)
            } else {
                ((c[a] + 1) as f64 * self.grid.side[a], (a as u8) << 1 | 1)
            };
            let (down_target, down_code) = if c[a] == 0 {
                (p.radius, WALL | (a as u8) << 1)
            } else {
                (c[a] as f64 * self.grid.side[a], (a as u8) << 1)
            };
            let t_up = rise_time(x, u, g, up_target);
            let t_down = fall_time(x, u, g, down_target);
            best = if t_up < t_down {
                (now + t_up, up_code)
            } else {
                (now + t_down, down_code)
            };
        }
        for a in 0..D {
            if B::GRAVITY && a == D - 1 {
                continue;
            }
            let v = p.vel[a];
            let up = v > 0.0;
            if v == 0.0 {
                continue;
            }
            let edge = if up {
                c[a] as usize + 1 == self.grid.n[a]
            } else {
                c[a] == 0
            };
            let (dt, code) = if B::is_wall(a) && edge {
                let target = if up {
                    self.box_len[a] - p.radius
                } else {
                    p.radius
                };
                (
                    reach_time(p.r0[a] + v * self.now, v, target),
                    WALL | (a as u8) << 1 | up as u8,
                )
            } else {
                let face = (c[a] + up as u32) as f64 * self.grid.side[a];
                (
                    reach_time(p.r0[a] + v * self.now, v, face),
                    (a as u8) << 1 | up as u8,
                )
            };
            let t = self.now + dt;
            if t < best.0 {
                best = (t, code);
            }
        }
        best
    }

    /// Applies the collision rule to the touching pair `(i, j)`.
    #[inline]
    fn collide(&mut self, i: usize, j: usize) {
        let (pi, pj) = (self.particles[i], self.particles[j]);
        let now = self.now;
        let (pos_i, pos_j) = (pi.r0 + pi.vel * now, pj.r0 + pj.vel * now);
        // The image of j nearest to i, and the separation written exactly as `search` writes it, so
        // that the approach test below and the prediction agree to the last bit: a pair found
        // approaching is treated as approaching, and one found receding is never predicted again.
        let ri = self.image_near(&pos_i, &pos_j);
        let dr = ri - (pj.r0 + pj.vel * now);
        let dv = pi.vel - pj.vel;
        let b = dr.dot(&dv);
        if !approaching(
            b,
            dr.norm_squared(),
            pi.vel.norm_squared() + pj.vel.norm_squared(),
        ) {
            // Round-off turned a grazing contact into a separation: nothing to exchange.
            return;
        }
        let dist = dr.norm();
        let normal = dr / dist;
        let gn = b / dist;
        let (mi, mj) = (self.meta[i].mass, self.meta[j].mass);
        let m_eff = mi * mj / (mi + mj);
        let r_eff = pi.radius * pj.radius / (pi.radius + pj.radius);
        let t_phys = self.time();
        let (si, sj) = if i < j {
            let (lo, hi) = self.rule_state.split_at_mut(j);
            (&mut lo[i], &mut hi[0])
        } else {
            let (lo, hi) = self.rule_state.split_at_mut(i);
            (&mut hi[0], &mut lo[j])
        };
        let eps = self
            .rule
            .restitution_at(-gn * self.inv_scale, m_eff, r_eff, t_phys, si, sj);
        let impulse = -(1.0 + eps) * gn * m_eff;
        // New velocities, and the trajectories' origins moved so that positions stay put at `now`.
        let (mut vi, mut vj) = (
            pi.vel + normal * (impulse / mi),
            pj.vel - normal * (impulse / mj),
        );
        if R::ROUGH {
            let (beta, q) = self.rule.roughness();
            let (ri, rj) = (pi.radius, pj.radius);
            let n3 = pad3(&normal);
            let (wi, wj) = (R::spin(si), R::spin(sj));
            let arm = [
                ri * wi[0] + rj * wj[0],
                ri * wi[1] + rj * wj[1],
                ri * wi[2] + rj * wj[2],
            ];
            let spin_part = cross3(&arm, &n3);
            let g3 = pad3(&dv);
            let gc = [
                g3[0] - spin_part[0],
                g3[1] - spin_part[1],
                g3[2] - spin_part[2],
            ];
            let gcn = gc[0] * n3[0] + gc[1] * n3[1] + gc[2] * n3[2];
            let gt = [
                gc[0] - gcn * n3[0],
                gc[1] - gcn * n3[1],
                gc[2] - gcn * n3[2],
            ];
            let inv_mu_t = 1.0 / mi + 1.0 / mj + 1.0 / (q * mi) + 1.0 / (q * mj);
            let k = -(1.0 + beta) / inv_mu_t;
            let pt = [k * gt[0], k * gt[1], k * gt[2]];
            for a in 0..D {
                vi[a] += pt[a] / mi;
                vj[a] -= pt[a] / mj;
            }
            // Torques: i is touched at −R_i n, j at +R_j n with −P_t.
            let np = cross3(&n3, &pt);
            let (ii, ij) = (q * mi * ri * ri, q * mj * rj * rj);
            let dwi = [-ri * np[0] / ii, -ri * np[1] / ii, -ri * np[2] / ii];
            let dwj = [-rj * np[0] / ij, -rj * np[1] / ij, -rj * np[2] / ij];
            R::set_spin(si, [wi[0] + dwi[0], wi[1] + dwi[1], wi[2] + dwi[2]]);
            R::set_spin(sj, [wj[0] + dwj[0], wj[1] + dwj[1], wj[2] + dwj[2]]);
        }
        if R::ROTATES {
            let theta = self.rule.rotation_angle(&mut self.rng);
            (vi, vj) = rotate_relative(vi, vj, mi, mj, &normal, theta, &mut self.rng);
        }
        self.particles[i].vel = vi;
        self.particles[i].r0 = pos_i - vi * now;
        self.particles[j].vel = vj;
        self.particles[j].r0 = pos_j - vj * now;
        self.meta[i].counter = self.meta[i].counter.wrapping_add(1);
        self.meta[j].counter = self.meta[j].counter.wrapping_add(1);
        self.counters.pair_collisions += 1;
        // Physical momentum transfer (the simulated one carries the deep-cooling scale).
        self.counters.virial += impulse * dist * self.inv_scale;
    }

    /// Specular reflection of particle `i` at a wall normal to `axis`, with the wall's restitution.
    #[inline]
    fn wall(&mut self, i: usize, axis: usize) {
        let now = self.now;
        let gravity = if B::GRAVITY && axis == D - 1 {
            self.params.gravity
        } else {
            0.0
        };
        let p = &mut self.particles[i];
        // Normal speed at contact (the stored velocity is the one at local time 0 under gravity).
        let u = p.vel[axis] - gravity * now;
        let e = if u.abs() < self.params.wall_threshold {
            1.0
        } else {
            self.params.wall_epsilon
        };
        let v_new = -e * u + gravity * now;
        // Keep the position continuous: r0 + v t is the non-gravitational part of the trajectory.
        p.r0[axis] += (p.vel[axis] - v_new) * now;
        p.vel[axis] = v_new;
        self.meta[i].counter = self.meta[i].counter.wrapping_add(1);
        self.counters.wall_collisions += 1;
    }

    /// Moves particle `i` into the neighbouring cell along `axis` and searches the new neighbours.
    #[inline]
    fn cross(&mut self, i: usize, axis: usize, up: bool) {
        self.counters.crossings += 1;
        let old = self.grid.index(&self.meta[i].cell);
        let n = self.grid.n[axis] as u32;
        let c = &mut self.meta[i].cell[axis];
        if up {
            *c += 1;
            if *c == n {
                *c = 0;
                self.particles[i].r0[axis] -= self.box_len[axis];
            }
        } else if *c == 0 {
            *c = n - 1;
            self.particles[i].r0[axis] += self.box_len[axis];
        } else {
            *c -= 1;
        }
        let new = self.grid.index(&self.meta[i].cell);
        self.grid.remove(&mut self.particles, i as u32, old);
        self.grid.insert(&mut self.particles, i as u32, new);
        // Only the cells that just became adjacent need a search, unless the candidate went stale.
        // Every pair a search has seen keeps a bound: since the last trajectory change of either
        // particle, one of the two searched the other (a velocity change is always followed by a
        // full search), so its stored candidate time is no later than their contact. A valid
        // candidate is thus still the earliest among the old neighbours, and no candidate at all
        // (the common case in a gas) means no old neighbour will be touched; only a stale one
        // loses the bound and calls for a full search.
        let e = self.meta[i].ev;
        let valid = e.partner == NONE || self.meta[e.partner as usize].counter == e.partner_count;
        let (t, partner) = if valid {
            self.search(
                i,
                Some((axis, if up { 1 } else { -1 })),
                (e.coll_t, e.partner),
            )
        } else {
            self.search(i, None, (f64::INFINITY, NONE))
        };
        self.store(i, t, partner);
    }

    /// `x` moved by a box length on each periodic axis where that brings it nearer to `y` (the
    /// minimum image of `x − y` is then the plain difference). `collide` and the neighbour-list
    /// search both take images this way, so that they agree to the last bit.
    #[inline(always)]
    fn image_near(&self, x: &Vector<D>, y: &Vector<D>) -> Vector<D> {
        let mut r = *x;
        for a in 0..D {
            if !B::is_wall(a) {
                let d = x[a] - y[a];
                if d > self.half_box[a] {
                    r[a] -= self.box_len[a];
                } else if d < -self.half_box[a] {
                    r[a] += self.box_len[a];
                }
            }
        }
        r
    }

    /// Neighbour-list mode: draws every shell around the particle's current position, files each
    /// particle in the cell of its centre and fills all lists from scratch.
    fn build_lists(&mut self) {
        let Some(mut nl) = self.nl.take() else {
            return;
        };
        nl.clear();
        self.grid.clear();
        for i in 0..self.particles.len() {
            let pos = self.wrapped_now(i);
            nl.centre[i] = pos;
            let c = self.grid.coords_of(&pos);
            self.meta[i].cell = c;
            self.grid
                .insert(&mut self.particles, i as u32, self.grid.index(&c));
        }
        for i in 0..self.particles.len() {
            self.gather(&mut nl, i, true);
        }
        self.nl = Some(nl);
    }

    /// The position of slot `i` now, with its trajectory moved by whole box lengths so that the
    /// position lies in the box on every periodic axis (neighbour-list mode; no gravity).
    fn wrapped_now(&mut self, i: usize) -> Vector<D> {
        let now = self.now;
        let p = &mut self.particles[i];
        let mut pos = p.r0 + p.vel * now;
        for a in 0..D {
            if !B::is_wall(a) {
                let l = self.box_len[a];
                if pos[a] < 0.0 {
                    pos[a] += l;
                    p.r0[a] += l;
                } else if pos[a] >= l {
                    pos[a] -= l;
                    p.r0[a] -= l;
                }
            }
        }
        pos
    }

    /// Links slot `i` with every particle whose shell centre lies within `σ + δ` of its own, found in
    /// the 3^D cells around `i`'s cell; with `later_only`, only slots above `i` (full builds).
    fn gather(&self, nl: &mut NeighbourLists<D>, i: usize, later_only: bool) {
        let ci = self.meta[i].cell;
        let centre = nl.centre[i];
        let ri = self.particles[i].radius;
        // Squared distance from the centre to the lower and upper face of its cell, per axis: a
        // neighbour cell farther than the largest reach cannot hold a neighbour (in 3D about a
        // quarter of the 27, mostly corners, for a centre anywhere in its cell).
        let mut face2 = [[0.0; 3]; D];
        for a in 0..D {
            let lo = ci[a] as f64 * self.grid.side[a];
            face2[a][0] = (centre[a] - lo).powi(2);
            face2[a][2] = (lo + self.grid.side[a] - centre[a]).powi(2);
        }
        let far = nl.max_reach * nl.max_reach * (1.0 + 1e-9);
        let out_of_reach = |code: usize| {
            let mut rest = code;
            let mut d2 = 0.0;
            for f in &face2 {
                d2 += f[rest % 3];
                rest /= 3;
            }
            d2 > far
        };
        // The first member of each neighbour cell, all loads started before any list is walked.
        let mut firsts = [NONE; 27];
        let mut count = 0;
        if self.grid.is_interior(&ci) {
            let c = self.grid.index(&ci) as isize;
            for (code, &o) in self.grid.full.iter().enumerate() {
                if out_of_reach(code) {
                    continue;
                }
                firsts[count] = self.grid.first((c + o) as usize);
                count += 1;
            }
        } else {
            for code in 0..3usize.pow(D as u32) {
                if out_of_reach(code) {
                    continue;
                }
                if let Some(idx) = self.grid.neighbour(&ci, code, B::is_wall) {
                    firsts[count] = self.grid.first(idx);
                    count += 1;
                }
            }
        }
        for &k in &firsts[..count] {
            if k != NONE {
                crate::prefetch::prefetch(&self.particles[k as usize]);
                crate::prefetch::prefetch(&nl.centre[k as usize]);
            }
        }
        for &first in &firsts[..count] {
            let mut k = first;
            while k != NONE {
                let j = k as usize;
                let pj = &self.particles[j];
                k = pj.next_in_cell;
                if k != NONE {
                    crate::prefetch::prefetch(&self.particles[k as usize]);
                    crate::prefetch::prefetch(&nl.centre[k as usize]);
                }
                if j == i || (later_only && j < i) {
                    continue;
                }
                let d = self.image_near(&centre, &nl.centre[j]) - nl.centre[j];
                let reach = ri + pj.radius + nl.skin;
                if d.norm_squared() < reach * reach {
                    nl.link(i, j);
                }
            }
        }
    }

    /// Shell exit of slot `i`: a new shell around its current position, new neighbours, and a new
    /// prediction. Its trajectory is unchanged, so every other particle's event stays valid.
    fn renew_list(&mut self, i: usize) {
        self.counters.crossings += 1;
        let Some(mut nl) = self.nl.take() else {
            return;
        };
        nl.detach(i);
        let pos = self.wrapped_now(i);
        nl.centre[i] = pos;
        let c = self.grid.coords_of(&pos);
        if c != self.meta[i].cell {
            let old = self.grid.index(&self.meta[i].cell);
            self.grid.remove(&mut self.particles, i as u32, old);
            self.grid
                .insert(&mut self.particles, i as u32, self.grid.index(&c));
            self.meta[i].cell = c;
        }
        self.gather(&mut nl, i, false);
        self.nl = Some(nl);
        self.predict(i);
    }

    /// Earliest contact of slot `i` (at now) with its listed neighbours.
    #[inline]
    fn search_list(&self, nl: &NeighbourLists<D>, i: usize, mut best: (f64, u32)) -> (f64, u32) {
        let now = self.now;
        let pi = self.particles[i];
        let pos_i = pi.r0 + pi.vel * now;
        let vi2 = pi.vel.norm_squared();
        let list = nl.of(i);
        // Ask for every partner's cache line at once: their loads then overlap.
        for &j in list {
            crate::prefetch::prefetch(&self.particles[j as usize]);
        }
        for &j in list {
            let pj = &self.particles[j as usize];
            let pos_j = pj.r0 + pj.vel * now;
            // The nearest image, exactly as `collide` takes it.
            let dr = self.image_near(&pos_i, &pos_j) - pos_j;
            let dv = pi.vel - pj.vel;
            let t = now + pair_time(&dr, &dv, pi.radius + pj.radius, vi2 + pj.vel.norm_squared());
            if t < best.0 {
                best = (t, j);
            }
        }
        best
    }

    /// Neighbour-list mode: the shell exit or wall contact of slot `i` (at now), whichever is first.
    #[inline]
    fn aux_event_list(&self, nl: &NeighbourLists<D>, i: usize) -> (f64, u8) {
        let now = self.now;
        let p = &self.particles[i];
        let pos = p.r0 + p.vel * now;
        let u = pos - nl.centre[i];
        let v2 = p.vel.norm_squared();
        let mut best = (f64::INFINITY, SHELL);
        if v2 > 0.0 {
            // Positive root of |u + v s|² = h² with |u| ≤ h (up to round-off), cancellation-free.
            let b = u.dot(&p.vel);
            let c = (u.norm_squared() - nl.shell * nl.shell).min(0.0);
            let q = (b * b - v2 * c).sqrt();
            let s = if b > 0.0 { -c / (b + q) } else { (q - b) / v2 };
            best.0 = now + s;
        }
        for a in 0..D {
            let v = p.vel[a];
            if !B::is_wall(a) || v == 0.0 {
                continue;
            }
            let up = v > 0.0;
            let target = if up {
                self.box_len[a] - p.radius
            } else {
                p.radius
            };
            let t = now + reach_time(pos[a], v, target);
            if t < best.0 {
                best = (t, WALL | (a as u8) << 1 | up as u8);
            }
        }
        best
    }

    /// Simulated local time at physical time `t`.
    fn local_time_of(&self, t: f64) -> f64 {
        t * self.inv_scale - self.epoch
    }

    /// Deep cooling: if the simulated temperature fell below `rescale_below` of the reference, scales
    /// every velocity back up to it and records the factor, so that T/T0 = 1e-300 and beyond is
    /// reached without underflow. The caller predicts all events again.
    fn rescale_if_cold(&mut self) -> bool {
        // Under gravity the acceleration would have to be rescaled too: no deep cooling there.
        if self.params.rescale_below <= 0.0 || B::GRAVITY {
            return false;
        }
        let sim_t = self.simulated_temperature();
        if self.t_ref == 0.0 {
            self.t_ref = sim_t;
            return false;
        }
        if !(sim_t > 0.0) || sim_t >= self.params.rescale_below * self.t_ref {
            return false;
        }
        let factor = (self.t_ref / sim_t).sqrt();
        self.rebase_clock();
        for p in &mut self.particles {
            p.vel *= factor;
        }
        self.scale_spins(factor);
        for m in &mut self.meta {
            m.counter = m.counter.wrapping_add(1);
        }
        self.epoch /= factor;
        self.ln_scale += factor.ln();
        self.inv_scale = (-self.ln_scale).exp();
        self.scale = self.ln_scale.exp();
        // The monitor's clock check compares simulated times; restart it in the new units.
        self.monitor.next_check = 0;
        true
    }

    /// Periodic scenes conserve momentum exactly, so the round-off residual of the initial zero
    /// momentum (≈ 1e-16 of the initial velocity scale) never decays, while free cooling shrinks the
    /// thermal velocities: below T/T0 ≈ 1e-32 the whole gas would drift with that residual, cooling
    /// would stop and cell crossings would swamp the collisions. A uniform velocity changes no relative
    /// motion, so once the drift carries more than 1e-12 of the kinetic energy it is removed (a
    /// Galilean boost; events are predicted again). Walls and gravity break the symmetry: never there.
    fn remove_drift_if_large(&mut self) -> bool {
        if B::WALL_MASK != 0 || B::GRAVITY {
            return false;
        }
        let (mut p, mut mass, mut twice_ke) = (Vector::<D>::zeros(), 0.0, 0.0);
        for (q, m) in self.particles.iter().zip(&self.meta) {
            p += q.vel * m.mass;
            mass += m.mass;
            twice_ke += m.mass * q.vel.norm_squared();
        }
        let drift = p / mass;
        if !(mass * drift.norm_squared() > 1e-12 * twice_ke) {
            return false;
        }
        self.rebase_clock();
        for q in &mut self.particles {
            q.vel -= drift;
        }
        for m in &mut self.meta {
            m.counter = m.counter.wrapping_add(1);
        }
        true
    }

    /// Rebases the clock to zero and re-tunes the calendar to the current event rate.
    fn maintenance(&mut self) {
        let drifted = self.remove_drift_if_large();
        if self.rescale_if_cold() || drifted {
            self.restart_events();
            return;
        }
        let (events0, t0) = self.last_maintenance;
        let elapsed = self.now - t0;
        let count = self.counters.events - events0;
        self.rebase_clock();
        self.sort_by_cell();
        if elapsed > 0.0 && count > 0 {
            self.reschedule_all(EVENTS_PER_BUCKET * elapsed / count as f64);
        } else {
            self.reschedule_all(1.0);
        }
        let n = self.particles.len() as f64;
        self.next_maintenance =
            self.counters.events + (self.params.rebase_events_per_particle * n).max(64.0) as u64;
        self.last_maintenance = (self.counters.events, 0.0);
    }

    /// True if neighbour lists replace cell crossings ([`SimParams::neighbour_skin`] > 0, no gravity,
    /// and a box of at least three cells of side `σ + δ`).
    pub fn uses_neighbour_lists(&self) -> bool {
        self.nl.is_some()
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// True if there are no particles (never, for a constructed simulation).
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// Physical time since the start (overflows to ∞ only beyond 1e308 under extreme deep cooling).
    pub fn time(&self) -> f64 {
        (self.epoch + self.now) * self.scale
    }

    /// ln of the physical time, finite however deep the cooling (the time itself overflows to ∞
    /// beyond 1e308).
    pub fn ln_time(&self) -> f64 {
        (self.epoch + self.now).ln() + self.ln_scale
    }

    /// Pair collisions per particle, τ = C/N.
    pub fn tau(&self) -> f64 {
        self.counters.pair_collisions as f64 / self.len() as f64
    }

    /// Event counters.
    pub fn counters(&self) -> &Counters {
        &self.counters
    }

    /// Resets the event counters (not the clock), e.g. after equilibration.
    pub fn reset_counters(&mut self) {
        let events = self.counters.events;
        self.counters = Counters {
            events,
            ..Counters::default()
        };
    }

    /// The box sides.
    pub fn box_len(&self) -> &Vector<D> {
        &self.box_len
    }

    /// The cell grid.
    pub fn grid(&self) -> &CellGrid<D> {
        &self.grid
    }

    /// The collision rule.
    pub fn rule(&self) -> &R {
        &self.rule
    }

    /// Masses, in the original particle order.
    pub fn masses(&self) -> Vec<f64> {
        self.in_original_order(|s| self.meta[s].mass)
    }

    /// Particle states by internal slot, which is not the original order (positions at each
    /// particle's own time `t`); see [`Self::positions`] and [`Self::velocities`].
    pub fn particles(&self) -> &[Particle<D>] {
        &self.particles
    }

    fn scale_spins(&mut self, factor: f64) {
        if R::ROUGH {
            for st in &mut self.rule_state {
                let w = R::spin(st);
                R::set_spin(st, [w[0] * factor, w[1] * factor, w[2] * factor]);
            }
        }
    }

    /// Angular velocities (physical units, original order; z only in 2D; zero for smooth rules).
    pub fn spins(&self) -> Vec<[f64; 3]> {
        self.in_original_order(|s| {
            let w = R::spin(&self.rule_state[s]);
            [
                w[0] * self.inv_scale,
                w[1] * self.inv_scale,
                w[2] * self.inv_scale,
            ]
        })
    }

    /// Sets the angular velocity of particle `id` (original index; physical units; only z counts in
    /// 2D). Ignored by smooth rules. Events are predicted again.
    pub fn set_spin(&mut self, id: usize, spin: [f64; 3]) {
        if let Some(s) = self.meta.iter().position(|m| m.id as usize == id) {
            let f = self.scale;
            R::set_spin(
                &mut self.rule_state[s],
                [spin[0] * f, spin[1] * f, spin[2] * f],
            );
        }
    }

    /// Rotational kinetic energy Σ I ω²/2 (physical units; zero for smooth rules).
    pub fn rotational_energy(&self) -> f64 {
        if !R::ROUGH {
            return 0.0;
        }
        let (_, q) = self.rule.roughness();
        let sum: f64 = (0..self.len())
            .map(|s| {
                let w = R::spin(&self.rule_state[s]);
                let r = self.particles[s].radius;
                0.5 * q * self.meta[s].mass * r * r * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
            })
            .sum();
        sum * self.inv_scale * self.inv_scale
    }

    /// Collisions (pair and wall) suffered by each particle, in the original order.
    pub fn collision_counts(&self) -> Vec<u32> {
        self.in_original_order(|s| self.meta[s].counter)
    }

    /// Gathers a per-slot quantity into the original particle order.
    fn in_original_order<T>(&self, f: impl Fn(usize) -> T) -> Vec<T> {
        let mut slot = vec![0u32; self.len()];
        for (s, m) in self.meta.iter().enumerate() {
            slot[m.id as usize] = s as u32;
        }
        slot.into_iter().map(|s| f(s as usize)).collect()
    }

    /// Velocities, in the original particle order.
    pub fn velocities(&self) -> Vec<Vector<D>> {
        self.in_original_order(|s| self.velocity_now(&self.particles[s]) * self.inv_scale)
    }

    /// Velocities in the simulation's internal units (the physical ones times
    /// `exp(ln_velocity_scale())`), in the original order: finite and well-scaled at any depth of
    /// cooling, for scale-free measures such as [`crate::order_parameters`].
    pub fn velocities_internal(&self) -> Vec<Vector<D>> {
        self.in_original_order(|s| self.velocity_now(&self.particles[s]))
    }

    /// A particle's velocity at the current time (the stored one is at local time 0 under gravity).
    #[inline(always)]
    pub(crate) fn velocity_now(&self, p: &Particle<D>) -> Vector<D> {
        let mut v = p.vel;
        if B::GRAVITY {
            v[D - 1] -= self.params.gravity * self.now;
        }
        v
    }

    /// Potential energy Σ m g h in the gravity field (0 without gravity).
    pub fn potential_energy(&self) -> f64 {
        if !B::GRAVITY {
            return 0.0;
        }
        let g = self.params.gravity;
        (0..self.len())
            .map(|s| self.meta[s].mass * g * self.position_of_slot(s)[D - 1])
            .sum()
    }

    /// Positions at the current time, wrapped into the box on periodic axes, in the original order.
    pub fn positions(&self) -> Vec<Vector<D>> {
        self.in_original_order(|s| self.position_of_slot(s))
    }

    fn position_of_slot(&self, s: usize) -> Vector<D> {
        let p = &self.particles[s];
        let mut x = p.r0 + p.vel * self.now;
        if B::GRAVITY {
            x[D - 1] -= 0.5 * self.params.gravity * self.now * self.now;
        }
        for a in 0..D {
            if !B::is_wall(a) {
                x[a] = x[a].rem_euclid(self.box_len[a]);
            }
        }
        x
    }

    /// Scales every velocity by `factor` and predicts all events again (e.g. to set a temperature).
    pub fn scale_velocities(&mut self, factor: f64) {
        self.rebase_clock();
        for p in &mut self.particles {
            p.vel *= factor;
        }
        self.scale_spins(factor);
        for m in &mut self.meta {
            m.counter = m.counter.wrapping_add(1);
        }
        self.restart_events();
    }

    /// Heap bytes held by the simulation's own arrays (particles, events, cells, calendar estimate).
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        self.particles.capacity() * size_of::<Particle<D>>()
            + self.meta.capacity() * size_of::<Meta<D>>()
            + self.grid.heap_bytes()
            + self.nl.as_ref().map_or(0, |nl| nl.heap_bytes())
    }

    /// The deepest overlap among all neighbouring pairs, as `(i, j, depth / contact distance)` with
    /// original indices (negative depth: the closest pair's gap); O(N).
    pub fn deepest_overlap(&self) -> Option<(usize, usize, f64)> {
        let pos: Vec<Vector<D>> = (0..self.len()).map(|s| self.position_of_slot(s)).collect();
        let mut worst: Option<(usize, usize, f64)> = None;
        for i in 0..self.len() {
            let ci = self.meta[i].cell;
            for code in 0..3usize.pow(D as u32) {
                let Some(idx) = self.grid.neighbour(&ci, code, B::is_wall) else {
                    continue;
                };
                let mut k = self.grid.first(idx);
                while k != NONE {
                    let k_ = k as usize;
                    if k_ > i {
                        let mut dr = pos[i] - pos[k_];
                        for a in 0..D {
                            if !B::is_wall(a) {
                                dr[a] -= self.box_len[a] * (dr[a] / self.box_len[a]).round();
                            }
                        }
                        let sigma = self.particles[i].radius + self.particles[k_].radius;
                        let depth = (sigma - dr.norm()) / sigma;
                        if worst.is_none_or(|w| depth > w.2) {
                            worst =
                                Some((self.meta[i].id as usize, self.meta[k_].id as usize, depth));
                        }
                    }
                    k = self.particles[k_].next_in_cell;
                }
            }
        }
        worst
    }
}

/// A D-vector as a 3-vector (z = 0 in 2D).
#[inline(always)]
fn pad3<const D: usize>(v: &Vector<D>) -> [f64; 3] {
    let mut out = [0.0; 3];
    for a in 0..D.min(3) {
        out[a] = v[a];
    }
    out
}

#[inline(always)]
fn cross3(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Rotates the relative velocity `vi − vj` by `theta` about a random axis in the centre-of-mass frame,
/// keeping the centre-of-mass velocity and |vi − vj|; the direction is flipped if the first choice
/// would make the pair approach along `normal`, and no rotation is done if both would.
fn rotate_relative<const D: usize>(
    vi: Vector<D>,
    vj: Vector<D>,
    mi: f64,
    mj: f64,
    normal: &Vector<D>,
    theta: f64,
    rng: &mut Xoshiro256PlusPlus,
) -> (Vector<D>, Vector<D>) {
    use rand::Rng;
    let g = vi - vj;
    let speed = g.norm();
    if theta == 0.0 || speed == 0.0 {
        return (vi, vj);
    }
    let gh = g / speed;
    // A random unit vector perpendicular to g (in 2D: one of the two normals).
    let mut w = Vector::<D>::from_fn(|_, _| rng.sample::<f64, _>(rand_distr::StandardNormal));
    w -= gh * w.dot(&gh);
    let wn = w.norm();
    if wn == 0.0 {
        return (vi, vj);
    }
    w /= wn;
    let (s, c) = theta.sin_cos();
    let mut rotated = (gh * c + w * s) * speed;
    if rotated.dot(normal) < 0.0 {
        rotated = (gh * c - w * s) * speed;
        if rotated.dot(normal) < 0.0 {
            return (vi, vj);
        }
    }
    let mt = mi + mj;
    let vcm = (vi * mi + vj * mj) / mt;
    (vcm + rotated * (mj / mt), vcm - rotated * (mi / mt))
}

/// When to stop a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stop {
    /// After this many pair collisions per particle, τ = C/N (counted since the last counter reset).
    Tau(f64),
    /// At this physical time.
    Time(f64),
    /// After this many more events of any kind.
    Events(u64),
}

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunEnd {
    /// The stop condition was reached.
    Reached,
    /// No event is left (every particle at rest).
    Exhausted,
    /// Inelastic collapse was detected (see [`Simulation::collapse`]).
    Collapsed,
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Runs until `stop`.
    pub fn run(&mut self, stop: Stop) -> RunEnd {
        if self.monitor.found.is_some() {
            return RunEnd::Collapsed;
        }
        match stop {
            Stop::Tau(tau) => {
                let target = (tau * self.len() as f64).ceil().max(0.0) as u64;
                while self.counters.pair_collisions < target {
                    if self.step().is_none() {
                        return RunEnd::Exhausted;
                    }
                    if self.monitor.found.is_some() {
                        return RunEnd::Collapsed;
                    }
                }
            }
            Stop::Events(n) => {
                let target = self.counters.events + n;
                while self.counters.events < target {
                    if self.step().is_none() {
                        return RunEnd::Exhausted;
                    }
                    if self.monitor.found.is_some() {
                        return RunEnd::Collapsed;
                    }
                }
            }
            Stop::Time(t) => loop {
                let local = self.local_time_of(t);
                match self.calendar.peek_time() {
                    Some(next) if next <= local => {
                        self.step();
                        if self.monitor.found.is_some() {
                            return RunEnd::Collapsed;
                        }
                    }
                    Some(_) => {
                        self.now = local.max(self.now);
                        return RunEnd::Reached;
                    }
                    None => {
                        self.now = local.max(self.now);
                        return RunEnd::Exhausted;
                    }
                }
            },
        }
        RunEnd::Reached
    }

    /// Runs until `stop`, calling `observe` whenever τ passes a point of `schedule` (including the
    /// current τ if the schedule holds it).
    pub fn run_sampled(
        &mut self,
        stop: Stop,
        schedule: &crate::Schedule,
        mut observe: impl FnMut(&Self),
    ) -> RunEnd {
        let n = self.len() as f64;
        let mut next = schedule.first_at_or_after(self.tau());
        let event_target = match stop {
            Stop::Events(k) => self.counters.events + k,
            _ => u64::MAX,
        };
        loop {
            while let Some(tau) = next {
                if (self.counters.pair_collisions as f64) < (tau * n).ceil() {
                    break;
                }
                observe(self);
                next = schedule.next_after(tau);
            }
            let done = match stop {
                Stop::Tau(t) => self.counters.pair_collisions as f64 >= (t * n).ceil(),
                Stop::Events(_) => self.counters.events >= event_target,
                Stop::Time(t) => match self.calendar.peek_time() {
                    Some(next_t) if next_t <= self.local_time_of(t) => false,
                    _ => {
                        self.now = self.local_time_of(t).max(self.now);
                        true
                    }
                },
            };
            if done {
                return RunEnd::Reached;
            }
            if self.step().is_none() {
                return RunEnd::Exhausted;
            }
            if self.monitor.found.is_some() {
                return RunEnd::Collapsed;
            }
        }
    }
}

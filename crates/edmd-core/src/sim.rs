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
//! Time is a local clock, rebased to zero every few `N` events together with a re-tuning of the
//! calendar's bucket width; [`Simulation::time`] adds the rebased epochs back.

use std::marker::PhantomData;

use crate::calendar::{Calendar, PaulCalendar};
use crate::cells::{CellGrid, NONE};
use crate::predict::{pair_time, reach_time};
use crate::{Boundary, CollisionRule, EdmdError, Particle, ParticleInit, Vector};

const WALL: u8 = 0x80;
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
    const EMPTY: EventSlot = EventSlot { coll_t: f64::INFINITY, aux_t: f64::INFINITY, partner: NONE, partner_count: 0, aux: 0 };
}

/// What an event was.
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
    /// Cell crossings.
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
}

impl Default for SimParams {
    fn default() -> Self {
        SimParams { cell_factor: 1.0, rebase_events_per_particle: 8.0 }
    }
}

impl SimParams {
    /// A cell factor that balances crossings against neighbour checks for a packing fraction `phi`.
    pub fn for_density<const D: usize>(phi: f64) -> Self {
        // About one particle per cell area at low density, never below the diameter.
        let per_cell_volume = if D == 2 { std::f64::consts::PI / 4.0 } else { std::f64::consts::PI / 6.0 };
        let side = (per_cell_volume / phi.max(1e-12)).powf(1.0 / D as f64) * 0.9;
        SimParams { cell_factor: side.max(1.0), ..Default::default() }
    }
}

/// An event-driven simulation of hard disks (`D = 2`) or spheres (`D = 3`) in a box with boundary
/// `B`, collision rule `R` and calendar `C`.
#[derive(Debug, Clone)]
pub struct Simulation<const D: usize, B: Boundary, R: CollisionRule, C: Calendar = PaulCalendar> {
    pub(crate) particles: Vec<Particle<D>>,
    pub(crate) mass: Vec<f64>,
    pub(crate) counter: Vec<u32>,
    pub(crate) cell: Vec<[u32; D]>,
    pub(crate) events: Vec<EventSlot>,
    pub(crate) grid: CellGrid<D>,
    pub(crate) calendar: C,
    pub(crate) rule: R,
    pub(crate) box_len: Vector<D>,
    pub(crate) half_box: Vector<D>,
    pub(crate) now: f64,
    pub(crate) epoch: f64,
    pub(crate) counters: Counters,
    params: SimParams,
    next_maintenance: u64,
    last_maintenance: (u64, f64),
    _boundary: PhantomData<B>,
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Builds a simulation from explicit particles. Errors if a parameter is invalid, a particle lies
    /// outside the box (or inside a wall), or two particles overlap.
    pub fn new(box_len: Vector<D>, particles: &[ParticleInit<D>], rule: R, params: SimParams) -> Result<Self, EdmdError> {
        let n = particles.len();
        if n == 0 {
            return Err(EdmdError::invalid("N", 0, "need at least one particle"));
        }
        if n >= NONE as usize {
            return Err(EdmdError::invalid("N", n, "at most 2^32 − 2 particles"));
        }
        for a in 0..D {
            if !(box_len[a] > 0.0 && box_len[a].is_finite()) {
                return Err(EdmdError::invalid(crate::error::AXIS_NAMES[a], box_len[a], "box side must be positive and finite"));
            }
        }
        if !(params.cell_factor >= 1.0 && params.cell_factor.is_finite()) {
            return Err(EdmdError::invalid("cell_factor", params.cell_factor, "must be ≥ 1"));
        }
        if !(params.rebase_events_per_particle > 0.0) {
            return Err(EdmdError::invalid("rebase_events_per_particle", params.rebase_events_per_particle, "must be > 0"));
        }
        let mut max_d: f64 = 0.0;
        for (i, p) in particles.iter().enumerate() {
            if !(p.radius > 0.0 && p.radius.is_finite()) {
                return Err(EdmdError::invalid("radius", p.radius, format!("particle {i}: radius must be positive")));
            }
            if !(p.mass > 0.0 && p.mass.is_finite()) {
                return Err(EdmdError::invalid("mass", p.mass, format!("particle {i}: mass must be positive")));
            }
            for a in 0..D {
                let (lo, hi) = if B::is_wall(a) { (p.radius, box_len[a] - p.radius) } else { (0.0, box_len[a]) };
                let x = p.pos[a];
                if !(x >= lo && x <= hi) || (!B::is_wall(a) && x >= hi) {
                    return Err(EdmdError::invalid("position", x, format!("particle {i}, axis {a}: outside [{lo}, {hi}]")));
                }
                if !p.vel[a].is_finite() {
                    return Err(EdmdError::invalid("velocity", p.vel[a], format!("particle {i}: not finite")));
                }
            }
            max_d = max_d.max(2.0 * p.radius);
        }
        let grid = CellGrid::new(&box_len, max_d, max_d * params.cell_factor, n)?;
        let mut sim = Simulation {
            particles: particles.iter().map(|p| Particle { pos: p.pos, vel: p.vel, t: 0.0, radius: p.radius }).collect(),
            mass: particles.iter().map(|p| p.mass).collect(),
            counter: vec![0; n],
            cell: vec![[0; D]; n],
            events: vec![EventSlot::EMPTY; n],
            grid,
            calendar: C::with_capacity(n),
            rule,
            box_len,
            half_box: box_len / 2.0,
            now: 0.0,
            epoch: 0.0,
            counters: Counters::default(),
            params,
            next_maintenance: 0,
            last_maintenance: (0, 0.0),
            _boundary: PhantomData,
        };
        for i in 0..n {
            let c = sim.grid.coords_of(&sim.particles[i].pos);
            sim.cell[i] = c;
            sim.grid.insert(i as u32, sim.grid.index(&c));
        }
        if let Some((i, j, overlap)) = sim.deepest_overlap().filter(|o| o.2 > 1e-12) {
            return Err(EdmdError::Overlap { i, j, overlap });
        }
        sim.restart_events();
        Ok(sim)
    }

    /// Replaces the collision rule, keeping the state (e.g. after an elastic melt).
    pub fn with_rule<R2: CollisionRule>(self, rule: R2) -> Simulation<D, B, R2, C> {
        Simulation {
            particles: self.particles,
            mass: self.mass,
            counter: self.counter,
            cell: self.cell,
            events: self.events,
            grid: self.grid,
            calendar: self.calendar,
            rule,
            box_len: self.box_len,
            half_box: self.half_box,
            now: self.now,
            epoch: self.epoch,
            counters: self.counters,
            params: self.params,
            next_maintenance: self.next_maintenance,
            last_maintenance: self.last_maintenance,
            _boundary: PhantomData,
        }
    }

    /// Predicts every particle's event from scratch and sizes the calendar's buckets from them.
    pub fn restart_events(&mut self) {
        let n = self.particles.len();
        self.sync();
        let mut sum = 0.0;
        let mut count = 0usize;
        for i in 0..n {
            let (coll_t, partner) = self.search(i, None, (f64::INFINITY, NONE));
            let (aux_t, aux) = self.aux_event(i);
            let partner_count = if partner == NONE { 0 } else { self.counter[partner as usize] };
            self.events[i] = EventSlot { coll_t, aux_t, partner, partner_count, aux };
            let t = coll_t.min(aux_t);
            if t.is_finite() {
                sum += t - self.now;
                count += 1;
            }
        }
        // Each event renews about 1.5 predictions: the mean time between events is ≈ ⟨Δt⟩ / (0.7 N).
        let width = if count > 0 && sum > 0.0 { EVENTS_PER_BUCKET * sum / count as f64 / (0.7 * n as f64) } else { 1.0 };
        self.reschedule_all(width);
        self.next_maintenance = self.counters.events + n.max(1000) as u64;
        self.last_maintenance = (self.counters.events, self.now);
    }

    fn reschedule_all(&mut self, width: f64) {
        self.calendar.reset(self.now, width);
        for i in 0..self.particles.len() {
            let e = &self.events[i];
            self.calendar.schedule(i as u32, e.coll_t.min(e.aux_t));
        }
    }

    /// Moves every particle to the current time.
    pub fn sync(&mut self) {
        let now = self.now;
        for p in &mut self.particles {
            p.pos += p.vel * (now - p.t);
            p.t = now;
        }
    }

    #[inline(always)]
    fn advance(&mut self, i: usize) {
        let p = &mut self.particles[i];
        p.pos += p.vel * (self.now - p.t);
        p.t = self.now;
    }

    /// Processes the next event. Returns `None` when nothing will ever happen again (all at rest).
    #[inline]
    pub fn step(&mut self) -> Option<EventKind> {
        let (i, t) = self.calendar.pop()?;
        debug_assert!(t >= self.now, "event in the past: {t} < {}", self.now);
        self.now = t;
        self.counters.events += 1;
        let i = i as usize;
        let e = self.events[i];
        let kind = if e.coll_t <= e.aux_t {
            let j = e.partner as usize;
            if self.counter[j] == e.partner_count {
                self.collide(i, j);
                self.predict(i);
                self.predict(j);
                EventKind::Collision(i as u32, j as u32)
            } else {
                self.advance(i);
                self.predict(i);
                EventKind::Stale(i as u32)
            }
        } else if e.aux & WALL != 0 {
            self.wall(i, (e.aux & 0x7f) as usize >> 1);
            self.predict(i);
            EventKind::Wall(i as u32)
        } else {
            self.cross(i, (e.aux >> 1) as usize, e.aux & 1 != 0);
            EventKind::CellCrossing(i as u32)
        };
        if self.counters.events >= self.next_maintenance {
            self.maintenance();
        }
        Some(kind)
    }

    /// Full prediction for particle `i` (already advanced to now), then reschedule it.
    #[inline]
    fn predict(&mut self, i: usize) {
        let (coll_t, partner) = self.search(i, None, (f64::INFINITY, NONE));
        self.store(i, coll_t, partner);
    }

    #[inline]
    fn store(&mut self, i: usize, coll_t: f64, partner: u32) {
        let (aux_t, aux) = self.aux_event(i);
        let partner_count = if partner == NONE { 0 } else { self.counter[partner as usize] };
        self.events[i] = EventSlot { coll_t, aux_t, partner, partner_count, aux };
        self.calendar.schedule(i as u32, coll_t.min(aux_t));
    }

    /// Earliest contact of particle `i` (at now) with the members of its neighbour cells; with
    /// `only = Some((axis, dir))`, just the cells at offset `dir` along `axis`.
    #[inline]
    fn search(&self, i: usize, only: Option<(usize, i32)>, mut best: (f64, u32)) -> (f64, u32) {
        let pi = self.particles[i];
        let ci = self.cell[i];
        let now = self.now;
        let combos = 3usize.pow(D as u32);
        'cells: for code in 0..combos {
            let mut rest = code;
            let mut idx = 0usize;
            let mut shift = Vector::<D>::zeros();
            for a in 0..D {
                let off = (rest % 3) as i32 - 1;
                rest /= 3;
                if let Some((axis, dir)) = only {
                    if a == axis && off != dir {
                        continue 'cells;
                    }
                }
                let n = self.grid.n[a] as i32;
                let mut x = ci[a] as i32 + off;
                if x < 0 {
                    if B::is_wall(a) {
                        continue 'cells;
                    }
                    x += n;
                    shift[a] = -self.box_len[a];
                } else if x >= n {
                    if B::is_wall(a) {
                        continue 'cells;
                    }
                    x -= n;
                    shift[a] = self.box_len[a];
                }
                idx += x as usize * self.grid.stride[a];
            }
            let mut k = self.grid.first(idx);
            while k != NONE {
                if k as usize != i {
                    let pk = &self.particles[k as usize];
                    let dr = pi.pos - pk.pos - pk.vel * (now - pk.t) - shift;
                    let dv = pi.vel - pk.vel;
                    let t = now + pair_time(&dr, &dv, pi.radius + pk.radius);
                    if t < best.0 {
                        best = (t, k);
                    }
                }
                k = self.grid.next(k);
            }
        }
        best
    }

    /// Next cell crossing or wall contact of particle `i` (at now).
    #[inline]
    fn aux_event(&self, i: usize) -> (f64, u8) {
        let p = &self.particles[i];
        let c = &self.cell[i];
        let mut best = (f64::INFINITY, 0u8);
        for a in 0..D {
            let v = p.vel[a];
            let up = v > 0.0;
            if v == 0.0 {
                continue;
            }
            let edge = if up { c[a] as usize + 1 == self.grid.n[a] } else { c[a] == 0 };
            let (dt, code) = if B::is_wall(a) && edge {
                let target = if up { self.box_len[a] - p.radius } else { p.radius };
                (reach_time(p.pos[a], v, target), WALL | (a as u8) << 1 | up as u8)
            } else {
                let face = (c[a] + up as u32) as f64 * self.grid.side[a];
                (reach_time(p.pos[a], v, face), (a as u8) << 1 | up as u8)
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
        self.advance(i);
        self.advance(j);
        let (pi, pj) = (self.particles[i], self.particles[j]);
        let mut dr = pi.pos - pj.pos;
        for a in 0..D {
            if !B::is_wall(a) {
                if dr[a] > self.half_box[a] {
                    dr[a] -= self.box_len[a];
                } else if dr[a] < -self.half_box[a] {
                    dr[a] += self.box_len[a];
                }
            }
        }
        let dist = dr.norm();
        let normal = dr / dist;
        let gn = (pi.vel - pj.vel).dot(&normal);
        if gn >= 0.0 {
            // Grazing contact that round-off turned into a separation: nothing to exchange.
            return;
        }
        let eps = self.rule.restitution(-gn);
        let (mi, mj) = (self.mass[i], self.mass[j]);
        let impulse = -(1.0 + eps) * gn * (mi * mj / (mi + mj));
        self.particles[i].vel += normal * (impulse / mi);
        self.particles[j].vel -= normal * (impulse / mj);
        self.counter[i] = self.counter[i].wrapping_add(1);
        self.counter[j] = self.counter[j].wrapping_add(1);
        self.counters.pair_collisions += 1;
        self.counters.virial += impulse * dist;
    }

    /// Specular reflection of particle `i` at a wall normal to `axis`.
    #[inline]
    fn wall(&mut self, i: usize, axis: usize) {
        self.advance(i);
        let p = &mut self.particles[i];
        p.vel[axis] = -p.vel[axis];
        self.counter[i] = self.counter[i].wrapping_add(1);
        self.counters.wall_collisions += 1;
    }

    /// Moves particle `i` into the neighbouring cell along `axis` and searches the new neighbours.
    #[inline]
    fn cross(&mut self, i: usize, axis: usize, up: bool) {
        self.advance(i);
        self.counters.crossings += 1;
        let old = self.grid.index(&self.cell[i]);
        let n = self.grid.n[axis] as u32;
        let c = &mut self.cell[i][axis];
        if up {
            *c += 1;
            if *c == n {
                *c = 0;
                self.particles[i].pos[axis] -= self.box_len[axis];
            }
        } else if *c == 0 {
            *c = n - 1;
            self.particles[i].pos[axis] += self.box_len[axis];
        } else {
            *c -= 1;
        }
        let new = self.grid.index(&self.cell[i]);
        self.grid.remove(i as u32, old);
        self.grid.insert(i as u32, new);
        let e = self.events[i];
        let valid = e.partner != NONE && self.counter[e.partner as usize] == e.partner_count;
        let (t, partner) = if valid {
            self.search(i, Some((axis, if up { 1 } else { -1 })), (e.coll_t, e.partner))
        } else {
            self.search(i, None, (f64::INFINITY, NONE))
        };
        self.store(i, t, partner);
    }

    /// Rebases the clock to zero and re-tunes the calendar to the current event rate.
    fn maintenance(&mut self) {
        let (events0, t0) = self.last_maintenance;
        let elapsed = self.now - t0;
        let count = self.counters.events - events0;
        self.sync();
        let shift = self.now;
        for p in &mut self.particles {
            p.t = 0.0;
        }
        for e in &mut self.events {
            e.coll_t -= shift;
            e.aux_t -= shift;
        }
        self.epoch += shift;
        self.now = 0.0;
        if elapsed > 0.0 && count > 0 {
            self.reschedule_all(EVENTS_PER_BUCKET * elapsed / count as f64);
        } else {
            self.reschedule_all(1.0);
        }
        let n = self.particles.len() as f64;
        self.next_maintenance = self.counters.events + (self.params.rebase_events_per_particle * n).max(1000.0) as u64;
        self.last_maintenance = (self.counters.events, 0.0);
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// True if there are no particles (never, for a constructed simulation).
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// Physical time since the start.
    pub fn time(&self) -> f64 {
        self.epoch + self.now
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
        self.counters = Counters { events, ..Counters::default() };
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

    /// Per-particle masses.
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }

    /// Particle states (positions at each particle's own time `t`; see [`Self::positions`]).
    pub fn particles(&self) -> &[Particle<D>] {
        &self.particles
    }

    /// Per-particle collision counters (pair and wall collisions suffered).
    pub fn collision_counts(&self) -> &[u32] {
        &self.counter
    }

    /// Velocities, which do not depend on the lazy update.
    pub fn velocities(&self) -> impl ExactSizeIterator<Item = Vector<D>> + '_ {
        self.particles.iter().map(|p| p.vel)
    }

    /// Positions at the current time, wrapped into the box on periodic axes.
    pub fn positions(&self) -> Vec<Vector<D>> {
        self.particles
            .iter()
            .map(|p| {
                let mut x = p.pos + p.vel * (self.now - p.t);
                for a in 0..D {
                    if !B::is_wall(a) {
                        x[a] = x[a].rem_euclid(self.box_len[a]);
                    }
                }
                x
            })
            .collect()
    }

    /// Scales every velocity by `factor` and predicts all events again (e.g. to set a temperature).
    pub fn scale_velocities(&mut self, factor: f64) {
        self.sync();
        for p in &mut self.particles {
            p.vel *= factor;
        }
        for c in &mut self.counter {
            *c = c.wrapping_add(1);
        }
        self.restart_events();
    }

    /// Heap bytes held by the simulation's own arrays (particles, events, cells, calendar estimate).
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        self.particles.capacity() * size_of::<Particle<D>>()
            + self.mass.capacity() * 8
            + self.counter.capacity() * 4
            + self.cell.capacity() * size_of::<[u32; D]>()
            + self.events.capacity() * size_of::<EventSlot>()
            + self.grid.heap_bytes()
    }

    /// The deepest overlap among all touching pairs, as `(i, j, depth / contact distance)`; O(N).
    pub fn deepest_overlap(&self) -> Option<(usize, usize, f64)> {
        let pos = self.positions();
        let mut worst: Option<(usize, usize, f64)> = None;
        for i in 0..self.len() {
            let ci = self.grid.coords_of(&pos[i]);
            // Use the authoritative cell, except right after construction where both agree.
            let ci = if self.counters.events == 0 { ci } else { self.cell[i] };
            for code in 0..3usize.pow(D as u32) {
                let mut rest = code;
                let mut idx = 0;
                let mut ok = true;
                for a in 0..D {
                    let off = (rest % 3) as i32 - 1;
                    rest /= 3;
                    let n = self.grid.n[a] as i32;
                    let x = ci[a] as i32 + off;
                    if (x < 0 || x >= n) && B::is_wall(a) {
                        ok = false;
                        break;
                    }
                    idx += x.rem_euclid(n) as usize * self.grid.stride[a];
                }
                if !ok {
                    continue;
                }
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
                            worst = Some((i, k_, depth));
                        }
                    }
                    k = self.grid.next(k);
                }
            }
        }
        worst
    }
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
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Runs until `stop`.
    pub fn run(&mut self, stop: Stop) -> RunEnd {
        match stop {
            Stop::Tau(tau) => {
                let target = (tau * self.len() as f64).ceil().max(0.0) as u64;
                while self.counters.pair_collisions < target {
                    if self.step().is_none() {
                        return RunEnd::Exhausted;
                    }
                }
            }
            Stop::Events(n) => {
                let target = self.counters.events + n;
                while self.counters.events < target {
                    if self.step().is_none() {
                        return RunEnd::Exhausted;
                    }
                }
            }
            Stop::Time(t) => loop {
                let local = t - self.epoch;
                match self.calendar.peek_time() {
                    Some(next) if next <= local => {
                        self.step();
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
    pub fn run_sampled(&mut self, stop: Stop, schedule: &crate::Schedule, mut observe: impl FnMut(&Self)) -> RunEnd {
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
                    Some(next_t) if next_t <= t - self.epoch => false,
                    _ => {
                        self.now = (t - self.epoch).max(self.now);
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
        }
    }
}

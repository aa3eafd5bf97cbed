//! Read access and small edits: time, counters, per-particle quantities in the original order,
//! energies, overlaps.

use super::{Meta, Simulation};
use crate::calendar::Calendar;
use crate::sim::neighbours::{CellGrid, NONE};
use crate::{Boundary, CollisionRule, Counters, EdmdError, Particle, Vector};

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// True if neighbour lists replace cell crossings ([`SimParams::neighbour_skin`] > 0, no gravity,
    /// and a box of at least three cells of side `σ + δ`).
    pub fn uses_neighbour_lists(&self) -> bool {
        self.uses_lists()
    }

    /// [`Self::uses_neighbour_lists`] as the one place the event loop chooses its strategy. A scene
    /// with gravity never has lists (`Simulation::new`), and the constant makes that known to the
    /// compiler: the list-mode loop is not compiled into those scenes at all.
    #[inline(always)]
    pub(super) fn uses_lists(&self) -> bool {
        super::lists_possible::<B>() && self.nl.is_some()
    }

    /// The member after slot `k` in its cell: the grid links through [`NeighbourLists::links`] in
    /// list mode and through the records themselves in cell mode (for the walks outside the event
    /// loop's own, which know their mode).
    ///
    /// [`NeighbourLists::links`]: crate::sim::neighbours::NeighbourLists::links
    #[inline]
    pub(super) fn next_in_cell(&self, k: u32) -> u32 {
        match &self.nl {
            Some(nl) => nl.links[k as usize],
            None => self.particles[k as usize].next_in_cell,
        }
    }

    /// Files slot `i` in the grid's cell `idx`, linked as [`Self::next_in_cell`] reads.
    #[inline]
    pub(super) fn file_in_cell(&mut self, i: u32, idx: usize) {
        match &mut self.nl {
            Some(nl) => self.grid.insert(&mut nl.links, i, idx),
            None => self.grid.insert(&mut self.particles, i, idx),
        }
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

    /// Whether the large-system look-ahead is on: prefetch hints for what the coming events will
    /// read (the next partner's list in neighbour-list mode, the staged look-ahead over the
    /// calendar's next buckets in cell mode). It is switched on when the engine's arrays exceed
    /// [`crate::caches::look_ahead_threshold`] (32 times the per-core L2: 64 MiB with a 2 MiB L2),
    /// where those lines are not in cache.
    pub fn look_ahead(&self) -> bool {
        self.look_ahead.on
    }

    /// Forces the large-system look-ahead on or off (benchmarks, tests). Hints only: events and
    /// trajectories are the same either way.
    pub fn set_look_ahead(&mut self, on: bool) {
        self.look_ahead.on = on;
    }

    /// Whether list scans test four partners at once (x86-64 processors with AVX2;
    /// `sim/neighbours/wide_scan.rs`).
    pub fn wide_scan(&self) -> bool {
        self.nl.as_ref().is_some_and(|nl| nl.wide)
    }

    /// Scans lists two partners at a time, as on any processor (tests, benchmarks): events and
    /// trajectories are bit-identical either way.
    pub fn use_portable_scan(&mut self) {
        if let Some(nl) = &mut self.nl {
            nl.use_portable_scan();
        }
    }

    /// Resets the event counters (not the clock), e.g. after equilibration.
    pub fn reset_counters(&mut self) {
        let events = self.counters.events;
        self.counters = Counters {
            events,
            ..Counters::default()
        };
    }

    /// Zeroes the sheared scene's interval sums, [`Counters::virial_tensor`] and
    /// [`Counters::dissipated`], so that they sum the next interval alone.
    pub fn restart_shear_sums(&mut self) {
        self.counters.virial_tensor = [[0.0; 3]; 3];
        self.counters.dissipated = 0.0;
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

    /// Replaces the collision rule's law and remedy between runs (see [`CollisionRule::set_law`]).
    pub fn set_law(&mut self, law: crate::Law, remedy: crate::Remedy) -> Result<(), EdmdError> {
        self.rule.set_law(law, remedy)
    }

    /// Radii, in the original particle order.
    pub fn radii(&self) -> Vec<f64> {
        self.in_original_order(|s| self.particles[s].radius)
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
    /// 2D). Ignored by smooth rules. Contact times do not depend on spins, so no event changes.
    pub fn set_spin(&mut self, id: usize, spin: [f64; 3]) {
        if let Some(s) = self.meta[..self.len()]
            .iter()
            .position(|m| m.id as usize == id)
        {
            let f = self.scale;
            R::set_spin(
                &mut self.rule_state[s],
                [spin[0] * f, spin[1] * f, spin[2] * f],
            );
        }
    }

    /// Sets every angular velocity at once (original order; physical units; only z counts in 2D).
    /// Ignored by smooth rules.
    pub fn set_spins(&mut self, spins: &[[f64; 3]]) -> Result<(), EdmdError> {
        if spins.len() != self.len() {
            return Err(EdmdError::invalid(
                "spins",
                spins.len(),
                format!("{} particles need as many angular velocities", self.len()),
            ));
        }
        let f = self.scale;
        for s in 0..self.len() {
            let w = spins[self.meta[s].id as usize];
            R::set_spin(&mut self.rule_state[s], [w[0] * f, w[1] * f, w[2] * f]);
        }
        Ok(())
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
        self.in_original_order(|s| self.particles[s].counter)
    }

    /// Gathers a per-slot quantity into the original particle order.
    pub(super) fn in_original_order<T>(&self, f: impl Fn(usize) -> T) -> Vec<T> {
        let mut slot = vec![0u32; self.len()];
        for (s, m) in self.meta[..self.len()].iter().enumerate() {
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

    /// Positions at the current time, wrapped into the box on periodic axes, in the original order.
    pub fn positions(&self) -> Vec<Vector<D>> {
        self.in_original_order(|s| self.position_of_slot(s))
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
        // Particles cell by cell, so that the neighbour cells' members were read shortly before
        // (slots need not be in cell order here: this runs before the first renumbering).
        let members = (0..self.grid.len()).flat_map(|c| {
            let first = self.grid.first(c);
            std::iter::successors((first != NONE).then_some(first), |&k| {
                let next = self.next_in_cell(k);
                (next != NONE).then_some(next)
            })
        });
        for i in members {
            let i = i as usize;
            let cells = self.grid.neighbours(&self.meta[i].cell(), B::is_wall);
            for &idx in &cells[..3usize.pow(D as u32)] {
                if idx == usize::MAX {
                    continue;
                }
                let mut k = self.grid.first(idx);
                while k != NONE {
                    let k_ = k as usize;
                    k = self.next_in_cell(k);
                    if k_ <= i {
                        continue;
                    }
                    let mut dr = pos[i] - pos[k_];
                    for a in 0..D {
                        if !B::is_wall(a) {
                            dr[a] -= self.box_len[a] * (dr[a] / self.box_len[a]).round();
                        }
                    }
                    let sigma = self.particles[i].radius + self.particles[k_].radius;
                    // depth > w needs |r| < σ(1 − w): a test without the root and the division
                    // (with room for round-off) before the depth itself.
                    if let Some(w) = worst {
                        let reach = sigma * (1.0 - w.2);
                        if reach <= 0.0 || dr.norm_squared() > reach * reach * (1.0 + 1e-9) {
                            continue;
                        }
                    }
                    let depth = (sigma - dr.norm()) / sigma;
                    if worst.is_none_or(|w| depth > w.2) {
                        worst = Some((self.meta[i].id as usize, self.meta[k_].id as usize, depth));
                    }
                }
            }
        }
        worst
    }
}

//! One sample of a running replica: the observables on the schedule, the profiles and order
//! parameters its scene has, and a snapshot when one is due.

use edmd_core::theory::haff_temperature_tau;
use edmd_core::{order_parameters, Counters, Engine, Vector, VirialMeter};

use super::bed_meter::BedMeter;
use super::{Series, Snapshot};
use crate::spec::{Replica, RuleSpec, Spec};

fn flat<const D: usize>(v: &[Vector<D>]) -> Vec<f64> {
    v.iter().flat_map(|x| x.iter().copied()).collect()
}

/// Angular velocities of rough grains, N × 1 (ω_z) in 2D and N × 3 in 3D; empty for smooth grains.
fn spins<const D: usize>(sim: &dyn Engine<D>) -> Vec<f64> {
    if !sim.rough() {
        return Vec::new();
    }
    let w = sim.spins();
    if D == 2 {
        w.iter().map(|s| s[2]).collect()
    } else {
        w.iter().flat_map(|s| s.iter().copied()).collect()
    }
}

/// The state now, in the original particle order.
pub(super) fn snapshot<const D: usize>(sim: &dyn Engine<D>) -> Snapshot {
    Snapshot {
        step: sim.counters().pair_collisions as i64,
        time: sim.time(),
        position: flat(&sim.positions()),
        velocity: flat(&sim.velocities()),
        angular_velocity: spins(sim),
        box_offset: sim.shear_offset(),
    }
}

/// Rotational degrees of freedom per particle: 1 for disks, 3 for spheres.
const fn rotational_dof(d: usize) -> f64 {
    if d == 2 {
        1.0
    } else {
        3.0
    }
}

/// What a replica samples, fixed for its run, and the virial meter running between samples.
pub(super) struct Sampler<'a> {
    r: &'a Replica,
    /// The initial temperature (Haff's law starts from it).
    t0: f64,
    n: f64,
    volume: f64,
    sides: Vec<f64>,
    /// Haff's law applies: one species of smooth grains, constant ε, free cooling.
    haff: bool,
    /// The order-parameter grid, where the classes apply (free cooling).
    grid: Option<usize>,
    /// Bins of the density profile along gravity (0 without gravity).
    pub(super) profile_bins: usize,
    cross_section: f64,
    masses: Vec<f64>,
    counts: Vec<usize>,
    species_of: &'a [usize],
    meter: Option<VirialMeter>,
    /// The engine's counters at the start of the run (the event counts start there).
    start: Counters,
    /// A shaken bed's uniform-time samples, and the radii they need.
    pub(super) bed: Option<BedMeter>,
    radii: Vec<f64>,
}

impl<'a> Sampler<'a> {
    pub(super) fn new<const D: usize>(
        spec: &Spec,
        r: &'a Replica,
        species_of: &'a [usize],
        sim: &dyn Engine<D>,
    ) -> Self {
        let sides = r.sides();
        let haff = matches!(spec.rule, RuleSpec::Constant {})
            && !r.rough()
            && r.species.is_none()
            && !r.driven_or_stratified()
            && r.wall_eps == 1.0;
        // Under gravity: the number density n(z) along the last axis in bins of about one diameter.
        let profile_bins = if r.gravity > 0.0 {
            (sides[D - 1].floor() as usize).max(1)
        } else {
            0
        };
        Sampler {
            r,
            t0: sim.temperature(),
            n: r.n as f64,
            volume: sim.box_len().iter().product::<f64>(),
            cross_section: sides[..D - 1].iter().product(),
            sides,
            haff,
            grid: spec
                .classify
                .as_ref()
                .filter(|_| !r.driven_or_stratified())
                .map(|c| c.grid_for(r.n, D)),
            profile_bins,
            masses: sim.masses(),
            counts: r.species_counts(),
            species_of,
            meter: None,
            start: *sim.counters(),
            bed: r
                .shaken()
                .then(|| BedMeter::new(r, profile_bins, sim.time())),
            radii: if r.shaken() { sim.radii() } else { Vec::new() },
        }
    }

    /// The initial temperature.
    pub(super) fn t0(&self) -> f64 {
        self.t0
    }

    /// What a checkpoint keeps: the initial temperature, the running virial meter, the counters
    /// at the start.
    pub(super) fn state(&self) -> (f64, Option<VirialMeter>, Counters) {
        (self.t0, self.meter, self.start)
    }

    /// Goes on from a checkpoint's [`Self::state`] and bed meter.
    pub(super) fn resume(
        &mut self,
        (t0, meter, start): (f64, Option<VirialMeter>, Counters),
        bed: Option<BedMeter>,
    ) {
        (self.t0, self.meter, self.start) = (t0, meter, start);
        if bed.is_some() {
            self.bed = bed;
        }
    }

    /// Records a shaken bed's uniform-time samples from the next one on.
    pub(super) fn start_bed(&mut self) {
        if let Some(b) = &mut self.bed {
            b.start();
        }
    }

    /// When the next uniform-time sample of a shaken bed is due (None elsewhere).
    pub(super) fn bed_time(&self) -> Option<f64> {
        self.bed.as_ref().map(BedMeter::next_time)
    }

    /// Takes the uniform-time sample due now (passes it before the window).
    pub(super) fn record_bed<const D: usize>(&mut self, sim: &dyn Engine<D>) {
        match &mut self.bed {
            Some(b) if b.recording() => {
                b.record(
                    &sim.positions(),
                    &sim.velocities(),
                    &self.masses,
                    &self.radii,
                );
            }
            Some(b) => b.skip(),
            None => {}
        }
    }

    /// Samples `sim` into `series`, with a snapshot into `snapshots` when `snapshot`.
    pub(super) fn sample<const D: usize>(
        &mut self,
        sim: &mut dyn Engine<D>,
        series: &mut Series,
        snapshots: &mut Vec<Snapshot>,
        snapshot: bool,
    ) {
        self.observables(&*sim, series);
        if self.profile_bins > 0 {
            series.density_profile.push(self.density_profile(&*sim));
        }
        if self.r.shaken() {
            let work = sim.counters().floor_work - self.start.floor_work;
            series.floor_work.push(work);
            let heights = sim.positions().iter().map(|x| x[D - 1]).sum::<f64>();
            series.centre_of_mass_height.push(heights / self.n);
        }
        if self.r.species.is_some() {
            series
                .species_temperature
                .push(self.species_temperatures(&*sim));
        }
        if self.r.sheared() {
            series.shear.sample(sim, &self.masses);
        }
        if sim.rough() {
            // T_rot = Σ I ω² / (d_rot N) (PHYSICS.md §6.5), beside the translational T.
            series
                .rotational_temperature
                .push(2.0 * sim.rotational_energy() / (rotational_dof(D) * self.n));
        }
        let tau = *series.tau.last().expect("observables sampled first");
        series.haff_temperature.push(if self.haff {
            haff_temperature_tau(D, self.r.eps, self.t0, tau)
        } else {
            f64::NAN
        });
        if let Some(grid) = self.grid {
            self.order_parameters(&*sim, grid, series);
        }
        if snapshot {
            snapshots.push(self::snapshot(&*sim));
        }
    }

    /// The scalar observables, and the compressibility over the interval since the last sample.
    fn observables<const D: usize>(&mut self, sim: &dyn Engine<D>, series: &mut Series) {
        let o = sim.observe();
        let z = match &self.meter {
            Some(m) if sim.time() > 0.0 => {
                let reading = m.read(sim);
                if reading.duration > 0.0 {
                    reading.z
                } else {
                    f64::NAN
                }
            }
            _ => f64::NAN,
        };
        self.meter = Some(VirialMeter::start(sim));
        series.step.push(o.pair_collisions as i64);
        series.time.push(o.time);
        series.tau.push(o.tau);
        series.temperature.push(o.temperature);
        series.ln_temperature.push(o.ln_temperature);
        series.kinetic_energy.push(o.kinetic_energy);
        series.kurtosis.push(o.kurtosis);
        series.wall_collisions.push(o.wall_collisions as i64);
        series.compressibility.push(z);
        series
            .pressure
            .push(z * self.n * o.temperature / self.volume);
        series
            .momentum_error
            .push(o.momentum.norm() / o.momentum_scale.max(f64::MIN_POSITIVE));
        series.events.push(&self.start, sim.counters());
    }

    /// The number density along gravity, in `profile_bins` bins.
    fn density_profile<const D: usize>(&self, sim: &dyn Engine<D>) -> Vec<f64> {
        let width = self.sides[D - 1] / self.profile_bins as f64;
        let mut n_z = vec![0.0; self.profile_bins];
        for x in sim.positions() {
            let b = ((x[D - 1] / width) as usize).min(self.profile_bins - 1);
            n_z[b] += 1.0 / (self.cross_section * width);
        }
        n_z
    }

    /// T_k = Σ_{a∈k} m v_a² / (d N_k), species in order.
    fn species_temperatures<const D: usize>(&self, sim: &dyn Engine<D>) -> Vec<f64> {
        let mut e = vec![0.0; self.counts.len()];
        for ((v, m), &k) in sim
            .peculiar_velocities()
            .iter()
            .zip(&self.masses)
            .zip(self.species_of)
        {
            e[k] += m * v.norm_squared();
        }
        e.iter()
            .zip(&self.counts)
            .map(|(e, &c)| e / (D as f64 * c as f64))
            .collect()
    }

    /// The classifier's order parameters on a grid of `grid` cells per axis.
    fn order_parameters<const D: usize>(
        &self,
        sim: &dyn Engine<D>,
        grid: usize,
        series: &mut Series,
    ) {
        let mut walls = [false; D];
        for (a, w) in walls.iter_mut().enumerate() {
            *w = sim.has_walls(a);
        }
        let op = order_parameters(
            &sim.positions(),
            &sim.velocities_internal(),
            &self.masses,
            sim.box_len(),
            walls,
            grid,
        );
        let os = &mut series.order;
        os.tau
            .push(*series.tau.last().expect("observables sampled first"));
        os.ln_temperature.push(
            *series
                .ln_temperature
                .last()
                .expect("observables sampled first"),
        );
        os.f_flow.push(op.f_flow);
        os.s_perp.push(op.s_perp);
        os.delta_rho2.push(op.delta_rho2);
        os.f_2x.push(op.f_2x);
        os.s_rho.push(op.s_rho);
    }
}

//! Running one replica: build the scene as a type and the rule (law, remedy, grains) as data, run to
//! the stop condition, and collect the observables and snapshots in memory.

use std::time::Instant;

use edmd_core::theory::haff_rate;
use edmd_core::{
    Boundary, Channel, Column, ConstantRestitution, Container, EdmdError, Law, LeesEdwards,
    Periodic, Remedy as CoreRemedy, Rule, ThesisRestitution, ThresholdRestitution, Walls,
};

use crate::classify::{critical_box_sides, Class, Classification, OrderSeries, Theory};
pub use crate::record::Status;
use crate::spec::{viscoelastic, BoundaryKind, Remedy, Replica, RuleSpec, Spec};

pub mod bare;
pub mod bed_meter;
pub mod checkpoint;
pub mod extend;
mod given;
pub mod noise;
mod points;
mod sampler;
mod scene_theory;
mod setup;
mod shaken;
mod shear;
mod simulate;
mod stall;
mod verdict;
use checkpoint::Checkpoints;
pub use scene_theory::{
    density_profile_theory, rotational_ratio_theory, shear_theory, species_temperature_theory,
    ProfileTheory,
};
pub use shaken::{shaken_state, ShakenState, ShakenThresholds, SHAKEN_THRESHOLDS};
pub use shear::{
    classify as classify_shear, contrast as density_contrast, profile_bins, ShearSeries,
};
use simulate::simulate;

/// Observables sampled at the points of the schedule.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Series {
    /// Pair collisions C (the H5MD `step`).
    pub step: Vec<i64>,
    /// Physical time.
    pub time: Vec<f64>,
    /// τ = C/N.
    pub tau: Vec<f64>,
    /// Granular temperature T (underflows to 0 below 1e-308; see `ln_temperature`).
    pub temperature: Vec<f64>,
    /// ln T, finite however deep the cooling.
    pub ln_temperature: Vec<f64>,
    /// Total kinetic energy.
    pub kinetic_energy: Vec<f64>,
    /// Speed kurtosis ⟨v⁴⟩/⟨v²⟩².
    pub kurtosis: Vec<f64>,
    /// Particle–wall collisions.
    pub wall_collisions: Vec<i64>,
    /// Compressibility factor Z = pV/(NT) from the collision virial since the previous sample
    /// (NaN at the first sample).
    pub compressibility: Vec<f64>,
    /// Pressure p = Z N T / V (NaN at the first sample).
    pub pressure: Vec<f64>,
    /// |Σ m v| / Σ m|v|: momentum conservation (round-off level in periodic boxes).
    pub momentum_error: Vec<f64>,
    /// Haff's law T0 exp(−k(ε) τ) (first Sonine order), for the constant-restitution rule only.
    pub haff_temperature: Vec<f64>,
    /// Rotational temperature Σ I ω² / (d_rot N) of rough grains (empty for smooth ones).
    pub rotational_temperature: Vec<f64>,
    /// Temperatures of the species of a mixture per sample, in species order (empty otherwise).
    pub species_temperature: Vec<Vec<f64>>,
    /// Under gravity: the number density in bins along the last axis per sample (empty otherwise).
    pub density_profile: Vec<Vec<f64>>,
    /// On a vibrating floor: the work it has done on the grains since the start of the replica's
    /// run (its power over an interval is the difference over the time between); empty elsewhere.
    pub floor_work: Vec<f64>,
    /// On a vibrating floor: the grains' mean height (empty elsewhere).
    pub centre_of_mass_height: Vec<f64>,
    /// Order parameters (empty unless the spec has a `classify` section).
    pub order: OrderSeries,
    /// The observables of a sheared replica (empty elsewhere).
    pub shear: ShearSeries,
    /// The engine's events by kind, counted from the start of the replica's run.
    pub events: EventSeries,
}

/// The engine's events by kind at each sample, counted from the start of the replica's run (after
/// the melt); the pair collisions are `Series::step`, the wall contacts `Series::wall_collisions`.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EventSeries {
    /// All events, pair collisions included.
    pub all: Vec<i64>,
    /// Stale pops: collision candidates whose partner had collided since.
    pub stale: Vec<i64>,
    /// Cell crossings (cell mode) or shell exits (list mode).
    pub crossings: Vec<i64>,
    /// System events (the shear shift of a sheared box).
    pub system: Vec<i64>,
    /// Calendar re-tunings by the event count.
    pub maintenances: Vec<i64>,
    /// Full re-predictions of every particle (after deep-cooling rescales and drift removals).
    pub restarts: Vec<i64>,
    /// Deep-cooling rescales of the velocity scale.
    pub rescales: Vec<i64>,
}

impl EventSeries {
    /// Appends the counts of `now` since `start`.
    pub(crate) fn push(&mut self, start: &edmd_core::Counters, now: &edmd_core::Counters) {
        let since = |f: fn(&edmd_core::Counters) -> u64| (f(now) - f(start)) as i64;
        self.all.push(since(|c| c.events));
        self.stale.push(since(|c| c.stale));
        self.crossings.push(since(|c| c.crossings));
        self.system.push(since(|c| c.system_events));
        self.maintenances.push(since(|c| c.maintenances));
        self.restarts.push(since(|c| c.restarts));
        self.rescales.push(since(|c| c.rescales));
    }

    /// The series by the names of the replica file's observables, in order.
    pub fn named(&self) -> [(&'static str, &[i64]); 7] {
        [
            ("events", &self.all),
            ("stale_events", &self.stale),
            ("crossings", &self.crossings),
            ("system_events", &self.system),
            ("maintenances", &self.maintenances),
            ("restarts", &self.restarts),
            ("rescales", &self.rescales),
        ]
    }
}

/// Positions and velocities at one instant, in the original particle order.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Snapshot {
    /// Pair collisions C.
    pub step: i64,
    /// Physical time.
    pub time: f64,
    /// Positions, N × D, row-major.
    pub position: Vec<f64>,
    /// Velocities, N × D, row-major.
    pub velocity: Vec<f64>,
    /// Angular velocities of rough grains, N × 1 (2D) or N × 3 (3D), row-major; empty when smooth.
    pub angular_velocity: Vec<f64>,
    /// Displacement along x of the images above the box (0 where the box is not sheared).
    pub box_offset: f64,
}

/// Everything a replica produced.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// How it ended.
    pub status: Status,
    /// Why (empty when done normally).
    pub message: String,
    /// Sampled observables.
    pub series: Series,
    /// Stored snapshots.
    pub snapshots: Vec<Snapshot>,
    /// Box sides.
    pub box_len: Vec<f64>,
    /// Bins of the density profile along the last axis (0 without gravity).
    pub profile_bins: usize,
    /// Particle radii.
    pub radius: Vec<f64>,
    /// Particle masses.
    pub mass: Vec<f64>,
    /// Species index of each particle of a mixture (empty otherwise).
    pub species: Vec<i64>,
    /// Initial temperature T0.
    pub t0: f64,
    /// Pair collisions run.
    pub collisions: u64,
    /// (time, τ) of a detected collapse.
    pub collapse: Option<(f64, f64)>,
    /// Wall-clock seconds spent simulating.
    pub wall_s: f64,
    /// Times the replica went on from a saved state (a checkpoint, or `edmd extend`).
    pub resumes: u64,
    /// The classifier's verdict (None unless the spec has a `classify` section).
    pub classification: Option<Classification>,
    /// Particles per cell of the order-parameter grid (NaN without classification).
    pub per_cell: f64,
    /// A shaken bed's uniform-time samples, summed up (None elsewhere or before they start).
    pub bed: Option<bed_meter::BedSummary>,
}

impl Outcome {
    fn failed(message: String) -> Outcome {
        Outcome {
            status: Status::Failed,
            message,
            series: Series::default(),
            snapshots: Vec::new(),
            box_len: Vec::new(),
            profile_bins: 0,
            radius: Vec::new(),
            mass: Vec::new(),
            species: Vec::new(),
            t0: f64::NAN,
            collisions: 0,
            collapse: None,
            wall_s: 0.0,
            resumes: 0,
            classification: None,
            per_cell: f64::NAN,
            bed: None,
        }
    }

    /// The last sample's τ, or 0.
    pub fn final_tau(&self) -> f64 {
        self.series.tau.last().copied().unwrap_or(0.0)
    }
}

/// Runs a replica. `progress` is called with the number of new pair collisions every so often.
pub fn run(spec: &Spec, r: &Replica, progress: &(dyn Fn(u64) + Sync)) -> Outcome {
    run_with(spec, r, progress, None).expect("without checkpoints nothing interrupts a replica")
}

/// [`run`], going on from the replica's checkpoint in `ckpt` if it has one and saving its state
/// there on the way; `None` when a signal interrupted it (its checkpoint written).
pub fn run_with(
    spec: &Spec,
    r: &Replica,
    progress: &(dyn Fn(u64) + Sync),
    ckpt: Option<&Checkpoints>,
) -> Option<Outcome> {
    let start = Instant::now();
    let result = match r.dim {
        2 => by_boundary::<2>(spec, r, progress, ckpt),
        3 => by_boundary::<3>(spec, r, progress, ckpt),
        d => Err(EdmdError::invalid("dim", d, "dimension must be 2 or 3")),
    };
    let mut outcome = match result {
        Ok(None) => return None,
        Ok(Some(o)) => o,
        Err(e) => Outcome::failed(e.to_string()),
    };
    // Added to the seconds of earlier runs, which the checkpoint kept.
    outcome.wall_s += start.elapsed().as_secs_f64();
    if spec.classify.is_some() && outcome.classification.is_none() {
        outcome.classification = Some(Classification {
            class: Class::Failed,
            shear_onset: f64::NAN,
            cluster_onset: f64::NAN,
            haff_deviation: Vec::new(),
            note: String::new(),
        });
    }
    Some(outcome)
}

/// The replica's collision rule: its law and remedy as data ([`Rule`]), the same for every scene.
fn rule(spec: &Spec, r: &Replica) -> Result<Rule, EdmdError> {
    let law: Law = match spec.rule {
        RuleSpec::Constant {} => ConstantRestitution::new(r.eps)?.into(),
        RuleSpec::Threshold { delta, eps_low } => {
            ThresholdRestitution::new(r.eps, eps_low, delta)?.into()
        }
        RuleSpec::Thesis { v0 } => ThesisRestitution::new(r.eps, v0)?.into(),
        RuleSpec::Viscoelastic { speed } => viscoelastic(r.eps, speed)?.into(),
    };
    if r.gravity > 0.0
        && !(matches!(spec.rule, RuleSpec::Constant {})
            && matches!(r.remedy, Remedy::None {} | Remedy::Tc { .. }))
    {
        // Checked by the spec; kept here for a replica built by hand.
        return Err(EdmdError::invalid(
            "gravity",
            r.gravity,
            "runs with rule constant and remedy none or tc only",
        ));
    }
    Rule::new(law).with_remedy(match r.remedy {
        Remedy::None {} => CoreRemedy::None,
        Remedy::Tc { tc } => CoreRemedy::Tc { tc },
        Remedy::Rotation { theta_max_deg } => CoreRemedy::Rotation {
            theta_max: theta_max_deg.to_radians(),
        },
    })
}

/// The scene's geometry as a type: the one choice, with the grains' kind, that the event loop is
/// compiled for.
fn by_boundary<const D: usize>(
    spec: &Spec,
    r: &Replica,
    progress: &(dyn Fn(u64) + Sync),
    ckpt: Option<&Checkpoints>,
) -> Result<Option<Outcome>, EdmdError> {
    let rule = rule(spec, r)?;
    if r.gravity > 0.0 {
        // Gravity pulls towards the floor of the last axis: walls there (checked in the spec).
        return match r.boundary {
            BoundaryKind::Walls => by_grain::<D, Container>(spec, r, rule, progress, ckpt),
            BoundaryKind::Channel => by_grain::<D, Column>(spec, r, rule, progress, ckpt),
            BoundaryKind::Periodic | BoundaryKind::LeesEdwards => Err(EdmdError::invalid(
                "gravity",
                r.gravity,
                "needs walls on the last axis",
            )),
        };
    }
    match r.boundary {
        BoundaryKind::Periodic => by_grain::<D, Periodic>(spec, r, rule, progress, ckpt),
        BoundaryKind::Walls => by_grain::<D, Walls>(spec, r, rule, progress, ckpt),
        BoundaryKind::Channel => by_grain::<D, Channel>(spec, r, rule, progress, ckpt),
        BoundaryKind::LeesEdwards => by_grain::<D, LeesEdwards>(spec, r, rule, progress, ckpt),
    }
}

/// The checks of building replica `r` that need no simulation (a lattice start's reach, the cell
/// grid of its box), so that `validate-spec` and `run` refuse what would fail at run time.
pub(crate) fn preflight(spec: &Spec, r: &Replica) -> Result<(), EdmdError> {
    fn scene<const D: usize>(spec: &Spec, r: &Replica) -> Result<(), EdmdError> {
        let p = setup::init_params::<D>(spec, r)?.0;
        match (r.boundary, r.gravity > 0.0) {
            (BoundaryKind::Periodic, _) => p.preflight::<Periodic>(),
            (BoundaryKind::LeesEdwards, _) => p.preflight::<LeesEdwards>(),
            (BoundaryKind::Walls, false) => p.preflight::<Walls>(),
            (BoundaryKind::Channel, false) => p.preflight::<Channel>(),
            (BoundaryKind::Walls, true) => p.preflight::<Container>(),
            (BoundaryKind::Channel, true) => p.preflight::<Column>(),
        }
    }
    let (amplitude, _) = r.floor_motion();
    let height = *r.sides().last().expect("a box has sides");
    if 2.0 * amplitude >= height {
        return Err(EdmdError::invalid(
            "shake_s",
            r.shake_s,
            format!(
                "the floor's stroke 2A = 2 S d/Gamma = {} must stay below the box's height {height}",
                2.0 * amplitude
            ),
        ));
    }
    let checked = match r.dim {
        2 => scene::<2>(spec, r),
        3 => scene::<3>(spec, r),
        d => Err(EdmdError::invalid("dim", d, "dimension must be 2 or 3")),
    };
    // What the engine finds wrong with a given configuration (an overlap, a particle outside the
    // box) names the file too.
    match (checked, &spec.init.from) {
        (Err(e), Some(from)) if !e.to_string().contains(&from.file) => {
            Err(EdmdError::invalid("init.from", &from.file, e.to_string()))
        }
        (checked, _) => checked,
    }
}

/// Smooth grains run the rule as it is; rough ones (β > −1) carry spin.
fn by_grain<const D: usize, B: Boundary>(
    spec: &Spec,
    r: &Replica,
    rule: Rule,
    progress: &(dyn Fn(u64) + Sync),
    ckpt: Option<&Checkpoints>,
) -> Result<Option<Outcome>, EdmdError> {
    if r.rough() {
        simulate::<D, B, _>(spec, r, rule.rough(r.beta, r.inertia)?, progress, ckpt)
    } else {
        simulate::<D, B, _>(spec, r, rule, progress, ckpt)
    }
}

/// What linear theory says about a replica's box (critical sizes halved when any axis has walls).
pub fn theory(spec: &Spec, r: &Replica) -> Theory {
    let periodic = r.boundary.periodic();
    let (lp, lq) = critical_box_sides(r.dim, r.eps, r.phi(), periodic);
    let grid = spec
        .classify
        .as_ref()
        .map(|c| c.grid_for(r.n, r.dim))
        .unwrap_or(1);
    Theory {
        // Smooth grains only: for rough ones the classifier fits the cooling rate instead.
        haff_rate: (matches!(spec.rule, RuleSpec::Constant {})
            && !r.rough()
            && r.species.is_none())
        .then(|| haff_rate(r.dim, r.eps)),
        l_over_l_perp: r.sides().into_iter().fold(0.0, f64::max) / lp,
        l_over_l_par: r.sides().into_iter().fold(0.0, f64::max) / lq,
        per_cell: r.n as f64 / (grid as f64).powi(r.dim as i32),
    }
}

//! The replica record: one row of the sweep index, and how a replica ended ([`Status`]).
//!
//! The field list is written once, in [`record_fields!`]: it declares the struct, whose serde
//! derive gives the columns of `summary.csv` (csv crate) and the objects of `summary.json`, and the
//! columns of the `replicas` group of `sweep.h5`, in the same order.

use std::fmt;
use std::str::FromStr;

use hdf5::types::VarLenUnicode;
use serde::{Deserialize, Serialize};

use crate::spec::Replica;

/// How a replica ended, or that it has not run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Reached its stop condition.
    Done,
    /// Inelastic collapse was detected; the data up to the collapse are kept.
    Collapsed,
    /// Stopped before its stop condition without a collapse: pair collisions ceased (a
    /// wall-collision cascade on a dissipating floor, lanes that stream past each other, no events
    /// left). The message says which; the data up to the stall are kept.
    Stalled,
    /// Could not be set up (e.g. a start that cannot reach the density).
    Failed,
    /// No replica file yet (index records only; never written into a replica file).
    Missing,
    /// A file under the final name that cannot be used (index records only: `edmd run` moves it
    /// aside as `.corrupt` and redoes the replica).
    Corrupt,
}

impl Status {
    /// Every status, in the order of the tables.
    pub const ALL: [Status; 6] = [
        Status::Done,
        Status::Collapsed,
        Status::Stalled,
        Status::Failed,
        Status::Missing,
        Status::Corrupt,
    ];

    /// The name used in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            Status::Done => "done",
            Status::Collapsed => "collapsed",
            Status::Stalled => "stalled",
            Status::Failed => "failed",
            Status::Missing => "missing",
            Status::Corrupt => "corrupt",
        }
    }

    /// True for a replica with a whole file (done, collapsed, stalled or failed).
    pub fn has_file(self) -> bool {
        matches!(
            self,
            Status::Done | Status::Collapsed | Status::Stalled | Status::Failed
        )
    }

    /// True for a replica that ran and has data to aggregate (done, collapsed or stalled).
    pub fn has_data(self) -> bool {
        matches!(self, Status::Done | Status::Collapsed | Status::Stalled)
    }

    /// True for a replica that ran but did not reach its stop (exit code 2 of `run` and `status`).
    pub fn ended_early(self) -> bool {
        matches!(self, Status::Collapsed | Status::Stalled)
    }
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Status {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Status::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| format!("unknown status {s:?}"))
    }
}

/// A value that can fill a column of the HDF5 index.
pub trait IndexValue {
    /// The HDF5 element type of the column.
    type H5: hdf5::H5Type + Clone;
    /// The element.
    fn to_h5(&self) -> Self::H5;
}

macro_rules! index_value {
    ($($t:ty => $h:ty),*) => {
        $(impl IndexValue for $t {
            type H5 = $h;
            fn to_h5(&self) -> $h {
                *self as $h
            }
        })*
    };
}
index_value!(usize => i64, u32 => i64, u64 => u64, f64 => f64);

fn varlen(s: &str) -> VarLenUnicode {
    // Interior NUL bytes are the only thing VarLenUnicode rejects; they never occur in our strings.
    s.replace('\0', " ").parse().expect("string without NUL")
}

impl IndexValue for String {
    type H5 = VarLenUnicode;
    fn to_h5(&self) -> VarLenUnicode {
        varlen(self)
    }
}

impl IndexValue for Status {
    type H5 = VarLenUnicode;
    fn to_h5(&self) -> VarLenUnicode {
        varlen(self.name())
    }
}

/// Declares [`Record`] and [`Record::write_columns`] from one list of fields.
macro_rules! record_fields {
    ($($(#[doc = $doc:expr])* $field:ident: $ty:ty,)*) => {
        /// One row of the sweep index: a replica's parameters, status and final values.
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        pub struct Record {
            $($(#[doc = $doc])* pub $field: $ty,)*
        }

        impl Record {
            /// Column names, in the order of `summary.csv`.
            pub const COLUMNS: &'static [&'static str] = &[$(stringify!($field)),*];

            /// Writes one dataset per field into `group` (the `replicas` group of `sweep.h5`).
            pub fn write_columns(group: &hdf5::Group, records: &[Record]) -> hdf5::Result<()> {
                $(
                    let values: Vec<_> = records.iter().map(|r| r.$field.to_h5()).collect();
                    group
                        .new_dataset_builder()
                        .with_data(&ndarray::Array1::from(values))
                        .create(stringify!($field))?;
                )*
                Ok(())
            }
        }
    };
}

record_fields! {
    /// Replica index.
    index: usize,
    /// File name relative to `OUT/replicas/` (empty when missing).
    file: String,
    /// How the replica ended, or `missing`.
    status: Status,
    /// Why the replica failed or stopped early.
    message: String,
    /// Dimension.
    dim: usize,
    /// Boundary name.
    boundary: String,
    /// Restitution.
    eps: f64,
    /// Tangential restitution (−1: smooth).
    beta: f64,
    /// The mixture as `fraction:diameter:mass` per species joined by `+` (empty: one species).
    species: String,
    /// Gravity (0: none).
    gravity: f64,
    /// Shear rate of a Lees–Edwards box (0: none).
    shear_rate: f64,
    /// Wall restitution (1: elastic).
    wall_eps: f64,
    /// Temperature of a thermal floor (0: none).
    floor_temperature: f64,
    /// The white-noise thermostat's strength ξ₀² (0: none).
    white_noise: f64,
    /// A vibrating floor's shaking strength S = A²ω²/(g d) (0: a floor that stands still).
    shake_s: f64,
    /// A vibrating floor's peak acceleration Γ = Aω²/g (0: a floor that stands still).
    shake_gamma: f64,
    /// A shaken bed's state: solid, bouncing_bed, leidenfrost, gas or undetermined (PHYSICS.md
    /// §8.4; empty for a still floor).
    shaken_state: String,
    /// Relative box sides joined by `x` (empty: square or cubic).
    aspect: String,
    /// Packing fraction.
    phi: f64,
    /// Box side.
    box_side: f64,
    /// Particle number.
    n: usize,
    /// Seed number within the grid point.
    seed_index: u32,
    /// Seed of the initial state.
    seed: u64,
    /// Remedy label.
    remedy: String,
    /// τ at the end.
    tau: f64,
    /// Physical time at the end.
    time: f64,
    /// ln(T/T0) at the end.
    ln_temperature_ratio: f64,
    /// Pair collisions run.
    collisions: u64,
    /// τ of a detected collapse (NaN if none).
    collapse_tau: f64,
    /// Regime (`kinetic`, `shearing`, `clustering`; `homogeneous`, `inhomogeneous` for a sheared box;
    /// `collapsed`, `stalled`, `failed`, `not_applicable`), or `unclassified`.
    class: String,
    /// First τ of the shearing predicate (NaN if never or unclassified).
    shear_onset_tau: f64,
    /// First τ of the clustering predicate (NaN if never or unclassified).
    cluster_onset_tau: f64,
    /// f_flow at the end.
    f_flow: f64,
    /// S⊥(k₁) at the end.
    s_perp: f64,
    /// δ²ρ − δ²ρ(0) at the end.
    delta_rho2: f64,
    /// Wall-clock seconds of the replica.
    wall_s: f64,
    /// Times the replica went on from a saved state: a checkpoint after a stop, or its final state
    /// by `edmd extend` (0: one uninterrupted run).
    resumes: u64,
}

impl Record {
    /// The record of a replica without a file.
    pub fn missing(r: &Replica) -> Record {
        Record {
            index: r.index,
            file: String::new(),
            status: Status::Missing,
            message: String::new(),
            dim: r.dim,
            boundary: r.boundary.name().into(),
            eps: r.eps,
            beta: r.beta,
            species: r
                .species
                .as_ref()
                .map(|m| crate::spec::species_label(m, r.dim))
                .unwrap_or_default(),
            gravity: r.gravity,
            shear_rate: r.shear_rate,
            wall_eps: r.wall_eps,
            floor_temperature: r.floor_temperature,
            white_noise: r.white_noise,
            shake_s: r.shake_s,
            shake_gamma: r.shake_gamma,
            shaken_state: String::new(),
            aspect: r
                .aspect
                .as_ref()
                .map(|a| crate::spec::aspect_label(a))
                .unwrap_or_default(),
            phi: r.phi(),
            box_side: r.side(),
            n: r.n,
            seed_index: r.seed_index,
            seed: r.seed,
            remedy: r.remedy.label(),
            tau: f64::NAN,
            time: f64::NAN,
            ln_temperature_ratio: f64::NAN,
            collisions: 0,
            collapse_tau: f64::NAN,
            class: "missing".into(),
            shear_onset_tau: f64::NAN,
            cluster_onset_tau: f64::NAN,
            f_flow: f64::NAN,
            s_perp: f64::NAN,
            delta_rho2: f64::NAN,
            wall_s: f64::NAN,
            resumes: 0,
        }
    }

    /// `summary.csv`: a header line of [`Record::COLUMNS`], then one line per record.
    pub fn to_csv(records: &[Record]) -> String {
        let mut w = csv::Writer::from_writer(Vec::new());
        if records.is_empty() {
            w.write_record(Record::COLUMNS).expect("write to memory");
        }
        for r in records {
            w.serialize(r).expect("records serialise");
        }
        String::from_utf8(w.into_inner().expect("write to memory")).expect("UTF-8")
    }
}

//! H5MD 1.1 replica files: writing them (under a temporary name, renamed when complete) and reading
//! back the summary record the sweep index is built from.
//!
//! Layout (see `docs/output.md`):
//!
//! ```text
//! /h5md                      version = [1, 1]; author/name; creator/name, creator/version
//! /particles/gas/box         dimension, boundary ("periodic"/"none" per axis); edges [D]
//! /particles/gas/position    step [k] (pair collisions), time [k], value [k, N, D]
//! /particles/gas/velocity    step [k], time [k], value [k, N, D]
//! /particles/gas/angular_velocity  step [k], time [k], value [k, N, 1 (2D) or 3]  (rough grains)
//! /particles/gas/mass        [N];  /particles/gas/radius [N]
//! /particles/gas/species     [N] species index; /particles/gas/diameter [N]   (mixtures)
//! /observables/<name>        step [s], time [s], value [s]   (temperature, ln_temperature, tau, …)
//! /observables/species_temperature  step [s], time [s], value [s, S]   (mixtures)
//! /observables/density_profile  step [s], time [s], value [s, B], position [B]; theory [B] (gravity)
//! /observables/rotational_ratio_theory  step [s], time [s], value [s]   (rough grains)
//! /observables/floor_work, centre_of_mass_height  step [s], time [s], value [s]   (vibrating floor)
//! /observables/pressure_tensor, pressure_tensor_kinetic  step [s], time [s], value [s, D, D]
//! /observables/collision_frequency, dissipation_rate, box_offset  value [s]   (Lees–Edwards)
//! /observables/velocity_profile, density_profile_y, density_profile_x  value [s, B], position [B]
//! /particles/gas/box/offset  step [k], time [k], value [k]: the images' x offset (Lees–Edwards)
//! /bed/height, packing, temperature [Z]; phase_packing [16, Z]; vertical_velocity [Z, X]
//!                            a shaken bed's uniform-time profiles (replica::bed_meter)
//! /parameters                schema_version, spec (JSON), spec_hash, engine_version, git_commit,
//!                            replica parameters, seed, status, message and final values as attributes;
//!                            /parameters/spec holds every spec field as an attribute.
//! ```

use std::path::Path;

use hdf5::types::VarLenUnicode;
use hdf5::{Group, Location};

mod parameters;
mod read;
mod scene;
use ndarray::{Array1, Array2, Array3};
pub use read::{check_file, read_record, read_snapshots};

use crate::record::Status;
use crate::replica::{Outcome, Snapshot};
use crate::spec::{Replica, Spec};
use crate::SweepError;

/// Version of the layout of files written by edmd; readers check it.
pub const SCHEMA_VERSION: i64 = 1;

/// The commit the binary was built from ("unknown" outside a git checkout).
pub const GIT_COMMIT: &str = env!("EDMD_GIT_COMMIT");

fn vlu(s: &str) -> VarLenUnicode {
    // Interior NUL bytes are the only thing VarLenUnicode rejects; they never occur in our strings.
    s.replace('\0', " ").parse().expect("string without NUL")
}

pub(crate) fn attr_str(loc: &Location, name: &str, value: &str) -> hdf5::Result<()> {
    loc.new_attr::<VarLenUnicode>()
        .shape(())
        .create(name)?
        .write_scalar(&vlu(value))
}

pub(crate) fn attr_f64(loc: &Location, name: &str, value: f64) -> hdf5::Result<()> {
    loc.new_attr::<f64>()
        .shape(())
        .create(name)?
        .write_scalar(&value)
}

pub(crate) fn attr_i64(loc: &Location, name: &str, value: i64) -> hdf5::Result<()> {
    loc.new_attr::<i64>()
        .shape(())
        .create(name)?
        .write_scalar(&value)
}

fn attr_u64(loc: &Location, name: &str, value: u64) -> hdf5::Result<()> {
    loc.new_attr::<u64>()
        .shape(())
        .create(name)?
        .write_scalar(&value)
}

/// Writes every leaf of a JSON tree as an attribute named by its dotted path.
fn json_attrs(loc: &Location, prefix: &str, v: &serde_json::Value) -> hdf5::Result<()> {
    use serde_json::Value;
    match v {
        Value::Object(map) => {
            for (k, child) in map {
                let name = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                json_attrs(loc, &name, child)?;
            }
            Ok(())
        }
        Value::Null => attr_str(loc, prefix, "null"),
        Value::Bool(b) => attr_i64(loc, prefix, *b as i64),
        Value::Number(x) => match (x.as_i64(), x.as_f64()) {
            (Some(i), _) => attr_i64(loc, prefix, i),
            (None, Some(f)) => attr_f64(loc, prefix, f),
            _ => attr_str(loc, prefix, &x.to_string()),
        },
        Value::String(s) => attr_str(loc, prefix, s),
        Value::Array(items) => {
            let numbers: Option<Vec<f64>> = items.iter().map(|x| x.as_f64()).collect();
            match numbers {
                Some(xs) if !xs.is_empty() => loc
                    .new_attr::<f64>()
                    .shape(xs.len())
                    .create(prefix)?
                    .write(&xs[..]),
                _ => attr_str(loc, prefix, &v.to_string()),
            }
        }
    }
}

struct Writer {
    compression: u8,
}

impl Writer {
    fn series_1d<T: hdf5::H5Type + Copy>(
        &self,
        g: &Group,
        name: &str,
        data: &[T],
    ) -> hdf5::Result<()> {
        let arr = Array1::from(data.to_vec());
        let b = g
            .new_dataset_builder()
            .with_data(&arr)
            .chunk(data.len().max(1));
        if self.compression > 0 {
            b.deflate(self.compression).create(name)?;
        } else {
            b.create(name)?;
        }
        Ok(())
    }

    /// An H5MD time-dependent element: `step`, `time` and `value` [k].
    fn observable(
        &self,
        parent: &Group,
        name: &str,
        step: &[i64],
        time: &[f64],
        value: &[f64],
    ) -> hdf5::Result<()> {
        let g = parent.create_group(name)?;
        self.series_1d(&g, "step", step)?;
        self.series_1d(&g, "time", time)?;
        self.series_1d(&g, "value", value)
    }

    /// An H5MD time-dependent element with a row per sample: `value` [k, columns]; returns its group.
    fn observable_2d(
        &self,
        parent: &Group,
        name: &str,
        step: &[i64],
        time: &[f64],
        rows: &[Vec<f64>],
    ) -> hdf5::Result<Group> {
        let g = parent.create_group(name)?;
        self.series_1d(&g, "step", step)?;
        self.series_1d(&g, "time", time)?;
        let columns = rows.first().map_or(0, Vec::len);
        let flat: Vec<f64> = rows.iter().flatten().copied().collect();
        let arr = Array2::from_shape_vec((rows.len(), columns), flat).expect("rows of one length");
        g.new_dataset_builder().with_data(&arr).create("value")?;
        Ok(g)
    }

    /// An H5MD time-dependent per-particle element: `value` [k, N, D].
    fn trajectory(
        &self,
        parent: &Group,
        name: &str,
        snaps: &[Snapshot],
        n: usize,
        d: usize,
        pick: impl Fn(&Snapshot) -> &[f64],
    ) -> hdf5::Result<()> {
        let g = parent.create_group(name)?;
        let step: Vec<i64> = snaps.iter().map(|s| s.step).collect();
        let time: Vec<f64> = snaps.iter().map(|s| s.time).collect();
        self.series_1d(&g, "step", &step)?;
        self.series_1d(&g, "time", &time)?;
        let flat: Vec<f64> = snaps.iter().flat_map(|s| pick(s).iter().copied()).collect();
        let arr = Array3::from_shape_vec((snaps.len(), n, d), flat).expect("snapshot shape");
        let b = g.new_dataset_builder().with_data(&arr).chunk((1, n, d));
        if self.compression > 0 {
            b.shuffle().deflate(self.compression).create("value")?;
        } else {
            b.create("value")?;
        }
        Ok(())
    }
}

/// Writes a replica's file to `path.part`; once it is written, flushed, closed, synced to disk and
/// read back whole ([`check_file`]), renames it to `path` and syncs the directory. On any error the
/// `.part` file is removed and nothing appears under the final name.
pub fn write_replica(
    path: &Path,
    spec: &Spec,
    r: &Replica,
    out: &Outcome,
) -> Result<(), SweepError> {
    let part = path.with_extension("h5.part");
    let result = finish_replica(path, &part, spec, r, out);
    if result.is_err() {
        let _ = std::fs::remove_file(&part);
    }
    result
}

fn finish_replica(
    path: &Path,
    part: &Path,
    spec: &Spec,
    r: &Replica,
    out: &Outcome,
) -> Result<(), SweepError> {
    // Made by us, as a regular file (never through a link), before HDF5 truncates it.
    crate::files::create_fresh(part)?;
    let file = hdf5::File::create(part).map_err(|e| SweepError::hdf5(part, e))?;
    // Every group and dataset is closed when write_file returns, so that flush and close below
    // report the errors of the last writes (a close with objects still open is deferred by HDF5,
    // and its errors are lost).
    write_file(&file, spec, r, out)
        .and_then(|_| file.flush())
        .and_then(|_| file.close())
        .map_err(|e| SweepError::hdf5(part, e))?;
    std::fs::File::open(part)
        .and_then(|f| f.sync_all())
        .map_err(|e| SweepError::io("cannot sync", part, e))?;
    check_file(part, &spec.hash(), r.index).map_err(|reason| {
        SweepError::Output(format!(
            "{}: written but unreadable: {reason}",
            part.display()
        ))
    })?;
    std::fs::rename(part, path).map_err(|e| SweepError::io("cannot rename", part, e))?;
    if let Some(dir) = path.parent() {
        std::fs::File::open(dir)
            .and_then(|d| d.sync_all())
            .map_err(|e| SweepError::io("cannot sync", dir, e))?;
    }
    Ok(())
}

fn write_file(file: &hdf5::File, spec: &Spec, r: &Replica, out: &Outcome) -> hdf5::Result<()> {
    let w = Writer {
        compression: spec.output.compression,
    };
    write_h5md(file, spec)?;
    parameters::write(&file.create_group("parameters")?, spec, r, out)?;
    if out.status == Status::Failed {
        return Ok(());
    }
    write_particles(&w, file, r, out)?;
    scene::bed_group(file, out.bed.as_ref())?;
    write_observables(&w, &file.create_group("observables")?, spec, r, out)
}

/// The H5MD metadata: version, author and creator.
fn write_h5md(file: &hdf5::File, spec: &Spec) -> hdf5::Result<()> {
    let h5md = file.create_group("h5md")?;
    h5md.new_attr::<i32>()
        .shape(2)
        .create("version")?
        .write(&[1, 1][..])?;
    let author = h5md.create_group("author")?;
    attr_str(&author, "name", &spec.output.author)?;
    let creator = h5md.create_group("creator")?;
    attr_str(&creator, "name", "edmd")?;
    attr_str(&creator, "version", env!("CARGO_PKG_VERSION"))?;

    Ok(())
}

/// The particles: box, masses, radii, species, and the snapshots' trajectories.
fn write_particles(w: &Writer, file: &hdf5::File, r: &Replica, out: &Outcome) -> hdf5::Result<()> {
    let d = r.dim;
    let gas = file.create_group("particles")?.create_group("gas")?;
    let bx = gas.create_group("box")?;
    attr_i64(&bx, "dimension", d as i64)?;
    let boundary: Vec<VarLenUnicode> = r.boundary.h5md_boundary(d).iter().map(|s| vlu(s)).collect();
    bx.new_attr::<VarLenUnicode>()
        .shape(d)
        .create("boundary")?
        .write(&boundary[..])?;
    bx.new_dataset_builder()
        .with_data(&Array1::from(out.box_len.clone()))
        .create("edges")?;
    gas.new_dataset_builder()
        .with_data(&Array1::from(out.mass.clone()))
        .create("mass")?;
    gas.new_dataset_builder()
        .with_data(&Array1::from(out.radius.clone()))
        .create("radius")?;
    if !out.species.is_empty() {
        gas.new_dataset_builder()
            .with_data(&Array1::from(out.species.clone()))
            .create("species")?;
        let diameter: Vec<f64> = out.radius.iter().map(|r| 2.0 * r).collect();
        gas.new_dataset_builder()
            .with_data(&Array1::from(diameter))
            .create("diameter")?;
    }
    if !out.snapshots.is_empty() {
        w.trajectory(&gas, "position", &out.snapshots, r.n, d, |s| &s.position)?;
        w.trajectory(&gas, "velocity", &out.snapshots, r.n, d, |s| &s.velocity)?;
        scene::shear_offsets(w, &bx, r, &out.snapshots)?;
        if r.rough() {
            // ω_z of disks, (N, 1); ω of spheres, (N, 3).
            let width = if d == 2 { 1 } else { 3 };
            w.trajectory(&gas, "angular_velocity", &out.snapshots, r.n, width, |s| {
                &s.angular_velocity
            })?;
        }
    }

    Ok(())
}

/// The observables sampled on the schedule, each with its step and time.
fn write_observables(
    w: &Writer,
    obs: &Group,
    spec: &Spec,
    r: &Replica,
    out: &Outcome,
) -> hdf5::Result<()> {
    let s = &out.series;
    let columns: [(&str, &[f64]); 9] = [
        ("tau", &s.tau),
        ("temperature", &s.temperature),
        ("ln_temperature", &s.ln_temperature),
        ("kinetic_energy", &s.kinetic_energy),
        ("kurtosis", &s.kurtosis),
        ("compressibility", &s.compressibility),
        ("pressure", &s.pressure),
        ("momentum_error", &s.momentum_error),
        ("haff_temperature", &s.haff_temperature),
    ];
    for (name, values) in columns {
        w.observable(obs, name, &s.step, &s.time, values)?;
    }
    if r.rough() && s.rotational_temperature.len() == s.step.len() {
        w.observable(
            obs,
            "rotational_temperature",
            &s.step,
            &s.time,
            &s.rotational_temperature,
        )?;
    }
    // A vibrating floor's work since the start and the grains' mean height (PHYSICS.md §8.3).
    for (name, values) in [
        ("floor_work", &s.floor_work),
        ("centre_of_mass_height", &s.centre_of_mass_height),
    ] {
        if !values.is_empty() && values.len() == s.step.len() {
            w.observable(obs, name, &s.step, &s.time, values)?;
        }
    }
    if !s.species_temperature.is_empty() && s.species_temperature.len() == s.step.len() {
        w.observable_2d(
            obs,
            "species_temperature",
            &s.step,
            &s.time,
            &s.species_temperature,
        )?;
    }
    if out.profile_bins > 0 && s.density_profile.len() == s.step.len() {
        // n(z) per sample; `position` holds the bin centres along the last axis, `theory` the
        // barometric profile of an elastic column (PHYSICS.md §1.4).
        let bins = out.profile_bins;
        let g = w.observable_2d(obs, "density_profile", &s.step, &s.time, &s.density_profile)?;
        let height = out.box_len.last().copied().unwrap_or(0.0);
        let centres: Vec<f64> = (0..bins)
            .map(|b| (b as f64 + 0.5) * height / bins as f64)
            .collect();
        g.new_dataset_builder()
            .with_data(&Array1::from(centres))
            .create("position")?;
        scene::profile_theory(&g, r, s, bins)?;
    }
    scene::rotational_observables(w, obs, spec, r, s)?;
    scene::shear_observables(w, obs, r, s, &out.box_len)?;
    let collisions: Vec<f64> = s.step.iter().map(|&c| c as f64).collect();
    w.observable(obs, "collisions", &s.step, &s.time, &collisions)?;
    let walls: Vec<f64> = s.wall_collisions.iter().map(|&c| c as f64).collect();
    w.observable(obs, "wall_collisions", &s.step, &s.time, &walls)?;
    for (name, counts) in s.events.named() {
        let values: Vec<f64> = counts.iter().map(|&c| c as f64).collect();
        w.observable(obs, name, &s.step, &s.time, &values)?;
    }
    if let Some(c) = &out.classification {
        let o = &s.order;
        let order: [(&str, &[f64]); 6] = [
            ("f_flow", &o.f_flow),
            ("s_perp", &o.s_perp),
            ("delta_rho2", &o.delta_rho2),
            ("f_2x", &o.f_2x),
            ("s_rho", &o.s_rho),
            ("haff_deviation", &c.haff_deviation),
        ];
        for (name, values) in order {
            if values.len() == s.step.len() {
                w.observable(obs, name, &s.step, &s.time, values)?;
            }
        }
    }
    Ok(())
}

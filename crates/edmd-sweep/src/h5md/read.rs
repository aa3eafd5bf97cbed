//! Reading replica files back: the index record, and whether a final file is whole.

use std::path::Path;

use hdf5::types::VarLenUnicode;
use hdf5::Group;

use super::SCHEMA_VERSION;
use crate::record::{Record, Status};
use crate::SweepError;

/// Checks that a replica file is whole: it opens as HDF5, holds this schema and spec hash and the
/// replica's index, and (unless the replica failed) its particle and observable datasets, whose last
/// temperature value reads back. Returns the record, or why the file is unusable.
pub fn check_file(path: &Path, spec_hash: &str, index: usize) -> Result<Record, String> {
    let rec = read_record(path, spec_hash).map_err(|e| e.chain())?;
    if rec.index != index {
        return Err(format!("holds replica {} instead of {index}", rec.index));
    }
    if rec.status == Status::Failed {
        return Ok(rec);
    }
    let datasets = (|| -> hdf5::Result<Option<String>> {
        let file = hdf5::File::open(path)?;
        for name in [
            "particles/gas/box/edges",
            "particles/gas/mass",
            "particles/gas/radius",
            "observables/tau/value",
            "observables/temperature/value",
        ] {
            if !file.link_exists(name) {
                return Ok(Some(format!("dataset /{name} is missing")));
            }
        }
        let tau = file.dataset("observables/tau/value")?;
        let temperature = file.dataset("observables/temperature/value")?;
        let k = temperature.size();
        if tau.size() != k || k == 0 {
            return Ok(Some(format!(
                "observables/temperature has {k} values, tau {}",
                tau.size()
            )));
        }
        let last: Vec<f64> = temperature.read_slice_1d(k - 1..k)?.to_vec();
        if last.len() != 1 {
            return Ok(Some("the last temperature does not read back".into()));
        }
        Ok(None)
    })();
    match datasets {
        Ok(None) => Ok(rec),
        Ok(Some(reason)) => Err(reason),
        Err(e) => Err(format!("{e}")),
    }
}

fn read_str(g: &Group, name: &str) -> hdf5::Result<String> {
    Ok(g.attr(name)?
        .read_scalar::<VarLenUnicode>()?
        .as_str()
        .to_string())
}

fn read_f64(g: &Group, name: &str) -> hdf5::Result<f64> {
    g.attr(name)?.read_scalar::<f64>()
}

fn read_i64(g: &Group, name: &str) -> hdf5::Result<i64> {
    g.attr(name)?.read_scalar::<i64>()
}

/// Reads the index record of a replica file, checking its schema version and spec hash.
pub fn read_record(path: &Path, spec_hash: &str) -> Result<Record, SweepError> {
    let err = |e: hdf5::Error| SweepError::hdf5(path, e);
    let file = hdf5::File::open(path).map_err(err)?;
    let p = file.group("parameters").map_err(err)?;
    let version = read_i64(&p, "schema_version").map_err(err)?;
    if version != SCHEMA_VERSION {
        return Err(SweepError::Output(format!(
            "{}: schema_version {version}, this edmd reads {SCHEMA_VERSION}",
            path.display()
        )));
    }
    let hash = read_str(&p, "spec_hash").map_err(err)?;
    if hash != spec_hash {
        return Err(SweepError::Output(format!(
            "{}: written by a different spec (hash {hash}, expected {spec_hash})",
            path.display()
        )));
    }
    let rec = (|| -> hdf5::Result<Record> {
        Ok(Record {
            index: read_i64(&p, "index")? as usize,
            file: path
                .file_name()
                .map(|f| f.to_string_lossy().into_owned())
                .unwrap_or_default(),
            status: Status::Missing,
            message: read_str(&p, "message")?,
            dim: read_i64(&p, "dim")? as usize,
            boundary: read_str(&p, "boundary")?,
            eps: read_f64(&p, "eps")?,
            // Files written before rough grains have no beta: smooth.
            beta: if p.attr("beta").is_ok() {
                read_f64(&p, "beta")?
            } else {
                -1.0
            },
            // One species unless the file names a mixture.
            species: if p.attr("species").is_ok() {
                let dim = read_i64(&p, "dim")? as usize;
                serde_json::from_str::<Vec<crate::spec::Species>>(&read_str(&p, "species")?)
                    .map(|m| crate::spec::species_label(&m, dim))
                    .unwrap_or_default()
            } else {
                String::new()
            },
            // Files written before these scenes: none of them.
            gravity: read_or(&p, "gravity", 0.0)?,
            shear_rate: read_or(&p, "shear_rate", 0.0)?,
            wall_eps: read_or(&p, "wall_eps", 1.0)?,
            floor_temperature: read_or(&p, "floor_temperature", 0.0)?,
            white_noise: read_or(&p, "white_noise", 0.0)?,
            shake_s: read_or(&p, "shake_s", 0.0)?,
            shake_gamma: read_or(&p, "shake_gamma", 0.0)?,
            shaken_state: if p.attr("shaken_state").is_ok() {
                read_str(&p, "shaken_state")?
            } else {
                String::new()
            },
            aspect: aspect_of(&p)?,
            phi: read_f64(&p, "phi")?,
            box_side: read_f64(&p, "box_side")?,
            n: read_i64(&p, "n")? as usize,
            seed_index: read_i64(&p, "seed_index")? as u32,
            seed: p.attr("seed")?.read_scalar::<u64>()?,
            remedy: read_str(&p, "remedy")?,
            tau: read_f64(&p, "final_tau")?,
            time: read_f64(&p, "final_time")?,
            ln_temperature_ratio: read_f64(&p, "final_ln_temperature_ratio")?,
            collisions: p.attr("collisions")?.read_scalar::<u64>()?,
            collapse_tau: read_f64(&p, "collapse_tau")?,
            wall_s: read_f64(&p, "wall_s")?,
            // Files written before checkpoints: one run.
            resumes: if p.attr("resumes").is_ok() {
                p.attr("resumes")?.read_scalar::<u64>()?
            } else {
                0
            },
            class: read_str(&p, "class")?,
            shear_onset_tau: read_f64(&p, "shear_onset_tau")?,
            cluster_onset_tau: read_f64(&p, "cluster_onset_tau")?,
            f_flow: read_f64(&p, "final_f_flow")?,
            s_perp: read_f64(&p, "final_s_perp")?,
            delta_rho2: read_f64(&p, "final_delta_rho2")?,
        })
    })()
    .map_err(err)?;
    let status = read_str(&p, "status").map_err(err)?;
    match status.parse::<Status>() {
        Ok(s) if s != Status::Missing => Ok(Record { status: s, ..rec }),
        _ => Err(SweepError::Output(format!(
            "{}: unknown status {status:?}",
            path.display()
        ))),
    }
}

/// An f64 attribute, or `default` where an older file lacks it.
fn read_or(p: &hdf5::Group, name: &str, default: f64) -> hdf5::Result<f64> {
    if p.attr(name).is_ok() {
        p.attr(name)?.read_scalar::<f64>()
    } else {
        Ok(default)
    }
}

/// The relative box sides as `2x1`, or "" for a square or cubic box (or an older file).
fn aspect_of(p: &hdf5::Group) -> hdf5::Result<String> {
    if p.attr("aspect").is_ok() {
        read_str(p, "aspect")
    } else {
        Ok(String::new())
    }
}

/// The first `k` snapshots of replica `r`'s file, as the runner held them before writing it: what a
/// final state leaves in the file rather than keeping twice (`edmd extend`).
pub fn read_snapshots(
    path: &Path,
    r: &crate::spec::Replica,
    k: usize,
) -> Result<Vec<crate::replica::Snapshot>, String> {
    let read = || -> hdf5::Result<Vec<crate::replica::Snapshot>> {
        if k == 0 {
            return Ok(Vec::new());
        }
        let gas = hdf5::File::open(path)?.group("particles/gas")?;
        let frames = |name: &str| -> hdf5::Result<Vec<f64>> { gas.dataset(name)?.read_raw() };
        let position = frames("position/value")?;
        let velocity = frames("velocity/value")?;
        let step: Vec<i64> = gas.dataset("position/step")?.read_raw()?;
        let time = frames("position/time")?;
        let spins = if r.rough() {
            frames("angular_velocity/value")?
        } else {
            Vec::new()
        };
        let offsets = if r.sheared() {
            frames("box/offset/value")?
        } else {
            vec![0.0; step.len()]
        };
        if step.len() < k {
            return Err(hdf5::Error::from(format!(
                "{} snapshots, the final state counts {k}",
                step.len()
            )));
        }
        let per = |v: &[f64], j: usize| {
            let w = v.len() / step.len();
            v[j * w..(j + 1) * w].to_vec()
        };
        Ok((0..k)
            .map(|j| crate::replica::Snapshot {
                step: step[j],
                time: time[j],
                position: per(&position, j),
                velocity: per(&velocity, j),
                angular_velocity: if spins.is_empty() {
                    Vec::new()
                } else {
                    per(&spins, j)
                },
                box_offset: offsets[j],
            })
            .collect())
    };
    read().map_err(|e| format!("{}: {e}", path.display()))
}

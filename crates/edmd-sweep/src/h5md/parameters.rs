//! The `/parameters` group of a replica file: the spec, the replica's parameters and scene, its
//! status and final values, and its classification, as attributes.

use hdf5::Group;

use super::{
    attr_f64, attr_i64, attr_str, attr_u64, json_attrs, scene, GIT_COMMIT, SCHEMA_VERSION,
};
use crate::replica::Outcome;
use crate::spec::{Replica, Spec};

/// Writes every attribute of `/parameters` into `p`.
pub(super) fn write(p: &Group, spec: &Spec, r: &Replica, out: &Outcome) -> hdf5::Result<()> {
    attr_i64(p, "schema_version", SCHEMA_VERSION)?;
    // The spec without a refinement's points: a replica's file is the same whichever round ran it.
    let base = spec.base();
    attr_str(p, "spec", &base.canonical_json())?;
    attr_str(p, "spec_hash", &spec.hash())?;
    attr_str(p, "sweep_name", &spec.name)?;
    attr_str(p, "engine_version", env!("CARGO_PKG_VERSION"))?;
    attr_str(p, "git_commit", GIT_COMMIT)?;
    attr_i64(p, "index", r.index as i64)?;
    attr_i64(p, "dim", r.dim as i64)?;
    attr_str(p, "boundary", r.boundary.name())?;
    attr_f64(p, "eps", r.eps)?;
    attr_f64(p, "beta", r.beta)?;
    attr_f64(p, "inertia", if r.rough() { r.inertia } else { f64::NAN })?;
    if let Some(m) = &r.species {
        // The mixture as JSON (fraction, diameter, mass per species), and Garzó–Dufty's T_k/T.
        attr_str(
            p,
            "species",
            &serde_json::to_string(m.as_slice()).unwrap_or_default(),
        )?;
        let counts = r.species_counts();
        p.new_attr::<i64>()
            .shape(counts.len())
            .create("species_count")?
            .write(&counts.iter().map(|&c| c as i64).collect::<Vec<_>>()[..])?;
        let theory = crate::replica::species_temperature_theory(spec, r);
        p.new_attr::<f64>()
            .shape(theory.len())
            .create("species_temperature_theory")?
            .write(&theory[..])?;
    }
    scene::rotational_parameters(p, spec, r)?;
    scene::shear_parameters(p, spec, r)?;
    scene::white_noise_parameters(p, spec, r)?;
    scene::shaken_parameters(p, r, out.bed.as_ref())?;
    attr_f64(p, "gravity", r.gravity)?;
    attr_f64(p, "wall_eps", r.wall_eps)?;
    attr_f64(p, "floor_temperature", r.floor_temperature)?;
    attr_f64(p, "white_noise", r.white_noise)?;
    attr_f64(p, "shake_s", r.shake_s)?;
    attr_f64(p, "shake_gamma", r.shake_gamma)?;
    let (amplitude, omega) = r.floor_motion();
    attr_f64(p, "floor_amplitude", amplitude)?;
    attr_f64(p, "floor_omega", if r.shaken() { omega } else { 0.0 })?;
    let aspect = r.aspect.as_ref().map(|a| crate::spec::aspect_label(a));
    attr_str(p, "aspect", &aspect.unwrap_or_default())?;
    let sides = r.sides();
    p.new_attr::<f64>()
        .shape(sides.len())
        .create("box_sides")?
        .write(&sides[..])?;
    attr_f64(p, "phi", r.phi())?;
    attr_f64(p, "box_side", r.side())?;
    attr_i64(p, "n", r.n as i64)?;
    attr_i64(p, "seed_index", r.seed_index as i64)?;
    attr_u64(p, "seed", r.seed)?;
    attr_str(p, "remedy", &r.remedy.label())?;
    attr_str(p, "rule", &serde_json::to_string(&spec.rule).expect("rule"))?;
    results(p, out)?;
    let spec_group = p.create_group("spec")?;
    let tree = serde_json::to_value(&base).expect("spec serialises");
    json_attrs(&spec_group, "", &tree)?;

    Ok(())
}

/// The replica's outcome: status, message, final values, collapse and classification.
fn results(p: &Group, out: &Outcome) -> hdf5::Result<()> {
    attr_str(p, "status", out.status.name())?;
    attr_str(p, "message", &out.message)?;
    attr_f64(p, "t0", out.t0)?;
    let last = |v: &[f64]| v.last().copied().unwrap_or(f64::NAN);
    attr_f64(p, "final_tau", last(&out.series.tau))?;
    attr_f64(p, "final_time", last(&out.series.time))?;
    attr_f64(
        p,
        "final_ln_temperature_ratio",
        last(&out.series.ln_temperature) - out.t0.ln(),
    )?;
    attr_u64(p, "collisions", out.collisions)?;
    for (name, counts) in out.series.events.named() {
        attr_u64(p, name, counts.last().map_or(0, |&c| c as u64))?;
    }
    let (ct, ctau) = out.collapse.unwrap_or((f64::NAN, f64::NAN));
    attr_f64(p, "collapse_time", ct)?;
    attr_f64(p, "collapse_tau", ctau)?;
    attr_f64(p, "wall_s", out.wall_s)?;
    attr_u64(p, "resumes", out.resumes)?;
    let os = &out.series.order;
    let lastv = |v: &[f64]| v.last().copied().unwrap_or(f64::NAN);
    match &out.classification {
        Some(c) => {
            attr_str(p, "class", c.class.name())?;
            attr_str(p, "class_note", &c.note)?;
            attr_f64(p, "shear_onset_tau", c.shear_onset)?;
            attr_f64(p, "cluster_onset_tau", c.cluster_onset)?;
        }
        None => {
            attr_str(p, "class", "unclassified")?;
            attr_str(p, "class_note", "")?;
            attr_f64(p, "shear_onset_tau", f64::NAN)?;
            attr_f64(p, "cluster_onset_tau", f64::NAN)?;
        }
    }
    attr_f64(p, "final_f_flow", lastv(&os.f_flow))?;
    attr_f64(p, "final_s_perp", lastv(&os.s_perp))?;
    attr_f64(
        p,
        "final_delta_rho2",
        lastv(&os.delta_rho2) - os.delta_rho2.first().copied().unwrap_or(f64::NAN),
    )?;
    attr_f64(p, "per_cell", out.per_cell)?;
    Ok(())
}

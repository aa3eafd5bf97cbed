//! The theory of a replica's scene written beside its measurement (`replica::scene_theory`): the
//! rotational ratio of rough grains and the barometric profile of an elastic column.

use hdf5::Group;

use super::{attr_f64, attr_str, Writer};
use crate::replica::bed_meter::BedSummary;
use crate::replica::{density_profile_theory, rotational_ratio_theory, Series};
use crate::spec::{Replica, Spec};

/// Parameters `rotational_ratio_theory` (the Maxwellian two-temperature theory's stationary R/T) and
/// `rotational_ratio_sonine` (its Sonine correction) of rough replicas; NaN where neither applies.
pub(super) fn rotational_parameters(p: &Group, spec: &Spec, r: &Replica) -> hdf5::Result<()> {
    if !r.rough() {
        return Ok(());
    }
    let (maxwell, sonine) = rotational_ratio_theory(spec, r)
        .map_or((f64::NAN, f64::NAN), |(m, s)| (m.stationary_ratio(), s));
    attr_f64(p, "rotational_ratio_theory", maxwell)?;
    attr_f64(p, "rotational_ratio_sonine", sonine)
}

/// Observable `rotational_ratio_theory`: R(τ)/T(τ) of the Maxwellian two-temperature theory from the
/// measured T and R at the first sample, transient included.
pub(super) fn rotational_observables(
    w: &Writer,
    obs: &Group,
    spec: &Spec,
    r: &Replica,
    s: &Series,
) -> hdf5::Result<()> {
    let Some((maxwell, _)) = rotational_ratio_theory(spec, r) else {
        return Ok(());
    };
    if s.rotational_temperature.len() != s.step.len() || s.step.is_empty() {
        return Ok(());
    }
    let (t0, r0, tau0) = (s.temperature[0], s.rotational_temperature[0], s.tau[0]);
    let ratio: Vec<f64> = s
        .tau
        .iter()
        .map(|&tau| {
            let (t, r) = maxwell.temperatures(t0, r0, tau - tau0);
            r / t
        })
        .collect();
    w.observable(obs, "rotational_ratio_theory", &s.step, &s.time, &ratio)
}

/// Dataset `theory` [B] and attribute `theory_temperature` in `observables/density_profile` of an
/// elastic column.
pub(super) fn profile_theory(g: &Group, r: &Replica, s: &Series, bins: usize) -> hdf5::Result<()> {
    let Some(th) = density_profile_theory(r, s, bins) else {
        return Ok(());
    };
    g.new_dataset_builder()
        .with_data(&ndarray::Array1::from(th.density))
        .create("theory")?;
    attr_f64(g, "theory_temperature", th.temperature)
}

/// Parameters of a sheared replica: `shear_rate`, and where the theory applies (smooth grains of
/// one species, constant restitution below 1) its steady state (the Enskog gas at the replica's φ,
/// PHYSICS.md §7.2): `shear_theory_reduced_rate` a* = a/ν0 (the Boltzmann ν0 = p/η0),
/// `shear_theory_viscosity` η* = −P*_xy/a*, `shear_theory_pxx`, `shear_theory_pyy`,
/// `shear_theory_pzz` (P*_ii = P_ii/(nT), kinetic plus collisional; NaN in 2D),
/// `shear_theory_temperature` (the T that a sustains).
pub(super) fn shear_parameters(p: &Group, spec: &Spec, r: &Replica) -> hdf5::Result<()> {
    if !r.sheared() {
        return Ok(());
    }
    attr_f64(p, "shear_rate", r.shear_rate)?;
    let values = crate::replica::shear_theory(spec, r).map_or([f64::NAN; 6], |(f, t)| {
        [
            f.reduced_shear_rate(),
            f.reduced_viscosity(),
            f.pressure(0, 0),
            f.pressure(1, 1),
            if r.dim == 3 {
                f.pressure(2, 2)
            } else {
                f64::NAN
            },
            t,
        ]
    });
    for (name, v) in [
        "shear_theory_reduced_rate",
        "shear_theory_viscosity",
        "shear_theory_pxx",
        "shear_theory_pyy",
        "shear_theory_pzz",
        "shear_theory_temperature",
    ]
    .into_iter()
    .zip(values)
    {
        attr_f64(p, name, v)?;
    }
    Ok(())
}

/// Parameters of a shaken bed's state (PHYSICS.md §8.4): `shaken_state` and the numbers it was
/// read from, `shaken_phi_max`, `shaken_peak_height` (diameters above the floor's first layer),
/// `shaken_inversion`, `shaken_undulation` (diameters), `shaken_convection` (√(g d)) and
/// `shaken_convection_mode`; the centre of mass's `shaken_com_mean`, `shaken_com_f` and
/// `shaken_com_half_f` (diameters), `shaken_contact_fraction`, `shaken_touching` and
/// `shaken_samples`; nothing for a still floor or a bed without uniform-time samples.
pub(super) fn shaken_parameters(
    p: &Group,
    r: &Replica,
    bed: Option<&BedSummary>,
) -> hdf5::Result<()> {
    let Some((bed, state)) = bed.and_then(|b| Some((b, crate::replica::shaken_state(r, b)?)))
    else {
        return Ok(());
    };
    attr_str(p, "shaken_state", state.label)?;
    for (name, v) in [
        ("shaken_phi_max", state.phi_max),
        ("shaken_peak_height", state.peak_height),
        ("shaken_inversion", state.inversion),
        ("shaken_undulation", bed.undulation),
        ("shaken_convection", bed.convection),
        ("shaken_convection_mode", bed.convection_mode as f64),
        ("shaken_convection_noise", bed.convection_noise),
        ("shaken_com_mean", bed.com_mean),
        ("shaken_com_f", bed.com_f),
        ("shaken_com_half_f", bed.com_half_f),
        ("shaken_contact_fraction", bed.contact_fraction),
        ("shaken_touching", bed.touching),
        ("shaken_samples", bed.samples as f64),
    ] {
        attr_f64(p, name, v)?;
    }
    Ok(())
}

/// Group `bed` of a shaken bed: its uniform-time profiles, `height` [Z] (bin centres), `packing`
/// [Z], `temperature` [Z], `phase_packing` [16, Z] (per phase bin of the floor, from its lowest
/// point) and `vertical_velocity` [Z, X] (time-averaged v_z in √(g d), NaN where no grain was seen).
pub(super) fn bed_group(file: &Group, bed: Option<&BedSummary>) -> hdf5::Result<()> {
    let Some(bed) = bed else {
        return Ok(());
    };
    let g = file.create_group("bed")?;
    let z = bed.height.len();
    for (name, v) in [
        ("height", &bed.height),
        ("packing", &bed.packing),
        ("temperature", &bed.temperature),
    ] {
        g.new_dataset_builder()
            .with_data(&ndarray::Array1::from(v.clone()))
            .create(name)?;
    }
    for (name, v, rows) in [
        (
            "phase_packing",
            &bed.phase_packing,
            bed.phase_packing.len() / z,
        ),
        ("vertical_velocity", &bed.vertical_velocity, z),
    ] {
        let a = ndarray::Array2::from_shape_vec((rows, v.len() / rows), v.clone())
            .map_err(|e| hdf5::Error::from(e.to_string().as_str()))?;
        g.new_dataset_builder().with_data(&a).create(name)?;
    }
    attr_f64(&g, "samples", bed.samples as f64)
}

/// Parameters of a replica heated by white noise: `kick_interval` Δt, and where the theory applies
/// (smooth grains of one species, constant restitution below 1) its steady state (PHYSICS.md §8.1):
/// `white_noise_theory_temperature` T_s and `white_noise_theory_a2`.
pub(super) fn white_noise_parameters(p: &Group, spec: &Spec, r: &Replica) -> hdf5::Result<()> {
    if r.white_noise <= 0.0 {
        return Ok(());
    }
    use crate::replica::noise;
    attr_f64(p, "kick_interval", noise::kick_interval(r))?;
    let (t, a2) = noise::white_noise_theory(spec, r).unwrap_or((f64::NAN, f64::NAN));
    attr_f64(p, "white_noise_theory_temperature", t)?;
    attr_f64(p, "white_noise_theory_a2", a2)
}

/// The observables of a sheared replica (`replica::ShearSeries`); tensors as [s, D, D], profiles
/// as [s, B] with the bin centres in `position`.
pub(super) fn shear_observables(
    w: &Writer,
    obs: &Group,
    r: &Replica,
    s: &Series,
    sides: &[f64],
) -> hdf5::Result<()> {
    let sh = &s.shear;
    if !r.sheared() || sh.box_offset.len() != s.step.len() {
        return Ok(());
    }
    let d = r.dim;
    for (name, rows) in [
        ("pressure_tensor", &sh.pressure_tensor),
        ("pressure_tensor_kinetic", &sh.pressure_tensor_kinetic),
    ] {
        let g = obs.create_group(name)?;
        w.series_1d(&g, "step", &s.step)?;
        w.series_1d(&g, "time", &s.time)?;
        let flat: Vec<f64> = rows.iter().flatten().copied().collect();
        let arr = ndarray::Array3::from_shape_vec((rows.len(), d, d), flat).expect("D x D rows");
        g.new_dataset_builder().with_data(&arr).create("value")?;
    }
    w.observable(
        obs,
        "collision_frequency",
        &s.step,
        &s.time,
        &sh.collision_frequency,
    )?;
    w.observable(
        obs,
        "dissipation_rate",
        &s.step,
        &s.time,
        &sh.dissipation_rate,
    )?;
    w.observable(obs, "box_offset", &s.step, &s.time, &sh.box_offset)?;
    for (name, rows, axis) in [
        ("velocity_profile", &sh.velocity_profile, 1),
        ("density_profile_y", &sh.density_profile_y, 1),
        ("density_profile_x", &sh.density_profile_x, 0),
    ] {
        let g = w.observable_2d(obs, name, &s.step, &s.time, rows)?;
        let bins = rows.first().map_or(0, Vec::len);
        let centres: Vec<f64> = (0..bins)
            .map(|b| (b as f64 + 0.5) * sides[axis] / bins as f64)
            .collect();
        g.new_dataset_builder()
            .with_data(&ndarray::Array1::from(centres))
            .create("position")?;
    }
    Ok(())
}

/// `particles/gas/box/offset` of a sheared replica: the images' offset at each snapshot. The images
/// above the box sit at x + offset, y + L_y (below: x − offset, y − L_y) and move with v_x ± a L_y
/// (docs/output.md).
pub(super) fn shear_offsets(
    w: &Writer,
    bx: &Group,
    r: &Replica,
    snapshots: &[crate::replica::Snapshot],
) -> hdf5::Result<()> {
    if !r.sheared() {
        return Ok(());
    }
    let g = bx.create_group("offset")?;
    let step: Vec<i64> = snapshots.iter().map(|s| s.step).collect();
    let time: Vec<f64> = snapshots.iter().map(|s| s.time).collect();
    let value: Vec<f64> = snapshots.iter().map(|s| s.box_offset).collect();
    w.series_1d(&g, "step", &step)?;
    w.series_1d(&g, "time", &time)?;
    w.series_1d(&g, "value", &value)?;
    attr_f64(&g, "shear_rate", r.shear_rate)
}

//! The theory of a replica's scene written beside its measurement (`replica::scene_theory`): the
//! rotational ratio of rough grains and the barometric profile of an elastic column.

use hdf5::Group;

use super::{attr_f64, Writer};
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

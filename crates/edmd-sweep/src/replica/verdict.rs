//! A finished replica's verdict: the classifier's class for free cooling, the sheared flow's, or why
//! none applies.

use super::{Series, Status};
use crate::classify::{classify, Class, Classification, Theory};
use crate::spec::{Replica, Spec};

/// The classification of a replica that ended with `status` (None without `classify`).
pub(super) fn classification(
    spec: &Spec,
    r: &Replica,
    status: Status,
    series: &Series,
    theory: &Theory,
) -> Option<Classification> {
    spec.classify.as_ref().map(|c| match status {
        Status::Done if r.sheared() => {
            super::shear::classify(&series.shear, r.n, c.thresholds.cluster_density)
        }
        Status::Done if r.driven_or_stratified() => Classification {
            class: Class::NotApplicable,
            shear_onset: f64::NAN,
            cluster_onset: f64::NAN,
            haff_deviation: Vec::new(),
            note: if r.shaken() {
                "a shaken bed: not free cooling (its state: parameters/shaken_state)".into()
            } else if r.gravity > 0.0 {
                "gravity: a stratified column is not free cooling".into()
            } else {
                "driven by a thermal floor: not free cooling".into()
            },
        },
        Status::Done => classify(&series.order, &c.thresholds, theory),
        Status::Collapsed
        | Status::Stalled
        | Status::Failed
        | Status::Missing
        | Status::Corrupt => Classification {
            class: match status {
                Status::Collapsed => Class::Collapsed,
                Status::Stalled => Class::Stalled,
                _ => Class::Failed,
            },
            shear_onset: f64::NAN,
            cluster_onset: f64::NAN,
            haff_deviation: crate::classify::haff_deviation(
                &series.order,
                c.thresholds.haff_tau0,
                theory.haff_rate,
            )
            .0,
            note: String::new(),
        },
    })
}

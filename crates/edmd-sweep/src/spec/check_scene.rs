//! Checks of a grid's scene: gravity, wall restitution, a thermal floor, the box's aspect and the
//! species of a mixture. Errors name the field (`grid.gravity = [0.1]: …`).

use super::check::{bad, no_duplicates, within};
use super::{AspectAxis, BoundaryKind, Grid, Remedy, RuleSpec, Spec, SpeciesAxis};
use crate::domain;
use crate::SweepError;

impl Spec {
    /// The scene checks of one grid, whose fields are named `{at}.gravity` and so on.
    pub(super) fn validate_scene(&self, g: &Grid, at: &str) -> Result<(), SweepError> {
        scene_axes(g, at)?;
        shaking(g, at)?;
        walls_and_shear(g, at)?;
        self.driven_rules(g, at)?;
        if let Some(axis) = &g.aspect {
            aspect(g, axis, at)?;
        }
        if let Some(axis) = &g.species {
            species(axis, at)?;
        }
        Ok(())
    }

    /// Gravity and thermal floors take the constant rule, and a remedy other than the rotation.
    fn driven_rules(&self, g: &Grid, at: &str) -> Result<(), SweepError> {
        let gravity = g.gravity.values().iter().any(|&x| x > 0.0);
        if !(gravity || g.floor_temperature.is_some()) {
            return Ok(());
        }
        let field = if gravity {
            "gravity"
        } else {
            "floor_temperature"
        };
        if !matches!(self.rule, RuleSpec::Constant {}) {
            return bad(
                at,
                field,
                &"given",
                "gravity and thermal floors run with rule \"constant\" only",
            );
        }
        if g.remedy
            .values()
            .iter()
            .any(|r| matches!(r, Remedy::Rotation { .. }))
        {
            return bad(
                at,
                field,
                &"given",
                "gravity and thermal floors run with remedy \"none\" or \"tc\" only",
            );
        }
        Ok(())
    }
}

/// The scene's numeric axes: gravity, shear rate, wall restitution and thermal floor, each without
/// duplicates, non-empty and in its domain.
fn scene_axes(g: &Grid, at: &str) -> Result<(), SweepError> {
    for (field, axis, d) in [
        ("gravity", &g.gravity, &domain::GRAVITY),
        ("shear_rate", &g.shear_rate, &domain::SHEAR_RATE),
        ("wall_eps", &g.wall_eps, &domain::WALL_EPS),
    ] {
        no_duplicates(at, field, axis)?;
        if axis.values().is_empty() {
            return bad(at, field, &"[]", "empty axis: the grid has no replicas");
        }
        for v in axis.values() {
            within(&format!("{at}.{field}"), v, d)?;
        }
    }
    if let Some(f) = &g.white_noise {
        no_duplicates(at, "white_noise", f)?;
        if f.values().is_empty() {
            return bad(
                at,
                "white_noise",
                &"[]",
                "empty axis: the grid has no replicas",
            );
        }
        for v in f.values() {
            within(&format!("{at}.white_noise"), v, &domain::WHITE_NOISE)?;
        }
        white_noise_scene(g, &format!("{:?}", f.values()), at)?;
    }
    if let Some(f) = &g.floor_temperature {
        no_duplicates(at, "floor_temperature", f)?;
        if f.values().is_empty() {
            return bad(
                at,
                "floor_temperature",
                &"[]",
                "empty axis: the grid has no replicas",
            );
        }
        for v in f.values() {
            within(
                &format!("{at}.floor_temperature"),
                v,
                &domain::FLOOR_TEMPERATURE,
            )?;
        }
    }
    Ok(())
}

/// The thermostat heats a gas in a periodic or walled box, with nothing else driving it.
fn white_noise_scene(g: &Grid, value: &str, at: &str) -> Result<(), SweepError> {
    let others = [
        (g.gravity.values().iter().any(|&x| x > 0.0), "gravity"),
        (g.floor_temperature.is_some(), "a thermal floor"),
        (
            g.boundary.values().contains(&BoundaryKind::LeesEdwards),
            "a sheared box",
        ),
    ];
    match others.into_iter().find(|o| o.0) {
        Some((_, what)) => bad(
            at,
            "white_noise",
            &value,
            &format!("runs without {what} (one drive at a time)"),
        ),
        None => Ok(()),
    }
}

/// A vibrating floor: S and Γ given together, each a non-empty axis in its domain, under gravity on
/// every grid point, with a floor restitution > 0 (at 0 a grain would ride it in contacts without
/// end), and no other drive.
fn shaking(g: &Grid, at: &str) -> Result<(), SweepError> {
    let (s, gamma) = match (&g.shake_s, &g.shake_gamma) {
        (None, None) => return Ok(()),
        (Some(s), Some(gamma)) => (s, gamma),
        (Some(s), None) => {
            let v = format!("{:?}", s.values());
            return bad(at, "shake_s", &v, "needs shake_gamma too (Gamma = A w^2/g)");
        }
        (None, Some(gamma)) => {
            let v = format!("{:?}", gamma.values());
            return bad(
                at,
                "shake_gamma",
                &v,
                "needs shake_s too (S = A^2 w^2/(g d))",
            );
        }
    };
    for (field, axis, d) in [
        ("shake_s", s, &domain::SHAKE_S),
        ("shake_gamma", gamma, &domain::SHAKE_GAMMA),
    ] {
        no_duplicates(at, field, axis)?;
        if axis.values().is_empty() {
            return bad(at, field, &"[]", "empty axis: the grid has no replicas");
        }
        for v in axis.values() {
            within(&format!("{at}.{field}"), v, d)?;
        }
    }
    let value = format!("{:?}", s.values());
    let refuse = |reason: &str| bad(at, "shake_s", &value, reason);
    if g.gravity.values().iter().any(|&x| x <= 0.0) {
        return refuse("a vibrating floor needs gravity > 0 on every grid point");
    }
    if g.floor_temperature.is_some() || g.white_noise.is_some() {
        return refuse("a floor either vibrates or is thermal, and runs without white noise");
    }
    if g.wall_eps.values().contains(&0.0) {
        return bad(
            at,
            "wall_eps",
            &format!("{:?}", g.wall_eps.values()),
            "a vibrating floor needs wall_eps > 0 (at 0 a grain rides it in contacts without end)",
        );
    }
    Ok(())
}

/// Gravity, floors and wall restitution need walls on the last axis; shear needs the sliding box.
fn walls_and_shear(g: &Grid, at: &str) -> Result<(), SweepError> {
    let gravity = g.gravity.values().iter().any(|&x| x > 0.0);
    let walls_needed = [
        (gravity, "gravity", format!("{:?}", g.gravity.values())),
        (
            g.floor_temperature.is_some(),
            "floor_temperature",
            format!(
                "{:?}",
                g.floor_temperature
                    .as_ref()
                    .map(|f| f.values())
                    .unwrap_or_default()
            ),
        ),
        (
            g.wall_eps.values().iter().any(|&x| x != 1.0),
            "wall_eps",
            format!("{:?}", g.wall_eps.values()),
        ),
    ];
    for (needed, field, value) in walls_needed {
        if let Some(b) = g.boundary.values().into_iter().find(|b| b.periodic()) {
            if needed {
                return bad(
                    at,
                    field,
                    &value,
                    &format!(
                        "needs walls on the last axis: boundary \"walls\" or \"channel\", not \"{}\"",
                        b.name()
                    ),
                );
            }
        }
    }
    // Shear needs the sliding box, and the sliding box is sheared only by its rate.
    if g.shear_rate.values().iter().any(|&a| a > 0.0) {
        if let Some(b) = g
            .boundary
            .values()
            .into_iter()
            .find(|&b| b != BoundaryKind::LeesEdwards)
        {
            return bad(
                at,
                "shear_rate",
                &format!("{:?}", g.shear_rate.values()),
                &format!(
                    "needs boundary \"lees-edwards\" (the sliding periodic box), not \"{}\"",
                    b.name()
                ),
            );
        }
    }
    Ok(())
}

/// Each aspect holds one relative side per axis of every dimension, each in its domain.
fn aspect(g: &Grid, axis: &AspectAxis, at: &str) -> Result<(), SweepError> {
    for (k, a) in axis.0.iter().enumerate() {
        let at_k = if axis.0.len() > 1 {
            format!("aspect[{k}]")
        } else {
            "aspect".into()
        };
        for d in g.dim.values() {
            if a.len() != d {
                return bad(
                    at,
                    &at_k,
                    &format!("{:?}", a.as_slice()),
                    &format!("needs one relative side per axis ({d} for dim {d})"),
                );
            }
        }
        for (i, &x) in a.iter().enumerate() {
            within(&format!("{at}.{at_k}[{i}]"), x, &domain::ASPECT)?;
        }
    }
    Ok(())
}

/// Each mixture: 1 to 64 species, each in its domains, fractions summing to 1; no mixture twice.
fn species(axis: &SpeciesAxis, at: &str) -> Result<(), SweepError> {
    let axis_len = axis.0.len();
    for (k, mixture) in axis.0.iter().enumerate() {
        let at_k = if axis_len > 1 {
            format!("species[{k}]")
        } else {
            "species".into()
        };
        if mixture.is_empty() || mixture.len() > domain::MAX_SPECIES {
            return bad(
                at,
                &at_k,
                &mixture.len(),
                &format!("a mixture needs 1 to {} species", domain::MAX_SPECIES),
            );
        }
        for (i, sp) in mixture.iter().enumerate() {
            within(
                &format!("{at}.{at_k}[{i}].fraction"),
                sp.fraction,
                &domain::FRACTION,
            )?;
            within(
                &format!("{at}.{at_k}[{i}].diameter"),
                sp.diameter,
                &domain::DIAMETER,
            )?;
            if let Some(m) = sp.mass {
                within(&format!("{at}.{at_k}[{i}].mass"), m, &domain::MASS)?;
            }
        }
        let total: f64 = mixture.iter().map(|sp| sp.fraction).sum();
        if (total - 1.0).abs() > 1e-9 {
            return bad(
                at,
                &format!("{at_k}[*].fraction"),
                &format!("{total}"),
                "the fractions of a mixture must sum to 1",
            );
        }
    }
    if axis.0.windows(2).any(|w| w[0] == w[1]) || {
        let mut seen = Vec::new();
        axis.0.iter().any(|m| {
            let dup = seen.contains(&m);
            seen.push(m);
            dup
        })
    } {
        return bad(
            at,
            "species",
            &"[…]",
            "a mixture appears twice (grid points must differ)",
        );
    }
    Ok(())
}

//! `Simulation.save`: the particles as the text `init.from` reads (docs/sweep-spec.md, "Starting
//! from a configuration"), every number in Rust's shortest form that parses back to the same
//! double, so that a saved and loaded state starts from exactly the positions and velocities.

use std::fmt::Write;

use edmd_core::Engine;

/// The text of the configuration now: a comment header, then one line per particle in the
/// original order.
pub(crate) fn text<const D: usize>(e: &dyn Engine<D>) -> String {
    let (x, v, radii, masses) = (e.positions(), e.velocities(), e.radii(), e.masses());
    let spins = e.rough().then(|| e.spins());
    let sides: Vec<String> = e.box_len().iter().map(|s| format!("{s}")).collect();
    let mut out = format!(
        "# edmd configuration: {D}D, N = {}, box {}, tau {}, time {}\n\
         # positions ({D}), velocities ({D}), radius, mass{}\n",
        x.len(),
        sides.join(" × "),
        e.tau(),
        e.time(),
        if spins.is_some() { ", spin" } else { "" }
    );
    for i in 0..x.len() {
        let mut fields: Vec<f64> = x[i].iter().chain(v[i].iter()).copied().collect();
        fields.extend([radii[i], masses[i]]);
        if let Some(w) = &spins {
            fields.extend(if D == 2 { &w[i][2..] } else { &w[i][..] });
        }
        let line: Vec<String> = fields.iter().map(|f| format!("{f:e}")).collect();
        writeln!(out, "{}", line.join(" ")).expect("writing to a String");
    }
    out
}

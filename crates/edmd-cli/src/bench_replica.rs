//! `edmd bench-replica SPEC --replica I`: the runner against the engine alone on the same replica
//! (one thread, no files), alternating, to measure what sampling, classification and snapshots cost
//! (docs/benchmarks.md, "The runner against the engine").

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::bail;
use clap::Args;

use edmd_sweep::replica::{self, bare::engine_only};

use crate::load_spec;

/// Arguments of `edmd bench-replica`.
#[derive(Debug, Args)]
pub struct BenchReplicaArgs {
    /// Sweep spec (JSON) [default: the embedded quick sweep].
    pub spec: Option<PathBuf>,
    /// The replica's index in the sweep.
    #[arg(long, default_value_t = 0)]
    pub replica: usize,
    /// Rounds, each the runner then the engine alone (the ratio is the median of the rounds').
    #[arg(long, default_value_t = 3)]
    pub rounds: usize,
    /// Run one side only, once (for instruction counts under cachegrind): `runner`, or `engine` to
    /// the replica's stop.tau_max.
    #[arg(long, value_parser = ["runner", "engine"])]
    pub only: Option<String>,
    /// One JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs the rounds and prints each and the median ratio of the runner's rate to the engine's.
pub fn command(a: BenchReplicaArgs) -> anyhow::Result<ExitCode> {
    let spec = load_spec(a.spec.as_deref())?;
    let replicas = spec.replicas();
    let Some(r) = replicas.get(a.replica) else {
        bail!(
            "--replica {}: the sweep has {} replicas",
            a.replica,
            replicas.len()
        );
    };
    if a.rounds == 0 {
        bail!("--rounds 0: need at least one round");
    }
    if !a.json {
        eprintln!("{r}, to tau {}", spec.stop.tau_max);
    }
    match a.only.as_deref() {
        Some("runner") => {
            let o = replica::run(&spec, r, &|_| {});
            eprintln!("runner: {} collisions in {:.3} s", o.collisions, o.wall_s);
            return Ok(ExitCode::SUCCESS);
        }
        Some(_) => {
            let (c, s) = engine_only(&spec, r, (spec.stop.tau_max * r.n as f64) as u64)?;
            eprintln!("engine alone: {c} collisions in {s:.3} s");
            return Ok(ExitCode::SUCCESS);
        }
        None => {}
    }
    let mut rows = Vec::new();
    for round in 0..a.rounds {
        let outcome = replica::run(&spec, r, &|_| {});
        if outcome.collisions == 0 {
            bail!("replica {}: no collisions ({})", a.replica, outcome.message);
        }
        let runner = outcome.collisions as f64 / outcome.wall_s;
        let (c, s) = engine_only(&spec, r, outcome.collisions)?;
        let engine = c as f64 / s;
        if !a.json {
            eprintln!(
                "round {round}: runner {:.4e} collisions/s, engine alone {:.4e} ({} collisions): {:.4}",
                runner,
                engine,
                outcome.collisions,
                runner / engine
            );
        }
        rows.push((runner, engine));
    }
    let mut ratios: Vec<f64> = rows.iter().map(|(r, e)| r / e).collect();
    ratios.sort_by(f64::total_cmp);
    let median = ratios[ratios.len() / 2];
    if a.json {
        let runner: Vec<f64> = rows.iter().map(|x| x.0).collect();
        let engine: Vec<f64> = rows.iter().map(|x| x.1).collect();
        // Finite rates only (checked above), so Rust's float lists are JSON.
        println!(
            r#"{{"replica": {}, "runner": {runner:?}, "engine": {engine:?}, "median_ratio": {median}}}"#,
            a.replica
        );
    } else {
        println!(
            "replica {}: the runner at {median:.4} of the engine alone (median of {} rounds)",
            a.replica, a.rounds
        );
    }
    Ok(ExitCode::SUCCESS)
}

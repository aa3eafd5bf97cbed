//! `edmd.Simulation`: one replica of a sweep spec, built as `edmd run` builds it, advanced from
//! Python with the GIL released and Ctrl-C honoured between chunks of events.

use std::path::PathBuf;
use std::sync::Mutex;

use edmd_core::{order_parameters, Engine, Stop, Vector, VirialMeter};
use edmd_sweep::budget::{check_memory, MemoryLimit};
use edmd_sweep::replica::bare::{any_engine, law_and_remedy, AnyEngine};
use edmd_sweep::spec::{FromSpec, Replica, Spec};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::chunks::Chunks;
use crate::stress::sheared_stress;
use crate::{configuration, value_error};

enum Inner {
    D2(Box<dyn Engine<2>>),
    D3(Box<dyn Engine<3>>),
}

/// One replica of a sweep spec, running in this process.
#[pyclass(module = "edmd")]
pub struct Simulation {
    inner: Mutex<Inner>,
    /// The spec and replica it was built from; `set_rule` changes their rule, eps and remedy.
    spec: Spec,
    replica: Replica,
}

/// `f(engine)` whatever the dimension.
macro_rules! with_engine {
    ($inner:expr, $e:ident => $body:expr) => {
        match $inner {
            Inner::D2($e) => $body,
            Inner::D3($e) => $body,
        }
    };
}

fn rows<const D: usize>(py: Python<'_>, v: Vec<Vector<D>>) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let n = v.len();
    let flat: Vec<f64> = v.iter().flat_map(|x| x.iter().copied()).collect();
    PyArray1::from_vec(py, flat).reshape([n, D])
}

impl Simulation {
    /// Replica `replica` of `spec`, built as `edmd run` builds it.
    fn build(spec: Spec, replica: usize) -> PyResult<Self> {
        let replicas = spec.replicas();
        let r = replicas.get(replica).ok_or_else(|| {
            value_error(format!(
                "replica {replica}: the sweep has {} replicas",
                replicas.len()
            ))
        })?;
        // As `edmd run` does: a replica beyond this machine's memory is refused, not attempted.
        check_memory(&spec, std::slice::from_ref(r), 1, MemoryLimit::new(None))
            .map_err(value_error)?;
        let inner = match any_engine(&spec, r).map_err(value_error)? {
            AnyEngine::D2(e) => Inner::D2(e),
            AnyEngine::D3(e) => Inner::D3(e),
        };
        Ok(Simulation {
            inner: Mutex::new(inner),
            replica: r.clone(),
            spec,
        })
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Inner> {
        self.inner
            .lock()
            .expect("not poisoned: the engine does not panic")
    }
}

/// A spec given as a dict or as JSON text, as JSON text.
fn json_text(spec: &Bound<'_, PyAny>) -> PyResult<String> {
    match spec.extract::<String>() {
        Ok(s) => Ok(s),
        Err(_) => spec
            .py()
            .import("json")?
            .call_method1("dumps", (spec,))?
            .extract(),
    }
}

/// A spec field given from Python (a dict, or JSON text), read as the spec reads it.
fn from_json_field<T: serde::de::DeserializeOwned>(
    field: &str,
    value: &Bound<'_, PyAny>,
) -> PyResult<T> {
    serde_json::from_str(&json_text(value)?).map_err(|e| value_error(format!("{field}: {e}")))
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("dim", &self.replica.dim)
            .field("n", &self.replica.n)
            .finish_non_exhaustive()
    }
}

/// [`Simulation::observe`]'s entries.
fn fill<const D: usize>(
    d: &Bound<'_, PyDict>,
    e: &dyn Engine<D>,
    grid: Option<usize>,
) -> PyResult<()> {
    let o = e.observe();
    let c = e.counters();
    d.set_item("time", o.time)?;
    d.set_item("tau", o.tau)?;
    d.set_item("temperature", o.temperature)?;
    d.set_item("kinetic_energy", o.kinetic_energy)?;
    d.set_item("rotational_energy", e.rotational_energy())?;
    d.set_item("kurtosis", o.kurtosis)?;
    d.set_item("momentum", o.momentum.iter().copied().collect::<Vec<f64>>())?;
    for (name, v) in [
        ("events", c.events),
        ("pair_collisions", c.pair_collisions),
        ("wall_collisions", c.wall_collisions),
        ("crossings", c.crossings),
        ("stale_events", c.stale),
        ("system_events", c.system_events),
        ("restarts", c.restarts),
        ("rescales", c.rescales),
    ] {
        d.set_item(name, v)?;
    }
    if let Some(grid) = grid {
        let walls = std::array::from_fn(|a| e.has_walls(a));
        let (x, v, m) = (e.positions(), e.velocities_internal(), e.masses());
        let op = order_parameters(&x, &v, &m, e.box_len(), walls, grid);
        d.set_item("f_flow", op.f_flow)?;
        d.set_item("s_perp", op.s_perp)?;
        d.set_item("delta_rho2", op.delta_rho2)?;
        d.set_item("f_2x", op.f_2x)?;
        d.set_item("s_rho", op.s_rho)?;
    }
    Ok(())
}

#[pymethods]
impl Simulation {
    /// Replica `replica` of a sweep spec (a dict, or its JSON text), built exactly as `edmd run`
    /// builds it: placement, velocities, melt, rule, scene. Raises ValueError with the line the
    /// command prints for a bad spec or index.
    #[staticmethod]
    #[pyo3(signature = (spec, replica = 0))]
    fn from_spec(spec: &Bound<'_, PyAny>, replica: usize) -> PyResult<Self> {
        Self::build(
            Spec::from_json(&json_text(spec)?).map_err(value_error)?,
            replica,
        )
    }

    /// Replica `replica` of `spec` started from the configuration file `path` (what
    /// :meth:`save` writes, or any file `init.from` reads; checked against this replica's grid
    /// point alone), without a melt; τ and time count from 0.
    #[staticmethod]
    #[pyo3(signature = (path, spec, replica = 0))]
    fn load(path: PathBuf, spec: &Bound<'_, PyAny>, replica: usize) -> PyResult<Self> {
        let mut spec = Spec::from_json(&json_text(spec)?).map_err(value_error)?;
        spec.init.from = Some(FromSpec {
            file: path.to_string_lossy().into_owned(),
            tau: None,
        });
        spec.init.melt_tau = None;
        Self::build(spec, replica)
    }

    /// Writes the particles now to `path` as text that `init.from` (and :meth:`load`) reads: per
    /// particle D positions, D velocities, radius, mass, and for rough grains the spin, each
    /// number in the shortest form that reads back to the same double. The shear offset of a
    /// sheared box, the event calendar and the rule's memory are not part of it.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        let text = with_engine!(&*self.lock(), e => configuration::text(&**e));
        std::fs::write(&path, text)
            .map_err(|e| PyOSError::new_err(format!("cannot write {}: {e}", path.display())))
    }

    /// Runs to `tau` pair collisions per particle (counted from the start), or `collisions` more
    /// pair collisions, or until the temperature falls to `until_temperature` (with `tau` or
    /// `collisions` as a limit, or alone). The GIL is released while the engine runs; Ctrl-C
    /// stops it between two events within a fraction of a second and leaves the simulation
    /// usable. Returns what the interval measured: the compressibility factor Z = pV/(NT) from
    /// the collisions' virial, the collision frequency per particle and the time run; in a
    /// sheared box also the pressure tensor (kinetic at the end plus collisional over the
    /// interval, D × D) and the dissipation rate per unit volume, as the files sample them.
    #[pyo3(signature = (tau = None, collisions = None, until_temperature = None))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        tau: Option<f64>,
        collisions: Option<u64>,
        until_temperature: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let now = self.tau();
        let limit = match (tau, collisions) {
            (Some(t), None) if t.is_finite() => t,
            (None, Some(c)) => now + c as f64 / self.replica.n as f64,
            (None, None) if until_temperature.is_some() => f64::INFINITY,
            _ => {
                return Err(value_error(
                    "give one of tau (finite) or collisions, or until_temperature",
                ))
            }
        };
        if let Some(t) = until_temperature {
            if !(t > 0.0 && t.is_finite()) {
                return Err(value_error(format!(
                    "until_temperature = {t}: must be a positive temperature"
                )));
            }
        }
        let meter = with_engine!(&*self.lock(), e => VirialMeter::start(&**e));
        if self.replica.sheared() {
            with_engine!(&mut *self.lock(), e => e.restart_shear_sums());
        }
        let mut chunks = Chunks::new(
            self.replica.n,
            now,
            self.temperature(),
            limit,
            until_temperature,
        );
        while let Some(next) = chunks.next_stop() {
            let (reached, temperature) = py.detach(|| {
                let mut inner = self.lock();
                with_engine!(&mut *inner, e => { e.run(Stop::Tau(next)); (e.tau(), e.temperature()) })
            });
            py.check_signals()?;
            if !chunks.advance(next, reached, temperature) {
                break;
            }
        }
        let d = PyDict::new(py);
        let reading = with_engine!(&*self.lock(), e => meter.read(&**e));
        d.set_item("z", reading.z)?;
        d.set_item("collision_frequency", reading.nu)?;
        d.set_item("duration", reading.duration)?;
        if self.replica.sheared() {
            let (p, dissipation) = match &*self.lock() {
                Inner::D2(e) => sheared_stress(&**e, reading.duration),
                Inner::D3(e) => sheared_stress(&**e, reading.duration),
            };
            d.set_item("pressure_tensor", p)?;
            d.set_item("dissipation_rate", dissipation)?;
        }
        Ok(d)
    }

    /// Changes the collision rule between runs, as a spec's fields would set it: `eps` (the grid's
    /// restitution), `rule` (the spec's `rule`, e.g. ``{"kind": "threshold", "delta": 0.1}``),
    /// `remedy` (the grid's, e.g. ``{"kind": "tc", "tc": 1e-4}``); what is not given stays. The
    /// grains' kind (smooth or rough) stays. Raises ValueError as the spec would.
    #[pyo3(signature = (eps = None, rule = None, remedy = None))]
    fn set_rule(
        &mut self,
        eps: Option<f64>,
        rule: Option<&Bound<'_, PyAny>>,
        remedy: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let (mut spec, mut r) = (self.spec.clone(), self.replica.clone());
        if let Some(e) = eps {
            r.eps = e;
        }
        if let Some(x) = rule {
            spec.rule = from_json_field("rule", x)?;
        }
        if let Some(x) = remedy {
            r.remedy = from_json_field("remedy", x)?;
        }
        let (law, remedy) = law_and_remedy(&spec, &r).map_err(value_error)?;
        with_engine!(&mut *self.lock(), e => e.set_law(law, remedy)).map_err(value_error)?;
        (self.spec, self.replica) = (spec, r);
        Ok(())
    }

    /// The restitution `eps` of the grid point, as last set.
    #[getter]
    fn eps(&self) -> f64 {
        self.replica.eps
    }

    /// Pair collisions per particle so far.
    #[getter]
    fn tau(&self) -> f64 {
        with_engine!(&*self.lock(), e => e.tau())
    }

    /// Physical time.
    #[getter]
    fn time(&self) -> f64 {
        with_engine!(&*self.lock(), e => e.time())
    }

    /// Granular temperature m⟨v²⟩/d.
    #[getter]
    fn temperature(&self) -> f64 {
        with_engine!(&*self.lock(), e => e.temperature())
    }

    /// Pair collisions so far.
    #[getter]
    fn collisions(&self) -> u64 {
        with_engine!(&*self.lock(), e => e.counters().pair_collisions)
    }

    /// Particles.
    #[getter]
    fn n(&self) -> usize {
        self.replica.n
    }

    /// Dimension, 2 or 3.
    #[getter]
    fn dim(&self) -> usize {
        self.replica.dim
    }

    /// Radii, in the original particle order.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, with_engine!(&*self.lock(), e => e.radii()))
    }

    /// Masses, in the original particle order.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, with_engine!(&*self.lock(), e => e.masses()))
    }

    /// The species of each particle (0 without a mixture): species k takes the next N_k
    /// particles, as `edmd run` places them and writes `particles/gas/species`.
    #[getter]
    fn species<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        let species: Vec<i64> = (self.replica.species_counts().iter().enumerate())
            .flat_map(|(k, &c)| std::iter::repeat(k as i64).take(c))
            .collect();
        PyArray1::from_vec(py, species)
    }

    /// Positions now, N × D, in the original particle order, wrapped into the box.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        match &*self.lock() {
            Inner::D2(e) => rows(py, e.positions()),
            Inner::D3(e) => rows(py, e.positions()),
        }
    }

    /// Velocities now, N × D, in the original particle order.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        match &*self.lock() {
            Inner::D2(e) => rows(py, e.velocities()),
            Inner::D3(e) => rows(py, e.velocities()),
        }
    }

    /// Angular velocities, in the original particle order: N × 1 (ω_z) in 2D, N × 3 in 3D; zero
    /// for smooth grains.
    #[getter]
    fn spins<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (spins, dim) = match &*self.lock() {
            Inner::D2(e) => (e.spins(), 2),
            Inner::D3(e) => (e.spins(), 3),
        };
        let width = if dim == 2 { 1 } else { 3 };
        let flat: Vec<f64> = spins.iter().flat_map(|w| w[3 - width..].to_vec()).collect();
        PyArray1::from_vec(py, flat).reshape([spins.len(), width])
    }

    /// The bulk observables now, as a dict: time, tau, temperature, kinetic and rotational
    /// energy, kurtosis, total momentum, and the event counters by kind; with `grid` (cells per
    /// axis) also the classifier's order parameters on that grid (f_flow, s_perp, delta_rho2,
    /// f_2x, s_rho; docs/output.md).
    #[pyo3(signature = (grid = None))]
    fn observe<'py>(&self, py: Python<'py>, grid: Option<usize>) -> PyResult<Bound<'py, PyDict>> {
        if grid == Some(0) {
            return Err(value_error(
                "grid = 0: the order parameters need at least one cell",
            ));
        }
        let d = PyDict::new(py);
        match &*self.lock() {
            Inner::D2(e) => fill(&d, &**e, grid)?,
            Inner::D3(e) => fill(&d, &**e, grid)?,
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "<edmd.Simulation {}D N={} tau={:.3} T={:.4e}>",
            self.replica.dim,
            self.replica.n,
            self.tau(),
            self.temperature()
        )
    }
}

//! `edmd.Simulation`: one replica of a sweep spec, built as `edmd run` builds it, advanced from
//! Python with the GIL released and Ctrl-C honoured between chunks of events.

use std::sync::Mutex;

use edmd_core::{Engine, Stop, Vector};
use edmd_sweep::budget::{check_memory, MemoryLimit};
use edmd_sweep::replica::bare::{any_engine, AnyEngine};
use edmd_sweep::spec::Spec;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::value_error;

/// Pair collisions per chunk between two looks at Ctrl-C (about a tenth of a second).
const CHUNK_COLLISIONS: f64 = 2e5;

enum Inner {
    D2(Box<dyn Engine<2>>),
    D3(Box<dyn Engine<3>>),
}

/// One replica of a sweep spec, running in this process.
#[pyclass(module = "edmd")]
pub struct Simulation {
    inner: Mutex<Inner>,
    n: usize,
    dim: usize,
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

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("dim", &self.dim)
            .field("n", &self.n)
            .finish_non_exhaustive()
    }
}

/// [`Simulation::observe`]'s entries.
fn fill<const D: usize>(d: &Bound<'_, PyDict>, e: &dyn Engine<D>) -> PyResult<()> {
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
        let text: String = match spec.extract::<String>() {
            Ok(s) => s,
            Err(_) => spec
                .py()
                .import("json")?
                .call_method1("dumps", (spec,))?
                .extract()?,
        };
        let spec = Spec::from_json(&text).map_err(value_error)?;
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
            n: r.n,
            dim: r.dim,
        })
    }

    /// Runs to `tau` pair collisions per particle (counted from the start), or `collisions` more
    /// pair collisions. The GIL is released while the engine runs; Ctrl-C stops it between two
    /// events within a fraction of a second and leaves the simulation usable.
    #[pyo3(signature = (tau = None, collisions = None))]
    fn run(&self, py: Python<'_>, tau: Option<f64>, collisions: Option<u64>) -> PyResult<()> {
        let now = self.tau();
        let target = match (tau, collisions) {
            (Some(t), None) if t.is_finite() => t,
            (None, Some(c)) => now + c as f64 / self.n as f64,
            _ => return Err(value_error("give one of tau (finite) or collisions")),
        };
        let step = CHUNK_COLLISIONS / self.n as f64;
        let mut at = now;
        while at < target {
            let next = (at + step).min(target);
            let reached = py.detach(|| {
                let mut inner = self.inner.lock().expect("not poisoned");
                with_engine!(&mut *inner, e => { e.run(Stop::Tau(next)); e.tau() })
            });
            py.check_signals()?;
            if reached < next {
                break; // the gas stopped (no events left, or a collapse)
            }
            at = reached;
        }
        Ok(())
    }

    /// Pair collisions per particle so far.
    #[getter]
    fn tau(&self) -> f64 {
        with_engine!(&*self.inner.lock().expect("not poisoned"), e => e.tau())
    }

    /// Physical time.
    #[getter]
    fn time(&self) -> f64 {
        with_engine!(&*self.inner.lock().expect("not poisoned"), e => e.time())
    }

    /// Granular temperature m⟨v²⟩/d.
    #[getter]
    fn temperature(&self) -> f64 {
        with_engine!(&*self.inner.lock().expect("not poisoned"), e => e.temperature())
    }

    /// Pair collisions so far.
    #[getter]
    fn collisions(&self) -> u64 {
        with_engine!(&*self.inner.lock().expect("not poisoned"), e => e.counters().pair_collisions)
    }

    /// Particles.
    #[getter]
    fn n(&self) -> usize {
        self.n
    }

    /// Dimension, 2 or 3.
    #[getter]
    fn dim(&self) -> usize {
        self.dim
    }

    /// Positions now, N × D, in the original particle order, wrapped into the box.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        match &*self.inner.lock().expect("not poisoned") {
            Inner::D2(e) => rows(py, e.positions()),
            Inner::D3(e) => rows(py, e.positions()),
        }
    }

    /// Velocities now, N × D, in the original particle order.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        match &*self.inner.lock().expect("not poisoned") {
            Inner::D2(e) => rows(py, e.velocities()),
            Inner::D3(e) => rows(py, e.velocities()),
        }
    }

    /// Angular velocities, in the original particle order: N × 1 (ω_z) in 2D, N × 3 in 3D; zero
    /// for smooth grains.
    #[getter]
    fn spins<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (spins, dim) = match &*self.inner.lock().expect("not poisoned") {
            Inner::D2(e) => (e.spins(), 2),
            Inner::D3(e) => (e.spins(), 3),
        };
        let width = if dim == 2 { 1 } else { 3 };
        let flat: Vec<f64> = spins.iter().flat_map(|w| w[3 - width..].to_vec()).collect();
        PyArray1::from_vec(py, flat).reshape([spins.len(), width])
    }

    /// The bulk observables now, as a dict: time, tau, temperature, kinetic and rotational
    /// energy, kurtosis, total momentum, and the event counters by kind.
    fn observe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        match &*self.inner.lock().expect("not poisoned") {
            Inner::D2(e) => fill(&d, &**e)?,
            Inner::D3(e) => fill(&d, &**e)?,
        }
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "<edmd.Simulation {}D N={} tau={:.3} T={:.4e}>",
            self.dim,
            self.n,
            self.tau(),
            self.temperature()
        )
    }
}

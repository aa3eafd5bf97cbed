//! A simulation's state as bytes, and back: what a checkpoint keeps of a run.
//!
//! Everything the next event depends on is kept as it is in memory: the trajectories, the event
//! slots, the calendar with its buckets, the cell heads, the neighbour lists, the clocks and the
//! velocity scale, the counters, the random stream, the collapse monitor and a vibrating floor's
//! phase. A simulation loaded from it therefore goes on bit for bit as the saved one would have,
//! wherever it was stopped between two events, with no rebuild that could file two equal times in
//! another order. What the
//! spec fixes (the box, the rule, the parameters) is not kept: the loader is a simulation built
//! from the same spec, and the saved box and particle count are checked against it. The encoding
//! is postcard's (little-endian floats, variable-length integers).

use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

use super::collapse::CollapseMonitor;
use super::neighbours::NeighbourLists;
use super::{Counters, Meta, Shear, Simulation, Thermostat, VibratingFloor};
use crate::calendar::Calendar;
use crate::{Boundary, CollisionRule, EdmdError, Particle, Vector};

/// The version of the layout below; a state of another version is refused.
pub const STATE_VERSION: u32 = 3;

/// Fixed-size arrays of any length as a serde tuple (serde itself covers lengths up to 32, and
/// not a length that is a const parameter).
pub(crate) mod array {
    use serde::de::{Deserialize, Deserializer, Error, SeqAccess, Visitor};
    use serde::ser::{Serialize, SerializeTuple, Serializer};

    pub fn serialize<S: Serializer, T: Serialize, const N: usize>(
        a: &[T; N],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        let mut t = s.serialize_tuple(N)?;
        for x in a {
            t.serialize_element(x)?;
        }
        t.end()
    }

    pub fn deserialize<'de, D: Deserializer<'de>, T: Deserialize<'de>, const N: usize>(
        d: D,
    ) -> Result<[T; N], D::Error> {
        struct Tuple<T, const N: usize>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for Tuple<T, N> {
            type Value = [T; N];
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "an array of {N}")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[T; N], A::Error> {
                let mut v = Vec::with_capacity(N);
                for k in 0..N {
                    v.push(
                        seq.next_element()?
                            .ok_or_else(|| A::Error::invalid_length(k, &self))?,
                    );
                }
                v.try_into().map_err(|_| A::Error::custom("array length"))
            }
        }
        d.deserialize_tuple(N, Tuple::<T, N>(std::marker::PhantomData))
    }
}

/// The state as it is written: borrowed from the simulation.
#[derive(Serialize)]
struct Saving<'a, const D: usize, S, C> {
    version: u32,
    box_len: &'a Vector<D>,
    particles: &'a [Particle<D>],
    meta: &'a [Meta<D>],
    rule_state: &'a [S],
    heads: &'a [u32],
    lists: Option<&'a NeighbourLists<D>>,
    calendar: &'a C,
    clocks: [f64; 6],
    counters: &'a Counters,
    rng: &'a Xoshiro256PlusPlus,
    monitor: &'a CollapseMonitor,
    maintenance: (u64, u64, f64),
    shear: &'a Shear,
    thermostat: &'a Thermostat,
    vibration: &'a VibratingFloor,
}

/// The state as it is read: the same fields, in the same order, owned.
#[derive(Deserialize)]
struct Loading<const D: usize, S, C> {
    #[allow(dead_code)] // read on its own, before the rest, by `load_state`
    version: u32,
    box_len: Vector<D>,
    particles: Vec<Particle<D>>,
    meta: Vec<Meta<D>>,
    rule_state: Vec<S>,
    heads: Vec<u32>,
    lists: Option<NeighbourLists<D>>,
    calendar: C,
    clocks: [f64; 6],
    counters: Counters,
    rng: Xoshiro256PlusPlus,
    monitor: CollapseMonitor,
    maintenance: (u64, u64, f64),
    shear: Shear,
    thermostat: Thermostat,
    vibration: VibratingFloor,
}

fn refused(reason: impl Into<String>) -> EdmdError {
    EdmdError::invalid("checkpoint", "state", reason)
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// The complete dynamic state, as bytes (see the module documentation).
    pub fn save_state(&self) -> Vec<u8> {
        let saving = Saving {
            version: STATE_VERSION,
            box_len: &self.box_len,
            particles: &self.particles,
            meta: &self.meta,
            rule_state: &self.rule_state,
            heads: self.grid.heads(),
            lists: self.nl.as_ref(),
            calendar: &self.calendar,
            clocks: [
                self.now,
                self.epoch,
                self.ln_scale,
                self.inv_scale,
                self.scale,
                self.t_ref,
            ],
            counters: &self.counters,
            rng: &self.rng,
            monitor: &self.monitor,
            maintenance: (
                self.next_maintenance,
                self.last_maintenance.0,
                self.last_maintenance.1,
            ),
            shear: &self.shear,
            thermostat: &self.thermostat,
            vibration: &self.vibration,
        };
        // Sized up front: growing by doubling copied the state several times (docs/benchmarks.md).
        let buffer = Vec::with_capacity(self.heap_bytes());
        postcard::to_extend(&saving, buffer).expect("the state serialises to memory")
    }

    /// Replaces the dynamic state with one [`Self::save_state`] wrote from a simulation built
    /// from the same parameters. Refuses, leaving `self` as it was, a state of another layout
    /// version, another particle count, box or neighbour strategy.
    pub fn load_state(&mut self, bytes: &[u8]) -> Result<(), EdmdError> {
        let version = postcard::take_from_bytes::<u32>(bytes).map(|v| v.0);
        if version != Ok(STATE_VERSION) {
            return Err(refused(format!(
                "layout version {version:?}, this build reads {STATE_VERSION}"
            )));
        }
        let s: Loading<D, R::State, C> =
            postcard::from_bytes(bytes).map_err(|e| refused(format!("unreadable: {e}")))?;
        let n = self.particles.len();
        if s.particles.len() != n || s.meta.len() != self.meta.len() || s.rule_state.len() != n {
            return Err(refused(format!(
                "{} particles, the spec has {n}",
                s.particles.len()
            )));
        }
        if s.box_len != self.box_len {
            return Err(refused(format!(
                "box {:?}, the spec's is {:?}",
                s.box_len.as_slice(),
                self.box_len.as_slice()
            )));
        }
        if s.heads.len() != self.grid.heads().len() || s.lists.is_some() != self.nl.is_some() {
            return Err(refused("another cell grid or neighbour strategy"));
        }
        self.particles = s.particles;
        self.meta = s.meta;
        self.rule_state = s.rule_state;
        self.grid.set_heads(s.heads);
        if let (Some(mut lists), Some(built)) = (s.lists, self.nl.as_ref()) {
            // How this processor scans is its own choice, not the saved one's.
            lists.wide = built.wide;
            lists.hint_partners = built.hint_partners;
            self.nl = Some(lists);
        }
        self.calendar = s.calendar;
        [
            self.now,
            self.epoch,
            self.ln_scale,
            self.inv_scale,
            self.scale,
            self.t_ref,
        ] = s.clocks;
        self.counters = s.counters;
        self.rng = s.rng;
        self.monitor = s.monitor;
        (
            self.next_maintenance,
            self.last_maintenance.0,
            self.last_maintenance.1,
        ) = s.maintenance;
        self.shear = s.shear;
        self.thermostat = s.thermostat;
        self.vibration = s.vibration;
        Ok(())
    }
}

//! How the simulation finds its neighbours, in one module: the cell grid (`grid.rs`) and cell mode's
//! search (`cell_search.rs`: the 3^D cells around a particle, its next crossing or wall contact,
//! the crossing), and the neighbour lists (`lists.rs`) with their builds (`list_gather.rs`,
//! `shear_lists.rs` across sliding faces), their search (`list_search.rs`, `wide_scan.rs` four
//! lanes at a time) and the geometry they share (`space.rs`).
//!
//! The strategy is fixed at construction and is a type, [`Cells`] or [`Lists`]: the event loop is
//! compiled once for each, and each predicts for itself ([`Search::search`],
//! [`Search::next_exit`]), so no search asks which one it is.

mod cell_search;
mod grid;
mod list_gather;
mod list_search;
mod lists;
mod shear_lists;
mod space;
mod wide_scan;

pub use grid::{CellGrid, MAX_PER_AXIS, NONE};
pub(crate) use lists::NeighbourLists;

use super::{Aux, SimParams, Simulation};
use crate::calendar::Calendar;
use crate::{Boundary, CollisionRule, EdmdError, ParticleInit, Vector};

/// How a simulation finds its neighbours, fixed at construction: [`Cells`] or [`Lists`]. The event
/// loop is compiled once for each, and the choice is made once per [`Simulation::step`] or per
/// run ([`Simulation::uses_lists`]), never inside a search: each strategy predicts for itself.
///
/// The cell grid serves both (list mode files shell centres in cells of side σ + δ); the lists are
/// list mode's own data, which the cell-mode loop never reads.
pub(crate) trait Search {
    /// Neighbour lists with a skin (else cell crossings).
    const LISTS: bool;

    /// Earliest contact of slot `i` (at now) with any neighbour. List mode seeks only contacts up
    /// to `horizon` (the particle's own next shell exit or wall contact, after which it searches
    /// again); cell mode finds the earliest whatever its time, since crossings rely on it.
    fn search<const D: usize, B: Boundary, R: CollisionRule, C: Calendar>(
        sim: &Simulation<D, B, R, C>,
        i: usize,
        horizon: f64,
    ) -> (f64, u32);

    /// Slot `i`'s next crossing (cell mode), shell exit (list mode) or wall contact.
    fn next_exit<const D: usize, B: Boundary, R: CollisionRule, C: Calendar>(
        sim: &Simulation<D, B, R, C>,
        i: usize,
    ) -> (f64, Aux);
}

/// Cell mode: crossings between cells of side ≥ the largest diameter.
#[derive(Debug)]
pub(crate) struct Cells;

/// Neighbour-list mode: shells of skin δ ([`SimParams::neighbour_skin`]).
#[derive(Debug)]
pub(crate) struct Lists;

/// The cell grid and, where the scene and density call for them, the neighbour lists: lists with
/// their own grid of cells of side σ + δ, or cells of one diameter.
pub(super) fn neighbour_search<const D: usize, B: Boundary>(
    box_len: &Vector<D>,
    particles: &[ParticleInit<D>],
    params: &SimParams,
    max_d: f64,
) -> Result<(CellGrid<D>, Option<NeighbourLists<D>>), EdmdError> {
    let skin = params.neighbour_skin * max_d;
    let list_grid = (skin > 0.0 && super::scene::lists_possible::<B>())
        .then(|| CellGrid::new(box_len, max_d + skin, max_d * params.cell_factor).ok())
        .flatten()
        .filter(super::scene::list_grid_fits::<D, B>);
    Ok(match list_grid {
        Some(g) => {
            let mut nl = NeighbourLists::new(particles.len(), skin, max_d);
            nl.same_radius = particles.iter().all(|p| p.radius == particles[0].radius);
            (g, Some(nl))
        }
        None => (
            CellGrid::new(box_len, max_d, max_d * params.cell_factor)?,
            None,
        ),
    })
}

//! Finishing the mesh extraction made: topological cleanup and smoothing
//! ([`improve`], thesis §5.1 "de-noise"), closed rows lower than the size
//! field removed ([`coarsen`](coarsen::coarsen)), local remeshing of the
//! regions still bad ([`remesh_bad`]), polishing ([`polish`]), corners
//! flat to rounding moved off the line ([`unflatten`]), and the final
//! check. [`crate::pipeline`] runs extraction and then [`finish`].
//!
//! Inside, `params` ([`FinishParams`]) is at the bottom, the steps
//! (`cleanup`, `coarsen` on cleanup, `remesh` on cleanup and params) above
//! it, and this file's [`finish`] on all of them. Smoothing is not here:
//! extraction uses it too, so [`crate::smooth`] sits at the mesh level
//! below both.

pub mod cleanup;
pub mod coarsen;
mod params;
pub mod remesh;

pub use params::FinishParams;

use crate::extract::{MeshError, Mesher};
use crate::geom::Point;
use crate::mesh::QuadMesh;
use crate::smooth::{polish, unflatten, untaper, LOCAL_ABOVE};
use cleanup::improve;
use coarsen::coarsen;
use remesh::remesh_bad;

/// The finished mesh of `mesher`'s run (a large one renumbered for memory
/// locality, [`QuadMesh::sort_spatially`]): cleaned up and smoothed
/// ([`improve`]; a mesh with front left is only smoothed), closed rows
/// lower than the mesher's size field removed ([`coarsen`]) and the
/// mesh cleaned up and smoothed again if any was, the regions of
/// quads still bad remeshed with the mesher's model and extraction
/// parameters ([`remesh_bad`]) and polished ([`polish`]), corners flat to
/// rounding moved off the line ([`unflatten`]), and checked ([`QuadMesh::check_finished`], or
/// [`QuadMesh::check_invariants`] for a partial mesh). Call after
/// [`Mesher::run`]; an unfinished mesh is returned as it stands.
pub fn finish(mesher: &Mesher, f: &FinishParams) -> Result<QuadMesh, MeshError> {
    finish_moved(mesher, f, Point::ZERO)
}

/// [`finish`] for a mesher run in a frame moved by `-origin` (as
/// [`crate::pipeline::mesh_boundary`] runs it,
/// [`Boundary::to_local`](crate::boundary::Boundary::to_local)): the mesh is moved
/// back by `origin` before it is checked, so the check is of the mesh as
/// written (quads far smaller than the domain's distance from the origin
/// may turn flat when moved).
pub fn finish_moved(
    mesher: &Mesher,
    f: &FinishParams,
    origin: Point,
) -> Result<QuadMesh, MeshError> {
    finish_phased(mesher, f, origin, |_| {})
}

/// The parts of finishing a mesh, in the order [`finish_phased`] reports
/// them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FinishPhase {
    /// Topological cleanup and smoothing ([`improve`]).
    Cleanup,
    /// Closed rows lower than the size field removed ([`coarsen`]).
    Coarsening,
    /// The regions still bad meshed again ([`remesh_bad`]).
    Remeshing,
    /// The last smoothing ([`polish`]).
    Smoothing,
    /// The final check.
    Checking,
}

impl FinishPhase {
    /// The phase as a progress line names it.
    pub fn name(self) -> &'static str {
        match self {
            FinishPhase::Cleanup => "cleanup and smoothing",
            FinishPhase::Coarsening => "coarsening",
            FinishPhase::Remeshing => "remeshing bad regions",
            FinishPhase::Smoothing => "smoothing",
            FinishPhase::Checking => "checking",
        }
    }
}

/// [`finish_moved`], `phase` called as each part of it starts.
pub fn finish_phased(
    mesher: &Mesher,
    f: &FinishParams,
    origin: Point,
    mut phase: impl FnMut(FinishPhase),
) -> Result<QuadMesh, MeshError> {
    let mut mesh = mesher.mesh().clone();
    mesh.compact();
    if mesh.quads.len() > LOCAL_ABOVE {
        mesh.sort_spatially();
    }
    let complete = mesher.is_done();
    phase(FinishPhase::Cleanup);
    improve(&mut mesh, complete, &f.cleanup, &f.smooth);
    if complete {
        let size = mesher.size();
        phase(FinishPhase::Coarsening);
        if coarsen(&mut mesh, |p| size.at(p), &f.coarsen).chords > 0 {
            phase(FinishPhase::Cleanup);
            improve(&mut mesh, complete, &f.cleanup, &f.smooth);
        }
        phase(FinishPhase::Remeshing);
        remesh_bad(&mut mesh, mesher.model(), mesher.params(), f);
        phase(FinishPhase::Smoothing);
        polish(&mut mesh, &f.smooth);
        if f.smooth.optimize_sweeps > 0 {
            untaper(&mut mesh);
        }
    }
    phase(FinishPhase::Checking);
    unflatten(&mut mesh);
    to_world(&mut mesh, origin);
    let checked = if complete {
        mesh.check_finished()
    } else {
        mesh.check_invariants(false)
    };
    checked.map_err(|problem| MeshError::Final { problem })?;
    Ok(mesh)
}

/// Moves a mesh made from [`Boundary::to_local`](crate::boundary::Boundary::to_local)'s boundary back by its
/// offset (exact at the boundary nodes).
pub fn to_world(mesh: &mut QuadMesh, origin: Point) {
    if origin != Point::ZERO {
        for p in &mut mesh.nodes {
            *p += origin;
        }
    }
}

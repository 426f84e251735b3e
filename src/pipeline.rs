//! The meshing pipeline: element extraction ([`crate::extract`], method §2)
//! and then finishing the mesh it made: topological cleanup and smoothing
//! ([`improve`], thesis §5.1 "de-noise"), closed rows lower than the size
//! field removed ([`coarsen`]), local remeshing of the regions
//! still bad ([`remesh_bad`]), corners flat to rounding moved off the line
//! ([`unflatten`]), and the final check. The command line, the editor and
//! the tests all mesh through here, so a mesh is finished the same way
//! wherever it is made.

use crate::boundary::Boundary;
use crate::cleanup::{improve, CleanupParams};
use crate::coarsen::{coarsen, CoarsenParams};
use crate::extract::{MeshError, MeshParams, Mesher, RunProgress, StepStats};
use crate::mesh::QuadMesh;
use crate::model::Model;
use crate::remesh::{remesh_bad, RemeshParams};
use crate::smooth::{polish, unflatten, SmoothParams, LOCAL_ABOVE};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// What finishing does to the mesh extraction made.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct FinishParams {
    /// Topological cleanup of a complete mesh before smoothing
    /// ([`crate::cleanup`]).
    pub cleanup: CleanupParams,
    /// Closed rows removed where the mesh runs finer than the size field,
    /// on a complete mesh ([`crate::coarsen`]).
    pub coarsen: CoarsenParams,
    /// Local remeshing of the regions around quads that cleanup and
    /// smoothing leave bad ([`crate::remesh`]), on a complete mesh.
    pub remesh: RemeshParams,
    /// Laplacian smoothing and optimisation ([`crate::smooth`]).
    pub smooth: SmoothParams,
}

impl FinishParams {
    pub const DEFAULT: FinishParams = FinishParams {
        cleanup: CleanupParams::DEFAULT,
        coarsen: CoarsenParams::DEFAULT,
        remesh: RemeshParams::DEFAULT,
        smooth: SmoothParams::DEFAULT,
    };
}

impl Default for FinishParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Extraction and finishing parameters together.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Params {
    pub extract: MeshParams,
    pub finish: FinishParams,
}

impl Params {
    pub const DEFAULT: Params = Params {
        extract: MeshParams::DEFAULT,
        finish: FinishParams::DEFAULT,
    };
}

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
    finish_moved(mesher, f, crate::geom::Point::ZERO)
}

/// [`finish`] for a mesher run in a frame moved by `-origin` (as
/// [`mesh_boundary`] runs it, [`Boundary::to_local`]): the mesh is moved
/// back by `origin` before it is checked, so the check is of the mesh as
/// written (quads far smaller than the domain's distance from the origin
/// may turn flat when moved).
pub fn finish_moved(
    mesher: &Mesher,
    f: &FinishParams,
    origin: crate::geom::Point,
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
    origin: crate::geom::Point,
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

/// Meshes a boundary to the end with `model` and `params`: extraction, then
/// finishing. Returns the mesh and the step counts; `progress` is called
/// after every step with how far extraction has got.
pub fn mesh_boundary(
    boundary: &Boundary,
    model: Arc<dyn Model>,
    params: &Params,
    progress: impl FnMut(RunProgress),
) -> Result<(QuadMesh, StepStats), MeshError> {
    let (local, origin) = boundary.to_local();
    let mut m = Mesher::new(local, model, params.extract.moved(origin));
    m.run(progress)?;
    let mesh = finish_moved(&m, &params.finish, origin)?;
    Ok((mesh, m.stats().clone()))
}

/// Moves a mesh made from [`Boundary::to_local`]'s boundary back by its
/// offset (exact at the boundary nodes).
pub fn to_world(mesh: &mut QuadMesh, origin: crate::geom::Point) {
    if origin != crate::geom::Point::ZERO {
        for p in &mut mesh.nodes {
            *p += origin;
        }
    }
}

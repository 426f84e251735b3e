//! The meshing pipeline: element extraction ([`crate::extract`], method §2)
//! and then finishing the mesh it made ([`crate::finish`]). The command
//! line, the editor and the tests all mesh through here, so a mesh is
//! finished the same way wherever it is made.

use crate::boundary::Boundary;
use crate::extract::{MeshError, MeshParams, Mesher, RunProgress, StepStats};
use crate::mesh::QuadMesh;
use crate::model::Model;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

pub use crate::finish::{finish, finish_moved, finish_phased, to_world, FinishParams, FinishPhase};

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

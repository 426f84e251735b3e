//! What the user chose to mesh with, and the parameters it gives.

use crate::extract::{MeshParams, Strategy};
use crate::finish::cleanup::CleanupParams;
use crate::finish::coarsen::CoarsenParams;
use crate::finish::remesh::RemeshParams;
use crate::pipeline::FinishParams;
use crate::smooth::SmoothParams;
use std::sync::Arc;

/// What the user chose to mesh with.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Settings {
    /// `default`, `rules`, `thesis` or a model file.
    pub model: String,
    pub strategy: Strategy,
    /// Input points: 5, 7, 9 or 11.
    pub points: usize,
    pub pure_model: bool,
    /// See [`MeshParams::fill_after_layers`].
    pub fill_after_layers: Option<u32>,
    /// Smoothing of the finished mesh.
    pub smooth: SmoothParams,
    /// Topological cleanup of the finished mesh.
    pub cleanup: CleanupParams,
    /// Chord coarsening of the finished mesh.
    pub coarsen: CoarsenParams,
    /// Local remeshing of the finished mesh's bad regions.
    pub remesh: RemeshParams,
    /// The size field a drawing's interior follows
    /// ([`MeshParams::size_target`]), as `quadex mesh part.dxf --size H`
    /// meshes it; none for nodes given. Set with the drawing, not saved (a
    /// project keeps the nodes cut from it).
    #[serde(skip)]
    pub size_target: Option<Arc<crate::extract::size::SizeTarget>>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            model: "default".into(),
            strategy: Strategy::B,
            points: 7,
            pure_model: false,
            fill_after_layers: MeshParams::DEFAULT.fill_after_layers,
            smooth: FinishParams::DEFAULT.smooth,
            cleanup: FinishParams::DEFAULT.cleanup,
            coarsen: FinishParams::DEFAULT.coarsen,
            remesh: FinishParams::DEFAULT.remesh,
            size_target: None,
        }
    }
}

impl Settings {
    /// The extraction parameters of these settings.
    pub fn params(&self) -> MeshParams {
        MeshParams {
            strategy: self.strategy,
            leading_points: (self.points - 1) / 2,
            pure_model: self.pure_model,
            fill_after_layers: self.fill_after_layers,
            size_target: self.size_target.as_deref().cloned(),
            ..MeshParams::DEFAULT
        }
    }

    /// What finishing the mesh does.
    pub fn finishing(&self) -> FinishParams {
        FinishParams {
            cleanup: self.cleanup,
            coarsen: self.coarsen,
            remesh: self.remesh,
            smooth: self.smooth,
        }
    }

    /// True when `other` differs from these settings only in what
    /// finishing does (the steps stay).
    pub fn same_steps(&self, other: &Settings) -> bool {
        Settings {
            smooth: self.smooth,
            cleanup: self.cleanup,
            coarsen: self.coarsen,
            remesh: self.remesh,
            ..other.clone()
        } == *self
    }
}

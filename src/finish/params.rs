//! What finishing does, [`FinishParams`], and the remeshing parameters it
//! holds: their own file so that `remesh`, which takes a `FinishParams`
//! for the patches it meshes again, and `finish`, which calls `remesh`,
//! both import them from below.

use super::cleanup::CleanupParams;
use super::coarsen::CoarsenParams;
use crate::smooth::SmoothParams;
use serde::{Deserialize, Serialize};

/// Local remeshing parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RemeshParams {
    /// Quads with a scaled Jacobian below this are remeshed with their
    /// surroundings (default 0.7; 0 turns remeshing off).
    pub below: f64,
    /// Largest cavity, in rings of quads around the bad one (default 4;
    /// cavities of 2 rings up to this are tried, the smallest that leaves
    /// no bad quad wins).
    pub rings: usize,
    /// At most this many bad quads are tried per mesh (default 200), which
    /// bounds the time remeshing can take on a large mesh.
    pub max_regions: usize,
}

impl RemeshParams {
    pub const DEFAULT: RemeshParams = RemeshParams {
        below: 0.7,
        rings: 4,
        max_regions: 200,
    };
    /// No remeshing.
    pub const OFF: RemeshParams = RemeshParams {
        below: 0.0,
        rings: 4,
        max_regions: 200,
    };
}

impl Default for RemeshParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What finishing does to the mesh extraction made.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct FinishParams {
    /// Topological cleanup of a complete mesh before smoothing
    /// ([`crate::finish::cleanup`]).
    pub cleanup: CleanupParams,
    /// Closed rows removed where the mesh runs finer than the size field,
    /// on a complete mesh ([`crate::finish::coarsen`]).
    pub coarsen: CoarsenParams,
    /// Local remeshing of the regions around quads that cleanup and
    /// smoothing leave bad ([`crate::finish::remesh`]), on a complete mesh.
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

    /// The defaults with the switches the command line and the Python
    /// module offer: `smooth` Laplacian sweeps (0: no smoothing at all,
    /// neither Laplacian nor optimisation), cleanup and chord coarsening
    /// on or off, and remeshing below scaled Jacobian `remesh_below`
    /// (0: off).
    pub fn switched(smooth: usize, cleanup: bool, coarsen: bool, remesh_below: f64) -> Self {
        FinishParams {
            smooth: if smooth == 0 {
                SmoothParams::OFF
            } else {
                SmoothParams {
                    iterations: smooth,
                    ..SmoothParams::DEFAULT
                }
            },
            cleanup: if cleanup {
                CleanupParams::DEFAULT
            } else {
                CleanupParams::OFF
            },
            coarsen: if coarsen {
                CoarsenParams::DEFAULT
            } else {
                CoarsenParams::OFF
            },
            remesh: RemeshParams {
                below: remesh_below,
                ..RemeshParams::DEFAULT
            },
        }
    }
}

impl Default for FinishParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

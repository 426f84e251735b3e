//! Parameters of element extraction (method §2): the reference-point
//! strategy and window, the guard's angle limits, snapping, the scores at
//! which an element is taken or waits, and when the region fill takes over.
//! Finishing (cleanup, smoothing, remeshing) has its own parameters in
//! [`crate::pipeline`].

use serde::{Deserialize, Serialize};

/// Order in which reference points are taken (thesis §5.1, Figure 40).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Strategy {
    /// Next valid reference point beside the current one on the new front.
    A,
    /// Every valid reference point of the current layer first, then the
    /// next layer (fewer bad elements).
    B,
}

/// Parameters of the extraction loop. Angles in degrees.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MeshParams {
    /// Reference point order (default B).
    pub strategy: Strategy,
    /// Leading points per side, `N` (default 3: 7 input points). A model
    /// that needs a fixed `N` overrides it.
    pub leading_points: usize,
    /// Window of front angles that make a reference point (default
    /// [45, 135]); smaller angles are sharp corners, taken first.
    pub reference_angle: [f64; 2],
    /// Front angles up to this (beyond the reference window) are taken
    /// too, after every reference point of their band and layer: a row
    /// whose end opened a little wider than the window goes on instead of
    /// stopping (default 150).
    pub row_angle: f64,
    /// Smallest new quad corner the guard accepts (default 30).
    pub min_corner: f64,
    /// Largest new quad corner the guard accepts (default 150).
    pub max_corner: f64,
    /// Smallest angle a step may leave on the front (default 20).
    pub min_front_angle: f64,
    /// A predicted Pn within this fraction of the local edge length of a
    /// front node is snapped to it first (default 0.5).
    pub snap_radius: f64,
    /// An element whose score (guard's quality in [0, 1]) reaches this is
    /// taken at once; the model's own element first (default 0.5).
    pub accept_score: f64,
    /// Below this score a reference point waits while others do better
    /// (default 0.25).
    pub defer_score: f64,
    /// A sharp front corner below this angle is closed by a seam when the
    /// merge keeps the mesh valid (default 30).
    pub seam_angle: f64,
    /// Stop with [`MeshError::StepLimit`] after this many steps (`None`:
    /// a bound derived from the boundary's area and shortest segment).
    pub max_steps: Option<usize>,
    /// Fill the region left with [`fill::fill_region`] when extraction
    /// cannot go on or has used its step budget (default true). Off, such a
    /// run ends with [`MeshError::Stuck`] or [`MeshError::StepLimit`].
    pub fill: bool,
    /// With `Some(k)`, once every reference point left lies on layer `k`
    /// or deeper (strategy B's layers: the boundary is layer 0), the region
    /// left is filled with [`fill::fill_region`] instead of being extracted
    /// further; a fill that fails is retried later while extraction goes on.
    /// `None` (the default): extraction to the end, the fill only as the
    /// last resort.
    pub fill_after_layers: Option<u32>,
    /// Pure model: the guard takes the model's element as predicted or
    /// rejects it (no snapping, no other type, no corrected Pn). A rejected
    /// prediction is counted ([`StepReport::rejected`],
    /// [`StepStats::rejected_predictions`]) and the next reference point is
    /// tried; the rule-based element, closure and fill still finish the
    /// mesh, and their steps are counted apart (default false).
    pub pure_model: bool,
    /// A row whose front edges are this many times finer than the size
    /// field wants is made coarser by transition elements (three front
    /// edges to one, [`super::transition`]), one per as many ordinary
    /// elements as that ratio asks; `None` turns them off (default 1.3).
    pub transition_ratio: Option<f64>,
    /// A loop that is a logical rectangle (four corners, opposite sides of
    /// equal edge counts) at most this many elements across is closed in
    /// one step by a mapped grid ([`super::mapped`]), as is, with
    /// [`MappedTuning::graded_grid`](super::tuning::MappedTuning::graded_grid)
    /// on, a loop of the given boundary graded past
    /// [`super::mapped::GRADED_SPREAD`] that has a
    /// [`super::mapped::transfinite`] grid; `None` turns both off
    /// (default 4).
    pub mapped_rows: Option<usize>,
    /// The size field to follow inside the domain (a drawing's target
    /// size and local sizes, [`super::size::SizeTarget`]), in the
    /// boundary's frame; `None` (the default): the boundary's spacing
    /// interpolated inside.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size_target: Option<super::size::SizeTarget>,
    /// The heuristics' constants ([`super::Tuning`]; default
    /// [`super::Tuning::DEFAULT`]). Written to files only where they
    /// differ from the defaults.
    #[serde(skip_serializing_if = "super::Tuning::is_default")]
    pub tuning: super::Tuning,
}

impl MeshParams {
    pub const DEFAULT: MeshParams = MeshParams {
        strategy: Strategy::B,
        leading_points: 3,
        reference_angle: [45.0, 135.0],
        row_angle: 150.0,
        min_corner: 30.0,
        max_corner: 150.0,
        min_front_angle: 20.0,
        snap_radius: 0.5,
        accept_score: 0.5,
        defer_score: 0.25,
        seam_angle: 30.0,
        max_steps: None,
        fill: true,
        fill_after_layers: None,
        pure_model: false,
        transition_ratio: Some(1.3),
        mapped_rows: Some(4),
        size_target: None,
        tuning: super::Tuning::DEFAULT,
    };
}

impl MeshParams {
    /// These parameters for a boundary moved by `-origin`
    /// ([`crate::Boundary::to_local`]): the size target moved with it.
    pub fn moved(&self, origin: crate::geom::Point) -> MeshParams {
        MeshParams {
            size_target: self.size_target.as_ref().map(|t| t.moved(origin)),
            ..self.clone()
        }
    }
}

impl Default for MeshParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

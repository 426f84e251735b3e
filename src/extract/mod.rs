//! Element extraction (method §2; thesis §2.1.2, §5.1): the [`Mesher`] cuts
//! one quad at a time off the front. Each step picks a reference point P0
//! (strategy A or B, sharp corners first), normalises its leading points,
//! asks the model for `[type, Pn]`, and commits the element if the guard
//! accepts it; otherwise it tries the remedies in order: a snapped Pn, the
//! other types, a corrected Pn, the next reference point, and finally a
//! rule-based element. Loops of 4 and 6 nodes are closed with the final
//! patterns; a loop that no element can reduce is split along a chord into
//! two even loops. Once the reference points left lie on layer
//! [`MeshParams::fill_after_layers`] or deeper, when nothing reduces the
//! front any more, or when the step budget is spent, the region left is
//! filled by [`fill`].
//!
//! The same step API drives the command line, the tests and the editor.

pub mod closure;
pub mod fill;
pub mod guard;

use crate::boundary::Boundary;
use crate::cleanup::{improve, CleanupParams};
use crate::front::{Front, SlotId};
use crate::geom::{ccw_angle, Point};
use crate::mesh::QuadMesh;
use crate::model::{rules, ElementType, Model, Prediction, RulesModel};
use crate::normalize::{Frame, LeadingPoints};
use crate::remesh::{remesh_bad, RemeshParams};
use crate::smooth::{unflatten, SmoothParams};
use guard::{Corner, Limits, Scratch};
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::f64::consts::PI;
use std::sync::Arc;
use thiserror::Error;

/// Loops up to this many nodes are split along a chord before a square is
/// cut on them.
const SMALL_LOOP: usize = 48;

/// Steps allowed before the region left is filled, per element a uniform
/// mesh at the median boundary segment would have (plus one per boundary
/// node and 200).
const FILL_BUDGET: f64 = 2.0;

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
    /// further; a fill that fails is retried later while extraction goes on
    /// (default `Some(2)`). `None`: extraction to the end.
    pub fill_after_layers: Option<u32>,
    /// Laplacian smoothing after extraction.
    pub smooth: SmoothParams,
    /// Topological cleanup of a complete mesh before smoothing
    /// ([`cleanup`](crate::cleanup)).
    pub cleanup: CleanupParams,
    /// Local remeshing of the regions around quads that cleanup and
    /// smoothing leave bad ([`remesh`](crate::remesh)), on a complete mesh.
    pub remesh: RemeshParams,
    /// Pure model: the guard takes the model's element as predicted or
    /// rejects it (no snapping, no other type, no corrected Pn). A rejected
    /// prediction is counted ([`StepReport::rejected`],
    /// [`StepStats::rejected_predictions`]) and the next reference point is
    /// tried; the rule-based element, closure and fill still finish the
    /// mesh, and their steps are counted apart (default false).
    pub pure_model: bool,
}

impl MeshParams {
    pub const DEFAULT: MeshParams = MeshParams {
        strategy: Strategy::B,
        leading_points: 3,
        reference_angle: [45.0, 135.0],
        min_corner: 30.0,
        max_corner: 150.0,
        min_front_angle: 20.0,
        snap_radius: 0.5,
        accept_score: 0.5,
        defer_score: 0.25,
        seam_angle: 30.0,
        max_steps: None,
        fill: true,
        fill_after_layers: Some(2),
        smooth: SmoothParams::DEFAULT,
        cleanup: CleanupParams::DEFAULT,
        remesh: RemeshParams::DEFAULT,
        pure_model: false,
    };
}

/// What [`Mesher::finish_with`] does to a mesh after extraction: the parts
/// of [`MeshParams`] that change the finished mesh without stepping again.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinishParams {
    pub cleanup: CleanupParams,
    pub remesh: RemeshParams,
    pub smooth: SmoothParams,
}

impl MeshParams {
    /// The finishing parameters.
    pub fn finishing(&self) -> FinishParams {
        FinishParams {
            cleanup: self.cleanup,
            remesh: self.remesh,
            smooth: self.smooth,
        }
    }
}

impl Default for MeshParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why meshing stopped.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeshError {
    #[error("front loop {loop_index} (at node {node}) cannot be reduced: no valid element, closure or chord split")]
    Stuck { loop_index: u32, node: u32 },
    #[error("step limit of {limit} reached with {remaining} front nodes left")]
    StepLimit { limit: usize, remaining: usize },
    #[error("the correction at node {node} is not a valid element")]
    InvalidCorrection { node: u32 },
    #[error("node {node} is not on the front")]
    NotOnFront { node: u32 },
    #[error("the finished mesh is not valid: {problem}")]
    Final {
        problem: crate::mesh::InvariantError,
    },
}

/// What the guard had to do to the model's prediction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Remedy {
    /// The model's element was accepted as predicted.
    None,
    /// Pn was snapped onto a nearby front node.
    Snapped,
    /// Another element type was used.
    OtherType,
    /// Pn was replaced by the rule-based position.
    CorrectedPn,
    /// The rule-based element with relaxed limits.
    RuleBased,
    /// Not a model step (square cut, closure, chord split, correction).
    NotApplicable,
}

/// The kind of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum StepKind {
    /// One element of type 0, 1 or 2 (or a snapped type 0).
    Element,
    /// A square cut on the shortest front edge (no reference point).
    Square,
    /// A 4-node loop closed by one quad.
    Close4,
    /// A 6-node loop closed by a final pattern.
    Close6,
    /// The interior front nodes of a stuck loop were moved to straighten it.
    Relax,
    /// A sharp front corner closed by merging its two neighbours (the
    /// seam of paving).
    Seam,
    /// A loop split along a chord.
    Split,
    /// Elements around a loop that could not be reduced were removed to
    /// give it room.
    RipUp,
    /// The region left was filled by a ring and a split triangulation.
    Fill,
    /// An element given by the user.
    Correction,
}

/// What one step did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StepReport {
    pub index: usize,
    pub kind: StepKind,
    /// Reference point P0 (node id).
    pub reference: Option<u32>,
    /// Leading points as node ids, thesis order `l_N..l1, P0, r1..r_N`.
    pub leading: Vec<u32>,
    /// The model's raw output (normalised frame).
    pub prediction: Option<Prediction>,
    /// The model's Pn in world coordinates.
    pub predicted_pn: Option<Point>,
    /// The type of the element committed.
    pub element_type: Option<ElementType>,
    pub remedy: Remedy,
    /// Reference points passed over before this one succeeded.
    pub skipped: usize,
    /// Closure pattern ('a', 'b', 'c') for 6-node loops.
    pub pattern: Option<char>,
    pub quads: Vec<[u32; 4]>,
    pub new_nodes: Vec<u32>,
    /// Quads removed (rip-up steps, and a fill after rewinding).
    pub removed: usize,
    /// Pure-model mode: the model's predictions the guard rejected before
    /// this step.
    pub rejected: usize,
}

impl StepReport {
    /// The element's Pn as a node: the corner of its (first) quad opposite
    /// the reference point; for types 1 and 2 that is P_r2 or P_l2.
    pub fn pn_node(&self) -> Option<u32> {
        let p0 = self.reference?;
        let q = self.quads.first()?;
        let k = q.iter().position(|&v| v == p0)?;
        Some(q[(k + 2) % 4])
    }
}

/// Step counts by kind, type and remedy.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepStats {
    pub steps: usize,
    pub by_kind: std::collections::BTreeMap<String, usize>,
    pub by_type: [usize; 3],
    pub by_remedy: std::collections::BTreeMap<String, usize>,
    pub skipped_references: usize,
    /// Pure-model mode: predictions the guard rejected.
    pub rejected_predictions: usize,
}

impl StepStats {
    /// Pure-model mode: the model's elements the guard accepted as
    /// predicted, and all the model's predictions (accepted + rejected).
    pub fn model_valid(&self) -> (usize, usize) {
        let ok = self.by_remedy.get("None").copied().unwrap_or(0);
        (ok, ok + self.rejected_predictions)
    }

    fn record(&mut self, r: &StepReport) {
        self.steps += 1;
        *self.by_kind.entry(format!("{:?}", r.kind)).or_default() += 1;
        if let Some(t) = r.element_type {
            self.by_type[t as usize] += 1;
        }
        if r.kind == StepKind::Element {
            *self.by_remedy.entry(format!("{:?}", r.remedy)).or_default() += 1;
        }
        self.skipped_references += r.skipped;
        self.rejected_predictions += r.rejected;
    }
}

/// An element forced by the user at a reference node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Correction {
    /// Reference point P0 (node id on the front).
    pub reference: u32,
    pub element_type: ElementType,
    /// Pn (world) for type 0.
    pub pn: Option<Point>,
    /// Close type 0 onto this front node instead of a new one.
    pub snap_to: Option<u32>,
}

/// One recorded step, as [`Mesher::actions`] lists them: replaying the
/// actions of a run with [`Mesher::take`] rebuilds it (steps are
/// deterministic), which is how undo works and how a project file keeps a
/// mesh that can be stepped on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Action {
    /// A step chosen by the mesher.
    Auto,
    /// An element given by the user.
    Correction(Correction),
    /// A fill taken after rewinding (see [`Mesher::rewind_and_fill`]).
    Fill,
}

/// Result of [`Mesher::step`].
#[derive(Clone, Debug, PartialEq)]
pub enum StepOutcome {
    Stepped(Box<StepReport>),
    Done,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Entry {
    class: u8,
    layer: u32,
    seq: u64,
    slot: SlotId,
    version: u32,
}

impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        // Max-heap: sharp class first, lower layer first, newest first.
        o.class
            .cmp(&self.class)
            .then(o.layer.cmp(&self.layer))
            .then(self.seq.cmp(&o.seq))
    }
}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// A candidate element at a reference slot.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Cand {
    New { s: SlotId, pn: Point },
    Snap { s: SlotId, q: SlotId },
    Right { s: SlotId },
    Left { s: SlotId },
}

/// The element extraction loop over one boundary.
#[derive(Clone)]
pub struct Mesher {
    /// The model the run started with (replays start from it).
    initial_model: Arc<dyn Model>,
    /// Models set with [`Mesher::set_model`], each with the number of
    /// actions taken before it.
    model_changes: Vec<(usize, Arc<dyn Model>)>,
    boundary: Boundary,
    params: MeshParams,
    model: Arc<dyn Model>,
    mesh: QuadMesh,
    front: Front,
    queue: BinaryHeap<Entry>,
    version: Vec<u32>,
    seq: u64,
    history: Vec<Action>,
    /// Actions undone, the most recent last: what [`Mesher::redo`] takes
    /// again. A new step or correction clears it.
    undone: Vec<Action>,
    stats: StepStats,
    scratch: Scratch,
    step_limit: usize,
    rules: RulesModel,
    /// Loops to check for a first row (no reference point on them).
    row_start: Vec<u32>,
    rip_ups: usize,
    /// Quads incident to each node.
    incident: Vec<Vec<u32>>,
    relaxes: usize,
    /// Relaxations since the last other step.
    relax_streak: usize,
    /// Steps after which the region left is filled.
    fill_after: usize,
    /// No fill is tried before this step (set after a fill fails).
    fill_retry_at: usize,
    /// Set while history is being replayed (no rewinding then).
    replaying: bool,
    /// A rewind has been tried.
    rewound: bool,
    /// Pure-model rejections since the last step.
    rejected: usize,
    /// Pure-model: the leading points (node ids) of every rejected
    /// prediction, so a prediction met again is counted once.
    rejected_inputs: std::collections::BTreeSet<Vec<u32>>,
}

/// The element chosen at a reference point.
#[derive(Clone, Debug)]
struct Chosen {
    cand: Cand,
    remedy: Remedy,
    score: f64,
    prediction: Prediction,
    frame: Frame,
    leading: Vec<u32>,
}

/// Scores closer than this are a tie, which the first candidate wins: a
/// model whose outputs differ in the last digits (a refit, another
/// machine's rounding) then makes the same choices.
const SCORE_TIE: f64 = 1e-6;

/// True when score `a` is better than `b` by more than a tie.
fn beats(a: f64, b: f64) -> bool {
    a > b + SCORE_TIE
}

impl Chosen {
    /// Keeps `self` in `best` if it scores higher (the first wins ties).
    fn keep_if_best(self, best: &mut Option<Chosen>) {
        if best.as_ref().is_none_or(|b| beats(self.score, b.score)) {
            *best = Some(self);
        }
    }
}

impl Mesher {
    /// A mesher over `boundary` with `model` and `params`.
    pub fn new(boundary: Boundary, model: Arc<dyn Model>, params: MeshParams) -> Mesher {
        let mesh = QuadMesh::from_boundary(&boundary);
        let h = boundary.median_segment();
        let front = Front::new(&mesh.loops, &mesh.nodes, 2.0 * h);
        let mut min_seg = f64::INFINITY;
        for (a, b) in boundary.segments() {
            min_seg = min_seg.min(boundary.points[a].distance(boundary.points[b]));
        }
        let est = (boundary.area() / (min_seg * min_seg)).min(1e9) as usize;
        let work = est.max(boundary.node_count());
        let step_limit = params.max_steps.unwrap_or(8 * work + 10_000);
        let mut m = Mesher {
            step_limit,
            fill_after: (FILL_BUDGET * (boundary.area() / (h * h)).min(1e9)) as usize
                + boundary.node_count()
                + 200,
            fill_retry_at: 0,
            replaying: false,
            rewound: false,
            rejected: 0,
            rejected_inputs: Default::default(),
            boundary,
            params,
            initial_model: model.clone(),
            model_changes: Vec::new(),
            model,
            mesh,
            front,
            queue: BinaryHeap::new(),
            version: Vec::new(),
            seq: 0,
            history: Vec::new(),
            undone: Vec::new(),
            stats: StepStats::default(),
            scratch: Scratch::default(),
            rules: RulesModel::DEFAULT,
            row_start: Vec::new(),
            rip_ups: 0,
            incident: Vec::new(),
            relaxes: 0,
            relax_streak: 0,
        };
        m.row_start = m.front.live_loops().collect();
        m.incident = vec![Vec::new(); m.mesh.nodes.len()];
        for s in 0..m.front.slots.len() as SlotId {
            m.push(s);
        }
        m
    }

    /// The mesh so far (unsmoothed).
    pub fn mesh(&self) -> &QuadMesh {
        &self.mesh
    }
    /// The front.
    pub fn front(&self) -> &Front {
        &self.front
    }
    pub fn boundary(&self) -> &Boundary {
        &self.boundary
    }
    pub fn params(&self) -> &MeshParams {
        &self.params
    }
    pub fn model(&self) -> &Arc<dyn Model> {
        &self.model
    }
    pub fn stats(&self) -> &StepStats {
        &self.stats
    }
    /// Steps taken so far.
    pub fn steps(&self) -> usize {
        self.history.len()
    }
    /// Quads that use node `v`.
    pub fn quads_at(&self, v: u32) -> &[u32] {
        self.incident
            .get(v as usize)
            .map(Vec::as_slice)
            .unwrap_or(&[])
    }

    /// True when the front is empty.
    pub fn is_done(&self) -> bool {
        self.front.is_empty()
    }

    /// Checks the front and the partial mesh.
    pub fn check_invariants(&self) -> Result<(), crate::mesh::InvariantError> {
        self.front
            .check_invariants(&self.mesh.nodes)
            .map_err(crate::mesh::InvariantError::Front)?;
        for (k, q) in self.mesh.quads.iter().enumerate() {
            for &v in q {
                if !self.quads_at(v).contains(&(k as u32)) {
                    return Err(crate::mesh::InvariantError::Front(format!(
                        "quad {k} is missing from node {v}'s incidence"
                    )));
                }
            }
        }
        // Quads and the region the front still bounds tile the domain.
        let meshed: f64 = self
            .mesh
            .quads
            .iter()
            .map(|q| crate::geom::polygon_area(self.mesh.corners(q)))
            .sum();
        let open: f64 = self
            .front
            .live_loops()
            .map(|l| {
                crate::geom::polygon_area(
                    self.front
                        .loop_slots(l)
                        .iter()
                        .map(|&s| self.mesh.nodes[self.front.node(s) as usize]),
                )
            })
            .sum();
        let domain = self.boundary.area();
        if (meshed + open - domain).abs() > 1e-9 * domain.abs() {
            return Err(crate::mesh::InvariantError::Area {
                covered: meshed + open,
                domain,
            });
        }
        self.mesh.check_invariants(self.is_done())
    }

    fn limits(&self) -> Limits {
        Limits {
            min_corner: self.params.min_corner.to_radians(),
            max_corner: self.params.max_corner.to_radians(),
            min_front: self.params.min_front_angle.to_radians(),
        }
    }

    fn leading_n(&self) -> usize {
        self.model
            .leading_points()
            .unwrap_or(self.params.leading_points)
            .max(2)
    }

    /// (Re)queues slot `s` if its angle makes it a reference point.
    fn push(&mut self, s: SlotId) {
        let i = s as usize;
        if self.version.len() <= i {
            self.version.resize(i + 1, 0);
        }
        self.version[i] = self.version[i].wrapping_add(1);
        let sl = *self.front.slot(s);
        if !sl.alive {
            return;
        }
        let a = self.front.angle(s, &self.mesh.nodes).to_degrees();
        let [lo, hi] = self.params.reference_angle;
        let class = if a < lo {
            0
        } else if a <= hi {
            1
        } else {
            return;
        };
        self.seq += 1;
        let layer = match self.params.strategy {
            Strategy::A => 0,
            Strategy::B => sl.layer,
        };
        self.queue.push(Entry {
            class,
            layer,
            seq: self.seq,
            slot: s,
            version: self.version[i],
        });
    }

    fn world(&self, s: SlotId) -> Point {
        self.mesh.nodes[self.front.node(s) as usize]
    }

    /// Leading slots `l_N..l1, P0, r1..r_N` of reference slot `s`.
    fn leading_slots(&self, s: SlotId, n: usize) -> Vec<SlotId> {
        let mut v = vec![s; 2 * n + 1];
        let (mut l, mut r) = (s, s);
        for k in 1..=n {
            l = self.front.prev(l);
            r = self.front.next(r);
            v[n - k] = l;
            v[n + k] = r;
        }
        v
    }

    fn normalised(&self, slots: &[SlotId]) -> (Frame, LeadingPoints) {
        let n = slots.len() / 2;
        let p0 = self.world(slots[n]);
        let frame = Frame::new(p0, self.world(slots[n + 1]));
        let left: Vec<Point> = (1..=n).map(|k| self.world(slots[n - k])).collect();
        let right: Vec<Point> = (1..=n).map(|k| self.world(slots[n + k])).collect();
        (frame, LeadingPoints::normalise(&frame, &left, &right))
    }

    /// The guard on one candidate: its score when it passes.
    fn check(&mut self, c: Cand, limits: Limits) -> Option<f64> {
        let f = &self.front;
        let n = self.front.loop_len(match c {
            Cand::New { s, .. } | Cand::Snap { s, .. } | Cand::Right { s } | Cand::Left { s } => s,
        });
        let (corners, consumed): ([Corner; 4], Vec<SlotId>) = match c {
            Cand::New { s, pn } => {
                let (l, r) = (f.prev(s), f.next(s));
                (
                    [
                        Corner::Full(s),
                        Corner::Partial(r),
                        Corner::New(pn),
                        Corner::Partial(l),
                    ],
                    vec![l, s],
                )
            }
            Cand::Snap { s, q } => {
                let (l, r) = (f.prev(s), f.next(s));
                if q == s || q == l || q == r || q == f.next(r) || q == f.prev(l) {
                    return None;
                }
                (
                    [
                        Corner::Full(s),
                        Corner::Partial(r),
                        Corner::Partial(q),
                        Corner::Partial(l),
                    ],
                    vec![l, s],
                )
            }
            Cand::Right { s } => {
                if n < 6 {
                    return None;
                }
                let (l, r) = (f.prev(s), f.next(s));
                let r2 = f.next(r);
                (
                    [
                        Corner::Full(s),
                        Corner::Full(r),
                        Corner::Partial(r2),
                        Corner::Partial(l),
                    ],
                    vec![l, s, r],
                )
            }
            Cand::Left { s } => {
                if n < 6 {
                    return None;
                }
                let (l, r) = (f.prev(s), f.next(s));
                let l2 = f.prev(l);
                (
                    [
                        Corner::Full(s),
                        Corner::Partial(r),
                        Corner::Partial(l2),
                        Corner::Full(l),
                    ],
                    vec![l2, l, s],
                )
            }
        };
        let passed = guard::check(
            f,
            &self.mesh.nodes,
            corners,
            &consumed,
            limits,
            &mut self.scratch,
        )?;
        let p = passed.corners;
        let ids = corners.map(|c| match c {
            Corner::Full(s) | Corner::Partial(s) => Some(self.front.node(s)),
            Corner::New(_) => None,
        });
        if !self.pinned_corners_turn(p, ids) {
            return None;
        }
        if let Cand::Snap { s, q } = c {
            // The quad's corner at X must sit inside X's front wedge with
            // room on both sides, and a split must leave two even loops.
            let x = p[2];
            let (qn, qp) = (self.world(f.next(q)), self.world(f.prev(q)));
            let a1 = ccw_angle(x, qn, p[3]);
            let a2 = ccw_angle(x, p[1], qp);
            let corner = ccw_angle(x, p[3], p[1]);
            let wedge = f.angle(q, &self.mesh.nodes);
            if (a1 + corner + a2 - wedge).abs() > 1e-9
                || a1 < limits.min_front
                || a2 < limits.min_front
            {
                return None;
            }
            if f.slot(q).loop_id == f.slot(s).loop_id {
                let d = self.loop_distance(s, q);
                if d % 2 == 1 || d < 4 || n - d < 4 {
                    return None;
                }
            }
        }
        Some(passed.score)
    }

    /// Shorter distance along the loop between two slots of one loop.
    fn loop_distance(&self, a: SlotId, b: SlotId) -> usize {
        let n = self.front.loop_len(a);
        let (mut x, mut y) = (a, a);
        for k in 1..=n / 2 {
            x = self.front.next(x);
            y = self.front.prev(y);
            if x == b || y == b {
                return k;
            }
        }
        n
    }

    /// The nearest front node to `p` within `radius` (excluding the reference
    /// point's own neighbours), as a slot.
    fn snap_target(&mut self, s: SlotId, p: Point, radius: f64) -> Option<SlotId> {
        let r = Point::splat(radius);
        self.front.edges_near(p - r, p + r, &mut self.scratch.near);
        let own = [s, self.front.prev(s), self.front.next(s)];
        let mut best: Option<(f64, SlotId)> = None;
        for &e in &self.scratch.near {
            if own.contains(&e) {
                continue;
            }
            let d = self.world(e).distance(p);
            if d <= radius && best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, e));
            }
        }
        best.map(|(_, e)| e)
    }

    /// Candidate list at reference slot `s`, model first, then remedies.
    fn candidates(&mut self, s: SlotId, pred: Prediction, frame: &Frame) -> Vec<(Cand, Remedy)> {
        let f = &self.front;
        let h = 0.5 * (self.world(s).distance(self.world(f.prev(s))) + frame.scale);
        let mut out = Vec::with_capacity(8);
        let pn_world = frame.to_world(pred.pn);
        let model_cand = match pred.element_type {
            ElementType::New => Cand::New { s, pn: pn_world },
            ElementType::Right => Cand::Right { s },
            ElementType::Left => Cand::Left { s },
        };
        if self.params.pure_model {
            return vec![(model_cand, Remedy::None)];
        }
        let snap_pn = match pred.element_type {
            ElementType::New => Some(pn_world),
            _ => None,
        };
        if let Some(pn) = snap_pn {
            if let Some(q) = self.snap_target(s, pn, self.params.snap_radius * h) {
                out.push((Cand::Snap { s, q }, Remedy::Snapped));
            }
        }
        out.push((model_cand, Remedy::None));
        for t in [Cand::Right { s }, Cand::Left { s }] {
            if t != model_cand {
                out.push((t, Remedy::OtherType));
            }
        }
        // Corrected Pn: the rule-based position, and the same nearer in.
        let l1 = frame.to_local(self.world(self.front.prev(s)));
        let pg = rules::parallelogram(l1, Point::X);
        for scale in [1.0, 0.7] {
            let pn = frame.to_world(pg * scale);
            out.push((Cand::New { s, pn }, Remedy::CorrectedPn));
        }
        if pred.element_type != ElementType::New {
            if let Some(q) = self.snap_target(s, frame.to_world(pg), self.params.snap_radius * h) {
                out.push((Cand::Snap { s, q }, Remedy::Snapped));
            }
        }
        out
    }

    /// Takes one step: closes a small loop, or cuts one element, or (when no
    /// reference point works) cuts a square, splits a loop, or fails.
    pub fn step(&mut self) -> Result<StepOutcome, MeshError> {
        if self.front.is_empty() {
            return Ok(StepOutcome::Done);
        }
        if self.history.len() >= self.step_limit {
            return Err(MeshError::StepLimit {
                limit: self.step_limit,
                remaining: self.front.len(),
            });
        }
        let mut r = match self.auto_step() {
            Ok(r) => r,
            Err(e) => {
                if self.params.fill && !self.replaying {
                    if let Some(r) = self.rewind_and_fill() {
                        return Ok(StepOutcome::Stepped(Box::new(r)));
                    }
                }
                return Err(e);
            }
        };
        r.rejected = std::mem::take(&mut self.rejected);
        if r.kind != StepKind::Relax {
            self.relax_streak = 0;
        }
        self.history.push(Action::Auto);
        self.undone.clear();
        self.stats.record(&r);
        Ok(StepOutcome::Stepped(Box::new(r)))
    }

    fn report(&self, kind: StepKind) -> StepReport {
        StepReport {
            index: self.history.len(),
            kind,
            reference: None,
            leading: Vec::new(),
            prediction: None,
            predicted_pn: None,
            element_type: None,
            remedy: Remedy::NotApplicable,
            skipped: 0,
            rejected: 0,
            pattern: None,
            quads: Vec::new(),
            new_nodes: Vec::new(),
            removed: 0,
        }
    }

    fn auto_step(&mut self) -> Result<StepReport, MeshError> {
        if self.params.fill && self.history.len() >= self.fill_after {
            if let Some(r) = self.fill_rest() {
                return Ok(r);
            }
            if !self.replaying {
                return Err(MeshError::StepLimit {
                    limit: self.fill_after,
                    remaining: self.front.len(),
                });
            }
        }
        let limits = self.limits();
        // 0. A loop with no reference point starts a row with a square.
        while let Some(lid) = self.row_start.pop() {
            if self.front.loops[lid as usize].alive
                && self.front.loops[lid as usize].len > 6
                && !self.loop_has_reference(lid)
            {
                if let Some(r) = self.square_cut(Some(lid), limits) {
                    return Ok(r);
                }
            }
        }
        // 1. Small loops close first.
        let small: Vec<u32> = self
            .front
            .live_loops()
            .filter(|&l| self.front.loops[l as usize].len <= 6)
            .collect();
        for lid in small {
            if let Some(r) = self.close_small(lid) {
                return Ok(r);
            }
        }
        // 2. The region inside the first layers is filled directly.
        if let Some(k) = self.params.fill_after_layers {
            if self.params.fill && self.queue_layer().is_some_and(|l| l >= k) {
                if let Some(r) = self.fill_rest() {
                    return Ok(r);
                }
            }
        }
        // 3. Reference points in queue order; poor elements wait while a
        //    better reference point exists (the "next reference point" remedy).
        let mut skipped = 0;
        let mut deferred: Vec<SlotId> = Vec::new();
        let mut best: Option<Chosen> = None;
        let mut chosen = None;
        while let Some(e) = self.queue.pop() {
            let i = e.slot as usize;
            if !self.front.slot(e.slot).alive || self.version[i] != e.version {
                continue;
            }
            if e.class == 0
                && self.front.angle(e.slot, &self.mesh.nodes) < self.params.seam_angle.to_radians()
            {
                if let Some(mut r) = self.try_seam(e.slot) {
                    r.skipped = skipped;
                    for s in deferred {
                        self.push(s);
                    }
                    return Ok(r);
                }
            }
            match self.evaluate(e.slot, limits, false)? {
                Some(c) if c.score >= self.params.defer_score => {
                    chosen = Some(c);
                    break;
                }
                Some(c) => c.keep_if_best(&mut best),
                None => {}
            }
            deferred.push(e.slot);
            skipped += 1;
        }
        if let Some(c) = chosen.or(best) {
            let mut r = self.commit_chosen(c);
            r.skipped = skipped;
            for s in deferred {
                self.push(s);
            }
            return Ok(r);
        }
        // 4. A seam at any sharp corner.
        let sharp: Vec<SlotId> = self
            .front
            .live_loops()
            .flat_map(|l| self.front.loop_slots(l))
            .filter(|&s| {
                self.front.angle(s, &self.mesh.nodes) < self.params.reference_angle[0].to_radians()
            })
            .collect();
        for s in sharp {
            if let Some(r) = self.try_seam(s) {
                return Ok(r);
            }
        }
        // 5. A small loop without a usable reference point is split along
        //    its best chord (a ring becomes two halves with square corners).
        let mut loops: Vec<u32> = self.front.live_loops().collect();
        loops.sort_by_key(|&l| self.front.loops[l as usize].len);
        for &lid in &loops {
            if self.front.loops[lid as usize].len <= SMALL_LOOP {
                if let Some(r) = self.chord_split(lid) {
                    return Ok(r);
                }
            }
        }
        // 6. No reference point: a square on the shortest front edge.
        if let Some(mut r) = self.square_cut(None, limits) {
            r.skipped = skipped;
            return Ok(r);
        }
        // 7. The best rule-based element with relaxed limits, anywhere.
        let relaxed = Limits {
            min_corner: 10f64.to_radians(),
            max_corner: 170f64.to_radians(),
            min_front: 5f64.to_radians(),
        };
        let all: Vec<SlotId> = self
            .front
            .live_loops()
            .flat_map(|l| self.front.loop_slots(l))
            .collect();
        let mut best: Option<Chosen> = None;
        for &s in &all {
            if self.front.angle(s, &self.mesh.nodes) >= PI {
                continue;
            }
            if let Some(c) = self.evaluate(s, relaxed, true)? {
                c.keep_if_best(&mut best);
            }
        }
        if let Some(c) = best {
            let mut r = self.commit_chosen(c);
            r.remedy = Remedy::RuleBased;
            r.skipped = skipped;
            return Ok(r);
        }
        // 8. Split a loop along a chord.
        for &lid in &loops {
            if let Some(r) = self.chord_split(lid) {
                return Ok(r);
            }
        }
        // 9. Straighten the smallest stuck loop, moving its interior nodes.
        if let Some(&lid) = loops.first() {
            if self.relaxes < 400 && self.relax_streak < 3 {
                if let Some(r) = self.relax_loop(lid) {
                    self.relaxes += 1;
                    self.relax_streak += 1;
                    return Ok(r);
                }
            }
        }
        // 10. Give the smallest stuck loop room: remove the elements around it.
        if let Some(&lid) = loops.first() {
            if self.rip_ups < 64 {
                let r = self.rip_up(lid, 1 + self.rip_ups % 4);
                self.rip_ups += 1;
                return Ok(r);
            }
        }
        // 11. Fill the region left.
        if self.params.fill {
            if let Some(r) = self.fill_rest() {
                return Ok(r);
            }
        }
        let lid = self.front.live_loops().next().unwrap_or(0);
        let head = self.front.loops[lid as usize].head;
        Err(MeshError::Stuck {
            loop_index: lid,
            node: self.front.node(head),
        })
    }

    /// Layer of the first live entry of the queue (stale entries dropped).
    fn queue_layer(&mut self) -> Option<u32> {
        while let Some(e) = self.queue.peek() {
            if self.front.slot(e.slot).alive && self.version[e.slot as usize] == e.version {
                return Some(e.layer);
            }
            self.queue.pop();
        }
        None
    }

    /// When extraction has led the front into a state no fill can take, the
    /// run goes back to an earlier step (3/4, 1/2, 1/4 of the way, then the
    /// start) and fills the region left there. The history then holds the
    /// steps kept and the fill, so undo goes back to the step rewound to.
    fn rewind_and_fill(&mut self) -> Option<StepReport> {
        if self.rewound {
            return None;
        }
        self.rewound = true;
        let n = self.history.len();
        for k in [3 * n / 4, n / 2, n / 4, 0] {
            let mut fresh = self.replayed(&self.history[..k]);
            let kept = fresh.mesh.quads.len();
            if let Some(mut r) = fresh.commit_fill() {
                r.removed = self.mesh.quads.len().saturating_sub(kept);
                fresh.rewound = true;
                *self = fresh;
                return Some(r);
            }
        }
        None
    }

    /// Replays one recorded action.
    fn replay(&mut self, a: &Action) -> bool {
        match a {
            Action::Auto => self.step().is_ok(),
            Action::Correction(c) => self.correct(c).is_ok(),
            Action::Fill => self.commit_fill().is_some(),
        }
    }

    /// A fill taken as a step of its own (after rewinding, or replayed).
    fn commit_fill(&mut self) -> Option<StepReport> {
        self.fill_retry_at = 0;
        let r = self.fill_rest()?;
        self.history.push(Action::Fill);
        self.undone.clear();
        self.stats.record(&r);
        Some(r)
    }

    /// Fills the whole region left with [`fill::fill_region`] and empties
    /// the front.
    fn fill_rest(&mut self) -> Option<StepReport> {
        let step = self.history.len();
        if step < self.fill_retry_at {
            return None;
        }
        let ids: Vec<u32> = self.front.live_loops().collect();
        let loops: Vec<Vec<u32>> = ids.iter().map(|&l| self.front.loop_nodes(l)).collect();
        let Ok(f) = fill::fill_region(&loops, &self.mesh.nodes) else {
            self.fill_retry_at = step + (step / 4).max(50);
            return None;
        };
        let mut r = self.report(StepKind::Fill);
        for p in f.points {
            let v = self.add_node(p);
            r.new_nodes.push(v);
        }
        for q in f.quads {
            self.push_quad(q);
            r.quads.push(q);
        }
        for l in ids {
            self.front.remove_loop(l, &self.mesh.nodes);
        }
        Some(r)
    }

    /// True when some slot of the loop is a reference point or sharp corner.
    fn loop_has_reference(&self, lid: u32) -> bool {
        let hi = self.params.reference_angle[1].to_radians();
        self.front
            .loop_slots(lid)
            .into_iter()
            .any(|s| self.front.angle(s, &self.mesh.nodes) <= hi)
    }

    /// The model's element at reference slot `s`, or the best remedy. With
    /// `rules`, the rule model stands in for the model.
    fn evaluate(
        &mut self,
        s: SlotId,
        limits: Limits,
        rules: bool,
    ) -> Result<Option<Chosen>, MeshError> {
        let n = if rules { 2 } else { self.leading_n() };
        let slots = self.leading_slots(s, n);
        let (frame, input) = self.normalised(&slots);
        let pred = if rules {
            self.rules.predict(&input)
        } else {
            self.model.predict(&input)
        };
        let pred = if pred.pn.is_finite() {
            pred
        } else {
            Prediction {
                pn: Point::new(1.0, 1.0),
                ..pred
            }
        };
        let leading: Vec<u32> = slots.iter().map(|&t| self.front.node(t)).collect();
        let mut best: Option<Chosen> = None;
        for (c, remedy) in self.candidates(s, pred, &frame) {
            let Some(score) = self.check(c, limits) else {
                if self.params.pure_model && !rules {
                    if self.rejected_inputs.insert(leading.clone()) {
                        self.rejected += 1;
                    }
                    return Ok(None);
                }
                continue;
            };
            let better = best.as_ref().is_none_or(|b| beats(score, b.score));
            if better {
                best = Some(Chosen {
                    cand: c,
                    remedy,
                    score,
                    prediction: pred,
                    frame,
                    leading: leading.clone(),
                });
            }
            if remedy == Remedy::None && score >= self.params.accept_score {
                break;
            }
        }
        Ok(best)
    }

    fn commit_chosen(&mut self, c: Chosen) -> StepReport {
        let mut r = self.commit(c.cand, StepKind::Element);
        r.reference = Some(c.leading[c.leading.len() / 2]);
        r.predicted_pn = Some(c.frame.to_world(c.prediction.pn));
        r.prediction = Some(c.prediction);
        r.leading = c.leading;
        r.remedy = c.remedy;
        r
    }

    /// Removes every quad within `rings` element rings of loop `lid` and
    /// rebuilds the front around the enlarged hole in the mesh.
    fn rip_up(&mut self, lid: u32, rings: usize) -> StepReport {
        let mut r = self.report(StepKind::RipUp);
        let mut mark = vec![false; self.mesh.nodes.len()];
        for s in self.front.loop_slots(lid) {
            mark[self.front.node(s) as usize] = true;
        }
        r.reference = Some(self.front.node(self.front.loops[lid as usize].head));
        for _ in 0..rings {
            let hit: Vec<usize> = (0..self.mesh.quads.len())
                .filter(|&k| self.mesh.quads[k].iter().any(|&v| mark[v as usize]))
                .collect();
            for &k in &hit {
                for &v in &self.mesh.quads[k] {
                    mark[v as usize] = true;
                }
            }
            let before = self.mesh.quads.len();
            let mut k = 0;
            self.mesh.quads.retain(|_| {
                let keep = hit.binary_search(&k).is_err();
                k += 1;
                keep
            });
            r.removed += before - self.mesh.quads.len();
        }
        self.rebuild_incidence();
        let loops = Front::loops_of_unmeshed(&self.mesh);
        self.front = Front::new(
            &loops,
            &self.mesh.nodes,
            2.0 * self.boundary.median_segment(),
        );
        self.queue.clear();
        self.version.clear();
        for s in 0..self.front.slots.len() as SlotId {
            self.push(s);
        }
        // The enlarged loop is split next: a chord across the wider region.
        let target = self.front.live_loops().max_by_key(|&l| {
            self.front
                .loop_slots(l)
                .iter()
                .filter(|&&s| mark[self.front.node(s) as usize])
                .count()
        });
        if let Some(t) = target {
            if let Some(split) = self.chord_split(t) {
                r.quads = split.quads;
                r.new_nodes = split.new_nodes;
            }
        }
        self.row_start = self.front.live_loops().collect();
        r
    }

    fn push_quad(&mut self, q: [u32; 4]) {
        let k = self.mesh.quads.len() as u32;
        for &v in &q {
            self.incident[v as usize].push(k);
        }
        self.mesh.quads.push(q);
    }

    fn rebuild_incidence(&mut self) {
        self.incident = vec![Vec::new(); self.mesh.nodes.len()];
        for (k, q) in self.mesh.quads.iter().enumerate() {
            for &v in q {
                self.incident[v as usize].push(k as u32);
            }
        }
    }

    /// Seam at sharp slot `s`: merges P_l1 and P_r1 (at their midpoint, or
    /// onto the one on the boundary) so the sharp corner closes. Kept only
    /// if every quad around the merged node stays strictly convex with a
    /// scaled Jacobian of at least 0.2 and the new front edges cross nothing.
    fn try_seam(&mut self, s: SlotId) -> Option<StepReport> {
        let f = &self.front;
        if f.loop_len(s) < 6 {
            return None;
        }
        let (l, r) = (f.prev(s), f.next(s));
        let (l2, r2) = (f.prev(l), f.next(r));
        let (nl, nr) = (f.node(l), f.node(r));
        if nl == nr || f.node(l2) == nr || f.node(r2) == nl {
            return None;
        }
        let nb = self.mesh.n_boundary() as u32;
        let (pl, pr) = (self.mesh.nodes[nl as usize], self.mesh.nodes[nr as usize]);
        let (keep, gone, pos) = match (nl < nb, nr < nb) {
            (true, true) => return None,
            (true, false) => (nl, nr, pl),
            (false, true) => (nr, nl, pr),
            (false, false) => (nl, nr, pl.lerp(pr, 0.5)),
        };
        // Both nodes must stand on the front only here.
        let probe = Point::splat(1e-12 * (1.0 + pos.abs().max_element()));
        for (v, pv) in [(nl, pl), (nr, pr)] {
            self.front
                .edges_near(pv - probe, pv + probe, &mut self.scratch.near);
            if self
                .scratch
                .near
                .iter()
                .any(|&e| self.front.node(e) == v && e != l && e != r)
            {
                return None;
            }
        }
        let sub = |v: u32| if v == gone { keep } else { v };
        let mut quads: Vec<u32> = self.incident[nl as usize].clone();
        quads.extend_from_slice(&self.incident[nr as usize]);
        let at = |v: u32| {
            if v == keep || v == gone {
                pos
            } else {
                self.mesh.nodes[v as usize]
            }
        };
        for &k in &quads {
            let q = self.mesh.quads[k as usize].map(sub);
            let p = q.map(at);
            if !crate::geom::is_strictly_convex(p) {
                return None;
            }
            if crate::quality::Shape::of(p).scaled_jacobian < 0.2 {
                return None;
            }
        }
        // New front edges l2 → X → r2 and the moved mesh edges at X.
        let mut ends: Vec<u32> = vec![self.front.node(l2), self.front.node(r2)];
        for &k in &quads {
            let q = self.mesh.quads[k as usize].map(sub);
            for i in 0..4 {
                if q[i] == keep {
                    ends.push(q[(i + 1) % 4]);
                    ends.push(q[(i + 3) % 4]);
                }
            }
        }
        ends.sort_unstable();
        ends.dedup();
        let tip = self.front.node(s);
        for &w in &ends {
            let pw = self.mesh.nodes[w as usize];
            if self.crosses_front(pos, pw, &[w, nl, nr, tip]) {
                return None;
            }
        }
        let mut rep = self.report(StepKind::Seam);
        rep.reference = Some(self.front.node(s));
        self.front.remove_pair(s, &self.mesh.nodes);
        self.front.unfile_edges_at(l, &self.mesh.nodes);
        self.mesh.nodes[keep as usize] = pos;
        self.front.refile_edges_at(l, keep, &self.mesh.nodes);
        let moved = std::mem::take(&mut self.incident[gone as usize]);
        for &k in &moved {
            let q = &mut self.mesh.quads[k as usize];
            *q = q.map(sub);
        }
        self.incident[keep as usize].extend(moved);
        for t in [l, l2, r2] {
            self.push(t);
        }
        Some(rep)
    }

    /// Moves each interior (non-boundary) node of loop `lid` half-way to
    /// the midpoint of its front neighbours when every quad around it stays
    /// strictly convex with a scaled Jacobian of at least
    /// `min(former, 0.3)` and its front edges cross nothing.
    fn relax_loop(&mut self, lid: u32) -> Option<StepReport> {
        let nb = self.mesh.n_boundary() as u32;
        let slots = self.front.loop_slots(lid);
        let mut count: std::collections::BTreeMap<u32, usize> = Default::default();
        for l in self.front.live_loops() {
            for t in self.front.loop_slots(l) {
                *count.entry(self.front.node(t)).or_default() += 1;
            }
        }
        let mut moved = 0;
        for &s in &slots {
            let v = self.front.node(s);
            if v < nb || count[&v] > 1 {
                continue;
            }
            let (pp, pn) = (
                self.world(self.front.prev(s)),
                self.world(self.front.next(s)),
            );
            let old = self.mesh.nodes[v as usize];
            let new = old.lerp(pp.lerp(pn, 0.5), 0.5);
            if (new - old).length() < 1e-9 * pp.distance(pn) {
                continue;
            }
            let quads = self.incident[v as usize].clone();
            let before: Vec<f64> = quads
                .iter()
                .map(|&k| {
                    crate::quality::Shape::of(self.mesh.corners(&self.mesh.quads[k as usize]))
                        .scaled_jacobian
                })
                .collect();
            self.front.unfile_edges_at(s, &self.mesh.nodes);
            self.mesh.nodes[v as usize] = new;
            let mut ok = quads.iter().zip(&before).all(|(&k, &b)| {
                let p = self.mesh.corners(&self.mesh.quads[k as usize]);
                crate::geom::is_strictly_convex(p)
                    && crate::quality::Shape::of(p).scaled_jacobian >= b.min(0.3)
            });
            if ok {
                let prev_node = self.front.node(self.front.prev(s));
                let next_node = self.front.node(self.front.next(s));
                for w in [prev_node, next_node] {
                    let pw = self.mesh.nodes[w as usize];
                    if self.crosses_front(new, pw, &[v, w]) {
                        ok = false;
                        break;
                    }
                }
            }
            if !ok {
                self.mesh.nodes[v as usize] = old;
            } else {
                moved += 1;
            }
            self.front.refile_edges_at(s, v, &self.mesh.nodes);
        }
        if moved == 0 {
            return None;
        }
        for &s in &slots {
            self.push(s);
        }
        let mut r = self.report(StepKind::Relax);
        r.reference = Some(self.front.node(slots[0]));
        Some(r)
    }

    fn add_node(&mut self, p: Point) -> u32 {
        self.mesh.nodes.push(p);
        self.incident.push(Vec::new());
        (self.mesh.nodes.len() - 1) as u32
    }

    /// Commits a checked candidate and requeues the slots it touched.
    fn commit(&mut self, c: Cand, kind: StepKind) -> StepReport {
        let mut r = self.report(kind);
        let f = &self.front;
        let touched: Vec<SlotId>;
        match c {
            Cand::New { s, pn } => {
                let (l, rr) = (f.prev(s), f.next(s));
                let layer = f.slot(s).layer + 1;
                let (p0, r1, l1) = (f.node(s), f.node(rr), f.node(l));
                let v = self.add_node(pn);
                self.push_quad([p0, r1, v, l1]);
                self.front.replace_node(s, v, layer, &self.mesh.nodes);
                r.new_nodes.push(v);
                r.element_type = Some(ElementType::New);
                touched = vec![s, rr, l];
            }
            Cand::Snap { s, q } => {
                let (l, rr) = (f.prev(s), f.next(s));
                let (qp, qn) = (f.prev(q), f.next(q));
                let (p0, r1, l1, x) = (f.node(s), f.node(rr), f.node(l), f.node(q));
                let layer = f.slot(s).layer + 1;
                self.push_quad([p0, r1, x, l1]);
                self.front.replace_node(s, x, layer, &self.mesh.nodes);
                self.front.exchange_successors(s, q, &self.mesh.nodes);
                r.element_type = Some(ElementType::New);
                touched = vec![s, q, rr, l, qp, qn];
            }
            Cand::Right { s } => {
                let (l, rr) = (f.prev(s), f.next(s));
                let r2 = f.next(rr);
                let quad = [f.node(s), f.node(rr), f.node(r2), f.node(l)];
                self.push_quad(quad);
                self.front.remove_pair(s, &self.mesh.nodes);
                r.element_type = Some(ElementType::Right);
                touched = vec![r2, l];
            }
            Cand::Left { s } => {
                let (l, rr) = (f.prev(s), f.next(s));
                let l2 = f.prev(l);
                let quad = [f.node(s), f.node(rr), f.node(l2), f.node(l)];
                self.push_quad(quad);
                self.front.remove_pair(l, &self.mesh.nodes);
                r.element_type = Some(ElementType::Left);
                touched = vec![rr, l2];
            }
        }
        if let Some(q) = self.mesh.quads.last() {
            r.quads.push(*q);
        }
        for s in touched {
            self.push(s);
        }
        r
    }

    /// True when every corner of quad `p` at a boundary node (`ids`, `None`
    /// for a new node) turns left measurably ([`crate::geom::turns_left`]).
    /// Boundary nodes never move, so a corner flat to rounding there would
    /// stay in the finished mesh; elsewhere smoothing moves it off the line.
    fn pinned_corners_turn(&self, p: [Point; 4], ids: [Option<u32>; 4]) -> bool {
        (0..4).all(|k| match ids[k] {
            Some(v) if self.mesh.is_boundary(v) => {
                crate::geom::turns_left(p[(k + 3) % 4], p[k], p[(k + 1) % 4])
            }
            _ => true,
        })
    }

    /// Closes a loop of 4 or 6 slots, if a valid closure exists.
    fn close_small(&mut self, lid: u32) -> Option<StepReport> {
        let slots = self.front.loop_slots(lid);
        let nodes: Vec<u32> = slots.iter().map(|&s| self.front.node(s)).collect();
        let pts: Vec<Point> = nodes.iter().map(|&v| self.mesh.nodes[v as usize]).collect();
        let mut uniq = nodes.clone();
        uniq.sort_unstable();
        uniq.dedup();
        if uniq.len() != nodes.len() {
            return None; // a pinched loop: leave it to extraction
        }
        match slots.len() {
            4 => {
                let q = [pts[0], pts[1], pts[2], pts[3]];
                let ids = [nodes[0], nodes[1], nodes[2], nodes[3]].map(Some);
                if !crate::geom::is_strictly_convex(q) || !self.pinned_corners_turn(q, ids) {
                    return None;
                }
                if !self.loop_is_clear(&slots, &pts) {
                    return None;
                }
                let mut r = self.report(StepKind::Close4);
                let quad = [nodes[0], nodes[1], nodes[2], nodes[3]];
                self.push_quad(quad);
                self.front.remove_loop(lid, &self.mesh.nodes);
                r.quads.push(quad);
                Some(r)
            }
            6 => {
                let p6: [Point; 6] = std::array::from_fn(|k| pts[k]);
                let fill = closure::fill_six(&p6)?;
                if !self.loop_is_clear(&slots, &pts) {
                    return None;
                }
                if let Some(c) = fill.interior {
                    if !crate::geom::point_in_polygon(c, &pts) {
                        return None;
                    }
                }
                let mut r = self.report(StepKind::Close6);
                r.pattern = Some(fill.pattern);
                let centre = fill.interior.map(|c| self.add_node(c));
                if let Some(c) = centre {
                    r.new_nodes.push(c);
                }
                for q in &fill.quads {
                    let quad = q.map(|i| {
                        if i == 6 {
                            centre.unwrap_or(0)
                        } else {
                            nodes[i]
                        }
                    });
                    self.push_quad(quad);
                    r.quads.push(quad);
                }
                self.front.remove_loop(lid, &self.mesh.nodes);
                Some(r)
            }
            _ => None,
        }
    }

    /// No other front edge or node lies inside the loop `slots` (e.g. a hole
    /// not yet joined).
    fn loop_is_clear(&mut self, slots: &[SlotId], pts: &[Point]) -> bool {
        let lo = pts
            .iter()
            .fold(Point::splat(f64::INFINITY), |a, &b| a.min(b));
        let hi = pts
            .iter()
            .fold(Point::splat(f64::NEG_INFINITY), |a, &b| a.max(b));
        self.front.edges_near(lo, hi, &mut self.scratch.near);
        let lid = self.front.slot(slots[0]).loop_id;
        self.scratch.near.iter().all(|&e| {
            self.front.slot(e).loop_id == lid
                || !crate::geom::point_in_polygon(self.mesh.nodes[self.front.node(e) as usize], pts)
        })
    }

    /// A square element on the shortest front edge whose square fits
    /// (thesis §5.1: no front node qualifies as a reference point).
    fn square_cut(&mut self, only: Option<u32>, limits: Limits) -> Option<StepReport> {
        let mut edges: Vec<(f64, SlotId)> = self
            .front
            .live_loops()
            .filter(|&l| only.is_none_or(|o| o == l) && self.front.loops[l as usize].len >= 16)
            .flat_map(|l| self.front.loop_slots(l))
            .map(|s| (self.world(s).distance(self.world(self.front.next(s))), s))
            .collect();
        edges.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for &(len, s) in edges.iter().take(64) {
            let t = self.front.next(s);
            let (a, b) = (self.world(s), self.world(t));
            let up = (b - a).perp() / len;
            for height in [1.0, 0.7, 0.5] {
                let (a2, b2) = (a + up * len * height, b + up * len * height);
                let corners = [
                    Corner::Partial(s),
                    Corner::Partial(t),
                    Corner::New(b2),
                    Corner::New(a2),
                ];
                if guard::check(
                    &self.front,
                    &self.mesh.nodes,
                    corners,
                    &[s],
                    limits,
                    &mut self.scratch,
                )
                .is_some()
                {
                    let mut r = self.report(StepKind::Square);
                    let layer = self.front.slot(s).layer.max(self.front.slot(t).layer) + 1;
                    let va = self.add_node(a2);
                    let vb = self.add_node(b2);
                    let quad = [self.front.node(s), self.front.node(t), vb, va];
                    self.push_quad(quad);
                    let ids = self
                        .front
                        .insert_after(s, &[va, vb], layer, &self.mesh.nodes);
                    r.quads.push(quad);
                    r.new_nodes = vec![va, vb];
                    r.reference = Some(self.front.node(s));
                    for x in [s, ids[0], ids[1], t] {
                        self.push(x);
                    }
                    return Some(r);
                }
            }
        }
        None
    }

    /// Splits a loop along an interior chord into two even loops (the
    /// splitting-line rule of the extension of TP, thesis §1.3.2): both
    /// ends' angles split as close to 90° as possible, the chord visible
    /// and inside, with new nodes spaced like the front.
    fn chord_split(&mut self, lid: u32) -> Option<StepReport> {
        let slots = self.front.loop_slots(lid);
        let n = slots.len();
        if n < 8 {
            return None;
        }
        let min_part = 40f64.to_radians();
        let mut best: Option<(f64, SlotId, SlotId, usize)> = None;
        let stride = (n / 200).max(1);
        for i in (0..n).step_by(stride) {
            for j in (i + 2..n).step_by(stride) {
                if i == 0 && j == n - 1 {
                    continue;
                }
                let (a, b) = (slots[i], slots[j]);
                if self.front.node(a) == self.front.node(b) {
                    continue;
                }
                let (pa, pb) = (self.world(a), self.world(b));
                let mut score = 0.0;
                let mut ok = true;
                for (s, other) in [(a, pb), (b, pa)] {
                    let p = self.world(s);
                    let wedge = self.front.angle(s, &self.mesh.nodes);
                    let part1 = ccw_angle(p, self.world(self.front.next(s)), other);
                    let part2 = wedge - part1;
                    if part1 < min_part || part2 < min_part {
                        ok = false;
                        break;
                    }
                    score += (part1 - PI / 2.0).abs() + (part2 - PI / 2.0).abs();
                }
                if !ok {
                    continue;
                }
                let len = pa.distance(pb);
                let h = 0.25
                    * (pa.distance(self.world(self.front.next(a)))
                        + pa.distance(self.world(self.front.prev(a)))
                        + pb.distance(self.world(self.front.next(b)))
                        + pb.distance(self.world(self.front.prev(b))));
                let d = j - i;
                let mut k = ((len / h).round() as usize).saturating_sub(1);
                if (d + 1 + k) % 2 == 1 {
                    k += 1;
                }
                if k == 0 && (d + 1 < 4 || n - d + 1 < 4) {
                    k = 2;
                }
                let spacing = (len / (k + 1) as f64) / h;
                if !(0.4..=2.5).contains(&spacing) {
                    continue;
                }
                score += 0.5 * (spacing - 1.0).abs();
                if best.is_some_and(|(bs, ..)| score >= bs) {
                    continue;
                }
                if !self.chord_clear(a, b) {
                    continue;
                }
                best = Some((score, a, b, k));
            }
        }
        let (_, a, b, k) = best?;
        let (pa, pb) = (self.world(a), self.world(b));
        let (na, nb) = (self.front.node(a), self.front.node(b));
        let layer = self.front.slot(a).layer.max(self.front.slot(b).layer) + 1;
        let mut r = self.report(StepKind::Split);
        r.reference = Some(na);
        let chord: Vec<u32> = (1..=k)
            .map(|t| self.add_node(pa.lerp(pb, t as f64 / (k + 1) as f64)))
            .collect();
        r.new_nodes = chord.clone();
        let mut seq = chord.clone();
        seq.push(nb);
        seq.extend(chord.iter().rev());
        seq.push(na);
        let ids = self.front.insert_after(a, &seq, layer, &self.mesh.nodes);
        let b_star = ids[k];
        self.front.exchange_successors(b_star, b, &self.mesh.nodes);
        self.row_start.push(self.front.slot(a).loop_id);
        self.row_start.push(self.front.slot(b).loop_id);
        let mut touched = vec![a, b, b_star, ids[ids.len() - 1]];
        touched.extend(ids.iter().copied());
        for s in touched {
            self.push(s);
        }
        Some(r)
    }

    /// The open segment between slots `a` and `b` meets no front edge.
    fn chord_clear(&mut self, a: SlotId, b: SlotId) -> bool {
        let (pa, pb) = (self.world(a), self.world(b));
        let skip = [self.front.node(a), self.front.node(b)];
        !self.crosses_front(pa, pb, &skip)
    }

    /// True when segment `pa–pb` meets a front edge that has none of the
    /// nodes `skip` as an end.
    fn crosses_front(&mut self, pa: Point, pb: Point, skip: &[u32]) -> bool {
        self.front
            .edges_near(pa.min(pb), pa.max(pb), &mut self.scratch.near);
        self.scratch.near.iter().any(|&e| {
            let (c, d) = (self.front.node(e), self.front.node(self.front.next(e)));
            !skip.contains(&c)
                && !skip.contains(&d)
                && crate::geom::segments_intersect(
                    pa,
                    pb,
                    self.mesh.nodes[c as usize],
                    self.mesh.nodes[d as usize],
                )
        })
    }

    /// Commits an element chosen by the user at reference node `c.reference`.
    pub fn correct(&mut self, c: &Correction) -> Result<StepReport, MeshError> {
        let r = self.apply_correction(c)?;
        self.history.push(Action::Correction(c.clone()));
        self.undone.clear();
        self.stats.record(&r);
        Ok(r)
    }

    fn apply_correction(&mut self, c: &Correction) -> Result<StepReport, MeshError> {
        let s = self
            .front
            .live_loops()
            .flat_map(|l| self.front.loop_slots(l))
            .find(|&s| self.front.node(s) == c.reference)
            .ok_or(MeshError::NotOnFront { node: c.reference })?;
        let cand = match (c.element_type, c.snap_to, c.pn) {
            (ElementType::Right, ..) => Cand::Right { s },
            (ElementType::Left, ..) => Cand::Left { s },
            (ElementType::New, Some(x), _) => {
                let q = self
                    .front
                    .live_loops()
                    .flat_map(|l| self.front.loop_slots(l))
                    .find(|&q| self.front.node(q) == x)
                    .ok_or(MeshError::NotOnFront { node: x })?;
                Cand::Snap { s, q }
            }
            (ElementType::New, None, Some(pn)) => Cand::New { s, pn },
            (ElementType::New, None, None) => {
                return Err(MeshError::InvalidCorrection { node: c.reference })
            }
        };
        let relaxed = Limits {
            min_corner: 1e-6,
            max_corner: PI - 1e-6,
            min_front: 1e-6,
        };
        if self.check(cand, relaxed).is_none() {
            return Err(MeshError::InvalidCorrection { node: c.reference });
        }
        let leading: Vec<u32> = self
            .leading_slots(s, self.leading_n())
            .iter()
            .map(|&t| self.front.node(t))
            .collect();
        let mut r = self.commit(cand, StepKind::Correction);
        r.reference = Some(c.reference);
        r.leading = leading;
        Ok(r)
    }

    /// The training sample of an element step or a correction (method §3):
    /// the real front around P0 as it was before the step (the report's
    /// leading points, which never move while meshing) and the element
    /// committed. `None` for other steps. The editor appends these to the
    /// training set when the user accepts or corrects an element.
    pub fn sample_of(&self, r: &StepReport) -> Option<crate::samples::Sample> {
        if !matches!(r.kind, StepKind::Element | StepKind::Correction) {
            return None;
        }
        let t = r.element_type?;
        let n = r.leading.len() / 2;
        let p0 = *r.leading.get(n)?;
        let pn = r.pn_node()?;
        let pos = |v: u32| self.mesh.nodes.get(v as usize).copied();
        let left: Option<Vec<Point>> = (1..=n).map(|i| pos(r.leading[n - i])).collect();
        let right: Option<Vec<Point>> = (1..=n).map(|i| pos(r.leading[n + i])).collect();
        crate::samples::Sample::from_front(
            &left?,
            pos(p0)?,
            &right?,
            t,
            pos(pn)?,
            crate::samples::Source::Correction,
        )
    }

    /// Runs to the end; `progress` is called after every step with the
    /// number of front nodes left.
    pub fn run(&mut self, mut progress: impl FnMut(usize)) -> Result<(), MeshError> {
        while let StepOutcome::Stepped(_) = self.step()? {
            progress(self.front.len());
        }
        Ok(())
    }

    /// Undoes the last step by replaying all the others from the start
    /// (steps are deterministic). Returns false when there is nothing to undo.
    pub fn undo(&mut self) -> bool {
        let Some(a) = self.history.pop() else {
            return false;
        };
        let mut fresh = self.replayed(&self.history);
        fresh.rewound = self.rewound;
        fresh.undone = std::mem::take(&mut self.undone);
        fresh.undone.push(a);
        *self = fresh;
        true
    }

    /// The actions taken so far, in order.
    pub fn actions(&self) -> &[Action] {
        &self.history
    }

    /// Takes one recorded action: an automatic step, a correction or a
    /// fill. `Ok(None)` when the mesh is complete or the fill does not go.
    pub fn take(&mut self, a: &Action) -> Result<Option<StepReport>, MeshError> {
        match a {
            Action::Auto => self.step().map(|o| match o {
                StepOutcome::Stepped(r) => Some(*r),
                StepOutcome::Done => None,
            }),
            Action::Correction(c) => self.correct(c).map(Some),
            Action::Fill => Ok(self.commit_fill()),
        }
    }

    /// Steps that [`Mesher::undo`] took back and [`Mesher::redo`] can take
    /// again.
    pub fn redo_len(&self) -> usize {
        self.undone.len()
    }

    /// Takes the most recently undone step again (the same action: an
    /// automatic step, the user's correction, or a fill) and returns its
    /// report; `Ok(None)` when nothing was undone.
    pub fn redo(&mut self) -> Result<Option<StepReport>, MeshError> {
        let Some(a) = self.undone.pop() else {
            return Ok(None);
        };
        let rest = std::mem::take(&mut self.undone);
        let r = self.take(&a);
        self.undone = rest;
        if r.is_err() {
            self.undone.push(a);
        }
        r
    }

    /// A new mesher over the same input with `actions` replayed, switching
    /// models where [`Mesher::set_model`] did; a model set after the last
    /// replayed action stays in force.
    fn replayed(&self, actions: &[Action]) -> Mesher {
        let mut fresh = Mesher::new(
            self.boundary.clone(),
            self.initial_model.clone(),
            self.params.clone(),
        );
        fresh.replaying = true;
        let mut changes = self.model_changes.iter().peekable();
        for (i, a) in actions.iter().enumerate() {
            while let Some((_, m)) = changes.next_if(|(at, _)| *at <= i) {
                fresh.set_model(m.clone());
            }
            let ok = fresh.replay(a);
            debug_assert!(ok, "replay diverged");
        }
        if let Some((_, m)) = changes.last() {
            fresh.set_model(m.clone());
        }
        fresh.replaying = false;
        fresh
    }

    /// Meshes the rest with `model` (the editor's refit). Steps already
    /// taken stay as they are; undo and replay switch models at the same
    /// point.
    pub fn set_model(&mut self, model: Arc<dyn Model>) {
        self.model_changes.push((self.history.len(), model.clone()));
        self.model = model;
    }

    /// The finished mesh (a large one renumbered for memory locality,
    /// [`QuadMesh::sort_spatially`]), cleaned up and smoothed as the parameters say
    /// ([`improve`]; a mesh with front left is only smoothed), the regions
    /// of quads still bad remeshed ([`remesh_bad`]), with corners flat
    /// to rounding moved off the line ([`unflatten`]), and checked
    /// ([`QuadMesh::check_invariants`], complete when the front is empty).
    /// Call after [`Mesher::run`]; an unfinished mesh is returned as it
    /// stands, checked as a partial mesh.
    pub fn finish(&self) -> Result<QuadMesh, MeshError> {
        self.finish_with(&self.params.finishing())
    }

    /// [`Mesher::finish`] with other cleanup, remeshing and smoothing
    /// parameters (the editor's Smoothing panel changes them without
    /// stepping again).
    pub fn finish_with(&self, f: &FinishParams) -> Result<QuadMesh, MeshError> {
        let mut mesh = self.mesh.clone();
        mesh.compact();
        if mesh.quads.len() > crate::smooth::LOCAL_ABOVE {
            mesh.sort_spatially();
        }
        let complete = self.front.is_empty();
        improve(&mut mesh, complete, &f.cleanup, &f.smooth);
        let params = MeshParams {
            cleanup: f.cleanup,
            remesh: f.remesh,
            smooth: f.smooth,
            ..self.params.clone()
        };
        if complete {
            remesh_bad(&mut mesh, &self.model, &params);
        }
        unflatten(&mut mesh);
        let checked = if self.front.is_empty() {
            mesh.check_finished()
        } else {
            mesh.check_invariants(false)
        };
        checked.map_err(|problem| MeshError::Final { problem })?;
        Ok(mesh)
    }
}

/// Meshes a boundary to the end with `model` and `params`: extraction, then
/// smoothing. Returns the mesh and the step counts.
pub fn mesh_boundary(
    boundary: &Boundary,
    model: Arc<dyn Model>,
    params: &MeshParams,
    progress: impl FnMut(usize),
) -> Result<(QuadMesh, StepStats), MeshError> {
    let mut m = Mesher::new(boundary.clone(), model, params.clone());
    m.run(progress)?;
    Ok((m.finish()?, m.stats.clone()))
}

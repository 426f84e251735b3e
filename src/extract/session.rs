//! The [`Mesher`] session: the extraction state over one boundary (mesh,
//! front, reference queue), its public step API, and its history: every
//! action is recorded, so undo replays the others, redo takes undone ones
//! again, a project file rebuilds a run, and a model set mid-run is
//! switched at the same point on replay.

use super::candidate::Cand;
use super::fill;
use super::guard::{Limits, Scratch};
use super::params::MeshParams;
use super::queue::Entry;
use super::report::{
    Action, CheckedElement, Correction, MeshError, RunProgress, StepKind, StepOutcome, StepReport,
    StepStats,
};
use super::size::SizeField;
use crate::boundary::Boundary;
use crate::front::{Front, SlotId};
use crate::geom::Point;
use crate::mesh::QuadMesh;
use crate::model::{ElementType, Model, RulesModel};
use std::collections::BinaryHeap;
use std::f64::consts::PI;
use std::ops::ControlFlow;
use std::sync::Arc;

/// Steps allowed before the region left is filled, per element a mesh
/// following the size field would have (plus one per boundary node and
/// 200). The size field's estimate runs low where rows cannot coarsen as
/// fast as it asks (a fine side facing a coarse one), so the budget is
/// three times it: at twice, a 201-against-3-node strip (`R06a`) reached
/// it in a tangle no rewind could fill.
const FILL_BUDGET: f64 = 3.0;

/// A mesh made by rewinding and filling whose worst quad is at least this
/// good (scaled Jacobian, before finishing) is taken without trying earlier
/// steps ([`Mesher::rewind_and_fill`]).
const REWIND_GOOD: f64 = 0.2;

/// The progress watch: every [`PROGRESS_EVERY`] steps the area the front
/// still encloses is noted. A run whose last [`PROGRESS_WINDOW`] steps took
/// off less than [`PROGRESS_RATE`] of the mean area of its quads so far per
/// step is going round in circles (elements cut and ripped up again, rows
/// that grow the front where they should close it), and the region left is
/// filled. The window is long enough for the place where the rows of a
/// large disk meet: its rip-ups and relaxations take some 700 steps before
/// the front closes there by itself (disk1600 finishes by extraction alone;
/// with a window of 1,024 steps it was filled).
///
/// The mean of the quads so far is not what a graded domain's fine part
/// asks for: its quads can be a hundredth of the mean's size while the
/// rows there move on as they should. So a run is also held to the size
/// field: the window is no progress only if the area it took off is also
/// under [`PROGRESS_RATE`] of the area the size field asks of the quads it
/// made (h² at each one's centre, quads later ripped up included). Knots of
/// quads far finer than the field and rows cut and ripped up again fail
/// both.
pub(super) const PROGRESS_EVERY: usize = 128;
/// See [`PROGRESS_EVERY`].
pub(super) const PROGRESS_WINDOW: usize = 2048;
/// See [`PROGRESS_EVERY`].
pub(super) const PROGRESS_RATE: f64 = 0.25;
/// The progress watch's window in the end game, when the front encloses
/// less than one [`PROGRESS_WINDOW`] is held to take off: the last pockets
/// where rows met close one after another, each by rip-ups and
/// relaxations that give area back before the pocket closes, so a window
/// sees little progress however well the run goes (disk3200 and disk4800
/// close their last few hundred front nodes by extraction some 2,000
/// steps after a 2,048-step window calls them stalled).
pub(super) const END_WINDOW: usize = 4 * PROGRESS_WINDOW;
/// A region the fill cannot take has this many element rings around it
/// removed, one ring more at each try, before the fill gives up on it
/// ([`Mesher::fill_rest`]).
const FILL_RINGS: usize = 3;
/// A window whose front lost at least this share of its nodes made
/// progress whatever the area: pockets are closing.
pub(super) const FRONT_SHRINK: f64 = 0.1;

/// Cell width of the front's edge grid: as fine as the finest elements (the
/// grid caps its cell count), so a query near fine elements stays short.
pub(super) fn grid_cell(size: &SizeField) -> f64 {
    2.0 * size.range()[0]
}

/// The element extraction loop over one boundary.
#[derive(Clone)]
pub struct Mesher {
    /// The model the run started with (replays start from it).
    pub(super) initial_model: Arc<dyn Model>,
    /// Models set with [`Mesher::set_model`], each with the number of
    /// actions taken before it.
    pub(super) model_changes: Vec<(usize, Arc<dyn Model>)>,
    pub(super) boundary: Boundary,
    pub(super) params: MeshParams,
    pub(super) model: Arc<dyn Model>,
    pub(super) mesh: QuadMesh,
    pub(super) front: Front,
    pub(super) queue: BinaryHeap<Entry>,
    /// The box of the front the last seam changed (its corner, the edges
    /// beside it and the mesh edges at the merged node), for the memory.
    pub(super) seam_box: Option<crate::geom::Aabb>,
    pub(super) version: Vec<u32>,
    pub(super) seq: u64,
    pub(super) history: Vec<Action>,
    /// Actions undone, the most recent last: what [`Mesher::redo`] takes
    /// again. A new step or correction clears it.
    pub(super) undone: Vec<Action>,
    pub(super) stats: StepStats,
    pub(super) scratch: Scratch,
    pub(super) step_limit: usize,
    /// The coarsest band and deepest layer the queue had reached when loops
    /// left behind were last looked for.
    pub(super) row_key: (u32, u32),
    /// The element size wanted anywhere in the domain.
    pub(super) size: Arc<SizeField>,
    pub(super) rules: RulesModel,
    /// Loops to check for a first row (no reference point on them).
    pub(super) row_start: Vec<u32>,
    /// Front edges (by start slot) to start a row on: stretches of the
    /// boundary left behind.
    pub(super) row_edges: Vec<SlotId>,
    pub(super) rip_ups: usize,
    /// The area inside the boundary.
    pub(super) domain_area: f64,
    /// Quads incident to each node.
    pub(super) incident: Vec<Vec<u32>>,
    /// Per node made by a row: the row's elements since its last
    /// transition ([`super::transition`]), counted at the element's top.
    pub(super) row_run: Vec<u32>,
    pub(super) relaxes: usize,
    /// Relaxations since the last other step.
    pub(super) relax_streak: usize,
    /// Steps after which the region left is filled.
    pub(super) fill_after: usize,
    /// No fill is tried before this step (set after a fill fails).
    pub(super) fill_retry_at: usize,
    /// Set while history is being replayed (no rewinding then).
    pub(super) replaying: bool,
    /// A rewind has been tried.
    pub(super) rewound: bool,
    /// Pure-model rejections since the last step.
    pub(super) rejected: usize,
    /// Pure-model: the leading points (node ids) of every rejected
    /// prediction, so a prediction met again is counted once.
    pub(super) rejected_inputs: std::collections::BTreeSet<Vec<u32>>,
    /// Per loop id, the [`Mesher::small_loop_key`] of the state in which
    /// that small loop last neither closed nor settled (0: none): the same
    /// state is not tried again.
    pub(super) small_stuck: Vec<u64>,
    /// Per loop, the [`crate::front::FrontLoop::version`] last looked at
    /// for a mapped grid (see [`super::mapped`]; 0: never).
    pub(super) mapped_seen: Vec<u32>,
    /// The same for [`Mesher::close_strip`].
    pub(super) strip_seen: Vec<u32>,
    /// The progress watch's checkpoints: (step, area still open, [`Mesher::asked`]
    /// then, front nodes then), one per [`PROGRESS_EVERY`] steps.
    pub(super) progress: Vec<(usize, f64, f64, usize)>,
    /// The area the size field asks of the quads made so far: the sum of
    /// h² at the centre of every quad extraction has made (the progress
    /// watch's second measure, [`PROGRESS_EVERY`]).
    pub(super) asked: f64,
    /// Quads that closed a needle ([`Mesher::needle_kite`]) and their area:
    /// the progress watch leaves them out of its mean (a fan of long
    /// needles would make every later quad look like no progress).
    pub(super) needle_quads: (usize, f64),
    /// Evaluations of reference points put back in the queue.
    pub(super) memo: super::memo::EvalMemo,
    /// The box of the front the last [`Mesher::evaluate`] read.
    pub(super) evaluated: (Point, Point),
    /// This run as it was after the first actions of its history (as many
    /// as the checkpoint's own history holds): replays start from it
    /// rather than from the boundary ([`Mesher::undo`]). Kept only while
    /// those actions are still the first of the history.
    pub(super) checkpoint: Option<Arc<Mesher>>,
}

/// [`Mesher::undo`] keeps a [`Mesher::checkpoint`] this many actions
/// before the end of the history, so the undos after it replay at most
/// this many steps each, not the whole run.
pub const CHECKPOINT_BEHIND: usize = 512;

impl Mesher {
    /// A mesher over `boundary` with `model` and `params`.
    pub fn new(boundary: Boundary, model: Arc<dyn Model>, params: MeshParams) -> Mesher {
        let size = Arc::new(SizeField::of_boundary_with(
            &boundary,
            params.size_target.as_ref(),
        ));
        Mesher::with_size(boundary, model, params, size)
    }

    /// [`Mesher::new`] with the size field given: `size` must be
    /// [`SizeField::of_boundary_with`] of `boundary` and the parameters'
    /// size target, built once and shared by
    /// the meshers of one boundary (remeshing tries several settings on
    /// one cavity; a replay starts again from the same boundary).
    pub fn with_size(
        boundary: Boundary,
        model: Arc<dyn Model>,
        params: MeshParams,
        size: Arc<SizeField>,
    ) -> Mesher {
        let mesh = QuadMesh::from_boundary(&boundary);
        let front = Front::new(&mesh.loops, &mesh.nodes, grid_cell(&size));
        let mut min_seg = f64::INFINITY;
        for (a, b) in boundary.segments() {
            min_seg = min_seg.min(boundary.points[a].distance(boundary.points[b]));
        }
        let domain_area = boundary.area();
        let est = (domain_area / (min_seg * min_seg)).min(1e9) as usize;
        let work = est.max(boundary.node_count());
        let step_limit = params.max_steps.unwrap_or(8 * work + 10_000);
        let quads = size.quad_estimate().min(1e9);
        let mut m = Mesher {
            step_limit,
            row_key: (0, 0),
            size,
            fill_after: (FILL_BUDGET * quads) as usize + boundary.node_count() + 200,
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
            seam_box: None,
            version: Vec::new(),
            seq: 0,
            history: Vec::new(),
            undone: Vec::new(),
            stats: StepStats::default(),
            scratch: Scratch::default(),
            rules: RulesModel::DEFAULT,
            row_start: Vec::new(),
            row_edges: Vec::new(),
            rip_ups: 0,
            domain_area,
            incident: Vec::new(),
            row_run: Vec::new(),
            small_stuck: Vec::new(),
            mapped_seen: Vec::new(),
            strip_seen: Vec::new(),
            memo: Default::default(),
            progress: Vec::new(),
            asked: 0.0,
            needle_quads: (0, 0.0),
            evaluated: (Point::ZERO, Point::ZERO),
            relaxes: 0,
            relax_streak: 0,
            checkpoint: None,
        };
        m.row_start = m.front.live_loops().collect();
        m.incident = vec![Vec::new(); m.mesh.nodes.len()];
        m.row_run = vec![super::transition::FRESH_ROW; m.mesh.nodes.len()];
        for s in 0..m.front.slots.len() as SlotId {
            m.push(s);
        }
        m
    }

    /// The share of the domain's area meshed, from 0 to 1 (the area the
    /// front still encloses, over the domain's: a walk over the front).
    /// Unlike the front's node count, it grows steadily on a disk, whose
    /// rows keep their node count as they go in.
    pub fn meshed_share(&self) -> f64 {
        if self.front.is_empty() || self.domain_area <= 0.0 {
            return 1.0;
        }
        (1.0 - self.front.open_area(&self.mesh.nodes) / self.domain_area).clamp(0.0, 1.0)
    }

    /// The mesh so far (unsmoothed).
    pub fn mesh(&self) -> &QuadMesh {
        &self.mesh
    }

    /// The element size field extraction follows.
    pub fn size(&self) -> &SizeField {
        &self.size
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
        let nodes = &self.mesh.nodes;
        let loops: Vec<(u32, Vec<Point>, f64)> = self
            .front
            .live_loops()
            .map(|l| {
                let p: Vec<Point> = self
                    .front
                    .loop_nodes(l)
                    .iter()
                    .map(|&v| nodes[v as usize])
                    .collect();
                let a = crate::geom::polygon_area(p.iter().copied());
                (l, p, a)
            })
            .collect();
        // Quads and the region the front still bounds tile the domain, up
        // to the sums' rounding bounds (`AreaSum`, as in the final check).
        let mut covered = self.mesh.quads_area_sum();
        for (_, p, _) in &loops {
            covered.add_polygon(p);
        }
        // A clockwise loop (a hole's front) lies inside a counter-clockwise
        // one. A loop turned inside out would go on cutting elements
        // outwards, out of the domain, and the sum above would not see it:
        // its negative area grows as its quads' does.
        for (l, p, a) in &loops {
            let held = *a >= 0.0
                || p.iter().any(|&x| {
                    loops
                        .iter()
                        .any(|(_, q, b)| *b > 0.0 && crate::geom::point_in_polygon(x, q))
                });
            if !held {
                return Err(crate::mesh::InvariantError::Front(format!(
                    "loop {l} runs clockwise (area {a:.3e}) inside no counter-clockwise loop"
                )));
            }
        }
        // The mesh's loops are the boundary's, its first nodes the
        // boundary's points.
        let domain = self.mesh.loops_area_sum();
        if !covered.agrees_with(&domain) {
            return Err(crate::mesh::InvariantError::Area {
                covered: covered.area(),
                domain: domain.area(),
            });
        }
        self.mesh.check_invariants(self.is_done())
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
                        self.memo.clear();
                        return Ok(StepOutcome::Stepped(Box::new(r)));
                    }
                }
                return Err(e);
            }
        };
        // The memory forgets what the step may have changed: the box of
        // the quads it made (an element, a transition, a small loop or a
        // narrow rectangle closed, a row's first square), the region a
        // seam gave up, or everything after any other step.
        let seam_box = self.seam_box.take();
        let local = match r.kind {
            _ if r.removed > 0 => None,
            StepKind::Element
            | StepKind::Transition
            | StepKind::Close4
            | StepKind::Close6
            | StepKind::Mapped
            | StepKind::Square => crate::geom::Aabb::of(
                r.quads
                    .iter()
                    .flatten()
                    .map(|&v| self.mesh.nodes[v as usize]),
            ),
            StepKind::Seam => seam_box,
            _ => None,
        };
        match local {
            Some(bb) => self.memo.changed(bb.min, bb.max),
            None => self.memo.clear(),
        }
        r.rejected = std::mem::take(&mut self.rejected);
        if r.kind != StepKind::Relax {
            self.relax_streak = 0;
        }
        self.history.push(Action::Auto);
        self.undone.clear();
        self.stats.record(&r, self.mesh.quads.len());
        Ok(StepOutcome::Stepped(Box::new(r)))
    }

    pub(super) fn report(&self, kind: StepKind) -> StepReport {
        StepReport::new(self.history.len(), kind)
    }

    /// The progress watch ([`PROGRESS_EVERY`]): true when the last
    /// [`PROGRESS_WINDOW`] steps ([`END_WINDOW`] once the area still open
    /// is less than that window is held to take off) made too little of
    /// the mesh and did not shrink the front by [`FRONT_SHRINK`].
    pub(super) fn stalled(&mut self) -> bool {
        let n = self.history.len();
        if n == 0 || n % PROGRESS_EVERY != 0 || self.progress.last().is_some_and(|p| p.0 == n) {
            return false;
        }
        let open = self.front.open_area(&self.mesh.nodes);
        self.progress.push((n, open, self.asked, self.front.len()));
        let (needles, needle_area) = self.needle_quads;
        let quads = self.mesh.quads.len().saturating_sub(needles);
        if quads == 0 {
            return false;
        }
        let mean = (self.domain_area - open - needle_area) / quads as f64;
        let window = if open < PROGRESS_RATE * END_WINDOW as f64 * mean {
            END_WINDOW
        } else {
            PROGRESS_WINDOW
        };
        let Some(k) = n.checked_sub(window) else {
            return false;
        };
        let Some(&(_, before, asked_before, front_before)) =
            self.progress.iter().rev().find(|p| p.0 <= k)
        else {
            return false;
        };
        if (self.front.len() as f64) < (1.0 - FRONT_SHRINK) * front_before as f64 {
            return false;
        }
        before - open < PROGRESS_RATE * (self.asked - asked_before)
            && before - open < PROGRESS_RATE * window as f64 * mean
    }

    /// When extraction has led the front into a state no fill can take, the
    /// run goes back to an earlier step (3/4, 1/2, 1/4, 1/8, 1/16 and 1/32
    /// of the way, then the start) and fills the region left there: a fill
    /// that fails on a front extraction has tangled may still take the
    /// front of the first rows. The first mesh whose worst quad has a scaled
    /// Jacobian of at least [`REWIND_GOOD`] is taken; if none has, the best
    /// of those made. The history then holds the steps kept and the fill,
    /// so undo goes back to the step rewound to.
    /// Each step is tried once and only before the current one: a replay is
    /// deterministic, so a step tried again (a run of fewer than four steps)
    /// or the current step (a run stuck at its first step, whose fill has
    /// just failed on the same front) would fail the same way, at the cost
    /// of a whole fill (seconds on a front of thousands of nodes).
    pub(super) fn rewind_and_fill(&mut self) -> Option<StepReport> {
        if self.rewound {
            return None;
        }
        self.rewound = true;
        let n = self.history.len();
        let mut tried = n;
        let mut best: Option<(f64, Mesher, StepReport)> = None;
        for k in [3 * n / 4, n / 2, n / 4, n / 8, n / 16, n / 32, 0] {
            if k >= tried {
                continue;
            }
            tried = k;
            let mut fresh = self.replayed(&self.history[..k]);
            let kept = fresh.mesh.quads.len();
            // Only a fill that closes the whole front ends the run.
            let filled = fresh.commit_fill().filter(|_| fresh.front.is_empty());
            if let Some(mut r) = filled {
                r.removed = self.mesh.quads.len().saturating_sub(kept);
                let worst = fresh.mesh.worst_scaled_jacobian();
                if best.as_ref().is_none_or(|b| worst > b.0) {
                    best = Some((worst, fresh, r));
                }
                if worst >= REWIND_GOOD {
                    break;
                }
            }
        }
        let (_, mut fresh, r) = best?;
        fresh.rewound = true;
        *self = fresh;
        Some(r)
    }

    /// Replays one recorded action.
    pub(super) fn replay(&mut self, a: &Action) -> bool {
        match a {
            Action::Auto => self.step().is_ok(),
            Action::Correction(c) => self.correct(c).is_ok(),
            Action::Fill => self.commit_fill().is_some(),
        }
    }

    /// A fill taken as a step of its own (after rewinding, or replayed).
    pub(super) fn commit_fill(&mut self) -> Option<StepReport> {
        self.fill_retry_at = 0;
        let r = self.fill_rest()?;
        self.history.push(Action::Fill);
        self.undone.clear();
        self.stats.record(&r, self.mesh.quads.len());
        Some(r)
    }

    /// Fills the whole region left with [`fill::fill_region`] and empties
    /// the front; where that fails, fills the regions left one by one,
    /// removing up to [`FILL_RINGS`] rings of elements around those it
    /// cannot take. `None` when nothing changed (tried again after a
    /// quarter as many steps as made so far).
    pub(super) fn fill_rest(&mut self) -> Option<StepReport> {
        let step = self.history.len();
        if step < self.fill_retry_at {
            return None;
        }
        let ids: Vec<u32> = self.front.live_loops().collect();
        let loops: Vec<Vec<u32>> = ids.iter().map(|&l| self.front.loop_nodes(l)).collect();
        let mut r = self.report(StepKind::Fill);
        if let Ok(f) = fill::fill_region(&loops, &self.mesh.nodes) {
            self.commit_region(f, &ids, &mut r);
            return Some(r);
        }
        // The regions left one by one (each counter-clockwise loop with the
        // clockwise loops inside it: holes, or islands of elements a
        // rip-up cut loose), and where none of those can be filled
        // either, the elements around what is left are removed ring by
        // ring and the wider regions filled: a pocket where a coarse row
        // met a fine one is a sliver no fill takes, but a few rings out its
        // loop runs through whole elements. This only ever takes off the
        // elements around the regions left, never the whole run.
        for rings in 0..=FILL_RINGS {
            if rings > 0 {
                let ids: Vec<u32> = self.front.live_loops().collect();
                let (removed, _) = self.remove_around(&ids, 1, true);
                r.removed += removed;
            }
            let ids: Vec<u32> = self.front.live_loops().collect();
            let regions = self.regions(&ids);
            if rings == 0 && regions.len() == 1 {
                continue;
            }
            for region in regions {
                let part: Vec<Vec<u32>> = region
                    .iter()
                    .map(|&k| self.front.loop_nodes(ids[k]))
                    .collect();
                let ff = fill::fill_region(&part, &self.mesh.nodes);
                if let Ok(f) = ff {
                    let lids: Vec<u32> = region.iter().map(|&k| ids[k]).collect();
                    self.commit_region(f, &lids, &mut r);
                }
            }
            if self.front.is_empty() {
                self.keep_standing(&mut r);
                return Some(r);
            }
        }
        if r.quads.is_empty() {
            self.fill_retry_at = step + (step / 4).max(50);
            if r.removed == 0 {
                return None;
            }
            // Nothing filled, but elements were removed: the step is the
            // rip-up it was.
            r.kind = StepKind::RipUp;
        }
        self.keep_standing(&mut r);
        Some(r)
    }

    /// Keeps in report `r` only the quads still in the mesh: a fill that
    /// removes rings of elements round what it could not take may remove
    /// quads it made itself a ring before.
    fn keep_standing(&self, r: &mut StepReport) {
        if r.removed == 0 {
            return;
        }
        let standing: std::collections::BTreeSet<[u32; 4]> =
            self.mesh.quads.iter().copied().collect();
        r.quads.retain(|q| standing.contains(q));
    }

    /// The regions bounded by front loops `ids`, as indices into `ids`: each
    /// counter-clockwise loop, followed by the clockwise loops most of
    /// whose nodes lie inside it and inside no smaller one. A clockwise loop in no
    /// counter-clockwise one makes every loop one region.
    fn regions(&self, ids: &[u32]) -> Vec<Vec<usize>> {
        let nodes = &self.mesh.nodes;
        let area: Vec<f64> = ids
            .iter()
            .map(|&l| self.front.loop_area(l, nodes))
            .collect();
        let outline: Vec<Vec<Point>> = ids
            .iter()
            .map(|&l| {
                self.front
                    .loop_nodes(l)
                    .iter()
                    .map(|&v| nodes[v as usize])
                    .collect()
            })
            .collect();
        let mut regions: Vec<Vec<usize>> = Vec::new();
        let mut region_of = vec![usize::MAX; ids.len()];
        for k in (0..ids.len()).filter(|&k| area[k] > 0.0) {
            region_of[k] = regions.len();
            regions.push(vec![k]);
        }
        for k in (0..ids.len()).filter(|&k| area[k] <= 0.0) {
            let inside = (0..ids.len())
                .filter(|&o| {
                    // Most of its nodes (a node it shares with the loop
                    // around it, at a pinch, may test either way).
                    let inside = outline[k]
                        .iter()
                        .filter(|&&p| crate::geom::point_in_polygon(p, &outline[o]))
                        .count();
                    area[o] > 0.0 && 2 * inside > outline[k].len()
                })
                .min_by(|&a, &b| area[a].total_cmp(&area[b]));
            match inside {
                Some(o) => regions[region_of[o]].push(k),
                None => return vec![(0..ids.len()).collect()],
            }
        }
        regions
    }

    /// Adds a region fill's nodes and quads to the mesh and to report `r`,
    /// and takes the loops it filled off the front.
    fn commit_region(&mut self, f: fill::RegionFill, loops: &[u32], r: &mut StepReport) {
        for p in f.points {
            let v = self.add_node(p);
            r.new_nodes.push(v);
        }
        for q in f.quads {
            self.push_quad(q);
            r.quads.push(q);
        }
        for &l in loops {
            self.front.remove_loop(l);
        }
    }

    /// Commits an element chosen by the user at reference node `c.reference`.
    pub fn correct(&mut self, c: &Correction) -> Result<StepReport, MeshError> {
        let r = self.apply_correction(c)?;
        self.history.push(Action::Correction(c.clone()));
        self.undone.clear();
        self.stats.record(&r, self.mesh.quads.len());
        Ok(r)
    }

    /// Checks that [`Mesher::correct`] would commit `c` now, without
    /// committing it, and gives its element: the guard's score (in
    /// `[0, 1]`: the quality of the quad and of the front it leaves) and
    /// the quad's corners. The editor marks the front nodes an element can
    /// be closed onto, and how good that element would be.
    pub fn check_correction(&mut self, c: &Correction) -> Result<CheckedElement, MeshError> {
        let (_, cand, score) = self.correction_cand(c)?;
        Ok(CheckedElement {
            score,
            quad: cand.corners(&self.front, &self.mesh.nodes),
        })
    }

    /// The element of a correction, checked with relaxed limits.
    fn correction_cand(&mut self, c: &Correction) -> Result<(SlotId, Cand, f64), MeshError> {
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
        match self.check(cand, relaxed) {
            Some(score) => Ok((s, cand, score)),
            None => Err(MeshError::InvalidCorrection { node: c.reference }),
        }
    }

    pub(super) fn apply_correction(&mut self, c: &Correction) -> Result<StepReport, MeshError> {
        self.memo.clear();
        let (s, cand, _) = self.correction_cand(c)?;
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
    pub fn sample_of(&self, r: &StepReport) -> Option<crate::model::sample::Sample> {
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
        crate::model::sample::Sample::from_front(
            &left?,
            pos(p0)?,
            &right?,
            t,
            pos(pn)?,
            crate::model::sample::Source::Correction,
        )
    }

    /// Runs to the end; `progress` is called after every step with how far
    /// the run has got.
    pub fn run(&mut self, mut progress: impl FnMut(RunProgress)) -> Result<(), MeshError> {
        self.run_with(|_, at| {
            progress(at);
            ControlFlow::Continue(())
        })
        .map(|_| ())
    }

    /// Steps until the mesh is complete or `each` breaks; `each` sees every
    /// step's report and how far the run has got after it (a background
    /// run counts steps, shows the last element and its progress, and stops
    /// when cancelled). Returns whether the mesh is complete.
    pub fn run_with(
        &mut self,
        mut each: impl FnMut(&StepReport, RunProgress) -> ControlFlow<()>,
    ) -> Result<bool, MeshError> {
        // The meshed share is measured every PROGRESS_EVERY steps (it walks
        // the front).
        let mut meshed = self.meshed_share();
        let mut taken = 0;
        while let StepOutcome::Stepped(r) = self.step()? {
            taken += 1;
            if taken % PROGRESS_EVERY == 0 || self.front.is_empty() {
                meshed = self.meshed_share();
            }
            let at = RunProgress {
                front: self.front.len(),
                meshed,
            };
            if each(&r, at).is_break() {
                return Ok(self.is_done());
            }
        }
        Ok(true)
    }

    /// Undoes the last step by replaying the others (steps are
    /// deterministic), from the [`Mesher::checkpoint`] if there is one
    /// before the step, else from the start. Unless the checkpoint is at
    /// most `2 ×` [`CHECKPOINT_BEHIND`] actions back, the replay keeps a new
    /// one [`CHECKPOINT_BEHIND`] actions before the end. Undo after undo
    /// thus replays a few hundred steps, not the whole run.
    /// Returns false when there is nothing to undo.
    pub fn undo(&mut self) -> bool {
        let Some(a) = self.history.pop() else {
            return false;
        };
        let n = self.history.len();
        let near = self
            .usable_checkpoint(n)
            .is_some_and(|c| n - c.history.len() <= 2 * CHECKPOINT_BEHIND);
        let keep_at = (!near && n > CHECKPOINT_BEHIND).then(|| n - CHECKPOINT_BEHIND);
        let mut fresh = self.replayed_keeping(&self.history, keep_at);
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
    /// `actions` must be the first of this run's history.
    pub(super) fn replayed(&self, actions: &[Action]) -> Mesher {
        self.replayed_keeping(actions, None)
    }

    /// The [`Mesher::checkpoint`], if a replay of the first `n` actions of
    /// the history can start from it.
    fn usable_checkpoint(&self, n: usize) -> Option<&Arc<Mesher>> {
        let c = self.checkpoint.as_ref().filter(|c| c.history.len() <= n)?;
        debug_assert!(self.history.starts_with(&c.history));
        Some(c)
    }

    /// [`Mesher::replayed`] from the [`Mesher::checkpoint`] when it can
    /// start there; keeps a new checkpoint after `keep_at` actions (if the
    /// replay passes there), else the one it started from.
    fn replayed_keeping(&self, actions: &[Action], keep_at: Option<usize>) -> Mesher {
        debug_assert!(self.history.starts_with(actions));
        let base = self.usable_checkpoint(actions.len());
        let (mut fresh, start) = match base {
            Some(c) => (Mesher::clone(c), c.history.len()),
            None => (
                Mesher::with_size(
                    self.boundary.clone(),
                    self.initial_model.clone(),
                    self.params.clone(),
                    self.size.clone(),
                ),
                0,
            ),
        };
        fresh.replaying = true;
        // The checkpoint's model is already the one set before `start`.
        let mut changes = self
            .model_changes
            .iter()
            .filter(|(at, _)| *at >= start)
            .peekable();
        let mut kept = None;
        for (i, a) in actions.iter().enumerate().skip(start) {
            if keep_at == Some(i) {
                kept = Some(Arc::new(fresh.clone()));
            }
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
        fresh.checkpoint = kept.or_else(|| base.cloned());
        fresh
    }

    /// Meshes the rest with `model` (the editor's refit). Steps already
    /// taken stay as they are; undo and replay switch models at the same
    /// point.
    pub fn set_model(&mut self, model: Arc<dyn Model>) {
        self.model_changes.push((self.history.len(), model.clone()));
        self.model = model;
        self.memo.clear();
    }

    pub(super) fn add_node(&mut self, p: Point) -> u32 {
        self.mesh.nodes.push(p);
        self.incident.push(Vec::new());
        self.row_run.push(super::transition::FRESH_ROW);
        (self.mesh.nodes.len() - 1) as u32
    }

    pub(super) fn push_quad(&mut self, q: [u32; 4]) {
        let k = self.mesh.quads.len() as u32;
        let mut centre = Point::ZERO;
        for &v in &q {
            self.incident[v as usize].push(k);
            centre += self.mesh.nodes[v as usize];
        }
        self.asked += self.size.at(centre * 0.25).powi(2);
        self.mesh.quads.push(q);
    }

    /// Removes the quads marked in `removed` (indexed by quad), keeping the
    /// others in order, and renumbers the incidence lists in place.
    /// Returns the number removed.
    pub(super) fn remove_quads(&mut self, removed: &[bool]) -> usize {
        // New index of each quad: its index less the removed ones before it.
        let mut new_index = Vec::with_capacity(removed.len());
        let mut kept = 0u32;
        for &gone in removed {
            new_index.push(kept);
            kept += u32::from(!gone);
        }
        for list in &mut self.incident {
            list.retain(|&k| !removed[k as usize]);
            for k in list.iter_mut() {
                *k = new_index[*k as usize];
            }
        }
        let before = self.mesh.quads.len();
        let mut k = 0;
        self.mesh.quads.retain(|_| {
            let keep = !removed[k];
            k += 1;
            keep
        });
        before - self.mesh.quads.len()
    }
}

#[cfg(test)]
impl Mesher {
    /// A mesher with the shipped model and the default parameters over one
    /// boundary loop through `pts`, for tests that set up a front by hand.
    pub(super) fn of_loop(pts: Vec<Point>) -> Mesher {
        Mesher::of_loops(vec![pts])
    }

    /// As [`Mesher::of_loop`], over the loops through `loops` (the outer
    /// one first).
    pub(super) fn of_loops(loops: Vec<Vec<Point>>) -> Mesher {
        let mut points = Vec::new();
        let mut ids = Vec::new();
        for l in loops {
            ids.push((points.len()..points.len() + l.len()).collect());
            points.extend(l);
        }
        let b = Boundary::new(points, ids, None).expect("valid loops");
        let model = Arc::new(crate::model::default_model().expect("the shipped model"));
        Mesher::new(b, model, MeshParams::DEFAULT)
    }

    /// Steps to the end, checking the invariants after every step (a
    /// failed step or check panics); returns the steps' kinds.
    pub(super) fn run_checked(&mut self) -> Vec<StepKind> {
        let mut kinds = Vec::new();
        loop {
            match self.step() {
                Ok(StepOutcome::Done) => break,
                Ok(StepOutcome::Stepped(r)) => {
                    self.check_invariants()
                        .unwrap_or_else(|e| panic!("step {}: {e}", r.index));
                    kinds.push(r.kind);
                }
                Err(e) => panic!("{e}"),
            }
        }
        kinds
    }
}

//! The [`Mesher`] session: the extraction state over one boundary (mesh,
//! front, reference queue), its public step API, and its history: every
//! action is recorded, so undo replays the others, redo takes undone ones
//! again, a project file rebuilds a run, and a model set mid-run is
//! switched at the same point on replay.

use super::candidate::Cand;
use super::candidate::Rejections;
use super::fill_step::FillBudget;
use super::guard::{Limits, Scratch};
use super::ladder::{Repairs, RowStarts, Rung, SmallLoops, WatchedLoops};
use super::mapped::GridsSeen;
use super::memo::EvalMemo;
use super::params::MeshParams;
use super::queue::RefQueue;
use super::report::{
    Action, CheckedElement, Correction, MeshError, RunProgress, StepKind, StepOutcome, StepReport,
    StepStats,
};
use super::size::SizeField;
use super::transition::RowRuns;
use super::watch::ProgressWatch;
use crate::boundary::Boundary;
use crate::front::{Front, SlotId};
use crate::geom::{AngleLimit, Point, StraightLimit};
use crate::mesh::QuadMesh;
use crate::model::{ElementType, Model, RulesModel};
use std::f64::consts::PI;
use std::ops::ControlFlow;
use std::sync::Arc;

/// Cell width of the front's edge grid: as fine as the finest elements (the
/// grid caps its cell count), so a query near fine elements stays short.
pub(super) fn grid_cell(size: &SizeField) -> f64 {
    2.0 * size.range()[0]
}

/// The element extraction loop over one boundary.
///
/// Its fields fall in three parts: the input (boundary, parameters,
/// model, size field), the mesh state (the mesh, the front, node
/// incidence and the reference-point queue) with each heuristic's own
/// state beside it, and the [`Record`] of the session (history, undo,
/// replay, step counts).
#[derive(Clone)]
pub struct Mesher {
    // The input.
    pub(super) boundary: Boundary,
    pub(super) params: MeshParams,
    /// The model meshing goes on with (see [`Record::model_changes`]).
    pub(super) model: Arc<dyn Model>,
    /// The element size wanted anywhere in the domain.
    pub(super) size: Arc<SizeField>,
    /// The rule-based model the relaxed rung and the remedies use.
    pub(super) rules: RulesModel,
    /// The area inside the boundary.
    pub(super) domain_area: f64,
    /// The boundary's node count: nodes `0..boundary_nodes` are the
    /// boundary's ([`QuadMesh::is_boundary`], without summing the loops
    /// at every call).
    pub(super) boundary_nodes: usize,
    /// The angle limits the ladder tests front angles against at every
    /// step, from the parameters.
    pub(super) angles: FrontAngles,

    // The mesh state.
    pub(super) mesh: QuadMesh,
    pub(super) front: Front,
    /// Quads incident to each node.
    pub(super) incident: Vec<Vec<u32>>,
    pub(super) queue: RefQueue,
    /// Buffers the guard reuses.
    pub(super) scratch: Scratch,

    // Each heuristic's state.
    pub(super) rows: RowStarts,
    pub(super) small: SmallLoops,
    pub(super) watched: WatchedLoops,
    pub(super) grids: GridsSeen,
    pub(super) bands: super::band::BandsSeen,
    pub(super) fans: super::fan::Fans,
    pub(super) notches: super::notch::Notches,
    pub(super) runs: RowRuns,
    pub(super) repairs: Repairs,
    pub(super) chords: super::repair::ChordsSeen,
    pub(super) fill: FillBudget,
    pub(super) watch: ProgressWatch,
    pub(super) rejections: Rejections,
    /// Evaluations of reference points put back in the queue.
    pub(super) memo: EvalMemo,

    // The session.
    pub(super) record: Record,
}

/// The angle limits the ladder tests front angles against at every step
/// (the parameters' degrees in radians, ready for a test mostly by sign).
#[derive(Clone, Copy, Debug)]
pub(super) struct FrontAngles {
    /// [`MeshParams::seam_angle`]: a sharp corner this sharp is tried for
    /// a seam.
    pub(super) seam: AngleLimit,
    /// The lower [`MeshParams::reference_angle`]: a sharp corner.
    pub(super) sharp: AngleLimit,
    /// [`TransitionTuning::straight`](super::tuning::TransitionTuning::straight):
    /// the nodes inside a transition's stretch.
    pub(super) straight: StraightLimit,
}

impl FrontAngles {
    fn of(params: &MeshParams) -> FrontAngles {
        FrontAngles {
            seam: AngleLimit::new(params.seam_angle.to_radians()),
            sharp: AngleLimit::new(params.reference_angle[0].to_radians()),
            straight: StraightLimit::new(params.tuning.transition.straight),
        }
    }
}

/// A run's record: what undo, redo, replay and project files use.
#[derive(Clone)]
pub(super) struct Record {
    /// The model the run started with (replays start from it).
    pub(super) initial_model: Arc<dyn Model>,
    /// Models set with [`Mesher::set_model`], each with the number of
    /// actions taken before it.
    pub(super) model_changes: Vec<(usize, Arc<dyn Model>)>,
    pub(super) history: Vec<Action>,
    /// Actions undone, the most recent last: what [`Mesher::redo`] takes
    /// again. A new step or correction clears it.
    pub(super) undone: Vec<Action>,
    /// This run as it was after the first actions of its history (as many
    /// as the checkpoint's own history holds): replays start from it
    /// rather than from the boundary ([`Mesher::undo`]). Kept only while
    /// those actions are still the first of the history.
    pub(super) checkpoint: Option<Arc<Mesher>>,
    /// Set while history is being replayed (no rewinding then).
    pub(super) replaying: bool,
    /// A rewind has been tried.
    pub(super) rewound: bool,
    /// The run has been made again with balanced fans
    /// ([`Mesher::refan`]), or that was tried.
    pub(super) refan_tried: bool,
    pub(super) stats: StepStats,
    pub(super) step_limit: usize,
}

/// A user's correction is checked with angle limits this near to none
/// (radians): any element that is not degenerate is the user's to choose.
const ANY_ANGLE: f64 = 1e-6;

/// Element counts estimated from a domain's area are capped here, so a
/// domain of microscopic segments gets a large budget, not an overflow.
const ESTIMATE_CAP: f64 = 1e9;

/// [`Mesher::undo`] keeps a [`Record::checkpoint`] this many actions
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
        let est = (domain_area / (min_seg * min_seg)).min(ESTIMATE_CAP) as usize;
        let work = est.max(boundary.node_count());
        let step_limit = params.max_steps.unwrap_or(
            params.tuning.fill.step_limit_per_element * work + params.tuning.fill.step_limit_extra,
        );
        let quads = size.quad_estimate().min(ESTIMATE_CAP);
        let fill_after = (params.tuning.fill.budget * quads) as usize
            + boundary.node_count()
            + params.tuning.fill.budget_extra;
        let angles = FrontAngles::of(&params);
        let mut m = Mesher {
            boundary,
            params,
            model: model.clone(),
            size,
            rules: RulesModel::DEFAULT,
            domain_area,
            boundary_nodes: mesh.n_boundary(),
            angles,
            mesh,
            front,
            incident: Vec::new(),
            queue: RefQueue::default(),
            scratch: Scratch::default(),
            rows: RowStarts::default(),
            small: SmallLoops::default(),
            watched: WatchedLoops::default(),
            grids: GridsSeen::default(),
            bands: Default::default(),
            fans: Default::default(),
            notches: Default::default(),
            runs: RowRuns::default(),
            repairs: Repairs::default(),
            chords: Default::default(),
            fill: FillBudget::new(fill_after),
            watch: ProgressWatch::default(),
            rejections: Rejections::default(),
            memo: EvalMemo::default(),
            record: Record {
                initial_model: model,
                model_changes: Vec::new(),
                history: Vec::new(),
                undone: Vec::new(),
                checkpoint: None,
                replaying: false,
                rewound: false,
                refan_tried: false,
                stats: StepStats::default(),
                step_limit,
            },
        };
        m.rows = RowStarts::new(m.front.live_loops());
        m.incident = vec![Vec::new(); m.mesh.nodes.len()];
        m.runs = RowRuns::new(m.mesh.nodes.len());
        for s in 0..m.front.slots.len() as SlotId {
            m.push(s);
        }
        m.fans = super::fan::Fans::of(&m);
        m.notches = super::notch::Notches::of(&m);
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
        &self.record.stats
    }

    /// Steps taken so far.
    pub fn steps(&self) -> usize {
        self.record.history.len()
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
        if self.record.history.len() >= self.record.step_limit {
            return Err(MeshError::StepLimit {
                limit: self.record.step_limit,
                remaining: self.front.len(),
            });
        }
        let mut r = match self.auto_step() {
            Ok(r) => r,
            Err(e) => {
                if self.params.fill && !self.record.replaying {
                    if let Some(r) = self.refan() {
                        return Ok(StepOutcome::Stepped(Box::new(r)));
                    }
                    if let Some(r) = self.rewind_and_fill() {
                        self.forget(None);
                        return Ok(StepOutcome::Stepped(Box::new(r)));
                    }
                }
                return Err(e);
            }
        };
        if r.kind == StepKind::Fill && r.rung != Rung::FillLayers {
            if let Some(r) = self.refan() {
                return Ok(StepOutcome::Stepped(Box::new(r)));
            }
        }
        // The memory forgets what the step may have changed: the box of
        // the quads it made (an element, a bridge, a transition, a small
        // loop or a narrow rectangle closed, a row's first square), the
        // region a seam gave up, a chord split's chord, the nodes a loop's
        // relaxing moved (where they were and are), the region a rip-up
        // took, or everything after any other step; and the slots of the
        // short loops it relinked (`SHORT_LOOP`).
        let changed_box = self.memo.changed_box.take();
        let local = match r.kind {
            StepKind::RipUp => changed_box,
            _ if r.removed > 0 => None,
            StepKind::Element
            | StepKind::Bridge
            | StepKind::Transition
            | StepKind::Close4
            | StepKind::Close6
            | StepKind::Mapped
            | StepKind::Notch
            | StepKind::Square => crate::geom::Aabb::of(
                r.quads
                    .iter()
                    .flatten()
                    .map(|&v| self.mesh.nodes[v as usize]),
            ),
            StepKind::Seam | StepKind::Split | StepKind::Relax => changed_box,
            _ => None,
        };
        self.forget(local);
        r.rejected = self.rejections.take();
        if r.kind != StepKind::Relax {
            self.repairs.other_step();
        }
        self.record.history.push(Action::Auto);
        self.record.undone.clear();
        self.record.stats.record(&r, self.mesh.quads.len());
        Ok(StepOutcome::Stepped(Box::new(r)))
    }

    pub(super) fn report(&self, kind: StepKind) -> StepReport {
        StepReport::new(self.record.history.len(), kind)
    }

    /// Replays one recorded action.
    pub(super) fn replay(&mut self, a: &Action) -> bool {
        match a {
            Action::Auto => self.step().is_ok(),
            Action::Correction(c) => self.correct(c).is_ok(),
            Action::Fill => self.commit_fill().is_some(),
        }
    }

    /// Commits an element chosen by the user at reference node `c.reference`.
    pub fn correct(&mut self, c: &Correction) -> Result<StepReport, MeshError> {
        let r = self.apply_correction(c)?;
        self.record
            .history
            .push(Action::Correction(Box::new(c.clone())));
        self.record.undone.clear();
        self.record.stats.record(&r, self.mesh.quads.len());
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
            min_corner: ANY_ANGLE,
            max_corner: PI - ANY_ANGLE,
            min_front: ANY_ANGLE,
        };
        match self.check(cand, relaxed) {
            Some(score) => Ok((s, cand, score)),
            None => Err(MeshError::InvalidCorrection { node: c.reference }),
        }
    }

    pub(super) fn apply_correction(&mut self, c: &Correction) -> Result<StepReport, MeshError> {
        self.forget(None);
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
        // The meshed share is measured every `tuning.watch.every` steps (it walks
        // the front).
        let mut meshed = self.meshed_share();
        let mut taken = 0;
        while let StepOutcome::Stepped(r) = self.step()? {
            taken += 1;
            if taken % self.params.tuning.watch.every == 0 || self.front.is_empty() {
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
    /// deterministic), from the [`Record::checkpoint`] if there is one
    /// before the step, else from the start. Unless the checkpoint is at
    /// most `2 ×` [`CHECKPOINT_BEHIND`] actions back, the replay keeps a new
    /// one [`CHECKPOINT_BEHIND`] actions before the end. Undo after undo
    /// thus replays a few hundred steps, not the whole run.
    /// Returns false when there is nothing to undo.
    pub fn undo(&mut self) -> bool {
        let Some(a) = self.record.history.pop() else {
            return false;
        };
        let n = self.record.history.len();
        let near = self
            .usable_checkpoint(n)
            .is_some_and(|c| n - c.record.history.len() <= 2 * CHECKPOINT_BEHIND);
        let keep_at = (!near && n > CHECKPOINT_BEHIND).then(|| n - CHECKPOINT_BEHIND);
        let mut fresh = self.replayed_keeping(&self.record.history, keep_at);
        fresh.record.rewound = self.record.rewound;
        fresh.record.refan_tried = self.record.refan_tried;
        fresh.record.undone = std::mem::take(&mut self.record.undone);
        fresh.record.undone.push(a);
        *self = fresh;
        true
    }

    /// The actions taken so far, in order.
    pub fn actions(&self) -> &[Action] {
        &self.record.history
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
        self.record.undone.len()
    }

    /// Takes the most recently undone step again (the same action: an
    /// automatic step, the user's correction, or a fill) and returns its
    /// report; `Ok(None)` when nothing was undone.
    pub fn redo(&mut self) -> Result<Option<StepReport>, MeshError> {
        let Some(a) = self.record.undone.pop() else {
            return Ok(None);
        };
        let rest = std::mem::take(&mut self.record.undone);
        let r = self.take(&a);
        self.record.undone = rest;
        if r.is_err() {
            self.record.undone.push(a);
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

    /// The [`Record::checkpoint`], if a replay of the first `n` actions of
    /// the history can start from it.
    fn usable_checkpoint(&self, n: usize) -> Option<&Arc<Mesher>> {
        let c = self
            .record
            .checkpoint
            .as_ref()
            .filter(|c| c.record.history.len() <= n)?;
        debug_assert!(self.record.history.starts_with(&c.record.history));
        Some(c)
    }

    /// [`Mesher::replayed`] from the [`Record::checkpoint`] when it can
    /// start there; keeps a new checkpoint after `keep_at` actions (if the
    /// replay passes there), else the one it started from.
    fn replayed_keeping(&self, actions: &[Action], keep_at: Option<usize>) -> Mesher {
        debug_assert!(self.record.history.starts_with(actions));
        let base = self.usable_checkpoint(actions.len());
        let (mut fresh, start) = match base {
            Some(c) => (Mesher::clone(c), c.record.history.len()),
            None => (
                Mesher::with_size(
                    self.boundary.clone(),
                    self.record.initial_model.clone(),
                    self.params.clone(),
                    self.size.clone(),
                ),
                0,
            ),
        };
        fresh.record.replaying = true;
        // The checkpoint's model is already the one set before `start`.
        let mut changes = self
            .record
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
        fresh.record.replaying = false;
        fresh.record.checkpoint = kept.or_else(|| base.cloned());
        fresh
    }

    /// Meshes the rest with `model` (the editor's refit). Steps already
    /// taken stay as they are; undo and replay switch models at the same
    /// point.
    pub fn set_model(&mut self, model: Arc<dyn Model>) {
        self.record
            .model_changes
            .push((self.record.history.len(), model.clone()));
        self.model = model;
        self.forget(None);
    }

    pub(super) fn add_node(&mut self, p: Point) -> u32 {
        self.mesh.nodes.push(p);
        self.incident.push(Vec::new());
        self.runs.add_node();
        (self.mesh.nodes.len() - 1) as u32
    }

    /// Adds `points` as new nodes (their ids appended to `ids`) and the
    /// `quads`, indices into `ids`, to the mesh and to the report `r`.
    pub(super) fn add_patch(
        &mut self,
        r: &mut StepReport,
        ids: &mut Vec<u32>,
        points: &[Point],
        quads: &[[usize; 4]],
    ) {
        for &p in points {
            let v = self.add_node(p);
            r.new_nodes.push(v);
            ids.push(v);
        }
        for q in quads {
            let quad = q.map(|k| ids[k]);
            self.push_quad(quad);
            r.quads.push(quad);
        }
    }

    /// The slots of the front's live loops that `keep` keeps, the highest
    /// id first: a rung's list of places to try, popped lowest id first.
    pub(super) fn initial_slots(&self, keep: impl Fn(SlotId) -> bool) -> Vec<SlotId> {
        let mut slots: Vec<SlotId> = self
            .front
            .live_loops()
            .flat_map(|l| self.front.loop_slots(l))
            .filter(|&s| keep(s))
            .collect();
        slots.sort_unstable();
        slots.reverse();
        slots
    }

    /// True when a patch may take the front chain `chain` (consecutive
    /// slots) and run the front from its first slot through `path` (new
    /// points, in front order) to its last: no front node other than the
    /// chain's lies inside the outline (the chain, then `path` backwards),
    /// and no front edge crosses the outline's new edges.
    pub(super) fn chain_is_clear(&mut self, chain: &[SlotId], path: &[Point]) -> bool {
        let mut outline: Vec<Point> = chain.iter().map(|&t| self.world(t)).collect();
        outline.extend(path.iter().rev());
        let Some(bb) = crate::geom::Aabb::of(outline.iter().copied()) else {
            return false;
        };
        self.front
            .edges_near(bb.min, bb.max, &mut self.scratch.near);
        let own: Vec<u32> = chain.iter().map(|&t| self.front.node(t)).collect();
        let (first, last) = (own[0], own[own.len() - 1]);
        // The outline's new edges: from the chain's last point through the
        // path backwards to its first.
        let k = chain.len() - 1;
        let new_edges: Vec<(Point, Point)> = (k..outline.len())
            .map(|i| (outline[i], outline[(i + 1) % outline.len()]))
            .collect();
        self.scratch.near.iter().all(|&e| {
            let (u, v) = (self.front.node(e), self.front.node(self.front.next(e)));
            let (a, b) = (self.mesh.nodes[u as usize], self.mesh.nodes[v as usize]);
            if !own.contains(&u) && crate::geom::point_in_polygon(a, &outline) {
                return false;
            }
            new_edges.iter().enumerate().all(|(i, &(x, y))| {
                // The first new edge starts at the chain's last node, the
                // last one ends at its first.
                let shared =
                    |w: u32| (i == 0 && w == last) || (i + 1 == new_edges.len() && w == first);
                shared(u) || shared(v) || !crate::geom::segments_intersect(x, y, a, b)
            })
        })
    }

    pub(super) fn push_quad(&mut self, q: [u32; 4]) {
        let k = self.mesh.quads.len() as u32;
        let mut centre = Point::ZERO;
        for &v in &q {
            self.incident[v as usize].push(k);
            centre += self.mesh.nodes[v as usize];
        }
        self.watch.made(self.size.at(centre * 0.25));
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

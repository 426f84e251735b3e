//! What a step did and why meshing stopped: step kinds and remedies, the
//! report of one step, step counts, the user's corrections and the actions
//! a run records (replayed by undo and by project files).

use super::ladder::Rung;
use crate::geom::Point;
use crate::model::{ElementType, Prediction};
use crate::quality::QuadQuality;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use thiserror::Error;

/// Why meshing stopped.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeshError {
    #[error("front loop {loop_index} (at node {node}) cannot be reduced: no valid element, closure or chord split")]
    Stuck { loop_index: u32, node: u32 },
    #[error("step limit of {limit} reached with {remaining} front nodes left")]
    StepLimit { limit: usize, remaining: usize },
    #[error("no progress: {steps} steps met less than a quarter of an element's area each, {remaining} front nodes left")]
    Stalled { steps: usize, remaining: usize },
    #[error("the correction at node {node} is not a valid element")]
    InvalidCorrection { node: u32 },
    #[error("node {node} is not on the front")]
    NotOnFront { node: u32 },
    #[error("the finished mesh is not valid: {problem}")]
    Final {
        problem: crate::mesh::InvariantError,
    },
}

/// A type-0 element taken from the model counts as [`Remedy::Rescaled`]
/// when its Pn lies further than this from the predicted Pn, in the
/// normalised frame (units of the front edge |P_r1 − P0|).
pub const RESCALED_BEYOND: f64 = 0.01;

/// What the guard had to do to the model's prediction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Remedy {
    /// The model's element was accepted as predicted.
    None,
    /// The model's element was taken with its Pn drawn towards the size
    /// field (the row's height, `Mesher::sized_pn`) by more than
    /// [`RESCALED_BEYOND`] of the front edge at P0: the model's type and
    /// direction, not its distance.
    Rescaled,
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
    /// Three front edges of a row taken by the 3-to-1 transition template
    /// (four quads): the row goes on coarser.
    Transition,
    /// A loop that is a logical rectangle closed by a mapped grid.
    Mapped,
    /// A fan of quads around a boundary corner between a short and a long
    /// segment.
    Fan,
    /// One or two quads cutting off a front edge far shorter than the
    /// given segments beside it.
    Notch,
    /// A loop split along a chord.
    Split,
    /// Two facing front edges joined by one quad across a gap no other
    /// step fits (a front collision).
    Bridge,
    /// Elements around a loop that could not be reduced were removed to
    /// give it room.
    RipUp,
    /// The region left was filled by a ring and a split triangulation.
    Fill,
    /// Before its region fill, the run was made again from the start with
    /// balanced corner fans and finished by extraction alone: every quad
    /// is new ([`super::Rung::Refan`]).
    Refan,
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
    /// The rung of the step ladder that took the step
    /// ([`Rung::User`] for the user's element).
    #[serde(default)]
    pub rung: Rung,
}

impl StepReport {
    /// The report of step `index` of `kind`, before the step fills it in.
    pub(crate) fn new(index: usize, kind: StepKind) -> StepReport {
        StepReport {
            index,
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
            rung: Rung::User,
        }
    }

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
    pub by_kind: BTreeMap<StepKind, usize>,
    /// Quads made by the steps of each kind (before any later rip-up,
    /// cleanup or remeshing): how much of a mesh the region fill made.
    #[serde(default)]
    pub quads_by_kind: BTreeMap<StepKind, usize>,
    /// Quads in the mesh after the last step: what extraction (and a
    /// region fill) left, before finishing (cleanup, remeshing of bad
    /// spots) changes the mesh. A fill's share of the mesh is
    /// `quads_made(Fill) / standing`.
    #[serde(default)]
    pub standing: usize,
    pub by_type: [usize; 3],
    /// Element steps by what the guard did to the model's element.
    pub by_remedy: BTreeMap<Remedy, usize>,
    pub skipped_references: usize,
    /// Pure-model mode: predictions the guard rejected.
    pub rejected_predictions: usize,
    /// Steps by the rung of the step ladder that took them.
    #[serde(default)]
    pub by_rung: BTreeMap<Rung, usize>,
    /// The run was made again with balanced corner fans before its region
    /// fill, and these are that run's counts ([`super::Rung::Refan`]).
    #[serde(default)]
    pub refanned: bool,
}

impl StepStats {
    /// Pure-model mode: the model's elements the guard accepted (as
    /// predicted or with Pn rescaled to the size field), and all the
    /// model's predictions (accepted + rejected).
    pub fn model_valid(&self) -> (usize, usize) {
        let ok = self.remedies(Remedy::None) + self.remedies(Remedy::Rescaled);
        (ok, ok + self.rejected_predictions)
    }

    /// Whether a run with these counts would be made again step for step
    /// under another [`super::Strategy`] or
    /// [`super::MeshParams::fill_after_layers`]: every step was taken by a
    /// rung that reads neither ([`Rung::ignores_strategy`]), and the run
    /// was not made again with balanced corner fans (the first try, which
    /// the counts leave out, may have read them).
    pub fn ignores_strategy(&self) -> bool {
        !self.refanned && self.by_rung.keys().all(|r| r.ignores_strategy())
    }

    /// Element steps with remedy `r`.
    pub fn remedies(&self, r: Remedy) -> usize {
        self.by_remedy.get(&r).copied().unwrap_or(0)
    }

    /// Steps of kind `k`.
    pub fn count(&self, k: StepKind) -> usize {
        self.by_kind.get(&k).copied().unwrap_or(0)
    }

    /// Quads made by steps of kind `k`.
    pub fn quads_made(&self, k: StepKind) -> usize {
        self.quads_by_kind.get(&k).copied().unwrap_or(0)
    }

    /// Adds the counts of another run (another face of the same domain):
    /// `standing` adds up too.
    pub fn add(&mut self, o: &StepStats) {
        self.steps += o.steps;
        self.standing += o.standing;
        for (k, n) in &o.by_kind {
            *self.by_kind.entry(*k).or_default() += n;
        }
        for (k, n) in &o.quads_by_kind {
            *self.quads_by_kind.entry(*k).or_default() += n;
        }
        for (t, n) in self.by_type.iter_mut().zip(o.by_type) {
            *t += n;
        }
        for (r, n) in &o.by_remedy {
            *self.by_remedy.entry(*r).or_default() += n;
        }
        self.skipped_references += o.skipped_references;
        self.rejected_predictions += o.rejected_predictions;
        self.refanned |= o.refanned;
    }

    /// Counts step `r`, after which the mesh holds `standing` quads.
    pub(super) fn record(&mut self, r: &StepReport, standing: usize) {
        self.steps += 1;
        self.standing = standing;
        *self.by_kind.entry(r.kind).or_default() += 1;
        *self.by_rung.entry(r.rung).or_default() += 1;
        *self.quads_by_kind.entry(r.kind).or_default() += r.quads.len();
        if let Some(t) = r.element_type {
            self.by_type[t as usize] += 1;
        }
        if r.kind == StepKind::Element {
            *self.by_remedy.entry(r.remedy).or_default() += 1;
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

/// What [`super::Mesher::check_correction`] finds of a correction that the
/// mesher would commit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CheckedElement {
    /// The guard's score of the element, in `[0, 1]`: the quality of the
    /// quad and of the front it leaves, as extraction weighs its own
    /// candidates. It is not the thesis's criteria (§1.2; see
    /// [`CheckedElement::quality`]).
    pub score: f64,
    /// The element's corners (P0, P_r1, the fourth corner, P_l1 for type
    /// 0; in the quad's node order for types 1 and 2).
    pub quad: [Point; 4],
}

impl CheckedElement {
    /// The element's own figures: angles, aspect, taper and whether it
    /// meets the thesis's criteria ([`QuadQuality::meets_thesis`]).
    pub fn quality(&self) -> QuadQuality {
        QuadQuality::of(self.quad)
    }
}

/// How far a run has got, after each of its steps ([`super::Mesher::run_with`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunProgress {
    /// Front nodes left.
    pub front: usize,
    /// The share of the domain's area meshed ([`super::Mesher::meshed_share`]),
    /// measured every 128 steps and when the front closes.
    pub meshed: f64,
}

/// One recorded step, as [`Mesher::actions`] lists them: replaying the
/// actions of a run with [`Mesher::take`] rebuilds it (steps are
/// deterministic), which is how undo works and how a project file keeps a
/// mesh that can be stepped on. A run keeps one per step, millions on a
/// large domain, so the rare correction is boxed and an action is two words.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Action {
    /// A step chosen by the mesher.
    Auto,
    /// An element given by the user.
    Correction(Box<Correction>),
    /// A fill taken after rewinding (see [`Mesher::rewind_and_fill`]).
    Fill,
}

/// Result of [`Mesher::step`].
#[derive(Clone, Debug, PartialEq)]
pub enum StepOutcome {
    Stepped(Box<StepReport>),
    Done,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(index: usize, kind: StepKind, quads: usize) -> StepReport {
        StepReport {
            quads: vec![[0, 1, 2, 3]; quads],
            ..StepReport::new(index, kind)
        }
    }

    #[test]
    fn an_action_is_two_words() {
        assert!(std::mem::size_of::<Action>() <= 2 * std::mem::size_of::<usize>());
    }

    #[test]
    fn stats_count_the_quads_each_kind_of_step_made() {
        let mut stats = StepStats::default();
        for (k, (kind, quads)) in [
            (StepKind::Element, 1),
            (StepKind::Transition, 4),
            (StepKind::Element, 1),
            (StepKind::Fill, 37),
        ]
        .into_iter()
        .enumerate()
        {
            stats.record(&step(k, kind, quads), 40 + k);
        }
        assert_eq!(stats.count(StepKind::Element), 2);
        assert_eq!(stats.quads_made(StepKind::Element), 2);
        assert_eq!(stats.quads_made(StepKind::Transition), 4);
        assert_eq!(stats.quads_made(StepKind::Fill), 37);
        assert_eq!(stats.quads_made(StepKind::Seam), 0);
        assert_eq!(stats.standing, 43);
        // Reports written before the count existed still read.
        let old = r#"{"steps":1,"by_kind":{"Fill":1},"by_type":[0,0,0],
            "by_remedy":{},"skipped_references":0,"rejected_predictions":0}"#;
        let read: StepStats = serde_json::from_str(old).unwrap();
        assert_eq!(read.count(StepKind::Fill), 1);
        assert_eq!(read.quads_made(StepKind::Fill), 0);
        assert_eq!(read.standing, 0);
    }
}

//! The step ladder: what one automatic step tries, in order (method §2,
//! thesis §5.1): notches cut off by rule, thin bands closed by rows, mapped grids on narrow logical
//! rectangles, fans at strongly graded corners of the boundary, a first row
//! on a loop without reference points, closing small loops, the fill inside
//! the first layers, the reference points in queue order, seams, chord
//! splits, a square cut, a relaxed rule-based element, relaxation, a
//! bridge across a gap, rip-up, and the fill as the last resort.

use super::candidate::Chosen;
use super::guard::Limits;
use super::memo::Eval;
use super::params::Strategy;
use super::queue::Entry;
use serde::{Deserialize, Serialize};

use super::repair::Squares;
use super::report::{MeshError, Remedy, StepReport};
use super::session::Mesher;
use crate::front::SlotId;
use std::collections::BTreeSet;
use std::f64::consts::PI;

/// The row-start rung's state (strategy B): the coarsest band and deepest
/// layer the queue had reached when loops left behind were last looked
/// for, the loops to check for a first row (no reference point on them)
/// and the front edges (by start slot) to start a row on: stretches of
/// the boundary left behind.
#[derive(Clone, Debug, Default)]
pub(super) struct RowStarts {
    key: (u32, u32),
    loops: Vec<u32>,
    edges: Vec<SlotId>,
}

impl RowStarts {
    /// Row starts for every loop of `loops` (a new front).
    pub(super) fn new(loops: impl Iterator<Item = u32>) -> RowStarts {
        RowStarts {
            loops: loops.collect(),
            ..RowStarts::default()
        }
    }

    /// Loop `lid` is new (a split or a join made it): it is checked for a
    /// first row.
    pub(super) fn check_loop(&mut self, lid: u32) {
        self.loops.push(lid);
    }

    /// Every loop of `live` is checked for a first row (instead of those
    /// waiting).
    pub(super) fn check_loops(&mut self, live: Vec<u32>) {
        self.loops = live;
    }
}

/// The small-loop rung's state: per loop id, the
/// [`Mesher::small_loop_key`] of the state in which that small loop last
/// neither closed nor settled (0: none), so the same state is not tried
/// again.
#[derive(Clone, Debug, Default)]
pub(super) struct SmallLoops {
    stuck: Vec<u64>,
}

/// The loops two rungs look at at every step, kept up to date from the
/// front's changes ([`crate::front::Front::take_changed`]) rather than
/// found among all the live loops each time: on a plate of a thousand
/// holes, most steps change one loop.
#[derive(Clone, Debug, Default)]
pub(super) struct WatchedLoops {
    /// The live loops of at most [`CLOSED_LOOP`] slots.
    small: BTreeSet<u32>,
    /// The loops of a size for a mapped grid changed since
    /// [`Rung::MappedGrid`] last found them not [`Mesher::grid_unseen`]:
    /// every unseen loop is among them.
    grid: BTreeSet<u32>,
    /// The front's last changes, a buffer kept for reuse.
    changed: Vec<u32>,
}

/// The repairs' budgets: rip-ups and relaxations taken so far, and
/// relaxations since the last other step.
#[derive(Clone, Debug, Default)]
pub(super) struct Repairs {
    rip_ups: usize,
    relaxes: usize,
    relax_streak: usize,
}

impl Repairs {
    /// A step of another kind than a relaxation was taken.
    pub(super) fn other_step(&mut self) {
        self.relax_streak = 0;
    }
}

/// The rungs of the step ladder: what one automatic step tries, in the
/// order of [`LADDER`]. The first rung that changes the mesh or the front
/// makes the step, and its report names it ([`super::StepReport::rung`]).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
)]
pub enum Rung {
    /// The step budget is spent: the region left is filled (or the run
    /// stops with [`MeshError::StepLimit`]).
    FillDue,
    /// The progress watch finds the run going round in circles: the region
    /// left is filled (or the run stops with [`MeshError::Stalled`]).
    FillStalled,
    /// A loop with no reference point (a new loop, or one left behind the
    /// band or layer the queue has moved on to) starts a row: a bridge
    /// across a gap a row would not fit, or a square.
    RowStart,
    /// Loops of 4 and 6 nodes close by the final patterns, settled first
    /// where they are too skewed.
    SmallLoop,
    /// Narrow logical rectangles, and (with
    /// [`super::tuning::MappedTuning::graded_grid`] on) loops of the given
    /// boundary graded past [`super::mapped::GRADED_SPREAD`], close by a
    /// mapped grid ([`super::MeshParams::mapped_rows`]).
    MappedGrid,
    /// A corner of the given boundary between a short and a long segment
    /// takes a fan of quads around it ([`super::tuning::FanTuning`]).
    Fan,
    /// A front edge far shorter than the given segments beside it is cut
    /// off with them ([`super::tuning::NotchTuning`]).
    Notch,
    /// A thin band (a loop with two short ends, or the ring between the
    /// front's two loops) closes by rows along it ([`super::tuning::BandTuning`]).
    Band,
    /// The region inside the first layers is filled
    /// ([`super::MeshParams::fill_after_layers`]).
    FillLayers,
    /// Reference points in queue order: a seam at a sharp corner, a
    /// transition at a wide row end, or the model's element under the
    /// guard and its remedies; poor elements wait while a better reference
    /// point of the same kind, band and layer exists.
    Queue,
    /// A seam at any sharp corner.
    SharpSeam,
    /// A small loop without a usable reference point split along its best
    /// chord.
    SmallSplit,
    /// A square on the shortest front edge.
    Square,
    /// The best rule-based element with relaxed limits, anywhere.
    Relaxed,
    /// A row started around a small hole no front has reached.
    HoleRow,
    /// A loop split along a chord.
    Split,
    /// The smallest stuck loop straightened, its interior nodes moved.
    Relax,
    /// A strip no step could take closed by its best mapped grid.
    Strip,
    /// Two facing front edges joined across a gap.
    Bridge,
    /// The elements around the smallest stuck loop removed.
    RipUp,
    /// The region left filled: the last resort.
    Fill,
    /// Not a rung of the ladder: after a failed step, the run went back
    /// to an earlier step and filled the region left there.
    Rewind,
    /// Not a rung of the ladder: before its region fill, the run was made
    /// again with balanced corner fans and finished by extraction alone
    /// (the report, of kind [`super::StepKind::Refan`], holds all of that
    /// run's quads).
    Refan,
    /// Not a rung of the ladder: an element given by the user.
    #[default]
    User,
}

/// Loops of at most this many nodes are closed by the final patterns
/// ([`Rung::SmallLoop`]: 4 nodes by one quad, 6 by the patterns of thesis
/// Figure 20); fixed by the method, not tuned.
const CLOSED_LOOP: usize = 6;

/// The step ladder: the order one automatic step tries its rungs in.
pub const LADDER: [Rung; 21] = [
    Rung::FillDue,
    Rung::FillStalled,
    Rung::Notch,
    Rung::Band,
    Rung::MappedGrid,
    Rung::Fan,
    Rung::RowStart,
    Rung::SmallLoop,
    Rung::FillLayers,
    Rung::Queue,
    Rung::SharpSeam,
    Rung::SmallSplit,
    Rung::Square,
    Rung::Relaxed,
    Rung::HoleRow,
    Rung::Split,
    Rung::Relax,
    Rung::Strip,
    Rung::Bridge,
    Rung::RipUp,
    Rung::Fill,
];

impl Rung {
    /// Whether a step this rung takes is the same whatever the run's
    /// [`super::Strategy`] and [`super::MeshParams::fill_after_layers`]:
    /// the rung reads neither, and it comes in [`LADDER`] before the first
    /// rung that does (the row start reads strategy B's queue; the fill of
    /// the first layers and the queue read both), so the rungs tried before
    /// it in a step read neither either. A run whose every step such a rung
    /// took would be made again step for step under the other settings.
    pub fn ignores_strategy(self) -> bool {
        matches!(
            self,
            Rung::Notch | Rung::Band | Rung::MappedGrid | Rung::Fan
        )
    }

    /// The rung's name as reports and tables print it.
    pub fn name(self) -> &'static str {
        match self {
            Rung::FillDue => "fill-due",
            Rung::FillStalled => "fill-stalled",
            Rung::RowStart => "row-start",
            Rung::SmallLoop => "small-loop",
            Rung::MappedGrid => "mapped-grid",
            Rung::Band => "band",
            Rung::Fan => "fan",
            Rung::Notch => "notch",
            Rung::FillLayers => "fill-layers",
            Rung::Queue => "queue",
            Rung::SharpSeam => "sharp-seam",
            Rung::SmallSplit => "small-split",
            Rung::Square => "square",
            Rung::Relaxed => "relaxed",
            Rung::HoleRow => "hole-row",
            Rung::Split => "split",
            Rung::Relax => "relax",
            Rung::Strip => "strip",
            Rung::Bridge => "bridge",
            Rung::RipUp => "rip-up",
            Rung::Fill => "fill",
            Rung::Rewind => "rewind",
            Rung::Refan => "refan",
            Rung::User => "user",
        }
    }
}

/// What the rungs of one step hand on to the rungs after them.
struct Climb {
    /// The guard's limits.
    limits: Limits,
    /// Reference points the queue passed over (reported by the rungs
    /// after it).
    skipped: usize,
    /// The live loops, smallest first (worked out by the first rung that
    /// needs them; a rung that does not step leaves them as they are).
    loops: Option<Vec<u32>>,
}

impl Mesher {
    /// One automatic step: the first rung of [`LADDER`] that steps.
    pub(super) fn auto_step(&mut self) -> Result<StepReport, MeshError> {
        let mut climb = Climb {
            limits: self.limits(),
            skipped: 0,
            loops: None,
        };
        for rung in LADDER {
            if let Some(mut r) = self.try_rung(rung, &mut climb)? {
                r.rung = rung;
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

    /// Tries one rung: `Ok(None)` when it does not step.
    fn try_rung(&mut self, rung: Rung, climb: &mut Climb) -> Result<Option<StepReport>, MeshError> {
        let limits = climb.limits;
        let skipped = climb.skipped;
        let with_skipped = |r: Option<StepReport>| {
            r.map(|mut r| {
                r.skipped = skipped;
                r
            })
        };
        Ok(match rung {
            Rung::FillDue | Rung::FillStalled | Rung::FillLayers | Rung::Fill => {
                self.fill_rung(rung)?
            }
            Rung::RowStart => self.row_start(limits),
            Rung::SmallLoop => self.small_loop(),
            Rung::MappedGrid => self.mapped_grid(),
            Rung::Band => self.close_band(),
            Rung::Fan => self.corner_fan(),
            Rung::Notch => self.notch(),
            Rung::Queue => {
                let (r, skipped) = self.queue_rung(limits)?;
                climb.skipped = skipped;
                r
            }
            Rung::SharpSeam => self.sharp_seam(),
            Rung::SmallSplit => {
                let loops = self.loops_smallest_first(climb);
                let mut split = None;
                for lid in loops {
                    if self.front.loops[lid as usize].len <= self.params.tuning.ladder.small_loop {
                        split = self.chord_split(lid);
                        if split.is_some() {
                            break;
                        }
                    }
                }
                split
            }
            Rung::Square => with_skipped(self.square_cut(Squares::Any, limits)),
            Rung::Relaxed => with_skipped(self.relaxed_rung()?),
            Rung::HoleRow => with_skipped(self.square_cut(Squares::SmallHoles, limits)),
            Rung::Split => {
                let loops = self.loops_smallest_first(climb);
                loops.into_iter().find_map(|lid| self.chord_split(lid))
            }
            Rung::Relax => {
                let loops = self.loops_smallest_first(climb);
                loops.first().and_then(|&lid| self.relax_rung(lid))
            }
            Rung::Strip => {
                let loops = self.loops_smallest_first(climb);
                loops.into_iter().find_map(|lid| self.close_strip(lid))
            }
            Rung::Bridge => self.bridge(None, 0.0, self.params.tuning.ladder.bridge_gap),
            Rung::RipUp => {
                let loops = self.loops_smallest_first(climb);
                loops.first().and_then(|&lid| self.rip_up_rung(lid))
            }
            Rung::Rewind | Rung::Refan | Rung::User => None,
        })
    }

    /// The live loops, smallest first, as the first rung that needs them
    /// found them.
    fn loops_smallest_first(&self, climb: &mut Climb) -> Vec<u32> {
        climb
            .loops
            .get_or_insert_with(|| {
                let mut loops: Vec<u32> = self.front.live_loops().collect();
                loops.sort_by_key(|&l| self.front.loops[l as usize].len);
                loops
            })
            .clone()
    }

    /// The fill's rungs, the one place the ladder fills from: when the
    /// step budget is spent ([`Rung::FillDue`]), when the run stalls
    /// ([`Rung::FillStalled`]), once the reference points left lie on
    /// layer [`super::MeshParams::fill_after_layers`] or deeper
    /// ([`Rung::FillLayers`]), and when no other rung steps
    /// ([`Rung::Fill`]). Nothing is filled with
    /// [`super::MeshParams::fill`] off.
    fn fill_rung(&mut self, rung: Rung) -> Result<Option<StepReport>, MeshError> {
        if !self.params.fill {
            return Ok(None);
        }
        let (due, error) = match rung {
            Rung::FillDue => (
                self.record.history.len() >= self.fill.after(),
                Some(MeshError::StepLimit {
                    limit: self.fill.after(),
                    remaining: self.front.len(),
                }),
            ),
            Rung::FillStalled => (
                self.stalled(),
                (!self.record.rewound).then(|| MeshError::Stalled {
                    steps: self.params.tuning.watch.window,
                    remaining: self.front.len(),
                }),
            ),
            Rung::FillLayers => (self.first_layers_done(), None),
            _ => (true, None),
        };
        if !due {
            return Ok(None);
        }
        if let Some(r) = self.fill_rest() {
            return Ok(Some(r));
        }
        match error {
            Some(e) if !self.record.replaying => Err(e),
            _ => Ok(None),
        }
    }

    /// True when [`super::MeshParams::fill_after_layers`] is set and the
    /// reference points left lie on that layer or deeper. Strategy B's
    /// queue is ordered by layer; strategy A's is not, so there the
    /// front's reference points are looked at.
    fn first_layers_done(&mut self) -> bool {
        let Some(k) = self.params.fill_after_layers else {
            return false;
        };
        let layer = match self.params.strategy {
            Strategy::B => self.queue_top().map(|(_, l)| l),
            Strategy::A => {
                let row = self.params.row_angle.to_radians();
                self.front
                    .live_loops()
                    .flat_map(|l| self.front.loop_slots(l))
                    .filter(|&s| self.front.angle(s, &self.mesh.nodes) <= row)
                    .map(|s| self.front.slot(s).layer)
                    .min()
            }
        };
        layer.is_some_and(|l| l >= k)
    }

    /// [`Rung::RowStart`]: a loop with no reference point starts a row
    /// with a square: a new loop, or (strategy B) a loop left behind the
    /// band or layer the queue has moved on to.
    fn row_start(&mut self, limits: Limits) -> Option<StepReport> {
        self.queue_rows_behind();
        while let Some(lid) = self.rows.loops.pop() {
            if self.front.loops[lid as usize].alive
                && self.front.loops[lid as usize].len > CLOSED_LOOP
                && !self.loop_has_reference(lid)
            {
                if let Some(r) = self.bridge(
                    Some(lid),
                    self.params.tuning.ladder.row_bridge_sj,
                    self.params.tuning.ladder.row_bridge_gap,
                ) {
                    return Some(r);
                }
                if let Some(r) = self.square_cut(Squares::Loop(lid), limits) {
                    return Some(r);
                }
            }
        }
        let hi = self.params.row_angle.to_radians();
        while let Some(s) = self.rows.edges.pop() {
            let t = self.front.next(s);
            if self.front.slot(s).alive
                && self.front.loop_len(s) > CLOSED_LOOP
                && self.front.angle(s, &self.mesh.nodes) > hi
                && self.front.angle(t, &self.mesh.nodes) > hi
            {
                if let Some(r) = self.square_on(s, limits, 0.0) {
                    return Some(r);
                }
            }
        }
        None
    }

    /// [`Rung::SmallLoop`]: small loops close first; one too skewed to
    /// close is settled and tried again, and one that neither closes nor
    /// settles is not tried again in the same state.
    fn small_loop(&mut self) -> Option<StepReport> {
        self.watch_loops();
        #[cfg(test)]
        assert!(
            self.watched
                .small
                .iter()
                .copied()
                .eq(self
                    .front
                    .live_loops()
                    .filter(|&l| self.front.loops[l as usize].len <= CLOSED_LOOP)),
            "the watched small loops are the small live loops"
        );
        // In id order; the set stays as it is until the next step.
        let mut from = 0;
        while let Some(&lid) = self.watched.small.range(from..).next() {
            from = lid + 1;
            let key = self.small_loop_key(lid);
            if self.small.stuck.get(lid as usize) == Some(&key) {
                continue;
            }
            if let Some(r) = self.close_small(lid) {
                return Some(r);
            }
            if self.settle_small(lid) {
                if let Some(r) = self.close_small(lid) {
                    return Some(r);
                }
            } else {
                if self.small.stuck.len() <= lid as usize {
                    self.small.stuck.resize(lid as usize + 1, 0);
                }
                self.small.stuck[lid as usize] = key;
            }
        }
        None
    }

    /// [`Rung::MappedGrid`]: narrow logical rectangles (and strongly graded
    /// loops of the given boundary, if asked) close by a mapped grid
    /// ([`Mesher::close_mapped`]).
    fn mapped_grid(&mut self) -> Option<StepReport> {
        self.params.mapped_rows?;
        self.watch_loops();
        #[cfg(test)]
        assert!(
            (0..self.front.loops.len() as u32)
                .filter(|&l| self.grid_unseen(l))
                .all(|l| self.watched.grid.contains(&l)),
            "every unseen loop is watched"
        );
        // In id order; only this loop takes loops out of the set.
        let mut from = 0;
        while let Some(&lid) = self.watched.grid.range(from..).next() {
            from = lid + 1;
            if self.grid_unseen(lid) {
                if let Some(r) = self.close_mapped(lid) {
                    return Some(r);
                }
            }
            if !self.grid_unseen(lid) {
                self.watched.grid.remove(&lid);
            }
        }
        None
    }

    /// Brings [`WatchedLoops`] up to date with the front's changes (a
    /// front built anew lists all its loops; ids past its last are
    /// dropped).
    fn watch_loops(&mut self) {
        let n = self.front.loops.len() as u32;
        let w = &mut self.watched;
        for set in [&mut w.small, &mut w.grid] {
            if set.last().is_some_and(|&l| l >= n) {
                let _stale = set.split_off(&n);
            }
        }
        self.front.take_changed(&mut w.changed);
        let grid_sizes = 8..=self.params.tuning.mapped.max_loop;
        for &lid in &w.changed {
            let l = &self.front.loops[lid as usize];
            if l.alive && l.len <= CLOSED_LOOP {
                w.small.insert(lid);
            } else {
                w.small.remove(&lid);
            }
            // A loop of another size is not unseen; it is listed again
            // when it changes.
            if l.alive && grid_sizes.contains(&l.len) {
                w.grid.insert(lid);
            }
        }
    }

    /// [`Rung::Queue`]: reference points in queue order; poor elements
    /// wait while a better reference point of the same kind, band and
    /// layer exists (the "next reference point" remedy): the best of the
    /// group is taken before the queue moves on to the next group. Also
    /// gives the number of reference points passed over.
    fn queue_rung(&mut self, limits: Limits) -> Result<(Option<StepReport>, usize), MeshError> {
        let mut skipped = 0;
        let mut deferred: Vec<Entry> = Vec::new();
        let mut best: Option<Chosen> = None;
        let mut chosen = None;
        let mut after = None;
        'groups: while let Some(key) = self.queue.group_after(after) {
            after = Some(key);
            while let Some(e) = self.queue.pop_from(key) {
                let i = e.slot as usize;
                if !self.front.slot(e.slot).alive || self.queue.version[i] != e.version {
                    continue;
                }
                if e.class == 0
                    && self
                        .front
                        .angle_below(e.slot, &self.mesh.nodes, &self.angles.seam)
                {
                    if let Some(mut r) = self.try_seam(e.slot) {
                        r.skipped = skipped;
                        self.requeue(deferred);
                        return Ok((Some(r), skipped));
                    }
                }
                if e.class > 0 {
                    if let Some(mut r) = self.try_transition(e.slot, limits) {
                        r.skipped = skipped;
                        self.requeue(deferred);
                        return Ok((Some(r), skipped));
                    }
                }
                let node = self.front.node(e.slot);
                let result = match self.memo.get(Eval::Queue, e.slot, node) {
                    // A remembered element is copied out only when it may be
                    // taken or kept as the best so far: most are neither, at
                    // every step they wait through.
                    Some(Some(c))
                        if c.score >= self.params.defer_score
                            || Chosen::would_keep(c.score, &best)
                            || self.at_needle(e.slot) =>
                    {
                        Some(c.clone())
                    }
                    Some(_) => None,
                    None => {
                        let r = self.evaluate(e.slot, limits, false)?;
                        if r.as_ref().is_none_or(|c| c.score < self.params.defer_score) {
                            self.memo
                                .put(Eval::Queue, e.slot, node, self.memo.read_box, r.clone());
                        }
                        r
                    }
                };
                match result {
                    Some(c) if c.score >= self.params.defer_score || self.at_needle(e.slot) => {
                        chosen = Some(c);
                        break 'groups;
                    }
                    Some(c) => c.keep_if_best(&mut best),
                    None => {}
                }
                deferred.push(e);
                skipped += 1;
            }
            // The points parked in the group wait for a change near them:
            // only their best score counts.
            self.best_parked(key, &mut best);
            if best.is_some() {
                break;
            }
        }
        if chosen.is_none() && best.is_none() {
            // Every group was walked and no point has an element.
            self.queue.drop_parked();
        }
        // A remembered element is checked again before it is taken (its
        // box was read with room to spare, but a guard is a guard).
        let best = self.confirmed(best, limits, false)?;
        if let Some(c) = chosen.or(best) {
            let mut r = self.commit_chosen(c);
            r.skipped = skipped;
            self.requeue(deferred);
            return Ok((Some(r), skipped));
        }
        Ok((None, skipped))
    }

    /// [`Rung::SharpSeam`]: a seam at any sharp corner.
    fn sharp_seam(&mut self) -> Option<StepReport> {
        let sharp: Vec<SlotId> = self
            .front
            .live_loops()
            .flat_map(|l| self.front.loop_slots(l))
            .filter(|&s| {
                self.front
                    .angle_below(s, &self.mesh.nodes, &self.angles.sharp)
            })
            .collect();
        sharp.into_iter().find_map(|s| self.try_seam(s))
    }

    /// [`Rung::Relaxed`]: the best rule-based element with
    /// [`LadderTuning::relaxed_limits`](super::tuning::LadderTuning::relaxed_limits), anywhere. The [`LadderTuning::sharpest`](super::tuning::LadderTuning::sharpest) front nodes are
    /// looked at first, the rest only when none of them gives an element
    /// (a ring with no corner left is long, and its row may start at any
    /// of them).
    fn relaxed_rung(&mut self) -> Result<Option<StepReport>, MeshError> {
        let relaxed = self.params.tuning.ladder.relaxed_limits.radians();
        let mut all: Vec<(f64, SlotId)> = self
            .front
            .live_loops()
            .flat_map(|l| self.front.loop_slots(l))
            .map(|s| (self.front.angle(s, &self.mesh.nodes), s))
            .filter(|&(a, _)| a < PI)
            .collect();
        all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut best: Option<Chosen> = None;
        for part in [
            &all[..all.len().min(self.params.tuning.ladder.sharpest)],
            &all[all.len().min(self.params.tuning.ladder.sharpest)..],
        ] {
            for &(_, s) in part {
                if let Some(c) = self.evaluate_relaxed(s, relaxed)? {
                    c.keep_if_best(&mut best);
                }
            }
            if best.is_some() {
                break;
            }
        }
        let best = self.confirmed(best, relaxed, true)?;
        Ok(best.map(|c| {
            let mut r = self.commit_chosen(c);
            r.remedy = Remedy::RuleBased;
            r
        }))
    }

    /// [`Rung::Relax`]: the smallest stuck loop `lid` straightened, at
    /// most [`LadderTuning::relax_streak`](super::tuning::LadderTuning::relax_streak) times in a row and within the run's budget
    /// ([`LadderTuning::relaxes`](super::tuning::LadderTuning::relaxes)).
    fn relax_rung(&mut self, lid: u32) -> Option<StepReport> {
        let budget = self.params.tuning.ladder.relaxes
            + self.mesh.quads.len() / self.params.tuning.ladder.relax_quads;
        if self.repairs.relaxes >= budget
            || self.repairs.relax_streak >= self.params.tuning.ladder.relax_streak
        {
            return None;
        }
        let r = self.relax_loop(lid)?;
        self.repairs.relaxes += 1;
        self.repairs.relax_streak += 1;
        Some(r)
    }

    /// [`Rung::RipUp`]: the elements around the smallest stuck loop `lid`
    /// removed, one to [`LadderTuning::rip_up_rings`](super::tuning::LadderTuning::rip_up_rings) rings in turn, within the run's
    /// budget ([`LadderTuning::rip_ups`](super::tuning::LadderTuning::rip_ups)).
    fn rip_up_rung(&mut self, lid: u32) -> Option<StepReport> {
        if self.repairs.rip_ups
            >= self.params.tuning.ladder.rip_ups
                + self.mesh.quads.len() / self.params.tuning.ladder.rip_up_quads
        {
            return None;
        }
        let r = self.rip_up(
            lid,
            1 + self.repairs.rip_ups % self.params.tuning.ladder.rip_up_rings,
        );
        self.repairs.rip_ups += 1;
        if r.removed > 0 || !r.quads.is_empty() {
            return Some(r);
        }
        // Nothing around the loop to remove and no split: rip-ups cannot
        // help any more.
        self.repairs.rip_ups = usize::MAX / 2;
        None
    }

    /// A remembered element checked again before it is taken (its box was
    /// read with room to spare, but a guard is a guard): if the guard now
    /// refuses it, the memory is dropped and its slot evaluated afresh.
    fn confirmed(
        &mut self,
        best: Option<Chosen>,
        limits: Limits,
        rules: bool,
    ) -> Result<Option<Chosen>, MeshError> {
        Ok(match best {
            Some(c) if self.check(c.cand, limits).is_none() => {
                self.forget(None);
                match c.cand.slot() {
                    s if self.front.slot(s).alive => self.evaluate(s, limits, rules)?,
                    _ => None,
                }
            }
            b => b,
        })
    }

    /// The relaxed rung's evaluation of slot `s` (the rule model under
    /// `limits`), remembered.
    fn evaluate_relaxed(&mut self, s: SlotId, limits: Limits) -> Result<Option<Chosen>, MeshError> {
        let node = self.front.node(s);
        if let Some(r) = self.memo.get(Eval::Relaxed, s, node) {
            return Ok(r.clone());
        }
        let r = self.evaluate(s, limits, true)?;
        self.memo
            .put(Eval::Relaxed, s, node, self.memo.read_box, r.clone());
        Ok(r)
    }

    /// Strategy B: when the queue moves on to a coarser band or deeper
    /// layer, every loop left behind without a reference point (the front
    /// around a hole after a full ring, all its angles reflex) is queued
    /// for a row start, and so is every stretch of the given boundary no
    /// row has reached, so that every part of the front keeps up.
    fn queue_rows_behind(&mut self) {
        if self.params.strategy != super::params::Strategy::B {
            return;
        }
        let Some(top) = self.queue_top() else {
            return;
        };
        if top <= self.rows.key {
            return;
        }
        self.rows.key = top;
        let hi = self.params.row_angle.to_radians();
        let loops: Vec<u32> = self.front.live_loops().collect();
        for lid in loops {
            let slots = self.front.loop_slots(lid);
            let n = slots.len();
            if n <= CLOSED_LOOP || !slots.iter().any(|&s| self.slot_key(s) < top) {
                continue;
            }
            let open: Vec<bool> = slots
                .iter()
                .map(|&s| self.front.angle(s, &self.mesh.nodes) > hi)
                .collect();
            if open.iter().all(|&o| o) {
                self.rows.loops.push(lid);
                continue;
            }
            // Stretches of the given boundary no row has reached yet (the
            // far side of a hole): a row start on each one's shortest edge.
            let nb = self.boundary_nodes;
            let untouched = |k: usize| open[k] && (self.front.node(slots[k]) as usize) < nb;
            let first = (0..n).find(|&k| !untouched(k)).unwrap_or(0);
            let mut run: Vec<SlotId> = Vec::new();
            for k in 1..=n {
                let i = (first + k) % n;
                if untouched(i) && k < n {
                    run.push(slots[i]);
                    continue;
                }
                if run.len() >= self.params.tuning.ladder.row_run {
                    let best = run
                        .windows(2)
                        .map(|w| (self.world(w[0]).distance(self.world(w[1])), w[0]))
                        .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                    if let Some((_, s)) = best {
                        self.rows.edges.push(s);
                    }
                }
                run.clear();
            }
        }
    }

    /// True when some slot of the loop is a reference point or sharp corner.
    pub(super) fn loop_has_reference(&self, lid: u32) -> bool {
        let hi = self.params.reference_angle[1].to_radians();
        self.front
            .loop_slots(lid)
            .into_iter()
            .any(|s| self.front.angle(s, &self.mesh.nodes) <= hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extract::{MeshParams, StepOutcome};
    use std::sync::Arc;

    /// After every step of runs over many loops (a plate of nine holes and
    /// real-like domains: bands, zig-zags, tube sheets, graded sides), the
    /// loops the front's changes kept are the ones a scan of every loop
    /// finds: the small live loops, and every loop not yet looked at for
    /// a mapped grid among the watched ones.
    #[test]
    fn the_watched_loops_are_the_ones_a_scan_finds() {
        let model: Arc<dyn crate::model::Model> =
            Arc::new(crate::model::default_model().expect("the shipped model"));
        let mut boundaries = vec![crate::domains::perforated_plate(3)];
        boundaries.extend(
            crate::domains::real_like_domains(8, 7)
                .into_iter()
                .map(|d| d.boundary),
        );
        let mut checked = 0;
        for b in boundaries {
            let mut m = Mesher::new(b, model.clone(), MeshParams::DEFAULT);
            while let StepOutcome::Stepped(_) = m.step().expect("a step") {
                m.watch_loops();
                let small: Vec<u32> = m
                    .front
                    .live_loops()
                    .filter(|&l| m.front.loops[l as usize].len <= CLOSED_LOOP)
                    .collect();
                assert_eq!(m.watched.small.iter().copied().collect::<Vec<u32>>(), small);
                for l in 0..m.front.loops.len() as u32 {
                    if m.grid_unseen(l) {
                        assert!(m.watched.grid.contains(&l), "loop {l} unseen, not watched");
                    }
                }
                checked += 1;
            }
        }
        assert!(checked > 1000, "{checked} steps checked");
    }
}

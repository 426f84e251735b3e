//! The region fill as a step (method §2.5): when the step budget is
//! spent, the run stalls, the first layers are done or nothing else
//! reduces the front, the region left is filled
//! ([`super::fill::fill_region`]); when extraction has led the front into
//! a state no fill can take, the run goes back to an earlier step and
//! fills there. A run that placed corner fans is first made again with
//! balanced ones, and taken if it needs no fill ([`Mesher::refan`]).

use super::fill;
use super::ladder::Rung;
use super::report::{Action, StepKind, StepReport};
use super::session::Mesher;
use super::tuning::FarCorner;
use crate::geom::Point;
use std::ops::ControlFlow;

/// The fill's budget: the steps after which the region left is filled,
/// and the step before which no fill is tried again (set after a fill
/// fails).
#[derive(Clone, Debug, Default)]
pub(super) struct FillBudget {
    after: usize,
    retry_at: usize,
}

impl FillBudget {
    /// A budget of `after` steps.
    pub(super) fn new(after: usize) -> FillBudget {
        FillBudget { after, retry_at: 0 }
    }

    /// The steps after which the region left is filled.
    pub(super) fn after(&self) -> usize {
        self.after
    }
}

impl Mesher {
    /// Before the region fill: the run, if it placed corner fans with
    /// [`FarCorner::Squarest`], made again from the start with
    /// [`FarCorner::Balanced`] ([`FillTuning::refan`](super::tuning::FillTuning::refan)). That run
    /// replaces this one if it finishes by extraction alone, without a
    /// fill; the step's report ([`StepKind::Refan`]) has all of that
    /// run's quads and none of this one's. The history
    /// is then that run's, whose parameters carry the balanced fans, so
    /// undo replays it. Tried once per run, never while replaying, and not
    /// on a run the user steered (a correction, or a model set during the
    /// run): the steps before the first fan do not depend on the far
    /// corners, but the user's would not be made again.
    pub(super) fn refan(&mut self) -> Option<StepReport> {
        let t = &self.params.tuning;
        if !t.fill.refan
            || t.fan.far_corner != FarCorner::Squarest
            || self.record.refan_tried
            || self.record.replaying
            || self.record.rewound
            || self.record.stats.count(StepKind::Fan) == 0
            || !self.record.model_changes.is_empty()
            || self.record.history.iter().any(|a| *a != Action::Auto)
        {
            return None;
        }
        self.record.refan_tried = true;
        let mut params = self.params.clone();
        params.tuning.fan.far_corner = FarCorner::Balanced;
        let mut fresh = Mesher::with_size(
            self.boundary.clone(),
            self.record.initial_model.clone(),
            params,
            self.size.clone(),
        );
        let done = fresh
            .run_with(|r, _| match r.kind {
                StepKind::Fill => ControlFlow::Break(()),
                _ => ControlFlow::Continue(()),
            })
            .ok()?;
        if !done || fresh.record.stats.count(StepKind::Fill) > 0 {
            return None;
        }
        let last = fresh.record.history.len().saturating_sub(1);
        let mut r = StepReport::new(last, StepKind::Refan);
        r.rung = Rung::Refan;
        r.quads = fresh.mesh.quads.clone();
        r.new_nodes = (fresh.mesh.n_boundary() as u32..fresh.mesh.nodes.len() as u32).collect();
        r.removed = self.mesh.quads.len();
        fresh.record.refan_tried = true;
        fresh.record.stats.refanned = true;
        *self = fresh;
        Some(r)
    }

    /// When extraction has led the front into a state no fill can take, the
    /// run goes back to an earlier step (3/4, 1/2, 1/4, 1/8, 1/16 and 1/32
    /// of the way, then the start) and fills the region left there: a fill
    /// that fails on a front extraction has tangled may still take the
    /// front of the first rows. The first mesh whose worst quad has a scaled
    /// Jacobian of at least [`FillTuning::rewind_good`](super::tuning::FillTuning::rewind_good) is taken; if none has, the best
    /// of those made. The history then holds the steps kept and the fill,
    /// so undo goes back to the step rewound to.
    /// Each step is tried once and only before the current one: a replay is
    /// deterministic, so a step tried again (a run of fewer than four steps)
    /// or the current step (a run stuck at its first step, whose fill has
    /// just failed on the same front) would fail the same way, at the cost
    /// of a whole fill (seconds on a front of thousands of nodes).
    pub(super) fn rewind_and_fill(&mut self) -> Option<StepReport> {
        if self.record.rewound {
            return None;
        }
        self.record.rewound = true;
        let n = self.record.history.len();
        let mut tried = n;
        let mut best: Option<(f64, Mesher, StepReport)> = None;
        for (a, b) in self.params.tuning.fill.rewind_to {
            let k = a * n / b;
            if k >= tried {
                continue;
            }
            tried = k;
            let mut fresh = self.replayed(&self.record.history[..k]);
            let kept = fresh.mesh.quads.len();
            // Only a fill that closes the whole front ends the run.
            let filled = fresh.commit_fill().filter(|_| fresh.front.is_empty());
            if let Some(mut r) = filled {
                r.removed = self.mesh.quads.len().saturating_sub(kept);
                let worst = fresh.mesh.worst_scaled_jacobian();
                if best.as_ref().is_none_or(|b| worst > b.0) {
                    best = Some((worst, fresh, r));
                }
                if worst >= self.params.tuning.fill.rewind_good {
                    break;
                }
            }
        }
        let (_, mut fresh, r) = best?;
        fresh.record.rewound = true;
        *self = fresh;
        Some(r)
    }

    /// A fill taken as a step of its own (after rewinding, or replayed).
    pub(super) fn commit_fill(&mut self) -> Option<StepReport> {
        self.fill.retry_at = 0;
        let mut r = self.fill_rest()?;
        r.rung = super::ladder::Rung::Rewind;
        self.record.history.push(Action::Fill);
        self.record.undone.clear();
        self.record.stats.record(&r, self.mesh.quads.len());
        Some(r)
    }

    /// Fills the whole region left with [`fill::fill_region`] and empties
    /// the front; where that fails, fills the regions left one by one,
    /// removing up to [`FillTuning::rings`](super::tuning::FillTuning::rings) rings of elements around those it
    /// cannot take. `None` when nothing changed (tried again after a
    /// quarter as many steps as made so far).
    pub(super) fn fill_rest(&mut self) -> Option<StepReport> {
        let step = self.record.history.len();
        if step < self.fill.retry_at {
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
        for rings in 0..=self.params.tuning.fill.rings {
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
            let fill = &self.params.tuning.fill;
            self.fill.retry_at = step + (step / fill.retry_share).max(fill.retry_min);
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
}

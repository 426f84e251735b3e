//! Candidate elements at a reference point (method §2.4–2.6): the model's
//! element first, then the remedies (a snapped Pn, the other types, a
//! corrected Pn), each checked by the [`guard`](super::guard) and scored;
//! and committing the chosen one to the mesh and the front.

use super::guard::{self, Corner, Limits};
use super::report::MeshError;
use super::report::{Remedy, StepKind, StepReport, RESCALED_BEYOND};
use super::session::Mesher;
use crate::front::{Front, SlotId};
use crate::geom::{ccw_angle, Aabb, Point};
use crate::model::{rules, ElementType, Model, Prediction};
use crate::normalize::{Frame, LeadingPoints};
use std::f64::consts::PI;

/// A candidate element at a reference slot.
/// Pure-model mode's state: the model's predictions the guard rejected
/// since the last step, and the leading points (node ids) of every
/// rejected prediction, so a prediction met again is counted once.
#[derive(Clone, Debug, Default)]
pub(super) struct Rejections {
    pub(super) count: usize,
    pub(super) inputs: std::collections::BTreeSet<Vec<u32>>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Cand {
    New { s: SlotId, pn: Point },
    Snap { s: SlotId, q: SlotId },
    Right { s: SlotId },
    Left { s: SlotId },
}

impl Cand {
    /// The reference slot the candidate is built at.
    pub(super) fn slot(self) -> SlotId {
        match self {
            Cand::New { s, .. } | Cand::Snap { s, .. } | Cand::Right { s } | Cand::Left { s } => s,
        }
    }

    /// The corners of the quad the candidate would commit, in the order
    /// [`Mesher::commit`] writes them.
    pub(super) fn corners(self, f: &Front, nodes: &[Point]) -> [Point; 4] {
        let at = |x: SlotId| nodes[f.node(x) as usize];
        let s = self.slot();
        let (l, r) = (f.prev(s), f.next(s));
        match self {
            Cand::New { pn, .. } => [at(s), at(r), pn, at(l)],
            Cand::Snap { q, .. } => [at(s), at(r), at(q), at(l)],
            Cand::Right { .. } => [at(s), at(r), at(f.next(r)), at(l)],
            Cand::Left { .. } => [at(s), at(r), at(f.prev(l)), at(l)],
        }
    }
}

/// One candidate element as [`Mesher::explain`] lists it.
#[derive(Clone, Debug, PartialEq)]
pub struct CandidateReport {
    /// [`Remedy::None`] for the model's own element.
    pub remedy: Remedy,
    pub element_type: ElementType,
    /// The new node of a type-0 element.
    pub pn: Option<Point>,
    /// The front node a snapped element closes onto.
    pub snap_to: Option<u32>,
    /// The guard's score, `None` when it refuses the element.
    pub score: Option<f64>,
}

/// A row being continued at a reference point: the front node it goes on
/// from (P0's neighbour that is not the last element's top), the node
/// beyond that, and whether that is to P0's right.
#[derive(Clone, Copy, Debug)]
pub(super) struct Row {
    pub(super) base: SlotId,
    pub(super) beyond: SlotId,
    pub(super) right: bool,
}

/// The element chosen at a reference point.
#[derive(Clone, Debug)]
pub(super) struct Chosen {
    pub(super) cand: Cand,
    pub(super) remedy: Remedy,
    pub(super) score: f64,
    pub(super) prediction: Prediction,
    pub(super) frame: Frame,
    pub(super) leading: Vec<u32>,
}

/// The model's element is taken at once when it scores this much.
const EXCELLENT: f64 = 0.85;
/// The model's element is taken over a better-scoring remedy that beats
/// it by less than this.
const MODEL_MARGIN: f64 = 0.15;
/// A row's height moves towards the size field by at most this factor per
/// element.
const SIZE_STEP: f64 = 1.1;
/// Front nodes within this many local sizes of Pn are snap candidates.
const SNAP_REACH: f64 = 0.8;
/// The front ahead is looked for within this many local sizes.
const GAP_REACH: f64 = 2.8;
/// How far past a right-angled kite the element at a sharp corner may open
/// its opposite corner.
const TIP_SLACK: f64 = 5.0 * PI / 180.0;
/// The kite at a sharp corner reaches this fraction of the way to right
/// angles beside the tip.
const TIP_REACH: f64 = 0.95;
/// The kite that closes a needle (a corner whose sides are more than
/// [`NEEDLE_RATIO`](super::guard::NEEDLE_RATIO) times the distance
/// between their far ends) puts its new node this many such distances past
/// the middle of that span: shallow, so the front it leaves stays smooth
/// (about 157° at the span's ends and 203° at the new node).
const NEEDLE_DEPTH: f64 = 0.1;

/// A front node whose angle is above this is a row's side (below, it is a
/// corner the row ends at).
const ROW_SIDE: f64 = 150.0 * std::f64::consts::PI / 180.0;
/// ... and above this a reflex corner the row turns around.
const ROW_CORNER: f64 = 225.0 * std::f64::consts::PI / 180.0;
/// An element's corner at the node a row goes on from may differ this much
/// from its share of the node's angle before it costs.
const ROW_SLACK: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// ... and the cost grows to its floor over this much more.
const ROW_FALLOFF: f64 = 60.0 * std::f64::consts::PI / 180.0;

/// Scores closer than this are a tie, which the first candidate wins: a
/// model whose outputs differ in the last digits (a refit, another
/// machine's rounding) then makes the same choices.
const SCORE_TIE: f64 = 1e-6;

/// True when score `a` is better than `b` by more than a tie.
pub(super) fn beats(a: f64, b: f64) -> bool {
    a > b + SCORE_TIE
}

impl Chosen {
    /// Whether an element scoring `score` would be kept in `best`
    /// ([`Chosen::keep_if_best`]).
    pub(super) fn would_keep(score: f64, best: &Option<Chosen>) -> bool {
        best.as_ref().is_none_or(|b| beats(score, b.score))
    }

    /// Keeps `self` in `best` if it scores higher (the first wins ties).
    pub(super) fn keep_if_best(self, best: &mut Option<Chosen>) {
        if Chosen::would_keep(self.score, best) {
            *best = Some(self);
        }
    }
}

impl Mesher {
    pub(super) fn limits(&self) -> Limits {
        Limits {
            min_corner: self.params.min_corner.to_radians(),
            max_corner: self.params.max_corner.to_radians(),
            min_front: self.params.min_front_angle.to_radians(),
        }
    }

    pub(super) fn leading_n(&self) -> usize {
        self.model
            .leading_points()
            .unwrap_or(self.params.leading_points)
            .max(2)
    }

    pub(super) fn world(&self, s: SlotId) -> Point {
        self.mesh.nodes[self.front.node(s) as usize]
    }

    /// True when the front corner at `s` is a needle
    /// ([`guard::is_needle`]): its kite is taken however it scores, as no
    /// better element can take that corner.
    pub(super) fn at_needle(&self, s: SlotId) -> bool {
        self.needle_span(s).is_some()
    }

    /// At a needle, the span between its sides' far ends: the width of
    /// the element that takes it.
    fn needle_span(&self, s: SlotId) -> Option<f64> {
        let (pl, pr) = (
            self.world(self.front.prev(s)),
            self.world(self.front.next(s)),
        );
        guard::is_needle(self.world(s), pl, pr).then(|| pl.distance(pr))
    }

    /// At a needle ([`Mesher::at_needle`]), the new node of the kite that
    /// closes it across its narrow end: no kite meets the side ratio there.
    pub(super) fn needle_kite(&self, s: SlotId) -> Option<Point> {
        let (p0, pl, pr) = (
            self.world(s),
            self.world(self.front.prev(s)),
            self.world(self.front.next(s)),
        );
        if !guard::is_needle(p0, pl, pr) {
            return None;
        }
        let mid = 0.5 * (pl + pr);
        let dir = (mid - p0).normalize_or_zero();
        Some(mid + dir * (NEEDLE_DEPTH * pl.distance(pr)))
    }

    /// Leading slots `l_N..l1, P0, r1..r_N` of reference slot `s`.
    pub(super) fn leading_slots(&self, s: SlotId, n: usize) -> Vec<SlotId> {
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

    pub(super) fn normalised(&self, slots: &[SlotId]) -> (Frame, LeadingPoints) {
        let n = slots.len() / 2;
        let p0 = self.world(slots[n]);
        let frame = Frame::new(p0, self.world(slots[n + 1]));
        let left: Vec<Point> = (1..=n).map(|k| self.world(slots[n - k])).collect();
        let right: Vec<Point> = (1..=n).map(|k| self.world(slots[n + k])).collect();
        (frame, LeadingPoints::normalise(&frame, &left, &right))
    }

    /// The guard on one candidate: its score when it passes.
    pub(super) fn check(&mut self, c: Cand, limits: Limits) -> Option<f64> {
        let p0 = c.slot();
        // The element at a sharp corner of the front has that corner's
        // angle; the corner opposite may open as far as a kite with right
        // angles beside the tip needs.
        let tip = self.front.angle(p0, &self.mesh.nodes);
        let limits = if tip < self.params.reference_angle[0].to_radians() {
            Limits {
                max_corner: limits.max_corner.max(PI - tip + TIP_SLACK),
                ..limits
            }
        } else {
            limits
        };
        let at = match c {
            Cand::New { s, pn } => 0.5 * (self.world(s) + pn),
            Cand::Snap { s, .. } | Cand::Right { s } | Cand::Left { s } => self.world(s),
        };
        // A needle's element is as wide as its narrow end, however long.
        let size = self.needle_span(p0).unwrap_or_else(|| self.size.at(at));
        let f = &self.front;
        let n = self.front.loop_len(p0);
        let (corners, consumed): ([Corner; 4], Vec<SlotId>) = match c {
            Cand::New { s, pn } => {
                let (l, r) = (f.prev(s), f.next(s));
                // On a four-node loop the element leaves another four-node
                // loop (P0 moved to Pn), which must run the way it ran.
                if n == 4 {
                    let p = |t: SlotId| self.mesh.nodes[f.node(t) as usize];
                    let before = crate::geom::polygon_area([p(l), p(s), p(r), p(f.next(r))]);
                    let after = crate::geom::polygon_area([p(l), pn, p(r), p(f.next(r))]);
                    if before * after <= 0.0 {
                        return None;
                    }
                }
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
            size,
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
        let mut score = passed.score;
        if let Cand::New { s, pn } = c {
            // Where a row goes on along the front, the element's corner
            // at the next node should take its share of that node's angle,
            // as paving's rows do: half of a side node's (the bisector),
            // a third of a reflex corner's. Much more or less opens the
            // row into a fan or closes it into a wedge.
            if let Some(row) = self.row_at(s) {
                let theta = self.front.angle(row.base, &self.mesh.nodes);
                if theta > ROW_SIDE {
                    let share = if theta < ROW_CORNER {
                        theta / 2.0
                    } else {
                        theta / 3.0
                    };
                    let corner = theta - self.row_angle_left(&row, pn);
                    let off = (corner - share).abs() - ROW_SLACK;
                    score = score.min((1.0 - off.max(0.0) / ROW_FALLOFF).clamp(0.3, 1.0));
                }
            }
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
                // The part between s and q (the shorter way round) with the
                // odd loops it takes in must be even.
                let (from, to) = if f.walk(s, d as isize) == q {
                    (s, q)
                } else {
                    (q, s)
                };
                let odd = self.part_parity(f.slot(s).loop_id, from, to);
                if (d + odd) % 2 == 1 || d < 4 || n - d < 4 {
                    return None;
                }
            }
        }
        Some(score)
    }

    /// Shorter distance along the loop between two slots of one loop.
    pub(super) fn loop_distance(&self, a: SlotId, b: SlotId) -> usize {
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

    /// Front nodes within `radius` of `p`, nearest first (the reference
    /// point's own neighbours left out), as slots: at most `max`.
    pub(super) fn snap_targets(
        &mut self,
        s: SlotId,
        p: Point,
        radius: f64,
        max: usize,
    ) -> Vec<SlotId> {
        let r = Point::splat(radius);
        self.front.edges_near(p - r, p + r, &mut self.scratch.near);
        let own = [s, self.front.prev(s), self.front.next(s)];
        let mut found: Vec<(f64, SlotId)> = self
            .scratch
            .near
            .iter()
            .filter(|e| !own.contains(e))
            .map(|&e| (self.world(e).distance(p), e))
            .filter(|&(d, _)| d <= radius)
            .collect();
        found.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        found.truncate(max);
        found.into_iter().map(|(_, e)| e).collect()
    }

    /// Pn with the row's height drawn towards the size field (the model's
    /// output is normalised by the front edge at P0, so it carries the
    /// front's spacing, not the size wanted here). Where P0 continues a row
    /// (one of its front neighbours was made by extraction after P0), the
    /// new side from the other neighbour to Pn is the row's next height:
    /// its length moves towards the local size by at most [`SIZE_STEP`].
    /// At a corner of the front both sides are the front's own edges and
    /// Pn is left as predicted.
    pub(super) fn sized_pn(&self, s: SlotId, pn: Point) -> Point {
        let Some(row) = self.row_at(s) else {
            return pn;
        };
        let base = self.world(row.base);
        let v = pn - base;
        let len = v.length();
        if len <= 0.0 || !len.is_finite() {
            return pn;
        }
        let want = self.size.at(base);
        let k = (want / len).clamp(1.0 / SIZE_STEP, SIZE_STEP);
        base + v * k
    }

    /// The row that reference slot `s` continues, if any: one front
    /// neighbour of P0 was made by extraction after P0 (it is the top of
    /// the row's last element), and the row goes on towards the other.
    pub(super) fn row_at(&self, s: SlotId) -> Option<Row> {
        let f = &self.front;
        let (l, r) = (f.prev(s), f.next(s));
        let layer = f.slot(s).layer;
        match (f.slot(l).layer > layer, f.slot(r).layer > layer) {
            (true, false) => Some(Row {
                base: r,
                beyond: f.next(r),
                right: true,
            }),
            (false, true) => Some(Row {
                base: l,
                beyond: f.prev(l),
                right: false,
            }),
            _ => None,
        }
    }

    /// The front angle a type-0 element with new node `pn` leaves at the
    /// node the row goes on from.
    pub(super) fn row_angle_left(&self, row: &Row, pn: Point) -> f64 {
        let (b, y) = (self.world(row.base), self.world(row.beyond));
        if row.right {
            ccw_angle(b, y, pn)
        } else {
            ccw_angle(b, pn, y)
        }
    }

    /// Paving's new node for a row: from the node the row goes on from,
    /// along the bisector of its front angle, far enough that the row is
    /// `height` high there.
    pub(super) fn paving_pn(&self, s: SlotId, row: &Row, height: f64) -> Point {
        let (b, y, p0) = (self.world(row.base), self.world(row.beyond), self.world(s));
        let (from, to) = if row.right { (y, p0) } else { (p0, y) };
        let phi = ccw_angle(b, from, to);
        let u = (from - b).normalize_or_zero();
        let (sn, cs) = (0.5 * phi).sin_cos();
        let dir = Point::new(u.x * cs - u.y * sn, u.x * sn + u.y * cs);
        b + dir * (height / sn.max(0.5))
    }

    /// Where fronts are about to meet: the distance from `from` along
    /// `dir` (a unit vector) to the first front edge not at the nodes
    /// `skip`, within `reach`.
    pub(super) fn gap_along(
        &mut self,
        from: Point,
        dir: Point,
        reach: f64,
        skip: &[u32],
    ) -> Option<f64> {
        let to = from + dir * reach;
        self.front
            .edges_near(from.min(to), from.max(to), &mut self.scratch.near);
        let mut best: Option<f64> = None;
        for &e in &self.scratch.near {
            let (c, d) = (self.front.node(e), self.front.node(self.front.next(e)));
            if skip.contains(&c) || skip.contains(&d) {
                continue;
            }
            let (pc, pd) = (self.mesh.nodes[c as usize], self.mesh.nodes[d as usize]);
            if let Some(t) = crate::geom::ray_segment(from, dir, pc, pd) {
                if t <= reach && best.is_none_or(|b| t < b) {
                    best = Some(t);
                }
            }
        }
        best
    }

    /// Candidate list at reference slot `s`, model first, then remedies:
    /// the model's element (Pn sized, [`Mesher::sized_pn`]); where the
    /// model's Pn comes near other front nodes, the element closed onto
    /// each of them (snapped); the other types; where the front ahead is
    /// too close for a full element and too far to reach, Pn half-way
    /// across; the rule-based Pn.
    /// The model's own element at reference slot `s` (its Pn sized to the
    /// row it continues), and that Pn in world coordinates.
    fn model_candidate(&self, s: SlotId, pred: Prediction, frame: &Frame) -> (Cand, Point) {
        let pn_world = self.sized_pn(s, frame.to_world(pred.pn));
        let cand = match pred.element_type {
            ElementType::New => Cand::New { s, pn: pn_world },
            ElementType::Right => Cand::Right { s },
            ElementType::Left => Cand::Left { s },
        };
        (cand, pn_world)
    }

    pub(super) fn candidates(
        &mut self,
        s: SlotId,
        pred: Prediction,
        frame: &Frame,
    ) -> Vec<(Cand, Remedy)> {
        let (model_cand, pn_world) = self.model_candidate(s, pred, frame);
        if self.params.pure_model {
            return vec![(model_cand, Remedy::None)];
        }
        let mut out = Vec::with_capacity(12);
        out.push((model_cand, Remedy::None));
        let (l, r) = (self.front.prev(s), self.front.next(s));
        let (p0, pl, pr) = (self.world(s), self.world(l), self.world(r));
        let rule_pn = {
            let l1 = frame.to_local(pl);
            self.sized_pn(s, frame.to_world(rules::parallelogram(l1, Point::X)))
        };
        let pn = if pred.element_type == ElementType::New {
            pn_world
        } else {
            rule_pn
        };
        let size = self.size.at(pn);
        for q in self.snap_targets(s, pn, SNAP_REACH * size, 4) {
            out.push((Cand::Snap { s, q }, Remedy::Snapped));
        }
        for t in [Cand::Right { s }, Cand::Left { s }] {
            if t != model_cand {
                out.push((t, Remedy::OtherType));
            }
        }
        // The front ahead: measured from P0's neighbours along the new
        // sides; a gap of one to three sizes is split evenly.
        let skip = [self.front.node(s), self.front.node(l), self.front.node(r)];
        let mut gap: Option<f64> = None;
        let mut along = 0.0;
        for base in [pr, pl] {
            let v = pn - base;
            let len = v.length();
            if len <= 0.0 {
                continue;
            }
            if let Some(g) = self.gap_along(base, v / len, GAP_REACH * size, &skip) {
                if gap.is_none_or(|b| g < b) {
                    gap = Some(g);
                    along = len;
                }
            }
        }
        if let Some(g) = gap {
            if g > 0.8 * size && g < GAP_REACH * size {
                let k = 0.5 * g / along;
                out.push((
                    Cand::New {
                        s,
                        pn: p0 + (pn - p0) * k,
                    },
                    Remedy::CorrectedPn,
                ));
            }
        }
        if let Some(row) = self.row_at(s) {
            let base = self.world(row.base);
            let height = self.size.at(base);
            let prev = if row.right {
                p0.distance(pl)
            } else {
                p0.distance(pr)
            };
            let h = height.clamp(prev / SIZE_STEP, prev * SIZE_STEP);
            out.push((
                Cand::New {
                    s,
                    pn: self.paving_pn(s, &row, h),
                },
                Remedy::CorrectedPn,
            ));
        }
        // At a sharp corner, the kite with near right angles beside it.
        let theta = self.front.angle(s, &self.mesh.nodes);
        if theta < self.params.reference_angle[0].to_radians() {
            let a = 0.5 * (p0.distance(pl) + p0.distance(pr));
            let dir =
                ((pl - p0).normalize_or_zero() + (pr - p0).normalize_or_zero()).normalize_or_zero();
            let d = TIP_REACH * a / (0.5 * theta).cos();
            out.push((
                Cand::New {
                    s,
                    pn: p0 + dir * d,
                },
                Remedy::CorrectedPn,
            ));
        }
        if let Some(pn) = self.needle_kite(s) {
            out.push((Cand::New { s, pn }, Remedy::CorrectedPn));
        }
        out.push((Cand::New { s, pn: rule_pn }, Remedy::CorrectedPn));
        out.push((
            Cand::New {
                s,
                pn: p0 + (rule_pn - p0) * 0.7,
            },
            Remedy::CorrectedPn,
        ));
        out
    }

    /// The model's element at reference slot `s`, or the best remedy. With
    /// `rules`, the rule model stands in for the model. The model's element
    /// is taken when it scores at least `accept_score` and is not beaten by
    /// more than [`MODEL_MARGIN`]; otherwise the best candidate.
    pub(super) fn evaluate(
        &mut self,
        s: SlotId,
        limits: Limits,
        rules: bool,
    ) -> Result<Option<Chosen>, MeshError> {
        let (slots, frame, pred) = self.predict_at(s, rules);
        let leading: Vec<u32> = slots.iter().map(|&t| self.front.node(t)).collect();
        // The model's element comes first among the candidates: when it is
        // excellent the others need not be built. The box read
        // (`evaluated`) is worked out where the evaluation ends: of the
        // model's element alone when it returns early, else of all the
        // candidates.
        if !self.params.pure_model || rules {
            let (c, _) = self.model_candidate(s, pred, &frame);
            if let Some(score) = self.check(c, limits).filter(|&v| v >= EXCELLENT) {
                self.memo.read_box = self.extent(s, &[c]);
                return Ok(Some(Chosen {
                    cand: c,
                    remedy: Remedy::None,
                    score,
                    prediction: pred,
                    frame,
                    leading,
                }));
            }
            // A needle takes the kite it forces, or nothing.
            if let Some(pn) = self.needle_kite(s) {
                let cand = Cand::New { s, pn };
                self.memo.read_box = self.extent(s, &[c]);
                return Ok(self.check(cand, limits).map(|score| Chosen {
                    cand,
                    remedy: Remedy::CorrectedPn,
                    score,
                    prediction: pred,
                    frame,
                    leading,
                }));
            }
        }
        let mut best: Option<Chosen> = None;
        let mut model: Option<Chosen> = None;
        let cands = self.candidates(s, pred, &frame);
        let all: Vec<Cand> = cands.iter().map(|&(c, _)| c).collect();
        self.memo.read_box = self.extent(s, &all);
        for (c, remedy) in cands {
            let Some(score) = self.check(c, limits) else {
                if self.params.pure_model && !rules {
                    if self.rejections.inputs.insert(leading.clone()) {
                        self.rejections.count += 1;
                    }
                    return Ok(None);
                }
                continue;
            };
            let chosen = Chosen {
                cand: c,
                remedy,
                score,
                prediction: pred,
                frame,
                leading: leading.clone(),
            };
            if remedy == Remedy::None && model.is_none() {
                if score >= EXCELLENT {
                    return Ok(Some(chosen));
                }
                model = Some(chosen.clone());
            }
            chosen.keep_if_best(&mut best);
        }
        if let (Some(m), Some(b)) = (&model, &best) {
            if m.score >= self.params.accept_score && m.score + MODEL_MARGIN >= b.score {
                return Ok(model);
            }
        }
        Ok(best)
    }

    /// A box holding all of the front that evaluating reference slot `s`
    /// with candidates `cands` reads: the front nodes around it, the
    /// candidates' points, and the reach of the guard, the snaps and the
    /// gap search around them (the largest local size there, with room).
    fn extent(&self, s: SlotId, cands: &[Cand]) -> (Point, Point) {
        let f = &self.front;
        let k = self.leading_n().max(6) / 2 + 2;
        let mut pts = vec![self.world(s)];
        let (mut a, mut b) = (s, s);
        for _ in 0..k {
            a = f.prev(a);
            b = f.next(b);
            pts.push(self.world(a));
            pts.push(self.world(b));
        }
        for &c in cands {
            match c {
                Cand::New { pn, .. } => pts.push(pn),
                Cand::Snap { q, .. } => {
                    pts.extend([q, f.prev(q), f.next(q)].map(|t| self.world(t)));
                }
                Cand::Right { .. } | Cand::Left { .. } => {}
            }
        }
        // (`pts` holds P0 at least.)
        let Aabb { min: lo, max: hi } = Aabb::of(pts.iter().copied()).unwrap_or(Aabb {
            min: pts[0],
            max: pts[0],
        });
        // The leading points lie between P0 and the box's corners; the
        // candidates' points reach furthest.
        let size = [lo, hi, Point::new(lo.x, hi.y), Point::new(hi.x, lo.y)]
            .into_iter()
            .chain(std::iter::once(pts[0]))
            .chain(pts[2 * k + 1..].iter().copied())
            .map(|p| self.size.at(p))
            .fold(0.0, f64::max);
        let reach = Point::splat(1.5 * (GAP_REACH + 1.0) * size);
        (lo - reach, hi + reach)
    }

    /// The leading slots, frame and prediction at reference slot `s` (with
    /// `rules`, of the rule model on two leading points a side). A
    /// prediction that is not finite becomes the square corner's Pn.
    fn predict_at(&self, s: SlotId, rules: bool) -> (Vec<SlotId>, Frame, Prediction) {
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
        (slots, frame, pred)
    }

    /// Every candidate element at front node `node` as the next step would
    /// see it, in the order they are tried: what it is, its new node or the
    /// node it closes onto, and its score, or `None` where the guard refuses
    /// it. `None` when the node is not on the front. The state is not
    /// changed.
    pub fn explain(&mut self, node: u32) -> Option<Vec<CandidateReport>> {
        let s = self
            .front
            .live_loops()
            .flat_map(|l| self.front.loop_slots(l))
            .find(|&s| self.front.node(s) == node)?;
        let limits = self.limits();
        let (_, frame, pred) = self.predict_at(s, false);
        let cands = self.candidates(s, pred, &frame);
        Some(
            cands
                .into_iter()
                .map(|(c, remedy)| {
                    let score = self.check(c, limits);
                    let (element_type, pn, snap_to) = match c {
                        Cand::New { pn, .. } => (ElementType::New, Some(pn), None),
                        Cand::Snap { q, .. } => (ElementType::New, None, Some(self.front.node(q))),
                        Cand::Right { .. } => (ElementType::Right, None, None),
                        Cand::Left { .. } => (ElementType::Left, None, None),
                    };
                    CandidateReport {
                        remedy,
                        element_type,
                        pn,
                        snap_to,
                        score,
                    }
                })
                .collect(),
        )
    }

    pub(super) fn commit_chosen(&mut self, c: Chosen) -> StepReport {
        let mut r = self.commit(c.cand, StepKind::Element);
        r.reference = Some(c.leading[c.leading.len() / 2]);
        r.predicted_pn = Some(c.frame.to_world(c.prediction.pn));
        r.prediction = Some(c.prediction);
        r.leading = c.leading;
        r.remedy = match (c.remedy, c.cand) {
            (Remedy::None, Cand::New { pn, .. })
                if c.frame.to_local(pn).distance(c.prediction.pn) > RESCALED_BEYOND =>
            {
                Remedy::Rescaled
            }
            (remedy, _) => remedy,
        };
        r
    }

    /// Commits a checked candidate and requeues the slots it touched.
    pub(super) fn commit(&mut self, c: Cand, kind: StepKind) -> StepReport {
        let mut r = self.report(kind);
        let f = &self.front;
        let touched: Vec<SlotId>;
        match c {
            Cand::New { s, pn } => {
                let (l, rr) = (f.prev(s), f.next(s));
                // A needle's kite closes it rather than moving the front on:
                // its new node stays in the needle's layer.
                let needle = self.at_needle(s);
                let layer = f.slot(s).layer + u32::from(!needle);
                let (p0, r1, l1) = (f.node(s), f.node(rr), f.node(l));
                let run = self.row_at(s).map(|row| {
                    let top = if row.right { l1 } else { r1 };
                    self.runs.since[top as usize].saturating_add(1)
                });
                let v = self.add_node(pn);
                if let Some(run) = run {
                    self.runs.since[v as usize] = run;
                }
                self.push_quad([p0, r1, v, l1]);
                if needle {
                    let corners = [p0, r1, v, l1].map(|k| self.mesh.nodes[k as usize]);
                    self.watch.needle_quads.0 += 1;
                    self.watch.needle_quads.1 += crate::geom::polygon_area(corners);
                }
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
    pub(super) fn pinned_corners_turn(&self, p: [Point; 4], ids: [Option<u32>; 4]) -> bool {
        (0..4).all(|k| match ids[k] {
            Some(v) if self.mesh.is_boundary(v) => {
                crate::geom::turns_left(p[(k + 3) % 4], p[k], p[(k + 1) % 4])
            }
            _ => true,
        })
    }
}

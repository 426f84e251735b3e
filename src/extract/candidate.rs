//! Candidate elements at a reference point (method §2.4–2.6): what a
//! candidate is, the remedies built when the model's element is not
//! excellent (a snapped Pn, the other types, a corrected Pn, paving's row
//! node, a kite at a sharp corner or a needle), and committing the chosen
//! one to the mesh and the front. The model's path that calls them is in
//! [`super::model_path`].

use super::guard::{self, Limits};
use super::report::{Remedy, StepKind, StepReport, RESCALED_BEYOND};
use super::session::Mesher;
use crate::front::{Front, SlotId};
use crate::geom::{ccw_angle, Point};
use crate::model::{rules, ElementType, Prediction};
use crate::normalize::{Frame, LeadingPoints};

/// Pure-model mode's state: the model's predictions the guard rejected
/// since the last step, and the leading points (node ids) of every
/// rejected prediction, so a prediction met again is counted once.
#[derive(Clone, Debug, Default)]
pub(super) struct Rejections {
    count: usize,
    inputs: std::collections::BTreeSet<Vec<u32>>,
}

impl Rejections {
    /// The model's prediction at leading points `leading` was rejected.
    pub(super) fn reject(&mut self, leading: &[u32]) {
        if self.inputs.insert(leading.to_vec()) {
            self.count += 1;
        }
    }

    /// The rejections since the last step, counted afresh from here.
    pub(super) fn take(&mut self) -> usize {
        std::mem::take(&mut self.count)
    }
}

/// A candidate element at a reference slot.
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

    /// The score an element must be over to be kept in `best`
    /// ([`Chosen::would_keep`]; any, with none kept yet).
    pub(super) fn to_beat(best: &Option<Chosen>) -> f64 {
        best.as_ref()
            .map_or(f64::NEG_INFINITY, |b| b.score + SCORE_TIE)
    }

    /// Keeps `self` in `best` if it scores higher (the first wins ties).
    pub(super) fn keep_if_best(self, best: &mut Option<Chosen>) {
        if Chosen::would_keep(self.score, best) {
            *best = Some(self);
        }
    }
}

impl Mesher {
    /// The guard's limits, from the parameters' degrees.
    pub(super) fn limits(&self) -> Limits {
        Limits {
            min_corner: self.params.min_corner,
            max_corner: self.params.max_corner,
            min_front: self.params.min_front_angle,
        }
        .radians()
    }

    pub(super) fn leading_n(&self) -> usize {
        self.model
            .leading_points()
            .unwrap_or(self.params.leading_points)
            .max(2)
    }

    /// True for a boundary node (never moved).
    pub(super) fn is_boundary(&self, v: u32) -> bool {
        (v as usize) < self.boundary_nodes
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
    pub(super) fn needle_span(&self, s: SlotId) -> Option<f64> {
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
        Some(mid + dir * (self.params.tuning.choice.needle_depth * pl.distance(pr)))
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
        for q in self.snap_targets(s, pn, self.params.tuning.choice.snap_reach * size, 4) {
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
            if let Some(g) = self.gap_along(
                base,
                v / len,
                self.params.tuning.choice.gap_reach * size,
                &skip,
            ) {
                if gap.is_none_or(|b| g < b) {
                    gap = Some(g);
                    along = len;
                }
            }
        }
        if let Some(g) = gap {
            if g > self.params.tuning.choice.gap_min * size
                && g < self.params.tuning.choice.gap_reach * size
            {
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
            let h = height.clamp(
                prev / self.params.tuning.choice.size_step,
                prev * self.params.tuning.choice.size_step,
            );
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
            let d = self.params.tuning.choice.tip_reach * a / (0.5 * theta).cos();
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
                pn: p0 + (rule_pn - p0) * self.params.tuning.choice.short_rule,
            },
            Remedy::CorrectedPn,
        ));
        out
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
                    self.runs.next(top)
                });
                let v = self.add_node(pn);
                if let Some(run) = run {
                    self.runs.set(v, run);
                }
                self.push_quad([p0, r1, v, l1]);
                if needle {
                    let corners = [p0, r1, v, l1].map(|k| self.mesh.nodes[k as usize]);
                    self.watch.needle(crate::geom::polygon_area(corners));
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
            Some(v) if self.is_boundary(v) => {
                crate::geom::turns_left(p[(k + 3) % 4], p[k], p[(k + 1) % 4])
            }
            _ => true,
        })
    }
}

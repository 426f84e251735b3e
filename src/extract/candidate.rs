//! Candidate elements at a reference point (method §2.4–2.6): the model's
//! element first, then the remedies (a snapped Pn, the other types, a
//! corrected Pn), each checked by the [`guard`](super::guard) and scored;
//! and committing the chosen one to the mesh and the front.

use super::guard::{self, Corner, Limits};
use super::report::MeshError;
use super::report::{Remedy, StepKind, StepReport};
use super::session::Mesher;
use crate::front::SlotId;
use crate::geom::{ccw_angle, Point};
use crate::model::{rules, ElementType, Model, Prediction};
use crate::normalize::{Frame, LeadingPoints};

/// A candidate element at a reference slot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Cand {
    New { s: SlotId, pn: Point },
    Snap { s: SlotId, q: SlotId },
    Right { s: SlotId },
    Left { s: SlotId },
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
    /// Keeps `self` in `best` if it scores higher (the first wins ties).
    pub(super) fn keep_if_best(self, best: &mut Option<Chosen>) {
        if best.as_ref().is_none_or(|b| beats(self.score, b.score)) {
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

    /// The nearest front node to `p` within `radius` (excluding the reference
    /// point's own neighbours), as a slot.
    pub(super) fn snap_target(&mut self, s: SlotId, p: Point, radius: f64) -> Option<SlotId> {
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
    pub(super) fn candidates(
        &mut self,
        s: SlotId,
        pred: Prediction,
        frame: &Frame,
    ) -> Vec<(Cand, Remedy)> {
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

    /// The model's element at reference slot `s`, or the best remedy. With
    /// `rules`, the rule model stands in for the model.
    pub(super) fn evaluate(
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

    pub(super) fn commit_chosen(&mut self, c: Chosen) -> StepReport {
        let mut r = self.commit(c.cand, StepKind::Element);
        r.reference = Some(c.leading[c.leading.len() / 2]);
        r.predicted_pn = Some(c.frame.to_world(c.prediction.pn));
        r.prediction = Some(c.prediction);
        r.leading = c.leading;
        r.remedy = c.remedy;
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
    pub(super) fn pinned_corners_turn(&self, p: [Point; 4], ids: [Option<u32>; 4]) -> bool {
        (0..4).all(|k| match ids[k] {
            Some(v) if self.mesh.is_boundary(v) => {
                crate::geom::turns_left(p[(k + 3) % 4], p[k], p[(k + 1) % 4])
            }
            _ => true,
        })
    }
}

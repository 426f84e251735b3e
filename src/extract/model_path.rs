//! The model's path at one reference point (method §2.3–2.6), in the
//! order it runs:
//!
//! 1. **predict**: the leading points around P0 normalised
//!    ([`crate::normalize`]) and the model's `[type, Pn]`
//!    ([`Mesher::predict_at`]);
//! 2. **size**: Pn back in the world, its row's height drawn towards the
//!    size field ([`Mesher::sized_pn`], [`Mesher::model_candidate`]);
//! 3. **guard**: the element checked and scored ([`Mesher::check`], in
//!    [`super::guard`]);
//! 4. **choose**: the model's element when it is excellent, else the
//!    remedies ([`Mesher::candidates`]) are built, guarded and scored, and
//!    the model's element is kept unless a remedy beats it by more than
//!    [`ChoiceTuning::model_margin`](super::tuning::ChoiceTuning::model_margin)
//!    ([`Mesher::evaluate`]).
//!
//! [`Mesher::explain`] shows every candidate of a node as the next step
//! would see it.

use super::candidate::{Cand, CandidateReport, Chosen};
use super::guard::Limits;
use super::report::{MeshError, Remedy};
use super::session::Mesher;
use crate::front::SlotId;
use crate::geom::{Aabb, Point};
use crate::model::{ElementType, Model, Prediction};
use crate::normalize::Frame;

impl Mesher {
    /// The model's element at reference slot `s`, or the best remedy. With
    /// `rules`, the rule model stands in for the model. The model's element
    /// is taken when it scores at least `accept_score` and is not beaten by
    /// more than [`ChoiceTuning::model_margin`](super::tuning::ChoiceTuning::model_margin); otherwise the best candidate.
    pub(super) fn evaluate(
        &mut self,
        s: SlotId,
        limits: Limits,
        rules: bool,
    ) -> Result<Option<Chosen>, MeshError> {
        let (slots, frame, pred) = self.predict_at(s, rules);
        let leading: Vec<u32> = slots.iter().map(|&t| self.front.node(t)).collect();
        // Pure, the model's element alone is weighed and its refusal counts.
        let pure = self.params.pure_model && !rules;
        // The model's element as guarded here, not guarded again below.
        let mut guarded: Option<(Cand, Option<f64>)> = None;
        // The model's element comes first among the candidates: when it is
        // excellent the others need not be built. The box read
        // (`evaluated`) is worked out where the evaluation ends: of the
        // model's element alone when it returns early, else of all the
        // candidates.
        if !pure {
            let (c, _) = self.model_candidate(s, pred, &frame);
            let checked = self.check(c, limits);
            guarded = Some((c, checked));
            if let Some(score) = checked.filter(|&v| v >= self.params.tuning.choice.excellent) {
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
        // Unless pure, a candidate that could not beat the best so far
        // ([`Chosen::keep_if_best`]) need not be weighed whole.
        for (c, remedy) in cands {
            let bar = if pure {
                f64::NEG_INFINITY
            } else {
                Chosen::to_beat(&best)
            };
            let checked = match guarded.take() {
                // The model's element, first (with no best yet to beat).
                Some((g, score)) if g == c && remedy == Remedy::None => score,
                _ => self.check_above(c, limits, bar),
            };
            let Some(score) = checked else {
                if pure {
                    self.rejections.reject(&leading);
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
                if score >= self.params.tuning.choice.excellent {
                    return Ok(Some(chosen));
                }
                model = Some(chosen.clone());
            }
            chosen.keep_if_best(&mut best);
        }
        if let (Some(m), Some(b)) = (&model, &best) {
            if m.score >= self.params.accept_score
                && m.score + self.params.tuning.choice.model_margin >= b.score
            {
                return Ok(model);
            }
        }
        Ok(best)
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

    /// Candidate list at reference slot `s`, model first, then remedies:
    /// the model's element (Pn sized, [`Mesher::sized_pn`]); where the
    /// model's Pn comes near other front nodes, the element closed onto
    /// each of them (snapped); the other types; where the front ahead is
    /// too close for a full element and too far to reach, Pn half-way
    /// across; the rule-based Pn.
    /// The model's own element at reference slot `s` (its Pn sized to the
    /// row it continues), and that Pn in world coordinates.
    pub(super) fn model_candidate(
        &self,
        s: SlotId,
        pred: Prediction,
        frame: &Frame,
    ) -> (Cand, Point) {
        let pn_world = self.sized_pn(s, frame.to_world(pred.pn));
        let cand = match pred.element_type {
            ElementType::New => Cand::New { s, pn: pn_world },
            ElementType::Right => Cand::Right { s },
            ElementType::Left => Cand::Left { s },
        };
        (cand, pn_world)
    }

    /// Pn with the row's height drawn towards the size field (the model's
    /// output is normalised by the front edge at P0, so it carries the
    /// front's spacing, not the size wanted here). Where P0 continues a row
    /// (one of its front neighbours was made by extraction after P0), the
    /// new side from the other neighbour to Pn is the row's next height:
    /// its length moves towards the local size by at most [`ChoiceTuning::size_step`](super::tuning::ChoiceTuning::size_step).
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
        let k = (want / len).clamp(
            1.0 / self.params.tuning.choice.size_step,
            self.params.tuning.choice.size_step,
        );
        base + v * k
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
        let choice = &self.params.tuning.choice;
        let reach = Point::splat(choice.read_margin * (choice.gap_reach + 1.0) * size);
        (lo - reach, hi + reach)
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extract::StepOutcome;

    /// Every candidate at every front node of a holed, unevenly spaced
    /// domain, at several points of its run: refused for a bar only when
    /// its full score is not over the bar (or the guard refuses it), and
    /// scored the same otherwise; some that pass the guard are refused
    /// for a bar.
    #[test]
    fn a_candidate_refused_for_a_bar_would_not_have_scored_over_it() {
        let ring = |n: usize, r: f64, wobble: f64, cw: bool| -> Vec<Point> {
            let mut pts: Vec<Point> = (0..n)
                .map(|k| {
                    // Uneven spacing: nodes bunched towards angle 0.
                    let t = k as f64 / n as f64;
                    let a = std::f64::consts::TAU * (t + 0.08 * (std::f64::consts::TAU * t).sin());
                    let rr = r * (1.0 + wobble * (5.0 * a).sin());
                    Point::new(rr * a.cos(), rr * a.sin())
                })
                .collect();
            if cw {
                pts.reverse();
            }
            pts
        };
        let mut m = Mesher::of_loops(vec![ring(56, 1.0, 0.12, false), ring(20, 0.35, 0.0, true)]);
        let limits = m.limits();
        let (mut cut, mut kept) = (0, 0);
        for round in 0..6 {
            let slots: Vec<SlotId> = m
                .front
                .live_loops()
                .flat_map(|l| m.front.loop_slots(l))
                .collect();
            for s in slots {
                let (_, frame, pred) = m.predict_at(s, false);
                for (c, _) in m.candidates(s, pred, &frame) {
                    let full = m.check(c, limits);
                    for bar in [0.0, 0.3, 0.6, 0.8, full.unwrap_or(0.5)] {
                        let got = m.check_above(c, limits, bar);
                        match got {
                            Some(v) => {
                                assert_eq!(Some(v.to_bits()), full.map(f64::to_bits));
                                kept += 1;
                            }
                            None => {
                                assert!(
                                    full.is_none_or(|v| v <= bar),
                                    "round {round}: {c:?} bar {bar}: {full:?}"
                                );
                                cut += usize::from(full.is_some());
                            }
                        }
                    }
                }
            }
            for _ in 0..12 {
                match m.step() {
                    Ok(StepOutcome::Stepped(_)) => {}
                    Ok(StepOutcome::Done) => break,
                    Err(e) => panic!("{e}"),
                }
            }
        }
        assert!(cut > 100 && kept > 100, "{cut} cut, {kept} kept");
    }
}

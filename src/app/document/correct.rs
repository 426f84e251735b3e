//! Correcting the last element: the mesher before it, the correction,
//! and the front nodes the element could close onto instead.

use super::{kind_name, Document};
use crate::app::error::EditorError;
use crate::app::framed::Framed;
use crate::extract::{CheckedElement, Correction, StepKind};
use crate::geom::Point;
use crate::model::ElementType;

/// A front node the last element could be closed onto instead, and
/// whether that gives a valid element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    pub node: u32,
    pub at: Point,
    /// Type 1 for P_r2, type 2 for P_l2, else type 0 closed onto the node.
    pub element_type: ElementType,
    /// The element closing onto the node gives (`None`: not a valid
    /// element): its guard's score and corners. A valid element may still
    /// be a poor one.
    pub check: Option<CheckedElement>,
}

impl Target {
    /// True when closing onto this node gives a valid element.
    pub fn valid(&self) -> bool {
        self.check.is_some()
    }

    /// The correction that closes the element onto this node.
    pub fn command(&self) -> crate::app::Command {
        crate::app::Command::CorrectLast {
            element_type: self.element_type,
            pn: self.at,
            snap_to: (self.element_type == ElementType::New).then_some(self.node),
        }
    }
}

impl Document {
    /// The mesher as it was before the last step (the last step undone).
    pub fn before_last(&self) -> Option<Framed> {
        let mut m = self.mesher()?.clone();
        m.undo().then_some(m)
    }

    /// Replaces the last element by the user's (type 0 closes onto front
    /// node `snap_to` when given): the step is undone, the correction
    /// committed at the same reference point, and its sample appended (in
    /// place of any earlier correction of the same input: the step
    /// corrected again, or corrected before a Reset). `before` is the
    /// mesher before the last step when the caller has it (else it is
    /// replayed). If the correction is not a valid element,
    /// nothing changes.
    pub fn correct_last(
        &mut self,
        element_type: ElementType,
        pn: Point,
        snap_to: Option<u32>,
        before: Option<Framed>,
    ) -> Result<usize, EditorError> {
        let r = self.last().ok_or(EditorError::NoStep)?;
        if !matches!(r.kind, StepKind::Element | StepKind::Correction) {
            return Err(EditorError::NotAnElement(kind_name(r.kind)));
        }
        let reference = r.reference.ok_or(EditorError::NoStep)?;
        let c = Correction {
            reference,
            element_type,
            pn: Some(pn),
            snap_to,
        };
        let mut mesher = match before {
            Some(b) => b,
            None => self.before_last().ok_or(EditorError::NoStep)?,
        };
        let (prediction, predicted_pn) = (r.prediction, r.predicted_pn);
        let mut report = mesher.correct(&c)?;
        let sample = mesher.sample_of(&report);
        // The model's element at this input stays on show beside the
        // user's, to compare them (a correction has no prediction of its
        // own).
        report.prediction = prediction;
        report.predicted_pn = predicted_pn;
        let m = self.meshing_mut()?;
        m.mesher = mesher;
        m.last = Some(report);
        match sample {
            Some(s) => {
                // One input, one answer: an earlier correction of the same
                // input (the step corrected again, or corrected before a
                // Reset) gives way to this one.
                self.training.samples.retain(|o| {
                    !(o.source == crate::samples::Source::Correction && o.input == s.input)
                });
                self.push_sample(s)
            }
            None => Ok(self.training.len()),
        }
    }

    /// The front nodes near the last element's reference point that the
    /// element could be closed onto instead (P_r2 as type 1, P_l2 as type 2,
    /// any other as type 0 with that node as Pn), each checked on `before`,
    /// the mesher before the last step.
    pub fn closing_targets(&self, before: &mut Framed) -> Vec<Target> {
        let Some(r) = self.last_element() else {
            return Vec::new();
        };
        let n = r.leading.len() / 2;
        if n == 0 {
            return Vec::new();
        }
        let nodes = &before.mesh().nodes;
        let at = |v: u32| nodes.get(v as usize).copied();
        let (Some(p0), Some(l1), Some(r1)) =
            (at(r.leading[n]), at(r.leading[n - 1]), at(r.leading[n + 1]))
        else {
            return Vec::new();
        };
        let (p0_id, l1_id, r1_id) = (r.leading[n], r.leading[n - 1], r.leading[n + 1]);
        let l2 = (n >= 2).then(|| r.leading[n - 2]);
        let r2 = r.leading.get(n + 2).copied();
        let reach = 3.0 * p0.distance(l1).max(p0.distance(r1));
        let f = before.front();
        let mut near: Vec<(u32, Point)> = f
            .live_loops()
            .flat_map(|l| f.loop_nodes(l))
            .filter(|&v| v != p0_id && v != l1_id && v != r1_id)
            .filter_map(|v| at(v).map(|p| (v, p)))
            .filter(|(_, p)| p.distance(p0) <= reach)
            .collect();
        near.sort_unstable_by_key(|(v, _)| *v);
        near.dedup_by_key(|(v, _)| *v);
        near.into_iter()
            .map(|(v, p)| {
                let element_type = if Some(v) == r2 {
                    ElementType::Right
                } else if Some(v) == l2 {
                    ElementType::Left
                } else {
                    ElementType::New
                };
                let c = Correction {
                    reference: p0_id,
                    element_type,
                    pn: Some(p),
                    snap_to: (element_type == ElementType::New).then_some(v),
                };
                Target {
                    node: v,
                    at: p,
                    element_type,
                    check: before.check_correction(&c).ok(),
                }
            })
            .collect()
    }
}

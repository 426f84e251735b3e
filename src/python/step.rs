//! The step API for the Python module, without Python: a [`Mesher`] run in
//! its boundary's local frame (as [`crate::pipeline::mesh_boundary`] runs
//! it, so a run stepped to the end gives the mesh `quadex mesh` writes),
//! what the next step will do (a step taken on a copy, as the editor's
//! preview does), the model's element there, an element given by the
//! caller (the editor's correction), and an element given as the model's
//! prediction (the learning environment's action).

use super::run::{load_model, read_boundary, Options, Source};
use crate::extract::{Correction, MeshError, Mesher, Remedy, StepKind, StepOutcome, StepReport};
use crate::geom::Point;
use crate::mesh::QuadMesh;
use crate::model::{ElementType, Model, Prediction};
use crate::normalize::{Frame, LeadingPoints};
use crate::pipeline::{self, FinishParams};
use std::sync::Arc;

/// A model that answers `prediction` for exactly the input `input` and
/// asks `inner` for every other: the caller's element at one reference
/// point, every other reference point the engine looks at left to the
/// model.
struct Given {
    inner: Arc<dyn Model>,
    input: LeadingPoints,
    prediction: Prediction,
}

impl Model for Given {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn leading_points(&self) -> Option<usize> {
        self.inner.leading_points()
    }
    fn predict(&self, input: &LeadingPoints) -> Prediction {
        if *input == self.input {
            self.prediction
        } else {
            self.inner.predict(input)
        }
    }
}

/// The next step as a step on a copy found it.
#[derive(Clone)]
pub struct Next {
    /// The copy after the step: taking the step is taking the copy.
    after: Result<Mesher, MeshError>,
    /// Its report (`None`: the mesh is complete).
    pub report: Option<StepReport>,
}

/// An element step's reference point and leading points, before the step.
#[derive(Clone, Debug)]
pub struct Observation {
    pub reference: u32,
    /// Node ids, thesis order `l_N..l1, P0, r1..r_N`.
    pub leading: Vec<u32>,
    /// Their positions, world frame.
    pub world: Vec<Point>,
    /// The normalised frame of P0 (in the mesher's local frame).
    frame: Frame,
    /// The model's input: the leading points normalised.
    pub input: LeadingPoints,
}

impl Observation {
    /// The `2N + 1` normalised points in thesis order (P0 the origin).
    pub fn normalised(&self) -> Vec<Point> {
        self.input.thesis_order()
    }
}

/// What a step given as the model's prediction did.
#[derive(Clone, Debug)]
pub struct Taken {
    pub report: StepReport,
    /// The step took an element at the observed reference point.
    pub at_observed: bool,
    /// The guard's score of the element the step committed (the quality
    /// of the quad and of the front it leaves, in `[0, 1]`), when it
    /// committed one element.
    pub score: Option<f64>,
}

/// What an element given by the caller came to.
#[derive(Clone, Debug)]
pub enum Verdict {
    /// Committed, with the guard's score and the step's report.
    Taken { score: f64, report: StepReport },
    /// Refused, with the reason.
    Refused(String),
}

/// A mesher over one boundary, stepped from Python.
#[derive(Clone)]
pub struct Stepper {
    mesher: Mesher,
    origin: Point,
    model: Arc<dyn Model>,
    finish: FinishParams,
    label: String,
    next: Option<Next>,
}

impl Stepper {
    /// A stepper over `src` with `o`'s options (those of extraction and
    /// finishing; order and drawing sizes do not apply).
    pub fn new(src: &Source, o: &Options) -> Result<Stepper, String> {
        o.check()?;
        let boundary = read_boundary(src, o.resample)?;
        let model = load_model(&o.model)?;
        let params = o.params(model.as_ref())?;
        let (local, origin) = boundary.to_local();
        let mesher = Mesher::new(local, model.clone(), params.extract.moved(origin));
        Ok(Stepper {
            mesher,
            origin,
            model,
            finish: params.finish,
            label: src.label(),
            next: None,
        })
    }

    /// An engine error as the command line words it.
    fn fail(&self, e: &dyn std::fmt::Display) -> String {
        format!("{}: {e}", self.label)
    }

    pub fn is_done(&self) -> bool {
        self.mesher.is_done()
    }

    pub fn steps(&self) -> usize {
        self.mesher.steps()
    }

    pub fn front_len(&self) -> usize {
        self.mesher.front().len()
    }

    /// The mesher's frame is moved by `-origin`: world positions.
    pub fn origin(&self) -> Point {
        self.origin
    }

    /// The next step, taken on a copy (once per state).
    fn next(&mut self) -> &Next {
        let m = &self.mesher;
        self.next.get_or_insert_with(|| {
            let mut after = m.clone();
            match after.step() {
                Ok(StepOutcome::Stepped(r)) => Next {
                    after: Ok(after),
                    report: Some(*r),
                },
                Ok(StepOutcome::Done) => Next {
                    after: Ok(after),
                    report: None,
                },
                Err(e) => Next {
                    after: Err(e),
                    report: None,
                },
            }
        })
    }

    /// What the next step will be: its kind (`None` when the mesh is
    /// complete), and for an element step its reference point and leading
    /// points. An engine error is the step's error.
    pub fn observe(&mut self) -> Result<(Option<StepKind>, Option<Observation>), String> {
        self.next();
        let Some(next) = self.next.as_ref() else {
            return Ok((None, None));
        };
        if let Err(e) = &next.after {
            return Err(format!("{}: {e}", self.label));
        }
        let Some(r) = &next.report else {
            return Ok((None, None));
        };
        if r.kind != StepKind::Element || r.leading.len() < 5 {
            return Ok((Some(r.kind), None));
        }
        let nodes = &self.mesher.mesh().nodes;
        let pos = |v: u32| nodes[v as usize];
        let n = r.leading.len() / 2;
        let p0 = pos(r.leading[n]);
        let frame = Frame::new(p0, pos(r.leading[n + 1]));
        let left: Vec<Point> = (1..=n).map(|k| pos(r.leading[n - k])).collect();
        let right: Vec<Point> = (1..=n).map(|k| pos(r.leading[n + k])).collect();
        let input = LeadingPoints::normalise(&frame, &left, &right);
        Ok((
            Some(r.kind),
            Some(Observation {
                reference: r.leading[n],
                world: r.leading.iter().map(|&v| pos(v) + self.origin).collect(),
                leading: r.leading.clone(),
                frame,
                input,
            }),
        ))
    }

    /// The observed element step, or why there is none.
    fn observed(&mut self) -> Result<Observation, String> {
        match self.observe()? {
            (_, Some(o)) => Ok(o),
            (None, _) => Err(format!("{}: the mesh is complete", self.label)),
            (Some(k), None) => Err(format!(
                "{}: the next step is not an element step ({k:?}): take it with step()",
                self.label
            )),
        }
    }

    /// The model's element at the observed reference point (normalised
    /// frame) and its Pn in the world frame.
    pub fn predict(&mut self) -> Result<(Prediction, Point), String> {
        let o = self.observed()?;
        let p = self.model.predict(&o.input);
        Ok((p, o.frame.to_world(p.pn) + self.origin))
    }

    /// The engine's own step; `None` when the mesh is complete.
    pub fn step(&mut self) -> Result<Option<StepReport>, String> {
        self.next();
        let Some(next) = self.next.take() else {
            return Ok(None);
        };
        match next.after {
            Ok(m) => {
                self.mesher = m;
                Ok(next.report)
            }
            Err(e) => Err(self.fail(&e)),
        }
    }

    /// The engine's step with `prediction` (normalised frame) as the
    /// model's element at the observed reference point: the guard takes
    /// it, draws its Pn to the size field, snaps it, or replaces it as it
    /// would the model's own; an element too poor waits while another
    /// reference point does better, as the model's would.
    pub fn step_as(&mut self, prediction: Prediction) -> Result<Taken, String> {
        let o = self.observed()?;
        if !(prediction.pn.x.is_finite() && prediction.pn.y.is_finite()) {
            return Err(format!("{}: Pn must be finite", self.label));
        }
        let mut after = self.mesher.clone();
        after.set_model(Arc::new(Given {
            inner: self.model.clone(),
            input: o.input.clone(),
            prediction,
        }));
        let out = after.step();
        after.set_model(self.model.clone());
        let report = match out {
            Ok(StepOutcome::Stepped(r)) => *r,
            Ok(StepOutcome::Done) => return Err(format!("{}: the mesh is complete", self.label)),
            Err(e) => return Err(self.fail(&e)),
        };
        let at_observed = report.kind == StepKind::Element && report.reference == Some(o.reference);
        let score = self.score_of(&report, &after);
        self.mesher = after;
        self.next = None;
        Ok(Taken {
            report,
            at_observed,
            score,
        })
    }

    /// The guard's score, before the step, of the one element step `r`
    /// committed (`after` is the mesher after it).
    fn score_of(&mut self, r: &StepReport, after: &Mesher) -> Option<f64> {
        if r.kind != StepKind::Element || r.quads.len() != 1 {
            return None;
        }
        let c = Correction {
            reference: r.reference?,
            element_type: r.element_type?,
            pn: r.new_nodes.first().map(|&v| after.mesh().nodes[v as usize]),
            snap_to: match r.new_nodes.first() {
                Some(_) => None,
                None => r.pn_node(),
            },
        };
        self.mesher.check_correction(&c).ok().map(|e| e.score)
    }

    /// The caller's element at the observed reference point (the editor's
    /// correction): type 0 with Pn (world frame) or closed onto front node
    /// `snap_to`, or type 1 or 2. The guard checks that it is a valid
    /// element (convex, crossing no front edge) and scores it.
    pub fn apply(
        &mut self,
        element_type: ElementType,
        pn: Option<Point>,
        snap_to: Option<u32>,
    ) -> Result<Verdict, String> {
        let o = self.observed()?;
        let c = Correction {
            reference: o.reference,
            element_type,
            pn: pn.map(|p| p - self.origin),
            snap_to,
        };
        if element_type == ElementType::New && pn.is_none() && snap_to.is_none() {
            return Err(format!(
                "{}: a type 0 element needs pn or snap_to",
                self.label
            ));
        }
        let score = match self.mesher.check_correction(&c) {
            Ok(e) => e.score,
            Err(e) => return Ok(Verdict::Refused(e.to_string())),
        };
        match self.mesher.correct(&c) {
            Ok(report) => {
                self.next = None;
                Ok(Verdict::Taken { score, report })
            }
            Err(e) => Ok(Verdict::Refused(e.to_string())),
        }
    }

    /// The element at the observed reference point given in its
    /// normalised frame, in the world frame.
    pub fn to_world(&mut self, q: Point) -> Result<Point, String> {
        let o = self.observed()?;
        Ok(o.frame.to_world(q) + self.origin)
    }

    /// Takes the last step back.
    pub fn undo(&mut self) -> bool {
        self.next = None;
        self.mesher.undo()
    }

    /// The mesh: finished as `quadex mesh` finishes it (cleanup,
    /// coarsening, remeshing, smoothing, checked) when `finished`, else as
    /// extraction left it; world frame.
    pub fn mesh(&self, finished: bool) -> Result<QuadMesh, String> {
        if finished {
            return pipeline::finish_moved(&self.mesher, &self.finish, self.origin)
                .map_err(|e| self.fail(&e));
        }
        let mut m = self.mesher.mesh().clone();
        pipeline::to_world(&mut m, self.origin);
        Ok(m)
    }

    /// A report's quads' corners, world frame.
    pub fn corners(&self, r: &StepReport) -> Vec<[Point; 4]> {
        r.quads
            .iter()
            .filter(|q| {
                q.iter()
                    .all(|&v| (v as usize) < self.mesher.mesh().nodes.len())
            })
            .map(|q| self.mesher.mesh().corners(q).map(|p| p + self.origin))
            .collect()
    }
}

/// A remedy's name as docs/python.md lists them.
pub fn remedy_name(r: Remedy) -> &'static str {
    match r {
        Remedy::None => "none",
        Remedy::Rescaled => "rescaled",
        Remedy::Snapped => "snapped",
        Remedy::OtherType => "other_type",
        Remedy::CorrectedPn => "corrected_pn",
        Remedy::RuleBased => "rule_based",
        Remedy::NotApplicable => "not_applicable",
    }
}

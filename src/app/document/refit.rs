//! A refit: its work taken to a thread ([`RefitTask`]), its phases, and
//! the figures of the model before and after it.

use super::fit_cache::{global_fit, reference, reference_samples};
use super::models::ModelInfo;
use super::Document;
use crate::app::error::EditorError;
use crate::fit::{self, Figures, FitParams, TypeFigures};
use crate::model::fitted::FittedModel;
use crate::model::Model as _;
use crate::model::{self, Form, ModelFile};
use crate::samples::TrainingSet;
use crate::{compare, Boundary};
use std::sync::Arc;

/// Figures of the model before and after a refit, on the same samples.
#[derive(Clone, Debug, PartialEq)]
pub struct RefitFigures {
    /// Samples the global part was fitted on (the reference meshes' and
    /// those collected from meshes, duplicates dropped), as the model's
    /// own summary counts them.
    pub samples: usize,
    /// The user's corrections layered over it.
    pub corrections: usize,
    /// Samples collected from meshes or imported that the fit dropped as
    /// repeats of samples already in the set (they add nothing).
    pub repeated: usize,
    pub before: (TypeFigures, Figures, Figures),
    pub after: (TypeFigures, Figures, Figures),
    /// The refitted model's name.
    pub model: String,
    /// What the models before and after predict at each correction.
    pub checks: Vec<CorrectionCheck>,
    /// The boundary meshed from the start with the model before and the
    /// refitted one.
    pub meshed: Option<(compare::Outcome, compare::Outcome)>,
    /// Meshing the boundary from the start with the refitted model: the
    /// predictions its corrections changed, of all it made (none without
    /// corrections or without that meshing).
    pub memory_reach: Option<(usize, usize)>,
    /// How the refitted model meshes the boundary worse (empty: it does
    /// not).
    pub worse: Vec<String>,
}

/// A correction and what the models predict at its input (normalised
/// frame).
#[derive(Clone, Debug, PartialEq)]
pub struct CorrectionCheck {
    /// The position of the correction among the user's samples.
    pub sample: usize,
    pub corrected: model::Prediction,
    pub before: model::Prediction,
    pub after: model::Prediction,
}

/// How near the refitted model's Pn must come to the correction's for the
/// correction to count as reproduced (normalised units).
pub const REPRODUCED: f64 = 0.05;

impl CorrectionCheck {
    /// The refitted model predicts the corrected element.
    pub fn reproduced(&self) -> bool {
        self.after.element_type == self.corrected.element_type
            && self.after.pn.distance(self.corrected.pn) <= REPRODUCED
    }
}

/// The reference samples and the user's `training`, as a refit sees them
/// ([`Document::refit_set`]).
pub fn refit_set_of(training: TrainingSet) -> Result<TrainingSet, EditorError> {
    let mut set = (*reference_samples(training.points)?).clone();
    set.merge(training)?;
    Ok(set)
}

/// The fitting parameters of the editor's refit (no held-out folds: the
/// figures shown are those of the samples themselves).
const REFIT_PARAMS: FitParams = FitParams {
    folds: 0,
    ..FitParams::DEFAULT
};

/// A refit's work ([`Document::refit_task`]), to be taken to a thread.
pub struct RefitTask {
    pub form: Form,
    training: TrainingSet,
    /// The refitted model's name.
    name: String,
    /// The model meshed with before the refit.
    old: Arc<dyn model::Model>,
    params: crate::pipeline::Params,
    /// The boundary meshed from the start with both models (none above
    /// [`COMPARE_NODES`] nodes).
    boundary: Option<Boundary>,
}

/// The parts of a refit, as its progress line names them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RefitPhase {
    /// The reference samples collected (once per session).
    Collecting,
    /// The global fit on this many samples (taken at once when it was
    /// made before) and the corrections layered over it.
    Fitting(usize),
    /// Both models measured on the samples.
    Measuring,
    /// The boundary meshed from the start with the model before; the share
    /// of its area meshed.
    MeshingBefore(f64),
    /// The same with the refitted model.
    MeshingAfter(f64),
}

impl RefitPhase {
    /// The progress line: "meshing the boundary with the refitted model
    /// (45 %)".
    pub fn describe(self) -> String {
        match self {
            RefitPhase::Collecting => "collecting the reference samples".into(),
            RefitPhase::Fitting(n) => format!("fitting on {}", crate::app::plural(n, "sample")),
            RefitPhase::Measuring => "measuring both models on the samples".into(),
            RefitPhase::MeshingBefore(f) => format!(
                "meshing the boundary from the start with the model before ({:.0} %)",
                100.0 * f
            ),
            RefitPhase::MeshingAfter(f) => format!(
                "meshing the boundary from the start with the refitted model ({:.0} %)",
                100.0 * f
            ),
        }
    }
}

/// What a refit made, to be taken into the document
/// ([`Document::take_refit`]).
pub struct RefitDone {
    file: ModelFile,
    model: FittedModel,
    pub figures: RefitFigures,
}

/// Predictions a correction memory may change, as a share of a run's
/// predictions, before the refit report says the corrections reach too
/// far (one correction meant for one front that changes a large part of
/// the mesh).
pub const WORSE_MEMORY_SHARE: f64 = 0.05;

/// A fitted model that counts the predictions its corrections changed
/// (those where [`FittedModel::predict`] is not
/// [`FittedModel::predict_global`]).
struct MemoryCount {
    model: FittedModel,
    calls: std::sync::atomic::AtomicUsize,
    changed: std::sync::atomic::AtomicUsize,
}

impl model::Model for MemoryCount {
    fn name(&self) -> &str {
        self.model.name()
    }

    fn leading_points(&self) -> Option<usize> {
        self.model.leading_points()
    }

    fn predict(&self, input: &crate::normalize::LeadingPoints) -> model::Prediction {
        use std::sync::atomic::Ordering;
        let p = self.model.predict(input);
        self.calls.fetch_add(1, Ordering::Relaxed);
        if p != self.model.predict_global(input) {
            self.changed.fetch_add(1, Ordering::Relaxed);
        }
        p
    }
}

impl RefitTask {
    /// Makes the refit: the global fit (kept for the session), the
    /// corrections layered over it, both models measured on the samples
    /// and at each correction, and the boundary meshed from the start with
    /// both; `phase` is told as each part starts.
    pub fn run(self, phase: impl Fn(RefitPhase)) -> Result<RefitDone, EditorError> {
        use std::sync::atomic::Ordering;
        phase(RefitPhase::Collecting);
        let base = reference(self.training.points)?;
        let (own, from_meshes) = fit::split_added(&self.training);
        let (from_meshes, repeated) = if from_meshes.is_empty() {
            (from_meshes, 0)
        } else {
            from_meshes.beyond(base.keys.get_or_init(|| base.set.keys()))
        };
        let base = base.set;
        phase(RefitPhase::Fitting(base.len() + from_meshes.len()));
        let set = refit_set_of(self.training.clone())?;
        let memory = fit::correction_memory(base.points, &own, model::memory::DEFAULT_RADIUS)?;
        let mut global = global_fit(&base, &from_meshes, self.form, &REFIT_PARAMS)?;
        global.name = self.name.clone();
        let file = fit::with_memory(global, memory);
        let model = file.model();
        let old = self.old;
        phase(RefitPhase::Measuring);
        // The two models measured side by side (a second each on the
        // reference samples).
        let (before, after) = std::thread::scope(|scope| {
            let before = scope.spawn(|| fit::evaluate(old.as_ref(), &set));
            let after = fit::evaluate(&model, &set);
            (before.join(), after)
        });
        let before = before.map_err(|_| EditorError::JobPanicked)??;
        let after = after?;
        let checks = self
            .training
            .samples
            .iter()
            .enumerate()
            .filter(|(_, s)| s.source == crate::samples::Source::Correction)
            .map(|(i, s)| CorrectionCheck {
                sample: i,
                corrected: model::Prediction {
                    element_type: s.element_type,
                    pn: s.pn,
                },
                before: old.predict(&s.input),
                after: model.predict(&s.input),
            })
            .collect();
        let counted = Arc::new(MemoryCount {
            model: model.clone(),
            calls: Default::default(),
            changed: Default::default(),
        });
        let meshed = self.boundary.as_ref().map(|b| {
            let before =
                compare::mesh_with_progress(old.name(), b, old.clone(), &self.params, |p| {
                    phase(RefitPhase::MeshingBefore(p.meshed))
                });
            let after =
                compare::mesh_with_progress(&file.name, b, counted.clone(), &self.params, |p| {
                    phase(RefitPhase::MeshingAfter(p.meshed))
                });
            (before, after)
        });
        let memory_reach = meshed
            .as_ref()
            .filter(|_| !model.memory.is_empty())
            .map(|_| {
                (
                    counted.changed.load(Ordering::Relaxed),
                    counted.calls.load(Ordering::Relaxed),
                )
            });
        let mut worse = meshed
            .as_ref()
            .map(|(b, a)| a.worse_than(b))
            .unwrap_or_default();
        if let Some((changed, calls)) = memory_reach {
            if changed as f64 > WORSE_MEMORY_SHARE * calls as f64 {
                worse.push(format!(
                    "the corrections change {} of {} predictions",
                    compare::grouped(changed),
                    compare::grouped(calls)
                ));
            }
        }
        let figures = RefitFigures {
            samples: file.training.samples,
            corrections: file.training.corrections,
            repeated,
            before,
            after,
            model: file.name.clone(),
            checks,
            meshed,
            memory_reach,
            worse,
        };
        Ok(RefitDone {
            file,
            model,
            figures,
        })
    }
}

/// The name of the `k`-th refitted model of `form`.
fn refit_name(form: Form, k: usize) -> String {
    format!("fitted ({}) {k}", form.name())
}

/// Boundaries with more nodes than this are not meshed again from the
/// start after a refit (it would take too long to wait for).
pub const COMPARE_NODES: usize = 4000;

impl Document {
    /// The reference samples and the user's, as a refit sees them.
    pub fn refit_set(&self) -> Result<TrainingSet, EditorError> {
        refit_set_of(self.training.clone())
    }

    /// Refits a model of `form` on the reference samples plus the user's
    /// ([`fit::refit`]: samples collected from meshes join the global fit,
    /// the user's own elements are layered over it as corrections), adds it
    /// to the document's models and chooses it (a reset or a boundary edit
    /// keeps it), sets it to mesh the rest of the mesh with, and returns
    /// the figures of the old and the new model: on those samples, at each
    /// correction, and meshing the boundary from the start.
    pub fn refit(&mut self, form: Form) -> Result<RefitFigures, EditorError> {
        let done = self.refit_task(form)?.run(|_| {})?;
        self.take_refit(done)
    }

    /// What a refit in `form` works on ([`Document::refit`]), to be made
    /// in a thread ([`RefitTask::run`]) and taken back with
    /// [`Document::take_refit`].
    pub fn refit_task(&self, form: Form) -> Result<RefitTask, EditorError> {
        let m = self.meshing.as_ref().ok_or(EditorError::NoStep)?;
        let mut k = self.models.len() + 1;
        while self.models.iter().any(|f| f.name == refit_name(form, k)) {
            k += 1;
        }
        Ok(RefitTask {
            form,
            training: self.training.clone(),
            name: refit_name(form, k),
            old: m.mesher.model().clone(),
            params: crate::pipeline::Params {
                extract: m.mesher.params().clone(),
                finish: self.settings.finishing(),
            },
            boundary: (m.boundary.node_count() <= COMPARE_NODES).then(|| m.boundary.clone()),
        })
    }

    /// Takes a refit made by [`RefitTask::run`]: the model joins the
    /// document's models, is chosen, and meshes the rest.
    pub fn take_refit(&mut self, done: RefitDone) -> Result<RefitFigures, EditorError> {
        let RefitDone {
            file,
            model,
            figures,
        } = done;
        let m = self.meshing_mut()?;
        m.mesher.set_model(Arc::new(model.clone()));
        m.refits.push((m.mesher.steps(), model));
        m.info = ModelInfo::of_file(&file);
        self.settings.model = file.name.clone();
        self.models.push(file);
        self.last_refit = Some(figures.clone());
        Ok(figures)
    }
}

//! Model fitting (thesis Chapter 4, §4.3; method §4): from a
//! [`TrainingSet`] to the coefficients of a [`Form`], with the fit figures
//! on the training samples and on held-out samples (k-fold, fixed seed).
//!
//! - [`thesis`]: Xn and Yn by linear least squares (SVD); the type by a 1-D
//!   search over μ1 with least squares inside (replacing the thesis's
//!   Auto2Fit global optimiser).
//! - [`quadratic`]: a multinomial logistic classifier for the type (Newton
//!   iterations with an L2 penalty) and a ridge quadratic per type for Pn;
//! - [`ann`]: a back-propagation network (Yao & Zeng), trained by Adam
//!   from a seeded start.
//!
//! Linear algebra is nalgebra's.

pub mod ann;
pub mod quadratic;
pub mod thesis;

pub use crate::model::figures::{Figures, FitReport, Split, TypeFigures};

use crate::geom::Point;
use crate::model::fitted::{Coefficients, ModelFile, TrainingSummary};
use crate::model::memory::CorrectionMemory;
use crate::model::Form;
use crate::normalize::LeadingPoints;
use crate::samples::{Source, TrainingSet};
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use thiserror::Error;

/// Parameters of fitting, with documented defaults.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct FitParams {
    /// Folds of the held-out figures (k-fold cross-validation). Default 5;
    /// 0 or 1 skips it (held-out figures are then those of training).
    pub folds: usize,
    /// Seed of the fold assignment. Default 2011 (the thesis's year).
    pub seed: u64,
    /// Ridge penalty of the quadratic Pn model (on standardised inputs,
    /// intercept free). Default 1e-3.
    pub ridge: f64,
    /// L2 penalty of the logistic type classifier. Default 1.
    pub logistic_l2: f64,
    /// Newton iterations of the classifier at most. Default 30.
    pub newton_iterations: usize,
    /// Range of the μ1 search of the thesis's type model. Default [0.01, 100].
    pub mu1_range: [f64; 2],
    /// Hidden units of the network form. Default 16.
    pub ann_hidden: usize,
    /// Sample visits the network's training makes (whole passes over the
    /// samples, 5 to 400 of them). Default 2,000,000.
    pub ann_samples: usize,
}

impl FitParams {
    pub const DEFAULT: FitParams = FitParams {
        folds: 5,
        seed: 2011,
        ridge: 1e-3,
        logistic_l2: 1.0,
        newton_iterations: 30,
        mu1_range: [0.01, 100.0],
        ann_hidden: 16,
        ann_samples: 2_000_000,
    };
}

impl Default for FitParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why a fit cannot be made.
#[derive(Debug, Error, PartialEq)]
pub enum FitError {
    #[error("{found} samples are too few for the {form} form (at least {needed})")]
    TooFew {
        form: &'static str,
        found: usize,
        needed: usize,
    },
    #[error("the least-squares system of {what} is singular")]
    Singular { what: &'static str },
    #[error("sample {index} has a coordinate that is not finite")]
    NotFinite { index: usize },
    #[error("sample {index}: {msg}")]
    BadSample { index: usize, msg: String },
    #[error("{folds} folds for {samples} samples: held-out figures take 2 to {max} folds, and no more than the samples (0 skips them)", max = MAX_FOLDS)]
    Folds { folds: usize, samples: usize },
    #[error("the {form} fit gave coefficients that are not finite")]
    Diverged { form: &'static str },
    #[error("{0}")]
    Corrections(String),
}

/// The most folds of the held-out figures (each fold is a full fit).
pub const MAX_FOLDS: usize = 100;

/// Checks a fold count against the samples: 0 or 1 (no held-out figures)
/// or 2 to [`MAX_FOLDS`], and no more than the samples.
pub fn check_folds(folds: usize, samples: usize) -> Result<(), FitError> {
    if folds >= 2 && (folds > MAX_FOLDS || folds > samples) {
        return Err(FitError::Folds { folds, samples });
    }
    Ok(())
}

/// Checks a set before a fit: 5, 7, 9 or 11 input points and every sample
/// well formed ([`crate::samples::sample_problem`]: `N` leading points a
/// side, coordinates finite and in range), samples numbered from 1.
pub fn check_set(set: &TrainingSet) -> Result<(), FitError> {
    if !matches!(set.points, 5 | 7 | 9 | 11) {
        return Err(FitError::BadSample {
            index: 0,
            msg: format!("{} input points (5, 7, 9 or 11)", set.points),
        });
    }
    for (index, s) in set.samples.iter().enumerate() {
        let finite = s.input.thesis_order().iter().all(|p| p.is_finite()) && s.pn.is_finite();
        if !finite {
            return Err(FitError::NotFinite { index: index + 1 });
        }
        if let Some(msg) = crate::samples::sample_problem(s, set.points) {
            return Err(FitError::BadSample {
                index: index + 1,
                msg,
            });
        }
    }
    Ok(())
}

/// Samples as the fitting code reads them.
#[derive(Clone, Debug)]
pub struct Data {
    pub n: usize,
    pub inputs: Vec<LeadingPoints>,
    pub types: Vec<u8>,
    pub pn: Vec<Point>,
}

impl Data {
    /// The samples of a set, each checked ([`crate::samples::sample_problem`]:
    /// `N` leading points a side, coordinates finite and in range), so that
    /// no fit is made of a malformed sample.
    pub fn of(set: &TrainingSet) -> Result<Data, FitError> {
        check_set(set)?;
        Ok(Data {
            n: set.n(),
            inputs: set.samples.iter().map(|s| s.input.clone()).collect(),
            types: set
                .samples
                .iter()
                .map(|s| s.element_type.number())
                .collect(),
            pn: set.samples.iter().map(|s| s.pn).collect(),
        })
    }

    pub fn len(&self) -> usize {
        self.types.len()
    }

    pub fn is_empty(&self) -> bool {
        self.types.is_empty()
    }

    fn subset(&self, idx: &[usize]) -> Data {
        Data {
            n: self.n,
            inputs: idx.iter().map(|&i| self.inputs[i].clone()).collect(),
            types: idx.iter().map(|&i| self.types[i]).collect(),
            pn: idx.iter().map(|&i| self.pn[i]).collect(),
        }
    }
}

/// Fits the coefficients of `form` to `data`.
pub fn fit_coefficients(
    data: &Data,
    form: Form,
    params: &FitParams,
) -> Result<Coefficients, FitError> {
    let c = match form {
        Form::Thesis => thesis::fit(data, params).map(Coefficients::Thesis)?,
        Form::Quadratic => quadratic::fit(data, params).map(Coefficients::Quadratic)?,
        Form::Ann => ann::fit(data, params).map(Coefficients::Ann)?,
    };
    if !c.all_finite() {
        return Err(FitError::Diverged { form: form.name() });
    }
    Ok(c)
}

/// Predictions on `data` by `f` (type value and prediction): type value,
/// type, Pn.
fn predictions(
    data: &Data,
    f: impl Fn(&LeadingPoints) -> (f64, crate::model::Prediction),
) -> (Vec<f64>, Vec<u8>, Vec<Point>) {
    let mut value = Vec::with_capacity(data.len());
    let mut types = Vec::with_capacity(data.len());
    let mut pn = Vec::with_capacity(data.len());
    for lp in &data.inputs {
        let (v, p) = f(lp);
        value.push(v);
        types.push(p.element_type.number());
        pn.push(p.pn);
    }
    (value, types, pn)
}

/// Predictions of `coef` on `data`: type value, type, Pn.
fn predict_all(coef: &Coefficients, data: &Data) -> (Vec<f64>, Vec<u8>, Vec<Point>) {
    predictions(data, |lp| coef.predict_with_value(lp))
}

/// The figures of predictions against the samples.
fn figures(
    data: &Data,
    value: &[f64],
    types: &[u8],
    pn: &[Point],
) -> (TypeFigures, Figures, Figures) {
    let col = |v: &[Point], x: bool| -> Vec<f64> {
        v.iter().map(|p| if x { p.x } else { p.y }).collect()
    };
    (
        TypeFigures::of(&data.types, value, types),
        Figures::of(&col(&data.pn, true), &col(pn, true)),
        Figures::of(&col(&data.pn, false), &col(pn, false)),
    )
}

/// A deterministic shuffle (splitmix64 + Fisher–Yates).
fn shuffled(n: usize, seed: u64) -> Vec<usize> {
    let mut g = crate::rng::SplitMix64::new(seed);
    let mut idx: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        let j = (g.next_u64() % (i as u64 + 1)) as usize;
        idx.swap(i, j);
    }
    idx
}

/// `m` pseudo-random normalised inputs with `n` leading points per side:
/// left points in `[−1, 1] × [0, 2]`, right points beyond P_r1 in
/// `[1, 3] × [−1, 1]` (for the tests of the fitting code).
#[cfg(test)]
pub(crate) fn random_inputs(n: usize, m: usize, seed: u64) -> Vec<LeadingPoints> {
    let mut g = crate::rng::SplitMix64::new(seed);
    let mut r = || g.unit() * 2.0 - 1.0;
    (0..m)
        .map(|_| {
            let left = (0..n).map(|_| Point::new(r(), r() + 1.0)).collect();
            let mut right = vec![Point::X];
            right.extend((1..n).map(|_| Point::new(r() + 2.0, r())));
            LeadingPoints { left, right }
        })
        .collect()
}

/// Fits `form` to `set` and measures it: figures on the training samples
/// and, pooled over `params.folds` folds, on held-out samples.
pub fn fit_with_report(
    set: &TrainingSet,
    form: Form,
    params: &FitParams,
) -> Result<(Coefficients, FitReport), FitError> {
    let data = Data::of(set)?;
    check_folds(params.folds, data.len())?;
    let coef = fit_coefficients(&data, form, params)?;
    let (v, t, p) = predict_all(&coef, &data);
    let train = figures(&data, &v, &t, &p);
    let folds = params.folds;
    let holdout = if folds >= 2 {
        let order = shuffled(data.len(), params.seed);
        let mut v = vec![0.0; data.len()];
        let mut t = vec![0u8; data.len()];
        let mut p = vec![Point::ZERO; data.len()];
        for f in 0..folds {
            let test: Vec<usize> = order.iter().copied().skip(f).step_by(folds).collect();
            let test_set: BTreeSet<usize> = test.iter().copied().collect();
            let train_idx: Vec<usize> = (0..data.len()).filter(|i| !test_set.contains(i)).collect();
            let c = fit_coefficients(&data.subset(&train_idx), form, params)?;
            let (fv, ft, fp) = predict_all(&c, &data.subset(&test));
            for (k, &i) in test.iter().enumerate() {
                v[i] = fv[k];
                t[i] = ft[k];
                p[i] = fp[k];
            }
        }
        figures(&data, &v, &t, &p)
    } else {
        train
    };
    let report = FitReport {
        form,
        points: set.points,
        samples: data.len(),
        folds,
        seed: params.seed,
        type_: Split {
            train: train.0,
            holdout: holdout.0,
        },
        xn: Split {
            train: train.1,
            holdout: holdout.1,
        },
        yn: Split {
            train: train.2,
            holdout: holdout.2,
        },
    };
    Ok((coef, report))
}

/// How well any model (fitted, rules, the thesis preset) predicts a
/// training set: type (its value is the predicted type number), Xn, Yn.
pub fn evaluate(
    model: &dyn crate::model::Model,
    set: &TrainingSet,
) -> Result<(TypeFigures, Figures, Figures), FitError> {
    Ok(evaluate_all(model, set)?.figures)
}

/// A model's output on every sample of a set beside the sample's own: what
/// the fit plots draw (thesis Tables 5–8 plot both against the sample
/// index).
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// The samples' types and Pn.
    pub types: Vec<u8>,
    pub pn: Vec<Point>,
    /// The model's.
    pub predicted_types: Vec<u8>,
    pub predicted_pn: Vec<Point>,
    /// Type, Xn and Yn figures, as [`evaluate`] gives them.
    pub figures: (TypeFigures, Figures, Figures),
}

/// [`evaluate`] with the predictions kept.
pub fn evaluate_all(
    model: &dyn crate::model::Model,
    set: &TrainingSet,
) -> Result<Evaluation, FitError> {
    let data = Data::of(set)?;
    let (value, types, pn) = predictions(&data, |lp| {
        let p = model.predict(lp);
        (p.element_type.number() as f64, p)
    });
    let figures = figures(&data, &value, &types, &pn);
    Ok(Evaluation {
        types: data.types,
        pn: data.pn,
        predicted_types: types,
        predicted_pn: pn,
        figures,
    })
}

/// What a training set holds, for a model file.
pub fn summary(set: &TrainingSet) -> TrainingSummary {
    let sources: BTreeSet<String> = set
        .samples
        .iter()
        .map(|s| match &s.source {
            Source::Mesh { file, .. } => file.clone(),
            Source::Correction => "correction".into(),
        })
        .collect();
    TrainingSummary {
        samples: set.len(),
        types: set.type_counts(),
        sources: sources.into_iter().collect(),
        corrections: 0,
    }
}

/// Fits `form` (or, with `None`, every form, keeping the best held-out
/// score) and returns the model file with its figures.
pub fn fit_model(
    set: &TrainingSet,
    form: Option<Form>,
    name: &str,
    params: &FitParams,
) -> Result<(ModelFile, Vec<FitReport>), FitError> {
    let forms: Vec<Form> = form.map_or(Form::ALL.to_vec(), |f| vec![f]);
    let mut best: Option<(Coefficients, FitReport)> = None;
    let mut reports = Vec::new();
    for f in forms {
        let (c, r) = fit_with_report(set, f, params)?;
        reports.push(r.clone());
        if best.as_ref().is_none_or(|(_, b)| r.score() > b.score()) {
            best = Some((c, r));
        }
    }
    let (coef, report) = best.ok_or(FitError::TooFew {
        form: "any",
        found: 0,
        needed: 1,
    })?;
    Ok((
        ModelFile::new(name, coef, summary(set), Some(report)),
        reports,
    ))
}

/// Fits `form` (or every form, as [`fit_model`]) to `set` and layers
/// `corrections` over it ([`CorrectionMemory`] with `radius`): the
/// corrections do not enter the global fit, so that the global model is
/// the fit of `set` alone and a correction reaches no farther than its
/// radius. The model file's training summary counts both.
pub fn fit_with_corrections(
    set: &TrainingSet,
    corrections: &TrainingSet,
    form: Option<Form>,
    name: &str,
    params: &FitParams,
    radius: f64,
) -> Result<(ModelFile, Vec<FitReport>), FitError> {
    let memory = correction_memory(set.points, corrections, radius)?;
    let (file, reports) = fit_model(set, form, name, params)?;
    Ok((with_memory(file, memory), reports))
}

/// The [`CorrectionMemory`] of `corrections` over a model of `points`
/// input points, or why they cannot be layered over it: checked before a
/// global fit is made, which takes seconds.
pub fn correction_memory(
    points: usize,
    corrections: &TrainingSet,
    radius: f64,
) -> Result<CorrectionMemory, FitError> {
    if corrections.points != points && !corrections.is_empty() {
        return Err(FitError::BadSample {
            index: 0,
            msg: format!(
                "the corrections have {} input points, the samples {}",
                corrections.points, points
            ),
        });
    }
    let memory = CorrectionMemory::new(radius, corrections.samples.clone());
    if let Some(msg) = memory.problem(points.saturating_sub(1) / 2) {
        return Err(FitError::Corrections(msg));
    }
    Ok(memory)
}

/// `file`, a global fit, with the corrections of `memory` layered over it
/// ([`correction_memory`]), counted in its training summary.
pub fn with_memory(mut file: ModelFile, memory: CorrectionMemory) -> ModelFile {
    file.training.corrections = memory.len();
    file.with_corrections(memory)
}

/// A refit as the editor makes it: the global form fitted on `base` (the
/// shipped model's training set, [`crate::reference::training_set`]) plus
/// the `added` samples taken from meshes, with the added corrections (the
/// samples of the user's own elements, [`Source::Correction`]) layered
/// over it by [`fit_with_corrections`]. With nothing added, at the shipped
/// model's points and form, this is how the shipped model is made
/// ([`crate::reference::default_model`]), so it gives the same
/// coefficients.
pub fn refit(
    base: &TrainingSet,
    added: &TrainingSet,
    form: Form,
    name: &str,
    params: &FitParams,
) -> Result<ModelFile, FitError> {
    let (corrections, from_meshes) = split_added(added);
    let memory = correction_memory(
        base.points,
        &corrections,
        crate::model::memory::DEFAULT_RADIUS,
    )?;
    let global = refit_global(base, &from_meshes, form, name, params)?;
    Ok(with_memory(global, memory))
}

/// The samples of `added` in two sets: the user's own elements
/// ([`Source::Correction`]), and those taken from meshes.
pub fn split_added(added: &TrainingSet) -> (TrainingSet, TrainingSet) {
    let (corrections, from_meshes): (Vec<_>, Vec<_>) = added
        .samples
        .iter()
        .cloned()
        .partition(|s| s.source == Source::Correction);
    let set = |samples| TrainingSet {
        points: added.points,
        samples,
    };
    (set(corrections), set(from_meshes))
}

/// The global part of [`refit`]: `form` fitted on `base` plus the samples
/// `from_meshes` (duplicates dropped), with no corrections. It depends on
/// nothing else, so a caller may keep it for the next refit that adds no
/// sample from a mesh.
pub fn refit_global(
    base: &TrainingSet,
    from_meshes: &TrainingSet,
    form: Form,
    name: &str,
    params: &FitParams,
) -> Result<ModelFile, FitError> {
    let mut set = base.clone();
    if !from_meshes.is_empty() {
        set.samples.extend(from_meshes.samples.iter().cloned());
        set.dedup();
    }
    Ok(fit_model(&set, Some(form), name, params)?.0)
}

/// Least squares `min |X w − y|` by SVD.
pub(crate) fn lstsq(
    x: &nalgebra::DMatrix<f64>,
    y: &nalgebra::DVector<f64>,
    what: &'static str,
) -> Result<nalgebra::DVector<f64>, FitError> {
    let svd = x.clone().svd(true, true);
    svd.solve(y, 1e-12).map_err(|_| FitError::Singular { what })
}

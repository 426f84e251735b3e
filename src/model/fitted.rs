//! Fitted regression models (method §4; thesis §4.3) and their versioned
//! JSON file.
//!
//! Two forms:
//!
//! - [`ThesisForm`]: the thesis's three models (a logistic-sum type score
//!   over P_l2, P_l1, P_r2 thresholded at 0.75 and 1.5; Xn and Yn as a cubic
//!   and square in P_l1 plus a linear term in every leading point),
//!   generalised from 7 to any `2N + 1` input points;
//! - [`QuadraticForm`]: a richer form. The type is a multinomial logistic
//!   classifier and Pn a ridge-regularised quadratic, one per type, both
//!   over all leading coordinates (standardised), with every product of
//!   two of them;
//! - [`AnnForm`]: the comparison system of thesis §2.2.2 (Yao & Zeng: a
//!   back-propagation network with the same inputs and outputs): one
//!   hidden layer of tanh units over the standardised leading coordinates,
//!   three type scores (softmax) and Pn.
//!
//! The fitting itself is in [`crate::fit`].

use super::figures::FitReport;
use super::memory::CorrectionMemory;
use super::sample::variable_points;
use super::{ElementType, Model, Prediction};
use crate::geom::Point;
use crate::normalize::LeadingPoints;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The model forms `quadex fit` knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Form {
    /// The thesis's forms (§4.3.1).
    Thesis,
    /// Multinomial logistic type and per-type ridge quadratic Pn.
    Quadratic,
    /// A back-propagation network (Yao & Zeng).
    Ann,
}

impl Form {
    pub const ALL: [Form; 3] = [Form::Thesis, Form::Quadratic, Form::Ann];

    pub fn name(self) -> &'static str {
        match self {
            Form::Thesis => "thesis",
            Form::Quadratic => "quadratic",
            Form::Ann => "ann",
        }
    }

    pub fn parse(s: &str) -> Option<Form> {
        Form::ALL.into_iter().find(|f| f.name() == s)
    }
}

/// The logistic function.
#[inline]
pub fn sigmoid(v: f64) -> f64 {
    1.0 / (1.0 + (-v).exp())
}

/// The points the thesis's type model reads: P_l2, P_l1, P_r2.
fn type_points(lp: &LeadingPoints) -> [Point; 3] {
    [lp.left[1], lp.left[0], lp.right[1]]
}

/// Features of the thesis's type model for a given μ1:
/// `σ(μ1 X_i), σ(μ1 Y_i)` for i = l2, l1, r2 (the coefficients are
/// `λ_i, γ_i` interleaved).
pub fn thesis_type_features(lp: &LeadingPoints, mu1: f64) -> [f64; 6] {
    let p = type_points(lp);
    let s = |v: f64| sigmoid(mu1 * v);
    [
        s(p[0].x),
        s(p[0].y),
        s(p[1].x),
        s(p[1].y),
        s(p[2].x),
        s(p[2].y),
    ]
}

/// Features of the thesis's Xn / Yn model: `1, X_l1³, Y_l1³, X_l1², Y_l1²`,
/// then `X_i, Y_i` for every leading point but P0 and P_r1 (thesis order
/// `l_N..l1, r2..r_N`).
pub fn thesis_coord_features(lp: &LeadingPoints) -> Vec<f64> {
    let l1 = lp.left[0];
    let mut f = vec![1.0, l1.x.powi(3), l1.y.powi(3), l1.x.powi(2), l1.y.powi(2)];
    for p in variable_points(lp) {
        f.push(p.x);
        f.push(p.y);
    }
    f
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The type from the thesis's score P: 0 if P ≤ 0.75, 1 if P ≤ 1.5, else 2.
pub fn type_of_score(p: f64) -> ElementType {
    if p <= 0.75 {
        ElementType::New
    } else if p <= 1.5 {
        ElementType::Right
    } else {
        ElementType::Left
    }
}

/// Coefficients of the thesis's forms for `2N + 1` input points.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ThesisForm {
    /// `N`, leading points per side.
    pub n: usize,
    pub mu0: f64,
    pub mu1: f64,
    /// `λ_i, γ_i` interleaved for P_l2, P_l1, P_r2.
    pub type_coef: [f64; 6],
    /// Xn: `λ0..λ4`, then `ε_i, τ_i` interleaved (see
    /// [`thesis_coord_features`]).
    pub xn: Vec<f64>,
    /// Yn: `η0..η4`, then `χ_i, φ_i` interleaved.
    pub yn: Vec<f64>,
}

impl ThesisForm {
    /// The type score P.
    pub fn type_score(&self, lp: &LeadingPoints) -> f64 {
        self.mu0 + dot(&self.type_coef, &thesis_type_features(lp, self.mu1))
    }

    /// Xn and Yn.
    pub fn position(&self, lp: &LeadingPoints) -> Point {
        let f = thesis_coord_features(lp);
        Point::new(dot(&self.xn, &f), dot(&self.yn, &f))
    }

    /// The prediction and the type score P it came from.
    pub fn predict_with_score(&self, lp: &LeadingPoints) -> (f64, Prediction) {
        let p = self.type_score(lp);
        let pred = Prediction {
            element_type: type_of_score(p),
            pn: self.position(lp),
        };
        (p, pred)
    }

    pub fn predict(&self, lp: &LeadingPoints) -> Prediction {
        self.predict_with_score(lp).1
    }
}

/// Number of quadratic features over `m` standardised inputs.
pub fn quadratic_len(m: usize) -> usize {
    1 + m + m * (m + 1) / 2
}

/// Quadratic features `1, z_i, z_i z_j (i ≤ j)` of standardised inputs,
/// written into `out` (cleared first).
pub fn quadratic_features_into(z: &[f64], out: &mut Vec<f64>) {
    out.clear();
    out.push(1.0);
    out.extend_from_slice(z);
    for i in 0..z.len() {
        for j in i..z.len() {
            out.push(z[i] * z[j]);
        }
    }
}

/// The raw inputs of the quadratic form: the coordinates of every leading
/// point but P0 and P_r1, thesis order.
pub fn raw_inputs(lp: &LeadingPoints) -> Vec<f64> {
    variable_points(lp)
        .into_iter()
        .flat_map(|p| [p.x, p.y])
        .collect()
}

/// The raw inputs of `lp` clamped to `[lo, hi]` and standardised:
/// `z = (clamp(x) − mean) / scale`.
fn standardised(
    lp: &LeadingPoints,
    mean: &[f64],
    scale: &[f64],
    lo: &[f64],
    hi: &[f64],
) -> Vec<f64> {
    raw_inputs(lp)
        .iter()
        .enumerate()
        .map(|(k, x)| (x.clamp(lo[k], hi[k]) - mean[k]) / scale[k])
        .collect()
}

/// Coefficients of the quadratic form.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct QuadraticForm {
    /// `N`, leading points per side.
    pub n: usize,
    /// Standardisation of the raw inputs: `z = (clamp(x) − mean) / scale`.
    pub mean: Vec<f64>,
    pub scale: Vec<f64>,
    /// The range of each raw input in the training samples: inputs are
    /// clamped to it, so the quadratic never extrapolates past the data.
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    /// Logits of types 1 and 2 against type 0 (whose logit is 0).
    pub type_logit: [Vec<f64>; 2],
    /// Xn, one quadratic per type.
    pub xn: [Vec<f64>; 3],
    /// Yn, one quadratic per type.
    pub yn: [Vec<f64>; 3],
}

impl QuadraticForm {
    /// The quadratic features of `lp`.
    pub fn features(&self, lp: &LeadingPoints) -> Vec<f64> {
        let z = standardised(lp, &self.mean, &self.scale, &self.lo, &self.hi);
        let mut f = Vec::with_capacity(quadratic_len(z.len()));
        quadratic_features_into(&z, &mut f);
        f
    }

    /// Type probabilities from features.
    pub fn probabilities(&self, f: &[f64]) -> [f64; 3] {
        softmax(dot(&self.type_logit[0], f), dot(&self.type_logit[1], f))
    }

    /// The type and Pn from features.
    pub fn predict_features(&self, f: &[f64]) -> (ElementType, [f64; 3], Point) {
        let p = self.probabilities(f);
        let k = (0..3).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap_or(0);
        let t = ElementType::from_number(k as u8).unwrap_or(ElementType::New);
        (t, p, Point::new(dot(&self.xn[k], f), dot(&self.yn[k], f)))
    }

    pub fn predict(&self, lp: &LeadingPoints) -> Prediction {
        let (element_type, _, pn) = self.predict_features(&self.features(lp));
        Prediction { element_type, pn }
    }
}

/// Softmax of logits `(0, a, b)`.
pub fn softmax(a: f64, b: f64) -> [f64; 3] {
    let m = a.max(b).max(0.0);
    let e = [(-m).exp(), (a - m).exp(), (b - m).exp()];
    let s = e[0] + e[1] + e[2];
    [e[0] / s, e[1] / s, e[2] / s]
}

/// Weights of the network form: `hidden` tanh units over the standardised
/// raw inputs ([`raw_inputs`]), then five linear outputs: the scores of
/// types 0, 1, 2 (softmax) and the standardised Xn, Yn.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AnnForm {
    /// `N`, leading points per side.
    pub n: usize,
    /// Standardisation of the raw inputs, as [`QuadraticForm`]'s.
    pub mean: Vec<f64>,
    pub scale: Vec<f64>,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    pub hidden: usize,
    /// Hidden layer, row by row: `hidden × (inputs + 1)`, the bias last.
    pub w1: Vec<f64>,
    /// Output layer, row by row: `5 × (hidden + 1)`, the bias last.
    pub w2: Vec<f64>,
    /// Xn, Yn = output × scale + mean.
    pub pn_mean: [f64; 2],
    pub pn_scale: [f64; 2],
}

/// Outputs of the network form.
pub const ANN_OUTPUTS: usize = 5;

impl AnnForm {
    /// The standardised inputs of `lp`.
    pub fn inputs(&self, lp: &LeadingPoints) -> Vec<f64> {
        standardised(lp, &self.mean, &self.scale, &self.lo, &self.hi)
    }

    /// The hidden activations and the raw outputs for standardised inputs.
    pub fn forward(&self, z: &[f64], h: &mut Vec<f64>) -> [f64; ANN_OUTPUTS] {
        let m = z.len();
        h.clear();
        for j in 0..self.hidden {
            let row = &self.w1[j * (m + 1)..(j + 1) * (m + 1)];
            h.push((dot(&row[..m], z) + row[m]).tanh());
        }
        let mut o = [0.0; ANN_OUTPUTS];
        for (k, out) in o.iter_mut().enumerate() {
            let row = &self.w2[k * (self.hidden + 1)..(k + 1) * (self.hidden + 1)];
            *out = dot(&row[..self.hidden], h) + row[self.hidden];
        }
        o
    }

    /// Type probabilities, type and Pn.
    pub fn predict_full(&self, lp: &LeadingPoints) -> ([f64; 3], ElementType, Point) {
        let mut h = Vec::with_capacity(self.hidden);
        let o = self.forward(&self.inputs(lp), &mut h);
        let p = softmax(o[1] - o[0], o[2] - o[0]);
        let k = (0..3).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap_or(0);
        let t = ElementType::from_number(k as u8).unwrap_or(ElementType::New);
        let pn = Point::new(
            o[3] * self.pn_scale[0] + self.pn_mean[0],
            o[4] * self.pn_scale[1] + self.pn_mean[1],
        );
        (p, t, pn)
    }

    pub fn predict(&self, lp: &LeadingPoints) -> Prediction {
        let (_, element_type, pn) = self.predict_full(lp);
        Prediction { element_type, pn }
    }
}

/// The coefficients of a fitted model, by form.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "form", rename_all = "lowercase")]
pub enum Coefficients {
    Thesis(ThesisForm),
    Quadratic(QuadraticForm),
    Ann(AnnForm),
}

impl Coefficients {
    /// True when every coefficient is finite.
    pub fn all_finite(&self) -> bool {
        let ok = |v: &[f64]| v.iter().all(|x| x.is_finite());
        match self {
            Coefficients::Thesis(t) => {
                ok(&[t.mu0, t.mu1]) && ok(&t.type_coef) && ok(&t.xn) && ok(&t.yn)
            }
            Coefficients::Quadratic(q) => {
                ok(&q.mean)
                    && ok(&q.scale)
                    && ok(&q.lo)
                    && ok(&q.hi)
                    && q.type_logit.iter().all(|v| ok(v))
                    && q.xn.iter().chain(&q.yn).all(|v| ok(v))
            }
            Coefficients::Ann(a) => {
                ok(&a.mean)
                    && ok(&a.scale)
                    && ok(&a.lo)
                    && ok(&a.hi)
                    && ok(&a.w1)
                    && ok(&a.w2)
                    && ok(&a.pn_mean)
                    && ok(&a.pn_scale)
            }
        }
    }

    pub fn form(&self) -> Form {
        match self {
            Coefficients::Thesis(_) => Form::Thesis,
            Coefficients::Quadratic(_) => Form::Quadratic,
            Coefficients::Ann(_) => Form::Ann,
        }
    }

    /// `N`, leading points per side.
    pub fn n(&self) -> usize {
        match self {
            Coefficients::Thesis(t) => t.n,
            Coefficients::Quadratic(q) => q.n,
            Coefficients::Ann(a) => a.n,
        }
    }

    pub fn predict(&self, lp: &LeadingPoints) -> Prediction {
        match self {
            Coefficients::Thesis(t) => t.predict(lp),
            Coefficients::Quadratic(q) => q.predict(lp),
            Coefficients::Ann(a) => a.predict(lp),
        }
    }

    /// The prediction with the raw type output the fit figures use: the
    /// thesis's score P, or the expected type number under the classifier's
    /// probabilities (each computed once).
    pub fn predict_with_value(&self, lp: &LeadingPoints) -> (f64, Prediction) {
        match self {
            Coefficients::Thesis(t) => t.predict_with_score(lp),
            Coefficients::Quadratic(q) => {
                let (element_type, p, pn) = q.predict_features(&q.features(lp));
                (p[1] + 2.0 * p[2], Prediction { element_type, pn })
            }
            Coefficients::Ann(a) => {
                let (p, element_type, pn) = a.predict_full(lp);
                (p[1] + 2.0 * p[2], Prediction { element_type, pn })
            }
        }
    }
}

/// What a model was trained on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TrainingSummary {
    pub samples: usize,
    /// Samples of type 0, 1, 2.
    pub types: [usize; 3],
    /// The meshes the samples came from (sorted), and "correction".
    pub sources: Vec<String>,
    /// Corrections layered over the fit (not among `samples`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub corrections: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// A fitted model as a [`Model`]: the global form's coefficients, with the
/// user's corrections layered over them ([`CorrectionMemory`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FittedModel {
    pub name: String,
    pub coefficients: Coefficients,
    #[serde(default, skip_serializing_if = "CorrectionMemory::is_empty")]
    pub memory: CorrectionMemory,
}

impl FittedModel {
    /// A model of the global form alone (no corrections).
    pub fn global(name: &str, coefficients: Coefficients) -> FittedModel {
        FittedModel {
            name: name.into(),
            coefficients,
            memory: CorrectionMemory::default(),
        }
    }

    /// The global form's prediction, without the corrections.
    pub fn predict_global(&self, input: &LeadingPoints) -> Prediction {
        self.coefficients.predict(input)
    }
}

impl Model for FittedModel {
    fn name(&self) -> &str {
        &self.name
    }

    fn leading_points(&self) -> Option<usize> {
        Some(self.coefficients.n())
    }

    fn predict(&self, input: &LeadingPoints) -> Prediction {
        self.memory.apply(input, self.coefficients.predict(input))
    }
}

/// The file format's name and the newest version this quadex reads: 1 for
/// a global model alone, 2 for one that carries corrections (an older
/// reader refuses it rather than meshing without them).
pub const MODEL_FORMAT: &str = "quadex-model";
pub const MODEL_VERSION: u32 = 2;

/// A model file: versioned JSON with the coefficients, what they were
/// trained on and how well they fit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ModelFile {
    pub format: String,
    pub version: u32,
    pub name: String,
    /// Input points, `2N + 1`.
    pub points: usize,
    pub coefficients: Coefficients,
    pub training: TrainingSummary,
    pub figures: Option<FitReport>,
    /// The user's corrections, layered over the coefficients.
    #[serde(default, skip_serializing_if = "CorrectionMemory::is_empty")]
    pub corrections: CorrectionMemory,
}

/// A model file that cannot be used.
#[derive(Debug, Error)]
pub enum ModelFileError {
    #[error("not a quadex model file: {0}")]
    Json(String),
    #[error("format {found:?} is not {MODEL_FORMAT:?}")]
    Format { found: String },
    #[error("version {found} is newer than this quadex reads ({MODEL_VERSION})")]
    Version { found: u32 },
    #[error("{points} input points do not match the coefficients ({n} per side)")]
    Points { points: usize, n: usize },
    #[error("coefficient vector {what} has length {found}, expected {expected}")]
    Length {
        what: &'static str,
        found: usize,
        expected: usize,
    },
    #[error("coefficient {what} is not finite")]
    NotFinite { what: &'static str },
    #[error("{0}")]
    Corrections(String),
}

// The cause as text (escaped, one line), not a `source`.
impl From<serde_json::Error> for ModelFileError {
    fn from(e: serde_json::Error) -> Self {
        ModelFileError::Json(crate::io::quote_long(&e.to_string()))
    }
}

impl ModelFile {
    pub fn new(
        name: &str,
        coefficients: Coefficients,
        training: TrainingSummary,
        figures: Option<FitReport>,
    ) -> ModelFile {
        ModelFile {
            format: MODEL_FORMAT.into(),
            version: 1,
            name: name.into(),
            points: 2 * coefficients.n() + 1,
            coefficients,
            training,
            figures,
            corrections: CorrectionMemory::default(),
        }
    }

    /// The file with `corrections` layered over its coefficients (version
    /// 2 when there are any).
    pub fn with_corrections(mut self, corrections: CorrectionMemory) -> ModelFile {
        self.version = if corrections.is_empty() { 1 } else { 2 };
        self.corrections = corrections;
        self
    }

    /// The file of a model (its name, coefficients and corrections).
    pub fn of_model(
        model: &FittedModel,
        training: TrainingSummary,
        figures: Option<FitReport>,
    ) -> ModelFile {
        ModelFile::new(&model.name, model.coefficients.clone(), training, figures)
            .with_corrections(model.memory.clone())
    }

    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).unwrap_or_default();
        s.push('\n');
        s
    }

    /// Reads and checks a model file.
    pub fn from_json(text: &str) -> Result<ModelFile, ModelFileError> {
        let text = crate::io::normalise_text(text);
        let f: ModelFile = serde_json::from_str(&text)?;
        if f.format != MODEL_FORMAT {
            return Err(ModelFileError::Format {
                found: crate::io::quote(&f.format),
            });
        }
        if f.version > MODEL_VERSION {
            return Err(ModelFileError::Version { found: f.version });
        }
        let n = f.coefficients.n();
        if !(2..=5).contains(&n) || f.points != 2 * n + 1 {
            return Err(ModelFileError::Points {
                points: f.points,
                n,
            });
        }
        f.check_lengths()?;
        if let Some(p) = f.corrections.problem(n) {
            return Err(ModelFileError::Corrections(crate::io::quote_long(&p)));
        }
        Ok(f)
    }

    fn check_lengths(&self) -> Result<(), ModelFileError> {
        let n = self.coefficients.n();
        let len = |what, v: &[f64], expected| {
            if v.len() != expected {
                Err(ModelFileError::Length {
                    what,
                    found: v.len(),
                    expected,
                })
            } else if v.iter().any(|x| !x.is_finite()) {
                Err(ModelFileError::NotFinite { what })
            } else {
                Ok(())
            }
        };
        let m = 2 * (2 * n - 1);
        match &self.coefficients {
            Coefficients::Thesis(t) => {
                len("xn", &t.xn, 5 + m)?;
                len("yn", &t.yn, 5 + m)?;
                len("type", &[t.mu0, t.mu1], 2)?;
                len("type", &t.type_coef, 6)
            }
            Coefficients::Quadratic(q) => {
                let f = quadratic_len(m);
                len("mean", &q.mean, m)?;
                len("scale", &q.scale, m)?;
                len("lo", &q.lo, m)?;
                len("hi", &q.hi, m)?;
                if q.scale.iter().any(|&s| s <= 0.0) || q.lo.iter().zip(&q.hi).any(|(a, b)| a > b) {
                    return Err(ModelFileError::NotFinite {
                        what: "scale/range",
                    });
                }
                for v in &q.type_logit {
                    len("type_logit", v, f)?;
                }
                for v in q.xn.iter().chain(&q.yn) {
                    len("xn/yn", v, f)?;
                }
                Ok(())
            }
            Coefficients::Ann(a) => {
                len("mean", &a.mean, m)?;
                len("scale", &a.scale, m)?;
                len("lo", &a.lo, m)?;
                len("hi", &a.hi, m)?;
                if !(1..=1024).contains(&a.hidden) {
                    return Err(ModelFileError::Length {
                        what: "hidden",
                        found: a.hidden,
                        expected: 16,
                    });
                }
                len("w1", &a.w1, a.hidden * (m + 1))?;
                len("w2", &a.w2, ANN_OUTPUTS * (a.hidden + 1))?;
                len("pn_mean", &a.pn_mean, 2)?;
                len("pn_scale", &a.pn_scale, 2)?;
                if a.scale.iter().chain(&a.pn_scale).any(|&s| s <= 0.0)
                    || a.lo.iter().zip(&a.hi).any(|(l, h)| l > h)
                {
                    return Err(ModelFileError::NotFinite {
                        what: "scale/range",
                    });
                }
                Ok(())
            }
        }
    }

    /// The model to mesh with.
    pub fn model(&self) -> FittedModel {
        FittedModel {
            name: self.name.clone(),
            coefficients: self.coefficients.clone(),
            memory: self.corrections.clone(),
        }
    }
}

//! Element models (method §4): a model maps the normalised leading points
//! of a reference point to `[type, Pn]` (thesis Figure 18):
//!
//! - type 0: a new node Pn; quad (P0, P_r1, Pn, P_l1);
//! - type 1: no new node, Pn = P_r2; quad (P0, P_r1, P_r2, P_l1);
//! - type 2: no new node, Pn = P_l2; quad (P0, P_r1, P_l2, P_l1).
//!
//! Every model sits behind [`Model`], so the mesher, the command line and
//! the editor treat the knowledge-based rules, the thesis's printed
//! regression and fitted models alike.

pub mod figures;
pub mod fitted;
pub mod memory;
pub mod rules;
pub mod sample;
pub mod thesis;

use crate::geom::Point;
use crate::normalize::LeadingPoints;
use serde::{Deserialize, Serialize};

pub use fitted::{FittedModel, Form, ModelFile, ModelFileError};
pub use memory::CorrectionMemory;
pub use rules::RulesModel;
pub use thesis::ThesisModel;

/// The three element types of thesis Figure 18.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum ElementType {
    /// One new node Pn.
    New = 0,
    /// Close onto P_r2.
    Right = 1,
    /// Close onto P_l2.
    Left = 2,
}

impl ElementType {
    pub const ALL: [ElementType; 3] = [ElementType::New, ElementType::Right, ElementType::Left];

    /// The thesis's type number (0, 1 or 2).
    pub fn number(self) -> u8 {
        self as u8
    }

    pub fn from_number(k: u8) -> Option<ElementType> {
        match k {
            0 => Some(ElementType::New),
            1 => Some(ElementType::Right),
            2 => Some(ElementType::Left),
            _ => None,
        }
    }
}

/// A model's output in the normalised frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    pub element_type: ElementType,
    /// Pn in the normalised frame. For types 1 and 2 this is the model's
    /// raw coordinate output; the element uses P_r2 or P_l2.
    pub pn: Point,
}

/// A regression (or rule) model of element extraction.
pub trait Model: Send + Sync {
    /// Short name shown in reports and the editor.
    fn name(&self) -> &str;
    /// The number of leading points per side the model reads (`N`, giving
    /// `2N + 1` input points), or `None` when it works with any `N ≥ 2`.
    fn leading_points(&self) -> Option<usize>;
    /// Predicts the element for normalised leading points.
    fn predict(&self, input: &LeadingPoints) -> Prediction;
}

/// The shipped default model file: the quadratic form fitted to the
/// samples of the reference meshes (see [`crate::reference`]) (`cargo run --example default_model` rebuilds
/// it).
pub const DEFAULT_MODEL_JSON: &str = include_str!("../../assets/models/default.json");

/// The shipped default model.
pub fn default_model() -> Result<FittedModel, ModelFileError> {
    ModelFile::from_json(DEFAULT_MODEL_JSON).map(|f| f.model())
}

/// The shipped network model (the comparison system of thesis §2.2.2,
/// Yao & Zeng's back-propagation network): the network form fitted to the
/// default model's samples (`cargo run --example default_model` rebuilds
/// it).
pub const ANN_MODEL_JSON: &str = include_str!("../../assets/models/ann.json");

/// The file of a shipped fitted model by name (`default`, `ann`).
pub fn shipped_file(name: &str) -> Option<&'static str> {
    match name {
        "default" => Some(DEFAULT_MODEL_JSON),
        "ann" => Some(ANN_MODEL_JSON),
        _ => None,
    }
}

/// The names of the built-in models.
pub const BUILTIN: [&str; 4] = ["default", "rules", "thesis", "ann"];

/// The built-in models by name: `default` (the shipped fitted model),
/// `rules`, `thesis` (Table 8 as printed) or `ann` (the shipped network).
pub fn builtin(name: &str) -> Option<Box<dyn Model>> {
    match name {
        "default" | "ann" => shipped_file(name)
            .and_then(|text| ModelFile::from_json(text).ok())
            .map(|f| Box::new(f.model()) as Box<dyn Model>),
        "rules" => Some(Box::new(RulesModel::default())),
        "thesis" => Some(Box::new(ThesisModel::TABLE_8)),
        _ => None,
    }
}

/// A model that cannot be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("{0}")]
    Io(std::io::Error),
    #[error("{0}")]
    File(ModelFileError),
    #[error("not a model: no such file, and not one of the names {}", BUILTIN.join(", "))]
    Unknown,
}

// Causes are part of the message, not `source`s: printing the error with
// its chain must not repeat them.
impl From<std::io::Error> for LoadError {
    fn from(e: std::io::Error) -> Self {
        LoadError::Io(e)
    }
}
impl From<ModelFileError> for LoadError {
    fn from(e: ModelFileError) -> Self {
        LoadError::File(e)
    }
}

/// A built-in model by name, or a model file by path.
pub fn load(spec: &str) -> Result<Box<dyn Model>, LoadError> {
    if let Some(m) = builtin(spec) {
        return Ok(m);
    }
    let bytes = std::fs::read(spec).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => LoadError::Unknown,
        _ => LoadError::Io(e),
    })?;
    let text = crate::io::decode_text(&bytes);
    Ok(Box::new(ModelFile::from_json(&text)?.model()))
}

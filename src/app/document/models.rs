//! The models a document meshes with: its refitted ones, the built-in
//! ones (loaded once per session) and model files.

use crate::app::error::EditorError;
use crate::io;
use crate::model::{self, ModelFile};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock};

/// What the editor says about the model it meshes with.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelInfo {
    pub name: String,
    /// `quadratic`, `thesis` (fitted), `rules`, `thesis (Table 8)`, …
    pub form: String,
    /// Samples its global part was fitted on (none for rules and presets).
    pub samples: Option<usize>,
    /// Corrections layered over it.
    pub corrections: usize,
}

impl ModelInfo {
    pub(super) fn of_file(f: &ModelFile) -> ModelInfo {
        ModelInfo {
            name: f.name.clone(),
            form: f.coefficients.form().name().into(),
            samples: Some(f.training.samples),
            corrections: f.corrections.len(),
        }
    }
}

/// The model named `spec`: one of the document's refitted `models` by
/// name, a built-in model, or a model file; with what the editor shows of
/// it.
pub fn load_model(
    spec: &str,
    models: &[ModelFile],
) -> Result<(Arc<dyn model::Model>, ModelInfo), EditorError> {
    if let Some(f) = models.iter().find(|f| f.name == spec) {
        return Ok((Arc::new(f.model()), ModelInfo::of_file(f)));
    }
    // A built-in model is loaded once and shared: the same model after an
    // Open or a Reset is the same one (the Model panel measures it once).
    if model::BUILTIN.contains(&spec) {
        if let Some(hit) = BUILTIN_MODELS
            .get_or_init(Default::default)
            .lock()
            .ok()
            .and_then(|c| c.get(spec).cloned())
        {
            return Ok(hit);
        }
    }
    let loaded = load_model_afresh(spec)?;
    if model::BUILTIN.contains(&spec) {
        if let Ok(mut c) = BUILTIN_MODELS.get_or_init(Default::default).lock() {
            c.insert(spec.to_string(), loaded.clone());
        }
    }
    Ok(loaded)
}

/// The built-in models loaded this session, by name.
type LoadedModel = (Arc<dyn model::Model>, ModelInfo);
static BUILTIN_MODELS: OnceLock<Mutex<BTreeMap<String, LoadedModel>>> = OnceLock::new();

/// Loads a built-in model or a model file by name or path.
fn load_model_afresh(spec: &str) -> Result<LoadedModel, EditorError> {
    let failed = |cause| EditorError::Model {
        spec: spec.to_string(),
        cause,
    };
    let file = match spec {
        "default" | "ann" => model::shipped_file(spec).map(ModelFile::from_json),
        "rules" | "thesis" => None,
        path => Some(
            std::fs::read(path)
                .map_err(|e| failed(model::LoadError::Io(e)))
                .map(|b| ModelFile::from_json(&io::decode_text(&b)))?,
        ),
    };
    match file {
        Some(f) => {
            let f = f.map_err(|e| failed(model::LoadError::File(e)))?;
            let info = ModelInfo {
                name: spec.to_string(),
                ..ModelInfo::of_file(&f)
            };
            Ok((Arc::new(f.model()), info))
        }
        None => {
            let m = model::load(spec).map_err(failed)?;
            let info = ModelInfo {
                name: spec.to_string(),
                form: if spec == "rules" {
                    "rules (Zeng & Cheng)".into()
                } else {
                    "thesis (Table 8 as printed)".into()
                },
                samples: None,
                corrections: 0,
            };
            Ok((Arc::from(m), info))
        }
    }
}

//! What refits keep for the whole session, process-wide: the global fits
//! made, and the reference meshes' samples at each count of input points.

use crate::app::error::EditorError;
use crate::fit::{self, FitParams};
use crate::model::{self, Form, ModelFile};
use crate::samples::{SampleKeys, TrainingSet};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock};

/// Global fits made this session, by [`fit_key`].
type FitKey = (usize, &'static str, String, u64);
static FITS: OnceLock<Mutex<BTreeMap<FitKey, ModelFile>>> = OnceLock::new();

/// What a global fit depends on: the input points (which give the
/// reference samples), the form, the parameters and the samples from
/// meshes.
fn fit_key(
    base: &TrainingSet,
    from_meshes: &TrainingSet,
    form: Form,
    params: &FitParams,
) -> FitKey {
    let samples = serde_json::to_string(&from_meshes.samples).unwrap_or_default();
    (
        base.points,
        form.name(),
        format!("{params:?}"),
        fingerprint(&samples),
    )
}

/// The global fit when it is made already: kept from earlier in the
/// session, or a shipped model's own file. With no samples from meshes, a
/// shipped model of that form and input points fitted with these
/// parameters (folds aside) is that fit (the tests
/// `the_shipped_*_model_is_the_fit_of_the_reference_meshes` refit them and
/// compare).
fn cached_or_shipped(
    key: &FitKey,
    from_meshes: &TrainingSet,
    form: Form,
    params: &FitParams,
) -> Option<ModelFile> {
    let fits = FITS.get_or_init(Default::default);
    if let Some(f) = fits.lock().ok().and_then(|c| c.get(key).cloned()) {
        return Some(f);
    }
    let shipped_params = FitParams {
        folds: FitParams::DEFAULT.folds,
        ..*params
    } == FitParams::DEFAULT;
    [model::DEFAULT_MODEL_JSON, model::ANN_MODEL_JSON]
        .into_iter()
        .filter(|_| from_meshes.is_empty() && shipped_params)
        .filter_map(|json| ModelFile::from_json(json).ok())
        .find(|f| f.points == key.0 && f.coefficients.form() == form)
}

/// The global fit of a refit ([`fit::refit_global`]): `form` on the
/// reference samples `base` plus the samples `from_meshes`, kept for the
/// rest of the session, since it depends on nothing else and takes seconds
/// (a refit after each correction adds none from meshes).
pub(super) fn global_fit(
    base: &TrainingSet,
    from_meshes: &TrainingSet,
    form: Form,
    params: &FitParams,
) -> Result<ModelFile, EditorError> {
    let key = fit_key(base, from_meshes, form, params);
    if let Some(f) = cached_or_shipped(&key, from_meshes, form, params) {
        return Ok(f);
    }
    let file = fit::refit_global(base, from_meshes, form, "global", params)?;
    if let Ok(mut c) = FITS.get_or_init(Default::default).lock() {
        c.insert(key, file.clone());
    }
    Ok(file)
}

/// A 64-bit fingerprint of `text` (FNV-1a).
fn fingerprint(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The reference meshes' samples at `points` input points, collected as
/// for the shipped model ([`crate::reference::training_set`]), once per run
/// of the program and shared.
pub fn reference_samples(points: usize) -> Result<Arc<TrainingSet>, EditorError> {
    Ok(reference(points)?.set)
}

/// The reference samples at `points` input points, and their duplicate
/// keys when a refit has needed them, kept for the session.
#[derive(Clone)]
pub(super) struct Reference {
    pub(super) set: Arc<TrainingSet>,
    pub(super) keys: Arc<OnceLock<SampleKeys>>,
}

pub(super) fn reference(points: usize) -> Result<Reference, EditorError> {
    static CACHE: OnceLock<Mutex<BTreeMap<usize, Reference>>> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    if let Some(r) = cache.lock().ok().and_then(|c| c.get(&points).cloned()) {
        return Ok(r);
    }
    let meshes = crate::reference::read_shipped()?;
    let r = Reference {
        set: Arc::new(crate::reference::training_set(&meshes, points)),
        keys: Arc::default(),
    };
    if let Ok(mut c) = cache.lock() {
        c.insert(points, r.clone());
    }
    Ok(r)
}

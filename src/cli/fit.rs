//! `quadex fit`: a model fitted to training sets (and corrections) and
//! written as a model file.

use super::common::{check_output, read_set};
use super::InputError;
use anyhow::{anyhow, Result};
use clap::Args;
use quadex::fit::{self, FitParams};
use quadex::io;
use quadex::model::Form;
use quadex::samples::TrainingSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Args)]
pub(super) struct FitArgs {
    #[arg(required = true)]
    sets: Vec<PathBuf>,
    /// `thesis`, `quadratic` or `ann` (a back-propagation network);
    /// without it, each is fitted and the one with the best held-out
    /// figures is kept.
    #[arg(long)]
    form: Option<String>,
    #[arg(short, long)]
    output: PathBuf,
    /// Write the fit figures as JSON.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Folds of the held-out figures: 2 to 100, and no more than the
    /// samples (0: no held-out figures). Default 5, or the sample count
    /// when smaller.
    #[arg(long)]
    folds: Option<usize>,
    /// The model's name (default: the output file's stem).
    #[arg(long)]
    name: Option<String>,
    /// Corrections (a training set in the same layout: the samples of
    /// elements the user made), layered over the fitted model: each is
    /// reproduced at its input, inputs within --radius move towards
    /// it, the rest is the fit of the samples alone.
    #[arg(long)]
    corrections: Vec<PathBuf>,
    /// How far a correction reaches: the root mean square distance of
    /// the varying leading points, in normalised units.
    #[arg(long, default_value_t = quadex::model::memory::DEFAULT_RADIUS)]
    radius: f64,
}

pub(super) fn run(a: FitArgs) -> Result<()> {
    let FitArgs {
        sets,
        form,
        output,
        report,
        folds,
        name,
        corrections,
        radius,
    } = a;
    let form = match form.as_deref() {
        None => None,
        Some(f) => Some(Form::parse(f).ok_or_else(|| {
            InputError(anyhow!("{f}: unknown form (use thesis, quadratic or ann)"))
        })?),
    };
    check_output(&output)?;
    if let Some(r) = &report {
        check_output(r)?;
    }
    let mut set = read_set(&sets[0])?;
    for path in &sets[1..] {
        set.merge(read_set(path)?)
            .map_err(|e| InputError(anyhow!("{}: {e}", path.display())))?;
    }
    let folds = match folds {
        Some(1) => {
            return Err(InputError(anyhow!(
                "{}: --folds 1: one fold holds nothing out; give 2 to {} (or 0 to skip the held-out figures)",
                sets[0].display(),
                fit::MAX_FOLDS.min(set.len())
            ))
            .into())
        }
        Some(f) => {
            fit::check_folds(f, set.len()).map_err(|e| {
                InputError(anyhow!("{}: --folds: {e}", sets[0].display()))
            })?;
            f
        }
        None if set.len() >= 2 => FitParams::DEFAULT.folds.min(set.len()),
        None => 0,
    };
    let name = name.unwrap_or_else(|| {
        output
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "fitted".into())
    });
    let params = FitParams {
        folds,
        ..FitParams::DEFAULT
    };
    let mut fixes = TrainingSet::new(set.points);
    for path in &corrections {
        fixes
            .merge(read_set(path)?)
            .map_err(|e| InputError(anyhow!("{}: {e}", path.display())))?;
    }
    if !(radius.is_finite() && radius > 0.0) {
        return Err(InputError(anyhow!("--radius {radius}: give a positive number")).into());
    }
    let t0 = Instant::now();
    let (file, reports) = fit::fit_with_corrections(&set, &fixes, form, &name, &params, radius)
        .map_err(|e| {
            let at = corrections
                .first()
                .filter(|_| matches!(e, fit::FitError::Corrections(_)));
            InputError(anyhow!("{}: {e}", at.unwrap_or(&sets[0]).display()))
        })?;
    let seconds = t0.elapsed().as_secs_f64();
    for r in &reports {
        outln!("{}", r.table());
    }
    let json = file.to_json();
    // Never write a model file that `--model` would refuse.
    quadex::model::ModelFile::from_json(&json).map_err(|e| {
        InputError(anyhow!(
            "{}: the fitted model cannot be used: {e}",
            sets[0].display()
        ))
    })?;
    let report_json = match &report {
        Some(_) => {
            // The chosen form's figures at the top (`type`, `xn`,
            // `yn`, each with `train` and `holdout`), every form
            // under `forms`.
            let mut v = serde_json::to_value(&file.figures)?;
            if let Some(obj) = v.as_object_mut() {
                obj.insert("forms".into(), serde_json::to_value(&reports)?);
            }
            Some(serde_json::to_string_pretty(&v)?)
        }
        None => None,
    };
    let mut files: Vec<(&Path, &[u8])> = vec![(&output, json.as_bytes())];
    if let (Some(path), Some(r)) = (&report, &report_json) {
        files.push((path, r.as_bytes()));
    }
    io::write_atomic_all(&files)?;
    outln!(
        "{}: form {}, {} samples{}, {} in {seconds:.2} s",
        output.display(),
        file.coefficients.form().name(),
        set.len(),
        match fixes.len() {
            0 => String::new(),
            k => format!(" and {k} corrections (radius {radius})"),
        },
        if folds >= 2 {
            "fitted and cross-validated"
        } else {
            "fitted"
        }
    );
    Ok(())
}

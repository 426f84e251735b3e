//! `quadex predict`: a model's element for each row of inputs.

use super::common::{check_output, load_model, plural, want_extension};
use super::InputError;
use anyhow::{anyhow, Result};
use clap::Args;
use quadex::io;
use quadex::predict;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct PredictArgs {
    /// `default`, `rules`, `thesis`, `ann` or a model file (.json).
    model: String,
    rows: PathBuf,
    #[arg(short, long)]
    output: PathBuf,
}

pub(super) fn run(a: PredictArgs) -> Result<()> {
    let PredictArgs {
        model,
        rows,
        output,
    } = a;
    check_output(&output)?;
    want_extension(&output, &["csv"])?;
    let m = load_model(&model)?;
    let text = std::fs::read(&rows).map_err(|e| InputError(anyhow!("{}: {e}", rows.display())))?;
    let bad = |e: predict::PredictError| InputError(anyhow!("{}: {e}", rows.display()));
    let (points, inputs) = predict::read_rows(&io::decode_text(&text)).map_err(bad)?;
    let answers = predict::predict_rows(m.as_ref(), points, &inputs).map_err(bad)?;
    io::write_atomic(&output, predict::to_csv(&answers).as_bytes())?;
    outln!(
        "{}: {} predicted by {}",
        output.display(),
        plural(answers.len(), "row"),
        m.name()
    );
    Ok(())
}

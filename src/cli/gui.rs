//! `quadex gui`: the editor (also `quadex` with no subcommand).

use super::args::parse_size;
use super::InputError;
use anyhow::{anyhow, Result};
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct GuiArgs {
    /// Boundary to open (default: the shipped example).
    #[arg(long)]
    open: Option<PathBuf>,
    /// Steps to take after opening.
    #[arg(long, conflicts_with = "run")]
    steps: Option<usize>,
    /// Run to the end after opening.
    #[arg(long)]
    run: bool,
    #[arg(long)]
    screenshot: Option<PathBuf>,
    /// Window size, WIDTHxHEIGHT in points.
    #[arg(long, value_parser = parse_size)]
    size: Option<[f32; 2]>,
    /// The panel shown on the right: model, samples, quality or
    /// smoothing.
    #[arg(long)]
    panel: Option<String>,
}

pub(super) fn run(a: GuiArgs) -> Result<()> {
    launch(quadex::app::GuiOptions {
        open: a.open,
        steps: a.steps,
        run: a.run,
        screenshot: a.screenshot,
        size: a.size,
        panel: a.panel,
    })
}

/// Opens the editor window; a file it cannot open is the user's input.
pub(super) fn launch(o: quadex::app::GuiOptions) -> Result<()> {
    quadex::app::run(o).map_err(|e| InputError(anyhow!("{e}")).into())
}

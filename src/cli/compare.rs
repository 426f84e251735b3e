//! `quadex compare`: one boundary meshed with several models, side by side.

use super::common::{check_output, load_model, read_resampled, want_extension};
use anyhow::Result;
use clap::Args;
use quadex::compare;
use quadex::io;
use quadex::model;
use quadex::pipeline;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub(super) struct CompareArgs {
    input: PathBuf,
    /// Comma-separated: `default`, `rules`, `thesis`, `ann`, model files.
    #[arg(long, value_delimiter = ',', default_value = "default,rules,thesis")]
    models: Vec<String>,
    /// The SVG of the meshes side by side (.svg).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Write the figures as JSON.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Resample the boundary first, as `mesh --resample H` does.
    #[arg(long, value_name = "H")]
    resample: Option<f64>,
}

pub(super) fn run(a: CompareArgs) -> Result<()> {
    let CompareArgs {
        input,
        models,
        output,
        report,
        resample,
    } = a;
    for path in output.iter().chain(&report) {
        check_output(path)?;
    }
    if let Some(path) = &output {
        want_extension(path, &["svg"])?;
    }
    let boundary = read_resampled(&input, resample)?;
    let loaded = models
        .iter()
        .map(|spec| load_model(spec).map(|m| (spec, m)))
        .collect::<Result<Vec<_>>>()?;
    let outcomes: Vec<compare::Outcome> = loaded
        .into_iter()
        .map(|(spec, m)| {
            let name = Path::new(spec)
                .file_stem()
                .filter(|_| model::builtin(spec).is_none())
                .map_or(spec.clone(), |s| s.to_string_lossy().into_owned());
            compare::mesh_with(&name, &boundary, m, &pipeline::Params::DEFAULT)
        })
        .collect();
    out!("{}", compare::table(&outcomes));
    let mut files: Vec<(PathBuf, String)> = Vec::new();
    if let Some(path) = output {
        files.push((path, compare::svg(&outcomes, 400.0)));
    }
    if let Some(path) = report {
        let json = serde_json::to_string_pretty(&serde_json::json!({
            "input": input.display().to_string(),
            "models": outcomes,
        }))?;
        files.push((path, json));
    }
    let refs: Vec<(&Path, &[u8])> = files
        .iter()
        .map(|(p, t)| (p.as_path(), t.as_bytes()))
        .collect();
    io::write_atomic_all(&refs)?;
    Ok(())
}

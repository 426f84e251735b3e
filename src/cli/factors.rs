//! `quadex factors`: the critical factors (the weight of each leading
//! point).

use super::args::parse_points;
use super::common::{check_output, is_mesh, not_written_only, read_mesh, read_set};
use super::InputError;
use anyhow::{anyhow, Result};
use clap::Args;
use quadex::factors;
use quadex::io;
use quadex::samples::{self, CollectParams, TrainingSet};
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct FactorsArgs {
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Input-point counts, comma-separated.
    #[arg(long, default_value = "5,7,9,11", value_delimiter = ',', value_parser = parse_points)]
    points: Vec<usize>,
    /// Write the tables as JSON.
    #[arg(long)]
    report: Option<PathBuf>,
}

pub(super) fn run(a: FactorsArgs) -> Result<()> {
    let FactorsArgs {
        inputs,
        points,
        report,
    } = a;
    if let Some(r) = &report {
        check_output(r)?;
    }
    let mut tables = Vec::new();
    for &pts in &points {
        let mut set = TrainingSet::new(pts);
        for path in &inputs {
            if is_mesh(path) {
                let m = read_mesh(path)?;
                let name = path.display().to_string();
                set.samples.extend(samples::collect(
                    &m,
                    (pts - 1) / 2,
                    &CollectParams::DEFAULT,
                    &name,
                ));
            } else {
                not_written_only(path)?;
                let full = read_set(path)?;
                let cut = factors::truncated(&full, pts).ok_or_else(|| {
                    InputError(anyhow!(
                        "{}: has {} input points, cannot give {pts}",
                        path.display(),
                        full.points
                    ))
                })?;
                set.samples.extend(cut.samples);
            }
        }
        set.dedup();
        let f = factors::factors(&set).map_err(|e| {
            let names: Vec<String> = inputs.iter().map(|p| p.display().to_string()).collect();
            InputError(anyhow!("{}: {pts} points: {e}", names.join(", ")))
        })?;
        outln!("{}", f.table());
        tables.push(f);
    }
    if let Some(path) = report {
        io::write_atomic(&path, serde_json::to_string_pretty(&tables)?.as_bytes())?;
    }
    Ok(())
}

//! `quadex samples`: training samples collected from quad meshes.

use super::args::parse_points;
use super::common::{check_output, read_mesh, want_extension};
use super::InputError;
use anyhow::{anyhow, Result};
use clap::Args;
use quadex::samples::{self, CollectParams, TrainingSet};
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct SamplesArgs {
    #[arg(required = true)]
    meshes: Vec<PathBuf>,
    /// Input points: 5, 7, 9 or 11.
    #[arg(long, default_value_t = 7, value_parser = parse_points)]
    points: usize,
    #[arg(short, long)]
    output: PathBuf,
    /// Keep samples that repeat an earlier one.
    #[arg(long)]
    keep_duplicates: bool,
    /// Window of the front's interior angle along a sample's path, in
    /// degrees: LO,HI (default 35,235, method §3; the shipped model and
    /// the editor's "Collect from this mesh" use 35,300).
    #[arg(
        long,
        value_name = "LO,HI",
        value_delimiter = ',',
        default_values_t = CollectParams::DEFAULT.turn,
        hide_default_value = true
    )]
    turn: Vec<f64>,
}

pub(super) fn run(a: SamplesArgs) -> Result<()> {
    let SamplesArgs {
        meshes,
        points,
        output,
        keep_duplicates,
        turn,
    } = a;
    let [lo, hi] = turn[..] else {
        return Err(InputError(anyhow!("--turn takes two angles, LO,HI")).into());
    };
    want_extension(&output, &["csv", "json"])?;
    if !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo < hi && hi <= 360.0) {
        return Err(InputError(anyhow!(
            "--turn {lo},{hi}: give two angles in degrees with 0 <= LO < HI <= 360"
        ))
        .into());
    }
    check_output(&output)?;
    let params = CollectParams {
        turn: [lo, hi],
        ..CollectParams::DEFAULT
    };
    let mut set = TrainingSet::new(points);
    for path in &meshes {
        let m = read_mesh(path)?;
        let name = path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        let s = samples::collect(&m, (points - 1) / 2, &params, &name);
        outln!("{}: {} samples", path.display(), s.len());
        set.samples.extend(s);
    }
    let dropped = if keep_duplicates { 0 } else { set.dedup() };
    set.write(&output)
        .map_err(|e| anyhow!("{}: {e}", output.display()))?;
    let t = set.type_counts();
    outln!(
        "{}: {} samples ({} types 0/1/2: {}/{}/{}), {} duplicates dropped",
        output.display(),
        set.len(),
        points,
        t[0],
        t[1],
        t[2],
        dropped
    );
    Ok(())
}

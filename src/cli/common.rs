//! What the subcommands share: reading the user's files, refusing bad
//! output paths, the progress bar.

use super::InputError;
use anyhow::{anyhow, Result};
use indicatif::{ProgressBar, ProgressStyle};
use quadex::boundary::Boundary;
use quadex::boundary_edit::Draft;
use quadex::io::{self, MeshFormat};
use quadex::model::{self, Model};
use quadex::samples::TrainingSet;
use std::io::IsTerminal;
use std::path::Path;
use std::sync::Arc;

/// The boundary in `path`, resampled to segments of about `h` when given
/// ([`Draft::resample`], every loop): the file is read as loops, so a file
/// whose node count is odd can be meshed once resampling evens it.
pub(super) fn read_resampled(path: &Path, h: Option<f64>) -> Result<Boundary> {
    let at = |e: &dyn std::fmt::Display| InputError(anyhow!("{}: {e}", path.display()));
    let Some(h) = h else {
        return io::read_boundary(path).map_err(|e| at(&e).into());
    };
    let mut draft = Draft {
        loops: io::read_boundary_loops(path).map_err(|e| at(&e))?,
    };
    for li in 0..draft.loops.len() {
        draft.resample(li, h).map_err(|e| at(&e))?;
    }
    draft.to_boundary().map_err(|e| at(&e).into())
}

/// Refuses an output path whose folder does not exist, before any work.
pub(super) fn check_output(path: &Path) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let refuse = |why: String| -> Result<()> {
        Err(InputError(anyhow!("{}: cannot write there: {why}", path.display())).into())
    };
    if dir.exists() && !dir.is_dir() {
        return refuse(format!("{} is not a folder", dir.display()));
    }
    if !dir.is_dir() {
        return refuse(format!("the folder {} does not exist", dir.display()));
    }
    if path.is_dir() {
        return refuse("it is a folder".to_string());
    }
    // A file made and removed again: a folder that exists but cannot be
    // written (read-only, or a system folder) is found before any work.
    let probe = dir.join(format!(".quadex-probe-{}", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => refuse(format!(
            "the folder {} cannot be written: {e}",
            dir.display()
        )),
    }
}

pub(super) fn load_model(spec: &str) -> Result<Arc<dyn Model>> {
    model::load(spec)
        .map(Arc::from)
        .map_err(|e| InputError(anyhow!("{spec}: {e}")).into())
}

/// Reads a training set, the user's input.
pub(super) fn read_set(path: &Path) -> Result<TrainingSet> {
    TrainingSet::read(path).map_err(|e| InputError(anyhow!("{}: {e}", path.display())).into())
}

/// Reads a quad mesh (.msh), the user's input.
pub(super) fn read_mesh(path: &Path) -> Result<quadex::QuadMesh> {
    not_written_only(path)?;
    Ok(io::read_mesh(path).map_err(|e| InputError(anyhow!("{}: {e}", path.display())))?)
}

/// Refuses an output named with none of the extensions `exts` (the first
/// is what the file holds), so a `.json` is never a CSV.
pub(super) fn want_extension(path: &Path, exts: &[&str]) -> Result<()> {
    let ok = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| exts.iter().any(|x| e.eq_ignore_ascii_case(x)));
    if ok {
        return Ok(());
    }
    let names: Vec<String> = exts.iter().map(|e| format!(".{e}")).collect();
    Err(InputError(anyhow!(
        "{}: written as {}: name the file {}",
        path.display(),
        exts.iter()
            .map(|e| e.to_uppercase())
            .collect::<Vec<_>>()
            .join(" or "),
        names.join(" or ")
    ))
    .into())
}

/// Refuses the mesh formats quadex writes but does not read (.vtk, .vtu,
/// .inp, .svg), naming the one it reads.
pub(super) fn not_written_only(path: &Path) -> Result<()> {
    match MeshFormat::from_path(path) {
        Ok(f @ (MeshFormat::Vtk | MeshFormat::Vtu | MeshFormat::Abaqus | MeshFormat::Svg)) => {
            Err(InputError(anyhow!(
                "{}: .{} is written, not read: meshes are read from Gmsh .msh files (MSH 2.2 or 4.1)",
                path.display(),
                f.extension()
            ))
            .into())
        }
        _ => Ok(()),
    }
}

pub(super) fn is_mesh(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("msh"))
}

/// `n thing(s)`.
pub(super) fn plural(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

pub(super) fn progress_bar(front: usize) -> Option<ProgressBar> {
    if !std::io::stderr().is_terminal() || front < 2000 {
        return None;
    }
    let b = ProgressBar::new_spinner();
    b.set_style(ProgressStyle::with_template("{spinner} meshing: {msg} [{elapsed}]").ok()?);
    Some(b)
}

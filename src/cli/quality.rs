//! `quadex quality`: the quality figures of a mesh file, and optionally
//! the check that it meshes a given boundary.

use super::common::read_mesh;
use super::InputError;
use anyhow::{anyhow, Result};
use clap::Args;
use quadex::io;
use quadex::quality::MeshQuality;
use std::path::PathBuf;

#[derive(Args)]
pub(super) struct QualityArgs {
    mesh: PathBuf,
    #[arg(long)]
    boundary: Option<PathBuf>,
}

pub(super) fn run(a: QualityArgs) -> Result<()> {
    let QualityArgs { mesh, boundary } = a;
    // Reading checks the mesh: convex quads, no overlaps, one piece.
    let m = read_mesh(&mesh)?;
    if let Some(b) = boundary {
        let bd = io::read_boundary(&b).map_err(|e| InputError(anyhow!("{}: {e}", b.display())))?;
        check_against(&m, &bd).map_err(|e| InputError(anyhow!("{}: {e}", mesh.display())))?;
        // On stderr: stdout stays the JSON alone.
        eprintln!(
            "{} meshes {}: the same {} boundary nodes and the same area",
            mesh.display(),
            b.display(),
            bd.node_count()
        );
    }
    outln!("{}", serde_json::to_string_pretty(&MeshQuality::of(&m))?);
    Ok(())
}

/// The mesh keeps the boundary's nodes and its area.
fn check_against(m: &quadex::QuadMesh, b: &quadex::Boundary) -> Result<()> {
    if m.n_boundary() != b.node_count() {
        return Err(anyhow!(
            "the mesh has {} boundary nodes, the boundary {}",
            m.n_boundary(),
            b.node_count()
        ));
    }
    let rel = (m.domain_area() - b.area()).abs() / b.area().abs();
    if rel > 1e-9 {
        return Err(anyhow!(
            "the mesh covers a different area than the boundary"
        ));
    }
    Ok(())
}

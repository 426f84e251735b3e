//! Writes the reference meshes (`quadex::reference`) to `assets/reference/`
//! as MSH 4.1 and prints their quality and how many of their quads are good
//! enough to learn from.
//!
//! `cargo run --release --example reference_meshes [OUT_DIR]`

use quadex::io::{write_mesh, MeshFormat};
use quadex::quality::{MeshQuality, QuadQuality};
use quadex::samples::{is_good, CollectParams};
use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(quadex::reference::shipped_dir);
    std::fs::create_dir_all(&dir)?;
    println!(
        "{:<16} {:>6} {:>7} {:>7} {:>8} {:>6}",
        "mesh", "quads", "sj min", "sj mean", "[45,135]", "good"
    );
    for (name, mesh) in quadex::reference::all()? {
        let path = dir.join(format!("{name}.{}", MeshFormat::Msh41.extension()));
        write_mesh(&mesh, &path)?;
        let q = MeshQuality::of(&mesh);
        let good = mesh
            .quads
            .iter()
            .filter(|c| is_good(&QuadQuality::of(mesh.corners(c)), &CollectParams::DEFAULT))
            .count();
        println!(
            "{name:<16} {:>6} {:>7.3} {:>7.3} {:>7.1}% {:>6}",
            q.quads,
            q.sj_min,
            q.sj_mean,
            100.0 * q.frac_angles_45_135,
            good
        );
    }
    Ok(())
}

//! Writes the reference meshes (`quadex::reference`) to `assets/reference/`
//! as MSH 4.1 and prints their quality and how many of their quads are good
//! enough to learn from. The generated domain's mesh is the recorded one;
//! with `--record`, it is meshed again by the extraction of this build
//! (`reference::record_generated`).
//!
//! `cargo run --release --example reference_meshes [OUT_DIR] [--record]`

use quadex::io::{write_mesh, MeshFormat};
use quadex::quality::{MeshQuality, QuadQuality};
use quadex::samples::{is_good, CollectParams};
use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let record = args.iter().any(|a| a == "--record");
    let dir = args
        .iter()
        .find(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .unwrap_or_else(quadex::reference::shipped_dir);
    std::fs::create_dir_all(&dir)?;
    println!(
        "{:<16} {:>6} {:>7} {:>7} {:>8} {:>6}",
        "mesh", "quads", "sj min", "sj mean", "[45,135]", "good"
    );
    for (name, mut mesh) in quadex::reference::all()? {
        if record && name == quadex::reference::GENERATED_NAME {
            mesh = quadex::reference::record_generated()?;
        }
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

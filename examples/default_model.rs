//! Rebuilds the shipped default model, `assets/models/default.json`, from
//! the reference meshes in `assets/reference/` (see `quadex::reference`),
//! and prints its fit figures.
//!
//! `cargo run --release --example default_model`

use quadex::fit::FitParams;
use quadex::reference::{default_model, read_shipped};
use std::path::Path;

fn main() -> anyhow::Result<()> {
    let meshes = read_shipped()?;
    let model = default_model(&meshes, &FitParams::DEFAULT)?;
    if let Some(r) = &model.figures {
        println!("{}", r.table());
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = root.join("assets/models/default.json");
    std::fs::create_dir_all(out.parent().unwrap_or(root))?;
    quadex::io::write_atomic(&out, model.to_json().as_bytes())?;
    println!("{}", out.display());
    Ok(())
}

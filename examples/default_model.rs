//! Rebuilds the shipped models, `assets/models/default.json` (the
//! quadratic form) and `assets/models/ann.json` (the network form), from
//! the reference meshes in `assets/reference/` (see `quadex::reference`),
//! and prints their fit figures.
//!
//! `cargo run --release --example default_model`

use quadex::fit::FitParams;
use quadex::reference::{ann_model, default_model, read_shipped};
use std::path::Path;

fn main() -> anyhow::Result<()> {
    let meshes = read_shipped()?;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (file, model) in [
        ("default.json", default_model(&meshes, &FitParams::DEFAULT)?),
        ("ann.json", ann_model(&meshes, &FitParams::DEFAULT)?),
    ] {
        if let Some(r) = &model.figures {
            println!("{}", r.table());
        }
        let out = root.join("assets/models").join(file);
        std::fs::create_dir_all(out.parent().unwrap_or(root))?;
        quadex::io::write_atomic(&out, model.to_json().as_bytes())?;
        println!("{}", out.display());
    }
    Ok(())
}

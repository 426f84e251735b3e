//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// The shared benchmark folder beside the checkout.
pub fn bench() -> PathBuf {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/bench");
    assert!(p.is_dir(), "benchmark folder {} not found", p.display());
    p
}

/// The `.poly` files of a benchmark sub-folder, sorted.
pub fn cases(folder: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(bench().join(folder))
        .expect("bench folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "poly"))
        .collect();
    v.sort();
    v
}

//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// The editor tests' harness.
#[cfg(feature = "gui")]
pub mod editor;

/// The benchmark boundaries the tests use, kept in the repository
/// (`tests/data`, provenance in its README): `boundaries`, `peer`, `edge`
/// and `bad`.
pub fn bench() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// The reproducers of reported failures (`tests/repro`).
pub fn repro() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/repro")
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

/// The nodes of the rectangle from `origin`, `w` wide and `h` high,
/// counter-clockwise from `origin`: `below` equal segments along the
/// bottom, `across` up each side and `above` along the top.
pub fn rectangle(
    origin: quadex::geom::Point,
    w: f64,
    h: f64,
    below: usize,
    across: usize,
    above: usize,
) -> Vec<quadex::geom::Point> {
    use quadex::geom::Point;
    let at = |x: f64, y: f64| origin + Point::new(x, y);
    let mut p = Vec::with_capacity(below + above + 2 * across);
    p.extend((0..below).map(|i| at(w * i as f64 / below as f64, 0.0)));
    p.extend((0..across).map(|j| at(w, h * j as f64 / across as f64)));
    p.extend((0..above).map(|i| at(w * (above - i) as f64 / above as f64, h)));
    p.extend((0..across).map(|j| at(0.0, h * (across - j) as f64 / across as f64)));
    p
}

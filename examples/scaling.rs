//! Prints time per element for growing meshes: generated unit squares
//! (n × n boundary segments a side), the benchmark disks, and perforated
//! plates of k × k round holes (a tube sheet's pattern: ligaments 2.5
//! sizes wide between holes of 12 nodes), meshed with the default model
//! and parameters. Median of `RUNS` runs (3 unless given), release build.
//! The plates show how the cost grows with the number of loops.
//!
//! `cargo run --release --example scaling [MAX_SIDE] [RUNS]`

use quadex::extract::{MeshParams, Mesher};
use quadex::model::{default_model, Model};
use quadex::Boundary;
use std::sync::Arc;
use std::time::Instant;

/// The command line's allocator, so the times are the ones it gives.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn time(b: &Boundary, model: &Arc<dyn Model>, n: usize) -> Result<(usize, f64, f64), String> {
    let mut runs = Vec::new();
    let mut quads = 0;
    let mut smooth_share = 0.0;
    for _ in 0..n {
        let t0 = Instant::now();
        let mut m = Mesher::new(b.clone(), model.clone(), MeshParams::DEFAULT);
        m.run(|_| {}).map_err(|e| e.to_string())?;
        let t1 = Instant::now();
        let mesh = quadex::pipeline::finish(&m, &quadex::FinishParams::DEFAULT).expect("finish");
        let t2 = Instant::now();
        quads = mesh.quads.len();
        runs.push((t2 - t0).as_secs_f64());
        smooth_share = (t2 - t1).as_secs_f64() / (t2 - t0).as_secs_f64();
    }
    runs.sort_by(f64::total_cmp);
    Ok((quads, runs[runs.len() / 2], smooth_share))
}

fn main() {
    let max: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1024);
    let runs: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(3)
        .max(1);
    let model: Arc<dyn Model> = Arc::new(default_model().expect("the shipped model"));
    println!("| case | quads | median s | µs / quad | improvement share |");
    println!("|---|---:|---:|---:|---:|");
    let mut n = 32;
    while n <= max {
        match time(&Boundary::unit_square(n), &model, runs) {
            Ok((q, t, s)) => println!(
                "| square {n}×{n} | {q} | {t:.3} | {:.2} | {:.0}% |",
                1e6 * t / q as f64,
                100.0 * s
            ),
            Err(e) => println!("| square {n}×{n} | – | failed: {e} | | |"),
        }
        n *= 2;
    }
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries");
    for name in ["disk100", "disk400", "disk1600", "disk6400"] {
        let Ok(b) = quadex::io::read_boundary(&dir.join(format!("{name}.poly"))) else {
            continue;
        };
        match time(&b, &model, runs) {
            Ok((q, t, s)) => println!(
                "| {name} | {q} | {t:.3} | {:.2} | {:.0}% |",
                1e6 * t / q as f64,
                100.0 * s
            ),
            Err(e) => println!("| {name} | – | did not finish: {e} | | |"),
        }
    }
    for k in [5, 10, 16, 22] {
        let name = format!("plate, {} holes", k * k);
        match time(&quadex::domains::perforated_plate(k), &model, runs) {
            Ok((q, t, s)) => println!(
                "| {name} | {q} | {t:.3} | {:.2} | {:.0}% |",
                1e6 * t / q as f64,
                100.0 * s
            ),
            Err(e) => println!("| {name} | – | did not finish: {e} | | |"),
        }
    }
}

//! Frame time of the editor with a large finished mesh on screen, measured
//! headless with egui_kittest: the CPU side of a frame (the UI, building
//! the canvas shapes and egui's tessellation into triangles), not the
//! GPU's drawing.
//!
//! `cargo run --release --example frame_time [CELLS_PER_SIDE]` (default 450,
//! about 200k quads).

use egui_kittest::Harness;
use quadex::app::{App, Command, Document, Settings};
use quadex::Boundary;
use std::time::Instant;

fn main() -> Result<(), String> {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(450);
    let settings = Settings {
        model: "rules".into(),
        ..Settings::default()
    };
    let t0 = Instant::now();
    let mut app = App::new(Document::new(Boundary::unit_square(n), None, settings)?);
    app.apply(Command::RunToEnd);
    let quads = app.doc.mesher.mesh().quads.len();
    eprintln!(
        "meshed {quads} quads in {:.2} s",
        t0.elapsed().as_secs_f64()
    );
    let mut h = Harness::builder()
        .with_size([1280.0, 800.0])
        .build_state(|ctx, app: &mut App| app.ui(ctx), app);
    h.run();
    let mut times = Vec::new();
    for _ in 0..15 {
        let t = Instant::now();
        h.step();
        let shapes = h.output().shapes.clone();
        let meshes = h.ctx.tessellate(shapes, 1.0);
        std::hint::black_box(meshes);
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    println!(
        "{quads} quads on screen: frame (CPU) median {:.1} ms, min {:.1} ms, max {:.1} ms over {} frames",
        times[times.len() / 2],
        times[0],
        times[times.len() - 1],
        times.len()
    );
    Ok(())
}

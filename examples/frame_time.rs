//! Frame time of the editor with a large finished mesh on screen, measured
//! headless with egui_kittest: the CPU side of a frame (the UI, building
//! the canvas shapes and egui's tessellation into triangles), not the
//! GPU's drawing.
//!
//! `cargo run --release --example frame_time [CELLS_PER_SIDE | FILE]`
//! (default 450, about 200k quads; a boundary file is meshed with the
//! default model).

use egui_kittest::Harness;
use quadex::app::{App, Command, Document, Settings};
use quadex::Boundary;
use std::time::Instant;

fn main() -> Result<(), String> {
    let arg = std::env::args().nth(1).unwrap_or_else(|| "450".into());
    let (boundary, settings) = match arg.parse::<usize>() {
        Ok(n) => (
            Boundary::unit_square(n),
            // Extraction to the end: a uniform n × n grid.
            Settings {
                model: "rules".into(),
                fill_after_layers: None,
                ..Settings::default()
            },
        ),
        Err(_) => (
            quadex::io::read_boundary(std::path::Path::new(&arg)).map_err(|e| e.to_string())?,
            Settings::default(),
        ),
    };
    let t0 = Instant::now();
    let mut app = App::new(Document::new(boundary, None, settings).map_err(|e| e.to_string())?);
    app.apply(Command::RunToEnd);
    app.wait();
    let quads = app.doc().mesher().map_or(0, |m| m.mesh().quads.len());
    eprintln!(
        "meshed and finished {quads} quads in {:.2} s",
        t0.elapsed().as_secs_f64()
    );
    let mut h = Harness::builder()
        .with_size([1400.0, 860.0])
        .build_state(|ctx, app: &mut App| app.ui(ctx), app);
    h.run();
    let mut times = Vec::new();
    let mut ui_times = Vec::new();
    for _ in 0..15 {
        let t = Instant::now();
        h.step();
        ui_times.push(t.elapsed().as_secs_f64() * 1e3);
        let shapes = h.output().shapes.clone();
        let meshes = h.ctx.tessellate(shapes, 1.0);
        std::hint::black_box(meshes);
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    ui_times.sort_by(f64::total_cmp);
    eprintln!(
        "of which the UI pass (panels, canvas shapes) median {:.1} ms",
        ui_times[ui_times.len() / 2]
    );
    println!(
        "{quads} quads on screen: frame (CPU) median {:.1} ms, min {:.1} ms, max {:.1} ms over {} frames",
        times[times.len() / 2],
        times[0],
        times[times.len() - 1],
        times.len()
    );
    Ok(())
}

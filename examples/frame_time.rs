//! Frame time of the editor with a large finished mesh on screen, measured
//! headless with egui_kittest: the CPU side of a frame (the UI, building
//! the canvas shapes and egui's tessellation into triangles), not the
//! GPU's drawing.
//!
//! `cargo run --release --example frame_time [CELLS_PER_SIDE | FILE]`
//! (default 450, about 200k quads; a boundary file is meshed with the
//! default model, e.g. `../shared/bench/boundaries/disk1600.poly`).
//! Prints the median over still frames, frames with the pointer moving
//! over the mesh, and frames of a pan.

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
    let canvas = h.state().view.canvas_rect;
    // Still frames, frames with the pointer moving over the mesh (the quad
    // under it outlined, its tooltip), and frames of a pan (the view moves:
    // the mesh's shapes are built again every frame).
    let still = measure(&mut h, |_, _| {});
    let hover = measure(&mut h, |h, k| {
        h.hover_at(canvas.center() + egui::vec2(3.0 * k as f32, 2.0 * k as f32));
    });
    let start = canvas.center();
    h.hover_at(start);
    h.run();
    h.drag_at(start);
    h.run();
    let pan = measure(&mut h, |h, k| {
        h.hover_at(start + egui::vec2(4.0 * (k + 1) as f32, 0.0));
    });
    h.drop_at(start);
    h.run();
    for (what, t) in [
        ("still", &still),
        ("pointer moving", &hover),
        ("panning", &pan),
    ] {
        println!(
            "{quads} quads on screen, {what}: frame (CPU) median {:.1} ms (UI pass {:.1} ms), min {:.1} ms, max {:.1} ms over {} frames",
            t.total[t.total.len() / 2],
            t.ui[t.ui.len() / 2],
            t.total[0],
            t.total[t.total.len() - 1],
            t.total.len()
        );
    }
    Ok(())
}

/// Frame times in ms, sorted: the whole frame (UI pass and tessellation)
/// and the UI pass alone.
struct Times {
    total: Vec<f64>,
    ui: Vec<f64>,
}

/// Times 21 frames, `input(h, k)` given before frame `k`.
fn measure(
    h: &mut Harness<'static, App>,
    mut input: impl FnMut(&mut Harness<'static, App>, usize),
) -> Times {
    let (mut total, mut ui) = (Vec::new(), Vec::new());
    for k in 0..21 {
        input(h, k);
        let t = Instant::now();
        h.step();
        ui.push(t.elapsed().as_secs_f64() * 1e3);
        let shapes = h.output().shapes.clone();
        let meshes = h.ctx.tessellate(shapes, 1.0);
        std::hint::black_box(meshes);
        total.push(t.elapsed().as_secs_f64() * 1e3);
    }
    total.sort_by(f64::total_cmp);
    ui.sort_by(f64::total_cmp);
    Times { total, ui }
}

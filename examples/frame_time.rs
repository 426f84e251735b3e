//! Frame time of the editor with a large finished mesh on screen, measured
//! headless with egui_kittest: the CPU side of a frame (the UI, building
//! the canvas shapes and egui's tessellation into triangles), not the
//! GPU's drawing.
//!
//! `cargo run --release --example frame_time [CELLS_PER_SIDE | FILE]`
//! (default 450, about 200k quads; a boundary file is meshed with the
//! default model, e.g. `tests/data/boundaries/disk1600.poly`).
//! Prints the median over still frames, frames with the pointer moving
//! over the mesh, frames of a pan and of a zoom at the fit, and of zooming
//! in to 4× and panning there and at 2×.

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
    let fit = h.state().view.canvas.zoom;
    let mut rows = Vec::new();
    // Still frames, frames with the pointer moving over the mesh (the quad
    // under it outlined, its tooltip), a pan and a zoom about the pointer
    // in and out by turns (the whole mesh stays on screen).
    rows.push(("still", measure(&mut h, |_, _| {})));
    rows.push((
        "pointer moving",
        measure(&mut h, |h, k| {
            h.hover_at(canvas.center() + egui::vec2(3.0 * k as f32, 2.0 * k as f32));
        }),
    ));
    let start = canvas.center();
    rows.push(("panning", pan(&mut h, start)));
    rows.push((
        "zooming",
        zoom(&mut h, start, |k| if k % 2 == 0 { 6.0 } else { -6.0 }),
    ));
    // Zoomed in: to 4× the fit (the quads' image drawn again at each
    // density step, then the quads as triangles where it would be too
    // large), a pan there, back out to 2× and a pan there.
    rows.push(("zooming in to 4×", zoom(&mut h, start, |_| 5.44)));
    let at4 = h.state().view.canvas.zoom / fit;
    rows.push(("panning at 4×", pan(&mut h, start)));
    rows.push(("zooming out to 2×", zoom(&mut h, start, |_| -2.72)));
    let at2 = h.state().view.canvas.zoom / fit;
    rows.push(("panning at 2×", pan(&mut h, start)));
    eprintln!("zoomed to {at4:.2}× and {at2:.2}× the fit");
    for (what, t) in &rows {
        println!(
            "{quads} quads, {what}: frame (CPU) median {:.1} ms (UI pass {:.1} ms), min {:.1} ms, max {:.1} ms over {} frames",
            t.total[t.total.len() / 2],
            t.ui[t.ui.len() / 2],
            t.total[0],
            t.total[t.total.len() - 1],
            t.total.len()
        );
    }
    Ok(())
}

/// Frames of a pan: a drag from `start` 4 points a frame to the right.
fn pan(h: &mut Harness<'static, App>, start: egui::Pos2) -> Times {
    h.hover_at(start);
    h.run();
    h.drag_at(start);
    h.run();
    let t = measure(h, |h, k| {
        h.hover_at(start + egui::vec2(4.0 * (k + 1) as f32, 0.0));
    });
    h.drop_at(start);
    h.run();
    t
}

/// Frames of a zoom about `at`: the wheel turned by `notch(k)` points
/// before frame `k` (200 points zoom by e).
fn zoom(h: &mut Harness<'static, App>, at: egui::Pos2, notch: impl Fn(usize) -> f32) -> Times {
    h.hover_at(at);
    h.run();
    measure(h, |h, k| {
        h.event(egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(0.0, notch(k)),
            modifiers: egui::Modifiers::NONE,
        });
    })
}

/// Frame times in ms, sorted: the whole frame (UI pass and tessellation)
/// and the UI pass alone.
struct Times {
    total: Vec<f64>,
    ui: Vec<f64>,
}

/// Times 51 frames, `input(h, k)` given before frame `k`.
fn measure(
    h: &mut Harness<'static, App>,
    mut input: impl FnMut(&mut Harness<'static, App>, usize),
) -> Times {
    let (mut total, mut ui) = (Vec::new(), Vec::new());
    for k in 0..51 {
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

//! The editor's window layout and legibility, with egui_kittest: the
//! canvas's room at any size, side panels, glyphs, scrolling, menus and
//! tooltips.
#![cfg(feature = "gui")]

mod common;

use common::editor::*;
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use quadex::app::{App, Command};
use quadex::model::Form;
use std::path::PathBuf;
use std::time::Duration;

/// 10a. The canvas keeps most of a small window and fits the boundary
///      again when the window is resized.
#[test]
fn issue17_the_canvas_keeps_room_and_refits_on_resize() {
    for (w, hh, share) in [(1000.0, 650.0, 0.45), (800.0, 500.0, 0.4)] {
        let mut h = harness_sized(example(), w, hh);
        h.run();
        let cw = h.state().view.canvas_rect.width();
        assert!(cw >= share * w, "canvas {cw} px wide at {w} x {hh}");
        // With a step's table in the panels, nothing wider than a panel
        // pushes the canvas aside (rows that cannot wrap scroll).
        let mut h = harness_sized(example_named("plate_hole.poly"), w, hh);
        h.run();
        h.state_mut().apply(Command::StepN(30));
        h.run();
        let r = h.state().view.canvas_rect;
        assert!(
            r.left() <= 0.24 * w + 1.0 && r.right() >= 0.72 * w - 1.0,
            "canvas {r:?} at {w} x {hh}"
        );
    }
    let mut h = harness(example());
    h.run();
    let zoom = h.state().view.canvas.zoom;
    h.set_size(egui::vec2(1000.0, 650.0));
    h.run();
    assert!(h.state().view.canvas.zoom < zoom);
    let r = h.state().view.canvas_rect;
    let b = h.state().doc().boundary().unwrap().clone();
    for &p in &b.points {
        assert!(r.contains(screen(&h, p)), "{p:?} off the canvas");
    }
    // After the user zooms, a resize keeps the user's view.
    h.hover_at(r.center());
    h.event(egui::Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, 120.0),
        modifiers: egui::Modifiers::NONE,
    });
    h.run();
    let zoomed = h.state().view.canvas.zoom;
    h.set_size(egui::vec2(1100.0, 700.0));
    h.run();
    assert_eq!(h.state().view.canvas.zoom, zoomed);
}

/// The side panels get their width back when a window made narrow is made
/// wide again (egui keeps the narrowed width, and persists it), and a
/// width the user drags is what they get back.
#[test]
fn the_side_panels_widen_again_with_the_window() {
    let width = |h: &Harness<'static, App>, id: &str| {
        egui::containers::panel::PanelState::load(&h.ctx, egui::Id::new(id))
            .expect("the panel was shown")
            .rect
            .width()
    };
    let mut h = harness(example());
    h.run();
    let (left, right) = (width(&h, "steps"), width(&h, "panels"));
    assert!((left - 290.0).abs() < 1.0, "{left}");
    h.set_size(egui::vec2(800.0, 500.0));
    h.run();
    assert!(width(&h, "steps") < left - 50.0);
    assert!(width(&h, "panels") < right - 50.0);
    h.set_size(egui::vec2(1400.0, 860.0));
    h.run();
    assert!((width(&h, "steps") - left).abs() < 1.0);
    assert!((width(&h, "panels") - right).abs() < 1.0);
    // The remembered widths come back in a new window too.
    let prefs = h.state().prefs();
    let mut app = example();
    app.set_prefs(prefs);
    let mut h = harness(app);
    h.run();
    assert!((width(&h, "steps") - left).abs() < 1.0);
    // A narrower left panel, dragged by its edge, stays narrower.
    let y = h.state().view.canvas_rect.center().y;
    h.drag_at(egui::pos2(left - 1.0, y));
    h.run();
    h.hover_at(egui::pos2(230.0, y));
    h.run();
    h.drop_at(egui::pos2(230.0, y));
    h.run();
    let dragged = width(&h, "steps");
    assert!(dragged < left - 30.0, "{dragged}");
    assert!((h.state().prefs().widths[0] - dragged).abs() < 1.0);
    h.set_size(egui::vec2(800.0, 500.0));
    h.run();
    h.set_size(egui::vec2(1400.0, 860.0));
    h.run();
    assert!((width(&h, "steps") - dragged).abs() < 1.0);
}

/// 10c. Every character painted in every panel has a glyph; counts read
///      as English; fit figures are never printed as infinities.
#[test]
fn issue17_every_glyph_exists_and_counts_read_as_english() {
    let mut h = stepped_example(5);
    h.state_mut().apply(Command::AppendLast);
    h.state_mut().apply(Command::Refit {
        form: Form::Quadratic,
        mesh_rest: false,
    });
    // The refit is made in the background: wait for it.
    h.state_mut().wait();
    h.run();
    let mut texts = Vec::new();
    for tab in ["Quality", "Model", "Training set", "Smoothing"] {
        h.get_by_label(tab).click();
        settle(&mut h);
        texts.extend(painted(&h));
        if tab == "Model" {
            // One sample of yours: figures stay finite.
            h.get_by_label("yours").click();
            settle(&mut h);
            texts.extend(painted(&h));
        }
    }
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    texts.extend(painted(&h));
    let mut missing = Vec::new();
    for (t, _, font) in &texts {
        for ch in t.chars().filter(|c| !c.is_whitespace()) {
            if !h.ctx.fonts_mut(|f| f.has_glyph(font, ch)) {
                missing.push((ch, t.clone()));
            }
        }
        assert!(
            !t.contains("1 samples") && !t.contains("3th") && !t.contains("2th"),
            "{t}"
        );
        assert!(!t.contains("inf") || t.contains("info"), "{t}");
        assert!(!t.contains("NaN"), "{t}");
    }
    assert!(missing.is_empty(), "no glyph for {missing:?}");
    // The model's Pn has its unit beside it.
    h.state_mut().apply(Command::Undo);
    h.state_mut().apply(Command::Reset);
    h.state_mut().apply(Command::StepN(3));
    h.run();
    h.get_by_label("model's Pn, normalised");
    h.get_by_label_contains("× |P0 r1|");
    h.get_by_label("model's Pn, world");
}

/// 10d. The wheel over a plot of the Model panel scrolls the panel; it does
///      not pan the plot away.
#[test]
fn issue17_the_wheel_scrolls_the_model_panel() {
    let mut h = harness(example());
    h.run();
    h.get_by_label("Model").click();
    settle(&mut h);
    let rects = h.state().panels.model.plot_rects.clone();
    assert!(!rects.is_empty());
    let plot = rects[0];
    h.hover_at(plot.center());
    h.run();
    for _ in 0..3 {
        h.event(egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(0.0, -80.0),
            modifiers: egui::Modifiers::NONE,
        });
        h.run();
    }
    let moved = h.state().panels.model.plot_rects[0];
    assert!(
        moved.top() < plot.top() - 50.0,
        "the panel did not scroll: {plot:?} then {moved:?}"
    );
}

/// 10e. Esc closes an open menu (and cancels nothing); the histograms have
///      ticks along x; controls explain themselves on hover; the export
///      path starts beside the document's file, the export dialog starts
///      from it, and another document resets it.
#[test]
fn issue17_menus_ticks_tooltips_and_export_path() {
    let mut h = harness(open(&boundary("plate_hole.poly")));
    h.run();
    h.get_by_label("File").click();
    h.run();
    h.get_by_label_contains("New Ctrl");
    h.key_press(egui::Key::Escape);
    h.run();
    assert!(
        h.query_by_label_contains("New Ctrl").is_none(),
        "the menu is still open"
    );
    assert!(h.state().doc().draft.loops.len() == 2);
    // Histograms with ticks.
    h.state_mut().apply(Command::StepN(30));
    h.run();
    let texts: Vec<String> = painted(&h).into_iter().map(|t| t.0).collect();
    for tick in ["30°", "60°", "90°", "0.25", "0.5", "0.75"] {
        assert!(texts.iter().any(|t| t == tick), "no tick {tick}: {texts:?}");
    }
    // Tooltips.
    for (control, tip) in [
        ("Step  (Space)", "Take one extraction step"),
        ("Refit", "Fit the model on the reference"),
        ("move", "Drag a boundary node"),
        ("Append as sample", "Keep the last element"),
        ("Model", "How well the model fits"),
    ] {
        let r = h.get_by_label(control).rect();
        h.hover_at(r.center());
        h.run();
        std::thread::sleep(Duration::from_millis(600));
        h.run();
        h.get_by_label_contains(tip);
    }
    // The export path.
    let want = boundary("plate_hole.msh");
    assert_eq!(PathBuf::from(&h.state().panels.export_path), want);
    // The export dialog (here the prompt in the window) starts where the
    // Export box says.
    let dir = tempfile::tempdir().unwrap();
    let custom = dir.path().join("custom.vtk").display().to_string();
    h.state_mut().panels.export_path = custom.clone();
    h.state_mut().window.native_dialogs = false;
    h.run();
    // (Nodes showing the path: the Export box's, then the prompt's too.)
    let showing = |h: &Harness<'static, App>| h.query_all_by_value(&custom).count();
    let panel = showing(&h);
    assert!(panel > 0);
    h.state_mut()
        .apply(Command::Dialog(quadex::app::command::Dialog::ExportMesh));
    h.run();
    assert_eq!(showing(&h), 2 * panel, "the prompt does not show the path");
    h.key_press(egui::Key::Escape);
    h.run();
    assert_eq!(showing(&h), panel, "the prompt stays open");
    // Another document: the Export box starts again beside it, though it
    // held a path of the user's.
    h.state_mut().apply(Command::OpenExample("lshape.poly"));
    h.run();
    // A built-in example has no folder of its own, and nothing was
    // exported yet: no path (not the folder plate_hole came from).
    assert_eq!(h.state().panels.export_path, "");
    // Once a mesh is exported, its Export box (and so its dialogs) start
    // where the last mesh was written.
    let written = dir.path().join("lshape.msh");
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    h.state_mut().apply(Command::Export(written.clone()));
    settle(&mut h);
    assert!(written.exists(), "{}", h.state().window.status);
    h.state_mut().apply(Command::OpenExample("square.poly"));
    h.run();
    let p = PathBuf::from(&h.state().panels.export_path);
    assert_eq!(p, dir.path().join("square.msh"));
}

/// The Boundary section is in view without scrolling when a boundary
/// tool is chosen; at 800 × 500 the refit report's "model now" is in view
/// and the colour legend leaves the canvas most of its room.
#[test]
fn a_small_window_keeps_the_refit_report_the_boundary_and_the_canvas_in_view() {
    // An editing tool chosen with the pointer: the Boundary section comes
    // right under the Extraction panel, in view.
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(5));
    h.get_by_label("move").click();
    h.run();
    let boundary_heading = h.get_by_label("Boundary").rect();
    assert!(boundary_heading.bottom() < 860.0, "{boundary_heading:?}");
    h.get_by_label("Resample");
    let mut h = harness_sized(example(), 800.0, 500.0);
    h.run();
    // A correction, a refit.
    let (_, _, _) = step_five_and_correct(&mut h, |pn, p0, _| pn + (p0 - pn) * 0.05);
    h.state_mut().apply(Command::Refit {
        form: Form::Quadratic,
        mesh_rest: false,
    });
    h.state_mut().wait();
    h.run();
    // The left panel ends where the canvas begins.
    let left = h.state().view.canvas_rect.left();
    let after = h.state().doc().last_refit.as_ref().unwrap().checks[0].after;
    let value = format!(
        "{} ({:.3}, {:.3})",
        after.element_type.number(),
        after.pn.x,
        after.pn.y
    );
    // (Found by its node: the report is further down the panel.)
    // (The corrected element reads the same when it is reproduced.)
    let found: Vec<_> = h.query_all_by_label(&value).collect();
    assert!(!found.is_empty(), "no {value}");
    for n in found {
        let at = n.rect();
        assert!(
            at.right() <= left,
            "the model now at {at:?}, the panel ends at {left}"
        );
    }
    assert!(h.get_by_label("model now").rect().right() <= left);
    // The finished mesh coloured: the legend's backdrop takes little of
    // the canvas.
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    let canvas = h.state().view.canvas_rect;
    let back = h
        .output()
        .shapes
        .iter()
        .filter_map(|c| match &c.shape {
            egui::Shape::Rect(r) if r.fill == egui::Color32::from_black_alpha(170) => Some(r.rect),
            _ => None,
        })
        .next()
        .expect("the legend");
    let share = back.area() / canvas.area();
    assert!(
        share < 0.2,
        "the legend takes {:.0} % of the canvas",
        100.0 * share
    );
}

//! The editor clicked through with egui_kittest (no window, no GPU): the
//! same `App::ui` the window runs. This file: stepping and running, undo
//! and redo, Cancel, and what the canvas shows of the steps. The other
//! panels and flows are in `editor_*.rs` beside it, sharing the harness of
//! `tests/common/editor.rs`; the tests named after issue 17 drive the
//! problems it lists (see `docs/editor_tests.md`).

mod common;

use common::editor::*;
use egui::Rect;
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use quadex::app::{App, Command, Document, MeshKind, Settings};
use quadex::extract::StepKind;
use quadex::model::{ElementType, Form};
use std::time::{Duration, Instant};

#[test]
fn step_undo_run_and_export_a_valid_mesh() {
    let mut h = harness(example());
    h.run();
    for _ in 0..5 {
        h.get_by_label_contains("(Space)").click();
        h.run();
    }
    assert_eq!(h.state().doc().steps(), 5);
    let last = h.state().doc().last().cloned().expect("a step report");
    assert!(last.reference.is_some() && !last.leading.is_empty());
    // The panel shows what the step did, and which rung of the ladder
    // took it.
    h.get_by_label("remedy");
    h.get_by_label("rung");
    h.get_by_label(last.rung.name());
    h.get_by_label_contains("Undo  (").click();
    h.run();
    assert_eq!(h.state().doc().steps(), 4);
    h.get_by_label_contains("Redo  (").click();
    h.run();
    assert_eq!(h.state().doc().steps(), 5);
    // Run to end goes to the background: a progress bar, then the mesh.
    h.get_by_label_contains("Run to end").click();
    h.step();
    settle(&mut h);
    assert!(h.state().doc().is_done());
    h.get_by_label("mesh complete");
    // The colours of the quads have a legend, in the metric's figures.
    let texts: Vec<String> = painted(&h).into_iter().map(|(t, _, _)| t).collect();
    assert!(
        texts.iter().any(|t| t == "scaled Jacobian (colour)"),
        "{texts:?}"
    );
    assert!(texts.iter().any(|t| t == "0.50"));
    h.state_mut().panels.quality.metric = Some(quadex::app::quality_panel::Metric::Aspect);
    h.run();
    let texts: Vec<String> = painted(&h).into_iter().map(|(t, _, _)| t).collect();
    assert!(
        texts.iter().any(|t| t == "aspect ratio (colour)"),
        "{texts:?}"
    );
    assert!(texts.iter().any(|t| t == "10.0") && texts.iter().any(|t| t == "2.0"));
    // The status counts the run's steps and all of them.
    let all = h.state().doc().steps();
    assert_eq!(
        status(&h),
        format!("{} steps taken ({all} in all), mesh complete", all - 5)
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("annulus.msh");
    h.state_mut().panels.export_path = out.display().to_string();
    h.get_by_label("Export mesh").click();
    h.run();
    assert!(status(&h).starts_with("wrote"), "{}", status(&h));
    assert_valid_annulus_mesh(&out);
}

#[test]
fn keyboard_shortcuts_step_undo_and_redo() {
    let mut h = harness(example());
    h.run();
    h.key_press(egui::Key::Space);
    h.run();
    h.key_press(egui::Key::Space);
    h.run();
    assert_eq!(h.state().doc().steps(), 2);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc().steps(), 1);
    h.key_press_modifiers(
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    h.run();
    assert_eq!(h.state().doc().steps(), 2);
}

/// Steps undo one by one; the status says how many are left and that
/// Reset goes back to the start (a run to the end is hundreds of steps).
#[test]
fn undoing_a_step_says_how_many_are_left_and_how_to_start_again() {
    let mut h = stepped_example(4);
    h.state_mut().apply(Command::Undo);
    assert_eq!(
        status(&h),
        "undone: step (3 steps left; Reset, Ctrl+R, starts the mesh again)"
    );
    assert_eq!(h.state().doc().steps(), 3);
}

#[test]
fn undo_and_redo_every_edit() {
    let mut h = stepped_example(4);
    let stepped = h.state().doc().mesher().unwrap().mesh().clone();
    // A correction (an edit) on top of steps.
    let last = h.state().doc().last().cloned().unwrap();
    let pn = stepped.nodes[last.pn_node().unwrap() as usize];
    h.state_mut().apply(Command::CorrectLast {
        element_type: ElementType::New,
        pn,
        snap_to: None,
    });
    assert_eq!(h.state().doc().training.len(), 1);
    let corrected = h.state().doc().mesher().unwrap().mesh().clone();
    // New settings (an edit that restarts the mesh).
    let rules = Settings {
        model: "rules".into(),
        ..Settings::default()
    };
    h.state_mut().apply(Command::SetSettings(rules));
    assert_eq!(h.state().doc().steps(), 0);
    // Ctrl+Z twice: the settings, then the correction.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc().settings.model, "default");
    assert_eq!(h.state().doc().mesher().unwrap().mesh(), &corrected);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc().training.len(), 0);
    assert_eq!(h.state().doc().mesher().unwrap().mesh(), &stepped);
    // Ctrl+Shift+Z, then Ctrl+Y: the correction, then the settings.
    let redo = egui::Modifiers::COMMAND | egui::Modifiers::SHIFT;
    h.key_press_modifiers(redo, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc().training.len(), 1);
    assert_eq!(h.state().doc().mesher().unwrap().mesh(), &corrected);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Y);
    h.run();
    assert_eq!(h.state().doc().settings.model, "rules");
    assert!(!h.state().document.history.can_redo());
    // Undo past the steps too, one at a time.
    for _ in 0..6 {
        h.state_mut().apply(Command::Undo);
    }
    assert_eq!(h.state().doc().steps(), 0);
    assert_eq!(h.state().doc().training.len(), 0);
    // A refit is an edit: undo brings the old model back, redo the new.
    h.state_mut().apply(Command::StepN(5));
    h.state_mut().apply(Command::AppendLast);
    h.state_mut().apply(Command::Refit {
        form: Form::Quadratic,
        mesh_rest: false,
    });
    // The refit is made in the background: wait for it.
    h.state_mut().wait();
    let fitted = |h: &Harness<'static, App>| {
        h.state()
            .doc()
            .mesher()
            .unwrap()
            .model()
            .name()
            .starts_with("fitted")
    };
    assert!(fitted(&h));
    h.state_mut().apply(Command::Undo);
    assert!(!fitted(&h));
    h.state_mut().apply(Command::Redo);
    assert!(fitted(&h));
}

/// 1. Cancel on a large run: the editor is free at once, the document is
///    as before the run, and the run's result never arrives later.
#[test]
fn issue17_cancel_drops_a_large_run_at_once() {
    let mut h = harness(open(&boundary("disk1600.poly")));
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    assert!(h.state().busy());
    h.step();
    std::thread::sleep(Duration::from_millis(800));
    h.step();
    h.get_by_label("Cancel").click();
    h.step();
    let s = h.state();
    assert!(!s.busy(), "still busy after Cancel: {}", s.status());
    assert!(s.status().starts_with("cancelled"), "{}", s.status());
    assert_eq!(s.doc().steps(), 0);
    assert!(!s.doc().is_done());
    // The thread stops after the step it is taking; nothing is applied.
    let t = Instant::now();
    while h.state_mut().cancelled_running() {
        assert!(t.elapsed().as_secs() < 120, "the cancelled run goes on");
        h.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    h.run();
    let s = h.state();
    assert_eq!(s.doc().steps(), 0);
    assert!(!s.doc().is_done());
    assert!(!s.busy() && !s.finishing());
    assert_eq!(s.shown_kind(), MeshKind::Stepped);
    // Esc cancels too.
    h.state_mut().apply(Command::RunToEnd);
    h.step();
    h.key_press(egui::Key::Escape);
    h.step();
    assert!(!h.state().busy(), "{}", status(&h));
    assert_eq!(h.state().doc().steps(), 0);
}

/// 3a. After reopening a project, undo takes its steps back one by one
///     (and its refits), before undoing the opening itself.
#[test]
fn issue17_undo_carries_on_after_reopening_a_project() {
    let (_h, _dir, path) = refitted_and_saved("a.quadex.json");
    let mut o = harness(open(&boundary("square.poly")));
    o.run();
    o.state_mut().apply(Command::Open(path));
    o.run();
    assert_eq!(o.state().doc().steps(), 9);
    // The refitted model is kept with the project and still chosen.
    assert_eq!(o.state().doc().models.len(), 1);
    assert_eq!(o.state().doc().settings.model, "fitted (quadratic) 1");
    assert_eq!(o.state().doc().model_info().name, "fitted (quadratic) 1");
    // Ctrl+Z: a step at a time, the refit, then the opening.
    let undo = |o: &mut Harness<'static, App>| {
        o.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
        o.run();
    };
    undo(&mut o);
    assert_eq!(o.state().doc().name, "a.quadex.json", "{}", status(&o));
    assert_eq!(o.state().doc().steps(), 8);
    assert!(
        o.state().doc().last().is_some(),
        "the step before is the last one"
    );
    for _ in 0..2 {
        undo(&mut o);
    }
    assert_eq!(o.state().doc().steps(), 6);
    let model =
        |o: &Harness<'static, App>| o.state().doc().mesher().unwrap().model().name().to_string();
    assert!(model(&o).starts_with("fitted"));
    undo(&mut o);
    assert_eq!(status(&o), "undone: refit");
    assert!(!model(&o).starts_with("fitted"));
    assert_eq!(o.state().doc().steps(), 6);
    for _ in 0..6 {
        undo(&mut o);
    }
    assert_eq!(o.state().doc().steps(), 0);
    undo(&mut o);
    assert_eq!(status(&o), "undone: open");
    assert_eq!(o.state().doc().name, "square.poly");
}

/// A run the region fill finished says so in the step panel, with the
/// quads the fill made; one extraction finished does not.
#[test]
fn the_step_panel_names_the_region_fill_and_its_quads() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    h.step();
    settle(&mut h);
    assert!(h.state().doc().is_done());
    assert!(h
        .query_by_label_contains("the region fill (not extraction) made")
        .is_none());
    let two_layers = Settings {
        fill_after_layers: Some(2),
        ..Settings::default()
    };
    h.state_mut().apply(Command::SetSettings(two_layers));
    h.state_mut().apply(Command::RunToEnd);
    h.step();
    settle(&mut h);
    assert!(h.state().doc().is_done());
    let stats = h.state().doc().mesher().unwrap().stats().clone();
    let filled = stats.quads_made(StepKind::Fill);
    assert_eq!(stats.count(StepKind::Fill), 1);
    let mesh = h.state().doc().mesher().unwrap().mesh().clone();
    assert!(filled > 0 && filled < mesh.quads.len());
    assert_eq!(stats.standing, mesh.quads.len());
    // The fill's report lists the quads it left in the mesh.
    let last = h.state().doc().last().cloned().unwrap();
    assert_eq!(last.kind, StepKind::Fill);
    assert_eq!(last.quads.len(), filled);
    assert!(last.quads.iter().all(|q| mesh.quads.contains(q)));
    h.get_by_label(&format!(
        "the region fill (not extraction) made {filled} quads"
    ));
}

/// A run that reached the fill with the squarest corner fans and was made
/// again with balanced ones (a real-like graded side) says so in the step
/// panel: the last step is that run, and no fill is named.
#[test]
fn the_step_panel_names_a_run_made_again_with_balanced_fans() {
    use quadex::domains::{generate, Family};
    let d = generate(Family::GradedSide, 0xb11b8e4816ee8538);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("graded_side.poly");
    std::fs::write(&path, quadex::io::poly::write_poly(&d.boundary)).unwrap();
    let mut h = harness(open(&path));
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    h.step();
    settle(&mut h);
    assert!(h.state().doc().is_done());
    let stats = h.state().doc().mesher().unwrap().stats().clone();
    assert!(stats.refanned);
    assert_eq!(stats.count(StepKind::Fill), 0);
    let last = h.state().doc().last().cloned().unwrap();
    assert_eq!(last.kind, StepKind::Refan);
    h.get_by_label("made again with balanced corner fans: no fill");
    h.get_by_label_contains("(run made again with balanced corner fans)");
    assert!(h
        .query_by_label_contains("the region fill (not extraction) made")
        .is_none());
    let steps = h.state().doc().steps();
    assert!(status(&h).ends_with("(the run made again with balanced corner fans)"));
    // Undo takes back the steps of the run made again, one by one.
    h.state_mut().apply(Command::Undo);
    assert_eq!(h.state().doc().steps(), steps - 1);
    assert!(
        status(&h).starts_with(&format!("undone: step ({} steps left", steps - 1)),
        "{}",
        status(&h)
    );
}

/// 10a'. The side panels keep their width while stepping, correcting and
///       refitting: a new table row (the last step's) does not widen a
///       panel and shift the canvas under the pointer.
#[test]
fn issue17_the_canvas_stays_put_while_stepping() {
    for tab in ["Quality", "Model"] {
        let mut h = harness_sized(example_named("plate_hole.poly"), 1000.0, 650.0);
        h.run();
        h.get_by_label(tab).click();
        settle(&mut h);
        let r0 = h.state().view.canvas_rect;
        for k in 0..40 {
            let cmd = match k {
                10 => Command::AppendLast,
                20 => Command::Refit {
                    form: Form::Quadratic,
                    mesh_rest: false,
                },
                _ => Command::Step,
            };
            h.state_mut().apply(cmd);
            settle(&mut h);
            let r = h.state().view.canvas_rect;
            assert!(
                (r.left() - r0.left()).abs() <= 1.0 && (r.right() - r0.right()).abs() <= 1.0,
                "{tab}: the canvas moved at step {k}: {r:?}, was {r0:?}"
            );
        }
    }
}

/// 10b. The last step's labels (P0, l1.., r1.., Pn) never overlap.
#[test]
fn issue17_step_labels_do_not_overlap() {
    for (w, hh, steps) in [(1000.0, 650.0, 5), (1400.0, 860.0, 12), (800.0, 500.0, 30)] {
        let mut h = harness_sized(example(), w, hh);
        h.run();
        h.state_mut().apply(Command::StepN(steps));
        h.run();
        let labels: Vec<(String, Rect)> = painted(&h)
            .into_iter()
            .filter(|(t, _, _)| {
                t == "P0"
                    || t == "Pn"
                    || (t.len() == 2 && (t.starts_with('l') || t.starts_with('r')))
            })
            .map(|(t, r, _)| (t, r))
            .collect();
        assert!(labels.iter().any(|(t, _)| t == "P0"), "{labels:?}");
        for (i, a) in labels.iter().enumerate() {
            for b in &labels[i + 1..] {
                assert!(
                    !a.1.intersects(b.1),
                    "{} and {} overlap at {w} x {hh}",
                    a.0,
                    b.0
                );
            }
        }
    }
}

/// A boundary away from the origin is meshed by the editor in the frame
/// the command line meshes it in (moved next to the origin, exactly): the
/// same mesh, the same file bytes, and corrections given in the file's
/// coordinates. Run in its own coordinates, this domain ends in another
/// mesh (129 quads against 133 as stepped).
#[test]
fn the_editor_meshes_a_domain_away_from_the_origin_as_the_command_line_does() {
    use quadex::domains::{generate, Family};
    let d = generate(Family::Unbalanced, 0xa23f69ab86b9b961);
    let (_, origin) = d.boundary.to_local();
    assert_ne!(origin, quadex::Point::ZERO, "the domain must be moved");
    let dir = tempfile::tempdir().unwrap();
    let poly = dir.path().join("away.poly");
    std::fs::write(&poly, quadex::io::poly::write_poly(&d.boundary)).unwrap();
    // The command line's mesh.
    let settings = Settings::default();
    let params = quadex::Params {
        extract: settings.params(),
        finish: settings.finishing(),
    };
    let model: std::sync::Arc<dyn quadex::Model> = quadex::model::load("default").unwrap().into();
    let boundary = quadex::io::read_boundary(&poly).unwrap();
    let (cli, _) = quadex::mesh_boundary(&boundary, model, &params, |_| {}).unwrap();
    let cli_file = dir.path().join("cli.msh");
    quadex::io::write_mesh(&cli, &cli_file).unwrap();
    // The editor's, stepped to the end and exported.
    let mut h = harness(open(&poly));
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    assert!(h.state().doc().is_done());
    let out = dir.path().join("editor.msh");
    h.state_mut().apply(Command::Export(out.clone()));
    h.run();
    assert!(status(&h).starts_with("wrote"), "{}", status(&h));
    assert_eq!(
        std::fs::read(&out).unwrap(),
        std::fs::read(&cli_file).unwrap()
    );
    // A correction in world coordinates: the model's own Pn, given back,
    // makes the same element (moved into the mesher's frame and out, to
    // rounding).
    h.state_mut().apply(Command::Reset);
    h.state_mut().apply(Command::StepN(5));
    h.run();
    let last = h.state().doc().last().cloned().unwrap();
    assert_eq!(last.kind, StepKind::Element);
    let pn = h.state().doc().mesher().unwrap().mesh().nodes[last.pn_node().unwrap() as usize];
    h.state_mut().apply(Command::CorrectLast {
        element_type: ElementType::New,
        pn,
        snap_to: None,
    });
    h.run();
    assert!(
        status(&h).starts_with("element corrected"),
        "{}",
        status(&h)
    );
    let doc = h.state().doc();
    let after = doc.last().unwrap();
    let moved = doc.mesher().unwrap().mesh().nodes[after.pn_node().unwrap() as usize];
    assert!(
        moved.distance(pn) <= 1e-12 * origin.length(),
        "{pn} {moved}"
    );
    // A project of it opens with the same mesh (its actions are kept in
    // the mesher's frame).
    let mesh = doc.mesher().unwrap().mesh().clone();
    let project = dir.path().join("away.quadex.json");
    h.state_mut().apply(Command::SaveProject(project.clone()));
    assert!(status(&h).starts_with("saved"), "{}", status(&h));
    let (reopened, _) = Document::open(&project, Settings::default()).unwrap();
    assert_eq!(reopened.mesher().unwrap().mesh(), &mesh);
}

/// A step that is not the model's still marks its reference point: the
/// circle's first step is a square cut, and P0 is drawn at the node the
/// step panel names.
#[test]
fn a_square_cut_marks_its_reference_point() {
    let mut h = harness(open(&boundary("circle.poly")));
    h.run();
    h.state_mut().apply(Command::Step);
    h.run();
    let last = h.state().doc().last().cloned().unwrap();
    assert_eq!(last.kind, StepKind::Square);
    assert!(last.leading.is_empty());
    let p0 = h.state().doc().mesher().unwrap().mesh().nodes[last.reference.unwrap() as usize];
    let at = screen(&h, p0);
    let label = painted(&h)
        .into_iter()
        .find(|(t, _, _)| t == "P0")
        .expect("a P0 label");
    assert!(
        label.1.center().distance(at) < 40.0,
        "{label:?} far from {at:?}"
    );
}

/// The texts painted in the last frame that were cut short ("…").
fn elided(h: &Harness<'static, App>) -> Vec<String> {
    fn walk(s: &egui::Shape, out: &mut Vec<String>) {
        match s {
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, out)),
            egui::Shape::Text(t) if t.galley.elided => out.push(t.galley.job.text.clone()),
            _ => {}
        }
    }
    let mut out = Vec::new();
    for c in &h.output().shapes {
        walk(&c.shape, &mut out);
    }
    out
}

/// At fit view on a large mesh the last step's labels do not pile up
/// (P0 is ringed); Z (View ▸ Zoom to the last step) zooms to it and the
/// labels show; the tool bar's hint is not cut off.
#[test]
fn the_last_step_is_ringed_at_fit_view_and_zoomed_to_with_z() {
    let mut h = harness(open(&boundary("disk1600.poly")));
    h.run();
    h.state_mut().apply(Command::StepN(3));
    h.run();
    let texts = |h: &Harness<'static, App>| -> Vec<String> {
        painted(h).into_iter().map(|t| t.0).collect()
    };
    for l in ["P0", "l1", "r1"] {
        assert!(!texts(&h).iter().any(|t| t == l), "{l} painted at fit view");
    }
    assert!(elided(&h).is_empty(), "cut off: {:?}", elided(&h));
    let hint = texts(&h)
        .into_iter()
        .find(|t| t.starts_with("Click a ringed node") || t.starts_with("Drag Pn"))
        .expect("the correct tool's hint");
    assert!(hint.len() > 100, "{hint}");
    let zoom = h.state().view.canvas.zoom;
    h.key_press(egui::Key::Z);
    h.run();
    assert!(h.state().view.canvas.zoom > 10.0 * zoom, "{}", status(&h));
    for l in ["P0", "l1", "r1"] {
        assert!(texts(&h).iter().any(|t| t == l), "{l} not painted after Z");
    }
    // The View menu has it too.
    h.get_by_label("View").click();
    h.run();
    h.get_by_label_contains("Zoom to the last step");
}

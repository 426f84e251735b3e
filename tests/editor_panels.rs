//! The editor's right-hand panels, clicked through with egui_kittest:
//! settings, Quality, Smoothing (the finishing pass) and Compare.
#![cfg(feature = "gui")]

mod common;

use common::editor::*;
use egui::Pos2;
use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use quadex::app::{App, Command, MeshKind, Settings};
use quadex::model::Form;
use std::path::PathBuf;
use std::time::{Duration, Instant};

#[test]
fn changing_the_model_restarts_the_mesh() {
    let mut h = stepped_example(3);
    let s = Settings {
        model: "rules".into(),
        ..Settings::default()
    };
    h.state_mut().apply(Command::SetSettings(s));
    h.run();
    assert_eq!(h.state().doc().steps(), 0);
    assert_eq!(h.state().doc().mesher().unwrap().model().name(), "rules");
    // An unknown model file is refused and the settings stay.
    let bad = Settings {
        model: "/no/such/model.json".into(),
        ..Settings::default()
    };
    h.state_mut().apply(Command::SetSettings(bad));
    assert!(status(&h).starts_with("error:"));
    assert_eq!(h.state().doc().settings.model, "rules");
    // A fitted model from a file (the model button's dialog gives a path).
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/models/default.json");
    h.state_mut().apply(Command::UseModel(file.clone()));
    assert_eq!(h.state().doc().settings.model, file.display().to_string());
    h.state_mut().apply(Command::Step);
    assert_eq!(h.state().doc().steps(), 1);
}

/// A comparison that meshed a refitted model whose refit is then undone
/// says so, rather than show it as one of the document's models.
#[test]
fn the_compare_panel_says_when_a_compared_model_is_gone() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::Refit {
        form: Form::Quadratic,
        mesh_rest: false,
    });
    // The refit is made in the background: wait for it.
    h.state_mut().wait();
    let name = h.state().doc().models[0].name.clone();
    h.get_by_label("Compare").click();
    h.run();
    // The refitted model comes ticked, beside the built-in ones.
    assert!(h.state().panels.compare.chosen.contains(&name));
    h.state_mut().apply(Command::Compare(vec![name.clone()]));
    wait_for_comparison(&mut h);
    let gone = format!("{name} no longer in the document (its refit undone): compare again");
    assert!(h.query_by_label(&gone).is_none());
    h.state_mut().apply(Command::Undo);
    h.run();
    h.get_by_label(&gone);
}

#[test]
fn panels_show_the_model_samples_quality_and_smoothing() {
    let mut h = stepped_example(5);
    h.state_mut().apply(Command::AppendLast);
    h.run();
    // Quality: the figures of the mesh so far.
    h.get_by_label("Quality").click();
    h.run();
    h.get_by_label("scaled Jacobian mean");
    // Model: the fit table and the critical factors of the samples.
    h.get_by_label("Model").click();
    h.step();
    // Measured in a thread (seconds on the reference samples): the panel
    // says so meanwhile.
    assert!(h.state().measuring());
    h.get_by_label_contains("on the samples…");
    settle(&mut h);
    assert!(!h.state().measuring());
    h.get_by_label_contains("type accuracy");
    h.get_by_label_contains("Critical factors");
    h.get_by_label("RMSE");
    // Training set: the table, export and import, delete.
    h.get_by_label("Training set").click();
    h.run();
    h.get_by_label_contains("1 shown");
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("samples.csv");
    h.state_mut().apply(Command::ExportSamples(csv.clone()));
    h.state_mut().apply(Command::ImportSamples(csv.clone()));
    assert_eq!(h.state().doc().training.len(), 2);
    h.run();
    h.get_by_label("Select shown").click();
    h.run();
    h.get_by_label("Delete selected").click();
    h.run();
    assert_eq!(h.state().doc().training.len(), 0);
    h.state_mut().apply(Command::Undo);
    assert_eq!(h.state().doc().training.len(), 2);
    // Smoothing: changing it keeps the steps.
    h.get_by_label("Smoothing").click();
    h.run();
    h.get_by_label("No smoothing").click();
    h.run();
    assert_eq!(h.state().doc().steps(), 5);
    assert_eq!(
        h.state().doc().settings.smooth,
        quadex::smooth::SmoothParams::OFF
    );
    // Collect from the finished mesh.
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    h.state_mut().apply(Command::CollectFromMesh);
    assert!(status(&h).contains("collected"), "{}", status(&h));
    assert!(h.state().doc().training.len() > 10);
    // As many as `quadex samples --turn 35,300` takes from the same mesh
    // (the status names the option).
    let finished = h.state().doc().finished().unwrap().clone();
    let params = quadex::samples::CollectParams {
        turn: quadex::reference::DEFAULT_MODEL_TURN,
        ..quadex::samples::CollectParams::DEFAULT
    };
    let direct = quadex::samples::TrainingSet::collect(&[("m".into(), finished)], 7, &params);
    assert!(
        status(&h).starts_with(&format!("{} samples collected", direct.len()))
            && status(&h).contains("--turn 35,300"),
        "{}",
        status(&h)
    );
    h.get_by_label("as stepped");
}

/// 7. A finishing-settings change on a large mesh keeps the finished mesh
///    on the canvas (marked as being updated) and Export enabled; no step
///    is highlighted; an export waits for the new finished mesh.
#[test]
fn issue17_a_smoothing_change_keeps_the_finished_mesh_and_export() {
    let mut h = harness(open(&boundary("disk400.poly")));
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    h.step();
    settle(&mut h);
    assert_eq!(h.state().shown_kind(), MeshKind::Finished);
    h.get_by_label("Smoothing").click();
    h.run();
    h.get_by_label("No smoothing").click();
    h.step();
    h.step();
    assert_eq!(h.state().shown_kind(), MeshKind::Updating);
    assert!(!h.get_by_label("Export mesh").accesskit_node().is_disabled());
    let yellow = egui::Color32::from_rgb(255, 230, 60);
    assert_eq!(strokes_of(&h, yellow), 0, "a step is highlighted");
    h.get_by_label_contains("Updating the finished mesh");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("disk400.msh");
    h.state_mut().apply(Command::Export(out.clone()));
    settle(&mut h);
    assert!(status(&h).starts_with("wrote"), "{}", status(&h));
    assert_eq!(h.state().shown_kind(), MeshKind::Finished);
    let written = quadex::io::read_mesh(&out).unwrap();
    let mut expected = h.state().doc().clone();
    expected.settings.smooth = quadex::smooth::SmoothParams::OFF;
    assert_eq!(
        written.quads.len(),
        expected.finished().unwrap().quads.len()
    );
}

/// 9. The panels say which mesh they count: the left panel the mesh as
///    stepped, the Quality panel the finished mesh (and the stepped count
///    beside it).
#[test]
fn issue17_the_panels_say_which_mesh_they_count() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    h.step();
    settle(&mut h);
    let stepped = h.state().doc().mesher().unwrap().mesh().quads.len();
    let finished = h.state().doc().finished().unwrap().quads.len();
    assert_ne!(stepped, finished);
    h.get_by_label_contains(&format!("{stepped} quads as stepped"));
    h.get_by_label(&format!(
        "The finished mesh (cleaned up, coarsened, remeshed and smoothed): {finished} quads; the mesh as stepped has {stepped} quads."
    ));
}

#[test]
fn the_compare_panel_meshes_the_boundary_with_each_model() {
    let mut h = harness(example());
    h.run();
    h.get_by_label("Compare").click();
    h.run();
    // Two of the four built-in models, to be quick.
    for name in ["thesis", "ann"] {
        h.get_by_role_and_label(egui::accesskit::Role::CheckBox, name)
            .click();
    }
    h.run();
    h.get_by_label("Compare models").click();
    h.step();
    assert!(h.state().comparing());
    wait_for_comparison(&mut h);
    // The status line says it is done (not "comparing" any more).
    assert_eq!(
        status(&h),
        "compared 2 models: 2 finished (the Compare panel)"
    );
    // The table: a heading per column, a row per model.
    for col in quadex::compare::COLUMNS {
        h.get_by_label(col);
    }
    let c = h.state().comparison().expect("a comparison");
    let names: Vec<&str> = c.outcomes.iter().map(|o| o.model.as_str()).collect();
    assert_eq!(names, ["default", "rules"]);
    // The same figures as `quadex compare` (the core's comparison, with the
    // editor's default settings).
    let b = h.state().doc().boundary().unwrap().clone();
    for o in &c.outcomes {
        let model: std::sync::Arc<dyn quadex::Model> =
            std::sync::Arc::from(quadex::model::builtin(&o.model).unwrap());
        let direct = quadex::compare::mesh_with(&o.model, &b, model, &quadex::Params::DEFAULT);
        assert_eq!(o.quads, direct.quads);
        assert_eq!(o.sj_mean, direct.sj_mean);
        assert_eq!(o.accepted_share, direct.accepted_share);
        assert_eq!(o.rescaled_share, direct.rescaled_share);
        assert!(o.finished && o.quads > 200, "{o:?}");
        // Each row's figures are on screen.
        for v in o.figures().unwrap() {
            assert!(
                !h.query_all_by_label(&v).collect::<Vec<_>>().is_empty(),
                "{v}"
            );
        }
    }
}

/// A quad's tip opens towards the middle of the canvas: near the canvas's
/// right edge it stays off the right panel's figures.
#[test]
fn a_quads_tip_stays_over_the_canvas() {
    let mut h = harness(example());
    h.run();
    h.get_by_label_contains("Run to end").click();
    h.step();
    settle(&mut h);
    assert!(h.state().doc().is_done());
    let r = h.state().view.canvas_rect;
    let b = h.state().doc().boundary().unwrap().clone();
    let xs = b.points.iter().map(|&p| screen(&h, p).x);
    let (left, right) = xs.fold((f32::INFINITY, 0.0f32), |(l, r), x| (l.min(x), r.max(x)));
    let y = screen(&h, quadex::Point::new(0.0, 0.0)).y;
    for (at, towards_left) in [(right - 8.0, true), (left + 8.0, false)] {
        let pointer = Pos2::new(at, y);
        h.hover_at(pointer);
        h.run();
        h.run();
        let tip = painted(&h)
            .into_iter()
            .find(|(t, _, _)| t == "thesis criteria")
            .map(|(_, rect, _)| rect)
            .expect("the quad's tip");
        assert!(r.contains_rect(tip), "{tip:?} off the canvas {r:?}");
        if towards_left {
            assert!(tip.right() < pointer.x, "{tip:?} {pointer:?}");
        } else {
            assert!(tip.left() > pointer.x, "{tip:?} {pointer:?}");
        }
    }
}

#[test]
fn chord_coarsening_is_turned_off_in_the_finishing_panel_without_stepping_again() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    h.step();
    settle(&mut h);
    let steps = h.state().doc().steps();
    let with = h.state().doc().finished().unwrap().quads.len();
    h.get_by_label("Smoothing").click();
    h.run();
    h.get_by_label("No coarsening").click();
    let without = refinished(&mut h, with);
    assert_eq!(
        h.state().doc().settings.coarsen,
        quadex::finish::coarsen::CoarsenParams::OFF
    );
    assert_eq!(h.state().doc().steps(), steps);
    // As the command line finishes the same boundary with --no-coarsen.
    let b = quadex::io::read_boundary(&boundary("annulus.poly")).unwrap();
    let model = std::sync::Arc::new(quadex::model::default_model().unwrap());
    let params = quadex::Params {
        finish: quadex::FinishParams {
            coarsen: quadex::finish::coarsen::CoarsenParams::OFF,
            ..quadex::FinishParams::DEFAULT
        },
        ..quadex::Params::default()
    };
    let (cli, _) = quadex::mesh_boundary(&b, model, &params, |_| {}).unwrap();
    assert_eq!(without, cli.quads.len());
    assert!(without > with, "{without} quads without, {with} with");
    // Defaults bring it back.
    h.get_by_label("Defaults").click();
    assert_eq!(refinished(&mut h, without), with);
}

/// Runs frames until a finished mesh of other than `quads` quads is shown
/// (after a change of the finishing settings, which waits a moment before
/// finishing again); returns its quad count.
fn refinished(h: &mut Harness<'static, App>, quads: usize) -> usize {
    let t = Instant::now();
    loop {
        h.step();
        let shown = (h.state().shown_kind() == MeshKind::Finished && !h.state().finishing())
            .then(|| h.state().doc().finished().ok().map(|m| m.quads.len()))
            .flatten();
        if let Some(n) = shown.filter(|&n| n != quads) {
            return n;
        }
        assert!(
            t.elapsed().as_secs() < 120,
            "the mesh was not finished again"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The Quality panel counts the quads that miss a criterion: disk1600's
/// finished mesh without the local remeshing has quads with an angle below
/// 45°, few enough that a share would read 100.0 %.
#[test]
fn the_quality_panel_counts_the_quads_outside_the_angle_range() {
    let settings = Settings {
        remesh: quadex::finish::remesh::RemeshParams::OFF,
        ..Settings::default()
    };
    let doc = quadex::app::Document::open(&boundary("disk1600.poly"), settings).unwrap();
    let mut h = harness(App::new(doc.0));
    h.run();
    h.get_by_label("Quality").click();
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    let mesh = h.state().doc().finished().unwrap();
    let n = mesh.quads.len();
    let outside = mesh
        .quads
        .iter()
        .filter(|q| !quadex::quality::QuadQuality::of(mesh.corners(q)).angles_ok())
        .count();
    assert!(
        outside > 0 && (outside as f64) < 0.0005 * n as f64,
        "{outside} of {n}"
    );
    let want = format!("{} of {} outside", outside, quadex::compare::grouped(n));
    h.get_by_label(&want);
    assert!(
        h.query_by_label("100.0 %").is_none(),
        "a share reads 100.0 % with {outside} quads outside"
    );
}

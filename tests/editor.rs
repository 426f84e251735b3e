//! The editor clicked through with egui_kittest (no window, no GPU): the
//! same `App::ui` the window runs.

use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use quadex::app::{App, Command, Document, Settings};
use std::path::PathBuf;

fn bench() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/bench")
}

/// `tools/judge.py` accepts `mesh` as a mesh of the annulus example.
fn assert_judged_valid(mesh: &std::path::Path) {
    let judge = std::process::Command::new("python3")
        .arg(bench().join("tools/judge.py"))
        .arg(bench().join("boundaries/annulus.poly"))
        .arg(mesh)
        .output()
        .expect("python3 runs the judge");
    let verdict = String::from_utf8_lossy(&judge.stdout);
    assert!(verdict.contains("\"valid\": true"), "{verdict}");
}

fn harness(app: App) -> Harness<'static, App> {
    Harness::builder()
        .with_size([1280.0, 800.0])
        .build_state(|ctx, app: &mut App| app.ui(ctx), app)
}

fn example() -> App {
    App::new(Document::open(&quadex::app::example_path(), Settings::default()).unwrap())
}

#[test]
fn step_undo_run_and_export_a_mesh_the_judge_accepts() {
    let mut h = harness(example());
    h.run();
    for _ in 0..5 {
        h.get_by_label_contains("(Space)").click();
        h.run();
    }
    assert_eq!(h.state().doc.mesher.steps(), 5);
    let last = h.state().doc.last.clone().expect("a step report");
    assert!(last.reference.is_some() && !last.leading.is_empty());
    // The panel shows what the step did.
    h.get_by_label("remedy");
    h.get_by_label_contains("Undo step").click();
    h.run();
    assert_eq!(h.state().doc.mesher.steps(), 4);
    h.get_by_label_contains("Run to end").click();
    h.run();
    assert!(h.state().doc.is_done());
    h.get_by_label("mesh complete");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("annulus.msh");
    h.state_mut().export_path = out.display().to_string();
    h.get_by_label("Export mesh").click();
    h.run();
    assert!(
        h.state().status.starts_with("wrote"),
        "{}",
        h.state().status
    );
    assert_judged_valid(&out);
}

#[test]
fn keyboard_shortcuts_step_and_undo() {
    let mut h = harness(example());
    h.run();
    h.key_press(egui::Key::Space);
    h.run();
    h.key_press(egui::Key::Space);
    h.run();
    assert_eq!(h.state().doc.mesher.steps(), 2);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc.mesher.steps(), 1);
}

#[test]
fn a_bad_file_shows_an_error_and_keeps_the_document() {
    let mut h = harness(example());
    h.run();
    h.get_by_label_contains("(Space)").click();
    h.run();
    for bad in ["bowtie.poly", "nan.poly", "garbage.poly", "odd_count.poly"] {
        h.state_mut()
            .apply(Command::Open(bench().join("bad").join(bad)));
        h.run();
        let s = h.state();
        assert!(
            s.status.starts_with("error:") && s.status.contains(bad),
            "{}",
            s.status
        );
        assert_eq!(s.doc.name(), "annulus.poly");
        assert_eq!(s.doc.mesher.steps(), 1);
    }
    // The message is on screen.
    h.get_by_label_contains("error:");
}

#[test]
fn changing_the_model_restarts_the_mesh() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(3));
    let s = Settings {
        model: "rules".into(),
        ..Settings::default()
    };
    h.state_mut().apply(Command::SetSettings(s));
    h.run();
    assert_eq!(h.state().doc.mesher.steps(), 0);
    assert_eq!(h.state().doc.mesher.model().name(), "rules");
    // An unknown model file is refused and the settings stay.
    let bad = Settings {
        model: "/no/such/model.json".into(),
        ..Settings::default()
    };
    h.state_mut().apply(Command::SetSettings(bad));
    assert!(h.state().status.starts_with("error:"));
    assert_eq!(h.state().doc.settings.model, "rules");
}

#[test]
fn correct_append_refit_and_finish() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(5));
    h.run();
    let last = h.state().doc.last.clone().unwrap();
    assert_eq!(last.kind, quadex::extract::StepKind::Element);
    // Move the new node a little towards P0 and commit that instead.
    let m = h.state().doc.mesher.mesh().clone();
    let p0 = last.reference.unwrap();
    let (pn, at_p0) = (
        m.nodes[last.pn_node().unwrap() as usize],
        m.nodes[p0 as usize],
    );
    let moved = pn + (at_p0 - pn) * 0.05;
    h.state_mut().apply(Command::CorrectLast {
        element_type: quadex::ElementType::New,
        pn: moved,
    });
    h.run();
    let s = h.state();
    assert!(s.status.starts_with("element corrected"), "{}", s.status);
    assert_eq!(s.doc.mesher.steps(), 5);
    assert_eq!(
        s.doc.last.as_ref().unwrap().kind,
        quadex::extract::StepKind::Correction
    );
    assert_eq!(s.doc.training.len(), 1);
    let new_node = s.doc.last.as_ref().unwrap().new_nodes[0];
    assert!((s.doc.mesher.mesh().nodes[new_node as usize] - moved).length() < 1e-12);
    // Append the corrected element again from the panel (a counter shows it).
    h.get_by_label("Append as sample").click();
    h.run();
    assert_eq!(h.state().doc.training.len(), 2);
    h.get_by_label_contains("2 samples of yours");
    // Refit in one click: figures before and after; the rest of the mesh
    // uses the new model.
    h.get_by_label("Refit").click();
    h.run();
    let f = h.state().refit.clone().expect("refit figures");
    assert_eq!(f.corrections, 2);
    assert!(f.after.0.accuracy > 0.95 && f.after.1.r > 0.95, "{f:?}");
    assert!(h.state().doc.mesher.model().name().starts_with("fitted"));
    h.get_by_label("before");
    // Undo keeps the refit model for what comes next.
    h.state_mut().apply(Command::Undo);
    assert!(h.state().doc.mesher.model().name().starts_with("fitted"));
    h.get_by_label_contains("Run to end").click();
    h.run();
    assert!(h.state().doc.is_done());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("annulus.vtu");
    h.state_mut().apply(Command::Export(out.clone()));
    assert_judged_valid(&out);
}

#[test]
fn an_invalid_correction_changes_nothing() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(3));
    let before = h.state().doc.mesher.mesh().clone();
    let last = h.state().doc.last.clone();
    // Pn far outside the domain: not a valid element.
    h.state_mut().apply(Command::CorrectLast {
        element_type: quadex::ElementType::New,
        pn: quadex::Point::new(100.0, 100.0),
    });
    let s = h.state();
    assert!(s.status.starts_with("error:"), "{}", s.status);
    assert_eq!(s.doc.mesher.mesh(), &before);
    assert_eq!(s.doc.mesher.steps(), 3);
    assert_eq!(s.doc.last, last);
    assert_eq!(s.doc.training.len(), 0);
}

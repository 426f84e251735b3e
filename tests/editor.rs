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
        .with_size([1400.0, 860.0])
        .build_state(|ctx, app: &mut App| app.ui(ctx), app)
}

/// Runs frames until the background run (if any) is over.
fn settle(h: &mut Harness<'static, App>) {
    let t = std::time::Instant::now();
    while h.state().busy() {
        assert!(
            t.elapsed().as_secs() < 300,
            "the background run did not end"
        );
        h.step();
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    h.run();
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
    h.get_by_label_contains("Undo  (").click();
    h.run();
    assert_eq!(h.state().doc.mesher.steps(), 4);
    h.get_by_label_contains("Redo  (").click();
    h.run();
    assert_eq!(h.state().doc.mesher.steps(), 5);
    // Run to end goes to the background: a progress bar, then the mesh.
    h.get_by_label_contains("Run to end").click();
    h.step();
    settle(&mut h);
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
fn a_mesh_file_opens_as_its_boundary_with_the_mesh_shown() {
    // A mesh written by the command line's library, read back as a document.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.msh");
    let b = quadex::io::read_boundary(&bench().join("boundaries/plate_hole.poly")).unwrap();
    let model = std::sync::Arc::new(quadex::model::RulesModel::DEFAULT);
    let (mesh, _) = quadex::mesh_boundary(&b, model, &quadex::Params::DEFAULT, |_| {}).unwrap();
    quadex::io::write_mesh(&mesh, &path).unwrap();
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::Open(path.clone()));
    h.run();
    let s = h.state();
    assert!(s.status.starts_with("opened"), "{}", s.status);
    assert_eq!(s.doc.name(), "plate.msh");
    assert_eq!(s.doc.boundary.node_count(), b.node_count());
    let shown = s.doc.imported().expect("the file's mesh is shown");
    assert_eq!(shown.quads.len(), mesh.quads.len());
    assert!(s.doc.has_mesh() && !s.doc.is_done());
    h.get_by_label_contains("showing the mesh read from plate.msh");
    // Its quality, its samples and an export, as for a finished mesh.
    h.get_by_label("Quality").click();
    h.run();
    h.get_by_label("The mesh read from the file.");
    h.state_mut().apply(Command::CollectFromMesh);
    assert!(!h.state().doc.training.is_empty(), "{}", h.state().status);
    let out = dir.path().join("plate.vtk");
    h.state_mut().apply(Command::Export(out.clone()));
    assert!(
        h.state().status.starts_with("wrote"),
        "{}",
        h.state().status
    );
    // Stepping meshes the same boundary with quadex; undo shows the file's
    // mesh again.
    h.state_mut().apply(Command::Step);
    assert!(h.state().doc.imported().is_none());
    h.state_mut().apply(Command::Undo);
    assert!(h.state().doc.imported().is_some());
    // A project keeps the file's mesh.
    let project = dir.path().join("plate.quadex.json");
    h.state_mut().apply(Command::SaveProject(project.clone()));
    let reopened = Document::open(&project, Settings::default()).unwrap();
    assert_eq!(reopened.imported(), h.state().doc.imported());
    // A mesh file that is not one is refused and the document kept.
    let bad = dir.path().join("bad.msh");
    std::fs::write(&bad, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n").unwrap();
    h.state_mut().apply(Command::Open(bad));
    assert!(
        h.state().status.starts_with("error:"),
        "{}",
        h.state().status
    );
    assert_eq!(h.state().doc.name(), "plate.msh");
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
    // A fitted model from a file (the model button's dialog gives a path).
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/models/default.json");
    h.state_mut().apply(Command::UseModel(file.clone()));
    assert_eq!(h.state().doc.settings.model, file.display().to_string());
    h.state_mut().apply(Command::Step);
    assert_eq!(h.state().doc.mesher.steps(), 1);
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
        snap_to: None,
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
    // Refit in one click: figures before and after, and the rest of the
    // mesh regenerated with the new model (in the background).
    h.get_by_label("Refit").click();
    h.step();
    settle(&mut h);
    let f = h.state().refit.clone().expect("refit figures");
    assert_eq!(f.corrections, 2);
    assert!(f.after.0.accuracy > 0.95 && f.after.1.r > 0.95, "{f:?}");
    assert!(h.state().doc.mesher.model().name().starts_with("fitted"));
    h.get_by_label("before");
    assert!(h.state().doc.is_done());
    // The corrected step stays as the user made it.
    let kept = h.state().doc.mesher.actions()[4].clone();
    assert!(matches!(kept, quadex::extract::Action::Correction(_)));
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
        snap_to: None,
    });
    let s = h.state();
    assert!(s.status.starts_with("error:"), "{}", s.status);
    assert_eq!(s.doc.mesher.mesh(), &before);
    assert_eq!(s.doc.mesher.steps(), 3);
    assert_eq!(s.doc.last, last);
    assert_eq!(s.doc.training.len(), 0);
}

#[test]
fn undo_and_redo_every_edit() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(4));
    let stepped = h.state().doc.mesher.mesh().clone();
    // A correction (an edit) on top of steps.
    let last = h.state().doc.last.clone().unwrap();
    let pn = h.state().doc.mesher.mesh().nodes[last.pn_node().unwrap() as usize];
    h.state_mut().apply(Command::CorrectLast {
        element_type: quadex::ElementType::New,
        pn,
        snap_to: None,
    });
    assert_eq!(h.state().doc.training.len(), 1);
    let corrected = h.state().doc.mesher.mesh().clone();
    // New settings (an edit that restarts the mesh).
    let rules = Settings {
        model: "rules".into(),
        ..Settings::default()
    };
    h.state_mut().apply(Command::SetSettings(rules));
    assert_eq!(h.state().doc.mesher.steps(), 0);
    // Ctrl+Z twice: the settings, then the correction.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc.settings.model, "default");
    assert_eq!(h.state().doc.mesher.mesh(), &corrected);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc.training.len(), 0);
    assert_eq!(h.state().doc.mesher.mesh(), &stepped);
    // Ctrl+Shift+Z twice: the correction, then the settings.
    let redo = egui::Modifiers::COMMAND.plus(egui::Modifiers::SHIFT);
    h.key_press_modifiers(redo, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc.training.len(), 1);
    assert_eq!(h.state().doc.mesher.mesh(), &corrected);
    h.key_press_modifiers(redo, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc.settings.model, "rules");
    assert!(!h.state().history.can_redo());
    // Undo past the steps too, one at a time.
    for _ in 0..6 {
        h.state_mut().apply(Command::Undo);
    }
    assert_eq!(h.state().doc.mesher.steps(), 0);
    assert_eq!(h.state().doc.training.len(), 0);
    // A refit is an edit: undo brings the old model back, redo the new.
    h.state_mut().apply(Command::StepN(5));
    h.state_mut().apply(Command::AppendLast);
    h.state_mut()
        .apply(Command::Refit(quadex::model::Form::Quadratic));
    assert!(h.state().doc.mesher.model().name().starts_with("fitted"));
    h.state_mut().apply(Command::Undo);
    assert!(!h.state().doc.mesher.model().name().starts_with("fitted"));
    h.state_mut().apply(Command::Redo);
    assert!(h.state().doc.mesher.model().name().starts_with("fitted"));
}

#[test]
fn a_project_saves_and_opens_whole() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(6));
    h.state_mut().apply(Command::AppendLast);
    h.state_mut()
        .apply(Command::Refit(quadex::model::Form::Quadratic));
    h.state_mut().apply(Command::StepN(3));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("annulus.quadex.json");
    h.state_mut().apply(Command::SaveProject(path.clone()));
    assert!(
        h.state().status.starts_with("saved"),
        "{}",
        h.state().status
    );
    assert!(!h.state().dirty);
    let mesh = h.state().doc.mesher.mesh().clone();
    let mut other = harness(example());
    other.run();
    other.state_mut().apply(Command::Open(path.clone()));
    let s = other.state();
    assert!(s.status.starts_with("opened"), "{}", s.status);
    assert_eq!(s.doc.mesher.steps(), 9);
    assert_eq!(s.doc.mesher.mesh(), &mesh);
    assert_eq!(s.doc.training.len(), 1);
    assert!(s.doc.mesher.model().name().starts_with("fitted"));
    assert_eq!(s.project_path.as_deref(), Some(path.as_path()));
    // Stepping carries on, and undo too.
    other.state_mut().apply(Command::Step);
    other.state_mut().apply(Command::Undo);
    assert_eq!(other.state().doc.mesher.mesh(), &mesh);
    // A project whose steps do not replay is refused.
    let text = std::fs::read_to_string(&path).unwrap();
    let broken = dir.path().join("broken.json");
    std::fs::write(
        &broken,
        text.replace("\"quadex-project\"", "\"something-else\""),
    )
    .unwrap();
    other.state_mut().apply(Command::Open(broken));
    assert!(other.state().status.starts_with("error:"));
    assert_eq!(other.state().doc.mesher.steps(), 9);
}

#[test]
fn panels_show_the_model_samples_quality_and_smoothing() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(5));
    h.state_mut().apply(Command::AppendLast);
    h.run();
    // Quality: the figures of the mesh so far.
    h.get_by_label("Quality").click();
    h.run();
    h.get_by_label("scaled Jacobian mean");
    // Model: the fit table and the critical factors of the samples.
    h.get_by_label("Model").click();
    h.run();
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
    assert_eq!(h.state().doc.training.len(), 2);
    h.run();
    h.get_by_label("Select shown").click();
    h.run();
    h.get_by_label("Delete selected").click();
    h.run();
    assert_eq!(h.state().doc.training.len(), 0);
    h.state_mut().apply(Command::Undo);
    assert_eq!(h.state().doc.training.len(), 2);
    // Smoothing: changing it keeps the steps.
    h.get_by_label("Smoothing").click();
    h.run();
    h.get_by_label("No smoothing").click();
    h.run();
    assert_eq!(h.state().doc.mesher.steps(), 5);
    assert_eq!(
        h.state().doc.settings.smooth,
        quadex::smooth::SmoothParams::OFF
    );
    // Collect from the finished mesh.
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    h.state_mut().apply(Command::CollectFromMesh);
    assert!(
        h.state().status.contains("collected"),
        "{}",
        h.state().status
    );
    assert!(h.state().doc.training.len() > 10);
    h.get_by_label("as stepped");
}

#[test]
fn a_background_run_can_be_cancelled() {
    let b = quadex::io::read_boundary(&bench().join("boundaries/disk6400.poly")).unwrap();
    let mut h = harness(App::new(
        Document::new(b, None, Settings::default()).unwrap(),
    ));
    // A first frame draws the domain; the run starts after it.
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    assert!(h.state().busy());
    h.step();
    h.get_by_label("Cancel").click();
    h.step();
    settle(&mut h);
    let s = h.state();
    assert!(s.status.starts_with("cancelled after"), "{}", s.status);
    assert!(!s.doc.is_done());
    let steps = s.doc.mesher.steps();
    // The steps taken are kept and undo one at a time.
    h.state_mut().apply(Command::Undo);
    assert_eq!(h.state().doc.mesher.steps() + 1, steps);
}

/// A primary click at a screen position.
fn click_at(h: &mut Harness<'static, App>, pos: egui::Pos2) {
    h.hover_at(pos);
    h.run();
    h.drag_at(pos);
    h.run();
    h.drop_at(pos);
    h.run();
}

#[test]
fn boundary_edits_on_the_canvas_are_validated_live() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(3));
    h.run();
    let nodes = h.state().doc.boundary.node_count();
    h.get_by_label("split").click();
    h.run();
    let mid = |h: &Harness<'static, App>, k: usize| {
        let s = h.state();
        let l = &s.tools.draft.loops[0];
        let p = (l[k] + l[(k + 1) % l.len()]) * 0.5;
        s.view.to_screen(s.canvas_rect, p)
    };
    // Splitting one segment in two makes the node count odd: the problem
    // is listed and the document keeps its boundary.
    let p = mid(&h, 0);
    click_at(&mut h, p);
    assert!(h.state().tools.problem.is_some());
    assert_eq!(h.state().doc.boundary.node_count(), nodes);
    assert_eq!(h.state().doc.mesher.steps(), 3);
    h.get_by_label_contains("not a valid boundary yet");
    // A second split makes it even: the boundary changes, the mesh restarts.
    let p = mid(&h, 10);
    click_at(&mut h, p);
    assert!(h.state().tools.problem.is_none());
    assert_eq!(h.state().doc.boundary.node_count(), nodes + 2);
    assert_eq!(h.state().doc.mesher.steps(), 0);
    // Undo brings the boundary and the steps back.
    h.state_mut().apply(Command::Undo);
    h.run();
    assert_eq!(h.state().doc.boundary.node_count(), nodes);
    assert_eq!(h.state().doc.mesher.steps(), 3);
    assert_eq!(h.state().tools.draft.node_count(), nodes);
    // An invalid draft's edits are undone first (Ctrl+Z), without touching
    // the document's steps; redo takes the edit again.
    let p = mid(&h, 0);
    click_at(&mut h, p);
    assert!(h.state().tools.problem.is_some());
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert!(h.state().tools.problem.is_none(), "{}", h.state().status);
    assert_eq!(h.state().tools.draft.node_count(), nodes);
    assert_eq!(h.state().doc.mesher.steps(), 3);
    h.state_mut().apply(Command::Redo);
    assert_eq!(h.state().tools.draft.node_count(), nodes + 1);
    assert!(h.state().tools.problem.is_some());
    assert_eq!(h.state().doc.mesher.steps(), 3);
}

#[test]
fn dragging_pn_on_the_canvas_corrects_the_element() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(5));
    h.run();
    let last = h.state().doc.last.clone().unwrap();
    let pn = h.state().doc.mesher.mesh().nodes[last.pn_node().unwrap() as usize];
    let s = h.state().view.to_screen(h.state().canvas_rect, pn);
    // Drag the handle a few pixels towards P0 and let go.
    let p0 = h.state().doc.mesher.mesh().nodes[last.reference.unwrap() as usize];
    let t = h.state().view.to_screen(h.state().canvas_rect, p0);
    let to = s + (t - s) * 0.15;
    h.hover_at(s);
    h.run();
    h.drag_at(s);
    h.run();
    for k in 1..=5 {
        h.hover_at(s + (to - s) * (k as f32 / 5.0));
        h.run();
    }
    h.drop_at(to);
    h.run();
    let st = h.state();
    assert!(st.status.starts_with("element corrected"), "{}", st.status);
    assert_eq!(st.doc.training.len(), 1);
    let new_node = st.doc.last.as_ref().unwrap().new_nodes[0];
    let moved = st.doc.mesher.mesh().nodes[new_node as usize];
    assert!(moved.distance(pn) > 1e-6);
    assert_eq!(st.doc.mesher.steps(), 5);
}

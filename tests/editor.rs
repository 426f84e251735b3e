//! The editor clicked through with egui_kittest (no window, no GPU): the
//! same `App::ui` the window runs. The tests named after issue 17 drive
//! the problems it lists; several move the pointer on the canvas itself
//! (press, drag, release at screen positions).

use egui::{Pos2, Rect};
use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use quadex::app::tools::Hover;
use quadex::app::{App, Ask, Command, Document, MeshKind, Settings};
use quadex::extract::StepKind;
use quadex::model::{ElementType, Form};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn bench() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// `mesh` is a valid mesh of the annulus: quadex's reader takes it, which
/// checks it (convex quads, every edge used by one or two quads of opposite
/// orientations, the boundary loops a valid boundary, the quads covering the
/// enclosed area once), and its boundary nodes are the annulus's nodes
/// exactly, none added.
fn assert_valid_annulus_mesh(mesh: &Path) {
    let m = quadex::io::read_mesh(mesh).unwrap_or_else(|e| panic!("{}: {e}", mesh.display()));
    let b = quadex::io::read_boundary(&boundary("annulus.poly")).unwrap();
    let bits = |p: &quadex::Point| (p.x.to_bits(), p.y.to_bits());
    let mut want: Vec<(u64, u64)> = b.points.iter().map(bits).collect();
    let mut got: Vec<(u64, u64)> = m
        .loops
        .iter()
        .flatten()
        .map(|&v| bits(&m.nodes[v as usize]))
        .collect();
    want.sort_unstable();
    got.sort_unstable();
    assert_eq!(got, want, "the boundary nodes of {}", mesh.display());
    assert_eq!(m.loops.len(), b.loops.len());
}

fn harness_sized(app: App, w: f32, h: f32) -> Harness<'static, App> {
    Harness::builder()
        .with_size([w, h])
        .build_state(|ctx, app: &mut App| app.ui(ctx), app)
}

fn harness(app: App) -> Harness<'static, App> {
    harness_sized(app, 1400.0, 860.0)
}

/// Runs frames until the background work (a run, the finishing pass) is
/// over.
fn settle(h: &mut Harness<'static, App>) {
    let t = Instant::now();
    loop {
        h.step();
        let idle = |h: &Harness<'static, App>| {
            !h.state().busy() && !h.state().finishing() && !h.state().measuring()
        };
        if idle(h) {
            h.step();
            if idle(h) {
                break;
            }
        }
        assert!(
            t.elapsed().as_secs() < 300,
            "the background work did not end"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    h.run();
}

/// Waits for a comparison running in the background to end, then lets the
/// window take it in.
fn wait_for_comparison(h: &mut Harness<'static, App>) {
    let t = Instant::now();
    while h.state().comparing() {
        assert!(t.elapsed().as_secs() < 300, "the comparison did not end");
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    h.run();
}

/// The example open in a harness, `steps` steps taken.
fn stepped_example(steps: usize) -> Harness<'static, App> {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(steps));
    h
}

fn example() -> App {
    example_named("annulus.poly")
}

fn example_named(name: &str) -> App {
    App::new(Document::example(name, Settings::default()).unwrap())
}

fn open(path: &Path) -> App {
    App::new(Document::open(path, Settings::default()).unwrap().0)
}

fn boundary(name: &str) -> PathBuf {
    bench().join("boundaries").join(name)
}

/// The screen position of a world point on the canvas.
fn screen(h: &Harness<'static, App>, p: quadex::Point) -> Pos2 {
    let s = h.state();
    s.view.canvas.to_screen(s.view.canvas_rect, p)
}

/// A primary click at a screen position.
fn click_at(h: &mut Harness<'static, App>, pos: Pos2) {
    h.hover_at(pos);
    h.run();
    h.drag_at(pos);
    h.run();
    h.drop_at(pos);
    h.run();
}

/// Press at `from`, move in steps, release at `to`.
fn drag(h: &mut Harness<'static, App>, from: Pos2, to: Pos2) {
    h.hover_at(from);
    h.run();
    h.drag_at(from);
    h.run();
    for k in 1..=6 {
        h.hover_at(from + (to - from) * (k as f32 / 6.0));
        h.run();
    }
    h.drop_at(to);
    h.run();
}

/// Every text painted in the last frame, with its screen rectangle and
/// font.
fn painted(h: &Harness<'static, App>) -> Vec<(String, Rect, egui::FontId)> {
    fn walk(s: &egui::Shape, out: &mut Vec<(String, Rect, egui::FontId)>) {
        match s {
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, out)),
            egui::Shape::Text(t) => {
                let font = t
                    .galley
                    .job
                    .sections
                    .first()
                    .map(|s| s.format.font_id.clone())
                    .unwrap_or_default();
                out.push((
                    t.galley.job.text.clone(),
                    t.galley.rect.translate(t.pos.to_vec2()),
                    font,
                ));
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    for c in &h.output().shapes {
        walk(&c.shape, &mut out);
    }
    out
}

/// Paths and circles painted in the last frame with this stroke colour.
fn strokes_of(h: &Harness<'static, App>, color: egui::Color32) -> usize {
    fn walk(s: &egui::Shape, c: egui::Color32, n: &mut usize) {
        match s {
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, c, n)),
            egui::Shape::Path(p) if p.stroke.color == egui::epaint::ColorMode::Solid(c) => *n += 1,
            egui::Shape::Circle(k) if k.stroke.color == c => *n += 1,
            _ => {}
        }
    }
    let mut n = 0;
    for s in &h.output().shapes {
        walk(&s.shape, color, &mut n);
    }
    n
}

fn status(h: &Harness<'static, App>) -> String {
    h.state().status().to_string()
}

// ---------------------------------------------------------------------
// The flows.

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
    // The panel shows what the step did.
    h.get_by_label("remedy");
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

#[test]
fn a_file_that_cannot_be_read_shows_an_error_and_keeps_the_document() {
    let mut h = harness(example());
    h.run();
    h.get_by_label_contains("(Space)").click();
    h.run();
    for bad in [
        "nan.poly",
        "garbage.poly",
        "truncated.poly",
        "open_chain.poly",
    ] {
        h.state_mut()
            .apply(Command::Open(bench().join("bad").join(bad)));
        h.run();
        let s = status(&h);
        assert!(s.starts_with("error:") && s.contains(bad), "{s}");
        assert_eq!(h.state().doc().name, "annulus.poly");
        assert_eq!(h.state().doc().steps(), 1);
    }
    // The message is on screen.
    h.get_by_label_contains("error:");
}

#[test]
fn a_mesh_file_opens_as_its_boundary_with_the_mesh_shown() {
    // A mesh written by the command line's library, read back as a document.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plate.msh");
    let b = quadex::io::read_boundary(&boundary("plate_hole.poly")).unwrap();
    let model = std::sync::Arc::new(quadex::model::RulesModel::DEFAULT);
    let (mesh, _) = quadex::mesh_boundary(&b, model, &quadex::Params::DEFAULT, |_| {}).unwrap();
    quadex::io::write_mesh(&mesh, &path).unwrap();
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::Open(path.clone()));
    h.run();
    assert!(status(&h).starts_with("opened"), "{}", status(&h));
    let d = h.state().doc();
    assert_eq!(d.name, "plate.msh");
    assert_eq!(d.boundary().unwrap().node_count(), b.node_count());
    let shown = d.imported().expect("the file's mesh is shown");
    assert_eq!(shown.quads.len(), mesh.quads.len());
    assert!(d.has_mesh() && !d.is_done());
    assert_eq!(h.state().shown_kind(), MeshKind::Imported);
    h.get_by_label_contains("showing the mesh read from plate.msh");
    // The Export box does not start on the file opened: an export would
    // overwrite it unasked.
    assert_eq!(
        Path::new(h.state().panels.export_path.trim()),
        dir.path().join("plate_quadex.msh")
    );
    // Its quality, its samples and an export, as for a finished mesh.
    h.get_by_label("Quality").click();
    h.run();
    h.get_by_label_contains("The mesh read from the file");
    h.state_mut().apply(Command::CollectFromMesh);
    assert!(!h.state().doc().training.is_empty(), "{}", status(&h));
    let out = dir.path().join("plate.vtk");
    h.state_mut().apply(Command::Export(out.clone()));
    assert!(status(&h).starts_with("wrote"), "{}", status(&h));
    // Stepping meshes the same boundary with quadex; undo shows the file's
    // mesh again.
    h.state_mut().apply(Command::Step);
    assert!(h.state().doc().imported().is_none());
    h.state_mut().apply(Command::Undo);
    assert!(h.state().doc().imported().is_some());
    // A project keeps the file's mesh.
    let project = dir.path().join("plate.quadex.json");
    h.state_mut().apply(Command::SaveProject(project.clone()));
    let (reopened, _) = Document::open(&project, Settings::default()).unwrap();
    assert_eq!(reopened.imported(), h.state().doc().imported());
    // A mesh file that is not one is refused and the document kept.
    let bad = dir.path().join("bad.msh");
    std::fs::write(&bad, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n").unwrap();
    h.state_mut().apply(Command::Open(bad));
    assert!(status(&h).starts_with("error:"), "{}", status(&h));
    assert_eq!(h.state().doc().name, "plate.msh");
}

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

/// Takes five steps, then replaces the last element (type 0) by one whose
/// Pn is `move_pn(Pn, P0, P_r1)` (world) and checks that it was taken;
/// returns the step as it was, its Pn and the corrected Pn.
fn step_five_and_correct(
    h: &mut Harness<'static, App>,
    move_pn: impl Fn(quadex::Point, quadex::Point, quadex::Point) -> quadex::Point,
) -> (quadex::StepReport, quadex::Point, quadex::Point) {
    h.run();
    h.state_mut().apply(Command::StepN(5));
    h.run();
    let last = h.state().doc().last().cloned().unwrap();
    assert_eq!(last.kind, quadex::extract::StepKind::Element);
    let m = h.state().doc().mesher().unwrap().mesh().clone();
    let n = last.leading.len() / 2;
    let at = |k: usize| m.nodes[last.leading[k] as usize];
    let pn = m.nodes[last.pn_node().unwrap() as usize];
    let moved = move_pn(pn, at(n), at(n + 1));
    h.state_mut().apply(Command::CorrectLast {
        element_type: ElementType::New,
        pn: moved,
        snap_to: None,
    });
    h.run();
    assert!(status(h).starts_with("element corrected"), "{}", status(h));
    (last, pn, moved)
}

/// Corrects the last step with type 0 at `pn`; the training set then holds
/// that correction's sample alone.
fn correct_and_keep_one_sample(h: &mut Harness<'static, App>, pn: quadex::Point) {
    h.state_mut().apply(Command::CorrectLast {
        element_type: ElementType::New,
        pn,
        snap_to: None,
    });
    h.run();
    assert!(status(h).starts_with("element corrected"), "{}", status(h));
    let d = h.state().doc();
    assert_eq!(d.training.len(), 1);
    let last = d.last().cloned().unwrap();
    assert_eq!(
        d.training.samples[0],
        d.mesher().unwrap().sample_of(&last).unwrap()
    );
}

/// Correcting the same step again replaces its sample: the training set
/// keeps the last correction only, not two targets for one input.
#[test]
fn a_step_corrected_twice_keeps_one_sample() {
    let mut h = harness(example());
    let (_, pn, moved) = step_five_and_correct(&mut h, |pn, p0, _| p0 + (pn - p0) * 1.1);
    assert_eq!(h.state().doc().training.len(), 1);
    correct_and_keep_one_sample(&mut h, pn + (moved - pn) * 0.5);
    let second = h.state().doc().training.samples[0].clone();
    // One undo brings back the first correction and its sample.
    h.state_mut().apply(Command::Undo);
    h.run();
    assert_eq!(h.state().doc().training.len(), 1);
    assert_ne!(h.state().doc().training.samples[0], second);
    // Corrected again after a Reset: still one sample, the newest.
    h.state_mut().apply(Command::Reset);
    h.state_mut().apply(Command::StepN(5));
    correct_and_keep_one_sample(&mut h, moved);
}

#[test]
fn correct_append_refit_and_finish() {
    let mut h = harness(example());
    // Move the new node a little towards P0 and commit that instead.
    let (_, _, moved) = step_five_and_correct(&mut h, |pn, p0, _| pn + (p0 - pn) * 0.05);
    let d = h.state().doc();
    assert_eq!(d.steps(), 5);
    assert_eq!(
        d.last().unwrap().kind,
        quadex::extract::StepKind::Correction
    );
    assert_eq!(d.training.len(), 1);
    let new_node = d.last().unwrap().new_nodes[0];
    assert!((d.mesher().unwrap().mesh().nodes[new_node as usize] - moved).length() < 1e-12);
    // The corrected element keeps its sample: the panel says so and its
    // Append button is off; the command itself is refused, so the sample
    // does not weigh twice.
    h.get_by_label("kept as sample 1");
    assert!(h
        .get_by_label("Append as sample")
        .accesskit_node()
        .is_disabled());
    h.state_mut().apply(Command::AppendLast);
    h.run();
    assert_eq!(h.state().doc().training.len(), 1);
    assert_eq!(
        status(&h),
        "error: the last element is in the training set already (sample 1)"
    );
    // The step panel shows the correction beside the model's element.
    h.get_by_label("yours, corrected by hand");
    h.get_by_label("model's Pn, world");
    // The next element appended from the panel (a counter shows it).
    h.state_mut().apply(Command::Step);
    h.run();
    h.get_by_label("Append as sample").click();
    h.run();
    assert_eq!(h.state().doc().training.len(), 2, "{}", status(&h));
    h.get_by_label("training set: 2 samples of yours");
    // Refit in one click: figures before and after, and the rest of the
    // mesh regenerated with the new model (in the background).
    h.get_by_label("Refit").click();
    h.step();
    settle(&mut h);
    let f = h.state().doc().last_refit.clone().expect("refit figures");
    assert_eq!(f.corrections, 2);
    // The refit's counts are the model's own: samples fitted, corrections
    // layered over them.
    let info = h.state().doc().model_info();
    assert_eq!(
        (Some(f.samples), f.corrections),
        (info.samples, info.corrections)
    );
    h.get_by_label(&format!(
        "last refit: {}: {} samples fitted, 2 corrections of yours layered over them",
        f.model, f.samples
    ));
    // The fit of the samples is the shipped model's (R of Xn 0.864 on the
    // shipped set, assets/README.md); the corrections do not spoil it.
    assert!(f.after.0.accuracy > 0.95, "{f:?}");
    assert!(
        f.after.1.r > 0.85 && f.after.1.r >= f.before.1.r - 0.005,
        "{f:?}"
    );
    let d = h.state().doc();
    assert!(d.mesher().unwrap().model().name().starts_with("fitted"));
    h.get_by_label("before");
    assert!(d.is_done());
    // The corrected step stays as the user made it.
    let kept = d.mesher().unwrap().actions()[4].clone();
    assert!(matches!(kept, quadex::extract::Action::Correction(_)));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("annulus.msh");
    h.state_mut().apply(Command::Export(out.clone()));
    assert_valid_annulus_mesh(&out);
    // The same mesh as VTK XML: one cell per quad of the checked mesh.
    let vtu = dir.path().join("annulus.vtu");
    h.state_mut().apply(Command::Export(vtu.clone()));
    let quads = quadex::io::read_mesh(&out).unwrap().quads.len();
    let text = std::fs::read_to_string(&vtu).unwrap();
    assert!(
        text.contains(&format!("NumberOfCells=\"{quads}\"")),
        "{}",
        &text[..text.len().min(400)]
    );
}

/// A refitted model is the document's (a project keeps it) whatever the
/// mesh does after: replacing the document asks first, and names it.
#[test]
fn a_refitted_model_is_work_to_save_after_a_reset() {
    let mut h = stepped_example(3);
    h.state_mut().apply(Command::Refit {
        form: Form::Quadratic,
        mesh_rest: false,
    });
    // The refit is made in the background: wait for it.
    h.state_mut().wait();
    h.state_mut().apply(Command::Reset);
    h.state_mut().apply(Command::OpenExample("square.poly"));
    h.run();
    h.get_by_label("Unsaved changes");
    h.get_by_label("They hold 1 refitted model.");
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

/// Samples that repeat the reference set's (here collected from one of its
/// own meshes) add nothing: the refit needs no new fit, is made at once and
/// says why the figures did not move.
#[test]
fn a_refit_on_samples_the_reference_set_holds_says_they_add_nothing() {
    let mut h = stepped_example(3);
    let lshape = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/reference/lshape.msh");
    h.state_mut().apply(Command::CollectFromFile(lshape));
    let n = h.state().doc().training.len();
    assert!(n > 100, "{}", status(&h));
    h.state_mut().apply(Command::Refit {
        form: Form::Quadratic,
        mesh_rest: false,
    });
    // The refit is made in the background: wait for it.
    h.state_mut().wait();
    assert!(!h.state().busy(), "{}", status(&h));
    let f = h
        .state()
        .doc()
        .last_refit
        .clone()
        .expect("the refit, at once");
    assert_eq!(f.repeated, n);
    let base = quadex::app::document::reference_samples(7).unwrap().len();
    assert_eq!(f.samples, base);
    assert!(
        status(&h).ends_with(&format!(
            "; {n} samples of yours repeat samples already in the set and add nothing"
        )),
        "{}",
        status(&h)
    );
    h.run();
    h.get_by_label(&format!(
        "{n} samples of yours repeated samples already in the set: the fit dropped them"
    ));
}

/// A refit on samples collected from a mesh needs a new global fit (many
/// seconds): it is made in a thread while the window stays live, with its
/// progress in the status bar, and the refit follows.
#[test]
fn a_refit_that_must_fit_again_does_so_in_the_background() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    h.state_mut().apply(Command::CollectFromMesh);
    let collected = h.state().doc().training.len();
    assert!(collected > 1000, "{}", status(&h));
    h.get_by_label("Refit").click();
    h.step();
    h.step();
    assert_eq!(
        status(&h),
        "refitting the quadratic form in the background…"
    );
    assert!(h.state().busy());
    assert!(h.state().doc().last_refit.is_none());
    // The window goes on drawing meanwhile: the status bar names the
    // refit's phase.
    h.get_by_label_contains("refit: ");
    settle(&mut h);
    assert!(
        status(&h).starts_with("refit made fitted (quadratic) 1 from "),
        "{}",
        status(&h)
    );
    let f = h
        .state()
        .doc()
        .last_refit
        .clone()
        .expect("the refit, after the fit");
    assert_eq!(f.corrections, 0);
    let base = quadex::app::document::reference_samples(7).unwrap().len();
    assert!(f.samples > base && f.samples <= base + collected, "{f:?}");
    // A refit again (nothing new) takes the kept fit.
    h.state_mut().apply(Command::Refit {
        form: Form::Quadratic,
        mesh_rest: false,
    });
    // The refit is made in the background: wait for it.
    h.state_mut().wait();
    assert!(
        status(&h).starts_with("refit made fitted (quadratic) 2 from "),
        "{}",
        status(&h)
    );
    assert!(!h.state().busy());
}

/// A Refit with nothing added is the shipped model: the same
/// coefficients, and the annulus meshed the same as with `default`.
#[test]
fn a_refit_with_nothing_added_is_the_shipped_model() {
    let mut h = harness(example());
    h.run();
    h.get_by_label("Refit").click();
    h.step();
    settle(&mut h);
    let d = h.state().doc();
    let (at, refit) = d.refits().last().cloned().expect("a refit");
    assert_eq!(at, 0);
    let shipped = quadex::model::default_model().unwrap();
    assert_eq!(refit.coefficients, shipped.coefficients);
    assert!(refit.memory.is_empty());
    assert!(d.is_done());
    let b = d.boundary().unwrap().clone();
    let mut m = quadex::Mesher::new(b, std::sync::Arc::new(shipped), quadex::MeshParams::DEFAULT);
    m.run(|_| {}).unwrap();
    assert_eq!(d.mesher().unwrap().mesh(), m.mesh());
}

/// Corrections that stick: correct an element, Refit, Reset, step to the
/// same place: the refitted model predicts the corrected element there.
/// The refitted model is shown, kept through the reset, saved as a model
/// file, and `quadex mesh --model` meshes with it.
#[test]
fn a_correction_sticks_through_refit_and_reset_and_the_model_saves() {
    let mut h = harness(example());
    // Pn moved sideways by a fifth of P0–P_r1 (a drag on the canvas).
    let (last, pn, moved) = step_five_and_correct(&mut h, |pn, p0, r1| pn + (r1 - p0) * 0.2);
    let corrected = h.state().doc().training.samples[0].clone();
    // Before the refit the model predicts something else there.
    let shipped = quadex::model::default_model().unwrap();
    use quadex::Model as _;
    assert!((shipped.predict(&corrected.input).pn - corrected.pn).length() > 0.1);
    h.get_by_label_contains("model default: quadratic");
    h.get_by_label("Refit").click();
    h.step();
    settle(&mut h);
    assert_eq!(h.state().doc().settings.model, "fitted (quadratic) 1");
    // The model shown, what it predicts at the correction, and how it
    // meshes the boundary against the model before.
    h.get_by_label_contains("model fitted (quadratic) 1: quadratic, ");
    h.get_by_label_contains("samples, 1 correction");
    h.get_by_label("corrections reproduced: 1 of 1");
    h.get_by_label("meshed from the start, before and now:");
    h.get_by_label("of the size field's");
    assert!(
        h.query_by_label("the refitted model meshes this boundary no worse")
            .is_some()
            || h.query_all_by_label_contains("meshes this boundary worse")
                .next()
                .is_some()
    );
    let f = h.state().doc().last_refit.clone().unwrap();
    // The status line after the rest is meshed keeps the refit's warning.
    assert!(status(&h).starts_with("refitted, then meshed the rest"));
    assert_eq!(
        status(&h).contains("meshes this boundary worse"),
        !f.worse.is_empty(),
        "{}",
        status(&h)
    );
    assert_eq!(f.checks.len(), 1);
    assert!(f.checks[0].reproduced());
    assert!(f
        .meshed
        .as_ref()
        .is_some_and(|(b, a)| b.finished && a.finished));
    // Reset: the refitted model stays chosen; step to the same place.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::R);
    h.run();
    assert_eq!(h.state().doc().steps(), 0);
    assert_eq!(h.state().doc().settings.model, "fitted (quadratic) 1");
    h.state_mut().apply(Command::StepN(5));
    h.run();
    let d = h.state().doc();
    let r = d.last().cloned().unwrap();
    assert_eq!(r.reference, last.reference);
    let p = r.prediction.unwrap();
    assert_eq!(p.element_type, corrected.element_type);
    assert!(
        (p.pn - corrected.pn).length() < 1e-9,
        "{:?} vs {:?}",
        p.pn,
        corrected.pn
    );
    // The mesher draws a row's height towards the size field after the
    // prediction, so the node lands near the corrected one, not on it (and
    // the step says so).
    assert!(
        matches!(
            r.remedy,
            quadex::extract::Remedy::None | quadex::extract::Remedy::Rescaled
        ),
        "{:?}",
        r.remedy
    );
    let at = d.mesher().unwrap().mesh().nodes[r.pn_node().unwrap() as usize];
    assert!(
        (at - moved).length() < 0.25 * (pn - moved).length(),
        "{at:?} vs {moved:?}"
    );
    // A model change and back keeps it in the list.
    let mut s = d.settings.clone();
    s.model = "rules".into();
    h.state_mut().apply(Command::SetSettings(s.clone()));
    s.model = "fitted (quadratic) 1".into();
    h.state_mut().apply(Command::SetSettings(s));
    h.run();
    assert_eq!(h.state().doc().model_info().corrections, 1);
    // Saved as a model file, which the command line meshes with.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("corrected.json");
    h.state_mut().apply(Command::SaveModel(file.clone()));
    h.run();
    assert!(status(&h).starts_with("saved the model"), "{}", status(&h));
    let read =
        quadex::model::ModelFile::from_json(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_eq!(read.corrections.len(), 1);
    let msh = dir.path().join("annulus.msh");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
        .args(["mesh".as_ref(), boundary("annulus.poly").as_os_str()])
        .args([
            "--model".as_ref(),
            file.as_os_str(),
            "-o".as_ref(),
            msh.as_os_str(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_valid_annulus_mesh(&msh);
}

#[test]
fn an_invalid_correction_changes_nothing() {
    let mut h = stepped_example(3);
    let before = h.state().doc().mesher().unwrap().mesh().clone();
    let last = h.state().doc().last().cloned();
    // Pn far outside the domain: not a valid element.
    h.state_mut().apply(Command::CorrectLast {
        element_type: ElementType::New,
        pn: quadex::Point::new(100.0, 100.0),
        snap_to: None,
    });
    let s = status(&h);
    assert!(s.starts_with("error:") && s.contains("not valid"), "{s}");
    let d = h.state().doc();
    assert_eq!(d.mesher().unwrap().mesh(), &before);
    assert_eq!(d.steps(), 3);
    assert_eq!(d.last().cloned(), last);
    assert_eq!(d.training.len(), 0);
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

#[test]
fn a_project_saves_and_opens_whole() {
    let mut h = stepped_example(6);
    h.state_mut().apply(Command::AppendLast);
    h.state_mut().apply(Command::Refit {
        form: Form::Quadratic,
        mesh_rest: false,
    });
    // The refit is made in the background: wait for it.
    h.state_mut().wait();
    h.state_mut().apply(Command::StepN(3));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("annulus.quadex.json");
    h.state_mut().apply(Command::SaveProject(path.clone()));
    assert!(status(&h).starts_with("saved"), "{}", status(&h));
    assert!(!h.state().document.dirty);
    let mesh = h.state().doc().mesher().unwrap().mesh().clone();
    let mut other = harness(example());
    other.run();
    other.state_mut().apply(Command::Open(path.clone()));
    let s = other.state();
    assert!(s.status().starts_with("opened"), "{}", s.status());
    assert_eq!(s.doc().steps(), 9);
    assert_eq!(s.doc().mesher().unwrap().mesh(), &mesh);
    assert_eq!(s.doc().training.len(), 1);
    assert!(s
        .doc()
        .mesher()
        .unwrap()
        .model()
        .name()
        .starts_with("fitted"));
    assert_eq!(s.document.project_path.as_deref(), Some(path.as_path()));
    // Stepping carries on, and undo too.
    other.state_mut().apply(Command::Step);
    other.state_mut().apply(Command::Undo);
    assert_eq!(other.state().doc().mesher().unwrap().mesh(), &mesh);
    // A project that is not one is refused.
    let text = std::fs::read_to_string(&path).unwrap();
    let broken = dir.path().join("broken.json");
    std::fs::write(
        &broken,
        text.replace("\"quadex-project\"", "\"something-else\""),
    )
    .unwrap();
    other.state_mut().apply(Command::Open(broken));
    other.run();
    // (It holds a sample: the editor asks first.)
    other.get_by_label("Don't save").click();
    other.run();
    assert!(
        other.state().status().starts_with("error:"),
        "{}",
        other.state().status()
    );
    assert_eq!(other.state().doc().steps(), 9);
}

/// Undoing File ▸ New brings back the project the document was saved to:
/// its title and the file Save writes (it used to come back untitled, and
/// Save asked for a name).
#[test]
fn undoing_new_brings_back_the_project_file() {
    let mut h = stepped_example(2);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ring.quadex.json");
    h.state_mut().apply(Command::SaveProject(path.clone()));
    assert_eq!(h.state().title(), "ring.quadex.json");
    h.state_mut().apply(Command::New);
    h.run();
    assert_eq!(h.state().title(), "untitled");
    h.state_mut().apply(Command::Undo);
    h.run();
    assert_eq!(h.state().title(), "ring.quadex.json");
    assert_eq!(
        h.state().document.project_path.as_deref(),
        Some(path.as_path())
    );
    assert_eq!(h.state().doc().steps(), 2);
    h.state_mut().apply(Command::Redo);
    assert_eq!(h.state().title(), "untitled");
    assert_eq!(h.state().document.project_path, None);
    h.state_mut().apply(Command::Undo);
    h.state_mut().apply(Command::Save);
    assert!(status(&h).starts_with("saved"), "{}", status(&h));
}

/// The Model panel of an empty document (no boundary, so no mesher)
/// measures the chosen model once and shows its figures: it used to load
/// the model afresh every frame and start a measurement each time (tens of
/// threads and gigabytes, never done).
#[test]
fn the_model_panel_of_an_empty_document_measures_once() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::New);
    h.run();
    assert!(h.state().doc().draft.loops.is_empty());
    h.get_by_label("Model").click();
    h.step();
    assert!(h.state().measuring());
    settle(&mut h);
    h.get_by_label_contains("type accuracy");
    for _ in 0..5 {
        h.step();
        assert!(!h.state().measuring());
    }
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

#[test]
fn boundary_edits_on_the_canvas_are_validated_live() {
    let mut h = stepped_example(3);
    h.run();
    let nodes = h.state().doc().draft.node_count();
    h.get_by_label("split").click();
    h.run();
    // Three parts by default (two nodes more keep the count even); two
    // here, to make the count odd.
    assert_eq!(h.state().panels.tools.split_parts, 3);
    h.state_mut().panels.tools.split_parts = 2;
    let mid = |h: &Harness<'static, App>, k: usize| {
        let l = &h.state().doc().draft.loops[0];
        screen(h, (l[k] + l[(k + 1) % l.len()]) * 0.5)
    };
    // Splitting one segment in two makes the node count odd: the problem
    // is listed, the nodes at fault marked, and there is no mesh until
    // the draft is fixed.
    let p = mid(&h, 0);
    click_at(&mut h, p);
    assert!(h.state().doc().problem.is_some());
    assert!(h.state().doc().meshing.is_none());
    assert!(
        h.get_all_by_label_contains("not a valid boundary yet")
            .count()
            > 0
    );
    // A second split makes it even: a valid boundary, the mesh restarts.
    let p = mid(&h, 10);
    click_at(&mut h, p);
    assert!(h.state().doc().problem.is_none(), "{}", status(&h));
    assert_eq!(h.state().doc().boundary().unwrap().node_count(), nodes + 2);
    assert_eq!(h.state().doc().steps(), 0);
    // Undo takes the edits back one by one, then the steps are there again.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert!(h.state().doc().problem.is_some());
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert!(h.state().doc().problem.is_none());
    assert_eq!(h.state().doc().draft.node_count(), nodes);
    assert_eq!(h.state().doc().steps(), 3);
    h.state_mut().apply(Command::Redo);
    assert_eq!(h.state().doc().draft.node_count(), nodes + 1);
    assert!(h.state().doc().problem.is_some());
}

/// The annulus stepped five times: the last element's Pn (world) and the
/// screen positions of its Pn and P0.
fn five_steps_pn_and_p0(h: &mut Harness<'static, App>) -> (quadex::Point, Pos2, Pos2) {
    h.run();
    h.state_mut().apply(Command::StepN(5));
    h.run();
    let last = h.state().doc().last().cloned().unwrap();
    let m = h.state().doc().mesher().unwrap().mesh().clone();
    let pn = m.nodes[last.pn_node().unwrap() as usize];
    let p0 = m.nodes[last.reference.unwrap() as usize];
    (pn, screen(h, pn), screen(h, p0))
}

#[test]
fn dragging_pn_on_the_canvas_corrects_the_element() {
    let mut h = harness(example());
    let (pn, s, t) = five_steps_pn_and_p0(&mut h);
    // Drag the handle a few pixels towards P0 and let go.
    let to = s + (t - s) * 0.15;
    drag(&mut h, s, to);
    let st = h.state();
    assert!(
        st.status().starts_with("element corrected"),
        "{}",
        st.status()
    );
    assert_eq!(st.doc().training.len(), 1);
    let new_node = st.doc().last().unwrap().new_nodes[0];
    let moved = st.doc().mesher().unwrap().mesh().nodes[new_node as usize];
    assert!(moved.distance(pn) > 1e-6);
    assert_eq!(st.doc().steps(), 5);
}

/// While Pn is dragged the element is outlined in the colour of its score
/// (green, amber, orange; red where it would be no valid element) and the
/// tip says what letting go would give.
#[test]
fn dragging_pn_shows_how_good_the_element_would_be() {
    let mut h = harness(example());
    let (_, s, t) = five_steps_pn_and_p0(&mut h);
    h.hover_at(s);
    h.run();
    h.drag_at(s);
    h.run();
    for k in 1..=3 {
        h.hover_at(s + (t - s) * (0.05 * k as f32));
        h.run();
    }
    let scored = [(90, 230, 110), (240, 200, 60), (255, 140, 40)]
        .map(|(r, g, b)| strokes_of(&h, egui::Color32::from_rgb(r, g, b)));
    assert!(scored.iter().sum::<usize>() > 0, "{scored:?}");
    let says =
        |h: &Harness<'static, App>, text: &str| painted(h).iter().any(|(t, _, _)| t.contains(text));
    assert!(says(&h, "let go: element score "));
    // The tip names both measures: the guard's score and the thesis's
    // criteria for the quad alone.
    assert!(says(&h, "the thesis's criteria"));
    // Past P0 the quad folds: no valid element, and letting go there
    // changes nothing.
    let past = t + (t - s);
    for k in 1..=6 {
        h.hover_at(s + (past - s) * (k as f32 / 6.0));
        h.run();
    }
    assert!(says(&h, "not a valid element here"));
    let before = h.state().doc().mesher().unwrap().mesh().clone();
    h.drop_at(past);
    h.run();
    assert!(status(&h).contains("not valid"), "{}", status(&h));
    assert_eq!(h.state().doc().mesher().unwrap().mesh(), &before);
}

// ---------------------------------------------------------------------
// Issue 17: the editor as a newcomer finds it.

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

/// 2. The Move tool: press on a boundary node, drag, release; the node
///    follows the pointer (the view does not pan) and the boundary changes.
#[test]
fn issue17_the_move_tool_drags_a_boundary_node() {
    let mut h = harness(open(&boundary("square.poly")));
    h.run();
    h.get_by_label("move").click();
    h.run();
    let p = h.state().doc().draft.loops[0][0];
    let s = screen(&h, p);
    let center = h.state().view.canvas.center;
    let zoom = h.state().view.canvas.zoom;
    // Hovering the node highlights it.
    h.hover_at(s);
    h.run();
    assert!(matches!(
        h.state().panels.tools.hover,
        Some(Hover::Node((0, 0)))
    ));
    drag(&mut h, s, s + egui::vec2(12.0, -9.0));
    assert_eq!(
        h.state().view.canvas.center,
        center,
        "the drag panned the view"
    );
    let q = h.state().doc().draft.loops[0][0];
    let want = p + quadex::Point::new(12.0 / zoom, 9.0 / zoom);
    assert!(q.distance(want) < 1.5 / zoom, "{q:?} against {want:?}");
    assert!(h.state().doc().problem.is_none(), "{}", status(&h));
    assert!(status(&h).starts_with("boundary changed"), "{}", status(&h));
    // A drag that starts on no node pans.
    let empty = h.state().view.canvas_rect.left_top() + egui::vec2(30.0, 30.0);
    drag(&mut h, empty, empty + egui::vec2(40.0, 0.0));
    assert_ne!(h.state().view.canvas.center, center);
    assert_eq!(h.state().doc().draft.loops[0][0], q);
    // Undo puts the node back.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(h.state().doc().draft.loops[0][0], p);
}

/// 3a. After reopening a project, undo takes its steps back one by one
///     (and its refits), before undoing the opening itself.
#[test]
fn issue17_undo_carries_on_after_reopening_a_project() {
    let mut h = stepped_example(6);
    h.state_mut().apply(Command::AppendLast);
    h.state_mut().apply(Command::Refit {
        form: Form::Quadratic,
        mesh_rest: false,
    });
    // The refit is made in the background: wait for it.
    h.state_mut().wait();
    h.state_mut().apply(Command::StepN(3));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.quadex.json");
    h.state_mut().apply(Command::SaveProject(path.clone()));
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

/// 3b. A Refit that meshed the rest is one edit: one Ctrl+Z takes back the
///     refit and every step its run took, one Ctrl+Y brings them again.
#[test]
fn issue17_one_undo_takes_back_a_refit_and_the_rest_it_meshed() {
    let mut h = stepped_example(5);
    h.state_mut().apply(Command::AppendLast);
    h.run();
    h.get_by_label("Refit").click();
    h.step();
    settle(&mut h);
    assert!(h.state().doc().is_done());
    let done_steps = h.state().doc().steps();
    assert!(done_steps > 20);
    h.get_by_label_contains("last refit");
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    assert_eq!(status(&h), "undone: refit");
    assert_eq!(h.state().doc().steps(), 5);
    // The refit's figures go with it.
    assert!(h.query_by_label_contains("last refit").is_none());
    assert!(!h
        .state()
        .doc()
        .mesher()
        .unwrap()
        .model()
        .name()
        .starts_with("fitted"));
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Y);
    settle(&mut h);
    assert_eq!(h.state().doc().steps(), done_steps);
    assert!(h.state().doc().is_done());
}

/// 4. After Ctrl+Z the step now last is shown and can be corrected: drag
///    its Pn on the canvas.
#[test]
fn issue17_after_undo_the_last_step_can_be_corrected() {
    let mut h = stepped_example(5);
    h.run();
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run();
    let last = h
        .state()
        .doc()
        .last()
        .cloned()
        .expect("the step now last is shown");
    assert_eq!(last.index, 3);
    h.get_by_label_contains("4 (element)");
    let m = h.state().doc().mesher().unwrap().mesh().clone();
    let s = screen(&h, m.nodes[last.pn_node().unwrap() as usize]);
    let t = screen(&h, m.nodes[last.reference.unwrap() as usize]);
    drag(&mut h, s, s + (t - s) * 0.15);
    let st = h.state();
    assert!(
        st.status().starts_with("element corrected"),
        "{}",
        st.status()
    );
    assert_eq!(st.doc().steps(), 4);
    assert_eq!(
        st.doc().last().unwrap().kind,
        quadex::extract::StepKind::Correction
    );
}

/// 5. Clicking a front node closes the element onto it: P_r2 as type 1,
///    P_l2 as type 2, another node as type 0 with that node as Pn. The
///    nodes that give a valid element are marked, and a node under the
///    pointer is highlighted.
#[test]
fn issue17_clicking_a_front_node_closes_the_element_onto_it() {
    for file in [boundary("annulus.poly"), boundary("plate_hole.poly")] {
        let mut h = harness(open(&file));
        h.run();
        // Step until some front node gives a valid element (along a
        // straight row none does: the quads would be flat).
        let mut steps = 0;
        let (targets, valid) = loop {
            h.state_mut().apply(Command::Step);
            steps += 1;
            h.run();
            let targets = h.state().targets().to_vec();
            let valid: Vec<_> = targets.iter().filter(|t| t.valid()).copied().collect();
            if !valid.is_empty() && targets.len() > valid.len() {
                break (targets, valid);
            }
            assert!(
                steps < 300,
                "{}: no valid target in 300 steps",
                file.display()
            );
        };
        // The panel says how many there are.
        h.get_by_label_contains(&format!(
            "{} near P0 {} a valid element",
            quadex::app::plural(valid.len(), "front node"),
            if valid.len() == 1 { "gives" } else { "give" }
        ));
        // The valid targets are ringed in the colour of their element's
        // score: green good, amber fair, orange poor.
        let p = quadex::MeshParams::DEFAULT;
        let score = |t: &&quadex::app::Target| t.check.unwrap().score;
        let good = valid.iter().filter(|t| score(t) >= p.accept_score).count();
        let poor = valid.iter().filter(|t| score(t) < p.defer_score).count();
        assert!(valid.iter().all(|t| score(&t) > 0.0 && score(&t) <= 1.0));
        assert!(targets.iter().all(|t| t.valid() == t.check.is_some()));
        assert!(strokes_of(&h, egui::Color32::from_rgb(90, 230, 110)) >= good);
        assert!(strokes_of(&h, egui::Color32::from_rgb(240, 200, 60)) >= valid.len() - good - poor);
        assert!(strokes_of(&h, egui::Color32::from_rgb(255, 140, 40)) >= poor);
        let last = h.state().doc().last().cloned().unwrap();
        let n = last.leading.len() / 2;
        let r2 = last.leading[n + 2];
        let r2_target = targets.iter().find(|t| t.node == r2).copied().unwrap();
        assert_eq!(r2_target.element_type, ElementType::Right);
        // Hovering a target highlights it.
        let t = valid[0];
        h.hover_at(screen(&h, t.at));
        h.run();
        assert_eq!(h.state().panels.tools.hover, Some(Hover::Target(t)));
        // Clicking every valid target (one at a time, undone between)
        // corrects the element.
        for t in &valid {
            let s = screen(&h, t.at);
            click_at(&mut h, s);
            let s = status(&h);
            assert!(
                s.starts_with("element corrected"),
                "{}: node {}: {s}",
                file.display(),
                t.node
            );
            let d = h.state().doc();
            assert_eq!(d.steps(), steps);
            assert_eq!(d.last().unwrap().element_type, Some(t.element_type));
            assert_eq!(d.last().unwrap().pn_node(), Some(t.node));
            h.state_mut().apply(Command::Undo);
            h.run();
        }
        // An invalid one says why and changes nothing.
        if let Some(t) = targets.iter().find(|t| !t.valid()) {
            let before = h.state().doc().mesher().unwrap().mesh().clone();
            let s = screen(&h, t.at);
            click_at(&mut h, s);
            assert!(status(&h).contains("not valid"), "{}", status(&h));
            assert_eq!(h.state().doc().mesher().unwrap().mesh(), &before);
        }
    }
}

/// 5'. The report's own clicks: on the annulus, clicking the last
///     element's r2 or l2 with the Correct tool corrects it within a few
///     steps (before the rework, every such click said "not a valid
///     element" for 30 steps).
#[test]
fn issue17_clicking_r2_or_l2_on_the_annulus_corrects_the_element() {
    let mut h = harness(open(&boundary("annulus.poly")));
    h.run();
    h.get_by_label("correct").click();
    h.run();
    let mut said = Vec::new();
    for _ in 0..30 {
        h.state_mut().apply(Command::Step);
        h.run();
        let Some(last) = h.state().doc().last().cloned() else {
            continue;
        };
        let n = last.leading.len() / 2;
        if n < 2 {
            continue;
        }
        for node in [last.leading[n + 2], last.leading[n - 2]] {
            let p = h.state().doc().mesher().unwrap().mesh().nodes[node as usize];
            let s = screen(&h, p);
            click_at(&mut h, s);
            if status(&h).starts_with("element corrected") {
                return;
            }
            said.push(status(&h));
        }
    }
    panic!(
        "no click on l2 or r2 in 30 steps corrected the element; the last said: {}",
        said.last().cloned().unwrap_or_default()
    );
}

/// 6. Replacing a document that holds unsaved work asks first (Cancel
///    keeps it, Don't save goes on, Save saves then goes on); the close
///    question names the project file after Save as.
#[test]
fn issue17_replacing_the_document_asks_before_losing_work() {
    let mut h = stepped_example(3);
    h.state_mut().apply(Command::AppendLast);
    h.run();
    let square = boundary("square.poly");
    h.state_mut().apply(Command::Open(square.clone()));
    h.run();
    assert_eq!(
        h.state().window.ask,
        Some(Ask::Discard(Command::Open(square.clone())))
    );
    h.get_by_label("Unsaved changes");
    h.get_by_label_contains("1 training sample");
    // With no project yet, Save makes one: the question says so.
    h.get_by_label_contains(
        "Save the changes to annulus.poly as a project (annulus.quadex.json) before opening square.poly?",
    );
    h.get_by_label("Cancel").click();
    h.run();
    assert_eq!(h.state().window.ask, None);
    assert_eq!(h.state().doc().name, "annulus.poly");
    assert_eq!(h.state().doc().training.len(), 1);
    // File > New asks too; Don't save goes on.
    h.state_mut().apply(Command::New);
    h.run();
    h.get_by_label("Don't save").click();
    h.run();
    assert!(h.state().doc().draft.loops.is_empty());
    // Undo brings the work back; Save writes the project, then opens.
    h.state_mut().apply(Command::Undo);
    assert_eq!(h.state().doc().training.len(), 1);
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("plate.quadex.json");
    h.state_mut().apply(Command::SaveProject(project.clone()));
    h.state_mut().apply(Command::StepN(1));
    h.state_mut().apply(Command::AppendLast);
    h.state_mut().apply(Command::Open(square.clone()));
    h.run();
    h.get_by_label("Save").click();
    h.run();
    assert_eq!(h.state().doc().name, "square.poly");
    let (saved, _) = Document::open(&project, Settings::default()).unwrap();
    assert_eq!(saved.training.len(), 2);
    // Steps alone are no work to lose: no question.
    h.state_mut().apply(Command::StepN(2));
    h.state_mut().apply(Command::OpenExample("lshape.poly"));
    assert_eq!(h.state().doc().name, "lshape.poly");
    // The close question names the project.
    let mut c = harness(example());
    c.run();
    c.state_mut().apply(Command::StepN(5));
    c.state_mut().apply(Command::AppendLast);
    c.state_mut().apply(Command::SaveProject(project.clone()));
    c.state_mut().apply(Command::StepN(1));
    c.state_mut().apply(Command::AppendLast);
    c.input_mut()
        .viewports
        .entry(egui::ViewportId::ROOT)
        .or_default()
        .events
        .push(egui::ViewportEvent::Close);
    c.run();
    assert_eq!(
        c.state().window.ask,
        Some(Ask::Close),
        "{}",
        c.state().status()
    );
    c.get_by_label_contains("Save the changes to plate.quadex.json before closing?");
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

/// 8. File > New, draw a loop and a hole with the pointer, save the
///    boundary; a broken file opens as a draft to fix; the resample
///    target follows each file; the loops' numbers are on the canvas.
#[test]
fn issue17_new_draw_save_and_fix_a_broken_file() {
    let mut h = harness(open(&boundary("square.poly")));
    h.run();
    h.get_by_label("File").click();
    h.run();
    h.get_by_label_contains("New Ctrl").click();
    h.run();
    assert!(h.state().doc().draft.loops.is_empty());
    assert_eq!(h.state().panels.tools.tool, quadex::app::tools::Tool::Draw);
    h.get_by_label_contains("Nothing drawn yet");
    // An outer square and a square hole, clicked on the canvas.
    let r = h.state().view.canvas_rect;
    let c = r.center();
    // The outer square also gets its sides' midpoints (a square in a square
    // of four nodes each is beyond extraction: it has no element for the
    // ring of four bridging quads, and the fill takes over).
    for (half, midpoints) in [(150.0, true), (50.0, false)] {
        let mut corners = vec![
            c + egui::vec2(-half, half),
            c + egui::vec2(half, half),
            c + egui::vec2(half, -half),
            c + egui::vec2(-half, -half),
        ];
        if midpoints {
            corners = (0..4)
                .flat_map(|k| [corners[k], corners[k].lerp(corners[(k + 1) % 4], 0.5)])
                .collect();
        }
        for &p in &corners {
            click_at(&mut h, p);
        }
        click_at(&mut h, corners[0]);
    }
    // The view stayed put while drawing (the tool bar keeps its height).
    assert_eq!(h.state().view.canvas_rect, r);
    let d = h.state().doc();
    assert_eq!(d.draft.loops.len(), 2);
    assert!(d.problem.is_none(), "{:?}", d.problem);
    let want = |s: Pos2| h.state().view.canvas.to_world(r, s);
    assert!(d.draft.loops[1][0].distance(want(c + egui::vec2(-50.0, 50.0))) < 1e-9);
    assert_eq!(d.boundary().unwrap().loops.len(), 2);
    // Extraction finishes this domain in fewer than 20 steps; the count
    // taken is what must survive the project's round trip.
    h.state_mut().apply(Command::StepN(20));
    let steps = h.state().doc().steps();
    assert!(steps >= 1);
    // Stepping put the drawing tool away: a click on the mesh corrects.
    assert_eq!(
        h.state().panels.tools.tool,
        quadex::app::tools::Tool::Correct
    );
    // The hole was drawn counter-clockwise (the boundary turns it around):
    // a project of the drawing reopens with the same nodes and steps.
    let dir = tempfile::tempdir().unwrap();
    let project = dir.path().join("drawn.quadex.json");
    h.state_mut().apply(Command::SaveProject(project.clone()));
    let (reopened, _) = Document::open(&project, Settings::default()).unwrap();
    assert_eq!(reopened.steps(), steps);
    assert_eq!(
        reopened.mesher().unwrap().mesh(),
        h.state().doc().mesher().unwrap().mesh()
    );
    // The loops' numbers, as Resample names them, with a boundary tool
    // (once the finished mesh's background pass is over).
    h.state_mut().panels.tools.tool = quadex::app::tools::Tool::Move;
    settle(&mut h);
    let texts: Vec<String> = painted(&h).into_iter().map(|t| t.0).collect();
    assert!(texts.iter().any(|t| t == "loop 0 (outer)"), "{texts:?}");
    assert!(texts.iter().any(|t| t == "loop 1 (hole)"), "{texts:?}");
    // Save the boundary as .poly and as .json; both read back.
    for name in ["drawn.poly", "drawn.json"] {
        let p = dir.path().join(name);
        h.state_mut().apply(Command::SaveBoundary(p.clone()));
        assert!(
            status(&h).starts_with("saved the boundary"),
            "{}",
            status(&h)
        );
        let b = quadex::io::read_boundary(&p).unwrap();
        assert_eq!(b.node_count(), 12);
    }
    // A broken file opens as a draft: its problem shown, its nodes marked
    // (the drawing is work, changed since the save: the editor asks first).
    h.state_mut().apply(Command::Undo);
    let odd = bench().join("bad/odd_count.poly");
    h.state_mut().apply(Command::Open(odd));
    h.run();
    h.get_by_label("Don't save").click();
    h.run();
    let s = status(&h);
    assert!(s.contains("as a draft to fix"), "{s}");
    assert!(h.state().doc().meshing.is_none());
    h.get_by_label_contains("not a valid boundary yet");
    // The Move tool is chosen, so the draft is drawn with its nodes marked.
    assert_eq!(h.state().panels.tools.tool, quadex::app::tools::Tool::Move);
    // Fix it with the pointer: insert a node on a segment (12 nodes).
    h.get_by_label("insert").click();
    h.run();
    let l = h.state().doc().draft.loops[0].clone();
    let mid = screen(&h, (l[0] + l[1]) * 0.5);
    click_at(&mut h, mid);
    assert!(h.state().doc().problem.is_none(), "{}", status(&h));
    assert_eq!(h.state().doc().boundary().unwrap().node_count(), 12);
    // The resample target is each file's own median segment.
    let median = |p: &Path| quadex::io::read_boundary(p).unwrap().median_segment();
    for name in ["square.poly", "plate_hole.poly"] {
        h.state_mut().apply(Command::Open(boundary(name)));
        h.run();
        if h.state().window.ask.is_some() {
            h.get_by_label("Don't save").click();
            h.run();
        }
        // A valid file is to be meshed: the Correct tool.
        assert_eq!(
            h.state().panels.tools.tool,
            quadex::app::tools::Tool::Correct
        );
        let want = median(&boundary(name));
        let got = h.state().panels.tools.resample_h;
        assert!(
            (got - want).abs() < 1e-12 * want.max(1.0),
            "{name}: {got} for {want}"
        );
    }
    // A target so fine the boundary would pass a million nodes cannot be
    // applied: the button is disabled and the draft stays.
    let before = h.state().doc().draft.clone();
    h.state_mut().panels.tools.resample_h = 1e-9;
    h.run();
    let button = h.get_by_label("Resample");
    assert!(button.accesskit_node().is_disabled());
    button.click();
    h.run();
    assert_eq!(h.state().doc().draft, before);
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

#[test]
fn the_file_prompt_takes_the_keyboard() {
    // The prompt in the window (no desktop dialog): its path field has the
    // keyboard from the start, so typing a name needs no click.
    let mut h = harness(open(&boundary("plate_hole.poly")));
    h.state_mut().window.native_dialogs = false;
    h.run();
    h.state_mut()
        .apply(Command::Dialog(quadex::app::command::Dialog::ImportSamples));
    h.run();
    let start = format!("{}/", boundary("x").parent().unwrap().display());
    assert!(h.query_all_by_value(&start).count() > 0, "{start}");
    h.input_mut()
        .events
        .push(egui::Event::Text("mine.csv".into()));
    h.run();
    let typed = boundary("mine.csv").display().to_string();
    assert!(h.query_all_by_value(&typed).count() > 0, "{typed}");
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

#[test]
fn the_title_marks_unsaved_work_not_steps_alone() {
    let mut h = stepped_example(4);
    h.run();
    // Steps alone are made again by the same model: nothing to save.
    assert!(!h.state().unsaved());
    assert!(!h.state().title_line().contains("(changed)"));
    h.state_mut().apply(Command::AppendLast);
    h.run();
    assert!(h.state().unsaved());
    assert!(h.state().title_line().ends_with(" (changed)"));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("annulus.quadex.json");
    h.state_mut().apply(Command::SaveProject(path));
    h.run();
    assert!(status(&h).starts_with("saved"), "{}", status(&h));
    assert!(!h.state().title_line().contains("(changed)"));
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

/// The phases and labels the status bar showed while the background work
/// went on, frame by frame, and the longest frame (the window answers
/// between frames only).
fn watch_background(h: &mut Harness<'static, App>) -> (Vec<String>, Duration) {
    let (mut seen, mut longest) = (Vec::<String>::new(), Duration::ZERO);
    let t = Instant::now();
    loop {
        let f = Instant::now();
        h.step();
        longest = longest.max(f.elapsed());
        for (text, _, _) in painted(h) {
            if (text.starts_with("refit: ")
                || text.contains("finishing: ")
                || text.contains(": extraction, "))
                && seen.last() != Some(&text)
            {
                seen.push(text);
            }
        }
        let s = h.state();
        if !s.busy() && !s.finishing() {
            break;
        }
        assert!(
            t.elapsed().as_secs() < 300,
            "the background work did not end"
        );
        std::thread::sleep(Duration::from_millis(30));
    }
    h.run();
    (seen, longest)
}

/// Refit on disk1600 after one correction of a step's Pn (y nudged by
/// 0.003): the refit runs in the background, the window answers every
/// frame, the status bar names each phase (the refit's, extraction, and
/// the parts of finishing), Step and Run are greyed out meanwhile, and the
/// report judges the mesh by its quad count against the size field, its
/// taper and aspect and how far the correction reached, with those
/// figures shown.
#[test]
fn a_refit_on_a_large_mesh_keeps_the_window_answering_and_judges_the_whole_mesh() {
    let mut h = harness(open(&boundary("disk1600.poly")));
    h.run();
    // The first element step that makes a new node.
    let (pn, kind) = loop {
        h.state_mut().apply(Command::Step);
        let d = h.state().doc();
        let r = d.last().unwrap();
        if let (Some(v), Some(t), StepKind::Element) = (r.pn_node(), r.element_type, r.kind) {
            break (d.mesher().unwrap().mesh().nodes[v as usize], t);
        }
        assert!(d.steps() < 50, "no element step");
    };
    h.run();
    h.state_mut().apply(Command::CorrectLast {
        element_type: kind,
        pn: pn + quadex::Point::new(0.0, 0.003),
        snap_to: None,
    });
    h.run();
    assert_eq!(h.state().doc().training.len(), 1, "{}", status(&h));
    let t = Instant::now();
    h.get_by_label("Refit").click();
    h.step();
    let answered = t.elapsed();
    assert!(h.state().busy(), "{}", status(&h));
    assert!(
        answered < Duration::from_secs(1),
        "the click took {answered:?}"
    );
    h.step();
    // Step, Run and Run to end are greyed out while the refit goes on.
    for label in ["Step  (Space)", "Run  (P)", "Run to end  (Ctrl+Enter)"] {
        assert!(
            h.get_by_label(label).accesskit_node().is_disabled(),
            "{label} enabled during the refit"
        );
    }
    let (seen, longest) = watch_background(&mut h);
    eprintln!("phases seen: {seen:#?}\nlongest frame {longest:?}");
    assert!(longest < Duration::from_secs(1), "a frame took {longest:?}");
    let has = |p: &str| seen.iter().any(|s| s.contains(p));
    for p in [
        "refit: measuring both models on the samples",
        "refit: meshing the boundary from the start with the model before",
        "refit: meshing the boundary from the start with the refitted model",
        "meshing the rest: extraction, ",
        "finishing: cleanup and smoothing",
        "finishing: remeshing bad regions",
    ] {
        assert!(has(p), "no {p:?} among {seen:#?}");
    }
    let f = h.state().doc().last_refit.clone().expect("the refit");
    let (before, after) = f.meshed.clone().expect("meshed from the start");
    eprintln!(
        "before {} taper {:.2} aspect {:.2} irregular {}; after {} taper {:.2} aspect {:.2} irregular {}; memory {:?}; worse {:?}; status {}",
        before.count_line(), before.taper_max, before.aspect_max, before.irregular,
        after.count_line(), after.taper_max, after.aspect_max, after.irregular,
        f.memory_reach, f.worse, status(&h)
    );
    let (changed, calls) = f.memory_reach.expect("the corrections' reach");
    assert!(calls > 1000 && changed <= calls, "{changed} of {calls}");
    h.get_by_label_contains("the corrections changed ");
    h.get_by_label(&quadex::compare::grouped(before.quads));
    h.get_by_label(&quadex::compare::grouped(after.quads));
    h.get_by_label_contains("the size field asks for about");
    h.get_by_label("max taper");
    h.get_by_label("max aspect");
    assert!(h.state().doc().is_done());
    assert_eq!(h.state().shown_kind(), MeshKind::Finished);
}

/// A new document (File ▸ New, a built-in example) proposes no path from
/// the folder another document was opened from: its Export box is empty
/// (Export mesh greyed out) and its dialogs start in the working
/// directory, until a mesh is exported; then they start in that folder.
#[test]
fn a_new_document_proposes_no_path_from_the_last_file_opened() {
    let shared = tempfile::tempdir().unwrap();
    let file = shared.path().join("annulus.poly");
    std::fs::copy(boundary("annulus.poly"), &file).unwrap();
    let mut h = harness(example());
    h.state_mut().window.native_dialogs = false;
    h.run();
    h.state_mut().apply(Command::Open(file.clone()));
    h.run();
    assert_eq!(
        PathBuf::from(&h.state().panels.export_path),
        shared.path().join("annulus.msh")
    );
    let in_shared = |h: &Harness<'static, App>| {
        let dir = shared.path().display().to_string();
        h.state().panels.export_path.starts_with(&dir)
            || h.query_all_by_role(egui::accesskit::Role::TextInput)
                .any(|n| n.value().is_some_and(|v| v.starts_with(&dir)))
    };
    // File ▸ New with the pointer.
    h.get_by_label("File").click();
    h.run();
    h.get_by_label_contains("New").click();
    h.run();
    assert_eq!(h.state().doc().name, "untitled");
    assert_eq!(h.state().panels.export_path, "");
    assert!(!in_shared(&h));
    h.state_mut()
        .apply(Command::Dialog(quadex::app::command::Dialog::SaveProjectAs));
    h.run();
    assert!(
        !in_shared(&h),
        "the project prompt starts in the shared folder"
    );
    h.key_press(egui::Key::Escape);
    h.run();
    // A built-in example, from the menu.
    h.get_by_label("File").click();
    h.run();
    h.get_by_label_contains("Open an example").hover();
    h.run();
    h.get_by_label("square.poly").click();
    h.run();
    assert_eq!(h.state().doc().name, "square.poly");
    assert_eq!(h.state().panels.export_path, "");
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    assert!(h.get_by_label("Export mesh").accesskit_node().is_disabled());
    h.state_mut()
        .apply(Command::Dialog(quadex::app::command::Dialog::ExportMesh));
    h.run();
    assert!(
        !in_shared(&h),
        "the export prompt starts in the shared folder"
    );
    h.key_press(egui::Key::Escape);
    h.run();
    // An export: the next new document proposes its folder.
    let mine = tempfile::tempdir().unwrap();
    h.state_mut()
        .apply(Command::Export(mine.path().join("square.msh")));
    settle(&mut h);
    h.state_mut().apply(Command::New);
    h.run();
    assert_eq!(
        PathBuf::from(&h.state().panels.export_path),
        mine.path().join("untitled.msh")
    );
}

/// The Quality panel counts the quads that miss a criterion: disk1600's
/// finished mesh has quads with an angle below 45°, few enough that a
/// share would read 100.0 %.
#[test]
fn the_quality_panel_counts_the_quads_outside_the_angle_range() {
    let mut h = harness(open(&boundary("disk1600.poly")));
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

/// A plate drawn by hand with few nodes is resampled loop by loop no
/// more: "all loops" (the choice a document starts with) cuts every loop
/// at the size H in one click, and the plate meshes finer.
#[test]
fn resample_all_loops_at_one_size() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::New);
    h.run();
    let r = h.state().view.canvas_rect;
    let c = r.center();
    // A plate of 8 outer nodes (corners and midpoints) and a square hole.
    for (half, midpoints) in [(150.0, true), (50.0, false)] {
        let mut corners = vec![
            c + egui::vec2(-half, half),
            c + egui::vec2(half, half),
            c + egui::vec2(half, -half),
            c + egui::vec2(-half, -half),
        ];
        if midpoints {
            corners = (0..4)
                .flat_map(|k| [corners[k], corners[k].lerp(corners[(k + 1) % 4], 0.5)])
                .collect();
        }
        for &p in &corners {
            click_at(&mut h, p);
        }
        click_at(&mut h, corners[0]);
    }
    assert!(
        h.state().doc().problem.is_none(),
        "{:?}",
        h.state().doc().problem
    );
    assert_eq!(h.state().doc().draft.node_count(), 12);
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    let coarse = h.state().doc().finished().unwrap().quads.len();
    // The Boundary section offers all loops, and starts with them.
    assert!(
        h.query_all_by_value("all loops (12 nodes)").count() > 0
            || h.query_by_label("all loops (12 nodes)").is_some(),
        "no all loops choice"
    );
    let side = {
        let l = &h.state().doc().draft.loops[0];
        quadex::geom::polygon_area(l.iter().copied()).abs().sqrt()
    };
    h.state_mut().panels.tools.resample_h = side / 12.0;
    // The boundary tools bring the Boundary section to the top.
    h.get_by_label("move").click();
    h.run();
    h.get_by_label("Resample").click();
    h.run();
    let d = h.state().doc();
    assert!(d.problem.is_none(), "{:?}", d.problem);
    assert_eq!(d.draft.loops[0].len(), 48, "{}", status(&h));
    assert_eq!(d.draft.loops[1].len(), 16, "{}", status(&h));
    // One undo takes the resample back.
    h.state_mut().apply(Command::Undo);
    assert_eq!(h.state().doc().draft.node_count(), 12);
    h.state_mut().apply(Command::Redo);
    assert_eq!(h.state().doc().draft.node_count(), 64);
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    let fine = h.state().doc().finished().unwrap().quads.len();
    assert!(fine > 4 * coarse, "{coarse} quads, then {fine}");
}

/// A drawing (`.dxf`) opens with its curves drawn as curves over the
/// nodes cut from them; the size box cuts them again at another size and
/// meshes from the start; the mesh runs to the end and exports.
#[test]
fn a_drawing_opens_with_its_curves_and_a_size_box() {
    let dxf = bench().join("cad/annulus.dxf");
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::Open(dxf.clone()));
    h.run();
    let (size, nodes) = {
        let d = h.state().doc();
        let dr = d
            .drawing
            .as_ref()
            .unwrap_or_else(|| panic!("{}", status(&h)));
        assert_eq!(dr.geometry.curves.len(), 2);
        (dr.size, d.regions.as_ref().unwrap().graph.points.len())
    };
    // Two circles, each one path of many more points than its nodes.
    assert_eq!(strokes_of(&h, quadex::app::canvas::CURVE_COLOUR), 2);
    h.get_by_label("Drawing");
    h.get_by_label_contains(&format!(
        "0 lines, 2 arcs; cut at size {size} into {nodes} boundary nodes"
    ));
    // Half the size, Apply with the pointer.
    h.state_mut().panels.tools.resample_h = size / 2.0;
    h.run();
    h.get_by_label("Apply").click();
    h.run();
    let d = h.state().doc();
    let now = d.regions.as_ref().unwrap().graph.points.len();
    assert_eq!(d.drawing.as_ref().unwrap().size, size / 2.0);
    assert!(
        now > 2 * nodes - 8 && now < 2 * nodes + 8,
        "{nodes} nodes, then {now}"
    );
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    assert_eq!(h.state().shown_kind(), MeshKind::Finished, "{}", status(&h));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("annulus.msh");
    h.state_mut().apply(Command::Export(out.clone()));
    let m = quadex::io::read_mesh(&out).unwrap_or_else(|e| panic!("{e}: {}", status(&h)));
    assert_eq!(m.loops.len(), 2);
    // The command line cuts and meshes the drawing the same way.
    let exe = env!("CARGO_BIN_EXE_quadex");
    let cli = dir.path().join("cli.msh");
    let st = std::process::Command::new(exe)
        .args([
            "mesh",
            dxf.to_str().unwrap(),
            "-o",
            cli.to_str().unwrap(),
            "--size",
        ])
        .arg(format!("{}", size / 2.0))
        .status()
        .unwrap();
    assert!(st.success());
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&cli).unwrap());
}

/// A bow-tie drawn with the pointer is named as crossing segments (not a
/// loop of no area), and the nodes' numbers the message gives are on the
/// canvas.
#[test]
fn a_bow_tie_is_named_as_crossing_and_its_nodes_are_numbered() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::New);
    h.run();
    let c = h.state().view.canvas_rect.center();
    let corners = [
        c + egui::vec2(-100.0, -100.0),
        c + egui::vec2(100.0, 100.0),
        c + egui::vec2(100.0, -100.0),
        c + egui::vec2(-100.0, 100.0),
    ];
    for &p in &corners {
        click_at(&mut h, p);
    }
    click_at(&mut h, corners[0]);
    h.run();
    let d = h.state().doc();
    assert_eq!(d.draft.node_count(), 4);
    let problem = d
        .problem
        .as_ref()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(problem.contains("crosses"), "{problem}");
    assert!(
        h.query_all_by_label_contains("not a valid boundary yet: loop 0 (segment from node")
            .count()
            > 0
    );
    let texts: Vec<String> = painted(&h).into_iter().map(|t| t.0).collect();
    for n in ["1", "2", "3", "4"] {
        assert!(
            texts.iter().any(|t| t == n),
            "no node number {n}: {texts:?}"
        );
    }
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

/// Reset and Open of a document meshed with the same model do not measure
/// the model again (5 to 15 s on a shared machine).
#[test]
fn the_model_panel_measures_the_same_model_once() {
    let mut h = harness(example());
    h.run();
    h.get_by_label("Model").click();
    h.step();
    settle(&mut h);
    h.state_mut().apply(Command::StepN(3));
    h.state_mut().apply(Command::Reset);
    h.step();
    assert!(!h.state().measuring(), "measuring again after Reset");
    h.state_mut().apply(Command::Open(boundary("square.poly")));
    h.step();
    assert!(!h.state().measuring(), "measuring again after Open");
    // Another model is measured.
    let s = Settings {
        model: "rules".into(),
        ..Settings::default()
    };
    h.state_mut().apply(Command::SetSettings(s));
    h.step();
    assert!(h.state().measuring());
}

/// "Collect from this mesh" says why a small mesh gives so many samples,
/// and the table shows every input point, so rows of one corner are told
/// apart.
#[test]
fn collected_samples_say_why_so_many_and_show_every_input() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    h.get_by_label("Training set").click();
    h.run();
    h.get_by_label_contains("Collect from this mesh").click();
    h.run();
    let st = status(&h);
    assert!(
        st.contains(
            " a quad: each corner of a good quad is P0 for each of the three element types"
        ),
        "{st}"
    );
    let texts: Vec<String> = painted(&h).into_iter().map(|t| t.0).collect();
    assert!(
        texts
            .iter()
            .any(|t| t.contains("l3") && t.contains("l1") && t.contains("r1") && t.contains("r3")),
        "{texts:?}"
    );
    // Rows carry seven points each (l3..l1 | r1..r3).
    let row = texts
        .iter()
        .find(|t| t.contains(" | ") && t.contains("annulus.poly"))
        .expect("a sample row");
    assert_eq!(row.matches('(').count(), 6, "{row}");
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

/// A JSON geometry file opens as a drawing at its own target size, its
/// spline and ellipse drawn as curves and named in the Drawing section
/// beside the lines and arcs.
#[test]
fn a_geometry_file_opens_as_a_drawing_with_its_splines_and_ellipses() {
    let json = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/bracket.json");
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::Open(json));
    h.run();
    let (size, curves, nodes) = {
        let d = h.state().doc();
        let dr = d
            .drawing
            .as_ref()
            .unwrap_or_else(|| panic!("{}", status(&h)));
        (
            dr.size,
            dr.geometry.curves.len(),
            d.regions.as_ref().unwrap().graph.points.len(),
        )
    };
    assert_eq!(size, 4.0, "the file's own size");
    assert_eq!(curves, 7);
    assert_eq!(strokes_of(&h, quadex::app::canvas::CURVE_COLOUR), 7);
    h.get_by_label_contains(&format!(
        "2 lines, 3 arcs, 1 ellipse, 1 spline; cut at size 4 into {nodes} boundary nodes"
    ));
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    assert_eq!(h.state().shown_kind(), MeshKind::Finished, "{}", status(&h));
}

/// The Arc tool: two arcs of three clicks each, the second ending on the
/// loop's first node, draw a closed circle whose nodes all lie on it, at
/// most 15° apart; the loop meshes.
#[test]
fn two_arcs_of_three_clicks_draw_a_circle() {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::New);
    h.run();
    h.state_mut().panels.tools.tool = quadex::app::tools::Tool::Arc;
    h.run();
    let c = h.state().view.canvas_rect.center();
    let r = 120.0;
    let (a, top, b, bottom) = (
        c + egui::vec2(-r, 0.0),
        c + egui::vec2(0.0, -r),
        c + egui::vec2(r, 0.0),
        c + egui::vec2(0.0, r),
    );
    for p in [a, top, b] {
        click_at(&mut h, p);
    }
    assert_eq!(
        h.state().panels.tools.drawing.len(),
        13,
        "a half circle of 12 segments"
    );
    for p in [b, bottom, a] {
        click_at(&mut h, p);
    }
    assert!(h.state().panels.tools.drawing.is_empty(), "the loop closed");
    let d = &h.state().doc().draft;
    assert_eq!(d.loops.len(), 1);
    let l = &d.loops[0];
    assert_eq!(l.len(), 24);
    let centre = (l[0] + l[12]) * 0.5;
    let radius = l[0].distance(centre);
    for p in l {
        assert!(
            (p.distance(centre) - radius).abs() < 1e-9 * radius,
            "{p:?} off the circle"
        );
    }
    for k in 0..l.len() {
        let (p, q) = (l[k] - centre, l[(k + 1) % l.len()] - centre);
        assert!(p.angle_to(q).abs() <= 15f64.to_radians() + 1e-9);
    }
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    assert_eq!(h.state().shown_kind(), MeshKind::Finished, "{}", status(&h));
}

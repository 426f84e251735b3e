//! The editor's files, clicked through with egui_kittest: boundaries,
//! meshes, drawings and projects opened and saved, the question before
//! work is lost, the file prompt, the title and the proposed paths.
#![cfg(feature = "gui")]

mod common;

use common::editor::*;
use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use quadex::app::{App, Ask, Command, Document, MeshKind, Settings};
use std::path::{Path, PathBuf};

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
fn a_project_saves_and_opens_whole() {
    let (h, dir, path) = refitted_and_saved("annulus.quadex.json");
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
    open_example_from_menu(&mut h, "square.poly");
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
    let typed = mine.path().join("my_square.inp");
    h.state_mut().apply(Command::Export(typed.clone()));
    settle(&mut h);
    assert!(typed.exists());
    // The box keeps the path written to, though the export's folder is
    // now where a document of no file would be exported by default.
    assert_eq!(PathBuf::from(&h.state().panels.export_path), typed);
    h.state_mut().apply(Command::New);
    h.run();
    assert_eq!(
        PathBuf::from(&h.state().panels.export_path),
        mine.path().join("untitled.msh")
    );
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
        (
            dr.sizes.size,
            d.regions.as_ref().unwrap().graph.points.len(),
        )
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
    assert_eq!(d.drawing.as_ref().unwrap().sizes.size, size / 2.0);
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

/// A JSON geometry file opens as a drawing at its own target size, local
/// sizes and gradation, its spline and ellipse drawn as curves and named in
/// the Drawing section beside the lines and arcs; its export is the
/// command line's file, byte for byte, and a new size keeps the local ones.
#[test]
fn a_geometry_file_opens_as_a_drawing_with_its_splines_and_ellipses() {
    let json = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/bracket.json");
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::Open(json.clone()));
    h.run();
    let (size, curves, nodes) = {
        let d = h.state().doc();
        let dr = d
            .drawing
            .as_ref()
            .unwrap_or_else(|| panic!("{}", status(&h)));
        (
            dr.sizes.size,
            dr.geometry.curves.len(),
            d.regions.as_ref().unwrap().graph.points.len(),
        )
    };
    assert_eq!(size, 4.0, "the file's own size");
    assert_eq!(curves, 7);
    assert_eq!(strokes_of(&h, quadex::app::canvas::CURVE_COLOUR), 7);
    h.get_by_label_contains(&format!(
        "2 lines, 3 arcs, 1 ellipse, 1 spline; cut at size 4 (local sizes: bolt 1, 1 point; gradation 0.3) into {nodes} boundary nodes"
    ));
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    assert_eq!(h.state().shown_kind(), MeshKind::Finished, "{}", status(&h));
    let dir = tempfile::tempdir().unwrap();
    let exe = env!("CARGO_BIN_EXE_quadex");
    let cli_mesh = |name: &str, extra: &[&str]| {
        let cli = dir.path().join(name);
        let st = std::process::Command::new(exe)
            .arg("mesh")
            .arg(&json)
            .arg("-o")
            .arg(&cli)
            .args(extra)
            .status()
            .unwrap();
        assert!(st.success());
        std::fs::read(&cli).unwrap()
    };
    let out = dir.path().join("bracket.msh");
    h.state_mut().apply(Command::Export(out.clone()));
    assert_eq!(std::fs::read(&out).unwrap(), cli_mesh("cli.msh", &[]));
    // The bolt's circle (length 16π) is cut at its layer's size 1, not at 4.
    let m = quadex::io::read_mesh(&out).unwrap();
    let on_bolt = m
        .nodes
        .iter()
        .filter(|p| ((p.x - 80.0).hypot(p.y - 20.0) - 8.0).abs() < 1e-9)
        .count();
    assert!((48..=52).contains(&on_bolt), "{on_bolt} nodes on the bolt");
    // Another target size keeps the local ones.
    h.state_mut().panels.tools.resample_h = 3.0;
    h.run();
    h.get_by_label("Apply").click();
    h.run();
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    let out3 = dir.path().join("bracket3.msh");
    h.state_mut().apply(Command::Export(out3.clone()));
    assert_eq!(
        std::fs::read(&out3).unwrap(),
        cli_mesh("cli3.msh", &["--size", "3"])
    );
}

#[test]
fn undoing_an_open_brings_the_document_back_in_view() {
    let mut h = harness(example());
    h.run();
    let name = h.state().doc().name.clone();
    let (center, zoom) = (h.state().view.canvas.center, h.state().view.canvas.zoom);
    h.state_mut().apply(Command::OpenExample("naca0012.poly"));
    h.run();
    assert_eq!(h.state().doc().name, "naca0012.poly");
    // The airfoil is fitted: another centre and zoom than the annulus's.
    assert_ne!(
        (h.state().view.canvas.center, h.state().view.canvas.zoom),
        (center, zoom)
    );
    h.state_mut().apply(Command::Undo);
    h.run();
    assert_eq!(h.state().doc().name, name, "{}", status(&h));
    assert_eq!(status(&h), "undone: open");
    // Fitted again, as when it was first opened, not left at the
    // airfoil's view (where the annulus would be off the canvas).
    assert_eq!(
        (h.state().view.canvas.center, h.state().view.canvas.zoom),
        (center, zoom)
    );
    h.state_mut().apply(Command::Redo);
    h.run();
    assert_eq!(h.state().doc().name, "naca0012.poly");
    assert_ne!(
        (h.state().view.canvas.center, h.state().view.canvas.zoom),
        (center, zoom)
    );
}

/// The shipped drawing opens from File ▸ Open an example, cut at the
/// editor's size for it, and meshes region by region to the end.
#[test]
fn the_example_drawing_opens_from_the_menu_and_meshes() {
    let mut h = harness(example());
    h.run();
    open_example_from_menu(&mut h, "part.dxf");
    assert_eq!(h.state().doc().name, "part.dxf", "{}", status(&h));
    assert!(h.state().doc().drawing.is_some());
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    let m = h.state().doc().region_mesh().expect("every face meshed");
    assert!(m.mesh.quads.len() > 100);
    m.mesh.check_finished().unwrap();
    // Its layers are the mesh's named groups.
    let names: Vec<&str> = m.groups.iter().map(|g| g.name.as_str()).collect();
    assert!(names.contains(&"bolt"), "{names:?}");
}

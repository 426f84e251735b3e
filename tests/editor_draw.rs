//! The editor's drawing and boundary editing, with the pointer on the
//! canvas (egui_kittest): loops drawn by clicks, arcs, the Move tool,
//! live validation, resampling.
#![cfg(feature = "gui")]

mod common;

use common::editor::*;
use egui::Pos2;
use egui_kittest::kittest::{NodeT, Queryable};
use egui_kittest::Harness;
use quadex::app::tools::Hover;
use quadex::app::{App, Command, Document, MeshKind, Settings};
use std::path::Path;

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
    draw_plate_with_hole(&mut h, c);
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
    draw_plate_with_hole(&mut h, c);
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
    draw_loop(&mut h, &corners);
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

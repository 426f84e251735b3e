//! The editor's documents of several regions and named boundary groups,
//! clicked through with egui_kittest (no window, no GPU): the machine
//! example opened from the menu, stepped region by region, run to the end
//! and exported with its physical names; an interface drawn with the
//! pointer across a square; segments picked and named as a group; a
//! project saved and opened again.
#![cfg(feature = "gui")]

mod common;

use common::editor::*;
use egui::Pos2;
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use quadex::app::{App, Command, Document, Settings};
use quadex::Point;
use std::path::PathBuf;

/// A primary click with Shift held (the button events carry the
/// modifier).
fn shift_click_at(h: &mut Harness<'static, App>, pos: Pos2) {
    h.hover_at(pos);
    h.run();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::SHIFT,
        });
        h.run();
    }
}

/// Clicks a button of the left panel, scrolled into view first.
fn click_button(h: &mut Harness<'static, App>, label: &str) {
    h.get_by_label(label).scroll_to_me();
    h.run();
    h.get_by_label(label).click();
    h.run();
}

/// The square opened from its file and made a document of regions with
/// the button of the left panel.
fn square_as_regions() -> Harness<'static, App> {
    let mut h = harness(App::new(
        Document::open(&boundary("square.poly"), Settings::default())
            .unwrap()
            .0,
    ));
    h.run();
    assert!(
        h.state().doc().regions.is_none(),
        "a plain boundary opens as before"
    );
    h.get_by_label("Regions and groups…").click();
    h.run();
    let r = h
        .state()
        .doc()
        .regions
        .as_ref()
        .expect("a document of regions");
    assert_eq!(r.faces.len(), 1);
    h
}

/// Draws the interface x = 0.5 across the square with the pointer: a click
/// on the node (0.5, 0), a bend at (0.5, 0.4), a click on the node
/// (0.5, 1).
fn draw_interface(h: &mut Harness<'static, App>) {
    h.get_by_label("interface").click();
    h.run();
    for p in [(0.5, 0.0), (0.5, 0.4), (0.5, 1.0)] {
        let s = screen(h, Point::new(p.0, p.1));
        click_at(h, s);
    }
}

#[test]
fn the_machine_example_opens_from_the_menu_with_its_regions_and_groups() {
    let mut h = harness(App::new(
        Document::example("annulus.poly", Settings::default()).unwrap(),
    ));
    h.run();
    open_example_from_menu(&mut h, "machine.json");
    let r = h
        .state()
        .doc()
        .regions
        .as_ref()
        .expect("a document of regions");
    assert!(r.problem.is_none());
    assert_eq!(r.faces.len(), 19);
    let names: Vec<&str> = r.legend.iter().map(|(_, n)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "rotor_iron",
            "magnets",
            "air_gap",
            "stator_iron",
            "windings"
        ]
    );
    // The Regions panel lists the regions and the groups.
    for n in names {
        h.get_by_label(n);
    }
    h.get_by_label_contains("shaft (tag 1): 24 segments");
    h.get_by_label_contains("stator_outside (tag 2): 96 segments");
    h.get_by_label_contains("face 1 of 19");
}

/// The machine example after three clicks on Step.
fn machine_after_three_steps() -> Harness<'static, App> {
    let mut h = harness(example_named("machine.json"));
    h.run();
    for _ in 0..3 {
        h.get_by_label_contains("(Space)").click();
        h.run();
    }
    assert_eq!(h.state().doc().steps(), 3);
    h
}

#[test]
fn stepping_goes_region_by_region_and_the_export_has_the_physical_names() {
    let mut h = machine_after_three_steps();
    let first = {
        let s = h
            .state()
            .doc()
            .regions
            .as_ref()
            .unwrap()
            .stepper
            .as_ref()
            .unwrap();
        assert_eq!(s.current(), 0);
        s.current_region()
    };
    h.get_by_label(&format!("region {first}, face 1 of 19"));
    // Undo goes back within the face.
    h.get_by_label_contains("Undo  (").click();
    h.run();
    assert_eq!(h.state().doc().steps(), 2);
    // Enough steps to finish the first face: the panel names the next.
    for _ in 0..100 {
        h.state_mut().apply(Command::StepN(200));
        let s = h
            .state()
            .doc()
            .regions
            .as_ref()
            .unwrap()
            .stepper
            .as_ref()
            .unwrap();
        if s.current() > 0 {
            break;
        }
    }
    h.run();
    let (k, region) = {
        let s = h
            .state()
            .doc()
            .regions
            .as_ref()
            .unwrap()
            .stepper
            .as_ref()
            .unwrap();
        (s.current(), s.current_region())
    };
    assert!(k >= 1, "the first face is finished");
    h.get_by_label(&format!("region {region}, face {} of 19", k + 1));
    // Run to end in the background, then export.
    h.get_by_label_contains("Run to end").click();
    h.step();
    settle(&mut h);
    assert!(h.state().doc().is_done(), "{}", status(&h));
    h.get_by_label("mesh complete");
    let m = h.state().doc().region_mesh().unwrap().clone();
    assert_eq!(m.regions.len(), 5);
    assert!(m.regions.iter().all(|r| r.quality.quads > 0));
    m.check_conforming().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("machine.msh");
    h.state_mut().panels.export_path = out.display().to_string();
    h.get_by_label("Export mesh").click();
    h.run();
    assert!(status(&h).starts_with("wrote"), "{}", status(&h));
    let mesh = quadex::io::read_mesh(&out).unwrap();
    assert_eq!(mesh.quads.len(), m.mesh.quads.len());
    let text = std::fs::read_to_string(&out).unwrap();
    for name in [
        "rotor_iron",
        "stator_iron",
        "windings",
        "shaft",
        "stator_outside",
    ] {
        assert!(
            text.contains(&format!("\"{name}\"")),
            "{name} in the export"
        );
    }
    // The same mesh as the command line makes, byte for byte.
    let graph = h.state().doc().regions.as_ref().unwrap().graph.clone();
    let (model, _) = quadex::app::document::load_model("default", &[]).unwrap();
    let s = Settings::default();
    let params = quadex::pipeline::Params {
        extract: s.params(),
        finish: s.finishing(),
    };
    let cli = quadex::regions::mesh_regions(&graph, model, &params, |_| {}).unwrap();
    assert_eq!(text, quadex::io::MeshFormat::Msh41.render_regions(&cli));
}

#[test]
fn an_interface_drawn_across_the_square_makes_two_regions_that_mesh() {
    let mut h = square_as_regions();
    draw_interface(&mut h);
    let r = h.state().doc().regions.as_ref().unwrap();
    assert!(r.problem.is_none(), "{}", status(&h));
    assert_eq!(r.faces.len(), 2, "{}", status(&h));
    assert!(r.faces.iter().all(|f| f.boundary.node_count() % 2 == 0));
    // The curve is divided like the square's sides (0.1 long).
    assert_eq!(r.graph.points.len(), 40 + 9);
    // Name the two faces' regions: click inside each, type, Name region.
    for (x, name) in [(0.25, "copper"), (0.75, "steel")] {
        h.get_by_label("pick").click();
        h.run();
        let s = screen(&h, Point::new(x, 0.7));
        click_at(&mut h, s);
        assert!(h.state().panels.regions.face.is_some());
        h.state_mut().panels.regions.region_name = name.into();
        click_button(&mut h, "Name region");
        assert!(
            status(&h).starts_with("name region: 2 faces"),
            "{}",
            status(&h)
        );
    }
    let r = h.state().doc().regions.as_ref().unwrap();
    let names: Vec<&str> = r.legend.iter().map(|(_, n)| n.as_str()).collect();
    assert_eq!(names, ["copper", "steel"]);
    h.get_by_label_contains("Run to end").click();
    h.step();
    settle(&mut h);
    let m = h.state().doc().region_mesh().expect("meshed").clone();
    m.check_conforming().unwrap();
    assert_eq!(m.faces.len(), 2);
    assert!(m.regions.iter().all(|r| r.quality.quads > 0));
    // Both regions meet along the interface: its nodes are shared.
    let on_interface = m
        .mesh
        .nodes
        .iter()
        .filter(|p| (p.x - 0.5).abs() < 1e-12)
        .count();
    assert_eq!(on_interface, 11);
    // Undo takes the names and the interface back, one edit at a time.
    for _ in 0..3 {
        h.state_mut().apply(Command::Undo);
    }
    assert_eq!(status(&h), "undone: interface");
    let r = h.state().doc().regions.as_ref().unwrap();
    assert_eq!(r.faces.len(), 1);
}

#[test]
fn picked_segments_named_as_a_group_are_in_the_exports() {
    let mut h = square_as_regions();
    h.get_by_label("pick").click();
    h.run();
    // The bottom side's first two segments: a click, then a shift-click.
    let a = screen(&h, Point::new(0.05, 0.0));
    click_at(&mut h, a);
    let b = screen(&h, Point::new(0.15, 0.0));
    shift_click_at(&mut h, b);
    assert_eq!(h.state().panels.regions.picked.len(), 2);
    h.get_by_label("2 segments picked");
    h.state_mut().panels.regions.group_name = "inlet".into();
    click_button(&mut h, "Name group");
    let g = h.state().doc().regions.as_ref().unwrap().graph.clone();
    let grouped: Vec<usize> = (0..g.segments.len())
        .filter(|&k| g.segments[k].marker != 0)
        .collect();
    assert_eq!(grouped.len(), 2, "{}", status(&h));
    assert_eq!(g.group_name(g.segments[grouped[0]].marker), "inlet");
    h.get_by_label_contains("inlet (tag 1): 2 segments");
    // The boundary saved: names in JSON, markers in .poly.
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("square_regions.json");
    let poly = dir.path().join("square_regions.poly");
    h.state_mut().apply(Command::SaveBoundary(json.clone()));
    h.state_mut().apply(Command::SaveBoundary(poly.clone()));
    let back = quadex::io::read_regions(&json)
        .unwrap()
        .expect("a regions document");
    assert_eq!(back.group_names.get(&1).map(String::as_str), Some("inlet"));
    assert_eq!(back.segments, g.segments);
    let back = quadex::io::read_regions(&poly)
        .unwrap()
        .expect("markers read");
    assert_eq!(back.segments.iter().filter(|s| s.marker == 1).count(), 2);
    // The mesh export has the group.
    h.get_by_label_contains("Run to end").click();
    h.step();
    settle(&mut h);
    assert!(h.state().doc().is_done(), "{}", status(&h));
    let out = dir.path().join("square.msh");
    h.state_mut().apply(Command::Export(out.clone()));
    assert!(status(&h).starts_with("wrote"), "{}", status(&h));
    quadex::io::read_mesh(&out).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("\"inlet\""));
    let m = h.state().doc().region_mesh().unwrap();
    assert_eq!(m.groups.len(), 1);
    assert_eq!(m.groups[0].edges.len(), 2);
}

#[test]
fn regions_and_groups_survive_saving_and_opening_the_project() {
    let mut h = square_as_regions();
    draw_interface(&mut h);
    h.state_mut().apply(Command::NameRegion {
        at: Point::new(0.25, 0.5),
        name: "copper".into(),
        tag: 3,
    });
    h.state_mut().apply(Command::NameRegion {
        at: Point::new(0.75, 0.5),
        name: "steel".into(),
        tag: 0,
    });
    h.state_mut().apply(Command::NameGroup {
        segments: vec![0, 1, 2],
        name: "bottom".into(),
        tag: 0,
    });
    let before = h.state().doc().regions.as_ref().unwrap().graph.clone();
    assert!(h.state().unsaved());
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("split.quadex.json");
    h.state_mut().apply(Command::SaveProject(p.clone()));
    assert!(status(&h).starts_with("saved"), "{}", status(&h));
    assert!(!h.state().unsaved());
    let mut h = harness(App::new(Document::open(&p, Settings::default()).unwrap().0));
    h.run();
    let r = h
        .state()
        .doc()
        .regions
        .as_ref()
        .expect("a document of regions");
    assert!(r.problem.is_none());
    assert_eq!(r.graph.points, before.points);
    assert_eq!(r.graph.segments, before.segments);
    assert_eq!(r.graph.regions, before.regions);
    assert_eq!(r.graph.group_name(1), "bottom");
    let names: Vec<(i64, &str)> = r.legend.iter().map(|(t, n)| (*t, n.as_str())).collect();
    assert_eq!(names, [(3, "copper"), (4, "steel")]);
    h.get_by_label("copper");
    h.get_by_label_contains("bottom (tag 1): 3 segments");
    h.state_mut().apply(Command::RunToEnd);
    settle(&mut h);
    let m = h.state().doc().region_mesh().expect("meshed");
    assert_eq!(m.groups[0].name, "bottom");
    assert_eq!(m.regions.len(), 2);
}

#[test]
fn a_graph_that_cannot_be_meshed_opens_with_its_problem_named() {
    let p =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/regions/bad/odd_region.poly");
    let mut h = harness(App::new(Document::open(&p, Settings::default()).unwrap().0));
    h.run();
    let r = h
        .state()
        .doc()
        .regions
        .as_ref()
        .expect("a document of regions");
    let e = r.problem.as_ref().expect("its problem").to_string();
    assert!(e.contains("odd number"), "{e}");
    assert!(!h.state().doc().can_step());
    h.get_by_label(&format!("not a valid graph yet: {e}"));
    h.state_mut().apply(Command::Step);
    assert!(
        status(&h).starts_with("error: no regions to mesh yet"),
        "{}",
        status(&h)
    );
}

#[test]
fn a_face_being_stepped_has_no_front_node_counted_as_interior() {
    let mut h = machine_after_three_steps();
    h.get_by_label("Quality").click();
    h.run();
    h.get_by_label("irregular interior nodes");
    // Three quads cut off the first face's boundary: every corner is on
    // that boundary or on the front, none is closed in by quads yet.
    h.get_by_label("0 of 0");
}

/// The key to the regions and groups, drawn at the canvas's top left, is
/// kept clear of the drawing when the view is fitted: the machine's
/// outline lies right of the key or below it, in a wide window and in a
/// tall one.
#[test]
fn the_regions_key_keeps_clear_of_the_fitted_drawing() {
    for (w, hgt) in [(1400.0, 860.0), (1200.0, 760.0), (1000.0, 1000.0)] {
        let mut h = harness_sized(example_named("machine.json"), w, hgt);
        h.run();
        let rect = h.state().view.canvas_rect;
        let r = h.state().doc().regions.as_ref().unwrap();
        let room = quadex::app::regions_panel::legend_room(r);
        // Five regions and two groups: seven rows, "stator_outside" the
        // longest name.
        assert!(room.x > 100.0 && room.y > 140.0, "{room:?}");
        let xs = r.graph.points.iter().map(|p| p.x);
        let ys = r.graph.points.iter().map(|p| p.y);
        let left = xs.fold(f64::INFINITY, f64::min);
        let top = ys.fold(f64::NEG_INFINITY, f64::max);
        let view = h.state().view.canvas;
        let corner = view.to_screen(rect, Point::new(left, top));
        let margin = 10.0;
        assert!(
            corner.x >= rect.left() + room.x - margin || corner.y >= rect.top() + room.y - margin,
            "{w}x{hgt}: the box's top left {corner:?}, the canvas {rect:?}, the key {room:?}"
        );
    }
}

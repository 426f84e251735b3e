//! The harness the editor tests share (egui_kittest, no window, no GPU):
//! the app in a harness of a given size, frames run until the background
//! work is over, the documents they open, pointer gestures on the canvas
//! (clicks, drags, loops drawn), and what the last frame painted.

pub use super::bench;
use egui::{Pos2, Rect};
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use quadex::app::{App, Command, Document, Settings};
use quadex::model::{ElementType, Form};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// `mesh` is a valid mesh of the annulus: quadex's reader takes it, which
/// checks it (convex quads, every edge used by one or two quads of opposite
/// orientations, the boundary loops a valid boundary, the quads covering the
/// enclosed area once), and its boundary nodes are the annulus's nodes
/// exactly, none added.
pub fn assert_valid_annulus_mesh(mesh: &Path) {
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

pub fn harness_sized(app: App, w: f32, h: f32) -> Harness<'static, App> {
    Harness::builder()
        .with_size([w, h])
        .build_state(|ctx, app: &mut App| app.ui(ctx), app)
}

pub fn harness(app: App) -> Harness<'static, App> {
    harness_sized(app, 1400.0, 860.0)
}

/// Runs frames until the background work (a run, the finishing pass) is
/// over.
pub fn settle(h: &mut Harness<'static, App>) {
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
pub fn wait_for_comparison(h: &mut Harness<'static, App>) {
    let t = Instant::now();
    while h.state().comparing() {
        assert!(t.elapsed().as_secs() < 300, "the comparison did not end");
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    h.run();
}

/// The example open in a harness, `steps` steps taken.
pub fn stepped_example(steps: usize) -> Harness<'static, App> {
    let mut h = harness(example());
    h.run();
    h.state_mut().apply(Command::StepN(steps));
    h
}

/// Clicks File ▸ Open an example ▸ `name`, the menus opened with the
/// pointer.
pub fn open_example_from_menu(h: &mut Harness<'static, App>, name: &str) {
    h.get_by_label("File").click();
    h.run();
    h.get_by_label_contains("Open an example").hover();
    h.run();
    h.get_by_label(name).click();
    h.run();
}

pub fn example() -> App {
    example_named("annulus.poly")
}

pub fn example_named(name: &str) -> App {
    App::new(Document::example(name, Settings::default()).unwrap())
}

pub fn open(path: &Path) -> App {
    App::new(Document::open(path, Settings::default()).unwrap().0)
}

pub fn boundary(name: &str) -> PathBuf {
    bench().join("boundaries").join(name)
}

/// The screen position of a world point on the canvas.
pub fn screen(h: &Harness<'static, App>, p: quadex::Point) -> Pos2 {
    let s = h.state();
    s.view.canvas.to_screen(s.view.canvas_rect, p)
}

/// A primary click at a screen position.
pub fn click_at(h: &mut Harness<'static, App>, pos: Pos2) {
    h.hover_at(pos);
    h.run();
    h.drag_at(pos);
    h.run();
    h.drop_at(pos);
    h.run();
}

/// Press at `from`, move in steps, release at `to`.
pub fn drag(h: &mut Harness<'static, App>, from: Pos2, to: Pos2) {
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
pub fn painted(h: &Harness<'static, App>) -> Vec<(String, Rect, egui::FontId)> {
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
pub fn strokes_of(h: &Harness<'static, App>, color: egui::Color32) -> usize {
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

pub fn status(h: &Harness<'static, App>) -> String {
    h.state().status().to_string()
}

/// Takes five steps, then replaces the last element (type 0) by one whose
/// Pn is `move_pn(Pn, P0, P_r1)` (world) and checks that it was taken;
/// returns the step as it was, its Pn and the corrected Pn.
pub fn step_five_and_correct(
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

/// Clicks `nodes` in turn on the canvas (the drawing tool places a node at
/// each), then the first one again, which closes the loop.
pub fn draw_loop(h: &mut Harness<'static, App>, nodes: &[Pos2]) {
    for &p in nodes {
        click_at(h, p);
    }
    click_at(h, nodes[0]);
}

/// The corners of the square `half` points each way from `c` on screen,
/// from the lower left (screen y grows downwards) anticlockwise as the
/// world sees it; with `midpoints`, each side's midpoint after its first
/// corner.
pub fn square_nodes(c: Pos2, half: f32, midpoints: bool) -> Vec<Pos2> {
    let corners = vec![
        c + egui::vec2(-half, half),
        c + egui::vec2(half, half),
        c + egui::vec2(half, -half),
        c + egui::vec2(-half, -half),
    ];
    if !midpoints {
        return corners;
    }
    (0..4)
        .flat_map(|k| [corners[k], corners[k].lerp(corners[(k + 1) % 4], 0.5)])
        .collect()
}

/// A plate drawn with the drawing tool about `c`: an outer square of 300
/// points with its sides' midpoints (8 nodes) and a square hole of 100
/// points (4 nodes).
pub fn draw_plate_with_hole(h: &mut Harness<'static, App>, c: Pos2) {
    for (half, midpoints) in [(150.0, true), (50.0, false)] {
        draw_loop(h, &square_nodes(c, half, midpoints));
    }
}

/// The example stepped 6 times, its last element appended, refitted
/// (quadratic, in the background, waited for) and stepped 3 times more,
/// then saved as the project `name` in a new folder: the harness, the
/// folder (removed when dropped) and the project's path.
pub fn refitted_and_saved(name: &str) -> (Harness<'static, App>, tempfile::TempDir, PathBuf) {
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
    let path = dir.path().join(name);
    h.state_mut().apply(Command::SaveProject(path.clone()));
    (h, dir, path)
}

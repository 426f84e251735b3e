//! The canvas tools: correcting the last element (drag Pn, or click a
//! front node to close the element onto it: the nodes that give a valid
//! element are marked), and editing the boundary (draw loops, move,
//! insert, delete, split, resample), validated live. A tool takes the
//! pointer when a drag starts on something it handles (a node, the Pn
//! handle); any other drag pans the view.

use super::canvas::{Pointer, View};
use super::command::Command;
use super::document::{Document, Target};
use super::MeshKind;
use crate::boundary_edit::{At, Draft};
use crate::extract::CheckedElement;
use crate::geom::Point;
use crate::model::ElementType;
use crate::quality::{GOOD_ANGLE, GOOD_RATIO};
use egui::{Color32, Pos2, Shape, Stroke, Ui};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// What a primary click or drag on the canvas does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Tool {
    /// Drag Pn of the last element, click a front node to close onto it.
    #[default]
    Correct,
    /// Click to place nodes of a new loop (a hole when there is an outer
    /// loop); click the first node to close it.
    Draw,
    /// Three clicks place an arc in the loop being drawn: its start, a
    /// point it passes through, its end.
    Arc,
    /// Drag a boundary node.
    Move,
    /// Click a segment to insert a node there.
    Insert,
    /// Click a node to delete it.
    Delete,
    /// Click a segment to split it into k parts.
    Split,
}

impl Tool {
    pub const ALL: [Tool; 7] = [
        Tool::Correct,
        Tool::Draw,
        Tool::Arc,
        Tool::Move,
        Tool::Insert,
        Tool::Delete,
        Tool::Split,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Tool::Correct => "correct",
            Tool::Draw => "draw loop",
            Tool::Arc => "draw arc",
            Tool::Move => "move",
            Tool::Insert => "insert",
            Tool::Delete => "delete",
            Tool::Split => "split",
        }
    }

    /// What the tool does, for its tooltip and the hint under the tools.
    pub fn hint(self) -> &'static str {
        match self {
            Tool::Correct => "Drag Pn or click a ringed front node to correct the last element (Pn: the yellow handle; a ring closes the element onto its node: green good, amber fair, orange poor).",
            Tool::Draw => "Click to place nodes; click the first node to close the loop (the first loop is the outer one, later loops are holes). Right-click or Esc drops the loop being drawn.",
            Tool::Arc => "Three clicks place an arc in the loop being drawn: its start, a point it passes through, its end (its nodes at most 15° apart). End on the loop's first node to close the loop. Right-click or Esc drops the loop.",
            Tool::Move => "Drag a boundary node.",
            Tool::Insert => "Click a segment to insert a node there.",
            Tool::Delete => "Click a node to delete it.",
            Tool::Split => "Click a segment to split it into the number of parts below.",
        }
    }
}

/// Pixels within which a click picks a node or a segment.
pub const PICK: f32 = 10.0;

/// The nodes strictly between `a` and `b` of the arc from `a` through `m`
/// to `b`, at most [`crate::cad::MAX_ARC_ANGLE`] (15°) apart, as a
/// drawing's arcs are cut; none when the three points
/// are on a line (the arc is the straight segment).
pub fn arc_nodes(a: Point, m: Point, b: Point) -> Vec<Point> {
    let Some(curve) = crate::cad::arc_through(a, m, b) else {
        return Vec::new();
    };
    let sweep = match curve {
        crate::cad::Curve::Arc { sweep, .. } => sweep,
        _ => return Vec::new(),
    };
    // (A half circle clicked on the screen is 12 parts, not 13.)
    let n = (sweep.abs() / crate::cad::MAX_ARC_ANGLE - 1e-6)
        .ceil()
        .max(2.0) as usize;
    (1..n).map(|k| curve.at(k as f64 / n as f64)).collect()
}

/// What the pointer is over, for highlighting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Hover {
    /// A front node the element could close onto.
    Target(Target),
    /// A front node that is not among the targets.
    FrontNode(u32, Point),
    /// The Pn handle.
    Handle,
    /// A node of the draft.
    Node(At),
    /// A segment of the draft (its first node).
    Segment(At),
}

/// The tool in hand and what it is doing.
pub struct Tools {
    pub tool: Tool,
    /// The loop being drawn.
    pub drawing: Vec<Point>,
    /// The Arc tool's clicks so far (start, then a point on the arc).
    pub arc_clicks: Vec<Point>,
    /// The Move tool's drag: the node and where it is now.
    moving: Option<(At, Point)>,
    /// The Correct tool's drag of Pn: where it is now.
    pn_drag: Option<Point>,
    /// Parts a split makes (3 by default: two nodes more keep the node
    /// count even).
    pub split_parts: usize,
    /// Target segment length of a resample, and the loop.
    pub resample_h: f64,
    pub resample_loop: usize,
    /// Resample every loop (else loop `resample_loop` only).
    pub resample_all: bool,
    /// The document the resample target was set for (its name and file):
    /// another document sets it again.
    resample_for: Option<(String, Option<PathBuf>)>,
    /// What the pointer is over.
    pub hover: Option<Hover>,
}

impl Default for Tools {
    fn default() -> Self {
        Tools {
            tool: Tool::Correct,
            drawing: Vec::new(),
            arc_clicks: Vec::new(),
            moving: None,
            pn_drag: None,
            split_parts: 3,
            resample_h: 0.0,
            resample_loop: 0,
            resample_all: true,
            resample_for: None,
            hover: None,
        }
    }
}

/// What the tools see of the canvas this frame.
pub struct OnCanvas<'a> {
    pub view: &'a View,
    pub pointer: &'a Pointer,
    pub doc: &'a Document,
    /// Front nodes the last element could close onto.
    pub targets: &'a [Target],
    /// What mesh is on the canvas (nothing to correct on a finished one).
    pub kind: MeshKind,
    /// While Pn is dragged: the element it would give (`None` inside: no
    /// valid element there).
    pub drag: Option<Option<CheckedElement>>,
}

/// A drag value for a target size, its speed and range from the extent of
/// `points`.
fn size_value(ui: &mut Ui, h: &mut f64, points: impl Iterator<Item = Point>) -> egui::Response {
    let scale = points
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()))
        .max(1e-12);
    ui.add(
        egui::DragValue::new(h)
            .speed(0.001 * scale)
            .range(1e-9 * scale..=f64::MAX),
    )
}

impl Tools {
    /// The Drawing section of the left panel (a document cut from a
    /// drawing's curves): the target size H, and Apply to cut the curves
    /// again at it and mesh from the start.
    pub fn drawing_ui(&mut self, ui: &mut Ui, doc: &Document) -> Vec<Command> {
        let mut out = Vec::new();
        let Some(d) = &doc.drawing else {
            return out;
        };
        ui.heading("Drawing");
        let count = |f: fn(&crate::cad::Curve) -> bool| {
            d.geometry.curves.iter().filter(|c| f(&c.curve)).count()
        };
        let lines = count(|c| matches!(c, crate::cad::Curve::Line { .. }));
        let arcs = count(|c| matches!(c, crate::cad::Curve::Arc { .. }));
        let ellipses = count(|c| matches!(c, crate::cad::Curve::Ellipse { .. }));
        let splines = count(|c| matches!(c, crate::cad::Curve::Spline(_)));
        let nodes = doc.regions.as_ref().map_or(0, |r| r.graph.points.len());
        let mut kinds = vec![super::plural(lines, "line"), super::plural(arcs, "arc")];
        if ellipses > 0 {
            kinds.push(super::plural(ellipses, "ellipse"));
        }
        if splines > 0 {
            kinds.push(super::plural(splines, "spline"));
        }
        ui.label(format!(
            "{}; cut at size {} into {}{}",
            kinds.join(", "),
            d.size,
            super::plural(nodes, "boundary node"),
            if d.parity_fixes > 0 {
                format!(
                    " ({} one segment more for even regions)",
                    super::plural(d.parity_fixes, "curve")
                )
            } else {
                String::new()
            }
        ));
        ui.horizontal_wrapped(|ui| {
            ui.label("size H");
            let pts = doc.regions.iter().flat_map(|r| r.graph.points.iter().copied());
            size_value(ui, &mut self.resample_h, pts)
                .on_hover_text("Target size H: each curve is cut into about length / H segments (arcs also one per 15°), every region's node count made even");
            let changed = (self.resample_h - d.size).abs() > 1e-12 * d.size.abs().max(1.0);
            if ui
                .add_enabled(changed, egui::Button::new("Apply"))
                .on_hover_text("Cut the curves again at size H and mesh from the start")
                .on_disabled_hover_text("The drawing is cut at this size")
                .clicked()
            {
                out.push(Command::SetSize(self.resample_h));
            }
        });
        out
    }
}

/// Lines of the tool bar's note under its tools.
const NOTE_ROWS: usize = 2;

/// Drafts of at most this many nodes show every node's number.
const NUMBERED_NODES: usize = 400;
/// Screen points between two numbered nodes, at least.
const NUMBER_ROOM: f32 = 16.0;

/// The draft's median segment, the default target of a resample.
fn median_segment(d: &Draft) -> f64 {
    let mut lens: Vec<f64> = d
        .loops
        .iter()
        .flat_map(|l| (0..l.len()).map(move |k| l[k].distance(l[(k + 1) % l.len()])))
        .filter(|x| *x > 0.0)
        .collect();
    lens.sort_by(f64::total_cmp);
    lens.get(lens.len() / 2).copied().unwrap_or(0.0)
}

/// "outer" or "hole" for draft loop `li`: the largest loop is the outer
/// one when the draft becomes a boundary.
pub fn loop_role(d: &Draft, li: usize) -> &'static str {
    let area = |l: &Vec<Point>| crate::geom::polygon_area(l.iter().copied()).abs();
    let outer = (0..d.loops.len()).max_by(|&a, &b| area(&d.loops[a]).total_cmp(&area(&d.loops[b])));
    if Some(li) == outer {
        "outer"
    } else {
        "hole"
    }
}

impl Tools {
    /// Where Pn is being dragged to, if it is.
    pub fn pn_drag(&self) -> Option<Point> {
        self.pn_drag
    }

    /// Keeps the tool state in step with the document: a new document
    /// (another file, New) sets the resample target to its median segment.
    pub fn sync(&mut self, doc: &Document) {
        let id = (doc.name.clone(), doc.source.clone());
        if self.resample_for.as_ref() != Some(&id) {
            self.resample_for = Some(id);
            self.resample_h = match &doc.drawing {
                Some(d) => d.size,
                None => median_segment(&doc.draft),
            };
            self.resample_loop = 0;
            self.resample_all = true;
            self.drawing.clear();
            self.arc_clicks.clear();
            self.moving = None;
            self.pn_drag = None;
        }
        if self.resample_h <= 0.0 {
            self.resample_h = match &doc.drawing {
                Some(d) => d.size,
                None => median_segment(&doc.draft),
            };
        }
        self.resample_loop = self
            .resample_loop
            .min(doc.draft.loops.len().saturating_sub(1));
    }

    /// Drops the loop being drawn; false when there is none.
    pub fn drop_drawing(&mut self) -> bool {
        let clicks = !std::mem::take(&mut self.arc_clicks).is_empty();
        !std::mem::take(&mut self.drawing).is_empty() || clicks
    }

    /// The command that adds the loop being drawn, closed, to `draft`.
    fn close_drawing(&mut self, draft: &Draft, what: &'static str) -> Command {
        let mut d = draft.clone();
        d.loops.push(std::mem::take(&mut self.drawing));
        Command::SetDraft { draft: d, what }
    }

    /// A pointer drag or click of the tool; returns whether the tool takes
    /// the primary drag (else it pans the view).
    pub fn input(&mut self, at: &OnCanvas, out: &mut Vec<Command>) -> bool {
        self.hover = None;
        let p = at.pointer;
        let view = at.view;
        let to = |w: Point| view.to_screen(p.rect, w);
        let near = |a: Pos2, b: Option<Pos2>| b.is_some_and(|b| a.distance(b) <= PICK);
        match self.tool {
            Tool::Correct => {
                if at.kind != MeshKind::Stepped {
                    return false;
                }
                let Some(handle) = pn_handle(at.doc) else {
                    return false;
                };
                if p.drag_started && near(to(handle), p.press_origin) {
                    self.pn_drag = Some(handle);
                }
                if self.pn_drag.is_some() {
                    if let Some(w) = p.world {
                        self.pn_drag = Some(w);
                    }
                    self.hover = Some(Hover::Handle);
                    if p.drag_stopped || !p.dragging {
                        if let Some(pn) = self.pn_drag.take() {
                            out.push(Command::CorrectLast {
                                element_type: ElementType::New,
                                pn,
                                snap_to: None,
                            });
                        }
                    }
                    return true;
                }
                if !p.hovered {
                    return false;
                }
                if near(to(handle), p.pos) {
                    self.hover = Some(Hover::Handle);
                    return false;
                }
                // A front node under the pointer: a target, or not one.
                let target = p.pos.and_then(|s| {
                    at.targets
                        .iter()
                        .map(|t| (t, to(t.at).distance(s)))
                        .filter(|(_, d)| *d <= PICK)
                        .min_by(|a, b| a.1.total_cmp(&b.1))
                        .map(|(t, _)| *t)
                });
                self.hover = match target {
                    Some(t) => Some(Hover::Target(t)),
                    None => front_node_at(at, p.pos).map(|(v, w)| Hover::FrontNode(v, w)),
                };
                if p.clicked.is_some() {
                    match self.hover {
                        Some(Hover::Target(t)) => out.push(t.command()),
                        Some(Hover::FrontNode(v, w)) => out.push(Command::CorrectLast {
                            element_type: ElementType::New,
                            pn: w,
                            snap_to: Some(v),
                        }),
                        _ => {}
                    }
                }
                false
            }
            Tool::Draw => {
                if p.secondary_clicked {
                    self.drawing.clear();
                }
                if let (Some(c), Some(w)) = (p.clicked, p.world) {
                    let closes = self.drawing.len() >= 3 && to(self.drawing[0]).distance(c) <= PICK;
                    if closes {
                        out.push(self.close_drawing(&at.doc.draft, "draw loop"));
                    } else {
                        self.drawing.push(w);
                    }
                }
                false
            }
            Tool::Arc => {
                if p.secondary_clicked {
                    self.drawing.clear();
                    self.arc_clicks.clear();
                }
                if let (Some(c), Some(w)) = (p.clicked, p.world) {
                    // The end on the loop's first node closes the loop.
                    let closes = self.arc_clicks.len() == 2
                        && self.drawing.len() >= 2
                        && to(self.drawing[0]).distance(c) <= PICK;
                    self.arc_clicks
                        .push(if closes { self.drawing[0] } else { w });
                    if let [a, m, b] = self.arc_clicks[..] {
                        self.arc_clicks.clear();
                        if self.drawing.last() != Some(&a) {
                            self.drawing.push(a);
                        }
                        self.drawing.extend(arc_nodes(a, m, b));
                        if closes {
                            out.push(self.close_drawing(&at.doc.draft, "draw arc"));
                        } else {
                            self.drawing.push(b);
                        }
                    }
                }
                false
            }
            Tool::Move => {
                let d = &at.doc.draft;
                if p.drag_started {
                    let origin = p.press_origin.map(|s| view.to_world(p.rect, s));
                    self.moving = origin
                        .and_then(|o| d.nearest_node(o, PICK as f64 / view.zoom))
                        .and_then(|a| Some((a, *d.loops.get(a.0)?.get(a.1)?)));
                }
                if let Some((a, _)) = self.moving {
                    if let Some(w) = p.world {
                        self.moving = Some((a, w));
                    }
                    self.hover = Some(Hover::Node(a));
                    if p.drag_stopped || !p.dragging {
                        if let Some((a, w)) = self.moving.take() {
                            let mut d = d.clone();
                            d.move_node(a, w);
                            out.push(Command::SetDraft {
                                draft: d,
                                what: "move node",
                            });
                        }
                    }
                    return true;
                }
                self.hover = p
                    .world
                    .filter(|_| p.hovered)
                    .and_then(|w| d.nearest_node(w, PICK as f64 / view.zoom))
                    .map(Hover::Node);
                false
            }
            Tool::Insert | Tool::Delete | Tool::Split => {
                let d = &at.doc.draft;
                let r = PICK as f64 / view.zoom;
                self.hover = p.world.filter(|_| p.hovered).and_then(|w| {
                    if self.tool == Tool::Delete {
                        d.nearest_node(w, r).map(Hover::Node)
                    } else {
                        d.nearest_segment(w, r).map(Hover::Segment)
                    }
                });
                if p.clicked.is_some() {
                    let mut d = d.clone();
                    let what = match (self.tool, self.hover, p.world) {
                        (Tool::Delete, Some(Hover::Node(n)), _) => {
                            d.delete(n);
                            Some("delete node")
                        }
                        (Tool::Insert, Some(Hover::Segment(s)), Some(w)) => {
                            d.insert(s, w);
                            Some("insert node")
                        }
                        (Tool::Split, Some(Hover::Segment(s)), _) => {
                            d.split(s, self.split_parts);
                            Some("split segment")
                        }
                        _ => None,
                    };
                    if let Some(what) = what {
                        out.push(Command::SetDraft { draft: d, what });
                    }
                }
                false
            }
        }
    }

    /// Draws the tool's overlay: the Pn handle and the candidate element,
    /// the closing targets, or the draft with its loop numbers.
    pub fn draw(&self, ui: &Ui, painter: &egui::Painter, at: &OnCanvas) {
        let rect = at.pointer.rect;
        let to = |w: Point| at.view.to_screen(rect, w);
        let yellow = Color32::from_rgb(255, 230, 60);
        let red = Color32::from_rgb(255, 70, 70);
        let cyan = Color32::from_rgb(80, 220, 255);
        if self.tool == Tool::Correct {
            if at.kind != MeshKind::Stepped {
                return;
            }
            let Some(last) = at.doc.last_element() else {
                return;
            };
            let nodes = &at.doc.mesher().map(|m| &m.mesh().nodes);
            let Some(nodes) = nodes else { return };
            let n = last.leading.len() / 2;
            let node = |k: usize| {
                last.leading
                    .get(k)
                    .and_then(|&v| nodes.get(v as usize).copied())
            };
            let (Some(l1), Some(p0), Some(r1)) = (node(n.wrapping_sub(1)), node(n), node(n + 1))
            else {
                return;
            };
            for t in at.targets.iter().filter(|t| t.valid()) {
                painter.circle_stroke(to(t.at), 5.0, Stroke::new(2.0, target_colour(t)));
            }
            // The candidate element: while dragging, or for the hovered
            // target.
            let candidate = match (self.pn_drag, self.hover) {
                (Some(pn), _) => Some((
                    pn,
                    match at.drag {
                        Some(check) => check_colour(check.as_ref()),
                        None => yellow,
                    },
                )),
                (None, Some(Hover::Target(t))) => Some((t.at, target_colour(&t))),
                _ => None,
            };
            if let Some((pn, c)) = candidate {
                let ring = [p0, r1, pn, l1, p0].map(to);
                painter.extend(Shape::dashed_line(&ring, Stroke::new(2.0, c), 5.0, 4.0));
            }
            if let Some(h) = pn_handle(at.doc) {
                let s = to(self.pn_drag.unwrap_or(h));
                let w = if matches!(self.hover, Some(Hover::Handle)) {
                    3.0
                } else {
                    2.0
                };
                painter.circle_stroke(s, 8.0, Stroke::new(w, yellow));
            }
            match self.hover {
                Some(Hover::Target(t)) => {
                    painter.circle_stroke(to(t.at), 8.0, Stroke::new(2.5, target_colour(&t)));
                    let text = if let Some(check) = &t.check {
                        // Named as the canvas labels the leading points.
                        let label = match t.element_type {
                            ElementType::Right => "r2, ",
                            ElementType::Left => "l2, ",
                            ElementType::New => "",
                        };
                        format!(
                            "click: close the element onto node {} ({label}type {})\n{}",
                            t.node,
                            t.element_type.number(),
                            verdict(check)
                        )
                    } else {
                        format!("node {}: not a valid element there", t.node)
                    };
                    tip(ui, &text);
                }
                Some(Hover::FrontNode(v, w)) => {
                    painter.circle_stroke(to(w), 8.0, Stroke::new(2.0, red));
                    let corner = n
                        .checked_sub(1)
                        .and_then(|k| last.leading.get(k..=n + 1))
                        .is_some_and(|c| c.contains(&v));
                    tip(
                        ui,
                        &if corner {
                            format!("node {v} is a corner of this element: nothing to close onto")
                        } else {
                            format!("node {v}: too far from P0 to close the element onto")
                        },
                    );
                }
                Some(Hover::Handle) if self.pn_drag.is_none() => {
                    tip(ui, "drag Pn and let go to correct the element");
                }
                Some(Hover::Handle) => match at.drag {
                    Some(Some(check)) => tip(ui, &format!("let go: {}", verdict(&check))),
                    Some(None) => tip(ui, "not a valid element here: letting go changes nothing"),
                    None => {}
                },
                _ => {}
            }
            return;
        }
        // The draft, its loop numbers, the problem's nodes.
        let mut draft = at.doc.draft.clone();
        if let Some((a, w)) = self.moving {
            draft.move_node(a, w);
        }
        let line = Color32::from_rgb(240, 240, 240);
        for (li, l) in draft.loops.iter().enumerate() {
            let pts: Vec<Pos2> = l.iter().map(|&p| to(p)).collect();
            painter.add(Shape::closed_line(pts.clone(), Stroke::new(1.5, line)));
            for &p in &pts {
                painter.circle_filled(p, 3.0, line);
            }
            // The loop's number above its topmost node, kept on the canvas.
            if let Some(top) = pts.iter().min_by(|a, b| a.y.total_cmp(&b.y)) {
                let galley = painter.layout_no_wrap(
                    format!("loop {li} ({})", loop_role(&draft, li)),
                    egui::FontId::proportional(13.0),
                    cyan,
                );
                let size = galley.size();
                let min = *top + egui::vec2(-0.5 * size.x, -8.0 - size.y);
                let inner = rect.shrink(2.0);
                let x = min
                    .x
                    .clamp(inner.left(), (inner.right() - size.x).max(inner.left()));
                let y = min
                    .y
                    .clamp(inner.top(), (inner.bottom() - size.y).max(inner.top()));
                painter.galley(Pos2::new(x, y), galley, cyan);
            }
        }
        let marked = at
            .doc
            .problem
            .as_ref()
            .map(|e| draft.marked(e))
            .unwrap_or_default();
        for &(li, k) in &marked {
            if let Some(&p) = draft.loops.get(li).and_then(|l| l.get(k)) {
                painter.circle_stroke(to(p), 7.0, Stroke::new(2.0, red));
            }
        }
        // The nodes' numbers, as the problems name them (1 up over all
        // loops): each node at fault, and the others where they have room.
        let font = egui::FontId::proportional(11.0);
        let label = |p: Pos2, n: usize, c: Color32| {
            painter.text(
                p + egui::vec2(6.0, -6.0),
                egui::Align2::LEFT_BOTTOM,
                n.to_string(),
                font.clone(),
                c,
            );
        };
        let mut number = 0;
        let mut last: Option<Pos2> = None;
        for (li, l) in draft.loops.iter().enumerate() {
            for (k, &p) in l.iter().enumerate() {
                number += 1;
                let s = to(p);
                if marked.contains(&(li, k)) {
                    label(s, number, red);
                } else if draft.node_count() <= NUMBERED_NODES
                    && rect.contains(s)
                    && last.is_none_or(|q| q.distance(s) >= NUMBER_ROOM)
                {
                    label(s, number, Color32::from_gray(170));
                    last = Some(s);
                }
            }
        }
        // The Arc tool's clicks, and the arc the pointer would end.
        if !self.arc_clicks.is_empty() {
            let pointer = at.pointer.world.filter(|_| at.pointer.hovered);
            let mut path: Vec<Point> = self.arc_clicks[..1].to_vec();
            match (&self.arc_clicks[..], pointer) {
                ([a, m], Some(b)) => {
                    path.extend(arc_nodes(*a, *m, b));
                    path.push(b);
                }
                (_, Some(b)) => path.push(b),
                _ => {}
            }
            let pts: Vec<Pos2> = path.iter().map(|&p| to(p)).collect();
            painter.add(Shape::line(pts, Stroke::new(1.5, cyan)));
            for &p in &self.arc_clicks {
                painter.circle_stroke(to(p), 4.0, Stroke::new(1.5, cyan));
            }
        }
        if !self.drawing.is_empty() {
            let mut pts: Vec<Pos2> = self.drawing.iter().map(|&p| to(p)).collect();
            if let Some(h) = at.pointer.pos.filter(|_| at.pointer.hovered) {
                pts.push(h);
            }
            painter.add(Shape::line(pts.clone(), Stroke::new(1.5, cyan)));
            for p in &pts {
                painter.circle_filled(*p, 3.0, cyan);
            }
            if self.drawing.len() >= 3 {
                painter.circle_stroke(to(self.drawing[0]), PICK, Stroke::new(1.5, cyan));
            }
        }
        let node = |a: At| draft.loops.get(a.0).and_then(|l| l.get(a.1)).copied();
        match self.hover {
            Some(Hover::Node(a)) => {
                if let Some(p) = node(a) {
                    let c = if self.tool == Tool::Delete { red } else { cyan };
                    painter.circle_stroke(to(p), 7.0, Stroke::new(2.0, c));
                }
            }
            Some(Hover::Segment((li, k))) => {
                if let (Some(a), Some(b)) = (
                    node((li, k)),
                    draft
                        .loops
                        .get(li)
                        .and_then(|l| l.get((k + 1) % l.len()))
                        .copied(),
                ) {
                    painter.line_segment([to(a), to(b)], Stroke::new(3.0, cyan));
                }
            }
            _ => {}
        }
    }
}

/// A tooltip at the pointer, opening towards the canvas's middle
/// ([`super::canvas::canvas_tip`]).
fn tip(ui: &Ui, text: &str) {
    super::canvas::canvas_tip(ui, ui.clip_rect(), egui::Id::new("canvas_tip"), |ui| {
        ui.label(text);
    });
}

/// Where the Pn handle of the last element rests: its committed Pn node.
pub fn pn_handle(doc: &Document) -> Option<Point> {
    let r = doc.last_element()?;
    let v = r.pn_node()?;
    doc.mesher()?.mesh().nodes.get(v as usize).copied()
}

/// The front node under the pointer, if any.
fn front_node_at(at: &OnCanvas, pos: Option<Pos2>) -> Option<(u32, Point)> {
    let s = pos?;
    let m = at.doc.mesher()?;
    let f = m.front();
    let nodes = &m.mesh().nodes;
    f.live_loops()
        .flat_map(|l| f.loop_nodes(l))
        .filter_map(|v| {
            let w = *nodes.get(v as usize)?;
            let d = at.view.to_screen(at.pointer.rect, w).distance(s);
            (d <= PICK).then_some((v, w, d))
        })
        .min_by(|a, b| a.2.total_cmp(&b.2))
        .map(|(v, w, _)| (v, w))
}

impl Tools {
    /// The tool bar above the canvas: the tools, the one in hand's hint and
    /// options (a split's parts, the loop being drawn, the closing targets
    /// of the Correct tool).
    pub fn toolbar(
        &mut self,
        ui: &mut Ui,
        doc: &Document,
        kind: MeshKind,
        targets: &[Target],
    ) -> Vec<Command> {
        // The tools on one row, what the tool says below in two lines
        // whatever it says (a bar whose height changed would shrink the
        // canvas and move the drawing under the pointer): a text longer
        // than two lines is cut, in full on hover.
        let mut said: Option<(String, bool)> = None;
        let mut note = |_: &mut Ui, text: String, weak: bool| said = Some((text, weak));
        ui.horizontal(|ui| {
            ui.label(egui::RichText::new("Tool").strong());
            for t in Tool::ALL {
                ui.selectable_value(&mut self.tool, t, t.name())
                    .on_hover_text(t.hint());
            }
            ui.separator();
            match self.tool {
                Tool::Correct
                    if doc.last_element().is_some() && kind == MeshKind::Stepped =>
                {
                    let valid = targets.iter().filter(|t| t.valid()).count();
                    note(
                        ui,
                        if valid == 0 {
                            "Drag Pn to correct. No front node near P0 closes a valid element here: the quad would be flat or fold. Closing onto a node works where the front turns (corners, fronts meeting).".to_string()
                        } else {
                            format!(
                                "Click a ringed node to close onto it, or drag Pn: {} near P0 {} a valid element (green good, amber fair, orange poor).",
                                super::plural(valid, "front node"),
                                if valid == 1 { "gives" } else { "give" }
                            )
                        },
                        false,
                    );
                }
                Tool::Arc if !self.arc_clicks.is_empty() || !self.drawing.is_empty() => {
                    if ui
                        .button("Drop the loop")
                        .on_hover_text("Forget the nodes and arc points placed (Esc or right-click)")
                        .clicked()
                    {
                        self.drawing.clear();
                        self.arc_clicks.clear();
                    }
                    note(
                        ui,
                        format!(
                            "{} placed; {}",
                            super::plural(self.drawing.len(), "node"),
                            match self.arc_clicks.len() {
                                0 => "click the next arc's start",
                                1 => "click a point the arc passes through",
                                _ => "click the arc's end (the first node closes the loop)",
                            }
                        ),
                        false,
                    );
                }
                Tool::Draw if !self.drawing.is_empty() => {
                    if ui
                        .button("Drop the loop")
                        .on_hover_text("Forget the nodes placed (Esc or right-click)")
                        .clicked()
                    {
                        self.drawing.clear();
                    }
                    note(
                        ui,
                        format!(
                            "{} placed; click the first node to close the loop",
                            super::plural(self.drawing.len(), "node")
                        ),
                        false,
                    );
                }
                Tool::Split => {
                    ui.label("parts");
                    ui.add(egui::DragValue::new(&mut self.split_parts).range(2..=100))
                        .on_hover_text("A split cuts the segment clicked into this many equal parts (an odd number keeps the boundary's node count even, as an all-quad mesh needs)");
                    note(ui, self.tool.hint().to_string(), true);
                }
                t => note(ui, t.hint().to_string(), true),
            }
        });
        let rows = NOTE_ROWS as f32 * ui.text_style_height(&egui::TextStyle::Body)
            + ui.spacing().item_spacing.y;
        let width = ui.available_width();
        ui.allocate_ui_with_layout(
            egui::vec2(width, rows),
            egui::Layout::top_down(egui::Align::Min),
            |ui| {
                ui.set_min_size(egui::vec2(width, rows));
                if let Some((text, weak)) = said {
                    let color = if weak {
                        ui.visuals().weak_text_color()
                    } else {
                        ui.visuals().text_color()
                    };
                    let mut job = egui::text::LayoutJob::single_section(
                        text.clone(),
                        egui::TextFormat::simple(egui::TextStyle::Body.resolve(ui.style()), color),
                    );
                    job.wrap = egui::text::TextWrapping {
                        max_width: width,
                        max_rows: NOTE_ROWS,
                        break_anywhere: false,
                        overflow_character: Some('…'),
                    };
                    ui.add(egui::Label::new(job)).on_hover_text(text);
                }
            },
        );
        Vec::new()
    }
}

impl super::View for Tools {
    /// The boundary section of the left panel: its loops, resampling, and
    /// whether it is a valid boundary.
    type Input<'a> = ();

    fn ui(&mut self, ui: &mut Ui, doc: &Document, _: ()) -> Vec<Command> {
        let mut out = Vec::new();
        ui.heading("Boundary");
        let d = &doc.draft;
        if !d.loops.is_empty() {
            ui.horizontal_wrapped(|ui| {
                ui.label("resample");
                let name = |li: usize| {
                    format!(
                        "loop {li} ({}, {})",
                        loop_role(d, li),
                        super::plural(d.loops[li].len(), "node")
                    )
                };
                let all = format!("all loops ({})", super::plural(d.node_count(), "node"));
                let li = self.resample_loop.min(d.loops.len() - 1);
                egui::ComboBox::from_id_salt("resample_loop")
                    .selected_text(if self.resample_all { all.clone() } else { name(li) })
                    .show_ui(ui, |ui| {
                        if ui.selectable_label(self.resample_all, &all).clicked() {
                            self.resample_all = true;
                        }
                        for li in 0..d.loops.len() {
                            let on = !self.resample_all && self.resample_loop == li;
                            if ui.selectable_label(on, name(li)).clicked() {
                                self.resample_all = false;
                                self.resample_loop = li;
                            }
                        }
                    })
                    .response
                    .on_hover_text("The loops to resample: all of them, or one (numbers as on the canvas with an editing tool)");
                ui.label("to size H");
                size_value(ui, &mut self.resample_h, d.loops.iter().flatten().copied())
                    .on_hover_text("Target size H: the segment length to cut the boundary at (starts at this file's median segment)");
                let refused = if self.resample_all {
                    d.resample_all_nodes(self.resample_h).err()
                } else {
                    d.resample_parts(self.resample_loop, self.resample_h).err()
                };
                let mut button = ui
                    .add_enabled(refused.is_none(), egui::Button::new("Resample"))
                    .on_hover_text("Cut every segment of the loops chosen into round(length / H) parts, keeping the corners; one part more on the longest piece when the total node count would be odd");
                if let Some(e) = &refused {
                    button = button.on_disabled_hover_text(e.to_string());
                }
                if button.clicked() {
                    if self.resample_all {
                        out.push(Command::SetSize(self.resample_h));
                    } else {
                        let mut d = d.clone();
                        if d.resample(self.resample_loop, self.resample_h).is_ok() {
                            out.push(Command::SetDraft {
                                draft: d,
                                what: "resample loop",
                            });
                        }
                    }
                }
            });
        }
        match &doc.problem {
            None => {
                ui.label(format!(
                    "{}, {}: valid",
                    super::plural(d.loops.len(), "loop"),
                    super::plural(d.node_count(), "node")
                ));
            }
            Some(crate::boundary::BoundaryError::Empty) if d.loops.is_empty() => {
                ui.label(if self.tool == Tool::Draw {
                    "Nothing drawn yet: click on the canvas to place the outer loop's nodes."
                } else {
                    "Nothing drawn yet: choose the \"draw loop\" tool above the canvas and click on the canvas."
                });
            }
            Some(e) => {
                ui.colored_label(
                    Color32::from_rgb(255, 110, 110),
                    format!("not a valid boundary yet: {e}"),
                );
                ui.label(if d.marked(e).is_empty() {
                    "Fix it with the tools above the canvas or a resample, or undo."
                } else {
                    "The nodes at fault are circled in red; fix them with the tools above, or undo."
                });
            }
        }
        out
    }
}

/// The colour a front node the element could be closed onto is ringed
/// in: by the guard's score of that element ([`grade`]), red when it is no
/// valid element.
fn target_colour(t: &Target) -> Color32 {
    check_colour(t.check.as_ref())
}

/// The colour of an element by the guard's score (`None`: no valid
/// element, red), as [`target_colour`].
fn check_colour(check: Option<&CheckedElement>) -> Color32 {
    check.map_or(Color32::from_rgb(255, 70, 70), |c| grade(c.score).1)
}

/// What an element a correction would give is worth, in two measures that
/// can disagree: the guard's score, which extraction ranks its candidates
/// by (the quad and the front it leaves), and the thesis's criteria for
/// the quad alone (§1.2: corners in [45°, 135°], aspect and taper at most
/// 10), with the first figure that misses them.
fn verdict(check: &CheckedElement) -> String {
    let q = check.quality();
    let (lo, hi) = (q.min_angle(), q.max_angle());
    let thesis = if q.meets_thesis() {
        "meets the thesis's criteria".to_owned()
    } else if hi > GOOD_ANGLE.1 {
        format!(
            "misses the thesis's criteria: a {hi:.1}° corner (over {:.0}°)",
            GOOD_ANGLE.1
        )
    } else if lo < GOOD_ANGLE.0 {
        format!(
            "misses the thesis's criteria: a {lo:.1}° corner (under {:.0}°)",
            GOOD_ANGLE.0
        )
    } else if q.aspect > GOOD_RATIO {
        format!(
            "misses the thesis's criteria: aspect {:.1} (over {GOOD_RATIO})",
            q.aspect
        )
    } else {
        format!(
            "misses the thesis's criteria: taper {:.1} (over {GOOD_RATIO})",
            q.taper
        )
    };
    format!(
        "element score {:.2}, {} (the quad and the front it leaves, as extraction ranks its elements)\ncorners {lo:.0}°–{hi:.0}°, scaled Jacobian {:.2}: {thesis}",
        check.score,
        grade(check.score).0,
        q.scaled_jacobian
    )
}

/// The word and colour of the guard's score of an element, by the
/// extraction's own thresholds: taken at once from
/// [`MeshParams::accept_score`] (good, green), made to wait below
/// [`MeshParams::defer_score`] (poor, orange), fair (amber) between.
///
/// [`MeshParams::accept_score`]: crate::extract::MeshParams::accept_score
/// [`MeshParams::defer_score`]: crate::extract::MeshParams::defer_score
fn grade(score: f64) -> (&'static str, Color32) {
    let p = crate::extract::MeshParams::DEFAULT;
    if score >= p.accept_score {
        ("good", Color32::from_rgb(90, 230, 110))
    } else if score >= p.defer_score {
        ("fair", Color32::from_rgb(240, 200, 60))
    } else {
        ("poor", Color32::from_rgb(255, 140, 40))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checked(score: f64, quad: [Point; 4]) -> CheckedElement {
        CheckedElement { score, quad }
    }

    #[test]
    fn the_verdict_keeps_the_score_and_the_thesis_criteria_apart() {
        let square = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        let v = verdict(&checked(0.95, square));
        assert!(v.starts_with("element score 0.95, good"), "{v}");
        assert!(v.contains("corners 90°–90°"), "{v}");
        assert!(v.ends_with("meets the thesis's criteria"), "{v}");
        // A quad opened to 137.5° at one corner: the guard may still call
        // it good, the thesis's criteria do not.
        let turn = (180.0f64 - 137.5).to_radians();
        let kite = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0 + turn.cos(), turn.sin()),
            Point::new(0.0, 1.0),
        ];
        let q = checked(0.9, kite).quality();
        assert!((q.max_angle() - 137.5).abs() < 1e-9 && !q.meets_thesis());
        let v = verdict(&checked(0.9, kite));
        assert!(v.starts_with("element score 0.90, good"), "{v}");
        assert!(
            v.ends_with("misses the thesis's criteria: a 137.5° corner (over 135°)"),
            "{v}"
        );
        // No valid element is red; a poor one orange.
        assert_eq!(check_colour(None), Color32::from_rgb(255, 70, 70));
        assert_eq!(check_colour(Some(&checked(0.0, square))), grade(0.0).1);
    }
}

//! The canvas tools: correcting the last element (drag Pn, or click a
//! front node to close the element onto it: the nodes that give a valid
//! element are marked), and editing the boundary (draw loops, move,
//! insert, delete, split, resample), validated live. A tool takes the
//! pointer when a drag starts on something it handles (a node, the Pn
//! handle); any other drag pans the view.
//!
//! Here: the tools' state and the pointer's input; `paint` is what they
//! draw on the canvas, `panel` the tool bar and the left panel's sections.

use super::canvas::{Pointer, View};
use super::command::Command;
use super::document::{Document, Target};
use super::MeshKind;
use crate::boundary_edit::{At, Draft};
use crate::extract::CheckedElement;
use crate::geom::Point;
use crate::model::ElementType;
use egui::Pos2;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

mod paint;
mod panel;

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
                Some(d) => d.sizes.size,
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
                Some(d) => d.sizes.size,
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

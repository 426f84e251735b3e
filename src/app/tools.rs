//! The canvas tools: correcting the last element on the canvas (drag Pn,
//! click a front node to close onto it) and editing the boundary (draw a
//! loop, move, insert and delete nodes, split a segment, resample a loop)
//! over a [`Draft`] with live validation. Edits become
//! `Command::SetBoundary` once the draft is a valid boundary; until then
//! the problem is listed and its nodes are marked.

use super::canvas::{CanvasResponse, View};
use super::command::Command;
use super::document::Document;
use crate::boundary::BoundaryError;
use crate::boundary_edit::{At, Draft};
use crate::extract::StepKind;
use crate::geom::Point;
use crate::Boundary;
use egui::{Color32, Pos2, Rect, Sense, Shape, Stroke, Ui};
use serde::{Deserialize, Serialize};

/// What a primary click or drag on the canvas does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Tool {
    /// Drag Pn of the last element, click a front node to close onto it.
    #[default]
    Correct,
    /// Click to place nodes of a new loop (a hole when there is an outer
    /// loop); click the first node to close it.
    Draw,
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
    pub const ALL: [Tool; 6] = [
        Tool::Correct,
        Tool::Draw,
        Tool::Move,
        Tool::Insert,
        Tool::Delete,
        Tool::Split,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Tool::Correct => "correct",
            Tool::Draw => "draw loop",
            Tool::Move => "move",
            Tool::Insert => "insert",
            Tool::Delete => "delete",
            Tool::Split => "split",
        }
    }
}

/// What a tool sees of the canvas this frame.
#[derive(Clone, Copy)]
pub struct OnCanvas<'a> {
    pub view: &'a View,
    pub response: &'a CanvasResponse,
    pub doc: &'a Document,
    /// The finished mesh is on the canvas (nothing left to correct).
    pub finished: bool,
}

/// Pixels within which a click picks a node or a segment.
const PICK: f32 = 10.0;

/// The boundary being edited and the tool in hand.
pub struct Tools {
    pub tool: Tool,
    pub draft: Draft,
    /// The document boundary the draft started from.
    synced: Option<Boundary>,
    /// The loop being drawn.
    pub drawing: Vec<Point>,
    dragging: Option<At>,
    /// Parts a split makes.
    pub split_parts: usize,
    /// Target segment length of a resample, and the loop.
    pub resample_h: f64,
    pub resample_loop: usize,
    /// The draft's problem, when it is not a valid boundary.
    pub problem: Option<BoundaryError>,
    /// Drafts before each edit since the draft last was the document's
    /// boundary, and drafts undone: an invalid draft is not yet in the
    /// document's history, so its edits are undone here first.
    undo: Vec<Draft>,
    redo: Vec<Draft>,
}

impl Default for Tools {
    fn default() -> Self {
        Tools {
            tool: Tool::Correct,
            draft: Draft::default(),
            synced: None,
            drawing: Vec::new(),
            dragging: None,
            split_parts: 2,
            resample_h: 0.0,
            resample_loop: 0,
            problem: None,
            undo: Vec::new(),
            redo: Vec::new(),
        }
    }
}

impl Tools {
    /// Starts the draft again from the document when the document's
    /// boundary changed (an edit applied, undo, a file opened).
    pub fn sync(&mut self, doc: &Document) {
        if self.synced.as_ref() != Some(&doc.boundary) {
            self.draft = Draft::of(&doc.boundary);
            self.synced = Some(doc.boundary.clone());
            self.problem = None;
            self.drawing.clear();
            self.dragging = None;
            self.undo.clear();
            self.redo.clear();
            if self.resample_h <= 0.0 {
                self.resample_h = doc.boundary.median_segment();
            }
        }
    }

    /// Keeps the draft before an edit, for [`Tools::undo_draft`].
    fn before_edit(&mut self) {
        self.undo.push(self.draft.clone());
        self.redo.clear();
    }

    /// Whether a draft edit is there to undo and to redo.
    pub fn draft_edits(&self) -> (bool, bool) {
        (!self.undo.is_empty(), !self.redo.is_empty())
    }

    /// Undoes the last edit of a draft that is not (yet) a valid boundary;
    /// false when there is none (the document's undo is next).
    pub fn undo_draft(&mut self) -> bool {
        self.step_draft(true)
    }

    /// Redoes a draft edit undone by [`Tools::undo_draft`].
    pub fn redo_draft(&mut self) -> bool {
        self.step_draft(false)
    }

    fn step_draft(&mut self, back: bool) -> bool {
        let (from, to) = if back {
            (&mut self.undo, &mut self.redo)
        } else {
            (&mut self.redo, &mut self.undo)
        };
        let Some(d) = from.pop() else { return false };
        to.push(std::mem::replace(&mut self.draft, d));
        self.problem = self.draft.to_boundary().err();
        self.dragging = None;
        true
    }

    /// After a change to the draft: a valid draft becomes the document's
    /// boundary; an invalid one keeps its problem for the panel.
    fn commit(&mut self, out: &mut Vec<Command>) {
        match self.draft.to_boundary() {
            Ok(b) => {
                self.problem = None;
                out.push(Command::SetBoundary(Box::new(b)));
            }
            Err(e) => self.problem = Some(e),
        }
    }

    /// Boundary nodes the current problem is about.
    pub fn marked(&self) -> Vec<Point> {
        match &self.problem {
            Some(e) => self
                .draft
                .marked(e)
                .into_iter()
                .filter_map(|(l, k)| self.draft.loops.get(l)?.get(k).copied())
                .collect(),
            None => Vec::new(),
        }
    }

    /// The boundary section of the left panel.
    pub fn panel(&mut self, ui: &mut Ui, doc: &Document, out: &mut Vec<Command>) {
        ui.heading("Canvas tool");
        ui.horizontal_wrapped(|ui| {
            for t in Tool::ALL {
                ui.selectable_value(&mut self.tool, t, t.name());
            }
        });
        match self.tool {
            Tool::Correct => {
                ui.label("Drag Pn of the last element, or click a front node to close onto it.");
            }
            Tool::Draw => {
                ui.label(format!(
                    "Click to place nodes, click the first node to close the loop ({} placed).",
                    self.drawing.len()
                ));
                if !self.drawing.is_empty() && ui.button("Drop the loop being drawn").clicked() {
                    self.drawing.clear();
                }
            }
            Tool::Split => {
                ui.horizontal(|ui| {
                    ui.label("parts");
                    ui.add(egui::DragValue::new(&mut self.split_parts).range(2..=100));
                });
            }
            _ => {}
        }
        ui.horizontal_wrapped(|ui| {
            ui.label("resample loop");
            let loops = self.draft.loops.len().max(1);
            ui.add(egui::DragValue::new(&mut self.resample_loop).range(0..=loops - 1));
            ui.label("to");
            ui.add(
                egui::DragValue::new(&mut self.resample_h)
                    .speed(0.001 * doc.boundary.bbox().size().max_element())
                    .range(1e-9..=f64::MAX),
            );
            if ui.button("Resample").clicked() {
                self.before_edit();
                self.draft.resample(self.resample_loop, self.resample_h);
                self.commit(out);
            }
        });
        match &self.problem {
            None => {
                ui.label(format!(
                    "{} loops, {} nodes: valid",
                    self.draft.loops.len(),
                    self.draft.node_count()
                ));
            }
            Some(e) => {
                ui.colored_label(
                    Color32::from_rgb(255, 110, 110),
                    format!("not a valid boundary yet: {e}"),
                );
                if ui.button("Discard the draft").clicked() {
                    self.synced = None;
                }
            }
        }
    }

    /// Handles the tool on the canvas and draws its overlay; `pn` is the
    /// correction's Pn the handle drags.
    pub fn canvas(&mut self, ui: &mut Ui, at: &OnCanvas, pn: &mut Point, out: &mut Vec<Command>) {
        let OnCanvas {
            view,
            response: c,
            doc,
            finished,
        } = *at;
        let rect = c.rect;
        let to = |p: Point| view.to_screen(rect, p);
        let r = PICK as f64 / view.zoom;
        let painter = ui.painter_at(rect);
        if self.tool == Tool::Correct {
            if !finished {
                self.correct(ui, view, c, doc, pn, out);
            }
            return;
        }
        // The draft: loops, nodes, the loop being drawn.
        let line = Color32::from_rgb(240, 240, 240);
        for l in &self.draft.loops {
            let pts: Vec<Pos2> = l.iter().map(|&p| to(p)).collect();
            painter.add(Shape::closed_line(pts.clone(), Stroke::new(1.5, line)));
            for p in pts {
                painter.circle_filled(p, 3.0, line);
            }
        }
        if !self.drawing.is_empty() {
            let mut pts: Vec<Pos2> = self.drawing.iter().map(|&p| to(p)).collect();
            if let Some(h) = c.hover {
                pts.push(to(h));
            }
            let cyan = Color32::from_rgb(80, 220, 255);
            painter.add(Shape::line(pts.clone(), Stroke::new(1.5, cyan)));
            for p in pts {
                painter.circle_filled(p, 3.0, cyan);
            }
        }
        match self.tool {
            Tool::Draw => {
                if let Some(p) = c.clicked {
                    let closes = self.drawing.len() >= 3 && self.drawing[0].distance(p) <= r;
                    if closes {
                        self.before_edit();
                        self.draft.loops.push(std::mem::take(&mut self.drawing));
                        self.commit(out);
                    } else {
                        self.drawing.push(p);
                    }
                }
            }
            Tool::Move => self.drag_node(ui, view, c, out),
            Tool::Insert => {
                if let Some(p) = c.clicked {
                    if let Some(s) = self.draft.nearest_segment(p, r) {
                        self.before_edit();
                        self.draft.insert(s, p);
                        self.commit(out);
                    }
                }
            }
            Tool::Delete => {
                if let Some(p) = c.clicked {
                    if let Some(n) = self.draft.nearest_node(p, r) {
                        self.before_edit();
                        self.draft.delete(n);
                        self.commit(out);
                    }
                }
            }
            Tool::Split => {
                if let Some(p) = c.clicked {
                    if let Some(s) = self.draft.nearest_segment(p, r) {
                        self.before_edit();
                        self.draft.split(s, self.split_parts);
                        self.commit(out);
                    }
                }
            }
            Tool::Correct => {}
        }
    }

    /// The Move tool: a handle under the pointer's node, dragged.
    fn drag_node(&mut self, ui: &mut Ui, view: &View, c: &CanvasResponse, out: &mut Vec<Command>) {
        let rect = c.rect;
        let r = PICK as f64 / view.zoom;
        let target = self
            .dragging
            .or_else(|| c.hover.and_then(|h| self.draft.nearest_node(h, r)));
        let Some(at) = target else { return };
        let Some(&p) = self.draft.loops.get(at.0).and_then(|l| l.get(at.1)) else {
            self.dragging = None;
            return;
        };
        let s = view.to_screen(rect, p);
        let id = ui.id().with("boundary_node_handle");
        let resp = ui.interact(
            Rect::from_center_size(s, egui::vec2(2.0 * PICK, 2.0 * PICK)),
            id,
            Sense::drag(),
        );
        ui.painter_at(rect).circle_stroke(
            s,
            6.0,
            Stroke::new(2.0, Color32::from_rgb(80, 220, 255)),
        );
        if resp.drag_started() {
            self.before_edit();
        }
        if resp.dragged() {
            self.dragging = Some(at);
            let d = resp.drag_delta();
            let moved = p + Point::new(d.x as f64, -d.y as f64) / view.zoom;
            self.draft.move_node(at, moved);
        }
        if resp.drag_stopped() {
            self.dragging = None;
            self.commit(out);
        }
    }

    /// The Correct tool: the handle of Pn and the candidate element.
    fn correct(
        &mut self,
        ui: &mut Ui,
        view: &View,
        c: &CanvasResponse,
        doc: &Document,
        pn: &mut Point,
        out: &mut Vec<Command>,
    ) {
        let Some(last) = doc
            .last
            .as_ref()
            .filter(|r| matches!(r.kind, StepKind::Element | StepKind::Correction))
        else {
            return;
        };
        let rect = c.rect;
        let nodes = &doc.mesher.mesh().nodes;
        let n = last.leading.len() / 2;
        let node = |k: usize| last.leading.get(k).map(|&v| nodes[v as usize]);
        let (Some(l1), Some(p0), Some(r1)) = (node(n.wrapping_sub(1)), node(n), node(n + 1)) else {
            return;
        };
        // The candidate element of type 0 with the handle's Pn, dashed.
        let to = |p: Point| view.to_screen(rect, p);
        let ring = [p0, r1, *pn, l1, p0].map(to);
        let yellow = Color32::from_rgb(255, 230, 60);
        ui.painter_at(rect).extend(Shape::dashed_line(
            &ring,
            Stroke::new(1.5, yellow),
            5.0,
            4.0,
        ));
        let s = to(*pn);
        let resp = ui.interact(
            Rect::from_center_size(s, egui::vec2(2.0 * PICK, 2.0 * PICK)),
            ui.id().with("pn_handle"),
            Sense::click_and_drag(),
        );
        ui.painter_at(rect)
            .circle_stroke(s, 7.0, Stroke::new(2.0, yellow));
        if resp.dragged() {
            let d = resp.drag_delta();
            *pn += Point::new(d.x as f64, -d.y as f64) / view.zoom;
        }
        if resp.drag_stopped() || resp.double_clicked() {
            out.push(Command::CorrectLast {
                element_type: crate::ElementType::New,
                pn: *pn,
                snap_to: None,
            });
        }
        // A click on a front node closes the element onto it.
        if let Some(p) = c.clicked {
            let r = PICK as f64 / view.zoom;
            let f = doc.mesher.front();
            let hit = f
                .live_loops()
                .flat_map(|l| f.loop_nodes(l))
                .map(|v| (v, nodes[v as usize].distance(p)))
                .filter(|&(_, d)| d <= r)
                .min_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((v, _)) = hit {
                out.push(Command::CorrectLast {
                    element_type: crate::ElementType::New,
                    pn: nodes[v as usize],
                    snap_to: Some(v),
                });
            }
        }
    }
}

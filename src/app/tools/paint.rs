//! What the tools paint on the canvas: the draft with its node numbers,
//! the Pn handle and closing targets ringed by how good the element
//! would be, and the tips that say so.

use super::{arc_nodes, loop_role, pn_handle, Hover, OnCanvas, Tool, Tools, PICK};
use crate::app::document::Target;
use crate::app::MeshKind;
use crate::boundary_edit::At;
use crate::extract::CheckedElement;
use crate::geom::Point;
use crate::model::ElementType;
use crate::quality::{GOOD_ANGLE, GOOD_RATIO};
use egui::{Color32, Pos2, Shape, Stroke, Ui};

/// Drafts of at most this many nodes show every node's number.
const NUMBERED_NODES: usize = 400;

/// Screen points between two numbered nodes, at least.
const NUMBER_ROOM: f32 = 16.0;

/// A tooltip at the pointer, opening towards the canvas's middle
/// ([`crate::app::canvas::canvas_tip`]).
fn tip(ui: &Ui, text: &str) {
    crate::app::canvas::canvas_tip(ui, ui.clip_rect(), egui::Id::new("canvas_tip"), |ui| {
        ui.label(text);
    });
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

impl Tools {
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

//! What the canvas marks over the mesh: the grid with its coordinates, the
//! last step (reference point, leading points, Pn, the element) labelled
//! without overlaps, and a drawing's curves.

use super::{View, MAX_HIGHLIGHT};
use crate::extract::{Remedy, StepKind, StepReport};
use crate::geom::Point;
use crate::mesh::QuadMesh;
use egui::{Color32, Pos2, Rect, Shape, Stroke, Vec2};

/// Grid lines at a power of ten that keeps them 40+ pixels apart, with
/// coordinates along the left and bottom edges.
pub(super) fn draw_grid(painter: &egui::Painter, rect: Rect, view: &View, color: Color32) {
    let step = 10f64.powf((40.0 / view.zoom).log10().ceil());
    let lo = view.to_world(rect, rect.left_bottom());
    let hi = view.to_world(rect, rect.right_top());
    let stroke = Stroke::new(0.5, color.gamma_multiply(0.4));
    let font = egui::FontId::monospace(10.0);
    let mut x = (lo.x / step).floor() * step;
    while x <= hi.x {
        let sx = view.to_screen(rect, Point::new(x, 0.0)).x;
        painter.line_segment(
            [Pos2::new(sx, rect.top()), Pos2::new(sx, rect.bottom())],
            stroke,
        );
        painter.text(
            Pos2::new(sx + 2.0, rect.bottom() - 2.0),
            egui::Align2::LEFT_BOTTOM,
            format!("{}", round_label(x, step)),
            font.clone(),
            color,
        );
        x += step;
    }
    let mut y = (lo.y / step).floor() * step;
    while y <= hi.y {
        let sy = view.to_screen(rect, Point::new(0.0, y)).y;
        painter.line_segment(
            [Pos2::new(rect.left(), sy), Pos2::new(rect.right(), sy)],
            stroke,
        );
        painter.text(
            Pos2::new(rect.left() + 2.0, sy - 2.0),
            egui::Align2::LEFT_BOTTOM,
            format!("{}", round_label(y, step)),
            font.clone(),
            color,
        );
        y += step;
    }
}

/// `v` rounded to the grid step's decimals (no `0.30000000000000004`, and
/// no `-0` for a line a rounding left of the axis).
pub(super) fn round_label(v: f64, step: f64) -> f64 {
    let decimals = (-step.log10()).ceil().max(0.0) as i32;
    let f = 10f64.powi(decimals);
    // (Adding 0 turns -0 into 0.)
    (v * f).round() / f + 0.0
}

/// Places labels beside points without overlaps: each label goes on the
/// side of its point away from `away` if that is free, else on the first
/// free side of eight; a label with no free side is left out.
struct Labels<'p> {
    painter: &'p egui::Painter,
    taken: Vec<Rect>,
}

impl Labels<'_> {
    /// Reserves the area of a drawn point.
    fn block(&mut self, p: Pos2, r: f32) {
        self.taken
            .push(Rect::from_center_size(p, egui::vec2(2.0 * r, 2.0 * r)));
    }

    pub(super) fn place(&mut self, p: Pos2, away: Vec2, text: &str, color: Color32) -> bool {
        let font = egui::FontId::proportional(13.0);
        let galley = self.painter.layout_no_wrap(text.to_string(), font, color);
        let size = galley.size();
        let first = if away.length() > 1e-3 {
            away.normalized()
        } else {
            egui::vec2(1.0, -1.0).normalized()
        };
        let mut dirs = vec![first];
        for k in 0..8 {
            let a = k as f32 * std::f32::consts::FRAC_PI_4;
            dirs.push(egui::vec2(a.cos(), a.sin()));
        }
        for d in dirs {
            // The label's centre, far enough along `d` for its box to
            // clear the point.
            let reach = 7.0 + 0.5 * (size.x * d.x.abs() + size.y * d.y.abs());
            let rect = Rect::from_center_size(p + d * reach, size);
            if !self.taken.iter().any(|t| t.intersects(rect)) {
                self.taken.push(rect);
                // A dark backing: the label reads over any tint of quad.
                self.painter
                    .rect_filled(rect.expand(1.5), 3.0, Color32::from_black_alpha(170));
                self.painter.galley(rect.min, galley, color);
                return true;
            }
        }
        false
    }
}

/// The screen span (points) the last step's leading points need for
/// their labels.
pub const MIN_LABELLED_STEP: f32 = 40.0;

/// The last step: its element outlined (when it is a few quads), the
/// reference point (of any step that has one), the leading points labelled
/// l1..lN and r1..rN, and the model's Pn; labels go outside the element and
/// never overlap (those that find no room are left out, the outermost
/// first).
pub(super) fn draw_step(
    painter: &egui::Painter,
    r: &StepReport,
    mesh: &QuadMesh,
    to: &dyn Fn(Point) -> Pos2,
) {
    let highlight = Color32::from_rgb(255, 230, 60);
    let small = r.quads.len() <= MAX_HIGHLIGHT && r.kind != StepKind::Fill;
    let mut centre = Vec2::ZERO;
    let mut corners = 0.0;
    if small {
        for q in &r.quads {
            let s = mesh.corners(q).map(to);
            for p in s {
                centre += p.to_vec2();
                corners += 1.0;
            }
            painter.add(Shape::closed_line(s.to_vec(), Stroke::new(2.5, highlight)));
        }
    }
    let n = r.leading.len() / 2;
    // Steps that are not the model's (a square cut, a seam, a closure)
    // have a reference point but no leading points: P0 alone is marked.
    let Some(p0) = r.leading.get(n).copied().or(r.reference) else {
        return;
    };
    let at = |v: u32| mesh.nodes.get(v as usize).map(|&p| to(p));
    let Some(s0) = at(p0) else { return };
    let centre = if corners > 0.0 {
        (centre / corners).to_pos2()
    } else {
        s0 + egui::vec2(-10.0, 10.0)
    };
    // At a zoom where the step's points lie within a few pixels (a large
    // mesh at fit view) their labels would pile into a blob: P0 is ringed
    // instead, and View ▸ Zoom to the last step (Z) shows them.
    let span = r
        .leading
        .iter()
        .filter_map(|&v| at(v))
        .fold(egui::Rect::NOTHING, |b, p| {
            b.union(egui::Rect::from_min_max(p, p))
        });
    if r.leading.len() > 1 && span.width().max(span.height()) < MIN_LABELLED_STEP {
        painter.circle_stroke(s0, 9.0, Stroke::new(2.0, Color32::from_rgb(255, 120, 120)));
        return;
    }
    let mut labels = Labels {
        painter,
        taken: Vec::new(),
    };
    // Points first, so that no label covers one.
    let p0_color = Color32::from_rgb(230, 50, 50);
    let lead_color = Color32::from_rgb(80, 170, 255);
    painter.circle_filled(s0, 6.0, p0_color);
    labels.block(s0, 6.0);
    let mut leading = Vec::new();
    for i in 1..=n {
        for (v, name) in [
            (r.leading.get(n - i), format!("l{i}")),
            (r.leading.get(n + i), format!("r{i}")),
        ] {
            if let Some(s) = v.and_then(|&v| at(v)) {
                painter.circle_filled(s, 4.0, lead_color);
                labels.block(s, 4.0);
                leading.push((s, name));
            }
        }
    }
    let pn = r.predicted_pn.map(|p| {
        let s = to(p);
        let c = match r.remedy {
            Remedy::None => Color32::from_rgb(120, 255, 120),
            // White: the model's element, its Pn drawn to the size field
            // (cyan is the next element's, blue the leading points', and the
            // element itself sits on quads coloured green by quality).
            Remedy::Rescaled => Color32::from_rgb(240, 240, 240),
            _ => Color32::from_rgb(255, 120, 255),
        };
        let d = 6.0;
        painter.line_segment(
            [s - egui::vec2(d, d), s + egui::vec2(d, d)],
            Stroke::new(2.0, c),
        );
        painter.line_segment(
            [s - egui::vec2(d, -d), s + egui::vec2(d, -d)],
            Stroke::new(2.0, c),
        );
        labels.block(s, d);
        (s, c)
    });
    labels.place(s0, s0 - centre, "P0", Color32::from_rgb(255, 120, 120));
    if let Some((s, c)) = pn {
        labels.place(s, s - s0, "Pn", c);
    }
    let label_color = Color32::from_rgb(150, 210, 255);
    for (s, name) in leading {
        labels.place(s, s - centre, &name, label_color);
    }
}

/// The colour a drawing's curves are drawn in.
pub const CURVE_COLOUR: egui::Color32 = egui::Color32::from_rgb(255, 170, 60);

/// Screen points an arc or an elliptical arc is drawn with per radian, at
/// least.
const ARC_POINTS_PER_RADIAN: f64 = 24.0;

/// Screen points a spline is drawn with.
const SPLINE_POINTS: usize = 256;

/// The curves of a drawing as they are (arcs as arcs, not as the chords
/// between the nodes cut from them), over the canvas.
pub fn draw_curves(
    painter: &egui::Painter,
    view: &View,
    rect: egui::Rect,
    g: &crate::cad::Geometry,
) {
    let stroke = egui::Stroke::new(2.0, CURVE_COLOUR);
    for c in &g.curves {
        let n = match &c.curve {
            crate::cad::Curve::Line { .. } => 1,
            crate::cad::Curve::Arc { sweep, .. } | crate::cad::Curve::Ellipse { sweep, .. } => {
                (sweep.abs() * ARC_POINTS_PER_RADIAN).ceil().max(2.0) as usize
            }
            crate::cad::Curve::Spline(_) => SPLINE_POINTS,
        };
        let pts: Vec<egui::Pos2> = (0..=n)
            .map(|k| view.to_screen(rect, c.curve.at(k as f64 / n as f64)))
            .collect();
        painter.add(egui::Shape::line(pts, stroke));
    }
}

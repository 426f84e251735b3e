//! The canvas: pan and zoom, a grid with coordinates, the domain filled
//! (spade's constrained triangulation, so concave shapes and holes draw
//! right), the mesh as one batched shape, the front, and the last step's
//! reference point, leading points, predicted Pn and element, labelled
//! without overlaps.
//!
//! Here: the view, the pointer, pan and zoom, the domain, the legend and
//! the frame's drawing; `mesh_cache` keeps the mesh's batched shapes,
//! `marks` draws the grid, the last step's marks and a drawing's curves.

use super::quality_panel::Metric;
use super::world_mesh::QuadImage;
use crate::extract::StepReport;
use crate::front::EdgeGrid;
use crate::geom::{point_in_polygon, Aabb, Point};
use crate::mesh::QuadMesh;
use crate::quality::QuadQuality;
use crate::Boundary;
use egui::epaint::Mesh;
use egui::{Color32, Pos2, Rect, Response, Shape, Stroke, Ui, Vec2};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

mod marks;
mod mesh_cache;

pub use marks::{draw_curves, CURVE_COLOUR, MIN_LABELLED_STEP};
use marks::{draw_grid, draw_step};
pub use mesh_cache::MeshCache;
use mesh_cache::{push_fan, ScreenKey};

/// The world-to-screen map: `screen = centre of the canvas + zoom · (x, −y)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// World point at the canvas centre.
    pub center: Point,
    /// Pixels per world unit.
    pub zoom: f64,
    /// Fit the boundary on the next frame.
    pub fit_pending: bool,
    /// The view is as the last fit left it (no pan or zoom since): a
    /// resized canvas fits again.
    pub fitted: bool,
    /// The canvas size of the last frame.
    size: Vec2,
    /// The world box the last fit was for (a resize fits it again, not
    /// whatever the document holds by then).
    fitted_box: Option<(Point, Point)>,
    /// The room a key drawn at the canvas's top left takes (a regions
    /// document's legend), margins included: a fit keeps the box to its
    /// right or below it, whichever leaves the box larger.
    pub key_room: Vec2,
}

impl Default for View {
    fn default() -> Self {
        View {
            center: Point::ZERO,
            zoom: 1.0,
            fit_pending: true,
            fitted: false,
            size: Vec2::ZERO,
            fitted_box: None,
            key_room: Vec2::ZERO,
        }
    }
}

impl View {
    pub fn to_screen(&self, rect: Rect, p: Point) -> Pos2 {
        let c = rect.center();
        Pos2::new(
            c.x + ((p.x - self.center.x) * self.zoom) as f32,
            c.y - ((p.y - self.center.y) * self.zoom) as f32,
        )
    }

    pub fn to_world(&self, rect: Rect, s: Pos2) -> Point {
        let c = rect.center();
        Point::new(
            self.center.x + (s.x - c.x) as f64 / self.zoom,
            self.center.y - (s.y - c.y) as f64 / self.zoom,
        )
    }

    /// Fits the box `lo..hi` into `rect` with a margin, above the strip
    /// the colour legend takes at the bottom (where the canvas is tall
    /// enough to spare it).
    /// Centres the view on the box `lo`..`hi`, zoomed so that it spans
    /// `share` of the canvas (a pan and zoom of the user's: a resize keeps
    /// it).
    pub fn zoom_to(&mut self, rect: Rect, lo: Point, hi: Point, share: f64) {
        let size = (hi - lo).max_element().max(1e-300);
        let room = f64::from(rect.width().min(rect.height())).max(1.0);
        self.center = (lo + hi) * 0.5;
        self.zoom = share * room / size;
        self.fitted = false;
        self.fit_pending = false;
    }

    pub fn fit(&mut self, rect: Rect, lo: Point, hi: Point) {
        let below = if rect.height() > 4.0 * LEGEND_ROOM {
            LEGEND_ROOM
        } else {
            0.0
        };
        let size = (hi - lo).max(Point::splat(1e-300));
        let zoom_in = |w: f32, h: f32| 0.9 * (w as f64 / size.x).min(h as f64 / size.y);
        // The key at the top left is kept clear, beside the box or above
        // it, whichever leaves the box larger; where the canvas cannot
        // spare its room either way, the key is drawn over it.
        let key = self.key_room;
        let (w, h) = (rect.width(), rect.height() - below);
        let mut shift = (0.0, 0.0);
        self.zoom = zoom_in(w, h);
        if key.x > 0.0 && key.y > 0.0 {
            let beside = zoom_in(w - key.x, h);
            let under = zoom_in(w, h - key.y);
            if w > 3.0 * key.x && beside >= under {
                self.zoom = beside;
                shift = (key.x, 0.0);
            } else if h > 3.0 * key.y {
                self.zoom = under;
                shift = (0.0, key.y);
            }
        }
        if !(self.zoom.is_finite() && self.zoom > 0.0) {
            self.zoom = 1.0;
        }
        // The box's centre drawn half the strip below the canvas above the
        // canvas's centre, half the key's room right of it or below it.
        self.center = (lo + hi) * 0.5
            - Point::new(0.5 * shift.0 as f64, 0.5 * (below - shift.1) as f64) / self.zoom;
        self.fit_pending = false;
        self.fitted = true;
        self.fitted_box = Some((lo, hi));
    }

    /// Fits `bbox` when asked to; when the canvas changed size and the
    /// user has not moved the view since the last fit, fits what that fit
    /// showed again. `key_room` gives [`View::key_room`], asked only for
    /// a fit.
    pub fn update(&mut self, rect: Rect, bbox: Option<Aabb>, key_room: impl FnOnce() -> Vec2) {
        let resized = self.size != rect.size();
        self.size = rect.size();
        if self.fit_pending || (resized && self.fitted) {
            self.key_room = key_room();
        }
        if !self.fit_pending && resized && self.fitted {
            if let Some((lo, hi)) = self.fitted_box {
                self.fit(rect, lo, hi);
                return;
            }
        }
        if self.fit_pending || (resized && self.fitted) {
            match bbox {
                Some(bb) => self.fit(rect, bb.min, bb.max),
                None => {
                    // Nothing drawn yet: a unit square in view.
                    self.fit(rect, Point::new(0.0, 0.0), Point::new(1.0, 1.0));
                }
            }
        }
    }

    /// Pans by a screen displacement.
    pub fn pan(&mut self, d: Vec2) {
        self.center -= Point::new(d.x as f64, -d.y as f64) / self.zoom;
        self.fitted = false;
    }

    /// Zooms by `factor` about the screen point `at`.
    pub fn zoom_about(&mut self, rect: Rect, at: Pos2, factor: f64) {
        let before = self.to_world(rect, at);
        self.zoom *= factor;
        let after = self.to_world(rect, at);
        self.center += before - after;
        self.fitted = false;
    }
}

/// The pointer on the canvas this frame, in screen and world coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Pointer {
    pub rect: Rect,
    /// Where the pointer is, when over the canvas (or dragging from it).
    pub pos: Option<Pos2>,
    pub world: Option<Point>,
    /// Where the press of the current drag started.
    pub press_origin: Option<Pos2>,
    /// A primary drag started, goes on, or ended this frame.
    pub drag_started: bool,
    pub dragging: bool,
    pub drag_stopped: bool,
    /// A primary click without a drag, where it was.
    pub clicked: Option<Pos2>,
    /// A secondary click (drops the loop being drawn).
    pub secondary_clicked: bool,
    /// The canvas has the pointer (nothing above it).
    pub hovered: bool,
}

impl Pointer {
    /// The pointer as the canvas response `r` saw it.
    pub fn of(r: &Response, ui: &Ui) -> Pointer {
        let primary = r.dragged_by(egui::PointerButton::Primary);
        let pos = r.hover_pos().or_else(|| {
            (r.dragged() || r.drag_stopped())
                .then(|| r.interact_pointer_pos())
                .flatten()
        });
        Pointer {
            rect: r.rect,
            pos,
            world: None,
            press_origin: ui.input(|i| i.pointer.press_origin()),
            drag_started: r.drag_started_by(egui::PointerButton::Primary),
            dragging: primary,
            drag_stopped: r.drag_stopped_by(egui::PointerButton::Primary),
            clicked: r.clicked().then(|| r.interact_pointer_pos()).flatten(),
            secondary_clicked: r.secondary_clicked(),
            hovered: r.hovered(),
        }
    }

    /// Fills in the world positions for `view`.
    pub fn in_view(mut self, view: &View) -> Pointer {
        self.world = self.pos.map(|p| view.to_world(self.rect, p));
        self
    }
}

/// Pans with a drag no tool took (any button; the middle and secondary
/// buttons always pan) and zooms with the wheel about the pointer.
pub fn pan_zoom(view: &mut View, r: &Response, ui: &Ui, primary_taken: bool) {
    let pan = r.dragged_by(egui::PointerButton::Middle)
        || r.dragged_by(egui::PointerButton::Secondary)
        || (r.dragged_by(egui::PointerButton::Primary) && !primary_taken);
    if pan {
        view.pan(r.drag_delta());
    }
    if let Some(h) = r.hover_pos() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            view.zoom_about(r.rect, h, (scroll as f64 / 200.0).exp());
        }
    }
}

/// Triangles filling the domain, in world coordinates, from spade's
/// constrained Delaunay triangulation of the boundary (kept: those whose
/// centroid is inside the outer loop and outside every hole); none where
/// spade fails on the boundary (`spade_guard.rs`).
pub fn domain_triangles(b: &Boundary) -> Vec<[Point; 3]> {
    crate::spade_guard::guarded(|| triangulate_domain(b)).unwrap_or_default()
}

fn triangulate_domain(b: &Boundary) -> Vec<[Point; 3]> {
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut handles = Vec::with_capacity(b.points.len());
    for p in &b.points {
        match cdt.insert(Point2::new(p.x, p.y)) {
            Ok(h) => handles.push(Some(h)),
            Err(_) => handles.push(None),
        }
    }
    for l in &b.loops {
        for k in 0..l.len() {
            if let (Some(a), Some(c)) = (handles[l[k]], handles[l[(k + 1) % l.len()]]) {
                if a != c && cdt.can_add_constraint(a, c) {
                    cdt.add_constraint(a, c);
                }
            }
        }
    }
    let polys: Vec<Vec<Point>> = b
        .loops
        .iter()
        .map(|l| l.iter().map(|&i| b.points[i]).collect())
        .collect();
    let inside = |p: Point| {
        polys
            .first()
            .is_some_and(|outer| point_in_polygon(p, outer))
            && polys[1..].iter().all(|h| !point_in_polygon(p, h))
    };
    cdt.inner_faces()
        .map(|f| {
            f.vertices()
                .map(|v| Point::new(v.position().x, v.position().y))
        })
        .filter(|t| inside((t[0] + t[1] + t[2]) / 3.0))
        .collect()
}

/// The domain triangles of the boundary last drawn, recomputed when the
/// boundary changes (an edit, undo, an opened file).
#[derive(Default)]
pub struct DomainCache {
    boundary: Option<Boundary>,
    triangles: Vec<[Point; 3]>,
}

impl DomainCache {
    pub fn of(&mut self, b: &Boundary) -> &[[Point; 3]] {
        if self.boundary.as_ref() != Some(b) {
            self.triangles = domain_triangles(b);
            self.boundary = Some(b.clone());
        }
        &self.triangles
    }
}

/// Colour of a scaled Jacobian, on the scale of the SVG export (red at 0,
/// yellow at 0.5, green at 1).
pub fn quality_color(sj: f64) -> Color32 {
    let [r, g, b] = crate::io::svg::quality_colour(sj);
    Color32::from_rgb(r, g, b)
}

/// Height of the strip at the canvas's bottom the colour legend takes
/// ([`legend`], whose box reaches 96 points up), in points.
const LEGEND_ROOM: f32 = 98.0;

/// The colour legend of the quads' metric: a bar from bad to ideal in the
/// canvas's lower left corner, labelled with the metric's figures.
pub fn legend(painter: &egui::Painter, rect: egui::Rect, metric: super::quality_panel::Metric) {
    const STOPS: [f64; 5] = [0.1, 0.25, 0.5, 0.75, 1.0];
    // A small canvas gets a compact legend (narrower cells, no line on
    // the tint) that leaves it most of its room.
    let compact = rect.width() < COMPACT_LEGEND_BELOW[0] || rect.height() < COMPACT_LEGEND_BELOW[1];
    let (w, h, size, top) = if compact {
        (30.0, 10.0, 10.0, 18.0)
    } else {
        (44.0, 14.0, 12.0, 38.0)
    };
    let font = egui::FontId::proportional(size);
    let text = Color32::from_rgb(230, 230, 230);
    let origin = rect.left_bottom() + egui::vec2(12.0, -(h + size + 30.0));
    let back = egui::Rect::from_min_size(
        origin - egui::vec2(6.0, top),
        egui::vec2(w * STOPS.len() as f32 + 12.0, h + size + 30.0 + top - 14.0),
    );
    painter.rect_filled(back, 4.0, Color32::from_black_alpha(170));
    if !compact {
        // The tint of the quads that miss the thesis criteria, over a good
        // quad's colour, as it shows on the canvas.
        let swatch = egui::Rect::from_min_size(origin - egui::vec2(0.0, 34.0), egui::vec2(h, h));
        painter.rect_filled(swatch, 0.0, quality_color(1.0));
        painter.rect_filled(swatch, 0.0, POOR_TINT);
        painter.text(
            swatch.right_center() + egui::vec2(6.0, 0.0),
            egui::Align2::LEFT_CENTER,
            "tinted: misses the thesis criteria",
            font.clone(),
            text,
        );
    }
    painter.text(
        origin - egui::vec2(0.0, 4.0),
        egui::Align2::LEFT_BOTTOM,
        format!("{} (colour)", metric.name()),
        font.clone(),
        text,
    );
    for (k, &score) in STOPS.iter().enumerate() {
        let cell =
            egui::Rect::from_min_size(origin + egui::vec2(w * k as f32, 0.0), egui::vec2(w, h));
        painter.rect_filled(cell, 0.0, quality_color(score));
        painter.text(
            cell.center_bottom() + egui::vec2(0.0, 3.0),
            egui::Align2::CENTER_TOP,
            metric.label_at(score),
            font.clone(),
            text,
        );
    }
}

/// The mesh's edges over its quads' fills: dark, so that they stand out on
/// the quality colours (greens, yellows, oranges) and on the plain fill in
/// either theme.
pub const MESH_EDGE: Color32 = Color32::from_black_alpha(150);

/// A canvas narrower or lower than this (points) gets the compact legend.
pub const COMPACT_LEGEND_BELOW: [f32; 2] = [600.0, 400.0];

/// What the canvas shows.
pub struct Overlay<'a> {
    /// Changes whenever the mesh shown or its figures do (the canvas
    /// caches per key).
    pub version: u64,
    pub boundary: Option<&'a Boundary>,
    pub domain: &'a [[Point; 3]],
    pub mesh: &'a QuadMesh,
    /// Figures of each quad of `mesh` (empty: not computed).
    pub qualities: &'a [QuadQuality],
    /// Front loops as node ids of `mesh`.
    pub front: &'a [Vec<u32>],
    /// The last step, drawn on `mesh` (the mesh as stepped).
    pub last: Option<&'a StepReport>,
    /// Colour quads by this metric (plain when `None`).
    pub metric: Option<Metric>,
}

/// The tint of quads that miss the thesis criteria.
const POOR_TINT: Color32 = Color32::from_rgba_unmultiplied_const(200, 60, 220, 90);

/// Steps whose element is drawn highlighted: those that make a few quads
/// (a fill or a rip-up can make the whole mesh at once).
const MAX_HIGHLIGHT: usize = 12;

/// Draws the canvas: background and grid, domain, mesh, front, last step.
/// Returns the quad under the pointer.
pub fn draw(
    ui: &Ui,
    painter: &egui::Painter,
    view: &View,
    cache: &mut MeshCache,
    o: &Overlay,
    pointer: &Pointer,
) -> Option<usize> {
    let rect = painter.clip_rect();
    painter.rect_filled(rect, 0.0, ui.visuals().extreme_bg_color);
    draw_grid(painter, rect, view, ui.visuals().weak_text_color());
    let to = |p: Point| view.to_screen(rect, p);

    // Domain.
    let mut fill = Mesh::default();
    let domain_color = Color32::from_rgba_unmultiplied(90, 120, 170, 60);
    for t in o.domain {
        push_fan(&mut fill, &t.map(to), domain_color);
    }
    painter.add(Shape::mesh(fill));

    // Quads, their edges, the boundary and the front: built in world
    // coordinates once per mesh and colouring, mapped to the screen when
    // the view changes.
    cache.refresh(o);
    let show_edges = cache.mean_edge * view.zoom >= 3.0;
    // The quads' fills as one image instead of their triangles, unless
    // the image would be too large (zoomed in far, where few quads are
    // on the canvas).
    let as_image = {
        let MeshCache {
            generation,
            bounds,
            colors,
            poor,
            image,
            ..
        } = &mut *cache;
        let m = o.mesh;
        bounds.is_some_and(|b| {
            let fills = m.quads.iter().zip(colors.iter());
            let tints = poor.iter().filter_map(|&k| m.quads.get(k as usize));
            QuadImage::draw(
                image,
                *generation,
                b,
                || {
                    fills
                        .map(|(q, &c)| (m.corners(q), c, false))
                        .chain(tints.map(|q| (m.corners(q), POOR_TINT, true)))
                },
                painter,
                view,
                rect,
            )
        })
    };
    if !as_image {
        cache.fills(o.mesh).0.draw(painter, view, rect);
    }
    // Quads that miss the thesis criteria: tinted, and outlined dashed
    // when edges are drawn.
    if show_edges {
        let key = ScreenKey {
            mesh: cache.key,
            center: view.center,
            zoom: view.zoom,
            rect,
        };
        if cache.dashes_key != Some(key) {
            cache.dashes = poor_outlines(&cache.poor, o.mesh, view, rect);
            cache.dashes_key = Some(key);
        }
        painter.extend(cache.dashes.iter().cloned());
    }
    if !as_image {
        cache.fills(o.mesh).1.draw(painter, view, rect);
    }
    if show_edges {
        cache
            .edge_lines(o.mesh, MESH_EDGE)
            .draw(painter, view, rect);
    }
    cache.lines.draw(painter, view, rect);

    if let Some(r) = o.last {
        draw_step(painter, r, o.mesh, &to);
    }
    let hovered_quad = pointer
        .world
        .filter(|_| pointer.hovered)
        .and_then(|p| cache.index.quad_at(o.mesh, p));
    if let Some(k) = hovered_quad {
        let s = o.mesh.corners(&o.mesh.quads[k]).map(to);
        painter.add(Shape::closed_line(
            s.to_vec(),
            Stroke::new(2.0, Color32::WHITE),
        ));
    }
    hovered_quad
}

/// The outlines of the quads `poor` of `mesh` that reach the canvas,
/// dashed.
fn poor_outlines(poor: &[u32], mesh: &QuadMesh, view: &View, rect: Rect) -> Vec<Shape> {
    let mut dashed = Vec::new();
    for &k in poor {
        let s = mesh
            .corners(&mesh.quads[k as usize])
            .map(|p| view.to_screen(rect, p));
        if rect.intersects(Rect::from_points(&s)) {
            let mut ring = s.to_vec();
            ring.push(s[0]);
            dashed.extend(Shape::dashed_line(
                &ring,
                Stroke::new(1.5, Color32::from_rgb(230, 90, 255)),
                4.0,
                3.0,
            ));
        }
    }
    dashed
}

/// The quad tooltip while hovering quad `k` of the mesh on the canvas `r`.
pub fn quad_hover(ui: &Ui, r: &Response, k: usize, qualities: &[QuadQuality]) {
    if let Some(q) = qualities.get(k) {
        if r.hovered() {
            canvas_tip(ui, r.rect, r.id, |ui| quad_tooltip(ui, k, q));
        }
    }
}

/// A tooltip at the pointer on the canvas `rect` that opens towards the
/// canvas's middle, so it stays over the canvas (egui opens a tooltip
/// towards the window's free side, which near the canvas's right edge is
/// over the right panel, whose figures it would hide). `id` names the
/// widget the tip belongs to.
pub fn canvas_tip<R>(ui: &Ui, rect: Rect, id: egui::Id, content: impl FnOnce(&mut Ui) -> R) {
    use egui::RectAlign;
    /// Below right, below left, above right, above left of the pointer:
    /// each with the others, nearest first, where it does not fit.
    const ALIGNS: [[RectAlign; 4]; 4] = [
        [
            RectAlign::BOTTOM_START,
            RectAlign::TOP_START,
            RectAlign::BOTTOM_END,
            RectAlign::TOP_END,
        ],
        [
            RectAlign::BOTTOM_END,
            RectAlign::TOP_END,
            RectAlign::BOTTOM_START,
            RectAlign::TOP_START,
        ],
        [
            RectAlign::TOP_START,
            RectAlign::BOTTOM_START,
            RectAlign::TOP_END,
            RectAlign::BOTTOM_END,
        ],
        [
            RectAlign::TOP_END,
            RectAlign::BOTTOM_END,
            RectAlign::TOP_START,
            RectAlign::BOTTOM_START,
        ],
    ];
    let Some(p) = ui.ctx().pointer_hover_pos() else {
        return;
    };
    let side = usize::from(p.x > rect.center().x) + 2 * usize::from(p.y > rect.center().y);
    let mut tip = egui::Tooltip::always_open(
        ui.ctx().clone(),
        ui.layer_id(),
        id,
        egui::PopupAnchor::Pointer,
    )
    .gap(12.0);
    tip.popup = tip
        .popup
        .align(ALIGNS[side][0])
        .align_alternatives(&ALIGNS[side][1..]);
    tip.show(content);
}

/// The quads of a mesh filed in a uniform grid by their bounding boxes, to
/// find the quad under the pointer without a scan of the whole mesh.
#[derive(Default)]
pub struct QuadIndex {
    grid: Option<EdgeGrid>,
}

impl QuadIndex {
    /// Cells about two mean quads wide, at most four per quad.
    pub fn of(mesh: &QuadMesh) -> QuadIndex {
        let Some(bb) = Aabb::of(mesh.quads.iter().flatten().map(|&v| mesh.nodes[v as usize]))
        else {
            return QuadIndex::default();
        };
        let n = mesh.quads.len();
        let size = bb.size();
        let cell = 2.0 * (size.x * size.y / n as f64).sqrt();
        let mut grid = EdgeGrid::new(bb, cell, 4 * n + 16);
        for (k, q) in mesh.quads.iter().enumerate() {
            if let Some(b) = Aabb::of(mesh.corners(q)) {
                grid.insert_box(k as u32, b.min, b.max);
            }
        }
        QuadIndex { grid: Some(grid) }
    }

    /// The quad of `mesh` (the mesh indexed) that holds `p`.
    pub fn quad_at(&self, mesh: &QuadMesh, p: Point) -> Option<usize> {
        let grid = self.grid.as_ref()?;
        let mut near = Vec::new();
        grid.query(p, p, &mut near);
        near.into_iter().map(|k| k as usize).find(|&k| {
            mesh.quads
                .get(k)
                .is_some_and(|q| point_in_polygon(p, &mesh.corners(q)))
        })
    }
}

/// The figures of one quad, shown while hovering it.
fn quad_tooltip(ui: &mut Ui, k: usize, q: &QuadQuality) {
    egui::Grid::new("quad_tip").num_columns(2).show(ui, |ui| {
        ui.label("quad");
        ui.label(k.to_string());
        ui.end_row();
        for (name, v) in [
            ("scaled Jacobian", q.scaled_jacobian),
            ("min angle", q.min_angle()),
            ("max angle", q.max_angle()),
            ("aspect", q.aspect),
            ("taper", q.taper),
        ] {
            ui.label(name);
            ui.monospace(format!("{v:.3}"));
            ui.end_row();
        }
        ui.label("thesis criteria");
        ui.label(if q.meets_thesis() { "met" } else { "missed" });
        ui.end_row();
    });
}

#[cfg(test)]
mod tests {
    use super::marks::round_label;
    use super::*;

    #[test]
    fn grid_labels_are_rounded_to_the_step_and_never_minus_zero() {
        assert_eq!(format!("{}", round_label(0.1 + 0.2, 0.1)), "0.3");
        assert_eq!(format!("{}", round_label(-1e-17, 0.5)), "0");
        assert_eq!(format!("{}", round_label(-0.04, 0.1)), "0");
        assert_eq!(format!("{}", round_label(-2.0, 1.0)), "-2");
    }

    #[test]
    fn the_quad_index_finds_what_a_scan_finds() {
        let b = crate::io::poly::parse_poly(super::super::assets::example("annulus.poly").unwrap())
            .unwrap();
        let model = std::sync::Arc::new(crate::model::RulesModel::DEFAULT);
        let (mesh, _) = crate::mesh_boundary(&b, model, &crate::Params::DEFAULT, |_| {}).unwrap();
        let index = QuadIndex::of(&mesh);
        let bb = b.bbox();
        let mut hits = 0;
        for i in 0..60 {
            for j in 0..60 {
                let p = bb.min
                    + Point::new(
                        (i as f64 + 0.37) / 60.0 * bb.size().x,
                        (j as f64 + 0.61) / 60.0 * bb.size().y,
                    );
                let scan = mesh
                    .quads
                    .iter()
                    .position(|q| point_in_polygon(p, &mesh.corners(q)));
                let found = index.quad_at(&mesh, p);
                assert_eq!(found.is_some(), scan.is_some(), "{p:?}");
                if let Some(k) = found {
                    assert!(point_in_polygon(p, &mesh.corners(&mesh.quads[k])));
                    hits += 1;
                }
            }
        }
        assert!(hits > 1000, "{hits}");
        assert_eq!(QuadIndex::default().quad_at(&mesh, bb.min), None);
    }
}

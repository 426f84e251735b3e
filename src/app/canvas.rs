//! The canvas: pan and zoom, a grid with coordinates, the domain filled
//! (spade's constrained triangulation, so concave shapes and holes draw
//! right), the mesh as one batched shape, the front, and the last step's
//! reference point, leading points, predicted Pn and element, labelled
//! without overlaps.

use super::quality_panel::Metric;
use super::world_mesh::{QuadImage, WorldMesh, WorldMeshBuilder};
use crate::extract::{Remedy, StepKind, StepReport};
use crate::front::EdgeGrid;
use crate::geom::{point_in_polygon, Aabb, Point};
use crate::mesh::QuadMesh;
use crate::quality::QuadQuality;
use crate::Boundary;
use egui::epaint::Mesh;
use egui::{Color32, Pos2, Rect, Response, Shape, Stroke, Ui, Vec2};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

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
        self.zoom =
            0.9 * (rect.width() as f64 / size.x).min((rect.height() - below) as f64 / size.y);
        if !(self.zoom.is_finite() && self.zoom > 0.0) {
            self.zoom = 1.0;
        }
        // The box's centre drawn half the strip above the canvas's.
        self.center = (lo + hi) * 0.5 - Point::new(0.0, 0.5 * below as f64 / self.zoom);
        self.fit_pending = false;
        self.fitted = true;
        self.fitted_box = Some((lo, hi));
    }

    /// Fits `bbox` when asked to; when the canvas changed size and the
    /// user has not moved the view since the last fit, fits what that fit
    /// showed again.
    pub fn update(&mut self, rect: Rect, bbox: Option<Aabb>) {
        let resized = self.size != rect.size();
        self.size = rect.size();
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

/// A canvas narrower or lower than this (points) gets the compact legend.
pub const COMPACT_LEGEND_BELOW: [f32; 2] = [600.0, 400.0];

/// Adds a convex polygon as a triangle fan.
fn push_fan(mesh: &mut Mesh, pts: &[Pos2], color: Color32) {
    let base = mesh.vertices.len() as u32;
    for &p in pts {
        mesh.colored_vertex(p, color);
    }
    for k in 1..pts.len().saturating_sub(1) as u32 {
        mesh.add_triangle(base, base + k, base + k + 1);
    }
}

/// What the canvas keeps between frames for one mesh: each quad's colour,
/// each edge once, and the mesh, the boundary and the front as triangles
/// in world coordinates that each frame maps to the screen (a pan or zoom
/// moves vertices; nothing is built again). Rebuilt when the mesh or the
/// colouring changes.
#[derive(Default)]
pub struct MeshCache {
    key: Option<(u64, usize, Option<Metric>)>,
    edges: Vec<[u32; 2]>,
    /// Quads that miss the thesis criteria.
    poor: Vec<u32>,
    /// Mean edge length in world units.
    mean_edge: f64,
    /// The quads by place, for hovering.
    pub index: QuadIndex,
    /// Bumped whenever the key changes.
    generation: u64,
    /// The box of the mesh's nodes.
    bounds: Option<Aabb>,
    /// Each quad's colour.
    colors: Vec<Color32>,
    /// The quads filled in their colours, and those that miss the thesis
    /// criteria tinted (built when first drawn).
    fills: Option<(WorldMesh, WorldMesh)>,
    /// The fills as an image.
    image: Option<QuadImage>,
    /// The edges in this colour (built when first drawn).
    edge_lines: Option<(Color32, WorldMesh)>,
    /// The boundary and the front.
    lines: WorldMesh,
    /// What [`MeshCache::dashes`] was built for.
    dashes_key: Option<ScreenKey>,
    /// The outlines of the quads that miss the thesis criteria, dashed in
    /// screen space (the dashes are pixels long).
    dashes: Vec<Shape>,
}

/// What the screen-space dashes depend on.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ScreenKey {
    mesh: Option<(u64, usize, Option<Metric>)>,
    center: Point,
    zoom: f64,
    rect: Rect,
}

impl MeshCache {
    fn refresh(&mut self, o: &Overlay) {
        let key = (o.version, o.mesh.quads.len(), o.metric);
        if self.key == Some(key) {
            return;
        }
        self.key = Some(key);
        self.generation += 1;
        let m = o.mesh;
        self.poor = (0..o.qualities.len() as u32)
            .filter(|&k| !o.qualities[k as usize].meets_thesis())
            .collect();
        let mut edges: Vec<[u32; 2]> = m
            .quads
            .iter()
            .flat_map(|q| {
                (0..4).map(move |k| {
                    let (a, b) = (q[k], q[(k + 1) % 4]);
                    [a.min(b), a.max(b)]
                })
            })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let total: f64 = edges
            .iter()
            .map(|e| (m.nodes[e[0] as usize] - m.nodes[e[1] as usize]).length())
            .sum();
        self.mean_edge = if edges.is_empty() {
            f64::INFINITY
        } else {
            total / edges.len() as f64
        };
        self.edges = edges;
        self.index = QuadIndex::of(m);
        self.bounds = Aabb::of(m.nodes.iter().copied());
        let plain = Color32::from_rgb(70, 110, 90);
        self.colors = (0..m.quads.len())
            .map(|k| {
                let c = match (o.metric, o.qualities.get(k)) {
                    (Some(metric), Some(q)) => quality_color(metric.score(q)),
                    _ => plain,
                };
                c.gamma_multiply(0.8)
            })
            .collect();
        self.fills = None;
        self.edge_lines = None;
        // Boundary and front.
        let loops = o.boundary.map_or(0, |b| b.points.len());
        let front = o.front.iter().map(Vec::len).sum::<usize>();
        let mut lines = WorldMeshBuilder::new(self.world_box(), loops + front);
        if let Some(b) = o.boundary {
            for l in &b.loops {
                for k in 0..l.len() {
                    let (a, c) = (b.points[l[k]], b.points[l[(k + 1) % l.len()]]);
                    lines.segment(a, c, 1.5, Color32::from_gray(200));
                }
            }
        }
        let front_color = Color32::from_rgb(255, 150, 40);
        for l in o.front {
            for k in 0..l.len() {
                let (a, c) = (l[k] as usize, l[(k + 1) % l.len()] as usize);
                if let (Some(&a), Some(&c)) = (m.nodes.get(a), m.nodes.get(c)) {
                    lines.segment(a, c, 3.0, front_color);
                }
            }
        }
        self.lines = lines.build();
        self.dashes_key = None;
    }

    /// The box the chunks are filed in: the mesh's nodes (what lies
    /// outside goes to the edge chunks).
    fn world_box(&self) -> Aabb {
        self.bounds.unwrap_or(Aabb {
            min: Point::ZERO,
            max: Point::ZERO,
        })
    }

    /// The quads' fills and the tint, as triangles in world coordinates.
    fn fills(&mut self, mesh: &QuadMesh) -> &mut (WorldMesh, WorldMesh) {
        if self.fills.is_none() {
            let bounds = self.world_box();
            let mut quads = WorldMeshBuilder::new(bounds, mesh.quads.len());
            for (q, &c) in mesh.quads.iter().zip(&self.colors) {
                quads.fan(&mesh.corners(q), c);
            }
            let mut tint = WorldMeshBuilder::new(bounds, self.poor.len());
            for q in self.poor.iter().filter_map(|&k| mesh.quads.get(k as usize)) {
                tint.fan(&mesh.corners(q), POOR_TINT);
            }
            self.fills = Some((quads.build(), tint.build()));
        }
        self.fills.get_or_insert_with(Default::default)
    }

    /// The edges in `color`, as triangles in world coordinates.
    fn edge_lines(&mut self, mesh: &QuadMesh, color: Color32) -> &mut WorldMesh {
        if self.edge_lines.as_ref().is_none_or(|(c, _)| *c != color) {
            let mut b = WorldMeshBuilder::new(self.world_box(), self.edges.len());
            for e in &self.edges {
                if let (Some(&p), Some(&q)) =
                    (mesh.nodes.get(e[0] as usize), mesh.nodes.get(e[1] as usize))
                {
                    b.segment(p, q, 1.0, color);
                }
            }
            self.edge_lines = Some((color, b.build()));
        }
        &mut self
            .edge_lines
            .get_or_insert_with(|| (color, WorldMesh::default()))
            .1
    }
}

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
        let color = ui.visuals().text_color().gamma_multiply(0.7);
        cache.edge_lines(o.mesh, color).draw(painter, view, rect);
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

/// Grid lines at a power of ten that keeps them 40+ pixels apart, with
/// coordinates along the left and bottom edges.
fn draw_grid(painter: &egui::Painter, rect: Rect, view: &View, color: Color32) {
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
fn round_label(v: f64, step: f64) -> f64 {
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

    fn place(&mut self, p: Pos2, away: Vec2, text: &str, color: Color32) -> bool {
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
fn draw_step(painter: &egui::Painter, r: &StepReport, mesh: &QuadMesh, to: &dyn Fn(Point) -> Pos2) {
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

#[cfg(test)]
mod tests {
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

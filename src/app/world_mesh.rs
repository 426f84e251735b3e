//! Triangles kept in world coordinates and mapped to the screen for the
//! view of each frame, so that a pan or a zoom over a large mesh moves
//! vertices instead of building shapes again.
//!
//! Each vertex is a world point and an offset in pixels (half a line's
//! width across it: lines keep their width at any zoom). The triangles are
//! filed in spatial chunks: a chunk off the canvas is neither mapped nor
//! drawn, and a chunk on it is mapped again only when the view changed.
//! Colours and triangles are fixed when the mesh is built; a frame writes
//! positions into the chunk's epaint mesh in place (into a second buffer
//! while the renderer still holds the first), so it allocates nothing.

use super::canvas::View;
use crate::geom::{Aabb, Point};
use egui::epaint::{Mesh, Vertex, WHITE_UV};
use egui::{Color32, Pos2, Rect, Shape, Vec2};
use std::sync::Arc;

/// Items (fans or segments) per chunk, about: the chunk grid has
/// `ceil(sqrt(items / CHUNK_ITEMS))` cells a side.
const CHUNK_ITEMS: usize = 4096;

/// At most this many chunks a side.
const MAX_CHUNKS_SIDE: usize = 16;

/// The view a chunk's screen positions are for.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ViewKey {
    center: Point,
    zoom: f64,
    rect: Rect,
}

/// One spatial chunk of a [`WorldMesh`].
struct Chunk {
    /// Each vertex's world point.
    world: Vec<Point>,
    /// Each vertex's offset in pixels (empty: none).
    offset: Vec<Vec2>,
    /// The box of `world`.
    bounds: Aabb,
    /// The largest offset's length.
    reach: f32,
    /// Colours, triangles, and positions for `view`.
    mesh: Arc<Mesh>,
    /// The other buffer (the one the renderer held last).
    spare: Option<Arc<Mesh>>,
    view: Option<ViewKey>,
}

impl Chunk {
    /// The chunk's mesh, writable: the current buffer when nothing else
    /// holds it, else the spare when nothing holds that, else a copy.
    fn writable(&mut self) -> &mut Mesh {
        if Arc::get_mut(&mut self.mesh).is_none() {
            let free = self
                .spare
                .take()
                .filter(|s| Arc::strong_count(s) == 1 && Arc::weak_count(s) == 0);
            let next = free.unwrap_or_else(|| Arc::new((*self.mesh).clone()));
            self.spare = Some(std::mem::replace(&mut self.mesh, next));
        }
        Arc::make_mut(&mut self.mesh)
    }

    /// Writes the screen positions for `view` on `rect`.
    fn map(&mut self, view: &View, rect: Rect) {
        let key = ViewKey {
            center: view.center,
            zoom: view.zoom,
            rect,
        };
        if self.view == Some(key) {
            return;
        }
        let world = std::mem::take(&mut self.world);
        let offset = std::mem::take(&mut self.offset);
        let mesh = self.writable();
        if offset.is_empty() {
            for (v, &p) in mesh.vertices.iter_mut().zip(&world) {
                v.pos = view.to_screen(rect, p);
            }
        } else {
            for ((v, &p), &d) in mesh.vertices.iter_mut().zip(&world).zip(&offset) {
                v.pos = view.to_screen(rect, p) + d;
            }
        }
        self.world = world;
        self.offset = offset;
        self.view = Some(key);
    }

    /// The chunk's box on the screen for `view` (lines' widths included).
    fn screen_rect(&self, view: &View, rect: Rect) -> Rect {
        Rect::from_two_pos(
            view.to_screen(rect, self.bounds.min),
            view.to_screen(rect, self.bounds.max),
        )
        .expand(self.reach)
    }
}

/// Triangles in world coordinates, in spatial chunks (see the module).
#[derive(Default)]
pub struct WorldMesh {
    chunks: Vec<Chunk>,
}

impl WorldMesh {
    /// Draws the chunks that reach the canvas, mapped for `view`.
    pub fn draw(&mut self, painter: &egui::Painter, view: &View, rect: Rect) {
        for c in &mut self.chunks {
            if c.screen_rect(view, rect).intersects(rect) {
                c.map(view, rect);
                painter.add(Shape::Mesh(c.mesh.clone()));
            }
        }
    }

    /// Vertices over all chunks.
    pub fn vertex_count(&self) -> usize {
        self.chunks.iter().map(|c| c.world.len()).sum()
    }
}

/// One chunk being built.
#[derive(Default)]
struct ChunkBuilder {
    world: Vec<Point>,
    offset: Vec<Vec2>,
    mesh: Mesh,
}

impl ChunkBuilder {
    fn vertex(&mut self, p: Point, d: Vec2, color: Color32) {
        self.world.push(p);
        self.offset.push(d);
        self.mesh.vertices.push(Vertex {
            pos: Pos2::ZERO,
            uv: WHITE_UV,
            color,
        });
    }
}

/// Builds a [`WorldMesh`] of items filed by where they are.
pub struct WorldMeshBuilder {
    bounds: Aabb,
    side: usize,
    chunks: Vec<ChunkBuilder>,
}

impl WorldMeshBuilder {
    /// A builder for about `items` items inside `bounds` (items outside go
    /// to the nearest chunk).
    pub fn new(bounds: Aabb, items: usize) -> WorldMeshBuilder {
        let side =
            ((items as f64 / CHUNK_ITEMS as f64).sqrt().ceil() as usize).clamp(1, MAX_CHUNKS_SIDE);
        WorldMeshBuilder {
            bounds,
            side,
            chunks: (0..side * side).map(|_| ChunkBuilder::default()).collect(),
        }
    }

    /// The chunk of an item at `p`.
    fn chunk(&mut self, p: Point) -> &mut ChunkBuilder {
        let size = self.bounds.size();
        let cell = |v: f64, lo: f64, len: f64| {
            let t = if len > 0.0 { (v - lo) / len } else { 0.0 };
            // NaN and out-of-box values land in the edge cells.
            ((t * self.side as f64).max(0.0) as usize).min(self.side - 1)
        };
        let (i, j) = (
            cell(p.x, self.bounds.min.x, size.x),
            cell(p.y, self.bounds.min.y, size.y),
        );
        &mut self.chunks[j * self.side + i]
    }

    /// A convex polygon, as a triangle fan.
    pub fn fan(&mut self, pts: &[Point], color: Color32) {
        if pts.len() < 3 {
            return;
        }
        let centre = pts.iter().copied().sum::<Point>() / pts.len() as f64;
        let c = self.chunk(centre);
        let base = c.world.len() as u32;
        for &p in pts {
            c.vertex(p, Vec2::ZERO, color);
        }
        for k in 1..pts.len() as u32 - 1 {
            c.mesh.add_triangle(base, base + k, base + k + 1);
        }
    }

    /// The segment `a–b` as a band `width` pixels wide at any zoom.
    pub fn segment(&mut self, a: Point, b: Point, width: f32, color: Color32) {
        let d = b - a;
        let len = d.length();
        if !(len > 0.0 && len.is_finite()) {
            return;
        }
        // Across the segment on the screen (y points down there): the
        // world direction (dx, dy) shows as (dx, −dy), whose normal is
        // (dy, dx).
        let n = egui::vec2(d.y as f32, d.x as f32) * (0.5 * width / len as f32);
        let c = self.chunk((a + b) * 0.5);
        let base = c.world.len() as u32;
        for (p, o) in [(a, n), (b, n), (b, -n), (a, -n)] {
            c.vertex(p, o, color);
        }
        c.mesh.add_triangle(base, base + 1, base + 2);
        c.mesh.add_triangle(base, base + 2, base + 3);
    }

    pub fn build(self) -> WorldMesh {
        let chunks = self
            .chunks
            .into_iter()
            .filter_map(|c| {
                let bounds = Aabb::of(c.world.iter().copied())?;
                let reach = c.offset.iter().map(|d| d.length()).fold(0.0, f32::max);
                let offset = if reach > 0.0 { c.offset } else { Vec::new() };
                Some(Chunk {
                    world: c.world,
                    offset,
                    bounds,
                    reach,
                    mesh: Arc::new(c.mesh),
                    spare: None,
                    view: None,
                })
            })
            .collect();
        WorldMesh { chunks }
    }
}

/// The largest image side the level of detail uses (a larger one would
/// cost more to draw into than the triangles cost to draw).
const MAX_IMAGE_SIDE: usize = 2048;

/// Filled quads drawn into an image at about the screen's resolution:
/// one textured rectangle stands for hundreds of thousands of triangles
/// (their fills; edges are drawn as lines over it). Drawn again when the zoom passes a half-stop of pixel
/// density (the image has 1 to 1.41 of its pixels per screen pixel).
pub struct QuadImage {
    /// What the image was drawn from (the caller's key) and its level.
    key: (u64, i32),
    texture: egui::TextureHandle,
    /// The world point at the image's top left corner.
    origin: Point,
    /// Image pixels per world unit.
    density: f64,
    size: [usize; 2],
}

/// The half-stop level of pixel density for `pixels` pixels per world
/// unit, and its density.
fn level_of(pixels: f64) -> (i32, f64) {
    let level = (2.0 * pixels.log2()).ceil().clamp(-2000.0, 2000.0) as i32;
    (level, 2f64.powf(level as f64 / 2.0))
}

impl QuadImage {
    /// Draws the polygons of `polys` (each in its colour; one marked
    /// `over` is blended over what is there, else it replaces it) as an
    /// image at this view's resolution, drawn again when the view's level
    /// or `key` changes. False when the image would be too large (the
    /// caller draws triangles instead).
    pub fn draw<I>(
        slot: &mut Option<QuadImage>,
        key: u64,
        bounds: Aabb,
        polys: impl FnOnce() -> I,
        painter: &egui::Painter,
        view: &View,
        rect: Rect,
    ) -> bool
    where
        I: Iterator<Item = ([Point; 4], Color32, bool)>,
    {
        let ctx = painter.ctx();
        let ppp = ctx.pixels_per_point() as f64;
        let (level, density) = level_of(view.zoom * ppp);
        let size = bounds.size() * density;
        let max_side = ctx.input(|i| i.max_texture_side).min(MAX_IMAGE_SIDE) as f64;
        if !(size.x.is_finite() && size.y.is_finite())
            || size.x + 2.0 > max_side
            || size.y + 2.0 > max_side
        {
            return false;
        }
        let size = [size.x.ceil() as usize + 1, size.y.ceil() as usize + 1];
        let origin = Point::new(bounds.min.x, bounds.max.y);
        if slot.as_ref().is_none_or(|i| i.key != (key, level)) {
            let mut pixels = vec![Color32::TRANSPARENT; size[0] * size[1]];
            let to = |p: Point| ((p.x - origin.x) * density, (origin.y - p.y) * density);
            for (poly, color, over) in polys() {
                fill_convex(&mut pixels, size, &poly, to, color, over);
            }
            let image = egui::ColorImage::new(size, pixels);
            let options = egui::TextureOptions::LINEAR;
            match slot {
                Some(i) => {
                    i.texture.set(image, options);
                    i.key = (key, level);
                    i.origin = origin;
                    i.density = density;
                    i.size = size;
                }
                None => {
                    *slot = Some(QuadImage {
                        key: (key, level),
                        texture: ctx.load_texture("quadex-mesh-image", image, options),
                        origin,
                        density,
                        size,
                    })
                }
            }
        }
        let Some(i) = slot.as_ref() else {
            return false;
        };
        let far = i.origin + Point::new(i.size[0] as f64, -(i.size[1] as f64)) / i.density;
        let screen = Rect::from_two_pos(view.to_screen(rect, i.origin), view.to_screen(rect, far));
        let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
        painter.image(i.texture.id(), screen, uv, Color32::WHITE);
        true
    }
}

/// Fills the convex polygon `poly` (either orientation, at most 8
/// corners) into the image
/// `pixels` of `size`, `to` mapping a point to image coordinates: each
/// pixel whose centre is inside takes `color` (blended over it when
/// `over`).
fn fill_convex(
    pixels: &mut [Color32],
    size: [usize; 2],
    poly: &[Point],
    to: impl Fn(Point) -> (f64, f64),
    color: Color32,
    over: bool,
) {
    let n = poly.len();
    if !(3..=8).contains(&n) {
        return;
    }
    let mut p = [(0.0, 0.0); 8];
    for (k, &q) in poly.iter().enumerate() {
        p[k] = to(q);
    }
    let p = &p[..n];
    let area: f64 = (0..n)
        .map(|k| {
            let (a, b) = (p[k], p[(k + 1) % n]);
            a.0 * b.1 - a.1 * b.0
        })
        .sum();
    if !(area.is_finite() && area != 0.0) {
        return;
    }
    let sign = area.signum();
    let (mut lo, mut hi) = (
        (f64::INFINITY, f64::INFINITY),
        (f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for &(x, y) in p {
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    // Pixels whose centres (i + 0.5, j + 0.5) lie in the box.
    let first = |v: f64| (v - 0.5).ceil().max(0.0);
    let last = |v: f64, len: usize| (v - 0.5).floor().min(len as f64 - 1.0);
    let (i0, i1) = (first(lo.0), last(hi.0, size[0]));
    let (j0, j1) = (first(lo.1), last(hi.1, size[1]));
    if !(i0 <= i1 && j0 <= j1) {
        return;
    }
    for j in j0 as usize..=j1 as usize {
        let y = j as f64 + 0.5;
        for i in i0 as usize..=i1 as usize {
            let x = i as f64 + 0.5;
            let inside = (0..n).all(|k| {
                let (a, b) = (p[k], p[(k + 1) % n]);
                sign * ((b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)) >= 0.0
            });
            if inside {
                let px = &mut pixels[j * size[0] + i];
                *px = if over { px.blend(color) } else { color };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The positions a chunk writes are those of mapping each point
    /// (plus its offset) with the view, after any pan or zoom.
    #[test]
    fn chunks_map_like_the_view() {
        let bounds = Aabb {
            min: Point::new(0.0, 0.0),
            max: Point::new(100.0, 100.0),
        };
        let mut b = WorldMeshBuilder::new(bounds, 40_000);
        let mut fans = Vec::new();
        for i in 0..200 {
            for j in 0..200 {
                let p = Point::new(i as f64 * 0.5, j as f64 * 0.5);
                let q = [
                    p,
                    p + Point::X * 0.5,
                    p + Point::splat(0.5),
                    p + Point::Y * 0.5,
                ];
                b.fan(&q, Color32::RED);
                fans.push(q);
            }
        }
        b.segment(Point::ZERO, Point::new(3.0, 4.0), 2.0, Color32::WHITE);
        let mut m = b.build();
        assert!(m.chunks.len() > 1);
        assert_eq!(m.vertex_count(), 4 * 40_000 + 4);
        let rect = Rect::from_min_size(Pos2::new(10.0, 20.0), egui::vec2(800.0, 600.0));
        let mut view = View::default();
        view.fit(rect, bounds.min, bounds.max);
        let ctx = egui::Context::default();
        for step in 0..3 {
            let mut drawn = 0;
            let _ = ctx.run(egui::RawInput::default(), |ctx| {
                let painter = ctx.layer_painter(egui::LayerId::background());
                m.draw(&painter, &view, rect);
            });
            let key = ViewKey {
                center: view.center,
                zoom: view.zoom,
                rect,
            };
            for c in &m.chunks {
                // A chunk not mapped for this view is off the canvas.
                if c.view != Some(key) {
                    assert!(!c.screen_rect(&view, rect).intersects(rect));
                    continue;
                }
                drawn += 1;
                for (k, v) in c.mesh.vertices.iter().enumerate() {
                    let want = view.to_screen(rect, c.world[k])
                        + c.offset.get(k).copied().unwrap_or_default();
                    assert!((v.pos - want).length() < 1e-3, "step {step}");
                }
            }
            assert!(drawn > 0);
            // Pan, then zoom in about a point (chunks leave the canvas).
            view.pan(egui::vec2(35.0, -12.0));
            view.zoom_about(rect, Pos2::new(300.0, 300.0), 3.0);
        }
        // The segment's band is 2 pixels wide across it.
        let c = m
            .chunks
            .iter()
            .find(|c| !c.offset.is_empty())
            .expect("the segment's chunk");
        let k = c
            .offset
            .iter()
            .position(|d| *d != Vec2::ZERO)
            .expect("the segment's vertices");
        let w = (c.offset[k] - c.offset[k + 3]).length();
        assert!((w - 2.0).abs() < 1e-5, "{w}");
    }

    /// A frame maps into the buffer the renderer does not hold: with the
    /// last frame's shapes alive, the positions go to the spare buffer.
    #[test]
    fn a_held_buffer_is_not_written() {
        let bounds = Aabb {
            min: Point::ZERO,
            max: Point::ONE,
        };
        let mut b = WorldMeshBuilder::new(bounds, 1);
        b.fan(&[Point::ZERO, Point::X, Point::ONE, Point::Y], Color32::RED);
        let mut m = b.build();
        let rect = Rect::from_min_size(Pos2::ZERO, egui::vec2(100.0, 100.0));
        let mut view = View::default();
        view.fit(rect, bounds.min, bounds.max);
        m.chunks[0].map(&view, rect);
        let held = m.chunks[0].mesh.clone();
        let before = held.vertices[0].pos;
        view.pan(egui::vec2(10.0, 0.0));
        m.chunks[0].map(&view, rect);
        assert_eq!(held.vertices[0].pos, before);
        assert_eq!(
            m.chunks[0].mesh.vertices[0].pos,
            before + egui::vec2(10.0, 0.0)
        );
        // The first buffer is free again: while the second is held, the
        // next view goes to the first, not to a third.
        drop(held);
        let first = m.chunks[0].spare.as_ref().map(Arc::as_ptr);
        let held = m.chunks[0].mesh.clone();
        view.pan(egui::vec2(10.0, 0.0));
        m.chunks[0].map(&view, rect);
        assert_eq!(first, Some(Arc::as_ptr(&m.chunks[0].mesh)));
        assert_eq!(held.vertices[0].pos, before + egui::vec2(10.0, 0.0));
    }
    /// Quads that tile a square leave no pixel of it empty in the image,
    /// each pixel takes its quad's colour, and a tint blends over it.
    #[test]
    fn tiling_quads_cover_the_image() {
        let size = [97, 61];
        let mut pixels = vec![Color32::TRANSPARENT; size[0] * size[1]];
        // A 13 × 7 grid of skewed quads over the image (image coordinates
        // are world coordinates here, y down), half of them clockwise.
        let node = |i: usize, j: usize| {
            let x = i as f64 * 97.0 / 13.0
                + if j % 7 == 0 {
                    0.0
                } else {
                    1.3 * (i % 3) as f64
                };
            Point::new(x.min(97.0), j as f64 * 61.0 / 7.0)
        };
        for i in 0..13 {
            for j in 0..7 {
                let mut q = [
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                ];
                if (i + j) % 2 == 0 {
                    q.reverse();
                }
                let color = Color32::from_rgb(i as u8, j as u8, 200);
                fill_convex(&mut pixels, size, &q, |p| (p.x, p.y), color, false);
            }
        }
        assert!(pixels.iter().all(|c| c.a() == 255 && c.b() == 200));
        let tint = Color32::from_rgba_unmultiplied_const(200, 60, 220, 90);
        let q = [node(0, 0), node(1, 0), node(1, 1), node(0, 1)];
        fill_convex(&mut pixels, size, &q, |p| (p.x, p.y), tint, true);
        assert_eq!(
            pixels[size[0] + 1],
            Color32::from_rgb(0, 0, 200).blend(tint)
        );
        // Degenerate and non-finite polygons change nothing.
        let before = pixels.clone();
        let flat = [Point::ZERO, Point::new(5.0, 5.0), Point::new(9.0, 9.0)];
        let nan = [Point::ZERO, Point::new(f64::NAN, 5.0), Point::new(9.0, 0.0)];
        let huge = [Point::ZERO, Point::new(1e300, 0.0), Point::new(0.0, 1e300)];
        for poly in [flat, nan, huge] {
            fill_convex(
                &mut pixels,
                size,
                &poly,
                |p| (p.x, p.y),
                Color32::RED,
                false,
            );
        }
        assert_eq!(&pixels[..], &before[..]);
    }
}

//! The element size field (thesis §1.2: elements dense near short boundary
//! segments, sizes changing smoothly): the size at a boundary node is the
//! mean length of its two segments, and inside the domain it is
//! interpolated linearly over a constrained Delaunay triangulation of the
//! boundary nodes (as Gmsh interpolates a boundary's mesh sizes when it is
//! given no other), then sampled on a uniform grid so a look-up costs the
//! same anywhere, and its growth with distance capped at [`GRADING`] so a
//! fine hole in a coarse domain grades out smoothly. The two ends of a
//! needle (a corner far sharper than any quad can take within the side
//! ratio) are point sources of the needle's width there, looked up exactly
//! near them. Extraction uses it to give rows their height and to tell
//! when two fronts are about to meet.

use super::guard::is_needle;
use crate::boundary::Boundary;
use crate::geom::Point;
use rustc_hash::{FxHashMap, FxHashSet};
use serde::{Deserialize, Serialize};
use spade::{ConstrainedDelaunayTriangulation, HasPosition, Point2, Triangulation};

/// Grid cells along the longer side of the domain's bounding box, at most.
const MAX_CELLS_PER_SIDE: usize = 1024;
/// A boundary of `n` nodes gets at most `CELLS_PER_NODE · n` cells a side
/// (but never fewer than [`MIN_CELLS_PER_SIDE`]): a few nodes carry few
/// sizes, and the small regions remeshing cuts out are met by the hundred.
const CELLS_PER_NODE: usize = 4;
/// The fewest cells a side the node bound leaves.
const MIN_CELLS_PER_SIDE: usize = 256;

/// The fastest the size may grow with distance (size per unit length): away
/// from a fine boundary the size rises by at most half the distance, about
/// a 1.5 ratio from one row to the next.
const GRADING: f64 = 0.5;

/// A boundary node spaced more than this many times a [`SizeTarget`]'s
/// size is coarser than the target by request (a layer sized coarser), and
/// the size falls from its spacing to the target at the gradation around
/// it. Up to this, the spacing is the target's rounded: a curve cut at
/// size `h` into `round(length / h)` segments has them up to 1.5 `h` long.
pub const COARSE_SPACING: f64 = 1.5;

/// A size field asked for from outside (a drawing's target size and its
/// local sizes, [`crate::cad`]): the size at `p` is
/// `min(max, h_i + gradation·|p − p_i|)` over the point sizes `(p_i, h_i)`
/// and over the boundary nodes with their spacing as the size, `max`
/// raised first to `h_b − gradation·|p − p_b|` around a boundary node
/// spaced `h_b` more than [`COARSE_SPACING`] times `max`. Given to
/// [`SizeField::of_boundary_with`], it replaces the interpolation of the
/// boundary's spacing inside the domain, so the interior follows the size
/// asked for rather than the boundary's spacing alone.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SizeTarget {
    /// The size wherever nothing asks for less.
    pub max: f64,
    /// The growth of the size with distance from a finer size (size per
    /// unit length).
    pub gradation: f64,
    /// Point sizes: position and size.
    pub points: Vec<(Point, f64)>,
}

impl SizeTarget {
    /// The same target in a frame moved by `-origin` (as
    /// [`Boundary::to_local`] moves a boundary).
    pub fn moved(&self, origin: Point) -> SizeTarget {
        SizeTarget {
            points: self.points.iter().map(|&(p, h)| (p - origin, h)).collect(),
            ..self.clone()
        }
    }
}

/// A size field sampled on a grid of cell centres, looked up bilinearly.
#[derive(Clone, Debug)]
pub struct SizeField {
    origin: Point,
    inv_cell: f64,
    nx: usize,
    ny: usize,
    h: Vec<f32>,
    /// Smallest and largest size anywhere.
    range: [f64; 2],
    /// Quads a mesh following the field would have: the sum of
    /// `cell² / h²` over the cells inside the domain.
    quads: f64,
    /// Point sizes finer than the grid resolves (the ends of needles).
    sources: Sources,
}

/// Point sources of size, looked up exactly near them: within a few grid
/// cells of a source the size is the least of the sources' sizes grown by
/// [`GRADING`] with their distance (the grid, too coarse to hold a source
/// much finer than its cells, holds it only blurred). Sources are filed
/// twice: in cells about as wide as they are apart, searched a few rings
/// around a point, and in cells a quarter of the grid's, searched when the
/// first finds none.
#[derive(Clone, Debug, Default)]
struct Sources {
    origin: Point,
    /// The smallest source size.
    lo: f64,
    near: SourceCells,
    far: SourceCells,
    /// Keys of the grid cells holding a source.
    coarse: FxHashSet<u64>,
    /// Side of the grid's cells.
    grid_cell: f64,
}

/// Sources filed under square cells.
#[derive(Clone, Debug, Default)]
struct SourceCells {
    cell: f64,
    /// Rings of cells searched around a point, at most.
    reach: i64,
    /// `(cell key, position, size)`, sorted by key.
    filed: Vec<(u64, Point, f64)>,
    /// The run of `filed` each occupied cell's key heads (start, end): a
    /// look-up of a cell is one hash probe, where a search of `filed` took
    /// a dozen steps, and most cells a ring search visits are empty.
    runs: FxHashMap<u64, (u32, u32)>,
}

/// Grid cells around a point (each way) within which sources are looked
/// up exactly.
const SOURCE_CELLS: i64 = 2;
/// Rings of the finer source cells searched around a point.
const NEAR_RINGS: i64 = 8;
/// Source cells of the coarser filing a grid cell's side holds.
const FAR_PER_CELL: f64 = 4.0;

impl SourceCells {
    fn new(raw: &[(Point, f64)], origin: Point, cell: f64, reach: i64) -> SourceCells {
        let mut filed: Vec<(u64, Point, f64)> = raw
            .iter()
            .map(|&(p, h)| {
                let (i, j) = index(p, origin, cell);
                (key(i, j), p, h)
            })
            .collect();
        filed.sort_by_key(|e| e.0);
        let mut runs = FxHashMap::default();
        let mut start = 0;
        for (i, e) in filed.iter().enumerate() {
            if filed.get(i + 1).is_none_or(|n| n.0 != e.0) {
                runs.insert(e.0, (start as u32, i as u32 + 1));
                start = i + 1;
            }
        }
        SourceCells {
            cell,
            reach: reach.max(1),
            filed,
            runs,
        }
    }

    /// The least size the sources give at `p`, searching rings of cells
    /// outwards until no source further out can give less (`lo` being the
    /// smallest source size), or up to the reach; infinite when none is
    /// found.
    fn at(&self, p: Point, origin: Point, lo: f64) -> f64 {
        let (i, j) = index(p, origin, self.cell);
        let in_cell = |x: i64, y: i64| match self.runs.get(&key(x, y)) {
            Some(&(from, to)) => self.filed[from as usize..to as usize]
                .iter()
                .map(|&(_, q, h)| h + GRADING * q.distance(p))
                .fold(f64::INFINITY, f64::min),
            None => f64::INFINITY,
        };
        let mut best = in_cell(i, j);
        for r in 1..=self.reach {
            if lo + GRADING * (r - 1) as f64 * self.cell >= best {
                break;
            }
            for d in -r..=r {
                best = best.min(in_cell(i + d, j - r)).min(in_cell(i + d, j + r));
            }
            for d in (1 - r)..r {
                best = best.min(in_cell(i - r, j + d)).min(in_cell(i + r, j + d));
            }
        }
        best
    }
}

impl Sources {
    /// Files sources `raw` (position, size) for a grid with cells of side
    /// `grid_cell` from `origin`.
    fn new(raw: Vec<(Point, f64)>, origin: Point, grid_cell: f64) -> Sources {
        if raw.is_empty() {
            return Sources::default();
        }
        let mut sizes: Vec<f64> = raw.iter().map(|s| s.1).collect();
        sizes.sort_by(f64::total_cmp);
        let far_cell = grid_cell / FAR_PER_CELL;
        let near_cell = (2.0 * sizes[sizes.len() / 2]).min(far_cell);
        let far_reach = (SOURCE_CELLS as f64 * FAR_PER_CELL).ceil() as i64;
        let coarse: FxHashSet<u64> = raw
            .iter()
            .map(|&(p, _)| {
                let (i, j) = index(p, origin, grid_cell);
                key(i, j)
            })
            .collect();
        Sources {
            origin,
            lo: sizes[0],
            near: SourceCells::new(&raw, origin, near_cell, NEAR_RINGS),
            far: SourceCells::new(&raw, origin, far_cell, far_reach),
            coarse,
            grid_cell,
        }
    }

    /// The least size the sources give at `p` (infinite when none is
    /// within [`SOURCE_CELLS`] grid cells).
    fn at(&self, p: Point) -> f64 {
        if self.coarse.is_empty() {
            return f64::INFINITY;
        }
        let (ci, cj) = index(p, self.origin, self.grid_cell);
        let near = (-SOURCE_CELLS..=SOURCE_CELLS).any(|dj| {
            (-SOURCE_CELLS..=SOURCE_CELLS).any(|di| self.coarse.contains(&key(ci + di, cj + dj)))
        });
        if !near {
            return f64::INFINITY;
        }
        let h = if self.near_may_hold(p) {
            self.near.at(p, self.origin, self.lo)
        } else {
            f64::INFINITY
        };
        if h.is_finite() {
            h
        } else {
            self.far.at(p, self.origin, self.lo)
        }
    }

    /// Whether the cells the near filing searches around `p` may hold a
    /// source, answered from the coarser filing where that takes fewer
    /// look-ups: far from every source (most of a domain) the near search
    /// would visit all its rings of empty cells to find nothing. The far
    /// cells looked at cover the near search's square with a cell to spare
    /// each way, so a "no" is certain.
    fn near_may_hold(&self, p: Point) -> bool {
        let (near, far) = (&self.near, &self.far);
        let (i, j) = index(p, self.origin, near.cell);
        let r = near.reach as f64;
        let corner = |di: f64, dj: f64| {
            let q = self.origin + Point::new(i as f64 + di, j as f64 + dj) * near.cell;
            index(q, self.origin, far.cell)
        };
        let ((x0, y0), (x1, y1)) = (corner(-r, -r), corner(r + 1.0, r + 1.0));
        let (x0, y0, x1, y1) = (x0 - 1, y0 - 1, x1 + 1, y1 + 1);
        let side = 2 * near.reach + 1;
        if (x1 - x0 + 1) * (y1 - y0 + 1) >= side * side {
            return true;
        }
        (y0..=y1).any(|y| (x0..=x1).any(|x| far.runs.contains_key(&key(x, y))))
    }
}

/// The cell of side `cell` from `origin` that `p` lies in (clamped to
/// non-negative indices).
fn index(p: Point, origin: Point, cell: f64) -> (i64, i64) {
    let g = (p - origin) / cell;
    let f = |v: f64| v.floor().clamp(0.0, f64::from(u32::MAX - 1)) as i64;
    (f(g.x), f(g.y))
}

/// A cell's key (cells with a negative index get one no source has).
fn key(i: i64, j: i64) -> u64 {
    if i < 0 || j < 0 {
        return u64::MAX;
    }
    ((j as u64) << 32) | i as u64
}

#[derive(Clone, Copy, Debug)]
struct Sized {
    p: Point2<f64>,
    h: f64,
}

impl HasPosition for Sized {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.p
    }
}

impl SizeField {
    /// The field of `boundary`'s spacing.
    pub fn of_boundary(boundary: &Boundary) -> SizeField {
        SizeField::of_boundary_with(boundary, None)
    }

    /// The field of `boundary`'s spacing, or with `target` the field it
    /// asks for ([`SizeTarget`]); `None` is [`SizeField::of_boundary`].
    pub fn of_boundary_with(boundary: &Boundary, target: Option<&SizeTarget>) -> SizeField {
        let pts = &boundary.points;
        let mut node_h = vec![0.0; pts.len()];
        for l in &boundary.loops {
            let n = l.len();
            for k in 0..n {
                let (a, v, b) = (l[(k + n - 1) % n], l[k], l[(k + 1) % n]);
                node_h[v] = 0.5 * (pts[a].distance(pts[v]) + pts[v].distance(pts[b]));
            }
        }
        let bb = boundary.bbox();
        let size = bb.size();
        let mut lo = node_h.iter().copied().fold(f64::INFINITY, f64::min);
        let mut hi = node_h.iter().copied().fold(0.0, f64::max);
        if let Some(t) = target {
            // A point size counts by the least size it asks inside the
            // boundary's box: one far outside asks for nothing finer there
            // and leaves the grid as it would be without it.
            lo = t
                .points
                .iter()
                .map(|&(p, h)| h + t.gradation * bb.distance_to(p))
                .fold(lo, f64::min);
            hi = hi.max(t.max);
        }
        let extent = size.max_element().max(f64::MIN_POSITIVE);
        let per_side = (CELLS_PER_NODE * pts.len()).clamp(MIN_CELLS_PER_SIDE, MAX_CELLS_PER_SIDE);
        let cell = (extent / per_side as f64).max(0.5 * lo.min(extent));
        let nx = ((size.x / cell).ceil() as usize).clamp(1, per_side + 1) + 1;
        let ny = ((size.y / cell).ceil() as usize).clamp(1, per_side + 1) + 1;
        let mut f = SizeField {
            origin: bb.min,
            inv_cell: 1.0 / cell,
            nx,
            ny,
            h: vec![f32::NAN; nx * ny],
            range: [lo, hi],
            quads: 0.0,
            sources: Sources::default(),
        };
        let median = boundary.median_segment();
        if !f.rasterise(boundary, &node_h) {
            f.h.fill(median as f32);
            if target.is_none() {
                f.range = [median, median];
            }
        }
        let inside: Vec<bool> = f.h.iter().map(|v| !v.is_nan()).collect();
        match target {
            Some(t) => f.follow_target(boundary, &node_h, t),
            None => f.fill_gaps(median),
        }
        f.needle_sources(boundary);
        f.limit_grading(GRADING);
        let cell2 = cell * cell;
        f.quads =
            f.h.iter()
                .zip(&inside)
                .filter(|(_, &i)| i)
                .map(|(&h, _)| cell2 / (h as f64 * h as f64).max(f64::MIN_POSITIVE))
                .sum();
        if f.quads == 0.0 || !f.quads.is_finite() {
            f.quads = boundary.area() / (median * median);
        }
        f
    }

    /// About how many quads a mesh that follows the field has (the
    /// domain's area over the squared size, summed cell by cell).
    pub fn quad_estimate(&self) -> f64 {
        self.quads
    }

    /// The nodes across a needle's narrow end (guard::is_needle) are as far
    /// apart as its elements are wide there, whatever the length of its
    /// sides: each is a source of that size, which the grading then
    /// spreads (the region a fan of needles meets is meshed from their
    /// ends' spacing, growing inwards, not at their sides' length).
    fn needle_sources(&mut self, boundary: &Boundary) {
        let pts = &boundary.points;
        let mut raw = Vec::new();
        for l in &boundary.loops {
            let n = l.len();
            for k in 0..n {
                let (a, v, b) = (l[(k + n - 1) % n], l[k], l[(k + 1) % n]);
                if !is_needle(pts[v], pts[a], pts[b]) {
                    continue;
                }
                let span = pts[a].distance(pts[b]);
                for p in [pts[a], pts[b]] {
                    self.lower_around(p, span);
                    raw.push((p, span));
                }
                self.range[0] = self.range[0].min(span);
            }
        }
        self.sources = Sources::new(raw, self.origin, 1.0 / self.inv_cell);
    }

    /// Sets the field to what `target` asks ([`SizeTarget`]): its largest
    /// size, raised around the boundary nodes spaced more than
    /// [`COARSE_SPACING`] times it and falling from them at the target's
    /// gradation, then lowered around every point size and every boundary
    /// node (with its spacing) and grown from them at the gradation.
    fn follow_target(&mut self, boundary: &Boundary, node_h: &[f64], target: &SizeTarget) {
        self.h.fill(target.max as f32);
        let g = target.gradation;
        // A boundary coarser than the target (a curve on a layer sized
        // coarser) is met by sizes falling to the target at the gradation,
        // not by the target at once: a row of the target's height along
        // segments several times longer knots.
        let mut raised = false;
        for (&p, &h) in boundary.points.iter().zip(node_h) {
            if h > COARSE_SPACING * target.max {
                self.raise_around_at(p, h, g);
                raised = true;
            }
        }
        if raised {
            self.limit_decline(g);
        }
        for (&p, &h) in boundary.points.iter().zip(node_h) {
            self.lower_around_at(p, h, g);
        }
        for &(p, h) in &target.points {
            self.lower_around_at(p, h, g);
        }
        self.limit_grading(g);
    }

    /// Lowers the samples around `p` to size `h` grown by [`GRADING`] with
    /// their distance from `p` (the grading then spreads it over the grid).
    fn lower_around(&mut self, p: Point, h: f64) {
        self.lower_around_at(p, h, GRADING);
    }

    /// [`SizeField::lower_around`] with growth `rate`.
    fn lower_around_at(&mut self, p: Point, h: f64, rate: f64) {
        self.set_around(p, h, rate, false);
    }

    /// Raises the samples around `p` to size `h` lessened by `rate` with
    /// their distance from `p` ([`SizeField::limit_decline`] then spreads
    /// it over the grid).
    fn raise_around_at(&mut self, p: Point, h: f64, rate: f64) {
        self.set_around(p, h, rate, true);
    }

    /// The four samples around `p` lowered to `h` grown by `rate` with
    /// their distance from `p` (`raise` false), or raised to `h` lessened
    /// by it.
    fn set_around(&mut self, p: Point, h: f64, rate: f64, raise: bool) {
        let cell = 1.0 / self.inv_cell;
        let g = (p - self.origin) * self.inv_cell;
        let i0 = (g.x.max(0.0) as usize).min(self.nx - 1);
        let j0 = (g.y.max(0.0) as usize).min(self.ny - 1);
        for j in j0..=(j0 + 1).min(self.ny - 1) {
            for i in i0..=(i0 + 1).min(self.nx - 1) {
                let at = self.origin + Point::new(i as f64, j as f64) * cell;
                let k = j * self.nx + i;
                let d = rate * at.distance(p);
                self.h[k] = if raise {
                    self.h[k].max((h - d) as f32)
                } else {
                    self.h[k].min((h + d) as f32)
                };
            }
        }
    }

    /// Caps the growth of the size with distance at `rate` (size per unit
    /// length): `h(p) <= h(q) + rate·|p − q|` for every pair of cells, by
    /// two chamfer sweeps over the grid. A fine hole in a coarse box then
    /// grades out smoothly instead of along the long triangles between them.
    fn limit_grading(&mut self, rate: f64) {
        self.chamfer(rate, false);
    }

    /// Caps the fall of the size with distance at `rate`: `h(p) >= h(q) −
    /// rate·|p − q|` for every pair of cells ([`SizeField::limit_grading`]
    /// turned over): a coarse size fades out instead of stopping.
    fn limit_decline(&mut self, rate: f64) {
        self.chamfer(rate, true);
    }

    /// Two chamfer sweeps over the grid bounding the change of the size
    /// with distance at `rate`: its growth (`raise` false) or its fall.
    fn chamfer(&mut self, rate: f64, raise: bool) {
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        let cell = 1.0 / self.inv_cell;
        let straight = (rate * cell) as f32;
        let diagonal = (rate * cell * std::f64::consts::SQRT_2) as f32;
        let forward = [
            (-1, 0, straight),
            (-1, -1, diagonal),
            (0, -1, straight),
            (1, -1, diagonal),
        ];
        let backward = forward.map(|(di, dj, w)| (-di, -dj, w));
        let h = &mut self.h;
        let mut sweep = |order: &mut dyn Iterator<Item = (i64, i64)>,
                         steps: &[(i64, i64, f32); 4]| {
            for (i, j) in order {
                let k = (j * nx + i) as usize;
                let mut v = h[k];
                for &(di, dj, w) in steps {
                    let (a, b) = (i + di, j + dj);
                    if a >= 0 && b >= 0 && a < nx && b < ny {
                        let u = h[(b * nx + a) as usize];
                        v = if raise { v.max(u - w) } else { v.min(u + w) };
                    }
                }
                h[k] = v;
            }
        };
        sweep(
            &mut (0..ny).flat_map(|j| (0..nx).map(move |i| (i, j))),
            &forward,
        );
        sweep(
            &mut (0..ny)
                .rev()
                .flat_map(|j| (0..nx).rev().map(move |i| (i, j))),
            &backward,
        );
    }

    /// Linear interpolation over the triangles of the boundary nodes'
    /// constrained Delaunay triangulation, written to the cell centres each
    /// triangle covers. False when the triangulation cannot be built.
    fn rasterise(&mut self, boundary: &Boundary, node_h: &[f64]) -> bool {
        // Coordinates relative to the box's corner keep the triangulation's
        // arithmetic at the domain's own scale wherever the domain lies.
        let o = self.origin;
        let vertices: Vec<Sized> = boundary
            .points
            .iter()
            .zip(node_h)
            .map(|(p, &h)| Sized {
                p: Point2::new(p.x - o.x, p.y - o.y),
                h,
            })
            .collect();
        let edges: Vec<[usize; 2]> = boundary.segments().map(|(a, b)| [a, b]).collect::<Vec<_>>();
        let built = crate::spade_guard::guarded(move || {
            ConstrainedDelaunayTriangulation::<Sized>::try_bulk_load_cdt(vertices, edges, |_| {})
        });
        let Some(Ok(cdt)) = built else {
            return false;
        };
        let cell = 1.0 / self.inv_cell;
        for face in cdt.inner_faces() {
            let [a, b, c] = face.vertices().map(|v| {
                let d = v.data();
                (Point::new(d.p.x, d.p.y), d.h)
            });
            let area2 = (b.0 - a.0).perp_dot(c.0 - a.0);
            if area2.abs() <= 0.0 {
                continue;
            }
            let lo = a.0.min(b.0).min(c.0);
            let hi = a.0.max(b.0).max(c.0);
            let (i0, j0) = (
                ((lo.x / cell).floor().max(0.0)) as usize,
                ((lo.y / cell).floor().max(0.0)) as usize,
            );
            let (i1, j1) = (
                ((hi.x / cell).ceil() as usize).min(self.nx - 1),
                ((hi.y / cell).ceil() as usize).min(self.ny - 1),
            );
            for j in j0..=j1 {
                // The row's cells under the triangle, a cell to spare each
                // side (the test below decides): a long thin triangle
                // costs its own cells, not its bounding box's.
                let (r0, r1) = match row_span([a.0, b.0, c.0], j as f64 * cell) {
                    Some((x0, x1)) => (
                        ((x0 / cell).floor() - 1.0).max(i0 as f64) as usize,
                        ((x1 / cell).ceil() + 1.0).min(i1 as f64) as usize,
                    ),
                    None => (i0, i1),
                };
                for i in r0..=r1 {
                    let p = Point::new(i as f64 * cell, j as f64 * cell);
                    let wa = (b.0 - p).perp_dot(c.0 - p) / area2;
                    let wb = (c.0 - p).perp_dot(a.0 - p) / area2;
                    let wc = 1.0 - wa - wb;
                    let eps = -1e-9;
                    if wa >= eps && wb >= eps && wc >= eps {
                        self.h[j * self.nx + i] = (wa * a.1 + wb * b.1 + wc * c.1) as f32;
                    }
                }
            }
        }
        true
    }

    /// Cells no triangle covered (outside the domain, in holes) take the
    /// mean of their covered neighbours, ring by ring; `fallback` where
    /// nothing was covered at all.
    fn fill_gaps(&mut self, fallback: f64) {
        let (nx, ny) = (self.nx, self.ny);
        const UNKNOWN: u32 = u32::MAX;
        let neighbours = move |k: usize| {
            let (i, j) = ((k % nx) as i64, (k / nx) as i64);
            [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)]
                .into_iter()
                .map(move |(di, dj)| (i + di, j + dj))
                .filter(move |&(a, b)| a >= 0 && b >= 0 && (a as usize) < nx && (b as usize) < ny)
                .map(move |(a, b)| b as usize * nx + a as usize)
        };
        // The ring each cell was set in (0: covered by a triangle); ring r
        // takes the mean of its neighbours of earlier rings.
        let mut ring: Vec<u32> = self
            .h
            .iter()
            .map(|v| if v.is_nan() { UNKNOWN } else { 0 })
            .collect();
        let mut frontier: Vec<usize> = (0..nx * ny)
            .filter(|&k| ring[k] == UNKNOWN && neighbours(k).any(|u| ring[u] == 0))
            .collect();
        let mut r = 1;
        let mut set = Vec::new();
        while !frontier.is_empty() {
            set.clear();
            for &k in &frontier {
                let (mut s, mut n) = (0.0f32, 0);
                for u in neighbours(k) {
                    if ring[u] < r {
                        s += self.h[u];
                        n += 1;
                    }
                }
                set.push((k, s / n as f32));
            }
            for &(k, v) in &set {
                self.h[k] = v;
                ring[k] = r;
            }
            frontier.clear();
            for &(k, _) in &set {
                frontier.extend(neighbours(k).filter(|&u| ring[u] == UNKNOWN));
            }
            frontier.sort_unstable();
            frontier.dedup();
            r += 1;
        }
        for (h, &g) in self.h.iter_mut().zip(&ring) {
            if g == UNKNOWN {
                *h = fallback as f32;
            }
        }
    }

    /// The size at `p` (bilinear between cell centres, clamped to the grid).
    pub fn at(&self, p: Point) -> f64 {
        let q = (p - self.origin) * self.inv_cell;
        let x = q.x.clamp(0.0, (self.nx - 1) as f64);
        let y = q.y.clamp(0.0, (self.ny - 1) as f64);
        let (i, j) = (
            (x as usize).min(self.nx.saturating_sub(2)),
            (y as usize).min(self.ny.saturating_sub(2)),
        );
        let (fx, fy) = (x - i as f64, y - j as f64);
        let at =
            |i: usize, j: usize| self.h[(j.min(self.ny - 1)) * self.nx + i.min(self.nx - 1)] as f64;
        let a = at(i, j) * (1.0 - fx) + at(i + 1, j) * fx;
        let b = at(i, j + 1) * (1.0 - fx) + at(i + 1, j + 1) * fx;
        let h = a * (1.0 - fy) + b * fy;
        let h = h.min(self.sources.at(p));
        h.clamp(self.range[0], self.range[1])
    }

    /// Smallest and largest size of the field.
    pub fn range(&self) -> [f64; 2] {
        self.range
    }
}

/// Where the horizontal line at `y` crosses triangle `t`: the smallest and
/// largest x, or `None` when `y` is outside the triangle's rows.
fn row_span(t: [Point; 3], y: f64) -> Option<(f64, f64)> {
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..3 {
        let (p, q) = (t[k], t[(k + 1) % 3]);
        if (p.y - y) * (q.y - y) > 0.0 {
            continue;
        }
        let x = if p.y == q.y {
            x0 = x0.min(p.x.min(q.x));
            p.x.max(q.x)
        } else {
            p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y)
        };
        x0 = x0.min(x);
        x1 = x1.max(x);
    }
    (x0 <= x1).then_some((x0, x1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ends of needles are sources of their narrow end's width: the
    /// size there is that width, not their sides' length, and it grows
    /// inwards at the grading rate.
    #[test]
    fn needle_ends_set_the_size_around_them() {
        let n = 400;
        let pts = crate::extract::guard::sunburst(n);
        let span = pts[1].distance(pts[3]);
        let b = Boundary::new(pts.clone(), vec![(0..2 * n).collect()], None).unwrap();
        let f = SizeField::of_boundary(&b);
        assert!(
            (f.at(pts[1]) - span).abs() < 1e-9 * span,
            "{}",
            f.at(pts[1])
        );
        let inside = pts[1] * 0.9;
        let d = pts[1].distance(inside);
        assert!(f.at(inside) <= span + GRADING * d + 1e-12);
        assert!(f.at(inside) > 0.5 * (span + GRADING * d));
        assert!(f.at(Point::ZERO) <= span + GRADING * 0.05 + 1e-12);
        assert!((f.range()[0] - span).abs() < 1e-12);
    }

    #[test]
    fn uniform_spacing_gives_a_uniform_field() {
        let b = Boundary::unit_square(10);
        let f = SizeField::of_boundary(&b);
        for p in [
            Point::new(0.5, 0.5),
            Point::new(0.1, 0.9),
            Point::new(0.0, 0.0),
        ] {
            assert!((f.at(p) - 0.1).abs() < 1e-6, "{}", f.at(p));
        }
    }

    #[test]
    fn a_boundary_coarser_than_the_target_raises_the_size_beside_it() {
        // A 10 × 20 rectangle cut at 2 (five times the target 0.4) on its
        // left side and at 0.4 elsewhere, and a point size of 0.1 near the
        // bottom right corner.
        let mut pts: Vec<Point> = (0..25).map(|i| Point::new(i as f64 * 0.4, 0.0)).collect();
        pts.extend((0..50).map(|i| Point::new(10.0, i as f64 * 0.4)));
        pts.extend((0..25).map(|i| Point::new(10.0 - i as f64 * 0.4, 20.0)));
        pts.extend((0..10).map(|i| Point::new(0.0, 20.0 - i as f64 * 2.0)));
        let n = pts.len();
        let b = Boundary::new(pts, vec![(0..n).collect()], None).unwrap();
        let target = SizeTarget {
            max: 0.4,
            gradation: 0.3,
            points: vec![(Point::new(8.0, 1.5), 0.1)],
        };
        let f = SizeField::of_boundary_with(&b, Some(&target));
        let tol = 0.05;
        // Beside the coarse side, its spacing less the gradation times the
        // distance; the target from 5.3 away.
        for (x, want) in [(0.5, 1.85), (2.0, 1.4), (4.0, 0.8), (7.0, 0.4)] {
            let h = f.at(Point::new(x, 10.0));
            assert!((h - want).abs() < tol, "at x = {x}: {h}, not {want}");
        }
        // The point size still wins where it is finer.
        let h = f.at(Point::new(8.0, 1.5));
        assert!((h - 0.1).abs() < tol, "{h}");
        // Without a coarse side, nothing is raised.
        let g = SizeField::of_boundary_with(
            &Boundary::unit_square(10),
            Some(&SizeTarget {
                max: 0.1,
                gradation: 0.3,
                points: Vec::new(),
            }),
        );
        assert!((g.at(Point::new(0.05, 0.5)) - 0.1).abs() < 1e-6);
    }

    #[test]
    fn graded_spacing_is_interpolated() {
        // A 1 × 1 square: 10 segments along the bottom, 2 along the top.
        let mut pts: Vec<Point> = (0..=10).map(|i| Point::new(i as f64 / 10.0, 0.0)).collect();
        pts.push(Point::new(1.0, 0.5));
        pts.push(Point::new(1.0, 1.0));
        pts.push(Point::new(0.5, 1.0));
        pts.push(Point::new(0.0, 1.0));
        pts.push(Point::new(0.0, 0.5));
        let n = pts.len();
        let b = Boundary::new(pts, vec![(0..n).collect()], None).unwrap();
        let f = SizeField::of_boundary(&b);
        let bottom = f.at(Point::new(0.5, 0.02));
        let middle = f.at(Point::new(0.5, 0.5));
        let top = f.at(Point::new(0.5, 0.98));
        assert!(bottom < middle && middle < top, "{bottom} {middle} {top}");
        assert!(
            (bottom - 0.1).abs() < 0.03 && (top - 0.5).abs() < 0.05,
            "{bottom} {top}"
        );
    }
}

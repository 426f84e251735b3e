//! The domain to mesh: one outer loop and any number of hole loops of
//! straight segments (method §1).
//!
//! The given nodes are the boundary discretisation: the mesher never moves,
//! drops or adds one. [`Boundary::new`] validates the loops and orients them
//! so that the domain lies on the left of every directed edge (outer loop
//! counter-clockwise, holes clockwise). Every problem is reported with the
//! loop and the node (as numbered in the input) at fault.
//!
//! Validation judges "the same position" and "touching" relative to the
//! magnitude of the coordinates involved, never to the size of the other
//! segments: two points closer than [`TOUCH_EPS`] times their largest
//! coordinate are the same point up to rounding. Crossings are found
//! exactly (Shewchuk's predicates) by a sweep, in `O(n log n)` time and
//! linear memory, whatever the shape.

use crate::geom::{orient, polygon_area, segments_intersect, Aabb, Point};
use serde::{Deserialize, Serialize};
use std::cmp::Ordering;
use thiserror::Error;

/// Largest coordinate magnitude accepted. Squared lengths and areas of
/// larger coordinates (or their differences) overflow to infinity.
pub const MAX_COORDINATE: f64 = 1e150;

/// Smallest extent a boundary may span. Squared lengths and areas of a
/// smaller one underflow.
pub const MIN_EXTENT: f64 = 1e-150;

/// Two points closer (in each coordinate) than this times the largest
/// magnitude of their coordinates are the same point up to rounding, and a
/// node that close to a segment touches it: 8 units in the last place.
pub const TOUCH_EPS: f64 = 8.0 * f64::EPSILON;

/// A segment shorter than this fraction of the boundary's extent repeats
/// the node before it: no element between such a node and the rest of the
/// domain could have a sensible shape (grading of 1:100 000 along one
/// boundary is far beyond what a mesh can follow).
pub const DUPLICATE_RATIO: f64 = 1e-5;

/// Why a boundary cannot be meshed. Loops are numbered from 0 in input
/// order; nodes carry the label they had in the input file.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BoundaryError {
    #[error("the boundary has no nodes")]
    Empty,
    #[error("the boundary has {count} nodes; a quad mesh needs at least 4")]
    TooFewNodes { count: usize },
    #[error("node {node} has a non-finite coordinate")]
    NonFinite { node: i64 },
    #[error("node {node} has a coordinate of magnitude {value:e}: coordinates must lie within ±1e150, beyond which lengths and areas overflow (scale the boundary down)")]
    TooLarge { node: i64, value: f64 },
    #[error("the boundary spans only {extent:e}: below 1e-150 lengths and areas underflow (scale the boundary up)")]
    TooSmall { extent: f64 },
    #[error("segment {segment} refers to node {node}, which does not exist")]
    BadSegmentIndex { segment: usize, node: i64 },
    #[error("node {node} ends an open chain: every node must join exactly two segments")]
    OpenChain { node: i64 },
    #[error("node {node} joins {degree} segments: loops may not branch")]
    Branching { node: i64, degree: usize },
    #[error("loop {loop_index} has only {nodes} nodes; a loop needs at least 3")]
    LoopTooShort { loop_index: usize, nodes: usize },
    #[error("loop {loop_index}: node {node} repeats the position of the node before it (closer than 1e-5 of the boundary's extent)")]
    DuplicateNode { loop_index: usize, node: i64 },
    #[error("loop {loop_a}: node {node_a} is at the position of node {node_b} of loop {loop_b} (up to rounding)")]
    NodesCoincide {
        loop_a: usize,
        node_a: i64,
        loop_b: usize,
        node_b: i64,
    },
    #[error("loop {loop_index} encloses no area (its nodes are collinear or fold back)")]
    ZeroArea { loop_index: usize },
    #[error(
        "loop {loop_index} folds back on itself at node {node}: its two segments there overlap"
    )]
    FoldBack { loop_index: usize, node: i64 },
    #[error("loop {loop_a}: node {node} touches the segment from node {from} to node {to} of loop {loop_b} (it lies on it, up to rounding)")]
    NodeOnSegment {
        loop_a: usize,
        node: i64,
        loop_b: usize,
        from: i64,
        to: i64,
    },
    #[error("loop {loop_a} (segment from node {node_a}) crosses or touches loop {loop_b} (segment from node {node_b})")]
    Crossing {
        loop_a: usize,
        node_a: i64,
        loop_b: usize,
        node_b: i64,
    },
    #[error("loop {loop_index} is a hole that lies outside the outer loop")]
    HoleOutside { loop_index: usize },
    #[error("loop {loop_index} lies inside hole loop {hole}; islands in holes are not supported")]
    NestedHole { loop_index: usize, hole: usize },
    #[error("the boundary has {count} nodes, an odd number: an all-quad mesh needs an even total (add or remove one boundary node, for example by resampling a loop)")]
    OddNodeCount { count: usize },
}

/// A validated, oriented boundary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Boundary {
    /// Node positions, indexed by node id.
    pub points: Vec<Point>,
    /// Loops of node ids: `loops[0]` is the outer loop (CCW), the rest are
    /// holes (CW). Every node belongs to exactly one loop.
    pub loops: Vec<Vec<usize>>,
    /// The number each node had in the input (for messages); `id + 1` when
    /// the input had none.
    pub labels: Vec<i64>,
}

/// The rounding error of `a + b` (Knuth's TwoSum): zero exactly when the
/// sum is exact.
fn two_sum_error(a: f64, b: f64) -> f64 {
    let s = a + b;
    let bb = s - a;
    (a - (s - bb)) + (b - bb)
}

/// The largest magnitude of the coordinates of `pts`.
#[inline]
fn magnitude<const N: usize>(pts: [Point; N]) -> f64 {
    pts.iter().fold(0.0, |m, p| m.max(p.x.abs()).max(p.y.abs()))
}

/// True when `a` and `b` are the same point up to rounding.
#[inline]
fn same_point(a: Point, b: Point) -> bool {
    let d = (a - b).abs();
    d.x.max(d.y) <= TOUCH_EPS * magnitude([a, b])
}

/// Signed area of a loop, summed relative to its first node so that
/// coordinates far from the origin do not cancel (a unit square at 1e8
/// has area 1, not rounding noise).
fn local_area(pts: impl Iterator<Item = Point> + Clone) -> f64 {
    let mut it = pts.clone();
    let Some(o) = it.next() else {
        return 0.0;
    };
    let mut s = 0.0;
    let mut prev = Point::ZERO;
    for p in it.chain(std::iter::once(o)) {
        let q = p - o;
        s += prev.perp_dot(q);
        prev = q;
    }
    0.5 * s
}

/// Even–odd test with exact predicates: is `p` inside the closed polygon
/// `poly`? `p` must not lie on it (validation has ruled touching out).
fn inside(p: Point, poly: &[Point]) -> bool {
    let n = poly.len();
    let mut result = false;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) {
            // The edge crosses the horizontal line through p: does it
            // cross it to the right of p?
            let o = if b.y > a.y {
                orient(a, b, p)
            } else {
                orient(b, a, p)
            };
            if o > 0.0 {
                result = !result;
            }
        }
    }
    result
}

impl Boundary {
    /// Validates `loops` over `points` and returns the oriented boundary with
    /// the outer loop (the one of largest area) first.
    ///
    /// The checks, cheapest first: nodes exist, are finite and within
    /// [`MAX_COORDINATE`]; every loop has 3 nodes or more and the total is
    /// even; no segment has zero length and no two nodes share a position
    /// (up to rounding, [`TOUCH_EPS`]); every loop encloses an area; no two
    /// segments cross, overlap or touch, and no node touches a segment it
    /// does not end (exactly, and up to rounding); every hole lies inside
    /// the outer loop and outside the other holes.
    pub fn new(
        points: Vec<Point>,
        loops: Vec<Vec<usize>>,
        labels: Option<Vec<i64>>,
    ) -> Result<Boundary, BoundaryError> {
        let labels = labels.unwrap_or_else(|| (1..=points.len() as i64).collect());
        let lab = |i: usize| labels.get(i).copied().unwrap_or(i as i64 + 1);
        if points.is_empty() || loops.is_empty() {
            return Err(BoundaryError::Empty);
        }
        let total: usize = loops.iter().map(Vec::len).sum();
        let mut owner: Vec<Option<(usize, usize)>> = vec![None; points.len()];
        for (li, l) in loops.iter().enumerate() {
            if l.len() < 3 {
                if total < 4 {
                    return Err(BoundaryError::TooFewNodes { count: total });
                }
                return Err(BoundaryError::LoopTooShort {
                    loop_index: li,
                    nodes: l.len(),
                });
            }
            for (k, &i) in l.iter().enumerate() {
                let Some(slot) = owner.get_mut(i) else {
                    return Err(BoundaryError::BadSegmentIndex {
                        segment: 0,
                        node: i as i64,
                    });
                };
                if let Some((lj, _)) = *slot {
                    // One node used twice: the loops touch there.
                    return Err(BoundaryError::NodesCoincide {
                        loop_a: li,
                        node_a: lab(i),
                        loop_b: lj,
                        node_b: lab(i),
                    });
                }
                *slot = Some((li, k));
            }
        }
        let used = || loops.iter().flatten().copied();
        if let Some(i) = used().find(|&i| !points[i].is_finite()) {
            return Err(BoundaryError::NonFinite { node: lab(i) });
        }
        if let Some(i) = used().find(|&i| magnitude([points[i]]) > MAX_COORDINATE) {
            return Err(BoundaryError::TooLarge {
                node: lab(i),
                value: magnitude([points[i]]),
            });
        }
        if total < 4 {
            return Err(BoundaryError::TooFewNodes { count: total });
        }
        if total % 2 == 1 {
            return Err(BoundaryError::OddNodeCount { count: total });
        }
        let bb = Aabb::of(used().map(|i| points[i])).ok_or(BoundaryError::Empty)?;
        let extent = bb.size().max_element();
        // A zero extent is one position repeated: reported below.
        if extent > 0.0 && extent < MIN_EXTENT {
            return Err(BoundaryError::TooSmall { extent });
        }
        for (li, l) in loops.iter().enumerate() {
            for k in 0..l.len() {
                let (a, b) = (l[k], l[(k + 1) % l.len()]);
                if same_point(points[a], points[b])
                    || points[a].distance(points[b]) < DUPLICATE_RATIO * extent
                {
                    return Err(BoundaryError::DuplicateNode {
                        loop_index: li,
                        node: lab(b),
                    });
                }
            }
        }
        check_coincident(&points, &loops, &owner, &labels)?;
        let areas: Vec<f64> = loops
            .iter()
            .map(|l| local_area(l.iter().map(|&i| points[i])))
            .collect();
        for (li, l) in loops.iter().enumerate() {
            let ext =
                Aabb::of(l.iter().map(|&i| points[i])).map_or(0.0, |b| b.size().max_element());
            // Below this the sum is rounding noise and its sign means nothing.
            let noise = 4.0 * l.len() as f64 * f64::EPSILON * ext * ext;
            if areas[li].abs() <= noise {
                // A loop that crosses itself (a bow-tie) can enclose no
                // net area: its crossing is what to fix, so it is named.
                check_crossings(&points, &loops, &owner, &labels)?;
                return Err(BoundaryError::ZeroArea { loop_index: li });
            }
        }
        check_crossings(&points, &loops, &owner, &labels)?;
        // Simple loops now: the orientation is exactly that of the corner
        // at the lowest-leftmost node (never flat, or the loop would fold
        // back there).
        let ccw: Vec<bool> = loops
            .iter()
            .map(|l| {
                let n = l.len();
                let k = (0..n)
                    .min_by(|&a, &b| lex(points[l[a]], points[l[b]]))
                    .unwrap_or(0);
                orient(
                    points[l[(k + n - 1) % n]],
                    points[l[k]],
                    points[l[(k + 1) % n]],
                ) > 0.0
            })
            .collect();
        let outer = (0..loops.len())
            .max_by(|&a, &b| areas[a].abs().total_cmp(&areas[b].abs()))
            .unwrap_or(0);
        let polys: Vec<Vec<Point>> = loops
            .iter()
            .map(|l| l.iter().map(|&i| points[i]).collect())
            .collect();
        let boxes: Vec<Aabb> = polys
            .iter()
            .map(|p| {
                Aabb::of(p.iter().copied()).unwrap_or(Aabb {
                    min: Point::ZERO,
                    max: Point::ZERO,
                })
            })
            .collect();
        let in_box = |p: Point, b: &Aabb| p.cmpge(b.min).all() && p.cmple(b.max).all();
        for (li, l) in loops.iter().enumerate() {
            if li == outer {
                continue;
            }
            // Loops neither cross nor touch, so one node decides inside or
            // outside.
            let p = points[l[0]];
            if !in_box(p, &boxes[outer]) || !inside(p, &polys[outer]) {
                return Err(BoundaryError::HoleOutside { loop_index: li });
            }
            for (hj, hp) in polys.iter().enumerate() {
                if hj != li && hj != outer && in_box(p, &boxes[hj]) && inside(p, hp) {
                    return Err(BoundaryError::NestedHole {
                        loop_index: li,
                        hole: hj,
                    });
                }
            }
        }
        let mut ordered = Vec::with_capacity(loops.len());
        for (li, mut l) in loops.into_iter().enumerate() {
            if (li == outer) != ccw[li] {
                l.reverse();
            }
            if li == outer {
                ordered.insert(0, l);
            } else {
                ordered.push(l);
            }
        }
        Ok(Boundary {
            points,
            loops: ordered,
            labels,
        })
    }

    /// A unit square with `n` equal segments per side (a test and
    /// benchmark domain).
    pub fn unit_square(n: usize) -> Boundary {
        let n = n.max(1);
        let t = |k: usize| k as f64 / n as f64;
        let mut pts = Vec::with_capacity(4 * n);
        pts.extend((0..n).map(|k| Point::new(t(k), 0.0)));
        pts.extend((0..n).map(|k| Point::new(1.0, t(k))));
        pts.extend((0..n).map(|k| Point::new(1.0 - t(k), 1.0)));
        pts.extend((0..n).map(|k| Point::new(0.0, 1.0 - t(k))));
        let ids = (0..pts.len()).collect();
        let labels = (1..=pts.len() as i64).collect();
        Boundary {
            points: pts,
            loops: vec![ids],
            labels,
        }
    }

    /// Total number of boundary nodes.
    pub fn node_count(&self) -> usize {
        self.loops.iter().map(Vec::len).sum()
    }

    /// Area of the domain (outer loop less the holes).
    pub fn area(&self) -> f64 {
        self.loops
            .iter()
            .map(|l| polygon_area(l.iter().map(|&i| self.points[i])))
            .sum()
    }

    /// The directed boundary segments, loop by loop.
    pub fn segments(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.loops
            .iter()
            .flat_map(|l| (0..l.len()).map(move |k| (l[k], l[(k + 1) % l.len()])))
    }

    /// The same boundary moved next to the origin, and the offset to add
    /// back. Per axis the offset is the smallest coordinate when every
    /// coordinate minus it is exact (always so when the coordinates lie
    /// within a factor 2 of it, Sterbenz's lemma: a domain far from the
    /// origin), zero otherwise. Geometry is then computed at the domain's
    /// own scale, and a domain moved by an offset that keeps its
    /// coordinates exact meshes to the same local coordinates.
    pub fn to_local(&self) -> (Boundary, Point) {
        let o = self.local_origin();
        let mut local = self.clone();
        for p in &mut local.points {
            *p -= o;
        }
        (local, o)
    }

    /// What [`Boundary::to_local`] moves the boundary by (subtracts from
    /// its coordinates), without moving it: its smallest coordinates, each
    /// where subtracting it is exact for every node, else zero.
    pub fn local_origin(&self) -> Point {
        let bb = self.bbox();
        let exact = |o: f64, v: f64| two_sum_error(v, -o) == 0.0;
        let axis = |o: f64, get: fn(&Point) -> f64| {
            if o != 0.0 && self.points.iter().all(|p| exact(o, get(p))) {
                o
            } else {
                0.0
            }
        };
        Point::new(axis(bb.min.x, |p| p.x), axis(bb.min.y, |p| p.y))
    }

    /// Bounding box of all nodes.
    pub fn bbox(&self) -> Aabb {
        Aabb::of(self.points.iter().copied()).unwrap_or(Aabb {
            min: Point::ZERO,
            max: Point::ZERO,
        })
    }

    /// Median boundary segment length: the nominal element size.
    pub fn median_segment(&self) -> f64 {
        let mut l: Vec<f64> = self
            .segments()
            .map(|(a, b)| self.points[a].distance(self.points[b]))
            .collect();
        l.sort_by(f64::total_cmp);
        l.get(l.len() / 2).copied().unwrap_or(0.0)
    }
}

/// Chains undirected segments into closed loops, in the order of first
/// appearance. Each node must join exactly two segments.
pub fn loops_from_segments(
    n_nodes: usize,
    segments: &[(usize, usize)],
    labels: &[i64],
) -> Result<Vec<Vec<usize>>, BoundaryError> {
    let lab = |i: usize| labels.get(i).copied().unwrap_or(i as i64 + 1);
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n_nodes];
    for (k, &(a, b)) in segments.iter().enumerate() {
        if let Some(&bad) = [a, b].iter().find(|&&i| i >= n_nodes) {
            return Err(BoundaryError::BadSegmentIndex {
                segment: k + 1,
                node: bad as i64,
            });
        }
        adj[a].push(b);
        adj[b].push(a);
    }
    for (i, a) in adj.iter().enumerate() {
        match a.len() {
            0 | 2 => {}
            1 => return Err(BoundaryError::OpenChain { node: lab(i) }),
            d => {
                return Err(BoundaryError::Branching {
                    node: lab(i),
                    degree: d,
                })
            }
        }
    }
    let mut seen = vec![false; n_nodes];
    let mut loops = Vec::new();
    for &(start, second) in segments {
        if seen[start] {
            continue;
        }
        let mut l = vec![start];
        seen[start] = true;
        let (mut prev, mut cur) = (start, second);
        while cur != start {
            if seen[cur] {
                return Err(BoundaryError::Branching {
                    node: lab(cur),
                    degree: adj[cur].len(),
                });
            }
            seen[cur] = true;
            l.push(cur);
            let nx = if adj[cur][0] == prev {
                adj[cur][1]
            } else {
                adj[cur][0]
            };
            prev = cur;
            cur = nx;
        }
        loops.push(l);
    }
    Ok(loops)
}

/// Lexicographic order of points, x then y (`-0` equal to `0`).
fn lex(a: Point, b: Point) -> Ordering {
    let c = |u: f64, v: f64| u.partial_cmp(&v).unwrap_or(Ordering::Equal);
    c(a.x, b.x).then(c(a.y, b.y))
}

/// `2^k` for `-1074 <= k <= 1023`, exactly.
fn pow2(k: i32) -> f64 {
    if k >= -1022 {
        f64::from_bits(((k + 1023) as u64) << 52)
    } else {
        f64::from_bits(1u64 << (k + 1074).max(0))
    }
}

/// The binary exponent of a magnitude (`2^e <= m < 2^(e+1)`), subnormals
/// and zero counted as -1022.
fn binade(m: f64) -> i32 {
    let e = ((m.to_bits() >> 52) & 0x7ff) as i32;
    if e == 0 {
        -1022
    } else {
        e - 1023
    }
}

/// Refuses two distinct nodes at the same position up to rounding
/// ([`same_point`]). Nodes are hashed into cells a little larger than
/// their tolerance (one grid per binade of the coordinates' magnitude),
/// so each node is compared with the few nodes of the cells around it.
fn check_coincident(
    points: &[Point],
    loops: &[Vec<usize>],
    owner: &[Option<(usize, usize)>],
    labels: &[i64],
) -> Result<(), BoundaryError> {
    let lab = |i: usize| labels.get(i).copied().unwrap_or(i as i64 + 1);
    let lp = |i: usize| owner[i].map_or(0, |o| o.0);
    // A node of binade e has a tolerance under 2^(e-48): cells of that
    // side at level e hold every node within tolerance of it in the 3 × 3
    // cells around its own, once nodes are filed at their own level and
    // the next (the tolerance of a pair is that of its larger node).
    let cell = |p: Point, level: i32| {
        let c = pow2(level - 48);
        ((p.x / c).floor() as i64, (p.y / c).floor() as i64)
    };
    let mut grid: std::collections::HashMap<(i32, i64, i64), Vec<usize>> =
        std::collections::HashMap::new();
    for &v in loops.iter().flatten() {
        let p = points[v];
        let e = binade(magnitude([p]));
        for level in [e, e + 1] {
            let (cx, cy) = cell(p, level);
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let Some(list) = grid.get(&(level, cx + dx, cy + dy)) else {
                        continue;
                    };
                    if let Some(&u) = list.iter().find(|&&u| same_point(points[u], p)) {
                        return Err(BoundaryError::NodesCoincide {
                            loop_a: lp(v),
                            node_a: lab(v),
                            loop_b: lp(u),
                            node_b: lab(u),
                        });
                    }
                }
            }
        }
        for level in [e, e + 1] {
            let (cx, cy) = cell(p, level);
            grid.entry((level, cx, cy)).or_default().push(v);
        }
    }
    Ok(())
}

/// A segment of the sweep: its nodes in loop order, and its ends in sweep
/// order (`lo` before `hi`).
#[derive(Clone, Copy)]
struct Seg {
    from: usize,
    to: usize,
    lo: usize,
    hi: usize,
}

/// What a sweep found.
enum Hit {
    FoldBack { node: usize },
    NodeOnSegment { node: usize, seg: usize },
    Crossing { s: usize, t: usize },
}

/// True when node position `p` lies on the segment `a–b` up to rounding.
fn near(p: Point, a: Point, b: Point) -> bool {
    crate::geom::point_segment_distance(p, a, b) <= TOUCH_EPS * magnitude([p, a, b])
}

/// True when `p`, collinear with `a–b`, lies within the closed segment.
fn within(p: Point, a: Point, b: Point) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// Segments `s` and `t` clash: they cross or overlap, one's node touches
/// the other (exactly or up to rounding), or, when consecutive, they fold
/// back on each other.
fn clash(pts: &[Point], segs: &[Seg], s: usize, t: usize) -> Option<Hit> {
    let (u, v) = (segs[s], segs[t]);
    let shared = if u.to == v.from {
        Some((u.to, u.from, v.to))
    } else if v.to == u.from {
        Some((u.from, u.to, v.from))
    } else {
        None
    };
    if let Some((w, p, r)) = shared {
        // Consecutive: they meet at w; p and r are their other ends.
        let (pw, pp, pr) = (pts[w], pts[p], pts[r]);
        let same_side = |a: f64, b: f64, c: f64| (a - c).signum() == (b - c).signum();
        if orient(pp, pw, pr) == 0.0 && same_side(pp.x, pr.x, pw.x) && same_side(pp.y, pr.y, pw.y) {
            return Some(Hit::FoldBack { node: w });
        }
        if near(pr, pp, pw) {
            return Some(Hit::NodeOnSegment { node: r, seg: s });
        }
        if near(pp, pw, pr) {
            return Some(Hit::NodeOnSegment { node: p, seg: t });
        }
        return None;
    }
    let ends = [(u.from, t, v), (u.to, t, v), (v.from, s, u), (v.to, s, u)];
    let (a, b, c, d) = (pts[u.from], pts[u.to], pts[v.from], pts[v.to]);
    if segments_intersect(a, b, c, d) {
        for (node, seg, o) in ends {
            let (p, x, y) = (pts[node], pts[o.from], pts[o.to]);
            if orient(x, y, p) == 0.0 && within(p, x, y) {
                return Some(Hit::NodeOnSegment { node, seg });
            }
        }
        return Some(Hit::Crossing {
            s: s.min(t),
            t: s.max(t),
        });
    }
    ends.into_iter()
        .find(|&(node, _, o)| near(pts[node], pts[o.from], pts[o.to]))
        .map(|(node, seg, _)| Hit::NodeOnSegment { node, seg })
}

/// One sweep of a vertical line over the nodes in lexicographic order
/// (Shamos and Hoey): the segments the line cuts are kept in order from
/// bottom to top, and each pair that becomes neighbours there is checked
/// ([`clash`]), as is each node against the segments just above and below
/// it. If any two segments cross or touch, some such pair does before the
/// line passes the first crossing, so every crossing and exact touching is
/// found; comparisons are exact, so the order never breaks before it is.
fn sweep(pts: &[Point], segs: &[Seg], incident: &[[usize; 2]], nodes: &[usize]) -> Option<Hit> {
    let mut order = nodes.to_vec();
    order.sort_by(|&a, &b| lex(pts[a], pts[b]));
    let mut status: Vec<usize> = Vec::new();
    for &v in &order {
        let p = pts[v];
        let own = incident[v];
        // Where p falls: status[..lo] below it, status[lo..hi] through it.
        let side = |t: usize| {
            let o = orient(pts[segs[t].lo], pts[segs[t].hi], p);
            if o > 0.0 {
                Ordering::Less
            } else if o < 0.0 {
                Ordering::Greater
            } else {
                Ordering::Equal
            }
        };
        let lo = status.partition_point(|&t| side(t) == Ordering::Less);
        let hi = lo + status[lo..].partition_point(|&t| side(t) == Ordering::Equal);
        if let Some(&t) = status[lo..hi].iter().find(|t| !own.contains(t)) {
            return Some(Hit::NodeOnSegment { node: v, seg: t });
        }
        if hi - lo == 2 {
            if let Some(h) = clash(pts, segs, status[lo], status[lo + 1]) {
                return Some(h);
            }
        }
        status.drain(lo..hi);
        let mut starting: Vec<usize> = own.iter().copied().filter(|&s| segs[s].lo == v).collect();
        if let [s1, s2] = starting[..] {
            if let Some(h) = clash(pts, segs, s1, s2) {
                return Some(h);
            }
            // Lower one first: s2 is above s1 when it turns left of it.
            if orient(p, pts[segs[s1].hi], pts[segs[s2].hi]) < 0.0 {
                starting.swap(0, 1);
            }
        }
        let k = starting.len();
        status.splice(lo..lo, starting);
        let below = lo.checked_sub(1).map(|i| status[i]);
        let above = status.get(lo + k).copied();
        let pairs = if k == 0 {
            [below.zip(above), None]
        } else {
            [
                below.map(|b| (b, status[lo])),
                above.map(|a| (status[lo + k - 1], a)),
            ]
        };
        for (s, t) in pairs.into_iter().flatten() {
            if let Some(h) = clash(pts, segs, s, t) {
                return Some(h);
            }
        }
        for t in [below, above].into_iter().flatten() {
            let q = segs[t];
            if near(p, pts[q.from], pts[q.to]) {
                return Some(Hit::NodeOnSegment { node: v, seg: t });
            }
        }
    }
    None
}

/// Reports the first pair of segments that cross, touch or overlap, other
/// than consecutive segments meeting at their shared node, and any node
/// lying on a segment it does not end, exactly or up to rounding.
///
/// Two sweeps, along x and along y: the first finds every exact crossing
/// and touching; a node within rounding of a segment is found by the sweep
/// in which the segment passes it at a distance (along the sweep line) of
/// the same order. `O(n log n)` time, `O(n)` memory.
fn check_crossings(
    points: &[Point],
    loops: &[Vec<usize>],
    owner: &[Option<(usize, usize)>],
    labels: &[i64],
) -> Result<(), BoundaryError> {
    let lab = |i: usize| labels.get(i).copied().unwrap_or(i as i64 + 1);
    let lp = |i: usize| owner[i].map_or(0, |o| o.0);
    let mut segs = Vec::new();
    // Each node's segments: the one into it and the one out of it.
    let mut incident = vec![[usize::MAX; 2]; points.len()];
    for l in loops {
        let (first, n) = (segs.len(), l.len());
        for k in 0..n {
            let (a, b) = (l[k], l[(k + 1) % n]);
            incident[a] = [first + (k + n - 1) % n, first + k];
            segs.push(Seg {
                from: a,
                to: b,
                lo: a,
                hi: b,
            });
        }
    }
    let nodes: Vec<usize> = loops.iter().flatten().copied().collect();
    let along_y: Vec<Point> = points.iter().map(|p| Point::new(p.y, -p.x)).collect();
    for pts in [points, &along_y[..]] {
        for s in &mut segs {
            let (a, b) = (s.from, s.to);
            (s.lo, s.hi) = if lex(pts[a], pts[b]) == Ordering::Greater {
                (b, a)
            } else {
                (a, b)
            };
        }
        let hit = sweep(pts, &segs, &incident, &nodes);
        let seg_of = |s: usize| (lp(segs[s].from), lab(segs[s].from), lab(segs[s].to));
        match hit {
            None => {}
            Some(Hit::FoldBack { node }) => {
                return Err(BoundaryError::FoldBack {
                    loop_index: lp(node),
                    node: lab(node),
                })
            }
            Some(Hit::NodeOnSegment { node, seg }) => {
                let (loop_b, from, to) = seg_of(seg);
                return Err(BoundaryError::NodeOnSegment {
                    loop_a: lp(node),
                    node: lab(node),
                    loop_b,
                    from,
                    to,
                });
            }
            Some(Hit::Crossing { s, t }) => {
                return Err(BoundaryError::Crossing {
                    loop_a: seg_of(s).0,
                    node_a: seg_of(s).1,
                    loop_b: seg_of(t).0,
                    node_b: seg_of(t).1,
                })
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(n: usize) -> (Vec<Point>, Vec<usize>) {
        let mut pts = Vec::new();
        for k in 0..n {
            pts.push(Point::new(k as f64 / n as f64, 0.0));
        }
        for k in 0..n {
            pts.push(Point::new(1.0, k as f64 / n as f64));
        }
        for k in 0..n {
            pts.push(Point::new(1.0 - k as f64 / n as f64, 1.0));
        }
        for k in 0..n {
            pts.push(Point::new(0.0, 1.0 - k as f64 / n as f64));
        }
        let l = (0..pts.len()).collect();
        (pts, l)
    }

    #[test]
    fn clockwise_outer_is_reoriented() {
        let (pts, mut l) = square(2);
        l.reverse();
        let b = Boundary::new(pts, vec![l], None).unwrap();
        assert!(b.area() > 0.99 && b.area() < 1.01);
    }

    #[test]
    fn odd_count_is_refused() {
        let (mut pts, _) = square(2);
        pts.pop();
        let l = (0..pts.len()).collect();
        assert_eq!(
            Boundary::new(pts, vec![l], None),
            Err(BoundaryError::OddNodeCount { count: 7 })
        );
    }

    #[test]
    fn crossing_names_the_loops() {
        let p = |x, y| Point::new(x, y);
        let pts = vec![p(0., 0.), p(2., 2.), p(2., 0.), p(0., 1.)];
        let e = Boundary::new(pts, vec![vec![0, 1, 2, 3]], None).unwrap_err();
        assert!(
            matches!(
                e,
                BoundaryError::Crossing {
                    loop_a: 0,
                    loop_b: 0,
                    ..
                }
            ),
            "{e:?}"
        );
    }

    /// Every pair of segments and of nodes checked directly: what the
    /// sweeps must agree with.
    fn brute_force(points: &[Point], loops: &[Vec<usize>]) -> bool {
        let nodes: Vec<usize> = loops.iter().flatten().copied().collect();
        for (i, &a) in nodes.iter().enumerate() {
            if nodes[i + 1..]
                .iter()
                .any(|&b| same_point(points[a], points[b]))
            {
                return false;
            }
        }
        let mut segs = Vec::new();
        for l in loops {
            for k in 0..l.len() {
                let (a, b) = (l[k], l[(k + 1) % l.len()]);
                segs.push(Seg {
                    from: a,
                    to: b,
                    lo: a,
                    hi: b,
                });
            }
        }
        for s in 0..segs.len() {
            for t in s + 1..segs.len() {
                if clash(points, &segs, s, t).is_some() {
                    return false;
                }
            }
        }
        true
    }

    fn sweeps_accept(points: &[Point], loops: &[Vec<usize>]) -> bool {
        let mut owner = vec![None; points.len()];
        for (li, l) in loops.iter().enumerate() {
            for (k, &i) in l.iter().enumerate() {
                owner[i] = Some((li, k));
            }
        }
        let labels: Vec<i64> = (1..=points.len() as i64).collect();
        check_coincident(points, loops, &owner, &labels).is_ok()
            && check_crossings(points, loops, &owner, &labels).is_ok()
    }

    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn below(&mut self, n: u64) -> u64 {
            self.next() % n
        }
    }

    /// Random loops on a small integer grid: crossings, touchings,
    /// overlaps, vertical and collinear runs galore, all exact.
    fn random_loops(g: &mut Rng) -> (Vec<Point>, Vec<Vec<usize>>) {
        let mut points = Vec::new();
        let mut loops = Vec::new();
        for _ in 0..1 + g.below(3) {
            let n = 3 + g.below(6) as usize;
            let start = points.len();
            for _ in 0..n {
                points.push(Point::new(g.below(7) as f64, g.below(7) as f64));
            }
            loops.push((start..start + n).collect());
        }
        (points, loops)
    }

    #[test]
    fn sweeps_agree_with_checking_every_pair() {
        let mut g = Rng(0x9E37_79B9_7F4A_7C15);
        let (mut valid, mut invalid) = (0, 0);
        for case in 0..20000 {
            let (points, loops) = random_loops(&mut g);
            // Consecutive repeats are refused before the sweeps.
            if loops.iter().any(|l| {
                (0..l.len()).any(|k| same_point(points[l[k]], points[l[(k + 1) % l.len()]]))
            }) {
                continue;
            }
            let expected = brute_force(&points, &loops);
            assert_eq!(
                sweeps_accept(&points, &loops),
                expected,
                "case {case}: {points:?} {loops:?}"
            );
            // The same shapes moved far away and turned a quarter: exact
            // transforms, the same verdict.
            let moved: Vec<Point> = points
                .iter()
                .map(|p| Point::new(-p.y * 0.5 + 1e6, p.x * 0.5 - 3e5))
                .collect();
            assert_eq!(sweeps_accept(&moved, &loops), expected, "case {case} moved");
            if expected {
                valid += 1;
            } else {
                invalid += 1;
            }
        }
        assert!(valid > 500 && invalid > 500, "{valid} {invalid}");
    }

    #[test]
    fn a_node_on_a_segment_up_to_rounding_is_refused() {
        // Regular polygons of 8 to 40 nodes, turned by random angles and
        // moved far out; one node is moved onto the rounded midpoint of a
        // segment across the polygon, its neighbours giving a spike.
        let mut g = Rng(77);
        for case in 0..500 {
            let n = 8 + 2 * g.below(17) as usize;
            let turn = g.below(1000) as f64 * 0.00628;
            let offset = Point::new(
                (g.below(2000) as f64 - 1000.0) * 10f64.powi(g.below(9) as i32),
                (g.below(2000) as f64 - 1000.0) * 10f64.powi(g.below(9) as i32),
            );
            let mut pts: Vec<Point> = (0..n)
                .map(|k| {
                    let a = turn + std::f64::consts::TAU * k as f64 / n as f64;
                    offset + Point::new(a.cos(), a.sin())
                })
                .collect();
            // The valid polygon first.
            let l: Vec<usize> = (0..n).collect();
            assert!(sweeps_accept(&pts, std::slice::from_ref(&l)), "case {case}");
            assert!(brute_force(&pts, std::slice::from_ref(&l)), "case {case}");
            // Node n/2 onto the midpoint of segment 0–1.
            let m = (pts[0] + pts[1]) * 0.5;
            pts[n / 2] = m;
            let b = Boundary::new(pts.clone(), vec![l.clone()], None);
            assert!(
                matches!(
                    b,
                    Err(BoundaryError::NodeOnSegment { .. } | BoundaryError::Crossing { .. })
                ),
                "case {case}: {b:?}"
            );
        }
    }

    #[test]
    fn validation_is_relative_to_the_coordinates_magnitude() {
        let rect = |w: f64, h: f64, o: Point| {
            vec![
                o,
                o + Point::new(w, 0.0),
                o + Point::new(w, h),
                o + Point::new(0.0, h),
            ]
        };
        let l = vec![vec![0, 1, 2, 3]];
        for (w, h, o) in [
            (1000.0, 1.0, Point::ZERO),
            (1.0, 1e-4, Point::ZERO),
            (1.0, 1.0, Point::splat(1e8)),
            (1e-3, 1.0, Point::new(-5e7, 3e7)),
            (1e120, 1e120, Point::ZERO),
            (1e-120, 1e-120, Point::ZERO),
        ] {
            let b = Boundary::new(rect(w, h, o), l.clone(), None)
                .unwrap_or_else(|e| panic!("{w} × {h} at {o}: {e}"));
            assert!(b.loops[0].len() == 4);
        }
        // A segment shorter than rounding at its magnitude is a repeat.
        let e = Boundary::new(rect(1.0, 1e-9, Point::splat(1e8)), l.clone(), None).unwrap_err();
        assert!(matches!(e, BoundaryError::DuplicateNode { .. }), "{e}");
        // Coordinates whose squares overflow, extents whose squares underflow.
        let e = Boundary::new(rect(1e308, 1e308, Point::ZERO), l.clone(), None).unwrap_err();
        assert!(matches!(e, BoundaryError::TooLarge { node: 2, .. }), "{e}");
        let e = Boundary::new(rect(1e-200, 1e-200, Point::ZERO), l, None).unwrap_err();
        assert!(matches!(e, BoundaryError::TooSmall { .. }), "{e}");
    }

    #[test]
    fn a_thin_annulus_far_away_is_valid() {
        // 0.004 wide, at 1e8: areas summed relative to each loop.
        let n = 64;
        let o = Point::splat(1e8);
        let ring = |r: f64| -> Vec<Point> {
            (0..n)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / n as f64;
                    o + r * Point::new(a.cos(), a.sin())
                })
                .collect()
        };
        let mut pts = ring(1.0);
        pts.extend(ring(0.996));
        let loops = vec![(0..n).collect(), (n..2 * n).collect()];
        let b = Boundary::new(pts, loops, None).unwrap();
        assert_eq!(b.loops.len(), 2);
    }

    #[test]
    fn a_long_spiked_sunburst_validates_quickly() {
        // 20,000 nodes: 10,000 spikes from radius 0.05 to 1, every segment
        // long; the crossing check must not compare them all.
        let n = 10_000;
        let mut pts = Vec::with_capacity(2 * n);
        for k in 0..n {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            pts.push(Point::new(a.cos(), a.sin()));
            let b = a + std::f64::consts::PI / n as f64;
            pts.push(0.05 * Point::new(b.cos(), b.sin()));
        }
        let t = std::time::Instant::now();
        let b = Boundary::new(pts, vec![(0..2 * n).collect()], None).unwrap();
        assert_eq!(b.node_count(), 20_000);
        assert!(t.elapsed().as_secs_f64() < 1.0, "{:?}", t.elapsed());
    }

    #[test]
    fn chaining_detects_branches_and_open_chains() {
        let labels = [1, 2, 3, 4, 5];
        assert!(matches!(
            loops_from_segments(4, &[(0, 1), (1, 2), (2, 3)], &labels),
            Err(BoundaryError::OpenChain { .. })
        ));
        assert!(matches!(
            loops_from_segments(5, &[(0, 1), (1, 2), (2, 3), (3, 0), (2, 4)], &labels),
            Err(BoundaryError::Branching { node: 3, degree: 3 })
                | Err(BoundaryError::OpenChain { .. })
        ));
        let l = loops_from_segments(4, &[(2, 3), (0, 1), (3, 0), (1, 2)], &labels).unwrap();
        assert_eq!(l, vec![vec![2, 3, 0, 1]]);
    }
}

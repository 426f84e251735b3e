//! Region fill: the last-resort closure of whatever front is left when
//! extraction, seams, chord splits, relaxation and rip-up cannot go on.
//!
//! The thesis closes a loop by extraction down to 4 or 6 nodes (method §2.7,
//! thesis Figure 20) and leaves a front that can no longer be reduced to a
//! failure. quadex instead fills the remaining region with a construction
//! that keeps every front node and edge and needs only an even node count per
//! loop, which element extraction preserves. Loops that are all
//! counter-clockwise bound regions of their own and are filled one by one.
//!
//! **Quadrangulation** (shared by both constructions below). A constrained
//! Delaunay triangulation (spade) of the region, refined inside with a 25°
//! angle limit and a size taken from the front edges (triangles of up to
//! four squared mean front edges, so that the quads are about as wide as
//! the front's edges all through the region). Neighbouring triangles
//! are paired into quads, best pair first, where the pair's scaled Jacobian
//! is at least [`MIN_PAIR_SJ`]; every cell (pair or lone triangle) is then
//! cut into quads through its centre and edge midpoints (a quad into four,
//! a triangle into three), so the result is all-quad whatever the pairing.
//!
//! 1. **Direct.** Every second front node (both parities are tried, the one
//!    with the better worst quad wins) makes a coarse loop whose edges skip
//!    one front node each. The coarse region is quadrangulated, and each
//!    coarse edge takes its skipped front node as the midpoint, so the quads
//!    meet the front edge for edge.
//! 2. **Ring** (when no direct fill is valid). Every front node `p_i` gets
//!    an inner node `q_i` on the bisector of its front angle. The radial edge
//!    `p_i q_i` is split by a node `r_i` at every second node, so each cell
//!    `p_i p_{i+1} q_{i+1} q_i` has six sides (its inner side gets a node
//!    `m_i`) and is cut into two quads. The inner loops `q` are
//!    quadrangulated; on an inner-loop edge the midpoint is `m_i`, moved a
//!    little towards the cell's centre so that the ring quad beside it stays
//!    strictly convex. The ring height is tried at decreasing scales.
//!
//! Where a construction leaves a few new quads folded (a triangle's centre
//! that cannot serve a front corner beside a zigzag of the front), the new
//! nodes of those quads are moved to where their worst quad is best, the
//! front fixed, before the check below.
//!
//! A fill is accepted only when every new quad is measurably convex and
//! every front edge is the side of one quad and every other side of two; the
//! result is then a valid tiling of the region (the new quads are all
//! positively oriented and their boundary is the front). Smoothing
//! afterwards evens the element sizes out.

use std::collections::BTreeMap;

use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use crate::front::EdgeGrid;
use crate::geom::{ccw_angle, is_strictly_convex, Aabb, Point};
use crate::smooth::{search, SearchSteps, SEARCH_MARGIN};
use crate::spade_guard::guarded;

/// The quads that fill a region, over the existing nodes (ids below
/// `first_new`) and the new nodes `points` (id `first_new + k`).
#[derive(Clone, Debug, PartialEq)]
pub struct RegionFill {
    pub first_new: u32,
    pub points: Vec<Point>,
    pub quads: Vec<[u32; 4]>,
}

impl RegionFill {
    /// An empty fill over `nodes`, to be built.
    fn new(nodes: &[Point]) -> RegionFill {
        RegionFill {
            first_new: nodes.len() as u32,
            points: Vec::new(),
            quads: Vec::new(),
        }
    }

    /// Adds a new node; returns its id.
    fn add(&mut self, p: Point) -> u32 {
        self.points.push(p);
        self.first_new + self.points.len() as u32 - 1
    }

    /// The position of node `v`, existing or new.
    fn at(&self, v: u32, nodes: &[Point]) -> Point {
        if v < self.first_new {
            nodes[v as usize]
        } else {
            self.points[(v - self.first_new) as usize]
        }
    }

    /// The smallest scaled Jacobian of the fill's quads.
    pub fn min_scaled_jacobian(&self, nodes: &[Point]) -> f64 {
        self.quads
            .iter()
            .map(|q| crate::quality::Shape::of(q.map(|v| self.at(v, nodes))).scaled_jacobian)
            .fold(f64::INFINITY, f64::min)
    }
}

/// Why a region could not be filled.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FillError {
    #[error("front loop {loop_index} has {len} nodes; a fill needs an even count of at least 4")]
    OddLoop { loop_index: usize, len: usize },
    #[error("the front has no usable edge length")]
    NoSize,
    #[error("the ring's inner loops cross each other")]
    Crossing,
    #[error("a ring edge crosses the front or another ring edge")]
    RingCrossing,
    #[error("the inner edge after node {node} borders no triangle of the region")]
    Unbordered { node: u32 },
    #[error("a new quad at node {node} would not be strictly convex")]
    NotConvex { node: u32 },
    #[error("the region's triangulation failed on nearly degenerate input")]
    Triangulation,
}

/// Smallest new quad area, as a fraction of the squared mean front edge (and
/// never below 1e-12 of the squared coordinate magnitude, so that a shoelace
/// sum over absolute coordinates still sees it positive).
const MIN_AREA: f64 = 1e-7;

/// Two triangles of the region's triangulation become one cell (split into
/// four quads) when the quad they form has at least this scaled Jacobian.
const MIN_PAIR_SJ: f64 = 0.5;

/// Largest triangle of the refined triangulation, in squared front edge
/// lengths. A triangle becomes three quads and a pair of triangles four, so
/// the quads come out about one front edge wide, the size of the elements
/// extraction cuts along the boundary, however large the region.
const CELL_AREA: f64 = 4.0;

/// Ring heights tried, as fractions of the room at a node: its shorter
/// front edge (longer where the front angle is sharp) or its distance to the
/// nearest other front edge, whichever is less.
const RING_SCALES: [f64; 7] = [0.45, 0.3, 0.2, 0.12, 0.06, 0.03, 0.01];

/// Fills the region bounded by `loops` (node ids in `nodes`; the region lies
/// to the left of every loop, as on the front). Every loop must have an even
/// number of nodes. Fails, with the reason of the last try, when no ring
/// height gives a valid fill.
pub fn fill_region(loops: &[Vec<u32>], nodes: &[Point]) -> Result<RegionFill, FillError> {
    let area = |l: &Vec<u32>| crate::geom::polygon_area(l.iter().map(|&v| nodes[v as usize]));
    let odd = loops.iter().filter(|l| l.len() % 2 == 1).count();
    if odd >= 2 && odd % 2 == 0 && loops.iter().any(|l| l.len() >= 3 && area(l) < 0.0) {
        // One region with odd loops (triangular holes): join them in pairs
        // by corridors of quads, then fill what is left.
        let mut joined = RegionFill::new(nodes);
        let mut loops = loops.to_vec();
        while let Some(i) = loops.iter().position(|l| l.len() % 2 == 1) {
            let all: Vec<Point> = nodes.iter().chain(&joined.points).copied().collect();
            let merged = join_odd(&mut loops, i, &all, &mut joined)?;
            loops[i] = merged.0;
            loops.remove(merged.1);
        }
        let all: Vec<Point> = nodes.iter().chain(&joined.points).copied().collect();
        let rest = fill_region(&loops, &all)?;
        joined.points.extend(rest.points);
        joined.quads.extend(rest.quads);
        return Ok(joined);
    }
    if let Some((loop_index, l)) = loops
        .iter()
        .enumerate()
        .find(|(_, l)| l.len() < 4 || l.len() % 2 == 1)
    {
        return Err(FillError::OddLoop {
            loop_index,
            len: l.len(),
        });
    }
    if loops.len() > 1 && loops.iter().all(|l| area(l) > 0.0) {
        // No loop is a hole, so each bounds a region of its own.
        let mut all = nodes.to_vec();
        let mut quads = Vec::new();
        for l in loops {
            let f = fill_one(std::slice::from_ref(l), &all)?;
            all.extend_from_slice(&f.points);
            quads.extend(f.quads);
        }
        return Ok(RegionFill {
            first_new: nodes.len() as u32,
            points: all.split_off(nodes.len()),
            quads,
        });
    }
    fill_one(loops, nodes)
}

/// Joins odd loop `i` to the nearest other odd loop it can reach by a
/// straight corridor of quads between two front edges facing each other
/// (`a→a'` on one, `b→b'` on the other; the corridor's sides run `a`–`b'`
/// and `a'`–`b` and are cut about one front edge apart). The two loops become
/// one, with an even node count: `n1 + n2 + 2(m − 1)` for `m` quads. Adds
/// the corridor's nodes and quads to `out`; returns the merged loop and the
/// index of the loop it absorbed.
fn join_odd(
    loops: &mut [Vec<u32>],
    i: usize,
    nodes: &[Point],
    out: &mut RegionFill,
) -> Result<(Vec<u32>, usize), FillError> {
    let at = |v: u32| nodes[v as usize];
    let edges: Vec<(Point, Point, u32, u32)> = loops
        .iter()
        .flat_map(|l| (0..l.len()).map(move |k| (l[k], l[(k + 1) % l.len()])))
        .map(|(u, v)| (at(u), at(v), u, v))
        .collect();
    let crosses = |p: Point, q: Point, ends: [u32; 4]| {
        edges.iter().any(|&(c, d, u, v)| {
            !ends.contains(&u) && !ends.contains(&v) && crate::geom::segments_intersect(p, q, c, d)
        })
    };
    let l1 = &loops[i];
    let mut best: Option<(f64, usize, usize, usize)> = None;
    for (j, l2) in loops.iter().enumerate() {
        if j == i || l2.len() % 2 == 0 {
            continue;
        }
        for k1 in 0..l1.len() {
            let (a, a2) = (l1[k1], l1[(k1 + 1) % l1.len()]);
            for k2 in 0..l2.len() {
                let (b, b2) = (l2[k2], l2[(k2 + 1) % l2.len()]);
                let (m1, m2) = (at(a).midpoint(at(a2)), at(b).midpoint(at(b2)));
                let d = m1.distance(m2);
                if best.is_some_and(|(bd, ..)| d >= bd) {
                    continue;
                }
                // Both edges face the corridor, which is convex and clear.
                let facing = (at(a2) - at(a)).perp().dot(m2 - m1) > 0.0
                    && (at(b2) - at(b)).perp().dot(m1 - m2) > 0.0;
                let ends = [a, a2, b, b2];
                let poly = [at(a), at(a2), at(b), at(b2)];
                if !facing
                    || !crate::geom::is_measurably_convex(poly)
                    || crosses(at(a), at(b2), ends)
                    || crosses(at(a2), at(b), ends)
                    || loops
                        .iter()
                        .flatten()
                        .any(|&v| !ends.contains(&v) && crate::geom::point_in_polygon(at(v), &poly))
                {
                    continue;
                }
                best = Some((d, j, k1, k2));
            }
        }
    }
    let (d, j, k1, k2) = best.ok_or(FillError::OddLoop {
        loop_index: i,
        len: loops[i].len(),
    })?;
    let (l1, l2) = (&loops[i], &loops[j]);
    let (a, a2) = (l1[k1], l1[(k1 + 1) % l1.len()]);
    let (b, b2) = (l2[k2], l2[(k2 + 1) % l2.len()]);
    let h = 0.5 * (at(a).distance(at(a2)) + at(b).distance(at(b2)));
    let m = ((d / h).round() as usize).max(1);
    // Side nodes p_t on a–b', q_t on a'–b, for t = 1..m-1.
    let mut p = vec![a];
    let mut q = vec![a2];
    for t in 1..m {
        let f = t as f64 / m as f64;
        p.push(out.add(at(a).lerp(at(b2), f)));
        q.push(out.add(at(a2).lerp(at(b), f)));
    }
    p.push(b2);
    q.push(b);
    for t in 0..m {
        out.quads.push([p[t], q[t], q[t + 1], p[t + 1]]);
    }
    // a, p_1.., b', on round loop 2 to b, q_{m-1}.., a', on round loop 1.
    let mut merged = p.clone();
    merged.extend((1..l2.len()).map(|s| l2[(k2 + 1 + s) % l2.len()]));
    merged.extend(q.iter().rev().skip(1));
    merged.extend((1..l1.len() - 1).map(|s| l1[(k1 + 1 + s) % l1.len()]));
    Ok((merged, j))
}

/// [`fill_region`] on one region: the direct quadrangulation when one of
/// its two parities gives valid quads (the one with the better worst quad),
/// else the ring.
fn fill_one(loops: &[Vec<u32>], nodes: &[Point]) -> Result<RegionFill, FillError> {
    let mut edge_sum = 0.0;
    let mut edge_count = 0usize;
    for l in loops {
        for k in 0..l.len() {
            edge_sum += nodes[l[k] as usize].distance(nodes[l[(k + 1) % l.len()] as usize]);
            edge_count += 1;
        }
    }
    let size = edge_sum / edge_count as f64;
    if !(size.is_finite() && size > 0.0) {
        return Err(FillError::NoSize);
    }
    let reach = loops
        .iter()
        .flatten()
        .map(|&v| nodes[v as usize].abs().max_element())
        .fold(0.0, f64::max);
    let min_area = (MIN_AREA * size * size).max(1e-12 * reach * reach);
    let mut last = FillError::NoSize;
    {
        let mut best: Option<(f64, RegionFill)> = None;
        for parity in [0, 1] {
            match try_direct(loops, nodes, parity, size, min_area) {
                Ok(f) => {
                    let worst = f.min_scaled_jacobian(nodes);
                    if best.as_ref().is_none_or(|(w, _)| worst > *w) {
                        best = Some((worst, f));
                    }
                }
                Err(e) => last = e,
            }
        }
        if let Some((_, f)) = best {
            return Ok(f);
        }
    }
    let clear = clearances(loops, nodes);
    for refine in [true, false] {
        for scale in RING_SCALES {
            match try_fill(loops, nodes, &clear, scale, size, min_area, refine) {
                Ok(f) => return Ok(f),
                Err(e) => last = e,
            }
        }
    }
    Err(last)
}

fn try_fill(
    loops: &[Vec<u32>],
    nodes: &[Point],
    clear: &[Vec<f64>],
    scale: f64,
    size: f64,
    min_area: f64,
    refine: bool,
) -> Result<RegionFill, FillError> {
    let mut b = RegionFill::new(nodes);
    // 1. Inner nodes q_i and split radial nodes r_i.
    let mut inner: Vec<Vec<u32>> = Vec::with_capacity(loops.len());
    let mut radial: Vec<Vec<Option<u32>>> = Vec::with_capacity(loops.len());
    for (l, clear) in loops.iter().zip(clear) {
        let n = l.len();
        let mut q = Vec::with_capacity(n);
        let mut r = Vec::with_capacity(n);
        for i in 0..n {
            let p = nodes[l[i] as usize];
            let next = nodes[l[(i + 1) % n] as usize];
            let prev = nodes[l[(i + n - 1) % n] as usize];
            let theta = ccw_angle(p, next, prev);
            let e = (next - p).normalize_or_zero();
            let (s, c) = (0.5 * theta).sin_cos();
            let dir = Point::new(e.x * c - e.y * s, e.x * s + e.y * c);
            let h = p.distance(next).min(p.distance(prev)) / s.max(0.5);
            let room = clear[i].min(clear[(i + 1) % n]).min(clear[(i + n - 1) % n]);
            let d = scale * h.min(room);
            let qi = b.add(p + dir * d);
            q.push(qi);
            r.push(if i % 2 == 1 {
                Some(b.add(p + dir * (0.5 * d)))
            } else {
                None
            });
        }
        inner.push(q);
        radial.push(r);
    }
    // 2.–4. The inner loops quadrangulated; the midpoint of an inner-loop
    // edge is a new node moved a little towards its cell's centre, so that
    // the ring quad beside it stays strictly convex.
    let mut mids: Vec<Vec<Option<u32>>> = inner.iter().map(|q| vec![None; q.len()]).collect();
    let mut index: BTreeMap<(u32, u32), (usize, usize)> = BTreeMap::new();
    for (li, q) in inner.iter().enumerate() {
        for k in 0..q.len() {
            index.insert((q[k], q[(k + 1) % q.len()]), (li, k));
        }
    }
    quadrangulate(&inner, nodes, &mut b, size, refine, |b, u, w, m, g| {
        let &(li, ki) = index.get(&(u, w))?;
        let id = b.add(m + 0.15 * (g - m));
        mids[li][ki] = Some(id);
        Some(id)
    })?;
    // Ring quads, two per front edge.
    for (li, l) in loops.iter().enumerate() {
        let n = l.len();
        for i in 0..n {
            let j = (i + 1) % n;
            let m = mids[li][i].ok_or(FillError::Unbordered { node: l[i] })?;
            let (q, r) = (&inner[li], &radial[li]);
            if let Some(rj) = r[j] {
                b.quads.push([l[i], l[j], rj, q[i]]);
                b.quads.push([q[i], rj, q[j], m]);
            } else {
                let ri = r[i].ok_or(FillError::Unbordered { node: l[i] })?;
                b.quads.push([l[i], l[j], q[j], ri]);
                b.quads.push([ri, q[j], m, q[i]]);
            }
        }
    }
    untangle(&mut b, nodes, front_nodes(loops), min_area)?;
    check_quads(&b, nodes, min_area)?;
    if !ring_is_clear(loops, &inner, nodes, &b) {
        return Err(FillError::RingCrossing);
    }
    Ok(b)
}

/// Fills the region bounded by `loops` with a direct quadrangulation: the
/// loops' even-indexed nodes (or odd, by `parity`) make coarse loops whose
/// edges skip one node each; the coarse region is quadrangulated and each
/// coarse edge takes the skipped front node as its midpoint, so the quads
/// meet the front edge for edge with no ring between.
fn try_direct(
    loops: &[Vec<u32>],
    nodes: &[Point],
    parity: usize,
    size: f64,
    min_area: f64,
) -> Result<RegionFill, FillError> {
    let mut b = RegionFill::new(nodes);
    let mut coarse: Vec<Vec<u32>> = Vec::with_capacity(loops.len());
    let mut skipped: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    for l in loops {
        let n = l.len();
        if n == 4 {
            // A loop of four nodes is one quad (a hole of four is refused
            // by the check below, being clockwise).
            b.quads.push([l[0], l[1], l[2], l[3]]);
            continue;
        }
        let c: Vec<u32> = (0..n / 2).map(|k| l[(2 * k + parity) % n]).collect();
        for k in 0..n / 2 {
            let i = 2 * k + parity;
            skipped.insert((l[i % n], l[(i + 2) % n]), l[(i + 1) % n]);
        }
        coarse.push(c);
    }
    quadrangulate(&coarse, nodes, &mut b, size, true, |_, u, w, _, _| {
        skipped.get(&(u, w)).copied()
    })?;
    untangle(&mut b, nodes, front_nodes(loops), min_area)?;
    check_quads(&b, nodes, min_area)?;
    check_edges(loops, &b.quads)?;
    Ok(b)
}

/// The quads' sides: each loop edge once in its direction, every other
/// side once in each direction.
fn check_edges(loops: &[Vec<u32>], quads: &[[u32; 4]]) -> Result<(), FillError> {
    let mut count: BTreeMap<(u32, u32), i32> = BTreeMap::new();
    for q in quads {
        for k in 0..4 {
            *count.entry((q[k], q[(k + 1) % 4])).or_default() += 1;
        }
    }
    for l in loops {
        for k in 0..l.len() {
            *count.entry((l[k], l[(k + 1) % l.len()])).or_default() -= 1;
        }
    }
    for (&(u, w), &c) in &count {
        let back = count.get(&(w, u)).copied().unwrap_or(0);
        if c != 0 && (c != 1 || back != 1) {
            return Err(FillError::Unbordered { node: u });
        }
    }
    Ok(())
}

/// Sweeps of [`untangle`] at most.
const UNTANGLE_SWEEPS: usize = 12;

/// Every quad at a node [`untangle`] moved must have at least this scaled
/// Jacobian: a fold undone only to a sliver is no better a fill than none
/// (the run then closes the region another way, or rewinds).
const UNTANGLE_SJ: f64 = 0.1;

/// A fill with more folded quads than its front has nodes is not
/// untangled: untangling moves every node of every folded quad, sweep
/// after sweep, and a fill folded that widely (tens of thousands of quads
/// where a dense front meets a single long edge) is not mended by moving
/// nodes; the run closes the region another way.
const UNTANGLE_MAX_FOLDED_PER_FRONT_NODE: usize = 1;

/// The nodes of a region's loops.
fn front_nodes(loops: &[Vec<u32>]) -> usize {
    loops.iter().map(Vec::len).sum()
}

/// Whether a new quad passes [`check_quads`].
fn quad_ok(p: [Point; 4], min_area: f64) -> bool {
    crate::geom::is_measurably_convex(p) && crate::geom::polygon_area(p) >= min_area
}

/// Moves the new nodes of quads that are not convex (a fill's quads at a
/// front node whose angle one triangle's centre cannot serve, or beside a
/// zigzag of the front) to where the worst of their quads is best: a
/// pattern search over each such node's position, the front nodes fixed,
/// sweep after sweep while a sweep still mends a quad. The quads' topology
/// is kept, so a fill that is valid but for a few folded quads becomes
/// valid; the smoothing after the fill evens the sizes out. Fails when a
/// quad at a moved node stays under [`UNTANGLE_SJ`], and at once when the
/// folded quads outnumber the `front` nodes the region's loops have
/// ([`UNTANGLE_MAX_FOLDED_PER_FRONT_NODE`]).
fn untangle(
    b: &mut RegionFill,
    nodes: &[Point],
    front: usize,
    min_area: f64,
) -> Result<(), FillError> {
    let at = |b: &RegionFill, q: [u32; 4]| q.map(|v| b.at(v, nodes));
    // Whether each quad is folded; after a sweep only the quads at the
    // nodes it moved are tested again.
    let mut folded: Vec<bool> = b
        .quads
        .iter()
        .map(|&q| !quad_ok(at(b, q), min_area))
        .collect();
    let listed =
        |folded: &[bool]| -> Vec<usize> { (0..folded.len()).filter(|&k| folded[k]).collect() };
    let mut worse = listed(&folded);
    if worse.is_empty() {
        return Ok(());
    }
    if worse.len() > UNTANGLE_MAX_FOLDED_PER_FRONT_NODE * front {
        return Err(FillError::NotConvex {
            node: b.quads[worse[0]][0],
        });
    }
    let mut incident: Vec<Vec<usize>> = vec![Vec::new(); b.points.len()];
    for (k, q) in b.quads.iter().enumerate() {
        for &v in q {
            if v >= b.first_new {
                incident[(v - b.first_new) as usize].push(k);
            }
        }
    }
    // A node's quality: its worst quad's scaled Jacobian (signed: a
    // folded quad's reflex corner counts below a flat one).
    // With a floor it stops at the first quad at or under it plus the
    // search's margin: such a place is no improvement whatever its other
    // quads, and the search drops its figure.
    let quality_over = |b: &RegionFill, v: usize, floor: f64| -> f64 {
        let mut worst = f64::INFINITY;
        for &k in &incident[v] {
            worst = worst.min(crate::quality::Shape::of(at(b, b.quads[k])).scaled_jacobian);
            if worst <= floor + SEARCH_MARGIN {
                break;
            }
        }
        worst
    };
    let quality = |b: &RegionFill, v: usize| quality_over(b, v, f64::NEG_INFINITY);
    let moved_from = b.points.clone();
    for _ in 0..UNTANGLE_SWEEPS {
        let mut movable: Vec<usize> = worse
            .iter()
            .flat_map(|&k| b.quads[k])
            .filter(|&v| v >= b.first_new)
            .map(|v| (v - b.first_new) as usize)
            .collect();
        movable.sort_unstable();
        movable.dedup();
        for &v in &movable {
            let start = b.points[v];
            let reach = incident[v]
                .iter()
                .flat_map(|&k| b.quads[k])
                .map(|u| b.at(u, nodes).distance(start))
                .filter(|&d| d > 0.0)
                .fold(f64::INFINITY, f64::min);
            if !reach.is_finite() {
                continue;
            }
            let mut best = quality(b, v);
            // First the mean of its edge neighbours (a Laplacian step
            // undoes a fold a search from where the node is cannot
            // leave), then a pattern search.
            let mut sum = Point::ZERO;
            let mut count = 0.0;
            for &k in &incident[v] {
                let q = b.quads[k];
                let i = q
                    .iter()
                    .position(|&u| u == b.first_new + v as u32)
                    .unwrap_or(0);
                sum += b.at(q[(i + 1) % 4], nodes) + b.at(q[(i + 3) % 4], nodes);
                count += 2.0;
            }
            let mut here = start;
            b.points[v] = sum / count;
            let q = quality(b, v);
            if q > best {
                best = q;
                here = b.points[v];
            }
            b.points[v] = here;
            let steps = SearchSteps {
                first: 0.25 * reach,
                stop: 1e-3 * reach,
                cap: f64::INFINITY,
                grow: 1.0,
            };
            here = search(here, steps, (best, 0.0), |p, floor| {
                b.points[v] = p;
                Some((quality_over(b, v, floor), 0.0))
            });
            b.points[v] = here;
        }
        for &v in &movable {
            for &k in &incident[v] {
                folded[k] = !quad_ok(at(b, b.quads[k]), min_area);
            }
        }
        let left = listed(&folded);
        if left.is_empty() || left == worse {
            break;
        }
        worse = left;
    }
    for (v, quads) in incident.iter().enumerate() {
        if b.points[v] == moved_from[v] {
            continue;
        }
        for &k in quads {
            let q = b.quads[k];
            if crate::quality::Shape::of(at(b, q)).scaled_jacobian < UNTANGLE_SJ {
                return Err(FillError::NotConvex { node: q[0] });
            }
        }
    }
    Ok(())
}

/// Measurably convex, and not so thin that its area is lost to rounding when
/// computed from absolute coordinates (as other tools do).
fn check_quads(b: &RegionFill, nodes: &[Point], min_area: f64) -> Result<(), FillError> {
    for quad in &b.quads {
        if !quad_ok(quad.map(|v| b.at(v, nodes)), min_area) {
            return Err(FillError::NotConvex { node: quad[0] });
        }
    }
    Ok(())
}

/// Quadrangulates the region bounded by `loops` (ids in `nodes` or new in
/// `b`): a constrained Delaunay triangulation (spade), refined inside with a
/// 25° angle limit and triangles of about `size` squared (`refine`), whose
/// triangles are paired into quads where the pair makes a good one; then
/// every cell (pair or lone triangle) is cut into quads through its centre
/// and edge midpoints. The midpoint of a loop edge `(u, w)` comes from
/// `loop_mid(b, u, w, midpoint, centre)`, which must give one for every loop
/// edge.
fn quadrangulate(
    loops: &[Vec<u32>],
    nodes: &[Point],
    b: &mut RegionFill,
    size: f64,
    refine: bool,
    mut loop_mid: impl FnMut(&mut RegionFill, u32, u32, Point, Point) -> Option<u32>,
) -> Result<(), FillError> {
    let mut vertices: Vec<Point2<f64>> = Vec::new();
    let mut edges: Vec<[usize; 2]> = Vec::new();
    let mut vertex_node: Vec<u32> = Vec::new();
    for q in loops {
        let base = vertices.len();
        for (k, &v) in q.iter().enumerate() {
            let p = b.at(v, nodes);
            vertices.push(Point2::new(p.x, p.y));
            vertex_node.push(v);
            edges.push([base + k, base + (k + 1) % q.len()]);
        }
    }
    let expected = vertices.len();
    let mut conflict = false;
    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> = guarded(|| {
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(vertices, edges, |_| conflict = true)
    })
    .ok_or(FillError::Triangulation)?
    .map_err(|_| FillError::Crossing)?;
    if conflict || cdt.num_vertices() != expected {
        return Err(FillError::Crossing);
    }
    // Triangles of up to CELL_AREA size² make quads about `size` wide; the
    // vertices refinement may add are bounded by twice what that area needs
    // (and by the loops' size, for regions thin beside their edges).
    let area: f64 = loops
        .iter()
        .map(|q| crate::geom::polygon_area(q.iter().map(|&v| b.at(v, nodes))))
        .sum::<f64>()
        .abs();
    let budget = (2.0 * area / (CELL_AREA * size * size)).min(1e9) as usize + 4 * expected + 1000;
    let params = RefinementParameters::<f64>::new()
        .keep_constraint_edges()
        .exclude_outer_faces(true)
        .with_angle_limit(AngleLimit::from_deg(if refine { 25.0 } else { 0.0 }))
        .with_max_allowed_area(if refine {
            CELL_AREA * size * size
        } else {
            f64::INFINITY
        })
        .with_max_additional_vertices(if refine { budget } else { 0 });
    let Some(result) = guarded(|| cdt.refine(params)) else {
        return Err(FillError::Triangulation);
    };
    let outer: std::collections::BTreeSet<usize> =
        result.excluded_faces.iter().map(|f| f.index()).collect();
    for v in cdt.vertices().skip(expected) {
        let p = v.position();
        vertex_node.push(b.add(Point::new(p.x, p.y)));
    }
    let mut is_loop_edge: std::collections::BTreeSet<(u32, u32)> = Default::default();
    for q in loops {
        for k in 0..q.len() {
            is_loop_edge.insert((q[k], q[(k + 1) % q.len()]));
        }
    }
    // Triangles paired into quads where the pair makes a good one.
    let inside =
        |f: spade::handles::FaceHandle<'_, spade::handles::PossiblyOuterTag, _, _, _, _>| {
            f.as_inner()
                .map(|f| f.fix().index())
                .filter(|i| !outer.contains(i))
        };
    // (scaled Jacobian, diagonal as a sort key, the two faces, the quad)
    type Pair = (f64, [u32; 2], [usize; 2], [u32; 4]);
    let mut pairs: Vec<Pair> = Vec::new();
    for e in cdt.undirected_edges() {
        if cdt.is_constraint_edge(e.fix()) {
            continue;
        }
        let d = e.as_directed();
        let (Some(left), Some(right)) = (inside(d.face()), inside(d.rev().face())) else {
            continue;
        };
        let (Some(c), Some(o)) = (d.opposite_vertex(), d.rev().opposite_vertex()) else {
            continue;
        };
        let node = |v: spade::handles::FixedVertexHandle| vertex_node[v.index()];
        let quad = [
            node(d.from().fix()),
            node(o.fix()),
            node(d.to().fix()),
            node(c.fix()),
        ];
        let p = quad.map(|v| b.at(v, nodes));
        if !is_strictly_convex(p) {
            continue;
        }
        let sj = crate::quality::Shape::of(p).scaled_jacobian;
        if sj >= MIN_PAIR_SJ {
            let key = [quad[0].min(quad[2]), quad[0].max(quad[2])];
            pairs.push((sj, key, [left, right], quad));
        }
    }
    pairs.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut paired: std::collections::BTreeSet<usize> = std::collections::BTreeSet::new();
    let mut cells: Vec<Vec<u32>> = Vec::new();
    for (_, _, [f, g], quad) in pairs {
        if !paired.contains(&f) && !paired.contains(&g) {
            paired.insert(f);
            paired.insert(g);
            cells.push(quad.to_vec());
        }
    }
    for face in cdt.inner_faces() {
        let i = face.fix().index();
        if !outer.contains(&i) && !paired.contains(&i) {
            cells.push(
                face.vertices()
                    .map(|v| vertex_node[v.fix().index()])
                    .to_vec(),
            );
        }
    }
    // Every cell into quads through its centre and edge midpoints.
    let mut shared: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    for t in &cells {
        let n = t.len();
        let tp: Vec<Point> = t.iter().map(|&v| b.at(v, nodes)).collect();
        let g = tp.iter().copied().sum::<Point>() / n as f64;
        let gi = b.add(g);
        let mut mid = Vec::with_capacity(n);
        for k in 0..n {
            let (u, w) = (t[k], t[(k + 1) % n]);
            let m = 0.5 * (tp[k] + tp[(k + 1) % n]);
            let id = if is_loop_edge.contains(&(u, w)) {
                loop_mid(b, u, w, m, g).ok_or(FillError::Unbordered { node: u })?
            } else {
                let key = (u.min(w), u.max(w));
                match shared.get(&key) {
                    Some(&id) => id,
                    None => {
                        let id = b.add(m);
                        shared.insert(key, id);
                        id
                    }
                }
            };
            mid.push(id);
        }
        for k in 0..n {
            b.quads.push([t[k], mid[k], gi, mid[(k + n - 1) % n]]);
        }
    }
    Ok(())
}

/// The segments between the node pairs `ends` (positions from `at`), and
/// a grid over them about one mean segment per cell.
fn segment_grid(ends: &[(u32, u32)], at: impl Fn(u32) -> Point) -> (Vec<(Point, Point)>, EdgeGrid) {
    let segs: Vec<(Point, Point)> = ends.iter().map(|&(u, v)| (at(u), at(v))).collect();
    let bb = Aabb::of(segs.iter().flat_map(|&(a, c)| [a, c])).unwrap_or(Aabb {
        min: Point::ZERO,
        max: Point::ONE,
    });
    let len: f64 = segs.iter().map(|&(a, c)| a.distance(c)).sum();
    let cell = (len / segs.len().max(1) as f64).max(1e-300);
    let mut grid = EdgeGrid::new(bb, cell, (4 * segs.len()).clamp(1024, 4_000_000));
    for (k, &(a, c)) in segs.iter().enumerate() {
        grid.insert(k as u32, a, c);
    }
    (segs, grid)
}

/// For every loop node, the distance to the nearest front edge that does
/// not end at that node, looked for within twice its longer edge.
fn clearances(loops: &[Vec<u32>], nodes: &[Point]) -> Vec<Vec<f64>> {
    let mut ends: Vec<(u32, u32)> = Vec::new();
    for l in loops {
        for k in 0..l.len() {
            ends.push((l[k], l[(k + 1) % l.len()]));
        }
    }
    let (segs, grid) = segment_grid(&ends, |v| nodes[v as usize]);
    let mut near = Vec::new();
    loops
        .iter()
        .map(|l| {
            let n = l.len();
            (0..n)
                .map(|i| {
                    let p = nodes[l[i] as usize];
                    let reach = 2.0
                        * p.distance(nodes[l[(i + 1) % n] as usize])
                            .max(p.distance(nodes[l[(i + n - 1) % n] as usize]));
                    grid.query(p - Point::splat(reach), p + Point::splat(reach), &mut near);
                    near.iter()
                        .map(|&k| k as usize)
                        .filter(|&k| ends[k].0 != l[i] && ends[k].1 != l[i])
                        .map(|k| crate::geom::point_segment_distance(p, segs[k].0, segs[k].1))
                        .fold(reach, f64::min)
                })
                .collect()
        })
        .collect()
}

/// True when no radial or inner-loop edge crosses a front edge or another
/// ring edge (the triangulation already ruled out crossings among inner
/// edges).
fn ring_is_clear(loops: &[Vec<u32>], inner: &[Vec<u32>], nodes: &[Point], b: &RegionFill) -> bool {
    let mut ends: Vec<(u32, u32)> = Vec::new();
    for (l, q) in loops.iter().zip(inner) {
        let n = l.len();
        for i in 0..n {
            ends.push((l[i], l[(i + 1) % n]));
            ends.push((l[i], q[i]));
            ends.push((q[i], q[(i + 1) % n]));
        }
    }
    let (segs, grid) = segment_grid(&ends, |v| b.at(v, nodes));
    let mut near = Vec::new();
    for (s, &(a, c)) in ends.iter().enumerate() {
        grid.query(
            segs[s].0.min(segs[s].1),
            segs[s].0.max(segs[s].1),
            &mut near,
        );
        for &t in &near {
            let t = t as usize;
            let (d, e) = ends[t];
            if t <= s || a == d || a == e || c == d || c == e {
                continue;
            }
            if crate::geom::segments_intersect(segs[s].0, segs[s].1, segs[t].0, segs[t].1) {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(loops: &[Vec<u32>], nodes: &[Point]) -> RegionFill {
        let f = fill_region(loops, nodes).expect("a fill");
        let all: Vec<Point> = nodes.iter().chain(&f.points).copied().collect();
        let mut area = 0.0;
        for q in &f.quads {
            let p = q.map(|v| all[v as usize]);
            assert!(is_strictly_convex(p), "{q:?}");
            area += crate::geom::polygon_area(p);
        }
        let want: f64 = loops
            .iter()
            .map(|l| crate::geom::polygon_area(l.iter().map(|&v| nodes[v as usize])))
            .sum();
        assert!(
            (area - want).abs() < 1e-9 * want.abs().max(1.0),
            "{area} vs {want}"
        );
        // Every front edge is used by exactly one quad, in its direction.
        for l in loops {
            for k in 0..l.len() {
                let (a, c) = (l[k], l[(k + 1) % l.len()]);
                let uses = f
                    .quads
                    .iter()
                    .filter(|q| (0..4).any(|i| q[i] == a && q[(i + 1) % 4] == c))
                    .count();
                assert_eq!(uses, 1, "edge {a}-{c}");
            }
        }
        f
    }

    #[test]
    fn untangles_folded_quads_with_the_front_fixed() {
        // A 3×3 grid over the unit square: the 12 nodes of its edge are
        // the front (fixed), the 4 inside are new. Two inner nodes pushed
        // past their neighbours fold quads around them.
        let nodes: Vec<Point> = [(0, 0), (1, 0), (2, 0), (3, 0), (3, 1), (3, 2)]
            .into_iter()
            .chain([(3, 3), (2, 3), (1, 3), (0, 3), (0, 2), (0, 1)])
            .map(|(x, y)| Point::new(x as f64 / 3.0, y as f64 / 3.0))
            .collect();
        let mut b = RegionFill::new(&nodes);
        let inner = [(1, 1), (2, 1), (2, 2), (1, 2)]
            .map(|(x, y)| b.add(Point::new(x as f64 / 3.0, y as f64 / 3.0)));
        let [a, c, d, e] = inner;
        b.quads = vec![
            [0, 1, a, 11],
            [1, 2, c, a],
            [2, 3, 4, c],
            [11, a, e, 10],
            [a, c, d, e],
            [c, 4, 5, d],
            [10, e, 8, 9],
            [e, d, 7, 8],
            [d, 5, 6, 7],
        ];
        b.points[0] = Point::new(0.8, 0.45);
        b.points[2] = Point::new(0.3, 0.55);
        let min_area = 1e-7 / 9.0;
        assert!(check_quads(&b, &nodes, min_area).is_err());
        // Folded more widely than a front of two nodes could be mended
        // from: refused at once, nothing moved.
        let folded = b.clone();
        assert!(untangle(&mut b, &nodes, 2, min_area).is_err());
        assert_eq!(b.points, folded.points);
        untangle(&mut b, &nodes, 12, min_area).expect("untangled");
        check_quads(&b, &nodes, min_area).expect("untangled");
        check_edges(&[(0..12).collect()], &b.quads).expect("same tiling");
        for (k, &p) in b.points.iter().enumerate() {
            assert!(
                p.x > 0.0 && p.x < 1.0 && p.y > 0.0 && p.y < 1.0,
                "node {k} at {p}"
            );
        }
    }

    #[test]
    fn fills_a_square_loop() {
        let nodes: Vec<Point> = (0..8)
            .map(|k| {
                let t = k as f64 / 2.0;
                match k / 2 {
                    0 => Point::new(t, 0.0),
                    1 => Point::new(1.0, t - 1.0),
                    2 => Point::new(3.0 - t, 1.0),
                    _ => Point::new(0.0, 4.0 - t),
                }
            })
            .collect();
        check(&[(0..8).collect()], &nodes);
    }

    #[test]
    fn fills_a_zigzag_and_a_hole() {
        // An outer loop with a sharp notch and a square hole (clockwise).
        let nodes = vec![
            Point::new(0.0, 0.0),
            Point::new(4.0, 0.0),
            Point::new(4.0, 4.0),
            Point::new(2.2, 4.0),
            Point::new(2.0, 1.0),
            Point::new(1.8, 4.0),
            Point::new(0.0, 4.0),
            Point::new(0.0, 2.0),
            Point::new(3.0, 1.0),
            Point::new(3.0, 2.0),
            Point::new(3.5, 2.0),
            Point::new(3.5, 1.0),
        ];
        check(&[(0..8).collect(), vec![8, 9, 10, 11]], &nodes);
    }

    #[test]
    fn joins_two_triangular_holes_by_a_corridor() {
        // A square of 8 front nodes with two triangular holes (clockwise):
        // each hole is odd, the region is even.
        let mut nodes: Vec<Point> = (0..8)
            .map(|k| {
                let t = 4.0 * (k % 2) as f64;
                match k / 2 {
                    0 => Point::new(t, 0.0),
                    1 => Point::new(8.0, t),
                    2 => Point::new(8.0 - t, 8.0),
                    _ => Point::new(0.0, 8.0 - t),
                }
            })
            .collect();
        for (cx, cy) in [(2.5, 4.0), (5.5, 4.0)] {
            for a in [90.0f64, 330.0, 210.0] {
                let a = a.to_radians();
                nodes.push(Point::new(cx + 0.8 * a.cos(), cy + 0.8 * a.sin()));
            }
        }
        let f = check(
            &[(0..8).collect(), vec![8, 9, 10], vec![11, 12, 13]],
            &nodes,
        );
        assert!(f.quads.len() >= 8, "{}", f.quads.len());
        // An odd hole alone in its region cannot be joined.
        assert!(fill_region(&[(0..8).collect(), vec![8, 9, 10]], &nodes).is_err());
    }

    #[test]
    fn fills_a_circle_directly_with_good_quads() {
        // A circle of 40 front nodes: the direct fill keeps every quad well
        // shaped and pairs most triangles.
        let nodes: Vec<Point> = (0..40)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 40.0;
                Point::new(t.cos(), t.sin())
            })
            .collect();
        let f = check(&[(0..40).collect()], &nodes);
        let all: Vec<Point> = nodes.iter().chain(&f.points).copied().collect();
        let sj: Vec<f64> = f
            .quads
            .iter()
            .map(|q| crate::quality::Shape::of(q.map(|v| all[v as usize])).scaled_jacobian)
            .collect();
        let worst = sj.iter().copied().fold(f64::INFINITY, f64::min);
        let mean = sj.iter().sum::<f64>() / sj.len() as f64;
        assert!(worst > 0.3, "worst scaled Jacobian {worst}");
        assert!(mean > 0.75, "mean scaled Jacobian {mean}");
        assert_eq!(f.min_scaled_jacobian(&nodes), worst);
    }

    #[test]
    fn fills_separate_loops_one_by_one() {
        // Two counter-clockwise squares of 8 nodes each, side by side.
        let square = |x0: f64| -> Vec<Point> {
            (0..8)
                .map(|k| {
                    let t = k as f64 / 2.0;
                    match k / 2 {
                        0 => Point::new(x0 + t, 0.0),
                        1 => Point::new(x0 + 1.0, t - 1.0),
                        2 => Point::new(x0 + 3.0 - t, 1.0),
                        _ => Point::new(x0, 4.0 - t),
                    }
                })
                .collect()
        };
        let nodes: Vec<Point> = square(0.0).into_iter().chain(square(2.0)).collect();
        let f = check(&[(0..8).collect(), (8..16).collect()], &nodes);
        // No quad joins the two squares.
        assert!(f
            .quads
            .iter()
            .all(|q| !(q.iter().any(|&v| v < 8) && q.iter().any(|&v| (8..16).contains(&v)))));
    }

    #[test]
    fn refuses_odd_loops() {
        let nodes = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(0.0, 1.0),
        ];
        assert_eq!(
            fill_region(&[vec![0, 1, 2]], &nodes),
            Err(FillError::OddLoop {
                loop_index: 0,
                len: 3
            })
        );
    }
}

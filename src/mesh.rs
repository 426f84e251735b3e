//! The all-quad mesh: node positions, quads as CCW node ids, and the
//! boundary loops it was built on (node ids `0..n_boundary` are the boundary
//! nodes, unchanged). [`QuadMesh::check_invariants`] is the mesh's sanity
//! check, run by the tests after every extraction step.

use crate::boundary::Boundary;
use crate::geom::{polygon_area, reflex_corner, turns_left, AreaSum, Point};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use thiserror::Error;

/// A broken mesh invariant, with the element or edge at fault.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum InvariantError {
    #[error("quad {quad} refers to node {node}, which does not exist")]
    BadNode { quad: usize, node: u32 },
    #[error("quad {quad} is not strictly convex and counter-clockwise (corner at node {node})")]
    NotConvex { quad: usize, node: u32 },
    #[error("edge {a}–{b} is used {count} times in the same direction or more than twice")]
    EdgeOveruse { a: u32, b: u32, count: usize },
    #[error("boundary edge {a}–{b} is not the side of exactly one quad")]
    BoundaryEdge { a: u32, b: u32 },
    #[error("edge {a}–{b} has a quad on one side only but is not a boundary edge")]
    OpenEdge { a: u32, b: u32 },
    #[error("the quads cover an area of {covered}, the domain {domain}")]
    Area { covered: f64, domain: f64 },
    #[error("front: {0}")]
    Front(String),
    #[error("node {node} is pinched: two boundary edges leave it")]
    Pinched { node: u32 },
    #[error("the boundary does not close at node {node}")]
    OpenBoundary { node: u32 },
    #[error("no quads, so no boundary")]
    Empty,
    #[error("quad {quad} has a corner flat to rounding at node {node}")]
    FlatCorner { quad: usize, node: u32 },
}

/// An all-quadrilateral mesh.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct QuadMesh {
    /// Node positions; ids below `n_boundary` are the boundary's nodes.
    pub nodes: Vec<Point>,
    /// Quads as node ids, counter-clockwise.
    pub quads: Vec<[u32; 4]>,
    /// The boundary loops (outer CCW first, holes CW) as node ids.
    pub loops: Vec<Vec<u32>>,
}

impl QuadMesh {
    /// An empty mesh over a boundary: its nodes, no quads yet.
    pub fn from_boundary(b: &Boundary) -> QuadMesh {
        QuadMesh {
            nodes: b.points.clone(),
            quads: Vec::new(),
            loops: b
                .loops
                .iter()
                .map(|l| l.iter().map(|&i| i as u32).collect())
                .collect(),
        }
    }

    /// A mesh from bare quads (any orientation): quads are turned
    /// counter-clockwise, the boundary loops are found from the edges used
    /// once (the outer loop, of largest area, first) and the nodes are
    /// renumbered boundary first, in loop order. Unused points are dropped.
    pub fn from_quads(
        points: Vec<Point>,
        quads: Vec<[u32; 4]>,
    ) -> Result<QuadMesh, InvariantError> {
        let mut qs = quads;
        for (k, q) in qs.iter_mut().enumerate() {
            if let Some(&node) = q.iter().find(|&&v| v as usize >= points.len()) {
                return Err(InvariantError::BadNode { quad: k, node });
            }
            if polygon_area(q.map(|i| points[i as usize])) < 0.0 {
                q.reverse();
            }
        }
        let loops = boundary_loops(&points, &qs)?;
        // Renumber: boundary nodes first, then the others the quads use.
        let mut new_id = vec![u32::MAX; points.len()];
        let mut order = Vec::with_capacity(points.len());
        let interior = qs.iter().flatten().copied();
        for v in loops.iter().flatten().copied().chain(interior) {
            if new_id[v as usize] == u32::MAX {
                new_id[v as usize] = order.len() as u32;
                order.push(v);
            }
        }
        Ok(QuadMesh {
            nodes: order.iter().map(|&v| points[v as usize]).collect(),
            quads: qs.iter().map(|q| q.map(|v| new_id[v as usize])).collect(),
            loops: loops
                .iter()
                .map(|l| l.iter().map(|&v| new_id[v as usize]).collect())
                .collect(),
        })
    }

    /// Number of boundary nodes.
    pub fn n_boundary(&self) -> usize {
        self.loops.iter().map(Vec::len).sum()
    }

    /// True for a node on the boundary (never moved by smoothing).
    pub fn is_boundary(&self, node: u32) -> bool {
        (node as usize) < self.n_boundary()
    }

    /// Positions of a quad's corners. Written out rather than through
    /// `array::map`, whose inlining into the quality measures' inner loops
    /// is left to how the crate happens to be split for compiling.
    #[inline]
    pub fn corners(&self, q: &[u32; 4]) -> [Point; 4] {
        let at = |k: usize| self.nodes[q[k] as usize];
        [at(0), at(1), at(2), at(3)]
    }

    /// Area of the domain the boundary loops enclose.
    pub fn domain_area(&self) -> f64 {
        self.loops
            .iter()
            .map(|l| polygon_area(l.iter().map(|&i| self.nodes[i as usize])))
            .sum()
    }

    /// Keeps the quads whose flag in `keep` is set, in order, and drops the
    /// nodes left unused ([`QuadMesh::compact`]). Returns, for each quad
    /// kept, its former index.
    pub fn retain_quads(&mut self, keep: &[bool]) -> Vec<u32> {
        let mut former = Vec::with_capacity(self.quads.len());
        let mut k = 0;
        self.quads.retain(|_| {
            k += 1;
            let kept = keep.get(k - 1).copied().unwrap_or(true);
            if kept {
                former.push(k as u32 - 1);
            }
            kept
        });
        self.compact();
        former
    }

    /// Renumbers the interior nodes along a Z-order curve over the domain
    /// (ties by their former id) and sorts the quads by their lowest
    /// corner, so that nodes and quads close in the plane are close in
    /// memory: sweeps over a large mesh then read memory mostly in order.
    /// Boundary nodes keep their ids; the mesh is the same.
    pub fn sort_spatially(&mut self) {
        let nb = self.n_boundary();
        let (lo, hi) = self.nodes.iter().fold(
            (Point::splat(f64::INFINITY), Point::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let span = (hi - lo).max_element().max(f64::MIN_POSITIVE);
        let spread = |mut x: u64| {
            x &= 0xffff_ffff;
            x = (x | (x << 16)) & 0x0000_ffff_0000_ffff;
            x = (x | (x << 8)) & 0x00ff_00ff_00ff_00ff;
            x = (x | (x << 4)) & 0x0f0f_0f0f_0f0f_0f0f;
            x = (x | (x << 2)) & 0x3333_3333_3333_3333;
            (x | (x << 1)) & 0x5555_5555_5555_5555
        };
        let key = |p: Point| {
            let q = (p - lo) / span * f64::from(u32::MAX);
            spread(q.x as u64) | (spread(q.y as u64) << 1)
        };
        // Keys made once; with the node's id, no two are equal.
        let mut order: Vec<(u64, usize)> = (nb..self.nodes.len())
            .map(|i| (key(self.nodes[i]), i))
            .collect();
        order.sort_unstable();
        let mut new_id: Vec<u32> = (0..self.nodes.len() as u32).collect();
        let mut nodes = self.nodes[..nb].to_vec();
        for &(_, i) in &order {
            new_id[i] = nodes.len() as u32;
            nodes.push(self.nodes[i]);
        }
        self.nodes = nodes;
        for q in &mut self.quads {
            *q = q.map(|v| new_id[v as usize]);
        }
        self.quads.sort_by_key(|q| q.iter().copied().min());
    }

    /// Drops interior nodes that no quad uses, renumbering the rest in
    /// order. Boundary nodes keep their ids.
    pub fn compact(&mut self) {
        let nb = self.n_boundary();
        let mut used = vec![false; self.nodes.len()];
        for q in &self.quads {
            for &v in q {
                used[v as usize] = true;
            }
        }
        let mut new_id = vec![u32::MAX; self.nodes.len()];
        let mut nodes = Vec::with_capacity(self.nodes.len());
        for (i, &p) in self.nodes.iter().enumerate() {
            if i < nb || used[i] {
                new_id[i] = nodes.len() as u32;
                nodes.push(p);
            }
        }
        self.nodes = nodes;
        for q in &mut self.quads {
            *q = q.map(|v| new_id[v as usize]);
        }
    }

    /// Node-to-quad incidence: for each node, the quads that use it.
    pub fn node_quads(&self) -> Vec<Vec<u32>> {
        let mut inc = vec![Vec::new(); self.nodes.len()];
        for (k, q) in self.quads.iter().enumerate() {
            for &v in q {
                inc[v as usize].push(k as u32);
            }
        }
        inc
    }

    /// [`QuadMesh::node_quads`] in two flat arrays ([`NodeQuads`]), for
    /// meshes of millions of quads, where a list per node costs an
    /// allocation each.
    pub fn node_quads_flat(&self) -> NodeQuads {
        let n = self.nodes.len();
        let mut start = vec![0u32; n + 1];
        for q in &self.quads {
            for &v in q {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut quads = vec![0u32; 4 * self.quads.len()];
        for (k, q) in self.quads.iter().enumerate() {
            for &v in q {
                quads[fill[v as usize] as usize] = k as u32;
                fill[v as usize] += 1;
            }
        }
        NodeQuads { start, quads }
    }

    /// The checks of a finished mesh: [`QuadMesh::check_invariants`] with
    /// `complete`, and no corner flat to rounding
    /// ([`crate::geom::turns_left`]), which any floating-point
    /// reader would see as degenerate.
    pub fn check_finished(&self) -> Result<(), InvariantError> {
        self.check_invariants(true)?;
        self.check_no_flat_corner()
    }

    /// No corner of any quad flat to rounding ([`crate::geom::turns_left`]).
    pub fn check_no_flat_corner(&self) -> Result<(), InvariantError> {
        for (k, q) in self.quads.iter().enumerate() {
            let p = self.corners(q);
            if let Some(i) = (0..4).find(|&i| !turns_left(p[(i + 3) % 4], p[i], p[(i + 1) % 4])) {
                return Err(InvariantError::FlatCorner {
                    quad: k,
                    node: q[i],
                });
            }
        }
        Ok(())
    }

    /// Checks that every quad is strictly convex and CCW (exactly), that no
    /// edge is used twice in one direction, and, when `complete`, that the quads
    /// tile the domain exactly: every boundary segment is the side of one
    /// quad, every other edge of two, and the areas add up
    /// ([`QuadMesh::check_area`]).
    pub fn check_invariants(&self, complete: bool) -> Result<(), InvariantError> {
        let n = self.nodes.len() as u32;
        for (k, q) in self.quads.iter().enumerate() {
            if let Some(&v) = q.iter().find(|&&v| v >= n) {
                return Err(InvariantError::BadNode { quad: k, node: v });
            }
            if let Some(i) = reflex_corner(self.corners(q)) {
                return Err(InvariantError::NotConvex {
                    quad: k,
                    node: q[i],
                });
            }
        }
        let directed = DirectedEdges::new(&self.quads);
        if let Some(((a, b), count)) = directed.iter().find(|&(_, c)| c > 1) {
            return Err(InvariantError::EdgeOveruse { a, b, count });
        }
        if !complete {
            return Ok(());
        }
        let mut boundary = std::collections::BTreeSet::new();
        for l in &self.loops {
            for k in 0..l.len() {
                let (a, b) = (l[k], l[(k + 1) % l.len()]);
                boundary.insert((a, b));
                if !directed.contains(a, b) || directed.contains(b, a) {
                    return Err(InvariantError::BoundaryEdge { a, b });
                }
            }
        }
        for ((a, b), _) in directed.iter() {
            if !directed.contains(b, a) && !boundary.contains(&(a, b)) {
                return Err(InvariantError::OpenEdge { a, b });
            }
        }
        self.check_area()
    }

    /// The quads' areas added up, with the sum's rounding bound.
    pub fn quads_area_sum(&self) -> AreaSum {
        let mut sum = AreaSum::default();
        for q in &self.quads {
            sum.add_polygon(&self.corners(q));
        }
        sum
    }

    /// The area the boundary loops enclose (holes negative), with the
    /// sum's rounding bound.
    pub fn loops_area_sum(&self) -> AreaSum {
        let mut sum = AreaSum::default();
        for l in &self.loops {
            let p: Vec<Point> = l.iter().map(|&i| self.nodes[i as usize]).collect();
            sum.add_polygon(&p);
        }
        sum
    }

    /// Checks that the quads' areas add up to the area the boundary loops
    /// enclose, up to the sums' own rounding bounds ([`AreaSum`]): a
    /// relative tolerance cannot tell rounding from a gap when many quads
    /// make up a thin domain (R09: 60,000 quads, sums off by 1.6e-9 of the
    /// area), while these bounds are a few ε of the sums' conditioning, far
    /// below any one quad's area.
    ///
    /// In exact arithmetic the edge checks of [`QuadMesh::check_invariants`]
    /// already imply it (interior edges cancel in the quads' shoelace sums,
    /// leaving the loops'); it stays as a check of that bookkeeping against
    /// the geometry.
    pub fn check_area(&self) -> Result<(), InvariantError> {
        let (covered, domain) = (self.quads_area_sum(), self.loops_area_sum());
        if covered.agrees_with(&domain) {
            Ok(())
        } else {
            Err(InvariantError::Area {
                covered: covered.area(),
                domain: domain.area(),
            })
        }
    }
}

/// Node-to-quad incidence in flat arrays ([`QuadMesh::node_quads_flat`]):
/// the quads at node `v`, in quad order, are `quads[start[v]..start[v + 1]]`.
pub struct NodeQuads {
    pub start: Vec<u32>,
    pub quads: Vec<u32>,
}

impl NodeQuads {
    /// The quads at node `v`.
    pub fn at(&self, v: u32) -> &[u32] {
        &self.quads[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }
}

/// The directed edges of quads (corner i to corner i + 1), grouped by their
/// first node and sorted: counts and reverse-twin lookups without a map
/// over all edges (a mesh of millions of quads is checked in linear time).
struct DirectedEdges {
    start: Vec<usize>,
    to: Vec<u32>,
}

impl DirectedEdges {
    fn new(quads: &[[u32; 4]]) -> DirectedEdges {
        let n = quads.iter().flatten().max().map_or(0, |&v| v as usize + 1);
        let mut start = vec![0usize; n + 1];
        for q in quads {
            for &v in q {
                start[v as usize + 1] += 1;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut to = vec![0u32; 4 * quads.len()];
        for q in quads {
            for k in 0..4 {
                let a = q[k] as usize;
                to[fill[a]] = q[(k + 1) % 4];
                fill[a] += 1;
            }
        }
        for a in 0..n {
            to[start[a]..start[a + 1]].sort_unstable();
        }
        DirectedEdges { start, to }
    }

    fn out(&self, a: u32) -> &[u32] {
        let a = a as usize;
        if a + 1 < self.start.len() {
            &self.to[self.start[a]..self.start[a + 1]]
        } else {
            &[]
        }
    }

    fn contains(&self, a: u32, b: u32) -> bool {
        self.out(a).contains(&b)
    }

    /// Every edge once, in `(a, b)` order, with how many quads use it.
    fn iter(&self) -> impl Iterator<Item = ((u32, u32), usize)> + '_ {
        (0..self.start.len().saturating_sub(1) as u32).flat_map(move |a| {
            self.out(a)
                .chunk_by(|x, y| x == y)
                .map(move |run| ((a, run[0]), run.len()))
        })
    }
}

/// The nodes on an edge of only one of `quads` (a mesh's boundary, and a
/// mesh still being made its front as well), each once, in id order.
pub fn open_edge_nodes(quads: &[[u32; 4]]) -> Vec<u32> {
    let directed = DirectedEdges::new(quads);
    let mut nodes: Vec<u32> = directed
        .iter()
        .filter(|&((a, b), _)| !directed.contains(b, a))
        .flat_map(|((a, b), _)| [a, b])
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// The boundary loops of counter-clockwise `quads` over `points`: chains of
/// the directed edges that have no reverse twin, the loop of largest area
/// first. A node with two such edges out of it is [`InvariantError::Pinched`].
pub fn boundary_loops(
    points: &[Point],
    quads: &[[u32; 4]],
) -> Result<Vec<Vec<u32>>, InvariantError> {
    // Boundary edges: directed edges without a reverse twin.
    let directed = DirectedEdges::new(quads);
    let mut next: BTreeMap<u32, u32> = BTreeMap::new();
    for ((a, b), _) in directed.iter() {
        if !directed.contains(b, a) && next.insert(a, b).is_some() {
            return Err(InvariantError::Pinched { node: a });
        }
    }
    let mut loops: Vec<Vec<u32>> = Vec::new();
    let mut seen = std::collections::BTreeSet::new();
    for &start in next.keys() {
        if seen.contains(&start) {
            continue;
        }
        let mut l = Vec::new();
        let mut c = start;
        while seen.insert(c) {
            l.push(c);
            c = *next
                .get(&c)
                .ok_or(InvariantError::OpenBoundary { node: c })?;
        }
        loops.push(l);
    }
    let area = |l: &Vec<u32>| polygon_area(l.iter().map(|&i| points[i as usize]));
    let outer = (0..loops.len())
        .max_by(|&a, &b| area(&loops[a]).total_cmp(&area(&loops[b])))
        .ok_or(InvariantError::Empty)?;
    loops.swap(0, outer);
    Ok(loops)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The thin annulus of reproducer R09 as one ring of `n` quads: outer
    /// circle of radius 1 and hole of radius 1 − h, `n` nodes each, h = 2π/n
    /// (so the quads are about square). Boundary nodes first, as the mesher
    /// numbers them.
    fn thin_annulus_ring(n: u32) -> QuadMesh {
        let tau = std::f64::consts::TAU;
        let h = tau / f64::from(n);
        let at = |r: f64, k: u32| {
            let a = tau * f64::from(k) / f64::from(n);
            Point::new(r * a.cos(), r * a.sin())
        };
        let mut nodes: Vec<Point> = (0..n).map(|k| at(1.0, k)).collect();
        nodes.extend((0..n).map(|k| at(1.0 - h, k)));
        let quads = (0..n)
            .map(|k| {
                let k1 = (k + 1) % n;
                [k, k1, n + k1, n + k]
            })
            .collect();
        QuadMesh {
            nodes,
            quads,
            loops: vec![(0..n).collect(), (n..2 * n).rev().collect()],
        }
    }

    #[test]
    fn a_thin_annulus_of_many_quads_passes_the_final_check() {
        // R09: the loops' plain shoelace sums, of about π each, were off by
        // 1e-12 together, 1.6e-9 of the domain's area of 6.6e-4, and a
        // relative tolerance of 1e-9 refused the mesh.
        thin_annulus_ring(60_000).check_finished().unwrap();
    }

    #[test]
    fn a_thin_annulus_short_of_one_quad_or_with_one_twice_is_refused() {
        // By the edge checks, and by the area check alone: one quad is
        // 1.7e-5 of the area.
        let mut m = thin_annulus_ring(60_000);
        m.quads.remove(12_345);
        assert!(m.check_invariants(true).is_err());
        assert!(matches!(m.check_area(), Err(InvariantError::Area { .. })));
        let mut m = thin_annulus_ring(60_000);
        m.quads.push(m.quads[12_345]);
        assert!(m.check_invariants(true).is_err());
        assert!(matches!(m.check_area(), Err(InvariantError::Area { .. })));
    }

    #[test]
    fn retain_quads_keeps_the_order_and_drops_unused_nodes() {
        // A 3 × 1 strip of unit squares; the middle one is dropped.
        let pts: Vec<Point> = (0..8)
            .map(|i| Point::new((i % 4) as f64, (i / 4) as f64))
            .collect();
        let quads = vec![[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6]];
        let mut m = QuadMesh::from_quads(pts, quads).unwrap();
        let before: Vec<[Point; 4]> = m.quads.iter().map(|q| m.corners(q)).collect();
        let former = m.retain_quads(&[true, false, true]);
        assert_eq!(former, vec![0, 2]);
        let after: Vec<[Point; 4]> = m.quads.iter().map(|q| m.corners(q)).collect();
        assert_eq!(after, vec![before[0], before[2]]);
        // Every node is a boundary node here, so none is dropped.
        assert_eq!(m.nodes.len(), 8);
    }

    #[test]
    fn sorting_spatially_keeps_the_mesh() {
        // A 6 × 6 grid whose interior nodes are numbered backwards.
        let n = 6;
        let mut pts: Vec<Point> = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                pts.push(Point::new(i as f64, j as f64));
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut quads = Vec::new();
        for j in (0..n).rev() {
            for i in (0..n).rev() {
                quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let mut m = QuadMesh::from_quads(pts, quads).unwrap();
        let shape = |m: &QuadMesh| {
            let mut s: Vec<[(u64, u64); 4]> = m
                .quads
                .iter()
                .map(|q| m.corners(q).map(|p| (p.x.to_bits(), p.y.to_bits())))
                .collect();
            s.sort();
            s
        };
        let before = shape(&m);
        let boundary: Vec<Point> = m.nodes[..m.n_boundary()].to_vec();
        m.sort_spatially();
        m.check_finished().unwrap();
        assert_eq!(shape(&m), before);
        assert_eq!(&m.nodes[..m.n_boundary()], &boundary[..]);
        // The first interior node is the one nearest the lower left corner,
        // and the quads come by their lowest corner.
        assert_eq!(m.nodes[m.n_boundary()], Point::new(1.0, 1.0));
        let lowest: Vec<u32> = m.quads.iter().map(|q| *q.iter().min().unwrap()).collect();
        assert!(lowest.windows(2).all(|w| w[0] <= w[1]));
    }
}

//! The domain to mesh: one outer loop and any number of hole loops of
//! straight segments (method §1).
//!
//! The given nodes are the boundary discretisation: the mesher never moves,
//! drops or adds one. [`Boundary::new`] validates the loops and orients them
//! so that the domain lies on the left of every directed edge (outer loop
//! counter-clockwise, holes clockwise). Every problem is reported with the
//! loop and the node (as numbered in the input) at fault.

use crate::geom::{orient, point_in_polygon, polygon_area, segments_intersect, Aabb, Point};
use serde::{Deserialize, Serialize};
use thiserror::Error;

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
    #[error("segment {segment} refers to node {node}, which does not exist")]
    BadSegmentIndex { segment: usize, node: i64 },
    #[error("node {node} ends an open chain: every node must join exactly two segments")]
    OpenChain { node: i64 },
    #[error("node {node} joins {degree} segments: loops may not branch")]
    Branching { node: i64, degree: usize },
    #[error("loop {loop_index} has only {nodes} nodes; a loop needs at least 3")]
    LoopTooShort { loop_index: usize, nodes: usize },
    #[error("loop {loop_index}: node {node} (almost) repeats the position of the node before it")]
    DuplicateNode { loop_index: usize, node: i64 },
    #[error("loop {loop_index} encloses no area (its nodes are collinear or fold back)")]
    ZeroArea { loop_index: usize },
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

impl Boundary {
    /// Validates `loops` over `points` and returns the oriented boundary with
    /// the outer loop (the one of largest area) first.
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
        if let Some(i) = points.iter().position(|p| !p.is_finite()) {
            return Err(BoundaryError::NonFinite { node: lab(i) });
        }
        let total: usize = loops.iter().map(Vec::len).sum();
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
            if let Some(&bad) = l.iter().find(|&&i| i >= points.len()) {
                return Err(BoundaryError::BadSegmentIndex {
                    segment: 0,
                    node: bad as i64,
                });
            }
        }
        // Consecutive nodes closer than a thousandth of the median segment
        // are the same node entered twice.
        let mut lens: Vec<f64> = loops
            .iter()
            .flat_map(|l| (0..l.len()).map(move |k| (l[k], l[(k + 1) % l.len()])))
            .map(|(a, b)| points[a].distance(points[b]))
            .collect();
        lens.sort_by(f64::total_cmp);
        let tol = 1e-3 * lens.get(lens.len() / 2).copied().unwrap_or(0.0);
        for (li, l) in loops.iter().enumerate() {
            for k in 0..l.len() {
                let (a, b) = (l[k], l[(k + 1) % l.len()]);
                if points[a].distance(points[b]) <= tol {
                    return Err(BoundaryError::DuplicateNode {
                        loop_index: li,
                        node: lab(b),
                    });
                }
            }
        }
        if total < 4 {
            return Err(BoundaryError::TooFewNodes { count: total });
        }
        let bb = Aabb::of(points.iter().copied()).ok_or(BoundaryError::Empty)?;
        let scale = bb.size().max_element();
        let areas: Vec<f64> = loops
            .iter()
            .map(|l| polygon_area(l.iter().map(|&i| points[i])))
            .collect();
        for (li, a) in areas.iter().enumerate() {
            if a.abs() <= 1e-12 * scale * scale || scale == 0.0 {
                return Err(BoundaryError::ZeroArea { loop_index: li });
            }
        }
        check_crossings(&points, &loops, &labels)?;
        let outer = (0..loops.len())
            .max_by(|&a, &b| areas[a].abs().total_cmp(&areas[b].abs()))
            .unwrap_or(0);
        let outer_pts: Vec<Point> = loops[outer].iter().map(|&i| points[i]).collect();
        let polys: Vec<Vec<Point>> = loops
            .iter()
            .map(|l| l.iter().map(|&i| points[i]).collect())
            .collect();
        for (li, l) in loops.iter().enumerate() {
            if li == outer {
                continue;
            }
            // Loops do not cross, so one node decides inside or outside.
            let p = points[l[0]];
            if !point_in_polygon(p, &outer_pts) {
                return Err(BoundaryError::HoleOutside { loop_index: li });
            }
            for (hj, hp) in polys.iter().enumerate() {
                if hj != li && hj != outer && point_in_polygon(p, hp) {
                    return Err(BoundaryError::NestedHole {
                        loop_index: li,
                        hole: hj,
                    });
                }
            }
        }
        if total % 2 == 1 {
            return Err(BoundaryError::OddNodeCount { count: total });
        }
        let mut ordered = Vec::with_capacity(loops.len());
        for (li, mut l) in loops.into_iter().enumerate() {
            let ccw = areas[li] > 0.0;
            if (li == outer) != ccw {
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
    for &(a, b) in segments {
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

/// Reports the first pair of segments that cross, touch or overlap, other
/// than consecutive segments meeting at their shared node. A uniform grid
/// keeps this near-linear in the number of segments.
fn check_crossings(
    points: &[Point],
    loops: &[Vec<usize>],
    labels: &[i64],
) -> Result<(), BoundaryError> {
    let lab = |i: usize| labels.get(i).copied().unwrap_or(i as i64 + 1);
    // segment k: (loop, position)
    let segs: Vec<(usize, usize)> = loops
        .iter()
        .enumerate()
        .flat_map(|(li, l)| (0..l.len()).map(move |k| (li, k)))
        .collect();
    let ends = |s: (usize, usize)| {
        let l = &loops[s.0];
        (l[s.1], l[(s.1 + 1) % l.len()])
    };
    let bb = Aabb::of(points.iter().copied()).ok_or(BoundaryError::Empty)?;
    let n = segs.len();
    let cells = ((n as f64).sqrt().ceil() as usize).clamp(1, 1024);
    let size = bb.size().max(Point::splat(f64::MIN_POSITIVE));
    let cell_of = |p: Point| {
        let c = ((p - bb.min) / size * cells as f64).floor();
        (
            (c.x.max(0.0) as usize).min(cells - 1),
            (c.y.max(0.0) as usize).min(cells - 1),
        )
    };
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); cells * cells];
    for (k, &s) in segs.iter().enumerate() {
        let (a, b) = ends(s);
        let (c0, c1) = (
            cell_of(points[a].min(points[b])),
            cell_of(points[a].max(points[b])),
        );
        for cy in c0.1..=c1.1 {
            for cx in c0.0..=c1.0 {
                grid[cy * cells + cx].push(k);
            }
        }
    }
    let mut pairs: Vec<(usize, usize)> = Vec::new();
    for cell in &grid {
        for (i, &s) in cell.iter().enumerate() {
            for &t in &cell[i + 1..] {
                pairs.push((s.min(t), s.max(t)));
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    for (s, t) in pairs {
        let (a, b) = ends(segs[s]);
        let (c, d) = ends(segs[t]);
        let (pa, pb, pc, pd) = (points[a], points[b], points[c], points[d]);
        let shared = if b == c {
            Some((pa, pb, pd))
        } else if d == a {
            Some((pc, pa, pb))
        } else {
            None
        };
        let bad = match shared {
            // Consecutive segments only clash when they fold back on each other.
            Some((p, q, r)) => orient(p, q, r) == 0.0 && (p - q).dot(r - q) > 0.0,
            None => segments_intersect(pa, pb, pc, pd),
        };
        if bad {
            return Err(BoundaryError::Crossing {
                loop_a: segs[s].0,
                node_a: lab(a),
                loop_b: segs[t].0,
                node_b: lab(c),
            });
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

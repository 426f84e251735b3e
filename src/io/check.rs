//! The checks of a quad mesh read from a file: a parseable file may still
//! hold quads that are not convex, that overlap or that lie in separate
//! pieces. A mesh passes when its nodes are finite, every quad is strictly
//! and measurably convex, every edge has at most two quads and then of
//! opposite orientations, its boundary loops form a valid boundary (one
//! outer loop counter-clockwise, holes inside it clockwise, no two loops
//! crossing or touching: [`Boundary::new`]) and the quads' areas add up to
//! the area the loops enclose. Together these rule out overlaps: the quads
//! then cover the domain exactly once.

use crate::boundary::{Boundary, BoundaryError, MAX_COORDINATE};
use crate::geom::{orient, Point};
use crate::mesh::{InvariantError, QuadMesh};
use thiserror::Error;

/// Why a mesh read from a file is not a valid quad mesh. Nodes and quads
/// carry the numbers (tags) they have in the file.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeshCheckError {
    #[error("node {node} has a non-finite coordinate")]
    NonFinite { node: u64 },
    #[error("node {node} has a coordinate of magnitude {value:e}, beyond ±1e150")]
    TooLarge { node: u64, value: f64 },
    #[error("quad {quad} is not strictly convex (corner at node {node})")]
    NotConvex { quad: u64, node: u64 },
    #[error("quad {quad} has a corner flat to rounding at node {node}")]
    FlatCorner { quad: u64, node: u64 },
    #[error("the edge from node {a} to node {b} belongs to more than two quads, or to two quads of the same orientation: the quads overlap")]
    EdgeOveruse { a: u64, b: u64 },
    #[error("node {node} is pinched: two boundary edges leave it")]
    Pinched { node: u64 },
    #[error("the boundary does not close at node {node}")]
    OpenBoundary { node: u64 },
    #[error("its boundary loops do not bound one domain ({0}): the quads overlap or the mesh is in separate pieces")]
    Boundary(BoundaryError),
    #[error("boundary loop {loop_index} (through node {node}) runs counter-clockwise inside the outer loop: the quads overlap or the mesh is in separate pieces")]
    InnerLoop { loop_index: usize, node: u64 },
    #[error("the quads cover an area of {covered}, but the boundary encloses {domain}: the quads overlap")]
    Area { covered: f64, domain: f64 },
    #[error("{0}")]
    Other(String),
}

/// True when a simple loop runs counter-clockwise: the sign of its corner
/// at the lowest-leftmost node, exactly.
fn is_ccw(p: &[Point]) -> bool {
    let n = p.len();
    let k = (0..n)
        .min_by(|&a, &b| {
            let c = |u: f64, v: f64| u.partial_cmp(&v).unwrap_or(std::cmp::Ordering::Equal);
            c(p[a].x, p[b].x).then(c(p[a].y, p[b].y))
        })
        .unwrap_or(0);
    orient(p[(k + n - 1) % n], p[k], p[(k + 1) % n]) > 0.0
}

/// A mesh invariant broken by `from_quads` or the edge checks, with the
/// file's numbers.
pub(crate) fn from_invariant(
    e: InvariantError,
    node: &dyn Fn(u32) -> u64,
    quad: &dyn Fn(usize) -> u64,
) -> MeshCheckError {
    use InvariantError as I;
    match e {
        I::NotConvex { quad: q, node: v } => MeshCheckError::NotConvex {
            quad: quad(q),
            node: node(v),
        },
        I::FlatCorner { quad: q, node: v } => MeshCheckError::FlatCorner {
            quad: quad(q),
            node: node(v),
        },
        I::EdgeOveruse { a, b, .. } => MeshCheckError::EdgeOveruse {
            a: node(a),
            b: node(b),
        },
        I::Pinched { node: v } => MeshCheckError::Pinched { node: node(v) },
        I::Area { covered, domain } => MeshCheckError::Area { covered, domain },
        I::OpenBoundary { node: v } => MeshCheckError::OpenBoundary { node: node(v) },
        other => MeshCheckError::Other(other.to_string()),
    }
}

/// Checks a mesh (see the module's documentation); `node` and `quad` give
/// the numbers of node ids and quad indices in messages.
pub fn check_mesh_labelled(
    m: &QuadMesh,
    node: &dyn Fn(u32) -> u64,
    quad: &dyn Fn(usize) -> u64,
) -> Result<(), MeshCheckError> {
    for (i, p) in m.nodes.iter().enumerate() {
        if !p.is_finite() {
            return Err(MeshCheckError::NonFinite {
                node: node(i as u32),
            });
        }
        let value = p.x.abs().max(p.y.abs());
        if value > MAX_COORDINATE {
            return Err(MeshCheckError::TooLarge {
                node: node(i as u32),
                value,
            });
        }
    }
    m.check_invariants(false)
        .map_err(|e| from_invariant(e, node, quad))?;
    m.check_no_flat_corner()
        .map_err(|e| from_invariant(e, node, quad))?;
    // The boundary loops as a boundary of their own.
    let mut ids: Vec<u32> = m.loops.iter().flatten().copied().collect();
    ids.sort_unstable();
    ids.dedup();
    let compact = |v: u32| ids.binary_search(&v).unwrap_or(0);
    let points: Vec<Point> = ids.iter().map(|&v| m.nodes[v as usize]).collect();
    let loops: Vec<Vec<usize>> = m
        .loops
        .iter()
        .map(|l| l.iter().map(|&v| compact(v)).collect())
        .collect();
    let labels: Vec<i64> = ids.iter().map(|&v| node(v) as i64).collect();
    let b = Boundary::new(points, loops, Some(labels)).map_err(MeshCheckError::Boundary)?;
    let outer_node = b.loops.first().and_then(|l| l.first()).map(|&i| ids[i]);
    for (k, l) in m.loops.iter().enumerate() {
        let p: Vec<Point> = l.iter().map(|&v| m.nodes[v as usize]).collect();
        let is_outer = outer_node.is_some_and(|v| l.contains(&v));
        if is_ccw(&p) != is_outer {
            return Err(MeshCheckError::InnerLoop {
                loop_index: k,
                node: node(l[0]),
            });
        }
    }
    // Up to the sums' rounding bounds (`AreaSum`), not a relative
    // tolerance, which the rounding of many thin quads can exceed.
    m.check_area().map_err(|e| from_invariant(e, node, quad))?;
    Ok(())
}

/// [`check_mesh_labelled`] with node ids and quad indices as numbers.
pub fn check_mesh(m: &QuadMesh) -> Result<(), MeshCheckError> {
    check_mesh_labelled(m, &|v| u64::from(v), &|k| k as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(nx: u32, ny: u32) -> (Vec<Point>, Vec<[u32; 4]>) {
        let mut pts = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                pts.push(Point::new(i as f64, j as f64));
            }
        }
        let id = |i: u32, j: u32| j * (nx + 1) + i;
        let mut quads = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (pts, quads)
    }

    #[test]
    fn a_grid_passes_far_from_the_origin_too() {
        let (pts, quads) = grid(3, 2);
        check_mesh(&QuadMesh::from_quads(pts.clone(), quads.clone()).unwrap()).unwrap();
        let far: Vec<Point> = pts.iter().map(|&p| p + Point::splat(1e8)).collect();
        check_mesh(&QuadMesh::from_quads(far, quads).unwrap()).unwrap();
    }

    #[test]
    fn overlapping_and_separate_quads_are_refused() {
        let p = |x, y| Point::new(x, y);
        // Two unit squares overlapping at a corner.
        let pts = vec![
            p(0., 0.),
            p(1., 0.),
            p(1., 1.),
            p(0., 1.),
            p(0.5, 0.5),
            p(1.5, 0.5),
            p(1.5, 1.5),
            p(0.5, 1.5),
        ];
        let m = QuadMesh::from_quads(pts.clone(), vec![[0, 1, 2, 3], [4, 5, 6, 7]]).unwrap();
        assert!(
            matches!(check_mesh(&m), Err(MeshCheckError::Boundary(_))),
            "{:?}",
            check_mesh(&m)
        );
        // A small square inside a large one: both loops counter-clockwise.
        let pts2 = vec![
            p(0., 0.),
            p(4., 0.),
            p(4., 4.),
            p(0., 4.),
            p(1., 1.),
            p(2., 1.),
            p(2., 2.),
            p(1., 2.),
        ];
        let m = QuadMesh::from_quads(pts2, vec![[0, 1, 2, 3], [4, 5, 6, 7]]).unwrap();
        assert!(matches!(
            check_mesh(&m),
            Err(MeshCheckError::InnerLoop { loop_index: 1, .. })
        ));
        // Two separate squares: the second is a "hole" outside the first.
        let pts3 = vec![
            p(0., 0.),
            p(1., 0.),
            p(1., 1.),
            p(0., 1.),
            p(3., 0.),
            p(4., 0.),
            p(4., 1.),
            p(3., 1.),
        ];
        let m = QuadMesh::from_quads(pts3, vec![[0, 1, 2, 3], [4, 5, 6, 7]]).unwrap();
        assert!(matches!(
            check_mesh(&m),
            Err(MeshCheckError::Boundary(BoundaryError::HoleOutside { .. }))
        ));
    }

    #[test]
    fn a_non_convex_quad_is_refused() {
        let p = |x, y| Point::new(x, y);
        let m = QuadMesh::from_quads(
            vec![p(0., 0.), p(2., 0.), p(0.5, 0.5), p(0., 2.)],
            vec![[0, 1, 2, 3]],
        )
        .unwrap();
        assert!(matches!(
            check_mesh(&m),
            Err(MeshCheckError::NotConvex { .. })
        ));
    }
}

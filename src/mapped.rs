//! Mapped (structured) quad meshing by transfinite interpolation: the
//! classic way to mesh four-sided blocks, used here to build the reference
//! meshes the models learn from (thesis §3.1.2 trains on "good" meshes;
//! method §3).
//!
//! A [`Block`] is a four-sided patch given by its four sides as curves on
//! `[0, 1]`; [`Block::grid`] places nodes by the Coons formula at
//! parameter values `u_i`, `v_j` (which carry the grading). [`merge`] joins
//! blocks that share sides into one [`QuadMesh`], fusing coincident nodes.

use crate::geom::Point;
use crate::mesh::{InvariantError, QuadMesh};
use std::collections::BTreeMap;

/// A curve on `[0, 1]`.
pub type Curve = Box<dyn Fn(f64) -> Point>;

/// A four-sided patch: `bottom(u)` from corner 00 to 10, `top(u)` from 01
/// to 11, `left(v)` from 00 to 01, `right(v)` from 10 to 11.
pub struct Block {
    pub bottom: Curve,
    pub top: Curve,
    pub left: Curve,
    pub right: Curve,
}

impl Block {
    /// The straight-sided block with corners `p00, p10, p11, p01`.
    pub fn straight(p00: Point, p10: Point, p11: Point, p01: Point) -> Block {
        let seg = |a: Point, b: Point| -> Curve { Box::new(move |t| a.lerp(b, t)) };
        Block {
            bottom: seg(p00, p10),
            top: seg(p01, p11),
            left: seg(p00, p01),
            right: seg(p10, p11),
        }
    }

    /// The Coons patch at `(u, v)`: [`coons`]' formula with the corner
    /// terms summed in the order 00, 10, 01, 11. The shipped reference
    /// meshes and the models fitted to them were made with this order;
    /// [`coons`]' order changes four of them and both shipped models at the
    /// rounding level, and with the default model the benchmark meshes.
    pub fn at(&self, u: f64, v: f64) -> Point {
        let (b, t, l, r) = (&self.bottom, &self.top, &self.left, &self.right);
        let (p00, p10, p01, p11) = (b(0.0), b(1.0), t(0.0), t(1.0));
        (1.0 - v) * b(u) + v * t(u) + (1.0 - u) * l(v) + u * r(v)
            - ((1.0 - u) * (1.0 - v) * p00
                + u * (1.0 - v) * p10
                + (1.0 - u) * v * p01
                + u * v * p11)
    }

    /// Quads of the grid over parameter values `us × vs` (see [`map_grid`]).
    pub fn grid(&self, us: &[f64], vs: &[f64]) -> Vec<[Point; 4]> {
        map_grid(us, vs, |u, v| self.at(u, v))
    }
}

/// The Coons patch (bilinearly blended transfinite interpolation) at
/// `(u, v)`: `sides` are the points of the bottom and top at `u` and of
/// the left and right at `v`, `corners` the corners 00, 10, 11 and 01
/// (counter-clockwise). Extraction's mapped closure places its grid nodes
/// with it; the sum's order is the one its meshes were made with.
#[inline]
pub fn coons(u: f64, v: f64, sides: [Point; 4], corners: [Point; 4]) -> Point {
    let [bottom, top, left, right] = sides;
    let [c00, c10, c11, c01] = corners;
    (1.0 - v) * bottom + v * top + (1.0 - u) * left + u * right
        - ((1.0 - u) * (1.0 - v) * c00 + u * (1.0 - v) * c10 + u * v * c11 + (1.0 - u) * v * c01)
}

/// Quads of the grid over parameter values `us × vs` (each increasing from
/// 0 to 1) under the map `f`, as corner positions; counter-clockwise when
/// `f` keeps orientation.
pub fn map_grid(us: &[f64], vs: &[f64], f: impl Fn(f64, f64) -> Point) -> Vec<[Point; 4]> {
    let cols = us.len();
    let pts: Vec<Point> = vs
        .iter()
        .flat_map(|&v| us.iter().map(move |&u| (u, v)))
        .map(|(u, v)| f(u, v))
        .collect();
    let mut out = Vec::with_capacity(cols.saturating_sub(1) * vs.len().saturating_sub(1));
    for j in 0..vs.len().saturating_sub(1) {
        for i in 0..cols.saturating_sub(1) {
            let at = |a: usize, b: usize| pts[b * cols + a];
            out.push([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    out
}

/// `cells + 1` parameter values on `[0, 1]` whose steps grow by `ratio`
/// (1: uniform).
pub fn graded(cells: usize, ratio: f64) -> Vec<f64> {
    let steps: Vec<f64> = (0..cells).map(|k| ratio.powi(k as i32)).collect();
    let total: f64 = steps.iter().sum();
    let mut v = Vec::with_capacity(cells + 1);
    let mut acc = 0.0;
    v.push(0.0);
    for s in &steps {
        acc += s;
        v.push(acc / total);
    }
    if let Some(last) = v.last_mut() {
        *last = 1.0;
    }
    v
}

/// One mesh from quads given by corner positions: nodes closer than
/// `tol` (relative to the extent) are fused.
pub fn merge(quads: &[[Point; 4]], tol: f64) -> Result<QuadMesh, InvariantError> {
    let extent = quads
        .iter()
        .flatten()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()))
        .max(1e-300);
    let q = tol * extent;
    let key = |p: Point| ((p.x / q).round() as i64, (p.y / q).round() as i64);
    let mut ids: BTreeMap<(i64, i64), u32> = BTreeMap::new();
    let mut points = Vec::new();
    let mut out = Vec::with_capacity(quads.len());
    for c in quads {
        out.push(c.map(|p| {
            *ids.entry(key(p)).or_insert_with(|| {
                points.push(p);
                (points.len() - 1) as u32
            })
        }));
    }
    QuadMesh::from_quads(points, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_blocks_share_a_side() {
        let a = Block::straight(
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        );
        let b = Block::straight(
            Point::new(1.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 1.0),
        );
        let u = graded(4, 1.2);
        assert_eq!(u.len(), 5);
        assert!((u[1] - 1.0 / (1.0 + 1.2 + 1.44 + 1.728)).abs() < 1e-12);
        let mut quads = a.grid(&u, &graded(3, 1.0));
        quads.extend(b.grid(&graded(4, 1.0), &graded(3, 1.0)));
        let m = merge(&quads, 1e-9).unwrap();
        m.check_finished().unwrap();
        assert_eq!(m.quads.len(), 24);
        assert_eq!(m.nodes.len(), 9 * 4);
        assert_eq!(m.loops.len(), 1);
        assert!((m.domain_area() - 2.0).abs() < 1e-12);
    }
}

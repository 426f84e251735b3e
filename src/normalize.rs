//! Normalisation of the reference point and its leading points (thesis
//! §3.2, Figure 31): translate P0 to the origin, scale by
//! `d = |P_r1 − P0|`, rotate so that P_r1 lands on `(1, 0)`. The domain then
//! lies locally above the x axis.

use crate::geom::Point;
use serde::{Deserialize, Serialize};

/// The similarity transform of one reference point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub origin: Point,
    /// `d = |P_r1 − P0|`.
    pub scale: f64,
    /// Unit vector from P0 towards P_r1.
    pub axis: Point,
}

impl Frame {
    /// The frame of reference point `p0` with first right leading point `r1`.
    pub fn new(p0: Point, r1: Point) -> Frame {
        let v = r1 - p0;
        let d = v.length();
        Frame {
            origin: p0,
            scale: d,
            axis: v / d,
        }
    }

    /// World → normalised.
    #[inline]
    pub fn to_local(&self, p: Point) -> Point {
        let q = (p - self.origin) / self.scale;
        Point::new(q.dot(self.axis), self.axis.perp_dot(q))
    }

    /// Normalised → world.
    #[inline]
    pub fn to_world(&self, q: Point) -> Point {
        self.origin + self.scale * (self.axis * q.x + self.axis.perp() * q.y)
    }
}

/// The normalised model input: `N` left and `N` right leading points
/// (`left[0] = P_l1`, `right[0] = P_r1 = (1, 0)`), P0 being the origin.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LeadingPoints {
    pub left: Vec<Point>,
    pub right: Vec<Point>,
}

impl LeadingPoints {
    /// Normalises world points `left = [P_l1..P_lN]`, `right = [P_r1..P_rN]`.
    pub fn normalise(frame: &Frame, left: &[Point], right: &[Point]) -> LeadingPoints {
        LeadingPoints {
            left: left.iter().map(|&p| frame.to_local(p)).collect(),
            right: right.iter().map(|&p| frame.to_local(p)).collect(),
        }
    }

    /// `N`, the number of leading points on each side.
    pub fn n(&self) -> usize {
        self.left.len()
    }

    /// The `2N + 1` input points in the thesis's order
    /// `P_lN, …, P_l1, P0, P_r1, …, P_rN`.
    pub fn thesis_order(&self) -> Vec<Point> {
        let mut v: Vec<Point> = self.left.iter().rev().copied().collect();
        v.push(Point::ZERO);
        v.extend_from_slice(&self.right);
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        let f = Frame::new(Point::new(1.0, 2.0), Point::new(1.5, 3.0));
        let p = Point::new(-0.3, 7.0);
        assert!((f.to_world(f.to_local(p)) - p).length() < 1e-12);
        assert!((f.to_local(Point::new(1.5, 3.0)) - Point::X).length() < 1e-12);
    }
}

//! The knowledge-based extraction rules of Zeng & Cheng (1993), thesis
//! §2.1.1 (Figures 15–16), as a [`Model`].
//!
//! With θ1 the front angle at P0, θ2 the angle at P_r1 and θ4 the angle at
//! P_l1, and U_c the upper bound of an element corner:
//!
//! - θ1 ≤ U_c and θ2 ≤ U_c: link P_l1 and P_r2 (one new line, type 1);
//!   symmetrically θ1 ≤ U_c and θ4 ≤ U_c links P_r1 and P_l2 (type 2);
//!   when both apply the sharper neighbour is closed;
//! - otherwise two new lines meet at the new node Pn, the new edges at P_r1
//!   and P_l1 turning by φ = π − θ1 (rule (b)): Pn completes the
//!   parallelogram on P_l1, P0, P_r1. Its height is the mean of the two
//!   front edges, so a row keeps an even size where the front is graded.

use super::{ElementType, Model, Prediction};
use crate::geom::{ccw_angle, Point};
use crate::normalize::LeadingPoints;
use serde::{Deserialize, Serialize};

/// Parameters of the rule model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RulesModel {
    /// U_c, the upper bound of an element corner, in degrees (default 135).
    pub upper_corner: f64,
}

impl RulesModel {
    pub const DEFAULT: RulesModel = RulesModel {
        upper_corner: 135.0,
    };
}

impl Default for RulesModel {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl Model for RulesModel {
    fn name(&self) -> &str {
        "rules"
    }

    fn leading_points(&self) -> Option<usize> {
        None
    }

    fn predict(&self, input: &LeadingPoints) -> Prediction {
        let uc = self.upper_corner.to_radians();
        let p0 = Point::ZERO;
        let r1 = input.right[0];
        let l1 = input.left[0];
        let theta1 = ccw_angle(p0, r1, l1);
        let theta2 = input
            .right
            .get(1)
            .map(|&r2| ccw_angle(r1, r2, p0))
            .unwrap_or(f64::INFINITY);
        let theta4 = input
            .left
            .get(1)
            .map(|&l2| ccw_angle(l1, p0, l2))
            .unwrap_or(f64::INFINITY);
        if theta1 <= uc {
            let right = theta2 <= uc;
            let left = theta4 <= uc;
            if right && (!left || theta2 <= theta4) {
                return Prediction {
                    element_type: ElementType::Right,
                    pn: input.right[1],
                };
            }
            if left {
                return Prediction {
                    element_type: ElementType::Left,
                    pn: input.left[1],
                };
            }
        }
        Prediction {
            element_type: ElementType::New,
            pn: parallelogram(l1, r1),
        }
    }
}

/// Pn for rule (b): the parallelogram on P_l1, P0 = origin, P_r1, with the
/// sides scaled to the mean front edge so the element stays near square.
pub fn parallelogram(l1: Point, r1: Point) -> Point {
    let (a, b) = (l1.length(), r1.length());
    let h = 0.5 * (a + b);
    l1 / a * h + r1 / b * h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(left: &[(f64, f64)], right: &[(f64, f64)]) -> LeadingPoints {
        LeadingPoints {
            left: left.iter().map(|&(x, y)| Point::new(x, y)).collect(),
            right: right.iter().map(|&(x, y)| Point::new(x, y)).collect(),
        }
    }

    #[test]
    fn straight_corner_gives_a_square() {
        let p = RulesModel::DEFAULT.predict(&input(&[(0., 1.), (0., 2.)], &[(1., 0.), (2., 0.)]));
        assert_eq!(p.element_type, ElementType::New);
        assert!((p.pn - Point::new(1., 1.)).length() < 1e-12);
    }

    #[test]
    fn two_right_angles_close_the_strip() {
        // P0 and P_r1 are both square corners: link P_l1 to P_r2.
        let p = RulesModel::DEFAULT.predict(&input(&[(0., 1.), (0., 2.)], &[(1., 0.), (1., 1.)]));
        assert_eq!(p.element_type, ElementType::Right);
        let p = RulesModel::DEFAULT.predict(&input(&[(0., 1.), (1., 1.)], &[(1., 0.), (2., 0.)]));
        assert_eq!(p.element_type, ElementType::Left);
    }
}

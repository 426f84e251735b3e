//! One training sample (thesis §3.1.3): the normalised front path
//! `P_lN..P_l1, P0, P_r1..P_rN` around a reference point together with the
//! element cut there, `(type, Pn)`, and the checks a sample passes.
//!
//! It sits with the models because a model file's correction memory is kept
//! as samples and extraction records its steps as samples; collecting
//! samples from meshes and training sets are in [`crate::samples`], which
//! re-exports these items.

use super::ElementType;
use crate::geom::Point;
use crate::normalize::{Frame, LeadingPoints};
use serde::{Deserialize, Serialize};

/// Where a sample came from.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Source {
    /// Element `element` (0-based) of the mesh in `file`.
    Mesh { file: String, element: usize },
    /// An element corrected (or accepted) by the user at one step.
    Correction,
}

/// One training sample in the normalised frame (P0 at the origin, P_r1 at
/// `(1, 0)`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    pub input: LeadingPoints,
    pub element_type: ElementType,
    /// Pn: the new node for type 0, P_r2 for type 1, P_l2 for type 2.
    pub pn: Point,
    pub source: Source,
}

impl Sample {
    /// The sample of one extraction step from world points: the front path
    /// `left = [P_l1..P_lN]`, `p0`, `right = [P_r1..P_rN]` and the element's
    /// Pn (world). Returns `None` when `P_r1` coincides with P0.
    pub fn from_front(
        left: &[Point],
        p0: Point,
        right: &[Point],
        element_type: ElementType,
        pn: Point,
        source: Source,
    ) -> Option<Sample> {
        let r1 = *right.first()?;
        if (r1 - p0).length() <= 0.0 {
            return None;
        }
        let frame = Frame::new(p0, r1);
        Some(Sample {
            input: LeadingPoints::normalise(&frame, left, right),
            element_type,
            pn: frame.to_local(pn),
            source,
        })
    }

    /// `N`, leading points per side.
    pub fn n(&self) -> usize {
        self.input.n()
    }

    /// The model inputs without the constants P0 and P_r1, in the thesis's
    /// order `P_lN..P_l1, P_r2..P_rN` (`2N − 1` points).
    pub fn variable_points(&self) -> Vec<Point> {
        variable_points(&self.input)
    }
}

/// The inputs of `lp` that are not constant after normalisation, in the
/// thesis's order `P_lN..P_l1, P_r2..P_rN`.
pub fn variable_points(lp: &LeadingPoints) -> Vec<Point> {
    let mut v: Vec<Point> = lp.left.iter().rev().copied().collect();
    v.extend_from_slice(lp.right.get(1..).unwrap_or(&[]));
    v
}

/// The names of [`variable_points`] for `N` leading points per side:
/// `l3, l2, l1, r2, r3` for `N = 3`.
pub fn variable_names(n: usize) -> Vec<String> {
    let mut v: Vec<String> = (1..=n).rev().map(|k| format!("l{k}")).collect();
    v.extend((2..=n).map(|k| format!("r{k}")));
    v
}

/// The largest magnitude of a normalised coordinate in a training set: the
/// frame's unit is `|P0 P_r1|`, so a leading point a million such units
/// away is no mesh's, and larger values overflow the fits' sums of squares.
pub const MAX_SAMPLE_COORDINATE: f64 = 1e6;

/// Why a value cannot be a sample's coordinate, if it cannot.
pub(crate) fn bad_coordinate(v: f64) -> Option<String> {
    if !v.is_finite() {
        Some("is not finite".into())
    } else if v.abs() > MAX_SAMPLE_COORDINATE {
        Some(format!(
            "= {v:e} is out of range: normalised coordinates lie within ±{MAX_SAMPLE_COORDINATE:e}"
        ))
    } else {
        None
    }
}

/// The problem of one sample in a set of `points` input points, if any:
/// its leading points do not number `N` on each side, or a coordinate is
/// not finite or out of range ([`MAX_SAMPLE_COORDINATE`]).
pub fn sample_problem(s: &Sample, points: usize) -> Option<String> {
    let n = points.saturating_sub(1) / 2;
    for (side, pts) in [("left", &s.input.left), ("right", &s.input.right)] {
        if pts.len() != n {
            return Some(format!(
                "{} {side} leading points, where {points} input points need {n}",
                pts.len()
            ));
        }
    }
    let names = csv_header(n);
    let coords = s
        .input
        .thesis_order()
        .into_iter()
        .enumerate()
        .flat_map(|(k, p)| [(2 * k, p.x), (2 * k + 1, p.y)])
        .chain([(2 * points + 1, s.pn.x), (2 * points + 2, s.pn.y)]);
    for (k, v) in coords {
        if let Some(why) = bad_coordinate(v) {
            return Some(format!("{} {why}", names[k]));
        }
    }
    None
}

/// The CSV header of a training set of `N = n` leading points a side: the
/// thesis's Table 3 column order (`xlN, ylN, …, x0, y0, xr1, yr1, …, type,
/// xn, yn`), then the source.
pub fn csv_header(n: usize) -> Vec<String> {
    let mut h = Vec::new();
    for k in (1..=n).rev() {
        h.push(format!("xl{k}"));
        h.push(format!("yl{k}"));
    }
    h.extend(["x0".into(), "y0".into()]);
    for k in 1..=n {
        h.push(format!("xr{k}"));
        h.push(format!("yr{k}"));
    }
    h.extend(["type", "xn", "yn", "source", "element"].map(String::from));
    h
}

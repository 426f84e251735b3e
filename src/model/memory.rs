//! Corrections that stick: a nearest-neighbour memory of the user's
//! corrections, layered over a global model (thesis §2.2.2, §5.3: the
//! corrected pattern joins the model, and applying the model again gives
//! the corrected element).
//!
//! Why a memory and not a weighted sample in the global fit: a correction
//! is one sample among hundreds of thousands, and the global forms are
//! smooth (a quadratic, the thesis's sums of sigmoids): one sample cannot
//! move them at its input, and weighting it until it does bends the whole
//! form, so every other prediction moves too. The memory instead
//!
//! - reproduces a correction exactly at its input (type and Pn), and at
//!   inputs within half the radius of it (the same front met again, to
//!   rounding);
//! - moves inputs between half the radius and the radius
//!   ([`CorrectionMemory::radius`]) towards it, the more the nearer
//!   ([`weight`]);
//! - leaves every other input's prediction as the global model gives it,
//!   to the bit, so that a refit with nothing corrected is the global
//!   model and a correction cannot spoil what it is far from.
//!
//! Distances are measured in the normalised input space: the root mean
//! square distance of the leading points that vary (every one but P0 and
//! P_r1, [`distance`]).

use super::sample::{variable_points, Sample};
use super::{ElementType, Prediction};
use crate::geom::Point;
use crate::normalize::LeadingPoints;
use serde::{Deserialize, Serialize};

/// The default radius of a correction, in normalised units (root mean
/// square distance of the varying leading points). It is under the
/// distance between the inputs of consecutive elements along a front
/// (about 0.03 along the annulus example's first layer), so that a
/// correction changes the element it was made at and fronts as alike as
/// that, not its neighbours: after a reset the run comes to the same place
/// over the same front and takes the corrected element there. A wider
/// radius spreads a correction over a family of fronts.
pub const DEFAULT_RADIUS: f64 = 0.025;

/// The user's corrections with the radius each reaches.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CorrectionMemory {
    /// Inputs farther than this from every correction are not touched.
    pub radius: f64,
    /// The corrections, in the order they were made (a later one at the
    /// same input wins).
    pub samples: Vec<Sample>,
}

impl Default for CorrectionMemory {
    fn default() -> Self {
        CorrectionMemory {
            radius: DEFAULT_RADIUS,
            samples: Vec::new(),
        }
    }
}

/// The distance of two inputs with the same number of leading points: the
/// root mean square distance of their varying points (infinite when the
/// counts differ).
pub fn distance(a: &LeadingPoints, b: &LeadingPoints) -> f64 {
    if a.n() != b.n() {
        return f64::INFINITY;
    }
    let (pa, pb) = (variable_points(a), variable_points(b));
    let sum: f64 = pa
        .iter()
        .zip(&pb)
        .map(|(p, q)| p.distance_squared(*q))
        .sum();
    (sum / pa.len().max(1) as f64).sqrt()
}

/// The weight of a correction at distance `d` with radius `r`: 1 up to
/// half the radius, then falling smoothly (a smoothstep) to 0 at the
/// radius, 0 beyond.
pub fn weight(d: f64, r: f64) -> f64 {
    if d.is_nan() || d >= r || r <= 0.0 {
        return 0.0;
    }
    let core = 0.5 * r;
    if d <= core {
        return 1.0;
    }
    let t = (d - core) / (r - core);
    1.0 - t * t * (3.0 - 2.0 * t)
}

/// The weight above which a correction's type replaces the model's.
pub const TYPE_WEIGHT: f64 = 0.5;

/// Pn of a correction's element type for `input`: the corrected Pn for
/// type 0; the input's own P_r2 or P_l2 for types 1 and 2 (the element
/// closes onto that node wherever it is).
fn pn_at(c: &Sample, input: &LeadingPoints) -> Point {
    match c.element_type {
        ElementType::New => c.pn,
        ElementType::Right => input.right.get(1).copied().unwrap_or(c.pn),
        ElementType::Left => input.left.get(1).copied().unwrap_or(c.pn),
    }
}

impl CorrectionMemory {
    pub fn new(radius: f64, samples: Vec<Sample>) -> CorrectionMemory {
        CorrectionMemory { radius, samples }
    }

    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// The correction nearest to `input` and its distance (among equally
    /// near ones, the latest).
    pub fn nearest(&self, input: &LeadingPoints) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (k, s) in self.samples.iter().enumerate() {
            let d = distance(&s.input, input);
            if best.is_none_or(|(_, b)| d <= b) {
                best = Some((k, d));
            }
        }
        best.filter(|(_, d)| d.is_finite())
    }

    /// The global model's prediction `base` at `input` with the memory
    /// applied: unchanged outside every correction's radius; inside the
    /// nearest one's, Pn moved towards the correction's by its
    /// [`weight`], and its type taken once the weight reaches
    /// [`TYPE_WEIGHT`]. At a correction's input this is the correction.
    pub fn apply(&self, input: &LeadingPoints, base: Prediction) -> Prediction {
        let Some((k, d)) = self.nearest(input) else {
            return base;
        };
        let w = weight(d, self.radius);
        if w <= 0.0 {
            return base;
        }
        let c = &self.samples[k];
        let target = pn_at(c, input);
        Prediction {
            element_type: if w >= TYPE_WEIGHT {
                c.element_type
            } else {
                base.element_type
            },
            pn: base.pn + (target - base.pn) * w,
        }
    }

    /// Why the memory cannot be used with a model of `n` leading points a
    /// side, if it cannot: a radius that is not positive and finite, or a
    /// correction that is not a well-formed sample of `2n + 1` points.
    pub fn problem(&self, n: usize) -> Option<String> {
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Some(format!(
                "correction radius {} is not a positive number",
                self.radius
            ));
        }
        self.samples.iter().enumerate().find_map(|(k, s)| {
            super::sample::sample_problem(s, 2 * n + 1)
                .map(|msg| format!("correction {}: {msg}", k + 1))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::sample::Source;

    fn input(dy: f64) -> LeadingPoints {
        let p = Point::new;
        LeadingPoints {
            left: vec![p(0.0, 1.0 + dy), p(0.0, 2.0), p(0.0, 3.0)],
            right: vec![p(1.0, 0.0), p(2.0, 0.0), p(3.0, 0.0)],
        }
    }

    fn correction(dy: f64, t: ElementType, pn: Point) -> Sample {
        Sample {
            input: input(dy),
            element_type: t,
            pn,
            source: Source::Correction,
        }
    }

    const BASE: Prediction = Prediction {
        element_type: ElementType::New,
        pn: Point::new(1.0, 1.0),
    };

    #[test]
    fn distance_is_the_rms_of_the_varying_points() {
        // One of the five varying points moved by 0.5.
        let d = distance(&input(0.0), &input(0.5));
        assert!((d - (0.25f64 / 5.0).sqrt()).abs() < 1e-12, "{d}");
        assert_eq!(distance(&input(0.2), &input(0.2)), 0.0);
        let short = LeadingPoints {
            left: vec![Point::new(0.0, 1.0), Point::new(0.0, 2.0)],
            right: vec![Point::X, Point::new(2.0, 0.0)],
        };
        assert_eq!(distance(&input(0.0), &short), f64::INFINITY);
    }

    #[test]
    fn weight_falls_from_one_to_zero_at_the_radius() {
        assert_eq!(weight(0.0, 0.1), 1.0);
        assert_eq!(weight(0.05, 0.1), 1.0);
        assert!((weight(0.075, 0.1) - 0.5).abs() < 1e-12);
        assert!(weight(0.06, 0.1) > weight(0.07, 0.1));
        assert_eq!(weight(0.1, 0.1), 0.0);
        assert_eq!(weight(0.3, 0.1), 0.0);
        assert_eq!(weight(f64::NAN, 0.1), 0.0);
    }

    #[test]
    fn a_correction_is_reproduced_nearby_inputs_move_and_far_ones_do_not() {
        let pn = Point::new(1.3, 0.8);
        let m = CorrectionMemory::new(0.1, vec![correction(0.0, ElementType::New, pn)]);
        // At the correction: exactly the correction.
        let at = m.apply(&input(0.0), BASE);
        assert_eq!(at.element_type, ElementType::New);
        assert!((at.pn - pn).length() < 1e-12);
        // Within half the radius (RMS 0.045): the correction too.
        let core = m.apply(&input(0.1), BASE);
        assert!((core.pn - pn).length() < 1e-12);
        // Nearby (RMS 0.067): between the model's Pn and the correction's.
        let near = m.apply(&input(0.15), BASE);
        let (before, after) = ((BASE.pn - pn).length(), (near.pn - pn).length());
        assert!(after < before && after > 0.0, "{after} vs {before}");
        // Far (RMS 0.13): the model's own prediction, to the bit.
        assert_eq!(m.apply(&input(0.3), BASE), BASE);
        // An empty memory never changes anything.
        assert_eq!(CorrectionMemory::default().apply(&input(0.0), BASE), BASE);
    }

    #[test]
    fn a_type_correction_takes_over_near_its_input_and_the_latest_wins() {
        let m = CorrectionMemory::new(
            0.1,
            vec![
                correction(0.0, ElementType::New, Point::new(5.0, 5.0)),
                correction(0.0, ElementType::Right, Point::new(2.0, 0.0)),
            ],
        );
        let at = m.apply(&input(0.0), BASE);
        assert_eq!(at.element_type, ElementType::Right);
        assert!((at.pn - Point::new(2.0, 0.0)).length() < 1e-12);
        // Near the edge of the radius the weight is small: the model's type
        // stays.
        let edge = m.apply(&input(0.2), BASE);
        assert_eq!(edge.element_type, ElementType::New);
    }

    #[test]
    fn problems_are_named() {
        let mut m = CorrectionMemory::new(0.0, vec![]);
        assert!(m.problem(3).is_some_and(|p| p.contains("radius")));
        m.radius = 0.1;
        assert_eq!(m.problem(3), None);
        m.samples
            .push(correction(0.0, ElementType::New, Point::new(1.0, 1.0)));
        assert_eq!(m.problem(3), None);
        assert!(m.problem(2).is_some_and(|p| p.starts_with("correction 1")));
    }
}

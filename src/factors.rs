//! Critical factors (thesis §4.2; method §4): which leading points matter.
//!
//! Per output (type, Xn, Yn) a linear model `c + Σ α_i X_i + β_i Y_i` over
//! the leading points but P0 and P_r1 is fitted by least squares; the
//! weight of point i is `|α_i + β_i| / 2`, shown as a percentage of the sum
//! of weights. A symmetric pair (P_lk, P_rk) whose points are both under
//! 5 % in every output is not critical (the thesis's verdict on the
//! outermost pair: dropped at 9 and 11 input points, kept at 7).

use crate::fit::{lstsq, FitError};
use crate::samples::{variable_names, variable_points, TrainingSet};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// The thesis's threshold of a non-critical point, in percent.
pub const CRITICAL_PERCENT: f64 = 5.0;

/// Weights of the leading points for one input-point count.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Factors {
    pub points: usize,
    pub samples: usize,
    /// Point names in the thesis's order (`l3, l2, l1, r2, r3` at 7).
    pub names: Vec<String>,
    /// Percentages per point, for type, Xn and Yn.
    #[serde(rename = "type")]
    pub type_: Vec<f64>,
    pub xn: Vec<f64>,
    pub yn: Vec<f64>,
}

impl Factors {
    /// Percentages of the outermost pair `(l_N, r_N)` per output
    /// (type, Xn, Yn).
    pub fn outermost(&self) -> [(f64, f64); 3] {
        let last = self.names.len() - 1;
        [&self.type_, &self.xn, &self.yn].map(|v| (v[0], v[last]))
    }

    /// True when the outermost pair is under 5 % in every output, so it is
    /// not a critical factor.
    pub fn outermost_negligible(&self) -> bool {
        self.outermost()
            .iter()
            .all(|&(l, r)| l < CRITICAL_PERCENT && r < CRITICAL_PERCENT)
    }

    /// A text table: one row per output, one column per point.
    pub fn table(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{} input points, {} samples (weights in %)",
            self.points, self.samples
        );
        let _ = write!(s, "{:<6}", "output");
        for n in &self.names {
            let _ = write!(s, " {n:>6}");
        }
        let _ = writeln!(s);
        for (name, v) in [("type", &self.type_), ("Xn", &self.xn), ("Yn", &self.yn)] {
            let _ = write!(s, "{name:<6}");
            for x in v {
                let _ = write!(s, " {x:>6.2}");
            }
            let _ = writeln!(s);
        }
        let _ = writeln!(
            s,
            "outermost pair {}/{}: {}",
            self.names[0],
            self.names[self.names.len() - 1],
            if self.outermost_negligible() {
                "under 5 % in every output: not critical"
            } else {
                "5 % or more in some output: critical"
            }
        );
        s
    }
}

/// The critical-factor weights of a training set.
pub fn factors(set: &TrainingSet) -> Result<Factors, FitError> {
    // Every sample checked (N points a side, finite coordinates in range),
    // so that the rows below all have the same length.
    crate::fit::check_set(set)?;
    let n = set.n();
    let k = 2 * n - 1;
    let m = set.len();
    if m < 2 * k + 1 {
        return Err(FitError::TooFew {
            form: "linear factor",
            found: m,
            needed: 2 * k + 1,
        });
    }
    let mut rows = Vec::with_capacity(m * (2 * k + 1));
    for s in &set.samples {
        rows.push(1.0);
        rows.extend(variable_points(&s.input).iter().flat_map(|p| [p.x, p.y]));
    }
    let x = DMatrix::from_row_slice(m, 2 * k + 1, &rows);
    let weights = |y: DVector<f64>, what| -> Result<Vec<f64>, FitError> {
        let w = lstsq(&x, &y, what)?;
        let raw: Vec<f64> = (0..k)
            .map(|i| (w[1 + 2 * i] + w[2 + 2 * i]).abs() / 2.0)
            .collect();
        let total: f64 = raw.iter().sum();
        Ok(raw
            .iter()
            .map(|v| if total > 0.0 { 100.0 * v / total } else { 0.0 })
            .collect())
    };
    let s = &set.samples;
    Ok(Factors {
        points: set.points,
        samples: m,
        names: variable_names(n),
        type_: weights(
            DVector::from_iterator(m, s.iter().map(|s| s.element_type.number() as f64)),
            "type",
        )?,
        xn: weights(DVector::from_iterator(m, s.iter().map(|s| s.pn.x)), "Xn")?,
        yn: weights(DVector::from_iterator(m, s.iter().map(|s| s.pn.y)), "Yn")?,
    })
}

/// The set cut down to `points` input points: each sample keeps its inner
/// leading points; duplicates made by the cut are dropped. `None` when
/// `points` is more than the set has.
pub fn truncated(set: &TrainingSet, points: usize) -> Option<TrainingSet> {
    if points > set.points || points < 5 || points % 2 == 0 {
        return None;
    }
    let n = (points - 1) / 2;
    let mut out = TrainingSet::new(points);
    out.samples = set
        .samples
        .iter()
        .map(|s| {
            let mut c = s.clone();
            c.input.left.truncate(n);
            c.input.right.truncate(n);
            c
        })
        .collect();
    out.dedup();
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;
    use crate::model::ElementType;
    use crate::samples::{Sample, Source};

    #[test]
    fn weights_follow_the_coefficients() {
        // Xn = 3 X_l1 + Y_r2 exactly.
        let mut set = TrainingSet::new(5);
        for input in crate::fit::random_inputs(2, 200, 5) {
            let pn = Point::new(3.0 * input.left[0].x + input.right[1].y, 0.0);
            set.samples.push(Sample {
                input,
                element_type: ElementType::New,
                pn,
                source: Source::Correction,
            });
        }
        let f = factors(&set).unwrap();
        assert_eq!(f.names, ["l2", "l1", "r2"]);
        // |3 + 0| / 2 = 1.5 and |0 + 1| / 2 = 0.5: 75 % and 25 %.
        assert!((f.xn[1] - 75.0).abs() < 1e-6, "{:?}", f.xn);
        assert!((f.xn[2] - 25.0).abs() < 1e-6);
        assert!(f.xn[0].abs() < 1e-6);
        assert!(truncated(&set, 7).is_none());
        assert_eq!(truncated(&set, 5).unwrap().len(), 200);
        // A sample short of a right point is refused, not a panic.
        set.samples[7].input.right.pop();
        assert!(matches!(
            factors(&set),
            Err(FitError::BadSample { index: 8, .. })
        ));
    }
}

//! Fit figures (thesis §4.3.1; method §4): `SSE = Σ(y − ŷ)²`,
//! `RMSE = √(SSE/n)`, `R` the Pearson correlation of y and ŷ,
//! `DC = 1 − SSE/SST`; for the type also the accuracy and the confusion
//! matrix. Laid out like thesis Table 8 by [`FitReport::table`].

use super::Form;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// Figures of one output on one set of samples.
///
/// Every figure is finite for finite data: with a constant output (one
/// sample, or every sample of one type) `R` and `DC` are 1 when the
/// predictions are exact and 0 otherwise. A figure that is not finite all
/// the same (sums overflowing) is left out of JSON, never written as
/// `null`, and a missing or `null` figure reads as NaN: a model file's
/// figures are information and never stop it from loading.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Figures {
    pub n: usize,
    #[serde(
        default = "nan",
        skip_serializing_if = "not_finite",
        deserialize_with = "lenient"
    )]
    pub sse: f64,
    #[serde(
        default = "nan",
        skip_serializing_if = "not_finite",
        deserialize_with = "lenient"
    )]
    pub rmse: f64,
    #[serde(
        default = "nan",
        skip_serializing_if = "not_finite",
        deserialize_with = "lenient"
    )]
    pub r: f64,
    #[serde(
        default = "nan",
        skip_serializing_if = "not_finite",
        deserialize_with = "lenient"
    )]
    pub dc: f64,
}

fn nan() -> f64 {
    f64::NAN
}

fn not_finite(v: &f64) -> bool {
    !v.is_finite()
}

/// A figure, `null` reading as NaN (files written before figures were
/// always finite).
fn lenient<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

impl Figures {
    /// Figures of predictions `yhat` of `y`.
    pub fn of(y: &[f64], yhat: &[f64]) -> Figures {
        let n = y.len();
        if n == 0 {
            return Figures::default();
        }
        let nf = n as f64;
        let my = y.iter().sum::<f64>() / nf;
        let mh = yhat.iter().sum::<f64>() / nf;
        let (mut sse, mut sst, mut sxy, mut shh) = (0.0, 0.0, 0.0, 0.0);
        for (a, b) in y.iter().zip(yhat) {
            sse += (a - b) * (a - b);
            sst += (a - my) * (a - my);
            sxy += (a - my) * (b - mh);
            shh += (b - mh) * (b - mh);
        }
        let r = if sst > 0.0 && shh > 0.0 {
            sxy / (sst * shh).sqrt()
        } else if sse == 0.0 {
            1.0
        } else {
            0.0
        };
        Figures {
            n,
            sse,
            rmse: (sse / nf).sqrt(),
            r,
            // A constant output has no variance to explain: DC is 1 for
            // exact predictions and 0 otherwise (as R is).
            dc: if sst > 0.0 {
                1.0 - sse / sst
            } else if sse == 0.0 {
                1.0
            } else {
                0.0
            },
        }
    }
}

/// Figures of the type output: the regression figures of its raw value
/// (the thesis's score P, or the classifier's expected type), and the
/// accuracy and confusion matrix of the type it selects.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TypeFigures {
    #[serde(flatten)]
    pub figures: Figures,
    #[serde(
        default = "nan",
        skip_serializing_if = "not_finite",
        deserialize_with = "lenient"
    )]
    pub accuracy: f64,
    /// `confusion[actual][predicted]`.
    pub confusion: [[usize; 3]; 3],
}

impl TypeFigures {
    pub fn of(y: &[u8], value: &[f64], predicted: &[u8]) -> TypeFigures {
        let yf: Vec<f64> = y.iter().map(|&t| t as f64).collect();
        let mut confusion = [[0usize; 3]; 3];
        for (&a, &p) in y.iter().zip(predicted) {
            confusion[a as usize][p as usize] += 1;
        }
        let hits: usize = (0..3).map(|k| confusion[k][k]).sum();
        TypeFigures {
            figures: Figures::of(&yf, value),
            accuracy: if y.is_empty() {
                0.0
            } else {
                hits as f64 / y.len() as f64
            },
            confusion,
        }
    }
}

/// One output on the training samples and on held-out samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Split<T> {
    pub train: T,
    pub holdout: T,
}

/// How well a fitted model fits (thesis Table 8, plus held-out figures
/// from k-fold cross-validation with a fixed seed).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    pub form: Form,
    pub points: usize,
    pub samples: usize,
    /// Folds of the held-out figures (each sample is predicted once by the
    /// model fitted on the other folds).
    pub folds: usize,
    pub seed: u64,
    #[serde(rename = "type")]
    pub type_: Split<TypeFigures>,
    pub xn: Split<Figures>,
    pub yn: Split<Figures>,
}

impl FitReport {
    /// A single score to choose between forms: held-out type accuracy
    /// plus the held-out R of Xn and Yn.
    pub fn score(&self) -> f64 {
        self.type_.holdout.accuracy + self.xn.holdout.r + self.yn.holdout.r
    }

    /// The figures as a text table in the layout of thesis Table 8.
    pub fn table(&self) -> String {
        let mut s = String::new();
        // With no folds the held-out figures are the training figures
        // again: they are left out.
        let held_out = self.folds > 0;
        let _ = writeln!(
            s,
            "form {}, {} input points, {} samples, {}",
            self.form.name(),
            self.points,
            self.samples,
            if held_out {
                format!("{}-fold held-out (seed {})", self.folds, self.seed)
            } else {
                "no held-out figures".to_string()
            }
        );
        let _ = writeln!(
            s,
            "{:<6} {:<8} {:>12} {:>8} {:>8} {:>8} {:>9}",
            "output", "set", "SSE", "RMSE", "R", "DC", "accuracy"
        );
        let mut row = |name: &str, set: &str, f: &Figures, acc: Option<f64>| {
            let _ = writeln!(
                s,
                "{:<6} {:<8} {:>12.4} {:>8.4} {:>8.4} {:>8.4} {:>9}",
                name,
                set,
                f.sse,
                f.rmse,
                f.r,
                f.dc,
                acc.map(|a| format!("{:.2}%", 100.0 * a))
                    .unwrap_or_default()
            );
        };
        let (tt, th) = (&self.type_.train, &self.type_.holdout);
        let outputs = [
            (
                "type",
                (&tt.figures, Some(tt.accuracy)),
                (&th.figures, Some(th.accuracy)),
            ),
            ("Xn", (&self.xn.train, None), (&self.xn.holdout, None)),
            ("Yn", (&self.yn.train, None), (&self.yn.holdout, None)),
        ];
        for (name, (train, train_acc), (holdout, holdout_acc)) in outputs {
            row(name, "train", train, train_acc);
            if held_out {
                row(name, "held-out", holdout, holdout_acc);
            }
        }
        if !held_out {
            return s;
        }
        let c = &self.type_.holdout.confusion;
        let _ = writeln!(
            s,
            "held-out confusion (rows: actual type 0,1,2; columns: predicted)"
        );
        for (k, r) in c.iter().enumerate() {
            let _ = writeln!(s, "  {k}: {:>8} {:>8} {:>8}", r[0], r[1], r[2]);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perfect_and_constant_predictions() {
        let y = [1.0, 2.0, 3.0, 4.0];
        let f = Figures::of(&y, &y);
        assert_eq!((f.sse, f.rmse, f.r, f.dc), (0.0, 0.0, 1.0, 1.0));
        let f = Figures::of(&y, &[2.5; 4]);
        assert_eq!(f.sse, 5.0);
        assert_eq!(f.r, 0.0);
        assert!((f.dc - 0.0).abs() < 1e-12);
    }

    #[test]
    fn constant_outputs_have_finite_figures() {
        let f = Figures::of(&[1.0, 1.0, 1.0], &[1.0, 0.5, 1.5]);
        assert_eq!((f.r, f.dc), (0.0, 0.0));
        let f = Figures::of(&[2.0], &[2.0]);
        assert_eq!((f.r, f.dc), (1.0, 1.0));
        let json = serde_json::to_string(&Figures::of(&[0.0], &[1.0])).unwrap();
        assert!(!json.contains("null"), "{json}");
        // A figure that is not finite is left out, and reads back as NaN;
        // so does `null`.
        let odd = Figures {
            sse: f64::INFINITY,
            ..Figures::default()
        };
        let json = serde_json::to_string(&odd).unwrap();
        assert!(!json.contains("sse") && !json.contains("null"), "{json}");
        assert!(serde_json::from_str::<Figures>(&json).unwrap().sse.is_nan());
        let back: Figures =
            serde_json::from_str(r#"{"n":1,"sse":0,"rmse":0,"r":1,"dc":null}"#).unwrap();
        assert!(back.dc.is_nan());
    }

    #[test]
    fn confusion_counts() {
        let t = TypeFigures::of(&[0, 1, 2, 2], &[0.0, 1.0, 2.0, 1.0], &[0, 1, 2, 1]);
        assert_eq!(t.accuracy, 0.75);
        assert_eq!(t.confusion[2][1], 1);
    }
}

//! A model's predictions for rows of inputs (`quadex predict`): each row
//! holds the `2N + 1` leading points in the thesis's column order
//! (`xlN, ylN, …, x0, y0, xr1, yr1, …, xrN, yrN`, the layout of a
//! training set's CSV; further columns such as `type,xn,yn` are ignored),
//! and the answer is one `type,xn,yn` row per input row, in the normalised
//! frame (P0 at the origin, P_r1 at `(1, 0)`). Rows in world coordinates
//! are normalised first; normalised rows are kept as they are.

use crate::geom::Point;
use crate::model::{Model, Prediction};
use crate::normalize::{Frame, LeadingPoints};
use crate::samples::{bad_coordinate, csv_number, TrainingSet};
use thiserror::Error;

/// Rows that cannot be predicted.
#[derive(Debug, Error, PartialEq)]
pub enum PredictError {
    #[error("the header does not name leading points (xlN, ylN, …, x0, y0, xr1, yr1, …): {0}")]
    Header(String),
    #[error("line {line}: {msg}")]
    Parse { line: usize, msg: String },
    #[error("line {line}: P_r1 coincides with P0")]
    Degenerate { line: usize },
    #[error("the rows have {rows} input points, the model reads {model}")]
    Points { rows: usize, model: usize },
    #[error("{0}")]
    Csv(String),
}

/// Reads input rows: the number of input points and each row's normalised
/// leading points.
pub fn read_rows(text: &str) -> Result<(usize, Vec<LeadingPoints>), PredictError> {
    let text = crate::io::normalise_text(text);
    let mut r = csv::ReaderBuilder::new()
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header: Vec<String> = r
        .headers()
        .map_err(|e| PredictError::Csv(crate::io::quote_long(&e.to_string())))?
        .iter()
        .map(str::to_lowercase)
        .collect();
    let named = || PredictError::Header(crate::io::quote_long(&header.join(",")));
    // The input columns run up to the first column that is not a
    // coordinate (`type`, or the end).
    let coords = header
        .iter()
        .position(|h| !(h.starts_with('x') || h.starts_with('y')))
        .unwrap_or(header.len());
    let points = coords / 2;
    if coords % 2 != 0 || !matches!(points, 5 | 7 | 9 | 11) {
        return Err(named());
    }
    let n = (points - 1) / 2;
    let expected = TrainingSet::csv_header(n);
    if header.get(..coords) != expected.get(..coords) {
        return Err(named());
    }
    let mut rows = Vec::new();
    for (i, rec) in r.records().enumerate() {
        let line = i + 2;
        let rec = rec.map_err(|e| PredictError::Csv(crate::io::quote_long(&e.to_string())))?;
        let num = |k: usize| -> Result<f64, PredictError> {
            let v = csv_number(&rec, k, &expected[k])
                .map_err(|msg| PredictError::Parse { line, msg })?;
            match bad_coordinate(v) {
                Some(why) => Err(PredictError::Parse {
                    line,
                    msg: format!("{} {why}", expected[k]),
                }),
                None => Ok(v),
            }
        };
        let mut pts = Vec::with_capacity(points);
        for k in 0..points {
            pts.push(Point::new(num(2 * k)?, num(2 * k + 1)?));
        }
        let (p0, r1) = (pts[n], pts[n + 1]);
        if (r1 - p0).length() <= 0.0 {
            return Err(PredictError::Degenerate { line });
        }
        let left: Vec<Point> = pts[..n].iter().rev().copied().collect();
        let right: Vec<Point> = pts[n + 1..].to_vec();
        let frame = Frame::new(p0, r1);
        rows.push(LeadingPoints::normalise(&frame, &left, &right));
    }
    Ok((points, rows))
}

/// The model's prediction for every row (`points` input points); refused
/// when the model reads another number of points.
pub fn predict_rows(
    model: &dyn Model,
    points: usize,
    rows: &[LeadingPoints],
) -> Result<Vec<Prediction>, PredictError> {
    if let Some(n) = model.leading_points() {
        if 2 * n + 1 != points {
            return Err(PredictError::Points {
                rows: points,
                model: 2 * n + 1,
            });
        }
    }
    Ok(rows.iter().map(|lp| model.predict(lp)).collect())
}

/// Predictions as CSV: `type,xn,yn`, one line each (shortest decimals that
/// read back to the same numbers).
pub fn to_csv(predictions: &[Prediction]) -> String {
    let mut s = String::from("type,xn,yn\n");
    for p in predictions {
        s.push_str(&p.element_type.number().to_string());
        s.push(',');
        crate::io::fmt_f64(&mut s, p.pn.x);
        s.push(',');
        crate::io::fmt_f64(&mut s, p.pn.y);
        s.push('\n');
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{ElementType, RulesModel};

    const HEADER: &str = "xl2,yl2,xl1,yl1,x0,y0,xr1,yr1,xr2,yr2";

    #[test]
    fn rows_are_read_normalised_and_predicted() {
        // A square corner, once normalised and once in world coordinates
        // (scaled by 2 and moved): the same input.
        let text = format!(
            "{HEADER},type,xn,yn\n0,2,0,1,0,0,1,0,2,0,0,1,1\n10,14,10,12,10,10,12,10,14,10\n"
        );
        let (points, rows) = read_rows(&text).unwrap();
        assert_eq!(points, 5);
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0], rows[1]);
        assert_eq!(rows[0].left[1], Point::new(0.0, 2.0));
        let p = predict_rows(&RulesModel::default(), points, &rows).unwrap();
        assert_eq!(p[0].element_type, ElementType::New);
        assert!((p[0].pn - Point::new(1.0, 1.0)).length() < 1e-9, "{p:?}");
        let csv = to_csv(&p);
        assert_eq!(csv.lines().count(), 3);
        assert!(csv.starts_with("type,xn,yn\n0,"));
    }

    #[test]
    fn bad_rows_are_refused_with_their_line() {
        let e = read_rows("a,b\n1,2\n").unwrap_err();
        assert!(matches!(e, PredictError::Header(_)));
        let e = read_rows(&format!("{HEADER}\n0,2,0,1,0,0,1,0,x,0\n")).unwrap_err();
        assert!(
            matches!(&e, PredictError::Parse { line: 2, msg } if msg.contains("xr2")),
            "{e}"
        );
        let e = read_rows(&format!("{HEADER}\n0,2,0,1,0,0,0,0,2,0\n")).unwrap_err();
        assert_eq!(e, PredictError::Degenerate { line: 2 });
        let e = read_rows(&format!("{HEADER}\n0,2,0,1\n")).unwrap_err();
        assert!(matches!(e, PredictError::Parse { line: 2, .. }), "{e}");
        let e = read_rows(&format!("{HEADER}\n0,2,0,inf,0,0,1,0,2,0\n")).unwrap_err();
        assert!(matches!(e, PredictError::Parse { line: 2, .. }), "{e}");
    }

    #[test]
    fn a_model_of_other_points_is_refused() {
        let (points, rows) = read_rows(&format!("{HEADER}\n0,2,0,1,0,0,1,0,2,0\n")).unwrap();
        let m = crate::model::default_model().unwrap();
        assert_eq!(
            predict_rows(&m, points, &rows).unwrap_err(),
            PredictError::Points { rows: 5, model: 7 }
        );
    }
}

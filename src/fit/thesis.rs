//! Fitting the thesis's forms (§4.3.1; method §4).
//!
//! Xn and Yn are linear in their coefficients: one least-squares solve
//! each (SVD). The type model
//! `P = μ0 + Σ λ_i σ(μ1 X_i) + γ_i σ(μ1 Y_i)` is linear once μ1 is fixed,
//! so a 1-D search over μ1 (a log-spaced scan, then golden-section
//! refinement around the best scan point) with least squares inside finds
//! its optimum. This replaces the Auto2Fit "UGO" optimiser the thesis used.

use super::{lstsq, Data, FitError, FitParams};
use crate::model::fitted::{thesis_coord_features, thesis_type_features, ThesisForm};
use nalgebra::{DMatrix, DVector};

/// Points of the μ1 scan.
const MU1_SCAN: usize = 48;
/// Golden-section iterations after the scan.
const MU1_REFINE: usize = 40;

/// Fits the thesis form.
pub fn fit(data: &Data, params: &FitParams) -> Result<ThesisForm, FitError> {
    let m = data.len();
    let coord_len = 5 + 2 * (2 * data.n - 1);
    if m < coord_len.max(7) {
        return Err(FitError::TooFew {
            form: "thesis",
            found: m,
            needed: coord_len.max(7),
        });
    }
    let mut xs = Vec::with_capacity(m * coord_len);
    for lp in &data.inputs {
        xs.extend(thesis_coord_features(lp));
    }
    let x = DMatrix::from_row_slice(m, coord_len, &xs);
    let xn = lstsq(
        &x,
        &DVector::from_iterator(m, data.pn.iter().map(|p| p.x)),
        "Xn",
    )?;
    let yn = lstsq(
        &x,
        &DVector::from_iterator(m, data.pn.iter().map(|p| p.y)),
        "Yn",
    )?;

    let y = DVector::from_iterator(m, data.types.iter().map(|&t| t as f64));
    let (mu1, _) = search_mu1(data, &y, params.mu1_range)?;
    let f = type_matrix(data, mu1);
    let w = lstsq(&f, &y, "type")?;
    Ok(ThesisForm {
        n: data.n,
        mu0: w[0],
        mu1,
        type_coef: [w[1], w[2], w[3], w[4], w[5], w[6]],
        xn: xn.iter().copied().collect(),
        yn: yn.iter().copied().collect(),
    })
}

/// The type model's design matrix `[1, σ(μ1 X_i), σ(μ1 Y_i) …]` for μ1.
fn type_matrix(data: &Data, mu1: f64) -> DMatrix<f64> {
    let mut rows = Vec::with_capacity(7 * data.len());
    for lp in &data.inputs {
        rows.push(1.0);
        rows.extend(thesis_type_features(lp, mu1));
    }
    DMatrix::from_row_slice(data.len(), 7, &rows)
}

/// SSE of the type model's least-squares fit at μ1 (normal equations:
/// the 7 × 7 system is solved by SVD, which tolerates a rank drop).
fn type_sse(data: &Data, y: &DVector<f64>, mu1: f64) -> f64 {
    let f = type_matrix(data, mu1);
    let gram = f.tr_mul(&f);
    let rhs = f.tr_mul(y);
    match gram.svd(true, true).solve(&rhs, 1e-12) {
        Ok(w) => (&f * w - y).norm_squared(),
        Err(_) => f64::INFINITY,
    }
}

/// The μ1 of least SSE in `range`: a log-spaced scan, then golden-section
/// search between the best point's neighbours.
fn search_mu1(data: &Data, y: &DVector<f64>, range: [f64; 2]) -> Result<(f64, f64), FitError> {
    let (lo, hi) = (range[0].max(1e-6).ln(), range[1].max(range[0] * 1.01).ln());
    let at = |k: usize| lo + (hi - lo) * k as f64 / (MU1_SCAN - 1) as f64;
    let scan: Vec<f64> = (0..MU1_SCAN)
        .map(|k| type_sse(data, y, at(k).exp()))
        .collect();
    let best = (0..MU1_SCAN)
        .min_by(|&a, &b| scan[a].total_cmp(&scan[b]))
        .filter(|&k| scan[k].is_finite())
        .ok_or(FitError::Singular { what: "type" })?;
    let (mut a, mut b) = (at(best.saturating_sub(1)), at((best + 1).min(MU1_SCAN - 1)));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (type_sse(data, y, c.exp()), type_sse(data, y, d.exp()));
    for _ in 0..MU1_REFINE {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = type_sse(data, y, c.exp());
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = type_sse(data, y, d.exp());
        }
    }
    let (mu, sse) = if fc < fd { (c, fc) } else { (d, fd) };
    if sse <= scan[best] {
        Ok((mu.exp(), sse))
    } else {
        Ok((at(best).exp(), scan[best]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;
    use crate::model::ThesisModel;
    use crate::normalize::LeadingPoints;

    /// Deterministic pseudo-random inputs in a box.
    fn inputs(m: usize) -> Vec<LeadingPoints> {
        let mut s = 12345u64;
        let mut r = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 3.0 - 1.0
        };
        (0..m)
            .map(|_| LeadingPoints {
                left: (0..3).map(|_| Point::new(r(), r() + 1.0)).collect(),
                right: std::iter::once(Point::X)
                    .chain((0..2).map(|_| Point::new(r() + 1.0, r())))
                    .collect(),
            })
            .collect()
    }

    #[test]
    fn recovers_known_coordinate_coefficients() {
        // Pn generated by Table 8's Xn/Yn: least squares gives them back.
        let truth = ThesisModel::TABLE_8.form();
        let inputs = inputs(400);
        let data = Data {
            n: 3,
            pn: inputs.iter().map(|lp| truth.position(lp)).collect(),
            types: inputs
                .iter()
                .map(|lp| truth.predict(lp).element_type.number())
                .collect(),
            inputs,
        };
        let f = fit(&data, &FitParams::DEFAULT).unwrap();
        for (a, b) in f.xn.iter().zip(&truth.xn).chain(f.yn.iter().zip(&truth.yn)) {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
    }

    #[test]
    fn recovers_mu1_of_a_noise_free_type_score() {
        // A continuous target made by the type model itself: the μ1
        // search and the inner least squares recover μ1 and the weights.
        let truth = ThesisForm {
            n: 3,
            mu0: 0.3,
            mu1: 1.7,
            type_coef: [0.5, -0.4, 1.2, 0.8, -0.6, 0.9],
            xn: vec![0.0; 15],
            yn: vec![0.0; 15],
        };
        let data = Data {
            n: 3,
            inputs: inputs(500),
            types: vec![0; 500],
            pn: vec![Point::ZERO; 500],
        };
        let y = DVector::from_iterator(500, data.inputs.iter().map(|lp| truth.type_score(lp)));
        let (mu1, sse) = search_mu1(&data, &y, [0.01, 100.0]).unwrap();
        assert!((mu1 - 1.7).abs() < 1e-3, "mu1 {mu1}");
        assert!(sse < 1e-8, "sse {sse}");
    }
}

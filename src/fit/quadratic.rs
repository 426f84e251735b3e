//! Fitting the quadratic form: a richer model than the thesis's.
//!
//! Inputs are every leading coordinate but the constant P0 and P_r1,
//! standardised; features are `1, z_i, z_i z_j`. The type is a multinomial
//! logistic classifier (types 1 and 2 against type 0), fitted by Newton's
//! method with a step-halving line search and an L2 penalty (which keeps
//! separable classes finite). Pn is one ridge regression per type, solved
//! by Cholesky on the normal equations.

use super::{Data, FitError, FitParams};
use crate::model::fitted::{
    quadratic_features_into, quadratic_len, raw_inputs, softmax, QuadraticForm,
};
use nalgebra::{DMatrix, DVector};

/// Newton stops when no coefficient moves more than this…
const NEWTON_TOL: f64 = 1e-8;
/// …or when an iteration lowers the loss by less than this fraction.
const LOSS_TOL: f64 = 1e-9;

/// The standardisation of raw inputs `z = (clamp(x) − mean) / scale`,
/// with the range each input is clamped to (the training samples').
pub(crate) struct Standardisation {
    pub mean: Vec<f64>,
    pub scale: Vec<f64>,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
}

impl Standardisation {
    /// The raw inputs of `data` ([`raw_inputs`]) and their
    /// standardisation, for a fit of `form` (at least 3 samples).
    pub fn of_data(
        data: &Data,
        form: &'static str,
    ) -> Result<(Vec<Vec<f64>>, Standardisation), FitError> {
        if data.len() < 3 {
            return Err(FitError::TooFew {
                form,
                found: data.len(),
                needed: 3,
            });
        }
        let raw: Vec<Vec<f64>> = data.inputs.iter().map(raw_inputs).collect();
        let st = Standardisation::of(&raw);
        Ok((raw, st))
    }

    /// Of the rows `raw` (at least one, all of one length).
    pub fn of(raw: &[Vec<f64>]) -> Standardisation {
        let n_obs = raw.len();
        let m = raw.first().map_or(0, Vec::len);
        let mut mean = vec![0.0; m];
        for r in raw {
            for (a, v) in mean.iter_mut().zip(r) {
                *a += v / n_obs as f64;
            }
        }
        let mut scale = vec![0.0; m];
        for r in raw {
            for ((s, v), mu) in scale.iter_mut().zip(r).zip(&mean) {
                *s += (v - mu) * (v - mu) / n_obs as f64;
            }
        }
        for s in &mut scale {
            *s = s.sqrt().max(1e-9);
        }
        let mut lo = vec![f64::INFINITY; m];
        let mut hi = vec![f64::NEG_INFINITY; m];
        for r in raw {
            for k in 0..m {
                lo[k] = lo[k].min(r[k]);
                hi[k] = hi[k].max(r[k]);
            }
        }
        Standardisation {
            mean,
            scale,
            lo,
            hi,
        }
    }
}

/// Fits the quadratic form.
pub fn fit(data: &Data, params: &FitParams) -> Result<QuadraticForm, FitError> {
    let n_obs = data.len();
    let (
        raw,
        Standardisation {
            mean,
            scale,
            lo,
            hi,
        },
    ) = Standardisation::of_data(data, "quadratic")?;
    let m = raw[0].len();
    let p = quadratic_len(m);
    let mut rows = Vec::with_capacity(n_obs * p);
    let mut f = Vec::with_capacity(p);
    let mut z = vec![0.0; m];
    for r in &raw {
        for k in 0..m {
            z[k] = (r[k] - mean[k]) / scale[k];
        }
        quadratic_features_into(&z, &mut f);
        rows.extend_from_slice(&f);
    }
    let x = DMatrix::from_row_slice(n_obs, p, &rows);

    let mut xn: [Vec<f64>; 3] = Default::default();
    let mut yn: [Vec<f64>; 3] = Default::default();
    for t in 0..3u8 {
        let idx: Vec<usize> = (0..n_obs).filter(|&i| data.types[i] == t).collect();
        if idx.is_empty() {
            xn[t as usize] = vec![0.0; p];
            yn[t as usize] = vec![0.0; p];
            continue;
        }
        let xt = x.select_rows(&idx);
        let targets = DMatrix::from_fn(idx.len(), 2, |r, c| {
            let q = data.pn[idx[r]];
            if c == 0 {
                q.x
            } else {
                q.y
            }
        });
        let w = ridge(&xt, &targets, params.ridge)?;
        xn[t as usize] = w.column(0).iter().copied().collect();
        yn[t as usize] = w.column(1).iter().copied().collect();
    }
    let type_logit = logistic(&x, &data.types, params)?;
    Ok(QuadraticForm {
        n: data.n,
        mean,
        scale,
        lo,
        hi,
        type_logit,
        xn,
        yn,
    })
}

/// `(XᵀX + αI') W = XᵀY`, the intercept (column 0) unpenalised.
fn ridge(x: &DMatrix<f64>, y: &DMatrix<f64>, alpha: f64) -> Result<DMatrix<f64>, FitError> {
    let xt = x.transpose();
    let mut g = &xt * x;
    for k in 1..g.nrows() {
        g[(k, k)] += alpha;
    }
    // A tiny floor on the intercept keeps a one-type set solvable.
    g[(0, 0)] += 1e-12;
    let rhs = &xt * y;
    match g.clone().cholesky() {
        Some(c) => Ok(c.solve(&rhs)),
        None => g
            .svd(true, true)
            .solve(&rhs, 1e-12)
            .map_err(|_| FitError::Singular { what: "Pn" }),
    }
}

/// Penalised negative log-likelihood of logits `(0, a, b)`.
fn loss(x: &DMatrix<f64>, y: &[u8], w: &DVector<f64>, p: usize, alpha: f64) -> f64 {
    let a = x * w.rows(0, p);
    let b = x * w.rows(p, p);
    let mut l = 0.0;
    for i in 0..y.len() {
        let pr = softmax(a[i], b[i]);
        l -= pr[y[i] as usize].max(1e-300).ln();
    }
    let pen: f64 = (1..p).map(|k| w[k] * w[k] + w[p + k] * w[p + k]).sum();
    l + 0.5 * alpha * pen
}

/// Samples per block of [`weighted_products`]: a multiple of the depth
/// block of matrixmultiply's f64 kernels (256), so the blocks' products add
/// up exactly as one product over all samples would (the shipped model is
/// the fit's output bit for bit).
const BLOCK: usize = 256 * 4;

/// `Xᵀ diag(d) X` for three weightings `d` at once, stacked in `out`
/// (`3p × p`): one product per block of samples, into `buf` (`3p ×
/// BLOCK`), so `X` is packed once for the three and no copy of `Xᵀ` is
/// made.
fn weighted_products(
    x: &DMatrix<f64>,
    xt: &DMatrix<f64>,
    d: [&DVector<f64>; 3],
    buf: &mut DMatrix<f64>,
    out: &mut DMatrix<f64>,
) {
    let (n, p) = x.shape();
    let mut start = 0;
    while start < n {
        let len = BLOCK.min(n - start);
        for i in 0..len {
            let xi = xt.column(start + i);
            let mut col = buf.column_mut(i);
            for (b, w) in d.iter().enumerate() {
                let wi = w[start + i];
                for k in 0..p {
                    col[b * p + k] = xi[k] * wi;
                }
            }
        }
        let beta = if start == 0 { 0.0 } else { 1.0 };
        out.gemm(1.0, &buf.columns(0, len), &x.rows(start, len), beta);
        start += len;
    }
}

/// Multinomial logistic regression by Newton's method.
fn logistic(x: &DMatrix<f64>, y: &[u8], params: &FitParams) -> Result<[Vec<f64>; 2], FitError> {
    let (n, p) = x.shape();
    let alpha = params.logistic_l2.max(1e-12);
    let xt = x.transpose();
    let mut w = DVector::<f64>::zeros(2 * p);
    let mut current = loss(x, y, &w, p, alpha);
    let mut stacked = DMatrix::zeros(3 * p, BLOCK.min(n));
    let mut products = DMatrix::zeros(3 * p, p);
    for _ in 0..params.newton_iterations {
        let a = x * w.rows(0, p);
        let b = x * w.rows(p, p);
        let mut r1 = DVector::zeros(n);
        let mut r2 = DVector::zeros(n);
        let mut w11 = DVector::zeros(n);
        let mut w22 = DVector::zeros(n);
        let mut w12 = DVector::zeros(n);
        for i in 0..n {
            let pr = softmax(a[i], b[i]);
            r1[i] = pr[1] - f64::from(y[i] == 1);
            r2[i] = pr[2] - f64::from(y[i] == 2);
            w11[i] = pr[1] * (1.0 - pr[1]);
            w22[i] = pr[2] * (1.0 - pr[2]);
            w12[i] = -pr[1] * pr[2];
        }
        let mut grad = DVector::zeros(2 * p);
        grad.rows_mut(0, p).copy_from(&(&xt * &r1));
        grad.rows_mut(p, p).copy_from(&(&xt * &r2));
        for k in 1..p {
            grad[k] += alpha * w[k];
            grad[p + k] += alpha * w[p + k];
        }
        weighted_products(x, &xt, [&w11, &w22, &w12], &mut stacked, &mut products);
        let mut h = DMatrix::zeros(2 * p, 2 * p);
        h.view_mut((0, 0), (p, p)).copy_from(&products.rows(0, p));
        h.view_mut((p, p), (p, p)).copy_from(&products.rows(p, p));
        h.view_mut((0, p), (p, p))
            .copy_from(&products.rows(2 * p, p));
        h.view_mut((p, 0), (p, p))
            .copy_from(&products.rows(2 * p, p).transpose());
        for k in 0..p {
            h[(k, k)] += if k == 0 { 1e-9 } else { alpha };
            h[(p + k, p + k)] += if k == 0 { 1e-9 } else { alpha };
        }
        let step = match h.clone().cholesky() {
            Some(c) => c.solve(&grad),
            None => h
                .svd(true, true)
                .solve(&grad, 1e-12)
                .map_err(|_| FitError::Singular { what: "type" })?,
        };
        // Step halving until the loss does not grow.
        let mut t = 1.0;
        let mut next = &w - &step * t;
        let mut l = loss(x, y, &next, p, alpha);
        while l > current && t > 1e-6 {
            t *= 0.5;
            next = &w - &step * t;
            l = loss(x, y, &next, p, alpha);
        }
        let moved = (&step * t).amax();
        if l > current {
            break;
        }
        let gain = current - l;
        w = next;
        current = l;
        if moved < NEWTON_TOL || gain <= LOSS_TOL * current {
            break;
        }
    }
    Ok([
        w.rows(0, p).iter().copied().collect(),
        w.rows(p, p).iter().copied().collect(),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Point;
    use crate::model::fitted::QuadraticForm;

    #[test]
    fn recovers_a_quadratic_pn_and_a_separable_type() {
        // Pn an exact quadratic of the inputs; the type set by which side
        // of two lines P_l1 falls: both are learnt almost exactly.
        let inputs = crate::fit::random_inputs(2, 1500, 777);
        let types: Vec<u8> = inputs
            .iter()
            .map(|lp| {
                let l1 = lp.left[0];
                if l1.x < -0.3 {
                    2
                } else if l1.x > 0.4 {
                    1
                } else {
                    0
                }
            })
            .collect();
        let pn: Vec<Point> = inputs
            .iter()
            .map(|lp| {
                let (l1, r2) = (lp.left[0], lp.right[1]);
                Point::new(
                    0.5 + l1.x * r2.y - 0.25 * l1.y * l1.y,
                    1.0 + 0.3 * r2.x + l1.x * l1.y,
                )
            })
            .collect();
        let data = Data {
            n: 2,
            inputs,
            types,
            pn,
        };
        let params = FitParams {
            ridge: 1e-9,
            ..FitParams::DEFAULT
        };
        let q: QuadraticForm = fit(&data, &params).unwrap();
        let mut hits = 0;
        for (i, lp) in data.inputs.iter().enumerate() {
            let pr = q.predict(lp);
            hits += usize::from(pr.element_type.number() == data.types[i]);
            // Pn of the true type's regression is exact.
            let f = q.features(lp);
            let t = data.types[i] as usize;
            let x: f64 = q.xn[t].iter().zip(&f).map(|(a, b)| a * b).sum();
            let y: f64 = q.yn[t].iter().zip(&f).map(|(a, b)| a * b).sum();
            assert!((Point::new(x, y) - data.pn[i]).length() < 1e-5);
        }
        assert!(hits as f64 / data.len() as f64 > 0.99, "{hits}");
    }
}

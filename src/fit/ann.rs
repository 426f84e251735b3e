//! Training the network form (thesis §2.2.2: Yao & Zeng's back-propagation
//! network, the same inputs and outputs as the regression models): one
//! hidden layer of tanh units, the type by softmax cross-entropy and Pn
//! (standardised) by squared error, the two losses added. Back-propagation
//! with Adam steps over mini-batches; the weights start from a seeded
//! Glorot draw and the batches follow a seeded shuffle, so the same samples
//! and parameters give the same network.

use super::quadratic::Standardisation;
use super::{Data, FitError, FitParams};
use crate::model::fitted::{softmax, AnnForm, ANN_OUTPUTS};
use crate::rng::SplitMix64;

/// Samples per Adam step.
const BATCH: usize = 128;
/// Adam's step size at the start (it falls linearly to a tenth by the end)
/// and its moment decays.
const LEARNING_RATE: f64 = 0.01;
const BETA1: f64 = 0.9;
const BETA2: f64 = 0.999;
const EPS: f64 = 1e-8;
/// Passes over the samples: enough for about `params.ann_samples` sample
/// visits, between these bounds.
const MIN_EPOCHS: usize = 5;
const MAX_EPOCHS: usize = 400;

/// Adam's state for one weight vector.
struct Adam {
    m: Vec<f64>,
    v: Vec<f64>,
}

impl Adam {
    fn new(n: usize) -> Adam {
        Adam {
            m: vec![0.0; n],
            v: vec![0.0; n],
        }
    }

    fn step(&mut self, w: &mut [f64], g: &[f64], lr: f64, t: i32) {
        let (c1, c2) = (1.0 - BETA1.powi(t), 1.0 - BETA2.powi(t));
        for k in 0..w.len() {
            self.m[k] = BETA1 * self.m[k] + (1.0 - BETA1) * g[k];
            self.v[k] = BETA2 * self.v[k] + (1.0 - BETA2) * g[k] * g[k];
            w[k] -= lr * (self.m[k] / c1) / ((self.v[k] / c2).sqrt() + EPS);
        }
    }
}

/// Trains the network form.
pub fn fit(data: &Data, params: &FitParams) -> Result<AnnForm, FitError> {
    let n_obs = data.len();
    let (raw, st) = Standardisation::of_data(data, "ann")?;
    let m = raw[0].len();
    let z: Vec<Vec<f64>> = raw
        .iter()
        .map(|r| (0..m).map(|k| (r[k] - st.mean[k]) / st.scale[k]).collect())
        .collect();
    let coord = |i: usize, c: usize| if c == 0 { data.pn[i].x } else { data.pn[i].y };
    let mut pn_mean = [0.0; 2];
    let mut pn_scale = [0.0; 2];
    for c in 0..2 {
        pn_mean[c] = (0..n_obs).map(|i| coord(i, c)).sum::<f64>() / n_obs as f64;
        let var = (0..n_obs)
            .map(|i| (coord(i, c) - pn_mean[c]).powi(2))
            .sum::<f64>()
            / n_obs as f64;
        pn_scale[c] = var.sqrt().max(1e-9);
    }
    let hidden = params.ann_hidden.max(1);
    let mut g = SplitMix64::new(params.seed);
    let mut glorot = |fan_in: usize, fan_out: usize, len: usize| -> Vec<f64> {
        let a = (6.0 / (fan_in + fan_out) as f64).sqrt();
        (0..len).map(|_| g.uni(-a, a)).collect()
    };
    let mut w1 = glorot(m, hidden, hidden * (m + 1));
    let mut w2 = glorot(hidden, ANN_OUTPUTS, ANN_OUTPUTS * (hidden + 1));
    for j in 0..hidden {
        w1[j * (m + 1) + m] = 0.0;
    }
    for k in 0..ANN_OUTPUTS {
        w2[k * (hidden + 1) + hidden] = 0.0;
    }
    let mut net = AnnForm {
        n: data.n,
        mean: st.mean,
        scale: st.scale,
        lo: st.lo,
        hi: st.hi,
        hidden,
        w1,
        w2,
        pn_mean,
        pn_scale,
    };
    let epochs = params
        .ann_samples
        .div_ceil(n_obs)
        .clamp(MIN_EPOCHS, MAX_EPOCHS);
    let steps_total = (epochs * n_obs.div_ceil(BATCH)) as f64;
    let (mut adam1, mut adam2) = (Adam::new(net.w1.len()), Adam::new(net.w2.len()));
    let mut g1 = vec![0.0; net.w1.len()];
    let mut g2 = vec![0.0; net.w2.len()];
    let mut order: Vec<usize> = (0..n_obs).collect();
    let mut h = Vec::with_capacity(hidden);
    let mut dh = vec![0.0; hidden];
    let mut t = 0i32;
    for _ in 0..epochs {
        for i in (1..n_obs).rev() {
            let j = (g.next_u64() % (i as u64 + 1)) as usize;
            order.swap(i, j);
        }
        for batch in order.chunks(BATCH) {
            g1.iter_mut().for_each(|x| *x = 0.0);
            g2.iter_mut().for_each(|x| *x = 0.0);
            let scale = 1.0 / batch.len() as f64;
            for &i in batch {
                let zi = &z[i];
                let o = net.forward(zi, &mut h);
                // Output errors: softmax cross-entropy for the type scores,
                // squared error (halved) for the standardised Pn.
                let p = softmax(o[1] - o[0], o[2] - o[0]);
                let ty = data.types[i] as usize;
                let mut d = [0.0; ANN_OUTPUTS];
                for k in 0..3 {
                    d[k] = p[k] - if k == ty { 1.0 } else { 0.0 };
                }
                for c in 0..2 {
                    d[3 + c] = o[3 + c] - (coord(i, c) - net.pn_mean[c]) / net.pn_scale[c];
                }
                dh.iter_mut().for_each(|x| *x = 0.0);
                for (k, &dk) in d.iter().enumerate() {
                    let row = k * (hidden + 1);
                    for jh in 0..hidden {
                        g2[row + jh] += scale * dk * h[jh];
                        dh[jh] += dk * net.w2[row + jh];
                    }
                    g2[row + hidden] += scale * dk;
                }
                for jh in 0..hidden {
                    let dj = dh[jh] * (1.0 - h[jh] * h[jh]) * scale;
                    let row = jh * (m + 1);
                    for (k, &x) in zi.iter().enumerate() {
                        g1[row + k] += dj * x;
                    }
                    g1[row + m] += dj;
                }
            }
            t += 1;
            let lr = LEARNING_RATE * (1.0 - 0.9 * f64::from(t) / steps_total);
            adam1.step(&mut net.w1, &g1, lr, t);
            adam2.step(&mut net.w2, &g2, lr, t);
        }
    }
    Ok(net)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::random_inputs;
    use crate::geom::Point;

    /// A type set by the sign of P_l1's x and Pn a smooth function of the
    /// inputs: the network learns both.
    fn data(seed: u64) -> Data {
        let inputs = random_inputs(3, 2000, seed);
        let types = inputs
            .iter()
            .map(|lp| if lp.left[0].x > 0.3 { 1 } else { 0 })
            .collect();
        let pn = inputs
            .iter()
            .map(|lp| {
                Point::new(
                    0.5 * lp.left[0].x + 0.8,
                    0.3 * lp.left[0].y + 0.2 * lp.right[1].y + 0.7,
                )
            })
            .collect();
        Data {
            n: 3,
            inputs,
            types,
            pn,
        }
    }

    #[test]
    fn learns_a_type_boundary_and_a_smooth_pn_and_is_deterministic() {
        let d = data(3);
        let params = FitParams {
            ann_samples: 200_000,
            ..FitParams::DEFAULT
        };
        let net = fit(&d, &params).unwrap();
        let test = data(4);
        let mut right = 0;
        let mut err = 0.0;
        for i in 0..test.len() {
            let p = net.predict(&test.inputs[i]);
            right += usize::from(p.element_type.number() == test.types[i]);
            err += (p.pn - test.pn[i]).length();
        }
        let (acc, mean_err) = (right as f64 / test.len() as f64, err / test.len() as f64);
        assert!(acc > 0.95, "accuracy {acc}");
        assert!(mean_err < 0.05, "mean Pn error {mean_err}");
        // Same samples and seed, same weights.
        assert_eq!(fit(&d, &params).unwrap(), net);
    }
}

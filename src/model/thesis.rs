//! The thesis's regression models with the coefficients of its Table 8
//! exactly as printed (§4.3.2; method §4), for 7 input points
//! (P_l3, P_l2, P_l1, P0, P_r1, P_r2, P_r3; P0 and P_r1 are constant after
//! normalisation).
//!
//! - type: `P = μ0 + Σ_{i∈{l2,l1,r2}} λ_i σ(μ1 X_i) + γ_i σ(μ1 Y_i)`,
//!   σ the logistic function; type 0 if P ≤ 0.75, 1 if P ≤ 1.5, else 2;
//! - Xn: `λ0 + λ1 X_N³ + λ2 Y_N³ + λ3 X_N² + λ4 Y_N² + Σ ε_i X_i + τ_i Y_i`
//!   over i ∈ {l3, l2, l1, r2, r3}, with (X_N, Y_N) = P_l1;
//! - Yn: the same form with η, χ, φ.
//!
//! The printed values are shipped as they are and never tuned; what they do
//! is measured and stated in the README.

use super::fitted::ThesisForm;
use super::{Model, Prediction};
use crate::geom::Point;
use crate::normalize::LeadingPoints;
use serde::{Deserialize, Serialize};

/// Coefficients of the thesis's three regression models.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ThesisModel {
    /// Type model: μ0.
    pub mu0: f64,
    /// Type model: μ1.
    pub mu1: f64,
    /// Type model: λ for P_l2, P_l1, P_r2.
    pub type_lambda: [f64; 3],
    /// Type model: γ for P_l2, P_l1, P_r2.
    pub type_gamma: [f64; 3],
    /// Xn: λ0..λ4.
    pub xn_poly: [f64; 5],
    /// Xn: ε for l3, l2, l1, r2, r3.
    pub xn_eps: [f64; 5],
    /// Xn: τ for l3, l2, l1, r2, r3.
    pub xn_tau: [f64; 5],
    /// Yn: η0..η4.
    pub yn_poly: [f64; 5],
    /// Yn: χ for l3, l2, l1, r2, r3.
    pub yn_chi: [f64; 5],
    /// Yn: φ for l3, l2, l1, r2, r3.
    pub yn_phi: [f64; 5],
}

impl ThesisModel {
    /// Table 8 of the thesis as printed (12,293 samples, meshes #1, #4, #6).
    pub const TABLE_8: ThesisModel = ThesisModel {
        mu0: 0.8325,
        mu1: 1.2008,
        type_lambda: [1.8022, -1.2238, -3.9728],
        type_gamma: [-1.3188, 1.9398, 4.0131],
        xn_poly: [0.4567, -0.2856, 0.0741, 0.0255, -0.2922],
        xn_eps: [-0.0006, -0.0029, -0.0301, 0.7916, 0.0385],
        xn_tau: [0.0018, 0.0052, 0.0239, 0.5909, -0.0656],
        yn_poly: [1.0933, -0.2256, -0.5996, -0.0729, 2.2923],
        yn_chi: [0.0025, 0.0163, -0.0469, -0.1483, 0.0392],
        yn_phi: [-0.0025, 0.0019, 0.0011, -1.9436, -0.0611],
    };

    /// The same coefficients in the general thesis form of
    /// [`super::fitted`] (the single implementation of the formulas).
    pub fn form(&self) -> ThesisForm {
        let interleave = |a: &[f64; 5], b: &[f64; 5]| -> Vec<f64> {
            a.iter().zip(b).flat_map(|(x, y)| [*x, *y]).collect()
        };
        let mut xn = self.xn_poly.to_vec();
        xn.extend(interleave(&self.xn_eps, &self.xn_tau));
        let mut yn = self.yn_poly.to_vec();
        yn.extend(interleave(&self.yn_chi, &self.yn_phi));
        let l = self.type_lambda;
        let g = self.type_gamma;
        ThesisForm {
            n: 3,
            mu0: self.mu0,
            mu1: self.mu1,
            type_coef: [l[0], g[0], l[1], g[1], l[2], g[2]],
            xn,
            yn,
        }
    }

    /// The type model's raw output P.
    pub fn type_score(&self, input: &LeadingPoints) -> f64 {
        self.form().type_score(input)
    }

    /// Xn and Yn.
    pub fn position(&self, input: &LeadingPoints) -> Point {
        self.form().position(input)
    }
}

impl Model for ThesisModel {
    fn name(&self) -> &str {
        "thesis"
    }

    fn leading_points(&self) -> Option<usize> {
        Some(3)
    }

    fn predict(&self, input: &LeadingPoints) -> Prediction {
        self.form().predict(input)
    }
}

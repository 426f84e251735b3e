//! The curves of a drawing, evaluated exactly: straight segments, circular
//! and elliptical arcs and non-uniform rational B-splines. Every node and
//! midside node is a point [`Curve::at`] gives, so it lies on the curve.

use crate::geom::Point;
use std::f64::consts::PI;
use std::sync::Arc;

/// The largest angle an arc segment spans: 15°, a chord error of at most
/// 0.86 % of the radius. A curve of varying curvature gets segments no
/// longer than this angle times its local radius of curvature, the same
/// bound.
pub const MAX_ARC_ANGLE: f64 = PI / 12.0;

/// Samples per curve for the lengths, curvatures and spacings of an
/// ellipse or a spline (at least; a spline gets [`SAMPLES_PER_SPAN`] per
/// knot span when that is more).
const SAMPLES_CURVED: usize = 1024;
/// Samples per knot span of a spline.
const SAMPLES_PER_SPAN: usize = 64;
/// Samples of a line or a circular arc (exact lengths; the samples carry
/// only the size wanted along it).
const SAMPLES_SIMPLE: usize = 64;

/// A non-uniform rational B-spline: `degree`, a knot vector of
/// `points.len() + degree + 1` non-decreasing values, control points and
/// their weights (all 1 for a non-rational spline). It is evaluated over
/// the knots `knots[degree] ..= knots[points.len()]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Nurbs {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<Point>,
    weights: Vec<f64>,
}

impl Nurbs {
    /// A spline, checked: why not when its data cannot make one. Empty
    /// `weights` are all 1.
    pub fn new(
        degree: usize,
        knots: Vec<f64>,
        points: Vec<Point>,
        weights: Vec<f64>,
    ) -> Result<Nurbs, String> {
        let n = points.len();
        if degree < 1 {
            return Err(format!("degree {degree}: at least 1"));
        }
        if n < degree + 1 {
            return Err(format!(
                "{n} control points: a degree-{degree} spline needs at least {}",
                degree + 1
            ));
        }
        if knots.len() != n + degree + 1 {
            return Err(format!(
                "{} knots: {n} control points of degree {degree} need {}",
                knots.len(),
                n + degree + 1
            ));
        }
        if knots.iter().any(|k| !k.is_finite()) || knots.windows(2).any(|w| w[1] < w[0]) {
            return Err("the knots must be finite and non-decreasing".into());
        }
        if knots[n] <= knots[degree] {
            return Err("the knots span no parameter range".into());
        }
        if points.iter().any(|p| !p.is_finite()) {
            return Err("a control point is not finite".into());
        }
        let weights = if weights.is_empty() {
            vec![1.0; n]
        } else {
            weights
        };
        if weights.len() != n {
            return Err(format!("{} weights for {n} control points", weights.len()));
        }
        if weights.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
            return Err("the weights must be positive".into());
        }
        Ok(Nurbs {
            degree,
            knots,
            points,
            weights,
        })
    }

    pub fn degree(&self) -> usize {
        self.degree
    }

    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    pub fn points(&self) -> &[Point] {
        &self.points
    }

    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The parameter range evaluated.
    fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.points.len()])
    }

    /// Knot spans of positive length in the domain.
    fn spans(&self) -> usize {
        let (p, n) = (self.degree, self.points.len());
        (p..n)
            .filter(|&k| self.knots[k + 1] > self.knots[k])
            .count()
    }

    /// The point at knot parameter `u` (de Boor's algorithm on the
    /// homogeneous control points).
    pub fn eval(&self, u: f64) -> Point {
        let (p, n) = (self.degree, self.points.len());
        let (lo, hi) = self.domain();
        let u = u.clamp(lo, hi);
        // The span k with knots[k] <= u < knots[k + 1], in p ..= n - 1.
        let k = self
            .knots
            .partition_point(|&x| x <= u)
            .saturating_sub(1)
            .clamp(p, n - 1);
        let mut d: Vec<(Point, f64)> = (0..=p)
            .map(|j| {
                let w = self.weights[j + k - p];
                (self.points[j + k - p] * w, w)
            })
            .collect();
        for r in 1..=p {
            for j in (r..=p).rev() {
                let (a, b) = (self.knots[j + k - p], self.knots[j + 1 + k - r]);
                let alpha = if b > a { (u - a) / (b - a) } else { 0.0 };
                d[j] = (
                    d[j - 1].0 * (1.0 - alpha) + d[j].0 * alpha,
                    d[j - 1].1 * (1.0 - alpha) + d[j].1 * alpha,
                );
            }
        }
        d[p].0 / d[p].1
    }
}

/// A curve of a drawing.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve {
    /// A straight segment from `a` to `b`.
    Line { a: Point, b: Point },
    /// A circular arc about `centre` of `radius`, from angle `start` over
    /// `sweep` radians (positive counter-clockwise; ±2π a full circle).
    Arc {
        centre: Point,
        radius: f64,
        start: f64,
        sweep: f64,
    },
    /// An elliptical arc: `centre + major·cos θ + minor·sin θ` for θ from
    /// `start` over `sweep` radians (±2π a full ellipse); `major` and
    /// `minor` are the semi-axes as vectors.
    Ellipse {
        centre: Point,
        major: Point,
        minor: Point,
        start: f64,
        sweep: f64,
    },
    /// A B-spline or NURBS over its whole parameter range.
    Spline(Arc<Nurbs>),
}

impl Curve {
    /// The point at parameter `t` in [0, 1].
    pub fn at(&self, t: f64) -> Point {
        match self {
            Curve::Line { a, b } => *a + (*b - *a) * t,
            Curve::Arc {
                centre,
                radius,
                start,
                sweep,
            } => {
                let th = start + sweep * t;
                *centre + Point::new(th.cos(), th.sin()) * *radius
            }
            Curve::Ellipse {
                centre,
                major,
                minor,
                start,
                sweep,
            } => {
                let th = start + sweep * t;
                *centre + *major * th.cos() + *minor * th.sin()
            }
            Curve::Spline(s) => {
                let (lo, hi) = s.domain();
                s.eval(lo + (hi - lo) * t.clamp(0.0, 1.0))
            }
        }
    }

    /// The curve's length (exact for lines and circular arcs, from
    /// [`SAMPLES_CURVED`] chords or more otherwise).
    pub fn length(&self) -> f64 {
        match self {
            Curve::Line { a, b } => (*b - *a).length(),
            Curve::Arc { radius, sweep, .. } => radius * sweep.abs(),
            _ => {
                let s = self.samples();
                s.s[s.s.len() - 1]
            }
        }
    }

    /// True for a curve that ends where it starts by construction (a full
    /// circle or ellipse).
    pub fn is_closed(&self) -> bool {
        match self {
            Curve::Arc { sweep, .. } | Curve::Ellipse { sweep, .. } => {
                (sweep.abs() - 2.0 * PI).abs() < 1e-12
            }
            _ => false,
        }
    }

    /// The distance from `p` to the curve.
    pub fn distance(&self, p: Point) -> f64 {
        match self {
            Curve::Line { a, b } => crate::geom::point_segment_distance(p, *a, *b),
            Curve::Arc {
                centre,
                radius,
                start,
                sweep,
            } => {
                let d = p - *centre;
                let th = d.y.atan2(d.x);
                // The angle of p measured along the sweep from the start.
                let along = ((th - start) * sweep.signum()).rem_euclid(2.0 * PI);
                if along <= sweep.abs() + 1e-12 {
                    (d.length() - radius).abs()
                } else {
                    (p - self.at(0.0)).length().min((p - self.at(1.0)).length())
                }
            }
            _ => {
                // The nearest sample, then a golden-section search of the
                // parameter between its neighbours.
                let s = self.samples();
                let n = s.t.len();
                let i = (0..n)
                    .min_by(|&i, &j| {
                        (s.p[i] - p)
                            .length_squared()
                            .total_cmp(&(s.p[j] - p).length_squared())
                    })
                    .unwrap_or(0);
                let (mut lo, mut hi) = (s.t[i.saturating_sub(1)], s.t[(i + 1).min(n - 1)]);
                let f = |t: f64| (self.at(t) - p).length_squared();
                let g = 0.5 * (5f64.sqrt() - 1.0);
                for _ in 0..80 {
                    let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
                    if f(a) < f(b) {
                        hi = b;
                    } else {
                        lo = a;
                    }
                }
                f(0.5 * (lo + hi)).sqrt()
            }
        }
    }

    /// Samples along the curve: parameters, points, arc lengths from the
    /// start and the local radius-of-curvature bound on the spacing
    /// ([`MAX_ARC_ANGLE`] times the radius; infinite where straight).
    pub(crate) fn samples(&self) -> Samples {
        let n = match self {
            Curve::Line { .. } | Curve::Arc { .. } => SAMPLES_SIMPLE,
            Curve::Ellipse { .. } => SAMPLES_CURVED,
            Curve::Spline(s) => SAMPLES_CURVED.max(SAMPLES_PER_SPAN * s.spans()),
        };
        let t: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
        let p: Vec<Point> = t.iter().map(|&t| self.at(t)).collect();
        let (s, bound) = match self {
            Curve::Line { a, b } => {
                let l = (*b - *a).length();
                (
                    t.iter().map(|t| t * l).collect(),
                    vec![f64::INFINITY; n + 1],
                )
            }
            Curve::Arc { radius, sweep, .. } => {
                let l = radius * sweep.abs();
                (
                    t.iter().map(|t| t * l).collect(),
                    vec![radius * MAX_ARC_ANGLE; n + 1],
                )
            }
            _ => {
                let mut s = vec![0.0; n + 1];
                for i in 1..=n {
                    s[i] = s[i - 1] + (p[i] - p[i - 1]).length();
                }
                // The turning angle per unit length at each inner sample.
                let mut bound = vec![f64::INFINITY; n + 1];
                for i in 1..n {
                    let (d1, d2) = (p[i] - p[i - 1], p[i + 1] - p[i]);
                    let turn = d1.perp_dot(d2).atan2(d1.dot(d2)).abs();
                    let ds = 0.5 * (d1.length() + d2.length());
                    if turn > 0.0 && ds > 0.0 {
                        bound[i] = MAX_ARC_ANGLE * ds / turn;
                    }
                }
                bound[0] = bound[1];
                bound[n] = bound[n - 1];
                (s, bound)
            }
        };
        Samples { t, p, s, bound }
    }
}

/// Samples of a curve ([`Curve::samples`]).
#[derive(Clone, Debug)]
pub(crate) struct Samples {
    pub t: Vec<f64>,
    pub p: Vec<Point>,
    pub s: Vec<f64>,
    pub bound: Vec<f64>,
}

impl Samples {
    /// The parameter at which the increasing table `f` (one value per
    /// sample) reaches `v`, interpolated linearly.
    pub fn invert(&self, f: &[f64], v: f64) -> f64 {
        let n = f.len() - 1;
        if v <= f[0] {
            return self.t[0];
        }
        if v >= f[n] {
            return self.t[n];
        }
        let i = f.partition_point(|&x| x <= v).clamp(1, n);
        let (a, b) = (f[i - 1], f[i]);
        let w = if b > a { (v - a) / (b - a) } else { 0.0 };
        self.t[i - 1] + w * (self.t[i] - self.t[i - 1])
    }
}

/// The circular arc from `a` through `m` to `b`; `None` when the three
/// points are on one line.
pub fn arc_through(a: Point, m: Point, b: Point) -> Option<Curve> {
    let (ab, am) = (b - a, m - a);
    let d = 2.0 * am.perp_dot(ab);
    let scale = ab.length().max(am.length());
    if d.abs() <= 1e-12 * scale * scale {
        return None;
    }
    // The circumcentre relative to a.
    let c = Point::new(
        ab.y * am.length_squared() - am.y * ab.length_squared(),
        am.x * ab.length_squared() - ab.x * am.length_squared(),
    ) / d;
    let centre = a + c;
    let angle = |p: Point| (p - centre).y.atan2((p - centre).x);
    let (ta, tm, tb) = (angle(a), angle(m), angle(b));
    let ccw_b = (tb - ta).rem_euclid(2.0 * PI);
    let ccw_m = (tm - ta).rem_euclid(2.0 * PI);
    let sweep = if ccw_m < ccw_b {
        ccw_b
    } else {
        ccw_b - 2.0 * PI
    };
    Some(Curve::Arc {
        centre,
        radius: c.length(),
        start: ta,
        sweep,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rational_quadratic_is_an_exact_quarter_circle() {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let s = Nurbs::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![
                Point::new(1.0, 0.0),
                Point::new(1.0, 1.0),
                Point::new(0.0, 1.0),
            ],
            vec![1.0, w, 1.0],
        )
        .unwrap();
        for k in 0..=100 {
            let p = s.eval(k as f64 / 100.0);
            assert!((p.length() - 1.0).abs() < 1e-14, "{p:?}");
        }
        let c = Curve::Spline(Arc::new(s));
        assert!((c.length() - PI / 2.0).abs() < 1e-6);
        assert!(c.distance(Point::new(2.0 * w, 2.0 * w)) - 1.0 < 1e-12);
    }

    #[test]
    fn three_points_give_the_arc_through_them_either_way() {
        let p = Point::new;
        let c = arc_through(p(1.0, 0.0), p(0.0, 1.0), p(-1.0, 0.0)).unwrap();
        assert!((c.at(0.5) - p(0.0, 1.0)).length() < 1e-12);
        let c = arc_through(p(1.0, 0.0), p(0.0, -1.0), p(-1.0, 0.0)).unwrap();
        assert!((c.at(0.5) - p(0.0, -1.0)).length() < 1e-12);
        assert!((c.at(1.0) - p(-1.0, 0.0)).length() < 1e-12);
        assert!(arc_through(p(0.0, 0.0), p(1.0, 1.0), p(2.0, 2.0)).is_none());
    }
}

//! Planar geometry shared by every algorithm: robust orientation tests,
//! angles measured the way the thesis measures them (§2.1.2), segment
//! intersection and polygon areas.

use glam::DVec2;

/// A point (or vector) in the plane.
pub type Point = DVec2;

/// Twice the signed area of the triangle `a, b, c`: positive when the turn
/// `a → b → c` is counter-clockwise. Uses Shewchuk's adaptive predicate, so
/// the sign is exact.
#[inline]
pub fn orient(a: Point, b: Point, c: Point) -> f64 {
    robust::orient2d(
        robust::Coord { x: a.x, y: a.y },
        robust::Coord { x: b.x, y: b.y },
        robust::Coord { x: c.x, y: c.y },
    )
}

/// The counter-clockwise angle, in radians in `[0, 2π)`, that turns the
/// direction `from − p` onto `to − p`.
///
/// With `from = P_r1` and `to = P_l1` this is the interior angle of the front
/// at `p` (method §2.1): a square's corner gives π/2, a reflex corner more
/// than π.
#[inline]
pub fn ccw_angle(p: Point, from: Point, to: Point) -> f64 {
    let u = from - p;
    let v = to - p;
    let a = u.perp_dot(v).atan2(u.dot(v));
    if a < 0.0 {
        a + std::f64::consts::TAU
    } else {
        a
    }
}

/// The sine of the corner at `b` of the turn `a → b → c`, the domain to
/// the left: positive when the corner is convex, negative when reflex; a
/// quad's scaled Jacobian is the least of its corners'.
#[inline]
pub fn corner_sine(a: Point, b: Point, c: Point) -> f64 {
    let (next, prev) = (c - b, a - b);
    next.perp_dot(prev) / (next.length() * prev.length()).max(1e-300)
}

/// The sines of the corners of the quad `q` (counter-clockwise): its
/// scaled Jacobian at each ([`corner_sine`]).
#[inline]
pub fn corner_sines(q: [Point; 4]) -> [f64; 4] {
    [0, 1, 2, 3].map(|k| corner_sine(q[(k + 3) % 4], q[k], q[(k + 1) % 4]))
}

/// The points `c + α u + γ v` for `α` and `γ` each one of `steps` values
/// spread evenly over `range` (ends included), `α` in the outer loop: the
/// grid the boundary patches search for a new node over.
pub fn weighted_points(
    c: Point,
    u: Point,
    v: Point,
    range: (f64, f64),
    steps: usize,
) -> impl Iterator<Item = Point> {
    let at = move |i: usize| range.0 + (range.1 - range.0) * i as f64 / (steps - 1) as f64;
    (0..steps).flat_map(move |i| (0..steps).map(move |j| c + u * at(i) + v * at(j)))
}

/// A corner angle to compare [`ccw_angle`]s with, mostly without the
/// arctangent: where a corner is clearly on one side of the limit, the
/// sign of a cross product decides; only corners within about
/// [`ANGLE_FILTER`] radians of the limit are measured. The answers are
/// those of comparing [`ccw_angle`] itself (its rounding is some 1e-15
/// radians, far inside the margin).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngleLimit {
    /// The limit (radians), as the comparison with [`ccw_angle`] uses it.
    pub limit: f64,
    /// Its cosine and sine, or `None` where the limit is too near 0 or π
    /// for the cross product to decide (every corner is measured then).
    cos_sin: Option<(f64, f64)>,
}

/// The margin, relative to the size of the corner's vectors, within which
/// [`AngleLimit`] measures the angle rather than deciding by sign.
pub const ANGLE_FILTER: f64 = 1e-9;

impl AngleLimit {
    /// The limit `limit` (radians).
    pub fn new(limit: f64) -> AngleLimit {
        const ROOM: f64 = 1e-6;
        let cos_sin = (ROOM..=std::f64::consts::PI - ROOM)
            .contains(&limit)
            .then(|| (limit.cos(), limit.sin()));
        AngleLimit { limit, cos_sin }
    }

    /// Where the angle of direction `(x, y)`, `y > 0`, lies against the
    /// limit, when clearly below (`Less`) or above (`Greater`).
    #[inline]
    fn side(&self, x: f64, y: f64) -> Option<std::cmp::Ordering> {
        let (c, s) = self.cos_sin?;
        if y.is_nan() || y <= 0.0 {
            return None;
        }
        // `r·sin(angle − limit)` for the direction at `angle`, length `r`.
        let d = c * y - s * x;
        let m = ANGLE_FILTER * (x.abs() + y.abs());
        if d < -m {
            Some(std::cmp::Ordering::Less)
        } else if d > m {
            Some(std::cmp::Ordering::Greater)
        } else {
            None
        }
    }

    /// True when `ccw_angle(p, from, to) < self.limit`.
    #[inline]
    pub fn below(&self, p: Point, from: Point, to: Point) -> bool {
        let (u, v) = (from - p, to - p);
        let (y, x) = (u.perp_dot(v), u.dot(v));
        if self.cos_sin.is_some() && y < -ANGLE_FILTER * (x.abs() + y.abs()) {
            // An angle in (π, 2π), over any limit below π.
            return false;
        }
        match self.side(x, y) {
            Some(o) => o.is_lt(),
            None => ccw_angle(p, from, to) < self.limit,
        }
    }
}

/// A tolerance on how far a corner may be from straight, tested as
/// [`AngleLimit`] tests its limit: mostly by sign.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StraightLimit {
    /// The tolerance (radians), as the comparison with [`ccw_angle`] uses
    /// it.
    pub tolerance: f64,
    /// `π − tolerance`, which the corner's angle either way from a full
    /// turn's edge must stay over.
    inner: AngleLimit,
}

impl StraightLimit {
    /// The tolerance `tolerance` (radians).
    pub fn new(tolerance: f64) -> StraightLimit {
        StraightLimit {
            tolerance,
            inner: AngleLimit::new(std::f64::consts::PI - tolerance),
        }
    }

    /// True when `(ccw_angle(p, from, to) − π).abs() > self.tolerance`.
    #[inline]
    pub fn off(&self, p: Point, from: Point, to: Point) -> bool {
        let (u, v) = (from - p, to - p);
        let (y, x) = (u.perp_dot(v), u.dot(v));
        // Either way from straight alike: the angle of `(x, |y|)`, in
        // `[0, π]`, under `π − tolerance`.
        match self.inner.side(x, y.abs()) {
            Some(o) => o.is_lt(),
            None => (ccw_angle(p, from, to) - std::f64::consts::PI).abs() > self.tolerance,
        }
    }
}

/// The smallest sine of a corner angle a quad may have. A corner flatter
/// than this (within about 6e-8 degrees of 0° or 180°) is convex in exact
/// arithmetic only by rounding, as when a node is the computed midpoint of
/// its neighbours, and reads as flat to any floating-point checker.
pub const MIN_CORNER_SINE: f64 = 1e-9;

/// True when corner `b` of the turn `a → b → c` turns left by more than
/// [`MIN_CORNER_SINE`]: exactly (robust sign) and measurably.
#[inline]
pub fn turns_left(a: Point, b: Point, c: Point) -> bool {
    let o = orient(a, b, c);
    o > 0.0 && o > MIN_CORNER_SINE * (b - a).length() * (c - b).length()
}

/// True when the quad `p` (corners in order) is strictly convex and
/// counter-clockwise: every corner turns left, exactly. A corner may be flat
/// to rounding; extraction allows that (smoothing moves such nodes), a
/// finished mesh does not ([`is_measurably_convex`]).
#[inline]
pub fn is_strictly_convex(p: [Point; 4]) -> bool {
    surely_convex(p) || reflex_corner(p).is_none()
}

/// The first corner of the quad `p` that does not turn left, exactly
/// (`None`: the quad is strictly convex and counter-clockwise).
#[inline]
pub fn reflex_corner(p: [Point; 4]) -> Option<usize> {
    (0..4).find(|&k| orient(p[(k + 3) % 4], p[k], p[(k + 1) % 4]) <= 0.0)
}

/// True when every corner of the quad `p` turns left by more than
/// [`MIN_CORNER_SINE`] (see [`turns_left`]).
#[inline]
pub fn is_measurably_convex(p: [Point; 4]) -> bool {
    surely_convex(p) || (0..4).all(|k| turns_left(p[(k + 3) % 4], p[k], p[(k + 1) % 4]))
}

/// A sine over which a corner is convex, strictly and measurably, whatever
/// the rounding of the plain cross product or scaled Jacobian
/// ([`crate::quality::Shape::convexity`]) that shows it.
pub const SURE_SINE: f64 = 1e-6;

/// Edge lengths squared between which [`surely_convex`] answers: its
/// products neither overflow nor fall into the subnormals.
const SURE_LENGTH2: (f64, f64) = (1e-100, 1e100);

/// True when the plain cross product shows every corner of `p` turning
/// left with a sine over [`SURE_SINE`]: then [`is_strictly_convex`] and
/// [`is_measurably_convex`] hold, and their orientation tests and square
/// roots are not needed (most quads a mesher looks at are such). False
/// says nothing.
#[inline]
fn surely_convex(p: [Point; 4]) -> bool {
    (0..4).all(|k| {
        let (u, v) = (p[k] - p[(k + 3) % 4], p[(k + 1) % 4] - p[k]);
        let (u2, v2) = (u.length_squared(), v.length_squared());
        let range = SURE_LENGTH2.0..SURE_LENGTH2.1;
        let cross = u.perp_dot(v);
        range.contains(&u2)
            && range.contains(&v2)
            && cross > 0.0
            && cross * cross > SURE_SINE * SURE_SINE * u2 * v2
    })
}

/// Where the ray from `from` along `dir` first meets the closed segment
/// `a–b`: the ray parameter (a distance when `dir` is a unit vector), or
/// `None` when it misses. A segment along the ray counts at its nearer end.
pub fn ray_segment(from: Point, dir: Point, a: Point, b: Point) -> Option<f64> {
    let e = b - a;
    let den = dir.perp_dot(e);
    let w = a - from;
    if den.abs() <= f64::EPSILON * dir.length() * e.length() {
        // Parallel: only a collinear segment ahead can be met.
        if w.perp_dot(dir).abs() > f64::EPSILON * (w.length() + e.length()) * dir.length() {
            return None;
        }
        let (ta, tb) = (w.dot(dir), (b - from).dot(dir));
        let t = ta.min(tb).max(0.0);
        return (ta.max(tb) >= 0.0).then(|| t / dir.length_squared());
    }
    let t = w.perp_dot(e) / den;
    let u = w.perp_dot(dir) / den;
    (t >= 0.0 && (0.0..=1.0).contains(&u)).then_some(t)
}

/// Distance from `p` to the closed segment `a–b`.
pub fn point_segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

/// True when the closed segments `a–b` and `c–d` share at least one point.
pub fn segments_intersect(a: Point, b: Point, c: Point, d: Point) -> bool {
    let d1 = orient(c, d, a);
    let d2 = orient(c, d, b);
    let d3 = orient(a, b, c);
    let d4 = orient(a, b, d);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && on_segment(c, d, a))
        || (d2 == 0.0 && on_segment(c, d, b))
        || (d3 == 0.0 && on_segment(a, b, c))
        || (d4 == 0.0 && on_segment(a, b, d))
}

/// For a point `p` collinear with `a–b`: true when it lies within the segment.
#[inline]
fn on_segment(a: Point, b: Point, p: Point) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// Signed area of a closed polygon given by its vertices (positive when CCW).
pub fn polygon_area(pts: impl IntoIterator<Item = Point>) -> f64 {
    let mut pts = pts.into_iter();
    let Some(first) = pts.next() else {
        return 0.0;
    };
    let mut s = 0.0;
    let mut prev = first;
    for p in pts {
        s += prev.perp_dot(p);
        prev = p;
    }
    s += prev.perp_dot(first);
    0.5 * s
}

/// Signed areas of polygons added up together with a bound on the sum's
/// rounding error, for checks that two ways of adding up one region agree
/// (a mesh's quads and its boundary loops).
///
/// Each polygon is summed as triangles from its first corner `o` to its
/// edges, `(p_i − o) × (p_{i+1} − p_i)`: differences of nearby points, so
/// coordinates far from the plane's origin do not cancel and a small
/// quad's terms are of its own size. The terms are added by Neumaier's
/// compensated summation, whose error does not grow with their number: a
/// plain shoelace sum over the 60,000 nodes of a unit circle is off by
/// about 1e-12, which is 1.6e-9 of the area of a ring 2π/60,000 wide
/// (reproducer R09), so a relative tolerance refused a correct mesh.
///
/// The bound ([`AreaSum::error_bound`]) comes from the sum's conditioning
/// M = Σ (|a.x·b.y| + |a.y·b.x|) over the terms `a × b`, not from the
/// area: to first order a term is off by 2ε of its part of M (two rounded
/// differences, a rounded product, the subtraction; ε =
/// [`f64::EPSILON`]) and the compensated sum by ε of Σ |terms| ≤ M, so
/// 3ε·M in all. The bound is twice that, which covers the second-order
/// terms for any number of terms below 1e15, plus one smallest subnormal
/// per term for products that underflow.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AreaSum {
    /// Twice the signed area: Neumaier's running sum ...
    sum: f64,
    /// ... and the low-order parts it lost.
    carry: f64,
    /// M, in the same units (twice the area).
    conditioning: f64,
    terms: u64,
}

impl AreaSum {
    /// Adds the signed area of the closed polygon `pts` (positive when
    /// counter-clockwise).
    pub fn add_polygon(&mut self, pts: &[Point]) {
        let Some(&o) = pts.first() else {
            return;
        };
        // The first and last terms have p_i − o = 0 or p_{i+1} − p_i = o − p_i
        // parallel to it: both are exactly zero and left out.
        for w in pts[1..].windows(2) {
            let a = w[0] - o;
            let b = w[1] - w[0];
            let (u, v) = (a.x * b.y, a.y * b.x);
            self.push(u - v);
            self.conditioning += u.abs() + v.abs();
            self.terms += 1;
        }
    }

    /// Neumaier's step: the running sum, and what rounding took off it.
    fn push(&mut self, t: f64) {
        let s = self.sum + t;
        self.carry += if self.sum.abs() >= t.abs() {
            (self.sum - s) + t
        } else {
            (t - s) + self.sum
        };
        self.sum = s;
    }

    /// The signed area added up so far.
    pub fn area(&self) -> f64 {
        0.5 * (self.sum + self.carry)
    }

    /// A bound on how far [`AreaSum::area`] can be from the exact sum of
    /// the polygons' areas (see the type's documentation).
    pub fn error_bound(&self) -> f64 {
        let underflow = self.terms as f64 * f64::from_bits(1);
        0.5 * (6.0 * f64::EPSILON * self.conditioning + underflow)
    }

    /// True when the two sums may be of the same exact area: they differ
    /// by no more than their two error bounds. Sums of equal exact areas
    /// always agree, so a disagreement is a real difference.
    pub fn agrees_with(&self, other: &AreaSum) -> bool {
        (self.area() - other.area()).abs() <= self.error_bound() + other.error_bound()
    }
}

/// Even–odd test: is `p` strictly inside the closed polygon `poly`?
/// Points on the boundary may go either way; callers test edges separately.
pub fn point_in_polygon(p: Point, poly: &[Point]) -> bool {
    let n = poly.len();
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Point,
    pub max: Point,
}

impl Aabb {
    /// The box around a set of points (`None` when the set is empty).
    pub fn of(pts: impl IntoIterator<Item = Point>) -> Option<Aabb> {
        let mut it = pts.into_iter();
        let first = it.next()?;
        let mut bb = Aabb {
            min: first,
            max: first,
        };
        for p in it {
            bb.min = bb.min.min(p);
            bb.max = bb.max.max(p);
        }
        Some(bb)
    }

    pub fn size(&self) -> Point {
        self.max - self.min
    }

    /// The distance from `p` to the box (0 inside it).
    pub fn distance_to(&self, p: Point) -> f64 {
        p.clamp(self.min, self.max).distance(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`AngleLimit`] answers as comparing [`ccw_angle`] does: on random
    /// corners, on corners a hair either side of the limit, on flat and
    /// degenerate ones, and for limits at and beyond the ends it decides
    /// by sign on.
    #[test]
    fn angle_limit_agrees_with_the_angle() {
        let mut state: u64 = 7;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let limits = [
            0.0,
            1e-7,
            0.3,
            std::f64::consts::FRAC_PI_4,
            std::f64::consts::FRAC_PI_2,
            2.5,
            std::f64::consts::PI - 1e-7,
            std::f64::consts::PI,
            4.0,
        ];
        for &limit in &limits {
            let lim = AngleLimit::new(limit);
            let straight = StraightLimit::new(limit);
            let check = |p: Point, from: Point, to: Point| {
                let a = ccw_angle(p, from, to);
                assert_eq!(lim.below(p, from, to), a < limit, "{p} {from} {to} {limit}");
                assert_eq!(
                    straight.off(p, from, to),
                    (a - std::f64::consts::PI).abs() > limit,
                    "{p} {from} {to} {limit}"
                );
            };
            for _ in 0..20_000 {
                let p = Point::new(next() * 10.0 - 5.0, next() * 10.0 - 5.0);
                let r = 1e-3 + next() * 3.0;
                let t = next() * std::f64::consts::TAU;
                let from = p + Point::new(t.cos(), t.sin()) * r;
                // Random, and a hair either side of the limit and of its
                // mirror about straight.
                for turn in [
                    next() * std::f64::consts::TAU,
                    limit * (1.0 + 1e-12),
                    limit * (1.0 - 1e-12),
                    limit + 1e-9,
                    std::f64::consts::TAU - limit + 1e-10,
                    std::f64::consts::PI + limit * (1.0 + 1e-12),
                    std::f64::consts::PI - limit * (1.0 - 1e-12),
                    std::f64::consts::PI,
                    0.0,
                ] {
                    let to =
                        p + Point::new((t + turn).cos(), (t + turn).sin()) * (r * (0.5 + next()));
                    check(p, from, to);
                }
                check(p, from, from);
                check(p, p, from);
                check(p, from, p + (p - from) * 2.0);
            }
        }
    }

    #[test]
    fn the_sure_convexity_test_never_says_more_than_the_exact_ones() {
        // Grid quads (flat, reflex, folded, degenerate), near-flat ones and
        // ones with sines about the sure test's bar, at scales from tiny to
        // huge.
        let mut g = crate::rng::SplitMix64::new(0xc0_ffee);
        let mut sure = 0;
        for n in 0..60_000 {
            let scale = [1.0, 1e-45, 1e45, 1e-60][n % 4];
            let p: [Point; 4] = std::array::from_fn(|_| {
                scale
                    * match n % 3 {
                        0 => Point::new(g.int(0, 4) as f64, g.int(0, 4) as f64),
                        1 => Point::new(g.uni(-1.0, 1.0), g.uni(-1.0, 1.0) * 1e-9),
                        _ => Point::new(g.uni(-1.0, 1.0), g.uni(-1.0, 1.0) * 1e-6),
                    }
            });
            let exact_strict = (0..4).all(|k| orient(p[(k + 3) % 4], p[k], p[(k + 1) % 4]) > 0.0);
            let exact_measurable = (0..4).all(|k| turns_left(p[(k + 3) % 4], p[k], p[(k + 1) % 4]));
            assert_eq!(is_strictly_convex(p), exact_strict, "{p:?}");
            assert_eq!(is_measurably_convex(p), exact_measurable, "{p:?}");
            if surely_convex(p) {
                assert!(exact_measurable && exact_strict, "{p:?}");
                sure += 1;
            }
        }
        assert!(sure > 1000, "{sure}");
    }

    #[test]
    fn square_corner_is_ninety_degrees() {
        let a = ccw_angle(Point::ZERO, Point::X, Point::Y);
        assert!((a.to_degrees() - 90.0).abs() < 1e-12);
        let r = ccw_angle(Point::ZERO, Point::Y, Point::X);
        assert!((r.to_degrees() - 270.0).abs() < 1e-12);
    }

    #[test]
    fn intersection_cases() {
        let p = |x, y| Point::new(x, y);
        assert!(segments_intersect(
            p(0., 0.),
            p(2., 2.),
            p(0., 2.),
            p(2., 0.)
        ));
        assert!(!segments_intersect(
            p(0., 0.),
            p(1., 0.),
            p(0., 1.),
            p(1., 1.)
        ));
        // touching at an end point counts
        assert!(segments_intersect(
            p(0., 0.),
            p(1., 0.),
            p(1., 0.),
            p(1., 1.)
        ));
        // collinear overlap counts, collinear disjoint does not
        assert!(segments_intersect(
            p(0., 0.),
            p(2., 0.),
            p(1., 0.),
            p(3., 0.)
        ));
        assert!(!segments_intersect(
            p(0., 0.),
            p(1., 0.),
            p(2., 0.),
            p(3., 0.)
        ));
    }

    #[test]
    fn area_and_inside() {
        let sq = [
            Point::new(0., 0.),
            Point::new(1., 0.),
            Point::new(1., 1.),
            Point::new(0., 1.),
        ];
        assert_eq!(polygon_area(sq), 1.0);
        assert!(point_in_polygon(Point::new(0.5, 0.5), &sq));
        assert!(!point_in_polygon(Point::new(1.5, 0.5), &sq));
    }

    #[test]
    fn area_sums_are_exact_for_a_square_and_far_from_the_origin() {
        let sq = [
            Point::new(0., 0.),
            Point::new(1., 0.),
            Point::new(1., 1.),
            Point::new(0., 1.),
        ];
        let mut s = AreaSum::default();
        s.add_polygon(&sq);
        assert_eq!(s.area(), 1.0);
        // A unit square at 1e8 still has area 1 exactly, and a clockwise
        // copy takes it off again.
        let far = sq.map(|p| p + Point::splat(1e8));
        let mut s = AreaSum::default();
        s.add_polygon(&far);
        assert_eq!(s.area(), 1.0);
        let mut back = far;
        back.reverse();
        s.add_polygon(&back);
        assert_eq!(s.area(), 0.0);
        assert!(s.agrees_with(&AreaSum::default()));
    }
}

//! Corner fans: a corner of the given boundary between a short and a long
//! segment takes a fan of quads around it before anything else is cut
//! there (a transition in the sense of thesis §2.1.4, started from the
//! boundary itself).
//!
//! Element by element, the first row along a side graded down to a corner
//! ends there in a quad with one edge of the fine side and one of the
//! coarse side: a sliver as long as the coarse segment and as wide as the
//! fine one, which no later step can mend (the corner's two boundary edges
//! are fixed). A fan of `k` quads around the corner node spreads that
//! ratio over `k` spokes instead: spoke `i` leaves the corner at `i / k`
//! of its angle, `a·gⁱ` long, where `a` is the short segment, `b` the long
//! one and `g = (b / a)^(1/k)`; the quad between two spokes has its far
//! corner where its three corners other than the fan's are squarest, or
//! with [`FarCorner::Balanced`] where its two outer sides are also alike
//! ([`far_corner`]). `k`
//! is the fewest quads that keep `g` within [`FanTuning::growth`], but no
//! more than leave each quad [`FanTuning::min_angle`] of the corner; fewer
//! than two is no fan. The
//! front then runs along the fan's outer edges, graded from the short
//! segment's length to the long one's, and extraction goes on from there.
//!
//! The fan is taken only if its quads are measurably convex with a scaled
//! Jacobian of at least [`FanTuning::min_sj`] (if not, the corner's fan of
//! one quad fewer is tried, down to two), and no front edge or node lies
//! inside it or crosses it.

use super::report::{StepKind, StepReport};
use super::session::Mesher;
use super::tuning::{FanTuning, FarCorner};
use crate::front::SlotId;
use crate::geom::{corner_sines, is_measurably_convex, weighted_points, Point};
use crate::quality::Shape;

/// The range of the weights of the spokes in a fan quad's far corner
/// ([`far_corner`]).
const FAR_RANGE: (f64, f64) = (0.5, 2.0);

/// The weights tried for each spoke in [`far_corner`], evenly over
/// [`FAR_RANGE`] (1 among them).
const FAR_STEPS: usize = 31;

/// The boundary corners still to be tried for a fan, in front order (the
/// next one last): those of the initial front, and those of the front
/// after a rip-up (which may have taken a fan away).
#[derive(Clone, Debug, Default)]
pub(super) struct Fans {
    pending: Vec<SlotId>,
}

impl Fans {
    /// The corners of the front that ask for a fan
    /// ([`spokes_at`]: segments whose lengths differ by at least
    /// [`FanTuning::min_ratio`], an angle under [`FanTuning::max_angle`]);
    /// whether its quads fit is worked out when each is tried.
    pub(super) fn of(m: &Mesher) -> Fans {
        let t = &m.params.tuning.fan;
        if t.min_ratio <= 0.0 {
            return Fans::default();
        }
        Fans {
            pending: m.initial_slots(|s| spokes_at(m, s, t).is_some()),
        }
    }
}

/// The spokes of a fan at a corner: the corner `c`, the unit directions and
/// the lengths of its `k + 1` spokes, the first along the edge to the
/// corner's next node, the last along the edge to its previous one.
#[derive(Clone, Debug, PartialEq)]
pub struct Spokes {
    pub c: Point,
    pub dirs: Vec<Point>,
    pub lengths: Vec<f64>,
}

/// The fan a corner at `c` between its previous node `prev` and its next
/// node `next` (the domain to the left of `prev → c → next`) would take:
/// `None` when it takes none.
pub fn fan_spokes(c: Point, prev: Point, next: Point, t: &FanTuning) -> Option<Spokes> {
    let (to_next, to_prev) = (next - c, prev - c);
    let (ln, lp) = (to_next.length(), to_prev.length());
    if !(ln > 0.0 && lp > 0.0) {
        return None;
    }
    let ratio = ln.max(lp) / ln.min(lp);
    if ratio < t.min_ratio {
        return None;
    }
    // The corner's angle inside the domain, from the edge to `next`
    // counter-clockwise to the edge to `prev`.
    let angle = crate::geom::ccw_angle(c, next, prev);
    if !(angle > 0.0 && angle <= t.max_angle.to_radians()) {
        return None;
    }
    let by_growth = (ratio.ln() / t.growth.max(1.0 + 1e-9).ln()).ceil() as usize;
    let by_angle = (angle / t.min_angle.to_radians()).floor() as usize;
    let k = by_growth.min(by_angle);
    if k < 2 {
        return None;
    }
    Some(spokes_of(c, prev, next, k))
}

/// The `k + 1` spokes of a fan of `k` quads at a corner at `c` between
/// `prev` and `next` (as [`fan_spokes`] has them, whatever its tuning
/// would ask).
fn spokes_of(c: Point, prev: Point, next: Point, k: usize) -> Spokes {
    let (to_next, to_prev) = (next - c, prev - c);
    let (ln, lp) = (to_next.length(), to_prev.length());
    let angle = crate::geom::ccw_angle(c, next, prev);
    let g = (lp / ln).powf(1.0 / k as f64);
    let base = to_next.y.atan2(to_next.x);
    let dirs = (0..=k)
        .map(|i| {
            let a = base + angle * i as f64 / k as f64;
            Point::new(a.cos(), a.sin())
        })
        .collect();
    let lengths = (0..=k).map(|i| ln * g.powi(i as i32)).collect();
    Spokes { c, dirs, lengths }
}

/// The far corner of the fan quad `c, p, m, q` between the spoke ends `p`
/// and `q`: `m = c + α (p − c) + γ (q − c)`, with `α` and `γ` each one of
/// [`FAR_STEPS`] values from [`FAR_RANGE`] (1 and 1: the parallelogram),
/// where the worst sine of the quad's three corners other than `c` is
/// highest ([`FarCorner::Squarest`]), or that sine times the ratio of its
/// outer sides `p m` and `m q`, the shorter over the longer
/// ([`FarCorner::Balanced`]). `None` if no such quad is measurably convex.
fn far_corner(c: Point, p: Point, q: Point, rule: FarCorner) -> Option<Point> {
    let mut best: Option<(f64, Point)> = None;
    for m in weighted_points(c, p - c, q - c, FAR_RANGE, FAR_STEPS) {
        let quad = [c, p, m, q];
        if !is_measurably_convex(quad) {
            continue;
        }
        let worst = corner_sines(quad)[1..]
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        let score = match rule {
            FarCorner::Squarest => worst,
            FarCorner::Balanced => {
                let (a, b) = ((m - p).length(), (q - m).length());
                worst * a.min(b) / a.max(b)
            }
        };
        if best.is_none_or(|(b, _)| score > b) {
            best = Some((score, m));
        }
    }
    best.map(|(_, m)| m)
}

/// The fan's quads and its outline: new points (the inner spoke ends and
/// the far corners, in front order from the previous node's side) and the
/// quads as indices into `[c, prev, next, new...]`, counter-clockwise;
/// `None` if a quad is not measurably convex with a scaled Jacobian of at
/// least [`FanTuning::min_sj`]. The far corners follow
/// [`FanTuning::far_corner`] ([`far_corner`]).
pub fn fan_quads(sp: &Spokes, prev: Point, next: Point, t: &FanTuning) -> Option<FanQuads> {
    let k = sp.dirs.len() - 1;
    // Spoke ends, from `next` (spoke 0) to `prev` (spoke k).
    let ends: Vec<Point> = (0..=k)
        .map(|i| match i {
            0 => next,
            _ if i == k => prev,
            _ => sp.c + sp.dirs[i] * sp.lengths[i],
        })
        .collect();
    let mut fars = Vec::with_capacity(k);
    for i in 0..k {
        fars.push(far_corner(sp.c, ends[i], ends[i + 1], t.far_corner)?);
    }
    // Indices: 0 the corner, 1 prev, 2 next, then the new points in front
    // order from prev: far k-1, end k-1, far k-2, ..., end 1, far 0.
    let mut points = Vec::with_capacity(2 * k - 1);
    let mut end_at = vec![0usize; k + 1];
    let mut far_at = vec![0usize; k];
    end_at[k] = 1;
    end_at[0] = 2;
    for i in (0..k).rev() {
        far_at[i] = 3 + points.len();
        points.push(fars[i]);
        if i > 0 {
            end_at[i] = 3 + points.len();
            points.push(ends[i]);
        }
    }
    let all = |j: usize| match j {
        0 => sp.c,
        1 => prev,
        2 => next,
        _ => points[j - 3],
    };
    let mut quads = Vec::with_capacity(k);
    for i in 0..k {
        let q = [0, end_at[i], far_at[i], end_at[i + 1]];
        let p = q.map(all);
        if !is_measurably_convex(p) || Shape::of(p).scaled_jacobian < t.min_sj {
            return None;
        }
        quads.push(q);
    }
    Some(FanQuads { points, quads })
}

/// A fan's new points, in front order from the corner's previous node,
/// and its quads over `[corner, prev, next, points...]`.
#[derive(Clone, Debug, PartialEq)]
pub struct FanQuads {
    pub points: Vec<Point>,
    pub quads: Vec<[usize; 4]>,
}

/// The spokes of the fan at slot `s` of `m`'s front and the corner's
/// previous and next points, if it asks for one: the corner must be a node
/// of the given boundary between two segments of it.
fn spokes_at(m: &Mesher, s: SlotId, t: &FanTuning) -> Option<(Spokes, Point, Point)> {
    let f = &m.front;
    let (p, n) = (f.prev(s), f.next(s));
    let ids = [f.node(p), f.node(s), f.node(n)];
    if !ids.iter().all(|&v| m.is_boundary(v)) || f.loop_len(s) < 6 {
        return None;
    }
    if [p, s, n].iter().any(|&x| f.slot(x).layer != 0) {
        return None;
    }
    let (c, prev, next) = (m.world(s), m.world(p), m.world(n));
    Some((fan_spokes(c, prev, next, t)?, prev, next))
}

/// The fan at slot `s` of `m`'s front, if it takes one ([`spokes_at`],
/// [`fitting_fan`]).
fn plan(m: &Mesher, s: SlotId, t: &FanTuning) -> Option<FanQuads> {
    let (sp, prev, next) = spokes_at(m, s, t)?;
    fitting_fan(&sp, prev, next, t)
}

/// The quads of the fan `sp` ([`fan_quads`]), or if they do not fit, of
/// the same corner's fan with one quad fewer ([`spokes_of`]), down to
/// two: a far corner that cannot be squared among narrow spokes may be
/// among wider ones.
fn fitting_fan(sp: &Spokes, prev: Point, next: Point, t: &FanTuning) -> Option<FanQuads> {
    let k = sp.dirs.len() - 1;
    fan_quads(sp, prev, next, t).or_else(|| {
        (2..k)
            .rev()
            .find_map(|j| fan_quads(&spokes_of(sp.c, prev, next, j), prev, next, t))
    })
}

impl Mesher {
    /// [`super::Rung::Fan`]: the next boundary corner between a short and
    /// a long segment takes its fan, if it still fits.
    pub(super) fn corner_fan(&mut self) -> Option<StepReport> {
        let t = self.params.tuning.fan;
        while let Some(s) = self.fans.pending.pop() {
            if !self.front.slot(s).alive {
                continue;
            }
            let Some(fan) = plan(self, s, &t) else {
                continue;
            };
            let chain = [self.front.prev(s), s, self.front.next(s)];
            if !self.chain_is_clear(&chain, &fan.points) {
                continue;
            }
            return Some(self.commit_fan(s, &fan));
        }
        None
    }

    /// Commits the fan at slot `s`: its quads, and the front running along
    /// its outer edges instead of through the corner.
    fn commit_fan(&mut self, s: SlotId, fan: &FanQuads) -> StepReport {
        let mut r = self.report(StepKind::Fan);
        let (p, n) = (self.front.prev(s), self.front.next(s));
        let layer = self.front.slot(s).layer + 1;
        let mut ids = vec![self.front.node(s), self.front.node(p), self.front.node(n)];
        self.add_patch(&mut r, &mut ids, &fan.points, &fan.quads);
        r.reference = Some(ids[0]);
        let new = &r.new_nodes;
        self.front.replace_node(s, new[0], layer, &self.mesh.nodes);
        let rest = self
            .front
            .insert_after(s, &new[1..], layer, &self.mesh.nodes);
        for x in [p, s, n].into_iter().chain(rest) {
            self.push(x);
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::polygon_area;

    /// The default fan tuning with a bar of `min_sj` for its worst quad.
    fn at(min_sj: f64) -> FanTuning {
        FanTuning {
            min_sj,
            ..FanTuning::DEFAULT
        }
    }

    /// A right-angled corner at the origin, its next node `a` along x and
    /// its previous node `b` up y (the domain in the first quadrant).
    fn corner(a: f64, b: f64) -> (Point, Point, Point) {
        (Point::ZERO, Point::new(0.0, b), Point::new(a, 0.0))
    }

    #[test]
    fn a_corner_of_segments_1_and_100_gets_six_quads_growing_evenly() {
        let (c, prev, next) = corner(0.01, 1.0);
        let t = FanTuning::DEFAULT;
        let sp = fan_spokes(c, prev, next, &t).expect("fan");
        // ln 100 / ln 2.5 wants 6 quads (5.03); 90° at 10° a quad would
        // allow 9.
        assert_eq!(sp.dirs.len(), 7);
        for w in sp.lengths.windows(2) {
            assert!((w[1] / w[0] - 100f64.powf(1.0 / 6.0)).abs() < 1e-9);
        }
        assert!((sp.lengths[6] - 1.0).abs() < 1e-12);
        let fan = fan_quads(&sp, prev, next, &t).expect("quads");
        assert_eq!(fan.quads.len(), 6);
        assert_eq!(fan.points.len(), 11);
        let all = |j: usize| match j {
            0 => c,
            1 => prev,
            2 => next,
            _ => fan.points[j - 3],
        };
        let mut area = 0.0;
        for q in &fan.quads {
            let p = q.map(all);
            assert!(is_measurably_convex(p));
            // Each quad takes a sixth of the corner: its scaled Jacobian
            // there is sin 15°.
            assert!(Shape::of(p).scaled_jacobian > 0.2588 - 1e-3, "{p:?}");
            area += polygon_area(p);
        }
        // The quads tile the fan: the outline's area is theirs.
        let mut outline = vec![c, next];
        outline.extend(fan.points.iter().rev());
        outline.push(prev);
        assert!((polygon_area(outline.iter().copied()) - area).abs() < 1e-12 * area.max(1.0));
        // The outline goes from next round to prev, away from the corner.
        let r: Vec<f64> = outline[1..].iter().map(|p| p.length()).collect();
        assert!(r.iter().all(|&x| x >= 0.01 - 1e-12));
    }

    #[test]
    fn a_sharp_corners_balanced_fan_keeps_the_outer_sides_of_its_quads_alike() {
        // A 47.8° corner between segments of 0.015 and 1.856 (a side
        // graded to a sharp corner): 10° a quad allows four.
        let t = FanTuning::DEFAULT;
        let a = 47.8f64.to_radians();
        let (c, next) = (Point::ZERO, Point::new(0.015, 0.0));
        let prev = Point::new(a.cos(), a.sin()) * 1.856;
        let sp = fan_spokes(c, prev, next, &t).expect("fan");
        let outer = |fan: &FanQuads| {
            let all = |j: usize| match j {
                0 => c,
                1 => prev,
                2 => next,
                _ => fan.points[j - 3],
            };
            fan.quads
                .iter()
                .map(|q| {
                    let p = q.map(all);
                    let (pm, mq) = ((p[2] - p[1]).length(), (p[3] - p[2]).length());
                    (Shape::of(p), pm.min(mq) / pm.max(mq))
                })
                .collect::<Vec<_>>()
        };
        // The squarest far corners: kites whose outer side at the longer
        // spoke is a tenth of the other or less, and the front's first
        // edge from the long segment's end a sixteenth of that segment.
        let square = fan_quads(&sp, prev, next, &t).expect("quads");
        assert_eq!(square.quads.len(), 4);
        assert!(outer(&square).iter().any(|(_, r)| *r < 0.1));
        assert!((square.points[0] - prev).length() < 0.1 * 1.856);
        // The balanced ones: outer sides within 2.5:1, side ratios under
        // 5, and the scaled Jacobian still what the corner's share bounds
        // it to (sin 11.95°).
        let balanced = FanTuning {
            far_corner: FarCorner::Balanced,
            ..t
        };
        let even = fan_quads(&sp, prev, next, &balanced).expect("quads");
        assert_eq!(even.quads.len(), 4);
        for (shape, r) in outer(&even) {
            assert!(r > 0.4, "outer sides {r:.3}");
            assert!(shape.side_ratio() < 5.0, "{}", shape.side_ratio());
            assert!(
                shape.scaled_jacobian > 0.207 - 1e-3,
                "{}",
                shape.scaled_jacobian
            );
        }
        assert!((even.points[0] - prev).length() > 0.2 * 1.856);
    }

    #[test]
    fn a_fan_whose_quads_do_not_fit_takes_one_fewer() {
        let (c, prev, next) = corner(0.01, 1.0);
        // Six quads of 15° at the corner are under a bar of 0.3 (sin 15° =
        // 0.26); five of 18° are over it (0.31).
        let sp = fan_spokes(c, prev, next, &FanTuning::DEFAULT).expect("fan");
        assert_eq!(sp.dirs.len(), 7);
        assert!(fan_quads(&sp, prev, next, &at(0.3)).is_none());
        let fan = fitting_fan(&sp, prev, next, &at(0.3)).expect("a fan of five");
        assert_eq!(fan.quads.len(), 5);
        assert_eq!(
            Some(&fan),
            fan_quads(&spokes_of(c, prev, next, 5), prev, next, &at(0.3)).as_ref()
        );
        // Nothing fits a bar over sin 45°: no fan, not even of two.
        assert!(fitting_fan(&sp, prev, next, &at(0.75)).is_none());
    }

    #[test]
    fn even_segments_and_wide_corners_get_no_fan() {
        let t = FanTuning::DEFAULT;
        let (c, prev, next) = corner(1.0, 2.0);
        assert!(fan_spokes(c, prev, next, &t).is_none());
        // A flat side graded 1:100 at a node is a row's business.
        let flat = fan_spokes(
            Point::ZERO,
            Point::new(-1.0, 0.0),
            Point::new(0.01, 0.0),
            &t,
        );
        assert!(flat.is_none());
        // A reflex corner takes none either.
        let reflex = fan_spokes(
            Point::ZERO,
            Point::new(0.0, -1.0),
            Point::new(0.01, 0.0),
            &t,
        );
        assert!(reflex.is_none());
    }
}

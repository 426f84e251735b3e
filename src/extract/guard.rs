//! The guard (method §2.6): a candidate quad is accepted only if it is
//! strictly convex and counter-clockwise, its new corners meet the angle
//! limits, it crosses and contains no front edge or node, and the front it
//! leaves has no sliver angle.

use super::candidate::Cand;
use super::session::Mesher;
use crate::front::{Front, SlotId};
use crate::geom::{
    ccw_angle, is_strictly_convex, orient, point_segment_distance, segments_intersect, Point,
};
use std::f64::consts::PI;

/// One corner of a candidate quad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Corner {
    /// A front node whose whole front angle the quad takes.
    Full(SlotId),
    /// A front node of which the quad takes part of the angle; the rest
    /// stays on the front.
    Partial(SlotId),
    /// A new node at this position.
    New(Point),
}

/// Angle limits the guard applies, in radians.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Limits {
    pub min_corner: f64,
    pub max_corner: f64,
    pub min_front: f64,
}

impl Limits {
    /// These limits given in degrees, in radians.
    pub fn radians(self) -> Limits {
        Limits {
            min_corner: self.min_corner.to_radians(),
            max_corner: self.max_corner.to_radians(),
            min_front: self.min_front.to_radians(),
        }
    }
}

/// Scratch buffers reused across checks.
#[derive(Default, Debug, Clone)]
pub struct Scratch {
    pub near: Vec<SlotId>,
    /// Per slot, its position in its loop, written for the loops a bridge
    /// search numbers (kept between searches so that none allocates a
    /// buffer as long as the front's slots).
    pub loop_pos: Vec<usize>,
}

/// A candidate that passed the guard: its corners and its score.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Passed {
    pub corners: [Point; 4],
    /// Quality of the element and of the front it leaves (thesis §2.3.1:
    /// "a good element and a good remaining boundary"), in `[0, 1]`: the
    /// minimum of the quad's scaled Jacobian, `1/aspect` softened, a factor
    /// that falls from 1 to 0 as an angle left on the front drops from 60°
    /// to 15°, and one that falls from 1 to 0 as the room left between the
    /// element's new sides and the rest of the front drops from
    /// [`CLEAR_GOOD`] to [`CLEAR_NONE`] local sizes (a gap that narrow
    /// would become a sliver); times a factor for how far the new sides'
    /// lengths are from the local size.
    pub score: f64,
}

/// The front angle an element leaves at a node it takes part of costs
/// nothing from [`FRONT_REST_BAD`] + [`FRONT_REST_SPAN`] degrees up, and
/// grows to rejection as it falls to [`FRONT_REST_BAD`] degrees.
pub const FRONT_REST_BAD: f64 = 15.0;
/// See [`FRONT_REST_BAD`].
pub const FRONT_REST_SPAN: f64 = 45.0;
/// A new side `len` long where the size is `h` scores
/// `1 − SIZE_FIT_SLOPE · |ln(len / h)|`, at least [`SIZE_FIT_FLOOR`].
pub const SIZE_FIT_SLOPE: f64 = 0.35;
/// See [`SIZE_FIT_SLOPE`].
pub const SIZE_FIT_FLOOR: f64 = 0.2;
/// Room, in local element sizes, from a candidate's new sides and node to
/// the rest of the front that is enough for the next element.
pub const CLEAR_GOOD: f64 = 0.7;
/// Room below which a candidate leaves a gap only a sliver could fill.
pub const CLEAR_NONE: f64 = 0.25;
/// Longest over shortest side of a new quad, at most (the thesis's aspect
/// and taper limit is 10; smoothing afterwards moves nodes a little).
pub const MAX_SIDE_RATIO: f64 = 8.0;

/// A corner whose sides are both longer than this many times the span
/// between their far ends is a needle (under about 1.8° between equal
/// sides): a kite that takes it with sides within [`MAX_SIDE_RATIO`] would
/// need corners beside the tip of over 170°, so no quad there meets the
/// side ratio.
pub const NEEDLE_RATIO: f64 = 4.0 * MAX_SIDE_RATIO;

/// True when the corner at `p0` between front sides to `pl` and `pr` is a
/// needle ([`NEEDLE_RATIO`]): the element that takes it is the kite the
/// boundary forces, however stretched.
pub fn is_needle(p0: Point, pl: Point, pr: Point) -> bool {
    let span = pl.distance(pr);
    p0.distance(pl).min(p0.distance(pr)) > NEEDLE_RATIO * span
}

/// Checks a candidate quad. `consumed` are the front edges (by start slot)
/// that become sides of the quad; `size` is the local element size.
/// Returns the corners and score when it passes.
pub fn check(
    front: &Front,
    nodes: &[Point],
    corners: [Corner; 4],
    consumed: &[SlotId],
    limits: Limits,
    size: f64,
    scratch: &mut Scratch,
) -> Option<Passed> {
    check_above(
        front,
        nodes,
        corners,
        consumed,
        (limits, f64::NEG_INFINITY),
        size,
        scratch,
    )
}

/// [`check`], refusing as well a candidate whose score could not be over
/// `bar`: the score is at most the least of the quad's scaled Jacobian,
/// its softened aspect and the front factor, times the size fit, all
/// known before the front near the quad is looked at (the room to the
/// front only lowers it). A candidate refused for `bar` would have scored
/// at most `bar`.
pub fn check_above(
    front: &Front,
    nodes: &[Point],
    corners: [Corner; 4],
    consumed: &[SlotId],
    (limits, bar): (Limits, f64),
    size: f64,
    scratch: &mut Scratch,
) -> Option<Passed> {
    let pos = |c: Corner| match c {
        Corner::Full(s) | Corner::Partial(s) => nodes[front.node(s) as usize],
        Corner::New(p) => p,
    };
    let id = |c: Corner| match c {
        Corner::Full(s) | Corner::Partial(s) => Some(front.node(s)),
        Corner::New(_) => None,
    };
    let p = corners.map(pos);
    let ids = corners.map(id);
    if !is_strictly_convex(p) {
        return None;
    }
    // New edges: quad sides that are not consumed front edges.
    let side_consumed: [bool; 4] = std::array::from_fn(|k| match (ids[k], ids[(k + 1) % 4]) {
        (Some(a), Some(b)) => consumed.iter().any(|&s| {
            let e = (front.node(s), front.node(front.next(s)));
            e == (b, a) || e == (a, b)
        }),
        _ => false,
    });
    let is_consumed = |k: usize| side_consumed[k];
    // Side lengths within the thesis's ratio (aspect and taper ≤ 10), unless
    // the front edges the quad takes already differ that much, or the quad
    // takes a needle, which no quad can take within it.
    let q = crate::quality::Shape::of(p);
    let sides = q.side_ratio();
    if sides > MAX_SIDE_RATIO {
        let taken = (0..4).filter(|&k| is_consumed(k)).map(|k| q.edges[k]);
        let (lo, hi) = taken.fold((f64::INFINITY, 0.0f64), |(lo, hi), l| {
            (lo.min(l), hi.max(l))
        });
        let needle = (0..4).any(|k| {
            matches!(corners[k], Corner::Full(_))
                && is_consumed(k)
                && is_consumed((k + 3) % 4)
                && is_needle(p[k], p[(k + 3) % 4], p[(k + 1) % 4])
        });
        if sides > hi / lo && !needle {
            return None;
        }
    }
    // Corner limits and what the front keeps.
    let mut front_factor: f64 = 1.0;
    for k in 0..4 {
        // A corner the quad takes whole is the front's own: not measured.
        let corner = || ccw_angle(p[k], p[(k + 1) % 4], p[(k + 3) % 4]);
        match corners[k] {
            Corner::Full(_) => {}
            Corner::New(_) => {
                let corner = corner();
                if corner < limits.min_corner || corner > limits.max_corner {
                    return None;
                }
            }
            Corner::Partial(s) => {
                let corner = corner();
                if corner < limits.min_corner || corner > limits.max_corner {
                    return None;
                }
                let rest = front.angle(s, nodes) - corner;
                if rest < limits.min_front {
                    return None;
                }
                front_factor = front_factor
                    .min(((rest.to_degrees() - FRONT_REST_BAD) / FRONT_REST_SPAN).clamp(0.0, 1.0));
            }
        }
    }
    let new_sides = || (0..4).filter(|&k| !is_consumed(k));
    let stretch = (1.0 / q.aspect()).sqrt();
    // New sides far from the local size cost a little: a tie-breaker
    // between otherwise good elements, not a limit.
    let mut fit: f64 = 1.0;
    for k in new_sides() {
        let len = p[k].distance(p[(k + 1) % 4]);
        fit = fit.min((1.0 - SIZE_FIT_SLOPE * (len / size).ln().abs()).clamp(SIZE_FIT_FLOOR, 1.0));
    }
    // The score before the room to the front, which can only lower it.
    let bound = q.scaled_jacobian.min(stretch).min(front_factor) * fit;
    if bound.partial_cmp(&bar) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    // Front edges near the quad: within the room that counts as enough, so
    // the same query finds what crosses the quad and what comes close.
    let reach = Point::splat(CLEAR_GOOD * size);
    let lo = p.iter().fold(Point::splat(f64::INFINITY), |a, &b| a.min(b)) - reach;
    let hi = p
        .iter()
        .fold(Point::splat(f64::NEG_INFINITY), |a, &b| a.max(b))
        + reach;
    front.edges_near(lo, hi, &mut scratch.near);
    // Each corner's front neighbours: their room to the sides at that
    // corner is the front angle left there, judged above.
    let neighbours = corners.map(|c| match c {
        Corner::Full(s) | Corner::Partial(s) => [
            Some(front.node(front.prev(s))),
            Some(front.node(front.next(s))),
        ],
        Corner::New(_) => [None, None],
    });
    let mut clearance = f64::INFINITY;
    for &e in &scratch.near {
        if consumed.contains(&e) {
            continue;
        }
        let (c, d) = (front.node(e), front.node(front.next(e)));
        let (pc, pd) = (nodes[c as usize], nodes[d as usize]);
        let c_in = ids.contains(&Some(c));
        let d_in = ids.contains(&Some(d));
        if c_in && d_in {
            // A front edge between two corners must be one of the quad's
            // consumed sides; anything else is a diagonal or a duplicate.
            return None;
        }
        for k in new_sides() {
            let (a, b) = (ids[k], ids[(k + 1) % 4]);
            let shares = |v: u32| a == Some(v) || b == Some(v);
            if shares(c) || shares(d) {
                continue;
            }
            if segments_intersect(p[k], p[(k + 1) % 4], pc, pd) {
                return None;
            }
        }
        // A front node inside or on the quad (other than its corners).
        for (v, pv) in [(c, pc), (d, pd)] {
            if ids.contains(&Some(v)) {
                continue;
            }
            if (0..4).all(|k| orient(p[k], p[(k + 1) % 4], pv) >= 0.0) {
                return None;
            }
            // Room between the quad's new sides and this node.
            for k in new_sides() {
                let k1 = (k + 1) % 4;
                if neighbours[k].contains(&Some(v)) || neighbours[k1].contains(&Some(v)) {
                    continue;
                }
                clearance = clearance.min(point_segment_distance(pv, p[k], p[(k + 1) % 4]));
            }
        }
        // Room between a new node and this edge.
        for k in 0..4 {
            if ids[k].is_none() && !touches(&ids, c, d) {
                clearance = clearance.min(point_segment_distance(p[k], pc, pd));
            }
        }
    }
    let room = ((clearance / size - CLEAR_NONE) / (CLEAR_GOOD - CLEAR_NONE)).clamp(0.0, 1.0);
    Some(Passed {
        corners: p,
        score: q.scaled_jacobian.min(stretch).min(front_factor).min(room) * fit,
    })
}

/// True when front edge `c–d` has an end among the quad's corners or next
/// to one on the front.
fn touches(ids: &[Option<u32>; 4], c: u32, d: u32) -> bool {
    ids.contains(&Some(c)) || ids.contains(&Some(d))
}

impl Mesher {
    /// The guard on one candidate: its score when it passes.
    pub(super) fn check(&mut self, c: Cand, limits: Limits) -> Option<f64> {
        self.check_above(c, limits, f64::NEG_INFINITY)
    }

    /// [`Mesher::check`], refusing as well a candidate that could not
    /// score over `bar` ([`check_above`]; what is weighed after the guard
    /// only lowers the score).
    pub(super) fn check_above(&mut self, c: Cand, limits: Limits, bar: f64) -> Option<f64> {
        let p0 = c.slot();
        // The element at a sharp corner of the front has that corner's
        // angle; the corner opposite may open as far as a kite with right
        // angles beside the tip needs.
        let limits = if self
            .front
            .angle_below(p0, &self.mesh.nodes, &self.angles.sharp)
        {
            let tip = self.front.angle(p0, &self.mesh.nodes);
            Limits {
                max_corner: limits
                    .max_corner
                    .max(PI - tip + self.params.tuning.choice.tip_slack),
                ..limits
            }
        } else {
            limits
        };
        let at = match c {
            Cand::New { s, pn } => 0.5 * (self.world(s) + pn),
            Cand::Snap { s, .. } | Cand::Right { s } | Cand::Left { s } => self.world(s),
        };
        // A needle's element is as wide as its narrow end, however long.
        let size = self.needle_span(p0).unwrap_or_else(|| self.size.at(at));
        let f = &self.front;
        let n = self.front.loop_len(p0);
        // The front edges the element takes, the first `taken` of `consumed`.
        let (corners, consumed, taken): ([Corner; 4], [SlotId; 3], usize) = match c {
            Cand::New { s, pn } => {
                let (l, r) = (f.prev(s), f.next(s));
                // On a four-node loop the element leaves another four-node
                // loop (P0 moved to Pn), which must run the way it ran.
                if n == 4 {
                    let p = |t: SlotId| self.mesh.nodes[f.node(t) as usize];
                    let before = crate::geom::polygon_area([p(l), p(s), p(r), p(f.next(r))]);
                    let after = crate::geom::polygon_area([p(l), pn, p(r), p(f.next(r))]);
                    if before * after <= 0.0 {
                        return None;
                    }
                }
                (
                    [
                        Corner::Full(s),
                        Corner::Partial(r),
                        Corner::New(pn),
                        Corner::Partial(l),
                    ],
                    [l, s, s],
                    2,
                )
            }
            Cand::Snap { s, q } => {
                let (l, r) = (f.prev(s), f.next(s));
                if q == s || q == l || q == r || q == f.next(r) || q == f.prev(l) {
                    return None;
                }
                (
                    [
                        Corner::Full(s),
                        Corner::Partial(r),
                        Corner::Partial(q),
                        Corner::Partial(l),
                    ],
                    [l, s, s],
                    2,
                )
            }
            Cand::Right { s } => {
                if n < 6 {
                    return None;
                }
                let (l, r) = (f.prev(s), f.next(s));
                let r2 = f.next(r);
                (
                    [
                        Corner::Full(s),
                        Corner::Full(r),
                        Corner::Partial(r2),
                        Corner::Partial(l),
                    ],
                    [l, s, r],
                    3,
                )
            }
            Cand::Left { s } => {
                if n < 6 {
                    return None;
                }
                let (l, r) = (f.prev(s), f.next(s));
                let l2 = f.prev(l);
                (
                    [
                        Corner::Full(s),
                        Corner::Partial(r),
                        Corner::Partial(l2),
                        Corner::Full(l),
                    ],
                    [l2, l, s],
                    3,
                )
            }
        };
        let passed = check_above(
            f,
            &self.mesh.nodes,
            corners,
            &consumed[..taken],
            (limits, bar),
            size,
            &mut self.scratch,
        )?;
        let p = passed.corners;
        let ids = corners.map(|c| match c {
            Corner::Full(s) | Corner::Partial(s) => Some(self.front.node(s)),
            Corner::New(_) => None,
        });
        if !self.pinned_corners_turn(p, ids) {
            return None;
        }
        let mut score = passed.score;
        if let Cand::New { s, pn } = c {
            // Where a row goes on along the front, the element's corner
            // at the next node should take its share of that node's angle,
            // as paving's rows do: half of a side node's (the bisector),
            // a third of a reflex corner's. Much more or less opens the
            // row into a fan or closes it into a wedge.
            if let Some(row) = self.row_at(s) {
                let theta = self.front.angle(row.base, &self.mesh.nodes);
                if theta > self.params.tuning.choice.row_side {
                    let share = if theta < self.params.tuning.choice.row_corner {
                        theta / 2.0
                    } else {
                        theta / 3.0
                    };
                    let corner = theta - self.row_angle_left(&row, pn);
                    let off = (corner - share).abs() - self.params.tuning.choice.row_slack;
                    score = score.min(
                        (1.0 - off.max(0.0) / self.params.tuning.choice.row_falloff)
                            .clamp(self.params.tuning.choice.row_floor, 1.0),
                    );
                }
            }
        }
        if let Cand::Snap { s, q } = c {
            // The quad's corner at X must sit inside X's front wedge with
            // room on both sides, and a split must leave two even loops.
            let x = p[2];
            let (qn, qp) = (self.world(f.next(q)), self.world(f.prev(q)));
            let a1 = ccw_angle(x, qn, p[3]);
            let a2 = ccw_angle(x, p[1], qp);
            let corner = ccw_angle(x, p[3], p[1]);
            let wedge = f.angle(q, &self.mesh.nodes);
            if (a1 + corner + a2 - wedge).abs() > 1e-9
                || a1 < limits.min_front
                || a2 < limits.min_front
            {
                return None;
            }
            if f.slot(q).loop_id == f.slot(s).loop_id {
                let d = self.loop_distance(s, q);
                // The part between s and q (the shorter way round) with the
                // odd loops it takes in must be even.
                let (from, to) = if f.walk(s, d as isize) == q {
                    (s, q)
                } else {
                    (q, s)
                };
                let odd = self.part_parity(f.slot(s).loop_id, from, to);
                if (d + odd) % 2 == 1 || d < 4 || n - d < 4 {
                    return None;
                }
            }
        }
        Some(score)
    }
}

/// A sunburst of `n` needles from radius 0.05 to 1, counter-clockwise:
/// tips at even indices, the ends between them at odd ones.
#[cfg(test)]
pub(crate) fn sunburst(n: usize) -> Vec<Point> {
    (0..n)
        .flat_map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            let b = a + std::f64::consts::PI / n as f64;
            [
                Point::new(a.cos(), a.sin()),
                Point::new(0.05 * b.cos(), 0.05 * b.sin()),
            ]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extract::{Mesher, StepKind};

    #[test]
    fn a_needle_is_a_corner_no_quad_meets_the_side_ratio_at() {
        let p0 = Point::new(0.0, 0.0);
        let at = |deg: f64| Point::new(deg.to_radians().cos(), deg.to_radians().sin());
        assert!(is_needle(p0, at(0.0), at(1.0)));
        assert!(!is_needle(p0, at(0.0), at(5.0)));
        // Unequal sides: the shorter decides.
        assert!(!is_needle(p0, at(0.0), at(1.0) * 0.01));
    }

    /// Each of the 64 needles (0.1° at the tip) is closed by one kite, the
    /// kites' new nodes stay in the boundary's layer, and the disk inside
    /// is meshed by extraction with no fill; the invariants hold after
    /// every step.
    #[test]
    fn needles_close_by_their_kites_and_the_rest_by_extraction() {
        let n = 64;
        let pts = sunburst(n);
        let (p0, pl, pr) = (pts[0], pts[2 * n - 1], pts[1]);
        assert!(is_needle(p0, pl, pr));
        let mut m = Mesher::of_loop(pts);
        let kinds = m.run_checked();
        assert!(!kinds.contains(&StepKind::Fill), "{kinds:?}");
        // The first n steps are the kites, one per needle tip.
        assert!(kinds[..n].iter().all(|&k| k == StepKind::Element));
        let tips: Vec<u32> = (0..n as u32).map(|k| 2 * k).collect();
        for &t in &tips {
            let at_tip = m.mesh().quads.iter().filter(|q| q.contains(&t)).count();
            assert_eq!(at_tip, 1, "tip {t}");
        }
        assert!(m.mesh().check_finished().is_ok());
    }
}

//! The guard (method §2.6): a candidate quad is accepted only if it is
//! strictly convex and counter-clockwise, its new corners meet the angle
//! limits, it crosses and contains no front edge or node, and the front it
//! leaves has no sliver angle.

use crate::front::{Front, SlotId};
use crate::geom::{
    ccw_angle, is_strictly_convex, orient, point_segment_distance, segments_intersect, Point,
};

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
#[derive(Clone, Copy, Debug)]
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
    let consumed_edges: Vec<(u32, u32)> = consumed
        .iter()
        .map(|&s| (front.node(s), front.node(front.next(s))))
        .collect();
    let is_consumed = |k: usize| match (ids[k], ids[(k + 1) % 4]) {
        (Some(a), Some(b)) => consumed_edges.contains(&(b, a)) || consumed_edges.contains(&(a, b)),
        _ => false,
    };
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
        let corner = ccw_angle(p[k], p[(k + 1) % 4], p[(k + 3) % 4]);
        match corners[k] {
            Corner::Full(_) => {}
            Corner::New(_) => {
                if corner < limits.min_corner || corner > limits.max_corner {
                    return None;
                }
            }
            Corner::Partial(s) => {
                if corner < limits.min_corner || corner > limits.max_corner {
                    return None;
                }
                let rest = front.angle(s, nodes) - corner;
                if rest < limits.min_front {
                    return None;
                }
                front_factor =
                    front_factor.min(((rest.to_degrees() - 15.0) / 45.0).clamp(0.0, 1.0));
            }
        }
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
    let new_sides: Vec<usize> = (0..4).filter(|&k| !is_consumed(k)).collect();
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
        for &k in &new_sides {
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
            for &k in &new_sides {
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
    let stretch = (1.0 / q.aspect()).sqrt();
    let room = ((clearance / size - CLEAR_NONE) / (CLEAR_GOOD - CLEAR_NONE)).clamp(0.0, 1.0);
    // New sides far from the local size cost a little: a tie-breaker
    // between otherwise good elements, not a limit.
    let mut fit: f64 = 1.0;
    for &k in &new_sides {
        let len = p[k].distance(p[(k + 1) % 4]);
        fit = fit.min((1.0 - 0.35 * (len / size).ln().abs()).clamp(0.2, 1.0));
    }
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

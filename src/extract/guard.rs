//! The guard (method §2.6): a candidate quad is accepted only if it is
//! strictly convex and counter-clockwise, its new corners meet the angle
//! limits, it crosses and contains no front edge or node, and the front it
//! leaves has no sliver angle.

use crate::front::{Front, SlotId};
use crate::geom::{ccw_angle, is_strictly_convex, orient, segments_intersect, Point};

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

/// Scratch buffers reused across checks.
#[derive(Default, Debug, Clone)]
pub struct Scratch {
    pub near: Vec<SlotId>,
}

/// A candidate that passed the guard: its corners and its score.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Passed {
    pub corners: [Point; 4],
    /// Quality of the element and of the front it leaves, in `[0, 1]`:
    /// the minimum of the quad's scaled Jacobian, `1/aspect` softened, and
    /// a factor that falls from 1 to 0 as an angle left on the front drops
    /// from 60° to 15°.
    pub score: f64,
}

/// Checks a candidate quad. `consumed` are the front edges (by start slot)
/// that become sides of the quad. Returns the corners and score when it
/// passes.
pub fn check(
    front: &Front,
    nodes: &[Point],
    corners: [Corner; 4],
    consumed: &[SlotId],
    limits: Limits,
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
    // New edges: quad sides that are not consumed front edges.
    let consumed_edges: Vec<(u32, u32)> = consumed
        .iter()
        .map(|&s| (front.node(s), front.node(front.next(s))))
        .collect();
    let is_consumed = |k: usize| match (ids[k], ids[(k + 1) % 4]) {
        (Some(a), Some(b)) => consumed_edges.contains(&(b, a)) || consumed_edges.contains(&(a, b)),
        _ => false,
    };
    let lo = p.iter().fold(Point::splat(f64::INFINITY), |a, &b| a.min(b));
    let hi = p
        .iter()
        .fold(Point::splat(f64::NEG_INFINITY), |a, &b| a.max(b));
    front.edges_near(lo, hi, &mut scratch.near);
    let new_sides: Vec<usize> = (0..4).filter(|&k| !is_consumed(k)).collect();
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
        }
    }
    let q = crate::quality::Shape::of(p);
    let size = (1.0 / q.aspect()).sqrt();
    Some(Passed {
        corners: p,
        score: q.scaled_jacobian.min(size).min(front_factor),
    })
}

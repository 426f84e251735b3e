//! Notches: a front edge far shorter than the segments of the given
//! boundary on either side of it is cut off with those segments by an
//! element of type 1, or two short edges in a row by an element of type 0
//! and one of type 1 (thesis §2.1.2, Figure 18), taken by rule before
//! anything else is cut there.
//!
//! The model's normalisation (thesis §3.2) scales the leading points by the
//! edge to the reference point's right. Where that edge is a tenth of its
//! neighbours, the leading points lie far outside anything the model was
//! fitted on, and the elements it predicts there are slivers or fail the
//! guard: the dead end of a slit a few units wide between segments a
//! hundred long, its mouth once the dead end is closed, the junction of
//! two slits. The segments of the given boundary are fixed, so the quad
//! on each of them is as long as the segment whatever is done; the notch
//! takes the quad that also uses the short edge:
//!
//! - **one short edge** `b → c` between long segments `a → b` and
//!   `c → d`: the quad `a, b, c, d` (type 1 at `b`); the front then runs
//!   `a → d`.
//! - **two short edges** `b → c → d` between long segments `a → b` and
//!   `d → e`: the quads `a, b, c, x` and `x, c, d, e` (type 0 at `b`,
//!   type 1 at `c`), the new node `x` where the two quads' worst corner is
//!   squarest; the front then runs `a → x → e`.
//!
//! The front edges a notch leaves are notches in their turn when they are
//! as short: a slit closes from its dead end to its mouth, and the mouth
//! goes with the segments beside it.
//!
//! A notch is taken only if its quads are measurably convex with a scaled
//! Jacobian of at least [`super::tuning::NotchTuning::min_sj`] and no front edge or node
//! lies inside them or crosses them.

use super::report::{StepKind, StepReport};
use super::session::Mesher;
use crate::front::SlotId;
use crate::geom::{corner_sine, corner_sines, is_measurably_convex, weighted_points, Point};
use crate::quality::Shape;

/// The range of the weights in [`middle_node`]'s search.
const MIDDLE_RANGE: (f64, f64) = (0.0, 1.2);

/// The weights tried for each direction in [`middle_node`], evenly over
/// [`MIDDLE_RANGE`].
const MIDDLE_STEPS: usize = 25;

/// The front slots still to be looked at for a notch (the next one last),
/// and each boundary node's successor along the given boundary (to tell
/// the given segments from chords).
#[derive(Clone, Debug, Default)]
pub(super) struct Notches {
    pending: Vec<SlotId>,
    succ: Vec<u32>,
}

impl Notches {
    /// Every slot of the initial front is looked at once; the notches'
    /// own front edges are looked at again as they are made, and every
    /// slot again when a rip-up replaces loops.
    pub(super) fn of(m: &Mesher) -> Notches {
        if m.params.tuning.notch.min_ratio <= 0.0 {
            return Notches::default();
        }
        let mut succ = vec![u32::MAX; m.boundary_nodes];
        for (a, b) in m.boundary.segments() {
            succ[a] = b as u32;
        }
        let mut n = Notches {
            pending: Vec::new(),
            succ,
        };
        n.pending = n.listed(m);
        n
    }

    /// The slots of `m`'s front that have a notch's shape, in front order
    /// (the next one last): what the front is looked at for again after a
    /// rip-up.
    pub(super) fn listed(&self, m: &Mesher) -> Vec<SlotId> {
        if self.succ.is_empty() {
            return Vec::new();
        }
        m.initial_slots(|s| self.shape_at(m, s).is_some())
    }

    /// A rip-up replaced loops: `pending` is the front's slots to look at.
    pub(super) fn look_again(&mut self, pending: Vec<SlotId>) {
        self.pending = pending;
    }

    /// True when the front edge from slot `s` is a segment of the given
    /// boundary.
    fn given(&self, m: &Mesher, s: SlotId) -> bool {
        let (u, v) = (m.front.node(s), m.front.node(m.front.next(s)));
        self.succ.get(u as usize) == Some(&v)
    }

    /// The chain of a notch at slot `s`: `[a, b, c, d]` for one short edge
    /// from `s`, `[a, b, c, d, e]` for two short edges meeting at `s`,
    /// flanked by given segments at least
    /// [`super::tuning::NotchTuning::min_ratio`] times longer; `None` when
    /// `s` has neither.
    fn shape_at(&self, m: &Mesher, s: SlotId) -> Option<Vec<SlotId>> {
        let f = &m.front;
        if f.loop_len(s) < 6 {
            return None;
        }
        let ratio = m.params.tuning.notch.min_ratio;
        let len = |t: SlotId| m.world(t).distance(m.world(f.next(t)));
        let flanked = |left: SlotId, right: SlotId, short: f64| {
            self.given(m, left)
                && self.given(m, right)
                && len(left) >= ratio * short
                && len(right) >= ratio * short
        };
        let (p, n) = (f.prev(s), f.next(s));
        // One short edge s → n.
        if flanked(p, n, len(s)) {
            return Some(vec![p, s, n, f.next(n)]);
        }
        // Two short edges p → s → n.
        let pp = f.prev(p);
        if flanked(pp, n, len(p).max(len(s))) {
            return Some(vec![pp, p, s, n, f.next(n)]);
        }
        None
    }
}

/// A notch's quads over its chain's points and its new points: indices
/// into `[chain..., new...]`, counter-clockwise.
#[derive(Clone, Debug, PartialEq)]
pub struct NotchQuads {
    pub points: Vec<Point>,
    pub quads: Vec<[usize; 4]>,
}

/// The quads a notch takes over the chain `pts` (4 points: one short edge
/// between the middle two; 5 points: two short edges meeting at the
/// middle one), or `None` when a quad would not be measurably convex with
/// a scaled Jacobian of at least `min_sj`. `before` and `after` are the
/// front's points before the chain's first and after its last: a notch of
/// two short edges places its new node so that the front corners it
/// leaves there are square too ([`middle_node`]).
pub fn notch_quads(pts: &[Point], before: Point, after: Point, min_sj: f64) -> Option<NotchQuads> {
    let ok = |q: [Point; 4]| is_measurably_convex(q) && Shape::of(q).scaled_jacobian >= min_sj;
    match *pts {
        [a, b, c, d] => ok([a, b, c, d]).then(|| NotchQuads {
            points: Vec::new(),
            quads: vec![[0, 1, 2, 3]],
        }),
        [a, b, c, d, e] => {
            let x = middle_node([before, a, b, c, d, e, after])?;
            (ok([a, b, c, x]) && ok([x, c, d, e])).then(|| NotchQuads {
                points: vec![x],
                quads: vec![[0, 1, 2, 5], [5, 2, 3, 4]],
            })
        }
        _ => None,
    }
}

/// The new node `x = c + α (a − c) + γ (e − c)` of a notch of two short
/// edges over the front points `[before, a, b, c, d, e, after]`, with `α`
/// and `γ` each one of [`MIDDLE_STEPS`] values over [`MIDDLE_RANGE`]: the
/// one whose worst corner, of the quads `a, b, c, x` and `x, c, d, e` and
/// of the front corners left at `a` and `e`, is squarest. A front corner
/// counts by the size of its sine, so that only one near 0° or 180° is
/// poor (a flat corner there would be a flat corner of the next quad).
/// Where the worst corner is the same, as when it is a corner the notch
/// cannot change, the mean sine of the quads' corners decides. `None` if
/// no such pair of quads is measurably convex.
fn middle_node(p: [Point; 7]) -> Option<Point> {
    let [before, a, b, c, d, e, after] = p;
    let mut best: Option<((f64, f64), Point)> = None;
    for x in weighted_points(c, a - c, e - c, MIDDLE_RANGE, MIDDLE_STEPS) {
        let (q1, q2) = ([a, b, c, x], [x, c, d, e]);
        if !is_measurably_convex(q1) || !is_measurably_convex(q2) {
            continue;
        }
        let sines = [corner_sines(q1), corner_sines(q2)].concat();
        let worst = sines.iter().copied().fold(f64::INFINITY, f64::min);
        let mean = sines.iter().sum::<f64>() / sines.len() as f64;
        let front = corner_sine(before, a, x)
            .abs()
            .min(corner_sine(x, e, after).abs());
        let score = (worst.min(front), mean);
        if best.is_none_or(|(w, _)| score > w) {
            best = Some((score, x));
        }
    }
    best.map(|(_, x)| x)
}

impl Mesher {
    /// [`super::Rung::Notch`]: the next front edge far shorter than the
    /// given segments beside it is cut off with them, if its quads fit.
    pub(super) fn notch(&mut self) -> Option<StepReport> {
        let min_sj = self.params.tuning.notch.min_sj;
        while let Some(s) = self.notches.pending.pop() {
            if !self.front.slot(s).alive {
                continue;
            }
            let Some(chain) = self.notches.shape_at(self, s) else {
                continue;
            };
            let pts: Vec<Point> = chain.iter().map(|&t| self.world(t)).collect();
            let before = self.world(self.front.prev(chain[0]));
            let after = self.world(self.front.next(chain[chain.len() - 1]));
            let Some(notch) = notch_quads(&pts, before, after, min_sj) else {
                continue;
            };
            if !self.chain_is_clear(&chain, &notch.points) {
                continue;
            }
            return Some(self.commit_notch(&chain, &notch));
        }
        None
    }

    /// Commits a notch over `chain`: its quads, and the front running from
    /// the chain's first slot through the new node (if any) to its last.
    fn commit_notch(&mut self, chain: &[SlotId], notch: &NotchQuads) -> StepReport {
        let mut r = self.report(StepKind::Notch);
        let layer = chain
            .iter()
            .map(|&t| self.front.slot(t).layer)
            .max()
            .unwrap_or(0)
            + 1;
        let mut ids: Vec<u32> = chain.iter().map(|&t| self.front.node(t)).collect();
        self.add_patch(&mut r, &mut ids, &notch.points, &notch.quads);
        r.reference = Some(ids[1]);
        // Chain a, b, c, d: b and c leave the front. Chain a, b, c, d, e:
        // b and c leave it, and d's slot takes the new node.
        self.front.remove_pair(chain[1], &self.mesh.nodes);
        let (first, last) = (chain[0], chain[chain.len() - 1]);
        let mut touched = vec![first, last];
        if let Some(&x) = r.new_nodes.first() {
            self.front
                .replace_node(chain[3], x, layer, &self.mesh.nodes);
            touched.push(chain[3]);
        }
        for &t in &touched {
            self.push(t);
        }
        // The front edges the notch leaves may be notches too.
        self.notches.pending.extend(touched.into_iter().rev());
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point::new(x, y)
    }

    #[test]
    fn the_dead_end_of_a_slit_is_one_quad() {
        // A slit 4 wide and 120 long, its dead end at x = 120: the front
        // runs along its lower wall to the end, across and back.
        let chain = [p(0., 0.), p(120., 0.), p(120., 4.), p(0., 4.)];
        let (before, after) = (p(-100., -60.), p(-100., 64.));
        let n = notch_quads(&chain, before, after, 0.25).expect("notch");
        assert_eq!(n.quads, vec![[0, 1, 2, 3]]);
        assert!(n.points.is_empty());
        // A reflex short edge takes none.
        let reflex = [p(0., 0.), p(120., 0.), p(116., 4.), p(240., 4.)];
        assert!(notch_quads(&reflex, before, after, 0.25).is_none());
    }

    #[test]
    fn two_short_edges_take_two_quads_through_the_mouth() {
        // Slit 4 wide from the mouth (x = 0) to a junction at x = 120,
        // where two branches left it: the front runs up the lower wall, over
        // two short edges meeting at (122, 2), and back along the upper
        // wall.
        let chain = [p(0., 0.), p(120., 0.), p(122.3, 2.), p(120., 4.), p(0., 4.)];
        // Outside the mouth, the boundary turns away at 60° to either side.
        let (before, after) = (p(-60., -103.), p(-60., 107.));
        let n = notch_quads(&chain, before, after, 0.25).expect("notch");
        assert_eq!(n.points.len(), 1);
        let x = n.points[0];
        // The new node sits in the mouth, between the walls, leaving the
        // front corners there no flatter than the mouth's own 150°.
        assert!(x.x.abs() < 2.0 && x.y > 0.5 && x.y < 3.5, "{x:?}");
        assert!(corner_sine(before, chain[0], x) > 0.45);
        assert!(corner_sine(x, chain[4], after) > 0.45);
        let all = |k: usize| if k < 5 { chain[k] } else { n.points[k - 5] };
        let area: f64 = n
            .quads
            .iter()
            .map(|q| crate::geom::polygon_area(q.map(all)))
            .sum();
        let outline = crate::geom::polygon_area(chain.iter().copied().chain([x]));
        assert!((area - outline).abs() < 1e-9 * outline);
    }
}

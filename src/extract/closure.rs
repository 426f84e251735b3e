//! Closing small loops (method §2.7; thesis Figure 20): a 4-node loop is one
//! quad; a 6-node loop takes one of the final patterns
//!
//! - (a) an interior node at (x2+x4+x6)/3 joined to nodes 2, 4, 6;
//! - (b) an interior node at (3x3+3x5+x2+x6)/8 joined to nodes 1, 3, 5
//!   (decision: the figure's weights put the node near 3 and 5, so it
//!   joins the odd nodes);
//! - (c) the diagonal 3–6;
//!
//! chosen over all rotations as the valid one of best minimum scaled
//! Jacobian.
//!
//! A small loop that does not close as it stands has its movable nodes
//! settled first ([`Mesher::settle_small`]).

use super::guard::MAX_SIDE_RATIO;
use super::report::{StepKind, StepReport};
use super::session::Mesher;
use crate::front::SlotId;
use crate::geom::{is_measurably_convex, Point};
use crate::mesh::QuadMesh;
use crate::quality::Shape;
use crate::smooth::pattern_search;

/// A way to fill a 6-node loop: the quads (indices into the loop, with
/// 6 and 7 standing for the interior nodes) and the interior nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct Fill {
    pub pattern: char,
    pub interior: Vec<Point>,
    pub quads: Vec<[usize; 4]>,
    pub min_sj: f64,
}

/// Evaluates quads over `pts` (index 6 + k = `interior[k]`); `None` if any
/// is not measurably convex (no corner flat to rounding: the closure has
/// other patterns and rotations to choose from).
fn score(pts: &[Point], interior: &[Point], quads: &[[usize; 4]]) -> Option<f64> {
    let at = |i: usize| if i >= 6 { interior[i - 6] } else { pts[i] };
    let mut min_sj = f64::INFINITY;
    for q in quads {
        let p = q.map(at);
        if !is_measurably_convex(p) {
            return None;
        }
        min_sj = min_sj.min(Shape::of(p).scaled_jacobian);
    }
    Some(min_sj)
}

/// The best closure a loop of 4 or 6 nodes could have: the scaled
/// Jacobian (signed, so a folded closure scores below zero) of its one quad,
/// or the best over the patterns and rotations of [`fill_six`] of their
/// worst quad. A continuous measure a node can be moved to improve.
pub fn closure_quality(pts: &[Point]) -> f64 {
    match pts.len() {
        4 => Shape::of([pts[0], pts[1], pts[2], pts[3]]).scaled_jacobian,
        6 => {
            let p6: [Point; 6] = std::array::from_fn(|k| pts[k]);
            let mut best = f64::NEG_INFINITY;
            each_pattern(&p6, |_, interior, quads| {
                let at = |i: usize| if i >= 6 { interior[i - 6] } else { p6[i] };
                // Corners written out, as in `QuadMesh::corners`.
                let worst = quads
                    .iter()
                    .map(|q| Shape::of([at(q[0]), at(q[1]), at(q[2]), at(q[3])]).scaled_jacobian)
                    .fold(f64::INFINITY, f64::min);
                best = best.max(worst);
            });
            best
        }
        _ => f64::NEG_INFINITY,
    }
}

/// A pattern: its letter, interior nodes and quads (index 6 + k = the
/// interior node k).
type Pattern = (char, Vec<Point>, Vec<[usize; 4]>);

/// Every pattern of Figure 20 over every rotation of a 6-node loop.
fn patterns(pts: &[Point; 6]) -> Vec<Pattern> {
    let mut out = Vec::with_capacity(18);
    each_pattern(pts, |letter, interior, quads| {
        out.push((letter, interior.to_vec(), quads.to_vec()))
    });
    out
}

/// Gives `visit` every pattern of Figure 20 over every rotation of a
/// 6-node loop, in [`patterns`]' order: its letter, interior nodes and
/// quads, on the stack (a loop's closure is weighed this way at every
/// position of a node being settled).
fn each_pattern(pts: &[Point; 6], mut visit: impl FnMut(char, &[Point], &[[usize; 4]])) {
    for r in 0..6 {
        let i = |k: usize| (k - 1 + r) % 6; // 1-based pattern index → loop index
        visit(
            'a',
            &[(pts[i(2)] + pts[i(4)] + pts[i(6)]) / 3.0],
            &[
                [i(1), i(2), 6, i(6)],
                [i(2), i(3), i(4), 6],
                [i(4), i(5), i(6), 6],
            ],
        );
        visit(
            'b',
            &[(3.0 * pts[i(3)] + 3.0 * pts[i(5)] + pts[i(2)] + pts[i(6)]) / 8.0],
            &[
                [i(1), i(2), i(3), 6],
                [i(3), i(4), i(5), 6],
                [i(5), i(6), i(1), 6],
            ],
        );
        visit(
            'c',
            &[],
            &[[i(1), i(2), i(3), i(6)], [i(3), i(4), i(5), i(6)]],
        );
    }
}

/// Pattern (d) over every rotation, for when no pattern of Figure 20 gives
/// convex quads: two interior nodes and four quads, a strip along a loop
/// with a straight side (three edges in line against one, as in a thin
/// rectangle).
fn strip_patterns(pts: &[Point; 6]) -> Vec<Pattern> {
    let mut out = Vec::with_capacity(6);
    for r in 0..6 {
        let i = |k: usize| (k - 1 + r) % 6; // 1-based pattern index → loop index
                                            // (d): a half-way up from node 2 along side 1-6, b half-way up
                                            // from node 3 along side 4-5; quads 1-2-a-6, 2-3-b-a, 3-4-5-b and
                                            // a-b-5-6.
        out.push((
            'd',
            vec![
                pts[i(2)] + (pts[i(6)] - pts[i(1)]) / 2.0,
                pts[i(3)] + (pts[i(5)] - pts[i(4)]) / 2.0,
            ],
            vec![
                [i(1), i(2), 6, i(6)],
                [i(2), i(3), 7, 6],
                [i(3), i(4), i(5), 7],
                [6, 7, i(5), i(6)],
            ],
        ));
    }
    out
}

/// The best fill of a 6-node loop (positions in loop order, CCW), or `None`
/// when no pattern gives convex quads (pattern (d) only when none of
/// Figure 20's does). The caller still checks that an
/// interior node does not fall on other front edges.
pub fn fill_six(pts: &[Point; 6]) -> Option<Fill> {
    let best = |candidates: Vec<Pattern>| {
        let mut best: Option<Fill> = None;
        for (pattern, interior, quads) in candidates {
            if let Some(min_sj) = score(pts, &interior, &quads) {
                if best.as_ref().is_none_or(|b| min_sj > b.min_sj) {
                    best = Some(Fill {
                        pattern,
                        interior,
                        quads,
                        min_sj,
                    });
                }
            }
        }
        best
    };
    best(patterns(pts)).or_else(|| best(strip_patterns(pts)))
}

/// A loop's slots, nodes and points, in loop order
/// ([`Mesher::loop_geometry`]).
pub(super) type LoopGeometry = (Vec<SlotId>, Vec<u32>, Vec<Point>);

/// True when a loop's nodes repeat one (the loop touches itself there):
/// such a loop is not closed as a whole.
pub(super) fn is_pinched(nodes: &[u32]) -> bool {
    let mut uniq = nodes.to_vec();
    uniq.sort_unstable();
    uniq.dedup();
    uniq.len() != nodes.len()
}

impl Mesher {
    /// Loop `lid`'s slots, their nodes and the nodes' positions, in loop
    /// order from its head.
    pub(super) fn loop_geometry(&self, lid: u32) -> LoopGeometry {
        let slots = self.front.loop_slots(lid);
        let nodes: Vec<u32> = slots.iter().map(|&s| self.front.node(s)).collect();
        let pts: Vec<Point> = nodes.iter().map(|&v| self.mesh.nodes[v as usize]).collect();
        (slots, nodes, pts)
    }

    /// Closes a loop of 4 or 6 slots, if a valid closure exists.
    pub(super) fn close_small(&mut self, lid: u32) -> Option<StepReport> {
        let (slots, nodes, pts) = self.loop_geometry(lid);
        if is_pinched(&nodes) {
            return None; // leave it to extraction
        }
        match slots.len() {
            4 => {
                let q = [pts[0], pts[1], pts[2], pts[3]];
                let ids = [nodes[0], nodes[1], nodes[2], nodes[3]].map(Some);
                if !crate::geom::is_strictly_convex(q) || !self.pinned_corners_turn(q, ids) {
                    return None;
                }
                if !self.loop_is_clear(&slots, &nodes, &pts) {
                    return None;
                }
                let mut r = self.report(StepKind::Close4);
                let quad = [nodes[0], nodes[1], nodes[2], nodes[3]];
                self.push_quad(quad);
                self.front.remove_loop(lid);
                r.quads.push(quad);
                Some(r)
            }
            6 => {
                let p6: [Point; 6] = std::array::from_fn(|k| pts[k]);
                let fill = fill_six(&p6)?;
                if !self.loop_is_clear(&slots, &nodes, &pts) {
                    return None;
                }
                if fill
                    .interior
                    .iter()
                    .any(|&c| !crate::geom::point_in_polygon(c, &pts))
                {
                    return None;
                }
                let mut r = self.report(StepKind::Close6);
                r.pattern = Some(fill.pattern);
                let inner: Vec<u32> = fill.interior.iter().map(|&c| self.add_node(c)).collect();
                r.new_nodes.extend(&inner);
                for q in &fill.quads {
                    let quad = q.map(|i| if i >= 6 { inner[i - 6] } else { nodes[i] });
                    self.push_quad(quad);
                    r.quads.push(quad);
                }
                self.front.remove_loop(lid);
                Some(r)
            }
            _ => None,
        }
    }

    /// A key of what closing or settling small loop `lid` depends on: its
    /// nodes and where they and the corners of their quads are (never 0).
    pub(super) fn small_loop_key(&self, lid: u32) -> u64 {
        let mut h: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut mix = |x: u64| {
            h = (h ^ x).wrapping_mul(0x1000_0000_01b3).rotate_left(29);
        };
        for s in self.front.loop_slots(lid) {
            let v = self.front.node(s);
            mix(u64::from(v));
            for &q in &self.incident[v as usize] {
                for u in self.mesh.quads[q as usize] {
                    let p = self.mesh.nodes[u as usize];
                    mix(p.x.to_bits());
                    mix(p.y.to_bits());
                }
            }
            let p = self.mesh.nodes[v as usize];
            mix(p.x.to_bits());
            mix(p.y.to_bits());
        }
        h.max(1)
    }

    /// A loop of 4 or 6 slots that does not close as it stands: its
    /// movable nodes (made by extraction, on the front only once) are moved,
    /// each by a pattern search, to where the worst of their quads and of
    /// the loop's best closure ([`closure_quality`]) is best, keeping the
    /// front free of crossings and the loop running the way it ran
    /// (paving's smoothing before closure); no quad at a moved node falls
    /// under [`ClosureTuning::settle_floor`](super::tuning::ClosureTuning::settle_floor) (or its own measure, if lower). True when a
    /// node moved.
    pub(super) fn settle_small(&mut self, lid: u32) -> bool {
        let slots = self.front.loop_slots(lid);
        let nodes: Vec<u32> = slots.iter().map(|&s| self.front.node(s)).collect();
        if !matches!(nodes.len(), 4 | 6) {
            return false;
        }
        let area = self.front.loop_area(lid, &self.mesh.nodes);
        let mut moved = false;
        for (k, &s) in slots.iter().enumerate() {
            let v = nodes[k];
            if self.is_boundary(v) || !self.front_once(v) {
                continue;
            }
            let quads: Vec<u32> = self.incident[v as usize].clone();
            // A quad squeezed towards a triangle keeps good angles but not
            // its sides: both count.
            let measure = |c: [Point; 4]| {
                let shape = Shape::of(c);
                let sides = (MAX_SIDE_RATIO / shape.side_ratio()).min(1.0);
                shape.scaled_jacobian.min(sides)
            };
            // No quad may fall under its own measure or `ClosureTuning::settle_floor`,
            // whichever is lower: where the loop's closure is folded (a
            // negative quality), any quad over that would otherwise do,
            // and a node settled again at every step crept onto its
            // neighbour.
            let floors: Vec<f64> = quads
                .iter()
                .map(|&q| {
                    measure(self.mesh.corners(&self.mesh.quads[q as usize]))
                        .min(self.params.tuning.closure.settle_floor)
                })
                .collect();
            // The quads are measured first: a position one of them refuses
            // needs no closure weighed.
            let quality = |m: &QuadMesh| {
                let mut sjs = Vec::with_capacity(quads.len());
                for (&q, &floor) in quads.iter().zip(&floors) {
                    let c = m.corners(&m.quads[q as usize]);
                    if !is_measurably_convex(c) {
                        return None;
                    }
                    let sj = measure(c);
                    if sj < floor {
                        return None;
                    }
                    sjs.push(sj);
                }
                let pts: Vec<Point> = nodes.iter().map(|&u| m.nodes[u as usize]).collect();
                let mut worst = closure_quality(&pts);
                let mut sum = worst;
                for sj in sjs {
                    worst = worst.min(sj);
                    sum += sj;
                }
                Some((worst, sum))
            };
            let Some(start) = quality(&self.mesh) else {
                continue;
            };
            if start.0 >= self.params.tuning.closure.settled {
                continue;
            }
            let mut nbs: Vec<u32> = quads
                .iter()
                .flat_map(|&q| self.mesh.quads[q as usize])
                .filter(|&u| u != v)
                .collect();
            nbs.extend(nodes.iter().copied().filter(|&u| u != v));
            let old = self.mesh.nodes[v as usize];
            self.front.unfile_edges_at(s);
            let at = pattern_search(&mut self.mesh, v as usize, &nbs, start, |m, _| quality(m));
            let (pp, pn) = (
                self.world(self.front.prev(s)),
                self.world(self.front.next(s)),
            );
            let (np, nn) = (
                self.front.node(self.front.prev(s)),
                self.front.node(self.front.next(s)),
            );
            // The loop must keep running the way it ran (a closure's
            // quality need not see a loop turned inside out).
            let turned = |m: &QuadMesh| {
                let pts = nodes.iter().map(|&u| m.nodes[u as usize]);
                area * crate::geom::polygon_area(pts) <= 0.0
            };
            if at != old
                && (self.crosses_front(at, pp, &[v, np])
                    || self.crosses_front(at, pn, &[v, nn])
                    || turned(&self.mesh))
            {
                self.mesh.nodes[v as usize] = old;
            } else if at != old {
                moved = true;
                // What moved: the node, its two front edges and the quads
                // around it.
                let near = nbs.iter().map(|&u| self.mesh.nodes[u as usize]);
                if let Some(bb) = crate::geom::Aabb::of([old, at, pp, pn].into_iter().chain(near)) {
                    self.forget(Some(bb));
                }
            }
            self.front.refile_edges_at(s, v, &self.mesh.nodes);
        }
        if moved {
            for &s in &slots {
                self.push(s);
            }
        }
        moved
    }

    /// True when node `v` stands on the front once (not where a loop was
    /// pinched), judged by the slots at its position.
    pub(super) fn front_once(&mut self, v: u32) -> bool {
        let p = self.mesh.nodes[v as usize];
        let probe = Point::splat(1e-12 * (1.0 + p.abs().max_element()));
        self.front
            .edges_near(p - probe, p + probe, &mut self.scratch.near);
        let near = std::mem::take(&mut self.scratch.near);
        let count = near.iter().filter(|&&e| self.front.node(e) == v).count();
        self.scratch.near = near;
        count <= 1
    }

    /// No other front edge or node lies inside the loop `slots` (its
    /// `nodes` at `pts`, as [`Mesher::loop_geometry`] gives them; e.g. a
    /// hole not yet joined). A node the loop itself has is on its boundary,
    /// not inside: a neighbouring loop cut off along a chord shares the
    /// chord's nodes, and they do not stop either loop from closing.
    pub(super) fn loop_is_clear(&mut self, slots: &[SlotId], nodes: &[u32], pts: &[Point]) -> bool {
        let Some(bb) = crate::geom::Aabb::of(pts.iter().copied()) else {
            return true;
        };
        self.front
            .edges_near(bb.min, bb.max, &mut self.scratch.near);
        let lid = self.front.slot(slots[0]).loop_id;
        self.scratch.near.iter().all(|&e| {
            let v = self.front.node(e);
            self.front.slot(e).loop_id == lid
                || nodes.contains(&v)
                || !crate::geom::point_in_polygon(self.mesh.nodes[v as usize], pts)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 1 rectangle with a node half-way along each long side,
    /// counter-clockwise from the origin.
    fn two_by_one() -> [Point; 6] {
        let p = |x, y| Point::new(x, y);
        [
            p(0., 0.),
            p(1., 0.),
            p(2., 0.),
            p(2., 1.),
            p(1., 1.),
            p(0., 1.),
        ]
    }

    #[test]
    fn rectangle_of_six_uses_the_diagonal() {
        let f = fill_six(&two_by_one()).unwrap();
        assert_eq!(f.pattern, 'c');
        assert!((f.min_sj - 1.0).abs() < 1e-12);
    }

    /// Two 6-node loops parted by a chord of two nodes across a 2 × 1
    /// rectangle: each closes, though the other's nodes lie on its side
    /// (a point-in-polygon test of a node on the boundary may say inside).
    #[test]
    fn loops_sharing_a_chord_both_close() {
        use crate::front::Front;
        let p = |x, y| Point::new(x, y);
        let mut m = Mesher::of_loop(two_by_one().to_vec());
        let low = m.add_node(p(1., 1. / 3.));
        let high = m.add_node(p(1., 2. / 3.));
        let left = vec![0, 1, low, high, 4, 5];
        let right = vec![1, 2, 3, 4, high, low];
        m.front = Front::new(&[left, right], &m.mesh.nodes, 0.5);
        for lid in [1, 0] {
            let r = m.close_small(lid).expect("the loop closes");
            assert_eq!(r.kind, StepKind::Close6);
        }
        assert!(m.front.is_empty());
        m.mesh.check_invariants(true).unwrap();
    }

    #[test]
    fn hexagon_takes_an_interior_node() {
        let pts: [Point; 6] = std::array::from_fn(|k| {
            let a = std::f64::consts::TAU * k as f64 / 6.0;
            Point::new(a.cos(), a.sin())
        });
        let f = fill_six(&pts).unwrap();
        assert_eq!(f.quads.len(), 3);
        assert!(f.min_sj > 0.8, "{f:?}");
    }
}

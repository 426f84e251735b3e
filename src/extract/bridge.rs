//! Bridges (front collision across a gap; paving's closure of two facing
//! rows, thesis §5.1's stuck fronts): two front edges that face each
//! other, `s → s'` and `t → t'`, are joined by the one quad
//! `(s, s', t, t')`. The front then runs `s → t'` and `t → s'`: two loops
//! become one (a hole's front joins the front around it), or one loop
//! becomes two.
//!
//! The ladder asks for one where a loop would start a row across a gap
//! the row does not fit (a thin ring is its ring of quads), and where the
//! front is stuck: between a hole and the outer boundary that nearly
//! touch, any quad across the gap has the gap's height, and a hole with
//! only its corners inside a square with only its corners is meshed by
//! the four trapezoids of the ring. The bridge of best scaled Jacobian is
//! taken; the guard checks it as any element, with angle limits loose
//! enough for the slanted quads of a gap.

use super::guard::{self, Corner};
use super::report::StepKind;
use super::report::StepReport;
use super::session::Mesher;
use crate::front::SlotId;
use crate::geom::{is_strictly_convex, polygon_area, Point};
use crate::quality::Shape;

/// A bridge: the two front edges (by start slot) and the quad's scaled
/// Jacobian.
#[derive(Clone, Copy, Debug)]
struct Bridge {
    s: SlotId,
    t: SlotId,
    sj: f64,
}

impl Mesher {
    /// Joins the two facing front edges whose quad is the best (see the
    /// module's documentation), one of them on loop `from` if given, with
    /// a scaled Jacobian of at least `floor` across a gap at most `gap`
    /// times as high as the two edges are long; `None` when no pair passes
    /// the guard.
    pub(super) fn bridge(&mut self, from: Option<u32>, floor: f64, gap: f64) -> Option<StepReport> {
        // The edges searched from, and each one's position in its loop for
        // the parity of a split (a split's two edges are on one loop).
        let mut pos = std::mem::take(&mut self.scratch.loop_pos);
        pos.resize(pos.len().max(self.front.slots.len()), 0);
        let loops: Vec<u32> = match from {
            Some(lid) => vec![lid],
            None => self.front.live_loops().collect(),
        };
        let mut edges = Vec::new();
        for &lid in &loops {
            for (k, s) in self.front.loop_slots(lid).into_iter().enumerate() {
                pos[s as usize] = k;
                edges.push(s);
            }
        }
        let mut best: Option<Bridge> = None;
        let mut near = Vec::new();
        for &s in &edges {
            let s1 = self.front.next(s);
            let (a, b) = (self.world(s), self.world(s1));
            let reach = self.params.tuning.bridge.reach * a.distance(b);
            let pad = Point::splat(reach);
            self.front
                .edges_near(a.min(b) - pad, a.max(b) + pad, &mut near);
            for &t in &near {
                // Each pair once: from the edge of the lower slot.
                if from.is_none() && t <= s {
                    continue;
                }
                let Some(sj) = self.bridge_quality(s, t, &pos, gap) else {
                    continue;
                };
                if sj >= floor && best.is_none_or(|x| sj > x.sj) {
                    best = Some(Bridge { s, t, sj });
                }
            }
        }
        self.scratch.loop_pos = pos;
        let Bridge { s, t, .. } = best?;
        Some(self.commit_bridge(s, t))
    }

    /// The scaled Jacobian of the bridge between the front edges from `s`
    /// and from `t`, if the guard takes it and the loops it leaves can be
    /// closed (a split's parts of four nodes or more, of the parity their
    /// holes ask).
    fn bridge_quality(&mut self, s: SlotId, t: SlotId, pos: &[usize], gap: f64) -> Option<f64> {
        let f = &self.front;
        let (s1, t1) = (f.next(s), f.next(t));
        let ids = [f.node(s), f.node(s1), f.node(t), f.node(t1)];
        if (0..4).any(|i| (i + 1..4).any(|j| ids[i] == ids[j])) {
            return None;
        }
        let p = ids.map(|v| self.mesh.nodes[v as usize]);
        let (ls, lt) = (p[0].distance(p[1]), p[2].distance(p[3]));
        if ls.max(lt) > self.params.tuning.bridge.edge_ratio * ls.min(lt) || !is_strictly_convex(p)
        {
            return None;
        }
        let lid = f.slot(s).loop_id;
        if f.slot(t).loop_id == lid {
            let n = f.loops[lid as usize].len;
            // The part from s' forward to t, closed by t → s'.
            let part = (pos[t as usize] + n - pos[s1 as usize]) % n + 1;
            if part < 4 || n - part < 4 || part % 2 != self.part_parity(lid, s1, t) {
                return None;
            }
        }
        let corners = [
            Corner::Partial(s),
            Corner::Partial(s1),
            Corner::Partial(t),
            Corner::Partial(t1),
        ];
        // The gap's height: the quad's area over the mean of the two
        // front edges it joins, which it is measured against.
        let width = 0.5 * (ls + lt);
        if polygon_area(p) > gap * width * width {
            return None;
        }
        let size = self.size.at(0.25 * (p[0] + p[1] + p[2] + p[3]));
        guard::check(
            &self.front,
            &self.mesh.nodes,
            corners,
            &[s, t],
            self.params.tuning.bridge.limits,
            size,
            &mut self.scratch,
        )?;
        Some(Shape::of(p).scaled_jacobian)
    }

    /// Commits the bridge between the front edges from `s` and from `t`.
    fn commit_bridge(&mut self, s: SlotId, t: SlotId) -> StepReport {
        let mut r = self.report(StepKind::Bridge);
        let (s1, t1) = (self.front.next(s), self.front.next(t));
        let quad = [s, s1, t, t1].map(|x| self.front.node(x));
        r.reference = Some(quad[0]);
        self.push_quad(quad);
        r.quads.push(quad);
        self.front.relink(s, t, &self.mesh.nodes);
        self.rows.check_loop(self.front.slot(s).loop_id);
        self.rows.check_loop(self.front.slot(t).loop_id);
        for x in [s, s1, t, t1, self.front.prev(s), self.front.prev(t)] {
            self.push(x);
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use crate::extract::{Mesher, StepKind};
    use crate::geom::Point;

    /// Meshes the loops (outer first) with the shipped model, checking the
    /// invariants after every step; also returns the steps' kinds.
    /// Band closure is turned off: it would close the rings below in one
    /// step, and these tests are of the bridges.
    fn run(loops: Vec<Vec<Point>>) -> (Mesher, Vec<StepKind>) {
        let mut m = Mesher::of_loops(loops);
        m.params.tuning.band.max_rows = 0;
        let kinds = m.run_checked();
        (m, kinds)
    }

    /// A square hole in a square, corners only: the ring's four trapezoids,
    /// by extraction (the region fill made 30 quads of scaled Jacobian 0.12).
    #[test]
    fn a_corner_only_square_ring_is_four_trapezoids() {
        let p = |x: f64, y: f64| Point::new(x, y);
        let (m, kinds) = run(vec![
            vec![p(0.0, 0.0), p(4.0, 0.0), p(4.0, 4.0), p(0.0, 4.0)],
            vec![p(1.0, 1.0), p(1.0, 3.0), p(3.0, 3.0), p(3.0, 1.0)],
        ]);
        assert!(!kinds.contains(&StepKind::Fill), "{kinds:?}");
        assert!(kinds.contains(&StepKind::Bridge), "{kinds:?}");
        assert_eq!(m.mesh().quads.len(), 4);
        assert!(m.mesh().check_finished().is_ok());
    }

    /// A square hole a twentieth of the spacing above the bottom of a
    /// rectangle, its nodes half a spacing off the bottom's: the gap under
    /// it closes by bridges (slanted, as any quad there must be), and the
    /// rest by extraction, with no fill.
    #[test]
    fn a_hole_that_nearly_touches_the_boundary_is_bridged() {
        let p = |x: f64, y: f64| Point::new(x, y);
        let mut outer: Vec<Point> = (0..20).map(|i| p(i as f64, 0.0)).collect();
        outer.extend((0..10).map(|j| p(20.0, j as f64)));
        outer.extend((0..20).map(|i| p(20.0 - i as f64, 10.0)));
        outer.extend((0..10).map(|j| p(0.0, 10.0 - j as f64)));
        // (The boundary orients its loops: the hole runs either way.)
        let (x0, y0) = (5.5, 0.05);
        let mut hole: Vec<Point> = (0..4).map(|j| p(x0, y0 + 4.0 - j as f64)).collect();
        hole.extend((0..4).map(|i| p(x0 + i as f64, y0)));
        hole.extend((0..4).map(|j| p(x0 + 4.0, y0 + j as f64)));
        hole.extend((0..4).map(|i| p(x0 + 4.0 - i as f64, y0 + 4.0)));
        let (m, kinds) = run(vec![outer, hole]);
        assert!(!kinds.contains(&StepKind::Fill), "{kinds:?}");
        assert!(kinds.contains(&StepKind::Bridge), "{kinds:?}");
        assert!(m.mesh().check_finished().is_ok());
    }

    /// A thin ring (gap a fifth of the spacing) starts with a bridge across
    /// the gap, where no row fits, and is its ring of quads, one per
    /// boundary segment, with no fill (it was 309 quads of scaled Jacobian
    /// 0.024 with a fill).
    #[test]
    fn a_thin_ring_closes_by_bridges() {
        let n = 40;
        let ring = |r: f64, cw: bool| -> Vec<Point> {
            let mut v: Vec<Point> = (0..n)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / n as f64;
                    Point::new(r * a.cos(), r * a.sin())
                })
                .collect();
            if cw {
                v.reverse();
            }
            v
        };
        let gap = 0.2 * std::f64::consts::TAU / n as f64;
        let (m, kinds) = run(vec![ring(1.0, false), ring(1.0 - gap, true)]);
        assert!(!kinds.contains(&StepKind::Fill), "{kinds:?}");
        assert_eq!(kinds[0], StepKind::Bridge, "{kinds:?}");
        assert_eq!(m.mesh().quads.len(), n);
        assert!(m.mesh().check_finished().is_ok());
    }
}

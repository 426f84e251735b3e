//! Row coarsening by a transition element (the "tuck" of paving, Blacker
//! and Stephenson 1991, as the 3-to-1 template). The thesis asks for
//! element sizes that follow the boundary and change smoothly (§1.2), but
//! its three element types keep a straight row's node count: type 0 moves
//! one node forward, and types 1 and 2 need a corner. Where a row runs
//! along a straight stretch of front whose edges are much shorter than the
//! size field wants (a fine side facing a coarse one, a ring shrinking
//! around a disk), the row would go on as ever thinner quads. Instead, three
//! front edges are taken at once by four quads:
//!
//! ```text
//!  T0 ______________ T3
//!    |\            /|
//!    | m1 ------ m2 |
//!    |  |        |  |
//!   a0--a1------a2--a3
//! ```
//!
//! `a0..a3` are front nodes in front order, one of `T0` / `T3` is the top
//! of the row's last element and the other is new, as are `m1` and `m2`.
//! The front `a0 a1 a2 a3` becomes `T0 T3`: two nodes fewer (the parity of
//! every loop is kept), and the row goes on three times as coarse.

use super::guard::{self, Corner, Limits};
use super::report::{StepKind, StepReport};
use super::session::Mesher;
use crate::front::SlotId;
use crate::geom::Point;
use crate::quality::Shape;

/// The transitions' state: per node made by a row, the row's elements
/// since its last transition, counted at the element's top
/// ([`FRESH_ROW`] for a node no row made).
#[derive(Clone, Debug, Default)]
pub(super) struct RowRuns {
    since: Vec<u32>,
}

impl RowRuns {
    /// Runs for `nodes` nodes no row made.
    pub(super) fn new(nodes: usize) -> RowRuns {
        RowRuns {
            since: vec![FRESH_ROW; nodes],
        }
    }

    /// A new node, made by no row yet.
    pub(super) fn add_node(&mut self) {
        self.since.push(FRESH_ROW);
    }

    /// The run of the row element whose top is node `top`, one element
    /// on: what the element's new node carries.
    pub(super) fn next(&self, top: u32) -> u32 {
        self.since[top as usize].saturating_add(1)
    }

    /// Node `v` carries run `run`.
    pub(super) fn set(&mut self, v: u32, run: u32) {
        self.since[v as usize] = run;
    }
}

/// What a node's row count ([`RowRuns`]) starts at: a row's first
/// element may be a transition.
const FRESH_ROW: u32 = u32::MAX / 2;

/// A transition laid out at a reference slot, before the guard: the
/// stretch it takes, its new points and its outline against the front.
struct Plan {
    right: bool,
    a: [SlotId; 4],
    ids: [u32; 4],
    top: SlotId,
    top_id: u32,
    m1: Point,
    m2: Point,
    t0: Point,
    t3: Point,
    corners: [Corner; 4],
    consumed: [SlotId; 4],
    want: f64,
}

impl Mesher {
    /// The transition element at reference slot `s` when the row `s`
    /// continues runs on along a straight, too-fine stretch of front, if it
    /// passes the guard: the step that commits it.
    pub(super) fn try_transition(&mut self, s: SlotId, limits: Limits) -> Option<StepReport> {
        let plan = self.transition_plan(s)?;
        let passed = guard::check(
            &self.front,
            &self.mesh.nodes,
            plan.corners,
            &plan.consumed,
            limits,
            plan.want,
            &mut self.scratch,
        )?;
        if passed.score < self.params.tuning.transition.min_score {
            return None;
        }
        // Commit: the reference slot becomes the new top and a1, a2 leave
        // the front.
        let mut r = self.report(StepKind::Transition);
        r.reference = Some(self.front.node(s));
        let layer = self.front.slot(plan.top).layer;
        let (v1, v2) = (self.add_node(plan.m1), self.add_node(plan.m2));
        let vt = self.add_node(if plan.right { plan.t3 } else { plan.t0 });
        let (id0, id3) = if plan.right {
            (plan.top_id, vt)
        } else {
            (vt, plan.top_id)
        };
        for q in [
            [plan.ids[0], plan.ids[1], v1, id0],
            [plan.ids[1], plan.ids[2], v2, v1],
            [plan.ids[2], plan.ids[3], id3, v2],
            [v1, v2, id3, id0],
        ] {
            self.push_quad(q);
            r.quads.push(q);
        }
        r.new_nodes = vec![v1, v2, vt];
        self.runs.since[vt as usize] = 0;
        self.front.replace_node(s, vt, layer, &self.mesh.nodes);
        self.front.remove_pair(plan.a[1], &self.mesh.nodes);
        let other_end = if plan.right { plan.a[3] } else { plan.a[0] };
        for x in [s, plan.top, other_end] {
            self.push(x);
        }
        Some(r)
    }

    /// Whether a transition may be laid out at reference slot `s` (it may
    /// still fail the guard): `false` stays so until the front within
    /// [`Mesher::transition_extent`] of `s` changes.
    pub(super) fn transition_laid(&self, s: SlotId) -> bool {
        self.transition_plan(s).is_some()
    }

    /// The box of the front a transition's layout at `s` reads: the slots
    /// as far either side as [`Mesher::spacing_around`] looks.
    pub(super) fn transition_extent(&self, s: SlotId) -> Option<crate::geom::Aabb> {
        let f = &self.front;
        let reach = self.spacing_reach().max(0) as usize + 4;
        let (mut back, mut ahead) = (s, s);
        let mut pts = vec![self.world(s)];
        for _ in 0..reach.min(f.loop_len(s)) {
            (back, ahead) = (f.prev(back), f.next(ahead));
            pts.push(self.world(back));
            pts.push(self.world(ahead));
        }
        crate::geom::Aabb::of(pts)
    }

    /// The transition at `s` laid out (see [`Mesher::try_transition`]),
    /// before the guard.
    fn transition_plan(&self, s: SlotId) -> Option<Plan> {
        let coarser = self.params.transition_ratio?;
        let row = self.row_at(s)?;
        let f = &self.front;
        if f.loop_len(s) < self.params.tuning.transition.min_loop {
            return None;
        }
        let along = |x: SlotId| if row.right { f.next(x) } else { f.prev(x) };
        let (b1, top) = (row.base, if row.right { f.prev(s) } else { f.next(s) });
        let b2 = along(b1);
        let b3 = along(b2);
        // Front order: a[0] → a[3]; the existing top stands over a[0] when
        // the row goes right, over a[3] when it goes left.
        let a = if row.right {
            [s, b1, b2, b3]
        } else {
            [b3, b2, b1, s]
        };
        let ids = a.map(|x| f.node(x));
        let top_id = f.node(top);
        for (i, &v) in ids.iter().enumerate() {
            if v == top_id || ids[i + 1..].contains(&v) {
                return None;
            }
        }
        for x in [b1, b2] {
            if f.off_straight(x, &self.mesh.nodes, &self.angles.straight) {
                return None;
            }
        }
        let p = a.map(|x| self.world(x));
        let e = [
            p[0].distance(p[1]),
            p[1].distance(p[2]),
            p[2].distance(p[3]),
        ];
        let (lo, hi) = e.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &l| {
            (lo.min(l), hi.max(l))
        });
        let total = e[0] + e[1] + e[2];
        let width = total / 3.0;
        if !(lo > 0.0 && hi / lo <= self.params.tuning.transition.even) {
            return None;
        }
        let under = if row.right { p[0] } else { p[3] };
        let pt = self.world(top);
        let h0 = under.distance(pt);
        if h0 < self.params.tuning.transition.min_height * width {
            return None;
        }
        let chord = p[3] - p[0];
        let normal = chord.perp() / chord.length();
        let want = self.size.at(0.5 * (p[0] + p[3]) + normal * (0.5 * h0));
        let ratio = want / self.spacing_around(a[0], a[3], total);
        if ratio.is_nan() || ratio < coarser.max(1.0 + 1e-3) {
            return None;
        }
        // A row coarser by `ratio` than its front takes one transition
        // (three edges to one) per `k` ordinary elements (one to one):
        // (3 + k) / (1 + k) = ratio.
        let k = ((3.0 - ratio) / (ratio - 1.0)).max(0.0).round();
        if f64::from(self.runs.since[top_id as usize]) < k {
            return None;
        }
        // The new top: over the other end, along the mean of the chord's
        // normal and the existing side, the height drawn towards the size.
        let side = (pt - under) / h0;
        let dir = (normal + side).normalize_or_zero();
        if dir == Point::ZERO {
            return None;
        }
        let h = want.clamp(
            h0 / self.params.tuning.transition.height_step,
            h0 * self.params.tuning.transition.height_step,
        );
        let (t0, t3) = if row.right {
            (pt, p[3] + dir * h)
        } else {
            (p[0] + dir * h, pt)
        };
        let on_top = |u: f64| t0 + (t3 - t0) * u;
        let m1 = p[1] + (on_top(e[0] / total) - p[1]) * self.params.tuning.transition.mid;
        let m2 = p[2] + (on_top((e[0] + e[1]) / total) - p[2]) * self.params.tuning.transition.mid;
        let quads = [
            [p[0], p[1], m1, t0],
            [p[1], p[2], m2, m1],
            [p[2], p[3], t3, m2],
            [m1, m2, t3, t0],
        ];
        for q in quads {
            if !crate::geom::is_strictly_convex(q)
                || Shape::of(q).scaled_jacobian < self.params.tuning.transition.min_sj
            {
                return None;
            }
        }
        // Boundary nodes never move: their corners must turn measurably.
        let bottom_ids = [
            [Some(ids[0]), Some(ids[1]), None, None],
            [Some(ids[1]), Some(ids[2]), None, None],
            [Some(ids[2]), Some(ids[3]), None, None],
        ];
        for (q, qi) in quads.iter().zip(bottom_ids) {
            if !self.pinned_corners_turn(*q, qi) {
                return None;
            }
        }
        // The template's outline against the rest of the front.
        let (corners, consumed) = if row.right {
            (
                [
                    Corner::Full(a[0]),
                    Corner::Partial(a[3]),
                    Corner::New(t3),
                    Corner::Partial(top),
                ],
                [top, a[0], a[1], a[2]],
            )
        } else {
            (
                [
                    Corner::Partial(a[0]),
                    Corner::Full(a[3]),
                    Corner::Partial(top),
                    Corner::New(t0),
                ],
                [a[0], a[1], a[2], a[3]],
            )
        };
        Some(Plan {
            right: row.right,
            a,
            ids,
            top,
            top_id,
            m1,
            m2,
            t0,
            t3,
            corners,
            consumed,
            want,
        })
    }

    /// Front edges either side of a stretch looked at for the top of an
    /// earlier transition: [`TransitionTuning::spacing_reach`](super::tuning::TransitionTuning::spacing_reach), or more at a ratio closer to
    /// one, where transitions stand further apart along a row (the `k`
    /// ordinary elements per transition at the ratio itself, rounded up).
    fn spacing_reach(&self) -> isize {
        let t = self.params.transition_ratio.unwrap_or(1.3).max(1.0 + 1e-3);
        let k = ((3.0 - t) / (t - 1.0)).ceil().clamp(0.0, 64.0) as isize;
        self.params.tuning.transition.spacing_reach.max(k)
    }

    /// The width the stretch from slot `from` to slot `to` (its three edges
    /// `stretch` long in all) is judged by: its own mean edge, or, where an
    /// edge [`TransitionTuning::wide`](super::tuning::TransitionTuning::wide) times that lies within [`TransitionTuning::spacing_reach`](super::tuning::TransitionTuning::spacing_reach) edges either
    /// side (the top of an earlier transition, carried up by the rows
    /// since), the mean edge length over the stretch and those edges (fewer
    /// where the loop is short).
    fn spacing_around(&self, from: SlotId, to: SlotId, stretch: f64) -> f64 {
        let f = &self.front;
        let width = stretch / 3.0;
        let reach = self
            .spacing_reach()
            .min((f.loop_len(from) as isize - 3) / 2 - 1)
            .max(0);
        let (mut sum, mut edges, mut wide) = (stretch, 3.0, false);
        let (mut back, mut ahead) = (from, to);
        for _ in 0..reach {
            let (b, a) = (f.prev(back), f.next(ahead));
            let (lb, la) = (
                self.world(b).distance(self.world(back)),
                self.world(ahead).distance(self.world(a)),
            );
            wide |= lb.max(la) > self.params.tuning.transition.wide * width;
            sum += lb + la;
            edges += 2.0;
            (back, ahead) = (b, a);
        }
        if wide {
            sum / edges
        } else {
            width
        }
    }
}

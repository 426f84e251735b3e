//! Topological cleanup of a finished mesh: local changes of connectivity
//! that bring node valences towards their ideal, so that smoothing can
//! reach the thesis's element criteria (every angle in [45°, 135°], thesis
//! §1.2 and §5.1; method §5). The thesis leaves the mesh's topology as
//! extraction made it; where fronts meet, extraction and the region fill
//! leave interior nodes of valence 2, 3 and 5 or more, whose quads no node
//! placement makes square.
//!
//! The valence of a node is its number of quads. Its ideal is 4 inside and,
//! on the boundary, its interior angle in right angles (at least 1). (An
//! interior node of valence 2 cannot occur: its two quads' angles there add
//! up to 360°, so one is not convex.) The operations, every quad they make
//! measurably convex ([`crate::geom::is_measurably_convex`]):
//!
//! - **Sliver collapse**: a quad with a scaled Jacobian below
//!   [`CleanupParams::sliver_sj`] (a needle or a flattened quad, where
//!   fronts met at a shallow angle) is removed by merging two opposite
//!   corners, the shorter diagonal first, when that leaves fewer such quads
//!   around and the worst of them no worse; an interior corner may merge
//!   into a boundary node.
//! - **Diagonal collapse**: a quad whose opposite corners are interior
//!   nodes of valence 3 is removed and the two nodes merge at their
//!   midpoint.
//! - **Edge swap**: the hexagon of two quads sharing an interior edge is
//!   re-split along one of its two other diagonals.
//!
//! The collapse and the swap are taken only when they lower the sum of
//! squared deviations from the ideal valence over the nodes they touch, and
//! the quads they make must not be thin ([`QuadQuality::THIN_RS`]).
//!
//! Boundary nodes never move and are never removed. Passes run in node,
//! quad and edge order, so the result is deterministic. Removed nodes are
//! dropped with [`QuadMesh::compact`]; the caller smooths afterwards.

use serde::{Deserialize, Serialize};

use crate::geom::{ccw_angle, is_measurably_convex, Point};
use crate::mesh::QuadMesh;
use crate::quality::{QuadQuality, Shape};
use crate::smooth::{after_change, pattern_search, smooth_and_optimize, SmoothParams};

/// Cleanup parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CleanupParams {
    /// Passes over the mesh (default 4; 0 turns cleanup off). A pass that
    /// changes nothing ends the cleanup early.
    pub passes: usize,
    /// An edge swap must leave both new quads with at least this scaled
    /// Jacobian, or with no less than the worse of the two old ones
    /// (default 0.2).
    pub min_swap_quality: f64,
    /// Rounds of cleanup and smoothing in [`improve`] (default 8): a swap
    /// refused in one round for want of convexity is often taken after the
    /// smoothing that follows. Rounds stop early when a cleanup changes
    /// nothing, and after a round that changed less than a twentieth of
    /// what the first changed.
    pub rounds: usize,
    /// A quad whose scaled Jacobian is below this is collapsed across a
    /// diagonal when that raises the worst quad around it (default 0.2;
    /// 0 turns it off).
    pub sliver_sj: f64,
}

impl CleanupParams {
    pub const DEFAULT: CleanupParams = CleanupParams {
        passes: 4,
        min_swap_quality: 0.2,
        rounds: 8,
        sliver_sj: 0.2,
    };
    /// No cleanup.
    pub const OFF: CleanupParams = CleanupParams {
        passes: 0,
        min_swap_quality: 0.2,
        rounds: 0,
        sliver_sj: 0.0,
    };
}

impl Default for CleanupParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What a cleanup changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CleanupReport {
    /// Quads below [`CleanupParams::sliver_sj`] collapsed.
    pub slivers: usize,
    /// Quads between two valence-3 nodes collapsed.
    pub collapses: usize,
    pub swaps: usize,
}

impl CleanupReport {
    /// All changes made.
    pub fn total(&self) -> usize {
        self.slivers + self.collapses + self.swaps
    }
}

/// The mesh being changed: quads with a live flag and each node's quads.
struct Work<'a> {
    mesh: &'a mut QuadMesh,
    nb: usize,
    alive: Vec<bool>,
    /// Quads made or moved by a change.
    changed: Vec<bool>,
    inc: Vec<Vec<u32>>,
    ideal: Vec<i32>,
    /// Ticks once per change.
    clock: u32,
    /// Per quad, the tick of the last change to anything an operation on
    /// it looks at: its corners' quads, their nodes' positions and
    /// valences.
    stamp: Vec<u32>,
}

impl Work<'_> {
    fn valence(&self, v: u32) -> i32 {
        self.inc[v as usize].len() as i32
    }

    fn dev(&self, v: u32, valence: i32) -> i32 {
        let d = valence - self.ideal[v as usize];
        d * d
    }

    fn interior(&self, v: u32) -> bool {
        v as usize >= self.nb
    }

    /// Measurably convex and not thin ([`QuadQuality::THIN_RS`]).
    fn convex(&self, q: &[u32; 4]) -> bool {
        let p = self.mesh.corners(q);
        is_measurably_convex(p) && Shape::of(p).rs >= QuadQuality::THIN_RS
    }

    fn sj(&self, q: &[u32; 4]) -> f64 {
        Shape::of(self.mesh.corners(q)).scaled_jacobian
    }

    /// The worst scaled Jacobian of `quads` and how many are below `bound`.
    fn slivers<'q>(&self, quads: impl Iterator<Item = &'q [u32; 4]>, bound: f64) -> (f64, usize) {
        quads.fold((f64::INFINITY, 0), |(m, n), r| {
            let sj = self.sj(r);
            (m.min(sj), n + usize::from(sj < bound))
        })
    }

    /// Records a change to quad `k` (made, removed or a corner moved; called
    /// while it is in its nodes' quad lists): every quad with a corner that
    /// shares a quad with a node of `k` is stamped with the next tick.
    fn touch(&mut self, k: u32) {
        self.clock += 1;
        self.changed[k as usize] = true;
        for x in self.mesh.quads[k as usize] {
            self.stamp_around(x);
        }
    }

    /// Stamps with the current tick every quad with a corner that shares a
    /// quad with node `x`: what a change at `x` can make decide otherwise.
    fn stamp_around(&mut self, x: u32) {
        for &m in &self.inc[x as usize] {
            for c in self.mesh.quads[m as usize] {
                for &j in &self.inc[c as usize] {
                    self.stamp[j as usize] = self.clock;
                }
            }
        }
    }

    fn remove_quad(&mut self, k: u32) {
        self.touch(k);
        self.alive[k as usize] = false;
        for v in self.mesh.quads[k as usize] {
            self.inc[v as usize].retain(|&j| j != k);
        }
    }

    fn set_quad(&mut self, k: u32, q: [u32; 4]) {
        self.remove_quad(k);
        self.mesh.quads[k as usize] = q;
        self.alive[k as usize] = true;
        self.touch(k);
        for v in q {
            self.inc[v as usize].push(k);
            self.inc[v as usize].sort_unstable();
        }
    }

    /// Collapses quad `k` across the diagonal of two interior valence-3
    /// corners.
    fn collapse(&mut self, k: u32) -> bool {
        let q = self.mesh.quads[k as usize];
        for i in 0..2 {
            let (v, w) = (q[i], q[i + 2]);
            let (s, t) = (q[i + 1], q[(i + 3) % 4]);
            if !(self.interior(v) && self.interior(w))
                || self.valence(v) != 3
                || self.valence(w) != 3
                || s == t
            {
                continue;
            }
            let before = self.dev(v, 3)
                + self.dev(w, 3)
                + self.dev(s, self.valence(s))
                + self.dev(t, self.valence(t));
            let after = self.dev(v, 4)
                + self.dev(s, self.valence(s) - 1)
                + self.dev(t, self.valence(t) - 1);
            if after < before && self.merge(k, i, None) {
                return true;
            }
        }
        false
    }

    /// Collapses quad `k`, when its scaled Jacobian is below `below`,
    /// across its shorter diagonal first (see [`Work::merge`]).
    fn collapse_sliver(&mut self, k: u32, below: f64) -> bool {
        let q = self.mesh.quads[k as usize];
        let old = self.sj(&q);
        if old >= below {
            return false;
        }
        let p = |v: u32| self.mesh.nodes[v as usize];
        let order = if p(q[0]).distance(p(q[2])) <= p(q[1]).distance(p(q[3])) {
            [0, 1]
        } else {
            [1, 0]
        };
        order.into_iter().any(|i| self.merge(k, i, Some(below)))
    }

    /// Removes quad `k` by merging its corners `i` and `i + 2` into one
    /// node, at the boundary node if one of them is on the boundary. With
    /// `sliver: None` the node goes to their midpoint or either end, the
    /// first where every quad changed is measurably convex and not thin.
    /// With `Some(bound)` it goes where the worst quad around is best
    /// ([`pattern_search`] from the midpoint), and the quads there must be
    /// measurably convex, fewer of them below `bound` scaled Jacobian and
    /// the worst no worse than before.
    fn merge(&mut self, k: u32, i: usize, sliver: Option<f64>) -> bool {
        let q = self.mesh.quads[k as usize];
        let (mut v, mut w) = (q[i], q[i + 2]);
        let (s, t) = (q[i + 1], q[(i + 3) % 4]);
        if !self.interior(w) {
            std::mem::swap(&mut v, &mut w);
        }
        if !self.interior(w) || s == t || self.valence(s) < 3 || self.valence(t) < 3 {
            return false;
        }
        // Quads of w other than k, with w renamed v.
        let others: Vec<u32> = self.inc[w as usize]
            .iter()
            .copied()
            .filter(|&j| j != k)
            .collect();
        if others
            .iter()
            .any(|&j| self.mesh.quads[j as usize].contains(&v))
        {
            return false;
        }
        let (pv, pw) = (self.mesh.nodes[v as usize], self.mesh.nodes[w as usize]);
        let renamed: Vec<[u32; 4]> = others
            .iter()
            .map(|&j| self.mesh.quads[j as usize].map(|u| if u == w { v } else { u }))
            .collect();
        let v_quads: Vec<[u32; 4]> = self.inc[v as usize]
            .iter()
            .filter(|&&j| j != k)
            .map(|&j| self.mesh.quads[j as usize])
            .collect();
        let after = || renamed.iter().chain(&v_quads);
        let spots: &[Point] = if self.interior(v) {
            &[0.5 * (pv + pw), pv, pw]
        } else {
            &[pv]
        };
        let placed = match sliver {
            None => spots.iter().any(|&p| {
                self.mesh.nodes[v as usize] = p;
                after().all(|r| self.convex(r))
            }),
            Some(bound) => {
                let others_now: Vec<[u32; 4]> = others
                    .iter()
                    .map(|&j| self.mesh.quads[j as usize])
                    .collect();
                let all = std::iter::once(&q).chain(&others_now).chain(&v_quads);
                let (min, count) = self.slivers(all, bound);
                self.mesh.nodes[v as usize] = spots[0];
                if self.interior(v) {
                    let quads: Vec<[u32; 4]> = after().copied().collect();
                    let nbs: Vec<u32> = quads
                        .iter()
                        .flatten()
                        .copied()
                        .filter(|&u| u != v)
                        .collect();
                    let quality = |m: &QuadMesh| {
                        Some(quads.iter().fold((f64::INFINITY, 0.0), |(lo, sum), r| {
                            let sj = Shape::of(m.corners(r)).scaled_jacobian;
                            (lo.min(sj), sum + sj)
                        }))
                    };
                    let start = quality(self.mesh).unwrap_or_default();
                    pattern_search(self.mesh, v as usize, &nbs, start, |m, _| quality(m));
                }
                let (new_min, new_count) = self.slivers(after(), bound);
                after().all(|r| is_measurably_convex(self.mesh.corners(r)))
                    && new_count < count
                    && new_min >= min
            }
        };
        if !placed {
            self.mesh.nodes[v as usize] = pv;
            return false;
        }
        self.remove_quad(k);
        for (&j, &r) in others.iter().zip(&renamed) {
            self.set_quad(j, r);
        }
        for j in self.inc[v as usize].clone() {
            self.touch(j);
        }
        true
    }

    /// Swaps the edge from `u` to `w` (interior: two quads share it) when
    /// another split of their hexagon is better.
    fn swap(&mut self, u: u32, w: u32, min_quality: f64) -> bool {
        let mut a = None;
        let mut b = None;
        for &k in &self.inc[u as usize] {
            let q = self.mesh.quads[k as usize];
            for i in 0..4 {
                if q[i] == u && q[(i + 1) % 4] == w {
                    a = Some((k, [q[i], q[(i + 1) % 4], q[(i + 2) % 4], q[(i + 3) % 4]]));
                }
                if q[i] == w && q[(i + 1) % 4] == u {
                    b = Some((k, [q[i], q[(i + 1) % 4], q[(i + 2) % 4], q[(i + 3) % 4]]));
                }
            }
        }
        let (Some((ka, qa)), Some((kb, qb))) = (a, b) else {
            return false;
        };
        // The hexagon around both quads, counter-clockwise from w.
        let h = [qa[1], qa[2], qa[3], qa[0], qb[2], qb[3]];
        if (0..6).any(|i| h[i + 1..].contains(&h[i])) {
            return false;
        }
        // No split lowers a deviation sum that is already zero.
        let old_cost: i32 = h.iter().map(|&v| self.dev(v, self.valence(v))).sum();
        if old_cost == 0 {
            return false;
        }
        // A hexagon node's valence with `quads` in place of the two.
        let count = |v: u32, quads: &[[u32; 4]]| -> i32 {
            let with = |qs: &[[u32; 4]]| qs.iter().filter(|q| q.contains(&v)).count() as i32;
            self.valence(v) - with(&[qa, qb]) + with(quads)
        };
        let cost =
            |quads: &[[u32; 4]]| -> i32 { h.iter().map(|&v| self.dev(v, count(v, quads))).sum() };
        let old_min = self.sj(&qa).min(self.sj(&qb));
        let mut best: Option<(i32, f64, [[u32; 4]; 2])> = None;
        for s in [1, 2] {
            let pair = [
                [h[s], h[s + 1], h[s + 2], h[(s + 3) % 6]],
                [h[(s + 3) % 6], h[(s + 4) % 6], h[(s + 5) % 6], h[s]],
            ];
            if pair.iter().any(|q| count(q[0], &pair) < 1) {
                continue;
            }
            let c = cost(&pair);
            if c >= old_cost || !pair.iter().all(|q| self.convex(q)) {
                continue;
            }
            let m = self.sj(&pair[0]).min(self.sj(&pair[1]));
            if m < min_quality.min(old_min) {
                continue;
            }
            if best
                .as_ref()
                .is_none_or(|(bc, bm, _)| c < *bc || (c == *bc && m > *bm))
            {
                best = Some((c, m, pair));
            }
        }
        let Some((_, _, [p, q])) = best else {
            return false;
        };
        self.set_quad(ka, p);
        self.set_quad(kb, q);
        true
    }
}

/// The ideal valence of every node: 4 inside; on the boundary the interior
/// angle in right angles, at least 1.
pub(crate) fn ideal_valences(mesh: &QuadMesh) -> Vec<i32> {
    let mut ideal = vec![4; mesh.nodes.len()];
    for l in &mesh.loops {
        let n = l.len();
        for k in 0..n {
            let (prev, v, next) = (l[(k + n - 1) % n], l[k], l[(k + 1) % n]);
            let p = |i: u32| -> Point { mesh.nodes[i as usize] };
            let angle = ccw_angle(p(v), p(next), p(prev));
            ideal[v as usize] = ((angle / std::f64::consts::FRAC_PI_2).round() as i32).max(1);
        }
    }
    ideal
}

/// Cleans up a complete mesh in place (see the module documentation) and
/// drops the nodes it removed.
pub fn cleanup(mesh: &mut QuadMesh, params: &CleanupParams) -> CleanupReport {
    cleanup_marking(mesh, params, false, None).report
}

/// Where a cleanup after an earlier one must look: the quads the earlier
/// one left to try again (it ran out of passes) and those around the nodes
/// moved since. Elsewhere every operation was tried and refused, and would
/// be again.
struct Since {
    /// Per quad.
    pending: Vec<bool>,
    /// Per node.
    moved: Vec<bool>,
}

/// What [`cleanup_marking`] did: its report, and per quad of the result,
/// whether it made or moved it and whether an operation on it is left to
/// try again.
struct Marked {
    report: CleanupReport,
    changed: Vec<bool>,
    pending: Vec<bool>,
}

/// [`cleanup`], also returning which quads of the result it made or moved.
/// A pass tries an operation on a quad again only when something it looks
/// at changed since it was last tried ([`Work::touch`]), unless `retry_all`;
/// with `since`, the first pass tries only what [`Since`] says. The result
/// is the same either way.
fn cleanup_marking(
    mesh: &mut QuadMesh,
    params: &CleanupParams,
    retry_all: bool,
    since: Option<&Since>,
) -> Marked {
    let mut report = CleanupReport::default();
    if params.passes == 0 || mesh.quads.is_empty() {
        return Marked {
            report,
            changed: vec![false; mesh.quads.len()],
            pending: vec![false; mesh.quads.len()],
        };
    }
    let nb = mesh.n_boundary();
    let alive = vec![true; mesh.quads.len()];
    let changed = vec![false; mesh.quads.len()];
    let inc = mesh.node_quads();
    let ideal = ideal_valences(mesh);
    let n_quads = mesh.quads.len();
    let mut w = Work {
        mesh,
        nb,
        alive,
        changed,
        inc,
        ideal,
        clock: 1,
        stamp: vec![u32::from(since.is_none()); n_quads],
    };
    if let Some(since) = since {
        for (k, _) in since.pending.iter().enumerate().filter(|(_, &p)| p) {
            w.stamp[k] = 1;
        }
        // Quads with a corner that shares a quad with a moved node (what
        // [`Work::stamp_around`] marks, in three passes over the quads).
        let mut near = vec![false; w.mesh.nodes.len()];
        for q in &w.mesh.quads {
            if q.iter()
                .any(|&v| since.moved.get(v as usize) == Some(&true))
            {
                for &v in q {
                    near[v as usize] = true;
                }
            }
        }
        for (k, q) in w.mesh.quads.iter().enumerate() {
            if q.iter().any(|&v| near[v as usize]) {
                w.stamp[k] = 1;
            }
        }
    }
    // Per operation and quad, the tick it was last tried at: a quad whose
    // surroundings have not changed since is not tried again.
    let mut seen = vec![[0u32; 3]; w.mesh.quads.len()];
    let mut due = |w: &Work, k: u32, op: usize| -> bool {
        let ok = w.alive[k as usize] && (retry_all || w.stamp[k as usize] > seen[k as usize][op]);
        if ok {
            seen[k as usize][op] = w.clock;
        }
        ok
    };
    for _ in 0..params.passes {
        let before = report.total();
        for k in 0..w.mesh.quads.len() as u32 {
            if due(&w, k, 0) && w.collapse_sliver(k, params.sliver_sj) {
                report.slivers += 1;
            }
        }
        for k in 0..w.mesh.quads.len() as u32 {
            if due(&w, k, 1) && w.collapse(k) {
                report.collapses += 1;
            }
        }
        for k in 0..w.mesh.quads.len() as u32 {
            if !due(&w, k, 2) {
                continue;
            }
            for i in 0..4 {
                let q = w.mesh.quads[k as usize];
                if !w.alive[k as usize] {
                    break;
                }
                let (u, v) = (q[i], q[(i + 1) % 4]);
                if u < v && w.swap(u, v, params.min_swap_quality) {
                    report.swaps += 1;
                }
            }
        }
        if report.total() == before {
            break;
        }
    }
    let Work {
        mesh,
        alive,
        changed,
        stamp,
        ..
    } = w;
    let former = mesh.retain_quads(&alive);
    Marked {
        report,
        changed: former.iter().map(|&k| changed[k as usize]).collect(),
        pending: former
            .iter()
            .map(|&k| seen[k as usize].iter().any(|&t| stamp[k as usize] > t))
            .collect(),
    }
}

/// [`improve`] stops after a round whose cleanup made less than
/// 1/`LAST_ROUND_SHARE` of the first round's changes: the last few changes
/// do not pay for another round (on a mesh of up to [`crate::smooth::LOCAL_ABOVE`] quads,
/// another smoothing of the whole). A first round of fewer changes than
/// this goes on while any round changes something.
const LAST_ROUND_SHARE: usize = 20;

/// Mesh improvement after extraction: smoothing ([`smooth`] then
/// [`optimize`]), preceded on a `complete` mesh by [`cleanup`] and repeated
/// while the cleanup finds changes, up to `cleanup.rounds` rounds; after the
/// first round, on a large mesh, only near the changes ([`after_change`]:
/// the rest was smoothed in the first round and has not changed since). Returns the
/// cleanup's changes over all rounds.
pub fn improve(
    mesh: &mut QuadMesh,
    complete: bool,
    cleanup_params: &CleanupParams,
    smooth_params: &SmoothParams,
) -> CleanupReport {
    let mut total = CleanupReport::default();
    let mut first = 0;
    let mut since: Option<Since> = None;
    for round in 0..cleanup_params.rounds.max(1) {
        let (changes, changed, pending) = if complete && round < cleanup_params.rounds {
            let m = cleanup_marking(mesh, cleanup_params, false, since.as_ref());
            total.slivers += m.report.slivers;
            total.collapses += m.report.collapses;
            total.swaps += m.report.swaps;
            (m.report.total(), m.changed, m.pending)
        } else {
            (0, Vec::new(), Vec::new())
        };
        if round == 0 {
            first = changes;
        } else if changes == 0 {
            break;
        }
        let only = if round > 0 {
            after_change(mesh, &changed)
        } else {
            None
        };
        let before = mesh.nodes.clone();
        smooth_and_optimize(mesh, smooth_params, only.as_deref());
        since = Some(Since {
            pending,
            moved: before
                .iter()
                .zip(&mesh.nodes)
                .map(|(a, b)| a != b)
                .collect(),
        });
        if changes * LAST_ROUND_SHARE < first {
            break;
        }
    }
    total
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::smooth::smooth_only;

    /// An n × n grid of unit squares as raw points and quads; node (i, j)
    /// is `j * (n + 1) + i`.
    pub(crate) fn grid(n: usize) -> (Vec<Point>, Vec<[u32; 4]>) {
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut pts = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                pts.push(Point::new(i as f64, j as f64));
            }
        }
        let mut quads = Vec::new();
        for j in 0..n {
            for i in 0..n {
                quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (pts, quads)
    }

    fn mesh(pts: Vec<Point>, quads: Vec<[u32; 4]>) -> QuadMesh {
        let m = QuadMesh::from_quads(pts, quads).unwrap();
        m.check_invariants(true).unwrap();
        m
    }

    /// A mesh by extraction without cleanup, with work for one: a disk of
    /// 56 segments around an off-centre square hole.
    fn uncleaned() -> QuadMesh {
        use crate::extract::{MeshParams, Mesher};
        use crate::model::RulesModel;
        let mut pts: Vec<Point> = (0..56)
            .map(|i| {
                let t = i as f64 / 56.0 * std::f64::consts::TAU;
                Point::new(10.0 * t.cos(), 10.0 * t.sin())
            })
            .collect();
        pts.extend(
            [(2.0, -1.0), (2.0, 3.0), (6.0, 3.0), (6.0, -1.0)].map(|(x, y)| Point::new(x, y)),
        );
        let loops = vec![(0..56).collect(), (56..60).collect()];
        let b = crate::Boundary::new(pts, loops, None).unwrap();
        let finish = crate::finish::FinishParams {
            cleanup: CleanupParams::OFF,
            remesh: crate::finish::remesh::RemeshParams::OFF,
            ..crate::finish::FinishParams::DEFAULT
        };
        // Two layers and the region fill: a mesh with work for cleanup.
        let params = MeshParams {
            fill_after_layers: Some(2),
            ..MeshParams::DEFAULT
        };
        let mut m = Mesher::new(b, std::sync::Arc::new(RulesModel::DEFAULT), params);
        m.run(|_| {}).unwrap();
        crate::finish::finish(&m, &finish).unwrap()
    }

    #[test]
    fn skipping_unchanged_quads_changes_nothing() {
        let start = uncleaned();
        let (mut a, mut b) = (start.clone(), start.clone());
        let ma = cleanup_marking(&mut a, &CleanupParams::DEFAULT, false, None);
        let mb = cleanup_marking(&mut b, &CleanupParams::DEFAULT, true, None);
        assert!(
            ma.report.total() > 0,
            "the test mesh needs cleanup: {:?}",
            ma.report
        );
        assert_eq!(ma.report, mb.report);
        assert_eq!(ma.changed, mb.changed);
        let ca = ma.changed;
        assert_eq!((&a.nodes, &a.quads), (&b.nodes, &b.quads));
        a.check_invariants(true).unwrap();
        // Every quad not marked changed was in the mesh before, corner for
        // corner (node ids are renumbered by the cleanup, positions are not).
        let key = |m: &QuadMesh, q: &[u32; 4]| m.corners(q).map(|p| (p.x.to_bits(), p.y.to_bits()));
        let old: std::collections::BTreeSet<_> =
            start.quads.iter().map(|q| key(&start, q)).collect();
        assert!(a
            .quads
            .iter()
            .zip(&ca)
            .any(|(q, &c)| c && !old.contains(&key(&a, q))));
        assert!(a
            .quads
            .iter()
            .zip(&ca)
            .all(|(q, &c)| c || old.contains(&key(&a, q))));
    }

    #[test]
    fn a_later_cleanup_looking_only_where_needed_changes_nothing() {
        // One pass leaves work pending; smoothing then moves nodes.
        let one_pass = CleanupParams {
            passes: 1,
            ..CleanupParams::DEFAULT
        };
        let mut m = uncleaned();
        let first = cleanup_marking(&mut m, &one_pass, false, None);
        assert!(
            first.pending.iter().any(|&p| p),
            "the first cleanup leaves work"
        );
        let before = m.nodes.clone();
        smooth_only(&mut m, &SmoothParams::DEFAULT, None);
        let since = Since {
            pending: first.pending,
            moved: before.iter().zip(&m.nodes).map(|(a, b)| a != b).collect(),
        };
        assert!(since.moved.iter().any(|&x| x) && !since.moved.iter().all(|&x| x));
        let (mut a, mut b) = (m.clone(), m);
        let ma = cleanup_marking(&mut a, &CleanupParams::DEFAULT, false, Some(&since));
        let mb = cleanup_marking(&mut b, &CleanupParams::DEFAULT, true, None);
        assert!(ma.report.total() > 0);
        assert_eq!((ma.report, ma.changed), (mb.report, mb.changed));
        assert_eq!((&a.nodes, &a.quads), (&b.nodes, &b.quads));
    }

    fn interior_valences(m: &QuadMesh) -> Vec<usize> {
        let inc = m.node_quads();
        (m.n_boundary()..m.nodes.len())
            .map(|v| inc[v].len())
            .collect()
    }

    #[test]
    fn a_regular_grid_is_left_alone() {
        let (p, q) = grid(4);
        let mut m = mesh(p, q);
        let before = m.clone();
        assert_eq!(cleanup(&mut m, &CleanupParams::DEFAULT).total(), 0);
        assert_eq!(m, before);
    }

    #[test]
    fn collapses_a_quad_between_two_valence_three_nodes() {
        // A 4 × 4 grid whose centre node (2, 2) is opened into a diamond
        // c–s–e–t: its left and right corners c and e have valence 3, and
        // the diamond collapses back into one node of valence 4.
        let (mut p, mut q) = grid(4);
        let (c, s, t) = (12u32, 7u32, 17u32);
        p[c as usize] = Point::new(1.8, 2.0);
        p.push(Point::new(2.2, 2.0));
        let e = (p.len() - 1) as u32;
        for quad in &mut q {
            if *quad == [7, 8, 13, 12] {
                *quad = [7, 8, 13, e];
            }
            if *quad == [12, 13, 18, 17] {
                *quad = [e, 13, 18, 17];
            }
        }
        q.push([c, s, e, t]);
        let mut m = mesh(p, q);
        let r = cleanup(&mut m, &CleanupParams::DEFAULT);
        assert_eq!(r.collapses, 1, "{r:?}");
        m.check_invariants(true).unwrap();
        assert_eq!(m.quads.len(), 16);
        assert!(interior_valences(&m).iter().all(|&v| v == 4));
    }

    #[test]
    fn collapses_a_sliver() {
        // The centre quad (5, 6, 10, 9) of a 3 × 3 grid flattened into a
        // needle: its corners 5 and 10 nearly meet. The cleanup merges them.
        let (mut p, q) = grid(3);
        p[5] = Point::new(1.48, 1.48);
        p[10] = Point::new(1.52, 1.52);
        let mut m = mesh(p, q);
        let worst = QuadMesh::worst_scaled_jacobian;
        assert!(worst(&m) < 0.1);
        let r = cleanup(&mut m, &CleanupParams::DEFAULT);
        assert_eq!(r.slivers, 1, "{r:?}");
        m.check_invariants(true).unwrap();
        assert_eq!(m.quads.len(), 8);
        assert!(worst(&m) > 0.2, "{}", worst(&m));
        let off = CleanupParams {
            sliver_sj: 0.0,
            ..CleanupParams::DEFAULT
        };
        let (mut p, q) = grid(3);
        p[5] = Point::new(1.48, 1.48);
        p[10] = Point::new(1.52, 1.52);
        let mut m = mesh(p, q);
        assert_eq!(cleanup(&mut m, &off).slivers, 0);
    }

    #[test]
    fn swaps_an_edge_back_to_regular_valences() {
        // Quads (5, 6, 11, 10) and (6, 7, 12, 11) of a 4 × 4 grid re-split
        // along 5–12: nodes 6 and 11 drop to valence 3, 12 rises to 5. The
        // cleanup swaps back.
        let (mut p, mut q) = grid(4);
        p[6] = Point::new(1.0, 0.8);
        p[11] = Point::new(1.0, 2.2);
        let a = q.iter().position(|x| *x == [5, 6, 11, 10]).unwrap();
        let b = q.iter().position(|x| *x == [6, 7, 12, 11]).unwrap();
        q[a] = [5, 6, 7, 12];
        q[b] = [12, 11, 10, 5];
        let mut m = mesh(p, q);
        assert!(interior_valences(&m).iter().any(|&v| v != 4));
        let r = cleanup(&mut m, &CleanupParams::DEFAULT);
        assert_eq!(r.swaps, 1, "{r:?}");
        m.check_invariants(true).unwrap();
        assert_eq!(m.quads.len(), 16);
        assert!(interior_valences(&m).iter().all(|&v| v == 4));
    }
}

//! Steps that reshape the front when no element can be cut: seams at sharp
//! corners (paving's seam), a square cut to start a row, chord splits of a
//! loop into two even loops (the extension of TP, thesis §1.3.2),
//! relaxation of a stuck loop and rip-up of the elements around it.

use super::guard::{self, Corner, Limits, MAX_SIDE_RATIO};
use super::report::{StepKind, StepReport};
use super::session::Mesher;
use crate::front::{Front, FrontLoop, SlotId};
use crate::geom::{ccw_angle, Point};
use std::f64::consts::PI;

/// Where [`Mesher::square_cut`] looks for the shortest front edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Squares {
    /// On one loop of at least 16 nodes.
    Loop(u32),
    /// On any loop of at least 16 nodes.
    Any,
    /// On holes of the boundary of fewer than 16 nodes that no row has
    /// reached yet (a triangular hole far from everything has no reference
    /// point, and no other front reaches it).
    SmallHoles,
}

/// A region of the mesh being removed ([`Mesher::remove_around`]).
struct Removal {
    /// Per quad, whether it goes.
    removed: Vec<bool>,
    /// Per node, whether it is on the loops the removal started from or a
    /// corner of a quad that goes.
    mark: Vec<bool>,
    /// The nodes `mark` marks, in the order marked.
    marked: Vec<u32>,
    /// The region's boundary: the directed edges of the loops and of the
    /// quads that go, a pair met both ways cancelling.
    edges: std::collections::BTreeSet<(u32, u32)>,
}

/// Adds the directed edge `(a, b)` to a region's boundary `edges`, or
/// takes `(b, a)` off it where the region already had that edge the other
/// way (the two sides of an edge inside the region cancel).
fn toggle_edge(edges: &mut std::collections::BTreeSet<(u32, u32)>, (a, b): (u32, u32)) {
    if !edges.remove(&(b, a)) {
        edges.insert((a, b));
    }
}

/// [`Mesher::chord_split`]'s state: per loop, the [`FrontLoop::version`]
/// and head at which none of its nodes could be a chord's end, every chord
/// splitting a corner too unevenly
/// ([`RepairTuning::chord_min_part`](super::tuning::RepairTuning::chord_min_part));
/// version 0: never. That test reads the loop's own nodes alone (which
/// slots are paired follows from its length and head), so while the loop
/// keeps its version and head no chord is found on it.
#[derive(Clone, Debug, Default)]
pub(super) struct ChordsSeen {
    cornerless: Vec<(u32, SlotId)>,
}

impl ChordsSeen {
    fn cornerless(&self, lid: u32, l: FrontLoop) -> bool {
        self.cornerless.get(lid as usize) == Some(&(l.version, l.head))
    }

    fn remember_cornerless(&mut self, lid: u32, l: FrontLoop) {
        let k = lid as usize;
        if self.cornerless.len() <= k {
            self.cornerless.resize(k + 1, (0, 0));
        }
        self.cornerless[k] = (l.version, l.head);
    }
}

impl Mesher {
    /// Removes every quad within `rings` element rings of loop `lid`
    /// ([`Mesher::remove_around`]) and splits the enlarged loop.
    pub(super) fn rip_up(&mut self, lid: u32, rings: usize) -> StepReport {
        let mut r = self.report(StepKind::RipUp);
        r.reference = Some(self.front.node(self.front.loops[lid as usize].head));
        let mark;
        (r.removed, mark) = self.remove_around(&[lid], rings, false);
        // The enlarged loop is split next: a chord across the wider region.
        let target = self.front.live_loops().max_by_key(|&l| {
            self.front
                .loop_slots(l)
                .iter()
                .filter(|&&s| mark[self.front.node(s) as usize])
                .count()
        });
        if let Some(t) = target {
            if let Some(split) = self.chord_split(t) {
                r.quads = split.quads;
                r.new_nodes = split.new_nodes;
            }
        }
        let live: Vec<u32> = self.front.live_loops().collect();
        self.rows.check_loops(live);
        r
    }

    /// Removes every quad within `rings` element rings of the loops `lids`
    /// and replaces the loops the removal reached by the loops around the
    /// enlarged holes in the mesh ([`Mesher::replace_loops`]; each new loop
    /// waits for a row start): the quads removed, and a mark on every node
    /// of the removed quads and of the loops.
    pub(super) fn remove_around(
        &mut self,
        lids: &[u32],
        rings: usize,
        tidy: bool,
    ) -> (usize, Vec<bool>) {
        let mut mark = vec![false; self.mesh.nodes.len()];
        // The marked nodes, listed too (the mesh may be millions of nodes).
        let mut marked: Vec<u32> = Vec::new();
        for &lid in lids {
            for s in self.front.loop_slots(lid) {
                let v = self.front.node(s);
                if !mark[v as usize] {
                    mark[v as usize] = true;
                    marked.push(v);
                }
            }
        }
        // The region left grows by the quads removed: its bounding edges are
        // the front's edges and the removed quads' edges, a pair met in
        // both directions cancelling (only the front and the removed quads
        // are looked at, not the whole mesh).
        // A chord that split a loop (an edge in both directions, no quad on
        // either side) goes too: the loops it parted become one again.
        let mut edges: std::collections::BTreeSet<(u32, u32)> = Default::default();
        for l in self.front.live_loops() {
            for s in self.front.loop_slots(l) {
                toggle_edge(
                    &mut edges,
                    (self.front.node(s), self.front.node(self.front.next(s))),
                );
            }
        }
        let mut region = Removal {
            removed: vec![false; self.mesh.quads.len()],
            mark,
            marked,
            edges,
        };
        for _ in 0..rings {
            let ring = region.marked.clone();
            self.take_quads_at(&ring, &mut region);
        }
        if tidy {
            self.tidy_removal(&mut region);
        }
        let Removal {
            removed,
            mark,
            marked,
            edges,
        } = region;
        let count = self.remove_quads(&removed);
        let loops = Front::link_loops(edges.into_iter().collect(), &self.mesh.nodes);
        // The memory forgets what the region read, where the quads went
        // and the loops they bordered ran.
        self.memo.widen_changed(crate::geom::Aabb::of(
            marked.iter().map(|&v| self.mesh.nodes[v as usize]),
        ));
        for lid in self.replace_loops(&loops, &mark) {
            // The new loops' slots are reference points to look at, and
            // each loop is checked for a first row.
            for s in self.front.loop_slots(lid) {
                self.push(s);
            }
            self.rows.check_loop(lid);
        }
        // Loop ids are never taken again, so what the band, grid and chord
        // rungs remember per loop (by id and version) still holds.
        // A corner or a short edge of the given boundary the removal put
        // back on the front is looked at for its fan or notch again.
        self.fans = super::fan::Fans::of(self);
        let notches = self.notches.listed(self);
        self.notches.look_again(notches);
        (count, mark)
    }

    /// Makes the front's loops `loops` (node sequences, as
    /// [`Front::link_loops`] gives them): a live loop with no node `mark`
    /// marks that is among them stays as it is, with its slots, their
    /// layers and queue entries; the other live loops go, and the loops
    /// left are added (their slots on layer 0). Returns the ids of the
    /// loops added, in the order of `loops`. The work is along the loops,
    /// not a new front: a rip-up among a thousand holes leaves the others'
    /// rows where they were.
    fn replace_loops(&mut self, loops: &[Vec<u32>], mark: &[bool]) -> Vec<u32> {
        let mut stays: std::collections::HashMap<Vec<u32>, u32> = Default::default();
        let mut going: Vec<u32> = Vec::new();
        for lid in self.front.live_loops() {
            let nodes = self.front.loop_nodes(lid);
            if nodes.iter().any(|&v| mark[v as usize]) {
                going.push(lid);
            } else {
                stays.insert(cyclic_key(&nodes), lid);
            }
        }
        let mut added = Vec::new();
        let mut new_loops: Vec<&Vec<u32>> = Vec::new();
        for l in loops {
            if stays.remove(&cyclic_key(l)).is_none() {
                new_loops.push(l);
            }
        }
        // Loops not found again (a cancelled chord joined them to one
        // the region reached) go too.
        going.extend(stays.into_values());
        going.sort_unstable();
        for lid in going {
            self.front.remove_loop(lid);
        }
        for l in new_loops {
            added.push(self.front.add_loop(l, &self.mesh.nodes));
        }
        added
    }

    /// Adds to `region` every quad at one of `nodes` it does not hold yet
    /// (in id order): marks their corners and toggles their edges on the
    /// region's boundary. Returns how many it added.
    fn take_quads_at(&self, nodes: &[u32], region: &mut Removal) -> usize {
        let mut hit: Vec<usize> = nodes
            .iter()
            .flat_map(|&v| self.incident[v as usize].iter().map(|&q| q as usize))
            .filter(|&q| !region.removed[q])
            .collect();
        hit.sort_unstable();
        hit.dedup();
        for &k in &hit {
            region.removed[k] = true;
            let q = self.mesh.quads[k];
            for j in 0..4 {
                let (a, b) = (q[j], q[(j + 1) % 4]);
                if !region.mark[a as usize] {
                    region.mark[a as usize] = true;
                    region.marked.push(a);
                }
                toggle_edge(&mut region.edges, (a, b));
            }
        }
        hit.len()
    }

    /// Grows a removal until the region's boundary is one a fill can take:
    /// no node the boundary passes twice (two removed quads meeting at a
    /// corner only) and no boundary edge under [`RepairTuning::tidy_edge`](super::tuning::RepairTuning::tidy_edge) of the size
    /// there (the knots of tiny quads where rows met) and no slit
    /// ([`RepairTuning::tidy_angle`](super::tuning::RepairTuning::tidy_angle)). All quads at such a node go, for at most
    /// [`RepairTuning::tidy_rounds`](super::tuning::RepairTuning::tidy_rounds) rounds.
    fn tidy_removal(&self, region: &mut Removal) {
        let nodes = &self.mesh.nodes;
        for _ in 0..self.params.tuning.repair.tidy_rounds {
            let edges = &region.edges;
            let mut seen: std::collections::BTreeMap<u32, usize> = Default::default();
            let mut bad: Vec<u32> = Vec::new();
            for &(a, b) in edges.iter() {
                *seen.entry(a).or_default() += 1;
                let (pa, pb) = (nodes[a as usize], nodes[b as usize]);
                if pa.distance(pb)
                    < self.params.tuning.repair.tidy_edge * self.size.at(0.5 * (pa + pb))
                {
                    bad.extend([a, b]);
                }
            }
            bad.extend(seen.iter().filter(|(_, &c)| c > 1).map(|(&v, _)| v));
            // Slits: a corner so sharp or so reflex that the boundary
            // nearly runs back on itself (a sliver quad outside it).
            let mut next: std::collections::BTreeMap<u32, u32> = Default::default();
            let mut prev: std::collections::BTreeMap<u32, u32> = Default::default();
            for &(a, b) in edges.iter() {
                next.insert(a, b);
                prev.insert(b, a);
            }
            for (&v, &w) in &next {
                if let Some(&u) = prev.get(&v) {
                    let p = nodes[v as usize];
                    let angle = crate::geom::ccw_angle(p, nodes[w as usize], nodes[u as usize]);
                    if !(self.params.tuning.repair.tidy_angle
                        ..=2.0 * PI - self.params.tuning.repair.tidy_angle)
                        .contains(&angle)
                    {
                        bad.push(v);
                    }
                }
            }
            bad.sort_unstable();
            bad.dedup();
            if self.take_quads_at(&bad, region) == 0 {
                return;
            }
        }
    }

    /// Seam at sharp slot `s`: merges P_l1 and P_r1 (at their midpoint, or
    /// onto the one on the boundary) so the sharp corner closes. Kept only
    /// if every quad around the merged node stays strictly convex with a
    /// scaled Jacobian of at least 0.2, the new front edges cross nothing,
    /// the region the front gives up holds no front node, and the loop left
    /// runs the way it ran.
    pub(super) fn try_seam(&mut self, s: SlotId) -> Option<StepReport> {
        let f = &self.front;
        if f.loop_len(s) < 6 {
            return None;
        }
        let (l, r) = (f.prev(s), f.next(s));
        let (l2, r2) = (f.prev(l), f.next(r));
        let (nl, nr) = (f.node(l), f.node(r));
        if nl == nr || f.node(l2) == nr || f.node(r2) == nl {
            return None;
        }
        let nb = self.boundary_nodes as u32;
        let (pl, pr) = (self.mesh.nodes[nl as usize], self.mesh.nodes[nr as usize]);
        let (keep, gone, pos) = match (nl < nb, nr < nb) {
            (true, true) => return None,
            (true, false) => (nl, nr, pl),
            (false, true) => (nr, nl, pr),
            (false, false) => (nl, nr, pl.lerp(pr, 0.5)),
        };
        // Both nodes must stand on the front only here.
        let probe = Point::splat(1e-12 * (1.0 + pos.abs().max_element()));
        for (v, pv) in [(nl, pl), (nr, pr)] {
            self.front
                .edges_near(pv - probe, pv + probe, &mut self.scratch.near);
            if self
                .scratch
                .near
                .iter()
                .any(|&e| self.front.node(e) == v && e != l && e != r)
            {
                return None;
            }
        }
        let sub = |v: u32| if v == gone { keep } else { v };
        let mut quads: Vec<u32> = self.incident[nl as usize].clone();
        quads.extend_from_slice(&self.incident[nr as usize]);
        let at = |v: u32| {
            if v == keep || v == gone {
                pos
            } else {
                self.mesh.nodes[v as usize]
            }
        };
        for &k in &quads {
            let q = self.mesh.quads[k as usize].map(sub);
            let p = q.map(at);
            if !crate::geom::is_strictly_convex(p) {
                return None;
            }
            if crate::quality::Shape::of(p).scaled_jacobian < self.params.tuning.repair.relax_sj {
                return None;
            }
        }
        // New front edges l2 → X → r2 and the moved mesh edges at X.
        let mut ends: Vec<u32> = vec![self.front.node(l2), self.front.node(r2)];
        for &k in &quads {
            let q = self.mesh.quads[k as usize].map(sub);
            for i in 0..4 {
                if q[i] == keep {
                    ends.push(q[(i + 1) % 4]);
                    ends.push(q[(i + 3) % 4]);
                }
            }
        }
        ends.sort_unstable();
        ends.dedup();
        let tip = self.front.node(s);
        for &w in &ends {
            let pw = self.mesh.nodes[w as usize];
            if self.crosses_front(pos, pw, &[w, nl, nr, tip]) {
                return None;
            }
        }
        // And the region the front gives up (the corner, and what the edges
        // beside it sweep as their ends move to the merged node) must hold
        // no front: an island's loop there would be left outside the front
        // around it.
        let (nl2, nr2) = (self.front.node(l2), self.front.node(r2));
        let cut = [self.world(l2), pl, self.world(s), pr, self.world(r2), pos];
        let bb = crate::geom::Aabb::of(cut)?;
        self.front
            .edges_near(bb.min, bb.max, &mut self.scratch.near);
        if self.scratch.near.iter().any(|&e| {
            let v = self.front.node(e);
            ![nl2, nl, tip, nr, nr2].contains(&v)
                && crate::geom::point_in_polygon(self.mesh.nodes[v as usize], &cut)
        }) {
            return None;
        }
        // The loop left must run the way it ran: a short loop can turn
        // inside out with no edge crossing (its last nodes on the wrong
        // side of the merged one).
        let slots = self.front.loop_slots(self.front.slot(s).loop_id);
        let before = crate::geom::polygon_area(slots.iter().map(|&t| self.world(t)));
        let after =
            crate::geom::polygon_area(slots.iter().filter(|&&t| t != s && t != r).map(|&t| {
                if t == l {
                    pos
                } else {
                    self.world(t)
                }
            }));
        if before * after <= 0.0 {
            return None;
        }
        let mut rep = self.report(StepKind::Seam);
        rep.reference = Some(self.front.node(s));
        self.memo.widen_changed(crate::geom::Aabb::of(
            cut.into_iter()
                .chain(ends.iter().map(|&w| self.mesh.nodes[w as usize])),
        ));
        self.front.remove_pair(s, &self.mesh.nodes);
        self.front.unfile_edges_at(l);
        self.mesh.nodes[keep as usize] = pos;
        self.front.refile_edges_at(l, keep, &self.mesh.nodes);
        let moved = std::mem::take(&mut self.incident[gone as usize]);
        for &k in &moved {
            let q = &mut self.mesh.quads[k as usize];
            *q = q.map(sub);
        }
        self.incident[keep as usize].extend(moved);
        for t in [l, l2, r2] {
            self.push(t);
        }
        Some(rep)
    }

    /// Moves each interior (non-boundary) node of loop `lid` half-way to
    /// the midpoint of its front neighbours when every quad around it stays
    /// strictly convex with a scaled Jacobian of at least
    /// `min(former, 0.3)`, and neither its front edges nor its path there
    /// cross the front.
    pub(super) fn relax_loop(&mut self, lid: u32) -> Option<StepReport> {
        let nb = self.boundary_nodes as u32;
        let slots = self.front.loop_slots(lid);
        let area = self.front.loop_area(lid, &self.mesh.nodes);
        let mut moved: Vec<(SlotId, u32, Point)> = Vec::new();
        for &s in &slots {
            let v = self.front.node(s);
            if v < nb || self.on_front_again(s) {
                continue;
            }
            let (pp, pn) = (
                self.world(self.front.prev(s)),
                self.world(self.front.next(s)),
            );
            let old = self.mesh.nodes[v as usize];
            let new = old.lerp(pp.lerp(pn, 0.5), 0.5);
            if (new - old).length() < 1e-9 * pp.distance(pn) {
                continue;
            }
            let quads = self.incident[v as usize].clone();
            let before: Vec<(f64, f64)> = quads
                .iter()
                .map(|&k| {
                    let s =
                        crate::quality::Shape::of(self.mesh.corners(&self.mesh.quads[k as usize]));
                    (s.scaled_jacobian, s.side_ratio())
                })
                .collect();
            self.front.unfile_edges_at(s);
            self.mesh.nodes[v as usize] = new;
            let mut ok = quads.iter().zip(&before).all(|(&k, &(sj, sides))| {
                let p = self.mesh.corners(&self.mesh.quads[k as usize]);
                let s = crate::quality::Shape::of(p);
                crate::geom::is_strictly_convex(p)
                    && s.scaled_jacobian >= sj.min(self.params.tuning.repair.tidy_sj)
                    && s.side_ratio() <= sides.max(MAX_SIDE_RATIO)
            });
            // The node may not pass over the front on its way: front
            // edges missed by its new edges but crossed by its path would
            // lie on the other side of it, the loop turned inside out
            // around them (a thin loop relaxed across its own far side).
            if ok && self.crosses_front(old, new, &[v]) {
                ok = false;
            }
            if ok {
                let prev_node = self.front.node(self.front.prev(s));
                let next_node = self.front.node(self.front.next(s));
                for w in [prev_node, next_node] {
                    let pw = self.mesh.nodes[w as usize];
                    if self.crosses_front(new, pw, &[v, w]) {
                        ok = false;
                        break;
                    }
                }
            }
            if !ok {
                self.mesh.nodes[v as usize] = old;
            } else {
                moved.push((s, v, old));
            }
            self.front.refile_edges_at(s, v, &self.mesh.nodes);
        }
        // A short loop can turn inside out with no edge crossing (each
        // move checked on its own): then every move is taken back.
        if !moved.is_empty() && area * self.front.loop_area(lid, &self.mesh.nodes) <= 0.0 {
            for &(s, v, old) in moved.iter().rev() {
                self.front.unfile_edges_at(s);
                self.mesh.nodes[v as usize] = old;
                self.front.refile_edges_at(s, v, &self.mesh.nodes);
            }
            moved.clear();
        }
        if moved.is_empty() {
            return None;
        }
        self.memo.widen_changed(crate::geom::Aabb::of(
            moved
                .iter()
                .flat_map(|&(_, v, old)| [old, self.mesh.nodes[v as usize]]),
        ));
        for &s in &slots {
            self.push(s);
        }
        let mut r = self.report(StepKind::Relax);
        r.reference = Some(self.front.node(slots[0]));
        Some(r)
    }

    /// A square element on the shortest front edge whose square fits
    /// (thesis §5.1: no front node qualifies as a reference point).
    pub(super) fn square_cut(&mut self, only: Squares, limits: Limits) -> Option<StepReport> {
        let mut edges: Vec<(f64, SlotId)> = self
            .front
            .live_loops()
            .filter(|&l| {
                // A short loop is closed rather than cut, except a small
                // hole (asked for apart, after everything else).
                let len = self.front.loops[l as usize].len;
                let min_loop = self.params.tuning.repair.square_min_loop;
                match only {
                    Squares::Loop(o) => o == l && len >= min_loop,
                    Squares::Any => len >= min_loop,
                    Squares::SmallHoles => {
                        len < min_loop
                            && self
                                .front
                                .loop_slots(l)
                                .iter()
                                .all(|&s| self.front.slot(s).layer == 0)
                            && self.is_hole_loop(l)
                    }
                }
            })
            .flat_map(|l| self.front.loop_slots(l))
            .map(|s| (self.world(s).distance(self.world(self.front.next(s))), s))
            .collect();
        edges.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        edges
            .iter()
            .take(self.params.tuning.repair.square_edges)
            .find_map(|&(_, s)| {
                let floor = if only == Squares::Any {
                    self.params.tuning.repair.square_floor
                } else {
                    0.0
                };
                self.square_on(s, limits, floor)
            })
    }

    /// True when loop `lid` runs clockwise: a hole's front, with the
    /// region outside it.
    pub(super) fn is_hole_loop(&self, lid: u32) -> bool {
        self.front.loop_area(lid, &self.mesh.nodes) < 0.0
    }

    /// A square element on the front edge from slot `s`, as high as the
    /// edge is long (or 0.7 or 0.5 of that where the full one does not fit
    /// and those sides are at least `floor` times the size there).
    pub(super) fn square_on(
        &mut self,
        s: SlotId,
        limits: Limits,
        floor: f64,
    ) -> Option<StepReport> {
        {
            let t = self.front.next(s);
            let (a, b) = (self.world(s), self.world(t));
            let len = a.distance(b);
            let up = (b - a).perp() / len;
            let least = floor * self.size.at(0.5 * (a + b));
            for height in self.params.tuning.repair.square_heights {
                if height < 1.0 && len * height < least {
                    break;
                }
                let (a2, b2) = (a + up * len * height, b + up * len * height);
                let corners = [
                    Corner::Partial(s),
                    Corner::Partial(t),
                    Corner::New(b2),
                    Corner::New(a2),
                ];
                if guard::check(
                    &self.front,
                    &self.mesh.nodes,
                    corners,
                    &[s],
                    limits,
                    self.size.at(a),
                    &mut self.scratch,
                )
                .is_some()
                {
                    let mut r = self.report(StepKind::Square);
                    let layer = self.front.slot(s).layer.max(self.front.slot(t).layer) + 1;
                    let va = self.add_node(a2);
                    let vb = self.add_node(b2);
                    let quad = [self.front.node(s), self.front.node(t), vb, va];
                    self.push_quad(quad);
                    let ids = self
                        .front
                        .insert_after(s, &[va, vb], layer, &self.mesh.nodes);
                    r.quads.push(quad);
                    r.new_nodes = vec![va, vb];
                    r.reference = Some(self.front.node(s));
                    for x in [s, ids[0], ids[1], t] {
                        self.push(x);
                    }
                    return Some(r);
                }
            }
        }
        None
    }

    /// Splits a loop along an interior chord into two even loops (the
    /// splitting-line rule of the extension of TP, thesis §1.3.2): both
    /// ends' angles split as close to 90° as possible, the chord visible
    /// and inside, with new nodes spaced like the front. A chord is not
    /// given more nodes than its loop has: where the front at its ends is
    /// far finer than its length (a sliver of microscopic elements), a split
    /// would multiply the front instead of dividing it.
    ///
    /// A loop on which no two ends' corners can be split (the test that
    /// depends on the loop alone) is remembered until it changes
    /// ([`ChordsSeen`]): a round hole's front, reflex everywhere, is
    /// otherwise searched again at every step that reaches this rung.
    pub(super) fn chord_split(&mut self, lid: u32) -> Option<StepReport> {
        let l = self.front.loops[lid as usize];
        if l.len < self.params.tuning.repair.chord_min_loop || self.chords.cornerless(lid, l) {
            return None;
        }
        let slots = self.front.loop_slots(lid);
        let n = slots.len();
        let tuning = &self.params.tuning.repair;
        let min_part = tuning.chord_min_part.to_radians();
        let [spacing_lo, spacing_hi] = tuning.chord_spacing;
        let mut best: Option<(f64, SlotId, SlotId, usize)> = None;
        let stride = (n / tuning.chord_ends).max(1);
        // Whether any live loop is odd, and each end's front angle: worked
        // out when first needed (most chords fail on their ends' angles).
        let mut any_odd: Option<bool> = None;
        let mut wedges: Vec<Option<f64>> = vec![None; n];
        let mut any_corners = false;
        for i in (0..n).step_by(stride) {
            for j in (i + 2..n).step_by(stride) {
                if i == 0 && j == n - 1 {
                    continue;
                }
                let (a, b) = (slots[i], slots[j]);
                if self.front.node(a) == self.front.node(b) {
                    continue;
                }
                let (pa, pb) = (self.world(a), self.world(b));
                let mut score = 0.0;
                let mut ok = true;
                for (end, s, other) in [(i, a, pb), (j, b, pa)] {
                    let p = self.world(s);
                    let wedge =
                        *wedges[end].get_or_insert_with(|| self.front.angle(s, &self.mesh.nodes));
                    let part1 = ccw_angle(p, self.world(self.front.next(s)), other);
                    let part2 = wedge - part1;
                    if part1 < min_part || part2 < min_part {
                        ok = false;
                        break;
                    }
                    score += (part1 - PI / 2.0).abs() + (part2 - PI / 2.0).abs();
                }
                if !ok {
                    continue;
                }
                any_corners = true;
                let len = pa.distance(pb);
                let h = 0.25
                    * (pa.distance(self.world(self.front.next(a)))
                        + pa.distance(self.world(self.front.prev(a)))
                        + pb.distance(self.world(self.front.next(b)))
                        + pb.distance(self.world(self.front.prev(b))));
                let d = j - i;
                let mut k = ((len / h).round() as usize).saturating_sub(1);
                let any_odd = *any_odd.get_or_insert_with(|| {
                    self.front
                        .live_loops()
                        .any(|l| self.front.loops[l as usize].len % 2 == 1)
                });
                let want = if any_odd {
                    self.part_parity(lid, a, b)
                } else {
                    0
                };
                if (d + 1 + k) % 2 != want {
                    k += 1;
                }
                if k == 0 && (d + 1 < 4 || n - d + 1 < 4) {
                    k = 2;
                }
                let spacing = (len / (k + 1) as f64) / h;
                if !(spacing_lo..=spacing_hi).contains(&spacing) || k > n {
                    continue;
                }
                score += 0.5 * (spacing - 1.0).abs();
                if best.is_some_and(|(bs, ..)| score >= bs) {
                    continue;
                }
                if !self.chord_clear(a, b, self.params.tuning.repair.chord_clearance * h) {
                    continue;
                }
                best = Some((score, a, b, k));
            }
        }
        if !any_corners {
            self.chords.remember_cornerless(lid, l);
        }
        let (_, a, b, k) = best?;
        let (pa, pb) = (self.world(a), self.world(b));
        let (na, nb) = (self.front.node(a), self.front.node(b));
        let layer = self.front.slot(a).layer.max(self.front.slot(b).layer) + 1;
        let mut r = self.report(StepKind::Split);
        r.reference = Some(na);
        let chord: Vec<u32> = (1..=k)
            .map(|t| self.add_node(pa.lerp(pb, t as f64 / (k + 1) as f64)))
            .collect();
        r.new_nodes = chord.clone();
        self.memo.widen_changed(crate::geom::Aabb::of([pa, pb]));
        let mut seq = chord.clone();
        seq.push(nb);
        seq.extend(chord.iter().rev());
        seq.push(na);
        let ids = self.front.insert_after(a, &seq, layer, &self.mesh.nodes);
        let b_star = ids[k];
        self.front.exchange_successors(b_star, b, &self.mesh.nodes);
        self.rows.check_loop(self.front.slot(a).loop_id);
        self.rows.check_loop(self.front.slot(b).loop_id);
        let mut touched = vec![a, b, b_star, ids[ids.len() - 1]];
        touched.extend(ids.iter().copied());
        for s in touched {
            self.push(s);
        }
        Some(r)
    }

    /// The parity a part of loop `lid` cut off along a chord must have: a
    /// region's loops together need an even number of nodes (each quad side
    /// inside is shared by two quads), so a part that takes in an odd number
    /// of odd loops (a triangular hole) must be odd itself. The part is the
    /// loop from slot `a` forward to slot `b`, closed by the chord `b`–`a`.
    /// Returns 0 or 1; 0 at once when no live loop is odd.
    pub(super) fn part_parity(&self, lid: u32, a: SlotId, b: SlotId) -> usize {
        let odd: Vec<u32> = self
            .front
            .live_loops()
            .filter(|&l| l != lid && self.front.loops[l as usize].len % 2 == 1)
            .collect();
        if odd.is_empty() {
            return 0;
        }
        let mut part = vec![self.world(a)];
        let mut s = a;
        while s != b {
            s = self.front.next(s);
            part.push(self.world(s));
        }
        odd.iter()
            .filter(|&&l| {
                let p =
                    self.mesh.nodes[self.front.node(self.front.loops[l as usize].head) as usize];
                crate::geom::point_in_polygon(p, &part)
            })
            .count()
            % 2
    }

    /// The open segment between slots `a` and `b` meets no front edge and
    /// passes no front node closer than `clearance`: a chord that grazes a
    /// node would cut off a sliver, or put a chord node on top of it.
    pub(super) fn chord_clear(&mut self, a: SlotId, b: SlotId, clearance: f64) -> bool {
        let (pa, pb) = (self.world(a), self.world(b));
        let skip = [self.front.node(a), self.front.node(b)];
        if self.crosses_front(pa, pb, &skip) {
            return false;
        }
        let pad = Point::splat(clearance);
        self.front
            .edges_near(pa.min(pb) - pad, pa.max(pb) + pad, &mut self.scratch.near);
        self.scratch.near.iter().all(|&e| {
            let v = self.front.node(e);
            skip.contains(&v)
                || crate::geom::point_segment_distance(self.mesh.nodes[v as usize], pa, pb)
                    >= clearance
        })
    }

    /// True when segment `pa–pb` meets a front edge that has none of the
    /// nodes `skip` as an end.
    /// Whether the node at slot `s` is at another front slot too (the
    /// front passes it twice): the front edges from the node's slots are
    /// the ones near it that start there.
    fn on_front_again(&mut self, s: SlotId) -> bool {
        let v = self.front.node(s);
        let p = self.mesh.nodes[v as usize];
        self.front.edges_near(p, p, &mut self.scratch.near);
        self.scratch
            .near
            .iter()
            .any(|&t| t != s && self.front.node(t) == v)
    }

    pub(super) fn crosses_front(&mut self, pa: Point, pb: Point, skip: &[u32]) -> bool {
        self.front
            .edges_near(pa.min(pb), pa.max(pb), &mut self.scratch.near);
        self.scratch.near.iter().any(|&e| {
            let (c, d) = (self.front.node(e), self.front.node(self.front.next(e)));
            !skip.contains(&c)
                && !skip.contains(&d)
                && crate::geom::segments_intersect(
                    pa,
                    pb,
                    self.mesh.nodes[c as usize],
                    self.mesh.nodes[d as usize],
                )
        })
    }
}

/// A loop's node sequence from its least rotation: two sequences are the
/// same loop exactly when their keys are equal.
fn cyclic_key(nodes: &[u32]) -> Vec<u32> {
    let n = nodes.len();
    let rotated = |i: usize| nodes[i..].iter().chain(&nodes[..i]);
    let first = (0..n)
        .min_by(|&i, &j| rotated(i).cmp(rotated(j)))
        .unwrap_or(0);
    rotated(first).copied().collect()
}

#[cfg(test)]
mod tests {
    use crate::extract::Mesher;
    use crate::geom::Point;

    /// A notch reaching down to a hair above the line from (0, 1) to
    /// (2, 1): the chord along that line crosses no edge, but passes the
    /// notch's tip too closely to be taken.
    #[test]
    fn a_chord_keeps_clear_of_front_nodes() {
        let p = |x, y| Point::new(x, y);
        let pts = vec![
            p(0., 0.),
            p(2., 0.),
            p(2., 1.),
            p(2., 2.),
            p(1.01, 2.),
            p(1., 1. + 1e-9),
            p(0.99, 2.),
            p(0., 2.),
            p(0., 1.),
            p(0., 0.5),
        ];
        let mut m = Mesher::of_loop(pts);
        let slots = m.front.loop_slots(0);
        let at = |m: &Mesher, q: Point| {
            *slots
                .iter()
                .find(|&&s| m.world(s) == q)
                .expect("a slot there")
        };
        let (a, c) = (at(&m, p(2., 1.)), at(&m, p(0., 1.)));
        assert!(m.chord_clear(a, c, 0.0));
        assert!(!m.chord_clear(a, c, 0.1));
        let d = at(&m, p(0., 0.5));
        assert!(m.chord_clear(a, d, 0.1));
    }

    /// A round hole's front is reflex at every node, so no chord can have
    /// its ends on it: the loop is searched once, remembered, and searched
    /// again only once it has changed.
    #[test]
    fn a_loop_without_chord_ends_is_searched_again_only_once_changed() {
        let p = |x, y| Point::new(x, y);
        let outer = vec![p(0., 0.), p(4., 0.), p(4., 4.), p(0., 4.)];
        let hole: Vec<Point> = (0..12)
            .map(|k| {
                let t = -(k as f64) * std::f64::consts::TAU / 12.0;
                p(2. + t.cos(), 2. + t.sin())
            })
            .collect();
        let mut m = Mesher::of_loops(vec![outer, hole]);
        let lid = m.front.slot(4).loop_id;
        let l = m.front.loops[lid as usize];
        assert_eq!(l.len, 12, "the hole's loop");
        assert!(!m.chords.cornerless(lid, l));
        assert!(m.chord_split(lid).is_none());
        assert!(m.chords.cornerless(lid, l), "remembered");
        assert!(m.chord_split(lid).is_none());
        // One of its edges filed anew: the loop may have changed.
        let s = l.head;
        let node = m.front.node(s);
        m.front.refile_edges_at(s, node, &m.mesh.nodes);
        let changed = m.front.loops[lid as usize];
        assert_ne!(changed.version, l.version);
        assert!(!m.chords.cornerless(lid, changed));
        assert!(m.chord_split(lid).is_none());
        assert!(m.chords.cornerless(lid, changed));
    }

    /// A 36-hole perforated plate after `steps` steps of extraction.
    fn plate_stepped(steps: usize) -> Mesher {
        let b = crate::domains::perforated_plate(6);
        let model = std::sync::Arc::new(crate::model::default_model().expect("the shipped model"));
        let mut m = Mesher::new(b, model, crate::extract::MeshParams::DEFAULT);
        for _ in 0..steps {
            m.step().expect("a step");
        }
        m
    }

    /// A rip-up among many holes replaces only the loops it reached: the
    /// other holes keep their loop ids, slots and layers (their rows and
    /// queue entries stay where they were), the step ladder's memory
    /// keeps what it read away from the removal, and the plate still meshes
    /// with its invariants after every step.
    #[test]
    fn a_rip_up_replaces_only_the_loops_it_reached() {
        let mut m = plate_stepped(300);
        // Each live loop and its slots' ids, nodes and layers.
        type Seen = (u32, Vec<(crate::front::SlotId, u32, u32)>);
        let before: Vec<Seen> = m
            .front
            .live_loops()
            .map(|l| {
                let slots = m.front.loop_slots(l);
                let seen = slots
                    .iter()
                    .map(|&s| (s, m.front.node(s), m.front.slot(s).layer))
                    .collect();
                (l, seen)
            })
            .collect();
        // The loop with quads at it nearest the plate's centre, not the
        // outer one.
        let centre = Point::new(3.0, 3.0);
        let hole = before
            .iter()
            .filter(|(_, slots)| {
                slots.len() < 40
                    && slots
                        .iter()
                        .any(|&(_, v, _)| !m.incident[v as usize].is_empty())
            })
            .min_by(|a, b| {
                let d = |l: &Seen| m.mesh.nodes[l.1[0].1 as usize].distance(centre);
                d(a).total_cmp(&d(b))
            })
            .map(|(l, _)| *l)
            .expect("a hole with a row around it");
        let entries = m.memo.len();
        assert!(entries > 0, "the memory holds evaluations");
        let r = m.rip_up(hole, 1);
        assert!(r.removed > 0, "quads around the hole were removed");
        assert!(!m.front.loops[hole as usize].alive);
        let kept = before
            .iter()
            .filter(|(l, slots)| {
                m.front.loops[*l as usize].alive
                    && m.front.loop_slots(*l).len() == slots.len()
                    && slots.iter().all(|&(s, node, layer)| {
                        let now = m.front.slot(s);
                        now.alive && now.node == node && now.layer == layer && now.loop_id == *l
                    })
            })
            .count();
        assert!(
            kept + 4 >= before.len(),
            "{kept} of {} loops kept",
            before.len()
        );
        m.check_invariants()
            .expect("the invariants after the rip-up");
        // The step's forgetting: the removal's box, not everything.
        let bb = m.memo.changed_box.take();
        assert!(bb.is_some(), "the removal's box");
        m.forget(bb);
        assert!(
            m.memo.len() > entries / 2,
            "{} of {entries} evaluations kept",
            m.memo.len()
        );
        m.run_checked();
        assert!(m.mesh.check_finished().is_ok());
    }

    /// A chord split relinks one loop: the memory forgets the chord's box
    /// (and the slots of a short loop it leaves), not every evaluation.
    #[test]
    fn a_chord_split_forgets_only_around_its_chord() {
        let mut m = plate_stepped(300);
        let entries = m.memo.len();
        let longest = m
            .front
            .live_loops()
            .max_by_key(|&l| (m.front.loops[l as usize].len, std::cmp::Reverse(l)))
            .expect("a live loop");
        let r = m
            .chord_split(longest)
            .expect("a chord across the longest loop");
        assert!(!r.new_nodes.is_empty() || r.reference.is_some());
        let bb = m.memo.changed_box.take();
        assert!(bb.is_some(), "the chord's box");
        m.forget(bb);
        m.check_invariants()
            .expect("the invariants after the split");
        assert!(
            m.memo.len() > entries / 2,
            "{} of {entries} evaluations kept",
            m.memo.len()
        );
    }

    /// Loops are the same exactly when their node sequences are rotations
    /// of each other.
    #[test]
    fn a_loop_is_known_from_any_node_it_starts_at() {
        use super::cyclic_key;
        assert_eq!(cyclic_key(&[5, 2, 9, 2, 7]), cyclic_key(&[2, 7, 5, 2, 9]));
        assert_eq!(cyclic_key(&[5, 2, 9, 2, 7]), vec![2, 7, 5, 2, 9]);
        assert_ne!(cyclic_key(&[1, 2, 3, 4]), cyclic_key(&[1, 4, 3, 2]));
        assert_eq!(cyclic_key(&[]), Vec::<u32>::new());
    }
}

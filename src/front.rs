//! The advancing front (method §2): the loops bounding the region not yet
//! meshed, as doubly linked rings of *slots*. A slot is one occurrence of a
//! node on the front, so a node where a loop was pinched (after a snap that
//! split a loop or joined a hole) can stand on the front twice.
//!
//! A uniform grid over the front edges answers "which front edges are near
//! this box" in time independent of the front's length, so a step costs the
//! same whether the front has ten nodes or ten thousand.

use crate::geom::{ccw_angle, Aabb, AngleLimit, Point, StraightLimit};
use std::collections::BTreeSet;

/// Slot id.
pub type SlotId = u32;
/// No slot.
pub const NONE: SlotId = u32::MAX;

/// One occurrence of a node on the front.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slot {
    pub node: u32,
    pub next: SlotId,
    pub prev: SlotId,
    /// Loop id (index into [`Front::loops`]).
    pub loop_id: u32,
    /// Front layer: 0 on the boundary, one more for each row inwards.
    pub layer: u32,
    pub alive: bool,
}

/// A front loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrontLoop {
    /// Some slot of the loop (any one).
    pub head: SlotId,
    pub len: usize,
    pub alive: bool,
    /// Changes (never to 0) whenever an edge of the loop is filed anew: a
    /// loop whose version is unchanged has the same nodes where they were.
    pub version: u32,
}

/// Uniform grid of segments, each filed under an id (the front files an
/// edge under its start slot) in every cell the segment passes through: a
/// long edge (a needle's side across a fine grid) costs the cells along
/// it, not the cells of its bounding box. Boxes may be filed too (in
/// every cell they cover).
///
/// A query costs the cells it covers or, when that is more, one pass over
/// the ids' bounding boxes: a box many cells wide (a long reach where the
/// grid is fine for the smallest edges) never costs more than a scan.
#[derive(Clone, Debug)]
pub(crate) struct EdgeGrid {
    origin: Point,
    cell: f64,
    inv_cell: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<SlotId>>,
    /// Each id's bounding cell range `[x0, y0, x1, y1]`;
    /// [`EdgeGrid::UNFILED`] when the id is not filed.
    spans: Vec<[u32; 4]>,
    /// Each id's segment, as filed (its cells are found from it again
    /// when it is taken out); `None` for a box, filed in all its cells.
    ends: Vec<Option<[Point; 2]>>,
}

impl EdgeGrid {
    const UNFILED: [u32; 4] = [u32::MAX; 4];
    /// A segment is filed under the cells within this fraction of a cell
    /// of it, so one along a cell border is found from either side.
    const PAD: f64 = 1e-6;

    pub(crate) fn new(bb: Aabb, cell: f64, max_cells: usize) -> EdgeGrid {
        let size = bb.size().max(Point::splat(cell));
        let mut cell = cell.max(size.max_element() * 1e-6);
        while (size.x / cell).ceil() * (size.y / cell).ceil() > max_cells as f64 {
            cell *= 1.5;
        }
        let nx = ((size.x / cell).ceil() as usize).max(1);
        let ny = ((size.y / cell).ceil() as usize).max(1);
        EdgeGrid {
            origin: bb.min,
            cell,
            inv_cell: 1.0 / cell,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
            spans: Vec::new(),
            ends: Vec::new(),
        }
    }

    fn cell_range(&self, lo: Point, hi: Point) -> [u32; 4] {
        let f = |v: f64, n: usize| (v.max(0.0) as usize).min(n - 1) as u32;
        let a = (lo - self.origin) * self.inv_cell;
        let b = (hi - self.origin) * self.inv_cell;
        [
            f(a.x, self.nx),
            f(a.y, self.ny),
            f(b.x, self.nx),
            f(b.y, self.ny),
        ]
    }

    /// Calls `f` with the index of every cell the segment `ends` passes
    /// through, `span` being its bounding cell range: column by column,
    /// the rows the segment crosses within the column (cells beyond the
    /// grid's edge count as its border cells); every cell of `span` when
    /// there are no ends (a box).
    fn for_cells(&self, ends: Option<[Point; 2]>, span: [u32; 4], mut f: impl FnMut(usize)) {
        let [x0, y0, x1, y1] = span;
        let Some([a, b]) = ends.filter(|_| x0 != x1 && y0 != y1) else {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    f(y as usize * self.nx + x as usize);
                }
            }
            return;
        };
        let (a, b) = if a.x <= b.x { (a, b) } else { (b, a) };
        let slope = (b.y - a.y) / (b.x - a.x);
        let row = |y: f64, pad: f64| {
            let v = (y - self.origin.y) * self.inv_cell + pad;
            (v.max(0.0) as u32).clamp(y0, y1)
        };
        for x in x0..=x1 {
            let left = self.origin.x + x as f64 * self.cell;
            let xa = if x == x0 { a.x } else { left };
            let xb = if x == x1 { b.x } else { left + self.cell };
            let ya = a.y + slope * (xa - a.x);
            let yb = a.y + slope * (xb - a.x);
            let (lo, hi) = (row(ya.min(yb), -Self::PAD), row(ya.max(yb), Self::PAD));
            for y in lo..=hi {
                f(y as usize * self.nx + x as usize);
            }
        }
    }

    /// Files `s` under the cells of segment `a`–`b` (an id already filed
    /// is moved).
    pub(crate) fn insert(&mut self, s: SlotId, a: Point, b: Point) {
        self.file(s, a.min(b), a.max(b), Some([a, b]));
    }

    /// Files `s` under every cell of the box `lo..hi` (an id already filed
    /// is moved). Only the editor's quad index uses it.
    #[cfg_attr(not(feature = "gui"), allow(dead_code))]
    pub(crate) fn insert_box(&mut self, s: SlotId, lo: Point, hi: Point) {
        self.file(s, lo, hi, None);
    }

    fn file(&mut self, s: SlotId, lo: Point, hi: Point, ends: Option<[Point; 2]>) {
        self.remove(s);
        let span = self.cell_range(lo, hi);
        let mut cells = std::mem::take(&mut self.cells);
        self.for_cells(ends, span, |c| cells[c].push(s));
        self.cells = cells;
        let k = s as usize;
        if self.spans.len() <= k {
            self.spans.resize(k + 1, Self::UNFILED);
            self.ends.resize(k + 1, None);
        }
        self.spans[k] = span;
        self.ends[k] = ends;
    }

    /// Takes `s` out of the grid (nothing if it is not filed).
    pub(crate) fn remove(&mut self, s: SlotId) {
        let Some(span) = self.spans.get_mut(s as usize) else {
            return;
        };
        if *span == Self::UNFILED {
            return;
        }
        let span = std::mem::replace(span, Self::UNFILED);
        let ends = self.ends[s as usize];
        let mut cells = std::mem::take(&mut self.cells);
        self.for_cells(ends, span, |c| {
            let c = &mut cells[c];
            if let Some(k) = c.iter().position(|&t| t == s) {
                c.swap_remove(k);
            }
        });
        self.cells = cells;
    }

    /// The ids filed in cells that meet the box `lo..hi`, sorted, once each.
    pub(crate) fn query(&self, lo: Point, hi: Point, out: &mut Vec<SlotId>) {
        out.clear();
        let [x0, y0, x1, y1] = self.cell_range(lo, hi);
        let covered = (x1 - x0 + 1) as usize * (y1 - y0 + 1) as usize;
        if covered > self.spans.len() {
            let meets = |sp: &[u32; 4]| {
                *sp != Self::UNFILED && sp[0] <= x1 && sp[2] >= x0 && sp[1] <= y1 && sp[3] >= y0
            };
            out.extend((0..self.spans.len() as u32).filter(|&k| meets(&self.spans[k as usize])));
            return;
        }
        for y in y0..=y1 {
            for x in x0..=x1 {
                out.extend_from_slice(&self.cells[y as usize * self.nx + x as usize]);
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}

/// The front: loops of slots over the mesh's nodes.
#[derive(Clone, Debug)]
pub struct Front {
    pub slots: Vec<Slot>,
    pub loops: Vec<FrontLoop>,
    grid: EdgeGrid,
    alive: usize,
    /// The live loops' ids: a front that has taken in a thousand holes
    /// keeps their dead loops, and the steps that look at every live loop
    /// need not pass over those.
    live: BTreeSet<u32>,
    /// The loops changed (nodes, length, alive or not) since the last
    /// [`Front::take_changed`], in the order of the changes, with
    /// repeats: what lets a step look at the loops that changed rather
    /// than at every loop. A new front lists all its loops.
    changed: Vec<u32>,
    /// The loops relinks formed (a split's two, a join's one) since the
    /// last [`Front::take_relinked`]: their slots' loop, length and the
    /// parts a chord between two of them would cut changed, wherever the
    /// slots are.
    relinked: Vec<u32>,
}

impl Front {
    /// The initial front: one loop per boundary loop. `nodes` are the
    /// positions; the grid's cells are about `cell` wide and cover the
    /// loops' nodes (a front only moves into the region its loops bound,
    /// so the loops a rip-up adds later lie within the grid too; a front
    /// over a small cavity of a large mesh gets a grid of the cavity's
    /// extent, not of the mesh's).
    pub fn new(loops: &[Vec<u32>], nodes: &[Point], cell: f64) -> Front {
        let on_loops = loops.iter().flatten().map(|&v| nodes[v as usize]);
        let bb = Aabb::of(on_loops).unwrap_or(Aabb {
            min: Point::ZERO,
            max: Point::ONE,
        });
        let total: usize = loops.iter().map(Vec::len).sum();
        let max_cells = (64 * total).clamp(4096, 4_000_000);
        let mut f = Front {
            slots: Vec::with_capacity(total * 2),
            loops: Vec::new(),
            grid: EdgeGrid::new(bb, cell, max_cells),
            alive: 0,
            live: BTreeSet::new(),
            changed: Vec::new(),
            relinked: Vec::new(),
        };
        for l in loops {
            f.add_loop(l, nodes);
        }
        f
    }

    /// Number of slots on the front.
    pub fn len(&self) -> usize {
        self.alive
    }

    pub fn is_empty(&self) -> bool {
        self.alive == 0
    }

    #[inline]
    pub fn slot(&self, s: SlotId) -> &Slot {
        &self.slots[s as usize]
    }
    #[inline]
    pub fn next(&self, s: SlotId) -> SlotId {
        self.slots[s as usize].next
    }
    #[inline]
    pub fn prev(&self, s: SlotId) -> SlotId {
        self.slots[s as usize].prev
    }
    #[inline]
    pub fn node(&self, s: SlotId) -> u32 {
        self.slots[s as usize].node
    }

    /// The slot `k` steps along the loop (negative: backwards).
    pub fn walk(&self, mut s: SlotId, k: isize) -> SlotId {
        if k >= 0 {
            for _ in 0..k {
                s = self.next(s);
            }
        } else {
            for _ in 0..(-k) {
                s = self.prev(s);
            }
        }
        s
    }

    /// Length of the loop `s` belongs to.
    pub fn loop_len(&self, s: SlotId) -> usize {
        self.loops[self.slot(s).loop_id as usize].len
    }

    /// Interior angle of the front at slot `s` (radians, in `[0, 2π)`).
    #[inline]
    pub fn angle(&self, s: SlotId, nodes: &[Point]) -> f64 {
        let [p, next, prev] = self.corner(s, nodes);
        ccw_angle(p, next, prev)
    }

    /// The front's corner at slot `s`: its node and the nodes after and
    /// before it.
    #[inline]
    fn corner(&self, s: SlotId, nodes: &[Point]) -> [Point; 3] {
        let sl = self.slot(s);
        [
            nodes[sl.node as usize],
            nodes[self.node(sl.next) as usize],
            nodes[self.node(sl.prev) as usize],
        ]
    }

    /// True when the interior angle at slot `s` ([`Front::angle`]) is
    /// under `limit`.
    #[inline]
    pub fn angle_below(&self, s: SlotId, nodes: &[Point], limit: &AngleLimit) -> bool {
        let [p, next, prev] = self.corner(s, nodes);
        limit.below(p, next, prev)
    }

    /// True when the interior angle at slot `s` ([`Front::angle`]) is
    /// further from π than `limit`'s tolerance.
    #[inline]
    pub fn off_straight(&self, s: SlotId, nodes: &[Point], limit: &StraightLimit) -> bool {
        let [p, next, prev] = self.corner(s, nodes);
        limit.off(p, next, prev)
    }

    /// The number of live loops.
    pub fn live_loop_count(&self) -> usize {
        self.live.len()
    }

    /// The live loops' ids.
    pub fn live_loops(&self) -> impl Iterator<Item = u32> + '_ {
        self.live.iter().copied()
    }

    /// The slots of a loop, in order from its head.
    pub fn loop_slots(&self, lid: u32) -> Vec<SlotId> {
        let mut v = Vec::with_capacity(self.loops[lid as usize].len);
        v.extend(self.loop_walk(lid));
        v
    }

    /// [`Front::loop_slots`] walked in place, without collecting them.
    pub fn loop_walk(&self, lid: u32) -> impl Iterator<Item = SlotId> + '_ {
        let l = self.loops[lid as usize];
        std::iter::successors(Some(l.head), |&s| Some(self.next(s))).take(l.len)
    }

    /// The signed area loop `lid` encloses (negative for a hole's front,
    /// which runs clockwise).
    pub fn loop_area(&self, lid: u32, nodes: &[Point]) -> f64 {
        crate::geom::polygon_area(self.loop_walk(lid).map(|s| nodes[self.node(s) as usize]))
    }

    /// The area the live loops enclose (the region not meshed yet; holes'
    /// loops count negative).
    pub fn open_area(&self, nodes: &[Point]) -> f64 {
        self.live_loops().map(|l| self.loop_area(l, nodes)).sum()
    }

    /// The node ids of loop `lid`, in order from its head.
    pub fn loop_nodes(&self, lid: u32) -> Vec<u32> {
        self.loop_slots(lid).iter().map(|&s| self.node(s)).collect()
    }

    /// Front edges (by start slot) whose bounding box may meet `[lo, hi]`.
    pub fn edges_near(&self, lo: Point, hi: Point, out: &mut Vec<SlotId>) {
        self.grid.query(lo, hi, out);
    }

    fn grid_insert(&mut self, s: SlotId, nodes: &[Point]) {
        let (a, b) = (self.node(s), self.node(self.next(s)));
        self.grid.insert(s, nodes[a as usize], nodes[b as usize]);
        let lid = self.slots[s as usize].loop_id;
        let l = &mut self.loops[lid as usize];
        l.version = l.version.wrapping_add(1).max(1);
        self.changed.push(lid);
    }

    /// Puts into `out` the loops changed since the last call (sorted, each
    /// once; all of them on a new front), and forgets them: a loop not
    /// listed has the same slots, length and state as at that call.
    pub fn take_changed(&mut self, out: &mut Vec<u32>) {
        out.clear();
        out.append(&mut self.changed);
        out.sort_unstable();
        out.dedup();
    }

    /// Puts into `out` the loops relinks formed since the last call
    /// (sorted, each once; live or not by now) and forgets them.
    pub fn take_relinked(&mut self, out: &mut Vec<u32>) {
        out.clear();
        out.append(&mut self.relinked);
        out.sort_unstable();
        out.dedup();
    }

    /// Type 0: the node at slot `s` is replaced by `node` (same loop).
    pub fn replace_node(&mut self, s: SlotId, node: u32, layer: u32, nodes: &[Point]) {
        let p = self.prev(s);
        self.slots[s as usize].node = node;
        self.slots[s as usize].layer = layer;
        self.grid_insert(p, nodes);
        self.grid_insert(s, nodes);
    }

    /// Removes the two consecutive slots `s` and `next(s)` (types 1 and 2).
    pub fn remove_pair(&mut self, s: SlotId, nodes: &[Point]) {
        let t = self.next(s);
        let p = self.prev(s);
        let n = self.next(t);
        self.grid.remove(p);
        self.grid.remove(s);
        self.grid.remove(t);
        self.slots[p as usize].next = n;
        self.slots[n as usize].prev = p;
        for k in [s, t] {
            self.slots[k as usize].alive = false;
        }
        let lid = self.slot(p).loop_id as usize;
        self.loops[lid].len -= 2;
        self.loops[lid].head = p;
        self.alive -= 2;
        self.grid_insert(p, nodes);
    }

    /// Inserts new slots for `new_nodes` between `s` and `next(s)`; returns
    /// their ids in order.
    pub fn insert_after(
        &mut self,
        s: SlotId,
        new_nodes: &[u32],
        layer: u32,
        nodes: &[Point],
    ) -> Vec<SlotId> {
        let n = self.next(s);
        let lid = self.slot(s).loop_id;
        self.grid.remove(s);
        let mut prev = s;
        let mut ids = Vec::with_capacity(new_nodes.len());
        for &node in new_nodes {
            let id = self.slots.len() as SlotId;
            self.slots.push(Slot {
                node,
                next: NONE,
                prev,
                loop_id: lid,
                layer,
                alive: true,
            });
            self.slots[prev as usize].next = id;
            prev = id;
            ids.push(id);
        }
        self.slots[prev as usize].next = n;
        self.slots[n as usize].prev = prev;
        self.loops[lid as usize].len += new_nodes.len();
        self.alive += new_nodes.len();
        self.grid_insert(s, nodes);
        for &id in &ids {
            self.grid_insert(id, nodes);
        }
        ids
    }

    /// Takes the two front edges at slot `s` out of the grid (before their
    /// geometry changes).
    pub fn unfile_edges_at(&mut self, s: SlotId) {
        let p = self.prev(s);
        self.grid.remove(p);
        self.grid.remove(s);
    }

    /// Files the two front edges at slot `s` again and sets its node.
    pub fn refile_edges_at(&mut self, s: SlotId, node: u32, nodes: &[Point]) {
        self.slots[s as usize].node = node;
        let p = self.prev(s);
        self.grid_insert(p, nodes);
        self.grid_insert(s, nodes);
    }

    /// Removes a whole loop (it was closed by the final elements).
    pub fn remove_loop(&mut self, lid: u32) {
        for s in self.loop_slots(lid) {
            self.grid.remove(s);
            self.slots[s as usize].alive = false;
        }
        let l = &mut self.loops[lid as usize];
        self.alive -= l.len;
        if l.alive {
            self.live.remove(&lid);
        }
        self.changed.push(lid);
        l.len = 0;
        l.alive = false;
    }

    /// Adds a loop through `nodes` (in order, the region on the left), its
    /// slots on layer 0, and returns its id.
    pub fn add_loop(&mut self, loop_nodes: &[u32], nodes: &[Point]) -> u32 {
        let first = self.slots.len() as SlotId;
        let n = loop_nodes.len() as SlotId;
        let lid = self.loops.len() as u32;
        for (k, &node) in loop_nodes.iter().enumerate() {
            let k = k as SlotId;
            self.slots.push(Slot {
                node,
                next: first + (k + 1) % n,
                prev: first + (k + n - 1) % n,
                loop_id: lid,
                layer: 0,
                alive: true,
            });
        }
        self.loops.push(FrontLoop {
            head: first,
            len: loop_nodes.len(),
            alive: true,
            version: 1,
        });
        self.live.insert(lid);
        self.alive += loop_nodes.len();
        // Filing each edge lists the loop as changed.
        for s in first..first + n {
            self.grid_insert(s, nodes);
        }
        lid
    }

    /// Re-links two slots of the same node `a` and `b` so that `a` takes
    /// `b`'s successor and `b` takes `a`'s: one loop through both becomes
    /// two loops; two loops become one. Edges are unchanged in geometry.
    /// Returns the loop ids of `a` and `b` afterwards.
    pub fn exchange_successors(&mut self, a: SlotId, b: SlotId, nodes: &[Point]) -> (u32, u32) {
        debug_assert_eq!(self.node(a), self.node(b));
        self.relink(a, b, nodes)
    }

    /// Re-links slots `a` and `b` so that `a` takes `b`'s successor and `b`
    /// takes `a`'s: the edges from `a` and `b` are replaced by the edges
    /// `a → next(b)` and `b → next(a)` (for slots of one node, see
    /// [`Front::exchange_successors`]). One loop through both becomes two
    /// loops; two loops become one. Returns the loop ids of `a` and `b`
    /// afterwards.
    pub fn relink(&mut self, a: SlotId, b: SlotId, nodes: &[Point]) -> (u32, u32) {
        let an = self.next(a);
        let bn = self.next(b);
        self.slots[a as usize].next = bn;
        self.slots[bn as usize].prev = a;
        self.slots[b as usize].next = an;
        self.slots[an as usize].prev = b;
        self.grid_insert(a, nodes);
        self.grid_insert(b, nodes);
        let la = self.slot(a).loop_id;
        let lb = self.slot(b).loop_id;
        if la == lb {
            // Split: walk both new rings together; relabel the shorter.
            let (mut x, mut y) = (self.next(a), self.next(b));
            let (mut na, mut nb) = (1usize, 1usize);
            loop {
                if x == a {
                    break;
                }
                if y == b {
                    break;
                }
                x = self.next(x);
                y = self.next(y);
                na += 1;
                nb += 1;
            }
            let total = self.loops[la as usize].len;
            let (short, short_len) = if x == a { (a, na) } else { (b, nb) };
            let new_id = self.loops.len() as u32;
            self.live.insert(new_id);
            self.loops.push(FrontLoop {
                head: short,
                len: short_len,
                alive: true,
                version: 1,
            });
            let mut s = short;
            for _ in 0..short_len {
                self.slots[s as usize].loop_id = new_id;
                s = self.next(s);
            }
            let keep = if short == a { b } else { a };
            self.changed.extend([la, new_id]);
            self.relinked.extend([la, new_id]);
            self.loops[la as usize].len = total - short_len;
            self.loops[la as usize].head = keep;
            (self.slot(a).loop_id, self.slot(b).loop_id)
        } else {
            // Join: relabel the shorter loop into the longer one.
            let (keep, gone) = if self.loops[la as usize].len >= self.loops[lb as usize].len {
                (la, lb)
            } else {
                (lb, la)
            };
            let gone_len = self.loops[gone as usize].len;
            let start = if la == gone { a } else { b };
            // After the exchange the whole ring runs through both; relabel
            // the slots that carried the old id.
            let mut s = start;
            let total = self.loops[keep as usize].len + gone_len;
            for _ in 0..total {
                if self.slots[s as usize].loop_id == gone {
                    self.slots[s as usize].loop_id = keep;
                }
                s = self.next(s);
            }
            self.loops[keep as usize].len = total;
            self.changed.extend([keep, gone]);
            self.relinked.push(keep);
            self.live.remove(&gone);
            self.loops[gone as usize] = FrontLoop {
                head: NONE,
                len: 0,
                alive: false,
                version: 0,
            };
            (keep, keep)
        }
    }

    /// The loops bounding the part of the domain that `mesh`'s quads do not
    /// cover, as node sequences with the domain on the left. Where the
    /// uncovered region touches itself at a node, each incoming edge is
    /// paired with the outgoing edge that bounds the same wedge.
    pub fn loops_of_unmeshed(mesh: &crate::mesh::QuadMesh) -> Vec<Vec<u32>> {
        use std::collections::BTreeSet;
        let mut used: BTreeSet<(u32, u32)> = BTreeSet::new();
        for q in &mesh.quads {
            for k in 0..4 {
                used.insert((q[k], q[(k + 1) % 4]));
            }
        }
        let mut boundary: BTreeSet<(u32, u32)> = BTreeSet::new();
        for l in &mesh.loops {
            for k in 0..l.len() {
                boundary.insert((l[k], l[(k + 1) % l.len()]));
            }
        }
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for &(a, b) in &boundary {
            if !used.contains(&(a, b)) {
                edges.push((a, b));
            }
        }
        for &(a, b) in &used {
            if !used.contains(&(b, a)) && !boundary.contains(&(a, b)) {
                edges.push((b, a));
            }
        }
        Front::link_loops(edges, &mesh.nodes)
    }

    /// The loops of a set of directed edges that bound a region (region on
    /// the left), where the region may touch itself at a node: each incoming
    /// edge is paired with the outgoing edge that bounds the same wedge.
    /// Deterministic: loops start from the smallest edge left.
    pub fn link_loops(mut edges: Vec<(u32, u32)>, nodes: &[Point]) -> Vec<Vec<u32>> {
        use std::collections::BTreeMap;
        edges.sort_unstable();
        let mut out: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
        for (k, &(a, _)) in edges.iter().enumerate() {
            out.entry(a).or_default().push(k);
        }
        // successor of each edge (x→a): the edge (a→y) with the smallest
        // CCW turn from a→y to a→x.
        let mut succ = vec![usize::MAX; edges.len()];
        let mut taken = vec![false; edges.len()];
        for (k, &(x, a)) in edges.iter().enumerate() {
            let Some(cands) = out.get(&a) else { continue };
            let pa = nodes[a as usize];
            let px = nodes[x as usize];
            let best = cands
                .iter()
                .copied()
                .filter(|&c| !taken[c])
                .min_by(|&c, &d| {
                    let ac = ccw_angle(pa, nodes[edges[c].1 as usize], px);
                    let ad = ccw_angle(pa, nodes[edges[d].1 as usize], px);
                    ac.total_cmp(&ad)
                });
            if let Some(c) = best {
                succ[k] = c;
                taken[c] = true;
            }
        }
        let mut seen = vec![false; edges.len()];
        let mut loops = Vec::new();
        for k in 0..edges.len() {
            if seen[k] {
                continue;
            }
            let mut l = Vec::new();
            let mut e = k;
            while e != usize::MAX && !seen[e] {
                seen[e] = true;
                l.push(edges[e].0);
                e = succ[e];
            }
            loops.push(l);
        }
        loops
    }

    /// Checks the front's structure: links are mutual, loop lengths and ids
    /// match, no edge is degenerate, and the grid files every live edge.
    pub fn check_invariants(&self, nodes: &[Point]) -> Result<(), String> {
        let live: BTreeSet<u32> = (0..self.loops.len() as u32)
            .filter(|&l| self.loops[l as usize].alive)
            .collect();
        if live != self.live {
            return Err(format!(
                "live loops {live:?}, the front's list says {:?}",
                self.live
            ));
        }
        let mut count = 0;
        for lid in self.live_loops() {
            let l = self.loops[lid as usize];
            let mut s = l.head;
            for k in 0..l.len {
                let sl = self.slot(s);
                if !sl.alive {
                    return Err(format!("loop {lid}: slot {s} is dead"));
                }
                if sl.loop_id != lid {
                    return Err(format!("loop {lid}: slot {s} says loop {}", sl.loop_id));
                }
                if self.prev(sl.next) != s {
                    return Err(format!(
                        "loop {lid}: slot {s} is not its successor's predecessor"
                    ));
                }
                if self.node(sl.next) == sl.node {
                    return Err(format!("loop {lid}: zero-length edge at node {}", sl.node));
                }
                let (a, b) = (nodes[sl.node as usize], nodes[self.node(sl.next) as usize]);
                let mut near = Vec::new();
                self.edges_near(a.min(b), a.max(b), &mut near);
                if !near.contains(&s) {
                    return Err(format!(
                        "loop {lid}: edge from node {} missing from the grid",
                        sl.node
                    ));
                }
                s = sl.next;
                if s == l.head && k + 1 != l.len {
                    return Err(format!(
                        "loop {lid}: closes after {} of {} slots",
                        k + 1,
                        l.len
                    ));
                }
            }
            if s != l.head {
                return Err(format!("loop {lid}: does not close after {} slots", l.len));
            }
            count += l.len;
        }
        // A loop may be odd (a triangular hole); elements change a loop by
        // an even number of nodes, so the front as a whole stays even.
        if count % 2 != 0 {
            return Err(format!("{count} live slots in all: odd"));
        }
        if count != self.alive {
            return Err(format!(
                "{} live slots counted, {} recorded",
                count, self.alive
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A long diagonal segment is filed under the cells along it, not the
    /// cells of its box: a query off the diagonal in a corner of its box
    /// does not find it, one on it does, and taking it out empties every
    /// cell.
    #[test]
    fn a_long_segment_is_filed_along_its_cells() {
        let bb = Aabb {
            min: Point::ZERO,
            max: Point::splat(100.0),
        };
        let mut g = EdgeGrid::new(bb, 1.0, 1 << 20);
        g.insert(7, Point::new(0.5, 0.5), Point::new(99.5, 99.5));
        let filed: usize = g.cells.iter().map(Vec::len).sum();
        assert!((100..=400).contains(&filed), "{filed} cells");
        let mut out = Vec::new();
        // (Single cells: a query over more cells than there are ids scans
        // the ids' boxes instead.)
        g.query(Point::new(91.0, 6.0), Point::new(91.0, 6.0), &mut out);
        assert!(out.is_empty(), "{out:?}");
        g.query(Point::new(50.2, 49.8), Point::new(50.2, 49.8), &mut out);
        assert_eq!(out, vec![7]);
        // Along a cell border.
        g.insert(8, Point::new(10.0, 2.5), Point::new(10.0, 60.5));
        for x in [10.0, 10.1] {
            g.query(Point::new(x, 30.0), Point::new(x, 30.0), &mut out);
            assert_eq!(out, vec![8], "at x = {x}");
        }
        g.remove(7);
        g.remove(8);
        assert!(g.cells.iter().all(Vec::is_empty));
    }

    /// A front rebuilt around a small hole in a large mesh (as a rip-up
    /// does) gets cells of the size asked for over the hole, not cells
    /// stretched over the whole mesh, so a query near one edge reads only
    /// the edges around it.
    #[test]
    fn grid_covers_the_loops_not_the_mesh() {
        let mut nodes = vec![
            Point::new(-500.0, -500.0),
            Point::new(500.0, -500.0),
            Point::new(500.0, 500.0),
            Point::new(-500.0, 500.0),
        ];
        // A ring of 16 nodes of radius 4 at the centre.
        let ring: Vec<u32> = (0..16)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 16.0;
                nodes.push(Point::new(4.0 * a.cos(), 4.0 * a.sin()));
                nodes.len() as u32 - 1
            })
            .collect();
        let f = Front::new(&[ring], &nodes, 1.0);
        assert!(
            f.grid.nx <= 9 && f.grid.ny <= 9,
            "{} × {}",
            f.grid.nx,
            f.grid.ny
        );
        let p = nodes[f.node(0) as usize];
        let mut near = Vec::new();
        f.edges_near(p - Point::splat(0.1), p + Point::splat(0.1), &mut near);
        assert!(near.contains(&0) && near.contains(&15), "{near:?}");
        assert!(near.len() <= 4, "{near:?}");
        f.check_invariants(&nodes).expect("a valid front");
    }
}

//! Constrained Laplacian smoothing (thesis §5.1, "de-noise"; method §2.9):
//! each interior node moves towards the mean of its edge neighbours, and a
//! move is kept only if no adjacent quad inverts and none falls below
//! `min(its former scaled Jacobian, threshold)`. Boundary nodes never move.
//! Nodes are visited in id order (Gauss–Seidel), so the result is
//! deterministic. The optimisation's searches of a large mesh go by
//! groups of nodes that share no quad instead, each group on every core
//! ([`GROUPED_FROM`]), the result the same on any number of threads.

use crate::geom::{is_measurably_convex, Point};
use crate::mesh::{NodeQuads, QuadMesh};
use crate::quality::{QuadQuality, Shape, GOOD_RATIO};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::cell::Cell;

/// Smoothing parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SmoothParams {
    /// Sweeps over all interior nodes (default 8; 0 turns smoothing off).
    pub iterations: usize,
    /// A move may lower an adjacent quad's scaled Jacobian only while it
    /// stays at or above this value (default 0.6).
    pub threshold: f64,
    /// Fraction of the way to the neighbour mean moved per sweep (default 1).
    pub relaxation: f64,
    /// Sweeps of optimisation after the Laplacian ones (default 4; 0 turns
    /// it off): see [`optimize`].
    pub optimize_sweeps: usize,
    /// Nodes of quads whose scaled Jacobian is below this are optimised
    /// (default 0.8).
    pub optimize_below: f64,
    /// Sweeps of polishing once the mesh is final (default 4; 0 turns it
    /// off): see [`polish`].
    pub polish_sweeps: usize,
    /// Nodes of quads whose scaled Jacobian is below this are polished
    /// (default 0.95).
    pub polish_below: f64,
}

impl SmoothParams {
    pub const DEFAULT: SmoothParams = SmoothParams {
        iterations: 8,
        threshold: 0.6,
        relaxation: 1.0,
        optimize_sweeps: 4,
        optimize_below: 0.8,
        polish_sweeps: 4,
        polish_below: 0.95,
    };
    /// No smoothing.
    pub const OFF: SmoothParams = SmoothParams {
        iterations: 0,
        threshold: 0.6,
        relaxation: 1.0,
        optimize_sweeps: 0,
        optimize_below: 0.8,
        polish_sweeps: 0,
        polish_below: 0.95,
    };
}

impl Default for SmoothParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Compressed adjacency: per node, its quads and its edge neighbours.
struct Adjacency {
    quad_start: Vec<u32>,
    quads: Vec<u32>,
    nb_start: Vec<u32>,
    nbs: Vec<u32>,
}

impl Adjacency {
    fn new(mesh: &QuadMesh) -> Adjacency {
        let n = mesh.nodes.len();
        let NodeQuads {
            start: quad_start,
            quads,
        } = mesh.node_quads_flat();
        let mut nb_start = vec![0u32; n + 1];
        let mut nbs = Vec::with_capacity(4 * mesh.quads.len());
        // Per node, the two corners next to it in each of its quads, each
        // once, in id order.
        let mut list = Vec::new();
        for v in 0..n {
            list.clear();
            for &k in &quads[quad_start[v] as usize..quad_start[v + 1] as usize] {
                let q = mesh.quads[k as usize];
                let i = q.iter().position(|&u| u as usize == v).unwrap_or(0);
                list.extend([q[(i + 1) % 4], q[(i + 3) % 4]]);
            }
            list.sort_unstable();
            list.dedup();
            nbs.extend_from_slice(&list);
            nb_start[v + 1] = nbs.len() as u32;
        }
        Adjacency {
            quad_start,
            quads,
            nb_start,
            nbs,
        }
    }

    /// The quads at node `v`.
    fn quads_at(&self, v: usize) -> &[u32] {
        &self.quads[self.quad_start[v] as usize..self.quad_start[v + 1] as usize]
    }

    /// The neighbours of node `v`.
    fn nbs_at(&self, v: usize) -> &[u32] {
        &self.nbs[self.nb_start[v] as usize..self.nb_start[v + 1] as usize]
    }
}

/// The quads with a corner among some interior nodes of a mesh, as a mesh
/// of their own, for work on those nodes alone. Node and quad ids keep
/// their order, and a visit of [`smooth_with`] or [`search_with`] reads
/// only the node's quads and their corners, so working on the patch does
/// exactly what working on those nodes of the whole mesh does, at a cost
/// that follows the nodes rather than the mesh.
struct Patch {
    mesh: QuadMesh,
    /// Per node of the patch, its id in the whole mesh.
    global: Vec<u32>,
    /// The patch's ids of the nodes worked on, in order.
    moving: Vec<usize>,
}

impl Patch {
    /// The patch of the interior nodes `only` marks.
    fn of(mesh: &QuadMesh, only: &[bool]) -> Patch {
        let nb = mesh.n_boundary();
        let moves = |v: u32| v as usize >= nb && only.get(v as usize).copied().unwrap_or(false);
        let quads: Vec<[u32; 4]> = mesh
            .quads
            .iter()
            .filter(|q| q.iter().any(|&v| moves(v)))
            .copied()
            .collect();
        let mut global: Vec<u32> = quads.iter().flatten().copied().collect();
        global.sort_unstable();
        global.dedup();
        let local = |v: u32| global.partition_point(|&g| g < v) as u32;
        let quads = quads.iter().map(|q| q.map(local)).collect();
        let moving = (0..global.len()).filter(|&i| moves(global[i])).collect();
        Patch {
            mesh: QuadMesh {
                nodes: global.iter().map(|&v| mesh.nodes[v as usize]).collect(),
                quads,
                loops: Vec::new(),
            },
            global,
            moving,
        }
    }

    /// Puts the nodes worked on back into `mesh`.
    fn write_back(&self, mesh: &mut QuadMesh) {
        for &i in &self.moving {
            mesh.nodes[self.global[i] as usize] = self.mesh.nodes[i];
        }
    }
}

fn quad_sj(mesh: &QuadMesh, q: &[u32; 4]) -> f64 {
    Shape::of(mesh.corners(q)).scaled_jacobian
}

/// Steps tried along the way to a better position when unflattening.
const UNFLATTEN_STEPS: [f64; 6] = [1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125];

/// Moves interior nodes off corners that are flat to rounding (a node left
/// on the straight line between its neighbours, see
/// [`crate::geom::turns_left`]): each interior corner node of such a quad
/// is tried part of the way towards its neighbours' mean and towards the
/// quad's centroid, and the first position that leaves all its quads
/// measurably convex is kept. Runs whatever the smoothing parameters, so a
/// finished mesh never has a flat corner that an interior move can fix.
/// Returns the number of quads still flat.
pub fn unflatten(mesh: &mut QuadMesh) -> usize {
    let flat = |m: &QuadMesh| -> Vec<usize> {
        (0..m.quads.len())
            .filter(|&k| !is_measurably_convex(m.corners(&m.quads[k])))
            .collect()
    };
    let mut bad = flat(mesh);
    if bad.is_empty() {
        return 0;
    }
    let adj = Adjacency::new(mesh);
    let nb = mesh.n_boundary();
    for _ in 0..4 {
        for &k in &bad {
            let q = mesh.quads[k];
            if is_measurably_convex(mesh.corners(&q)) {
                continue;
            }
            let centroid = mesh.corners(&q).iter().copied().sum::<Point>() / 4.0;
            for v in q.map(|v| v as usize).into_iter().filter(|&v| v >= nb) {
                let (quads, nbs) = (adj.quads_at(v), adj.nbs_at(v));
                let mean = nbs.iter().map(|&u| mesh.nodes[u as usize]).sum::<Point>()
                    / nbs.len().max(1) as f64;
                let old = mesh.nodes[v];
                let found = [mean, centroid].into_iter().any(|goal| {
                    UNFLATTEN_STEPS.iter().any(|&t| {
                        mesh.nodes[v] = old + (goal - old) * t;
                        quads
                            .iter()
                            .all(|&j| is_measurably_convex(mesh.corners(&mesh.quads[j as usize])))
                    })
                });
                if found {
                    break;
                }
                mesh.nodes[v] = old;
            }
        }
        bad = flat(mesh);
        if bad.is_empty() {
            break;
        }
    }
    bad.len()
}

/// The interior nodes of `mesh`, or those of them `only` marks, in id
/// order.
fn interior_nodes(mesh: &QuadMesh, only: Option<&[bool]>) -> Vec<usize> {
    (mesh.n_boundary()..mesh.nodes.len())
        .filter(|&v| only.is_none_or(|m| m.get(v).copied().unwrap_or(false)))
        .collect()
}

/// Rings of quads around a local change of a mesh that are smoothed again
/// after it ([`after_change`]).
pub const LOCAL_RINGS: usize = 6;

/// A mesh of more than this many quads is smoothed again only near a local
/// change ([`after_change`]); a smaller one all over, where the extra sweeps
/// cost little and still even out the mesh away from the change.
pub const LOCAL_ABOVE: usize = 20_000;

/// The interior nodes to smooth again after a change to the quads `changed`
/// marks: all (`None`) on a mesh of up to [`LOCAL_ABOVE`] quads, else those
/// within [`LOCAL_RINGS`] rings of the change ([`near`]).
pub fn after_change(mesh: &QuadMesh, changed: &[bool]) -> Option<Vec<bool>> {
    (mesh.quads.len() > LOCAL_ABOVE).then(|| near(mesh, changed, LOCAL_RINGS))
}

/// The nodes within `rings` rings (sharing a quad) of the quads `changed`
/// marks, as a mask over the nodes: where [`smooth_only`] and
/// [`optimize_only`] need to work after a local change of the mesh.
pub fn near(mesh: &QuadMesh, changed: &[bool], rings: usize) -> Vec<bool> {
    let mut mask = vec![false; mesh.nodes.len()];
    let mut layer: Vec<u32> = Vec::new();
    for (q, _) in mesh.quads.iter().zip(changed).filter(|(_, &c)| c) {
        for &v in q {
            if !mask[v as usize] {
                mask[v as usize] = true;
                layer.push(v);
            }
        }
    }
    if rings == 0 || layer.is_empty() {
        return mask;
    }
    let inc = mesh.node_quads_flat();
    for _ in 0..rings {
        let mut next = Vec::new();
        for v in layer {
            for &k in inc.at(v) {
                for &u in &mesh.quads[k as usize] {
                    if !mask[u as usize] {
                        mask[u as usize] = true;
                        next.push(u);
                    }
                }
            }
        }
        layer = next;
    }
    mask
}

/// Smooths `mesh` in place; returns the number of accepted moves. A move is
/// refused when one of the node's quads would stop being convex (measurably
/// so, if it was), fall under `params.threshold` scaled Jacobian (or under
/// its own), or stretch past [`MAX_STRETCH`] (or past its own).
pub fn smooth(mesh: &mut QuadMesh, params: &SmoothParams) -> usize {
    smooth_only(mesh, params, None)
}

/// [`smooth`] over the interior nodes `only` marks (all with `None`).
pub fn smooth_only(mesh: &mut QuadMesh, params: &SmoothParams, only: Option<&[bool]>) -> usize {
    if params.iterations == 0 || mesh.quads.is_empty() {
        return 0;
    }
    on_nodes(mesh, only, |mesh, adj, nodes| {
        smooth_with(mesh, params, adj, nodes)
    })
}

/// [`smooth_only`], then [`optimize_only`] and the optimisation of
/// stretched quads ([`destretch_with`]) over the same nodes, sharing the
/// mesh's adjacency. Returns the moves of the smoothing and of the two
/// optimisations.
pub fn smooth_and_optimize(
    mesh: &mut QuadMesh,
    params: &SmoothParams,
    only: Option<&[bool]>,
) -> (usize, usize) {
    if mesh.quads.is_empty() || (params.iterations == 0 && params.optimize_sweeps == 0) {
        return (0, 0);
    }
    on_nodes(mesh, only, |mesh, adj, nodes| {
        let smoothed = smooth_with(mesh, params, adj, nodes);
        let optimized =
            optimize_with(mesh, params, adj, nodes) + destretch_with(mesh, params, adj, nodes);
        (smoothed, optimized)
    })
}

/// Runs `work` over the interior nodes `only` marks, with the adjacency
/// of the mesh it works on: the whole mesh with `None`, else the nodes'
/// [`Patch`], put back into `mesh` after.
fn on_nodes<R>(
    mesh: &mut QuadMesh,
    only: Option<&[bool]>,
    work: impl FnOnce(&mut QuadMesh, &Adjacency, &[usize]) -> R,
) -> R {
    match only {
        Some(only) => {
            let mut patch = Patch::of(mesh, only);
            let adj = Adjacency::new(&patch.mesh);
            let done = work(&mut patch.mesh, &adj, &patch.moving);
            patch.write_back(mesh);
            done
        }
        None => {
            let adj = Adjacency::new(mesh);
            let nodes = interior_nodes(mesh, None);
            work(mesh, &adj, &nodes)
        }
    }
}

/// The quads of `nodes`, each once, in id order.
fn quads_of(adj: &Adjacency, nodes: &[usize], n_quads: usize) -> Vec<u32> {
    let mut mark = vec![false; n_quads];
    for &v in nodes {
        for &k in adj.quads_at(v) {
            mark[k as usize] = true;
        }
    }
    (0..n_quads as u32).filter(|&k| mark[k as usize]).collect()
}

/// Which nodes a sweep of [`smooth_with`] or [`search_with`] visits. A
/// visit depends on the corners of the node's quads alone (and, in a
/// search, on which of those quads were poor when the sweep began), so a
/// node is visited again only when one of those corners moved in the
/// sweep before or in its own: the others would do what they did last
/// time, which was nothing. Sweeps give the same mesh as visiting every
/// node, at the cost of the nodes still moving.
struct Visits {
    /// Per node, the last sweep it is to be visited in.
    until: Vec<usize>,
}

impl Visits {
    /// Every node visited in sweep 0.
    fn new(n_nodes: usize) -> Visits {
        Visits {
            until: vec![0; n_nodes],
        }
    }

    /// Whether node `v` is visited in `sweep`.
    fn due(&self, v: usize, sweep: usize) -> bool {
        self.until[v] >= sweep
    }

    /// Node `v` moved in `sweep`: the corners of its quads are visited in
    /// this sweep (those still to come) and the next.
    fn moved(&mut self, mesh: &QuadMesh, adj: &Adjacency, v: usize, sweep: usize) {
        for &k in adj.quads_at(v) {
            for &u in &mesh.quads[k as usize] {
                self.until[u as usize] = sweep + 1;
            }
        }
    }
}

fn smooth_with(
    mesh: &mut QuadMesh,
    params: &SmoothParams,
    adj: &Adjacency,
    nodes: &[usize],
) -> usize {
    if params.iterations == 0 {
        return 0;
    }
    // Per quad, what a move may not go past where it is now: its scaled
    // Jacobian, whether it is measurably convex, its stretch bound. Filled
    // when first needed and kept up to date as its corners move.
    let mut now: Vec<Option<(f64, bool, f64)>> = vec![None; mesh.quads.len()];
    // With whether the quad is strictly convex.
    let limits = |p: [Point; 4]| {
        let shape = Shape::of(p);
        let (strict, measurable) = shape.convexity(p);
        (
            strict,
            (
                shape.scaled_jacobian,
                measurable,
                shape.side_ratio().max(MAX_STRETCH),
            ),
        )
    };
    let mut accepted = 0;
    let mut after = Vec::new();
    let mut visits = Visits::new(mesh.nodes.len());
    for sweep in 0..params.iterations {
        let mut moved = 0;
        for &v in nodes {
            if !visits.due(v, sweep) {
                continue;
            }
            let quads = adj.quads_at(v);
            if quads.is_empty() {
                continue;
            }
            let nbs = adj.nbs_at(v);
            let mut mean = Point::ZERO;
            for &u in nbs {
                mean += mesh.nodes[u as usize];
            }
            mean /= nbs.len() as f64;
            let old = mesh.nodes[v];
            let target = old + (mean - old) * params.relaxation;
            if (target - old).length_squared() == 0.0 {
                continue;
            }
            for &k in quads {
                if now[k as usize].is_none() {
                    now[k as usize] = Some(limits(mesh.corners(&mesh.quads[k as usize])).1);
                }
            }
            mesh.nodes[v] = target;
            // A quad stays convex, and measurably so if it was.
            after.clear();
            let ok = quads.iter().all(|&k| {
                let Some((b, m, st)) = now[k as usize] else {
                    return false;
                };
                let (strict, l) = limits(mesh.corners(&mesh.quads[k as usize]));
                if !strict {
                    return false;
                }
                // (Stretch bounds are at least MAX_STRETCH, so comparing
                // them is comparing the stretch itself.)
                after.push(l);
                (!m || l.1) && l.0 >= b.min(params.threshold) && l.2 <= st
            });
            if ok {
                moved += 1;
                for (&k, &l) in quads.iter().zip(&after) {
                    now[k as usize] = Some(l);
                }
                visits.moved(mesh, adj, v, sweep);
            } else {
                mesh.nodes[v] = old;
            }
        }
        accepted += moved;
        if moved == 0 {
            break;
        }
    }
    accepted
}

/// Smoothing never makes a quad's [`Shape::side_ratio`] exceed this, or its
/// own if larger: the scaled Jacobian does not see an edge shrinking to
/// nothing.
pub const MAX_STRETCH: f64 = 4.0;

/// What optimisation may not go past, per quad: its area, Rs and
/// [`Shape::side_ratio`] bounds, and whether it must stay measurably convex.
#[derive(Clone)]
struct Floor {
    area: f64,
    rs: f64,
    convex: bool,
    stretch: f64,
}

impl Floor {
    /// For a quad optimisation does not look at.
    const NONE: Floor = Floor {
        area: 0.0,
        rs: 0.0,
        convex: false,
        stretch: f64::INFINITY,
    };
}

/// A quad may shrink to this fraction of its area before optimisation: the
/// scaled Jacobian does not see size, and would let a quad be flattened
/// into a thin rectangle to favour its neighbours.
const MIN_AREA_RATIO: f64 = 0.3;

/// The quality of a node's `quads`: their smallest [`Measure`] (counted
/// up to `clip`) and their sum, or `None` when one goes past its [`Floor`]:
/// not measurably convex (when it was), smaller than its area bound,
/// thinner than its Rs bound or stretched past its stretch bound.
///
/// It is `None` as well as soon as one quad is under `beat`: the node's
/// quality would then not improve on a best whose worst is `beat`
/// ([`improves`]), and the other quads need not be looked at.
///
/// `failed` is the index in `quads` of the quad that refused the last
/// position tried: it is looked at first, for the positions of a search
/// lie close together and the same quad tends to refuse them. Any refusal
/// gives `None` whichever quad is looked at first, and the figures of a
/// position none refuses are summed in `quads`' order, so the result is
/// the same as without it.
fn node_quality(
    mesh: &QuadMesh,
    quads: &[u32],
    floor: &[Floor],
    (clip, measure): (f64, Measure),
    beat: f64,
    moving: (u32, Point),
    failed: &Cell<usize>,
) -> Option<(f64, f64)> {
    // The quad's measure, or `None` if it refuses the position.
    let quality = |k: u32| {
        let p = corners_with(mesh, &mesh.quads[k as usize], moving);
        let q = Shape::of(p);
        // Either measure is at most the scaled Jacobian: a quad under
        // `beat` by it is refused before the floor is looked at.
        if q.scaled_jacobian < beat {
            return None;
        }
        let f = &floor[k as usize];
        if (f.convex && !q.convexity(p).1)
            || q.area < f.area
            || q.rs < f.rs
            || q.side_ratio() > f.stretch
        {
            return None;
        }
        let sj = measure.of(&q);
        (sj >= beat).then_some(sj)
    };
    let first = failed.get();
    let measured = match quads.get(first) {
        Some(&k) => Some(quality(k)?),
        None => None,
    };
    let mut min = f64::INFINITY;
    let mut sum = 0.0;
    for (i, &k) in quads.iter().enumerate() {
        let sj = if i == first { measured } else { quality(k) };
        let Some(sj) = sj else {
            failed.set(i);
            return None;
        };
        min = min.min(sj);
        sum += sj;
    }
    Some((min.min(clip), sum))
}

/// The corners of quad `q` of `mesh` with node `v` at `at` (`moving` is
/// `(v, at)`).
#[inline]
fn corners_with(mesh: &QuadMesh, q: &[u32; 4], (v, at): (u32, Point)) -> [Point; 4] {
    let mut p = mesh.corners(q);
    for (c, &u) in p.iter_mut().zip(q) {
        if u == v {
            *c = at;
        }
    }
    p
}

/// Directions of the pattern search, unit length.
const DIRECTIONS: [(f64, f64); 8] = [
    (1.0, 0.0),
    (0.0, 1.0),
    (-1.0, 0.0),
    (0.0, -1.0),
    (
        std::f64::consts::FRAC_1_SQRT_2,
        std::f64::consts::FRAC_1_SQRT_2,
    ),
    (
        -std::f64::consts::FRAC_1_SQRT_2,
        std::f64::consts::FRAC_1_SQRT_2,
    ),
    (
        -std::f64::consts::FRAC_1_SQRT_2,
        -std::f64::consts::FRAC_1_SQRT_2,
    ),
    (
        std::f64::consts::FRAC_1_SQRT_2,
        -std::f64::consts::FRAC_1_SQRT_2,
    ),
];

/// Moves node `v` to where `quality` (lexicographic; `None`: the position
/// is refused) is best, starting from `best` = its quality where it is, by
/// a pattern search in eight directions whose step starts at a quarter of
/// the shortest edge to `nbs`, doubles after a success (up to a quarter of
/// the longest) and halves after a failure ([`search`]). `quality` is
/// given the worst member of the best so far: a position whose worst is
/// under it cannot improve, and `quality` may refuse it without looking
/// further. Returns the final position (the node is left there).
pub(crate) fn pattern_search(
    mesh: &mut QuadMesh,
    v: usize,
    nbs: &[u32],
    best: (f64, f64),
    quality: impl Fn(&QuadMesh, f64) -> Option<(f64, f64)>,
) -> Point {
    let steps = search_steps(mesh, v, nbs);
    let at = search(mesh.nodes[v], steps, best, |p, worst| {
        mesh.nodes[v] = p;
        quality(mesh, worst)
    });
    mesh.nodes[v] = at;
    at
}

/// The steps of [`pattern_search`] at node `v`: the first a quarter of the
/// shortest edge to `nbs`, stopping under a thousandth of it, none over a
/// quarter of the longest.
fn search_steps(mesh: &QuadMesh, v: usize, nbs: &[u32]) -> SearchSteps {
    let (shortest, longest) = edge_range(mesh, v, nbs);
    SearchSteps {
        first: 0.25 * shortest,
        stop: 1e-3 * shortest,
        cap: 0.25 * longest,
        grow: 2.0,
    }
}

/// The steps of a [`search`]: the first, the one it stops under, the
/// largest, and the factor a step grows by after a success.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SearchSteps {
    pub(crate) first: f64,
    pub(crate) stop: f64,
    pub(crate) cap: f64,
    pub(crate) grow: f64,
}

/// Tries at most this many rounds of a [`search`].
const SEARCH_ROUNDS: usize = 60;

/// A pattern search for the position of one node: from `start`, whose
/// quality is `best`, each round tries a step in each of eight directions
/// (`try_at` puts the node there and gives its quality, lexicographic, or
/// `None` to refuse it; it is given the first member of the best so far,
/// and may stop measuring and return any first member not over it by
/// [`SEARCH_MARGIN`], which is then no improvement)
/// and moves to the best that improves; the step grows by `steps.grow`
/// after a move (up to `steps.cap`) and halves after a round without one,
/// until it is under `steps.stop` or [`SEARCH_ROUNDS`] rounds are done.
/// Returns the best position found; where `try_at` left the node is the
/// caller's to undo.
pub(crate) fn search(
    start: Point,
    steps: SearchSteps,
    mut best: (f64, f64),
    mut try_at: impl FnMut(Point, f64) -> Option<(f64, f64)>,
) -> Point {
    let mut h = steps.first;
    let mut at = start;
    let mut rounds = 0;
    while h > steps.stop && rounds < SEARCH_ROUNDS {
        rounds += 1;
        let mut step = None;
        for (dx, dy) in DIRECTIONS {
            let p = at + Point::new(dx, dy) * h;
            if let Some(q) = try_at(p, best.0).filter(|&q| improves(q, best)) {
                best = q;
                step = Some(p);
            }
        }
        match step {
            Some(p) => {
                at = p;
                h = (steps.grow * h).min(steps.cap);
            }
            None => h *= 0.5,
        }
    }
    at
}

/// The shortest and the longest edge from node `v` to its neighbours `nbs`:
/// the scale of a node's search.
fn edge_range(mesh: &QuadMesh, v: usize, nbs: &[u32]) -> (f64, f64) {
    let at = mesh.nodes[v];
    nbs.iter().fold((f64::INFINITY, 0.0_f64), |(s, l), &u| {
        let d = mesh.nodes[u as usize].distance(at);
        (s.min(d), l.max(d))
    })
}

/// Whether node quality `q` is better than `best` (lexicographic, by more
/// than rounding).
fn improves(q: (f64, f64), best: (f64, f64)) -> bool {
    q.0 > best.0 + SEARCH_MARGIN || (q.0 >= best.0 && q.1 > best.1 + SEARCH_MARGIN)
}

/// By how much a quality must rise to count as better in a [`search`]
/// (more than rounding).
pub(crate) const SEARCH_MARGIN: f64 = 1e-12;

/// Steps [`ascend`] takes up the slope at most.
const ASCENT_STEPS: usize = 3;

/// Moves a node from `start` up the slope of the sum `quality` gives at a
/// position (its first member must not drop: lexicographic, as for
/// [`pattern_search`]), from `best`, its quality at `start`. The slope is
/// taken by forward differences over a thousandth of `shortest` (the
/// shortest edge to the node's neighbours); a step goes a fifth of that
/// edge along it, halved until the quality rises (at most five times); up
/// to [`ASCENT_STEPS`] steps. Returns the final position.
fn ascend(
    start: Point,
    shortest: f64,
    mut best: (f64, f64),
    quality: impl Fn(Point) -> Option<(f64, f64)>,
) -> Point {
    let mut at = start;
    let d = 1e-3 * shortest;
    'steps: for _ in 0..ASCENT_STEPS {
        let mut slope = Point::ZERO;
        for (k, e) in [Point::new(d, 0.0), Point::new(0.0, d)]
            .into_iter()
            .enumerate()
        {
            let Some(q) = quality(at + e) else {
                break 'steps;
            };
            slope[k] = (q.1 - best.1) / d;
        }
        let norm = slope.length();
        if norm == 0.0 || !norm.is_finite() {
            break;
        }
        let mut h = 0.2 * shortest;
        let mut stepped = false;
        for _ in 0..6 {
            let p = at + slope * (h / norm);
            if let Some(q) = quality(p).filter(|&q| improves(q, best)) {
                best = q;
                at = p;
                stepped = true;
                break;
            }
            h *= 0.5;
        }
        if !stepped {
            break;
        }
    }
    at
}

/// Optimisation-based smoothing: every interior node of a quad whose
/// scaled Jacobian is under `params.optimize_below` moves to where the
/// worst of its quads is best (ties: their sum), found by
/// [`pattern_search`]. Aimed at the elements Laplacian smoothing leaves
/// poor where fronts meet (a quad has all angles in [45°, 135°] exactly when its scaled Jacobian is
/// at least sin 45°). A move never lowers the node's worst quad, never
/// leaves a quad not measurably convex, never shrinks one below
/// [`MIN_AREA_RATIO`] of its area and never makes one thinner than
/// [`QuadQuality::THIN_RS`] (or than it was), and never stretches one past
/// [`MAX_STRETCH`] (or past its own). Returns the number of nodes moved.
pub fn optimize(mesh: &mut QuadMesh, params: &SmoothParams) -> usize {
    optimize_only(mesh, params, None)
}

/// [`optimize`] over the interior nodes `only` marks (all with `None`).
pub fn optimize_only(mesh: &mut QuadMesh, params: &SmoothParams, only: Option<&[bool]>) -> usize {
    if params.optimize_sweeps == 0 || mesh.quads.is_empty() {
        return 0;
    }
    on_nodes(mesh, only, |mesh, adj, nodes| {
        optimize_with(mesh, params, adj, nodes)
    })
}

/// Polishing, once a mesh is final: every interior node of a quad whose
/// scaled Jacobian is under `params.polish_below`, and of none under
/// `params.optimize_below`, climbs the slope of the sum of its quads'
/// scaled Jacobians ([`ascend`]) while none of them falls under
/// `params.optimize_below`. The mean scaled Jacobian rises where rows fan
/// out (round holes, an airfoil's nose) and where fronts met, and no quad
/// gets worse than the bar (nodes of the worst quads are left to
/// [`optimize`] and remeshing, which trade the sum for the worst). The nodes
/// polished are those of the quads under `polish_below` when it starts.
/// Moves are bounded as [`optimize`]'s are, and a quad keeps at least
/// [`POLISH_AREA_RATIO`] of its area, so sizes keep following the boundary.
/// Returns the number of nodes moved.
pub fn polish(mesh: &mut QuadMesh, params: &SmoothParams) -> usize {
    if params.polish_sweeps == 0 || mesh.quads.is_empty() {
        return 0;
    }
    // The nodes of the quads under the bar when polishing starts (most of
    // a large mesh is over it).
    let mut mark = vec![false; mesh.nodes.len()];
    for q in &mesh.quads {
        if quad_sj(mesh, q) < params.polish_below {
            for &v in q {
                mark[v as usize] = true;
            }
        }
    }
    let pass = Search {
        below: params.polish_below,
        seek: Seek::Sum {
            keep: params.optimize_below,
        },
        sweeps: params.polish_sweeps,
        area_ratio: POLISH_AREA_RATIO,
        measure: Measure::Jacobian,
    };
    on_nodes(mesh, Some(&mark), |mesh, adj, nodes| {
        search_with(mesh, &pass, adj, nodes)
    })
}

/// A quad may shrink to this fraction of its area when polished.
pub const POLISH_AREA_RATIO: f64 = 0.7;

/// [`untaper`] may lower a quad's scaled Jacobian to this, or not at all
/// if it is lower already.
pub const UNTAPER_FLOOR: f64 = 0.5;

/// [`untaper`] goes over the quads still past the bound at most this
/// many times: a move that only lowers a quad's excess leaves the rest to
/// its other corners, some of which come before it in the pass; a pass
/// that keeps no move ends it sooner.
pub const UNTAPER_PASSES: usize = 10;

/// Brings quads whose longest side is over [`GOOD_RATIO`] times their
/// shortest (the thesis's aspect and taper bound, §1.2) under it where
/// their interior corners' moves can: each interior corner of such a quad
/// is moved, by pattern search, to where its quads' side ratios exceed the
/// bound least, then where the worst of their scaled Jacobians is best;
/// no quad may stop being measurably convex, shrink under
/// [`MIN_AREA_RATIO`] of its area or fall under [`UNTAPER_FLOOR`] (or its
/// own scaled Jacobian, if lower). A move is kept when all of the node's
/// quads end within the bound, when it takes one of them within the bound
/// and leaves none more stretched than it was (or than the bound), or
/// when it lowers the excess of those with
/// no corner on the boundary and leaves that of the others no higher: a
/// quad whose two short sides are both too short needs two of its corners
/// moved, one pass after the other, while quads the boundary forces past
/// the bound (a slit between long walls) are not pulled about for a share
/// of their excess. The quads still past it are gone over again,
/// [`UNTAPER_PASSES`] times at most. Returns the number of moves kept.
pub fn untaper(mesh: &mut QuadMesh) -> usize {
    let mut moved = 0;
    for _ in 0..UNTAPER_PASSES {
        let pass = untaper_pass(mesh);
        moved += pass;
        if pass == 0 {
            break;
        }
    }
    moved
}

/// One pass of [`untaper`] over the interior corners of the quads past
/// the bound.
fn untaper_pass(mesh: &mut QuadMesh) -> usize {
    let over = |m: &QuadMesh, q: &[u32; 4]| Shape::of(m.corners(q)).side_ratio() > GOOD_RATIO;
    let mut mark = vec![false; mesh.nodes.len()];
    let mut any = false;
    for q in &mesh.quads {
        if over(mesh, q) {
            any = true;
            for &v in q {
                mark[v as usize] = true;
            }
        }
    }
    if !any {
        return 0;
    }
    on_nodes(mesh, Some(&mark), |mesh, adj, nodes| {
        let mut works = vec![false; mesh.nodes.len()];
        for &v in nodes {
            works[v] = true;
        }
        let mut moved = 0;
        for &v in nodes {
            let quads = adj.quads_at(v);
            if !quads.iter().any(|&k| over(mesh, &mesh.quads[k as usize])) {
                continue;
            }
            let floors: Vec<(f64, f64)> = quads
                .iter()
                .map(|&k| {
                    let s = Shape::of(mesh.corners(&mesh.quads[k as usize]));
                    (
                        s.scaled_jacobian.min(UNTAPER_FLOOR),
                        MIN_AREA_RATIO * s.area,
                    )
                })
                .collect();
            let quality = |m: &QuadMesh, _: f64| {
                let mut excess = 0.0;
                let mut worst = f64::INFINITY;
                for (&k, &(sj, area)) in quads.iter().zip(&floors) {
                    let p = m.corners(&m.quads[k as usize]);
                    let s = Shape::of(p);
                    if s.scaled_jacobian < sj || s.area < area || !is_measurably_convex(p) {
                        return None;
                    }
                    excess += (s.side_ratio() - GOOD_RATIO).max(0.0);
                    worst = worst.min(s.scaled_jacobian);
                }
                Some((-excess, worst))
            };
            let Some(start) = quality(mesh, f64::NEG_INFINITY) else {
                continue;
            };
            // Whether each quad is away from the boundary (every corner of
            // one is worked on: boundary nodes never are), and the quads'
            // side ratios before and after the move ([`untaper_keeps`]).
            let inside: Vec<bool> = quads
                .iter()
                .map(|&k| mesh.quads[k as usize].iter().all(|&u| works[u as usize]))
                .collect();
            let ratios = |m: &QuadMesh| -> Vec<f64> {
                quads
                    .iter()
                    .map(|&k| Shape::of(m.corners(&m.quads[k as usize])).side_ratio())
                    .collect()
            };
            let before = ratios(mesh);
            let old = mesh.nodes[v];
            let nbs = adj.nbs_at(v);
            pattern_search(mesh, v, nbs, start, quality);
            if quality(mesh, f64::NEG_INFINITY).is_some()
                && untaper_keeps(&before, &ratios(mesh), &inside)
            {
                moved += 1;
            } else {
                mesh.nodes[v] = old;
            }
        }
        moved
    })
}

/// Whether [`untaper`] keeps a move that takes the side ratios of a
/// node's quads from `before` to `after` (`inside[i]`: quad `i` has no
/// corner on the boundary): when all of them end within [`GOOD_RATIO`];
/// when it takes one of them within the bound and leaves none more
/// stretched than it was or than the bound (beside a quad the boundary
/// forces far past it, such as a slit's mouth, whose own excess no move
/// lowers); or when it lowers the excess of the quads inside without
/// ending it and leaves that of the others no higher (a quad whose two
/// short sides are both too short needs two corners moved).
fn untaper_keeps(before: &[f64], after: &[f64], inside: &[bool]) -> bool {
    let over = |r: &[f64]| r.iter().filter(|&&x| x > GOOD_RATIO).count();
    let excess = |r: &[f64]| {
        r.iter()
            .zip(inside)
            .fold((0.0, 0.0), |(ins, other), (&x, &is_inside)| {
                let e = (x - GOOD_RATIO).max(0.0);
                if is_inside {
                    (ins + e, other)
                } else {
                    (ins, other + e)
                }
            })
    };
    let (b, a) = (excess(before), excess(after));
    over(after) == 0
        || (over(after) < over(before)
            && after
                .iter()
                .zip(before)
                .all(|(&x, &y)| x <= y.max(GOOD_RATIO)))
        || (a.0 < b.0 && a.1 <= b.1)
}

fn optimize_with(
    mesh: &mut QuadMesh,
    params: &SmoothParams,
    adj: &Adjacency,
    nodes: &[usize],
) -> usize {
    let pass = Search {
        below: params.optimize_below,
        seek: Seek::Worst,
        sweeps: params.optimize_sweeps,
        area_ratio: MIN_AREA_RATIO,
        measure: Measure::Jacobian,
    };
    search_with(mesh, &pass, adj, nodes)
}

/// The scaled Jacobian [`destretch_with`] weighs a quad stretched to
/// [`GOOD_RATIO`] (longest over shortest side) as: about the thesis's
/// element criterion (every angle in [45°, 135°]).
pub const STRETCH_SJ: f64 = 0.7;

/// A move of [`destretch_with`] that takes the smallest scaled Jacobian
/// of the node's quads lower, and under [`STRETCH_SJ`], is kept only if
/// it divides the largest side ratio among them by at least this. A node come to sit on another gains far
/// more (a side ratio of 55 falls under 6); a node whose quads' ratio is
/// the boundary's, such as the node in a slit's mouth beside walls thirty
/// times the slit's width, gains a few per cent, and its quads would have
/// their angles traded for it.
pub const STRETCH_GAIN: f64 = 1.5;

/// The largest [`Shape::side_ratio`] and the smallest scaled Jacobian of
/// `quads`.
fn stretch_and_sj(mesh: &QuadMesh, quads: &[u32], moving: (u32, Point)) -> (f64, f64) {
    quads.iter().fold((0.0f64, f64::INFINITY), |(r, sj), &k| {
        let s = Shape::of(corners_with(mesh, &mesh.quads[k as usize], moving));
        (r.max(s.side_ratio()), sj.min(s.scaled_jacobian))
    })
}

/// Optimisation of stretched quads: every interior node of a quad among
/// `nodes` whose longest side is over [`GOOD_RATIO`] times its shortest
/// moves to where the worst of its quads is best, as [`optimize`] moves
/// nodes, each quad measured by its scaled Jacobian but no more than
/// [`STRETCH_SJ`] · [`GOOD_RATIO`] / its side ratio. The scaled Jacobian
/// alone does not see a node that has come to sit on another (two quads
/// each with a side near zero, two triangles with fair angles), so
/// [`optimize`] leaves it there; weighed this way, such a node moves off.
/// Moves are bounded as [`optimize`]'s are, and one that costs a quad
/// angles must pay for it in side ratio ([`STRETCH_GAIN`]). Returns the
/// number of nodes moved.
fn destretch_with(
    mesh: &mut QuadMesh,
    params: &SmoothParams,
    adj: &Adjacency,
    nodes: &[usize],
) -> usize {
    if params.optimize_sweeps == 0 {
        return 0;
    }
    let mut mark = vec![false; mesh.nodes.len()];
    for k in quads_of(adj, nodes, mesh.quads.len()) {
        let q = &mesh.quads[k as usize];
        if Shape::of(mesh.corners(q)).side_ratio() > GOOD_RATIO {
            for &v in q {
                mark[v as usize] = true;
            }
        }
    }
    let nodes: Vec<usize> = nodes.iter().copied().filter(|&v| mark[v]).collect();
    if nodes.is_empty() {
        return 0;
    }
    let pass = Search {
        below: STRETCH_SJ,
        seek: Seek::Worst,
        sweeps: params.optimize_sweeps,
        area_ratio: MIN_AREA_RATIO,
        measure: Measure::Stretch,
    };
    search_with(mesh, &pass, adj, &nodes)
}

/// What a [`Search`] seeks at a node.
enum Seek {
    /// The best worst quad, then the best sum ([`pattern_search`]).
    Worst,
    /// The best sum, at nodes whose quads are all at or above `keep`, which
    /// they stay ([`ascend`]).
    Sum { keep: f64 },
}

/// A pass of node-by-node search ([`optimize`], [`polish`]).
struct Search {
    /// Nodes of a quad under this scaled Jacobian are visited.
    below: f64,
    seek: Seek,
    sweeps: usize,
    /// A quad may shrink to this fraction of its area.
    area_ratio: f64,
    /// What a quad's quality is.
    measure: Measure,
}

/// What a [`Search`] measures a quad by.
#[derive(Clone, Copy, Debug)]
enum Measure {
    /// Its scaled Jacobian.
    Jacobian,
    /// [`Shape::stretch_weighted`] with [`STRETCH_SJ`] at the limit
    /// ([`destretch_with`]).
    Stretch,
}

impl Measure {
    fn of(self, shape: &Shape) -> f64 {
        match self {
            Measure::Jacobian => shape.scaled_jacobian,
            Measure::Stretch => shape.stretch_weighted(STRETCH_SJ),
        }
    }
}

/// Groups `nodes` so that no two of a group are corners of one quad: each
/// node, in `nodes`' order, joins the first group none of its quads'
/// corners is in. Within a group, a node's quads and their other corners
/// are the same wherever the others of its group move.
fn independent_groups(mesh: &QuadMesh, adj: &Adjacency, nodes: &[usize]) -> Vec<Vec<usize>> {
    let mut group = vec![u32::MAX; mesh.nodes.len()];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut taken: Vec<bool> = Vec::new();
    for &v in nodes {
        taken.clear();
        for &k in adj.quads_at(v) {
            for &u in &mesh.quads[k as usize] {
                let g = group[u as usize] as usize;
                if g < groups.len() {
                    if taken.len() <= g {
                        taken.resize(g + 1, false);
                    }
                    taken[g] = true;
                }
            }
        }
        let g = taken.iter().position(|&t| !t).unwrap_or(taken.len());
        if g == groups.len() {
            groups.push(Vec::new());
        }
        groups[g].push(v);
        group[v] = g as u32;
    }
    groups
}

/// A group of [`search_with`]'s nodes is searched on all cores from this
/// many nodes due.
const PARALLEL_NODES: usize = 64;

/// [`search_with`] takes its nodes in [`independent_groups`] from this
/// many on, and in id order below: a group's nodes are searched side by
/// side, which pays only on large meshes; in id order each sees the moves
/// of those before it.
pub const GROUPED_FROM: usize = 4096;

/// Where [`search_with`]'s `pass` moves node `v`, the mesh otherwise as it
/// is, or `None` if it stays.
fn visit(
    mesh: &QuadMesh,
    adj: &Adjacency,
    v: usize,
    pass: &Search,
    floor: &[Floor],
    clip: f64,
) -> Option<Point> {
    let quads = adj.quads_at(v);
    let start = mesh.nodes[v];
    let failed = Cell::new(0);
    let quality = |at: Point, beat: f64| {
        node_quality(
            mesh,
            quads,
            floor,
            (clip, pass.measure),
            beat,
            (v as u32, at),
            &failed,
        )
    };
    let best = quality(start, f64::NEG_INFINITY)?;
    let nbs = adj.nbs_at(v);
    let at = match pass.seek {
        Seek::Worst => search(start, search_steps(mesh, v, nbs), best, quality),
        Seek::Sum { keep } if best.0 >= keep => {
            ascend(start, edge_range(mesh, v, nbs).0, best, |p| {
                quality(p, f64::NEG_INFINITY)
            })
        }
        Seek::Sum { .. } => return None,
    };
    if at == start {
        return None;
    }
    if matches!(pass.measure, Measure::Stretch) {
        let before = stretch_and_sj(mesh, quads, (v as u32, start));
        let after = stretch_and_sj(mesh, quads, (v as u32, at));
        if after.1 < before.1.min(STRETCH_SJ) && after.0 * STRETCH_GAIN > before.0 {
            return None;
        }
    }
    Some(at)
}

/// Sweeps of `pass` over `nodes`: in each, the nodes due ([`Visits`]) with
/// a quad under `pass.below` when the sweep began are moved by [`visit`].
/// From [`GROUPED_FROM`] nodes on they are taken one [`independent_groups`]
/// group after another: the nodes of a group do not see each other's
/// moves, so a group is searched on all cores and the mesh is the same
/// whatever their number. Fewer are taken in id order, each after the
/// moves of those before it.
fn search_with(mesh: &mut QuadMesh, pass: &Search, adj: &Adjacency, nodes: &[usize]) -> usize {
    if pass.sweeps == 0 {
        return 0;
    }
    // Only the quads of the nodes visited are looked at.
    let quads = quads_of(adj, nodes, mesh.quads.len());
    let mut floor = vec![Floor::NONE; mesh.quads.len()];
    for &k in &quads {
        let p = mesh.corners(&mesh.quads[k as usize]);
        let s = Shape::of(p);
        floor[k as usize] = Floor {
            area: pass.area_ratio * s.area,
            rs: s.rs.min(QuadQuality::THIN_RS),
            convex: is_measurably_convex(p),
            stretch: s.side_ratio().max(MAX_STRETCH),
        };
    }
    // Counting the worst quad only up to `keep` leaves the sum alone to
    // rise, and keeps the worst from falling under `keep`.
    let clip = match pass.seek {
        Seek::Worst => f64::INFINITY,
        Seek::Sum { keep } => keep,
    };
    let grouped = nodes.len() >= GROUPED_FROM;
    let groups = if grouped {
        independent_groups(mesh, adj, nodes)
    } else {
        vec![nodes.to_vec()]
    };
    let mut moved = 0;
    let mut poor = vec![false; mesh.quads.len()];
    // The quads a corner of moved in since `poor` was last set.
    let mut stale = vec![true; mesh.quads.len()];
    let mut visits = Visits::new(mesh.nodes.len());
    let mut due: Vec<usize> = Vec::new();
    for sweep in 0..pass.sweeps {
        for &k in &quads {
            if std::mem::take(&mut stale[k as usize]) {
                let shape = Shape::of(mesh.corners(&mesh.quads[k as usize]));
                poor[k as usize] = pass.measure.of(&shape) < pass.below;
            }
        }
        let mut moved_now = 0;
        let wanted = |visits: &Visits, v: usize| {
            visits.due(v, sweep) && adj.quads_at(v).iter().any(|&k| poor[k as usize])
        };
        // Node `v` moves to `at`: the nodes and quads it touches are marked.
        let mut take = |mesh: &mut QuadMesh, visits: &mut Visits, v: usize, at: Point| {
            mesh.nodes[v] = at;
            moved_now += 1;
            visits.moved(mesh, adj, v, sweep);
            for &k in adj.quads_at(v) {
                stale[k as usize] = true;
            }
        };
        for group in &groups {
            if !grouped {
                for &v in group {
                    if !wanted(&visits, v) {
                        continue;
                    }
                    if let Some(at) = visit(mesh, adj, v, pass, &floor, clip) {
                        take(mesh, &mut visits, v, at);
                    }
                }
                continue;
            }
            due.clear();
            due.extend(group.iter().copied().filter(|&v| wanted(&visits, v)));
            let view: &QuadMesh = mesh;
            let to: Vec<Option<Point>> = if due.len() >= PARALLEL_NODES {
                due.par_iter()
                    .map(|&v| visit(view, adj, v, pass, &floor, clip))
                    .collect()
            } else {
                due.iter()
                    .map(|&v| visit(view, adj, v, pass, &floor, clip))
                    .collect()
            };
            for (&v, at) in due.iter().zip(to) {
                if let Some(at) = at {
                    take(mesh, &mut visits, v, at);
                }
            }
        }
        moved += moved_now;
        if moved_now == 0 {
            break;
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::is_measurably_convex;

    /// A 2 × 2 grid of unit squares whose centre node sits on the line
    /// between its neighbours (1,0) and (0,1): a flat corner.
    fn flat_grid() -> QuadMesh {
        let mut pts = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                pts.push(Point::new(i as f64, j as f64));
            }
        }
        pts[4] = Point::new(0.5, 0.5);
        QuadMesh::from_quads(
            pts,
            vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]],
        )
        .unwrap()
    }

    #[test]
    fn unflatten_moves_a_node_off_the_line() {
        let mut m = flat_grid();
        assert!(m.check_finished().is_err());
        assert_eq!(unflatten(&mut m), 0);
        assert!(m.quads.iter().all(|q| is_measurably_convex(m.corners(q))));
        m.check_finished().unwrap();
    }

    #[test]
    fn smoothing_restores_the_square_grid() {
        let mut m = flat_grid();
        let c = m.nodes.len() - 1; // the only interior node comes last
        m.nodes[c] = Point::new(0.8, 1.1);
        smooth(&mut m, &SmoothParams::DEFAULT);
        assert!((m.nodes[c] - Point::new(1.0, 1.0)).length() < 1e-12);
    }

    #[test]
    fn untapering_brings_a_short_sided_quad_within_the_bound() {
        // A 3 × 3 grid of unit squares whose interior node (1, 1) sits
        // just above the bottom side: the two quads under it have a side
        // of 0.09 beside sides of 1.
        let start = grid_at(3, |i, j| match (i, j) {
            (1, 1) => Point::new(1.0, 0.09),
            _ => Point::new(i as f64, j as f64),
        });
        let worst_ratio = |m: &QuadMesh| {
            m.quads
                .iter()
                .map(|q| Shape::of(m.corners(q)).side_ratio())
                .fold(0.0, f64::max)
        };
        assert!(worst_ratio(&start) > GOOD_RATIO);
        let mut m = start.clone();
        assert_eq!(untaper(&mut m), 1);
        assert!(worst_ratio(&m) <= GOOD_RATIO, "{}", worst_ratio(&m));
        for (k, q) in m.quads.iter().enumerate() {
            let (before, after) = (quad_sj(&start, q), quad_sj(&m, q));
            assert!(
                after >= before.min(UNTAPER_FLOOR),
                "quad {k}: {before} -> {after}"
            );
        }
        for v in 0..m.n_boundary() {
            assert_eq!(m.nodes[v], start.nodes[v], "boundary node {v} moved");
        }
        // Nothing over the bound: nothing to do.
        assert_eq!(untaper(&mut m), 0);
    }

    #[test]
    fn untapering_brings_a_quad_within_the_bound_beside_one_the_boundary_forces() {
        // The four quads round an interior node 0.017 from a corner of a
        // zig-zag outline (a real-like domain, seed 6's `297`): two of them
        // touch a slit's mouth 0.0034 wide beside walls of 0.27 (77 and
        // 78:1, forced), and the one on the corner's other side is 12:1
        // only because the node sits that close to the corner. No move of
        // the node brings the first two within the bound, so none ends all
        // four within it, and the third has a corner on the boundary; yet
        // moving it takes the third within the bound and stretches none of
        // them more.
        let pts = vec![
            Point::new(-0.030665, -0.044052),
            Point::new(-0.030665, -0.310598),
            Point::new(-0.028975, -0.313526),
            Point::new(-0.027285, -0.316453),
            Point::new(0.110939, -0.175460),
            Point::new(0.177851, -0.038475),
            Point::new(0.029990, 0.057700),
            Point::new(-0.106717, 0.147085),
            Point::new(-0.016514, -0.053309),
        ];
        let quads = vec![[0, 1, 2, 8], [4, 8, 2, 3], [6, 8, 4, 5], [7, 0, 8, 6]];
        let start = QuadMesh::from_quads(pts, quads).unwrap();
        assert_eq!(start.nodes.len() - start.n_boundary(), 1);
        let ratios = |m: &QuadMesh| -> Vec<f64> {
            m.quads
                .iter()
                .map(|q| Shape::of(m.corners(q)).side_ratio())
                .collect()
        };
        let before = ratios(&start);
        assert_eq!(before.iter().filter(|&&r| r > GOOD_RATIO).count(), 3);
        assert!(before[3] > 12.0 && before[3] < 12.5, "{before:?}");
        let mut m = start.clone();
        assert!(untaper(&mut m) > 0);
        let after = ratios(&m);
        assert_eq!(after.iter().filter(|&&r| r > GOOD_RATIO).count(), 2);
        assert!(after[3] <= GOOD_RATIO, "{after:?}");
        for (k, (a, b)) in after.iter().zip(&before).enumerate() {
            assert!(*a <= b.max(GOOD_RATIO), "quad {k}: {b} -> {a}");
            let (sj0, sj1) = (quad_sj(&start, &m.quads[k]), quad_sj(&m, &m.quads[k]));
            assert!(sj1 >= sj0.min(UNTAPER_FLOOR), "quad {k}: SJ {sj0} -> {sj1}");
        }
    }

    #[test]
    fn untapering_leaves_a_quad_the_boundary_forces() {
        // A strip of two quads between a side of 0.05 and sides of 1: no
        // interior node, nothing moves.
        let pts = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 0.05),
            Point::new(1.0, 0.05),
            Point::new(0.0, 0.05),
        ];
        let mut m = QuadMesh::from_quads(pts, vec![[0, 1, 4, 5], [1, 2, 3, 4]]).unwrap();
        let before = m.clone();
        assert_eq!(untaper(&mut m), 0);
        assert_eq!(m, before);
    }

    /// An n × n grid of quads, node (i, j) at `at(i, j)`.
    fn grid_at(n: usize, at: impl Fn(usize, usize) -> Point) -> QuadMesh {
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut pts = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                pts.push(at(i, j));
            }
        }
        let mut quads = Vec::new();
        for j in 0..n {
            for i in 0..n {
                quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        QuadMesh::from_quads(pts, quads).unwrap()
    }

    /// An n × n grid of unit squares with every interior node pushed off
    /// its place by a fixed pattern.
    fn jittered_grid(n: usize) -> QuadMesh {
        grid_at(n, |i, j| {
            let inside = i > 0 && j > 0 && i < n && j < n;
            let d = if inside {
                0.2 * ((i * 7 + j * 3) % 5) as f64 / 4.0
            } else {
                0.0
            };
            Point::new(i as f64 + d, j as f64 - d)
        })
    }

    #[test]
    fn the_quad_that_refused_last_is_looked_at_first_and_changes_nothing() {
        // A node of a jittered grid tried at positions all around it, with
        // floors of its quads as they stand and a `beat` that refuses
        // some: carrying the refusing quad from one position to the next
        // gives each position the figures a fresh look does.
        let mesh = jittered_grid(4);
        let v = 6; // node (1, 1)
        let adj = Adjacency::new(&mesh);
        let quads = adj.quads_at(v);
        let mut floor = vec![Floor::NONE; mesh.quads.len()];
        for &k in quads {
            let p = mesh.corners(&mesh.quads[k as usize]);
            let s = Shape::of(p);
            floor[k as usize] = Floor {
                area: MIN_AREA_RATIO * s.area,
                rs: s.rs.min(QuadQuality::THIN_RS),
                convex: is_measurably_convex(p),
                stretch: s.side_ratio().max(MAX_STRETCH),
            };
        }
        let carried = Cell::new(0);
        let (mut refused, mut kept, mut hinted) = (0, 0, 0);
        for step in 0..200 {
            let a = step as f64 * 0.37;
            let r = 0.05 + 1.1 * ((step * 13) % 17) as f64 / 17.0;
            let at = mesh.nodes[v] + Point::new(a.cos(), a.sin()) * r;
            for beat in [f64::NEG_INFINITY, 0.5, 0.8] {
                let q = |failed: &Cell<usize>| {
                    node_quality(
                        &mesh,
                        quads,
                        &floor,
                        (f64::INFINITY, Measure::Jacobian),
                        beat,
                        (v as u32, at),
                        failed,
                    )
                };
                let fresh = q(&Cell::new(0));
                if carried.get() > 0 {
                    hinted += 1;
                }
                let with = q(&carried);
                assert_eq!(
                    fresh.map(|(a, b)| (a.to_bits(), b.to_bits())),
                    with.map(|(a, b)| (a.to_bits(), b.to_bits())),
                    "position {step}, beat {beat}"
                );
                match fresh {
                    Some(_) => kept += 1,
                    None => refused += 1,
                }
            }
        }
        assert!(refused > 50 && kept > 50, "{refused} refused, {kept} kept");
        assert!(
            hinted > 50,
            "{hinted} looks began at another quad than the first"
        );
    }

    #[test]
    fn a_node_sitting_by_another_moves_off() {
        // A 3 × 3 grid whose node (1, 1) has come down to 0.02 above the
        // bottom node (1, 0): two quads with a side of 0.02, both with
        // corners near 45° and 135° (scaled Jacobian 0.7), that
        // optimisation by the scaled Jacobian alone leaves alone.
        let mut m = jittered_grid(3);
        for p in &mut m.nodes {
            *p = Point::new(p.x.round(), p.y.round());
        }
        let v = m
            .nodes
            .iter()
            .position(|&p| p == Point::new(1.0, 1.0))
            .unwrap();
        m.nodes[v] = Point::new(1.0, 0.02);
        let ratio = |m: &QuadMesh| {
            m.quads
                .iter()
                .map(|q| Shape::of(m.corners(q)).side_ratio())
                .fold(0.0, f64::max)
        };
        let worst_sj = |m: &QuadMesh| m.quads.iter().map(|q| quad_sj(m, q)).fold(1.0, f64::min);
        assert!(ratio(&m) > 40.0);
        let before = worst_sj(&m);
        let adj = Adjacency::new(&m);
        let nodes = interior_nodes(&m, None);
        assert!(destretch_with(&mut m, &SmoothParams::DEFAULT, &adj, &nodes) >= 1);
        assert!(ratio(&m) < GOOD_RATIO, "{}", ratio(&m));
        assert!(worst_sj(&m) >= before.min(STRETCH_SJ), "{}", worst_sj(&m));
        m.check_invariants(true).unwrap();
    }

    #[test]
    fn a_node_in_a_slits_mouth_keeps_its_quads_square() {
        // A slit 4 wide and 120 long (its walls y = ±2) opens at x = 0
        // into a corner of 120° between sides 119 long; the node x in
        // the mouth's middle is the one interior node. Its four quads
        // have side ratios of 30 to 60 that no move mends: pulling x into
        // the slit gains a few per cent of ratio and would take the
        // corners beside the mouth from 150° towards 173°.
        let p = Point::new;
        let pts = vec![
            p(-59.5, 103.1),  // 0: side's far end, above
            p(0.0, 2.0),      // 1: mouth, above
            p(0.0, -2.0),     // 2: mouth, below
            p(-59.5, -103.1), // 3: side's far end, below
            p(120.0, 2.0),    // 4: slit's upper wall end
            p(120.0, -2.0),   // 5: slit's lower wall end
            p(122.3, 0.0),    // 6: the junction beyond
            p(0.0, 0.0),      // 7: x, in the mouth
            p(-59.5, 0.0),    // 8: on the chord between the sides' ends
        ];
        let quads = vec![[2, 5, 6, 7], [7, 6, 4, 1], [3, 2, 7, 8], [8, 7, 1, 0]];
        let mut m = QuadMesh::from_quads(pts, quads).unwrap();
        let x = m.nodes.iter().position(|&q| q == p(0.0, 0.0)).unwrap();
        let worst_sj = |m: &QuadMesh| m.quads.iter().map(|q| quad_sj(m, q)).fold(1.0, f64::min);
        let before = worst_sj(&m);
        assert!((before - 0.5).abs() < 0.01, "{before}");
        let adj = Adjacency::new(&m);
        let nodes = interior_nodes(&m, None);
        assert_eq!(nodes, vec![x]);
        destretch_with(&mut m, &SmoothParams::DEFAULT, &adj, &nodes);
        assert!(worst_sj(&m) >= before - 1e-12, "{}", worst_sj(&m));
        m.check_invariants(true).unwrap();
    }

    /// The quad whose corners' mean is nearest `(x, y)`.
    fn quad_at(m: &QuadMesh, x: f64, y: f64) -> usize {
        let d = |q: &[u32; 4]| {
            (m.corners(q).iter().copied().sum::<Point>() / 4.0).distance(Point::new(x, y))
        };
        (0..m.quads.len())
            .min_by(|&a, &b| d(&m.quads[a]).total_cmp(&d(&m.quads[b])))
            .unwrap()
    }

    #[test]
    fn near_marks_the_rings_around_a_change() {
        let m = jittered_grid(8);
        let mut changed = vec![false; m.quads.len()];
        changed[quad_at(&m, 4.5, 4.5)] = true;
        let count = |rings| near(&m, &changed, rings).iter().filter(|&&b| b).count();
        // The quad's corners, then squares of 4, 6 and 8 nodes a side.
        assert_eq!([count(0), count(1), count(2), count(3)], [4, 16, 36, 64]);
        assert!(
            after_change(&m, &changed).is_none(),
            "a small mesh is smoothed all over"
        );
    }

    #[test]
    fn polishing_raises_the_mean_and_keeps_the_worst() {
        let start = jittered_grid(8);
        let q0 = crate::quality::MeshQuality::of(&start);
        let (min0, mean0) = (q0.sj_min, q0.sj_mean);
        let mut m = start.clone();
        let p = SmoothParams::DEFAULT;
        assert!(polish(&mut m, &p) > 0);
        let q1 = crate::quality::MeshQuality::of(&m);
        let (min1, mean1) = (q1.sj_min, q1.sj_mean);
        assert!(mean1 > mean0 + 0.01, "mean {mean0} -> {mean1}");
        assert!(min1 >= min0.min(p.optimize_below), "min {min0} -> {min1}");
        // No quad falls under the bar, or under where it was when it was
        // under the bar already.
        for (k, q) in m.quads.iter().enumerate() {
            let (before, after) = (quad_sj(&start, q), quad_sj(&m, q));
            assert!(
                after >= before.min(p.optimize_below),
                "quad {k}: {before} -> {after}"
            );
        }
        for v in 0..m.n_boundary() {
            assert_eq!(m.nodes[v], start.nodes[v], "boundary node {v} moved");
        }
        m.check_finished().unwrap();
        let mut off = start.clone();
        assert_eq!(polish(&mut off, &SmoothParams::OFF), 0);
        assert_eq!(off.nodes, start.nodes);
    }

    #[test]
    fn a_large_mesh_is_optimised_in_groups_alike_on_any_number_of_threads() {
        // 65 × 65 interior nodes, past GROUPED_FROM, pushed off their
        // places by a fixed pattern that leaves many quads under the bar.
        let n = 66;
        let start = grid_at(n, |i, j| {
            let inside = i > 0 && j > 0 && i < n && j < n;
            let (dx, dy) = if inside {
                (
                    0.15 * ((i * 7 + j * 3) % 5) as f64 - 0.3,
                    0.1 * ((i * 3 + j * 5) % 7) as f64 - 0.3,
                )
            } else {
                (0.0, 0.0)
            };
            Point::new(i as f64 + dx, j as f64 + dy)
        });
        let nodes = interior_nodes(&start, None);
        assert!(nodes.len() >= GROUPED_FROM);
        // The groups hold every node once, and no two of a group share a
        // quad.
        let adj = Adjacency::new(&start);
        let groups = independent_groups(&start, &adj, &nodes);
        let mut seen = vec![0; start.nodes.len()];
        for group in &groups {
            let mut in_group = vec![false; start.nodes.len()];
            for &v in group {
                seen[v] += 1;
                in_group[v] = true;
            }
            for &v in group {
                for &k in adj.quads_at(v) {
                    for &u in &start.quads[k as usize] {
                        assert!(u as usize == v || !in_group[u as usize], "{v} and {u}");
                    }
                }
            }
        }
        assert!(nodes.iter().all(|&v| seen[v] == 1));
        assert!(groups.len() <= 9, "{} groups", groups.len());
        let p = SmoothParams::DEFAULT;
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut m = start.clone();
                let moved = optimize(&mut m, &p);
                (m, moved)
            })
        };
        let (one, moved) = on(1);
        let (two, _) = on(2);
        assert_eq!(one.nodes, two.nodes);
        assert!(moved > 0);
        let (before, after) = (start.worst_scaled_jacobian(), one.worst_scaled_jacobian());
        assert!(after > before + 0.05, "worst {before} -> {after}");
        one.check_finished().unwrap();
    }

    #[test]
    fn smoothing_only_marked_nodes_leaves_the_rest() {
        let start = jittered_grid(8);
        let mut changed = vec![false; start.quads.len()];
        changed[quad_at(&start, 4.5, 4.5)] = true;
        let only = near(&start, &changed, 1);
        let mut m = start.clone();
        assert!(smooth_only(&mut m, &SmoothParams::DEFAULT, Some(&only)) > 0);
        optimize_only(&mut m, &SmoothParams::DEFAULT, Some(&only));
        for (v, &marked) in only.iter().enumerate() {
            if !marked {
                assert_eq!(m.nodes[v], start.nodes[v], "node {v} is not marked");
            }
        }
        assert!((0..m.nodes.len()).any(|v| m.nodes[v] != start.nodes[v]));
        m.check_finished().unwrap();
    }
}

//! Local remeshing of bad regions: a quad of a finished mesh whose scaled
//! Jacobian stays below [`RemeshParams::below`] after cleanup and smoothing,
//! or whose longest side is over ten times its shortest (thesis §1.2's
//! bound on aspect and taper, which the scaled Jacobian does not see), is
//! cut out with the quads around it (a cavity of two to
//! [`RemeshParams::rings`] rings of neighbours), and the cavity is meshed
//! again by element extraction (thesis §5.1, method §2), with the same
//! model, and cleaned up and smoothed with the cavity's nodes fixed as its
//! boundary. The new patch replaces the old one when its worst quad is no
//! worse and it has fewer quads below the bound, or as many and a better
//! worst one, it stretches no quad (longest over shortest edge) past
//! [`MAX_STRETCH`] or past the cavity's worst, and, unless the cavity's
//! worst quad is under [`POOR_SJ`], it leaves no more irregular interior
//! nodes (valence other than 4) among the cavity's nodes than there were
//! (such a cavity takes its smallest patch or none, and once a setting's
//! patch adds irregular nodes the other settings are not tried). The default bound,
//! 0.7, is about the thesis's element criterion (every angle in [45°,
//! 135°], scaled Jacobian at least sin 45° ≈ 0.707, thesis §1.2).
//!
//! Such quads come from where extraction fronts met at a shallow angle or
//! jammed into a narrow spike: a stack of flattened quads that no node
//! placement and no single collapse repairs, but a fresh extraction over a
//! slightly larger region does, because it sees the whole region at once.
//! The patch keeps every node of the cavity's boundary, so the mesh around
//! it is untouched and stays conforming. The mesh is smoothed at the end,
//! a large one only around the patches
//! ([`crate::smooth::after_change`]).
//!
//! Regions are taken worst quad first, in quad order among equals, and the
//! candidates are tried in a fixed order, so the result is deterministic.
//! The regions of the next bad quads in line whose cavities are apart are
//! worked out together, on every core; a region worked out ahead is used
//! only when no patch applied since has touched a node it read and the
//! work budget still covers it, else it is worked out again. The mesh is
//! therefore the same, byte for byte, whatever the number of threads.

use std::collections::BTreeMap;
use std::sync::Arc;

use rayon::prelude::*;

use super::cleanup::{improve, CleanupParams};
use super::params::FinishParams;
pub use super::params::RemeshParams;
use crate::boundary::Boundary;
use crate::extract::size::SizeField;
use crate::extract::{MeshParams, Mesher, StepKind, Strategy};
use crate::geom::Point;
use crate::mesh::{boundary_loops, QuadMesh};
use crate::model::Model;
use crate::quality::Shape;
use crate::smooth::{after_change, smooth_and_optimize, unflatten, MAX_STRETCH};

/// The order bad quads are taken in: flattened ones (scaled Jacobian
/// below the bound) first, then the ones only stretched, each worst first.
/// A stretch the input forces (a boundary segment far longer than its
/// neighbours) cannot be remeshed away, and taken first it would spend the
/// work budget before the flattened quads had their turn.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Priority {
    stretched_only: bool,
    fitness: f64,
}

impl Eq for Priority {}

impl PartialOrd for Priority {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Priority {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.stretched_only
            .cmp(&other.stretched_only)
            .then(self.fitness.total_cmp(&other.fitness))
    }
}

fn priority(mesh: &QuadMesh, q: &[u32; 4], bound: f64) -> Priority {
    let shape = Shape::of(mesh.corners(q));
    Priority {
        stretched_only: shape.scaled_jacobian >= bound,
        fitness: fitness_of(&shape, bound),
    }
}

/// How good a quad of `shape` is, measured against the remeshing `bound`:
/// [`Shape::stretch_weighted`], so a quad stretched past
/// [`GOOD_RATIO`](crate::quality::GOOD_RATIO) (the thesis's bound on
/// aspect and taper, §1.2) counts as bad too, the more so the more it is
/// stretched.
fn fitness_of(shape: &Shape, bound: f64) -> f64 {
    shape.stretch_weighted(bound)
}

/// How bad a set of quads is: smaller is better (fewer bad quads first,
/// then a higher worst [`fitness_of`]).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Badness {
    /// Quads whose fitness is below the bound.
    bad: usize,
    /// The worst fitness.
    worst: f64,
    /// The worst scaled Jacobian.
    worst_sj: f64,
    /// The largest [`Shape::side_ratio`].
    worst_stretch: f64,
}

fn badness<'q>(mesh: &QuadMesh, quads: impl Iterator<Item = &'q [u32; 4]>, bound: f64) -> Badness {
    quads.fold(
        Badness {
            bad: 0,
            worst: f64::INFINITY,
            worst_sj: f64::INFINITY,
            worst_stretch: 0.0,
        },
        |b, q| {
            let shape = Shape::of(mesh.corners(q));
            let f = fitness_of(&shape, bound);
            Badness {
                bad: b.bad + usize::from(f < bound),
                worst: b.worst.min(f),
                worst_sj: b.worst_sj.min(shape.scaled_jacobian),
                worst_stretch: b.worst_stretch.max(shape.side_ratio()),
            }
        },
    )
}

fn better(a: Badness, b: Badness) -> bool {
    a.bad < b.bad || (a.bad == b.bad && a.worst > b.worst)
}

/// A patch with `new` badness may replace a cavity with `old`: better, its
/// worst quad no worse, and its worst scaled Jacobian no lower than the
/// cavity's or than the bound (a stretched quad is not traded for a
/// flattened one; a patch may give up corner angle only while its corners
/// stay within the bound's).
fn improves(new: Badness, old: Badness, bound: f64) -> bool {
    better(new, old) && new.worst >= old.worst && new.worst_sj >= old.worst_sj.min(bound)
}

/// The mesh being patched: live quads and each node's quads.
struct Work<'a> {
    mesh: &'a mut QuadMesh,
    alive: Vec<bool>,
    inc: Vec<Vec<u32>>,
}

/// A replacement for a cavity: its quads and the nodes it adds.
struct Patch {
    cavity: Vec<u32>,
    nodes: Vec<Point>,
    /// Quads over the cavity's boundary nodes (by mesh id) and the new
    /// nodes (`u32::MAX - i` for new node `i`).
    quads: Vec<[u32; 4]>,
    badness: Badness,
}

const NEW: u32 = u32::MAX;

/// What a region's work reads apart from the mesh: the largest cavity in
/// rings, the model, the extraction settings, the patches' finishing and
/// the remeshing bound.
struct RegionContext<'a> {
    rings: usize,
    model: &'a Arc<dyn Model>,
    candidates: &'a [MeshParams],
    finish: &'a FinishParams,
    bound: f64,
}

/// A bad quad's region as worked out: the patch chosen, the nodes of the
/// quads it read (its largest cavity), the work it took, whether the
/// work ran out on it, and the number of patches applied before it.
struct Region {
    chosen: Option<Patch>,
    nodes: Vec<u32>,
    cost: usize,
    ran_dry: bool,
    after: usize,
}

impl Region {
    /// True if working the region out now gives the same: no patch since
    /// touched a node it read (`touched`: per node, the number of patches
    /// applied when one last covered it; `replaced` so far), and `work`
    /// covers its cost without running out.
    fn still_holds(&self, touched: &[usize], replaced: usize, work: usize) -> bool {
        (self.after == replaced
            || self
                .nodes
                .iter()
                .all(|&v| touched[v as usize] <= self.after))
            && !self.ran_dry
            && work > self.cost
    }
}

/// A cavity whose worst quad is at or above this scaled Jacobian is not
/// poor enough to take a patch with more irregular nodes.
const POOR_SJ: f64 = 0.4;

/// Regions worked out ahead per thread.
const AHEAD: usize = 6;
/// Bad quads looked at for a batch of regions worked out ahead.
const AHEAD_SCAN: usize = 64;

/// Extraction steps all patch runs of one mesh may take together, per quad
/// of the mesh, plus [`WORK_BASE`]; a run that fails is charged its whole
/// step limit (it has been through its fills as well). This bounds
/// remeshing on meshes that are poor nearly everywhere, where every patch
/// is tried with every setting and fails.
const WORK_PER_QUAD: usize = 16;
/// Patch steps allowed on any mesh, however small.
const WORK_BASE: usize = 1000;

/// A patch may have at most this many quads per quad of its cavity (plus
/// 16 steps of extraction, after which the run is cut short): a much finer
/// patch than its surroundings is not an improvement.
const MAX_QUADS: usize = 2;

impl Work<'_> {
    /// The live quads within `rings` rings of quad `k` (sharing a node),
    /// sorted.
    fn cavity(&self, k: u32, rings: usize) -> Vec<u32> {
        let mut set = std::collections::BTreeSet::from([k]);
        for _ in 0..rings {
            let grown: Vec<u32> = set
                .iter()
                .flat_map(|&j| self.mesh.quads[j as usize])
                .flat_map(|v| self.inc[v as usize].iter().copied())
                .collect();
            set.extend(grown);
        }
        set.into_iter().collect()
    }

    /// Meshes the cavity again with each candidate setting and returns the
    /// best patch that [`improves`] on `old` (the cavity's badness against
    /// `bound`), if the cavity's boundary makes a valid boundary.
    fn patch(
        &self,
        cavity: Vec<u32>,
        model: &Arc<dyn Model>,
        candidates: &[MeshParams],
        finish: &FinishParams,
        (bound, old): (f64, Badness),
        work: &mut usize,
    ) -> Option<Patch> {
        let quads: Vec<[u32; 4]> = cavity
            .iter()
            .map(|&j| self.mesh.quads[j as usize])
            .collect();
        let loops = cavity_loops(&self.mesh.nodes, &quads)?;
        let mut ids: Vec<u32> = Vec::new();
        let mut local: BTreeMap<u32, usize> = BTreeMap::new();
        let sub_loops: Vec<Vec<usize>> = loops
            .iter()
            .map(|l| {
                l.iter()
                    .map(|&v| {
                        *local.entry(v).or_insert_with(|| {
                            ids.push(v);
                            ids.len() - 1
                        })
                    })
                    .collect()
            })
            .collect();
        let points: Vec<Point> = ids.iter().map(|&v| self.mesh.nodes[v as usize]).collect();
        let irregular_before = self.irregular_before(&quads);
        // A patch may not stretch a quad more than smoothing would
        // (MAX_STRETCH) or than the cavity already does.
        let max_stretch = old.worst_stretch.max(MAX_STRETCH);
        let boundary = Boundary::new(points, sub_loops, None).ok()?;
        let mut best: Option<Patch> = None;
        // The meshes the settings gave before cleanup and smoothing: one
        // that gives the same as an earlier setting is not finished again
        // (it would come out the same, and what was taken or refused then
        // would be again).
        let mut made: Vec<QuadMesh> = Vec::new();
        // Every setting meshes the same cavity: one size field serves all.
        let size = Arc::new(SizeField::of_boundary(&boundary));
        // A patch of many more quads than the cavity is not wanted, and an
        // extraction that would make one is cut short.
        let limit = MAX_QUADS * cavity.len() + 16;
        // The cost of a run the settings after it would make again step for
        // step (every step by a rung that reads no setting, such as a band
        // closed by rows): they are not run, as the mesh they would give
        // would not be finished again, but the work budget is charged as
        // if they were.
        let mut repeated: Option<usize> = None;
        for params in candidates {
            let params = MeshParams {
                max_steps: Some(limit),
                ..params.clone()
            };
            if *work == 0 {
                break;
            }
            if let Some(cost) = repeated {
                *work = work.saturating_sub(cost);
                continue;
            }
            let mut mesher =
                Mesher::with_size(boundary.clone(), model.clone(), params, size.clone());
            let run = mesher.run(|_| {});
            // A run that fails has tried its fills too: it costs its limit,
            // as does each fill of a run that finishes.
            let cost = if run.is_ok() {
                mesher.steps() + mesher.stats().count(StepKind::Fill) * limit
            } else {
                limit
            };
            *work = work.saturating_sub(cost.max(1));
            if run.is_ok() && mesher.stats().ignores_strategy() {
                repeated = Some(cost.max(1));
            }
            if run.is_err() || mesher.mesh().quads.len() > MAX_QUADS * cavity.len() {
                continue;
            }
            let mut sub = mesher.mesh().clone();
            sub.compact();
            if made.contains(&sub) {
                continue;
            }
            made.push(sub.clone());
            improve(&mut sub, true, &finish.cleanup, &finish.smooth);
            unflatten(&mut sub);
            if sub.check_finished().is_err() {
                continue;
            }
            let b = badness(&sub, sub.quads.iter(), bound);
            if old.worst_sj >= POOR_SJ
                && self.irregular_after(&quads, &sub, &ids) > irregular_before
            {
                // The other settings mesh the cavity much the same way.
                break;
            }
            if b.worst_stretch > max_stretch
                || !improves(b, old, bound)
                || best.as_ref().is_some_and(|p| !better(b, p.badness))
            {
                continue;
            }
            let nb = ids.len();
            let map = |v: u32| {
                let v = v as usize;
                if v < nb {
                    ids[v]
                } else {
                    NEW - (v - nb) as u32
                }
            };
            best = Some(Patch {
                cavity: cavity.clone(),
                nodes: sub.nodes[nb..].to_vec(),
                quads: sub.quads.iter().map(|q| q.map(map)).collect(),
                badness: b,
            });
            if b.bad == 0 {
                break;
            }
        }
        best
    }

    /// The interior nodes of the mesh among the corners of `cavity`'s
    /// quads whose valence is not 4.
    fn irregular_before(&self, cavity: &[[u32; 4]]) -> usize {
        let mut nodes: Vec<u32> = cavity.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
            .iter()
            .filter(|&&v| !self.mesh.is_boundary(v) && self.inc[v as usize].len() != 4)
            .count()
    }

    /// [`Work::irregular_before`] once `cavity` is replaced by `sub`
    /// (whose first `ids.len()` nodes are the mesh's nodes `ids`, the rest
    /// new).
    fn irregular_after(&self, cavity: &[[u32; 4]], sub: &QuadMesh, ids: &[u32]) -> usize {
        let nb = ids.len();
        let mut valence = vec![0usize; sub.nodes.len()];
        for q in &sub.quads {
            for &v in q {
                valence[v as usize] += 1;
            }
        }
        let kept = ids.iter().enumerate().filter(|&(i, &v)| {
            let inside = cavity.iter().filter(|q| q.contains(&v)).count();
            !self.mesh.is_boundary(v) && self.inc[v as usize].len() - inside + valence[i] != 4
        });
        kept.count() + valence[nb..].iter().filter(|&&d| d != 4).count()
    }

    /// The region of bad quad `k` (cavities of 2 to `ctx.rings` rings,
    /// the smallest that leaves no bad quad, else the best) on the mesh as
    /// it stands after `replaced` patches, with `work` left to spend.
    fn region(&self, k: u32, ctx: &RegionContext, work: usize, replaced: usize) -> Region {
        let mut left = work;
        let mut chosen: Option<Patch> = None;
        let mut read: Vec<u32> = Vec::new();
        for rings in 2..=ctx.rings {
            let cavity = self.cavity(k, rings);
            read.clone_from(&cavity);
            let old = badness(
                self.mesh,
                cavity.iter().map(|&j| &self.mesh.quads[j as usize]),
                ctx.bound,
            );
            let Some(p) = self.patch(
                cavity,
                ctx.model,
                ctx.candidates,
                ctx.finish,
                (ctx.bound, old),
                &mut left,
            ) else {
                continue;
            };
            let clean = p.badness.bad == 0;
            if chosen.as_ref().is_none_or(|c| better(p.badness, c.badness)) {
                chosen = Some(p);
            }
            // A cavity not poor takes the smallest patch that improves it:
            // larger ones rarely keep its irregular nodes down.
            if clean || old.worst_sj >= POOR_SJ {
                break;
            }
        }
        let mut nodes: Vec<u32> = read
            .iter()
            .flat_map(|&j| self.mesh.quads[j as usize])
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        Region {
            chosen,
            nodes,
            cost: work - left,
            ran_dry: left == 0,
            after: replaced,
        }
    }

    /// Bad quad `k` and the live bad quads after it in `bad` (at most
    /// [`AHEAD`] per thread, from the next [`AHEAD_SCAN`], and no more
    /// than `left` in all: the regions still to be tried) whose largest
    /// cavities share no node with each other's, leaving out those whose
    /// region worked out ahead still holds (`holds`): the regions worked
    /// out together.
    fn batch(
        &self,
        k: u32,
        bad: &[(Priority, u32)],
        (rings, left): (usize, usize),
        holds: impl Fn(u32) -> bool,
    ) -> Vec<u32> {
        let threads = rayon::current_num_threads();
        let mut batch = vec![k];
        if threads <= 1 {
            return batch;
        }
        let want = (AHEAD * threads).min(left);
        let mut taken: std::collections::BTreeSet<u32> = std::collections::BTreeSet::new();
        let mut disjoint = |j: u32| {
            let nodes: Vec<u32> = self
                .cavity(j, rings)
                .iter()
                .flat_map(|&q| self.mesh.quads[q as usize])
                .collect();
            if nodes.iter().any(|v| taken.contains(v)) {
                return false;
            }
            taken.extend(nodes);
            true
        };
        disjoint(k);
        for &(_, j) in bad.iter().take(AHEAD_SCAN) {
            if batch.len() >= want {
                break;
            }
            if self.alive[j as usize] && !batch.contains(&j) && !holds(j) && disjoint(j) {
                batch.push(j);
            }
        }
        batch
    }

    /// Replaces the patch's cavity by its quads.
    fn apply(&mut self, p: Patch) {
        for &k in &p.cavity {
            self.alive[k as usize] = false;
            for v in self.mesh.quads[k as usize] {
                self.inc[v as usize].retain(|&j| j != k);
            }
        }
        let first = self.mesh.nodes.len() as u32;
        self.mesh.nodes.extend(&p.nodes);
        self.inc.resize(self.mesh.nodes.len(), Vec::new());
        for q in p.quads {
            let q = q.map(|v| {
                if v > NEW - p.nodes.len() as u32 {
                    first + (NEW - v)
                } else {
                    v
                }
            });
            let k = self.mesh.quads.len() as u32;
            self.mesh.quads.push(q);
            self.alive.push(true);
            for v in q {
                self.inc[v as usize].push(k);
            }
        }
    }
}

/// The extraction settings a cavity is meshed with: the caller's, then the
/// other strategy, then the other way to finish (extraction to the end when
/// the caller fills after some layers, the fill after two layers when the
/// caller extracts to the end).
fn candidates(params: &MeshParams) -> Vec<MeshParams> {
    let base = MeshParams {
        max_steps: None,
        ..params.clone()
    };
    let other_strategy = MeshParams {
        strategy: match base.strategy {
            Strategy::A => Strategy::B,
            Strategy::B => Strategy::A,
        },
        ..base.clone()
    };
    let other_finish = MeshParams {
        fill_after_layers: match base.fill_after_layers {
            Some(_) => None,
            None => Some(2),
        },
        ..base.clone()
    };
    vec![base, other_strategy, other_finish]
}

/// [`boundary_loops`] of a cavity's `quads`, found over the cavity's own
/// nodes numbered in the order of their ids (so the loops are the same, in
/// the same order), not over every node of the mesh.
fn cavity_loops(nodes: &[Point], quads: &[[u32; 4]]) -> Option<Vec<Vec<u32>>> {
    let mut ids: Vec<u32> = quads.iter().flatten().copied().collect();
    ids.sort_unstable();
    ids.dedup();
    let local: Vec<[u32; 4]> = quads
        .iter()
        .map(|q| q.map(|v| ids.partition_point(|&u| u < v) as u32))
        .collect();
    let points: Vec<Point> = ids.iter().map(|&v| nodes[v as usize]).collect();
    let loops = boundary_loops(&points, &local).ok()?;
    Some(
        loops
            .into_iter()
            .map(|l| l.into_iter().map(|i| ids[i as usize]).collect())
            .collect(),
    )
}

/// The quads of `mesh` whose [`fitness_of`] is under `bound`, in the order
/// they are taken ([`Priority`], then quad order).
fn bad_quads(mesh: &QuadMesh, bound: f64) -> Vec<(Priority, u32)> {
    let mut bad: Vec<(Priority, u32)> = (0..mesh.quads.len() as u32)
        .map(|k| (priority(mesh, &mesh.quads[k as usize], bound), k))
        .filter(|&(p, _)| p.fitness < bound)
        .collect();
    bad.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.cmp(&b.1)));
    bad
}

/// Remeshes the regions around quads below `finish.remesh.below` (see the
/// module documentation) in a complete mesh, extracting with `model` and
/// `params`, and drops the nodes it removed. A patch is cleaned up (with
/// the sliver bound raised to the remeshing bound) and smoothed with
/// `finish`'s parameters, never remeshed again. Returns the number of
/// regions replaced.
pub fn remesh_bad(
    mesh: &mut QuadMesh,
    model: &Arc<dyn Model>,
    params: &MeshParams,
    finish: &FinishParams,
) -> usize {
    let rp = finish.remesh;
    if rp.below <= 0.0 || rp.max_regions == 0 {
        return 0;
    }
    let bound = rp.below;
    let cands = candidates(params);
    let patch_finish = FinishParams {
        remesh: RemeshParams::OFF,
        coarsen: super::coarsen::CoarsenParams::OFF,
        cleanup: CleanupParams {
            sliver_sj: rp.below.max(finish.cleanup.sliver_sj),
            ..finish.cleanup
        },
        smooth: finish.smooth,
    };
    let old = mesh.quads.len();
    let inc = mesh.node_quads();
    let alive = vec![true; old];
    let mut w = Work { mesh, alive, inc };
    let mut replaced = 0;
    let mut tried = 0;
    let mut work = WORK_PER_QUAD * old + WORK_BASE;
    let mut bad = bad_quads(w.mesh, bound);
    // Regions worked out ahead, on both cores, for the bad quads next in
    // line: each is used only if nothing it read has changed since.
    let mut ahead: BTreeMap<u32, Region> = BTreeMap::new();
    let mut touched: Vec<usize> = vec![0; w.mesh.nodes.len()];
    let ctx = RegionContext {
        rings: rp.rings.max(2),
        model,
        candidates: &cands,
        finish: &patch_finish,
        bound,
    };
    while let Some((_, k)) = (!bad.is_empty()).then(|| bad.remove(0)) {
        if !w.alive[k as usize] || tried >= rp.max_regions || work == 0 {
            continue;
        }
        tried += 1;
        let region = match ahead.remove(&k) {
            Some(r) if r.still_holds(&touched, replaced, work) => r,
            _ => {
                // Regions past the last to be tried would be worked out
                // for nothing.
                let left = rp.max_regions - tried + 1;
                let batch = w.batch(k, &bad, (ctx.rings, left), |j| {
                    ahead
                        .get(&j)
                        .is_some_and(|r| r.still_holds(&touched, replaced, work))
                });
                let mut regions: Vec<Region> = if batch.len() > 1 {
                    let wr = &w;
                    batch
                        .par_iter()
                        .map(|&j| wr.region(j, &ctx, work, replaced))
                        .collect()
                } else {
                    vec![w.region(k, &ctx, work, replaced)]
                };
                let first = regions.remove(0);
                ahead.extend(batch[1..].iter().copied().zip(regions));
                first
            }
        };
        work -= region.cost;
        let chosen = region.chosen;
        let Some(p) = chosen else {
            continue;
        };
        let first_new = w.mesh.quads.len() as u32;
        replaced += 1;
        for &j in &p.cavity {
            for v in w.mesh.quads[j as usize] {
                touched[v as usize] = replaced;
            }
        }
        w.apply(p);
        touched.resize(w.mesh.nodes.len(), replaced);
        // Bad quads the patch made are taken in their turn.
        for j in first_new..w.mesh.quads.len() as u32 {
            let p = priority(w.mesh, &w.mesh.quads[j as usize], bound);
            if p.fitness < bound {
                let at = bad.partition_point(|&(t, i)| t.cmp(&p).then(i.cmp(&j)).is_lt());
                bad.insert(at, (p, j));
            }
        }
    }
    let Work { mesh, alive, .. } = w;
    let former = mesh.retain_quads(&alive);
    if replaced > 0 {
        let patched: Vec<bool> = former.iter().map(|&k| k as usize >= old).collect();
        let only = after_change(mesh, &patched);
        smooth_and_optimize(mesh, &finish.smooth, only.as_deref());
    }
    replaced
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::RulesModel;
    use crate::quality::GOOD_RATIO;

    /// An n × n grid of unit squares; node (i, j) is `j * (n + 1) + i`.
    fn grid(n: usize) -> QuadMesh {
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
        QuadMesh::from_quads(pts, quads).unwrap()
    }

    fn model() -> Arc<dyn Model> {
        Arc::new(RulesModel::DEFAULT)
    }

    /// The meshes of `boundary` under each remeshing setting, and whether
    /// each run's counts say the others would make it again.
    fn under_each_setting(boundary: &Boundary) -> Vec<(QuadMesh, bool)> {
        candidates(&MeshParams::DEFAULT)
            .into_iter()
            .map(|params| {
                let mut m = Mesher::new(boundary.clone(), model(), params);
                while let crate::extract::StepOutcome::Stepped(_) = m.step().expect("a step") {
                    m.check_invariants().expect("invariants after every step");
                }
                assert!(m.is_done());
                (m.mesh().clone(), m.stats().ignores_strategy())
            })
            .collect()
    }

    #[test]
    fn a_band_closed_by_rows_is_the_same_under_every_setting() {
        // A thin ring, 60 nodes outside and 70 on the hole, closed by the
        // band rung in one step: the settings a cavity is tried with
        // cannot change it, so remeshing runs it once.
        let circle = |n: usize, r: f64| -> Vec<Point> {
            (0..n)
                .map(|k| {
                    let t = std::f64::consts::TAU * k as f64 / n as f64;
                    Point::new(r * t.cos(), r * t.sin())
                })
                .collect()
        };
        let mut pts = circle(60, 1.1);
        pts.extend(circle(70, 1.0).into_iter().rev());
        let ring =
            Boundary::new(pts, vec![(0..60).collect(), (60..130).collect()], None).expect("a ring");
        let runs = under_each_setting(&ring);
        assert_eq!(runs.len(), 3);
        for (mesh, blind) in &runs {
            assert!(*blind);
            assert_eq!(mesh, &runs[0].0);
            assert!(!mesh.quads.is_empty());
        }
        // A square of 8 × 8 segments is meshed by the queue, which reads
        // the strategy: its runs are not taken as repeats.
        let mut square = Vec::new();
        for k in 0..32 {
            let t = (k % 8) as f64 / 8.0;
            square.push(match k / 8 {
                0 => Point::new(t, 0.0),
                1 => Point::new(1.0, t),
                2 => Point::new(1.0 - t, 1.0),
                _ => Point::new(0.0, 1.0 - t),
            });
        }
        let square = Boundary::new(square, vec![(0..32).collect()], None).expect("a square");
        assert!(under_each_setting(&square).iter().all(|(_, blind)| !blind));
    }

    #[test]
    fn a_good_mesh_is_left_alone() {
        let mut m = grid(6);
        let before = m.clone();
        assert_eq!(
            remesh_bad(
                &mut m,
                &model(),
                &MeshParams::DEFAULT,
                &FinishParams::DEFAULT
            ),
            0
        );
        assert_eq!(m, before);
    }

    /// Longest over shortest side, worst over the mesh.
    fn worst_stretch(m: &QuadMesh) -> f64 {
        m.quads
            .iter()
            .map(|q| Shape::of(m.corners(q)).side_ratio())
            .fold(0.0, f64::max)
    }

    #[test]
    fn remeshes_a_stretched_region_the_scaled_jacobian_does_not_see() {
        // The interior nodes of column x = 3 of a 6 × 6 grid pushed to
        // x = 2.05: the quads between the two columns are thin rectangles,
        // 20 times as long as wide, with right angles.
        let mut m = grid(6);
        for v in 0..m.nodes.len() {
            let p = m.nodes[v];
            if p.x == 3.0 && p.y > 0.0 && p.y < 6.0 {
                m.nodes[v] = Point::new(2.05, p.y);
            }
        }
        m.check_invariants(true).unwrap();
        assert!(worst_stretch(&m) > 19.0);
        let thin = |m: &QuadMesh| {
            m.quads
                .iter()
                .filter(|q| {
                    let s = Shape::of(m.corners(q));
                    s.scaled_jacobian > 0.99 && s.side_ratio() > GOOD_RATIO
                })
                .count()
        };
        assert_eq!(thin(&m), 4);
        remesh_6x6(&mut m);
        assert_eq!(thin(&m), 0);
        assert!(worst_stretch(&m) <= GOOD_RATIO, "{}", worst_stretch(&m));
    }

    /// Remeshes a distorted 6 × 6 grid with the defaults and checks that
    /// something was remeshed, the mesh is finished, its boundary nodes
    /// stayed and its area is the grid's.
    fn remesh_6x6(m: &mut QuadMesh) {
        let boundary: Vec<Point> = m.nodes[..m.n_boundary()].to_vec();
        let n = remesh_bad(m, &model(), &MeshParams::DEFAULT, &FinishParams::DEFAULT);
        assert!(n >= 1);
        m.check_finished().unwrap();
        assert_eq!(&m.nodes[..m.n_boundary()], &boundary[..]);
        let area: f64 = m
            .quads
            .iter()
            .map(|q| crate::geom::polygon_area(m.corners(q)))
            .sum();
        assert!((area - 36.0).abs() < 1e-9, "{area}");
    }

    #[test]
    fn flattened_quads_are_taken_before_stretched_ones() {
        let shape = |p: [(f64, f64); 4]| Shape::of(p.map(|(x, y)| Point::new(x, y)));
        // A right-angled strip 20 long (fitness 0.35) and a flattened quad
        // (scaled Jacobian about 0.1, a higher fitness).
        let strip = shape([(0.0, 0.0), (20.0, 0.0), (20.0, 1.0), (0.0, 1.0)]);
        let flat = shape([(0.0, 0.0), (1.0, 0.0), (2.0, 0.1), (1.0, 0.1)]);
        let bound = 0.7;
        assert!((fitness_of(&strip, bound) - 0.35).abs() < 1e-12);
        assert!(fitness_of(&flat, bound) < 0.2);
        let p = |s: &Shape| Priority {
            stretched_only: s.scaled_jacobian >= bound,
            fitness: fitness_of(s, bound),
        };
        assert!(p(&flat) < p(&strip));
        // A square is no worse than its scaled Jacobian says.
        let square = shape([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
        assert_eq!(fitness_of(&square, bound), 1.0);
    }

    /// The node of `m` at (`x`, `y`).
    fn node_at(m: &QuadMesh, x: f64, y: f64) -> usize {
        (0..m.nodes.len())
            .find(|&v| m.nodes[v] == Point::new(x, y))
            .unwrap()
    }

    #[test]
    fn remeshes_a_flattened_region() {
        // Two interior nodes of a 6 × 6 grid pushed towards each other:
        // the quad between them is a needle and its neighbours are skewed.
        let mut m = grid(6);
        let (a, b) = (node_at(&m, 3.0, 3.0), node_at(&m, 4.0, 4.0));
        m.nodes[a] = Point::new(3.45, 3.45);
        m.nodes[b] = Point::new(3.55, 3.55);
        m.check_invariants(true).unwrap();
        assert!(m.worst_scaled_jacobian() < 0.2);
        remesh_6x6(&mut m);
        assert!(
            m.worst_scaled_jacobian() >= 0.7,
            "{}",
            m.worst_scaled_jacobian()
        );
    }

    /// A 24 × 24 grid with a needle at each of `at`: the node there moved
    /// almost onto its diagonal neighbour.
    fn needled_grid(at: &[(f64, f64)]) -> QuadMesh {
        let mut m = grid(24);
        for &(x, y) in at {
            let v = node_at(&m, x, y);
            m.nodes[v] = Point::new(x + 0.45, y + 0.45);
        }
        m.check_invariants(true).unwrap();
        m
    }

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    /// [`remesh_bad`] on a copy of `m` with `finish`, on `threads`
    /// threads: the regions patched and the mesh.
    fn remesh_on(m: &QuadMesh, threads: usize, finish: &FinishParams) -> (usize, QuadMesh) {
        let mut mesh = m.clone();
        let n =
            pool(threads).install(|| remesh_bad(&mut mesh, &model(), &MeshParams::DEFAULT, finish));
        (n, mesh)
    }

    /// Regions worked out ahead on several threads give the mesh one
    /// thread gives, byte for byte: a 24 × 24 grid with needles far apart
    /// (worked out together) and two side by side (the second worked out
    /// again after the first is patched).
    #[test]
    fn the_same_mesh_on_one_thread_and_on_several() {
        let m = needled_grid(&[
            (4.0, 4.0),
            (12.0, 4.0),
            (20.0, 4.0),
            (4.0, 14.0),
            (12.0, 14.0),
            (13.0, 14.0),
            (20.0, 20.0),
        ]);
        let on = |threads: usize| remesh_on(&m, threads, &FinishParams::DEFAULT);
        let (n1, one) = on(1);
        assert!(n1 >= 6, "{n1} regions");
        one.check_finished().unwrap();
        assert!(
            one.worst_scaled_jacobian() >= 0.7,
            "{}",
            one.worst_scaled_jacobian()
        );
        for threads in [2, 3] {
            let (n, many) = on(threads);
            assert_eq!(n, n1);
            assert_eq!(many, one, "{threads} threads");
        }
    }

    /// No more regions are worked out together than are still to be
    /// tried, and a cap met while regions were worked out ahead leaves the
    /// mesh one thread gives.
    #[test]
    fn regions_worked_out_ahead_stop_at_the_cap() {
        let m = needled_grid(&[
            (4.0, 4.0),
            (12.0, 4.0),
            (20.0, 4.0),
            (4.0, 14.0),
            (20.0, 20.0),
        ]);
        let batch = |left: usize| {
            let mut mesh = m.clone();
            let alive = vec![true; mesh.quads.len()];
            let inc = mesh.node_quads();
            let w = Work {
                mesh: &mut mesh,
                alive,
                inc,
            };
            let mut bad = bad_quads(w.mesh, FinishParams::DEFAULT.remesh.below);
            let (_, k) = bad.remove(0);
            pool(3).install(|| w.batch(k, &bad, (3, left), |_| false).len())
        };
        // The five needles are far apart: all are worked out together
        // unless fewer are still to be tried.
        assert_eq!(batch(100), 5);
        assert_eq!(batch(2), 2);
        assert_eq!(batch(1), 1);
        let capped = FinishParams {
            remesh: RemeshParams {
                max_regions: 2,
                ..FinishParams::DEFAULT.remesh
            },
            ..FinishParams::DEFAULT
        };
        let (n1, one) = remesh_on(&m, 1, &capped);
        assert_eq!(n1, 2);
        one.check_finished().unwrap();
        for threads in [2, 3] {
            assert_eq!(
                remesh_on(&m, threads, &capped),
                (n1, one.clone()),
                "{threads} threads"
            );
        }
    }

    #[test]
    fn irregular_nodes_are_counted_as_a_patch_would_leave_them() {
        let mut m = grid(4);
        let at = |m: &QuadMesh, x: f64, y: f64| node_at(m, x, y) as u32;
        let centre = at(&m, 2.0, 2.0);
        let ring: Vec<u32> = [
            (1., 1.),
            (2., 1.),
            (3., 1.),
            (3., 2.),
            (3., 3.),
            (2., 3.),
            (1., 3.),
            (1., 2.),
        ]
        .iter()
        .map(|&(x, y)| at(&m, x, y))
        .collect();
        let inc = m.node_quads();
        let alive = vec![true; m.quads.len()];
        let w = Work {
            mesh: &mut m,
            alive,
            inc,
        };
        let cavity: Vec<[u32; 4]> = w.inc[centre as usize]
            .iter()
            .map(|&k| w.mesh.quads[k as usize])
            .collect();
        assert_eq!(w.irregular_before(&cavity), 0);
        // The patch's nodes: the ring's, then the centre as a new one.
        let mut nodes: Vec<Point> = ring.iter().map(|&v| w.mesh.nodes[v as usize]).collect();
        nodes.push(Point::new(2.0, 2.0));
        let same = QuadMesh {
            nodes: nodes.clone(),
            quads: vec![[0, 1, 8, 7], [1, 2, 3, 8], [8, 3, 4, 5], [7, 8, 5, 6]],
            loops: Vec::new(),
        };
        assert_eq!(w.irregular_after(&cavity, &same, &ring), 0);
        // Three quads over the ring: (1, 1) and (3, 3) go to valence 5,
        // (2, 1) and (2, 3) to 3.
        let three = QuadMesh {
            nodes: nodes[..8].to_vec(),
            quads: vec![[0, 1, 2, 3], [4, 5, 6, 7], [0, 3, 4, 7]],
            loops: Vec::new(),
        };
        assert_eq!(w.irregular_after(&cavity, &three, &ring), 4);
    }

    #[test]
    fn off_changes_nothing() {
        let mut m = grid(6);
        m.nodes[24] = Point::new(3.45, 3.45);
        let before = m.clone();
        let finish = FinishParams {
            remesh: RemeshParams::OFF,
            ..FinishParams::DEFAULT
        };
        assert_eq!(
            remesh_bad(&mut m, &model(), &MeshParams::DEFAULT, &finish),
            0
        );
        assert_eq!(m, before);
    }
}

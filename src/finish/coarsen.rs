//! Chord coarsening of a finished mesh: removes closed rows of quads where
//! the mesh runs finer than the size field asks (thesis §1.2: element sizes
//! follow the boundary). Extraction keeps a ring's node count as the ring
//! shrinks around a round hole or inside a disk (its transitions coarsen a
//! row only once it is much finer than the size field), so rows there end
//! up lower than the size field wants, one or two rows too many.
//!
//! A *chord* is a sequence of quads each entered and left through opposite
//! edges (the dual of a row). A closed chord that crosses itself nowhere
//! can be removed whole, as quad-mesh simplification does (Daniels, Silva,
//! Shepherd and Cohen 2008, "poly-chord collapse"): each edge the chord
//! crosses (a *rung*) shrinks to one node, and the two sides of the row
//! close up. A node on both sides of the row keeps its valence, so a row of
//! regular nodes leaves regular nodes: the mesh gets coarser without new
//! irregular nodes, unlike a transition template.
//!
//! A chord is removed when its rungs are on average at most
//! [`CoarsenParams::max_rung`] of the size field, the valences of the nodes
//! it merges come no further from their ideal, and the quads around it,
//! after a few local smoothing sweeps, are convex, no worse in scaled
//! Jacobian than [`CoarsenParams::min_sj`] (or than they were) and at most
//! [`CoarsenParams::max_aspect`] long for their width. Boundary nodes never
//! move; a rung with one boundary end merges into it, one with two is not
//! removed. Chords are taken the lowest first, never two in one round that
//! share a quad's neighbourhood; the caller smooths afterwards.

use serde::{Deserialize, Serialize};

use super::cleanup::ideal_valences;
use crate::geom::{is_measurably_convex, Point};
use crate::mesh::QuadMesh;
use crate::quality::{QuadQuality, Shape};

/// Chord coarsening parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CoarsenParams {
    /// Rounds of coarsening (default 4; 0 turns it off). A round removes
    /// chords that do not touch each other and ends the coarsening when
    /// it removes none.
    pub rounds: usize,
    /// A chord is removed only when its rungs are on average at most this
    /// fraction of the size field at their middles (default 0.9).
    pub max_rung: f64,
    /// The quads around a removed chord must keep at least this scaled
    /// Jacobian, or no less than their worst before (default 0.6).
    pub min_sj: f64,
    /// ... and be at most this many times as long as wide (longest over
    /// shortest edge, default 1.6), or no more than [`ASPECT_SLACK`] times
    /// their worst before.
    pub max_aspect: f64,
}

impl CoarsenParams {
    pub const DEFAULT: CoarsenParams = CoarsenParams {
        rounds: 4,
        max_rung: 0.9,
        min_sj: 0.6,
        max_aspect: 1.6,
    };
    /// No coarsening.
    pub const OFF: CoarsenParams = CoarsenParams {
        rounds: 0,
        ..CoarsenParams::DEFAULT
    };
}

impl Default for CoarsenParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What a coarsening removed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct CoarsenReport {
    /// Chords removed.
    pub chords: usize,
    /// Quads removed with them.
    pub quads: usize,
}

/// The quads around a removed chord may stretch to this many times their
/// worst aspect before (the local sweeps judged here are cruder than the
/// smoothing that follows).
const ASPECT_SLACK: f64 = 1.1;

/// Local smoothing sweeps over a removed chord's neighbourhood before it is
/// judged.
const SWEEPS: usize = 12;

/// A closed chord: its quads in order and, per quad, the rung it leaves by
/// (the edge it shares with the next quad).
struct Chord {
    quads: Vec<u32>,
    rungs: Vec<(u32, u32)>,
}

/// The quad other than `k` with the edge from `b` to `a` (the edge `a → b`
/// of `k` seen from the other side), among `at_a`, the quads at `a`.
fn across(mesh: &QuadMesh, at_a: &[u32], k: u32, a: u32, b: u32) -> Option<(u32, usize)> {
    at_a.iter().copied().find_map(|m| {
        if m == k {
            return None;
        }
        let q = mesh.quads[m as usize];
        (0..4)
            .find(|&j| q[j] == b && q[(j + 1) % 4] == a)
            .map(|j| (m, j))
    })
}

/// Every closed chord that visits no quad twice, each once.
fn closed_chords(mesh: &QuadMesh) -> Vec<Chord> {
    let inc = mesh.node_quads_flat();
    // Per quad, whether each pair of opposite edges has been walked.
    let mut seen = vec![[false; 2]; mesh.quads.len()];
    let mut in_walk = vec![false; mesh.quads.len()];
    let mut out = Vec::new();
    // The walk under way.
    let mut chord = Chord {
        quads: Vec::new(),
        rungs: Vec::new(),
    };
    for k0 in 0..mesh.quads.len() as u32 {
        for p0 in 0..2 {
            if seen[k0 as usize][p0] {
                continue;
            }
            chord.quads.clear();
            chord.rungs.clear();
            let (mut k, mut exit) = (k0, p0 + 2);
            let mut closed = false;
            let mut simple = true;
            loop {
                seen[k as usize][exit % 2] = true;
                simple &= !in_walk[k as usize];
                in_walk[k as usize] = true;
                let q = mesh.quads[k as usize];
                let (a, b) = (q[exit], q[(exit + 1) % 4]);
                chord.quads.push(k);
                chord.rungs.push((a, b));
                let Some((m, j)) = across(mesh, inc.at(a), k, a, b) else {
                    break;
                };
                if m == k0 && j % 2 == p0 {
                    closed = true;
                    break;
                }
                if seen[m as usize][j % 2] {
                    break;
                }
                (k, exit) = (m, (j + 2) % 4);
            }
            for &k in &chord.quads {
                in_walk[k as usize] = false;
            }
            if closed && simple {
                out.push(Chord {
                    quads: chord.quads.clone(),
                    rungs: chord.rungs.clone(),
                });
            }
        }
    }
    out
}

/// The worst scaled Jacobian and aspect of `quads`, and whether all are
/// measurably convex and not thin.
fn judge(mesh: &QuadMesh, quads: &[u32]) -> (f64, f64, bool) {
    quads
        .iter()
        .fold((f64::INFINITY, 0.0f64, true), |(sj, asp, ok), &k| {
            let p = mesh.corners(&mesh.quads[k as usize]);
            let s = Shape::of(p);
            (
                sj.min(s.scaled_jacobian),
                asp.max(s.side_ratio()),
                ok && is_measurably_convex(p) && s.rs >= QuadQuality::THIN_RS,
            )
        })
}

/// The mesh being coarsened: quads with a live flag and each node's quads.
struct Work<'a> {
    mesh: &'a mut QuadMesh,
    nb: usize,
    inc: Vec<Vec<u32>>,
    alive: Vec<bool>,
    ideal: Vec<i32>,
}

impl Work<'_> {
    /// The corners of node `v`'s quads.
    fn neighbours(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.inc[v as usize]
            .iter()
            .flat_map(|&k| self.mesh.quads[k as usize])
    }

    /// Removes `chord` if it passes (see the module documentation).
    fn try_remove(&mut self, chord: &Chord, params: &CoarsenParams) -> bool {
        let nb = self.nb as u32;
        // Each rung's pair of nodes: the survivor (a boundary node, else
        // the lower id) and the node merged into it.
        let mut merges: Vec<(u32, u32)> = Vec::with_capacity(chord.rungs.len());
        for &(a, b) in &chord.rungs {
            if a < nb && b < nb {
                return false;
            }
            merges.push((a.min(b), a.max(b)));
        }
        merges.sort_unstable_by_key(|&(_, m)| m);
        let mut ends: Vec<u32> = merges.iter().flat_map(|&(a, b)| [a, b]).collect();
        ends.sort_unstable();
        if ends.windows(2).any(|w| w[0] == w[1]) {
            return false;
        }
        // Valences: each node of a rung is in two quads of the chord.
        let valence = |v: u32| self.inc[v as usize].len() as i32;
        let dev = |v: u32, val: i32| (val - self.ideal[v as usize]).pow(2);
        let (mut before, mut after) = (0, 0);
        for &(s, m) in &merges {
            before += dev(s, valence(s)) + dev(m, valence(m));
            after += dev(s, valence(s) + valence(m) - 4);
        }
        if after > before {
            return false;
        }
        let mut in_chord = chord.quads.clone();
        in_chord.sort_unstable();
        // The quads around: every live quad at a rung's node, the only
        // quads whose corners change.
        let mut around: Vec<u32> = ends
            .iter()
            .flat_map(|&v| self.inc[v as usize].iter().copied())
            .filter(|k| in_chord.binary_search(k).is_err())
            .collect();
        around.sort_unstable();
        around.dedup();
        let merged_into = |v: u32| {
            merges
                .binary_search_by_key(&v, |&(_, m)| m)
                .map_or(v, |i| merges[i].0)
        };
        // The nodes smoothed: the interior corners of those quads once
        // merged; the quads judged: all of theirs.
        let mut movable: Vec<u32> = around
            .iter()
            .flat_map(|&k| self.mesh.quads[k as usize].map(merged_into))
            .filter(|&v| v >= nb)
            .collect();
        movable.sort_unstable();
        movable.dedup();
        let mut by_survivor = merges.clone();
        by_survivor.sort_unstable();
        let partner = |v: u32| {
            by_survivor
                .binary_search_by_key(&v, |&(s, _)| s)
                .ok()
                .map(|i| by_survivor[i].1)
        };
        let mut judged: Vec<u32> = movable
            .iter()
            .flat_map(|&v| {
                let own = self.inc[v as usize].iter().copied();
                own.chain(
                    partner(v)
                        .into_iter()
                        .flat_map(|m| self.inc[m as usize].iter().copied()),
                )
            })
            .filter(|k| in_chord.binary_search(k).is_err())
            .collect();
        judged.extend(&around);
        judged.sort_unstable();
        judged.dedup();
        let (sj0, asp0, _) = judge(self.mesh, &judged);
        // Tentatively: merge, then smooth the neighbourhood.
        let old_quads: Vec<[u32; 4]> = around
            .iter()
            .map(|&k| self.mesh.quads[k as usize])
            .collect();
        let old_pos: Vec<Point> = movable
            .iter()
            .map(|&v| self.mesh.nodes[v as usize])
            .collect();
        for &(s, m) in &merges {
            if s >= nb {
                self.mesh.nodes[s as usize] =
                    0.5 * (self.mesh.nodes[s as usize] + self.mesh.nodes[m as usize]);
            }
        }
        let mut degenerate = false;
        for &k in &around {
            let q = self.mesh.quads[k as usize].map(merged_into);
            degenerate |= (0..4).any(|i| q[i] == q[(i + 1) % 4] || q[i] == q[(i + 2) % 4]);
            self.mesh.quads[k as usize] = q;
        }
        // A directed edge used twice would make the mesh non-manifold.
        if !degenerate {
            let mut edges: Vec<(u32, u32)> = judged
                .iter()
                .flat_map(|&k| {
                    let q = self.mesh.quads[k as usize];
                    (0..4).map(move |i| (q[i], q[(i + 1) % 4]))
                })
                .collect();
            edges.sort_unstable();
            degenerate = edges.windows(2).any(|w| w[0] == w[1]);
        }
        if !degenerate {
            self.smooth_locally(&judged, &movable);
        }
        let (sj1, asp1, convex) = judge(self.mesh, &judged);
        let ok = !degenerate
            && convex
            && sj1 >= params.min_sj.min(sj0)
            && asp1 <= params.max_aspect.max(ASPECT_SLACK * asp0);
        if !ok {
            for (&k, &q) in around.iter().zip(&old_quads) {
                self.mesh.quads[k as usize] = q;
            }
            for (&v, &p) in movable.iter().zip(&old_pos) {
                self.mesh.nodes[v as usize] = p;
            }
            return false;
        }
        // Commit: the chord's quads go, the merged nodes' quads move to
        // their survivors.
        for &k in &chord.quads {
            self.alive[k as usize] = false;
            for v in self.mesh.quads[k as usize] {
                self.inc[v as usize].retain(|&j| j != k);
            }
        }
        for &(s, m) in &merges {
            let moved = std::mem::take(&mut self.inc[m as usize]);
            self.inc[s as usize].extend(moved);
            self.inc[s as usize].sort_unstable();
        }
        true
    }

    /// Jacobi sweeps moving each of `nodes` (sorted) to the mean of its
    /// neighbours along the edges of `quads`, which hold all their quads.
    fn smooth_locally(&mut self, quads: &[u32], nodes: &[u32]) {
        let mut sum = vec![(Point::ZERO, 0.0); nodes.len()];
        let slot = |v: u32| nodes.binary_search(&v).ok();
        for _ in 0..SWEEPS {
            sum.iter_mut().for_each(|s| *s = (Point::ZERO, 0.0));
            for &k in quads {
                let q = self.mesh.quads[k as usize];
                for i in 0..4 {
                    if let Some(j) = slot(q[i]) {
                        for n in [q[(i + 1) % 4], q[(i + 3) % 4]] {
                            sum[j].0 += self.mesh.nodes[n as usize];
                            sum[j].1 += 1.0;
                        }
                    }
                }
            }
            for (&v, &(s, n)) in nodes.iter().zip(&sum) {
                if n > 0.0 {
                    self.mesh.nodes[v as usize] = s / n;
                }
            }
        }
    }
}

/// Coarsens a complete mesh in place by removing closed chords (see the
/// module documentation) against the size field `size`, and drops the
/// nodes it merged away.
pub fn coarsen(
    mesh: &mut QuadMesh,
    size: impl Fn(Point) -> f64,
    params: &CoarsenParams,
) -> CoarsenReport {
    let mut report = CoarsenReport::default();
    for _ in 0..params.rounds {
        let mut chords: Vec<(f64, Chord)> = closed_chords(mesh)
            .into_iter()
            .filter_map(|c| {
                let rel = c
                    .rungs
                    .iter()
                    .map(|&(a, b)| {
                        let (pa, pb) = (mesh.nodes[a as usize], mesh.nodes[b as usize]);
                        pa.distance(pb) / size(0.5 * (pa + pb))
                    })
                    .sum::<f64>()
                    / c.rungs.len() as f64;
                (rel <= params.max_rung).then_some((rel, c))
            })
            .collect();
        if chords.is_empty() {
            break;
        }
        chords.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.quads[0].cmp(&b.1.quads[0])));
        let mut w = Work {
            nb: mesh.n_boundary(),
            alive: vec![true; mesh.quads.len()],
            ideal: ideal_valences(mesh),
            inc: mesh.node_quads(),
            mesh,
        };
        // Nodes near a chord removed this round: a chord touching them
        // waits for the next round's fresh look.
        let mut claimed = vec![false; w.mesh.nodes.len()];
        let mut removed = 0;
        for (_, chord) in &chords {
            let ends = || chord.rungs.iter().flat_map(|&(a, b)| [a, b]);
            if ends().any(|v| w.neighbours(v).any(|u| claimed[u as usize])) {
                continue;
            }
            if !w.try_remove(chord, params) {
                continue;
            }
            removed += 1;
            report.quads += chord.quads.len();
            // Two rings around the merged nodes.
            let mut ring: Vec<u32> = ends().flat_map(|v| w.neighbours(v)).collect();
            ring.sort_unstable();
            ring.dedup();
            for u in ring {
                let second: Vec<u32> = w.neighbours(u).collect();
                for x in second {
                    claimed[x as usize] = true;
                }
            }
        }
        let alive = std::mem::take(&mut w.alive);
        report.chords += removed;
        mesh.retain_quads(&alive);
        if removed == 0 {
            break;
        }
    }
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A polar grid over the annulus between radii 1 and 2: `around`
    /// quads a ring, `rings` rings. Node ids: the outer loop (CCW), the
    /// inner loop (CW), then the rings between, inside out.
    fn annulus(around: usize, rings: usize) -> QuadMesh {
        let mut id = vec![vec![0u32; around]; rings + 1];
        let mut nodes = Vec::new();
        let mut place = |j: usize, i: usize, nodes: &mut Vec<Point>| {
            let (r, t) = (
                1.0 + j as f64 / rings as f64,
                std::f64::consts::TAU * i as f64 / around as f64,
            );
            id[j][i] = nodes.len() as u32;
            nodes.push(Point::new(r * t.cos(), r * t.sin()));
        };
        for i in 0..around {
            place(rings, i, &mut nodes);
        }
        for i in (0..around).rev() {
            place(0, i, &mut nodes);
        }
        for j in 1..rings {
            for i in 0..around {
                place(j, i, &mut nodes);
            }
        }
        let mut quads = Vec::new();
        for j in 0..rings {
            for i in 0..around {
                let n = (i + 1) % around;
                quads.push([id[j][i], id[j + 1][i], id[j + 1][n], id[j][n]]);
            }
        }
        QuadMesh {
            nodes,
            quads,
            loops: vec![
                (0..around as u32).collect(),
                (around as u32..2 * around as u32).collect(),
            ],
        }
    }

    fn irregular_interior(mesh: &QuadMesh) -> usize {
        let nb = mesh.n_boundary();
        mesh.node_quads()
            .iter()
            .enumerate()
            .filter(|&(v, q)| v >= nb && q.len() != 4)
            .count()
    }

    #[test]
    fn closed_chords_of_a_polar_grid_are_its_rings() {
        let mesh = annulus(24, 5);
        let chords = closed_chords(&mesh);
        assert_eq!(chords.len(), 5);
        assert!(chords.iter().all(|c| c.quads.len() == 24));
        // Each rung is a radial edge: its ends lie on neighbouring rings.
        for c in &chords {
            for &(a, b) in &c.rungs {
                let (ra, rb) = (
                    mesh.nodes[a as usize].length(),
                    mesh.nodes[b as usize].length(),
                );
                assert!(((ra - rb).abs() - 0.2).abs() < 1e-9, "{ra} {rb}");
            }
        }
    }

    #[test]
    fn rows_lower_than_the_size_field_are_removed_and_stay_regular() {
        // 32 around at radius 1.5 is about 0.29 wide; rows 0.125 high
        // against a size of 0.3: rungs at 0.42 of the size.
        let mut mesh = annulus(32, 8);
        let boundary: Vec<Point> = mesh.nodes[..mesh.n_boundary()].to_vec();
        let report = coarsen(&mut mesh, |_| 0.3, &CoarsenParams::DEFAULT);
        assert!(report.chords > 0, "{report:?}");
        assert_eq!(report.quads, 32 * report.chords);
        assert_eq!(mesh.quads.len(), 32 * (8 - report.chords));
        mesh.check_invariants(true).unwrap();
        assert_eq!(&mesh.nodes[..mesh.n_boundary()], &boundary[..]);
        assert_eq!(irregular_interior(&mesh), 0);
        // Rows are removed only while they are lower than 0.9 of the
        // size: the rows left are not all that low, and not fewer than
        // the size asks for.
        let rows = 8 - report.chords;
        assert!(1.0 / rows as f64 > 0.9 * 0.3, "{rows} rows left");
        assert!(rows >= 3, "{rows} rows left");
        // Deterministic.
        let mut again = annulus(32, 8);
        coarsen(&mut again, |_| 0.3, &CoarsenParams::DEFAULT);
        assert_eq!(again, mesh);
    }

    #[test]
    fn rows_as_high_as_the_size_field_stay() {
        let mut mesh = annulus(32, 8);
        let before = mesh.clone();
        let report = coarsen(&mut mesh, |_| 0.125 / 0.95, &CoarsenParams::DEFAULT);
        assert_eq!(report, CoarsenReport::default());
        assert_eq!(mesh, before);
        let off = coarsen(&mut mesh, |_| 10.0, &CoarsenParams::OFF);
        assert_eq!(off, CoarsenReport::default());
        assert_eq!(mesh, before);
    }

    #[test]
    fn a_grid_has_no_closed_chord() {
        let (nodes, quads) = super::super::cleanup::tests::grid(6);
        let mesh = QuadMesh {
            nodes,
            quads,
            loops: Vec::new(),
        };
        assert!(closed_chords(&mesh).is_empty());
    }
}

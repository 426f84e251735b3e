//! Mapped closure: a front loop that is a logical rectangle is closed in
//! one step by a structured grid (the mapping transformations of thesis
//! §1.1, used as a final pattern in the sense of §2.1.4).
//!
//! A loop is a logical rectangle when it has exactly four corners (front
//! angles under [`CORNER_MAX`]), every other node lies on a side that
//! turns by at most [`SIDE_TURN`] at it, and opposite sides have the same
//! number of edges `m × n`. Where the narrower way is at most
//! [`MeshParams::mapped_rows`](super::MeshParams::mapped_rows) elements
//! across, the loop is closed by transfinite interpolation (a discrete
//! Coons patch over the sides' arc-length fractions): the strip left where
//! two fronts meet becomes one clean row (paving's row closure), and a
//! rectangle whose sides are divided unevenly (13 × 4 segments on a 50 × 1
//! plate) gets its grid instead of rows from the long sides that cannot
//! match. The grid is taken only if every quad is convex with a scaled
//! Jacobian of at least [`MappedTuning::min_sj`](super::tuning::MappedTuning::min_sj) and no other loop lies inside.
//!
//! With [`MappedTuning::graded_grid`](super::tuning::MappedTuning::graded_grid)
//! on (it is off by default), a loop of the given boundary graded past
//! [`GRADED_SPREAD`] (a side graded 1:100 towards a corner) gets its
//! [`transfinite`] grid whatever its width, as a Gmsh transfinite surface
//! would: the columns carry the grading across, as slivers where the other
//! sides are spaced evenly. By default such a loop is left to extraction,
//! whose corner fans and transitions coarsen the grading within a few rows.

use super::closure::{is_pinched, LoopGeometry};
use super::report::{StepKind, StepReport};
use super::session::Mesher;
use crate::geom::{is_measurably_convex, Point};
use crate::mapped::coons;
use crate::quality::Shape;

/// A node whose front angle is under this (degrees) is a corner.
pub const CORNER_MAX: f64 = 150.0;
/// A node on a side may turn the side by at most this (degrees) either way.
pub const SIDE_TURN: f64 = 35.0;

/// The mapped rungs' state: per loop, the
/// [`crate::front::FrontLoop::version`] last looked at for a mapped grid
/// (`mapped`) and for a strip's best grid (`strip`); 0: never.
#[derive(Clone, Debug, Default)]
pub(super) struct GridsSeen {
    mapped: Vec<u32>,
    strip: Vec<u32>,
}

/// A structured grid over a logical rectangle: `m × n` quads, the nodes
/// `(i, j)` for `0 ≤ i ≤ m`, `0 ≤ j ≤ n`, row by row.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub m: usize,
    pub n: usize,
    /// Index into the loop of each boundary node, `None` inside.
    pub at: Vec<Option<usize>>,
    /// Position of every node.
    pub points: Vec<Point>,
}

impl Grid {
    fn index(&self, i: usize, j: usize) -> usize {
        j * (self.m + 1) + i
    }

    /// The quads, as node indices of the grid, counter-clockwise.
    pub fn quads(&self) -> impl Iterator<Item = [usize; 4]> + '_ {
        (0..self.n).flat_map(move |j| {
            (0..self.m).map(move |i| {
                [
                    self.index(i, j),
                    self.index(i + 1, j),
                    self.index(i + 1, j + 1),
                    self.index(i, j + 1),
                ]
            })
        })
    }

    /// The worst scaled Jacobian of its quads, or `None` if one is not
    /// measurably convex.
    pub fn min_sj(&self) -> Option<f64> {
        let mut worst = f64::INFINITY;
        for q in self.quads() {
            let c = q.map(|k| self.points[k]);
            if !is_measurably_convex(c) {
                return None;
            }
            worst = worst.min(Shape::of(c).scaled_jacobian);
        }
        Some(worst)
    }
}

/// The turn of a closed loop at node `k`: the cosine of the angle between
/// the edges into and out of it, and whether it turns left (a convex node
/// of a counter-clockwise loop); `None` at an edge of length zero.
fn turn(pts: &[Point], k: usize) -> Option<(f64, bool)> {
    let n = pts.len();
    let a = pts[k] - pts[(k + n - 1) % n];
    let b = pts[(k + 1) % n] - pts[k];
    let (la, lb) = (a.length(), b.length());
    if la <= 0.0 || lb <= 0.0 {
        return None;
    }
    Some((a.dot(b) / (la * lb), a.perp_dot(b) > 0.0))
}

/// The four corners of a counter-clockwise loop (indices, in loop order),
/// if it is a logical rectangle whose opposite sides have equal edge
/// counts, rotated so that the first side is the longer way (ties: the
/// first corner in loop order).
pub fn rectangle(pts: &[Point]) -> Option<[usize; 4]> {
    let n = pts.len();
    if n < 4 || n % 2 == 1 {
        return None;
    }
    let corner_cos = (180.0 - CORNER_MAX).to_radians().cos();
    let side_cos = SIDE_TURN.to_radians().cos();
    let mut corners = [0usize; 4];
    let mut found = 0;
    for k in 0..n {
        let (cos, left) = turn(pts, k)?;
        if left && cos < corner_cos {
            if found == 4 {
                return None;
            }
            corners[found] = k;
            found += 1;
        } else if cos < side_cos {
            return None;
        }
    }
    if found != 4 {
        return None;
    }
    let side = |t: usize| (corners[(t + 1) % 4] + n - corners[t]) % n;
    let (m1, m2, m3, m4) = (side(0), side(1), side(2), side(3));
    if m1 != m3 || m2 != m4 {
        return None;
    }
    let start = if m2 > m1 { 1 } else { 0 };
    Some(std::array::from_fn(|t| corners[(t + start) % 4]))
}

/// The transfinite-interpolation grid of a loop (counter-clockwise) over
/// its four `corners` (from [`rectangle`]).
pub fn grid(pts: &[Point], corners: [usize; 4]) -> Grid {
    let len = pts.len();
    let m = (corners[1] + len - corners[0]) % len;
    let n = (corners[2] + len - corners[1]) % len;
    let idx = |t: usize| (corners[0] + t) % len;
    // Loop positions of the four sides, each from its grid origin.
    let bottom: Vec<usize> = (0..=m).map(idx).collect();
    let right: Vec<usize> = (0..=n).map(|j| idx(m + j)).collect();
    let top: Vec<usize> = (0..=m).map(|i| idx(2 * m + n - i)).collect();
    let left: Vec<usize> = (0..=n).map(|j| idx((2 * m + 2 * n - j) % len)).collect();
    let fractions = |side: &[usize]| -> Vec<f64> {
        let mut acc = vec![0.0];
        for w in side.windows(2) {
            let d = pts[w[0]].distance(pts[w[1]]);
            acc.push(acc[acc.len() - 1] + d);
        }
        let total = acc[acc.len() - 1];
        let steps = (side.len() - 1) as f64;
        acc.iter()
            .enumerate()
            .map(|(k, &a)| {
                if total > 0.0 {
                    a / total
                } else {
                    k as f64 / steps
                }
            })
            .collect()
    };
    let (ub, ut) = (fractions(&bottom), fractions(&top));
    let (vl, vr) = (fractions(&left), fractions(&right));
    let (c00, c10, c11, c01) = (pts[bottom[0]], pts[bottom[m]], pts[top[m]], pts[top[0]]);
    let mut at = Vec::with_capacity((m + 1) * (n + 1));
    let mut points = Vec::with_capacity((m + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=m {
            let on = if j == 0 {
                Some(bottom[i])
            } else if j == n {
                Some(top[i])
            } else if i == 0 {
                Some(left[j])
            } else if i == m {
                Some(right[j])
            } else {
                None
            };
            at.push(on);
            if let Some(k) = on {
                points.push(pts[k]);
                continue;
            }
            // u and v where the lines of constant i and j cross: u runs
            // from the bottom's fraction to the top's, v from the left's
            // to the right's.
            let (du, dv) = (ut[i] - ub[i], vr[j] - vl[j]);
            let u = (ub[i] + vl[j] * du) / (1.0 - du * dv);
            let v = vl[j] + u * dv;
            let sides = [pts[bottom[i]], pts[top[i]], pts[left[j]], pts[right[j]]];
            points.push(coons(u, v, sides, [c00, c10, c11, c01]));
        }
    }
    Grid { m, n, at, points }
}

/// The logical rectangle over a counter-clockwise loop, corners chosen
/// anywhere, whose grid is best: at most `across` elements the narrow way,
/// every quad measurably convex, the highest worst scaled Jacobian. Ties
/// go to the first corners in loop order. `None` for an odd loop or when
/// no choice gives a convex grid.
///
/// This is the grid of a strip whose ends are not at corners the side
/// test of [`rectangle`] accepts: a hole a fiftieth of a segment from the
/// outer side leaves a strip whose ends are a near-flat node on one side
/// and a reflex corner of the hole on the other.
pub fn best_strip(pts: &[Point], across: usize) -> Option<(Grid, f64)> {
    let len = pts.len();
    if len < 4 || len % 2 == 1 {
        return None;
    }
    let half = len / 2;
    let choices = (1..=across.min(half / 2)).flat_map(|b| {
        let a = half - b;
        (0..len)
            .map(move |start| [start, start + a, start + a + b, start + 2 * a + b].map(|k| k % len))
    });
    best_grid(pts, choices)
}

/// The grid over `pts` with the highest worst scaled Jacobian among the
/// `choices` of corners whose grids are measurably convex (ties: the
/// first), with that worst.
fn best_grid(pts: &[Point], choices: impl Iterator<Item = [usize; 4]>) -> Option<(Grid, f64)> {
    let mut best: Option<(Grid, f64)> = None;
    for corners in choices {
        let g = grid(pts, corners);
        let Some(sj) = g.min_sj() else {
            continue;
        };
        if best.as_ref().is_none_or(|(_, worst)| sj > *worst) {
            best = Some((g, sj));
        }
    }
    best
}

/// Nodes at most this many may be a [`transfinite`] loop's corner
/// candidates (every choice of four is tried).
pub const TRANSFINITE_CANDIDATES: usize = 8;

/// A loop of the given boundary whose longest segment is over this many
/// times its shortest is strongly graded: with
/// [`MappedTuning::graded_grid`](super::tuning::MappedTuning::graded_grid)
/// on, it gets its [`transfinite`] grid when it has one.
pub const GRADED_SPREAD: f64 = crate::quality::GOOD_RATIO;

/// Longest over shortest segment of a closed loop.
pub fn segment_spread(pts: &[Point]) -> f64 {
    let n = pts.len();
    let (lo, hi) = (0..n).fold((f64::INFINITY, 0.0_f64), |(lo, hi), k| {
        let d = pts[k].distance(pts[(k + 1) % n]);
        (lo.min(d), hi.max(d))
    });
    hi / lo.max(f64::MIN_POSITIVE)
}

/// The transfinite grid of a counter-clockwise loop whose sides may bend
/// (Gmsh's transfinite surface): four corners chosen among the convex
/// nodes that turn the loop by at least `180° − CORNER_MAX` (at most
/// [`TRANSFINITE_CANDIDATES`] of them), opposite sides of equal edge
/// counts, the grid's quads all measurably convex, and the highest worst
/// scaled Jacobian among such choices (ties: the first corners in loop
/// order). Its columns follow the sides' grading from one side to the
/// other. `None` when no choice gives one.
pub fn transfinite(pts: &[Point]) -> Option<(Grid, f64)> {
    let n = pts.len();
    if n < 4 || n % 2 == 1 {
        return None;
    }
    let corner_cos = (180.0 - CORNER_MAX).to_radians().cos();
    let mut candidates = Vec::new();
    for k in 0..n {
        let (cos, left) = turn(pts, k)?;
        if left && cos < corner_cos {
            candidates.push(k);
        }
    }
    if !(4..=TRANSFINITE_CANDIDATES).contains(&candidates.len()) {
        return None;
    }
    let c = &candidates;
    let k = c.len();
    let choices = (0..k).flat_map(|a| {
        (a + 1..k).flat_map(move |b| {
            (b + 1..k).flat_map(move |d| (d + 1..k).map(move |e| [c[a], c[b], c[d], c[e]]))
        })
    });
    let matched = choices.filter(|corners| {
        let side = |t: usize| (corners[(t + 1) % 4] + n - corners[t]) % n;
        side(0) == side(2) && side(1) == side(3)
    });
    best_grid(pts, matched)
}

impl Mesher {
    /// Closes loop `lid` by a mapped grid, if it is a logical rectangle at
    /// most [`MeshParams::mapped_rows`](super::MeshParams::mapped_rows)
    /// across whose grid is good enough, or (with
    /// [`MappedTuning::graded_grid`](super::tuning::MappedTuning::graded_grid)
    /// on) a loop of the given boundary graded past [`GRADED_SPREAD`] whose
    /// [`transfinite`] grid is.
    pub(super) fn close_mapped(&mut self, lid: u32) -> Option<StepReport> {
        let (rows, (slots, nodes, pts)) = self.grid_loop(lid, |m| &mut m.grids.mapped)?;
        let min_sj = self.params.tuning.mapped.min_sj;
        let narrow = rectangle(&pts)
            .map(|corners| grid(&pts, corners))
            .filter(|g| g.n <= rows && g.min_sj().is_some_and(|sj| sj >= min_sj));
        let g = match narrow {
            Some(g) => g,
            None => {
                let given = nodes.iter().all(|&v| self.is_boundary(v));
                if !self.params.tuning.mapped.graded_grid
                    || !given
                    || segment_spread(&pts) <= GRADED_SPREAD
                {
                    return None;
                }
                let (g, sj) = transfinite(&pts)?;
                if sj < min_sj {
                    return None;
                }
                g
            }
        };
        if !self.loop_is_clear(&slots, &nodes, &pts) {
            return None;
        }
        Some(self.commit_grid(lid, &nodes, &g))
    }

    /// Closes loop `lid`, which no step could reduce, by its
    /// [`best_strip`] at most
    /// [`MeshParams::mapped_rows`](super::MeshParams::mapped_rows) across.
    /// Its worst quad must reach [`MappedTuning::strip_sj`](super::tuning::MappedTuning::strip_sj), unless every node of the loop
    /// is a node of the given boundary: then nothing extraction could do
    /// would move them, a fill would meet the same skew, and a convex grid
    /// is taken.
    pub(super) fn close_strip(&mut self, lid: u32) -> Option<StepReport> {
        let (rows, (slots, nodes, pts)) = self.grid_loop(lid, |m| &mut m.grids.strip)?;
        let (g, sj) = best_strip(&pts, rows)?;
        let fixed = nodes.iter().all(|&v| self.is_boundary(v));
        if (sj < self.params.tuning.mapped.strip_sj && !fixed)
            || !self.loop_is_clear(&slots, &nodes, &pts)
        {
            return None;
        }
        let mut r = self.commit_grid(lid, &nodes, &g);
        r.remedy = super::report::Remedy::RuleBased;
        Some(r)
    }

    /// True when loop `lid` is alive, of a size a mapped grid may close,
    /// and changed since [`Mesher::close_mapped`] last looked at it: what
    /// [`Mesher::grid_loop`] asks first, without its call.
    #[inline]
    pub(super) fn grid_unseen(&self, lid: u32) -> bool {
        let l = &self.front.loops[lid as usize];
        l.alive
            && (8..=self.params.tuning.mapped.max_loop).contains(&l.len)
            && self.grids.mapped.get(lid as usize) != Some(&l.version)
    }

    /// The rows a grid may have across and loop `lid`'s slots, nodes and
    /// points, if the loop is to be looked at for a grid: mapping is on,
    /// the loop has 8 to [`MappedTuning::max_loop`](super::tuning::MappedTuning::max_loop) nodes, is not pinched, and has
    /// changed since it was last looked at (`seen` picks the record: per
    /// loop, the version last looked at, 0 for none; updated here).
    fn grid_loop(
        &mut self,
        lid: u32,
        seen: fn(&mut Mesher) -> &mut Vec<u32>,
    ) -> Option<(usize, LoopGeometry)> {
        let rows = self.params.mapped_rows?;
        let l = self.front.loops[lid as usize];
        if !(8..=self.params.tuning.mapped.max_loop).contains(&l.len) {
            return None;
        }
        let (k, seen) = (lid as usize, seen(self));
        if seen.get(k) == Some(&l.version) {
            return None;
        }
        if seen.len() <= k {
            seen.resize(k + 1, 0);
        }
        seen[k] = l.version;
        let (slots, nodes, pts) = self.loop_geometry(lid);
        if is_pinched(&nodes) {
            return None;
        }
        Some((rows, (slots, nodes, pts)))
    }

    /// Meshes loop `lid` (its `nodes`) by the grid `g` over it and removes
    /// the loop from the front.
    fn commit_grid(&mut self, lid: u32, nodes: &[u32], g: &Grid) -> StepReport {
        let mut r = self.report(StepKind::Mapped);
        let ids: Vec<u32> = (0..g.points.len())
            .map(|k| match g.at[k] {
                Some(t) => nodes[t],
                None => {
                    let v = self.add_node(g.points[k]);
                    r.new_nodes.push(v);
                    v
                }
            })
            .collect();
        for q in g.quads() {
            let quad = q.map(|k| ids[k]);
            self.push_quad(quad);
            r.quads.push(quad);
        }
        r.reference = g.at[0].map(|t| nodes[t]);
        self.front.remove_loop(lid);
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rectangle `w × h` with `m × n` edges, counter-clockwise from the
    /// origin.
    fn rect(w: f64, h: f64, m: usize, n: usize) -> Vec<Point> {
        let mut p = Vec::new();
        for i in 0..m {
            p.push(Point::new(w * i as f64 / m as f64, 0.0));
        }
        for j in 0..n {
            p.push(Point::new(w, h * j as f64 / n as f64));
        }
        for i in 0..m {
            p.push(Point::new(w * (m - i) as f64 / m as f64, h));
        }
        for j in 0..n {
            p.push(Point::new(0.0, h * (n - j) as f64 / n as f64));
        }
        p
    }

    /// A loop looked at for a grid is not looked at again until it
    /// changes.
    #[test]
    fn a_loop_looked_at_for_a_grid_is_looked_at_again_once_changed() {
        let ring: Vec<Point> = (0..12)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 12.0;
                Point::new(t.cos(), t.sin())
            })
            .collect();
        let mut m = Mesher::of_loop(ring);
        assert!(m.grid_unseen(0));
        assert!(m.close_mapped(0).is_none(), "a ring has no corners");
        assert!(!m.grid_unseen(0));
        // One of its edges filed anew: the loop may have changed.
        let s = m.front.loops[0].head;
        let node = m.front.node(s);
        m.front.refile_edges_at(s, node, &m.mesh.nodes);
        assert!(m.grid_unseen(0));
    }

    #[test]
    fn a_plate_of_13_by_4_segments_is_its_grid() {
        let p = rect(50.0, 1.0, 13, 4);
        let c = rectangle(&p).unwrap();
        assert_eq!(c, [0, 13, 17, 30]);
        let g = grid(&p, c);
        assert_eq!((g.m, g.n), (13, 4));
        assert_eq!(g.quads().count(), 52);
        assert!((g.min_sj().unwrap() - 1.0).abs() < 1e-12);
        // Interior nodes on the straight lines between the sides' nodes.
        let k = g.index(5, 2);
        assert!(g.at[k].is_none());
        let q = g.points[k];
        assert!((q.x - 50.0 * 5.0 / 13.0).abs() < 1e-9 && (q.y - 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_longer_way_comes_first() {
        let p = rect(1.0, 8.0, 2, 9);
        let c = rectangle(&p).unwrap();
        let g = grid(&p, c);
        assert_eq!((g.m, g.n), (9, 2));
        assert_eq!(g.quads().count(), 18);
    }

    #[test]
    fn unequal_sides_odd_loops_and_reflex_nodes_are_not_rectangles() {
        // 3 edges below, 1 above.
        let mut p = rect(3.0, 1.0, 3, 1);
        p.remove(6);
        p.remove(5);
        assert_eq!(p.len(), 6);
        assert!(rectangle(&p).is_none());
        // An L-shape: a reflex corner.
        let l = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .map(|(x, y)| Point::new(x, y));
        assert!(rectangle(&l).is_none());
        assert!(rectangle(&rect(1.0, 1.0, 2, 1)[..5]).is_none());
    }

    #[test]
    fn graded_sides_keep_their_spacing_inside() {
        // Bottom and top graded alike: the columns follow them.
        let xs = [0.0, 0.1, 0.3, 0.6, 1.0];
        let mut p: Vec<Point> = xs[..4].iter().map(|&x| Point::new(x, 0.0)).collect();
        p.extend([Point::new(1.0, 0.0), Point::new(1.0, 0.5)]);
        p.extend(xs[1..].iter().rev().map(|&x| Point::new(x, 1.0)));
        p.extend([Point::new(0.0, 1.0), Point::new(0.0, 0.5)]);
        assert_eq!(p.len(), 12);
        let c = rectangle(&p).unwrap();
        let g = grid(&p, c);
        assert_eq!((g.m, g.n), (4, 2));
        for (i, &x) in xs.iter().enumerate() {
            assert!((g.points[g.index(i, 1)].x - x).abs() < 1e-12);
        }
    }

    #[test]
    fn a_strip_whose_end_is_no_corner_gets_its_best_grid() {
        // One row 0.3 high: four edges below, four above, the top running
        // on past the bottom's start so that (0, 0) turns by 17° only.
        let p = [
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (3., 0.),
            (4., 0.),
            (4., 0.3),
            (3., 0.3),
            (2., 0.3),
            (1., 0.3),
            (-1., 0.3),
        ]
        .map(|(x, y)| Point::new(x, y));
        assert!(rectangle(&p).is_none());
        let (g, sj) = best_strip(&p, 4).unwrap();
        assert_eq!((g.m, g.n), (4, 1));
        assert_eq!(g.at[0], Some(0));
        assert!(g.at.iter().all(Option::is_some));
        // Its worst quad is the one at (0, 0): sin(180° - 16.7°).
        assert!((sj - 0.3 / 1.09f64.sqrt()).abs() < 1e-9, "{sj}");
        // An odd loop has no grid.
        assert!(best_strip(&p[..9], 4).is_none());
    }
}

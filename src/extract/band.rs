//! Band closure: a front that is a thin band is closed in one step by rows
//! laid along it (the mapping transformations of thesis §1.1 used as a final
//! pattern in the sense of §2.1.4, generalised from [`super::mapped`]'s
//! logical rectangles to bands whose two sides have unequal node counts).
//!
//! A band is either one loop with two long sides facing each other and two
//! short ends (four corners, the ends at most [`BandTuning::max_end`]
//! segments, sides of unequal counts or unequal ends: equal ones are the
//! mapped grid's), or the ring between the two loops that are all the front
//! holds (an electric machine's air gap). It is thin when its mean width,
//! twice its area over its perimeter, is at most
//! [`BandTuning::max_rows`] (and a half) of its mean segment length.
//!
//! Element by element, two fronts this close meet in collisions that knot:
//! the counts of the two sides differ, and every place where a row gives
//! out leaves an irregular node, often a sliver. Here the band gets rows:
//! a ring its width over its spacing (at least two when the counts
//! differ), a loop as many as its ends' segments (two for ends of one
//! segment). The inner lines follow the finer side's nodes, at even
//! fractions of the way across over their feet on the other side, and
//! take the other side's count where it is locally finer; the row beside
//! each side takes the difference by wedges (a quad with one corner on the
//! side and two edges on the inner line), spread along the band where the
//! lines' arc-length fractions drift apart. A wedge's middle node is moved
//! away from its corner, so the wedge is convex there. An end of one
//! segment with two rows hands the inner line to the finer side's corner.
//! Each wedge leaves one irregular interior node (valence 3); everything
//! else is regular. Each inner node then moves to the mean of the nodes
//! facing it across the row below and across the row above, so that where
//! the sides' nodes are offset the rows share the skew rather than the row
//! beside the side the lines do not follow taking all of it. The inner
//! nodes are smoothed among themselves, the band's own nodes held.
//!
//! A ring whose sides' counts differ, at most three rows wide, gets three
//! rows where they fit: its two rows' inner line is split in two
//! ([`ring_rows_split`]), each row's nodes squeezed towards its side, so
//! the wedges stay in the rows beside the sides and the middle row is a
//! clean strip (a rotating machine's sliding band). The irregular nodes
//! are the same, the interior nodes twice as many.
//!
//! The rows are taken only if every quad is measurably convex with a
//! scaled Jacobian of at least [`BandTuning::min_sj`], and the quads do not
//! fold over one another (their areas add up to the band's).

use super::closure::is_pinched;
use super::report::{StepKind, StepReport};
use super::session::Mesher;
use super::tuning::BandTuning;
use crate::geom::{is_measurably_convex, polygon_area, Point};
use crate::mesh::QuadMesh;
use crate::quality::Shape;
use crate::smooth::{smooth_and_optimize, SmoothParams};

/// A node's front angle under this (degrees) makes it a corner of a band.
const CORNER_MAX: f64 = 150.0;

/// The rows of a ring whose sides' counts differ: a row of wedges beside
/// each side and a clean row between them.
const RING_ROWS: usize = 3;

/// The quads of a band may cover this much more than its area (relative)
/// before they are taken to fold over one another: rounding only.
const FOLD_TOLERANCE: f64 = 1e-9;

/// Sweeps per row of the placement across the band ([`across`]).
const ACROSS_SWEEPS: usize = 4;

/// How far a wedge's middle node moves away from its corner (a fraction
/// of the distance between them), so the wedge is convex there.
const WEDGE_LIFT: f64 = 0.35;

/// The band's sides, as indices into the points given to [`band_rows`]:
/// `a` and `b` run the same way along the band. An open band's end 1 joins
/// `a[0]` to `b[0]` through the nodes `ends.0` (from the `a` side), end 2
/// joins the last nodes through `ends.1`; a ring's sides are cycles.
#[derive(Clone, Debug)]
pub struct BandSides {
    pub a: Vec<usize>,
    pub b: Vec<usize>,
    pub ends: Option<(Vec<usize>, Vec<usize>)>,
}

/// The rows over a band: new interior points (numbered after the given
/// ones) and quads, counter-clockwise, over both.
#[derive(Clone, Debug)]
pub struct BandRows {
    pub points: Vec<Point>,
    pub quads: Vec<[usize; 4]>,
}

/// Cumulative arc-length fractions along `idx` (a cycle when `ring`: the
/// fraction of node `k` from node 0, the last edge back included in the
/// total).
fn fractions(pts: &[Point], idx: &[usize], ring: bool) -> Vec<f64> {
    let mut f = Vec::with_capacity(idx.len());
    let mut s = 0.0;
    f.push(0.0);
    for w in idx.windows(2) {
        s += pts[w[0]].distance(pts[w[1]]);
        f.push(s);
    }
    if ring {
        if let (Some(&l), Some(&z)) = (idx.last(), idx.first()) {
            s += pts[l].distance(pts[z]);
        }
    }
    if s > 0.0 {
        for x in &mut f {
            *x /= s;
        }
    }
    f
}

/// The point at arc fraction `u` along `idx` (fractions `fr`).
fn at_fraction(pts: &[Point], idx: &[usize], fr: &[f64], ring: bool, u: f64) -> Point {
    let n = idx.len();
    let k = fr.partition_point(|&x| x <= u).clamp(1, n) - 1;
    let (u0, u1, j) = if k + 1 < n {
        (fr[k], fr[k + 1], idx[k + 1])
    } else if ring {
        (fr[k], 1.0, idx[0])
    } else {
        return pts[idx[n - 1]];
    };
    let t = if u1 > u0 {
        ((u - u0) / (u1 - u0)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    pts[idx[k]].lerp(pts[j], t)
}

/// The feet of `b`'s nodes on `a`: for each, the arc fraction along `a`
/// of the nearest point of `a` and the distance to it. The search walks
/// along `a` as `b` goes on (the sides run the same way), and the
/// fractions never go back.
fn feet(pts: &[Point], a: &[usize], fa: &[f64], ring: bool, b: &[usize]) -> Vec<(f64, f64)> {
    let na = if ring { a.len() } else { a.len() - 1 };
    let end_u = |s: usize| if s + 1 < fa.len() { fa[s + 1] } else { 1.0 };
    let on = |s: usize, p: Point| {
        let (x, y) = (pts[a[s % a.len()]], pts[a[(s + 1) % a.len()]]);
        let d = y - x;
        let t = if d.length_squared() > 0.0 {
            ((p - x).dot(d) / d.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let u = fa[s] + t * (end_u(s) - fa[s]);
        (u, p.distance(x + t * d))
    };
    let window = 16 + 4 * na.div_ceil(b.len().max(1));
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(b.len());
    let mut at = 0usize;
    for (k, &v) in b.iter().enumerate() {
        let p = pts[v];
        let range: Vec<usize> = if k == 0 {
            (0..na).collect()
        } else if ring {
            (0..2 * window).map(|i| (at + na + i - 2) % na).collect()
        } else {
            (at.saturating_sub(2)..(at + 2 * window).min(na)).collect()
        };
        let mut best = (0usize, f64::INFINITY, 0.0);
        for s in range {
            let (u, d) = on(s, p);
            if d < best.1 {
                best = (s, d, u);
            }
        }
        at = best.0;
        let mut u = best.2;
        if let Some(&(prev, _)) = out.last() {
            if ring && u < prev - 0.5 {
                u += 1.0;
            }
            u = u.max(prev).min(1.0);
        } else if ring && u > 0.5 {
            u -= 1.0;
        }
        out.push((u, best.1));
    }
    out
}

/// One line of a band: its nodes (indices) and their arc-length fractions.
struct Line {
    idx: Vec<usize>,
    u: Vec<f64>,
}

/// A row's cells between the lines `p` and `q`, `q` with at least as many
/// edges: regular cells and wedges on `q`; the lines may share their first
/// or last node (an end of one segment handed to the inner line), and then
/// the cell there takes two edges of `q` and one of `p`. Wedges go where
/// the lines' fractions drift apart.
fn zip_row(p: &Line, q: &Line, ring: bool, taken: &[usize]) -> Option<Zipped> {
    let (np, nq) = if ring {
        (p.idx.len(), q.idx.len())
    } else {
        (p.idx.len() - 1, q.idx.len() - 1)
    };
    let pi = |i: usize| p.idx[i % p.idx.len()];
    let qi = |k: usize| q.idx[k % q.idx.len()];
    let pu = |i: usize| if i >= p.u.len() { 1.0 } else { p.u[i] };
    let qu = |k: usize| if k >= q.u.len() { 1.0 } else { q.u[k] };
    let shared_start = !ring && pi(0) == qi(0);
    let shared_end = !ring && pi(np) == qi(nq);
    let mut cells = Vec::new();
    let mut wedges = Vec::new();
    let mut pairs = Vec::new();
    let (mut i, mut k) = (0, 0);
    if shared_start {
        if np < 1 || nq < 2 {
            return None;
        }
        cells.push([pi(0), pi(1), qi(2), qi(1)]);
        (i, k) = (1, 2);
    }
    let (end_p, end_q) = if shared_end {
        (np - 1, nq - 2)
    } else {
        (np, nq)
    };
    // Each wedge takes two edges of the difference: an odd one cannot be
    // taken.
    if end_q < k || end_p < i || end_q - k < end_p - i || (end_q - k - (end_p - i)) % 2 == 1 {
        return None;
    }
    while i < end_p || k < end_q {
        let spare = (end_q - k) - (end_p - i);
        let wedge = if spare == 0 {
            false
        } else if i == end_p {
            true
        } else if !ring && (k == 0 || k + 2 >= end_q) {
            // A band's corner is no wedge's.
            false
        } else if taken.binary_search(&qi(k + 1)).is_ok() {
            false
        } else {
            (qu(k + 2) - pu(i)).abs() < (qu(k + 1) - pu(i + 1)).abs()
        };
        if wedge {
            cells.push([pi(i), qi(k), qi(k + 1), qi(k + 2)]);
            wedges.push((pi(i), qi(k + 1)));
            k += 2;
        } else {
            cells.push([pi(i), pi(i + 1), qi(k + 1), qi(k)]);
            pairs.extend([(pi(i), qi(k)), (pi(i + 1), qi(k + 1))]);
            i += 1;
            k += 1;
        }
    }
    if shared_end {
        cells.push([pi(np - 1), pi(np), qi(nq - 1), qi(nq - 2)]);
    }
    Some(Zipped {
        cells,
        wedges,
        pairs,
    })
}

/// A row zipped between two lines: its cells, its wedges as (corner on
/// `p`, middle node on `q`), and the nodes facing each other across it
/// as (node of `p`, node of `q`): a regular cell's two pairs of corners
/// (a wedge's middle faces no node; its other two nodes are a regular
/// cell's).
struct Zipped {
    cells: Vec<[usize; 4]>,
    wedges: Vec<(usize, usize)>,
    pairs: Vec<(usize, usize)>,
}

/// Places each inner node of the lines at the mean of the means of the
/// nodes facing it across the row below and across the row above
/// (`pairs`: per row, (node below, node above)), sweeps over all of them
/// at once, the sides held: across the band the nodes then share the
/// offset between the sides' nodes evenly among the rows, instead of the
/// row beside the side the lines do not follow taking all of it. A node
/// without a facing node on both sides stays.
fn across(points: &mut [Point], pts: &[Point], base: usize, pairs: &[Vec<(usize, usize)>]) {
    let n = points.len();
    let mut below: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut above: Vec<Vec<usize>> = vec![Vec::new(); n];
    for row in pairs {
        for &(lo, hi) in row {
            if hi >= base && !below[hi - base].contains(&lo) {
                below[hi - base].push(lo);
            }
            if lo >= base && !above[lo - base].contains(&hi) {
                above[lo - base].push(hi);
            }
        }
    }
    let at = |points: &[Point], k: usize| if k < base { pts[k] } else { points[k - base] };
    let mean = |points: &[Point], ks: &[usize]| {
        ks.iter().fold(Point::ZERO, |s, &k| s + at(points, k)) / ks.len() as f64
    };
    for _ in 0..ACROSS_SWEEPS * pairs.len() {
        let next: Vec<Point> = (0..n)
            .map(|v| {
                if below[v].is_empty() || above[v].is_empty() {
                    points[v]
                } else {
                    0.5 * (mean(points, &below[v]) + mean(points, &above[v]))
                }
            })
            .collect();
        points.copy_from_slice(&next);
    }
}

/// Lays `rows` rows over the band `sides` of the points `pts`: the inner
/// lines follow the side with more edges, the row beside the other takes
/// the difference by wedges. `None` when the ends do not fit the rows (an
/// end of `rows` segments, or of one segment with two rows), a quad is
/// not measurably convex with a scaled Jacobian of at least `min_sj`, or
/// the quads fold over one another.
pub fn band_rows(pts: &[Point], sides: &BandSides, rows: usize, min_sj: f64) -> Option<BandRows> {
    lay_and_settle(pts, sides, rows, false, min_sj)
}

/// Three rows over a ring whose sides' counts differ: the two rows of
/// [`band_rows`] with their inner line then split in two
/// ([`split_inner_line`]), so that every wedge is in a row beside a side
/// and the middle row is a clean strip of quads (a rotating machine's
/// sliding band). The same wedges as two rows, each leaving one irregular
/// node, among twice the interior nodes. `None` as for [`band_rows`].
pub fn ring_rows_split(pts: &[Point], sides: &BandSides, min_sj: f64) -> Option<BandRows> {
    let ring = sides.ends.is_none();
    if !ring || sides.a.len() == sides.b.len() {
        return None;
    }
    lay_and_settle(pts, sides, 2, true, min_sj)
}

fn lay_and_settle(
    pts: &[Point],
    sides: &BandSides,
    rows: usize,
    split: bool,
    min_sj: f64,
) -> Option<BandRows> {
    let ring = sides.ends.is_none();
    // The band's area: the loop's, or the outer side's less the hole's.
    let area = if ring {
        let side = |s: &[usize]| polygon_area(s.iter().map(|&k| pts[k])).abs();
        (side(&sides.a) - side(&sides.b)).abs()
    } else {
        polygon_area(pts.iter().copied()).abs()
    };
    let mut laid = lay_rows(pts, sides, rows)?;
    settle(pts, &mut laid, min_sj, area)?;
    if split {
        split_inner_line(pts, &mut laid);
        settle(pts, &mut laid, min_sj, area)?;
    }
    Some(BandRows {
        points: laid.points,
        quads: laid.quads,
    })
}

/// Orients the laid quads counter-clockwise and smooths the inner nodes
/// among themselves, the band's own nodes held; `None` when a quad is then
/// not measurably convex with a scaled Jacobian of at least `min_sj`, or
/// the quads fold over one another (their areas add up to more than the
/// band's `area`: each quad may be convex and still lie over another).
fn settle(pts: &[Point], laid: &mut Laid, min_sj: f64, area: f64) -> Option<()> {
    let base = pts.len();
    let mut mesh = QuadMesh {
        nodes: pts.iter().chain(&laid.points).copied().collect(),
        quads: Vec::with_capacity(laid.quads.len()),
        loops: vec![(0..base as u32).collect()],
    };
    for q in &mut laid.quads {
        if polygon_area(q.map(|k| mesh.nodes[k])) < 0.0 {
            q.reverse();
        }
        mesh.quads.push(q.map(|k| k as u32));
    }
    smooth_and_optimize(&mut mesh, &SmoothParams::DEFAULT, None);
    laid.points.copy_from_slice(&mesh.nodes[base..]);
    let mut covered = 0.0;
    for q in &laid.quads {
        let p = q.map(|k| mesh.nodes[k]);
        if !is_measurably_convex(p) || Shape::of(p).scaled_jacobian < min_sj {
            return None;
        }
        covered += polygon_area(p);
    }
    (covered <= area * (1.0 + FOLD_TOLERANCE)).then_some(())
}

/// Rows laid over a band, before smoothing: the new points and quads (in
/// row order, `row_starts` the first quad of each row), and the lines from
/// the coarser side (`lines[0]`) to the finer.
struct Laid {
    points: Vec<Point>,
    quads: Vec<[usize; 4]>,
    row_starts: Vec<usize>,
    lines: Vec<Vec<usize>>,
}

/// Splits the inner line of a ring's two rows (every node of it new) in two (the pillowing of
/// that line): each node of it becomes a node a third of the way towards
/// its foot on the coarser side, kept by the first row, and one a third
/// of the way towards its foot on the finer side, taken by the second;
/// a clean strip of quads joins the two lines. Every wedge stays in the
/// row beside a side, and the middle row has no irregular node. Moving
/// each row's nodes towards its side by the same fraction keeps its quads'
/// shapes (an affine squeeze across a locally straight band), so the
/// split is convex where the two rows were.
fn split_inner_line(pts: &[Point], laid: &mut Laid) {
    let base = pts.len();
    let (side_a, line, side_b) = (&laid.lines[0], &laid.lines[1], &laid.lines[2]);
    let all: Vec<Point> = pts.iter().chain(&laid.points).copied().collect();
    let foot = |side: &[usize]| -> Vec<Point> {
        let fr = fractions(&all, side, true);
        feet(&all, side, &fr, true, line)
            .iter()
            .map(|&(u, _)| at_fraction(&all, side, &fr, true, u))
            .collect()
    };
    let (on_a, on_b) = (foot(side_a), foot(side_b));
    let mut lower = vec![usize::MAX; laid.points.len()];
    let mut split: Vec<(usize, usize)> = Vec::with_capacity(line.len());
    for (k, &v) in line.iter().enumerate() {
        let p = all[v];
        laid.points[v - base] = p + (on_a[k] - p) / 3.0;
        laid.points.push(p + (on_b[k] - p) / 3.0);
        lower[v - base] = base + laid.points.len() - 1;
        split.push((v, lower[v - base]));
    }
    let second = laid.row_starts[1];
    for q in &mut laid.quads[second..] {
        for k in q.iter_mut() {
            if let Some(&l) = k.checked_sub(base).and_then(|i| lower.get(i)) {
                if l != usize::MAX {
                    *k = l;
                }
            }
        }
    }
    let n = split.len();
    laid.row_starts.push(laid.quads.len());
    laid.quads.extend((0..n).map(|i| {
        let ((t0, b0), (t1, b1)) = (split[i], split[(i + 1) % n]);
        [t0, t1, b1, b0]
    }));
}

/// Lays `rows` rows over the band `sides` (see [`band_rows`]), before the
/// quads are oriented and smoothed.
fn lay_rows(pts: &[Point], sides: &BandSides, rows: usize) -> Option<Laid> {
    let ring = sides.ends.is_none();
    let edges = |s: &[usize]| if ring { s.len() } else { s.len() - 1 };
    if rows == 0 || sides.a.len() < 2 || sides.b.len() < 2 {
        return None;
    }
    // The finer side is `b`: swap, ends' nodes running the other way.
    let (a, b, ends) = if edges(&sides.a) > edges(&sides.b) {
        let flip = |e: &Vec<usize>| e.iter().rev().copied().collect::<Vec<_>>();
        (
            &sides.b,
            &sides.a,
            sides.ends.as_ref().map(|(s, t)| (flip(s), flip(t))),
        )
    } else {
        (&sides.a, &sides.b, sides.ends.clone())
    };
    let (na, nb) = (edges(a), edges(b));
    if rows == 1 && na != nb {
        return None;
    }
    let fa = fractions(pts, a, ring);
    // The inner lines follow `b`'s nodes, each at its foot's fraction on
    // `a`; a node half way along `b`'s first or last edge is at `k ± ½`.
    let ub: Vec<f64> = feet(pts, a, &fa, ring, b).iter().map(|f| f.0).collect();
    let ring_end = if ring { 1.0 } else { 0.0 };
    let b_at = |k: f64| -> (f64, Point) {
        let i = (k.floor() as usize).min(b.len() - 1);
        let t = k - i as f64;
        if t == 0.0 {
            return (ub[i], pts[b[i]]);
        }
        let (j, uj) = if i + 1 < b.len() {
            (b[i + 1], ub[i + 1])
        } else {
            (b[0], ub[0] + ring_end)
        };
        (ub[i] + t * (uj - ub[i]), pts[b[i]].lerp(pts[j], t))
    };
    // Where `a` is finer than `b` (nodes of `a` inside an edge of `b`, by
    // their fractions), the inner lines take `a`'s count there: a row
    // cannot put a wedge on a side.
    let inside = |lo: f64, hi: f64| {
        let count = |lo: f64, hi: f64| {
            fa.partition_point(|&x| x < hi)
                .saturating_sub(fa.partition_point(|&x| x <= lo))
        };
        count(lo, hi)
            + if ring {
                count(lo - 1.0, hi - 1.0) + count(lo + 1.0, hi + 1.0)
            } else {
                0
            }
    };
    let mut added: Vec<usize> = (0..nb)
        .map(|k| {
            let hi = if k + 1 < ub.len() {
                ub[k + 1]
            } else {
                ub[0] + 1.0
            };
            inside(ub[k], hi).saturating_sub(1)
        })
        .collect();
    // A wedge takes two edges of the difference: the nodes added must be
    // even in number.
    if added.iter().sum::<usize>() % 2 == 1 {
        if let Some(m) = added.iter_mut().max() {
            *m += 1;
        }
    }
    let mut points: Vec<Point> = Vec::new();
    let base = pts.len();
    let mut lines: Vec<Line> = vec![Line {
        idx: a.clone(),
        u: fa.clone(),
    }];
    for j in 1..rows {
        let t = j as f64 / rows as f64;
        let new_point = |k: f64, points: &mut Vec<Point>| {
            let (u, pb) = b_at(k);
            points.push(at_fraction(pts, a, &fa, ring, u).lerp(pb, t));
            (base + points.len() - 1, u)
        };
        let (mut idx, mut u) = (Vec::new(), Vec::new());
        let mut put = |(v, x): (usize, f64)| {
            idx.push(v);
            u.push(x);
        };
        let ends_here = if ring {
            None
        } else {
            let (e1, e2) = ends.as_ref()?;
            // The line's first node: the end's node `j`, or the finer
            // side's corner (an end of one segment, two rows).
            let first = |e: &Vec<usize>, corner: usize| match (e.len() + 1, rows) {
                (s, r) if s == r => Some((e[j - 1], false)),
                (1, 2) => Some((corner, true)),
                _ => None,
            };
            Some((first(e1, b[0])?, first(e2, b[nb])?))
        };
        if let Some(((s1, _), _)) = ends_here {
            put((s1, 0.0));
        }
        for (k, &extra) in added.iter().enumerate() {
            if k > 0 || ring {
                put(new_point(k as f64, &mut points));
            }
            // A shared end needs a node inside its edge.
            let shared = match ends_here {
                Some(((_, s1), (_, s2))) => (k == 0 && s1) || (k + 1 == nb && s2),
                None => false,
            };
            let m = extra + 1 + usize::from(shared);
            for i in 1..m {
                put(new_point(k as f64 + i as f64 / m as f64, &mut points));
            }
        }
        if let Some((_, (s2, _))) = ends_here {
            put((s2, 1.0));
        }
        lines.push(Line { idx, u });
    }
    lines.push(Line {
        idx: b.clone(),
        u: ub,
    });
    let mut quads = Vec::new();
    let mut lifts = Vec::new();
    let mut facing: Vec<Vec<(usize, usize)>> = Vec::new();
    // A node that is a wedge's middle in one row is none in the next (it
    // would be left with two edges).
    let mut middles: Vec<usize> = Vec::new();
    let mut row_starts = Vec::with_capacity(rows);
    for j in 0..rows {
        row_starts.push(quads.len());
        let (p, q) = (&lines[j], &lines[j + 1]);
        // The wedges go on the line with more edges, never on a side.
        let up = edges(&q.idx) >= edges(&p.idx);
        let Zipped {
            cells,
            wedges: w,
            pairs,
        } = if up {
            zip_row(p, q, ring, &middles)?
        } else {
            zip_row(q, p, ring, &middles)?
        };
        facing.push(if up {
            pairs
        } else {
            pairs.into_iter().map(|(x, y)| (y, x)).collect()
        });
        // A wedge's two edges on a side would meet there flat.
        let wedge_line = if edges(&q.idx) >= edges(&p.idx) {
            j + 1
        } else {
            j
        };
        if !w.is_empty() && (wedge_line == 0 || wedge_line == rows) {
            return None;
        }
        quads.extend(cells);
        middles.extend(w.iter().map(|x| x.1));
        middles.sort_unstable();
        lifts.extend(w);
    }
    across(&mut points, pts, base, &facing);
    let all = |points: &[Point], k: usize| {
        if k < base {
            pts[k]
        } else {
            points[k - base]
        }
    };
    for &(corner, middle) in &lifts {
        if middle >= base {
            let (c, m) = (all(&points, corner), all(&points, middle));
            points[middle - base] = m.lerp(c, -WEDGE_LIFT);
        }
    }
    Some(Laid {
        points,
        quads,
        row_starts,
        lines: lines.into_iter().map(|l| l.idx).collect(),
    })
}

/// Rows for a band `w` wide whose spacing is `h`: its width over its
/// spacing, at least two when the sides' counts differ.
fn rows_for(w: f64, h: f64, unequal: bool, max_rows: usize) -> Option<usize> {
    let r = (w / h).round().max(1.0) as usize;
    let r = if unequal { r.max(2) } else { r };
    (r <= max_rows).then_some(r)
}

/// True when every node of either side lies within `reach` of the other
/// side ([`feet`]: the sides face each other along the band).
fn faces(pts: &[Point], a: &[usize], b: &[usize], ring: bool, reach: f64) -> bool {
    let (fa, fb) = (fractions(pts, a, ring), fractions(pts, b, ring));
    feet(pts, a, &fa, ring, b).iter().all(|&(_, d)| d <= reach)
        && feet(pts, b, &fb, ring, a).iter().all(|&(_, d)| d <= reach)
}

/// The band of one loop's points (counter-clockwise, `angles` its front
/// angles in degrees): four corners, two opposite short ends, two long
/// sides facing each other; and its rows.
pub fn loop_band(pts: &[Point], angles: &[f64], t: &BandTuning) -> Option<(BandSides, usize)> {
    let n = pts.len();
    let corners: Vec<usize> = (0..n).filter(|&k| angles[k] < CORNER_MAX).collect();
    if corners.len() != 4 {
        return None;
    }
    let seg = |x: usize, y: usize| (y + n - x) % n;
    let spans: Vec<usize> = (0..4)
        .map(|c| seg(corners[c], corners[(c + 1) % 4]))
        .collect();
    // The ends are spans 0 and 2 from corner `s`.
    let s = (0..2).find(|&s| {
        spans[s].max(spans[s + 2]) <= t.max_end && spans[s + 1].min(spans[(s + 3) % 4]) >= 4
    })?;
    let k = |c: usize| corners[(s + c) % 4];
    let walk = |from: usize, len: usize| (0..=len).map(|i| (from + i) % n).collect::<Vec<_>>();
    // Loop order: end 1 from k(0) to k(1), side from k(1) to k(2), end 2
    // from k(2) to k(3), side from k(3) back to k(0).
    let a = walk(k(1), seg(k(1), k(2)));
    let mut b = walk(k(3), seg(k(3), k(0)));
    b.reverse();
    let e1: Vec<usize> = walk(k(0), seg(k(0), k(1)))[1..spans[s]]
        .iter()
        .rev()
        .copied()
        .collect();
    let e2: Vec<usize> = walk(k(2), seg(k(2), k(3)))[1..spans[(s + 2) % 4]].to_vec();
    let perimeter: f64 = (0..n).map(|i| pts[i].distance(pts[(i + 1) % n])).sum();
    let area = polygon_area(pts.iter().copied());
    let (w, h) = (2.0 * area / perimeter, perimeter / n as f64);
    // The ends fix the rows: as many as an end's segments, two where an
    // end of one segment meets sides of unequal counts. Sides of equal
    // counts with equal ends make a logical rectangle, the mapped grid's.
    let (n1, n2) = (spans[s], spans[(s + 2) % 4]);
    let rows = match (n1.min(n2), n1.max(n2)) {
        (1, 1) if a.len() != b.len() => 2,
        (1, 2) => 2,
        (x, y) if x == y && a.len() != b.len() => x,
        _ => return None,
    };
    if rows > t.max_rows || w > (rows as f64 + 0.5) * h {
        return None;
    }
    if !faces(pts, &a, &b, false, t.reach * (rows as f64) * h) {
        return None;
    }
    Some((
        BandSides {
            a,
            b,
            ends: Some((e1, e2)),
        },
        rows,
    ))
}

/// The ring between an outer loop (`outer`, counter-clockwise) and the one
/// hole loop inside it (`hole`, clockwise), as indices into `pts`: their
/// sides run the same way, from the hole's node nearest the outer loop's
/// first; and its rows.
pub fn ring_band(
    pts: &[Point],
    outer: &[usize],
    hole: &[usize],
    t: &BandTuning,
) -> Option<(BandSides, usize)> {
    let len = |l: &[usize]| -> f64 {
        (0..l.len())
            .map(|i| pts[l[i]].distance(pts[l[(i + 1) % l.len()]]))
            .sum()
    };
    let (po, ph) = (len(outer), len(hole));
    let area =
        polygon_area(outer.iter().map(|&v| pts[v])) + polygon_area(hole.iter().map(|&v| pts[v]));
    let perimeter = po + ph;
    let (w, h) = (
        2.0 * area / perimeter,
        perimeter / (outer.len() + hole.len()) as f64,
    );
    let rows = rows_for(w, h, outer.len() != hole.len(), t.max_rows)?;
    let a = outer.to_vec();
    let mut b: Vec<usize> = hole.iter().rev().copied().collect();
    let p0 = pts[a[0]];
    let start = (0..b.len()).min_by(|&i, &j| {
        pts[b[i]]
            .distance_squared(p0)
            .total_cmp(&pts[b[j]].distance_squared(p0))
    })?;
    b.rotate_left(start);
    if !faces(pts, &a, &b, true, t.reach * (rows as f64) * h) {
        return None;
    }
    Some((BandSides { a, b, ends: None }, rows))
}

/// The band rung's state: per loop, whether it was looked at as a band;
/// the first loop id not yet walked past (every loop below it was looked
/// at, or had died: loops are only ever added, and a dead one stays
/// dead); the pair of loops last looked at as a
/// ring, and the front's loop count and live loop count when the live
/// loops were last listed for it.
#[derive(Clone, Debug, Default)]
pub(super) struct BandsSeen {
    loops: Vec<bool>,
    next: u32,
    ring: Option<(u32, u32)>,
    ring_listed: Option<(usize, usize)>,
}

impl Mesher {
    /// [`super::Rung::Band`]: a loop that is a thin band when it first
    /// appears, or the ring between the front's two loops, is closed by its
    /// rows.
    pub(super) fn close_band(&mut self) -> Option<StepReport> {
        let tuning = self.params.tuning.band;
        if tuning.max_rows == 0 {
            return None;
        }
        // The live loops can only be another pair once a loop was added
        // or one died: the loop count or the live count changed.
        let counts = (self.front.loops.len(), self.front.live_loop_count());
        if counts.1 == 2 && self.bands.ring_listed != Some(counts) {
            self.bands.ring_listed = Some(counts);
            let pair = {
                let mut live = self.front.live_loops();
                (live.next(), live.next())
            };
            if let (Some(a), Some(b)) = pair {
                if self.bands.ring != Some((a, b)) {
                    self.bands.ring = Some((a, b));
                    if let Some(r) = self.close_ring(a, b, &tuning) {
                        return Some(r);
                    }
                }
            }
        }
        while (self.bands.next as usize) < self.front.loops.len() {
            let lid = self.bands.next;
            self.bands.next += 1;
            let k = lid as usize;
            if !self.front.loops[k].alive {
                continue;
            }
            if self.bands.loops.len() <= k {
                self.bands.loops.resize(k + 1, false);
            }
            if std::mem::replace(&mut self.bands.loops[k], true) {
                continue;
            }
            if let Some(r) = self.close_loop_band(lid, &tuning) {
                return Some(r);
            }
        }
        None
    }

    fn close_loop_band(&mut self, lid: u32, t: &BandTuning) -> Option<StepReport> {
        let l = self.front.loops[lid as usize];
        if l.len < 12 {
            return None;
        }
        let (slots, nodes, pts) = self.loop_geometry(lid);
        if is_pinched(&nodes) {
            return None;
        }
        let angles: Vec<f64> = slots
            .iter()
            .map(|&s| self.front.angle(s, &self.mesh.nodes).to_degrees())
            .collect();
        let (sides, rows) = loop_band(&pts, &angles, t)?;
        let grid = band_rows(&pts, &sides, rows, t.min_sj)?;
        if !self.loop_is_clear(&slots, &nodes, &pts) {
            return None;
        }
        Some(self.commit_band(&[lid], &nodes, &grid))
    }

    fn close_ring(&mut self, l0: u32, l1: u32, t: &BandTuning) -> Option<StepReport> {
        let (_, n0, _) = self.loop_geometry(l0);
        let (_, n1, _) = self.loop_geometry(l1);
        if is_pinched(&n0) || is_pinched(&n1) {
            return None;
        }
        let area = |l: u32| self.front.loop_area(l, &self.mesh.nodes);
        let (outer, hole) = match (area(l0) > 0.0, area(l1) > 0.0) {
            (true, false) => (n0, n1),
            (false, true) => (n1, n0),
            _ => return None,
        };
        let hole_pts: Vec<Point> = hole.iter().map(|&v| self.mesh.nodes[v as usize]).collect();
        let outer_pts: Vec<Point> = outer.iter().map(|&v| self.mesh.nodes[v as usize]).collect();
        if !crate::geom::point_in_polygon(hole_pts[0], &outer_pts) {
            return None;
        }
        let nodes: Vec<u32> = outer.iter().chain(&hole).copied().collect();
        let pts: Vec<Point> = outer_pts.into_iter().chain(hole_pts).collect();
        let (no, nh) = (outer.len(), hole.len());
        let (sides, rows) = ring_band(
            &pts,
            &(0..no).collect::<Vec<_>>(),
            &(no..no + nh).collect::<Vec<_>>(),
            t,
        )?;
        // Unequal counts: three rows, the wedges beside the sides and a
        // clean row between them, where they fit; else the ring's own rows.
        let split = (rows <= RING_ROWS && t.max_rows >= RING_ROWS)
            .then(|| ring_rows_split(&pts, &sides, t.min_sj))
            .flatten();
        let grid = split.or_else(|| band_rows(&pts, &sides, rows, t.min_sj))?;
        Some(self.commit_band(&[l0, l1], &nodes, &grid))
    }

    /// Meshes the loops `lids` (their `nodes`, in the order the band's
    /// indices count them) by `rows` and removes them from the front.
    fn commit_band(&mut self, lids: &[u32], nodes: &[u32], rows: &BandRows) -> StepReport {
        let mut r = self.report(StepKind::Mapped);
        let mut ids: Vec<u32> = nodes.to_vec();
        self.add_patch(&mut r, &mut ids, &rows.points, &rows.quads);
        r.reference = nodes.first().copied();
        for &l in lids {
            self.front.remove_loop(l);
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default() -> BandTuning {
        BandTuning::DEFAULT
    }

    /// A circle of `n` nodes of radius `r`, counter-clockwise.
    fn circle(n: usize, r: f64) -> Vec<Point> {
        (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                Point::new(r * t.cos(), r * t.sin())
            })
            .collect()
    }

    /// The points of the ring between a circle of 60 nodes, radius 1.1,
    /// and a hole of 70 nodes, radius 1 (clockwise), and its band.
    fn thin_ring() -> (Vec<Point>, BandSides, usize) {
        let mut pts = circle(60, 1.1);
        pts.extend(circle(70, 1.0).into_iter().rev());
        let outer: Vec<usize> = (0..60).collect();
        let hole: Vec<usize> = (60..130).collect();
        let (sides, rows) = ring_band(&pts, &outer, &hole, &default()).expect("a band");
        (pts, sides, rows)
    }

    /// Asserts that the quads of `g` over `pts` cover [`thin_ring`] once.
    fn assert_covers_thin_ring(pts: &[Point], g: &BandRows) {
        let at = |k: usize| {
            if k < pts.len() {
                pts[k]
            } else {
                g.points[k - pts.len()]
            }
        };
        let area: f64 = g.quads.iter().map(|q| polygon_area(q.map(at))).sum();
        let ring = polygon_area(circle(60, 1.1)) - polygon_area(circle(70, 1.0));
        assert!(
            (area - ring).abs() < 1e-9 * ring.abs().max(1.0),
            "{area} vs {ring}"
        );
    }

    /// The ring between circles of 60 and 70 nodes, radii 1 and 1.1:
    /// two rows, 5 wedges (each takes two edges of the difference).
    #[test]
    fn a_thin_ring_of_unequal_counts_gets_two_rows_with_wedges() {
        let (pts, sides, rows) = thin_ring();
        assert_eq!(rows, 2);
        let g = band_rows(&pts, &sides, rows, 0.3).expect("rows");
        assert_eq!(g.points.len(), 70);
        assert_eq!(g.quads.len(), 60 + 5 + 70);
        assert_covers_thin_ring(&pts, &g);
    }

    /// The same ring in three rows: the two rows' inner line split in two,
    /// the 5 wedges (5 irregular nodes) beside the sides and a clean middle
    /// row of 70 quads between two lines of 70 nodes; the quads cover the
    /// ring once.
    #[test]
    fn a_thin_ring_of_unequal_counts_splits_into_three_rows_with_a_clean_middle() {
        let (pts, sides, _) = thin_ring();
        let g = ring_rows_split(&pts, &sides, 0.3).expect("three rows");
        assert_eq!(g.points.len(), 140);
        assert_eq!(g.quads.len(), 60 + 5 + 70 + 70);
        assert_covers_thin_ring(&pts, &g);
        let mut neighbours = vec![std::collections::BTreeSet::new(); pts.len() + 140];
        for q in &g.quads {
            for i in 0..4 {
                neighbours[q[i]].insert(q[(i + 1) % 4]);
                neighbours[q[(i + 1) % 4]].insert(q[i]);
            }
        }
        let irregular = (pts.len()..pts.len() + 140)
            .filter(|&v| neighbours[v].len() != 4)
            .count();
        assert_eq!(irregular, 5);
    }

    /// Sides of equal counts are no split ring's (the mapped grid's).
    #[test]
    fn a_ring_of_equal_counts_is_not_split() {
        let mut pts = circle(60, 1.1);
        let inner: Vec<Point> = circle(60, 1.0).into_iter().rev().collect();
        pts.extend(inner);
        let sides = BandSides {
            a: (0..60).collect(),
            b: (60..120).rev().collect(),
            ends: None,
        };
        assert!(ring_rows_split(&pts, &sides, 0.1).is_none());
    }

    /// A thin strip of 30 and 24 segments with ends of one segment: two
    /// rows, the inner line handed to the finer side's corners.
    #[test]
    fn a_strip_with_ends_of_one_segment_gets_two_rows() {
        let (m, k, h) = (30, 24, 0.09);
        let mut pts = Vec::new();
        for i in 0..=m {
            pts.push(Point::new(i as f64 * 3.0 / m as f64, 0.0));
        }
        for i in (0..=k).rev() {
            pts.push(Point::new(i as f64 * 3.0 / k as f64, h));
        }
        let n = pts.len();
        let angles: Vec<f64> = (0..n)
            .map(|i| {
                let (p, c, q) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
                let (u, v) = (q - c, p - c);
                u.perp_dot(v)
                    .atan2(u.dot(v))
                    .rem_euclid(std::f64::consts::TAU)
                    .to_degrees()
            })
            .collect();
        let (sides, rows) = loop_band(&pts, &angles, &default()).expect("a band");
        assert_eq!(rows, 2);
        let g = band_rows(&pts, &sides, rows, 0.1).expect("rows");
        let total: f64 = g
            .quads
            .iter()
            .map(|q| polygon_area(q.map(|j| if j < n { pts[j] } else { g.points[j - n] })))
            .sum();
        assert!((total - 3.0 * h).abs() < 1e-9, "{total}");
        // Row 1: 24 cells and (32 - 24) / 2 wedges; row 2: 28 cells and
        // the two at the shared corners.
        assert_eq!(g.quads.len(), 24 + 4 + 28 + 2);
        assert_eq!(g.points.len(), 31);
    }

    /// Sides whose difference is odd (31 and 24 segments, ends of one) cannot
    /// be taken by wedges of two edges: no rows, and no panic.
    #[test]
    fn an_odd_difference_gets_no_rows() {
        let mut pts = Vec::new();
        for i in 0..=31 {
            pts.push(Point::new(i as f64 * 3.0 / 31.0, 0.0));
        }
        for i in (0..=24).rev() {
            pts.push(Point::new(i as f64 * 3.0 / 24.0, 0.09));
        }
        let sides = BandSides {
            a: (0..=31).collect(),
            b: (32..57).rev().collect(),
            ends: Some((Vec::new(), Vec::new())),
        };
        assert!(band_rows(&pts, &sides, 2, 0.0).is_none());
    }

    /// A wide loop is no band; an end longer than allowed is none either.
    /// The inner line of two rows between sides offset by half a segment
    /// goes half way between the nodes facing it: each row takes a
    /// quarter segment of skew, not one row all of it.
    #[test]
    fn the_rows_share_the_offset_between_the_sides() {
        let a: Vec<Point> = (0..5).map(|i| Point::new(f64::from(i), 0.0)).collect();
        let b: Vec<Point> = (0..5)
            .map(|i| Point::new(f64::from(i) + 0.5, 1.0))
            .collect();
        let pts: Vec<Point> = a.iter().chain(&b).copied().collect();
        let base = pts.len();
        // The inner line starts over `b`'s nodes, half way across.
        let mut points: Vec<Point> = b.iter().map(|p| Point::new(p.x, 0.5)).collect();
        let below: Vec<(usize, usize)> = (0..5).map(|i| (i, base + i)).collect();
        let above: Vec<(usize, usize)> = (0..5).map(|i| (base + i, 5 + i)).collect();
        across(&mut points, &pts, base, &[below, above]);
        for (i, p) in points.iter().enumerate() {
            let want = Point::new(i as f64 + 0.25, 0.5);
            assert!(p.distance(want) < 1e-12, "node {i} at {p:?}");
        }
    }

    #[test]
    fn wide_loops_are_not_bands() {
        let sq: Vec<Point> = (0..16)
            .map(|i| match i / 4 {
                0 => Point::new(i as f64, 0.0),
                1 => Point::new(4.0, (i - 4) as f64),
                2 => Point::new((12 - i) as f64, 4.0),
                _ => Point::new(0.0, (16 - i) as f64),
            })
            .collect();
        let angles: Vec<f64> = (0..16)
            .map(|i| if i % 4 == 0 { 90.0 } else { 180.0 })
            .collect();
        assert!(loop_band(&sq, &angles, &default()).is_none());
    }
}

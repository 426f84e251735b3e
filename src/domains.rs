//! Seeded generator of awkward but valid boundaries, for measuring the
//! mesher beyond the benchmark cases (issue 15): plates with up to 30
//! holes, thin channels and slots up to 1:50, boundary spacing graded up
//! to 1:100, spikes with tips down to 5°, loops that nearly touch (gaps of
//! 2–20 % of the local segment length), rectangles with 2 nodes on one
//! side and up to 200 on the opposite one, and mixtures of these.
//!
//! Everything is a pure function of the [`Family`] and the seed (a small
//! SplitMix64 generator, no dependency): the same seed gives the same
//! points bit for bit. Every domain passes [`Boundary::new`] and has an
//! even node count on every loop; a draw that does not validate is drawn
//! again from the next sub-seed, so the generator only yields valid
//! boundaries. Seeds that are multiples of 4 take the family's extreme
//! parameters (30 holes, 1:50, 1:100, 5°, a 2 % gap, 2 against 200 nodes),
//! so any four consecutive seeds of a family reach them; [`suite`] draws
//! consecutive seeds per family.

use crate::boundary::Boundary;
use crate::geom::Point;
use std::f64::consts::{PI, TAU};
use std::fmt;

pub use crate::rng::SplitMix64;

/// A tube sheet's pattern: a square plate `k` pitches a side with a round
/// hole of radius 0.3 pitch in each pitch cell (`k`² holes of 12 nodes,
/// ligaments 0.4 pitch wide, about 2.5 boundary segments), its outline cut
/// into 4 segments a pitch. For measuring how the cost grows with the
/// number of loops.
pub fn perforated_plate(k: usize) -> Boundary {
    let k = k.max(1);
    let side = 4 * k;
    let t = |i: usize| i as f64 / 4.0;
    let w = k as f64;
    let mut pts: Vec<Point> = Vec::new();
    pts.extend((0..side).map(|i| Point::new(t(i), 0.0)));
    pts.extend((0..side).map(|i| Point::new(w, t(i))));
    pts.extend((0..side).map(|i| Point::new(w - t(i), w)));
    pts.extend((0..side).map(|i| Point::new(0.0, w - t(i))));
    let mut loops = vec![(0..pts.len()).collect::<Vec<usize>>()];
    for i in 0..k {
        for j in 0..k {
            let c = Point::new(i as f64 + 0.5, j as f64 + 0.5);
            let start = pts.len();
            pts.extend((0..12).map(|n| {
                let a = -(n as f64) * TAU / 12.0;
                c + 0.3 * Point::new(a.cos(), a.sin())
            }));
            loops.push((start..pts.len()).collect());
        }
    }
    let labels = (1..=pts.len() as i64).collect();
    Boundary {
        points: pts,
        loops,
        labels,
    }
}

/// One SplitMix64 output for `x`: a seed mixer.
fn mix(x: u64) -> u64 {
    SplitMix64::new(x).next_u64()
}

/// The kinds of awkward domain.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    /// A plate with up to 30 holes (circles and polygons of varied sizes
    /// and spacings, apart by a margin).
    ManyHoles,
    /// Thin channels and slots, length to width up to 50: a plate with a
    /// slot, a straight channel, a serpentine channel.
    Channel,
    /// Boundary spacing graded up to 1:100 along the boundary.
    Graded,
    /// Star and saw-tooth outlines and V notches, tips down to 5°.
    Spikes,
    /// Loops (or two parts of one loop) closer than 2–20 % of the local
    /// segment length.
    NearTouching,
    /// Rectangles with 2 (to 4) nodes on one side and up to 200 on the
    /// opposite side.
    Unbalanced,
    /// An outline with spikes, notches, grading or unbalanced sides and
    /// holes, a slot or a near-touching pair inside.
    Mixed,
    /// Real-like: a thin band between two fine loops of unequal node
    /// counts (an electric machine's air gap: a ring 0.7 to 3 sizes wide,
    /// or a curved sliver between two arcs), the counts 2 to 15 % apart.
    Band,
    /// Real-like: a ring whose outline is a zig-zag of 120° turns in and
    /// out (a reactor core bounded by hexagonal assemblies), each zig or
    /// zag cut into 1 to 4 segments, round a round or zig-zag hole; half
    /// of them with slits between the assemblies (1/40 to 1/20 of a zig
    /// wide, walls of one segment) going out from the outline's tips, dead
    /// ends and Ys.
    Zigzag,
    /// Real-like: a tube sheet, a plate pierced by a grid of 16 to 196
    /// round holes, its ligaments 1.2 to 4 sizes wide.
    TubeSheet,
    /// Real-like: a quadrilateral with one side graded towards both ends
    /// (end segments 10 to 100 times finer than the middle), the other
    /// sides uniform.
    GradedSide,
}

impl Family {
    pub const ALL: [Family; 7] = [
        Family::ManyHoles,
        Family::Channel,
        Family::Graded,
        Family::Spikes,
        Family::NearTouching,
        Family::Unbalanced,
        Family::Mixed,
    ];

    /// The real-like families: shapes real parts have that the others
    /// miss ([`real_like_domains`]).
    pub const REAL_LIKE: [Family; 4] = [
        Family::Band,
        Family::Zigzag,
        Family::TubeSheet,
        Family::GradedSide,
    ];

    /// Lower-case name, used in domain names.
    pub fn name(self) -> &'static str {
        match self {
            Family::ManyHoles => "holes",
            Family::Channel => "channel",
            Family::Graded => "graded",
            Family::Spikes => "spikes",
            Family::NearTouching => "near",
            Family::Unbalanced => "unbalanced",
            Family::Mixed => "mixed",
            Family::Band => "band",
            Family::Zigzag => "zigzag",
            Family::TubeSheet => "tubesheet",
            Family::GradedSide => "gradedside",
        }
    }

    /// The family of a [`Family::name`].
    pub fn from_name(s: &str) -> Option<Family> {
        Family::ALL
            .into_iter()
            .chain(Family::REAL_LIKE)
            .find(|f| f.name() == s)
    }
}

impl fmt::Display for Family {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A generated domain.
#[derive(Clone, Debug, PartialEq)]
pub struct Domain {
    /// `family_seed` (seed in hexadecimal): unique, usable as a file name.
    pub name: String,
    pub family: Family,
    pub seed: u64,
    /// The parameters drawn, for people ("30 holes", "slot 1:50", ...).
    pub description: String,
    pub boundary: Boundary,
}

/// Draws a domain of `family` for `seed`; always valid.
pub fn generate(family: Family, seed: u64) -> Domain {
    generate_counted(family, seed).0
}

/// Draws tried before giving up on a seed's family (never reached by the
/// families here: the tests check that no suite domain needs more than a
/// few).
const MAX_DRAWS: u64 = 64;

/// [`generate`], and the number of draws it took (`MAX_DRAWS + 1` when it
/// fell back to a plain square).
fn generate_counted(family: Family, seed: u64) -> (Domain, u64) {
    let extreme = seed % 4 == 0;
    for draw in 0..MAX_DRAWS {
        let mut rng = SplitMix64::new(mix(seed ^ mix(draw.wrapping_add(family as u64 * 1000))));
        let Some((loops, description)) = draw_family(family, &mut rng, extreme) else {
            continue;
        };
        let loops = transform(&mut rng, loops);
        if let Some(boundary) = assemble(&loops) {
            let domain = Domain {
                name: format!("{}_{seed:016x}", family.name()),
                family,
                seed,
                description,
                boundary,
            };
            return (domain, draw + 1);
        }
    }
    let domain = Domain {
        name: format!("{}_{seed:016x}", family.name()),
        family,
        seed,
        description: "fallback square".into(),
        boundary: Boundary::unit_square(4),
    };
    (domain, MAX_DRAWS + 1)
}

/// `n` domains, the families in turn, each family drawing consecutive
/// seeds from its own start (so every four domains of a family include one
/// with extreme parameters). Named `NNN_family_seed`.
pub fn suite_domains(n: usize, seed: u64) -> Vec<Domain> {
    families_suite(&Family::ALL, n, seed)
}

/// [`suite_domains`] over the [`Family::REAL_LIKE`] families: thin bands
/// of unequal counts, zig-zag outlines, tube sheets and graded sides.
pub fn real_like_domains(n: usize, seed: u64) -> Vec<Domain> {
    families_suite(&Family::REAL_LIKE, n, seed)
}

fn families_suite(families: &[Family], n: usize, seed: u64) -> Vec<Domain> {
    let starts: Vec<u64> = families
        .iter()
        .map(|&f| mix(seed ^ mix(f as u64 + 0x5EED)))
        .collect();
    (0..n)
        .map(|i| {
            let f = i % families.len();
            let k = (i / families.len()) as u64;
            let mut d = generate(families[f], starts[f].wrapping_add(k));
            d.name = format!("{i:03}_{}", d.name);
            d
        })
        .collect()
}

/// [`suite_domains`] as (name, boundary) pairs.
pub fn suite(n: usize, seed: u64) -> Vec<(String, Boundary)> {
    suite_domains(n, seed)
        .into_iter()
        .map(|d| (d.name, d.boundary))
        .collect()
}

// ---------------------------------------------------------------------
// Loops as pieces of lines and arcs, discretised by a size along them.

#[derive(Clone, Copy, Debug)]
enum Path {
    Line(Point, Point),
    /// Counter-clockwise from angle `a0` to `a1` (radians) when `a1 > a0`.
    Arc {
        c: Point,
        r: f64,
        a0: f64,
        a1: f64,
    },
}

impl Path {
    fn length(&self) -> f64 {
        match *self {
            Path::Line(a, b) => a.distance(b),
            Path::Arc { r, a0, a1, .. } => r * (a1 - a0).abs(),
        }
    }

    fn at(&self, t: f64) -> Point {
        match *self {
            Path::Line(a, b) => a + (b - a) * t,
            Path::Arc { c, r, a0, a1 } => {
                let a = a0 + (a1 - a0) * t;
                c + Point::new(a.cos(), a.sin()) * r
            }
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Piece {
    path: Path,
    /// A fixed number of segments; `None`: from the size.
    segments: Option<usize>,
}

fn line(a: Point, b: Point) -> Piece {
    Piece {
        path: Path::Line(a, b),
        segments: None,
    }
}

fn fixed(a: Point, b: Point, n: usize) -> Piece {
    Piece {
        path: Path::Line(a, b),
        segments: Some(n.max(1)),
    }
}

/// Target segment length along a loop, by the fraction `s` of its
/// perimeter.
#[derive(Clone, Copy, Debug)]
enum Size {
    Uniform(f64),
    /// From `h_min` at `s = phase` smoothly up to `h_min * ratio` half a
    /// loop away.
    Graded {
        h_min: f64,
        ratio: f64,
        phase: f64,
    },
}

impl Size {
    fn at(&self, s: f64) -> f64 {
        match *self {
            Size::Uniform(h) => h,
            Size::Graded {
                h_min,
                ratio,
                phase,
            } => h_min * ratio.powf(0.5 * (1.0 - (TAU * (s - phase)).cos())),
        }
    }
}

struct LoopSpec {
    pieces: Vec<Piece>,
    size: Size,
}

fn polygon(vertices: &[Point], size: Size) -> LoopSpec {
    let n = vertices.len();
    LoopSpec {
        pieces: (0..n)
            .map(|k| line(vertices[k], vertices[(k + 1) % n]))
            .collect(),
        size,
    }
}

fn rect_vertices(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
    vec![
        Point::new(x0, y0),
        Point::new(x1, y0),
        Point::new(x1, y1),
        Point::new(x0, y1),
    ]
}

fn circle(c: Point, r: f64, start: f64, size: Size) -> LoopSpec {
    LoopSpec {
        pieces: vec![Piece {
            path: Path::Arc {
                c,
                r,
                a0: start,
                a1: start + TAU,
            },
            segments: None,
        }],
        size,
    }
}

/// Samples per piece for the size integral.
const SAMPLES: usize = 512;

/// The nodes of a loop: every piece starts at a node, its segment count is
/// its integral of `1 / size` rounded (at least 1, or as fixed), the total
/// is made even (and at least 4) by adding a segment to the free piece
/// that is coarsest relative to its size, and nodes sit at equal steps of
/// the integral.
fn discretise(spec: &LoopSpec) -> Vec<Point> {
    let lens: Vec<f64> = spec.pieces.iter().map(|p| p.path.length()).collect();
    let total: f64 = lens.iter().sum();
    let mut start = 0.0;
    let mut tables = Vec::with_capacity(spec.pieces.len());
    for &len in &lens {
        let mut cum = Vec::with_capacity(SAMPLES + 1);
        cum.push(0.0);
        let mut prev = 1.0 / spec.size.at(start / total);
        for j in 1..=SAMPLES {
            let s = start + len * j as f64 / SAMPLES as f64;
            let cur = 1.0 / spec.size.at(s / total);
            cum.push(cum[j - 1] + 0.5 * (prev + cur) * len / SAMPLES as f64);
            prev = cur;
        }
        tables.push(cum);
        start += len;
    }
    let phi = |k: usize| tables[k][SAMPLES];
    let mut counts: Vec<usize> = spec
        .pieces
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let closed =
                matches!(p.path, Path::Arc { a0, a1, .. } if (a1 - a0).abs() >= TAU - 1e-12);
            let least = if closed { 3 } else { 1 };
            p.segments
                .unwrap_or_else(|| (phi(k).round() as usize).max(least))
        })
        .collect();
    let bump = |counts: &mut Vec<usize>| {
        let free = (0..counts.len()).filter(|&k| spec.pieces[k].segments.is_none());
        let k = free
            .max_by(|&a, &b| (phi(a) / counts[a] as f64).total_cmp(&(phi(b) / counts[b] as f64)))
            .unwrap_or(0);
        counts[k] += 1;
    };
    while counts.iter().sum::<usize>() < 4 {
        bump(&mut counts);
    }
    if counts.iter().sum::<usize>() % 2 == 1 {
        bump(&mut counts);
    }
    let mut pts = Vec::with_capacity(counts.iter().sum());
    for (k, piece) in spec.pieces.iter().enumerate() {
        let cum = &tables[k];
        let n = counts[k];
        for i in 0..n {
            let target = phi(k) * i as f64 / n as f64;
            let j = cum.partition_point(|&c| c <= target).clamp(1, SAMPLES) - 1;
            let step = cum[j + 1] - cum[j];
            let frac = if step > 0.0 {
                ((target - cum[j]) / step).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t = if i == 0 {
                0.0
            } else {
                (j as f64 + frac) / SAMPLES as f64
            };
            pts.push(piece.path.at(t));
        }
    }
    pts
}

/// A random similarity (scale over three decades, any rotation, a shift)
/// applied to every loop's nodes, after discretising.
fn transform(rng: &mut SplitMix64, loops: Vec<Vec<Point>>) -> Vec<Vec<Point>> {
    let scale = rng.log_uni(0.1, 100.0);
    let turn = if rng.chance(0.5) {
        rng.uni(0.0, TAU)
    } else {
        0.0
    };
    let rot = Point::new(turn.cos(), turn.sin()) * scale;
    let shift = Point::new(rng.uni(-100.0, 100.0), rng.uni(-100.0, 100.0)) * scale;
    loops
        .into_iter()
        .map(|l| l.into_iter().map(|p| rot.rotate(p) + shift).collect())
        .collect()
}

/// The validated boundary of discretised loops (each of even length), or
/// `None` when they are not a valid domain.
fn assemble(loops: &[Vec<Point>]) -> Option<Boundary> {
    if loops.iter().any(|l| l.len() % 2 == 1 || l.len() < 4) {
        return None;
    }
    let mut points = Vec::new();
    let mut ids = Vec::with_capacity(loops.len());
    for l in loops {
        ids.push((points.len()..points.len() + l.len()).collect());
        points.extend_from_slice(l);
    }
    Boundary::new(points, ids, None).ok()
}

// ---------------------------------------------------------------------
// Building blocks.

/// An axis-aligned box.
#[derive(Clone, Copy, Debug)]
struct Bx {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

impl Bx {
    fn w(&self) -> f64 {
        self.x1 - self.x0
    }
    fn h(&self) -> f64 {
        self.y1 - self.y0
    }
    fn inset(&self, m: f64) -> Bx {
        Bx {
            x0: self.x0 + m,
            y0: self.y0 + m,
            x1: self.x1 - m,
            y1: self.y1 - m,
        }
    }
    /// `n` boxes side by side along the longer axis, apart by `gap`.
    fn split(&self, n: usize, gap: f64) -> Vec<Bx> {
        let n = n.max(1);
        let horizontal = self.w() >= self.h();
        let len = if horizontal { self.w() } else { self.h() };
        let part = (len - gap * (n - 1) as f64) / n as f64;
        (0..n)
            .map(|k| {
                let a = k as f64 * (part + gap);
                if horizontal {
                    Bx {
                        x0: self.x0 + a,
                        x1: self.x0 + a + part,
                        ..*self
                    }
                } else {
                    Bx {
                        y0: self.y0 + a,
                        y1: self.y0 + a + part,
                        ..*self
                    }
                }
            })
            .collect()
    }
}

/// `k` holes in `bx` on a jittered grid, one per cell: circles (60 %) and
/// regular polygons of 3 to 8 sides, of varied radii; holes in neighbouring
/// cells are apart by at least a tenth of a cell. Segment length about
/// `h` (finer on small holes).
fn holes_in_box(rng: &mut SplitMix64, bx: Bx, k: usize, h: f64) -> Vec<LoopSpec> {
    if k == 0 || bx.w() <= 0.0 || bx.h() <= 0.0 {
        return Vec::new();
    }
    let nx = ((k as f64 * bx.w() / bx.h()).sqrt().ceil() as usize).clamp(1, k);
    let ny = k.div_ceil(nx);
    let (cw, ch) = (bx.w() / nx as f64, bx.h() / ny as f64);
    let mut cells: Vec<usize> = (0..nx * ny).collect();
    for i in (1..cells.len()).rev() {
        let j = rng.int(0, i);
        cells.swap(i, j);
    }
    let s = 0.05 * cw.min(ch);
    cells
        .into_iter()
        .take(k)
        .map(|cell| {
            let (cx, cy) = ((cell % nx) as f64, (cell / nx) as f64);
            let room = 0.5 * cw.min(ch) - s;
            let r = room * rng.uni(0.3, 1.0);
            let jx = (0.5 * cw - s - r).max(0.0);
            let jy = (0.5 * ch - s - r).max(0.0);
            let c = Point::new(
                bx.x0 + (cx + 0.5) * cw + rng.uni(-jx, jx),
                bx.y0 + (cy + 0.5) * ch + rng.uni(-jy, jy),
            );
            let hh = (h * rng.uni(0.3, 1.2)).min(TAU * r / 6.0);
            if rng.chance(0.6) {
                circle(c, r, rng.uni(0.0, TAU), Size::Uniform(hh))
            } else {
                let sides = rng.int(3, 8);
                let rot = rng.uni(0.0, TAU);
                let v: Vec<Point> = (0..sides)
                    .map(|i| {
                        let a = rot + TAU * i as f64 / sides as f64;
                        c + Point::new(a.cos(), a.sin()) * r
                    })
                    .collect();
                polygon(&v, Size::Uniform(hh))
            }
        })
        .collect()
}

/// A slot (a thin rectangular hole) of length to width `ratio` along the
/// longer side of `bx`, 1 or 2 segments across.
fn slot_in_box(rng: &mut SplitMix64, bx: Bx, ratio: f64) -> LoopSpec {
    let horizontal = bx.w() >= bx.h();
    let (long, short) = if horizontal {
        (bx.w(), bx.h())
    } else {
        (bx.h(), bx.w())
    };
    let mut l = long * rng.uni(0.5, 0.95);
    if l / ratio > 0.4 * short {
        l = 0.4 * short * ratio;
    }
    let w = l / ratio;
    let a = rng.uni(0.0, long - l);
    let b = rng.uni(0.0, short - w);
    let across = rng.int(1, 2);
    let h = (w * rng.uni(1.0, 8.0)).min(l / 3.0);
    let (x0, y0, x1, y1) = if horizontal {
        (bx.x0 + a, bx.y0 + b, bx.x0 + a + l, bx.y0 + b + w)
    } else {
        (bx.x0 + b, bx.y0 + a, bx.x0 + b + w, bx.y0 + a + l)
    };
    let v = rect_vertices(x0, y0, x1, y1);
    let mut pieces: Vec<Piece> = (0..4).map(|k| line(v[k], v[(k + 1) % 4])).collect();
    let cross = if horizontal { [1, 3] } else { [0, 2] };
    for k in cross {
        pieces[k].segments = Some(across);
    }
    LoopSpec {
        pieces,
        size: Size::Uniform(h),
    }
}

/// Two holes in `bx` whose facing sides are `f` times their segment
/// length apart: two squares (the second shifted along the gap) or two
/// circles with a node each on the line between their centres.
fn near_pair_in_box(rng: &mut SplitMix64, bx: Bx, f: f64) -> Vec<LoopSpec> {
    let horizontal = bx.w() >= bx.h();
    let (long, short) = if horizontal {
        (bx.w(), bx.h())
    } else {
        (bx.h(), bx.w())
    };
    // Local frame: along = the long axis of the box.
    let place = |u: f64, v: f64| {
        if horizontal {
            Point::new(bx.x0 + u, bx.y0 + v)
        } else {
            Point::new(bx.x0 + v, bx.y0 + u)
        }
    };
    let a = (0.45 * long).min(0.8 * short) * rng.uni(0.4, 1.0);
    if rng.chance(0.5) {
        let n = rng.int(2, 6);
        let h = a / n as f64;
        let g = f * h;
        let u0 = rng.uni(0.0, (long - 2.0 * a - g).max(0.0));
        let v0 = rng.uni(0.0, short - a);
        let shift = (rng.uni(-0.5, 0.5) * a).clamp(-v0, short - a - v0);
        let sq = |u: f64, v: f64| {
            let p = [
                place(u, v),
                place(u + a, v),
                place(u + a, v + a),
                place(u, v + a),
            ];
            polygon(&p, Size::Uniform(h))
        };
        vec![sq(u0, v0), sq(u0 + a + g, v0 + shift)]
    } else {
        let r1 = 0.5 * a;
        let r2 = r1 * rng.uni(0.5, 1.0);
        let n1 = 2 * rng.int(3, 12);
        let h = TAU * r1 / n1 as f64;
        // The facing segments are chords.
        let g = f * 2.0 * r1 * (PI / n1 as f64).sin();
        let u1 = rng.uni(r1, (long - r1 - g - 2.0 * r2).max(r1));
        let v1 = short * 0.5;
        let c1 = place(u1, v1);
        let c2 = place(u1 + r1 + g + r2, v1);
        let toward = if horizontal { 0.0 } else { 0.5 * PI };
        vec![
            circle(c1, r1, toward, Size::Uniform(h)),
            circle(c2, r2, toward + PI, Size::Uniform(TAU * r2 / n1 as f64)),
        ]
    }
}

/// Offsets an open polyline by `±w/2` into a closed channel outline
/// (mitred corners).
fn thicken(path: &[Point], w: f64) -> Vec<Point> {
    let n = path.len();
    let normal = |a: Point, b: Point| (b - a).normalize().perp();
    let offset = |k: usize| -> Point {
        if k == 0 {
            normal(path[0], path[1])
        } else if k == n - 1 {
            normal(path[n - 2], path[n - 1])
        } else {
            let (n1, n2) = (normal(path[k - 1], path[k]), normal(path[k], path[k + 1]));
            (n1 + n2) / (1.0 + n1.dot(n2))
        }
    };
    let d = 0.5 * w;
    let mut out: Vec<Point> = (0..n).map(|k| path[k] + offset(k) * d).collect();
    out.extend((0..n).rev().map(|k| path[k] - offset(k) * d));
    out
}

/// Radius of the valleys of a `k`-pointed star of tip radius `big` whose
/// tips have angle `alpha`.
fn star_valley(big: f64, k: usize, alpha: f64) -> f64 {
    let t = (0.5 * alpha).tan();
    let q = PI / k as f64;
    big * t / (q.sin() + t * q.cos())
}

/// The outline of a rectangle `w × h` whose top side carries `m` teeth of
/// tip angle `alpha` (symmetric, or right-angled with a vertical side),
/// with the tooth height.
fn sawtooth(w: f64, h: f64, m: usize, alpha: f64, right: bool) -> (Vec<Point>, f64) {
    let b = w / m as f64;
    let t = if right {
        b / alpha.tan()
    } else {
        0.5 * b / (0.5 * alpha).tan()
    };
    let mut v = vec![Point::new(0.0, 0.0), Point::new(w, 0.0)];
    for i in (0..m).rev() {
        let x0 = i as f64 * b;
        if right {
            // Up the vertical side (straight on from the outer side for
            // the first tooth), down the slant to the next tooth's foot.
            if i != m - 1 {
                v.push(Point::new(x0 + b, h));
            }
            v.push(Point::new(x0 + b, h + t));
        } else {
            v.push(Point::new(x0 + b, h));
            v.push(Point::new(x0 + 0.5 * b, h + t));
        }
    }
    v.push(Point::new(0.0, h));
    (v, t)
}

/// The outline of the rectangle `w × h` with `tips.len()` V notches cut
/// down from its top side: notch `i` has its tip at `(x, h - depth)` and
/// angle `alpha`.
fn notched(w: f64, h: f64, tips: &[(f64, f64)], alpha: f64) -> Vec<Point> {
    let mut v = vec![Point::new(0.0, 0.0), Point::new(w, 0.0), Point::new(w, h)];
    let mut sorted = tips.to_vec();
    sorted.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (x, depth) in sorted {
        let half = depth * (0.5 * alpha).tan();
        v.push(Point::new(x + half, h));
        v.push(Point::new(x, h - depth));
        v.push(Point::new(x - half, h));
    }
    v.push(Point::new(0.0, h));
    v
}

// ---------------------------------------------------------------------
// The families.

type Drawn = Option<(Vec<Vec<Point>>, String)>;

fn finish(specs: &[LoopSpec], description: String) -> Drawn {
    Some((specs.iter().map(discretise).collect(), description))
}

fn draw_family(family: Family, rng: &mut SplitMix64, extreme: bool) -> Drawn {
    match family {
        Family::ManyHoles => many_holes(rng, extreme),
        Family::Channel => channel(rng, extreme),
        Family::Graded => graded(rng, extreme),
        Family::Spikes => spikes(rng, extreme),
        Family::NearTouching => near_touching(rng, extreme),
        Family::Unbalanced => unbalanced(rng, extreme),
        Family::Mixed => mixed(rng, extreme),
        Family::Band => band(rng, extreme),
        Family::Zigzag => zigzag(rng, extreme),
        Family::TubeSheet => tube_sheet(rng, extreme),
        Family::GradedSide => graded_side(rng, extreme),
    }
}

/// `n` points on the circle of centre `c` and radius `r`, from angle `a0`,
/// counter-clockwise (`ccw`) or clockwise.
fn ring_points(c: Point, r: f64, n: usize, a0: f64, ccw: bool) -> Vec<Point> {
    let sign = if ccw { 1.0 } else { -1.0 };
    (0..n)
        .map(|k| {
            let a = a0 + sign * TAU * k as f64 / n as f64;
            c + Point::new(a.cos(), a.sin()) * r
        })
        .collect()
}

/// The even number nearest `x`, at least `least`.
fn even(x: f64, least: usize) -> usize {
    ((x / 2.0).round() as usize * 2).max(least)
}

fn band(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let n_outer = even(rng.uni(60.0, 400.0), 8);
    let apart = if extreme { 0.15 } else { rng.uni(0.02, 0.15) };
    let finer = rng.chance(0.5);
    let h = TAU / n_outer as f64;
    let gap = if extreme { 0.7 } else { rng.uni(0.7, 3.0) } * h;
    if rng.chance(0.5) {
        // A ring: two circles.
        let n_inner = even(
            n_outer as f64 * if finer { 1.0 + apart } else { 1.0 - apart },
            8,
        );
        let outer = ring_points(Point::ZERO, 1.0, n_outer, 0.0, true);
        let inner = ring_points(Point::ZERO, 1.0 - gap, n_inner, rng.uni(0.0, TAU), false);
        Some((
            vec![outer, inner],
            format!(
                "ring band {gap:.4} wide ({:.2} sizes), {n_outer} against {n_inner} nodes",
                gap / h
            ),
        ))
    } else {
        // A sliver between two arcs, closed by one segment at each end.
        let sweep = rng.uni(0.5, 1.6);
        let m_outer = ((sweep / h).round() as usize).max(4);
        let m_inner = ((m_outer as f64 * if finer { 1.0 + apart } else { 1.0 - apart }).round()
            as usize)
            .max(2);
        // The loop has m_outer + m_inner + 2 nodes: one more on the inner
        // arc when that is odd.
        let m_inner = m_inner + (m_outer + m_inner) % 2;
        let m_inner = match m_inner.cmp(&m_outer) {
            std::cmp::Ordering::Equal if finer => m_inner + 2,
            std::cmp::Ordering::Equal => m_inner - 2,
            _ => m_inner,
        };
        let r_in = 1.0 - gap;
        let mut pts: Vec<Point> = (0..=m_outer)
            .map(|k| {
                let a = sweep * k as f64 / m_outer as f64;
                Point::new(a.cos(), a.sin())
            })
            .collect();
        pts.extend((0..=m_inner).map(|k| {
            let a = sweep * (1.0 - k as f64 / m_inner as f64);
            Point::new(a.cos(), a.sin()) * r_in
        }));
        Some((
            vec![pts],
            format!(
                "sliver band {gap:.4} wide ({:.2} sizes) over {sweep:.2} rad, {m_outer} against {m_inner} segments",
                gap / h
            ),
        ))
    }
}

/// A hexagon's outline as a zig-zag: each of its six sides is `teeth`
/// zigs and zags at ±30° to the side (so every turn is 120° in or out),
/// each cut into `cuts` segments, counter-clockwise (`ccw`) or clockwise.
fn zigzag_hexagon(radius: f64, teeth: usize, cuts: usize, ccw: bool) -> Vec<Point> {
    let corners: Vec<Point> = (0..6)
        .map(|k| {
            let a = TAU * k as f64 / 6.0;
            Point::new(a.cos(), a.sin()) * radius
        })
        .collect();
    let mut pts = Vec::new();
    for k in 0..6 {
        let (a, b) = (corners[k], corners[(k + 1) % 6]);
        let along = (b - a) / (2 * teeth) as f64;
        // Outwards, for a counter-clockwise hexagon: the side's right.
        let out = Point::new(along.y, -along.x) * (30f64.to_radians().tan());
        for z in 0..2 * teeth {
            let p = a + along * z as f64 + if z % 2 == 1 { out } else { Point::ZERO };
            let q = a + along * (z + 1) as f64 + if z % 2 == 0 { out } else { Point::ZERO };
            for c in 0..cuts {
                pts.push(p + (q - p) * (c as f64 / cuts as f64));
            }
        }
    }
    if !ccw {
        pts.reverse();
    }
    pts
}

fn zigzag(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let teeth = rng.int(2, 6);
    let cuts = if extreme { 1 } else { rng.int(1, 4) };
    let outer = zigzag_hexagon(1.0, teeth, cuts, true);
    let zig = 1.0 / (2 * teeth) as f64 / 30f64.to_radians().cos();
    let h = zig / cuts as f64;
    let r_hole = rng.uni(0.3, 0.6);
    let hole = if rng.chance(0.5) {
        let teeth_in = ((teeth as f64 * r_hole).round() as usize).max(1);
        let cuts_in = rng.int(1, 4);
        zigzag_hexagon(r_hole, teeth_in, cuts_in, false)
    } else {
        let n = even(TAU * r_hole / h, 8);
        ring_points(Point::ZERO, r_hole, n, 0.0, false)
    };
    let mut description = format!(
        "zig-zag hexagon, {teeth} teeth a side, {cuts} segments a zig, hole radius {r_hole:.2}"
    );
    let outer = if extreme || rng.chance(0.5) {
        let (outer, slits) = with_slits(rng, &outer, zig, extreme);
        description += &slits;
        outer
    } else {
        outer
    };
    Some((vec![outer, hole], description))
}

/// Slits between the assemblies of a zig-zag outline (`zig` the length of
/// a zig): at each outward tip, by chance, a dead-end slit going out along
/// the tip's bisector, or a slit forking at its end into two dead ends at
/// ±60° (a Y), each `1/40` to `1/20` of a zig wide with single-segment
/// walls half to one zig long, as between the hexagonal assemblies of a
/// reactor core. Every tip has one in the extreme case. The number of
/// dead-end slits is kept even (each adds 3 nodes, a Y 8). Returns the
/// outline and a description.
fn with_slits(
    rng: &mut SplitMix64,
    outline: &[Point],
    zig: f64,
    extreme: bool,
) -> (Vec<Point>, String) {
    let n = outline.len();
    let width = zig
        * if extreme {
            1.0 / 40.0
        } else {
            rng.uni(1.0 / 40.0, 1.0 / 20.0)
        };
    let tip = |k: usize| {
        let (a, b, c) = (outline[(k + n - 1) % n], outline[k], outline[(k + 1) % n]);
        // An outward tip of a counter-clockwise outline turns left by 60°.
        let turn = (b - a).angle_to(c - b).to_degrees();
        (turn - 60.0).abs() < 1e-6
    };
    // Per tip: 0 none, 1 a dead end, 2 a Y.
    let mut kind: Vec<u8> = (0..n)
        .map(|k| match (tip(k), extreme) {
            (false, _) => 0,
            (true, true) => 1 + u8::from(rng.chance(0.4)),
            (true, false) => {
                let x = rng.unit();
                u8::from(x < 0.6) + u8::from(x < 0.25)
            }
        })
        .collect();
    if kind.iter().filter(|&&k| k == 1).count() % 2 == 1 {
        if let Some(last) = kind.iter().rposition(|&k| k == 1) {
            kind[last] = 0;
        }
    }
    let mut pts = Vec::with_capacity(n + 8 * kind.iter().filter(|&&k| k > 0).count());
    for k in 0..n {
        if kind[k] == 0 {
            pts.push(outline[k]);
            continue;
        }
        let (prev, b, next) = (outline[(k + n - 1) % n], outline[k], outline[(k + 1) % n]);
        let length = zig * rng.uni(0.5, 1.0);
        let branch = zig * rng.uni(0.4, 0.7);
        pts.extend(slit(
            prev,
            b,
            next,
            width,
            length,
            (kind[k] == 2).then_some(branch),
        ));
    }
    let count = |v: u8| kind.iter().filter(|&&k| k == v).count();
    let text = format!(
        ", {} dead-end slits and {} Y slits {:.4} wide ({:.0} to a zig)",
        count(1),
        count(2),
        width,
        zig / width
    );
    (pts, text)
}

/// The points that replace the convex corner `tip` (between `prev` and
/// `next`, counter-clockwise) of an outline when a slit `width` wide goes
/// out from it along its bisector for `length`: a dead end (4 points), or
/// with `branch`, a fork into two dead ends `branch` long at ±60° whose
/// three channels meet in a triangular hub (9 points). Each wall is one
/// segment.
pub fn slit(
    prev: Point,
    tip: Point,
    next: Point,
    width: f64,
    length: f64,
    branch: Option<f64>,
) -> Vec<Point> {
    let (to_prev, to_next) = ((prev - tip).normalize(), (next - tip).normalize());
    let out = -(to_prev + to_next).normalize();
    let half_angle = to_prev.angle_to(-out).abs();
    let h = width / 2.0;
    let t = h / half_angle.sin();
    // The mouth: on the edge from prev (the right, looking out) and on the
    // edge to next (the left).
    let (m_r, m_l) = (tip + to_prev * t, tip + to_next * t);
    let Some(branch) = branch else {
        return vec![m_r, m_r + out * length, m_l + out * length, m_l];
    };
    let dir = |deg: f64| {
        let a = out.y.atan2(out.x) + deg.to_radians();
        Point::new(a.cos(), a.sin())
    };
    let o = (m_r + m_l) * 0.5 + out * length;
    let r = h / 60f64.to_radians().sin();
    let left_of = |u: Point| Point::new(-u.y, u.x);
    let (u_r, u_l) = (dir(-60.0), dir(60.0));
    vec![
        m_r,
        o + dir(-120.0) * r,
        o + u_r * branch - left_of(u_r) * h,
        o + u_r * branch + left_of(u_r) * h,
        o + dir(0.0) * r,
        o + u_l * branch - left_of(u_l) * h,
        o + u_l * branch + left_of(u_l) * h,
        o + dir(120.0) * r,
        m_l,
    ]
}

fn tube_sheet(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let k = if extreme { 14 } else { rng.int(4, 14) };
    let per_hole = 2 * rng.int(4, 8);
    // Ligament width in hole segments.
    let lig = if extreme { 1.2 } else { rng.uni(1.2, 4.0) };
    // Pitch 1: hole segment length h = 2πr / per_hole, ligament 1 - 2r.
    let r = 1.0 / (2.0 + lig * TAU / per_hole as f64);
    let h = TAU * r / per_hole as f64;
    let w = k as f64;
    let side = ((1.0 / h).round() as usize).max(1) * k;
    let t = |i: usize| w * i as f64 / side as f64;
    let mut outer: Vec<Point> = Vec::new();
    outer.extend((0..side).map(|i| Point::new(t(i), 0.0)));
    outer.extend((0..side).map(|i| Point::new(w, t(i))));
    outer.extend((0..side).map(|i| Point::new(w - t(i), w)));
    outer.extend((0..side).map(|i| Point::new(0.0, w - t(i))));
    let mut loops = vec![outer];
    for i in 0..k {
        for j in 0..k {
            let c = Point::new(i as f64 + 0.5, j as f64 + 0.5);
            loops.push(ring_points(c, r, per_hole, 0.0, false));
        }
    }
    Some((
        loops,
        format!(
            "tube sheet, {} holes of {per_hole} nodes, ligament {lig:.2} sizes",
            k * k
        ),
    ))
}

fn graded_side(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let ratio = if extreme {
        100.0
    } else {
        rng.log_uni(10.0, 100.0)
    };
    let (w, hgt) = (rng.uni(1.0, 3.0), rng.uni(0.5, 1.5));
    let n_side = rng.int(6, 20);
    let h = hgt / n_side as f64;
    // The bottom side: segments growing geometrically from h / ratio at
    // both ends to the middle, as long as the side asks.
    let grow: f64 = rng.uni(1.1, 1.4);
    let mut half: Vec<f64> = Vec::new();
    let mut len = h / ratio;
    let mut sum = 0.0;
    while sum + len < 0.5 * w {
        half.push(len);
        sum += len;
        len = (len * grow).min(h * 3.0);
    }
    let scale = 0.5 * w / sum;
    let mut segs: Vec<f64> = half.iter().map(|l| l * scale).collect();
    let mirrored: Vec<f64> = segs.iter().rev().copied().collect();
    segs.extend(mirrored);
    let mut bottom = vec![Point::new(0.0, 0.0)];
    let mut x = 0.0;
    for l in &segs[..segs.len() - 1] {
        x += l;
        bottom.push(Point::new(x, 0.0));
    }
    let n_top = ((w / h).round() as usize).max(2);
    let mut pts = bottom;
    let skew = rng.uni(-0.3, 0.3) * w;
    let corners = [
        Point::new(w, 0.0),
        Point::new(w + skew, hgt),
        Point::new(skew, hgt),
    ];
    pts.extend(
        (0..n_side).map(|k| corners[0] + (corners[1] - corners[0]) * (k as f64 / n_side as f64)),
    );
    pts.extend(
        (0..n_top).map(|k| corners[1] + (corners[2] - corners[1]) * (k as f64 / n_top as f64)),
    );
    let n_left = n_side + (pts.len() + n_side) % 2;
    pts.extend(
        (0..n_left).map(|k| corners[2] + (Point::ZERO - corners[2]) * (k as f64 / n_left as f64)),
    );
    Some((
        vec![pts],
        format!(
            "graded side 1:{ratio:.0} over {} segments, {n_side} on the sides, {n_top} on top",
            segs.len()
        ),
    ))
}

fn many_holes(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let k = if extreme { 30 } else { rng.int(1, 30) };
    let (w, h) = (rng.uni(1.0, 3.0), 1.0);
    let ho = rng.log_uni(0.03, 0.12);
    let outer = polygon(&rect_vertices(0.0, 0.0, w, h), Size::Uniform(ho));
    let inner = Bx {
        x0: 0.0,
        y0: 0.0,
        x1: w,
        y1: h,
    }
    .inset(ho.max(0.03));
    let mut specs = vec![outer];
    specs.extend(holes_in_box(rng, inner, k, ho));
    finish(
        &specs,
        format!("{k} holes in a {w:.2} x 1 plate, h {ho:.3}"),
    )
}

fn channel(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let ratio = if extreme { 50.0 } else { rng.uni(5.0, 50.0) };
    match rng.int(0, 2) {
        0 => {
            let (w, h) = (rng.uni(1.5, 3.0), rng.uni(0.5, 1.5));
            let ho = rng.log_uni(0.04, 0.15) * h;
            let outer = polygon(&rect_vertices(0.0, 0.0, w, h), Size::Uniform(ho));
            let inner = Bx {
                x0: 0.0,
                y0: 0.0,
                x1: w,
                y1: h,
            }
            .inset(ho.max(0.05 * h));
            let slot = slot_in_box(rng, inner, ratio);
            finish(&[outer, slot], format!("slot 1:{ratio:.1} in a plate"))
        }
        1 => {
            let across = rng.int(1, 4);
            let l = ratio;
            let hs = rng.uni(0.7, 2.0) / across as f64;
            let v = rect_vertices(0.0, 0.0, l, 1.0);
            let spec = LoopSpec {
                pieces: vec![
                    line(v[0], v[1]),
                    fixed(v[1], v[2], across),
                    line(v[2], v[3]),
                    fixed(v[3], v[0], across),
                ],
                size: Size::Uniform(hs),
            };
            finish(
                &[spec],
                format!("straight channel 1:{ratio:.1}, {across} across"),
            )
        }
        _ => {
            let legs = rng.int(2, 4);
            let w = 1.0;
            let leg = ratio * w;
            let pitch = w + w * rng.uni(0.5, 3.0);
            let mut path = Vec::with_capacity(2 * legs);
            for i in 0..legs {
                let y = i as f64 * pitch;
                let (a, b) = if i % 2 == 0 { (0.0, leg) } else { (leg, 0.0) };
                path.push(Point::new(a, y));
                path.push(Point::new(b, y));
            }
            let outline = thicken(&path, w);
            let across = rng.int(1, 3);
            let h = w / across as f64 * rng.uni(0.8, 2.5);
            finish(
                &[polygon(&outline, Size::Uniform(h))],
                format!("serpentine channel of {legs} legs 1:{ratio:.1}"),
            )
        }
    }
}

fn graded(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let ratio = if extreme {
        115.0
    } else {
        rng.log_uni(5.0, 100.0)
    };
    let phase = rng.unit();
    let variant = rng.int(0, 3);
    let (verts, name): (Option<Vec<Point>>, &str) = match variant {
        0 => (
            Some(rect_vertices(0.0, 0.0, rng.uni(1.0, 3.0), 1.0)),
            "rectangle",
        ),
        1 => {
            let (a, b) = (rng.uni(0.3, 0.7), rng.uni(0.3, 0.7));
            (
                Some(vec![
                    Point::new(0.0, 0.0),
                    Point::new(1.0, 0.0),
                    Point::new(1.0, a),
                    Point::new(b, a),
                    Point::new(b, 1.0),
                    Point::new(0.0, 1.0),
                ]),
                "L-shape",
            )
        }
        2 => (None, "circle"),
        _ => (Some(rect_vertices(0.0, 0.0, 2.0, 1.0)), "plate with a hole"),
    };
    let perimeter = verts.as_ref().map_or(TAU * 0.5, |v| {
        (0..v.len())
            .map(|k| v[k].distance(v[(k + 1) % v.len()]))
            .sum()
    });
    let h_max = perimeter / rng.uni(8.0, 20.0);
    let size = Size::Graded {
        h_min: h_max / ratio,
        ratio,
        phase,
    };
    let mut specs = vec![match &verts {
        Some(v) => polygon(v, size),
        None => circle(Point::new(0.5, 0.5), 0.5, rng.uni(0.0, TAU), size),
    }];
    if variant == 3 {
        let r = rng.uni(0.15, 0.35);
        let c = Point::new(rng.uni(0.5, 1.5), 0.5);
        let hh = rng.log_uni(h_max / ratio, h_max).min(TAU * r / 6.0);
        specs.push(circle(c, r, rng.uni(0.0, TAU), Size::Uniform(hh)));
    }
    finish(&specs, format!("{name} graded 1:{ratio:.0}"))
}

fn spikes(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let alpha_deg = if extreme { 5.0 } else { rng.uni(5.0, 40.0) };
    let alpha = alpha_deg.to_radians();
    match rng.int(0, 2) {
        0 => {
            let k = rng.int(3, 16);
            let big = 1.0;
            let valley = star_valley(big, k, alpha);
            let v: Vec<Point> = (0..2 * k)
                .map(|i| {
                    let a = PI * i as f64 / k as f64;
                    let r = if i % 2 == 0 { big } else { valley };
                    Point::new(a.cos(), a.sin()) * r
                })
                .collect();
            let h = (big - valley) / rng.uni(4.0, 16.0);
            finish(
                &[polygon(&v, Size::Uniform(h))],
                format!("{k}-pointed star, tips {alpha_deg:.1}°"),
            )
        }
        1 => {
            let w = rng.uni(1.0, 3.0);
            let right = rng.chance(0.4);
            let t_max = rng.uni(0.5, 2.0) * w;
            let per_tooth = if right {
                alpha.tan() * t_max
            } else {
                2.0 * (0.5 * alpha).tan() * t_max
            };
            let m = ((w / per_tooth).ceil() as usize).clamp(2, 16);
            let (v, t) = sawtooth(w, rng.uni(0.3, 1.0), m, alpha, right);
            let h = t / rng.uni(5.0, 16.0);
            finish(
                &[polygon(&v, Size::Uniform(h))],
                format!(
                    "{m} {} teeth, tips {alpha_deg:.1}°",
                    if right { "right-angled" } else { "symmetric" }
                ),
            )
        }
        _ => {
            let (w, hgt) = (rng.uni(1.0, 3.0), 1.0);
            let widest = 2.4 * 0.7 * hgt * (0.5 * alpha).tan();
            let n = rng.int(1, 4).min(((w / widest) as usize).max(1));
            let slot = w / n as f64;
            let tips: Vec<(f64, f64)> = (0..n)
                .map(|i| {
                    let depth = rng.uni(0.3, 0.7) * hgt;
                    let half = depth * (0.5 * alpha).tan();
                    let room = (0.5 * slot - half - 0.05 * slot).max(0.0);
                    ((i as f64 + 0.5) * slot + rng.uni(-room, room), depth)
                })
                .collect();
            let v = notched(w, hgt, &tips, alpha);
            let h = hgt / rng.uni(8.0, 25.0);
            finish(
                &[polygon(&v, Size::Uniform(h))],
                format!("{n} V notches, tips {alpha_deg:.1}°"),
            )
        }
    }
}

fn near_touching(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let f = if extreme {
        0.02
    } else {
        rng.log_uni(0.02, 0.2)
    };
    let plate = |rng: &mut SplitMix64| (rng.uni(1.5, 3.0), 1.0);
    match rng.int(0, 2) {
        0 => {
            let (w, hgt) = plate(rng);
            let ho = rng.log_uni(0.04, 0.12);
            let outer = polygon(&rect_vertices(0.0, 0.0, w, hgt), Size::Uniform(ho));
            let inner = Bx {
                x0: 0.0,
                y0: 0.0,
                x1: w,
                y1: hgt,
            }
            .inset(ho.max(0.05));
            let mut specs = vec![outer];
            specs.extend(near_pair_in_box(rng, inner, f));
            finish(&specs, format!("two holes {f:.3} of a segment apart"))
        }
        1 => {
            // A square hole near the bottom side of the plate, both with
            // segments of length h.
            let (w, hgt) = plate(rng);
            let h = rng.log_uni(0.04, 0.12);
            let a = h * rng.int(2, 6) as f64;
            let g = f * h;
            let x = rng.uni(0.1, w - a - 0.1);
            let outer = polygon(&rect_vertices(0.0, 0.0, w, hgt), Size::Uniform(h));
            let hole = polygon(&rect_vertices(x, g, x + a, g + a), Size::Uniform(h));
            finish(
                &[outer, hole],
                format!("hole {f:.3} of a segment from the outer side"),
            )
        }
        _ => {
            // A slit from the top side: its two sides are g apart.
            let (w, hgt) = plate(rng);
            let depth = rng.uni(0.3, 0.8) * hgt;
            let h = depth / rng.int(3, 12) as f64;
            let g = f * h;
            let xs = rng.uni(0.2, w - 0.2);
            let v = vec![
                Point::new(0.0, 0.0),
                Point::new(w, 0.0),
                Point::new(w, hgt),
                Point::new(xs + g, hgt),
                Point::new(xs + g, hgt - depth),
                Point::new(xs, hgt - depth),
                Point::new(xs, hgt),
                Point::new(0.0, hgt),
            ];
            finish(
                &[polygon(&v, Size::Uniform(h))],
                format!("slit {f:.3} of a segment wide"),
            )
        }
    }
}

/// The outline of a `w × h` rectangle with `low` nodes on the bottom side
/// and `high` on the top (corners included), `m` segments on each of the
/// other sides (made even in total).
fn unbalanced_outline(
    rng: &mut SplitMix64,
    w: f64,
    h: f64,
    low: usize,
    high: usize,
) -> (LoopSpec, usize) {
    let mut high = high;
    if (low + high) % 2 == 1 {
        high -= 1;
    }
    let fine = w / (high - 1) as f64;
    let m = ((h / fine * rng.uni(0.1, 1.0)).round() as usize).clamp(1, 60);
    let v = rect_vertices(0.0, 0.0, w, h);
    let spec = LoopSpec {
        pieces: vec![
            fixed(v[0], v[1], low - 1),
            fixed(v[1], v[2], m),
            fixed(v[2], v[3], high - 1),
            fixed(v[3], v[0], m),
        ],
        size: Size::Uniform(fine),
    };
    (spec, high)
}

fn unbalanced(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let (low, high) = if extreme {
        (2, 200)
    } else {
        (rng.int(2, 4), rng.int(10, 200))
    };
    let w = rng.uni(0.5, 4.0);
    let (spec, high) = unbalanced_outline(rng, w, 1.0, low, high);
    finish(
        &[spec],
        format!("{w:.2} x 1 rectangle, {low} nodes against {high}"),
    )
}

fn mixed(rng: &mut SplitMix64, extreme: bool) -> Drawn {
    let (w, hgt) = (rng.uni(1.5, 3.0), 1.0);
    let mut parts = Vec::new();
    let alpha_deg = if extreme { 5.0 } else { rng.uni(5.0, 40.0) };
    let alpha = alpha_deg.to_radians();
    // The outline; `safe` is the part of the rectangle it leaves whole.
    let (outer, top) = match rng.int(0, 3) {
        0 => {
            let ratio = rng.log_uni(5.0, 100.0);
            let h_max = 2.0 * (w + hgt) / rng.uni(8.0, 20.0);
            parts.push(format!("graded 1:{ratio:.0}"));
            let size = Size::Graded {
                h_min: h_max / ratio,
                ratio,
                phase: rng.unit(),
            };
            (polygon(&rect_vertices(0.0, 0.0, w, hgt), size), hgt)
        }
        1 => {
            let m = rng.int(2, 10);
            let (v, t) = sawtooth(w, hgt, m, alpha, rng.chance(0.4));
            parts.push(format!("{m} teeth of {alpha_deg:.1}°"));
            (polygon(&v, Size::Uniform(t / rng.uni(5.0, 12.0))), hgt)
        }
        2 => {
            let n = rng.int(1, 3);
            let slot = w / n as f64;
            let depth = rng.uni(0.2, 0.4) * hgt;
            let half = depth * (0.5 * alpha).tan();
            let tips: Vec<(f64, f64)> = (0..n)
                .map(|i| {
                    let room = (0.4 * slot - half).max(0.0);
                    ((i as f64 + 0.5) * slot + rng.uni(-room, room), depth)
                })
                .collect();
            parts.push(format!("{n} notches of {alpha_deg:.1}°"));
            let v = notched(w, hgt, &tips, alpha);
            (
                polygon(&v, Size::Uniform(hgt / rng.uni(10.0, 25.0))),
                hgt - depth,
            )
        }
        _ => {
            let high = rng.int(40, 200);
            let (spec, high) = unbalanced_outline(rng, w, hgt, 2, high);
            parts.push(format!("2 nodes against {high}"));
            (spec, hgt)
        }
    };
    let ho = 0.08;
    let safe = Bx {
        x0: 0.0,
        y0: 0.0,
        x1: w,
        y1: top,
    }
    .inset(ho);
    if safe.w() <= 0.0 || safe.h() <= 0.0 {
        return None;
    }
    let mut specs = vec![outer];
    let n = rng.int(1, 3);
    for bx in safe.split(n, ho) {
        match rng.int(0, 2) {
            0 => {
                let k = rng.int(1, 10);
                parts.push(format!("{k} holes"));
                specs.extend(holes_in_box(rng, bx, k, ho));
            }
            1 => {
                let ratio = rng.uni(5.0, 50.0);
                parts.push(format!("slot 1:{ratio:.0}"));
                specs.push(slot_in_box(rng, bx, ratio));
            }
            _ => {
                let f = rng.log_uni(0.02, 0.2);
                parts.push(format!("pair {f:.3} apart"));
                specs.extend(near_pair_in_box(rng, bx, f));
            }
        }
    }
    finish(&specs, parts.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn angle_at(a: Point, b: Point, c: Point) -> f64 {
        // Interior angle at b of a loop oriented with the domain on the
        // left (degrees, 0–360).
        let (u, v) = (c - b, a - b);
        let mut t = v.y.atan2(v.x) - u.y.atan2(u.x);
        if t < 0.0 {
            t += TAU;
        }
        t.to_degrees()
    }

    fn min_corner(b: &Boundary) -> f64 {
        let mut m = f64::INFINITY;
        for l in &b.loops {
            let n = l.len();
            for k in 0..n {
                let p = |i: usize| b.points[l[i % n]];
                m = m.min(angle_at(p(k + n - 1), p(k), p(k + 1)));
            }
        }
        m
    }

    fn grading(b: &Boundary) -> f64 {
        b.loops
            .iter()
            .map(|l| {
                let n = l.len();
                let len: Vec<f64> = (0..n)
                    .map(|k| b.points[l[k]].distance(b.points[l[(k + 1) % n]]))
                    .collect();
                len.iter().cloned().fold(0.0, f64::max)
                    / len.iter().cloned().fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    /// Length over width of the thinnest loop (a rectangle `l × w` gives
    /// `l / w`): `P² / 4A − 2`.
    fn slenderness(b: &Boundary) -> f64 {
        b.loops
            .iter()
            .map(|l| {
                let n = l.len();
                let p: f64 = (0..n)
                    .map(|k| b.points[l[k]].distance(b.points[l[(k + 1) % n]]))
                    .sum();
                let a = crate::geom::polygon_area(l.iter().map(|&i| b.points[i])).abs();
                p * p / (4.0 * a) - 2.0
            })
            .fold(0.0, f64::max)
    }

    /// Smallest distance between two segments sharing no node, over the
    /// longer of their lengths.
    fn gap_fraction(b: &Boundary) -> f64 {
        let segs: Vec<(usize, usize)> = b.segments().collect();
        let mut m = f64::INFINITY;
        for (i, &(a, c)) in segs.iter().enumerate() {
            for &(d, e) in &segs[i + 1..] {
                if a == d || a == e || c == d || c == e {
                    continue;
                }
                let p = |k: usize| b.points[k];
                let dist = [
                    crate::geom::point_segment_distance(p(a), p(d), p(e)),
                    crate::geom::point_segment_distance(p(c), p(d), p(e)),
                    crate::geom::point_segment_distance(p(d), p(a), p(c)),
                    crate::geom::point_segment_distance(p(e), p(a), p(c)),
                ]
                .into_iter()
                .fold(f64::INFINITY, f64::min);
                let len = p(a).distance(p(c)).max(p(d).distance(p(e)));
                m = m.min(dist / len);
            }
        }
        m
    }

    /// Node counts of the sides of a single loop between its corners
    /// (turns over 1°), corners included.
    fn side_nodes(b: &Boundary) -> Vec<usize> {
        let l = &b.loops[0];
        let n = l.len();
        let p = |i: usize| b.points[l[i % n]];
        let corners: Vec<usize> = (0..n)
            .filter(|&k| (angle_at(p(k + n - 1), p(k), p(k + 1)) - 180.0).abs() > 1.0)
            .collect();
        (0..corners.len())
            .map(|i| {
                let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
                (b + n - a) % n + 1
            })
            .collect()
    }

    #[test]
    fn same_seed_same_points() {
        for f in Family::ALL {
            for seed in [0, 1, 7, u64::MAX] {
                let (a, b) = (generate(f, seed), generate(f, seed));
                assert_eq!(a.boundary.loops, b.boundary.loops);
                let bits = |d: &Domain| -> Vec<(u64, u64)> {
                    d.boundary
                        .points
                        .iter()
                        .map(|p| (p.x.to_bits(), p.y.to_bits()))
                        .collect()
                };
                assert_eq!(bits(&a), bits(&b), "{f} {seed}");
            }
        }
        assert_eq!(suite(21, 3), suite(21, 3));
        assert_ne!(suite(7, 3), suite(7, 4));
    }

    #[test]
    fn every_domain_is_valid_with_even_loops() {
        for f in Family::ALL {
            for seed in 0..40 {
                let (d, draws) = generate_counted(f, seed);
                assert!(draws <= MAX_DRAWS, "{}: fell back", d.name);
                let b = &d.boundary;
                assert!(b.loops.iter().all(|l| l.len() % 2 == 0), "{}", d.name);
                let again = Boundary::new(b.points.clone(), b.loops.clone(), None);
                assert!(again.is_ok(), "{}: {again:?}", d.name);
                // What the command line reads back from the written file.
                let text = crate::io::poly::write_poly(b);
                let read = crate::io::poly::parse_poly(&text)
                    .unwrap_or_else(|e| panic!("{}: {e}", d.name));
                assert_eq!(read.node_count(), b.node_count());
            }
        }
    }

    #[test]
    fn suite_covers_families_evenly_and_reaches_the_extremes() {
        let domains = suite_domains(70, 1);
        for f in Family::ALL {
            assert_eq!(domains.iter().filter(|d| d.family == f).count(), 10);
        }
        let of = |f: Family| domains.iter().filter(move |d| d.family == f);
        let most_holes = of(Family::ManyHoles)
            .map(|d| d.boundary.loops.len() - 1)
            .max();
        assert_eq!(most_holes, Some(30));
        let thinnest = of(Family::Channel)
            .map(|d| slenderness(&d.boundary))
            .fold(0.0, f64::max);
        assert!(thinnest >= 50.0 - 1e-6, "channel 1:{thinnest}");
        let steepest = of(Family::Graded)
            .map(|d| grading(&d.boundary))
            .fold(0.0, f64::max);
        assert!(steepest >= 100.0, "grading 1:{steepest}");
        let sharpest = of(Family::Spikes)
            .map(|d| min_corner(&d.boundary))
            .fold(f64::INFINITY, f64::min);
        assert!(sharpest <= 5.0 + 1e-6, "sharpest tip {sharpest}°");
        let closest = of(Family::NearTouching)
            .map(|d| gap_fraction(&d.boundary))
            .fold(f64::INFINITY, f64::min);
        assert!(closest <= 0.02 + 1e-9, "gap {closest} of a segment");
        assert!(of(Family::NearTouching).all(|d| gap_fraction(&d.boundary) <= 0.2 + 1e-9));
        let unbalanced = of(Family::Unbalanced).any(|d| {
            let mut s = side_nodes(&d.boundary);
            s.sort_unstable();
            s.len() == 4 && s[0] == 2 && s[3] == 200
        });
        assert!(unbalanced, "no rectangle with 2 nodes against 200");
    }
}

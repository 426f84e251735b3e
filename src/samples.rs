//! Training samples (thesis Chapter 3, §3.1.3; method §3): a sample is the
//! normalised front path `P_lN..P_l1, P0, P_r1..P_rN` around a reference
//! point together with the element cut there, `(type, Pn)`.
//!
//! [`collect`] takes samples from a finished quad mesh: every corner of every
//! good element (`Rs ≥ 0.8`, corners in [35°, 145°]) serves as P0 for each
//! of the three element types, and the front path is continued outward from
//! both ends along mesh edges, one sample per continuation whose interior
//! angles stay in [35°, 235°]. [`Sample::from_front`] makes the sample of one
//! extraction step from the real front (the editor's corrections).
//!
//! A [`TrainingSet`] holds samples of one input-point count, reads and
//! writes CSV (the thesis's Table 3 column order) and JSON, merges and drops
//! duplicates.

use crate::geom::{ccw_angle, Point};
use crate::mesh::QuadMesh;
use crate::model::sample::csv_header;
use crate::model::ElementType;
use crate::normalize::LeadingPoints;
use crate::quality::QuadQuality;

pub(crate) use crate::model::sample::bad_coordinate;
pub use crate::model::sample::{
    sample_problem, variable_names, variable_points, Sample, Source, MAX_SAMPLE_COORDINATE,
};
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use thiserror::Error;

/// Parameters of sample collection (method §3), angles in degrees.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CollectParams {
    /// Smallest `Rs = A / ē²` of a good element. Default 0.8.
    pub min_rs: f64,
    /// Corner window of a good element. Default [35, 145].
    pub corner: [f64; 2],
    /// Window of the front's interior angle along the path. Default [35, 235].
    pub turn: [f64; 2],
    /// Most samples taken per element corner and type (a guard against
    /// combinatorial growth on very irregular meshes). Default 4096.
    pub max_per_corner: usize,
}

impl CollectParams {
    pub const DEFAULT: CollectParams = CollectParams {
        min_rs: 0.8,
        corner: [35.0, 145.0],
        turn: [35.0, 235.0],
        max_per_corner: 4096,
    };
}

impl Default for CollectParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// True for an element good enough to learn from.
pub fn is_good(q: &QuadQuality, p: &CollectParams) -> bool {
    q.rs >= p.min_rs && q.min_angle() >= p.corner[0] && q.max_angle() <= p.corner[1]
}

/// Node adjacency of a mesh, each list sorted (deterministic output).
fn adjacency(mesh: &QuadMesh) -> Vec<Vec<u32>> {
    let mut adj: Vec<BTreeSet<u32>> = vec![BTreeSet::new(); mesh.nodes.len()];
    for q in &mesh.quads {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            adj[a as usize].insert(b);
            adj[b as usize].insert(a);
        }
    }
    adj.into_iter().map(|s| s.into_iter().collect()).collect()
}

/// Collects the samples of a quad mesh with `n` leading points per side
/// (`2n + 1` input points). `file` names the mesh in each sample's source.
pub fn collect(mesh: &QuadMesh, n: usize, params: &CollectParams, file: &str) -> Vec<Sample> {
    let adj = adjacency(mesh);
    let c = Collector {
        mesh,
        adj: &adj,
        n,
        params,
    };
    let mut out = Vec::new();
    for (e, q) in mesh.quads.iter().enumerate() {
        if !is_good(&QuadQuality::of(mesh.corners(q)), params) {
            continue;
        }
        for k in 0..4 {
            // The element as (P0, r1, Pn, l1), counter-clockwise.
            let [p0, r1, opp, l1] = [q[k], q[(k + 1) % 4], q[(k + 2) % 4], q[(k + 3) % 4]];
            let source = Source::Mesh {
                file: file.to_string(),
                element: e,
            };
            // type 0: l1 → P0 → r1, Pn the opposite corner.
            c.emit(&[l1], p0, &[r1], ElementType::New, opp, &source, &mut out);
            // type 1: l1 → P0 → r1 → r2, Pn = r2 = opposite corner.
            c.emit(
                &[l1],
                p0,
                &[r1, opp],
                ElementType::Right,
                opp,
                &source,
                &mut out,
            );
            // type 2: l2 → l1 → P0 → r1, Pn = l2 = opposite corner.
            c.emit(
                &[l1, opp],
                p0,
                &[r1],
                ElementType::Left,
                opp,
                &source,
                &mut out,
            );
        }
    }
    out
}

struct Collector<'a> {
    mesh: &'a QuadMesh,
    adj: &'a [Vec<u32>],
    n: usize,
    params: &'a CollectParams,
}

impl Collector<'_> {
    fn pos(&self, v: u32) -> Point {
        self.mesh.nodes[v as usize]
    }

    /// All continuations of one side of the path to `n` nodes. `side` holds
    /// the nodes from P0 outward (`[r1, r2, ..]` or `[l1, l2, ..]`); `back`
    /// is the node before `side[0]` (P0). `right` selects the orientation of
    /// the interior angle.
    fn extend(&self, p0: u32, side: &[u32], right: bool, opp: u32) -> Vec<Vec<u32>> {
        let mut done = Vec::new();
        let mut stack = vec![side.to_vec()];
        let (lo, hi) = (
            self.params.turn[0].to_radians(),
            self.params.turn[1].to_radians(),
        );
        while let Some(path) = stack.pop() {
            if path.len() >= self.n {
                done.push(path);
                if done.len() >= self.params.max_per_corner {
                    break;
                }
                continue;
            }
            let cur = path[path.len() - 1];
            let prev = if path.len() >= 2 {
                path[path.len() - 2]
            } else {
                p0
            };
            // Reverse so that the stack pops the candidates in sorted order.
            for &next in self.adj[cur as usize].iter().rev() {
                if next == p0 || next == opp || path.contains(&next) {
                    continue;
                }
                let (c, pp, nx) = (self.pos(cur), self.pos(prev), self.pos(next));
                // Interior angle at `cur`: CCW from its right neighbour to
                // its left neighbour.
                let theta = if right {
                    ccw_angle(c, nx, pp)
                } else {
                    ccw_angle(c, pp, nx)
                };
                if theta < lo || theta > hi {
                    continue;
                }
                let mut p = path.clone();
                p.push(next);
                stack.push(p);
            }
        }
        done
    }

    #[allow(clippy::too_many_arguments)]
    fn emit(
        &self,
        left: &[u32],
        p0: u32,
        right: &[u32],
        t: ElementType,
        pn: u32,
        source: &Source,
        out: &mut Vec<Sample>,
    ) {
        if left.len() > self.n || right.len() > self.n {
            return;
        }
        // The element's own corners may close the path only through `pn`.
        let lefts = self.extend(p0, left, false, if left.len() > 1 { u32::MAX } else { pn });
        let rights = self.extend(p0, right, true, if right.len() > 1 { u32::MAX } else { pn });
        let mut taken = 0;
        for l in &lefts {
            for r in &rights {
                if !disjoint(l, r, self.n) {
                    continue;
                }
                let lp: Vec<Point> = l.iter().map(|&v| self.pos(v)).collect();
                let rp: Vec<Point> = r.iter().map(|&v| self.pos(v)).collect();
                if let Some(s) =
                    Sample::from_front(&lp, self.pos(p0), &rp, t, self.pos(pn), source.clone())
                {
                    out.push(s);
                    taken += 1;
                    if taken >= self.params.max_per_corner {
                        return;
                    }
                }
            }
        }
    }
}

/// Left and right leading points do not overlap, except the outermost pair
/// for 7 or more input points (method §3).
fn disjoint(l: &[u32], r: &[u32], n: usize) -> bool {
    l.iter().enumerate().all(|(i, a)| {
        r.iter()
            .enumerate()
            .all(|(j, b)| a != b || (n >= 3 && i == n - 1 && j == n - 1))
    })
}

/// A problem reading a training set, with the line (CSV) or the sample
/// (JSON, numbered from 1) at fault.
#[derive(Debug, Error)]
pub enum SamplesError {
    #[error("line {line}: {msg}")]
    Parse { line: usize, msg: String },
    #[error("sample {sample}: {msg}")]
    Sample { sample: usize, msg: String },
    #[error("the header does not name a sample layout: {0}")]
    Header(String),
    #[error("a set of {expected} input points cannot take samples of {found}")]
    Points { expected: usize, found: usize },
    #[error("{0}")]
    Json(String),
    #[error("{0}")]
    Csv(String),
    #[error("{0}")]
    Io(String),
    #[error("{0}")]
    Write(String),
}

// The causes are kept as text (escaped, one line), not as `source`s:
// printing an error with its chain must not repeat them.
impl From<serde_json::Error> for SamplesError {
    fn from(e: serde_json::Error) -> Self {
        SamplesError::Json(crate::io::quote_long(&e.to_string()))
    }
}
impl From<csv::Error> for SamplesError {
    fn from(e: csv::Error) -> Self {
        SamplesError::Csv(crate::io::quote_long(&e.to_string()))
    }
}
impl From<std::io::Error> for SamplesError {
    fn from(e: std::io::Error) -> Self {
        SamplesError::Io(e.to_string())
    }
}
impl From<crate::io::WriteError> for SamplesError {
    fn from(e: crate::io::WriteError) -> Self {
        SamplesError::Write(e.to_string())
    }
}

/// Samples of one input-point count (`2N + 1`). Reading one (from JSON,
/// CSV or inside any document) checks every sample ([`sample_problem`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "UncheckedSet")]
pub struct TrainingSet {
    /// Input points: 5, 7, 9 or 11.
    pub points: usize,
    pub samples: Vec<Sample>,
}

/// A training set as read, before its checks.
#[derive(Deserialize)]
struct UncheckedSet {
    points: usize,
    samples: Vec<Sample>,
}

impl TryFrom<UncheckedSet> for TrainingSet {
    type Error = SamplesError;

    fn try_from(u: UncheckedSet) -> Result<TrainingSet, SamplesError> {
        let set = TrainingSet {
            points: u.points,
            samples: u.samples,
        };
        set.check()?;
        Ok(set)
    }
}

/// Rounding of coordinates when comparing samples for duplicates.
const DEDUP_QUANTUM: f64 = 1e-9;

/// The duplicate keys of a set's samples ([`TrainingSet::keys`]).
#[derive(Clone, Debug, Default)]
pub struct SampleKeys(BTreeSet<Vec<i64>>);

/// What two samples must share to be duplicates: their points, Pn and type,
/// rounded to [`DEDUP_QUANTUM`].
fn dedup_key(s: &Sample) -> Vec<i64> {
    let mut key: Vec<i64> = s
        .input
        .thesis_order()
        .iter()
        .chain(std::iter::once(&s.pn))
        .flat_map(|p| [p.x, p.y])
        .map(|v| (v / DEDUP_QUANTUM).round() as i64)
        .collect();
    key.push(s.element_type as i64);
    key
}

impl TrainingSet {
    /// An empty set of `points` input points.
    pub fn new(points: usize) -> TrainingSet {
        TrainingSet {
            points,
            samples: Vec::new(),
        }
    }

    /// `N`, leading points per side.
    pub fn n(&self) -> usize {
        self.points.saturating_sub(1) / 2
    }

    /// Checks the set: 5, 7, 9 or 11 input points, and every sample with
    /// `N` leading points a side and coordinates in range
    /// ([`sample_problem`]); a bad sample is named by its number (from 1).
    pub fn check(&self) -> Result<(), SamplesError> {
        if !matches!(self.points, 5 | 7 | 9 | 11) {
            return Err(SamplesError::Header(format!(
                "{} input points (5, 7, 9 or 11)",
                self.points
            )));
        }
        for (k, s) in self.samples.iter().enumerate() {
            if let Some(msg) = sample_problem(s, self.points) {
                return Err(SamplesError::Sample { sample: k + 1, msg });
            }
        }
        Ok(())
    }

    pub fn len(&self) -> usize {
        self.samples.len()
    }

    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// The samples of `meshes` (`(name, mesh)` pairs, the name going into
    /// each sample's source) at `points` input points, duplicates dropped.
    pub fn collect(
        meshes: &[(String, QuadMesh)],
        points: usize,
        params: &CollectParams,
    ) -> TrainingSet {
        let mut set = TrainingSet::new(points);
        for (name, m) in meshes {
            set.samples
                .extend(collect(m, (points - 1) / 2, params, name));
        }
        set.dedup();
        set
    }

    /// Appends one sample of the same input-point count.
    pub fn push(&mut self, s: Sample) -> Result<(), SamplesError> {
        if 2 * s.n() + 1 != self.points {
            return Err(SamplesError::Points {
                expected: self.points,
                found: 2 * s.n() + 1,
            });
        }
        if let Some(msg) = sample_problem(&s, self.points) {
            return Err(SamplesError::Sample {
                sample: self.samples.len() + 1,
                msg,
            });
        }
        self.samples.push(s);
        Ok(())
    }

    /// Appends every sample of `other` (same input-point count).
    pub fn merge(&mut self, other: TrainingSet) -> Result<(), SamplesError> {
        if other.points != self.points {
            return Err(SamplesError::Points {
                expected: self.points,
                found: other.points,
            });
        }
        self.samples.extend(other.samples);
        Ok(())
    }

    /// Drops samples whose points, type and Pn equal (to 1e-9) an earlier
    /// sample's; returns how many were dropped.
    pub fn dedup(&mut self) -> usize {
        let before = self.samples.len();
        let mut seen = BTreeSet::new();
        self.samples.retain(|s| seen.insert(dedup_key(s)));
        before - self.samples.len()
    }

    /// The position of the first sample that `s` duplicates (as
    /// [`TrainingSet::dedup`] compares them), if any.
    pub fn position_of(&self, s: &Sample) -> Option<usize> {
        let key = dedup_key(s);
        self.samples.iter().position(|o| dedup_key(o) == key)
    }

    /// What its samples are compared by for duplicates, to test other
    /// samples against the set ([`TrainingSet::beyond`]).
    pub fn keys(&self) -> SampleKeys {
        SampleKeys(self.samples.iter().map(dedup_key).collect())
    }

    /// The samples of this set that are in the set of keys `base` (a
    /// [`TrainingSet::keys`]) neither, nor earlier in this set (as
    /// [`TrainingSet::dedup`] compares them), and how many were left out:
    /// what this set adds to `base` (`base` followed by the result and
    /// deduplicated is `base` followed by this set and deduplicated,
    /// sample for sample).
    pub fn beyond(&self, base: &SampleKeys) -> (TrainingSet, usize) {
        let mut seen = BTreeSet::new();
        let samples: Vec<Sample> = self
            .samples
            .iter()
            .filter(|s| {
                let key = dedup_key(s);
                !base.0.contains(&key) && seen.insert(key)
            })
            .cloned()
            .collect();
        let left_out = self.samples.len() - samples.len();
        (
            TrainingSet {
                points: self.points,
                samples,
            },
            left_out,
        )
    }

    /// Counts of samples by type.
    pub fn type_counts(&self) -> [usize; 3] {
        let mut c = [0; 3];
        for s in &self.samples {
            c[s.element_type as usize] += 1;
        }
        c
    }

    /// The CSV header: the thesis's Table 3 column order
    /// (`xlN, ylN, …, x0, y0, xr1, yr1, …, type, xn, yn`), then the source.
    pub fn csv_header(n: usize) -> Vec<String> {
        csv_header(n)
    }

    /// The set as CSV text (one header line, one line per sample).
    pub fn to_csv(&self) -> Result<String, SamplesError> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(Self::csv_header(self.n()))?;
        for s in &self.samples {
            let mut rec: Vec<String> = s
                .input
                .thesis_order()
                .iter()
                .flat_map(|p| [fmt(p.x), fmt(p.y)])
                .collect();
            rec.push(s.element_type.number().to_string());
            rec.push(fmt(s.pn.x));
            rec.push(fmt(s.pn.y));
            match &s.source {
                Source::Mesh { file, element } => {
                    rec.push(file.clone());
                    rec.push(element.to_string());
                }
                Source::Correction => {
                    rec.push("correction".into());
                    rec.push(String::new());
                }
            }
            w.write_record(&rec)?;
        }
        let bytes = w.into_inner().map_err(|e| SamplesError::Parse {
            line: 0,
            msg: e.to_string(),
        })?;
        Ok(String::from_utf8_lossy(&bytes).into_owned())
    }

    /// Reads CSV written by [`TrainingSet::to_csv`]; the source columns may
    /// be missing (then the source is "correction").
    pub fn from_csv(text: &str) -> Result<TrainingSet, SamplesError> {
        let text = crate::io::normalise_text(text);
        let mut r = csv::ReaderBuilder::new()
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let header: Vec<String> = r.headers()?.iter().map(str::to_lowercase).collect();
        let coords = header
            .iter()
            .position(|h| h == "type")
            .ok_or_else(|| SamplesError::Header(crate::io::quote_long(&header.join(","))))?;
        let points = coords / 2;
        if coords % 2 != 0 || !matches!(points, 5 | 7 | 9 | 11) {
            return Err(SamplesError::Header(crate::io::quote_long(
                &header.join(","),
            )));
        }
        let n = (points - 1) / 2;
        let expected = Self::csv_header(n);
        if header.get(..coords + 3) != expected.get(..coords + 3) {
            return Err(SamplesError::Header(crate::io::quote_long(
                &header.join(","),
            )));
        }
        let mut set = TrainingSet::new(points);
        for (i, rec) in r.records().enumerate() {
            let line = i + 2;
            let rec = rec?;
            let num = |k: usize| -> Result<f64, SamplesError> {
                let v = csv_number(&rec, k, &expected[k])
                    .map_err(|msg| SamplesError::Parse { line, msg })?;
                match bad_coordinate(v) {
                    // The type column is checked on its own.
                    Some(why) if k != coords => Err(SamplesError::Parse {
                        line,
                        msg: format!("{} {why}", expected[k]),
                    }),
                    _ => Ok(v),
                }
            };
            let mut pts = Vec::with_capacity(points);
            for k in 0..points {
                pts.push(Point::new(num(2 * k)?, num(2 * k + 1)?));
            }
            let t = num(coords)?;
            let element_type = ElementType::from_number(t as u8)
                .filter(|_| t.fract() == 0.0 && t >= 0.0)
                .ok_or_else(|| SamplesError::Parse {
                    line,
                    msg: format!("type must be 0, 1 or 2, not {t}"),
                })?;
            let pn = Point::new(num(coords + 1)?, num(coords + 2)?);
            let source = match rec.get(coords + 3) {
                None | Some("") | Some("correction") => Source::Correction,
                Some(file) => Source::Mesh {
                    file: file.to_string(),
                    element: rec
                        .get(coords + 4)
                        .and_then(|e| e.parse().ok())
                        .unwrap_or(0),
                },
            };
            let left: Vec<Point> = pts[..n].iter().rev().copied().collect();
            let right: Vec<Point> = pts[n + 1..].to_vec();
            set.samples.push(Sample {
                input: LeadingPoints { left, right },
                element_type,
                pn,
                source,
            });
        }
        Ok(set)
    }

    /// Reads a set from a `.json` file, or CSV otherwise.
    pub fn read(path: &std::path::Path) -> Result<TrainingSet, SamplesError> {
        let text = crate::io::decode_text(&std::fs::read(path)?);
        if is_json(path) {
            TrainingSet::from_json(&text)
        } else {
            TrainingSet::from_csv(&text)
        }
    }

    /// Writes the set as JSON for a `.json` path, CSV otherwise (atomically).
    pub fn write(&self, path: &std::path::Path) -> Result<(), SamplesError> {
        let text = if is_json(path) {
            self.to_json()?
        } else {
            self.to_csv()?
        };
        crate::io::write_atomic(path, text.as_bytes())?;
        Ok(())
    }

    pub fn to_json(&self) -> Result<String, SamplesError> {
        Ok(serde_json::to_string_pretty(self)?)
    }

    /// Reads a set from JSON, checked (see [`TrainingSet::check`]).
    pub fn from_json(text: &str) -> Result<TrainingSet, SamplesError> {
        let text = crate::io::normalise_text(text);
        // Parsed unchecked first, so that a bad sample is reported as
        // itself rather than inside serde's message.
        let u: UncheckedSet = serde_json::from_str(&text)?;
        let set = TrainingSet {
            points: u.points,
            samples: u.samples,
        };
        set.check()?;
        Ok(set)
    }
}

/// Column `k` (named `name`) of a CSV record as a number, or why not.
pub(crate) fn csv_number(rec: &csv::StringRecord, k: usize, name: &str) -> Result<f64, String> {
    let f = rec.get(k).ok_or_else(|| format!("missing column {name}"))?;
    f.parse()
        .map_err(|_| format!("{name}: not a number: `{}`", crate::io::quote(f)))
}

fn is_json(path: &std::path::Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

/// Shortest decimal that reads back to the same f64 (the mesh writers').
fn fmt(v: f64) -> String {
    let mut s = String::new();
    crate::io::fmt_f64(&mut s, v);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 2 grid of unit squares (nodes row by row).
    fn grid(nx: usize, ny: usize) -> QuadMesh {
        let mut m = QuadMesh::default();
        for j in 0..=ny {
            for i in 0..=nx {
                m.nodes.push(Point::new(i as f64, j as f64));
            }
        }
        let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        for j in 0..ny {
            for i in 0..nx {
                m.quads
                    .push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        m
    }

    #[test]
    fn single_square_gives_the_three_types() {
        let m = grid(1, 1);
        // 5 points: type 1 and 2 need l2/r2 outside the element: none.
        // Type 0 needs r2 beyond r1 and l2 beyond l1: none in one quad.
        assert!(collect(&m, 2, &CollectParams::DEFAULT, "m").is_empty());
    }

    #[test]
    fn grid_samples_are_the_hand_checked_ones() {
        let m = grid(3, 3);
        let s = collect(&m, 2, &CollectParams::DEFAULT, "g");
        assert!(!s.is_empty());
        // Every sample: P_r1 = (1,0) after normalisation; the domain lies
        // above the x axis, so type 0's Pn is the unit square's far corner.
        for x in &s {
            assert!((x.input.right[0] - Point::X).length() < 1e-12);
            match x.element_type {
                ElementType::New => assert!((x.pn - Point::new(1.0, 1.0)).length() < 1e-12),
                ElementType::Right => {
                    assert_eq!(x.pn, x.input.right[1]);
                    assert!((x.pn - Point::new(1.0, 1.0)).length() < 1e-12);
                }
                ElementType::Left => {
                    assert_eq!(x.pn, x.input.left[1]);
                    assert!((x.pn - Point::new(1.0, 1.0)).length() < 1e-12);
                }
            }
        }
        // The centre element's corner at (1,1): type 0 with the path
        // straight on both sides, l1 = (1,2) → P0 = (1,1) → r1 = (2,1).
        let e = 4; // the centre quad of a 3 × 3 grid
        let straight: Vec<&Sample> = s
            .iter()
            .filter(|x| {
                x.source
                    == Source::Mesh {
                        file: "g".into(),
                        element: e,
                    }
                    && x.element_type == ElementType::New
                    && (x.input.right[1] - Point::new(2.0, 0.0)).length() < 1e-12
                    && (x.input.left[1] - Point::new(0.0, 2.0)).length() < 1e-12
            })
            .collect();
        // One per corner of the centre element (4 corners, all interior).
        assert_eq!(straight.len(), 4);
        let counts = {
            let mut t = TrainingSet::new(5);
            t.samples = s.clone();
            t.type_counts()
        };
        assert!(counts.iter().all(|&c| c > 0), "{counts:?}");
    }

    #[test]
    fn bad_elements_give_no_samples() {
        let mut m = grid(3, 3);
        // Squash the grid into thin rectangles: Rs = 0.1 / 0.3025 < 0.8.
        for p in &mut m.nodes {
            p.y *= 0.1;
        }
        assert!(collect(&m, 2, &CollectParams::DEFAULT, "g").is_empty());
    }

    #[test]
    fn csv_and_json_round_trip() {
        let m = grid(3, 3);
        let mut t = TrainingSet::new(7);
        t.samples = collect(&m, 3, &CollectParams::DEFAULT, "g,\"quoted\"");
        t.samples.push(Sample {
            source: Source::Correction,
            ..t.samples[0].clone()
        });
        let back = TrainingSet::from_csv(&t.to_csv().unwrap()).unwrap();
        assert_eq!(back, t);
        let back = TrainingSet::from_json(&t.to_json().unwrap()).unwrap();
        assert_eq!(back, t);
    }

    #[test]
    fn beyond_keeps_what_a_set_adds_to_another() {
        // Five samples that differ in Pn.
        let one = collect(&grid(4, 4), 2, &CollectParams::DEFAULT, "g")[0].clone();
        let mut t = TrainingSet::new(5);
        t.samples = (0..5)
            .map(|k| Sample {
                pn: one.pn + Point::new(0.01 * k as f64, 0.0),
                ..one.clone()
            })
            .collect();
        let mut base = t.clone();
        base.samples.truncate(2);
        let mut more = t.clone();
        more.samples.push(t.samples[0].clone());
        let (fresh, left_out) = more.beyond(&base.keys());
        assert_eq!(fresh.samples, t.samples[2..].to_vec());
        assert_eq!(more.position_of(&t.samples[0]), Some(0));
        assert_eq!(base.position_of(&t.samples[3]), None);
        assert_eq!(left_out, 3);
        let mut a = base.clone();
        a.samples.extend(more.samples.clone());
        a.dedup();
        let mut b = base.clone();
        b.samples.extend(fresh.samples);
        b.dedup();
        assert_eq!(a, b);
    }

    #[test]
    fn dedup_and_merge() {
        let m = grid(4, 4);
        let mut t = TrainingSet::new(5);
        t.samples = collect(&m, 2, &CollectParams::DEFAULT, "g");
        let all = t.len();
        let dropped = t.dedup();
        assert!(dropped > 0 && t.len() + dropped == all);
        let mut u = t.clone();
        u.merge(t.clone()).unwrap();
        assert_eq!(u.dedup(), t.len());
        assert!(u.merge(TrainingSet::new(7)).is_err());
    }

    #[test]
    fn short_or_absurd_samples_are_refused_with_their_number() {
        let m = grid(3, 3);
        let mut t = TrainingSet::new(7);
        t.samples = collect(&m, 3, &CollectParams::DEFAULT, "g");
        let mut bad = t.clone();
        bad.samples[2].input.right.truncate(1);
        let e = TrainingSet::from_json(&serde_json::to_string(&bad).unwrap()).unwrap_err();
        assert!(matches!(e, SamplesError::Sample { sample: 3, .. }), "{e:?}");
        assert!(e.to_string().contains("1 right leading points"), "{e}");
        // Inside any document too.
        assert!(
            serde_json::from_str::<TrainingSet>(&serde_json::to_string(&bad).unwrap()).is_err()
        );
        let mut huge = t.clone();
        huge.samples[0].input.left[1].y = 1e300;
        let e = TrainingSet::from_json(&huge.to_json().unwrap()).unwrap_err();
        assert!(matches!(e, SamplesError::Sample { sample: 1, .. }), "{e:?}");
        let e = TrainingSet::from_csv(&huge.to_csv().unwrap()).unwrap_err();
        assert!(
            matches!(e, SamplesError::Parse { line: 2, .. }) && e.to_string().contains("yl2"),
            "{e}"
        );
        assert!(t.clone().push(huge.samples[0].clone()).is_err());
        // A byte-order mark and CR line ends read the same.
        let csv = t.to_csv().unwrap();
        let back = TrainingSet::from_csv(&format!("\u{feff}{}", csv.replace('\n', "\r"))).unwrap();
        assert_eq!(back, t);
    }

    #[test]
    fn bad_csv_names_the_line() {
        let h = TrainingSet::csv_header(2).join(",");
        let text = format!("{h}\n1,1,0,1,0,0,1,0,2,0,7,1,1,,\n");
        let e = TrainingSet::from_csv(&text).unwrap_err().to_string();
        assert!(e.contains("line 2") && e.contains("type"), "{e}");
        let e = TrainingSet::from_csv("a,b\n1,2\n").unwrap_err().to_string();
        assert!(e.contains("header"), "{e}");
    }
}

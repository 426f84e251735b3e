//! Several regions and named boundaries: a planar straight-line graph
//! (Triangle's `.poly` with segment markers and regional attributes) cut
//! into the faces it bounds.
//!
//! The method (`../shared/docs/method.md` §1; the thesis's boundary of one domain)
//! meshes one face at a time with its boundary nodes fixed. A graph of
//! several faces is meshed face by face: the nodes of a curve two faces
//! share are the same on both sides, so the meshes of the faces conform
//! across it by construction.
//!
//! [`Pslg::faces`] finds the faces: at each node the segments are ordered
//! by angle; walking every directed segment with its face on the left
//! gives the faces' boundary cycles, counter-clockwise for a face's outer
//! boundary and clockwise for the outline of a connected piece seen from
//! outside. Each clockwise cycle is a hole of the smallest
//! counter-clockwise cycle of another piece that contains it (none: it
//! bounds the unbounded face). A face holding a hole point is not meshed.
//! Without region points, a face inside a hole loop (at odd depth) is not
//! meshed either, so a `.poly` of one outer loop and holes reads as it
//! always has. A region point gives its face an attribute.
//!
//! Every problem is refused with the node or region at fault: a dangling
//! segment, crossing segments, a node on another segment's interior, a
//! face with an odd node count, a region point outside every face, two
//! region points of different attributes in one face.

use crate::boundary::{Boundary, BoundaryError, TOUCH_EPS};
use crate::geom::{orient, point_in_polygon, polygon_area, segments_intersect, Point};
use std::collections::BTreeMap;
use thiserror::Error;

/// A segment of the graph: two node indices and its marker (0: none).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Segment {
    pub a: usize,
    pub b: usize,
    pub marker: i64,
}

/// A region point: the face that holds `at` takes `attribute`.
#[derive(Clone, Debug, PartialEq)]
pub struct RegionPoint {
    pub at: Point,
    pub attribute: i64,
    /// Triangle's maximum triangle area for the region. Read and kept for
    /// a round trip; the mesh's sizes follow the boundary's spacing.
    pub max_area: Option<f64>,
}

/// A planar straight-line graph: nodes, segments with markers, hole
/// points, region points, and names for attributes and markers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pslg {
    pub points: Vec<Point>,
    /// The number each node had in the input (for messages).
    pub labels: Vec<i64>,
    pub segments: Vec<Segment>,
    pub holes: Vec<Point>,
    pub regions: Vec<RegionPoint>,
    /// Names of region attributes (default `region_A`).
    pub region_names: BTreeMap<i64, String>,
    /// Names of segment markers (default `marker_M`).
    pub group_names: BTreeMap<i64, String>,
    /// Without region points, each face to mesh is a region of its own
    /// (attributes 1, 2, … in face order) instead of all one region.
    pub face_regions: bool,
}

/// A bounded face of the graph ([`Pslg::face_cycles`]).
#[derive(Clone, Debug, PartialEq)]
pub struct FaceCycle {
    /// Graph node indices: the outer loop first (counter-clockwise), then
    /// the holes (clockwise).
    pub loops: Vec<Vec<usize>>,
    /// False for a face holding a hole point, or, without region points,
    /// inside a hole loop.
    pub meshed: bool,
    pub attribute: i64,
}

/// A face to mesh: its boundary and attribute.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    /// The boundary over the face's own nodes (outer loop first).
    pub boundary: Boundary,
    /// The graph's node index of each of `boundary.points`.
    pub nodes: Vec<usize>,
    /// The region attribute (0 where no region point lies in the face).
    pub attribute: i64,
}

/// Why a graph cannot be cut into faces to mesh.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum PslgError {
    #[error("the graph has no segments")]
    Empty,
    #[error("node {node} ends a dangling segment: every node must join at least two segments")]
    Dangling { node: i64 },
    #[error("the segment from node {a} to node {b} is given twice")]
    Repeated { a: i64, b: i64 },
    #[error("the segment from node {a} to node {b} crosses the segment from node {c} to node {d} at about ({x}, {y})")]
    Crossing {
        a: i64,
        b: i64,
        c: i64,
        d: i64,
        x: f64,
        y: f64,
    },
    #[error("node {node} at ({x}, {y}) lies on the segment from node {a} to node {b} (split that segment at the node)")]
    NodeOnSegment {
        node: i64,
        a: i64,
        b: i64,
        x: f64,
        y: f64,
    },
    #[error("node {a} and node {b} are at the same position, ({x}, {y}) up to rounding")]
    Coincident { a: i64, b: i64, x: f64, y: f64 },
    #[error("the segment from node {a} to node {b} has the same face on both sides (a slit): faces must be bounded by closed loops")]
    Slit { a: i64, b: i64 },
    #[error("region {region} has {count} boundary nodes, an odd number: an all-quad mesh needs an even count (add or remove a node on one of its curves)")]
    OddRegion { region: String, count: usize },
    #[error("region point {index} at ({x}, {y}) lies outside every face")]
    RegionOutside { index: usize, x: f64, y: f64 },
    #[error("region points {first} and {second} lie in one face but give attributes {a} and {b}")]
    RegionConflict {
        first: usize,
        second: usize,
        a: i64,
        b: i64,
    },
    #[error("no face is left to mesh: every face holds a hole point")]
    NothingToMesh,
    #[error("region {region}: {source}")]
    Face {
        region: String,
        #[source]
        source: BoundaryError,
    },
}

/// Where segments `a`–`b` and `c`–`d`, known to meet, cross: the point
/// of their lines' intersection, or for segments along one line the end
/// of one that lies on the other (what an error names to the user).
fn crossing_point(a: Point, b: Point, c: Point, d: Point) -> Point {
    let (r, s) = (b - a, d - c);
    let den = r.perp_dot(s);
    if den != 0.0 {
        let t = (c - a).perp_dot(s) / den;
        return a + r * t.clamp(0.0, 1.0);
    }
    [c, d, a]
        .into_iter()
        .find(|&p| crate::geom::point_segment_distance(p, a, b) == 0.0)
        .unwrap_or(b)
}

/// A boundary cycle found by the walk: directed segments (node pairs) and
/// its signed area.
struct Cycle {
    nodes: Vec<usize>,
    area: f64,
    poly: Vec<Point>,
    lo: Point,
    hi: Point,
}

impl Cycle {
    fn contains(&self, p: Point) -> bool {
        p.x >= self.lo.x
            && p.x <= self.hi.x
            && p.y >= self.lo.y
            && p.y <= self.hi.y
            && point_in_polygon(p, &self.poly)
    }
}

impl Pslg {
    /// The graph of a boundary's loops, without markers or regions.
    pub fn from_boundary(b: &Boundary) -> Pslg {
        let mut segments = Vec::new();
        for l in &b.loops {
            for k in 0..l.len() {
                segments.push(Segment {
                    a: l[k],
                    b: l[(k + 1) % l.len()],
                    marker: 0,
                });
            }
        }
        Pslg {
            points: b.points.clone(),
            labels: b.labels.clone(),
            segments,
            ..Pslg::default()
        }
    }

    /// True when the graph carries more than one domain's worth of
    /// information: region points or segment markers.
    pub fn has_groups(&self) -> bool {
        !self.regions.is_empty() || self.segments.iter().any(|s| s.marker != 0)
    }

    /// True when every node joins exactly two segments: the graph is a
    /// set of loops, one domain as [`Boundary`] reads it (unless it has
    /// groups).
    pub fn is_loops(&self) -> bool {
        let mut degree = vec![0u8; self.points.len()];
        for s in &self.segments {
            for v in [s.a, s.b] {
                degree[v] = degree[v].saturating_add(1);
            }
        }
        degree.iter().all(|&d| d == 2)
    }

    fn lab(&self, i: usize) -> i64 {
        self.labels.get(i).copied().unwrap_or(i as i64 + 1)
    }

    /// The name of region attribute `a`.
    pub fn region_name(&self, a: i64) -> String {
        self.region_names
            .get(&a)
            .cloned()
            .unwrap_or_else(|| format!("region_{a}"))
    }

    /// The name of segment marker `m`.
    pub fn group_name(&self, m: i64) -> String {
        self.group_names
            .get(&m)
            .cloned()
            .unwrap_or_else(|| format!("marker_{m}"))
    }

    /// Refuses repeated segments, dangling segments, crossings, nodes on
    /// other segments and coincident nodes. Pairs are checked within the
    /// cells of a uniform grid over the segments' boxes, so the cost grows
    /// with the number of segments, not its square, for evenly spread
    /// graphs.
    fn check(&self) -> Result<(), PslgError> {
        if self.segments.is_empty() {
            return Err(PslgError::Empty);
        }
        let mut seen = BTreeMap::new();
        let mut degree = vec![0usize; self.points.len()];
        for s in &self.segments {
            let key = (s.a.min(s.b), s.a.max(s.b));
            if seen.insert(key, ()).is_some() {
                return Err(PslgError::Repeated {
                    a: self.lab(s.a),
                    b: self.lab(s.b),
                });
            }
            degree[s.a] += 1;
            degree[s.b] += 1;
        }
        if let Some(v) = degree.iter().position(|&d| d == 1) {
            return Err(PslgError::Dangling { node: self.lab(v) });
        }
        let used: Vec<usize> = (0..self.points.len()).filter(|&v| degree[v] > 0).collect();
        // A uniform grid of about one cell per segment.
        let (mut lo, mut hi) = (Point::splat(f64::INFINITY), Point::splat(f64::NEG_INFINITY));
        for &v in &used {
            lo = lo.min(self.points[v]);
            hi = hi.max(self.points[v]);
        }
        let n = self.segments.len().max(1);
        let side = (n as f64).sqrt().ceil().max(1.0) as usize;
        let ext = (hi - lo).max(Point::splat(f64::MIN_POSITIVE));
        let cell = |p: Point| -> (usize, usize) {
            let f = (p - lo) / ext * side as f64;
            (
                (f.x.max(0.0) as usize).min(side - 1),
                (f.y.max(0.0) as usize).min(side - 1),
            )
        };
        let mut grid: Vec<Vec<usize>> = vec![Vec::new(); side * side];
        for (k, s) in self.segments.iter().enumerate() {
            let (a, b) = (self.points[s.a], self.points[s.b]);
            let (c0, c1) = (cell(a.min(b)), cell(a.max(b)));
            for i in c0.0..=c1.0 {
                for j in c0.1..=c1.1 {
                    grid[j * side + i].push(k);
                }
            }
        }
        let mut node_grid: Vec<Vec<usize>> = vec![Vec::new(); side * side];
        for &v in &used {
            let c = cell(self.points[v]);
            node_grid[c.1 * side + c.0].push(v);
        }
        let near = |p: Point, a: Point, b: Point| {
            let m = [p, a, b]
                .iter()
                .fold(0.0f64, |m, q| m.max(q.x.abs()).max(q.y.abs()));
            crate::geom::point_segment_distance(p, a, b) <= TOUCH_EPS * m
        };
        // Nodes against the segments of their cell first: a node on a
        // segment also makes the segments at it touch that one.
        for c in 0..side * side {
            let segs = &grid[c];
            for &v in &node_grid[c] {
                let p = self.points[v];
                for &k in segs {
                    let s = self.segments[k];
                    if s.a == v || s.b == v {
                        continue;
                    }
                    let (a, b) = (self.points[s.a], self.points[s.b]);
                    if orient(a, b, p) == 0.0 && within(p, a, b) || near(p, a, b) {
                        if p == a || p == b || near(p, a, a) || near(p, b, b) {
                            let other = if near(p, a, a) { s.a } else { s.b };
                            return Err(PslgError::Coincident {
                                a: self.lab(v.min(other)),
                                b: self.lab(v.max(other)),
                                x: p.x,
                                y: p.y,
                            });
                        }
                        return Err(PslgError::NodeOnSegment {
                            node: self.lab(v),
                            a: self.lab(s.a),
                            b: self.lab(s.b),
                            x: p.x,
                            y: p.y,
                        });
                    }
                }
            }
        }
        for segs in &grid {
            // Segments against segments.
            for (x, &k) in segs.iter().enumerate() {
                for &l in &segs[x + 1..] {
                    let (s, t) = (self.segments[k], self.segments[l]);
                    if s.a == t.a || s.a == t.b || s.b == t.a || s.b == t.b {
                        // Segments at one node overlap only when collinear
                        // and pointing the same way.
                        let (w, p, r) = if s.a == t.a || s.a == t.b {
                            (s.a, s.b, if s.a == t.a { t.b } else { t.a })
                        } else {
                            (s.b, s.a, if s.b == t.a { t.b } else { t.a })
                        };
                        let (pw, pp, pr) = (self.points[w], self.points[p], self.points[r]);
                        if orient(pw, pp, pr) == 0.0 && (pp - pw).dot(pr - pw) > 0.0 {
                            let (node, a, b) = if (pp - pw).length() < (pr - pw).length() {
                                (p, w, r)
                            } else {
                                (r, w, p)
                            };
                            return Err(PslgError::NodeOnSegment {
                                node: self.lab(node),
                                a: self.lab(a),
                                b: self.lab(b),
                                x: self.points[node].x,
                                y: self.points[node].y,
                            });
                        }
                        continue;
                    }
                    let (a, b, c, d) = (
                        self.points[s.a],
                        self.points[s.b],
                        self.points[t.a],
                        self.points[t.b],
                    );
                    if segments_intersect(a, b, c, d) {
                        let at = crossing_point(a, b, c, d);
                        return Err(PslgError::Crossing {
                            a: self.lab(s.a),
                            b: self.lab(s.b),
                            c: self.lab(t.a),
                            d: self.lab(t.b),
                            x: at.x,
                            y: at.y,
                        });
                    }
                }
            }
        }
        Ok(())
    }

    /// Every bounded face of the graph, in a fixed order, with its loops
    /// (graph node indices: the outer loop counter-clockwise, then its
    /// holes clockwise), whether it is meshed and its attribute. Neither
    /// node counts nor the loops as a boundary are checked yet.
    pub fn face_cycles(&self) -> Result<Vec<FaceCycle>, PslgError> {
        self.check()?;
        let n = self.points.len();
        // Neighbours of each node, counter-clockwise by angle.
        let mut around: Vec<Vec<usize>> = vec![Vec::new(); n];
        for s in &self.segments {
            around[s.a].push(s.b);
            around[s.b].push(s.a);
        }
        for (v, nb) in around.iter_mut().enumerate() {
            let p = self.points[v];
            nb.sort_by(|&x, &y| {
                let (dx, dy) = (self.points[x] - p, self.points[y] - p);
                dx.y.atan2(dx.x).total_cmp(&dy.y.atan2(dy.x))
            });
        }
        // Directed segments walked with their face on the left: after u→v
        // comes v→w, w the neighbour of v just clockwise of u.
        let mut done: BTreeMap<(usize, usize), usize> = BTreeMap::new();
        let mut cycles: Vec<Cycle> = Vec::new();
        let mut starts: Vec<(usize, usize)> = Vec::new();
        for s in &self.segments {
            starts.push((s.a, s.b));
            starts.push((s.b, s.a));
        }
        starts.sort_unstable();
        for start in starts {
            if done.contains_key(&start) {
                continue;
            }
            let id = cycles.len();
            let mut nodes = Vec::new();
            let (mut u, mut v) = start;
            loop {
                if done.insert((u, v), id).is_some() {
                    break;
                }
                nodes.push(u);
                let nb = &around[v];
                let k = nb.iter().position(|&x| x == u).unwrap_or(0);
                let w = nb[(k + nb.len() - 1) % nb.len()];
                (u, v) = (v, w);
            }
            let poly: Vec<Point> = nodes.iter().map(|&i| self.points[i]).collect();
            let (mut lo, mut hi) = (Point::splat(f64::INFINITY), Point::splat(f64::NEG_INFINITY));
            for &p in &poly {
                lo = lo.min(p);
                hi = hi.max(p);
            }
            cycles.push(Cycle {
                area: polygon_area(poly.iter().copied()),
                nodes,
                poly,
                lo,
                hi,
            });
        }
        // A segment with one cycle on both sides is a slit.
        for s in &self.segments {
            if done.get(&(s.a, s.b)) == done.get(&(s.b, s.a)) {
                return Err(PslgError::Slit {
                    a: self.lab(s.a),
                    b: self.lab(s.b),
                });
            }
        }
        let ccw: Vec<usize> = (0..cycles.len())
            .filter(|&c| cycles[c].area > 0.0)
            .collect();
        // The smallest counter-clockwise cycle that contains p, of another
        // piece than `own` (a piece's cycles share no containment).
        let piece = pieces(n, &self.segments);
        let locate = |p: Point, own: Option<usize>| -> Option<usize> {
            ccw.iter()
                .copied()
                .filter(|&c| own.is_none_or(|o| piece[cycles[c].nodes[0]] != o))
                .filter(|&c| cycles[c].contains(p))
                .min_by(|&a, &b| cycles[a].area.total_cmp(&cycles[b].area))
        };
        // Holes of each counter-clockwise cycle.
        let mut holes: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        let mut parent_of_piece: BTreeMap<usize, Option<usize>> = BTreeMap::new();
        for (c, cy) in cycles.iter().enumerate() {
            if cy.area < 0.0 {
                let own = piece[cy.nodes[0]];
                let parent = locate(cy.poly[0], Some(own));
                parent_of_piece.insert(own, parent);
                if let Some(f) = parent {
                    holes.entry(f).or_default().push(c);
                }
            }
        }
        // Depth of each face: the number of faces it lies in.
        let depth = |mut c: usize| -> usize {
            let mut d = 0;
            while let Some(Some(p)) = parent_of_piece.get(&piece[cycles[c].nodes[0]]) {
                d += 1;
                c = *p;
            }
            d
        };
        let mut hollow: Vec<bool> = vec![false; cycles.len()];
        for &h in &self.holes {
            if let Some(c) = locate(h, None) {
                hollow[c] = true;
            }
        }
        let mut attribute: BTreeMap<usize, (usize, i64)> = BTreeMap::new();
        for (i, r) in self.regions.iter().enumerate() {
            let c = locate(r.at, None).ok_or(PslgError::RegionOutside {
                index: i + 1,
                x: r.at.x,
                y: r.at.y,
            })?;
            if let Some(&(first, a)) = attribute.get(&c) {
                if a != r.attribute {
                    return Err(PslgError::RegionConflict {
                        first,
                        second: i + 1,
                        a,
                        b: r.attribute,
                    });
                }
            } else {
                attribute.insert(c, (i + 1, r.attribute));
            }
        }
        let mut out = Vec::new();
        for &c in &ccw {
            let meshed = !(hollow[c] || (self.regions.is_empty() && depth(c) % 2 == 1));
            let mut attr = attribute.get(&c).map_or(0, |&(_, a)| a);
            if meshed && self.regions.is_empty() && self.face_regions {
                attr = out.iter().filter(|f: &&FaceCycle| f.meshed).count() as i64 + 1;
            }
            let mut loops = vec![cycles[c].nodes.clone()];
            for &h in holes.get(&c).map_or(&[][..], |v| &v[..]) {
                loops.push(cycles[h].nodes.clone());
            }
            out.push(FaceCycle {
                loops,
                meshed,
                attribute: attr,
            });
        }
        Ok(out)
    }

    /// The faces to mesh, in a fixed order (by their smallest node index),
    /// each with its boundary validated ([`Boundary::new`]) and an even
    /// node count.
    pub fn faces(&self) -> Result<Vec<Face>, PslgError> {
        let mut faces = Vec::new();
        for f in self.face_cycles()? {
            if !f.meshed {
                continue;
            }
            let count: usize = f.loops.iter().map(Vec::len).sum();
            let region = self.region_name(f.attribute);
            if count % 2 == 1 {
                return Err(PslgError::OddRegion { region, count });
            }
            let mut nodes: Vec<usize> = Vec::with_capacity(count);
            let loops: Vec<Vec<usize>> = f
                .loops
                .iter()
                .map(|l| {
                    l.iter()
                        .map(|&g| {
                            nodes.push(g);
                            nodes.len() - 1
                        })
                        .collect()
                })
                .collect();
            let points = nodes.iter().map(|&g| self.points[g]).collect();
            let labels = nodes.iter().map(|&g| self.lab(g)).collect();
            let boundary = Boundary::new(points, loops, Some(labels))
                .map_err(|source| PslgError::Face { region, source })?;
            faces.push(Face {
                boundary,
                nodes,
                attribute: f.attribute,
            });
        }
        if faces.is_empty() {
            return Err(PslgError::NothingToMesh);
        }
        Ok(faces)
    }
}

/// True when `p`, collinear with `a–b`, lies strictly inside the segment.
fn within(p: Point, a: Point, b: Point) -> bool {
    p != a
        && p != b
        && p.x >= a.x.min(b.x)
        && p.x <= a.x.max(b.x)
        && p.y >= a.y.min(b.y)
        && p.y <= a.y.max(b.y)
}

/// The connected piece of each node (its smallest node index).
fn pieces(n: usize, segments: &[Segment]) -> Vec<usize> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for s in segments {
        let (a, b) = (root(&mut parent, s.a), root(&mut parent, s.b));
        if a != b {
            parent[a.max(b)] = a.min(b);
        }
    }
    (0..n).map(|v| root(&mut parent, v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square cut by the vertical x = 0.5, `k` nodes a side.
    fn split_square() -> Pslg {
        // 0 (0,0) 1 (0.5,0) 2 (1,0) 3 (1,1) 4 (0.5,1) 5 (0,1)
        let points = [
            (0.0, 0.0),
            (0.5, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.5, 1.0),
            (0.0, 1.0),
        ]
        .map(|(x, y)| Point::new(x, y))
        .to_vec();
        let seg = |a, b, marker| Segment { a, b, marker };
        Pslg {
            labels: (1..=6).collect(),
            points,
            segments: vec![
                seg(0, 1, 1),
                seg(1, 2, 1),
                seg(2, 3, 2),
                seg(3, 4, 0),
                seg(4, 5, 0),
                seg(5, 0, 3),
                seg(1, 4, 4),
            ],
            ..Pslg::default()
        }
    }

    #[test]
    fn a_split_square_has_two_faces() {
        let g = split_square();
        let faces = g.faces().unwrap();
        assert_eq!(faces.len(), 2);
        for f in &faces {
            assert_eq!(f.boundary.node_count(), 4);
            assert!((f.boundary.area() - 0.5).abs() < 1e-12);
        }
    }

    #[test]
    fn region_points_name_faces() {
        let mut g = split_square();
        g.regions = vec![
            RegionPoint {
                at: Point::new(0.25, 0.5),
                attribute: 1,
                max_area: None,
            },
            RegionPoint {
                at: Point::new(0.75, 0.5),
                attribute: 2,
                max_area: None,
            },
        ];
        let faces = g.faces().unwrap();
        let mut attrs: Vec<i64> = faces.iter().map(|f| f.attribute).collect();
        attrs.sort_unstable();
        assert_eq!(attrs, [1, 2]);
        g.regions[1].at = Point::new(0.3, 0.5);
        assert!(matches!(
            g.faces(),
            Err(PslgError::RegionConflict {
                first: 1,
                second: 2,
                ..
            })
        ));
        g.regions[1].at = Point::new(3.0, 0.5);
        assert!(matches!(
            g.faces(),
            Err(PslgError::RegionOutside { index: 2, .. })
        ));
    }

    #[test]
    fn a_hole_point_empties_its_face() {
        let mut g = split_square();
        g.holes = vec![Point::new(0.75, 0.5)];
        let faces = g.faces().unwrap();
        assert_eq!(faces.len(), 1);
        assert!(faces[0].boundary.points.iter().all(|p| p.x <= 0.5));
    }

    #[test]
    fn broken_graphs_are_refused() {
        let mut g = split_square();
        g.segments.pop();
        g.segments.push(Segment {
            a: 1,
            b: 3,
            marker: 0,
        });
        g.segments.push(Segment {
            a: 4,
            b: 2,
            marker: 0,
        });
        // The error says where: (0.5, 0)–(1, 1) and (0.5, 1)–(1, 0) cross
        // at (0.75, 0.5).
        let err = g.faces().unwrap_err();
        assert!(
            matches!(err, PslgError::Crossing { x, y, .. } if (x - 0.75).abs() < 1e-12 && (y - 0.5).abs() < 1e-12),
            "{err}"
        );
        assert!(err.to_string().ends_with("at about (0.75, 0.5)"), "{err}");
        let mut g = split_square();
        g.points.push(Point::new(0.5, 0.5));
        g.labels.push(7);
        g.segments.push(Segment {
            a: 0,
            b: 6,
            marker: 0,
        });
        assert_eq!(g.faces(), Err(PslgError::Dangling { node: 7 }));
    }
}

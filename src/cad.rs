//! Geometry as CAD users have it: lines and circular arcs on named layers,
//! read from DXF, and cut into boundary nodes at a target size with every
//! region's node count made even.
//!
//! The method (`../shared/docs/method.md` §1) starts from boundary nodes;
//! this module places them. [`read_dxf`] reads LINE, ARC, CIRCLE and
//! LWPOLYLINE / POLYLINE (straight and bulged segments) entities into
//! [`Curve`]s, joins their ends within [`JOIN_TOLERANCE`] of the drawing's
//! size and refuses a gap with its position. [`Geometry::discretise`] cuts
//! each curve into about `length / h` segments (arcs also into at least
//! one segment per [`MAX_ARC_ANGLE`], which bounds the chord error), then
//! solves parity over the whole graph: adding one segment to a curve flips
//! the parity of the two faces beside it, so the curves to refine are the
//! edges of a spanning forest of the faces (built over the curves with the
//! most segments first, where one more changes the spacing least), and
//! every odd face flips the curve to its parent. A face beside no other
//! face to mesh (a hole, the outside) takes any parity, so every region
//! ends even and a user never sees an odd-count refusal. Each layer
//! becomes a boundary group (a segment marker named after the layer).

use crate::geom::Point;
use crate::pslg::{Pslg, PslgError, Segment};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use thiserror::Error;

/// Two curve ends closer than this times the drawing's extent are one
/// vertex.
pub const JOIN_TOLERANCE: f64 = 1e-6;

/// The largest angle an arc segment spans: 15°, a chord error of at most
/// 0.86 % of the radius.
pub const MAX_ARC_ANGLE: f64 = PI / 12.0;

/// A curve of a drawing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Curve {
    /// A straight segment from `a` to `b`.
    Line { a: Point, b: Point },
    /// A circular arc about `centre` of `radius`, from angle `start` over
    /// `sweep` radians (positive counter-clockwise; ±2π a full circle).
    Arc {
        centre: Point,
        radius: f64,
        start: f64,
        sweep: f64,
    },
}

impl Curve {
    /// The point at parameter `t` in [0, 1].
    pub fn at(&self, t: f64) -> Point {
        match *self {
            Curve::Line { a, b } => a + (b - a) * t,
            Curve::Arc {
                centre,
                radius,
                start,
                sweep,
            } => {
                let th = start + sweep * t;
                centre + Point::new(th.cos(), th.sin()) * radius
            }
        }
    }

    pub fn length(&self) -> f64 {
        match *self {
            Curve::Line { a, b } => (b - a).length(),
            Curve::Arc { radius, sweep, .. } => radius * sweep.abs(),
        }
    }

    /// True for a curve that ends where it starts (a full circle).
    pub fn is_closed(&self) -> bool {
        matches!(*self, Curve::Arc { sweep, .. } if (sweep.abs() - 2.0 * PI).abs() < 1e-12)
    }

    /// The fewest segments this curve is cut into: 1 for a line, one per
    /// [`MAX_ARC_ANGLE`] for an arc (3 at least for a full circle).
    fn min_segments(&self) -> usize {
        match *self {
            Curve::Line { .. } => 1,
            Curve::Arc { sweep, .. } => {
                let n = (sweep.abs() / MAX_ARC_ANGLE - 1e-9).ceil().max(1.0) as usize;
                if self.is_closed() {
                    n.max(3)
                } else {
                    n
                }
            }
        }
    }

    /// The distance from `p` to the curve.
    pub fn distance(&self, p: Point) -> f64 {
        match *self {
            Curve::Line { a, b } => crate::geom::point_segment_distance(p, a, b),
            Curve::Arc {
                centre,
                radius,
                start,
                sweep,
            } => {
                let d = p - centre;
                let th = d.y.atan2(d.x);
                // The angle of p measured along the sweep from the start.
                let along = ((th - start) * sweep.signum()).rem_euclid(2.0 * PI);
                if along <= sweep.abs() + 1e-12 {
                    (d.length() - radius).abs()
                } else {
                    (p - self.at(0.0)).length().min((p - self.at(1.0)).length())
                }
            }
        }
    }
}

/// A curve on its layer.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerCurve {
    pub curve: Curve,
    pub layer: String,
}

/// The curves of a drawing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Geometry {
    pub curves: Vec<LayerCurve>,
}

/// Why a drawing cannot become a boundary.
#[derive(Debug, Error)]
pub enum CadError {
    #[error("cannot read the DXF file: {0}")]
    Dxf(String),
    #[error("the drawing has no lines, arcs, circles or polylines")]
    Empty,
    #[error("{kind} entities are not read (entity {index} on layer {layer:?}): draw the outline with lines, arcs, circles and polylines")]
    Unsupported {
        kind: &'static str,
        index: usize,
        layer: String,
    },
    #[error(
        "the outline is open: the end at ({x}, {y}) meets no other curve's end (within {tol:.1e})"
    )]
    Gap { x: f64, y: f64, tol: f64 },
    #[error("the curve on layer {layer:?} at ({x}, {y}) is degenerate (no length)")]
    Degenerate { layer: String, x: f64, y: f64 },
    #[error("a size must be a positive number, not {0}")]
    BadSize(f64),
    #[error("{0}")]
    Graph(#[from] PslgError),
}

/// The arc of a polyline segment from `a` to `b` with `bulge` (the
/// tangent of a quarter of its included angle, positive counter-clockwise).
fn bulge_curve(a: Point, b: Point, bulge: f64) -> Curve {
    if bulge.abs() < 1e-12 {
        return Curve::Line { a, b };
    }
    let sweep = 4.0 * bulge.atan();
    let chord = b - a;
    let half = chord.length() / 2.0;
    let radius = half / (sweep / 2.0).sin().abs();
    // The centre lies on the chord's bisector, to the left for a
    // counter-clockwise arc of less than half a turn.
    let mid = a + chord * 0.5;
    let normal = Point::new(-chord.y, chord.x) / chord.length();
    let offset = (radius * radius - half * half).max(0.0).sqrt();
    let side = if (sweep.abs() < PI) == (sweep > 0.0) {
        1.0
    } else {
        -1.0
    };
    let centre = mid + normal * (offset * side);
    let d = a - centre;
    Curve::Arc {
        centre,
        radius,
        start: d.y.atan2(d.x),
        sweep,
    }
}

/// Reads the curves of a DXF file (its entities section; blocks are not
/// expanded).
pub fn read_dxf(path: &std::path::Path) -> Result<Geometry, CadError> {
    let drawing = dxf::Drawing::load_file(path).map_err(|e| CadError::Dxf(e.to_string()))?;
    geometry_of(&drawing)
}

/// The curves of a DXF drawing.
pub fn geometry_of(drawing: &dxf::Drawing) -> Result<Geometry, CadError> {
    use dxf::entities::EntityType as E;
    let mut g = Geometry::default();
    let p2 = |p: &dxf::Point| Point::new(p.x, p.y);
    for (index, e) in drawing.entities().enumerate() {
        let layer = e.common.layer.clone();
        let mut push = |curve: Curve| {
            g.curves.push(LayerCurve {
                curve,
                layer: layer.clone(),
            })
        };
        match &e.specific {
            E::Line(l) => push(Curve::Line {
                a: p2(&l.p1),
                b: p2(&l.p2),
            }),
            E::Arc(a) => {
                let sweep = (a.end_angle - a.start_angle).rem_euclid(360.0);
                let sweep = if sweep == 0.0 { 360.0 } else { sweep };
                push(Curve::Arc {
                    centre: p2(&a.center),
                    radius: a.radius,
                    start: a.start_angle.to_radians(),
                    sweep: sweep.to_radians(),
                })
            }
            E::Circle(c) => push(Curve::Arc {
                centre: p2(&c.center),
                radius: c.radius,
                start: 0.0,
                sweep: 2.0 * PI,
            }),
            E::LwPolyline(pl) => {
                let v = &pl.vertices;
                let n = v.len();
                let segs = if pl.is_closed() {
                    n
                } else {
                    n.saturating_sub(1)
                };
                for k in 0..segs {
                    let (a, b) = (&v[k], &v[(k + 1) % n]);
                    push(bulge_curve(
                        Point::new(a.x, a.y),
                        Point::new(b.x, b.y),
                        a.bulge,
                    ));
                }
            }
            E::Polyline(pl) => {
                let v: Vec<&dxf::entities::Vertex> = pl.vertices().collect();
                let n = v.len();
                let segs = if pl.is_closed() {
                    n
                } else {
                    n.saturating_sub(1)
                };
                for k in 0..segs {
                    let (a, b) = (v[k], v[(k + 1) % n]);
                    push(bulge_curve(p2(&a.location), p2(&b.location), a.bulge));
                }
            }
            E::Spline(_) => {
                return Err(CadError::Unsupported {
                    kind: "SPLINE",
                    index: index + 1,
                    layer,
                })
            }
            E::Ellipse(_) => {
                return Err(CadError::Unsupported {
                    kind: "ELLIPSE",
                    index: index + 1,
                    layer,
                })
            }
            _ => {}
        }
    }
    if g.curves.is_empty() {
        return Err(CadError::Empty);
    }
    Ok(g)
}

/// The curves' end vertices, joined within the tolerance: per curve its
/// start and end vertex (the same for a full circle), and the vertices.
fn join_ends(g: &Geometry) -> Result<(Vec<[usize; 2]>, Vec<Point>), CadError> {
    let (mut lo, mut hi) = (Point::splat(f64::INFINITY), Point::splat(f64::NEG_INFINITY));
    for c in &g.curves {
        for t in [0.0, 0.25, 0.5, 0.75, 1.0] {
            let p = c.curve.at(t);
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    let tol = JOIN_TOLERANCE * (hi - lo).max_element().max(f64::MIN_POSITIVE);
    let mut vertices: Vec<Point> = Vec::new();
    let mut find = |p: Point| -> usize {
        match vertices.iter().position(|&v| (v - p).length() <= tol) {
            Some(i) => i,
            None => {
                vertices.push(p);
                vertices.len() - 1
            }
        }
    };
    let mut ends = Vec::with_capacity(g.curves.len());
    for c in &g.curves {
        if c.curve.length() <= tol {
            let p = c.curve.at(0.0);
            return Err(CadError::Degenerate {
                layer: c.layer.clone(),
                x: p.x,
                y: p.y,
            });
        }
        let a = find(c.curve.at(0.0));
        let b = if c.curve.is_closed() {
            a
        } else {
            find(c.curve.at(1.0))
        };
        ends.push([a, b]);
    }
    let mut degree = vec![0usize; vertices.len()];
    for e in &ends {
        degree[e[0]] += 1;
        degree[e[1]] += 1;
    }
    if let Some(v) = degree.iter().position(|&d| d < 2) {
        return Err(CadError::Gap {
            x: vertices[v].x,
            y: vertices[v].y,
            tol,
        });
    }
    Ok((ends, vertices))
}

/// The boundary nodes of a geometry: the graph and, for each of its
/// segments, the curve it lies on.
#[derive(Clone, Debug)]
pub struct Discretised {
    pub graph: Pslg,
    /// The curve (index into the geometry's curves) of each segment.
    pub curve_of: Vec<usize>,
    /// Segments per curve.
    pub counts: Vec<usize>,
    /// The curves given one segment more to make every region even.
    pub parity_fixes: Vec<usize>,
    /// The curve parameters of each segment's ends.
    params: Vec<(f64, f64)>,
    /// The segment between two node positions, either way round.
    by_ends: std::collections::HashMap<(Key, Key), usize>,
    curves: Vec<Curve>,
}

/// A node position as its coordinates' bits.
type Key = (u64, u64);

fn key(p: Point) -> Key {
    (p.x.to_bits(), p.y.to_bits())
}

impl Discretised {
    /// The point halfway along its curve between the nodes at `a` and `b`,
    /// when they are the ends of one of the graph's segments: where a
    /// second-order boundary edge puts its midside node.
    pub fn midside(&self, a: Point, b: Point) -> Option<Point> {
        let &s = self.by_ends.get(&(key(a), key(b)))?;
        let (ta, tb) = self.params[s];
        Some(self.curves[self.curve_of[s]].at(0.5 * (ta + tb)))
    }
}

impl Geometry {
    /// The layers, sorted: layer `k` is segment marker `k + 1`.
    pub fn layers(&self) -> Vec<String> {
        let mut l: Vec<String> = self.curves.iter().map(|c| c.layer.clone()).collect();
        l.sort();
        l.dedup();
        l
    }

    /// Boundary nodes on every curve at about size `h`, every face to
    /// mesh with an even node count.
    pub fn discretise(&self, h: f64) -> Result<Discretised, CadError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(CadError::BadSize(h));
        }
        let (ends, vertices) = join_ends(self)?;
        let mut counts: Vec<usize> = self
            .curves
            .iter()
            .map(|c| ((c.curve.length() / h).round() as usize).max(c.curve.min_segments()))
            .collect();
        let first = self.build(&ends, &vertices, &counts);
        let fixes = parity_fixes(&first, self.curves.len())?;
        for &c in &fixes {
            counts[c] += 1;
        }
        let mut d = self.build(&ends, &vertices, &counts);
        d.parity_fixes = fixes;
        Ok(d)
    }

    /// The graph of the curves cut into `counts` segments each.
    fn build(&self, ends: &[[usize; 2]], vertices: &[Point], counts: &[usize]) -> Discretised {
        let layers = self.layers();
        let mut g = Pslg {
            points: vertices.to_vec(),
            labels: (1..=vertices.len() as i64).collect(),
            face_regions: true,
            ..Pslg::default()
        };
        for (k, name) in layers.iter().enumerate() {
            g.group_names.insert(k as i64 + 1, name.clone());
        }
        let mut curve_of = Vec::new();
        let mut params = Vec::new();
        for (ci, (c, e)) in self.curves.iter().zip(ends).enumerate() {
            let marker = layers.binary_search(&c.layer).map_or(0, |k| k as i64 + 1);
            let n = counts[ci];
            let mut prev = e[0];
            for k in 1..=n {
                let id = if k == n {
                    e[1]
                } else {
                    g.points.push(c.curve.at(k as f64 / n as f64));
                    g.labels.push(g.points.len() as i64);
                    g.points.len() - 1
                };
                g.segments.push(Segment {
                    a: prev,
                    b: id,
                    marker,
                });
                curve_of.push(ci);
                params.push(((k - 1) as f64 / n as f64, k as f64 / n as f64));
                prev = id;
            }
        }
        let mut by_ends = std::collections::HashMap::new();
        for (k, seg) in g.segments.iter().enumerate() {
            let (a, b) = (key(g.points[seg.a]), key(g.points[seg.b]));
            by_ends.insert((a, b), k);
            by_ends.insert((b, a), k);
        }
        Discretised {
            graph: g,
            curve_of,
            counts: counts.to_vec(),
            parity_fixes: Vec::new(),
            params,
            by_ends,
            curves: self.curves.iter().map(|c| c.curve).collect(),
        }
    }
}

/// The curves to give one segment more so that every face to mesh has an
/// even node count (see the module's documentation).
fn parity_fixes(d: &Discretised, n_curves: usize) -> Result<Vec<usize>, CadError> {
    let cycles = d.graph.face_cycles()?;
    // The face on the left of each directed segment: meshed faces by
    // index, every other side is the free face.
    let free = cycles.len();
    let mut left: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    let mut odd = vec![false; free + 1];
    for (f, c) in cycles.iter().enumerate() {
        if !c.meshed {
            continue;
        }
        let count: usize = c.loops.iter().map(Vec::len).sum();
        odd[f] = count % 2 == 1;
        for l in &c.loops {
            for k in 0..l.len() {
                left.insert((l[k], l[(k + 1) % l.len()]), f);
            }
        }
    }
    // Each curve joins the faces on its two sides.
    let mut sides: Vec<Option<(usize, usize)>> = vec![None; n_curves];
    for (s, seg) in d.graph.segments.iter().enumerate() {
        let c = d.curve_of[s];
        if sides[c].is_none() {
            let l = left.get(&(seg.a, seg.b)).copied().unwrap_or(free);
            let r = left.get(&(seg.b, seg.a)).copied().unwrap_or(free);
            sides[c] = Some((l, r));
        }
    }
    // A spanning forest over the curves with the most segments first.
    let mut order: Vec<usize> = (0..n_curves).collect();
    order.sort_by_key(|&c| (std::cmp::Reverse(d.counts[c]), c));
    let mut parent: Vec<usize> = (0..=free).collect();
    fn root(p: &mut [usize], mut v: usize) -> usize {
        while p[v] != v {
            p[v] = p[p[v]];
            v = p[v];
        }
        v
    }
    let mut tree: Vec<Vec<(usize, usize)>> = vec![Vec::new(); free + 1];
    for c in order {
        let Some((a, b)) = sides[c] else { continue };
        if a == b {
            continue;
        }
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        if ra != rb {
            parent[ra] = rb;
            tree[a].push((b, c));
            tree[b].push((a, c));
        }
    }
    // Post-order over each tree from its root (the free face first):
    // an odd face flips the curve to its parent.
    let mut fixes = Vec::new();
    let mut seen = vec![false; free + 1];
    let mut roots: Vec<usize> = vec![free];
    roots.extend(0..free);
    for r in roots {
        if seen[r] {
            continue;
        }
        let mut stack = vec![(r, usize::MAX, usize::MAX)];
        let mut post = Vec::new();
        seen[r] = true;
        while let Some((v, up, via)) = stack.pop() {
            post.push((v, up, via));
            for &(w, c) in &tree[v] {
                if !seen[w] {
                    seen[w] = true;
                    stack.push((w, v, c));
                }
            }
        }
        for &(v, up, via) in post.iter().rev() {
            if odd[v] && up != usize::MAX {
                odd[v] = false;
                odd[up] = !odd[up];
                fixes.push(via);
            }
        }
    }
    fixes.sort_unstable();
    Ok(fixes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bulge_of_one_is_a_half_circle() {
        let c = bulge_curve(Point::new(0.0, 0.0), Point::new(2.0, 0.0), 1.0);
        let Curve::Arc {
            centre,
            radius,
            sweep,
            ..
        } = c
        else {
            panic!("{c:?}")
        };
        assert!((centre - Point::new(1.0, 0.0)).length() < 1e-12);
        assert!((radius - 1.0).abs() < 1e-12);
        assert!((sweep - PI).abs() < 1e-12);
        // Counter-clockwise from (0,0) to (2,0) passes below.
        assert!((c.at(0.5) - Point::new(1.0, -1.0)).length() < 1e-12);
        assert!((c.at(1.0) - Point::new(2.0, 0.0)).length() < 1e-12);
    }

    #[test]
    fn odd_faces_are_made_even_by_curves_between_them() {
        // A square cut in two; 3 + 1 + 3 + 1 segments and a 1-segment
        // interface: both faces odd until the interface gets one more.
        let l = |a: (f64, f64), b: (f64, f64), layer: &str| LayerCurve {
            curve: Curve::Line {
                a: Point::new(a.0, a.1),
                b: Point::new(b.0, b.1),
            },
            layer: layer.into(),
        };
        let g = Geometry {
            curves: vec![
                l((0.0, 0.0), (1.0, 0.0), "bottom"),
                l((1.0, 0.0), (2.0, 0.0), "bottom"),
                l((2.0, 0.0), (2.0, 1.0), "right"),
                l((2.0, 1.0), (1.0, 1.0), "top"),
                l((1.0, 1.0), (0.0, 1.0), "top"),
                l((0.0, 1.0), (0.0, 0.0), "left"),
                l((1.0, 0.0), (1.0, 1.0), "middle"),
            ],
        };
        let d = g.discretise(0.34).unwrap();
        let faces = d.graph.faces().unwrap();
        assert_eq!(faces.len(), 2);
        assert!(faces.iter().all(|f| f.boundary.node_count() % 2 == 0));
        assert_eq!(d.graph.group_name(3), "middle");
    }
}

//! Geometry as CAD users have it: lines, circular and elliptical arcs and
//! splines on named layers, read from DXF or a JSON geometry file, and cut
//! into boundary nodes at a target size with every region's node count
//! made even.
//!
//! The method (`../shared/docs/method.md` §1) starts from boundary nodes;
//! this module places them. [`read_dxf`] reads LINE, ARC, CIRCLE, ELLIPSE,
//! SPLINE and LWPOLYLINE / POLYLINE (straight and bulged segments)
//! entities into [`Curve`]s, [`read_geometry_json`] the same curves from
//! JSON; their ends are joined within [`JOIN_TOLERANCE`] of the drawing's
//! size and a gap is refused with its position. [`Geometry::discretise`]
//! cuts each curve at the sizes a [`SizeSpec`] asks (a target size, point
//! sizes, layer sizes, blended at a gradation), no longer than
//! [`MAX_ARC_ANGLE`] of the local curvature (which bounds the chord
//! error), and grading from the spacing of the curves meeting at its ends;
//! then it solves parity over the whole graph: adding one segment to a
//! curve flips the parity of the two faces beside it, so the curves to
//! refine are the edges of a spanning forest of the faces (built over the
//! curves with the most segments first, where one more changes the
//! spacing least), and every odd face flips the curve to its parent. A
//! face beside no other face to mesh (a hole, the outside) takes any
//! parity, so every region ends even and a user never sees an odd-count
//! refusal. Each layer becomes a boundary group (a segment marker named
//! after the layer).

use crate::geom::Point;
use crate::pslg::{FaceCycle, Pslg, PslgError, Segment};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::sync::Arc;
use thiserror::Error;

mod curve;
pub mod json;

pub use curve::{arc_through, Curve, Nurbs, MAX_ARC_ANGLE};
pub use json::{
    is_geometry_file, is_geometry_json, parse_geometry_json, read_geometry_json, CadDocument,
};

/// Two curve ends closer than this times the drawing's extent are one
/// vertex.
pub const JOIN_TOLERANCE: f64 = 1e-6;

/// Angles (radians) closer than this are one: an elliptical arc whose
/// sweep is within it of none or of a full turn is a full ellipse.
pub const ANGLE_TOLERANCE: f64 = 1e-9;

/// The default growth of the element size with distance from a finer
/// local size (size per unit length): away from a size `h_i` the size is
/// `h_i + 0.3·d`, about a 1.3 ratio from one element to the next.
pub const GRADATION: f64 = 0.3;

/// A point size: the size wanted at `at`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointSize {
    pub at: Point,
    pub size: f64,
}

/// The sizes a drawing is meshed at: the target size `size` everywhere,
/// finer near point sizes and on the curves of sized layers, blended at
/// `gradation`: at `p` the size is
/// `min(size, h_i + gradation·|p − p_i|, h_L + gradation·dist(p, layer L))`
/// (a curve on a sized layer itself takes its layer's size, coarser or
/// finer; beside a curve spaced more than
/// [`COARSE_SPACING`](crate::extract::size::COARSE_SPACING) times `size`,
/// the size falls from its spacing to `size` at `gradation`). Along a
/// curve the spacing also grades from its ends' neighbours at `gradation`
/// and keeps to [`MAX_ARC_ANGLE`] of the local curvature.
#[derive(Clone, Debug, PartialEq)]
pub struct SizeSpec {
    pub size: f64,
    pub gradation: f64,
    pub points: Vec<PointSize>,
    /// Sizes by layer name.
    pub layers: BTreeMap<String, f64>,
}

impl SizeSpec {
    /// Size `h` everywhere, at the default [`GRADATION`].
    pub fn uniform(h: f64) -> SizeSpec {
        SizeSpec {
            size: h,
            gradation: GRADATION,
            points: Vec::new(),
            layers: BTreeMap::new(),
        }
    }

    fn check(&self) -> Result<(), CadError> {
        let bad = |h: f64| !(h.is_finite() && h > 0.0);
        if bad(self.size) {
            return Err(CadError::BadSize(self.size));
        }
        if bad(self.gradation) {
            return Err(CadError::BadGradation(self.gradation));
        }
        if let Some(p) = self
            .points
            .iter()
            .find(|p| bad(p.size) || !p.at.is_finite())
        {
            return Err(CadError::BadSize(p.size));
        }
        if let Some((_, &h)) = self.layers.iter().find(|(_, &h)| bad(h)) {
            return Err(CadError::BadSize(h));
        }
        Ok(())
    }

    /// The size field this asks the mesher to follow inside
    /// ([`crate::extract::size::SizeTarget`]); the sized layers reach it
    /// through the boundary nodes' spacing.
    pub fn target(&self) -> crate::extract::size::SizeTarget {
        crate::extract::size::SizeTarget {
            max: self.size,
            gradation: self.gradation,
            points: self.points.iter().map(|p| (p.at, p.size)).collect(),
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
    #[error("cannot read the geometry file: {0}")]
    Json(String),
    #[error("the drawing has no lines, arcs, circles, ellipses, splines or polylines")]
    Empty,
    #[error("the SPLINE (entity {index} on layer {layer:?}) has fit points only: save it with its control points (as a NURBS)")]
    FitPointsOnly { index: usize, layer: String },
    #[error("the spline (entity {index} on layer {layer:?}) cannot be evaluated: {why}")]
    BadSpline {
        index: usize,
        layer: String,
        why: String,
    },
    #[error(
        "the outline is open: the end at ({x}, {y}) meets no other curve's end (within {tol:.1e})"
    )]
    Gap { x: f64, y: f64, tol: f64 },
    #[error("the curve on layer {layer:?} at ({x}, {y}) is degenerate (no length)")]
    Degenerate { layer: String, x: f64, y: f64 },
    #[error("a size must be a positive number, not {0}")]
    BadSize(f64),
    #[error("the gradation must be a positive number, not {0}")]
    BadGradation(f64),
    #[error("a size of {size} cuts the drawing's curves (total length {length:.4e}) into at least {nodes:.3e} boundary nodes, more than {max}: take a larger size", max = crate::boundary_edit::MAX_RESAMPLED_NODES)]
    TooFine { size: f64, length: f64, nodes: f64 },
    #[error("a size of {size} asks for about {quads:.3e} quads inside the drawing (area {area:.4e}), more than {max}: take a larger size", max = crate::boundary_edit::MAX_RESAMPLED_QUADS)]
    TooManyQuads { size: f64, area: f64, quads: f64 },
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

/// [`read_dxf`] from the text of a DXF file (a drawing built into the
/// binary, say).
pub fn parse_dxf(text: &str) -> Result<Geometry, CadError> {
    let drawing =
        dxf::Drawing::load(&mut text.as_bytes()).map_err(|e| CadError::Dxf(e.to_string()))?;
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
            E::Spline(sp) => {
                if sp.control_points.is_empty() {
                    return Err(CadError::FitPointsOnly {
                        index: index + 1,
                        layer,
                    });
                }
                let degree = usize::try_from(sp.degree_of_curve).unwrap_or(0);
                let points = sp.control_points.iter().map(p2).collect();
                let weights = if sp.weight_values.iter().all(|&w| w == 1.0) {
                    Vec::new()
                } else {
                    sp.weight_values.clone()
                };
                let nurbs =
                    Nurbs::new(degree, sp.knot_values.clone(), points, weights).map_err(|why| {
                        CadError::BadSpline {
                            index: index + 1,
                            layer: layer.clone(),
                            why,
                        }
                    })?;
                push(Curve::Spline(Arc::new(nurbs)))
            }
            E::Ellipse(el) => {
                let major = Point::new(el.major_axis.x, el.major_axis.y);
                // The minor axis is the normal crossed with the major one:
                // a normal along -z runs the ellipse clockwise.
                let side = if el.normal.z < 0.0 { -1.0 } else { 1.0 };
                let minor = Point::new(-major.y, major.x) * (el.minor_axis_ratio * side);
                // DXF writers round the parameters: a sweep within
                // ANGLE_TOLERANCE of none or of a turn is a full turn.
                let sweep = (el.end_parameter - el.start_parameter).rem_euclid(2.0 * PI);
                let full = sweep <= ANGLE_TOLERANCE || sweep >= 2.0 * PI - ANGLE_TOLERANCE;
                let sweep = if full { 2.0 * PI } else { sweep };
                push(Curve::Ellipse {
                    centre: p2(&el.center),
                    major,
                    minor,
                    start: el.start_parameter,
                    sweep,
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
    /// The sizes the nodes were placed at.
    pub sizes: SizeSpec,
    /// The curve parameters of each segment's start, arc-length middle and
    /// end.
    params: Vec<[f64; 3]>,
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
    /// The point halfway along its curve (by arc length) between the nodes
    /// at `a` and `b`, when they are the ends of one of the graph's
    /// segments: where a second-order boundary edge puts its midside node.
    pub fn midside(&self, a: Point, b: Point) -> Option<Point> {
        let &s = self.by_ends.get(&(key(a), key(b)))?;
        Some(self.curves[self.curve_of[s]].at(self.params[s][1]))
    }

    /// The size field the mesher is to follow inside ([`SizeSpec::target`]).
    pub fn size_target(&self) -> crate::extract::size::SizeTarget {
        self.sizes.target()
    }
}

/// How a curve is cut: its samples, the cumulative density of nodes
/// (the integral of 1 / size over arc length) at each, and whether the
/// density is uniform on a curve whose parameter is proportional to arc
/// length (cut at equal parameter steps then, exactly).
struct Cut {
    samples: curve::Samples,
    density: Vec<f64>,
    uniform: bool,
    /// The fewest segments the curvature bound allows.
    fewest: usize,
}

impl Cut {
    /// The curve parameters of `n` segments' ends and middles.
    fn params(&self, n: usize) -> Vec<[f64; 3]> {
        let nf = n as f64;
        if self.uniform {
            return (0..n)
                .map(|k| {
                    let k = k as f64;
                    [k / nf, (k + 0.5) / nf, (k + 1.0) / nf]
                })
                .collect();
        }
        let total = self.density[self.density.len() - 1];
        let ends: Vec<f64> = (0..=n)
            .map(|k| match k {
                0 => 0.0,
                k if k == n => 1.0,
                k => self.samples.invert(&self.density, total * k as f64 / nf),
            })
            .collect();
        (0..n)
            .map(|k| {
                // The middle by arc length: half way between the ends'
                // lengths, read back from the samples.
                let s = |t: f64| {
                    // The samples are at equal parameter steps.
                    let last = self.samples.t.len() - 1;
                    let x = t * last as f64;
                    let j = (x.floor() as usize).min(last - 1);
                    let w = x - j as f64;
                    self.samples.s[j] * (1.0 - w) + self.samples.s[j + 1] * w
                };
                let mid = self
                    .samples
                    .invert(&self.samples.s, 0.5 * (s(ends[k]) + s(ends[k + 1])));
                [ends[k], mid.clamp(ends[k], ends[k + 1]), ends[k + 1]]
            })
            .collect()
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
        self.discretise_with(&SizeSpec::uniform(h))
    }

    /// Boundary nodes on every curve at the sizes `spec` asks, every face
    /// to mesh with an even node count.
    pub fn discretise_with(&self, spec: &SizeSpec) -> Result<Discretised, CadError> {
        spec.check()?;
        // A curve is cut at its layer's size if sized, else at the target
        // size, or finer (near local sizes, where it turns): its length
        // over that size is a floor on its node count, and a size far too
        // fine for the drawing is refused before it is cut.
        let (length, nodes) = self.curves.iter().fold((0.0, 0.0), |(l, n), c| {
            let h = spec.layers.get(&c.layer).copied().unwrap_or(spec.size);
            let len = c.curve.length();
            (l + len, n + len / h)
        });
        if nodes > crate::boundary_edit::MAX_RESAMPLED_NODES as f64 {
            return Err(CadError::TooFine {
                size: spec.size,
                length,
                nodes,
            });
        }
        let (ends, vertices) = join_ends(self)?;
        let samples: Vec<curve::Samples> = self.curves.iter().map(|c| c.curve.samples()).collect();
        // The points of each sized layer's curves, to measure the distance
        // to the layer by.
        let mut layer_points: BTreeMap<&str, Vec<Point>> = BTreeMap::new();
        for (c, s) in self.curves.iter().zip(&samples) {
            if spec.layers.contains_key(&c.layer) {
                layer_points.entry(&c.layer).or_default().extend(&s.p);
            }
        }
        let g = spec.gradation;
        // The size asked at `p` on a curve of layer `own`.
        let asked = |p: Point, own: &str| -> f64 {
            let mut h = spec.layers.get(own).copied().unwrap_or(spec.size);
            for q in &spec.points {
                h = h.min(q.size + g * (p - q.at).length());
            }
            for (layer, pts) in &layer_points {
                if *layer == own {
                    continue;
                }
                let d = pts
                    .iter()
                    .map(|&q| (p - q).length_squared())
                    .fold(f64::INFINITY, f64::min)
                    .sqrt();
                h = h.min(spec.layers[*layer] + g * d);
            }
            h
        };
        // The size along each curve before grading from its ends.
        let own: Vec<Vec<f64>> = self
            .curves
            .iter()
            .zip(&samples)
            .map(|(c, s)| {
                s.p.iter()
                    .zip(&s.bound)
                    .map(|(&p, &b)| asked(p, &c.layer).min(b))
                    .collect()
            })
            .collect();
        // The spacing at each vertex: the least of the sizes the curves
        // meeting there have at it, and of their lengths (a curve shorter
        // than its size is one segment).
        let mut at_vertex = vec![f64::INFINITY; vertices.len()];
        for (ci, e) in ends.iter().enumerate() {
            let s = &samples[ci];
            let len = s.s[s.s.len() - 1];
            let h = &own[ci];
            at_vertex[e[0]] = at_vertex[e[0]].min(h[0]).min(len);
            at_vertex[e[1]] = at_vertex[e[1]].min(h[h.len() - 1]).min(len);
        }
        let cuts: Vec<Cut> = samples
            .into_iter()
            .zip(&own)
            .zip(&ends)
            .zip(&self.curves)
            .map(|(((samples, own), e), c)| {
                let len = samples.s[samples.s.len() - 1];
                let closed = c.curve.is_closed() || e[0] == e[1];
                let size: Vec<f64> = samples
                    .s
                    .iter()
                    .zip(own)
                    .map(|(&s, &h)| {
                        if closed {
                            h
                        } else {
                            h.min(at_vertex[e[0]] + g * s)
                                .min(at_vertex[e[1]] + g * (len - s))
                        }
                    })
                    .collect();
                let integral = |f: &dyn Fn(usize) -> f64| {
                    let mut acc = vec![0.0; samples.s.len()];
                    for i in 1..acc.len() {
                        acc[i] = acc[i - 1]
                            + 0.5 * (f(i - 1) + f(i)) * (samples.s[i] - samples.s[i - 1]);
                    }
                    acc
                };
                let density = integral(&|i| 1.0 / size[i]);
                let curvature = integral(&|i| 1.0 / samples.bound[i]);
                let fewest = ((curvature[curvature.len() - 1] - 1e-9).ceil().max(1.0) as usize)
                    .max(if closed { 3 } else { 1 });
                let (lo, hi) = size.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &h| {
                    (lo.min(h), hi.max(h))
                });
                let uniform = matches!(c.curve, Curve::Line { .. } | Curve::Arc { .. })
                    && hi - lo <= 1e-12 * hi;
                let density = if uniform {
                    // Exactly length / size at the end.
                    let total = len / hi;
                    samples.t.iter().map(|t| t * total).collect()
                } else {
                    density
                };
                Cut {
                    samples,
                    density,
                    uniform,
                    fewest,
                }
            })
            .collect();
        let mut counts: Vec<usize> = cuts
            .iter()
            .map(|c| (c.density[c.density.len() - 1].round() as usize).max(c.fewest))
            .collect();
        let first = self.build(&ends, &vertices, &counts, &cuts, spec);
        // The quads inside at the target size, about: the meshed faces'
        // area over its square (local sizes only add). A size asking for
        // far more than a mesh can hold is refused before meshing.
        let cycles = first.graph.face_cycles()?;
        let area: f64 = cycles
            .iter()
            .filter(|f| f.meshed)
            .flat_map(|f| &f.loops)
            .map(|l| crate::geom::polygon_area(l.iter().map(|&i| first.graph.points[i])))
            .sum();
        let quads = area.abs() / (spec.size * spec.size);
        if quads > crate::boundary_edit::MAX_RESAMPLED_QUADS as f64 {
            return Err(CadError::TooManyQuads {
                size: spec.size,
                area: area.abs(),
                quads,
            });
        }
        let fixes = parity_fixes(&first, &cycles, self.curves.len());
        for &c in &fixes {
            counts[c] += 1;
        }
        let mut d = self.build(&ends, &vertices, &counts, &cuts, spec);
        d.parity_fixes = fixes;
        Ok(d)
    }

    /// The graph of the curves cut into `counts` segments each.
    fn build(
        &self,
        ends: &[[usize; 2]],
        vertices: &[Point],
        counts: &[usize],
        cuts: &[Cut],
        spec: &SizeSpec,
    ) -> Discretised {
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
            let cut = cuts[ci].params(n);
            let mut prev = e[0];
            for (k, t) in cut.into_iter().enumerate() {
                let id = if k + 1 == n {
                    e[1]
                } else {
                    g.points.push(c.curve.at(t[2]));
                    g.labels.push(g.points.len() as i64);
                    g.points.len() - 1
                };
                g.segments.push(Segment {
                    a: prev,
                    b: id,
                    marker,
                });
                curve_of.push(ci);
                params.push(t);
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
            sizes: spec.clone(),
            params,
            by_ends,
            curves: self.curves.iter().map(|c| c.curve.clone()).collect(),
        }
    }
}

/// The curves to give one segment more so that every face to mesh has an
/// even node count (see the module's documentation); `cycles` are the
/// faces of `d`'s graph.
fn parity_fixes(d: &Discretised, cycles: &[FaceCycle], n_curves: usize) -> Vec<usize> {
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
    fixes
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

//! The JSON geometry form: the curves of a drawing (lines, arcs, circles,
//! elliptical arcs, splines) on layers, with the target size and local
//! sizes to mesh it at. `docs/formats.md` ("A geometry file") documents it;
//! [`read_geometry_json`] is the one reader the command line and the editor
//! use.

use super::{arc_through, CadError, Curve, Geometry, LayerCurve, Nurbs, PointSize, SizeSpec};
use crate::geom::Point;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::sync::Arc;

/// A geometry file read: the curves and the sizes it asks for (each
/// optional; the command line's options take precedence).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CadDocument {
    pub geometry: Geometry,
    /// The target size.
    pub size: Option<f64>,
    /// The growth of sizes away from finer local sizes.
    pub gradation: Option<f64>,
    pub points: Vec<PointSize>,
    /// Sizes by layer.
    pub layers: BTreeMap<String, f64>,
}

impl CadDocument {
    /// The sizes to mesh at: `size` (else the file's), the file's
    /// gradation (else [`super::GRADATION`]) and local sizes, with `points`
    /// and `layers` added (a layer given twice takes the later size).
    /// `None` when neither gives a target size.
    pub fn spec(
        &self,
        size: Option<f64>,
        gradation: Option<f64>,
        points: &[PointSize],
        layers: &[(String, f64)],
    ) -> Option<SizeSpec> {
        let mut spec = SizeSpec::uniform(size.or(self.size)?);
        spec.gradation = gradation.or(self.gradation).unwrap_or(super::GRADATION);
        spec.points = self.points.clone();
        spec.points.extend_from_slice(points);
        spec.layers = self.layers.clone();
        spec.layers.extend(layers.iter().cloned());
        Some(spec)
    }
}

type Xy = [f64; 2];

fn point(p: Xy) -> Point {
    Point::new(p[0], p[1])
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Doc {
    #[serde(default)]
    size: Option<f64>,
    #[serde(default)]
    gradation: Option<f64>,
    curves: Vec<CurveDoc>,
    #[serde(default)]
    sizes: Vec<SizeDoc>,
}

/// The layer of a curve that names none (DXF's default layer).
const DEFAULT_LAYER: &str = "0";

fn default_layer() -> String {
    DEFAULT_LAYER.into()
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CurveDoc {
    #[serde(default = "default_layer")]
    layer: String,
    #[serde(default)]
    line: Option<[Xy; 2]>,
    #[serde(default)]
    arc: Option<ArcDoc>,
    #[serde(default)]
    circle: Option<CircleDoc>,
    #[serde(default)]
    ellipse: Option<EllipseDoc>,
    #[serde(default)]
    spline: Option<SplineDoc>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum ArcDoc {
    /// Counter-clockwise from `start` to `end`, in degrees.
    Centre {
        centre: Xy,
        radius: f64,
        start: f64,
        end: f64,
    },
    /// From the first point through the second to the third.
    Through { through: [Xy; 3] },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CircleDoc {
    centre: Xy,
    radius: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EllipseDoc {
    centre: Xy,
    /// The major semi-axis as a vector from the centre.
    major: Xy,
    /// Minor over major semi-axis.
    ratio: f64,
    /// Parameter angles in degrees, counter-clockwise from the major axis
    /// (default: the whole ellipse).
    #[serde(default)]
    start: Option<f64>,
    #[serde(default)]
    end: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SplineDoc {
    degree: usize,
    points: Vec<Xy>,
    /// Default: clamped and uniform.
    #[serde(default)]
    knots: Option<Vec<f64>>,
    /// Default: all 1.
    #[serde(default)]
    weights: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum SizeDoc {
    At { at: Xy, size: f64 },
    Layer { layer: String, size: f64 },
}

/// The clamped uniform knots of `n` control points of degree `p`.
fn clamped_knots(n: usize, p: usize) -> Vec<f64> {
    let inner = n.saturating_sub(p);
    (0..n + p + 1)
        .map(|i| (i.saturating_sub(p).min(inner)) as f64 / inner.max(1) as f64)
        .collect()
}

/// Counter-clockwise sweep in radians from `start` to `end` degrees (a
/// full turn when they are equal).
fn ccw_sweep(start: f64, end: f64) -> f64 {
    let s = (end - start).rem_euclid(360.0);
    if s == 0.0 {
        2.0 * PI
    } else {
        s.to_radians()
    }
}

/// Reads a JSON geometry document.
pub fn parse_geometry_json(text: &str) -> Result<CadDocument, CadError> {
    let doc: Doc = serde_json::from_str(text).map_err(|e| CadError::Json(e.to_string()))?;
    let mut out = CadDocument {
        size: doc.size,
        gradation: doc.gradation,
        ..CadDocument::default()
    };
    for (i, c) in doc.curves.into_iter().enumerate() {
        let index = i + 1;
        let bad = |why: String| CadError::Json(format!("curve {index}: {why}"));
        let given = [
            c.line.is_some(),
            c.arc.is_some(),
            c.circle.is_some(),
            c.ellipse.is_some(),
            c.spline.is_some(),
        ]
        .iter()
        .filter(|&&b| b)
        .count();
        if given != 1 {
            return Err(bad(
                "give exactly one of line, arc, circle, ellipse, spline".into(),
            ));
        }
        let curve = if let Some([a, b]) = c.line {
            Curve::Line {
                a: point(a),
                b: point(b),
            }
        } else if let Some(arc) = c.arc {
            match arc {
                ArcDoc::Centre {
                    centre,
                    radius,
                    start,
                    end,
                } => Curve::Arc {
                    centre: point(centre),
                    radius,
                    start: start.to_radians(),
                    sweep: ccw_sweep(start, end),
                },
                ArcDoc::Through { through: [a, m, b] } => arc_through(point(a), point(m), point(b))
                    .ok_or_else(|| bad("the arc's three points are on one line".into()))?,
            }
        } else if let Some(ci) = c.circle {
            Curve::Arc {
                centre: point(ci.centre),
                radius: ci.radius,
                start: 0.0,
                sweep: 2.0 * PI,
            }
        } else if let Some(e) = c.ellipse {
            let major = point(e.major);
            let start = e.start.unwrap_or(0.0);
            Curve::Ellipse {
                centre: point(e.centre),
                major,
                minor: Point::new(-major.y, major.x) * e.ratio,
                start: start.to_radians(),
                sweep: ccw_sweep(start, e.end.unwrap_or(start)),
            }
        } else if let Some(s) = c.spline {
            let n = s.points.len();
            let knots = s.knots.unwrap_or_else(|| clamped_knots(n, s.degree));
            let points = s.points.into_iter().map(point).collect();
            Curve::Spline(Arc::new(
                Nurbs::new(s.degree, knots, points, s.weights).map_err(bad)?,
            ))
        } else {
            unreachable!("one curve kind is given")
        };
        let finite = match &curve {
            Curve::Line { a, b } => a.is_finite() && b.is_finite(),
            Curve::Arc { centre, radius, .. } => {
                centre.is_finite() && radius.is_finite() && *radius > 0.0
            }
            Curve::Ellipse {
                centre,
                major,
                minor,
                ..
            } => centre.is_finite() && major.is_finite() && minor.is_finite(),
            Curve::Spline(_) => true,
        };
        if !finite {
            return Err(bad(
                "its numbers must be finite (and a radius positive)".into()
            ));
        }
        out.geometry.curves.push(LayerCurve {
            curve,
            layer: c.layer,
        });
    }
    if out.geometry.curves.is_empty() {
        return Err(CadError::Empty);
    }
    for s in doc.sizes {
        match s {
            SizeDoc::At { at, size } => out.points.push(PointSize {
                at: point(at),
                size,
            }),
            SizeDoc::Layer { layer, size } => {
                out.layers.insert(layer, size);
            }
        }
    }
    Ok(out)
}

/// Reads a JSON geometry file ([`parse_geometry_json`]).
pub fn read_geometry_json(path: &std::path::Path) -> Result<CadDocument, CadError> {
    let bytes = std::fs::read(path).map_err(|e| CadError::Json(e.to_string()))?;
    let text = crate::io::decode_text(&bytes);
    parse_geometry_json(&crate::io::normalise_text(&text))
}

/// True for a `.json` file holding a geometry document
/// ([`is_geometry_json`]).
pub fn is_geometry_file(path: &std::path::Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        && std::fs::read(path).is_ok_and(|b| {
            is_geometry_json(&crate::io::normalise_text(&crate::io::decode_text(&b)))
        })
}

/// True when `text` is a JSON object with a `curves` member: a geometry
/// file rather than a boundary or regions file.
pub fn is_geometry_json(text: &str) -> bool {
    serde_json::from_str::<serde_json::Value>(text)
        .is_ok_and(|v| v.get("curves").is_some_and(|c| c.is_array()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamped_knots_repeat_the_ends() {
        assert_eq!(
            clamped_knots(4, 3),
            [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]
        );
        assert_eq!(
            clamped_knots(5, 2),
            [0.0, 0.0, 0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0, 1.0, 1.0]
        );
    }
}

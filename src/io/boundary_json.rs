//! The project's own boundary document: JSON with the loops as lists of
//! `[x, y]` points, outer loop first or not (orientation and order are
//! normalised on reading).
//!
//! ```json
//! { "format": "quadex-boundary", "version": 1, "name": "square",
//!   "loops": [[[0,0],[1,0],[1,1],[0,1]]] }
//! ```

use super::ReadError;
use crate::boundary::Boundary;
use crate::geom::Point;
use serde::{Deserialize, Serialize};

/// The serialised form of a boundary.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BoundaryDoc {
    #[serde(default = "default_format")]
    pub format: String,
    #[serde(default = "default_version")]
    pub version: u32,
    #[serde(default)]
    pub name: String,
    pub loops: Vec<Vec<[f64; 2]>>,
}

fn default_format() -> String {
    "quadex-boundary".into()
}
fn default_version() -> u32 {
    1
}

impl BoundaryDoc {
    /// The document of a boundary (loops in the boundary's order and orientation).
    pub fn from_boundary(b: &Boundary, name: &str) -> BoundaryDoc {
        BoundaryDoc {
            format: default_format(),
            version: 1,
            name: name.to_string(),
            loops: b
                .loops
                .iter()
                .map(|l| l.iter().map(|&i| b.points[i].to_array()).collect())
                .collect(),
        }
    }

    /// Validates the document into a boundary.
    pub fn to_boundary(&self) -> Result<Boundary, ReadError> {
        let mut points = Vec::new();
        let mut loops = Vec::new();
        for l in &self.loops {
            let start = points.len();
            points.extend(l.iter().map(|&[x, y]| Point::new(x, y)));
            loops.push((start..points.len()).collect());
        }
        Ok(Boundary::new(points, loops, None)?)
    }
}

/// Parses a boundary document.
pub fn parse(text: &str) -> Result<Boundary, ReadError> {
    let text = super::normalise_text(text);
    if text.trim().is_empty() {
        return Err(ReadError::Empty);
    }
    let doc: BoundaryDoc = serde_json::from_str(&text)
        .map_err(|e| ReadError::Json(super::quote_long(&e.to_string())))?;
    doc.to_boundary()
}

/// The loops of a boundary document as points, not validated as a
/// boundary (see [`super::read_boundary_loops`]).
pub fn parse_loops(text: &str) -> Result<Vec<Vec<Point>>, ReadError> {
    let text = super::normalise_text(text);
    if text.trim().is_empty() {
        return Err(ReadError::Empty);
    }
    let doc: BoundaryDoc = serde_json::from_str(&text)
        .map_err(|e| ReadError::Json(super::quote_long(&e.to_string())))?;
    Ok(doc
        .loops
        .iter()
        .map(|l| l.iter().map(|&[x, y]| Point::new(x, y)).collect())
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip() {
        let t = r#"{"loops": [[[0,0],[0,1],[1,1],[1,0]]]}"#;
        let b = parse(t).unwrap();
        let doc = BoundaryDoc::from_boundary(&b, "sq");
        let b2 = doc.to_boundary().unwrap();
        assert_eq!(b.points.len(), b2.points.len());
        assert!((b2.area() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bom_and_line_ends() {
        let t = "{\"loops\": [[[0,0],[1000,0],\r\n[1000,1],\r[0,1]]]}";
        let b = parse(&format!("\u{feff}{t}")).unwrap();
        assert_eq!(b.node_count(), 4);
        assert!((b.area() - 1000.0).abs() < 1e-9);
    }
}

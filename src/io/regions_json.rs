//! The project's document of several regions and named boundary groups:
//! a planar straight-line graph in JSON ([`Pslg`]).
//!
//! ```json
//! { "format": "quadex-regions", "version": 1,
//!   "nodes": [[0,0],[0.5,0],[1,0],[1,1],[0.5,1],[0,1]],
//!   "segments": [[0,1],[1,2],[2,3],[3,4],[4,5],[5,0],[1,4]],
//!   "groups": [{"name": "left", "tag": 1, "segments": [5]},
//!              {"name": "right", "segments": [2]}],
//!   "regions": [{"name": "copper", "tag": 1, "point": [0.25, 0.5]},
//!               {"name": "steel", "point": [0.75, 0.5]}],
//!   "holes": [] }
//! ```
//!
//! Nodes and segments are numbered from 0. A group names segments (each
//! in one group at most); a region names the face that holds its point.
//! A `tag` is the physical tag written for it; without one, a group or
//! region takes the smallest whole number from 1 that no other one has.
//! Two regions may share a tag (and then must share the name): their
//! faces form one region.

use super::ReadError;
use crate::geom::Point;
use crate::pslg::{Pslg, RegionPoint, Segment};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

/// A named boundary group of the document.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct GroupDoc {
    pub name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tag: Option<i64>,
    pub segments: Vec<usize>,
}

/// A named region of the document.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct RegionDoc {
    pub name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tag: Option<i64>,
    pub point: [f64; 2],
}

/// The serialised form of a graph of regions.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct RegionsDoc {
    pub format: String,
    #[serde(default = "one")]
    pub version: u32,
    pub nodes: Vec<[f64; 2]>,
    pub segments: Vec<[usize; 2]>,
    #[serde(default)]
    pub groups: Vec<GroupDoc>,
    #[serde(default)]
    pub regions: Vec<RegionDoc>,
    #[serde(default)]
    pub holes: Vec<[f64; 2]>,
}

fn one() -> u32 {
    1
}

/// The `format` value of a regions document.
pub const FORMAT: &str = "quadex-regions";

fn bad(message: String) -> ReadError {
    ReadError::Json(message)
}

/// Tags for items with optional tags: given ones kept, the others the
/// smallest free whole numbers from 1, in order.
fn assign(tags: &[Option<i64>]) -> Vec<i64> {
    let mut taken: BTreeSet<i64> = tags.iter().flatten().copied().collect();
    let mut next = 1;
    tags.iter()
        .map(|t| {
            t.unwrap_or_else(|| {
                while taken.contains(&next) {
                    next += 1;
                }
                taken.insert(next);
                next
            })
        })
        .collect()
}

impl RegionsDoc {
    /// The graph of the document, its references checked.
    pub fn to_pslg(&self) -> Result<Pslg, ReadError> {
        let n = self.nodes.len();
        let mut markers = vec![0i64; self.segments.len()];
        let mut g = Pslg {
            points: self.nodes.iter().map(|&[x, y]| Point::new(x, y)).collect(),
            labels: (0..n as i64).collect(),
            ..Pslg::default()
        };
        if let Some(i) = g.points.iter().position(|p| !p.is_finite()) {
            return Err(crate::boundary::BoundaryError::NonFinite { node: i as i64 }.into());
        }
        let tags = assign(&self.groups.iter().map(|x| x.tag).collect::<Vec<_>>());
        for (grp, &tag) in self.groups.iter().zip(&tags) {
            if tag < 1 {
                return Err(bad(format!(
                    "group {:?}: tag {tag}: tags are whole numbers from 1",
                    grp.name
                )));
            }
            if let Some(other) = g.group_names.insert(tag, grp.name.clone()) {
                return Err(bad(format!(
                    "groups {other:?} and {:?} have the same tag {tag}",
                    grp.name
                )));
            }
            for &s in &grp.segments {
                let m = markers.get_mut(s).ok_or_else(|| {
                    bad(format!(
                        "group {:?} names segment {s}, which does not exist",
                        grp.name
                    ))
                })?;
                if *m != 0 {
                    return Err(bad(format!(
                        "segment {s} is in two groups ({:?} and {:?})",
                        g.group_names[m], grp.name
                    )));
                }
                *m = tag;
            }
        }
        for (k, (&[a, b], &marker)) in self.segments.iter().zip(&markers).enumerate() {
            if a >= n || b >= n {
                return Err(bad(format!(
                    "segment {k} refers to node {}, which does not exist",
                    a.max(b)
                )));
            }
            if a == b {
                return Err(bad(format!("segment {k} joins node {a} to itself")));
            }
            g.segments.push(Segment { a, b, marker });
        }
        let tags = assign(&self.regions.iter().map(|x| x.tag).collect::<Vec<_>>());
        for (r, &tag) in self.regions.iter().zip(&tags) {
            if tag < 1 {
                return Err(bad(format!(
                    "region {:?}: tag {tag}: tags are whole numbers from 1",
                    r.name
                )));
            }
            match g.region_names.get(&tag) {
                Some(other) if other != &r.name => {
                    return Err(bad(format!(
                        "regions {other:?} and {:?} have the same tag {tag}",
                        r.name
                    )))
                }
                _ => {
                    g.region_names.insert(tag, r.name.clone());
                }
            }
            let at = Point::new(r.point[0], r.point[1]);
            if !at.is_finite() {
                return Err(bad(format!("region {:?}: its point is not finite", r.name)));
            }
            g.regions.push(RegionPoint {
                at,
                attribute: tag,
                max_area: None,
            });
        }
        g.holes = self.holes.iter().map(|&[x, y]| Point::new(x, y)).collect();
        Ok(g)
    }

    /// The document of a graph (groups and regions by tag, named by the
    /// graph's names).
    pub fn from_pslg(g: &Pslg) -> RegionsDoc {
        let mut groups: BTreeMap<i64, Vec<usize>> = BTreeMap::new();
        for (k, s) in g.segments.iter().enumerate() {
            if s.marker != 0 {
                groups.entry(s.marker).or_default().push(k);
            }
        }
        RegionsDoc {
            format: FORMAT.into(),
            version: 1,
            nodes: g.points.iter().map(|p| p.to_array()).collect(),
            segments: g.segments.iter().map(|s| [s.a, s.b]).collect(),
            groups: groups
                .into_iter()
                .map(|(tag, segments)| GroupDoc {
                    name: g.group_name(tag),
                    tag: Some(tag),
                    segments,
                })
                .collect(),
            regions: g
                .regions
                .iter()
                .map(|r| RegionDoc {
                    name: g.region_name(r.attribute),
                    tag: Some(r.attribute),
                    point: r.at.to_array(),
                })
                .collect(),
            holes: g.holes.iter().map(|p| p.to_array()).collect(),
        }
    }
}

/// True when a JSON text is a regions document (its `format`).
pub fn is_regions(text: &str) -> bool {
    #[derive(Deserialize)]
    struct Head {
        #[serde(default)]
        format: String,
    }
    serde_json::from_str::<Head>(text).is_ok_and(|h| h.format == FORMAT)
}

/// Parses a regions document.
pub fn parse(text: &str) -> Result<Pslg, ReadError> {
    let text = super::normalise_text(text);
    if text.trim().is_empty() {
        return Err(ReadError::Empty);
    }
    let doc: RegionsDoc = serde_json::from_str(&text)
        .map_err(|e| ReadError::Json(super::quote_long(&e.to_string())))?;
    doc.to_pslg()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPLIT: &str = r#"{ "format": "quadex-regions", "version": 1,
      "nodes": [[0,0],[0.5,0],[1,0],[1,1],[0.5,1],[0,1]],
      "segments": [[0,1],[1,2],[2,3],[3,4],[4,5],[5,0],[1,4]],
      "groups": [{"name": "left", "tag": 1, "segments": [5]},
                 {"name": "right", "segments": [2]}],
      "regions": [{"name": "copper", "tag": 1, "point": [0.25, 0.5]},
                  {"name": "steel", "point": [0.75, 0.5]}] }"#;

    #[test]
    fn a_document_reads_and_round_trips() {
        assert!(is_regions(SPLIT));
        let g = parse(SPLIT).unwrap();
        assert_eq!(g.group_name(1), "left");
        assert_eq!(g.group_name(2), "right");
        assert_eq!(g.region_name(2), "steel");
        assert_eq!(g.segments[2].marker, 2);
        assert_eq!(g.faces().unwrap().len(), 2);
        let again = RegionsDoc::from_pslg(&g).to_pslg().unwrap();
        assert_eq!(again.segments, g.segments);
        assert_eq!(again.regions, g.regions);
        assert_eq!(again.group_names, g.group_names);
    }

    #[test]
    fn bad_references_are_refused() {
        let e = parse(&SPLIT.replace("\"segments\": [5]", "\"segments\": [9]")).unwrap_err();
        assert!(e.to_string().contains("segment 9"), "{e}");
        let e = parse(&SPLIT.replace("\"segments\": [2]", "\"segments\": [5]")).unwrap_err();
        assert!(e.to_string().contains("two groups"), "{e}");
    }
}

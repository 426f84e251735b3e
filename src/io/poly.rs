//! Triangle `.poly` boundaries: nodes (0- or 1-based, any numbering),
//! optional attributes and markers, segments in any order and direction
//! with optional markers, hole points, the optional regional attributes
//! section (`r x y attribute maxarea`), `#` comments. For one domain the
//! segments are chained into loops ([`parse_poly`]); as a planar
//! straight-line graph of several regions and marked segments they are
//! kept as they are ([`parse_pslg`]).

use super::ReadError;
use crate::boundary::{loops_from_segments, Boundary, BoundaryError};
use crate::geom::Point;
use crate::pslg::{Pslg, RegionPoint, Segment};
use std::collections::BTreeMap;

struct Lines<'a> {
    inner: std::iter::Enumerate<std::str::Lines<'a>>,
    /// Lines in the file.
    total: usize,
}

impl<'a> Lines<'a> {
    /// Refuses a count announced on line `line` that the lines after it
    /// cannot hold (each item takes a line): a count never makes the
    /// reader reserve memory for data that is not there.
    fn room_for(&self, line: usize, count: u64, what: &'static str) -> Result<usize, ReadError> {
        let room = self.total.saturating_sub(line);
        if count > room as u64 {
            return Err(ReadError::TooMany {
                line,
                count,
                what,
                room,
            });
        }
        Ok(count as usize)
    }

    /// The next line with content, as (1-based line number, fields).
    fn next_fields(&mut self, expected: &str) -> Result<(usize, Vec<&'a str>), ReadError> {
        for (i, raw) in self.inner.by_ref() {
            let s = raw.split('#').next().unwrap_or("").trim();
            if !s.is_empty() {
                return Ok((i + 1, s.split_whitespace().collect()));
            }
        }
        Err(ReadError::Truncated {
            expected: expected.to_string(),
        })
    }
}

fn num<T: std::str::FromStr>(
    line: usize,
    fields: &[&str],
    k: usize,
    what: &str,
) -> Result<T, ReadError> {
    fields
        .get(k)
        .ok_or_else(|| ReadError::Syntax {
            line,
            message: format!("missing {what}"),
        })?
        .parse()
        .map_err(|_| ReadError::Syntax {
            line,
            message: format!(
                "`{}` is not a valid {what}",
                super::quote(fields.get(k).copied().unwrap_or(""))
            ),
        })
}

/// Parses the text of a `.poly` file into a validated boundary.
pub fn parse_poly(text: &str) -> Result<Boundary, ReadError> {
    let (points, loops, labels) = parse_poly_loops(text)?;
    Ok(Boundary::new(points, loops, Some(labels))?)
}

/// The nodes (with their labels) and loops of a `.poly` file, the
/// segments chained into loops but the loops not validated as a boundary:
/// what the editor opens as a draft to fix when [`parse_poly`] refuses
/// the boundary.
#[allow(clippy::type_complexity)]
pub fn parse_poly_loops(text: &str) -> Result<(Vec<Point>, Vec<Vec<usize>>, Vec<i64>), ReadError> {
    let g = parse_graph(text)?;
    let segs: Vec<(usize, usize)> = g.segments.iter().map(|s| (s.a, s.b)).collect();
    let loops = loops_from_segments(g.points.len(), &segs, &g.labels)?;
    Ok((g.points, loops, g.labels))
}

/// A `.poly` file as a planar straight-line graph: its nodes used by
/// segments, its segments with their markers, hole points and region
/// points. The graph is not yet checked ([`Pslg::faces`] does).
pub fn parse_pslg(text: &str) -> Result<Pslg, ReadError> {
    parse_graph(text)
}

/// Reads every section of a `.poly` file; nodes no segment uses are
/// dropped.
fn parse_graph(text: &str) -> Result<Pslg, ReadError> {
    let text = super::normalise_text(text);
    if text.trim().is_empty() {
        return Err(ReadError::Empty);
    }
    let mut lines = Lines {
        inner: text.lines().enumerate(),
        total: text.lines().count(),
    };
    let (ln, head) = lines.next_fields("the node count")?;
    let n: u64 = num(ln, &head, 0, "node count")?;
    let dim: usize = if head.len() > 1 {
        num(ln, &head, 1, "dimension")?
    } else {
        2
    };
    if dim != 2 {
        return Err(ReadError::Syntax {
            line: ln,
            message: format!("dimension {dim}; only 2 is supported"),
        });
    }
    if n == 0 {
        return Err(BoundaryError::Empty.into());
    }
    let n = lines.room_for(ln, n, "nodes")?;
    let mut points = Vec::with_capacity(n);
    let mut labels = Vec::with_capacity(n);
    let mut index: BTreeMap<i64, usize> = BTreeMap::new();
    for k in 0..n {
        let (ln, f) = lines.next_fields(&format!("node {} of {n}", k + 1))?;
        let id: i64 = num(ln, &f, 0, "node number")?;
        let x: f64 = num(ln, &f, 1, "x coordinate")?;
        let y: f64 = num(ln, &f, 2, "y coordinate")?;
        if index.insert(id, k).is_some() {
            return Err(ReadError::Syntax {
                line: ln,
                message: format!("node {id} is defined twice"),
            });
        }
        points.push(Point::new(x, y));
        labels.push(id);
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(BoundaryError::NonFinite { node: labels[i] }.into());
    }
    let (ln, f) = lines.next_fields("the segment count")?;
    let ns: u64 = num(ln, &f, 0, "segment count")?;
    let with_markers = f.len() > 1 && num::<u64>(ln, &f, 1, "marker flag")? != 0;
    let ns = lines.room_for(ln, ns, "segments")?;
    let mut segs = Vec::with_capacity(ns);
    for k in 0..ns {
        let (ln, f) = lines.next_fields(&format!("segment {} of {ns}", k + 1))?;
        let mut ends = [0usize; 2];
        for (j, e) in ends.iter_mut().enumerate() {
            let id: i64 = num(ln, &f, 1 + j, "node number")?;
            *e = *index.get(&id).ok_or(BoundaryError::BadSegmentIndex {
                segment: k + 1,
                node: id,
            })?;
        }
        if ends[0] == ends[1] {
            return Err(ReadError::Syntax {
                line: ln,
                message: "a segment joins a node to itself".into(),
            });
        }
        let marker: i64 = if with_markers && f.len() > 3 {
            num(ln, &f, 3, "segment marker")?
        } else {
            0
        };
        segs.push(Segment {
            a: ends[0],
            b: ends[1],
            marker,
        });
    }
    // Hole points are optional; when present they must be well formed.
    let mut holes = Vec::new();
    let mut regions = Vec::new();
    if let Ok((ln, f)) = lines.next_fields("") {
        let nh: u64 = num(ln, &f, 0, "hole count")?;
        let nh = lines.room_for(ln, nh, "hole points")?;
        for k in 0..nh {
            let (ln, f) = lines.next_fields(&format!("hole point {} of {nh}", k + 1))?;
            let x: f64 = num(ln, &f, 1, "hole x coordinate")?;
            let y: f64 = num(ln, &f, 2, "hole y coordinate")?;
            if !(x.is_finite() && y.is_finite()) {
                return Err(ReadError::Syntax {
                    line: ln,
                    message: "non-finite hole point".into(),
                });
            }
            holes.push(Point::new(x, y));
        }
        // The regional attributes section is optional too.
        if let Ok((ln, f)) = lines.next_fields("") {
            let nr: u64 = num(ln, &f, 0, "region count")?;
            let nr = lines.room_for(ln, nr, "region points")?;
            for k in 0..nr {
                let (ln, f) = lines.next_fields(&format!("region point {} of {nr}", k + 1))?;
                let x: f64 = num(ln, &f, 1, "region x coordinate")?;
                let y: f64 = num(ln, &f, 2, "region y coordinate")?;
                let a: f64 = num(ln, &f, 3, "regional attribute")?;
                if !(x.is_finite() && y.is_finite()) {
                    return Err(ReadError::Syntax {
                        line: ln,
                        message: "non-finite region point".into(),
                    });
                }
                if a.fract() != 0.0 || !(1.0..=2e9).contains(&a) {
                    return Err(ReadError::Syntax {
                        line: ln,
                        message: format!(
                            "regional attribute {a}: attributes are whole numbers from 1, the regions' physical tags"
                        ),
                    });
                }
                let max_area = match f.get(4) {
                    Some(_) => Some(num::<f64>(ln, &f, 4, "maximum area")?),
                    None => None,
                };
                regions.push(RegionPoint {
                    at: Point::new(x, y),
                    attribute: a as i64,
                    max_area,
                });
            }
        }
    }
    // Nodes used by no segment are not part of the boundary.
    let mut used = vec![false; n];
    for s in &segs {
        used[s.a] = true;
        used[s.b] = true;
    }
    let mut remap = vec![usize::MAX; n];
    let (mut pts2, mut lab2) = (Vec::new(), Vec::new());
    for i in 0..n {
        if used[i] {
            remap[i] = pts2.len();
            pts2.push(points[i]);
            lab2.push(labels[i]);
        }
    }
    if segs.is_empty() {
        return Err(BoundaryError::TooFewNodes { count: 0 }.into());
    }
    for s in &mut segs {
        s.a = remap[s.a];
        s.b = remap[s.b];
    }
    Ok(Pslg {
        points: pts2,
        labels: lab2,
        segments: segs,
        holes,
        regions,
        ..Pslg::default()
    })
}

/// Renders a boundary as a `.poly` file (1-based, loops in order).
pub fn write_poly(b: &Boundary) -> String {
    let mut out = String::new();
    let n = b.node_count();
    let mut number = vec![0usize; b.points.len()];
    let mut k = 0;
    out.push_str(&format!("{n} 2 0 0\n"));
    for l in &b.loops {
        for &i in l {
            k += 1;
            number[i] = k;
            out.push_str(&format!("{k} "));
            super::fmt_f64(&mut out, b.points[i].x);
            out.push(' ');
            super::fmt_f64(&mut out, b.points[i].y);
            out.push('\n');
        }
    }
    out.push_str(&format!("{n} 0\n"));
    let mut s = 0;
    for (a, c) in b.segments() {
        s += 1;
        out.push_str(&format!("{s} {} {}\n", number[a], number[c]));
    }
    out.push_str("0\n");
    out
}

/// Renders a planar straight-line graph as a `.poly` file (1-based):
/// nodes, segments with their markers, hole points and the regional
/// attributes section (maximum areas kept). [`parse_pslg`] reads it back
/// to the same graph; the names of regions and groups have no place in
/// the format (a regions document, `.json`, keeps them).
pub fn write_pslg(g: &Pslg) -> String {
    let mut out = String::new();
    let xy = |out: &mut String, p: Point| {
        super::fmt_f64(out, p.x);
        out.push(' ');
        super::fmt_f64(out, p.y);
    };
    out.push_str(&format!("{} 2 0 0\n", g.points.len()));
    for (k, &p) in g.points.iter().enumerate() {
        out.push_str(&format!("{} ", k + 1));
        xy(&mut out, p);
        out.push('\n');
    }
    out.push_str(&format!("{} 1\n", g.segments.len()));
    for (k, s) in g.segments.iter().enumerate() {
        out.push_str(&format!("{} {} {} {}\n", k + 1, s.a + 1, s.b + 1, s.marker));
    }
    out.push_str(&format!("{}\n", g.holes.len()));
    for (k, &p) in g.holes.iter().enumerate() {
        out.push_str(&format!("{} ", k + 1));
        xy(&mut out, p);
        out.push('\n');
    }
    out.push_str(&format!("{}\n", g.regions.len()));
    for (k, r) in g.regions.iter().enumerate() {
        out.push_str(&format!("{} ", k + 1));
        xy(&mut out, r.at);
        out.push_str(&format!(" {}", r.attribute));
        if let Some(a) = r.max_area {
            out.push(' ');
            super::fmt_f64(&mut out, a);
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_based_with_attributes_and_markers() {
        let t = "# c\n4 2 1 1\n0 0 0 7 1\n1 1 0 7 1 # x\n2 1 1 7 1\n3 0 1 7 1\n4 1\n0 2 3 1\n1 0 1 1\n2 1 2 1\n3 3 0 1\n0\n";
        let b = parse_poly(t).unwrap();
        assert_eq!(b.loops.len(), 1);
        assert_eq!(b.node_count(), 4);
        assert!((b.area() - 1.0).abs() < 1e-12);
        assert_eq!(b.labels, vec![0, 1, 2, 3]);
    }

    #[test]
    fn round_trip() {
        let t = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n";
        let b = parse_poly(t).unwrap();
        let b2 = parse_poly(&write_poly(&b)).unwrap();
        assert_eq!(b.points, b2.points);
        assert_eq!(b.loops, b2.loops);
    }

    #[test]
    fn counts_beyond_the_file_are_refused_before_reading() {
        for t in [
            "99999999999 2 0 0\n1 0 0\n",
            "18446744073709551615 2 0 0\n1 0 0\n",
            "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n18446744073709551615 0\n1 1 2\n",
            "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4294967296 0\n1 1 2\n",
        ] {
            let e = parse_poly(t).unwrap_err();
            assert!(matches!(e, ReadError::TooMany { .. }), "{e:?}");
        }
        assert!(matches!(
            parse_poly("18446744073709551616 2 0 0\n"),
            Err(ReadError::Syntax { line: 1, .. })
        ));
    }

    #[test]
    fn bom_and_any_line_ends_are_read() {
        let t = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n";
        let plain = parse_poly(t).unwrap();
        for v in [
            format!("\u{feff}{t}"),
            t.replace('\n', "\r\n"),
            t.replace('\n', "\r"),
            format!("\u{feff}{}", t.replace('\n', "\r")),
        ] {
            assert_eq!(parse_poly(&v).unwrap(), plain);
        }
        // Old Mac line ends count as lines in messages.
        let e = parse_poly("4 2 0 0\r1 0 0\r2 x 0\r3 1 1\r4 0 1\r").unwrap_err();
        assert!(matches!(e, ReadError::Syntax { line: 3, .. }), "{e:?}");
    }

    #[test]
    fn control_bytes_are_not_echoed() {
        let e = parse_poly("4 2 0 0\n1 0 0\n2 1 0.\u{1c}5\n3 1 1\n4 0 1\n")
            .unwrap_err()
            .to_string();
        assert!(!e.chars().any(char::is_control), "{e:?}");
        assert!(e.contains("\\u{1c}"), "{e}");
    }

    #[test]
    fn truncated_and_garbage() {
        assert!(matches!(
            parse_poly("8 2 0 0\n1 0 0\n"),
            Err(ReadError::TooMany { line: 1, .. })
        ));
        assert!(matches!(
            parse_poly("4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n"),
            Err(ReadError::Truncated { .. })
        ));
        assert!(matches!(
            parse_poly("hello world"),
            Err(ReadError::Syntax { line: 1, .. })
        ));
        assert!(matches!(parse_poly("  \n"), Err(ReadError::Empty)));
    }

    #[test]
    fn a_graph_round_trips_through_write_pslg() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/data/regions/machine.poly"
        ))
        .unwrap();
        let g = parse_pslg(&text).unwrap();
        assert!(g.has_groups());
        let again = parse_pslg(&write_pslg(&g)).unwrap();
        assert_eq!(again.points, g.points);
        assert_eq!(again.segments, g.segments);
        assert_eq!(again.holes, g.holes);
        assert_eq!(again.regions, g.regions);
    }
}

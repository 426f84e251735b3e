//! Gmsh MSH ASCII: writers for 4.1 (with `$Entities` and physical groups:
//! each boundary loop a physical curve, the domain a physical surface) and
//! 2.2, and a reader for quad meshes in either version.

use super::check::{self, MeshCheckError};
use super::{fmt_f64, ReadError};
use crate::geom::{reflex_corner, Point};
use crate::mesh::{boundary_loops, InvariantError, QuadMesh};
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// Physical names: loop 0 is "outer", others "hole_k"; the surface "domain".
pub(crate) fn loop_name(k: usize) -> String {
    if k == 0 {
        "outer".into()
    } else {
        format!("hole_{k}")
    }
}

const SURFACE_TAG: usize = 100;

/// Gmsh element types: the quads written and read (4-node; 9- and 8-node
/// at second order), the lines of the groups (2- and 3-node) and points.
pub(crate) const QUAD4: u32 = 3;
pub(crate) const QUAD9: u32 = 10;
pub(crate) const QUAD8: u32 = 16;
pub(crate) const LINE2: u32 = 1;
pub(crate) const LINE3: u32 = 8;
pub(crate) const POINT: u32 = 15;

fn physical_names(out: &mut String, mesh: &QuadMesh) {
    out.push_str("$PhysicalNames\n");
    let _ = writeln!(out, "{}", mesh.loops.len() + 1);
    for k in 0..mesh.loops.len() {
        let _ = writeln!(out, "1 {} \"{}\"", k + 1, loop_name(k));
    }
    let _ = writeln!(out, "2 {SURFACE_TAG} \"domain\"");
    out.push_str("$EndPhysicalNames\n");
}

pub(super) fn xyz(out: &mut String, p: Point) {
    fmt_f64(out, p.x);
    out.push(' ');
    fmt_f64(out, p.y);
    out.push_str(" 0");
}

/// MSH 4.1 ASCII.
pub fn write_msh41(mesh: &QuadMesh) -> String {
    let mut out = String::with_capacity(64 * mesh.nodes.len() + 48 * mesh.quads.len());
    out.push_str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    physical_names(&mut out, mesh);
    // Entities: one curve per loop, one surface.
    out.push_str("$Entities\n");
    let _ = writeln!(out, "0 {} 1 0", mesh.loops.len());
    let bbox = |ids: &mut dyn Iterator<Item = u32>| {
        let mut lo = Point::splat(f64::INFINITY);
        let mut hi = Point::splat(f64::NEG_INFINITY);
        for i in ids {
            lo = lo.min(mesh.nodes[i as usize]);
            hi = hi.max(mesh.nodes[i as usize]);
        }
        (lo, hi)
    };
    for (k, l) in mesh.loops.iter().enumerate() {
        let (lo, hi) = bbox(&mut l.iter().copied());
        let _ = write!(out, "{} ", k + 1);
        xyz(&mut out, lo);
        out.push(' ');
        xyz(&mut out, hi);
        let _ = writeln!(out, " 1 {} 0", k + 1);
    }
    let (lo, hi) = bbox(&mut (0..mesh.nodes.len() as u32));
    out.push_str("1 ");
    xyz(&mut out, lo);
    out.push(' ');
    xyz(&mut out, hi);
    let _ = write!(out, " 1 {SURFACE_TAG} {}", mesh.loops.len());
    for k in 0..mesh.loops.len() {
        // Holes bound the surface with reversed orientation.
        let _ = write!(
            out,
            " {}",
            if k == 0 {
                (k + 1) as i64
            } else {
                -((k + 1) as i64)
            }
        );
    }
    out.push_str("\n$EndEntities\n");
    // Nodes: boundary nodes in their curve's block, the rest in the surface.
    let nb = mesh.n_boundary();
    let n = mesh.nodes.len();
    let interior = n - nb;
    let blocks = mesh.loops.len() + usize::from(interior > 0);
    out.push_str("$Nodes\n");
    let _ = writeln!(out, "{blocks} {n} 1 {n}");
    let block = |out: &mut String, dim: usize, tag: usize, ids: &[u32]| {
        let _ = writeln!(out, "{dim} {tag} 0 {}", ids.len());
        for &i in ids {
            let _ = writeln!(out, "{}", i + 1);
        }
        for &i in ids {
            xyz(out, mesh.nodes[i as usize]);
            out.push('\n');
        }
    };
    for (k, l) in mesh.loops.iter().enumerate() {
        block(&mut out, 1, k + 1, l);
    }
    if interior > 0 {
        let ids: Vec<u32> = (nb as u32..n as u32).collect();
        block(&mut out, 2, 1, &ids);
    }
    out.push_str("$EndNodes\n");
    let n_lines = nb;
    let total = n_lines + mesh.quads.len();
    out.push_str("$Elements\n");
    let _ = writeln!(out, "{} {total} 1 {total}", mesh.loops.len() + 1);
    let mut tag = 0;
    for (k, l) in mesh.loops.iter().enumerate() {
        let _ = writeln!(out, "1 {} {LINE2} {}", k + 1, l.len());
        for i in 0..l.len() {
            tag += 1;
            let _ = writeln!(out, "{tag} {} {}", l[i] + 1, l[(i + 1) % l.len()] + 1);
        }
    }
    let _ = writeln!(out, "2 1 {QUAD4} {}", mesh.quads.len());
    for q in &mesh.quads {
        tag += 1;
        let _ = writeln!(
            out,
            "{tag} {} {} {} {}",
            q[0] + 1,
            q[1] + 1,
            q[2] + 1,
            q[3] + 1
        );
    }
    out.push_str("$EndElements\n");
    out
}

/// MSH 2.2 ASCII.
pub fn write_msh22(mesh: &QuadMesh) -> String {
    let mut out = String::with_capacity(48 * mesh.nodes.len() + 40 * mesh.quads.len());
    out.push_str("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
    physical_names(&mut out, mesh);
    out.push_str("$Nodes\n");
    let _ = writeln!(out, "{}", mesh.nodes.len());
    for (i, &p) in mesh.nodes.iter().enumerate() {
        let _ = write!(out, "{} ", i + 1);
        xyz(&mut out, p);
        out.push('\n');
    }
    out.push_str("$EndNodes\n$Elements\n");
    let _ = writeln!(out, "{}", mesh.n_boundary() + mesh.quads.len());
    let mut tag = 0;
    for (k, l) in mesh.loops.iter().enumerate() {
        for i in 0..l.len() {
            tag += 1;
            let _ = writeln!(
                out,
                "{tag} {LINE2} 2 {} {} {} {}",
                k + 1,
                k + 1,
                l[i] + 1,
                l[(i + 1) % l.len()] + 1
            );
        }
    }
    for q in &mesh.quads {
        tag += 1;
        let _ = writeln!(
            out,
            "{tag} {QUAD4} 2 {SURFACE_TAG} 1 {} {} {} {}",
            q[0] + 1,
            q[1] + 1,
            q[2] + 1,
            q[3] + 1
        );
    }
    out.push_str("$EndElements\n");
    out
}

struct Tokens<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    line: usize,
    /// Lines in the file.
    total: usize,
}

impl<'a> Tokens<'a> {
    fn next_line(&mut self) -> Option<&'a str> {
        let (i, l) = self.lines.next()?;
        self.line = i + 1;
        Some(l.trim())
    }
    fn fields(&mut self, what: &str) -> Result<Vec<&'a str>, ReadError> {
        self.next_line()
            .map(|l| l.split_whitespace().collect())
            .ok_or_else(|| ReadError::Truncated {
                expected: what.to_string(),
            })
    }
    fn err(&self, message: impl Into<String>) -> ReadError {
        ReadError::Syntax {
            line: self.line,
            message: message.into(),
        }
    }
    fn num<T: std::str::FromStr>(&self, f: &[&str], k: usize) -> Result<T, ReadError> {
        f.get(k)
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| self.err(format!("expected a number in field {}", k + 1)))
    }
    /// Refuses a count (field `k` of the current line) of items taking
    /// `lines_each` lines each that the rest of the file cannot hold: a
    /// count never makes the reader reserve memory for data that is not
    /// there.
    fn count(
        &self,
        f: &[&str],
        k: usize,
        lines_each: u64,
        what: &'static str,
    ) -> Result<usize, ReadError> {
        let count: u64 = self.num(f, k)?;
        let room = self.total.saturating_sub(self.line);
        if count.saturating_mul(lines_each) > room as u64 {
            return Err(ReadError::TooMany {
                line: self.line,
                count,
                what,
                room,
            });
        }
        Ok(count as usize)
    }
}

/// Reads an all-quad 2D mesh from MSH 2.2 or 4.1 ASCII and checks it
/// ([`super::check`]): a file that parses but holds non-convex,
/// overlapping or separate quads is refused. Second-order quads (9- and
/// 8-node, as `quadex mesh --order 2` writes them) are read by their
/// corners: the mesh of their straight-sided quads. Nodes are renumbered so that
/// the boundary nodes come first, loop by loop (outer loop CCW first,
/// holes CW), and quads are made CCW.
pub fn read_msh(text: &str) -> Result<QuadMesh, ReadError> {
    let text = super::normalise_text(text);
    if text.trim().is_empty() {
        return Err(ReadError::Empty);
    }
    let mut t = Tokens {
        lines: text.lines().enumerate(),
        line: 0,
        total: text.lines().count(),
    };
    // Quads are read by their corners (a second-order quad's first four
    // nodes); lines and points are the groups', passed over.
    let mut version = 0.0f64;
    let mut nodes: BTreeMap<u64, Point> = BTreeMap::new();
    // Quads as (element tag, node tags).
    let mut quads: Vec<(u64, [u64; 4])> = Vec::new();
    while let Some(l) = t.next_line() {
        match l {
            "$MeshFormat" => {
                let f = t.fields("the format line")?;
                version = t.num(&f, 0)?;
                if !version.is_finite() || version <= 0.0 {
                    return Err(t.err("the format version is not a positive number"));
                }
                if f.get(1) != Some(&"0") {
                    return Err(t.err("binary MSH is not supported; save as ASCII"));
                }
            }
            "$Nodes" if version >= 4.0 => {
                let f = t.fields("the node header")?;
                let blocks = t.count(&f, 0, 1, "node blocks")?;
                for _ in 0..blocks {
                    let f = t.fields("a node block header")?;
                    let count = t.count(&f, 3, 2, "nodes")?;
                    let mut tags = Vec::with_capacity(count);
                    for _ in 0..count {
                        let f = t.fields("a node tag")?;
                        tags.push(t.num::<u64>(&f, 0)?);
                    }
                    for tag in tags {
                        let f = t.fields("node coordinates")?;
                        nodes.insert(tag, Point::new(t.num(&f, 0)?, t.num(&f, 1)?));
                    }
                }
            }
            "$Nodes" => {
                let f = t.fields("the node count")?;
                let count = t.count(&f, 0, 1, "nodes")?;
                for _ in 0..count {
                    let f = t.fields("a node")?;
                    nodes.insert(t.num(&f, 0)?, Point::new(t.num(&f, 1)?, t.num(&f, 2)?));
                }
            }
            "$Elements" if version >= 4.0 => {
                let f = t.fields("the element header")?;
                let blocks = t.count(&f, 0, 1, "element blocks")?;
                for _ in 0..blocks {
                    let f = t.fields("an element block header")?;
                    let ty: u32 = t.num(&f, 2)?;
                    let count = t.count(&f, 3, 1, "elements")?;
                    for _ in 0..count {
                        let f = t.fields("an element")?;
                        match ty {
                            QUAD4 | QUAD9 | QUAD8 => quads.push((
                                t.num(&f, 0)?,
                                [t.num(&f, 1)?, t.num(&f, 2)?, t.num(&f, 3)?, t.num(&f, 4)?],
                            )),
                            LINE2 | LINE3 | POINT => {}
                            other => {
                                return Err(ReadError::NotQuadMesh(format!("element type {other}")))
                            }
                        }
                    }
                }
            }
            "$Elements" => {
                let f = t.fields("the element count")?;
                let count = t.count(&f, 0, 1, "elements")?;
                for _ in 0..count {
                    let f = t.fields("an element")?;
                    let ty: u32 = t.num(&f, 1)?;
                    let ntags: usize = t.num(&f, 2)?;
                    let at = ntags.saturating_add(3);
                    match ty {
                        QUAD4 | QUAD9 | QUAD8 => quads.push((
                            t.num(&f, 0)?,
                            [
                                t.num(&f, at)?,
                                t.num(&f, at.saturating_add(1))?,
                                t.num(&f, at.saturating_add(2))?,
                                t.num(&f, at.saturating_add(3))?,
                            ],
                        )),
                        LINE2 | LINE3 | POINT => {}
                        other => {
                            return Err(ReadError::NotQuadMesh(format!("element type {other}")))
                        }
                    }
                }
            }
            _ => {}
        }
    }
    if version == 0.0 {
        return Err(ReadError::Syntax {
            line: 1,
            message: "no $MeshFormat section".into(),
        });
    }
    if quads.is_empty() {
        return Err(ReadError::NotQuadMesh("no quads".into()));
    }
    from_raw(&nodes, &quads)
}

/// The mesh of the quads read, checked, with the file's tags in messages.
fn from_raw(
    nodes: &BTreeMap<u64, Point>,
    quads: &[(u64, [u64; 4])],
) -> Result<QuadMesh, ReadError> {
    // Compact ids over the nodes the quads use.
    let mut id: BTreeMap<u64, u32> = BTreeMap::new();
    let mut pts = Vec::new();
    let mut tags = Vec::new();
    let mut qs = Vec::with_capacity(quads.len());
    for (_, q) in quads {
        let mut out = [0u32; 4];
        for (k, tag) in q.iter().enumerate() {
            let p = *nodes.get(tag).ok_or_else(|| {
                ReadError::NotQuadMesh(format!("a quad uses node {tag}, which is not defined"))
            })?;
            out[k] = *id.entry(*tag).or_insert_with(|| {
                pts.push(p);
                tags.push(*tag);
                (pts.len() - 1) as u32
            });
        }
        qs.push(out);
    }
    let quad_tag = |k: usize| quads.get(k).map_or(k as u64, |q| q.0);
    if let Some(k) = pts.iter().position(|p| !p.is_finite()) {
        return Err(MeshCheckError::NonFinite { node: tags[k] }.into());
    }
    let (mesh, order) = assemble(&pts, qs)
        .map_err(|e| check::from_invariant(e, &|v| tags[v as usize], &quad_tag))?;
    check::check_mesh_labelled(&mesh, &|v| tags[order[v as usize] as usize], &quad_tag)?;
    Ok(mesh)
}

/// Signed area of a quad, relative to its first corner.
fn quad_area(p: [Point; 4]) -> f64 {
    0.5 * ((p[1] - p[0]).perp_dot(p[2] - p[0]) + (p[2] - p[0]).perp_dot(p[3] - p[0]))
}

/// The mesh of bare quads (any orientation): quads turned counter-clockwise
/// (judged relative to each quad's first corner, so far from the origin
/// too), boundary loops from the edges used once (the outer loop, of
/// largest area, first), nodes renumbered boundary first in loop order,
/// then in order of use. Also returns, per new node id, the old one.
fn assemble(
    points: &[Point],
    quads: Vec<[u32; 4]>,
) -> Result<(QuadMesh, Vec<u32>), InvariantError> {
    let mut qs = quads;
    for (k, q) in qs.iter_mut().enumerate() {
        if quad_area(q.map(|i| points[i as usize])) < 0.0 {
            q.reverse();
        }
        // A quad that is not convex (a bow-tie above all) is named before
        // the boundary is traced: its crossed sides would show there only
        // as a node with two boundary edges leaving it.
        if let Some(i) = reflex_corner(q.map(|i| points[i as usize])) {
            return Err(InvariantError::NotConvex {
                quad: k,
                node: q[i],
            });
        }
    }
    let mut loops = boundary_loops(points, &qs)?;
    // The outer loop by an area free of cancellation.
    let area = |l: &Vec<u32>| {
        let p: Vec<Point> = l.iter().map(|&i| points[i as usize]).collect();
        let o = p[0];
        (1..p.len().saturating_sub(1))
            .map(|i| (p[i] - o).perp_dot(p[i + 1] - o))
            .sum::<f64>()
    };
    if let Some(outer) =
        (0..loops.len()).max_by(|&a, &b| area(&loops[a]).total_cmp(&area(&loops[b])))
    {
        loops.swap(0, outer);
    }
    let mut new_id = vec![u32::MAX; points.len()];
    let mut order: Vec<u32> = Vec::with_capacity(points.len());
    for v in loops.iter().flatten().chain(qs.iter().flatten()).copied() {
        if new_id[v as usize] == u32::MAX {
            new_id[v as usize] = order.len() as u32;
            order.push(v);
        }
    }
    let mesh = QuadMesh {
        nodes: order.iter().map(|&v| points[v as usize]).collect(),
        quads: qs.iter().map(|q| q.map(|v| new_id[v as usize])).collect(),
        loops: loops
            .iter()
            .map(|l| l.iter().map(|&v| new_id[v as usize]).collect())
            .collect(),
    };
    Ok((mesh, order))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_beyond_the_file_are_refused_before_reading() {
        let head = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n";
        for block in ["2 1 0 18446744073709551615\n", "2 1 0 99999999999\n"] {
            let e = read_msh(&format!("{head}{block}")).unwrap_err();
            assert!(matches!(e, ReadError::TooMany { line: 6, .. }), "{e:?}");
        }
        let e = read_msh("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n99999999999\n1 0 0 0\n")
            .unwrap_err();
        assert!(matches!(e, ReadError::TooMany { line: 5, .. }), "{e:?}");
        let e = read_msh("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Elements\n18446744073709551615\n")
            .unwrap_err();
        assert!(matches!(e, ReadError::TooMany { line: 5, .. }), "{e:?}");
    }

    #[test]
    fn tags_name_the_quad_and_node_at_fault() {
        let t = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n11 0 0 0\n12 2 0 0\n13 0.5 0.5 0\n14 0 2 0\n$EndNodes\n$Elements\n1\n7 3 2 1 1 11 12 13 14\n$EndElements\n";
        let e = read_msh(t).unwrap_err();
        assert!(
            matches!(
                e,
                ReadError::InvalidMesh(MeshCheckError::NotConvex { quad: 7, node: 13 })
            ),
            "{e:?}"
        );
        // CRLF and a byte-order mark read the same.
        let e2 = read_msh(&format!("\u{feff}{}", t.replace('\n', "\r\n"))).unwrap_err();
        assert_eq!(e.to_string(), e2.to_string());
    }

    #[test]
    fn a_bow_tie_is_named_by_its_tag() {
        // Element 9's sides 12-13 and 15-16 cross: its nodes run 12, 13,
        // 15, 16 where the square beside element 8 would be 12, 13, 16, 15.
        let t = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n11 0 0 0\n12 1 0 0\n13 2 0 0\n14 0 1 0\n15 1 1 0\n16 2 1 0\n$EndNodes\n$Elements\n2\n8 3 2 0 1 11 12 15 14\n9 3 2 0 1 12 13 15 16\n$EndElements\n";
        let e = read_msh(t).unwrap_err();
        assert!(
            matches!(
                e,
                ReadError::InvalidMesh(MeshCheckError::NotConvex { quad: 9, .. })
            ),
            "{e:?}"
        );
    }

    #[test]
    fn a_small_mesh_far_from_the_origin_reads() {
        let mut t = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n");
        for (k, (x, y)) in [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]
            .iter()
            .enumerate()
        {
            t.push_str(&format!(
                "{} {} {} 0\n",
                k + 1,
                1e8 + *x as f64,
                1e8 + *y as f64
            ));
        }
        t.push_str("$EndNodes\n$Elements\n2\n1 3 2 1 1 1 2 5 6\n2 3 2 1 1 2 3 4 5\n$EndElements\n");
        let m = read_msh(&t).unwrap();
        assert_eq!(m.quads.len(), 2);
        assert_eq!(m.n_boundary(), 6);
    }
}

//! Writers of a mesh of several regions with named boundary groups
//! ([`Labelled`]: the view of a `crate::regions::RegionMesh` they write),
//! in the formats FE codes read:
//!
//! - Gmsh MSH 4.1 and 2.2: region `a` is physical surface `a` (named
//!   `region_a` or its given name), marker `m` physical curve `m` (named
//!   `marker_m` or its given name) with the 2-node line elements of its
//!   segments, interface segments included;
//! - Abaqus `.inp`: an ELSET per region, and per group an NSET and an
//!   element-based SURFACE;
//! - VTK legacy and XML: the quads with a `region` cell array, and the
//!   group lines with a `marker` array (0 on quads, as `region` is 0 on
//!   lines).

use super::abaqus::{list, surface};
use super::msh::xyz;
use super::{fmt_f64, svg, vtk};
use crate::geom::Point;
use crate::mesh::QuadMesh;
use crate::order2::Order2;
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// A region or a group as the writers see it: its physical tag, its name
/// and (for a group) its mesh edges as node pairs.
#[derive(Clone, Copy, Debug)]
pub struct Named<'a> {
    pub tag: i64,
    pub name: &'a str,
    pub edges: &'a [[u32; 2]],
}

/// A mesh with its quads' regions and its boundary groups: what the
/// writers of this module write.
#[derive(Clone, Debug)]
pub struct Labelled<'a> {
    pub mesh: &'a QuadMesh,
    /// The region (index into `regions`) of each quad.
    pub quad_region: &'a [u32],
    pub regions: Vec<Named<'a>>,
    pub groups: Vec<Named<'a>>,
    /// The quads as 9-node quads (second order), when asked for.
    pub order2: Option<&'a Order2>,
}

impl Labelled<'_> {
    /// Every node written: the mesh's, then the second-order ones.
    fn points(&self) -> &[Point] {
        self.order2.map_or(&self.mesh.nodes, |o| o.written_nodes())
    }

    /// The nodes of quad `k`: 4, or 9 at second order.
    fn element(&self, k: usize) -> Vec<u32> {
        match self.order2 {
            Some(o) => o.element(k).to_vec(),
            None => self.mesh.quads[k].to_vec(),
        }
    }

    /// The nodes of a group's edge: 2, or 3 at second order.
    fn line(&self, e: [u32; 2]) -> Vec<u32> {
        match self.order2.and_then(|o| o.mid(e[0], e[1])) {
            Some(m) => vec![e[0], e[1], m],
            None => e.to_vec(),
        }
    }

    /// Gmsh element types of the quads and the lines.
    fn msh_types(&self) -> (u32, u32) {
        use super::msh::{LINE2, LINE3, QUAD4, QUAD8, QUAD9};
        match self.order2 {
            Some(o) if o.serendipity => (QUAD8, LINE3),
            Some(_) => (QUAD9, LINE3),
            None => (QUAD4, LINE2),
        }
    }
}
/// Node numbers (from 1) after a tag, space separated.
fn numbered(out: &mut String, nodes: &[u32]) {
    for v in nodes {
        let _ = write!(out, " {}", v + 1);
    }
    out.push('\n');
}

fn physical_names(out: &mut String, m: &Labelled) {
    out.push_str("$PhysicalNames\n");
    let _ = writeln!(out, "{}", m.groups.len() + m.regions.len());
    for g in &m.groups {
        let _ = writeln!(out, "1 {} \"{}\"", g.tag, g.name);
    }
    for r in &m.regions {
        let _ = writeln!(out, "2 {} \"{}\"", r.tag, r.name);
    }
    out.push_str("$EndPhysicalNames\n");
}

/// The quads of each region, in mesh order.
fn quads_by_region(m: &Labelled) -> Vec<Vec<usize>> {
    let mut by = vec![Vec::new(); m.regions.len()];
    for (k, &r) in m.quad_region.iter().enumerate() {
        by[r as usize].push(k);
    }
    by
}

fn bbox(m: &Labelled, ids: impl Iterator<Item = u32>) -> (Point, Point) {
    let mut lo = Point::splat(f64::INFINITY);
    let mut hi = Point::splat(f64::NEG_INFINITY);
    for i in ids {
        lo = lo.min(m.mesh.nodes[i as usize]);
        hi = hi.max(m.mesh.nodes[i as usize]);
    }
    (lo, hi)
}

/// MSH 4.1 ASCII: one curve entity per group, one surface entity per
/// region, every node in the first surface's block.
pub fn write_msh41(m: &Labelled) -> String {
    let mesh = m.mesh;
    let mut out = String::with_capacity(64 * mesh.nodes.len() + 48 * mesh.quads.len());
    out.push_str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    physical_names(&mut out, m);
    let by_region = quads_by_region(m);
    out.push_str("$Entities\n");
    let _ = writeln!(out, "0 {} {} 0", m.groups.len(), m.regions.len());
    let entity = |out: &mut String, tag: usize, (lo, hi): (Point, Point), physical: i64| {
        let _ = write!(out, "{tag} ");
        xyz(out, lo);
        out.push(' ');
        xyz(out, hi);
        let _ = writeln!(out, " 1 {physical} 0");
    };
    for (k, g) in m.groups.iter().enumerate() {
        entity(
            &mut out,
            k + 1,
            bbox(m, g.edges.iter().flatten().copied()),
            g.tag,
        );
    }
    for (k, r) in m.regions.iter().enumerate() {
        let ids = by_region[k].iter().flat_map(|&q| mesh.quads[q]);
        entity(&mut out, k + 1, bbox(m, ids), r.tag);
    }
    out.push_str("$EndEntities\n");
    let n = m.points().len();
    out.push_str("$Nodes\n");
    let _ = writeln!(out, "1 {n} 1 {n}\n2 1 0 {n}");
    for i in 1..=n {
        let _ = writeln!(out, "{i}");
    }
    for &p in m.points() {
        xyz(&mut out, p);
        out.push('\n');
    }
    out.push_str("$EndNodes\n");
    let lines: usize = m.groups.iter().map(|g| g.edges.len()).sum();
    let total = lines + mesh.quads.len();
    let blocks = m.groups.len() + m.regions.len();
    let (quad_type, line_type) = m.msh_types();
    out.push_str("$Elements\n");
    let _ = writeln!(out, "{blocks} {total} 1 {total}");
    let mut tag = 0;
    for (k, g) in m.groups.iter().enumerate() {
        let _ = writeln!(out, "1 {} {line_type} {}", k + 1, g.edges.len());
        for e in g.edges {
            tag += 1;
            let _ = write!(out, "{tag}");
            numbered(&mut out, &m.line(*e));
        }
    }
    for (k, quads) in by_region.iter().enumerate() {
        let _ = writeln!(out, "2 {} {quad_type} {}", k + 1, quads.len());
        for &q in quads {
            tag += 1;
            let _ = write!(out, "{tag}");
            numbered(&mut out, &m.element(q));
        }
    }
    out.push_str("$EndElements\n");
    out
}

/// MSH 2.2 ASCII: each element carries its physical tag and its entity.
pub fn write_msh22(m: &Labelled) -> String {
    let mesh = m.mesh;
    let mut out = String::with_capacity(48 * mesh.nodes.len() + 40 * mesh.quads.len());
    out.push_str("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
    physical_names(&mut out, m);
    out.push_str("$Nodes\n");
    let _ = writeln!(out, "{}", m.points().len());
    for (i, &p) in m.points().iter().enumerate() {
        let _ = write!(out, "{} ", i + 1);
        xyz(&mut out, p);
        out.push('\n');
    }
    let lines: usize = m.groups.iter().map(|g| g.edges.len()).sum();
    let (quad_type, line_type) = m.msh_types();
    out.push_str("$EndNodes\n$Elements\n");
    let _ = writeln!(out, "{}", lines + mesh.quads.len());
    let mut tag = 0;
    for (k, g) in m.groups.iter().enumerate() {
        for e in g.edges {
            tag += 1;
            let _ = write!(out, "{tag} {line_type} 2 {} {}", g.tag, k + 1);
            numbered(&mut out, &m.line(*e));
        }
    }
    for (k, quads) in quads_by_region(m).iter().enumerate() {
        for &q in quads {
            tag += 1;
            let _ = write!(out, "{tag} {quad_type} 2 {} {}", m.regions[k].tag, k + 1);
            numbered(&mut out, &m.element(q));
        }
    }
    out.push_str("$EndElements\n");
    out
}

/// A name as an Abaqus label: letters, digits and `_`, upper case, not
/// starting with a digit.
fn label(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect();
    if !s.starts_with(|c: char| c.is_ascii_alphabetic()) {
        s.insert(0, 'G');
    }
    s
}

/// Abaqus input: CPS4 quads (CPS8 at second order, 9-node or serendipity:
/// Abaqus has no 9-node plane element, so the centre node is left out, of
/// the elements and of the node list) numbered region by
/// region, an ELSET per region, and per group an NSET and an element
/// SURFACE (the quad face on each edge; on an interface, the quad on the
/// left of the segment as given).
pub fn write_inp(m: &Labelled) -> String {
    let mesh = m.mesh;
    let mut out = String::with_capacity(40 * mesh.nodes.len() + 40 * mesh.quads.len());
    out.push_str("*HEADING\nquadex all-quad mesh\n*NODE\n");
    // The nodes the elements use, numbered in order: all of them but a
    // 9-node quad's centre, which a CPS8 element has no place for.
    let points = m.points();
    let mut used = vec![false; points.len()];
    for q in 0..mesh.quads.len() {
        let nodes = m.element(q);
        for &v in &nodes[..nodes.len().min(8)] {
            used[v as usize] = true;
        }
    }
    let mut id = vec![0usize; points.len()];
    let mut count = 0;
    for (i, p) in points.iter().enumerate().filter(|&(i, _)| used[i]) {
        count += 1;
        id[i] = count;
        let _ = write!(out, "{count}, ");
        fmt_f64(&mut out, p.x);
        out.push_str(", ");
        fmt_f64(&mut out, p.y);
        out.push('\n');
    }
    // Which element face lies on each directed edge.
    let mut face: BTreeMap<(u32, u32), (usize, usize)> = BTreeMap::new();
    let mut number = 0;
    for (k, quads) in quads_by_region(m).iter().enumerate() {
        let kind = if m.order2.is_some() { "CPS8" } else { "CPS4" };
        let _ = writeln!(
            out,
            "*ELEMENT, TYPE={kind}, ELSET={}",
            label(m.regions[k].name)
        );
        for &q in quads {
            number += 1;
            let corners = mesh.quads[q];
            for i in 0..4 {
                face.insert((corners[i], corners[(i + 1) % 4]), (number, i + 1));
            }
            let nodes = m.element(q);
            let _ = write!(out, "{number}");
            for &v in &nodes[..nodes.len().min(8)] {
                let _ = write!(out, ", {}", id[v as usize]);
            }
            out.push('\n');
        }
    }
    for g in &m.groups {
        let name = label(g.name);
        let _ = writeln!(out, "*NSET, NSET={name}");
        let mut nodes: Vec<usize> = g
            .edges
            .iter()
            .flat_map(|e| m.line(*e))
            .map(|v| id[v as usize])
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        list(&mut out, nodes);
        let mut by_face: [Vec<usize>; 4] = Default::default();
        for e in g.edges {
            let on = face.get(&(e[0], e[1])).or_else(|| face.get(&(e[1], e[0])));
            if let Some(&(el, f)) = on {
                by_face[f - 1].push(el);
            }
        }
        surface(&mut out, &name, &by_face);
    }
    out
}

/// The cells of a VTK file: quads then group lines, as node lists, with
/// their `region` and `marker` values.
struct Cells {
    nodes: Vec<Vec<u32>>,
    region: Vec<i64>,
    marker: Vec<i64>,
    sj: Vec<f64>,
    angle: Vec<f64>,
}

fn cells(m: &Labelled) -> Cells {
    let (mut sj, mut angle) = vtk::cell_fields(m.mesh);
    let mut c = Cells {
        nodes: (0..m.mesh.quads.len()).map(|k| m.element(k)).collect(),
        region: m
            .quad_region
            .iter()
            .map(|&r| m.regions[r as usize].tag)
            .collect(),
        marker: vec![0; m.mesh.quads.len()],
        sj: Vec::new(),
        angle: Vec::new(),
    };
    for g in &m.groups {
        for e in g.edges {
            c.nodes.push(m.line(*e));
            c.region.push(0);
            c.marker.push(g.tag);
            sj.push(0.0);
            angle.push(0.0);
        }
    }
    c.sj = sj;
    c.angle = angle;
    c
}

/// The VTK cell type of a cell of `n` nodes: line, quadratic line, quad,
/// quadratic (serendipity) quad, biquadratic quad.
fn vtk_type(n: usize) -> &'static str {
    match n {
        2 => "3\n",
        3 => "21\n",
        8 => "23\n",
        9 => "28\n",
        _ => "9\n",
    }
}

/// Legacy VTK 2.0 ASCII.
pub fn write_legacy(m: &Labelled) -> String {
    let mesh = m.mesh;
    let c = cells(m);
    let mut out = String::with_capacity(48 * mesh.nodes.len() + 64 * c.nodes.len());
    out.push_str(
        "# vtk DataFile Version 2.0\nquadex all-quad mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n",
    );
    let _ = writeln!(out, "POINTS {} double", m.points().len());
    for p in m.points() {
        xyz(&mut out, *p);
        out.push('\n');
    }
    let size: usize = c.nodes.iter().map(|n| n.len() + 1).sum();
    let _ = writeln!(out, "CELLS {} {size}", c.nodes.len());
    for n in &c.nodes {
        let _ = write!(out, "{}", n.len());
        for v in n {
            let _ = write!(out, " {v}");
        }
        out.push('\n');
    }
    let _ = writeln!(out, "CELL_TYPES {}", c.nodes.len());
    for n in &c.nodes {
        out.push_str(vtk_type(n.len()));
    }
    let _ = writeln!(out, "CELL_DATA {}", c.nodes.len());
    for (name, v) in [("region", &c.region), ("marker", &c.marker)] {
        let _ = writeln!(out, "SCALARS {name} int 1\nLOOKUP_TABLE default");
        for x in v {
            let _ = writeln!(out, "{x}");
        }
    }
    for (name, v) in [("scaled_jacobian", &c.sj), ("min_angle", &c.angle)] {
        let _ = writeln!(out, "SCALARS {name} double 1\nLOOKUP_TABLE default");
        for &x in v {
            fmt_f64(&mut out, x);
            out.push('\n');
        }
    }
    out
}

/// VTK XML unstructured grid, ASCII.
pub fn write_vtu(m: &Labelled) -> String {
    let mesh = m.mesh;
    let c = cells(m);
    let mut out = String::with_capacity(48 * mesh.nodes.len() + 80 * c.nodes.len());
    out.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n");
    let _ = writeln!(
        out,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        m.points().len(),
        c.nodes.len()
    );
    out.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in m.points() {
        xyz(&mut out, *p);
        out.push('\n');
    }
    out.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for n in &c.nodes {
        let s: Vec<String> = n.iter().map(u32::to_string).collect();
        let _ = writeln!(out, "{}", s.join(" "));
    }
    out.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    let mut at = 0;
    for n in &c.nodes {
        at += n.len();
        let _ = writeln!(out, "{at}");
    }
    out.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for n in &c.nodes {
        out.push_str(vtk_type(n.len()));
    }
    out.push_str("</DataArray>\n</Cells>\n<CellData Scalars=\"region\">\n");
    for (name, v) in [("region", &c.region), ("marker", &c.marker)] {
        let _ = writeln!(
            out,
            "<DataArray type=\"Int64\" Name=\"{name}\" format=\"ascii\">"
        );
        for x in v {
            let _ = writeln!(out, "{x}");
        }
        out.push_str("</DataArray>\n");
    }
    for (name, v) in [("scaled_jacobian", &c.sj), ("min_angle", &c.angle)] {
        vtk::vtu_floats(&mut out, name, v);
    }
    out.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    out
}

/// An SVG picture: quads tinted by region, and the interfaces between
/// regions and the groups' edges drawn as the boundary is.
pub fn write_svg(m: &Labelled) -> String {
    let fill = |k: usize| svg::PALETTE[m.quad_region[k] as usize % svg::PALETTE.len()];
    let mut side: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    let mut lines: Vec<[u32; 2]> = Vec::new();
    for (q, &r) in m.mesh.quads.iter().zip(m.quad_region) {
        for i in 0..4 {
            let (a, b) = (q[i], q[(i + 1) % 4]);
            match side.insert((a.min(b), a.max(b)), r) {
                Some(other) if other != r => lines.push([a, b]),
                _ => {}
            }
        }
    }
    lines.extend(m.groups.iter().flat_map(|g| g.edges.iter().copied()));
    svg::write_svg_with(m.mesh, svg::SvgOptions::default().width, &fill, &lines)
}

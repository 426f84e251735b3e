//! Abaqus input (`.inp`): CPS4 plane-stress quads in an element set
//! `DOMAIN`, and for each boundary loop a node set and an element-based
//! surface (`OUTER`, `HOLE_1`, …).

use super::fmt_f64;
use crate::mesh::QuadMesh;
use std::collections::BTreeMap;
use std::fmt::Write as _;

pub(super) fn list(out: &mut String, ids: impl IntoIterator<Item = usize>) {
    for (k, id) in ids.into_iter().enumerate() {
        if k > 0 {
            out.push_str(if k % 16 == 0 { ",\n" } else { ", " });
        }
        let _ = write!(out, "{id}");
    }
    out.push('\n');
}

/// An element-based surface `name`: an ELSET of the elements whose face
/// `k + 1` lies on it for each face number, then the SURFACE over them.
pub(super) fn surface(out: &mut String, name: &str, by_face: &[Vec<usize>; 4]) {
    for (f, els) in by_face.iter().enumerate() {
        if !els.is_empty() {
            let _ = writeln!(out, "*ELSET, ELSET={name}_S{}", f + 1);
            list(out, els.iter().copied());
        }
    }
    let _ = writeln!(out, "*SURFACE, TYPE=ELEMENT, NAME={name}");
    for (f, els) in by_face.iter().enumerate() {
        if !els.is_empty() {
            let _ = writeln!(out, "{name}_S{}, S{}", f + 1, f + 1);
        }
    }
}

/// Renders the mesh as an Abaqus input file.
pub fn write_inp(mesh: &QuadMesh) -> String {
    let mut out = String::with_capacity(40 * mesh.nodes.len() + 40 * mesh.quads.len());
    out.push_str("*HEADING\nquadex all-quad mesh\n*NODE\n");
    for (i, p) in mesh.nodes.iter().enumerate() {
        let _ = write!(out, "{}, ", i + 1);
        fmt_f64(&mut out, p.x);
        out.push_str(", ");
        fmt_f64(&mut out, p.y);
        out.push('\n');
    }
    out.push_str("*ELEMENT, TYPE=CPS4, ELSET=DOMAIN\n");
    for (k, q) in mesh.quads.iter().enumerate() {
        let _ = writeln!(
            out,
            "{}, {}, {}, {}, {}",
            k + 1,
            q[0] + 1,
            q[1] + 1,
            q[2] + 1,
            q[3] + 1
        );
    }
    // Which quad face lies on each directed boundary edge.
    let mut face: BTreeMap<(u32, u32), (usize, usize)> = BTreeMap::new();
    for (k, q) in mesh.quads.iter().enumerate() {
        for i in 0..4 {
            face.insert((q[i], q[(i + 1) % 4]), (k + 1, i + 1));
        }
    }
    for (li, l) in mesh.loops.iter().enumerate() {
        let name = if li == 0 {
            "OUTER".to_string()
        } else {
            format!("HOLE_{li}")
        };
        let _ = writeln!(out, "*NSET, NSET={name}");
        list(&mut out, l.iter().map(|&v| v as usize + 1));
        let mut by_face: [Vec<usize>; 4] = Default::default();
        for i in 0..l.len() {
            if let Some(&(el, f)) = face.get(&(l[i], l[(i + 1) % l.len()])) {
                by_face[f - 1].push(el);
            }
        }
        surface(&mut out, &name, &by_face);
    }
    out
}

//! VTK output: legacy 2.0 ASCII (`.vtk`) and XML unstructured grid
//! (`.vtu`, ASCII). Quads are cell type 9; each cell carries its scaled
//! Jacobian and minimum angle.

use super::fmt_f64;
use crate::mesh::QuadMesh;
use crate::quality::QuadQuality;
use std::fmt::Write as _;

pub(super) fn cell_fields(mesh: &QuadMesh) -> (Vec<f64>, Vec<f64>) {
    mesh.quads
        .iter()
        .map(|q| {
            let f = QuadQuality::of(mesh.corners(q));
            (f.scaled_jacobian, f.min_angle())
        })
        .unzip()
}

/// Legacy VTK 2.0 ASCII unstructured grid.
pub fn write_legacy(mesh: &QuadMesh) -> String {
    let mut out = String::with_capacity(48 * mesh.nodes.len() + 64 * mesh.quads.len());
    out.push_str(
        "# vtk DataFile Version 2.0\nquadex all-quad mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n",
    );
    let _ = writeln!(out, "POINTS {} double", mesh.nodes.len());
    for p in &mesh.nodes {
        fmt_f64(&mut out, p.x);
        out.push(' ');
        fmt_f64(&mut out, p.y);
        out.push_str(" 0\n");
    }
    let m = mesh.quads.len();
    let _ = writeln!(out, "CELLS {m} {}", 5 * m);
    for q in &mesh.quads {
        let _ = writeln!(out, "4 {} {} {} {}", q[0], q[1], q[2], q[3]);
    }
    let _ = writeln!(out, "CELL_TYPES {m}");
    for _ in 0..m {
        out.push_str("9\n");
    }
    let (sj, ang) = cell_fields(mesh);
    let _ = writeln!(out, "CELL_DATA {m}");
    for (name, v) in [("scaled_jacobian", &sj), ("min_angle", &ang)] {
        let _ = writeln!(out, "SCALARS {name} double 1\nLOOKUP_TABLE default");
        for &x in v {
            fmt_f64(&mut out, x);
            out.push('\n');
        }
    }
    out
}

/// A VTK XML data array of floats, one a line.
pub(super) fn vtu_floats(out: &mut String, name: &str, values: &[f64]) {
    let _ = writeln!(
        out,
        "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
    );
    for &x in values {
        fmt_f64(out, x);
        out.push('\n');
    }
    out.push_str("</DataArray>\n");
}

/// VTK XML unstructured grid, ASCII.
pub fn write_vtu(mesh: &QuadMesh) -> String {
    let mut out = String::with_capacity(48 * mesh.nodes.len() + 80 * mesh.quads.len());
    let m = mesh.quads.len();
    out.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n");
    let _ = writeln!(
        out,
        "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{m}\">",
        mesh.nodes.len()
    );
    out.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for p in &mesh.nodes {
        fmt_f64(&mut out, p.x);
        out.push(' ');
        fmt_f64(&mut out, p.y);
        out.push_str(" 0\n");
    }
    out.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for q in &mesh.quads {
        let _ = writeln!(out, "{} {} {} {}", q[0], q[1], q[2], q[3]);
    }
    out.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for k in 1..=m {
        let _ = writeln!(out, "{}", 4 * k);
    }
    out.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in 0..m {
        out.push_str("9\n");
    }
    out.push_str("</DataArray>\n</Cells>\n<CellData Scalars=\"scaled_jacobian\">\n");
    let (sj, ang) = cell_fields(mesh);
    for (name, v) in [("scaled_jacobian", &sj), ("min_angle", &ang)] {
        vtu_floats(&mut out, name, v);
    }
    out.push_str("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    out
}

//! File formats: boundary input (Triangle `.poly`, the project's JSON),
//! mesh output (Gmsh MSH 4.1 and 2.2, legacy VTK, VTU, Abaqus, SVG) and mesh
//! input (Gmsh MSH ASCII).
//!
//! Every writer renders the whole file in memory first and then writes it to
//! a temporary name beside the target and renames it, so a failure never
//! leaves a partial file. Output is byte-for-byte deterministic.

pub mod abaqus;
pub mod boundary_json;
pub mod msh;
pub mod poly;
pub mod svg;
pub mod vtk;

use crate::boundary::{Boundary, BoundaryError};
use crate::mesh::QuadMesh;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// A file that could not be read as a boundary or a mesh.
#[derive(Debug, Error)]
pub enum ReadError {
    #[error("cannot read the file: {0}")]
    Io(#[from] std::io::Error),
    #[error("the file is empty")]
    Empty,
    #[error("line {line}: {message}")]
    Syntax { line: usize, message: String },
    #[error("the file ends early: {expected} expected")]
    Truncated { expected: String },
    #[error("invalid JSON: {0}")]
    Json(String),
    #[error("{0}")]
    Boundary(#[from] BoundaryError),
    #[error("unsupported file type `{0}`")]
    UnknownFormat(String),
    #[error("the mesh is not an all-quad 2D mesh: {0}")]
    NotQuadMesh(String),
}

/// A file that could not be written.
#[derive(Debug, Error)]
pub enum WriteError {
    #[error("cannot write {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("unsupported output type `{0}` (use .msh, .msh22, .vtk, .vtu, .inp or .svg)")]
    UnknownFormat(String),
}

/// Mesh output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum MeshFormat {
    /// Gmsh MSH 4.1 ASCII with entities and physical groups.
    Msh41,
    /// Gmsh MSH 2.2 ASCII.
    Msh22,
    /// Legacy VTK 2.0 ASCII unstructured grid.
    Vtk,
    /// VTK XML unstructured grid (ASCII).
    Vtu,
    /// Abaqus input file (CPS4 elements).
    Abaqus,
    /// An SVG picture coloured by quality.
    Svg,
}

impl MeshFormat {
    /// All formats, in the order menus list them.
    pub const ALL: [MeshFormat; 6] = [
        MeshFormat::Msh41,
        MeshFormat::Msh22,
        MeshFormat::Vtk,
        MeshFormat::Vtu,
        MeshFormat::Abaqus,
        MeshFormat::Svg,
    ];

    /// The format named by a file's extension (`.msh` is MSH 4.1; `.msh22`
    /// or `.msh2` is MSH 2.2).
    pub fn from_path(path: &Path) -> Result<MeshFormat, WriteError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        Ok(match ext.as_str() {
            "msh" => MeshFormat::Msh41,
            "msh22" | "msh2" => MeshFormat::Msh22,
            "vtk" => MeshFormat::Vtk,
            "vtu" => MeshFormat::Vtu,
            "inp" => MeshFormat::Abaqus,
            "svg" => MeshFormat::Svg,
            _ => return Err(WriteError::UnknownFormat(ext)),
        })
    }

    /// The usual file extension.
    pub fn extension(self) -> &'static str {
        match self {
            MeshFormat::Msh41 => "msh",
            MeshFormat::Msh22 => "msh22",
            MeshFormat::Vtk => "vtk",
            MeshFormat::Vtu => "vtu",
            MeshFormat::Abaqus => "inp",
            MeshFormat::Svg => "svg",
        }
    }

    /// Renders `mesh` in this format.
    pub fn render(self, mesh: &QuadMesh) -> String {
        match self {
            MeshFormat::Msh41 => msh::write_msh41(mesh),
            MeshFormat::Msh22 => msh::write_msh22(mesh),
            MeshFormat::Vtk => vtk::write_legacy(mesh),
            MeshFormat::Vtu => vtk::write_vtu(mesh),
            MeshFormat::Abaqus => abaqus::write_inp(mesh),
            MeshFormat::Svg => svg::write_svg(mesh, &svg::SvgOptions::default()),
        }
    }
}

/// Writes `mesh` to `path` in the format its extension names.
pub fn write_mesh(mesh: &QuadMesh, path: &Path) -> Result<(), WriteError> {
    let fmt = MeshFormat::from_path(path)?;
    write_atomic(path, fmt.render(mesh).as_bytes())
}

/// Writes `bytes` to a temporary file beside `path`, then renames it over
/// `path`: readers never see a partial file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let err = |source| WriteError::Io {
        path: path.to_path_buf(),
        source,
    };
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let res = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = res {
        let _ = std::fs::remove_file(&tmp);
        return Err(err(e));
    }
    Ok(())
}

/// Reads a boundary from `.poly` or `.json`, by extension.
pub fn read_boundary(path: &Path) -> Result<Boundary, ReadError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let bytes = std::fs::read(path)?;
    let text = String::from_utf8_lossy(&bytes);
    match ext.as_str() {
        "poly" => poly::parse_poly(&text),
        "json" => boundary_json::parse(&text),
        _ => Err(ReadError::UnknownFormat(ext)),
    }
}

/// Reads a quad mesh file (Gmsh MSH 2.2 or 4.1 ASCII).
pub fn read_mesh(path: &Path) -> Result<QuadMesh, ReadError> {
    let bytes = std::fs::read(path)?;
    msh::read_msh(&String::from_utf8_lossy(&bytes))
}

/// Formats a float so that it reads back to the same value (shortest
/// round-trip representation), the same on every platform.
pub(crate) fn fmt_f64(out: &mut String, v: f64) {
    // `{}` on f64 prints the shortest string that parses back exactly.
    let v = if v == 0.0 { 0.0 } else { v }; // no "-0"
    let _ = write!(out, "{v}");
}

//! File formats: boundary input (Triangle `.poly`, the project's JSON),
//! mesh output (Gmsh MSH 4.1 and 2.2, legacy VTK, VTU, Abaqus, SVG) and mesh
//! input (Gmsh MSH ASCII).
//!
//! Every writer renders the whole file in memory first and then writes it to
//! a temporary name beside the target and renames it, so a failure never
//! leaves a partial file. Output is byte-for-byte deterministic.

pub mod abaqus;
pub mod boundary_json;
pub mod check;
pub mod groups;
pub mod msh;
pub mod poly;
pub mod regions_json;
pub mod svg;
pub mod vtk;

use crate::boundary::{Boundary, BoundaryError};
use crate::mesh::QuadMesh;
use std::borrow::Cow;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use thiserror::Error;

pub use check::MeshCheckError;

/// A file that could not be read as a boundary or a mesh.
#[derive(Debug, Error)]
pub enum ReadError {
    // The cause is part of the message, not a `source`: printing the
    // error with its chain must not repeat it.
    #[error("cannot read the file: {0}")]
    Io(std::io::Error),
    #[error("the file is empty")]
    Empty,
    #[error("line {line}: {message}")]
    Syntax { line: usize, message: String },
    #[error("the file ends early: {expected} expected")]
    Truncated { expected: String },
    #[error("line {line}: {count} {what} announced, more than the file holds (only {} after it)", lines(*room))]
    TooMany {
        line: usize,
        count: u64,
        what: &'static str,
        room: usize,
    },
    #[error("invalid JSON: {0}")]
    Json(String),
    #[error("{0}")]
    Boundary(#[from] BoundaryError),
    #[error("{0}")]
    Graph(#[from] crate::pslg::PslgError),
    #[error("unsupported file type `{0}`")]
    UnknownFormat(String),
    #[error("the mesh is not an all-quad 2D mesh: {0}")]
    NotQuadMesh(String),
    #[error("the mesh is not valid: {0}")]
    InvalidMesh(#[from] MeshCheckError),
}

/// "1 line", "2 lines".
fn lines(n: usize) -> String {
    if n == 1 {
        "1 line".into()
    } else {
        format!("{n} lines")
    }
}

impl From<std::io::Error> for ReadError {
    fn from(e: std::io::Error) -> Self {
        ReadError::Io(e)
    }
}

/// A file that could not be written.
#[derive(Debug, Error)]
pub enum WriteError {
    // `cause`, not `source`: the message already carries it.
    #[error("cannot write {path}: {cause}")]
    Io {
        path: PathBuf,
        cause: std::io::Error,
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

impl MeshFormat {
    /// Renders a mesh with its regions, groups and, when given, 9-node
    /// quads ([`groups`]; an SVG picture is tinted by region).
    pub fn render_labelled(self, l: &groups::Labelled) -> String {
        match self {
            MeshFormat::Msh41 => groups::write_msh41(l),
            MeshFormat::Msh22 => groups::write_msh22(l),
            MeshFormat::Vtk => groups::write_legacy(l),
            MeshFormat::Vtu => groups::write_vtu(l),
            MeshFormat::Abaqus => groups::write_inp(l),
            MeshFormat::Svg => groups::write_svg(l),
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
    write_atomic_all(&[(path, bytes)])
}

/// The temporary name [`write_atomic`] writes `path` to first.
fn temporary(path: &Path) -> PathBuf {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    dir.join(format!(".{name}.{}.tmp", std::process::id()))
}

/// Writes several files all or none: each to a temporary name beside its
/// target first; only when every one is written are they renamed. A
/// failure leaves none of the targets changed (short of a rename failing
/// between two renames in the same folders, when the files renamed so far
/// are removed again).
pub fn write_atomic_all(files: &[(&Path, &[u8])]) -> Result<(), WriteError> {
    let err = |path: &Path, cause| WriteError::Io {
        path: path.to_path_buf(),
        cause,
    };
    let tmps: Vec<PathBuf> = files.iter().map(|(p, _)| temporary(p)).collect();
    let clean = |tmps: &[PathBuf]| {
        for t in tmps {
            let _ = std::fs::remove_file(t);
        }
    };
    for (k, (path, bytes)) in files.iter().enumerate() {
        if let Err(e) = std::fs::write(&tmps[k], bytes) {
            clean(&tmps[..=k]);
            return Err(err(path, e));
        }
    }
    for (k, (path, _)) in files.iter().enumerate() {
        if let Err(e) = std::fs::rename(&tmps[k], path) {
            clean(&tmps[k..]);
            for (done, _) in &files[..k] {
                let _ = std::fs::remove_file(done);
            }
            return Err(err(path, e));
        }
    }
    Ok(())
}

/// The text of a file's bytes as every reader takes it: invalid UTF-8
/// replaced, a leading UTF-8 byte-order mark dropped, and CRLF and old Mac
/// (CR only) line ends made LF (so line numbers count either).
pub fn decode_text(bytes: &[u8]) -> String {
    normalise_text(&String::from_utf8_lossy(bytes)).into_owned()
}

/// [`decode_text`] for text already decoded: the byte-order mark dropped,
/// CRLF and CR made LF. Borrows when there is nothing to change.
pub fn normalise_text(text: &str) -> Cow<'_, str> {
    let t = text.strip_prefix('\u{feff}').unwrap_or(text);
    if t.contains('\r') {
        Cow::Owned(t.replace("\r\n", "\n").replace('\r', "\n"))
    } else {
        Cow::Borrowed(t)
    }
}

/// A piece of a file as a message quotes it: control characters escaped
/// (a message never carries raw bytes of the file to the terminal) and cut
/// to 40 characters.
pub fn quote(s: &str) -> String {
    let mut out = String::new();
    for (k, c) in s.chars().enumerate() {
        if k == 40 {
            out.push('…');
            break;
        }
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// A message that may quote a file (a parser's): control characters
/// escaped, cut to 300 characters.
pub fn quote_long(s: &str) -> String {
    let mut out = one_line(s);
    if let Some((k, _)) = out.char_indices().nth(300) {
        out.truncate(k);
        out.push('…');
    }
    out
}

/// A message made fit for one line of a terminal: every control character
/// (line breaks included) escaped.
pub fn one_line(msg: &str) -> String {
    if !msg.chars().any(char::is_control) {
        return msg.to_string();
    }
    msg.chars()
        .flat_map(|c| {
            let esc: Vec<char> = if c.is_control() {
                c.escape_default().collect()
            } else {
                vec![c]
            };
            esc
        })
        .collect()
}

/// A boundary file's text, and whether it is `.poly` (else `.json`); any
/// other extension is refused.
/// The extensions of the boundary files [`read_boundary`] reads (any
/// case).
const BOUNDARY_EXTENSIONS: [&str; 2] = ["poly", "json"];

/// True for a file named as a boundary [`read_boundary`] reads (`.poly`
/// or `.json`).
pub fn is_boundary_file(path: &Path) -> bool {
    path.extension().is_some_and(|x| {
        BOUNDARY_EXTENSIONS
            .iter()
            .any(|e| x.eq_ignore_ascii_case(e))
    })
}

fn read_boundary_text(path: &Path) -> Result<(bool, String), ReadError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if !BOUNDARY_EXTENSIONS.contains(&ext.as_str()) {
        return Err(ReadError::UnknownFormat(quote(&ext)));
    }
    Ok((ext == "poly", decode_text(&std::fs::read(path)?)))
}

/// Reads a boundary from `.poly` or `.json`, by extension.
pub fn read_boundary(path: &Path) -> Result<Boundary, ReadError> {
    let (poly, text) = read_boundary_text(path)?;
    if poly {
        poly::parse_poly(&text)
    } else {
        boundary_json::parse(&text)
    }
}

/// True for a `.json` file in the regions document form
/// ([`regions_json`]).
pub fn is_regions_document(path: &Path) -> bool {
    matches!(read_boundary_text(path), Ok((false, text)) if regions_json::is_regions(&normalise_text(&text)))
}

/// Reads a boundary file (`.poly` or `.json`, by extension) as a planar
/// straight-line graph: a `.poly` file with its segment markers and
/// regional attributes, a regions document ([`regions_json`]), or a
/// boundary document's loops.
pub fn read_graph(path: &Path) -> Result<crate::pslg::Pslg, ReadError> {
    let (poly, text) = read_boundary_text(path)?;
    if poly {
        poly::parse_pslg(&text)
    } else if regions_json::is_regions(&normalise_text(&text)) {
        regions_json::parse(&text)
    } else {
        Ok(crate::pslg::Pslg::from_boundary(&boundary_json::parse(
            &text,
        )?))
    }
}

/// The graph of a boundary file that is more than one domain's loops: it
/// has region points or segment markers, its segments branch (several
/// faces), or it is a regions document. `Ok(None)` for a file of one
/// domain, which [`read_boundary`] reads as it always has (its errors are
/// that reader's too). The command line and the editor decide with this.
pub fn read_regions(path: &Path) -> Result<Option<crate::pslg::Pslg>, ReadError> {
    if !is_boundary_file(path) {
        return Ok(None);
    }
    let document = is_regions_document(path);
    match read_graph(path) {
        Ok(g) if document || g.has_groups() || !g.is_loops() => Ok(Some(g)),
        Err(e) if document => Err(e),
        _ => Ok(None),
    }
}

/// The loops of a boundary file (`.poly` or `.json`, by extension) as
/// points, not validated as a boundary: the editor opens a file that
/// [`read_boundary`] refuses as a draft to fix. Syntax errors, non-finite
/// coordinates and segments that do not chain into loops are still errors.
pub fn read_boundary_loops(path: &Path) -> Result<Vec<Vec<crate::geom::Point>>, ReadError> {
    let (poly, text) = read_boundary_text(path)?;
    if poly {
        let (points, loops, _) = poly::parse_poly_loops(&text)?;
        Ok(loops
            .iter()
            .map(|l| l.iter().map(|&i| points[i]).collect())
            .collect())
    } else {
        boundary_json::parse_loops(&text)
    }
}

/// Reads a quad mesh file (Gmsh MSH 2.2 or 4.1 ASCII) and checks that it
/// is a valid mesh ([`check`]).
pub fn read_mesh(path: &Path) -> Result<QuadMesh, ReadError> {
    msh::read_msh(&decode_text(&std::fs::read(path)?))
}

/// Formats a float so that it reads back to the same value, the same on
/// every platform: the shortest round-trip decimal, in positional notation
/// for magnitudes in [1e-5, 1e16) and in exponent notation (`1e120`,
/// `-2.5e-7`) outside, which every reader (meshio, Gmsh, VTK, Abaqus)
/// takes; positional notation there would run to hundreds of digits.
pub(crate) fn fmt_f64(out: &mut String, v: f64) {
    let v = if v == 0.0 { 0.0 } else { v }; // no "-0"
    let a = v.abs();
    if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
        // `{}` on f64 prints the shortest string that parses back exactly.
        let _ = write!(out, "{v}");
    } else {
        // `{:e}` prints the shortest round-trip mantissa too.
        let _ = write!(out, "{v:e}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(v: f64) -> String {
        let mut s = String::new();
        fmt_f64(&mut s, v);
        s
    }

    #[test]
    fn floats_round_trip_in_short_notation() {
        assert_eq!(f(0.5), "0.5");
        assert_eq!(f(-0.0), "0");
        assert_eq!(f(1e120), "1e120");
        assert_eq!(f(-2.5e-120), "-2.5e-120");
        assert_eq!(f(123456.75), "123456.75");
        assert_eq!(f(1e16), "1e16");
        assert_eq!(f(9.5e-6), "9.5e-6");
        let mut g = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..20000 {
            g ^= g << 13;
            g ^= g >> 7;
            g ^= g << 17;
            let v = f64::from_bits(g);
            if v.is_finite() {
                let s = f(v);
                assert!(s.len() <= 24, "{s}");
                assert_eq!(s.parse::<f64>().unwrap(), if v == 0.0 { 0.0 } else { v });
            }
        }
    }

    #[test]
    fn text_is_normalised() {
        assert_eq!(
            normalise_text("\u{feff}4 2\r\n1 0 0\r2 1 0\n"),
            "4 2\n1 0 0\n2 1 0\n"
        );
        assert!(matches!(normalise_text("a\nb"), Cow::Borrowed(_)));
        assert_eq!(decode_text(b"\xef\xbb\xbfx\ry"), "x\ny");
        assert_eq!(quote("a\u{1c}b"), "a\\u{1c}b");
        assert_eq!(one_line("a\nb\u{7}"), "a\\nb\\u{7}");
    }
}

//! Opening files as documents: boundaries, drawings, graphs of regions,
//! quad meshes and projects; which files those are.

use super::project::PROJECT_FORMAT;
use super::settings::Settings;
use super::{drawing_size, Document, Replayed};
use crate::app::error::AtPath;
use crate::app::error::EditorError;
use crate::boundary_edit::Draft;
use crate::mesh::QuadMesh;
use crate::{io, Boundary};
use serde::Deserialize;
use std::path::{Path, PathBuf};
use std::sync::Arc;

impl Document {
    /// The shipped example `name` (built into the binary).
    pub fn example(name: &str, settings: Settings) -> Result<Document, EditorError> {
        let text = crate::app::assets::example(name)
            .ok_or(EditorError::UnknownExample(name.to_string()))?;
        let path = PathBuf::from(name);
        if name.ends_with(".dxf") {
            let g = crate::cad::parse_dxf(text).map_err(|cause| EditorError::Drawing {
                path: Some(path.clone()),
                cause,
            })?;
            let sizes = crate::cad::SizeSpec::uniform(drawing_size(&g));
            return Document::from_drawing(g, sizes, None, name, settings);
        }
        if name.ends_with(".json") {
            let graph = io::regions_json::parse(text).at(&path)?;
            return Document::from_graph(graph, None, name, settings);
        }
        let (points, loops, _) = io::poly::parse_poly_loops(text).at(&path)?;
        let draft = Draft {
            loops: loops
                .iter()
                .map(|l| l.iter().map(|&i| points[i]).collect())
                .collect(),
        };
        Document::from_draft(draft, None, name, settings)
    }

    /// A document over the boundary of a quad mesh, showing that mesh.
    pub fn from_mesh(
        mesh: QuadMesh,
        path: &Path,
        settings: Settings,
    ) -> Result<Document, EditorError> {
        mesh.check_invariants(true)
            .map_err(|cause| EditorError::MeshFile {
                path: path.to_path_buf(),
                cause,
            })?;
        let nb = mesh.n_boundary();
        let loops = mesh
            .loops
            .iter()
            .map(|l| l.iter().map(|&v| v as usize).collect())
            .collect();
        let boundary = Boundary::new(mesh.nodes[..nb].to_vec(), loops, None).map_err(|cause| {
            EditorError::MeshBoundary {
                path: path.to_path_buf(),
                cause,
            }
        })?;
        let mut doc = Document::new(boundary, Some(path.to_path_buf()), settings)?;
        if let Some(m) = doc.meshing.as_mut() {
            m.imported = Some(Arc::new(mesh));
        }
        Ok(doc)
    }

    /// Opens a boundary file (`.poly`, `.json`: a boundary that is not
    /// valid opens as a draft to fix, its problem shown), a project
    /// (with what its steps put in the history), or a quad mesh (`.msh`,
    /// `.msh22`: its boundary, with the mesh shown).
    pub fn open(path: &Path, settings: Settings) -> Result<(Document, Vec<Replayed>), EditorError> {
        if is_project(path) {
            return Document::open_project(path);
        }
        if is_mesh_file(path) {
            let m = io::read_mesh(path).at(path)?;
            return Ok((Document::from_mesh(m, path, settings)?, Vec::new()));
        }
        if is_drawing(path) {
            let failed = |cause| EditorError::Drawing {
                path: Some(path.to_path_buf()),
                cause,
            };
            // A geometry file (JSON) may carry its target size, its local
            // sizes and its gradation: the command line's (`quadex mesh`).
            let (g, sizes) = if crate::cad::is_geometry_file(path) {
                let d = crate::cad::read_geometry_json(path).map_err(failed)?;
                let size = d.size.unwrap_or_else(|| drawing_size(&d.geometry));
                let sizes = d.spec(Some(size), None, &[], &[]);
                (d.geometry, sizes)
            } else {
                (crate::cad::read_dxf(path).map_err(failed)?, None)
            };
            let sizes = sizes.unwrap_or_else(|| crate::cad::SizeSpec::uniform(drawing_size(&g)));
            let doc = Document::from_drawing(
                g,
                sizes,
                Some(path.to_path_buf()),
                &file_name(path),
                settings,
            )?;
            return Ok((doc, Vec::new()));
        }
        // A graph that cannot be meshed opens as a document of regions
        // to fix when it names groups or regions (or is a regions
        // document); otherwise it is read as one domain's loops, whose
        // reader says what is wrong (an open chain, say), as before.
        let graph = io::read_regions(path)
            .at(path)?
            .filter(|g| g.has_groups() || io::is_regions_document(path) || g.faces().is_ok());
        if let Some(graph) = graph {
            let doc =
                Document::from_graph(graph, Some(path.to_path_buf()), &file_name(path), settings)?;
            return Ok((doc, Vec::new()));
        }
        let loops = io::read_boundary_loops(path).at(path)?;
        let doc = Document::from_draft(
            Draft { loops },
            Some(path.to_path_buf()),
            &file_name(path),
            settings,
        )?;
        Ok((doc, Vec::new()))
    }
}

/// The file name of `path`, for titles and sample sources.
pub fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// True for a file named as a quad mesh (`.msh`, `.msh22`, `.msh2`).
pub fn is_mesh_file(path: &Path) -> bool {
    matches!(
        io::MeshFormat::from_path(path),
        Ok(io::MeshFormat::Msh41 | io::MeshFormat::Msh22)
    )
}

/// True for a file named as one [`Document::open`] reads: a boundary
/// ([`io::is_boundary_file`]; a project is a `.json` too) or a quad mesh
/// ([`is_mesh_file`]). An export to `.vtk`, `.vtu`, `.inp` or `.svg` is
/// not one.
pub fn opens(path: &Path) -> bool {
    io::is_boundary_file(path) || is_mesh_file(path) || is_drawing(path)
}

/// True for a drawing (`.dxf`, or a JSON geometry file of curves).
pub fn is_drawing(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("dxf"))
        || crate::cad::is_geometry_file(path)
}

/// True for a JSON file whose `format` is a project's.
pub fn is_project(path: &Path) -> bool {
    #[derive(Deserialize)]
    struct Format {
        format: Option<String>,
    }
    let json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    json && std::fs::read(path)
        .ok()
        .and_then(|t| serde_json::from_str::<Format>(&io::decode_text(&t)).ok())
        .and_then(|f| f.format)
        .is_some_and(|f| f == PROJECT_FORMAT)
}

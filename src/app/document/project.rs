//! The project file (the whole document in one JSON file) and the
//! boundary written on its own.

use super::models::ModelInfo;
use super::open::file_name;
use super::settings::Settings;
use super::{Document, Meshing, Replayed};
use crate::app::error::AtPath;
use crate::app::error::{EditorError, ProjectError};
use crate::app::framed::Framed;
use crate::app::regions::Regions;
use crate::boundary::BoundaryError;
use crate::boundary_edit::Draft;
use crate::extract::Action;
use crate::geom::Point;
use crate::io::boundary_json::BoundaryDoc;
use crate::mesh::QuadMesh;
use crate::model::fitted::FittedModel;
use crate::model::ModelFile;
use crate::samples::TrainingSet;
use crate::{io, Boundary};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A project file: the whole document in one JSON file. The mesh is kept
/// both as the actions that built it (replayed on opening, so stepping and
/// undo carry on) and as nodes and quads for other readers. A document
/// whose boundary is not valid yet is saved with its loops as they are and
/// opens as that draft again.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Project {
    pub format: String,
    pub version: u32,
    pub boundary: BoundaryDoc,
    pub settings: Settings,
    pub actions: Vec<Action>,
    /// Models set by refits, with the steps taken before each.
    pub refits: Vec<(usize, FittedModel)>,
    /// The document's refitted models (see [`Document::models`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub models: Vec<ModelFile>,
    /// The model the run started with, when it is not the one chosen now
    /// (a refit chose another).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_model: Option<String>,
    pub training: TrainingSet,
    /// The mesh as stepped (not smoothed).
    pub mesh: QuadMesh,
    /// A mesh read from a file over the same boundary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub imported: Option<QuadMesh>,
    /// A document of several regions: its graph with the regions' and
    /// groups' names (the faces are meshed again when it opens).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub regions: Option<io::regions_json::RegionsDoc>,
}

/// The `format` field of a project file.
pub const PROJECT_FORMAT: &str = "quadex-project";

/// The `version` a project is saved with. Version 2 records its actions in
/// the frame the mesher runs in (the boundary moved next to the origin, as
/// the command line meshes it, [`Framed`]); version 1 recorded them in the
/// boundary's own coordinates, and is replayed there.
pub const PROJECT_VERSION: u32 = 2;

impl Document {
    /// The document as a project.
    pub fn project(&self) -> Project {
        Project {
            format: PROJECT_FORMAT.into(),
            // A version-1 project replayed in the boundary's own frame
            // goes on in it, and is saved as version 1 again.
            version: match &self.meshing {
                Some(m) if m.mesher.origin() != m.boundary.local_origin() => 1,
                _ => PROJECT_VERSION,
            },
            boundary: self.boundary_doc(),
            settings: self.settings.clone(),
            actions: self
                .mesher()
                .map(|m| m.actions().to_vec())
                .unwrap_or_default(),
            refits: self.refits().to_vec(),
            models: self.models.clone(),
            start_model: self
                .meshing
                .as_ref()
                .map(|m| m.start.clone())
                .filter(|m| *m != self.settings.model),
            training: self.training.clone(),
            mesh: self.mesher().map(|m| m.mesh().clone()).unwrap_or_default(),
            imported: self
                .meshing
                .as_ref()
                .and_then(|m| m.imported.as_deref().cloned()),
            regions: self
                .regions
                .as_ref()
                .map(|r| io::regions_json::RegionsDoc::from_pslg(&r.graph)),
        }
    }

    /// Saves the document as a project file (written whole or not at all).
    pub fn save_project(&self, path: &Path) -> Result<(), EditorError> {
        let json = serde_json::to_string(&self.project()).map_err(|cause| EditorError::Encode {
            path: path.to_path_buf(),
            cause,
        })?;
        io::write_atomic(path, json.as_bytes())?;
        Ok(())
    }

    /// A document from a project: the boundary checked, the actions
    /// replayed with the refitted models set where they were; also what
    /// the replay puts in the history (runs of steps, and the document
    /// before each refit), so that undo carries on.
    pub fn from_project(
        p: Project,
        source: Option<PathBuf>,
    ) -> Result<(Document, Vec<Replayed>), ProjectError> {
        if p.format != PROJECT_FORMAT {
            return Err(ProjectError::Format(p.format));
        }
        let name = source
            .as_deref()
            .map(file_name)
            .unwrap_or_else(|| "untitled".into());
        if let Some(r) = &p.regions {
            let graph = r.to_pslg().map_err(ProjectError::Regions)?;
            let mut doc = Document::empty(p.settings.clone());
            doc.models = p.models;
            doc.training = p.training;
            doc.problem = None;
            doc.regions = Some(Regions::new(graph, &doc.settings, &doc.models).map_err(
                |e| match e {
                    EditorError::Model { cause, .. } => ProjectError::Model(cause),
                    other => ProjectError::Start(Box::new(other)),
                },
            )?);
            doc.source = source;
            doc.name = name;
            return Ok((doc, Vec::new()));
        }
        let loops: Vec<Vec<Point>> = p
            .boundary
            .loops
            .iter()
            .map(|l| l.iter().map(|&[x, y]| Point::new(x, y)).collect())
            .collect();
        let draft = Draft { loops };
        // The run replays from the model it started with; the model chosen
        // now (a refitted one) is set back after.
        let chosen = p.settings.model.clone();
        let mut settings = p.settings;
        if let Some(m) = p.start_model {
            settings.model = m;
        }
        let mut doc = Document::empty(settings);
        doc.models = p.models;
        doc.source = source;
        doc.name = name;
        doc.set_draft(draft).map_err(|e| match e {
            EditorError::Model { cause, .. } => ProjectError::Model(cause),
            other => ProjectError::Start(Box::new(other)),
        })?;
        doc.boundary_edited = false;
        doc.training = p.training;
        let mut replayed = Vec::new();
        let Some(mut meshing) = doc.meshing.take() else {
            // A draft: nothing was stepped.
            doc.settings.model = chosen;
            return match (&doc.problem, p.actions.is_empty()) {
                (Some(e), false) => Err(ProjectError::Boundary(e.clone())),
                _ => Ok((doc, replayed)),
            };
        };
        if p.version < 2 {
            let m = &meshing.mesher;
            meshing.mesher = Framed::unmoved(
                meshing.boundary.clone(),
                m.model().clone(),
                m.params().clone(),
            );
        }
        // The document as it is before a refit (the rest of `doc` holds no
        // mesh while replaying, so the copy is the mesher's).
        let snapshot = |meshing: &Meshing, doc: &Document| {
            Replayed::Refit(Box::new(Document {
                meshing: Some(meshing.clone()),
                ..doc.clone()
            }))
        };
        let mut refits = p.refits.into_iter().peekable();
        let mut run = 0;
        for (i, a) in p.actions.iter().enumerate() {
            while let Some((_, m)) = refits.next_if(|(at, _)| *at <= i) {
                if run > 0 {
                    replayed.push(Replayed::Steps(std::mem::take(&mut run)));
                }
                replayed.push(snapshot(&meshing, &doc));
                meshing.mesher.set_model(Arc::new(m.clone()));
                meshing.refits.push((meshing.mesher.steps(), m));
            }
            meshing.last = meshing
                .mesher
                .take(a)
                .map_err(|cause| ProjectError::Replay { step: i + 1, cause })?;
            run += 1;
        }
        if run > 0 {
            replayed.push(Replayed::Steps(run));
        }
        for (_, m) in refits {
            replayed.push(snapshot(&meshing, &doc));
            meshing.mesher.set_model(Arc::new(m.clone()));
            meshing.refits.push((meshing.mesher.steps(), m));
        }
        if let Some((_, m)) = meshing.refits.last() {
            meshing.info = doc
                .model_file(&m.name)
                .map(ModelInfo::of_file)
                .unwrap_or_else(|| ModelInfo {
                    name: m.name.clone(),
                    form: m.coefficients.form().name().into(),
                    samples: None,
                    corrections: m.memory.len(),
                });
        }
        doc.settings.model = chosen;
        if meshing.mesher.mesh() != &p.mesh {
            return Err(ProjectError::MeshDiffers);
        }
        if let Some(m) = p.imported {
            m.check_invariants(true).map_err(ProjectError::Imported)?;
            meshing.imported = Some(Arc::new(m));
        }
        doc.meshing = Some(meshing);
        Ok((doc, replayed))
    }

    /// Opens a project file.
    pub fn open_project(path: &Path) -> Result<(Document, Vec<Replayed>), EditorError> {
        let bytes = std::fs::read(path).map_err(ProjectError::Io).at(path)?;
        let text = io::decode_text(&bytes);
        let p: Project = serde_json::from_str(&text)
            .map_err(ProjectError::Json)
            .at(path)?;
        Document::from_project(p, Some(path.to_path_buf())).at(path)
    }

    /// Writes the boundary as `.poly` (a valid boundary) or `.json` (the
    /// loops as they are, valid or not).
    pub fn save_boundary(&self, path: &Path) -> Result<(), EditorError> {
        let json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        if let Some(r) = &self.regions {
            // A regions document keeps the names; `.poly` keeps the
            // segment markers and region attributes (tags) only.
            let text = if json {
                serde_json::to_string_pretty(&io::regions_json::RegionsDoc::from_pslg(&r.graph))
                    .map_err(|cause| EditorError::Encode {
                        path: path.to_path_buf(),
                        cause,
                    })?
            } else {
                io::poly::write_pslg(&r.graph)
            };
            io::write_atomic(path, text.as_bytes())?;
            return Ok(());
        }
        let text = if json {
            serde_json::to_string_pretty(&self.boundary_doc()).map_err(|cause| {
                EditorError::Encode {
                    path: path.to_path_buf(),
                    cause,
                }
            })?
        } else {
            match self.boundary() {
                Some(b) => io::poly::write_poly(b),
                None => {
                    return Err(EditorError::NoBoundary(
                        self.problem.clone().unwrap_or(BoundaryError::Empty),
                    ))
                }
            }
        };
        io::write_atomic(path, text.as_bytes())?;
        Ok(())
    }

    /// The boundary (or the draft's loops) as a boundary document.
    fn boundary_doc(&self) -> BoundaryDoc {
        match self.boundary() {
            Some(b) => boundary_doc_numbered(b, &self.name),
            None => BoundaryDoc {
                format: "quadex-boundary".into(),
                version: 1,
                name: self.name.clone(),
                loops: self
                    .draft
                    .loops
                    .iter()
                    .map(|l| l.iter().map(|p| p.to_array()).collect())
                    .collect(),
            },
        }
    }
}

/// `b` as a boundary document whose loops list the points in `b`'s own
/// numbering (each loop's points as they are numbered, the loops in the
/// order of their numbers), so that reading it back numbers every node
/// as `b` does and a project's steps replay onto the same nodes.
/// (`BoundaryDoc::from_boundary` lists each loop in its traversal order,
/// which for a loop the validation turned around numbers it anew.) A
/// boundary whose loops are not runs of consecutive numbers is written
/// in traversal order.
fn boundary_doc_numbered(b: &Boundary, name: &str) -> BoundaryDoc {
    let mut runs: Vec<(usize, usize)> = b
        .loops
        .iter()
        .map(|l| {
            let lo = l.iter().copied().min().unwrap_or(0);
            let hi = l.iter().copied().max().map_or(0, |m| m + 1);
            (lo, hi)
        })
        .collect();
    runs.sort_unstable();
    let consecutive = b.loops.iter().all(|l| {
        let (lo, hi) = (
            l.iter().copied().min().unwrap_or(0),
            l.iter().copied().max().map_or(0, |m| m + 1),
        );
        hi - lo == l.len()
    }) && runs.first().is_some_and(|r| r.0 == 0)
        && runs.windows(2).all(|w| w[0].1 == w[1].0)
        && runs.last().is_some_and(|r| r.1 == b.points.len());
    if !consecutive {
        return BoundaryDoc::from_boundary(b, name);
    }
    BoundaryDoc {
        loops: runs
            .iter()
            .map(|&(lo, hi)| b.points[lo..hi].iter().map(|p| p.to_array()).collect())
            .collect(),
        ..BoundaryDoc::from_boundary(b, name)
    }
}

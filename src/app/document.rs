//! The editor's document: the boundary, the mesher stepping over it with
//! the chosen model and settings, the last step's report, the training set
//! the user's corrections go to, and the models refits made. A document is
//! saved whole as a project file ([`Project`]). Everything here goes
//! through the core's public API (`Mesher`, `model::load`, `fit`, `io`).

use crate::cleanup::CleanupParams;
use crate::extract::{
    Action, Correction, MeshParams, Mesher, StepKind, StepOutcome, StepReport, Strategy,
};
use crate::fit::{self, Figures, FitParams, TypeFigures};
use crate::io;
use crate::io::boundary_json::BoundaryDoc;
use crate::mesh::QuadMesh;
use crate::model;
use crate::model::fitted::FittedModel;
use crate::model::Form;
use crate::pipeline::FinishParams;
use crate::remesh::RemeshParams;
use crate::samples::CollectParams;
use crate::samples::TrainingSet;
use crate::smooth::SmoothParams;
use crate::Boundary;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What the user chose to mesh with.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Settings {
    /// `default`, `rules`, `thesis` or a model file.
    pub model: String,
    pub strategy: Strategy,
    /// Input points: 5, 7, 9 or 11.
    pub points: usize,
    pub pure_model: bool,
    /// See [`MeshParams::fill_after_layers`].
    pub fill_after_layers: Option<u32>,
    /// Smoothing of the finished mesh.
    pub smooth: SmoothParams,
    /// Topological cleanup of the finished mesh.
    pub cleanup: CleanupParams,
    /// Local remeshing of the finished mesh's bad regions.
    pub remesh: RemeshParams,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            model: "default".into(),
            strategy: Strategy::B,
            points: 7,
            pure_model: false,
            fill_after_layers: MeshParams::DEFAULT.fill_after_layers,
            smooth: FinishParams::DEFAULT.smooth,
            cleanup: FinishParams::DEFAULT.cleanup,
            remesh: FinishParams::DEFAULT.remesh,
        }
    }
}

impl Settings {
    fn params(&self) -> MeshParams {
        MeshParams {
            strategy: self.strategy,
            leading_points: (self.points - 1) / 2,
            pure_model: self.pure_model,
            fill_after_layers: self.fill_after_layers,
            ..MeshParams::DEFAULT
        }
    }

    /// What finishing the mesh does.
    pub fn finishing(&self) -> FinishParams {
        FinishParams {
            cleanup: self.cleanup,
            remesh: self.remesh,
            smooth: self.smooth,
        }
    }
}

/// The boundary being meshed and the state of its mesh. Cloning is what
/// the editor's undo keeps; the reference samples are shared.
#[derive(Clone)]
pub struct Document {
    pub boundary: Boundary,
    /// The file the boundary came from.
    pub source: Option<PathBuf>,
    pub settings: Settings,
    pub mesher: Mesher,
    /// The report of the last step taken (cleared by undo and reset).
    pub last: Option<StepReport>,
    /// Samples from accepted and corrected elements.
    pub training: TrainingSet,
    /// Models set by refits, with the number of steps taken before each.
    pub refits: Vec<(usize, FittedModel)>,
    /// The reference meshes' samples a refit starts from (loaded at the
    /// first refit).
    base: Option<Arc<TrainingSet>>,
    /// A mesh read from a file (`.msh`), its boundary being the document's
    /// boundary: shown, checked and exported as the document's mesh until
    /// the boundary is stepped.
    imported: Option<Arc<QuadMesh>>,
}

/// Figures of the model before and after a refit, on the same samples.
#[derive(Clone, Debug, PartialEq)]
pub struct RefitFigures {
    pub samples: usize,
    pub corrections: usize,
    pub before: (TypeFigures, Figures, Figures),
    pub after: (TypeFigures, Figures, Figures),
}

impl Document {
    /// A fresh document over `boundary`; fails when the model cannot be
    /// loaded.
    pub fn new(
        boundary: Boundary,
        source: Option<PathBuf>,
        settings: Settings,
    ) -> Result<Document, String> {
        let mesher = Self::mesher(&boundary, &settings)?;
        Ok(Document {
            boundary,
            source,
            training: TrainingSet::new(settings.points),
            settings,
            mesher,
            last: None,
            refits: Vec::new(),
            base: None,
            imported: None,
        })
    }

    /// A document over the boundary of a quad mesh, showing that mesh.
    pub fn from_mesh(
        mesh: QuadMesh,
        source: Option<PathBuf>,
        settings: Settings,
    ) -> Result<Document, String> {
        mesh.check_invariants(true).map_err(|e| e.to_string())?;
        let nb = mesh.n_boundary();
        let loops = mesh
            .loops
            .iter()
            .map(|l| l.iter().map(|&v| v as usize).collect())
            .collect();
        let boundary = Boundary::new(mesh.nodes[..nb].to_vec(), loops, None)
            .map_err(|e| format!("its boundary: {e}"))?;
        let mut doc = Document::new(boundary, source, settings)?;
        doc.imported = Some(Arc::new(mesh));
        Ok(doc)
    }

    /// The mesh read from a file, while it is what the document shows (no
    /// step taken on its boundary yet).
    pub fn imported(&self) -> Option<&QuadMesh> {
        self.imported
            .as_deref()
            .filter(|_| self.mesher.steps() == 0)
    }

    /// True when there is a complete mesh to show and export: the run is
    /// complete, or a mesh read from a file is shown.
    pub fn has_mesh(&self) -> bool {
        self.is_done() || self.imported().is_some()
    }

    fn mesher(boundary: &Boundary, settings: &Settings) -> Result<Mesher, String> {
        let m = model::load(&settings.model).map_err(|e| format!("{}: {e}", settings.model))?;
        Ok(Mesher::new(
            boundary.clone(),
            Arc::from(m),
            settings.params(),
        ))
    }

    /// Opens a boundary file (`.poly`, `.json`), a project, or a quad mesh
    /// (`.msh`, `.msh22`: its boundary, with the mesh shown); the message
    /// names the file and the problem.
    pub fn open(path: &Path, settings: Settings) -> Result<Document, String> {
        if is_project(path) {
            return Document::open_project(path);
        }
        if is_mesh_file(path) {
            let m = io::read_mesh(path).map_err(|e| format!("{}: {e}", path.display()))?;
            return Document::from_mesh(m, Some(path.to_path_buf()), settings)
                .map_err(|e| format!("{}: {e}", path.display()));
        }
        let b = io::read_boundary(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Document::new(b, Some(path.to_path_buf()), settings)
    }

    /// The document's name for the title bar.
    pub fn name(&self) -> String {
        self.source
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_else(|| "untitled".into())
    }

    /// One step; `Ok(false)` when the mesh is already complete.
    pub fn step(&mut self) -> Result<bool, String> {
        match self.mesher.step().map_err(|e| e.to_string())? {
            StepOutcome::Stepped(r) => {
                self.last = Some(*r);
                Ok(true)
            }
            StepOutcome::Done => Ok(false),
        }
    }

    pub fn undo(&mut self) -> bool {
        self.last = None;
        self.mesher.undo()
    }

    /// Takes the last undone step again; `Ok(false)` when there is none.
    pub fn redo(&mut self) -> Result<bool, String> {
        match self.mesher.redo().map_err(|e| e.to_string())? {
            Some(r) => {
                self.last = Some(r);
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// A fresh mesh: no steps, no last report, no refitted models.
    fn restart(&mut self, mesher: Mesher) {
        self.mesher = mesher;
        self.last = None;
        self.refits.clear();
    }

    /// Starts the mesh again with the current settings.
    pub fn reset(&mut self) -> Result<(), String> {
        let mesher = Self::mesher(&self.boundary, &self.settings)?;
        self.restart(mesher);
        Ok(())
    }

    /// A new boundary (edited in the editor); the mesh starts again.
    pub fn set_boundary(&mut self, boundary: Boundary) -> Result<(), String> {
        let mesher = Self::mesher(&boundary, &self.settings)?;
        self.boundary = boundary;
        self.restart(mesher);
        Ok(())
    }

    /// Changes the settings and starts again (unless only cleanup and
    /// smoothing changed: they apply to the finished mesh); returns whether
    /// the mesh restarted. On failure nothing changes.
    pub fn set_settings(&mut self, settings: Settings) -> Result<bool, String> {
        let finishing_only = Settings {
            smooth: self.settings.smooth,
            cleanup: self.settings.cleanup,
            remesh: self.settings.remesh,
            ..settings.clone()
        } == self.settings;
        if finishing_only {
            // Cleanup and smoothing act on the finished mesh only.
            self.settings = settings;
            return Ok(false);
        }
        let mesher = Self::mesher(&self.boundary, &settings)?;
        self.settings = settings;
        self.restart(mesher);
        Ok(true)
    }

    /// Appends the sample of the last step (an element the user accepts).
    pub fn append_last(&mut self) -> Result<usize, String> {
        let r = self.last.as_ref().ok_or("no step to take a sample from")?;
        let s = self
            .mesher
            .sample_of(r)
            .ok_or("the last step is not an element")?;
        self.push_sample(s)
    }

    fn push_sample(&mut self, s: crate::samples::Sample) -> Result<usize, String> {
        if self.training.points != 2 * s.n() + 1 {
            self.training = TrainingSet::new(2 * s.n() + 1);
        }
        self.training.push(s).map_err(|e| e.to_string())?;
        Ok(self.training.len())
    }

    /// Replaces the last element by the user's (type 0 closes onto front
    /// node `snap_to` when given): the step is undone, the correction
    /// committed at the same reference point, and its sample appended. If the correction is not a valid element, nothing changes.
    pub fn correct_last(
        &mut self,
        element_type: crate::model::ElementType,
        pn: crate::geom::Point,
        snap_to: Option<u32>,
    ) -> Result<usize, String> {
        let r = self.last.clone().ok_or("no step to correct")?;
        if !matches!(r.kind, StepKind::Element | StepKind::Correction) {
            return Err("only an element step can be corrected".into());
        }
        let reference = r.reference.ok_or("the last step has no reference point")?;
        let c = Correction {
            reference,
            element_type,
            pn: Some(pn),
            snap_to,
        };
        let saved = self.mesher.clone();
        self.mesher.undo();
        match self.mesher.correct(&c) {
            Ok(report) => {
                let sample = self.mesher.sample_of(&report);
                self.last = Some(report);
                match sample {
                    Some(s) => self.push_sample(s),
                    None => Ok(self.training.len()),
                }
            }
            Err(e) => {
                // Leave the mesh as it was.
                self.mesher = saved;
                Err(e.to_string())
            }
        }
    }

    /// The reference meshes' samples at the current input points (the
    /// method's defaults), loaded once.
    pub fn base_set(&mut self) -> Result<Arc<TrainingSet>, String> {
        let points = self.training.points;
        if self.base.as_ref().is_none_or(|b| b.points != points) {
            let meshes = crate::reference::read_shipped().map_err(|e| e.to_string())?;
            self.base = Some(Arc::new(TrainingSet::collect(
                &meshes,
                points,
                &CollectParams::DEFAULT,
            )));
        }
        self.base
            .clone()
            .ok_or_else(|| "no reference samples".into())
    }

    /// The reference samples and the user's, as a refit sees them.
    pub fn refit_set(&mut self) -> Result<TrainingSet, String> {
        let mut set = (*self.base_set()?).clone();
        set.merge(self.training.clone())
            .map_err(|e| e.to_string())?;
        Ok(set)
    }

    /// Refits a model of `form` on the reference samples plus the user's,
    /// meshes the rest of the mesh with it, and returns the figures of the
    /// old and the new model on those samples.
    pub fn refit(&mut self, form: Form) -> Result<RefitFigures, String> {
        let corrections = self.training.len();
        let set = self.refit_set()?;
        let params = FitParams {
            folds: 0,
            ..FitParams::DEFAULT
        };
        let before =
            fit::evaluate(self.mesher.model().as_ref(), &set).map_err(|e| e.to_string())?;
        let model = fit::refit(&set, form, &params).map_err(|e| e.to_string())?;
        let after = fit::evaluate(&model, &set).map_err(|e| e.to_string())?;
        self.mesher.set_model(Arc::new(model.clone()));
        self.refits.push((self.mesher.steps(), model));
        Ok(RefitFigures {
            samples: set.len(),
            corrections,
            before,
            after,
        })
    }

    pub fn is_done(&self) -> bool {
        self.mesher.is_done()
    }

    /// The finished mesh (smoothed and checked), for export.
    pub fn finished(&self) -> Result<QuadMesh, String> {
        if let Some(m) = self.imported() {
            return Ok(m.clone());
        }
        if !self.is_done() {
            return Err("the mesh is not finished: run to the end first".into());
        }
        crate::pipeline::finish(&self.mesher, &self.settings.finishing()).map_err(|e| e.to_string())
    }
}

/// A training-set edit from the editor's Training set panel.
impl Document {
    /// Drops the user's samples at `indices` (positions in the set);
    /// returns how many are left.
    pub fn delete_samples(&mut self, indices: &[usize]) -> usize {
        let drop: std::collections::BTreeSet<usize> = indices.iter().copied().collect();
        let mut k = 0;
        self.training.samples.retain(|_| {
            k += 1;
            !drop.contains(&(k - 1))
        });
        self.training.len()
    }

    /// Appends the samples of a CSV or JSON training-set file (the input
    /// points must match the set's, unless the set is empty); returns how
    /// many were added.
    pub fn import_samples(&mut self, path: &Path) -> Result<usize, String> {
        let set = TrainingSet::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        self.add_samples(set)
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    fn add_samples(&mut self, set: TrainingSet) -> Result<usize, String> {
        let n = set.len();
        if self.training.is_empty() {
            self.training = set;
        } else {
            self.training.merge(set).map_err(|e| e.to_string())?;
        }
        Ok(n)
    }

    /// Writes the user's samples (CSV, or JSON for a `.json` path).
    pub fn export_samples(&self, path: &Path) -> Result<(), String> {
        self.training
            .write(path)
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Collects samples from a finished mesh (the current one, or a mesh
    /// file) at the set's input points and appends them; returns how many.
    pub fn collect_samples(&mut self, name: &str, mesh: QuadMesh) -> Result<usize, String> {
        let set = TrainingSet::collect(
            &[(name.to_string(), mesh)],
            self.training.points,
            &CollectParams::DEFAULT,
        );
        self.add_samples(set)
    }

    /// Collects from a quad mesh file (`.msh`).
    pub fn collect_from_file(&mut self, path: &Path) -> Result<usize, String> {
        let mesh = io::read_mesh(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let name = path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        self.collect_samples(&name, mesh)
    }
}

/// A project file: the whole document in one JSON file. The mesh is kept
/// both as the actions that built it (replayed on opening, so stepping and
/// undo carry on) and as nodes and quads for other readers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Project {
    pub format: String,
    pub version: u32,
    pub boundary: BoundaryDoc,
    pub settings: Settings,
    pub actions: Vec<Action>,
    /// Models set by refits, with the steps taken before each.
    pub refits: Vec<(usize, FittedModel)>,
    pub training: TrainingSet,
    /// The mesh as stepped (not smoothed).
    pub mesh: QuadMesh,
    /// A mesh read from a file over the same boundary.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub imported: Option<QuadMesh>,
}

/// The `format` field of a project file.
pub const PROJECT_FORMAT: &str = "quadex-project";

impl Document {
    /// The document as a project.
    pub fn project(&self) -> Project {
        Project {
            format: PROJECT_FORMAT.into(),
            version: 1,
            boundary: BoundaryDoc::from_boundary(&self.boundary, &self.name()),
            settings: self.settings.clone(),
            actions: self.mesher.actions().to_vec(),
            refits: self.refits.clone(),
            training: self.training.clone(),
            mesh: self.mesher.mesh().clone(),
            imported: self.imported.as_deref().cloned(),
        }
    }

    /// Saves the document as a project file (written whole or not at all).
    pub fn save_project(&self, path: &Path) -> Result<(), String> {
        let json = serde_json::to_string(&self.project()).map_err(|e| e.to_string())?;
        io::write_atomic(path, json.as_bytes()).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// A document from a project: the boundary checked, the actions
    /// replayed with the refitted models set where they were.
    pub fn from_project(p: Project, source: Option<PathBuf>) -> Result<Document, String> {
        if p.format != PROJECT_FORMAT {
            return Err(format!("not a quadex project (format \"{}\")", p.format));
        }
        let boundary = p.boundary.to_boundary().map_err(|e| e.to_string())?;
        let mut doc = Document::new(boundary, source, p.settings)?;
        let mut refits = p.refits.into_iter().peekable();
        for (i, a) in p.actions.iter().enumerate() {
            while let Some((_, m)) = refits.next_if(|(at, _)| *at <= i) {
                doc.set_refit(m);
            }
            doc.last = doc
                .mesher
                .take(a)
                .map_err(|e| format!("step {} of the project does not replay: {e}", i + 1))?;
        }
        for (_, m) in refits {
            doc.set_refit(m);
        }
        if doc.mesher.mesh() != &p.mesh {
            return Err("the project's mesh differs from its replayed steps".into());
        }
        doc.training = p.training;
        if let Some(m) = p.imported {
            m.check_invariants(true)
                .map_err(|e| format!("the project's imported mesh: {e}"))?;
            doc.imported = Some(Arc::new(m));
        }
        Ok(doc)
    }

    fn set_refit(&mut self, m: FittedModel) {
        self.mesher.set_model(Arc::new(m.clone()));
        self.refits.push((self.mesher.steps(), m));
    }

    /// Opens a project file.
    pub fn open_project(path: &Path) -> Result<Document, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let p: Project =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        Document::from_project(p, Some(path.to_path_buf()))
            .map_err(|e| format!("{}: {e}", path.display()))
    }
}

/// True for a file named as a quad mesh (`.msh`, `.msh22`, `.msh2`).
pub fn is_mesh_file(path: &Path) -> bool {
    matches!(
        io::MeshFormat::from_path(path),
        Ok(io::MeshFormat::Msh41 | io::MeshFormat::Msh22)
    )
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
    json && std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<Format>(&t).ok())
        .and_then(|f| f.format)
        .is_some_and(|f| f == PROJECT_FORMAT)
}

//! The editor's document: the boundary as the user draws, reads and edits
//! it (a [`Draft`], valid or not), and once it is a valid boundary the
//! mesher stepping over it ([`Meshing`]) with the chosen model and
//! settings, the last step's report and the models refits made; the
//! training set the user's corrections go to. A document is saved whole
//! as a project file ([`Project`]). Everything here goes through the
//! core's public API (`Mesher`, `model::load`, `fit`, `io`).
//!
//! Here: the document and its edits. Beside it: `settings` (what the user
//! meshes with), `models` (the models a document meshes with, built-in
//! ones loaded once), `open` (files opened as documents), `project` (the
//! project file and the boundary written), `samples` (the user's training
//! samples), `correct` (the last element corrected), `refit` (a refit's
//! work and figures) and `fit_cache` (the process-wide caches of global
//! fits and reference samples).

use super::error::EditorError;
use super::framed::Framed;
use super::regions::Regions;
use crate::boundary::BoundaryError;
use crate::boundary_edit::Draft;
use crate::extract::{Action, StepKind, StepOutcome, StepReport};
use crate::io;
use crate::mesh::QuadMesh;
use crate::model::fitted::FittedModel;
use crate::model::ModelFile;
use crate::pslg::Pslg;
use crate::regions::RegionMesh;
use crate::samples::TrainingSet;
use crate::Boundary;
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod correct;
mod fit_cache;
mod models;
mod open;
mod project;
mod refit;
mod samples;
mod settings;

pub use correct::Target;
pub use fit_cache::reference_samples;
pub use models::{load_model, ModelInfo};
pub use open::{file_name, is_drawing, is_mesh_file, is_project, opens};
pub use project::{Project, PROJECT_FORMAT, PROJECT_VERSION};
pub use refit::{
    refit_set_of, CorrectionCheck, RefitDone, RefitFigures, RefitPhase, RefitTask, COMPARE_NODES,
    REPRODUCED, WORSE_MEMORY_SHARE,
};
pub use settings::Settings;

/// The mesh being made over a valid boundary.
#[derive(Clone)]
pub struct Meshing {
    pub boundary: Boundary,
    /// The mesher, run in the command line's frame.
    pub mesher: Framed,
    /// The report of the last step taken (after undo: of the step now
    /// last, so that it can be corrected).
    pub last: Option<StepReport>,
    /// Models set by refits, with the number of steps taken before each.
    pub refits: Vec<(usize, FittedModel)>,
    /// A mesh read from a file (`.msh`), its boundary being this one:
    /// shown, checked and exported as the document's mesh until the
    /// boundary is stepped.
    imported: Option<Arc<QuadMesh>>,
    /// The model meshed with now (after a refit: the refitted one).
    pub info: ModelInfo,
    /// The model the run started with (a refit chooses another for the
    /// rest and for the next run).
    start: String,
}

impl Meshing {
    fn new(
        boundary: Boundary,
        settings: &Settings,
        models: &[ModelFile],
    ) -> Result<Meshing, EditorError> {
        let (m, info) = load_model(&settings.model, models)?;
        Ok(Meshing {
            mesher: Framed::new(boundary.clone(), m, settings.params()),
            boundary,
            last: None,
            refits: Vec::new(),
            imported: None,
            start: settings.model.clone(),
            info,
        })
    }
}

/// The document. Cloning is what the editor's undo keeps.
#[derive(Clone)]
pub struct Document {
    /// The loops as drawn, read or edited, valid or not.
    pub draft: Draft,
    /// Why the draft is not a valid boundary (`None`: it is one, and
    /// [`Document::meshing`] holds its mesh).
    pub problem: Option<BoundaryError>,
    /// The file the document came from (a boundary, mesh or project).
    pub source: Option<PathBuf>,
    /// The name shown in the title (the file's name, an example's name,
    /// or "untitled").
    pub name: String,
    pub settings: Settings,
    pub meshing: Option<Meshing>,
    /// Samples from accepted and corrected elements, and collected ones.
    pub training: TrainingSet,
    /// The boundary was drawn or edited in the editor.
    pub boundary_edited: bool,
    /// Figures of the last refit (undone with it; not saved).
    pub last_refit: Option<RefitFigures>,
    /// The models refits made, by name: chosen like the built-in ones,
    /// they survive a reset, a boundary edit or a model change, are saved
    /// with the project and can be saved as model files.
    pub models: Vec<ModelFile>,
    /// A document of several regions and named groups (then `draft` is
    /// empty and `meshing` is `None`: the regions' faces are meshed one
    /// by one).
    pub regions: Option<Regions>,
    /// The drawing (lines and arcs, `.dxf`) the regions' nodes were cut
    /// from, and the size they were cut at.
    pub drawing: Option<Drawing>,
}

/// A drawing's curves and the sizes its boundary nodes are placed at
/// ([`crate::cad::Geometry::discretise_with`]): a target size, and a
/// geometry file's local sizes (by point and by layer) and gradation, the
/// command line's.
#[derive(Clone, Debug)]
pub struct Drawing {
    pub geometry: Arc<crate::cad::Geometry>,
    pub sizes: crate::cad::SizeSpec,
    /// The curves given one segment more to make every region even.
    pub parity_fixes: usize,
}

/// Boundary segments a drawing opens with, about: its first size is the
/// curves' total length over this, rounded to two significant figures.
pub const DRAWING_SEGMENTS: f64 = 120.0;

/// The size a drawing opens with ([`DRAWING_SEGMENTS`]).
pub fn drawing_size(g: &crate::cad::Geometry) -> f64 {
    let total: f64 = g.curves.iter().map(|c| c.curve.length()).sum();
    round_figures(total / DRAWING_SEGMENTS, 2)
}

/// `v` rounded to `k` significant figures.
pub fn round_figures(v: f64, k: i32) -> f64 {
    if !(v.is_finite() && v > 0.0) {
        return v;
    }
    let scale = 10f64.powi(k - 1 - v.log10().floor() as i32);
    (v * scale).round() / scale
}

/// What a project replays into the editor's history, in order: runs of
/// steps, and the documents as they were before each refit.
pub enum Replayed {
    Steps(usize),
    Refit(Box<Document>),
}

/// A kind of step as the panels name it.
pub fn kind_name(k: StepKind) -> &'static str {
    match k {
        StepKind::Element => "element",
        StepKind::Square => "square cut",
        StepKind::Close4 => "4-node loop closed",
        StepKind::Close6 => "6-node loop closed",
        StepKind::Relax => "loop relaxed",
        StepKind::Seam => "seam",
        StepKind::Transition => "transition (3 to 1)",
        StepKind::Mapped => "mapped grid",
        StepKind::Fan => "corner fan",
        StepKind::Notch => "notch",
        StepKind::Split => "loop split",
        StepKind::Bridge => "bridge across a gap",
        StepKind::RipUp => "rip-up",
        StepKind::Fill => "fill of the region left",
        StepKind::Refan => "run made again with balanced corner fans",
        StepKind::Correction => "correction",
    }
}

impl Document {
    /// An empty document: nothing drawn yet.
    pub fn empty(mut settings: Settings) -> Document {
        // A new document has no drawing to follow.
        settings.size_target = None;
        Document {
            problem: Some(BoundaryError::Empty),
            draft: Draft::default(),
            source: None,
            name: "untitled".into(),
            training: TrainingSet::new(settings.points),
            settings,
            meshing: None,
            boundary_edited: false,
            last_refit: None,
            models: Vec::new(),
            regions: None,
            drawing: None,
        }
    }

    /// A document of several regions over `graph` (an invalid graph is
    /// kept with its problem and has no mesh until it is fixed).
    pub fn from_graph(
        graph: Pslg,
        source: Option<PathBuf>,
        name: &str,
        settings: Settings,
    ) -> Result<Document, EditorError> {
        let mut doc = Document::empty(settings);
        doc.problem = None;
        doc.regions = Some(Regions::new(graph, &doc.settings, &doc.models)?);
        doc.source = source;
        doc.name = name.to_string();
        Ok(doc)
    }

    /// A new graph of regions (an edit on the canvas): its faces are
    /// meshed from the start. Fails only when the model cannot be loaded.
    pub fn set_graph(&mut self, graph: Pslg) -> Result<(), EditorError> {
        self.regions = Some(Regions::new(graph, &self.settings, &self.models)?);
        self.boundary_edited = true;
        Ok(())
    }

    /// The document's boundary as a graph of regions (one region, no
    /// groups yet), to be split and named; the steps taken are dropped.
    pub fn to_regions(&mut self) -> Result<(), EditorError> {
        let b = self.boundary().cloned().ok_or_else(|| {
            EditorError::NoBoundary(self.problem.clone().unwrap_or(BoundaryError::Empty))
        })?;
        self.set_graph(Pslg::from_boundary(&b))?;
        self.meshing = None;
        self.draft = Draft::default();
        self.problem = None;
        Ok(())
    }

    /// True when there is something to step: a valid boundary, or a valid
    /// graph of regions.
    pub fn can_step(&self) -> bool {
        self.meshing.is_some() || self.regions.as_ref().is_some_and(|r| r.stepper.is_some())
    }

    /// The mesh of every region, once all are meshed.
    pub fn region_mesh(&self) -> Option<&Arc<RegionMesh>> {
        self.regions.as_ref()?.mesh.as_ref()
    }

    /// A document over `draft` (meshing when it is a valid boundary); fails
    /// only when the model cannot be loaded.
    pub fn from_draft(
        draft: Draft,
        source: Option<PathBuf>,
        name: &str,
        settings: Settings,
    ) -> Result<Document, EditorError> {
        Document::opened(source, name, settings, |d| d.set_draft(draft))
    }

    /// A document over the drawing `g`, its curves cut at `sizes` and its
    /// regions meshed from the start.
    pub(super) fn from_drawing(
        g: crate::cad::Geometry,
        sizes: crate::cad::SizeSpec,
        source: Option<PathBuf>,
        name: &str,
        settings: Settings,
    ) -> Result<Document, EditorError> {
        Document::opened(source, name, settings, |d| {
            d.set_drawing(Arc::new(g), sizes)
        })
    }

    /// A new document named `name`, from the file `source`, its boundary
    /// or drawing set by `fill`: as opened, not edited.
    fn opened(
        source: Option<PathBuf>,
        name: &str,
        settings: Settings,
        fill: impl FnOnce(&mut Document) -> Result<(), EditorError>,
    ) -> Result<Document, EditorError> {
        let mut doc = Document::empty(settings);
        doc.source = source;
        doc.name = name.to_string();
        fill(&mut doc)?;
        doc.boundary_edited = false;
        Ok(doc)
    }

    /// A document over a valid boundary.
    pub fn new(
        boundary: Boundary,
        source: Option<PathBuf>,
        settings: Settings,
    ) -> Result<Document, EditorError> {
        let name = source
            .as_deref()
            .map(file_name)
            .unwrap_or_else(|| "untitled".into());
        let mut doc = Document::empty(settings);
        doc.draft = Draft::of(&boundary);
        doc.problem = None;
        doc.meshing = Some(Meshing::new(boundary, &doc.settings, &doc.models)?);
        doc.source = source;
        doc.name = name;
        Ok(doc)
    }

    pub fn boundary(&self) -> Option<&Boundary> {
        self.meshing.as_ref().map(|m| &m.boundary)
    }

    /// Cuts the drawing `g` into boundary nodes at `sizes` and meshes its
    /// regions from the start. Sizes the drawing cannot be cut at leave
    /// the document as it was.
    pub fn set_drawing(
        &mut self,
        g: Arc<crate::cad::Geometry>,
        sizes: crate::cad::SizeSpec,
    ) -> Result<(), EditorError> {
        let size = sizes.size;
        let cut = g
            .discretise_with(&sizes)
            .map_err(|cause| EditorError::Drawing {
                path: self.source.clone(),
                cause,
            })?;
        if cut.graph.points.len() > crate::boundary_edit::MAX_RESAMPLED_NODES {
            return Err(EditorError::Size(format!(
                "a size of {size} cuts the drawing into {} nodes, more than {}: take a larger size",
                cut.graph.points.len(),
                crate::boundary_edit::MAX_RESAMPLED_NODES
            )));
        }
        self.settings.size_target = Some(Arc::new(cut.size_target()));
        self.set_graph(cut.graph)?;
        self.meshing = None;
        self.draft = Draft::default();
        self.problem = None;
        self.drawing = Some(Drawing {
            geometry: g,
            sizes,
            parity_fixes: cut.parity_fixes.len(),
        });
        Ok(())
    }

    /// The document's boundary cut again at target size `h`: a drawing's
    /// curves ([`Document::set_drawing`]), or every loop of the boundary
    /// resampled ([`Draft::resample_all`]); the mesh starts again.
    pub fn set_size(&mut self, h: f64) -> Result<(), EditorError> {
        if let Some(d) = &self.drawing {
            let g = d.geometry.clone();
            let sizes = crate::cad::SizeSpec {
                size: h,
                ..d.sizes.clone()
            };
            return self.set_drawing(g, sizes);
        }
        if self.regions.is_some() {
            return Err(EditorError::Size(
                "the nodes of a document of regions are placed in its file: a size applies to drawings and single boundaries".into(),
            ));
        }
        let mut draft = self.draft.clone();
        draft
            .resample_all(h)
            .map_err(|e| EditorError::Size(e.to_string()))?;
        self.set_draft(draft)
    }

    pub fn mesher(&self) -> Option<&Framed> {
        self.meshing.as_ref().map(|m| &m.mesher)
    }

    /// The last step's report (see [`Meshing::last`]).
    pub fn last(&self) -> Option<&StepReport> {
        if let Some(r) = &self.regions {
            return r.last.as_ref();
        }
        self.meshing.as_ref()?.last.as_ref()
    }

    /// The last step, when it is an element that can be corrected.
    pub fn last_element(&self) -> Option<&StepReport> {
        // (A region's elements are not corrected in the editor.)
        self.meshing
            .as_ref()?
            .last
            .as_ref()
            .filter(|r| matches!(r.kind, StepKind::Element | StepKind::Correction))
    }

    /// Steps taken.
    pub fn steps(&self) -> usize {
        if let Some(r) = &self.regions {
            return r.steps;
        }
        self.mesher().map_or(0, |m| m.steps())
    }

    /// Models set by refits.
    pub fn refits(&self) -> &[(usize, FittedModel)] {
        self.meshing.as_ref().map_or(&[], |m| &m.refits)
    }

    /// The mesh read from a file, while it is what the document shows (no
    /// step taken on its boundary yet).
    pub fn imported(&self) -> Option<&QuadMesh> {
        let m = self.meshing.as_ref()?;
        m.imported.as_deref().filter(|_| m.mesher.steps() == 0)
    }

    /// True when the run is complete.
    pub fn is_done(&self) -> bool {
        if let Some(r) = &self.regions {
            return r.is_done();
        }
        self.mesher().is_some_and(|m| m.is_done())
    }

    /// True when there is a complete mesh to show and export: the run is
    /// complete, or a mesh read from a file is shown.
    pub fn has_mesh(&self) -> bool {
        self.is_done() || self.imported().is_some()
    }

    /// True when closing or replacing the document loses something the
    /// user made: samples, corrections, refits, a drawn or edited boundary
    /// (automatic steps can be taken again).
    pub fn has_work(&self) -> bool {
        !self.training.is_empty()
            || !self.models.is_empty()
            || self.boundary_edited
            || self.mesher().is_some_and(|m| {
                m.actions()
                    .iter()
                    .any(|a| matches!(a, Action::Correction(_)))
            })
    }

    fn meshing_mut(&mut self) -> Result<&mut Meshing, EditorError> {
        match self.meshing.as_mut() {
            Some(m) => Ok(m),
            None => Err(EditorError::NoBoundary(
                self.problem.clone().unwrap_or(BoundaryError::Empty),
            )),
        }
    }

    /// One step; `Ok(false)` when the mesh is already complete.
    pub fn step(&mut self) -> Result<bool, EditorError> {
        if let Some(r) = self.regions.as_mut() {
            return r.step();
        }
        let m = self.meshing_mut()?;
        match m.mesher.step()? {
            StepOutcome::Stepped(r) => {
                m.last = Some(*r);
                Ok(true)
            }
            StepOutcome::Done => Ok(false),
        }
    }

    /// Undoes the last step; the step before becomes the last one, with its
    /// report (replayed), so that it can be corrected.
    pub fn undo_step(&mut self) -> bool {
        if let Some(r) = self.regions.as_mut() {
            return r.undo_step();
        }
        let Some(m) = self.meshing.as_mut() else {
            return false;
        };
        if !m.mesher.undo() {
            return false;
        }
        m.last = None;
        if m.mesher.steps() > 0 {
            let mut probe = m.mesher.clone();
            if probe.undo() {
                m.last = probe.redo().ok().flatten();
            }
        }
        true
    }

    /// Takes the last undone step again; `Ok(false)` when there is none.
    pub fn redo_step(&mut self) -> Result<bool, EditorError> {
        if let Some(r) = self.regions.as_mut() {
            return r.redo_step();
        }
        let m = self.meshing_mut()?;
        match m.mesher.redo()? {
            Some(r) => {
                m.last = Some(r);
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// Starts the mesh again with the current settings.
    pub fn reset(&mut self) -> Result<(), EditorError> {
        if let Some(r) = &self.regions {
            let graph = r.graph.clone();
            self.regions = Some(Regions::new(graph, &self.settings, &self.models)?);
            return Ok(());
        }
        let boundary = self.meshing_mut()?.boundary.clone();
        self.meshing = Some(Meshing::new(boundary, &self.settings, &self.models)?);
        Ok(())
    }

    /// A new draft (an edit on the canvas): when it is a valid boundary the
    /// mesh starts again over it, else the problem is kept and there is no
    /// mesh until the draft is fixed. Fails only when the model cannot be
    /// loaded (nothing changes then).
    pub fn set_draft(&mut self, draft: Draft) -> Result<(), EditorError> {
        let (meshing, problem) = match draft.to_boundary() {
            Ok(b) => (Some(Meshing::new(b, &self.settings, &self.models)?), None),
            Err(e) => (None, Some(e)),
        };
        self.draft = draft;
        self.meshing = meshing;
        self.problem = problem;
        self.boundary_edited = true;
        Ok(())
    }

    /// Changes the settings and starts again (unless only what finishing
    /// does changed: the steps stay); returns whether the mesh restarted.
    /// On failure nothing changes.
    pub fn set_settings(&mut self, settings: Settings) -> Result<bool, EditorError> {
        if let Some(r) = &self.regions {
            // Each face is finished as it is meshed: any change starts
            // the faces again.
            let regions = Regions::new(r.graph.clone(), &settings, &self.models)?;
            self.settings = settings;
            self.regions = Some(regions);
            return Ok(true);
        }
        if self.settings.same_steps(&settings) || self.meshing.is_none() {
            if self.meshing.is_none() {
                load_model(&settings.model, &self.models)?;
            }
            self.settings = settings;
            return Ok(false);
        }
        let boundary = self.meshing_mut()?.boundary.clone();
        let meshing = Meshing::new(boundary, &settings, &self.models)?;
        self.settings = settings;
        self.meshing = Some(meshing);
        Ok(true)
    }

    /// The settings for another document: a refitted model of this one
    /// gives way to the shipped model (the refitted models stay with this
    /// document and its project).
    pub fn portable_settings(&self) -> Settings {
        let mut s = self.settings.clone();
        if self.model_file(&s.model).is_some() {
            s.model = Settings::default().model;
        }
        s
    }

    /// The document's model named `name`, if a refit made one.
    pub fn model_file(&self, name: &str) -> Option<&ModelFile> {
        self.models.iter().find(|f| f.name == name)
    }

    /// Writes the refitted model meshed with now as a model file (what
    /// `quadex mesh --model` reads).
    pub fn save_model(&self, path: &Path) -> Result<String, EditorError> {
        let f = self
            .model_file(&self.model_info().name)
            .ok_or(EditorError::NoRefittedModel)?;
        io::write_atomic(path, f.to_json().as_bytes())?;
        Ok(f.name.clone())
    }

    /// The model meshed with now.
    pub fn model_info(&self) -> ModelInfo {
        match &self.meshing {
            Some(m) => m.info.clone(),
            None => load_model(&self.settings.model, &self.models)
                .map(|(_, i)| i)
                .unwrap_or(ModelInfo {
                    name: self.settings.model.clone(),
                    form: String::new(),
                    samples: None,
                    corrections: 0,
                }),
        }
    }

    /// The finished mesh (cleaned up, smoothed and checked), for export.
    pub fn finished(&self) -> Result<QuadMesh, EditorError> {
        if let Some(r) = &self.regions {
            return r
                .mesh
                .as_ref()
                .map(|m| m.mesh.clone())
                .ok_or(EditorError::NotFinished);
        }
        if let Some(m) = self.imported() {
            return Ok(m.clone());
        }
        match self.mesher() {
            Some(m) if m.is_done() => Ok(m.finish(&self.settings.finishing())?),
            _ => Err(EditorError::NotFinished),
        }
    }
}

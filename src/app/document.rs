//! The editor's document: the boundary as the user draws, reads and edits
//! it (a [`Draft`], valid or not), and once it is a valid boundary the
//! mesher stepping over it ([`Meshing`]) with the chosen model and
//! settings, the last step's report and the models refits made; the
//! training set the user's corrections go to. A document is saved whole
//! as a project file ([`Project`]). Everything here goes through the
//! core's public API (`Mesher`, `model::load`, `fit`, `io`).

use super::error::{AtPath, EditorError, ProjectError};
use super::framed::Framed;
use super::regions::Regions;
use crate::boundary::BoundaryError;
use crate::boundary_edit::Draft;
use crate::compare;
use crate::extract::{
    Action, CheckedElement, Correction, MeshParams, StepKind, StepOutcome, StepReport, Strategy,
};
use crate::finish::cleanup::CleanupParams;
use crate::finish::coarsen::CoarsenParams;
use crate::finish::remesh::RemeshParams;
use crate::fit::{self, Figures, FitParams, TypeFigures};
use crate::geom::Point;
use crate::io;
use crate::io::boundary_json::BoundaryDoc;
use crate::mesh::QuadMesh;
use crate::model::fitted::FittedModel;
use crate::model::{self, ElementType, Form, Model as _, ModelFile};
use crate::pipeline::FinishParams;
use crate::pslg::Pslg;
use crate::regions::RegionMesh;
use crate::samples::{Sample, SampleKeys, TrainingSet};
use crate::smooth::SmoothParams;
use crate::Boundary;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

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
    /// Chord coarsening of the finished mesh.
    pub coarsen: CoarsenParams,
    /// Local remeshing of the finished mesh's bad regions.
    pub remesh: RemeshParams,
    /// The size field a drawing's interior follows
    /// ([`MeshParams::size_target`]), as `quadex mesh part.dxf --size H`
    /// meshes it; none for nodes given. Set with the drawing, not saved (a
    /// project keeps the nodes cut from it).
    #[serde(skip)]
    pub size_target: Option<Arc<crate::extract::size::SizeTarget>>,
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
            coarsen: FinishParams::DEFAULT.coarsen,
            remesh: FinishParams::DEFAULT.remesh,
            size_target: None,
        }
    }
}

impl Settings {
    /// The extraction parameters of these settings.
    pub fn params(&self) -> MeshParams {
        MeshParams {
            strategy: self.strategy,
            leading_points: (self.points - 1) / 2,
            pure_model: self.pure_model,
            fill_after_layers: self.fill_after_layers,
            size_target: self.size_target.as_deref().cloned(),
            ..MeshParams::DEFAULT
        }
    }

    /// What finishing the mesh does.
    pub fn finishing(&self) -> FinishParams {
        FinishParams {
            cleanup: self.cleanup,
            coarsen: self.coarsen,
            remesh: self.remesh,
            smooth: self.smooth,
        }
    }

    /// True when `other` differs from these settings only in what
    /// finishing does (the steps stay).
    pub fn same_steps(&self, other: &Settings) -> bool {
        Settings {
            smooth: self.smooth,
            cleanup: self.cleanup,
            coarsen: self.coarsen,
            remesh: self.remesh,
            ..other.clone()
        } == *self
    }
}

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

/// What the editor says about the model it meshes with.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelInfo {
    pub name: String,
    /// `quadratic`, `thesis` (fitted), `rules`, `thesis (Table 8)`, …
    pub form: String,
    /// Samples its global part was fitted on (none for rules and presets).
    pub samples: Option<usize>,
    /// Corrections layered over it.
    pub corrections: usize,
}

impl ModelInfo {
    fn of_file(f: &ModelFile) -> ModelInfo {
        ModelInfo {
            name: f.name.clone(),
            form: f.coefficients.form().name().into(),
            samples: Some(f.training.samples),
            corrections: f.corrections.len(),
        }
    }
}

/// The model named `spec`: one of the document's refitted `models` by
/// name, a built-in model, or a model file; with what the editor shows of
/// it.
pub fn load_model(
    spec: &str,
    models: &[ModelFile],
) -> Result<(Arc<dyn model::Model>, ModelInfo), EditorError> {
    if let Some(f) = models.iter().find(|f| f.name == spec) {
        return Ok((Arc::new(f.model()), ModelInfo::of_file(f)));
    }
    // A built-in model is loaded once and shared: the same model after an
    // Open or a Reset is the same one (the Model panel measures it once).
    if model::BUILTIN.contains(&spec) {
        if let Some(hit) = BUILTIN_MODELS
            .get_or_init(Default::default)
            .lock()
            .ok()
            .and_then(|c| c.get(spec).cloned())
        {
            return Ok(hit);
        }
    }
    let loaded = load_model_afresh(spec)?;
    if model::BUILTIN.contains(&spec) {
        if let Ok(mut c) = BUILTIN_MODELS.get_or_init(Default::default).lock() {
            c.insert(spec.to_string(), loaded.clone());
        }
    }
    Ok(loaded)
}

/// The built-in models loaded this session, by name.
type LoadedModel = (Arc<dyn model::Model>, ModelInfo);
static BUILTIN_MODELS: OnceLock<Mutex<BTreeMap<String, LoadedModel>>> = OnceLock::new();

/// Loads a built-in model or a model file by name or path.
fn load_model_afresh(spec: &str) -> Result<LoadedModel, EditorError> {
    let failed = |cause| EditorError::Model {
        spec: spec.to_string(),
        cause,
    };
    let file = match spec {
        "default" | "ann" => model::shipped_file(spec).map(ModelFile::from_json),
        "rules" | "thesis" => None,
        path => Some(
            std::fs::read(path)
                .map_err(|e| failed(model::LoadError::Io(e)))
                .map(|b| ModelFile::from_json(&io::decode_text(&b)))?,
        ),
    };
    match file {
        Some(f) => {
            let f = f.map_err(|e| failed(model::LoadError::File(e)))?;
            let info = ModelInfo {
                name: spec.to_string(),
                ..ModelInfo::of_file(&f)
            };
            Ok((Arc::new(f.model()), info))
        }
        None => {
            let m = model::load(spec).map_err(failed)?;
            let info = ModelInfo {
                name: spec.to_string(),
                form: if spec == "rules" {
                    "rules (Zeng & Cheng)".into()
                } else {
                    "thesis (Table 8 as printed)".into()
                },
                samples: None,
                corrections: 0,
            };
            Ok((Arc::from(m), info))
        }
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

/// A drawing's curves and the target size its boundary nodes are placed
/// at ([`crate::cad::Geometry::discretise`]).
#[derive(Clone, Debug)]
pub struct Drawing {
    pub geometry: Arc<crate::cad::Geometry>,
    pub size: f64,
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

/// Figures of the model before and after a refit, on the same samples.
#[derive(Clone, Debug, PartialEq)]
pub struct RefitFigures {
    /// Samples the global part was fitted on (the reference meshes' and
    /// those collected from meshes, duplicates dropped), as the model's
    /// own summary counts them.
    pub samples: usize,
    /// The user's corrections layered over it.
    pub corrections: usize,
    /// Samples collected from meshes or imported that the fit dropped as
    /// repeats of samples already in the set (they add nothing).
    pub repeated: usize,
    pub before: (TypeFigures, Figures, Figures),
    pub after: (TypeFigures, Figures, Figures),
    /// The refitted model's name.
    pub model: String,
    /// What the models before and after predict at each correction.
    pub checks: Vec<CorrectionCheck>,
    /// The boundary meshed from the start with the model before and the
    /// refitted one.
    pub meshed: Option<(compare::Outcome, compare::Outcome)>,
    /// Meshing the boundary from the start with the refitted model: the
    /// predictions its corrections changed, of all it made (none without
    /// corrections or without that meshing).
    pub memory_reach: Option<(usize, usize)>,
    /// How the refitted model meshes the boundary worse (empty: it does
    /// not).
    pub worse: Vec<String>,
}

/// A correction and what the models predict at its input (normalised
/// frame).
#[derive(Clone, Debug, PartialEq)]
pub struct CorrectionCheck {
    /// The position of the correction among the user's samples.
    pub sample: usize,
    pub corrected: model::Prediction,
    pub before: model::Prediction,
    pub after: model::Prediction,
}

/// How near the refitted model's Pn must come to the correction's for the
/// correction to count as reproduced (normalised units).
pub const REPRODUCED: f64 = 0.05;

impl CorrectionCheck {
    /// The refitted model predicts the corrected element.
    pub fn reproduced(&self) -> bool {
        self.after.element_type == self.corrected.element_type
            && self.after.pn.distance(self.corrected.pn) <= REPRODUCED
    }
}

/// A front node the last element could be closed onto instead, and
/// whether that gives a valid element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    pub node: u32,
    pub at: Point,
    /// Type 1 for P_r2, type 2 for P_l2, else type 0 closed onto the node.
    pub element_type: ElementType,
    /// The element closing onto the node gives (`None`: not a valid
    /// element): its guard's score and corners. A valid element may still
    /// be a poor one.
    pub check: Option<CheckedElement>,
}

impl Target {
    /// True when closing onto this node gives a valid element.
    pub fn valid(&self) -> bool {
        self.check.is_some()
    }

    /// The correction that closes the element onto this node.
    pub fn command(&self) -> super::Command {
        super::Command::CorrectLast {
            element_type: self.element_type,
            pn: self.at,
            snap_to: (self.element_type == ElementType::New).then_some(self.node),
        }
    }
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
        StepKind::Split => "loop split",
        StepKind::Bridge => "bridge across a gap",
        StepKind::RipUp => "rip-up",
        StepKind::Fill => "fill of the region left",
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
        let mut doc = Document::empty(settings);
        doc.source = source;
        doc.name = name.to_string();
        doc.set_draft(draft)?;
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

    /// The shipped example `name` (built into the binary).
    pub fn example(name: &str, settings: Settings) -> Result<Document, EditorError> {
        let text =
            super::assets::example(name).ok_or(EditorError::UnknownExample(name.to_string()))?;
        let path = PathBuf::from(name);
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
            // A geometry file (JSON) may carry its target size; its local
            // sizes are the command line's (`quadex mesh`).
            let (g, size) = if crate::cad::is_geometry_file(path) {
                let d = crate::cad::read_geometry_json(path).map_err(failed)?;
                (d.geometry, d.size)
            } else {
                (crate::cad::read_dxf(path).map_err(failed)?, None)
            };
            let mut doc = Document::empty(settings);
            doc.source = Some(path.to_path_buf());
            doc.name = file_name(path);
            doc.set_drawing(Arc::new(g), size)?;
            doc.boundary_edited = false;
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

    pub fn boundary(&self) -> Option<&Boundary> {
        self.meshing.as_ref().map(|m| &m.boundary)
    }

    /// Cuts the drawing `g` into boundary nodes at `size` (its first size,
    /// [`drawing_size`], when `None`) and meshes its regions from the
    /// start. A size the drawing cannot be cut at leaves the document as
    /// it was.
    pub fn set_drawing(
        &mut self,
        g: Arc<crate::cad::Geometry>,
        size: Option<f64>,
    ) -> Result<(), EditorError> {
        let size = size.unwrap_or_else(|| drawing_size(&g));
        let cut = g.discretise(size).map_err(|cause| EditorError::Drawing {
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
            size,
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
            return self.set_drawing(g, Some(h));
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

    /// Appends the sample of the last step (an element the user accepts).
    pub fn append_last(&mut self) -> Result<usize, EditorError> {
        let r = self.last().ok_or(EditorError::NoStep)?;
        if self.last_element().is_none() {
            return Err(EditorError::NotAnElement(kind_name(r.kind)));
        }
        let m = self.mesher().ok_or(EditorError::NoStep)?;
        let s = m.sample_of(r).ok_or(EditorError::NotAnElement("step"))?;
        // The same input and element (whatever its source) would weigh
        // twice in a refit and tell it nothing new.
        if let Some(i) = self.training.position_of(&s) {
            return Err(EditorError::AlreadySampled(i + 1));
        }
        self.push_sample(s)
    }

    /// The number (from 1) of the training sample the last element's
    /// sample already is, if it is one: a correction keeps its sample at
    /// once, and appending it again would add nothing.
    pub fn last_sampled(&self) -> Option<usize> {
        let r = self.last_element()?;
        let s = self.mesher()?.sample_of(r)?;
        self.training.position_of(&s).map(|i| i + 1)
    }

    fn push_sample(&mut self, s: Sample) -> Result<usize, EditorError> {
        if self.training.points != 2 * s.n() + 1 && self.training.is_empty() {
            self.training = TrainingSet::new(2 * s.n() + 1);
        }
        self.training.push(s)?;
        Ok(self.training.len())
    }

    /// The mesher as it was before the last step (the last step undone).
    pub fn before_last(&self) -> Option<Framed> {
        let mut m = self.mesher()?.clone();
        m.undo().then_some(m)
    }

    /// Replaces the last element by the user's (type 0 closes onto front
    /// node `snap_to` when given): the step is undone, the correction
    /// committed at the same reference point, and its sample appended (in
    /// place of any earlier correction of the same input: the step
    /// corrected again, or corrected before a Reset). `before` is the
    /// mesher before the last step when the caller has it (else it is
    /// replayed). If the correction is not a valid element,
    /// nothing changes.
    pub fn correct_last(
        &mut self,
        element_type: ElementType,
        pn: Point,
        snap_to: Option<u32>,
        before: Option<Framed>,
    ) -> Result<usize, EditorError> {
        let r = self.last().ok_or(EditorError::NoStep)?;
        if !matches!(r.kind, StepKind::Element | StepKind::Correction) {
            return Err(EditorError::NotAnElement(kind_name(r.kind)));
        }
        let reference = r.reference.ok_or(EditorError::NoStep)?;
        let c = Correction {
            reference,
            element_type,
            pn: Some(pn),
            snap_to,
        };
        let mut mesher = match before {
            Some(b) => b,
            None => self.before_last().ok_or(EditorError::NoStep)?,
        };
        let (prediction, predicted_pn) = (r.prediction, r.predicted_pn);
        let mut report = mesher.correct(&c)?;
        let sample = mesher.sample_of(&report);
        // The model's element at this input stays on show beside the
        // user's, to compare them (a correction has no prediction of its
        // own).
        report.prediction = prediction;
        report.predicted_pn = predicted_pn;
        let m = self.meshing_mut()?;
        m.mesher = mesher;
        m.last = Some(report);
        match sample {
            Some(s) => {
                // One input, one answer: an earlier correction of the same
                // input (the step corrected again, or corrected before a
                // Reset) gives way to this one.
                self.training.samples.retain(|o| {
                    !(o.source == crate::samples::Source::Correction && o.input == s.input)
                });
                self.push_sample(s)
            }
            None => Ok(self.training.len()),
        }
    }

    /// The front nodes near the last element's reference point that the
    /// element could be closed onto instead (P_r2 as type 1, P_l2 as type 2,
    /// any other as type 0 with that node as Pn), each checked on `before`,
    /// the mesher before the last step.
    pub fn closing_targets(&self, before: &mut Framed) -> Vec<Target> {
        let Some(r) = self.last_element() else {
            return Vec::new();
        };
        let n = r.leading.len() / 2;
        if n == 0 {
            return Vec::new();
        }
        let nodes = &before.mesh().nodes;
        let at = |v: u32| nodes.get(v as usize).copied();
        let (Some(p0), Some(l1), Some(r1)) =
            (at(r.leading[n]), at(r.leading[n - 1]), at(r.leading[n + 1]))
        else {
            return Vec::new();
        };
        let (p0_id, l1_id, r1_id) = (r.leading[n], r.leading[n - 1], r.leading[n + 1]);
        let l2 = (n >= 2).then(|| r.leading[n - 2]);
        let r2 = r.leading.get(n + 2).copied();
        let reach = 3.0 * p0.distance(l1).max(p0.distance(r1));
        let f = before.front();
        let mut near: Vec<(u32, Point)> = f
            .live_loops()
            .flat_map(|l| f.loop_nodes(l))
            .filter(|&v| v != p0_id && v != l1_id && v != r1_id)
            .filter_map(|v| at(v).map(|p| (v, p)))
            .filter(|(_, p)| p.distance(p0) <= reach)
            .collect();
        near.sort_unstable_by_key(|(v, _)| *v);
        near.dedup_by_key(|(v, _)| *v);
        near.into_iter()
            .map(|(v, p)| {
                let element_type = if Some(v) == r2 {
                    ElementType::Right
                } else if Some(v) == l2 {
                    ElementType::Left
                } else {
                    ElementType::New
                };
                let c = Correction {
                    reference: p0_id,
                    element_type,
                    pn: Some(p),
                    snap_to: (element_type == ElementType::New).then_some(v),
                };
                Target {
                    node: v,
                    at: p,
                    element_type,
                    check: before.check_correction(&c).ok(),
                }
            })
            .collect()
    }

    /// The reference samples and the user's, as a refit sees them.
    pub fn refit_set(&self) -> Result<TrainingSet, EditorError> {
        refit_set_of(self.training.clone())
    }

    /// Refits a model of `form` on the reference samples plus the user's
    /// ([`fit::refit`]: samples collected from meshes join the global fit,
    /// the user's own elements are layered over it as corrections), adds it
    /// to the document's models and chooses it (a reset or a boundary edit
    /// keeps it), sets it to mesh the rest of the mesh with, and returns
    /// the figures of the old and the new model: on those samples, at each
    /// correction, and meshing the boundary from the start.
    pub fn refit(&mut self, form: Form) -> Result<RefitFigures, EditorError> {
        let done = self.refit_task(form)?.run(|_| {})?;
        self.take_refit(done)
    }

    /// What a refit in `form` works on ([`Document::refit`]), to be made
    /// in a thread ([`RefitTask::run`]) and taken back with
    /// [`Document::take_refit`].
    pub fn refit_task(&self, form: Form) -> Result<RefitTask, EditorError> {
        let m = self.meshing.as_ref().ok_or(EditorError::NoStep)?;
        let mut k = self.models.len() + 1;
        while self.models.iter().any(|f| f.name == refit_name(form, k)) {
            k += 1;
        }
        Ok(RefitTask {
            form,
            training: self.training.clone(),
            name: refit_name(form, k),
            old: m.mesher.model().clone(),
            params: crate::pipeline::Params {
                extract: m.mesher.params().clone(),
                finish: self.settings.finishing(),
            },
            boundary: (m.boundary.node_count() <= COMPARE_NODES).then(|| m.boundary.clone()),
        })
    }

    /// Takes a refit made by [`RefitTask::run`]: the model joins the
    /// document's models, is chosen, and meshes the rest.
    pub fn take_refit(&mut self, done: RefitDone) -> Result<RefitFigures, EditorError> {
        let RefitDone {
            file,
            model,
            figures,
        } = done;
        let m = self.meshing_mut()?;
        m.mesher.set_model(Arc::new(model.clone()));
        m.refits.push((m.mesher.steps(), model));
        m.info = ModelInfo::of_file(&file);
        self.settings.model = file.name.clone();
        self.models.push(file);
        self.last_refit = Some(figures.clone());
        Ok(figures)
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

/// The reference samples and the user's `training`, as a refit sees them
/// ([`Document::refit_set`]).
pub fn refit_set_of(training: TrainingSet) -> Result<TrainingSet, EditorError> {
    let mut set = (*reference_samples(training.points)?).clone();
    set.merge(training)?;
    Ok(set)
}

/// The fitting parameters of the editor's refit (no held-out folds: the
/// figures shown are those of the samples themselves).
const REFIT_PARAMS: FitParams = FitParams {
    folds: 0,
    ..FitParams::DEFAULT
};

/// A refit's work ([`Document::refit_task`]), to be taken to a thread.
pub struct RefitTask {
    pub form: Form,
    training: TrainingSet,
    /// The refitted model's name.
    name: String,
    /// The model meshed with before the refit.
    old: Arc<dyn model::Model>,
    params: crate::pipeline::Params,
    /// The boundary meshed from the start with both models (none above
    /// [`COMPARE_NODES`] nodes).
    boundary: Option<Boundary>,
}

/// The parts of a refit, as its progress line names them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RefitPhase {
    /// The reference samples collected (once per session).
    Collecting,
    /// The global fit on this many samples (taken at once when it was
    /// made before) and the corrections layered over it.
    Fitting(usize),
    /// Both models measured on the samples.
    Measuring,
    /// The boundary meshed from the start with the model before; the share
    /// of its area meshed.
    MeshingBefore(f64),
    /// The same with the refitted model.
    MeshingAfter(f64),
}

impl RefitPhase {
    /// The progress line: "meshing the boundary with the refitted model
    /// (45 %)".
    pub fn describe(self) -> String {
        match self {
            RefitPhase::Collecting => "collecting the reference samples".into(),
            RefitPhase::Fitting(n) => format!("fitting on {}", super::plural(n, "sample")),
            RefitPhase::Measuring => "measuring both models on the samples".into(),
            RefitPhase::MeshingBefore(f) => format!(
                "meshing the boundary from the start with the model before ({:.0} %)",
                100.0 * f
            ),
            RefitPhase::MeshingAfter(f) => format!(
                "meshing the boundary from the start with the refitted model ({:.0} %)",
                100.0 * f
            ),
        }
    }
}

/// What a refit made, to be taken into the document
/// ([`Document::take_refit`]).
pub struct RefitDone {
    file: ModelFile,
    model: FittedModel,
    pub figures: RefitFigures,
}

/// Predictions a correction memory may change, as a share of a run's
/// predictions, before the refit report says the corrections reach too
/// far (one correction meant for one front that changes a large part of
/// the mesh).
pub const WORSE_MEMORY_SHARE: f64 = 0.05;

/// A fitted model that counts the predictions its corrections changed
/// (those where [`FittedModel::predict`] is not
/// [`FittedModel::predict_global`]).
struct MemoryCount {
    model: FittedModel,
    calls: std::sync::atomic::AtomicUsize,
    changed: std::sync::atomic::AtomicUsize,
}

impl model::Model for MemoryCount {
    fn name(&self) -> &str {
        self.model.name()
    }

    fn leading_points(&self) -> Option<usize> {
        self.model.leading_points()
    }

    fn predict(&self, input: &crate::normalize::LeadingPoints) -> model::Prediction {
        use std::sync::atomic::Ordering;
        let p = self.model.predict(input);
        self.calls.fetch_add(1, Ordering::Relaxed);
        if p != self.model.predict_global(input) {
            self.changed.fetch_add(1, Ordering::Relaxed);
        }
        p
    }
}

impl RefitTask {
    /// Makes the refit: the global fit (kept for the session), the
    /// corrections layered over it, both models measured on the samples
    /// and at each correction, and the boundary meshed from the start with
    /// both; `phase` is told as each part starts.
    pub fn run(self, phase: impl Fn(RefitPhase)) -> Result<RefitDone, EditorError> {
        use std::sync::atomic::Ordering;
        phase(RefitPhase::Collecting);
        let base = reference(self.training.points)?;
        let (own, from_meshes) = fit::split_added(&self.training);
        let (from_meshes, repeated) = if from_meshes.is_empty() {
            (from_meshes, 0)
        } else {
            from_meshes.beyond(base.keys.get_or_init(|| base.set.keys()))
        };
        let base = base.set;
        phase(RefitPhase::Fitting(base.len() + from_meshes.len()));
        let set = refit_set_of(self.training.clone())?;
        let memory = fit::correction_memory(base.points, &own, model::memory::DEFAULT_RADIUS)?;
        let mut global = global_fit(&base, &from_meshes, self.form, &REFIT_PARAMS)?;
        global.name = self.name.clone();
        let file = fit::with_memory(global, memory);
        let model = file.model();
        let old = self.old;
        phase(RefitPhase::Measuring);
        // The two models measured side by side (a second each on the
        // reference samples).
        let (before, after) = std::thread::scope(|scope| {
            let before = scope.spawn(|| fit::evaluate(old.as_ref(), &set));
            let after = fit::evaluate(&model, &set);
            (before.join(), after)
        });
        let before = before.map_err(|_| EditorError::JobPanicked)??;
        let after = after?;
        let checks = self
            .training
            .samples
            .iter()
            .enumerate()
            .filter(|(_, s)| s.source == crate::samples::Source::Correction)
            .map(|(i, s)| CorrectionCheck {
                sample: i,
                corrected: model::Prediction {
                    element_type: s.element_type,
                    pn: s.pn,
                },
                before: old.predict(&s.input),
                after: model.predict(&s.input),
            })
            .collect();
        let counted = Arc::new(MemoryCount {
            model: model.clone(),
            calls: Default::default(),
            changed: Default::default(),
        });
        let meshed = self.boundary.as_ref().map(|b| {
            let before =
                compare::mesh_with_progress(old.name(), b, old.clone(), &self.params, |p| {
                    phase(RefitPhase::MeshingBefore(p.meshed))
                });
            let after =
                compare::mesh_with_progress(&file.name, b, counted.clone(), &self.params, |p| {
                    phase(RefitPhase::MeshingAfter(p.meshed))
                });
            (before, after)
        });
        let memory_reach = meshed
            .as_ref()
            .filter(|_| !model.memory.is_empty())
            .map(|_| {
                (
                    counted.changed.load(Ordering::Relaxed),
                    counted.calls.load(Ordering::Relaxed),
                )
            });
        let mut worse = meshed
            .as_ref()
            .map(|(b, a)| a.worse_than(b))
            .unwrap_or_default();
        if let Some((changed, calls)) = memory_reach {
            if changed as f64 > WORSE_MEMORY_SHARE * calls as f64 {
                worse.push(format!(
                    "the corrections change {} of {} predictions",
                    compare::grouped(changed),
                    compare::grouped(calls)
                ));
            }
        }
        let figures = RefitFigures {
            samples: file.training.samples,
            corrections: file.training.corrections,
            repeated,
            before,
            after,
            model: file.name.clone(),
            checks,
            meshed,
            memory_reach,
            worse,
        };
        Ok(RefitDone {
            file,
            model,
            figures,
        })
    }
}

/// Global fits made this session, by [`fit_key`].
type FitKey = (usize, &'static str, String, u64);
static FITS: OnceLock<Mutex<BTreeMap<FitKey, ModelFile>>> = OnceLock::new();

/// What a global fit depends on: the input points (which give the
/// reference samples), the form, the parameters and the samples from
/// meshes.
fn fit_key(
    base: &TrainingSet,
    from_meshes: &TrainingSet,
    form: Form,
    params: &FitParams,
) -> FitKey {
    let samples = serde_json::to_string(&from_meshes.samples).unwrap_or_default();
    (
        base.points,
        form.name(),
        format!("{params:?}"),
        fingerprint(&samples),
    )
}

/// The global fit when it is made already: kept from earlier in the
/// session, or a shipped model's own file. With no samples from meshes, a
/// shipped model of that form and input points fitted with these
/// parameters (folds aside) is that fit (the tests
/// `the_shipped_*_model_is_the_fit_of_the_reference_meshes` refit them and
/// compare).
fn cached_or_shipped(
    key: &FitKey,
    from_meshes: &TrainingSet,
    form: Form,
    params: &FitParams,
) -> Option<ModelFile> {
    let fits = FITS.get_or_init(Default::default);
    if let Some(f) = fits.lock().ok().and_then(|c| c.get(key).cloned()) {
        return Some(f);
    }
    let shipped_params = FitParams {
        folds: FitParams::DEFAULT.folds,
        ..*params
    } == FitParams::DEFAULT;
    [model::DEFAULT_MODEL_JSON, model::ANN_MODEL_JSON]
        .into_iter()
        .filter(|_| from_meshes.is_empty() && shipped_params)
        .filter_map(|json| ModelFile::from_json(json).ok())
        .find(|f| f.points == key.0 && f.coefficients.form() == form)
}

/// The global fit of a refit ([`fit::refit_global`]): `form` on the
/// reference samples `base` plus the samples `from_meshes`, kept for the
/// rest of the session, since it depends on nothing else and takes seconds
/// (a refit after each correction adds none from meshes).
fn global_fit(
    base: &TrainingSet,
    from_meshes: &TrainingSet,
    form: Form,
    params: &FitParams,
) -> Result<ModelFile, EditorError> {
    let key = fit_key(base, from_meshes, form, params);
    if let Some(f) = cached_or_shipped(&key, from_meshes, form, params) {
        return Ok(f);
    }
    let file = fit::refit_global(base, from_meshes, form, "global", params)?;
    if let Ok(mut c) = FITS.get_or_init(Default::default).lock() {
        c.insert(key, file.clone());
    }
    Ok(file)
}

/// A 64-bit fingerprint of `text` (FNV-1a).
fn fingerprint(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The name of the `k`-th refitted model of `form`.
fn refit_name(form: Form, k: usize) -> String {
    format!("fitted ({}) {k}", form.name())
}

/// Boundaries with more nodes than this are not meshed again from the
/// start after a refit (it would take too long to wait for).
pub const COMPARE_NODES: usize = 4000;

/// The reference meshes' samples at `points` input points, collected as
/// for the shipped model ([`crate::reference::training_set`]), once per run
/// of the program and shared.
pub fn reference_samples(points: usize) -> Result<Arc<TrainingSet>, EditorError> {
    Ok(reference(points)?.set)
}

/// The reference samples at `points` input points, and their duplicate
/// keys when a refit has needed them, kept for the session.
#[derive(Clone)]
struct Reference {
    set: Arc<TrainingSet>,
    keys: Arc<OnceLock<SampleKeys>>,
}

fn reference(points: usize) -> Result<Reference, EditorError> {
    static CACHE: OnceLock<Mutex<BTreeMap<usize, Reference>>> = OnceLock::new();
    let cache = CACHE.get_or_init(Default::default);
    if let Some(r) = cache.lock().ok().and_then(|c| c.get(&points).cloned()) {
        return Ok(r);
    }
    let meshes = crate::reference::read_shipped()?;
    let r = Reference {
        set: Arc::new(crate::reference::training_set(&meshes, points)),
        keys: Arc::default(),
    };
    if let Ok(mut c) = cache.lock() {
        c.insert(points, r.clone());
    }
    Ok(r)
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
    pub fn import_samples(&mut self, path: &Path) -> Result<usize, EditorError> {
        let set = TrainingSet::read(path).at(path)?;
        self.add_samples(set).at(path)
    }

    fn add_samples(&mut self, set: TrainingSet) -> Result<usize, crate::samples::SamplesError> {
        let n = set.len();
        if self.training.is_empty() {
            self.training = set;
        } else {
            self.training.merge(set)?;
        }
        Ok(n)
    }

    /// Writes the user's samples (CSV, or JSON for a `.json` path).
    pub fn export_samples(&self, path: &Path) -> Result<(), EditorError> {
        self.training.write(path).at(path)
    }

    /// Collects samples from a finished mesh (the current one, or a mesh
    /// file) at the set's input points and appends them; returns how many.
    pub fn collect_samples(&mut self, name: &str, mesh: QuadMesh) -> Result<usize, EditorError> {
        // As the shipped model's samples are collected, so that a refit
        // with them is the self-training of `examples/self_training.rs`.
        let set = crate::reference::training_set(&[(name.to_string(), mesh)], self.training.points);
        Ok(self.add_samples(set)?)
    }

    /// Collects from a quad mesh file (`.msh`).
    pub fn collect_from_file(&mut self, path: &Path) -> Result<usize, EditorError> {
        let mesh = io::read_mesh(path).at(path)?;
        self.collect_samples(&file_name(path), mesh)
    }
}

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

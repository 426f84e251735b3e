//! The desktop editor (eframe/egui): a view and a controller over the core.
//!
//! [`App`] holds five groups: the document ([`DocumentState`]: the
//! [`Document`], its [`History`] for undo and redo, the file it is saved
//! to), the view ([`ViewState`]: the canvas view and the caches drawn
//! from the document), the panels ([`Panels`]: each a [`View`] that draws
//! itself from the [`Document`] and what little else it shows, and
//! returns [`Command`]s), the background work
//! ([`Background`]: runs and the finishing pass in a thread, the animated
//! run) and the window plumbing ([`Window`]: status line, questions, file
//! prompts, screenshots). Every user intent is a [`Command`] applied in
//! [`App::apply`]. No meshing logic lives here: the editor drives `Mesher`
//! through its public step API like the command line and the tests do.
//! What is remembered between runs is one serde struct, [`Prefs`].
//!
//! Here: the state and the eframe entry. The rest by concern: `commands/`
//! (each command's handler, by area: stepping, history, view, files,
//! training, samples, drawing, regions, compare), `layout` (the frame: side
//! panels, canvas, status bar), `menus` (the menus and shortcuts),
//! `dialogs` (questions, file dialogs, the paths they start from),
//! `background` (work off the UI thread, the animated run, the caches each
//! frame refreshes), `screenshot`, `prefs` and `text` (counts and figures
//! in words).

pub mod assets;
mod background;
pub mod canvas;
pub mod command;
mod commands;
pub mod compare_panel;
mod dialogs;
pub mod document;
pub mod error;
pub mod files;
pub mod framed;
pub mod history;
pub mod job;
mod layout;
mod menus;
pub mod model_panel;
mod prefs;
pub mod quality_panel;
pub mod regions;
pub mod regions_panel;
pub mod samples_panel;
mod screenshot;
pub mod smooth_panel;
pub mod step_panel;
mod text;
pub mod tools;
pub mod train_panel;
pub mod world_mesh;

use crate::geom::Point;
use crate::mesh::QuadMesh;
use crate::pipeline::FinishParams;
use background::{RefitJob, RegionRun};
pub use command::{Command, Dialog};
use compare_panel::{CompareJob, ComparePanel, Comparison};
pub use document::{CorrectionCheck, Document, ModelInfo, RefitFigures, Settings, Target};
pub use error::{EditorError, ScreenshotError};
use files::{Prompt, Recent};
use framed::Framed;
pub use history::History;
use job::{Job, JobDone};
pub use layout::Tab;
use layout::PANEL_WIDTHS;
use model_panel::ModelPanel;
pub use prefs::Prefs;
use quality_panel::{MeshStats, QualityPanel};
use regions_panel::RegionsPanel;
use samples_panel::SamplesPanel;
use smooth_panel::SmoothPanel;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use step_panel::StepPanel;
pub use text::{figure, missing, ordinal, plural, sideways_table};
use tools::{Tool, Tools};
use train_panel::TrainPanel;

/// How the editor starts (`quadex gui`).
#[derive(Clone, Debug, Default)]
pub struct GuiOptions {
    /// Boundary or project to open (default: the shipped example).
    pub open: Option<PathBuf>,
    /// Steps to take after opening.
    pub steps: Option<usize>,
    /// Run to the end after opening.
    pub run: bool,
    /// Save a PNG of the window after the first frames and exit.
    pub screenshot: Option<PathBuf>,
    /// Window size in points.
    pub size: Option<[f32; 2]>,
    /// The panel on the right (`model`, `samples`, `quality`, `smoothing`).
    pub panel: Option<String>,
}

/// A panel (the shape of `egui_demo_lib`'s `View`): draws itself from the
/// document, and from the little else of the editor it shows (`Input`),
/// and returns what the user asked for as commands. A panel changes
/// nothing but its own state.
pub trait View {
    /// What the panel reads besides the document (`()` for most).
    type Input<'a>;

    fn ui(&mut self, ui: &mut egui::Ui, doc: &Document, input: Self::Input<'_>) -> Vec<Command>;
}

/// Which mesh is on the canvas and in the Quality panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshKind {
    /// The mesh as stepped (no cleanup or smoothing).
    Stepped,
    /// The finished mesh of the current settings.
    Finished,
    /// The finished mesh of earlier finishing settings, while the current
    /// ones are computed.
    Updating,
    /// A mesh read from a file.
    Imported,
}

/// The mesh shown.
pub struct Shown<'a> {
    pub mesh: &'a QuadMesh,
    pub kind: MeshKind,
}

/// The figures of the mesh shown, for the panels that report them.
#[derive(Clone, Copy)]
pub struct Figures<'a> {
    /// Which mesh is shown.
    pub kind: MeshKind,
    pub stats: &'a MeshStats,
    /// Changes whenever the mesh as stepped does.
    pub mesh_version: u64,
    /// A run or refit goes on in the background (the panels' commands
    /// wait for it).
    pub busy: bool,
}

/// What the stepping panel shows of the editor: the animated run, and
/// whether there is something to undo or redo.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunState {
    pub animating: bool,
    /// A run or refit goes on in the background: stepping, undo and
    /// reset wait for it (Cancel stops it).
    pub busy: bool,
    pub can_undo: bool,
    pub can_redo: bool,
}

/// What a finished mesh belongs to: the mesh as stepped and the finishing
/// settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinishKey {
    pub mesh_version: u64,
    pub params: FinishParams,
}

/// A finished mesh (cleaned up, remeshed, smoothed).
struct Finished {
    key: FinishKey,
    mesh: QuadMesh,
}

/// The document and its files.
pub struct DocumentState {
    pub doc: Document,
    pub history: History,
    /// The project file the document was opened from or saved to.
    pub project_path: Option<PathBuf>,
    /// Changes since the last save.
    pub dirty: bool,
    /// Bumped whenever the document changes.
    version: u64,
    /// Bumped whenever the mesh as stepped changes.
    mesh_version: u64,
}

/// The canvas view and what is drawn from the document, cached.
pub struct ViewState {
    pub canvas: canvas::View,
    /// Where the canvas was drawn last (screen points).
    pub canvas_rect: egui::Rect,
    domain: canvas::DomainCache,
    mesh: canvas::MeshCache,
    stats: MeshStats,
    stats_key: Option<(u64, MeshKind, usize)>,
    finished: Option<Finished>,
    /// The finishing pass failed or was cancelled for this key.
    finish_failed: Option<FinishKey>,
    /// The element the next step would cut, by mesh version.
    preview: Option<(u64, Vec<[Point; 4]>)>,
    /// The mesher before the last step, by mesh version.
    before_last: Option<(u64, Framed)>,
    /// Front nodes the last element could close onto, by mesh version.
    targets: Option<(u64, Vec<Target>)>,
    /// Front loops of the mesh as stepped, by mesh version.
    front: (u64, Vec<Vec<u32>>),
    /// The world position under the pointer.
    pub hover: Option<Point>,
    empty: QuadMesh,
}

/// The panels' own states.
pub struct Panels {
    pub step: StepPanel,
    pub train: TrainPanel,
    pub tools: Tools,
    pub model: ModelPanel,
    pub samples: SamplesPanel,
    pub smooth: SmoothPanel,
    pub quality: QualityPanel,
    pub compare: ComparePanel,
    /// The Regions panel and tools (a document of several regions).
    pub regions: RegionsPanel,
    pub tab: Tab,
    pub show_left: bool,
    pub show_right: bool,
    /// The widths the user gave the left and right panels (a narrow window
    /// narrows them for the time being).
    pub widths: [f32; 2],
    /// The path in the Export box.
    pub export_path: String,
    /// The Export box holds the default path (it follows the document).
    export_default: Option<String>,
}

/// Work off the UI thread, and the animated run on it.
pub struct Background {
    job: Option<Job>,
    /// Threads of cancelled jobs, joined when they end.
    orphans: Vec<std::thread::JoinHandle<JobDone>>,
    /// Animated run: steps owed to the animation.
    animating: Option<f64>,
    /// An export waiting for the finishing pass.
    pending_export: Option<PathBuf>,
    /// Runs and finishing go to threads (off: they run on the UI thread).
    pub threads: bool,
    /// When the finishing settings last changed.
    settings_changed: Option<std::time::Instant>,
    /// A comparison of models being made.
    compare: Option<CompareJob>,
    /// A refit being made.
    refit: Option<RefitJob>,
    /// The last comparison made.
    comparison: Option<Comparison>,
    /// A run of a document of regions.
    region_run: Option<RegionRun>,
}

/// A question the editor asks before going on.
#[derive(Clone, Debug, PartialEq)]
pub enum Ask {
    /// Unsaved work would be lost by this command.
    Discard(Command),
    /// Unsaved work would be lost by closing the window.
    Close,
}

/// What follows a save the user asked for in a question.
#[derive(Clone, Debug, PartialEq)]
enum Then {
    Run(Command),
    Close,
}

/// The window: status line, questions, file prompts, screenshots.
pub struct Window {
    /// The last message for the user.
    pub status: String,
    pub ask: Option<Ask>,
    prompt: Option<Prompt>,
    /// What to do after the next successful save (a question answered
    /// "Save").
    after_save: Option<Then>,
    /// Close the window on the next frame.
    close_now: bool,
    pub recent: Recent,
    /// The folder of the last mesh exported: where a document of no file
    /// (New, a built-in example) proposes to export and save.
    pub export_dir: Option<PathBuf>,
    close_allowed: bool,
    /// The desktop offers file dialogs (else the prompt in the window).
    pub native_dialogs: bool,
    screenshot: Option<PathBuf>,
    screenshot_requested: bool,
    /// The window size asked for on the command line (it wins over the
    /// size remembered from the last run).
    size: Option<egui::Vec2>,
    title: String,
    frame: u64,
}

pub struct App {
    pub document: DocumentState,
    pub view: ViewState,
    pub panels: Panels,
    pub background: Background,
    pub window: Window,
}

/// True when the two documents have the same mesh as stepped (the same
/// boundary, model, parameters and actions, and the same imported mesh).
fn same_mesh(a: &Document, b: &Document) -> bool {
    let imported = |d: &Document| d.imported().map(|m| m as *const QuadMesh);
    if imported(a) != imported(b) {
        return false;
    }
    match (a.mesher(), b.mesher()) {
        (Some(x), Some(y)) => {
            std::ptr::eq(
                Arc::as_ptr(x.model()) as *const (),
                Arc::as_ptr(y.model()) as *const (),
            ) && x.params() == y.params()
                && x.boundary() == y.boundary()
                && x.actions() == y.actions()
        }
        (None, None) => true,
        _ => false,
    }
}

/// The mesh on the canvas and the Quality panel: a mesh read from a file;
/// the finished mesh (of these settings, or of the previous ones while
/// they are computed); else the mesh as stepped.
fn shown_of<'a>(
    d: &'a DocumentState,
    finished: &'a Option<Finished>,
    empty: &'a QuadMesh,
) -> Shown<'a> {
    let doc = &d.doc;
    if let Some(m) = doc.imported() {
        return Shown {
            mesh: m,
            kind: MeshKind::Imported,
        };
    }
    if let Some(r) = &doc.regions {
        // Each face is finished as it is meshed: the merged mesh is the
        // finished one.
        return Shown {
            mesh: r.shown_mesh(),
            kind: if r.is_done() {
                MeshKind::Finished
            } else {
                MeshKind::Stepped
            },
        };
    }
    if doc.is_done() {
        if let Some(f) = finished
            .as_ref()
            .filter(|f| f.key.mesh_version == d.mesh_version)
        {
            let kind = if f.key.params == doc.settings.finishing() {
                MeshKind::Finished
            } else {
                MeshKind::Updating
            };
            return Shown {
                mesh: &f.mesh,
                kind,
            };
        }
    }
    Shown {
        mesh: doc.mesher().map_or(empty, |m| m.mesh()),
        kind: MeshKind::Stepped,
    }
}

/// The front nodes the last element can close onto, when computed for the
/// mesh as stepped now.
fn targets_of<'a>(d: &DocumentState, v: &'a ViewState) -> &'a [Target] {
    match &v.targets {
        Some((k, t)) if *k == d.mesh_version => t,
        _ => &[],
    }
}

/// The figures of the mesh shown this frame.
fn figures_of<'a>(d: &'a DocumentState, v: &'a ViewState) -> Figures<'a> {
    Figures {
        kind: shown_of(d, &v.finished, &v.empty).kind,
        stats: &v.stats,
        mesh_version: d.mesh_version,
        busy: false,
    }
}

impl App {
    /// The editor over `doc`.
    pub fn new(doc: Document) -> App {
        App {
            document: DocumentState {
                doc,
                history: History::default(),
                project_path: None,
                dirty: false,
                version: 0,
                mesh_version: 0,
            },
            view: ViewState {
                canvas: canvas::View::default(),
                canvas_rect: egui::Rect::NOTHING,
                domain: canvas::DomainCache::default(),
                mesh: canvas::MeshCache::default(),
                stats: MeshStats::default(),
                stats_key: None,
                finished: None,
                finish_failed: None,
                preview: None,
                before_last: None,
                targets: None,
                front: (u64::MAX, Vec::new()),
                hover: None,
                empty: QuadMesh::default(),
            },
            panels: Panels {
                step: StepPanel::default(),
                train: TrainPanel::default(),
                tools: Tools::default(),
                model: ModelPanel::default(),
                samples: SamplesPanel::default(),
                smooth: SmoothPanel::default(),
                quality: QualityPanel::default(),
                compare: ComparePanel::default(),
                regions: RegionsPanel::default(),
                tab: Tab::default(),
                show_left: true,
                show_right: true,
                widths: PANEL_WIDTHS,
                export_path: String::new(),
                export_default: None,
            },
            background: Background {
                job: None,
                orphans: Vec::new(),
                animating: None,
                pending_export: None,
                threads: true,
                settings_changed: None,
                compare: None,
                refit: None,
                comparison: None,
                region_run: None,
            },
            window: Window {
                status: String::new(),
                ask: None,
                prompt: None,
                after_save: None,
                close_now: false,
                recent: Recent::default(),
                export_dir: None,
                close_allowed: false,
                native_dialogs: files::native_dialogs(),
                screenshot: None,
                screenshot_requested: false,
                size: None,
                title: String::new(),
                frame: 0,
            },
        }
    }

    /// The editor as `quadex gui` starts it: the file (or the shipped
    /// example) opened with the remembered settings, then the requested
    /// steps taken.
    pub fn from_options(o: &GuiOptions, prefs: Prefs) -> Result<App, EditorError> {
        let settings = prefs.settings.clone();
        // Remembered settings that no longer load (a model file gone) give
        // way to the defaults.
        let opened = match &o.open {
            Some(path) => Document::open(path, settings)
                .or_else(|_| Document::open(path, Settings::default()))?,
            None => (
                Document::example(assets::DEFAULT_EXAMPLE, settings)
                    .or_else(|_| Document::example(assets::DEFAULT_EXAMPLE, Settings::default()))?,
                Vec::new(),
            ),
        };
        let mut app = App::new(opened.0);
        app.document.history.replayed(opened.1);
        app.set_prefs(prefs);
        if let Some(path) = &o.open {
            app.note_opened(path);
        }
        if let Some(t) = o.panel.as_deref() {
            app.panels.tab = Tab::parse(t).ok_or_else(|| EditorError::UnknownPanel(t.into()))?;
        }
        if let Some(n) = o.steps {
            app.apply(Command::StepN(n));
        }
        if o.run {
            app.apply(Command::RunToEnd);
        }
        app.wait();
        app.window.screenshot = o.screenshot.clone();
        app.window.size = o.size.map(egui::Vec2::from);
        Ok(app)
    }

    pub fn doc(&self) -> &Document {
        &self.document.doc
    }

    pub fn status(&self) -> &str {
        &self.window.status
    }

    /// True while a run goes on in the background.
    pub fn busy(&self) -> bool {
        self.background.job.as_ref().is_some_and(Job::is_run)
            || self.background.refit.is_some()
            || self.background.region_run.is_some()
    }

    /// True while the Model panel measures the model in the background.
    pub fn measuring(&self) -> bool {
        self.panels.model.measuring()
    }

    /// True while the finishing pass goes on in the background.
    pub fn finishing(&self) -> bool {
        self.background.job.as_ref().is_some_and(|j| !j.is_run())
    }

    /// True while threads of cancelled runs still work.
    pub fn cancelled_running(&mut self) -> bool {
        self.background.orphans.retain(|h| !h.is_finished());
        !self.background.orphans.is_empty()
    }

    /// The front nodes the last element can close onto (computed when
    /// the canvas needs them).
    pub fn targets(&self) -> &[Target] {
        targets_of(&self.document, &self.view)
    }

    /// Which mesh is on the canvas.
    pub fn shown_kind(&self) -> MeshKind {
        self.shown().kind
    }

    /// The mesh on the canvas and the Quality panel.
    fn shown(&self) -> Shown<'_> {
        shown_of(&self.document, &self.view.finished, &self.view.empty)
    }

    fn finish_key(&self) -> FinishKey {
        FinishKey {
            mesh_version: self.document.mesh_version,
            params: self.document.doc.settings.finishing(),
        }
    }

    /// The title: the project's file name, else the document's name.
    pub fn title(&self) -> String {
        match &self.document.project_path {
            Some(p) => document::file_name(p),
            None => self.document.doc.name.clone(),
        }
    }

    /// Whether replacing or closing the document would lose work: it
    /// changed since it was opened or saved, and holds something a rerun
    /// does not give back (samples, refitted models, an edited boundary,
    /// hand corrections; steps alone the model makes again).
    pub fn unsaved(&self) -> bool {
        self.document.dirty && self.document.doc.has_work()
    }

    /// The document's name, marked "(changed)" while it holds unsaved work.
    pub fn title_line(&self) -> String {
        let mark = if self.unsaved() { " (changed)" } else { "" };
        format!("{}{mark}", self.title())
    }

    /// Remembers a file opened from a path the user gave.
    fn note_opened(&mut self, path: &Path) {
        self.document.project_path = document::is_project(path).then(|| path.to_path_buf());
        self.window.recent.push(path);
    }

    /// The document changed (`mesh`: the mesh as stepped too).
    fn changed(&mut self, mesh: bool) {
        self.document.version += 1;
        if mesh {
            self.document.mesh_version += 1;
        }
        self.document.dirty = true;
    }

    /// Runs an edit that keeps the document as it was for undo; on failure
    /// the document is left as it was.
    fn edit<T>(
        &mut self,
        name: &'static str,
        f: impl FnOnce(&mut Document) -> Result<T, EditorError>,
    ) -> Result<T, EditorError> {
        let before = self.document.doc.clone();
        match f(&mut self.document.doc) {
            Ok(v) => {
                let mesh = !same_mesh(&before, &self.document.doc);
                self.document.history.edit(before, name);
                self.changed(mesh);
                Ok(v)
            }
            Err(e) => {
                self.document.doc = before;
                Err(e)
            }
        }
    }

    /// [`App::edit`] for an edit that replaces the whole document (New,
    /// Open): its undo brings back the project file too.
    fn replace_document<T>(
        &mut self,
        name: &'static str,
        f: impl FnOnce(&mut Document) -> Result<T, EditorError>,
    ) -> Result<T, EditorError> {
        let project = self.document.project_path.clone();
        let v = self.edit(name, f)?;
        self.document.history.replaced(project);
        Ok(v)
    }

    /// Applies one command; failures go to the status line and leave the
    /// document as it was. A command that would replace a document holding
    /// unsaved work asks first.
    pub fn apply(&mut self, cmd: Command) {
        if self.busy() && !cmd.allowed_while_running() {
            self.window.status = format!("error: {}", EditorError::Busy);
            return;
        }
        if cmd.replaces_document() && self.unsaved() {
            self.window.status = format!("unsaved changes in {}", self.title());
            self.window.ask = Some(Ask::Discard(cmd));
            return;
        }
        self.apply_now(cmd);
    }

    /// Applies a command without asking.
    fn apply_now(&mut self, cmd: Command) {
        // Stepping means meshing: the drawing tool (a loop closed, none
        // begun) gives way to correcting, so that a click on the mesh
        // corrects instead of starting a hole.
        if matches!(
            cmd,
            Command::Step | Command::StepN(_) | Command::RunToEnd | Command::Animate(true)
        ) && matches!(self.panels.tools.tool, Tool::Draw | Tool::Arc)
            && self.panels.tools.drawing.is_empty()
            && self.panels.tools.arc_clicks.is_empty()
        {
            self.panels.tools.tool = Tool::Correct;
        }
        match self.run_command(cmd) {
            Ok(s) => {
                if !s.is_empty() {
                    self.window.status = s;
                }
            }
            Err(e) => self.window.status = format!("error: {e}"),
        }
    }
}

impl eframe::App for App {
    fn update(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        self.ui(ctx);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        if !self.window.screenshot_requested {
            eframe::set_value(storage, eframe::APP_KEY, &self.prefs());
        }
    }
}

/// Runs the editor window.
pub fn run(o: GuiOptions) -> Result<(), EditorError> {
    let size = o.size.unwrap_or([1400.0, 860.0]);
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size(size)
            .with_min_inner_size([640.0, 420.0])
            .with_title("quadex")
            .with_drag_and_drop(true),
        // A screenshot run neither reads nor writes the remembered settings.
        persist_window: o.screenshot.is_none(),
        ..Default::default()
    };
    // A file that cannot be read is reported before a window opens (a
    // boundary that is not valid opens as a draft).
    if let Some(p) = &o.open {
        Document::open(p, Settings::default())?;
    }
    let screenshot = o.screenshot.is_some();
    eframe::run_native(
        "quadex",
        native,
        Box::new(move |cc| {
            let prefs = match cc.storage {
                Some(s) if !screenshot => eframe::get_value(s, eframe::APP_KEY).unwrap_or_default(),
                _ => Prefs::default(),
            };
            let app = App::from_options(&o, prefs).map_err(
                |e| -> Box<dyn std::error::Error + Send + Sync> { e.to_string().into() },
            )?;
            Ok(Box::new(app))
        }),
    )
    .map_err(|cause| EditorError::Window { cause })
}

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

pub mod assets;
pub mod canvas;
pub mod command;
pub mod compare_panel;
pub mod document;
pub mod error;
pub mod files;
pub mod framed;
pub mod history;
pub mod job;
pub mod model_panel;
pub mod quality_panel;
pub mod regions;
pub mod regions_panel;
pub mod samples_panel;
pub mod smooth_panel;
pub mod step_panel;
pub mod tools;
pub mod train_panel;
pub mod world_mesh;

use crate::geom::{Aabb, Point};
use crate::mesh::QuadMesh;
use crate::pipeline::FinishParams;
pub use command::{Command, Dialog};
use compare_panel::{CompareJob, ComparePanel, CompareState, Comparison};
pub use document::{CorrectionCheck, Document, ModelInfo, RefitFigures, Settings, Target};
pub use error::{EditorError, ScreenshotError};
use files::{Prompt, Recent};
use framed::Framed;
pub use history::History;
use job::{Job, JobDone, Record, Work};
use model_panel::ModelPanel;
use quality_panel::{MeshStats, QualityPanel};
use regions_panel::RegionsPanel;
use samples_panel::SamplesPanel;
use serde::{Deserialize, Serialize};
use smooth_panel::SmoothPanel;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use step_panel::StepPanel;
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

/// Frames drawn before a screenshot is taken (layout and view settle).
const SCREENSHOT_FRAME: u64 = 3;

/// Steps ×N above this run in the background.
const BACKGROUND_STEPS: usize = 200;

/// A finishing-settings change waits this long for the next before the
/// finished mesh is computed again (a dragged value changes every frame).
const FINISH_DEBOUNCE: std::time::Duration = std::time::Duration::from_millis(250);

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

/// The panels on the right.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Tab {
    #[default]
    Quality,
    Model,
    Samples,
    Smoothing,
    Compare,
}

impl Tab {
    const ALL: [Tab; 5] = [
        Tab::Quality,
        Tab::Model,
        Tab::Samples,
        Tab::Smoothing,
        Tab::Compare,
    ];

    fn name(self) -> &'static str {
        match self {
            Tab::Quality => "Quality",
            Tab::Model => "Model",
            Tab::Samples => "Training set",
            Tab::Smoothing => "Smoothing",
            Tab::Compare => "Compare",
        }
    }

    fn hint(self) -> &'static str {
        match self {
            Tab::Quality => "Figures and histograms of the mesh shown",
            Tab::Model => "How well the model fits the samples, and the critical factors",
            Tab::Samples => "Your training samples: filter, delete, import, export, collect",
            Tab::Smoothing => "Cleanup, remeshing and smoothing of the finished mesh",
            Tab::Compare => "The boundary meshed by several models side by side",
        }
    }

    fn parse(s: &str) -> Option<Tab> {
        match s {
            "quality" => Some(Tab::Quality),
            "model" => Some(Tab::Model),
            "samples" | "training" => Some(Tab::Samples),
            "smoothing" => Some(Tab::Smoothing),
            "compare" => Some(Tab::Compare),
            _ => None,
        }
    }
}

/// What the editor remembers between runs (eframe persistence), in one
/// struct: settings, recent files and the panels' choices, not the
/// document.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Prefs {
    pub settings: Settings,
    pub recent: Recent,
    pub step: StepPanel,
    pub quality: QualityPanel,
    pub tab: Tab,
    pub show_left: bool,
    pub show_right: bool,
    /// The widths the user gave the left and right panels.
    pub widths: [f32; 2],
    /// The folder of the last mesh exported (a document of no file
    /// proposes it).
    pub export_dir: Option<PathBuf>,
}

impl Default for Prefs {
    fn default() -> Self {
        Prefs {
            settings: Settings::default(),
            recent: Recent::default(),
            step: StepPanel::default(),
            quality: QualityPanel::default(),
            tab: Tab::default(),
            show_left: true,
            show_right: true,
            widths: PANEL_WIDTHS,
            export_dir: None,
        }
    }
}

/// The share of the canvas the last step spans after View ▸ Zoom to the
/// last step.
const ZOOM_TO_STEP_SHARE: f64 = 0.4;

/// The side panels' widths at first (points): left, right.
const PANEL_WIDTHS: [f32; 2] = [290.0, 400.0];

/// The side panels' narrowest widths: left, right.
const PANEL_MIN_WIDTHS: [f32; 2] = [170.0, 190.0];

/// The share of the window a side panel may take at most: left, right.
const PANEL_MAX_SHARES: [f32; 2] = [0.24, 0.28];

/// Gives side panel `id` the width the user chose, `want`, as far as
/// `max` allows. egui keeps (and persists) the width a narrower window
/// forced on a panel, so a window made wide again would keep it narrow.
fn restore_panel_width(ctx: &egui::Context, id: egui::Id, want: f32, max: f32) {
    let w = want.min(max);
    if let Some(mut state) = egui::containers::panel::PanelState::load(ctx, id) {
        if state.rect.width() + 0.5 < w {
            state.rect.set_width(w);
            ctx.data_mut(|d| d.insert_persisted(id, state));
        }
    }
}

/// The width the user chose for a panel shown `shown` wide: any width
/// under the window's bound `max` is a choice (a drag), as is a width over
/// the last choice; at the bound the window may have forced it.
fn chosen_panel_width(want: f32, shown: f32, max: f32) -> f32 {
    if shown < max - 0.5 || shown > want {
        shown
    } else {
        want
    }
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

/// A run of a document of regions in a thread: its faces stepped on a
/// copy of the stepper, taken into the document when it ends (a
/// cancelled run is dropped, the mesh stays as before it).
struct RegionRun {
    handle: std::thread::JoinHandle<RegionRunDone>,
    cancel: Arc<std::sync::atomic::AtomicBool>,
    steps: Arc<std::sync::atomic::AtomicUsize>,
    face: Arc<std::sync::atomic::AtomicUsize>,
    faces: usize,
    started: std::time::Instant,
}

/// What a run of a document of regions gives back.
struct RegionRunDone {
    stepper: crate::regions::RegionStepper,
    steps: usize,
    last: Option<crate::extract::StepReport>,
    error: Option<crate::regions::RegionError>,
    /// The merged mesh, when every face is meshed.
    mesh: Option<Result<crate::regions::RegionMesh, crate::regions::RegionError>>,
}

impl RegionRun {
    /// Steps `stepper` up to `max` steps (to the end with `usize::MAX`).
    fn start(mut stepper: crate::regions::RegionStepper, max: usize) -> RegionRun {
        use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
        let cancel = Arc::new(AtomicBool::new(false));
        let steps = Arc::new(AtomicUsize::new(0));
        let face = Arc::new(AtomicUsize::new(stepper.current()));
        let faces = stepper.faces().len();
        let (c, st, f) = (cancel.clone(), steps.clone(), face.clone());
        let handle = std::thread::spawn(move || {
            let (mut k, mut last, mut error) = (0, None, None);
            while !stepper.is_done() && k < max && !c.load(Ordering::Relaxed) {
                match stepper.step() {
                    Ok(crate::extract::StepOutcome::Stepped(r)) => {
                        last = Some(*r);
                        k += 1;
                        st.store(k, Ordering::Relaxed);
                        f.store(stepper.current(), Ordering::Relaxed);
                    }
                    Ok(crate::extract::StepOutcome::Done) => {}
                    Err(e) => {
                        error = Some(e);
                        break;
                    }
                }
            }
            let mesh = stepper.is_done().then(|| stepper.clone().finish());
            RegionRunDone {
                stepper,
                steps: k,
                last,
                error,
                mesh,
            }
        });
        RegionRun {
            handle,
            cancel,
            steps,
            face,
            faces,
            started: std::time::Instant::now(),
        }
    }
}

/// A refit made in a thread ([`document::RefitTask::run`]), taken into
/// the document when it is done (a cancelled one is dropped).
struct RefitJob {
    handle: std::thread::JoinHandle<Result<document::RefitDone, String>>,
    phase: Arc<std::sync::Mutex<document::RefitPhase>>,
    /// Mesh the rest with the refitted model once it is taken.
    mesh_rest: bool,
    started: std::time::Instant,
}

impl RefitJob {
    /// What the refit is doing now.
    fn phase(&self) -> String {
        self.phase
            .lock()
            .map_or_else(|_| String::new(), |p| p.describe())
    }
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

/// A table wider than its panel: it scrolls sideways under a solid bar
/// that is always shown (a floating bar, shown on hover only, leaves the
/// clipped columns unannounced), and its rows are never wrapped.
pub fn sideways_table(ui: &mut egui::Ui, id: &str, table: impl FnOnce(&mut egui::Ui)) {
    ui.scope(|ui| {
        ui.spacing_mut().scroll = egui::style::ScrollStyle::solid();
        egui::ScrollArea::horizontal()
            .id_salt(id)
            .scroll_bar_visibility(egui::scroll_area::ScrollBarVisibility::AlwaysVisible)
            .show(ui, |ui| {
                ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
                table(ui)
            });
    });
}

/// "1 quad", "2 quads".
pub fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

/// The quads of `n` that miss a criterion `share` of them meet, as a
/// count ("3 of 198,007 outside"): a share rounded to 100.0 % would hide
/// them.
pub fn missing(share: f64, n: usize, word: &str) -> String {
    let met = (share * n as f64).round().clamp(0.0, n as f64) as usize;
    let miss = n - met;
    let grouped = crate::compare::grouped;
    if miss == 0 {
        format!("none of {} {word}", grouped(n))
    } else {
        format!("{} of {} {word}", grouped(miss), grouped(n))
    }
}

/// "1st", "2nd", "3rd", "4th", "11th", "22nd".
pub fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// A fit figure with `decimals`, or "n/a" when it is not finite.
pub fn figure(v: f64, decimals: usize) -> String {
    if v.is_finite() {
        format!("{v:.decimals$}")
    } else {
        "n/a".into()
    }
}

/// The stem of a document name: `plate.quadex.json` gives `plate`.
fn stem(name: &str) -> String {
    let s = name.split('.').next().unwrap_or("");
    if s.is_empty() {
        "untitled".into()
    } else {
        s.to_string()
    }
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

    /// The remembered state.
    pub fn prefs(&self) -> Prefs {
        Prefs {
            settings: self.document.doc.settings.clone(),
            recent: self.window.recent.clone(),
            step: self.panels.step.clone(),
            quality: self.panels.quality.clone(),
            tab: self.panels.tab,
            show_left: self.panels.show_left,
            show_right: self.panels.show_right,
            widths: self.panels.widths,
            export_dir: self.window.export_dir.clone(),
        }
    }

    /// Takes the remembered state (the settings are the document's own).
    pub fn set_prefs(&mut self, p: Prefs) {
        self.window.recent = p.recent;
        self.window.export_dir = p.export_dir;
        // (Lists remembered before the list kept only files Open reads.)
        self.window.recent.0.retain(|f| document::opens(f));
        self.panels.step = p.step;
        self.panels.quality = p.quality;
        self.panels.tab = p.tab;
        self.panels.show_left = p.show_left;
        self.panels.show_right = p.show_right;
        // Widths no panel may have (a hand-edited or damaged store) are
        // taken as the first ones.
        for k in 0..2 {
            let w = p.widths[k];
            self.panels.widths[k] = if w.is_finite() && w >= PANEL_MIN_WIDTHS[k] {
                w
            } else {
                PANEL_WIDTHS[k]
            };
        }
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

    /// Waits for the background work, if any, and takes its result; then
    /// finishes the mesh if it is complete (as the frames would).
    pub fn wait(&mut self) {
        if let Some(r) = self.background.refit.take() {
            self.refit_joined(r);
        }
        if let Some(mut j) = self.background.job.take() {
            let done = j.wait();
            self.job_done(j, done);
        }
        if let Some(r) = self.background.region_run.take() {
            self.region_run_done(r);
        }
        self.compare_done();
        if self.document.doc.has_mesh() && self.document.doc.imported().is_none() {
            let key = self.finish_key();
            if self.view.finished.as_ref().is_none_or(|f| f.key != key)
                && self.view.finish_failed != Some(key)
            {
                if let Err(e) = self.finished_mesh() {
                    self.window.status = format!("error: {e}");
                }
            }
        }
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

    fn run_command(&mut self, cmd: Command) -> Result<String, EditorError> {
        match cmd {
            Command::Step => self.step_sync(1).map(|k| match self.document.doc.last() {
                Some(r) if k == 1 => {
                    format!("step {}: {}", r.index + 1, document::kind_name(r.kind))
                }
                _ if k == 1 => "stepped".into(),
                _ => "the mesh is complete".into(),
            }),
            Command::StepN(n) if self.background.threads && n > BACKGROUND_STEPS => {
                if self.document.doc.regions.is_some() {
                    self.start_region_run(n)?;
                    return Ok(format!("taking {n} steps…"));
                }
                self.start_run(n, "stepping", Record::Steps)?;
                Ok(format!("taking {n} steps…"))
            }
            Command::StepN(n) => self.step_sync(n).map(|k| plural(k, "step")),
            Command::RunToEnd if self.background.threads && self.document.doc.regions.is_some() => {
                self.start_region_run(usize::MAX)?;
                Ok("running every region to the end…".into())
            }
            Command::RunToEnd if self.background.threads => {
                self.start_run(usize::MAX, "running to the end", Record::Steps)?;
                Ok("running to the end…".into())
            }
            Command::RunToEnd => self
                .step_sync(usize::MAX)
                .map(|k| format!("{} to the end", plural(k, "step"))),
            Command::Animate(on) => {
                if on && !self.document.doc.can_step() {
                    return Err(self.no_boundary());
                }
                self.background.animating = on.then_some(0.0);
                Ok(if on { "running…" } else { "paused" }.into())
            }
            Command::Cancel => Ok(self.cancel()),
            Command::Compare(names) => self.start_compare(&names),
            Command::StopCompare => Ok(match &self.background.compare {
                Some(j) => {
                    j.cancel();
                    "the comparison stops after the model it is meshing".into()
                }
                None => String::new(),
            }),
            Command::Quit => {
                // Closing asks first when there is unsaved work.
                self.window.close_now = true;
                Ok(String::new())
            }
            Command::Undo => {
                let before = self.document.doc.clone();
                let what = self
                    .document
                    .history
                    .undo(&mut self.document.doc, &mut self.document.project_path);
                let mesh = what.is_some_and(|w| w.step) || !same_mesh(&before, &self.document.doc);
                if what.is_some() {
                    self.changed(mesh);
                }
                let left = self.document.doc.steps();
                Ok(match what {
                    None if self.document.doc.regions.is_some() => "nothing to undo in this face (undo goes back within the face being meshed; Reset starts every face again)".into(),
                    None => "nothing to undo".into(),
                    // Steps undo one by one (to go back to an element to
                    // correct); the way back to the start is Reset.
                    Some(w) if w.step && left > 1 => format!(
                        "undone: step ({left} steps left; Reset, Ctrl+R, starts the mesh again)"
                    ),
                    Some(w) => format!("undone: {}", w.name),
                })
            }
            Command::Redo => {
                let before = self.document.doc.clone();
                let what = self
                    .document
                    .history
                    .redo(&mut self.document.doc, &mut self.document.project_path)?;
                let mesh = what.is_some_and(|w| w.step) || !same_mesh(&before, &self.document.doc);
                if what.is_some() {
                    self.changed(mesh);
                }
                Ok(what.map_or("nothing to redo".into(), |w| format!("redone: {}", w.name)))
            }
            Command::Reset => self.edit("reset", |d| d.reset().map(|_| "restarted".into())),
            Command::FitView => {
                self.view.canvas.fit_pending = true;
                Ok(String::new())
            }
            Command::ZoomToStep => {
                let doc = &self.document.doc;
                let (Some(r), Some(m)) = (doc.last(), doc.mesher()) else {
                    return Err(EditorError::NoStep);
                };
                let mesh = m.mesh();
                let pts: Vec<Point> = r
                    .leading
                    .iter()
                    .chain(r.reference.iter())
                    .chain(r.quads.iter().flatten())
                    .filter_map(|&v| mesh.nodes.get(v as usize).copied())
                    .collect();
                let b = Aabb::of(pts.iter().copied()).ok_or(EditorError::NoStep)?;
                let rect = self.view.canvas_rect;
                self.view
                    .canvas
                    .zoom_to(rect, b.min, b.max, ZOOM_TO_STEP_SHARE);
                Ok(format!("zoomed to step {} (F fits the view again)", r.index + 1))
            }
            Command::New => {
                let settings = self.document.doc.portable_settings();
                self.replace_document("new", |d| {
                    *d = Document::empty(settings);
                    Ok(())
                })?;
                self.after_open(None);
                self.panels.tools.tool = Tool::Draw;
                Ok("a new boundary: click on the canvas to place the outer loop's nodes".into())
            }
            Command::Open(path) => {
                let settings = self.document.doc.portable_settings();
                let replayed = self.replace_document("open", |d| {
                    let (doc, replayed) = Document::open(&path, settings)?;
                    *d = doc;
                    Ok(replayed)
                })?;
                self.document.history.replayed(replayed);
                self.after_open(Some(&path));
                Ok(self.opened_message(&path.display().to_string()))
            }
            Command::OpenExample(name) => {
                let settings = self.document.doc.portable_settings();
                self.replace_document("open", |d| {
                    *d = Document::example(name, settings)?;
                    Ok(())
                })?;
                self.after_open(None);
                Ok(self.opened_message(name))
            }
            Command::Save => match self.document.project_path.clone() {
                Some(p) => self.save(&p),
                None => {
                    self.dialog(Dialog::SaveProjectAs);
                    Ok(String::new())
                }
            },
            Command::SaveProject(path) => self.save(&path),
            Command::SaveBoundary(path) => {
                self.document.doc.save_boundary(&path)?;
                self.window.recent.push(&path);
                Ok(format!("saved the boundary to {}", path.display()))
            }
            Command::Dialog(d) => {
                self.dialog(d);
                Ok(String::new())
            }
            Command::Export(path) => self.export(path),
            Command::SetSettings(s) => {
                let finishing = self.document.doc.settings.same_steps(&s);
                let restarted = self.edit("settings", |d| d.set_settings(s))?;
                if finishing {
                    self.background.settings_changed = Some(std::time::Instant::now());
                }
                Ok(if restarted {
                    "settings changed; mesh restarted".into()
                } else {
                    "settings changed".into()
                })
            }
            Command::UseModel(path) => {
                let s = Settings {
                    model: path.display().to_string(),
                    ..self.document.doc.settings.clone()
                };
                self.run_command(Command::SetSettings(s))
            }
            Command::AppendLast => self.edit("append sample", |d| {
                d.append_last()
                    .map(|n| format!("sample appended ({} of yours)", plural(n, "sample")))
            }),
            Command::CorrectLast {
                element_type,
                pn,
                snap_to,
            } => {
                let before = self.cached_before_last();
                self.edit("correct element", |d| {
                    d.correct_last(element_type, pn, snap_to, before)
                        .map(|n| format!("element corrected ({} of yours)", plural(n, "sample")))
                })
            }
            Command::Refit { form, mesh_rest } => {
                let task = self.document.doc.refit_task(form)?;
                if self.background.threads {
                    let phase = Arc::new(std::sync::Mutex::new(document::RefitPhase::Collecting));
                    let p = phase.clone();
                    let handle = std::thread::spawn(move || {
                        task.run(|at| {
                            if let Ok(mut now) = p.lock() {
                                *now = at;
                            }
                        })
                        .map_err(|e| e.to_string())
                    });
                    self.background.refit = Some(RefitJob {
                        handle,
                        phase,
                        mesh_rest,
                        started: std::time::Instant::now(),
                    });
                    return Ok(format!(
                        "refitting the {} form in the background…",
                        form.name()
                    ));
                }
                let done = task.run(|_| {})?;
                self.refit_done(done, mesh_rest)
            }
            Command::SaveModel(path) => {
                let name = self.document.doc.save_model(&path)?;
                Ok(format!("saved the model {name} to {}", path.display()))
            }
            Command::Finish => {
                self.view.finish_failed = None;
                Ok("finishing the mesh…".into())
            }
            Command::ImportSamples(p) => self.edit("import samples", |d| {
                d.import_samples(&p)
                    .map(|n| format!("imported {} from {}", plural(n, "sample"), p.display()))
            }),
            Command::ExportSamples(p) => {
                self.document.doc.export_samples(&p)?;
                Ok(format!(
                    "wrote {} to {}",
                    plural(self.document.doc.training.len(), "sample"),
                    p.display()
                ))
            }
            Command::DeleteSamples(idx) => self.edit("delete samples", |d| {
                Ok(format!("{} left", plural(d.delete_samples(&idx), "sample")))
            }),
            Command::CollectFromMesh => {
                let mesh = self.finished_mesh()?;
                let quads = mesh.quads.len();
                let name = self.document.doc.name.clone();
                self.edit("collect samples", |d| {
                    d.collect_samples(&name, mesh).map(|n| {
                        let [lo, hi] = crate::reference::DEFAULT_MODEL_TURN;
                        format!(
                            "{} collected from the mesh's {} (about {} a quad: each corner of a good quad is P0 for each of the three element types, once for every way the front continues along mesh edges beyond l1 and r1 turning within {lo} to {hi} degrees, as for the shipped model: `quadex samples --turn {lo},{hi}`)",
                            plural(n, "sample"),
                            plural(quads, "quad"),
                            (n as f64 / quads.max(1) as f64).round()
                        )
                    })
                })
            }
            Command::CollectFromFile(p) => self.edit("collect samples", |d| {
                d.collect_from_file(&p)
                    .map(|n| format!("{} collected from {}", plural(n, "sample"), p.display()))
            }),
            Command::ToRegions => self.edit("regions", |d| {
                d.to_regions()?;
                Ok("a document of regions: split it with the interface tool, name its groups and regions in the Regions panel".into())
            }),
            Command::SplitRegion { from, through, to } => self.graph_edit("interface", |g| {
                regions::with_interface(g, from, &through, to)
            }),
            Command::NameGroup {
                segments,
                name,
                tag,
            } => self.graph_edit("name group", |g| {
                regions::with_group(g, &segments, &name, tag)
            }),
            Command::NameRegion { at, name, tag } => self.graph_edit("name region", |g| {
                regions::with_region(g, at, &name, tag)
            }),
            Command::SetSize(h) => self.edit("size", |d| {
                d.set_size(h)?;
                let nodes = match &d.regions {
                    Some(r) => r.graph.points.len(),
                    None => d.draft.node_count(),
                };
                Ok(format!(
                    "cut at size {h}: {}; mesh restarted",
                    plural(nodes, "boundary node")
                ))
            }),
            Command::SetDraft { draft, what } => self.edit(what, |d| {
                d.set_draft(draft)?;
                Ok(match &d.problem {
                    None => "boundary changed; mesh restarted".to_string(),
                    Some(crate::boundary::BoundaryError::Empty) => String::new(),
                    Some(e) => format!("not a valid boundary yet: {e}"),
                })
            }),
        }
    }

    /// Takes a refit made into the document (one undo takes it back, and
    /// the rest it meshes).
    fn refit_done(
        &mut self,
        done: document::RefitDone,
        mesh_rest: bool,
    ) -> Result<String, EditorError> {
        let f = self.edit("refit", |d| d.take_refit(done))?;
        let mut msg = format!(
            "refit made {} from {} and {} of yours: Xn R {} to {}, Yn R {} to {}",
            f.model,
            plural(f.samples, "sample"),
            plural(f.corrections, "correction"),
            figure(f.before.1.r, 3),
            figure(f.after.1.r, 3),
            figure(f.before.2.r, 3),
            figure(f.after.2.r, 3),
        );
        if f.repeated > 0 {
            msg.push_str(&format!(
                "; {} of yours {} samples already in the set and {} nothing",
                plural(f.repeated, "sample"),
                if f.repeated == 1 { "repeats" } else { "repeat" },
                if f.repeated == 1 { "adds" } else { "add" },
            ));
        }
        if !f.worse.is_empty() {
            msg.push_str(&format!(
                "; it meshes this boundary worse: {}",
                f.worse.join(", ")
            ));
        }
        if mesh_rest && !self.document.doc.is_done() {
            if self.background.threads {
                self.start_run(usize::MAX, "meshing the rest", Record::WithLastEdit)?;
                return Ok(format!("{msg}; meshing the rest…"));
            }
            // Without threads: the steps join the refit's edit.
            let m = self
                .document
                .doc
                .meshing
                .as_mut()
                .ok_or(EditorError::NoStep)?;
            let mut last = None;
            let res = m.mesher.run_with(|r, _| {
                last = Some(r.clone());
                std::ops::ControlFlow::Continue(())
            });
            if last.is_some() {
                m.last = last;
            }
            self.changed(true);
            res?;
        }
        Ok(msg)
    }

    /// Takes a refit's thread's result (its error to the status line).
    fn refit_joined(&mut self, r: RefitJob) {
        let res = match r.handle.join() {
            Ok(Ok(done)) => self.refit_done(done, r.mesh_rest),
            Ok(Err(e)) => Err(EditorError::Refit(e)),
            Err(_) => Err(EditorError::JobPanicked),
        };
        match res {
            Ok(msg) => self.window.status = msg,
            Err(e) => self.window.status = format!("error: {e}"),
        }
    }

    /// An edit of a document of regions: the new graph from the current
    /// one, validated (an invalid graph is kept with its problem).
    fn graph_edit(
        &mut self,
        what: &'static str,
        f: impl FnOnce(&crate::pslg::Pslg) -> Result<crate::pslg::Pslg, EditorError>,
    ) -> Result<String, EditorError> {
        let graph = match &self.document.doc.regions {
            Some(r) => f(&r.graph)?,
            None => {
                return Err(EditorError::RegionEdit(
                    "regions and groups are edited in a document of regions (open a file with several regions)".into(),
                ))
            }
        };
        self.edit(what, |d| {
            d.set_graph(graph)?;
            let r = d.regions.as_ref().ok_or(EditorError::NotFinished)?;
            Ok(match &r.problem {
                None => format!(
                    "{what}: {} in {}; mesh restarted",
                    plural(r.faces.len(), "face"),
                    plural(r.legend.len(), "region")
                ),
                Some(e) => format!("{what}: not a valid graph yet: {e}"),
            })
        })
    }

    /// Starts a run of a document of regions in the background (without
    /// threads: on this thread, at once).
    fn start_region_run(&mut self, max: usize) -> Result<(), EditorError> {
        let r = self
            .document
            .doc
            .regions
            .as_ref()
            .ok_or_else(|| self.no_boundary())?;
        let stepper = r.stepper.clone().ok_or_else(|| r.no_graph())?;
        let run = RegionRun::start(stepper, max);
        if self.background.threads {
            self.background.region_run = Some(run);
        } else {
            self.region_run_done(run);
        }
        Ok(())
    }

    /// Takes a finished run of a document of regions into the document.
    fn region_run_done(&mut self, run: RegionRun) {
        let faces = run.faces;
        let Ok(done) = run.handle.join() else {
            self.window.status = format!("error: {}", EditorError::JobPanicked);
            return;
        };
        let Some(r) = self.document.doc.regions.as_mut() else {
            return;
        };
        r.take_run(done.stepper, done.steps, done.last);
        let mut error = done.error.map(EditorError::from);
        match done.mesh {
            Some(Ok(m)) => r.mesh = Some(Arc::new(m)),
            Some(Err(e)) => error = Some(e.into()),
            None => {}
        }
        r.sync_shown();
        let complete = r.is_done();
        self.document.history.steps(done.steps);
        if done.steps > 0 {
            self.changed(true);
        }
        self.window.status = match error {
            Some(e) => format!("error after {}: {e}", plural(done.steps, "step")),
            None if complete => format!(
                "{} taken, mesh complete ({} meshed)",
                plural(done.steps, "step"),
                plural(faces, "face")
            ),
            None => plural(done.steps, "step") + " taken",
        };
    }

    /// Starts meshing the boundary with each of the models `names` (the
    /// Compare panel), with the document's extraction and finishing
    /// settings; without threads it is done at once.
    fn start_compare(&mut self, names: &[String]) -> Result<String, EditorError> {
        let doc = &self.document.doc;
        let boundary = doc.boundary().ok_or_else(|| self.no_boundary())?.clone();
        let models = names
            .iter()
            .map(|n| document::load_model(n, &doc.models).map(|(m, _)| (n.clone(), m)))
            .collect::<Result<Vec<_>, _>>()?;
        let params = crate::pipeline::Params {
            extract: doc.settings.params(),
            finish: doc.settings.finishing(),
        };
        let job = CompareJob::start(boundary, models, params);
        if let Some(old) = self.background.compare.replace(job) {
            old.cancel();
        }
        if !self.background.threads {
            self.compare_done();
            return Ok(self.window.status.clone());
        }
        Ok(format!("comparing {}…", plural(names.len(), "model")))
    }

    /// Takes the comparison's outcomes when its thread is done.
    fn compare_done(&mut self) {
        if let Some(mut j) = self.background.compare.take() {
            if let Some(outcomes) = j.wait() {
                let finished = outcomes.iter().filter(|o| o.finished).count();
                self.window.status = format!(
                    "compared {}: {finished} finished (the Compare panel)",
                    plural(outcomes.len(), "model")
                );
                self.background.comparison = Some(Comparison {
                    boundary: j.boundary.clone(),
                    outcomes,
                });
            }
        }
    }

    /// True while a comparison of models is being made.
    pub fn comparing(&self) -> bool {
        self.background.compare.is_some()
    }

    /// The last comparison of models made (the Compare panel).
    pub fn comparison(&self) -> Option<&Comparison> {
        self.background.comparison.as_ref()
    }

    fn no_boundary(&self) -> EditorError {
        EditorError::NoBoundary(
            self.document
                .doc
                .problem
                .clone()
                .unwrap_or(crate::boundary::BoundaryError::Empty),
        )
    }

    /// After a document was opened or made: its file, a fresh view, the
    /// export path beside it.
    fn after_open(&mut self, path: Option<&Path>) {
        match path {
            Some(p) => self.note_opened(p),
            None => self.document.project_path = None,
        }
        self.document.dirty = false;
        self.view.canvas.fit_pending = true;
        self.background.animating = None;
        // A file opened is to be meshed: a click on it corrects, it does
        // not start a loop (New chooses the drawing tool after this). A
        // file opened as a draft to fix gets the Move tool, which draws
        // the draft with its nodes at fault marked.
        self.panels.tools.drop_drawing();
        self.panels.tools.tool = if self.document.doc.problem.is_some() {
            Tool::Move
        } else {
            Tool::Correct
        };
    }

    fn opened_message(&self, name: &str) -> String {
        match &self.document.doc.problem {
            None => format!("opened {name}"),
            Some(e) => format!("opened {name} as a draft to fix: {e}"),
        }
    }

    /// Stops the background run (the document stays as before it), the
    /// finishing pass, or the animation.
    fn cancel(&mut self) -> String {
        let was_animating = self.background.animating.take().is_some();
        if self.background.refit.take().is_some() {
            // The thread cannot be stopped; a global fit it makes is kept
            // for the next refit, the rest is dropped.
            return "cancelled the refit: the model is as before it".into();
        }
        if self.panels.tools.drop_drawing() {
            return "dropped the loop being drawn".into();
        }
        if self.panels.regions.drop_curve() {
            return "dropped the curve being drawn".into();
        }
        if let Some(run) = self.background.region_run.take() {
            run.cancel.store(true, std::sync::atomic::Ordering::Relaxed);
            let steps = run.steps.load(std::sync::atomic::Ordering::Relaxed);
            // The thread stops after the step it takes.
            let _ = run.handle.join();
            return format!(
                "cancelled: the run is dropped ({} taken), the mesh is as before it",
                plural(steps, "step")
            );
        }
        match self.background.job.take() {
            Some(j) if j.is_run() => {
                let (steps, _, _) = j.progress();
                if let Some(h) = j.cancel() {
                    self.background.orphans.push(h);
                }
                self.background.pending_export = None;
                format!(
                    "cancelled: the run is dropped ({} taken), the mesh is as before it",
                    plural(steps, "step")
                )
            }
            Some(j) => {
                self.view.finish_failed = Some(j.key);
                if let Some(h) = j.cancel() {
                    self.background.orphans.push(h);
                }
                self.background.pending_export = None;
                "cancelled the finishing pass (Mesh ▸ Finish the mesh starts it again)".into()
            }
            None if was_animating => "paused".into(),
            None => String::new(),
        }
    }

    /// Steps on the UI thread; records them for undo.
    fn step_sync(&mut self, n: usize) -> Result<usize, EditorError> {
        if let Some(r) = &self.document.doc.regions {
            if r.stepper.is_none() {
                return Err(r.no_graph());
            }
        } else if self.document.doc.meshing.is_none() {
            return Err(self.no_boundary());
        }
        let before = (n == 1)
            .then(|| self.document.doc.mesher().cloned())
            .flatten();
        let mut k = 0;
        let res = loop {
            if k == n {
                break Ok(k);
            }
            match self.document.doc.step() {
                Ok(true) => k += 1,
                Ok(false) => break Ok(k),
                Err(e) => break Err(e),
            }
        };
        self.document.history.steps(k);
        if k > 0 {
            self.changed(true);
            if let (1, Some(b)) = (k, before) {
                self.view.before_last = Some((self.document.mesh_version, b));
            }
        }
        res
    }

    /// The mesher before the last step, when it is at hand.
    fn cached_before_last(&mut self) -> Option<Framed> {
        match self.view.before_last.take() {
            Some((v, m)) if v == self.document.mesh_version => Some(m),
            _ => None,
        }
    }

    /// Starts a run in the background (a finishing pass going on is
    /// dropped: the run makes a new mesh).
    fn start_run(
        &mut self,
        n: usize,
        what: &'static str,
        record: Record,
    ) -> Result<(), EditorError> {
        let mesher = self
            .document
            .doc
            .mesher()
            .cloned()
            .ok_or_else(|| self.no_boundary())?;
        if let Some(j) = self.background.job.take() {
            if let Some(h) = j.cancel() {
                self.background.orphans.push(h);
            }
        }
        let finish = self.document.doc.settings.finishing();
        self.background.job = Some(Job::start(
            mesher,
            Work::Run {
                max_steps: n,
                finish: Some(finish),
            },
            what,
            record,
            self.finish_key(),
        ));
        Ok(())
    }

    /// Takes a background job's result into the document.
    fn job_done(&mut self, job: Job, done: Option<JobDone>) {
        let Some(done) = done else {
            self.window.status = format!("error: {}", EditorError::JobPanicked);
            return;
        };
        if job.is_run() {
            if done.steps > 0 {
                if let Some(m) = self.document.doc.meshing.as_mut() {
                    m.mesher = done.mesher;
                    if done.last.is_some() {
                        m.last = done.last;
                    }
                }
                if job.record == Record::Steps {
                    self.document.history.steps(done.steps);
                }
                self.changed(true);
            }
            let key = self.finish_key();
            match done.finished {
                Some(Ok(mesh)) => self.view.finished = Some(Finished { key, mesh }),
                Some(Err(e)) => {
                    self.view.finish_failed = Some(key);
                    self.window.status = format!("error: {e}");
                    return;
                }
                None => {}
            }
            let what = if job.record == Record::WithLastEdit {
                "refitted, then meshed the rest: "
            } else {
                ""
            };
            // A refit's warning (it meshes this boundary worse) stays in
            // the status line that replaces the refit's own.
            let worse = match (&job.record, &self.document.doc.last_refit) {
                (Record::WithLastEdit, Some(f)) if !f.worse.is_empty() => {
                    format!(
                        "; the refitted model meshes this boundary worse: {}",
                        f.worse.join(", ")
                    )
                }
                _ => String::new(),
            };
            self.window.status = match done.error {
                Some(e) => format!(
                    "{what}error after {}: {e}{worse}",
                    plural(done.steps, "step")
                ),
                None => {
                    let all = self.document.doc.steps();
                    format!(
                        "{what}{} taken{}{}{worse}",
                        plural(done.steps, "step"),
                        if all > done.steps {
                            format!(" ({all} in all)")
                        } else {
                            String::new()
                        },
                        if self.document.doc.is_done() {
                            ", mesh complete"
                        } else {
                            ""
                        }
                    )
                }
            };
        } else {
            // A finishing pass: kept when it belongs to the mesh as
            // stepped now (for other settings it is shown while the
            // current ones are computed).
            if job.key.mesh_version != self.document.mesh_version {
                return;
            }
            match done.finished {
                Some(Ok(mesh)) => {
                    self.view.finished = Some(Finished { key: job.key, mesh });
                }
                Some(Err(e)) => {
                    self.view.finish_failed = Some(job.key);
                    self.window.status = format!("error: {e}");
                }
                None => {}
            }
        }
        self.export_pending();
    }

    /// Writes the export that waited for the finishing pass, once the
    /// finished mesh of these settings is there.
    fn export_pending(&mut self) {
        let key = self.finish_key();
        let ready = self.view.finished.as_ref().is_some_and(|f| f.key == key);
        if ready || self.view.finish_failed == Some(key) {
            if let Some(p) = self.background.pending_export.take() {
                self.apply_now(Command::Export(p));
            }
        }
    }

    /// Exports the finished mesh; while the finishing pass runs, the export
    /// waits for it.
    fn export(&mut self, path: PathBuf) -> Result<String, EditorError> {
        let format = crate::io::MeshFormat::from_path(&path)?;
        if let Some(r) = &self.document.doc.regions {
            // The regions as physical surfaces, the groups as physical
            // curves (or the format's sets and arrays).
            let m = r.mesh.clone().ok_or(EditorError::NotFinished)?;
            crate::io::write_atomic(&path, format.render_regions(&m).as_bytes())?;
            self.window.recent.push(&path);
            self.note_export(&path);
            self.panels.export_path = path.display().to_string();
            return Ok(format!(
                "wrote {} ({}, {}, {})",
                path.display(),
                plural(m.mesh.quads.len(), "quad"),
                plural(m.regions.len(), "region"),
                plural(m.groups.len(), "group")
            ));
        }
        let key = self.finish_key();
        let pending =
            self.background.job.as_ref().is_some_and(|j| {
                !j.is_run() && j.key == key && self.document.doc.imported().is_none()
            });
        if pending {
            self.background.pending_export = Some(path.clone());
            return Ok(format!(
                "exporting to {} once the mesh is finished…",
                path.display()
            ));
        }
        let mesh = self.finished_mesh()?;
        crate::io::write_mesh(&mesh, &path)?;
        self.window.recent.push(&path);
        self.note_export(&path);
        // The Export box writes there again.
        self.panels.export_path = path.display().to_string();
        Ok(format!(
            "wrote {} ({})",
            path.display(),
            plural(mesh.quads.len(), "quad")
        ))
    }

    /// Remembers the folder a mesh was exported to.
    fn note_export(&mut self, path: &Path) {
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map(Path::to_path_buf)
            .or_else(|| std::env::current_dir().ok());
        if let Some(d) = dir {
            self.window.export_dir = Some(std::path::absolute(&d).unwrap_or(d));
        }
    }

    fn save(&mut self, path: &Path) -> Result<String, EditorError> {
        self.document.doc.save_project(path)?;
        self.document.project_path = Some(path.to_path_buf());
        self.window.recent.push(path);
        self.document.dirty = false;
        match self.window.after_save.take() {
            Some(Then::Run(c)) => self.apply_now(c),
            Some(Then::Close) => {
                self.window.close_allowed = true;
                self.window.close_now = true;
            }
            None => {}
        }
        Ok(format!("saved {}", path.display()))
    }

    /// The folder a document's files go to: the folder of its own file;
    /// for a document of no file (a built-in example, a new drawing) the
    /// folder of the last mesh exported, else none (a folder another
    /// document was opened from is not this one's).
    fn document_dir(&self) -> Option<PathBuf> {
        let own = self
            .document
            .project_path
            .as_ref()
            .or(self.document.doc.source.as_ref());
        match own {
            Some(p) => p
                .parent()
                .filter(|p| !p.as_os_str().is_empty())
                .map(Path::to_path_buf),
            None => self.window.export_dir.clone(),
        }
    }

    /// The folder and file name a dialog starts from: [`App::document_dir`],
    /// else the working directory.
    fn dialog_start(&self, d: Dialog) -> (PathBuf, String) {
        let dir = self
            .document_dir()
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        let stem = stem(&self.title());
        let mut name = d.file_name(&stem);
        // An export never starts on the file the document was opened
        // from (a mesh opened to look at would be overwritten unasked).
        if d == Dialog::ExportMesh && self.document.doc.source.as_deref() == Some(&dir.join(&name))
        {
            name = format!("{stem}_quadex.msh");
        }
        (dir, name)
    }

    /// Asks for a file (the desktop's dialog, else the prompt in the
    /// window) and applies what it is for.
    fn dialog(&mut self, d: Dialog) {
        let (dir, name) = match self.export_box_path() {
            Some(at) if d == Dialog::ExportMesh => at,
            _ => self.dialog_start(d),
        };
        if self.window.native_dialogs {
            if let Some(p) = files::pick(d, Some(&dir), &name) {
                self.apply(files::command_for(d, p));
            }
        } else {
            self.window.prompt = Some(Prompt::new(d, &dir, &name));
        }
    }

    /// The folder and file name in the side panel's Export box, where the
    /// export dialog starts too (so the two agree).
    fn export_box_path(&self) -> Option<(PathBuf, String)> {
        let p = Path::new(self.panels.export_path.trim());
        let name = p.file_name()?.to_str()?.to_string();
        let dir = p.parent().filter(|d| !d.as_os_str().is_empty())?;
        Some((dir.to_path_buf(), name))
    }

    /// The default export path: beside the document's file, named after
    /// it; for a document of no file in the folder of the last export,
    /// and with none, no path.
    fn default_export_path(&self) -> String {
        if self.document_dir().is_none() {
            return String::new();
        }
        let (dir, name) = self.dialog_start(Dialog::ExportMesh);
        dir.join(name).display().to_string()
    }

    /// The finished mesh of the current document (computed here when the
    /// background has not done it yet).
    fn finished_mesh(&mut self) -> Result<QuadMesh, EditorError> {
        if let Some(m) = self.document.doc.imported() {
            return Ok(m.clone());
        }
        let key = self.finish_key();
        if let Some(f) = self.view.finished.as_ref().filter(|f| f.key == key) {
            return Ok(f.mesh.clone());
        }
        match self.document.doc.finished() {
            Ok(m) => {
                self.view.finished = Some(Finished {
                    key,
                    mesh: m.clone(),
                });
                Ok(m)
            }
            Err(e) => {
                if self.document.doc.is_done() {
                    self.view.finish_failed = Some(key);
                }
                Err(e)
            }
        }
    }

    /// Starts the finishing pass when the run is complete and its finished
    /// mesh is not there yet (after a short pause while the finishing
    /// settings are being changed).
    fn refresh_finished(&mut self, ctx: &egui::Context) {
        let doc = &self.document.doc;
        if !doc.is_done()
            || doc.imported().is_some()
            || doc.regions.is_some()
            || self.background.job.is_some()
        {
            return;
        }
        let key = self.finish_key();
        if self.view.finished.as_ref().is_some_and(|f| f.key == key)
            || self.view.finish_failed == Some(key)
        {
            return;
        }
        let shown_stale = self
            .view
            .finished
            .as_ref()
            .is_some_and(|f| f.key.mesh_version == key.mesh_version);
        if let Some(t) = self.background.settings_changed {
            if shown_stale && t.elapsed() < FINISH_DEBOUNCE {
                ctx.request_repaint_after(FINISH_DEBOUNCE);
                return;
            }
        }
        if !self.background.threads {
            if let Err(e) = self.finished_mesh() {
                self.window.status = format!("error: {e}");
            }
            self.export_pending();
            return;
        }
        let Some(mesher) = doc.mesher().cloned() else {
            return;
        };
        self.background.job = Some(Job::start(
            mesher,
            Work::Finish(key.params),
            "finishing",
            Record::Steps,
            key,
        ));
    }

    /// The element the next step would cut (a step taken on a copy of the
    /// mesher), when the Extraction panel asks for it.
    fn refresh_preview(&mut self) {
        let doc = &self.document.doc;
        if !self.panels.step.preview || self.busy() || doc.is_done() || doc.meshing.is_none() {
            self.view.preview = None;
            return;
        }
        let v = self.document.mesh_version;
        if self.view.preview.as_ref().is_some_and(|(k, _)| *k == v) {
            return;
        }
        let Some(mut probe) = doc.mesher().cloned() else {
            return;
        };
        let quads = match probe.step() {
            Ok(crate::extract::StepOutcome::Stepped(r)) if r.quads.len() <= 12 => {
                r.quads.iter().map(|q| probe.mesh().corners(q)).collect()
            }
            _ => Vec::new(),
        };
        self.view.preview = Some((v, quads));
    }

    /// The closing targets of the last element, when the Correct tool
    /// needs them.
    fn refresh_targets(&mut self) {
        let v = self.document.mesh_version;
        if self.view.targets.as_ref().is_some_and(|(k, _)| *k == v) {
            return;
        }
        let doc = &self.document.doc;
        let wanted = self.panels.tools.tool == Tool::Correct
            && !self.busy()
            && self.background.animating.is_none()
            && doc.last_element().is_some()
            && !doc.has_mesh();
        if !wanted {
            return;
        }
        let before = match self.view.before_last.take() {
            Some((k, m)) if k == v => Some(m),
            _ => doc.before_last(),
        };
        let Some(mut before) = before else {
            self.view.targets = Some((v, Vec::new()));
            return;
        };
        let targets = doc.closing_targets(&mut before);
        self.view.before_last = Some((v, before));
        self.view.targets = Some((v, targets));
    }

    /// Shortcuts and dropped files, as commands. Esc closes an open menu
    /// first, then drops a loop being drawn, then cancels.
    fn input_commands(&self, ctx: &egui::Context, out: &mut Vec<Command>) {
        if self.window.ask.is_some() || self.window.prompt.is_some() {
            return;
        }
        ctx.input(|i| {
            for f in &i.raw.dropped_files {
                if let Some(p) = &f.path {
                    out.push(Command::Open(p.clone()));
                }
            }
        });
        if ctx.wants_keyboard_input() {
            return;
        }
        let menu_open = egui::Popup::is_any_open(ctx);
        let n = self.panels.step.n;
        // Redo before Undo: Ctrl+Shift+Z also matches Ctrl+Z.
        for cmd in [
            Command::Redo,
            Command::Undo,
            Command::ZoomToStep,
            Command::StepN(n),
            Command::Step,
            Command::RunToEnd,
            Command::Reset,
            Command::FitView,
            Command::New,
            Command::Save,
            Command::Dialog(Dialog::Open),
            Command::Dialog(Dialog::ExportMesh),
            Command::Animate(self.background.animating.is_none()),
            Command::Quit,
            Command::Cancel,
        ] {
            if menu_open && cmd == Command::Cancel {
                continue;
            }
            for s in [cmd.shortcut(), cmd.alternative_shortcut()]
                .into_iter()
                .flatten()
            {
                if ctx.input_mut(|i| i.consume_shortcut(&s)) {
                    out.push(cmd.clone());
                    break;
                }
            }
        }
    }

    /// One frame of the whole editor (also what the UI tests drive).
    pub fn ui(&mut self, ctx: &egui::Context) {
        self.window.frame += 1;
        if let (1, Some(size)) = (self.window.frame, self.window.size) {
            ctx.send_viewport_cmd(egui::ViewportCommand::InnerSize(size));
        }
        if self.background.job.as_ref().is_some_and(Job::is_finished) {
            if let Some(mut j) = self.background.job.take() {
                let done = j.wait();
                self.job_done(j, done);
            }
        }
        self.background.orphans.retain(|h| !h.is_finished());
        if self
            .background
            .region_run
            .as_ref()
            .is_some_and(|r| r.handle.is_finished())
        {
            if let Some(r) = self.background.region_run.take() {
                self.region_run_done(r);
            }
        }
        if let Some(r) = self.document.doc.regions.as_mut() {
            r.sync_shown();
            self.panels.regions.sync(r);
        }
        if self
            .background
            .compare
            .as_ref()
            .is_some_and(CompareJob::is_finished)
        {
            self.compare_done();
        }
        if self
            .background
            .refit
            .as_ref()
            .is_some_and(|f| f.handle.is_finished())
        {
            if let Some(r) = self.background.refit.take() {
                self.refit_joined(r);
            }
        }
        let mut cmds = Vec::new();
        self.input_commands(ctx, &mut cmds);
        self.panels.tools.sync(&self.document.doc);
        let d = self.default_export_path();
        if self.panels.export_default.as_ref() != Some(&d) {
            // Another document (or the same under another name): the
            // Export box starts again beside it.
            self.panels.export_path = d.clone();
            self.panels.export_default = Some(d);
        }
        self.refresh_finished(ctx);
        self.refresh_preview();
        self.refresh_targets();
        let title = format!("quadex: {}", self.title_line());
        if title != self.window.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.window.title = title;
        }
        egui::TopBottomPanel::top("menu").show(ctx, |ui| {
            egui::MenuBar::new().ui(ui, |ui| self.menus(ui, &mut cmds));
        });
        egui::TopBottomPanel::bottom("status").show(ctx, |ui| self.status_bar(ui, &mut cmds));
        // The figures of the shown mesh.
        let shown_key = {
            let s = self.shown();
            (
                self.document.mesh_version,
                s.kind,
                s.mesh as *const QuadMesh as usize,
            )
        };
        if self.view.stats_key != Some(shown_key) {
            let ViewState {
                stats,
                finished,
                empty,
                stats_key,
                ..
            } = &mut self.view;
            let s = shown_of(&self.document, finished, empty);
            // The stepped mesh's front nodes are not interior nodes yet.
            let open: Vec<u32> = match (s.kind, self.document.doc.mesher()) {
                (MeshKind::Stepped, Some(m)) => {
                    let f = m.front();
                    f.live_loops().flat_map(|l| f.loop_nodes(l)).collect()
                }
                _ => Vec::new(),
            };
            stats.refresh(shown_key.0 * 8 + shown_key.1 as u64, s.mesh, &open);
            *stats_key = Some(shown_key);
        }
        let width = ctx.content_rect().width();
        let busy = self.busy();
        let max_widths = [0, 1].map(|k| (PANEL_MAX_SHARES[k] * width).max(PANEL_MIN_WIDTHS[k]));
        if self.panels.show_left {
            let id = egui::Id::new("steps");
            restore_panel_width(ctx, id, self.panels.widths[0], max_widths[0]);
            let shown = egui::SidePanel::left(id)
                .resizable(true)
                .default_width(self.panels.widths[0])
                .min_width(PANEL_MIN_WIDTHS[0])
                .max_width(max_widths[0])
                .show(ctx, |ui| {
                    // Both ways: content wider than the panel (a row that
                    // cannot wrap in a narrow window) scrolls instead of
                    // widening the panel over the canvas.
                    egui::ScrollArea::both().show(ui, |ui| {
                        let doc = &self.document.doc;
                        let run = RunState {
                            animating: self.background.animating.is_some(),
                            busy,
                            can_undo: self.document.history.can_undo(),
                            can_redo: self.document.history.can_redo(),
                        };
                        let mut out = Vec::new();
                        out.extend(self.panels.step.ui(ui, doc, run));
                        ui.separator();
                        // The section of what the tool bar does comes
                        // first, in view without scrolling: the boundary
                        // (or the drawing) with an editing tool, else the
                        // correction and training.
                        let editing = self.panels.tools.tool != Tool::Correct;
                        let figures = Figures {
                            busy,
                            ..figures_of(&self.document, &self.view)
                        };
                        if doc.regions.is_some() {
                            out.extend(self.panels.tools.drawing_ui(ui, doc));
                        } else if editing {
                            out.extend(self.panels.tools.ui(ui, doc, ()));
                        } else {
                            out.extend(self.panels.train.ui(ui, doc, figures));
                        }
                        ui.separator();
                        export_box(ui, &mut self.panels.export_path, doc, &mut out);
                        ui.separator();
                        if doc.regions.is_some() {
                            out.extend(self.panels.regions.ui(ui, doc, ()));
                        } else {
                            let figures = Figures {
                                busy,
                                ..figures_of(&self.document, &self.view)
                            };
                            if editing {
                                out.extend(self.panels.train.ui(ui, doc, figures));
                            } else {
                                out.extend(self.panels.tools.ui(ui, doc, ()));
                            }
                            ui.separator();
                            if ui
                                .add_enabled(
                                    doc.boundary().is_some(),
                                    egui::Button::new("Regions and groups…"),
                                )
                                .on_hover_text("Make this boundary a document of regions: split it into regions with interface curves, name boundary groups and regions (the steps taken are dropped)")
                                .on_disabled_hover_text("Needs a valid boundary")
                                .clicked()
                            {
                                out.push(Command::ToRegions);
                            }
                        }
                        cmds.extend(out);
                    });
                });
            self.panels.widths[0] = chosen_panel_width(
                self.panels.widths[0],
                shown.response.rect.width(),
                max_widths[0],
            );
        }
        if self.panels.show_right {
            let threads = self.background.threads;
            let id = egui::Id::new("panels");
            restore_panel_width(ctx, id, self.panels.widths[1], max_widths[1]);
            let shown = egui::SidePanel::right(id)
                .resizable(true)
                .default_width(self.panels.widths[1])
                .min_width(PANEL_MIN_WIDTHS[1])
                .max_width(max_widths[1])
                .show(ctx, |ui| {
                    ui.horizontal_wrapped(|ui| {
                        for t in Tab::ALL {
                            ui.selectable_value(&mut self.panels.tab, t, t.name())
                                .on_hover_text(t.hint());
                        }
                    });
                    ui.separator();
                    egui::ScrollArea::both()
                        .id_salt("right_panel")
                        .show(ui, |ui| {
                            let doc = &self.document.doc;
                            let figures = figures_of(&self.document, &self.view);
                            let b = &self.background;
                            let compare_state = CompareState {
                                comparison: b.comparison.as_ref(),
                                comparing: b.compare.as_ref().map(|j| (j.done(), j.total)),
                            };
                            let p = &mut self.panels;
                            let out = match p.tab {
                                Tab::Quality => p.quality.ui(ui, doc, figures),
                                Tab::Model => p.model.ui(ui, doc, threads),
                                Tab::Samples => p.samples.ui(ui, doc, figures.kind),
                                Tab::Smoothing => p.smooth.ui(ui, doc, figures),
                                Tab::Compare => p.compare.ui(ui, doc, compare_state),
                            };
                            cmds.extend(out);
                        });
                });
            self.panels.widths[1] = chosen_panel_width(
                self.panels.widths[1],
                shown.response.rect.width(),
                max_widths[1],
            );
        }
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ctx, |ui| {
                egui::Frame::side_top_panel(ui.style()).show(ui, |ui| {
                    ui.set_width(ui.available_width());
                    let kind = self.shown().kind;
                    let targets = targets_of(&self.document, &self.view);
                    let doc = &self.document.doc;
                    if doc.regions.is_some() {
                        self.panels.regions.toolbar(ui);
                    } else {
                        cmds.extend(self.panels.tools.toolbar(ui, doc, kind, targets));
                    }
                });
                self.canvas(ui, &mut cmds);
            });
        self.questions(ctx, &mut cmds);
        for c in cmds {
            self.apply(c);
        }
        self.animate(ctx);
        if busy || self.finishing() || self.comparing() {
            ctx.request_repaint_after(std::time::Duration::from_millis(50));
        }
        self.screenshot_step(ctx);
    }

    /// The canvas: the document drawn, the tool's gestures, pan and zoom.
    fn canvas(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        let (resp, painter) =
            ui.allocate_painter(ui.available_size(), egui::Sense::click_and_drag());
        let rect = resp.rect;
        let kind = self.shown().kind;
        let targets: Vec<Target> = self.targets().to_vec();
        let ViewState {
            canvas: view,
            canvas_rect,
            domain,
            mesh: mesh_cache,
            stats,
            finished,
            preview,
            front,
            hover,
            empty,
            before_last,
            ..
        } = &mut self.view;
        *canvas_rect = rect;
        let d = &self.document;
        let doc = &d.doc;
        let bbox = match &doc.regions {
            Some(r) => Aabb::of(r.graph.points.iter().copied()),
            None => Aabb::of(doc.draft.loops.iter().flatten().copied()),
        };
        view.update(rect, bbox);
        let pointer = canvas::Pointer::of(&resp, ui).in_view(view);
        if let Some(r) = &doc.regions {
            // Shift-click adds to the picked segments (the release's own
            // modifiers count too).
            let shift = ui.input(|i| {
                i.modifiers.shift
                    || i.events.iter().any(|e| {
                        matches!(e, egui::Event::PointerButton { modifiers, .. } if modifiers.shift)
                    })
            });
            self.panels.regions.input(r, view, &pointer, shift, cmds);
        }
        let taken = doc.regions.is_none() && {
            let at = tools::OnCanvas {
                view,
                pointer: &pointer,
                doc,
                targets: &targets,
                kind,
                drag: None,
            };
            self.panels.tools.input(&at, cmds)
        };
        canvas::pan_zoom(view, &resp, ui, taken);
        // While Pn is dragged: how good the element would be, checked on
        // the mesher before the last step (as the targets are).
        let drag = self.panels.tools.pn_drag().and_then(|pn| {
            let reference = doc.last_element()?.reference?;
            let (k, before) = before_last.as_mut()?;
            (*k == d.mesh_version).then(|| {
                before
                    .check_correction(&crate::extract::Correction {
                        reference,
                        element_type: crate::model::ElementType::New,
                        pn: Some(pn),
                        snap_to: None,
                    })
                    .ok()
            })
        });
        let pointer = pointer.in_view(view);
        *hover = pointer.world.filter(|_| pointer.hovered);
        // The front of the mesh as stepped, by mesh version.
        let v = d.mesh_version;
        if front.0 != v {
            let loops = doc
                .mesher()
                .map(|m| {
                    let f = m.front();
                    f.live_loops().map(|l| f.loop_nodes(l)).collect()
                })
                .unwrap_or_default();
            *front = (v, loops);
        }
        let shown = shown_of(d, finished, empty);
        let stepped = shown.kind == MeshKind::Stepped;
        let domain = match doc.boundary() {
            Some(b) => domain.of(b),
            None => &[],
        };
        let overlay = canvas::Overlay {
            version: (v * 8 + shown.kind as u64) ^ ((shown.mesh as *const QuadMesh as u64) << 20),
            boundary: doc.boundary(),
            domain,
            mesh: shown.mesh,
            qualities: &stats.per_quad,
            front: if stepped { &front.1 } else { &[] },
            // The finished mesh is renumbered: the last step's node ids
            // belong to the mesh as stepped.
            last: if stepped && doc.regions.is_none() {
                doc.last()
            } else {
                None
            },
            // A document of regions is coloured by region unless asked.
            metric: if doc.regions.is_none() || self.panels.regions.plain_quality {
                self.panels.quality.metric
            } else {
                None
            },
        };
        let hovered_quad = canvas::draw(ui, &painter, view, mesh_cache, &overlay, &pointer);
        if let Some(metric) = overlay.metric.filter(|_| !shown.mesh.quads.is_empty()) {
            canvas::legend(&painter, rect, metric);
        }
        if let Some((_, quads)) = preview {
            let cyan = egui::Color32::from_rgb(80, 220, 255);
            for q in quads.iter() {
                let mut ring: Vec<egui::Pos2> =
                    q.iter().map(|&p| view.to_screen(rect, p)).collect();
                ring.push(ring[0]);
                painter.extend(egui::Shape::dashed_line(
                    &ring,
                    egui::Stroke::new(2.0, cyan),
                    6.0,
                    4.0,
                ));
            }
        }
        if let Some(r) = &doc.regions {
            if !self.panels.regions.plain_quality || shown.mesh.quads.is_empty() {
                self.panels.regions.draw(ui, &painter, view, r, *hover);
            }
        }
        if let Some(dr) = &doc.drawing {
            canvas::draw_curves(&painter, view, rect, &dr.geometry);
        }
        let at = tools::OnCanvas {
            view,
            pointer: &pointer,
            doc,
            targets: &targets,
            kind,
            drag,
        };
        self.panels.tools.draw(ui, &painter, &at);
        if doc.draft.loops.is_empty()
            && doc.regions.is_none()
            && self.panels.tools.drawing.is_empty()
        {
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "Nothing drawn yet: with the \"draw loop\" tool, click to place nodes",
                egui::FontId::proportional(16.0),
                ui.visuals().weak_text_color(),
            );
        }
        // (Not in a screenshot: the pointer is wherever the display left it.)
        if let (Some(k), None, None) = (
            hovered_quad,
            self.panels.tools.hover,
            &self.window.screenshot,
        ) {
            canvas::quad_hover(ui, &resp, k, &stats.per_quad);
        }
    }

    fn menus(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        let item = |ui: &mut egui::Ui,
                    label: &str,
                    tip: &str,
                    cmd: Command,
                    enabled: bool,
                    out: &mut Vec<Command>| {
            let mut b = egui::Button::new(label);
            if let Some(s) = cmd.shortcut() {
                b = b.shortcut_text(ui.ctx().format_shortcut(&s));
            }
            if ui.add_enabled(enabled, b).on_hover_text(tip).clicked() {
                out.push(cmd);
            }
        };
        let doc = &self.document.doc;
        let (has_draft, has_mesh, has_samples) = (
            !doc.draft.loops.is_empty() || doc.regions.is_some(),
            doc.has_mesh(),
            !doc.training.is_empty(),
        );
        // While a run or refit goes on, stepping, undo and reset wait for
        // it (the commands would be refused).
        let busy = self.busy();
        let can = doc.can_step() && !doc.is_done() && !busy;
        let can_reset = doc.can_step() && !busy;
        let can_finish = doc.is_done() && self.view.finish_failed.is_some();
        ui.menu_button("File", |ui| {
            item(
                ui,
                "New",
                "An empty canvas to draw a boundary on",
                Command::New,
                true,
                cmds,
            );
            item(
                ui,
                "Open…",
                "A boundary (.poly, .json), a project or a quad mesh (.msh)",
                Command::Dialog(Dialog::Open),
                true,
                cmds,
            );
            ui.menu_button("Open an example", |ui| {
                for (name, _) in assets::EXAMPLES {
                    if ui.button(name).clicked() {
                        cmds.push(Command::OpenExample(name));
                    }
                }
            });
            ui.menu_button("Open recent", |ui| {
                if self.window.recent.0.is_empty() {
                    ui.label("none yet");
                }
                for p in self.window.recent.0.clone() {
                    if ui.button(p.display().to_string()).clicked() {
                        cmds.push(Command::Open(p));
                    }
                }
            });
            ui.separator();
            item(
                ui,
                "Save project",
                "Boundary, steps, models, samples and settings in one file",
                Command::Save,
                true,
                cmds,
            );
            item(
                ui,
                "Save project as…",
                "Save the project under a new name",
                Command::Dialog(Dialog::SaveProjectAs),
                true,
                cmds,
            );
            item(
                ui,
                "Save boundary as…",
                "The boundary as .poly, or as .json (a draft too)",
                Command::Dialog(Dialog::SaveBoundaryAs),
                has_draft,
                cmds,
            );
            ui.separator();
            item(
                ui,
                "Export mesh…",
                "The finished mesh as .msh, .msh22, .vtk, .vtu, .inp or .svg",
                Command::Dialog(Dialog::ExportMesh),
                has_mesh,
                cmds,
            );
            item(
                ui,
                "Import training samples…",
                "Append the samples of a .csv or .json training set",
                Command::Dialog(Dialog::ImportSamples),
                true,
                cmds,
            );
            item(
                ui,
                "Export training samples…",
                "Write your samples as .csv or .json",
                Command::Dialog(Dialog::ExportSamples),
                has_samples,
                cmds,
            );
            item(
                ui,
                "Collect samples from a mesh file…",
                "Every corner of every good quad of a .msh file",
                Command::Dialog(Dialog::CollectFromFile),
                true,
                cmds,
            );
            if self.window.native_dialogs {
                ui.separator();
                if ui
                    .button("Type a path to open…")
                    .on_hover_text("Open a file by its path, without the desktop's dialog")
                    .clicked()
                {
                    let (dir, _) = self.dialog_start(Dialog::Open);
                    self.window.prompt = Some(Prompt::new(Dialog::Open, &dir, ""));
                }
            }
            ui.label(egui::RichText::new("(or drop a file on the window)").weak());
            ui.separator();
            item(
                ui,
                "Quit",
                "Close the editor (asks first when there is unsaved work)",
                Command::Quit,
                true,
                cmds,
            );
        });
        ui.menu_button("Edit", |ui| {
            let h = &self.document.history;
            let undo = h.undo_name().map_or("Undo".into(), |n| format!("Undo {n}"));
            let redo = h.redo_name().map_or("Redo".into(), |n| format!("Redo {n}"));
            item(
                ui,
                &undo,
                "Also Ctrl+Z",
                Command::Undo,
                h.can_undo() && !busy,
                cmds,
            );
            item(
                ui,
                &redo,
                "Also Ctrl+Y",
                Command::Redo,
                h.can_redo() && !busy,
                cmds,
            );
            ui.separator();
            item(
                ui,
                "Reset",
                "Start the mesh again (undo brings the steps back)",
                Command::Reset,
                can_reset,
                cmds,
            );
        });
        ui.menu_button("Mesh", |ui| {
            let n = self.panels.step.n;
            item(ui, "Step", "One extraction step", Command::Step, can, cmds);
            item(
                ui,
                &format!("Step ×{n}"),
                "N steps (set N in the Extraction panel)",
                Command::StepN(n),
                can,
                cmds,
            );
            let anim = self.background.animating.is_some();
            item(
                ui,
                if anim { "Pause" } else { "Run (animated)" },
                "Steps on their own at the panel's speed",
                Command::Animate(!anim),
                can || (anim && !busy),
                cmds,
            );
            item(
                ui,
                "Run to end",
                "In the background, with a progress bar",
                Command::RunToEnd,
                can,
                cmds,
            );
            item(
                ui,
                "Cancel the run",
                "The run is dropped: the mesh stays as before it",
                Command::Cancel,
                self.background.job.is_some() || busy,
                cmds,
            );
            item(
                ui,
                "Finish the mesh",
                "Cleanup, remeshing and smoothing of the complete mesh",
                Command::Finish,
                can_finish,
                cmds,
            );
        });
        ui.menu_button("View", |ui| {
            item(
                ui,
                "Fit view",
                "Fit the boundary into the canvas",
                Command::FitView,
                true,
                cmds,
            );
            item(
                ui,
                "Zoom to the last step",
                "Centre the canvas on the last step, zoomed so that its points and their labels show",
                Command::ZoomToStep,
                self.document.doc.last().is_some(),
                cmds,
            );
            ui.checkbox(&mut self.panels.show_left, "Left panel (stepping, tools)");
            ui.checkbox(&mut self.panels.show_right, "Right panel (figures)");
            ui.separator();
            for t in Tab::ALL {
                ui.selectable_value(&mut self.panels.tab, t, t.name());
            }
        });
        ui.separator();
        ui.label(self.title_line());
    }

    fn status_bar(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        ui.horizontal(|ui| {
            if let Some(f) = &self.background.refit {
                ui.spinner();
                ui.label(format!("refit: {}", f.phase()));
                let secs = f.started.elapsed().as_secs_f64();
                cancel_button(ui, secs, "Stop (Esc): the refit is dropped, the model stays as before it", cmds);
            }
            if let Some(j) = &self.background.job {
                let (steps, front, frac) = j.progress();
                match j.phase() {
                    None if j.is_run() => {
                        ui.add(
                            egui::ProgressBar::new(frac)
                                .desired_width(120.0)
                                .show_percentage(),
                        )
                        .on_hover_text("The share of the domain's area meshed so far");
                        ui.label(format!(
                            "{}: extraction, {}, {} left",
                            j.what,
                            plural(steps, "step"),
                            plural(front, "front node")
                        ));
                    }
                    // Extraction is over: the part of finishing going on
                    // (the share meshed would stand at 100 % meanwhile).
                    phase => {
                        ui.spinner();
                        let what = if j.is_run() {
                            format!("{}: {} taken; finishing", j.what, plural(steps, "step"))
                        } else {
                            "finishing".into()
                        };
                        ui.label(format!(
                            "{what}: {}",
                            phase.map_or("starting", crate::pipeline::FinishPhase::name)
                        ))
                        .on_hover_text("Finishing the mesh: cleanup and smoothing, coarsening, remeshing bad regions, smoothing, checking");
                    }
                }
                cancel_button(
                    ui,
                    j.elapsed(),
                    "Stop (Esc): a run is dropped, the mesh stays as before it",
                    cmds,
                );
            }
            if let Some(r) = &self.background.region_run {
                use std::sync::atomic::Ordering;
                ui.spinner();
                ui.label(format!(
                    "meshing the regions: face {} of {}, {}",
                    (r.face.load(Ordering::Relaxed) + 1).min(r.faces),
                    r.faces,
                    plural(r.steps.load(Ordering::Relaxed), "step")
                ));
                cancel_button(
                    ui,
                    r.started.elapsed().as_secs_f64(),
                    "Stop (Esc): the run is dropped, the mesh stays as before it",
                    cmds,
                );
            }
            if let Some(p) = self.view.hover {
                ui.monospace(format!("x {:.4}  y {:.4}", p.x, p.y));
                ui.separator();
            }
            ui.label(&self.window.status);
        });
    }

    /// The animated run: steps at the panel's speed, on the UI thread.
    fn animate(&mut self, ctx: &egui::Context) {
        let Some(owed) = self.background.animating else {
            return;
        };
        if self.busy() {
            return;
        }
        let dt = ctx.input(|i| i.stable_dt).min(0.1) as f64;
        let owed = owed + dt * self.panels.step.speed;
        let n = owed.floor() as usize;
        self.background.animating = Some(owed - n as f64);
        if n > 0 {
            match self.step_sync(n.min(1000)) {
                Ok(k) if k < n.min(1000) => {
                    self.background.animating = None;
                    self.window.status = "the mesh is complete".into();
                }
                Ok(_) => {}
                Err(e) => {
                    self.background.animating = None;
                    self.window.status = format!("error: {e}");
                }
            }
        }
        ctx.request_repaint();
    }

    /// The questions (unsaved work) and the file prompt.
    fn questions(&mut self, ctx: &egui::Context, cmds: &mut Vec<Command>) {
        let wants_close = ctx.input(|i| i.viewport().close_requested());
        if std::mem::take(&mut self.window.close_now) {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        if wants_close && self.unsaved() && !self.window.close_allowed {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.window.ask = Some(Ask::Close);
        }
        if let Some(mut p) = self.window.prompt.take() {
            match p.ui(ctx, &self.window.recent) {
                Some(Some(c)) => cmds.push(c),
                Some(None) => self.window.after_save = None,
                None => self.window.prompt = Some(p),
            }
        }
        let Some(ask) = self.window.ask.clone() else {
            return;
        };
        // Save writes a project file: with none yet, the question says so
        // (the boundary file the document came from is left as it is).
        let title = match &self.document.project_path {
            Some(_) => self.title(),
            None => format!(
                "{} as a project ({})",
                self.title(),
                Dialog::SaveProjectAs.file_name(&stem(&self.title()))
            ),
        };
        let question = match &ask {
            Ask::Close => format!("Save the changes to {title} before closing?"),
            Ask::Discard(c) => {
                let what = match c {
                    Command::New => "starting a new boundary".to_string(),
                    Command::Open(p) => format!("opening {}", document::file_name(p)),
                    Command::OpenExample(n) => format!("opening {n}"),
                    _ => "going on".into(),
                };
                format!("Save the changes to {title} before {what}?")
            }
        };
        let work = {
            let d = &self.document.doc;
            let mut w = Vec::new();
            if !d.training.is_empty() {
                w.push(plural(d.training.len(), "training sample"));
            }
            if !d.models.is_empty() {
                w.push(plural(d.models.len(), "refitted model"));
            }
            if d.boundary_edited {
                w.push("boundary edits".into());
            }
            w.join(", ")
        };
        let mut answer: Option<u8> = None;
        let modal = egui::Modal::new(egui::Id::new("unsaved_changes")).show(ctx, |ui| {
            ui.heading("Unsaved changes");
            ui.label(question);
            if !work.is_empty() {
                ui.label(format!("They hold {work}."));
            }
            ui.horizontal(|ui| {
                if ui.button("Save").clicked() {
                    answer = Some(0);
                }
                let discard = match ask {
                    Ask::Close => "Close without saving",
                    Ask::Discard(_) => "Don't save",
                };
                if ui.button(discard).clicked() {
                    answer = Some(1);
                }
                if ui.button("Cancel").clicked() {
                    answer = Some(2);
                }
            });
        });
        if modal.should_close() && answer.is_none() {
            answer = Some(2);
        }
        let Some(a) = answer else { return };
        self.window.ask = None;
        let then = match &ask {
            Ask::Close => None,
            Ask::Discard(c) => Some(c.clone()),
        };
        match a {
            0 => {
                // Save, then go on (after the save-as prompt if need be).
                self.window.after_save = Some(match then {
                    Some(c) => Then::Run(c),
                    None => Then::Close,
                });
                cmds.push(Command::Save);
            }
            1 => match then {
                Some(c) => self.apply_now(c),
                None => {
                    self.window.close_allowed = true;
                    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                }
            },
            _ => self.window.status = "cancelled".into(),
        }
    }

    /// The `--screenshot` option: request a screenshot after the first
    /// frames, save it when it arrives, then close.
    fn screenshot_step(&mut self, ctx: &egui::Context) {
        let Some(path) = self.window.screenshot.clone() else {
            return;
        };
        if self.busy() || self.finishing() {
            ctx.request_repaint();
            return;
        }
        // The window at the size asked for first (eframe restores the
        // size of the last run before the first frame).
        let sized = self
            .window
            .size
            .is_none_or(|want| (ctx.content_rect().size() - want).length() < 1.0);
        if !self.window.screenshot_requested && self.window.frame >= SCREENSHOT_FRAME && sized {
            ctx.send_viewport_cmd(egui::ViewportCommand::Screenshot(Default::default()));
            self.window.screenshot_requested = true;
        }
        let shot = ctx.input(|i| {
            i.raw.events.iter().find_map(|e| match e {
                egui::Event::Screenshot { image, .. } => Some(image.clone()),
                _ => None,
            })
        });
        if let Some(img) = shot {
            match save_png(&img, &path) {
                Ok(()) => eprintln!("quadex: wrote {}", path.display()),
                Err(e) => eprintln!("quadex: {e}"),
            }
            self.window.screenshot = None;
            self.window.close_allowed = true;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        } else {
            ctx.request_repaint();
        }
    }
}

/// The seconds a background job has taken and its Cancel button, in the
/// status bar.
fn cancel_button(ui: &mut egui::Ui, secs: f64, tip: &str, cmds: &mut Vec<Command>) {
    ui.label(format!("{secs:.1} s"));
    if ui.button("Cancel").on_hover_text(tip).clicked() {
        cmds.push(Command::Cancel);
    }
    ui.separator();
}

/// Saves a screenshot as PNG.
fn save_png(img: &egui::ColorImage, path: &Path) -> Result<(), EditorError> {
    let [w, h] = img.size;
    let bytes: Vec<u8> = img.pixels.iter().flat_map(|c| c.to_array()).collect();
    let err = |cause| EditorError::Screenshot {
        path: path.to_path_buf(),
        cause,
    };
    let len = bytes.len();
    let im = image::RgbaImage::from_raw(w as u32, h as u32, bytes).ok_or(err(
        ScreenshotError::Buffer {
            width: w,
            height: h,
            bytes: len,
        },
    ))?;
    im.save(path).map_err(|e| err(ScreenshotError::Png(e)))
}

/// The export box of the left panel: a path (beside the document's file
/// by default) and the buttons.
fn export_box(ui: &mut egui::Ui, path: &mut String, doc: &Document, out: &mut Vec<Command>) {
    ui.label(egui::RichText::new("Export").strong());
    let done = doc.has_mesh();
    ui.add(
        egui::TextEdit::singleline(path)
            .desired_width(f32::INFINITY)
            .hint_text("a path, or Export… to choose one"),
    )
    .on_hover_text("The file to write; its extension picks the format");
    ui.label(egui::RichText::new(".msh .msh22 .vtk .vtu .inp .svg").weak());
    ui.horizontal(|ui| {
        let named = !path.trim().is_empty();
        if ui
            .add_enabled(done && named, egui::Button::new("Export mesh"))
            .on_hover_text("Write the finished mesh to the path above")
            .on_disabled_hover_text(if done {
                "Type a path above, or choose one with Export…"
            } else {
                "Run the mesh to the end first"
            })
            .clicked()
        {
            out.push(Command::Export(PathBuf::from(path.trim())));
        }
        if ui
            .add_enabled(done, egui::Button::new("Export…"))
            .on_hover_text("Choose where to write the finished mesh")
            .on_disabled_hover_text("Run the mesh to the end first")
            .clicked()
        {
            out.push(Command::Dialog(Dialog::ExportMesh));
        }
    });
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_read_as_english() {
        assert_eq!(plural(1, "sample"), "1 sample");
        assert_eq!(plural(0, "sample"), "0 samples");
        assert_eq!(plural(3, "quad"), "3 quads");
        let o: Vec<String> = [1, 2, 3, 4, 11, 12, 13, 21, 22, 23, 101, 111]
            .iter()
            .map(|&n| ordinal(n))
            .collect();
        assert_eq!(
            o,
            [
                "1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "23rd",
                "101st", "111th"
            ]
        );
        assert_eq!(figure(f64::NEG_INFINITY, 4), "n/a");
        assert_eq!(figure(0.98765, 3), "0.988");
        assert_eq!(stem("plate.quadex.json"), "plate");
        assert_eq!(stem(""), "untitled");
        assert_eq!(
            missing(1.0 - 3.0 / 198_007.0, 198_007, "outside"),
            "3 of 198,007 outside"
        );
        assert_eq!(missing(1.0, 12, "outside"), "none of 12 outside");
    }
}

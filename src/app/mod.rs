//! The desktop editor (eframe/egui): a view and a controller over the core.
//! [`App`] holds the [`Document`] (boundary, mesher, training set), its
//! [`History`] for undo and redo, the canvas [`View`], the panels' own state
//! and a status line; every user intent is a [`Command`] applied in
//! [`App::apply`]. No meshing logic lives here: the editor drives `Mesher`
//! through its public step API like the CLI and the tests do. Long runs go
//! to a background [`job::Job`].

pub mod canvas;
pub mod command;
pub mod document;
pub mod files;
pub mod history;
pub mod job;
pub mod model_panel;
pub mod quality_panel;
pub mod samples_panel;
pub mod smooth_panel;
pub mod step_panel;
pub mod tools;
pub mod train_panel;

use crate::geom::Point;
use crate::mesh::QuadMesh;
use canvas::{MeshCache, Overlay, View};
pub use command::{Command, Dialog};
pub use document::{Document, Settings};
use files::Recent;
pub use history::History;
use job::Job;
use model_panel::ModelPanel;
use quality_panel::{MeshStats, QualityPanel};
use samples_panel::SamplesPanel;
use serde::{Deserialize, Serialize};
use smooth_panel::SmoothPanel;
use std::path::{Path, PathBuf};
use step_panel::StepPanel;
use tools::Tools;
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

/// The shipped example the editor opens by default.
pub fn example_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples/annulus.poly")
}

/// Frames drawn before a screenshot is taken (layout and view settle).
const SCREENSHOT_FRAME: u64 = 3;

/// Steps ×N above this run in the background.
const BACKGROUND_STEPS: usize = 200;

/// The panels on the right.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Tab {
    #[default]
    Quality,
    Model,
    Samples,
    Smoothing,
}

impl Tab {
    const ALL: [Tab; 4] = [Tab::Quality, Tab::Model, Tab::Samples, Tab::Smoothing];

    fn name(self) -> &'static str {
        match self {
            Tab::Quality => "Quality",
            Tab::Model => "Model",
            Tab::Samples => "Training set",
            Tab::Smoothing => "Smoothing",
        }
    }

    fn parse(s: &str) -> Option<Tab> {
        match s {
            "quality" => Some(Tab::Quality),
            "model" => Some(Tab::Model),
            "samples" | "training" => Some(Tab::Samples),
            "smoothing" => Some(Tab::Smoothing),
            _ => None,
        }
    }
}

/// What the editor remembers between runs (eframe persistence): settings
/// and view choices, not the document.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Prefs {
    pub settings: Settings,
    pub recent: Recent,
    pub step: StepPanel,
    pub quality: QualityPanel,
    pub tab: Tab,
}

/// The finished mesh (cleaned up and smoothed) of one document version.
struct Finished {
    version: u64,
    mesh: QuadMesh,
}

pub struct App {
    pub doc: Document,
    pub history: History,
    pub view: View,
    pub prefs: Prefs,
    train_panel: TrainPanel,
    pub tools: Tools,
    /// The element the next step would cut, with the document version it
    /// belongs to.
    preview: Option<(u64, Vec<[Point; 4]>)>,
    model_panel: ModelPanel,
    samples_panel: SamplesPanel,
    smooth_panel: SmoothPanel,
    /// Figures of the last refit.
    pub refit: Option<document::RefitFigures>,
    /// Export path typed in the export box.
    pub export_path: String,
    /// The last message for the user (errors from files and steps).
    pub status: String,
    /// The project file the document was opened from or saved to.
    pub project_path: Option<PathBuf>,
    /// Changes since the last save.
    pub dirty: bool,
    /// Long runs go to a thread (off in some tests).
    pub background: bool,
    job: Option<Job>,
    /// Animated run: steps owed to the animation.
    animating: Option<f64>,
    /// Domain triangles of the boundary on the canvas.
    domain: canvas::DomainCache,
    mesh_cache: MeshCache,
    stats: MeshStats,
    /// Bumped whenever the document changes.
    version: u64,
    finished: Option<Finished>,
    finished_failed: Option<u64>,
    hover: Option<Point>,
    /// Where the canvas was drawn last (screen points).
    pub canvas_rect: egui::Rect,
    /// The close-without-saving question is open.
    confirm_close: bool,
    close_allowed: bool,
    screenshot: Option<PathBuf>,
    screenshot_requested: bool,
    frame: u64,
}

impl App {
    /// The editor over `doc`.
    pub fn new(doc: Document) -> App {
        App {
            export_path: std::env::temp_dir()
                .join("quadex_mesh.msh")
                .display()
                .to_string(),
            doc,
            history: History::default(),
            view: View::default(),
            prefs: Prefs::default(),
            train_panel: TrainPanel::default(),
            tools: Tools::default(),
            preview: None,
            model_panel: ModelPanel::default(),
            samples_panel: SamplesPanel::default(),
            smooth_panel: SmoothPanel::default(),
            refit: None,
            status: String::new(),
            project_path: None,
            dirty: false,
            background: true,
            job: None,
            animating: None,
            domain: canvas::DomainCache::default(),
            mesh_cache: MeshCache::default(),
            stats: MeshStats::default(),
            version: 0,
            finished: None,
            finished_failed: None,
            hover: None,
            canvas_rect: egui::Rect::NOTHING,
            confirm_close: false,
            close_allowed: false,
            screenshot: None,
            screenshot_requested: false,
            frame: 0,
        }
    }

    /// The editor as `quadex gui` starts it: the file (or the shipped
    /// example) opened with the remembered settings, then the requested
    /// steps taken.
    pub fn from_options(o: &GuiOptions, prefs: Prefs) -> Result<App, String> {
        let path = o.open.clone().unwrap_or_else(example_path);
        // Remembered settings that no longer load (a model file gone) give
        // way to the defaults.
        let doc = Document::open(&path, prefs.settings.clone())
            .or_else(|_| Document::open(&path, Settings::default()))?;
        let mut app = App::new(doc);
        app.prefs = prefs;
        app.note_opened(&path);
        if let Some(t) = o.panel.as_deref() {
            app.prefs.tab = Tab::parse(t).ok_or_else(|| format!("unknown panel `{t}`"))?;
        }
        if let Some(n) = o.steps {
            app.apply(Command::StepN(n));
        }
        if o.run {
            app.apply(Command::RunToEnd);
        }
        app.wait();
        app.screenshot = o.screenshot.clone();
        Ok(app)
    }

    /// True while a run is going in the background.
    pub fn busy(&self) -> bool {
        self.job.is_some()
    }

    /// Waits for the background run, if any, and takes its result.
    pub fn wait(&mut self) {
        if let Some(mut j) = self.job.take() {
            if let Some(r) = j.wait() {
                self.job_done(r);
            }
        }
    }

    /// Remembers a file opened from a path the user gave.
    fn note_opened(&mut self, path: &Path) {
        if document::is_project(path) {
            self.project_path = Some(path.to_path_buf());
        }
        self.prefs.recent.push(path);
    }

    /// The document changed: caches and the finished mesh are stale.
    fn changed(&mut self) {
        self.version += 1;
        self.dirty = true;
    }

    /// Runs an edit that keeps the document as it was for undo; on failure
    /// the document is left as it was.
    fn edit(
        &mut self,
        name: &'static str,
        f: impl FnOnce(&mut Document) -> Result<String, String>,
    ) -> Result<String, String> {
        let before = self.doc.clone();
        match f(&mut self.doc) {
            Ok(msg) => {
                self.history.edit(before, name);
                self.changed();
                Ok(msg)
            }
            Err(e) => {
                self.doc = before;
                Err(e)
            }
        }
    }

    /// Applies one command; failures go to the status line and leave the
    /// document as it was.
    pub fn apply(&mut self, cmd: Command) {
        if self.busy() && !matches!(cmd, Command::Cancel | Command::FitView) {
            self.status = "busy: wait for the run to finish or cancel it (Esc)".into();
            return;
        }
        let res = self.run_command(cmd);
        match res {
            Ok(s) => {
                if !s.is_empty() {
                    self.status = s;
                }
            }
            Err(e) => self.status = format!("error: {e}"),
        }
    }

    fn run_command(&mut self, cmd: Command) -> Result<String, String> {
        match cmd {
            Command::Step => self.step_sync(1).map(|k| {
                if k == 1 {
                    String::new()
                } else {
                    "the mesh is complete".into()
                }
            }),
            Command::StepN(n) if self.background && n > BACKGROUND_STEPS => {
                self.start_job(n, "stepping");
                Ok(format!("taking {n} steps…"))
            }
            Command::StepN(n) => self.step_sync(n).map(|k| format!("{k} steps")),
            Command::RunToEnd if self.background => {
                self.start_job(usize::MAX, "running to the end");
                Ok("running to the end…".into())
            }
            Command::RunToEnd => self
                .step_sync(usize::MAX)
                .map(|k| format!("{k} steps to the end")),
            Command::Animate(on) => {
                self.animating = on.then_some(0.0);
                Ok(if on { "running…" } else { "paused" }.into())
            }
            Command::Cancel => {
                self.animating = None;
                match &self.job {
                    Some(j) => {
                        j.cancel();
                        Ok("cancelling…".into())
                    }
                    None => Ok(String::new()),
                }
            }
            Command::Undo if self.tools.undo_draft() => Ok("undone: boundary draft edit".into()),
            Command::Redo if self.tools.redo_draft() => Ok("redone: boundary draft edit".into()),
            Command::Undo => {
                let what = self.history.undo(&mut self.doc);
                self.changed();
                Ok(what.map_or("nothing to undo".into(), |w| format!("undone: {w}")))
            }
            Command::Redo => {
                let what = self.history.redo(&mut self.doc);
                self.changed();
                Ok(what?.map_or("nothing to redo".into(), |w| format!("redone: {w}")))
            }
            Command::Reset => self.edit("reset", |d| d.reset().map(|_| "restarted".into())),
            Command::FitView => {
                self.view.fit_pending = true;
                Ok(String::new())
            }
            Command::Open(path) => {
                let settings = self.doc.settings.clone();
                let msg = self.edit("open", |d| {
                    *d = Document::open(&path, settings)?;
                    Ok(format!("opened {}", path.display()))
                })?;
                self.project_path = None;
                self.note_opened(&path);
                self.dirty = false;
                self.view.fit_pending = true;
                Ok(msg)
            }
            Command::Save => match self.project_path.clone() {
                Some(p) => self.save(&p),
                None => {
                    self.dialog(Dialog::SaveProjectAs);
                    Ok(String::new())
                }
            },
            Command::SaveProject(path) => self.save(&path),
            Command::Dialog(d) => {
                self.dialog(d);
                Ok(String::new())
            }
            Command::Export(path) => {
                crate::io::MeshFormat::from_path(&path)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                let mesh = self.finished_mesh()?;
                crate::io::write_mesh(&mesh, &path)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                Ok(format!("wrote {}", path.display()))
            }
            Command::SetSettings(s) => {
                self.prefs.settings = s.clone();
                self.edit("settings", |d| {
                    Ok(if d.set_settings(s)? {
                        "settings changed; mesh restarted".into()
                    } else {
                        "cleanup and smoothing changed".into()
                    })
                })
            }
            Command::AppendLast => self.edit("append sample", |d| {
                d.append_last()
                    .map(|n| format!("sample appended ({n} in the training set)"))
            }),
            Command::CorrectLast {
                element_type,
                pn,
                snap_to,
            } => self.edit("correction", |d| {
                d.correct_last(element_type, pn, snap_to).map(|n| {
                    format!("element corrected, sample appended ({n} in the training set)")
                })
            }),
            Command::Refit(form) => {
                let mut figures = None;
                let msg = self.edit("refit", |d| {
                    let f = d.refit(form)?;
                    let msg = format!(
                        "refitted ({}) on {} samples: Xn R {:.3} → {:.3}",
                        form.name(),
                        f.samples,
                        f.before.1.r,
                        f.after.1.r
                    );
                    figures = Some(f);
                    Ok(msg)
                })?;
                self.refit = figures;
                Ok(msg)
            }
            Command::ImportSamples(p) => self.edit("import samples", |d| {
                d.import_samples(&p)
                    .map(|n| format!("{n} samples imported from {}", p.display()))
            }),
            Command::ExportSamples(p) => self.doc.export_samples(&p).map(|_| {
                format!(
                    "wrote {} samples to {}",
                    self.doc.training.len(),
                    p.display()
                )
            }),
            Command::DeleteSamples(rows) => self.edit("delete samples", |d| {
                let left = d.delete_samples(&rows);
                Ok(format!("{} samples deleted, {left} left", rows.len()))
            }),
            Command::CollectFromMesh => {
                let mesh = self.finished_mesh()?;
                let name = self.doc.name();
                self.edit("collect samples", |d| {
                    d.collect_samples(&name, mesh)
                        .map(|n| format!("{n} samples collected from the mesh"))
                })
            }
            Command::CollectFromFile(p) => self.edit("collect samples", |d| {
                d.collect_from_file(&p)
                    .map(|n| format!("{n} samples collected from {}", p.display()))
            }),
            Command::UseModel(path) => {
                let s = Settings {
                    model: path.display().to_string(),
                    ..self.doc.settings.clone()
                };
                self.run_command(Command::SetSettings(s))
            }
            Command::SetBoundary(b) => self.edit("edit boundary", |d| {
                d.set_boundary(*b)
                    .map(|_| "boundary changed; mesh restarted".into())
            }),
        }
    }

    /// Steps on the UI thread; records them for undo.
    fn step_sync(&mut self, n: usize) -> Result<usize, String> {
        let mut k = 0;
        let res = loop {
            if k == n {
                break Ok(k);
            }
            match self.doc.step() {
                Ok(true) => k += 1,
                Ok(false) => break Ok(k),
                Err(e) => break Err(e),
            }
        };
        self.history.steps(k);
        if k > 0 {
            self.changed();
        }
        res
    }

    fn start_job(&mut self, n: usize, what: &'static str) {
        let s = &self.doc.settings;
        self.job = Some(Job::start(
            self.doc.mesher.clone(),
            n,
            Some(s.finishing()),
            what,
        ));
    }

    /// Takes a background run's result into the document.
    fn job_done(&mut self, r: Result<job::JobDone, String>) {
        let done = match r {
            Ok(d) => d,
            Err(e) => {
                self.status = format!("error: {e}");
                return;
            }
        };
        if done.steps > 0 {
            self.doc.mesher = done.mesher;
            self.doc.last = done.last;
            self.history.steps(done.steps);
            self.changed();
        }
        match done.finished {
            Some(Ok(mesh)) => {
                self.finished = Some(Finished {
                    version: self.version,
                    mesh,
                })
            }
            Some(Err(e)) => {
                self.finished_failed = Some(self.version);
                self.status = format!("error: {e}");
                return;
            }
            None => {}
        }
        self.status = match (done.error, done.cancelled) {
            (Some(e), _) => format!("error after {} steps: {e}", done.steps),
            (None, true) => format!("cancelled after {} steps", done.steps),
            (None, false) if done.steps > 0 => format!(
                "{} steps{}",
                done.steps,
                if self.doc.is_done() {
                    ", mesh complete"
                } else {
                    ""
                }
            ),
            (None, false) => "mesh finished".into(),
        };
    }

    fn save(&mut self, path: &Path) -> Result<String, String> {
        self.doc.save_project(path)?;
        self.project_path = Some(path.to_path_buf());
        self.prefs.recent.push(path);
        self.dirty = false;
        Ok(format!("saved {}", path.display()))
    }

    /// Asks for a file and applies what it is for.
    fn dialog(&mut self, d: Dialog) {
        let dir = self
            .project_path
            .as_ref()
            .or(self.doc.source.as_ref())
            .and_then(|p| p.parent())
            .map(Path::to_path_buf);
        let stem = self
            .doc
            .name()
            .split('.')
            .next()
            .unwrap_or("quadex")
            .to_string();
        if let Some(p) = files::pick(d, dir.as_deref(), &stem) {
            self.apply(files::command_for(d, p));
        }
    }

    /// The finished mesh of the current document (computed here when the
    /// background has not done it yet).
    fn finished_mesh(&mut self) -> Result<QuadMesh, String> {
        if let Some(f) = self.finished.as_ref().filter(|f| f.version == self.version) {
            return Ok(f.mesh.clone());
        }
        let m = self.doc.finished()?;
        self.finished = Some(Finished {
            version: self.version,
            mesh: m.clone(),
        });
        Ok(m)
    }

    /// The element the next step would cut (a step taken on a copy of the
    /// mesher), when the Extraction panel asks for it.
    fn refresh_preview(&mut self) {
        if !self.prefs.step.preview || self.busy() || self.doc.is_done() {
            self.preview = None;
            return;
        }
        if self
            .preview
            .as_ref()
            .is_some_and(|(v, _)| *v == self.version)
        {
            return;
        }
        let mut probe = self.doc.mesher.clone();
        let quads = match probe.step() {
            Ok(crate::extract::StepOutcome::Stepped(r)) => {
                r.quads.iter().map(|q| probe.mesh().corners(q)).collect()
            }
            _ => Vec::new(),
        };
        self.preview = Some((self.version, quads));
    }

    /// Keeps the finished mesh for display while the run is complete: the
    /// finishing pass runs in the background.
    fn refresh_finished(&mut self) {
        let fresh = self
            .finished
            .as_ref()
            .is_some_and(|f| f.version == self.version);
        if !self.doc.has_mesh()
            || fresh
            || self.busy()
            || self.finished_failed == Some(self.version)
        {
            return;
        }
        if self.background && self.doc.imported().is_none() {
            self.start_job(0, "cleanup and smoothing");
        } else if self.finished_mesh().is_err() {
            self.finished_failed = Some(self.version);
        }
    }

    /// The mesh on the canvas: the finished one when there is one.
    fn shown_mesh(&self) -> (&QuadMesh, bool) {
        shown(&self.finished, self.version, &self.doc)
    }

    /// Shortcuts and dropped files, as commands.
    fn input_commands(&self, ctx: &egui::Context, out: &mut Vec<Command>) {
        if ctx.wants_keyboard_input() {
            return;
        }
        let n = self.prefs.step.n;
        // Redo before Undo: Ctrl+Shift+Z also matches Ctrl+Z.
        for cmd in [
            Command::Redo,
            Command::Undo,
            Command::StepN(n),
            Command::Step,
            Command::RunToEnd,
            Command::Reset,
            Command::FitView,
            Command::Save,
            Command::Dialog(Dialog::Open),
            Command::Dialog(Dialog::ExportMesh),
            Command::Animate(self.animating.is_none()),
            Command::Cancel,
        ] {
            if let Some(s) = cmd.shortcut() {
                if ctx.input_mut(|i| i.consume_shortcut(&s)) {
                    out.push(cmd);
                }
            }
        }
        ctx.input(|i| {
            for f in &i.raw.dropped_files {
                if let Some(p) = &f.path {
                    out.push(Command::Open(p.clone()));
                }
            }
        });
    }

    /// One frame of the whole editor (also what the UI tests drive).
    pub fn ui(&mut self, ctx: &egui::Context) {
        self.frame += 1;
        if let Some(r) = self.job.as_mut().and_then(Job::poll) {
            self.job = None;
            self.job_done(r);
        }
        let mut cmds = Vec::new();
        self.input_commands(ctx, &mut cmds);
        self.tools.sync(&self.doc);
        self.refresh_preview();
        egui::TopBottomPanel::top("menu").show(ctx, |ui| {
            egui::MenuBar::new().ui(ui, |ui| self.menus(ui, &mut cmds));
        });
        egui::TopBottomPanel::bottom("status").show(ctx, |ui| self.status_bar(ui, &mut cmds));
        egui::SidePanel::left("steps")
            .resizable(true)
            .default_width(290.0)
            .show(ctx, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    let done = self.shown_mesh().1;
                    self.prefs
                        .step
                        .ui(ui, &self.doc, self.animating.is_some(), &mut cmds);
                    ui.separator();
                    self.train_panel
                        .ui(ui, &self.doc, self.refit.as_ref(), &mut cmds);
                    ui.separator();
                    self.tools.panel(ui, &self.doc, &mut cmds);
                    ui.separator();
                    ui.label(egui::RichText::new("Export").strong());
                    ui.text_edit_singleline(&mut self.export_path);
                    ui.label(".msh .msh22 .vtk .vtu .inp .svg");
                    ui.horizontal(|ui| {
                        if ui
                            .add_enabled(done, egui::Button::new("Export mesh"))
                            .clicked()
                        {
                            cmds.push(Command::Export(PathBuf::from(self.export_path.trim())));
                        }
                        if ui.add_enabled(done, egui::Button::new("Export…")).clicked() {
                            cmds.push(Command::Dialog(Dialog::ExportMesh));
                        }
                    });
                });
            });
        self.refresh_finished();
        let (shown_version, finished) = {
            let (_, fin) = self.shown_mesh();
            (2 * self.version + u64::from(fin), fin)
        };
        self.stats.refresh(
            shown_version,
            shown(&self.finished, self.version, &self.doc).0,
        );
        egui::SidePanel::right("panels")
            .resizable(true)
            .default_width(430.0)
            .show(ctx, |ui| {
                ui.horizontal(|ui| {
                    for t in Tab::ALL {
                        ui.selectable_value(&mut self.prefs.tab, t, t.name());
                    }
                });
                ui.separator();
                egui::ScrollArea::vertical().show(ui, |ui| match self.prefs.tab {
                    Tab::Quality => self.prefs.quality.ui(
                        ui,
                        &self.stats,
                        finished,
                        self.doc.imported().is_some(),
                    ),
                    Tab::Model => self.model_panel.ui(ui, &mut self.doc),
                    Tab::Samples => self.samples_panel.ui(ui, &self.doc, finished, &mut cmds),
                    Tab::Smoothing => self.smooth_panel.ui(
                        ui,
                        &self.doc,
                        self.version,
                        finished.then_some(&self.stats.summary),
                        &mut cmds,
                    ),
                });
            });
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ctx, |ui| {
                let front = {
                    let f = self.doc.mesher.front();
                    f.live_loops().map(|l| f.loop_nodes(l)).collect()
                };
                let (mesh, fin) = shown(&self.finished, self.version, &self.doc);
                let marked = self.tools.marked();
                let overlay = Overlay {
                    version: shown_version,
                    boundary: &self.doc.boundary,
                    domain: self.domain.of(&self.doc.boundary),
                    mesh,
                    qualities: &self.stats.per_quad,
                    index: &self.stats.index,
                    front,
                    // The finished mesh is renumbered: the last step's node
                    // ids belong to the mesher's own mesh.
                    last: if fin { None } else { self.doc.last.as_ref() },
                    metric: self.prefs.quality.metric,
                    marked: &marked,
                };
                let r = canvas::ui(ui, &mut self.view, &mut self.mesh_cache, &overlay);
                self.hover = r.hover;
                self.canvas_rect = r.rect;
                if let Some((_, quads)) = &self.preview {
                    let cyan = egui::Color32::from_rgb(80, 220, 255);
                    for q in quads {
                        let mut ring: Vec<egui::Pos2> =
                            q.iter().map(|&p| self.view.to_screen(r.rect, p)).collect();
                        ring.push(ring[0]);
                        ui.painter_at(r.rect).extend(egui::Shape::dashed_line(
                            &ring,
                            egui::Stroke::new(2.0, cyan),
                            6.0,
                            4.0,
                        ));
                    }
                }
                let at = tools::OnCanvas {
                    view: &self.view,
                    response: &r,
                    doc: &self.doc,
                    finished: fin,
                };
                self.tools
                    .canvas(ui, &at, &mut self.train_panel.pn, &mut cmds);
            });
        self.close_dialog(ctx, &mut cmds);
        for c in cmds {
            self.apply(c);
        }
        self.animate(ctx);
        if self.busy() {
            ctx.request_repaint_after(std::time::Duration::from_millis(50));
        }
        self.screenshot_step(ctx);
    }

    fn menus(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        let item = |ui: &mut egui::Ui,
                    label: &str,
                    cmd: Command,
                    enabled: bool,
                    out: &mut Vec<Command>| {
            let mut b = egui::Button::new(label);
            if let Some(s) = cmd.shortcut() {
                b = b.shortcut_text(ui.ctx().format_shortcut(&s));
            }
            if ui.add_enabled(enabled, b).clicked() {
                out.push(cmd);
            }
        };
        ui.menu_button("File", |ui| {
            item(ui, "Open…", Command::Dialog(Dialog::Open), true, cmds);
            ui.menu_button("Open an example", |ui| {
                for name in examples() {
                    if ui.button(&name).clicked() {
                        cmds.push(Command::Open(example_path().with_file_name(&name)));
                    }
                }
            });
            ui.menu_button("Open recent", |ui| {
                if self.prefs.recent.0.is_empty() {
                    ui.label("none yet");
                }
                for p in self.prefs.recent.0.clone() {
                    if ui.button(p.display().to_string()).clicked() {
                        cmds.push(Command::Open(p));
                    }
                }
            });
            ui.separator();
            item(ui, "Save project", Command::Save, true, cmds);
            item(
                ui,
                "Save project as…",
                Command::Dialog(Dialog::SaveProjectAs),
                true,
                cmds,
            );
            ui.separator();
            let done = self.doc.has_mesh();
            item(
                ui,
                "Export mesh…",
                Command::Dialog(Dialog::ExportMesh),
                done,
                cmds,
            );
            item(
                ui,
                "Import training samples…",
                Command::Dialog(Dialog::ImportSamples),
                true,
                cmds,
            );
            item(
                ui,
                "Export training samples…",
                Command::Dialog(Dialog::ExportSamples),
                !self.doc.training.is_empty(),
                cmds,
            );
            item(
                ui,
                "Collect samples from a mesh file…",
                Command::Dialog(Dialog::CollectFromFile),
                true,
                cmds,
            );
            ui.label("(or drop a .poly / .json file on the window)");
        });
        ui.menu_button("Edit", |ui| {
            let (draft_undo, draft_redo) = self.tools.draft_edits();
            let undo = if draft_undo {
                Some("boundary draft edit")
            } else {
                self.history.undo_name()
            };
            let redo = if draft_redo {
                Some("boundary draft edit")
            } else {
                self.history.redo_name()
            };
            let undo = undo.map_or("Undo".into(), |n| format!("Undo {n}"));
            let redo = redo.map_or("Redo".into(), |n| format!("Redo {n}"));
            let can_undo = draft_undo || self.history.can_undo();
            let can_redo = draft_redo || self.history.can_redo();
            item(ui, &undo, Command::Undo, can_undo, cmds);
            item(ui, &redo, Command::Redo, can_redo, cmds);
            ui.separator();
            item(ui, "Restart the mesh", Command::Reset, true, cmds);
        });
        ui.menu_button("Mesh", |ui| {
            let n = self.prefs.step.n;
            item(ui, "Step", Command::Step, true, cmds);
            item(ui, &format!("Step ×{n}"), Command::StepN(n), true, cmds);
            let anim = self.animating.is_some();
            item(
                ui,
                if anim { "Pause" } else { "Run (animated)" },
                Command::Animate(!anim),
                true,
                cmds,
            );
            item(ui, "Run to end", Command::RunToEnd, true, cmds);
            item(ui, "Cancel the run", Command::Cancel, self.busy(), cmds);
        });
        ui.menu_button("View", |ui| {
            item(ui, "Fit view", Command::FitView, true, cmds);
            ui.separator();
            for t in Tab::ALL {
                ui.selectable_value(&mut self.prefs.tab, t, t.name());
            }
        });
        ui.separator();
        ui.label(format!(
            "quadex — {}{}",
            self.doc.name(),
            if self.dirty { " •" } else { "" }
        ));
    }

    fn status_bar(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        ui.horizontal(|ui| {
            if let Some(j) = &self.job {
                let (steps, front, frac) = j.progress();
                ui.add(
                    egui::ProgressBar::new(frac)
                        .desired_width(160.0)
                        .text(format!("{} {steps} steps, {front} front nodes", j.what)),
                );
                ui.label(format!("{:.1} s", j.elapsed()));
                if ui.button("Cancel").clicked() {
                    cmds.push(Command::Cancel);
                }
                ui.separator();
            }
            if let Some(p) = self.hover {
                ui.monospace(format!("x {:.4}  y {:.4}", p.x, p.y));
                ui.separator();
            }
            ui.label(&self.status);
        });
    }

    /// The animated run: steps at the panel's speed, on the UI thread.
    fn animate(&mut self, ctx: &egui::Context) {
        let Some(owed) = self.animating else { return };
        if self.busy() {
            return;
        }
        let dt = ctx.input(|i| i.stable_dt).min(0.1) as f64;
        let owed = owed + dt * self.prefs.step.speed;
        let n = owed.floor() as usize;
        self.animating = Some(owed - n as f64);
        if n > 0 {
            match self.step_sync(n.min(1000)) {
                Ok(k) if k < n.min(1000) => {
                    self.animating = None;
                    self.status = "the mesh is complete".into();
                }
                Ok(_) => {}
                Err(e) => {
                    self.animating = None;
                    self.status = format!("error: {e}");
                }
            }
        }
        ctx.request_repaint();
    }

    /// Closing with unsaved changes asks first.
    fn close_dialog(&mut self, ctx: &egui::Context, cmds: &mut Vec<Command>) {
        if ctx.input(|i| i.viewport().close_requested()) && self.dirty && !self.close_allowed {
            ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            self.confirm_close = true;
        }
        if !self.confirm_close {
            return;
        }
        egui::Modal::new(egui::Id::new("confirm_close")).show(ctx, |ui| {
            ui.heading("Unsaved changes");
            ui.label(format!(
                "Save the changes to {} before closing?",
                self.doc.name()
            ));
            ui.horizontal(|ui| {
                if ui.button("Save").clicked() {
                    self.confirm_close = false;
                    cmds.push(Command::Save);
                }
                if ui.button("Close without saving").clicked() {
                    self.confirm_close = false;
                    self.close_allowed = true;
                    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                }
                if ui.button("Cancel").clicked() {
                    self.confirm_close = false;
                }
            });
        });
    }

    /// The `--screenshot` option: request a screenshot after the first
    /// frames, save it when it arrives, then close.
    fn screenshot_step(&mut self, ctx: &egui::Context) {
        let Some(path) = self.screenshot.clone() else {
            return;
        };
        if self.busy() {
            ctx.request_repaint();
            return;
        }
        if !self.screenshot_requested && self.frame >= SCREENSHOT_FRAME {
            ctx.send_viewport_cmd(egui::ViewportCommand::Screenshot(Default::default()));
            self.screenshot_requested = true;
        }
        let shot = ctx.input(|i| {
            i.raw.events.iter().find_map(|e| match e {
                egui::Event::Screenshot { image, .. } => Some(image.clone()),
                _ => None,
            })
        });
        if let Some(img) = shot {
            let [w, h] = img.size;
            let bytes: Vec<u8> = img.pixels.iter().flat_map(|c| c.to_array()).collect();
            let saved = image::RgbaImage::from_raw(w as u32, h as u32, bytes)
                .ok_or_else(|| "bad screenshot buffer".to_string())
                .and_then(|im| im.save(&path).map_err(|e| e.to_string()));
            match saved {
                Ok(()) => eprintln!("quadex: wrote {}", path.display()),
                Err(e) => eprintln!("quadex: {}: {e}", path.display()),
            }
            self.screenshot = None;
            self.close_allowed = true;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        } else {
            ctx.request_repaint();
        }
    }
}

/// The mesh on the canvas: the finished one when it belongs to this
/// version of the document, else the mesh as stepped.
fn shown<'a>(
    finished: &'a Option<Finished>,
    version: u64,
    doc: &'a Document,
) -> (&'a QuadMesh, bool) {
    match finished {
        Some(f) if f.version == version && doc.has_mesh() => (&f.mesh, true),
        _ => (doc.mesher.mesh(), false),
    }
}

/// The shipped example boundaries, sorted.
fn examples() -> Vec<String> {
    let dir = example_path().with_file_name("");
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(".poly"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

impl eframe::App for App {
    fn update(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        self.ui(ctx);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        if !self.screenshot_requested {
            eframe::set_value(storage, eframe::APP_KEY, &self.prefs);
        }
    }
}

/// Runs the editor window.
pub fn run(o: GuiOptions) -> Result<(), String> {
    let size = o.size.unwrap_or([1400.0, 860.0]);
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size(size)
            .with_title("quadex")
            .with_drag_and_drop(true),
        // A screenshot run neither reads nor writes the remembered settings.
        persist_window: o.screenshot.is_none(),
        ..Default::default()
    };
    // A file that cannot be opened is reported before a window opens.
    Document::open(
        &o.open.clone().unwrap_or_else(example_path),
        Settings::default(),
    )?;
    let screenshot = o.screenshot.is_some();
    eframe::run_native(
        "quadex",
        native,
        Box::new(move |cc| {
            let prefs = match cc.storage {
                Some(s) if !screenshot => eframe::get_value(s, eframe::APP_KEY).unwrap_or_default(),
                _ => Prefs::default(),
            };
            let app = App::from_options(&o, prefs)
                .map_err(|e| -> Box<dyn std::error::Error + Send + Sync> { e.into() })?;
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| e.to_string())
}

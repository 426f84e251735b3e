//! The desktop editor (eframe/egui): a view and a controller over the core.
//! [`App`] holds the [`Document`] (boundary, mesher, training set), the
//! canvas [`View`], the panels' own state and a status line; every user
//! intent is a [`Command`] applied in [`App::apply`]. No meshing logic
//! lives here: the editor drives `Mesher` through its public step API like
//! the CLI and the tests do.

pub mod canvas;
pub mod command;
pub mod document;
pub mod step_panel;
pub mod train_panel;

use crate::geom::Point;
use canvas::{MeshCache, Overlay, View};
pub use command::Command;
pub use document::{Document, Settings};
use std::path::{Path, PathBuf};
use step_panel::StepPanel;
use train_panel::TrainPanel;

/// How the editor starts (`quadex gui`).
#[derive(Clone, Debug, Default)]
pub struct GuiOptions {
    /// Boundary to open (default: the shipped example).
    pub open: Option<PathBuf>,
    /// Steps to take after opening.
    pub steps: Option<usize>,
    /// Run to the end after opening.
    pub run: bool,
    /// Save a PNG of the window after the first frames and exit.
    pub screenshot: Option<PathBuf>,
    /// Window size in points.
    pub size: Option<[f32; 2]>,
}

/// The shipped example the editor opens by default.
pub fn example_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples/annulus.poly")
}

/// Frames drawn before a screenshot is taken (layout and view settle).
const SCREENSHOT_FRAME: u64 = 3;

pub struct App {
    pub doc: Document,
    pub view: View,
    step_panel: StepPanel,
    train_panel: TrainPanel,
    /// Figures of the last refit.
    pub refit: Option<document::RefitFigures>,
    /// Export path typed in the export box.
    pub export_path: String,
    /// The last message for the user (errors from files and steps).
    pub status: String,
    /// Cached domain triangles of the boundary.
    domain: Vec<[Point; 3]>,
    color_by_quality: bool,
    mesh_cache: MeshCache,
    /// Bumped whenever a command may have changed the mesh.
    version: u64,
    /// The smoothed mesh once the run is complete, with the step count it
    /// belongs to.
    finished: Option<(usize, crate::mesh::QuadMesh)>,
    hover: Option<Point>,
    screenshot: Option<PathBuf>,
    screenshot_requested: bool,
    frame: u64,
}

impl App {
    /// The editor over `doc`.
    pub fn new(doc: Document) -> App {
        let domain = canvas::domain_triangles(&doc.boundary);
        App {
            export_path: std::env::temp_dir()
                .join("quadex_mesh.msh")
                .display()
                .to_string(),
            doc,
            view: View::default(),
            step_panel: StepPanel::default(),
            train_panel: TrainPanel::default(),
            refit: None,
            status: String::new(),
            domain,
            color_by_quality: true,
            mesh_cache: MeshCache::default(),
            version: 0,
            finished: None,
            hover: None,
            screenshot: None,
            screenshot_requested: false,
            frame: 0,
        }
    }

    /// The editor as `quadex gui` starts it: the file (or the shipped
    /// example) opened, then the requested steps taken.
    pub fn from_options(o: &GuiOptions) -> Result<App, String> {
        let path = o.open.clone().unwrap_or_else(example_path);
        let mut app = App::new(Document::open(&path, Settings::default())?);
        if let Some(n) = o.steps {
            app.apply(Command::StepN(n));
        }
        if o.run {
            app.apply(Command::RunToEnd);
        }
        app.screenshot = o.screenshot.clone();
        Ok(app)
    }

    /// Applies one command; failures go to the status line and leave the
    /// document as it was.
    pub fn apply(&mut self, cmd: Command) {
        self.version += 1;
        let res: Result<String, String> = match cmd {
            Command::Step => self.doc.step().map(|more| {
                if more {
                    String::new()
                } else {
                    "the mesh is complete".into()
                }
            }),
            Command::StepN(n) => self.doc.step_n(n).map(|k| format!("{k} steps")),
            Command::RunToEnd => self
                .doc
                .run_to_end()
                .map(|k| format!("{k} steps to the end")),
            Command::Undo => Ok(if self.doc.undo() {
                "undone".into()
            } else {
                "nothing to undo".into()
            }),
            Command::Reset => self.doc.reset().map(|_| "restarted".into()),
            Command::FitView => {
                self.view.fit_pending = true;
                Ok(String::new())
            }
            Command::Open(path) => Document::open(&path, self.doc.settings.clone()).map(|d| {
                self.domain = canvas::domain_triangles(&d.boundary);
                self.doc = d;
                self.view.fit_pending = true;
                format!("opened {}", path.display())
            }),
            Command::Export(path) => self
                .doc
                .export(&path)
                .map(|_| format!("wrote {}", path.display())),
            Command::SetSettings(s) => self
                .doc
                .set_settings(s)
                .map(|_| "settings changed; mesh restarted".into()),
            Command::AppendLast => self
                .doc
                .append_last()
                .map(|n| format!("sample appended ({n} in the training set)")),
            Command::CorrectLast { element_type, pn } => self
                .doc
                .correct_last(element_type, pn)
                .map(|n| format!("element corrected, sample appended ({n} in the training set)")),
            Command::Refit(form) => self.doc.refit(form).map(|f| {
                let msg = format!(
                    "refitted ({}) on {} samples: Xn R {:.3} → {:.3}",
                    form.name(),
                    f.samples,
                    f.before.1.r,
                    f.after.1.r
                );
                self.refit = Some(f);
                msg
            }),
        };
        self.status = match res {
            Ok(s) => s,
            Err(e) => format!("error: {e}"),
        };
    }

    /// Shortcuts and dropped files, as commands.
    fn input_commands(&self, ctx: &egui::Context, out: &mut Vec<Command>) {
        let n = self.step_panel.n;
        for cmd in [
            Command::StepN(n),
            Command::Step,
            Command::RunToEnd,
            Command::Undo,
            Command::Reset,
            Command::FitView,
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
        let mut cmds = Vec::new();
        self.input_commands(ctx, &mut cmds);
        egui::TopBottomPanel::top("menu").show(ctx, |ui| {
            egui::MenuBar::new().ui(ui, |ui| {
                ui.menu_button("File", |ui| {
                    ui.label("Open an example:");
                    for name in examples() {
                        if ui.button(&name).clicked() {
                            let p = example_path().with_file_name(&name);
                            cmds.push(Command::Open(p));
                        }
                    }
                    ui.label("(or drop a .poly / .json file on the window)");
                });
                ui.menu_button("View", |ui| {
                    ui.checkbox(
                        &mut self.color_by_quality,
                        "colour quads by scaled Jacobian",
                    );
                    if ui.button("Fit view (F)").clicked() {
                        cmds.push(Command::FitView);
                    }
                });
                ui.separator();
                ui.label(format!("quadex — {}", self.doc.name()));
            });
        });
        egui::TopBottomPanel::bottom("status").show(ctx, |ui| {
            ui.horizontal(|ui| {
                if let Some(p) = self.hover {
                    ui.monospace(format!("x {:.4}  y {:.4}", p.x, p.y));
                    ui.separator();
                }
                ui.label(&self.status);
            });
        });
        egui::SidePanel::left("steps")
            .resizable(true)
            .default_width(280.0)
            .show(ctx, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    self.step_panel.ui(ui, &self.doc, &mut cmds);
                    ui.separator();
                    self.train_panel
                        .ui(ui, &self.doc, self.refit.as_ref(), &mut cmds);
                    ui.separator();
                    ui.label(egui::RichText::new("Export").strong());
                    ui.text_edit_singleline(&mut self.export_path);
                    ui.label(".msh .msh22 .vtk .vtu .inp .svg");
                    if ui.button("Export mesh").clicked() {
                        cmds.push(Command::Export(PathBuf::from(self.export_path.trim())));
                    }
                });
            });
        self.refresh_finished();
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ctx, |ui| {
                let front = {
                    let f = self.doc.mesher.front();
                    f.live_loops().map(|l| f.loop_nodes(l)).collect()
                };
                let overlay = Overlay {
                    // The finished mesh is renumbered: a version of its own.
                    version: 2 * self.version + u64::from(self.finished.is_some()),
                    boundary: &self.doc.boundary,
                    domain: &self.domain,
                    mesh: match &self.finished {
                        Some((_, m)) => m,
                        None => self.doc.mesher.mesh(),
                    },
                    front,
                    // The finished mesh is renumbered: the last step's node
                    // ids belong to the mesher's own mesh.
                    last: match &self.finished {
                        Some(_) => None,
                        None => self.doc.last.as_ref(),
                    },
                    color_by_quality: self.color_by_quality,
                };
                self.hover = canvas::ui(ui, &mut self.view, &mut self.mesh_cache, &overlay);
            });
        for c in cmds {
            self.apply(c);
        }
        self.screenshot_step(ctx);
    }

    /// Keeps the smoothed mesh for display while the run is complete.
    fn refresh_finished(&mut self) {
        let steps = self.doc.mesher.steps();
        let stale = self.finished.as_ref().is_none_or(|(k, _)| *k != steps);
        if !self.doc.is_done() {
            self.finished = None;
        } else if stale {
            self.finished = self.doc.finished().ok().map(|m| (steps, m));
        }
    }

    /// The `--screenshot` option: request a screenshot after the first
    /// frames, save it when it arrives, then close.
    fn screenshot_step(&mut self, ctx: &egui::Context) {
        let Some(path) = self.screenshot.clone() else {
            return;
        };
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
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        } else {
            ctx.request_repaint();
        }
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
}

/// Runs the editor window.
pub fn run(o: GuiOptions) -> Result<(), String> {
    let app = App::from_options(&o)?;
    let size = o.size.unwrap_or([1280.0, 800.0]);
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size(size)
            .with_title("quadex"),
        ..Default::default()
    };
    eframe::run_native("quadex", native, Box::new(|_cc| Ok(Box::new(app))))
        .map_err(|e| e.to_string())
}

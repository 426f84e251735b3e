//! The menus and the keyboard shortcuts, as commands.

use super::command::{Command, Dialog};
use super::files::Prompt;
use super::layout::Tab;
use super::{assets, App};

impl App {
    pub(super) fn menus(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
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
                "A boundary (.poly, .json), a drawing (.dxf), a project or a quad mesh (.msh)",
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

    /// Shortcuts and dropped files, as commands. Esc closes an open menu
    /// first, then drops a loop being drawn, then cancels.
    pub(super) fn input_commands(&self, ctx: &egui::Context, out: &mut Vec<Command>) {
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
}

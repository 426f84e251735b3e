//! Questions and file dialogs: unsaved work asked about, the desktop's
//! file dialog (else the prompt in the window), and the folder and name a
//! dialog or the Export box starts from.

use super::command::{Command, Dialog};
use super::files::{self, Prompt};
use super::text::{plural, stem};
use super::{document, App, Ask, Then};
use std::path::{Path, PathBuf};

impl App {
    /// The questions (unsaved work) and the file prompt.
    pub(super) fn questions(&mut self, ctx: &egui::Context, cmds: &mut Vec<Command>) {
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

    /// Asks for a file (the desktop's dialog, else the prompt in the
    /// window) and applies what it is for.
    pub(super) fn dialog(&mut self, d: Dialog) {
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

    /// The folder and file name a dialog starts from: [`App::document_dir`],
    /// else the working directory.
    pub(super) fn dialog_start(&self, d: Dialog) -> (PathBuf, String) {
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

    /// The folder a document's files go to: the folder of its own file;
    /// for a document of no file (a built-in example, a new drawing) the
    /// folder of the last mesh exported, else none (a folder another
    /// document was opened from is not this one's).
    pub(super) fn document_dir(&self) -> Option<PathBuf> {
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

    /// The folder and file name in the side panel's Export box, where the
    /// export dialog starts too (so the two agree).
    pub(super) fn export_box_path(&self) -> Option<(PathBuf, String)> {
        let p = Path::new(self.panels.export_path.trim());
        let name = p.file_name()?.to_str()?.to_string();
        let dir = p.parent().filter(|d| !d.as_os_str().is_empty())?;
        Some((dir.to_path_buf(), name))
    }

    /// The default export path: beside the document's file, named after
    /// it; for a document of no file in the folder of the last export,
    /// and with none, no path.
    pub(super) fn default_export_path(&self) -> String {
        if self.document_dir().is_none() {
            return String::new();
        }
        let (dir, name) = self.dialog_start(Dialog::ExportMesh);
        dir.join(name).display().to_string()
    }
}

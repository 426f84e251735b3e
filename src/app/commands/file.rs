//! Files: New, Open, the examples, Save, the boundary saved, the mesh
//! exported.

use crate::app::command::Dialog;
use crate::app::document::Document;
use crate::app::error::EditorError;
use crate::app::text::plural;
use crate::app::tools::Tool;
use crate::app::{App, Then};
use std::path::{Path, PathBuf};

impl App {
    /// File ▸ New: an empty document with the drawing tool.
    pub(in crate::app) fn new_document(&mut self) -> Result<String, EditorError> {
        let settings = self.document.doc.portable_settings();
        self.replace_document("new", |d| {
            *d = Document::empty(settings);
            Ok(())
        })?;
        self.after_open(None);
        self.panels.tools.tool = Tool::Draw;
        Ok("a new boundary: click on the canvas to place the outer loop's nodes".into())
    }

    /// Opens a boundary, drawing, project or mesh file.
    pub(in crate::app) fn open_file(&mut self, path: PathBuf) -> Result<String, EditorError> {
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

    /// Opens a shipped example.
    pub(in crate::app) fn open_example(
        &mut self,
        name: &'static str,
    ) -> Result<String, EditorError> {
        let settings = self.document.doc.portable_settings();
        self.replace_document("open", |d| {
            *d = Document::example(name, settings)?;
            Ok(())
        })?;
        self.after_open(None);
        Ok(self.opened_message(name))
    }

    /// Save: to the project file, else asks where.
    pub(in crate::app) fn save_or_ask(&mut self) -> Result<String, EditorError> {
        match self.document.project_path.clone() {
            Some(p) => self.save(&p),
            None => {
                self.dialog(Dialog::SaveProjectAs);
                Ok(String::new())
            }
        }
    }

    /// Writes the boundary (`.poly`, or `.json` for any draft).
    pub(in crate::app) fn save_boundary(&mut self, path: PathBuf) -> Result<String, EditorError> {
        self.document.doc.save_boundary(&path)?;
        self.window.recent.push(&path);
        Ok(format!("saved the boundary to {}", path.display()))
    }

    /// After a document was opened or made: its file, a fresh view, the
    /// export path beside it.
    pub(in crate::app) fn after_open(&mut self, path: Option<&Path>) {
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

    pub(in crate::app) fn opened_message(&self, name: &str) -> String {
        match &self.document.doc.problem {
            None => format!("opened {name}"),
            Some(e) => format!("opened {name} as a draft to fix: {e}"),
        }
    }

    /// After an export to `path`: the Export box writes there again. The
    /// export's folder becomes the default one (the next document's box
    /// starts there), and that change of default is not taken for another
    /// document, which would put the default back in the box.
    fn exported_to(&mut self, path: &Path) {
        self.window.recent.push(path);
        self.note_export(path);
        self.panels.export_path = path.display().to_string();
        self.panels.export_default = Some(self.default_export_path());
    }

    /// Exports the finished mesh; while the finishing pass runs, the export
    /// waits for it.
    pub(in crate::app) fn export(&mut self, path: PathBuf) -> Result<String, EditorError> {
        let format = crate::io::MeshFormat::from_path(&path)?;
        if let Some(r) = &self.document.doc.regions {
            // The regions as physical surfaces, the groups as physical
            // curves (or the format's sets and arrays).
            let m = r.mesh.clone().ok_or(EditorError::NotFinished)?;
            crate::io::write_atomic(&path, format.render_regions(&m).as_bytes())?;
            self.exported_to(&path);
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
        self.exported_to(&path);
        Ok(format!(
            "wrote {} ({})",
            path.display(),
            plural(mesh.quads.len(), "quad")
        ))
    }

    /// Remembers the folder a mesh was exported to.
    pub(in crate::app) fn note_export(&mut self, path: &Path) {
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map(Path::to_path_buf)
            .or_else(|| std::env::current_dir().ok());
        if let Some(d) = dir {
            self.window.export_dir = Some(std::path::absolute(&d).unwrap_or(d));
        }
    }

    pub(in crate::app) fn save(&mut self, path: &Path) -> Result<String, EditorError> {
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
}

//! Undo, redo and reset.

use crate::app::error::EditorError;
use crate::app::history::Undone;
use crate::app::{same_mesh, App};

impl App {
    /// Undo: the last edit, or the last step.
    pub(in crate::app) fn undo(&mut self) -> Result<String, EditorError> {
        let before = self.document.doc.clone();
        let what = self
            .document
            .history
            .undo(&mut self.document.doc, &mut self.document.project_path);
        let mesh = what.is_some_and(|w| w.step) || !same_mesh(&before, &self.document.doc);
        if what.is_some() {
            self.changed(mesh);
        }
        self.fit_if_replaced(what);
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

    /// Redo: the last edit or step undone.
    pub(in crate::app) fn redo(&mut self) -> Result<String, EditorError> {
        let before = self.document.doc.clone();
        let what = self
            .document
            .history
            .redo(&mut self.document.doc, &mut self.document.project_path)?;
        let mesh = what.is_some_and(|w| w.step) || !same_mesh(&before, &self.document.doc);
        if what.is_some() {
            self.changed(mesh);
        }
        self.fit_if_replaced(what);
        Ok(what.map_or("nothing to redo".into(), |w| format!("redone: {}", w.name)))
    }

    /// After undoing or redoing `what`: an edit that replaced the whole
    /// document (New, Open) brings another boundary back, which the view
    /// is fitted to, as it was when the document was opened.
    fn fit_if_replaced(&mut self, what: Option<Undone>) {
        if what.is_some_and(|w| matches!(w.name, "open" | "new")) {
            self.view.canvas.fit_pending = true;
        }
    }

    /// Reset: the mesh starts again (one undo brings it back).
    pub(in crate::app) fn reset_mesh(&mut self) -> Result<String, EditorError> {
        self.edit("reset", |d| d.reset().map(|_| "restarted".into()))
    }
}

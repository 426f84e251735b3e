//! The model and its training: settings, the element accepted or
//! corrected, the refit (in the background), the model saved.

use crate::app::background::RefitJob;
use crate::app::document::{self, Settings};
use crate::app::error::EditorError;
use crate::app::job::Record;
use crate::app::text::{figure, plural};
use crate::app::App;
use crate::geom::Point;
use crate::model::{ElementType, Form};
use std::path::PathBuf;
use std::sync::Arc;

impl App {
    /// New settings: the mesh restarts, unless only finishing changed.
    pub(in crate::app) fn set_settings(&mut self, s: Settings) -> Result<String, EditorError> {
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

    /// Meshes with the model in this file.
    pub(in crate::app) fn use_model(&mut self, path: PathBuf) -> Result<String, EditorError> {
        let s = Settings {
            model: path.display().to_string(),
            ..self.document.doc.settings.clone()
        };
        self.set_settings(s)
    }

    /// Appends the last element to the training set as it is.
    pub(in crate::app) fn append_last(&mut self) -> Result<String, EditorError> {
        self.edit("append sample", |d| {
            d.append_last()
                .map(|n| format!("sample appended ({} of yours)", plural(n, "sample")))
        })
    }

    /// Replaces the last element by the user's.
    pub(in crate::app) fn correct_last(
        &mut self,
        element_type: ElementType,
        pn: Point,
        snap_to: Option<u32>,
    ) -> Result<String, EditorError> {
        let before = self.cached_before_last();
        self.edit("correct element", |d| {
            d.correct_last(element_type, pn, snap_to, before)
                .map(|n| format!("element corrected ({} of yours)", plural(n, "sample")))
        })
    }

    /// Refits the model (in the background with threads); with
    /// `mesh_rest` the rest is meshed with it.
    pub(in crate::app) fn start_refit(
        &mut self,
        form: Form,
        mesh_rest: bool,
    ) -> Result<String, EditorError> {
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

    /// Writes the refitted model meshed with now as a model file.
    pub(in crate::app) fn save_model(&mut self, path: PathBuf) -> Result<String, EditorError> {
        let name = self.document.doc.save_model(&path)?;
        Ok(format!("saved the model {name} to {}", path.display()))
    }

    /// Takes a refit made into the document (one undo takes it back, and
    /// the rest it meshes).
    pub(in crate::app) fn refit_done(
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
}

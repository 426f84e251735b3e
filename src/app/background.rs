//! Work off the UI thread and what comes back from it: runs, runs of a
//! document of regions, refits and the finishing pass; the animated run;
//! the caches the frame refreshes (the finished mesh, the next element's
//! preview, the closing targets).

use super::command::Command;
use super::error::EditorError;
use super::job::{Job, JobDone, Record, Work};
use super::text::plural;
use super::tools::Tool;
use super::{document, App, Finished};
use crate::extract::Rung;
use crate::mesh::QuadMesh;
use std::sync::Arc;

/// A finishing-settings change waits this long for the next before the
/// finished mesh is computed again (a dragged value changes every frame).
pub(super) const FINISH_DEBOUNCE: std::time::Duration = std::time::Duration::from_millis(250);

/// A run of a document of regions in a thread: its faces stepped on a
/// copy of the stepper, taken into the document when it ends (a
/// cancelled run is dropped, the mesh stays as before it).
pub(super) struct RegionRun {
    pub(super) handle: std::thread::JoinHandle<RegionRunDone>,
    pub(super) cancel: Arc<std::sync::atomic::AtomicBool>,
    pub(super) steps: Arc<std::sync::atomic::AtomicUsize>,
    pub(super) face: Arc<std::sync::atomic::AtomicUsize>,
    pub(super) faces: usize,
    pub(super) started: std::time::Instant,
}

/// What a run of a document of regions gives back.
pub(super) struct RegionRunDone {
    pub(super) stepper: crate::regions::RegionStepper,
    pub(super) steps: usize,
    pub(super) last: Option<crate::extract::StepReport>,
    pub(super) error: Option<crate::regions::RegionError>,
    /// The merged mesh, when every face is meshed.
    pub(super) mesh: Option<Result<crate::regions::RegionMesh, crate::regions::RegionError>>,
}

impl RegionRun {
    /// Steps `stepper` up to `max` steps (to the end with `usize::MAX`).
    pub(super) fn start(mut stepper: crate::regions::RegionStepper, max: usize) -> RegionRun {
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
pub(super) struct RefitJob {
    pub(super) handle: std::thread::JoinHandle<Result<document::RefitDone, String>>,
    pub(super) phase: Arc<std::sync::Mutex<document::RefitPhase>>,
    /// Mesh the rest with the refitted model once it is taken.
    pub(super) mesh_rest: bool,
    pub(super) started: std::time::Instant,
}

impl RefitJob {
    /// What the refit is doing now.
    pub(super) fn phase(&self) -> String {
        self.phase
            .lock()
            .map_or_else(|_| String::new(), |p| p.describe())
    }
}

impl App {
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

    /// Takes a refit's thread's result (its error to the status line).
    pub(super) fn refit_joined(&mut self, r: RefitJob) {
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

    /// Takes a finished run of a document of regions into the document.
    pub(super) fn region_run_done(&mut self, run: RegionRun) {
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

    /// Takes a background job's result into the document.
    pub(super) fn job_done(&mut self, job: Job, done: Option<JobDone>) {
        let Some(done) = done else {
            self.window.status = format!("error: {}", EditorError::JobPanicked);
            return;
        };
        if job.is_run() {
            let mut remade = false;
            if done.steps > 0 {
                // The steps undo can take back one by one: those the
                // mesher's history gained. A rewind or a run made again
                // with balanced fans replaces steps, so the history may
                // hold fewer than were taken.
                let mut gained = done.steps;
                if let Some(m) = self.document.doc.meshing.as_mut() {
                    gained = done.mesher.steps().saturating_sub(m.mesher.steps());
                    m.mesher = done.mesher;
                    if done.last.is_some() {
                        m.last = done.last;
                    }
                    remade = m.last.as_ref().is_some_and(|r| r.rung == Rung::Refan);
                }
                if job.record == Record::Steps {
                    self.document.history.steps(gained);
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
                        "{what}{} taken{}{}{}{worse}",
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
                        },
                        if remade {
                            " (the run made again with balanced corner fans)"
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
    pub(super) fn export_pending(&mut self) {
        let key = self.finish_key();
        let ready = self.view.finished.as_ref().is_some_and(|f| f.key == key);
        if ready || self.view.finish_failed == Some(key) {
            if let Some(p) = self.background.pending_export.take() {
                self.apply_now(Command::Export(p));
            }
        }
    }

    /// The finished mesh of the current document (computed here when the
    /// background has not done it yet).
    pub(super) fn finished_mesh(&mut self) -> Result<QuadMesh, EditorError> {
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
    pub(super) fn refresh_finished(&mut self, ctx: &egui::Context) {
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
    pub(super) fn refresh_preview(&mut self) {
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
    pub(super) fn refresh_targets(&mut self) {
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

    /// The animated run: steps at the panel's speed, on the UI thread.
    pub(super) fn animate(&mut self, ctx: &egui::Context) {
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
}

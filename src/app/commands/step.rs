//! Stepping and running: one step, N steps, the run to the end (in the
//! background above [`BACKGROUND_STEPS`]), the animated run, Cancel, and
//! the finishing pass asked for again.

use crate::app::background::RegionRun;
use crate::app::error::EditorError;
use crate::app::framed::Framed;
use crate::app::job::{Job, Record, Work};
use crate::app::text::plural;
use crate::app::{document, App};

/// Steps ×N above this run in the background.
const BACKGROUND_STEPS: usize = 200;

impl App {
    /// Step: one extraction step.
    pub(in crate::app) fn step_once(&mut self) -> Result<String, EditorError> {
        self.step_sync(1).map(|k| match self.document.doc.last() {
            Some(r) if k == 1 => {
                format!("step {}: {}", r.index + 1, document::kind_name(r.kind))
            }
            _ if k == 1 => "stepped".into(),
            _ => "the mesh is complete".into(),
        })
    }

    /// Steps ×N: in the background above [`BACKGROUND_STEPS`].
    pub(in crate::app) fn step_n(&mut self, n: usize) -> Result<String, EditorError> {
        if self.background.threads && n > BACKGROUND_STEPS {
            if self.document.doc.regions.is_some() {
                self.start_region_run(n)?;
                return Ok(format!("taking {n} steps…"));
            }
            self.start_run(n, "stepping", Record::Steps)?;
            return Ok(format!("taking {n} steps…"));
        }
        self.step_sync(n).map(|k| plural(k, "step"))
    }

    /// Run to the end: in the background unless threads are off.
    pub(in crate::app) fn run_to_end(&mut self) -> Result<String, EditorError> {
        if self.background.threads && self.document.doc.regions.is_some() {
            self.start_region_run(usize::MAX)?;
            return Ok("running every region to the end…".into());
        }
        if self.background.threads {
            self.start_run(usize::MAX, "running to the end", Record::Steps)?;
            return Ok("running to the end…".into());
        }
        self.step_sync(usize::MAX)
            .map(|k| format!("{} to the end", plural(k, "step")))
    }

    /// Starts or stops the animated run.
    pub(in crate::app) fn set_animating(&mut self, on: bool) -> Result<String, EditorError> {
        if on && !self.document.doc.can_step() {
            return Err(self.no_boundary());
        }
        self.background.animating = on.then_some(0.0);
        Ok(if on { "running…" } else { "paused" }.into())
    }

    /// Mesh ▸ Finish the mesh: the finishing pass starts again.
    pub(in crate::app) fn finish_again(&mut self) -> Result<String, EditorError> {
        self.view.finish_failed = None;
        Ok("finishing the mesh…".into())
    }

    pub(in crate::app) fn no_boundary(&self) -> EditorError {
        EditorError::NoBoundary(
            self.document
                .doc
                .problem
                .clone()
                .unwrap_or(crate::boundary::BoundaryError::Empty),
        )
    }

    /// Stops the background run (the document stays as before it), the
    /// finishing pass, or the animation.
    pub(in crate::app) fn cancel(&mut self) -> String {
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
    pub(in crate::app) fn step_sync(&mut self, n: usize) -> Result<usize, EditorError> {
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
        let history = |app: &App| {
            (app.document.doc.regions.is_none())
                .then(|| app.document.doc.mesher().map(|m| m.steps()))
                .flatten()
        };
        let h0 = history(self);
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
        // The steps undo can take back one by one: those the mesher's
        // history gained, as for a run in the background (a rewind or a run
        // made again with balanced fans replaces steps; steps the mesher no
        // longer has are dropped on undo).
        let gained = match (h0, history(self)) {
            (Some(a), Some(b)) => b.saturating_sub(a),
            _ => k,
        };
        self.document.history.steps(gained);
        if k > 0 {
            self.changed(true);
            if let (1, Some(b)) = (k, before) {
                self.view.before_last = Some((self.document.mesh_version, b));
            }
        }
        res
    }

    /// The mesher before the last step, when it is at hand.
    pub(in crate::app) fn cached_before_last(&mut self) -> Option<Framed> {
        match self.view.before_last.take() {
            Some((v, m)) if v == self.document.mesh_version => Some(m),
            _ => None,
        }
    }

    /// Starts a run in the background (a finishing pass going on is
    /// dropped: the run makes a new mesh).
    pub(in crate::app) fn start_run(
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

    /// Starts a run of a document of regions in the background (without
    /// threads: on this thread, at once).
    pub(in crate::app) fn start_region_run(&mut self, max: usize) -> Result<(), EditorError> {
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
}

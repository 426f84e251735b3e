//! Long runs off the UI thread: stepping to the end (or N steps) and the
//! finishing pass (cleanup and smoothing, `Mesher::finish`) run on a copy of
//! the mesher in a thread of their own, with a progress count the panel
//! shows and a Cancel that stops between steps. The steps taken before a
//! Cancel are kept.

use crate::extract::{Mesher, StepOutcome, StepReport};
use crate::mesh::QuadMesh;
use crate::pipeline::{self, FinishParams};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

/// What a finished job hands back.
pub struct JobDone {
    pub mesher: Mesher,
    /// The report of the last step taken, if any.
    pub last: Option<StepReport>,
    pub steps: usize,
    pub cancelled: bool,
    /// The step that failed.
    pub error: Option<String>,
    /// The finished mesh (when the run completed the mesh and was asked to
    /// finish it).
    pub finished: Option<Result<QuadMesh, String>>,
}

/// A run in the background.
pub struct Job {
    handle: Option<JoinHandle<JobDone>>,
    cancel: Arc<AtomicBool>,
    steps: Arc<AtomicUsize>,
    front: Arc<AtomicUsize>,
    /// What runs, for the progress line.
    pub what: &'static str,
    start_front: usize,
    started: std::time::Instant,
}

impl Job {
    /// Takes up to `max_steps` steps on `mesher`, then, if the mesh is
    /// complete and `finish` gives the cleanup and smoothing, finishes it.
    pub fn start(
        mut mesher: Mesher,
        max_steps: usize,
        finish: Option<FinishParams>,
        what: &'static str,
    ) -> Job {
        let cancel = Arc::new(AtomicBool::new(false));
        let steps = Arc::new(AtomicUsize::new(0));
        let start_front = mesher.front().len();
        let front = Arc::new(AtomicUsize::new(start_front));
        let (c, s, f) = (cancel.clone(), steps.clone(), front.clone());
        let handle = std::thread::spawn(move || {
            let (mut last, mut taken, mut cancelled, mut error) = (None, 0, false, None);
            while taken < max_steps && !mesher.is_done() {
                if c.load(Ordering::Relaxed) {
                    cancelled = true;
                    break;
                }
                match mesher.step() {
                    Ok(StepOutcome::Stepped(r)) => {
                        last = Some(*r);
                        taken += 1;
                        s.store(taken, Ordering::Relaxed);
                        f.store(mesher.front().len(), Ordering::Relaxed);
                    }
                    Ok(StepOutcome::Done) => break,
                    Err(e) => {
                        error = Some(e.to_string());
                        break;
                    }
                }
            }
            let finished = finish
                .filter(|_| mesher.is_done() && !cancelled)
                .map(|f| pipeline::finish(&mesher, &f).map_err(|e| e.to_string()));
            JobDone {
                mesher,
                last,
                steps: taken,
                cancelled,
                error,
                finished,
            }
        });
        Job {
            handle: Some(handle),
            cancel,
            steps,
            front,
            what,
            start_front,
            started: std::time::Instant::now(),
        }
    }

    /// Asks the run to stop after the step it is taking.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// Steps taken so far, front nodes left, and a rough fraction done
    /// (the front shrinks as the mesh fills; the finishing pass has none).
    pub fn progress(&self) -> (usize, usize, f32) {
        let steps = self.steps.load(Ordering::Relaxed);
        let front = self.front.load(Ordering::Relaxed);
        let frac = if self.start_front == 0 {
            0.0
        } else {
            1.0 - (front as f32 / self.start_front as f32).min(1.0)
        };
        (steps, front, frac)
    }

    /// Seconds since the start.
    pub fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// The result once the thread is done (`None` while it runs).
    pub fn poll(&mut self) -> Option<Result<JobDone, String>> {
        if !self.handle.as_ref()?.is_finished() {
            return None;
        }
        self.wait()
    }

    /// Blocks until the thread is done.
    pub fn wait(&mut self) -> Option<Result<JobDone, String>> {
        let h = self.handle.take()?;
        Some(
            h.join()
                .map_err(|_| "the background run failed".to_string()),
        )
    }
}

//! Long work off the UI thread: a run (to the end, or N steps, with
//! `Mesher::run_with`) and the finishing pass (cleanup, remeshing and
//! smoothing, `pipeline::finish`) on a copy of the mesher, in a thread of
//! their own, with a progress count the status bar shows.
//!
//! Cancel is immediate: the editor drops the job and keeps the document as
//! it was before the run; the thread is told to stop after the step it is
//! taking (a step, the fill of a large region in particular, is not
//! interrupted) and its result is thrown away.

use super::framed::Framed;
use crate::extract::StepReport;
use crate::mesh::QuadMesh;
use crate::pipeline::FinishParams;
use crate::pipeline::FinishPhase;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

/// What a job does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Work {
    /// Up to `max_steps` steps, then (when the mesh is complete and
    /// `finish` is given) the finishing pass.
    Run {
        max_steps: usize,
        finish: Option<FinishParams>,
    },
    /// The finishing pass only.
    Finish(FinishParams),
}

/// How the steps of a run go into the history.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Record {
    /// As steps, undone one by one.
    Steps,
    /// As part of the edit just made (a refit that meshes the rest: one
    /// undo takes back the refit and its steps).
    WithLastEdit,
}

/// What a finished job hands back.
pub struct JobDone {
    pub mesher: Framed,
    /// The report of the last step taken, if any.
    pub last: Option<StepReport>,
    pub steps: usize,
    /// The step that failed.
    pub error: Option<crate::extract::MeshError>,
    /// The finished mesh (when the mesh is complete and finishing was
    /// asked for).
    pub finished: Option<Result<QuadMesh, crate::extract::MeshError>>,
}

/// Work in the background.
pub struct Job {
    handle: Option<JoinHandle<JobDone>>,
    cancel: Arc<AtomicBool>,
    steps: Arc<AtomicUsize>,
    front: Arc<AtomicUsize>,
    /// The share of the domain meshed, as `f64` bits.
    meshed: Arc<AtomicU64>,
    /// The part of the work going on ([`Job::phase`]).
    phase: Arc<AtomicU8>,
    /// What runs, for the progress line.
    pub what: &'static str,
    pub work: Work,
    pub record: Record,
    /// The mesh version the job started from, and for finishing the
    /// parameters (what its result belongs to).
    pub key: super::FinishKey,
    started: std::time::Instant,
}

impl Job {
    /// Starts `work` on `mesher` in a thread.
    pub fn start(
        mut mesher: Framed,
        work: Work,
        what: &'static str,
        record: Record,
        key: super::FinishKey,
    ) -> Job {
        let cancel = Arc::new(AtomicBool::new(false));
        let steps = Arc::new(AtomicUsize::new(0));
        let front = Arc::new(AtomicUsize::new(mesher.front().len()));
        let meshed = Arc::new(AtomicU64::new(mesher.meshed_share().to_bits()));
        let phase = Arc::new(AtomicU8::new(0));
        let (c, s, f, a) = (cancel.clone(), steps.clone(), front.clone(), meshed.clone());
        let ph = phase.clone();
        let handle = std::thread::spawn(move || {
            let (mut last, mut taken, mut error) = (None, 0, None);
            let finish = match work {
                Work::Run { max_steps, finish } => {
                    if max_steps > 0 && !c.load(Ordering::Relaxed) {
                        let res = mesher.run_with(|r, at| {
                            taken += 1;
                            last = Some(r.clone());
                            s.store(taken, Ordering::Relaxed);
                            f.store(at.front, Ordering::Relaxed);
                            a.store(at.meshed.to_bits(), Ordering::Relaxed);
                            if taken >= max_steps || c.load(Ordering::Relaxed) {
                                ControlFlow::Break(())
                            } else {
                                ControlFlow::Continue(())
                            }
                        });
                        error = res.err();
                    }
                    finish
                }
                Work::Finish(p) => Some(p),
            };
            let finished = finish
                .filter(|_| mesher.is_done() && !c.load(Ordering::Relaxed))
                .map(|p| {
                    mesher.finish_phased(&p, |at| {
                        ph.store(phase_code(at), Ordering::Relaxed);
                    })
                });
            JobDone {
                mesher,
                last,
                steps: taken,
                error,
                finished,
            }
        });
        Job {
            handle: Some(handle),
            cancel,
            steps,
            front,
            meshed,
            phase,
            what,
            work,
            record,
            key,
            started: std::time::Instant::now(),
        }
    }

    /// True for a run (stepping), false for the finishing pass alone.
    pub fn is_run(&self) -> bool {
        matches!(self.work, Work::Run { .. })
    }

    /// Asks the thread to stop after the step it is taking, and gives back
    /// the thread to be joined later (its result is of no use any more).
    pub fn cancel(mut self) -> Option<JoinHandle<JobDone>> {
        self.cancel.store(true, Ordering::Relaxed);
        self.handle.take()
    }

    /// Steps taken so far, front nodes left, and the share of the
    /// domain's area meshed ([`Mesher::meshed_share`]; the finishing pass
    /// has none).
    pub fn progress(&self) -> (usize, usize, f32) {
        let steps = self.steps.load(Ordering::Relaxed);
        let front = self.front.load(Ordering::Relaxed);
        let meshed = f64::from_bits(self.meshed.load(Ordering::Relaxed));
        (steps, front, meshed as f32)
    }

    /// The part of the work going on: `None` while extraction steps,
    /// else the part of finishing the mesh.
    pub fn phase(&self) -> Option<FinishPhase> {
        PHASES
            .get(usize::from(self.phase.load(Ordering::Relaxed)).wrapping_sub(1))
            .copied()
    }

    /// What the job does now, for the progress line: "extraction" or the
    /// part of finishing the mesh.
    pub fn phase_name(&self) -> &'static str {
        self.phase().map_or("extraction", FinishPhase::name)
    }

    /// Seconds since the start.
    pub fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// True when the thread is done.
    pub fn is_finished(&self) -> bool {
        self.handle.as_ref().is_none_or(|h| h.is_finished())
    }

    /// Blocks until the thread is done and takes its result (`None` when
    /// it panicked).
    pub fn wait(&mut self) -> Option<JobDone> {
        self.handle.take()?.join().ok()
    }
}

/// The parts of finishing, by their code in [`Job::phase`] less one.
const PHASES: [FinishPhase; 5] = [
    FinishPhase::Cleanup,
    FinishPhase::Coarsening,
    FinishPhase::Remeshing,
    FinishPhase::Smoothing,
    FinishPhase::Checking,
];

/// `p`'s code in [`Job::phase`] (0 is extraction).
fn phase_code(p: FinishPhase) -> u8 {
    PHASES
        .iter()
        .position(|&q| q == p)
        .map_or(0, |k| k as u8 + 1)
}

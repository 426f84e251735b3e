//! The progress watch (method §2.5): a run that goes round in circles
//! (elements cut and ripped up again, rows that grow the front where they
//! should close it) is noticed, and the region left is filled.

use super::session::Mesher;

/// The progress watch's state.
#[derive(Clone, Debug, Default)]
pub(super) struct ProgressWatch {
    /// One checkpoint per [`WatchTuning::every`](super::tuning::WatchTuning::every) steps: (step, area still
    /// open, [`ProgressWatch::asked`] then, front nodes then).
    checkpoints: Vec<(usize, f64, f64, usize)>,
    /// The area the size field asks of the quads made so far: the sum of
    /// h² at the centre of every quad extraction has made (the watch's
    /// second measure).
    asked: f64,
    /// Quads that closed a needle ([`Mesher::needle_kite`]) and their
    /// area: the watch leaves them out of its mean (a fan of long needles
    /// would make every later quad look like no progress).
    needle_quads: (usize, f64),
}

impl ProgressWatch {
    /// A quad was made where the size field asks for `h`.
    pub(super) fn made(&mut self, h: f64) {
        self.asked += h.powi(2);
    }

    /// A quad of `area` closed a needle.
    pub(super) fn needle(&mut self, area: f64) {
        self.needle_quads.0 += 1;
        self.needle_quads.1 += area;
    }
}

impl Mesher {
    /// The progress watch ([`WatchTuning::every`](super::tuning::WatchTuning::every)): true when the last
    /// [`WatchTuning::window`](super::tuning::WatchTuning::window) steps ([`WatchTuning::end_window`](super::tuning::WatchTuning::end_window) once the area still open
    /// is less than that window is held to take off) made too little of
    /// the mesh and did not shrink the front by [`WatchTuning::front_shrink`](super::tuning::WatchTuning::front_shrink).
    pub(super) fn stalled(&mut self) -> bool {
        let n = self.record.history.len();
        if n == 0
            || n % self.params.tuning.watch.every != 0
            || self.watch.checkpoints.last().is_some_and(|p| p.0 == n)
        {
            return false;
        }
        let open = self.front.open_area(&self.mesh.nodes);
        self.watch
            .checkpoints
            .push((n, open, self.watch.asked, self.front.len()));
        let (needles, needle_area) = self.watch.needle_quads;
        let quads = self.mesh.quads.len().saturating_sub(needles);
        if quads == 0 {
            return false;
        }
        let mean = (self.domain_area - open - needle_area) / quads as f64;
        let window = if open
            < self.params.tuning.watch.rate * self.params.tuning.watch.end_window as f64 * mean
        {
            self.params.tuning.watch.end_window
        } else {
            self.params.tuning.watch.window
        };
        let Some(k) = n.checked_sub(window) else {
            return false;
        };
        let Some(&(_, before, asked_before, front_before)) =
            self.watch.checkpoints.iter().rev().find(|p| p.0 <= k)
        else {
            return false;
        };
        if (self.front.len() as f64)
            < (1.0 - self.params.tuning.watch.front_shrink) * front_before as f64
        {
            return false;
        }
        before - open < self.params.tuning.watch.rate * (self.watch.asked - asked_before)
            && before - open < self.params.tuning.watch.rate * window as f64 * mean
    }
}

//! The progress watch (method §2.5): a run that goes round in circles
//! (elements cut and ripped up again, rows that grow the front where they
//! should close it) is noticed, and the region left is filled.

use super::session::Mesher;

/// The progress watch: every [`PROGRESS_EVERY`] steps the area the front
/// still encloses is noted. A run whose last [`PROGRESS_WINDOW`] steps took
/// off less than [`PROGRESS_RATE`] of the mean area of its quads so far per
/// step is going round in circles (elements cut and ripped up again, rows
/// that grow the front where they should close it), and the region left is
/// filled. The window is long enough for the place where the rows of a
/// large disk meet: its rip-ups and relaxations take some 700 steps before
/// the front closes there by itself (disk1600 finishes by extraction alone;
/// with a window of 1,024 steps it was filled).
///
/// The mean of the quads so far is not what a graded domain's fine part
/// asks for: its quads can be a hundredth of the mean's size while the
/// rows there move on as they should. So a run is also held to the size
/// field: the window is no progress only if the area it took off is also
/// under [`PROGRESS_RATE`] of the area the size field asks of the quads it
/// made (h² at each one's centre, quads later ripped up included). Knots of
/// quads far finer than the field and rows cut and ripped up again fail
/// both.
pub(super) const PROGRESS_EVERY: usize = 128;
/// See [`PROGRESS_EVERY`].
pub(super) const PROGRESS_WINDOW: usize = 2048;
/// See [`PROGRESS_EVERY`].
pub(super) const PROGRESS_RATE: f64 = 0.25;
/// The progress watch's window in the end game, when the front encloses
/// less than one [`PROGRESS_WINDOW`] is held to take off: the last pockets
/// where rows met close one after another, each by rip-ups and
/// relaxations that give area back before the pocket closes, so a window
/// sees little progress however well the run goes (disk3200 and disk4800
/// close their last few hundred front nodes by extraction some 2,000
/// steps after a 2,048-step window calls them stalled).
pub(super) const END_WINDOW: usize = 4 * PROGRESS_WINDOW;
/// A window whose front lost at least this share of its nodes made
/// progress whatever the area: pockets are closing.
pub(super) const FRONT_SHRINK: f64 = 0.1;

/// The progress watch's state.
#[derive(Clone, Debug, Default)]
pub(super) struct ProgressWatch {
    /// One checkpoint per [`PROGRESS_EVERY`] steps: (step, area still
    /// open, [`ProgressWatch::asked`] then, front nodes then).
    pub(super) checkpoints: Vec<(usize, f64, f64, usize)>,
    /// The area the size field asks of the quads made so far: the sum of
    /// h² at the centre of every quad extraction has made (the watch's
    /// second measure).
    pub(super) asked: f64,
    /// Quads that closed a needle ([`Mesher::needle_kite`]) and their
    /// area: the watch leaves them out of its mean (a fan of long needles
    /// would make every later quad look like no progress).
    pub(super) needle_quads: (usize, f64),
}

impl Mesher {
    /// The progress watch ([`PROGRESS_EVERY`]): true when the last
    /// [`PROGRESS_WINDOW`] steps ([`END_WINDOW`] once the area still open
    /// is less than that window is held to take off) made too little of
    /// the mesh and did not shrink the front by [`FRONT_SHRINK`].
    pub(super) fn stalled(&mut self) -> bool {
        let n = self.record.history.len();
        if n == 0
            || n % PROGRESS_EVERY != 0
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
        let window = if open < PROGRESS_RATE * END_WINDOW as f64 * mean {
            END_WINDOW
        } else {
            PROGRESS_WINDOW
        };
        let Some(k) = n.checked_sub(window) else {
            return false;
        };
        let Some(&(_, before, asked_before, front_before)) =
            self.watch.checkpoints.iter().rev().find(|p| p.0 <= k)
        else {
            return false;
        };
        if (self.front.len() as f64) < (1.0 - FRONT_SHRINK) * front_before as f64 {
            return false;
        }
        before - open < PROGRESS_RATE * (self.watch.asked - asked_before)
            && before - open < PROGRESS_RATE * window as f64 * mean
    }
}

//! Calls into spade that cannot bring the mesher down. Spade's constrained
//! triangulation and its refinement can panic on nearly degenerate input
//! where they have no error to return (its refinement reported "Failed to
//! locate position. This is a bug in spade." on a region of seven 5° teeth
//! and a 1:25 slot, `tests/random_domains.rs`). Such a call is
//! run here: a panic becomes `None`, which the caller handles as the
//! failure of that attempt (the size field falls back to the median
//! segment, the region fill to its next try, the editor draws the domain
//! unshaded), and its message is kept off standard error, since nothing
//! failed for the user.
//!
//! Silencing works through the process's panic hook, wrapped once: while
//! a guarded call runs on a thread, a panic on that thread is not printed;
//! every other panic goes to the hook that was there before.

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;

thread_local! {
    /// Guarded calls running on this thread.
    static GUARDED: Cell<u32> = const { Cell::new(0) };
}

static WRAP_HOOK: Once = Once::new();

/// Runs `f`, giving `None` if it panics (the panic's message unprinted).
/// `f` must leave nothing it borrows half-changed that the caller uses
/// afterwards: whatever it was working on is dropped on failure.
pub(crate) fn guarded<R>(f: impl FnOnce() -> R) -> Option<R> {
    WRAP_HOOK.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if GUARDED.with(Cell::get) == 0 {
                previous(info);
            }
        }));
    });
    GUARDED.with(|g| g.set(g.get() + 1));
    let out = panic::catch_unwind(AssertUnwindSafe(f));
    GUARDED.with(|g| g.set(g.get() - 1));
    out.ok()
}

#[cfg(test)]
mod tests {
    use super::guarded;

    #[test]
    fn a_panic_becomes_none_and_a_result_passes_through() {
        assert_eq!(guarded(|| 7), Some(7));
        let failed: Option<u32> = guarded(|| panic!("deliberate"));
        assert_eq!(failed, None);
        // The guard is released: a later call still passes its value on.
        assert_eq!(guarded(|| "after"), Some("after"));
    }
}

//! Element extraction (method §2; thesis §2.1.2, §5.1): the [`Mesher`] cuts
//! one quad at a time off the front. Each step picks a reference point P0
//! (strategy A or B, sharp corners first), normalises its leading points,
//! asks the model for `[type, Pn]`, and commits the element if the guard
//! accepts it; otherwise it tries the remedies in order: a snapped Pn, the
//! other types, a corrected Pn, the next reference point, and finally a
//! rule-based element. Loops of 4 and 6 nodes are closed with the final
//! patterns, and narrow loops that are logical rectangles by a mapped grid
//! ([`mapped`]); a loop that no element can reduce is split along a chord into
//! two even loops. Once the reference points left lie on layer
//! [`MeshParams::fill_after_layers`] or deeper, when nothing reduces the
//! front any more, or when the step budget is spent, the region left is
//! filled by [`fill`].
//!
//! The same step API drives the command line, the tests and the editor.

mod band;
mod bridge;
mod candidate;
mod closure;
mod fan;
mod fill;
mod fill_step;
mod guard;
mod ladder;
mod mapped;
mod memo;
mod model_path;
mod notch;
mod params;
mod queue;
mod repair;
mod report;
mod session;
pub mod size;
mod transition;
pub mod tuning;
mod watch;

pub use candidate::CandidateReport;
pub use guard::Limits;
pub use ladder::{Rung, LADDER};
pub use params::{MeshParams, Strategy};
pub use report::{
    Action, CheckedElement, Correction, MeshError, Remedy, RunProgress, StepKind, StepOutcome,
    StepReport, StepStats, RESCALED_BEYOND,
};
pub use session::{Mesher, CHECKPOINT_BEHIND};
pub use tuning::Tuning;

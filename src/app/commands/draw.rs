//! The boundary edited: drawn, moved, resampled (a draft, valid or not),
//! or cut again at a target size.

use crate::app::error::EditorError;
use crate::app::text::plural;
use crate::app::App;
use crate::boundary_edit::Draft;

impl App {
    /// Cuts the boundary again at target size `h`.
    pub(in crate::app) fn set_size(&mut self, h: f64) -> Result<String, EditorError> {
        self.edit("size", |d| {
            d.set_size(h)?;
            let nodes = match &d.regions {
                Some(r) => r.graph.points.len(),
                None => d.draft.node_count(),
            };
            Ok(format!(
                "cut at size {h}: {}; mesh restarted",
                plural(nodes, "boundary node")
            ))
        })
    }

    /// The boundary as edited on the canvas.
    pub(in crate::app) fn set_draft(
        &mut self,
        draft: Draft,
        what: &'static str,
    ) -> Result<String, EditorError> {
        self.edit(what, |d| {
            d.set_draft(draft)?;
            Ok(match &d.problem {
                None => "boundary changed; mesh restarted".to_string(),
                Some(crate::boundary::BoundaryError::Empty) => String::new(),
                Some(e) => format!("not a valid boundary yet: {e}"),
            })
        })
    }
}

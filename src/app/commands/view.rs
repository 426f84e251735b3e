//! The view and the window: fit the view, zoom to the last step, ask for
//! a file, quit.

use crate::app::command::Dialog;
use crate::app::error::EditorError;
use crate::app::App;
use crate::geom::{Aabb, Point};

/// The share of the canvas the last step spans after View ▸ Zoom to the
/// last step.
const ZOOM_TO_STEP_SHARE: f64 = 0.4;

impl App {
    /// Fits the boundary into the canvas on the next frame.
    pub(in crate::app) fn fit_view(&mut self) -> Result<String, EditorError> {
        self.view.canvas.fit_pending = true;
        Ok(String::new())
    }

    /// Centres and zooms the canvas on the last step.
    pub(in crate::app) fn zoom_to_step(&mut self) -> Result<String, EditorError> {
        let doc = &self.document.doc;
        let (Some(r), Some(m)) = (doc.last(), doc.mesher()) else {
            return Err(EditorError::NoStep);
        };
        let mesh = m.mesh();
        let pts: Vec<Point> = r
            .leading
            .iter()
            .chain(r.reference.iter())
            .chain(r.quads.iter().flatten())
            .filter_map(|&v| mesh.nodes.get(v as usize).copied())
            .collect();
        let b = Aabb::of(pts.iter().copied()).ok_or(EditorError::NoStep)?;
        let rect = self.view.canvas_rect;
        self.view
            .canvas
            .zoom_to(rect, b.min, b.max, ZOOM_TO_STEP_SHARE);
        Ok(format!(
            "zoomed to step {} (F fits the view again)",
            r.index + 1
        ))
    }

    /// Asks for a file, then acts on it.
    pub(in crate::app) fn ask_file(&mut self, d: Dialog) -> Result<String, EditorError> {
        self.dialog(d);
        Ok(String::new())
    }

    /// Closes the window (asks first when there is unsaved work).
    pub(in crate::app) fn quit(&mut self) -> Result<String, EditorError> {
        // Closing asks first when there is unsaved work.
        self.window.close_now = true;
        Ok(String::new())
    }
}

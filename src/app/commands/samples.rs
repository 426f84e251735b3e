//! The training set: samples imported, exported, deleted and collected.

use crate::app::error::EditorError;
use crate::app::text::plural;
use crate::app::App;
use std::path::PathBuf;

impl App {
    /// Appends the samples of a training-set file.
    pub(in crate::app) fn import_samples(&mut self, p: PathBuf) -> Result<String, EditorError> {
        self.edit("import samples", |d| {
            d.import_samples(&p)
                .map(|n| format!("imported {} from {}", plural(n, "sample"), p.display()))
        })
    }

    /// Writes the user's samples.
    pub(in crate::app) fn export_samples(&mut self, p: PathBuf) -> Result<String, EditorError> {
        self.document.doc.export_samples(&p)?;
        Ok(format!(
            "wrote {} to {}",
            plural(self.document.doc.training.len(), "sample"),
            p.display()
        ))
    }

    /// Drops the user's samples at these positions.
    pub(in crate::app) fn delete_samples(
        &mut self,
        idx: Vec<usize>,
    ) -> Result<String, EditorError> {
        self.edit("delete samples", |d| {
            Ok(format!("{} left", plural(d.delete_samples(&idx), "sample")))
        })
    }

    /// Collects samples from the finished mesh on the canvas.
    pub(in crate::app) fn collect_from_mesh(&mut self) -> Result<String, EditorError> {
        let mesh = self.finished_mesh()?;
        let quads = mesh.quads.len();
        let name = self.document.doc.name.clone();
        self.edit("collect samples", |d| {
            d.collect_samples(&name, mesh).map(|n| {
                let [lo, hi] = crate::reference::DEFAULT_MODEL_TURN;
                format!(
                    "{} collected from the mesh's {} (about {} a quad: each corner of a good quad is P0 for each of the three element types, once for every way the front continues along mesh edges beyond l1 and r1 turning within {lo} to {hi} degrees, as for the shipped model: `quadex samples --turn {lo},{hi}`)",
                    plural(n, "sample"),
                    plural(quads, "quad"),
                    (n as f64 / quads.max(1) as f64).round()
                )
            })
        })
    }

    /// Collects samples from a quad mesh file.
    pub(in crate::app) fn collect_from_file(&mut self, p: PathBuf) -> Result<String, EditorError> {
        self.edit("collect samples", |d| {
            d.collect_from_file(&p)
                .map(|n| format!("{} collected from {}", plural(n, "sample"), p.display()))
        })
    }
}

//! The Compare panel: the boundary meshed with several models in the
//! background.

use crate::app::compare_panel::{CompareJob, Comparison};
use crate::app::error::EditorError;
use crate::app::text::plural;
use crate::app::{document, App};

impl App {
    /// Stops the comparison after the model it is meshing.
    pub(in crate::app) fn stop_compare(&mut self) -> Result<String, EditorError> {
        Ok(match &self.background.compare {
            Some(j) => {
                j.cancel();
                "the comparison stops after the model it is meshing".into()
            }
            None => String::new(),
        })
    }

    /// Starts meshing the boundary with each of the models `names` (the
    /// Compare panel), with the document's extraction and finishing
    /// settings; without threads it is done at once.
    pub(in crate::app) fn start_compare(
        &mut self,
        names: &[String],
    ) -> Result<String, EditorError> {
        let doc = &self.document.doc;
        let boundary = doc.boundary().ok_or_else(|| self.no_boundary())?.clone();
        let models = names
            .iter()
            .map(|n| document::load_model(n, &doc.models).map(|(m, _)| (n.clone(), m)))
            .collect::<Result<Vec<_>, _>>()?;
        let params = crate::pipeline::Params {
            extract: doc.settings.params(),
            finish: doc.settings.finishing(),
        };
        let job = CompareJob::start(boundary, models, params);
        if let Some(old) = self.background.compare.replace(job) {
            old.cancel();
        }
        if !self.background.threads {
            self.compare_done();
            return Ok(self.window.status.clone());
        }
        Ok(format!("comparing {}…", plural(names.len(), "model")))
    }

    /// Takes the comparison's outcomes when its thread is done.
    pub(in crate::app) fn compare_done(&mut self) {
        if let Some(mut j) = self.background.compare.take() {
            if let Some(outcomes) = j.wait() {
                let finished = outcomes.iter().filter(|o| o.finished).count();
                self.window.status = format!(
                    "compared {}: {finished} finished (the Compare panel)",
                    plural(outcomes.len(), "model")
                );
                self.background.comparison = Some(Comparison {
                    boundary: j.boundary.clone(),
                    outcomes,
                });
            }
        }
    }

    /// True while a comparison of models is being made.
    pub fn comparing(&self) -> bool {
        self.background.compare.is_some()
    }

    /// The last comparison of models made (the Compare panel).
    pub fn comparison(&self) -> Option<&Comparison> {
        self.background.comparison.as_ref()
    }
}

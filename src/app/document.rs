//! The editor's document: the boundary, the mesher stepping over it with
//! the chosen model and settings, the last step's report, and the training
//! set the user's corrections go to. Everything here goes through the
//! core's public API (`Mesher`, `model::load`, `io`).

use crate::extract::{Correction, MeshParams, Mesher, StepKind, StepOutcome, StepReport, Strategy};
use crate::fit::{self, Figures, FitParams, TypeFigures};
use crate::io;
use crate::mesh::QuadMesh;
use crate::model;
use crate::model::Form;
use crate::samples::CollectParams;
use crate::samples::TrainingSet;
use crate::Boundary;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What the user chose to mesh with.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Settings {
    /// `default`, `rules`, `thesis` or a model file.
    pub model: String,
    pub strategy: Strategy,
    /// Input points: 5, 7, 9 or 11.
    pub points: usize,
    pub pure_model: bool,
    /// See [`MeshParams::fill_after_layers`].
    pub fill_after_layers: Option<u32>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            model: "default".into(),
            strategy: Strategy::B,
            points: 7,
            pure_model: false,
            fill_after_layers: MeshParams::DEFAULT.fill_after_layers,
        }
    }
}

impl Settings {
    fn params(&self) -> MeshParams {
        MeshParams {
            strategy: self.strategy,
            leading_points: (self.points - 1) / 2,
            pure_model: self.pure_model,
            fill_after_layers: self.fill_after_layers,
            ..MeshParams::DEFAULT
        }
    }
}

/// The boundary being meshed and the state of its mesh.
pub struct Document {
    pub boundary: Boundary,
    /// The file the boundary came from.
    pub source: Option<PathBuf>,
    pub settings: Settings,
    pub mesher: Mesher,
    /// The report of the last step taken (cleared by undo and reset).
    pub last: Option<StepReport>,
    /// Samples from accepted and corrected elements.
    pub training: TrainingSet,
    /// The reference meshes' samples a refit starts from (loaded at the
    /// first refit).
    base: Option<TrainingSet>,
}

/// Figures of the model before and after a refit, on the same samples.
#[derive(Clone, Debug, PartialEq)]
pub struct RefitFigures {
    pub samples: usize,
    pub corrections: usize,
    pub before: (TypeFigures, Figures, Figures),
    pub after: (TypeFigures, Figures, Figures),
}

impl Document {
    /// A fresh document over `boundary`; fails when the model cannot be
    /// loaded.
    pub fn new(
        boundary: Boundary,
        source: Option<PathBuf>,
        settings: Settings,
    ) -> Result<Document, String> {
        let mesher = Self::mesher(&boundary, &settings)?;
        Ok(Document {
            boundary,
            source,
            training: TrainingSet::new(settings.points),
            settings,
            mesher,
            last: None,
            base: None,
        })
    }

    fn mesher(boundary: &Boundary, settings: &Settings) -> Result<Mesher, String> {
        let m = model::load(&settings.model).map_err(|e| format!("{}: {e}", settings.model))?;
        Ok(Mesher::new(
            boundary.clone(),
            Arc::from(m),
            settings.params(),
        ))
    }

    /// Opens a boundary file (`.poly`, `.json`); the message names the file
    /// and the problem.
    pub fn open(path: &Path, settings: Settings) -> Result<Document, String> {
        let b = io::read_boundary(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Document::new(b, Some(path.to_path_buf()), settings)
    }

    /// The document's name for the title bar.
    pub fn name(&self) -> String {
        self.source
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_else(|| "untitled".into())
    }

    /// One step; `Ok(false)` when the mesh is already complete.
    pub fn step(&mut self) -> Result<bool, String> {
        match self.mesher.step().map_err(|e| e.to_string())? {
            StepOutcome::Stepped(r) => {
                self.last = Some(*r);
                Ok(true)
            }
            StepOutcome::Done => Ok(false),
        }
    }

    /// Up to `n` steps; returns how many were taken.
    pub fn step_n(&mut self, n: usize) -> Result<usize, String> {
        for k in 0..n {
            if !self.step()? {
                return Ok(k);
            }
        }
        Ok(n)
    }

    /// Steps until the front is empty.
    pub fn run_to_end(&mut self) -> Result<usize, String> {
        let mut k = 0;
        while self.step()? {
            k += 1;
        }
        Ok(k)
    }

    pub fn undo(&mut self) -> bool {
        self.last = None;
        self.mesher.undo()
    }

    /// Starts the mesh again with the current settings.
    pub fn reset(&mut self) -> Result<(), String> {
        self.mesher = Self::mesher(&self.boundary, &self.settings)?;
        self.last = None;
        Ok(())
    }

    /// Changes the settings and starts again; on failure nothing changes.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), String> {
        let mesher = Self::mesher(&self.boundary, &settings)?;
        self.settings = settings;
        self.mesher = mesher;
        self.last = None;
        Ok(())
    }

    /// Appends the sample of the last step (an element the user accepts).
    pub fn append_last(&mut self) -> Result<usize, String> {
        let r = self.last.as_ref().ok_or("no step to take a sample from")?;
        let s = self
            .mesher
            .sample_of(r)
            .ok_or("the last step is not an element")?;
        self.push_sample(s)
    }

    fn push_sample(&mut self, s: crate::samples::Sample) -> Result<usize, String> {
        if self.training.points != 2 * s.n() + 1 {
            self.training = TrainingSet::new(2 * s.n() + 1);
        }
        self.training.push(s).map_err(|e| e.to_string())?;
        Ok(self.training.len())
    }

    /// Replaces the last element by the user's: the step is undone, the
    /// correction committed at the same reference point, and its sample
    /// appended. If the correction is not a valid element, nothing changes.
    pub fn correct_last(
        &mut self,
        element_type: crate::model::ElementType,
        pn: crate::geom::Point,
    ) -> Result<usize, String> {
        let r = self.last.clone().ok_or("no step to correct")?;
        if !matches!(r.kind, StepKind::Element | StepKind::Correction) {
            return Err("only an element step can be corrected".into());
        }
        let reference = r.reference.ok_or("the last step has no reference point")?;
        let c = Correction {
            reference,
            element_type,
            pn: Some(pn),
            snap_to: None,
        };
        let saved = self.mesher.clone();
        self.mesher.undo();
        match self.mesher.correct(&c) {
            Ok(report) => {
                let sample = self.mesher.sample_of(&report);
                self.last = Some(report);
                match sample {
                    Some(s) => self.push_sample(s),
                    None => Ok(self.training.len()),
                }
            }
            Err(e) => {
                // Leave the mesh as it was.
                self.mesher = saved;
                Err(e.to_string())
            }
        }
    }

    /// The reference meshes' samples at the current input points (the
    /// method's defaults), loaded once.
    fn base_set(&mut self) -> Result<&TrainingSet, String> {
        let points = self.training.points;
        if self.base.as_ref().is_none_or(|b| b.points != points) {
            let meshes = crate::reference::read_shipped().map_err(|e| e.to_string())?;
            self.base = Some(TrainingSet::collect(
                &meshes,
                points,
                &CollectParams::DEFAULT,
            ));
        }
        self.base
            .as_ref()
            .ok_or_else(|| "no reference samples".into())
    }

    /// Refits a model of `form` on the reference samples plus the user's,
    /// meshes the rest of the mesh with it, and returns the figures of the
    /// old and the new model on those samples.
    pub fn refit(&mut self, form: Form) -> Result<RefitFigures, String> {
        let corrections = self.training.clone();
        let mut set = self.base_set()?.clone();
        set.merge(corrections.clone()).map_err(|e| e.to_string())?;
        let params = FitParams {
            folds: 0,
            ..FitParams::DEFAULT
        };
        let before =
            fit::evaluate(self.mesher.model().as_ref(), &set).map_err(|e| e.to_string())?;
        let model = fit::refit(&set, form, &params).map_err(|e| e.to_string())?;
        let after = fit::evaluate(&model, &set).map_err(|e| e.to_string())?;
        self.mesher.set_model(Arc::new(model));
        Ok(RefitFigures {
            samples: set.len(),
            corrections: corrections.len(),
            before,
            after,
        })
    }

    pub fn is_done(&self) -> bool {
        self.mesher.is_done()
    }

    /// The finished mesh (smoothed and checked), for export.
    pub fn finished(&self) -> Result<QuadMesh, String> {
        if !self.is_done() {
            return Err("the mesh is not finished: run to the end first".into());
        }
        self.mesher.finish().map_err(|e| e.to_string())
    }

    /// Writes the finished mesh; the format follows the extension.
    pub fn export(&self, path: &Path) -> Result<(), String> {
        let fmt =
            io::MeshFormat::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mesh = self.finished()?;
        io::write_atomic(path, fmt.render(&mesh).as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))
    }
}

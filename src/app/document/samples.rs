//! The user's training samples: the last element appended, samples
//! imported, exported, deleted and collected from meshes.

use super::open::file_name;
use super::{kind_name, Document};
use crate::app::error::AtPath;
use crate::app::error::EditorError;
use crate::io;
use crate::mesh::QuadMesh;
use crate::samples::{Sample, TrainingSet};
use std::path::Path;

/// The training-set edits (the Training set panel and the Correct tool).
impl Document {
    /// Appends the sample of the last step (an element the user accepts).
    pub fn append_last(&mut self) -> Result<usize, EditorError> {
        let r = self.last().ok_or(EditorError::NoStep)?;
        if self.last_element().is_none() {
            return Err(EditorError::NotAnElement(kind_name(r.kind)));
        }
        let m = self.mesher().ok_or(EditorError::NoStep)?;
        let s = m.sample_of(r).ok_or(EditorError::NotAnElement("step"))?;
        // The same input and element (whatever its source) would weigh
        // twice in a refit and tell it nothing new.
        if let Some(i) = self.training.position_of(&s) {
            return Err(EditorError::AlreadySampled(i + 1));
        }
        self.push_sample(s)
    }

    /// The number (from 1) of the training sample the last element's
    /// sample already is, if it is one: a correction keeps its sample at
    /// once, and appending it again would add nothing.
    pub fn last_sampled(&self) -> Option<usize> {
        let r = self.last_element()?;
        let s = self.mesher()?.sample_of(r)?;
        self.training.position_of(&s).map(|i| i + 1)
    }

    pub(super) fn push_sample(&mut self, s: Sample) -> Result<usize, EditorError> {
        if self.training.points != 2 * s.n() + 1 && self.training.is_empty() {
            self.training = TrainingSet::new(2 * s.n() + 1);
        }
        self.training.push(s)?;
        Ok(self.training.len())
    }

    /// Drops the user's samples at `indices` (positions in the set);
    /// returns how many are left.
    pub fn delete_samples(&mut self, indices: &[usize]) -> usize {
        let drop: std::collections::BTreeSet<usize> = indices.iter().copied().collect();
        let mut k = 0;
        self.training.samples.retain(|_| {
            k += 1;
            !drop.contains(&(k - 1))
        });
        self.training.len()
    }

    /// Appends the samples of a CSV or JSON training-set file (the input
    /// points must match the set's, unless the set is empty); returns how
    /// many were added.
    pub fn import_samples(&mut self, path: &Path) -> Result<usize, EditorError> {
        let set = TrainingSet::read(path).at(path)?;
        self.add_samples(set).at(path)
    }

    fn add_samples(&mut self, set: TrainingSet) -> Result<usize, crate::samples::SamplesError> {
        let n = set.len();
        if self.training.is_empty() {
            self.training = set;
        } else {
            self.training.merge(set)?;
        }
        Ok(n)
    }

    /// Writes the user's samples (CSV, or JSON for a `.json` path).
    pub fn export_samples(&self, path: &Path) -> Result<(), EditorError> {
        self.training.write(path).at(path)
    }

    /// Collects samples from a finished mesh (the current one, or a mesh
    /// file) at the set's input points and appends them; returns how many.
    pub fn collect_samples(&mut self, name: &str, mesh: QuadMesh) -> Result<usize, EditorError> {
        // As the shipped model's samples are collected, so that a refit
        // with them is the self-training of `examples/self_training.rs`.
        let set = crate::reference::training_set(&[(name.to_string(), mesh)], self.training.points);
        Ok(self.add_samples(set)?)
    }

    /// Collects from a quad mesh file (`.msh`).
    pub fn collect_from_file(&mut self, path: &Path) -> Result<usize, EditorError> {
        let mesh = io::read_mesh(path).at(path)?;
        self.collect_samples(&file_name(path), mesh)
    }
}

//! # quadex
//!
//! All-quadrilateral 2D mesh generation by learned element extraction, after
//! the thesis "Regression Model based Automatic Finite Element Mesh
//! Generation": quads are cut off the boundary one at a time, a regression
//! model predicting each element from the normalised leading points of a
//! reference point.
//!
//! ```no_run
//! use std::sync::Arc;
//! use quadex::{io, pipeline::{mesh_boundary, Params}, model::RulesModel};
//! let boundary = io::read_boundary("square.poly".as_ref()).unwrap();
//! let (mesh, _stats) =
//!     mesh_boundary(&boundary, Arc::new(RulesModel::DEFAULT), &Params::DEFAULT, |_| {}).unwrap();
//! io::write_mesh(&mesh, "square.msh".as_ref()).unwrap();
//! ```
//!
//! Modules, one algorithm each: [`geom`] (predicates), [`boundary`]
//! (validation), [`front`] (the advancing front), [`normalize`] (thesis
//! §3.2), [`model`] (rules, the thesis preset, fitted models and their
//! files), [`extract`] (the step loop, guard, closure, fill), [`smooth`],
//! [`finish`] (cleanup, chord coarsening, remeshing), [`quality`], [`io`] (file
//! formats), [`samples`] (training samples, thesis Chapter 3), [`fit`]
//! (model fitting and fit figures, Chapter 4), [`factors`] (critical
//! factors, §4.2), [`predict`] (a model's answers
//! for rows of inputs), [`domains`] (seeded awkward test
//! domains), [`mapped`] (transfinite mapped meshing) and
//! [`reference`](mod@reference) (the meshes the shipped model learns from).
//! `app` is the desktop editor, the only module that uses egui (behind the
//! default cargo feature `gui`).

#[cfg(feature = "gui")]
pub mod app;
pub mod boundary;
pub mod boundary_edit;
pub mod cad;
pub mod compare;
pub mod domains;
pub mod extract;
pub mod factors;
pub mod finish;
pub mod fit;
pub mod front;
pub mod geom;
pub mod io;
pub mod mapped;
pub mod mesh;
pub mod model;
pub mod normalize;
pub mod order2;
pub mod pipeline;
pub mod predict;
pub mod pslg;
pub mod quality;
pub mod reference;
pub mod regions;
pub mod rng;
pub mod samples;
pub mod smooth;
mod spade_guard;

pub use boundary::{Boundary, BoundaryError};
pub use extract::{MeshError, MeshParams, Mesher, StepOutcome, StepReport, Strategy};
pub use geom::Point;
pub use mesh::QuadMesh;
pub use model::{ElementType, Model, Prediction};
pub use pipeline::{mesh_boundary, FinishParams, Params};
pub use quality::{MeshQuality, QuadQuality};

// The finishing steps under their former paths, for the command line and
// the editor until their imports name `finish`.
pub use finish::{cleanup, coarsen, remesh};

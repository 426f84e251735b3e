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
//! ## The public surface
//!
//! The items most programs need are re-exported here at the root:
//! [`Boundary`], [`Point`], [`QuadMesh`], the [`Mesher`] step API and its
//! parameters and reports, [`mesh_boundary`] with [`Params`] and
//! [`FinishParams`], the [`Model`] trait and [`ElementType`], and the
//! quality figures [`MeshQuality`] and [`QuadQuality`].
//!
//! The public namespaces, one subject each, in layers (each uses only those
//! above it):
//!
//! - geometry: [`geom`] (predicates, angles), [`rng`] (the seeded
//!   generator), [`boundary`] (validation), [`boundary_edit`] (the
//!   editor's boundary drafts), [`pslg`] (graphs of several regions);
//! - mesh: [`mesh`], [`quality`], [`smooth`], [`order2`] (9-node quads),
//!   [`io`] (file formats);
//! - the advancing front and the models: [`front`], [`normalize`] (thesis
//!   §3.2), [`model`] (rules, the thesis preset, fitted models, their
//!   files and the training sample they carry);
//! - [`extract`]: element extraction, the [`Mesher`] step API, its step
//!   ladder ([`extract::Rung`]) and its constants ([`extract::Tuning`]);
//!   inside it only `size` (the size field) and `tuning` are public;
//! - [`finish`]: cleanup, chord coarsening, remeshing of bad regions;
//!   [`pipeline`]: extraction then finishing; [`regions`]: several faces
//!   meshed and merged; [`compare`]: one boundary by several models;
//!   [`cad`]: drawings (DXF, JSON geometry) joined into graphs at a size
//!   field;
//! - the learning side: [`samples`] (training sets, thesis Chapter 3),
//!   [`fit`] (fitting and fit figures, Chapter 4), [`factors`] (critical
//!   factors, §4.2), [`predict`] (a model's answers for rows of inputs),
//!   [`reference`](mod@reference) (the meshes the shipped model learns
//!   from);
//! - `app`: the desktop editor, the only module that uses egui (behind the
//!   default cargo feature `gui`).
//!
//! Private: `mapped` (transfinite mapped meshing of four-sided blocks, for
//! the reference meshes, and the Coons patch of extraction's mapped
//! closure), `spade_guard` (calls into spade that may panic) and `domains`
//! (the seeded generator of awkward test domains the reference meshes and
//! the tests use), which the cargo feature `domains` (not default) makes
//! public as `quadex::domains`.

#[cfg(feature = "gui")]
pub mod app;
pub mod boundary;
pub mod boundary_edit;
pub mod cad;
pub mod compare;
#[cfg(feature = "domains")]
pub mod domains;
#[cfg(not(feature = "domains"))]
#[allow(dead_code)] // most of it serves the tests, through the feature
mod domains;
pub mod extract;
pub mod factors;
pub mod finish;
pub mod fit;
pub mod front;
pub mod geom;
pub mod io;
mod mapped;
pub mod mesh;
pub mod model;
pub mod normalize;
pub mod order2;
pub mod pipeline;
pub mod predict;
pub mod pslg;
#[cfg(feature = "python")]
pub mod python;
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

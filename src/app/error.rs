//! The editor's errors: what went wrong with a file, a step, a correction
//! or a refit, said in one line for the status bar. Causes are part of the
//! message (fields named `cause`, not `source`), as in the rest of the
//! crate: printing an error with its chain must not repeat them.

use crate::boundary::BoundaryError;
use crate::extract::MeshError;
use crate::fit::FitError;
use crate::io::{ReadError, WriteError};
use crate::mesh::InvariantError;
use crate::model::LoadError;
use crate::reference::ReferenceError;
use crate::samples::SamplesError;
use std::path::PathBuf;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum EditorError {
    /// A boundary, mesh or project file that cannot be read.
    #[error("{}: {cause}", path.display())]
    Read { path: PathBuf, cause: ReadError },
    /// A file that cannot be written (the message names it).
    #[error("{cause}")]
    Write { cause: WriteError },
    /// A project file that cannot be opened.
    #[error("{}: {cause}", path.display())]
    Project { path: PathBuf, cause: ProjectError },
    /// A training-set file, or samples that do not fit the set.
    #[error("{}{cause}", path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
    Samples {
        path: Option<PathBuf>,
        cause: SamplesError,
    },
    /// A model that cannot be loaded.
    #[error("{spec}: {cause}")]
    Model { spec: String, cause: LoadError },
    #[error("{0}")]
    Mesh(MeshError),
    /// A click or drag that does not give a valid element.
    #[error(
        "the element is not valid there (node {node}); the nodes marked green give valid elements"
    )]
    InvalidCorrection { node: u32 },
    #[error("{0}")]
    Fit(FitError),
    #[error("the reference meshes: {0}")]
    Reference(ReferenceError),
    /// A mesh file whose boundary is not a valid boundary.
    #[error("{}: its boundary: {cause}", path.display())]
    MeshBoundary { path: PathBuf, cause: BoundaryError },
    /// A mesh file that is not a valid mesh.
    #[error("{}: {cause}", path.display())]
    MeshFile {
        path: PathBuf,
        cause: InvariantError,
    },
    /// Stepping needs a valid boundary.
    #[error("no boundary to mesh yet: {0}")]
    NoBoundary(BoundaryError),
    #[error("no step to correct: take a step first")]
    NoStep,
    #[error("the last step is a {0}, not an element: only an element can be corrected or kept as a sample")]
    NotAnElement(&'static str),
    /// "Append as sample" on an element whose sample the set holds (a
    /// corrected element keeps its sample when it is made).
    #[error("the last element is in the training set already (sample {0})")]
    AlreadySampled(usize),
    #[error("the mesh is not finished: run it to the end first")]
    NotFinished,
    #[error("a run is going: wait for it or cancel it (Esc)")]
    Busy,
    #[error("unknown panel `{0}` (model, samples, quality or smoothing)")]
    UnknownPanel(String),
    #[error("unknown example `{0}`")]
    UnknownExample(String),
    #[error("the background run stopped unexpectedly")]
    JobPanicked,
    /// A refit made in the background failed (its error, as text).
    #[error("the refit failed: {0}")]
    Refit(String),
    #[error("{}: cannot save the screenshot: {cause}", path.display())]
    Screenshot {
        path: PathBuf,
        cause: ScreenshotError,
    },
    /// The window could not be opened or ran into an error.
    #[error("the window: {cause} (the editor needs a display; `quadex --help` lists the command line, which does not)")]
    Window { cause: eframe::Error },
    /// A document part that could not be put into JSON.
    #[error("{}: cannot write it as JSON: {cause}", path.display())]
    Encode {
        path: PathBuf,
        cause: serde_json::Error,
    },
    #[error(
        "the model meshed with is not a refitted one: refit first (or choose a refitted model)"
    )]
    NoRefittedModel,
    /// Meshing a face of a document of several regions failed.
    #[error("{0}")]
    Regions(crate::regions::RegionError),
    /// A graph of regions that cannot be meshed as it is.
    #[error("no regions to mesh yet: {0}")]
    NoGraph(crate::pslg::PslgError),
    /// A region or group edit that cannot be made.
    #[error("{0}")]
    RegionEdit(String),
    /// A drawing that cannot be read or cut into boundary nodes.
    #[error("{}{cause}", path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
    Drawing {
        path: Option<PathBuf>,
        cause: crate::cad::CadError,
    },
    /// A size the document cannot take.
    #[error("{0}")]
    Size(String),
}

impl From<crate::regions::RegionError> for EditorError {
    fn from(e: crate::regions::RegionError) -> Self {
        EditorError::Regions(e)
    }
}

/// Why a screenshot is not saved.
#[derive(Debug, Error)]
pub enum ScreenshotError {
    /// The pixels the window gave do not fill an image of its size.
    #[error("{bytes} bytes of pixels for a {width} × {height} image")]
    Buffer {
        width: usize,
        height: usize,
        bytes: usize,
    },
    #[error("{0}")]
    Png(image::ImageError),
}

/// Why a project file does not open.
#[derive(Debug, Error)]
pub enum ProjectError {
    #[error("cannot read the file: {0}")]
    Io(std::io::Error),
    /// Not JSON, or not a project's fields (the parser's message, any
    /// quoted text of the file cut short).
    #[error("invalid JSON: {}", crate::io::quote_long(&.0.to_string()))]
    Json(serde_json::Error),
    #[error("not a quadex project (format \"{0}\")")]
    Format(String),
    #[error("its boundary: {0}")]
    Boundary(BoundaryError),
    #[error("its regions: {0}")]
    Regions(ReadError),
    #[error("step {step} does not replay: {cause}")]
    Replay { step: usize, cause: MeshError },
    #[error("the project's mesh differs from its replayed steps")]
    MeshDiffers,
    #[error("its imported mesh: {0}")]
    Imported(InvariantError),
    #[error("its model: {0}")]
    Model(LoadError),
    /// Its boundary is valid but meshing it cannot start.
    #[error("its mesh cannot start: {0}")]
    Start(Box<EditorError>),
}

impl From<MeshError> for EditorError {
    fn from(e: MeshError) -> Self {
        match e {
            MeshError::InvalidCorrection { node } => EditorError::InvalidCorrection { node },
            e => EditorError::Mesh(e),
        }
    }
}

impl From<FitError> for EditorError {
    fn from(e: FitError) -> Self {
        EditorError::Fit(e)
    }
}

impl From<WriteError> for EditorError {
    fn from(cause: WriteError) -> Self {
        EditorError::Write { cause }
    }
}

impl From<ReferenceError> for EditorError {
    fn from(e: ReferenceError) -> Self {
        EditorError::Reference(e)
    }
}

impl From<SamplesError> for EditorError {
    fn from(cause: SamplesError) -> Self {
        EditorError::Samples { path: None, cause }
    }
}

/// Attaches a path to errors of reading files.
pub trait AtPath<T> {
    fn at(self, path: &std::path::Path) -> Result<T, EditorError>;
}

impl<T> AtPath<T> for Result<T, ReadError> {
    fn at(self, path: &std::path::Path) -> Result<T, EditorError> {
        self.map_err(|cause| EditorError::Read {
            path: path.to_path_buf(),
            cause,
        })
    }
}

impl<T> AtPath<T> for Result<T, SamplesError> {
    fn at(self, path: &std::path::Path) -> Result<T, EditorError> {
        self.map_err(|cause| EditorError::Samples {
            path: Some(path.to_path_buf()),
            cause,
        })
    }
}

impl<T> AtPath<T> for Result<T, ProjectError> {
    fn at(self, path: &std::path::Path) -> Result<T, EditorError> {
        self.map_err(|cause| EditorError::Project {
            path: path.to_path_buf(),
            cause,
        })
    }
}

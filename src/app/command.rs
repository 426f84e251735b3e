//! Every intent of the user as data: menus, shortcuts, buttons and canvas
//! gestures all make a [`Command`] and the app applies it in one place
//! ([`super::App::apply`]).

use super::document::Settings;
use crate::boundary_edit::Draft;
use crate::geom::Point;
use crate::model::{ElementType, Form};
use egui::{Key, KeyboardShortcut, Modifiers};
use std::path::PathBuf;

#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// One extraction step.
    Step,
    /// Up to this many steps.
    StepN(usize),
    /// Step until the mesh is complete.
    RunToEnd,
    /// Undo the last edit or step.
    Undo,
    /// Take the last undone edit or step again.
    Redo,
    /// Start the mesh again.
    Reset,
    /// Fit the boundary into the canvas.
    FitView,
    /// Centre and zoom the canvas on the last step.
    ZoomToStep,
    /// An empty document to draw a boundary in.
    New,
    /// Open a boundary, project or mesh file (asks first when the
    /// document holds unsaved work).
    Open(PathBuf),
    /// Open a shipped example (built into the binary).
    OpenExample(&'static str),
    /// Save the project (to the file it came from, else ask where).
    Save,
    /// Save the project to this file.
    SaveProject(PathBuf),
    /// Save the boundary (`.poly`, or `.json` for any draft).
    SaveBoundary(PathBuf),
    /// Export the finished mesh (format from the extension).
    Export(PathBuf),
    /// Ask for a file, then act on it.
    Dialog(Dialog),
    /// New model / strategy / points / pure-model settings (restarts), or
    /// new finishing settings (the steps stay).
    SetSettings(Settings),
    /// Mesh with the fitted model in this file (restarts).
    UseModel(PathBuf),
    /// Append the last step's element to the training set as it is.
    AppendLast,
    /// Replace the last element by this one and append its sample.
    CorrectLast {
        element_type: ElementType,
        /// Pn in world coordinates (types 1 and 2 take P_r2 / P_l2).
        pn: Point,
        /// Type 0 closed onto this front node instead of a new one.
        snap_to: Option<u32>,
    },
    /// Refit the model on the reference samples and the user's; with
    /// `mesh_rest`, mesh the rest with it (one undo takes both back).
    Refit { form: Form, mesh_rest: bool },
    /// Save the refitted model meshed with now as a model file.
    SaveModel(PathBuf),
    /// Step on their own at the animation speed, or stop.
    Animate(bool),
    /// Stop the background run; the document stays as before it.
    Cancel,
    /// Close the window (asks first when there is unsaved work).
    Quit,
    /// Compute the finished mesh (after its pass was cancelled or failed).
    Finish,
    /// Append the samples of a training-set file (CSV or JSON).
    ImportSamples(PathBuf),
    /// Write the user's samples (CSV, or JSON by extension).
    ExportSamples(PathBuf),
    /// Drop the user's samples at these positions.
    DeleteSamples(Vec<usize>),
    /// Collect samples from the finished mesh on the canvas.
    CollectFromMesh,
    /// Collect samples from a quad mesh file (`.msh`).
    CollectFromFile(PathBuf),
    /// Mesh the boundary from the start with each of these models (names as
    /// in the model list) in the background, for the Compare panel.
    Compare(Vec<String>),
    /// Stop the comparison after the model it is meshing.
    StopCompare,
    /// The boundary as edited on the canvas (valid or not: an invalid
    /// draft shows its problem and has no mesh until it is fixed).
    SetDraft { draft: Draft, what: &'static str },
    /// Cut the boundary again at this target size: a drawing's curves, or
    /// every loop of a boundary of nodes resampled.
    SetSize(f64),
    /// Turn a document of one valid boundary into a document of regions
    /// (one region, no groups yet) to split and name.
    ToRegions,
    /// A document of regions: a curve from node `from` through `through`
    /// to node `to` becomes an interface (new nodes and segments).
    SplitRegion {
        from: usize,
        through: Vec<Point>,
        to: usize,
    },
    /// A document of regions: these segments form the group `name` (tag
    /// 0: the group's own, or a new one; an empty name ungroups them).
    NameGroup {
        segments: Vec<usize>,
        name: String,
        tag: i64,
    },
    /// A document of regions: the face holding `at` is in region `name`
    /// (tag 0: the region's own, or a new one).
    NameRegion { at: Point, name: String, tag: i64 },
}

/// What a file prompt is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialog {
    Open,
    SaveProjectAs,
    SaveBoundaryAs,
    ExportMesh,
    ImportSamples,
    ExportSamples,
    CollectFromFile,
    /// A fitted model file to mesh with.
    ModelFile,
    /// Where to save the refitted model.
    SaveModel,
}

impl Command {
    /// The keyboard shortcut shown beside the command, if it has one.
    pub fn shortcut(&self) -> Option<KeyboardShortcut> {
        let k = KeyboardShortcut::new;
        match self {
            Command::Step => Some(k(Modifiers::NONE, Key::Space)),
            Command::StepN(_) => Some(k(Modifiers::SHIFT, Key::Space)),
            Command::RunToEnd => Some(k(Modifiers::COMMAND, Key::Enter)),
            Command::Undo => Some(k(Modifiers::COMMAND, Key::Z)),
            Command::Redo => Some(k(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::Z)),
            Command::New => Some(k(Modifiers::COMMAND, Key::N)),
            Command::Save => Some(k(Modifiers::COMMAND, Key::S)),
            Command::Dialog(Dialog::Open) => Some(k(Modifiers::COMMAND, Key::O)),
            Command::Dialog(Dialog::ExportMesh) => Some(k(Modifiers::COMMAND, Key::E)),
            Command::Animate(_) => Some(k(Modifiers::NONE, Key::P)),
            Command::Cancel => Some(k(Modifiers::NONE, Key::Escape)),
            Command::Quit => Some(k(Modifiers::COMMAND, Key::Q)),
            Command::Reset => Some(k(Modifiers::COMMAND, Key::R)),
            Command::FitView => Some(k(Modifiers::NONE, Key::F)),
            Command::ZoomToStep => Some(k(Modifiers::NONE, Key::Z)),
            _ => None,
        }
    }

    /// Other shortcuts that do the same (Ctrl+Y redoes, as on Windows).
    pub fn alternative_shortcut(&self) -> Option<KeyboardShortcut> {
        match self {
            Command::Redo => Some(KeyboardShortcut::new(Modifiers::COMMAND, Key::Y)),
            _ => None,
        }
    }

    /// True for the commands that replace the whole document (the editor
    /// asks first when it holds unsaved work).
    pub fn replaces_document(&self) -> bool {
        matches!(
            self,
            Command::New | Command::Open(_) | Command::OpenExample(_)
        )
    }

    /// True for what may be done while a run goes on in the background.
    pub fn allowed_while_running(&self) -> bool {
        matches!(
            self,
            Command::Cancel
                | Command::FitView
                | Command::ZoomToStep
                | Command::Quit
                | Command::StopCompare
        )
    }
}

//! Every intent of the user as data: menus, shortcuts and buttons all make
//! a [`Command`] and the app applies it in one place ([`super::App::apply`]).

use super::document::Settings;
use crate::geom::Point;
use crate::model::{ElementType, Form};
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
    /// Start the mesh again.
    Reset,
    /// Fit the boundary into the canvas.
    FitView,
    /// Open a boundary file.
    Open(PathBuf),
    /// Export the finished mesh (format from the extension).
    Export(PathBuf),
    /// New model / strategy / points / pure-model settings (restarts).
    SetSettings(Settings),
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
    /// Refit the model on the reference samples and the user's, and mesh
    /// the rest with it.
    Refit(Form),
    /// Take the last undone edit or step again.
    Redo,
    /// Step on their own at the animation speed, or stop.
    Animate(bool),
    /// Stop the run in the background (the steps taken so far stay).
    Cancel,
    /// Save the project (to the file it came from, else ask where).
    Save,
    /// Save the project to this file.
    SaveProject(PathBuf),
    /// Ask for a file with a dialog, then act on it.
    Dialog(Dialog),
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
    /// Mesh with the fitted model in this file (restarts).
    UseModel(PathBuf),
    /// Replace the boundary (an edit on the canvas); the mesh restarts.
    SetBoundary(Box<crate::Boundary>),
}

/// What a file dialog is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialog {
    Open,
    SaveProjectAs,
    ExportMesh,
    ImportSamples,
    ExportSamples,
    CollectFromFile,
    /// A fitted model file to mesh with.
    ModelFile,
}

impl Command {
    /// The keyboard shortcut shown beside the command, if it has one.
    pub fn shortcut(&self) -> Option<egui::KeyboardShortcut> {
        use egui::{Key, KeyboardShortcut, Modifiers};
        match self {
            Command::Step => Some(KeyboardShortcut::new(Modifiers::NONE, Key::Space)),
            Command::StepN(_) => Some(KeyboardShortcut::new(Modifiers::SHIFT, Key::Space)),
            Command::RunToEnd => Some(KeyboardShortcut::new(Modifiers::COMMAND, Key::Enter)),
            Command::Undo => Some(KeyboardShortcut::new(Modifiers::COMMAND, Key::Z)),
            Command::Redo => Some(KeyboardShortcut::new(
                Modifiers::COMMAND.plus(Modifiers::SHIFT),
                Key::Z,
            )),
            Command::Save => Some(KeyboardShortcut::new(Modifiers::COMMAND, Key::S)),
            Command::Dialog(Dialog::Open) => {
                Some(KeyboardShortcut::new(Modifiers::COMMAND, Key::O))
            }
            Command::Dialog(Dialog::ExportMesh) => {
                Some(KeyboardShortcut::new(Modifiers::COMMAND, Key::E))
            }
            Command::Animate(_) => Some(KeyboardShortcut::new(Modifiers::NONE, Key::P)),
            Command::Cancel => Some(KeyboardShortcut::new(Modifiers::NONE, Key::Escape)),
            Command::Reset => Some(KeyboardShortcut::new(Modifiers::COMMAND, Key::R)),
            Command::FitView => Some(KeyboardShortcut::new(Modifiers::NONE, Key::F)),
            _ => None,
        }
    }
}

//! Every intent of the user as data: menus, shortcuts and buttons all make
//! a [`Command`] and the app applies it in one place ([`super::App::apply`]).

use super::document::Settings;
use std::path::PathBuf;

#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// One extraction step.
    Step,
    /// Up to this many steps.
    StepN(usize),
    /// Step until the mesh is complete.
    RunToEnd,
    /// Undo the last step.
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
            Command::Reset => Some(KeyboardShortcut::new(Modifiers::COMMAND, Key::R)),
            Command::FitView => Some(KeyboardShortcut::new(Modifiers::NONE, Key::F)),
            _ => None,
        }
    }
}

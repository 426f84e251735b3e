//! What the editor remembers between runs ([`Prefs`]).

use super::document::{self, Settings};
use super::files::Recent;
use super::layout::{Tab, PANEL_MIN_WIDTHS, PANEL_WIDTHS};
use super::quality_panel::QualityPanel;
use super::step_panel::StepPanel;
use super::App;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// What the editor remembers between runs (eframe persistence), in one
/// struct: settings, recent files and the panels' choices, not the
/// document.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Prefs {
    pub settings: Settings,
    pub recent: Recent,
    pub step: StepPanel,
    pub quality: QualityPanel,
    pub tab: Tab,
    pub show_left: bool,
    pub show_right: bool,
    /// The widths the user gave the left and right panels.
    pub widths: [f32; 2],
    /// The folder of the last mesh exported (a document of no file
    /// proposes it).
    pub export_dir: Option<PathBuf>,
}

impl Default for Prefs {
    fn default() -> Self {
        Prefs {
            settings: Settings::default(),
            recent: Recent::default(),
            step: StepPanel::default(),
            quality: QualityPanel::default(),
            tab: Tab::default(),
            show_left: true,
            show_right: true,
            widths: PANEL_WIDTHS,
            export_dir: None,
        }
    }
}

impl App {
    /// The remembered state.
    pub fn prefs(&self) -> Prefs {
        Prefs {
            settings: self.document.doc.settings.clone(),
            recent: self.window.recent.clone(),
            step: self.panels.step.clone(),
            quality: self.panels.quality.clone(),
            tab: self.panels.tab,
            show_left: self.panels.show_left,
            show_right: self.panels.show_right,
            widths: self.panels.widths,
            export_dir: self.window.export_dir.clone(),
        }
    }

    /// Takes the remembered state (the settings are the document's own).
    pub fn set_prefs(&mut self, p: Prefs) {
        self.window.recent = p.recent;
        self.window.export_dir = p.export_dir;
        // (Lists remembered before the list kept only files Open reads.)
        self.window.recent.0.retain(|f| document::opens(f));
        self.panels.step = p.step;
        self.panels.quality = p.quality;
        self.panels.tab = p.tab;
        self.panels.show_left = p.show_left;
        self.panels.show_right = p.show_right;
        // Widths no panel may have (a hand-edited or damaged store) are
        // taken as the first ones.
        for k in 0..2 {
            let w = p.widths[k];
            self.panels.widths[k] = if w.is_finite() && w >= PANEL_MIN_WIDTHS[k] {
                w
            } else {
                PANEL_WIDTHS[k]
            };
        }
    }
}

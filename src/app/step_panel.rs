//! The stepping panel: model and settings, Step / Step ×N / Run to end /
//! Undo / Reset, and what the last step did (kind, type, the model's raw
//! prediction, the remedy the guard used).

use super::command::Command;
use super::document::{Document, Settings};
use crate::extract::{MeshParams, Strategy};
use crate::model::BUILTIN;
use egui::Ui;

/// The panel's own state: how many steps "Step ×N" takes and how fast the
/// animated run goes.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct StepPanel {
    pub n: usize,
    /// Steps per second of the animated run.
    pub speed: f64,
    /// Show the element the next step would cut.
    pub preview: bool,
}

impl Default for StepPanel {
    fn default() -> Self {
        StepPanel {
            n: 10,
            speed: 20.0,
            preview: true,
        }
    }
}

/// A button that shows its command's shortcut.
fn button(ui: &mut Ui, label: &str, cmd: Command, out: &mut Vec<Command>) {
    let text = match cmd.shortcut() {
        Some(s) => format!("{label}  ({})", ui.ctx().format_shortcut(&s)),
        None => label.to_string(),
    };
    if ui.button(text).clicked() {
        out.push(cmd);
    }
}

impl StepPanel {
    /// Draws the panel; the user's intents are pushed to `out`.
    pub fn ui(&mut self, ui: &mut Ui, doc: &Document, animating: bool, out: &mut Vec<Command>) {
        ui.heading("Extraction");
        let mut s: Settings = doc.settings.clone();
        ui.horizontal(|ui| {
            let shown = std::path::Path::new(&s.model)
                .file_name()
                .map_or(s.model.clone(), |f| f.to_string_lossy().into_owned());
            egui::ComboBox::from_label("model")
                .selected_text(shown)
                .show_ui(ui, |ui| {
                    for name in BUILTIN {
                        ui.selectable_value(&mut s.model, name.to_string(), name);
                    }
                });
            if ui
                .button("File…")
                .on_hover_text("Mesh with a fitted model file")
                .clicked()
            {
                out.push(Command::Dialog(super::command::Dialog::ModelFile));
            }
        });
        ui.horizontal(|ui| {
            ui.label("strategy");
            ui.selectable_value(&mut s.strategy, Strategy::A, "A");
            ui.selectable_value(&mut s.strategy, Strategy::B, "B");
        });
        ui.horizontal(|ui| {
            ui.label("input points");
            for p in [5, 7, 9, 11] {
                ui.selectable_value(&mut s.points, p, p.to_string());
            }
        });
        ui.checkbox(&mut s.pure_model, "pure model (no remedies)");
        ui.horizontal(|ui| {
            let mut on = s.fill_after_layers.is_some();
            ui.checkbox(&mut on, "fill inside layer").on_hover_text(
                "Extract this many layers from the boundary, then fill the region left directly",
            );
            let mut k = s
                .fill_after_layers
                .or(MeshParams::DEFAULT.fill_after_layers)
                .unwrap_or(1);
            ui.add_enabled(on, egui::DragValue::new(&mut k).range(1..=1000));
            s.fill_after_layers = on.then_some(k);
        });
        if s != doc.settings {
            out.push(Command::SetSettings(s));
        }
        ui.separator();
        ui.horizontal_wrapped(|ui| {
            button(ui, "Step", Command::Step, out);
            ui.add(
                egui::DragValue::new(&mut self.n)
                    .range(1..=100_000)
                    .prefix("×"),
            );
            button(ui, "Step ×N", Command::StepN(self.n), out);
        });
        ui.horizontal_wrapped(|ui| {
            let label = if animating { "Pause" } else { "Run" };
            button(ui, label, Command::Animate(!animating), out);
            ui.add(
                egui::Slider::new(&mut self.speed, 1.0..=2000.0)
                    .logarithmic(true)
                    .suffix(" steps/s"),
            );
        });
        ui.horizontal_wrapped(|ui| {
            button(ui, "Run to end", Command::RunToEnd, out);
            button(ui, "Reset", Command::Reset, out);
        });
        ui.checkbox(&mut self.preview, "show the next element (dashed)");
        ui.horizontal_wrapped(|ui| {
            button(ui, "Undo", Command::Undo, out);
            button(ui, "Redo", Command::Redo, out);
            button(ui, "Fit view", Command::FitView, out);
        });
        ui.separator();
        let m = doc.mesher.mesh();
        let stats = doc.mesher.stats();
        ui.label(format!(
            "steps {}   quads {}   front nodes {}",
            doc.mesher.steps(),
            m.quads.len(),
            doc.mesher.front().len()
        ));
        if doc.is_done() {
            ui.colored_label(egui::Color32::LIGHT_GREEN, "mesh complete");
        } else if let Some(m) = doc.imported() {
            ui.label(format!(
                "showing the mesh read from {} ({} quads); Step or Run meshes its boundary",
                doc.name(),
                m.quads.len()
            ));
        }
        if doc.settings.pure_model {
            let (ok, all) = stats.model_valid();
            ui.label(format!("model predictions valid: {ok} of {all}"));
        }
        ui.separator();
        ui.label(egui::RichText::new("Last step").strong());
        match &doc.last {
            None => {
                ui.label("none yet");
            }
            Some(r) => {
                egui::Grid::new("last_step").num_columns(2).show(ui, |ui| {
                    ui.label("kind");
                    ui.label(format!("{:?}", r.kind));
                    ui.end_row();
                    if let Some(v) = r.reference {
                        ui.label("reference P0");
                        ui.label(format!("node {v}"));
                        ui.end_row();
                    }
                    if let Some(p) = &r.prediction {
                        ui.label("model says");
                        ui.label(format!(
                            "type {}, Pn ({:.3}, {:.3})",
                            p.element_type.number(),
                            p.pn.x,
                            p.pn.y
                        ));
                        ui.end_row();
                    }
                    if let Some(t) = r.element_type {
                        ui.label("element");
                        ui.label(format!("type {}", t.number()));
                        ui.end_row();
                    }
                    ui.label("remedy");
                    ui.label(format!("{:?}", r.remedy));
                    ui.end_row();
                    if r.skipped > 0 {
                        ui.label("passed over");
                        ui.label(format!("{} reference points", r.skipped));
                        ui.end_row();
                    }
                });
            }
        }
    }
}

//! The stepping panel: model and settings, Step / Step ×N / Run / Run to
//! end / Undo / Redo / Reset, the counts of the mesh as stepped, and what
//! the last step did (kind, type, the model's raw prediction in its
//! normalised frame and in the world, the remedy the guard used).

use super::command::{Command, Dialog};
use super::document::{kind_name, Settings};
use super::{Document, RunState};
use crate::extract::{MeshParams, Remedy, StepKind, Strategy};
use crate::model::BUILTIN;
use egui::Ui;

/// The panel's own state: how many steps "Step ×N" takes and how fast the
/// animated run goes (remembered between runs).
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

/// A button that shows its command's shortcut, with a tooltip.
pub fn button(ui: &mut Ui, label: &str, tip: &str, cmd: Command, out: &mut Vec<Command>) {
    button_enabled(ui, true, label, tip, cmd, out);
}

/// [`button`], greyed out unless `enabled`.
pub fn button_enabled(
    ui: &mut Ui,
    enabled: bool,
    label: &str,
    tip: &str,
    cmd: Command,
    out: &mut Vec<Command>,
) {
    let text = match cmd.shortcut() {
        Some(s) => format!("{label}  ({})", ui.ctx().format_shortcut(&s)),
        None => label.to_string(),
    };
    if ui
        .add_enabled(enabled, egui::Button::new(text))
        .on_hover_text(tip)
        .clicked()
    {
        out.push(cmd);
    }
}

/// One row of the last-step table: the name in a column of its own, the
/// value wrapped in what is left of the panel's width (a table that sizes
/// its columns from the last frame would widen the panel when a new row
/// appears). Returns the name's response (for a tooltip).
fn row(ui: &mut Ui, name: &str, value: egui::RichText) -> egui::Response {
    ui.horizontal_top(|ui| {
        let w = (0.45 * ui.available_width()).min(140.0);
        let name = ui
            .allocate_ui_with_layout(
                egui::vec2(w, 0.0),
                egui::Layout::top_down(egui::Align::Min),
                |ui| {
                    ui.set_width(w);
                    ui.add(egui::Label::new(name).wrap())
                },
            )
            .inner;
        ui.add(egui::Label::new(value).wrap());
        name
    })
    .inner
}

/// What a remedy means, for the last-step table.
fn remedy_name(r: Remedy) -> &'static str {
    match r {
        Remedy::None => "none (the model's element as predicted)",
        Remedy::Rescaled => "the model's element, Pn drawn to the size field",
        Remedy::Snapped => "Pn snapped onto a front node",
        Remedy::OtherType => "another element type",
        Remedy::CorrectedPn => "Pn moved to the rule-based position",
        Remedy::RuleBased => "the rule-based element",
        Remedy::NotApplicable => "not a model step",
    }
}

impl super::View for StepPanel {
    type Input<'a> = RunState;

    fn ui(&mut self, ui: &mut Ui, doc: &Document, run: RunState) -> Vec<Command> {
        let mut out = Vec::new();
        ui.heading("Extraction");
        let mut s: Settings = doc.settings.clone();
        ui.horizontal_wrapped(|ui| {
            let shown = std::path::Path::new(&s.model)
                .file_name()
                .map_or(s.model.clone(), |f| f.to_string_lossy().into_owned());
            egui::ComboBox::from_label("model")
                .selected_text(shown)
                .show_ui(ui, |ui| {
                    for name in BUILTIN {
                        ui.selectable_value(&mut s.model, name.to_string(), name);
                    }
                    for f in &doc.models {
                        ui.selectable_value(&mut s.model, f.name.clone(), &f.name)
                            .on_hover_text("A model refitted in this document");
                    }
                })
                .response
                .on_hover_text("default: the shipped fitted model; rules: Zeng & Cheng's rules; thesis: Table 8 as printed; ann: the shipped back-propagation network (Yao & Zeng)");
            if ui
                .button("File…")
                .on_hover_text("Mesh with a fitted model file (written by `quadex fit`)")
                .clicked()
            {
                out.push(Command::Dialog(Dialog::ModelFile));
            }
        });
        let info = doc.model_info();
        ui.label(model_line(&info))
            .on_hover_text("The model meshed with now: its form, the samples its fit learned from and the corrections layered over it");
        ui.horizontal(|ui| {
            ui.label("strategy");
            ui.selectable_value(&mut s.strategy, Strategy::A, "A")
                .on_hover_text("A: the next reference point beside the last element");
            ui.selectable_value(&mut s.strategy, Strategy::B, "B")
                .on_hover_text("B: every reference point of a layer before the next layer");
        });
        ui.horizontal(|ui| {
            ui.label("input points");
            for p in [5, 7, 9, 11] {
                ui.selectable_value(&mut s.points, p, p.to_string())
                    .on_hover_text("Points the model sees: P0 and N leading points on each side");
            }
        });
        ui.checkbox(&mut s.pure_model, "pure model (no remedies)")
            .on_hover_text(
                "Take the model's element as predicted or reject it; the guard's remedies are off",
            );
        ui.horizontal(|ui| {
            let mut on = s.fill_after_layers.is_some();
            ui.checkbox(&mut on, "fill inside layer").on_hover_text(
                "Extract this many layers from the boundary, then fill the region left directly (off: extraction to the end)",
            );
            let mut k = s
                .fill_after_layers
                .or(MeshParams::DEFAULT.fill_after_layers)
                .unwrap_or(2);
            ui.add_enabled(on, egui::DragValue::new(&mut k).range(1..=1000))
                .on_hover_text("Layers extracted before the fill");
            s.fill_after_layers = on.then_some(k);
        });
        if s != doc.settings {
            out.push(Command::SetSettings(s));
        }
        ui.separator();
        // A run or refit in the background: stepping, undo and reset wait
        // for it (Cancel in the status bar, or Esc, stops it).
        let can_step = doc.can_step() && !doc.is_done() && !run.busy;
        button_enabled(
            ui,
            can_step,
            "Step",
            "Take one extraction step",
            Command::Step,
            &mut out,
        );
        // N beside the button it sets, and in its label.
        ui.horizontal_wrapped(|ui| {
            button_enabled(
                ui,
                can_step,
                &format!("Step ×{}", self.n),
                "Take N steps (over 200 in the background); N is set beside",
                Command::StepN(self.n),
                &mut out,
            );
            ui.add(
                egui::DragValue::new(&mut self.n)
                    .range(1..=100_000)
                    .prefix("N = "),
            )
            .on_hover_text("How many steps Step ×N takes (drag or type)");
        });
        ui.horizontal_wrapped(|ui| {
            let animating = run.animating;
            let label = if animating { "Pause" } else { "Run" };
            button_enabled(
                ui,
                can_step || (animating && !run.busy),
                label,
                "Step on their own at the speed beside; Pause keeps the steps taken",
                Command::Animate(!animating),
                &mut out,
            );
            // A slider narrow enough to stay beside the button in a
            // narrow panel (it does not wrap on its own).
            ui.spacing_mut().slider_width = 60.0;
            ui.add(
                egui::Slider::new(&mut self.speed, 1.0..=2000.0)
                    .logarithmic(true)
                    .suffix("/s"),
            )
            .on_hover_text("Speed of the animated run, in steps per second");
        });
        ui.horizontal_wrapped(|ui| {
            button_enabled(
                ui,
                can_step,
                "Run to end",
                "Step until the mesh is complete, in the background (Cancel drops the run)",
                Command::RunToEnd,
                &mut out,
            );
            button_enabled(
                ui,
                doc.can_step() && !run.busy,
                "Reset",
                "Start the mesh again (undo brings the steps back)",
                Command::Reset,
                &mut out,
            );
        });
        ui.checkbox(&mut self.preview, "show the next element")
            .on_hover_text("Draw the element the next step would cut, dashed in cyan");
        ui.horizontal_wrapped(|ui| {
            button_enabled(
                ui,
                run.can_undo && !run.busy,
                "Undo",
                "Undo the last step or edit",
                Command::Undo,
                &mut out,
            );
            button_enabled(
                ui,
                run.can_redo && !run.busy,
                "Redo",
                "Take the last undone step or edit again (also Ctrl+Y)",
                Command::Redo,
                &mut out,
            );
            button(
                ui,
                "Fit view",
                "Fit the boundary into the canvas",
                Command::FitView,
                &mut out,
            );
            button_enabled(
                ui,
                doc.last().is_some(),
                "Zoom to step",
                "Centre the canvas on the last step, zoomed so that its points and their labels show",
                Command::ZoomToStep,
                &mut out,
            );
        });
        ui.separator();
        if let Some(r) = &doc.regions {
            regions_status(ui, r);
            last_step(ui, doc);
            return out;
        }
        let Some(mesher) = doc.mesher() else {
            ui.label("No mesh: the boundary is not valid yet (see Boundary below).");
            return out;
        };
        let stats = mesher.stats();
        ui.label(format!(
            "{}, {} as stepped, {} left",
            super::plural(mesher.steps(), "step"),
            super::plural(mesher.mesh().quads.len(), "quad"),
            super::plural(mesher.front().len(), "front node"),
        ))
        .on_hover_text("The mesh as stepped; the Quality panel shows the finished mesh (cleaned up and smoothed) once the run is complete");
        if doc.is_done() {
            ui.colored_label(egui::Color32::LIGHT_GREEN, "mesh complete");
        } else if let Some(m) = doc.imported() {
            ui.label(format!(
                "showing the mesh read from {} ({}); Step or Run meshes its boundary",
                doc.name,
                super::plural(m.quads.len(), "quad")
            ));
        }
        if stats.count(StepKind::Fill) > 0 {
            ui.colored_label(
                egui::Color32::from_rgb(230, 180, 60),
                format!(
                    "the region fill (not extraction) made {}",
                    super::plural(stats.quads_made(StepKind::Fill), "quad")
                ),
            )
            .on_hover_text("Extraction could not reduce the front any further; the region left was meshed by a split triangulation, as the last resort");
        }
        if stats.refanned {
            ui.label("made again with balanced corner fans: no fill")
                .on_hover_text("The run reached the region fill with fans whose quads are squarest; it was made again from the start with fans whose outer sides are alike, and that run finished by extraction (docs/engine.md, Corner fans)");
        }
        if doc.settings.pure_model {
            let (ok, all) = stats.model_valid();
            ui.label(format!("model predictions valid: {ok} of {all}"));
        }
        ui.separator();
        last_step(ui, doc);
        out
    }
}

/// Where the meshing of a document of regions stands: the region and
/// face being meshed, the counts.
fn regions_status(ui: &mut Ui, r: &super::regions::Regions) {
    let Some(s) = &r.stepper else {
        ui.label("No mesh: the graph of regions is not valid yet (see Regions below).");
        return;
    };
    let n = s.faces().len();
    match &r.mesh {
        Some(m) => {
            ui.label(format!(
                "{} meshed: {}, {} in {}",
                super::plural(n, "face"),
                super::plural(r.steps, "step"),
                super::plural(m.mesh.quads.len(), "quad"),
                super::plural(m.regions.len(), "region"),
            ));
            ui.colored_label(egui::Color32::LIGHT_GREEN, "mesh complete");
        }
        None => {
            ui.label(
                egui::RichText::new(format!(
                    "region {}, face {} of {n}",
                    s.current_region(),
                    s.current() + 1
                ))
                .strong(),
            )
            .on_hover_text("The faces are meshed one by one, each with its boundary nodes fixed, so that the meshes of two faces meet node to node");
            ui.label(format!(
                "{}, {} as stepped, {} left in this face",
                super::plural(r.steps, "step"),
                super::plural(r.shown_mesh().quads.len(), "quad"),
                super::plural(r.front_left(), "front node"),
            ));
            ui.label(
                egui::RichText::new(
                    "Undo goes back within the face being meshed; Reset starts every face again.",
                )
                .weak(),
            );
        }
    }
}

/// The last step's table.
fn last_step(ui: &mut Ui, doc: &Document) {
    {
        ui.label(egui::RichText::new("Last step").strong());
        match doc.last() {
            None => {
                ui.label("none yet");
            }
            Some(r) => {
                let mono = |t: String| egui::RichText::new(t).monospace();
                let plain = egui::RichText::new;
                row(
                    ui,
                    "step",
                    plain(format!("{} ({})", r.index + 1, kind_name(r.kind))),
                );
                row(ui, "rung", plain(r.rung.name().to_string())).on_hover_text(
                    "The rung of the step ladder that took the step (docs/engine.md, Each step)",
                );
                if let Some(v) = r.reference {
                    row(ui, "reference P0", plain(format!("node {v}")));
                }
                if let Some(p) = &r.prediction {
                    row(
                        ui,
                        "model's type",
                        plain(p.element_type.number().to_string()),
                    );
                    row(
                        ui,
                        "model's Pn, normalised",
                        mono(format!("({:.3}, {:.3}) × |P0 r1|", p.pn.x, p.pn.y)),
                    )
                    .on_hover_text(
                        "In the frame of P0: P0 at the origin, r1 at (1, 0); unit |P0 r1|",
                    );
                }
                if let Some(w) = r.predicted_pn {
                    row(
                        ui,
                        "model's Pn, world",
                        mono(format!("({:.4}, {:.4})", w.x, w.y)),
                    );
                }
                if let Some(t) = r.element_type {
                    row(ui, "element", plain(format!("type {}", t.number())));
                }
                if r.kind == StepKind::Correction {
                    row(ui, "remedy", plain("yours, corrected by hand".to_string()));
                } else {
                    row(ui, "remedy", plain(remedy_name(r.remedy).to_string()));
                }
                if r.skipped > 0 {
                    row(
                        ui,
                        "passed over",
                        plain(super::plural(r.skipped, "reference point")),
                    );
                }
            }
        }
    }
}

/// The model meshed with, in one line: name, form, samples, corrections.
pub fn model_line(info: &super::document::ModelInfo) -> String {
    let mut parts = vec![info.form.clone()];
    if let Some(n) = info.samples {
        parts.push(super::plural(n, "sample"));
    }
    if info.corrections > 0 {
        parts.push(super::plural(info.corrections, "correction"));
    }
    format!("model {}: {}", info.name, parts.join(", "))
}

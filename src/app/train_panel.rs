//! Correction and retraining: replace the last element by the user's
//! (type and Pn), append the last element as it is, see how many samples
//! the training set holds, and refit in one click with the figures before
//! and after.

use super::command::Command;
use super::document::{Document, RefitFigures};
use crate::extract::StepKind;
use crate::geom::Point;
use crate::model::{ElementType, Form};
use egui::Ui;

/// The panel's own state: the correction being edited.
pub struct TrainPanel {
    pub element_type: ElementType,
    /// Pn of the correction (the canvas handle drags it).
    pub pn: Point,
    /// The step the correction fields were filled from.
    filled_from: Option<usize>,
    form: Form,
    /// Mesh the rest with the new model right after a refit.
    pub regenerate: bool,
}

impl Default for TrainPanel {
    fn default() -> Self {
        TrainPanel {
            element_type: ElementType::New,
            pn: Point::ZERO,
            filled_from: None,
            form: Form::Quadratic,
            regenerate: true,
        }
    }
}

impl TrainPanel {
    pub fn ui(
        &mut self,
        ui: &mut Ui,
        doc: &Document,
        refit: Option<&RefitFigures>,
        out: &mut Vec<Command>,
    ) {
        ui.heading("Correction and training");
        let element = doc
            .last
            .as_ref()
            .filter(|r| matches!(r.kind, StepKind::Element | StepKind::Correction));
        match element {
            None => {
                ui.label("Take a step to correct its element.");
            }
            Some(r) => {
                // Start from what was committed: the new node, or r2 / l2.
                if self.filled_from != Some(r.index) {
                    self.filled_from = Some(r.index);
                    self.element_type = r.element_type.unwrap_or(ElementType::New);
                    if let Some(v) = r.pn_node() {
                        self.pn = doc.mesher.mesh().nodes[v as usize];
                    }
                }
                ui.horizontal(|ui| {
                    ui.label("type");
                    for t in ElementType::ALL {
                        ui.selectable_value(&mut self.element_type, t, t.number().to_string());
                    }
                });
                ui.horizontal(|ui| {
                    ui.label("Pn");
                    let speed = 0.01 * pn_scale(doc);
                    ui.add(
                        egui::DragValue::new(&mut self.pn.x)
                            .speed(speed)
                            .prefix("x "),
                    );
                    ui.add(
                        egui::DragValue::new(&mut self.pn.y)
                            .speed(speed)
                            .prefix("y "),
                    );
                });
                ui.horizontal_wrapped(|ui| {
                    if ui.button("Correct element").clicked() {
                        out.push(Command::CorrectLast {
                            element_type: self.element_type,
                            pn: self.pn,
                            snap_to: None,
                        });
                    }
                    if ui.button("Append as sample").clicked() {
                        out.push(Command::AppendLast);
                    }
                });
            }
        }
        ui.label(format!(
            "training set: {} sample{} of yours",
            doc.training.len(),
            if doc.training.len() == 1 { "" } else { "s" }
        ));
        ui.checkbox(&mut self.regenerate, "mesh the rest after a refit");
        ui.horizontal(|ui| {
            for f in Form::ALL {
                ui.selectable_value(&mut self.form, f, f.name());
            }
            if ui.button("Refit").clicked() {
                out.push(Command::Refit(self.form));
                if self.regenerate {
                    out.push(Command::RunToEnd);
                }
            }
        });
        if let Some(f) = refit {
            ui.label(format!(
                "last refit: {} samples ({} of yours)",
                f.samples, f.corrections
            ));
            egui::Grid::new("refit").num_columns(3).show(ui, |ui| {
                ui.label("");
                ui.label("before");
                ui.label("after");
                ui.end_row();
                ui.label("type accuracy");
                ui.label(format!("{:.2} %", 100.0 * f.before.0.accuracy));
                ui.label(format!("{:.2} %", 100.0 * f.after.0.accuracy));
                ui.end_row();
                for (name, b, a) in [
                    ("Xn R", &f.before.1, &f.after.1),
                    ("Yn R", &f.before.2, &f.after.2),
                ] {
                    ui.label(name);
                    ui.label(format!("{:.4}", b.r));
                    ui.label(format!("{:.4}", a.r));
                    ui.end_row();
                }
            });
        }
    }
}

/// A drag speed for Pn: the boundary's size.
fn pn_scale(doc: &Document) -> f64 {
    crate::geom::Aabb::of(doc.boundary.points.iter().copied())
        .map(|b| (b.max - b.min).length())
        .unwrap_or(1.0)
}

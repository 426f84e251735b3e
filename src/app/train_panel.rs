//! Correction and retraining: replace the last element by the user's
//! (type and Pn), append the last element as it is, see how many samples
//! the training set holds, and refit in one click with the figures before
//! and after.

use super::command::{Command, Dialog};
use super::step_panel::button_enabled;
use super::{Document, Figures};
use crate::geom::Point;
use crate::model::{ElementType, Form};
use egui::Ui;

/// The panel's own state: the correction being edited.
pub struct TrainPanel {
    pub element_type: ElementType,
    /// Pn of the correction, in world coordinates.
    pub pn: Point,
    /// The mesh (by version) the correction fields were filled from: a
    /// step, a correction or an undo fills them again.
    filled_from: Option<u64>,
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

impl super::View for TrainPanel {
    type Input<'a> = Figures<'a>;

    fn ui(&mut self, ui: &mut Ui, doc: &Document, s: Figures<'_>) -> Vec<Command> {
        let mut out = Vec::new();
        ui.heading("Correction and training");
        match (doc.last_element(), doc.mesher()) {
            (Some(r), Some(m)) if s.kind == super::MeshKind::Stepped => {
                // Start from what was committed: the new node, or r2 / l2.
                let key = s.mesh_version;
                if self.filled_from != Some(key) {
                    self.filled_from = Some(key);
                    self.element_type = r.element_type.unwrap_or(ElementType::New);
                    if let Some(v) = r.pn_node() {
                        self.pn = m.mesh().nodes[v as usize];
                    }
                }
                ui.label(format!("the element of step {}", r.index + 1));
                ui.horizontal(|ui| {
                    ui.label("type");
                    for t in ElementType::ALL {
                        ui.selectable_value(&mut self.element_type, t, t.number().to_string())
                            .on_hover_text(match t {
                                ElementType::New => "type 0: a new node Pn",
                                ElementType::Right => "type 1: closes onto r2",
                                ElementType::Left => "type 2: closes onto l2",
                            });
                    }
                });
                ui.horizontal(|ui| {
                    ui.label("Pn (world)");
                    let speed = 0.002 * pn_scale(doc);
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
                    if ui
                        .button("Correct element")
                        .on_hover_text("Replace the last element by this type and Pn, and keep it as a training sample")
                        .clicked()
                    {
                        out.push(Command::CorrectLast {
                            element_type: self.element_type,
                            pn: self.pn,
                            snap_to: None,
                        });
                    }
                    match doc.last_sampled() {
                        Some(i) => {
                            ui.add_enabled(false, egui::Button::new("Append as sample"))
                                .on_disabled_hover_text(format!(
                                    "The last element is in the training set already (sample {i})"
                                ));
                            ui.weak(format!("kept as sample {i}"));
                        }
                        None => {
                            if ui
                                .button("Append as sample")
                                .on_hover_text("Keep the last element as it is as a training sample")
                                .clicked()
                            {
                                out.push(Command::AppendLast);
                            }
                        }
                    }
                });
            }
            _ => {
                ui.label("Take a step to correct its element (on the canvas: drag its Pn, or click a front node).");
            }
        }
        ui.label(format!(
            "training set: {} of yours",
            super::plural(doc.training.len(), "sample")
        ));
        ui.checkbox(&mut self.regenerate, "mesh the rest after a refit")
            .on_hover_text("Run to the end with the new model right after the refit (one undo takes both back)");
        ui.horizontal(|ui| {
            for f in Form::ALL {
                ui.selectable_value(&mut self.form, f, f.name())
                    .on_hover_text("The form of the model a refit fits");
            }
            button_enabled(
                ui,
                doc.meshing.is_some() && !s.busy,
                "Refit",
                "Fit the model on the reference meshes' samples and yours, and mesh with it",
                Command::Refit {
                    form: self.form,
                    mesh_rest: self.regenerate,
                },
                &mut out,
            );
        });
        if doc.model_file(&doc.model_info().name).is_some() {
            button_enabled(
                ui,
                true,
                "Save model…",
                "Save the refitted model as a model file (`quadex mesh --model FILE` reads it)",
                Command::Dialog(Dialog::SaveModel),
                &mut out,
            );
        }
        if let Some(f) = doc.last_refit.as_ref() {
            ui.label(format!(
                "last refit: {}: {} fitted, {} of yours layered over them",
                f.model,
                super::plural(f.samples, "sample"),
                super::plural(f.corrections, "correction")
            ));
            if f.repeated > 0 {
                ui.colored_label(
                    ui.visuals().warn_fg_color,
                    format!(
                        "{} of yours repeated samples already in the set: the fit dropped them",
                        super::plural(f.repeated, "sample")
                    ),
                );
            }
            refit_outcome(ui, f);
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
                    ui.label(super::figure(b.r, 4));
                    ui.label(super::figure(a.r, 4));
                    ui.end_row();
                }
            });
        }
        out
    }
}

/// A drag speed for Pn: the boundary's size.
fn pn_scale(doc: &super::Document) -> f64 {
    doc.boundary()
        .map(|b| b.bbox().size().length())
        .unwrap_or(1.0)
}

/// What a refit did to the corrections and to the mesh of the boundary.
fn refit_outcome(ui: &mut Ui, f: &super::RefitFigures) {
    if !f.checks.is_empty() {
        let kept = f.checks.iter().filter(|c| c.reproduced()).count();
        ui.label(format!(
            "corrections reproduced: {kept} of {}",
            f.checks.len()
        ))
        .on_hover_text("The refitted model's element at each correction's input: the corrected type, and Pn within 0.05 (normalised)");
        corrections_grid(ui, f);
    }
    if let Some((before, after)) = &f.meshed {
        ui.label("meshed from the start, before and now:");
        if after.size_quads > 0.0 {
            ui.label(format!(
                "(the size field asks for about {} quads)",
                crate::compare::grouped(after.size_quads.round() as usize)
            ));
        }
        super::sideways_table(ui, "refit meshed scroll", |ui| {
            meshed_grid(ui, before, after)
        });
        if let Some((changed, calls)) = f.memory_reach {
            ui.label(format!(
                "the corrections changed {} of {} predictions ({:.1} %)",
                crate::compare::grouped(changed),
                crate::compare::grouped(calls),
                100.0 * changed as f64 / calls.max(1) as f64
            ))
            .on_hover_text(format!(
                "Meshing the boundary from the start with the refitted model: the predictions where the corrections' memory gave another element than the fit alone; more than {:.0} % counts as reaching too far",
                100.0 * super::document::WORSE_MEMORY_SHARE
            ));
        }
        if f.worse.is_empty() {
            ui.label("the refitted model meshes this boundary no worse")
                .on_hover_text("Judged by finishing, the region fill, scaled Jacobian, irregular nodes, the quad count against the size field, taper, aspect and the corrections' reach");
        } else {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                format!(
                    "the refitted model meshes this boundary worse: {}",
                    f.worse.join(", ")
                ),
            );
        }
    }
}

/// A figure of a mesh made from the start, as the refit report shows it.
type Figure = fn(&crate::compare::Outcome) -> String;

/// The boundary meshed from the start with the model before the refit and
/// the refitted one, figure by figure.
fn meshed_grid(ui: &mut Ui, before: &crate::compare::Outcome, after: &crate::compare::Outcome) {
    use crate::compare::grouped;
    egui::Grid::new("refit meshed")
        .num_columns(3)
        .striped(true)
        .show(ui, |ui| {
            ui.label("");
            ui.label("model before");
            ui.label("refitted");
            ui.end_row();
            let rows: [(&str, Figure); 7] = [
                ("quads", |o| grouped(o.quads)),
                ("of the size field's", |o| {
                    format!("{:.0} %", 100.0 * o.quads as f64 / o.size_quads.max(1.0))
                }),
                ("SJ min / mean", |o| {
                    format!("{:.3} / {:.3}", o.sj_min, o.sj_mean)
                }),
                ("irregular nodes", |o| {
                    format!(
                        "{} ({:.1} %)",
                        grouped(o.irregular),
                        100.0 * o.irregular_share
                    )
                }),
                ("max taper", |o| format!("{:.1}", o.taper_max)),
                ("max aspect", |o| format!("{:.1}", o.aspect_max)),
                ("region fill", |o| if o.fill { "yes" } else { "no" }.into()),
            ];
            for (name, value) in rows {
                ui.label(name);
                for o in [before, after] {
                    if o.finished {
                        ui.label(value(o));
                    } else {
                        ui.label("does not finish");
                    }
                }
                ui.end_row();
            }
        });
}

/// The refitted model's element at each correction, before and now: a
/// block of rows per correction, two columns, so that the model now is in
/// view in a narrow panel too.
fn corrections_grid(ui: &mut Ui, f: &super::RefitFigures) {
    let pred = |p: &crate::model::Prediction| {
        format!("{} ({:.3}, {:.3})", p.element_type.number(), p.pn.x, p.pn.y)
    };
    egui::Grid::new("corrections")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            for c in &f.checks {
                ui.strong(format!("sample {}", c.sample + 1));
                ui.label(if c.reproduced() {
                    "reproduced"
                } else {
                    "not reproduced"
                });
                ui.end_row();
                ui.label("corrected");
                ui.label(pred(&c.corrected));
                ui.end_row();
                ui.label("model before");
                ui.label(pred(&c.before));
                ui.end_row();
                ui.label("model now");
                ui.label(pred(&c.after));
                ui.end_row();
            }
        });
}

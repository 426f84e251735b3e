//! The Compare panel: the document's boundary meshed from the start by
//! several models side by side (thesis Figure 44), with the figures of
//! `quadex compare` ([`crate::compare`]: finished, quads, scaled Jacobian
//! minimum and mean, irregular share, and the element steps accepted as
//! predicted, rescaled to the size field or replaced) and a small picture
//! of each mesh. The meshing runs in a thread ([`CompareJob`]); the panel
//! only asks for it ([`Command::Compare`]).

use super::canvas::quality_color;
use super::command::Command;
use super::Document;
use crate::compare::{self, Outcome};
use crate::geom::Aabb;
use crate::mesh::QuadMesh;
use crate::model::{Model, BUILTIN};
use crate::pipeline::Params;
use crate::quality::QuadQuality;
use crate::Boundary;
use egui::{Color32, Pos2, Sense, Stroke, Ui};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

/// A comparison made: the boundary it meshed and one outcome per model.
pub struct Comparison {
    pub boundary: Boundary,
    pub outcomes: Vec<Outcome>,
}

/// A comparison being made in a thread, one model after the other.
pub struct CompareJob {
    handle: Option<JoinHandle<Vec<Outcome>>>,
    done: Arc<AtomicUsize>,
    cancel: Arc<AtomicBool>,
    pub total: usize,
    pub boundary: Boundary,
}

impl CompareJob {
    /// Meshes `boundary` with each of `models` ([`compare::mesh_with`]) in
    /// a thread.
    pub fn start(
        boundary: Boundary,
        models: Vec<(String, Arc<dyn Model>)>,
        params: Params,
    ) -> CompareJob {
        let done = Arc::new(AtomicUsize::new(0));
        let cancel = Arc::new(AtomicBool::new(false));
        let total = models.len();
        let (d, c, b) = (done.clone(), cancel.clone(), boundary.clone());
        let handle = std::thread::spawn(move || {
            let mut out = Vec::with_capacity(models.len());
            for (name, m) in models {
                if c.load(Ordering::Relaxed) {
                    break;
                }
                out.push(compare::mesh_with(&name, &b, m, &params));
                d.fetch_add(1, Ordering::Relaxed);
            }
            out
        });
        CompareJob {
            handle: Some(handle),
            done,
            cancel,
            total,
            boundary,
        }
    }

    /// Models meshed so far.
    pub fn done(&self) -> usize {
        self.done.load(Ordering::Relaxed)
    }

    /// True when the thread is done.
    pub fn is_finished(&self) -> bool {
        self.handle.as_ref().is_none_or(|h| h.is_finished())
    }

    /// Blocks until the thread is done and takes its outcomes (`None` when
    /// it panicked).
    pub fn wait(&mut self) -> Option<Vec<Outcome>> {
        self.handle.take()?.join().ok()
    }

    /// Tells the thread to stop after the model it is meshing.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// The panel's own state: the models ticked.
#[derive(Clone, Debug, PartialEq)]
pub struct ComparePanel {
    pub chosen: Vec<String>,
    /// The models the list has offered: one new to it (a refit) comes
    /// ticked, to be compared with the others.
    offered: Vec<String>,
}

impl Default for ComparePanel {
    fn default() -> Self {
        let builtin: Vec<String> = BUILTIN.iter().map(|s| s.to_string()).collect();
        ComparePanel {
            chosen: builtin.clone(),
            offered: builtin,
        }
    }
}

/// Side of a mesh picture, in points.
const PICTURE: f32 = 150.0;

/// What the Compare panel shows besides the document.
#[derive(Clone, Copy, Default)]
pub struct CompareState<'a> {
    /// The last comparison made.
    pub comparison: Option<&'a Comparison>,
    /// A comparison running: models meshed so far, and all.
    pub comparing: Option<(usize, usize)>,
}

impl super::View for ComparePanel {
    type Input<'a> = CompareState<'a>;

    fn ui(&mut self, ui: &mut Ui, doc: &Document, scene: CompareState<'_>) -> Vec<Command> {
        let mut out = Vec::new();
        ui.label("The boundary meshed from the start by each model ticked, with the editor's extraction and finishing settings (as quadex compare).");
        let names: Vec<String> = BUILTIN
            .iter()
            .map(|s| s.to_string())
            .chain(doc.models.iter().map(|f| f.name.clone()))
            .collect();
        self.chosen.retain(|c| names.contains(c));
        self.offered.retain(|c| names.contains(c));
        for name in &names {
            if !self.offered.contains(name) {
                self.offered.push(name.clone());
                self.chosen.push(name.clone());
            }
        }
        ui.horizontal_wrapped(|ui| {
            for name in &names {
                let mut on = self.chosen.contains(name);
                if ui.checkbox(&mut on, name.as_str()).changed() {
                    if on {
                        self.chosen.push(name.clone());
                    } else {
                        self.chosen.retain(|c| c != name);
                    }
                }
            }
        });
        // In the order of the list, whatever the order of ticking.
        let chosen: Vec<String> = names
            .iter()
            .filter(|n| self.chosen.contains(n))
            .cloned()
            .collect();
        ui.horizontal(|ui| {
            // Why the button is off, the first reason that holds.
            let why_not = if doc.regions.is_some() {
                Some("Compares one boundary: a drawing or a file of several regions has several faces (quadex compare takes one boundary too)")
            } else if doc.boundary().is_none() {
                Some("Needs a valid boundary")
            } else if chosen.is_empty() {
                Some("Tick a model")
            } else if scene.comparing.is_some() {
                Some("A comparison is running")
            } else {
                None
            };
            if ui
                .add_enabled(why_not.is_none(), egui::Button::new("Compare models"))
                .on_hover_text("Mesh the boundary with each model ticked, in the background")
                .on_disabled_hover_text(why_not.unwrap_or_default())
                .clicked()
            {
                out.push(Command::Compare(chosen.clone()));
            }
            if let Some((done, total)) = scene.comparing {
                ui.spinner();
                ui.label(format!("meshing {} of {total}", done + 1));
                if ui.button("Stop").clicked() {
                    out.push(Command::StopCompare);
                }
            }
        });
        let Some(c) = scene.comparison else {
            return out;
        };
        // What makes the comparison out of date, in amber.
        let stale = |ui: &mut Ui, why: String| {
            ui.colored_label(
                Color32::from_rgb(230, 170, 60),
                format!("{why}: compare again"),
            );
        };
        if doc.boundary() != Some(&c.boundary) {
            stale(ui, "for an earlier boundary".into());
        }
        let gone: Vec<&str> = c
            .outcomes
            .iter()
            .map(|o| o.model.as_str())
            .filter(|m| !names.iter().any(|n| n == m))
            .collect();
        if !gone.is_empty() {
            stale(
                ui,
                format!(
                    "{} no longer in the document (its refit undone)",
                    gone.join(", ")
                ),
            );
        }
        // The table scrolls on its own, its scroll bar right under it: it
        // is wider than the panel.
        super::sideways_table(ui, "compare table scroll", |ui| table(ui, c));
        ui.label("accepted: the model's element as predicted; rescaled: its element with Pn drawn to the size field; replaced: a remedy's element. Shares of the element steps.");
        // As many pictures a row as the panel's width takes (a child of a
        // wrapping row does not move to the next one when it overflows).
        let gap = ui.spacing().item_spacing.x;
        let per_row = (((ui.available_width() + gap) / (PICTURE + gap)).floor() as usize).max(1);
        for row in c.outcomes.chunks(per_row) {
            ui.horizontal_top(|ui| {
                for o in row {
                    ui.vertical(|ui| {
                        // The name wraps at the picture's width (by words).
                        ui.set_width(PICTURE);
                        ui.add(egui::Label::new(&o.model).wrap());
                        picture(ui, o.mesh.as_ref());
                    });
                }
            });
        }
        out
    }
}

/// The comparison's table: a row per model, a column per figure.
fn table(ui: &mut Ui, c: &Comparison) {
    // Scrolled sideways in a narrow panel, so no column is cut off.
    egui::ScrollArea::horizontal()
        .id_salt("compare_table_scroll")
        .show(ui, |ui| {
            egui::Grid::new("compare_table")
                .striped(true)
                .num_columns(compare::COLUMNS.len() + 1)
                .show(ui, |ui| {
                    ui.strong("model");
                    for col in compare::COLUMNS {
                        ui.strong(col);
                    }
                    ui.end_row();
                    for o in &c.outcomes {
                        ui.label(&o.model);
                        ui.label(o.finished_label())
                            .on_hover_text(o.error.as_deref().unwrap_or("finished"));
                        if let Some(f) = o.figures() {
                            for v in f {
                                ui.label(v);
                            }
                        }
                        ui.end_row();
                    }
                });
        });
}

/// A small picture of `mesh`, its quads coloured by scaled Jacobian (an
/// empty frame when the run did not finish).
fn picture(ui: &mut Ui, mesh: Option<&QuadMesh>) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(PICTURE, PICTURE), Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_stroke(
        rect,
        0.0,
        Stroke::new(1.0, Color32::GRAY),
        egui::StrokeKind::Inside,
    );
    let Some(m) = mesh else { return };
    let Some(b) = Aabb::of(m.nodes.iter().copied()) else {
        return;
    };
    let inner = rect.shrink(4.0);
    let ext = b.max - b.min;
    let scale =
        (inner.width() as f64 / ext.x.max(1e-300)).min(inner.height() as f64 / ext.y.max(1e-300));
    let to = |p: crate::Point| {
        Pos2::new(
            inner.center().x + ((p.x - 0.5 * (b.min.x + b.max.x)) * scale) as f32,
            inner.center().y - ((p.y - 0.5 * (b.min.y + b.max.y)) * scale) as f32,
        )
    };
    let edge = Stroke::new(0.5, Color32::from_gray(40));
    for q in &m.quads {
        let c = m.corners(q);
        let pts: Vec<Pos2> = c.iter().map(|&p| to(p)).collect();
        let fill = quality_color(QuadQuality::of(c).scaled_jacobian);
        painter.add(egui::Shape::convex_polygon(pts, fill, edge));
    }
}

//! The Smoothing panel: the cleanup (topological improvement), the local
//! remeshing of bad regions and the smoothing (constrained Laplacian,
//! method §2 step 4, then optimisation) applied to the finished mesh, with the mesh's figures before and after.
//! Changing them does not step again: the finished mesh is recomputed.

use super::command::Command;
use super::document::Settings;
use super::{Document, Figures, MeshKind};
use crate::finish::cleanup::CleanupParams;
use crate::finish::coarsen::CoarsenParams;
use crate::finish::remesh::RemeshParams;
use crate::quality::MeshQuality;
use crate::smooth::SmoothParams;
use egui::Ui;
use std::ops::RangeInclusive;

/// One figure of a mesh, as the comparison table shows it.
type Figure = fn(&MeshQuality) -> String;

#[derive(Default)]
pub struct SmoothPanel {
    /// Figures of the mesh as stepped, keyed by the mesh version.
    raw: Option<(u64, MeshQuality)>,
}

impl super::View for SmoothPanel {
    type Input<'a> = Figures<'a>;

    fn ui(&mut self, ui: &mut Ui, doc: &Document, shown: Figures<'_>) -> Vec<Command> {
        let mut cmds = Vec::new();
        let out = &mut cmds;
        let version = shown.mesh_version;
        let finished = match shown.kind {
            MeshKind::Finished | MeshKind::Updating => Some(&shown.stats.summary),
            _ => None,
        };
        ui.label("Applied to the mesh once it is complete; changing them keeps the steps (the finished mesh is computed again in the background, the previous one shown meanwhile).");
        let mut s: Settings = doc.settings.clone();
        let sm = &mut s.smooth;
        egui::Grid::new("smooth_params")
            .num_columns(2)
            .show(ui, |ui| {
                count_row(ui, "Laplacian sweeps", &mut sm.iterations, 0..=100);
                fraction_row(ui, "keep scaled Jacobian ≥", &mut sm.threshold, 0.0..=1.0);
                fraction_row(ui, "relaxation", &mut sm.relaxation, 0.05..=1.0);
                count_row(ui, "optimisation sweeps", &mut sm.optimize_sweeps, 0..=50);
                fraction_row(
                    ui,
                    "optimise quads below",
                    &mut sm.optimize_below,
                    0.0..=1.0,
                );
                count_row(ui, "polishing sweeps", &mut sm.polish_sweeps, 0..=50).on_hover_text(
                    "raise the mean scaled Jacobian of the final mesh, keeping its worst quads",
                );
                fraction_row(ui, "polish quads below", &mut sm.polish_below, 0.0..=1.0);
            });
        ui.label(egui::RichText::new("Cleanup").strong());
        let c = &mut s.cleanup;
        egui::Grid::new("cleanup_params")
            .num_columns(2)
            .show(ui, |ui| {
                count_row(ui, "passes", &mut c.passes, 0..=20);
                count_row(ui, "rounds with smoothing", &mut c.rounds, 0..=20);
                fraction_row(ui, "collapse slivers below SJ", &mut c.sliver_sj, 0.0..=0.5);
                fraction_row(
                    ui,
                    "edge swap keeps SJ ≥",
                    &mut c.min_swap_quality,
                    0.0..=1.0,
                );
            });
        ui.label(egui::RichText::new("Chord coarsening").strong())
            .on_hover_text("closed rows of quads lower than the size field asks are removed");
        let k = &mut s.coarsen;
        egui::Grid::new("coarsen_params")
            .num_columns(2)
            .show(ui, |ui| {
                count_row(ui, "rounds", &mut k.rounds, 0..=20);
                fraction_row(
                    ui,
                    "remove rows lower than (× size)",
                    &mut k.max_rung,
                    0.0..=1.5,
                );
                fraction_row(ui, "quads around keep SJ ≥", &mut k.min_sj, 0.0..=1.0);
                fraction_row(
                    ui,
                    "quads around at most (long/short)",
                    &mut k.max_aspect,
                    1.0..=10.0,
                );
            });
        ui.label(egui::RichText::new("Local remeshing").strong())
            .on_hover_text("the regions around quads still bad after cleanup are meshed again");
        let r = &mut s.remesh;
        egui::Grid::new("remesh_params")
            .num_columns(2)
            .show(ui, |ui| {
                fraction_row(ui, "remesh around quads below SJ", &mut r.below, 0.0..=0.9);
                count_row(ui, "largest region (rings)", &mut r.rings, 2..=8);
                count_row(ui, "at most regions", &mut r.max_regions, 0..=10_000);
            });
        ui.horizontal_wrapped(|ui| {
            if ui
                .button("Defaults")
                .on_hover_text(
                    "Cleanup, coarsening, remeshing and smoothing as the command line does them",
                )
                .clicked()
            {
                s.smooth = SmoothParams::DEFAULT;
                s.cleanup = CleanupParams::DEFAULT;
                s.coarsen = CoarsenParams::DEFAULT;
                s.remesh = RemeshParams::DEFAULT;
            }
            if ui
                .button("No smoothing")
                .on_hover_text("No Laplacian smoothing and no optimisation")
                .clicked()
            {
                s.smooth = SmoothParams::OFF;
            }
            if ui
                .button("No cleanup")
                .on_hover_text("No topological cleanup (collapses, swaps)")
                .clicked()
            {
                s.cleanup = CleanupParams::OFF;
            }
            if ui
                .button("No coarsening")
                .on_hover_text("No chord coarsening (rows lower than the size field stay)")
                .clicked()
            {
                s.coarsen = CoarsenParams::OFF;
            }
            if ui
                .button("No remeshing")
                .on_hover_text("No local remeshing of bad regions")
                .clicked()
            {
                s.remesh = RemeshParams::OFF;
            }
        });
        if s != doc.settings {
            out.push(Command::SetSettings(s));
        }
        ui.separator();
        let Some(mesher) = doc.mesher() else {
            return cmds;
        };
        if self.raw.as_ref().is_none_or(|(v, _)| *v != version) {
            self.raw = Some((version, MeshQuality::of(mesher.mesh())));
        }
        let Some((_, raw)) = &self.raw else {
            return cmds;
        };
        let Some(done) = finished else {
            ui.label("Run the mesh to the end to see the finished mesh's figures.");
            return cmds;
        };
        if shown.kind == MeshKind::Updating {
            ui.label("Updating the finished mesh for these settings…");
        }
        egui::Grid::new("smooth_effect")
            .num_columns(3)
            .striped(true)
            .show(ui, |ui| {
                ui.strong("");
                ui.strong("as stepped");
                ui.strong("finished");
                ui.end_row();
                let rows: [(&str, Figure); 6] = [
                    ("quads", |q| q.quads.to_string()),
                    ("scaled Jacobian min", |q| format!("{:.3}", q.sj_min)),
                    ("scaled Jacobian mean", |q| format!("{:.3}", q.sj_mean)),
                    ("angles in [45°, 135°]", |q| {
                        super::missing(q.frac_angles_45_135, q.quads, "outside")
                    }),
                    ("min angle", |q| format!("{:.1}°", q.min_angle)),
                    ("irregular interior", |q| q.irregular_interior.to_string()),
                ];
                for (name, f) in rows {
                    ui.label(name);
                    ui.monospace(f(raw));
                    ui.monospace(f(done));
                    ui.end_row();
                }
            });
        cmds
    }
}

/// A grid row: `label` and a drag value for `value`, a bound or fraction
/// in `range`, stepped by 0.01. Returns the label's response.
fn fraction_row(
    ui: &mut Ui,
    label: &str,
    value: &mut f64,
    range: RangeInclusive<f64>,
) -> egui::Response {
    let r = ui.label(label);
    ui.add(egui::DragValue::new(value).range(range).speed(0.01));
    ui.end_row();
    r
}

/// A grid row: `label` and a drag value for `value`, a count in `range`.
/// Returns the label's response.
fn count_row(
    ui: &mut Ui,
    label: &str,
    value: &mut usize,
    range: RangeInclusive<usize>,
) -> egui::Response {
    let r = ui.label(label);
    ui.add(egui::DragValue::new(value).range(range));
    ui.end_row();
    r
}

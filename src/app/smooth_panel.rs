//! The Smoothing panel: the cleanup (topological improvement), the local
//! remeshing of bad regions and the smoothing (constrained Laplacian,
//! method §2 step 4, then optimisation) applied to the finished mesh, with the mesh's figures before and after.
//! Changing them does not step again: the finished mesh is recomputed.

use super::command::Command;
use super::document::Settings;
use super::{Document, Figures, MeshKind};
use crate::cleanup::CleanupParams;
use crate::coarsen::CoarsenParams;
use crate::quality::MeshQuality;
use crate::remesh::RemeshParams;
use crate::smooth::SmoothParams;
use egui::Ui;

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
                ui.label("Laplacian sweeps");
                ui.add(egui::DragValue::new(&mut sm.iterations).range(0..=100));
                ui.end_row();
                ui.label("keep scaled Jacobian ≥");
                ui.add(
                    egui::DragValue::new(&mut sm.threshold)
                        .range(0.0..=1.0)
                        .speed(0.01),
                );
                ui.end_row();
                ui.label("relaxation");
                ui.add(
                    egui::DragValue::new(&mut sm.relaxation)
                        .range(0.05..=1.0)
                        .speed(0.01),
                );
                ui.end_row();
                ui.label("optimisation sweeps");
                ui.add(egui::DragValue::new(&mut sm.optimize_sweeps).range(0..=50));
                ui.end_row();
                ui.label("optimise quads below");
                ui.add(
                    egui::DragValue::new(&mut sm.optimize_below)
                        .range(0.0..=1.0)
                        .speed(0.01),
                );
                ui.end_row();
                ui.label("polishing sweeps").on_hover_text(
                    "raise the mean scaled Jacobian of the final mesh, keeping its worst quads",
                );
                ui.add(egui::DragValue::new(&mut sm.polish_sweeps).range(0..=50));
                ui.end_row();
                ui.label("polish quads below");
                ui.add(
                    egui::DragValue::new(&mut sm.polish_below)
                        .range(0.0..=1.0)
                        .speed(0.01),
                );
                ui.end_row();
            });
        ui.label(egui::RichText::new("Cleanup").strong());
        let c = &mut s.cleanup;
        egui::Grid::new("cleanup_params")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("passes");
                ui.add(egui::DragValue::new(&mut c.passes).range(0..=20));
                ui.end_row();
                ui.label("rounds with smoothing");
                ui.add(egui::DragValue::new(&mut c.rounds).range(0..=20));
                ui.end_row();
                ui.label("collapse slivers below SJ");
                ui.add(
                    egui::DragValue::new(&mut c.sliver_sj)
                        .range(0.0..=0.5)
                        .speed(0.01),
                );
                ui.end_row();
                ui.label("edge swap keeps SJ ≥");
                ui.add(
                    egui::DragValue::new(&mut c.min_swap_quality)
                        .range(0.0..=1.0)
                        .speed(0.01),
                );
                ui.end_row();
            });
        ui.label(egui::RichText::new("Chord coarsening").strong())
            .on_hover_text("closed rows of quads lower than the size field asks are removed");
        let k = &mut s.coarsen;
        egui::Grid::new("coarsen_params")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("rounds");
                ui.add(egui::DragValue::new(&mut k.rounds).range(0..=20));
                ui.end_row();
                ui.label("remove rows lower than (× size)");
                ui.add(
                    egui::DragValue::new(&mut k.max_rung)
                        .range(0.0..=1.5)
                        .speed(0.01),
                );
                ui.end_row();
                ui.label("quads around keep SJ ≥");
                ui.add(
                    egui::DragValue::new(&mut k.min_sj)
                        .range(0.0..=1.0)
                        .speed(0.01),
                );
                ui.end_row();
                ui.label("quads around at most (long/short)");
                ui.add(
                    egui::DragValue::new(&mut k.max_aspect)
                        .range(1.0..=10.0)
                        .speed(0.01),
                );
                ui.end_row();
            });
        ui.label(egui::RichText::new("Local remeshing").strong())
            .on_hover_text("the regions around quads still bad after cleanup are meshed again");
        let r = &mut s.remesh;
        egui::Grid::new("remesh_params")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("remesh around quads below SJ");
                ui.add(
                    egui::DragValue::new(&mut r.below)
                        .range(0.0..=0.9)
                        .speed(0.01),
                );
                ui.end_row();
                ui.label("largest region (rings)");
                ui.add(egui::DragValue::new(&mut r.rings).range(2..=8));
                ui.end_row();
                ui.label("at most regions");
                ui.add(egui::DragValue::new(&mut r.max_regions).range(0..=10_000));
                ui.end_row();
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
                        format!("{:.1} %", 100.0 * q.frac_angles_45_135)
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

//! The Training set panel: the user's samples (method §3: the leading
//! points normalised, the type and Pn) in a table with a filter, deleting
//! the selected ones, CSV import and export, and collecting samples from
//! the finished mesh or a mesh file.

use super::command::{Command, Dialog};
use super::document::Document;
use super::MeshKind;
use crate::samples::{Sample, Source};
use egui::Ui;
use std::collections::BTreeSet;

/// The panel's state: the filter and the selection.
#[derive(Default)]
pub struct SamplesPanel {
    /// Show only this type.
    pub type_filter: Option<u8>,
    /// Show only samples whose source contains this text.
    pub source_filter: String,
    /// Selected rows (positions in the set).
    pub selected: BTreeSet<usize>,
}

/// The source of a sample as the table shows it.
fn source(s: &Sample) -> String {
    match &s.source {
        Source::Mesh { file, element } => format!("{file} #{element}"),
        Source::Correction => "correction".into(),
    }
}

impl SamplesPanel {
    /// Positions of the samples the filter lets through.
    pub fn visible(&self, doc: &Document) -> Vec<usize> {
        let text = self.source_filter.to_lowercase();
        doc.training
            .samples
            .iter()
            .enumerate()
            .filter(|(_, s)| {
                self.type_filter
                    .is_none_or(|t| s.element_type.number() == t)
                    && (text.is_empty() || source(s).to_lowercase().contains(&text))
            })
            .map(|(i, _)| i)
            .collect()
    }
}

impl super::View for SamplesPanel {
    type Input<'a> = MeshKind;

    fn ui(&mut self, ui: &mut Ui, doc: &Document, kind: MeshKind) -> Vec<Command> {
        let mut cmds = Vec::new();
        let out = &mut cmds;
        let done = matches!(kind, MeshKind::Finished | MeshKind::Imported);
        let set = &doc.training;
        let [t0, t1, t2] = set.type_counts();
        ui.label(format!(
            "{} of yours at {} input points (type 0: {t0}, 1: {t1}, 2: {t2}); a refit adds them to the reference meshes' samples",
            super::plural(set.len(), "sample"),
            set.points
        ));
        ui.horizontal_wrapped(|ui| {
            if ui
                .button("Import CSV…")
                .on_hover_text("Append the samples of a training-set file (.csv or .json)")
                .clicked()
            {
                out.push(Command::Dialog(Dialog::ImportSamples));
            }
            if ui
                .add_enabled(!set.is_empty(), egui::Button::new("Export CSV…"))
                .on_hover_text("Write your samples as CSV in the thesis's column order (or .json)")
                .clicked()
            {
                out.push(Command::Dialog(Dialog::ExportSamples));
            }
            if ui
                .add_enabled(done, egui::Button::new("Collect from this mesh"))
                .on_hover_text("Every corner of every good quad of the finished mesh as a sample")
                .on_disabled_hover_text("Run the mesh to the end first")
                .clicked()
            {
                out.push(Command::CollectFromMesh);
            }
            if ui
                .button("Collect from a mesh file…")
                .on_hover_text("Every corner of every good quad of a .msh file as a sample")
                .clicked()
            {
                out.push(Command::Dialog(Dialog::CollectFromFile));
            }
        });
        ui.horizontal(|ui| {
            ui.label("type");
            ui.selectable_value(&mut self.type_filter, None, "all");
            for t in 0..3u8 {
                ui.selectable_value(&mut self.type_filter, Some(t), t.to_string());
            }
            ui.label("source");
            ui.add(egui::TextEdit::singleline(&mut self.source_filter).desired_width(90.0))
                .on_hover_text("Show only samples whose source contains this text");
        });
        self.selected.retain(|&i| i < set.len());
        let rows = self.visible(doc);
        ui.horizontal_wrapped(|ui| {
            ui.label(format!(
                "{} shown, {} selected",
                rows.len(),
                self.selected.len()
            ));
            if ui
                .button("Select shown")
                .on_hover_text("Select every sample the filter shows")
                .clicked()
            {
                self.selected.extend(rows.iter().copied());
            }
            if ui
                .button("Select none")
                .on_hover_text("Clear the selection")
                .clicked()
            {
                self.selected.clear();
            }
            if ui
                .add_enabled(
                    !self.selected.is_empty(),
                    egui::Button::new("Delete selected"),
                )
                .on_hover_text("Drop the selected samples (undo brings them back)")
                .clicked()
            {
                out.push(Command::DeleteSamples(
                    self.selected.iter().copied().collect(),
                ));
                self.selected.clear();
            }
        });
        let row_h = ui.text_style_height(&egui::TextStyle::Monospace) + 4.0;
        // Every input point: samples of one corner differ only in the front
        // beyond l1 or r1 (and in their type), so a row shows all of them.
        let n = set.points / 2;
        let names = |side: char, rev: bool| {
            let mut v: Vec<String> = (1..=n).map(|k| format!("{side}{k}")).collect();
            if rev {
                v.reverse();
            }
            v
        };
        let width = 13;
        let inputs_header = format!(
            "{} | {}",
            names('l', true)
                .iter()
                .map(|s| format!("{s:<width$}"))
                .collect::<Vec<_>>()
                .join(" "),
            names('r', false)
                .iter()
                .map(|s| format!("{s:<width$}"))
                .collect::<Vec<_>>()
                .join(" ")
        );
        let header = format!(
            "{:>6} {:>4} {:>8} {:>8}  {inputs_header}  source",
            "#", "type", "Xn", "Yn"
        );
        // The rows are one line each however narrow the panel: the table
        // scrolls sideways (header with it) rather than wrap a row's source.
        // The rows take the panel's height left (less the bar below them).
        let rows_height = (ui.available_height() - 40.0).max(160.0);
        super::sideways_table(ui, "samples_table_wide", |ui| {
            ui.monospace(header);
            egui::ScrollArea::vertical()
                .id_salt("samples_table")
                .max_height(rows_height)
                .auto_shrink([false, true])
                .show_rows(ui, row_h, rows.len(), |ui, range| {
                    for &i in &rows[range] {
                        let s = &set.samples[i];
                        let pt = |p: &crate::geom::Point| {
                            format!("{:<width$}", format!("({:.2},{:.2})", p.x, p.y))
                        };
                        let left: Vec<String> = s.input.left.iter().rev().map(pt).collect();
                        let right: Vec<String> = s.input.right.iter().map(pt).collect();
                        let text = format!(
                            "{i:>6} {:>4} {:>8.4} {:>8.4}  {} | {}  {}",
                            s.element_type.number(),
                            s.pn.x,
                            s.pn.y,
                            left.join(" "),
                            right.join(" "),
                            source(s)
                        );
                        let mut on = self.selected.contains(&i);
                        if ui
                            .toggle_value(&mut on, egui::RichText::new(text).monospace())
                            .changed()
                        {
                            if on {
                                self.selected.insert(i);
                            } else {
                                self.selected.remove(&i);
                            }
                        }
                    }
                });
        });
        cmds
    }
}

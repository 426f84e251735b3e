//! The tools' panels: the tool bar above the canvas, the Boundary section
//! of the left panel ([`View`](crate::app::View) for [`Tools`]) and the
//! Drawing section.

use super::{loop_role, Tool, Tools};
use crate::app::command::Command;
use crate::app::document::{Document, Target};
use crate::app::MeshKind;
use crate::geom::Point;
use egui::{Color32, Ui};

/// A drag value for a target size, its speed and range from the extent of
/// `points`.
fn size_value(ui: &mut Ui, h: &mut f64, points: impl Iterator<Item = Point>) -> egui::Response {
    let scale = points
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()))
        .max(1e-12);
    ui.add(
        egui::DragValue::new(h)
            .speed(0.001 * scale)
            .range(1e-9 * scale..=f64::MAX),
    )
}

/// Lines of the tool bar's note under its tools.
const NOTE_ROWS: usize = 2;

impl crate::app::View for Tools {
    /// The boundary section of the left panel: its loops, resampling, and
    /// whether it is a valid boundary.
    type Input<'a> = ();

    fn ui(&mut self, ui: &mut Ui, doc: &Document, _: ()) -> Vec<Command> {
        let mut out = Vec::new();
        ui.heading("Boundary");
        let d = &doc.draft;
        if !d.loops.is_empty() {
            ui.horizontal_wrapped(|ui| {
                ui.label("resample");
                let name = |li: usize| {
                    format!(
                        "loop {li} ({}, {})",
                        loop_role(d, li),
                        crate::app::plural(d.loops[li].len(), "node")
                    )
                };
                let all = format!("all loops ({})", crate::app::plural(d.node_count(), "node"));
                let li = self.resample_loop.min(d.loops.len() - 1);
                egui::ComboBox::from_id_salt("resample_loop")
                    .selected_text(if self.resample_all { all.clone() } else { name(li) })
                    .show_ui(ui, |ui| {
                        if ui.selectable_label(self.resample_all, &all).clicked() {
                            self.resample_all = true;
                        }
                        for li in 0..d.loops.len() {
                            let on = !self.resample_all && self.resample_loop == li;
                            if ui.selectable_label(on, name(li)).clicked() {
                                self.resample_all = false;
                                self.resample_loop = li;
                            }
                        }
                    })
                    .response
                    .on_hover_text("The loops to resample: all of them, or one (numbers as on the canvas with an editing tool)");
                ui.label("to size H");
                size_value(ui, &mut self.resample_h, d.loops.iter().flatten().copied())
                    .on_hover_text("Target size H: the segment length to cut the boundary at (starts at this file's median segment)");
                let refused = if self.resample_all {
                    d.resample_all_nodes(self.resample_h).err()
                } else {
                    d.resample_parts(self.resample_loop, self.resample_h).err()
                };
                let mut button = ui
                    .add_enabled(refused.is_none(), egui::Button::new("Resample"))
                    .on_hover_text("Cut every segment of the loops chosen into round(length / H) parts, keeping the corners; one part more on the longest piece when the total node count would be odd");
                if let Some(e) = &refused {
                    button = button.on_disabled_hover_text(e.to_string());
                }
                if button.clicked() {
                    if self.resample_all {
                        out.push(Command::SetSize(self.resample_h));
                    } else {
                        let mut d = d.clone();
                        if d.resample(self.resample_loop, self.resample_h).is_ok() {
                            out.push(Command::SetDraft {
                                draft: d,
                                what: "resample loop",
                            });
                        }
                    }
                }
            });
        }
        match &doc.problem {
            None => {
                ui.label(format!(
                    "{}, {}: valid",
                    crate::app::plural(d.loops.len(), "loop"),
                    crate::app::plural(d.node_count(), "node")
                ));
            }
            Some(crate::boundary::BoundaryError::Empty) if d.loops.is_empty() => {
                ui.label(if self.tool == Tool::Draw {
                    "Nothing drawn yet: click on the canvas to place the outer loop's nodes."
                } else {
                    "Nothing drawn yet: choose the \"draw loop\" tool above the canvas and click on the canvas."
                });
            }
            Some(e) => {
                ui.colored_label(
                    Color32::from_rgb(255, 110, 110),
                    format!("not a valid boundary yet: {e}"),
                );
                ui.label(if d.marked(e).is_empty() {
                    "Fix it with the tools above the canvas or a resample, or undo."
                } else {
                    "The nodes at fault are circled in red; fix them with the tools above, or undo."
                });
            }
        }
        out
    }
}

impl Tools {
    /// The Drawing section of the left panel (a document cut from a
    /// drawing's curves): the target size H, and Apply to cut the curves
    /// again at it and mesh from the start.
    pub fn drawing_ui(&mut self, ui: &mut Ui, doc: &Document) -> Vec<Command> {
        let mut out = Vec::new();
        let Some(d) = &doc.drawing else {
            return out;
        };
        ui.heading("Drawing");
        let count = |f: fn(&crate::cad::Curve) -> bool| {
            d.geometry.curves.iter().filter(|c| f(&c.curve)).count()
        };
        let lines = count(|c| matches!(c, crate::cad::Curve::Line { .. }));
        let arcs = count(|c| matches!(c, crate::cad::Curve::Arc { .. }));
        let ellipses = count(|c| matches!(c, crate::cad::Curve::Ellipse { .. }));
        let splines = count(|c| matches!(c, crate::cad::Curve::Spline(_)));
        let nodes = doc.regions.as_ref().map_or(0, |r| r.graph.points.len());
        let mut kinds = vec![
            crate::app::plural(lines, "line"),
            crate::app::plural(arcs, "arc"),
        ];
        if ellipses > 0 {
            kinds.push(crate::app::plural(ellipses, "ellipse"));
        }
        if splines > 0 {
            kinds.push(crate::app::plural(splines, "spline"));
        }
        // A geometry file's local sizes, which the cut follows too: by
        // layer ("bolt 1") and at points.
        let mut local: Vec<String> = d
            .sizes
            .layers
            .iter()
            .map(|(l, h)| format!("{l} {h}"))
            .collect();
        if !d.sizes.points.is_empty() {
            local.push(crate::app::plural(d.sizes.points.len(), "point"));
        }
        let local = if local.is_empty() {
            String::new()
        } else {
            format!(
                " (local sizes: {}; gradation {})",
                local.join(", "),
                d.sizes.gradation
            )
        };
        ui.label(format!(
            "{}; cut at size {}{local} into {}{}",
            kinds.join(", "),
            d.sizes.size,
            crate::app::plural(nodes, "boundary node"),
            if d.parity_fixes > 0 {
                format!(
                    " ({} one segment more for even regions)",
                    crate::app::plural(d.parity_fixes, "curve")
                )
            } else {
                String::new()
            }
        ));
        ui.horizontal_wrapped(|ui| {
            ui.label("size H");
            let pts = doc.regions.iter().flat_map(|r| r.graph.points.iter().copied());
            size_value(ui, &mut self.resample_h, pts)
                .on_hover_text("Target size H: each curve is cut into about length / H segments (arcs also one per 15°), every region's node count made even");
            let changed = (self.resample_h - d.sizes.size).abs() > 1e-12 * d.sizes.size.abs().max(1.0);
            if ui
                .add_enabled(changed, egui::Button::new("Apply"))
                .on_hover_text("Cut the curves again at size H and mesh from the start")
                .on_disabled_hover_text("The drawing is cut at this size")
                .clicked()
            {
                out.push(Command::SetSize(self.resample_h));
            }
        });
        out
    }

    /// The tool bar above the canvas: the tools, the one in hand's hint and
    /// options (a split's parts, the loop being drawn, the closing targets
    /// of the Correct tool).
    pub fn toolbar(
        &mut self,
        ui: &mut Ui,
        doc: &Document,
        kind: MeshKind,
        targets: &[Target],
    ) -> Vec<Command> {
        // The tools on one row, what the tool says below in two lines
        // whatever it says (a bar whose height changed would shrink the
        // canvas and move the drawing under the pointer): a text longer
        // than two lines is cut, in full on hover.
        let mut said: Option<(String, bool)> = None;
        let mut note = |_: &mut Ui, text: String, weak: bool| said = Some((text, weak));
        ui.horizontal(|ui| {
            ui.label(egui::RichText::new("Tool").strong());
            for t in Tool::ALL {
                ui.selectable_value(&mut self.tool, t, t.name())
                    .on_hover_text(t.hint());
            }
            ui.separator();
            match self.tool {
                Tool::Correct
                    if doc.last_element().is_some() && kind == MeshKind::Stepped =>
                {
                    let valid = targets.iter().filter(|t| t.valid()).count();
                    note(
                        ui,
                        if valid == 0 {
                            "Drag Pn to correct. No front node near P0 closes a valid element here: the quad would be flat or fold. Closing onto a node works where the front turns (corners, fronts meeting).".to_string()
                        } else {
                            format!(
                                "Click a ringed node to close onto it, or drag Pn: {} near P0 {} a valid element (green good, amber fair, orange poor).",
                                crate::app::plural(valid, "front node"),
                                if valid == 1 { "gives" } else { "give" }
                            )
                        },
                        false,
                    );
                }
                Tool::Arc if !self.arc_clicks.is_empty() || !self.drawing.is_empty() => {
                    if ui
                        .button("Drop the loop")
                        .on_hover_text("Forget the nodes and arc points placed (Esc or right-click)")
                        .clicked()
                    {
                        self.drawing.clear();
                        self.arc_clicks.clear();
                    }
                    note(
                        ui,
                        format!(
                            "{} placed; {}",
                            crate::app::plural(self.drawing.len(), "node"),
                            match self.arc_clicks.len() {
                                0 => "click the next arc's start",
                                1 => "click a point the arc passes through",
                                _ => "click the arc's end (the first node closes the loop)",
                            }
                        ),
                        false,
                    );
                }
                Tool::Draw if !self.drawing.is_empty() => {
                    if ui
                        .button("Drop the loop")
                        .on_hover_text("Forget the nodes placed (Esc or right-click)")
                        .clicked()
                    {
                        self.drawing.clear();
                    }
                    note(
                        ui,
                        format!(
                            "{} placed; click the first node to close the loop",
                            crate::app::plural(self.drawing.len(), "node")
                        ),
                        false,
                    );
                }
                Tool::Split => {
                    ui.label("parts");
                    ui.add(egui::DragValue::new(&mut self.split_parts).range(2..=100))
                        .on_hover_text("A split cuts the segment clicked into this many equal parts (an odd number keeps the boundary's node count even, as an all-quad mesh needs)");
                    note(ui, self.tool.hint().to_string(), true);
                }
                t => note(ui, t.hint().to_string(), true),
            }
        });
        let rows = NOTE_ROWS as f32 * ui.text_style_height(&egui::TextStyle::Body)
            + ui.spacing().item_spacing.y;
        let width = ui.available_width();
        ui.allocate_ui_with_layout(
            egui::vec2(width, rows),
            egui::Layout::top_down(egui::Align::Min),
            |ui| {
                ui.set_min_size(egui::vec2(width, rows));
                if let Some((text, weak)) = said {
                    let color = if weak {
                        ui.visuals().weak_text_color()
                    } else {
                        ui.visuals().text_color()
                    };
                    let mut job = egui::text::LayoutJob::single_section(
                        text.clone(),
                        egui::TextFormat::simple(egui::TextStyle::Body.resolve(ui.style()), color),
                    );
                    job.wrap = egui::text::TextWrapping {
                        max_width: width,
                        max_rows: NOTE_ROWS,
                        break_anywhere: false,
                        overflow_character: Some('…'),
                    };
                    ui.add(egui::Label::new(job)).on_hover_text(text);
                }
            },
        );
        Vec::new()
    }
}

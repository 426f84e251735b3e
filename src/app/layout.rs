//! The frame's layout: the menu bar, the status bar, the side panels (the
//! left one's sections, the right one's tabs) and the canvas between them.

use super::command::{Command, Dialog};
use super::compare_panel::{CompareJob, CompareState};
use super::document::{Document, Target};
use super::job::Job;
use super::text::plural;
use super::tools::{self, Tool};
use super::{
    canvas, figures_of, shown_of, targets_of, App, Figures, MeshKind, RunState, View, ViewState,
};
use crate::geom::Aabb;
use crate::mesh::QuadMesh;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The panels on the right.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Tab {
    #[default]
    Quality,
    Model,
    Samples,
    Smoothing,
    Compare,
}

impl Tab {
    pub(super) const ALL: [Tab; 5] = [
        Tab::Quality,
        Tab::Model,
        Tab::Samples,
        Tab::Smoothing,
        Tab::Compare,
    ];

    pub(super) fn name(self) -> &'static str {
        match self {
            Tab::Quality => "Quality",
            Tab::Model => "Model",
            Tab::Samples => "Training set",
            Tab::Smoothing => "Smoothing",
            Tab::Compare => "Compare",
        }
    }

    pub(super) fn hint(self) -> &'static str {
        match self {
            Tab::Quality => "Figures and histograms of the mesh shown",
            Tab::Model => "How well the model fits the samples, and the critical factors",
            Tab::Samples => "Your training samples: filter, delete, import, export, collect",
            Tab::Smoothing => "Cleanup, remeshing and smoothing of the finished mesh",
            Tab::Compare => "The boundary meshed by several models side by side",
        }
    }

    pub(super) fn parse(s: &str) -> Option<Tab> {
        match s {
            "quality" => Some(Tab::Quality),
            "model" => Some(Tab::Model),
            "samples" | "training" => Some(Tab::Samples),
            "smoothing" => Some(Tab::Smoothing),
            "compare" => Some(Tab::Compare),
            _ => None,
        }
    }
}

/// The side panels' widths at first (points): left, right.
pub(super) const PANEL_WIDTHS: [f32; 2] = [290.0, 400.0];

/// The side panels' narrowest widths: left, right.
pub(super) const PANEL_MIN_WIDTHS: [f32; 2] = [170.0, 190.0];

/// The share of the window a side panel may take at most: left, right.
pub(super) const PANEL_MAX_SHARES: [f32; 2] = [0.24, 0.28];

/// Gives side panel `id` the width the user chose, `want`, as far as
/// `max` allows. egui keeps (and persists) the width a narrower window
/// forced on a panel, so a window made wide again would keep it narrow.
pub(super) fn restore_panel_width(ctx: &egui::Context, id: egui::Id, want: f32, max: f32) {
    let w = want.min(max);
    if let Some(mut state) = egui::containers::panel::PanelState::load(ctx, id) {
        if state.rect.width() + 0.5 < w {
            state.rect.set_width(w);
            ctx.data_mut(|d| d.insert_persisted(id, state));
        }
    }
}

/// The width the user chose for a panel shown `shown` wide: any width
/// under the window's bound `max` is a choice (a drag), as is a width over
/// the last choice; at the bound the window may have forced it.
pub(super) fn chosen_panel_width(want: f32, shown: f32, max: f32) -> f32 {
    if shown < max - 0.5 || shown > want {
        shown
    } else {
        want
    }
}

impl App {
    /// One frame of the whole editor (also what the UI tests drive).
    pub fn ui(&mut self, ctx: &egui::Context) {
        self.window.frame += 1;
        if let (1, Some(size)) = (self.window.frame, self.window.size) {
            ctx.send_viewport_cmd(egui::ViewportCommand::InnerSize(size));
        }
        if self.background.job.as_ref().is_some_and(Job::is_finished) {
            if let Some(mut j) = self.background.job.take() {
                let done = j.wait();
                self.job_done(j, done);
            }
        }
        self.background.orphans.retain(|h| !h.is_finished());
        if self
            .background
            .region_run
            .as_ref()
            .is_some_and(|r| r.handle.is_finished())
        {
            if let Some(r) = self.background.region_run.take() {
                self.region_run_done(r);
            }
        }
        if let Some(r) = self.document.doc.regions.as_mut() {
            r.sync_shown();
            self.panels.regions.sync(r);
        }
        if self
            .background
            .compare
            .as_ref()
            .is_some_and(CompareJob::is_finished)
        {
            self.compare_done();
        }
        if self
            .background
            .refit
            .as_ref()
            .is_some_and(|f| f.handle.is_finished())
        {
            if let Some(r) = self.background.refit.take() {
                self.refit_joined(r);
            }
        }
        let mut cmds = Vec::new();
        self.input_commands(ctx, &mut cmds);
        self.panels.tools.sync(&self.document.doc);
        let d = self.default_export_path();
        if self.panels.export_default.as_ref() != Some(&d) {
            // Another document (or the same under another name): the
            // Export box starts again beside it.
            self.panels.export_path = d.clone();
            self.panels.export_default = Some(d);
        }
        self.refresh_finished(ctx);
        self.refresh_preview();
        self.refresh_targets();
        let title = format!("quadex: {}", self.title_line());
        if title != self.window.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.window.title = title;
        }
        egui::TopBottomPanel::top("menu").show(ctx, |ui| {
            egui::MenuBar::new().ui(ui, |ui| self.menus(ui, &mut cmds));
        });
        egui::TopBottomPanel::bottom("status").show(ctx, |ui| self.status_bar(ui, &mut cmds));
        // The figures of the shown mesh.
        let shown_key = {
            let s = self.shown();
            (
                self.document.mesh_version,
                s.kind,
                s.mesh as *const QuadMesh as usize,
            )
        };
        if self.view.stats_key != Some(shown_key) {
            let ViewState {
                stats,
                finished,
                empty,
                stats_key,
                ..
            } = &mut self.view;
            let s = shown_of(&self.document, finished, empty);
            // The stepped mesh's front nodes are not interior nodes yet.
            // The faces of a drawing or a file of regions are shown side by
            // side, each with its own copy of the nodes it shares: a node on
            // an edge of one quad only is on a face's boundary or front.
            let open: Vec<u32> = match (s.kind, self.document.doc.mesher()) {
                (MeshKind::Stepped, Some(m)) => {
                    let f = m.front();
                    f.live_loops().flat_map(|l| f.loop_nodes(l)).collect()
                }
                (MeshKind::Stepped, None) if self.document.doc.regions.is_some() => {
                    crate::mesh::open_edge_nodes(&s.mesh.quads)
                }
                _ => Vec::new(),
            };
            stats.refresh(shown_key.0 * 8 + shown_key.1 as u64, s.mesh, &open);
            *stats_key = Some(shown_key);
        }
        let width = ctx.content_rect().width();
        let busy = self.busy();
        let max_widths = [0, 1].map(|k| (PANEL_MAX_SHARES[k] * width).max(PANEL_MIN_WIDTHS[k]));
        if self.panels.show_left {
            let id = egui::Id::new("steps");
            restore_panel_width(ctx, id, self.panels.widths[0], max_widths[0]);
            let shown = egui::SidePanel::left(id)
                .resizable(true)
                .default_width(self.panels.widths[0])
                .min_width(PANEL_MIN_WIDTHS[0])
                .max_width(max_widths[0])
                .show(ctx, |ui| {
                    // Both ways: content wider than the panel (a row that
                    // cannot wrap in a narrow window) scrolls instead of
                    // widening the panel over the canvas.
                    egui::ScrollArea::both().show(ui, |ui| {
                        let doc = &self.document.doc;
                        let run = RunState {
                            animating: self.background.animating.is_some(),
                            busy,
                            can_undo: self.document.history.can_undo(),
                            can_redo: self.document.history.can_redo(),
                        };
                        let mut out = Vec::new();
                        out.extend(self.panels.step.ui(ui, doc, run));
                        ui.separator();
                        // The section of what the tool bar does comes
                        // first, in view without scrolling: the boundary
                        // (or the drawing) with an editing tool, else the
                        // correction and training.
                        let editing = self.panels.tools.tool != Tool::Correct;
                        let figures = Figures {
                            busy,
                            ..figures_of(&self.document, &self.view)
                        };
                        if doc.regions.is_some() {
                            out.extend(self.panels.tools.drawing_ui(ui, doc));
                        } else if editing {
                            out.extend(self.panels.tools.ui(ui, doc, ()));
                        } else {
                            out.extend(self.panels.train.ui(ui, doc, figures));
                        }
                        ui.separator();
                        export_box(ui, &mut self.panels.export_path, doc, &mut out);
                        ui.separator();
                        if doc.regions.is_some() {
                            out.extend(self.panels.regions.ui(ui, doc, ()));
                        } else {
                            let figures = Figures {
                                busy,
                                ..figures_of(&self.document, &self.view)
                            };
                            if editing {
                                out.extend(self.panels.train.ui(ui, doc, figures));
                            } else {
                                out.extend(self.panels.tools.ui(ui, doc, ()));
                            }
                            ui.separator();
                            if ui
                                .add_enabled(
                                    doc.boundary().is_some(),
                                    egui::Button::new("Regions and groups…"),
                                )
                                .on_hover_text("Make this boundary a document of regions: split it into regions with interface curves, name boundary groups and regions (the steps taken are dropped)")
                                .on_disabled_hover_text("Needs a valid boundary")
                                .clicked()
                            {
                                out.push(Command::ToRegions);
                            }
                        }
                        cmds.extend(out);
                    });
                });
            self.panels.widths[0] = chosen_panel_width(
                self.panels.widths[0],
                shown.response.rect.width(),
                max_widths[0],
            );
        }
        if self.panels.show_right {
            let threads = self.background.threads;
            let id = egui::Id::new("panels");
            restore_panel_width(ctx, id, self.panels.widths[1], max_widths[1]);
            let shown = egui::SidePanel::right(id)
                .resizable(true)
                .default_width(self.panels.widths[1])
                .min_width(PANEL_MIN_WIDTHS[1])
                .max_width(max_widths[1])
                .show(ctx, |ui| {
                    ui.horizontal_wrapped(|ui| {
                        for t in Tab::ALL {
                            ui.selectable_value(&mut self.panels.tab, t, t.name())
                                .on_hover_text(t.hint());
                        }
                    });
                    ui.separator();
                    egui::ScrollArea::both()
                        .id_salt("right_panel")
                        .show(ui, |ui| {
                            let doc = &self.document.doc;
                            let figures = figures_of(&self.document, &self.view);
                            let b = &self.background;
                            let compare_state = CompareState {
                                comparison: b.comparison.as_ref(),
                                comparing: b.compare.as_ref().map(|j| (j.done(), j.total)),
                            };
                            let p = &mut self.panels;
                            let out = match p.tab {
                                Tab::Quality => p.quality.ui(ui, doc, figures),
                                Tab::Model => p.model.ui(ui, doc, threads),
                                Tab::Samples => p.samples.ui(ui, doc, figures.kind),
                                Tab::Smoothing => p.smooth.ui(ui, doc, figures),
                                Tab::Compare => p.compare.ui(ui, doc, compare_state),
                            };
                            cmds.extend(out);
                        });
                });
            self.panels.widths[1] = chosen_panel_width(
                self.panels.widths[1],
                shown.response.rect.width(),
                max_widths[1],
            );
        }
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ctx, |ui| {
                egui::Frame::side_top_panel(ui.style()).show(ui, |ui| {
                    ui.set_width(ui.available_width());
                    let kind = self.shown().kind;
                    let targets = targets_of(&self.document, &self.view);
                    let doc = &self.document.doc;
                    if doc.regions.is_some() {
                        self.panels.regions.toolbar(ui);
                    } else {
                        cmds.extend(self.panels.tools.toolbar(ui, doc, kind, targets));
                    }
                });
                self.canvas(ui, &mut cmds);
            });
        self.questions(ctx, &mut cmds);
        for c in cmds {
            self.apply(c);
        }
        self.animate(ctx);
        if busy || self.finishing() || self.comparing() {
            ctx.request_repaint_after(std::time::Duration::from_millis(50));
        }
        self.screenshot_step(ctx);
    }

    /// The canvas: the document drawn, the tool's gestures, pan and zoom.
    pub(super) fn canvas(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        let (resp, painter) =
            ui.allocate_painter(ui.available_size(), egui::Sense::click_and_drag());
        let rect = resp.rect;
        let kind = self.shown().kind;
        let targets: Vec<Target> = self.targets().to_vec();
        let ViewState {
            canvas: view,
            canvas_rect,
            domain,
            mesh: mesh_cache,
            stats,
            finished,
            preview,
            front,
            hover,
            empty,
            before_last,
            ..
        } = &mut self.view;
        *canvas_rect = rect;
        let d = &self.document;
        let doc = &d.doc;
        let bbox = match &doc.regions {
            Some(r) => Aabb::of(r.graph.points.iter().copied()),
            None => Aabb::of(doc.draft.loops.iter().flatten().copied()),
        };
        view.update(rect, bbox, || {
            doc.regions
                .as_ref()
                .map_or(egui::Vec2::ZERO, super::regions_panel::legend_room)
        });
        let pointer = canvas::Pointer::of(&resp, ui).in_view(view);
        if let Some(r) = &doc.regions {
            // Shift-click adds to the picked segments (the release's own
            // modifiers count too).
            let shift = ui.input(|i| {
                i.modifiers.shift
                    || i.events.iter().any(|e| {
                        matches!(e, egui::Event::PointerButton { modifiers, .. } if modifiers.shift)
                    })
            });
            self.panels.regions.input(r, view, &pointer, shift, cmds);
        }
        let taken = doc.regions.is_none() && {
            let at = tools::OnCanvas {
                view,
                pointer: &pointer,
                doc,
                targets: &targets,
                kind,
                drag: None,
            };
            self.panels.tools.input(&at, cmds)
        };
        canvas::pan_zoom(view, &resp, ui, taken);
        // While Pn is dragged: how good the element would be, checked on
        // the mesher before the last step (as the targets are).
        let drag = self.panels.tools.pn_drag().and_then(|pn| {
            let reference = doc.last_element()?.reference?;
            let (k, before) = before_last.as_mut()?;
            (*k == d.mesh_version).then(|| {
                before
                    .check_correction(&crate::extract::Correction {
                        reference,
                        element_type: crate::model::ElementType::New,
                        pn: Some(pn),
                        snap_to: None,
                    })
                    .ok()
            })
        });
        let pointer = pointer.in_view(view);
        *hover = pointer.world.filter(|_| pointer.hovered);
        // The front of the mesh as stepped, by mesh version.
        let v = d.mesh_version;
        if front.0 != v {
            let loops = doc
                .mesher()
                .map(|m| {
                    let f = m.front();
                    f.live_loops().map(|l| f.loop_nodes(l)).collect()
                })
                .unwrap_or_default();
            *front = (v, loops);
        }
        let shown = shown_of(d, finished, empty);
        let stepped = shown.kind == MeshKind::Stepped;
        let domain = match doc.boundary() {
            Some(b) => domain.of(b),
            None => &[],
        };
        let overlay = canvas::Overlay {
            version: (v * 8 + shown.kind as u64) ^ ((shown.mesh as *const QuadMesh as u64) << 20),
            boundary: doc.boundary(),
            domain,
            mesh: shown.mesh,
            qualities: &stats.per_quad,
            front: if stepped { &front.1 } else { &[] },
            // The finished mesh is renumbered: the last step's node ids
            // belong to the mesh as stepped.
            last: if stepped && doc.regions.is_none() {
                doc.last()
            } else {
                None
            },
            // A document of regions is coloured by region unless asked.
            metric: if doc.regions.is_none() || self.panels.regions.plain_quality {
                self.panels.quality.metric
            } else {
                None
            },
        };
        let hovered_quad = canvas::draw(ui, &painter, view, mesh_cache, &overlay, &pointer);
        if let Some(metric) = overlay.metric.filter(|_| !shown.mesh.quads.is_empty()) {
            canvas::legend(&painter, rect, metric);
        }
        if let Some((_, quads)) = preview {
            let cyan = egui::Color32::from_rgb(80, 220, 255);
            for q in quads.iter() {
                let mut ring: Vec<egui::Pos2> =
                    q.iter().map(|&p| view.to_screen(rect, p)).collect();
                ring.push(ring[0]);
                painter.extend(egui::Shape::dashed_line(
                    &ring,
                    egui::Stroke::new(2.0, cyan),
                    6.0,
                    4.0,
                ));
            }
        }
        if let Some(r) = &doc.regions {
            if !self.panels.regions.plain_quality || shown.mesh.quads.is_empty() {
                self.panels.regions.draw(ui, &painter, view, r, *hover);
            }
        }
        if let Some(dr) = &doc.drawing {
            canvas::draw_curves(&painter, view, rect, &dr.geometry);
        }
        let at = tools::OnCanvas {
            view,
            pointer: &pointer,
            doc,
            targets: &targets,
            kind,
            drag,
        };
        self.panels.tools.draw(ui, &painter, &at);
        if doc.draft.loops.is_empty()
            && doc.regions.is_none()
            && self.panels.tools.drawing.is_empty()
        {
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "Nothing drawn yet: with the \"draw loop\" tool, click to place nodes",
                egui::FontId::proportional(16.0),
                ui.visuals().weak_text_color(),
            );
        }
        // (Not in a screenshot: the pointer is wherever the display left it.)
        if let (Some(k), None, None) = (
            hovered_quad,
            self.panels.tools.hover,
            &self.window.screenshot,
        ) {
            canvas::quad_hover(ui, &resp, k, &stats.per_quad);
        }
    }

    pub(super) fn status_bar(&mut self, ui: &mut egui::Ui, cmds: &mut Vec<Command>) {
        ui.horizontal(|ui| {
            if let Some(f) = &self.background.refit {
                ui.spinner();
                ui.label(format!("refit: {}", f.phase()));
                let secs = f.started.elapsed().as_secs_f64();
                cancel_button(ui, secs, "Stop (Esc): the refit is dropped, the model stays as before it", cmds);
            }
            if let Some(j) = &self.background.job {
                let (steps, front, frac) = j.progress();
                match j.phase() {
                    None if j.is_run() => {
                        ui.add(
                            egui::ProgressBar::new(frac)
                                .desired_width(120.0)
                                .show_percentage(),
                        )
                        .on_hover_text("The share of the domain's area meshed so far");
                        ui.label(format!(
                            "{}: extraction, {}, {} left",
                            j.what,
                            plural(steps, "step"),
                            plural(front, "front node")
                        ));
                    }
                    // Extraction is over: the part of finishing going on
                    // (the share meshed would stand at 100 % meanwhile).
                    phase => {
                        ui.spinner();
                        let what = if j.is_run() {
                            format!("{}: {} taken; finishing", j.what, plural(steps, "step"))
                        } else {
                            "finishing".into()
                        };
                        ui.label(format!(
                            "{what}: {}",
                            phase.map_or("starting", crate::pipeline::FinishPhase::name)
                        ))
                        .on_hover_text("Finishing the mesh: cleanup and smoothing, coarsening, remeshing bad regions, smoothing, checking");
                    }
                }
                cancel_button(
                    ui,
                    j.elapsed(),
                    "Stop (Esc): a run is dropped, the mesh stays as before it",
                    cmds,
                );
            }
            if let Some(r) = &self.background.region_run {
                use std::sync::atomic::Ordering;
                ui.spinner();
                ui.label(format!(
                    "meshing the regions: face {} of {}, {}",
                    (r.face.load(Ordering::Relaxed) + 1).min(r.faces),
                    r.faces,
                    plural(r.steps.load(Ordering::Relaxed), "step")
                ));
                cancel_button(
                    ui,
                    r.started.elapsed().as_secs_f64(),
                    "Stop (Esc): the run is dropped, the mesh stays as before it",
                    cmds,
                );
            }
            if let Some(p) = self.view.hover {
                ui.monospace(format!("x {:.4}  y {:.4}", p.x, p.y));
                ui.separator();
            }
            ui.label(&self.window.status);
        });
    }
}

/// The seconds a background job has taken and its Cancel button, in the
/// status bar.
pub(super) fn cancel_button(ui: &mut egui::Ui, secs: f64, tip: &str, cmds: &mut Vec<Command>) {
    ui.label(format!("{secs:.1} s"));
    if ui.button("Cancel").on_hover_text(tip).clicked() {
        cmds.push(Command::Cancel);
    }
    ui.separator();
}

/// The export box of the left panel: a path (beside the document's file
/// by default) and the buttons.
pub(super) fn export_box(
    ui: &mut egui::Ui,
    path: &mut String,
    doc: &Document,
    out: &mut Vec<Command>,
) {
    ui.label(egui::RichText::new("Export").strong());
    let done = doc.has_mesh();
    ui.add(
        egui::TextEdit::singleline(path)
            .desired_width(f32::INFINITY)
            .hint_text("a path, or Export… to choose one"),
    )
    .on_hover_text("The file to write; its extension picks the format");
    ui.label(egui::RichText::new(".msh .msh22 .vtk .vtu .inp .svg").weak());
    ui.horizontal(|ui| {
        let named = !path.trim().is_empty();
        if ui
            .add_enabled(done && named, egui::Button::new("Export mesh"))
            .on_hover_text("Write the finished mesh to the path above")
            .on_disabled_hover_text(if done {
                "Type a path above, or choose one with Export…"
            } else {
                "Run the mesh to the end first"
            })
            .clicked()
        {
            out.push(Command::Export(PathBuf::from(path.trim())));
        }
        if ui
            .add_enabled(done, egui::Button::new("Export…"))
            .on_hover_text("Choose where to write the finished mesh")
            .on_disabled_hover_text("Run the mesh to the end first")
            .clicked()
        {
            out.push(Command::Dialog(Dialog::ExportMesh));
        }
    });
}

//! The Regions panel and canvas tools of a document of several regions:
//! the regions (colour, tag, faces, and once meshed their quality) and
//! the named groups; picking segments to name a group, picking a face to
//! name its region, drawing an interface curve that splits a region. The
//! canvas shows the graph's segments (groups highlighted and labelled by
//! name) over the faces tinted by region, with a legend.

use super::canvas::{Pointer, View};
use super::command::Command;
use super::regions::{group_color, groups_of, region_color, Regions};
use super::tools::PICK;
use super::Document;
use crate::geom::{point_segment_distance, Point};
use egui::{Color32, Pos2, Rect, Shape, Stroke, Ui};

/// What a primary click on the canvas does in a document of regions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RegionTool {
    /// Click a segment to pick it (shift-click adds), or inside a face to
    /// pick the face.
    #[default]
    Pick,
    /// Click a node, then points of the curve, then another node: the
    /// curve becomes an interface between two regions.
    Interface,
}

impl RegionTool {
    pub const ALL: [RegionTool; 2] = [RegionTool::Pick, RegionTool::Interface];

    pub fn name(self) -> &'static str {
        match self {
            RegionTool::Pick => "pick",
            RegionTool::Interface => "interface",
        }
    }

    pub fn hint(self) -> &'static str {
        match self {
            RegionTool::Pick => "Click a segment to pick it (shift-click adds more), or inside a face to pick it; then name the group or the region in the Regions panel.",
            RegionTool::Interface => "Click a node to start the curve, click to place its bends, click another node to end it: the curve splits the region in two (divided like the segments around it, the node counts kept even). Right-click or Esc drops it.",
        }
    }
}

/// The panel's and the tools' state.
#[derive(Default)]
pub struct RegionsPanel {
    pub tool: RegionTool,
    /// Picked segments (indices into the graph's segments).
    pub picked: Vec<usize>,
    /// The picked face, by a point inside it.
    pub face: Option<Point>,
    /// The interface being drawn: its first node and its bends.
    pub curve: Option<(usize, Vec<Point>)>,
    /// The name and tag (0: automatic) given to the picked segments.
    pub group_name: String,
    pub group_tag: i64,
    /// The name and tag (0: automatic) given to the picked face's region.
    pub region_name: String,
    pub region_tag: i64,
    /// Tint the mesh by region (else it is coloured by the quality metric).
    pub plain_quality: bool,
    /// The graph the picks belong to (another graph drops them).
    picked_for: Option<crate::pslg::Pslg>,
}

/// The width of the canvas's key to the regions and groups (`groups`:
/// [`groups_of`] the graph), drawn at its top left.
fn legend_width(r: &Regions, groups: &[(i64, String, Vec<usize>)]) -> f32 {
    r.legend
        .iter()
        .map(|(_, n)| n.len())
        .chain(groups.iter().map(|(_, n, _)| n.len()))
        .max()
        .unwrap_or(0) as f32
        * 8.0
        + 40.0
}

/// The room the key takes at the canvas's top left: its width and
/// height with the margins either side (none without regions or groups
/// to list).
pub fn legend_room(r: &Regions) -> egui::Vec2 {
    let groups = groups_of(&r.graph);
    let rows = r.legend.len() + groups.len();
    if rows == 0 {
        return egui::Vec2::ZERO;
    }
    egui::vec2(legend_width(r, &groups), LEGEND_ROW * rows as f32)
        + egui::Vec2::splat(2.0 * LEGEND_MARGIN)
}

/// The height of a row of the key.
const LEGEND_ROW: f32 = 20.0;

/// The key's distance from the canvas's left edge, and the clear room a
/// fit leaves right of it.
const LEGEND_MARGIN: f32 = 10.0;

/// The node of the graph within [`PICK`] pixels of `s`, the nearest.
fn node_near(r: &Regions, view: &View, rect: Rect, s: Pos2) -> Option<usize> {
    r.graph
        .points
        .iter()
        .enumerate()
        .map(|(k, &p)| (k, view.to_screen(rect, p).distance(s)))
        .filter(|(_, d)| *d <= PICK)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(k, _)| k)
}

/// The segment within [`PICK`] pixels of `s`, the nearest.
fn segment_near(r: &Regions, view: &View, rect: Rect, s: Pos2) -> Option<usize> {
    let w = view.to_world(rect, s);
    let g = &r.graph;
    g.segments
        .iter()
        .enumerate()
        .map(|(k, seg)| {
            let d = point_segment_distance(w, g.points[seg.a], g.points[seg.b]);
            (k, d * view.zoom)
        })
        .filter(|(_, d)| *d <= PICK as f64)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(k, _)| k)
}

impl RegionsPanel {
    /// Drops picks and a curve drawn on another graph.
    pub fn sync(&mut self, r: &Regions) {
        if self.picked_for.as_ref() != Some(&r.graph) {
            self.picked.clear();
            self.face = None;
            self.curve = None;
            self.picked_for = Some(r.graph.clone());
        }
    }

    /// Drops the curve being drawn; false when there is none.
    pub fn drop_curve(&mut self) -> bool {
        self.curve.take().is_some()
    }

    /// A click on the canvas (`shift`: add to the picked segments).
    pub fn input(
        &mut self,
        r: &Regions,
        view: &View,
        p: &Pointer,
        shift: bool,
        out: &mut Vec<Command>,
    ) {
        if p.secondary_clicked {
            self.curve = None;
        }
        let Some(s) = p.clicked else { return };
        let rect = p.rect;
        match self.tool {
            RegionTool::Pick => {
                if let Some(k) = segment_near(r, view, rect, s) {
                    if shift {
                        if let Some(i) = self.picked.iter().position(|&x| x == k) {
                            self.picked.remove(i);
                        } else {
                            self.picked.push(k);
                        }
                    } else {
                        self.picked = vec![k];
                    }
                    let m = r.graph.segments[k].marker;
                    if m != 0 {
                        self.group_name = r.graph.group_name(m);
                    }
                    self.face = None;
                    return;
                }
                let w = view.to_world(rect, s);
                self.face = r.face_at(w).map(|f| {
                    let a = r.faces[f].attribute;
                    if a != 0 {
                        self.region_name = r.graph.region_name(a);
                    }
                    w
                });
                if !shift {
                    self.picked.clear();
                }
            }
            RegionTool::Interface => {
                let node = node_near(r, view, rect, s);
                match (&mut self.curve, node) {
                    (None, Some(n)) => self.curve = Some((n, Vec::new())),
                    (None, None) => {}
                    (Some((from, bends)), Some(to)) => {
                        out.push(Command::SplitRegion {
                            from: *from,
                            through: std::mem::take(bends),
                            to,
                        });
                        self.curve = None;
                    }
                    (Some((_, bends)), None) => bends.push(view.to_world(rect, s)),
                }
            }
        }
    }

    /// The tool row above the canvas.
    pub fn toolbar(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            ui.label(egui::RichText::new("Tool").strong());
            for t in RegionTool::ALL {
                ui.selectable_value(&mut self.tool, t, t.name())
                    .on_hover_text(t.hint());
            }
            ui.separator();
            let note = match (&self.curve, self.tool) {
                (Some((_, bends)), _) => format!(
                    "Interface: {} placed; click a node to end the curve (Esc drops it)",
                    super::plural(bends.len(), "bend")
                ),
                (None, RegionTool::Interface) => {
                    "Interface: click a node of the graph to start the curve".into()
                }
                (None, RegionTool::Pick) => {
                    "Pick: click a segment (shift-click adds) or inside a face".into()
                }
            };
            ui.add(egui::Label::new(egui::RichText::new(note).weak()).truncate());
        });
    }

    /// Draws the graph over the mesh: the faces tinted by region, the
    /// segments (groups highlighted and labelled), the picks, the curve
    /// being drawn and the legend.
    pub fn draw(
        &self,
        ui: &Ui,
        painter: &egui::Painter,
        view: &View,
        r: &Regions,
        hover: Option<Point>,
    ) {
        let rect = painter.clip_rect();
        let to = |p: Point| view.to_screen(rect, p);
        // Faces: a light tint once meshed (the mesh shows through).
        let meshed = !r.shown_mesh().quads.is_empty();
        let alpha = if meshed { 100 } else { 120 };
        let mut fill = egui::epaint::Mesh::default();
        for (k, tris) in r.tints.iter().enumerate() {
            let c = region_color(r.face_region[k]);
            let c = Color32::from_rgba_unmultiplied(c.r(), c.g(), c.b(), alpha);
            for t in tris {
                let base = fill.vertices.len() as u32;
                for &p in t {
                    fill.colored_vertex(to(p), c);
                }
                fill.add_triangle(base, base + 1, base + 2);
            }
        }
        painter.add(Shape::mesh(fill));
        if let Some(f) = self.face.and_then(|p| r.face_at(p)) {
            let mut fill = egui::epaint::Mesh::default();
            let c = Color32::from_rgba_unmultiplied(255, 255, 255, 60);
            for t in &r.tints[f] {
                let base = fill.vertices.len() as u32;
                for &p in t {
                    fill.colored_vertex(to(p), c);
                }
                fill.add_triangle(base, base + 1, base + 2);
            }
            painter.add(Shape::mesh(fill));
        }
        // Segments.
        let g = &r.graph;
        let groups = groups_of(g);
        let plain = ui.visuals().text_color().gamma_multiply(0.8);
        let bad = r.problem.is_some();
        for s in &g.segments {
            if s.marker == 0 {
                let c = if bad {
                    Color32::from_rgb(255, 120, 80)
                } else {
                    plain
                };
                painter.line_segment([to(g.points[s.a]), to(g.points[s.b])], Stroke::new(1.5, c));
            }
        }
        for (gi, (_, name, segs)) in groups.iter().enumerate() {
            let c = group_color(gi);
            for &k in segs {
                let s = g.segments[k];
                painter.line_segment([to(g.points[s.a]), to(g.points[s.b])], Stroke::new(3.5, c));
            }
            // The name beside the group's middle segment.
            let s = g.segments[segs[segs.len() / 2]];
            let mid = to((g.points[s.a] + g.points[s.b]) * 0.5);
            painter.text(
                mid + egui::vec2(6.0, -6.0),
                egui::Align2::LEFT_BOTTOM,
                name,
                egui::FontId::proportional(14.0),
                c,
            );
        }
        for &k in &self.picked {
            if let Some(s) = g.segments.get(k) {
                painter.line_segment(
                    [to(g.points[s.a]), to(g.points[s.b])],
                    Stroke::new(5.0, Color32::WHITE),
                );
            }
        }
        if let Some((from, bends)) = &self.curve {
            let mut pts: Vec<Pos2> = std::iter::once(g.points[*from])
                .chain(bends.iter().copied())
                .map(to)
                .collect();
            if let Some(h) = hover {
                pts.push(to(h));
            }
            let cyan = Color32::from_rgb(80, 220, 255);
            painter.add(Shape::line(pts.clone(), Stroke::new(2.0, cyan)));
            for p in pts {
                painter.circle_filled(p, 3.5, cyan);
            }
        }
        // The legend, top left.
        let mut y = rect.top() + LEGEND_MARGIN;
        let x = rect.left() + LEGEND_MARGIN;
        let font = egui::FontId::proportional(14.0);
        let w = legend_width(r, &groups);
        let rows = r.legend.len() + groups.len();
        if rows > 0 {
            painter.rect_filled(
                Rect::from_min_size(
                    Pos2::new(x - 4.0, y - 4.0),
                    egui::vec2(w, LEGEND_ROW * rows as f32 + 8.0),
                ),
                4.0,
                ui.visuals().extreme_bg_color.gamma_multiply(0.85),
            );
        }
        for (k, (_, name)) in r.legend.iter().enumerate() {
            painter.rect_filled(
                Rect::from_min_size(Pos2::new(x, y + 2.0), egui::vec2(14.0, 14.0)),
                2.0,
                region_color(k),
            );
            painter.text(
                Pos2::new(x + 22.0, y),
                egui::Align2::LEFT_TOP,
                name,
                font.clone(),
                ui.visuals().text_color(),
            );
            y += LEGEND_ROW;
        }
        for (gi, (_, name, _)) in groups.iter().enumerate() {
            painter.line_segment(
                [Pos2::new(x, y + 9.0), Pos2::new(x + 14.0, y + 9.0)],
                Stroke::new(3.5, group_color(gi)),
            );
            painter.text(
                Pos2::new(x + 22.0, y),
                egui::Align2::LEFT_TOP,
                name,
                font.clone(),
                ui.visuals().text_color(),
            );
            y += LEGEND_ROW;
        }
    }
}

impl super::View for RegionsPanel {
    type Input<'a> = ();

    fn ui(&mut self, ui: &mut Ui, doc: &Document, _: ()) -> Vec<Command> {
        let mut out = Vec::new();
        let Some(r) = &doc.regions else {
            return out;
        };
        ui.heading("Regions");
        if let Some(e) = &r.problem {
            ui.colored_label(
                Color32::from_rgb(255, 140, 90),
                format!("not a valid graph yet: {e}"),
            );
        }
        let quality = r.mesh.as_ref();
        // Scrolled sideways in a narrow panel, so no column is cut off.
        egui::ScrollArea::horizontal()
            .id_salt("regions_table_scroll")
            .show(ui, |ui| {
                egui::Grid::new("regions_table")
                    .striped(true)
                    .show(ui, |ui| {
                        ui.label("");
                        ui.label("region");
                        ui.label("tag");
                        ui.label("faces");
                        if quality.is_some() {
                            ui.label("quads");
                            ui.label("SJ min");
                            ui.label("SJ mean");
                        }
                        ui.end_row();
                        for (k, (tag, name)) in r.legend.iter().enumerate() {
                            let (rect, _) = ui
                                .allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
                            ui.painter().rect_filled(rect, 2.0, region_color(k));
                            ui.label(name);
                            ui.label(tag.to_string());
                            ui.label(
                                r.face_region
                                    .iter()
                                    .filter(|&&f| f == k)
                                    .count()
                                    .to_string(),
                            );
                            if let Some(m) = quality {
                                if let Some(q) = m.regions.get(k).map(|x| &x.quality) {
                                    ui.label(q.quads.to_string());
                                    ui.label(format!("{:.3}", q.sj_min));
                                    ui.label(format!("{:.3}", q.sj_mean));
                                }
                            }
                            ui.end_row();
                        }
                    });
            });
        let groups = groups_of(&r.graph);
        ui.label(egui::RichText::new("Groups").strong());
        if groups.is_empty() {
            ui.label(egui::RichText::new("none: pick segments and name them below").weak());
        }
        for (gi, (tag, name, segs)) in groups.iter().enumerate() {
            ui.horizontal(|ui| {
                let (rect, _) =
                    ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
                ui.painter().line_segment(
                    [rect.left_center(), rect.right_center()],
                    Stroke::new(3.5, group_color(gi)),
                );
                ui.label(format!(
                    "{name} (tag {tag}): {}",
                    super::plural(segs.len(), "segment")
                ));
            });
        }
        ui.separator();
        ui.label(egui::RichText::new("Name a group").strong());
        ui.label(format!(
            "{} picked",
            super::plural(self.picked.len(), "segment")
        ));
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut self.group_name)
                    .hint_text("group name")
                    .desired_width(120.0),
            )
            .on_hover_text(
                "The group's name (an empty name takes the segments out of their groups)",
            );
            ui.add(
                egui::DragValue::new(&mut self.group_tag)
                    .range(0..=1_000_000)
                    .prefix("tag "),
            )
            .on_hover_text("The physical tag (0: the group's own, or a new one)");
        });
        if ui
            .add_enabled(!self.picked.is_empty(), egui::Button::new("Name group"))
            .on_hover_text("Put the picked segments in this group")
            .on_disabled_hover_text("Pick segments first (pick tool: click, shift-click)")
            .clicked()
        {
            out.push(Command::NameGroup {
                segments: self.picked.clone(),
                name: self.group_name.clone(),
                tag: self.group_tag,
            });
        }
        ui.separator();
        ui.label(egui::RichText::new("Name a region").strong());
        let face = self.face.and_then(|p| r.face_at(p));
        ui.label(match face {
            Some(f) => format!(
                "face {} of {} picked (region {})",
                f + 1,
                r.faces.len(),
                r.legend[r.face_region[f]].1
            ),
            None => "no face picked: click inside one".into(),
        });
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut self.region_name)
                    .hint_text("region name")
                    .desired_width(120.0),
            );
            ui.add(
                egui::DragValue::new(&mut self.region_tag)
                    .range(0..=1_000_000)
                    .prefix("tag "),
            )
            .on_hover_text("The physical tag (0: the region's own, or a new one)");
        });
        if ui
            .add_enabled(face.is_some(), egui::Button::new("Name region"))
            .on_hover_text("Put the picked face in this region (adds or moves its region point)")
            .on_disabled_hover_text("Pick a face first (pick tool: click inside it)")
            .clicked()
        {
            if let Some(at) = self.face {
                out.push(Command::NameRegion {
                    at,
                    name: self.region_name.clone(),
                    tag: self.region_tag,
                });
            }
        }
        ui.separator();
        ui.checkbox(
            &mut self.plain_quality,
            "colour the mesh by quality, not by region",
        );
        ui.label(
            egui::RichText::new(
                "Names are kept in project files and in a boundary saved as .json (a regions document); a .poly keeps the tags only.",
            )
            .weak(),
        );
        out
    }
}

//! The Quality panel: the figures of the mesh on the canvas (method §5, the
//! fields `judge.py` reports), histograms of the minimum angle and of the
//! scaled Jacobian, and the metric the canvas colours quads by.

use super::command::Command;
use super::{Document, Figures, MeshKind};
use crate::mesh::QuadMesh;
use crate::quality::{MeshQuality, QuadQuality};
use egui::Ui;
use egui_plot::{Bar, BarChart, Plot};
use serde::{Deserialize, Serialize};

/// A per-quad figure the canvas can colour by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Metric {
    ScaledJacobian,
    MinAngle,
    MaxAngle,
    Aspect,
    Taper,
}

impl Metric {
    pub const ALL: [Metric; 5] = [
        Metric::ScaledJacobian,
        Metric::MinAngle,
        Metric::MaxAngle,
        Metric::Aspect,
        Metric::Taper,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Metric::ScaledJacobian => "scaled Jacobian",
            Metric::MinAngle => "minimum angle",
            Metric::MaxAngle => "maximum angle",
            Metric::Aspect => "aspect ratio",
            Metric::Taper => "taper",
        }
    }

    /// The figure itself.
    pub fn value(self, q: &QuadQuality) -> f64 {
        match self {
            Metric::ScaledJacobian => q.scaled_jacobian,
            Metric::MinAngle => q.min_angle(),
            Metric::MaxAngle => q.max_angle(),
            Metric::Aspect => q.aspect,
            Metric::Taper => q.taper,
        }
    }

    /// The figure whose [`Metric::score`] is `score` (in `(0, 1]`), as the
    /// colour legend labels it.
    pub fn label_at(self, score: f64) -> String {
        match self {
            Metric::ScaledJacobian => format!("{score:.2}"),
            Metric::MinAngle => format!("{:.0}°", 90.0 * score),
            Metric::MaxAngle => format!("{:.0}°", 180.0 - 90.0 * score),
            Metric::Aspect | Metric::Taper => format!("{:.1}", 1.0 / score.max(1e-9)),
        }
    }

    /// The figure on a 0 (bad) to 1 (ideal) scale, for the colour.
    pub fn score(self, q: &QuadQuality) -> f64 {
        let v = self.value(q);
        match self {
            Metric::ScaledJacobian => v,
            Metric::MinAngle => v / 90.0,
            Metric::MaxAngle => (180.0 - v) / 90.0,
            Metric::Aspect | Metric::Taper => 1.0 / v.max(1.0),
        }
    }
}

/// The histograms: range and bins of the minimum angle, then of the
/// scaled Jacobian.
const MIN_ANGLE_BINS: (f64, f64, usize) = (0.0, 90.0, 18);
const SJ_BINS: (f64, f64, usize) = (0.0, 1.0, 20);

/// Figures of the mesh on the canvas, recomputed when it changes.
#[derive(Default)]
pub struct MeshStats {
    key: Option<u64>,
    pub per_quad: Vec<QuadQuality>,
    pub summary: MeshQuality,
    /// Histogram counts over [`MIN_ANGLE_BINS`] and [`SJ_BINS`].
    min_angle_counts: Vec<usize>,
    sj_counts: Vec<usize>,
}

impl MeshStats {
    /// Recomputes for `mesh` unless `key` (the mesh version) is the same;
    /// `open` are the nodes of the front of a mesh still being made
    /// ([`MeshQuality::of_open`]).
    pub fn refresh(&mut self, key: u64, mesh: &QuadMesh, open: &[u32]) {
        if self.key == Some(key) {
            return;
        }
        self.key = Some(key);
        self.per_quad = mesh
            .quads
            .iter()
            .map(|q| QuadQuality::of(mesh.corners(q)))
            .collect();
        self.summary = MeshQuality::of_open(mesh, open);
        let counts = |f: fn(&QuadQuality) -> f64, (lo, hi, bins): (f64, f64, usize)| {
            let v: Vec<f64> = self.per_quad.iter().map(f).collect();
            bin_counts(&v, lo, hi, bins)
        };
        self.min_angle_counts = counts(QuadQuality::min_angle, MIN_ANGLE_BINS);
        self.sj_counts = counts(|q| q.scaled_jacobian, SJ_BINS);
    }
}

/// The panel's own state: the colouring.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct QualityPanel {
    /// The canvas colours quads by this (plain when `None`).
    pub metric: Option<Metric>,
}

impl Default for QualityPanel {
    fn default() -> Self {
        QualityPanel {
            metric: Some(Metric::ScaledJacobian),
        }
    }
}

impl super::View for QualityPanel {
    type Input<'a> = Figures<'a>;

    fn ui(&mut self, ui: &mut Ui, doc: &Document, s: Figures<'_>) -> Vec<Command> {
        let stats = s.stats;
        let q = &stats.summary;
        let stepped = doc.mesher().map_or(0, |m| m.mesh().quads.len());
        let (what, note) = match s.kind {
            MeshKind::Imported => ("The mesh read from the file", String::new()),
            MeshKind::Finished if doc.regions.is_some() => (
                "The mesh of every region (each face finished as it was meshed; the Regions panel has each region's figures)",
                String::new(),
            ),
            MeshKind::Finished => (
                "The finished mesh (cleaned up, coarsened, remeshed and smoothed)",
                format!(
                    "; the mesh as stepped has {}",
                    super::plural(stepped, "quad")
                ),
            ),
            MeshKind::Updating => (
                "The finished mesh of the previous settings, being updated",
                format!(
                    "; the mesh as stepped has {}",
                    super::plural(stepped, "quad")
                ),
            ),
            MeshKind::Stepped => (
                "The mesh as stepped (not smoothed; run to the end for the finished mesh)",
                String::new(),
            ),
        };
        ui.label(format!("{what}: {}{note}.", super::plural(q.quads, "quad")));
        ui.horizontal_wrapped(|ui| {
            ui.label("colour quads by");
            egui::ComboBox::from_id_salt("colour_quads_by")
                .selected_text(self.metric.map_or("nothing", Metric::name))
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.metric, None, "nothing");
                    for m in Metric::ALL {
                        ui.selectable_value(&mut self.metric, Some(m), m.name());
                    }
                })
                .response
                .on_hover_text("The figure the canvas colours quads by (red bad, green good)");
        });
        ui.label("Quads that miss the thesis criteria (angles in [45°, 135°], aspect and taper ≤ 10) are tinted and outlined dashed.");
        if q.quads == 0 {
            ui.label("No quads yet.");
            return Vec::new();
        }
        egui::Grid::new("quality_summary")
            .num_columns(2)
            .striped(true)
            .show(ui, |ui| {
                // (figure, value, what it is: hover the figure's name)
                let rows: [(&str, String, &str); 12] = [
                    ("quads", crate::compare::grouped(q.quads), "Quads in the finished mesh"),
                    ("nodes", crate::compare::grouped(q.nodes), "Nodes in the finished mesh"),
                    (
                        "scaled Jacobian min",
                        format!("{:.3}", q.sj_min),
                        "The sine of a quad's worst corner angle, with its sign: 1 for right angles, 0 for a flat corner, below 0 for a reflex one",
                    ),
                    (
                        "scaled Jacobian mean",
                        format!("{:.3}", q.sj_mean),
                        "The mean over the quads of their scaled Jacobian",
                    ),
                    ("smallest angle", format!("{:.1}°", q.min_angle), "The smallest corner angle of any quad"),
                    ("largest angle", format!("{:.1}°", q.max_angle), "The largest corner angle of any quad"),
                    (
                        "angles in [45°, 135°]",
                        super::missing(q.frac_angles_45_135, q.quads, "outside"),
                        "The quads with an angle outside 45° to 135°, of all",
                    ),
                    (
                        "thesis criteria missed",
                        super::missing(q.frac_thesis_good, q.quads, "quads"),
                        "The quads that miss an angle in [45°, 135°] or aspect or taper at most 10 (thesis §1.2), of all",
                    ),
                    (
                        "Rs below 0.8",
                        super::missing(q.frac_rs_ge_0_8, q.quads, "quads"),
                        "The quads whose area over the square of their mean edge length is below 0.8 (1 for a square), of all",
                    ),
                    (
                        "aspect max",
                        format!("{:.2}", q.aspect_max),
                        "Aspect ratio: the larger ratio of a quad's opposite edges (1 for a parallelogram, 4 for a trapezoid with one parallel side 4 times the other)",
                    ),
                    (
                        "taper max",
                        format!("{:.2}", q.taper_max),
                        "Taper (the thesis's sense): the largest ratio of a quad's adjacent edges (1 for a square, 4 for a 1 × 4 rectangle)",
                    ),
                    (
                        "irregular interior nodes",
                        format!(
                            "{} of {}",
                            crate::compare::grouped(q.irregular_interior),
                            crate::compare::grouped(q.interior_nodes)
                        ),
                        "Interior nodes with other than four quads round them",
                    ),
                ];
                for (name, v, tip) in rows {
                    ui.label(name).on_hover_text(tip);
                    ui.monospace(v);
                    ui.end_row();
                }
            });
        ui.label("Minimum angle of each quad");
        histogram(
            ui,
            "hist_min_angle",
            &stats.min_angle_counts,
            MIN_ANGLE_BINS,
            [5.0, 15.0, 30.0],
            |x| format!("{x:.0}°"),
        );
        ui.label("Scaled Jacobian of each quad");
        histogram(
            ui,
            "hist_sj",
            &stats.sj_counts,
            SJ_BINS,
            [0.05, 0.25, 0.5],
            |x| format!("{}", (100.0 * x).round() / 100.0),
        );
        Vec::new()
    }
}

/// Counts of `values` in `bins` equal bins over `lo..hi` (values outside
/// go to the end bins).
pub fn bin_counts(values: &[f64], lo: f64, hi: f64, bins: usize) -> Vec<usize> {
    let mut c = vec![0; bins];
    let w = (hi - lo) / bins as f64;
    for &v in values {
        let k = ((v - lo) / w).floor().clamp(0.0, (bins - 1) as f64) as usize;
        c[k] += 1;
    }
    c
}

/// A histogram of `counts` over the bins, with grid lines along x at the
/// three `steps` (the coarser ones labelled by `label`).
fn histogram(
    ui: &mut Ui,
    id: &str,
    counts: &[usize],
    (lo, hi, bins): (f64, f64, usize),
    steps: [f64; 3],
    label: fn(f64) -> String,
) {
    let w = (hi - lo) / bins as f64;
    let top = counts.iter().copied().max().unwrap_or(0) as f64;
    let bars: Vec<Bar> = counts
        .iter()
        .copied()
        .enumerate()
        .map(|(k, n)| {
            let x = lo + (k as f64 + 0.5) * w;
            Bar::new(x, n as f64)
                .width(w * 0.95)
                .fill(super::canvas::quality_color((x - lo) / (hi - lo)))
        })
        .collect();
    Plot::new(id)
        .height(140.0)
        .allow_scroll(false)
        .allow_zoom(false)
        .allow_drag(false)
        .allow_boxed_zoom(false)
        .include_x(lo)
        .include_x(hi)
        .include_y(0.0)
        .x_grid_spacer(egui_plot::uniform_grid_spacer(move |_| steps))
        // Counts labelled at a round step that gives two or three lines
        // (the default spacing can leave only the 0 labelled).
        .y_grid_spacer(egui_plot::uniform_grid_spacer(move |_| {
            let s = count_step(top);
            [s / 10.0, s / 2.0, s]
        }))
        .x_axis_formatter(move |m, _| label(m.value))
        // Whole counts only (a step of 1 has lines at 0.1 and 0.5 too).
        .y_axis_formatter(|m, _| {
            if (m.value - m.value.round()).abs() < 1e-9 {
                format!("{}", m.value.round() as i64)
            } else {
                String::new()
            }
        })
        .y_axis_label("quads")
        // The pointer's own coordinates would read as fractional counts;
        // a bar says its count and its bin.
        .label_formatter(|_, _| String::new())
        .show(ui, |p| {
            p.bar_chart(
                BarChart::new("quads", bars).element_formatter(Box::new(move |bar, _| {
                    let half = 0.5 * w;
                    format!(
                        "{} from {} to {}",
                        super::plural(bar.value.round() as usize, "quad"),
                        label(bar.argument - half),
                        label(bar.argument + half)
                    )
                })),
            )
        });
}

/// A round step (1, 2 or 5 times a power of ten, at least 1) that divides
/// `0..=top` into two to five parts.
fn count_step(top: f64) -> f64 {
    let raw = (top / 2.5).max(1.0);
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn count_steps_are_round_and_few() {
        for (top, step) in [
            (0.0, 1.0),
            (3.0, 2.0),
            (80.0, 50.0),
            (150.0, 100.0),
            (1234.0, 500.0),
        ] {
            assert_eq!(count_step(top), step, "{top}");
            assert!(
                top / step <= 5.0 && (top < 2.0 || top / step >= 1.0),
                "{top}"
            );
        }
    }

    #[test]
    fn bins_hold_every_value() {
        let c = bin_counts(&[0.0, 0.05, 0.5, 1.0, 1.5, -1.0], 0.0, 1.0, 10);
        assert_eq!(c.iter().sum::<usize>(), 6);
        assert_eq!(c[0], 3);
        assert_eq!(c[5], 1);
        assert_eq!(c[9], 2);
    }

    #[test]
    fn scores_run_from_bad_to_ideal() {
        let square = QuadQuality::of([
            crate::Point::new(0.0, 0.0),
            crate::Point::new(1.0, 0.0),
            crate::Point::new(1.0, 1.0),
            crate::Point::new(0.0, 1.0),
        ]);
        for m in Metric::ALL {
            assert!((m.score(&square) - 1.0).abs() < 1e-9, "{}", m.name());
        }
    }
}

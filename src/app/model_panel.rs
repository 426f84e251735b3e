//! The Model panel: how well the model the mesher uses fits the training
//! samples (thesis §4.3: the figures of Table 8; the plots of Tables 5–8,
//! each output against the sample index beside the sample's own, and
//! predicted against actual), and the critical factors of the samples
//! (thesis §4.2, Figures 34–37: the weight of each leading point).

use super::command::Command;
use super::document::{refit_set_of, Document};
use crate::factors::{factors, Factors, CRITICAL_PERCENT};
use crate::fit::{evaluate_all, Evaluation, Figures};
use egui::{Color32, Ui};
use egui_plot::{Bar, BarChart, HLine, Legend, Line, Plot, PlotPoints, Points};

/// Which samples the model is measured on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SampleChoice {
    /// The reference meshes' samples and the user's (what a refit fits).
    All,
    /// The user's samples only.
    Yours,
}

/// The output a plot shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    Type,
    Xn,
    Yn,
}

impl Output {
    const ALL: [Output; 3] = [Output::Type, Output::Xn, Output::Yn];

    fn name(self) -> &'static str {
        match self {
            Output::Type => "type",
            Output::Xn => "Xn",
            Output::Yn => "Yn",
        }
    }

    /// Actual and predicted value of sample `i`.
    fn values(self, e: &Evaluation, i: usize) -> (f64, f64) {
        match self {
            Output::Type => (e.types[i] as f64, e.predicted_types[i] as f64),
            Output::Xn => (e.pn[i].x, e.predicted_pn[i].x),
            Output::Yn => (e.pn[i].y, e.predicted_pn[i].y),
        }
    }
}

/// Figures of one model on one set of samples.
pub struct ModelFit {
    pub model: String,
    pub evaluation: Evaluation,
    pub factors: Option<Factors>,
}

/// The panel's state: what to show and the figures computed for it.
pub struct ModelPanel {
    pub samples: SampleChoice,
    pub output: Output,
    /// First sample of the index plot and how many it shows.
    pub window_start: usize,
    pub window_len: usize,
    key: Option<(usize, usize, usize, SampleChoice)>,
    /// The model measured when the document has no mesher (no valid
    /// boundary), loaded once per model name: the key above tells models
    /// apart by address, and a model loaded afresh every frame would start
    /// a measurement every frame.
    loaded: Option<(String, std::sync::Arc<dyn crate::model::Model>)>,
    fit: Option<Result<ModelFit, String>>,
    /// The figures being measured in a thread (seconds on the reference
    /// samples), and the model's name.
    measuring: Option<(std::thread::JoinHandle<Result<ModelFit, String>>, String)>,
    /// Where the plots were drawn last (screen points).
    pub plot_rects: Vec<egui::Rect>,
}

impl Default for ModelPanel {
    fn default() -> Self {
        ModelPanel {
            samples: SampleChoice::All,
            output: Output::Xn,
            window_start: 0,
            window_len: 150,
            key: None,
            loaded: None,
            fit: None,
            measuring: None,
            plot_rects: Vec::new(),
        }
    }
}

/// Points drawn at most in a scatter plot (every k-th sample beyond).
const MAX_SCATTER: usize = 4000;

impl ModelPanel {
    /// The figures of the document's model, measured again when the model
    /// or the samples change: in a thread when `threads` (the panel shows a
    /// spinner meanwhile), else at once.
    pub fn refresh(&mut self, doc: &Document, threads: bool) -> Option<&ModelFit> {
        let spec = &doc.settings.model;
        let model = match (doc.mesher(), &self.loaded) {
            (Some(m), _) => m.model().clone(),
            (None, Some((name, m))) if name == spec => m.clone(),
            (None, _) => match super::document::load_model(spec, &doc.models) {
                Ok((m, _)) => {
                    self.loaded = Some((spec.clone(), m.clone()));
                    m
                }
                Err(e) => {
                    self.fit = Some(Err(e.to_string()));
                    return None;
                }
            },
        };
        let key = (
            std::sync::Arc::as_ptr(&model) as *const () as usize,
            doc.training.len(),
            doc.training.points,
            self.samples,
        );
        if self.key != Some(key) {
            self.key = Some(key);
            let (training, choice) = (doc.training.clone(), self.samples);
            let name = model.name().to_string();
            let measure = move || {
                let set = match choice {
                    SampleChoice::All => refit_set_of(training).map_err(|e| e.to_string())?,
                    SampleChoice::Yours => training,
                };
                let evaluation = evaluate_all(model.as_ref(), &set).map_err(|e| e.to_string())?;
                Ok(ModelFit {
                    model: model.name().to_string(),
                    evaluation,
                    factors: factors(&set).ok(),
                })
            };
            self.fit = None;
            // A measurement of figures no longer asked for is left to end
            // on its own.
            self.measuring = None;
            if threads {
                self.measuring = Some((std::thread::spawn(measure), name));
            } else {
                self.fit = Some(measure());
            }
        }
        if self
            .measuring
            .as_ref()
            .is_some_and(|(h, _)| h.is_finished())
        {
            if let Some((h, _)) = self.measuring.take() {
                self.fit = Some(
                    h.join()
                        .unwrap_or_else(|_| Err("the measurement failed".to_string())),
                );
            }
        }
        self.fit.as_ref().and_then(|f| f.as_ref().ok())
    }

    /// True while the figures are being measured in a thread.
    pub fn measuring(&self) -> bool {
        self.measuring.is_some()
    }
}

impl super::View for ModelPanel {
    /// Whether the figures are measured in a thread.
    type Input<'a> = bool;

    fn ui(&mut self, ui: &mut Ui, doc: &Document, threads: bool) -> Vec<Command> {
        self.plot_rects.clear();
        ui.horizontal(|ui| {
            ui.label("measured on");
            ui.selectable_value(&mut self.samples, SampleChoice::All, "reference + yours")
                .on_hover_text("The reference meshes' samples and yours: what a refit fits");
            ui.selectable_value(&mut self.samples, SampleChoice::Yours, "yours")
                .on_hover_text("Only the samples of your corrections and collections");
        });
        self.refresh(doc, threads);
        if let Some((_, name)) = &self.measuring {
            ui.horizontal(|ui| {
                ui.spinner();
                ui.label(format!("measuring {name} on the samples…"));
            });
            ui.ctx().request_repaint();
        }
        let fit = match &self.fit {
            Some(Ok(f)) => f,
            Some(Err(e)) => {
                ui.colored_label(Color32::LIGHT_RED, format!("cannot measure: {e}"));
                return Vec::new();
            }
            None => return Vec::new(),
        };
        let e = &fit.evaluation;
        if e.types.is_empty() {
            ui.label("No samples to measure on: correct or append elements first.");
            return Vec::new();
        }
        ui.label(format!(
            "{} on {}",
            fit.model,
            super::plural(e.types.len(), "sample")
        ));
        fit_table(ui, e);
        ui.horizontal(|ui| {
            ui.label("output");
            for o in Output::ALL {
                ui.selectable_value(&mut self.output, o, o.name());
            }
        });
        let n = e.types.len();
        ui.horizontal(|ui| {
            ui.label("samples from");
            ui.add(egui::DragValue::new(&mut self.window_start).range(0..=n.saturating_sub(1)))
                .on_hover_text("The first sample the plot below shows");
            ui.label("count");
            ui.add(egui::DragValue::new(&mut self.window_len).range(10..=5000))
                .on_hover_text("How many samples it shows");
        });
        let r = index_plot(self.output, self.window_start, self.window_len, ui, e);
        self.plot_rects.push(r);
        let r = scatter_plot(self.output, ui, e);
        self.plot_rects.push(r);
        if let Some(f) = &fit.factors {
            let r = factor_plot(ui, f);
            self.plot_rects.push(r);
        }
        Vec::new()
    }
}

/// The output against the sample index, the sample's own and the
/// model's (thesis Tables 5–8). Plots pan with a drag and zoom with
/// Ctrl+wheel; the wheel alone scrolls the panel.
fn index_plot(
    output: Output,
    window_start: usize,
    window_len: usize,
    ui: &mut Ui,
    e: &Evaluation,
) -> egui::Rect {
    let n = e.types.len();
    let start = window_start.min(n.saturating_sub(1));
    let end = (start + window_len).min(n);
    let (mut actual, mut predicted) = (Vec::new(), Vec::new());
    for i in start..end {
        let (a, p) = output.values(e, i);
        actual.push([i as f64, a]);
        predicted.push([i as f64, p]);
    }
    ui.label(format!("{} by sample", output.name()));
    Plot::new("fit_index")
        .height(170.0)
        .legend(Legend::default())
        .allow_scroll(false)
        .x_axis_label("sample")
        .show(ui, |p| {
            p.points(
                Points::new("samples", PlotPoints::from(actual))
                    .radius(2.5)
                    .color(Color32::from_rgb(90, 160, 255)),
            );
            p.line(
                Line::new("model", PlotPoints::from(predicted))
                    .color(Color32::from_rgb(255, 150, 60)),
            );
        })
        .response
        .rect
}

/// Predicted against actual, with the line of a perfect fit.
fn scatter_plot(output: Output, ui: &mut Ui, e: &Evaluation) -> egui::Rect {
    let n = e.types.len();
    let stride = n.div_ceil(MAX_SCATTER).max(1);
    let pts: Vec<[f64; 2]> = (0..n)
        .step_by(stride)
        .map(|i| {
            let (a, p) = output.values(e, i);
            [a, p]
        })
        .collect();
    let (lo, hi) = pts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
            (l.min(p[0]).min(p[1]), h.max(p[0]).max(p[1]))
        });
    ui.label(format!(
        "{}: model against samples{}",
        output.name(),
        if stride > 1 {
            format!(" (every {} sample)", super::ordinal(stride))
        } else {
            String::new()
        }
    ));
    Plot::new("fit_scatter")
        .height(200.0)
        .data_aspect(1.0)
        .allow_scroll(false)
        .x_axis_label("sample")
        .y_axis_label("model")
        .show(ui, |p| {
            if lo.is_finite() && hi.is_finite() {
                p.line(
                    Line::new("perfect fit", PlotPoints::from(vec![[lo, lo], [hi, hi]]))
                        .color(Color32::GRAY),
                );
            }
            p.points(
                Points::new("samples", PlotPoints::from(pts))
                    .radius(1.5)
                    .color(Color32::from_rgb(90, 200, 140)),
            );
        })
        .response
        .rect
}

/// The fit figures (thesis Table 8) and the type's confusion matrix.
fn fit_table(ui: &mut Ui, e: &Evaluation) {
    let (t, x, y) = &e.figures;
    egui::Grid::new("fit_table")
        .num_columns(6)
        .striped(true)
        .show(ui, |ui| {
            for h in ["output", "n", "SSE", "RMSE", "R", "DC"] {
                ui.strong(h);
            }
            ui.end_row();
            let row = |ui: &mut Ui, name: &str, f: &Figures| {
                ui.label(name);
                ui.monospace(f.n.to_string());
                for v in [f.sse, f.rmse, f.r, f.dc] {
                    ui.monospace(super::figure(v, 4));
                }
                ui.end_row();
            };
            row(ui, "type", &t.figures);
            row(ui, "Xn", x);
            row(ui, "Yn", y);
        });
    ui.label(format!("type accuracy {:.2} %", 100.0 * t.accuracy));
    egui::Grid::new("confusion").num_columns(4).show(ui, |ui| {
        ui.label("actual \\ model");
        for k in 0..3 {
            ui.strong(format!("type {k}"));
        }
        ui.end_row();
        for (a, row) in t.confusion.iter().enumerate() {
            ui.strong(format!("type {a}"));
            for c in row {
                ui.monospace(c.to_string());
            }
            ui.end_row();
        }
    });
}

/// The weight of each leading point per output, in percent, with the 5 %
/// line under which a point is not critical (thesis Figures 34–37).
fn factor_plot(ui: &mut Ui, f: &Factors) -> egui::Rect {
    ui.label(format!(
        "Critical factors ({} input points, {}): outermost pair {}",
        f.points,
        super::plural(f.samples, "sample"),
        if f.outermost_negligible() {
            "under 5 % (not critical)"
        } else {
            "critical"
        }
    ));
    let colors = [
        Color32::from_rgb(230, 120, 80),
        Color32::from_rgb(90, 160, 255),
        Color32::from_rgb(120, 210, 120),
    ];
    let names = f.names.clone();
    Plot::new("factors")
        .height(170.0)
        .legend(Legend::default())
        .allow_scroll(false)
        .allow_zoom(false)
        .allow_drag(false)
        .y_axis_label("weight %")
        .x_axis_formatter(move |m, _| {
            let k = m.value.round();
            if (m.value - k).abs() < 1e-6 && k >= 0.0 && (k as usize) < names.len() {
                names[k as usize].clone()
            } else {
                String::new()
            }
        })
        .show(ui, |p| {
            for (j, (name, v)) in [("type", &f.type_), ("Xn", &f.xn), ("Yn", &f.yn)]
                .into_iter()
                .enumerate()
            {
                let bars = v
                    .iter()
                    .enumerate()
                    .map(|(i, &w)| Bar::new(i as f64 + (j as f64 - 1.0) * 0.27, w).width(0.25))
                    .collect();
                p.bar_chart(BarChart::new(name, bars).color(colors[j]));
            }
            p.hline(HLine::new("5 %", CRITICAL_PERCENT).color(Color32::GRAY));
        })
        .response
        .rect
}

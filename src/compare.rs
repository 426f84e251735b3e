//! One boundary meshed by several models, side by side (thesis Figure 44,
//! the comparison of extraction methods): whether each run finishes, and
//! the figures of its mesh. The editor uses the same figures to say
//! whether a refitted model meshes the boundary worse than the model
//! before it.

use crate::extract::size::SizeField;
use crate::extract::{Remedy, RunProgress, StepKind};
use crate::io::svg::{write_svg, SvgOptions};
use crate::mesh::QuadMesh;
use crate::model::Model;
use crate::pipeline::{mesh_boundary, Params};
use crate::quality::MeshQuality;
use crate::Boundary;
use serde::Serialize;
use std::fmt::Write as _;
use std::sync::Arc;

/// How one model meshed the boundary.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Outcome {
    /// The model's name as asked for.
    pub model: String,
    /// The run ended with a valid mesh.
    pub finished: bool,
    /// Why it did not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The region fill had to finish it.
    pub fill: bool,
    pub quads: usize,
    pub sj_min: f64,
    pub sj_mean: f64,
    /// Interior nodes whose valence is not 4, as a share of the interior
    /// nodes.
    pub irregular_share: f64,
    /// Element steps whose element the guard took as the model predicted
    /// it, as a share of the element steps.
    pub accepted_share: f64,
    /// Element steps that took the model's element with its Pn drawn
    /// towards the size field ([`Remedy::Rescaled`]), as a share.
    pub rescaled_share: f64,
    /// Element steps where the guard used another element (snapped, another
    /// type, a moved Pn, the rules), as a share.
    pub replaced_share: f64,
    /// Interior nodes whose valence is not 4.
    pub irregular: usize,
    /// The largest aspect ratio and taper of a quad.
    pub aspect_max: f64,
    pub taper_max: f64,
    /// About how many quads a mesh following the boundary's size field has
    /// ([`SizeField::quad_estimate`]).
    pub size_quads: f64,
    /// The finished mesh.
    #[serde(skip)]
    pub mesh: Option<QuadMesh>,
}

/// Meshes `boundary` with `model` (named `name`) and measures the result.
pub fn mesh_with(
    name: &str,
    boundary: &Boundary,
    model: Arc<dyn Model>,
    params: &Params,
) -> Outcome {
    mesh_with_progress(name, boundary, model, params, |_| {})
}

/// [`mesh_with`], `progress` called after every extraction step with how
/// far it has got.
pub fn mesh_with_progress(
    name: &str,
    boundary: &Boundary,
    model: Arc<dyn Model>,
    params: &Params,
    progress: impl FnMut(RunProgress),
) -> Outcome {
    let size_quads = SizeField::of_boundary(&boundary.to_local().0).quad_estimate();
    match mesh_boundary(boundary, model, params, progress) {
        Ok((mesh, stats)) => {
            let q = MeshQuality::of(&mesh);
            let elements = stats.count(StepKind::Element);
            let share = |n: usize| n as f64 / elements.max(1) as f64;
            let accepted = stats.remedies(Remedy::None);
            let rescaled = stats.remedies(Remedy::Rescaled);
            Outcome {
                model: name.into(),
                finished: true,
                error: None,
                fill: stats.count(StepKind::Fill) > 0,
                quads: q.quads,
                sj_min: q.sj_min,
                sj_mean: q.sj_mean,
                irregular_share: q.irregular_interior as f64 / q.interior_nodes.max(1) as f64,
                accepted_share: share(accepted),
                rescaled_share: share(rescaled),
                replaced_share: share(elements.saturating_sub(accepted + rescaled)),
                irregular: q.irregular_interior,
                aspect_max: q.aspect_max,
                taper_max: q.taper_max,
                size_quads,
                mesh: Some(mesh),
            }
        }
        Err(e) => Outcome {
            model: name.into(),
            finished: false,
            error: Some(e.to_string()),
            fill: false,
            quads: 0,
            sj_min: 0.0,
            sj_mean: 0.0,
            irregular_share: 0.0,
            accepted_share: 0.0,
            rescaled_share: 0.0,
            replaced_share: 0.0,
            irregular: 0,
            aspect_max: 0.0,
            taper_max: 0.0,
            size_quads,
            mesh: None,
        },
    }
}

/// How much worse a figure may get before it counts.
pub const WORSE_SJ_MEAN: f64 = 0.005;
pub const WORSE_SJ_MIN: f64 = 0.02;
pub const WORSE_IRREGULAR: f64 = 0.02;
/// Irregular nodes count as more when they grow by this factor (and by
/// [`WORSE_IRREGULAR_NODES`] nodes at least): a large mesh's share moves
/// little when its interior turns irregular.
pub const WORSE_IRREGULAR_RATIO: f64 = 1.15;
pub const WORSE_IRREGULAR_NODES: usize = 10;
/// How much further from the count the size field asks for the quad count
/// may move (as a share of that count) before it counts.
pub const WORSE_COUNT: f64 = 0.10;
/// The factor the largest taper or aspect ratio may grow by before it
/// counts.
pub const WORSE_SHAPE: f64 = 1.25;

impl Outcome {
    /// The ways this mesh is worse than `before`'s (empty: not worse):
    /// it does not finish where `before` did, needs the region fill where
    /// `before` did not, or its mean scaled Jacobian, minimum scaled
    /// Jacobian or irregular share is worse by more than
    /// [`WORSE_SJ_MEAN`], [`WORSE_SJ_MIN`], [`WORSE_IRREGULAR`]; its
    /// irregular nodes grow by [`WORSE_IRREGULAR_RATIO`]; its quad count
    /// moves further from the size field's by more than [`WORSE_COUNT`]
    /// of it; its largest taper or aspect ratio grows by [`WORSE_SHAPE`].
    pub fn worse_than(&self, before: &Outcome) -> Vec<String> {
        if !before.finished {
            return Vec::new();
        }
        if !self.finished {
            return vec!["does not finish".into()];
        }
        let mut why = Vec::new();
        if self.fill && !before.fill {
            why.push("needs the region fill".into());
        }
        if self.sj_mean < before.sj_mean - WORSE_SJ_MEAN {
            why.push(format!(
                "mean SJ from {:.3} to {:.3}",
                before.sj_mean, self.sj_mean
            ));
        }
        if self.sj_min < before.sj_min - WORSE_SJ_MIN {
            why.push(format!(
                "min SJ from {:.3} to {:.3}",
                before.sj_min, self.sj_min
            ));
        }
        if self.irregular_share > before.irregular_share + WORSE_IRREGULAR {
            why.push(format!(
                "irregular from {:.1} % to {:.1} %",
                100.0 * before.irregular_share,
                100.0 * self.irregular_share
            ));
        } else if self.irregular as f64 > before.irregular as f64 * WORSE_IRREGULAR_RATIO
            && self.irregular >= before.irregular + WORSE_IRREGULAR_NODES
        {
            why.push(format!(
                "irregular nodes from {} to {}",
                grouped(before.irregular),
                grouped(self.irregular)
            ));
        }
        if self.size_quads > 0.0 {
            let off = |o: &Outcome| (o.quads as f64 / self.size_quads - 1.0).abs();
            if off(self) > off(before) + WORSE_COUNT {
                why.push(format!(
                    "quads from {} to {} (the size field asks for about {})",
                    grouped(before.quads),
                    grouped(self.quads),
                    grouped(self.size_quads.round() as usize)
                ));
            }
        }
        for (name, b, a) in [
            ("max taper", before.taper_max, self.taper_max),
            ("max aspect", before.aspect_max, self.aspect_max),
        ] {
            if a > b * WORSE_SHAPE {
                why.push(format!("{name} from {b:.1} to {a:.1}"));
            }
        }
        why
    }

    /// The quad count against the count the size field asks for, as the
    /// editor's refit report shows it: "134,128 quads (size field about
    /// 190,000: 71 %)".
    pub fn count_line(&self) -> String {
        if self.size_quads > 0.0 {
            format!(
                "{} quads (size field about {}: {:.0} %)",
                grouped(self.quads),
                grouped(self.size_quads.round() as usize),
                100.0 * self.quads as f64 / self.size_quads
            )
        } else {
            format!("{} quads", grouped(self.quads))
        }
    }
}

/// The columns of the comparison after the model's name, as the table
/// and the editor's panel head them.
pub const COLUMNS: [&str; 8] = [
    "finished",
    "quads",
    "SJ min",
    "SJ mean",
    "irregular",
    "accepted",
    "rescaled",
    "replaced",
];

impl Outcome {
    /// `yes`, `fill` (finished with the region fill) or `no`.
    pub fn finished_label(&self) -> &'static str {
        match (self.finished, self.fill) {
            (false, _) => "no",
            (true, true) => "fill",
            (true, false) => "yes",
        }
    }

    /// The figures under [`COLUMNS`] after `finished` (quads, SJ min and
    /// mean, then the irregular, accepted, rescaled and replaced shares in
    /// per cent); none when the run did not finish.
    pub fn figures(&self) -> Option<[String; 7]> {
        let pc = |v: f64| format!("{:.1}%", 100.0 * v);
        self.finished.then(|| {
            [
                self.quads.to_string(),
                format!("{:.3}", self.sj_min),
                format!("{:.3}", self.sj_mean),
                pc(self.irregular_share),
                pc(self.accepted_share),
                pc(self.rescaled_share),
                pc(self.replaced_share),
            ]
        })
    }
}

/// The outcomes as a text table, one row per model.
pub fn table(outcomes: &[Outcome]) -> String {
    let widths = [9, 7, 7, 7, 10, 9, 9, 9];
    let mut s = format!("{:<16}", "model");
    for (c, w) in COLUMNS.iter().zip(widths) {
        let _ = write!(s, " {c:>w$}");
    }
    s.push('\n');
    for o in outcomes {
        let _ = write!(s, "{:<16} {:>9}", o.model, o.finished_label());
        match o.figures() {
            Some(f) => {
                for (v, w) in f.iter().zip(&widths[1..]) {
                    let _ = write!(s, " {v:>w$}");
                }
            }
            None => {
                let _ = write!(s, "  {}", o.error.as_deref().unwrap_or(""));
            }
        }
        s.push('\n');
    }
    s
}

/// One SVG with each finished mesh side by side (coloured by scaled
/// Jacobian), each titled with its model and figures; a run that did not
/// finish leaves its place with the reason.
pub fn svg(outcomes: &[Outcome], panel_width: f64) -> String {
    let title_h = 36.0;
    let gap = 12.0;
    let opt = SvgOptions {
        width: panel_width,
        ..SvgOptions::default()
    };
    let panels: Vec<String> = outcomes
        .iter()
        .map(|o| {
            o.mesh
                .as_ref()
                .map_or_else(String::new, |m| write_svg(m, &opt))
        })
        .collect();
    let height = panels
        .iter()
        .filter_map(|p| svg_height(p))
        .fold(panel_width * 0.5, f64::max);
    let total_w = outcomes.len() as f64 * (panel_width + gap) + gap;
    let total_h = height + title_h + 2.0 * gap;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{total_w:.0}\" height=\"{total_h:.0}\" viewBox=\"0 0 {total_w:.2} {total_h:.2}\">"
    );
    out.push_str("<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n");
    for (k, (o, panel)) in outcomes.iter().zip(&panels).enumerate() {
        let x = gap + k as f64 * (panel_width + gap);
        let line2 = if o.finished {
            format!(
                "{} quads, SJ {:.3} / {:.3}, {:.1} % irregular",
                o.quads,
                o.sj_min,
                o.sj_mean,
                100.0 * o.irregular_share
            )
        } else {
            "did not finish".to_string()
        };
        let _ = writeln!(
            out,
            "<text x=\"{:.1}\" y=\"{:.1}\" font-family=\"sans-serif\" font-size=\"14\">{}</text>\n<text x=\"{:.1}\" y=\"{:.1}\" font-family=\"sans-serif\" font-size=\"11\">{}</text>",
            x,
            gap + 12.0,
            escape(&o.model),
            x,
            gap + 28.0,
            escape(&line2)
        );
        if !panel.is_empty() {
            // The mesh's own picture, placed as a nested SVG.
            out.push_str(&panel.replacen(
                "<svg ",
                &format!("<svg x=\"{x:.1}\" y=\"{:.1}\" ", gap + title_h),
                1,
            ));
        }
    }
    out.push_str("</svg>\n");
    out
}

/// The height attribute of an SVG's opening tag.
fn svg_height(svg: &str) -> Option<f64> {
    let head = svg.lines().next()?;
    let at = head.find("height=\"")? + "height=\"".len();
    head[at..].split('"').next()?.parse().ok()
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// A count with thousands separated by commas: 198007 gives "198,007".
pub fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::RulesModel;

    fn square() -> Boundary {
        let mut pts = Vec::new();
        for k in 0..4 {
            pts.push(crate::Point::new(k as f64, 0.0));
        }
        for k in 0..4 {
            pts.push(crate::Point::new(4.0, k as f64));
        }
        for k in 0..4 {
            pts.push(crate::Point::new(4.0 - k as f64, 4.0));
        }
        for k in 0..4 {
            pts.push(crate::Point::new(0.0, 4.0 - k as f64));
        }
        Boundary::new(pts, vec![(0..16).collect()], None).unwrap()
    }

    /// The square meshed by the rules, element by element (a 4 × 4 square
    /// would otherwise close at once by a mapped grid).
    fn rules_on_square() -> Outcome {
        let params = Params {
            extract: crate::extract::MeshParams {
                mapped_rows: None,
                ..crate::extract::MeshParams::DEFAULT
            },
            ..Params::DEFAULT
        };
        mesh_with("rules", &square(), Arc::new(RulesModel::default()), &params)
    }

    #[test]
    fn a_square_meshed_by_the_rules_and_its_figures() {
        let o = rules_on_square();
        assert!(o.finished && !o.fill, "{o:?}");
        assert_eq!(o.quads, 16);
        assert!(o.sj_min > 0.99 && o.accepted_share > 0.5, "{o:?}");
        assert!(o.worse_than(&o).is_empty());
        let t = table(std::slice::from_ref(&o));
        assert!(
            t.lines().nth(1).is_some_and(|l| l.starts_with("rules")),
            "{t}"
        );
        let pic = svg(&[o.clone(), o.clone()], 300.0);
        assert_eq!(pic.matches("<svg ").count(), 3);
        assert!(pic.contains("16 quads"));
    }

    /// A mesh with another quad count than the size field asks for, a
    /// worse taper or aspect, or many more irregular nodes is worse, though
    /// its scaled Jacobians are the same (a large mesh coarsened by one
    /// correction kept its mean SJ).
    #[test]
    fn worse_counts_quads_against_the_size_field_taper_and_irregular_nodes() {
        let o = Outcome {
            quads: 198_007,
            size_quads: 190_000.0,
            irregular: 1657,
            irregular_share: 0.017,
            taper_max: 4.0,
            aspect_max: 3.0,
            ..rules_on_square()
        };
        let coarse = Outcome {
            quads: 134_128,
            irregular: 2144,
            irregular_share: 0.022,
            taper_max: 8.1,
            ..o.clone()
        };
        let why = coarse.worse_than(&o);
        assert_eq!(
            why,
            [
                "irregular nodes from 1,657 to 2,144",
                "quads from 198,007 to 134,128 (the size field asks for about 190,000)",
                "max taper from 4.0 to 8.1",
            ],
        );
        assert!(o
            .worse_than(&coarse)
            .iter()
            .all(|w| !w.starts_with("quads")));
        assert_eq!(
            coarse.count_line(),
            "134,128 quads (size field about 190,000: 71 %)"
        );
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1_000), "1,000");
        assert_eq!(grouped(1_234_567), "1,234,567");
    }

    #[test]
    fn worse_is_said_figure_by_figure() {
        let o = rules_on_square();
        let worse = Outcome {
            sj_mean: o.sj_mean - 0.1,
            fill: true,
            ..o.clone()
        };
        let why = worse.worse_than(&o);
        assert_eq!(why.len(), 2, "{why:?}");
        // Plain text: the editor's font has no arrows.
        assert!(why[1].starts_with("mean SJ from ") && why[1].contains(" to "));
        assert!(why.iter().all(|w| w.is_ascii()), "{why:?}");
        assert!(o.worse_than(&worse).is_empty());
        let failed = Outcome {
            finished: false,
            ..o.clone()
        };
        assert_eq!(failed.worse_than(&o), vec!["does not finish".to_string()]);
        assert!(o.worse_than(&failed).is_empty());
    }
}

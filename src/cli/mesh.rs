//! `quadex mesh`: a boundary, a drawing or a graph of regions meshed and
//! written in the format its output name asks for.

use super::args::{
    parse_layers, parse_mapped_rows, parse_points, parse_remesh_below, parse_size_at,
    parse_size_on, parse_transitions, Layers, MappedRows, Transitions,
};
use super::common::{check_output, load_model, plural, progress_bar, read_resampled};
use super::InputError;
use anyhow::{anyhow, Context, Result};
use clap::{Args, ValueEnum};
use quadex::extract::{MeshParams, StepKind, StepStats, Strategy, Tuning};
use quadex::finish::remesh::RemeshParams;
use quadex::io::{self, MeshFormat};
use quadex::model::Model;
use quadex::pipeline::{self, FinishParams};
use quadex::quality::MeshQuality;
use quadex::smooth::SmoothParams;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

#[derive(Clone, Copy, ValueEnum)]
enum StrategyArg {
    A,
    B,
}

#[derive(Serialize)]
struct Report<'a> {
    input: String,
    model: String,
    quality: MeshQuality,
    steps: &'a StepStats,
    seconds: f64,
}

#[derive(Args)]
pub(super) struct MeshArgs {
    input: PathBuf,
    #[arg(short, long)]
    output: PathBuf,
    /// `default` (the shipped fitted model), `rules`, `thesis` (Table 8
    /// as printed), `ann` (the shipped back-propagation network), or a
    /// model file (.json).
    #[arg(long, default_value = "default")]
    model: String,
    #[arg(long, value_enum, default_value = "b")]
    strategy: StrategyArg,
    /// Input points: 5, 7, 9 or 11 [default: the model's own, else 7].
    /// A model fitted on one count takes only that count.
    #[arg(long, value_parser = parse_points)]
    points: Option<usize>,
    /// Laplacian smoothing sweeps (0: no smoothing at all, neither
    /// Laplacian nor optimisation).
    #[arg(long, default_value_t = SmoothParams::DEFAULT.iterations)]
    smooth: usize,
    /// No topological cleanup (sliver and diagonal collapses, edge
    /// swaps) of the finished mesh.
    #[arg(long)]
    no_cleanup: bool,
    /// No chord coarsening (closed rows of quads lower than the size
    /// field asks are removed) of the finished mesh.
    #[arg(long)]
    no_coarsen: bool,
    /// Remesh the regions around quads whose scaled Jacobian is still
    /// below this after cleanup and smoothing (0: no remeshing).
    #[arg(long, default_value_t = RemeshParams::DEFAULT.below, value_parser = parse_remesh_below)]
    remesh_below: f64,
    /// Pure model: no remedies; a rejected prediction is counted and
    /// the step ladder's fallbacks (and the fill) finish the mesh.
    #[arg(long)]
    pure_model: bool,
    /// No region fill: a run extraction cannot finish stops with an error.
    #[arg(long)]
    no_fill: bool,
    /// `all` (the default): extraction to the end, the region fill only
    /// as the last resort; K: K layers extracted from the boundary, then
    /// the region left filled directly.
    #[arg(long, value_parser = parse_layers)]
    layers: Option<Layers>,
    /// Transition elements (3 to 1) where a row is this many times finer
    /// than the boundary's spacing asks for (`off`: none).
    #[arg(long, value_parser = parse_transitions)]
    transitions: Option<Transitions>,
    /// Loops that are logical rectangles (four corners, opposite sides
    /// of equal segment counts) at most N elements across are closed by a
    /// mapped grid (`off`: never) [default: 4]. Loops of the input graded
    /// past 1:10 get their transfinite grid too with the tuning
    /// {"mapped": {"graded_grid": true}}.
    #[arg(long, value_parser = parse_mapped_rows)]
    mapped_rows: Option<MappedRows>,
    /// Resample the boundary first: every segment cut into
    /// round(length / H) equal parts (at least one; the given nodes
    /// stay, one part more on the longest piece when the node count
    /// would be odd). Without it the file's nodes are the mesh's
    /// boundary nodes.
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    resample: Option<f64>,
    /// Write the quality figures and step counts as JSON.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Target size for a drawing (.dxf, or a geometry .json that gives
    /// none itself): every curve is cut at about this spacing (curved
    /// ones also into at least one segment per 15° of turning), the
    /// counts made even per region, and the interior meshed to it.
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    size: Option<f64>,
    /// A local size at a point of a drawing, X,Y,H (repeatable): the
    /// size there is H, growing at the gradation away from it.
    #[arg(long, value_name = "X,Y,H", value_parser = parse_size_at, allow_hyphen_values = true)]
    size_at: Vec<(f64, f64, f64)>,
    /// A local size on a drawing's layer, LAYER=H (repeatable): its
    /// curves are cut at H, and the size grows at the gradation away
    /// from them.
    #[arg(long, value_name = "LAYER=H", value_parser = parse_size_on)]
    size_on: Vec<(String, f64)>,
    /// How fast the size grows away from a finer local size or curve
    /// (size per unit length) [default: the file's, else 0.3].
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    gradation: Option<f64>,
    /// Element order: 1 (4-node quads) or 2 (9-node quads, their
    /// boundary midside nodes on a drawing's true curves; 8-node CPS8
    /// in .inp).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=2))]
    order: u8,
    /// With --order 2: 8-node (serendipity) quads in every format, the
    /// centre nodes left out.
    #[arg(long)]
    serendipity: bool,
    /// Threads (default: every core): the regions of a file with several
    /// are meshed side by side, the remeshing works out the regions of the
    /// next bad quads together, and the optimisation of a large mesh
    /// searches nodes that share no quad together. The mesh is the same
    /// whatever the count.
    #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
    threads: Option<u16>,
    /// The extraction engine's constants from a JSON file: any of the
    /// groups and fields of `extract::Tuning` (docs/engine.md), the rest
    /// left at their defaults, e.g. {"ladder": {"rip_ups": 16}}.
    #[arg(long, value_name = "FILE")]
    tuning: Option<PathBuf>,
}

pub(super) fn run(a: MeshArgs) -> Result<()> {
    let MeshArgs {
        input,
        output,
        model,
        strategy,
        points,
        smooth,
        no_cleanup,
        no_coarsen,
        remesh_below,
        pure_model,
        no_fill,
        layers,
        transitions,
        mapped_rows,
        resample,
        report,
        size,
        size_at,
        size_on,
        gradation,
        order,
        serendipity,
        threads,
        tuning,
    } = a;
    let fmt = MeshFormat::from_path(&output)
        .map_err(|e| InputError(anyhow!("{}: {e}", output.display())))?;
    check_output(&output)?;
    if let Some(r) = &report {
        check_output(r)?;
        if r == &output {
            return Err(InputError(anyhow!(
                "{}: the mesh and its --report would be the same file",
                r.display()
            ))
            .into());
        }
    }
    let at = |e: &dyn std::fmt::Display| InputError(anyhow!("{}: {e}", input.display()));
    let is_dxf = input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("dxf"));
    let is_geometry = is_dxf || quadex::cad::is_geometry_file(&input);
    if serendipity && order != 2 {
        return Err(InputError(anyhow!(
            "--serendipity asks for 8-node quads: add --order 2"
        ))
        .into());
    }
    if order == 2 && fmt == MeshFormat::Svg {
        return Err(InputError(anyhow!(
            "{}: an .svg draws the quads' corners only; --order 2 needs .msh, .msh22, .vtk, .vtu or .inp",
            output.display()
        ))
        .into());
    }
    let mut drawing = None;
    let graph = if is_geometry {
        let doc = if is_dxf {
            quadex::cad::CadDocument {
                geometry: quadex::cad::read_dxf(&input).map_err(|e| at(&e))?,
                ..Default::default()
            }
        } else {
            quadex::cad::read_geometry_json(&input).map_err(|e| at(&e))?
        };
        let points: Vec<quadex::cad::PointSize> = size_at
            .iter()
            .map(|&(x, y, h)| quadex::cad::PointSize {
                at: quadex::geom::Point::new(x, y),
                size: h,
            })
            .collect();
        let Some(spec) = doc.spec(size, gradation, &points, &size_on) else {
            return Err(at(&"a drawing needs a target size: add --size H").into());
        };
        let layers = doc.geometry.layers();
        if let Some((l, _)) = spec.layers.iter().find(|(l, _)| !layers.contains(l)) {
            return Err(at(&format!(
                "no curve is on layer {l:?} (the layers are {layers:?})"
            ))
            .into());
        }
        let d = doc.geometry.discretise_with(&spec).map_err(|e| at(&e))?;
        let graph = d.graph.clone();
        drawing = Some(d);
        Some(graph)
    } else {
        if size.is_some() || !size_at.is_empty() || !size_on.is_empty() || gradation.is_some() {
            return Err(at(
                &"--size, --size-at, --size-on and --gradation apply to drawings (.dxf, geometry .json); for boundary nodes use --resample H",
            )
            .into());
        }
        io::read_regions(&input).map_err(|e| at(&e))?
    };
    if graph.is_some() && resample.is_some() {
        return Err(InputError(anyhow!(
            "{}: --resample does not apply to a file with regions or boundary markers yet: place its nodes in the file",
            input.display()
        ))
        .into());
    }
    let boundary = match graph {
        Some(_) => None,
        None => Some(read_resampled(&input, resample)?),
    };
    let spec = model;
    let model = load_model(&spec)?;
    let own = model.leading_points().map(|n| 2 * n + 1);
    if let (Some(asked), Some(own)) = (points, own) {
        if asked != own {
            return Err(InputError(anyhow!(
                "{spec}: the model takes {own} input points, not the {asked} of --points"
            ))
            .into());
        }
    }
    let points = points.or(own).unwrap_or(7);
    let params = MeshParams {
        strategy: match strategy {
            StrategyArg::A => Strategy::A,
            StrategyArg::B => Strategy::B,
        },
        leading_points: (points - 1) / 2,
        pure_model,
        fill: !no_fill,
        fill_after_layers: layers.map_or(MeshParams::DEFAULT.fill_after_layers, |l| l.0),
        transition_ratio: transitions.map_or(MeshParams::DEFAULT.transition_ratio, |t| t.0),
        mapped_rows: mapped_rows.map_or(MeshParams::DEFAULT.mapped_rows, |m| m.0),
        size_target: drawing.as_ref().map(|d| d.size_target()),
        tuning: match &tuning {
            Some(path) => read_tuning(path)?,
            None => Tuning::DEFAULT,
        },
        ..MeshParams::DEFAULT
    };
    let finish = FinishParams::switched(smooth, !no_cleanup, !no_coarsen, remesh_below);
    let t0 = Instant::now();
    let name = model.name().to_string();
    let params = pipeline::Params {
        extract: params,
        finish,
    };
    let Some(boundary) = boundary else {
        let graph = graph.unwrap_or_default();
        return mesh_graph(MeshGraph {
            input: &input,
            output: &output,
            report: report.as_deref(),
            fmt,
            graph: &graph,
            model,
            params: &params,
            threads,
            order,
            serendipity,
            drawing: drawing.as_ref(),
            t0,
        });
    };
    let bar = progress_bar(boundary.node_count());
    let (mesh, stats) = thread_pool(threads)?
        .install(|| {
            pipeline::mesh_boundary(&boundary, model, &params, |at| {
                if let Some(b) = &bar {
                    b.set_message(format!(
                        "{:.0}% of the area, {} front nodes",
                        100.0 * at.meshed,
                        at.front
                    ));
                    b.tick();
                }
            })
        })
        .map_err(|e| match resample_hint(&boundary) {
            Some(hint) if resample.is_none() => anyhow!("{}: {e}; {hint}", input.display()),
            _ => anyhow!("{}: {e}", input.display()),
        })?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let seconds = t0.elapsed().as_secs_f64();
    let q = MeshQuality::of(&mesh);
    let rendered = if order == 2 {
        let single =
            quadex::regions::RegionMesh::single(mesh.clone(), stats.clone()).with_loop_groups();
        let mut o2 = quadex::order2::Order2::elevate(&single.mesh, &|_, _| None);
        if serendipity {
            o2 = o2.serendipity();
        }
        fmt.render_labelled(&single.labelled_with(Some(&o2)))
    } else {
        fmt.render(&mesh)
    };
    // The mesh and its report are written together or not at all.
    let report_json = match &report {
        Some(_) => Some(serde_json::to_string_pretty(&Report {
            input: input.display().to_string(),
            model: name,
            quality: q.clone(),
            steps: &stats,
            seconds,
        })?),
        None => None,
    };
    let mut files: Vec<(&Path, &[u8])> = vec![(&output, rendered.as_bytes())];
    if let (Some(path), Some(json)) = (&report, &report_json) {
        files.push((path, json.as_bytes()));
    }
    io::write_atomic_all(&files)?;
    let made_by = match stats.count(StepKind::Fill) {
        0 => format!(
            "{}{}",
            plural(stats.steps, "extraction step"),
            refanned(&stats)
        ),
        _ => format!(
            "{} and a region fill ({} of the {} quads before finishing)",
            plural(stats.steps - stats.count(StepKind::Fill), "extraction step"),
            stats.quads_made(StepKind::Fill),
            stats.standing
        ),
    };
    outln!(
        "{}: {} quads, sj min {:.3} mean {:.3}, {:.1}% in [45,135], taper max {:.2}, aspect max {:.2}, {} irregular of {} interior, {made_by}, {:.3} s",
        output.display(),
        q.quads,
        q.sj_min,
        q.sj_mean,
        100.0 * q.frac_angles_45_135,
        q.taper_max,
        q.aspect_max,
        q.irregular_interior,
        q.interior_nodes,
        seconds
    );
    if pure_model {
        let (ok, all) = stats.model_valid();
        outln!(
            "pure model: {ok} of {all} predictions valid ({:.1}%)",
            100.0 * ok as f64 / all.max(1) as f64
        );
    }
    Ok(())
}

/// What `quadex mesh` meshes a graph of regions with.
struct MeshGraph<'a> {
    input: &'a Path,
    output: &'a Path,
    report: Option<&'a Path>,
    fmt: MeshFormat,
    graph: &'a quadex::pslg::Pslg,
    model: Arc<dyn Model>,
    params: &'a pipeline::Params,
    threads: Option<u16>,
    order: u8,
    /// 8-node quads at second order.
    serendipity: bool,
    /// The drawing's curves, for midside nodes on them.
    drawing: Option<&'a quadex::cad::Discretised>,
    t0: Instant,
}

#[derive(Serialize)]
struct RegionsReport<'a> {
    input: String,
    model: String,
    quality: MeshQuality,
    regions: &'a [quadex::regions::Region],
    groups: Vec<GroupSummary<'a>>,
    faces: &'a [quadex::regions::FaceMesh],
    steps: StepStats,
    seconds: f64,
}

#[derive(Serialize)]
struct GroupSummary<'a> {
    tag: i64,
    name: &'a str,
    edges: usize,
}

/// A pool of `threads` threads (`None`: one per core).
fn thread_pool(threads: Option<u16>) -> Result<rayon::ThreadPool> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        pool = pool.num_threads(usize::from(n));
    }
    Ok(pool.build()?)
}

/// Meshes every region of a graph, writes the mesh with its groups (and
/// the report), and prints the quality overall and per region.
fn mesh_graph(a: MeshGraph) -> Result<()> {
    let at = |e: &dyn std::fmt::Display| InputError(anyhow!("{}: {e}", a.input.display()));
    let faces = a.graph.faces().map_err(|e| at(&e))?;
    let pool = thread_pool(a.threads)?;
    let bar = progress_bar(a.graph.points.len());
    let name = a.model.name().to_string();
    let m = pool
        .install(|| {
            quadex::regions::mesh_regions(a.graph, a.model, a.params, |done| {
                if let Some(b) = &bar {
                    b.set_message(format!("{done} of {} regions' faces meshed", faces.len()));
                    b.tick();
                }
            })
        })
        .with_context(|| format!("{}", a.input.display()))?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let seconds = a.t0.elapsed().as_secs_f64();
    let q = m.quality();
    let steps = m.steps();
    let (rendered, straightened) = if a.order == 2 {
        let nodes = &m.mesh.nodes;
        let curved = |u: u32, v: u32| {
            a.drawing
                .and_then(|d| d.midside(nodes[u as usize], nodes[v as usize]))
        };
        let mut o2 = quadex::order2::Order2::elevate(&m.mesh, &curved);
        if a.serendipity {
            o2 = o2.serendipity();
        }
        let text = a.fmt.render_labelled(&m.labelled_with(Some(&o2)));
        (text, o2.straightened)
    } else {
        (a.fmt.render_regions(&m), 0)
    };
    let report_json = match a.report {
        Some(_) => Some(serde_json::to_string_pretty(&RegionsReport {
            input: a.input.display().to_string(),
            model: name,
            quality: q.clone(),
            regions: &m.regions,
            groups: m
                .groups
                .iter()
                .map(|g| GroupSummary {
                    tag: g.tag,
                    name: &g.name,
                    edges: g.edges.len(),
                })
                .collect(),
            faces: &m.faces,
            steps: steps.clone(),
            seconds,
        })?),
        None => None,
    };
    let mut files: Vec<(&Path, &[u8])> = vec![(a.output, rendered.as_bytes())];
    if let (Some(path), Some(json)) = (a.report, &report_json) {
        files.push((path, json.as_bytes()));
    }
    io::write_atomic_all(&files)?;
    let fills = steps.count(StepKind::Fill);
    outln!(
        "{}: {} quads in {} ({}), {}, sj min {:.3} mean {:.3}, {:.1}% in [45,135], taper max {:.2}, aspect max {:.2}, {} irregular of {} interior, {}{}, {:.3} s",
        a.output.display(),
        q.quads,
        plural(m.regions.len(), "region"),
        plural(m.faces.len(), "face"),
        plural(m.groups.len(), "group"),
        q.sj_min,
        q.sj_mean,
        100.0 * q.frac_angles_45_135,
        q.taper_max,
        q.aspect_max,
        q.irregular_interior,
        q.interior_nodes,
        plural(steps.steps - fills, "extraction step"),
        match fills {
            0 => refanned(&steps).to_string(),
            1 => " and a region fill".to_string(),
            _ => format!(" and {fills} region fills"),
        },
        seconds
    );
    for r in &m.regions {
        let rq = &r.quality;
        outln!(
            "  region {} {:?}: {} quads, sj min {:.3} mean {:.3}, {} irregular of {} interior",
            r.tag,
            r.name,
            rq.quads,
            rq.sj_min,
            rq.sj_mean,
            rq.irregular_interior,
            rq.interior_nodes
        );
    }
    for g in &m.groups {
        outln!("  group {} {:?}: {} edges", g.tag, g.name, g.edges.len());
    }
    if a.order == 2 {
        outln!(
            "  {}-node quads; {straightened} curved quads straightened to keep the Jacobian positive",
            if a.serendipity { 8 } else { 9 }
        );
    }
    Ok(())
}

/// The engine's tuning from a JSON file; an unreadable file or an unknown
/// field is the user's error.
fn read_tuning(path: &Path) -> Result<Tuning> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError(anyhow!("{}: {e}", path.display())))?;
    let t: Tuning = serde_json::from_str(&text)
        .map_err(|e| InputError(anyhow!("{}: not a tuning file: {e}", path.display())))?;
    Ok(t)
}

/// Boundaries of more nodes than this get no [`resample_hint`] (its
/// search compares every node with every segment).
const HINT_MAX_NODES: usize = 5000;

/// When a run failed on a boundary whose longest segment is over four
/// times the domain's narrowest width (a node's distance to a segment two
/// or more segments away along its loop, or on another loop), the advice
/// to resample it to about that width: with the file's nodes kept, quads
/// there cannot be near square.
fn resample_hint(b: &quadex::Boundary) -> Option<String> {
    let n = b.node_count();
    if n > HINT_MAX_NODES {
        return None;
    }
    let segments: Vec<(usize, usize)> = b.segments().collect();
    let longest = segments
        .iter()
        .map(|&(i, j)| b.points[i].distance(b.points[j]))
        .fold(0.0, f64::max);
    // A segment is near node v when it ends at v or at one of v's
    // neighbours along the loop.
    let mut neighbours: Vec<Vec<usize>> = vec![Vec::new(); b.points.len()];
    for &(i, j) in &segments {
        neighbours[i].push(j);
        neighbours[j].push(i);
    }
    let mut narrowest = f64::INFINITY;
    for (v, &p) in b.points.iter().enumerate() {
        let near = |k: usize| k == v || neighbours[v].contains(&k);
        for &(i, j) in &segments {
            if near(i) || near(j) {
                continue;
            }
            let d = quadex::geom::point_segment_distance(p, b.points[i], b.points[j]);
            narrowest = narrowest.min(d);
        }
    }
    (narrowest.is_finite() && narrowest > 0.0 && longest > 4.0 * narrowest).then(|| {
        format!(
            "the boundary's segments are up to {longest:.3} long where the domain is {narrowest:.3} wide, \
             and its nodes are kept as given: `--resample {narrowest:.3}` adds nodes along them"
        )
    })
}

/// What the summary line says of a run made again with balanced corner
/// fans before its fill ([`quadex::extract::Rung::Refan`]).
fn refanned(stats: &StepStats) -> &'static str {
    if stats.refanned {
        " (made again with balanced corner fans, no fill)"
    } else {
        ""
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use quadex::geom::Point;

    fn loop_of(points: &[(f64, f64)]) -> quadex::Boundary {
        let p: Vec<Point> = points.iter().map(|&(x, y)| Point::new(x, y)).collect();
        let k = p.len();
        quadex::Boundary::new(p, vec![(0..k).collect()], None).unwrap()
    }

    #[test]
    fn a_channel_of_long_segments_gets_the_advice_to_resample() {
        // 40 long, 1 wide, two segments a side.
        let channel = loop_of(&[
            (0., 0.),
            (20., 0.),
            (40., 0.),
            (40., 1.),
            (20., 1.),
            (0., 1.),
        ]);
        let hint = resample_hint(&channel).unwrap();
        assert!(hint.contains("`--resample 1.000`"), "{hint}");
        assert!(hint.contains("up to 20.000 long"), "{hint}");
        // A square of unit segments is as wide as its segments are long.
        let mut square = Vec::new();
        for k in 0..4 {
            square.push((k as f64, 0.0));
        }
        for k in 0..4 {
            square.push((4.0, k as f64));
        }
        for k in 0..4 {
            square.push((4.0 - k as f64, 4.0));
        }
        for k in 0..4 {
            square.push((0.0, 4.0 - k as f64));
        }
        assert_eq!(resample_hint(&loop_of(&square)), None);
    }
}

//! The command line: `gui` (the default), `mesh`, `quality`, `samples`, `fit`, `predict`, `compare`, `factors`. Errors are reported once, here, as
//! one line naming the file and the problem; bad input exits with code 2.

use anyhow::{anyhow, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use quadex::boundary::Boundary;
use quadex::boundary_edit::Draft;
use quadex::compare;
use quadex::extract::{MeshParams, StepKind, StepStats, Strategy};
use quadex::factors;
use quadex::finish::cleanup::CleanupParams;
use quadex::finish::coarsen::CoarsenParams;
use quadex::finish::remesh::RemeshParams;
use quadex::fit::{self, FitParams};
use quadex::io::{self, MeshFormat};
use quadex::model::Form;
use quadex::model::{self, Model};
use quadex::pipeline::{self, FinishParams};
use quadex::predict;
use quadex::quality::MeshQuality;
use quadex::samples::{self, CollectParams, TrainingSet};
use quadex::smooth::SmoothParams;
use serde::Serialize;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "quadex",
    version,
    about = "All-quad 2D meshing by learned element extraction"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Clone, Copy, ValueEnum)]
enum StrategyArg {
    A,
    B,
}

#[derive(Subcommand)]
enum Command {
    /// Mesh a boundary (.poly or .json) and write the mesh; the format
    /// follows OUT's extension: .msh (4.1), .msh22, .vtk, .vtu, .inp, .svg.
    Mesh {
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
        /// of equal segment counts) at most N elements across are closed by
        /// a mapped grid (`off`: never) [default: 4].
        #[arg(long, value_parser = parse_mapped_rows)]
        mapped_rows: Option<MappedRows>,
        /// Resample the boundary first: every segment cut into
        /// round(length / H) equal parts (at least one; the given nodes
        /// stay, one part more on the longest piece when the node count
        /// would be odd). Without it the file's nodes are the mesh's
        /// boundary nodes.
        #[arg(long, value_name = "H")]
        resample: Option<f64>,
        /// Write the quality figures and step counts as JSON.
        #[arg(long)]
        report: Option<PathBuf>,
        /// Target size for a drawing (.dxf, or a geometry .json that gives
        /// none itself): every curve is cut at about this spacing (curved
        /// ones also into at least one segment per 15° of turning), the
        /// counts made even per region, and the interior meshed to it.
        #[arg(long, value_name = "H")]
        size: Option<f64>,
        /// A local size at a point of a drawing, X,Y,H (repeatable): the
        /// size there is H, growing at the gradation away from it.
        #[arg(long, value_name = "X,Y,H", value_parser = parse_size_at)]
        size_at: Vec<(f64, f64, f64)>,
        /// A local size on a drawing's layer, LAYER=H (repeatable): its
        /// curves are cut at H, and the size grows at the gradation away
        /// from them.
        #[arg(long, value_name = "LAYER=H", value_parser = parse_size_on)]
        size_on: Vec<(String, f64)>,
        /// How fast the size grows away from a finer local size or curve
        /// (size per unit length) [default: the file's, else 0.3].
        #[arg(long, value_name = "G")]
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
        /// Threads meshing the regions of a file with several (default:
        /// every core). The mesh is the same whatever the count.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
        threads: Option<u16>,
    },
    /// Quality figures of a mesh file (.msh); with --boundary, also checks
    /// that it meshes that boundary.
    Quality {
        mesh: PathBuf,
        #[arg(long)]
        boundary: Option<PathBuf>,
    },
    /// The editor (the default with no subcommand). With --screenshot it
    /// renders after loading (and stepping), saves a PNG of the window and
    /// exits.
    #[cfg(feature = "gui")]
    Gui {
        /// Boundary to open (default: the shipped example).
        #[arg(long)]
        open: Option<PathBuf>,
        /// Steps to take after opening.
        #[arg(long, conflicts_with = "run")]
        steps: Option<usize>,
        /// Run to the end after opening.
        #[arg(long)]
        run: bool,
        #[arg(long)]
        screenshot: Option<PathBuf>,
        /// Window size, WIDTHxHEIGHT in points.
        #[arg(long, value_parser = parse_size)]
        size: Option<[f32; 2]>,
        /// The panel shown on the right: model, samples, quality or
        /// smoothing.
        #[arg(long)]
        panel: Option<String>,
    },
    /// Collect training samples from quad meshes (.msh) into a training
    /// set (.csv in the thesis's column order, or .json).
    Samples {
        #[arg(required = true)]
        meshes: Vec<PathBuf>,
        /// Input points: 5, 7, 9 or 11.
        #[arg(long, default_value_t = 7, value_parser = parse_points)]
        points: usize,
        #[arg(short, long)]
        output: PathBuf,
        /// Keep samples that repeat an earlier one.
        #[arg(long)]
        keep_duplicates: bool,
        /// Window of the front's interior angle along a sample's path, in
        /// degrees: LO,HI (default 35,235, method §3; the shipped model and
        /// the editor's "Collect from this mesh" use 35,300).
        #[arg(
            long,
            value_name = "LO,HI",
            value_delimiter = ',',
            default_values_t = CollectParams::DEFAULT.turn,
            hide_default_value = true
        )]
        turn: Vec<f64>,
    },
    /// Fit a model to training sets (.csv or .json) and write the model
    /// file; prints the fit figures (thesis Table 8 layout).
    Fit {
        #[arg(required = true)]
        sets: Vec<PathBuf>,
        /// `thesis`, `quadratic` or `ann` (a back-propagation network);
        /// without it, each is fitted and the one with the best held-out
        /// figures is kept.
        #[arg(long)]
        form: Option<String>,
        #[arg(short, long)]
        output: PathBuf,
        /// Write the fit figures as JSON.
        #[arg(long)]
        report: Option<PathBuf>,
        /// Folds of the held-out figures: 2 to 100, and no more than the
        /// samples (0: no held-out figures). Default 5, or the sample count
        /// when smaller.
        #[arg(long)]
        folds: Option<usize>,
        /// The model's name (default: the output file's stem).
        #[arg(long)]
        name: Option<String>,
        /// Corrections (a training set in the same layout: the samples of
        /// elements the user made), layered over the fitted model: each is
        /// reproduced at its input, inputs within --radius move towards
        /// it, the rest is the fit of the samples alone.
        #[arg(long)]
        corrections: Vec<PathBuf>,
        /// How far a correction reaches: the root mean square distance of
        /// the varying leading points, in normalised units.
        #[arg(long, default_value_t = quadex::model::memory::DEFAULT_RADIUS)]
        radius: f64,
    },
    /// Mesh one boundary with several models and compare them (thesis
    /// Figure 44): a table (finished or not, quads, scaled Jacobian min and
    /// mean, irregular interior nodes, and the element steps that took the
    /// model's element as predicted, took it with Pn rescaled to the size
    /// field, or replaced it) and, with -o, one SVG with the meshes side by
    /// side.
    Compare {
        input: PathBuf,
        /// Comma-separated: `default`, `rules`, `thesis`, `ann`, model files.
        #[arg(long, value_delimiter = ',', default_value = "default,rules,thesis")]
        models: Vec<String>,
        /// The SVG of the meshes side by side (.svg).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Write the figures as JSON.
        #[arg(long)]
        report: Option<PathBuf>,
        /// Resample the boundary first, as `mesh --resample H` does.
        #[arg(long, value_name = "H")]
        resample: Option<f64>,
    },
    /// A model's element for each row of inputs: writes `type,xn,yn` (the
    /// normalised frame) per row of ROWS (.csv with the leading points in
    /// the training-set layout; extra columns are ignored).
    Predict {
        /// `default`, `rules`, `thesis`, `ann` or a model file (.json).
        model: String,
        rows: PathBuf,
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Critical factors (thesis §4.2): the weight of each leading point.
    /// Inputs are meshes (.msh, sampled at each count) or training sets
    /// (.csv/.json, cut down to each count).
    Factors {
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Input-point counts, comma-separated.
        #[arg(long, default_value = "5,7,9,11", value_delimiter = ',', value_parser = parse_points)]
        points: Vec<usize>,
        /// Write the tables as JSON.
        #[arg(long)]
        report: Option<PathBuf>,
    },
}

fn parse_size_at(s: &str) -> Result<(f64, f64, f64), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| "a point size is X,Y,H (three numbers)".to_string())?;
    match v[..] {
        [x, y, h] if x.is_finite() && y.is_finite() && h.is_finite() && h > 0.0 => Ok((x, y, h)),
        _ => Err("a point size is X,Y,H with H a positive number".into()),
    }
}

fn parse_size_on(s: &str) -> Result<(String, f64), String> {
    let (layer, h) = s.rsplit_once('=').ok_or("a layer size is LAYER=H")?;
    match h.trim().parse::<f64>() {
        Ok(h) if h.is_finite() && h > 0.0 => Ok((layer.to_string(), h)),
        _ => Err("a layer size is LAYER=H with H a positive number".into()),
    }
}

#[cfg(feature = "gui")]
fn parse_size(s: &str) -> Result<[f32; 2], String> {
    let (w, h) = s.split_once('x').ok_or("size is WIDTHxHEIGHT")?;
    match (w.parse::<f32>(), h.parse::<f32>()) {
        (Ok(w), Ok(h)) if w >= 200.0 && h >= 200.0 => Ok([w, h]),
        _ => Err("size is WIDTHxHEIGHT, each at least 200".into()),
    }
}

#[cfg(feature = "gui")]
fn gui(o: quadex::app::GuiOptions) -> Result<()> {
    quadex::app::run(o).map_err(|e| InputError(anyhow!("{e}")).into())
}

/// `--layers`: a count, or `all` for extraction to the end.
#[derive(Clone, Copy, Debug)]
struct Layers(Option<u32>);

fn parse_remesh_below(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{s}` is not a scaled Jacobian from 0 (no remeshing) to 1"
        )),
    }
}

fn parse_layers(s: &str) -> Result<Layers, String> {
    if s == "all" {
        return Ok(Layers(None));
    }
    match s.parse::<u32>() {
        Ok(k) if k >= 1 => Ok(Layers(Some(k))),
        _ => Err(format!("`{s}` is not a layer count (1 or more) or `all`")),
    }
}

/// `--transitions`: a ratio above 1, or `off`.
#[derive(Clone, Copy, Debug)]
struct Transitions(Option<f64>);

fn parse_transitions(s: &str) -> Result<Transitions, String> {
    off_or(s, |r: &f64| *r > 1.0 && r.is_finite(), "a ratio above 1").map(Transitions)
}

/// A value `keep` accepts, or `off` (`None`); `what` names the value in
/// the error.
fn off_or<T: std::str::FromStr>(
    s: &str,
    keep: impl Fn(&T) -> bool,
    what: &str,
) -> Result<Option<T>, String> {
    if s == "off" {
        return Ok(None);
    }
    match s.parse::<T>() {
        Ok(v) if keep(&v) => Ok(Some(v)),
        _ => Err(format!("`{s}` is not {what} or `off`")),
    }
}

/// `--mapped-rows`: a count of at least 1, or `off`.
#[derive(Clone, Copy, Debug)]
struct MappedRows(Option<usize>);

/// The boundary in `path`, resampled to segments of about `h` when given
/// ([`Draft::resample`], every loop): the file is read as loops, so a file
/// whose node count is odd can be meshed once resampling evens it.
fn read_resampled(path: &Path, h: Option<f64>) -> Result<Boundary> {
    let at = |e: &dyn std::fmt::Display| InputError(anyhow!("{}: {e}", path.display()));
    let Some(h) = h else {
        return io::read_boundary(path).map_err(|e| at(&e).into());
    };
    let mut draft = Draft {
        loops: io::read_boundary_loops(path).map_err(|e| at(&e))?,
    };
    for li in 0..draft.loops.len() {
        draft.resample(li, h).map_err(|e| at(&e))?;
    }
    draft.to_boundary().map_err(|e| at(&e).into())
}

fn parse_mapped_rows(s: &str) -> Result<MappedRows, String> {
    off_or(s, |n: &usize| *n >= 1, "a count of at least 1").map(MappedRows)
}

fn parse_points(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n @ (5 | 7 | 9 | 11)) => Ok(n),
        _ => Err("input points must be 5, 7, 9 or 11".into()),
    }
}

/// Writes to standard output. A reader that closes the pipe early
/// (`quadex quality FILE | head`) ends the command quietly: see [`main`].
macro_rules! outln {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($t)*)?;
    }};
}

/// [`outln`] without the line end.
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        write!(std::io::stdout().lock(), $($t)*)?;
    }};
}

/// An error in the user's input (exit code 2) as opposed to a failure.
struct InputError(anyhow::Error);

pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // Help and version print as clap prints them; a wrong argument is
        // one line, as every other bad input is.
        Err(e) if !e.use_stderr() => e.exit(),
        Err(e) => {
            // The message is the first paragraph (a list of missing
            // arguments runs over several lines); usage and tips follow.
            let text = e.render().to_string();
            let first: Vec<&str> = text
                .lines()
                .take_while(|l| !l.trim().is_empty())
                .map(str::trim)
                .collect();
            let first = first.join(" ");
            let first = first.strip_prefix("error: ").unwrap_or(&first);
            eprintln!(
                "quadex: {} (`quadex --help` lists the commands and options)",
                io::one_line(first)
            );
            return ExitCode::from(2);
        }
    };
    let res = match cli.command {
        #[cfg(feature = "gui")]
        None => gui(quadex::app::GuiOptions::default()),
        #[cfg(not(feature = "gui"))]
        None => {
            eprintln!("quadex: built without the editor (cargo feature `gui`); see `quadex --help` for the command line");
            return ExitCode::from(2);
        }
        Some(c) => run(c),
    };
    match res {
        Ok(()) => ExitCode::SUCCESS,
        Err(e)
            if e.downcast_ref::<std::io::Error>()
                .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe) =>
        {
            // The reader has all it wanted.
            ExitCode::SUCCESS
        }
        Err(e) => {
            let (code, msg) = match e.downcast_ref::<BadInput>() {
                Some(b) => (2, b.0.clone()),
                None => (1, format!("{e:#}")),
            };
            // One line, whatever the file held.
            eprintln!("quadex: {}", io::one_line(&msg));
            ExitCode::from(code)
        }
    }
}

/// The message of an error in the user's input.
#[derive(Debug)]
struct BadInput(String);
impl std::fmt::Display for BadInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for BadInput {}

impl From<InputError> for anyhow::Error {
    fn from(e: InputError) -> Self {
        // Keep the message; mark the error as the user's.
        anyhow::Error::new(BadInput(format!("{:#}", e.0)))
    }
}

/// Refuses an output path whose folder does not exist, before any work.
fn check_output(path: &Path) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let refuse = |why: String| -> Result<()> {
        Err(InputError(anyhow!("{}: cannot write there: {why}", path.display())).into())
    };
    if dir.exists() && !dir.is_dir() {
        return refuse(format!("{} is not a folder", dir.display()));
    }
    if !dir.is_dir() {
        return refuse(format!("the folder {} does not exist", dir.display()));
    }
    if path.is_dir() {
        return refuse("it is a folder".to_string());
    }
    // A file made and removed again: a folder that exists but cannot be
    // written (read-only, or a system folder) is found before any work.
    let probe = dir.join(format!(".quadex-probe-{}", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => refuse(format!(
            "the folder {} cannot be written: {e}",
            dir.display()
        )),
    }
}

fn load_model(spec: &str) -> Result<Arc<dyn Model>> {
    model::load(spec)
        .map(Arc::from)
        .map_err(|e| InputError(anyhow!("{spec}: {e}")).into())
}

/// Reads a training set, the user's input.
fn read_set(path: &Path) -> Result<TrainingSet> {
    TrainingSet::read(path).map_err(|e| InputError(anyhow!("{}: {e}", path.display())).into())
}

/// Reads a quad mesh (.msh), the user's input.
fn read_mesh(path: &Path) -> Result<quadex::QuadMesh> {
    not_written_only(path)?;
    Ok(io::read_mesh(path).map_err(|e| InputError(anyhow!("{}: {e}", path.display())))?)
}

/// Refuses an output named with none of the extensions `exts` (the first
/// is what the file holds), so a `.json` is never a CSV.
fn want_extension(path: &Path, exts: &[&str]) -> Result<()> {
    let ok = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| exts.iter().any(|x| e.eq_ignore_ascii_case(x)));
    if ok {
        return Ok(());
    }
    let names: Vec<String> = exts.iter().map(|e| format!(".{e}")).collect();
    Err(InputError(anyhow!(
        "{}: written as {}: name the file {}",
        path.display(),
        exts.iter()
            .map(|e| e.to_uppercase())
            .collect::<Vec<_>>()
            .join(" or "),
        names.join(" or ")
    ))
    .into())
}

/// Refuses the mesh formats quadex writes but does not read (.vtk, .vtu,
/// .inp, .svg), naming the one it reads.
fn not_written_only(path: &Path) -> Result<()> {
    match MeshFormat::from_path(path) {
        Ok(f @ (MeshFormat::Vtk | MeshFormat::Vtu | MeshFormat::Abaqus | MeshFormat::Svg)) => {
            Err(InputError(anyhow!(
                "{}: .{} is written, not read: meshes are read from Gmsh .msh files (MSH 2.2 or 4.1)",
                path.display(),
                f.extension()
            ))
            .into())
        }
        _ => Ok(()),
    }
}

fn is_mesh(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("msh"))
}

#[derive(Serialize)]
struct Report<'a> {
    input: String,
    model: String,
    quality: MeshQuality,
    steps: &'a StepStats,
    seconds: f64,
}

fn run(c: Command) -> Result<()> {
    match c {
        #[cfg(feature = "gui")]
        Command::Gui {
            open,
            steps,
            run,
            screenshot,
            size,
            panel,
        } => gui(quadex::app::GuiOptions {
            open,
            steps,
            run,
            screenshot,
            size,
            panel,
        }),
        Command::Mesh {
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
        } => {
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
                if size.is_some()
                    || !size_at.is_empty()
                    || !size_on.is_empty()
                    || gradation.is_some()
                {
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
                ..MeshParams::DEFAULT
            };
            let finish = FinishParams {
                smooth: if smooth == 0 {
                    SmoothParams::OFF
                } else {
                    SmoothParams {
                        iterations: smooth,
                        ..SmoothParams::DEFAULT
                    }
                },
                cleanup: if no_cleanup {
                    CleanupParams::OFF
                } else {
                    CleanupParams::DEFAULT
                },
                coarsen: if no_coarsen {
                    CoarsenParams::OFF
                } else {
                    CoarsenParams::DEFAULT
                },
                remesh: RemeshParams {
                    below: remesh_below,
                    ..RemeshParams::DEFAULT
                },
            };
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
            let (mesh, stats) = pipeline::mesh_boundary(&boundary, model, &params, |at| {
                if let Some(b) = &bar {
                    b.set_message(format!(
                        "{:.0}% of the area, {} front nodes",
                        100.0 * at.meshed,
                        at.front
                    ));
                    b.tick();
                }
            })
            .with_context(|| format!("{}", input.display()))?;
            if let Some(b) = bar {
                b.finish_and_clear();
            }
            let seconds = t0.elapsed().as_secs_f64();
            let q = MeshQuality::of(&mesh);
            let rendered = if order == 2 {
                let single = quadex::regions::RegionMesh::single(mesh.clone(), stats.clone());
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
                0 => format!("{} extraction steps", stats.steps),
                _ => format!(
                    "{} extraction steps and a region fill ({} of the {} quads before finishing)",
                    stats.steps - stats.count(StepKind::Fill),
                    stats.quads_made(StepKind::Fill),
                    stats.standing
                ),
            };
            outln!(
                "{}: {} quads, sj min {:.3} mean {:.3}, {:.1}% in [45,135], {} irregular, {made_by}, {:.3} s",
                output.display(),
                q.quads,
                q.sj_min,
                q.sj_mean,
                100.0 * q.frac_angles_45_135,
                q.irregular_interior,
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
        Command::Quality { mesh, boundary } => {
            // Reading checks the mesh: convex quads, no overlaps, one piece.
            let m = read_mesh(&mesh)?;
            if let Some(b) = boundary {
                let bd = io::read_boundary(&b)
                    .map_err(|e| InputError(anyhow!("{}: {e}", b.display())))?;
                check_against(&m, &bd)
                    .map_err(|e| InputError(anyhow!("{}: {e}", mesh.display())))?;
                // On stderr: stdout stays the JSON alone.
                eprintln!(
                    "{} meshes {}: the same {} boundary nodes and the same area",
                    mesh.display(),
                    b.display(),
                    bd.node_count()
                );
            }
            outln!("{}", serde_json::to_string_pretty(&MeshQuality::of(&m))?);
            Ok(())
        }
        Command::Samples {
            meshes,
            points,
            output,
            keep_duplicates,
            turn,
        } => {
            let [lo, hi] = turn[..] else {
                return Err(InputError(anyhow!("--turn takes two angles, LO,HI")).into());
            };
            want_extension(&output, &["csv", "json"])?;
            if !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo < hi && hi <= 360.0) {
                return Err(InputError(anyhow!(
                    "--turn {lo},{hi}: give two angles in degrees with 0 <= LO < HI <= 360"
                ))
                .into());
            }
            check_output(&output)?;
            let params = CollectParams {
                turn: [lo, hi],
                ..CollectParams::DEFAULT
            };
            let mut set = TrainingSet::new(points);
            for path in &meshes {
                let m = read_mesh(path)?;
                let name = path
                    .file_name()
                    .map(|f| f.to_string_lossy().into_owned())
                    .unwrap_or_default();
                let s = samples::collect(&m, (points - 1) / 2, &params, &name);
                outln!("{}: {} samples", path.display(), s.len());
                set.samples.extend(s);
            }
            let dropped = if keep_duplicates { 0 } else { set.dedup() };
            set.write(&output)
                .map_err(|e| anyhow!("{}: {e}", output.display()))?;
            let t = set.type_counts();
            outln!(
                "{}: {} samples ({} types 0/1/2: {}/{}/{}), {} duplicates dropped",
                output.display(),
                set.len(),
                points,
                t[0],
                t[1],
                t[2],
                dropped
            );
            Ok(())
        }
        Command::Fit {
            sets,
            form,
            output,
            report,
            folds,
            name,
            corrections,
            radius,
        } => {
            let form = match form.as_deref() {
                None => None,
                Some(f) => Some(Form::parse(f).ok_or_else(|| {
                    InputError(anyhow!("{f}: unknown form (use thesis, quadratic or ann)"))
                })?),
            };
            check_output(&output)?;
            if let Some(r) = &report {
                check_output(r)?;
            }
            let mut set = read_set(&sets[0])?;
            for path in &sets[1..] {
                set.merge(read_set(path)?)
                    .map_err(|e| InputError(anyhow!("{}: {e}", path.display())))?;
            }
            let folds = match folds {
                Some(1) => {
                    return Err(InputError(anyhow!(
                        "{}: --folds 1: one fold holds nothing out; give 2 to {} (or 0 to skip the held-out figures)",
                        sets[0].display(),
                        fit::MAX_FOLDS.min(set.len())
                    ))
                    .into())
                }
                Some(f) => {
                    fit::check_folds(f, set.len()).map_err(|e| {
                        InputError(anyhow!("{}: --folds: {e}", sets[0].display()))
                    })?;
                    f
                }
                None if set.len() >= 2 => FitParams::DEFAULT.folds.min(set.len()),
                None => 0,
            };
            let name = name.unwrap_or_else(|| {
                output
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "fitted".into())
            });
            let params = FitParams {
                folds,
                ..FitParams::DEFAULT
            };
            let mut fixes = TrainingSet::new(set.points);
            for path in &corrections {
                fixes
                    .merge(read_set(path)?)
                    .map_err(|e| InputError(anyhow!("{}: {e}", path.display())))?;
            }
            if !(radius.is_finite() && radius > 0.0) {
                return Err(
                    InputError(anyhow!("--radius {radius}: give a positive number")).into(),
                );
            }
            let t0 = Instant::now();
            let (file, reports) = fit::fit_with_corrections(
                &set, &fixes, form, &name, &params, radius,
            )
            .map_err(|e| {
                let at = corrections
                    .first()
                    .filter(|_| matches!(e, fit::FitError::Corrections(_)));
                InputError(anyhow!("{}: {e}", at.unwrap_or(&sets[0]).display()))
            })?;
            let seconds = t0.elapsed().as_secs_f64();
            for r in &reports {
                outln!("{}", r.table());
            }
            let json = file.to_json();
            // Never write a model file that `--model` would refuse.
            quadex::model::ModelFile::from_json(&json).map_err(|e| {
                InputError(anyhow!(
                    "{}: the fitted model cannot be used: {e}",
                    sets[0].display()
                ))
            })?;
            let report_json = match &report {
                Some(_) => {
                    // The chosen form's figures at the top (`type`, `xn`,
                    // `yn`, each with `train` and `holdout`), every form
                    // under `forms`.
                    let mut v = serde_json::to_value(&file.figures)?;
                    if let Some(obj) = v.as_object_mut() {
                        obj.insert("forms".into(), serde_json::to_value(&reports)?);
                    }
                    Some(serde_json::to_string_pretty(&v)?)
                }
                None => None,
            };
            let mut files: Vec<(&Path, &[u8])> = vec![(&output, json.as_bytes())];
            if let (Some(path), Some(r)) = (&report, &report_json) {
                files.push((path, r.as_bytes()));
            }
            io::write_atomic_all(&files)?;
            outln!(
                "{}: form {}, {} samples{}, {} in {seconds:.2} s",
                output.display(),
                file.coefficients.form().name(),
                set.len(),
                match fixes.len() {
                    0 => String::new(),
                    k => format!(" and {k} corrections (radius {radius})"),
                },
                if folds >= 2 {
                    "fitted and cross-validated"
                } else {
                    "fitted"
                }
            );
            Ok(())
        }
        Command::Compare {
            input,
            models,
            output,
            report,
            resample,
        } => {
            for path in output.iter().chain(&report) {
                check_output(path)?;
            }
            if let Some(path) = &output {
                want_extension(path, &["svg"])?;
            }
            let boundary = read_resampled(&input, resample)?;
            let loaded = models
                .iter()
                .map(|spec| load_model(spec).map(|m| (spec, m)))
                .collect::<Result<Vec<_>>>()?;
            let outcomes: Vec<compare::Outcome> = loaded
                .into_iter()
                .map(|(spec, m)| {
                    let name = Path::new(spec)
                        .file_stem()
                        .filter(|_| model::builtin(spec).is_none())
                        .map_or(spec.clone(), |s| s.to_string_lossy().into_owned());
                    compare::mesh_with(&name, &boundary, m, &pipeline::Params::DEFAULT)
                })
                .collect();
            out!("{}", compare::table(&outcomes));
            let mut files: Vec<(PathBuf, String)> = Vec::new();
            if let Some(path) = output {
                files.push((path, compare::svg(&outcomes, 400.0)));
            }
            if let Some(path) = report {
                let json = serde_json::to_string_pretty(&serde_json::json!({
                    "input": input.display().to_string(),
                    "models": outcomes,
                }))?;
                files.push((path, json));
            }
            let refs: Vec<(&Path, &[u8])> = files
                .iter()
                .map(|(p, t)| (p.as_path(), t.as_bytes()))
                .collect();
            io::write_atomic_all(&refs)?;
            Ok(())
        }
        Command::Predict {
            model,
            rows,
            output,
        } => {
            check_output(&output)?;
            want_extension(&output, &["csv"])?;
            let m = load_model(&model)?;
            let text =
                std::fs::read(&rows).map_err(|e| InputError(anyhow!("{}: {e}", rows.display())))?;
            let bad = |e: predict::PredictError| InputError(anyhow!("{}: {e}", rows.display()));
            let (points, inputs) = predict::read_rows(&io::decode_text(&text)).map_err(bad)?;
            let answers = predict::predict_rows(m.as_ref(), points, &inputs).map_err(bad)?;
            io::write_atomic(&output, predict::to_csv(&answers).as_bytes())?;
            outln!(
                "{}: {} predicted by {}",
                output.display(),
                plural(answers.len(), "row"),
                m.name()
            );
            Ok(())
        }
        Command::Factors {
            inputs,
            points,
            report,
        } => {
            if let Some(r) = &report {
                check_output(r)?;
            }
            let mut tables = Vec::new();
            for &pts in &points {
                let mut set = TrainingSet::new(pts);
                for path in &inputs {
                    if is_mesh(path) {
                        let m = read_mesh(path)?;
                        let name = path.display().to_string();
                        set.samples.extend(samples::collect(
                            &m,
                            (pts - 1) / 2,
                            &CollectParams::DEFAULT,
                            &name,
                        ));
                    } else {
                        not_written_only(path)?;
                        let full = read_set(path)?;
                        let cut = factors::truncated(&full, pts).ok_or_else(|| {
                            InputError(anyhow!(
                                "{}: has {} input points, cannot give {pts}",
                                path.display(),
                                full.points
                            ))
                        })?;
                        set.samples.extend(cut.samples);
                    }
                }
                set.dedup();
                let f = factors::factors(&set).map_err(|e| {
                    let names: Vec<String> =
                        inputs.iter().map(|p| p.display().to_string()).collect();
                    InputError(anyhow!("{}: {pts} points: {e}", names.join(", ")))
                })?;
                outln!("{}", f.table());
                tables.push(f);
            }
            if let Some(path) = report {
                io::write_atomic(&path, serde_json::to_string_pretty(&tables)?.as_bytes())?;
            }
            Ok(())
        }
    }
}

/// The mesh keeps the boundary's nodes and its area.
fn check_against(m: &quadex::QuadMesh, b: &quadex::Boundary) -> Result<()> {
    if m.n_boundary() != b.node_count() {
        return Err(anyhow!(
            "the mesh has {} boundary nodes, the boundary {}",
            m.n_boundary(),
            b.node_count()
        ));
    }
    let rel = (m.domain_area() - b.area()).abs() / b.area().abs();
    if rel > 1e-9 {
        return Err(anyhow!(
            "the mesh covers a different area than the boundary"
        ));
    }
    Ok(())
}

/// `n thing(s)`.
fn plural(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

fn progress_bar(front: usize) -> Option<ProgressBar> {
    if !std::io::stderr().is_terminal() || front < 2000 {
        return None;
    }
    let b = ProgressBar::new_spinner();
    b.set_style(ProgressStyle::with_template("{spinner} meshing: {msg} [{elapsed}]").ok()?);
    Some(b)
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

/// Meshes every region of a graph, writes the mesh with its groups (and
/// the report), and prints the quality overall and per region.
fn mesh_graph(a: MeshGraph) -> Result<()> {
    let at = |e: &dyn std::fmt::Display| InputError(anyhow!("{}: {e}", a.input.display()));
    let faces = a.graph.faces().map_err(|e| at(&e))?;
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = a.threads {
        pool = pool.num_threads(n as usize);
    }
    let pool = pool.build()?;
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
        "{}: {} quads in {} regions ({} faces), {} groups, sj min {:.3} mean {:.3}, {:.1}% in [45,135], {} irregular of {} interior, {} extraction steps{}, {:.3} s",
        a.output.display(),
        q.quads,
        m.regions.len(),
        m.faces.len(),
        m.groups.len(),
        q.sj_min,
        q.sj_mean,
        100.0 * q.frac_angles_45_135,
        q.irregular_interior,
        q.interior_nodes,
        steps.steps - fills,
        if fills > 0 { format!(" and {fills} region fills") } else { String::new() },
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

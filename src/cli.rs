//! The command line: `mesh`, `quality`. Errors are reported once, here, as
//! one line naming the file and the problem; bad input exits with code 2.

use anyhow::{anyhow, Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use quadex::extract::{MeshParams, Mesher, StepStats, Strategy};
use quadex::io::{self, MeshFormat};
use quadex::model::{self, Model};
use quadex::quality::MeshQuality;
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
        /// `rules`, `thesis`, or a model file.
        #[arg(long, default_value = "rules")]
        model: String,
        #[arg(long, value_enum, default_value = "b")]
        strategy: StrategyArg,
        /// Input points: 5, 7, 9 or 11.
        #[arg(long, default_value_t = 7, value_parser = parse_points)]
        points: usize,
        /// Smoothing sweeps (0: off).
        #[arg(long, default_value_t = SmoothParams::DEFAULT.iterations)]
        smooth: usize,
        /// Pure model: no remedies; a rejected prediction stops the run.
        #[arg(long)]
        pure_model: bool,
        /// No region fill: a run extraction cannot finish stops with an error.
        #[arg(long)]
        no_fill: bool,
        /// Write the quality figures and step counts as JSON.
        #[arg(long)]
        report: Option<PathBuf>,
    },
    /// Quality figures of a mesh file (.msh); with --boundary, also checks
    /// that it meshes that boundary.
    Quality {
        mesh: PathBuf,
        #[arg(long)]
        boundary: Option<PathBuf>,
    },
}

fn parse_points(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n @ (5 | 7 | 9 | 11)) => Ok(n),
        _ => Err("input points must be 5, 7, 9 or 11".into()),
    }
}

/// An error in the user's input (exit code 2) as opposed to a failure.
struct InputError(anyhow::Error);

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let res = match cli.command {
        None => example(),
        Some(c) => run(c),
    };
    match res {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let code = if e.downcast_ref::<InputErrorMarker>().is_some() {
                2
            } else {
                1
            };
            eprintln!("quadex: {:#}", e);
            ExitCode::from(code)
        }
    }
}

#[derive(Debug)]
struct InputErrorMarker;
impl std::fmt::Display for InputErrorMarker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("bad input")
    }
}
impl std::error::Error for InputErrorMarker {}

impl From<InputError> for anyhow::Error {
    fn from(e: InputError) -> Self {
        // Keep the message; mark the error as the user's.
        let msg = format!("{:#}", e.0);
        anyhow::Error::new(InputErrorMarker).context(msg)
    }
}

fn load_model(name: &str) -> Result<Arc<dyn Model>> {
    match model::builtin(name) {
        Some(m) => Ok(Arc::from(m)),
        None => Err(InputError(anyhow!("{name}: unknown model (use rules or thesis)")).into()),
    }
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
        Command::Mesh {
            input,
            output,
            model,
            strategy,
            points,
            smooth,
            pure_model,
            no_fill,
            report,
        } => {
            let fmt = MeshFormat::from_path(&output)
                .map_err(|e| InputError(anyhow!("{}: {e}", output.display())))?;
            let boundary = io::read_boundary(&input)
                .map_err(|e| InputError(anyhow!("{}: {e}", input.display())))?;
            let model = load_model(&model)?;
            let params = MeshParams {
                strategy: match strategy {
                    StrategyArg::A => Strategy::A,
                    StrategyArg::B => Strategy::B,
                },
                leading_points: (points - 1) / 2,
                smooth: SmoothParams {
                    iterations: smooth,
                    ..SmoothParams::DEFAULT
                },
                pure_model,
                fill: !no_fill,
                ..MeshParams::DEFAULT
            };
            let t0 = Instant::now();
            let name = model.name().to_string();
            let mut mesher = Mesher::new(boundary, model, params);
            let bar = progress_bar(mesher.front().len());
            mesher
                .run(|left| {
                    if let Some(b) = &bar {
                        b.set_message(format!("{left} front nodes"));
                        b.tick();
                    }
                })
                .with_context(|| format!("{}", input.display()))?;
            let mesh = mesher.finish();
            if let Some(b) = bar {
                b.finish_and_clear();
            }
            let seconds = t0.elapsed().as_secs_f64();
            io::write_atomic(&output, fmt.render(&mesh).as_bytes())?;
            let q = MeshQuality::of(&mesh);
            println!(
                "{}: {} quads, sj min {:.3} mean {:.3}, {:.1}% in [45,135], {} irregular, {:.3} s",
                output.display(),
                q.quads,
                q.sj_min,
                q.sj_mean,
                100.0 * q.frac_angles_45_135,
                q.irregular_interior,
                seconds
            );
            if let Some(path) = report {
                let r = Report {
                    input: input.display().to_string(),
                    model: name,
                    quality: q,
                    steps: mesher.stats(),
                    seconds,
                };
                io::write_atomic(&path, serde_json::to_string_pretty(&r)?.as_bytes())?;
            }
            Ok(())
        }
        Command::Quality { mesh, boundary } => {
            let text = std::fs::read_to_string(&mesh)
                .map_err(|e| InputError(anyhow!("{}: {e}", mesh.display())))?;
            let m = io::msh::read_msh(&text)
                .map_err(|e| InputError(anyhow!("{}: {e}", mesh.display())))?;
            if let Some(b) = boundary {
                let bd = io::read_boundary(&b)
                    .map_err(|e| InputError(anyhow!("{}: {e}", b.display())))?;
                check_against(&m, &bd).map_err(|e| anyhow!("{}: {e}", mesh.display()))?;
            }
            m.check_invariants(true)
                .map_err(|e| anyhow!("{}: {e}", mesh.display()))?;
            println!("{}", serde_json::to_string_pretty(&MeshQuality::of(&m))?);
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

fn progress_bar(front: usize) -> Option<ProgressBar> {
    if !std::io::stderr().is_terminal() || front < 2000 {
        return None;
    }
    let b = ProgressBar::new_spinner();
    b.set_style(ProgressStyle::with_template("{spinner} meshing: {msg} [{elapsed}]").ok()?);
    Some(b)
}

/// No arguments: mesh the shipped example and write an SVG beside it.
fn example() -> Result<()> {
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples/annulus.poly");
    let out = std::env::temp_dir().join("quadex_example.svg");
    run(Command::Mesh {
        input,
        output: out,
        model: "rules".into(),
        strategy: StrategyArg::B,
        points: 7,
        smooth: SmoothParams::DEFAULT.iterations,
        pure_model: false,
        no_fill: false,
        report: None,
    })
}

//! The command line: `gui` (the default), `mesh`, `quality`, `samples`, `fit`, `predict`, `compare`, `factors`. Errors are reported once, here, as
//! one line naming the file and the problem; bad input exits with code 2.
//!
//! Each subcommand is a file of its own holding its options (a clap
//! `Args` struct) and its `run`; [`args`] holds the options' value
//! parsers, [`common`] what the subcommands share (reading the user's
//! files, refusing bad output paths, the progress bar).

use anyhow::Result;
use clap::{Parser, Subcommand};
use quadex::io;
use std::process::ExitCode;

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

#[derive(Subcommand)]
enum Command {
    /// Mesh a boundary (.poly or .json) or a drawing (.dxf, or a geometry
    /// .json, with --size) and write the mesh; the format follows OUT's
    /// extension: .msh (4.1), .msh22, .vtk, .vtu, .inp, .svg.
    Mesh(mesh::MeshArgs),
    /// Quality figures of a mesh file (.msh); with --boundary, also checks
    /// that it meshes that boundary.
    Quality(quality::QualityArgs),
    /// The editor (the default with no subcommand). With --screenshot it
    /// renders after loading (and stepping), saves a PNG of the window and
    /// exits.
    #[cfg(feature = "gui")]
    Gui(gui::GuiArgs),
    /// Collect training samples from quad meshes (.msh) into a training
    /// set (.csv in the thesis's column order, or .json).
    Samples(samples::SamplesArgs),
    /// Fit a model to training sets (.csv or .json) and write the model
    /// file; prints the fit figures (thesis Table 8 layout).
    Fit(fit::FitArgs),
    /// Mesh one boundary with several models and compare them (thesis
    /// Figure 44): a table (finished or not, quads, scaled Jacobian min and
    /// mean, irregular interior nodes, and the element steps that took the
    /// model's element as predicted, took it with Pn rescaled to the size
    /// field, or replaced it) and, with -o, one SVG with the meshes side by
    /// side.
    Compare(compare::CompareArgs),
    /// A model's element for each row of inputs: writes `type,xn,yn` (the
    /// normalised frame) per row of ROWS (.csv with the leading points in
    /// the training-set layout; extra columns are ignored).
    Predict(predict::PredictArgs),
    /// Critical factors (thesis §4.2): the weight of each leading point.
    /// Inputs are meshes (.msh, sampled at each count) or training sets
    /// (.csv/.json, cut down to each count).
    Factors(factors::FactorsArgs),
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

mod args;
mod common;
mod compare;
mod factors;
mod fit;
#[cfg(feature = "gui")]
mod gui;
mod mesh;
mod predict;
mod quality;
mod samples;

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
        None => gui::launch(quadex::app::GuiOptions::default()),
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

fn run(c: Command) -> Result<()> {
    match c {
        #[cfg(feature = "gui")]
        Command::Gui(a) => gui::run(a),
        Command::Mesh(a) => mesh::run(a),
        Command::Quality(a) => quality::run(a),
        Command::Samples(a) => samples::run(a),
        Command::Fit(a) => fit::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Predict(a) => predict::run(a),
        Command::Factors(a) => factors::run(a),
    }
}

//! quadex: with no arguments, the example run; with a subcommand, the
//! command line (see `quadex --help`).

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}

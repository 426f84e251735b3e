//! quadex: with no arguments, the example run; with a subcommand, the
//! command line (see `quadex --help`).

mod cli;

/// mimalloc: the mesher makes and drops millions of small vectors, and
/// frees large ones between phases, where it is faster than the system's.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    cli::main()
}

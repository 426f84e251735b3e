//! quadex: with no arguments, the example run; with a subcommand, the
//! command line (see `quadex --help`).

mod cli;

/// mimalloc: the mesher makes and drops millions of small vectors, and
/// frees large ones between phases, where it is faster than the system's.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// mimalloc's `mi_option_purge_delay` (its `include/mimalloc.h`, v3; the
/// binding has no constant of that name).
const MI_OPTION_PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

fn main() -> std::process::ExitCode {
    // Freed memory kept for reuse, never handed back to the system: the
    // finishing phases free and allocate buffers of the mesh's size one
    // after another, and memory handed back comes back as fresh pages the
    // kernel must clear (an eighth of the time on a mesh of millions of
    // quads).
    // SAFETY: an option setter, called before any thread is started.
    unsafe { libmimalloc_sys::mi_option_set(MI_OPTION_PURGE_DELAY, -1) };
    cli::main()
}

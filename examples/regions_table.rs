//! Meshes the multi-region cases of `tests/data/regions` and prints, per
//! case, a table of its regions (quads, scaled Jacobian min and mean,
//! irregular interior share) and the time on one thread and on two
//! (median of `RUNS` runs, 5 unless given), checking that both give the
//! same bytes.
//!
//! `cargo run --release --example regions_table [RUNS]`

use quadex::io::{self, MeshFormat};
use quadex::pipeline::Params;
use quadex::regions::{mesh_regions, RegionMesh};
use std::sync::Arc;
use std::time::Instant;

/// The command line's allocator, so the times are the ones it gives.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn timed(g: &quadex::pslg::Pslg, threads: usize, runs: usize) -> (RegionMesh, f64) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    let model = Arc::new(quadex::model::default_model().expect("the shipped model"));
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..runs {
        let t0 = Instant::now();
        let m = pool
            .install(|| mesh_regions(g, model.clone(), &Params::DEFAULT, |_| {}))
            .expect("meshes");
        times.push(t0.elapsed().as_secs_f64());
        last = Some(m);
    }
    times.sort_by(f64::total_cmp);
    (last.expect("a run"), times[times.len() / 2])
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5)
        .max(1);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/regions");
    let mut timing = Vec::new();
    for name in [
        "split_square",
        "layered_strip",
        "plate_inclusions",
        "annulus_two_materials",
        "l_bracket",
        "machine",
        "machine_fine",
    ] {
        let g = io::read_graph(&dir.join(format!("{name}.poly"))).expect("reads");
        let (one, t1) = timed(&g, 1, runs);
        let (two, t2) = timed(&g, 2, runs);
        let same = MeshFormat::ALL
            .iter()
            .all(|f| f.render_regions(&one) == f.render_regions(&two));
        let q = one.quality();
        println!(
            "\n**{name}**: {} faces, {} quads, sj min {:.3} mean {:.3}, irregular {:.1} %, fills {}, conforming: {}",
            one.faces.len(),
            q.quads,
            q.sj_min,
            q.sj_mean,
            100.0 * q.irregular_interior as f64 / q.interior_nodes.max(1) as f64,
            one.steps().count(quadex::extract::StepKind::Fill),
            one.check_conforming().is_ok()
        );
        println!("\n| region | tag | quads | SJ min | SJ mean | irregular interior |");
        println!("|---|---:|---:|---:|---:|---:|");
        for r in &one.regions {
            let rq = &r.quality;
            println!(
                "| {} | {} | {} | {:.3} | {:.3} | {:.1} % ({} of {}) |",
                r.name,
                r.tag,
                rq.quads,
                rq.sj_min,
                rq.sj_mean,
                100.0 * rq.irregular_interior as f64 / rq.interior_nodes.max(1) as f64,
                rq.irregular_interior,
                rq.interior_nodes
            );
        }
        timing.push((name, q.quads, t1, t2, same));
    }
    println!("\n| case | quads | 1 thread, median s | 2 threads, median s | ratio | same bytes |");
    println!("|---|---:|---:|---:|---:|---|");
    for (name, quads, t1, t2, same) in timing {
        println!(
            "| {name} | {quads} | {t1:.3} | {t2:.3} | {:.2} | {} |",
            t1 / t2,
            if same { "yes" } else { "NO" }
        );
    }
}

//! Criterion benchmarks of whole meshing runs (extraction + smoothing).
//! `cargo bench` reports medians; `cargo run --release --example scaling`
//! prints the time per element from 1k to 1M elements.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use quadex::model::RulesModel;
use quadex::Boundary;
use quadex::Params;
use std::sync::Arc;

/// The command line's allocator, so the times are the ones it gives.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("mesh");
    g.sample_size(10);
    for n in [32usize, 64, 128] {
        let b = Boundary::unit_square(n);
        g.bench_with_input(BenchmarkId::new("square", n * n), &b, |bch, b| {
            bch.iter(|| {
                quadex::mesh_boundary(b, Arc::new(RulesModel::DEFAULT), &Params::DEFAULT, |_| {})
                    .unwrap()
            })
        });
    }
    let bench_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries");
    for name in ["circle", "disk100"] {
        let b = quadex::io::read_boundary(&bench_dir.join(format!("{name}.poly"))).unwrap();
        g.bench_function(name, |bch| {
            bch.iter(|| {
                quadex::mesh_boundary(&b, Arc::new(RulesModel::DEFAULT), &Params::DEFAULT, |_| {})
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

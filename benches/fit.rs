//! Criterion benchmarks of model fitting: the thesis's largest set has
//! 12,293 samples (Table 8); fitting that many must take under a second.
//! The samples are the first 12,293 of the reference meshes' 7-point set.

use criterion::{criterion_group, criterion_main, Criterion};
use quadex::fit::{fit_coefficients, Data, FitParams};
use quadex::model::Form;
use quadex::reference::read_shipped;
use quadex::samples::{CollectParams, TrainingSet};

/// The thesis's largest training set size.
const SAMPLES: usize = 12_293;

fn bench(c: &mut Criterion) {
    let meshes = read_shipped().unwrap();
    let mut set = TrainingSet::collect(&meshes, 7, &CollectParams::DEFAULT);
    set.samples.truncate(SAMPLES);
    assert_eq!(set.len(), SAMPLES);
    let data = Data::of(&set).unwrap();
    let params = FitParams {
        folds: 0,
        ..FitParams::DEFAULT
    };
    let mut g = c.benchmark_group("fit_12293");
    g.sample_size(10);
    for form in Form::ALL {
        g.bench_function(form.name(), |b| {
            b.iter(|| fit_coefficients(&data, form, &params).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

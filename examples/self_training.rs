//! Self-training (issue 16, thesis §5.3): does a model refitted on the
//! shipped training set plus samples from quadex's own finished meshes
//! mesh other domains better than the shipped model?
//!
//! Training domains: `domains::suite(TRAIN_N, TRAIN_SEED)`, meshed with the
//! shipped default model; every finished mesh (no region fill) of at most
//! `--max-quads` quads gives its good elements' samples, collected as the
//! shipped model's are (`reference::training_set`, what the editor's
//! "Collect from this mesh" does). The self-trained model is the editor's
//! refit (`fit::refit`) of the shipped set plus those samples. Both models
//! then mesh the held-out domains `domains::suite(TEST_N, TEST_SEED)` (other
//! seeds) and are compared: finished, with the fill, median mean scaled
//! Jacobian, median irregular share, median of each mesh's worst taper and
//! the meshes with a taper over 10, the median shares of element steps
//! accepted as predicted and rescaled.
//!
//! `cargo run --release --example self_training -- [--train-n 14]
//! [--train-seed 11] [--test-n 28] [--test-seed 12] [--max-quads 800]`

use anyhow::Context;
use quadex::compare::{mesh_with, Outcome};
use quadex::domains::suite;
use quadex::fit::{refit, FitParams};
use quadex::model::{builtin, Model};
use quadex::pipeline::Params;
use quadex::quality::MeshQuality;
use quadex::reference::{default_training_set, read_shipped, training_set, DEFAULT_MODEL_FORM};
use std::sync::Arc;

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// One row of the table: a model over the held-out domains.
fn row(name: &str, outcomes: &[Outcome]) -> String {
    let done: Vec<&Outcome> = outcomes.iter().filter(|o| o.finished).collect();
    let fill = done.iter().filter(|o| o.fill).count();
    let tapers: Vec<f64> = done
        .iter()
        .filter_map(|o| o.mesh.as_ref())
        .map(|m| MeshQuality::of(m).taper_max)
        .collect();
    let over = tapers.iter().filter(|&&t| t > 10.0).count();
    let med = |f: fn(&Outcome) -> f64| median(done.iter().map(|o| f(o)).collect());
    format!(
        "| {name} | {} of {} | {fill} | {:.4} | {:.1} % | {:.2} | {over} | {:.1} % | {:.1} % |",
        done.len(),
        outcomes.len(),
        med(|o| o.sj_mean),
        100.0 * med(|o| o.irregular_share),
        median(tapers),
        100.0 * med(|o| o.accepted_share),
        100.0 * med(|o| o.rescaled_share),
    )
}

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let (mut train_n, mut train_seed, mut test_n, mut test_seed, mut max_quads) =
        (14usize, 11u64, 28usize, 12u64, 800usize);
    while let Some(a) = args.next() {
        let mut val = || args.next().with_context(|| format!("{a} needs a value"));
        match a.as_str() {
            "--train-n" => train_n = val()?.parse()?,
            "--train-seed" => train_seed = val()?.parse()?,
            "--test-n" => test_n = val()?.parse()?,
            "--test-seed" => test_seed = val()?.parse()?,
            "--max-quads" => max_quads = val()?.parse()?,
            s => anyhow::bail!("unknown argument {s}"),
        }
    }
    let params = Params::DEFAULT;
    let base: Arc<dyn Model> = Arc::from(builtin("default").context("the default model")?);
    let mut own = Vec::new();
    for (name, b) in suite(train_n, train_seed) {
        let o = mesh_with(&name, &b, base.clone(), &params);
        let used = o.finished && !o.fill && o.quads <= max_quads;
        eprintln!(
            "train {name}: {} quads, finished {}, {}",
            o.quads,
            o.finished_label(),
            if used { "used" } else { "left out" }
        );
        if let (true, Some(m)) = (used, o.mesh) {
            own.push((name, m));
        }
    }
    let added = training_set(&own, 7);
    let set = default_training_set(&read_shipped()?);
    let fit = FitParams {
        folds: 0,
        ..FitParams::DEFAULT
    };
    let file = refit(&set, &added, DEFAULT_MODEL_FORM, "self-trained", &fit)?;
    let trained: Arc<dyn Model> = Arc::new(file.model());
    let test = suite(test_n, test_seed);
    let mut results: [Vec<Outcome>; 2] = [Vec::new(), Vec::new()];
    for (name, b) in &test {
        for (k, m) in [&base, &trained].into_iter().enumerate() {
            let o = mesh_with(name, b, m.clone(), &params);
            eprintln!(
                "test {name} model {k}: {} {} quads, SJ mean {:.3}",
                o.finished_label(),
                o.quads,
                o.sj_mean
            );
            results[k].push(o);
        }
    }
    println!(
        "training: {} of {train_n} domains of suite seed {train_seed} ({} samples added to {}); held out: {test_n} domains of suite seed {test_seed}\n",
        own.len(),
        added.len(),
        set.len()
    );
    println!("| model | finished | with the fill | median SJ mean | median irregular | median worst taper | taper > 10 | median accepted | median rescaled |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    println!("{}", row("shipped default", &results[0]));
    println!("{}", row("self-trained", &results[1]));
    Ok(())
}

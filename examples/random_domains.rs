//! Writes a suite of seeded awkward domains (`quadex::domains`) as `.poly`
//! files, `NNN_family_seed.poly`, and an index (`index.tsv`: name, family,
//! seed, loops, nodes, description) for `.ci/domains_sweep.py`.
//!
//! `cargo run --release --example random_domains -- OUT_DIR [--n 300] [--seed 1] [--real-like]`
//! (`--real-like`: the real-like families, `domains::real_like_domains`)

use anyhow::{bail, Context};
use quadex::domains::{real_like_domains, suite_domains};
use quadex::io::{poly::write_poly, write_atomic};
use std::fmt::Write as _;
use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let mut dir = None;
    let (mut n, mut seed) = (300usize, 1u64);
    let mut real_like = false;
    while let Some(a) = args.next() {
        match a.as_str() {
            "--n" => n = args.next().context("--n needs a count")?.parse()?,
            "--seed" => seed = args.next().context("--seed needs a number")?.parse()?,
            "--real-like" => real_like = true,
            s if s.starts_with("--") => bail!("unknown option {s}"),
            s => dir = Some(PathBuf::from(s)),
        }
    }
    let dir = dir.context("usage: random_domains OUT_DIR [--n 300] [--seed 1] [--real-like]")?;
    std::fs::create_dir_all(&dir)?;
    let mut index = String::from("name\tfamily\tseed\tloops\tnodes\tdescription\n");
    let domains = if real_like {
        real_like_domains(n, seed)
    } else {
        suite_domains(n, seed)
    };
    for d in domains {
        write_atomic(
            &dir.join(format!("{}.poly", d.name)),
            write_poly(&d.boundary).as_bytes(),
        )?;
        writeln!(
            index,
            "{}\t{}\t{}\t{}\t{}\t{}",
            d.name,
            d.family,
            d.seed,
            d.boundary.loops.len(),
            d.boundary.node_count(),
            d.description
        )?;
    }
    write_atomic(&dir.join("index.tsv"), index.as_bytes())?;
    println!("{n} domains (seed {seed}) in {}", dir.display());
    Ok(())
}

//! Deterministic fuzzing of every reader: `.poly` and JSON boundaries, MSH
//! 4.1 and 2.2 meshes, CSV and JSON training sets and model files. Inputs
//! are the benchmark's and the reproducers' files and files written by
//! quadex, mutated by a seeded xorshift generator (bit flips, odd bytes,
//! line ends and byte-order marks, deletions, repeats, truncation, swapped
//! lines, numbers replaced by extreme ones). Every input must give a value
//! or a typed error with a one-line message free of control characters,
//! never a panic; what is read must be usable (a training set fits, a model
//! predicts, a mesh is measured and sampled) without a panic either.

mod common;

use quadex::io::{self, boundary_json, msh, MeshFormat};
use quadex::model::ModelFile;
use quadex::samples::TrainingSet;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// xorshift64: small, fast, the same everywhere.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

const ODD_BYTES: &[u8] = b"\0\r\n\x1c\x7f\xff\xc3-+e.9 \t#\"[]{},:$";
const EXTREME: &[&str] = &[
    "1e308",
    "-1e308",
    "1e-320",
    "1e400",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "-0",
    "0",
    "-1",
    "18446744073709551615",
    "18446744073709551616",
    "99999999999",
    "4294967296",
    "2147483648",
    "1.5",
    "1e150",
    "1e-150",
    "0x10",
    "",
];

/// Byte ranges of the numbers in `b`.
fn numbers(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b"+-.".contains(&b[i])) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

fn mutate(g: &mut XorShift, seed: &[u8]) -> Vec<u8> {
    let mut b = seed.to_vec();
    for _ in 0..1 + g.below(4) {
        let n = b.len();
        match g.below(10) {
            0 if n > 0 => {
                let i = g.below(n);
                b[i] ^= 1 << g.below(8);
            }
            1 if n > 0 => {
                let i = g.below(n);
                b[i] = *g.pick(ODD_BYTES);
            }
            2 => {
                let i = g.below(n + 1);
                b.insert(i, *g.pick(ODD_BYTES));
            }
            3 if n > 0 => {
                let i = g.below(n);
                let len = 1 + g.below(64.min(n - i));
                b.drain(i..i + len);
            }
            4 if n > 0 => {
                let i = g.below(n);
                let len = 1 + g.below(256.min(n - i));
                let piece = b[i..i + len].to_vec();
                let at = g.below(n + 1);
                b.splice(at..at, piece);
            }
            5 | 6 => {
                let nums = numbers(&b);
                if !nums.is_empty() {
                    let (s, e) = *g.pick(&nums);
                    b.splice(s..e, g.pick(EXTREME).bytes());
                }
            }
            7 => b.truncate(g.below(n + 1)),
            8 => {
                let mut lines: Vec<Vec<u8>> =
                    b.split(|&c| c == b'\n').map(<[u8]>::to_vec).collect();
                if lines.len() > 2 {
                    let (i, j) = (g.below(lines.len()), g.below(lines.len()));
                    lines.swap(i, j);
                }
                b = lines.join(&b'\n');
            }
            _ => match g.below(3) {
                0 => b.splice(0..0, [0xef, 0xbb, 0xbf]).for_each(drop),
                1 => {
                    b = b
                        .iter()
                        .map(|&c| if c == b'\n' { b'\r' } else { c })
                        .collect()
                }
                _ => {
                    b = b
                        .iter()
                        .flat_map(|&c| {
                            if c == b'\n' {
                                vec![b'\r', b'\n']
                            } else {
                                vec![c]
                            }
                        })
                        .collect()
                }
            },
        }
    }
    b
}

/// A message fit for one line of a terminal.
fn check_message(kind: &str, case: usize, msg: &str) {
    assert!(!msg.is_empty(), "{kind} case {case}: empty message");
    assert!(
        !msg.chars().any(char::is_control),
        "{kind} case {case}: control character in {msg:?}"
    );
}

/// Runs `read` on every mutation of the seeds; `read` returns the error's
/// message, if any.
fn fuzz(
    kind: &str,
    seeds: &[Vec<u8>],
    cases: usize,
    seed: u64,
    mut read: impl FnMut(&str) -> Option<String>,
) {
    assert!(!seeds.is_empty(), "{kind}: no seeds");
    let mut g = XorShift(seed);
    let mut refused = 0;
    for case in 0..cases {
        let original = g.pick(seeds).clone();
        let bytes = mutate(&mut g, &original);
        // What every reader does with a file's bytes.
        let text = io::decode_text(&bytes);
        match catch_unwind(AssertUnwindSafe(|| read(&text))) {
            Ok(Some(msg)) => {
                check_message(kind, case, &msg);
                refused += 1;
            }
            Ok(None) => {}
            Err(_) => panic!(
                "{kind} case {case} (seed {seed}) panicked on {:?}",
                io::quote_long(&text)
            ),
        }
    }
    println!("{kind}: {cases} inputs, {refused} refused");
    // The mutations do make bad files (and leave some good).
    assert!(
        refused > cases / 10,
        "{kind}: only {refused} of {cases} refused"
    );
    assert!(refused < cases, "{kind}: every input refused");
}

fn files(folder: &Path, ext: &str, max_bytes: u64) -> Vec<Vec<u8>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(folder)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .filter(|p| std::fs::metadata(p).is_ok_and(|m| m.len() <= max_bytes))
        .collect();
    paths.sort();
    paths.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

fn repro_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/repro")
}

fn reference_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/reference")
}

fn poly_seeds() -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    for folder in ["boundaries", "peer", "edge", "bad"] {
        seeds.extend(files(&common::bench().join(folder), "poly", 16_000));
    }
    seeds.extend(files(&repro_dir(), "poly", 16_000));
    seeds
}

#[test]
fn poly_and_json_boundaries() {
    let polys = poly_seeds();
    fuzz(
        "poly",
        &polys,
        4000,
        0x5eed_0001,
        |t| match io::poly::parse_poly(t) {
            Ok(b) => {
                assert!(b.node_count() >= 4 && b.node_count() % 2 == 0);
                None
            }
            Err(e) => Some(e.to_string()),
        },
    );
    // JSON documents of the valid polygons, and the reproducer's.
    let mut json: Vec<Vec<u8>> = polys
        .iter()
        .filter_map(|p| io::poly::parse_poly(&io::decode_text(p)).ok())
        .map(|b| {
            serde_json::to_vec(&boundary_json::BoundaryDoc::from_boundary(&b, "fuzz")).unwrap()
        })
        .collect();
    json.extend(files(&repro_dir(), "json", 16_000).into_iter().filter(|f| {
        // The boundary documents only (not training sets).
        f.windows(7).any(|w| w == b"\"loops\"")
    }));
    fuzz(
        "boundary json",
        &json,
        2000,
        0x5eed_0002,
        |t| match boundary_json::parse(t) {
            Ok(b) => {
                assert!(b.node_count() % 2 == 0);
                None
            }
            Err(e) => Some(e.to_string()),
        },
    );
}

#[test]
fn msh_meshes() {
    let mut seeds = files(&reference_dir(), "msh", 25_000);
    // The same meshes in MSH 2.2, and small ones written by quadex.
    let meshes: Vec<_> = seeds
        .iter()
        .map(|s| msh::read_msh(&io::decode_text(s)).unwrap())
        .collect();
    for m in &meshes {
        seeds.push(MeshFormat::Msh22.render(m).into_bytes());
    }
    seeds.extend(files(&repro_dir(), "msh", 16_000));
    let n = seeds.len();
    // The repro files are tiny: weight them like the others.
    seeds.extend_from_within(n - 4..n);
    fuzz("msh", &seeds, 2500, 0x5eed_0003, |t| {
        match msh::read_msh(t) {
            Ok(m) => {
                // What a mesh read is used for: a second check, its quality and
                // its samples.
                io::check::check_mesh(&m).unwrap();
                let _ = quadex::MeshQuality::of(&m);
                let _ = quadex::samples::collect(&m, 2, &Default::default(), "fuzz");
                None
            }
            Err(e) => Some(e.to_string()),
        }
    });
}

/// A small training set of a reference mesh, `points` input points.
fn small_set(points: usize) -> TrainingSet {
    let m = io::read_mesh(&reference_dir().join("skewed_quad.msh")).unwrap();
    let mut set = TrainingSet::collect(
        &[("skewed_quad.msh".into(), m)],
        points,
        &Default::default(),
    );
    set.samples.truncate(40);
    set
}

/// Uses a set read: fits both forms (no held-out figures), its factors.
fn use_set(set: &TrainingSet) {
    let params = quadex::fit::FitParams {
        folds: 0,
        ..Default::default()
    };
    for form in quadex::model::Form::ALL {
        if let Ok((file, _)) = quadex::fit::fit_model(set, Some(form), "fuzz", &params) {
            // What fit writes loads back.
            ModelFile::from_json(&file.to_json()).unwrap();
        }
    }
    let _ = quadex::factors::factors(set);
}

#[test]
fn training_sets() {
    let mut csv = vec![
        small_set(5).to_csv().unwrap().into_bytes(),
        small_set(7).to_csv().unwrap().into_bytes(),
    ];
    csv.extend(files(&repro_dir(), "csv", 16_000));
    let mut json = vec![
        small_set(5).to_json().unwrap().into_bytes(),
        small_set(7).to_json().unwrap().into_bytes(),
    ];
    json.extend(
        files(&repro_dir(), "json", 16_000)
            .into_iter()
            .filter(|f| f.windows(9).any(|w| w == b"\"samples\"")),
    );
    let mut k = 0usize;
    fuzz(
        "training csv",
        &csv,
        2000,
        0x5eed_0004,
        |t| match TrainingSet::from_csv(t) {
            Ok(set) => {
                set.check().unwrap();
                k += 1;
                if k % 4 == 0 {
                    use_set(&set);
                }
                None
            }
            Err(e) => Some(e.to_string()),
        },
    );
    let mut k = 0usize;
    fuzz(
        "training json",
        &json,
        2000,
        0x5eed_0005,
        |t| match TrainingSet::from_json(t) {
            Ok(set) => {
                set.check().unwrap();
                k += 1;
                if k % 4 == 0 {
                    use_set(&set);
                }
                None
            }
            Err(e) => Some(e.to_string()),
        },
    );
}

#[test]
fn model_files() {
    let set = small_set(7);
    let params = quadex::fit::FitParams {
        folds: 0,
        ..Default::default()
    };
    let mut seeds = vec![std::fs::read(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/models/default.json"),
    )
    .unwrap()];
    for form in quadex::model::Form::ALL {
        let (file, _) = quadex::fit::fit_model(&set, Some(form), "fuzz", &params).unwrap();
        seeds.push(file.to_json().into_bytes());
    }
    fuzz(
        "model",
        &seeds,
        2000,
        0x5eed_0006,
        |t| match ModelFile::from_json(t) {
            Ok(f) => {
                // Predictions with the model's own number of leading points,
                // as the mesher asks for them.
                let m = f.model();
                let n = quadex::Model::leading_points(&m).unwrap_or(3);
                for scale in [0.5, 1.0, 3.0, 1e6] {
                    let lp = quadex::normalize::LeadingPoints {
                        left: (1..=n)
                            .map(|k| quadex::Point::new(0.1, scale * k as f64))
                            .collect(),
                        right: (1..=n)
                            .map(|k| quadex::Point::new(scale * k as f64, -0.1))
                            .collect(),
                    };
                    let _ = quadex::Model::predict(&m, &lp);
                }
                None
            }
            Err(e) => Some(e.to_string()),
        },
    );
}

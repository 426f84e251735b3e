//! Corrections that stick (the learning loop of thesis §2.2.2 and §5.3):
//! corrections taken at random from benchmark runs are reproduced by the
//! refitted model at their inputs, nearby inputs move towards them, and the
//! rest of the model is unchanged.

mod common;

use quadex::extract::{Correction, MeshParams, Mesher, StepKind, StepOutcome};
use quadex::fit::{self, FitParams};
use quadex::model::memory::{distance, DEFAULT_RADIUS};
use quadex::model::{self, ElementType, FittedModel, Form, Model, ModelFile};
use quadex::pipeline::{mesh_boundary, Params};
use quadex::reference;
use quadex::rng::SplitMix64;
use quadex::samples::{CollectParams, Sample, TrainingSet};
use quadex::{Boundary, Point};
use std::sync::Arc;

/// Benchmark cases the corrections are taken from.
const CASES: [&str; 6] = [
    "square",
    "lshape",
    "irregular",
    "plate_hole",
    "annulus",
    "star8",
];

fn read(case: &str) -> Boundary {
    quadex::io::read_boundary(&common::bench().join(format!("boundaries/{case}.poly"))).unwrap()
}

fn shipped() -> Arc<dyn Model> {
    Arc::from(model::builtin("default").unwrap())
}

/// `count` corrections taken at random (fixed seed) from runs of the
/// shipped model over [`CASES`]: at a random element step, the element is
/// replaced by a type-0 element whose Pn is moved by 0.1 to 0.3 of the
/// step's P0–P_r1 distance in a random direction (the first such move that
/// gives a valid element), and the correction's sample is kept.
fn corrections(count: usize, seed: u64) -> Vec<Sample> {
    corrections_in(&CASES, count, seed)
}

/// [`corrections`] from the runs over `cases`.
fn corrections_in(cases: &[&str], count: usize, seed: u64) -> Vec<Sample> {
    let model = shipped();
    let runs: Vec<(Boundary, Vec<usize>)> = cases
        .iter()
        .map(|case| {
            let b = read(case);
            let mut m = Mesher::new(b.clone(), model.clone(), MeshParams::DEFAULT);
            let mut elements = Vec::new();
            while let StepOutcome::Stepped(r) = m.step().unwrap() {
                if r.kind == StepKind::Element {
                    elements.push(r.index);
                }
            }
            (b, elements)
        })
        .collect();
    let mut g = SplitMix64::new(seed);
    let mut out = Vec::new();
    while out.len() < count {
        let (b, elements) = &runs[g.int(0, runs.len() - 1)];
        let at = elements[g.int(0, elements.len() - 1)];
        let mut m = Mesher::new(b.clone(), model.clone(), MeshParams::DEFAULT);
        for _ in 0..at {
            m.step().unwrap();
        }
        let StepOutcome::Stepped(r) = m.step().unwrap() else {
            panic!("the run has step {at}");
        };
        assert!(m.undo());
        let n = r.leading.len() / 2;
        let node = |k: usize| m.mesh().nodes[r.leading[k] as usize];
        let (p0, r1) = (node(n), node(n + 1));
        let committed = m.mesh().nodes.len();
        let pn = match r.pn_node() {
            Some(v) if (v as usize) < committed => m.mesh().nodes[v as usize],
            _ => r.predicted_pn.unwrap(),
        };
        let d = p0.distance(r1);
        for _ in 0..20 {
            let angle = g.uni(0.0, std::f64::consts::TAU);
            let len = g.uni(0.1, 0.3) * d;
            let c = Correction {
                reference: r.reference.unwrap(),
                element_type: ElementType::New,
                pn: Some(pn + Point::new(angle.cos(), angle.sin()) * len),
                snap_to: None,
            };
            if let Ok(checked) = m.check_correction(&c) {
                let rc = m.correct(&c).unwrap();
                // The checked element is the one committed.
                let quad = rc.quads[0].map(|v| m.mesh().nodes[v as usize]);
                assert_eq!(checked.quad, quad);
                let s = m.sample_of(&rc).unwrap();
                // Corrections at distinct places: a draw whose input lies
                // near an earlier one's (a regular grid repeats its
                // patterns) would correct the same place twice.
                if out
                    .iter()
                    .all(|o: &Sample| distance(&o.input, &s.input) >= 2.0 * DEFAULT_RADIUS)
                {
                    out.push(s);
                }
                break;
            }
        }
    }
    out
}

/// Samples of quadex's own finished meshes of benchmark cases the
/// corrections were not taken from (held out).
fn held_out() -> TrainingSet {
    let meshes: Vec<(String, quadex::QuadMesh)> = ["rect_graded", "wedge30", "naca0012"]
        .iter()
        .map(|case| {
            let (mesh, _) =
                mesh_boundary(&read(case), shipped(), &Params::DEFAULT, |_| {}).unwrap();
            (case.to_string(), mesh)
        })
        .collect();
    TrainingSet::collect(&meshes, 7, &CollectParams::DEFAULT)
}

fn refitted(corrections: &[Sample]) -> FittedModel {
    let base = reference::default_training_set(&reference::read_shipped().unwrap());
    let added = TrainingSet {
        points: 7,
        samples: corrections.to_vec(),
    };
    let params = FitParams {
        folds: 0,
        ..FitParams::DEFAULT
    };
    fit::refit(&base, &added, Form::Quadratic, "corrected", &params)
        .unwrap()
        .model()
}

#[test]
fn twenty_random_corrections_stick_and_the_rest_stays() {
    let cs = corrections(20, 16);
    assert_eq!(cs.len(), 20);
    let before = model::default_model().unwrap();
    let after = refitted(&cs);
    // The global part is the shipped model's; the corrections are layered
    // over it.
    assert_eq!(after.coefficients, before.coefficients);
    assert_eq!(after.memory.len(), 20);

    // 1. Reproduced at their inputs: the type, and Pn within 0.05.
    let mut stuck = 0;
    let mut moved_before = 0.0;
    for c in &cs {
        let p = after.predict(&c.input);
        let q = before.predict(&c.input);
        moved_before += (q.pn - c.pn).length();
        if p.element_type == c.element_type && (p.pn - c.pn).length() <= 0.05 {
            stuck += 1;
        }
    }
    assert!(stuck >= 19, "{stuck} of 20 reproduced");
    // The corrections were real changes: the shipped model predicted
    // something else there.
    assert!(moved_before / 20.0 > 0.05, "{moved_before}");

    // 2. Nearby inputs move towards the correction: P_l3 moved so that the
    //    input is a third of the radius away (within half the radius: the
    //    corrected element whole), or three quarters (part of the way).
    for c in &cs {
        for (frac, whole) in [(1.0 / 3.0, true), (0.75, false)] {
            let mut near = c.input.clone();
            near.left[2].y += DEFAULT_RADIUS * frac * (5.0f64).sqrt();
            assert!((distance(&near, &c.input) - DEFAULT_RADIUS * frac).abs() < 1e-9);
            let (p, q) = (after.predict(&near), before.predict(&near));
            let (moved, was) = ((p.pn - c.pn).length(), (q.pn - c.pn).length());
            assert!(
                moved < was,
                "{:?}: {:?} is not nearer than {:?}",
                c.pn,
                p.pn,
                q.pn
            );
            assert_eq!(moved < 1e-12, whole, "{moved} at {frac} of the radius");
        }
    }

    // 3. Inputs outside every correction's radius are predicted as before,
    //    to the bit, and the held-out R moves by no more than 0.005.
    let held = held_out();
    assert!(held.len() > 1000, "{}", held.len());
    let mut far = 0;
    for s in &held.samples {
        if cs
            .iter()
            .all(|c| distance(&c.input, &s.input) >= DEFAULT_RADIUS)
        {
            assert_eq!(after.predict(&s.input), before.predict(&s.input));
            far += 1;
        }
    }
    assert!(far > held.len() / 2, "{far} of {}", held.len());
    let (t0, x0, y0) = fit::evaluate(&before, &held).unwrap();
    let (t1, x1, y1) = fit::evaluate(&after, &held).unwrap();
    eprintln!(
        "held out ({} samples, {far} outside every radius): type {:.4} -> {:.4}, Xn R {:.4} -> {:.4}, Yn R {:.4} -> {:.4}",
        held.len(),
        t0.accuracy,
        t1.accuracy,
        x0.r,
        x1.r,
        y0.r,
        y1.r
    );
    assert!(x0.r - x1.r <= 0.005, "Xn R {} -> {}", x0.r, x1.r);
    assert!(y0.r - y1.r <= 0.005, "Yn R {} -> {}", y0.r, y1.r);
    assert!(t0.accuracy - t1.accuracy <= 0.005);

    // 4. The model file carries the corrections: written and read back, it
    //    predicts the same.
    let file = ModelFile::of_model(&after, Default::default(), None);
    assert_eq!(file.version, 2);
    let back = ModelFile::from_json(&file.to_json()).unwrap().model();
    assert_eq!(back, after);
}

#[test]
fn a_corrected_element_is_taken_again_at_the_same_place() {
    // One correction; fresh runs with the refitted model predict the
    // corrected element wherever an input comes within half the radius of
    // the correction's (its full weight), and the guard takes it there.
    use quadex::extract::Remedy;
    let cs = corrections(1, 7);
    let c = &cs[0];
    let after: Arc<dyn Model> = Arc::new(refitted(&cs));
    let (mut hits, mut taken) = (0, 0);
    for case in CASES {
        let mut m = Mesher::new(read(case), after.clone(), MeshParams::DEFAULT);
        while let StepOutcome::Stepped(r) = m.step().unwrap() {
            let Some(s) = m.sample_of(&r) else { continue };
            if r.kind == StepKind::Element && distance(&s.input, &c.input) < 0.5 * DEFAULT_RADIUS {
                let p = r.prediction.unwrap();
                assert_eq!(p.element_type, c.element_type);
                assert!((p.pn - c.pn).length() < 1e-9, "{:?} vs {:?}", p.pn, c.pn);
                hits += 1;
                if matches!(r.remedy, Remedy::None | Remedy::Rescaled) {
                    assert_eq!(s.element_type, c.element_type);
                    taken += 1;
                }
            }
        }
    }
    assert!(
        hits >= 1 && taken >= 1,
        "the corrected input is met again: {hits}, {taken}"
    );
}

fn quadex(args: &[&std::ffi::OsStr]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
        .args(args)
        .output()
        .unwrap()
}

fn run_ok(args: &[&std::ffi::OsStr]) -> String {
    let o = quadex(args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Bad input: exit code 2 and one line on stderr naming `what`.
fn refused(args: &[&std::ffi::OsStr], what: &str) {
    let o = quadex(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(what), "{err}");
}

#[test]
fn cli_fit_with_corrections_then_predict() {
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name);
    let refs = reference::shipped_dir();
    let (a, b) = (refs.join("lshape.msh"), refs.join("skewed_quad.msh"));
    let samples = out("s.csv");
    run_ok(&[
        "samples".as_ref(),
        a.as_os_str(),
        b.as_os_str(),
        "-o".as_ref(),
        samples.as_os_str(),
    ]);
    // Three corrections, written as a training set (the editor's export).
    let cs = corrections_in(&["square", "plate_hole"], 3, 5);
    let fixes = out("c.csv");
    TrainingSet {
        points: 7,
        samples: cs.clone(),
    }
    .write(&fixes)
    .unwrap();
    let (with, without) = (out("m.json"), out("plain.json"));
    let text = run_ok(&[
        "fit".as_ref(),
        samples.as_os_str(),
        "--corrections".as_ref(),
        fixes.as_os_str(),
        "--form".as_ref(),
        "quadratic".as_ref(),
        "--folds".as_ref(),
        "0".as_ref(),
        "-o".as_ref(),
        with.as_os_str(),
    ]);
    assert!(text.contains("and 3 corrections (radius 0.025)"), "{text}");
    run_ok(&[
        "fit".as_ref(),
        samples.as_os_str(),
        "--form".as_ref(),
        "quadratic".as_ref(),
        "--folds".as_ref(),
        "0".as_ref(),
        "-o".as_ref(),
        without.as_os_str(),
    ]);
    let file = ModelFile::from_json(&std::fs::read_to_string(&with).unwrap()).unwrap();
    assert_eq!((file.version, file.corrections.len()), (2, 3));
    assert_eq!(file.training.corrections, 3);
    let plain = ModelFile::from_json(&std::fs::read_to_string(&without).unwrap()).unwrap();
    // The corrections do not enter the global fit.
    assert_eq!(plain.coefficients, file.coefficients);
    assert_eq!(plain.version, 1);

    // predict: one `type,xn,yn` row per input row (the corrections file
    // itself: its type, xn, yn and source columns are ignored).
    let answers = |model: &std::path::Path| -> Vec<(u8, Point)> {
        let p = out("p.csv");
        let text = run_ok(&[
            "predict".as_ref(),
            model.as_os_str(),
            fixes.as_os_str(),
            "-o".as_ref(),
            p.as_os_str(),
        ]);
        assert!(text.contains("3 rows predicted"), "{text}");
        let csv = std::fs::read_to_string(&p).unwrap();
        let mut lines = csv.lines();
        assert_eq!(lines.next(), Some("type,xn,yn"));
        lines
            .map(|l| {
                let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
                (v[0] as u8, Point::new(v[1], v[2]))
            })
            .collect()
    };
    let got = answers(&with);
    assert_eq!(got.len(), 3);
    for (c, (t, pn)) in cs.iter().zip(&got) {
        assert_eq!(*t, c.element_type.number());
        assert!((*pn - c.pn).length() < 1e-9, "{pn:?} vs {:?}", c.pn);
    }
    let plain_answers = answers(&without);
    assert!(plain_answers
        .iter()
        .zip(&cs)
        .any(|((_, pn), c)| (*pn - c.pn).length() > 0.01));
    // Built-in models predict too.
    answers("default".as_ref());

    // Bad input: exit 2, one line.
    let bad = out("bad.csv");
    std::fs::write(&bad, "xl1,yl1,x0,y0\n1,2,3,4\n").unwrap();
    let p = out("p.csv");
    refused(
        &[
            "predict".as_ref(),
            with.as_os_str(),
            bad.as_os_str(),
            "-o".as_ref(),
            p.as_os_str(),
        ],
        "bad.csv: the header does not name leading points",
    );
    let five = out("five.csv");
    std::fs::write(
        &five,
        "xl2,yl2,xl1,yl1,x0,y0,xr1,yr1,xr2,yr2\n0,2,0,1,0,0,1,0,2,0\n",
    )
    .unwrap();
    refused(
        &[
            "predict".as_ref(),
            with.as_os_str(),
            five.as_os_str(),
            "-o".as_ref(),
            p.as_os_str(),
        ],
        "the rows have 5 input points, the model reads 7",
    );
    refused(
        &[
            "fit".as_ref(),
            samples.as_os_str(),
            "--corrections".as_ref(),
            five.as_os_str(),
            "-o".as_ref(),
            with.as_os_str(),
        ],
        "five.csv",
    );
    refused(
        &[
            "fit".as_ref(),
            samples.as_os_str(),
            "--corrections".as_ref(),
            fixes.as_os_str(),
            "--radius".as_ref(),
            "0".as_ref(),
            "-o".as_ref(),
            with.as_os_str(),
        ],
        "--radius",
    );
    // A model file whose corrections are broken is refused by `mesh`.
    let broken = out("broken.json");
    let text = std::fs::read_to_string(&with)
        .unwrap()
        .replace("\"radius\": 0.025", "\"radius\": -1.0");
    std::fs::write(&broken, text).unwrap();
    let square = common::bench().join("boundaries/square.poly");
    refused(
        &[
            "mesh".as_ref(),
            square.as_os_str(),
            "--model".as_ref(),
            broken.as_os_str(),
            "-o".as_ref(),
            out("x.msh").as_os_str(),
        ],
        "correction radius",
    );
}

#[test]
fn quadex_mesh_uses_the_corrections_a_model_file_carries() {
    // Corrections on the annulus; the refitted model saved as a file;
    // `quadex mesh --model FILE` gives the mesh the model gives in process,
    // which is not the shipped model's.
    let cs = corrections_in(&["annulus"], 3, 11);
    let model = refitted(&cs);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("corrected.json");
    std::fs::write(
        &file,
        ModelFile::of_model(&model, Default::default(), None).to_json(),
    )
    .unwrap();
    let annulus = common::bench().join("boundaries/annulus.poly");
    let msh = dir.path().join("a.msh");
    run_ok(&[
        "mesh".as_ref(),
        annulus.as_os_str(),
        "--model".as_ref(),
        file.as_os_str(),
        "-o".as_ref(),
        msh.as_os_str(),
    ]);
    let b = read("annulus");
    let (mine, _) = mesh_boundary(&b, Arc::new(model), &Params::DEFAULT, |_| {}).unwrap();
    let (theirs, _) = mesh_boundary(&b, shipped(), &Params::DEFAULT, |_| {}).unwrap();
    let written = std::fs::read_to_string(&msh).unwrap();
    assert_eq!(written, quadex::io::msh::write_msh41(&mine));
    assert_ne!(mine, theirs);
}

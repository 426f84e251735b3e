//! The learning loop end to end: reference meshes → samples → fit → model
//! file → meshing with the fitted model.

use quadex::extract::{MeshParams, Mesher, StepOutcome};
use quadex::fit::{fit_model, FitParams};
use quadex::io::msh::write_msh41;
use quadex::model::fitted::Coefficients;
use quadex::model::{self, ElementType, Form, Model, ModelFile};
use quadex::pipeline::{mesh_boundary, Params};
use quadex::reference;
use quadex::samples::{collect, CollectParams, Source, TrainingSet};
use quadex::{Point, QuadMesh};
use std::path::PathBuf;
use std::sync::Arc;

fn shipped_reference() -> Vec<(String, QuadMesh)> {
    reference::read_shipped().unwrap()
}

#[test]
fn shipped_reference_meshes_are_what_the_generator_makes() {
    for (name, mesh) in reference::all().unwrap() {
        mesh.check_finished().unwrap();
        let shipped =
            std::fs::read_to_string(reference::shipped_dir().join(format!("{name}.msh"))).unwrap();
        assert_eq!(
            write_msh41(&mesh),
            shipped,
            "{name}: rebuild with the example"
        );
    }
}

/// Three unit squares in an L (hand-drawn):
///
/// ```text
/// 6---7
/// | 2 |
/// 3---4---5
/// | 0 | 1 |
/// 0---1---2
/// ```
fn small_l() -> QuadMesh {
    let pts = vec![
        Point::new(0.0, 0.0),
        Point::new(1.0, 0.0),
        Point::new(2.0, 0.0),
        Point::new(0.0, 1.0),
        Point::new(1.0, 1.0),
        Point::new(2.0, 1.0),
        Point::new(0.0, 2.0),
        Point::new(1.0, 2.0),
    ];
    QuadMesh::from_quads(pts, vec![[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6]]).unwrap()
}

/// The 5-point samples `(l2, l1, r2, type, Pn)` (normalised) of `m`.
fn patterns(m: &QuadMesh) -> Vec<([Point; 3], ElementType, Point)> {
    collect(m, 2, &CollectParams::DEFAULT, "l")
        .into_iter()
        .map(|x| {
            assert_eq!(x.input.right[0], Point::X);
            assert!(
                matches!(&x.source, Source::Mesh { file, element } if file == "l" && *element < 3)
            );
            (
                [x.input.left[1], x.input.left[0], x.input.right[1]],
                x.element_type,
                x.pn,
            )
        })
        .collect()
}

#[test]
fn samples_of_a_hand_checked_mesh() {
    let s = patterns(&small_l());
    let p = Point::new;
    // Type 0 at (0,0) of square 0: r1 = (1,0), Pn = (1,1), l1 = (0,1); the
    // path goes straight on to r2 = (2,0) and l2 = (0,2) (180° each).
    let t0 = (
        [p(0.0, 2.0), p(0.0, 1.0), p(2.0, 0.0)],
        ElementType::New,
        p(1.0, 1.0),
    );
    // Type 1 at (1,0) of square 1: r1 = (2,0), r2 = Pn = (2,1), l1 = (1,1),
    // then l2 = (1,2) (180° at l1; (0,1) would turn 270°). Frame at (1,0).
    let t1 = (
        [p(0.0, 2.0), p(0.0, 1.0), p(1.0, 1.0)],
        ElementType::Right,
        p(1.0, 1.0),
    );
    // Type 2 at (0,0) of square 0: l2 = Pn = (1,1), l1 = (0,1), r1 = (1,0),
    // then r2 = (2,0).
    let t2 = (
        [p(1.0, 1.0), p(0.0, 1.0), p(2.0, 0.0)],
        ElementType::Left,
        p(1.0, 1.0),
    );
    // Counted by hand, corner by corner: the straight type-0 path exists
    // only at (0,0). The type-1 pattern comes from (0,0) and (0,1) of
    // square 0, (1,0) and (2,0) of square 1 and (1,2) of square 2; the
    // type-2 pattern from their mirror images across the diagonal.
    assert_eq!(s.len(), 11, "{s:?}");
    for (want, count) in [(t0, 1), (t1, 5), (t2, 5)] {
        assert_eq!(
            s.iter().filter(|x| **x == want).count(),
            count,
            "{want:?} in {s:?}"
        );
    }
    // Types 1 and 2 carry Pn as a leading point.
    for (pts, t, pn) in &s {
        match t {
            ElementType::Right => assert_eq!(*pn, pts[2]),
            ElementType::Left => assert_eq!(*pn, pts[0]),
            ElementType::New => {}
        }
    }
    // A reflex turn (270° at (1,1) going to (0,1) or (1,0)) never appears:
    // no sample has l2 or r2 at a right angle back across the element.
    assert!(!s.contains(&(
        [p(-1.0, 1.0), p(0.0, 1.0), p(2.0, 0.0)],
        ElementType::New,
        p(1.0, 1.0)
    )));
}

#[test]
fn model_file_round_trip_and_checks() {
    let meshes = shipped_reference();
    let set = TrainingSet::collect(&meshes[..2], 5, &CollectParams::DEFAULT);
    let params = FitParams {
        folds: 3,
        ..FitParams::DEFAULT
    };
    for form in Form::ALL {
        let (file, reports) = fit_model(&set, Some(form), "t", &params).unwrap();
        assert_eq!(reports.len(), 1);
        assert_eq!(file.coefficients.form(), form);
        assert_eq!(file.points, 5);
        assert_eq!(file.training.samples, set.len());
        let back = ModelFile::from_json(&file.to_json()).unwrap();
        assert_eq!(back, file);
        // A broken file is refused with a reason.
        let bad = file.to_json().replace("\"version\": 1", "\"version\": 99");
        assert!(ModelFile::from_json(&bad)
            .unwrap_err()
            .to_string()
            .contains("version"));
    }
    let truncated = r#"{"format": "quadex-model", "version": 1}"#;
    assert!(ModelFile::from_json(truncated).is_err());
}

#[test]
fn the_shipped_default_model_is_the_refit_of_the_reference_meshes() {
    // The editor's refit with nothing added (`fit::refit` on the reference
    // meshes' samples, no folds: the coefficients come from the full set
    // either way) gives the shipped model's coefficients exactly.
    let params = FitParams {
        folds: 0,
        ..FitParams::DEFAULT
    };
    let base = reference::training_set(&shipped_reference(), 7);
    let rebuilt = quadex::fit::refit(
        &base,
        &TrainingSet::new(7),
        Form::Quadratic,
        "refit 1",
        &params,
    )
    .unwrap();
    let shipped = ModelFile::from_json(model::DEFAULT_MODEL_JSON).unwrap();
    assert_eq!(rebuilt.training, shipped.training);
    assert_eq!(rebuilt.coefficients, shipped.coefficients);
    assert!(rebuilt.corrections.is_empty() && shipped.corrections.is_empty());
    assert!(matches!(shipped.coefficients, Coefficients::Quadratic(_)));
    // The shipped file is what `reference::default_model` writes.
    let again = reference::default_model(&shipped_reference(), &params).unwrap();
    assert_eq!(again.coefficients, shipped.coefficients);
    // The annulus meshes identically with either.
    let bench = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries");
    let b = quadex::io::read_boundary(&bench.join("annulus.poly")).unwrap();
    let mesh_with = |m: Arc<dyn Model>| mesh_boundary(&b, m, &Params::DEFAULT, |_| {}).unwrap().0;
    assert_eq!(
        mesh_with(Arc::new(rebuilt.model())),
        mesh_with(Arc::from(model::builtin("default").unwrap()))
    );
    // Its held-out figures beat thesis Table 8 (R = 0.84, 0.78, 0.79 on
    // training data). The extraction of the generated domain is less
    // regular than the mapped meshes, so Xn and Yn fit less tightly than
    // the 0.95 the mapped meshes alone reach (see
    // `the_richer_form_reaches_the_fit_targets_on_mapped_reference_samples`);
    // the model meshes the benchmark better for it (assets/README.md).
    let f = shipped.figures.unwrap();
    assert!(f.type_.holdout.accuracy >= 0.95);
    assert!(f.xn.holdout.r >= 0.85 && f.yn.holdout.r >= 0.9);
}

#[test]
fn the_shipped_ann_model_is_the_fit_of_the_reference_meshes() {
    // Trained again from the same samples and seed: the same weights, and
    // the figures the file carries meet the fit targets.
    let params = FitParams {
        folds: 0,
        ..FitParams::DEFAULT
    };
    let rebuilt = reference::ann_model(&shipped_reference(), &params).unwrap();
    let shipped = ModelFile::from_json(model::ANN_MODEL_JSON).unwrap();
    assert!(matches!(shipped.coefficients, Coefficients::Ann(_)));
    assert_eq!(rebuilt.coefficients, shipped.coefficients);
    let f = shipped.figures.unwrap();
    assert!(f.type_.holdout.accuracy >= 0.95);
    assert!(f.xn.holdout.r >= 0.85 && f.yn.holdout.r >= 0.9);
    // It meshes as a built-in model.
    let ann: Arc<dyn Model> = Arc::from(model::builtin("ann").unwrap());
    assert_eq!(ann.leading_points(), Some(3));
    let bench = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries");
    let b = quadex::io::read_boundary(&bench.join("plate_hole.poly")).unwrap();
    let (mesh, _) = mesh_boundary(&b, ann, &Params::DEFAULT, |_| {}).unwrap();
    mesh.check_finished().unwrap();
}

#[test]
fn the_richer_form_reaches_the_fit_targets_on_mapped_reference_samples() {
    // Issue target: held-out R ≥ 0.95 for Xn and Yn, type accuracy ≥ 95 %,
    // on the mapped reference meshes (the generated domain's extraction is
    // less regular; see the shipped model's test).
    let mapped: Vec<(String, QuadMesh)> = shipped_reference()
        .into_iter()
        .filter(|(name, _)| !name.starts_with(reference::GENERATED_NAME))
        .collect();
    assert_eq!(mapped.len(), reference::NAMES.len() - 1);
    let set = TrainingSet::collect(&mapped, 7, &CollectParams::DEFAULT);
    let (_, reports) = fit_model(&set, Some(Form::Quadratic), "q", &FitParams::DEFAULT).unwrap();
    let r = &reports[0];
    assert!(r.xn.holdout.r >= 0.95, "{}", r.table());
    assert!(r.yn.holdout.r >= 0.95, "{}", r.table());
    assert!(r.type_.holdout.accuracy >= 0.95, "{}", r.table());
}

#[test]
fn default_model_meshes_benchmark_cases_with_invariants_after_every_step() {
    let model: Arc<dyn Model> = Arc::from(model::builtin("default").unwrap());
    assert_eq!(model.leading_points(), Some(3));
    let bench = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries");
    for case in ["square", "lshape", "irregular", "plate_hole", "annulus"] {
        let b = quadex::io::read_boundary(&bench.join(format!("{case}.poly"))).unwrap();
        let mut m = Mesher::new(b.clone(), model.clone(), MeshParams::DEFAULT);
        while let StepOutcome::Stepped(_) = m.step().unwrap() {
            m.check_invariants().unwrap();
        }
        let mesh = quadex::pipeline::finish(&m, &quadex::FinishParams::DEFAULT).unwrap();
        mesh.check_finished().unwrap();
        // Same input, same mesh.
        let (again, _) = mesh_boundary(&b, model.clone(), &Params::DEFAULT, |_| {}).unwrap();
        assert_eq!(again, mesh, "{case}");
    }
}

#[test]
fn pure_model_counts_rejected_predictions() {
    let bench = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries");
    let b = quadex::io::read_boundary(&bench.join("lshape.poly")).unwrap();
    let params = Params {
        extract: MeshParams {
            pure_model: true,
            ..MeshParams::DEFAULT
        },
        ..Params::DEFAULT
    };
    let thesis: Arc<dyn Model> = Arc::from(model::builtin("thesis").unwrap());
    let (_, stats) = mesh_boundary(&b, thesis, &params, |_| {}).unwrap();
    let (ok, all) = stats.model_valid();
    assert!(all > ok && stats.rejected_predictions > 0, "{ok} of {all}");
    let rules: Arc<dyn Model> = Arc::from(model::builtin("rules").unwrap());
    let (_, stats) = mesh_boundary(&b, rules, &params, |_| {}).unwrap();
    let (ok, all) = stats.model_valid();
    assert_eq!(ok, all, "the rules never fail on the L-shape");
}

#[test]
fn a_step_and_the_same_element_as_a_correction_give_the_same_sample() {
    use quadex::extract::Correction;
    let bench = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries");
    let b = quadex::io::read_boundary(&bench.join("square.poly")).unwrap();
    let rules: Arc<dyn Model> = Arc::from(model::builtin("rules").unwrap());
    let mut m = Mesher::new(b, rules, MeshParams::DEFAULT);
    let StepOutcome::Stepped(r) = m.step().unwrap() else {
        panic!("the square has steps");
    };
    let auto = m.sample_of(&r).expect("an element step has a sample");
    assert_eq!(auto.n(), 3);
    assert_eq!(auto.source, Source::Correction);
    // The first element at a square corner of a uniform boundary: a unit
    // square in the normalised frame.
    assert_eq!(auto.element_type, ElementType::New);
    assert!(
        (auto.pn - Point::new(1.0, 1.0)).length() < 1e-9,
        "{:?}",
        auto.pn
    );
    // The same element given as a correction.
    let pn = m.mesh().nodes[r.new_nodes[0] as usize];
    assert!(m.undo());
    let c = Correction {
        reference: r.reference.unwrap(),
        element_type: ElementType::New,
        pn: Some(pn),
        snap_to: None,
    };
    let rc = m.correct(&c).unwrap();
    let corrected = m.sample_of(&rc).expect("a correction has a sample");
    assert_eq!(corrected, auto);
    // Other steps have none.
    let mut other = rc.clone();
    other.kind = quadex::extract::StepKind::Fill;
    assert!(m.sample_of(&other).is_none());
}

#[test]
fn cli_samples_fit_mesh_and_factors() {
    let bin = env!("CARGO_BIN_EXE_quadex");
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name);
    let run = |args: &[&std::ffi::OsStr]| {
        let o = std::process::Command::new(bin).args(args).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let refs = reference::shipped_dir();
    let (a, b) = (refs.join("lshape.msh"), refs.join("skewed_quad.msh"));
    let csv = out("s.csv");
    let text = run(&[
        "samples".as_ref(),
        a.as_os_str(),
        b.as_os_str(),
        "--points".as_ref(),
        "7".as_ref(),
        "-o".as_ref(),
        csv.as_os_str(),
    ]);
    assert!(text.contains("duplicates dropped"), "{text}");
    let set = TrainingSet::read(&csv).unwrap();
    assert_eq!(set.points, 7);
    assert!(set.len() > 100);
    let (model_file, report) = (out("m.json"), out("r.json"));
    let text = run(&[
        "fit".as_ref(),
        csv.as_os_str(),
        "-o".as_ref(),
        model_file.as_os_str(),
        "--report".as_ref(),
        report.as_os_str(),
        "--folds".as_ref(),
        "3".as_ref(),
    ]);
    // Both forms' tables are printed; the report has the issue's fields.
    assert!(
        text.contains("form thesis")
            && text.contains("form quadratic")
            && text.contains("form ann"),
        "{text}"
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    for output in ["type", "xn", "yn"] {
        for set in ["train", "holdout"] {
            for field in ["sse", "rmse", "r", "dc"] {
                assert!(r[output][set][field].is_number(), "{output}.{set}.{field}");
            }
        }
    }
    assert!(r["type"]["holdout"]["accuracy"].is_number());
    assert_eq!(r["forms"].as_array().unwrap().len(), 3);
    // The fitted model meshes a benchmark boundary.
    let square =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries/square.poly");
    let msh = out("square.msh");
    run(&[
        "mesh".as_ref(),
        square.as_os_str(),
        "-o".as_ref(),
        msh.as_os_str(),
        "--model".as_ref(),
        model_file.as_os_str(),
    ]);
    quadex::io::read_mesh(&msh)
        .unwrap()
        .check_finished()
        .unwrap();
    // Factors from the set, cut down to 5 points, and at 7.
    let text = run(&[
        "factors".as_ref(),
        csv.as_os_str(),
        "--points".as_ref(),
        "5,7".as_ref(),
    ]);
    assert!(
        text.contains("5 input points") && text.contains("7 input points"),
        "{text}"
    );
    // A model file that is not one is refused as bad input.
    let o = std::process::Command::new(bin)
        .args([
            "mesh".as_ref(),
            square.as_os_str(),
            "-o".as_ref(),
            msh.as_os_str(),
            "--model".as_ref(),
            csv.as_os_str(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_model_set_mid_run_survives_undo_and_replay() {
    let bench = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries");
    let b = quadex::io::read_boundary(&bench.join("plate_hole.poly")).unwrap();
    let rules: Arc<dyn Model> = Arc::from(model::builtin("rules").unwrap());
    let default: Arc<dyn Model> = Arc::from(model::builtin("default").unwrap());
    let mut m = Mesher::new(b, rules, MeshParams::DEFAULT);
    for _ in 0..10 {
        m.step().unwrap();
    }
    m.set_model(default);
    for _ in 0..10 {
        m.step().unwrap();
    }
    let before = m.mesh().clone();
    // Undo replays the first 10 steps with the rules and the next 9 with
    // the new model, then the same step again gives the same mesh.
    assert!(m.undo());
    assert_eq!(m.model().name(), "default");
    m.step().unwrap();
    assert_eq!(m.mesh(), &before);
    m.check_invariants().unwrap();
}

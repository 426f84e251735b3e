//! The step ladder and the engine's tuning seen from outside: every step
//! report names the rung that took it, the rung agrees with what the step
//! did, the step counts add up by rung, and a changed `Tuning` is read by
//! the engine and written to parameter files only where it differs.

mod common;

use quadex::extract::{MeshError, MeshParams, Rung, StepKind, StepOutcome, Tuning, LADDER};
use quadex::{Boundary, Mesher};
use std::collections::BTreeSet;
use std::sync::Arc;

fn mesher(case: &str, params: MeshParams) -> Mesher {
    let path = common::bench().join(case);
    let b: Boundary = quadex::io::read_boundary(&path).expect("a benchmark boundary");
    let model = Arc::new(quadex::model::default_model().expect("the shipped model"));
    Mesher::new(b, model, params)
}

/// The step kinds a rung may make.
fn kinds_of(rung: Rung) -> &'static [StepKind] {
    use StepKind::*;
    match rung {
        Rung::FillDue | Rung::FillStalled | Rung::FillLayers | Rung::Fill | Rung::Rewind => {
            &[Fill, RipUp]
        }
        Rung::RowStart => &[Square, Bridge],
        Rung::SmallLoop => &[Close4, Close6],
        Rung::MappedGrid | Rung::Strip | Rung::Band => &[Mapped],
        Rung::Fan => &[Fan],
        Rung::Notch => &[Notch],
        Rung::Queue => &[Element, Transition, Seam],
        Rung::SharpSeam => &[Seam],
        Rung::SmallSplit | Rung::Split => &[Split],
        Rung::Square | Rung::HoleRow => &[Square],
        Rung::Relaxed => &[Element],
        Rung::Relax => &[Relax],
        Rung::Bridge => &[Bridge],
        Rung::RipUp => &[RipUp, Split],
        Rung::Refan => &[Refan],
        Rung::User => &[Correction],
    }
}

#[test]
fn every_step_names_the_rung_that_took_it() {
    let mut seen = BTreeSet::new();
    for case in [
        "boundaries/annulus.poly",
        "boundaries/irregular.poly",
        "boundaries/plate_hole.poly",
        "boundaries/naca0012.poly",
        "boundaries/wedge30.poly",
        "peer/freemesh_bird1.poly",
        "peer/freemesh_tool1.poly",
        "edge/far_offset.poly",
    ] {
        let mut m = mesher(case, MeshParams::DEFAULT);
        while let StepOutcome::Stepped(r) = m.step().expect("the case meshes") {
            assert!(
                LADDER.contains(&r.rung) || r.rung == Rung::Rewind,
                "{case} step {}: rung {:?} is not on the ladder",
                r.index,
                r.rung
            );
            assert!(
                kinds_of(r.rung).contains(&r.kind),
                "{case} step {}: rung {} made a {:?} step",
                r.index,
                r.rung.name(),
                r.kind
            );
            m.check_invariants()
                .unwrap_or_else(|e| panic!("{case} step {}: {e}", r.index));
            seen.insert(r.rung);
        }
        let stats = m.stats();
        assert_eq!(
            stats.by_rung.values().sum::<usize>(),
            stats.steps,
            "{case}: steps by rung add up to the steps"
        );
    }
    // The queue does most of the work; rows start and small loops close
    // on every case.
    for rung in [Rung::Queue, Rung::RowStart, Rung::SmallLoop] {
        assert!(seen.contains(&rung), "no case stepped on {}", rung.name());
    }
}

#[test]
fn rung_names_are_distinct_and_the_ladder_lists_each_rung_once() {
    let names: BTreeSet<&str> = LADDER.iter().map(|r| r.name()).collect();
    assert_eq!(names.len(), LADDER.len());
    assert!(!LADDER.contains(&Rung::Rewind) && !LADDER.contains(&Rung::User));
    assert_eq!(LADDER.first(), Some(&Rung::FillDue));
    assert_eq!(LADDER.last(), Some(&Rung::Fill));
}

#[test]
fn the_engine_reads_its_tuning() {
    // A step budget of five steps stops the run after five steps.
    let mut params = MeshParams::DEFAULT;
    params.tuning.fill.step_limit_per_element = 0;
    params.tuning.fill.step_limit_extra = 5;
    let mut m = mesher("boundaries/annulus.poly", params);
    let mut steps = 0;
    let err = loop {
        match m.step() {
            Ok(StepOutcome::Stepped(_)) => steps += 1,
            Ok(StepOutcome::Done) => panic!("the annulus meshed in {steps} steps"),
            Err(e) => break e,
        }
    };
    assert_eq!(steps, 5);
    assert!(
        matches!(err, MeshError::StepLimit { limit: 5, .. }),
        "{err}"
    );

    // Mapped grids need loops of 8 nodes or more: capped at 7, none is
    // looked at, and the loops the default closes by a grid are meshed by
    // the other rungs.
    let run = |params: MeshParams| {
        let mut m = mesher("boundaries/wedge30.poly", params);
        m.run(|_| {}).expect("the wedge meshes");
        m.stats().clone()
    };
    let default = run(MeshParams::DEFAULT);
    let mut params = MeshParams::DEFAULT;
    params.tuning.mapped.max_loop = 7;
    let capped = run(params);
    assert!(
        default.count(StepKind::Mapped) > 0,
        "the wedge closes by grids"
    );
    assert_eq!(capped.count(StepKind::Mapped), 0);
    assert_eq!(capped.by_rung.get(&Rung::MappedGrid), None);
}

#[test]
fn tuning_is_written_only_where_it_differs_and_read_back_in_part() {
    let json = serde_json::to_string(&MeshParams::DEFAULT).expect("params as JSON");
    assert!(
        !json.contains("tuning"),
        "default tuning is not written: {json}"
    );

    let mut params = MeshParams::DEFAULT;
    params.tuning.ladder.rip_ups = 7;
    params.tuning.watch.window = 1024;
    let json = serde_json::to_string(&params).expect("params as JSON");
    let back: MeshParams = serde_json::from_str(&json).expect("params read back");
    assert_eq!(back, params);

    // A file that sets one value keeps every other default.
    let part: MeshParams =
        serde_json::from_str(r#"{"tuning": {"ladder": {"rip_ups": 3}}}"#).expect("a partial file");
    let mut want = Tuning::DEFAULT;
    want.ladder.rip_ups = 3;
    assert_eq!(part.tuning, want);
    assert_eq!(
        MeshParams {
            tuning: Tuning::DEFAULT,
            ..part
        },
        MeshParams::DEFAULT
    );
}

#[test]
fn the_command_line_reads_a_tuning_file_and_refuses_a_wrong_field() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let bin = env!("CARGO_BIN_EXE_quadex");
    let case = common::bench().join("boundaries/wedge30.poly");
    let run = |tuning: &str| {
        let t = dir.path().join("tuning.json");
        std::fs::write(&t, tuning).expect("tuning written");
        let report = dir.path().join("report.json");
        let out = std::process::Command::new(bin)
            .arg("mesh")
            .arg(&case)
            .arg("-o")
            .arg(dir.path().join("wedge.msh"))
            .arg("--report")
            .arg(&report)
            .arg("--tuning")
            .arg(&t)
            .output()
            .expect("quadex runs");
        let by_rung = std::fs::read_to_string(&report)
            .ok()
            .map(|r| {
                let v: serde_json::Value = serde_json::from_str(&r).expect("a JSON report");
                v["steps"]["by_rung"].clone()
            })
            .unwrap_or_default();
        (out, by_rung)
    };
    let (out, by_rung) = run(r#"{"mapped": {"max_loop": 400}}"#);
    assert!(out.status.success());
    assert!(
        by_rung["MappedGrid"].as_u64().is_some_and(|n| n > 0),
        "{by_rung}"
    );
    let (out, by_rung) = run(r#"{"mapped": {"max_loop": 7}}"#);
    assert!(out.status.success());
    assert!(by_rung.get("MappedGrid").is_none(), "{by_rung}");
    let (out, _) = run(r#"{"mapped": {"max_loops": 7}}"#);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("unknown field `max_loops`"), "{err}");
}

//! Meshes the benchmark boundaries (`bench/boundaries`, `peer`, `edge`;
//! the two largest disks are left to the benchmark) with default settings.
//! Every mesh produced must tile its domain exactly (checked after
//! smoothing), keep the boundary nodes and be all-quad, and every case must
//! finish by extraction alone (no region fill). With the shipped default
//! model (the command line's default) no quad may have a scaled Jacobian
//! below 0.2 or sides more than 10 times apart (the thesis's aspect and
//! taper limit).

mod common;

use quadex::extract::{MeshParams, Mesher, StepKind, StepOutcome};
use quadex::model::RulesModel;
use std::sync::Arc;

#[test]
fn benchmark_cases_mesh_validly() {
    let mut finished = Vec::new();
    let mut failures = Vec::new();
    for folder in ["boundaries", "peer", "edge"] {
        for path in common::cases(folder) {
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            if name == "disk1600" || name == "disk6400" {
                continue;
            }
            let b = quadex::io::read_boundary(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
            // Next to the origin, as `quadex mesh` and `mesh_boundary` mesh.
            let (b, _) = b.to_local();
            let area = b.area();
            let model = Arc::new(quadex::model::default_model().unwrap());
            let mut m = Mesher::new(b, model, MeshParams::DEFAULT);
            match m.run(|_| {}) {
                Ok(()) => {
                    let mesh =
                        quadex::pipeline::finish(&m, &quadex::FinishParams::DEFAULT).unwrap();
                    let q = quadex::MeshQuality::of(&mesh);
                    if q.sj_min < 0.2 {
                        failures.push((name.clone(), format!("scaled Jacobian {}", q.sj_min)));
                    }
                    if q.taper_max > 10.0 || q.aspect_max > 10.0 {
                        failures.push((
                            name.clone(),
                            format!("taper {} aspect {}", q.taper_max, q.aspect_max),
                        ));
                    }
                    if m.stats().count(StepKind::Fill) > 0 {
                        failures.push((name.clone(), "region fill".into()));
                    }
                    mesh.check_finished()
                        .unwrap_or_else(|e| panic!("{name}: {e}"));
                    assert!(
                        (mesh.domain_area() - area).abs() <= 1e-9 * area,
                        "{name}: area"
                    );
                    finished.push(name);
                }
                Err(e) => failures.push((name, e.to_string())),
            }
        }
    }
    println!("finished {} cases", finished.len());
    assert!(
        failures.is_empty(),
        "cases that do not finish: {failures:?}"
    );
}

/// On small cases the front and the partial mesh are checked after every
/// step, with extraction to the end (the default) and with the fill inside
/// the second layer.
#[test]
fn invariants_hold_after_every_step() {
    let names = [
        "square",
        "lshape",
        "irregular",
        "circle",
        "wedge30",
        "annulus",
        "plate_hole",
        "star8",
    ];
    for (name, layers) in names.iter().flat_map(|n| [(n, None), (n, Some(2))]) {
        let b = quadex::io::read_boundary(&common::bench().join(format!("boundaries/{name}.poly")))
            .unwrap();
        let params = MeshParams {
            fill_after_layers: layers,
            ..MeshParams::DEFAULT
        };
        let mut m = Mesher::new(b, Arc::new(RulesModel::DEFAULT), params);
        let mut steps = 0;
        while let StepOutcome::Stepped(r) = m.step().unwrap_or_else(|e| panic!("{name}: {e}")) {
            steps += 1;
            m.check_invariants().unwrap_or_else(|e| {
                panic!("{name} ({layers:?}) after step {steps} ({:?}): {e}", r.kind)
            });
        }
        assert!(m.is_done());
        quadex::pipeline::finish(&m, &quadex::FinishParams::DEFAULT)
            .unwrap()
            .check_finished()
            .unwrap();
    }
}

/// Undo replays: stepping, undoing and stepping again gives the same mesh.
#[test]
fn undo_returns_to_the_same_state() {
    let b = quadex::io::read_boundary(&common::bench().join("boundaries/lshape.poly")).unwrap();
    let mut m = Mesher::new(b, Arc::new(RulesModel::DEFAULT), MeshParams::DEFAULT);
    for _ in 0..7 {
        m.step().unwrap();
    }
    let snapshot = m.mesh().clone();
    m.step().unwrap();
    assert_ne!(m.mesh(), &snapshot);
    assert!(m.undo());
    assert_eq!(m.mesh(), &snapshot);
    assert_eq!(m.steps(), 7);
}

/// Undo on a long run replays from a checkpoint kept behind the end
/// (`CHECKPOINT_BEHIND`), switching models where the run did: each undo
/// gives the mesh a run stopped there gives.
#[test]
fn undo_on_a_long_run_matches_a_run_stopped_there() {
    use quadex::extract::CHECKPOINT_BEHIND;
    let b = quadex::io::read_boundary(&common::bench().join("boundaries/disk400.poly")).unwrap();
    let shipped: Arc<dyn quadex::model::Model> = Arc::new(quadex::model::default_model().unwrap());
    let rules: Arc<dyn quadex::model::Model> = Arc::new(RulesModel::DEFAULT);
    // Steps in all, and the step after which the model changes: past the
    // first checkpoint, so replays from it must switch models too.
    let (total, switch) = (3 * CHECKPOINT_BEHIND, 2 * CHECKPOINT_BEHIND + 100);
    let run_to = |n: usize| {
        let mut m = Mesher::new(b.clone(), shipped.clone(), MeshParams::DEFAULT);
        for k in 0..n {
            if k == switch {
                m.set_model(rules.clone());
            }
            m.step().unwrap();
        }
        m
    };
    let mut m = run_to(total);
    let end = m.mesh().clone();
    // Undo back across the model change and the first checkpoint.
    let back = total - CHECKPOINT_BEHIND - 50;
    for n in (back..total).rev() {
        assert!(m.undo());
        if n % 97 == 0 || n == back || n == switch {
            let stopped = run_to(n);
            assert_eq!(m.mesh(), stopped.mesh(), "after undoing to step {n}");
            m.check_invariants().unwrap();
        }
    }
    assert_eq!(m.steps(), back);
    assert_ne!(m.mesh(), &end);
}

/// A run's progress is the share of the domain's area meshed: on a disk,
/// whose rows keep their node count as they go in, it is past half while
/// the front has kept more than half its nodes, and it ends at 1.
#[test]
fn run_progress_follows_the_area_meshed() {
    let b = quadex::io::read_boundary(&common::bench().join("boundaries/disk400.poly")).unwrap();
    let start = b.node_count();
    let model = Arc::new(quadex::model::default_model().unwrap());
    let mut m = Mesher::new(b, model, MeshParams::DEFAULT);
    let mut seen = Vec::new();
    m.run(|at| seen.push(at)).unwrap();
    let last = seen.last().unwrap();
    assert_eq!((last.front, last.meshed), (0, 1.0));
    assert!(seen.iter().all(|at| (0.0..=1.0).contains(&at.meshed)));
    let half = seen.iter().find(|at| at.meshed > 0.5).unwrap();
    assert!(
        half.front * 2 > start,
        "half the area meshed with {} of {start} front nodes left",
        half.front
    );
}

/// Redo takes undone steps again, corrections included, and a new step
/// clears what was undone.
#[test]
fn redo_takes_undone_steps_again() {
    use quadex::extract::{Correction, StepOutcome};
    let b = quadex::io::read_boundary(&common::bench().join("boundaries/lshape.poly")).unwrap();
    let mut m = Mesher::new(b, Arc::new(RulesModel::DEFAULT), MeshParams::DEFAULT);
    for _ in 0..5 {
        m.step().unwrap();
    }
    // A correction: a type-0 element at the next step's reference point,
    // with Pn where the model put it.
    let mut probe = m.clone();
    let StepOutcome::Stepped(r) = probe.step().unwrap() else {
        panic!("the mesh is not done")
    };
    let c = Correction {
        reference: r.reference.unwrap(),
        element_type: quadex::ElementType::New,
        pn: r.predicted_pn,
        snap_to: None,
    };
    m.correct(&c).unwrap();
    m.step().unwrap();
    let after = m.mesh().clone();
    assert!(m.undo() && m.undo());
    assert_eq!(m.redo_len(), 2);
    let redone = m.redo().unwrap().unwrap();
    assert_eq!(redone.kind, quadex::extract::StepKind::Correction);
    m.redo().unwrap().unwrap();
    assert_eq!(m.mesh(), &after);
    assert_eq!(m.redo().unwrap(), None);
    m.check_invariants().unwrap();
    // A new step after an undo drops the undone one.
    assert!(m.undo());
    m.step().unwrap();
    assert_eq!(m.redo_len(), 0);
}

/// Same input, same bytes.
#[test]
fn output_is_deterministic() {
    let b = quadex::io::read_boundary(&common::bench().join("boundaries/circle.poly")).unwrap();
    let run = || {
        let (mesh, _) = quadex::mesh_boundary(
            &b,
            Arc::new(RulesModel::DEFAULT),
            &quadex::Params::DEFAULT,
            |_| {},
        )
        .unwrap();
        quadex::io::MeshFormat::Msh41.render(&mesh)
    };
    assert_eq!(run(), run());
}

/// The textbook cases finish by extraction alone even with the fill turned
/// off: a plate with a hole, the annulus, an aerofoil in a box and a star.
#[test]
fn textbook_cases_finish_without_fill() {
    for name in ["plate_hole", "annulus", "naca0012", "star8"] {
        let b = quadex::io::read_boundary(&common::bench().join(format!("boundaries/{name}.poly")))
            .unwrap();
        let model = Arc::new(quadex::model::default_model().unwrap());
        let params = MeshParams {
            fill: false,
            ..MeshParams::DEFAULT
        };
        let mut m = Mesher::new(b, model, params);
        m.run(|_| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(m.stats().count(StepKind::Fill), 0, "{name}");
        let mesh = quadex::pipeline::finish(&m, &quadex::FinishParams::DEFAULT).unwrap();
        mesh.check_finished()
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let q = quadex::MeshQuality::of(&mesh);
        assert!(q.sj_min >= 0.5, "{name}: scaled Jacobian {}", q.sj_min);
    }
}

/// `--layers K` holds for both reference-point strategies: the region
/// inside the first layers is filled, and extraction to the end needs no
/// fill.
#[test]
fn both_strategies_follow_the_layer_count() {
    use quadex::extract::Strategy;
    let b = quadex::io::read_boundary(&common::bench().join("boundaries/plate_hole.poly")).unwrap();
    for strategy in [Strategy::A, Strategy::B] {
        let run = |layers: Option<u32>| {
            let params = MeshParams {
                strategy,
                fill_after_layers: layers,
                ..MeshParams::DEFAULT
            };
            let model = Arc::new(quadex::model::default_model().unwrap());
            let mut m = Mesher::new(b.clone(), model, params);
            m.run(|_| {}).unwrap();
            m.stats().clone()
        };
        let two = run(Some(1));
        let all = run(None);
        assert_eq!(two.count(StepKind::Fill), 1, "{strategy:?} with one layer");
        assert_eq!(all.count(StepKind::Fill), 0, "{strategy:?} to the end");
        assert!(two.steps < all.steps, "{strategy:?}");
    }
}

/// A valid domain with a straight side of three edges against one (issue 18,
/// R05: a 1 × 0.02 rectangle of six nodes) closes with the strip pattern.
#[test]
fn a_thin_six_node_rectangle_meshes() {
    let b = quadex::io::read_boundary(&common::repro().join("R05_rect_1x0.02_6nodes_exit1.poly"))
        .unwrap();
    let model = Arc::new(quadex::model::default_model().unwrap());
    let (mesh, stats) = quadex::mesh_boundary(&b, model, &quadex::Params::DEFAULT, |_| {}).unwrap();
    mesh.check_finished().unwrap();
    assert_eq!(mesh.quads.len(), 4);
    assert_eq!(stats.count(StepKind::Fill), 0);
}

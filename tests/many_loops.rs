//! A domain of many holes: the step ladder's work per step stays local.
//! A reference point whose element the memory holds as impossible (one
//! pinched between two holes' fronts) is parked until something near it
//! changes, instead of being popped and put back at every step; closing a
//! small loop, settling it and a seam make the memory forget only the
//! region they changed. Stepped through the `Mesher` with the invariants
//! checked after every step, then finished into a valid mesh.

use quadex::domains::perforated_plate;
use quadex::extract::{MeshParams, Mesher, StepOutcome};
use quadex::model::default_model;
use quadex::Boundary;
use std::sync::Arc;

#[test]
fn a_perforated_plate_walks_few_reference_points_per_step() {
    let b = perforated_plate(10);
    assert_eq!(b.loops.len(), 101);
    Boundary::new(b.points.clone(), b.loops.clone(), None).expect("the plate is a valid boundary");
    let model = default_model().expect("the shipped model");
    let mut m = Mesher::new(b.clone(), Arc::new(model), MeshParams::DEFAULT);
    loop {
        match m.step().expect("a step") {
            StepOutcome::Done => break,
            StepOutcome::Stepped(_) => {}
        }
        m.check_invariants().expect("the invariants after a step");
    }
    let stats = m.stats();
    let per_step = stats.skipped_references as f64 / stats.steps as f64;
    // Walking every waiting point at every step passed over 10 a step
    // here (30,813 in 2,991 steps), growing with the number of holes.
    assert!(
        per_step < 2.0,
        "{} reference points passed over in {} steps",
        stats.skipped_references,
        stats.steps
    );
    let mesh = quadex::pipeline::finish(&m, &quadex::FinishParams::DEFAULT).expect("finished");
    let q = quadex::quality::MeshQuality::of(&mesh);
    assert!(q.sj_min > 0.3, "{q:?}");
    let area: f64 = mesh
        .quads
        .iter()
        .map(|k| quadex::geom::polygon_area(k.map(|v| mesh.nodes[v as usize])))
        .sum();
    assert!(
        (area - b.area()).abs() < 1e-9 * b.area(),
        "{area} against {}",
        b.area()
    );
}

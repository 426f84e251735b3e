//! A domain of many holes (a tube sheet's pattern): closing a small loop,
//! settling it, a row's first square and a seam make the step ladder's
//! memory forget only the region they changed. Stepped through the
//! `Mesher` with the invariants checked after every step, then finished
//! into a valid mesh of the plate's area.

use quadex::domains::perforated_plate;
use quadex::extract::{MeshParams, Mesher, StepOutcome};
use quadex::model::default_model;
use quadex::Boundary;
use std::sync::Arc;

#[test]
fn a_perforated_plate_steps_with_its_invariants_and_meshes() {
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

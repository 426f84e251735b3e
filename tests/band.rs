//! Band closure seen from outside: a thin ring between two loops of
//! unequal counts (an electric machine's air gap) and a thin curved strip
//! with ends of one segment close by rows along them, in one step, and the
//! finished meshes are valid, with few irregular nodes and no sliver.

use quadex::extract::{MeshParams, Rung, StepOutcome};
use quadex::pipeline::{mesh_boundary, Params};
use quadex::quality::MeshQuality;
use quadex::{Boundary, Mesher, Point};
use std::f64::consts::TAU;
use std::sync::Arc;

fn model() -> Arc<dyn quadex::model::Model> {
    Arc::new(quadex::model::default_model().expect("the shipped model"))
}

/// `n` points on an arc of radius `r` from angle `t0` to `t1`, both ends
/// included when `closed` is false (else `n` points round the circle).
fn arc(n: usize, r: f64, t0: f64, t1: f64, closed: bool) -> Vec<Point> {
    let d = if closed { n } else { n - 1 };
    (0..n)
        .map(|k| {
            let t = t0 + (t1 - t0) * k as f64 / d as f64;
            Point::new(r * t.cos(), r * t.sin())
        })
        .collect()
}

/// A ring between a circle of 180 nodes (radius 1) and one of 204 nodes
/// (radius 0.96, spaced unevenly): a gap of about one element.
fn air_gap() -> Boundary {
    let mut pts = arc(180, 1.0, 0.0, TAU, true);
    let inner: Vec<Point> = (0..204)
        .map(|k| {
            let s = k as f64 / 204.0;
            let t = TAU * (s + 0.02 * (TAU * s * 3.0).sin() / (TAU * 3.0));
            Point::new(0.96 * t.cos(), 0.96 * t.sin())
        })
        .collect();
    pts.extend(inner.into_iter().rev());
    Boundary::new(pts, vec![(0..180).collect(), (180..384).collect()], None).expect("a valid ring")
}

/// A thin curved strip: an arc of 70 segments over one of 52, 0.03 apart,
/// closed by ends of one segment.
fn sliver() -> Boundary {
    let mut pts = arc(71, 1.0, 0.0, 1.2, false);
    pts.extend(arc(53, 1.03, 0.0, 1.2, false).into_iter().rev());
    let n = pts.len();
    Boundary::new(pts, vec![(0..n).collect()], None).expect("a valid strip")
}

/// Steps `b` to the end and gives the rungs that took its steps.
fn rungs(b: Boundary) -> Vec<Rung> {
    let mut m = Mesher::new(b, model(), MeshParams::DEFAULT);
    let mut out = Vec::new();
    while let StepOutcome::Stepped(r) = m.step().expect("the band meshes") {
        m.check_invariants()
            .expect("the invariants after each step");
        out.push(r.rung);
    }
    out
}

fn finished(b: &Boundary) -> MeshQuality {
    let (mesh, _) = mesh_boundary(b, model(), &Params::DEFAULT, |_| {}).expect("a finished mesh");
    mesh.check_finished().expect("a valid mesh");
    MeshQuality::of(&mesh)
}

#[test]
fn a_thin_ring_closes_by_rows_in_one_step() {
    assert_eq!(rungs(air_gap()), vec![Rung::Band]);
    let q = finished(&air_gap());
    let share = q.irregular_interior as f64 / q.interior_nodes as f64;
    assert!(share <= 0.15, "irregular share {share:.3}");
    assert!(q.sj_min >= 0.3, "sj min {}", q.sj_min);
}

#[test]
fn a_thin_strip_with_ends_of_one_segment_closes_by_rows() {
    assert_eq!(rungs(sliver()), vec![Rung::Band]);
    let q = finished(&sliver());
    let share = q.irregular_interior as f64 / q.interior_nodes as f64;
    assert!(share <= 0.25, "irregular share {share:.3}");
    assert!(q.sj_min >= 0.2, "sj min {}", q.sj_min);
}

/// Band closure off (`max_rows` 0): the same ring is meshed element by
/// element, and no step is the band's.
#[test]
fn band_closure_can_be_turned_off() {
    let mut params = MeshParams::DEFAULT;
    params.tuning.band.max_rows = 0;
    let mut m = Mesher::new(air_gap(), model(), params);
    while let StepOutcome::Stepped(r) = m.step().expect("the ring meshes") {
        assert_ne!(r.rung, Rung::Band);
    }
}

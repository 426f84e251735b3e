//! Domains whose loops have odd node counts (triangular holes; the total is
//! even, as every quad mesh needs): a chord split must leave each part with
//! an even count together with the odd holes it takes in, a small hole that
//! no row reaches gets one of its own, and a fill joins odd loops by
//! corridors of quads. Each run is stepped through the `Mesher` with the
//! front's and the mesh's invariants checked after every step, then
//! finished by the pipeline into a valid mesh of the domain's area.

use quadex::extract::{MeshParams, Mesher, StepOutcome};
use quadex::geom::Point;
use quadex::io;
use quadex::Boundary;
use std::path::PathBuf;
use std::sync::Arc;

fn repro(name: &str) -> Boundary {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/repro")
        .join(name);
    io::read_boundary(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// A square of side 10 with `n` segments a side and triangles of
/// circumradius `r` centred at `centres`.
fn square_with_triangles(n: usize, r: f64, centres: &[(f64, f64)]) -> Boundary {
    let mut points = Vec::new();
    for side in 0..4 {
        for i in 0..n {
            let t = 10.0 * i as f64 / n as f64;
            points.push(match side {
                0 => Point::new(t, 0.0),
                1 => Point::new(10.0, t),
                2 => Point::new(10.0 - t, 10.0),
                _ => Point::new(0.0, 10.0 - t),
            });
        }
    }
    let mut loops = vec![(0..points.len()).collect::<Vec<_>>()];
    for &(cx, cy) in centres {
        let first = points.len();
        for k in 0..3 {
            let a = std::f64::consts::FRAC_PI_2 + 2.0 * std::f64::consts::PI * k as f64 / 3.0;
            points.push(Point::new(cx + r * a.cos(), cy + r * a.sin()));
        }
        loops.push((first..first + 3).collect());
    }
    Boundary::new(points, loops, None).expect("a valid boundary")
}

/// Steps `boundary` to the end with the default model, checking the
/// invariants after every step, then meshes it through the pipeline and
/// checks the finished mesh. Returns the finished mesh's quad count.
fn mesh_checked(name: &str, boundary: &Boundary) -> usize {
    let model: Arc<dyn quadex::Model> =
        Arc::new(quadex::model::default_model().expect("the shipped model loads"));
    let mut m = Mesher::new(boundary.clone(), model.clone(), MeshParams::DEFAULT);
    let mut steps = 0;
    loop {
        match m.step() {
            Ok(StepOutcome::Done) => break,
            Ok(StepOutcome::Stepped(_)) => steps += 1,
            Err(e) => panic!("{name}: step {steps}: {e}"),
        }
        m.check_invariants()
            .unwrap_or_else(|e| panic!("{name}: after step {steps}: {e}"));
    }
    let (mesh, _) = quadex::mesh_boundary(boundary, model, &quadex::Params::DEFAULT, |_| {})
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    mesh.check_invariants(true)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    mesh.check_finished()
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let area = boundary.area();
    assert!(
        (mesh.domain_area() - area).abs() <= 1e-9 * area,
        "{name}: area {} for {area}",
        mesh.domain_area()
    );
    assert!(quadex::MeshQuality::of(&mesh).sj_min > 0.0, "{name}");
    mesh.quads.len()
}

#[test]
fn triangular_holes_in_a_fine_square_mesh() {
    let b = square_with_triangles(10, 0.4, &[(3.0, 4.0), (7.0, 6.0)]);
    assert!(mesh_checked("fine square", &b) > 50);
}

#[test]
fn triangular_holes_in_a_coarse_square_mesh() {
    // Three segments a side: the outer front has no element to offer, and
    // the rows start around the holes.
    let b = square_with_triangles(3, 0.4, &[(3.0, 4.0), (7.0, 6.0)]);
    assert!(mesh_checked("coarse square", &b) >= 8);
    let four = square_with_triangles(3, 0.3, &[(2.5, 2.5), (7.5, 2.5), (2.5, 7.5), (7.5, 7.5)]);
    assert!(mesh_checked("four triangles", &four) >= 8);
}

/// Issue 18's R06b and R06d: a coarse nine-node outline with five
/// triangular holes, and a reduced plate with five holes; both ended with
/// "cannot be reduced".
#[test]
fn r06b_r06d_plates_with_odd_holes_mesh() {
    for name in [
        "R06b_many_holes_reduced.poly",
        "R06d_many_holes_steplimit_reduced.poly",
    ] {
        let b = repro(name);
        assert!(b.loops.iter().any(|l| l.len() % 2 == 1), "{name}");
        mesh_checked(name, &b);
    }
}

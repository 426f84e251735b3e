//! Mapped closure: a loop that is a logical rectangle (four corners,
//! opposite sides of equal segment counts) at most `mapped_rows` elements
//! across closes in one step by a structured grid. Runs are stepped
//! through the `Mesher` with the invariants checked after every step.

mod common;

use quadex::extract::{MeshParams, Mesher, Remedy, StepKind, StepOutcome};
use quadex::geom::Point;
use quadex::quality::Shape;
use quadex::{Boundary, Model};
use std::sync::Arc;

fn model() -> Arc<dyn Model> {
    Arc::new(quadex::model::default_model().expect("the shipped model loads"))
}

/// A `w × h` rectangle with `m` segments along the long sides and `n` up
/// the short ones.
fn plate(w: f64, h: f64, m: usize, n: usize) -> Boundary {
    let p = common::rectangle(Point::ZERO, w, h, m, n, m);
    let k = p.len();
    Boundary::new(p, vec![(0..k).collect()], None).expect("a valid boundary")
}

/// Steps to the end with the invariants checked after every step; the
/// kinds of the steps taken. The mesh is checked as finished: no corner
/// flat to rounding either.
fn stepped(name: &str, b: &Boundary, params: MeshParams) -> (Mesher, Vec<StepKind>) {
    let (m, kinds) = stepped_to_finish(name, b, params);
    m.mesh()
        .check_no_flat_corner()
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    (m, kinds)
}

/// [`stepped`] for a mesh the test finishes: extraction may leave an
/// interior corner flat to rounding (smoothing moves such nodes), and the
/// finished mesh is checked for those ([`quadex::pipeline::finish`]).
fn stepped_to_finish(name: &str, b: &Boundary, params: MeshParams) -> (Mesher, Vec<StepKind>) {
    let mut m = Mesher::new(b.clone(), model(), params);
    let mut kinds = Vec::new();
    loop {
        match m.step() {
            Ok(StepOutcome::Done) => break,
            Ok(StepOutcome::Stepped(r)) => kinds.push(r.kind),
            Err(e) => panic!("{name}: {e}"),
        }
        m.check_invariants()
            .unwrap_or_else(|e| panic!("{name}: after step {}: {e}", m.steps()));
    }
    m.mesh()
        .check_invariants(true)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    (m, kinds)
}

/// Issue 18's R19: a 50 × 1 plate with 13 segments along and 4 across
/// gave 3,213 quads down to SJ 0.002 in 20 s; its grid is 13 × 4.
#[test]
fn a_plate_of_13_by_4_segments_is_its_grid() {
    let (m, kinds) = stepped("R19 plate", &plate(50.0, 1.0, 13, 4), MeshParams::DEFAULT);
    assert_eq!(kinds, vec![StepKind::Mapped]);
    let mesh = m.mesh();
    assert_eq!(mesh.quads.len(), 52);
    for q in &mesh.quads {
        let sj = Shape::of(mesh.corners(q)).scaled_jacobian;
        assert!((sj - 1.0).abs() < 1e-9, "{sj}");
    }
}

/// Wider than `mapped_rows`, or with mapping off, the plate is left to
/// extraction.
#[test]
fn mapping_keeps_to_narrow_loops() {
    let wide = plate(10.0, 10.0, 10, 10);
    let (_, kinds) = stepped("square", &wide, MeshParams::DEFAULT);
    assert_ne!(kinds.first(), Some(&StepKind::Mapped));
    let off = MeshParams {
        mapped_rows: None,
        ..MeshParams::DEFAULT
    };
    let mut m = Mesher::new(plate(50.0, 1.0, 13, 4), model(), off);
    for _ in 0..20 {
        match m.step() {
            Ok(StepOutcome::Stepped(r)) => assert_ne!(r.kind, StepKind::Mapped),
            other => panic!("{other:?}"),
        }
    }
}

/// A plate with a slot: once the rows round the slot have met, the strip
/// left closes by a grid, and the mesh is valid after every step.
#[test]
fn strips_between_fronts_close_by_grids() {
    // A 24 × 6 plate with a 20 × 2 slot in the middle: one strip of two
    // rows all round.
    let mut p = common::rectangle(Point::ZERO, 24.0, 6.0, 24, 6, 24);
    let outer: Vec<usize> = (0..p.len()).collect();
    let first = p.len();
    // The hole, clockwise from its lower left corner.
    let mut slot = common::rectangle(Point::new(2.0, 2.0), 20.0, 2.0, 20, 2, 20);
    slot[1..].reverse();
    p.extend(slot);
    let hole: Vec<usize> = (first..p.len()).collect();
    let b = Boundary::new(p, vec![outer, hole], None).expect("a valid boundary");
    let (m, kinds) = stepped("slotted plate", &b, MeshParams::DEFAULT);
    let mesh = m.mesh();
    // Area 144 − 40 = 104 unit squares.
    assert_eq!(mesh.quads.len(), 104, "{kinds:?}");
    let worst = mesh.worst_scaled_jacobian();
    assert!(worst > 0.9, "{worst} {kinds:?}");
    assert_eq!(kinds.last(), Some(&StepKind::Mapped), "{kinds:?}");
}

/// Generated near-touching domains whose extraction jams on a strip whose
/// ends the corner test refuses: the strip grid over the loop's own choice
/// of corners closes it, and the run finishes with no fill. (The first
/// ended in a fill with a worst quad of 0.003 before strip grids; a bridge
/// across its gap now comes first, and it still finishes with no fill.)
#[test]
fn a_stuck_strip_closes_by_its_best_grid() {
    for (seed, strip) in [(0xfcf35d454d07e2e9, false), (0xfcf35d454d07e374, true)] {
        let d = quadex::domains::generate(quadex::domains::Family::NearTouching, seed);
        let mut m = Mesher::new(d.boundary.clone(), model(), MeshParams::DEFAULT);
        let mut strips = 0;
        loop {
            match m.step() {
                Ok(StepOutcome::Done) => break,
                Ok(StepOutcome::Stepped(r)) => {
                    assert_ne!(
                        r.kind,
                        StepKind::Fill,
                        "{}: step {}",
                        d.description,
                        r.index
                    );
                    strips +=
                        usize::from(r.kind == StepKind::Mapped && r.remedy == Remedy::RuleBased);
                }
                Err(e) => panic!("{}: {e}", d.description),
            }
            m.check_invariants()
                .unwrap_or_else(|e| panic!("{}: after step {}: {e}", d.description, m.steps()));
        }
        m.mesh()
            .check_finished()
            .unwrap_or_else(|e| panic!("{}: {e}", d.description));
        assert!(!strip || strips > 0, "{}: no strip grid", d.description);
    }
}

/// A quadrilateral like Gmsh's tutorial 6: bottom and top of `m` segments
/// graded geometrically 1:`ratio` towards the right-hand corners, a
/// straight right side and a left side bent twice, `n` segments each.
fn graded_quadrilateral(m: usize, n: usize, ratio: f64) -> Vec<Point> {
    // Fractions along a side from its fine end: segment k is g^k times the
    // first, the last `ratio` times the first.
    let g = ratio.powf(1.0 / (m - 1) as f64);
    let lengths: Vec<f64> = (0..m).map(|k| g.powi(k as i32)).collect();
    let total: f64 = lengths.iter().sum();
    let mut from_fine = vec![0.0];
    for l in &lengths {
        from_fine.push(from_fine[from_fine.len() - 1] + l / total);
    }
    let mut p = Vec::new();
    // Bottom, (0, 0) to (1, 0): fine at its end.
    for k in 0..m {
        p.push(Point::new(1.0 - from_fine[m - k], 0.0));
    }
    // Right side, (1, 0) to (1, 1).
    for j in 0..n {
        p.push(Point::new(1.0, j as f64 / n as f64));
    }
    // Top, (1, 1) to (0, 1): fine at its start.
    for f in &from_fine[..m] {
        p.push(Point::new(1.0 - f, 1.0));
    }
    // Left side: (0, 1) to (-0.3, 0.6) to (-0.3, 0.3) to (0, 0).
    let bends = [
        Point::new(0.0, 1.0),
        Point::new(-0.3, 0.6),
        Point::new(-0.3, 0.3),
        Point::new(0.0, 0.0),
    ];
    let per = n / 3;
    for s in 0..3 {
        for t in 0..per {
            p.push(bends[s].lerp(bends[s + 1], t as f64 / per as f64));
        }
    }
    p
}

/// With graded grids asked for, a loop of the given boundary graded past
/// 1:10 whose opposite sides have equal counts is its transfinite grid,
/// bent side and all, in one step; graded 1:4 it is left to extraction.
#[test]
fn a_strongly_graded_quadrilateral_can_be_its_transfinite_grid() {
    let p = graded_quadrilateral(20, 12, 150.0);
    let k = p.len();
    let b = Boundary::new(p, vec![(0..k).collect()], None).expect("a valid boundary");
    let mut graded = MeshParams::DEFAULT;
    graded.tuning.mapped.graded_grid = true;
    let (m, kinds) = stepped("graded 1:150", &b, graded.clone());
    assert_eq!(kinds, vec![StepKind::Mapped]);
    let mesh = m.mesh();
    assert_eq!(mesh.quads.len(), 20 * 12);
    let worst = mesh
        .quads
        .iter()
        .map(|q| Shape::of(mesh.corners(q)).scaled_jacobian)
        .fold(1.0, f64::min);
    assert!(worst >= 0.4, "{worst}");
    // The price: the columns beside the right side, where the grading is
    // fine and the sides' rows are not, are slivers.
    let slivers = mesh
        .quads
        .iter()
        .filter(|q| Shape::of(mesh.corners(q)).side_ratio() > quadex::quality::GOOD_RATIO)
        .count();
    assert_eq!(slivers, 76);
    // The columns follow the grading: above the node that ends the
    // bottom's finest segment (0.0016 long), a column of 11 nodes runs up
    // to the top's, within a third of that segment (the bent left side
    // pulls the grid's nodes by (1 - u) times its offset).
    let fine = b.points[19].x;
    assert!(1.0 - fine < 0.002, "{fine}");
    let column = mesh
        .nodes
        .iter()
        .filter(|q| (q.x - fine).abs() < 6e-4 && q.y > 0.0 && q.y < 1.0)
        .count();
    assert_eq!(column, 11);
    let mild = graded_quadrilateral(20, 12, 4.0);
    let k = mild.len();
    let b = Boundary::new(mild, vec![(0..k).collect()], None).expect("a valid boundary");
    let (_, kinds) = stepped("graded 1:4", &b, graded);
    assert!(kinds.len() > 1 && kinds[0] != StepKind::Mapped, "{kinds:?}");
}

/// By default the same 1:150 quadrilateral is meshed by extraction: fans
/// at its graded corners, no fill, and once finished no quad with a side
/// over ten times another (its transfinite grid has 76 such slivers, the
/// columns beside the right side, 0.0016 to 0.008 wide and 0.083 high),
/// the worst quad a fan's at a 90° corner (the grid's worst is 0.4).
#[test]
fn a_strongly_graded_quadrilateral_gets_fans_not_slivers() {
    let p = graded_quadrilateral(20, 12, 150.0);
    let k = p.len();
    let b = Boundary::new(p, vec![(0..k).collect()], None).expect("a valid boundary");
    let (m, kinds) = stepped_to_finish("graded 1:150", &b, MeshParams::DEFAULT);
    assert!(kinds.contains(&StepKind::Fan), "{kinds:?}");
    assert!(!kinds.contains(&StepKind::Fill), "{kinds:?}");
    assert!(!kinds.contains(&StepKind::Mapped), "{kinds:?}");
    let mesh = quadex::pipeline::finish(&m, &quadex::FinishParams::DEFAULT).expect("finished");
    let shapes: Vec<Shape> = mesh
        .quads
        .iter()
        .map(|q| Shape::of(mesh.corners(q)))
        .collect();
    let ratio = shapes.iter().map(Shape::side_ratio).fold(0.0, f64::max);
    let worst = shapes.iter().map(|s| s.scaled_jacobian).fold(1.0, f64::min);
    assert!(ratio <= quadex::quality::GOOD_RATIO, "{ratio}");
    assert!(worst >= 0.37, "{worst}");
}

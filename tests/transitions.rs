//! Transition elements (3 to 1): where a row runs finer than the boundary's
//! spacing asks, three front edges are taken by four quads and the front
//! loses two nodes. Runs are stepped through the `Mesher` with the front's
//! and the mesh's invariants checked after every step.

mod common;

use quadex::extract::{MeshParams, Mesher, StepKind, StepOutcome};
use quadex::geom::Point;
use quadex::{io, Boundary, Model};
use std::sync::Arc;

fn model() -> Arc<dyn Model> {
    Arc::new(quadex::model::default_model().expect("the shipped model loads"))
}

/// A 12 × 4 rectangle with `bottom` segments along the bottom, 12 along the
/// top and 4 up each side: fine below, coarse above.
fn graded_rectangle(bottom: usize) -> Boundary {
    let points = common::rectangle(Point::ZERO, 12.0, 4.0, bottom, 4, 12);
    let n = points.len();
    Boundary::new(points, vec![(0..n).collect()], None).expect("a valid boundary")
}

/// Steps `boundary` to the end, checking the invariants after every step
/// and what every transition did. Returns the mesher at the end and the
/// transitions.
fn stepped(name: &str, boundary: &Boundary, params: MeshParams) -> (Mesher, usize) {
    let mut m = Mesher::new(boundary.clone(), model(), params);
    let mut transitions = 0;
    loop {
        let before = m.front().len();
        match m.step() {
            Ok(StepOutcome::Done) => break,
            Ok(StepOutcome::Stepped(r)) => {
                assert_ne!(r.kind, StepKind::Fill, "{name}: step {}", r.index);
                if r.kind == StepKind::Transition {
                    transitions += 1;
                    assert_eq!(r.quads.len(), 4, "{name}: step {}", r.index);
                    assert_eq!(r.new_nodes.len(), 3, "{name}: step {}", r.index);
                    assert_eq!(m.front().len() + 2, before, "{name}: step {}", r.index);
                }
            }
            Err(e) => panic!("{name}: {e}"),
        }
        m.check_invariants()
            .unwrap_or_else(|e| panic!("{name}: after step {}: {e}", m.steps()));
    }
    m.mesh()
        .check_finished()
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    (m, transitions)
}

/// The quality of the finished mesh (cleaned up, smoothed, remeshed).
fn finished(m: &Mesher) -> quadex::MeshQuality {
    let mesh = quadex::pipeline::finish(m, &quadex::FinishParams::DEFAULT).expect("finishes");
    quadex::MeshQuality::of(&mesh)
}

#[test]
fn a_fine_side_facing_a_coarse_one_coarsens_by_transitions() {
    let b = graded_rectangle(48);
    let (m, transitions) = stepped("graded rectangle", &b, MeshParams::DEFAULT);
    assert!(transitions > 0, "no transition");
    let off = MeshParams {
        transition_ratio: None,
        ..MeshParams::DEFAULT
    };
    let (plain, none) = stepped("graded rectangle, no transitions", &b, off);
    assert_eq!(none, 0);
    // Without transitions the front sheds its nodes where rows meet, by
    // corner elements, closures and chord splits: a poorer mesh on the
    // whole (mean scaled Jacobian 0.936 against 0.946), with about as many
    // irregular nodes (32 against 34 since settling a small loop keeps
    // its quads over 0.1; 39 before, with a mean of 0.929).
    let (with, without) = (finished(&m), finished(&plain));
    assert!(
        with.sj_mean > without.sj_mean + 0.005
            && with.irregular_interior <= without.irregular_interior + 2,
        "with transitions {with:?}, without {without:?}"
    );
}

/// A disk with 100 boundary nodes: rings shrink inwards, and transitions
/// keep their elements near the boundary's spacing (about π / h² = 800
/// quads for h = 2π / 100) where rows of constant node count make 1,400.
#[test]
fn disk_rows_keep_the_boundary_spacing() {
    let path = common::bench().join("boundaries/disk100.poly");
    let b = io::read_boundary(&path).expect("disk100 reads");
    let (m, transitions) = stepped("disk100", &b, MeshParams::DEFAULT);
    let quads = m.mesh().quads.len();
    assert!(transitions > 0);
    assert!(quads < 1200, "{quads} quads");
}

/// A generated domain whose boundary spacing is graded 1:100: the rows of
/// its fine part make quads far smaller than the mean of those made so
/// far, and the progress watch, which holds them to the size field, lets
/// extraction run to the end instead of filling the rest (it filled after
/// 3,201 steps when the mean was its only measure).
#[test]
fn a_boundary_graded_one_to_a_hundred_is_meshed_by_extraction_alone() {
    let d = quadex::domains::generate(quadex::domains::Family::Graded, 0xfacec95d4663db9c);
    let (m, transitions) = stepped(&d.name, &d.boundary, MeshParams::DEFAULT);
    let quads = m.mesh().quads.len();
    assert!(transitions > 0, "{}: no transition", d.description);
    assert!(quads > 1000, "{}: {quads} quads", d.description);
}

/// A 2 × 1 parallelogram (corners of 70° and 110°) whose bottom is graded
/// from 1/100 of the sides' spacing at both ends, growing by 1.3 a
/// segment: each bottom corner takes a fan before anything else is cut
/// there, and the run finishes by extraction, no quad under the fan's
/// share of the 70° corner nor stretched past 10.
#[test]
fn corners_of_a_strongly_graded_side_take_fans() {
    let (w, h, n_side) = (2.0, 1.0, 10);
    let fine = h / n_side as f64 / 100.0;
    let mut half = Vec::new();
    let (mut len, mut sum) = (fine, 0.0);
    while sum + len < 0.5 * w {
        half.push(len);
        sum += len;
        len = (len * 1.3).min(0.3 * h);
    }
    let scale = 0.5 * w / sum;
    let mut segs: Vec<f64> = half.iter().map(|l| l * scale).collect();
    segs.extend(half.iter().rev().map(|l| l * scale));
    let skew = h / 70f64.to_radians().tan();
    let mut pts = vec![Point::ZERO];
    let mut x = 0.0;
    for l in &segs[..segs.len() - 1] {
        x += l;
        pts.push(Point::new(x, 0.0));
    }
    let corners = [
        Point::new(w, 0.0),
        Point::new(w + skew, h),
        Point::new(skew, h),
        Point::ZERO,
    ];
    let n_top = 20;
    let counts = [
        n_side,
        n_top,
        n_side + (pts.len() + n_side + n_top + n_side) % 2,
    ];
    for (k, &n) in counts.iter().enumerate() {
        let (a, b) = (corners[k], corners[k + 1]);
        pts.extend((0..n).map(|i| a + (b - a) * (i as f64 / n as f64)));
    }
    let n = pts.len();
    assert_eq!(n % 2, 0);
    let boundary = Boundary::new(pts, vec![(0..n).collect()], None).expect("a valid boundary");
    let (m, _) = stepped("graded side", &boundary, MeshParams::DEFAULT);
    assert_eq!(
        m.stats().count(StepKind::Fan),
        2,
        "one fan at each end of the graded side"
    );
    // At 1:87 (the bottom scaled to its width), five quads a corner keep
    // the spokes' growth within 2.5 (70° leaves each of them 14°, at least
    // the 10° asked).
    assert_eq!(m.stats().quads_made(StepKind::Fan), 10);
    let q = finished(&m);
    // The worst quad is a fan's, its corner's share: sin 14° = 0.2419.
    assert!(q.sj_min >= 0.24, "scaled Jacobian {}", q.sj_min);
    // And no quad has a side over ten times another.
    assert!(
        q.taper_max <= 10.0 && q.aspect_max <= 10.0,
        "taper {}, aspect {}",
        q.taper_max,
        q.aspect_max
    );
}

/// A hexagon 100 across its corners with a slit 4 wide and 100 long going
/// out from four of them, each wall one segment: two dead ends and two
/// that fork into two dead ends 60 long (the gaps between a reactor
/// core's assemblies). Each dead end is cut off by one quad, a fork's
/// junction by two through a node in its mouth, and each mouth with the
/// hexagon's sides beside it; the model's elements, whose leading points
/// are scaled by a 4-long edge among 100-long ones, knotted there.
#[test]
fn slits_between_assemblies_close_by_notches() {
    let corner = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / 6.0;
        Point::new(a.cos(), a.sin()) * 100.0
    };
    let mut pts = Vec::new();
    for k in 0..6 {
        let (prev, tip, next) = (corner((k + 5) % 6), corner(k), corner((k + 1) % 6));
        match k {
            0 | 3 => pts.extend(quadex::domains::slit(
                prev,
                tip,
                next,
                4.0,
                100.0,
                Some(60.0),
            )),
            1 | 4 => pts.extend(quadex::domains::slit(prev, tip, next, 4.0, 100.0, None)),
            _ => pts.push(tip),
        }
    }
    let n = pts.len();
    assert_eq!(n, 28);
    let boundary = Boundary::new(pts, vec![(0..n).collect()], None).expect("a valid boundary");
    let (m, _) = stepped("slits", &boundary, MeshParams::DEFAULT);
    // Two dead ends; two forks, each two dead ends, a junction (two
    // quads) and a mouth (two quads). A dead end's mouth takes no notch
    // here: the fork's mouth before it took the hexagon side it needs.
    assert_eq!(
        (
            m.stats().count(StepKind::Notch),
            m.stats().quads_made(StepKind::Notch)
        ),
        (10, 14)
    );
    let q = finished(&m);
    assert!(q.sj_min >= 0.3, "scaled Jacobian {}", q.sj_min);
}

//! Disks between the benchmark's (2,000 and 4,000 equal boundary segments
//! on the unit circle) finish by extraction alone, with no region fill.
//! Each once went to a fill of the whole disk: the first when square cuts
//! on a stuck loop shrank by half at each cut, each on the side of the one
//! before, down to nothing; the second when the progress watch took the
//! closing of the last pockets (rip-ups that give area back) for a stall.
//! Their elements keep the boundary's spacing inside: the 4,000 disk once
//! made 0.58 of the quads its size field asks for, its rows coarsened by
//! transitions ring after ring.

use quadex::boundary::Boundary;
use quadex::extract::{MeshParams, Mesher, StepKind};
use quadex::geom::Point;
use std::sync::Arc;

fn disk(n: usize) -> Boundary {
    let points = (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            Point::new(t.cos(), t.sin())
        })
        .collect();
    Boundary::new(points, vec![(0..n).collect()], None).expect("a valid disk")
}

#[test]
fn intermediate_disks_finish_by_extraction() {
    for n in [2000, 4000] {
        let model = Arc::new(quadex::model::default_model().unwrap());
        let mut m = Mesher::new(disk(n), model, MeshParams::DEFAULT);
        m.run(|_| {}).unwrap_or_else(|e| panic!("disk{n}: {e}"));
        assert_eq!(m.stats().count(StepKind::Fill), 0, "disk{n}: a fill");
        m.check_invariants()
            .unwrap_or_else(|e| panic!("disk{n}: {e}"));
        // Some 300,000 and 1.2 million quads.
        let share = m.mesh().quads.len() as f64 / m.size().quad_estimate();
        assert!(
            (0.85..1.1).contains(&share),
            "disk{n}: {} quads, {share:.2} of the size field's",
            m.mesh().quads.len()
        );
        let mesh = quadex::pipeline::finish(&m, &quadex::FinishParams::DEFAULT).unwrap();
        mesh.check_finished()
            .unwrap_or_else(|e| panic!("disk{n}: {e}"));
        let q = quadex::MeshQuality::of(&mesh);
        assert!(q.sj_min > 0.5, "disk{n}: scaled Jacobian {}", q.sj_min);
    }
}

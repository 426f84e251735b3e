//! Chord coarsening on the round benchmark cases: rows that stay lower than
//! the size field where rings keep their node count (`annulus`, `disk100`)
//! lose a whole ring, and the mesh stays as regular and as good.

mod common;

use quadex::extract::Mesher;
use quadex::finish::coarsen::CoarsenParams;
use quadex::pipeline::{finish, FinishParams};
use quadex::{io, MeshParams, MeshQuality};
use std::sync::Arc;

#[test]
fn round_cases_lose_a_ring_and_stay_regular() {
    // (case, nodes a ring)
    for (case, ring) in [("annulus", 64), ("disk100", 100)] {
        let path = common::bench()
            .join("boundaries")
            .join(format!("{case}.poly"));
        let boundary = io::read_boundary(&path).unwrap();
        let model = Arc::new(quadex::model::default_model().unwrap());
        let mut m = Mesher::new(boundary, model, MeshParams::DEFAULT);
        m.run(|_| {}).unwrap();
        let without = finish(
            &m,
            &FinishParams {
                coarsen: CoarsenParams::OFF,
                ..FinishParams::DEFAULT
            },
        )
        .unwrap();
        let with = finish(&m, &FinishParams::DEFAULT).unwrap();
        with.check_finished().unwrap();
        let (a, b) = (MeshQuality::of(&without), MeshQuality::of(&with));
        let removed = a.quads - b.quads;
        assert!(
            removed > 0 && removed % ring == 0,
            "{case}: {} → {} quads",
            a.quads,
            b.quads
        );
        assert!(
            b.irregular_interior <= a.irregular_interior,
            "{case}: irregular {} → {}",
            a.irregular_interior,
            b.irregular_interior
        );
        assert!(b.sj_min > 0.75, "{case}: scaled Jacobian min {}", b.sj_min);
        assert!(
            b.sj_mean > a.sj_mean - 0.005,
            "{case}: mean scaled Jacobian {} → {}",
            a.sj_mean,
            b.sj_mean
        );
    }
}

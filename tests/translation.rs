//! Results do not depend on where a domain lies or on its units: seeded
//! domains meshed at offsets 0, 1e5 and 1e8 and at scales 2^-20 (about
//! 1e-6) to 2^20 (about 1e6) give the same quads. The domains'
//! coordinates are multiples of 2^-12, so every offset and scale below is
//! exact in floating point: a difference could only come from the mesher.
//! (A domain 1e-5 wide placed at 1e8 cannot be: its coordinates would need
//! more than 53 bits.)

use quadex::boundary::Boundary;
use quadex::geom::Point;
use quadex::rng::SplitMix64;
use quadex::{mesh_boundary, Params};
use std::sync::Arc;

/// A point rounded to a multiple of 2^-12.
fn dyadic(x: f64, y: f64) -> Point {
    let q = 4096.0;
    Point::new((x * q).round() / q, (y * q).round() / q)
}

/// A star-shaped outer loop (an even number of nodes, radii varying) and,
/// for every other seed, a square hole in the middle.
fn domain(seed: u64) -> Boundary {
    let mut rng = SplitMix64::new(seed);
    let n = 2 * (8 + (rng.next_u64() % 13) as usize);
    let mut pts: Vec<Point> = (0..n)
        .map(|k| {
            let t = k as f64 / n as f64 * std::f64::consts::TAU;
            let r = 3.0 + 1.5 * rng.unit();
            dyadic(r * t.cos(), r * t.sin())
        })
        .collect();
    let mut loops = vec![(0..n).collect::<Vec<_>>()];
    if seed % 2 == 0 {
        let h = 0.5 + 0.5 * rng.unit();
        let hole = [(-h, -h), (-h, h), (h, h), (h, -h)].map(|(x, y)| dyadic(x, y));
        loops.push((n..n + 4).collect());
        pts.extend(hole);
    }
    Boundary::new(pts, loops, None).unwrap_or_else(|e| panic!("seed {seed}: {e}"))
}

fn moved(b: &Boundary, offset: f64, scale: f64) -> Boundary {
    let pts = b
        .points
        .iter()
        .map(|p| *p * scale + Point::splat(offset))
        .collect();
    Boundary::new(pts, b.loops.clone(), None).unwrap()
}

#[test]
fn offsets_and_scales_give_the_same_mesh() {
    let model: Arc<dyn quadex::Model> = Arc::new(quadex::model::default_model().unwrap());
    let mut differ = Vec::new();
    for seed in 0..100u64 {
        let b = domain(seed);
        let (reference, _) = mesh_boundary(&b, model.clone(), &Params::DEFAULT, |_| {})
            .unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        reference.check_finished().unwrap();
        for (offset, scale) in [
            (1e5, 1.0),
            (1e8, 1.0),
            (0.0, 2f64.powi(-20)),
            (0.0, 2f64.powi(20)),
            (1e5, 2f64.powi(-20)),
            (1e8, 2f64.powi(20)),
        ] {
            let (m, _) = mesh_boundary(
                &moved(&b, offset, scale),
                model.clone(),
                &Params::DEFAULT,
                |_| {},
            )
            .unwrap_or_else(|e| panic!("seed {seed} at {offset} × {scale}: {e}"));
            m.check_finished()
                .unwrap_or_else(|e| panic!("seed {seed} at {offset} × {scale}: {e}"));
            if m.quads != reference.quads {
                differ.push((seed, offset, scale, reference.quads.len(), m.quads.len()));
            }
        }
    }
    assert!(
        differ.is_empty(),
        "meshes that differ (seed, offset, scale, quads, quads): {differ:?}"
    );
}

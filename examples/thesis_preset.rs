//! Measures the thesis preset (Table 8 as printed) on the normalised
//! 7-point rows of thesis Table 3(b), on a straight 90° corner, and on real
//! meshing steps (pure-model mode on the benchmark boundaries).
//!
//! `cargo run --release --example thesis_preset`

use quadex::extract::{MeshParams, Mesher, StepOutcome};
use quadex::model::{Model, RulesModel, ThesisModel};
use quadex::normalize::LeadingPoints;
use quadex::Point;
use std::sync::Arc;

/// Table 3(b), the 22 rows printed in full: Xl3 Yl3 Xl2 Yl2 Xl1 Yl1 (P0, Pr1
/// omitted) Xr2 Yr2 Xr3 Yr3 type Xn Yn.
const TABLE_3B: [[f64; 13]; 22] = [
    [1.9, 0.8, 1., 1.1, 0., 1.3, 2., 0., 3., 0., 2., 1., 1.1],
    [1.4, 2.2, 1., 1.1, 0., 1.3, 2., 0., 3., 0., 2., 1., 1.1],
    [1.9, 0.8, 1., 1.1, 0., 1.3, 2., 0., 1.9, 0.8, 2., 1., 1.1],
    [1.4, 2.2, 1., 1.1, 0., 1.3, 2., 0., 1.9, 0.8, 2., 1., 1.1],
    [1.4, 2.2, 1., 2.37, 0., 1.3, 2., 0., 3., 0., 0., 1., 1.1],
    [0.7, 3.3, 1., 2.37, 0., 1.3, 2., 0., 3., 0., 0., 1., 1.1],
    [1.4, 2.2, 1., 2.37, 0., 1.3, 2., 0., 1.9, 0.8, 0., 1., 1.1],
    [0.7, 3.3, 1., 2.37, 0., 1.3, 2., 0., 1.9, 0.8, 0., 1., 1.1],
    [1.4, 2.2, 1., 2.37, 0., 1.3, 1., 1.1, 1.9, 0.8, 1., 1., 1.1],
    [0.7, 3.3, 1., 2.37, 0., 1.3, 1., 1.1, 1.9, 0.8, 1., 1., 1.1],
    [1.4, 2.2, 1., 2.37, 0., 1.3, 1., 1.1, 1.4, 2.2, 1., 1., 1.1],
    [0.7, 3.3, 1., 2.37, 0., 1.3, 1., 1.1, 1.4, 2.2, 1., 1., 1.1],
    [
        2.15, 0., 1.18, 0.91, 0., 0.91, 0.73, -0.82, 0., -0.91, 2., 1.18, 0.91,
    ],
    [
        2.15, 0., 1.18, 0.91, 0., 0.91, 0.73, -0.82, 0.91, -1.82, 2., 1.18, 0.91,
    ],
    [
        2.15, 0., 1.18, 0.91, 0., 0.91, 2., -0.36, 0.91, -1.82, 2., 1.18, 0.91,
    ],
    [
        2.15, 0., 1.18, 0.91, 0., 0.91, 2., -0.36, 2.03, -2.27, 2., 1.18, 0.91,
    ],
    [
        2.15, 0., 1.18, 0.91, 0., 0.91, 2., -0.36, 2.15, 0., 2., 1.18, 0.91,
    ],
    [
        2.15, 0., 1.18, 0.91, 0., 0.91, 2., -0.36, 3.04, -1., 2., 1.18, 0.91,
    ],
    [2., 1., 0.9, 0.8, 0., 1.1, 2., 0., 3., 0., 2., 0.9, 0.8],
    [2., 1., 0.9, 0.8, 0., 1.1, 2., 0., 2., 1., 2., 0.9, 0.8],
    [-1., 0., -1., 1.3, 0., 1.1, 2., 0., 3., 0., 0., 0.9, 0.8],
    [0., 2.37, -1., 1.3, 0., 1.1, 2., 0., 3., 0., 0., 0.9, 0.8],
];

fn input(r: &[f64; 13]) -> LeadingPoints {
    let p = |k: usize| Point::new(r[2 * k], r[2 * k + 1]);
    LeadingPoints {
        left: vec![p(2), p(1), p(0)],
        right: vec![Point::X, p(3), p(4)],
    }
}

fn main() {
    let m = ThesisModel::TABLE_8;
    let (mut ok, mut err) = (0, Vec::new());
    println!("Table 3(b), 22 rows: type (thesis → preset), Pn error");
    for r in &TABLE_3B {
        let p = m.predict(&input(r));
        let t = p.element_type.number() as f64;
        ok += (t == r[10]) as usize;
        let e = (p.pn - Point::new(r[11], r[12])).length();
        err.push(e);
        println!(
            "  type {} → {} (P = {:.3}), Pn ({:.2}, {:.2}) → ({:.2}, {:.2}), error {:.2}",
            r[10],
            t,
            m.type_score(&input(r)),
            r[11],
            r[12],
            p.pn.x,
            p.pn.y,
            e
        );
    }
    err.sort_by(f64::total_cmp);
    println!(
        "type correct: {ok}/22; median |Pn error| {:.2}, max {:.2}",
        err[11], err[21]
    );
    let corner = LeadingPoints {
        left: vec![Point::new(0., 1.), Point::new(0., 2.), Point::new(0., 3.)],
        right: vec![Point::X, Point::new(2., 0.), Point::new(3., 0.)],
    };
    let p = m.predict(&corner);
    println!("straight 90° corner: type {} Pn ({:.3}, {:.3}) (a square needs type 0 at (1, 1)); P = {:.3}",
        p.element_type.number(), p.pn.x, p.pn.y, m.type_score(&corner));
    let rules = RulesModel::DEFAULT.predict(&corner);
    println!(
        "rules on the same corner: type {} Pn ({:.3}, {:.3})",
        rules.element_type.number(),
        rules.pn.x,
        rules.pn.y
    );
    // Real steps: in pure-model mode the guard takes the model's element as
    // predicted or rejects it; count both (the fallbacks finish the mesh).
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundaries");
    println!("pure-model runs (remedies off):");
    for name in ["square", "lshape", "irregular", "circle", "plate_hole"] {
        let b = quadex::io::read_boundary(&dir.join(format!("{name}.poly"))).unwrap();
        let params = MeshParams {
            pure_model: true,
            ..MeshParams::DEFAULT
        };
        let mut mesher = Mesher::new(b, Arc::new(ThesisModel::TABLE_8), params);
        let end = loop {
            match mesher.step() {
                Ok(StepOutcome::Stepped(_)) => {}
                Ok(StepOutcome::Done) => break "finished".to_string(),
                Err(e) => break e.to_string(),
            }
        };
        let (ok, all) = mesher.stats().model_valid();
        println!("  {name}: {ok} of {all} predictions valid; run {end}");
    }
}

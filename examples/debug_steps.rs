//! Prints the front and the quads at given nodes after each of the first
//! steps: `cargo run --example debug_steps -- IN.poly FROM TO NODE...`

use quadex::extract::{MeshParams, Mesher};
use quadex::model::RulesModel;
use std::sync::Arc;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let b = quadex::io::read_boundary(a[1].as_ref()).expect("boundary");
    let (from, to): (usize, usize) = (a[2].parse().unwrap(), a[3].parse().unwrap());
    let watch: Vec<u32> = a[4..].iter().map(|s| s.parse().unwrap()).collect();
    let mut m = Mesher::new(b, Arc::new(RulesModel::DEFAULT), MeshParams::DEFAULT);
    for k in 1..=to {
        let r = m.step().expect("step");
        if k >= from {
            println!("step {k}: {r:?}\n  check: {:?}", m.check_invariants());
            for &w in &watch {
                println!("  at {w}: {:?}", m.quads_at(w));
            }
            let f = m.front();
            for l in f.live_loops() {
                let nodes: Vec<u32> = f.loop_nodes(l);
                println!("  loop {l}: {nodes:?}");
            }
            for (i, q) in m.mesh().quads.iter().enumerate() {
                if q.iter().any(|v| watch.contains(v)) {
                    println!("  quad {i}: {q:?}");
                }
            }
        }
    }
}

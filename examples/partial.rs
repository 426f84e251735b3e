//! Meshes a boundary step by step and, when the run stops (finished, stuck
//! or after `--steps N`), writes an SVG of the mesh so far with the front
//! drawn in blue, and prints the steps by kind. Extraction runs to the end
//! with no fill unless `--layers K` or `--fill` say otherwise. The boundary
//! is meshed moved next to the origin, as `quadex mesh` meshes it.
//!
//! `cargo run --release --example partial -- IN.poly OUT.svg [--steps N]
//! [--model default|rules|thesis|FILE] [--layers K] [--fill] [--trace]
//! [--check-every N] [--msh MESH.msh] [--front FRONT.txt]`
//!
//! `--trace` prints every step. The invariants are checked after every
//! step, or after every `N`th and at the end with `--check-every N` (a
//! check costs time in proportion to the mesh, too much for a large case
//! at every step).
//! `--msh` also writes the mesh so far, `--front` the front's loops, one
//! line each of `x y` points separated by `;`.

use quadex::extract::{MeshParams, Mesher, StepOutcome};
use quadex::io::svg::{write_svg, SvgOptions};
use std::sync::Arc;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (input, output) = (&args[1], &args[2]);
    let opt = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|k| args.get(k + 1))
            .cloned()
    };
    let flag = |name: &str| args.iter().any(|a| a == name);
    let max: usize = opt("--steps")
        .and_then(|s| s.parse().ok())
        .unwrap_or(usize::MAX);
    let model: Arc<dyn quadex::Model> =
        Arc::from(quadex::model::load(&opt("--model").unwrap_or("default".into())).expect("model"));
    let params = MeshParams {
        fill_after_layers: opt("--layers").and_then(|s| s.parse().ok()),
        fill: flag("--fill"),
        ..MeshParams::DEFAULT
    };
    // In the command line's frame (`Boundary::to_local`), so the run is
    // the one `quadex mesh` makes; files are written moved back.
    let (b, origin) = quadex::io::read_boundary(input.as_ref())
        .expect("boundary")
        .to_local();
    let mut m = Mesher::new(b, model, params);
    let check_every: usize = opt("--check-every")
        .and_then(|s| s.parse().ok())
        .unwrap_or(1)
        .max(1);
    let mut steps = 0;
    while steps < max {
        match m.step() {
            Ok(StepOutcome::Stepped(r)) => {
                steps += 1;
                if flag("--trace") {
                    eprintln!(
                        "{steps} {:?} ref={:?} remedy={:?} type={:?} removed={} front={}",
                        r.kind,
                        r.reference,
                        r.remedy,
                        r.element_type,
                        r.removed,
                        m.front().len()
                    );
                }
            }
            Ok(StepOutcome::Done) => break,
            Err(e) => {
                eprintln!("stopped after {steps} steps: {e}");
                break;
            }
        }
        if steps % check_every == 0 {
            if let Err(e) = m.check_invariants() {
                eprintln!("invariant broken after step {steps}: {e}");
                break;
            }
        }
        if flag("--tiny") {
            // Front edges far shorter than the size there.
            let (f, nodes) = (m.front(), &m.mesh().nodes);
            for lid in f.live_loops() {
                for sl in f.loop_slots(lid) {
                    let (a, b) = (f.node(sl), f.node(f.next(sl)));
                    let (pa, pb) = (nodes[a as usize], nodes[b as usize]);
                    if pa.distance(pb) < 0.05 * m.size().at(pa) {
                        eprintln!("step {steps}: tiny edge {a}-{b} {:.2e}", pa.distance(pb));
                        for v in [a, b] {
                            for &q in m.quads_at(v) {
                                let q = m.mesh().quads[q as usize];
                                eprintln!("  quad {q:?} {:?}", q.map(|k| nodes[k as usize]));
                            }
                        }
                    }
                }
            }
        }
    }
    // The last state, unless the loop checked it already (or stopped at a
    // broken invariant).
    if steps % check_every != 0 {
        if let Err(e) = m.check_invariants() {
            eprintln!("invariant broken at the end ({steps} steps): {e}");
        }
    }
    if flag("--sizes") {
        for k in 0..m.boundary().points.len().min(8) {
            let p = m.boundary().points[k];
            eprintln!("size at node {k} {:?}: {:.4}", p + origin, m.size().at(p));
        }
    }
    if let Some(node) = opt("--explain").and_then(|s| s.parse::<u32>().ok()) {
        match m.explain(node) {
            Some(list) => {
                for c in list {
                    eprintln!("  {c:?}");
                }
            }
            None => eprintln!("node {node} is not on the front"),
        }
    }
    let mut svg = write_svg(m.mesh(), &SvgOptions::default());
    // Overlay the front.
    let mesh = m.mesh();
    let (mut lo, mut hi) = (
        glam::DVec2::splat(f64::INFINITY),
        glam::DVec2::splat(f64::NEG_INFINITY),
    );
    for p in &mesh.nodes {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let size = hi - lo;
    let s = (800.0 - 20.0) / size.x.max(size.y);
    let tx = |p: glam::DVec2| ((p.x - lo.x) * s + 10.0, (hi.y - p.y) * s + 10.0);
    let f = m.front();
    let mut extra = String::from("<g fill=\"none\" stroke=\"blue\" stroke-width=\"1.2\">\n");
    for lid in f.live_loops() {
        extra.push_str("<polygon points=\"");
        for sl in f.loop_slots(lid) {
            let (x, y) = tx(mesh.nodes[f.node(sl) as usize]);
            extra.push_str(&format!("{x:.2},{y:.2} "));
        }
        extra.push_str("\"/>\n");
    }
    extra.push_str("</g>\n</svg>\n");
    svg = svg.replace("</svg>\n", &extra);
    std::fs::write(output, svg).expect("write");
    if let Some(path) = opt("--msh") {
        let mut world = mesh.clone();
        quadex::pipeline::to_world(&mut world, origin);
        quadex::io::write_mesh(&world, path.as_ref()).expect("write mesh");
    }
    if let Some(path) = opt("--front") {
        let mut text = String::new();
        for lid in f.live_loops() {
            for sl in f.loop_slots(lid) {
                let p = mesh.nodes[f.node(sl) as usize] + origin;
                text.push_str(&format!("{} {};", p.x, p.y));
            }
            text.push('\n');
        }
        std::fs::write(path, text).expect("write front");
    }
    if f.len() <= 24 || flag("--loops") {
        for lid in f.live_loops() {
            let pts: Vec<String> = f
                .loop_slots(lid)
                .iter()
                .map(|&sl| {
                    let v = f.node(sl);
                    let p = mesh.nodes[v as usize] + origin;
                    let b = if mesh.is_boundary(v) { "*" } else { "" };
                    format!(
                        "{v}{b}({:.7},{:.7}) {:.1}°",
                        p.x,
                        p.y,
                        f.angle(sl, &mesh.nodes).to_degrees()
                    )
                })
                .collect();
            eprintln!("loop {lid}: {}", pts.join("  "));
        }
    }
    eprintln!(
        "{} quads, {} front nodes in {} loops; steps {:?}",
        mesh.quads.len(),
        f.len(),
        f.live_loops().count(),
        m.stats().by_kind
    );
}

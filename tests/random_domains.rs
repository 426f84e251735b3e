//! Seeded property test: small generated awkward domains
//! (`quadex::domains`: many holes, channels, grading, spikes, near-touching
//! loops, unbalanced sides, mixtures) are meshed with the default model and
//! parameters through the library's pipeline. Every one must finish
//! without a panic, within a time limit, as a finished all-quad mesh
//! (`check_finished`: convex quads tiling the domain, boundary kept) of the
//! domain's area. Failures are listed by name, family and seed, so that
//! `quadex::domains::generate(family, seed)` reproduces each.

use quadex::domains::{suite_domains, Domain};
use quadex::extract::StepKind;
use std::sync::{mpsc, Arc};
use std::time::{Duration, Instant};

/// The suite drawn from (seed, size); the test meshes its small domains.
const SUITE_SEED: u64 = 15;
const SUITE_SIZE: usize = 70;
/// Domains with more boundary nodes than this are left to the sweep
/// (`.ci/domains_sweep.py`).
const MAX_NODES: usize = 200;
/// Domains meshed at most.
const COUNT: usize = 36;
/// Time one domain may take before it counts as a failure.
const LIMIT: Duration = Duration::from_secs(20);

fn small_domains() -> Vec<Domain> {
    suite_domains(SUITE_SIZE, SUITE_SEED)
        .into_iter()
        .filter(|d| d.boundary.node_count() <= MAX_NODES)
        .take(COUNT)
        .collect()
}

/// Meshes `d` on its own thread; `Err` says why it did not give a valid
/// finished mesh. A domain over the time limit is left running.
fn mesh_one(d: &Domain) -> Result<usize, String> {
    let boundary = d.boundary.clone();
    let area = boundary.area();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let model = Arc::new(quadex::model::default_model().expect("the shipped model loads"));
        let out = quadex::mesh_boundary(&boundary, model, &quadex::Params::DEFAULT, |_| {});
        let _ = tx.send(out);
    });
    let (mesh, stats) = match rx.recv_timeout(LIMIT) {
        Ok(Ok(done)) => done,
        Ok(Err(e)) => return Err(format!("error: {e}")),
        Err(mpsc::RecvTimeoutError::Timeout) => return Err(format!("over {LIMIT:?}")),
        Err(mpsc::RecvTimeoutError::Disconnected) => return Err("panicked".into()),
    };
    mesh.check_invariants(true)
        .map_err(|e| format!("invariants: {e}"))?;
    mesh.check_finished()
        .map_err(|e| format!("not finished: {e}"))?;
    if mesh.quads.is_empty() {
        return Err("no quads".into());
    }
    if (mesh.domain_area() - area).abs() > 1e-9 * area.abs() {
        return Err(format!("area {} for {area}", mesh.domain_area()));
    }
    let sj = quadex::MeshQuality::of(&mesh).sj_min;
    if sj.is_nan() || sj <= 0.0 {
        return Err(format!("scaled Jacobian {sj}"));
    }
    // The fill's count is of the quads extraction and the fill left.
    if stats.quads_made(StepKind::Fill) > stats.standing || stats.standing == 0 {
        return Err(format!(
            "fill quads {} of {} standing",
            stats.quads_made(StepKind::Fill),
            stats.standing
        ));
    }
    Ok(stats.by_kind.get(&StepKind::Fill).copied().unwrap_or(0))
}

/// `cargo test --release --test random_domains -- --nocapture` prints the
/// time and how many ended in a fill.
#[test]
fn small_random_domains_mesh_validly() {
    let domains = small_domains();
    assert!(domains.len() >= 30, "only {} small domains", domains.len());
    let t0 = Instant::now();
    let mut failures = Vec::new();
    let mut filled = 0;
    for d in &domains {
        match mesh_one(d) {
            Ok(fill) => filled += usize::from(fill > 0),
            Err(why) => failures.push(format!(
                "{} ({} seed {}, {}): {why}",
                d.name, d.family, d.seed, d.description
            )),
        }
    }
    println!(
        "{} domains in {:.1} s, {} ended in a fill, {} failed",
        domains.len(),
        t0.elapsed().as_secs_f64(),
        filled,
        failures.len()
    );
    for f in &failures {
        println!("  {f}");
    }
    assert!(
        failures.is_empty(),
        "{} of {} domains failed:\n{}",
        failures.len(),
        domains.len(),
        failures.join("\n")
    );
}

/// A mixed domain (seven teeth of 5°, a slot of 1:25) on which the region
/// fill's triangulation met a panic inside spade's refinement ("Failed to
/// locate position"): that attempt now fails quietly and the fill's next
/// try meshes the region.
#[test]
fn a_panic_inside_spade_is_an_attempt_that_failed() {
    let d = quadex::domains::generate(quadex::domains::Family::Mixed, 2_679_092_208_377_531_280);
    assert_eq!(d.boundary.node_count(), 124, "{}", d.description);
    if let Err(why) = mesh_one(&d) {
        panic!("{} ({}): {why}", d.name, d.description);
    }
}

/// Steps the generated domain `family`/`seed` to the end with the default
/// model, checking the invariants (among them: a clockwise loop lies
/// inside a counter-clockwise one) after every step, and with `fill`
/// false refusing a fill; returns how many steps of `kind` it took.
fn steps_checked(family: quadex::domains::Family, seed: u64, kind: StepKind, fill: bool) -> usize {
    use quadex::extract::{MeshParams, Mesher, StepOutcome};
    let d = quadex::domains::generate(family, seed);
    let model = Arc::new(quadex::model::default_model().expect("the shipped model loads"));
    let mut m = Mesher::new(d.boundary, model, MeshParams::DEFAULT);
    let mut taken = 0;
    for k in 1.. {
        match m.step().expect("a step") {
            StepOutcome::Done => break,
            StepOutcome::Stepped(r) => {
                assert!(
                    fill || r.kind != StepKind::Fill,
                    "{family:?} {seed:#x}: step {k} fills the region left"
                );
                taken += usize::from(r.kind == kind);
            }
        }
        if let Err(e) = m.check_invariants() {
            panic!("{family:?} {seed:#x}: after step {k}: {e}");
        }
    }
    assert!(m.is_done());
    taken
}

/// Generated domains on which a loop once turned inside out, each by
/// another step; a loop running the wrong way cuts its elements outwards,
/// out of the domain. Each is stepped to the end with the invariants
/// checked after every step:
/// - a channel domain (a rectangle with a thin slot): a loop relaxation
///   moved a front node clean across the thin loop's far side, no edge
///   crossing; extraction then cut elements outside the rectangle until
///   the run was rewound to nothing and filled (it now finishes by
///   extraction alone);
/// - a domain with holes: a seam closed a six-node loop into a four-node
///   one running clockwise;
/// - a four-node loop settled before its closure (its nodes moved for the
///   closure's quality alone);
/// - an element on a four-node loop (which leaves another four-node loop,
///   P0 moved to Pn) left it running the other way;
/// - a seam whose corner and the edges beside it swept over an island of
///   elements (no edge crossed, but the island's loop was left outside the
///   front).
#[test]
fn no_step_turns_a_loop_inside_out() {
    use quadex::domains::Family;
    for (family, seed, kind, fill) in [
        (
            Family::Channel,
            0xb399_c8a2_6925_d996,
            StepKind::Relax,
            false,
        ),
        (
            Family::ManyHoles,
            0x6f8d_8fc9_a414_4523,
            StepKind::Seam,
            false,
        ),
        (
            Family::ManyHoles,
            0x1d73_c8dd_c1da_57b2,
            StepKind::Close4,
            false,
        ),
        (
            Family::ManyHoles,
            0x1d73_c8dd_c1da_57cd,
            StepKind::Close4,
            false,
        ),
        (Family::Mixed, 0x2e75_7d1e_a087_85cc, StepKind::Seam, true),
    ] {
        let taken = steps_checked(family, seed, kind, fill);
        assert!(
            taken > 0,
            "{family:?} {seed:#x}: no {kind:?} step (the case no longer tests it)"
        );
    }
}

/// A 4- or 6-node loop whose closure is folded is settled again at every
/// step; it used to take any quad over its folded closure's quality, so a
/// node crept, step after step, onto its neighbour, and the rows started
/// on the microscopic edge left 671 quads under 10⁻⁵ of the domain across
/// in this 2-against-106-node rectangle (the smallest 1.2e-4 in a domain
/// 190 wide). No quad is now under a hundred-thousandth of the domain.
#[test]
fn settling_a_small_loop_never_collapses_an_edge() {
    use quadex::domains::{generate, Family};
    let d = generate(Family::Unbalanced, 0xb04e1af8d66fc382);
    let (local, _) = d.boundary.to_local();
    let extent = local.bbox().size().max_element();
    let model = Arc::new(quadex::model::default_model().expect("the shipped model loads"));
    let mut m = quadex::Mesher::new(local, model, quadex::MeshParams::DEFAULT);
    m.run(|_| {}).expect("finishes");
    let mesh = m.mesh();
    let smallest = mesh
        .quads
        .iter()
        .map(|q| {
            let p = q.map(|v| mesh.nodes[v as usize]);
            p[0].distance(p[2]).max(p[1].distance(p[3]))
        })
        .fold(f64::INFINITY, f64::min);
    assert!(
        smallest > 1e-5 * extent,
        "{}: a quad {smallest:e} across in a domain {extent} wide",
        d.description
    );
}

/// Generated domains on which a rip-up put parts of the given boundary
/// back on the front and nothing looked at them again: the corner of a
/// graded side (segments 1:100) lost its fan, short given edges of a
/// zig-zag's slits got no notch, and the region left there needed the
/// fill. The rebuilt front's corners and short edges are now looked at
/// again; each domain is stepped to the end with the invariants checked
/// after every step and no fill.
#[test]
fn what_a_rip_up_takes_away_at_the_boundary_is_made_again() {
    use quadex::domains::Family;
    for seed in [0xf65b_d507_8796_b41f, 0xf65b_d507_8796_b430] {
        let fans = steps_checked(Family::GradedSide, seed, StepKind::Fan, false);
        assert!(
            fans >= 3,
            "{seed:#x}: {fans} fans, the two corners' and one again at least"
        );
    }
    let notches = steps_checked(
        Family::Zigzag,
        0x6deb_28c2_64f8_a0e3,
        StepKind::Notch,
        false,
    );
    assert!(notches > 0, "the zig-zag's slits take notches");
}

/// A zig-zag ring (a hexagonal outline of teeth around a hole, nothing
/// between them but the ring) closes by band rows. Split into three rows
/// (wedges beside the sides, a clean middle row), its rows were each
/// convex but folded over one another where a tooth's tip and the hole
/// face each other askew: the quads covered more than the ring, and the
/// finished mesh used an edge twice. Rows that fold are not taken; the
/// ring takes its own rows instead. Stepped with the invariants (among
/// them the covered area) checked after every step, no fill.
#[test]
fn band_rows_that_fold_over_are_not_taken() {
    use quadex::domains::Family;
    let bands = steps_checked(
        Family::Zigzag,
        0x6deb_28c2_64f8_a0ea,
        StepKind::Mapped,
        false,
    );
    assert!(bands > 0, "the ring closes by rows");
}

/// The real-like families draw what they say: a band's two sides differ in
/// node count, a zig-zag outline turns by 60° at every node that is not a
/// cut point (120° in or out), a tube sheet has 16 to 196 holes, and a
/// graded side's end segments are ten times finer or more than its
/// middle. Every draw is a valid boundary of even loops.
#[test]
fn real_like_families_draw_what_they_say() {
    use quadex::domains::{real_like_domains, Family};
    let domains = real_like_domains(40, 3);
    assert_eq!(domains.len(), 40);
    for d in &domains {
        let b = &d.boundary;
        let pts = |l: &Vec<usize>| -> Vec<quadex::geom::Point> {
            l.iter().map(|&i| b.points[i]).collect()
        };
        assert!(b.loops.iter().all(|l| l.len() % 2 == 0), "{}", d.name);
        match d.family {
            Family::Band if b.loops.len() == 2 => {
                assert_ne!(b.loops[0].len(), b.loops[1].len(), "{}", d.description);
            }
            Family::Band => assert!(d.description.starts_with("sliver"), "{}", d.description),
            Family::Zigzag => {
                let p = pts(&b.loops[0]);
                let n = p.len();
                let sharp = (0..n)
                    .filter(|&k| {
                        let (a, c) = (p[(k + n - 1) % n], p[(k + 1) % n]);
                        let turn = (p[k] - a).angle_to(c - p[k]).abs().to_degrees();
                        (turn - 60.0).abs() < 1e-6
                    })
                    .count();
                // Six sides of at least two teeth, two turns a tooth.
                assert!(sharp >= 24, "{}: {sharp} turns of 60°", d.description);
                if d.description.contains("slits") {
                    // A slit's end is 1/40 to 1/20 of a zig, its walls
                    // half a zig or more.
                    let len = |k: usize| p[k].distance(p[(k + 1) % n]);
                    let ends = (0..n)
                        .filter(|&k| {
                            let (before, after) = (len((k + n - 1) % n), len((k + 1) % n));
                            before > 10.0 * len(k) && after > 10.0 * len(k)
                        })
                        .count();
                    assert!(ends > 0, "{}: no slit end", d.description);
                }
            }
            Family::TubeSheet => {
                assert!((17..=197).contains(&b.loops.len()), "{}", d.description);
            }
            Family::GradedSide => {
                let p = pts(&b.loops[0]);
                let first = p[0].distance(p[1]);
                let longest = p
                    .windows(2)
                    .map(|w| w[0].distance(w[1]))
                    .fold(0.0f64, f64::max);
                assert!(longest > 10.0 * first, "{}", d.description);
            }
            f => panic!("{f} is not a real-like family"),
        }
    }
}

/// A zig-zag outline with slits (the real-like suite of seed 5, `117`):
/// finishing left a quad two units long between sides of 0.17 and 0.18 away
/// from the boundary, a stretch no single corner's move brings within
/// 10:1. Untapering moves its corners one pass after the other; no quad
/// without a corner on the boundary (where only the boundary can force a
/// stretch) is left past the bound.
#[test]
fn a_quad_away_from_the_boundary_is_not_left_stretched_past_ten() {
    use quadex::domains::{generate, Family};
    use quadex::quality::{Shape, GOOD_RATIO};
    let d = generate(Family::Zigzag, 0xda75d895f2226e9c);
    let model = Arc::new(quadex::model::default_model().expect("the shipped model loads"));
    let (mesh, _) = quadex::mesh_boundary(&d.boundary, model, &quadex::Params::DEFAULT, |_| {})
        .expect("meshes");
    let inside: Vec<f64> = mesh
        .quads
        .iter()
        .filter(|q| !q.iter().any(|&v| mesh.is_boundary(v)))
        .map(|q| Shape::of(mesh.corners(q)).side_ratio())
        .collect();
    assert!(inside.len() > 100, "{} quads inside", inside.len());
    let worst = inside.iter().copied().fold(0.0, f64::max);
    assert!(worst <= GOOD_RATIO, "a quad inside stretched {worst:.2}:1");
}

/// A graded side (real-like family, seed 2's `207`) with a 45° corner
/// between segments about 130 times apart. The corner's fan, its far
/// corners where its quads are squarest, leaves kites: the front leaves
/// the long segment's end by an edge a tenth of the one beside it, the
/// rows from there knot, and the run needs the region fill (a quad of
/// scaled Jacobian 0.003 and taper 367 after finishing). Before that fill
/// the run is made again with balanced fans and finishes by extraction
/// alone, every quad within 10:1.
#[test]
fn a_graded_side_whose_squarest_fans_need_the_fill_finishes_with_balanced_ones() {
    use quadex::domains::{generate, Family};
    use quadex::quality::{Shape, GOOD_RATIO};
    let d = generate(Family::GradedSide, 0xb11b8e4816ee8538);
    let model: Arc<dyn quadex::model::Model> =
        Arc::new(quadex::model::default_model().expect("the shipped model loads"));
    let mut once = quadex::Params::DEFAULT;
    once.extract.tuning.fill.refan = false;
    let (_, stats) = quadex::mesh_boundary(&d.boundary, model.clone(), &once, |_| {})
        .expect("meshes with the fill");
    assert!(stats.count(StepKind::Fan) > 0);
    assert!(stats.count(StepKind::Fill) > 0, "{stats:?}");
    assert!(!stats.refanned);

    let (mesh, stats) =
        quadex::mesh_boundary(&d.boundary, model.clone(), &quadex::Params::DEFAULT, |_| {})
            .expect("meshes");
    assert!(stats.refanned);
    assert!(stats.count(StepKind::Fan) > 0);
    assert_eq!(stats.count(StepKind::Fill), 0, "{stats:?}");
    let shapes: Vec<Shape> = mesh
        .quads
        .iter()
        .map(|q| Shape::of(mesh.corners(q)))
        .collect();
    let stretch = shapes.iter().map(|s| s.side_ratio()).fold(0.0, f64::max);
    let sj = shapes.iter().map(|s| s.scaled_jacobian).fold(1.0, f64::min);
    assert!(stretch <= GOOD_RATIO, "a quad stretched {stretch:.2}:1");
    assert!(sj > 0.15, "scaled Jacobian {sj:.3}");
}

/// The run made again with balanced fans is the run from then on: its
/// history replays to the same mesh, so undoing its last step and taking
/// it again gives the same quads.
#[test]
fn a_run_made_again_with_balanced_fans_undoes_and_redoes_its_steps() {
    use quadex::domains::{generate, Family};
    use quadex::extract::{Mesher, Rung, StepOutcome};
    let d = generate(Family::GradedSide, 0xb11b8e4816ee8538);
    let model = Arc::new(quadex::model::default_model().expect("the shipped model loads"));
    let (local, origin) = d.boundary.to_local();
    let mut m = Mesher::new(local, model, quadex::Params::DEFAULT.extract.moved(origin));
    let mut last = None;
    while let StepOutcome::Stepped(r) = m.step().expect("steps") {
        last = Some(r);
    }
    let last = last.expect("a step");
    assert_eq!((last.rung, last.kind), (Rung::Refan, StepKind::Refan));
    assert_eq!(last.quads.len(), m.mesh().quads.len());
    assert!(last.removed > 0);
    assert!(m.stats().refanned && m.is_done());
    let done = m.mesh().quads.clone();
    assert!(m.undo());
    assert!(!m.is_done());
    assert!(m.mesh().quads.len() < done.len());
    assert!(matches!(m.step().expect("steps"), StepOutcome::Stepped(_)));
    assert!(m.is_done());
    assert_eq!(m.mesh().quads, done);
}

//! Several regions and named boundaries (`tests/data/regions/`): each face
//! meshed with its boundary fixed, one conforming mesh with shared node
//! numbering, regions and groups written in every format, the same bytes
//! whatever the thread count, and every broken graph refused with one line.

mod common;

use quadex::io::{self, MeshFormat};
use quadex::pipeline::Params;
use quadex::pslg::Pslg;
use quadex::regions::{mesh_regions, RegionMesh};
use std::path::PathBuf;
use std::sync::Arc;

fn case(name: &str) -> PathBuf {
    common::bench().join("regions").join(name)
}

fn graph(name: &str) -> Pslg {
    io::read_graph(&case(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// `quadex mesh INPUT -o OUT`.
fn quadex_mesh(input: &std::path::Path, out: &std::path::Path) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
        .args([
            "mesh".as_ref(),
            input.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ])
        .output()
        .unwrap()
}

fn mesh(g: &Pslg) -> RegionMesh {
    let model = Arc::new(quadex::model::default_model().unwrap());
    mesh_regions(g, model, &Params::DEFAULT, |_| {}).unwrap()
}

fn mesh_with_threads(g: &Pslg, threads: usize) -> RegionMesh {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| mesh(g))
}

/// The union is a valid mesh of the graph's outline (quadex's own reader
/// checks it: convex quads, edges used once or twice in opposite
/// directions, the quads covering the enclosed area once), and every
/// quad's corners are nodes of one numbering.
fn assert_valid(m: &RegionMesh) {
    m.check_conforming().unwrap();
    let text = MeshFormat::Msh41.render_regions(m);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.msh");
    std::fs::write(&path, &text).unwrap();
    let back = io::read_mesh(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.quads.len(), m.mesh.quads.len());
    assert!(m.regions.iter().all(|r| r.quality.quads > 0));
    assert_eq!(
        m.regions.iter().map(|r| r.quality.quads).sum::<usize>(),
        m.mesh.quads.len()
    );
}

#[test]
fn a_square_cut_by_an_uneven_interface_meshes_conforming() {
    let g = graph("split_square.poly");
    let m = mesh(&g);
    assert_valid(&m);
    let names: Vec<&str> = m.regions.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["region_1", "region_2"]);
    let groups: Vec<(&str, usize)> = m
        .groups
        .iter()
        .map(|g| (g.name.as_str(), g.edges.len()))
        .collect();
    assert_eq!(
        groups,
        [("marker_1", 10), ("marker_2", 10), ("marker_3", 8)]
    );
    // Region 1 lies left of the interface x = 0.4, region 2 right of it.
    for (q, &r) in m.mesh.quads.iter().zip(&m.quad_region) {
        let c = m.mesh.corners(q).iter().fold(0.0, |s, p| s + p.x) / 4.0;
        assert_eq!(r, u32::from(c > 0.4), "centroid x {c}");
    }
    // Every interface node is a corner of quads of both regions.
    for e in &m.groups[2].edges {
        for &v in e {
            let sides: std::collections::BTreeSet<u32> = m
                .mesh
                .quads
                .iter()
                .zip(&m.quad_region)
                .filter(|(q, _)| q.contains(&v))
                .map(|(_, &r)| r)
                .collect();
            assert_eq!(sides.len(), 2, "interface node {v}");
        }
    }
}

#[test]
fn every_multi_region_case_meshes_valid_with_no_fill() {
    for name in [
        "split_square.poly",
        "layered_strip.poly",
        "plate_inclusions.poly",
        "annulus_two_materials.poly",
        "l_bracket.poly",
        "machine.poly",
    ] {
        let m = mesh(&graph(name));
        assert_valid(&m);
        assert_eq!(
            m.steps().count(quadex::extract::StepKind::Fill),
            0,
            "{name}"
        );
        assert!(m.quality().sj_min > 0.5, "{name}: {:?}", m.quality());
    }
}

#[test]
fn the_layered_strip_keeps_its_thinnest_layer_one_row() {
    let m = mesh(&graph("layered_strip.poly"));
    let thin = m.regions.iter().find(|r| r.tag == 4).unwrap();
    assert_eq!(thin.quality.quads, 100);
    assert!(thin.quality.sj_min > 0.99);
}

#[test]
fn the_machine_example_has_its_named_regions_and_groups() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/examples/machine.json");
    let g = io::read_graph(&path).unwrap();
    let m = mesh(&g);
    assert_valid(&m);
    let names: Vec<&str> = m.regions.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "rotor_iron",
            "magnets",
            "air_gap",
            "stator_iron",
            "windings"
        ]
    );
    let groups: Vec<&str> = m.groups.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(groups, ["shaft", "stator_outside"]);
    // The .poly form of the same part gives the same mesh.
    let p = mesh(&graph("machine.poly"));
    assert_eq!(p.mesh.nodes, m.mesh.nodes);
    assert_eq!(p.mesh.quads, m.mesh.quads);
}

#[test]
fn the_mesh_is_the_same_bytes_on_one_thread_and_two() {
    let g = graph("machine.poly");
    let one = mesh_with_threads(&g, 1);
    let two = mesh_with_threads(&g, 2);
    for fmt in MeshFormat::ALL {
        assert_eq!(
            fmt.render_regions(&one),
            fmt.render_regions(&two),
            "{fmt:?}"
        );
    }
}

/// A single region's remeshing works out several regions at once on the
/// threads `--threads` gives it: the file written is the same on one
/// thread and on three (meshes remeshed in several regions).
#[test]
fn a_remeshed_region_is_the_same_bytes_on_one_thread_and_three() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "freemesh_boundary_fly_r2",
        "freemesh_boundary9",
        "freemesh_fat1",
    ] {
        let input = common::bench().join("peer").join(format!("{name}.poly"));
        let files: Vec<Vec<u8>> = ["1", "3"]
            .iter()
            .map(|t| {
                let out = dir.path().join(format!("{name}_{t}.msh"));
                let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
                    .arg("mesh")
                    .arg(&input)
                    .arg("-o")
                    .arg(&out)
                    .args(["--threads", t])
                    .output()
                    .unwrap();
                assert!(
                    o.status.success(),
                    "{name}: {}",
                    String::from_utf8_lossy(&o.stderr)
                );
                std::fs::read(&out).unwrap()
            })
            .collect();
        assert!(!files[0].is_empty(), "{name}");
        assert!(files[0] == files[1], "{name}: the meshes differ");
    }
}

/// Stepping face by face with the step API gives the mesh of the
/// parallel run.
#[test]
fn stepping_region_by_region_gives_the_same_mesh() {
    let g = graph("plate_inclusions.poly");
    let model = Arc::new(quadex::model::default_model().unwrap());
    let mut s = quadex::regions::RegionStepper::new(g.clone(), model, Params::DEFAULT).unwrap();
    assert_eq!(s.faces().len(), 4);
    let mut regions = Vec::new();
    let mut steps = 0;
    while !s.is_done() {
        regions.push((s.current(), s.current_region()));
        s.step().unwrap();
        steps += 1;
    }
    regions.dedup();
    let names: Vec<&str> = regions.iter().map(|(_, r)| r.as_str()).collect();
    assert_eq!(names, ["region_1", "region_2", "region_2", "region_2"]);
    let stepped = s.finish().unwrap();
    let run = mesh(&g);
    assert_eq!(stepped.steps().steps, steps);
    assert_eq!(
        MeshFormat::Msh41.render_regions(&stepped),
        MeshFormat::Msh41.render_regions(&run)
    );
}

#[test]
fn every_format_carries_regions_and_groups() {
    let m = mesh(&graph("split_square.poly"));
    let msh = MeshFormat::Msh41.render_regions(&m);
    for want in [
        "1 1 \"marker_1\"",
        "1 3 \"marker_3\"",
        "2 1 \"region_1\"",
        "2 2 \"region_2\"",
    ] {
        assert!(msh.contains(want), "{want}");
    }
    let msh22 = MeshFormat::Msh22.render_regions(&m);
    assert!(msh22.contains("2 2 \"region_2\""));
    // 28 line elements and the quads, each with its physical tag.
    let elements: Vec<&str> = msh22
        .split("$Elements\n")
        .nth(1)
        .unwrap()
        .lines()
        .skip(1)
        .take_while(|l| !l.starts_with('$'))
        .collect();
    assert_eq!(elements.len(), 28 + m.mesh.quads.len());
    assert_eq!(
        elements
            .iter()
            .filter(|l| l.split(' ').nth(1) == Some("1"))
            .count(),
        28
    );
    let inp = MeshFormat::Abaqus.render_regions(&m);
    for want in [
        "ELSET=REGION_1",
        "ELSET=REGION_2",
        "*NSET, NSET=MARKER_1",
        "*SURFACE, TYPE=ELEMENT, NAME=MARKER_3",
    ] {
        assert!(inp.contains(want), "{want}");
    }
    for fmt in [MeshFormat::Vtk, MeshFormat::Vtu] {
        let t = fmt.render_regions(&m);
        assert!(t.contains("region") && t.contains("marker"), "{fmt:?}");
    }
    let vtk = MeshFormat::Vtk.render_regions(&m);
    assert!(vtk.contains(&format!("CELL_TYPES {}", m.mesh.quads.len() + 28)));
}

#[test]
fn a_regions_document_round_trips() {
    let g = graph("plate_inclusions.poly");
    let doc = io::regions_json::RegionsDoc::from_pslg(&g);
    let text = serde_json::to_string(&doc).unwrap();
    let back = io::regions_json::parse(&text).unwrap();
    assert_eq!(back.points, g.points);
    assert_eq!(back.segments, g.segments);
    assert_eq!(back.regions, {
        let mut r = g.regions.clone();
        r.iter_mut().for_each(|r| r.max_area = None);
        r
    });
}

/// A file without regions or markers is meshed exactly as before: the
/// command line's output is the single-domain pipeline's.
#[test]
fn a_plain_boundary_is_written_as_before() {
    let input = common::bench().join("boundaries/plate_hole.poly");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p.msh");
    let o = quadex_mesh(&input, &out);
    assert!(o.status.success());
    let b = io::read_boundary(&input).unwrap();
    let model = Arc::new(quadex::model::default_model().unwrap());
    let (m, _) = quadex::mesh_boundary(&b, model, &Params::DEFAULT, |_| {}).unwrap();
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        MeshFormat::Msh41.render(&m)
    );
}

/// Each broken graph is refused by the command line: exit code 2, one line
/// naming the file and the problem, no output file.
#[test]
fn broken_graphs_are_refused_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for (file, words) in [
        ("dangling_segment.poly", "node 7 ends a dangling segment"),
        (
            "crossing_segments.poly",
            "the segment from node 1 to node 5 crosses the segment from node 2 to node 6 at about (0.5, 0.5)",
        ),
        (
            "node_on_segment.poly",
            "node 7 at (1, 0.5) lies on the segment from node 2 to node 5",
        ),
        (
            "odd_region.poly",
            "region region_1 has 5 boundary nodes, an odd number",
        ),
        (
            "region_outside.poly",
            "region point 2 at (5, 5) lies outside every face",
        ),
        (
            "region_conflict.poly",
            "region points 1 and 2 lie in one face but give attributes 1 and 2",
        ),
    ] {
        let input = case("bad").join(file);
        let out = dir.path().join("out.msh");
        let o = quadex_mesh(&input, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{file}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{file}: {err}");
        assert!(err.contains(file) && err.contains(words), "{file}: {err}");
        assert!(!out.exists(), "{file}");
    }
}

/// A seeded grid of `nx` × `ny` cells, each its own region: corners
/// jiggled, every edge cut into a random count of segments graded by a
/// random ratio, counts made even per cell by adding one segment to a
/// cell's right edge (shared only with the next cell, fixed after it).
fn seeded_grid(seed: u64) -> Pslg {
    use quadex::geom::Point;
    use quadex::pslg::{RegionPoint, Segment};
    let mut r = quadex::rng::SplitMix64::new(seed);
    let (nx, ny) = (r.int(1, 4), r.int(1, 4));
    let (w, h) = (r.uni(1.0, 4.0), r.uni(1.0, 4.0));
    let corner = |r: &mut quadex::rng::SplitMix64, i: usize, j: usize| {
        let inner = |k: usize, n: usize| k > 0 && k < n;
        let dx = if inner(i, nx) { r.uni(-0.2, 0.2) } else { 0.0 };
        let dy = if inner(j, ny) { r.uni(-0.2, 0.2) } else { 0.0 };
        Point::new(
            (i as f64 + dx) * w / nx as f64,
            (j as f64 + dy) * h / ny as f64,
        )
    };
    let mut c = vec![vec![Point::ZERO; ny + 1]; nx + 1];
    for (i, col) in c.iter_mut().enumerate() {
        for (j, p) in col.iter_mut().enumerate() {
            *p = corner(&mut r, i, j);
        }
    }
    // Segment counts: horizontal edges hc[i][j] (cell column i, line j),
    // vertical edges vc[i][j] (line i, cell row j).
    let mut hc = vec![vec![0usize; ny + 1]; nx];
    let mut vc = vec![vec![0usize; ny]; nx + 1];
    hc.iter_mut().flatten().for_each(|n| *n = r.int(1, 12));
    vc.iter_mut().flatten().for_each(|n| *n = r.int(1, 12));
    for j in 0..ny {
        for i in 0..nx {
            if (hc[i][j] + hc[i][j + 1] + vc[i][j] + vc[i + 1][j]) % 2 == 1 {
                vc[i + 1][j] += 1;
            }
        }
    }
    let mut g = Pslg::default();
    let mut index = std::collections::HashMap::new();
    let mut node = |g: &mut Pslg, p: Point| {
        *index
            .entry((p.x.to_bits(), p.y.to_bits()))
            .or_insert_with(|| {
                g.points.push(p);
                g.labels.push(g.points.len() as i64);
                g.points.len() - 1
            })
    };
    let mut edge = |g: &mut Pslg,
                    r: &mut quadex::rng::SplitMix64,
                    a: Point,
                    b: Point,
                    n: usize,
                    marker: i64| {
        // Geometric grading of ratio q from a to b.
        let q: f64 = r.log_uni(0.7, 1.4);
        let weights: Vec<f64> = (0..n).map(|k| q.powi(k as i32)).collect();
        let total: f64 = weights.iter().sum();
        let mut t = 0.0;
        let mut prev = node(g, a);
        for (k, wk) in weights.iter().enumerate() {
            t += wk / total;
            let p = if k + 1 == n { b } else { a + (b - a) * t };
            let id = node(g, p);
            g.segments.push(Segment {
                a: prev,
                b: id,
                marker,
            });
            prev = id;
        }
    };
    for j in 0..=ny {
        for i in 0..nx {
            let m = if j == 0 { 1 } else { 0 };
            edge(&mut g, &mut r, c[i][j], c[i + 1][j], hc[i][j], m);
        }
    }
    for i in 0..=nx {
        for j in 0..ny {
            let m = if i == nx { 2 } else { 0 };
            edge(&mut g, &mut r, c[i][j], c[i][j + 1], vc[i][j], m);
        }
    }
    for i in 0..nx {
        for j in 0..ny {
            let centre = (c[i][j] + c[i + 1][j] + c[i][j + 1] + c[i + 1][j + 1]) * 0.25;
            g.regions.push(RegionPoint {
                at: centre,
                attribute: (j * nx + i + 1) as i64,
                max_area: None,
            });
        }
    }
    g
}

/// Graphs no case was tuned on: seeded grids of graded, jiggled cells.
/// Every one meshes valid and conforming, each cell its own region.
#[test]
fn seeded_grids_of_regions_mesh_valid_and_conforming() {
    let (mut fills, mut worst) = (0, f64::INFINITY);
    for seed in 0..40u64 {
        let g = seeded_grid(0x5eed_0000 + seed);
        let t = std::time::Instant::now();
        let m = mesh(&g);
        let q = m.quality();
        println!(
            "seed {seed}: {} regions, {} quads, {} fills, sj min {:.3} mean {:.3}, {:.2} s",
            m.regions.len(),
            q.quads,
            m.steps().count(quadex::extract::StepKind::Fill),
            q.sj_min,
            q.sj_mean,
            t.elapsed().as_secs_f64()
        );
        assert_valid(&m);
        assert_eq!(m.regions.len(), g.regions.len(), "seed {seed}");
        fills += m.steps().count(quadex::extract::StepKind::Fill);
        worst = worst.min(m.quality().sj_min);
    }
    println!("40 seeded grids: {fills} fills, worst SJ {worst:.3}");
    assert!(worst > 0.0);
}

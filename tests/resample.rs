//! `quadex mesh --resample H`: the boundary is cut to segments of about H
//! before meshing, keeping every given node, and a target too fine to hold
//! is refused like any other bad input.

mod common;

use quadex::io;
use std::process::Command;

fn mesh(input: &std::path::Path, out: &std::path::Path, h: Option<&str>) -> std::process::Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_quadex"));
    c.arg("mesh").arg(input).arg("-o").arg(out);
    if let Some(h) = h {
        c.arg("--resample").arg(h);
    }
    c.output().unwrap()
}

/// The odd-count file is refused as it stands and meshes once resampled:
/// every node of the file is a node of the mesh's boundary, the boundary
/// segments are no longer than the target asks, and the mesh is valid.
#[test]
fn resampling_meshes_an_odd_count_boundary_and_keeps_its_nodes() {
    let input = common::bench().join("bad/odd_count.poly");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.msh");
    let o = mesh(&input, &out, None);
    assert_eq!(o.status.code(), Some(2));
    assert!(!out.exists());

    let o = mesh(&input, &out, Some("0.25"));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m = io::read_mesh(&out).unwrap();
    m.check_finished().unwrap();
    let given = io::read_boundary_loops(&input).unwrap();
    let loops = quadex::mesh::boundary_loops(&m.nodes, &m.quads).unwrap();
    assert_eq!(loops.len(), 1);
    let on_boundary: Vec<_> = loops[0].iter().map(|&v| m.nodes[v as usize]).collect();
    for p in &given[0] {
        assert!(
            on_boundary.iter().any(|q| q.distance(*p) < 1e-9),
            "node {p:?} of the file is not on the mesh's boundary"
        );
    }
    // Eight segments of 1 and three of 2/3 cut into round(len / 0.25)
    // parts, 4 and 3, and one more on the longest piece for an even count.
    assert_eq!(on_boundary.len(), 8 * 4 + 3 * 3 + 1);
    let n = on_boundary.len();
    let longest = (0..n)
        .map(|k| on_boundary[k].distance(on_boundary[(k + 1) % n]))
        .fold(0.0, f64::max);
    assert!(longest <= 0.25 + 1e-9, "longest boundary edge {longest}");
}

/// A target that would give the boundary billions of nodes is refused
/// before any is made: exit 2, one line naming the file, no output.
#[test]
fn a_resample_too_fine_to_hold_is_refused() {
    let input = common::bench().join("boundaries/square.poly");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.msh");
    for h in ["1e-12", "1e-4", "0", "nan"] {
        let o = mesh(&input, &out, Some(h));
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{h}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains("square.poly"), "{err}");
        assert!(!out.exists());
    }
}

//! Every broken boundary in `bench/bad/` is refused with an error that
//! names the problem; none panics.

mod common;

use quadex::io::{read_boundary, ReadError};
use quadex::BoundaryError;

fn refuse(name: &str) -> ReadError {
    let path = common::bench().join("bad").join(name);
    match read_boundary(&path) {
        Ok(_) => panic!("{name} was accepted"),
        Err(e) => {
            let msg = e.to_string();
            assert!(
                !msg.is_empty() && !msg.contains('\n'),
                "{name}: message {msg:?}"
            );
            e
        }
    }
}

macro_rules! bad {
    ($test:ident, $file:expr, $pat:pat) => {
        #[test]
        fn $test() {
            let e = refuse($file);
            assert!(matches!(e, $pat), "{}: {e:?}", $file);
        }
    };
}

bad!(
    bad_segment_index,
    "bad_segment_index.poly",
    ReadError::Boundary(BoundaryError::BadSegmentIndex { node: 9, .. })
);
bad!(
    bowtie,
    "bowtie.poly",
    ReadError::Boundary(
        BoundaryError::Crossing { .. }
            | BoundaryError::ZeroArea { .. }
            | BoundaryError::NodesCoincide { .. }
    )
);
bad!(
    branching,
    "branching.poly",
    ReadError::Boundary(BoundaryError::Branching { .. } | BoundaryError::OpenChain { .. })
);
bad!(
    collinear,
    "collinear.poly",
    ReadError::Boundary(
        BoundaryError::ZeroArea { .. }
            | BoundaryError::Crossing { .. }
            | BoundaryError::NodesCoincide { .. }
    )
);

// Nodes 97 and 98 are 0.0016 apart in a boundary about 430 wide: a
// segment under 1e-5 of the extent repeats its node (a 1000 × 1 rectangle,
// whose short sides are 1e-3 of its extent, is valid: tests/repro.rs).
bad!(
    duplicate_node,
    "duplicate_node_freemesh_boundary10.poly",
    ReadError::Boundary(BoundaryError::DuplicateNode { .. })
);
bad!(empty, "empty.poly", ReadError::Empty);
bad!(garbage, "garbage.poly", ReadError::Syntax { line: 1, .. });
bad!(
    hole_crossing,
    "hole_crossing.poly",
    ReadError::Boundary(BoundaryError::Crossing { .. } | BoundaryError::NodeOnSegment { .. })
);
bad!(
    huge_node_count,
    "huge_node_count.poly",
    ReadError::TooMany { line: 1, .. }
);
bad!(
    huge_segment_count,
    "huge_segment_count.poly",
    ReadError::TooMany { .. }
);
bad!(
    overflow_node_count,
    "overflow_node_count.poly",
    ReadError::TooMany { line: 1, .. }
);
bad!(
    hole_outside,
    "hole_outside.poly",
    ReadError::Boundary(BoundaryError::HoleOutside { .. })
);
bad!(
    inf,
    "inf.poly",
    ReadError::Boundary(BoundaryError::NonFinite { node: 3 })
);
bad!(
    nan,
    "nan.poly",
    ReadError::Boundary(BoundaryError::NonFinite { node: 3 })
);
bad!(
    odd_count,
    "odd_count.poly",
    ReadError::Boundary(BoundaryError::OddNodeCount { count: 11 })
);
bad!(
    open_chain,
    "open_chain.poly",
    ReadError::Boundary(BoundaryError::OpenChain { .. })
);
bad!(
    self_intersecting_star,
    "self_intersecting_star.poly",
    ReadError::Boundary(
        BoundaryError::NodeOnSegment {
            loop_a: 0,
            node: 32,
            loop_b: 0,
            from: 12,
            to: 13
        } | BoundaryError::Crossing { .. }
    )
);
bad!(
    touching_hole,
    "touching_hole.poly",
    ReadError::Boundary(
        BoundaryError::Crossing { .. }
            | BoundaryError::NodesCoincide { .. }
            | BoundaryError::NodeOnSegment { .. }
    )
);
bad!(
    truncated,
    "truncated.poly",
    ReadError::Truncated { .. } | ReadError::TooMany { .. }
);
bad!(
    two_nodes,
    "two_nodes.poly",
    ReadError::Boundary(BoundaryError::TooFewNodes { .. } | BoundaryError::LoopTooShort { .. })
);

#[test]
fn every_bad_file_has_a_test() {
    // Each of the 20 is refused by a test above.
    assert_eq!(common::cases("bad").len(), 20);
}

/// The command line refuses each bad file with exit code 2, one line on
/// stderr, and no output file.
#[test]
fn cli_refuses_bad_files() {
    let exe = env!("CARGO_BIN_EXE_quadex");
    let dir = tempfile::tempdir().unwrap();
    for case in common::cases("bad")
        .iter()
        .chain(std::iter::once(&common::bench().join("bad/empty.poly")))
    {
        let out = dir.path().join("out.msh");
        let o = std::process::Command::new(exe)
            .arg("mesh")
            .arg(case)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{}: {err}", case.display());
        assert_eq!(
            err.trim_end().lines().count(),
            1,
            "{}: {err}",
            case.display()
        );
        assert!(
            err.contains(case.file_name().unwrap().to_str().unwrap()),
            "{err}"
        );
        assert!(!out.exists());
    }
}

/// Options and outputs the command line refuses before any work: exit 2,
/// one line naming what is wrong, no output file.
#[test]
fn cli_refuses_bad_options_and_outputs() {
    let exe = env!("CARGO_BIN_EXE_quadex");
    let dir = tempfile::tempdir().unwrap();
    let input = common::bench().join("boundaries/square.poly");
    let out = dir.path().join("out.msh");
    let input_s = input.to_str().unwrap();
    let out_s = out.to_str().unwrap();
    let not_a_folder = format!("{input_s}/x.msh");
    let csv_s = dir.path().join("samples.csv").display().to_string();
    let vtk = dir.path().join("mesh.vtk");
    std::fs::write(&vtk, "# vtk DataFile Version 2.0\n").unwrap();
    let vtk_s = vtk.display().to_string();
    let msh_s = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/reference/lshape.msh").to_string();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["mesh", input_s, "-o", out_s, "--report", out_s],
            "would be the same file",
        ),
        (
            vec!["mesh", input_s, "-o", &not_a_folder],
            "is not a folder",
        ),
        (
            vec!["mesh", input_s, "-o", out_s, "--model", "no-such-model"],
            "not one of the names default, rules, thesis, ann",
        ),
        (
            vec!["mesh", input_s, "-o", out_s, "--remesh-below", "1.5"],
            "from 0 (no remeshing) to 1",
        ),
        (vec!["compare", input_s, "-o", out_s], "name the file .svg"),
        (
            vec!["samples", &msh_s, "-o", out_s],
            "name the file .csv or .json",
        ),
        (
            vec!["mesh", input_s, "-o", out_s, "--points", "5"],
            "the model takes 7 input points, not the 5 of --points",
        ),
        (
            vec!["mesh", input_s, "-o", out_s, "--layers", "0"],
            "invalid value '0' for '--layers",
        ),
        (vec!["mesh", input_s], "--output"),
        (vec!["quality", &vtk_s], "is written, not read"),
        (vec!["factors", &vtk_s], "is written, not read"),
        (
            vec!["samples", &msh_s, "--turn", "235,35", "-o", &csv_s],
            "0 <= LO < HI <= 360",
        ),
    ];
    for (args, says) in cases {
        let o = std::process::Command::new(exe)
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(!out.exists(), "{args:?}");
    }
    // A folder that exists but cannot be written is found before meshing
    // (no file can be made in /proc, whoever runs the test).
    #[cfg(target_os = "linux")]
    {
        let o = std::process::Command::new(exe)
            .args(["mesh", input_s, "-o", "/proc/quadex-out.msh"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("cannot be written"), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    }
}

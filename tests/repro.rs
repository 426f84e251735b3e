//! The reproducers of issue 18 about reading, validating and writing
//! files (`tests/repro/`, named as filed). Bad input is refused by the
//! command line with exit code 2 and one line on stderr that names the file
//! and the problem: no panic, no abort, no output file. Valid input is
//! accepted by validation (meshing it is the engine's business).

mod common;

use quadex::geom::Point;
use quadex::io::{self, msh, MeshFormat};
use quadex::QuadMesh;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn repro(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/repro")
        .join(name)
}

struct Run {
    code: Option<i32>,
    stdout: Vec<u8>,
    stderr: String,
    seconds: f64,
}

fn quadex<S: AsRef<OsStr>>(args: &[S]) -> Run {
    let t = Instant::now();
    let o = Command::new(env!("CARGO_BIN_EXE_quadex"))
        .args(args)
        .output()
        .unwrap();
    Run {
        code: o.status.code(),
        stdout: o.stdout,
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
        seconds: t.elapsed().as_secs_f64(),
    }
}

/// `quadex mesh INPUT -o OUT`.
fn mesh_to(input: &Path, out: &Path) -> Run {
    quadex(&[
        "mesh".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
    ])
}

/// `quadex mesh INPUT -o OUT --report REPORT`.
fn mesh_reporting(input: &Path, out: &Path, report: &Path) -> Run {
    quadex(&[
        "mesh".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        out.as_os_str(),
        "--report".as_ref(),
        report.as_os_str(),
    ])
}

/// Exit code 2 and one line naming `file` and containing `expect`, with no
/// control character from the file.
fn assert_refused(r: &Run, file: &str, expect: &str) {
    assert_eq!(r.code, Some(2), "{file}: {}", r.stderr);
    let line = r.stderr.strip_suffix('\n').unwrap_or(&r.stderr);
    assert!(!line.is_empty() && !line.contains('\n'), "{:?}", r.stderr);
    assert!(!line.chars().any(char::is_control), "{line:?}");
    assert!(line.contains(file), "{line}");
    assert!(line.contains(expect), "expected {expect:?} in {line}");
    assert!(!line.contains("panicked"), "{line}");
}

fn mesh_refused(file: &str, expect: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.msh");
    let r = mesh_to(&repro(file), &out);
    assert_refused(&r, file, expect);
    assert!(!out.exists());
}

fn accepted(file: &str) -> quadex::Boundary {
    io::read_boundary(&repro(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

#[test]
fn r01_poly_counts_larger_than_the_file_are_refused() {
    mesh_refused(
        "R01a_poly_nodecount_huge.poly",
        "line 1: 99999999999 nodes announced",
    );
    mesh_refused(
        "R01b_poly_nodecount_u64max.poly",
        "line 1: 18446744073709551615 nodes announced",
    );
    mesh_refused(
        "R01c_poly_segcount_u64max.poly",
        "line 6: 18446744073709551615 segments announced",
    );
    mesh_refused(
        "R01d_poly_segcount_2pow32.poly",
        "line 6: 4294967296 segments announced",
    );
}

#[test]
fn r02_msh_node_block_counts_larger_than_the_file_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for file in [
        "R02a_msh41_nodeblock_u64max.msh",
        "R02b_msh41_nodeblock_huge.msh",
    ] {
        let r = quadex(&["quality".as_ref(), repro(file).as_os_str()]);
        assert_refused(&r, file, "line 6:");
        let out = dir.path().join("s.csv");
        let r = quadex(&[
            "samples".as_ref(),
            repro(file).as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        assert_refused(&r, file, "nodes announced");
        assert!(!out.exists());
    }
}

#[test]
fn r03_a_sample_short_of_right_points_is_refused() {
    let file = "R03_trainingset_short_right.json";
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.json");
    let expect = "sample 1: 1 right leading points, where 7 input points need 3";
    let r = quadex(&[
        "fit".as_ref(),
        repro(file).as_os_str(),
        "-o".as_ref(),
        model.as_os_str(),
    ]);
    assert_refused(&r, file, expect);
    assert!(!model.exists());
    let r = quadex(&[
        "factors".as_ref(),
        repro(file).as_os_str(),
        "--points".as_ref(),
        "7".as_ref(),
    ]);
    assert_refused(&r, file, expect);
    // The editor and the library read training sets the same way.
    assert!(quadex::samples::TrainingSet::read(&repro(file)).is_err());
}

/// A unit square scaled by `s`, as one quad.
fn square(s: f64) -> QuadMesh {
    let p = |x: f64, y: f64| Point::new(x * s, y * s);
    QuadMesh::from_quads(
        vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)],
        vec![[0, 1, 2, 3]],
    )
    .unwrap()
}

/// meshio's reading of `path`: the points as Python writes them (repr
/// round-trips), or its error.
fn meshio_points(path: &Path, format: &str) -> Result<Vec<f64>, String> {
    let script = format!(
        "import meshio, sys\nm = meshio.read(sys.argv[1], file_format={format})\nprint(' '.join(repr(float(v)) for v in m.points[:, :2].ravel()))"
    );
    let o = Command::new("python3")
        .arg("-c")
        .arg(script)
        .arg(path)
        .output()
        .map_err(|e| e.to_string())?;
    if !o.status.success() {
        return Err(String::from_utf8_lossy(&o.stderr).into_owned());
    }
    Ok(String::from_utf8_lossy(&o.stdout)
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect())
}

/// The squares of `r10_*` at each extreme scale.
const R10_SCALES: [f64; 4] = [1e120, 1e-120, 1.2345678901234567e300, 3e-300];

#[test]
fn r10_extreme_coordinates_are_written_so_that_readers_read_them_exactly() {
    for s in R10_SCALES {
        let m = square(s);
        let want: Vec<f64> = m.nodes.iter().flat_map(|p| [p.x, p.y]).collect();
        for fmt in MeshFormat::ALL {
            let text = fmt.render(&m);
            // Deterministic, and no number longer than a float needs.
            assert_eq!(text, fmt.render(&m));
            assert!(
                text.split(|c: char| c.is_whitespace() || c == ',')
                    .all(|w| w.len() < 40),
                "{fmt:?} at {s}"
            );
            // quadex reads meshes within ±1e150 (beyond, areas overflow).
            if matches!(fmt, MeshFormat::Msh41 | MeshFormat::Msh22) && (s == 1e120 || s == 1e-120) {
                let back = msh::read_msh(&text).unwrap();
                let got: Vec<f64> = back.nodes.iter().flat_map(|p| [p.x, p.y]).collect();
                assert_eq!(got, want, "{fmt:?} at {s}");
            }
        }
    }
}

/// meshio, the reader of most Python FE codes, reads every format's
/// extreme coordinates back exactly. It needs python3 with meshio, so
/// `cargo test` leaves it out and `.ci/run` runs it (`-- --ignored`).
#[test]
#[ignore = "needs python3 with meshio; .ci/run runs it"]
fn r10_meshio_reads_extreme_coordinates_exactly() {
    let dir = tempfile::tempdir().unwrap();
    for s in R10_SCALES {
        let m = square(s);
        let want: Vec<f64> = m.nodes.iter().flat_map(|p| [p.x, p.y]).collect();
        for fmt in MeshFormat::ALL {
            let path = dir.path().join(format!("m.{}", fmt.extension()));
            io::write_mesh(&m, &path).unwrap();
            let format = match fmt {
                MeshFormat::Svg => continue,
                MeshFormat::Msh22 => "'gmsh'",
                _ => "None",
            };
            let got = meshio_points(&path, format)
                .unwrap_or_else(|e| panic!("meshio cannot read {fmt:?} at {s}: {e}"));
            assert_eq!(got, want, "meshio, {fmt:?} at {s}");
        }
    }
    // The reproducer itself: the 1e120 square meshed and read by meshio.
    let out = dir.path().join("r10.msh");
    let r = mesh_to(&repro("R10_square_4nodes_1e120.poly"), &out);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let got = meshio_points(&out, "None").unwrap();
    assert!(got.iter().all(|v| *v == 0.0 || *v == 1e120), "{got:?}");
}

#[test]
fn r11_a_thin_rectangle_is_valid() {
    let a = accepted("R11a_rect_1000x1_4nodes.poly");
    let b = accepted("R11b_rect_1000x1_4nodes.json");
    assert_eq!(a.node_count(), 4);
    assert_eq!(a.points, b.points);
    assert!((a.area() - 1000.0).abs() < 1e-9);
}

#[test]
fn r11c_r12c_shapes_far_from_the_origin_are_valid() {
    let c = accepted("R11c_annulus_0.004wide_at_offset1e8.poly");
    assert_eq!(c.loops.len(), 2);
    let s = accepted("R12c_unit_square_4nodes_at_1e8_refused.poly");
    assert_eq!(s.node_count(), 4);
}

#[test]
fn r13_r14_invalid_meshes_are_refused_by_quality_and_samples() {
    let dir = tempfile::tempdir().unwrap();
    for (file, expect) in [
        (
            "R13_msh_nonconvex_quad.msh",
            "quad 1 is not strictly convex (corner at node 3)",
        ),
        ("R14_msh_overlapping_quads.msh", "the quads overlap"),
    ] {
        let r = quadex(&["quality".as_ref(), repro(file).as_os_str()]);
        assert_refused(&r, file, expect);
        let out = dir.path().join("s.csv");
        let r = quadex(&[
            "samples".as_ref(),
            repro(file).as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ]);
        assert_refused(&r, file, expect);
        assert!(!out.exists());
    }
}

fn fit<S: AsRef<OsStr>>(set: &str, out: &Path, extra: &[S]) -> Run {
    let mut args: Vec<std::ffi::OsString> = vec![
        "fit".into(),
        repro(set).into_os_string(),
        "-o".into(),
        out.as_os_str().to_owned(),
    ];
    args.extend(extra.iter().map(|a| a.as_ref().to_owned()));
    quadex(&args)
}

#[test]
fn r16_fit_refuses_absurd_values_and_writes_only_loadable_models() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.json");
    let r = fit("R16_trainingset_1e300.csv", &model, &["--folds", "2"]);
    assert_refused(
        &r,
        "R16_trainingset_1e300.csv",
        "line 2: yl2 = 1e300 is out of range",
    );
    assert!(!model.exists());
    // One type only: the type's DC is defined, the file loads back.
    let set = "R16b_trainingset_only_type0_30rows.csv";
    for form in [
        &["--form", "quadratic"][..],
        &["--form", "thesis"][..],
        &[][..],
    ] {
        let report = dir.path().join("r.json");
        let mut args = form.to_vec();
        args.extend(["--report", report.to_str().unwrap()]);
        let r = fit(set, &model, &args);
        assert_eq!(r.code, Some(0), "{form:?}: {}", r.stderr);
        let text = std::fs::read_to_string(&model).unwrap();
        assert!(!text.contains("null"), "{form:?}");
        let m = quadex::model::load(model.to_str().unwrap())
            .unwrap_or_else(|e| panic!("{form:?}: {e}"));
        assert_eq!(m.leading_points(), Some(3));
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        assert!(report["type"]["holdout"]["dc"].is_number());
    }
}

#[test]
fn folds_are_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.json");
    let set = "R16b_trainingset_only_type0_30rows.csv";
    for (folds, expect) in [
        ("100000", "100000 folds for 30 samples"),
        ("31", "31 folds for 30 samples"),
        ("1", "--folds 1"),
    ] {
        let r = fit(set, &model, &["--folds", folds, "--form", "quadratic"]);
        assert_refused(&r, set, expect);
        assert!(r.seconds < 5.0);
        assert!(!model.exists());
    }
    for folds in ["0", "2", "30"] {
        let r = fit(set, &model, &["--folds", folds, "--form", "quadratic"]);
        assert_eq!(r.code, Some(0), "--folds {folds}: {}", r.stderr);
        quadex::model::load(model.to_str().unwrap()).unwrap();
    }
}

#[test]
fn r17a_an_odd_sunburst_is_refused_before_the_costly_checks() {
    let file = "R17a_sunburst_4001nodes_odd_validator_5GB.poly";
    let t = Instant::now();
    mesh_refused(file, "4001 nodes, an odd number");
    assert!(t.elapsed().as_secs_f64() < 5.0);
}

/// A sunburst of 20,000 nodes (R17b): 10,000 spikes from radius 0.05 to
/// 1, every segment long, written and read as a `.poly` file.
#[test]
fn r17b_a_large_valid_sunburst_validates_in_under_a_second() {
    let n = 10_000;
    let text = sunburst_poly(n);
    let t = Instant::now();
    let b = io::poly::parse_poly(&text).unwrap();
    let seconds = t.elapsed().as_secs_f64();
    assert_eq!(b.node_count(), 2 * n);
    assert!(seconds < 1.0, "{seconds} s");
}

/// R17b meshed: its 10,000 needles (0.002° at their tips, a thousand times
/// longer than wide) are each closed by the kite they force, and the disk
/// inside is meshed from their ends' spacing, coarsening inwards; all by
/// extraction, no fill.
#[test]
fn r17b_the_large_sunburst_is_meshed_by_extraction() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("R17b.poly");
    std::fs::write(&input, sunburst_poly(10_000)).unwrap();
    let out = dir.path().join("x.msh");
    let report = dir.path().join("x.json");
    let r = mesh_reporting(&input, &out, &report);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let kinds = &report["steps"]["by_kind"];
    assert!(kinds.get("Fill").is_none(), "{kinds}");
    assert!(kinds["Element"].as_u64().unwrap() >= 10_000, "{kinds}");
    let m = io::read_mesh(&out).unwrap();
    assert_eq!(m.n_boundary(), 20_000);
    // One kite per needle and a disk coarsened inwards: far fewer quads
    // than the 20,000-node ring would give at its own spacing throughout.
    assert!(
        (30_000..200_000).contains(&m.quads.len()),
        "{} quads",
        m.quads.len()
    );
}

/// A sunburst of `n` needles from radius 0.05 to 1 (`2n` nodes; the
/// construction of R17), as `.poly` text with numbers in shortest
/// round-trip notation.
fn sunburst_poly(n: usize) -> String {
    let mut text = format!("{} 2 0 0\n", 2 * n);
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let b = a + std::f64::consts::PI / n as f64;
        text.push_str(&format!("{} {} {}\n", 2 * k + 1, a.cos(), a.sin()));
        text.push_str(&format!(
            "{} {} {}\n",
            2 * k + 2,
            0.05 * b.cos(),
            0.05 * b.sin()
        ));
    }
    text.push_str(&format!("{} 0\n", 2 * n));
    for k in 0..2 * n {
        text.push_str(&format!("{} {} {}\n", k + 1, k + 1, (k + 1) % (2 * n) + 1));
    }
    text.push_str("0\n");
    text
}

/// The thin annulus of R09 (R09_make.py): outer circle of radius 1 and a
/// hole of radius 1 − h, 60,000 nodes each, h = 2π/60,000, as `.poly` text.
fn r09_thin_annulus() -> String {
    let n = 60_000;
    let tau = std::f64::consts::TAU;
    let h = tau / n as f64;
    let at = |r: f64, k: usize| {
        let a = tau * k as f64 / n as f64;
        (r * a.cos(), r * a.sin())
    };
    let points = (0..n)
        .map(|k| at(1.0, k))
        .chain((0..n).rev().map(|k| at(1.0 - h, k)));
    let mut text = format!("{} 2 0 0\n", 2 * n);
    for (k, (x, y)) in points.enumerate() {
        text.push_str(&format!("{} {x} {y}\n", k + 1));
    }
    text.push_str(&format!("{} 0\n", 2 * n));
    for k in 0..n {
        text.push_str(&format!("{} {} {}\n", k + 1, k + 1, (k + 1) % n + 1));
    }
    for k in 0..n {
        let (a, b) = (n + k + 1, n + (k + 1) % n + 1);
        text.push_str(&format!("{a} {a} {b}\n"));
    }
    text.push_str("0\n");
    text
}

/// R09: the mesh of a thin annulus of 120,000 nodes was refused by the
/// final check, whose area sums' rounding exceeded its relative tolerance.
#[test]
fn r09_a_thin_annulus_of_120k_nodes_is_meshed() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("R09.poly");
    std::fs::write(&input, r09_thin_annulus()).unwrap();
    let out = dir.path().join("x.msh");
    let r = mesh_to(&input, &out);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    // Read back, the mesh passes the file checks too.
    let m = io::read_mesh(&out).unwrap();
    assert_eq!(m.n_boundary(), 120_000);
    assert!(m.quads.len() >= 60_000, "{} quads", m.quads.len());
}

#[test]
fn r18_control_bytes_are_escaped() {
    let file = "R18_control_char_echo.poly";
    mesh_refused(
        file,
        "line 8: `0.8\\u{1c}40169943749474` is not a valid y coordinate",
    );
}

#[test]
fn r21_a_node_on_a_segment_up_to_rounding_is_refused() {
    mesh_refused(
        "R21_node_on_segment_within_rounding_exit1.poly",
        "loop 0: node 32 touches the segment from node 12 to node 13 of loop 0",
    );
}

#[test]
fn r22_coordinates_that_overflow_are_refused_as_such() {
    mesh_refused(
        "R22_square_1e308_misleading_message.poly",
        "node 2 has a coordinate of magnitude 1e308: coordinates must lie within ±1e150",
    );
}

#[test]
fn r23_byte_order_marks_and_any_line_ends_are_read() {
    let file = "R23_utf8_bom_refused.poly";
    let b = accepted(file);
    let text = std::fs::read_to_string(repro(file)).unwrap();
    let plain = text.trim_start_matches('\u{feff}');
    assert_ne!(plain.len(), text.len(), "the file has a byte-order mark");
    assert_eq!(io::poly::parse_poly(plain).unwrap(), b);
    assert_eq!(
        io::poly::parse_poly(&text.replace('\n', "\r\n")).unwrap(),
        b
    );
    assert_eq!(io::poly::parse_poly(&text.replace('\n', "\r")).unwrap(), b);
}

#[test]
fn outputs_in_missing_folders_leave_nothing_and_say_so_once() {
    let dir = tempfile::tempdir().unwrap();
    let square = common::bench().join("boundaries/square.poly");
    let out = dir.path().join("x.msh");
    let r = mesh_reporting(&square, &out, &dir.path().join("missing/r.json"));
    assert_ne!(r.code, Some(0));
    assert_eq!(r.stderr.lines().count(), 1, "{}", r.stderr);
    assert!(r.stderr.contains("missing"), "{}", r.stderr);
    assert!(!out.exists());
    let r = mesh_to(&square, &dir.path().join("missing/x.msh"));
    assert_ne!(r.code, Some(0));
    assert_eq!(r.stderr.lines().count(), 1, "{}", r.stderr);
    // A target that is a folder is refused before any work, once.
    let folder = dir.path().join("folder.msh");
    std::fs::create_dir(&folder).unwrap();
    let report = dir.path().join("r.json");
    let r = mesh_reporting(&square, &folder, &report);
    assert_eq!(r.code, Some(2));
    assert_eq!(r.stderr.lines().count(), 1, "{}", r.stderr);
    assert!(r.stderr.contains("it is a folder"), "{}", r.stderr);
    assert!(!report.exists());
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(left.len(), 1, "{left:?}");
}

/// R20b: a square with a hole 7e-4 from two of its sides. A chord split
/// in a sliver of microscopic elements gave its chord tens of thousands of
/// nodes, and remeshing ran for minutes; it meshes now (poorly: the gap
/// forces quads of aspect 40 or more).
#[test]
fn r20b_a_near_touching_hole_meshes() {
    meshed("R20b_near_touch_layers_all_timeout.poly");
}

/// R19 through the command line: the 13 × 4 grid of a 50 × 1 plate.
#[test]
fn r19_a_plate_meshes_as_its_grid() {
    assert_eq!(
        meshed("R19_rect_50x1_13x4_segments_quality.poly")
            .quads
            .len(),
        52
    );
}

/// A reader that closes the pipe before `quality` writes (as `| head`
/// does) ends the command quietly, not in a panic.
#[test]
fn output_into_a_closed_pipe_ends_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("square.msh");
    io::write_mesh(&square(1.0), &mesh).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_quadex"))
        .args(["quality".as_ref(), mesh.as_os_str()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(o.status.code(), Some(0), "{stderr}");
}

/// Meshes a reproducer through the command line; the mesh read back.
fn meshed(file: &str) -> QuadMesh {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.msh");
    let r = mesh_to(&repro(file), &out);
    assert_eq!(r.code, Some(0), "{file}: {}", r.stderr);
    let m = io::read_mesh(&out).unwrap();
    m.check_finished().unwrap();
    m
}

/// R06a: 201 segments below, 3 above, on a 1 × 0.1 strip. Extraction
/// tangles; the run rewinds to the first rows and fills from there.
#[test]
fn r06a_a_201_against_3_node_strip_meshes() {
    assert!(
        meshed("R06a_rect_1x0.1_bottom201_top3_side1.poly")
            .quads
            .len()
            > 300
    );
}

/// R06b: a fill that succeeds from a tangled front is not taken when an
/// earlier one gives a better worst quad (scaled Jacobian 0.000 against
/// 0.013 from the start; 0.009 after finishing before bridges, 0.0015
/// with them: five bridges change the front the fill starts from; 6e-5
/// since settling a small loop keeps its quads over 0.1, which changes
/// the closures before the fill). The 24-node plate with five holes is
/// meshed mostly by the fill either way; the test holds its worst quad
/// over 1e-5.
#[test]
fn r06b_rewinding_keeps_the_better_fill() {
    let m = meshed("R06b_many_holes_reduced.poly");
    let worst = m.worst_scaled_jacobian();
    assert!(worst > 1e-5, "{worst}");
}

/// `quadex quality MESH --boundary B` says on stderr that the mesh meshes
/// that boundary (stdout stays the figures' JSON), and refuses a mesh of
/// another boundary.
#[test]
fn quality_against_a_boundary_says_it_matches_or_why_not() {
    let dir = tempfile::tempdir().unwrap();
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples");
    let (square, lshape) = (examples.join("square.poly"), examples.join("lshape.poly"));
    let mesh = dir.path().join("square.msh");
    assert_eq!(mesh_to(&square, &mesh).code, Some(0));
    let quality_against = |boundary: &Path| {
        quadex(&[
            "quality".as_ref(),
            mesh.as_os_str(),
            "--boundary".as_ref(),
            boundary.as_os_str(),
        ])
    };
    let o = quality_against(&square);
    assert_eq!(o.code, Some(0), "{}", o.stderr);
    assert!(
        o.stderr.contains("boundary nodes and the same area"),
        "{}",
        o.stderr
    );
    let figures: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(figures["quads"].as_u64().unwrap() > 0);
    let r = quality_against(&lshape);
    assert_eq!(r.code, Some(2), "{}", r.stderr);
    assert!(
        r.stderr.contains("boundary nodes") || r.stderr.contains("area"),
        "{}",
        r.stderr
    );
}

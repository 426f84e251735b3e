//! Drawings as CAD programs write them (DXF, made here with the `dxf`
//! crate): a rounded plate from an LWPOLYLINE with bulges, a bolt hole from
//! a CIRCLE and a slot from LINEs and ARCs, each on its own layer, meshed
//! by `quadex mesh PART.dxf --size H`. The nodes lie on the curves, the
//! layers are physical curves, the edges follow H and every quad is valid.

use dxf::entities::{Arc, Circle, Entity, EntityType, Line, LwPolyline};
use dxf::Drawing;
use dxf::LwPolylineVertex;
use quadex::cad::{read_dxf, Curve};
use std::path::Path;

fn on_layer(specific: EntityType, layer: &str) -> Entity {
    let mut e = Entity::new(specific);
    e.common.layer = layer.into();
    e
}

/// A 100 × 60 plate with corners rounded to radius 10 (LWPOLYLINE with
/// bulges), a bolt hole of radius 8 at (25, 30) (CIRCLE) and a slot from
/// (55, 25) to (80, 25), 10 wide, with round ends (LINEs and ARCs).
fn part(path: &Path) {
    let mut d = Drawing::new();
    // LWPOLYLINE exists from R14 on; the crate writes R12 by default.
    d.header.version = dxf::enums::AcadVersion::R2013;
    let r = 10.0;
    let b = (std::f64::consts::PI / 8.0).tan(); // a quarter circle
    let v = |x: f64, y: f64, bulge: f64| LwPolylineVertex {
        x,
        y,
        bulge,
        ..Default::default()
    };
    let mut pl = LwPolyline {
        vertices: vec![
            v(r, 0.0, 0.0),
            v(100.0 - r, 0.0, b),
            v(100.0, r, 0.0),
            v(100.0, 60.0 - r, b),
            v(100.0 - r, 60.0, 0.0),
            v(r, 60.0, b),
            v(0.0, 60.0 - r, 0.0),
            v(0.0, r, b),
        ],
        ..Default::default()
    };
    pl.set_is_closed(true);
    d.add_entity(on_layer(EntityType::LwPolyline(pl), "plate"));
    let c = Circle {
        center: dxf::Point::new(25.0, 30.0, 0.0),
        radius: 8.0,
        ..Default::default()
    };
    d.add_entity(on_layer(EntityType::Circle(c), "bolt"));
    let line = |x1: f64, y1: f64, x2: f64, y2: f64| Line {
        p1: dxf::Point::new(x1, y1, 0.0),
        p2: dxf::Point::new(x2, y2, 0.0),
        ..Default::default()
    };
    d.add_entity(on_layer(
        EntityType::Line(line(55.0, 20.0, 80.0, 20.0)),
        "slot",
    ));
    d.add_entity(on_layer(
        EntityType::Line(line(80.0, 30.0, 55.0, 30.0)),
        "slot",
    ));
    let arc = |cx: f64, start: f64, end: f64| Arc {
        center: dxf::Point::new(cx, 25.0, 0.0),
        radius: 5.0,
        start_angle: start,
        end_angle: end,
        ..Default::default()
    };
    d.add_entity(on_layer(EntityType::Arc(arc(80.0, 270.0, 90.0)), "slot"));
    d.add_entity(on_layer(EntityType::Arc(arc(55.0, 90.0, 270.0)), "slot"));
    d.save_file(path).unwrap();
}

fn mesh(input: &Path, out: &Path, size: f64) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
        .args([
            "mesh".as_ref(),
            input.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ])
        .args(["--size", &size.to_string()])
        .output()
        .unwrap()
}

#[test]
fn a_drawing_meshes_on_its_curves_at_the_size_asked() {
    let dir = tempfile::tempdir().unwrap();
    let dxf = dir.path().join("part.dxf");
    part(&dxf);
    let geometry = read_dxf(&dxf).unwrap();
    assert_eq!(geometry.layers(), ["bolt", "plate", "slot"]);
    let arcs = geometry
        .curves
        .iter()
        .filter(|c| matches!(c.curve, Curve::Arc { .. }))
        .count();
    assert_eq!(arcs, 4 + 1 + 2);
    for h in [4.0, 2.0] {
        let out = dir.path().join(format!("part_{h}.msh"));
        let o = mesh(&dxf, &out, h);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        // quadex's reader checks the mesh: convex quads, one cover.
        let m = quadex::io::read_mesh(&out).unwrap();
        let text = std::fs::read_to_string(&out).unwrap();
        for layer in ["\"bolt\"", "\"plate\"", "\"slot\""] {
            assert!(text.contains(layer), "{layer}");
        }
        // Every boundary node lies on a curve, to 1e-9 of the part's size.
        let size = 100.0;
        for &v in m.loops.iter().flatten() {
            let p = m.nodes[v as usize];
            let d = geometry
                .curves
                .iter()
                .map(|c| c.curve.distance(p))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 1e-9 * size, "node at {p:?} is {d:e} off the curves");
        }
        // The median edge length follows H.
        let mut lengths: Vec<f64> = m
            .quads
            .iter()
            .flat_map(|q| (0..4).map(move |i| (q[i], q[(i + 1) % 4])))
            .filter(|(a, b)| a < b)
            .map(|(a, b)| (m.nodes[a as usize] - m.nodes[b as usize]).length())
            .collect();
        lengths.sort_by(f64::total_cmp);
        let median = lengths[lengths.len() / 2];
        assert!(
            (0.6 * h..=1.4 * h).contains(&median),
            "median edge {median} at H {h}"
        );
        // The holes are holes: the quads cover the plate less the bolt
        // hole and the slot.
        let area: f64 = m
            .quads
            .iter()
            .map(|q| quadex::geom::polygon_area(m.corners(q)))
            .sum();
        let exact = 100.0 * 60.0
            - (4.0 - std::f64::consts::PI) * 100.0
            - std::f64::consts::PI * 64.0
            - (25.0 * 10.0 + std::f64::consts::PI * 25.0);
        assert!(
            (area - exact).abs() < 0.02 * exact,
            "{area} against {exact}"
        );
    }
}

#[test]
fn an_open_outline_is_refused_with_the_gap() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = Drawing::new();
    let line = |x1: f64, y1: f64, x2: f64, y2: f64| {
        EntityType::Line(Line {
            p1: dxf::Point::new(x1, y1, 0.0),
            p2: dxf::Point::new(x2, y2, 0.0),
            ..Default::default()
        })
    };
    d.add_entity(on_layer(line(0.0, 0.0, 10.0, 0.0), "a"));
    d.add_entity(on_layer(line(10.0, 0.0, 10.0, 10.0), "a"));
    d.add_entity(on_layer(line(10.0, 10.0, 0.0, 10.0), "a"));
    d.add_entity(on_layer(line(0.0, 10.0, 0.0, 0.5), "a"));
    let path = dir.path().join("open.dxf");
    d.save_file(&path).unwrap();
    let out = dir.path().join("open.msh");
    let o = mesh(&path, &out, 1.0);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("the outline is open") && (err.contains("(0, 0.5)") || err.contains("(0, 0)")),
        "{err}"
    );
    assert!(!out.exists());
}

/// Seeded drawings no case was tuned on: a rounded rectangle with random
/// corner radii and sides, cut in two half the time by an interface
/// (straight, or a cubic B-spline), a random number of holes away from it
/// (circles or tilted ellipses, a third of the time with a finer layer
/// size) and a random target size, meshed with the interior at the size
/// field as the command line meshes. Every one meshes all-quad,
/// conforming, with no odd region.
#[test]
fn seeded_drawings_mesh_with_every_region_even() {
    use quadex::cad::{Geometry, LayerCurve};
    use std::f64::consts::FRAC_PI_2 as Q;
    let p = quadex::geom::Point::new;
    let mut r = quadex::rng::SplitMix64::new(0xcad0_5eed);
    let (mut two, mut fixes, mut quads) = (0, 0, 0);
    for k in 0..100 {
        let (w, hgt) = (r.uni(20.0, 80.0), r.uni(20.0, 80.0));
        let rad = r.uni(1.0, 0.2 * w.min(hgt));
        let split = r.chance(0.5);
        let mut g = Geometry::default();
        let mut add = |curve: Curve, layer: &str| {
            g.curves.push(LayerCurve {
                curve,
                layer: layer.into(),
            })
        };
        let arc = |cx: f64, cy: f64, start: f64| Curve::Arc {
            centre: p(cx, cy),
            radius: rad,
            start,
            sweep: Q,
        };
        let corners = [
            arc(w - rad, rad, -Q),
            arc(w - rad, hgt - rad, 0.0),
            arc(rad, hgt - rad, Q),
            arc(rad, rad, 2.0 * Q),
        ];
        for (i, c) in corners.iter().enumerate() {
            add(c.clone(), "outline");
            let (a, b) = (c.at(1.0), corners[(i + 1) % 4].at(0.0));
            // The bottom (i = 3) and top (i = 1) sides meet the interface
            // at x = w / 2.
            if split && (i == 1 || i == 3) {
                let m = p(w / 2.0, a.y);
                add(Curve::Line { a, b: m }, "outline");
                add(Curve::Line { a: m, b }, "outline");
            } else {
                add(Curve::Line { a, b }, "outline");
            }
        }
        if split {
            two += 1;
            // A straight interface, or a cubic B-spline wavering across
            // the middle.
            let (a, b) = (p(w / 2.0, 0.0), p(w / 2.0, hgt));
            if r.chance(0.5) {
                add(Curve::Line { a, b }, "interface");
            } else {
                let s = r.uni(-0.08, 0.08) * w;
                let nurbs = quadex::cad::Nurbs::new(
                    3,
                    vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
                    vec![
                        a,
                        p(w / 2.0 + s, hgt / 3.0),
                        p(w / 2.0 - s, 2.0 * hgt / 3.0),
                        b,
                    ],
                    Vec::new(),
                )
                .unwrap();
                add(Curve::Spline(std::sync::Arc::new(nurbs)), "interface");
            }
        }
        let holes = r.int(0, 3);
        for j in 0..holes {
            // Hole centres in the quarters, clear of the interface: circles
            // or tilted ellipses.
            let cx = w * [0.25, 0.75, 0.25][j];
            let cy = hgt * [0.5, 0.5, 0.25][j];
            let hr = r.uni(0.03, 0.1) * w.min(hgt);
            let hole = if r.chance(0.5) {
                Curve::Arc {
                    centre: p(cx, cy),
                    radius: hr,
                    start: 0.0,
                    sweep: 4.0 * Q,
                }
            } else {
                let (tilt, ratio) = (r.uni(0.0, 4.0 * Q), r.uni(0.4, 1.0));
                let major = p(tilt.cos(), tilt.sin()) * hr;
                Curve::Ellipse {
                    centre: p(cx, cy),
                    major,
                    minor: p(-major.y, major.x) * ratio,
                    start: 0.0,
                    sweep: 4.0 * Q,
                }
            };
            add(hole, "holes");
        }
        let h = r.uni(0.03, 0.12) * w.min(hgt);
        // A finer size on the holes a third of the time.
        let mut spec = quadex::cad::SizeSpec::uniform(h);
        if holes > 0 && r.chance(0.33) {
            spec.layers.insert("holes".into(), h * r.uni(0.2, 0.6));
        }
        let d = g
            .discretise_with(&spec)
            .unwrap_or_else(|e| panic!("drawing {k}: {e}"));
        fixes += d.parity_fixes.len();
        let faces = d
            .graph
            .faces()
            .unwrap_or_else(|e| panic!("drawing {k}: {e}"));
        assert_eq!(faces.len(), 1 + usize::from(split), "drawing {k}");
        let mut params = quadex::Params::DEFAULT;
        params.extract.size_target = Some(d.size_target());
        let m = quadex::regions::mesh_regions(&d.graph, model(), &params, |_| {})
            .unwrap_or_else(|e| panic!("drawing {k}: {e}"));
        m.check_conforming().unwrap();
        assert!(m.quality().sj_min > 0.0, "drawing {k}");
        quads += m.mesh.quads.len();
    }
    println!("100 seeded drawings ({two} of two regions): {quads} quads, {fixes} curves refined for parity");
}

/// Second order on a drawing's annulus: every boundary midside node lies
/// on its circle, every 9-node quad has a positive Jacobian at its Gauss
/// points, and the files carry 9-node quads and 3-node lines.
#[test]
fn nine_node_quads_put_their_boundary_midsides_on_the_arcs() {
    let path =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/cad/annulus.dxf");
    let geometry = read_dxf(&path).unwrap();
    let d = geometry.discretise(0.2).unwrap();
    let model = std::sync::Arc::new(quadex::model::default_model().unwrap());
    let m =
        quadex::regions::mesh_regions(&d.graph, model, &quadex::Params::DEFAULT, |_| {}).unwrap();
    let nodes = &m.mesh.nodes;
    let o2 = quadex::order2::Order2::elevate(&m.mesh, &|a, b| {
        d.midside(nodes[a as usize], nodes[b as usize])
    });
    assert_eq!(o2.straightened, 0);
    for l in &m.mesh.loops {
        for k in 0..l.len() {
            let mid = o2.mid(l[k], l[(k + 1) % l.len()]).unwrap();
            let r = o2.nodes[mid as usize].length();
            assert!(
                (r - 1.0).abs() < 1e-12 || (r - 2.0).abs() < 1e-12,
                "midside at r = {r}"
            );
        }
    }
    for q in &o2.quads {
        let p = q.map(|v| o2.nodes[v as usize]);
        assert!(quadex::order2::jacobians(&p).iter().all(|&j| j > 0.0));
    }
    let labelled = m.labelled_with(Some(&o2));
    let msh = quadex::io::MeshFormat::Msh41.render_labelled(&labelled);
    assert!(
        msh.contains(&format!("2 1 10 {}", m.mesh.quads.len())),
        "quad9 block"
    );
    assert!(msh.contains("\"inner\"") && msh.contains("\"outer\""));
    let vtk = quadex::io::MeshFormat::Vtk.render_labelled(&labelled);
    assert!(vtk.contains("\n28\n") && vtk.contains("\n21\n"));
    let inp = quadex::io::MeshFormat::Abaqus.render_labelled(&labelled);
    assert!(inp.contains("TYPE=CPS8"));
    // The .inp lists the nodes its CPS8 elements use, every one of them:
    // all but the quads' centres.
    let section = |name: &str| -> Vec<&str> {
        inp.split(name)
            .nth(1)
            .unwrap()
            .lines()
            .skip(1)
            .take_while(|l| !l.starts_with('*'))
            .collect()
    };
    let listed = section("*NODE");
    assert_eq!(listed.len(), o2.nodes.len() - m.mesh.quads.len());
    let mut used: Vec<usize> = section("TYPE=CPS8")
        .iter()
        .flat_map(|l| l.split(", ").skip(1).map(|w| w.parse::<usize>().unwrap()))
        .collect();
    used.sort_unstable();
    used.dedup();
    assert_eq!(used, (1..=listed.len()).collect::<Vec<_>>());
}

fn data(name: &str) -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(name)
}

fn model() -> std::sync::Arc<dyn quadex::model::Model> {
    std::sync::Arc::new(quadex::model::default_model().unwrap())
}

/// Meshes a discretised drawing as the command line does: the interior
/// follows the drawing's size target.
fn mesh_drawing(d: &quadex::cad::Discretised) -> quadex::regions::RegionMesh {
    let mut params = quadex::Params::DEFAULT;
    params.extract.size_target = Some(d.size_target());
    quadex::regions::mesh_regions(&d.graph, model(), &params, |_| {}).unwrap()
}

/// The edges of a mesh, each once, as node pairs.
fn edges(m: &quadex::mesh::QuadMesh) -> Vec<(u32, u32)> {
    let mut e: Vec<(u32, u32)> = m
        .quads
        .iter()
        .flat_map(|q| (0..4).map(move |i| (q[i].min(q[(i + 1) % 4]), q[i].max(q[(i + 1) % 4]))))
        .collect();
    e.sort_unstable();
    e.dedup();
    e
}

/// tests/data/cad/curves.dxf (written by `examples/cad_parts.rs`): a
/// plate with a cubic B-spline edge, a tilted ELLIPSE hole, a closed
/// rational SPLINE that is a circle of radius 7 and a slot with
/// half-ELLIPSE ends. Every boundary node and every boundary midside node
/// lies on its true curve, checked against each curve's own equation
/// (not the reader's evaluation), and every quad is valid.
#[test]
fn splines_and_ellipses_mesh_on_their_true_curves() {
    let geometry = read_dxf(&data("tests/data/cad/curves.dxf")).unwrap();
    let kinds = |f: fn(&Curve) -> bool| geometry.curves.iter().filter(|c| f(&c.curve)).count();
    assert_eq!(kinds(|c| matches!(c, Curve::Spline(_))), 2);
    assert_eq!(kinds(|c| matches!(c, Curve::Ellipse { .. })), 3);
    let p = quadex::geom::Point::new;
    // The tilted ellipse, from the file's numbers: centre, major axis.
    let (centre, major) = geometry
        .curves
        .iter()
        .find_map(|c| match c.curve {
            Curve::Ellipse {
                centre,
                major,
                sweep,
                ..
            } if sweep > 6.0 => Some((centre, major)),
            _ => None,
        })
        .unwrap();
    let (a, u) = (major.length(), major.normalize());
    let on_ellipse = |q: quadex::geom::Point| {
        let d = q - centre;
        let (x, y) = (d.dot(u) / a, d.perp_dot(u) / (0.5 * a));
        ((x * x + y * y).sqrt() - 1.0).abs() * 0.5 * a
    };
    let on_circle = |q: quadex::geom::Point| ((q - p(50.0, 20.0)).length() - 7.0).abs();
    let on_slot_end = |q: quadex::geom::Point| {
        let cx = if q.x > 80.0 { 88.0 } else { 72.0 };
        let (x, y) = ((q.x - cx) / 3.0, (q.y - 20.0) / 4.0);
        ((x * x + y * y).sqrt() - 1.0).abs() * 3.0
    };
    let wave = geometry
        .curves
        .iter()
        .find(|c| c.layer == "wave")
        .unwrap()
        .curve
        .clone();
    // The distance to the curve a boundary point should lie on.
    let off = |q: quadex::geom::Point| -> f64 {
        let straight = [
            (q.x.abs(), q.y >= 0.0 && q.y <= 40.0),
            (q.y.abs(), true),
            ((q.x - 100.0).abs(), q.y <= 40.0),
            ((q.y - 16.0).abs(), q.x >= 72.0 && q.x <= 88.0),
            ((q.y - 24.0).abs(), q.x >= 72.0 && q.x <= 88.0),
        ];
        let mut d = straight
            .iter()
            .filter(|s| s.1)
            .map(|s| s.0)
            .fold(f64::INFINITY, f64::min);
        d = d.min(on_ellipse(q)).min(on_circle(q)).min(wave.distance(q));
        if (q.x - 80.0).abs() > 8.0 - 1e-9 && (q.y - 20.0).abs() <= 4.0 + 1e-9 {
            d = d.min(on_slot_end(q));
        }
        d
    };
    let size = 100.0;
    for h in [4.0, 2.0] {
        let d = geometry.discretise(h).unwrap();
        let m = mesh_drawing(&d);
        m.check_conforming().unwrap();
        assert!(m.quality().sj_min > 0.0, "H {h}");
        let nodes = &m.mesh.nodes;
        for &v in m.mesh.loops.iter().flatten() {
            let e = off(nodes[v as usize]);
            assert!(
                e <= 1e-9 * size,
                "node {:?} is {e:e} off its curve",
                nodes[v as usize]
            );
        }
        let o2 = quadex::order2::Order2::elevate(&m.mesh, &|a, b| {
            d.midside(nodes[a as usize], nodes[b as usize])
        });
        for l in &m.mesh.loops {
            for k in 0..l.len() {
                let mid = o2.mid(l[k], l[(k + 1) % l.len()]).unwrap();
                let q = o2.nodes[mid as usize];
                // A straightened quad's midside is on the chord: none here.
                assert!(off(q) <= 1e-9 * size, "midside {q:?} is {:e} off", off(q));
            }
        }
        assert_eq!(o2.straightened, 0);
        for q in &o2.quads {
            let pts = q.map(|v| o2.nodes[v as usize]);
            assert!(quadex::order2::jacobians(&pts).iter().all(|&j| j > 0.0));
        }
        // The spacing along the wave follows H (it turns gently).
        let on_wave = m.groups.iter().find(|g| g.name == "wave").unwrap();
        let mut lens: Vec<f64> = on_wave
            .edges
            .iter()
            .map(|e| (nodes[e[0] as usize] - nodes[e[1] as usize]).length())
            .collect();
        lens.sort_by(f64::total_cmp);
        let median = lens[lens.len() / 2];
        assert!(
            (0.8 * h..=1.2 * h).contains(&median),
            "wave spacing {median} at H {h}"
        );
    }
}

/// A curve's chord error stays bounded: the sagitta of every boundary
/// segment on the drawing's ellipses is within 1.5 times that of a 15°
/// arc of the local radius of curvature (ρ·(1 − cos 7.5°), 0.86 % of ρ),
/// also on the tilted ellipse's sharp ends (ρ = b²/a = 2.5) where H = 8
/// alone would cut across them.
#[test]
fn curved_edges_keep_a_bounded_chord_error() {
    let geometry = read_dxf(&data("tests/data/cad/curves.dxf")).unwrap();
    let d = geometry.discretise(8.0).unwrap();
    let g = &d.graph;
    let (mut checked, mut worst) = (0, 0.0f64);
    for (s, seg) in g.segments.iter().enumerate() {
        let c = &geometry.curves[d.curve_of[s]].curve;
        if let Curve::Ellipse {
            centre,
            major,
            minor,
            ..
        } = c
        {
            let (a, b) = (g.points[seg.a], g.points[seg.b]);
            let mid = d.midside(a, b).unwrap();
            let sagitta = quadex::geom::point_segment_distance(mid, a, b);
            // The radius of curvature at the midside's parameter θ.
            let (ra, rb) = (major.length(), minor.length());
            let q = mid - *centre;
            let (cos, sin) = (q.dot(*major) / (ra * ra), q.dot(*minor) / (rb * rb));
            let rho = (ra * ra * sin * sin + rb * rb * cos * cos).powf(1.5) / (ra * rb);
            let bound = rho * (1.0 - (quadex::cad::MAX_ARC_ANGLE / 2.0).cos());
            worst = worst.max(sagitta / bound);
            checked += 1;
        }
    }
    assert!(checked > 30, "{checked} ellipse segments");
    assert!(worst <= 1.5, "a sagitta {worst} times that of a 15° arc");
}

/// A fit-point-only SPLINE has no control points to evaluate: it is
/// refused with its layer, never approximated silently.
#[test]
fn a_spline_of_fit_points_only_is_refused_with_its_layer() {
    let mut d = Drawing::new();
    d.header.version = dxf::enums::AcadVersion::R2013;
    let mut s = dxf::entities::Spline {
        degree_of_curve: 3,
        ..Default::default()
    };
    for (x, y) in [(0.0, 0.0), (1.0, 1.0), (2.0, 0.0), (0.0, 0.0)] {
        s.fit_points.push(dxf::Point::new(x, y, 0.0));
    }
    d.add_entity(on_layer(EntityType::Spline(s), "fitted"));
    let err = quadex::cad::geometry_of(&d).unwrap_err().to_string();
    assert!(
        err.contains("fit points only") && err.contains("\"fitted\""),
        "{err}"
    );
}

/// Where a short curve meets long ones, the spacing grades along the long
/// ones instead of jumping: a step 1 high in the top of a 100 × 99 box
/// meshed at H = 10. Consecutive boundary segments differ by at most the
/// gradation's ratio (and a rounding's worth), where cutting each curve on
/// its own gave 1 beside 10.
#[test]
fn spacing_grades_along_curves_from_a_short_neighbour() {
    use quadex::cad::{Geometry, LayerCurve};
    let p = quadex::geom::Point::new;
    let corners = [
        p(0.0, 0.0),
        p(100.0, 0.0),
        p(100.0, 100.0),
        p(50.0, 100.0),
        p(50.0, 99.0),
        p(0.0, 99.0),
    ];
    let g = Geometry {
        curves: (0..6)
            .map(|i| LayerCurve {
                curve: Curve::Line {
                    a: corners[i],
                    b: corners[(i + 1) % 6],
                },
                layer: "outline".into(),
            })
            .collect(),
    };
    let d = g.discretise(10.0).unwrap();
    let face = &d.graph.faces().unwrap()[0].boundary;
    let l = &face.loops[0];
    let n = l.len();
    let len = |k: usize| face.points[l[k % n]].distance(face.points[l[(k + 1) % n]]);
    let (mut worst, mut shortest, mut longest) = (1.0f64, f64::INFINITY, 0.0f64);
    for k in 0..n {
        let (a, b) = (len(k), len(k + 1));
        worst = worst.max(a.max(b) / a.min(b));
        shortest = shortest.min(a);
        longest = longest.max(a);
    }
    assert!((shortest - 1.0).abs() < 1e-9, "the step is one segment");
    assert!(
        longest > 8.0,
        "far from the step the spacing is H: {longest}"
    );
    assert!(worst < 1.6, "neighbouring segments differ by {worst}");
}

/// A square `side` long from the origin on layer `outline` with a round
/// hole of radius `r` at `centre` on layer `hole`.
fn square_with_hole(side: f64, centre: quadex::geom::Point, r: f64) -> quadex::cad::Geometry {
    use quadex::cad::{Geometry, LayerCurve};
    let p = quadex::geom::Point::new;
    let corners = [p(0.0, 0.0), p(side, 0.0), p(side, side), p(0.0, side)];
    let mut curves: Vec<LayerCurve> = (0..4)
        .map(|i| LayerCurve {
            curve: Curve::Line {
                a: corners[i],
                b: corners[(i + 1) % 4],
            },
            layer: "outline".into(),
        })
        .collect();
    curves.push(LayerCurve {
        curve: Curve::Arc {
            centre,
            radius: r,
            start: 0.0,
            sweep: 2.0 * std::f64::consts::PI,
        },
        layer: "hole".into(),
    });
    Geometry { curves }
}

/// The interior follows the size field, not only the boundary's spacing:
/// a 100 × 100 plate at H = 10 with a hole of radius 4 whose layer asks
/// for 0.8. The field is h(x) = min(10, 0.8 + 0.3·dist(x, hole)); the
/// interior edges' lengths over the field at their midpoints stay near 1.
/// The boundary's spacing interpolated alone (no size target) leaves the
/// plate far finer than asked.
#[test]
fn the_interior_follows_the_size_field() {
    use quadex::cad::SizeSpec;
    let p = quadex::geom::Point::new;
    let (centre, r) = (p(30.0, 40.0), 4.0);
    let g = square_with_hole(100.0, centre, r);
    let mut spec = SizeSpec::uniform(10.0);
    spec.layers.insert("hole".into(), 0.8);
    let d = g.discretise_with(&spec).unwrap();
    let field = |x: quadex::geom::Point| (0.8 + 0.3 * ((x - centre).length() - r)).min(10.0);
    let ratios = |m: &quadex::regions::RegionMesh| {
        let mut v: Vec<f64> = edges(&m.mesh)
            .into_iter()
            .map(|(a, b)| {
                let (pa, pb) = (m.mesh.nodes[a as usize], m.mesh.nodes[b as usize]);
                (pa - pb).length() / field(0.5 * (pa + pb))
            })
            .collect();
        v.sort_by(f64::total_cmp);
        let within = v.iter().filter(|&&x| (0.6..=1.5).contains(&x)).count();
        (
            v[v.len() / 2],
            within as f64 / v.len() as f64,
            m.mesh.quads.len(),
        )
    };
    let with = mesh_drawing(&d);
    with.check_conforming().unwrap();
    let without =
        quadex::regions::mesh_regions(&d.graph, model(), &quadex::Params::DEFAULT, |_| {}).unwrap();
    let (median, share, quads) = ratios(&with);
    let (median0, share0, quads0) = ratios(&without);
    println!(
        "edge / field: with the target median {median:.2}, {:.0}% in [0.6, 1.5], {quads} quads; boundary spacing alone median {median0:.2}, {:.0}%, {quads0} quads",
        100.0 * share,
        100.0 * share0
    );
    assert!(
        (0.75..=1.3).contains(&median),
        "median edge / field {median}"
    );
    assert!(
        share >= 0.75,
        "{share} of the edges within [0.6, 1.5] of the field"
    );
    assert!(median0 < median && share0 < share);
}

/// A hole on a layer sized six times coarser than the target is met by
/// sizes falling from its spacing to the target at the gradation, not by
/// rows of the target's height along segments six times longer (which
/// knotted into quads of scaled Jacobian 0 beside the bracket's bolt at
/// `--size 0.15`): the mesh needs no region fill, its quads stay fair, and
/// the edges beside the hole are about as long as its segments.
#[test]
fn a_layer_sized_coarser_than_the_target_grades_down_to_it() {
    use quadex::cad::SizeSpec;
    use quadex::extract::StepKind;
    let (centre, r) = (quadex::geom::Point::new(12.0, 12.0), 5.0);
    let g = square_with_hole(24.0, centre, r);
    let mut spec = SizeSpec::uniform(0.25);
    spec.layers.insert("hole".into(), 1.5);
    let d = g.discretise_with(&spec).unwrap();
    let m = mesh_drawing(&d);
    m.check_conforming().unwrap();
    let fills: usize = m.faces.iter().map(|f| f.steps.count(StepKind::Fill)).sum();
    let q = m.quality();
    // The edges with both ends within one hole segment of the hole.
    let mut near: Vec<f64> = edges(&m.mesh)
        .into_iter()
        .filter_map(|(a, b)| {
            let (pa, pb) = (m.mesh.nodes[a as usize], m.mesh.nodes[b as usize]);
            let off = |x: quadex::geom::Point| (x - centre).length() - r;
            (off(pa) < 1.5 && off(pb) < 1.5).then(|| (pa - pb).length())
        })
        .collect();
    near.sort_by(f64::total_cmp);
    let median = near[near.len() / 2];
    println!(
        "{} quads, fills {fills}, sj min {:.3}, taper {:.2}, aspect {:.2}, median edge beside the hole {median:.3}",
        q.quads, q.sj_min, q.taper_max, q.aspect_max
    );
    assert_eq!(fills, 0);
    assert!(q.sj_min >= 0.3, "sj min {}", q.sj_min);
    assert!(q.taper_max <= 10.0 && q.aspect_max <= 10.0, "{q:?}");
    assert!(
        median >= 0.6,
        "median edge beside the hole {median}, the target 0.25"
    );
}

/// The JSON geometry form (examples/bracket.json: lines, an arc by
/// centre and angles, one through three points, a spline, a circle and an
/// ellipse, a layer size and a point size) meshes through the command
/// line with its layers as physical curves and its nodes on the curves;
/// the layer size sets the hole's spacing.
#[test]
fn a_json_geometry_meshes_with_its_layers_and_local_sizes() {
    let path = data("examples/bracket.json");
    let doc = quadex::cad::read_geometry_json(&path).unwrap();
    assert_eq!(doc.size, Some(4.0));
    assert_eq!(doc.layers.get("bolt"), Some(&1.0));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bracket.msh");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
        .args([
            "mesh".as_ref(),
            path.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m = quadex::io::read_mesh(&out).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    for layer in ["base", "round", "top", "support", "bolt", "slot"] {
        assert!(text.contains(&format!("\"{layer}\"")), "{layer}");
    }
    for &v in m.loops.iter().flatten() {
        let q = m.nodes[v as usize];
        let d = doc
            .geometry
            .curves
            .iter()
            .map(|c| c.curve.distance(q))
            .fold(f64::INFINITY, f64::min);
        assert!(d <= 1e-9 * 100.0, "node {q:?} is {d:e} off the curves");
    }
    // The bolt hole (radius 8) at its layer's size 1: about 2π·8 / 1
    // segments, where H = 4 alone gives 24 (15° a segment).
    let hole = m
        .loops
        .iter()
        .find(|l| {
            l.iter().all(|&v| {
                ((m.nodes[v as usize] - quadex::geom::Point::new(80.0, 20.0)).length() - 8.0).abs()
                    < 1e-9
            })
        })
        .unwrap();
    assert!(
        (48..=53).contains(&hole.len()),
        "{} nodes on the bolt hole",
        hole.len()
    );
    // Errors name the curve.
    let bad = r#"{"curves": [{"line": [[0,0],[1,0]], "circle": {"centre": [0,0], "radius": 1}}]}"#;
    let e = quadex::cad::parse_geometry_json(bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("curve 1") && e.contains("exactly one"), "{e}");
    let flat = r#"{"curves": [{"arc": {"through": [[0,0],[1,1],[2,2]]}}]}"#;
    let e = quadex::cad::parse_geometry_json(flat)
        .unwrap_err()
        .to_string();
    assert!(e.contains("on one line"), "{e}");
}

/// `--order 2 --serendipity` writes 8-node quads: Gmsh type 16 in .msh
/// 4.1 and 2.2, VTK type 23 in .vtk and .vtu, with no centre nodes.
#[test]
fn serendipity_quads_are_written_without_their_centres() {
    let path = data("tests/data/cad/annulus.dxf");
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
            .args([
                "mesh".as_ref(),
                path.as_os_str(),
                "-o".as_ref(),
                out.as_os_str(),
            ])
            .args(["--size", "0.4", "--order", "2"])
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read_to_string(out).unwrap()
    };
    let nine = run("a9.msh", &[]);
    let eight = run("a8.msh", &["--serendipity"]);
    let count = |t: &str| -> usize {
        let n = t.split("$Nodes\n").nth(1).unwrap().lines().next().unwrap();
        n.split(' ').nth(1).unwrap().parse().unwrap()
    };
    let quads: usize = nine
        .lines()
        .find(|l| l.starts_with("2 1 10 "))
        .unwrap()
        .split(' ')
        .nth(3)
        .unwrap()
        .parse()
        .unwrap();
    assert!(eight.contains(&format!("2 1 16 {quads}")));
    assert_eq!(count(&nine), count(&eight) + quads);
    let msh22 = run("a8.msh22", &["--serendipity"]);
    assert!(msh22.lines().any(|l| l.split(' ').nth(1) == Some("16")));
    // Read back (and judged by `quadex quality`) by their corners: the
    // first-order mesh.
    let a4 = dir.path().join("a4.msh");
    let o = mesh(&path, &a4, 0.4);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let first = quadex::io::read_mesh(&a4).unwrap();
    for name in ["a9.msh", "a8.msh", "a8.msh22"] {
        let m = quadex::io::read_mesh(&dir.path().join(name)).unwrap();
        assert_eq!(m.quads.len(), quads, "{name}");
        assert_eq!(m.nodes, first.nodes, "{name}");
        assert_eq!(m.quads, first.quads, "{name}");
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
            .arg("quality")
            .arg(dir.path().join(name))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    for ext in ["vtk", "vtu"] {
        let t = run(&format!("a8.{ext}"), &["--serendipity"]);
        assert!(t.contains("\n23\n") && !t.contains("\n28\n"), ".{ext}");
    }
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
        .args(["mesh".as_ref(), path.as_os_str(), "-o".as_ref()])
        .arg(dir.path().join("x.msh"))
        .args(["--size", "0.4", "--serendipity"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--order 2"));
}

/// Local sizes from the command line: `--size-on bolt=1` cuts the bolt
/// hole (radius 8) at 1 where H = 4 cut it at 15° a segment (24), and the
/// spacing grows away from it; `--size-at 10,0,0.5` refines the boundary near its
/// point; a layer the drawing lacks, or a bad gradation, is refused.
#[test]
fn local_sizes_from_the_command_line() {
    let path = data("tests/data/cad/part.dxf");
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
            .args([
                "mesh".as_ref(),
                path.as_os_str(),
                "-o".as_ref(),
                out.as_os_str(),
            ])
            .args(["--size", "4"])
            .args(extra)
            .output()
            .unwrap();
        (o, out)
    };
    let bolt_nodes = |m: &quadex::mesh::QuadMesh| {
        let c = quadex::geom::Point::new(25.0, 30.0);
        m.loops
            .iter()
            .find(|l| {
                l.iter()
                    .all(|&v| ((m.nodes[v as usize] - c).length() - 8.0).abs() < 1e-9)
            })
            .map(Vec::len)
            .unwrap()
    };
    let (o, plain) = run("plain.msh", &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let plain = quadex::io::read_mesh(&plain).unwrap();
    let (o, fine) = run(
        "fine.msh",
        &["--size-on", "bolt=1", "--size-at", "10,0,0.5"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let fine = quadex::io::read_mesh(&fine).unwrap();
    assert_eq!(bolt_nodes(&plain), 24);
    assert!(
        (49..=52).contains(&bolt_nodes(&fine)),
        "{}",
        bolt_nodes(&fine)
    );
    // Near (0, 0) the boundary spacing is about the point's size.
    let near_corner = |m: &quadex::mesh::QuadMesh| {
        let l = &m.loops[0];
        (0..l.len())
            .map(|k| {
                (
                    m.nodes[l[k] as usize],
                    m.nodes[l[(k + 1) % l.len()] as usize],
                )
            })
            .filter(|(a, _)| a.length() < 12.0)
            .map(|(a, b)| (a - b).length())
            .fold(f64::INFINITY, f64::min)
    };
    assert!(near_corner(&fine) < 1.0 && near_corner(&plain) > 2.0);
    assert!(fine.quads.len() > plain.quads.len());
    for (extra, says) in [
        (
            &["--size-on", "nothere=1"][..],
            "no curve is on layer \"nothere\"",
        ),
        (&["--gradation", "0"][..], "gradation"),
        (&["--size-at", "1,2"][..], "X,Y,H"),
    ] {
        let (o, out) = run("bad.msh", extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(says), "{err}");
        assert!(!out.exists());
    }
}

/// A size far too fine for the drawing is refused before the curves are
/// cut, with the node count it would give, or before meshing, with the
/// quads it would ask for inside; and a negative size or
/// gradation is refused by the drawing's own check, not read as an option.
#[test]
fn a_size_far_too_fine_or_negative_is_refused_at_once() {
    let part = data("tests/data/cad/part.dxf");
    // Its bolt's layer is sized 1: the other curves still count at 1e-4.
    let bracket = data("examples/bracket.json");
    let dir = tempfile::tempdir().unwrap();
    for (path, args, says) in [
        (&part, &["--size", "1e-5"][..], "take a larger size"),
        (
            &bracket,
            &["--size", "1e-4"][..],
            "boundary nodes, more than",
        ),
        // 40,000 boundary nodes, but 37 million quads inside.
        (
            &bracket,
            &["--size", "0.01"][..],
            "quads inside the drawing",
        ),
        (
            &part,
            &["--size", "-1"][..],
            "a size must be a positive number, not -1",
        ),
        (
            &part,
            &["--size", "4", "--gradation", "-0.5"][..],
            "the gradation must be a positive number, not -0.5",
        ),
    ] {
        let out = dir.path().join("bad.msh");
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
            .arg("mesh")
            .arg(path)
            .arg("-o")
            .arg(&out)
            .args(args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!out.exists());
    }
}

/// A boundary file without markers keeps its loops' groups at second
/// order (`outer`, `hole_1`: the names of its first-order file), as
/// 3-node lines on every loop edge.
#[test]
fn second_order_keeps_the_loops_groups_of_a_boundary_file() {
    let path = data("assets/examples/plate_hole.poly");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p2.msh");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
        .arg("mesh")
        .arg(&path)
        .arg("-o")
        .arg(&out)
        .args(["--order", "2"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("1 1 \"outer\"") && text.contains("1 2 \"hole_1\""));
    let b = quadex::io::read_boundary(&path).unwrap();
    let lines: usize = text
        .lines()
        .filter(|l| l.starts_with("1 ") && l.split(' ').nth(2) == Some("8"))
        .map(|l| l.split(' ').nth(3).unwrap().parse::<usize>().unwrap())
        .sum();
    assert_eq!(lines, b.node_count());
}

/// An `.svg` draws corners only: `--order 2` with one is refused, with
/// the formats that hold 9-node quads named. A point size at a negative
/// coordinate is read as the option's value, not as another option.
#[test]
fn an_svg_at_second_order_is_refused_and_a_negative_point_is_read() {
    let part = data("tests/data/cad/part.dxf");
    let dir = tempfile::tempdir().unwrap();
    let mesh = |out: &std::path::Path, args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
            .arg("mesh")
            .arg(&part)
            .arg("-o")
            .arg(out)
            .args(["--size", "4"])
            .args(args)
            .output()
            .unwrap()
    };
    let svg = dir.path().join("p2.svg");
    let o = mesh(&svg, &["--order", "2"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--order 2 needs .msh"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!svg.exists());
    let msh = dir.path().join("neg.msh");
    let o = mesh(&msh, &["--size-at", "-1000,0,0.5"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(msh.exists());
}

/// A point size too far from the drawing to lower the size anywhere in it
/// (its size grown at the gradation over the distance is over the target)
/// leaves the mesh as it is, byte for byte.
#[test]
fn a_point_size_far_from_the_drawing_changes_nothing() {
    let part = data("tests/data/cad/part.dxf");
    let dir = tempfile::tempdir().unwrap();
    let mesh = |name: &str, args: &[&str]| {
        let out = dir.path().join(name);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_quadex"))
            .arg("mesh")
            .arg(&part)
            .arg("-o")
            .arg(&out)
            .args(["--size", "2"])
            .args(args)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read(out).unwrap()
    };
    let plain = mesh("plain.msh", &[]);
    for at in ["1000000,1000000,0.5", "1000,1000,1"] {
        assert!(mesh("far.msh", &["--size-at", at]) == plain, "{at}");
    }
    // A point inside does change it.
    assert!(mesh("near.msh", &["--size-at", "10,0,0.5"]) != plain);
}

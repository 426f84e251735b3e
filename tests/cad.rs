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
/// corner radii and sides, cut in two by a straight interface half the
/// time, a random number of round holes away from it and a random target
/// size. Every one meshes all-quad, conforming, with no odd region.
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
            add(
                Curve::Line {
                    a: p(w / 2.0, 0.0),
                    b: p(w / 2.0, hgt),
                },
                "interface",
            );
        }
        let holes = r.int(0, 3);
        for j in 0..holes {
            // Hole centres in the quarters, clear of the interface.
            let cx = w * [0.25, 0.75, 0.25][j];
            let cy = hgt * [0.5, 0.5, 0.25][j];
            let hr = r.uni(0.03, 0.1) * w.min(hgt);
            add(
                Curve::Arc {
                    centre: p(cx, cy),
                    radius: hr,
                    start: 0.0,
                    sweep: 4.0 * Q,
                },
                "holes",
            );
        }
        let h = r.uni(0.03, 0.12) * w.min(hgt);
        let d = g
            .discretise(h)
            .unwrap_or_else(|e| panic!("drawing {k}: {e}"));
        fixes += d.parity_fixes.len();
        let faces = d
            .graph
            .faces()
            .unwrap_or_else(|e| panic!("drawing {k}: {e}"));
        assert_eq!(faces.len(), 1 + usize::from(split), "drawing {k}");
        let model = std::sync::Arc::new(quadex::model::default_model().unwrap());
        let m = quadex::regions::mesh_regions(&d.graph, model, &quadex::Params::DEFAULT, |_| {})
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
}

//! Writes the drawings the tests and the Gmsh comparison mesh
//! (`tests/data/cad/part.dxf`, `tests/data/cad/curves.dxf`) with the `dxf`
//! crate, as a CAD program would save them.
//!
//! `part.dxf`: a 100 × 60 plate with corners rounded to radius 10 (an
//! LWPOLYLINE with bulges, layer `plate`), a bolt hole of radius 8 at
//! (25, 30) (a CIRCLE, layer `bolt`) and a slot from (55, 25) to (80, 25),
//! 10 wide, with round ends (LINEs and ARCs, layer `slot`).
//!
//! `curves.dxf`:
//! - a 100 × 40 plate whose top edge is a cubic B-spline (layer `wave`),
//!   the other sides LINEs (layer `outline`);
//! - a hole bounded by a full ELLIPSE, its major axis tilted (layer
//!   `ellipse`);
//! - a hole bounded by a closed rational quadratic SPLINE that is an exact
//!   circle of radius 7 (layer `nurbs`);
//! - a slot of two half-ELLIPSEs (one with its normal along -z, as
//!   mirrored drawings have) and two LINEs (layer `slot`).
//!
//! `cargo run --release --example cad_parts -- DIR` writes both into DIR.

use dxf::entities::{Arc, Circle, Ellipse, Entity, EntityType, Line, LwPolyline, Spline};
use dxf::{Drawing, LwPolylineVertex, Point, Vector};
use std::f64::consts::{FRAC_1_SQRT_2, PI};

fn on_layer(specific: EntityType, layer: &str) -> Entity {
    let mut e = Entity::new(specific);
    e.common.layer = layer.into();
    e
}

fn line(a: (f64, f64), b: (f64, f64)) -> EntityType {
    EntityType::Line(Line {
        p1: Point::new(a.0, a.1, 0.0),
        p2: Point::new(b.0, b.1, 0.0),
        ..Default::default()
    })
}

/// The rounded plate with a bolt hole and a slot.
fn part() -> Drawing {
    let mut d = Drawing::new();
    // LWPOLYLINE exists from R14 on; the crate writes R12 by default.
    d.header.version = dxf::enums::AcadVersion::R2013;
    let r = 10.0;
    let b = (PI / 8.0).tan(); // a quarter circle
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
        center: Point::new(25.0, 30.0, 0.0),
        radius: 8.0,
        ..Default::default()
    };
    d.add_entity(on_layer(EntityType::Circle(c), "bolt"));
    d.add_entity(on_layer(line((55.0, 20.0), (80.0, 20.0)), "slot"));
    d.add_entity(on_layer(line((80.0, 30.0), (55.0, 30.0)), "slot"));
    let arc = |cx: f64, start: f64, end: f64| Arc {
        center: Point::new(cx, 25.0, 0.0),
        radius: 5.0,
        start_angle: start,
        end_angle: end,
        ..Default::default()
    };
    d.add_entity(on_layer(EntityType::Arc(arc(80.0, 270.0, 90.0)), "slot"));
    d.add_entity(on_layer(EntityType::Arc(arc(55.0, 90.0, 270.0)), "slot"));
    d
}

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "tests/data/cad".into());
    let path = std::path::Path::new(&dir).join("part.dxf");
    part().save_file(&path).expect("write the drawing");
    println!("wrote {}", path.display());
    // (Each run writes the same entities; only the header's dates of
    // creation and update change.)
    let mut d = Drawing::new();
    d.header.version = dxf::enums::AcadVersion::R2013;
    // The plate: three LINEs and a cubic spline from (100, 40) to (0, 40).
    for (a, b) in [
        ((0.0, 40.0), (0.0, 0.0)),
        ((0.0, 0.0), (100.0, 0.0)),
        ((100.0, 0.0), (100.0, 40.0)),
    ] {
        d.add_entity(on_layer(line(a, b), "outline"));
    }
    let mut wave = Spline {
        degree_of_curve: 3,
        knot_values: vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.7, 1.0, 1.0, 1.0, 1.0],
        ..Default::default()
    };
    for (x, y) in [
        (100.0, 40.0),
        (80.0, 58.0),
        (60.0, 30.0),
        (40.0, 55.0),
        (20.0, 32.0),
        (0.0, 40.0),
    ] {
        wave.control_points.push(Point::new(x, y, 0.0));
    }
    wave.set_is_planar(true);
    d.add_entity(on_layer(EntityType::Spline(wave), "wave"));
    // A tilted elliptical hole: semi-axes 10 and 5.
    let tilt: f64 = 0.4;
    d.add_entity(on_layer(
        EntityType::Ellipse(Ellipse {
            center: Point::new(22.0, 20.0, 0.0),
            major_axis: Vector::new(10.0 * tilt.cos(), 10.0 * tilt.sin(), 0.0),
            minor_axis_ratio: 0.5,
            start_parameter: 0.0,
            end_parameter: 2.0 * PI,
            ..Default::default()
        }),
        "ellipse",
    ));
    // A circular hole as a closed rational quadratic NURBS: nine control
    // points on the square around it, the corners weighted 1/√2.
    let (cx, cy, r) = (50.0, 20.0, 7.0);
    let mut circle = Spline {
        degree_of_curve: 2,
        knot_values: vec![
            0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
        ],
        ..Default::default()
    };
    let square = [
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
        (-1.0, 1.0),
        (-1.0, 0.0),
        (-1.0, -1.0),
        (0.0, -1.0),
        (1.0, -1.0),
        (1.0, 0.0),
    ];
    for (k, (x, y)) in square.iter().enumerate() {
        circle
            .control_points
            .push(Point::new(cx + r * x, cy + r * y, 0.0));
        circle
            .weight_values
            .push(if k % 2 == 1 { FRAC_1_SQRT_2 } else { 1.0 });
    }
    circle.set_is_rational(true);
    circle.set_is_closed(true);
    circle.set_is_planar(true);
    d.add_entity(on_layer(EntityType::Spline(circle), "nurbs"));
    // A slot from (72, 20) to (88, 20), 8 wide, with half-elliptical ends
    // (semi-axes 3 along the slot, 4 across).
    d.add_entity(on_layer(line((72.0, 16.0), (88.0, 16.0)), "slot"));
    d.add_entity(on_layer(line((88.0, 24.0), (72.0, 24.0)), "slot"));
    // The right end from the top, its normal along -z: the minor axis is
    // the major one turned clockwise, so it bulges to the right.
    d.add_entity(on_layer(
        EntityType::Ellipse(Ellipse {
            center: Point::new(88.0, 20.0, 0.0),
            major_axis: Vector::new(0.0, 4.0, 0.0),
            minor_axis_ratio: 0.75,
            start_parameter: 0.0,
            end_parameter: PI,
            normal: Vector::new(0.0, 0.0, -1.0),
        }),
        "slot",
    ));
    // The left end from the top, normal +z: it bulges to the left.
    d.add_entity(on_layer(
        EntityType::Ellipse(Ellipse {
            center: Point::new(72.0, 20.0, 0.0),
            major_axis: Vector::new(0.0, 4.0, 0.0),
            minor_axis_ratio: 0.75,
            start_parameter: 0.0,
            end_parameter: PI,
            ..Default::default()
        }),
        "slot",
    ));
    let path = std::path::Path::new(&dir).join("curves.dxf");
    d.save_file(&path).expect("write the drawing");
    println!("wrote {}", path.display());
}

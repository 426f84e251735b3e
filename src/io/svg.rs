//! SVG pictures of a mesh, each quad filled by its scaled Jacobian (red at
//! 0, yellow at 0.5, green at 1) and the boundary drawn on top.

use crate::mesh::QuadMesh;
use crate::quality::QuadQuality;
use std::fmt::Write as _;

/// Picture options.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgOptions {
    /// Width of the picture in pixels (height follows the aspect ratio).
    pub width: f64,
    /// Colour quads by quality (otherwise a flat fill).
    pub colour_by_quality: bool,
}

impl Default for SvgOptions {
    fn default() -> Self {
        SvgOptions {
            width: 800.0,
            colour_by_quality: true,
        }
    }
}

/// Red → yellow → green over `[0, 1]`.
pub fn quality_colour(v: f64) -> [u8; 3] {
    let t = v.clamp(0.0, 1.0);
    if t < 0.5 {
        [230, (60.0 + 380.0 * t) as u8, 60]
    } else {
        [
            (230.0 - 340.0 * (t - 0.5)) as u8,
            250 - (40.0 * (t - 0.5)) as u8,
            60,
        ]
    }
}

/// Renders the mesh as SVG.
pub fn write_svg(mesh: &QuadMesh, opt: &SvgOptions) -> String {
    let fill = |k: usize| {
        if opt.colour_by_quality {
            let q = &mesh.quads[k];
            quality_colour(QuadQuality::of(mesh.corners(q)).scaled_jacobian)
        } else {
            [0xcf, 0xe0, 0xf5]
        }
    };
    write_svg_with(mesh, opt.width, &fill, &[])
}

/// Eight colours apart, for regions.
pub const PALETTE: [[u8; 3]; 8] = [
    [0x9e, 0xc5, 0xe8],
    [0xf2, 0xb7, 0x7a],
    [0xa8, 0xd8, 0x9a],
    [0xe8, 0x9e, 0xb0],
    [0xc9, 0xb3, 0xe6],
    [0xf0, 0xe0, 0x8a],
    [0x8f, 0xd6, 0xcf],
    [0xd9, 0xc2, 0xa5],
];

/// Renders the mesh as SVG, quad `k` filled with `fill(k)`, and the
/// `lines` (node pairs: interfaces, groups) drawn over it as the boundary
/// is.
pub fn write_svg_with(
    mesh: &QuadMesh,
    width: f64,
    fill: &dyn Fn(usize) -> [u8; 3],
    lines: &[[u32; 2]],
) -> String {
    let mut lo = glam::DVec2::splat(f64::INFINITY);
    let mut hi = glam::DVec2::splat(f64::NEG_INFINITY);
    for p in &mesh.nodes {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let size = (hi - lo).max(glam::DVec2::splat(1e-300));
    let margin = 10.0;
    let s = (width - 2.0 * margin) / size.x.max(size.y);
    let height = size.y * s + 2.0 * margin;
    let width = size.x * s + 2.0 * margin;
    let tx = |p: glam::DVec2| ((p.x - lo.x) * s + margin, (hi.y - p.y) * s + margin);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.2} {height:.2}\">"
    );
    out.push_str("<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<g stroke=\"#222\" stroke-width=\"0.5\" stroke-linejoin=\"round\">\n");
    for (k, q) in mesh.quads.iter().enumerate() {
        let c = fill(k);
        let fill = format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]);
        out.push_str("<polygon points=\"");
        for (k, &v) in q.iter().enumerate() {
            let (x, y) = tx(mesh.nodes[v as usize]);
            let _ = write!(out, "{}{x:.2},{y:.2}", if k > 0 { " " } else { "" });
        }
        let _ = writeln!(out, "\" fill=\"{fill}\"/>");
    }
    out.push_str("</g>\n<g fill=\"none\" stroke=\"black\" stroke-width=\"1.5\">\n");
    for l in &mesh.loops {
        out.push_str("<polygon points=\"");
        for (k, &v) in l.iter().enumerate() {
            let (x, y) = tx(mesh.nodes[v as usize]);
            let _ = write!(out, "{}{x:.2},{y:.2}", if k > 0 { " " } else { "" });
        }
        out.push_str("\"/>\n");
    }
    for [a, b] in lines {
        let (x0, y0) = tx(mesh.nodes[*a as usize]);
        let (x1, y1) = tx(mesh.nodes[*b as usize]);
        let _ = writeln!(
            out,
            "<line x1=\"{x0:.2}\" y1=\"{y0:.2}\" x2=\"{x1:.2}\" y2=\"{y1:.2}\"/>"
        );
    }
    out.push_str("</g>\n</svg>\n");
    out
}

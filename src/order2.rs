//! Second-order elements: each quad of a finished mesh becomes a 9-node
//! quad (Gmsh's and VTK's order: corners, midsides 0–1, 1–2, 2–3, 3–0,
//! centre) for solvers that want quadratic elements, or an 8-node
//! serendipity quad (the same without the centre).
//!
//! A boundary edge's midside node lies on the true curve the edge cuts
//! (a caller's function gives it, [`crate::cad`] for drawings); every
//! other midside node is the edge's midpoint, so interior edges stay
//! straight after smoothing. The centre node is the transfinite blend of
//! the eight others (their bilinear centre when the edges are straight).
//! Each curved quad is checked: its Jacobian determinant must stay
//! positive, and no less than [`MIN_JACOBIAN_RATIO`] of its largest, at the
//! 3 × 3 Gauss points; where a midside node on the curve breaks that, the
//! quad's curved edges are straightened (their midside nodes moved to the
//! chord's midpoint, off the curve) and [`Order2::straightened`] counts it.

use crate::geom::Point;
use crate::mesh::QuadMesh;
use std::collections::BTreeMap;

/// The smallest ratio of a curved quad's Jacobian determinant to its
/// largest, over the Gauss points, kept without straightening.
pub const MIN_JACOBIAN_RATIO: f64 = 0.05;

/// The 9-node quads of a mesh: the mesh's nodes first (same ids), then a
/// node per edge, then a centre per quad.
#[derive(Clone, Debug, PartialEq)]
pub struct Order2 {
    pub nodes: Vec<Point>,
    pub quads: Vec<[u32; 9]>,
    /// The midside node of each edge, by its end nodes (smaller first).
    pub midside: BTreeMap<(u32, u32), u32>,
    /// Quads whose curved edges were straightened to keep the Jacobian
    /// positive.
    pub straightened: usize,
    /// Written as 8-node (serendipity) quads: the centre nodes, the last
    /// `quads.len()` nodes, left out ([`Order2::serendipity`]).
    pub serendipity: bool,
}

/// Quadratic Lagrange shape-function derivatives of the 9-node quad at
/// (ξ, η), in [`Order2`]'s node order.
fn shape_derivatives(xi: f64, eta: f64) -> [(f64, f64); 9] {
    // 1D quadratic functions at -1, 1, 0 and their derivatives.
    let l = |t: f64| [0.5 * t * (t - 1.0), 0.5 * t * (t + 1.0), 1.0 - t * t];
    let d = |t: f64| [t - 0.5, t + 0.5, -2.0 * t];
    // Node k at (i, j) in {0: -1, 1: +1, 2: 0}.
    const IJ: [(usize, usize); 9] = [
        (0, 0),
        (1, 0),
        (1, 1),
        (0, 1),
        (2, 0),
        (1, 2),
        (2, 1),
        (0, 2),
        (2, 2),
    ];
    let (lx, ly, dx, dy) = (l(xi), l(eta), d(xi), d(eta));
    IJ.map(|(i, j)| (dx[i] * ly[j], lx[i] * dy[j]))
}

/// The Jacobian determinants of a 9-node quad at the 3 × 3 Gauss points.
pub fn jacobians(p: &[Point; 9]) -> [f64; 9] {
    let g = (0.6f64).sqrt();
    let at = [-g, 0.0, g];
    let mut out = [0.0; 9];
    for (k, o) in out.iter_mut().enumerate() {
        let ds = shape_derivatives(at[k % 3], at[k / 3]);
        let (mut xx, mut xy, mut yx, mut yy) = (0.0, 0.0, 0.0, 0.0);
        for (n, (a, b)) in ds.iter().enumerate() {
            xx += a * p[n].x;
            xy += b * p[n].x;
            yx += a * p[n].y;
            yy += b * p[n].y;
        }
        *o = xx * yy - xy * yx;
    }
    out
}

/// The centre of a 9-node quad from its corners and midsides.
fn centre(p: &[Point; 9]) -> Point {
    (p[4] + p[5] + p[6] + p[7]) * 0.5 - (p[0] + p[1] + p[2] + p[3]) * 0.25
}

/// True when the quad's Jacobian is positive and not far below its
/// largest at every Gauss point.
fn acceptable(p: &[Point; 9]) -> bool {
    let j = jacobians(p);
    let hi = j.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    hi > 0.0 && j.iter().all(|&v| v >= MIN_JACOBIAN_RATIO * hi)
}

impl Order2 {
    /// The 9-node quads of `mesh`; `curved(a, b)` gives the midside point
    /// of boundary edge `a–b` on its true curve (`None`: a straight edge).
    pub fn elevate(mesh: &QuadMesh, curved: &dyn Fn(u32, u32) -> Option<Point>) -> Order2 {
        let mut nodes = mesh.nodes.clone();
        let mut midside: BTreeMap<(u32, u32), u32> = BTreeMap::new();
        let mut on_curve: BTreeMap<(u32, u32), Point> = BTreeMap::new();
        let mut boundary = std::collections::BTreeSet::new();
        for l in &mesh.loops {
            for k in 0..l.len() {
                let (a, b) = (l[k], l[(k + 1) % l.len()]);
                boundary.insert((a.min(b), a.max(b)));
            }
        }
        // Midside nodes in quad order, one per edge.
        for q in &mesh.quads {
            for i in 0..4 {
                let (a, b) = (q[i], q[(i + 1) % 4]);
                let key = (a.min(b), a.max(b));
                if midside.contains_key(&key) {
                    continue;
                }
                let mid = (nodes[a as usize] + nodes[b as usize]) * 0.5;
                let p = match boundary.contains(&key).then(|| curved(a, b)).flatten() {
                    Some(p) => {
                        on_curve.insert(key, p);
                        p
                    }
                    None => mid,
                };
                nodes.push(p);
                midside.insert(key, (nodes.len() - 1) as u32);
            }
        }
        let mut quads = Vec::with_capacity(mesh.quads.len());
        let mut straightened = 0;
        for q in &mesh.quads {
            let keys: [(u32, u32); 4] = std::array::from_fn(|i| {
                let (a, b) = (q[i], q[(i + 1) % 4]);
                (a.min(b), a.max(b))
            });
            let mut ids = [0u32; 9];
            ids[..4].copy_from_slice(q);
            for i in 0..4 {
                ids[4 + i] = midside[&keys[i]];
            }
            let mut p: [Point; 9] = std::array::from_fn(|k| {
                if k < 8 {
                    nodes[ids[k] as usize]
                } else {
                    Point::ZERO
                }
            });
            p[8] = centre(&p);
            if keys.iter().any(|k| on_curve.contains_key(k)) && !acceptable(&p) {
                for (i, k) in keys.iter().enumerate() {
                    if on_curve.remove(k).is_some() {
                        let m = (nodes[k.0 as usize] + nodes[k.1 as usize]) * 0.5;
                        nodes[ids[4 + i] as usize] = m;
                        p[4 + i] = m;
                    }
                }
                p[8] = centre(&p);
                straightened += 1;
            }
            nodes.push(p[8]);
            ids[8] = (nodes.len() - 1) as u32;
            quads.push(ids);
        }
        Order2 {
            nodes,
            quads,
            midside,
            straightened,
            serendipity: false,
        }
    }

    /// The same quads as 8-node serendipity quads: the centre nodes are
    /// left out when written. Their geometry is the same: a quad8's
    /// centre is the blend the 9-node quad's centre was placed at, so the
    /// Jacobian check holds for both.
    pub fn serendipity(mut self) -> Order2 {
        self.serendipity = true;
        self
    }

    /// The nodes written: every node, or without the centres for 8-node
    /// quads.
    pub fn written_nodes(&self) -> &[Point] {
        if self.serendipity {
            &self.nodes[..self.nodes.len() - self.quads.len()]
        } else {
            &self.nodes
        }
    }

    /// The nodes of quad `k` as written: 9, or 8 for serendipity quads.
    pub fn element(&self, k: usize) -> &[u32] {
        let q = &self.quads[k];
        if self.serendipity {
            &q[..8]
        } else {
            q
        }
    }

    /// The midside node of edge `a–b`.
    pub fn mid(&self, a: u32, b: u32) -> Option<u32> {
        self.midside.get(&(a.min(b), a.max(b))).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_straight_square_has_a_constant_jacobian() {
        let c = [
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 2.0),
            Point::new(0.0, 2.0),
        ];
        let m = QuadMesh::from_quads(c.to_vec(), vec![[0, 1, 2, 3]]).unwrap();
        let o = Order2::elevate(&m, &|_, _| None);
        assert_eq!(o.nodes.len(), 9);
        let p: [Point; 9] = o.quads[0].map(|v| o.nodes[v as usize]);
        assert_eq!(p[8], Point::new(1.0, 1.0));
        assert!(jacobians(&p).iter().all(|&j| (j - 1.0).abs() < 1e-12));
    }

    #[test]
    fn a_curve_that_folds_the_quad_is_straightened() {
        let c = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        let m = QuadMesh::from_quads(c.to_vec(), vec![[0, 1, 2, 3]]).unwrap();
        // The bottom edge's midside pushed far inside, past the top.
        let bottom = |a: u32, b: u32| {
            let (pa, pb) = (m.nodes[a as usize], m.nodes[b as usize]);
            (pa.y == 0.0 && pb.y == 0.0).then(|| Point::new(0.5, 1.5))
        };
        let o = Order2::elevate(&m, &bottom);
        assert_eq!(o.straightened, 1);
        let p: [Point; 9] = o.quads[0].map(|v| o.nodes[v as usize]);
        assert!(acceptable(&p));
        // A gentle curve stays on the curve.
        let gentle = |a: u32, b: u32| {
            let (pa, pb) = (m.nodes[a as usize], m.nodes[b as usize]);
            (pa.y == 0.0 && pb.y == 0.0).then(|| Point::new(0.5, -0.1))
        };
        let o = Order2::elevate(&m, &gentle);
        assert_eq!(o.straightened, 0);
        assert!(o.nodes.contains(&Point::new(0.5, -0.1)));
    }
}

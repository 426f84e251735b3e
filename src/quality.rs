//! Element and mesh quality (method §5; thesis §1.2 and §3.1.4).
//!
//! Per quad (corners CCW): the four corner angles; the scaled Jacobian
//! (Verdict: the minimum over corners of the sine of the corner angle, with
//! sign); `Rs = A / ē²`; the aspect ratio (the larger ratio of opposite
//! edges) and the taper in the thesis's sense (the largest ratio of adjacent
//! edges). The formulas are those of the independent judge
//! (`bench/tools/judge.py`), so both agree to rounding.

use crate::geom::{is_measurably_convex, is_strictly_convex, Point, SURE_SINE};
use crate::mesh::QuadMesh;
use serde::{Deserialize, Serialize};

/// The thesis's angle window for a good quad corner, in degrees.
pub const GOOD_ANGLE: (f64, f64) = (45.0, 135.0);

/// The thesis's bound on a good quad's aspect and taper (§1.2).
pub const GOOD_RATIO: f64 = 10.0;

/// The figures of one quad that mesh improvement evaluates many times
/// over, without trigonometry: [`QuadQuality`]'s scaled Jacobian, Rs and
/// area, and the edge lengths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    pub scaled_jacobian: f64,
    pub rs: f64,
    pub area: f64,
    /// Edge lengths, edge `k` from corner `k` to corner `k + 1`.
    pub edges: [f64; 4],
}

impl Shape {
    /// The shape figures of the quad with corners `p` (CCW).
    #[inline]
    pub fn of(p: [Point; 4]) -> Shape {
        let mut edges = [0.0; 4];
        for k in 0..4 {
            edges[k] = (p[(k + 1) % 4] - p[k]).length();
        }
        let mut sj = f64::INFINITY;
        for k in 0..4 {
            let e_next = p[(k + 1) % 4] - p[k];
            let e_prev = p[(k + 3) % 4] - p[k];
            sj = sj.min(e_next.perp_dot(e_prev) / (edges[k] * edges[(k + 3) % 4]).max(1e-300));
        }
        let area = 0.5 * (0..4).map(|k| p[k].perp_dot(p[(k + 1) % 4])).sum::<f64>();
        let mean = edges.iter().sum::<f64>() / 4.0;
        Shape {
            scaled_jacobian: sj,
            rs: area / (mean * mean),
            area,
            edges,
        }
    }

    /// Whether the quad `p` this shape is of is strictly convex
    /// ([`is_strictly_convex`]) and whether it is measurably so
    /// ([`is_measurably_convex`]). A quad whose scaled Jacobian is over
    /// [`SURE_SINE`] is both without a test: every corner's sine is then
    /// that far above zero and above [`crate::geom::MIN_CORNER_SINE`], far
    /// past the rounding of either figure.
    #[inline]
    pub fn convexity(&self, p: [Point; 4]) -> (bool, bool) {
        if self.scaled_jacobian > SURE_SINE {
            return (true, true);
        }
        (is_strictly_convex(p), is_measurably_convex(p))
    }

    /// Its scaled Jacobian, but no more than `at_limit` · [`GOOD_RATIO`] /
    /// its [`Shape::side_ratio`]: a quality that sees stretch as well. The
    /// scaled Jacobian alone does not see an edge shrinking to nothing (a
    /// quad whose two corners nearly meet is a triangle with fair angles);
    /// weighed this way, a quad stretched past [`GOOD_RATIO`] counts as
    /// under `at_limit`, the more so the more it is stretched.
    pub fn stretch_weighted(&self, at_limit: f64) -> f64 {
        self.scaled_jacobian
            .min(at_limit * GOOD_RATIO / self.side_ratio())
    }

    /// Longest over shortest side (covers the thesis's aspect and taper).
    pub fn side_ratio(&self) -> f64 {
        let (lo, hi) = self
            .edges
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &l| {
                (lo.min(l), hi.max(l))
            });
        hi / lo.max(f64::MIN_POSITIVE)
    }

    /// The aspect ratio: the larger ratio of opposite edges.
    pub fn aspect(&self) -> f64 {
        let len = self.edges;
        (len[0] / len[2])
            .max(len[2] / len[0])
            .max((len[1] / len[3]).max(len[3] / len[1]))
    }
}

/// Mesh-wide figures that need [`Shape`]: kept here, beside the formulas,
/// so that `mesh` does not import `quality`.
impl QuadMesh {
    /// The smallest scaled Jacobian of the quads (infinity with none).
    pub fn worst_scaled_jacobian(&self) -> f64 {
        self.quads
            .iter()
            .map(|q| Shape::of(self.corners(q)).scaled_jacobian)
            .fold(f64::INFINITY, f64::min)
    }
}

/// Quality figures of one quad.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct QuadQuality {
    /// Corner angles in degrees, in the quad's node order.
    pub angles: [f64; 4],
    pub scaled_jacobian: f64,
    pub rs: f64,
    pub aspect: f64,
    pub taper: f64,
    pub area: f64,
}

impl QuadQuality {
    /// Below this [`QuadQuality::rs`] a quad is thin (a rectangle of aspect
    /// about 1 : 38): mesh improvement never makes a quad that thin, since
    /// the scaled Jacobian alone would let it flatten a quad into a sliver
    /// of right angles.
    pub const THIN_RS: f64 = 0.1;

    /// The figures of the quad with corners `p` (CCW).
    pub fn of(p: [Point; 4]) -> QuadQuality {
        let shape = Shape::of(p);
        let len = shape.edges;
        let mut angles = [0.0; 4];
        for k in 0..4 {
            let e_next = p[(k + 1) % 4] - p[k];
            let e_prev = p[(k + 3) % 4] - p[k];
            angles[k] = e_next
                .perp_dot(e_prev)
                .atan2(e_next.dot(e_prev))
                .to_degrees()
                .rem_euclid(360.0);
        }
        let aspect = shape.aspect();
        let taper = (0..4)
            .map(|k| {
                let (a, b) = (len[k], len[(k + 1) % 4]);
                (a / b).max(b / a)
            })
            .fold(0.0, f64::max);
        QuadQuality {
            angles,
            scaled_jacobian: shape.scaled_jacobian,
            rs: shape.rs,
            aspect,
            taper,
            area: shape.area,
        }
    }

    pub fn min_angle(&self) -> f64 {
        self.angles.iter().copied().fold(f64::INFINITY, f64::min)
    }

    pub fn max_angle(&self) -> f64 {
        self.angles
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// All corners in [45°, 135°].
    pub fn angles_ok(&self) -> bool {
        self.min_angle() >= GOOD_ANGLE.0 && self.max_angle() <= GOOD_ANGLE.1
    }

    /// The thesis's criteria: angles in [45°, 135°], aspect and taper ≤ 10.
    pub fn meets_thesis(&self) -> bool {
        self.angles_ok() && self.aspect <= GOOD_RATIO && self.taper <= GOOD_RATIO
    }
}

/// Quality figures of a whole mesh (the fields of `judge.py`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MeshQuality {
    pub quads: usize,
    pub nodes: usize,
    pub min_angle: f64,
    pub max_angle: f64,
    /// Share of quads with all angles in [45°, 135°].
    pub frac_angles_45_135: f64,
    /// Share of quads meeting all thesis criteria.
    pub frac_thesis_good: f64,
    /// Share of quads with Rs ≥ 0.8.
    pub frac_rs_ge_0_8: f64,
    pub sj_min: f64,
    pub sj_mean: f64,
    pub aspect_max: f64,
    pub taper_max: f64,
    pub interior_nodes: usize,
    /// Interior nodes whose valence is not 4.
    pub irregular_interior: usize,
}

impl MeshQuality {
    /// Figures for `mesh` (all zero for a mesh without quads).
    pub fn of(mesh: &QuadMesh) -> MeshQuality {
        Self::of_open(mesh, &[])
    }

    /// The figures of several meshes taken together (the faces of one
    /// region): counts add up, extremes are the extremes, shares and the
    /// mean are weighted by quad count. A node on two of the meshes counts
    /// once in each (their shared curves are their boundaries).
    pub fn combine(parts: &[MeshQuality]) -> MeshQuality {
        let parts: Vec<&MeshQuality> = parts.iter().filter(|q| q.quads > 0).collect();
        let n: usize = parts.iter().map(|q| q.quads).sum();
        if n == 0 {
            return MeshQuality::default();
        }
        let w = |f: fn(&MeshQuality) -> f64| {
            parts.iter().map(|q| f(q) * q.quads as f64).sum::<f64>() / n as f64
        };
        let min =
            |f: fn(&MeshQuality) -> f64| parts.iter().map(|q| f(q)).fold(f64::INFINITY, f64::min);
        let max = |f: fn(&MeshQuality) -> f64| {
            parts.iter().map(|q| f(q)).fold(f64::NEG_INFINITY, f64::max)
        };
        MeshQuality {
            quads: n,
            nodes: parts.iter().map(|q| q.nodes).sum(),
            min_angle: min(|q| q.min_angle),
            max_angle: max(|q| q.max_angle),
            frac_angles_45_135: w(|q| q.frac_angles_45_135),
            frac_thesis_good: w(|q| q.frac_thesis_good),
            frac_rs_ge_0_8: w(|q| q.frac_rs_ge_0_8),
            sj_min: min(|q| q.sj_min),
            sj_mean: w(|q| q.sj_mean),
            aspect_max: max(|q| q.aspect_max),
            taper_max: max(|q| q.taper_max),
            interior_nodes: parts.iter().map(|q| q.interior_nodes).sum(),
            irregular_interior: parts.iter().map(|q| q.irregular_interior).sum(),
        }
    }

    /// [`MeshQuality::of`] for a mesh still being made: the nodes `open`
    /// (the front's) are not counted as interior nodes, since their quads
    /// do not surround them yet and their valence says nothing.
    pub fn of_open(mesh: &QuadMesh, open: &[u32]) -> MeshQuality {
        let n = mesh.quads.len();
        if n == 0 {
            return MeshQuality::default();
        }
        let mut m = MeshQuality {
            quads: n,
            min_angle: f64::INFINITY,
            max_angle: f64::NEG_INFINITY,
            sj_min: f64::INFINITY,
            ..Default::default()
        };
        let (mut ok, mut good, mut rs, mut sj_sum) = (0usize, 0usize, 0usize, 0.0);
        for q in &mesh.quads {
            let f = QuadQuality::of(mesh.corners(q));
            m.min_angle = m.min_angle.min(f.min_angle());
            m.max_angle = m.max_angle.max(f.max_angle());
            m.sj_min = m.sj_min.min(f.scaled_jacobian);
            sj_sum += f.scaled_jacobian;
            m.aspect_max = m.aspect_max.max(f.aspect);
            m.taper_max = m.taper_max.max(f.taper);
            ok += f.angles_ok() as usize;
            good += f.meets_thesis() as usize;
            rs += (f.rs >= 0.8) as usize;
        }
        m.sj_mean = sj_sum / n as f64;
        m.frac_angles_45_135 = ok as f64 / n as f64;
        m.frac_thesis_good = good as f64 / n as f64;
        m.frac_rs_ge_0_8 = rs as f64 / n as f64;
        let mut valence = vec![0u32; mesh.nodes.len()];
        for q in &mesh.quads {
            for &v in q {
                valence[v as usize] += 1;
            }
        }
        let nb = mesh.n_boundary();
        m.nodes = valence.iter().filter(|&&v| v > 0).count();
        let mut on_front = vec![false; mesh.nodes.len()];
        for &v in open {
            if let Some(f) = on_front.get_mut(v as usize) {
                *f = true;
            }
        }
        for (i, &v) in valence.iter().enumerate() {
            if i >= nb && v > 0 && !on_front[i] {
                m.interior_nodes += 1;
                if v != 4 {
                    m.irregular_interior += 1;
                }
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn convexity_answers_as_the_geometry_tests_do() {
        // Random quads on a coarse grid (flat, reflex, folded and
        // degenerate ones among them), near-flat ones off it and ones whose
        // sines are about the bar of the test-free answer.
        let mut g = crate::rng::SplitMix64::new(0x5eed_c0de);
        let (mut strict, mut measurable) = (0, 0);
        for n in 0..30_000 {
            let p: [Point; 4] = std::array::from_fn(|_| match n % 3 {
                0 => Point::new(g.int(0, 4) as f64, g.int(0, 4) as f64),
                1 => Point::new(g.uni(-1.0, 1.0), g.uni(-1.0, 1.0) * 1e-9),
                _ => Point::new(g.uni(-1.0, 1.0), g.uni(-1.0, 1.0) * 1e-6),
            });
            let got = Shape::of(p).convexity(p);
            assert_eq!(
                got,
                (is_strictly_convex(p), is_measurably_convex(p)),
                "{p:?}"
            );
            strict += got.0 as usize;
            measurable += got.1 as usize;
        }
        // Both answers occur, and they differ on some quads.
        assert!(
            measurable > 0 && strict > measurable && strict < 30_000,
            "{strict} {measurable}"
        );
    }

    /// A 2 × 2 grid with one quad still to make: its middle node has three
    /// quads, but it is on the front, not an irregular interior node.
    #[test]
    fn front_nodes_of_a_mesh_being_made_are_not_interior() {
        let p = |x: f64, y: f64| Point::new(x, y);
        let mesh = QuadMesh {
            // The boundary loop (ids 0..8, CCW), then the middle node.
            nodes: vec![
                p(0., 0.),
                p(1., 0.),
                p(2., 0.),
                p(2., 1.),
                p(2., 2.),
                p(1., 2.),
                p(0., 2.),
                p(0., 1.),
                p(1., 1.),
            ],
            quads: vec![[0, 1, 8, 7], [1, 2, 3, 8], [8, 3, 4, 5]],
            loops: vec![(0..8).collect()],
        };
        let all = MeshQuality::of(&mesh);
        assert_eq!((all.irregular_interior, all.interior_nodes), (1, 1));
        let open = MeshQuality::of_open(&mesh, &[8, 5, 6, 7]);
        assert_eq!((open.irregular_interior, open.interior_nodes), (0, 0));
        assert_eq!(open.quads, 3);
    }

    #[test]
    fn unit_square() {
        let q = QuadQuality::of([
            Point::new(0., 0.),
            Point::new(1., 0.),
            Point::new(1., 1.),
            Point::new(0., 1.),
        ]);
        assert!((q.scaled_jacobian - 1.0).abs() < 1e-12);
        assert!((q.rs - 1.0).abs() < 1e-12);
        assert_eq!(q.aspect, 1.0);
        assert!(q.angles.iter().all(|a| (a - 90.0).abs() < 1e-9));
        assert!(q.meets_thesis());
    }

    #[test]
    fn rhombus() {
        let s = 60f64.to_radians();
        let q = QuadQuality::of([
            Point::new(0., 0.),
            Point::new(1., 0.),
            Point::new(1. + s.cos(), s.sin()),
            Point::new(s.cos(), s.sin()),
        ]);
        assert!((q.scaled_jacobian - s.sin()).abs() < 1e-12);
        assert!((q.min_angle() - 60.0).abs() < 1e-9);
        assert!((q.max_angle() - 120.0).abs() < 1e-9);
    }
}

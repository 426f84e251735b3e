//! The mesh drawn as batched shapes, cached in world coordinates and kept
//! while the mesh, the overlay and the view allow it.

use super::{quality_color, Overlay, QuadIndex, POOR_TINT};
use crate::app::quality_panel::Metric;
use crate::app::world_mesh::{QuadImage, WorldMesh, WorldMeshBuilder};
use crate::geom::{Aabb, Point};
use crate::mesh::QuadMesh;
use egui::epaint::Mesh;
use egui::{Color32, Pos2, Rect, Shape};

/// Adds a convex polygon as a triangle fan.
pub(super) fn push_fan(mesh: &mut Mesh, pts: &[Pos2], color: Color32) {
    let base = mesh.vertices.len() as u32;
    for &p in pts {
        mesh.colored_vertex(p, color);
    }
    for k in 1..pts.len().saturating_sub(1) as u32 {
        mesh.add_triangle(base, base + k, base + k + 1);
    }
}

/// What the canvas keeps between frames for one mesh: each quad's colour,
/// each edge once, and the mesh, the boundary and the front as triangles
/// in world coordinates that each frame maps to the screen (a pan or zoom
/// moves vertices; nothing is built again). Rebuilt when the mesh or the
/// colouring changes.
#[derive(Default)]
pub struct MeshCache {
    pub(super) key: Option<(u64, usize, Option<Metric>)>,
    pub(super) edges: Vec<[u32; 2]>,
    /// Quads that miss the thesis criteria.
    pub(super) poor: Vec<u32>,
    /// Mean edge length in world units.
    pub(super) mean_edge: f64,
    /// The quads by place, for hovering.
    pub index: QuadIndex,
    /// Bumped whenever the key changes.
    pub(super) generation: u64,
    /// The box of the mesh's nodes.
    pub(super) bounds: Option<Aabb>,
    /// Each quad's colour.
    pub(super) colors: Vec<Color32>,
    /// The quads filled in their colours, and those that miss the thesis
    /// criteria tinted (built when first drawn).
    pub(super) fills: Option<(WorldMesh, WorldMesh)>,
    /// The fills as an image.
    pub(super) image: Option<QuadImage>,
    /// The edges in this colour (built when first drawn).
    pub(super) edge_lines: Option<(Color32, WorldMesh)>,
    /// The boundary and the front.
    pub(super) lines: WorldMesh,
    /// What [`MeshCache::dashes`] was built for.
    pub(super) dashes_key: Option<ScreenKey>,
    /// The outlines of the quads that miss the thesis criteria, dashed in
    /// screen space (the dashes are pixels long).
    pub(super) dashes: Vec<Shape>,
}

/// What the screen-space dashes depend on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ScreenKey {
    pub(super) mesh: Option<(u64, usize, Option<Metric>)>,
    pub(super) center: Point,
    pub(super) zoom: f64,
    pub(super) rect: Rect,
}

impl MeshCache {
    pub(super) fn refresh(&mut self, o: &Overlay) {
        let key = (o.version, o.mesh.quads.len(), o.metric);
        if self.key == Some(key) {
            return;
        }
        self.key = Some(key);
        self.generation += 1;
        let m = o.mesh;
        self.poor = (0..o.qualities.len() as u32)
            .filter(|&k| !o.qualities[k as usize].meets_thesis())
            .collect();
        let mut edges: Vec<[u32; 2]> = m
            .quads
            .iter()
            .flat_map(|q| {
                (0..4).map(move |k| {
                    let (a, b) = (q[k], q[(k + 1) % 4]);
                    [a.min(b), a.max(b)]
                })
            })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let total: f64 = edges
            .iter()
            .map(|e| (m.nodes[e[0] as usize] - m.nodes[e[1] as usize]).length())
            .sum();
        self.mean_edge = if edges.is_empty() {
            f64::INFINITY
        } else {
            total / edges.len() as f64
        };
        self.edges = edges;
        self.index = QuadIndex::of(m);
        self.bounds = Aabb::of(m.nodes.iter().copied());
        let plain = Color32::from_rgb(70, 110, 90);
        self.colors = (0..m.quads.len())
            .map(|k| {
                let c = match (o.metric, o.qualities.get(k)) {
                    (Some(metric), Some(q)) => quality_color(metric.score(q)),
                    _ => plain,
                };
                c.gamma_multiply(0.8)
            })
            .collect();
        self.fills = None;
        self.edge_lines = None;
        // Boundary and front.
        let loops = o.boundary.map_or(0, |b| b.points.len());
        let front = o.front.iter().map(Vec::len).sum::<usize>();
        let mut lines = WorldMeshBuilder::new(self.world_box(), loops + front);
        if let Some(b) = o.boundary {
            for l in &b.loops {
                for k in 0..l.len() {
                    let (a, c) = (b.points[l[k]], b.points[l[(k + 1) % l.len()]]);
                    lines.segment(a, c, 1.5, Color32::from_gray(200));
                }
            }
        }
        let front_color = Color32::from_rgb(255, 150, 40);
        for l in o.front {
            for k in 0..l.len() {
                let (a, c) = (l[k] as usize, l[(k + 1) % l.len()] as usize);
                if let (Some(&a), Some(&c)) = (m.nodes.get(a), m.nodes.get(c)) {
                    lines.segment(a, c, 3.0, front_color);
                }
            }
        }
        self.lines = lines.build();
        self.dashes_key = None;
    }

    /// The box the chunks are filed in: the mesh's nodes (what lies
    /// outside goes to the edge chunks).
    fn world_box(&self) -> Aabb {
        self.bounds.unwrap_or(Aabb {
            min: Point::ZERO,
            max: Point::ZERO,
        })
    }

    /// The quads' fills and the tint, as triangles in world coordinates.
    pub(super) fn fills(&mut self, mesh: &QuadMesh) -> &mut (WorldMesh, WorldMesh) {
        if self.fills.is_none() {
            let bounds = self.world_box();
            let mut quads = WorldMeshBuilder::new(bounds, mesh.quads.len());
            for (q, &c) in mesh.quads.iter().zip(&self.colors) {
                quads.fan(&mesh.corners(q), c);
            }
            let mut tint = WorldMeshBuilder::new(bounds, self.poor.len());
            for q in self.poor.iter().filter_map(|&k| mesh.quads.get(k as usize)) {
                tint.fan(&mesh.corners(q), POOR_TINT);
            }
            self.fills = Some((quads.build(), tint.build()));
        }
        self.fills.get_or_insert_with(Default::default)
    }

    /// The edges in `color`, as triangles in world coordinates.
    pub(super) fn edge_lines(&mut self, mesh: &QuadMesh, color: Color32) -> &mut WorldMesh {
        if self.edge_lines.as_ref().is_none_or(|(c, _)| *c != color) {
            let mut b = WorldMeshBuilder::new(self.world_box(), self.edges.len());
            for e in &self.edges {
                if let (Some(&p), Some(&q)) =
                    (mesh.nodes.get(e[0] as usize), mesh.nodes.get(e[1] as usize))
                {
                    b.segment(p, q, 1.0, color);
                }
            }
            self.edge_lines = Some((color, b.build()));
        }
        &mut self
            .edge_lines
            .get_or_insert_with(|| (color, WorldMesh::default()))
            .1
    }
}

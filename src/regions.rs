//! One conforming mesh of several regions with named boundary groups.
//!
//! Each face of a planar straight-line graph ([`crate::pslg`]) is meshed by
//! the pipeline ([`crate::pipeline::mesh_boundary`]: extraction, method §2,
//! then finishing, thesis §5.1) with its boundary nodes fixed. Faces share
//! the nodes of the curves between them, and no step moves, drops or adds a
//! boundary node, so the meshes of two faces meet node to node along their
//! shared curve: the union conforms by construction, and
//! [`RegionMesh::check_conforming`] checks it. The size field of each face
//! follows its boundary's spacing, the same on both sides of a shared
//! curve.
//!
//! Faces are independent and are meshed in parallel (rayon, as many
//! threads as the pool the caller runs in). They are merged in face order,
//! so the mesh is the same, byte for byte, whatever the thread count.

use crate::extract::{MeshError, Mesher, StepOutcome, StepStats};
use crate::geom::Point;
use crate::io::groups::{Labelled, Named};
use crate::io::MeshFormat;
use crate::mesh::{InvariantError, QuadMesh};
use crate::model::Model;
use crate::order2::Order2;
use crate::pipeline::{finish_moved, mesh_boundary, Params};
use crate::pslg::{Face, Pslg, PslgError};
use crate::quality::MeshQuality;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;
use thiserror::Error;

/// A region of the mesh: the faces of one attribute.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Region {
    /// Physical surface tag: the region attribute (the unassigned faces of
    /// a graph with region points take the next free tag).
    pub tag: i64,
    pub name: String,
    /// Quality of the region's quads alone (its shared curves count as
    /// its boundary).
    pub quality: MeshQuality,
}

/// A named boundary group: the mesh edges of the segments of one marker,
/// interface segments included.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Group {
    /// Physical curve tag: the segment marker.
    pub tag: i64,
    pub name: String,
    /// Mesh edges as node pairs, in the graph's segment order and
    /// direction.
    pub edges: Vec<[u32; 2]>,
}

/// The conforming mesh of every face, with its regions and groups.
#[derive(Clone, Debug)]
pub struct RegionMesh {
    /// The union of the faces' meshes, one node numbering
    /// ([`QuadMesh::from_quads`]: the union's boundary nodes first).
    pub mesh: QuadMesh,
    /// The region (index into `regions`) of each quad.
    pub quad_region: Vec<u32>,
    /// Regions by tag.
    pub regions: Vec<Region>,
    /// Groups by tag.
    pub groups: Vec<Group>,
    /// Each face's region (index into `regions`), quads and step counts,
    /// in face order.
    pub faces: Vec<FaceMesh>,
}

/// What meshing one face made.
#[derive(Clone, Debug, Serialize)]
pub struct FaceMesh {
    pub region: u32,
    pub quads: usize,
    pub steps: StepStats,
}

/// Why a graph could not be meshed.
#[derive(Debug, Error)]
pub enum RegionError {
    #[error(transparent)]
    Graph(#[from] PslgError),
    #[error("region {region}: {source}")]
    Mesh {
        region: String,
        #[source]
        source: MeshError,
    },
    #[error("the regions' meshes do not conform: {0}")]
    NotConforming(String),
    #[error("the union of the regions' meshes: {0}")]
    Union(InvariantError),
}

/// A face's finished mesh and step counts, or why it failed.
type FaceResult = Result<(QuadMesh, StepStats), RegionError>;

/// Position key of a node: boundary nodes keep their exact coordinates.
fn key(p: Point) -> (u64, u64) {
    (p.x.to_bits(), p.y.to_bits())
}

/// Meshes every face of `graph` with `model` and `params` and merges the
/// meshes into one. `progress` is called after each face with the number
/// of faces done.
pub fn mesh_regions(
    graph: &Pslg,
    model: Arc<dyn Model>,
    params: &Params,
    progress: impl Fn(usize) + Sync,
) -> Result<RegionMesh, RegionError> {
    let faces = graph.faces()?;
    let done = std::sync::atomic::AtomicUsize::new(0);
    // Largest faces first, so that the last one to finish is a small one;
    // the results go back to face order, which alone fixes the output.
    let mut order: Vec<usize> = (0..faces.len()).collect();
    order.sort_by_key(|&k| std::cmp::Reverse(faces[k].boundary.node_count()));
    let mut meshed: Vec<(usize, FaceResult)> = order
        .par_iter()
        .with_max_len(1)
        .map(|&k| {
            let f = &faces[k];
            let r = mesh_boundary(&f.boundary, model.clone(), params, |_| {}).map_err(|source| {
                RegionError::Mesh {
                    region: graph.region_name(f.attribute),
                    source,
                }
            });
            progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
            (k, r)
        })
        .collect();
    meshed.sort_by_key(|(k, _)| *k);
    let meshed: Vec<_> = meshed.into_iter().map(|(_, r)| r).collect();
    let meshed = meshed.into_iter().collect::<Result<Vec<_>, _>>()?;
    merge(graph, &faces, meshed)
}

/// Meshes a graph face by face with the step API: the current face has a
/// [`Mesher`] (in its boundary's local frame, [`crate::Boundary::to_local`],
/// as [`mesh_boundary`] runs it) that the caller steps, corrects or
/// undoes like any other; [`RegionStepper::next_face`] finishes its mesh
/// and starts the next face. Stepped to the end, it gives the mesh of
/// [`mesh_regions`], byte for byte.
#[derive(Clone)]
pub struct RegionStepper {
    graph: Pslg,
    faces: Vec<Face>,
    model: Arc<dyn Model>,
    params: Params,
    /// The current face and its mesher, with the offset its local frame
    /// is moved by.
    current: usize,
    mesher: Mesher,
    origin: Point,
    finished: Vec<(QuadMesh, StepStats)>,
}

impl RegionStepper {
    /// The faces of `graph`, the first one ready to step.
    pub fn new(graph: Pslg, model: Arc<dyn Model>, params: Params) -> Result<Self, RegionError> {
        let faces = graph.faces()?;
        let (local, origin) = faces[0].boundary.to_local();
        let mesher = Mesher::new(local, model.clone(), params.extract.moved(origin));
        Ok(RegionStepper {
            graph,
            faces,
            model,
            params,
            current: 0,
            mesher,
            origin,
            finished: Vec::new(),
        })
    }

    pub fn graph(&self) -> &Pslg {
        &self.graph
    }

    /// Every face to mesh, in meshing order.
    pub fn faces(&self) -> &[Face] {
        &self.faces
    }

    /// The index of the face being meshed.
    pub fn current(&self) -> usize {
        self.current
    }

    /// The name of the region the current face belongs to.
    pub fn current_region(&self) -> String {
        region_name_of(&self.graph, &self.faces, self.current)
    }

    /// The current face's mesher, in its local frame.
    pub fn mesher(&self) -> &Mesher {
        &self.mesher
    }

    pub fn mesher_mut(&mut self) -> &mut Mesher {
        &mut self.mesher
    }

    /// The offset of the current face's local frame: world = local + origin.
    pub fn origin(&self) -> Point {
        self.origin
    }

    /// The finished meshes of the faces before the current one, in world
    /// coordinates.
    pub fn finished(&self) -> impl Iterator<Item = &QuadMesh> {
        self.finished.iter().map(|(m, _)| m)
    }

    /// True when every face is meshed.
    pub fn is_done(&self) -> bool {
        self.finished.len() == self.faces.len()
    }

    /// One step of the current face; when its front is empty, the face is
    /// finished and the next one started ([`RegionStepper::next_face`]).
    pub fn step(&mut self) -> Result<StepOutcome, RegionError> {
        if self.is_done() {
            return Ok(StepOutcome::Done);
        }
        let out = self.mesher.step().map_err(|e| self.error(e))?;
        if self.mesher.is_done() {
            self.next_face()?;
        }
        Ok(out)
    }

    /// Runs every face left to the end.
    pub fn run(&mut self) -> Result<(), RegionError> {
        while !self.is_done() {
            self.mesher.run(|_| {}).map_err(|e| self.error(e))?;
            self.next_face()?;
        }
        Ok(())
    }

    fn error(&self, source: MeshError) -> RegionError {
        RegionError::Mesh {
            region: self.current_region(),
            source,
        }
    }

    /// Finishes the current face's mesh ([`finish_moved`], whether its
    /// front is empty or it stops where it stands) and starts the next
    /// face. Returns false when there was no face left.
    pub fn next_face(&mut self) -> Result<bool, RegionError> {
        if self.is_done() {
            return Ok(false);
        }
        let mesh = finish_moved(&self.mesher, &self.params.finish, self.origin)
            .map_err(|e| self.error(e))?;
        self.finished.push((mesh, self.mesher.stats().clone()));
        self.current = self.finished.len();
        if let Some(f) = self.faces.get(self.current) {
            let (local, origin) = f.boundary.to_local();
            self.mesher = Mesher::new(local, self.model.clone(), self.params.extract.moved(origin));
            self.origin = origin;
        }
        Ok(true)
    }

    /// The merged mesh of every face, once all are meshed.
    pub fn finish(self) -> Result<RegionMesh, RegionError> {
        if !self.is_done() {
            return Err(RegionError::NotConforming(format!(
                "face {} of {} ({}) is not meshed yet",
                self.current + 1,
                self.faces.len(),
                self.current_region()
            )));
        }
        merge(&self.graph, &self.faces, self.finished)
    }
}

fn region_name_of(graph: &Pslg, faces: &[Face], k: usize) -> String {
    let (table, index) = region_table(graph, faces);
    faces
        .get(k)
        .and_then(|f| index.get(&f.attribute))
        .map_or_else(String::new, |&i| table[i as usize].1.clone())
}

/// The regions' tags and names: attributes in order, then the unassigned
/// faces' region (named `domain` when no face has an attribute).
fn region_table(graph: &Pslg, faces: &[Face]) -> (Vec<(i64, String)>, BTreeMap<i64, u32>) {
    let mut attrs: Vec<i64> = faces.iter().map(|f| f.attribute).collect();
    attrs.sort_unstable();
    attrs.dedup();
    let top = attrs.iter().copied().max().unwrap_or(0);
    let mut table = Vec::new();
    let mut index = BTreeMap::new();
    for &a in attrs.iter().filter(|&&a| a != 0) {
        index.insert(a, table.len() as u32);
        table.push((a, graph.region_name(a)));
    }
    if attrs.contains(&0) {
        let name = if top == 0 {
            graph
                .region_names
                .get(&0)
                .cloned()
                .unwrap_or_else(|| "domain".into())
        } else {
            "unassigned".into()
        };
        index.insert(0, table.len() as u32);
        table.push((top + 1, name));
    }
    (table, index)
}

fn merge(
    graph: &Pslg,
    faces: &[Face],
    meshed: Vec<(QuadMesh, StepStats)>,
) -> Result<RegionMesh, RegionError> {
    // The graph's nodes first, then each face's interior nodes in order.
    let mut points = graph.points.clone();
    let mut quads: Vec<[u32; 4]> = Vec::new();
    let mut owner: Vec<u32> = Vec::new();
    let (table, index) = region_table(graph, faces);
    let mut face_meshes = Vec::new();
    let mut by_region: Vec<Vec<MeshQuality>> = vec![Vec::new(); table.len()];
    for (f, (m, stats)) in faces.iter().zip(meshed) {
        let own: HashMap<(u64, u64), usize> =
            f.nodes.iter().map(|&g| (key(graph.points[g]), g)).collect();
        let id: Vec<u32> = m
            .nodes
            .iter()
            .map(|&p| match own.get(&key(p)) {
                Some(&g) => g as u32,
                None => {
                    points.push(p);
                    (points.len() - 1) as u32
                }
            })
            .collect();
        let region = index[&f.attribute];
        quads.extend(m.quads.iter().map(|q| q.map(|v| id[v as usize])));
        owner.extend(std::iter::repeat_n(region, m.quads.len()));
        by_region[region as usize].push(MeshQuality::of(&m));
        face_meshes.push(FaceMesh {
            region,
            quads: m.quads.len(),
            steps: stats,
        });
    }
    let mesh = QuadMesh::from_quads(points, quads).map_err(RegionError::Union)?;
    let id: HashMap<(u64, u64), u32> = mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(i, &p)| (key(p), i as u32))
        .collect();
    let mut groups: BTreeMap<i64, Vec<[u32; 2]>> = BTreeMap::new();
    let meshed_node = |g: usize| id.get(&key(graph.points[g])).copied();
    for s in &graph.segments {
        if s.marker == 0 {
            continue;
        }
        // Segments of faces not meshed (hole outlines are meshed; a
        // segment inside a hole is not) are left out.
        if let (Some(a), Some(b)) = (meshed_node(s.a), meshed_node(s.b)) {
            groups.entry(s.marker).or_default().push([a, b]);
        }
    }
    let out = RegionMesh {
        quad_region: owner,
        regions: table
            .into_iter()
            .zip(by_region)
            .map(|((tag, name), q)| Region {
                tag,
                name,
                quality: MeshQuality::combine(&q),
            })
            .collect(),
        groups: groups
            .into_iter()
            .map(|(tag, edges)| Group {
                tag,
                name: graph.group_name(tag),
                edges,
            })
            .collect(),
        faces: face_meshes,
        mesh,
    };
    out.check_conforming().map_err(RegionError::NotConforming)?;
    Ok(out)
}

impl RegionMesh {
    /// The mesh, its regions and groups as the writers see them.
    pub fn labelled(&self) -> Labelled<'_> {
        self.labelled_with(None)
    }

    /// [`RegionMesh::labelled`] with 9-node quads.
    pub fn labelled_with<'a>(&'a self, order2: Option<&'a Order2>) -> Labelled<'a> {
        let named = |tag, name| Named {
            tag,
            name,
            edges: &[],
        };
        Labelled {
            mesh: &self.mesh,
            quad_region: &self.quad_region,
            regions: self.regions.iter().map(|r| named(r.tag, &r.name)).collect(),
            groups: self
                .groups
                .iter()
                .map(|g| Named {
                    edges: &g.edges,
                    ..named(g.tag, &g.name)
                })
                .collect(),
            order2,
        }
    }

    /// The mesh of a single domain as one region (`domain`) without groups.
    pub fn single(mesh: QuadMesh, steps: StepStats) -> RegionMesh {
        let quality = MeshQuality::of(&mesh);
        RegionMesh {
            quad_region: vec![0; mesh.quads.len()],
            regions: vec![Region {
                tag: 1,
                name: "domain".into(),
                quality,
            }],
            groups: Vec::new(),
            faces: vec![FaceMesh {
                region: 0,
                quads: mesh.quads.len(),
                steps,
            }],
            mesh,
        }
    }

    /// This mesh with each boundary loop a group, tagged and named as the
    /// writers of a single domain name them (`outer`, `hole_1`, ...): the
    /// groups of a boundary file without markers, for the writers of
    /// regions and groups (second order).
    pub fn with_loop_groups(mut self) -> RegionMesh {
        self.groups = self
            .mesh
            .loops
            .iter()
            .enumerate()
            .map(|(k, l)| Group {
                tag: k as i64 + 1,
                name: crate::io::msh::loop_name(k),
                edges: (0..l.len()).map(|i| [l[i], l[(i + 1) % l.len()]]).collect(),
            })
            .collect();
        self
    }

    /// Step counts of all faces together.
    pub fn steps(&self) -> StepStats {
        let mut s = StepStats::default();
        for f in &self.faces {
            s.add(&f.steps);
        }
        s
    }

    /// Checks that the faces' meshes conform: every directed edge is used
    /// by one quad at most, every edge by two quads at most (then in
    /// opposite directions), and every edge used once lies on the union's
    /// boundary, so no quad's edge ends at a node inside another's side.
    /// Each face's mesh was checked by the pipeline.
    pub fn check_conforming(&self) -> Result<(), String> {
        let mut uses: BTreeMap<(u32, u32), (u32, u32)> = BTreeMap::new();
        for (k, q) in self.mesh.quads.iter().enumerate() {
            for i in 0..4 {
                let (a, b) = (q[i], q[(i + 1) % 4]);
                let e = uses.entry((a.min(b), a.max(b))).or_insert((0, 0));
                if a < b {
                    e.0 += 1;
                } else {
                    e.1 += 1;
                }
                if e.0 > 1 || e.1 > 1 {
                    return Err(format!(
                        "the edge from node {} to node {} is used twice in one direction (quad {})",
                        a + 1,
                        b + 1,
                        k + 1
                    ));
                }
            }
        }
        let on_boundary: std::collections::BTreeSet<(u32, u32)> = self
            .mesh
            .loops
            .iter()
            .flat_map(|l| (0..l.len()).map(move |i| (l[i], l[(i + 1) % l.len()])))
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        for (&(a, b), &(f, r)) in &uses {
            if f + r == 1 && !on_boundary.contains(&(a, b)) {
                return Err(format!(
                    "the edge from node {} to node {} has a quad on one side only, inside the mesh",
                    a + 1,
                    b + 1
                ));
            }
        }
        // A hanging node: an edge used once whose boundary loop passes
        // through a node interior to the union is caught by the loops:
        // their nodes must be the union's boundary nodes only.
        let nb = self.mesh.n_boundary();
        if self.mesh.loops.iter().flatten().any(|&v| v as usize >= nb) {
            return Err("a boundary loop passes through an interior node".into());
        }
        Ok(())
    }

    /// Quality of the whole mesh: interface nodes count as interior nodes.
    pub fn quality(&self) -> MeshQuality {
        MeshQuality::of(&self.mesh)
    }
}

impl MeshFormat {
    /// Renders a mesh of several regions with its groups in this format
    /// ([`crate::io::groups`]; an SVG picture is tinted by region).
    pub fn render_regions(self, m: &RegionMesh) -> String {
        self.render_labelled(&m.labelled())
    }
}

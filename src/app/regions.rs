//! Documents of several regions and named boundary groups: a planar
//! straight-line graph ([`Pslg`]) cut into faces, meshed face by face
//! through [`RegionStepper`] (each face's `Mesher` stepped like a single
//! domain's), and the edits the editor makes to the graph: an interface
//! curve that splits a region, a group of segments named, a face's region
//! named. Every edit gives a new graph, validated with [`Pslg::faces`]; an
//! invalid graph is kept with its one-line problem and has no mesh until
//! it is fixed.

use super::document::{load_model, ModelInfo, Settings};
use super::error::EditorError;
use crate::extract::{StepOutcome, StepReport};
use crate::geom::{point_in_polygon, Point};
use crate::mesh::QuadMesh;
use crate::model::ModelFile;
use crate::pipeline::Params;
use crate::pslg::{Face, Pslg, PslgError, RegionPoint, Segment};
use crate::regions::{RegionMesh, RegionStepper};
use egui::Color32;
use std::sync::Arc;

/// The regions part of a document: the graph, its faces and their
/// meshing.
#[derive(Clone)]
pub struct Regions {
    pub graph: Pslg,
    /// Why the graph cannot be meshed as it is (no faces, no stepper).
    pub problem: Option<PslgError>,
    /// The faces to mesh, in meshing order.
    pub faces: Vec<Face>,
    /// The index into `legend` of each face's region.
    pub face_region: Vec<usize>,
    /// The regions as the mesh numbers them (tag, name), in the order of
    /// [`RegionMesh::regions`].
    pub legend: Vec<(i64, String)>,
    /// Triangles filling each face (world), for the tint.
    pub tints: Vec<Vec<[Point; 3]>>,
    /// The faces being meshed.
    pub stepper: Option<RegionStepper>,
    /// The mesh of every face, once the last one is meshed.
    pub mesh: Option<Arc<RegionMesh>>,
    /// The finished faces' meshes and the current face's partial mesh,
    /// in world coordinates (what the canvas shows while stepping).
    pub shown: Arc<QuadMesh>,
    shown_stale: bool,
    /// The last step's report (in the current face's local frame).
    pub last: Option<StepReport>,
    /// Steps taken over every face.
    pub steps: usize,
    pub info: ModelInfo,
}

impl Regions {
    /// The regions of `graph`, meshed with `settings` (a graph that is not
    /// valid is kept with its problem); fails only when the model cannot
    /// be loaded or the first face cannot start.
    pub fn new(
        graph: Pslg,
        settings: &Settings,
        models: &[ModelFile],
    ) -> Result<Regions, EditorError> {
        let (model, info) = load_model(&settings.model, models)?;
        let mut r = Regions {
            problem: None,
            faces: Vec::new(),
            face_region: Vec::new(),
            legend: Vec::new(),
            tints: Vec::new(),
            stepper: None,
            mesh: None,
            shown: Arc::new(QuadMesh::default()),
            shown_stale: false,
            last: None,
            steps: 0,
            info,
            graph,
        };
        match r.graph.faces() {
            Ok(faces) => {
                let (legend, face_region) = legend_of(&r.graph, &faces);
                r.legend = legend;
                r.face_region = face_region;
                r.tints = faces
                    .iter()
                    .map(|f| super::canvas::domain_triangles(&f.boundary))
                    .collect();
                r.faces = faces;
                let params = Params {
                    extract: settings.params(),
                    finish: settings.finishing(),
                };
                r.stepper = Some(RegionStepper::new(r.graph.clone(), model, params)?);
                r.shown_stale = true;
                r.sync_shown();
            }
            Err(e) => r.problem = Some(e),
        }
        Ok(r)
    }

    /// True when every face is meshed.
    pub fn is_done(&self) -> bool {
        self.mesh.is_some()
    }

    /// The index of the face being meshed and its region's name.
    pub fn current(&self) -> Option<(usize, String)> {
        let s = self.stepper.as_ref()?;
        Some((s.current(), s.current_region()))
    }

    /// One step of the current face (the next face is started when it is
    /// meshed); `Ok(false)` when every face is meshed.
    pub fn step(&mut self) -> Result<bool, EditorError> {
        let Some(s) = self.stepper.as_mut() else {
            return Err(self.no_graph());
        };
        loop {
            if s.is_done() {
                return Ok(false);
            }
            match s.step()? {
                StepOutcome::Stepped(r) => {
                    self.last = Some(*r);
                    self.steps += 1;
                    self.shown_stale = true;
                    if s.is_done() {
                        self.mesh = Some(Arc::new(s.clone().finish()?));
                    }
                    return Ok(true);
                }
                // A face whose front was emptied by a redo: the stepper
                // has started the next one.
                StepOutcome::Done => {
                    self.shown_stale = true;
                    if s.is_done() {
                        self.mesh = Some(Arc::new(s.clone().finish()?));
                        return Ok(false);
                    }
                }
            }
        }
    }

    /// Takes the stepper a background run left (and its last report).
    pub fn take_run(&mut self, stepper: RegionStepper, steps: usize, last: Option<StepReport>) {
        self.stepper = Some(stepper);
        self.steps += steps;
        if last.is_some() {
            self.last = last;
        }
        self.shown_stale = true;
    }

    /// Undoes the last step of the current face; false when it has none
    /// (undo does not go back into a finished face).
    pub fn undo_step(&mut self) -> bool {
        if self.mesh.is_some() {
            return false;
        }
        let Some(s) = self.stepper.as_mut() else {
            return false;
        };
        if !s.mesher_mut().undo() {
            return false;
        }
        self.steps -= 1;
        self.last = None;
        self.shown_stale = true;
        true
    }

    /// Takes the last undone step of the current face again.
    pub fn redo_step(&mut self) -> Result<bool, EditorError> {
        let Some(s) = self.stepper.as_mut() else {
            return Ok(false);
        };
        if s.is_done() {
            return Ok(false);
        }
        let r = s.mesher_mut().redo()?;
        let Some(r) = r else { return Ok(false) };
        self.last = Some(r);
        self.steps += 1;
        self.shown_stale = true;
        if s.mesher().is_done() {
            s.next_face()?;
            if s.is_done() {
                self.mesh = Some(Arc::new(s.clone().finish()?));
            }
        }
        Ok(true)
    }

    /// Builds the mesh shown when steps changed it.
    pub fn sync_shown(&mut self) {
        if !std::mem::take(&mut self.shown_stale) {
            return;
        }
        let Some(s) = &self.stepper else {
            self.shown = Arc::new(QuadMesh::default());
            return;
        };
        let mut m = QuadMesh::default();
        for f in s.finished() {
            append(&mut m, f, Point::new(0.0, 0.0));
        }
        if !s.is_done() {
            append(&mut m, s.mesher().mesh(), s.origin());
        }
        self.shown = Arc::new(m);
    }

    /// The mesh the canvas shows: every face's once all are meshed, else
    /// the faces meshed so far.
    pub fn shown_mesh(&self) -> &QuadMesh {
        match &self.mesh {
            Some(m) => &m.mesh,
            None => &self.shown,
        }
    }

    /// Front nodes left in the current face.
    pub fn front_left(&self) -> usize {
        match &self.stepper {
            Some(s) if !s.is_done() => s.mesher().front().len(),
            _ => 0,
        }
    }

    pub fn no_graph(&self) -> EditorError {
        EditorError::NoGraph(self.problem.clone().unwrap_or(PslgError::Empty))
    }

    /// The face that holds `p` (inside its outer loop, outside its holes).
    pub fn face_at(&self, p: Point) -> Option<usize> {
        self.faces.iter().position(|f| face_contains(f, p))
    }
}

/// Appends `part` (moved by `by`) to `m`.
fn append(m: &mut QuadMesh, part: &QuadMesh, by: Point) {
    let off = m.nodes.len() as u32;
    m.nodes.extend(part.nodes.iter().map(|&p| p + by));
    m.quads
        .extend(part.quads.iter().map(|q| q.map(|v| v + off)));
    m.loops.extend(
        part.loops
            .iter()
            .map(|l| l.iter().map(|&v| v + off).collect::<Vec<u32>>()),
    );
}

/// True when `p` is inside face `f`.
pub fn face_contains(f: &Face, p: Point) -> bool {
    let b = &f.boundary;
    let poly = |k: usize| -> Vec<Point> { b.loops[k].iter().map(|&i| b.points[i]).collect() };
    !b.loops.is_empty()
        && point_in_polygon(p, &poly(0))
        && (1..b.loops.len()).all(|k| !point_in_polygon(p, &poly(k)))
}

/// The regions of the faces as the mesh numbers them (the attributes in
/// order, then the faces without one), and each face's index among them.
fn legend_of(g: &Pslg, faces: &[Face]) -> (Vec<(i64, String)>, Vec<usize>) {
    let mut attrs: Vec<i64> = faces.iter().map(|f| f.attribute).collect();
    attrs.sort_unstable();
    attrs.dedup();
    let top = attrs.iter().copied().max().unwrap_or(0);
    let mut legend: Vec<(i64, String)> = attrs
        .iter()
        .filter(|&&a| a != 0)
        .map(|&a| (a, g.region_name(a)))
        .collect();
    if attrs.contains(&0) {
        let name = if top == 0 {
            g.region_names
                .get(&0)
                .cloned()
                .unwrap_or_else(|| "domain".into())
        } else {
            "unassigned".into()
        };
        legend.push((top + 1, name));
    }
    let index = |a: i64| {
        if a == 0 {
            legend.len() - 1
        } else {
            attrs
                .iter()
                .filter(|&&x| x != 0)
                .position(|&x| x == a)
                .unwrap_or(0)
        }
    };
    let face_region = faces.iter().map(|f| index(f.attribute)).collect();
    (legend, face_region)
}

/// The colour of region `k` of the legend.
pub fn region_color(k: usize) -> Color32 {
    const PALETTE: [(u8, u8, u8); 10] = [
        (230, 120, 60),
        (80, 160, 230),
        (120, 200, 90),
        (200, 90, 200),
        (240, 200, 60),
        (70, 200, 190),
        (230, 80, 110),
        (150, 130, 230),
        (170, 170, 170),
        (140, 100, 60),
    ];
    let (r, g, b) = PALETTE[k % PALETTE.len()];
    Color32::from_rgb(r, g, b)
}

/// The colour of the group of tag `tag` (an index among the groups).
pub fn group_color(k: usize) -> Color32 {
    const PALETTE: [(u8, u8, u8); 6] = [
        (255, 90, 90),
        (90, 255, 140),
        (255, 230, 80),
        (90, 200, 255),
        (255, 140, 255),
        (255, 170, 60),
    ];
    let (r, g, b) = PALETTE[k % PALETTE.len()];
    Color32::from_rgb(r, g, b)
}

/// The groups of a graph: (tag, name, segment indices), by tag.
pub fn groups_of(g: &Pslg) -> Vec<(i64, String, Vec<usize>)> {
    let mut by: std::collections::BTreeMap<i64, Vec<usize>> = Default::default();
    for (k, s) in g.segments.iter().enumerate() {
        if s.marker != 0 {
            by.entry(s.marker).or_default().push(k);
        }
    }
    by.into_iter()
        .map(|(t, segs)| (t, g.group_name(t), segs))
        .collect()
}

/// The median segment length of a graph.
fn median_segment(g: &Pslg) -> f64 {
    let mut lens: Vec<f64> = g
        .segments
        .iter()
        .map(|s| g.points[s.a].distance(g.points[s.b]))
        .filter(|l| *l > 0.0)
        .collect();
    lens.sort_by(f64::total_cmp);
    lens.get(lens.len() / 2).copied().unwrap_or(1.0)
}

/// The graph with an interface curve from node `from` through `through`
/// to node `to`: each leg of the curve is divided into pieces about as
/// long as the graph's median segment, and when that leaves the faces it
/// splits with an odd node count, the longest leg takes one piece more
/// (both faces of a split have the same parity, so one node fixes both).
pub fn with_interface(
    g: &Pslg,
    from: usize,
    through: &[Point],
    to: usize,
) -> Result<Pslg, EditorError> {
    if from >= g.points.len() || to >= g.points.len() {
        return Err(EditorError::RegionEdit(
            "the curve must start and end on nodes of the graph".into(),
        ));
    }
    if from == to && through.is_empty() {
        return Err(EditorError::RegionEdit(
            "the curve ends where it starts: end it on another node".into(),
        ));
    }
    let mut corners = vec![g.points[from]];
    corners.extend_from_slice(through);
    corners.push(g.points[to]);
    let h = median_segment(g);
    let lens: Vec<f64> = corners.windows(2).map(|w| w[0].distance(w[1])).collect();
    let mut parts: Vec<usize> = lens
        .iter()
        .map(|&l| ((l / h).round() as usize).max(1))
        .collect();
    let build = |parts: &[usize]| -> Pslg {
        let mut out = g.clone();
        let next_label = g.labels.iter().copied().max().unwrap_or(0) + 1;
        let mut chain = vec![from];
        for (k, w) in corners.windows(2).enumerate() {
            let n = parts[k];
            for j in 1..=n {
                if k == corners.len() - 2 && j == n {
                    break;
                }
                let t = j as f64 / n as f64;
                out.points.push(w[0] + (w[1] - w[0]) * t);
                out.labels
                    .push(next_label + (out.points.len() - g.points.len()) as i64 - 1);
                chain.push(out.points.len() - 1);
            }
        }
        chain.push(to);
        for w in chain.windows(2) {
            out.segments.push(Segment {
                a: w[0],
                b: w[1],
                marker: 0,
            });
        }
        out
    };
    let first = build(&parts);
    if let Err(PslgError::OddRegion { .. }) = first.faces() {
        let longest = (0..lens.len())
            .max_by(|&a, &b| (lens[a] / parts[a] as f64).total_cmp(&(lens[b] / parts[b] as f64)))
            .unwrap_or(0);
        parts[longest] += 1;
        return Ok(build(&parts));
    }
    Ok(first)
}

/// The tag for `name` among `names`: the one it has, else `want` (when
/// given), else one more than any tag in use.
fn tag_for(
    names: &std::collections::BTreeMap<i64, String>,
    used: impl Iterator<Item = i64>,
    name: &str,
    want: i64,
) -> i64 {
    if want > 0 {
        return want;
    }
    if let Some((&t, _)) = names.iter().find(|(_, n)| n.as_str() == name) {
        return t;
    }
    used.chain(names.keys().copied()).max().unwrap_or(0).max(0) + 1
}

/// The graph with segments `segments` in the group `name` (tag `tag`, or
/// the group's own, or a new one when 0); an empty name takes them out of
/// their groups.
pub fn with_group(g: &Pslg, segments: &[usize], name: &str, tag: i64) -> Result<Pslg, EditorError> {
    if segments.is_empty() {
        return Err(EditorError::RegionEdit(
            "pick segments first (click one, shift-click to add more)".into(),
        ));
    }
    let mut out = g.clone();
    let name = name.trim();
    let tag = if name.is_empty() {
        0
    } else {
        let t = tag_for(
            &g.group_names,
            g.segments.iter().map(|s| s.marker),
            name,
            tag,
        );
        out.group_names.insert(t, name.to_string());
        t
    };
    for &k in segments {
        let s = out
            .segments
            .get_mut(k)
            .ok_or_else(|| EditorError::RegionEdit(format!("no segment {k}")))?;
        s.marker = tag;
    }
    Ok(out)
}

/// A point well inside face `f` (the centroid of its largest triangle).
fn inside_point(f: &Face) -> Option<Point> {
    let tris = super::canvas::domain_triangles(&f.boundary);
    let area = |t: &[Point; 3]| ((t[1] - t[0]).perp_dot(t[2] - t[0])).abs();
    tris.iter()
        .max_by(|a, b| area(a).total_cmp(&area(b)))
        .map(|t| (t[0] + t[1] + t[2]) / 3.0)
}

/// The graph with the face that holds `at` in the region `name` (tag
/// `tag`, or the region's own, or a new one when 0): the region points in
/// that face give way to one at `at`. The first region point of a graph
/// would make the faces inside holes faces to mesh: they get hole points
/// so that they stay holes.
pub fn with_region(g: &Pslg, at: Point, name: &str, tag: i64) -> Result<Pslg, EditorError> {
    let name = name.trim();
    if name.is_empty() {
        return Err(EditorError::RegionEdit("give the region a name".into()));
    }
    let faces = g.faces().map_err(EditorError::NoGraph)?;
    let face = faces
        .iter()
        .find(|f| face_contains(f, at))
        .ok_or_else(|| EditorError::RegionEdit("click inside a face first".into()))?;
    let mut out = g.clone();
    let t = tag_for(
        &g.region_names,
        g.regions.iter().map(|r| r.attribute),
        name,
        tag,
    );
    out.region_names.insert(t, name.to_string());
    out.regions.retain(|r| !face_contains(face, r.at));
    out.regions.push(RegionPoint {
        at,
        attribute: t,
        max_area: None,
    });
    if g.regions.is_empty() {
        let before: Vec<Vec<usize>> = faces.iter().map(|f| sorted(&f.nodes)).collect();
        if let Ok(after) = out.faces() {
            for f in after {
                if !before.contains(&sorted(&f.nodes)) {
                    if let Some(p) = inside_point(&f) {
                        out.holes.push(p);
                    }
                }
            }
        }
    }
    Ok(out)
}

fn sorted(v: &[usize]) -> Vec<usize> {
    let mut v = v.to_vec();
    v.sort_unstable();
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square, n nodes a side, as a graph.
    fn square(n: usize) -> Pslg {
        Pslg::from_boundary(&crate::Boundary::unit_square(n))
    }

    #[test]
    fn an_interface_splits_a_face_in_two_even_faces() {
        let g = square(4);
        // From (0.5, 0) to (0.5, 1): nodes 2 and 10.
        let out = with_interface(&g, 2, &[], 10).unwrap();
        let faces = out.faces().unwrap();
        assert_eq!(faces.len(), 2);
        assert!(faces.iter().all(|f| f.boundary.node_count() % 2 == 0));
        // From (0.25, 0) to (0.5, 1): the count is made even.
        let out = with_interface(&g, 1, &[Point::new(0.3, 0.5)], 10).unwrap();
        assert_eq!(out.faces().unwrap().len(), 2);
    }

    #[test]
    fn groups_and_regions_are_named() {
        let g = with_interface(&square(4), 2, &[], 10).unwrap();
        let g = with_group(&g, &[0, 1], "bottom", 0).unwrap();
        assert_eq!(g.segments[0].marker, 1);
        assert_eq!(g.group_name(1), "bottom");
        let g = with_region(&g, Point::new(0.25, 0.5), "copper", 0).unwrap();
        let g = with_region(&g, Point::new(0.75, 0.5), "steel", 7).unwrap();
        let g = with_region(&g, Point::new(0.2, 0.6), "copper", 0).unwrap();
        assert_eq!(g.regions.len(), 2);
        let mut attrs: Vec<i64> = g.faces().unwrap().iter().map(|f| f.attribute).collect();
        attrs.sort_unstable();
        assert_eq!(attrs, [1, 7]);
        assert_eq!(g.region_name(7), "steel");
    }
}

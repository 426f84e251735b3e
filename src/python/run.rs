//! Meshing for the Python module, without Python: the options of
//! `quadex mesh` as one struct, a source (a file or loops of points), and
//! the finished mesh with its regions and groups as flat arrays. Errors are
//! the command line's one-line messages (`FILE: problem`).

use crate::boundary::Boundary;
use crate::boundary_edit::Draft;
use crate::extract::{MeshParams, StepStats, Strategy, Tuning};
use crate::finish::remesh::RemeshParams;
use crate::geom::Point;
use crate::model::{self, Model};
use crate::order2::Order2;
use crate::pipeline::{self, FinishParams, Params};
use crate::quality::MeshQuality;
use crate::regions::RegionMesh;
use crate::smooth::SmoothParams;
use std::path::PathBuf;
use std::sync::Arc;

/// What is meshed: a boundary or drawing file, or loops of points (the
/// outer loop and holes, as a boundary file's loops).
#[derive(Clone, Debug)]
pub enum Source {
    File(PathBuf),
    Loops(Vec<Vec<Point>>),
}

impl Source {
    /// The name an error message starts with: the file, or `loops`.
    pub fn label(&self) -> String {
        match self {
            Source::File(p) => p.display().to_string(),
            Source::Loops(_) => "loops".to_string(),
        }
    }
}

/// The options of `quadex mesh`, with its defaults ([`Options::DEFAULT`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Target size of a drawing (`--size`).
    pub size: Option<f64>,
    /// Element order, 1 or 2 (`--order`).
    pub order: u8,
    /// 8-node quads at order 2 (`--serendipity`).
    pub serendipity: bool,
    /// `default`, `rules`, `thesis`, `ann` or a model file (`--model`).
    pub model: String,
    /// `a` or `b` (`--strategy`).
    pub strategy: String,
    /// Input points 5, 7, 9 or 11 (`--points`; default the model's own,
    /// else 7).
    pub points: Option<usize>,
    /// Laplacian smoothing sweeps, 0 for none (`--smooth`).
    pub smooth: usize,
    /// Topological cleanup (off: `--no-cleanup`).
    pub cleanup: bool,
    /// Chord coarsening (off: `--no-coarsen`).
    pub coarsen: bool,
    /// `--remesh-below`, a scaled Jacobian in [0, 1].
    pub remesh_below: f64,
    /// `--pure-model`.
    pub pure_model: bool,
    /// The region fill as the last resort (off: `--no-fill`).
    pub fill: bool,
    /// `--layers K` (`None`: all).
    pub layers: Option<u32>,
    /// `--transitions R` (`None`: off).
    pub transitions: Option<f64>,
    /// `--mapped-rows N` (`None`: off).
    pub mapped_rows: Option<usize>,
    /// `--resample H`.
    pub resample: Option<f64>,
    /// `--size-at X,Y,H`, repeated.
    pub size_at: Vec<(f64, f64, f64)>,
    /// `--size-on LAYER=H`, repeated.
    pub size_on: Vec<(String, f64)>,
    /// `--gradation G`.
    pub gradation: Option<f64>,
    /// `--threads N` (regions meshed in parallel; the mesh is the same).
    pub threads: Option<usize>,
    /// `--tuning FILE`: the extraction engine's constants.
    pub tuning: Tuning,
}

impl Options {
    pub const DEFAULT: Options = Options {
        size: None,
        order: 1,
        serendipity: false,
        model: String::new(),
        strategy: String::new(),
        points: None,
        smooth: SmoothParams::DEFAULT.iterations,
        cleanup: true,
        coarsen: true,
        remesh_below: RemeshParams::DEFAULT.below,
        pure_model: false,
        fill: true,
        layers: None,
        transitions: MeshParams::DEFAULT.transition_ratio,
        mapped_rows: MeshParams::DEFAULT.mapped_rows,
        resample: None,
        size_at: Vec::new(),
        size_on: Vec::new(),
        gradation: None,
        threads: None,
        tuning: Tuning::DEFAULT,
    };

    /// Checks the values the command line's parser checks, with its
    /// messages.
    pub fn check(&self) -> Result<(), String> {
        if !(1..=2).contains(&self.order) {
            return Err(format!("order {}: the element order is 1 or 2", self.order));
        }
        if self.serendipity && self.order != 2 {
            return Err("serendipity asks for 8-node quads: add order=2".into());
        }
        if let Some(n) = self.points {
            if ![5, 7, 9, 11].contains(&n) {
                return Err("input points must be 5, 7, 9 or 11".into());
            }
        }
        if !(0.0..=1.0).contains(&self.remesh_below) {
            return Err(format!(
                "`{}` is not a scaled Jacobian from 0 (no remeshing) to 1",
                self.remesh_below
            ));
        }
        if self.layers == Some(0) {
            return Err("`0` is not a layer count (1 or more) or `all`".into());
        }
        if let Some(r) = self.transitions {
            if !(r > 1.0 && r.is_finite()) {
                return Err(format!("`{r}` is not a ratio above 1 or `off`"));
            }
        }
        if self.mapped_rows == Some(0) {
            return Err("`0` is not a count of at least 1 or `off`".into());
        }
        if !matches!(self.strategy.as_str(), "a" | "b" | "A" | "B") {
            return Err(format!("strategy `{}`: a or b", self.strategy));
        }
        for &(x, y, h) in &self.size_at {
            if !(x.is_finite() && y.is_finite() && h.is_finite() && h > 0.0) {
                return Err("a point size is X,Y,H with H a positive number".into());
            }
        }
        for (_, h) in &self.size_on {
            if !(h.is_finite() && *h > 0.0) {
                return Err("a layer size is LAYER=H with H a positive number".into());
            }
        }
        if self.threads == Some(0) {
            return Err("threads: at least 1".into());
        }
        Ok(())
    }

    /// Extraction and finishing parameters, as `quadex mesh` sets them for
    /// `model` (whose own input-point count wins over the default 7).
    pub fn params(&self, model: &dyn Model) -> Result<Params, String> {
        let own = model.leading_points().map(|n| 2 * n + 1);
        if let (Some(asked), Some(own)) = (self.points, own) {
            if asked != own {
                return Err(format!(
                    "{}: the model takes {own} input points, not the {asked} of points",
                    self.model
                ));
            }
        }
        let points = self.points.or(own).unwrap_or(7);
        let extract = MeshParams {
            strategy: match self.strategy.as_str() {
                "a" | "A" => Strategy::A,
                _ => Strategy::B,
            },
            leading_points: (points - 1) / 2,
            pure_model: self.pure_model,
            fill: self.fill,
            fill_after_layers: self.layers,
            transition_ratio: self.transitions,
            mapped_rows: self.mapped_rows,
            tuning: self.tuning.clone(),
            ..MeshParams::DEFAULT
        };
        let finish =
            FinishParams::switched(self.smooth, self.cleanup, self.coarsen, self.remesh_below);
        Ok(Params { extract, finish })
    }
}

/// A model by name or file, with the command line's message.
pub fn load_model(spec: &str) -> Result<Arc<dyn Model>, String> {
    model::load(spec)
        .map(Arc::from)
        .map_err(|e| format!("{spec}: {e}"))
}

/// One boundary from a source, resampled to `resample` when given (every
/// loop, as `quadex mesh --resample` does). A file with regions, boundary
/// markers or curves is refused: it is more than one boundary.
pub fn read_boundary(src: &Source, resample: Option<f64>) -> Result<Boundary, String> {
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", src.label());
    let loops = match src {
        Source::File(path) => {
            if is_geometry(path) {
                return Err(at(
                    &"a drawing is meshed whole: use quadex.mesh(path, size=H)",
                ));
            }
            if crate::io::read_regions(path).map_err(|e| at(&e))?.is_some() {
                return Err(at(
                    &"the step API meshes one boundary: this file has regions or boundary markers; use quadex.mesh",
                ));
            }
            if resample.is_none() {
                return crate::io::read_boundary(path).map_err(|e| at(&e));
            }
            crate::io::read_boundary_loops(path).map_err(|e| at(&e))?
        }
        Source::Loops(loops) => loops.clone(),
    };
    let mut draft = Draft { loops };
    if let Some(h) = resample {
        for li in 0..draft.loops.len() {
            draft.resample(li, h).map_err(|e| at(&e))?;
        }
    }
    draft.to_boundary().map_err(|e| at(&e))
}

/// True for a drawing: `.dxf`, or a geometry `.json`.
fn is_geometry(path: &std::path::Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("dxf"))
        || crate::cad::is_geometry_file(path)
}

/// A finished mesh as flat arrays: what `quadex.mesh` turns into a
/// `meshio.Mesh`.
#[derive(Clone, Debug)]
pub struct Output {
    /// x, y of every node written (second-order nodes after the corners).
    pub points: Vec<f64>,
    /// meshio's name of the elements: `quad`, `quad8` or `quad9`.
    pub cell_type: &'static str,
    /// The elements' nodes, `nodes_per_cell` each.
    pub cells: Vec<u32>,
    pub nodes_per_cell: usize,
    /// The region (index into `regions`) of each element.
    pub cell_region: Vec<u32>,
    /// Regions as (tag, name).
    pub regions: Vec<(i64, String)>,
    /// Groups as (tag, name, line nodes: 2 or 3 per line).
    pub groups: Vec<(i64, String, Vec<u32>)>,
    /// meshio's name of the group lines: `line` or `line3`.
    pub line_type: &'static str,
    pub quality: MeshQuality,
    pub steps: StepStats,
}

impl Output {
    /// The arrays of `m` (at second order, of `o2`'s elements).
    pub fn of(m: &RegionMesh, o2: Option<&Order2>) -> Output {
        let l = m.labelled_with(o2);
        let points: Vec<f64> = match o2 {
            Some(o) => o.written_nodes(),
            None => &m.mesh.nodes[..],
        }
        .iter()
        .flat_map(|p| [p.x, p.y])
        .collect();
        let mut cells = Vec::new();
        for k in 0..m.mesh.quads.len() {
            match o2 {
                Some(o) => cells.extend_from_slice(o.element(k)),
                None => cells.extend_from_slice(&m.mesh.quads[k]),
            }
        }
        let nodes_per_cell = o2.map_or(4, |o| o.element(0).len());
        let cell_type = match nodes_per_cell {
            8 => "quad8",
            9 => "quad9",
            _ => "quad",
        };
        let groups = l
            .groups
            .iter()
            .map(|g| {
                let mut nodes = Vec::new();
                for e in g.edges {
                    nodes.extend_from_slice(e);
                    if let Some(mid) = o2.and_then(|o| o.mid(e[0], e[1])) {
                        nodes.push(mid);
                    }
                }
                (g.tag, g.name.to_string(), nodes)
            })
            .collect();
        Output {
            points,
            cell_type,
            cells,
            nodes_per_cell,
            cell_region: m.quad_region.clone(),
            regions: l
                .regions
                .iter()
                .map(|r| (r.tag, r.name.to_string()))
                .collect(),
            groups,
            line_type: if o2.is_some() { "line3" } else { "line" },
            quality: m.quality(),
            steps: m.steps(),
        }
    }
}

/// Meshes `src` as `quadex mesh` does with `o`'s options, and gives the
/// mesh as arrays instead of writing a file.
pub fn mesh(src: &Source, o: &Options) -> Result<Output, String> {
    o.check()?;
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", src.label());
    let mut drawing = None;
    let graph = match src {
        Source::File(path) if is_geometry(path) => {
            let is_dxf = path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("dxf"));
            let doc = if is_dxf {
                crate::cad::CadDocument {
                    geometry: crate::cad::read_dxf(path).map_err(|e| at(&e))?,
                    ..Default::default()
                }
            } else {
                crate::cad::read_geometry_json(path).map_err(|e| at(&e))?
            };
            let points: Vec<crate::cad::PointSize> = o
                .size_at
                .iter()
                .map(|&(x, y, h)| crate::cad::PointSize {
                    at: Point::new(x, y),
                    size: h,
                })
                .collect();
            let Some(spec) = doc.spec(o.size, o.gradation, &points, &o.size_on) else {
                return Err(at(&"a drawing needs a target size: add size=H"));
            };
            let layers = doc.geometry.layers();
            if let Some((l, _)) = spec.layers.iter().find(|(l, _)| !layers.contains(l)) {
                return Err(at(&format!(
                    "no curve is on layer {l:?} (the layers are {layers:?})"
                )));
            }
            let d = doc.geometry.discretise_with(&spec).map_err(|e| at(&e))?;
            let graph = d.graph.clone();
            drawing = Some(d);
            Some(graph)
        }
        _ => {
            if o.size.is_some()
                || !o.size_at.is_empty()
                || !o.size_on.is_empty()
                || o.gradation.is_some()
            {
                return Err(at(
                    &"size, size_at, size_on and gradation apply to drawings (.dxf, geometry .json); for boundary nodes use resample=H",
                ));
            }
            match src {
                Source::File(path) => crate::io::read_regions(path).map_err(|e| at(&e))?,
                Source::Loops(_) => None,
            }
        }
    };
    if graph.is_some() && o.resample.is_some() {
        return Err(at(
            &"resample does not apply to a file with regions or boundary markers yet: place its nodes in the file",
        ));
    }
    let model = load_model(&o.model)?;
    let mut params = o.params(model.as_ref())?;
    params.extract.size_target = drawing.as_ref().map(|d| d.size_target());
    let m = match &graph {
        Some(graph) => {
            let mut pool = rayon::ThreadPoolBuilder::new();
            if let Some(n) = o.threads {
                pool = pool.num_threads(n);
            }
            let pool = pool.build().map_err(|e| e.to_string())?;
            pool.install(|| crate::regions::mesh_regions(graph, model, &params, |_| {}))
                .map_err(|e| at(&e))?
        }
        None => {
            let boundary = read_boundary(src, o.resample)?;
            let (mesh, stats) =
                pipeline::mesh_boundary(&boundary, model, &params, |_| {}).map_err(|e| at(&e))?;
            RegionMesh::single(mesh, stats)
        }
    };
    if o.order == 2 {
        let nodes = &m.mesh.nodes;
        let curved = |u: u32, v: u32| {
            drawing
                .as_ref()
                .and_then(|d| d.midside(nodes[u as usize], nodes[v as usize]))
        };
        let mut o2 = Order2::elevate(&m.mesh, &curved);
        if o.serendipity {
            o2 = o2.serendipity();
        }
        Ok(Output::of(&m, Some(&o2)))
    } else {
        Ok(Output::of(&m, None))
    }
}

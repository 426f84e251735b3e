//! The reference meshes the shipped model learns from (thesis §3.1.2:
//! samples come from good meshes of varied character). Each is built by the
//! project itself: by mapped meshing ([`crate::mapped`]), or, for the
//! generated domain [`GENERATED`] (a plate with holes from
//! [`crate::domains`], not a benchmark case), recorded from quadex's own
//! extraction with the rules model (kept as data so that the shipped model
//! does not change with the extraction engine; [`record_generated`] makes
//! it again). Each is checked by [`QuadMesh::check_invariants`]. `cargo run
//! --example reference_meshes` writes them to `assets/reference/` and the
//! tests check that the shipped files are what the generator makes. No
//! benchmark case (`tests/data`) is among them.

use crate::domains::{generate, Family};
use crate::fit::{refit, FitError, FitParams};
use crate::geom::Point;
use crate::io::msh::read_msh;
use crate::mapped::{graded, map_grid, merge, Block};
use crate::mesh::{InvariantError, QuadMesh};
use crate::model::{Form, ModelFile};
use crate::samples::{CollectParams, TrainingSet};
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use thiserror::Error;

/// The generated domain whose extraction is a reference mesh: a plate
/// with holes, `domains::generate(Family::ManyHoles, seed)` (the 8th domain
/// of `domains::suite(14, 101)`). Chosen among non-benchmark candidates by
/// the benchmark sweep (see `assets/README.md`).
pub const GENERATED: (Family, u64) = (Family::ManyHoles, 0x1900_5992_3ebc_ad1c);

/// The name of [`GENERATED`]'s reference mesh (its domain's name).
pub const GENERATED_NAME: &str = "holes_190059923ebcad1c";

/// Extraction's mesh of [`GENERATED`] with the rules model, as recorded.
const GENERATED_MESH: &str = include_str!("../assets/reference/holes_190059923ebcad1c.msh");

/// A reference mesh that could not be built.
#[derive(Debug, Error)]
pub enum ReferenceError {
    #[error("{name}: {source}")]
    Invariant {
        name: &'static str,
        source: InvariantError,
    },
    /// A boundary or mesh file that cannot be read.
    #[error("{name}: {msg}")]
    Boundary { name: &'static str, msg: String },
}

/// The names of the reference meshes, in order.
pub const NAMES: [&str; 7] = [
    "graded_rect",
    "curved_quad",
    "skewed_quad",
    "ogrid_disk",
    "annulus_sector",
    "lshape",
    GENERATED_NAME,
];

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

fn rotate(q: Point, a: f64) -> Point {
    let (s, c) = a.sin_cos();
    p(c * q.x - s * q.y, s * q.x + c * q.y)
}

/// A 6 × 3 rectangle graded in both directions (30 × 15 cells).
fn graded_rect() -> Vec<[Point; 4]> {
    Block::straight(p(0.0, 0.0), p(6.0, 0.0), p(6.0, 3.0), p(0.0, 3.0))
        .grid(&graded(30, 1.05), &graded(15, 1.04))
}

/// A four-sided patch with wavy sides (16 × 16 cells).
fn curved_quad() -> Vec<[Point; 4]> {
    let b = Block {
        bottom: Box::new(|u| p(4.0 * u, -0.4 * (PI * u).sin())),
        top: Box::new(|u| p(4.0 * u, 4.0 + 0.3 * (TAU * u).sin())),
        left: Box::new(|v| p(0.3 * (PI * v).sin(), 4.0 * v)),
        right: Box::new(|v| p(4.0 + 0.4 * (PI * v).sin(), 4.0 * v)),
    };
    b.grid(&graded(16, 1.0), &graded(16, 1.0))
}

/// A skewed quadrilateral with slanted sides (14 × 10 cells).
fn skewed_quad() -> Vec<[Point; 4]> {
    Block::straight(p(0.0, 0.0), p(5.0, 0.0), p(6.5, 3.0), p(1.0, 3.5))
        .grid(&graded(14, 1.0), &graded(10, 1.0))
}

/// A unit disk as an O-grid: a central block with bulged sides and four
/// blocks out to the circle (10 × 10 centre, 10 × 6 in each ring block).
fn ogrid_disk() -> Vec<[Point; 4]> {
    const A: f64 = 0.4;
    const B: f64 = 0.06;
    let centre = Block {
        bottom: Box::new(|u| p(-A + 2.0 * A * u, -A - B * (PI * u).sin())),
        top: Box::new(|u| p(-A + 2.0 * A * u, A + B * (PI * u).sin())),
        left: Box::new(|v| p(-A - B * (PI * v).sin(), -A + 2.0 * A * v)),
        right: Box::new(|v| p(A + B * (PI * v).sin(), -A + 2.0 * A * v)),
    };
    let mut quads = centre.grid(&graded(10, 1.0), &graded(10, 1.0));
    let q = FRAC_PI_2 / 2.0;
    for k in 0..4 {
        let a = FRAC_PI_2 * k as f64;
        // East block rotated by a: u from the centre block out to the arc.
        let ring = Block {
            bottom: Box::new(move |u| rotate(p(A, -A).lerp(p(q.cos(), -q.sin()), u), a)),
            top: Box::new(move |u| rotate(p(A, A).lerp(p(q.cos(), q.sin()), u), a)),
            left: Box::new(move |v| rotate(p(A + B * (PI * v).sin(), -A + 2.0 * A * v), a)),
            right: Box::new(move |v| {
                let t = -q + 2.0 * q * v;
                rotate(p(t.cos(), t.sin()), a)
            }),
        };
        quads.extend(ring.grid(&graded(6, 0.9), &graded(10, 1.0)));
    }
    quads
}

/// A 120° annulus sector meshed in polar coordinates with geometric radial
/// steps, so every cell is nearly square (24 × 11 cells).
fn annulus_sector() -> Vec<[Point; 4]> {
    let cells = 24;
    let dtheta = (TAU / 3.0) / cells as f64;
    let q = dtheta.exp();
    let layers = 11;
    let outer = q.powi(layers);
    map_grid(&graded(layers as usize, q), &graded(cells, 1.0), |u, v| {
        let r = 1.0 + (outer - 1.0) * u;
        let t = (TAU / 3.0) * v;
        p(r * t.cos(), r * t.sin())
    })
}

/// An L-shape of three blocks, the arms graded away from the corner block.
fn lshape() -> Vec<[Point; 4]> {
    let n = 8;
    let mut quads = Block::straight(p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0))
        .grid(&graded(n, 1.0), &graded(n, 1.0));
    quads.extend(
        Block::straight(p(1.0, 0.0), p(2.5, 0.0), p(2.5, 1.0), p(1.0, 1.0))
            .grid(&graded(10, 1.06), &graded(n, 1.0)),
    );
    quads.extend(
        Block::straight(p(0.0, 1.0), p(1.0, 1.0), p(1.0, 2.5), p(0.0, 2.5))
            .grid(&graded(n, 1.0), &graded(10, 1.06)),
    );
    quads
}

/// Builds one reference mesh by name.
pub fn build(name: &'static str) -> Result<QuadMesh, ReferenceError> {
    let quads = match name {
        "graded_rect" => graded_rect(),
        "curved_quad" => curved_quad(),
        "skewed_quad" => skewed_quad(),
        "ogrid_disk" => ogrid_disk(),
        "annulus_sector" => annulus_sector(),
        "lshape" => lshape(),
        GENERATED_NAME => {
            // A recorded extraction of the generated domain with the rules
            // model, kept as data: the shipped model must not move each
            // time the extraction engine changes.
            let m = read_msh(GENERATED_MESH).map_err(|e| ReferenceError::Boundary {
                name,
                msg: e.to_string(),
            })?;
            m.check_finished()
                .map_err(|source| ReferenceError::Invariant { name, source })?;
            return Ok(m);
        }
        _ => {
            return Err(ReferenceError::Boundary {
                name,
                msg: "no such reference mesh".into(),
            })
        }
    };
    let m = merge(&quads, 1e-9).map_err(|source| ReferenceError::Invariant { name, source })?;
    m.check_finished()
        .map_err(|source| ReferenceError::Invariant { name, source })?;
    Ok(m)
}

/// The input points of the shipped default model.
pub const DEFAULT_MODEL_POINTS: usize = 7;
/// The form of the shipped default model.
pub const DEFAULT_MODEL_FORM: Form = Form::Quadratic;
/// The window of interior angles along the sample paths of the shipped
/// default model, in degrees. Wider than the thesis's [35, 235] (method
/// §3): the fronts the mesher meets have reflex turns next to the
/// reference point, and a model that never saw one extrapolates badly
/// there (see the README).
pub const DEFAULT_MODEL_TURN: [f64; 2] = [35.0, 300.0];

/// The folder the reference meshes ship in (the generator writes there;
/// the binary carries them, see [`SHIPPED`]).
pub fn shipped_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/reference")
}

/// The shipped reference meshes as built into the binary, `(name, MSH
/// text)` in the order of [`NAMES`]: an installed `quadex` (the editor's
/// refit) needs no files beside it.
pub const SHIPPED: [(&str, &str); 7] = [
    (
        "graded_rect",
        include_str!("../assets/reference/graded_rect.msh"),
    ),
    (
        "curved_quad",
        include_str!("../assets/reference/curved_quad.msh"),
    ),
    (
        "skewed_quad",
        include_str!("../assets/reference/skewed_quad.msh"),
    ),
    (
        "ogrid_disk",
        include_str!("../assets/reference/ogrid_disk.msh"),
    ),
    (
        "annulus_sector",
        include_str!("../assets/reference/annulus_sector.msh"),
    ),
    ("lshape", include_str!("../assets/reference/lshape.msh")),
    (GENERATED_NAME, GENERATED_MESH),
];

/// The shipped reference meshes as `(file name, mesh)` pairs, read from
/// the copies built into the binary ([`SHIPPED`], the files of
/// [`shipped_dir`] at build time) in the order of [`NAMES`].
pub fn read_shipped() -> Result<Vec<(String, QuadMesh)>, ReferenceError> {
    SHIPPED
        .iter()
        .map(|&(name, text)| {
            read_msh(text)
                .map(|m| (format!("{name}.msh"), m))
                .map_err(|e| ReferenceError::Boundary {
                    name,
                    msg: e.to_string(),
                })
        })
        .collect()
}

/// The training set of the shipped default model from the reference meshes
/// (as [`read_shipped`] gives them): their 7-point samples with
/// [`DEFAULT_MODEL_TURN`], duplicates dropped.
pub fn default_training_set(meshes: &[(String, QuadMesh)]) -> TrainingSet {
    training_set(meshes, DEFAULT_MODEL_POINTS)
}

/// The reference meshes' samples at `points` input points, collected as
/// for the shipped model (what the editor's refit fits on).
pub fn training_set(meshes: &[(String, QuadMesh)], points: usize) -> TrainingSet {
    let params = CollectParams {
        turn: DEFAULT_MODEL_TURN,
        ..CollectParams::DEFAULT
    };
    TrainingSet::collect(meshes, points, &params)
}

/// The shipped default model: [`default_training_set`] refitted with
/// nothing added ([`crate::fit::refit`], the editor's refit) in
/// [`DEFAULT_MODEL_FORM`] with `params` (the shipped file uses
/// [`FitParams::DEFAULT`]).
pub fn default_model(
    meshes: &[(String, QuadMesh)],
    params: &FitParams,
) -> Result<ModelFile, FitError> {
    let set = default_training_set(meshes);
    refit(
        &set,
        &TrainingSet::new(set.points),
        DEFAULT_MODEL_FORM,
        "default",
        params,
    )
}

/// The shipped network model (`--model ann`, the comparison system of
/// thesis §2.2.2): [`default_training_set`] fitted in the network form
/// ([`Form::Ann`]) with `params`, by the same refit as the default model.
pub fn ann_model(meshes: &[(String, QuadMesh)], params: &FitParams) -> Result<ModelFile, FitError> {
    let set = default_training_set(meshes);
    refit(
        &set,
        &TrainingSet::new(set.points),
        Form::Ann,
        "ann",
        params,
    )
}

/// [`GENERATED`]'s domain meshed now as its reference mesh was recorded:
/// extraction with the rules model at the default parameters, finished
/// ([`crate::pipeline::mesh_boundary`]), as read back from MSH 4.1. `cargo run --example
/// reference_meshes -- --record` writes it over the recorded file (which
/// changes the shipped models: rebuild them with `--example
/// default_model`).
pub fn record_generated() -> Result<QuadMesh, ReferenceError> {
    let name = GENERATED_NAME;
    let d = generate(GENERATED.0, GENERATED.1);
    debug_assert_eq!(d.name, name);
    let rules: std::sync::Arc<dyn crate::model::Model> =
        std::sync::Arc::new(crate::model::RulesModel::default());
    let failed = |msg: String| ReferenceError::Boundary { name, msg };
    let (m, _) =
        crate::pipeline::mesh_boundary(&d.boundary, rules, &crate::Params::DEFAULT, |_| {})
            .map_err(|e| failed(e.to_string()))?;
    // As read back from its file (the reader orders the hole loops its own
    // way), so that the recorded file is what [`build`] writes.
    read_msh(&crate::io::msh::write_msh41(&m)).map_err(|e| failed(e.to_string()))
}

/// Every reference mesh with its name.
pub fn all() -> Result<Vec<(&'static str, QuadMesh)>, ReferenceError> {
    NAMES.iter().map(|&n| build(n).map(|m| (n, m))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_meshes_are_the_shipped_files() {
        let names: Vec<&str> = SHIPPED.iter().map(|(n, _)| *n).collect();
        assert_eq!(names, NAMES);
        for (name, text) in SHIPPED {
            let file = std::fs::read_to_string(shipped_dir().join(format!("{name}.msh"))).unwrap();
            assert!(file == text, "{name}");
        }
    }
}

//! The Python module `quadex._quadex` (cargo feature `python`, built by
//! maturin; the package `quadex` in `python/` wraps it with numpy, meshio
//! and a learning environment, docs/python.md). Meshing runs without the
//! GIL; errors are `quadex.QuadexError` with the command line's one-line
//! messages, and a panic is caught and raised as one too.

pub mod run;
pub mod step;

use crate::geom::Point;
use crate::mesh::QuadMesh;
use crate::model::{ElementType, Prediction};
use pyo3::exceptions::{PyException, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use run::{Options, Source};
use std::panic::{catch_unwind, AssertUnwindSafe};
use step::{Stepper, Verdict};

pyo3::create_exception!(
    quadex,
    QuadexError,
    PyException,
    "Bad input or a mesh that cannot be made: the message is the command line's one line."
);

/// Runs `f`, its error or a panic raised as [`QuadexError`] (one line).
fn guarded<T>(f: impl FnOnce() -> Result<T, String>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(msg)) => Err(QuadexError::new_err(crate::io::one_line(&msg))),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown".into());
            Err(QuadexError::new_err(crate::io::one_line(&format!(
                "internal error (please report): {what}"
            ))))
        }
    }
}

/// The source: a path (str or os.PathLike) or a list of loops, each a list
/// of [x, y].
fn source(obj: &Bound<'_, PyAny>) -> PyResult<Source> {
    if let Ok(p) = obj.extract::<std::path::PathBuf>() {
        return Ok(Source::File(p));
    }
    match obj.extract::<Vec<Vec<[f64; 2]>>>() {
        Ok(loops) => Ok(Source::Loops(
            loops
                .into_iter()
                .map(|l| l.into_iter().map(|[x, y]| Point::new(x, y)).collect())
                .collect(),
        )),
        Err(_) => Err(PyTypeError::new_err(
            "source: a file path, or loops of points (the outer loop first, then the holes)",
        )),
    }
}

/// Options from keyword arguments, named as `quadex mesh`'s options
/// (`no_cleanup` as `cleanup=False`, `off` as `None`).
fn options(kwargs: Option<&Bound<'_, PyDict>>, drawing: bool) -> PyResult<Options> {
    let mut o = Options {
        model: "default".into(),
        strategy: "b".into(),
        ..Options::DEFAULT
    };
    let Some(kwargs) = kwargs else {
        return Ok(o);
    };
    for (k, v) in kwargs.iter() {
        let k: String = k.extract()?;
        let meshing_only = matches!(
            k.as_str(),
            "size" | "order" | "serendipity" | "size_at" | "size_on" | "gradation" | "threads"
        );
        if meshing_only && !drawing {
            return Err(PyTypeError::new_err(format!(
                "Mesher() takes no `{k}`: it applies to quadex.mesh"
            )));
        }
        match k.as_str() {
            "size" => o.size = v.extract()?,
            "order" => o.order = v.extract()?,
            "serendipity" => o.serendipity = v.extract()?,
            "model" => o.model = v.extract()?,
            "strategy" => o.strategy = v.extract()?,
            "points" => o.points = v.extract()?,
            "smooth" => o.smooth = v.extract()?,
            "cleanup" => o.cleanup = v.extract()?,
            "coarsen" => o.coarsen = v.extract()?,
            "remesh_below" => o.remesh_below = v.extract()?,
            "pure_model" => o.pure_model = v.extract()?,
            "fill" => o.fill = v.extract()?,
            "layers" => o.layers = v.extract()?,
            "transitions" => o.transitions = v.extract()?,
            "mapped_rows" => o.mapped_rows = v.extract()?,
            "resample" => o.resample = v.extract()?,
            "size_at" => o.size_at = v.extract()?,
            "size_on" => o.size_on = v.extract()?,
            "gradation" => o.gradation = v.extract()?,
            "threads" => o.threads = v.extract()?,
            "tuning" => {
                let text: String = v.extract()?;
                o.tuning = serde_json::from_str(&text)
                    .map_err(|e| QuadexError::new_err(format!("not a tuning: {e}")))?;
            }
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "unexpected keyword argument `{k}`"
                )))
            }
        }
    }
    Ok(o)
}

fn f64_bytes<'py>(py: Python<'py>, v: impl Iterator<Item = f64>) -> Bound<'py, PyBytes> {
    let b: Vec<u8> = v.flat_map(f64::to_le_bytes).collect();
    PyBytes::new(py, &b)
}

fn u32_bytes<'py>(py: Python<'py>, v: &[u32]) -> Bound<'py, PyBytes> {
    let b: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    PyBytes::new(py, &b)
}

fn json(v: &impl serde::Serialize) -> String {
    serde_json::to_string(v).unwrap_or_default()
}

/// Meshes a file or loops as `quadex mesh` does; returns the mesh as a
/// dict of little-endian arrays (the package makes a meshio.Mesh of it).
#[pyfunction]
#[pyo3(signature = (source, **kwargs))]
fn mesh<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let src = self::source(source)?;
    let o = options(kwargs, true)?;
    let out = py.detach(|| guarded(|| run::mesh(&src, &o)))?;
    let d = PyDict::new(py);
    d.set_item("points", f64_bytes(py, out.points.iter().copied()))?;
    d.set_item("cell_type", out.cell_type)?;
    d.set_item("nodes_per_cell", out.nodes_per_cell)?;
    d.set_item("cells", u32_bytes(py, &out.cells))?;
    d.set_item("cell_region", u32_bytes(py, &out.cell_region))?;
    d.set_item("regions", out.regions)?;
    let groups = PyList::empty(py);
    for (tag, name, nodes) in &out.groups {
        groups.append((tag, name, u32_bytes(py, nodes)))?;
    }
    d.set_item("groups", groups)?;
    d.set_item("line_type", out.line_type)?;
    d.set_item("quality", json(&out.quality))?;
    d.set_item("steps", json(&out.steps))?;
    Ok(d)
}

/// The figures of a mesh (`quadex quality`'s JSON) and its arrays.
fn mesh_dict<'py>(py: Python<'py>, m: &QuadMesh) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item(
        "points",
        f64_bytes(py, m.nodes.iter().flat_map(|p| [p.x, p.y])),
    )?;
    let quads: Vec<u32> = m.quads.iter().flatten().copied().collect();
    d.set_item("cells", u32_bytes(py, &quads))?;
    Ok(d)
}

fn element_type(t: u8) -> PyResult<ElementType> {
    ElementType::ALL
        .get(t as usize)
        .copied()
        .ok_or_else(|| PyTypeError::new_err(format!("element type {t}: 0, 1 or 2")))
}

/// An element as (type, xn, yn): the model's output in the normalised
/// frame.
type Element = (u8, f64, f64);

/// The step API over one boundary (see the package's `quadex.Mesher`).
#[pyclass(name = "_Mesher", module = "quadex._quadex")]
struct PyMesher {
    s: Stepper,
}

impl PyMesher {
    fn report<'py>(
        &self,
        py: Python<'py>,
        r: &crate::extract::StepReport,
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("index", r.index)?;
        d.set_item("kind", format!("{:?}", r.kind))?;
        d.set_item("reference", r.reference)?;
        d.set_item("element_type", r.element_type.map(|t| t.number()))?;
        d.set_item("remedy", step::remedy_name(r.remedy))?;
        d.set_item("skipped", r.skipped)?;
        d.set_item("removed", r.removed)?;
        let o = self.s.origin();
        d.set_item(
            "prediction",
            r.prediction
                .map(|p| (p.element_type.number(), p.pn.x, p.pn.y)),
        )?;
        d.set_item(
            "predicted_pn",
            r.predicted_pn.map(|p| (p.x + o.x, p.y + o.y)),
        )?;
        let quads: Vec<Vec<(f64, f64)>> = self
            .s
            .corners(r)
            .iter()
            .map(|q| q.iter().map(|p| (p.x, p.y)).collect())
            .collect();
        d.set_item("quads", quads)?;
        Ok(d)
    }
}

#[pymethods]
impl PyMesher {
    #[new]
    #[pyo3(signature = (source, **kwargs))]
    fn new(
        py: Python<'_>,
        source: &Bound<'_, PyAny>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let src = self::source(source)?;
        let o = options(kwargs, false)?;
        let s = py.detach(|| guarded(|| Stepper::new(&src, &o)))?;
        Ok(PyMesher { s })
    }

    #[getter]
    fn done(&self) -> bool {
        self.s.is_done()
    }

    #[getter]
    fn steps(&self) -> usize {
        self.s.steps()
    }

    #[getter]
    fn front_size(&self) -> usize {
        self.s.front_len()
    }

    /// The next step: its kind (None when complete) and, for an element
    /// step, P0 and the leading points.
    fn observe<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = &mut self.s;
        let (kind, o) = py.detach(|| guarded(|| s.observe()))?;
        let d = PyDict::new(py);
        d.set_item("kind", kind.map(|k| format!("{k:?}")))?;
        if let Some(o) = o {
            d.set_item("reference", o.reference)?;
            d.set_item("leading", o.leading.clone())?;
            let pts = |v: &[Point]| v.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>();
            d.set_item("world", pts(&o.world))?;
            d.set_item("normalised", pts(&o.normalised()))?;
        }
        Ok(d)
    }

    /// The model's element at the observed reference point: (type, xn,
    /// yn) in the normalised frame and Pn in the world frame.
    fn predict(&mut self) -> PyResult<(Element, (f64, f64))> {
        let (p, w) = guarded(|| self.s.predict())?;
        Ok(((p.element_type.number(), p.pn.x, p.pn.y), (w.x, w.y)))
    }

    /// The engine's own step: its report, or None when complete.
    fn step<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let s = &mut self.s;
        let r = py.detach(|| guarded(|| s.step()))?;
        r.map(|r| self.report(py, &r)).transpose()
    }

    /// The engine's step with (type, xn, yn) as the model's element at the
    /// observed reference point.
    fn step_as<'py>(
        &mut self,
        py: Python<'py>,
        element_type: u8,
        xn: f64,
        yn: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let p = Prediction {
            element_type: self::element_type(element_type)?,
            pn: Point::new(xn, yn),
        };
        let s = &mut self.s;
        let t = py.detach(|| guarded(|| s.step_as(p)))?;
        let d = self.report(py, &t.report)?;
        d.set_item("at_observed", t.at_observed)?;
        d.set_item("score", t.score)?;
        Ok(d)
    }

    /// The caller's element at the observed reference point: the guard's
    /// verdict, its score, and the report when taken.
    #[pyo3(signature = (element_type, pn=None, snap_to=None, normalised=false))]
    fn apply<'py>(
        &mut self,
        py: Python<'py>,
        element_type: u8,
        pn: Option<(f64, f64)>,
        snap_to: Option<u32>,
        normalised: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let t = self::element_type(element_type)?;
        let mut pn = pn.map(|(x, y)| Point::new(x, y));
        if normalised {
            if let Some(q) = pn {
                pn = Some(guarded(|| self.s.to_world(q))?);
            }
        }
        let s = &mut self.s;
        let v = py.detach(|| guarded(|| s.apply(t, pn, snap_to)))?;
        match v {
            Verdict::Taken { score, report } => {
                let d = self.report(py, &report)?;
                d.set_item("accepted", true)?;
                d.set_item("score", score)?;
                d.set_item("reason", None::<String>)?;
                Ok(d)
            }
            Verdict::Refused(why) => {
                let d = PyDict::new(py);
                d.set_item("accepted", false)?;
                d.set_item("score", None::<f64>)?;
                d.set_item("reason", why)?;
                Ok(d)
            }
        }
    }

    /// Takes the last step back; False when there is none.
    fn undo(&mut self, py: Python<'_>) -> PyResult<bool> {
        let s = &mut self.s;
        py.detach(|| guarded(|| Ok(s.undo())))
    }

    /// The mesh's arrays (finished as `quadex mesh` finishes it when
    /// `finished`) and its figures as JSON.
    #[pyo3(signature = (finished=true))]
    fn mesh<'py>(&self, py: Python<'py>, finished: bool) -> PyResult<Bound<'py, PyDict>> {
        let s = &self.s;
        let (m, q) = py.detach(|| {
            guarded(|| {
                let m = s.mesh(finished)?;
                let q = json(&crate::quality::MeshQuality::of(&m));
                Ok((m, q))
            })
        })?;
        let d = mesh_dict(py, &m)?;
        d.set_item("quality", q)?;
        Ok(d)
    }
}

/// The module: `mesh`, `_Mesher` and `QuadexError`.
#[pymodule]
fn _quadex(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(mesh, m)?)?;
    m.add_class::<PyMesher>()?;
    m.add("QuadexError", m.py().get_type::<QuadexError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

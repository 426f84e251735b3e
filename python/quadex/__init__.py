"""quadex: all-quadrilateral 2D meshes by learned element extraction.

``mesh(source, ...)`` meshes a boundary file, a drawing or loops of points
as ``quadex mesh`` does and returns a ``meshio.Mesh``; ``Mesher`` steps the
extraction loop one element at a time; ``quadex.env.QuadexEnv`` is the loop
as a Gymnasium-style learning environment. See docs/python.md.
"""

import json
import os

import numpy as np

from . import _quadex
from ._quadex import QuadexError

__all__ = ["mesh", "Mesher", "QuadexError", "quality"]
__version__ = _quadex.__version__

ELEMENT_TYPES = (0, 1, 2)


def _loop(a):
    a = np.asarray(a, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 2 or len(a) < 3:
        raise QuadexError("loops: each loop is an (n, 2) array of at least 3 points")
    return a.tolist()


def _source(source):
    """A path as a string, or loops as lists of [x, y] (outer loop first)."""
    if isinstance(source, (str, os.PathLike)):
        return os.fspath(source)
    if isinstance(source, np.ndarray) and source.ndim == 2:
        return [_loop(source)]
    try:
        loops = list(source)
    except TypeError:
        raise QuadexError(
            "source: a file path, or loops of points (the outer loop first, then the holes)"
        ) from None
    if loops and np.ndim(loops[0]) == 1:
        return [_loop(loops)]
    if not loops:
        raise QuadexError("loops: no loop given")
    return [_loop(l) for l in loops]


def _options(options):
    """The options as the extension takes them: ``tuning`` as JSON text."""
    tuning = options.get("tuning")
    if tuning is not None and not isinstance(tuning, str):
        options = {**options, "tuning": json.dumps(tuning)}
    return options


def _to_meshio(out, info):
    import meshio

    pts = np.frombuffer(out["points"], "<f8").reshape(-1, 2).copy()
    npe = out["nodes_per_cell"]
    cells = np.frombuffer(out["cells"], "<u4").reshape(-1, npe).astype(np.int64)
    region = np.frombuffer(out["cell_region"], "<u4").astype(np.int64)
    blocks = [meshio.CellBlock(out["cell_type"], cells)]
    groups = out["groups"]
    per_line = 3 if out["line_type"] == "line3" else 2
    lines = [np.frombuffer(b, "<u4").reshape(-1, per_line).astype(np.int64) for _, _, b in groups]
    if groups:
        blocks.append(meshio.CellBlock(out["line_type"], np.concatenate(lines)))
    empty = np.zeros(0, dtype=np.int64)
    cell_sets = {}
    region_tag = np.array([tag for tag, _ in out["regions"]], dtype=np.int64)
    for k, (_, name) in enumerate(out["regions"]):
        cell_sets[name] = [np.flatnonzero(region == k)] + ([empty] if groups else [])
    marker = []
    start = 0
    for (tag, name, _), l in zip(groups, lines):
        cell_sets[name] = [empty, np.arange(start, start + len(l))]
        marker.append(np.full(len(l), tag, dtype=np.int64))
        start += len(l)
    cell_data = {"region": [region_tag[region]]}
    if groups:
        cell_data["region"].append(np.zeros(start, dtype=np.int64))
        cell_data["marker"] = [np.zeros(len(cells), dtype=np.int64), np.concatenate(marker)]
    return meshio.Mesh(pts, blocks, cell_data=cell_data, cell_sets=cell_sets, info=info)


def mesh(source, size=None, order=1, model="default", **options):
    """Meshes ``source`` as ``quadex mesh`` does and returns a ``meshio.Mesh``.

    ``source`` is a file path (``.poly``, ``.json``, ``.dxf``: whatever the
    command line reads) or loops of points (an ``(n, 2)`` array, or a list
    of them: the outer loop, then the holes). ``size`` is a drawing's target
    size, ``order`` 1 (4-node quads) or 2 (9-node, or 8-node with
    ``serendipity=True``), ``model`` as ``--model``. The other options are
    ``quadex mesh``'s, by name: ``strategy``, ``points``, ``smooth``,
    ``cleanup``, ``coarsen``, ``remesh_below``, ``pure_model``, ``fill``,
    ``layers``, ``transitions``, ``mapped_rows``, ``resample``, ``size_at``,
    ``size_on``, ``gradation``, ``threads``, and ``tuning``: the engine's
    constants as ``--tuning``'s file holds them, a dict or its JSON text,
    e.g. ``{"mapped": {"graded_grid": True}}`` (docs/python.md).

    Regions and boundary groups are cell sets named as in the ``.msh``
    export; ``mesh.info`` holds the quality figures and step counts.
    Raises ``QuadexError`` with the command line's message.
    """
    out = _quadex.mesh(_source(source), size=size, order=order, model=model, **_options(options))
    info = {"quality": json.loads(out["quality"]), "steps": json.loads(out["steps"])}
    return _to_meshio(out, info)


def quality(m):
    """The quality figures of a mesh returned by ``mesh`` (``quadex
    quality``'s fields)."""
    return m.info["quality"]


def _pt(p):
    return None if p is None else np.asarray(p, dtype=np.float64)


class Mesher:
    """The extraction loop over one boundary, one step at a time.

    ``source`` is a boundary file (``.poly``, ``.json``) or loops of points;
    the options are ``mesh``'s extraction and finishing ones. Stepped until
    ``done``, ``to_meshio()`` is the mesh ``quadex mesh`` writes.
    """

    def __init__(self, source, model="default", **options):
        self._m = _quadex._Mesher(_source(source), model=model, **_options(options))

    @property
    def done(self):
        """True when the front is empty (the mesh is complete)."""
        return self._m.done

    @property
    def steps(self):
        """Steps taken so far."""
        return self._m.steps

    @property
    def front_size(self):
        """Front nodes left."""
        return self._m.front_size

    def observe(self):
        """What the next step will do: ``kind`` (``"Element"``, another
        step kind, or None when done) and for an element step the reference
        point and its leading points: ``reference`` (node id), ``leading``
        (node ids, ``l_N..l1, P0, r1..r_N``), ``p0``, ``world`` and
        ``normalised`` (``(2N+1, 2)`` arrays; P0 at the origin and P_r1 at
        (1, 0) in the normalised frame)."""
        d = self._m.observe()
        if "world" not in d:
            return {"kind": d["kind"], "reference": None, "leading": None,
                    "p0": None, "world": None, "normalised": None}
        world = np.asarray(d["world"], dtype=np.float64)
        return {
            "kind": d["kind"],
            "reference": d["reference"],
            "leading": np.asarray(d["leading"], dtype=np.int64),
            "p0": world[len(world) // 2].copy(),
            "world": world,
            "normalised": np.asarray(d["normalised"], dtype=np.float64),
        }

    def predict(self):
        """The model's element at the observed reference point: a dict of
        ``type`` (0, 1, 2), ``pn`` (normalised frame) and ``pn_world``."""
        (t, x, y), w = self._m.predict()
        return {"type": t, "pn": np.array([x, y]), "pn_world": np.asarray(w)}

    def apply(self, type, pn=None, snap_to=None, normalised=False):
        """The caller's element at the observed reference point (the
        editor's correction): type 0 with ``pn`` (world frame, or the
        normalised one with ``normalised=True``) or closed onto front node
        ``snap_to``, or type 1 or 2. Returns the guard's verdict:
        ``accepted``, ``score`` (in [0, 1]: the quality of the quad and of
        the front it leaves), ``reason`` when refused, and the step's report
        when taken."""
        p = None if pn is None else tuple(float(v) for v in np.asarray(pn, dtype=np.float64))
        return self._report(self._m.apply(int(type), p, snap_to, normalised))

    def step(self):
        """The engine's own step: its report (``kind``, ``reference``,
        ``element_type``, ``remedy``, ``quads``, ...), or None when done."""
        r = self._m.step()
        return None if r is None else self._report(r)

    def step_as(self, type, pn):
        """The engine's step with ``(type, pn)`` (normalised frame) as the
        model's element at the observed reference point: the guard treats
        it as it treats the model's own (accepts it, draws Pn to the size
        field, snaps it, replaces it, or passes to another reference
        point). The report adds ``at_observed`` and ``score``."""
        x, y = (float(v) for v in np.asarray(pn, dtype=np.float64))
        return self._report(self._m.step_as(int(type), x, y))

    def undo(self):
        """Takes the last step back; False when there is none."""
        return self._m.undo()

    def _report(self, r):
        r = dict(r)
        if r.get("quads") is not None:
            r["quads"] = np.asarray(r["quads"], dtype=np.float64).reshape(-1, 4, 2)
        for k in ("predicted_pn",):
            r[k] = _pt(r.get(k))
        return r

    def _mesh(self, finished):
        if finished is None:
            finished = self.done
        return self._m.mesh(finished)

    def quality(self, finished=None):
        """Quality figures of the mesh: finished as ``quadex mesh`` finishes
        it (default once done) or as extraction left it."""
        return json.loads(self._mesh(finished)["quality"])

    def to_meshio(self, finished=None):
        """The mesh as a ``meshio.Mesh`` (one region, ``domain``): finished
        as ``quadex mesh`` finishes it (default once done), else as
        extraction left it."""
        import meshio

        d = self._mesh(finished)
        pts = np.frombuffer(d["points"], "<f8").reshape(-1, 2).copy()
        quads = np.frombuffer(d["cells"], "<u4").reshape(-1, 4).astype(np.int64)
        return meshio.Mesh(
            pts,
            [meshio.CellBlock("quad", quads)],
            cell_sets={"domain": [np.arange(len(quads))]},
            info={"quality": json.loads(d["quality"])},
        )

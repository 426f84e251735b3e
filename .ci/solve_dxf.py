#!/usr/bin/env python3
"""A real solver converging on quadex's meshes of a drawing: Laplace on the
annulus 1 < r < 2 of tests/data/cad/annulus.dxf (two CIRCLEs, layers
inner and outer), u = log r on both circles, exact solution log r.
quadex meshes it at H, H/2 and H/4 with 4-node quads and with 9-node
quads (--order 2, midside nodes on the circles) and with 8-node quads
(--order 2 --serendipity); scikit-fem solves on each and the L2 error and
its rate are printed. Second order must show its higher rate, which needs
the midside nodes on the arcs.

scikit-fem reads no 8-node quad mesh (its meshio bridge knows quad and
quad9), so the quad8 file is read with meshio and each quad given the
centre node its serendipity map has (-1/4 the corners + 1/2 the
midsides): the 9-node geometry is then exactly the 8-node one, and the
solution is sought in the 8-node serendipity space (ElementQuadS2).

usage: solve_dxf.py QUADEX_BINARY OUTDIR
"""
import math
import os
import subprocess
import sys

import meshio
import numpy as np
from skfem import (Basis, BilinearForm, ElementQuad1, ElementQuad2, ElementQuadS2,
                   Functional, asm, condense, solve)
from skfem.helpers import dot, grad
from skfem.io.meshio import from_meshio

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DXF = os.path.join(ROOT, "tests", "data", "cad", "annulus.dxf")
SIZES = [0.2, 0.1, 0.05]


@BilinearForm
def laplace(u, v, _):
    return dot(grad(u), grad(v))


@Functional
def l2_error(w):
    r = np.sqrt(w.x[0] ** 2 + w.x[1] ** 2)
    return (w["uh"] - np.log(r)) ** 2


def with_centres(raw):
    """The quad8 mesh as quad9 with the serendipity centres (same geometry)."""
    q8 = raw.cells_dict["quad8"]
    pts = raw.points
    centres = -0.25 * pts[q8[:, :4]].sum(axis=1) + 0.5 * pts[q8[:, 4:]].sum(axis=1)
    ids = np.arange(len(pts), len(pts) + len(q8))[:, None]
    q9 = np.hstack([q8, ids])
    return meshio.Mesh(np.vstack([pts, centres]), [("quad9", q9)])


def solve_on(path, element, intorder):
    raw = meshio.read(path)
    # The layers are the physical curves (scikit-fem reads the named
    # boundaries of 4-node meshes; for 9-node meshes it does not parse
    # meshio's 3-node line sets, so the test checks the names in meshio).
    for name in ("inner", "outer"):
        assert name in raw.cell_sets, f"{path}: no group {name}"
    if "quad8" in raw.cells_dict:
        assert "quad9" not in raw.cells_dict
        raw = with_centres(raw)
    mesh = from_meshio(raw)
    basis = Basis(mesh, element, intorder=intorder)
    A = asm(laplace, basis)
    fixed = basis.get_dofs(mesh.boundary_facets()).flatten()
    u = basis.zeros()
    x = basis.doflocs
    u[fixed] = np.log(np.sqrt(x[0, fixed] ** 2 + x[1, fixed] ** 2))
    u = solve(*condense(A, np.zeros_like(u), x=u, D=fixed))
    err = math.sqrt(l2_error.assemble(basis, uh=basis.interpolate(u)))
    return mesh.t.shape[1], err


def main():
    binary, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    rates = {}
    print("| element | H | quads | L2 error | rate (H) | rate (mesh size) |")
    print("|---|---:|---:|---:|---:|---:|")
    runs = (("quad4", ["--order", "1"], ElementQuad1(), 4),
            ("quad9", ["--order", "2"], ElementQuad2(), 6),
            ("quad8", ["--order", "2", "--serendipity"], ElementQuadS2(), 6))
    for name, args, element, intorder in runs:
        errors, counts = [], []
        for h in SIZES:
            path = os.path.join(out, f"annulus_{name}_{h}.msh")
            subprocess.run([binary, "mesh", DXF, "--size", str(h), *args, "-o", path],
                           check=True, stdout=subprocess.DEVNULL)
            quads, err = solve_on(path, element, intorder)
            rate = math.log2(errors[-1] / err) if errors else float("nan")
            # Against the mesh's own size, sqrt(area / quads): the
            # unstructured meshes at H and H/2 are not exactly 4 times apart.
            eff = (math.log(errors[-1] / err) / (0.5 * math.log(quads / counts[-1]))
                   if errors else float("nan"))
            errors.append(err)
            counts.append(quads)
            print(f"| {name} | {h} | {quads} | {err:.3e} | {rate:.2f} | {eff:.2f} |")
        rates[name] = math.log(errors[-2] / errors[-1]) / (0.5 * math.log(counts[-1] / counts[-2]))
    if not (rates["quad4"] > 1.7 and rates["quad9"] > rates["quad4"] + 0.7
            and rates["quad8"] > rates["quad4"] + 0.7):
        print(f"rates {rates}: second order does not converge faster")
        sys.exit(1)
    print("L2 rates against the mesh size on the finest pair: " + ", ".join(f"{k} {v:.2f}" for k, v in rates.items()))


if __name__ == "__main__":
    main()

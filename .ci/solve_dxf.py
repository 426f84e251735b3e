#!/usr/bin/env python3
"""A real solver converging on quadex's meshes of a drawing: Laplace on the
annulus 1 < r < 2 of tests/data/cad/annulus.dxf (two CIRCLEs, layers
inner and outer), u = log r on both circles, exact solution log r.
quadex meshes it at H, H/2 and H/4 with 4-node quads and with 9-node
quads (--order 2, midside nodes on the circles); scikit-fem solves on
each and the L2 error and its rate are printed. Second order must show
its higher rate, which needs the midside nodes on the arcs.

usage: solve_dxf.py QUADEX_BINARY OUTDIR
"""
import math
import os
import subprocess
import sys

import meshio
import numpy as np
from skfem import (Basis, BilinearForm, ElementQuad1, ElementQuad2, Functional,
                   asm, condense, solve)
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


def solve_on(path, element, intorder):
    raw = meshio.read(path)
    # The layers are the physical curves (scikit-fem reads the named
    # boundaries of 4-node meshes; for 9-node meshes it does not parse
    # meshio's 3-node line sets, so the test checks the names in meshio).
    for name in ("inner", "outer"):
        assert name in raw.cell_sets, f"{path}: no group {name}"
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
    print("| order | H | quads | L2 error | rate |")
    print("|---|---:|---:|---:|---:|")
    for order, element, intorder in ((1, ElementQuad1(), 4), (2, ElementQuad2(), 6)):
        errors = []
        for h in SIZES:
            path = os.path.join(out, f"annulus_o{order}_{h}.msh")
            subprocess.run([binary, "mesh", DXF, "--size", str(h), "--order", str(order),
                            "-o", path], check=True, stdout=subprocess.DEVNULL)
            quads, err = solve_on(path, element, intorder)
            rate = math.log2(errors[-1] / err) if errors else float("nan")
            errors.append(err)
            print(f"| {order} | {h} | {quads} | {err:.3e} | {rate:.2f} |")
        rates[order] = math.log2(errors[-2] / errors[-1])
    if not (rates[1] > 1.7 and rates[2] > rates[1] + 0.7):
        print(f"rates {rates}: second order does not converge faster")
        sys.exit(1)
    print(f"L2 rates on the finest pair: quad4 {rates[1]:.2f}, quad9 {rates[2]:.2f}")


if __name__ == "__main__":
    main()

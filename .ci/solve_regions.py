#!/usr/bin/env python3
"""A real solver on quadex's multi-region meshes: scikit-fem reads the
exported mesh through meshio, finds the regions and boundary groups by name
and solves steady heat conduction with two conductivities,
-div(k grad u) = 0 with u = 0 on marker_1 (x = 0), u = 1 on marker_2
(x = 1), no flux elsewhere, across the interface x = 0.4 of
tests/data/regions/split_square.poly. The exact solution is piecewise
linear in x, which bilinear quads reproduce: the error must be below 1e-8.

usage: solve_regions.py QUADEX_BINARY OUTDIR
"""
import os
import subprocess
import sys

import meshio
import numpy as np
from skfem import Basis, BilinearForm, ElementQuad1, asm, condense, solve
from skfem.helpers import dot, grad
from skfem.io.meshio import from_meshio

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
K = {"region_1": 1.0, "region_2": 7.5}
A = 0.4


def exact(x):
    k1, k2 = K["region_1"], K["region_2"]
    q = 1.0 / (A / k1 + (1 - A) / k2)
    return np.where(x < A, q * x / k1, q * A / k1 + q * (x - A) / k2)


def with_cell_sets(m):
    """meshio's MSH 2.2 reader keeps the physical tags (gmsh:physical) and
    names (field_data) but builds no cell sets: build them the way its 4.1
    reader does."""
    if m.cell_sets:
        return m
    dim = {"line": 1, "quad": 2}
    for name, (tag, d) in m.field_data.items():
        m.cell_sets[name] = [
            np.flatnonzero((phys == tag) & (dim.get(block.type) == d))
            for block, phys in zip(m.cells, m.cell_data["gmsh:physical"])
        ]
    return m


def solve_on(path, fmt=None):
    mesh = from_meshio(with_cell_sets(meshio.read(path, file_format=fmt)))
    for name in ("region_1", "region_2"):
        assert name in mesh.subdomains, f"{path}: no subdomain {name}"
    for name in ("marker_1", "marker_2", "marker_3"):
        assert name in mesh.boundaries, f"{path}: no boundary {name}"
    basis = Basis(mesh, ElementQuad1())
    k = np.zeros(mesh.t.shape[1])
    for name, value in K.items():
        k[mesh.subdomains[name]] = value
    kq = basis.interpolate(basis.zeros()).value * 0 + k[:, None]

    @BilinearForm
    def laplace(u, v, w):
        return w["k"] * dot(grad(u), grad(v))

    A_ = asm(laplace, basis, k=kq)
    u = basis.zeros()
    left = basis.get_dofs(mesh.boundaries["marker_1"])
    right = basis.get_dofs(mesh.boundaries["marker_2"])
    u[right] = 1.0
    fixed = np.concatenate([left.flatten(), right.flatten()])
    u = solve(*condense(A_, np.zeros_like(u), x=u, D=fixed))
    err = np.max(np.abs(u - exact(mesh.p[0])))
    return mesh, err


def main():
    binary, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    src = os.path.join(ROOT, "tests", "data", "regions", "split_square.poly")
    worst = 0.0
    for ext in ("msh", "msh22", "vtu"):
        path = os.path.join(out, f"split_square.{ext}")
        subprocess.run([binary, "mesh", src, "-o", path], check=True, stdout=subprocess.DEVNULL)
        if ext == "vtu":
            # VTK carries the region and marker arrays, not names: check them.
            m = meshio.read(path)
            regions = np.concatenate(m.cell_data["region"])
            markers = np.concatenate(m.cell_data["marker"])
            assert set(regions[regions > 0]) == {1, 2}, set(regions)
            assert set(markers[markers > 0]) == {1, 2, 3}, set(markers)
            continue
        mesh, err = solve_on(path, "gmsh" if ext == "msh22" else None)
        worst = max(worst, err)
        print(f"scikit-fem on {ext}: {mesh.t.shape[1]} quads, regions "
              f"{sorted(mesh.subdomains)}, groups {sorted(mesh.boundaries)}, "
              f"max |u - u_exact| = {err:.2e}")
    if worst > 1e-8:
        print(f"the two-material heat solution is off by {worst:.2e}")
        sys.exit(1)
    print("two-material heat conduction exact to 1e-8 on quadex's regions")


if __name__ == "__main__":
    main()

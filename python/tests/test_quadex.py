"""The Python module: meshing from a script, the step API, the learning
environment, and errors. The command line's mesh is the reference: the
binary is $QUADEX_BIN, else target/release/quadex of this checkout."""

import os
import subprocess
import threading
import time

import meshio
import numpy as np
import pytest

import quadex
from quadex.env import QuadexEnv

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "tests", "data")
PLATE = os.path.join(DATA, "boundaries", "plate_hole.poly")
SPLIT = os.path.join(DATA, "regions", "split_square.poly")


def cli():
    path = os.environ.get("QUADEX_BIN") or os.path.join(
        os.environ.get("CARGO_TARGET_DIR") or os.path.join(ROOT, "target"), "release", "quadex"
    )
    if not os.path.exists(path):
        pytest.skip(f"no quadex binary at {path} (set QUADEX_BIN)")
    return path


def cli_mesh(tmp_path, src, *args):
    out = tmp_path / "out.msh"
    subprocess.run([cli(), "mesh", src, "-o", str(out), *args], check=True, capture_output=True)
    return meshio.read(out)


def ring(n, r, cw=False, centre=(0.0, 0.0)):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    if cw:
        t = -t
    return np.c_[centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)]


def square(n, side):
    """The square [0, side]^2 with n segments a side, counter-clockwise."""
    s = np.linspace(0, side, n, endpoint=False)
    z = np.zeros(n)
    return np.concatenate([np.c_[s, z], np.c_[z + side, s], np.c_[side - s, z + side], np.c_[z, side - s]])


def signed_areas(m):
    p = m.points[:, :2]
    q = m.cells_dict["quad"]
    x, y = p[q, 0], p[q, 1]
    return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)


def test_mesh_from_numpy_loops():
    outer = square(10, 4.0)
    hole = ring(24, 0.8, centre=(2.0, 2.0))
    m = quadex.mesh([outer, hole])
    assert isinstance(m, meshio.Mesh)
    areas = signed_areas(m)
    assert len(areas) > 50 and np.all(areas > 0)
    assert abs(areas.sum() - (16.0 - 24 / 2 * 0.8**2 * np.sin(2 * np.pi / 24))) < 1e-9
    assert list(m.cell_sets) == ["domain"]
    assert quadex.quality(m)["quads"] == len(areas)
    # One loop alone, as an array, meshes too.
    assert len(quadex.mesh(square(6, 1.0)).cells_dict["quad"]) > 0


def test_mesh_from_file_is_the_command_lines(tmp_path):
    ours = quadex.mesh(PLATE)
    theirs = cli_mesh(tmp_path, PLATE)
    assert np.array_equal(ours.points, theirs.points[:, :2])
    assert np.array_equal(ours.cells_dict["quad"], theirs.cells_dict["quad"])


def test_options_follow_the_command_line(tmp_path):
    ours = quadex.mesh(PLATE, smooth=0, cleanup=False, strategy="a", model="rules")
    theirs = cli_mesh(tmp_path, PLATE, "--smooth", "0", "--no-cleanup", "--strategy", "a", "--model", "rules")
    assert np.array_equal(ours.points, theirs.points[:, :2])
    assert np.array_equal(ours.cells_dict["quad"], theirs.cells_dict["quad"])
    assert not np.array_equal(ours.points, quadex.mesh(PLATE).points)


def test_second_order_and_drawings(tmp_path):
    m9 = quadex.mesh(PLATE, order=2)
    m8 = quadex.mesh(PLATE, order=2, serendipity=True)
    assert m9.cells_dict["quad9"].shape[1] == 9 and m8.cells_dict["quad8"].shape[1] == 8
    theirs = cli_mesh(tmp_path, PLATE, "--order", "2")
    assert np.array_equal(m9.cells_dict["quad9"], theirs.cells_dict["quad9"])
    dxf = quadex.mesh(os.path.join(DATA, "cad", "annulus.dxf"), size=0.5)
    assert np.all(signed_areas(dxf) > 0)


def test_regions_and_groups_round_trip(tmp_path):
    m = quadex.mesh(SPLIT)
    theirs = cli_mesh(tmp_path, SPLIT)
    names = ["region_1", "region_2", "marker_1", "marker_2", "marker_3"]
    assert sorted(m.cell_sets) == sorted(names)
    assert sorted(k for k in theirs.cell_sets if not k.startswith("gmsh")) == sorted(names)
    ours_sets, theirs_sets = m.cell_sets_dict, theirs.cell_sets_dict
    for name in names:
        for kind in ("quad", "line"):
            a = ours_sets[name].get(kind)
            b = theirs_sets[name].get(kind)
            a = m.cells_dict[kind][a] if a is not None and len(a) else np.zeros((0,))
            b = theirs.cells_dict[kind][b] if b is not None and len(b) else np.zeros((0,))
            assert np.array_equal(a, b), (name, kind)
    # Region 1 is x < 0.4 and region 2 the rest; marker 1 is x = 0.
    p = m.points
    quads = m.cells_dict["quad"]
    assert np.all(p[quads[ours_sets["region_1"]["quad"]], 0] <= 0.4 + 1e-12)
    assert np.all(p[quads[ours_sets["region_2"]["quad"]], 0] >= 0.4 - 1e-12)
    assert np.all(p[m.cells_dict["line"][ours_sets["marker_1"]["line"]], 0] == 0.0)


def test_scikit_fem_solves_linear_exactly():
    skfem = pytest.importorskip("skfem")
    from skfem.helpers import dot, grad
    from skfem.io.meshio import from_meshio

    mesh = from_meshio(quadex.mesh(PLATE))
    basis = skfem.Basis(mesh, skfem.ElementQuad1())

    @skfem.BilinearForm
    def laplace(u, v, _):
        return dot(grad(u), grad(v))

    exact = 1.0 + 2.0 * mesh.p[0] - 3.0 * mesh.p[1]
    u = skfem.solve(*skfem.condense(laplace.assemble(basis), basis.zeros(), x=exact.copy(),
                                    D=basis.get_dofs()))
    assert np.max(np.abs(u - exact)) < 1e-9
    # The groups: u = 0 on marker_1 (x = 0), 1 on marker_2 (x = 1) gives u = x.
    mesh = from_meshio(quadex.mesh(SPLIT))
    basis = skfem.Basis(mesh, skfem.ElementQuad1())
    u = basis.zeros()
    right = basis.get_dofs(mesh.boundaries["marker_2"]).flatten()
    left = basis.get_dofs(mesh.boundaries["marker_1"]).flatten()
    u[right] = 1.0
    u = skfem.solve(*skfem.condense(laplace.assemble(basis), basis.zeros(), x=u,
                                    D=np.concatenate([left, right])))
    assert np.max(np.abs(u - mesh.p[0])) < 1e-9


def test_mesher_stepped_to_the_end_is_the_mesh():
    m = quadex.Mesher(PLATE)
    kinds = set()
    while not m.done:
        kinds.add(m.step()["kind"])
    assert m.step() is None
    assert "Element" in kinds
    ours = m.to_meshio()
    ref = quadex.mesh(PLATE)
    assert np.array_equal(ours.points, ref.points)
    assert np.array_equal(ours.cells_dict["quad"], ref.cells_dict["quad"])
    assert m.quality() == quadex.quality(ref)


def first_element_step(m):
    while m.observe()["kind"] != "Element":
        m.step()
    return m.observe()


def test_observe_predict_apply_undo():
    m = quadex.Mesher(PLATE)
    o = first_element_step(m)
    n = len(o["leading"]) // 2
    assert o["world"].shape == o["normalised"].shape == (2 * n + 1, 2) and n == 3
    assert np.array_equal(o["normalised"][n], [0.0, 0.0])
    assert np.allclose(o["normalised"][n + 1], [1.0, 0.0])
    assert np.array_equal(o["p0"], o["world"][n])
    p = m.predict()
    assert p["type"] in (0, 1, 2)
    steps = m.steps
    # A point far outside the domain is no element: refused, nothing changes.
    far = m.apply(0, o["p0"] + 1e3)
    assert not far["accepted"] and "not a valid element" in far["reason"]
    assert m.steps == steps
    # The model's Pn, given by hand: the guard's score, and a step taken.
    ok = m.apply(0, p["pn_world"])
    assert ok["accepted"] and 0.0 < ok["score"] <= 1.0 and ok["kind"] == "Correction"
    assert ok["reference"] == o["reference"]
    assert m.steps == steps + 1
    # The same element given in the normalised frame is the same quad.
    assert m.undo() and m.steps == steps
    again = m.apply(0, p["pn"], normalised=True)
    assert np.allclose(again["quads"], ok["quads"])
    assert m.undo()
    # The engine's own step at the same state.
    r = m.step()
    assert r["kind"] == "Element" and r["reference"] == o["reference"]


def test_environment_with_the_models_actions_is_the_command_lines_mesh(tmp_path):
    env = QuadexEnv(PLATE)
    obs, info = env.reset()
    assert obs.shape == (14,)
    total, steps = 0.0, 0
    while True:
        obs, reward, terminated, truncated, info = env.step(env.model_action())
        assert -2.0 <= reward <= 1.0
        total += reward
        steps += 1
        if terminated or truncated:
            break
    assert terminated and not truncated and steps > 100
    assert total > 0.5 * steps
    assert info["quality"]["quads"] == 221
    ours = env.to_meshio()
    theirs = cli_mesh(tmp_path, PLATE)
    assert np.array_equal(ours.points, theirs.points[:, :2])
    assert np.array_equal(ours.cells_dict["quad"], theirs.cells_dict["quad"])


def test_environment_random_episode_ends():
    rng = np.random.default_rng(7)
    env = QuadexEnv(os.path.join(DATA, "peer", "freemesh_test1.poly"), max_steps=400)
    env.reset(seed=7)
    rewards = []
    while True:
        a = np.array([rng.integers(0, 3), rng.uniform(-0.5, 1.5), rng.uniform(0.0, 1.5)])
        _, reward, terminated, truncated, info = env.step(a)
        rewards.append(reward)
        if terminated or truncated:
            break
    assert terminated or len(rewards) == 400
    assert np.all(np.isfinite(rewards)) and min(rewards) < max(rewards)


def test_bad_input_raises_the_command_lines_message(tmp_path):
    missing = os.path.join(DATA, "no_such_file.poly")
    with pytest.raises(quadex.QuadexError) as e:
        quadex.mesh(missing)
    run = subprocess.run([cli(), "mesh", missing, "-o", str(tmp_path / "x.msh")],
                         capture_output=True, text=True)
    assert run.returncode == 2
    assert run.stderr.strip() == "quadex: " + str(e.value)
    bad = os.path.join(DATA, "bad", "bowtie.poly")
    with pytest.raises(quadex.QuadexError) as e:
        quadex.Mesher(bad)
    run = subprocess.run([cli(), "mesh", bad, "-o", str(tmp_path / "x.msh")], capture_output=True, text=True)
    assert run.stderr.strip() == "quadex: " + str(e.value)
    # An odd node count, a loop that is no loop, bad options.
    with pytest.raises(quadex.QuadexError, match="loops: "):
        quadex.mesh(ring(7, 1.0))
    with pytest.raises(quadex.QuadexError):
        quadex.mesh([[0, 0], [1, 1]])
    with pytest.raises(quadex.QuadexError, match="order"):
        quadex.mesh(PLATE, order=3)
    with pytest.raises(quadex.QuadexError, match="model"):
        quadex.mesh(PLATE, model="no-such-model")
    with pytest.raises(TypeError):
        quadex.mesh(PLATE, no_such_option=1)
    with pytest.raises(quadex.QuadexError, match="not an element step|complete"):
        m = quadex.Mesher(PLATE)
        while not m.done:
            m.step()
        m.predict()


def test_meshing_releases_the_gil():
    """The main thread runs while another meshes: a call that held the GIL
    would let it run before and after, never in the middle."""
    big = os.path.join(DATA, "boundaries", "disk400.poly")
    span = []
    out = []

    def work():
        t0 = time.perf_counter()
        out.append(quadex.mesh(big))
        span.extend([t0, time.perf_counter()])

    t = threading.Thread(target=work)
    ticks = []
    t.start()
    while t.is_alive():
        ticks.append(time.perf_counter())
    t.join()
    assert len(out[0].cells_dict["quad"]) > 300
    t0, t1 = span
    lo, hi = t0 + 0.2 * (t1 - t0), t1 - 0.2 * (t1 - t0)
    inside = sum(lo <= x <= hi for x in ticks)
    assert inside > 100, (inside, t1 - t0)


def graded_quadrilateral(m=20, n=12, ratio=150.0):
    """The unit square, bottom and top of m segments graded geometrically
    1:ratio towards the right-hand corners, the sides of n even segments,
    counter-clockwise."""
    g = ratio ** (1.0 / (m - 1))
    steps = g ** np.arange(m)
    from_fine = np.r_[0.0, np.cumsum(steps) / steps.sum()]
    from_fine[-1] = 1.0
    bottom = np.c_[1.0 - from_fine[m:0:-1], np.zeros(m)]
    right = np.c_[np.ones(n), np.arange(n) / n]
    top = np.c_[1.0 - from_fine[:m], np.ones(m)]
    left = np.c_[np.zeros(n), 1.0 - np.arange(n) / n]
    return np.concatenate([bottom, right, top, left])


def test_tuning_is_the_command_lines(tmp_path):
    loop = graded_quadrilateral()
    default = quadex.mesh(loop)
    # By default extraction, fans at its graded corners, not the grid.
    assert default.info["steps"]["by_kind"].get("Fan", 0) > 0
    assert default.info["steps"]["by_kind"] != {"Mapped": 1}
    grid = quadex.mesh(loop, tuning={"mapped": {"graded_grid": True}})
    assert grid.info["steps"]["by_kind"] == {"Mapped": 1}
    assert len(grid.cells_dict["quad"]) == 20 * 12
    poly = tmp_path / "graded.poly"
    k = len(loop)
    with open(poly, "w") as f:
        f.write(f"{k} 2 0 0\n")
        f.writelines(f"{i + 1} {float(x)!r} {float(y)!r}\n" for i, (x, y) in enumerate(loop))
        f.write(f"{k} 0\n")
        f.writelines(f"{i + 1} {i + 1} {(i + 1) % k + 1}\n" for i in range(k))
        f.write("0\n")
    tuning = tmp_path / "tuning.json"
    tuning.write_text('{"mapped": {"graded_grid": true}}')
    theirs = cli_mesh(tmp_path, str(poly), "--tuning", str(tuning))
    assert np.array_equal(grid.points, theirs.points[:, :2])
    assert np.array_equal(grid.cells_dict["quad"], theirs.cells_dict["quad"])
    stepped = quadex.Mesher(loop, tuning='{"mapped": {"graded_grid": true}}')
    stepped.step()
    assert stepped.done
    with pytest.raises(quadex.QuadexError, match="unknown field `graded`"):
        quadex.mesh(loop, tuning={"mapped": {"graded": True}})

#!/usr/bin/env python3
"""Writes the multi-region test cases of this folder (and the machine
example of assets/examples): Triangle .poly files with segment markers and
regional attributes, and regions documents (JSON) with names.

usage: python3 make.py   (from this folder)
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))


class Graph:
    def __init__(self):
        self.nodes, self.index, self.segs = [], {}, []
        self.holes, self.regions = [], []

    def node(self, x, y):
        k = (round(x, 12), round(y, 12))
        if k not in self.index:
            self.index[k] = len(self.nodes)
            self.nodes.append((x, y))
        return self.index[k]

    def chain(self, pts, marker=0, closed=False):
        ids = [self.node(x, y) for x, y in pts]
        pairs = list(zip(ids, ids[1:])) + ([(ids[-1], ids[0])] if closed else [])
        for a, b in pairs:
            self.segs.append((a, b, marker))
        return ids

    def line(self, p, q, n, marker=0):
        return self.chain([(p[0] + (q[0] - p[0]) * i / n, p[1] + (q[1] - p[1]) * i / n)
                           for i in range(n + 1)], marker)

    def circle(self, c, r, n, marker=0):
        return self.chain([(c[0] + r * math.cos(2 * math.pi * i / n),
                            c[1] + r * math.sin(2 * math.pi * i / n)) for i in range(n)],
                          marker, closed=True)

    def arc(self, c, r, t0, t1, n, marker=0):
        return self.chain([(c[0] + r * math.cos(t0 + (t1 - t0) * i / n),
                            c[1] + r * math.sin(t0 + (t1 - t0) * i / n)) for i in range(n + 1)],
                          marker)

    def poly(self, path, comment):
        with open(path, "w") as f:
            f.write(f"# {comment}\n")
            f.write(f"{len(self.nodes)} 2 0 0\n")
            for i, (x, y) in enumerate(self.nodes):
                f.write(f"{i + 1} {x!r} {y!r}\n")
            f.write(f"{len(self.segs)} 1\n")
            for i, (a, b, m) in enumerate(self.segs):
                f.write(f"{i + 1} {a + 1} {b + 1} {m}\n")
            f.write(f"{len(self.holes)}\n")
            for i, (x, y) in enumerate(self.holes):
                f.write(f"{i + 1} {x!r} {y!r}\n")
            f.write(f"{len(self.regions)}\n")
            for i, (x, y, a, _name) in enumerate(self.regions):
                f.write(f"{i + 1} {x!r} {y!r} {a} -1\n")

    def json(self, path, groups):
        doc = {
            "format": "quadex-regions", "version": 1,
            "nodes": [[x, y] for x, y in self.nodes],
            "segments": [[a, b] for a, b, _ in self.segs],
            "groups": [{"name": name, "tag": tag,
                        "segments": [k for k, s in enumerate(self.segs) if s[2] == tag]}
                       for tag, name in groups],
            "regions": [{"name": name, "tag": a, "point": [x, y]}
                        for x, y, a, name in self.regions],
            "holes": [[x, y] for x, y in self.holes],
        }
        with open(path, "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")


def split_square():
    """The unit square cut at x = 0.4 by an interface of uneven spacing:
    marker 1 on the left side (x = 0), 2 on the right (x = 1), 3 on the
    interface; region 1 left, region 2 right."""
    g = Graph()
    ys = [0, 0.07, 0.2, 0.26, 0.45, 0.6, 0.71, 0.9, 1]
    g.line((0, 0), (0.4, 0), 4)
    g.line((0.4, 0), (1, 0), 6)
    g.line((1, 0), (1, 1), 10, marker=2)
    g.line((1, 1), (0.4, 1), 6)
    g.line((0.4, 1), (0, 1), 4)
    g.line((0, 1), (0, 0), 10, marker=1)
    g.chain([(0.4, y) for y in ys], marker=3)
    g.regions = [(0.2, 0.5, 1, "left"), (0.7, 0.5, 2, "right")]
    return g


def layered_strip():
    """A strip 10 long of four layers 1, 0.5, 0.1 and 0.02 thick (ratios
    down to 1:0.02), 100 segments along every interface; marker 1 on the
    left end, 2 on the right end."""
    g = Graph()
    ys = [0, 1, 1.5, 1.6, 1.62]
    rows = [10, 5, 1, 1]
    for y in ys:
        g.line((0, y), (10, y), 100)
    for k in range(4):
        g.line((0, ys[k]), (0, ys[k + 1]), rows[k], marker=1)
        g.line((10, ys[k]), (10, ys[k + 1]), rows[k], marker=2)
        g.regions.append((5, (ys[k] + ys[k + 1]) / 2, k + 1, f"layer_{k + 1}"))
    return g


def plate_inclusions():
    """A 4 x 2 plate with three inclusions (two circles and a square);
    marker 1 on the left edge, 2 on the right edge, 3 on the inclusions'
    outlines; region 1 the plate, 2 the inclusions."""
    g = Graph()
    g.line((0, 0), (4, 0), 40)
    g.line((4, 0), (4, 2), 20, marker=2)
    g.line((4, 2), (0, 2), 40)
    g.line((0, 2), (0, 0), 20, marker=1)
    g.circle((0.9, 1), 0.4, 24, marker=3)
    g.chain([(1.7, 0.7), (1.75, 0.7), (1.8, 0.7), (1.85, 0.7), (1.9, 0.7), (1.95, 0.7), (2.0, 0.7),
             (2.0, 0.8), (2.0, 0.9), (2.0, 1.0), (2.0, 1.1), (2.0, 1.2), (2.0, 1.3),
             (1.95, 1.3), (1.9, 1.3), (1.85, 1.3), (1.8, 1.3), (1.75, 1.3), (1.7, 1.3),
             (1.7, 1.2), (1.7, 1.1), (1.7, 1.0), (1.7, 0.9), (1.7, 0.8)], marker=3, closed=True)
    g.circle((3.0, 1), 0.5, 32, marker=3)
    g.regions = [(0.2, 0.2, 1, "plate"), (0.9, 1, 2, "inclusion"), (1.85, 1, 2, "inclusion"),
                 (3.0, 1, 2, "inclusion")]
    return g


def annulus_two_materials():
    """An annulus (radii 0.5 and 1) of two rings split at r = 0.7, graded:
    48 nodes inside, 64 on the interface, 80 outside; marker 1 inside,
    2 outside."""
    g = Graph()
    g.circle((0, 0), 0.5, 48, marker=1)
    g.circle((0, 0), 0.7, 64)
    g.circle((0, 0), 1.0, 80, marker=2)
    g.holes = [(0, 0)]
    g.regions = [(0.6, 0, 1, "inner"), (0.85, 0, 2, "outer")]
    return g


def l_bracket():
    """An L-shaped bracket of three parts meeting at a T junction: nodes
    where three faces meet; marker 1 on the foot, 2 on the arm's end."""
    g = Graph()
    h = 0.1
    g.line((0, 0), (1, 0), 10, marker=1)
    g.line((1, 0), (2, 0), 10, marker=1)
    g.line((2, 0), (2, 0.5), 5)
    g.line((2, 0.5), (1, 0.5), 10)
    g.line((1, 0.5), (1, 2), 15)
    g.line((1, 2), (0, 2), 10, marker=2)
    g.line((0, 2), (0, 0.5), 15)
    g.line((0, 0.5), (0, 0), 5)
    g.line((0, 0.5), (1, 0.5), 10)
    g.line((1, 0), (1, 0.5), 5)
    g.regions = [(0.5, 0.25, 1, "corner"), (1.5, 0.25, 2, "foot"), (0.5, 1.2, 3, "arm")]
    assert h
    return g


def machine(f=1):
    """A machine-like cross section: shaft hole, rotor iron with four
    inset magnets, a thin air gap, a stator with twelve closed slots
    (windings). Marker 1 on the shaft, 2 on the stator's outside. `f`
    refines every curve f times."""
    g = Graph()
    n_gap = 144 * f
    g.circle((0, 0), 0.3, 24 * f, marker=1)
    g.holes = [(0, 0)]
    g.circle((0, 0), 1.0, n_gap)
    g.circle((0, 0), 1.04, n_gap)
    g.circle((0, 0), 1.8, 96 * f, marker=2)
    regions = []
    for k in range(4):
        t = math.pi / 4 + k * math.pi / 2
        w = math.radians(22)
        a = g.arc((0, 0), 0.8, t - w, t + w, 12 * f)
        b = g.arc((0, 0), 0.92, t + w, t - w, 12 * f)
        g.line(g.nodes[a[-1]], g.nodes[b[0]], f)
        g.line(g.nodes[b[-1]], g.nodes[a[0]], f)
        regions.append((0.86 * math.cos(t), 0.86 * math.sin(t), 2, "magnets"))
    for k in range(12):
        t = k * math.pi / 6
        w = math.radians(6)
        a = g.arc((0, 0), 1.12, t - w, t + w, 4 * f)
        b = g.arc((0, 0), 1.5, t + w, t - w, 6 * f)
        g.line(g.nodes[a[-1]], g.nodes[b[0]], 8 * f)
        g.line(g.nodes[b[-1]], g.nodes[a[0]], 8 * f)
        regions.append((1.3 * math.cos(t), 1.3 * math.sin(t), 5, "windings"))
    g.regions = [(0.5, 0, 1, "rotor_iron"), (1.02, 0, 3, "air_gap"),
                 (1.7, 0.1, 4, "stator_iron")] + regions
    return g


def main():
    split_square().poly(os.path.join(HERE, "split_square.poly"),
                        "the unit square cut at x = 0.4 by an interface of uneven spacing")
    layered_strip().poly(os.path.join(HERE, "layered_strip.poly"),
                         "four layers 1, 0.5, 0.1 and 0.02 thick")
    plate_inclusions().poly(os.path.join(HERE, "plate_inclusions.poly"),
                            "a plate with three inclusions")
    annulus_two_materials().poly(os.path.join(HERE, "annulus_two_materials.poly"),
                                 "an annulus of two rings")
    l_bracket().poly(os.path.join(HERE, "l_bracket.poly"), "an L bracket of three parts")
    m = machine()
    m.json(os.path.join(ROOT, "assets", "examples", "machine.json"),
           [(1, "shaft"), (2, "stator_outside")])
    m.poly(os.path.join(HERE, "machine.poly"), "a machine-like cross section")
    machine(4).poly(os.path.join(HERE, "machine_fine.poly"),
                    "the machine-like cross section, every curve four times finer")


if __name__ == "__main__":
    main()

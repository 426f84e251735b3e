#!/usr/bin/env python3
"""The import graph of the crate's top-level modules, and a check that it has
no cycle.

An edge A -> B is a `crate::B…` path (a `use crate::…` line, grouped
`use crate::{…}` items included, or an inline `crate::B::…` path) in the code
of module A outside `#[cfg(test)]` items; crate-root re-exports
(`crate::Boundary`, …) count as the module they come from. The binary's files
(`src/main.rs`, `src/cli.rs`, `src/cli/`) count their `quadex::…` paths as
the module `cli`. Comments, strings and character literals are ignored.

Folders listed in INNER_DAG are checked the same way one level down: the
files inside them must not import each other in a loop either.

Prints one line per module, `module -> imports`, and exits 1 when there is a
cycle, naming it.
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "src"
BIN_FILES = {"main.rs", "cli.rs"}
BIN_DIRS = {"cli"}
INNER_DAG = ["finish"]
IDENT = r"[A-Za-z_][A-Za-z0-9_]*"


def strip(text):
    """The code without comments, strings and character literals."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    i += 1
        elif re.match(r'(b?r#*")', text[i:i + 8]) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'b?r(#*)"', text[i:])
            end = '"' + m.group(1)
            j = text.find(end, i + m.end())
            out.append('""')
            i = n if j < 0 else j + len(end)
        elif c == '"':
            i += 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            out.append('""')
            i += 1
        elif c == "'":
            m = re.match(r"'(\\.[^']*|[^\\'])'", text[i:])
            if m:
                out.append("' '")
                i += m.end()
            else:
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def matching(code, i, pair="{}"):
    """Index just past the group opening at code[i] (`pair[0]`)."""
    depth = 0
    while i < len(code):
        if code[i] == pair[0]:
            depth += 1
        elif code[i] == pair[1]:
            depth -= 1
            if depth == 0:
                return i + 1
        i += 1
    return len(code)


def without_tests(code):
    """The code with every `#[cfg(test)]` item removed."""
    while True:
        m = re.search(r"#\[cfg\(test\)\]", code)
        if not m:
            return code
        i = m.end()
        # Skip further attributes, then the item up to `;` or its brace group.
        while True:
            k = re.match(r"\s*#\[", code[i:])
            if not k:
                break
            i = matching(code, i + k.end() - 1, "[]")
        j = i
        while j < len(code) and code[j] not in ";{":
            j += 1
        end = j + 1 if j < len(code) and code[j] == ";" else matching(code, j)
        code = code[:m.start()] + code[end:]


def group_heads(body):
    """The first path segment of each item of a `{…}` use group."""
    items, depth, cur = [], 0, []
    for c in body:
        if c in "{" :
            depth += 1
        elif c == "}":
            depth -= 1
        if c == "," and depth == 0:
            items.append("".join(cur))
            cur = []
        else:
            cur.append(c)
    items.append("".join(cur))
    heads = []
    for item in items:
        m = re.match(r"\s*(" + IDENT + ")", item)
        if m:
            heads.append(m.group(1))
    return heads


def targets(code, root):
    """Top-level names reached through `root::` paths in the code."""
    found = set()
    for m in re.finditer(r"(?<![A-Za-z0-9_$:])" + root + r"::", code):
        i = m.end()
        while i < len(code) and code[i].isspace():
            i += 1
        if i < len(code) and code[i] == "{":
            found.update(group_heads(code[i + 1:matching(code, i) - 1]))
        else:
            k = re.match(IDENT, code[i:])
            if k:
                found.add(k.group(0))
    return found


def modules():
    """Top-level module name -> its files."""
    mods = {}
    for p in sorted(SRC.iterdir()):
        if p.is_file() and p.suffix == ".rs" and p.name != "lib.rs":
            name = "cli" if p.name in BIN_FILES else p.stem
            mods.setdefault(name, []).append(p)
        elif p.is_dir():
            name = "cli" if p.name in BIN_DIRS else p.name
            mods.setdefault(name, []).extend(sorted(p.rglob("*.rs")))
    return mods


def reexports(names):
    """Crate-root re-exported item -> the module it comes from."""
    lib = without_tests(strip((SRC / "lib.rs").read_text()))
    out = {}
    for m in re.finditer(r"pub use (" + IDENT + r")::([^;]*);", lib):
        if m.group(1) not in names:
            continue
        body = m.group(2).strip()
        if body.startswith("{"):
            body = body[1:-1]
        for item in body.split(","):
            item = item.strip()
            if not item:
                continue
            last = re.split(r"\s+as\s+", item)[-1].split("::")[-1].strip()
            out[last] = m.group(1)
    return out


def cycles(graph):
    """The strongly connected components with more than one node (Tarjan)."""
    index, low, stack, on, comps, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                comps.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return comps


def report(title, graph):
    print(title)
    width = max(len(k) for k in graph)
    for k in sorted(graph):
        print(f"  {k:<{width}} -> {', '.join(sorted(graph[k])) or '—'}")
    comps = cycles(graph)
    for comp in comps:
        print(f"  CYCLE: {' ⇄ '.join(comp)}")
    return comps


def main():
    mods = modules()
    names = set(mods)
    alias = reexports(names)
    graph = {}
    for name, files in mods.items():
        root = "quadex" if name == "cli" else "crate"
        edges = set()
        for f in files:
            code = without_tests(strip(f.read_text()))
            for t in targets(code, root):
                t = alias.get(t, t)
                if t in names and t != name:
                    edges.add(t)
        graph[name] = edges
    bad = report("top-level modules", graph)

    for folder in INNER_DAG:
        d = SRC / folder
        if not d.is_dir():
            continue
        subs = {p.stem: p for p in sorted(d.glob("*.rs"))}
        subs.update({p.name: p / "mod.rs" for p in sorted(d.iterdir()) if p.is_dir()})
        inner = {}
        for sub, f in subs.items():
            code = without_tests(strip(f.read_text()))
            edges = set()
            for t in targets(code, "super") | {
                x.split("::")[0] for x in re.findall(r"(?<![A-Za-z0-9_$:])crate::" + folder + r"::(" + IDENT + ")", code)
            }:
                if t in subs and t != sub:
                    edges.add(t)
            if sub == "mod":
                edges |= {t for t in targets(code, "self") if t in subs}
                edges |= {
                    m.group(1)
                    for m in re.finditer(r"(?<![A-Za-z0-9_$:])(" + IDENT + r")::", code)
                    if m.group(1) in subs and m.group(1) != "mod"
                }
            inner[sub] = edges
        bad += report(f"inside {folder}/", inner)

    if bad:
        print(f"{len(bad)} import cycle(s)")
        sys.exit(1)
    print("no import cycle")


if __name__ == "__main__":
    main()

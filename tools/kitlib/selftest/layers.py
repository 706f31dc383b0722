"""Self-test of the driver's shape: its modules import only downwards, along the grading pipeline.

    core < boundary < build < judge < outputs < site < commands

core (paths, steps, the course, the secret, packages), the boundary (where graded code runs), builds,
the judge (running a step's cases), the outputs (the record and each platform's rendering, the class
report), the site (docs, decks, the lab's browser, the bench's report) and the commands (one module
each; none imports another). Every import counts, at the top of a module or inside a function: a
cycle or an upward arrow fails, and so does a module no layer names (place it in LAYERS). The
self-test package itself stands above all of it.
"""

from __future__ import annotations

import ast
from pathlib import Path

from ..common import ROOT
from .harness import expect

KITLIB = ROOT / "tools" / "kitlib"

LAYERS = [
    ("core", ["status", "common", "course", "secret", "packages", "includes", "relocate", "kitfiles", "waits",
              "submissions", "kitcache"]),
    ("boundary", ["sandbox", "studentpch", "launch"]),
    ("build", ["build", "warmup"]),
    ("judge", ["checking", "mutants"]),
    ("outputs", ["record", "gradescope", "plresults", "scoreboard", "picture", "robust_line", "report",
                 "report.grading", "report.make", "report.pages", "report.plots", "report.signatures",
                 "report.similar"]),
    ("site", ["webtools", "decks", "browser", "bench_report"]),
    ("commands", ["cli", "__main__", "commands"]),
]


def modules() -> dict[str, Path]:
    found = {}
    for p in KITLIB.rglob("*.py"):
        parts = p.relative_to(KITLIB).with_suffix("").parts
        if parts[0] == "selftest":
            continue
        name = ".".join(parts[:-1]) if parts[-1] == "__init__" else ".".join(parts)
        found[name or "kitlib"] = p
    return found


def imports(name: str, path: Path, known: set[str]) -> set[str]:
    """The kit's modules `name` imports, anywhere in it."""
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if not isinstance(node, ast.ImportFrom) or not node.level:
            continue
        base = package[:len(package) - (node.level - 1)] if node.level > 1 else package
        target = ".".join(base + ([node.module] if node.module else []))
        for alias in node.names:
            full = f"{target}.{alias.name}" if target else alias.name
            if full in known:
                found.add(full)
            elif target in known:
                found.add(target)
    found.discard(name)
    return found


def layer_of(name: str) -> int | None:
    for i, (_, names) in enumerate(LAYERS):
        if name in names or any(name.startswith(n + ".") for n in names if n == "commands"):
            return i
    return None


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected parts of more than one module (Tarjan's algorithm)."""
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]

    def visit(v: str) -> None:
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
            part = []
            while True:
                w = stack.pop()
                on.discard(w)
                part.append(w)
                if w == v:
                    break
            if len(part) > 1:
                found.append(sorted(part))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def selftest_layers(ctx) -> str:
    mods = modules()
    graph = {n: imports(n, p, set(mods)) for n, p in mods.items()}
    unplaced = sorted(n for n in mods if layer_of(n) is None)
    expect(not unplaced, f"modules in no layer of selftest/layers.py's LAYERS: {unplaced}")
    loops = cycles(graph)
    expect(not loops, f"import cycles: {loops}")
    upward = [f"{a} ({LAYERS[layer_of(a)][0]}) imports {b} ({LAYERS[layer_of(b)][0]})"
              for a, deps in sorted(graph.items()) for b in sorted(deps) if layer_of(b) > layer_of(a)]
    expect(not upward, "upward imports: " + "; ".join(upward[:6]))
    sideways = [f"{a} imports {b}" for a, deps in sorted(graph.items()) for b in sorted(deps)
                if a.startswith("commands.") and b.startswith("commands.") and b != "commands"]
    expect(not sideways, "a command imports another: " + "; ".join(sideways[:6]))
    lines = {name: sum(len(mods[n].read_text().splitlines()) for n in names if n in mods)
             + (sum(len(p.read_text().splitlines()) for n, p in mods.items() if n.startswith("commands."))
                if name == "commands" else 0)
             for name, names in LAYERS}
    return (f"{len(mods)} modules, {sum(len(d) for d in graph.values())} imports, no cycle, none upward; lines: "
            + ", ".join(f"{k} {v}" for k, v in lines.items()))


def selftests():
    return [("layers: imports go downwards, no cycle", selftest_layers)]

"""Self-test of the driver's shape: its modules import only downwards, along the grading pipeline.

    core < boundary < build < judge < outputs < site < commands

core (paths, steps, the course, the secret, packages), the boundary (where graded code runs), builds,
the judge (running a step's cases), the outputs (the record and each platform's rendering, the class
report), the site (docs, decks, the lab's browser, the bench's report) and the commands (one module
each; none imports another). Every import counts, at the top of a module or inside a function (not
one under `if TYPE_CHECKING:`, which never runs): a cycle or an upward arrow fails, and so does a module no layer names (place it in LAYERS). The
self-test package itself stands above all of it. And one module reads /proc: procfs.py.
"""

from __future__ import annotations

import ast
import os
import re
import time
from pathlib import Path

import pytest

from kitlib.common import ROOT
from .support import Skipped, expect

KITLIB = ROOT / "tools" / "kitlib"

LAYERS = [
    ("core", ["status", "common", "atomic", "course", "manifest", "secret", "packages", "includes", "relocate", "kitfiles",
              "waits", "submissions", "compilers", "procfs", "pycache", "faults"]),
    ("boundary", ["sandbox_slots", "sandbox.limits", "sandbox.ids", "sandbox.reaping", "sandbox.ipc", "sandbox.cgroups",
                  "sandbox.bwrap", "sandbox.runner", "sandbox.view", "sandbox.isolation", "sandbox", "studentpch"]),
    ("build", ["build", "bundle", "objcache", "warmup", "runfolders", "judgedby"]),
    ("judge", ["cases", "runcases", "checking", "mutants", "slips"]),
    ("outputs", ["charts", "record", "gradescope", "plresults", "classroomresults", "taskpage", "scoreboard", "picture",
                 "picture.basics", "picture.case", "picture.panel", "picture.shapes", "picture.drawing",
                 "picture.grading", "picture.gallery",
                 "robust_line", "report", "report.grading", "report.make", "report.merge", "report.pages", "report.plots", "report.rows",
                 "report.signatures",
                 "report.similar"]),
    ("site", ["webtools", "decks", "browser", "bench_report"]),
    ("commands", ["cli", "__main__", "commands"]),
]


def modules() -> dict[str, Path]:
    found = {}
    for p in KITLIB.rglob("*.py"):
        parts = p.relative_to(KITLIB).with_suffix("").parts
        name = ".".join(parts[:-1]) if parts[-1] == "__init__" else ".".join(parts)
        found[name or "kitlib"] = p
    return found


def imports(name: str, path: Path, known: set[str]) -> set[str]:
    """The kit's modules `name` imports, anywhere in it."""
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    found = set()
    tree = ast.parse(path.read_text())
    # An import for annotations only (`if TYPE_CHECKING:`) runs never: it makes no arrow.
    typing_only = {id(n) for block in ast.walk(tree) if isinstance(block, ast.If)
                   and isinstance(block.test, ast.Name) and block.test.id == "TYPE_CHECKING"
                   for stmt in block.body for n in ast.walk(stmt)}
    for node in ast.walk(tree):
        if not isinstance(node, ast.ImportFrom) or not node.level or id(node) in typing_only:
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


@pytest.mark.quick
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


# Renames that are not a write of the kit's own data, so not atomic.write's: per module, how many
# and what they move.
OTHER_RENAMES = {
    "studentpch": (1, "the compiler's own output (a precompiled header) moved into place"),
    "objcache": (2, "an object-cache entry's folder, swapped whole"),
    "report.pages": (1, "a folder of pages, swapped whole"),
    "report.merge": (1, "a merged grading folder, moved into place whole"),
    "commands.prairielearn": (1, "a staged folder, swapped whole"),
    "commands.handout": (1, "a staged folder, swapped whole"),
    "commands.docs": (2, "the site's folder, swapped whole"),
    "decks": (2, "the decks' folder, swapped whole"),
}


def renames(path: Path) -> int:
    """Calls in `path` that move a file into place: os.replace, os.rename, a Path's replace or rename
    (one argument: str.replace takes two)."""
    found = 0
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                and node.func.attr in ("replace", "rename"):
            if (isinstance(node.func.value, ast.Name) and node.func.value.id == "os") or len(node.args) == 1:
                found += 1
    return found


@pytest.mark.quick
def selftest_atomic_write(ctx) -> str:
    """One atomic write (kitlib/atomic.py): no other module moves a file into place but those
    OTHER_RENAMES names; and its guarantees, shown: a link planted at the target is replaced, not
    written through; a write that fails halfway leaves the old file whole and no temporary file; a
    missing folder is an OSError; the mode is what a plain open gives, or the one asked for."""
    import tempfile
    from kitlib import atomic

    counts = {n: renames(p) for n, p in modules().items() if n != "atomic"}
    hand_written = sorted(f"{n} ({k})" for n, k in counts.items() if k != OTHER_RENAMES.get(n, (0, ""))[0])
    expect(not hand_written, f"files moved into place by hand (use atomic.write or atomic.replacing; a folder or "
                             f"another program's output: name it in layers.OTHER_RENAMES): {hand_written}")
    with tempfile.TemporaryDirectory(prefix="raykit-atomic-") as tmp:
        d = Path(tmp)
        victim = d / "victim"
        victim.write_text("the victim")
        (d / "out.json").symlink_to(victim)
        atomic.write(d / "out.json", "new")
        expect(victim.read_text() == "the victim" and not (d / "out.json").is_symlink()
               and (d / "out.json").read_text() == "new", "a link planted at the target was written through")
        expect((d / "out.json").stat().st_mode & 0o777 == atomic.DEFAULT_MODE, "the default mode is not open()'s")
        try:
            with atomic.replacing(d / "out.json", 0o600) as f:
                f.write(b"half")
                raise RuntimeError("stopped halfway")
        except RuntimeError:
            pass
        left = sorted(p.name for p in d.iterdir())
        expect((d / "out.json").read_text() == "new" and left == ["out.json", "victim"],
               f"a write stopped halfway left {left}, the file reading {(d / 'out.json').read_text()!r}")
        try:
            atomic.write(d / "no-such-folder" / "x", b"x")
            expect(False, "a write into a missing folder did not fail")
        except OSError:
            pass
        atomic.write(d / "secret", b"\0", mode=0o600)
        expect((d / "secret").stat().st_mode & 0o777 == 0o600, "the mode asked for was not given")
    return (f"only atomic.py moves the kit's files into place ({sum(k for k, _ in OTHER_RENAMES.values())} other "
            "renames, of folders and compilers' output); a planted link replaced, a half write leaves nothing, "
            "modes kept")


# A path under /proc opened in code: a string that starts with /proc/, or Path of /proc itself.
# (sandbox/'s bubblewrap mounts a fresh /proc, which opens nothing; render's self-test writes to
# a /proc path on purpose, to fail.)
PROC_READ = re.compile(r"""(?:["']/proc/(?!raykit-cannot-exist)|Path\(\s*f?["']/proc["']\s*\))""")


@pytest.mark.quick
def selftest_one_proc_reader(ctx) -> str:
    """procfs.py is the kit's one reader of /proc: no other module of the driver or its self-test opens a
    path there; and what it reads is right: this process's owner, parent, session and command line, a
    child's own session, the child as a zombie until it is reaped, then gone."""
    import os
    import subprocess
    import sys
    from kitlib import procfs
    readers = sorted(str(f.relative_to(KITLIB)) for f in KITLIB.rglob("*.py")
                     if f.name != "procfs.py" and PROC_READ.search(f.read_text()))
    expect(not readers, f"modules that read /proc themselves, not through procfs.py: {readers}")
    if not procfs.pids():
        raise Skipped("no /proc here (not Linux): the scan above is all that applies")
    me = os.getpid()
    expect(procfs.real_uid(me) == os.getuid() and procfs.parent(me) == os.getppid()
           and procfs.session(me) == os.getsid(0) and procfs.alive(me) and me in procfs.pids(),
           f"this process read wrong: uid {procfs.real_uid(me)}, parent {procfs.parent(me)}, "
           f"session {procfs.session(me)}, state {procfs.state(me)!r}")
    expect(sys.executable.split("/")[-1] in procfs.cmdline(me), f"this process's command line: {procfs.cmdline(me)!r}")
    child = subprocess.Popen(["sleep", "30"], start_new_session=True)
    try:
        # Popen returns once the exec has begun; the new program's command line is readable a moment
        # later (an empty one was read here on a loaded machine), so wait for it, up to 10 s.
        for _ in range(1000):
            if procfs.cmdline(child.pid):
                break
            time.sleep(0.01)
        expect(procfs.session(child.pid) == child.pid and procfs.comm(child.pid) == "sleep"
               and procfs.cmdline(child.pid) == "sleep 30",
               f"a child read wrong: session {procfs.session(child.pid)}, {procfs.comm(child.pid)!r}")
        child.kill()
        for _ in range(200):                      # the kill lands: a zombie until reaped
            if procfs.state(child.pid) == "Z":
                break
            time.sleep(0.01)
        expect(procfs.state(child.pid) == "Z" and not procfs.alive(child.pid),
               f"a killed, unreaped child reads as {procfs.state(child.pid)!r}")
    finally:
        child.kill()
        child.wait()
    expect(procfs.status(child.pid) == {} and procfs.stat(child.pid) == [] and not procfs.alive(child.pid),
           "a reaped child still reads as a process")
    return (f"no module but procfs.py opens /proc ({len(list(KITLIB.rglob('*.py')))} scanned); own fields, "
            "a child's session, its zombie and its end read right")


@pytest.mark.quick
def selftest_compiled_modules(ctx) -> str:
    """./kit compiles the kit's own modules once, into its cache folder (kitlib/pycache.py), and no
    other module there: the standard library reads those installed beside it. Nothing is written
    beside the kit's sources. A cheap command (./kit check --help) with a fresh cache folder, twice."""
    import subprocess
    import tempfile
    before = {p for p in (ROOT / "tools").rglob("__pycache__")}
    with tempfile.TemporaryDirectory(prefix="raykit-pycache-") as home:
        env = {k: v for k, v in os.environ.items() if k not in ("RAYKIT_PYCACHE", "PYTHONPYCACHEPREFIX")}
        env["XDG_CACHE_HOME"] = home
        for _ in range(2):
            r = subprocess.run([str(ROOT / "kit"), "check", "--help"], cwd=ROOT, env=env, capture_output=True,
                               text=True, timeout=120)
            expect(r.returncode == 0, f"./kit check --help: {r.returncode} {r.stderr[-300:]}")
        folder = Path(home) / "raykit" / "pycache"
        compiled = sorted(p for p in folder.rglob("*.pyc")) if folder.is_dir() else []
        kit = [p for p in compiled if (KITLIB.resolve().as_posix().lstrip("/") + "/") in p.as_posix()]
        other = [p.relative_to(folder).as_posix() for p in compiled if p not in kit]
        expect(kit, f"no module of the kit's compiled into {folder}")
        expect(not other, f"modules other than the kit's compiled into the kit's cache: {other[:5]}")
    after = {p for p in (ROOT / "tools").rglob("__pycache__")}
    expect(after <= before, f"compiled modules written beside the kit's sources: {sorted(after - before)[:3]}")
    return f"{len(kit)} of the kit's modules compiled into its cache folder, none other, none beside the sources"

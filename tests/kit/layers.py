"""Self-test of the driver's shape: two packages along its two audiences, and in them modules that
import only downwards, along the grading pipeline.

The packages: tools/raykit, the student's runtime (./kit check, watch, hint, debug, render, reset and
everything they import), which a handout ships; tools/kitlib, the instructor's toolchain (grading, the
platforms, the report, docs, slides, the bench's reading, the self-test). raykit imports the standard
library and itself only, never kitlib (a student's copy has no kitlib, and may have no package of
Debian's beyond Python); kitlib imports raykit, and may use Debian 12's packages. Every module of raykit
is one the students' commands import (what only the instructor's side needs goes to kitlib).

The layers, across both packages:

    core < boundary < build < judge < outputs < site < commands

core (paths, steps, the course, the secret, packages), the boundary (where graded code runs), builds,
the judge (running a step's cases), the outputs (the record and each platform's rendering, the class
report), the site (docs, decks, the lab's browser, the bench's report) and the commands (one module
each; none imports another). Every import counts, at the top of a module or inside a function (not
one under `if TYPE_CHECKING:`, which never runs), and so does a module named to importlib: a cycle or
an upward arrow fails, and so does a module no layer names (place it in LAYERS). The self-test package
itself stands above all of it. And one module reads /proc: procfs.py.
"""

from __future__ import annotations

import ast
import os
import re
import sys
import time
from pathlib import Path

import pytest

from raykit.common import ROOT
from .support import Skipped, expect

TOOLS = ROOT / "tools"
STUDENT_PACKAGE, INSTRUCTOR_PACKAGE = "raykit", "kitlib"
PACKAGES = (STUDENT_PACKAGE, INSTRUCTOR_PACKAGE)
KITLIB = TOOLS / INSTRUCTOR_PACKAGE
RAYKIT = TOOLS / STUDENT_PACKAGE
# The student's commands' modules: where the student package's import closure starts.
STUDENT_ROOTS = ("raykit.__main__", "raykit.cli", "raykit.commands")

# Module names without their package: a layer holds a module of either package.
LAYERS = [
    ("core", ["status", "common", "atomic", "course", "manifest", "secret", "packages", "includes", "relocate", "kitfiles",
              "waits", "submissions", "compilers", "procfs", "pycache", "faults", "heldtmp"]),
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


def sources() -> list[Path]:
    """The driver's Python files, both packages, the self-test left out."""
    return sorted(p for pkg in PACKAGES for p in (TOOLS / pkg).rglob("*.py")
                  if "__pycache__" not in p.parts and p.relative_to(TOOLS).parts[1:2] != ("selftest",))


def modules() -> dict[str, Path]:
    """{qualified name (raykit.common, kitlib.report.pages): its file} of both packages."""
    found = {}
    for p in sources():
        parts = p.relative_to(TOOLS).with_suffix("").parts
        found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = p
    return found


def _typing_only(tree: ast.AST) -> set[int]:
    # An import for annotations only (`if TYPE_CHECKING:`) runs never: it makes no arrow.
    return {id(n) for block in ast.walk(tree) if isinstance(block, ast.If)
            and isinstance(block.test, ast.Name) and block.test.id == "TYPE_CHECKING"
            for stmt in block.body for n in ast.walk(stmt)}


def imported_names(name: str, path: Path) -> list[tuple[str, list[str]]]:
    """What `name` imports, anywhere in it: (absolute module, names taken from it) per import, its
    relative imports made absolute, and each literal module name given to importlib.import_module
    (an f-string's text before its first {})."""
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    tree = ast.parse(path.read_text())
    skip = _typing_only(tree)
    found = []
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.ImportFrom):
            if node.level:
                up = node.level - 1
                base = package[:len(package) - up] if up else package
                if up > len(package) - 1:       # above the top package: tools/ itself
                    base = ["<above " + package[0] + ">"]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            found.append((target, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            found += [(a.name, []) for a in node.names]
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                and node.func.attr == "import_module" and node.args:
            arg = node.args[0]
            text = arg.value if isinstance(arg, ast.Constant) and isinstance(arg.value, str) else \
                (arg.values[0].value if isinstance(arg, ast.JoinedStr) and arg.values
                 and isinstance(arg.values[0], ast.Constant) else "")
            if text:
                found.append((text.rstrip("."), []))
    return found


def imports(name: str, path: Path, known: set[str]) -> set[str]:
    """The kit's modules (of either package) `name` imports, anywhere in it."""
    found = set()
    for target, names in imported_names(name, path):
        for alias in names or [""]:
            full = f"{target}.{alias}" if alias else target
            if full in known:
                found.add(full)
            elif target in known:
                found.add(target)
    found.discard(name)
    return found


def layer_of(name: str) -> int | None:
    """The layer of a qualified name (raykit.common: core)."""
    bare = name.partition(".")[2] or name
    for i, (_, names) in enumerate(LAYERS):
        if bare in names or any(bare.startswith(n + ".") for n in names if n == "commands"):
            return i
    return None


def student_rule(mods: dict[str, Path]) -> list[str]:
    """What breaks "the student package imports only the standard library and itself", each a line."""
    stdlib = set(getattr(sys, "stdlib_module_names", ())) | {"__future__"}
    broken = []
    for name, path in sorted(mods.items()):
        if not name.startswith(STUDENT_PACKAGE + "."):
            continue
        for target, _ in imported_names(name, path):
            top = target.split(".")[0]
            if top == STUDENT_PACKAGE:
                continue
            if top == INSTRUCTOR_PACKAGE:
                broken.append(f"{name} imports {target} (the instructor's package)")
            elif top.startswith("<above"):
                broken.append(f"{name} imports from above its package ({target})")
            elif stdlib and top not in stdlib:
                broken.append(f"{name} imports {target} (not the standard library)")
    return broken


def unreached(mods: dict[str, Path], graph: dict[str, set[str]]) -> list[str]:
    """The student package's modules that no student's command imports (directly or not)."""
    todo = [n for n in mods if n in STUDENT_ROOTS or n.startswith("raykit.commands.")]
    seen: set[str] = set()
    while todo:
        n = todo.pop()
        if n not in seen:
            seen.add(n)
            todo += graph.get(n, ())
            parts = n.split(".")        # importing a.b.c runs the packages a.b's __init__ too
            todo += [".".join(parts[:i]) for i in range(2, len(parts)) if ".".join(parts[:i]) in mods]
    return sorted(n for n in mods if n.startswith(STUDENT_PACKAGE + ".") and n not in seen)


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
                if ".commands." in a and ".commands." in b]
    expect(not sideways, "a command imports another: " + "; ".join(sideways[:6]))
    lines = {name: sum(len(p.read_text().splitlines()) for n, p in mods.items() if layer_of(n) == i)
             for i, (name, _) in enumerate(LAYERS)}
    return (f"{len(mods)} modules, {sum(len(d) for d in graph.values())} imports, no cycle, none upward; lines: "
            + ", ".join(f"{k} {v}" for k, v in lines.items()))


@pytest.mark.quick
def selftest_two_packages(ctx) -> str:
    """The student's runtime (raykit) imports the standard library and itself only, never the
    instructor's toolchain (kitlib), and holds only what the students' commands import; its list of
    the instructor's commands (what a handout names as "an instructor's command") is kitlib's table.
    And the rule is seen to fail: a planted module of raykit that imports kitlib, or a package
    that is not the standard library, is reported."""
    import tempfile
    from raykit import cli as student_cli
    from kitlib import cli as instructor_cli
    if not getattr(sys, "stdlib_module_names", None):
        raise Skipped("this Python has no list of its standard library (sys.stdlib_module_names, 3.10+)")
    mods = modules()
    graph = {n: imports(n, p, set(mods)) for n, p in mods.items()}
    broken = student_rule(mods)
    expect(not broken, "the student's package reaches beyond the standard library: " + "; ".join(broken[:6]))
    left = unreached(mods, graph)
    expect(not left, f"modules of tools/raykit that no student's command imports (move them to tools/kitlib): {left}")
    elsewhere = [c.name for c in instructor_cli.COMMANDS if c.package == INSTRUCTOR_PACKAGE]
    expect(sorted(elsewhere) == sorted(student_cli.ELSEWHERE),
           f"raykit/cli.py's ELSEWHERE {sorted(student_cli.ELSEWHERE)} is not kitlib's commands {sorted(elsewhere)}")
    students = [c for c in instructor_cli.COMMANDS if c.package == STUDENT_PACKAGE]
    expect(students == student_cli.COMMANDS and all(c.audience == student_cli.STUDENT for c in students),
           "kitlib/cli.py does not list raykit's commands first, as they are")
    # The control: the same rule on planted modules.
    with tempfile.TemporaryDirectory(prefix="raykit-layers-") as tmp:
        planted = {}
        for stem, text in (("up", "from kitlib.report import pages\n"),
                           ("lazy", "def f():\n    import importlib\n    return importlib.import_module('kitlib.decks')\n"),
                           ("jinja", "import jinja2\n"), ("own", "from . import common\nimport os\n")):
            (Path(tmp) / f"{stem}.py").write_text(text)
            planted[f"raykit.{stem}"] = Path(tmp) / f"{stem}.py"
        caught = student_rule(planted)
        expect(len(caught) == 3 and not any("raykit.own" in c for c in caught),
               f"the rule on planted modules reports {caught}")
    raykit_lines = sum(len(p.read_text().splitlines()) for n, p in mods.items() if n.startswith("raykit."))
    kitlib_lines = sum(len(p.read_text().splitlines()) for n, p in mods.items() if n.startswith("kitlib."))
    return (f"raykit: {sum(n.startswith('raykit.') for n in mods)} modules, {raykit_lines} lines, standard library "
            f"only, all imported by the students' commands; kitlib: {sum(n.startswith('kitlib.') for n in mods)} "
            f"modules, {kitlib_lines} lines (self-test apart); 3 planted breaks caught")


# Renames that are not a write of the kit's own data, so not atomic.write's: per module, how many
# and what they move.
OTHER_RENAMES = {
    "raykit.studentpch": (1, "the compiler's own output (a precompiled header) moved into place"),
    "raykit.objcache": (2, "an object-cache entry's folder, swapped whole"),
    "kitlib.report.pages": (1, "a folder of pages, swapped whole"),
    "kitlib.report.merge": (1, "a merged grading folder, moved into place whole"),
    "kitlib.commands.prairielearn": (1, "a staged folder, swapped whole"),
    "kitlib.commands.handout": (1, "a staged folder, swapped whole"),
    "kitlib.webtools": (2, "a built folder (the docs site's, the decks'), swapped whole"),
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
    """One atomic write (raykit/atomic.py): no other module moves a file into place but those
    OTHER_RENAMES names; and its guarantees, shown: a link planted at the target is replaced, not
    written through; a write that fails halfway leaves the old file whole and no temporary file; a
    missing folder is an OSError; the mode is what a plain open gives, or the one asked for."""
    import tempfile
    from raykit import atomic

    counts = {n: renames(p) for n, p in modules().items() if n != "raykit.atomic"}
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
    from raykit import procfs
    scanned = [f for pkg in PACKAGES for f in (TOOLS / pkg).rglob("*.py") if "__pycache__" not in f.parts]
    readers = sorted(str(f.relative_to(TOOLS)) for f in scanned
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
    return (f"no module but procfs.py opens /proc ({len(scanned)} scanned); own fields, "
            "a child's session, its zombie and its end read right")


@pytest.mark.quick
def selftest_compiled_modules(ctx) -> str:
    """./kit compiles the kit's own modules once, into its cache folder (raykit/pycache.py), and no
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
        kit = [p for p in compiled if any((d.resolve().as_posix().lstrip("/") + "/") in p.as_posix()
                                          for d in (KITLIB, RAYKIT))]
        other = [p.relative_to(folder).as_posix() for p in compiled if p not in kit]
        expect(kit, f"no module of the kit's compiled into {folder}")
        expect(not other, f"modules other than the kit's compiled into the kit's cache: {other[:5]}")
    after = {p for p in (ROOT / "tools").rglob("__pycache__")}
    expect(after <= before, f"compiled modules written beside the kit's sources: {sorted(after - before)[:3]}")
    return f"{len(kit)} of the kit's modules compiled into its cache folder, none other, none beside the sources"

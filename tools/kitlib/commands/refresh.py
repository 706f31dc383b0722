"""./kit refresh: after a change to the course, make current what the kit records from it, then run the
self-tests the change touches.

An instructor changes course.json, the scene (include/raykit/scenes/), a step's cases or its reference,
or adds a step; several files are then derived from those and checked by ./kit test: lecture 05's
scene tables, the README's step table, the benchmark's figures that docs/bench.md and lecture 03's
appendix quote from its committed run, the reference pictures (docs/images/), the recorded stubs and
case lists, the ★ tier's exact answers and the mutants' signatures. Each is rewritten here by the
command that owns it, only when it is stale (each has a check), in an order where none reads a file a
later one writes. Then the self-tests of what changed since REV (default HEAD: the uncommitted change,
new files included) run, with the quick tier.

    ./kit refresh            rewrite what is stale, then run the touched self-tests
    ./kit refresh --plan     say what it would rewrite and run, and do nothing
    ./kit refresh --no-test  rewrite only
"""

from __future__ import annotations

import re
import subprocess
import sys
from dataclasses import dataclass

from raykit.common import ROOT, KitError, load_steps, say
from raykit.status import FAILED, OK


@dataclass(frozen=True)
class Regenerator:
    name: str           # what it makes current
    check: list[str]    # exits 0 when current (from ROOT)
    write: list[str]    # makes it current


KIT = [str(ROOT / "kit")]
PY = [sys.executable]

# In order: the pictures and the tables read the scene; the case lists and exact answers read the
# judges; the signatures read the mutants graded against all of them.
REGENERATORS = [
    Regenerator("lecture 05's scene tables", PY + ["docs/scene_tables.py", "--check"], PY + ["docs/scene_tables.py"]),
    Regenerator("the README's step table", PY + ["docs/readme_steps.py", "--check"], PY + ["docs/readme_steps.py"]),
    Regenerator("the benchmark's figures (docs/bench.md, lecture 03's appendix)",
                PY + ["docs/bench_numbers.py", "--check"], PY + ["docs/bench_numbers.py"]),
    Regenerator("the reference pictures (docs/images/)", KIT + ["test", "render:pictures current"], KIT + ["render", "--refresh"]),
    Regenerator("the recorded stubs and case lists", KIT + ["test", "latency:recorded"],
                KIT + ["check", "--record"]),
    Regenerator("the ★ tier's exact answers", KIT + ["exact"], KIT + ["exact", "--refresh"]),
    Regenerator("the mutants' signatures", KIT + ["test", "report:signatures fresh"], KIT + ["report", "--signatures"]),
]


def register(p) -> None:
    p.add_argument("--plan", action="store_true", help="say what would be rewritten and run; change nothing")
    p.add_argument("--no-test", action="store_true", help="rewrite what is stale, run no self-test")
    p.add_argument("--since", metavar="REV", default="HEAD",
                   help="the self-tests of what changed since this git revision (default HEAD: the uncommitted change)")


def changed_paths(since: str) -> list[str]:
    """The files changed since `since` in the working tree, untracked ones included."""
    git = ["git", "-C", str(ROOT)]
    diff = subprocess.run(git + ["diff", "--name-only", since, "--"], capture_output=True, text=True)
    if diff.returncode != 0:
        raise KitError(f"--since {since}: git does not know it ({diff.stderr.strip()[:200]})")
    new = subprocess.run(git + ["ls-files", "--others", "--exclude-standard"], capture_output=True, text=True)
    return sorted(set(diff.stdout.split("\n") + new.stdout.split("\n")) - {""})


def scene_steps(path: str) -> set[str]:
    """The steps that draw the scene of include/raykit/scenes/NAME.inc: those whose step.json lists
    NAME among its "scenes" (step 05 in the kit; not the last step, once an instructor adds one)."""
    import json
    name = path.rsplit("/", 1)[-1].split(".")[0]
    scenes = {s.number: json.loads((ROOT / "tests" / s.folder / "step.json").read_text()).get("scenes", [])
              for s in load_steps()}
    return {n for n, listed in scenes.items() if any(isinstance(e, dict) and e.get("name") == name for e in listed)}


def selftest_modules() -> list[str]:
    """The modules of tests/kit/ that hold self-tests (./kit test's MODULE words; a command imports no
    other command, so not commands/selftest.py's modules())."""
    return [p.stem for p in (ROOT / "tests" / "kit").glob("*.py")
            if re.search(r"^def selftest_\w+\(", p.read_text(), flags=re.M)]


def touched_tests(paths: list[str]) -> list[list[str]]:
    """The ./kit test calls the changed paths ask for: `--step N` for a step's cases, reference or
    stubs; the modules that read the course, the scene, the lectures; everything for the kit's code."""
    numbers = {s.number for s in load_steps()}
    steps, modules, everything = set(), [], False
    for p in paths:
        m = re.match(r"(?:tests|solutions|steps|tests/hidden|tests/mutants)/(\d\d)_", p) or \
            re.match(r"tests/(?:hidden|mutants)/(\d\d)_", p)
        if m and m.group(1) in numbers:
            steps.add(m.group(1))
        elif p == "course.json":
            modules += ["course", "customised"]
        elif p.startswith("include/raykit/scenes/"):
            modules += ["lectures:scene tables", "render", "pictures", "slips:turned render", "customised"]
            steps |= scene_steps(p) or {max(numbers)}
        elif p.startswith(("lectures/", "docs/")) and not p.startswith("docs/images/"):
            modules += ["lectures", "slides"]
        elif re.fullmatch(r"tests/kit/\w+\.py", p) and p[10:-3] in selftest_modules():
            modules.append(p[10:-3])        # a self-test module: itself
        elif p.startswith(("tools/", "tests/support/", "tests/kit/", "include/", "CMakeLists.txt", "cmake/")) \
                or p == "pytest.ini":
            everything = True
    if everything:
        return [[]]         # the whole self-test
    calls = [["--step", n] for n in sorted(steps)]
    if modules:
        calls.append(list(dict.fromkeys(modules)))
    return calls


def shown(argv: list[str]) -> str:
    """A command as the instructor would type it: ./kit ..., python3 docs/..."""
    if argv[0] == sys.executable:
        return "python3 " + " ".join(argv[1:])
    return "./kit " + " ".join(argv[1:])


def current(r: Regenerator) -> bool:
    return subprocess.run(r.check, cwd=ROOT, capture_output=True, text=True).returncode == 0


def rewrite(argv: list[str]) -> tuple[int, str]:
    """Runs a regenerator's command, its output shown as it comes (and kept): its exit status and
    what it said."""
    proc = subprocess.Popen(argv, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            errors="replace")
    kept = []
    for line in proc.stdout:
        sys.stdout.write(line)
        sys.stdout.flush()
        kept.append(line)
    return proc.wait(), "".join(kept)


# How many of a failed command's last lines refresh says again, under its FAILED line.
ERROR_LINES = 40


def the_error(output: str) -> str:
    """A failed command's own error, from what it said: from the kit's own "kit: ..." message or the
    first line that reads as an error (CMake's "CMake Error", a compiler's "error:"), to the end; else
    its last lines. Whole lines."""
    lines = output.rstrip().splitlines()
    marks = [i for i, line in enumerate(lines)
             if re.match(r"kit: |CMake Error|.*\berror:|.*\bError\b|FAILED:|Traceback", line)]
    start = marks[0] if marks else max(0, len(lines) - ERROR_LINES)
    if len(lines) - start > ERROR_LINES:
        start = len(lines) - ERROR_LINES
    return "\n".join(("    " + line) for line in lines[start:])


def run(args) -> int:
    if not (ROOT / "solutions").is_dir():
        raise KitError("./kit refresh rewrites what the instructor's copy records from the solutions: not in a handout")
    from .. import manifest
    # A manifest of an older form stops here, its field named (issue 55: it reached CMake, and every
    # regenerator after it ran against a broken build).
    manifest.check()
    tests = [] if args.no_test else touched_tests(changed_paths(args.since))
    for r in REGENERATORS:
        if current(r):
            say(f"  current   {r.name}")
            continue
        if args.plan:
            say(f"  stale     {r.name}: would run {shown(r.write)}")
            continue
        say(f"  stale     {r.name}: rewriting ({shown(r.write)}) ...")
        code, output = rewrite(r.write)
        if code != 0 or not current(r):
            # The first failure stops the refresh: what comes after reads what this one writes.
            why = f"{shown(r.write)} exited {code}" if code != 0 else f"{shown(r.write)} ran, but it is still stale"
            say(f"  FAILED    {r.name}: {why}; nothing after it was run. What it said:")
            say(the_error(output) if output.strip() else "    (nothing)")
            return FAILED
        say(f"  rewritten {r.name}")
    calls = [["--quick"]] + tests if tests else []
    if args.plan:
        for c in calls:
            say("  would run ./kit test " + (" ".join(c) if c else "(all of it: the kit's own code changed)"))
        return OK
    for c in calls:
        say("./kit test " + (" ".join(c) if c else "(all of it: the kit's own code changed)"))
        if subprocess.run(KIT + ["test", *c], cwd=ROOT).returncode != 0:
            say(f"not current: ./kit test {' '.join(c)} failed (its failures are listed above); the later "
                "self-tests were not run")
            return FAILED
    say("Everything the kit records from the course is current" + ("" if args.no_test else ", and the touched self-tests pass") + ".")
    return OK

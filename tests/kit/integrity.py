"""Self-test of grading's integrity: hostile submissions grade like what they answer.

Each check grades submissions from tests/fixtures/hostile/ (or the stubs, a mutant,
the solutions) the way an instructor does, `./kit check N --steps DIR --json FILE`
in a child process, under each sandbox the machine allows (bubblewrap; a dedicated
user id when root), and asserts on the JSON and the exit status:

- forge_verdicts: rewriting every verdict file it can reach changes no verdict;
- lingering_writer: a detached process that rewrites results.json and drops files
  into the kit's tree and the homes is ended, and changes nothing;
- table_of_visible_inputs: a lookup table of the visible inputs scores below the
  reference once the hidden cases are there;
- one scale: stubs, a one-slip submission and the solutions have one maximum, and
  the slip in step 04 costs step 05 nothing;
- read_answers: the solutions, build/, tests/hidden and the git objects cannot be
  read from inside the sandbox;
- read_classmate: a classmate's folder and another copy of the kit kept anywhere on
  the machine (/opt, /tmp) cannot be included at compile time nor read at run time.
- read_script: a step 05 render that reads its view rays out of its own memory, view_ray the
  stub, grades like the same step with an honest render: the stand-in's script holds no
  reference view ray;
- scratch_spy: what a hidden case's call wrote to its folder or /tmp or kept in
  memory is not there for a case whose output students see (the ★ case re-run
  alone after the hidden cases), also with a bubblewrap that cannot size its
  scratch folder; and the hidden cases run after every other.
- sleeper, slow_correct: code that sleeps, or computes correctly but slowly, just under
  each call's limit is stopped by the step's time budget, soon, and the timeouts are
  the student's, never "the kit's fault"; a case of many slow calls is the student's
  timeout too, whether the judge's bound or the kit's backstop stops it.

Each hostile fixture answers like tests/fixtures/hostile/always_miss, so "changes
nothing" is measurable: the same status for every case and the same score. Each
prints what it managed to do; that output, kept in the JSON, shows it really ran.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Callable

import pytest

from raykit import procfs
from raykit.common import BUILD, ROOT, load_steps, stage_on_reference
from raykit.status import DONE, NO_COMPILE, PARTIAL, TIMED_OUT
from . import scale
from .support import Failed, Skipped, expect, kit, need_solutions, partly_skipped
from .fixtures import fixture_dir

pytestmark = pytest.mark.security      # conftest.py: may not skip in CI

MARKER = "raykit-hostile"           # in the name of every file the hostile fixtures drop
LINGERER = "rk-lingerer"            # the process name of lingering_writer's detached writer
LINGER_WAIT = 3.0                   # seconds to wait after grading before looking again

# (folder, steps, isolation) -> (exit status, JSON bytes, seconds): each submission is
# graded once per run of the self-test, whichever check needs it first.
_graded: dict[tuple[str, tuple[str, ...], str], tuple[int, bytes, bytes, float]] = {}


def isolations() -> tuple[list[str], list[str]]:
    """The sandboxes to grade under here, and why any other was skipped."""
    from raykit.sandbox import bwrap_works

    modes, skipped = [], []
    if bwrap_works():
        modes.append("bwrap")
    else:       # in CI a failure unless .ci/run says this machine cannot (support.partly_skipped)
        skipped.append(partly_skipped("bwrap", "bwrap skipped: bubblewrap cannot run here "
                                               "(sandbox.bwrap_works() is false)"))
    if os.geteuid() == 0:
        modes.append("user")
    else:
        skipped.append(partly_skipped("root", "user skipped: the user isolation needs root"))
    return modes, skipped


def grade_json(folder: Path, numbers: list[str], isolation: str, json_path: Path | None = None,
               cache: bool = True) -> tuple[int, dict, bytes, float]:
    """`./kit check NUMBERS --steps FOLDER --json FILE --results RECORD --isolation ISOLATION`: exit
    status, Gradescope's JSON with the kit's own record (raykit/record.py) under "record", the JSON's
    bytes, seconds."""

    key = (str(folder), tuple(numbers), isolation)
    if json_path is None and cache and key in _graded:
        rc, raw, kept, took = _graded[key]
        return rc, dict(json.loads(raw), record=json.loads(kept)), raw, took
    with tempfile.TemporaryDirectory(prefix="raykit-integrity-") as tmp:
        target = json_path or Path(tmp) / "results.json"
        record_path = Path(tmp) / "record.json"
        start = time.monotonic()
        r = kit("check", *[str(int(n)) for n in numbers], "--steps", str(folder), "--json", str(target),
                "--results", str(record_path), "--isolation", isolation, "--quiet", timeout=1800)
        took = time.monotonic() - start
        if r.returncode not in (0, 1) or not target.is_file() or not record_path.is_file():
            raise Failed(f"./kit check --steps {folder.name} --isolation {isolation} exited {r.returncode}: "
                         f"{(r.stderr or r.stdout)[-800:]}")
        raw = target.read_bytes()
        kept = record_path.read_bytes()
    try:
        data = json.loads(raw)
        ok = isinstance(data, dict) and {"score", "tests", "extra_data"} <= set(data)
        data["record"] = json.loads(kept)
        ok = ok and data["record"].get("format") == "raykit-results"
    except (json.JSONDecodeError, TypeError):
        ok = False
    if not ok:
        raise Failed(f"{folder.name} ({isolation}): the results file is not what ./kit wrote: {raw[:200]!r}")
    if cache:
        _graded[key] = (r.returncode, raw, kept, took)
    return r.returncode, data, raw, took


def prewarm(folders: list[Path], numbers: list[str]) -> dict[str, float]:
    """Grades each folder under every isolation in turn, so the shared build/submission
    is rebuilt once per folder rather than once per folder and isolation; the seconds
    spent per isolation (builds included)."""
    modes, _ = isolations()
    spent = {m: 0.0 for m in modes}
    for folder in folders:
        for mode in modes:
            start = time.monotonic()
            grade_json(folder, numbers, mode)
            spent[mode] += time.monotonic() - start
    return spent


def step_results(data: dict) -> dict[str, dict]:
    return {s["step"]: s for s in data["record"]["steps"]}


def statuses(data: dict) -> list[tuple[str, str, str]]:
    return [(s["step"], c["name"], c["status"]) for s in data["record"]["steps"] for c in s["cases"]]


def printed(data: dict) -> str:
    return "\n".join(c["output"] for s in data["record"]["steps"] for c in s["cases"])


def same_as_wrong_answer(name: str, isolation: str, got: dict, rc: int, base: dict, base_rc: int,
                         own_cost: bool = False) -> None:
    """The hostile fixture `name` must grade exactly like always_miss: same statuses, score, exit.

    With `own_cost`, an attack whose own work depends on the machine (forge_verdicts walks every folder
    it can read, and a shared machine's /tmp may hold thousands) may run a case out of time: such a
    case is its own cost, not a verdict it changed, so it is left out of the comparison, and the score
    may fall below the plain wrong answer's but never rise above it."""

    expect(rc == base_rc == 1, f"{name} ({isolation}): exit {rc}, the plain wrong answer {base_rc}; both must be 1")
    if own_cost:
        slow = {(s["step"], c["name"]) for s in got["record"]["steps"] for c in s["cases"] if c["status"] == TIMED_OUT}
        expect(got["score"] <= base["score"] and (slow or got["score"] == base["score"]),
               f"{name} ({isolation}): scored {got['score']}, the same answers without the attack {base['score']}")
        got = dict(got, record=dict(got["record"], steps=[dict(st, cases=[c for c in st["cases"]
                   if (st["step"], c["name"]) not in slow]) for st in got["record"]["steps"]]))
        base = dict(base, record=dict(base["record"], steps=[dict(st, cases=[c for c in st["cases"]
                    if (st["step"], c["name"]) not in slow]) for st in base["record"]["steps"]]))
    else:
        expect(got["score"] == base["score"],
               f"{name} ({isolation}): scored {got['score']}, the same answers without the attack {base['score']}")
    changed = [(a[1], a[2], b[2]) for a, b in zip(statuses(base), statuses(got)) if a != b]
    diff = [f"{n}: {x} -> {y}" for n, x, y in changed]
    # Hidden cases are drawn from a seed made from the submission's files, so the two meet
    # different inputs; a never-hit answer fails or passes a family whatever the draw, so
    # their verdicts must still agree. Say so when only they differ.
    hidden = {c["name"] for s in base["record"]["steps"] for c in s["cases"] if c["tier"] == "hidden"}
    only_hidden = bool(changed) and all(n in hidden for n, _, _ in changed)
    seeds = (sorted({s["seed"] for s in base["record"]["steps"]}), sorted({s["seed"] for s in got["record"]["steps"]}))
    expect(statuses(got) == statuses(base) and not diff,
           f"{name} ({isolation}): case verdicts differ from the plain wrong answer: " + "; ".join(diff[:5])
           + (f" (only hidden cases differ, seeds {seeds[0]} and {seeds[1]}: does a never-hit answer's verdict "
              "on that family depend on the draw?)" if only_hidden else ""))
    expect(all(s["state"] != DONE for s in got["record"]["steps"]), f"{name} ({isolation}): graded done")
    expect(all(t["status"] == "failed" for t in got["tests"] if t["score"] == 0 and t["max_score"] > 0),
           f"{name} ({isolation}): a test with no points is marked passed")


def processes_named(word: str) -> list[str]:
    """Live processes whose name or command line holds `word`."""
    found = []
    for p in procfs.pids():
        if p == os.getpid():
            continue
        comm, cmdline = procfs.comm(p), procfs.cmdline(p)
        if (word in comm or word in cmdline) and procfs.alive(p):
            found.append(f"{p} {comm}")
    return found


def files_named(folder: Path, word: str, depth: int) -> list[Path]:
    found = []
    if depth < 0 or not folder.is_dir():
        return found
    try:
        entries = list(folder.iterdir())
    except OSError:
        return found
    for p in entries:
        if word in p.name:
            found.append(p)
        if p.is_dir() and not p.is_symlink():
            found += files_named(p, word, depth - 1)
    return found


def kit_tree() -> set[str]:
    """The kit's files outside build/ (the kit writes build/ itself while grading) and .git/ (a
    maintainer's commit during the self-test adds objects there; a file the hostile code drops
    anywhere carries MARKER in its name and is looked for apart)."""
    out = set()
    for dirpath, dirnames, filenames in os.walk(ROOT):
        rel = os.path.relpath(dirpath, ROOT)
        if rel == ".":
            dirnames[:] = [d for d in dirnames if d not in ("build", ".git")]
        out.update(os.path.join(rel, f) for f in filenames)
    return out


def run_modes(fn, spent: dict[str, float] | None = None) -> str:
    """Runs fn(isolation) -> summary under every available isolation; the summaries, with the
    seconds each isolation took (`spent`: already spent grading for it, see prewarm)."""

    need_solutions()
    modes, skipped = isolations()
    if not modes:
        raise Skipped("; ".join(skipped), need="bwrap root")
    parts = []
    for mode in modes:
        start = time.monotonic()
        summary = fn(mode)
        took = time.monotonic() - start + (spent or {}).get(mode, 0.0)
        parts.append(f"{mode}: {summary} [{took:.0f} s]")
    return "; ".join(parts + skipped)


# --- the checks ------------------------------------------------------------------------

def attack(name: str, mode: str, ran: str, harm: Callable[[str], bool], what: str, own_cost: bool = False) -> dict:
    """Checks the hostile step 01 `name` under `mode`: its output holds `ran` (the attack ran), no
    line of it shows `harm` (what it says it did: `what`), and it is scored as always_miss, a plain
    wrong answer, is. Returns its results.json."""
    base_rc, base, _, _ = grade_json(fixture_dir("hostile") / "always_miss", ["01"], mode)
    rc, got, _, _ = grade_json(fixture_dir("hostile") / name, ["01"], mode)
    out = printed(got)
    expect(ran in out, f"{name} ({mode}): its output is not in the JSON; did the attack run at all?")
    harmed = sorted({l for l in out.splitlines() if harm(l)})
    expect(not harmed, f"{name} ({mode}): the sandboxed code {what}: " + "; ".join(harmed[:6]))
    same_as_wrong_answer(name, mode, got, rc, base, base_rc, own_cost)
    return got


def selftest_forge_verdicts(ctx) -> str:
    def one(mode: str) -> str:
        got = attack("forge_verdicts", mode, "forge_verdicts:",
                     lambda l: l.startswith("forge_verdicts:") and " 0 rewritten" not in l, "rewrote files",
                     own_cost=True)
        slow = sum(c["status"] == TIMED_OUT for s in got["record"]["steps"] for c in s["cases"])
        return (f"{got['score']} of {got['extra_data']['max_score']}, as without forging"
                + (f" ({slow} cases out of time walking the machine's folders, none passed)" if slow else ""))

    need_solutions()
    spent = prewarm([fixture_dir("hostile") / "always_miss", fixture_dir("hostile") / "forge_verdicts"], ["01"])
    return run_modes(one, spent)


def selftest_lingering_writer(ctx) -> str:
    home = Path(os.environ.get("HOME") or "/root")

    def one(mode: str) -> str:
        base_rc, base, _, _ = grade_json(fixture_dir("hostile") / "always_miss", ["01"], mode)
        before = kit_tree()
        # The Gradescope flow: results in /autograder/results, made by `mkdir -p` (0755) as root.
        tmp = tempfile.mkdtemp(prefix="raykit-integrity-gs-")
        try:
            os.chmod(tmp, 0o755)
            results = Path(tmp) / "autograder" / "results"
            results.mkdir(parents=True)
            target = results / "results.json"
            rc, got, raw, _ = grade_json(fixture_dir("hostile") / "lingering_writer", ["01"], mode, json_path=target)
            expect("lingering_writer: detached a writer" in printed(got) or "lingering_writer: fork refused" in printed(got),
                   f"lingering_writer ({mode}): its output is not in the JSON; did it run at all?")
            time.sleep(LINGER_WAIT)
            alive = processes_named(LINGERER)
            after = target.read_bytes() if target.is_file() else b""
            extra = sorted(p.name for p in results.iterdir() if p.name != "results.json")
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        dropped = files_named(ROOT, MARKER, 3) + files_named(home, MARKER, 2) + files_named(Path("/home"), MARKER, 2)
        new = sorted(kit_tree() - before)
        expect(not alive, f"lingering_writer ({mode}): still running {LINGER_WAIT:g} s after grading: {alive[:5]}")
        expect(after == raw, f"lingering_writer ({mode}): results.json changed after ./kit wrote it: {after[:200]!r}")
        expect(not extra, f"lingering_writer ({mode}): new files beside results.json: {extra[:5]}")
        expect(not dropped, f"lingering_writer ({mode}): files dropped into the kit or a home: "
                            + ", ".join(str(p) for p in dropped[:5]))
        expect(not new, f"lingering_writer ({mode}): new files in the kit's tree: {new[:5]}")
        same_as_wrong_answer("lingering_writer", mode, got, rc, base, base_rc)
        return "results.json byte-identical, no process left, nothing dropped"

    summary = run_modes(one)
    return summary + "; ./kit grade: " + lingering_under_batch_grading(home)


def lingering_under_batch_grading(home: Path) -> str:
    """`./kit grade` (its own choice of isolation): the CSV and the JSON it keeps stay as written."""

    modes, _ = isolations()
    _, base, _, _ = grade_json(fixture_dir("hostile") / "always_miss", ["01"], modes[0])
    tmp = Path(tempfile.mkdtemp(prefix="raykit-integrity-batch-"))
    try:
        os.chmod(tmp, 0o755)
        shutil.copytree(fixture_dir("hostile") / "lingering_writer", tmp / "submissions" / "mallory")
        csv_path, jsons = tmp / "grades.csv", tmp / "json"
        start = time.monotonic()
        r = kit("grade", str(tmp / "submissions"), "--out", str(csv_path), "--json-dir", str(jsons), timeout=1800)
        took = time.monotonic() - start
        expect(r.returncode == 0 and csv_path.is_file(), f"./kit grade exited {r.returncode}: {r.stderr[-500:]}")
        written = {p: p.read_bytes() for p in [csv_path, *sorted(jsons.glob("*"))]}
        time.sleep(LINGER_WAIT)
        alive = processes_named(LINGERER)
        changed = [p.name for p, b in written.items() if not p.is_file() or p.read_bytes() != b]
        extra = sorted(str(p.relative_to(tmp)) for p in tmp.rglob("*") if MARKER in p.name)
        row = csv_path.read_text().splitlines()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    dropped = files_named(ROOT, MARKER, 3) + files_named(home, MARKER, 2)
    expect(not alive, f"./kit grade: the lingering writer is still running after grading: {alive[:5]}")
    expect(not changed, f"./kit grade: changed after it was written: {changed}")
    expect(not extra and not dropped, f"./kit grade: files dropped: {(extra + [str(p) for p in dropped])[:5]}")
    expect(len(row) == 2 and scale.exact(row[1].split(",")[1]) == scale.exact(base["score"]),    # "3.40" is 3.4
           f"./kit grade: the CSV gives {row[1:]} , the plain wrong answer scores {base['score']}")
    return f"grades.csv and results.json unchanged, score {base['score']} as without the attack [{took:.0f} s]"


def selftest_table_of_visible_inputs(ctx) -> str:
    def one(mode: str) -> str:
        rc, table, _, _ = grade_json(fixture_dir("hostile") / "table_of_visible_inputs", ["01"], mode)
        [step] = table["record"]["steps"]
        expect(step["basic"]["passed"] == step["basic"]["total"],
               f"table ({mode}): passes {step['basic']['passed']} of {step['basic']['total']} visible cases; "
               "the table no longer matches tests/01_unit_sphere, so it proves nothing: update it")
        if not any(c["tier"] == "hidden" for c in step["cases"]):
            raise Skipped("no hidden cases yet (the table passes every visible case: "
                          f"{step['basic']['passed']} of {step['basic']['total']})")
        _, reference, _, _ = grade_json(ROOT / "solutions", ["01"], mode)
        short = scale.record_short_of_full(reference["record"])
        expect(not short and scale.exact(reference["score"]) == scale.rounded(scale.full_total(reference["record"])),
               f"the solutions score {reference['score']} of {reference['extra_data']['max_score']}: {short or 'not the record'}")
        expect(table["score"] < reference["score"] and rc == 1,
               f"table ({mode}): scores {table['score']}, the reference {reference['score']} (exit {rc})")
        hidden = step["hidden"]
        return f"{table['score']} < {reference['score']} (hidden {hidden['passed']} of {hidden['total']})"

    return run_modes(one)


def one_slip_folder() -> Path:
    """Steps 01-05 from the solutions, with step 04's edges excluded (`<` for `<=`)."""
    steps = load_steps()
    [rect] = [s for s in steps if s.number == "04"]
    from raykit.mutants import write_answer
    slip = write_answer(rect, ROOT / "tests" / "mutants" / rect.folder / "edge_excluded.patch",
                        BUILD / "integrity-one-slip-04")
    target = stage_on_reference(BUILD / "integrity-one-slip", rect, steps, slip)
    for s in steps:
        if not (target / s.folder).exists():
            shutil.copytree(ROOT / "solutions" / s.folder, target / s.folder)
    return target


def selftest_one_scale(ctx) -> str:
    numbers = [s.number for s in load_steps()]

    def one(mode: str) -> str:
        graded = {}
        for name, folder in (("stubs", ROOT / "steps"), ("one slip", one_slip_folder()),
                             ("solutions", ROOT / "solutions")):
            _, data, _, _ = grade_json(folder, numbers, mode)
            # Each test's max_score is a decimal on the course's rounding: their sum is taken exactly (a
            # float sum of 115's shares reads 114.99999999999982), against the record's exact maximum.
            total = scale.exact_sum(t["max_score"] for t in data["tests"])
            want = scale.rounded(scale.exact(data["record"]["max_score_exact"]))
            expect(scale.exact(data["extra_data"]["max_score"]) == total == want,
                   f"{name} ({mode}): extra_data.max_score {data['extra_data']['max_score']}, tests add up to "
                   f"{scale.shown(total)}, the record's maximum is {scale.shown(want)}")
            graded[name] = data
        maxima = {n: d["extra_data"]["max_score"] for n, d in graded.items()}
        expect(len(set(maxima.values())) == 1, f"({mode}) not one scale: maxima {maxima}")
        per_step = {n: {k: v["maximum"] for k, v in step_results(d).items()} for n, d in graded.items()}
        expect(per_step["stubs"] == per_step["one slip"] == per_step["solutions"],
               f"({mode}) step maxima differ: {per_step}")
        stubs, slip, full = (step_results(graded[n]) for n in ("stubs", "one slip", "solutions"))
        expect(graded["stubs"]["score"] == 0, f"({mode}) the stubs score {graded['stubs']['score']}")
        short = scale.record_short_of_full(graded["solutions"]["record"])
        full_score = scale.rounded(scale.full_total(graded["solutions"]["record"]))
        expect(not short and scale.exact(graded["solutions"]["score"]) == full_score,
               f"({mode}) the solutions score {graded['solutions']['score']} of {maxima['solutions']}, not "
               f"{scale.shown(full_score)}: {short or 'the record and the score differ'}")
        # The slip loses counted points (its ★ cases, extra credit or not, may still pass: scale.py).
        expect(slip["04"]["state"] == PARTIAL and scale.base(slip["04"]) < scale.maximum(slip["04"]),
               f"({mode}) the slip in step 04 is not caught: {slip['04']['state']}, {slip['04']['earned']} of "
               f"{slip['04']['maximum']}")
        after = [n for n in numbers if n > "04" and "04" in next(s.needs for s in load_steps() if s.number == n)]
        for n in after:
            short = scale.short_of_full(slip[n])
            expect(slip[n]["state"] == DONE and not short,
                   f"({mode}) a correct step {n} after a slip in 04: {slip[n]['state']}, {short}")
        others = [n for n in numbers if n != "04"]
        expect(all(scale.earned(slip[n]) == scale.earned(full[n]) for n in others),
               f"({mode}) the slip in step 04 cost another step points")
        return (f"max {maxima['solutions']} for all; stubs 0, one slip {graded['one slip']['score']}, "
                f"solutions {graded['solutions']['score']}; "
                + ", ".join(f"step {n} {slip[n]['earned']} of {slip[n]['maximum']}" for n in after))

    need_solutions()
    spent = prewarm([ROOT / "steps", one_slip_folder(), ROOT / "solutions"], numbers)
    return run_modes(one, spent)


def selftest_read_answers(ctx) -> str:
    def one(mode: str) -> str:
        attack("read_answers", mode, "answer paths readable", lambda l: "could read" in l, "read the answers")
        return "nothing readable; graded like a wrong answer"

    need_solutions()
    spent = prewarm([fixture_dir("hostile") / "always_miss", fixture_dir("hostile") / "read_answers"], ["01"])
    return run_modes(one, spent)


# Where read_classmate looks (the fixture's fixed paths and the prefixes it scans).
CLASS_FOLDER = "raykit-selftest-class"     # a class handed to ./kit grade: alice (a solution) and mallory
KIT_COPY = "raykit-selftest-kit"           # another copy of the kit: its solutions/


def world_readable_copy(src: Path, dst: Path) -> None:
    """`src` copied to `dst` as a folder anyone may read (0755 folders, 0644 files): how a class
    unpacked by hand, or a kit cloned with the usual umask, is kept."""
    shutil.rmtree(dst, ignore_errors=True)
    shutil.copytree(src, dst)
    for p in [dst, *dst.rglob("*")]:
        os.chmod(p, 0o755 if p.is_dir() else 0o644)


def class_folder(top: str) -> Path:
    """A class of two under `top`: alice handed in the reference's step 01, mallory read_classmate."""
    folder = Path(top) / CLASS_FOLDER
    world_readable_copy(ROOT / "solutions" / "01_unit_sphere", folder / "alice" / "01_unit_sphere")
    world_readable_copy(fixture_dir("hostile") / "read_classmate", folder / "mallory")
    return folder


def grade_class_json(folder: Path, mode: str) -> tuple[dict, dict, float]:
    """`./kit grade FOLDER --isolation MODE`: the CSV's rows and the results record of each student,
    by name; the class folder's mode must be as it was before, after."""
    before = folder.stat().st_mode
    out = Path(tempfile.mkdtemp(prefix="raykit-integrity-class-"))
    try:
        start = time.monotonic()
        # Every compile done anew: the object cache keys a compile by the step's own files, not by
        # what an #include of an absolute path found (an object stolen under an older kit would be served).
        r = subprocess.run([str(ROOT / "kit"), "grade", str(folder), "--out", str(out / "grades.csv"),
                            "--json-dir", str(out / "json"), "--isolation", mode], cwd=ROOT, capture_output=True,
                           text=True, timeout=1800, env=dict(os.environ, RAYKIT_NO_OBJCACHE="1"))
        took = time.monotonic() - start
        expect(r.returncode == 0, f"./kit grade {folder} ({mode}) exited {r.returncode}: {r.stderr[-500:]}")
        import csv
        rows = {row["student"]: row for row in csv.DictReader((out / "grades.csv").open())}
        # Each student's record (raykit/record.py), in the shape grade_json gives: no Gradescope tests.
        data = {p.stem: {"record": rec, "score": rec["score"], "tests": []}
                for p in (out / "json").glob("*.json") if not p.name.startswith(".")     # .judged-by.json aside
                for rec in [json.loads(p.read_text())]}
    finally:
        shutil.rmtree(out, ignore_errors=True)
    after = folder.stat().st_mode
    expect(after == before, f"./kit grade {folder} ({mode}): the class folder's mode was {oct(before)}, "
                            f"is {oct(after)} after grading")
    expect({"alice", "mallory"} <= set(data), f"./kit grade {folder} ({mode}): results for {sorted(data)} only")
    return rows, data, took


def stopped_grading(folder: Path, sig: int) -> tuple[int, int, int]:
    """`./kit grade FOLDER --isolation user`, sent `sig` as soon as the class folder is closed to
    others: the folder's mode before, while closed (0 if it never was), and after the kit ended."""
    import signal as signals
    before = folder.stat().st_mode
    out = Path(tempfile.mkdtemp(prefix="raykit-integrity-stop-"))
    closed = 0
    try:
        proc = subprocess.Popen([str(ROOT / "kit"), "grade", str(folder), "--out", str(out / "grades.csv"),
                                 "--isolation", "user"], cwd=ROOT, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL, env=dict(os.environ, RAYKIT_NO_OBJCACHE="1"))
        try:
            deadline = time.monotonic() + 300
            while proc.poll() is None and time.monotonic() < deadline:
                mode = folder.stat().st_mode
                if not mode & 0o007:
                    closed = mode
                    break
                time.sleep(0.02)
            proc.send_signal(sig)
            proc.wait(timeout=900)
        finally:
            if proc.poll() is None:
                proc.send_signal(signals.SIGKILL)
                proc.wait()
    finally:
        shutil.rmtree(out, ignore_errors=True)
    return before, closed, folder.stat().st_mode


def selftest_read_classmate(ctx) -> str:
    """A classmate's step file and another copy of the kit's solutions, kept where the grader keeps
    them (under /opt, under /tmp), world-readable: read_classmate, graded beside that classmate,
    can neither #include them nor read them, and scores exactly like always_miss."""
    made = [Path(top) / name for top in ("/opt", "/tmp") for name in (CLASS_FOLDER, KIT_COPY)]

    def clear() -> None:
        for p in made:
            shutil.rmtree(p, ignore_errors=True)

    def leaks(data: dict) -> list[str]:
        return sorted({l for l in printed(data).splitlines() if l.startswith("read_classmate:") and "could" in l})

    def like_always_miss(data: dict, where: str, mode: str, base: dict, base_rc: int) -> None:
        name = f"read_classmate ({where})"
        expect("classmate or kit files readable" in printed(data),
               f"{name} ({mode}): its output is not in the JSON; did the attack run at all?")
        found = leaks(data)
        expect(not found, f"{name} ({mode}): the sandboxed code read another's files: " + "; ".join(found[:4]))
        # ./kit grade graded every step (the others missing, 0 points): step 01's part of its JSON is
        # compared; it gives no exit status per student, so always_miss's is taken.
        step01 = dict(data, tests=[t for t in data["tests"] if "step01" in t.get("tags", [])],
                      record=dict(data["record"], steps=[s for s in data["record"]["steps"] if s["step"] == "01"]))
        same_as_wrong_answer(name, mode, step01, base_rc, base, base_rc)

    def one(mode: str) -> str:
        base_rc, base, _, _ = grade_json(fixture_dir("hostile") / "always_miss", ["01"], mode)
        clear()
        try:
            if mode == "bwrap":
                # Everything at once: a class under /opt (graded) and under /tmp, a kit copy under each.
                for top in ("/opt", "/tmp"):
                    world_readable_copy(ROOT / "solutions", Path(top) / KIT_COPY / "solutions")
                    class_folder(top)
                _, data, took = grade_class_json(Path("/opt") / CLASS_FOLDER, mode)
                like_always_miss(data["mallory"], "class under /opt, kits under /opt and /tmp", mode, base, base_rc)
                expect(step_results(data["alice"])["01"]["state"] == DONE,
                       f"read_classmate (bwrap): alice's solution is not graded done: {data['alice']['score']}")
                return (f"a class under /opt and /tmp, a kit copy under each: nothing included or read, "
                        f"{data['mallory']['score']} points like always_miss ({took:.0f} s)")
            # The user isolation keeps files apart by their modes only: the class folder ./kit grade
            # is given (withheld from others while it grades) and the kit's own. Another copy of the
            # kit elsewhere is as readable as its modes make it (docs/integrity.md): not placed here.
            _, data, took = grade_class_json(class_folder("/tmp"), mode)
            like_always_miss(data["mallory"], "class under /tmp", mode, base, base_rc)
            # Stopped while it grades (Ctrl-C, a kill): the class folder's mode is put back all the same.
            import signal as signals
            for sig in (signals.SIGINT, signals.SIGTERM):
                before, closed, after = stopped_grading(Path("/tmp") / CLASS_FOLDER, sig)
                expect(closed and after == before,
                       f"./kit grade stopped by {signals.Signals(sig).name}: the class folder's mode was "
                       f"{oct(before)}, {oct(closed)} while grading, {oct(after)} after")
            shutil.rmtree(Path("/tmp") / CLASS_FOLDER)
            # The compile-time attack on a class under /opt: there the path exists but cannot be
            # opened, and both GCC and clang make that a hard error of __has_include: no compile.
            _, data, took2 = grade_class_json(class_folder("/opt"), mode)
            step = step_results(data["mallory"])["01"]
            expect(step["state"] == NO_COMPILE and "Permission denied" in step["detail"]
                   and f"{CLASS_FOLDER}/alice" in step["detail"],
                   f"read_classmate (class under /opt, {mode}): {step['state']}, {data['mallory']['score']} points: "
                   f"{step['detail'][-300:]!r}")
            return (f"a class under /tmp: nothing read, {base['score']} points like always_miss ({took:.0f} s), "
                    "its mode put back after SIGINT and SIGTERM too; "
                    f"under /opt: the #include is refused (Permission denied), 0 points ({took2:.0f} s)")
        finally:
            clear()

    need_solutions()
    return run_modes(one)


SPY_NOW = re.compile(r"scratch_spy: now ([RW](?: [0-9a-f]{8})+)")
SPY_FOUND = re.compile(r"scratch_spy: found (\d+) earlier in the folder, (\d+) in /tmp, (\d+) in memory")


def selftest_scratch_spy(ctx) -> str:
    """The oracle is the fixture's own record: the inputs it printed as "now" in the hidden cases
    must appear nowhere a student reads (the other cases' output and messages)."""

    def check(mode: str, data: dict) -> str:
        [step] = data["record"]["steps"]
        hidden, shown = set(), []
        for c in step["cases"]:
            if c["tier"] == "hidden":
                hidden |= set(SPY_NOW.findall(c["output"]))
            else:
                shown += [c["output"], *c["messages"]]
        if not any(c["tier"] == "hidden" for c in step["cases"]):
            raise Skipped("no hidden cases here, so nothing to spy on")
        expect(len(hidden) >= 24, f"scratch_spy ({mode}): only {len(hidden)} hidden inputs recorded; did it run?")
        # Under bubblewrap one answers process serves a judge's cases in turn (a re-run is a judge of
        # its own): its memory cannot reach a case students see only while the hidden cases run last.
        tiers = [c["tier"] == "hidden" for c in step["cases"]]
        expect(tiers == sorted(tiers), f"scratch_spy ({mode}): a case runs after the hidden cases: "
                                       f"{[c['name'] for c in step['cases']][tiers.index(True):][:4]}")
        [spun] = [c for c in step["cases"] if "10000 units" in c["name"]]
        found = SPY_FOUND.findall(spun["output"])
        expect(spun["status"] == "timed_out" and spun.get("runs") == 2 and found,
               f"scratch_spy ({mode}): the ★ case was not re-run after timing out, so the attack did not run: "
               f"{spun['status']}, {spun['output'][:200]!r}")
        text = "\n".join(shown)
        leaked = sorted(h for h in hidden if h in text)
        expect(not leaked, f"scratch_spy ({mode}): {len(leaked)} of the {len(hidden)} hidden inputs it met are in "
                           f"what students see, e.g. {leaked[:2]}; the re-run found {found[0]}")
        expect(found == [("0", "0", "0")], f"scratch_spy ({mode}): the re-run alone started with {found[0][0]} "
                                           f"earlier inputs in its folder, {found[0][1]} in /tmp, {found[0][2]} in memory")
        if mode == "user":      # its own folder, in one it can neither write (swap it) nor list
            expect("scratch_spy: folder mine mode 700, parent not writable and not listable" in spun["output"],
                   "scratch_spy (user): " + next((l for l in spun["output"].splitlines() if "folder" in l), "?"))
        return f"none of {len(hidden)} hidden inputs shown, the re-run started empty"

    def one(mode: str) -> str:
        _, base, _, _ = grade_json(fixture_dir("hostile") / "always_miss", ["01"], mode)
        _, data, _, _ = grade_json(fixture_dir("hostile") / "scratch_spy", ["01"], mode)
        # The ★ case it spins on is worth nothing: the score is the plain wrong answer's.
        expect(data["score"] == base["score"], f"scratch_spy ({mode}): {data['score']} points, always_miss {base['score']}")
        summary = check(mode, data)
        if mode != "bwrap":
            return summary
        os.environ["RAYKIT_BWRAP_UNSIZED"] = "1"        # sandbox.Isolation.run_env: as Debian 11's 0.4.1
        try:
            _, data, _, _ = grade_json(fixture_dir("hostile") / "scratch_spy", ["01"], mode, cache=False)
        finally:
            os.environ.pop("RAYKIT_BWRAP_UNSIZED", None)
        return summary + "; without --size: " + check("bwrap without --size", data)

    return run_modes(one)
# --- the grader's time (runcases.py, "Budgets") -----------------------------------------
BUDGET_BOUND = 120.0         # seconds: one grading of the sleeper, its build included (it may wait 10 s
                             # in the scored cases, 5 s in the ★ ones); the old kit: over 120 s for step 01
KIT_FAULT = "kit's fault"


def blamed_on_kit(data: dict) -> list[str]:
    return [f"{c['name']}: {m[:160]}" for s in data["record"]["steps"] for c in s["cases"]
            for m in c["messages"] if KIT_FAULT in m]


def not_the_students_time(data: dict) -> list[str]:
    """Cases that failed without a wrong answer (timed out, crashed, not run) whose first message
    does not say it was the student's code's time."""
    bad = []
    for s in data["record"]["steps"]:
        for c in s["cases"]:
            if c["status"] in ("pass", "fail"):
                continue
            first = c["messages"][0] if c["messages"] else ""
            if c["status"] != "timed_out" or not first.startswith(("Time out", "Not called")) or "your code" not in first:
                bad.append(f"{c['name']}: {c['status']}, {first[:160]!r}")
    return bad


def selftest_sleeper(ctx) -> str:
    """Each call sleeps 1.9 s, within its own limit: the step's budget for waiting ends it."""
    def one(mode: str) -> str:
        _, base, _, _ = grade_json(fixture_dir("hostile") / "always_miss", ["01"], mode)
        rc, got, _, took = grade_json(fixture_dir("hostile") / "sleeper", ["01"], mode)
        expect("sleeper: slept 1.9 s" in printed(got), f"sleeper ({mode}): its output is not in the JSON; did it run?")
        expect(took < BUDGET_BOUND, f"sleeper ({mode}): grading took {took:.0f} s, the bound is {BUDGET_BOUND:g} s "
                                    "(sleeping within each call's limit still costs the grader without limit)")
        expect(not blamed_on_kit(got), f"sleeper ({mode}): blamed on the kit: {blamed_on_kit(got)[:3]}")
        expect(not not_the_students_time(got), f"sleeper ({mode}): a timeout not worded as the student's: "
                                               + "; ".join(not_the_students_time(got)[:3]))
        # It answers as always_miss does until its budget is spent, then fails the rest: never more.
        ours = {n: st for _, n, st in statuses(got)}
        gained = [n for _, n, st in statuses(base) if st != "pass" and ours.get(n) == "pass"]
        expect(not gained, f"sleeper ({mode}): passes cases the plain wrong answer fails: {gained[:5]}")
        expect(got["score"] <= base["score"] and rc == 1,
               f"sleeper ({mode}): scored {got['score']}, the plain wrong answer {base['score']} (exit {rc})")
        budget = [m for s in got["record"]["steps"] for c in s["cases"] for m in c["messages"]
                  if "time budget" in m and "waited" in m]
        expect(bool(budget), f"sleeper ({mode}): no message names the step's time budget and the time waited")
        return f"{took:.0f} s, score {got['score']} (always_miss {base['score']}), the budget named"

    need_solutions()
    spent = prewarm([fixture_dir("hostile") / "always_miss", fixture_dir("hostile") / "sleeper"], ["01"])
    return run_modes(one, spent)


def selftest_slow_correct(ctx) -> str:
    """The reference's answers, 1.5 s of CPU a call: the budget ends it, the timeouts are the student's."""
    def one(mode: str) -> str:
        rc, got, _, took = grade_json(fixture_dir("hostile") / "slow_correct", ["01"], mode)
        [step] = got["record"]["steps"]
        expect(not blamed_on_kit(got), f"slow_correct ({mode}): blamed on the kit: {blamed_on_kit(got)[:3]}")
        expect(not not_the_students_time(got), f"slow_correct ({mode}): a timeout not worded as the student's: "
                                               + "; ".join(not_the_students_time(got)[:3]))
        wrong = [c["name"] for c in step["cases"] if c["status"] == "fail"]
        expect(not wrong, f"slow_correct ({mode}): correct answers judged wrong: {wrong[:5]}")
        passed = sum(c["status"] == "pass" for c in step["cases"])
        expect(passed > 0, f"slow_correct ({mode}): no case passed; its first calls are within the budget")
        budget = [m for c in step["cases"] for m in c["messages"] if "time budget" in m and "s of CPU" in m]
        expect(bool(budget), f"slow_correct ({mode}): no message names the step's time budget and the CPU used")
        # What it cost, in CPU seconds as the kit reports them (its wall time grows with the machine's
        # load): never more than the budget, which the judge enforces within a call.
        used = [(float(u), float(b)) for m in budget
                for u, b in re.findall(r"your code used ([\d.]+) s of CPU.*? may use ([\d.]+) s of CPU", m)]
        over = [f"{u:g} of {b:g} s" for u, b in used if u > b + 0.5]
        expect(bool(used) and not over, f"slow_correct ({mode}): CPU used beyond the budget: {over or budget[:1]}")
        return (f"{took:.0f} s, {passed} of {len(step['cases'])} passed, the rest the student's timeouts; "
                f"CPU used {max(u for u, _ in used):g} s of a {max(b for _, b in used):g} s budget")

    need_solutions()
    spent = prewarm([fixture_dir("hostile") / "slow_correct"], ["01"])
    return run_modes(one, spent)


def selftest_slow_case(ctx) -> str:
    """A case of many calls, each within its limit, that together take longer than a case may: the
    student's timeout, whether the judge's own bound for a case's calls stops it or, on a machine so
    busy that this bound comes late, the kit's backstop for the case. slow_correct at 0.2 s of CPU a
    call, graded in-process, unsandboxed, with 4 s a case and a step's CPU of 0.2 s for three calls a
    visible case and 24 more: the visible calls (one to four a case) pass; the first hidden family, 24
    draws, meets the bound (3.2 s of calls, or the backstop at 4 s) before the budget is spent."""
    from raykit import checking, runcases
    from raykit import course as course_file
    from raykit.checking import check_steps
    from raykit.build import submission_build

    need_solutions()
    steps = [s for s in ctx.steps if s.number == "01"]
    source = BUILD / "selftest-slow-case"
    shutil.rmtree(source, ignore_errors=True)
    shutil.copytree(fixture_dir("hostile") / "slow_correct", source)
    [cpp] = source.glob("*/*.cpp")
    text = cpp.read_text()
    expect(text.count("burn_cpu(1.5);") == 2, f"{cpp.name}: slow_correct no longer burns 1.5 s in each function")
    cpp.write_text(text.replace("burn_cpu(1.5);", "burn_cpu(0.2);"))
    scale = course_file.load()
    visible = [c for c in checking.recorded_cases(steps[0]) or [] if c.tier == "basic"]
    step_cpu = round(0.2 * (3 * len(visible) + 24))     # from the step's own cases, not a count typed here
    course = course_file.Course(**{**scale.__dict__, "limits": dict(scale.limits, case_seconds=4,
                                                                     step_cpu_seconds=step_cpu)})
    found = []
    saved = getattr(runcases, "CASE_SHARE", 0.8), checking.rerun_timeouts   # (the old kit had none)
    # 1.5: the judge's bound for a case's calls lies beyond the kit's backstop, which stops the case
    # first. The timed-out cases are not run again here, so that the message read is the first one.
    for share, words in ((saved[0], "a case may take"), (1.5, "this case was stopped after 4 s")):
        runcases.CASE_SHARE, checking.rerun_timeouts = share, lambda *a, **k: None
        start = time.monotonic()
        try:
            with course_file.using(course):
                [r] = check_steps(submission_build(source, "fixtures"), steps, ctx.steps)
        finally:
            runcases.CASE_SHARE, checking.rerun_timeouts = saved
        took = time.monotonic() - start
        kit = [m[:160] for c in r.cases for m in c.messages if KIT_FAULT in m]
        expect(not kit, f"slow_correct, {share:g} of a case to its calls: blamed on the kit: {kit[:2]}")
        hit = [c for c in r.cases if any(words in m and "your code" in m for m in c.messages)]
        expect(bool(hit) and all(c.status == "timed_out" for c in hit),
               f"slow_correct, {share:g} of a case to its calls: no case timed out with {words!r}: "
               + "; ".join(f"{c.name}: {c.status} {c.messages[:1]}" for c in r.cases if c.status != "pass")[:600])
        odd = [f"{c.name}: {c.status}" for c in r.cases if c.status not in ("pass", "timed_out")]
        expect(not odd, f"slow_correct, {share:g} of a case to its calls: {odd[:4]}")
        expect(r.passed("basic") > 0, f"slow_correct, {share:g} of a case to its calls: no visible case passed")
        found.append(f"{words!r}, {len(hit)} case(s) ({took:.0f} s)")
    shutil.rmtree(source, ignore_errors=True)
    return "the student's timeout: " + "; ".join(found)


# --- no reference code in a graded process (issue 43, 1) -------------------------------------------
STANDIN_SYMBOL = "_ZN6raykit14intersect_rectERKNS_3RayERKNS_4RectEff"     # raykit::intersect_rect


def function_bytes(program: Path, symbol: str) -> bytes:
    """The machine code of `symbol` in the ELF `program`, read through nm's address and size and
    readelf's section table (binutils: every machine that has g++)."""
    nm = subprocess.run(["nm", "-S", "--defined-only", str(program)], capture_output=True, text=True, check=True)
    found = [l.split() for l in nm.stdout.splitlines() if l.split()[-1:] == [symbol]]
    if not found or len(found[0]) < 4:
        raise Failed(f"{program.name} has no sized symbol {symbol}")
    address, size = int(found[0][0], 16), int(found[0][1], 16)
    sections = subprocess.run(["readelf", "-SW", str(program)], capture_output=True, text=True, check=True).stdout
    for line in sections.splitlines():
        words = line.replace("[ ", "[").split()
        if len(words) > 5 and words[1] == ".text":
            start, offset = int(words[3], 16), int(words[4], 16)
            data = program.read_bytes()
            return data[offset + address - start: offset + address - start + size]
    raise Failed(f"{program.name} has no .text section")


def alike(a: bytes, b: bytes) -> float:
    """The share of equal bytes, position by position, over the shorter (call offsets differ from one
    program's layout to another's; the rest of a function's code does not)."""
    n = min(len(a), len(b))
    return sum(x == y for x, y in zip(a[:n], b[:n])) / n if n else 0.0


def selftest_reference_out_of_reach(ctx) -> str:
    """A step 05 that dumps the code at &intersect_rect and asks intersect_rect questions of its own
    gets neither the reference's code nor its answers (tests/fixtures/hostile/dump_reference)."""
    def one(mode: str) -> str:
        _, got, _, _ = grade_json(fixture_dir("hostile") / "dump_reference", ["05"], mode)
        out = printed(got)
        dumps = [l.split("bytes ", 1)[1].strip() for l in out.splitlines() if l.startswith("dump_reference: bytes ")]
        expect(dumps, f"dump_reference ({mode}): its dump is not in the JSON; did the attack run at all?")
        oracle = sorted({l for l in out.splitlines() if l.startswith("dump_reference: oracle") and "refused" not in l})
        expect(not oracle, f"dump_reference ({mode}): step 04 answered its own questions: " + "; ".join(oracle))
        # The detector, checked on the kit's own programs: the reference's function in step 04's
        # reference program and in step 05's (which links it) are alike; the dump must not be.
        # The kit's side, with the reference's programs, is the bundle the grading used (bundle.py).
        from raykit import bundle
        from raykit.build import detect_undefined
        folder = bundle.ensure(detect_undefined()).folder
        expect((folder / "reference_answers_step05").is_file(), f"no reference_answers_step05 in {folder} to compare with")
        reference = function_bytes(folder / "reference_answers_step04", STANDIN_SYMBOL)
        calibration = alike(reference, function_bytes(folder / "reference_answers_step05", STANDIN_SYMBOL))
        expect(calibration >= 0.8, f"the detector cannot tell the reference's code ({calibration:.0%} alike in "
                                   "two reference programs)")
        shares = [alike(bytes.fromhex(d), reference) for d in dumps]
        expect(max(shares) < 0.5, f"dump_reference ({mode}): the code at &intersect_rect is "
                                  f"{max(shares):.0%} the reference's (the reference's in two programs: "
                                  f"{calibration:.0%})")
        return (f"3 questions refused, the code at &intersect_rect {max(shares):.0%} alike the reference's "
                f"(the reference's own in two programs: {calibration:.0%})")

    need_solutions()
    return run_modes(one)


def selftest_no_reference_answer(ctx) -> str:
    """A step 05 whose render reads the view rays scripted for the stand-in out of its own memory, with
    view_ray the stub (tests/fixtures/hostile/read_script), grades exactly like the same step with an
    honest render (hostile/view_ray_stub): the student's process holds no reference view ray, so it finds
    none, and the render cases wait on the student's own view_ray (standin.hpp, issue 52)."""
    from raykit.cases import picture_sections
    step = next(s for s in load_steps() if s.number == "05")
    pictures = picture_sections(step)

    def one(mode: str) -> str:
        base_rc, base, _, _ = grade_json(fixture_dir("hostile") / "view_ray_stub", ["05"], mode)
        rc, got, _, _ = grade_json(fixture_dir("hostile") / "read_script", ["05"], mode)
        found = [l for l in printed(got).splitlines() if l.startswith("read_script:") and "found" in l]
        expect(not found, f"read_script ({mode}): its render found rays in its memory: " + "; ".join(found[:3]))
        same_as_wrong_answer("read_script", mode, got, rc, base, base_rc)
        # Every case it fails waits on view_ray and says so first (view_ray's own cases and the render
        # cases alike: none a stand-in's refusal); the picture's cases (step.json) are among them.
        cases = [c for s in got["record"]["steps"] for c in s["cases"] if c["tier"] in ("basic", "hidden")]
        failing = [c for c in cases if c["status"] != "pass"]
        unnamed = [c["name"] for c in failing if not any("view_ray" in m for m in c["messages"][:1])]
        expect(not unnamed, f"read_script ({mode}): failing cases whose first message does not name view_ray: "
                            f"{unnamed[:5]}")
        picture = [c for c in cases if c["lecture"] in pictures]
        expect(picture and all(c["status"] != "pass" for c in picture),
               f"read_script ({mode}): the picture's cases {[c['name'] for c in picture]} did not all fail")
        return (f"{got['score']} points as view_ray_stub, {len(failing)} cases waiting on view_ray (the picture's "
                f"among them), no ray found")

    need_solutions()
    return run_modes(one)


def selftest_view_ray_one_pixel(ctx) -> str:
    """A step 05 whose view_ray crashes at pixel (1, 1) alone (tests/fixtures/view_ray_one_pixel): a
    render case asks every pixel's view ray in one call first (raykit.grid.view_ray, answers_main.cpp),
    and where that fails makes the calls one a pixel, so each render case that reaches the pixel fails
    as a crash named at view_ray(..., 1, 1), never at the one call, and a render of no such pixel passes."""
    def one(mode: str) -> str:
        _, got, _, _ = grade_json(fixture_dir("view_ray_one_pixel"), ["05"], mode)
        cases = [c for s in got["record"]["steps"] for c in s["cases"] if c["tier"] in ("basic", "hidden")]
        grid = [c["name"] for c in cases if any("raykit.grid" in m for m in c["messages"])]
        expect(not grid, f"view_ray_one_pixel ({mode}): the one call for every pixel is named to the student: "
                         f"{grid[:3]}")
        crashed = [c for c in cases if c["messages"] and re.search(r"crashed in view_ray\(.*, 1, 1\)", c["messages"][0])]
        expect(bool(crashed), f"view_ray_one_pixel ({mode}): no case's first message names the crash at pixel "
                              f"(1, 1): {[c['messages'][:1] for c in cases if c['status'] != 'pass'][:3]}")
        passed = sum(c["status"] == "pass" for c in cases)
        expect(passed > 0, f"view_ray_one_pixel ({mode}): no case passed (those that never reach pixel (1, 1))")
        return f"{len(crashed)} cases crashed at view_ray's pixel (1, 1), {passed} of {len(cases)} passed"

    need_solutions()
    return run_modes(one)


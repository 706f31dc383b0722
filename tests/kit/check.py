"""Self-tests of ./kit check: the reference passes, the stubs are not started, case names and
lecture pointers hold, manifests agree, the grader survives bad code, the command line refuses
bad input with a message."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

from raykit import record
from raykit.checking import check_steps
from raykit.runcases import RERUN_WHY, list_cases
from raykit.classroomresults import classroom
from raykit.gradescope import gradescope
from raykit.plresults import prairielearn
from raykit.scoreboard import status_cell
from raykit.common import BUILD, ROOT, load_steps, map_in_threads
from raykit.build import Build, detect_undefined, preset_build, submission_build, workflow
from raykit.status import CRASHED, DONE, FAIL, NOT_STARTED, NO_COMPILE, PARTIAL, PASS, THREW, TIMED_OUT
from .support import Context, Failed, expect, kit, need_solutions
from .fixtures import fixture_dir


def selftest_reference_builds(ctx: Context) -> str:
    need_solutions()
    # ctest runs the test programs as a student would, without the kit: each makes its scratch
    # folders under TMPDIR, here one of this test's own, and must leave nothing behind.
    with tempfile.TemporaryDirectory(prefix="raykit-ctest-tmp-") as tmp:
        r = workflow("reference", env=dict(os.environ, TMPDIR=tmp))  # the preset's settings, without --preset
        left = sorted(p.name for p in Path(tmp).iterdir())
    tail = (r.stdout + r.stderr)[-4000:]
    expect(r.returncode == 0, f"the reference build (preset reference) failed:\n{tail}")
    m = re.search(r"tests passed, (\d+) tests failed out of (\d+)", r.stdout)
    expect(m is not None and int(m.group(2)) > 0, "ctest ran no test")
    expect(not left, f"the test programs left {len(left)} folder(s) in TMPDIR: {', '.join(left[:5])}")
    return f"warnings as errors, ctest {m.group(2)} tests, nothing left in TMPDIR"


@pytest.mark.step
def selftest_solutions_pass(ctx: Context) -> str:
    need_solutions()
    ctx.reference = check_steps(preset_build("reference"), ctx.steps, ctx.steps)
    bad = []
    for r in ctx.reference:
        for c in r.cases:
            if c.status != "pass":
                bad.append(f"step {r.step.number} [{c.tier}] {c.name}: {c.status} {' '.join(c.messages)[:300]}")
        if r.state != DONE:
            bad.append(f"step {r.step.number}: {r.state} {r.detail[:500]}")
    expect(not bad, "the reference solutions fail:\n  " + "\n  ".join(bad[:10]))
    n = sum(len(r.cases) for r in ctx.reference)
    return f"{n} cases in {len(ctx.reference)} steps, both tiers"


@pytest.mark.quick
@pytest.mark.step
def selftest_stubs_not_started(ctx: Context, committed_steps) -> str:
    # The committed stubs, not steps/ (an instructor may keep answers there), in a build folder of their own.
    stubs = Build("student", BUILD / "selftest-stubs", committed_steps, committed_steps, preset="student", tools=False,
                  sanitize_student=detect_undefined())
    results = check_steps(stubs, ctx.steps, ctx.steps)
    bad = []
    for r in results:
        # A step that needs another is graded on top of the reference's answers to it.
        if r.state != NOT_STARTED:
            bad.append(f"step {r.step.number} is {r.state}")
        bad += [f"step {r.step.number} case '{c.name}' is {c.status}" for c in r.cases if c.status != NOT_STARTED]
    expect(not bad, "a shipped stub is not graded 'not started':\n  " + "\n  ".join(bad[:10]))
    n = sum(len(r.cases) for r in results)
    return f"all {n} cases of the {len(results)} shipped stubs report not_implemented (a step that needs another on top of its reference)"


@pytest.mark.step
def selftest_case_names_and_lectures(ctx: Context, kit_side) -> str:
    bad = []
    total = 0
    for step in ctx.steps:
        exe = kit_side.judge(step)
        if not exe.exists():
            raise Failed(f"step {step.number}: {exe} was not built")
        lecture = ROOT / step.lecture
        expect(lecture.is_file(), f"step {step.number}: lecture {step.lecture} is missing")
        headings = {h.strip() for h in re.findall(r"^#+\s+(.*)$", lecture.read_text(), re.M)}
        names = set()
        for c in list_cases(exe):
            total += 1
            if re.search(r"[,;*?\[\]\\]", c.name):
                bad.append(f"'{c.name}': , ; * ? [ ] \\ break doctest's and ctest's filters")
            if c.name in names:
                bad.append(f"'{c.name}' appears twice")
            names.add(c.name)
            if c.tier not in ("basic", "robust", "hidden"):
                bad.append(f"'{c.name}': tier '{c.tier}' is not basic, robust or hidden")
            if not c.lecture:
                bad.append(f"'{c.name}' names no lecture section")
            elif c.lecture not in headings:
                bad.append(f"'{c.name}' points to section '{c.lecture}', not a heading of {step.lecture}")
    expect(not bad, "\n  ".join(bad[:10]))
    return f"{total} case names are filter-safe and each points to a lecture heading that exists"


def remote_lines(steps) -> dict[str, str]:
    """Each step's RAYKIT_REMOTE lines as CMake reads them for the judge (cmake/StepManifest.cmake's
    raykit_remote_lines, from step.json's "functions"), by step number; Failed with CMake's message
    when a step's cannot be read."""
    cmake = ROOT / "cmake" / "StepManifest.cmake"
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "remote.cmake"
        lines = [f'include("{cmake}")']
        for step in steps:
            m = ROOT / "tests" / step.folder / "step.json"
            lines += [f'raykit_remote_lines("{m}" lines)', f'file(WRITE "{Path(tmp) / step.number}.inc" "${{lines}}")']
        script.write_text("\n".join(lines) + "\n")
        r = subprocess.run(["cmake", "-P", str(script)], capture_output=True, text=True)
        if r.returncode != 0:
            raise Failed(f"CMake cannot read the judge's list of functions: {(r.stdout + r.stderr).strip()[-600:]}")
        return {step.number: (Path(tmp) / f"{step.number}.inc").read_text() for step in steps}


REMOTE_LINE = re.compile(r"^RAYKIT_REMOTE\((.+?), (\w+), \(([^)]*)\), \(([^)]*)\)\)$", re.M)


def _proxy_compiles(inc: str) -> subprocess.CompletedProcess:
    """tests/support/proxies.cpp compiled (syntax only) with `inc` as its list of functions: what the
    build does with a step's list, without a build folder."""
    import shutil
    compiler = shutil.which("c++") or shutil.which("g++") or shutil.which("clang++")
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "list.inc").write_text(inc)
        headers = sorted((ROOT / "include" / "raykit").glob("*.hpp"))
        (Path(tmp) / "api.hpp").write_text("".join(f'#include "raykit/{h.name}"\n' for h in headers))
        return subprocess.run([compiler, "-std=c++17", "-fsyntax-only", f"-I{ROOT / 'include'}",
                               f"-I{ROOT / 'tests' / 'support'}", f'-DRAYKIT_REMOTE_LIST="{Path(tmp) / "list.inc"}"',
                               f'-DRAYKIT_API_HEADERS="{Path(tmp) / "api.hpp"}"', '-DRAYKIT_ANSWERS_EXE="answers"',
                               '-DRAYKIT_REFERENCE_EXE="reference"', str(ROOT / "tests" / "support" / "proxies.cpp")],
                              capture_output=True, text=True, timeout=300)


@pytest.mark.step
def selftest_remote_lists(ctx: Context) -> str:
    """The judge's list of each step's functions, read by CMake from step.json's "functions", names
    exactly those functions; a signature that is not its header's stops the compile with the function's
    name; a manifest entry without its return type stops the configure; and CMake reads step.json's
    lists (cmake/StepManifest.cmake, string(JSON)) as Python's json module does."""
    bad = []
    texts = remote_lines(ctx.steps)
    for number, text in texts.items():
        step = next(s for s in ctx.steps if s.number == number)
        names = [m.group(2) for m in REMOTE_LINE.finditer(text)]
        if names != step.functions or len(text.splitlines()) != len(names):
            bad.append(f"step {number}: the judge's list names {names}, step.json {step.functions}:\n{text}")
    # It can fail: a signature its header does not declare; a manifest entry without its return type.
    first = texts[ctx.steps[0].number]
    m = REMOTE_LINE.search(first)
    expect(m is not None, f"no RAYKIT_REMOTE line for step {ctx.steps[0].number}: {first!r}")
    drifted = f"RAYKIT_REMOTE({m.group(1)}, {m.group(2)}, ({m.group(3) + ', ' if m.group(3) else ''}int extra), " \
              f"({m.group(4) + ', ' if m.group(4) else ''}extra))\n"
    right, wrong = _proxy_compiles(first), _proxy_compiles(drifted)
    expect(right.returncode == 0, f"proxies.cpp does not compile with step {ctx.steps[0].number}'s list: {right.stderr[-600:]}")
    expect(wrong.returncode != 0 and f"entry for {m.group(2)} has another signature" in wrong.stderr,
           f"a signature its header does not declare went through: {wrong.stderr[-400:]}")
    with tempfile.TemporaryDirectory() as tmp:
        fake = Path(tmp) / "tests" / "99_none"
        fake.mkdir(parents=True)
        (fake / "step.json").write_text(json.dumps({"title": "x", "files": ["x.cpp"],
                                                   "functions": [{"name": "no_return", "parameters": []}]}))
        script = Path(tmp) / "fail.cmake"
        script.write_text(f'include("{ROOT / "cmake" / "StepManifest.cmake"}")\n'
                          f'raykit_remote_lines("{fake / "step.json"}" lines)\n')
        r = subprocess.run(["cmake", "-P", str(script)], capture_output=True, text=True)
        said = " ".join(r.stderr.split())      # CMake wraps a long message's lines
        expect(r.returncode != 0 and "no \"returns\"" in said and "step.json" in said,
               f"a manifest entry without its return type went through: {(r.stdout + r.stderr)[-300:]}")
    cmake = ROOT / "cmake" / "StepManifest.cmake"
    with tempfile.TemporaryDirectory() as tmp:
        script = Path(tmp) / "read.cmake"
        lines = [f'include("{cmake}")']
        for step in ctx.steps:
            m = ROOT / "tests" / step.folder / "step.json"
            lines += [f'raykit_manifest_list("{m}" files f)', f'raykit_manifest_list("{m}" needs n)',
                      f'message(STATUS "{step.number}|${{f}}|${{n}}")']
        script.write_text("\n".join(lines) + "\n")
        r = subprocess.run(["cmake", "-P", str(script)], capture_output=True, text=True)
        got = dict(line.strip("- ").split("|", 1)[0:1] + [line.split("|", 1)[1]]
                   for line in (r.stdout + r.stderr).splitlines() if "|" in line)
    for step in ctx.steps:
        want = f"{';'.join(step.files)}|{';'.join(step.needs)}"
        if got.get(step.number) != want:
            bad.append(f"step {step.number}: CMake reads {got.get(step.number)!r}, json says {want!r}")
    expect(not bad, "\n  ".join(bad))
    return (f"{len(ctx.steps)} steps: the judge's functions are step.json's; a signature not its header's is "
            "refused by the compiler with the function's name, an entry without its return type by CMake; CMake "
            "reads the manifests as json does")


def selftest_solution_copied_is_done(ctx: Context) -> str:
    need_solutions()
    r = kit("check", "--steps", "solutions")
    expect(r.returncode == 0, f"./kit check --steps solutions exited {r.returncode}:\n{r.stdout[-2000:]}")
    expect("done" in r.stdout, "the scoreboard does not say done")
    return "./kit check --steps solutions: every step done, exit 0"


FIXTURES = {
    # folder: (state, a case status that must appear, some cases must still pass)
    "wrong": (PARTIAL, FAIL, True),
    "crash": (PARTIAL, CRASHED, True),
    "hang": (PARTIAL, TIMED_OUT, True),
    "throw": (PARTIAL, THREW, True),
    "flood": (PARTIAL, CRASHED, True),
    "no_compile": (NO_COMPILE, None, False),
}


def selftest_grader_fixtures(ctx: Context) -> str:
    need_solutions()
    steps = [s for s in ctx.steps if s.number == "01"]
    seen = []
    for name, (state, status, some_pass) in FIXTURES.items():
        source = fixture_dir(name)
        [r] = check_steps(submission_build(source, "fixtures"), steps, ctx.steps)
        expect(r.state == state, f"fixture {name}: graded {r.state}, expected {state}")
        if status:
            expect(any(c.status == status for c in r.cases), f"fixture {name}: no case is {status}")
        if status == TIMED_OUT:
            # An endless loop: the first case that timed out was run again alone, timed out again and
            # says so; after it every call gets a fraction of a second of CPU (remote.cpp, Budget::
            # looped), so the others are not run again, and the loop costs its step about one call's
            # limit, not its budget: measured in CPU seconds, whatever the machine's load.
            timed = [c for c in r.cases if c.status == TIMED_OUT]
            odd = [f"{c.name}: {c.runs} runs, {c.rerun}" for c in timed[:1]
                   if not (c.runs == 2 and c.rerun and c.rerun["first"]["status"] == TIMED_OUT)]
            odd += [f"{c.name}: {c.runs} runs" for c in timed[1:] if c.runs != 1]
            expect(not odd, f"fixture {name}: not one timed-out case run again: {odd[:2]}")
            spent = (r.cost or {}).get("cpu", 0.0)
            bound = 2 * 2.0 + 0.2 * (len(timed) + 1) + 2.0
            expect(spent <= bound, f"fixture {name}: the loop cost its step {spent:.1f} s of CPU, beyond the "
                                   f"{bound:.1f} s of two full calls and a fifth of a second for each other case")
            later = [c for c in timed[1:] if not any("0.2 s of CPU" in m for m in c.messages)]
            expect(not later, f"fixture {name}: a later time-out does not say calls get 0.2 s after a loop: "
                              f"{later[0].messages if later else ''}")
        if some_pass:
            expect(r.passed("basic") > 0, f"fixture {name}: grading stopped, no other case passed")
        # A crash, time-out or throw is data in the record: the function called (one of the step's)
        # and the signal that ended the program, when one did (the class report groups by them).
        if status in (CRASHED, TIMED_OUT, THREW):
            bad = [f"{c.name}: {c.incident}" for c in r.cases if c.status == status and not (
                c.incident and c.incident.get("function") in steps[0].functions
                and (c.incident.get("signal") == "" or (status == CRASHED and
                                                          re.fullmatch(r"SIG[A-Z]+", c.incident["signal"]))))]
            expect(not bad, f"fixture {name}: {status} cases without their call's function and signal recorded: "
                            f"{bad[:2]}")
        seen.append(name)
    r = kit("check", "1", "--steps", str(fixture_dir("wrong")))
    expect(r.returncode == 1, f"a wrong answer must exit 1, got {r.returncode}")
    expect("window: a root exactly at tmin counts" in r.stdout and "section" in r.stdout,
           "the scoreboard does not name the first failing case and its lecture section")
    return "reported per case and graded on: " + ", ".join(seen)


def selftest_rerun_recorded(ctx: Context) -> str:
    """tests/fixtures/timeout_once: its first call loops, so one case times out, is run again alone
    (runcases.rerun_timeouts) and passes. The record says so for that case only (runs, why, the
    first run's verdict, which run is shown), the terminal's row counts it, and none of the outputs
    students get (Gradescope's, even revealed, PrairieLearn's, Classroom's) carries the first run."""
    need_solutions()
    steps = [s for s in ctx.steps if s.number == "01"]
    [r] = check_steps(submission_build(fixture_dir("timeout_once"), "fixtures"), steps, ctx.steps)
    cases = record.cases(record.make([r], 0.0))
    again = [c for c in cases if c.get("runs") != 1 or "rerun" in c]
    expect(len(again) == 1, f"timeout_once: {len(again)} cases recorded as run again, not 1: "
                            + "; ".join(f"{c['name']} {c['status']} runs {c.get('runs')}" for c in again[:4]))
    [c] = again
    rerun = c.get("rerun") or {}
    first = rerun.get("first") or {}
    expect(c["runs"] == 2 and rerun.get("why") == RERUN_WHY and first.get("status") == TIMED_OUT
           and c["status"] == PASS and rerun.get("kept") == 2,
           f"timeout_once: {c['name']}: {c['status']}, runs {c['runs']}, rerun {rerun}")
    expect(r.state == DONE, f"timeout_once: graded {r.state}, but its one timeout passed when run again")
    _, extra = status_cell(r)
    expect("1 case(s) timed out and were run again, 1 then passed" in extra, f"the terminal's row: {extra!r}")
    words = [m for m in first.get("messages", []) if m.strip()]
    expect(bool(words), f"timeout_once: the first run's verdict has no words: {first}")
    shown = json.dumps([gradescope([r], 0.0, "visible", reveal=True), prairielearn([r]), classroom([r])],
                       ensure_ascii=False)
    leaked = [m for m in words if json.dumps(m, ensure_ascii=False)[1:-1] in shown]
    expect(not leaked, f"timeout_once: students' outputs carry the first run's words: {leaked[:1]}")
    return f"{c['name']!r}: timed out, run again, passed; recorded, counted on the terminal, not shown to students"


def selftest_command_line(ctx: Context) -> str:
    for args, words in [(["check", "99"], "no step"), (["frobnicate"], "invalid choice"),
                        (["check", "--steps", "/nonexistent/folder"], "no such folder"),
                        (["check", "--bogus"], "unrecognized"),
                        (["render", "--size", "-5x10"], "the width is -5 pixels")]:
        r = kit(*args, timeout=60)
        expect(r.returncode == 2, f"./kit {' '.join(args)} exited {r.returncode}, expected 2")
        expect(words in r.stderr, f"./kit {' '.join(args)}: message lacks '{words}': {r.stderr[-300:]}")
    return "bad commands, options, steps and folders: message and exit 2"


def selftest_student_loop(ctx: Context) -> str:
    """What a student meets in a handout, as issue 13's trial did it: a printing slip shows its
    output under the case; two slips in two functions, --all lists both; a crash names the call and
    the signal; a function missing at link time is named; ./kit reset keeps the student's file."""
    need_solutions()
    where = BUILD / "loop-handout"
    shutil.rmtree(where, ignore_errors=True)
    r = kit("handout", str(where), "--committed", timeout=600)
    expect(r.returncode == 0, f"./kit handout failed:\n{r.stdout[-800:]}{r.stderr[-800:]}")
    step = ctx.steps[0]
    mine = where / "steps" / step.folder / step.files[0]
    wrong = (fixture_dir("wrong") / step.folder / step.files[0]).read_text()

    def check(text: str, *args: str) -> subprocess.CompletedProcess:
        mine.write_text(text)
        return subprocess.run([str(where / "kit"), "check", "1", *args], cwd=where, capture_output=True,
                              text=True, timeout=600)

    head = "std::optional<float> intersect_unit_sphere(const Ray& ray, float tmin, float tmax) {\n"
    expect(head in wrong, "tests/fixtures/wrong no longer has the line this self-test edits")
    r = check(wrong.replace(head, head + '    std::printf("raykit-debug tmin=%g\\n", tmin);\n', 1))
    expect(r.returncode == 1 and "your code printed (" in r.stdout and "| raykit-debug tmin=" in r.stdout,
           f"printf output is not shown under the failing case:\n{r.stdout[-1500:]}")
    tangent = "if (disc == 0.0f) return {1, "
    expect(tangent in wrong, "tests/fixtures/wrong no longer has the tangent line this self-test edits")
    two = wrong.replace(tangent, "if (disc == 0.0f) return {2, ", 1)
    r = check(two, "--all")
    groups = dict(re.findall(r"^\s+(\w+): (\d+) failing case", r.stdout, re.M))
    expect({"unit_sphere_roots", "intersect_unit_sphere"} <= set(groups),
           f"--all does not list both slips by function (found {groups}):\n{r.stdout[-1500:]}")
    r = check(two)
    expect(len(re.findall(r"^\s+✗ .*\[", r.stdout, re.M)) == 1,
           f"without --all, another case than the first failing one is shown:\n{r.stdout[-1500:]}")
    r = check((fixture_dir("crash") / step.folder / step.files[0]).read_text())
    # The student's own build has the sanitizers: UBSan names the null load and the line; without
    # them (a compiler that cannot link them) the signal is named.
    expect(re.search(r"(crashed|undefined behaviour) in intersect_unit_sphere\(ray\{origin .*"
                     r"(SIGSEGV|null pointer.*unit_sphere\.cpp:\d+)", r.stdout) is not None,
           f"a crash does not name the call and the signal or the sanitizer's reason:\n{r.stdout[-1500:]}")
    solution = (ROOT / "solutions" / step.folder / step.files[0]).read_text()
    # An endless recursion is named from where the stack ran out (answers_main.cpp), not as any
    # bad access: a function of the student's own that calls itself deeper on every call.
    head_at = solution.index("std::optional<float> intersect_unit_sphere(")
    body_at = solution.index("{", head_at) + 1
    recursion = (solution[:head_at] + "float deeper(int n) {\n    volatile char pad[64];\n    pad[0] = static_cast<char>(n);\n"
                 "    return n < 0 ? 0.0f : deeper(n + 1) + pad[0];\n}\n\n" + solution[head_at:body_at]
                 + "\n    if (tmin >= 0.0f) return deeper(0);" + solution[body_at:])
    r = check(recursion)
    expect(re.search(r"crashed in intersect_unit_sphere\(.*its stack ran out, \d+ MiB of calls deep", r.stdout)
           is not None and "raykit-fault" not in r.stdout,
           f"an endless recursion is not named as the stack running out:\n{r.stdout[-1500:]}")
    r = check(solution.replace("intersect_unit_sphere(const Ray&", "intersect_unit_spher(const Ray&", 1))
    expect("no definition of" in r.stdout and "raykit::intersect_unit_sphere(" in r.stdout,
           f"a missing function is not named:\n{r.stdout[-1500:]}")
    # ./kit reset: refuses without a terminal, then keeps the student's file and puts the stub back.
    mine.write_text(two)
    reset = subprocess.run([str(where / "kit"), "reset", "1"], cwd=where, capture_output=True, text=True,
                           stdin=subprocess.DEVNULL, timeout=60)
    expect(reset.returncode == 2 and "--yes" in reset.stderr, f"reset without a terminal: {reset.stderr[-300:]}")
    reset = subprocess.run([str(where / "kit"), "reset", "1", "--yes"], cwd=where, capture_output=True,
                           text=True, timeout=60)
    kept = list(mine.parent.glob(mine.name + ".bak-*"))
    stub = (where / "tools" / "stubs" / step.folder / step.files[0]).read_text()
    expect(reset.returncode == 0 and len(kept) == 1 and kept[0].read_text() == two and mine.read_text() == stub,
           f"./kit reset 1 --yes: {reset.stdout[-400:]} kept {[k.name for k in kept]}")
    shutil.rmtree(where, ignore_errors=True)
    return ("in a handout: printf shown under the case, two slips listed by --all, a crash named with its "
            "call and signal, an endless recursion as its stack running out, a missing function named, reset keeps "
            "the student's file")


def selftest_all_and_piped(ctx: Context) -> str:
    """`./kit check N --all` lists the basic cases first and marks each ★ case after them; with its
    output in a pipe, `./kit check` prints its progress as plain lines (no carriage return, no escape)."""
    need_solutions()
    import time
    textbook_02 = fixture_dir("textbook/02_general_sphere/general_sphere.cpp")
    folder = BUILD / "selftest-check-all" / "02_general_sphere"
    folder.mkdir(parents=True, exist_ok=True)
    # The float textbook formula fails ★ cases; a tangent taken for a miss fails basic ones. A new
    # comment each run makes the build do something, so its progress has something to say.
    text = textbook_02.read_text().replace("!(disc >= 0.0f)) return {};", "!(disc > 0.0f)) return {};")
    expect("!(disc > 0.0f)" in text, f"{textbook_02} has changed: the slip of a tangent taken for a miss is not made")
    (folder / "general_sphere.cpp").write_text(f"// {time.time()}\n" + text)
    r = kit("check", "2", "--steps", str(folder.parent), "--all")
    lines = r.stdout.split("\nNext: ")[0].splitlines()      # the --all list, not the next case shown
    cases = [(i, l) for i, l in enumerate(lines) if re.match(r"^\s+✗ ", l)]
    starred = [i for i, l in cases if "★" in l]
    plain = [i for i, l in cases if "★" not in l]
    expect(bool(starred) and bool(plain), f"--all lists no ★ case, or no basic one:\n{r.stdout[-2000:]}")
    expect(max(plain) < min(starred), f"--all lists a basic case after a ★ one:\n{r.stdout[-2000:]}")
    expect("\r" not in r.stdout and "\033[" not in r.stdout,
           f"./kit check into a pipe moves the cursor:\n{r.stdout[:600]!r}")
    expect(re.search(r"^\s+02\s+compiling your code", r.stdout, re.M) is not None,
           f"./kit check into a pipe prints no progress line while it builds:\n{r.stdout[:800]}")
    return f"--all: {len(plain)} basic case(s) first, {len(starred)} ★ case(s) after, marked; piped progress plain"


@pytest.mark.quick
def selftest_handout_pointers(ctx: Context) -> str:
    """A lecture's pointer to a file a handout lacks (lecture 03's appendix: solutions/, the exact-root
    header, the reference build, the textbook fixtures) says, in the handout, that the instructor's
    copy has it; pointers to files a handout has are left as they are."""
    need_solutions()
    from kitlib.commands import handout
    shipped = {r.as_posix() for r in handout.kit_files() if not handout.excluded(r)}
    folders = {"/".join(f.split("/")[:i]) for f in shipped for i in range(1, f.count("/") + 1)}

    def has(rel: str) -> bool:
        return rel in shipped or rel in folders

    marked, dangling = 0, []
    for lecture in sorted((ROOT / "lectures").glob("*.md")):
        text, n = handout.mark_missing_pointers(lecture.read_text(), has)
        marked += n
        for line in text.splitlines():
            for span in re.finditer(r"`([^`\n]+)`(.{0,%d})" % len(handout.INSTRUCTOR_ONLY), line):
                paths = handout._POINTER.findall(span.group(1))
                lacking = [q for q in paths if q.startswith("build/reference")
                           or (not q.startswith("build/") and not has(q.rstrip("/.")))]
                if lacking and span.group(2) != handout.INSTRUCTOR_ONLY:
                    dangling.append(f"{lecture.name}: `{span.group(1)}`")
    appendix, n = handout.mark_missing_pointers((ROOT / "lectures" / "03-appendix.md").read_text(), has)
    expect(f"`tests/support/reference_roots.hpp`{handout.INSTRUCTOR_ONLY}" in appendix,
           "lecture 03's appendix still points a handout's reader to tests/support/reference_roots.hpp unmarked")
    expect(not dangling, "a handout's lecture points to a file it lacks: " + "; ".join(dangling[:4]))
    again, twice = handout.mark_missing_pointers(appendix, has)
    expect(twice == 0 and again == appendix, "marking a lecture twice adds the note twice")
    return f"{marked} pointer(s) to files a handout lacks marked as the instructor's, none left unmarked"


# A step file that uses the standard library without including what it uses: it must compile on
# every standard library the kit meets (libstdc++ on the grader, libc++ on a Mac), or the same file
# gets two verdicts. include/raykit/ray.hpp brings the headers; without them this file compiles
# nowhere, or on one library and not the other.
NO_INCLUDES = """#include "raykit/unit_sphere.hpp"
namespace raykit {
float probe(const Ray& ray) {
    float xs[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
    float m = *std::min_element(xs, xs + 3);
    std::sort(xs, xs + 3);
    m = std::clamp(m, 0.0f, 1.0f);
    std::tuple<float, float> t{m, xs[0]};
    float copy = 0;
    std::memcpy(&copy, &xs[1], sizeof copy);
    auto twice = [](float v) { return v * 2; };
    std::array<float, 2> a{std::get<0>(t), copy};
    std::vector<float> v(a.begin(), a.end());
    const std::pair<float, float> p = std::make_pair(v[0], twice(v[1]));
    std::printf("%g", static_cast<double>(std::accumulate(v.begin(), v.end(), 0.0f)));
    return p.first + p.second + static_cast<float>(std::abs(-1)) + static_cast<float>(UINT32_C(1));
}
}  // namespace raykit
"""


@pytest.mark.quick
def selftest_one_verdict_per_library(ctx) -> str:
    libraries = [("g++ (libstdc++)", ["g++"]), ("clang++ (libstdc++)", ["clang++"]),
                 ("clang++ -stdlib=libc++", ["clang++", "-stdlib=libc++"])]
    with tempfile.TemporaryDirectory(prefix="raykit-stdlib-") as tmp:
        probe = Path(tmp) / "probe.cpp"
        probe.write_text(NO_INCLUDES)
        bare = Path(tmp) / "bare"          # the kit's headers without the standard headers ray.hpp brings
        shutil.copytree(ROOT / "include", bare)
        ray = bare / "raykit" / "ray.hpp"
        text = ray.read_text()
        start, end = text.index("#include <algorithm>"), text.index("#include <vector>") + len("#include <vector>")
        ray.write_text(text[:start] + text[end:])
        usable, told = [], []
        for name, cxx in libraries:
            empty = Path(tmp) / "empty.cpp"
            empty.write_text("#include <vector>\nint main() { return std::vector<int>{0}[0]; }\n")
            if shutil.which(cxx[0]) is None or subprocess.run(cxx + ["-std=c++17", str(empty), "-o",
                                                                      str(Path(tmp) / "e")],
                                                             capture_output=True, timeout=120).returncode != 0:
                told.append(f"{name}: not installed")
                continue
            usable.append(name)

            def compiles(include: Path) -> tuple[bool, str]:
                r = subprocess.run(cxx + ["-std=c++17", "-fsyntax-only", "-Wall", "-Wextra", "-I", str(include),
                                          str(probe)], capture_output=True, text=True, timeout=120)
                return r.returncode == 0, r.stdout + r.stderr
            ok, text_ = compiles(ROOT / "include")
            expect(ok, f"{name}: a step file using the standard library without its includes does not compile "
                       f"with the kit's headers:\n{text_[-800:]}")
            ok_bare, _ = compiles(bare)
            expect(not ok_bare, f"{name}: the probe compiles without the headers ray.hpp brings: it tests nothing")
            told.append(f"{name}: compiles (and not without them)")
    expect(len(usable) >= 2, f"fewer than two standard libraries to compare here: {told}")
    return "; ".join(told)




def with_compiler(env: dict[str, str], fn):
    """fn() with CXX, CXXFLAGS and LDFLAGS set as `env` says (CMake reads them when it first
    configures a build folder; each compiler here has a folder of its own)."""
    import os
    saved = {k: os.environ.get(k) for k in ("CXX", "CXXFLAGS", "LDFLAGS")}
    try:
        for k in saved:
            os.environ.pop(k, None)
        os.environ.update(env)
        return fn()
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def selftest_missing_include_told(ctx, committed_steps) -> str:
    """One verdict on every standard library (#36 item 2): a step file using std::make_unique
    without #include <memory> compiles on libc++ (a Mac's) and not on libstdc++ (the grader's). The
    student's own check with clang and libc++ says which header to add under the step (done, and
    the line); the grader's check with GCC fails to compile and its error's first line, the one
    Gradescope and PrairieLearn show, is that same line. The kit's headers count: the probe above
    (min_element, sort, clamp, tuple, memcpy, ...) is told nothing with them, and each of those
    names with the headers ray.hpp brings taken out; std::function, which ray.hpp leaves out (its
    cost), is told <functional> with the kit's headers as they are."""
    import json
    from raykit import includes
    from raykit.build import Build
    from raykit.common import load_steps
    from raykit.scoreboard import compile_errors
    need_solutions()    # tests/fixtures/ is not in a handout
    all_steps = load_steps()
    [step] = [s for s in all_steps if s.number == "01"]
    shipped = [f for s in all_steps for f in includes.step_findings(committed_steps, s.folder, s.files, ROOT / "include")
               + includes.step_findings(ROOT / "solutions", s.folder, s.files, ROOT / "include")]
    expect(not shipped, f"a shipped stub or solution is told to include a header: {shipped[:2]}")
    want = includes.step_findings(fixture_dir("missing_include"), step.folder, step.files, ROOT / "include")
    expect(len(want) == 1 and "<memory>" in want[0] and "std::make_unique" in want[0],
           f"the fixture should be told one header, <memory>: {want}")
    with tempfile.TemporaryDirectory(prefix="raykit-includes-") as tmp:
        probe = Path(tmp) / "probe.cpp"
        probe.write_text(NO_INCLUDES)
        told = includes.findings(probe, "probe.cpp", ROOT / "include")
        expect(not told, f"the probe is told headers the kit's ray.hpp brings: {[f.text() for f in told]}")
        bare = Path(tmp) / "bare"
        shutil.copytree(ROOT / "include", bare)
        ray = bare / "raykit" / "ray.hpp"
        text = ray.read_text()
        start, end = text.index("#include <algorithm>"), text.index("#include <vector>") + len("#include <vector>")
        ray.write_text(text[:start] + text[end:])
        probe.write_text(NO_INCLUDES.replace("return p.first", "std::function<float(float)> f;\n    return p.first"))
        told = {f.name: f.header for f in includes.findings(probe, "probe.cpp", ROOT / "include")}
        expect(told == {"function": "<functional>"}, f"std::function is told {told}, not <functional> alone")
        probe.write_text(NO_INCLUDES)
        told = {f.name: f.header for f in includes.findings(probe, "probe.cpp", bare)}
        for name, header in (("min_element", "<algorithm>"), ("sort", "<algorithm>"), ("clamp", "<algorithm>"),
                             ("tuple", "<tuple>"), ("memcpy", "<cstring>")):
            expect(told.get(name) == header, f"without ray.hpp's headers, std::{name} is told {told.get(name)}, "
                                             f"not {header}")
    libcxx = {"CXX": "clang++", "CXXFLAGS": "-stdlib=libc++", "LDFLAGS": "-stdlib=libc++"}
    empty = subprocess.run(["clang++", "-stdlib=libc++", "-std=c++17", "-x", "c++", "-", "-o", "/dev/null"],
                           input="#include <memory>\nint main() { return *std::make_unique<int>(0); }\n",
                           capture_output=True, text=True, timeout=120) if shutil.which("clang++") else None
    if empty is None or empty.returncode != 0:
        raise Failed("clang++ with libc++ is needed (packages.py's libcxx group, which ./kit test installs)")
    # The student's own check: their steps folder built as ./kit check builds it, with clang and libc++.
    own = Build("stdlib-libcxx", BUILD / "stdlib-libcxx", fixture_dir("missing_include"), fixture_dir("missing_include"), preset="student",
                tools=False)
    [mac] = with_compiler(libcxx, lambda: check_steps(own, [step], all_steps))
    expect(mac.state == DONE and mac.includes == want,
           f"with libc++: {mac.state}, told {mac.includes} (expected done, told {want})")
    import contextlib
    import io
    from raykit.scoreboard import scoreboard
    screen = io.StringIO()
    with contextlib.redirect_stdout(screen):        # the words on the student's screen
        scoreboard([mac], fixture_dir("missing_include"))
    expect(want[0] in screen.getvalue(), f"./kit check does not show the line: {screen.getvalue()[-800:]}")
    # The grader: the same folder graded as a submission, with GCC.
    [grader] = with_compiler({"CXX": "g++"}, lambda: check_steps(submission_build(fixture_dir("missing_include"), "stdlib-gcc"),
                                                                 [step], all_steps))
    expect(grader.state == NO_COMPILE, f"with GCC the fixture is {grader.state}, expected does not compile")
    first = compile_errors(grader.detail)[0]
    expect(first == want[0], f"the grader's first error line is {first!r}, not the student's {want[0]!r}")
    expect(all(c.messages == ["does not compile: " + want[0]] for c in grader.cases),
           f"a case's message is {grader.cases[0].messages}")
    expect("'<memory>'" in grader.detail or "‘<memory>’" in grader.detail or "<memory>" in grader.detail,
           "GCC's own error is kept below the line")
    json.dumps(grader.to_json())
    return (f"libc++: done, told \"{want[0][:70]}...\"; GCC: does not compile, its first error line the same; "
            "the kit's headers count, and each probe name is told its header without them")



# abs on a float, unqualified, in namespace raykit and in a helper outside it: 0.5 for -0.5f with
# a float abs, 0 with C's int abs.
ABS_PROBE = """#include "raykit/rect.hpp"
namespace raykit {
float in_raykit(float da) { return abs(da); }
}  // namespace raykit
static float outside(float da) { return abs(da); }
int main() { std::printf("%g %g\\n", static_cast<double>(raykit::in_raykit(-0.5f)), static_cast<double>(outside(-0.5f))); }
"""


def selftest_abs_one_verdict(ctx) -> str:
    """One verdict on every standard library (#45 item 5): `abs(da)` on a float called C's int abs
    with libstdc++ (0 for -0.5) and the float overload with libc++, so a step 04 done on a Mac failed
    on the Linux grader. include/raykit/ray.hpp brings std::abs's overloads into the global namespace
    for step files. A probe compiled and run with each library gives 0.5 with the kit's headers, and
    GCC's gives 0 without that declaration (so the probe tests it); then tests/fixtures/stdlib_abs/
    is graded as the student's own check with clang and libc++ (a Mac's) and as the grader's with
    GCC: done on both, every case with the same status."""
    from raykit.build import Build
    from raykit.common import load_steps
    need_solutions()    # tests/fixtures/ is not in a handout
    libraries = [("g++ (libstdc++)", ["g++"]), ("clang++ -stdlib=libc++", ["clang++", "-stdlib=libc++"])]
    if shutil.which("clang++") is None or subprocess.run(
            ["clang++", "-stdlib=libc++", "-std=c++17", "-x", "c++", "-", "-o", "/dev/null"],
            input="#include <vector>\nint main() { return std::vector<int>{0}[0]; }\n",
            capture_output=True, text=True, timeout=120).returncode != 0:
        raise Failed("clang++ with libc++ is needed (packages.py's libcxx group, which ./kit test installs)")
    told = []
    with tempfile.TemporaryDirectory(prefix="raykit-abs-") as tmp:
        probe = Path(tmp) / "probe.cpp"
        probe.write_text(ABS_PROBE)
        bare = Path(tmp) / "bare"           # the kit's headers without ray.hpp's `using std::abs;`
        shutil.copytree(ROOT / "include", bare)
        ray = bare / "raykit" / "ray.hpp"
        text = ray.read_text()
        expect(text.count("\nusing std::abs;\n") == 1, "include/raykit/ray.hpp no longer reads `using std::abs;`")
        ray.write_text(text.replace("\nusing std::abs;\n", "\n"))

        def run(cxx: list[str], include: Path) -> str:
            exe = Path(tmp) / "probe"
            built = subprocess.run(cxx + ["-std=c++17", "-w", "-I", str(include), str(probe), "-o", str(exe)],
                                   capture_output=True, text=True, timeout=120)
            expect(built.returncode == 0, f"{' '.join(cxx)}: the abs probe does not compile:\n{built.stderr[-800:]}")
            return subprocess.run([str(exe)], capture_output=True, text=True, timeout=60).stdout.strip()
        for name, cxx in libraries:
            got = run(cxx, ROOT / "include")
            expect(got == "0.5 0.5", f"{name}: abs(-0.5f) in a step file gives {got!r} with the kit's headers, "
                                     "not 0.5 (in namespace raykit and outside it)")
            told.append(f"{name}: {got}")
        without = run(["g++"], bare)
        expect(without != "0.5 0.5", "GCC gives 0.5 even without ray.hpp's `using std::abs;`: the probe tests "
                                     "nothing")
        told.append(f"GCC without the declaration: {without}")
    all_steps = load_steps()
    [step] = [s for s in all_steps if s.number == "04"]
    libcxx = {"CXX": "clang++", "CXXFLAGS": "-stdlib=libc++", "LDFLAGS": "-stdlib=libc++"}
    own = Build("stdlib-abs-libcxx", BUILD / "stdlib-abs-libcxx", fixture_dir("stdlib_abs"), fixture_dir("stdlib_abs"), preset="student",
                tools=False)
    [mac] = with_compiler(libcxx, lambda: check_steps(own, [step], all_steps))
    [grader] = with_compiler({"CXX": "g++"}, lambda: check_steps(submission_build(fixture_dir("stdlib_abs"), "stdlib-abs-gcc"),
                                                                 [step], all_steps))
    for name, r in (("libc++ (the student's check)", mac), ("GCC (the grader)", grader)):
        failing = [c.name for c in r.cases if c.status != PASS]
        expect(r.state == DONE, f"{name}: the abs fixture is {r.state}, expected done; failing: {failing[:3]}")
    on_mac, on_grader = ({c.name: c.status for c in r.cases} for r in (mac, grader))
    differ = sorted(n for n in on_mac.keys() | on_grader.keys() if on_mac.get(n) != on_grader.get(n))
    expect(not differ, f"the two libraries grade cases differently: {differ[:4]}")
    return "; ".join(told) + f"; the fixture is done with libc++ and with GCC, {len(mac.cases)} cases alike"


FLOAT_TEXT_CHECK = r"""
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include "float_text.hpp"
int main() {
    std::mt19937 rng(20261203);
    long differ = 0, compared = 0;
    auto one = [&](float x) {
        if (std::isnan(x) || std::isinf(x)) return;
        char buf[64];
        const std::string want(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
        const std::string got = raykit::float_text(x);
        ++compared;
        if (got != want && differ++ < 5) std::printf("%s, not %s\n", got.c_str(), want.c_str());
    };
    for (float x : {0.0f, -0.0f, 1.0f, 10.0f, 0.5f, 1e20f, 1e-20f, 123456792.0f, 0.1f, 1e7f, 1.5e-5f, 1e-45f}) one(x);
    for (int i = 0; i < 300000; ++i) {
        const std::uint32_t u = static_cast<std::uint32_t>(rng());
        float x;
        std::memcpy(&x, &u, sizeof x);
        one(x);
    }
    for (int k = -45; k <= 38; ++k)
        for (int m = 1; m < 100; ++m) one(static_cast<float>(m * std::pow(10.0, k)));
    std::printf("%ld of %ld\n", differ, compared);
    return differ != 0;
}
"""


@pytest.mark.quick
def selftest_float_text(ctx) -> str:
    """The grader writes every number as the shortest text that reads back as the same float, with
    one algorithm on every standard library (tests/support/float_text.hpp): the same as
    std::to_chars, checked here against it on 300,000 random floats and the powers of ten."""
    with tempfile.TemporaryDirectory(prefix="raykit-float-text-") as tmp:
        src = Path(tmp) / "check.cpp"
        src.write_text(FLOAT_TEXT_CHECK)
        exe = Path(tmp) / "check"
        r = subprocess.run(["g++", "-std=c++17", "-O2", "-ffp-contract=off", "-I", str(ROOT / "tests" / "support"),
                            str(src), "-o", str(exe)], capture_output=True, text=True, timeout=300)
        expect(r.returncode == 0, f"the float_text check does not build: {r.stderr[-600:]}")
        run = subprocess.run([str(exe)], capture_output=True, text=True, timeout=300)
        expect(run.returncode == 0, f"float_text differs from std::to_chars: {run.stdout[-600:]}")
    return "float_text equals std::to_chars on " + run.stdout.strip().split(" of ")[-1] + " floats"


# Calls Linux (glibc) has and macOS does not: none may be reached from the student-side C++ but
# through tests/support/platform.cpp, whose other branch CI builds here.
LINUX_ONLY = {"pipe2", "execvpe", "dup3", "accept4", "epoll_create", "epoll_create1", "epoll_ctl", "epoll_wait",
              "inotify_init", "inotify_init1", "signalfd", "eventfd", "timerfd_create", "memfd_create", "prctl",
              "clone", "unshare", "setns", "sched_getaffinity", "sched_setaffinity", "gettid", "get_nprocs",
              "getauxval", "splice", "sendfile", "copy_file_range", "fallocate", "posix_fallocate", "mremap",
              "strchrnul", "mempcpy", "get_current_dir_name", "canonicalize_file_name", "pipe2@GLIBC"}


def student_side_sources() -> list[Path]:
    """The C++ a student's own check builds: the judges, the answers program's dispatcher and the
    kit's support, and the render tool."""
    found = sorted((ROOT / "tests" / "support").glob("*.cpp"))
    found += sorted(p for p in (ROOT / "tests").glob("[0-9][0-9]_*/*.cpp"))
    found += sorted((ROOT / "tools" / "render").glob("*.cpp"))
    return found


def selftest_mac_build(ctx) -> str:
    """Portable by construction (#36): the student-side C++ compiled as a Mac would see it (clang,
    libc++, the platform file's POSIX branch), then every object's undefined symbols checked against
    the calls Linux has and macOS lacks; and no /proc outside the platform file."""
    cxx = ["clang++", "-stdlib=libc++"]
    if shutil.which("clang++") is None or shutil.which("nm") is None:
        raise Failed("clang++ and nm are needed (packages.py's libcxx group, which ./kit test installs)")
    sources = student_side_sources()
    proc = [p.relative_to(ROOT).as_posix() for p in sources + sorted((ROOT / "tests" / "support").glob("*.hpp"))
            if p.name != "platform.cpp" and '"/proc' in p.read_text()]
    expect(not proc, f"/proc read outside tests/support/platform.cpp: {proc}")
    includes = ["-I", str(ROOT / "include"), "-I", str(ROOT / "tests"), "-I", str(ROOT / "tests" / "support"),
                "-isystem", "/usr/include/stb"]
    bad, built, skipped = [], 0, []
    with tempfile.TemporaryDirectory(prefix="raykit-mac-") as tmp:
        # What CMake generates for the dispatcher and the judges (CMakeLists.txt): every step's
        # list of functions, every public header, the programs' paths.
        remote_list, api = Path(tmp) / "remote.inc", Path(tmp) / "api.inc"
        remote_list.write_text("".join(remote_lines(load_steps()).values()))
        api.write_text("".join(f'#include "raykit/{p.name}"\n' for p in sorted((ROOT / "include" / "raykit").glob("*.hpp"))))
        defines = [f'-DRAYKIT_REMOTE_LIST="{remote_list}"', f'-DRAYKIT_API_HEADERS="{api}"',
                   '-DRAYKIT_ANSWERS_EXE="answers"', '-DRAYKIT_REFERENCE_EXE="reference"']
        for src in sources:
            obj = Path(tmp) / (src.stem + ".o")
            r = subprocess.run(cxx + ["-std=c++17", "-O0", "-Wall", "-Wextra", "-Wpedantic", "-DRAYKIT_PLATFORM_POSIX",
                                      "-ffp-contract=off", *defines, *includes, "-c", str(src), "-o", str(obj)],
                               capture_output=True, text=True, timeout=600)
            if r.returncode != 0:
                if "file not found" in r.stderr and ("stb_image_write" in r.stderr or "generated" in r.stderr
                                                     or ".inc" in r.stderr):
                    skipped.append(src.name)        # needs a file the build generates or an optional library
                    continue
                bad.append(f"{src.relative_to(ROOT)} does not compile as on a Mac: {r.stderr[-400:]}")
                continue
            built += 1
            nm = subprocess.run(["nm", "-u", str(obj)], capture_output=True, text=True, timeout=60)
            used = {line.split()[-1].split("@")[0] for line in nm.stdout.splitlines() if line.strip()}
            linux = sorted(used & LINUX_ONLY)
            if linux:
                bad.append(f"{src.relative_to(ROOT)} calls {', '.join(linux)}, which macOS does not have")
    expect(not bad, "; ".join(bad[:4]))
    expect(built >= 3, f"only {built} sources built as on a Mac: {skipped}")
    # The control: Linux's branch of the platform file does reach /proc and no call macOS lacks is
    # needed there either, but this check must see a Linux-only call where one is.
    with tempfile.TemporaryDirectory(prefix="raykit-mac-") as tmp:
        probe = Path(tmp) / "probe.cpp"
        probe.write_text("#include <fcntl.h>\n#include <unistd.h>\nint f(int* p) { return pipe2(p, O_CLOEXEC); }\n")
        subprocess.run(cxx + ["-std=c++17", "-c", str(probe), "-o", str(Path(tmp) / "probe.o")], capture_output=True,
                       timeout=120)
        nm = subprocess.run(["nm", "-u", str(Path(tmp) / "probe.o")], capture_output=True, text=True, timeout=60)
        expect("pipe2" in nm.stdout, f"the check cannot see a call to pipe2: {nm.stdout!r}")
    return (f"{built} student-side sources built with clang and libc++ on the platform file's POSIX branch, "
            f"none calling what macOS lacks" + (f" ({len(skipped)} need generated files: {', '.join(skipped)})"
                                                if skipped else ""))


def _verdicts(rec: dict) -> tuple:
    """What a results record says of each step: its state, score and every case's status."""
    return (rec.get("score"), tuple((st["step"], st["state"], tuple((c["name"], c["status"]) for c in st["cases"]))
                                    for st in rec.get("steps", [])))


def selftest_two_checks_at_once(ctx) -> str:
    """Two `./kit check N --steps DIR` of different submissions at once in one clone (issue 52, item
    3): each reports what it reports alone (the kit's own record, never the display), round after
    round, under each isolation here; neither leaves its build folder behind."""
    from .integrity import isolations
    need_solutions()
    step = ctx.steps[0]
    folders = {"solutions": ROOT / "solutions", "wrong": fixture_dir("wrong")}
    expect((folders["wrong"] / step.folder).is_dir(), f"the fixture 'wrong' has no {step.folder}")
    modes, skipped = isolations()
    modes = modes or ["none"]
    work = Path(tempfile.mkdtemp(prefix="raykit-at-once-"))
    parts = []
    try:
        for mode in modes:
            def check(name: str, tag: str) -> tuple:
                out = work / f"{mode}-{name}-{tag}.json"
                r = kit("check", str(int(step.number)), "--steps", str(folders[name]), "--results", str(out),
                        "--isolation", mode, "--quiet", timeout=900)
                expect(out.is_file(), f"{name} ({mode}, {tag}): exited {r.returncode} without a record: "
                                      f"{r.stderr[-400:]}")
                rec = json.loads(out.read_text())
                expect(rec.get("finished", True) is not False, f"{name} ({mode}, {tag}): an unfinished record")
                return _verdicts(rec)

            alone = {name: check(name, "alone") for name in folders}
            expect(alone["solutions"] != alone["wrong"],
                   f"({mode}) the two submissions grade alike alone ({alone['wrong'][0]}): the test proves nothing")
            rounds = 3
            for i in range(rounds):
                # All at once, one thread each; an exception of either is raised here.
                got = dict(zip(folders, map_in_threads(lambda n: check(n, f"round{i}"), list(folders),
                                                       len(folders))))
                for name in folders:
                    expect(got[name] == alone[name],
                           f"({mode}, round {i + 1}) {name} checked beside the other scored {got[name][0]} with "
                           f"states {[st[1] for st in got[name][1]]}; alone {alone[name][0]}, "
                           f"{[st[1] for st in alone[name][1]]}")
            parts.append(f"{mode}: {rounds} rounds, solutions {alone['solutions'][0]}, wrong {alone['wrong'][0]}, "
                         "each as alone")
        # Every run folder still there is a live run's (its lock held): the checks above removed theirs.
        import fcntl
        left = []
        for p in (BUILD / "runs").glob("check-*"):
            try:
                fd = os.open(p / ".held", os.O_RDONLY)
            except OSError:
                continue
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                left.append(p.name)
            except OSError:
                pass
            finally:
                os.close(fd)
        expect(not left, f"run folders left behind by checks that ended: {left}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return "; ".join(parts + skipped)

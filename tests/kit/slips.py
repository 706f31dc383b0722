"""Self-test: a planted slip gets a first message that names it (issue 37, from a student trial).

Each folder of tests/fixtures/slips/ is a student's file with one slip, everything else right. It is
checked as a student checks it (./kit check N --steps DIR), and what the student reads first, the
one case the scoreboard shows, must name the slip: its words, the lecture section it points to (found
in the lecture by what the section teaches, not by its number), and the first hint ./kit hint gives.
What each folder must produce is in its own expected.json (expected_slips below): the tables of the
misdirections and trial 6 are those files; a test whose checks are code is named in its fixtures' files.
The ★ cases of a slip billions of ulps off must not blame rounding. Then the parts that need no
build: the next command of a step that waits for another, the terminal picture of a ray seen end-on,
and a render turned upside down or mirrored.
"""

from __future__ import annotations

import json
import re
import shutil
import tempfile
from pathlib import Path

import pytest

from raykit import slips
from raykit.common import BUILD, ROOT, Step, load_steps
from .support import Failed, expect, kit, need_solutions
from .fixtures import fixture_dir

CASE_LINE = re.compile(r"^\s+✗ (.*?)  \[", re.M)


def _steps() -> dict:
    return {s.number: s for s in load_steps()}


# Each folder of tests/fixtures/slips/ says what it must produce in its own expected.json: the step, the
# self-tests of this module that check it ("checked_by"), and for the tests that are tables ("says",
# "says_not": words the first message must say and must not say, null for none) those words; for a
# test whose checks are code, a "note" naming it. A folder without one, or naming no test of this
# module, fails every test that reads them, so no fixture is forgotten.
EXPECTED = "expected.json"
_WORDS = ("selftest_misdirections", "selftest_trial6")


def expected_slips() -> dict[str, dict]:
    """{fixture: its expected.json} for every folder of the slip fixtures; Failed naming a folder
    without one or one that does not say what it must."""
    found = {}
    for folder in sorted(p for p in fixture_dir("slips").iterdir() if p.is_dir()):
        spec = folder / EXPECTED
        where = f"tests/fixtures/slips/{folder.name}/{EXPECTED}"
        if not spec.is_file():
            raise Failed(f"tests/fixtures/slips/{folder.name}/ has no {EXPECTED}: what must it produce?")
        try:
            data = json.loads(spec.read_text())
        except ValueError as e:
            raise Failed(f"{where}: not JSON: {e}")
        by = data.get("checked_by")
        if not isinstance(data.get("step"), str) or not isinstance(by, list) or not by:
            raise Failed(f"{where}: needs \"step\" (\"01\") and \"checked_by\" (a list of self-tests)")
        for name in by:
            if not (name.startswith("selftest_") and callable(globals().get(name))):
                raise Failed(f"{where}: checked_by names {name!r}, no self-test of tests/kit/slips.py")
            if name in _WORDS and not (isinstance(data.get("says"), str) and data["says"]
                                       and (data.get("says_not") is None or isinstance(data["says_not"], str))):
                raise Failed(f"{where}: {name} needs \"says\" (words) and \"says_not\" (words or null)")
        if not set(by) & set(_WORDS) and not data.get("note"):
            raise Failed(f"{where}: its checks are code: a \"note\" must name the self-test")
        found[folder.name] = data
    return found


def _table(test: str) -> list[tuple[str, str, str, str | None]]:
    """(fixture, step, words the first message must say, words it must not say or None) of the
    fixtures whose expected.json names `test`."""
    return [(name, d["step"], d["says"], d.get("says_not"))
            for name, d in expected_slips().items() if test in d["checked_by"]]


def _declared(test: str, used) -> None:
    """The fixtures a self-test whose checks are code uses are those whose expected.json names it."""
    named = {name for name, d in expected_slips().items() if test in d["checked_by"]}
    expect(named == set(used), f"{test} checks {sorted(set(used))}, but the fixtures whose {EXPECTED} "
                               f"names it are {sorted(named)}")


def _first_block(stdout: str) -> str:
    """The failing case the scoreboard shows under "Next:", up to its "Then run" line."""
    at = stdout.find("Next: step")
    expect(at >= 0, f"no 'Next: step' in the scoreboard:\n{stdout[-1500:]}")
    block = stdout[at:]
    end = block.find("Then run:")
    return block if end < 0 else block[:end]


def _section_teaching(step, pattern: str, title: bool = False) -> str:
    """The heading ("3. The quadratic's coefficients") of the first section of the step's lecture whose
    text (with `title`, whose heading) matches `pattern`."""
    heading = ""
    for line in (ROOT / step.lecture).read_text().splitlines():
        m = re.match(r"## (\d+\. .+)$", line)
        if m:
            heading = m.group(1).strip()
            if title and re.search(pattern, heading):
                return heading
        elif heading and not title and re.search(pattern, line):
            return heading
    raise Failed(f"{step.lecture}: no section matches {pattern!r}")


def _check(step, fixture: str, work: Path, env: dict | None = None, *more: str) -> tuple[str, dict]:
    """./kit check N --steps DIR on a fixture: (stdout, the step's record); `env` set for it, `more`
    given to ./kit check."""
    record = work / f"{fixture}.json"
    r = kit("check", str(int(step.number)), "--steps", str(fixture_dir("slips") / fixture), "--results", str(record),
            *more, timeout=900, env=env)
    expect(r.returncode == 1, f"the planted slip {fixture} exited {r.returncode}, expected 1 (a wrong answer):\n"
                              f"{r.stdout[-1500:]}{r.stderr[-800:]}")
    return r.stdout, json.loads(record.read_text())["steps"][0]


def _first_hint(step, fixture: str) -> str:
    n = str(int(step.number))
    kit("hint", n, "--reset")
    try:
        r = kit("hint", n, "--steps", str(fixture_dir("slips") / fixture), timeout=900)
    finally:
        kit("hint", n, "--reset")
    expect(r.returncode == 0 and "Hint " in r.stdout, f"./kit hint {n} on {fixture}:\n{r.stdout[-1200:]}{r.stderr[-500:]}")
    return r.stdout[r.stdout.find("Hint "):]


def selftest_planted_slips(ctx) -> str:
    """The first case shown, its section and the first hint name each planted slip."""
    need_solutions()    # tests/fixtures/ ships in no handout
    steps = _steps()
    _declared("selftest_planted_slips", ["radius_not_squared", "roots_sign", "uv_swapped", "right_up_x_forward",
                                         "upside_down", "model_slip"])
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="slips-"))
    table = []
    try:
        # A radius not squared: a case about the radius, and the hint that says r enters squared.
        s = steps["02"]
        out, _ = _check(s, "radius_not_squared", work)
        block = _first_block(out)
        radius = _section_teaching(s, r"[Rr]adius", title=True)
        shown = CASE_LINE.search(block)
        expect(shown and "radius" in shown.group(1) and f'section "{radius}"' in block,
               f"a radius not squared is first shown another case than one of \"{radius}\":\n{block}")
        hint = _first_hint(s, "radius_not_squared")
        first = hint.split("\n\n", 1)[0]
        expect("squared" in first or "r²" in first, f"the first hint for a radius not squared is not r²'s:\n{hint}")
        table.append("radius not squared: " + shown.group(1))

        # A sign slip in the roots: named, pointed to the section with the roots' formula, and no ★
        # case blames rounding for an answer billions of ulps away.
        s = steps["01"]
        out, rec = _check(s, "roots_sign", work)
        block = _first_block(out)
        formula = _section_teaching(s, r"\\pm \\sqrt\{b\^2 - 4ac\}")
        expect("opposite sign" in block and f'section "{formula}"' in block,
               f"a sign slip in the roots is not named, or not pointed to \"{formula}\":\n{block}")
        stars = [c for c in rec["cases"] if c["tier"] == "robust" and c["status"] != "pass"]
        expect(stars, "the roots' sign slip passes every ★ case")
        for c in stars:
            # Each call whose answer has roots is named a slip; an answer of no roots leaves nothing to
            # measure (the textbook formula loses the same roots to rounding), so it may say what usually does.
            calls = [b for b in re.split(r"\n\s*\n", "\n".join(c["messages"])) if b.strip()]
            measured = [b for b in calls if not re.search(r"got\s+no roots", b)]
            expect(measured, f"★ case {c['name']!r}: no call of the sign slip has roots to measure")
            for b in measured:
                expect("not rounding" in b and "usually goes wrong" not in b,
                       f"★ case {c['name']!r} of a sign slip blames rounding:\n{b}")
        hint = _first_hint(s, "roots_sign")
        first = hint.split("\n\n", 1)[0]
        expect("minus in front of b" in first, f"the first hint for a sign slip in the roots is not the roots':\n{hint}")
        table.append("roots' sign: " + CASE_LINE.search(block).group(1))

        # Step 04: the (u, v) order: its first case points to the table of section 1 or 4, and the first
        # hint is about the order.
        s = steps["04"]
        out, _ = _check(s, "uv_swapped", work)
        block = _first_block(out)
        hint = _first_hint(s, "uv_swapped")
        first = hint.split("\n\n", 1)[0]
        expect("(u, v)" in first and "order" in first, f"the first hint for (u, v) swapped is not the order's:\n{hint}")
        table.append("(u, v) swapped: " + CASE_LINE.search(block).group(1))
        expect("the direction is zero" not in block, f"a ray seen end-on is drawn as a zero direction:\n{block}")

        # Step 05: right = up x forward, and rows from the bottom: each named, neither blamed on the other.
        s = steps["05"]
        out, _ = _check(s, "right_up_x_forward", work)
        block = _first_block(out)
        expect("mirrored left to right" in block and "forward x up" in block and "Rows count down" not in block,
               f"right = up x forward is not named as the cross product:\n{block}")
        table.append("right = up x forward: " + CASE_LINE.search(block).group(1))
        out, _ = _check(s, "upside_down", work)
        block = _first_block(out)
        expect("mirrored top to bottom" in block and "forward x up" not in block,
               f"rows counted from the bottom are not named:\n{block}")
        table.append("upside down: " + CASE_LINE.search(block).group(1))

        # cornell_box() takes no input: no empty input line.
        out, _ = _check(s, "model_slip", work)
        block = _first_block(out)
        expect("cornell_box()" in block and not re.search(r"^\s+input\s*$", block, re.M),
               f"a cornell_box() failure shows an empty input line:\n{block}")
        table.append("model: " + CASE_LINE.search(block).group(1))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return "first case shown: " + "; ".join(table)


# Issue 54: slips whose first message pointed elsewhere in a student trial, each a fixture of
# tests/fixtures/slips/ checked as a handout checks it (no catalogue of the course's mutants: only what
# the judge measures on the code speaks). (fixture, step, words the first message must say, words it
# must not say: the cause the trial's student was wrongly told, or one alike.) The measured fact comes
# before the case's own why. The table is the expected.json of each fixture whose checked_by names
# selftest_misdirections ("says", "says_not").


def selftest_misdirections(ctx) -> str:
    """Each slip of issue 54's trial, in a handout (no catalogue): its first message names the cause
    measured on the code, never the one the trial's student was wrongly told; and no hint writes the
    half sign that reads like a student's 1 / 2."""
    need_solutions()    # tests/fixtures/ ships in no handout
    from raykit.slips import NO_CATALOGUE
    steps = _steps()
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="slips-misdirected-"))
    table = []
    # Both isolations a foreign folder is graded under: the probes are ordinary calls of the answers
    # process, alike in each. The user isolation needs root; without it, bubblewrap alone (the default).
    import os
    modes = ["bwrap", "user"] if os.geteuid() == 0 else ["bwrap"]
    misdirected = _table("selftest_misdirections")
    expect(misdirected, "no slip fixture's expected.json names selftest_misdirections")
    try:
        for (fixture, number, words, not_words), mode in ((m, mode) for m in misdirected for mode in modes):
            out, _ = _check(steps[number], fixture, work, {NO_CATALOGUE: "1"},   # what a handout prints
                            "--isolation", mode)
            block = _first_block(out)
            why = block.find("why ")
            if why < 0:     # an exception's block has no why: its sentence follows "threw an exception in"
                why = block.find("threw an exception in")
            expect(words in block and (not_words is None or not_words not in block) and 0 <= why < block.find(words),
                   f"{fixture}: the first message does not say '{words}' first, or says '{not_words}':\n{block}")
            if mode == modes[0]:
                table.append(f"{fixture}: {CASE_LINE.search(block).group(1)[:40]}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    halves = [s.folder for s in steps.values() if "½" in (ROOT / "tests" / s.folder / "hints.md").read_text()]
    expect(not halves, f"a hint writes ½, which reads like the student's 1 / 2 (0 in C++): {halves}")
    return f"{len(misdirected)} slips named under {' and '.join(modes)}: " + "; ".join(table)


# Trial 6 (docs/trials/trial6.md): a new student's own code, slips they made up before reading the kit's
# catalogue, whose first message named only part of the slip (or, for sqrt_in_int, blamed a unit
# direction); and trial 7's (docs/trials/trial7.md), graded done (int_t_*) or pointed elsewhere
# (pixel_corner). What the first message must say and must not say: the expected.json of each fixture
# whose checked_by names selftest_trial6.


def selftest_trial6(ctx) -> str:
    """Each slip of trial 6 that the kit first named only in part, in a handout (no catalogue), under
    bubblewrap and the user isolation: its first message says what was measured on the code."""
    need_solutions()    # tests/fixtures/ ships in no handout
    from raykit.slips import NO_CATALOGUE
    steps = _steps()
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="slips-trial6-"))
    import os
    modes = ["bwrap", "user"] if os.geteuid() == 0 else ["bwrap"]
    trial6 = _table("selftest_trial6")
    expect(trial6, "no slip fixture's expected.json names selftest_trial6")
    try:
        for (fixture, number, words, not_words), mode in ((t, mode) for t in trial6 for mode in modes):
            if number not in steps:
                continue    # a course without that step
            out, _ = _check(steps[number], fixture, work, {NO_CATALOGUE: "1"}, "--isolation", mode)
            block = _first_block(out)
            expect(words in block and (not_words is None or not_words not in block),
                   f"{fixture} under {mode}: the first message does not say '{words}'"
                   f"{'' if not_words is None else f', or says {not_words!r}'}:\n{block}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return f"{len(trial6)} slips of trial 6 named under {' and '.join(modes)}"


def selftest_slow_named(ctx) -> str:
    """A right but slow step 01 (a square root by 3,000,000 bisection steps) is done, and its row says
    how many times the reference's CPU it took, not graded; the reference itself is not called slow."""
    need_solutions()
    from raykit.runcases import SLOW_FACTOR
    _declared("selftest_slow_named", ["slow_sqrt"])
    rows = {}
    for name, folder in (("reference", ROOT / "solutions"), ("slow", fixture_dir("slips") / "slow_sqrt"),
                         ("reference again", ROOT / "solutions")):
        r = kit("check", "1", "--steps", str(folder), timeout=900)
        row = next((l for l in r.stdout.splitlines() if " 01 " in l and ("done" in l or "cases" in l)), "")
        expect(r.returncode == 0 and "done" in row, f"{name}: step 01 is not done:\n{r.stdout[-1200:]}{r.stderr[-400:]}")
        rows[name] = row
    m = re.search(r"slow: (over )?(\d+)× the reference's CPU.*not graded", rows["slow"])
    expect(m is not None and int(m.group(2)) > SLOW_FACTOR, f"the slow square root's row says no factor: {rows['slow']}")
    expect("slow" not in rows["reference again"], f"the reference is called slow: {rows['reference again']}")
    return rows["slow"].split("(slow: ", 1)[1].rstrip(")")


def selftest_turned_render(ctx) -> str:
    """./kit render on an upside-down and a mirrored step 05 says so, not "an edge moved by a pixel"."""
    need_solutions()
    _declared("selftest_turned_render", ["upside_down", "right_up_x_forward"])
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="slips-render-"))
    said = []
    try:
        steps = _steps()
        for fixture, words in (("upside_down", "upside down"), ("right_up_x_forward", "mirrored left to right")):
            # The renderer draws with the folder's own step 04: a correct one from the grader's fixtures.
            folder = work / fixture / "steps"
            for n in steps["05"].needs:
                shutil.copytree(fixture_dir("cornell_wrong") / steps[n].folder, folder / steps[n].folder)
            shutil.copytree(fixture_dir("slips") / fixture / steps["05"].folder, folder / steps["05"].folder)
            r = kit("render", "cornell_box", "--steps", str(folder), "--out", str(work / fixture / "out"),
                    timeout=900)
            line = next((l for l in r.stdout.splitlines() if "✗" in l), "")
            expect(r.returncode == 1 and words in line and "an edge moved" not in r.stdout,
                   f"./kit render cornell_box with {fixture}: the first verdict does not say '{words}':\n"
                   f"{r.stdout[-1500:]}{r.stderr[-500:]}")
            said.append(f"{fixture}: {words}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return "; ".join(said)


@pytest.mark.quick
def selftest_expected_files(ctx) -> str:
    """Every folder of tests/fixtures/slips/ has an expected.json that names a self-test of this module
    and holds what that test reads; each test that reads a table has a row."""
    need_solutions()    # tests/fixtures/ ships in no handout
    found = expected_slips()
    steps = _steps()
    for name, d in found.items():
        expect(re.fullmatch(r"\d\d", d["step"]) is not None, f"tests/fixtures/slips/{name}/{EXPECTED}: step {d['step']!r}")
        if d["step"] not in steps:
            continue    # a course without that step
        expect((fixture_dir("slips") / name / steps[d["step"]].folder).is_dir(),
               f"tests/fixtures/slips/{name}/: no folder {steps[d['step']].folder} for its step {d['step']}")
    for test in _WORDS:
        expect(_table(test), f"no slip fixture's {EXPECTED} names {test}")
    return f"{len(found)} slip fixtures, each with its {EXPECTED}"


@pytest.mark.quick
def selftest_waiting_next_command(ctx) -> str:
    """A step waiting for another names that other step's check as the next command."""
    from raykit.cases import StepResult
    from raykit.scoreboard import next_steps
    from raykit.status import WAITING
    needing = [s for s in ctx.steps if s.needs]
    if not needing:
        from .support import Skipped
        raise Skipped("no step needs another")
    s = needing[-1]
    need = s.needs[0]
    lines = "\n".join(next_steps([StepResult(s, WAITING, [], detail=need)], ROOT / "steps"))
    expect(f"uses your step {need}" in lines and f"./kit check {int(need)}" in lines
           and f"./kit check {int(s.number)}" not in lines,
           f"step {s.number} waiting for step {need} names another next command:\n{lines}")
    return f"step {s.number} waits for {need}: next ./kit check {int(need)}"


@pytest.mark.quick
def selftest_end_on_sketch(ctx) -> str:
    """The terminal picture of a rectangle seen face on, with the ray along its normal, draws the ray
    as a point and says so; only a zero direction is called one."""
    from raykit import picture
    rect = {"axis": 2, "offset": 5, "lo": [-3, -1], "hi": [3, 1]}
    said = {}
    for name, direction in (("end-on", [0, 0, 1]), ("zero", [0, 0, 0])):
        figure = {"function": "intersect_rect", "ray": {"origin": [2.5, 0.5, 0], "direction": direction},
                  "rect": rect, "window": [0, "inf"], "expected": 5 if name == "end-on" else None, "got": None}
        _, _, sketch = picture.render_all(figure, name)
        said[name] = sketch[-1]
    expect("the direction is zero" not in said["end-on"] and "end-on" in said["end-on"],
           f"a ray seen end-on: {said['end-on']}")
    expect("the direction is zero" in said["zero"], f"a zero direction: {said['zero']}")
    return "end-on: " + said["end-on"].split("the ray ", 1)[1].split(";")[0]


# Step 05 (issue 45): slips whose picture is wrong, checked as code the kit never saw (the catalogue
# turned off, so only the order of the cases speaks). The first message must be the direct case's, a
# view ray, a closest hit or the sanitizer's finding, never the whole picture or a call the stand-in
# for step 04 refused. Each is a patch of tests/mutants/05_cornell_box/: (patch, the function the
# first case calls, words its first message must hold).
STEP05_DIRECT = [
    ("aspect_ignored", "view_ray(", "scale x by the film's width"),          # x scaled by the film's height
    ("film_point_as_direction", "view_ray(", "Your direction is the film point itself"),   # all black
    ("focal_length_forgotten", "view_ray(", "your film is not focal_length in front of the eye"),  # all white
    ("compared_with_tmax", "find_intersection(", "compare each t with the best so far, not with tmax"),
    ("miss_dereferenced", "render(", "UndefinedBehaviorSanitizer"),          # an empty optional read
]
PICTURE_CASE = "the Cornell box at 48 by 32 pixels matches the reference render"


def _check_patch(step, patch: Path, work: Path, catalogue: bool = True) -> tuple[str, dict]:
    """./kit check N --steps DIR on the reference with `patch` applied (the steps it needs: the
    reference's): (stdout, the step's record)."""
    import os
    import subprocess
    from raykit.common import load_steps, stage_on_reference
    from raykit.mutants import apply_patch, read_patch
    from raykit.slips import NO_CATALOGUE
    changed = work / patch.stem / "changed"
    changed.mkdir(parents=True, exist_ok=True)
    for name, text in apply_patch(read_patch(patch, step)).items():
        (changed / name).write_text(text)
    steps_dir = stage_on_reference(work / patch.stem / "steps", step, load_steps(), changed)
    record = work / patch.stem / "record.json"
    env = dict(os.environ)
    env.pop(NO_CATALOGUE, None)
    if not catalogue:
        env[NO_CATALOGUE] = "1"
    r = subprocess.run([str(ROOT / "kit"), "check", str(int(step.number)), "--steps", str(steps_dir),
                        "--results", str(record)], cwd=ROOT, capture_output=True, text=True, timeout=900, env=env)
    expect(r.returncode == 1, f"{patch.name} exited {r.returncode}, expected 1 (a wrong answer):\n"
                              f"{r.stdout[-1500:]}{r.stderr[-800:]}")
    return r.stdout, json.loads(record.read_text())["steps"][0]


def selftest_step05_direct_first(ctx) -> str:
    """Step 05's slips of a wrong picture: a direct case is shown first, not the picture or a refusal."""
    need_solutions()
    from raykit.mutants import MUTANTS
    s = _steps()["05"]
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="slips-05-"))
    said = []
    try:
        for name, call, words in STEP05_DIRECT:
            out, rec = _check_patch(s, MUTANTS / s.folder / f"{name}.patch", work, catalogue=False)
            block = _first_block(out)
            shown = CASE_LINE.search(block)
            expect(shown is not None, f"{name}: no case under 'Next:':\n{block}")
            case = next(c for c in rec["cases"] if c["name"] == shown.group(1).strip())
            picture = next((c for c in rec["cases"] if c["name"] == PICTURE_CASE), None)
            expect(picture is not None and picture["status"] != "pass",
                   f"{name}: the picture case passes, so the slip tests nothing here")
            expect(case["name"] != PICTURE_CASE and "the grader answers" not in block,
                   f"{name}: the picture or a refusal of the stand-in is shown first:\n{block}")
            expect(call in block and words in block,
                   f"{name}: the first message is not {call}...'s with '{words}':\n{block}")
            said.append(f"{name}: {case['lecture'].split('.')[0]}. {case['name']}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return "; ".join(said)


def selftest_near_slip_words(ctx) -> str:
    """A slip the catalogue does not have, failing exactly the cases one it has fails (c = o.o + 1 where
    the mutant is c = o.o): told the failing set, the known slip's words only as a likely cause."""
    need_solutions()
    from raykit.mutants import read_patch
    s = _steps()["01"]
    patch = fixture_dir("slips") / "c_plus_one.patch"
    known = read_patch(ROOT / "tests" / "mutants" / s.folder / "c_without_radius.patch", s)
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="slips-near-"))
    try:
        out, rec = _check_patch(s, patch, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    expect((rec.get("slip") or {}).get("name") == "c_without_radius",
           f"c = o.o + 1 is not matched with the mutant c_without_radius (slip: {rec.get('slip')}); "
           "it no longer fails the same cases, so this self-test tests nothing: choose another near slip")
    block = _first_block(out)
    words = known.slip.rstrip(".")
    at = block.find(words)
    expect(at >= 0, f"the known slip's words are not in the first message:\n{block}")
    before = block[:at]
    expect("likely cause" in before and "fails exactly the cases" in before,
           f"the known slip's words are said as a fact, not as the likely cause of the same failing set:\n{block}")
    return "c = o.o + 1: " + before[before.find("Your code"):].strip()[:90] + " ..."


@pytest.mark.quick
def selftest_first_problem_order(ctx) -> str:
    """first_problem, without a build: a direct case (a throw of the student's own included) before the
    picture and a stand-in's refusal, the picture when nothing else fails; a known slip's words said
    as a likely cause, several slips that fail alike each said."""
    from raykit.cases import Case, StepResult
    from raykit.slips import words
    from raykit.status import THREW, TIMED_OUT
    s = _steps()["05"]
    refusal = ("Your code threw an exception in render(scene{orange}, camera{...}): std::invalid_argument (\"while "
               "grading step 05 the grader answers intersect_rect only for the rays your view_ray gave for the "
               "case's camera\")")

    def result(*failing):
        # Each failing case's section also has passing cases, so a failing share below the picture's 100 %
        # (the old rule's winner): only the ranking puts a direct case first.
        cases = [Case(n, "basic", lec, st, [m]) for n, lec, st, m in failing]
        for lec in ("5. The camera", "7. The render loop"):
            cases += [Case(f"passes {k} in {lec}", "basic", lec, "pass", []) for k in range(3)]
        return StepResult(s, "partial", cases)
    picture = (PICTURE_CASE, "8. Checking the picture", "fail", "render(cornell_box(), cornell_camera(48, 32))")
    refused = ("every pixel that sees an object gets its colour", "7. The render loop", THREW, refusal)
    direct = ("a wide image sees more to the sides", "5. The camera", "fail", "view_ray(camera, 7, 1)")
    first = result(picture, refused, direct).first_problem()
    expect(first is not None and first.name == direct[0], f"a direct case is not first: {first and first.name}")
    first = result(picture, refused).first_problem()
    expect(first is not None and first.name in (refused[0], PICTURE_CASE), "nothing shown of a refusal and the picture")
    first = result(picture).first_problem()
    expect(first is not None and first.name == PICTURE_CASE, "the picture alone failing is not shown")
    own = ("a throw of the student's own", "7. The render loop", THREW, "Your code threw an exception in render: boom")
    first = result(picture, own).first_problem()
    expect(first is not None and first.name == own[0], "a throw of the student's own is taken for a refusal")
    two = words({"name": "a", "slip": "A.", "alike": [{"name": "a", "slip": "A."}, {"name": "b", "slip": "B."}]})
    one = words({"name": "a", "slip": "A."})
    expect("2 slips" in two and "A; or B" in two and "likely" in two, f"two slips alike: {two}")
    expect("likely cause" in one and not one.startswith("Your failing cases are exactly"), f"one slip: {one}")
    # The catalogue's match: a mutant's failing set is matched; the same set with a case that timed out
    # (a loop: no answer) is matched to nothing.
    if (ROOT / "solutions").is_dir():
        one = _steps()["01"]
        fails = slips._catalogue().get(f"{one.folder}/c_without_radius", {}).get("fails") or []
        expect(fails, "the catalogue has no signature of 01_unit_sphere/c_without_radius")
        graded = [Case(n, "basic", "", "fail", ["got"]) for n in fails] + [Case("other", "basic", "", "pass", [])]
        found = slips.match(one, graded)
        expect(found is not None and found["name"] == "c_without_radius", f"its own failing set: {found}")
        graded[0].status = TIMED_OUT
        expect(slips.match(one, graded) is None, "a step with a timed-out case is matched to a slip")
    return "a direct case before a refusal and the picture; slips said as likely causes; a loop matched to none"


# --- the measure: does the first message name the mutant's own slip? ------------------------

def first_message(step: Step, result: dict) -> tuple[str, str]:
    """(the case a student is shown first, its first message) for a step's graded record (./kit check
    --results), the slip matched again with the catalogue as it is now and its words said again."""
    from raykit.cases import Case, StepResult
    cases = [Case(c["name"], c["tier"], c["lecture"], c["status"],
                  [slips.unsaid(m) for m in c["messages"]])
             for c in result["cases"]]
    slip = slips.match(step, cases)
    shown = StepResult(step, result["state"], cases, slip=slip)
    slips.say(shown)
    first = shown.first_problem()
    return (first.name, first.messages[0] if first.messages else "") if first else ("", "")


def names_own_slip(step: Step, mutant_name: str, result: dict) -> tuple[bool, bool]:
    """On a mutant's graded record: (its first message says its slip's words, and the case is one its
    patch names; its first message says its slip's words, maybe beside other slips that fail alike)."""
    from raykit.mutants import read_patch
    mutant = read_patch(slips.MUTANTS / step.folder / f"{mutant_name}.patch", step)
    case, said = first_message(step, result)
    words_said = mutant.slip.rstrip(".") in said
    return words_said and case in mutant.cases, words_said


def measure(argv: list[str]) -> int:
    from pathlib import Path
    from raykit.common import load_steps
    steps = {s.folder: s for s in load_steps()}
    own, said, total, lines = 0, 0, 0, []
    for path in argv:
        data = json.loads(Path(path).read_text())
        folder, _, name = Path(path).stem.partition("__")
        if data.get("result") is None:
            lines.append(f"  {folder}/{name}: no result")
            continue
        total += 1
        first_own, first_said = names_own_slip(steps[folder], name, data["result"])
        own += first_own
        said += first_said
        if not first_own:
            case, message = first_message(steps[folder], data["result"])
            lines.append(f"  {folder}/{name}: {'said among others' if first_said else 'not named'}; "
                         f"first case {case!r}: {message.splitlines()[0][:100] if message else ''}")
    print(f"{own} of {total} mutants: the first message says their slip, their case first; "
          f"{said} of {total} say their slip, alone or beside slips that fail alike")
    print("\n".join(lines))
    return 0


# ---- words that fit the code (issue 45, item 6) ----------------------------------------------------------
#
# Each slip below is graded as a student's work (./kit check N --steps DIR); the cases it fails must say
# the cause measured on its answer, and no other code's words. Beside each, a control: a slip whose
# failure reads alike but whose cause differs must not be given these words.



def _graded(step, files: dict, work: Path, name: str, fixture: Path | None = None,
            quiet: bool = False) -> tuple[str, dict]:
    """(stdout, the step's record) of ./kit check N --steps DIR: `files` laid over the reference answers
    (a mutant's), or the folder `fixture` as it is. `quiet` (no scoreboard, so no first block) leaves
    the last-check store alone, which ./kit hint reads: another self-test hints on the same mutants."""
    from raykit.common import stage_on_reference
    if fixture is None:
        changed = work / name / "changed"
        changed.mkdir(parents=True, exist_ok=True)
        for file_name, text in files.items():
            (changed / file_name).write_text(text)
        fixture = stage_on_reference(work / name / "steps", step, load_steps(), changed)
    record = work / f"{name}.json"
    r = kit("check", str(int(step.number)), "--steps", str(fixture), "--all", "--results", str(record),
            *(["--quiet"] if quiet else []), timeout=900)
    expect(r.returncode in (0, 1) and record.exists(),
           f"{name}: ./kit check {int(step.number)} exited {r.returncode}:\n{r.stdout[-1500:]}{r.stderr[-800:]}")
    return r.stdout, json.loads(record.read_text())["steps"][0]


def _mutant(step, name: str) -> dict:
    from raykit.mutants import MUTANTS, apply_patch, read_patch
    return apply_patch(read_patch(MUTANTS / step.folder / f"{name}.patch", step))


def _failing(rec: dict, tier: str = "basic") -> dict:
    return {c["name"]: "\n".join(c["messages"]) for c in rec["cases"] if c["tier"] == tier and c["status"] != "pass"}


def selftest_fitting_words(ctx) -> str:
    """Each slip's failures name the cause measured on its answer (an own epsilon, a double computation, a
    tie kept by a loop from last to first, negative t dropped, a slab's in-plane hit), and no other."""
    need_solutions()
    steps = _steps()
    _declared("selftest_fitting_words", ["ties_last_to_first", "negative_t_dropped", "in_plane_slab"])
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="slips-words-"))
    said = []
    try:
        # An own epsilon, planted by each step's mutant own_epsilon: the first case shown names the bound
        # measured on the function, and every visible case it fails says so (the hidden ones do not probe); an open window, an ignored
        # tmin (skipped hits at t = tmin, a hit before tmin), a loop that drops only negative t and one
        # that searches from 0 are not called an epsilon.
        for number, bound in (("01", "0.001"), ("02", "0.0001"), ("04", "0.001"), ("05", "0.0001")):
            s = steps[number]
            out, rec = _graded(s, _mutant(s, "own_epsilon"), work, f"epsilon{number}")
            block = _first_block(out)
            words = f"your code skips hits below t = {bound}, an epsilon of its own"
            expect(words in block, f"step {number}, an own epsilon: the first case shown does not say '{words}':\n{block}")
            failing = _failing(rec)
            expect(failing and all(words in m for m in failing.values()),
                   f"step {number}, an own epsilon: a failing case does not name it:\n" +
                   "\n".join(f"{k}: {m[-400:]}" for k, m in failing.items() if words not in m))
            # The hidden families do not probe (tests/hidden/01_unit_sphere.cpp: a probe's fixed rays would
            # read as hidden inputs carried into a visible case), and so never claim it.
            hidden = _failing(rec, "hidden")
            expect(not any("an epsilon of its own" in m for m in hidden.values()),
                   f"step {number}, an own epsilon: a hidden family probed for it:\n{hidden}")
            said.append(f"step {number} epsilon below {bound}")
        for number, control in (("01", "open_window"), ("04", "tmin_ignored"), ("04", "open_window"),
                                ("05", "negative_t_dropped"), ("05", "window_from_zero")):
            s = steps[number]
            _, rec = _graded(s, _mutant(s, control), work, f"{control}{number}", quiet=True)
            failing = {**_failing(rec), **_failing(rec, "hidden")}
            expect(failing, f"step {number}: the mutant {control} fails no case")
            wrong = [k for k, m in failing.items() if "epsilon of its own" in m]
            expect(not wrong, f"step {number}: the mutant {control} is called an own epsilon in {wrong}")

        # The ★ pbrt case computed in double (forms/double_inside): named as the double form's answer,
        # never told "with every operation in float" alone, and every call is explained.
        s = steps["02"]
        _, rec = _graded(s, {}, work, "double_inside", fixture_dir("forms") / "double_inside", quiet=True)
        pbrt = next((m for k, m in _failing(rec, "robust").items() if "pbrt" in k), None)
        expect(pbrt is not None, "the textbook formula in double passes the ★ pbrt-range case")
        calls = [b for b in re.split(r"\n\s*\n", pbrt) if "why" in b]
        for b in calls:
            expect("in double" in b and "every operation in float" not in b and "matches none" not in b,
                   f"★ pbrt range in double: a call is not named as the double form's:\n{b}")
        said.append(f"double on pbrt's ranges: {len(calls)} calls named")

        # smallpt's loop, last to first with <: the tie is read off the answer, with each loop order's
        # comparison, not "use <" alone; the <= mutant gets the same words.
        s = steps["05"]
        for name, files, fixture in (("ties_last_to_first", {}, fixture_dir("slips") / "ties_last_to_first"),
                                     ("tie_goes_to_last", _mutant(s, "tie_goes_to_last"), None)):
            _, rec = _graded(s, files, work, name, fixture, quiet=True)
            ties = {k: m for k, m in _failing(rec).items() if "tie" in k}
            expect(ties, f"{name}: no tie case fails")
            for k, m in ties.items():
                expect("gives the tie to the object listed later" in m and "a loop from the last to the first" in m
                       and "keep the strict comparison" not in m,
                       f"{name}: the tie case '{k}' is not told what its answer shows:\n{m[-700:]}")
        said.append("a tie kept by the later object, either loop")

        # Negative t dropped, and the distance from the origin: each told its own cause, measured with the
        # expected object alone (or along the reversed ray), in every call of the cases it fails, and the
        # first message shown never names the other (the slip catalogue included: their failing cases differ).
        cases = ["a window with a negative part: the smallest t wins even behind the origin",
                 "an object behind the origin alone is hit when the window reaches behind it"]
        for name, files, fixture, words, not_words in (
                ("negative_t_dropped", {}, fixture_dir("slips") / "negative_t_dropped", "drops hits at a negative t", "distance"),
                ("negative_t_dropped mutant", _mutant(s, "negative_t_dropped"), None, "drops hits at a negative t",
                 "distance"),
                ("closest_by_distance", _mutant(s, "closest_by_distance"), None,
                 "chooses by distance from the origin", "drops hits")):
            out, rec = _graded(s, files, work, name.replace(" ", "_"), fixture)
            failing = _failing(rec)
            asked = [c for c in cases if c in failing]
            expect(cases[0] in asked, f"{name}: the case '{cases[0]}' passes")
            for case in asked:
                calls = [b for b in re.split(r"\n\s*\n", failing[case]) if "why" in b]
                expect(calls and all(words in b and not_words not in b.split("why", 1)[-1] for b in calls),
                       f"{name}: '{case}' does not say '{words}' (or also says '{not_words}'):\n{failing[case][-900:]}")
            block = _first_block(out)
            expect(words in block and not_words not in block,
                   f"{name}: the first message does not say '{words}', or says '{not_words}':\n{block}")
            said.append(f"{name}: {words}")

        # A slab test that checks d.z == 0 and lets a ray lying in the plane through: not told NaN.
        s = steps["04"]
        _, rec = _graded(s, {}, work, "in_plane_slab", fixture_dir("slips") / "in_plane_slab", quiet=True)
        in_plane = {k: m for k, m in _failing(rec).items() if "plane" in k}
        expect(in_plane, "the slab test fails no in-plane case")
        for k, m in in_plane.items():
            why = m.split("why", 1)[-1]
            expect("is NaN" not in why and "a NaN must not" not in why and "a number" in why,
                   f"the slab test's in-plane case '{k}' is told about a NaN it does not return:\n{m[-600:]}")
        said.append(f"a slab's in-plane hit: {len(in_plane)} cases without NaN")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return "; ".join(said)


@pytest.mark.quick
def selftest_platforms_lead_alike(ctx) -> str:
    """Gradescope's first failed test, PrairieLearn's picture and Classroom's first failing line are the
    case the terminal shows first (StepResult.first_problem), not the first failing case in the suite's
    order (issue 45 item 1)."""
    from raykit.cases import Case, StepResult
    from raykit.classroomresults import classroom
    from raykit.gradescope import gradescope
    from raykit.plresults import prairielearn
    from raykit.status import FAIL, PARTIAL, PASS
    step = Step(folder="01_toy", title="a toy step", files=["toy.cpp"], needs=[], lecture="lectures/toy.md")
    pictures = Path(tempfile.mkdtemp(prefix="raykit-lead-"))
    # Section 1 fails 1 of 2 cases, section 2 both of its 2: the terminal leads with section 2's first.
    spec = [("a: the first in the suite", "1. Roots", FAIL), ("b: the one the terminal shows", "2. The window", FAIL),
            ("c: its section's other", "2. The window", FAIL), ("d: passes", "1. Roots", PASS)]
    cases = []
    for k, (n, lec, st) in enumerate(spec):
        svg = pictures / f"case{k}.svg"
        svg.write_text("<svg xmlns='http://www.w3.org/2000/svg' width='4' height='4'></svg>")
        cases.append(Case(n, "basic", lec, status=st, messages=[] if st == PASS else [f"{n} is wrong"],
                          picture=str(svg) if st != PASS else "", picture_summary=f"picture of {n}"))
    r = StepResult(step, PARTIAL, cases)
    lead = r.first_problem("basic")
    expect(lead is not None and lead.name.startswith("b:"), f"the terminal leads with {lead and lead.name}, not b")
    gs = next(t for t in gradescope([r], 1.0)["tests"] if t["status"] == "failed")
    expect(lead.name in gs["name"], f"Gradescope's first failed test is {gs['name']!r}, not the terminal's {lead.name!r}")
    pl = prairielearn([r])
    label = (pl.get("images") or [{}])[0].get("label", "")
    expect(lead.name in label, f"PrairieLearn's picture is {label!r}, not the terminal's case")
    cl = json.dumps(classroom([r]))
    shutil.rmtree(pictures, ignore_errors=True)
    expect(cl.find(lead.name) != -1 and (cl.find(cases[0].name) == -1 or cl.find(lead.name) < cl.find(cases[0].name)),
           "Classroom's results name the suite's first failing case before the terminal's")
    return f"the terminal's first case ({lead.name!r}) leads on Gradescope, PrairieLearn's picture and Classroom"


if __name__ == "__main__":     # PYTHONPATH=tools:tests python3 -m kit.slips RECORD... (from the kit): the measure
    import sys
    raise SystemExit(measure(sys.argv[1:]))

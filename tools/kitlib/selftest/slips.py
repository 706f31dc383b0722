"""Self-test: a planted slip gets a first message that names it (issue 37, from a student trial).

Each folder of tests/fixtures/slips/ is a student's file with one slip, everything else right. It is
checked as a student checks it (./kit check N --steps DIR), and what the student reads first, the
one case the scoreboard shows, must name the slip: its words, the lecture section it points to (found
in the lecture by what the section teaches, not by its number), and the first hint ./kit hint gives.
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

from .. import slips
from ..common import BUILD, ROOT, Step, load_steps
from .harness import Failed, expect, kit, need_solutions

SLIPS = ROOT / "tests" / "fixtures" / "slips"
CASE_LINE = re.compile(r"^\s+✗ (.*?)  \[", re.M)


def _steps() -> dict:
    return {s.number: s for s in load_steps()}


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


def _check(step, fixture: str, work: Path) -> tuple[str, dict]:
    """./kit check N --steps DIR on a fixture: (stdout, the step's record)."""
    record = work / f"{fixture}.json"
    r = kit("check", str(int(step.number)), "--steps", str(SLIPS / fixture), "--results", str(record), timeout=900)
    expect(r.returncode == 1, f"the planted slip {fixture} exited {r.returncode}, expected 1 (a wrong answer):\n"
                              f"{r.stdout[-1500:]}{r.stderr[-800:]}")
    return r.stdout, json.loads(record.read_text())["steps"][0]


def _first_hint(step, fixture: str) -> str:
    n = str(int(step.number))
    kit("hint", n, "--reset")
    try:
        r = kit("hint", n, "--steps", str(SLIPS / fixture), timeout=900)
    finally:
        kit("hint", n, "--reset")
    expect(r.returncode == 0 and "Hint " in r.stdout, f"./kit hint {n} on {fixture}:\n{r.stdout[-1200:]}{r.stderr[-500:]}")
    return r.stdout[r.stdout.find("Hint "):]


def selftest_planted_slips(ctx) -> str:
    """The first case shown, its section and the first hint name each planted slip."""
    need_solutions()    # tests/fixtures/ ships in no handout
    steps = _steps()
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


def selftest_turned_render(ctx) -> str:
    """./kit render on an upside-down and a mirrored step 05 says so, not "an edge moved by a pixel"."""
    need_solutions()
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="slips-render-"))
    said = []
    try:
        steps = _steps()
        for fixture, words in (("upside_down", "upside down"), ("right_up_x_forward", "mirrored left to right")):
            # The renderer draws with the folder's own step 04: a correct one from the grader's fixtures.
            folder = work / fixture / "steps"
            for n in steps["05"].needs:
                shutil.copytree(ROOT / "tests" / "fixtures" / "cornell_wrong" / steps[n].folder, folder / steps[n].folder)
            shutil.copytree(SLIPS / fixture / steps["05"].folder, folder / steps["05"].folder)
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


def selftest_waiting_next_command(ctx) -> str:
    """A step waiting for another names that other step's check as the next command."""
    from ..checking import StepResult
    from ..scoreboard import next_steps
    from ..status import WAITING
    needing = [s for s in ctx.steps if s.needs]
    if not needing:
        from .harness import Skipped
        raise Skipped("no step needs another")
    s = needing[-1]
    need = s.needs[0]
    lines = "\n".join(next_steps([StepResult(s, WAITING, [], detail=need)], ROOT / "steps"))
    expect(f"uses your step {need}" in lines and f"./kit check {int(need)}" in lines
           and f"./kit check {int(s.number)}" not in lines,
           f"step {s.number} waiting for step {need} names another next command:\n{lines}")
    return f"step {s.number} waits for {need}: next ./kit check {int(need)}"


def selftest_end_on_sketch(ctx) -> str:
    """The terminal picture of a rectangle seen face on, with the ray along its normal, draws the ray
    as a point and says so; only a zero direction is called one."""
    from .. import picture
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
    from ..common import load_steps, stage_on_reference
    from ..mutants import apply_patch, read_patch
    from ..slips import NO_CATALOGUE
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
    from ..mutants import MUTANTS
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
    from ..mutants import read_patch
    s = _steps()["01"]
    patch = SLIPS / "c_plus_one.patch"
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


def selftest_first_problem_order(ctx) -> str:
    """first_problem, without a build: a direct case (a throw of the student's own included) before the
    picture and a stand-in's refusal, the picture when nothing else fails; a known slip's words said
    as a likely cause, several slips that fail alike each said."""
    from ..checking import Case, StepResult
    from ..slips import words
    from ..status import THREW, TIMED_OUT
    s = _steps()["05"]
    refusal = ("Your code threw an exception in render(scene{orange}, camera{...}): std::invalid_argument (\"while "
               "grading step 05 the grader answers intersect_rect only for the view rays of the case's camera\")")

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
    from ..checking import Case, StepResult
    cases = [Case(c["name"], c["tier"], c["lecture"], c["status"],
                  [m.split("\n", 1)[1] if m.startswith(slips.SAID) and "\n" in m else m for m in c["messages"]])
             for c in result["cases"]]
    slip = slips.match(step, cases)
    shown = StepResult(step, result["state"], cases, slip=slip)
    slips.say(shown)
    first = shown.first_problem()
    return (first.name, first.messages[0] if first.messages else "") if first else ("", "")


def names_own_slip(step: Step, mutant_name: str, result: dict) -> tuple[bool, bool]:
    """On a mutant's graded record: (its first message says its slip's words, and the case is one its
    patch names; its first message says its slip's words, maybe beside other slips that fail alike)."""
    from ..mutants import read_patch
    mutant = read_patch(slips.MUTANTS / step.folder / f"{mutant_name}.patch", step)
    case, said = first_message(step, result)
    words_said = mutant.slip.rstrip(".") in said
    return words_said and case in mutant.cases, words_said


def measure(argv: list[str]) -> int:
    from pathlib import Path
    from ..common import load_steps
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


def selftests():
    return [("slips: waiting step's next command", selftest_waiting_next_command),
            ("slips: a ray seen end-on", selftest_end_on_sketch),
            ("slips: the picture and refusals come after direct cases", selftest_first_problem_order),
            ("slips: step 05's first message is a direct case's", selftest_step05_direct_first),
            ("slips: a near slip's words are a likely cause", selftest_near_slip_words),
            ("slips: the first message names the planted slip", selftest_planted_slips),
            ("slips: a render turned over", selftest_turned_render)]


if __name__ == "__main__":     # python3 -m kitlib.selftest.slips RECORD... (from tools/): the measure
    import sys
    raise SystemExit(measure(sys.argv[1:]))

"""Self-test: the course's scale (course.json, raykit/course.py): exact totals for a default, a
weighted and an optional-group course, a step that does not compile, bad course files, the
Gradescope view (one ★ test, one test per non-compiling step) and the reveal after the due date."""

from __future__ import annotations

import json
import re
import tempfile
from fractions import Fraction
from pathlib import Path

import pytest

from raykit import course as course_file
from raykit.cases import SCORED_TIERS, Case, StepResult
from raykit.common import ROOT, KitError, Step
from raykit.gradescope import gradescope, reveal_options
from raykit.status import DONE, FAIL, NO_COMPILE, PARTIAL, PASS
from . import scale
from .support import Failed, Skipped, expect, kit, need_solutions, said

STEPS = ["01", "02"]
WEIGHTED = {"steps": {"01": {"points": 10}, "02": {"points": "15/2"}},
            "groups": {"core": {"weight": 2}, "degenerate": {"weight": 1}, "hidden": {"weight": 1},
                       "robust": {"weight": 0}},
            "rounding": {"decimals": 2}}


def toy_step(number: str) -> Step:
    return Step(folder=f"{number}_toy", title="a toy step", files=["toy.cpp"], needs=[], lecture="lectures/toy.md")


def toy_cases(statuses: list[str]) -> list[Case]:
    """3 core, 1 degenerate (by name), 1 hidden, 2 ★ cases, given their statuses in that order."""
    spec = [("basic", "two hits"), ("basic", "one hit"), ("basic", "no hit"), ("basic", "a NaN origin is no hit"),
            ("hidden", "random rays"), ("robust", "far away"), ("robust", "grazing")]
    return [Case(n, t, "", status=s, messages=[] if s == PASS else ["expected 2, got 3"])
            for (t, n), s in zip(spec, statuses)]


ALL = [PASS] * 7
ONE_CORE_WRONG = [FAIL] + [PASS] * 6


def results(statuses_by_step: dict[str, tuple[str, list[str]]]) -> list[StepResult]:
    return [StepResult(toy_step(n), state, toy_cases(st)) for n, (state, st) in statuses_by_step.items()]


# The scale the kit ships with: every step one point per core, degenerate and hidden case, ★ 0. An
# instructor changes course.json (steps 01-04 at 20 points, 05 at 40): the self-tests of the default
# scale parse it here, in memory, and the kit's own course.json is checked for what it is
# (selftest_kit_course), so a customised kit's ./kit test passes.
DEFAULT = {"steps": {}, "groups": {"core": {"weight": 1}, "degenerate": {"weight": 1}, "hidden": {"weight": 1},
                                   "robust": {"weight": 0}}}


@pytest.mark.quick
def selftest_default_scale(ctx) -> str:
    default = course_file.parse(DEFAULT, STEPS, "the default scale")
    code = course_file.Course()
    expect([code.weight(g) for g in course_file.GROUPS] == [default.weight(g) for g in course_file.GROUPS] == [1, 1, 1, 0],
           f"the default weights are not 1 1 1 0: {[str(code.weight(g)) for g in course_file.GROUPS]} without a "
           f"course.json, {[str(default.weight(g)) for g in course_file.GROUPS]} parsed")
    expect(not code.points and all(p is None for p in default.points.values()),
           f"the default scale sets a step's points: {code.points} {default.points}")
    with course_file.using(default):
        rs = results({"01": (DONE, ALL), "02": (PARTIAL, ONE_CORE_WRONG)})
        got = [(r.earned, r.maximum) for r in rs]
        expect(got == [(5, 5), (4, 5)], f"one point a case: expected 5 of 5 and 4 of 5, got {got}")
        expect(all(isinstance(r.earned, Fraction) for r in rs), "points are not exact fractions")
        groups = [c.group for c in rs[0].cases]
        expect(groups == ["core"] * 3 + ["degenerate", "hidden", "robust", "robust"],
               f"the group rule puts the toy cases in {groups}")
    return "the default scale (in memory, as shipped) is one point per case (5 of 5, 4 of 5), ★ 0; a NaN case is degenerate"


def _expected_maximum(course, number: str, groups: list[str]) -> Fraction:
    """A step's maximum under `course`, from its rules as documented: the step's points when set (and
    some counted case weighs something), else the sum of its counted cases' weights; extra credit aside."""
    return _expected(course, number, groups)[0]


def _expected(course, number: str, groups: list[str]) -> tuple[Fraction, Fraction]:
    """A step's maximum and the extra credit its cases add on top, from course.py's documented rules: an
    extra-credit case is worth its weight's share of the step's points as if its group were counted."""
    counted = sum((course.weight(g) for g in groups if not course.extra_credit(g)), Fraction(0))
    extra = sum((course.weight(g) for g in groups if course.extra_credit(g)), Fraction(0))
    points = course.points.get(number)
    if points is None:
        return counted, extra
    return (points, points * extra / counted) if counted else (Fraction(0), Fraction(0))


def extra_credit_data(numbers: list[str]) -> dict:
    """The kit's course.json as it stands with its ★ group made extra credit (as the instructor of #46
    did): its own weight when it has one, else 1/20 of a core case's (5 % of a core case each); a course
    whose ★ is extra credit already is taken as it is."""
    data = json.loads(course_file.COURSE_FILE.read_text()) if course_file.COURSE_FILE.is_file() else {}
    kit = course_file.parse(data, numbers, "course.json")
    if kit.extra_credit("robust"):
        return data
    groups = dict(data.get("groups", {}))
    weight = kit.weight("robust") or (kit.weight("core") or Fraction(1)) / 20
    groups["robust"] = {"weight": course_file.exact_text(weight), "extra_credit": True}
    return dict(data, groups=groups)


def extra_credit_course(numbers: list[str]):
    """extra_credit_data, parsed."""
    data = extra_credit_data(numbers)
    same = course_file.COURSE_FILE.is_file() and data == json.loads(course_file.COURSE_FILE.read_text())
    return course_file.parse(data, numbers, "course.json (★ extra credit)" if same else "course.json with ★ as extra credit")


def kit_results(course, steps, fail: dict[str, set[str]]) -> list[StepResult]:
    """Each step of `steps` with its recorded cases (tests/NN_topic/cases.json) under `course`: every case
    passes but those `fail[step number]` names, by their name or their group."""
    from raykit.checking import recorded_cases
    rs = []
    with course_file.using(course):
        for s in steps:
            cases = recorded_cases(s) or []
            failed = fail.get(s.number, set())
            for c in cases:
                c.status = FAIL if c.group in failed or c.name in failed else PASS
                c.messages = ["expected 2, got 3"] if c.status == FAIL else []
            done = all(c.status == PASS for c in cases if c.tier in SCORED_TIERS)     # as checking.py says
            rs.append(StepResult(s, DONE if done else PARTIAL, cases))
    return rs


def selftest_kit_course(ctx) -> str:
    """The kit's own course.json, whatever the instructor set: it parses for the kit's steps, and each
    step's maximum and a full score are what its points and weights say."""
    numbers = [s.number for s in ctx.steps]
    course = course_file.read(course_file.COURSE_FILE, numbers)
    told = []
    with course_file.using(course):
        rs = [StepResult(toy_step(n), DONE, toy_cases(ALL)) for n in numbers]
        for r, n in zip(rs, numbers):
            groups = [c.group for c in r.cases]
            want, bonus = _expected(course, n, groups)
            expect(r.maximum == want and r.earned == want + bonus,
                   f"step {n}: {r.earned} of {r.maximum} for a full score, not {want + bonus} of {want} (course.json: points "
                   f"{course.points.get(n)}, weights {[str(course.weight(g)) for g in course_file.GROUPS]})")
            told.append(f"{n}: {r.maximum}")
    default = all(course.points.get(n) is None for n in numbers) and \
        [course.weight(g) for g in course_file.GROUPS] == [1, 1, 1, 0]
    return (f"{course.source}, {'the default scale' if default else 'customised'}: a toy step of 7 cases is worth "
            f"{', '.join(told)}; weights {' '.join(str(course.weight(g)) for g in course_file.GROUPS)}")


@pytest.mark.quick
def selftest_weighted(ctx) -> str:
    weighted = course_file.parse(WEIGHTED, STEPS)
    with course_file.using(weighted):
        full = results({"01": (DONE, ALL), "02": (DONE, ALL)})
        slip = results({"01": (PARTIAL, ONE_CORE_WRONG), "02": (NO_COMPILE, [NO_COMPILE] * 7)})
        # Step 01: 10 points over weights 2+2+2+1+1 = 8: a core case is 10*2/8 = 5/2, exact.
        expect([r.maximum for r in full] == [10, Fraction(15, 2)] == [r.maximum for r in slip],
               f"the maxima are {[str(r.maximum) for r in full]} and {[str(r.maximum) for r in slip]}, "
               "not 10 and 15/2 for every student")
        expect(full[0].cases[0].points == Fraction(5, 2) and full[0].cases[3].points == Fraction(5, 4),
               f"a core case is worth {full[0].cases[0].points}, a degenerate {full[0].cases[3].points} "
               "(expected 5/2 and 5/4)")
        expect(slip[0].earned == Fraction(15, 2), f"one wrong core case leaves {slip[0].earned} of 10, not 15/2")
        expect(slip[1].earned == 0, f"a step that does not compile earns {slip[1].earned}, not 0")
        expect(weighted.rounded(Fraction(2, 3)) == course_file.Decimal("0.67"), "2/3 does not round to 0.67")
        view = gradescope(slip, 1.0)
        expect(view["score"] == 7.5 and view["extra_data"]["max_score"] == 17.5,
               f"Gradescope gets {view['score']} of {view['extra_data']['max_score']}, not 7.5 of 17.5")
    optional = course_file.parse(dict(WEIGHTED, groups={"degenerate": {"weight": 0}}), STEPS)
    with course_file.using(optional):
        r = results({"01": (PARTIAL, [PASS] * 3 + [FAIL] + [PASS] * 3)})
        expect(r[0].earned == r[0].maximum == 10, f"a failed case of an optional group costs points: "
               f"{r[0].earned} of {r[0].maximum}")
        view = gradescope(r, 1.0)
        star = [t for t in view["tests"] if "optional" in t["tags"]]
        expect(len(star) == 1 and star[0]["status"] == "passed" and star[0]["max_score"] == 0
               and "a NaN origin" in star[0]["output"],
               f"the optional cases are not one passed 0-point test naming the failed one: {star}")
    return "10 and 15/2 points for every student, a core case 5/2, a slip 15/2, no compile 0, optional group free"


@pytest.mark.quick
def selftest_bad_course_files(ctx) -> str:
    bad = [({"steps": {"01": {"points": "ten"}}}, "steps.01.points"), ({"groups": {"core": {"weight": -1}}}, "negative"),
           ({"steps": {"09": {"points": 1}}}, "no step '09'"), ({"groups": {"bonus": {}}}, "unknown group"),
           ({"hidden": {"visibility": "soon"}}, "hidden.visibility"), ({"rounding": {"decimals": 1.5}}, "decimals"),
           ({"time_limits": {"case_seconds": 0}}, "case_seconds"), ({"step": {}}, "unknown key 'step'"), ([], "object"),
           ({"time_limits": {"step_cpu_seconds": "10"}}, "step_cpu_seconds"),
           ({"time_limits": {"step_wait_seconds": -1}}, "step_wait_seconds")]
    for data, words in bad:
        try:
            course_file.parse(data, STEPS)
        except KitError as e:
            expect(words in str(e), f"{json.dumps(data)}: the message {str(e)!r} does not say {words!r}")
        else:
            raise Failed(f"{json.dumps(data)} is accepted as a course file")
    # A course.json written before the step budgets (no step_*_seconds) keeps working, with their defaults.
    older = course_file.parse({"time_limits": {"case_seconds": 20, "step_seconds": 90, "submission_seconds": 300}}, STEPS)
    expect(older.step_budget() == (course_file.LIMITS["step_cpu_seconds"], course_file.LIMITS["step_wait_seconds"])
           and older.case_limits() == (20, 90), f"a course.json without the step budgets: {older.limits}")
    need_solutions()    # ./kit course is an instructor's command
    with tempfile.TemporaryDirectory() as tmp:
        broken = Path(tmp) / "course.json"
        broken.write_text('{"steps": {"01": {"points": 3},}}')
        r = kit("course", "--file", str(broken))
        expect(r.returncode == 2 and "line 1" in r.stderr and "Traceback" not in r.stderr,
               f"./kit course on broken JSON: exit {r.returncode}, {r.stderr.strip()[-200:]}")
    return (f"{len(bad)} bad course files refused with the key named; one without the step budgets takes "
            "their defaults; broken JSON: one line, exit 2")


@pytest.mark.quick
def selftest_gradescope_views(ctx) -> str:
    default = course_file.Course()
    with course_file.using(default):
        rs = results({"01": (NO_COMPILE, [NO_COMPILE] * 7), "02": (PARTIAL, ONE_CORE_WRONG)})
        rs[0].detail = "toy.cpp:3:1: error: expected ';' before '}' token\n"
        view = gradescope(rs, 1.0)
        one = [t for t in view["tests"] if "step01" in t["tags"]]
        expect(len(one) == 1 and one[0]["status"] == "failed" and one[0]["max_score"] == 5
               and "expected ';'" in one[0]["output"] and "not run" in one[0]["output"],
               f"a step that does not compile is not one failed 5-point test with the diagnostic: {one}")
        two = [t for t in view["tests"] if "step02" in t["tags"]]
        star = [t for t in two if "optional" in t["tags"]]
        expect(len(two) == 6 and len(star) == 1 and star[0]["status"] == "passed",
               f"step 02 gives {len(two)} tests ({len(star)} optional): expected 5 scored and one ★ test")
        expect(view["score"] == 4 and view["extra_data"]["max_score"] == 10 == sum(t["max_score"] for t in view["tests"]),
               f"score {view['score']} of {view['extra_data']['max_score']}, expected 4 of 10")
    return "no compile: 1 failed test with the diagnostic; ★: 1 passed 0-point test; 4 of 10"


@pytest.mark.quick
def selftest_reveal(ctx) -> str:
    """The reveal's rules under a course that reveals and one that never does, each built in memory
    (the shipped default reveals; an instructor may turn it off); then autograde.py's command under the
    kit's own course.json as set: --reveal after the due date exactly when that course reveals."""
    due = {"assignment": {"due_date": "2026-03-01T23:59:00.000000-05:00", "late_due_date": None}}
    reveals = course_file.parse({"hidden": {"reveal_after_due_date": True, "visibility": "after_due_date"}}, STEPS)
    with tempfile.TemporaryDirectory() as tmp, course_file.using(reveals):
        meta = Path(tmp) / "submission_metadata.json"
        for made, want in (("2026-03-01T20:00:00-05:00", False), ("2026-03-02T09:00:00-05:00", True)):
            meta.write_text(json.dumps(dict(due, created_at=made)))
            got = "--reveal" in reveal_options(meta)
            expect(got == want, f"a course that reveals, a submission made {made} (due "
                                f"{due['assignment']['due_date']}): reveal {got}")
        late = dict(due, created_at="2026-03-02T09:00:00-05:00",
                    users=[{"assignment": {"due_date": "2026-03-05T23:59:00-05:00"}}])
        meta.write_text(json.dumps(late))
        expect("--reveal" not in reveal_options(meta), "a student with an extension sees hidden inputs before it ends")
        meta.write_text("{not json")
        expect("--reveal" not in reveal_options(meta), "an unreadable submission_metadata.json reveals")
        no_reveal = course_file.parse({"hidden": {"reveal_after_due_date": False, "visibility": "hidden"}}, STEPS)
        with course_file.using(no_reveal):
            meta.write_text(json.dumps(dict(due, created_at="2026-04-01T00:00:00Z")))
            got = reveal_options(meta)
            expect(got == ["--hidden-visibility", "hidden"], f"a course that never reveals passes {got}")
    # autograde.py passes them on: its ./kit check command after the due date, under course.json as set.
    need_solutions()    # tools/gradescope/ is the instructor's
    kits = course_file.read(course_file.COURSE_FILE, [s.number for s in ctx.steps])
    with tempfile.TemporaryDirectory() as tmp:
        Path(tmp, "submission_metadata.json").write_text(json.dumps(dict(due, created_at="2026-03-03T00:00:00Z")))
        cmd = autograde_command(Path(tmp))
    shown = cmd[cmd.index("--hidden-visibility") + 1] if "--hidden-visibility" in cmd else None
    expect(("--reveal" in cmd) == kits.reveal_after_due_date and shown == kits.hidden_visibility,
           f"autograde.py after the due date runs {' '.join(cmd[1:])}; course.json says reveal "
           f"{'yes' if kits.reveal_after_due_date else 'no'}, visibility {kits.hidden_visibility}")
    return ("a course that reveals: hidden before the due date, --reveal after; an extension, a broken file: "
            f"hidden; never revealing: hidden. course.json as set (reveal {'yes' if kits.reveal_after_due_date else 'no'}, "
            f"{kits.hidden_visibility}): autograde.py passes {'--reveal' if '--reveal' in cmd else 'no --reveal'}")


def autograde_command(root: Path) -> list[str]:
    """The ./kit command autograde.py would run with `root` as /autograder (its process is not started)."""
    import importlib.util
    import os

    class Stop(Exception):
        pass

    saved = os.environ.get("RAYKIT_AUTOGRADER_ROOT")
    os.environ["RAYKIT_AUTOGRADER_ROOT"] = str(root)
    try:
        spec = importlib.util.spec_from_file_location("raykit_autograde_probe", ROOT / "tools/gradescope/autograde.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    finally:
        if saved is None:
            os.environ.pop("RAYKIT_AUTOGRADER_ROOT")
        else:
            os.environ["RAYKIT_AUTOGRADER_ROOT"] = saved
    seen: list[list[str]] = []

    def popen(cmd, **kw):
        seen.append(list(cmd))
        raise Stop()

    module.pid_namespace_works = lambda: False
    module.subprocess.Popen, real = popen, module.subprocess.Popen
    try:
        module.run_kit(root / "steps", root / "results.json")
    except Stop:
        pass
    finally:
        module.subprocess.Popen = real
    expect(bool(seen), "autograde.py's run_kit started no ./kit")
    return seen[0]


def course_cases(steps) -> tuple[dict, dict, list[str]]:
    """The kit's course.json as data, and a results record of the cases ./kit course reads, both such that
    the course's own weights stay valid (issue 55: made-up cases matched none of an instructor's per-case
    and per-section weights, and ./kit course rightly refused them). Each step's cases are its recorded
    ones (tests/NN_topic/cases.json and the hidden record: the names and lecture sections the weights
    name). A step with no record yet (a customised copy's step from the template, before its first
    `./kit check N --record`) gets three made-up cases, and its `weights` are left out of the data: the
    course "mapped" for them. Returns (data, record, the steps made up)."""
    from raykit.checking import recorded_cases
    data = json.loads(course_file.COURSE_FILE.read_text()) if course_file.COURSE_FILE.is_file() else {}
    listed, made_up = [], []
    for s in steps:
        cases = recorded_cases(s)
        if cases:
            listed.append({"step": s.number, "cases": [{"tier": c.tier, "name": c.name, "lecture": c.lecture}
                                                       for c in cases]})
            continue
        made_up.append(s.number)
        listed.append({"step": s.number, "cases": [{"tier": t, "name": n} for t, n in
                                                   [("basic", "a"), ("basic", "a NaN ray"), ("robust", "b")]]})
        entry = data.get("steps", {}).get(s.number)
        if isinstance(entry, dict) and "weights" in entry:
            data = dict(data, steps=dict(data["steps"], **{s.number: {k: v for k, v in entry.items()
                                                                      if k != "weights"}}))
    return data, {"format": "raykit-results", "version": 1, "steps": listed}, made_up


def course_total(course, record: dict) -> Fraction:
    """The total of course.py's documented rules for the cases of `record`: each step's counted cases'
    shares, by group and by their own weights."""
    total = Fraction(0)
    for entry in record["steps"]:
        cases = [(c["tier"], c["name"], c.get("lecture", "")) for c in entry["cases"]]
        groups = [course.group(t, n) for t, n, _ in cases]
        total += course.step_maximum(entry["step"], groups, course.weights_of(entry["step"], cases))
    return total


@pytest.mark.quick
def selftest_course_table(ctx) -> str:
    need_solutions()    # ./kit course is an instructor's command
    with tempfile.TemporaryDirectory() as tmp:
        weighted = Path(tmp) / "weighted.json"
        steps = {s.number: {"points": 20} for s in ctx.steps}
        weighted.write_text(json.dumps(dict(WEIGHTED, steps=steps)))
        fake = Path(tmp) / "results.json"
        fake.write_text(json.dumps({"format": "raykit-results", "version": 1, "steps": [
            {"step": s.number, "cases": [{"tier": t, "name": n} for t, n in
                                         [("basic", "a"), ("basic", "a NaN ray"), ("robust", "b")]]}
            for s in ctx.steps]}))
        plain = Path(tmp) / "default.json"
        plain.write_text(json.dumps(DEFAULT))
        default = kit("course", "--file", str(plain), "--results", str(fake))
        want = f"Total to enter in Gradescope (the assignment's points): {2 * len(ctx.steps)}"
        expect(default.returncode == 0 and re.search(re.escape(want) + r"\b", default.stdout),
               f"./kit course --file (the default scale) does not say {want!r}:\n{said(default)}")
        # The kit's own course.json, as the instructor set it (weights by case and by section included),
        # on the steps' own cases: the total its rules give.
        data, record, made_up = course_cases(ctx.steps)
        kits = course_file.parse(data, [s.number for s in ctx.steps], "course.json")
        total = course_total(kits, record)
        own_cases = Path(tmp) / "own-cases.json"
        own_cases.write_text(json.dumps(record))
        mapped = Path(tmp) / "course.json"
        mapped.write_text(json.dumps(data))
        own = kit("course", *(["--file", str(mapped)] if made_up else []), "--results", str(own_cases))
        want = f"(the assignment's points): {course_file.exact_text(total)}"
        expect(own.returncode == 0 and re.search(re.escape(want) + r"\b", own.stdout),
               f"./kit course (the kit's course.json{', step ' + ', '.join(made_up) + ' made up' if made_up else ''}) "
               f"does not say {want!r}:\n{said(own)}")
        got = kit("course", "--file", str(weighted), "--results", str(fake))
        want = f"(the assignment's points): {20 * len(ctx.steps)}"
        expect(got.returncode == 0 and re.search(re.escape(want) + r"\b", got.stdout) and "1 × 40/3" in got.stdout and "1 × 20/3" in got.stdout,
               f"./kit course --file (20 points a step) does not say {want!r} nor a core case 40/3:\n{said(got)}")
    return (f"./kit course: {2 * len(ctx.steps)} on the default scale, {20 * len(ctx.steps)} weighted (a core case "
            f"40/3), {course_file.exact_text(total)} on the kit's course.json and its steps' recorded cases"
            + (f" (step {', '.join(made_up)} unrecorded: made-up cases, "
               f"{'its' if len(made_up) == 1 else 'their'} own weights left out)" if made_up else ""))


def selftest_roster(ctx) -> str:
    """./kit grade --roster: every student on the roster, submitted or not, id columns first; a folder
    on no one's line; a skipped duplicate named in full; the long CSV. Only step 01 is compiled."""
    import csv
    import shutil

    from raykit.common import BUILD
    need_solutions()
    step = ctx.steps[0]
    root = BUILD / "course-roster"
    shutil.rmtree(root, ignore_errors=True)
    subs = root / "submissions"
    for f in step.files:    # alice: loose files, the same file twice (the second is left out)
        for where in ("a", "b"):
            (subs / "alice" / where).mkdir(parents=True, exist_ok=True)
            shutil.copyfile(ROOT / "solutions" / step.folder / f, subs / "alice" / where / f)
    (subs / "bob").mkdir()          # bob: an empty upload
    (subs / "zed").mkdir()          # zed: on no one's line
    roster = root / "roster.csv"
    roster.write_text("Student ID;E-mail;Login\n1001;alice@uni.example;Alice\n1002;bob@uni.example;bob\n"
                      "1003;carol@uni.example;carol\n")
    out = root / "not-yet" / "grades.csv"       # --out into a folder that does not exist yet
    report = root / "report"
    # Every option with every other, in one call (#35): the roster, the report, two at a time.
    r = kit("grade", str(subs), "--roster", str(roster), "--out", str(out), "--report", str(report), "-j", "2",
            timeout=900)
    expect(r.returncode == 0, f"./kit grade --roster exited {r.returncode}: {r.stderr[-600:]}")
    table = list(csv.reader(out.open()))
    header, rows = table[0], {row[2] or row[3]: dict(zip(table[0], row)) for row in table[1:]}
    expect(header[:4] == ["Student ID", "E-mail", "Login", "submission"], f"the CSV starts {header[:5]}")
    expect(sorted(rows) == ["Alice", "bob", "carol", "zed"], f"the CSV's students: {sorted(rows)}")
    a, b, c, z = rows["Alice"], rows["bob"], rows["carol"], rows["zed"]
    n = step.number
    # alice solved step n: full marks on the course as set (its maximum, and on a course with extra credit
    # the ★ points she passed on top), read from her record (--report keeps it under grading/json/).
    kept = sorted((report / "grading" / "json").glob("alice*.json"))
    expect(len(kept) == 1, f"--report keeps no single record of alice's: {[p.name for p in kept]}")
    [mine_step] = [s for s in json.loads(kept[0].read_text())["steps"] if s["step"] == n]
    short = scale.short_of_full(mine_step)
    full = scale.shown(scale.maximum(mine_step) + scale.bonus(mine_step["cases"]))
    expect(a["submission"] == "alice" and not short and a[f"step{n}_earned"] == full and a["earned"] == full
           and a[f"step{n}_maximum"] == scale.shown(scale.maximum(mine_step)),
           f"alice (step {n} solved): {short or 'the CSV says ' + a[f'step{n}_earned'] + ' of ' + a[f'step{n}_maximum']}, "
           f"full marks are {full}: {a}")
    expect(c["status"] == "not submitted" and c["earned"] == "0" and c["maximum"] == a["maximum"], f"carol (nothing): {c}")
    # bob's empty upload is his: "nothing submitted", 0 points, listed apart from "not graded" (issue 55),
    # and the exit status stays 0 (README, "Not graded": only the grader's faults make it 1).
    expect(b["status"] == "nothing submitted" and b["earned"] == "0" and "No step files found" in b["note"],
           f"bob (empty): {b}")
    listed = [line for line in r.stdout.splitlines() if line.startswith(("nothing submitted", "not graded"))]
    empty = sorted(n for n, row in rows.items() if row["status"] == "nothing submitted")
    expect(any(line.startswith(f"nothing submitted ({len(empty)}") and all(n in line for n in empty) for line in listed)
           and "bob" in empty
           and not any(line.startswith("not graded") for line in listed),
           f"the summary does not list bob's empty upload as nothing submitted, apart: {listed}")
    expect(z["Student ID"] == "" and z["note"].startswith("not on the roster"), f"zed (not on the roster): {z}")
    dup = f"a second {step.files[0]}, left out (graded: a/{step.files[0]})"
    expect(dup in a["note"], f"alice's note does not say, whole, {dup!r}: {a['note']!r}")
    for words in ("not submitted (1): carol", "graded but not matched: zed", "files left out (1): alice"):
        expect(words in r.stdout, f"the summary does not say {words!r}:\n{r.stdout[-600:]}")
    index = (report / "index.html").read_text() if (report / "index.html").is_file() else ""
    pages = sorted(p.name for p in (report / "students").glob("*.html"))
    expect("alice" in index and any(p.startswith("alice") for p in pages) and any(p.startswith("1003") or
           p.startswith("carol") for p in pages), f"--report with --roster: index {len(index)} bytes, pages {pages}")
    cases = list(csv.DictReader((out.parent / "grades-cases.csv").open()))
    mine = [row for row in cases if row["submission"] == "alice"]
    firsts = [row for row in mine if row["step"] == n]
    expect(mine and all(row["Student ID"] == "1001" for row in mine) and firsts
           and not scale.counted_failed(firsts)
           and all(row["earned"] == (row["points"] if row["status"] == "pass" else "0") for row in firsts),
           f"the cases CSV has {len(mine)} rows for alice, step {n}'s: {firsts[:2]}")
    shutil.rmtree(root, ignore_errors=True)
    return (f"4 roster rows (id columns first; carol not submitted, 0 of {a['maximum']}; zed on no line); "
            f"the duplicate named whole; {len(mine)} case rows for alice")


def selftest_moved_kit(ctx) -> str:
    """A build folder configured at one path and used at another (a moved or copied kit) is built
    again, not CMake's "CMakeCache.txt directory ... is different"; outside build/: one line."""
    import contextlib
    import io
    import shutil

    from raykit.common import BUILD
    from raykit.build import Build, configure
    from raykit.relocate import forget_moved_build
    first, moved = BUILD / "course-moved-a", BUILD / "course-moved-b"
    for d in (first, moved):
        shutil.rmtree(d, ignore_errors=True)
    configure(Build("student", first, ROOT / "steps", ROOT / "steps", preset="student", tools=False))
    first.rename(moved)
    said = io.StringIO()
    try:
        with contextlib.redirect_stderr(said):
            configure(Build("student", moved, ROOT / "steps", ROOT / "steps", preset="student", tools=False))
    except KitError as e:
        raise Failed(f"a moved build folder does not configure: {str(e).splitlines()[0]}")
    cache = (moved / "CMakeCache.txt").read_text()
    expect(f"CMAKE_CACHEFILE_DIR:INTERNAL={moved}" in cache, "the moved build folder's cache still names the old path")
    expect("moved or copied" in said.getvalue(), f"no line says why it is built again: {said.getvalue()!r}")
    shutil.rmtree(moved, ignore_errors=True)
    with tempfile.TemporaryDirectory() as tmp:
        elsewhere = Path(tmp) / "build"
        elsewhere.mkdir()
        (elsewhere / "CMakeCache.txt").write_text("CMAKE_CACHEFILE_DIR:INTERNAL=/old/kit/build\n"
                                                  "CMAKE_HOME_DIRECTORY:INTERNAL=/old/kit\n")
        try:
            forget_moved_build(elsewhere)
        except KitError as e:
            expect("\n" not in str(e) and "rm -r" in str(e) and (elsewhere / "CMakeCache.txt").is_file(),
                   f"outside build/: {e}")
        else:
            raise Failed("a foreign build folder outside build/ is taken as this kit's")
    return "a build folder moved to another path is configured again (one line says so); outside build/: one line"


@pytest.mark.quick
def selftest_handout_wording(ctx) -> str:
    """The scoreboard's total: in a handout (no hidden cases), what it checks and what the course adds."""
    handout = course_file.parse({"hidden_cases": {"01": 7, "02": 6}}, STEPS)
    saved = course_file.HIDDEN_SOURCES
    try:
        course_file.HIDDEN_SOURCES = Path("/nonexistent/tests/hidden")
        with course_file.using(handout):
            rs = results({"01": (PARTIAL, ONE_CORE_WRONG[:4] + [PASS, PASS]), "02": (DONE, [PASS] * 4 + [PASS] * 2)})
            for r in rs:        # a handout has no hidden cases
                r.cases = [c for c in r.cases if c.tier != "hidden"]
            line = course_file.score_line(rs)
    finally:
        course_file.HIDDEN_SOURCES = saved
    want = "visible 7 of 8; the course grade also counts 13 hidden cases and weights the steps as your instructor set"
    expect(line.strip() == want, f"a handout's total says {line.strip()!r}, not {want!r}")
    with course_file.using(course_file.Course()):
        line = course_file.score_line(results({"01": (PARTIAL, ONE_CORE_WRONG)}))
    expect(line.strip() == "score 4 of 5 (80 %)", f"the instructor's total says {line.strip()!r}")
    return f"handout: {want!r}; with hidden cases: 'score 4 of 5 (80 %)'"


@pytest.mark.quick
def selftest_step_without_its_need(ctx) -> str:
    """In a handout, step 05's camera cases are checked while step 04 is not done; the cases that
    call step 04's function wait for the student's own, naming it."""
    from raykit import waits
    from raykit.status import NOT_STARTED, WAITING
    five = next((s for s in ctx.steps if s.needs and waits.runs_without(s)), None)
    if five is None:
        raise Failed("no step lists the sections that run without the step it needs (step.json runs_without)")
    need = five.needs[0]
    free = waits.runs_without(five)[need]
    before = next(s for s in ctx.steps if s.number == need)
    pending = {need: StepResult(before, PARTIAL, [])}
    expect(waits.waits_whole(five, pending) == "", f"step {five.number} still waits whole for step {need}")
    cases = [Case("the camera", "basic", free[0], status=FAIL, messages=["view_ray(...) wrong"]),
             Case("the closest hit", "basic", "4. The closest hit", status=FAIL, messages=["find_intersection(...)"]),
             Case("a hit", "basic", "4. The closest hit", status=PASS)]
    state = waits.wait_on_needs(five, cases, pending, PARTIAL)
    expect([c.status for c in cases] == [FAIL, WAITING, PASS] and state == PARTIAL,
           f"step {five.number} with step {need} not done: {[c.status for c in cases]}, state {state}")
    names = ", ".join(before.functions)
    expect(names and names in cases[1].messages[0], f"the waiting case does not name {names}: {cases[1].messages}")
    cases[0].status = PASS
    cases[1].status = NOT_STARTED
    state = waits.wait_on_needs(five, cases, pending, PARTIAL)
    expect(state == WAITING, f"only waiting cases left: state {state}, not waiting")
    expect(waits.wait_on_needs(five, cases, {need: StepResult(before, DONE, [])}, PARTIAL) == PARTIAL,
           "a done step still makes its needers wait")
    return (f"step {five.number} without step {need}: {len(free)} sections run ({', '.join(free)}); the others "
            f"wait for {names}")


@pytest.mark.quick
def selftest_launch_json(ctx) -> str:
    """.vscode/launch.json's list of steps is written from the steps (./kit handout does), so a step
    added by CONTRIBUTING's recipe appears there with nothing else to edit."""
    need_solutions()
    from kitlib.commands.handout import launch_json
    text = (ROOT / ".vscode" / "launch.json").read_text()
    stale = text.replace('"options": [', '"options": ["00", ', 1)
    got = launch_json(stale)
    want = json.dumps([s.number for s in ctx.steps])
    expect(f'"options": {want}' in got and '"00"' not in got, f"launch.json is not rewritten to {want}: {got[-300:]}")
    return f"launch.json's steps written from step.json: {want}"


@pytest.mark.quick
def selftest_gradescope_adds_up(ctx) -> str:
    """Each step's tests on Gradescope add up to the step's points on the course's decimals (each
    rounded alone, seven shares of 20/7 show 20.02), and before the due date the visible summary says
    how many points the hidden cases hold."""
    # Weights 2+2+2+1+1: step 01's 7 points give shares 7/4 and 7/8 (0.875, 0.88 when rounded alone:
    # 7.01 in all); step 02's 10/3 give 5/6 and 5/12.
    thirds = course_file.parse(dict(WEIGHTED, steps={"01": {"points": 7}, "02": {"points": "10/3"}}), STEPS)
    with course_file.using(thirds):
        rs = results({"01": (DONE, ALL), "02": (PARTIAL, ONE_CORE_WRONG)})
        view = gradescope(rs, 1.0, "after_due_date")
        for r in rs:
            shown = [t["max_score"] for t in view["tests"] if f"step{r.step.number}" in t["tags"]]
            # Summed exactly, each max_score as the decimal it is written as (scale.py), not as floats.
            expect(scale.exact_sum(shown) == Fraction(thirds.rounded(r.maximum)),
                   f"step {r.step.number}'s tests add up to {scale.exact_sum(shown)} exactly, its points are "
                   f"{r.maximum} ({thirds.rounded(r.maximum)}): {shown}")
        fractions = [line for line in view["output"].splitlines() if re.match(r"step \d+: .*\d/\d+ of", line)]
        expect(not fractions, f"Gradescope's summary gives a step's points as a fraction, not in decimals: {fractions}")
        held = [line for line in view["output"].splitlines() if "hidden cases hold" in line]
        expect(len(held) == 1 and "after the due date" in held[0],
               f"the visible summary does not say what the hidden cases hold: {view['output']!r}")
        revealed = gradescope(rs, 1.0, "after_due_date", reveal=True)
        expect("hidden cases hold" not in revealed["output"], "after the reveal the summary still says it")
    return f"shares of 7/8 and 5/12 add up to 7 and 3.33; {held[0]}"


@pytest.mark.quick
def selftest_extra_credit(ctx) -> str:
    """★ as extra credit (a group's "extra_credit": true): each ★ case passed adds its weight's share on
    top of the step's points; the maximum stays the step's points, on every platform's view."""
    from raykit.plresults import prairielearn
    bonus = course_file.parse(dict(WEIGHTED, steps={"01": {"points": 8}, "02": {"points": 8}},
                                   groups=dict(WEIGHTED["groups"], robust={"weight": 1, "extra_credit": True})), STEPS)
    with course_file.using(bonus):
        rs = results({"01": (DONE, ALL), "02": (PARTIAL, ONE_CORE_WRONG)})
        # Weights 2+2+2+1+1 = 8 share 8 points: a core case 2, each ★ case (weight 1) +1 on top.
        expect([r.maximum for r in rs] == [8, 8], f"the maxima are {[str(r.maximum) for r in rs]}, not 8 and 8")
        expect([r.earned for r in rs] == [10, 8], f"earned {[str(r.earned) for r in rs]}: expected 8 + 2 ★ = 10, "
               "and 8 - 2 (a core case) + 2 ★ = 8")
        view = gradescope(rs, 1.0)
        maxima = sum(t["max_score"] for t in view["tests"])
        expect(maxima == 16 and view["score"] == 18, f"Gradescope: tests' maxima {maxima} (16 expected), "
               f"score {view['score']} (18 expected)")
        starred = [t for t in view["tests"] if "extra_credit" in t["tags"]]
        expect(len(starred) == 2 and all(t["max_score"] == 0 and t["score"] == 2 and t["status"] == "passed"
                                         for t in starred),
               f"the ★ cases are not one passed 0-point test a step scoring 2: {starred}")
        # PrairieLearn: a step's question is worth its 8 points, complete at 1; the ★ cases are a question
        # of their own worth 2 a step (the assessment's bonus: ./kit prairielearn).
        pl = prairielearn(rs)
        plx = prairielearn(rs, part="extra")
        expect(pl["score"] == 14 / 16 and sum(t["points"] for t in pl["tests"]) == 14
               and sum(t["max_points"] for t in pl["tests"]) == 16,
               f"PrairieLearn, the steps' questions: score {pl['score']} (14/16 expected: 8 + 6 points), "
               f"tests {sum(t['points'] for t in pl['tests'])} of {sum(t['max_points'] for t in pl['tests'])}")
        expect(plx["score"] == 1 and sum(t["max_points"] for t in plx["tests"]) == 4,
               f"PrairieLearn, the extra-credit questions: score {plx['score']} of {sum(t['max_points'] for t in plx['tests'])} "
               "(1 of 4 expected)")
        words = bonus.scale_words()
        expect("extra credit" in words, f"the scale's words do not say ★ is extra credit: {words}")
        # The total a student reads: the points of the course's 16, the extra credit apart (not "18 of 16").
        said = course_file.score_words(rs)
        expect(said.startswith("score 14 of 16 + 4 extra credit"), f"the total reads {said!r}, not 14 of 16 + 4 extra")
        summary = view["output"]
        expect("14 of 16 + 4 extra credit" in summary and "18 of 16" not in summary,
               f"Gradescope's summary: {summary!r}")
    return (f"8 of 8 and a core slip: 10 and 8 of 8 each; Gradescope 18 of 16; PrairieLearn 14 of 16 and 4 of 4 extra; "
            f"the total reads '{said}'; '{words}'")


def selftest_case_weights(ctx) -> str:
    """steps.NN.weights: one case, or a lecture section's cases, weighed apart from their group, on every
    output (the results, Gradescope, ./kit course), and a key that weighs nothing refused (issue 46: an
    all-black picture cost 1.03 of 30 points)."""
    lectures = ["1. Roots", "6. A view ray per pixel", "6. A view ray per pixel", "2. Data", "", "6. Far", "6. Grazing"]
    spec = {"steps": {"01": {"points": 12, "weights": {"two hits": 6, "section 6": 2}}},
            "groups": DEFAULT["groups"]}
    weighted = course_file.parse(spec, STEPS)
    with course_file.using(weighted):
        cases = toy_cases([FAIL] + [PASS] * 6)
        for c, lec in zip(cases, lectures):
            c.lecture = lec
        r = StepResult(toy_step("01"), PARTIAL, cases)
        # Weights: "two hits" 6 (by name, before its section); two basic cases of section 6: 2; a degenerate
        # one and the hidden one: 1; the ★ cases stay optional. 6 + 2 + 2 + 1 + 1 = 12 units for 12 points.
        got = [c.points for c in r.cases]
        want = [Fraction(6), Fraction(2), Fraction(2), Fraction(1), Fraction(1), Fraction(0), Fraction(0)]
        expect(got == want, f"the cases are worth {[str(g) for g in got]}, not {[str(w) for w in want]}")
        expect(r.maximum == 12 and r.earned == 6, f"one heavy case missed: {r.earned} of {r.maximum}, not 6 of 12")
        view = gradescope([r], 1.0)
        heavy = [t for t in view["tests"] if "two hits" in t.get("name", "")]
        expect(heavy and heavy[0]["max_score"] == 6 and heavy[0]["score"] == 0,
               f"Gradescope's test of the heavy case: {heavy[:1]}")
    with tempfile.TemporaryDirectory() as tmp:
        fake = Path(tmp) / "results.json"
        first = ctx.steps[0].number
        fake.write_text(json.dumps({"format": "raykit-results", "version": 1, "steps": [
            {"step": first, "cases": [{"tier": c.tier, "name": c.name, "lecture": lec}
                                      for c, lec in zip(toy_cases(ALL), lectures)]}]}))
        good = Path(tmp) / "good.json"
        good.write_text(json.dumps(dict(spec, steps={first: spec["steps"]["01"]})))
        shown = kit("course", "--file", str(good), "--results", str(fake))
        expect(shown.returncode == 0 and "weight 6 for 'two hits': 1 case, 6 points each" in shown.stdout
               and "weight 2 for lecture section 6: 2 cases, 2 points each" in shown.stdout,
               f"./kit course does not show the cases' own weights: {shown.stdout[-600:]}{shown.stderr[-300:]}")
        bad = Path(tmp) / "bad.json"
        bad.write_text(json.dumps(dict(spec, steps={first: {"points": 12, "weights": {"two hit": 6}}})))
        refused = kit("course", "--file", str(bad), "--results", str(fake))
        expect(refused.returncode != 0 and "'two hit'" in refused.stderr,
               f"a misspelt case name is not refused: exit {refused.returncode}, {refused.stderr[-300:]}")
    try:
        course_file.parse(dict(spec, steps={"01": {"weights": {"section six": 2}}}), STEPS)
        raise Failed("\"section six\" was taken as a weight's key")
    except KitError as e:
        expect("section N" in str(e), f"a bad key's message: {e}")
    return ("a case weighed 6 by name and a section's 2 cases 2 each: 6 + 2 + 2 + 1 + 1 for 12 points, ★ still free; "
            "Gradescope's test 6 points; ./kit course lists them, refuses a misspelt name and 'section six'")


@pytest.mark.quick
def selftest_gradescope_extra_credit(ctx) -> str:
    """#46 item 2 on Gradescope, on the kit's course with ★ as extra credit and its steps' recorded cases:
    a solution that misses every ★ case has no failed test (a missed extra-credit case takes nothing from
    the assignment), one with a core slip has exactly that case failed; the ★ points are each step's
    extra-credit test's score above its max_score 0; the summary says the points and the extra apart."""
    from raykit.checking import recorded_cases
    course = extra_credit_course([s.number for s in ctx.steps])
    steps = [s for s in ctx.steps if recorded_cases(s)]
    if not steps:
        raise Skipped("no step has a recorded case list (tests/NN_topic/cases.json)")
    with course_file.using(course):
        textbook = kit_results(course, steps, {s.number: {"robust"} for s in steps})
        maximum = sum((r.maximum for r in textbook), Fraction(0))
        possible = course_file.extra_maximum(textbook)
        expect(possible > 0, f"no ★ case is worth anything on {course.source}")
        view = gradescope(textbook, 1.0)
        failed = [t["name"] for t in view["tests"] if t["status"] == "failed"]
        expect(not failed, f"a solution that misses only ★ (extra-credit) cases has {len(failed)} failed tests: {failed[:3]}")
        expect(view["score"] == course.number(maximum), f"it scores {view['score']}, not the course's {maximum}")
        # A core slip (step 01's first core case) carried by every ★ case.
        first = next(c.name for c in recorded_cases(steps[0]) if course.group(c.tier, c.name) == "core")
        slip = kit_results(course, steps, {steps[0].number: {first}})
        view = gradescope(slip, 1.0)
        failed = [t["name"] for t in view["tests"] if t["status"] == "failed"]
        expect(len(failed) == 1 and first in failed[0], f"one core slip: failed tests {failed[:4]}")
        bonus = [t for t in view["tests"] if "extra_credit" in t["tags"]]
        worth = [sum((c.points for c in r.cases if course.extra_credit(c.group)), Fraction(0)) for r in slip]
        expect([(t["score"], t["max_score"], t["status"]) for t in bonus]
               == [(course.number(w), 0, "passed") for w in worth if w],
               f"the ★ cases: {[(t['name'], t['score'], t['max_score'], t['status']) for t in bonus]}, not one passed "
               f"0-point test a step scoring its ★ points {[str(w) for w in worth]}")
        want = f"{course.shown(maximum)} + {course.shown(possible)} extra"
        expect(want in view["output"], f"Gradescope's summary does not say {want!r}: {view['output']!r}")
        # Each step's line: its points of its points, the extra apart (not "53.15 of 53").
        for r in slip:
            extra = sum((c.points for c in r.cases if c.status == PASS and course.extra_credit(c.group)), Fraction(0))
            line = (f"step {r.step.number}: " + next((l.split(": ", 1)[1] for l in view["output"].splitlines()
                                                       if l.startswith(f"step {r.step.number}: ")), ""))
            said = f"{course.shown(r.earned - extra)} of {course.shown(r.maximum)}" + (
                f" + {course.shown(extra)} extra" if extra else "")
            expect(line.endswith(said), f"Gradescope's summary says {line!r}, not ... {said!r}")
    return (f"{course.source}: misses every ★ case: no failed test, {course.shown(maximum)}; a core slip: 1 failed test; "
            f"summary '{want}'")


@pytest.mark.quick
def selftest_course_extra_credit_example(ctx) -> str:
    """#46 item 2: ./kit course says, with an example computed from the course as it is (here the kit's
    course.json with ★ made extra credit, on the steps' recorded cases), how much extra credit makes up
    for a bug: all of it, the costliest core case it covers and the two totals, bug + extra credit
    against a correct solution without it."""
    from raykit.checking import recorded_cases
    need_solutions()    # ./kit course is an instructor's command
    numbers = [s.number for s in ctx.steps]
    course = extra_credit_course(numbers)
    total, bonus, core, listed = Fraction(0), Fraction(0), [], []
    for s in ctx.steps:
        cases = [(c.tier, c.name, c.lecture) for c in recorded_cases(s) or []]
        listed.append({"step": s.number, "cases": [{"tier": t, "name": n, "lecture": lec} for t, n, lec in cases]})
        groups = [course.group(t, n) for t, n, _ in cases]
        shares = course.shares(s.number, groups, course.weights_of(s.number, cases))
        total += sum((p for p, g in zip(shares, groups) if not course.extra_credit(g)), Fraction(0))
        bonus += sum((p for p, g in zip(shares, groups) if course.extra_credit(g)), Fraction(0))
        core += [p for p, g in zip(shares, groups) if g == "core" and p > 0]
    if not bonus or not core:
        raise Skipped(f"{course.source}: no extra-credit case or no core case worth anything")
    covered = [p for p in core if p <= bonus]
    bug = max(covered) if covered else min(core)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "course.json"
        path.write_text(json.dumps(extra_credit_data(numbers)))
        # The same cases as here (a step without a record, as a customised copy's new one, has none).
        cases = Path(tmp) / "results.json"
        cases.write_text(json.dumps({"format": "raykit-results", "version": 1, "steps": listed}))
        r = kit("course", "--file", str(path), "--results", str(cases))
    want = [f"+{course.shown(bonus)}", f"{course.shown(total - bug + bonus)}  a bug that fails step",
            f"(-{course.shown(bug)}), every extra-credit case passed", f"{course.shown(total)}  a correct solution"]
    missing = [w for w in want if w not in r.stdout]
    expect(r.returncode == 0 and not missing, f"./kit course --file (★ as extra credit) does not say {missing}: "
           f"{r.stdout[-700:]}{r.stderr[-300:]}")
    plain = kit("course")
    expect("extra credit against a bug" not in plain.stdout or course_file.load().extra,
           "./kit course gives the extra-credit example on a course without extra credit")
    return (f"a core bug (-{course.shown(bug)}) with all the extra credit (+{course.shown(bonus)}): "
            f"{course.shown(total - bug + bonus)}, a correct solution without it {course.shown(total)}")


# Sentences that promise a student their hidden cases' inputs (issue 55: with the reveal off, every failed
# hidden test on Gradescope and the report's pages still said "its inputs are shown after the due date").
PROMISES_INPUTS = re.compile(r"inputs?\b[^.;\n]{0,40}\b(?:are|is|will be|get)\s+(?:shown|revealed|visible)"
                             r"(?![^.;\n]{0,30}\bnot\b)[^.;\n]{0,40}\bafter\b", re.IGNORECASE)
SAYS_NOT_SHOWN = re.compile(r"inputs?\b[^.;\n]{0,40}\b(?:not|never)\b[^.;\n]{0,20}\bshown|never shows[^.;\n]{0,20}inputs?",
                            re.IGNORECASE)


def rendered_outputs(rs) -> dict[str, str]:
    """Every text a student reads of results `rs` under the course in use: the terminal's failing cases,
    Gradescope's results.json (before the due date), PrairieLearn's and Classroom's, the report's student
    page (from the same results record ./kit grade keeps)."""
    import contextlib
    import io

    from raykit import record as results_record
    from raykit.classroomresults import classroom
    from raykit.plresults import prairielearn
    from kitlib.report import grading as grading_mod
    from kitlib.report.pages import student_page
    from raykit.scoreboard import all_failures
    out = {}
    out["the terminal"] = "\n".join(line for r in rs for line in all_failures(r, reveal=False))
    course = course_file.load()
    out["Gradescope"] = json.dumps(gradescope(rs, 1.0, course.hidden_visibility, reveal=False), ensure_ascii=False)
    out["PrairieLearn"] = json.dumps(prairielearn(rs), ensure_ascii=False)
    out["Classroom"] = json.dumps(classroom(rs), ensure_ascii=False)
    data = json.loads(json.dumps(results_record.make(rs, 1.0)))
    st = grading_mod.Student("ada", {"earned": str(data.get("score")), "maximum": str(data.get("max_score"))}, data)
    said = io.StringIO()
    with contextlib.redirect_stdout(said):
        out["the report's student page"] = student_page(st, {})
    return out


@pytest.mark.quick
def selftest_words_follow_course(ctx) -> str:
    """Issue 55 item 3: each output a student reads, rendered under a course that reveals the hidden
    inputs after the due date and one that never does (and ★ as extra credit or optional): no sentence
    promises inputs the course never reveals, and the course that reveals says when; the extra credit is
    named only where the course has it; the report lists counted cases before ★ ones, each with its weight."""
    import html as html_mod
    from raykit.status import FAIL as FAILED_CASE
    checked = []
    for reveal in (True, False):
        for extra in (True, False):
            data = dict(WEIGHTED, groups=dict(WEIGHTED["groups"], robust={"weight": "1/10", "extra_credit": True}
                                              if extra else {"weight": 0}),
                        hidden={"enabled": True, "visibility": "after_due_date", "reveal_after_due_date": reveal})
            course = course_file.parse(data, STEPS, f"reveal {'on' if reveal else 'off'}, ★ "
                                                    f"{'extra credit' if extra else 'optional'}")
            with course_file.using(course):
                # A core case, the hidden case and a ★ case fail.
                statuses = [FAILED_CASE, PASS, PASS, PASS, FAILED_CASE, FAILED_CASE, PASS]
                rs = results({"01": (PARTIAL, statuses), "02": (DONE, ALL)})
                for name, text in rendered_outputs(rs).items():
                    text = html_mod.unescape(text)
                    promised = [m.group(0) for m in PROMISES_INPUTS.finditer(text)]
                    if not reveal:
                        expect(not promised, f"{course.source}: {name} promises the hidden inputs: {promised}")
                    elif name in ("the terminal", "Gradescope", "the report's student page"):
                        expect(promised, f"{course.source}: {name} does not say the hidden inputs are shown after "
                                         f"the due date:\n{text[:1500]}")
                    if not reveal and name in ("the terminal", "Gradescope", "the report's student page", "PrairieLearn"):
                        expect(SAYS_NOT_SHOWN.search(text), f"{course.source}: {name} does not say the hidden "
                                                            f"inputs are not shown:\n{text[:1500]}")
                    if not extra:
                        expect("extra credit" not in text.lower(), f"{course.source}: {name} speaks of extra credit")
                    checked.append(name)
                page = html_mod.unescape(rendered_outputs(rs)["the report's student page"])
                heads = re.findall(r"<h3>(.*?)</h3>", page)
                star = [i for i, h in enumerate(heads) if "★" in h]
                counted = [i for i, h in enumerate(heads) if "★" not in h]
                expect(heads and all(i < j for i in counted for j in star),
                       f"{course.source}: the student page lists a ★ case before a counted one: {heads}")
                expect(all("weight → points" in h for h in heads), f"{course.source}: a case without its weight: {heads}")
    return (f"{len(checked)} renderings (terminal, Gradescope, PrairieLearn, Classroom, the report's page; reveal on "
            "and off, ★ extra credit and optional): no promise of inputs the course never shows; counted cases "
            "first, each with its weight")

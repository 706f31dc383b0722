"""Self-test: every mutant (the reference answer with one realistic slip) is caught, by its named case.

A mutant is a patch, tests/mutants/NN_topic/NAME.patch (format: cmd_mutant.py). Each one is applied
to a fresh copy of the reference answer and goes through the path a student's work takes:
`./kit check N --steps DIR`, where DIR holds the mutated files of its step and the reference files
of the steps it needs. It is caught when the basic tier fails; it is caught by its named case when
one of the cases its header names is among the failures. A patch that no longer applies, or that
names a case the suite does not have, fails by name.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from raykit.mutants import MUTANTS, PatchError, apply_patch, failing_cases, grade_files, patches, read_patch
from raykit.common import BUILD, ROOT, load_steps
from raykit.status import PARTIAL
from .support import Failed, expect, need_solutions
from .fixtures import fixture_dir

MINIMUM_PER_STEP = 8


def stray_files() -> list[str]:
    """Anything under tests/mutants/ but the patches and the README: a full copy of a solution
    left behind would go stale as the reference changes."""
    return sorted(str(p.relative_to(MUTANTS)) for p in MUTANTS.rglob("*")
                  if p.is_file() and p.suffix != ".patch" and p.name not in ("README.md", "signatures.json"))


NAMED_SLIPS: list[str] = []     # the mutants the check named as a known slip (judge)
FIRST_SAYS: list[tuple[bool, bool]] = []   # per mutant: its first message says its slip (its case first; at all)


def judge(step, path, work) -> tuple[bool, bool, list[str]]:
    """Grades one patch: (caught, caught by a named case, the problems to report by name)."""
    label = f"{step.folder}/{path.name}"
    try:
        mutant = read_patch(path, step)
        files = apply_patch(mutant)
    except PatchError as e:
        return False, False, [f"{label}: {e}"]
    problems = [] if mutant.cases else [f"{label}: its header names no case that must catch it"]
    code, result = grade_files(step, files, work)
    failing = failing_cases(result)
    known = {c["name"] for c in result["cases"]} if result else set()
    unknown = [c for c in mutant.cases if known and c not in known]
    if unknown:
        problems.append(f"{label}: names cases step {step.number} does not have: " + ", ".join(unknown))
    # Caught: graded as a wrong answer (exit status 1, a basic case fails), not as a build
    # problem or a stub, which would say nothing about the suite.
    if not (code == 1 and result and result["state"] == PARTIAL and failing):
        state = result["state"] if result else f"exit status {code}"
        return False, False, problems + [f"{label}: not caught ({state})"]
    named = any(c in failing for c in mutant.cases)
    if not named and mutant.cases and not unknown:
        problems.append(f"{label}: caught, but not by its named case(s); it fails: " + ", ".join(failing[:3]))
    # Its failures are its recorded signature, and no other slip's: the check names this slip, and its
    # named case comes first (slips.py, StepResult.first_problem).
    from raykit.slips import _catalogue
    alike = [k for k, e in _catalogue().items()
             if k.startswith(step.folder + "/") and isinstance(e, dict) and set(e.get("fails") or ()) == set(failing)]
    if named and alike == [f"{step.folder}/{mutant.name}"]:
        NAMED_SLIPS.append(label)
        if (result.get("slip") or {}).get("name") != mutant.name:
            problems.append(f"{label}: its failures are exactly its signature, yet the check names the slip "
                            f"{(result.get('slip') or {}).get('name')!r}")
    from .slips import names_own_slip
    FIRST_SAYS.append(names_own_slip(step, mutant.name, result))
    return True, named, problems


@pytest.mark.step
def selftest_mutants(ctx) -> str:
    need_solutions()
    stray = stray_files()
    if stray:
        raise Failed("tests/mutants/ holds files that are not patches: " + ", ".join(stray))

    problems, lines = [], []
    work = BUILD / "mutant-check"
    for step in ctx.steps:
        found = patches(step)
        if len(found) < MINIMUM_PER_STEP:
            problems.append(f"step {step.number} has {len(found)} mutants in tests/mutants/{step.folder}/, "
                            f"at least {MINIMUM_PER_STEP} are needed")
        caught = by_named = 0
        for path in found:
            is_caught, is_named, found_problems = judge(step, path, work)
            caught += is_caught
            by_named += is_named
            problems += found_problems
        lines.append(f"step {step.number}: {len(found)} mutants, {caught} caught, {by_named} by their named case")
    shutil.rmtree(work, ignore_errors=True)
    table = "\n    " + "\n    ".join(lines)
    if problems:
        raise Failed("mutation score" + table + "\n  " + "\n  ".join(problems))
    expect(NAMED_SLIPS, "no mutant was named as a known slip by the check: the catalogue match went untested")
    own, said = sum(o for o, _ in FIRST_SAYS), sum(a for _, a in FIRST_SAYS)
    return (f"mutation score (every mutant caught by its named case; {len(NAMED_SLIPS)} named as the known slip "
            f"they are, their case first; the first message says the slip for {own} of {len(FIRST_SAYS)} with "
            f"its case first, {said} alone or beside slips that fail alike)" + table)


# Causes planted in the reference's find_intersection, and the words the failure of the ★ case "the hit
# names the object it belongs to wherever it is listed" must use for each (measured on the answer in
# tests/05_cornell_box/test_spot_the_bugs.cpp), and must not use for the other.
LOOP = "if (t && (!best || *t < best->t)) best = Hit{*t, i};"
PLANTED = {
    "a tie kept late": (LOOP.replace("*t < best->t", "*t <= best->t"), "a tie, kept by the later object"),
    "an index the loop does not set": (LOOP.replace("Hit{*t, i}", "Hit{*t, 0}"), "a variable the loop does not set"),
}
NAMES_CASE = "the hit names the object it belongs to wherever it is listed"
WINDOW_CASE = "window: a root exactly at tmin counts"


def selftest_planted_causes(ctx) -> str:
    need_solutions()
    step = next(s for s in load_steps() if s.number == "05")
    source = ROOT / "solutions" / step.folder / "render.cpp"
    text = source.read_text()
    if LOOP not in text:
        raise Failed(f"{source.relative_to(ROOT)} no longer has the line this self-test plants causes in: {LOOP}")
    work = BUILD / "cause-check"
    named = []
    for cause, (line, words) in PLANTED.items():
        _, result = grade_files(step, {"render.cpp": text.replace(LOOP, line, 1)}, work)
        case = next((c for c in (result or {}).get("cases", []) if c["name"] == NAMES_CASE), None)
        if case is None or case["status"] != "fail":
            raise Failed(f"planted {cause}: the case '{NAMES_CASE}' did not fail ({case and case['status']})")
        message = "\n".join(case["messages"])
        others = [w for c, (_, w) in PLANTED.items() if c != cause]
        if words not in message or any(w in message for w in others):
            raise Failed(f"planted {cause}: the failure does not name it (and only it):\n{message[-600:]}")
        named.append(cause)
    # Step 01: the open window, planted by its mutant, is named; the far root tried first, which fails the
    # same case, is not called an open window.
    step01 = next(s for s in load_steps() if s.number == "01")
    for patch, want in (("open_window", True), ("far_root_preferred", False)):
        files = apply_patch(read_patch(MUTANTS / step01.folder / f"{patch}.patch", step01))
        _, result = grade_files(step01, files, work)
        case = next((c for c in (result or {}).get("cases", []) if c["name"] == WINDOW_CASE), None)
        if case is None or case["status"] != "fail":
            raise Failed(f"mutant {patch}: the case '{WINDOW_CASE}' did not fail")
        said = "treats the window as open" in "\n".join(case["messages"])
        if said != want:
            raise Failed(f"mutant {patch}: the failure {'does not name' if want else 'wrongly names'} an open "
                         f"window:\n{case['messages'][-1][-600:]}")
    named.append("an open window (and not for the far root tried first)")
    named += planted_root_causes(work)
    shutil.rmtree(work, ignore_errors=True)
    return "the failure names the planted cause: " + ", ".join(named)


# The causes of a ★ sphere failure (tests/support/robust_grading.hpp, measured_cause), each planted where
# it is the whole story, with the words its message must use; the failure must use no other cause's words.
ROOT_CAUSE_WORDS = {
    "the assumption a = 1": "the formula that takes a = d.d as exactly 1",
    "cancellation in h^2 - a c'": "the textbook formula, (-h -+ sqrt(h^2 - a c')) / a with every operation in float, "
                                  "gives: h^2 and a c' are nearly equal",
    "cancellation in c'": "So the cause is c' itself",
    "no known cause": "it matches none of the causes the kit knows",
}
# Step 03's shortcut with its discriminant h^2 - c' in double (smallpt's way): exact but for a = 1.
SHORTCUT_LEG = """    const glm::vec3 l = f - h * d;
    const float disc = r * r - glm::dot(l, l);"""
SHORTCUT_A_ONE = """    const glm::dvec3 fw(f), dw(d);
    const double hw = glm::dot(fw, dw);
    const float disc = static_cast<float>(hw * hw - (glm::dot(fw, fw) - double(r) * r));"""
STEP02_SQRT = "    const double s = std::sqrt(disc);"


def planted_root_causes(work: Path) -> list[str]:
    steps = {s.number: s for s in load_steps()}
    s03 = (ROOT / "solutions" / steps["03"].folder / "unit_direction.cpp").read_text()
    s02 = (ROOT / "solutions" / steps["02"].folder / "general_sphere.cpp").read_text()
    for text, line, where in ((s03, SHORTCUT_LEG, "step 03"), (s02, STEP02_SQRT, "step 02")):
        if line not in text:
            raise Failed(f"the {where} reference no longer has the lines this self-test plants a cause in:\n{line}")
    plants = [
        ("the assumption a = 1", "03", {"unit_direction.cpp": s03.replace(SHORTCUT_LEG, SHORTCUT_A_ONE, 1)},
         "shortcut: a unit sphere 1000 units away"),
        ("cancellation in h^2 - a c'", "02",
         {"general_sphere.cpp": (fixture_dir("textbook") / steps["02"].folder / "general_sphere.cpp").read_text()},
         "a unit sphere 1000 units away"),
        ("cancellation in c'", "02",
         {"general_sphere.cpp": (fixture_dir("forms") / "float_leg" / steps["02"].folder / "general_sphere.cpp").read_text()},
         "the ground seen from a metre or two up"),
        ("no known cause", "02", {"general_sphere.cpp": s02.replace(STEP02_SQRT, STEP02_SQRT[:-1] + " * 1.01;", 1)},
         "a unit sphere 1000 units away"),
    ]
    named = []
    for cause, number, files, case_name in plants:
        _, result = grade_files(steps[number], files, work)
        case = next((c for c in (result or {}).get("cases", []) if c["name"] == case_name), None)
        if case is None or case["status"] != "fail":
            raise Failed(f"planted {cause}: the case '{case_name}' did not fail ({case and case['status']})")
        message = "\n".join(case["messages"])
        others = [w for c, w in ROOT_CAUSE_WORDS.items() if c != cause]
        if ROOT_CAUSE_WORDS[cause] not in message or any(w in message for w in others):
            raise Failed(f"planted {cause}: the failure of '{case_name}' does not name it (and only it):\n"
                         f"{message[-900:]}")
        named.append(cause)
    return named


# Causes a failure must name where two read alike from the outside, each planted as a student's file
# (tests/fixtures/causes/, README "Causes a failure must name"): the folder, the step, the case, the words
# the first failure must use and the words of the cause it is mistaken for, which it must not use.
MEASURED = [
    ("the missing a, with no roots left", "double_a_one", "03", "geometric: a unit sphere 10000 units away",
     ROOT_CAUSE_WORDS["the assumption a = 1"], "h^2 and c' (or |L|^2 and t_m^2) are nearly equal"),
    ("a NaN root, not an order", "nan_roots", "01", "two hits: a ray through the centre enters at t = 2 and leaves at t = 4",
     "A root is NaN", "Roots must be sorted"),
]
# The edges' own rule, planted by its mutant, must still be named (the hidden edges case; an in-plane point
# an ulp outside an exact edge with closed comparisons is right within rounding, and passes it: the form
# tests/fixtures/forms/object_space, selftest/robust.py "fair verdicts"); so must an open window, planted
# by its mutant, in the window-end case.
EDGE_MUTANT = ("04", "edge_excluded", "intersect_rect on exact edges and corners of every axis", "it leaves the edges out")
WINDOW_MUTANT = ("01", "open_window", WINDOW_CASE, "treats the window as open")
# A root one ulp off at a window end (a fast reciprocal of a: 1.9999999 for an exact 2) is inside the basic
# tolerance, so skipping it is no fault: the window-end cases pass it (grading.hpp, check_hit_at_end).
ROUNDED_AT_END = ("root_one_ulp_off", "01", [WINDOW_CASE, "window: the far root exactly at tmin counts",
                                            "window: a root exactly at tmax counts",
                                            "window: the far root exactly at tmax counts"])
# A hidden case draws from the submission's files and the identity: a planted answer that is wrong on some
# draws only is graded under a few identities until the case fails (the fixture fails it on most).
IDENTITIES = 6


def _first_failure(folder: Path, number: str, case_name: str, work: Path,
                   identities: int = IDENTITIES) -> tuple[str, str]:
    """The case's status and messages, graded like a submission, under the first identity where it fails
    (a visible case is the same under every identity: identities=1)."""
    import json
    import subprocess
    status = "missing"
    for k in range(identities):
        report = work / "causes.json"
        report.unlink(missing_ok=True)
        subprocess.run([str(ROOT / "kit"), "check", str(int(number)), "--steps", str(folder), "--results", str(report),
                        "--quiet", "--identity", f"causes:{k}"], cwd=ROOT, capture_output=True, text=True, timeout=900)
        if not report.exists():
            raise Failed(f"{folder.name}: ./kit check {int(number)} wrote no results")
        steps = json.loads(report.read_text())["steps"]
        case = next((c for s in steps for c in s["cases"] if c["name"] == case_name), None)
        status = case["status"] if case else "missing"
        if case and status != "pass":
            return status, "\n".join(case["messages"])
    return status, ""


def selftest_measured_causes(ctx) -> str:
    """Each cause that reads like another from the outside is planted and must be named, and not the other:
    an open window is named as such, while a root one ulp off at a window end (a fast reciprocal) passes
    the window-end cases, its rounding being inside the basic tolerance; no roots from a double routine that takes
    a = 1 is the missing a, not cancellation; the edges' rule is named for its own mutant."""
    need_solutions()
    steps = {s.number: s for s in load_steps()}
    work = BUILD / "measured-causes"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    named = []
    for cause, fixture, number, case_name, words, mistaken in MEASURED:
        status, message = _first_failure(fixture_dir("causes") / fixture, number, case_name, work)
        if status != "fail":
            raise Failed(f"planted {cause}: the case '{case_name}' did not fail under {IDENTITIES} identities ({status})")
        if words not in message or mistaken in message:
            raise Failed(f"planted {cause}: the failure of '{case_name}' does not name it (or names \"{mistaken}\"):\n"
                         f"{message[-900:]}")
        named.append(cause)
    for (number, patch, case_name, words), what in ((EDGE_MUTANT, "the edges left out"), (WINDOW_MUTANT, "an open window")):
        step = steps[number]
        staged = work / f"mutant-{patch}"
        (staged / step.folder).mkdir(parents=True)
        for name, text in apply_patch(read_patch(MUTANTS / step.folder / f"{patch}.patch", step)).items():
            (staged / step.folder / name).write_text(text)
        status, message = _first_failure(staged, number, case_name, work)
        if status != "fail" or words not in message:
            raise Failed(f"mutant {patch}: the failure of '{case_name}' does not say \"{words}\" ({status}):\n"
                         f"{message[-900:]}")
        named.append(f"{what} ({patch})")
    fixture, number, window_cases = ROUNDED_AT_END
    for case_name in window_cases:
        status, message = _first_failure(fixture_dir("causes") / fixture, number, case_name, work, identities=1)
        if status != "pass":
            raise Failed(f"a root one ulp off at a window end ({fixture}): '{case_name}' is {status}, where the "
                         f"rounding is inside the basic tolerance:\n{message[-900:]}")
    named.append(f"a root one ulp off at a window end passes ({len(window_cases)} cases)")
    shutil.rmtree(work, ignore_errors=True)
    return "the failure names the measured cause: " + ", ".join(named)


def selftest_save_refuses_uncaught(ctx) -> str:
    """`./kit mutant save` writes no patch for a slip no basic case catches (an equivalent mutant), and
    says how to drop it (issue 46)."""
    from .support import expect, kit
    need_solutions()
    step = ctx.steps[0]
    name = "selftest_equivalent"
    target = MUTANTS / step.folder / f"{name}.patch"
    copy = BUILD / "mutants" / step.folder / name
    try:
        r = kit("mutant", "new", str(int(step.number)), name)
        expect(r.returncode == 0, f"./kit mutant new: exit {r.returncode}\n{r.stdout}{r.stderr}")
        source = next(p for p in sorted(copy.iterdir()) if p.suffix == ".cpp")
        source.write_text(source.read_text() + "\n// The same code: no case can tell.\n")
        r = kit("mutant", "save", str(int(step.number)), name, "--slip", "nothing at all")
        said = r.stdout + r.stderr
        expect(r.returncode != 0, f"an equivalent mutant was saved (exit 0):\n{said}")
        expect(not target.exists(), f"an equivalent mutant was written to {target.relative_to(ROOT)}")
        expect("not saved" in said and "rm -r" in said, f"the refusal does not say why or how to drop it:\n{said}")
    finally:
        shutil.rmtree(copy, ignore_errors=True)
        target.unlink(missing_ok=True)
    return f"step {step.number}: a comment-only slip refused, no patch written, the way to drop it named"


@pytest.mark.quick
def selftest_fixture_patches(ctx) -> str:
    """Every fixture kept as a patch (tests/fixtures/README.md, "How fixtures are kept") applies to its
    solution, and one that no longer does fails loudly, naming the fixture: a copy of a patch whose
    lines the solution no longer has, in a scratch tree of fixtures."""
    import tempfile

    from raykit.common import KitError
    from .fixtures import FIXTURES, fixture_dir, is_patch
    need_solutions()    # tests/fixtures/ ships in no handout
    kept = sorted(p for p in FIXTURES.rglob("*.patch") if is_patch(p))
    expect(kept, "no fixture is kept as a patch")
    tops = sorted({p.relative_to(FIXTURES).parts[0] for p in FIXTURES.iterdir() if p.is_dir()})
    for top in tops:
        fixture_dir(top)                                    # raises, naming the fixture, if one fails
    for p in kept:
        rel = p.relative_to(FIXTURES)
        made = fixture_dir(rel.parent / p.stem)
        expect(made.is_file(), f"tests/fixtures/{rel} gave no {p.stem}")
    victim = next(p for p in kept if "\n-" in p.read_text() or "\n+" in p.read_text())
    rel = victim.relative_to(FIXTURES)
    with tempfile.TemporaryDirectory(prefix="raykit-fixture-") as tmp:
        tree = Path(tmp) / "fixtures"
        shutil.copytree(FIXTURES / rel.parts[0], tree / rel.parts[0])
        broken = tree / rel
        lines = broken.read_text().splitlines(keepends=True)
        at = next(i for i, line in enumerate(lines) if i > 0 and line[:1] in " -" and line.strip(" -\n")
                  and not line.startswith("--- "))
        lines[at] = lines[at][0] + "    // a line the solution does not have\n"
        broken.write_text("".join(lines))
        try:
            fixture_dir(rel.parent, fixtures=tree, work=Path(tmp) / "build")
        except KitError as e:
            said = str(e)
        else:
            raise Failed(f"a copy of {rel} whose lines the solution lacks was applied without a word")
        expect(rel.as_posix() in said and "no longer applies" in said,
               f"the broken copy of {rel} failed without naming it: {said}")
        expect(not (Path(tmp) / "build" / rel.parts[0]).exists(), f"the broken copy of {rel} left a folder")
    return (f"{len(kept)} fixture files kept as patches, all applied ({len(tops)} fixture folders under "
            f"build/fixtures/); a broken copy fails: {said[:120]}")

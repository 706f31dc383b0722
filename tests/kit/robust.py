"""Self-test: the ★ robust tier tells a careful textbook answer from a robust one.

tests/fixtures/textbook/ holds, for each sphere step, the textbook formula written with every rule
of the contract (b^2 - 4ac, (-b -+ sqrt) / 2a, |L|^2 - t_m^2). Graded like a student's work, each
must pass the whole basic tier and fail part of the robust tier, while the reference solutions pass
both (checked by "solutions pass every case"). The scoreboard must show the two tiers apart.

Each ★ case says which ways of writing the step pass it (`graded_forms({...}, {...})` in the suites,
tests/support/robust_grading.hpp). "★ cases name the forms that pass them" grades those forms, the
float-only step 02s written as lecture 03 teaches (tests/fixtures/forms/float_leg, float_cross), the
textbook formula in double (forms/double_inside) and in float (textbook/), and fails when a case's lists
disagree with the grades or the lectures state another count of ★ cases for the float rewrites.
"""

from __future__ import annotations

import re
from pathlib import Path

from raykit.common import ROOT, load_steps
from raykit.build import submission_build
from raykit.checking import check_steps
from raykit.status import DONE
from .support import Failed, Skipped, expect, kit, need_solutions
from .fixtures import fixture_dir


# Form (as the suites name it) -> the folders graded as that form, per step. "solutions" is the
# reference, whose passing every ★ case "solutions pass every case" (selftest/check.py) checks; the
# others are fixtures (tests/fixtures/NAME, read through fixtures.fixture_dir).
GRADED = {
    "01": {"textbook_float": ["textbook"], "float_rewrites": ["solutions"]},
    "02": {"textbook_float": ["textbook"], "float_rewrites": ["forms/float_leg", "forms/float_cross"],
           "double_textbook": ["forms/double_inside"], "double_rewrite": ["solutions"]},
    "03": {"textbook_float": ["textbook"], "float_rewrites": ["solutions"]},
}
# Where the lectures and tasks state how many ★ cases of step 02 the float rewrites pass.
CLAIMS = ["lectures/02-general-sphere.md", "lectures/03-unit-direction.md", "steps/02_general_sphere/README.md",
          "steps/03_unit_direction/README.md"]
WORDS = {8: "eight", 9: "nine", 10: "ten", 7: "seven", 6: "six"}


def form_claims(text: str) -> dict[str, tuple[set[str], set[str]]]:
    """★ case name -> (forms said to pass, forms said to fail), read from a robust suite's source."""
    out = {}
    blocks = re.split(r"(?=^TEST_CASE\()", text[text.find('TEST_SUITE_BEGIN("robust")'):], flags=re.M)[1:]
    for block in blocks:
        name = re.match(r'TEST_CASE\("([^"]*)"', block).group(1)
        m = re.search(r"graded_forms\(\{([^}]*)\},\s*\{([^}]*)\}\)", block)
        out[name] = (set(re.findall(r"Form::(\w+)", m.group(1))), set(re.findall(r"Form::(\w+)", m.group(2)))) \
            if m else None
    return out


def claim_problems(step: str, claims: dict, grades: dict[str, dict[str, bool]]) -> list[str]:
    """What a suite says against what the forms got: grades[form][case] is True when it passes."""
    bad = []
    for case, said in claims.items():
        if said is None:
            bad.append(f"step {step}: ★ case '{case}' does not say which forms pass it (graded_forms)")
            continue
        passing, failing = said
        for form in sorted(GRADED[step]):
            if (form in passing) == (form in failing):
                bad.append(f"step {step}: '{case}' lists {form} {'twice' if form in passing else 'nowhere'}")
            elif form in grades and grades[form].get(case) is not None and grades[form][case] != (form in passing):
                bad.append(f"step {step}: '{case}' says {form} {'passes' if form in passing else 'fails'}, "
                           f"but graded it {'passes' if grades[form][case] else 'fails'}")
    return bad


def selftest_forms_named(ctx) -> str:
    need_solutions()
    steps = load_steps()
    by_number = {s.number: s for s in steps}
    bad, summary, float02 = [], [], None
    for number, forms in GRADED.items():
        step = by_number[number]
        suite = ROOT / "tests" / step.folder / "test_robust.cpp"
        claims = form_claims(suite.read_text())
        expect(claims, f"{suite.relative_to(ROOT)}: no ★ case found")
        grades: dict[str, dict[str, bool]] = {}
        reached = []
        for form, folders in sorted(forms.items()):
            for folder in folders:
                if folder == "solutions":
                    got = {case: True for case in claims}  # the reference: selftest/check.py
                else:
                    results = check_steps(submission_build(fixture_dir(folder), "forms"), [step], steps)
                    robust = results[0].tier("robust")
                    expect(results[0].state == DONE, f"tests/fixtures/{folder} step {number}: graded "
                                                     f"{results[0].state}, expected done")
                    got = {c.name: c.status == "pass" for c in robust}
                    expect(set(got) == set(claims), f"step {number}: the graded ★ cases {sorted(got)} are not "
                                                    f"the suite's {sorted(claims)}")
                if form in grades and grades[form] != got:
                    bad.append(f"step {number}: the folders graded as {form} do not pass the same ★ cases "
                               f"({folder}): name them apart")
                grades[form] = got
            reached.append(f"{form} {sum(grades[form].values())}/{len(claims)}")
        bad += claim_problems(number, claims, grades)
        summary.append(f"step {number}: " + ", ".join(reached))
        if number == "02":
            float02 = (sum(grades["float_rewrites"].values()), len(claims))
    n, total = float02
    for path in CLAIMS:
        text = (ROOT / path).read_text()
        if not re.search(rf"\b(?:{n}|{WORDS.get(n, n)}) of the (?:{total}|{WORDS.get(total, total)})\b", text):
            bad.append(f"{path} does not say that the float rewrites pass {n} of the {total} ★ cases of step 02")
    expect(not bad, "\n  ".join(bad[:12]))

    # The check can fail: a case that names a form wrongly, and one that names none.
    planted = {"a": ({"float_rewrites"}, {"textbook_float"}), "b": None}
    wrong = claim_problems("01", planted, {"float_rewrites": {"a": False}, "textbook_float": {"a": False}})
    expect(any("says float_rewrites passes" in w for w in wrong) and any("does not say" in w for w in wrong),
           f"a wrong form list went unnoticed: {wrong}")
    return "; ".join(summary) + "; as every ★ case says"


def selftest_textbook_fails_robust(ctx) -> str:
    need_solutions()   # a handout has neither solutions/ nor tests/fixtures/
    steps = load_steps()
    chosen = [s for s in steps if (fixture_dir("textbook") / s.folder).is_dir()]
    expect(any(s.number == "02" for s in chosen), "tests/fixtures/textbook/ has no answer for step 02")
    results = check_steps(submission_build(fixture_dir("textbook"), "fixtures"), chosen, steps)
    summary = []
    for r in results:
        basic, robust = r.tier("basic"), r.tier("robust")
        where = f"textbook step {r.step.number}"
        expect(r.state == DONE, f"{where}: graded {r.state}, expected done (it is a correct answer)")
        problem = r.first_problem("basic")
        expect(problem is None, f"{where}: basic case '{problem.name if problem else ''}' does not pass")
        expect(bool(robust), f"{where}: step {r.step.number} has no robust tier")
        failed = [c for c in robust if c.status != "pass"]
        if not failed:
            raise Failed(f"{where}: passes every robust case; the robust tier does not test robustness")
        for c in failed:
            expect(c.status == "fail", f"{where}: robust case '{c.name}' is {c.status}, expected a wrong answer")
        summary.append(f"step {r.step.number} basic {len(basic)}/{len(basic)}, robust "
                       f"{r.passed('robust')}/{len(robust)}")
    r = kit("check", "2", "--steps", str(fixture_dir("textbook")))
    expect(r.returncode == 0, f"./kit check 2 on the textbook answer exited {r.returncode}, expected 0 (done)")
    expect("done" in r.stdout and "★ robust" in r.stdout,
           f"the scoreboard does not show the basic and robust tiers apart:\n{r.stdout[-1500:]}")
    return "textbook formula: " + "; ".join(summary)


# --- the same bits with FMA ----------------------------------------------------------------------
# A driver that calls a step 02 routine on rays drawn by a fixed generator (grazing, far and near)
# and prints every root's bits: compiled with and without FMA instructions, the kit's flags must
# print the same; with contraction allowed (the control) the same source must print something else,
# or the check could not see a fused multiply-add at all.
FMA_DRIVER = r"""
#include <cstdint>
#include <cstdio>
#include <cstring>
#include "raykit/general_sphere.hpp"
static std::uint32_t state = 12345u;
static float next(float lo, float hi) {
    state = state * 1664525u + 1013904223u;
    return lo + (hi - lo) * static_cast<float>(state >> 8) / 16777216.0f;
}
static std::uint32_t bits(float f) { std::uint32_t u; std::memcpy(&u, &f, 4); return u; }
int main() {
    for (int i = 0; i < 4000; ++i) {
        const float far = (i % 3 == 0) ? 1000.0f : (i % 3 == 1) ? 10.0f : 1.0f;
        const raykit::Ray ray{{next(-far, far), next(-far, far), next(-far, far)},
                              {next(-1, 1), next(-1, 1), next(-1, 1)}};
        const raykit::Sphere sphere{{next(-2, 2), next(-2, 2), next(-2, 2)}, next(0.5f, 3)};
        const raykit::Roots r = raykit::sphere_roots(ray, sphere);
        std::printf("%d %08x %08x\n", r.count, bits(r.t[0]), bits(r.t[1]));
    }
}
"""


def kit_contraction_flags() -> list[str]:
    """The floating-point flags the kit's CMakeLists.txt gives every compile (raykit_options)."""
    text = (ROOT / "CMakeLists.txt").read_text()
    found = re.findall(r"target_compile_options\(raykit_options INTERFACE ([^)]*)\)", text)
    return [f for line in found for f in line.split() if f.startswith("-ffp-contract")]


def selftest_same_bits_with_fma(ctx) -> str:
    import shutil
    import subprocess
    import tempfile
    flags = kit_contraction_flags()
    expect(flags == ["-ffp-contract=off"], f"CMakeLists.txt gives every compile {flags or 'no -ffp-contract'}, "
           "not -ffp-contract=off: a Mac (ARM64) or -mfma fuses a*b + c and rounds otherwise")
    from raykit import procfs
    has_fma = "fma" in procfs.cpu_flags()
    compilers = [c for c in ("g++", "clang++") if shutil.which(c)]
    sources = {"solutions": ROOT / "solutions" / "02_general_sphere" / "general_sphere.cpp",
               "textbook": fixture_dir("forms") / "float_leg" / "02_general_sphere" / "general_sphere.cpp"}
    sources = {k: v for k, v in sources.items() if v.is_file()}
    expect(bool(sources) and bool(compilers), "no step 02 source or no compiler to try")
    told = []
    with tempfile.TemporaryDirectory(prefix="raykit-fma-") as tmp:
        driver = Path(tmp) / "driver.cpp"
        driver.write_text(FMA_DRIVER)

        def run(cxx: str, src: Path, extra: list[str]) -> str:
            exe = Path(tmp) / "a.out"
            r = subprocess.run([cxx, "-std=c++17", "-O2", *extra, "-I", str(ROOT / "include"), str(driver), str(src),
                                "-o", str(exe)], capture_output=True, text=True, timeout=300)
            expect(r.returncode == 0, f"{cxx} {' '.join(extra)} {src.name}: {r.stderr[-600:]}")
            return subprocess.run([str(exe)], capture_output=True, text=True, timeout=60).stdout

        for cxx in compilers:
            for name, src in sources.items():
                plain = run(cxx, src, flags)
                if not has_fma:
                    continue
                fused = run(cxx, src, flags + ["-mfma"])
                differ = sum(a != b for a, b in zip(plain.splitlines(), fused.splitlines()))
                expect(differ == 0, f"{cxx}, {name}: {differ} of 4000 rays give other bits with -mfma under the "
                       f"kit's flags {flags}")
                control = run(cxx, src, ["-ffp-contract=fast", "-mfma"])
                moved = sum(a != b for a, b in zip(plain.splitlines(), control.splitlines()))
                told.append(f"{cxx} {name}: 0 differ with -mfma, {moved} with contraction allowed")
                if name == "textbook":
                    expect(moved > 0, f"{cxx}: contraction allowed and -mfma changed no root of the float "
                           "rewrite: the check cannot see a fused multiply-add here")
    if not has_fma:
        raise Skipped("this CPU has no FMA: -ffp-contract=off is set, the answers with FMA cannot be run here")
    return "; ".join(told)


# --- fair verdicts: the lectures' forms on many draws --------------------------------------------
# Every form the lectures teach, in float and in double, is right by the basic tier's tolerance, so
# it must pass every basic and hidden case whatever the hidden draw: a case whose verdict hangs on
# the side a rounding error falls (a root at a window end) is a knife's edge, not a test. Graded
# under several identities, so the hidden families draw other inputs each time.
# The lectures' forms themselves (tests/fixtures/fair/, in float and double, with and without FMA) are
# graded by the fairness table (selftest/fair_table.py), on 2 draws here, 100 with RAYKIT_SELFTEST_FULL=1.
# Each a fixture's name (fixtures.fixture_dir) but "solutions".
FAIR_FORMS = [("solutions", ["1", "2", "3"]), ("textbook", ["1", "2", "3"]),
              ("forms/float_leg", ["2"]), ("forms/float_cross", ["2"]), ("forms/double_inside", ["2"]),
              ("forms/object_space", ["4"]), ("forms/quad_reciprocal", ["4"])]
# And the other side: a slip a hidden family is there to catch is caught on every draw, not on some.
ALWAYS_CAUGHT = [("04_rectangles", "edge_excluded", "intersect_rect on exact edges and corners of every axis")]


def selftest_fair_on_many_draws(ctx) -> str:
    import json
    import os
    import tempfile
    need_solutions()
    seeds = 100 if os.environ.get("RAYKIT_SELFTEST_FULL") == "1" else 3
    unfair, graded = [], 0
    with tempfile.TemporaryDirectory(prefix="raykit-fair-") as tmp:
        for name, numbers in FAIR_FORMS:
            folder = ROOT / "solutions" if name == "solutions" else fixture_dir(name)
            for k in range(seeds):
                target = Path(tmp) / "record.json"
                target.unlink(missing_ok=True)
                r = kit("check", *numbers, "--steps", str(folder), "--quiet", "--results", str(target),
                        "--identity", f"fair:{k}", timeout=1200)
                expect(target.is_file(), f"{folder.name}: no record (exit {r.returncode}): {r.stderr[-400:]}")
                graded += 1
                for step in json.loads(target.read_text())["steps"]:
                    for c in step["cases"]:
                        if c["tier"] in ("basic", "hidden") and c["status"] != "pass":
                            unfair.append(f"{folder.name} step {step['step']} draw {k}: {c['name']}: "
                                          + " ".join(c["messages"])[:300])
    from raykit.mutants import patches, write_answer
    caught_always = []
    with tempfile.TemporaryDirectory(prefix="raykit-always-") as tmp:
        for folder, name, family in ALWAYS_CAUGHT:
            step = next(s for s in ctx.steps if s.folder == folder)
            patch = next((p for p in patches(step) if p.stem == name), None)
            expect(patch is not None, f"no mutant {folder}/{name}.patch")
            write_answer(step, patch, Path(tmp) / "steps" / folder)
            missed = []
            for k in range(seeds):
                target = Path(tmp) / "record.json"
                target.unlink(missing_ok=True)
                kit("check", str(int(step.number)), "--steps", str(Path(tmp) / "steps"), "--quiet", "--results",
                    str(target), "--identity", f"fair:{k}", timeout=1200)
                expect(target.is_file(), f"{name}: no record")
                cases = [c for st in json.loads(target.read_text())["steps"] for c in st["cases"] if c["name"] == family]
                expect(len(cases) == 1, f"{name}: the record has no case {family!r}")
                if cases[0]["status"] == "pass":
                    missed.append(k)
            expect(not missed, f"{folder}/{name} passes {family!r} on draws {missed} of {seeds}: a verdict of the draw")
            caught_always.append(f"{name} on {seeds} of {seeds}")
    from . import fair_table
    rows, note = fair_table.measure(2 if seeds < 100 else 100)
    unfair += fair_table.unfair(rows)
    expect(not unfair, f"{len(unfair)} basic or hidden cases fail a form the lectures teach:\n  "
           + "\n  ".join(unfair[:6]))
    return (f"{len(FAIR_FORMS)} folders x {seeds} identities ({graded} gradings), and the fairness table's "
            f"{len(rows)} rows (forms x steps x float, double x contraction) on {2 if seeds < 100 else 100} draws: "
            "every basic and hidden case passes" + (f" ({note})" if note else "")
            + f"; caught on every draw: {', '.join(caught_always)}"
            + ("" if seeds == 100 else " (100 with RAYKIT_SELFTEST_FULL=1)"))

"""Self-test: the reference build and its tests under AddressSanitizer and UndefinedBehaviorSanitizer.
Last in the run: the slowest self-test, and left out by --fast."""

from __future__ import annotations

import re

from raykit.build import workflow
from .support import Context, Skipped, expect, need_solutions


def selftest_sanitizers(ctx: Context) -> str:
    need_solutions()
    if ctx.fast:
        raise Skipped("--fast leaves out the sanitizer build")
    r = workflow("sanitize")
    tail = (r.stdout + r.stderr)[-4000:]
    expect(r.returncode == 0, f"the ASan + UBSan build or its tests failed:\n{tail}")
    m = re.search(r"tests passed, (\d+) tests failed out of (\d+)", r.stdout)
    expect(m is not None and int(m.group(2)) > 0, "ctest ran no test under the sanitizers")
    return f"ASan + UBSan, {m.group(2)} tests, no finding"


# Undefined behaviour the grader must catch the same way in a student's own check and in the grade
# (tests/fixtures/README.md, "Undefined behaviour"): each student's files, and for each step the words
# its first crash must hold. Step 05's files are the fixture's render.cpp and the reference's data.
UB_STUDENTS = {
    "slips": {"02_general_sphere": ("ub_slips", "index 2 out of bounds"),
              "04_rectangles": ("ub_slips", "past the end of argument 1")},
    "slips05": {"05_cornell_box": ("ub_slips", "past the end of the list in argument 2")},
    "axis": {"04_rectangles": ("ub_axis", "an assert in the kit's headers failed")},
}
# A step of a student's that a UB step needs, given right (the reference's files): in a handout the
# step 05 cases that call step 04 wait for the student's own step 04, which must then be done (ub_slips'
# step 04 crashes on the basic axis cases, so step 05 has a student of its own).
UB_NEEDS = {"slips05": ["04_rectangles"]}


def _ub_files(student: str, dest) -> None:
    import shutil

    from raykit.common import ROOT
    from .fixtures import fixture_dir
    for folder in UB_NEEDS.get(student, []):
        shutil.copytree(ROOT / "solutions" / folder, dest / folder, dirs_exist_ok=True)
    for folder, (fixture, _) in UB_STUDENTS[student].items():
        (dest / folder).mkdir(parents=True, exist_ok=True)
        if folder == "05_cornell_box":
            shutil.copyfile(ROOT / "solutions" / folder / "cornell_box.cpp", dest / folder / "cornell_box.cpp")
        for f in (fixture_dir(fixture) / folder).iterdir():
            shutil.copyfile(f, dest / folder / f.name)


def _ub_cases(path) -> dict:
    import json
    data = json.loads(path.read_text())
    return {(s["folder"] if "folder" in s else s.get("step", ""), c["name"]): c
            for s in data["steps"] for c in s["cases"]}


def selftest_student_sanitizers(ctx: Context) -> str:
    """Undefined behaviour is found, and judged the same in a student's own ./kit check (run in a
    handout, where students run it) and in ./kit grade: a raw-pointer axis read past a vec3
    ((&v.x)[3]: past the Ray the grader passed, a guard page), glm's v[3] (its assert), a loop to
    `<= count` over the objects (past the scene's list, a guard page) and over the roots (UBSan: index
    2 of float[2]). Every case both run has the same status, and each slip's cases crash with its
    cause named; the plain build that graded them before gave "done"."""
    import shutil
    import subprocess
    import tempfile
    import time
    from pathlib import Path

    from raykit.common import BUILD
    from .support import kit
    need_solutions()
    handout = BUILD / "ub-handout"
    shutil.rmtree(handout, ignore_errors=True)
    r = kit("handout", str(handout), "--committed", timeout=600)
    expect(r.returncode == 0, f"./kit handout failed: {r.stderr[-400:]}")
    klass = Path(tempfile.mkdtemp(prefix="raykit-ub-class-"))
    checked: dict = {}
    start = time.monotonic()
    try:
        for student, steps in UB_STUDENTS.items():
            _ub_files(student, handout / "steps")
            _ub_files(student, klass / "class" / student)
            numbers = [folder[:2] for folder in steps]
            p = subprocess.run([str(handout / "kit"), "check", *numbers, "--results", str(handout / "r.json"), "--quiet"],
                               cwd=handout, capture_output=True, text=True, timeout=900)
            expect((handout / "r.json").is_file(), f"{student}: ./kit check wrote no results: {p.stderr[-400:]}")
            checked[student] = _ub_cases(handout / "r.json")
            (handout / "r.json").unlink()
        r = kit("grade", str(klass / "class"), "--out", str(klass / "grades.csv"), "--json-dir", str(klass / "json"),
                timeout=1800)
        expect(r.returncode == 0, f"./kit grade exited {r.returncode}: {r.stderr[-500:]}")
        graded = {student: _ub_cases(klass / "json" / f"{student}.json") for student in UB_STUDENTS}
    finally:
        shutil.rmtree(handout, ignore_errors=True)
        shutil.rmtree(klass, ignore_errors=True)
    took = time.monotonic() - start
    found, stacks = [], 0
    for student, steps in UB_STUDENTS.items():
        mine, theirs = checked[student], graded[student]
        both = sorted(set(mine) & set(theirs))
        expect(both, f"{student}: the check and the grade share no case")
        differ = [f"{f} {n}: check {mine[(f, n)]['status']}, grade {theirs[(f, n)]['status']} "
                  f"({' '.join(theirs[(f, n)]['messages'])[:200]} / {' '.join(mine[(f, n)]['messages'])[:200]})"
                  for f, n in both if mine[(f, n)]["status"] != theirs[(f, n)]["status"]]
        expect(not differ, f"{student}: the check and the grade disagree on {len(differ)} case(s): {differ[:3]}")
        for folder, (_, cause) in steps.items():
            for name, results in (("./kit check", mine), ("./kit grade", theirs)):
                crashed = [c for (f, _), c in sorted(results.items()) if f == folder and c["status"] == "crashed"]
                expect(crashed, f"{student}: {name} finds no crash in {folder}")
                message = " ".join(crashed[0]["messages"])
                expect(cause in message, f"{student}: {name}'s first crash in {folder} does not say "
                                         f"\"{cause}\": {message[:300]}")
                # Its stack as a student reads it (remote.cpp, readable_stack): names demangled, the
                # student's own frame marked, the dispatcher's frames in one line.
                frames = [l for c in crashed for l in c.get("output", "").splitlines() if l.strip().startswith("#")]
                expect(not any(" _Z" in l for l in frames), f"{student}: {name} shows a mangled frame in {folder}: "
                                                           f"{[l for l in frames if ' _Z' in l][:1]}")
                if frames:
                    stacks += 1
                    expect(any("<- your code" in l for l in frames),
                           f"{student}: {name}'s stack in {folder} marks none of the student's frames: {frames[:4]}")
            found.append(f"{folder[:2]} {cause} ({len(crashed)} cases)")
    expect(stacks > 0, "no crash showed a sanitizer's stack: the readable stack went untested")
    return (f"the same status on every shared case, check and grade; caught: {'; '.join(found)}; "
            f"{stacks} stacks demangled, the student's frames marked ({took:.0f} s)")

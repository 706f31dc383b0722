"""Self-test: the course-dependent self-tests pass on a customised copy of the kit (#35 item 3).

An instructor changes the course: the steps' points (here every step 20, the last one doubled; ★ as
5 % extra credit: weight 1/20 of a core case, "extra_credit": true), a
wall's colour in the scene file (include/raykit/scenes/cornell_box.inc, then `python3
docs/scene_tables.py` as CONTRIBUTING says), and a step of their own (the template of
tests/fixtures/new_step/ at the next free number, as CONTRIBUTING's "## A step" lists its files). A
self-test that read the shipped defaults then failed on a kit that is right: CI went red on a
customisation, and a TA could not tell one from a regression.

A scratch copy of the kit (its files, as ./kit handout lists them, in a git repository of its own under
build/customised-kit/) gets those three changes, and the self-tests that read the course run there:
the scale (`course`), lecture 05's tables from the scene file and the README's step table from the
manifests (`lectures`; the copy ran `python3 docs/readme_steps.py` after adding its step, as CONTRIBUTING
says), and the new-step test's
choice of number (the whole new-step test builds a step twice over; a customised copy's run of it is
in the closing note of #35, not here). The copy's new step is not recorded (`./kit check N --record`
needs a build): nothing run here reads its records. About 20 s on the shared 2-core machine.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

from ..common import BUILD
from .harness import expect, need_solutions

COPY = BUILD / "customised-kit"

# The self-tests run in the copy, by ./kit test's MODULE:WORDS.
DEPENDENT = ["course:the default scale", "course:course.json as set", "course:./kit course",
             "lectures:scene file", "lectures:README's step table"]


def customise(kit_dir: Path) -> dict:
    """The three changes of an instructor, in the copy at kit_dir; what was changed."""
    from . import newstep
    course_path = kit_dir / "course.json"
    course = json.loads(course_path.read_text())
    numbers = sorted(p.name[:2] for p in (kit_dir / "tests").glob("[0-9][0-9]_*") if (p / "step.json").is_file())
    course.setdefault("steps", {})
    for n in numbers:
        course["steps"][n] = {"points": 40 if n == numbers[-1] else 20}
    # ★ as 5 % extra credit: each ★ case passed adds a twentieth of a core case's points, on top.
    course.setdefault("groups", {})["robust"] = {"weight": "1/20", "extra_credit": True}
    course_path.write_text(json.dumps(course, indent=2) + "\n")

    scene = kit_dir / "include" / "raykit" / "scenes" / "cornell_box.inc"
    text = scene.read_text()
    m = next(m for m in re.finditer(r"(?m)^RAYKIT_SCENE_COLOR\((\w+),\s*([0-9.]+)f,(.*)\)\s*$", text)
             if m.group(1) != "light")
    value = float(m.group(2)) + (0.07 if float(m.group(2)) <= 0.9 else -0.07)
    scene.write_text(text.replace(m.group(0), f"RAYKIT_SCENE_COLOR({m.group(1)}, {value:.2f}f,{m.group(3)})", 1))
    r = subprocess.run([sys.executable, "docs/scene_tables.py"], cwd=kit_dir, capture_output=True, text=True)
    expect(r.returncode == 0, f"docs/scene_tables.py in the copy: {r.stderr[-400:]}")

    number = f"{int(numbers[-1]) + 1:02d}"
    for f in newstep.template_files():
        rel, body = newstep.numbered(f, (newstep.TEMPLATE / f).read_text(), number)
        (kit_dir / rel).parent.mkdir(parents=True, exist_ok=True)
        (kit_dir / rel).write_text(body)
    r = subprocess.run([sys.executable, "docs/readme_steps.py"], cwd=kit_dir, capture_output=True, text=True)
    expect(r.returncode == 0, f"docs/readme_steps.py in the copy: {r.stderr[-400:]}")
    newstep.commit(kit_dir, "customised: points, a colour, a step")
    return {"points": {n: course["steps"][n]["points"] for n in numbers}, "colour": f"{m.group(1)} {value:.2f}",
            "robust": course["groups"]["robust"],
            "step": number}


def selftest_customised(ctx) -> str:
    need_solutions()
    from . import newstep
    start = time.monotonic()
    kit_dir = newstep.scratch_kit(COPY)
    made = customise(kit_dir)
    r = subprocess.run([str(kit_dir / "kit"), "test", *DEPENDENT], cwd=kit_dir, capture_output=True, text=True,
                       timeout=900)
    out = r.stdout + r.stderr
    passed = re.findall(r"(?m)^✓ ", out)
    expect(r.returncode == 0 and len(passed) == len(DEPENDENT),
           f"in a customised copy ({made}), ./kit test {' '.join(DEPENDENT)}: exit {r.returncode}, "
           f"{len(passed)} of {len(DEPENDENT)} passed:\n{out[-1500:]}")
    expect(f"{made['colour'].split()[0]}" in out, f"the scene-table test did not change a colour the copy has:\n{out[-600:]}")
    # The new-step test's number in the copy: the one after the instructor's step.
    r = subprocess.run([sys.executable, "-c", "import sys; sys.path.insert(0, 'tools'); "
                        "from kitlib.selftest import newstep; print(newstep.free_number())"],
                       cwd=kit_dir, capture_output=True, text=True, timeout=120)
    want = f"{int(made['step']) + 1:02d}"
    expect(r.stdout.strip() == want, f"the new-step test would add step {r.stdout.strip() or r.stderr[-300:]} to "
                                     f"the copy that has a step {made['step']}, not {want}")
    shutil.rmtree(COPY, ignore_errors=True)
    points = "/".join(str(p) for p in made["points"].values())
    return (f"a copy with points {points}, {made['colour']}, a step {made['step']} from the template: "
            f"{len(DEPENDENT)} course-dependent self-tests pass there, the new-step test takes {want} "
            f"({time.monotonic() - start:.0f} s)")


def selftests():
    return [("customised: the course's self-tests on a customised copy", selftest_customised)]

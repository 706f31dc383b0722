"""Self-test: the course-dependent self-tests pass on the instructor's course as it stands, and on a
copy of it changed further (#35 item 3, #46 item 1).

An instructor changes the course: the steps' points, the groups' weights (the ★ tier as extra credit),
the reveal, a wall's colour in the scene file (include/raykit/scenes/cornell_box.inc), a step of their
own from the template. A self-test that read the shipped defaults then failed on a kit that is right:
CI went red on a customisation, and a TA could not tell one from a regression. So the self-tests that
read the course (DEPENDENT: the scale, the reveal, Gradescope's sums, extra credit and the roster;
lecture 05's tables and the README's step table; batch grading; the one scale of the stubs, a slip and
the solutions; the step 05 fixtures that read the scene's colours) run twice here:

1. on the kit as it stands, the instructor's course.json, scene and steps (in place, with its builds);
2. on a scratch copy of it (its files, as ./kit handout lists them, in a git repository of its own under
   build/customised-kit/) with the kit's own variations on top, each chosen to differ from the course
   as it stands: every step 20 points, the last 40 and the first 41/3 (a fraction, whose decimals must
   still add up exactly), each step's own weights (by case, by section) kept; the ★ tier as 5 % extra credit (weight 1/20, "extra_credit": true), or back
   to optional when the course has it as extra credit; the reveal after the due date turned the other
   way; a wall's colour moved by 0.07 (then `python3 docs/scene_tables.py`); and a step of their own, the
   template of tests/fixtures/new_step/ at the next free number (then `python3 docs/readme_steps.py`).
   The copy's new step is not recorded (`./kit check N --record` needs a build): nothing run here reads
   its records. Then the new-step test's choice of number in the copy: the one after that step.

The self-tests that make up cases for ./kit course list each step's recorded cases instead, so a course's
weights by case and by section name cases that exist (selftest/course.py, course_cases; issue 55). A failure is said
whole: each failed self-test's lines, the command's whole error (support.said).

Run it after each change of course.json or the scene (docs/instructors.md says so): 200 s measured on the kit as
shipped, 290 s on an instructor's customised course at a load of 9, 302 s on one with weights by case
and by section, ★ as extra credit, the reveal off, a due date, a new green and a step 06 from the
template at a load of 7 to 9, on the shared 2-core machine (its summary line gives each run's time).
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

from raykit.common import BUILD, ROOT
from .support import expect, last_lines, need_solutions
from .fixtures import fixture_dir

COPY = BUILD / "customised-kit"

# The self-tests that read the course, by ./kit test's MODULE:WORDS: run on the course as it stands,
# then in the customised copy.
DEPENDENT = ["course", "lectures:scene tables", "lectures:readme steps", "workflow",
             "slips:turned render", "integrity:one scale"]


def customise(kit_dir: Path) -> dict:
    """The three changes of an instructor, in the copy at kit_dir; what was changed."""
    from . import newstep
    course_path = kit_dir / "course.json"
    course = json.loads(course_path.read_text())
    numbers = sorted(p.name[:2] for p in (kit_dir / "tests").glob("[0-9][0-9]_*") if (p / "step.json").is_file())
    course.setdefault("steps", {})
    for n in numbers:      # other points; a step's own weights (by case, by section) kept as they are
        entry = course["steps"].get(n) if isinstance(course["steps"].get(n), dict) else {}
        course["steps"][n] = dict(entry, points=40 if n == numbers[-1] else "41/3" if n == numbers[0] else 20)
    # ★ as 5 % extra credit (each ★ case passed adds a twentieth of a core case's points, on top), or,
    # where the course has it as extra credit already, back to optional (weight 0, the default).
    from raykit import course as course_file
    groups = course.setdefault("groups", {})
    was_extra = course_file.read(course_path, numbers).extra_credit("robust")
    groups["robust"] = {"weight": 0} if was_extra else {"weight": "1/20", "extra_credit": True}
    # The reveal after the due date, the other way round from the course's.
    hidden = course.setdefault("hidden", {})
    hidden["reveal_after_due_date"] = not hidden.get("reveal_after_due_date", True)
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
        rel, body = newstep.numbered(f, (fixture_dir("new_step") / f).read_text(), number)
        (kit_dir / rel).parent.mkdir(parents=True, exist_ok=True)
        (kit_dir / rel).write_text(body)
    r = subprocess.run([sys.executable, "docs/readme_steps.py"], cwd=kit_dir, capture_output=True, text=True)
    expect(r.returncode == 0, f"docs/readme_steps.py in the copy: {r.stderr[-400:]}")
    newstep.commit(kit_dir, "customised: points, ★, the reveal, a colour, a step")
    return {"points": {n: course["steps"][n]["points"] for n in numbers}, "colour": f"{m.group(1)} {value:.2f}",
            "robust": "optional" if was_extra else "extra credit", "reveal": hidden["reveal_after_due_date"],
            "step": number}


def failures(out: str) -> list[str]:
    """Each failure of a ./kit test run's output (pytest's), whole: its section of pytest's FAILURES,
    from its ___ name ___ line to the next (a failure's reason runs over several lines: a command's error)."""
    m = re.search(r"(?ms)^=+ (?:FAILURES|ERRORS) =+$(.*?)^=+ ", out)
    if not m:
        return []
    return [part.strip() for part in re.split(r"(?m)^(?=_{3,} .* _{3,}$)", m.group(1)) if part.strip()]


def run_dependent(kit_dir: Path, where: str) -> tuple[str, str]:
    """./kit test DEPENDENT in `kit_dir`: a failure names the self-tests that failed there; else the
    counts of its summary line and the time, and what it printed."""
    start = time.monotonic()
    r = subprocess.run([str(kit_dir / "kit"), "test", *DEPENDENT], cwd=kit_dir, capture_output=True, text=True,
                       timeout=3600)
    out = r.stdout + r.stderr
    m = re.search(r"(?m)^selftest: (\d+) passed, (\d+) failed, (\d+) skipped", out)
    failed = failures(out)
    expect(r.returncode == 0 and m and int(m.group(1)) > 0 and m.group(2) == "0",
           f"on {where}, ./kit test {' '.join(DEPENDENT)}: exit {r.returncode}, "
           + (f"{m.group(1)} passed, {m.group(2)} failed" if m else "no summary line") + ":\n"
           + ("\n".join(failed) if failed else last_lines(out, 30)))
    skipped = re.findall(r"(?m)^SKIPPED \[\d+\] \S+?:\d+: (.*)", out)
    return (f"{m.group(1)} pass" + (f", {m.group(3)} skipped ({'; '.join(skipped)})" if skipped else "")
            + f", {time.monotonic() - start:.0f} s"), out


def selftest_customised(ctx) -> str:
    need_solutions()
    from raykit import course as course_file
    from . import newstep
    start = time.monotonic()
    # 1. The instructor's course as it stands.
    here = course_file.read(course_file.COURSE_FILE, [s.number for s in ctx.steps])
    as_is, _ = run_dependent(ROOT, "the course as it stands")
    # 2. A copy of it with the kit's variations on top.
    kit_dir = newstep.scratch_kit(COPY)
    made = customise(kit_dir)
    varied = course_file.read(kit_dir / "course.json", [s.number for s in ctx.steps] + [made["step"]])
    expect(varied.reveal_after_due_date != here.reveal_after_due_date
           and varied.extra_credit("robust") != here.extra_credit("robust"),
           f"the copy's variations do not differ from the course as it stands: {made}")
    copied, out = run_dependent(kit_dir, f"a customised copy ({made})")
    expect(made["colour"].split()[0] in out, f"the scene-table test did not name the colour the copy changed:\n{out[-600:]}")
    # The new-step test's number in the copy: the one after the instructor's step.
    r = subprocess.run([sys.executable, "-c", "import sys; sys.path[:0] = ['tools', 'tests']; "
                        "from kit import newstep; print(newstep.free_number())"],
                       cwd=kit_dir, capture_output=True, text=True, timeout=120)
    want = f"{int(made['step']) + 1:02d}"
    expect(r.stdout.strip() == want, f"the new-step test would add step {r.stdout.strip() or r.stderr[-300:]} to "
                                     f"the copy that has a step {made['step']}, not {want}")
    shutil.rmtree(COPY, ignore_errors=True)
    points = " ".join(str(p) for p in made["points"].values())
    return (f"the course as it stands ({here.source}: reveal {'on' if here.reveal_after_due_date else 'off'}, ★ "
            f"{'extra credit' if here.extra_credit('robust') else 'not extra credit'}, {len(ctx.steps)} steps): {as_is}; "
            f"a copy with points {points}, ★ {made['robust']}, reveal {'on' if made['reveal'] else 'off'}, "
            f"{made['colour']}, a step {made['step']} from the template: {copied}; the new-step test takes {want} "
            f"({time.monotonic() - start:.0f} s in all)")

#!/usr/bin/env python3
"""PrairieLearn's entry point for one kit step: grade /grade/student, write /grade/results/results.json.

    python3 grade.py NN [GRADE] [--extra-credit]
                                        (GRADE: the job's folder, default /grade; --extra-credit: the
                                        step's extra-credit question, graded on those cases alone)

Each question's tests/grade.py runs this file from the kit in /grade/serverFilesCourse/raykit/ with the
question's step. The student's files (one <pl-file-editor> per step file) are copied into a steps folder
of their own and `./kit check NN --steps THAT --prairielearn FILE` checks them (the instructor's kit:
hidden cases and the sandbox apply) and writes PrairieLearn's results itself (tools/raykit/plresults.py,
drawn from the same results as every other output: no display text is parsed here). A step that does
not compile is graded 0 with the compiler's first diagnostic, so the student sees why (PrairieLearn's
documentation would also allow "not gradable" for a syntax error: the kit grades it, as its other
graders do).

The kit's side (tools/raykit/bundle.py: the judges, the reference, the hidden cases) comes prebuilt:
serverFilesCourse/raykit-bundle/, built by the grading image's own toolchain when the image is built
(prebuild.py, graders/raykit/README.md), beside the kit in every job, private to the course as the
kit is. The check uses it when it is this kit's under this image's compiler and packages (its key),
and compiles the student's files alone; otherwise it builds its own and the results say so and why
("built", "built_why"). The job's folder is closed to other users first: graded code runs as one
(the user isolation, in PrairieLearn's container) and needs nothing of it.

The whole file stays under 1 MB (images dropped first, then outputs shortened). Only a failure of the
kit itself (no JSON, an exit status other than 0 or 1, the time budget RAYKIT_BUDGET seconds exceeded)
is written as {"gradable": false}: the student loses no attempt to the kit's fault.
Standard library only, Python 3.9+.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

KIT = Path(__file__).resolve().parents[2]
PREBUILT = KIT.parent / "raykit-bundle"     # serverFilesCourse/raykit-bundle/ (prebuild.py)
LIMIT = 1_000_000           # bytes: PrairieLearn's limit on results.json ("1 MB")


def write(results_dir: Path, data: dict) -> None:
    results_dir.mkdir(parents=True, exist_ok=True)   # PrairieLearn does not create it
    text = fit(data)
    tmp = results_dir / ".results.json.tmp"
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(results_dir / "results.json")


def fit(data: dict) -> str:
    """The JSON text, at most LIMIT bytes: images go first, then outputs and messages are cut."""
    text = json.dumps(data, ensure_ascii=False)
    if len(text.encode()) <= LIMIT:
        return text
    data = dict(data, images=[], tests=[{k: v for k, v in t.items() if k != "images"}
                                        for t in data.get("tests", [])])
    for cut in (1000, 200, 0):
        for t in data.get("tests", []):
            for k in ("message", "output"):
                if isinstance(t.get(k), str) and len(t[k]) > cut:
                    t[k] = t[k][:cut] + ("… (cut: results are limited to 1 MB)" if cut else "")
        text = json.dumps(data, ensure_ascii=False)
        if len(text.encode()) <= LIMIT:
            return text
    return json.dumps({"gradable": False, "message": "the results did not fit in 1 MB"})


def not_gradable(results_dir: Path, why: str) -> int:
    write(results_dir, {"gradable": False, "message": f"The grader could not grade this submission: {why}",
                        "format_errors": [why]})
    return 0


def identity(grade_dir: Path) -> str:
    """The submission's name for the hidden cases' seed: the question's variant (data.json's
    variant_seed); the files' bytes are in the seed too, so another attempt with other code draws
    other inputs."""
    try:
        seed = json.loads((grade_dir / "data" / "data.json").read_text()).get("variant_seed")
    except (OSError, ValueError, AttributeError):
        seed = None
    return f"prairielearn:{seed}" if isinstance(seed, (int, str)) and str(seed) else ""


def grade(number: str, grade_dir: Path, part: str = "step") -> int:
    results_dir = grade_dir / "results"
    steps = {p.parent.name[:2]: p for p in (KIT / "tests").glob("[0-9][0-9]_*/step.json")}
    number = number.zfill(2)
    if number not in steps:
        return not_gradable(results_dir, f"the kit has no step {number}")
    manifest = json.loads(steps[number].read_text())
    folder = steps[number].parent.name
    budget = float(os.environ.get("RAYKIT_BUDGET", "540"))
    started = time.monotonic()
    # Graded code runs as another user (the user isolation): nothing of the job's folder is its, not
    # the kit, its copy PrairieLearn also puts in /grade/shared, or the prebuilt bundle.
    mode = grade_dir.stat().st_mode
    if mode & 0o007:
        os.chmod(grade_dir, mode & ~0o007)
    env = dict(os.environ, RAYKIT_PREBUILT_BUNDLE=str(PREBUILT))
    isolation = os.environ.get("RAYKIT_AUTOGRADER_ISOLATION")   # the self-test's seam, as Gradescope's
    with tempfile.TemporaryDirectory(prefix="raykit-") as tmp:
        staged = Path(tmp) / "steps"
        (staged / folder).mkdir(parents=True)
        os.chmod(tmp, 0o755)
        for name in manifest["files"]:
            src = grade_dir / "student" / name
            if src.is_file():
                shutil.copyfile(src, staged / folder / name)
        out = Path(tmp) / "results.json"
        try:
            r = subprocess.run([str(KIT / "kit"), "check", number, "--steps", str(staged), "--prairielearn", str(out),
                                "--prairielearn-part", part, "--identity", identity(grade_dir)]
                               + (["--isolation", isolation] if isolation in ("bwrap", "user") else []),
                               capture_output=True, text=True, env=env,  # not --quiet: it draws the pictures
                               timeout=max(budget - (time.monotonic() - started), 1), cwd=KIT)
        except subprocess.TimeoutExpired:
            return not_gradable(results_dir, f"grading took more than {budget:g} s (RAYKIT_BUDGET)")
        if r.returncode not in (0, 1) or not out.is_file():
            return not_gradable(results_dir, f"./kit check exited {r.returncode}: "
                                f"{(r.stderr.strip() or r.stdout.strip())[-1500:]}")
        try:
            data = json.loads(out.read_text())
        except ValueError as e:
            return not_gradable(results_dir, f"the kit's results could not be read ({e})")
    write(results_dir, data)
    return 0


def main(argv: list[str]) -> int:
    part = "extra" if "--extra-credit" in argv else "step"
    argv = [a for a in argv if a != "--extra-credit"]
    if not argv or len(argv) > 2:
        print("usage: grade.py NN [GRADE] [--extra-credit]", file=sys.stderr)
        return 2
    grade_dir = Path(argv[1] if len(argv) > 1 else "/grade")
    try:
        return grade(argv[0], grade_dir, part)
    except OSError as e:
        try:
            return not_gradable(grade_dir / "results", f"{e}")
        except OSError:
            print(f"grade.py: cannot write {grade_dir}/results: {e}", file=sys.stderr)
            return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

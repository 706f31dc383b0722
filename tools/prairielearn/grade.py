#!/usr/bin/env python3
"""PrairieLearn's entry point for one kit step: grade /grade/student, write /grade/results/results.json.

    python3 grade.py NN [GRADE]        (GRADE: the job's folder, default /grade)

Each question's tests/grade.py runs this file from the kit in /grade/serverFilesCourse/raykit/ with the
question's step. The student's files (one <pl-file-editor> per step file) are copied into a steps folder
of their own, `./kit check NN --steps THAT --json FILE` checks them (the instructor's kit: hidden cases
and the sandbox apply), and its JSON (Gradescope's format, the kit's one scale) becomes PrairieLearn's
results (docs/externalGrading.md, read by externalGraderCommon.ts's makeGradingResult):

  score        earned / maximum, in [0, 1]: every basic and hidden case one point, ★ cases none
  tests[]      one per case: name, description (the lecture section), points, max_points (★: 0, shown
               neutrally), message (passed, or the kit's words), output (what the code printed)
  images       the picture of the first failing visible case, an SVG data URL (also on its test)
  message      the step's state and score; a step that does not compile is graded 0 with the
               compiler's first diagnostic, so the student sees why (PrairieLearn's documentation would
               also allow "not gradable" for a syntax error: the kit grades it, as its other graders do)

The whole file stays under 1 MB (images dropped first, then outputs shortened). Only a failure of the
kit itself (no JSON, an exit status other than 0 or 1, the time budget RAYKIT_BUDGET seconds exceeded)
is written as {"gradable": false}: the student loses no attempt to the kit's fault.
Standard library only, Python 3.9+.
"""

from __future__ import annotations

import base64
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

KIT = Path(__file__).resolve().parents[2]
LIMIT = 1_000_000           # bytes: PrairieLearn's limit on results.json ("1 MB")
TEXT = 4000                 # characters per test's message or output, before any shortening


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


def picture(path: str | None) -> str | None:
    try:
        if path and Path(path).is_file() and Path(path).stat().st_size < 300_000:
            return "data:image/svg+xml;base64," + base64.b64encode(Path(path).read_bytes()).decode()
    except OSError:
        pass
    return None


def convert(gs: dict, staged: Path, record: dict | None = None) -> dict:
    """Gradescope's results.json, as the kit writes it for students (no hidden input, no reference
    answer), in PrairieLearn's form; each case's lecture section, tier and picture from the kit's
    own record (kitlib/record.py), which stays here."""
    def clean(text: str) -> str:      # the student knows their file by its name, not our folder
        return text.replace(str(staged) + "/", "")[:TEXT]

    steps = (record or {}).get("steps", [])
    cases = [c for s in steps for c in s.get("cases", [])]
    tests, images = [], []
    # Gradescope's tests are not one a case (the ★ tier and a compile error are one test a step):
    # each test is matched to the case its name ends with, the longest such name.
    names = sorted(cases, key=lambda c: -len(c["name"]))
    for t in gs.get("tests", []):
        case = next((c for c in names if t["name"].endswith(c["name"])), {})
        lines = t.get("output", "").split("\nYour code printed", 1)
        test = {"name": t["name"], "description": f"lecture section: {case['lecture']}" if case.get("lecture") else "",
                "points": t["score"], "max_points": t["max_score"], "message": clean(lines[0]),
                "output": clean("Your code printed" + lines[1]) if len(lines) > 1 else ""}
        if t["status"] != "passed" and not images and t.get("visibility") == "visible" \
                and case.get("tier") == "basic":
            url = picture(case.get("picture"))
            if url:
                image = {"label": case.get("picture_summary") or t["name"], "url": url}
                test["images"] = [image]
                images.append(image)
        tests.append(test)
    maximum = gs.get("extra_data", {}).get("max_score", 0)
    earned = gs.get("score", 0)
    message = (gs.get("output", "").splitlines() or [f"score {earned} of {maximum}"])[0]
    # A step that does not compile: its first diagnostic, from the compiler's output (the step's detail).
    diagnostic = next((clean(line.strip()) for s in steps if s.get("state") == "no_compile"
                       for line in s.get("detail", "").splitlines() if "error" in line.lower()), "")
    if not diagnostic:
        diagnostic = next((line for t in tests for line in t["message"].splitlines()
                           if line.startswith("does not compile:")), "")
    if diagnostic:
        message += "\n" + diagnostic
    return {"gradable": True, "score": (earned / maximum) if maximum else 0.0, "message": message,
            "output": clean(gs.get("output", "")), "images": images, "tests": tests}


def identity(grade_dir: Path) -> str:
    """The submission's name for the hidden cases' seed: the question's variant (data.json's
    variant_seed); the files' bytes are in the seed too, so another attempt with other code draws
    other inputs."""
    try:
        seed = json.loads((grade_dir / "data" / "data.json").read_text()).get("variant_seed")
    except (OSError, ValueError, AttributeError):
        seed = None
    return f"prairielearn:{seed}" if isinstance(seed, (int, str)) and str(seed) else ""


def grade(number: str, grade_dir: Path) -> int:
    results_dir = grade_dir / "results"
    steps = {p.parent.name[:2]: p for p in (KIT / "tests").glob("[0-9][0-9]_*/step.json")}
    number = number.zfill(2)
    if number not in steps:
        return not_gradable(results_dir, f"the kit has no step {number}")
    manifest = json.loads(steps[number].read_text())
    folder = steps[number].parent.name
    budget = float(os.environ.get("RAYKIT_BUDGET", "540"))
    started = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="raykit-") as tmp:
        staged = Path(tmp) / "steps"
        (staged / folder).mkdir(parents=True)
        os.chmod(tmp, 0o755)
        for name in manifest["files"]:
            src = grade_dir / "student" / name
            if src.is_file():
                shutil.copyfile(src, staged / folder / name)
        out = Path(tmp) / "results.json"
        kept = Path(tmp) / "record.json"
        try:
            r = subprocess.run([str(KIT / "kit"), "check", number, "--steps", str(staged), "--json", str(out),
                                "--results", str(kept), "--identity", identity(grade_dir)],
                               capture_output=True, text=True,  # not --quiet: it draws the pictures
                               timeout=max(budget - (time.monotonic() - started), 1), cwd=KIT)
        except subprocess.TimeoutExpired:
            return not_gradable(results_dir, f"grading took more than {budget:g} s (RAYKIT_BUDGET)")
        if r.returncode not in (0, 1) or not out.is_file():
            return not_gradable(results_dir, f"./kit check exited {r.returncode}: "
                                f"{(r.stderr.strip() or r.stdout.strip())[-1500:]}")
        try:
            data = convert(json.loads(out.read_text()), staged / folder, json.loads(kept.read_text()))
        except (ValueError, KeyError, TypeError) as e:
            return not_gradable(results_dir, f"the kit's results could not be read ({e})")
    write(results_dir, data)
    return 0


def main(argv: list[str]) -> int:
    if not argv or len(argv) > 2:
        print("usage: grade.py NN [GRADE]", file=sys.stderr)
        return 2
    grade_dir = Path(argv[1] if len(argv) > 1 else "/grade")
    try:
        return grade(argv[0], grade_dir)
    except OSError as e:
        try:
            return not_gradable(grade_dir / "results", f"{e}")
        except OSError:
            print(f"grade.py: cannot write {grade_dir}/results: {e}", file=sys.stderr)
            return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

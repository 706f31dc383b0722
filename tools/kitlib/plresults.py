"""The results of ./kit check in PrairieLearn's external-grader format, for --prairielearn FILE.

Rendered from the same results as the terminal, Gradescope's file and the kit's record; only this
module knows PrairieLearn's fields (docs/externalGrading.md, read by externalGraderCommon.ts's
makeGradingResult) and what a PrairieLearn student may see:

  score        earned / (maximum + extra credit) on the course's scale, in [0, 1]: the question is worth
               the step's points plus its extra credit (./kit prairielearn's info and assessment: the
               assessment's maxPoints counts the steps' points, maxBonusPoints the extra credit), so
               score × the question's points is what the student earned, extra credit included
  tests[]      one per scored case: name, description (the lecture section), points, max_points (adding
               up to the step's points, and its extra credit, on the course's decimals), message, output
               (what the code printed);
               the optional (★) cases one 0-point test a step; a step that does not compile, misses a
               file or waits for another, one failed test with the reason
  images       the picture of the first failing visible case, an SVG data URL (also on its test)
  message      the step's state and score, and a compile error's first diagnostic
  gradable     false when a step is not graded (the grader's fault, kitlib/faults.py): PrairieLearn then
               marks the submission "invalid, not gradable", awards and takes no points and charges no
               attempt (docs/externalGrading.md); format_errors says why, in the student's words

PrairieLearn has no due date to reveal after: a hidden case never shows its input, what the reference
answered or what the code printed during it, only its family. The adapter
(tools/prairielearn/grade.py) fits the file under PrairieLearn's 1 MB.
"""

from __future__ import annotations

import base64
import json
from fractions import Fraction
from pathlib import Path

from . import atomic
from . import course as course_file
from . import faults
from .checking import StepResult
from .common import KitError
from .gradescope import UNRUN_STATES, shown_shares, split_cases
from .scoreboard import compile_errors
from .status import NOT_GRADED, NO_COMPILE, PASS, STATE_WORDS, STATUS_WORDS

TEXT = 4000         # characters per message or output
AGAIN = "this attempt is not counted: submit again, and tell your instructor if it stays so"
HIDDEN_WORDS = ("a hidden case: random inputs of this family, drawn for this submission; its inputs are not "
                "shown here, only whether your code gets them right")
# PrairieLearn has no "after the due date" for a question's results: what a job wrote is what the student
# sees, then and later. So the kit says it once, plainly.
HIDDEN_NOTE = ("Hidden cases (marked so) are graded and counted like the others; PrairieLearn never shows "
               "their inputs, before or after the due date.")


def picture_url(path: str | None) -> str | None:
    try:
        if path and Path(path).is_file() and Path(path).stat().st_size < 300_000:
            return "data:image/svg+xml;base64," + base64.b64encode(Path(path).read_bytes()).decode()
    except OSError:
        pass
    return None


def prairielearn(results: list[StepResult], shown_dir: str = "") -> dict:
    course = course_file.load()

    def clean(text: str) -> str:        # the student knows their file by its name, not our folder
        return (text.replace(shown_dir.rstrip("/") + "/", "") if shown_dir else text)[:TEXT]

    tests, images, notes = [], [], []
    for r in results:
        s = r.step
        cases, counted, bonus, optional = split_cases(r, course)
        if r.state == NOT_GRADED:
            tests.append({"name": f"Step {s.number} · {s.title}: not graded", "description": "", "points": 0,
                          "max_points": 0, "message": clean(faults.to_student(r.reason, AGAIN)), "output": ""})
            continue
        if r.state in UNRUN_STATES and cases:
            detail = "\n".join(compile_errors(r.detail, 40)) if r.state == NO_COMPILE else (r.detail or "")
            tests.append({"name": f"Step {s.number} · {s.title}: {STATE_WORDS[r.state]}",
                          "description": "", "points": 0, "max_points": course.number(r.maximum),
                          "message": clean(f"{STATE_WORDS[r.state]}: its {len(cases)} cases were not run.\n{detail}".strip()),
                          "output": ""})
            if r.state == NO_COMPILE:
                first = next((line.strip() for line in r.detail.splitlines() if "error" in line.lower()), "")
                if first:
                    notes.append(clean(first))
            continue
        # Extra credit: the question is worth the step's points and its bonus (the assessment counts the
        # bonus above its maxPoints), so its cases are scored tests, named as extra credit.
        shares = shown_shares([c.points for c in counted], course) + shown_shares([c.points for c in bonus], course)
        for c, points in zip(counted + bonus, shares):
            hidden = c.tier == "hidden"
            extra = " (extra credit)" if course.extra_credit(c.group) else ""
            test = {"name": f"Step {s.number}{' (hidden)' if hidden else ''}{extra} · {c.name}",
                    "description": f"lecture section: {c.lecture}" if c.lecture else "",
                    "points": points if c.status == PASS else 0, "max_points": points,
                    "message": STATUS_WORDS.get(c.status, c.status), "output": ""}
            if c.status != PASS:
                test["message"] = clean("\n".join([test["message"]] + ([HIDDEN_WORDS] if hidden else c.messages[:3])))
                if c.output_bytes and not hidden:
                    test["output"] = clean(f"Your code printed ({c.output_bytes} bytes):\n{c.output[:2000]}")
                if not hidden and not images and c.tier == "basic":
                    url = picture_url(c.picture)
                    if url:
                        image = {"label": c.picture_summary or test["name"], "url": url}
                        test["images"] = [image]
                        images.append(image)
            tests.append(test)
        if optional:
            passed = sum(c.status == PASS for c in optional)
            lines = [f"Optional, worth no points: {passed} of {len(optional)} pass."]
            for c in optional:
                if c.status != PASS:
                    lines += [f"✗ {c.name}"] + ["    " + m for m in c.messages[:2]]
            tests.append({"name": f"Step {s.number} ★ · optional cases: {passed} of {len(optional)} pass",
                          "description": "", "points": 0, "max_points": 0, "message": clean("\n".join(lines)),
                          "output": ""})
    exact = sum((c.points for r in results for c in r.cases if c.status == PASS), Fraction(0))
    maximum = sum((r.maximum for r in results), Fraction(0))
    bonus = sum((bonus_maximum(r, course) for r in results), Fraction(0))
    message = "; ".join(f"step {r.step.number}: {STATE_WORDS[r.state]}" + ("" if r.state == NOT_GRADED else
                        f", {course.shown(r.earned)} of {course.shown(r.maximum)}") for r in results)
    if notes:
        message += "\n" + notes[0]
    extra = f" and {course.shown(bonus)} of extra credit" if bonus else ""
    missed = [r for r in results if r.state == NOT_GRADED]
    if missed:      # not gradable: no points given or taken, no attempt used; the student is told why
        errors = [clean(f"Step {r.step.number}: " + faults.to_student(r.reason, AGAIN)) for r in missed]
        return {"gradable": False, "format_errors": errors, "message": "\n".join(errors + [message]),
                "images": images, "tests": tests}
    return {"gradable": True, "score": float(exact / (maximum + bonus)) if maximum + bonus else 0.0,
            "message": message,
            "output": f"score {course.shown(exact)} of {course.shown(maximum)}{extra} ({course.scale_words()})"
                      + (f". {HIDDEN_NOTE}" if any(c.tier == "hidden" for r in results for c in r.cases
                                                   if course.hidden_enabled) else ""),
            "images": images, "tests": tests}


def bonus_maximum(r: StepResult, course) -> Fraction:
    """The extra credit a step's cases can add on top of its points."""
    return sum((c.points for c in split_cases(r, course)[2]), Fraction(0))


def write(path: str, results: list[StepResult], shown_dir: str = "") -> None:
    target = Path(path)
    if not target.parent.is_dir():
        raise KitError(f"--prairielearn {path}: folder {target.parent} does not exist")
    try:
        atomic.write(target, json.dumps(prairielearn(results, shown_dir), ensure_ascii=False))
    except OSError as e:
        raise KitError(f"--prairielearn {path}: cannot write it ({e.strerror})")

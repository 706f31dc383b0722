"""The results of ./kit check in PrairieLearn's external-grader format, for --prairielearn FILE.

Rendered from the same results as the terminal, Gradescope's file and the kit's record; only this
module knows PrairieLearn's fields (docs/externalGrading.md, read by externalGraderCommon.ts's
makeGradingResult) and what a PrairieLearn student may see:

  score        what a question's cases earned of its points, in [0, 1] (PrairieLearn's range for a
               submission). PrairieLearn gives bonus points one way: an assessment's maxBonusPoints,
               points earned above its maxPoints, from questions of their own (its docs, "Assessment
               points"). So a step with extra-credit cases (course.json: a group's "extra_credit") is
               two questions (./kit prairielearn): the step's, worth its points, whose score leaves the
               extra-credit cases out (a complete step scores 1), and the step's extra credit, worth the
               extra points, graded on those cases alone (part "extra", --prairielearn-part extra)
  tests[]      one per scored case of the question: name, description (the lecture section), points,
               max_points (adding up to the question's points on the course's decimals), message,
               output (what the code printed); the optional (★) cases one 0-point test a step, and in
               the step's question its extra-credit cases one 0-point test naming the question that
               counts them; a step that does not compile, misses a file or waits for another, one
               failed test with the reason
  images       the picture of the first failing visible case, an SVG data URL (also on its test)
  message      the step's state and score, and a compile error's first diagnostic
  built        "student files only" when this job built nothing of the kit's side (a bundle prebuilt
               for the image: ./kit prairielearn, graders/raykit/README.md), else "kit side built in this
               job" and built_why, why (the kit's record's fields, raykit/record.py; the output says it
               in a sentence)
  gradable     false when a step is not graded (the grader's fault, raykit/faults.py): PrairieLearn then
               marks the submission "invalid, not gradable", awards and takes no points and charges no
               attempt (docs/externalGrading.md); format_errors says why, in the student's words

PrairieLearn has no due date to reveal after: a hidden case never shows its input, what the reference
answered or what the code printed during it, only its family. The adapter
(tools/prairielearn/grade.py) fits the file under PrairieLearn's 1 MB.
"""

from __future__ import annotations

import base64
import json
from contextlib import suppress
from fractions import Fraction
from pathlib import Path

from . import course as course_file
from . import faults
from .bundle import STUDENT_ONLY
from .cases import StepResult
from .common import KitError
from .record import built_fields, write_output
from .gradescope import UNRUN_STATES, shown_shares, split_cases, unrun_text
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
    with suppress(OSError):
        if path and Path(path).is_file() and Path(path).stat().st_size < 300_000:
            return "data:image/svg+xml;base64," + base64.b64encode(Path(path).read_bytes()).decode()
    return None


PARTS = ("step", "extra")


def prairielearn(results: list[StepResult], shown_dir: str = "", part: str = "step") -> dict:
    """The results as PrairieLearn's question `part` reads them: "step", the step's points; "extra",
    its extra-credit cases alone (the bonus question of ./kit prairielearn)."""
    if part not in PARTS:
        raise KitError(f"--prairielearn-part {part}: one of {', '.join(PARTS)}")
    course = course_file.load()
    extra_part = part == "extra"

    def clean(text: str) -> str:        # the student knows their file by its name, not our folder
        return (text.replace(shown_dir.rstrip("/") + "/", "") if shown_dir else text)[:TEXT]

    tests, images, notes = [], [], []
    earned, maximum = Fraction(0), Fraction(0)
    for r in results:
        s = r.step
        cases, counted, bonus, optional = split_cases(r, course)
        scored = bonus if extra_part else counted
        worth = sum((c.points for c in scored), Fraction(0))
        maximum += worth
        if r.state == NOT_GRADED:
            tests.append({"name": f"Step {s.number} · {s.title}: not graded", "description": "", "points": 0,
                          "max_points": 0, "message": clean(faults.to_student(r.reason, AGAIN)), "output": ""})
            continue
        if r.state in UNRUN_STATES and cases:
            tests.append({"name": f"Step {s.number} · {s.title}: {STATE_WORDS[r.state]}", "description": "",
                          "points": 0, "max_points": course.number(worth), "message": clean(unrun_text(r, cases)),
                          "output": ""})
            if r.state == NO_COMPILE:
                first = next((line.strip() for line in r.detail.splitlines() if "error" in line.lower()), "")
                if first:
                    notes.append(clean(first))
            continue
        earned += sum((c.points for c in scored if c.status == PASS), Fraction(0))
        for c, points in zip(scored, shown_shares([c.points for c in scored], course)):
            hidden = c.tier == "hidden"
            extra = " (extra credit)" if extra_part else ""
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
        if bonus and not extra_part:        # counted in the step's extra-credit question, not here
            passed = sum(c.status == PASS for c in bonus)
            tests.append({"name": f"Step {s.number} ★ · extra credit: {passed} of {len(bonus)} pass",
                          "description": "", "points": 0, "max_points": 0,
                          "message": clean(f"Extra credit, counted by this step's extra-credit question (submit "
                                           f"the same code there): {passed} of {len(bonus)} cases pass here, worth "
                                           f"{course.shown(sum((c.points for c in bonus if c.status == PASS), Fraction(0)))} "
                                           f"of {course.shown(sum((c.points for c in bonus), Fraction(0)))} extra "
                                           "points."), "output": ""})
        if optional and not extra_part:
            passed = sum(c.status == PASS for c in optional)
            lines = [f"Optional, worth no points: {passed} of {len(optional)} pass."]
            for c in optional:
                if c.status != PASS:
                    lines += [f"✗ {c.name}"] + ["    " + m for m in c.messages[:2]]
            tests.append({"name": f"Step {s.number} ★ · optional cases: {passed} of {len(optional)} pass",
                          "description": "", "points": 0, "max_points": 0, "message": clean("\n".join(lines)),
                          "output": ""})
    what = "extra credit" if extra_part else "score"
    message = "; ".join(f"step {r.step.number}: {STATE_WORDS[r.state]}" + ("" if r.state == NOT_GRADED else
                        f", {course.shown(sum(mine[0]))} of {course.shown(sum(mine[1]))}" + (" extra" if extra_part else ""))
                        for r in results for mine in [part_points(r, course, extra_part)])
    if notes:
        message += "\n" + notes[0]
    built = built_fields()      # the kit's record's "built": what this job compiled (bundle.built)
    missed = [r for r in results if r.state == NOT_GRADED]
    if missed:      # not gradable: no points given or taken, no attempt used; the student is told why
        errors = [clean(f"Step {r.step.number}: " + faults.to_student(r.reason, AGAIN)) for r in missed]
        return {"gradable": False, **built, "format_errors": errors, "message": "\n".join(errors + [message]),
                "images": images, "tests": tests}
    output = (f"{what} {course.shown(earned)} of {course.shown(maximum)}" + (
                      " (the extra-credit cases; the assessment counts these points above its total)" if extra_part
                      else f" ({course.scale_words()})")
                      + (f". {HIDDEN_NOTE}" if any(c.tier == "hidden" for r in results for c in r.cases
                                                   if course.hidden_enabled) and not extra_part else ""))
    output += ("" if output.endswith(".") else ".") + (" Built in this job: your files only." if built["built"] == STUDENT_ONLY
                                                       else " Built in this job: your files and the grader's own side.")
    return {"gradable": True, "score": float(earned / maximum) if maximum else 0.0, **built,
            "message": message, "output": output, "images": images, "tests": tests}


def part_points(r: StepResult, course, extra_part: bool) -> tuple[list[Fraction], list[Fraction]]:
    """The points a step's cases of one part earned, and those they are worth."""
    scored = split_cases(r, course)[2 if extra_part else 1]
    return ([c.points for c in scored if c.status == PASS] or [Fraction(0)], [c.points for c in scored] or [Fraction(0)])


def write(path: str, results: list[StepResult], shown_dir: str = "", part: str = "step") -> None:
    write_output("--prairielearn", path, json.dumps(prairielearn(results, shown_dir, part), ensure_ascii=False))

"""The results of ./kit check as GitHub Classroom's grading steps hand them on, for --classroom FILE.

Rendered from the same results as the terminal, the kit's record, Gradescope's and PrairieLearn's
files; only this module knows what Classroom's reporter (classroom-resources/autograding-grading-
reporter) reads and what a Classroom student may see. The workflow `./kit classroom` writes runs
`./kit check --classroom FILE` once, then tools/classroom/result.py FILE NN per kit step, which
hands step NN's runner object on as that step's `result` output, unchanged:

    {"format": "raykit-classroom", "version": 1,
     "score": 41, "max_score": 48,          # what the reporter's "Points X/Y" must read
     "kit_score": 41, "kit_max_score": 48,  # the kit's score on the course's scale
     "runners": {"01": RUNNER, ...}}

RUNNER is the command grader's version 1 result (autograding-command-grader): status "pass",
"fail" or "error", max_score, and tests[] of name, status, score, message, test_code, filename,
line_no, duration. The reporter's notice "Points X/Y" sums the tests' scores and the runners'
max_score, its console table computes passes / tests x max_score; the two agree because every
entry is one counted case worth exactly one point (max_score: the step's counted cases). So
"Points" is the kit's score where each counted case is worth one point (the default course.json),
and the number of counted cases passed otherwise. Extra-credit cases and the optional ones (★,
worth nothing) are not entries: the step's last entry names how many of them pass.

A step whose cases did not run (no compile, a missing file) has every counted case failed, the
first carrying the compiler's words, so the step's maximum stays the same; in a step that waits for
another, each case that waits says so. Hidden
cases (none in a handout, which is what Classroom grades) show only their family: Classroom has
no due date to reveal them after.

A step the grader failed (status.NOT_GRADED, raykit/faults.py) is a runner with status "error", its
entries "error" and worth nothing (max_score 0): the reporter then fails the workflow with "Some
tests errored." (Classroom's own way to say that no grade came), and the entry says why and to run
it again. The file's "not_graded" lists them; the placeholder written before the check has
"finished": false, which tools/classroom/result.py turns into such an error for every step.
"""

from __future__ import annotations

import json
from fractions import Fraction

from . import course as course_file
from . import faults
from .cases import StepResult
from .gradescope import case_lines, split_cases
from .record import write_output
from .scoreboard import compile_errors
from .status import NOT_GRADED, MISSING, NO_COMPILE, PASS, STATE_WORDS

FORMAT = "raykit-classroom"
VERSION = 1
MESSAGE_CHARS = 1500    # per entry: what the reporter's log shows
HIDDEN_WORDS = "a hidden case: random inputs of this family; its inputs are not shown here"


def entry(name: str, passed: bool, message: str) -> dict:
    return {"name": name, "status": "pass" if passed else "fail", "score": int(passed),
            "message": message[:MESSAGE_CHARS], "test_code": "", "filename": "", "line_no": 0, "duration": 0}


def runner(r: StepResult, course) -> dict:
    s = r.step
    _, counted, bonus, optional = split_cases(r, course)
    if r.state == NOT_GRADED:      # no verdict: an error worth nothing, never a failed case
        why = faults.to_student(r.reason, "run the workflow again (Actions: Re-run jobs), and tell your "
                                          "instructor if it stays so")
        return {"version": 1, "status": "error", "max_score": 0,
                "tests": [{**entry(f"Step {s.number} · {s.title}: not graded", False, why), "status": "error"}]}
    if not counted:     # the kit could not list the step's cases: one entry worth nothing, with why
        why = f"{STATE_WORDS[r.state]}. {r.detail}".strip()
        return {"version": 1, "status": "error", "max_score": 0,
                "tests": [{**entry(f"Step {s.number} · {s.title}", False, why), "status": "error"}]}
    entries = [entry(f"Step {s.number}{' (hidden)' if c.tier == 'hidden' else ''} · {c.name}",
                     c.status == PASS, "\n".join(case_lines(r, c, False, HIDDEN_WORDS, 1000))) for c in counted]
    if r.state == NO_COMPILE:       # the compiler's words once, on the first entry
        errors = "\n".join(compile_errors(r.detail, 20))
        entries[0]["message"] = (f"{STATE_WORDS[r.state]}: no case ran.\n{errors}")[:MESSAGE_CHARS]
    notes = [f"({kind}: {sum(c.status == PASS for c in cases)} of {len(cases)} pass)"
             for kind, cases in (("optional, worth no points", optional), ("extra credit, not counted here", bonus))
             if cases and r.state not in (NO_COMPILE, MISSING)]
    if notes:
        note = "\n".join(notes)
        entries[-1]["message"] = entries[-1]["message"][:MESSAGE_CHARS - len(note) - 1] + "\n" + note
    status = ("error" if r.state == NOT_GRADED else
              "pass" if all(e["status"] == "pass" for e in entries) else "fail")
    return {"version": 1, "status": status, "max_score": len(entries), "tests": entries}


def classroom(results: list[StepResult]) -> dict:
    course = course_file.load()
    counted = [split_cases(r, course)[1] if r.state != NOT_GRADED else [] for r in results]   # as the runners
    earned = sum((c.points for cases in counted for c in cases if c.status == PASS), Fraction(0))
    return {"format": FORMAT, "version": VERSION,
            # What the reporter's "Points X/Y" must read: counted cases passed, of all counted cases.
            "score": sum(c.status == PASS for cases in counted for c in cases),
            "max_score": sum(len(cases) for cases in counted),
            # The kit's own score on the course's scale, extra credit left out (the same where every
            # counted case is worth one point).
            "kit_score": course.number(earned),
            "kit_max_score": course.number(sum((r.maximum for r in results), Fraction(0))),
            "finished": bool(results),     # false: the placeholder, written before the check
            "not_graded": [{"step": r.step.number, "reason": r.reason} for r in results if r.state == NOT_GRADED],
            "runners": {r.step.number: runner(r, course) for r in results}}


def write(path: str, results: list[StepResult]) -> None:
    write_output("--classroom", path, json.dumps(classroom(results), ensure_ascii=False))

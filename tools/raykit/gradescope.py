"""The results of ./kit check in Gradescope's autograder format (results.json), for --json.

What the student's platform keeps: the tests' words, and in extra_data only each step's state and
points. Never a hidden case's input, the reference's answer to it, what the code printed during it
or the seed, unless --reveal (after the due date): a later submission is handed this file
(submission_metadata.json's previous_submissions), and so could the code it runs. The kit's own
record of everything is record.py's, kept by the grader.

On the course's scale (course.json, raykit/course.py): points are exact fractions; each test shows
its case's points rounded for display, and the top-level `score` (which Gradescope takes instead of
the tests' sum) is the exact total rounded once, at the end.

What Gradescope's documented fields allow (gradescope-autograders.readthedocs.io, specs): a test
has score, max_score, status ("passed" or "failed" only: no "informational" or "skipped" status),
name, number, output, output_format, tags, visibility, extra_data. So:
  - the optional cases (the ★ tier, and any group of weight 0) are one test per step with
    max_score 0 and status "passed" whatever they gave (informational: never shown as a failure),
    its output listing the ones that fail;
  - the extra-credit cases (a group's "extra_credit" in course.json) are one test per step with
    max_score 0, the extra points they earned as its score (a score above max_score is extra credit
    to Gradescope) and status "passed" whatever they gave: missing one takes nothing from the
    assignment, so it never reads as a failed test; its output names those missed. The summary
    says the assignment's points and the extra apart ("115 + 7.78 extra");
  - a step that does not compile (or misses a file, or waits for another) is one failed test
    worth the step's points, carrying the diagnostic; its cases are "not run", not 44 failures;
  - a step the grader failed (status.NOT_GRADED: its fault, not the student's; raykit/faults.py) is
    one failed test worth 0 of 0, "Step NN: not graded — REASON", so no point is taken away; the
    format has no "not graded", so the summary's first line says it and asks for a regrade
    (Gradescope's Request Regrade), and extra_data carries "gradable" and "not_graded";
  - the placeholder written before the check (no results yet) is one such test, for the whole upload.
"""

from __future__ import annotations

import json
from datetime import datetime, timezone
from fractions import Fraction
from pathlib import Path

from . import course as course_file
from . import faults
from .bundle import STUDENT_ONLY
from .cases import StepResult
from .record import built_fields, write_output
from .scoreboard import compile_errors
from .status import MISSING, NOT_GRADED, NO_COMPILE, PASS, STATE_WORDS, STATUS_WORDS, WAITING

UNRUN_STATES = (NO_COMPILE, MISSING, WAITING)
REGRADE = "ask for a regrade (Request Regrade on this page), or submit again"


def case_lines(r: StepResult, c, reveal: bool, hidden_words: str = "", printed: int = 2000) -> list[str]:
    """A case's words on a platform; a hidden one's inputs, messages and output only with `reveal`,
    else `hidden_words` (the course's hidden_note) in their place."""
    hidden = c.tier == "hidden" and not reveal
    lines = [STATUS_WORDS.get(c.status, c.status)]
    if c.status != PASS:
        lines += [hidden_words or course_file.hidden_note()] if hidden else c.messages[:3]
        if c.output_bytes and not hidden:
            lines.append(f"Your code printed ({c.output_bytes} bytes):\n{c.output[:printed]}")
        if c.lecture:
            lines.append(f"Read {r.step.lecture}, section \"{c.lecture}\".")
    return lines


def unrun_text(r: StepResult, cases: list) -> str:
    """Why a step's cases did not run (UNRUN_STATES), with the compiler's first errors."""
    detail = "\n".join(compile_errors(r.detail, 40)) if r.state == NO_COMPILE else (r.detail or "")
    return f"{STATE_WORDS[r.state]}: its {len(cases)} cases were not run.\n{detail}".strip()


def split_cases(r: StepResult, course) -> tuple[list, list, list, list]:
    """A step's cases as every platform's results show them: those shown at all (hidden ones only when
    the course counts them), then the counted ones, the extra-credit ones and the optional ones
    (worth nothing), each in the step's order but for the case `./kit check` shows first
    (StepResult.first_problem: the best-explained failure), which leads, so that the first failed test
    on Gradescope, PrairieLearn's picture and Classroom's first line say what the terminal says."""
    cases = [c for c in r.cases if c.tier != "hidden" or course.hidden_enabled]
    lead = r.first_problem("basic") or r.first_problem("hidden") if r.cases else None
    if lead is not None and lead in cases:
        cases = [lead] + [c for c in cases if c is not lead]
    scored = [c for c in cases if c.points > 0]
    return (cases, [c for c in scored if not course.extra_credit(c.group)],
            [c for c in scored if course.extra_credit(c.group)], [c for c in cases if c.points == 0])


def shown_shares(values: list[Fraction], course) -> list[int | float]:
    """Each of `values` on the course's decimals, so that they add up to their exact sum rounded once
    (largest remainders): a step's tests show points that sum to the step's points, where rounding
    each alone could give 120.05 of 120."""
    unit = Fraction(1, 10 ** course.decimals)
    target = round(Fraction(course.rounded(sum(values, Fraction(0)))) / unit)
    floors = [(v / unit).__floor__() for v in values]
    left = int(target - sum(floors))
    order = sorted(range(len(values)), key=lambda i: (-(values[i] / unit - floors[i]), i))
    for i in order[:max(left, 0)]:
        floors[i] += 1
    return [course.number(f * unit) for f in floors]


def _test(name: str, number: str | None, score, max_score, status: str, output: str, tags: list[str],
          visibility: str = "visible") -> dict:
    """One test of results.json in Gradescope's fields (`number` None: the test has none)."""
    return {"name": name, **({"number": number} if number is not None else {}), "score": score,
            "max_score": max_score, "status": status, "visibility": visibility, "output": output, "tags": tags}


def extra_credit_test(r: StepResult, bonus: list, number: int, course, visibility: str, reveal: bool) -> dict:
    """A step's extra-credit cases (course.json: a group's "extra_credit") as one test: max_score 0 and
    the points they earned as its score (Gradescope counts a score above a test's max_score as extra
    credit), and status "passed" whatever they gave: a missed extra-credit case takes nothing from the
    assignment, so it is never a failed test of it. Its output names the ones missed, and why."""
    s = r.step
    earned = [c for c in bonus if c.status == PASS]
    points = sum((c.points for c in earned), Fraction(0))
    most = sum((c.points for c in bonus), Fraction(0))
    lines = [f"Extra credit, on top of the step's {course.shown(r.maximum)} points: {len(earned)} of {len(bonus)} "
             f"cases pass, {course.shown(points)} of {course.shown(most)} extra points."]
    for c in bonus:
        if c.status != PASS:
            lines += [f"not earned: {c.name}"] + ["    " + l for l in case_lines(r, c, reveal)]
    hidden = any(c.tier == "hidden" for c in bonus)
    return _test(f"Step {s.number} ★ · extra credit: {len(earned)} of {len(bonus)} cases, +{course.shown(points)} "
                 f"of {course.shown(most)}", f"{int(s.number)}.{number}", course.number(points), 0, "passed",
                 "\n".join(lines)[:8000], [f"step{s.number}", "extra_credit"], visibility if hidden else "visible")


def gradescope(results: list[StepResult], elapsed: float, hidden_visibility: str | None = None,
               reveal: bool = False) -> dict:
    """The results in Gradescope's autograder format (results.json); hidden_visibility None: the
    course file's."""
    course = course_file.load()
    visibility = hidden_visibility or course.hidden_visibility
    tests = []
    for r in results:
        s = r.step
        cases, counted, bonus, optional = split_cases(r, course)
        if r.state == NOT_GRADED:   # no verdict: worth 0 of 0 here, so nothing is taken away
            tests.append(_test(f"Step {s.number} · {s.title}: not graded — {r.reason}"[:300], f"{int(s.number)}.0",
                               0, 0, "failed", faults.to_student(r.reason, REGRADE), [f"step{s.number}", "not_graded"]))
            continue
        if r.state in UNRUN_STATES and cases:
            tests.append(_test(f"Step {s.number} · {s.title}: {STATE_WORDS[r.state]}", f"{int(s.number)}.0", 0,
                               course.number(r.maximum), "failed", unrun_text(r, cases)[:8000],
                               [f"step{s.number}", r.state]))
            continue
        shown = shown_shares([c.points for c in counted], course)
        for i, (c, points) in enumerate(zip(counted, shown), 1):
            mark, passed = {"robust": " ★", "hidden": " (hidden)"}.get(c.tier, ""), c.status == PASS
            tests.append(_test(f"Step {s.number}{mark} · {c.name}", f"{int(s.number)}.{i}", points if passed else 0,
                               points, "passed" if passed else "failed", "\n".join(case_lines(r, c, reveal)),
                               [f"step{s.number}", c.tier, c.group], visibility if c.tier == "hidden" else "visible"))
        if bonus:
            tests.append(extra_credit_test(r, bonus, len(counted) + 1, course, visibility, reveal))
        if optional:
            passed = sum(c.status == PASS for c in optional)
            groups = sorted({"★ tier" if c.group == "robust" else c.group for c in optional})
            lines = [f"Optional, worth no points ({', '.join(groups)}): {passed} of {len(optional)} pass."]
            for c in optional:
                if c.status != PASS:
                    lines += [f"✗ {c.name}"] + ["    " + l for l in case_lines(r, c, reveal)]
            tests.append(_test(f"Step {s.number} ★ · optional cases: {passed} of {len(optional)} pass",
                               f"{int(s.number)}.{len(counted) + bool(bonus) + 1}", 0, 0, "passed",
                               "\n".join(lines)[:8000], [f"step{s.number}", "optional"]))
        if not r.cases:  # the kit's own test program failed: say so
            tests.append(_test(f"Step {s.number} · {s.title}", s.number, 0, course.number(r.maximum), "failed",
                               f"{STATE_WORDS[r.state]}. {r.detail[:4000]}".strip(), [f"step{s.number}"]))
    exact = sum((r.earned for r in results), Fraction(0))
    maximum = sum((r.maximum for r in results), Fraction(0))
    summary = [f"step {r.step.number}: {STATE_WORDS[r.state]}, " + ("no points taken" if r.state == NOT_GRADED else
               f"{course.shown(base)} of {course.shown(r.maximum)}" + (f" + {course.shown(extra)} extra" if extra else ""))
               for r in results for base, extra in [course_file.split_extra([r])]]
    summary.append(course_file.score_words(results)
                   + (f" (exact {course_file.exact_text(exact)} in all, rounded once to {course.decimals} decimals)"
                      if exact.denominator != 1 else ""))
    possible = course_file.extra_maximum(results)
    if possible:
        summary.append(f"the assignment is worth {course.shown(maximum)} points + {course.shown(possible)} extra: "
                       "extra-credit cases add their points when they pass and take nothing away when they do not")
    hidden = [c for r in results for c in r.cases if c.tier == "hidden" and course.hidden_enabled and c.points > 0]
    if hidden and not reveal and visibility != "visible":
        held = sum((c.points for c in hidden), Fraction(0))
        summary.append(f"{len(hidden)} hidden cases hold {course.shown(held)} of the {course.shown(maximum)} points: "
                       "they count in the score above, and their tests are shown "
                       + {"after_due_date": "after the due date", "after_published": "once grades are published",
                          "hidden": "to your instructor only"}.get(visibility, "later")
                       + ("" if course.reveal_after_due_date else "; their inputs are never shown"))
    isolation = next((r.isolation for r in results if r.isolation), "")
    if isolation:
        summary.append(f"graded code: {isolation}")
    built = built_fields()
    summary.append("built in this job: " + ("your files only (the kit's side was built before it)"
                                            if built["built"] == STUDENT_ONLY else "your files and the kit's side"))
    missed = [r for r in results if r.state == NOT_GRADED]
    if missed:      # first, where Gradescope shows the output
        summary.insert(0, f"NOT GRADED: step {', '.join(r.step.number for r in missed)}: the grader could not "
                          f"check {'them' if len(missed) > 1 else 'it'} (the grader's fault, not your code's). The "
                          f"score above leaves {'them' if len(missed) > 1 else 'it'} out; {REGRADE}.")
    if not results:     # the placeholder ./kit check writes before it starts: no result yet
        why = "the grader stopped before it finished"
        tests.append(_test(f"Not graded — {why}", None, 0, 0, "failed", faults.to_student(why, REGRADE),
                           ["not_graded"]))
        summary = [f"NOT GRADED: {why} (the grader's fault, not your code's); {REGRADE}."]
    return {"score": float(course.rounded(exact)) if exact.denominator != 1 else exact.numerator,
            "execution_time": round(elapsed, 3), "output": "\n".join(summary),
            "visibility": "visible", "stdout_visibility": "hidden", "tests": tests,
            "extra_data": {"max_score": course.number(maximum), "score_exact": course_file.exact_text(exact),
                           "max_score_exact": course_file.exact_text(maximum), "rounding": course.decimals,
                           "gradable": bool(results) and not missed, **built,
                           "not_graded": [{"step": r.step.number, "reason": r.reason} for r in missed],
                           # Each step's state and points, nothing of its cases: the kit's own record
                           # (record.py, with every input and expected answer) stays on the grader's side.
                           "step_scores": [{"step": r.step.number, "state": r.state,
                                            "earned_exact": course_file.exact_text(r.earned),
                                            "maximum_exact": course_file.exact_text(r.maximum)} for r in results]}}


def _when(text) -> datetime | None:
    if not isinstance(text, str) or not text:
        return None
    try:
        t = datetime.fromisoformat(text.replace("Z", "+00:00"))
    except ValueError:
        return None
    return t if t.tzinfo else t.replace(tzinfo=timezone.utc)


def due_date(metadata: dict) -> datetime | None:
    """The last date anyone may submit: the assignment's late due date, else its due date (the fields
    Gradescope documents), or a later one in a users[] entry's "assignment" (not documented; read if
    there)."""
    assignments = [metadata.get("assignment")] + [u.get("assignment") for u in metadata.get("users") or []
                                                  if isinstance(u, dict)]
    dates = [_when(a.get("late_due_date")) or _when(a.get("due_date")) for a in assignments if isinstance(a, dict)]
    return max((d for d in dates if d), default=None)


def reveal_options(metadata_path: Path, now: datetime | None = None) -> list[str]:
    """The ./kit check options Gradescope's run passes, from /autograder/submission_metadata.json and
    course.json: --hidden-visibility always, --reveal when the course reveals after the due date and
    the submission was made after it (a missing or unreadable file: no reveal)."""
    course = course_file.load()
    options = ["--hidden-visibility", course.hidden_visibility]
    try:
        metadata = json.loads(metadata_path.read_text())
    except (OSError, ValueError):
        return options
    if not isinstance(metadata, dict):
        return options
    due = due_date(metadata)
    made = _when(metadata.get("created_at")) or now or datetime.now(timezone.utc)
    if course.reveal_after_due_date and due is not None and made > due:
        options.append("--reveal")
    return options


def write_json(path: str, results: list[StepResult], elapsed: float, hidden_visibility: str | None = None,
               reveal: bool = False) -> None:
    write_output("--json", path, json.dumps(gradescope(results, elapsed, hidden_visibility, reveal), indent=2,
                                            ensure_ascii=False))

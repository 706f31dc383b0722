"""The kit's own results record: one file per grading of one submission, written by
`./kit check --results FILE`, read by everything of the instructor's side (`./kit grade`, the
class report, `./kit mutant`, `./kit course --check`, PrairieLearn's adapter, the portability
check). The outputs students see (the terminal, Gradescope's results.json, PrairieLearn's results,
GitHub Classroom's per-step results) are drawn from the same results, each by its own renderer; none
of them parses another.

The record is the grader's: it holds every case's messages, hidden ones included (their inputs and
the reference's answers), and the hidden cases' seeds. It is never handed to a student's platform;
`./kit grade` keeps it in its grading folder.

    {"format": "raykit-results", "version": 1,
     "score": 41, "max_score": 48,                  # on the course's scale, rounded once
     "score_exact": "41", "max_score_exact": "48", "rounding": 2,
     "extra_credit_exact": "3/2",                   # of the score, what extra-credit cases added on
     "extra_credit_max_exact": "5/2",               # top of max_score, and what they could have
     "execution_time": 3.1, "identity": "", "isolation": "...",
     "finished": true,                              # false: the placeholder ./kit check writes first
     "gradable": true,                              # false when a step is not graded (the grader's fault)
     "not_graded": [{"step": "03", "reason": "..."}],
     "grader": {"secret": "...", "cases": "..."},   # what drew and judged it (see `grader`)
     "built": "student files only",                # or "kit side built in this job", and then
     "built_why": "...",                            # why (bundle.built: the kit's own doing)
     "steps": [StepResult.to_json(), ...],          # raykit/cases.py
     "mac": "..."}                                  # in a grading folder: its seal (secret.seal)

The seal is put on by `./kit grade` as it keeps the record (HMAC-SHA256 of the rest under a key derived
from the secret); the merge of several machines' gradings refuses a record whose seal fails.

A placeholder (finished false, no steps) is not a result: whoever reads one where a result should be
(the check died after writing it) says "not graded", never "0 of 0".
"""

from __future__ import annotations

import functools
import json
from fractions import Fraction
from pathlib import Path

from . import atomic
from . import course as course_file
from . import judgedby
from . import secret as secret_file
from .cases import StepResult
from .common import KitError
from .status import NOT_GRADED, OLD_BROKEN

FORMAT = "raykit-results"
VERSION = 1


def make(results: list[StepResult], elapsed: float, identity: str = "", finished: bool = True) -> dict:
    course = course_file.load()
    missed = [{"step": r.step.number, "reason": r.reason} for r in results if r.state == NOT_GRADED]
    exact = sum((r.earned for r in results), Fraction(0))
    maximum = sum((r.maximum for r in results), Fraction(0))
    _, extra = course_file.split_extra(results)
    return {"format": FORMAT, "version": VERSION,
            "score": course.number(exact), "max_score": course.number(maximum),
            "score_exact": course_file.exact_text(exact), "max_score_exact": course_file.exact_text(maximum),
            "extra_credit_exact": course_file.exact_text(extra),
            "extra_credit_max_exact": course_file.exact_text(course_file.extra_maximum(results)),
            "rounding": course.decimals, "execution_time": round(elapsed, 3), "identity": identity,
            "isolation": next((r.isolation for r in results if r.isolation), ""),
            "finished": finished, "gradable": finished and not missed, "not_graded": missed,
            "grader": grader(), **built_fields(), "steps": [r.to_json() for r in results]}


def built_fields() -> dict:
    """What this check built of the kit's side (bundle.built): "built", and "built_why" when it built
    any (the record's; each grader's results render the same)."""
    from . import bundle
    done = bundle.built()
    return {"built": done["built"], **({"built_why": done["why"]} if "why" in done else {})}


@functools.lru_cache(maxsize=None)
def grader() -> dict:
    """Which secret drew the hidden inputs (secret.fingerprint) and which copy of the kit judged them: the
    digest of every input that can change a verdict or a point (judgedby.py; ./kit grade hashes them once
    and hands each check the digest). Two gradings compare only when both are equal, as the merge of
    several machines' gradings checks (report/merge.py), which names the first file that differs from the
    lists ./kit grade keeps."""
    return {"secret": secret_file.fingerprint(), "cases": judgedby.current_digest()}


def write_output(option: str, path: str | Path, text: str) -> None:
    """Writes `text` to the file `path` the command line's `option` named, whole or not at all
    (atomic.write); KitError, with the option, when it cannot."""
    target = Path(path)
    if not target.parent.is_dir():
        raise KitError(f"{option} {path}: folder {target.parent} does not exist")
    if target.is_dir():
        raise KitError(f"{option} {path}: is a folder, not a file")
    try:
        atomic.write(target, text)
    except OSError as e:
        raise KitError(f"{option} {path}: cannot write it ({e.strerror})")


def write(path: str | Path, data: dict) -> None:
    """Writes `data` whole or not at all (atomic.write)."""
    write_output("--results", path, json.dumps(data, indent=1, ensure_ascii=False))


def read(path: str | Path) -> dict:
    """A record written by `write`; KitError when the file is not one."""
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, ValueError) as e:
        raise KitError(f"{path}: not a results record ({e.__class__.__name__})")
    if not is_record(data):
        raise KitError(f"{path}: not a raykit results record (format {FORMAT} version {VERSION})")
    return data


def is_record(data: object) -> bool:
    return (isinstance(data, dict) and data.get("format") == FORMAT and data.get("version") == VERSION
            and isinstance(data.get("steps"), list))


def cases(data: dict) -> list[dict]:
    """Every case of every step, in order, each with its step's number under "step"."""
    return [dict(c, step=s["step"]) for s in data["steps"] for c in s.get("cases", [])]


def finished(data: dict) -> bool:
    """Whether a record is a result, not the placeholder a check writes first (a record of a kit
    before "finished": one with steps)."""
    return bool(data.get("finished", bool(data.get("steps"))))


def extra_credit(data: dict) -> tuple[Fraction, Fraction]:
    """What a record's score holds of extra credit, on top of its max_score, and what it could have
    held (0 and 0 for a record written before extra credit was kept apart)."""
    return Fraction(data.get("extra_credit_exact", "0")), Fraction(data.get("extra_credit_max_exact", "0"))


def not_graded(data: dict) -> list[tuple[str, str]]:
    """(step, reason) of each step of a record that is not graded: from its data, never its words."""
    return [(str(s.get("step", "")), str(s.get("not_graded") or s.get("detail") or "the grader failed").splitlines()[0])
            for s in data.get("steps", []) if s.get("state") in (NOT_GRADED, OLD_BROKEN)]

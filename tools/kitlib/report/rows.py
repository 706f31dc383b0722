"""The rows of ./kit grade's two CSV files, made from a results record (record_row) and written
(csv_text, each cell through csv_safe): below both commands that write them, `./kit grade` and the merge
of several machines' gradings (report/merge.py), so both write the same bytes for the same rows."""

from __future__ import annotations

import csv
import io
from fractions import Fraction

from raykit import course as course_file
from raykit import record as results_record
from raykit.common import printable
from raykit.status import CRASHED, DONE, GRADER_ERROR, NOT_GRADED, OLD_BROKEN, STATE_WORDS, THREW, TIMED_OUT

NOT_GRADED_WORDS = "not graded"     # a row's status, a step's cells: no verdict, the grader's fault


def csv_safe(cell) -> str:
    """One cell as written to a CSV: the one call point where the cells of both CSV files pass (the
    roster's too). Its control characters are shown as text (printable(): a folder name or a note
    holding an escape sequence would replay on `cat grades.csv`), and a text a spreadsheet would run
    as a formula (=, +, -, @, tab first; a CR is shown as \\x0d by then) gets a leading '."""
    text = "" if cell is None else printable(str(cell))
    if text[:1] in ("=", "+", "-", "@", "\t", "\r") and not _number(text):
        return "'" + text
    return text


def _decimal(exact: str) -> str:
    """A case's exact points ("10/23") as a decimal of 6 places at most (a spreadsheet reads 10/23
    as a date); the totals are rounded from the exact sum, not from these."""
    f = Fraction(exact)
    d = (course_file.Decimal(f.numerator) / f.denominator).quantize(course_file.Decimal("0.000001"))
    return format(d.normalize(), "f")


def _number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


def csv_text(cols: list[str], rows: list[dict]) -> str:
    text = io.StringIO()
    writer = csv.writer(text)
    writer.writerow([csv_safe(c) for c in cols])
    for r in rows:
        writer.writerow([csv_safe(r.get(c, "")) for c in cols])
    return text.getvalue()


def record_row(row: dict, data: dict, steps, left_out: list[str] = ()) -> dict:
    """A submission's row of the grades CSV from its results record (raykit/record.py): the total on
    the course's decimals, the extra credit it holds apart, each step; `left_out`, what its upload had
    that was not graded."""
    course = course_file.load()
    exact = Fraction(data["score_exact"])
    maximum = Fraction(data["max_score_exact"])
    row["earned"], row["earned_exact"] = course.shown(exact), course_file.exact_text(exact)
    row["maximum"] = course.shown(maximum)
    extra, possible = results_record.extra_credit(data)
    row["extra_credit"] = course.shown(extra) if possible else ""
    share = 100 * (exact - extra) / maximum if maximum else None
    row["percent"] = f"{course_file.Decimal(share.numerator) / share.denominator:.1f}" if share is not None else ""
    row["_cases"] = [{"step": s["step"], "case": c["name"], "tier": c["tier"], "group": c.get("group", ""),
                      "status": c["status"], "points": _decimal(c.get("points", "0")),
                      "earned": NOT_GRADED_WORDS if c["status"] == GRADER_ERROR or s["state"] in (NOT_GRADED, OLD_BROKEN)
                      else _decimal(c.get("points", "0")) if c["status"] == "pass" else "0"}
                     for s in data["steps"] for c in s["cases"]]
    by_number = {s["step"]: s for s in data["steps"]}
    row["status"] = "complete" if all(s["state"] == DONE for s in by_number.values()) else "incomplete"
    missed = results_record.not_graded(data)
    if missed:      # no verdict for a step: no total either, and a retry alone (_grade)
        row.update(status=NOT_GRADED_WORDS, earned=NOT_GRADED_WORDS, earned_exact="", percent="", extra_credit="",
                   _retry=True)
    row["isolation"] = next((s["isolation"] for s in by_number.values() if s.get("isolation")), "")
    notes = []
    for s in steps:
        res = by_number.get(s.number)
        if res is None:
            continue
        row[f"step{s.number}_state"] = STATE_WORDS.get(res["state"], res["state"])
        row[f"step{s.number}_earned"] = course.shown(Fraction(res.get("earned_exact", res["earned"])))
        row[f"step{s.number}_maximum"] = course.shown(Fraction(res.get("maximum_exact", res["maximum"])))
        row[f"step{s.number}_robust"] = res["robust"]["passed"]
        row[f"step{s.number}_robust_total"] = res["robust"]["total"]
        if res["state"] in (NOT_GRADED, OLD_BROKEN):    # no verdict: no points, no ★ count either
            row[f"step{s.number}_earned"] = NOT_GRADED_WORDS
            row[f"step{s.number}_robust"] = row[f"step{s.number}_robust_total"] = ""
            continue
        bad = sorted({c["status"] for c in res["cases"] if c["status"] in (CRASHED, TIMED_OUT, THREW)})
        if bad:
            notes.append(f"step {s.number}: {' '.join(bad)}")
        again = [c for c in res["cases"] if c.get("runs", 1) > 1]
        if again:
            notes.append(f"step {s.number}: {len(again)} case(s) run again after a timeout, "
                         f"{sum(c['status'] == 'pass' for c in again)} then passed")
    why: dict[str, list[str]] = {}
    for number, reason in missed:       # one note per reason: a full disk fails every step alike
        why.setdefault(reason, []).append(number)
    notes[:0] = [f"step {', '.join(numbers)} not graded: {reason}" for reason, numbers in why.items()]
    if left_out:        # what the upload had that was not graded, whole
        notes.append("left out: " + "; ".join(left_out))
    row["note"] = "; ".join(notes)
    return row

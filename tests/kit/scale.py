"""What a score should be, derived from the course as it stands: for the self-tests that grade the
solutions, a slip or a class (issue 46, item 1). Not a module of self-tests: the helpers they share.

An instructor's course.json may set any points, weights and groups (raykit/course.py). What a self-test
expects of a grading is then read from that course and from the grading's own record (raykit/record.py:
each case's group, status and exact points), never from the shipped defaults:

- full marks: every counted case passed, and the step earned its maximum plus the points of the
  extra-credit cases it passed ("extra_credit": true on a group). On the default course that is its
  maximum; with the ★ tier as extra credit the reference reads, say, 10.26 of 10.
- the counted points: what was earned less that extra credit, the part a slip must lose (a slip with
  the ★ cases right may earn more than the maximum, and still lose counted points).
- sums of the decimals a platform is given (Gradescope's tests' max_score) are exact: each value is
  taken as the decimal it was written as, as a fraction, so seven shares of 115 add up to 115, not
  114.99999999999982.
"""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

from raykit import course as course_file
from raykit.status import PASS


def exact(value) -> Fraction:
    """A number as written (an int, a JSON float, "41/3", "10.26") as an exact fraction: a float is
    taken as its shortest decimal, the one the kit wrote."""
    if isinstance(value, Fraction):
        return value
    if isinstance(value, str):
        value = value.strip()
        return Fraction(value) if "/" in value else Fraction(Decimal(value))
    if isinstance(value, bool):
        raise TypeError(f"not a number: {value!r}")
    return Fraction(Decimal(repr(value))) if isinstance(value, float) else Fraction(value)


def exact_sum(values) -> Fraction:
    return sum((exact(v) for v in values), Fraction(0))


def extra(group: str) -> bool:
    return course_file.load().extra_credit(group)


def counted(group: str) -> bool:
    """A group whose cases a step's maximum counts (not optional, not extra credit)."""
    course = course_file.load()
    return not course.optional(group) and not course.extra_credit(group)


def bonus(cases: list[dict]) -> Fraction:
    """The extra credit a step's cases (a record's, or the cases CSV's rows) earned: the points of the
    extra-credit cases passed."""
    return sum((exact(c["points"]) for c in cases if c["status"] == PASS and extra(c["group"])), Fraction(0))


def counted_failed(cases: list[dict]) -> list[str]:
    return [c["name"] if "name" in c else c["case"] for c in cases if counted(c["group"]) and c["status"] != PASS]


def earned(step: dict) -> Fraction:
    return exact(step["earned_exact"] if "earned_exact" in step else step["earned"])


def maximum(step: dict) -> Fraction:
    return exact(step["maximum_exact"] if "maximum_exact" in step else step["maximum"])


def base(step: dict) -> Fraction:
    """A record's step: the counted points it earned (its extra credit left out)."""
    return earned(step) - bonus(step["cases"])


def short_of_full(step: dict) -> str:
    """"" when a record's step has full marks on the course (see the docstring); else what it lacks,
    in words that name the cases and the numbers."""
    failed = counted_failed(step["cases"])
    want = maximum(step) + bonus(step["cases"])
    course = course_file.load()
    problems = []
    if failed:
        problems.append(f"{len(failed)} counted case(s) fail ({', '.join(failed[:3])})")
    if earned(step) != want:
        more = bonus(step["cases"])
        problems.append(f"earned {course.shown(earned(step))}, not {course.shown(maximum(step))}"
                        + (f" + {course.shown(more)} extra credit" if more else ""))
    return f"step {step['step']}: " + "; ".join(problems) if problems else ""


def full_total(record: dict) -> Fraction:
    """What a record whose counted cases all pass earns in all: its maximum and its extra credit."""
    return sum((maximum(s) + bonus(s["cases"]) for s in record["steps"]), Fraction(0))


def record_short_of_full(record: dict) -> str:
    """"" when every step of a record has full marks and its score is their sum on the course's
    rounding; else what is short, step by step."""
    course = course_file.load()
    short = [w for w in (short_of_full(s) for s in record["steps"]) if w]
    want = full_total(record)
    if exact(record["score_exact"] if "score_exact" in record else record["score"]) != want:
        short.append(f"the score is {record['score_exact'] if 'score_exact' in record else record['score']}, not {course.shown(want)}")
    return "; ".join(short)


def rounded(value: Fraction) -> Fraction:
    """`value` as the course rounds a total (half up, its decimals), exact."""
    return Fraction(course_file.load().rounded(value))


def shown(value: Fraction) -> str:
    return course_file.load().shown(value)

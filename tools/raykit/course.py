"""The course's scale: course.json at the kit's root, read and checked here.

course.json is plain JSON (Python 3.9 reads no TOML). What it holds:

  "steps":  {"NN": {"points": P, "weights": {KEY: W}}}
                                    the points of step NN. P is an integer, a decimal ("2.5") or a
                                    fraction ("41/3"); null means "one point per unit of weight", the
                                    sum of its cases' weights (the default: one point per case).
                                    "weights" (optional) gives single cases a weight of their own,
                                    where a group is too coarse: KEY is a case's name as ./kit course
                                    --cases lists it, or "section N" for every case pointing to its
                                    lecture's section N; W replaces the group's weight (a name before
                                    a section). A case of an optional group stays optional, an
                                    extra-credit one stays extra credit. ./kit course refuses a KEY
                                    that names no counted case.
  "groups": {"core" | "degenerate" | "hidden" | "robust": {"weight": W}}
                                    every case belongs to exactly one group, by this rule:
                                      - a case of the ★ tier (doctest suite "robust") is "robust";
                                      - a case of the hidden tier (suite "hidden") is "hidden";
                                      - a basic case whose name contains one of "degenerate"'s
                                        "names" (whole words, any case: "NaN", "zero direction",
                                        "radius of zero", ...) is "degenerate";
                                      - every other case is "core".
                                    A step's P points are shared among its cases in proportion to
                                    their weights. Weight 0 makes a group optional: its cases are
                                    run and shown like the ★ tier, worth nothing.
                                    "extra_credit": true makes a group's cases a bonus: each is worth
                                    its weight's share as if the group were counted, but on top of the
                                    step's P points (the maximum stays P: ★ at weight 1/20 and extra
                                    credit adds 5 % of a core case's points for each ★ case passed).
                                    Every output keeps it apart: the total reads "score 108.54 of 115
                                    + 7.78 extra credit (94 %)", the percentage of the points alone;
                                    Gradescope shows a step's extra-credit cases as one passed test
                                    of max_score 0 (a missed one is no failure) and its summary "115 +
                                    7.78 extra"; PrairieLearn gives them questions of their own, the
                                    assessment's bonus points (maxBonusPoints); the grades CSV has an
                                    extra_credit column; the class report's histogram and "at the
                                    maximum" count the points alone, the extra credit shown apart;
                                    ./kit course says how much of a bug extra credit can make up for.
  "hidden": {"enabled": true|false, "visibility": V, "reveal_after_due_date": true|false}
                                    hidden cases counted or left out; V is their Gradescope
                                    visibility (hidden, after_due_date, after_published, visible);
                                    whether failed hidden cases show their inputs after the due date.
  "due": {"date": "YYYY-MM-DDTHH:MM[:SS]", "timezone": "Area/City"}
                                    optional: the homework's due date, a local date and time
                                    (no offset), in the IANA timezone given (else the course's own
                                    on PrairieLearn). ./kit prairielearn writes it into the
                                    assessment's access rules (full credit until then; afterwards
                                    the assessment stays open to read, closed to submissions) and the
                                    timezone into the course instance it writes. Gradescope takes
                                    its dates from the assignment's settings instead. Without it,
                                    PrairieLearn's assessment is open for full credit for as long as
                                    the course instance is published.
  "rounding": {"decimals": D}       the total is rounded once, at the end, to D decimals (half up).
  "time_limits": {"case_seconds", "step_seconds", "submission_seconds",
                  "step_cpu_seconds", "step_wait_seconds"}
                                    the judge's backstop per case and per step (./kit check), and one
                                    submission of ./kit grade. (Each call of the student's code has
                                    its own 2 s limit in the judge; Gradescope's run: KIT_SECONDS in
                                    tools/gradescope/autograde.py.) The student's code has a budget per
                                    step, over all its cases: step_cpu_seconds of CPU (default 20) and
                                    step_wait_seconds spent waiting in calls, neither computing nor
                                    queued for a CPU (default 10); the ★ cases have a budget of their
                                    own, half as large. A step's budget is never below 50 times what
                                    the reference measured here needs (runcases.py, "Budgets"). The
                                    calls of one case may take 4/5 of case_seconds.

Points are exact fractions (fractions.Fraction) from the file to the total: no float noise. A
step's maximum is its points whatever state it is in, so every student has the same maximum; a
step that does not compile has all its cases failed and earns 0 of its points.
"""

from __future__ import annotations

import functools
import json
import re
from contextlib import contextmanager
from dataclasses import dataclass, field
from decimal import ROUND_HALF_UP, Decimal
from fractions import Fraction
from pathlib import Path
from typing import Iterator

from .common import ROOT, KitError
from .status import NOT_GRADED

COURSE_FILE = ROOT / "course.json"
GROUPS = ("core", "degenerate", "hidden", "robust")
VISIBILITIES = ("hidden", "after_due_date", "after_published", "visible")
LIMITS = {"case_seconds": 30, "step_seconds": 120, "submission_seconds": 600,
          "step_cpu_seconds": 20, "step_wait_seconds": 10}
DEGENERATE_NAMES = ["NaN", "infinite", "infinity", "zero direction", "radius of zero", "degenerate",
                    "empty window", "empty rectangle", "overflow", "underflow"]


@functools.lru_cache(maxsize=8)
def degenerate_pattern(words: tuple[str, ...]) -> re.Pattern:
    """One pattern for the degenerate names, each a whole word in any case: compiled once, not
    once per case and word (a check of the five steps asks it about 300 times)."""
    alternatives = "|".join(re.escape(w) for w in words) or r"(?!)"
    return re.compile(r"(?<!\w)(?:" + alternatives + r")(?!\w)", re.IGNORECASE)


@dataclass
class Course:
    points: dict[str, Fraction | None] = field(default_factory=dict)     # step number -> points (None: auto)
    weights: dict[str, Fraction] = field(default_factory=lambda: {"core": Fraction(1), "degenerate": Fraction(1),
                                                                  "hidden": Fraction(1), "robust": Fraction(0)})
    degenerate_names: list[str] = field(default_factory=lambda: list(DEGENERATE_NAMES))
    hidden_enabled: bool = True
    hidden_visibility: str = "after_due_date"
    reveal_after_due_date: bool = True
    decimals: int = 2
    extra: set[str] = field(default_factory=set)     # groups whose cases are extra credit
    limits: dict[str, float] = field(default_factory=lambda: dict(LIMITS))
    hidden_cases: dict[str, int] = field(default_factory=dict)    # a handout's record of them (./kit handout)
    case_weights: dict[str, dict[str, Fraction]] = field(default_factory=dict)   # step -> case name or "section N" -> weight
    due_date: str | None = None         # "YYYY-MM-DDTHH:MM:SS", local time (course.json "due")
    timezone: str | None = None         # the due date's IANA timezone, when given
    source: str = "the default scale"

    def group(self, tier: str, name: str) -> str:
        """The group of a case of `tier` named `name` (the rule in this module's docstring)."""
        if tier == "robust":
            return "robust"
        if tier == "hidden":
            return "hidden"
        return "degenerate" if degenerate_pattern(tuple(self.degenerate_names)).search(name) else "core"

    def weight(self, group: str) -> Fraction:
        if group == "hidden" and not self.hidden_enabled:
            return Fraction(0)
        return self.weights.get(group, Fraction(0))

    def weight_key(self, step: str, group: str, name: str, lecture: str = "") -> str | None:
        """Which key of steps.NN.weights gives this case its weight: its name, else its lecture's
        section ("section N"); None when its group's weight holds, as for every case of an optional
        group (it stays worth nothing)."""
        own = self.case_weights.get(step)
        if not own or self.weight(group) == 0:
            return None
        if name in own:
            return name
        section = re.match(r"\s*(\d+)[.)]", lecture or "")
        key = f"section {section.group(1)}" if section else None
        return key if key in own else None

    def case_weight(self, step: str, group: str, name: str, lecture: str = "") -> Fraction:
        """The weight of one case: its own (weight_key), else its group's."""
        key = self.weight_key(step, group, name, lecture)
        return self.case_weights[step][key] if key is not None else self.weight(group)

    def weights_of(self, step: str, cases: list[tuple[str, str, str]]) -> list[Fraction]:
        """The weight of each case of step `step`, given as (tier, name, lecture)."""
        return [self.case_weight(step, self.group(t, n), n, lec) for t, n, lec in cases]

    def unmatched_weights(self, step: str, cases: list[tuple[str, str, str]]) -> list[str]:
        """The keys of steps.NN.weights that give no counted case of the step its weight (a misspelt
        name, a section no case points to, or only optional cases)."""
        used = {self.weight_key(step, self.group(t, n), n, lec) for t, n, lec in cases}
        return [k for k in self.case_weights.get(step, {}) if k not in used]

    def optional(self, group: str) -> bool:
        """Worth nothing: run and shown like the ★ tier."""
        return self.weight(group) == 0

    def extra_credit(self, group: str) -> bool:
        """Worth points on top of the step's: passing adds them, failing takes nothing away."""
        return group in self.extra and not self.optional(group)

    def shares(self, step: str, groups: list[str], weights: list[Fraction] | None = None) -> list[Fraction]:
        """The exact points of each case of step `step`, given the cases' groups in order (and their own
        weights, weights_of, where the course gives some)."""
        weights = [self.weight(g) for g in groups] if weights is None else weights
        # The step's points are shared among the counted groups; an extra-credit case is worth its
        # weight's share of them, on top.
        total = sum((w for w, g in zip(weights, groups) if not self.extra_credit(g)), Fraction(0))
        points = self.points.get(step)
        if points is None:
            return weights
        if total == 0:
            return [Fraction(0)] * len(groups)
        return [points * w / total for w in weights]

    def step_maximum(self, step: str, groups: list[str], weights: list[Fraction] | None = None) -> Fraction:
        return sum((p for p, g in zip(self.shares(step, groups, weights), groups) if not self.extra_credit(g)),
                   Fraction(0))

    def rounded(self, value: Fraction) -> Decimal:
        """`value` rounded once, half up, to the course's decimals."""
        exact = Decimal(value.numerator) / Decimal(value.denominator)
        return exact.quantize(Decimal(1).scaleb(-self.decimals), rounding=ROUND_HALF_UP)

    def case_limits(self) -> tuple[float, float]:
        """The judge's backstops: seconds per case, per step."""
        return self.limits["case_seconds"], self.limits["step_seconds"]

    def scale_words(self) -> str:
        """The scale in a few words, for the text students read: the default's "every basic and hidden
        case one point", or this course's own points and weights, in decimals."""
        names = {"core": "core", "degenerate": "degenerate", "hidden": "hidden", "robust": "★"}
        weights = {g: self.weight(g) for g in names}
        if all(p is None for p in self.points.values()) and [weights[g] for g in names] == [1, 1, 1, 0] \
                and not self.extra:
            return "every basic and hidden case one point; ★ cases are optional and count for nothing"
        steps = ", ".join(f"step {n} {self.shown(p)}" for n, p in sorted(self.points.items()) if p is not None)
        shared = ", ".join(f"{names[g]} {self.shown(w)}" for g, w in weights.items())
        free = [names[g] for g, w in weights.items() if w == 0]
        extra = [names[g] for g in names if self.extra_credit(g)]
        return ((f"points per step: {steps}; " if steps else "") + f"a step's points shared among its cases by "
                f"weight ({shared})" + (f"; {' and '.join(extra)} cases are extra credit, on top of a step's "
                                        "points" if extra else "")
                + (f"; {' and '.join(free)} cases count for nothing" if free else ""))

    def step_budget(self) -> tuple[float, float]:
        """The student's code's budget on one step: seconds of CPU, seconds waited."""
        return self.limits["step_cpu_seconds"], self.limits["step_wait_seconds"]

    def shown(self, value: Fraction) -> str:
        """`value` for people: whole numbers as they are, others rounded once."""
        return exact_text(value) if value.denominator == 1 else str(self.rounded(value))

    def number(self, value: Fraction) -> int | float:
        """`value` for JSON: an int when whole, else the rounded decimal as a float."""
        return value.numerator if value.denominator == 1 else float(self.rounded(value))


def exact_text(value: Fraction) -> str:
    return str(value.numerator) if value.denominator == 1 else f"{value.numerator}/{value.denominator}"


def _fraction(value, where: str, allow_none: bool = False) -> Fraction | None:
    if value is None and allow_none:
        return None
    try:
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise ValueError(value)
        f = Fraction(str(value).strip())
    except (ValueError, ZeroDivisionError):
        raise KitError(f"{where}: {json.dumps(value)} is not a number (write 3, \"2.5\" or \"41/3\")")
    if f < 0:
        raise KitError(f"{where}: {value} is negative; points and weights are 0 or more")
    return f


def _object(value, where: str, keys=None) -> dict:
    """`value` when it is a JSON object (with no key but `keys`, when given); KitError otherwise."""
    if not isinstance(value, dict):
        raise KitError(f"{where}: expected a JSON object {{...}}, found {type(value).__name__}")
    unknown = sorted(set(value) - set(keys)) if keys is not None else []
    if unknown:
        raise KitError(f"{where}: unknown key {unknown[0]!r} (known: {', '.join(sorted(keys))})")
    return value


def _flag(entry: dict, key: str, where: str) -> None:
    if key in entry and not isinstance(entry[key], bool):
        raise KitError(f"{where}.{key}: expected true or false, found {json.dumps(entry[key])}")


def _due(entry: dict, where: str) -> tuple[str | None, str | None]:
    """course.json's "due": the date as PrairieLearn writes one ("YYYY-MM-DDTHH:MM:SS", seconds
    added when left out) and the timezone, each None when not given; KitError on a date that is not
    one or a timezone unknown to this machine's database."""
    from datetime import datetime
    _object(entry, where, {"date", "timezone"})
    date, zone = entry.get("date"), entry.get("timezone")
    if date is not None:
        if not isinstance(date, str) or not re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d(:\d\d)?", date.strip()):
            raise KitError(f"{where}.date: {json.dumps(date)} is not a local date and time like "
                           "\"2027-03-14T23:59:00\" (no offset: the timezone goes in \"timezone\")")
        try:
            date = datetime.fromisoformat(date.strip()).strftime("%Y-%m-%dT%H:%M:%S")
        except ValueError as e:
            raise KitError(f"{where}.date: {json.dumps(entry['date'])}: {e}")
    if zone is not None:
        if not isinstance(zone, str) or not re.fullmatch(r"[A-Za-z_]+(/[A-Za-z0-9_+-]+)*", zone):
            raise KitError(f"{where}.timezone: {json.dumps(zone)} is not a timezone name like \"America/Chicago\"")
        try:
            from zoneinfo import ZoneInfo, available_timezones
            if available_timezones():           # this machine has a timezone database to ask
                ZoneInfo(zone)
        except ImportError:
            pass
        except (KeyError, ValueError, OSError):
            raise KitError(f"{where}.timezone: {json.dumps(zone)} is not in the timezone database "
                           "(names like \"America/Chicago\", \"Europe/Paris\")")
        if date is None:
            raise KitError(f"{where}.timezone: given without a date")
    return date, zone


def parse(data, steps: list[str], where: str = "course.json") -> Course:
    """A Course from the decoded JSON `data`, for the steps numbered `steps`; KitError on bad input."""
    course = Course(source=where)
    data = _object(data, where, {"about", "steps", "groups", "hidden", "due", "rounding", "time_limits",
                                 "hidden_cases"})
    counts = _object(data.get("hidden_cases", {}), f"{where} hidden_cases")
    for number, n in counts.items():
        if number not in steps or isinstance(n, bool) or not isinstance(n, int) or n < 0:
            raise KitError(f"{where} hidden_cases: {number!r}: {json.dumps(n)} is not a step and a count")
        course.hidden_cases[number] = n
    for number, entry in _object(data.get("steps", {}), f"{where} steps").items():
        if number not in steps:
            raise KitError(f"{where} steps: no step {number!r} in this kit (steps: {', '.join(steps)})")
        entry = _object(entry, f"{where} steps.{number}", {"points", "weights"})
        course.points[number] = _fraction(entry.get("points"), f"{where} steps.{number}.points", allow_none=True)
        own = _object(entry.get("weights", {}), f"{where} steps.{number}.weights")
        for key, value in own.items():
            if not key.strip() or (key.lower().startswith("section") and not re.fullmatch(r"section \d+", key)):
                raise KitError(f"{where} steps.{number}.weights: {json.dumps(key)} is neither a case's name nor "
                               "\"section N\" (a lecture section's number)")
            course.case_weights.setdefault(number, {})[key] = _fraction(value, f"{where} steps.{number}.weights.{key}")
    for name, entry in _object(data.get("groups", {}), f"{where} groups").items():
        if name not in GROUPS:
            raise KitError(f"{where} groups: unknown group {name!r} (groups: {', '.join(GROUPS)})")
        entry = _object(entry, f"{where} groups.{name}",
                        {"weight", "names", "extra_credit"} if name == "degenerate" else {"weight", "extra_credit"})
        _flag(entry, "extra_credit", f"{where} groups.{name}")
        if entry.get("extra_credit"):
            course.extra.add(name)
        if "weight" in entry:
            course.weights[name] = _fraction(entry["weight"], f"{where} groups.{name}.weight")
        if "names" in entry:
            names = entry["names"]
            if not isinstance(names, list) or not all(isinstance(n, str) and n.strip() for n in names):
                raise KitError(f"{where} groups.degenerate.names: expected a list of words, e.g. [\"NaN\"]")
            course.degenerate_names = [n.strip() for n in names]
    hidden = _object(data.get("hidden", {}), f"{where} hidden", {"enabled", "visibility", "reveal_after_due_date"})
    for key in ("enabled", "reveal_after_due_date"):
        _flag(hidden, key, f"{where} hidden")
    course.hidden_enabled = hidden.get("enabled", True)
    course.reveal_after_due_date = hidden.get("reveal_after_due_date", True)
    course.hidden_visibility = hidden.get("visibility", "after_due_date")
    if course.hidden_visibility not in VISIBILITIES:
        raise KitError(f"{where} hidden.visibility: {json.dumps(course.hidden_visibility)} is not one of "
                       f"Gradescope's: {', '.join(VISIBILITIES)}")
    course.due_date, course.timezone = _due(_object(data.get("due", {}), f"{where} due"), f"{where} due")
    rounding = _object(data.get("rounding", {}), f"{where} rounding", {"decimals"})
    decimals = rounding.get("decimals", 2)
    if isinstance(decimals, bool) or not isinstance(decimals, int) or not 0 <= decimals <= 6:
        raise KitError(f"{where} rounding.decimals: expected a whole number from 0 to 6, found {json.dumps(decimals)}")
    course.decimals = decimals
    limits = _object(data.get("time_limits", {}), f"{where} time_limits", set(LIMITS))
    for key, value in limits.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value <= 24 * 3600:
            raise KitError(f"{where} time_limits.{key}: expected seconds above 0, found {json.dumps(value)}")
        course.limits[key] = float(value)
    return course


def read(path: Path, steps: list[str]) -> Course:
    try:
        text = path.read_text()
    except FileNotFoundError:
        return Course(source="the default scale (no course.json)")
    except OSError as e:
        raise KitError(f"{path}: cannot read it ({e.strerror})")
    try:
        data = json.loads(text)
    except json.JSONDecodeError as e:
        raise KitError(f"{path.name}: not valid JSON at line {e.lineno}, column {e.colno}: {e.msg}")
    return parse(data, steps, path.name)


_LOADED: Course | None = None


def load() -> Course:
    """The kit's course.json (cached); the default scale when there is none (a student's handout)."""
    global _LOADED
    if _LOADED is None:
        from .common import load_steps
        _LOADED = read(COURSE_FILE, [s.number for s in load_steps()])
    return _LOADED


HIDDEN_SOURCES = ROOT / "tests" / "hidden"


def hidden_counts(course: Course | None = None) -> dict[str, int]:
    """How many hidden cases each step has: counted in tests/hidden/ (the instructor's kit), else
    as the handout recorded them in its course.json (a handout has no hidden cases)."""
    if HIDDEN_SOURCES.is_dir():
        from .common import load_steps
        return {s.number: len(re.findall(r"^TEST_CASE\(", p.read_text(), re.M))
                for s in load_steps() for p in [HIDDEN_SOURCES / f"{s.folder}.cpp"] if p.is_file()}
    return dict((course or load()).hidden_cases)


def handout_text() -> str:
    """course.json as a handout ships it: with the count of hidden cases it leaves out, so the
    student's scoreboard can say what the course grade adds."""
    data = json.loads(COURSE_FILE.read_text()) if COURSE_FILE.is_file() else {}
    data["hidden_cases"] = hidden_counts()
    return json.dumps(data, indent=2, ensure_ascii=False) + "\n"


def split_extra(results) -> tuple[Fraction, Fraction]:
    """What `results` earned on the course's points and, apart, on top of them as extra credit (a step
    not graded earns neither)."""
    course = load()
    extra = sum((c.points for r in results if r.state != NOT_GRADED for c in r.cases
                 if c.status == "pass" and course.extra_credit(c.group)), Fraction(0))
    return sum((r.earned for r in results), Fraction(0)) - extra, extra


def extra_maximum(results) -> Fraction:
    """The extra credit `results`' cases could add on top of the course's points, all passed."""
    course = load()
    return sum((c.points for r in results for c in r.cases if course.extra_credit(c.group)), Fraction(0))


def score_words(results) -> str:
    """"score 108.54 of 115 + 7.78 extra credit (94 %)": the points earned of the course's points, the
    extra credit apart (issue 46: '116.32 of 115' read wrong), the percentage of the points alone."""
    course = load()
    base, extra = split_extra(results)
    maximum = sum((r.maximum for r in results), Fraction(0))
    share = float(100 * base / maximum) if maximum else 0.0
    # Whole percents, but never "100 %" for points short of the maximum (246 of 247 reads 99.6 %).
    pct = (f" ({share:.0f} %)" if round(share) < 100 or base >= maximum else f" ({int(share * 10) / 10:.1f} %)") if maximum else ""
    more = f" + {course.shown(extra)} extra credit" if extra else ""
    return f"score {course.shown(base)} of {course.shown(maximum)}{more}{pct}"


def hidden_note(course: Course | None = None) -> str:
    """What a failed hidden case says instead of its inputs, as the course says it (issue 55: with the
    reveal off, every such case still read "its inputs are shown after the due date")."""
    course = course or load()
    when = ("its inputs are shown after the due date" if course.reveal_after_due_date
            else "its inputs are not shown, before or after the due date")
    return "a hidden case: random inputs of this family, drawn afresh for each submission; " + when


def score_line(results) -> str:
    """The scoreboard's total. The instructor's kit: the score on the course's scale. A handout,
    which has no hidden cases: what it can check, and what the course grade adds."""
    course = load()
    has_hidden = any(c.tier == "hidden" for r in results for c in r.cases)
    missed = [r.step.number for r in results if r.state == NOT_GRADED]
    if missed:      # no verdict for these: a total would read as the student's, so none is given
        graded = [r for r in results if r.state != NOT_GRADED]
        return (f"  not graded: step {', '.join(missed)} (the grader's fault, not yours)" + (
                f"; the other steps: {course.shown(sum((r.earned for r in graded), Fraction(0)))} of "
                f"{course.shown(sum((r.maximum for r in graded), Fraction(0)))}" if graded else ""))
    if has_hidden or HIDDEN_SOURCES.is_dir():
        return "  " + score_words(results)
    visible = [c for r in results for c in r.cases if c.tier == "basic" and not course.optional(c.group)]
    passed = sum(c.status == "pass" for c in visible)
    hidden = sum(n for k, n in hidden_counts(course).items() if k in {r.step.number for r in results})
    more = (f"{hidden} hidden cases" if course.hidden_enabled and hidden else "")
    return (f"  visible {passed} of {len(visible)}; the course grade also counts " + (more + " and " if more else "")
            + "weights the steps as your instructor set")


def table(course: Course, cases_by_step: list[tuple[str, str, list[tuple[str, str]]]]) -> list[str]:
    """The lines of ./kit course: per step (number, title, [(tier, name)]), the cases per group and
    their points, and the total to enter in Gradescope."""
    lines = [f"Course scale from {course.source}", ""]
    total = Fraction(0)
    own_lines, rows = [], []
    for number, title, cases in cases_by_step:
        cases = [(c[0], c[1], c[2] if len(c) > 2 else "") for c in cases]
        groups = [course.group(t, n) for t, n, _ in cases]
        weights = course.weights_of(number, cases)
        shares = course.shares(number, groups, weights)
        cells = []
        for g in GROUPS:
            mine = [p for p, gg in zip(shares, groups) if gg == g]
            if not mine:
                cell = "-"
            elif course.optional(g):
                cell = f"{len(mine)} × 0 ★"
            else:       # a case with a weight of its own makes a group's cases differ: each value counted
                sign = "+" if course.extra_credit(g) else ""
                cell = ", ".join(f"{mine.count(v)} × {sign}{exact_text(v)}" for v in sorted(set(mine), key=mine.index))
            cells.append(cell)
        keys = [course.weight_key(number, g, n, lec) for (t, n, lec), g in zip(cases, groups)]
        for key, w in course.case_weights.get(number, {}).items():
            hit = [p for k, p in zip(keys, shares) if k == key]
            own_lines.append(f"  step {number}: weight {exact_text(w)} for " +
                             (f"lecture {key}" if key.startswith("section ") else repr(key)) +
                             (f": {len(hit)} case{'s' if len(hit) != 1 else ''}, {course.shown(hit[0])} points each"
                              if hit else ": NO COUNTED CASE (a misspelt name, or a section no case points to)"))
        step_max = course.step_maximum(number, groups, weights)
        total += step_max
        rows.append((f"{(number + ' ' + title)[:36]:<36}", cells, course.shown(step_max)))
    # Each group's column as wide as its widest cell: a case of its own weight makes a cell longer.
    widths = [max([15] + [len(cells[i]) + 2 for _, cells, _ in rows]) for i in range(len(GROUPS))]
    head = f"  {'step':<36}" + "".join(f"{g:>{w}}" for g, w in zip(GROUPS, widths)) + f"{'points':>9}"
    lines += [head, "  " + "-" * (len(head) - 2)]
    lines += [f"  {name}" + "".join(f"{c:>{w}}" for c, w in zip(cells, widths)) + f"{pts:>9}" for name, cells, pts in rows]
    lines += ["", "  (cases × the points of one; ★: optional, run and shown, worth nothing; +: extra credit, "
              "on top of the step's points)", ""]
    weights = ", ".join(f"{g} {exact_text(course.weight(g))}" + (" (optional, like ★)" if course.optional(g) else
                                                                 " (extra credit)" if course.extra_credit(g) else "")
                        for g in GROUPS)
    lines.append(f"  group weights: {weights}")
    lines += own_lines or ["  cases with a weight of their own: none (a step's \"weights\" in course.json: "
                           "{\"CASE NAME\": W} or {\"section N\": W})"]
    auto = [n for n, _, _ in cases_by_step if course.points.get(n) is None]
    if auto:
        lines.append(f"  steps {', '.join(auto)}: one point per unit of weight (points: null), so their points "
                     "change when a case is added; give them points to fix the total")
    lines.append(f"  hidden cases: {'counted' if course.hidden_enabled else 'left out'}, Gradescope visibility "
                 f"{course.hidden_visibility}, inputs revealed after the due date: "
                 f"{'yes' if course.reveal_after_due_date else 'no'}")
    lines.append("  due date: " + (f"{course.due_date}" + (f" ({course.timezone})" if course.timezone else
                                                             " (the PrairieLearn course's timezone)")
                                     if course.due_date else "none")
                 + " (PrairieLearn's access rules, ./kit prairielearn; Gradescope uses its assignment's own)")
    lines.append("  time limits: " + ", ".join(f"{k} {v:g}" for k, v in course.limits.items()))
    lines.append(f"  points are exact fractions; a student's total is rounded once, at the end, to "
                 f"{course.decimals} decimals (half up)")
    lines += extra_credit_lines(course, cases_by_step, total) + [""]
    lines.append(f"  Total to enter in Gradescope (the assignment's points): {exact_text(total)}"
                 + (f" = {course.rounded(total)}" if total.denominator != 1 else ""))
    return lines


def bug_and_bonus(course: Course, cases_by_step) -> tuple | None:
    """How much extra credit can make up for a bug, on this course's cases: (all the extra credit, the
    counted cases' points as (step, name, points), the example: the costliest core case (else counted
    case) that all the extra credit makes up for, else the cheapest one); None without extra credit."""
    bonus, counted = Fraction(0), []
    for number, _title, cases in cases_by_step:
        cases = [(c[0], c[1], c[2] if len(c) > 2 else "") for c in cases]
        groups = [course.group(t, n) for t, n, _ in cases]
        for (t, n, _), g, p in zip(cases, groups, course.shares(number, groups, course.weights_of(number, cases))):
            if course.extra_credit(g):
                bonus += p
            elif p > 0:
                counted.append((number, n, p, g))
    if not bonus or not counted:
        return None
    pool = [c for c in counted if c[3] == "core"] or counted      # a bug in the core, where there is one
    covered = [c for c in pool if c[2] <= bonus]
    example = max(covered, key=lambda c: c[2]) if covered else min(pool, key=lambda c: c[2])
    return bonus, [c[:3] for c in counted], example[:3]


def extra_credit_lines(course: Course, cases_by_step, total: Fraction) -> list[str]:
    """./kit course's example of what extra credit can do (#46: a student with a bug and the ★ points,
    121.91, outscored a correct solution without them, 118.90, and nothing said it could happen)."""
    found = bug_and_bonus(course, cases_by_step)
    if found is None:
        return []
    bonus, counted, (number, name, points) = found
    covered = sum(p <= bonus for _, _, p in counted)
    bugged = total - points + bonus
    return ["", f"  extra credit against a bug: the extra-credit cases add up to +{course.shown(bonus)}, so they make up for",
            f"  any one missed case worth up to that ({covered} of the {len(counted)} counted cases). For example:",
            f"    {course.shown(bugged):>9}  a bug that fails step {number}'s case {name[:60]!r} "
            f"(-{course.shown(points)}), every extra-credit case passed",
            f"    {course.shown(total):>9}  a correct solution that passes no extra-credit case"
            + (", less" if total < bugged else ", the same" if total == bugged else ", more")]


@contextmanager
def using(course: Course) -> Iterator[Course]:
    """`with using(course):` makes `course` the one load() gives (a self-test's scale), then puts
    the previous one back."""
    global _LOADED
    saved, _LOADED = _LOADED, course
    try:
        yield course
    finally:
        _LOADED = saved

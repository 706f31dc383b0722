"""The case and result model of a check: a case of a step's judge (Case) and a step's result
(StepResult), with its points on the course's one scale and the failing case shown first, and what
they need (the scored tiers, a case's lecture section, the stand-in's refusal, a step's picture
sections). Running the cases is runcases.py's; building and judging a step, checking.py's.
"""

from __future__ import annotations

import functools
import json
import re
from collections import Counter
from dataclasses import dataclass, field
from fractions import Fraction

from . import course as course_file
from .common import ROOT, Step
from .status import CRASHED, NOT_GRADED, NOT_RUN, NOT_STARTED, PASS, THREW, TIMED_OUT, WAITING

TIERS = ("basic", "hidden", "robust")
SCORED_TIERS = ("basic", "hidden")   # one point a case; ★ robust cases are optional, 0 points


def lecture_section(pointer: str) -> float:
    """A case's lecture pointer, "4. What the discriminant says", as its section's number (4); a pointer
    without one ("", "A. What the robust form costs") sorts after every numbered section."""
    head = (pointer or "").split(".", 1)[0].strip()
    return int(head) if head.isdigit() else float("inf")


# The stand-in's refusal (tests/support/standin_04.cpp): "while grading step 05 the grader answers
# intersect_rect only for ...". The student's code threw nothing itself; it asked a question the
# script for the case does not hold, which an earlier function of theirs (a view ray) explains.
_STANDIN_REFUSAL = re.compile(r"while grading step \d+ the grader answers \w+ only for")


def standin_refused(case: "Case") -> bool:
    """Whether the case failed because the stand-in for a needed step refused a call."""
    return case.status == THREW and any(_STANDIN_REFUSAL.search(m) for m in case.messages)


@functools.lru_cache(maxsize=None)
def _picture_sections(folder: str) -> frozenset[str]:
    try:
        found = json.loads((ROOT / "tests" / folder / "step.json").read_text()).get("picture_sections", [])
    except (OSError, ValueError, AttributeError):
        return frozenset()
    return frozenset(s for s in found if isinstance(s, str)) if isinstance(found, list) else frozenset()


def picture_sections(step: Step) -> frozenset[str]:
    """The lecture sections of `step` whose cases draw a whole picture with every function of the step
    (step.json "picture_sections"): a failure there says the picture is wrong, not why."""
    return _picture_sections(step.folder)


@dataclass
class Case:
    name: str
    tier: str                   # "basic", "hidden" or "robust"
    lecture: str                # lecture section, e.g. "4. What the discriminant says"
    status: str = NOT_RUN     # pass fail not_started threw crashed timed_out not_run no_compile missing waiting
    messages: list[str] = field(default_factory=list)
    output: str = ""            # what the student's code printed during the case (trimmed)
    output_bytes: int = 0
    figure: dict | None = None  # the geometry of the first failing check (tests/support/case_figure.hpp)
    picture: str = ""           # its SVG (picture/), when drawn
    picture_summary: str = ""   # one line: what the picture shows, or why there is none
    runs: int = 1               # how many times the grader ran it (rerun_timeouts runs a timed-out case again)
    rerun: dict | None = None   # when runs > 1: {"why", "first": {"status", "messages"}, "kept": the run shown}
    incident: dict | None = None  # a crash, time-out or throw: {"function": the call's, "signal": "SIGSEGV" or ""}

    share: Fraction | None = None   # its exact points on the course's scale (set by StepResult)

    @property
    def group(self) -> str:
        """core, degenerate, hidden or robust (the rule: raykit/course.py)."""
        return course_file.load().group(self.tier, self.name)

    @property
    def points(self) -> Fraction:
        """What passing this case is worth, exactly (course.json; the default: 1, and 0 for the ★ tier)."""
        return self.share if self.share is not None else course_file.load().weight(self.group)


@dataclass
class StepResult:
    step: Step
    state: str                  # done, partial, not_started, missing, no_compile, waiting, broken
    cases: list[Case] = field(default_factory=list)
    detail: str = ""            # compiler errors, the missing file, the step we wait for
    isolation: str = ""
    seed: str = ""
    cost: dict | None = None    # what the student's code cost the grader, and the budget (runcases.py, "Budgets")
    includes: list[str] = field(default_factory=list)   # standard headers the files use and do not include
    slip: dict | None = None    # the known slip the failing basic cases are exactly (slips.py): its case first
    reason: str = ""            # NOT_GRADED: why, in one line (the grader's fault: no points lost, none earned)

    def __post_init__(self) -> None:
        if self.state == NOT_GRADED and not self.reason:
            self.reason = next((l.strip() for l in self.detail.splitlines() if l.strip()), "the kit failed")
        # The step's points shared among its cases by their groups' weights, once, exactly.
        course = course_file.load()
        weights = course.weights_of(self.step.number, [(c.tier, c.name, c.lecture) for c in self.cases])
        for c, share in zip(self.cases, course.shares(self.step.number, [c.group for c in self.cases], weights)):
            c.share = share

    def tier(self, tier: str) -> list[Case]:
        return [c for c in self.cases if c.tier == tier]

    def passed(self, tier: str) -> int:
        return sum(c.status == PASS for c in self.tier(tier))

    @property
    def earned(self) -> Fraction:
        """Exact; a step that does not compile has every case failed, so it earns 0; one not graded has
        no verdict, so it earns nothing yet (and loses nothing: see faults.py)."""
        if self.state == NOT_GRADED:
            return Fraction(0)
        return sum((c.points for c in self.cases if c.status == PASS), Fraction(0))

    @property
    def maximum(self) -> Fraction:
        """Exact, and the same whatever state the step is in: the step's points in course.json
        (extra-credit cases come on top of it: earned may pass it)."""
        if not self.cases:
            return course_file.load().points.get(self.step.number) or Fraction(0)
        course = course_file.load()
        return sum((c.points for c in self.cases if not course.extra_credit(c.group)), Fraction(0))

    def first_problem(self, tier: str = "basic") -> Case | None:
        """The failing case of `tier` a student is shown first under "Next:" (./kit hint and ./kit debug
        start from it too).

        First, when the failing basic cases are exactly a known slip's (slips.py), the case its patch
        names (of slips that fail alike, one they all name, else one of those they name). Then, in this
        order, the failing cases
          0. that report their own function's answer (a wrong answer, a crash, a throw of the student's);
          1. whose cause lies elsewhere: a whole picture drawn with every function of the step (the
             sections step.json lists as "picture_sections"), and a call the stand-in for a needed
             step refused (the student's code asked it a question its script does not hold, so an
             earlier function, a view ray say, is wrong: standin.hpp);
          2. of a function not written yet;
          3. waiting for another step.
        Of the first of these groups that has a case: the lecture section whose cases fail in the
        largest share, the earliest section on a tie, its first failing case in the suite's order. A
        slip in what one section teaches fails nearly all of that section's cases and only some of the
        others' (a radius not squared: both of "2. Any radius", 10 of 12 of section 4), so that
        section's case is the one that names it. A picture at 100 % would always win that rule, with
        words about the picture, not the cause: it comes first only when no direct case fails."""
        cases = self.tier(tier)
        failing = [c for c in cases if c.status != PASS]
        if not failing:
            return None
        if tier == "basic" and self.slip:       # the failing set of a known slip first: a case its patch names
            named = next((c for c in failing if c.name == self.slip.get("case")), None)
            if named is not None:
                return named
            # Several slips fail alike and name no case in common: one of the cases they name.
            among = [c for c in failing if c.name in (self.slip.get("cases") or ())]
            if among:
                failing = among
        pictures = picture_sections(self.step)

        def rank(c: Case) -> int:
            if c.status == WAITING:
                return 3
            if c.status == NOT_STARTED:
                return 2
            return 1 if c.lecture in pictures or standin_refused(c) else 0
        best = min(rank(c) for c in failing)
        failing = [c for c in failing if rank(c) == best]
        total, bad = Counter(c.lecture for c in cases), Counter(c.lecture for c in failing)
        section = min(bad, key=lambda s: (-Fraction(bad[s], total[s]), lecture_section(s)))
        return next(c for c in failing if c.lecture == section)

    def incidents(self) -> list[Case]:
        return [c for c in self.cases if c.status in (CRASHED, TIMED_OUT, THREW)]

    def to_json(self) -> dict:
        return {
            "step": self.step.number, "folder": self.step.folder, "title": self.step.title,
            "state": self.state, "detail": self.detail, "isolation": self.isolation, "seed": self.seed,
            **({"cost": self.cost} if self.cost else {}),
            **({"includes": self.includes} if self.includes else {}),
            **({"slip": self.slip} if self.slip else {}),
            **({"not_graded": self.reason} if self.state == NOT_GRADED else {}),
            "earned": course_file.load().number(self.earned), "maximum": course_file.load().number(self.maximum),
            "earned_exact": course_file.exact_text(self.earned), "maximum_exact": course_file.exact_text(self.maximum),
            **{t: {"passed": self.passed(t), "total": len(self.tier(t))} for t in TIERS},
            "cases": [{"name": c.name, "tier": c.tier, "group": c.group, "points": course_file.exact_text(c.points),
                       "lecture": c.lecture, "status": c.status,
                       "messages": c.messages, "output": c.output, "output_bytes": c.output_bytes,
                       "picture": c.picture or None, "picture_summary": c.picture_summary or None,
                       "figure": c.figure or None,  # the geometry, so ./kit report can draw the case
                       "runs": c.runs, **({"rerun": c.rerun} if c.rerun else {}),
                       **({"incident": c.incident} if c.incident else {})}
                      for c in self.cases],
        }

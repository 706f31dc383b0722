"""Checking one build: compile the judge and the student's answers program, run the cases.

The judge (a step's test program) never loads the student's code: it calls each
step function in a child process, the answers program, which it starts itself
(in a sandbox when the folder graded is not the student's own; see sandbox/),
and judges the answers it gets back. Nothing the student's code prints or writes
reaches the verdicts. This module runs the judge, with a time limit per case as a
backstop, and reads its verdicts.

One scale: every case of every step counts, whatever state the step is in. A step
whose code is missing or does not compile has all its cases failed; a step that
needs another is graded, where solutions/ is present, on a stand-in for that other
step scripted from the reference's program (tests/support/standin.hpp), so one slip
costs one step and no reference code is in the student's process.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Callable

from . import atomic, slips
from . import course as course_file
from . import faults
from . import includes
from . import waits
from . import warmup
from .common import BUILD, ROOT, InOrder, Step, map_in_threads, prerequisites, printable
from .build import Build, build_target, build_targets, ensure_configured, ninja_of, shown_text
from .objcache import ObjectCache
from .sandbox import NONE_OWN, SANDBOX_FAILED, Isolation, Scratch
from .secret import hidden_seed
from .status import GRADER_ERROR, NOT_GRADED, CRASHED, DONE, MISSING, NOT_RUN, NOT_STARTED, NO_COMPILE, PARTIAL, PASS, THREW, TIMED_OUT, WAITING

CASE_SECONDS = 30.0         # backstop: the judge limits each call; a case may make many
STEP_SECONDS = 120.0        # backstop: all cases of one step, including restarts
OUTPUT_LIMIT = 1 << 20      # bytes the judge itself may print (it prints nothing)
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
        """core, degenerate, hidden or robust (the rule: kitlib/course.py)."""
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
    cost: dict | None = None    # what the student's code cost the grader, and the budget (see "Budgets")
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
        total: dict[str, int] = {}
        for c in cases:
            total[c.lecture] = total.get(c.lecture, 0) + 1
        bad: dict[str, int] = {}
        for c in failing:
            bad[c.lecture] = bad.get(c.lecture, 0) + 1
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


def _read_lines(path: Path) -> list[dict]:
    events = []
    try:
        text = path.read_text(errors="replace")
    except FileNotFoundError:
        return events
    for line in text.splitlines():
        try:
            events.append(json.loads(line))
        except json.JSONDecodeError:
            pass            # a half-written last line from a killed process
    return events


def _kill(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    proc.wait()


def list_cases(exe: Path) -> list[Case]:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "list.jsonl"
        r = subprocess.run([str(exe), "--reporters=raykit", "--list-test-cases", f"--out={out}"],
                           capture_output=True, timeout=20)
        if r.returncode != 0:
            raise RuntimeError(f"{exe.name} --list-test-cases failed")
        return [Case(e["case"], e.get("suite") or "basic", e.get("lecture") or "") for e in _read_lines(out)]


# --- Budgets: what the student's code may cost the grader ------------------------------------
# Each call of the student's code has its own limit in the judge (2 s of CPU, a wall-clock backstop
# of 8 s), but a case makes many calls (a hidden family 24) and a step some fifty cases: code that
# sleeps just under the limit in every call, or computes correctly but slowly, cost minutes of the
# grader's time per step and was stopped by the backstops above, which blamed the kit. So each step
# has a budget for the student's code, over all its cases and every run of its judge (a restart, a
# case run again): course.json's step_cpu_seconds of CPU and step_wait_seconds of waiting (time in
# a call neither computing nor queued for a CPU: sleeping, blocked; a busy machine adds none), never
# below REFERENCE_MULTIPLE times what the reference needed when the solutions were last graded on
# this machine (REFERENCE_TIMES, written then; its calls take micro- to milliseconds, so the
# course's figures decide unless the reference becomes slow). The ★ cases, optional and run first,
# have a budget of their own, half as large, so they never spend the scored cases' share. The calls
# of one case may take CASE_SHARE of case_seconds in all, so a case the backstop stops is the
# judge's own fault, not its calls'. The judge (tests/support/remote.cpp) enforces all of it and
# keeps the totals in a ledger file; once a budget is spent, the remaining cases fail without
# calling the code, with a message that gives the figures. A submission's whole cost is bounded by
# the sum over its steps.
REFERENCE_MULTIPLE = 50
CASE_SHARE = 0.8
REFERENCE_TIMES = BUILD / "reference-times.json"


@dataclass
class Budget:
    cpu: float                      # seconds of CPU for the step's calls of the student's code
    wait: float                     # seconds those calls may spend waiting
    case: float                     # wall seconds the calls of one case may take
    ledger: Path                    # the judge's record of what was spent (see remote.cpp)
    reference: dict | None = None   # what the reference needed here: {"cpu", "wait", "calls"}

    def note(self) -> str:
        r = self.reference
        if not r:
            return "the reference's own time is not measured on this machine yet"
        return (f"the reference needs {r['cpu']:.2f} s of CPU and waits {r['wait']:.2f} s for its "
                f"{r['calls']} calls on this machine")

    def env(self) -> dict[str, str]:
        return {"RAYKIT_BUDGET": f"{self.cpu:g} {self.wait:g} {self.case:g}", "RAYKIT_LEDGER": str(self.ledger),
                "RAYKIT_BUDGET_NOTE": self.note()}

    def spent(self) -> dict:
        """The ledger, both accounts (the scored cases' and the ★ cases') added: {"cpu", "wait",
        "calls", "case", "since"}, zeros before the first call."""
        try:
            f = self.ledger.read_text().split()
            cpu, wait, calls = float(f[0]) + float(f[3]), float(f[1]) + float(f[4]), int(f[2]) + int(f[5])
            case, since = float(f[6]), float(f[7])
            looped = len(f) > 8 and f[8] == "1"
        except (OSError, ValueError, IndexError):
            cpu, wait, calls, case, since, looped = 0.0, 0.0, 0, 0.0, 0.0, False
        return {"cpu": cpu, "wait": wait, "calls": calls, "case": case, "since": since, "looped": looped}

    def case_seconds_now(self) -> float:
        """Wall seconds the student's calls have taken in the current case, the one in flight included."""
        s = self.spent()
        return s["case"] + (max(0.0, time.monotonic() - s["since"]) if s["since"] > 0 else 0.0)


def reference_times() -> dict:
    try:
        data = json.loads(REFERENCE_TIMES.read_text())
        return data if isinstance(data, dict) else {}
    except (OSError, ValueError):
        return {}


def step_budget(step: Step, ledger: Path) -> Budget:
    course = course_file.load()
    cpu, wait = course.step_budget()
    case_seconds, _ = course.case_limits()
    ref = reference_times().get(step.number)
    if isinstance(ref, dict) and {"cpu", "wait", "calls"} <= set(ref):
        cpu = max(cpu, REFERENCE_MULTIPLE * float(ref["cpu"]))
        wait = max(wait, REFERENCE_MULTIPLE * float(ref["wait"]))
    else:
        ref = None
    return Budget(cpu, wait, CASE_SHARE * case_seconds, ledger, ref)


def record_reference_time(build: Build, step: Step, budget: Budget, cases: list[Case]) -> None:
    """When the files graded are the reference's own and every case passed, what its calls took is
    kept as the reference's figure on this machine (REFERENCE_TIMES)."""
    try:
        same = all((build.steps_dir / step.folder / f).read_bytes() == (ROOT / "solutions" / step.folder / f).read_bytes()
                   for f in step.files)
    except OSError:
        return
    if not same or not cases or any(c.status != PASS for c in cases):
        return
    spent = budget.spent()
    data = reference_times()
    data[step.number] = {"cpu": round(spent["cpu"], 3), "wait": round(spent["wait"], 3), "calls": spent["calls"]}
    try:
        REFERENCE_TIMES.parent.mkdir(parents=True, exist_ok=True)
        atomic.write(REFERENCE_TIMES, json.dumps(data, indent=1, sort_keys=True) + "\n")
    except OSError:
        pass


def run_cases(exe: Path, cases: list[Case], env: dict[str, str] | None = None,
              case_seconds: float = CASE_SECONDS, step_seconds: float = STEP_SECONDS,
              budget: Budget | None = None) -> None:
    """Runs the judge `exe` over every case, filling in each Case's status and messages.

    The judge is the kit's own code and limits each call to the student's code itself (and, with
    `budget`, the step's and each case's calls in all); the limits here only guard against the judge
    going wrong. Should one stop a case whose time went mostly into the student's calls all the
    same (a machine so busy that the judge's own bound came late), the timeout is the student's.
    """
    by_name = {c.name: c for c in cases}
    order = [c.name for c in cases]
    deadline = time.monotonic() + step_seconds
    done: set[str] = set()
    full_env = dict(os.environ, **(env or {}))
    with tempfile.TemporaryDirectory(prefix="raykit-judge-") as tmp:
        attempt = 0
        while len(done) < len(cases) and time.monotonic() < deadline:
            attempt += 1
            out = Path(tmp) / f"run{attempt}.jsonl"
            log = Path(tmp) / f"out{attempt}.txt"
            # doctest runs the cases in the order it lists them; resume after the last one seen.
            first = next(i for i, n in enumerate(order) if n not in done) + 1
            with open(log, "wb") as sink:
                proc = subprocess.Popen([str(exe), "--reporters=raykit", f"--out={out}", f"--first={first}",
                                         "--no-breaks=true"],
                                        stdout=sink, stderr=sink, stdin=subprocess.DEVNULL,
                                        start_new_session=True, env=full_env)
                current, started_at, reason = None, time.monotonic(), None
                seen = 0
                while True:
                    finished = proc.poll() is not None
                    events = _read_lines(out)
                    for e in events[seen:]:
                        if e.get("event") == "start":
                            current, started_at = e["case"], time.monotonic()
                            if faults.fault("judge", exe.name[-2:]):     # the self-test's crash of the judge
                                faults.abort(proc.pid)
                        elif e.get("event") == "end" and e["case"] in by_name:
                            c = by_name[e["case"]]
                            _take(c, e)
                            done.add(c.name)
                            current = None
                    seen = len(events)
                    if finished:
                        break
                    now = time.monotonic()
                    if now - started_at > case_seconds or now > deadline:
                        reason = TIMED_OUT
                    elif log.stat().st_size > OUTPUT_LIMIT:
                        reason = "flooded"
                    if reason:
                        _kill(proc)
                        break
                    time.sleep(0.01)
            if current is None and reason is None and proc.returncode in (0, 1):
                break       # a normal end (doctest exits 1 when a case failed)
            if current is None or current not in by_name:
                rest = [n for n in order if n not in done]
                if not rest:
                    break
                current = rest[0]
            c = by_name[current]
            done.add(current)
            theirs = budget.case_seconds_now() if budget is not None and reason == TIMED_OUT else 0.0
            if theirs >= case_seconds / 2:
                spent = budget.spent()
                c.status = TIMED_OUT
                c.messages = [f"Time out: this case was stopped after {case_seconds:g} s, {theirs:.1f} s of them in "
                              f"your code's calls (each call within its own limit, but a case makes many): your "
                              f"code is too slow or waits. On this step your code has used {spent['cpu']:.1f} s of "
                              f"CPU and waited {spent['wait']:.1f} s in {spent['calls']} calls; {budget.note()}."]
                continue
            # The judge itself stopped (its own crash, a flood, a stop the student's calls did not
            # cause): no verdict, the grader's fault, so not graded (faults.py), never a crash of theirs.
            how = reason or (f"signal {signal.Signals(-proc.returncode).name}"
                             if proc.returncode < 0 and -proc.returncode in signal.valid_signals()
                             else f"exit status {proc.returncode}")
            c.status = GRADER_ERROR
            c.incident = {"function": "", "signal": how.removeprefix("signal ") if how.startswith("signal") else "",
                          "fault": f"the kit's test program stopped ({how})"}
            c.messages = [f"The kit's test program itself stopped in this case ({how}): not graded, the "
                          "grader's fault, not yours."]
        ended = time.monotonic() < deadline    # the judge ended early, with cases it gave no verdict for
        # Or the step's wall-clock backstop ran out while the student's code was within its budget of CPU
        # and waiting: the time went to a busy machine or to the judge, not to the code (see "Budgets").
        spent = budget.spent() if budget is not None else None
        within = spent is not None and spent["cpu"] < budget.cpu and spent["wait"] < budget.wait
        for c in cases:
            if c.name not in done and c.status == NOT_RUN:
                if ended or within:
                    fault = ("the kit's test program gave no verdict" if ended else
                             f"the step's {step_seconds:g} s ran out with the code within its budget (a busy machine)")
                    c.status = GRADER_ERROR
                    c.incident = {"function": "", "signal": "", "fault": fault}
                    c.messages = [f"Not run: {fault}: not graded, the grader's fault, not yours."]
                else:
                    c.messages = ["Not run: the step's time ran out."]


RERUN_WHY = "timed out: run once more, alone, before it is failed"


def rerun_timeouts(exe: Path, cases: list[Case], env: dict[str, str],
                   fresh: Callable[[], None] | None = None, looped: bool = False) -> None:
    """A case that timed out is run once more, on its own, before it is failed: a loaded machine,
    a slow first start, must not fail correct code. The second verdict is the one kept (the first
    when the second gives none); the case records both runs (Case.runs, Case.rerun: why, the first
    run's verdict, which run is shown), for the grader's record, not for students.

    It runs after the hidden cases and students see what it prints, so it must start from nothing
    they left: its judge is a new process (a new answers process, in a new scratch folder, see
    sandbox.Scratch), and `fresh` clears what else the code could write (Scratch.between_runs).

    `looped`: a call of the step computed for its whole CPU limit (the judge's ledger says so). Then
    only the first case that timed out runs again: every later call gets a fraction of a second of
    CPU, so the others, run again, would only time out again, and an endless loop would cost its
    step a re-run a case."""
    again_left = 1 if looped else len(cases)
    for c in cases:
        if c.status != TIMED_OUT or again_left == 0:
            continue
        again_left -= 1
        if fresh is not None:
            fresh()
        again = Case(c.name, c.tier, c.lecture)
        c.runs += 1
        c.rerun = {"why": RERUN_WHY, "first": {"status": c.status, "messages": list(c.messages)}, "kept": 1}
        with tempfile.TemporaryDirectory(prefix="raykit-rerun-") as tmp:
            out = Path(tmp) / "run.jsonl"
            try:
                subprocess.run([str(exe), "--reporters=raykit", f"--out={out}", f"--test-case={c.name}",
                                "--no-breaks=true"], stdin=subprocess.DEVNULL, capture_output=True,
                               timeout=CASE_SECONDS, env=dict(os.environ, **env), start_new_session=True)
            except subprocess.TimeoutExpired:
                continue
            for e in _read_lines(out):
                if e.get("event") == "end" and e.get("case") == c.name:
                    _take(again, e)
        if again.status != NOT_RUN:
            again.messages = list(again.messages)
            if again.status == TIMED_OUT:
                again.messages.append("(It timed out twice: the case was run again on its own.)")
            c.status, c.messages, c.output, c.output_bytes, c.figure, c.incident = (
                again.status, again.messages, again.output, again.output_bytes, again.figure, again.incident)
            c.rerun["kept"] = c.runs


def _take(c: Case, e: dict) -> None:
    """A case's verdict from the judge's end event; what came from the student's code is data."""
    c.status = str(e.get("status", NOT_RUN))
    c.messages = [printable(str(m)) for m in e.get("messages", [])]
    c.output, c.output_bytes = printable(str(e.get("output", ""))), int(e.get("output_bytes", 0))
    c.figure = e.get("figure") if isinstance(e.get("figure"), dict) else None
    incident = e.get("incident")
    c.incident = ({"function": printable(str(incident.get("function", ""))),
                   "signal": printable(str(incident.get("signal", "")))} if isinstance(incident, dict) else None)
    if e.get("fault"):      # the judge's own crash (tests/support/reporter.cpp): no verdict, not theirs
        fault = printable(str(e["fault"]))[:300]
        c.status, c.incident = GRADER_ERROR, {"function": "", "signal": "", "fault": fault}
        c.messages = [f"{fault[:1].upper()}{fault[1:]}: not graded, the grader's fault, not yours."] + c.messages


def submission_seed(build: Build, step: Step) -> str:
    """The hidden cases' seed: from the instructor's secret, the submission's identity and the step's
    files (secret.py), so no student can know or steer it and a re-grade meets the same inputs."""
    if not hidden_cases_here():
        return ""               # a handout: no hidden cases, no secret
    files = []
    for f in step.files:
        p = build.steps_dir / step.folder / f
        files.append(p.read_bytes() if p.is_file() else None)
    return hidden_seed(step.folder, files, build.identity)


def not_graded(step: Step, reason: str, cases: list[Case] | None = None, detail: str = "") -> StepResult:
    """A step the grader failed: every case without a verdict (GRADER_ERROR), its recorded ones when
    the judge could not list them, so the step keeps its points' maximum and loses none of them."""
    cases = cases if cases else (recorded_cases(step) or [])
    return StepResult(step, NOT_GRADED, _all(cases, GRADER_ERROR, f"not graded: {reason}"),
                      detail=detail or f"not graded, the grader's fault, not the student's: {reason}",
                      reason=reason)


def _all(cases: list[Case], status: str, message: str) -> list[Case]:
    for c in cases:
        c.status, c.messages = status, [message]
    return cases


@dataclass
class Built:
    """What building a step's judge and answers program gave."""
    judge_ok: bool
    answers_ok: bool
    output: str                 # the build tool's output (the compiler's errors, if any)
    missing: list[str] = field(default_factory=list)    # the step's files not there when it was built


def build_step(build: Build, step: Step, progress: Callable[[int, int], None] | None = None,
               isolation: Isolation | None = None) -> Built:
    """Builds the step's judge and, when its files are all there, its answers program, in one call of
    the build tool (both in parallel; -k 0 so the judge is built even where the student's code fails).
    A graded submission's answers program is compiled and linked by the kit itself inside the
    boundary (build_answers), the rest by the build tool."""
    missing = [f for f in step.files if not (build.steps_dir / step.folder / f).is_file()]
    if not missing and build.boundary and isolation is not None:
        commands = answers_commands(build, step)
        if commands is not None:
            return build_answers(build, step, commands, isolation, progress)
    targets = [step.target] + ([] if missing else [f"answers_step{step.number}"])
    ok, out = build_targets(build, targets, progress)
    if ok:
        return Built(True, not missing, out, missing)
    judge_ok, judge_out = build_target(build, step.target)     # a no-op when the judge was built
    return Built(judge_ok, False, out if judge_ok else judge_out, missing)


@dataclass
class AnswersCommands:
    """How the build tool would make a step's answers program in a submission's build: the compiles
    of the student's files and the link, each as the sandbox launcher would be given it, and what
    of the kit's own they need first (the dispatcher's object, the reference's for the steps needed)."""
    compiles: list[list[str]]
    link: list[str]
    kit_inputs: list[str]


def answers_commands(build: Build, step: Step) -> AnswersCommands | None:
    """Read from Ninja (`ninja -t commands answers_stepNN`); None where there is no Ninja build or
    no such target (a step it needs is missing), and the build tool makes it as before."""
    import shlex
    ninja = ninja_of(build)
    if ninja is None:
        return None
    r = subprocess.run([ninja, "-C", str(build.binary_dir), "-t", "commands", f"answers_step{step.number}"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        return None
    compiles, link = [], None
    for line in r.stdout.splitlines():
        if "tools/kitlib/launch.py" not in line:    # the kit's own commands: not split, not needed
            continue
        words = shlex.split(line)
        segments, part = [], []
        for w in words + ["&&"]:
            if w == "&&":
                segments.append(part)
                part = []
            else:
                part.append(w)
        for seg in segments:
            at = next((i for i, w in enumerate(seg) if w.endswith("tools/kitlib/launch.py")), None)
            if at is None or at + 1 >= len(seg):
                continue
            if seg[at + 1] == "compile":
                compiles.append(seg[at + 2:])
            elif seg[at + 1] == "link":
                link = seg[at + 2:]
    if link is None or not compiles:
        return None
    made = {c[c.index("-o") + 1] for c in compiles if "-o" in c}
    inputs = [w for w in link[1:] if w.endswith((".o", ".a")) and w not in made and not w.startswith("-")]
    return AnswersCommands(compiles, link, inputs)


def build_answers(build: Build, step: Step, commands: AnswersCommands, isolation: Isolation,
                  progress: Callable[[int, int], None] | None = None) -> Built:
    """The judge and the kit's inputs by the build tool, then the student's files compiled (in
    parallel) and linked by this process inside the boundary (Isolation.tool, the code the sandbox
    launcher runs): no launcher process per compile (0.08 s of CPU each, measured)."""
    total = len(commands.compiles) + 2
    judge_ok, out = build_targets(build, [step.target] + commands.kit_inputs)
    if progress:
        progress(1, total)
    if not judge_ok:
        judge_ok, judge_out = build_target(build, step.target)
        return Built(judge_ok, False, out if judge_ok else judge_out)
    done = [1]

    def compile_one(argv: list[str]) -> tuple[int, str]:
        result = isolation.tool("compile", argv, build.binary_dir, ObjectCache)
        done[0] += 1
        if progress:
            progress(done[0], total)
        return result

    compiled = map_in_threads(compile_one, commands.compiles, os.cpu_count() or 1)
    texts = [text for _, text in compiled]
    ok = all(status == 0 for status, _ in compiled)
    if ok:
        status, text = isolation.tool("link", commands.link, build.binary_dir)
        texts.append(text)
        ok = status == 0
        if progress:
            progress(total, total)
    return Built(True, ok, shown_text(build, "".join(texts)))


def judge_step(build: Build, step: Step, built: Built, results: dict[str, StepResult],
               isolation: Isolation, tiers: set[str] | None = None) -> StepResult:
    """Runs a built step's cases and says what state the step is in; only those of `tiers` when given
    (the fairness table re-runs the hidden cases alone on each draw)."""
    machine = faults.machine_fault(built.output)
    if not built.judge_ok or machine:
        why = (f"the machine failed the build: {machine}" if machine else
               "the kit's test program does not build (a kit bug)")
        return not_graded(step, why, detail=why + ":\n" + built.output)
    judge = build.exe(step)
    try:
        cases = [c for c in list_cases(judge) if tiers is None or c.tier in tiers]
    except (RuntimeError, subprocess.TimeoutExpired, OSError) as e:
        return not_graded(step, f"the test program could not list its cases: {e}")
    if built.missing:
        detail = f"{step.folder}/{built.missing[0]} is missing"
        return StepResult(step, MISSING, _all(cases, MISSING, detail), detail=detail)
    if not build.reference_needs:
        # No reference here (a student's handout): the step runs on the student's own
        # earlier steps, so the cases that call them wait until they are done (waits.py).
        need = waits.waits_whole(step, results)
        if need:
            return StepResult(step, WAITING, _all(cases, WAITING, f"needs step {need} done first"), detail=need)
    if not built.answers_ok and SANDBOX_FAILED in built.output:
        line = next(l for l in built.output.splitlines() if SANDBOX_FAILED in l)
        return StepResult(step, NOT_GRADED, _all(cases, GRADER_ERROR, line), isolation=isolation.description,
                          detail="not graded, the grader's fault, not the student's: " + line.removeprefix("raykit: "),
                          reason=line.removeprefix("raykit: "))
    # A standard header the student's files use without including it (includes.py): said in the same
    # words whether the file compiles here (a warning under the step) or not (the error's first line).
    found = includes.step_findings(build.steps_dir, step.folder, step.files, ROOT / "include")
    if not built.answers_ok:
        first = found[0] if found else next((l for l in built.output.splitlines() if "error" in l), "")
        return StepResult(step, NO_COMPILE, _all(cases, NO_COMPILE, "does not compile: " + first.strip()),
                          detail="\n".join(found + [built.output]), includes=found)
    seed = submission_seed(build, step)
    scratch = Scratch(isolation, build.binary_dir / f"answers_step{step.number}")
    ledger_dir = ""
    try:
        # The step's budget (see "Budgets"): its ledger in a folder of the grader's, which the
        # sandboxed code cannot reach, shared by every run of the judge, the cases run again too.
        ledger_dir = tempfile.mkdtemp(prefix="raykit-ledger-")
        budget = step_budget(step, Path(ledger_dir) / "ledger")
        env = dict(scratch.env(), RAYKIT_SEED=seed, **budget.env())
        if not isolation.sandboxed:
            env["RAYKIT_ANSWERS"] = str(build.binary_dir / f"answers_step{step.number}")
        run_cases(judge, cases, env, *course_file.load().case_limits(), budget=budget)   # course.json time_limits
        rerun_timeouts(judge, cases, env, scratch.between_runs, looped=budget.spent()["looped"])
        record_reference_time(build, step, budget, cases)
        spent = budget.spent()
        cost = {"cpu": round(spent["cpu"], 3), "wait": round(spent["wait"], 3), "calls": spent["calls"],
                "cpu_budget": budget.cpu, "wait_budget": budget.wait}
    finally:
        scratch.close()
        if ledger_dir:
            shutil.rmtree(ledger_dir, ignore_errors=True)
    failed_sandbox = [c for c in cases if c.status == GRADER_ERROR]
    if failed_sandbox:      # the sandbox, the judge, the disk: no verdict for the step (faults.py)
        first = failed_sandbox[0].messages[0] if failed_sandbox[0].messages else "no verdict"
        fault = (failed_sandbox[0].incident or {}).get("fault")
        reason = f"{fault} in {len(failed_sandbox)} of {len(cases)} cases" if fault else first
        return StepResult(step, NOT_GRADED, cases, isolation=isolation.description, reason=reason,
                          detail=f"not graded, the grader's fault, not the student's ({len(failed_sandbox)} of "
                                 f"{len(cases)} cases without a verdict): {first}")
    scored = [c for c in cases if c.tier == "basic"]
    if scored and all(c.status == NOT_STARTED for c in cases if c.tier != "hidden"):
        state = NOT_STARTED
    elif all(c.status == PASS for c in cases if c.tier in SCORED_TIERS):
        state = DONE
    else:
        state = PARTIAL
    if not build.reference_needs:
        state = waits.wait_on_needs(step, cases, results, state)
    slip = slips.match(step, cases)
    result = StepResult(step, state, cases, detail=",".join(waits.pending(step, results)) if state == WAITING else "",
                        isolation=isolation.description, seed=seed if any(c.tier == "hidden" for c in cases) else "",
                        cost=cost, includes=found, slip=slip)
    slips.say(result)
    return result


# --- untouched steps: no build ---------------------------------------------------------------
# A step whose files are byte for byte the shipped stubs is "not started" without a compile: its
# state comes from the content. tests/stubs.json records the stubs' hashes, tests/NN_topic/cases.json
# each judge's visible cases and tests/hidden/cases.json the hidden ones (not in a handout), so that
# such a step still has its cases and its points on the one scale. `./kit check --record` writes
# them; the self-test fails when they are stale.
STUBS_FILE = ROOT / "tests" / "stubs.json"
HIDDEN_CASES_FILE = ROOT / "tests" / "hidden" / "cases.json"


def file_hash(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def untouched(build: Build, step: Step) -> bool:
    try:
        stubs = json.loads(STUBS_FILE.read_text())
    except (OSError, ValueError):
        return False
    for f in step.files:
        p = build.steps_dir / step.folder / f
        key = f"{step.folder}/{f}"
        if key not in stubs or not p.is_file() or file_hash(p) != stubs[key]:
            return False
    return True


def hidden_cases_here() -> bool:
    """Whether the judges hold hidden cases: the reference and tests/hidden/ are here."""
    return (ROOT / "solutions").is_dir() and (ROOT / "tests" / "hidden").is_dir()


def recorded_cases(step: Step) -> list[Case] | None:
    """The cases the step's judge lists, as recorded; None when there is no record."""
    try:
        visible = json.loads((ROOT / "tests" / step.folder / "cases.json").read_text())
        hidden = json.loads(HIDDEN_CASES_FILE.read_text()).get(step.number, []) if hidden_cases_here() else []
    except (OSError, ValueError):
        return None
    return [Case(c["name"], c["tier"], c.get("lecture", "")) for c in visible + hidden]


def untouched_result(step: Step, cases: list[Case], results: dict[str, StepResult], build: Build) -> StepResult:
    """Not started, whatever the steps it needs: nothing of it is written yet."""
    for c in cases:
        c.status, c.messages = NOT_STARTED, ["not started: the step's files are the shipped stubs "
                                             "(each function is still not_implemented_yet)"]
    return StepResult(step, NOT_STARTED, cases)


def record(build: Build, steps: list[Step], all_steps: list[Step] | None = None) -> list[Path]:
    """Writes tests/stubs.json from steps/ (every step of `all_steps`, default `steps`) and the case
    lists of `steps` from their built judges (`build` must have the hidden cases, i.e. solutions/
    present); the hidden case lists of the other steps are kept. Returns the files written."""
    stubs = {f"{s.folder}/{f}": file_hash(ROOT / "steps" / s.folder / f) for s in all_steps or steps
             for f in s.files}
    written = [STUBS_FILE]
    STUBS_FILE.write_text(json.dumps(stubs, indent=1, sort_keys=True) + "\n")
    known = {s.number for s in all_steps or steps}
    try:
        kept = json.loads(HIDDEN_CASES_FILE.read_text()) if all_steps else {}
    except (OSError, ValueError):
        kept = {}
    hidden: dict[str, list] = {n: v for n, v in kept.items() if n in known}
    for s in steps:
        cases = list_cases(build.exe(s))
        entry = lambda c: {"name": c.name, "tier": c.tier, "lecture": c.lecture}   # noqa: E731
        target = ROOT / "tests" / s.folder / "cases.json"
        target.write_text(json.dumps([entry(c) for c in cases if c.tier != "hidden"], indent=1) + "\n")
        written.append(target)
        hidden[s.number] = [entry(c) for c in cases if c.tier == "hidden"]
    HIDDEN_CASES_FILE.write_text(json.dumps(hidden, indent=1, sort_keys=True) + "\n")
    return written + [HIDDEN_CASES_FILE]


# --- one verdict per content within a grading --------------------------------------------------
# `./kit grade` names a folder of its own (RAYKIT_VERDICTS_DIR, made afresh for each run and
# removed after it) where each submission's check keeps its steps' results by content: a step
# whose files are byte for byte another submission's (a copy of the solutions, the same slip) was
# already compiled, run and judged, with the same hidden cases (their seed is a hash of the
# files), so it takes that verdict without a build. The key holds everything else a result
# depends on that can differ inside one grading: the isolation's kind, and, where there is no
# reference (a handout), the files of the steps it needs. Only the grader writes there (build/ is
# hidden from graded code); a result with a case that timed out or a sandbox that failed is never
# kept, so each copy gets its own chance at it.
VERDICTS_ENV = "RAYKIT_VERDICTS_DIR"


def verdict_key(build: Build, step: Step, all_steps: list[Step], isolation: Isolation) -> str:
    h = hashlib.sha256(f"raykit-verdict-2\0{isolation.mode.split(':')[0]}\0{build.reference_needs}\0".encode())
    h.update(build.identity.encode("utf-8", "surrogateescape") + b"\0")   # the hidden cases' draw
    for s in [step] + ([] if build.reference_needs else prerequisites(step, all_steps)):
        for f in s.files:
            p = build.steps_dir / s.folder / f
            h.update(f"{s.folder}/{f}\0".encode() + (p.read_bytes() if p.is_file() else b"\0missing") + b"\0")
    return h.hexdigest()


class Verdicts:
    """The grading's verdicts by content (see above); `here()` is None outside a grading."""

    SHOWN = "@SHOWN@"       # where the submission's own path stood in the text

    def __init__(self, folder: Path, build: Build, all_steps: list[Step], isolation: Isolation):
        self.folder, self.build, self.all_steps, self.isolation = folder, build, all_steps, isolation
        self.paths: dict[str, Path] = {}    # by step: the files are read once, before the build

    @classmethod
    def here(cls, build: Build, all_steps: list[Step], isolation: Isolation) -> "Verdicts | None":
        named = os.environ.get(VERDICTS_ENV)
        if not named or not build.boundary or not Path(named).is_dir():
            return None
        return cls(Path(named), build, all_steps, isolation)

    def _path(self, step: Step) -> Path:
        if step.number not in self.paths:
            self.paths[step.number] = self.folder / f"{verdict_key(self.build, step, self.all_steps, self.isolation)}.json"
        return self.paths[step.number]

    def load(self, step: Step) -> StepResult | None:
        try:
            d = json.loads(self._path(step).read_text())
        except (OSError, ValueError):
            return None
        shown = str(self.build.shown_dir)
        cases = [Case(c["name"], c["tier"], c["lecture"], c["status"], c["messages"], c["output"],
                      c["output_bytes"], c["figure"], runs=c.get("runs", 1), rerun=c.get("rerun"),
                      incident=c.get("incident"))
                 for c in d["cases"]]
        return StepResult(step, d["state"], cases, detail=d["detail"].replace(self.SHOWN, shown),
                          isolation=self.isolation.description, seed=d["seed"], includes=d.get("includes", []),
                          slip=d.get("slip"), reason=d.get("reason", ""))

    KEEP_TIMEOUTS = False   # a grading's copies each get their own chance at a case that timed out

    def store(self, result: StepResult, everything: bool = False) -> None:
        """Keeps `result` for its content; not one the grader failed (not graded, a sandbox that could
        not start), unless `everything`."""
        if not everything and (result.state == NOT_GRADED or any(c.status == GRADER_ERROR for c in result.cases) or
                               (not self.KEEP_TIMEOUTS and any(c.status == TIMED_OUT for c in result.cases))):
            return
        shown = str(self.build.shown_dir)
        data = {"state": result.state, "detail": result.detail.replace(shown, self.SHOWN), "seed": result.seed,
                "includes": result.includes, "slip": result.slip, "reason": result.reason,
                "cases": [{"name": c.name, "tier": c.tier, "lecture": c.lecture, "status": c.status,
                           "messages": c.messages, "output": c.output, "output_bytes": c.output_bytes,
                           "figure": c.figure, "runs": c.runs, "rerun": c.rerun, "incident": c.incident}
                          for c in result.cases]}
        try:
            atomic.write(self._path(result.step), json.dumps(data))
        except OSError:
            pass


class LastCheck(Verdicts):
    """The student's last `./kit check`, step by step, by content (build/last-check/): `./kit hint` takes
    its first failing case from there instead of running the step's cases again while the step's files
    (and those of the steps it needs), the isolation and the judge program are the same as then."""

    FOLDER = BUILD / "last-check"
    KEEP_TIMEOUTS = True    # what the student was shown, a loop included

    def __init__(self, build: Build, all_steps: list[Step], isolation: Isolation):
        super().__init__(self.FOLDER, build, all_steps, isolation)

    def _path(self, step: Step) -> Path:
        if step.number not in self.paths:
            try:
                st = self.build.exe(step).stat()
                judge = f"{st.st_size}-{st.st_mtime_ns}"
            except OSError:
                judge = "no judge"
            key = verdict_key(self.build, step, self.all_steps, self.isolation)
            self.paths[step.number] = self.folder / f"{key[:32]}-{hashlib.sha256(judge.encode()).hexdigest()[:16]}.json"
        return self.paths[step.number]

    def keep(self, results: list[StepResult]) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        for old in sorted(self.folder.glob("*.json"), key=lambda p: p.stat().st_mtime)[:-64]:
            old.unlink(missing_ok=True)       # the last few dozen checks are plenty
        for r in results:
            self.store(r)


class OneResult(Verdicts):
    """One step's result in a file of its own (./kit watch's check, run in a child process)."""

    def __init__(self, path: Path, build: Build, all_steps: list[Step]):
        super().__init__(path.parent, build, all_steps, NONE_OWN)
        self.path = path

    def _path(self, step: Step) -> Path:
        return self.path


class Progress:
    """What check_steps says while it works; the default says nothing (scoreboard.LiveProgress
    shows it on a terminal)."""

    def phase(self, text: str) -> None: ...
    def building(self, step: Step, done: int, total: int) -> None: ...
    def result(self, result: StepResult) -> None: ...


def check_steps(build: Build, steps: list[Step], all_steps: list[Step], isolation: Isolation = NONE_OWN,
                progress: Progress | None = None) -> list[StepResult]:
    """Checks `steps`; without a reference, first the steps they need (quietly, to know whether they
    are done).

    Pipelined: while one step's cases run (in a worker thread, in course order), the next step is
    built, so the first verdict comes after one step's build and the others follow as they build.
    """
    progress = progress or Progress()
    warmup.stop(build)      # never two builds in one folder: a check goes first (warmup.py)
    if build.boundary:
        build.spec = isolation.spec()
    wanted = {s.number for s in steps}
    needed = set() if build.reference_needs else {p.number for s in steps for p in prerequisites(s, all_steps)}
    order = [s for s in all_steps if s.number in wanted or s.number in needed]
    quick = {}
    for s in order:
        cases = recorded_cases(s) if untouched(build, s) else None
        if cases is not None:
            quick[s.number] = cases
    verdicts = Verdicts.here(build, all_steps, isolation)
    known = {}
    for s in order:
        found = verdicts.load(s) if verdicts is not None and s.number not in quick else None
        if found is not None:
            known[s.number] = found
    results: dict[str, StepResult] = {}
    if len(quick) + len(known) < len(order):
        progress.phase("configuring the build (cmake)")
        ensure_configured(build, all_steps)

    def judge(step: Step, built: Built | Exception | None) -> None:
        if step.number in known:
            results[step.number] = known[step.number]
        elif built is None:
            results[step.number] = untouched_result(step, quick[step.number], results, build)
        elif isinstance(built, Exception):
            results[step.number] = not_graded(step, f"the kit failed building it: {faults.describe(built)}")
        else:
            try:
                results[step.number] = judge_step(build, step, built, results, isolation)
            except Exception as e:      # noqa: BLE001 -- the kit's fault (a full disk): the step has no verdict
                results[step.number] = not_graded(step, f"the kit failed running it: {faults.describe(e)}")
            if verdicts is not None:
                verdicts.store(results[step.number])
        if step.number in wanted:
            progress.result(results[step.number])

    judges = InOrder()      # steps are judged in course order, each while the next one builds
    try:
        for s in order:
            built: Built | Exception | None = None
            if s.number not in quick and s.number not in known:
                try:
                    built = build_step(build, s, lambda done, total, s=s: progress.building(s, done, total),
                                       isolation)
                except Exception as e:      # noqa: BLE001 -- the kit's or the machine's: not graded
                    built = e
            judges.submit(judge, s, built)
    except BaseException:
        judges.finish(raising=False)    # the build's error, not a judge's, once the judges have ended
        raise
    judges.finish()
    return [results[s.number] for s in steps]

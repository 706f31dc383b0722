"""Running a step's judge over its cases: listing them, running them with the kit's backstops (a time
limit per case and per step, a limit on the judge's own output), a timed-out case run once more alone,
each case's verdict read from the judge's report; and the step's budget for the student's code (see
"Budgets" below), with the reference's own time on this machine. The cases are cases.py's; building
and judging a step, checking.py's.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from contextlib import suppress
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from . import atomic
from . import course as course_file
from . import faults
from . import heldtmp
from .build import Build
from .cases import Case
from .sandbox.reaping import reap_orphans
from .common import BUILD, ROOT, Step, printable
from .status import CRASHED, GRADER_ERROR, NOT_RUN, PASS, TIMED_OUT

CASE_SECONDS = 30.0         # backstop: the judge limits each call; a case may make many
STEP_SECONDS = 120.0        # backstop: all cases of one step, including restarts
OUTPUT_LIMIT = 1 << 20      # bytes the judge itself may print (it prints nothing)


def _read_lines(path: Path) -> list[dict]:
    events = []
    try:
        text = path.read_text(errors="replace")
    except FileNotFoundError:
        return events
    for line in text.splitlines():
        with suppress(json.JSONDecodeError):  # a half-written last line from a killed process
            events.append(json.loads(line))
    return events


def _kill(proc: subprocess.Popen) -> None:
    with suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()


def list_cases(exe: Path) -> list[Case]:
    with heldtmp.held("raykit-list-") as tmp:
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


# Speed is part of the course, but not of the grade: where a step's calls took more than SLOW_FACTOR
# times the CPU the reference's took on this machine (REFERENCE_TIMES, measured when the solutions were
# last graded here, so only where solutions/ is: a handout says nothing), the scoreboard says so beside
# the verdict, with the factor. A reference's figure below CPU_FLOOR seconds is taken as CPU_FLOOR: the
# CPU clock and a busy machine move such small figures by their own size, and a factor over them would
# be noise.
SLOW_FACTOR = 3.0
CPU_FLOOR = 0.05


def speed_note(cost: dict | None) -> str:
    """"slow: N× the reference's CPU ..." for a step's cost (StepResult.cost), or "" (not slow, or no
    reference figure)."""
    try:
        cpu, ref = float((cost or {})["cpu"]), float((cost or {})["reference_cpu"])
    except (KeyError, TypeError, ValueError):
        return ""
    base = max(ref, CPU_FLOOR)
    if not cpu > SLOW_FACTOR * base:
        return ""
    factor = f"{cpu / base:.0f}×" if ref >= CPU_FLOOR else f"over {cpu / base:.0f}×"
    return f"slow: {factor} the reference's CPU, {cpu:.2f} s against {ref:.2f} s on this machine; not graded"


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
    with suppress(OSError):
        REFERENCE_TIMES.parent.mkdir(parents=True, exist_ok=True)
        atomic.write(REFERENCE_TIMES, json.dumps(data, indent=1, sort_keys=True) + "\n")


def group_cpu(groups: list[str]) -> float | None:
    """CPU seconds the processes of the slot's control groups have used (cgroup v2 `cpu.stat`, v1
    `cpuacct.usage`): every process the student's code ran, start-ups and killed ones included, as the
    kernel counts them. None where there is no such group (a container: the judge's ledger only)."""
    total, found = 0.0, False
    for g in groups:
        with suppress(OSError, KeyError, ValueError):
            stat = dict(line.split() for line in (Path(g) / "cpu.stat").read_text().splitlines() if " " in line)
            total, found = total + int(stat["usage_usec"]) / 1e6, True
            continue
        with suppress(OSError, ValueError):
            total, found = total + int((Path(g) / "cpuacct.usage").read_text()) / 1e9, True
    return total if found else None


# A case not run because the step's wall-clock backstop ran out while the student's code held the time:
# the student's timeout, not run again (the step's time is gone).
STEP_TIME_OUT = "Time out: the step's time ran out"


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
    began = time.monotonic()
    deadline = began + step_seconds
    groups = [g for g in (env or {}).get("RAYKIT_SANDBOX_CGROUPS", "").split(":") if g]
    group_start = group_cpu(groups)
    done: set[str] = set()
    full_env = dict(os.environ, **(env or {}))
    sandbox_uids = {int(u) for u in [full_env.get("RAYKIT_SANDBOX_UID", "")] if u.isdigit() and int(u)}
    with heldtmp.held("raykit-judge-") as tmp:
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
                reaped_at = time.monotonic()
                while True:
                    finished = proc.poll() is not None
                    if sandbox_uids and time.monotonic() - reaped_at > 0.25:
                        # The sandboxes of calls that ended are given to this process (a subreaper)
                        # when their wrapper dies first. Reaped as the judge runs, not when the step
                        # ends: a step of many crashing calls (hostile/self_kill) would otherwise
                        # fill the sandbox id's process limit with zombies, and the sandbox could no
                        # longer start: "not graded", a free attempt.
                        reap_orphans(sandbox_uids)
                        reaped_at = time.monotonic()
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
        # Or the step's wall-clock backstop ran out. Whose time was it? The kit's own measurements say:
        # the judge's ledger (the CPU of the answers processes, their start-up included, and the time
        # they waited) and, where there is one, the slot's control group (the kernel's count of every
        # process of the student's). Once the budget is spent, or when the student's processes held
        # half the step's wall time or more, the cases left are the student's timeouts. Not graded
        # only when the code was within its budget and held under half the time: the machine (or
        # the judge) took the rest (see "Budgets").
        spent = budget.spent() if budget is not None else None
        wall = time.monotonic() - began
        group_now = group_cpu(groups)
        kernel_cpu = group_now - group_start if group_now is not None and group_start is not None else 0.0
        theirs_cpu = max(spent["cpu"] if spent else 0.0, kernel_cpu)
        theirs = theirs_cpu + (spent["wait"] if spent else 0.0)
        within = spent is not None and spent["cpu"] < budget.cpu and spent["wait"] < budget.wait
        machine = within and theirs < wall / 2
        for c in cases:
            if c.name not in done and c.status == NOT_RUN:
                if ended or machine:
                    fault = ("the kit's test program gave no verdict" if ended else
                             f"the step's {step_seconds:g} s ran out while the code used {theirs_cpu:.1f} s of CPU "
                             f"and waited {spent['wait']:.1f} s of {wall:.0f} s, within its budget (a busy machine)")
                    c.status = GRADER_ERROR
                    c.incident = {"function": "", "signal": "", "fault": fault}
                    c.messages = [f"Not run: {fault}: not graded, the grader's fault, not yours."]
                else:
                    c.status = TIMED_OUT
                    c.messages = [f"{STEP_TIME_OUT} ({step_seconds:g} s) before this case: your code's processes "
                                  f"used {theirs_cpu:.1f} s of CPU and waited "
                                  f"{spent['wait'] if spent else 0.0:.1f} s of the step's {wall:.0f} s"
                                  + (f"; {budget.note()}." if budget is not None else ".")]


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
        if c.status != TIMED_OUT or again_left == 0 or (c.messages and c.messages[0].startswith(STEP_TIME_OUT)):
            continue
        again_left -= 1
        if fresh is not None:
            fresh()
        c.runs += 1
        c.rerun = {"why": RERUN_WHY, "first": {"status": c.status, "messages": list(c.messages)}, "kept": 1}
        again, outlived = _run_alone(exe, c, env)
        if outlived:
            continue
        if again.status != NOT_RUN:
            again.messages = list(again.messages)
            if again.status == TIMED_OUT:
                again.messages.append("(It timed out twice: the case was run again on its own.)")
            c.status, c.messages, c.output, c.output_bytes, c.figure, c.incident = (
                again.status, again.messages, again.output, again.output_bytes, again.figure, again.incident)
            c.rerun["kept"] = c.runs


def _run_alone(exe: Path, c: Case, env: dict[str, str]) -> tuple[Case, bool]:
    """`c` run once more by the judge, alone, in a new session: the new verdict (NOT_RUN when the judge
    gave none), and whether the run outlived the case's backstop."""
    again = Case(c.name, c.tier, c.lecture)
    outlived = False
    with heldtmp.held("raykit-rerun-") as tmp:
        out = Path(tmp) / "run.jsonl"
        try:
            subprocess.run([str(exe), "--reporters=raykit", f"--out={out}", f"--test-case={c.name}",
                            "--no-breaks=true"], stdin=subprocess.DEVNULL, capture_output=True,
                           timeout=CASE_SECONDS, env=dict(os.environ, **env), start_new_session=True)
        except subprocess.TimeoutExpired:
            outlived = True
        for e in _read_lines(out):
            if e.get("event") == "end" and e.get("case") == c.name:
                _take(again, e)
    return again, outlived


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


UNSENT_WHY = "killed by SIGKILL or SIGTERM, which the kit did not send: run once more, alone"
UNSENT_SIGNALS = ("SIGKILL", "SIGTERM")


def rerun_unsent_kills(exe: Path, cases: list[Case], env: dict[str, str],
                       fresh: Callable[[], None] | None = None) -> None:
    """A case whose answers process died by SIGKILL or SIGTERM without the judge's own stop (a crash,
    not a time out: the judge's kills are time outs) is run once more, alone, like a case that timed
    out. Such a signal may be the code's own (raise(SIGKILL), its CPU limit) or another process's (a
    grading that took the same sandbox id and ended its processes, the machine's OOM killer); the
    kit cannot tell the sender after the fact, but the code's own death comes again on the same
    input. The same death again stays the code's crash; anything else is kept as the verdict
    (docs/integrity.md, "Signals the kit did not send"): the code computes the same answer twice,
    so the second run is its own. Once the first three such cases all died the same way again, the
    rest are the code's too and are not run again (a step that kills itself in every case costs three
    re-runs, not one a case)."""
    same = 0
    for c in cases:
        signal_name = (c.incident or {}).get("signal", "") if c.status == CRASHED else ""
        if signal_name not in UNSENT_SIGNALS:
            continue
        if same >= 3:
            return
        if fresh is not None:
            fresh()
        again, _ = _run_alone(exe, c, env)
        c.runs += 1
        c.rerun = {"why": UNSENT_WHY, "first": {"status": c.status, "messages": list(c.messages)}, "kept": 1}
        if again.status == NOT_RUN:
            continue            # no verdict the second time: the first stands
        if again.status == CRASHED and (again.incident or {}).get("signal") == signal_name:
            same += 1
            continue            # the same death: the code's own
        c.status, c.messages, c.output, c.output_bytes, c.figure, c.incident = (
            again.status, list(again.messages), again.output, again.output_bytes, again.figure, again.incident)
        c.rerun["kept"] = c.runs

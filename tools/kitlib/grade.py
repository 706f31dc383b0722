"""Grading one build: compile each step, run its cases in a child process, collect results.

A student's code may crash, loop, throw or print without end. Each step's test
program runs in its own process group with a time limit per case and a cap on
its output; when it dies, the case it was in is recorded and the run resumes
with the next case, so one bad case costs only itself.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from common import Build, Step, build_target, configure, prerequisites

CASE_SECONDS = 3.0          # one case may run this long before it counts as hung ...
HUNG_AGAIN_SECONDS = 0.5    # ... and, once one case of the step has hung, this long
STEP_SECONDS = 20.0         # all cases of one step, including restarts
OUTPUT_LIMIT = 1 << 20      # bytes a step's own printing may produce


@dataclass
class Case:
    name: str
    tier: str                   # "basic" or "robust"
    lecture: str                # lecture section, e.g. "4. What the discriminant says"
    status: str = "not_run"     # pass fail not_started threw crashed timed_out not_run
    messages: list[str] = field(default_factory=list)


@dataclass
class StepResult:
    step: Step
    state: str                  # done, partial, not_started, missing, no_compile, locked, broken
    cases: list[Case] = field(default_factory=list)
    detail: str = ""            # compiler errors, the missing file, the step we wait for

    def tier(self, tier: str) -> list[Case]:
        return [c for c in self.cases if c.tier == tier]

    def passed(self, tier: str) -> int:
        return sum(c.status == "pass" for c in self.tier(tier))

    def first_problem(self, tier: str = "basic") -> Case | None:
        for c in self.tier(tier):
            if c.status != "pass":
                return c
        return None

    def incidents(self) -> list[Case]:
        return [c for c in self.cases if c.status in ("crashed", "timed_out", "threw")]

    def to_json(self) -> dict:
        return {
            "step": self.step.number, "folder": self.step.folder, "title": self.step.title,
            "state": self.state, "detail": self.detail,
            "basic": {"passed": self.passed("basic"), "total": len(self.tier("basic"))},
            "robust": {"passed": self.passed("robust"), "total": len(self.tier("robust"))},
            "cases": [{"name": c.name, "tier": c.tier, "lecture": c.lecture, "status": c.status,
                       "messages": c.messages} for c in self.cases],
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


def run_cases(exe: Path, cases: list[Case], case_seconds: float = CASE_SECONDS,
              step_seconds: float = STEP_SECONDS) -> None:
    """Runs every case of `exe`, filling in each Case's status and messages."""
    by_name = {c.name: c for c in cases}
    order = [c.name for c in cases]
    deadline = time.monotonic() + step_seconds
    done: set[str] = set()
    with tempfile.TemporaryDirectory() as tmp:
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
                                        start_new_session=True)
                current, started_at, reason = None, time.monotonic(), None
                seen, reported_crash = 0, False
                while True:
                    finished = proc.poll() is not None
                    events = _read_lines(out)
                    for e in events[seen:]:
                        if e.get("event") == "start":
                            current, started_at = e["case"], time.monotonic()
                        elif e.get("event") == "end" and e["case"] in by_name:
                            c = by_name[e["case"]]
                            c.status, c.messages = e["status"], list(e.get("messages", []))
                            if c.status == "crashed":
                                c.messages = [f"Your code crashed in this case: {m}" for m in c.messages]
                            done.add(c.name)
                            current = None
                            reported_crash = c.status == "crashed"
                    seen = len(events)
                    if finished:
                        break
                    now = time.monotonic()
                    if now - started_at > case_seconds or now > deadline:
                        reason = "timed_out"
                    elif log.stat().st_size > OUTPUT_LIMIT:
                        reason = "flooded"
                    if reason:
                        _kill(proc)
                        break
                    time.sleep(0.01)
            if current is None and reason is None and proc.returncode in (0, 1):
                break       # a normal end (doctest exits 1 when a case failed)
            if current is None and reason is None and reported_crash:
                continue    # doctest caught the signal and told us which case it was
            if current is None or current not in by_name:
                # Died between cases (static initialisers, exit() in student code ...).
                rest = [n for n in order if n not in done]
                if not rest:
                    break
                current = rest[0]
            c = by_name[current]
            done.add(current)
            if reason == "timed_out":
                c.status = "timed_out"
                c.messages = [f"This case did not finish within {case_seconds:g} s: an endless loop?"]
                case_seconds = min(case_seconds, HUNG_AGAIN_SECONDS)
            elif reason == "flooded":
                c.status = "crashed"
                c.messages = [f"The code printed more than {OUTPUT_LIMIT >> 20} MiB and was stopped."]
            else:
                c.status = "crashed"
                if proc.returncode is not None and proc.returncode < 0:
                    try:
                        what = signal.Signals(-proc.returncode).name
                    except ValueError:
                        what = f"signal {-proc.returncode}"
                    c.messages = [f"The program died in this case ({what})."]
                else:
                    c.messages = [f"The program stopped in the middle of this case (exit status "
                                  f"{proc.returncode}): does the code call exit() or abort()?"]
        for c in cases:
            if c.name not in done and c.status == "not_run":
                c.messages = ["Not run: the step's time ran out."]


def grade_step(build: Build, step: Step, results: dict[str, StepResult]) -> StepResult:
    missing = [f for f in step.files if not (build.steps_dir / step.folder / f).is_file()]
    if missing:
        return StepResult(step, "missing", detail=f"{step.folder}/{missing[0]} is missing")
    for need in step.needs:
        dep = results.get(need)
        if dep is not None and dep.state != "done":
            return StepResult(step, "locked", detail=need)
    ok, out = build_target(build, step.target)
    if not ok:
        return StepResult(step, "no_compile", detail=out)
    exe = build.exe(step)
    try:
        cases = list_cases(exe)
    except (RuntimeError, subprocess.TimeoutExpired, OSError) as e:
        return StepResult(step, "broken", detail=f"the test program could not list its cases: {e}")
    run_cases(exe, cases)
    basic = [c for c in cases if c.tier == "basic"]
    if basic and all(c.status == "not_started" for c in cases):
        state = "not_started"
    elif all(c.status == "pass" for c in basic):
        state = "done"
    else:
        state = "partial"
    return StepResult(step, state, cases)


def grade(build: Build, steps: list[Step], all_steps: list[Step]) -> list[StepResult]:
    """Grades `steps`, and first the steps they need (quietly, to know whether they are done)."""
    configure(build)
    wanted = {s.number for s in steps}
    needed = {p.number for s in steps for p in prerequisites(s, all_steps)}
    results: dict[str, StepResult] = {}
    for s in all_steps:
        if s.number in wanted or s.number in needed:
            results[s.number] = grade_step(build, s, results)
    return [results[s.number] for s in steps]

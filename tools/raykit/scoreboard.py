"""What ./kit check and ./kit watch print: the table of steps, the failing case with its input,
expected and actual answer, the student's output, and what to do next."""

from __future__ import annotations

import os
import re
import sys
import threading
import time
from pathlib import Path

from . import faults
from . import includes
from .cases import StepResult
from .checking import Progress
from .course import hidden_note, score_line as course_score_line
from .common import ROOT, Step, paint, say
from .robust_line import robust_line
from .runcases import speed_note
from .sandbox import NONE_OWN
from .status import NOT_GRADED, DONE, MISSING, NOT_STARTED, NO_COMPILE, PARTIAL, PASS, STATUS_WORDS, WAITING


def rel(path: Path) -> str:
    try:
        return os.path.relpath(path, Path.cwd()) if Path.cwd() in path.parents or Path.cwd() == path \
            else str(path.relative_to(ROOT))
    except ValueError:
        return str(path)


def status_cell(r: StepResult) -> tuple[str, str]:
    basic, robust = r.tier("basic"), r.tier("robust")
    # NOT_GRADED (the default): the grader's fault, no verdict; yellow, not a student's red
    text, style, mark = {DONE: (f"done  {r.passed('basic')}/{len(basic)}", "green", "✓"),
                         NOT_STARTED: ("not started", "dim", "·"),
                         PARTIAL: (f"{r.passed('basic')} of {len(basic)} cases", "red", "✗"),
                         NO_COMPILE: ("does not compile", "red", "✗"), MISSING: ("file missing", "red", "✗"),
                         WAITING: (f"needs step {r.detail} first", "yellow", "…")
                         }.get(r.state, (f"not graded: {r.reason}"[:120], "yellow", "!"))
    extra = ""
    hidden = r.tier("hidden")
    if hidden and r.state in (DONE, PARTIAL):
        extra += f"  hidden {r.passed('hidden')} of {len(hidden)}"
    if robust and r.state in (DONE, PARTIAL):
        extra += f"  ★ robust {r.passed('robust')} of {len(robust)}"
    waiting = sum(c.status == NOT_STARTED for c in basic)
    if r.state == PARTIAL and waiting:
        extra += f"  ({waiting} not started yet)"
    incidents = r.incidents()
    if incidents and r.state not in (NOT_STARTED, NOT_GRADED):
        kinds = sorted({STATUS_WORDS[c.status] for c in incidents})
        extra += "  (" + ", ".join(f"{k} in {sum(STATUS_WORDS[c.status] == k for c in incidents)} case(s)"
                                   for k in kinds) + ")"
    if r.state == DONE:     # measured by the kit, never graded (runcases.speed_note)
        slow = speed_note(r.cost)
        extra += f"  ({slow})" if slow else ""
    again = [c for c in r.cases if c.runs > 1]
    if again:   # counts only: the first runs' words may hold a hidden case's inputs
        kept = sum(c.status == PASS for c in again)
        extra += f"  ({len(again)} case(s) timed out and were run again, {kept} then passed)"
    return paint(f"{mark} {text}", style), extra


OUTPUT_LINES = 12


def case_block(step: Step, case, indent: str = "  ", reveal: bool = True, drawing: bool = False) -> list[str]:
    """A failing case: its name, messages, output, picture and lecture section; with `drawing`, the
    picture in characters too (picture.sketch), for a terminal with no picture viewer."""
    star = "★ " if case.tier == "robust" else ""
    lines = [f"{indent}{paint('✗', 'red')} {star}{paint(case.name, 'bold')}  [{STATUS_WORDS.get(case.status, case.status)}]"]
    messages = case.messages if reveal or case.tier != "hidden" else [hidden_note()]
    lines += [f"{indent}    {line}" for m in messages[:3] for line in m.rstrip().splitlines()]
    if case.output_bytes and (reveal or case.tier != "hidden"):
        shown = case.output.splitlines()[:OUTPUT_LINES]
        lines.append(f"{indent}    your code printed ({case.output_bytes} bytes"
                     + (", the first lines" if len(shown) < len(case.output.splitlines()) or
                        len(case.output.encode()) < case.output_bytes else "") + "):")
        lines += [f"{indent}      | {l[:200]}" for l in shown]
    if case.picture and (reveal or case.tier != "hidden"):
        # The picture draws the first failing call: say so when the text lists more than one.
        which = " of the first call above" if sum(1 for m in case.messages if m.strip()) > 1 else ""
        lines.append(f"{indent}    picture{which}: {rel(Path(case.picture))}")
        if drawing and getattr(case, "sketch", None):
            lines += [indent + line for line in case.sketch]
    elif case.picture_summary:      # a figure that could not be drawn: say why
        lines.append(f"{indent}    picture: none, {case.picture_summary.replace('no picture: ', '')}")
    if case.lecture:
        lines.append(f"{indent}    read      {step.lecture}, section \"{case.lecture}\"")
    return lines


def compile_errors(text: str, limit: int = 12) -> list[str]:
    undefined = sorted({m.group(1) for m in re.finditer(r"undefined reference to [`'‘]([^'’]+)['’]", text)})
    if undefined:
        # The linker names the function, not the file: say which step function is missing.
        out = ["The linker found no definition of:"] + [f"  {u}" for u in undefined[:limit]]
        out.append("Each of these must be defined in the step's file with exactly this name and these "
                   "parameter types (a typo, a missing raykit:: namespace or a changed signature?).")
        return out
    lines = [l for l in text.splitlines() if "error" in l.lower() or l.startswith("  ") and "^" in l]
    # The compiler's and the assembler's errors, what the sandbox says of a stopped compile, and a
    # standard header the file uses without including it (includes.py), which comes first.
    errors = [l for l in text.splitlines() if "error:" in l.lower() or l.startswith("raykit: ")
              or includes.MARK in l]
    return (errors or lines or text.splitlines()[-limit:])[:limit]


def function_of(case) -> str:
    """The step function a failed case called, from its message's first line (`name(...)`)."""
    calls = (re.match(r"\s*(?:Your code \w+ (?:in|an exception in) )?([a-z_]+)\(", m) for m in case.messages)
    return next((hit.group(1) for hit in calls if hit), "other checks")


def all_failures(r: StepResult, reveal: bool) -> list[str]:
    """Every failing case of a step (./kit check N --all): the basic and hidden cases first, then the
    optional ★ robust ones under a heading of their own, each marked ★; grouped by the function called."""
    out = []
    for tiers, heading in ((("basic", "hidden"), ""), (("robust",), "★ robust cases (optional)")):
        groups: dict[str, list] = {}
        for c in r.cases:
            if c.status != PASS and c.tier in tiers:
                groups.setdefault(function_of(c), []).append(c)
        if groups and heading:
            out.append(paint(f"  {heading}", "bold"))
        for name, cases in groups.items():
            out.append(paint(f"  {name}: {len(cases)} failing {'★ ' if heading else ''}case(s)", "bold"))
            for c in cases:
                out += case_block(r.step, c, "    ", reveal=reveal)
    return out


def next_steps(results: list[StepResult], shown: Path, watching: bool = False) -> list[str]:
    out: list[str] = []
    todo = next((r for r in results if r.state != DONE), None)
    if todo is None:
        robust = [r for r in results if r.passed("robust") < len(r.tier("robust"))]
        if robust:
            # Optional cases of a done step: one calm line each, the cases only on request (--all).
            out.append(paint("Every step you asked for is done.", "green"))
            out += [f"  step {r.step.number}: {robust_line(r)}" for r in robust]
            out.append(paint(f"  ./kit check {int(robust[0].step.number)} --all shows these cases", "dim"))
        else:
            out.append(paint("Every step you asked for is done, robust cases included. Well done.", "green"))
        return out
    s = todo.step
    out.append(paint(f"Next: step {s.number}, {s.title}", "bold"))
    out += [f"  edit      {rel(shown / s.folder / f)}" for f in s.files]
    out += [f"  task      {rel(ROOT / 'steps' / s.folder / 'README.md')}", f"  lecture   {s.lecture}", ""]
    if todo.state == NOT_STARTED:
        out.append(f"  Read the task, then replace each not_implemented_yet(...) line in "
                   f"{s.files[0]} with your code.")
    elif todo.state == NO_COMPILE:
        out.append("  The compiler stopped here:")
        out += [f"    {l}" for l in compile_errors(todo.detail)]
    elif todo.state == MISSING:
        out.append(f"  {todo.detail}: put the file back (the kit's steps/ folder has the original stub).")
    elif todo.state == WAITING:
        out.append(f"  Step {s.number} uses your step {todo.detail}: finish that one first.")
    elif todo.state == NOT_GRADED:
        out += [f"  {faults.to_student(todo.reason, 'check again; if it stays so, tell your instructor')}",
                f"  {todo.detail.splitlines()[0] if todo.detail else ''}".rstrip()]
    else:
        c = todo.first_problem("basic") or todo.first_problem("hidden")
        if c is not None:
            out += case_block(s, c, reveal=False, drawing=True)
    if not watching:   # ./kit watch re-checks by itself at every save
        # A step waiting for another: the other one is what to check next, not this one again.
        then = todo.detail.split(",")[0] if todo.state == WAITING and todo.detail else s.number
        out += ["", f"  Then run: ./kit check {int(then)}"]
    return out


def header(shown: Path) -> str:
    return paint(f"raykit · checking {rel(shown)}/", "bold")


def title_width(steps: list[Step]) -> int:
    return max(len(s.title) for s in steps)


def row(r: StepResult, width: int) -> str:
    cell, extra = status_cell(r)
    return f"  {r.step.number}  {r.step.title.ljust(width)}  {cell}{extra}"


class LiveProgress(Progress):
    """The scoreboard's table, printed a row at a time as each step is checked, with what is being
    done meanwhile on one line below it: on a terminal the line is rewritten in place; into a file or
    a pipe, plain lines (no cursor movement), one per phase and one per step built, repeated at most
    every PLAIN_EVERY seconds while a build goes on."""

    PLAIN_EVERY = 10.0

    def __init__(self, shown: Path, steps: list[Step]):
        self.width = title_width(steps)
        self.tty = sys.stdout.isatty()
        self.start = time.monotonic()
        self.lock = threading.Lock()
        self.status = ""
        self.plain_last = ("", -1e9)     # the last plain line's kind and its time
        say(header(shown))
        say()

    def _draw(self, text: str, kind: str = "") -> None:
        if self.tty:
            self.status = text
            sys.stdout.write("\r\033[K" + paint(text, "dim"))
            sys.stdout.flush()
            return
        kind = kind or text
        now = time.monotonic()
        if kind != self.plain_last[0] or now - self.plain_last[1] >= self.PLAIN_EVERY:
            self.plain_last = (kind, now)
            say(text)

    def phase(self, text: str) -> None:
        with self.lock:
            self._draw(f"  {text} ...")

    def building(self, step: Step, done: int, total: int) -> None:
        with self.lock:
            self._draw(f"  {step.number}  compiling your code  [{done}/{total}]"
                       f"  {time.monotonic() - self.start:.0f} s", kind=f"build {step.number}")

    def result(self, result: StepResult) -> None:
        with self.lock:
            if self.tty:
                sys.stdout.write("\r\033[K")
            say(row(result, self.width))
            if self.tty and self.status:
                sys.stdout.write(paint(self.status, "dim"))
                sys.stdout.flush()

    def close(self) -> None:
        with self.lock:
            if self.tty:
                sys.stdout.write("\r\033[K")
                sys.stdout.flush()
            self.status = ""


def scoreboard(results: list[StepResult], shown: Path, every_failure: bool = False, reveal: bool = False,
               watching: bool = False, table_shown: bool = False) -> None:
    """Prints the scoreboard: the table of steps (unless LiveProgress has printed it already), the
    score, every failing case when asked, and what to do next."""
    if not table_shown:
        say(header(shown))
        say()
        width = title_width([r.step for r in results])
        for r in results:
            say(row(r, width))
    say()
    say(course_score_line(results))     # raykit/course.py: the course's scale, or a handout's visible part
    for r in results:   # compiled here, but maybe not on the grader's standard library: said before it is
        if r.state != NO_COMPILE:
            for line in r.includes:
                say(paint(f"  ! {line}", "yellow"))
    seeds = sorted({r.seed for r in results if r.seed})
    if seeds:
        say(paint(f"  hidden cases drawn with seed {', '.join(seeds)}", "dim"))
    isolation = next((r.isolation for r in results if r.isolation), "")
    if isolation and isolation != NONE_OWN.description:
        say(paint(f"  {isolation}", "yellow" if "NOT" in isolation else "dim"))
    say()
    if every_failure:
        for r in results:
            if any(c.status != PASS for c in r.cases):
                say(paint(f"Step {r.step.number}, {r.step.title}: every failing case", "bold"))
                for line in all_failures(r, reveal):
                    say(line)
                say()
    for line in next_steps(results, shown, watching):
        say(line)
    if watching:
        return
    done = sum(r.state == DONE for r in results)
    say()
    say(paint(f"{done} of {len(results)} steps done.", "bold"))

"""./kit check: grade the student's steps and print the scoreboard."""

from __future__ import annotations

import argparse
import json
import re
import os
import time
from pathlib import Path

import picture
from common import BUILD, ROOT, Build, KitError, Step, ensure_packages, load_steps, paint, preset_build, \
    resolve_steps_dir, say, select_steps, submission_build
from grade import StepResult, grade
from sandbox import NONE_OWN, choose

# The words for a step's state and a case's status: the same in the terminal, the
# CSV of ./kit grade and the Gradescope JSON.
STATE_WORDS = {
    "done": "done", "partial": "some cases fail", "not_started": "not started", "missing": "a file is missing",
    "no_compile": "does not compile", "waiting": "waits for an earlier step", "broken": "could not be graded",
}

STATUS_WORDS = {
    "pass": "passed", "fail": "wrong answer", "not_started": "not started", "threw": "threw an exception",
    "crashed": "crashed", "timed_out": "timed out", "not_run": "not run", "no_compile": "does not compile",
    "missing": "file missing", "waiting": "waits for an earlier step",
}

HIDDEN_NOTE = ("a hidden case: random inputs of this family, drawn from the seed above; "
               "its inputs are shown after the due date")


def rel(path: Path) -> str:
    try:
        return os.path.relpath(path, Path.cwd()) if Path.cwd() in path.parents or Path.cwd() == path \
            else str(path.relative_to(ROOT))
    except ValueError:
        return str(path)


def status_cell(r: StepResult) -> tuple[str, str]:
    basic, robust = r.tier("basic"), r.tier("robust")
    if r.state == "done":
        text, style = f"done  {r.passed('basic')}/{len(basic)}", "green"
        mark = "✓"
    elif r.state == "not_started":
        text, style, mark = "not started", "dim", "·"
    elif r.state == "partial":
        text, style, mark = f"{r.passed('basic')} of {len(basic)} cases", "red", "✗"
    elif r.state == "no_compile":
        text, style, mark = "does not compile", "red", "✗"
    elif r.state == "missing":
        text, style, mark = "file missing", "red", "✗"
    elif r.state == "waiting":
        text, style, mark = f"needs step {r.detail} first", "yellow", "…"
    else:
        text, style, mark = "could not be graded", "red", "✗"
    extra = ""
    hidden = r.tier("hidden")
    if hidden and r.state in ("done", "partial"):
        extra += f"  hidden {r.passed('hidden')} of {len(hidden)}"
    if robust and r.state in ("done", "partial"):
        extra += f"  ★ robust {r.passed('robust')} of {len(robust)}"
    waiting = sum(c.status == "not_started" for c in r.tier("basic"))
    if r.state == "partial" and waiting:
        extra += f"  ({waiting} not started yet)"
    incidents = r.incidents()
    if incidents and r.state != "not_started":
        kinds = sorted({STATUS_WORDS[c.status] for c in incidents})
        extra += "  (" + ", ".join(f"{k} in {sum(STATUS_WORDS[c.status] == k for c in incidents)} case(s)"
                                   for k in kinds) + ")"
    return paint(f"{mark} {text}", style), extra


OUTPUT_LINES = 12


def case_block(step: Step, case, indent: str = "  ", reveal: bool = True) -> list[str]:
    lines = [f"{indent}{paint('✗', 'red')} {paint(case.name, 'bold')}  [{STATUS_WORDS.get(case.status, case.status)}]"]
    messages = case.messages if reveal or case.tier != "hidden" else [HIDDEN_NOTE]
    for m in messages[:3]:
        for line in m.rstrip().splitlines():
            lines.append(f"{indent}    {line}")
    if case.output_bytes and (reveal or case.tier != "hidden"):
        shown = case.output.splitlines()[:OUTPUT_LINES]
        lines.append(f"{indent}    your code printed ({case.output_bytes} bytes"
                     + (", the first lines" if len(shown) < len(case.output.splitlines()) or
                        len(case.output.encode()) < case.output_bytes else "") + "):")
        lines += [f"{indent}      | {l[:200]}" for l in shown]
    if case.picture and (reveal or case.tier != "hidden"):
        lines.append(f"{indent}    picture: {rel(Path(case.picture))}")
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
    lines = [l for l in text.splitlines() if "error" in l or l.startswith("  ") and "^" in l]
    errors = [l for l in text.splitlines() if "error:" in l]
    return (errors or lines or text.splitlines()[-limit:])[:limit]


def function_of(case) -> str:
    """The step function a failed case called, from its message's first line (`name(...)`)."""
    for m in case.messages:
        hit = re.match(r"\s*(?:Your code \w+ (?:in|an exception in) )?([a-z_]+)\(", m)
        if hit:
            return hit.group(1)
    return "other checks"


def all_failures(r: StepResult, reveal: bool) -> list[str]:
    """Every failing case of a step, grouped by the function it called (./kit check N --all)."""
    groups: dict[str, list] = {}
    for c in r.cases:
        if c.status != "pass":
            groups.setdefault(function_of(c), []).append(c)
    out = []
    for name, cases in groups.items():
        out.append(paint(f"  {name}: {len(cases)} failing case(s)", "bold"))
        for c in cases:
            out += case_block(r.step, c, "    ", reveal=reveal)
    return out


def next_steps(results: list[StepResult], shown: Path) -> list[str]:
    out: list[str] = []
    todo = next((r for r in results if r.state != "done"), None)
    if todo is None:
        robust = [r for r in results if r.passed("robust") < len(r.tier("robust"))]
        if robust:
            r = robust[0]
            out.append(paint("Every step you asked for is done.", "green") +
                       f" Optional: the ★ robust cases of step {r.step.number}:")
            c = r.first_problem("robust")
            out += case_block(r.step, c)
        else:
            out.append(paint("Every step you asked for is done, robust cases included. Well done.", "green"))
        return out
    s = todo.step
    out.append(paint(f"Next: step {s.number}, {s.title}", "bold"))
    for f in s.files:
        out.append(f"  edit      {rel(shown / s.folder / f)}")
    out.append(f"  task      {rel(ROOT / 'steps' / s.folder / 'README.md')}")
    out.append(f"  lecture   {s.lecture}")
    out.append("")
    if todo.state == "not_started":
        out.append(f"  Read the task, then replace each not_implemented_yet(...) line in "
                   f"{s.files[0]} with your code.")
    elif todo.state == "no_compile":
        out.append("  The compiler stopped here:")
        out += [f"    {l}" for l in compile_errors(todo.detail)]
    elif todo.state == "missing":
        out.append(f"  {todo.detail}: put the file back (the kit's steps/ folder has the original stub).")
    elif todo.state == "waiting":
        out.append(f"  Step {s.number} uses your step {todo.detail}: finish that one first.")
    elif todo.state == "broken":
        out.append(f"  {todo.detail}")
    else:
        c = todo.first_problem("basic") or todo.first_problem("hidden")
        if c is not None:
            out += case_block(s, c, reveal=False)
    out.append("")
    out.append(f"  Then run: ./kit check {int(s.number)}")
    return out


def scoreboard(results: list[StepResult], shown: Path, every_failure: bool = False, reveal: bool = False) -> None:
    say(paint(f"raykit · grading {rel(shown)}/", "bold"))
    say()
    width = max(len(r.step.title) for r in results)
    for r in results:
        cell, extra = status_cell(r)
        say(f"  {r.step.number}  {r.step.title.ljust(width)}  {cell}{extra}")
    earned, maximum = sum(r.earned for r in results), sum(r.maximum for r in results)
    say()
    say(f"  score {earned} of {maximum}" + (f" ({100 * earned / maximum:.0f} %)" if maximum else ""))
    seeds = sorted({r.seed for r in results if r.seed})
    if seeds:
        say(paint(f"  hidden cases drawn with seed {', '.join(seeds)}", "dim"))
    isolation = next((r.isolation for r in results if r.isolation), "")
    if isolation and isolation != NONE_OWN.description:
        say(paint(f"  {isolation}", "yellow" if "NOT" in isolation else "dim"))
    say()
    if every_failure:
        for r in results:
            if any(c.status != "pass" for c in r.cases):
                say(paint(f"Step {r.step.number}, {r.step.title}: every failing case", "bold"))
                for line in all_failures(r, reveal):
                    say(line)
                say()
    for line in next_steps(results, shown):
        say(line)
    done = sum(r.state == "done" for r in results)
    say()
    say(paint(f"{done} of {len(results)} steps done.", "bold"))


HELP = "grade your steps and show what to do next"


def register(p) -> None:
    p.add_argument("numbers", nargs="*", metavar="N", help="step numbers (default: all)")
    p.add_argument("--steps", metavar="DIR", help="grade the steps in DIR instead of steps/ (DIR is not modified)")
    p.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    p.add_argument("--quiet", action="store_true", help="print nothing; the exit status tells")
    p.add_argument("--isolation", choices=["auto", "bwrap", "user", "none"],
                   help="how the graded code is kept apart (default: auto with --steps, none for your own steps/)")
    p.add_argument("--hidden-visibility", default="after_due_date",
                   choices=["hidden", "after_due_date", "after_published", "visible"],
                   help="Gradescope visibility of the hidden cases in --json (default: after_due_date)")
    p.add_argument("--reveal", action="store_true", help="show the inputs of failed hidden cases (instructors)")
    p.add_argument("--all", action="store_true", help="list every failing case of the steps, grouped by function")
    p.add_argument("--slot", type=int, default=0, help=argparse.SUPPRESS)  # ./kit grade -j: build folder and sandbox


def run(args) -> int:
    ensure_packages("build")
    all_steps = load_steps()
    steps = select_steps(all_steps, args.numbers)
    if args.steps:
        source = resolve_steps_dir(args.steps)
        build = submission_build(source, "submission" if args.slot == 0 else f"submission-{args.slot}")
    else:
        build = preset_build("student")
        source = build.steps_dir
    wanted = args.isolation or ("auto" if args.steps else "none")
    try:
        isolation = NONE_OWN if wanted == "none" and not args.steps else choose(wanted, args.slot)
    except RuntimeError as e:
        raise KitError(f"--isolation {wanted}: {e}")
    if args.json:  # fail early on a path we cannot write, before any building
        write_json(args.json, [], 0.0, args.hidden_visibility, args.reveal)
    start = time.monotonic()
    results = grade(build, steps, all_steps, isolation)
    if not args.quiet:      # a picture per failing sphere or rectangle case (not for class grading)
        picture.draw_results(results, BUILD / ("pictures" if args.slot == 0 else f"pictures-{args.slot}"),
                             args.reveal)
    if args.json:
        write_json(args.json, results, time.monotonic() - start, args.hidden_visibility, args.reveal)
    if not args.quiet:
        scoreboard(results, source, args.all, args.reveal)
    return 0 if all(r.state == "done" for r in results) else 1


def gradescope(results: list[StepResult], elapsed: float, hidden_visibility: str = "after_due_date",
               reveal: bool = False) -> dict:
    """The results in Gradescope's autograder format (results.json).

    One test per case, on one scale: every basic and hidden case is worth one point,
    whatever state its step is in (a step that does not compile fails all its cases,
    with the compiler's first error); a ★ robust case has max_score 0 (optional).
    """
    tests = []
    for r in results:
        s = r.step
        for i, c in enumerate(r.cases, 1):
            hidden = c.tier == "hidden"
            lines = [STATUS_WORDS.get(c.status, c.status)]
            if c.status != "pass":
                lines += [HIDDEN_NOTE] if hidden and not reveal else c.messages[:3]
                if c.output_bytes and not (hidden and not reveal):
                    lines.append(f"Your code printed ({c.output_bytes} bytes):\n{c.output[:2000]}")
                if c.lecture:
                    lines.append(f"Read {s.lecture}, section \"{c.lecture}\".")
            mark = {"robust": " ★", "hidden": " (hidden)"}.get(c.tier, "")
            tests.append({
                "name": f"Step {s.number}{mark} · {c.name}",
                "number": f"{int(s.number)}.{i}",
                "score": c.points * int(c.status == "pass"),
                "max_score": c.points,
                "status": "passed" if c.status == "pass" else "failed",
                "visibility": hidden_visibility if hidden else "visible",
                "output": "\n".join(lines),
                "tags": [f"step{s.number}", c.tier],
            })
        if not r.cases:  # the kit's own test program failed: say so, worth nothing
            tests.append({"name": f"Step {s.number} · {s.title}", "number": s.number, "score": 0,
                          "max_score": 0, "status": "failed", "visibility": "visible",
                          "output": f"{STATE_WORDS[r.state]}. {r.detail[:4000]}".strip(),
                          "tags": [f"step{s.number}"]})
    score = sum(t["score"] for t in tests)
    maximum = sum(t["max_score"] for t in tests)
    summary = [f"step {r.step.number}: {STATE_WORDS[r.state]}, {r.earned} of {r.maximum}" for r in results]
    seeds = sorted({r.seed for r in results if r.seed})
    if seeds:
        summary.append(f"hidden cases seed {', '.join(seeds)}")
    isolation = next((r.isolation for r in results if r.isolation), "")
    if isolation:
        summary.append(f"graded code: {isolation}")
    return {"score": score, "execution_time": round(elapsed, 3), "output": "\n".join(summary),
            "visibility": "visible", "stdout_visibility": "hidden", "tests": tests,
            "extra_data": {"max_score": maximum, "steps": [r.to_json() for r in results]}}


def write_json(path: str, results: list[StepResult], elapsed: float, hidden_visibility: str = "after_due_date",
               reveal: bool = False) -> None:
    target = Path(path)
    if not target.parent.is_dir():
        raise KitError(f"--json {path}: folder {target.parent} does not exist")
    if target.is_dir():
        raise KitError(f"--json {path}: is a folder, not a file")
    tmp = target.with_name(f".{target.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(json.dumps(gradescope(results, elapsed, hidden_visibility, reveal), indent=2,
                                  ensure_ascii=False))
        tmp.replace(target)
    except OSError as e:
        tmp.unlink(missing_ok=True)
        raise KitError(f"--json {path}: cannot write it ({e.strerror})")

"""./kit check: grade the student's steps and print the scoreboard."""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

from common import ROOT, Build, KitError, Step, ensure_packages, load_steps, paint, preset_build, \
    resolve_steps_dir, say, select_steps, submission_build
from grade import StepResult, grade

STATE_WORDS = {
    "done": "done", "partial": "some cases fail", "not_started": "not started", "missing": "a file is missing",
    "no_compile": "does not compile", "locked": "waits for an earlier step", "broken": "could not be graded",
}

STATUS_WORDS = {
    "fail": "wrong answer", "not_started": "not started", "threw": "threw an exception",
    "crashed": "crashed", "timed_out": "timed out", "not_run": "not run",
}


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
    elif r.state == "locked":
        text, style, mark = f"needs step {r.detail} first", "yellow", "…"
    else:
        text, style, mark = "could not be graded", "red", "✗"
    extra = ""
    if robust and r.state in ("done", "partial"):
        extra = f"  ★ robust {r.passed('robust')} of {len(robust)}"
    waiting = sum(c.status == "not_started" for c in r.tier("basic"))
    if r.state == "partial" and waiting:
        extra += f"  ({waiting} not started yet)"
    incidents = r.incidents()
    if incidents and r.state != "not_started":
        kinds = sorted({STATUS_WORDS[c.status] for c in incidents})
        extra += "  (" + ", ".join(f"{k} in {sum(STATUS_WORDS[c.status] == k for c in incidents)} case(s)"
                                   for k in kinds) + ")"
    return paint(f"{mark} {text}", style), extra


def case_block(step: Step, case, indent: str = "  ") -> list[str]:
    lines = [f"{indent}{paint('✗', 'red')} {paint(case.name, 'bold')}  [{STATUS_WORDS.get(case.status, case.status)}]"]
    for m in case.messages[:3]:
        for line in m.rstrip().splitlines():
            lines.append(f"{indent}    {line}")
    if case.lecture:
        lines.append(f"{indent}    read      {step.lecture}, section \"{case.lecture}\"")
    return lines


def compile_errors(text: str, limit: int = 12) -> list[str]:
    lines = [l for l in text.splitlines() if "error" in l or l.startswith("  ") and "^" in l]
    errors = [l for l in text.splitlines() if "error:" in l]
    return (errors or lines or text.splitlines()[-limit:])[:limit]


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
    elif todo.state == "locked":
        out.append(f"  Step {s.number} uses your step {todo.detail}: finish that one first.")
    elif todo.state == "broken":
        out.append(f"  {todo.detail}")
    else:
        c = todo.first_problem("basic")
        if c is not None:
            out += case_block(s, c)
    out.append("")
    out.append(f"  Then run: ./kit check {int(s.number)}")
    return out


def scoreboard(results: list[StepResult], shown: Path) -> None:
    say(paint(f"raykit · grading {rel(shown)}/", "bold"))
    say()
    width = max(len(r.step.title) for r in results)
    for r in results:
        cell, extra = status_cell(r)
        say(f"  {r.step.number}  {r.step.title.ljust(width)}  {cell}{extra}")
    say()
    for line in next_steps(results, shown):
        say(line)


HELP = "grade your steps and show what to do next"


def register(p) -> None:
    p.add_argument("numbers", nargs="*", metavar="N", help="step numbers (default: all)")
    p.add_argument("--steps", metavar="DIR", help="grade the steps in DIR instead of steps/ (DIR is not modified)")
    p.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    p.add_argument("--quiet", action="store_true", help="print nothing; the exit status tells")


def run(args) -> int:
    ensure_packages("build")
    all_steps = load_steps()
    steps = select_steps(all_steps, args.numbers)
    if args.steps:
        source = resolve_steps_dir(args.steps)
        build = submission_build(source)
    else:
        build = preset_build("student")
        source = build.steps_dir
    if args.json:  # fail early on a path we cannot write, before any building
        write_json(args.json, [], 0.0)
    start = time.monotonic()
    results = grade(build, steps, all_steps)
    if args.json:
        write_json(args.json, results, time.monotonic() - start)
    if not args.quiet:
        scoreboard(results, source)
    return 0 if all(r.state == "done" for r in results) else 1


def gradescope(results: list[StepResult], elapsed: float) -> dict:
    """The results in Gradescope's autograder format (results.json).

    One test per case. A basic case is worth one point; a ★ robust case is shown with
    max_score 0 (optional, never lowers the score). The kit's own per-step view is kept
    under extra_data for tools that want more than points.
    """
    tests = []
    for r in results:
        s = r.step
        if not r.cases:  # not compiled, missing file, locked: one line for the whole step
            tests.append({"name": f"Step {s.number} · {s.title}", "number": s.number, "score": 0,
                          "max_score": 0, "status": "failed", "visibility": "visible",
                          "output": f"{STATE_WORDS[r.state]}. {r.detail[:4000]}".strip(),
                          "tags": [f"step{s.number}"]})
            continue
        for i, c in enumerate(r.cases, 1):
            robust = c.tier == "robust"
            lines = [f"{STATUS_WORDS.get(c.status, c.status)}"] if c.status != "pass" else ["passed"]
            lines += c.messages[:3]
            if c.status != "pass" and c.lecture:
                lines.append(f"Read {s.lecture}, section \"{c.lecture}\".")
            tests.append({
                "name": f"Step {s.number}{' ★' if robust else ''} · {c.name}",
                "number": f"{int(s.number)}.{i}",
                "score": 0 if robust else int(c.status == "pass"),
                "max_score": 0 if robust else 1,
                "status": "passed" if c.status == "pass" else "failed",
                "visibility": "visible",
                "output": "\n".join(lines),
                "tags": [f"step{s.number}", c.tier],
            })
    score = sum(t["score"] for t in tests)
    summary = "; ".join(f"step {r.step.number}: {STATE_WORDS[r.state]}" for r in results)
    return {"score": score, "execution_time": round(elapsed, 3), "output": summary,
            "visibility": "visible", "stdout_visibility": "hidden", "tests": tests,
            "extra_data": {"steps": [r.to_json() for r in results]}}


def write_json(path: str, results: list[StepResult], elapsed: float) -> None:
    target = Path(path)
    if not target.parent.is_dir():
        raise KitError(f"--json {path}: folder {target.parent} does not exist")
    if target.is_dir():
        raise KitError(f"--json {path}: is a folder, not a file")
    tmp = target.with_name(f".{target.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(json.dumps(gradescope(results, elapsed), indent=2, ensure_ascii=False))
        tmp.replace(target)
    except OSError as e:
        tmp.unlink(missing_ok=True)
        raise KitError(f"--json {path}: cannot write it ({e.strerror})")

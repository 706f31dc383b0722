"""The results of ./kit check in Gradescope's autograder format (results.json), for --json."""

from __future__ import annotations

import json
import os
from pathlib import Path

from .checking import StepResult
from .common import KitError
from .scoreboard import HIDDEN_NOTE
from .status import PASS, STATE_WORDS, STATUS_WORDS


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
            if c.status != PASS:
                lines += [HIDDEN_NOTE] if hidden and not reveal else c.messages[:3]
                if c.output_bytes and not (hidden and not reveal):
                    lines.append(f"Your code printed ({c.output_bytes} bytes):\n{c.output[:2000]}")
                if c.lecture:
                    lines.append(f"Read {s.lecture}, section \"{c.lecture}\".")
            mark = {"robust": " ★", "hidden": " (hidden)"}.get(c.tier, "")
            tests.append({
                "name": f"Step {s.number}{mark} · {c.name}",
                "number": f"{int(s.number)}.{i}",
                "score": c.points * int(c.status == PASS),
                "max_score": c.points,
                "status": "passed" if c.status == PASS else "failed",
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

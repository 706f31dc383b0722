"""Self-test: every mutant (a full answer with one realistic slip) is caught by the basic tier.

Each mutant goes through the path a student's work takes: `./kit check N --steps DIR`, where DIR
holds the mutant's files for its step and the reference files for the steps it needs.
"""

from __future__ import annotations

import json
import shutil
from collections import defaultdict

from common import BUILD, ROOT, load_steps, stage_on_reference

MUTANTS = ROOT / "tests" / "mutants"
MINIMUM_PER_STEP = 8


def check_mutants(ctx) -> str:
    from cmd_test import Failed, kit, need_solutions

    need_solutions()

    steps = load_steps()
    scores: dict[str, list[int]] = defaultdict(lambda: [0, 0])
    escaped = []
    work = BUILD / "mutant-steps"
    for step in steps:
        folder = MUTANTS / step.folder
        mutants = sorted(p for p in folder.iterdir() if p.is_dir()) if folder.is_dir() else []
        if len(mutants) < MINIMUM_PER_STEP:
            raise Failed(f"step {step.number} has {len(mutants)} mutants in tests/mutants/{step.folder}/, "
                         f"at least {MINIMUM_PER_STEP} are needed")
        for mutant in mutants:
            # A mutant folder holds the files its slip is in; the step's other files are the
            # reference ones, so the whole is a complete answer with one mistake.
            stage_on_reference(work, step, steps, mutant)
            report = BUILD / "mutant.json"
            r = kit("check", str(int(step.number)), "--steps", str(work), "--json", str(report), "--quiet")
            result = json.loads(report.read_text())["extra_data"]["steps"][0] if report.exists() else None
            report.unlink(missing_ok=True)
            scores[step.number][1] += 1
            if r.returncode == 1 and result and result["state"] not in ("done", "not_started"):
                scores[step.number][0] += 1
            else:
                state = result["state"] if result else f"exit {r.returncode}"
                escaped.append(f"{step.folder}/{mutant.name} ({state})")
    shutil.rmtree(work, ignore_errors=True)
    summary = ", ".join(f"step {n}: {k}/{t}" for n, (k, t) in sorted(scores.items()))
    if escaped:
        raise Failed(f"mutation score {summary}; not caught: " + ", ".join(escaped))
    return f"mutation score {summary} (every mutant caught by the basic tier)"


def checks():
    return [("mutants are caught", check_mutants)]

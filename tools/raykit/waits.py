"""A step that needs another, in a student's handout (no reference code for the step it needs).

Without solutions/, step 05 runs on the student's own step 04. Its cases that call no step 04
function (the camera, the view rays) run anyway, whatever state step 04 is in; those that do wait
for the student's own step 04: a failure there is shown as "waits for your step 04's
intersect_rect", not as a wrong answer. No answer ships for this.

Which cases need the other step is said per lecture section, in the needing step's
tests/NN_topic/step.json:
    "runs_without": {"04": ["5. The camera", "6. A view ray per pixel"]}
the sections whose cases call no function of step 04. Every other section waits (a new section
waits until it is listed). A step with no "runs_without" entry for a step it needs waits whole,
as before.

Where the reference is present (a grading), nothing waits: step 05 runs on a stand-in for step 04
that the judge scripts from the reference's program (tests/support/standin.hpp), neither the
reference's code nor the student's own step 04, so one slip costs one step.
"""

from __future__ import annotations

import json

from .common import ROOT, Step, load_steps
from .status import DONE, PARTIAL, PASS, WAITING


def _manifest(step: Step) -> dict:
    try:
        data = json.loads((ROOT / "tests" / step.folder / "step.json").read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def runs_without(step: Step) -> dict[str, list[str]]:
    """The sections of `step` that call nothing of each step it needs."""
    found = _manifest(step).get("runs_without", {})
    return {k: list(v) for k, v in found.items()} if isinstance(found, dict) else {}


def pending(step: Step, results: dict) -> list[str]:
    """The steps `step` needs that have been checked and are not done."""
    return [n for n in step.needs if results.get(n) is not None and results[n].state != DONE]


def waits_whole(step: Step, results: dict) -> str:
    """The step `step` waits for as a whole (none of its cases can run without it), or ""."""
    free = runs_without(step)
    return next((n for n in pending(step, results) if n not in free), "")


def wait_on_needs(step: Step, cases: list, results: dict, state: str) -> str:
    """After the cases ran: each failed case of a section that needs a step not done yet waits for
    it. Returns the step's state: WAITING when only waiting cases are left, else `state`."""
    waits = pending(step, results)
    if not waits:
        return state
    free = runs_without(step)
    for c in cases:
        if c.status == PASS or c.tier == "hidden":
            continue
        need = next((n for n in waits if c.lecture not in free.get(n, [])), None)
        if need is not None:
            names = ", ".join(next((s.functions for s in load_steps() if s.number == need), [])) \
                or f"step {need}'s functions"
            c.status = WAITING
            c.messages = [f"waits for your step {need} ({names}): this case calls it, and step {need} is not "
                          f"done yet. The cases of {step.number} that call nothing of step {need} are checked now."]
    failing = [c for c in cases if c.status != PASS and c.tier != "robust"]
    if failing and all(c.status == WAITING for c in failing):
        return WAITING
    return state if state != DONE or not failing else PARTIAL

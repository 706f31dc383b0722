"""A submission's step matched against the slip catalogue (tests/mutants/, issue 45 item 2).

Each mutant is one realistic slip, and tests/mutants/signatures.json records which basic cases it
fails (./kit report --signatures). When a step's failing basic cases are exactly one slip's, that is a
measured cause: the case its patch names as catching it is the one shown first (StepResult.first_problem),
and the slip is said in the slip's own words above that case's. Only where the catalogue is (the
instructor's copy, the graders' images): a handout ships no mutant. The class report matches near
signatures too (report/signatures.py); a student is told only an exact match.
"""

from __future__ import annotations

import functools
import json

from .common import ROOT, Step
from .mutants import MUTANTS, PatchError, read_patch

SIGNATURES = MUTANTS / "signatures.json"


@functools.lru_cache(maxsize=1)
def _catalogue() -> dict:
    try:
        data = json.loads(SIGNATURES.read_text())
        found = data.get("mutants", {})
        return found if isinstance(found, dict) else {}
    except (OSError, ValueError):
        return {}


def known_slip(step: Step, failing_basic: set[str]) -> dict | None:
    """{"name", "slip", "case"} of the one slip of `step` whose recorded signature is exactly the
    failing basic cases given (and whose patch names a case among them), or None: no match, or
    several slips that fail alike (then no single cause is measured)."""
    if not failing_basic or not (ROOT / "solutions").is_dir():
        return None
    found = []
    for key, entry in _catalogue().items():
        folder, _, name = key.partition("/")
        if folder != step.folder or not isinstance(entry, dict) or set(entry.get("fails") or ()) != failing_basic:
            continue
        try:
            mutant = read_patch(MUTANTS / folder / f"{name}.patch", step)
        except (OSError, PatchError):
            continue
        case = next((c for c in mutant.cases if c in failing_basic), None)
        if case is not None:
            found.append({"name": name, "slip": mutant.slip, "case": case})
    return found[0] if len(found) == 1 else None

"""A submission's step matched against the slip catalogue (tests/mutants/, issue 45 item 2).

Each mutant is one realistic slip, and tests/mutants/signatures.json records which basic cases it
fails (./kit report --signatures). When a step's failing basic cases are exactly a slip's, that is
what is measured: the same failing set, not the same code. Another slip can fail the same cases
(`c = dot(o, o) + 1` fails what `c = dot(o, o)` fails), so the student is told the failing set as a
fact and the slip's words as its likely cause, never as a fact about their code: "Your code fails
exactly the cases a known slip fails; the likely cause: ...". The case its patch names as catching
it is the one shown first (StepResult.first_problem). Where several slips fail alike, each is said
as a possible cause, and a case they all name comes first (else the usual rule chooses). Only where
the catalogue is (the instructor's copy, the graders' images): a handout ships no mutant. The class
report matches near signatures too (report/signatures.py); a student is told only an exact failing set.

`PYTHONPATH=tools:tests python3 -m kit.slips RESULTS...` (from the kit) measures, on records of `./kit check
--results` kept per mutant, how many first messages name their own slip.
"""

from __future__ import annotations

import functools
import json
import os
import re

from .common import ROOT, Step
from .mutants import MUTANTS, PatchError, read_patch
from .status import NO_ANSWER, PASS

SIGNATURES = MUTANTS / "signatures.json"
# Set (to anything), the catalogue is not read: a self-test measures the first message code the kit
# never saw would get, from the cases alone.
NO_CATALOGUE = "RAYKIT_NO_SLIP_CATALOGUE"
MOST_SAID = 3       # slips that fail alike: at most this many are said


@functools.lru_cache(maxsize=1)
def _catalogue() -> dict:
    try:
        data = json.loads(SIGNATURES.read_text())
        found = data.get("mutants", {})
        return found if isinstance(found, dict) else {}
    except (OSError, ValueError):
        return {}


def alike_slips(step: Step, failing_basic: set[str]) -> list[dict]:
    """{"name", "slip", "cases"} of every slip of `step` whose recorded signature is exactly the
    failing basic cases given and whose patch names a case among them, in the catalogue's order."""
    if not failing_basic or not (ROOT / "solutions").is_dir() or os.environ.get(NO_CATALOGUE):
        return []
    found = []
    for key, entry in sorted(_catalogue().items()):
        folder, _, name = key.partition("/")
        if folder != step.folder or not isinstance(entry, dict) or set(entry.get("fails") or ()) != failing_basic:
            continue
        try:
            mutant = read_patch(MUTANTS / folder / f"{name}.patch", step)
        except (OSError, PatchError):
            continue
        cases = [c for c in mutant.cases if c in failing_basic]
        if cases:
            found.append({"name": name, "slip": mutant.slip, "cases": cases})
    return found


def known_slip(step: Step, failing_basic: set[str]) -> dict | None:
    """What the catalogue says of these failing basic cases, or None when no slip fails exactly them:
    {"name", "slip", "case", "cases", "alike"}. With one slip: its name, words and first named case.
    With several: "name" and "slip" are the first one's, "alike" lists every one ({"name", "slip"}),
    and "case" is a case each of them names, or "" when they name none in common (the usual rule then
    chooses among "cases", every case one of them names)."""
    found = alike_slips(step, failing_basic)
    if not found:
        return None
    common = [c for c in found[0]["cases"] if all(c in f["cases"] for f in found)]
    named = list(dict.fromkeys(c for f in found for c in f["cases"]))
    return {"name": found[0]["name"], "slip": found[0]["slip"], "case": common[0] if common else "",
            "cases": named, "alike": [{"name": f["name"], "slip": f["slip"]} for f in found]}


SAID = "Your code fails exactly the cases that "   # how words() begins


def match(step: Step, cases) -> dict | None:
    """known_slip for a step's graded cases (anything with .name, .tier and .status): None when a case
    gave no answer (status.NO_ANSWER: timed out, or never ran)."""
    if any(c.status in NO_ANSWER for c in cases):
        return None
    return known_slip(step, {c.name for c in cases if c.tier == "basic" and c.status != PASS})


def words(slip: dict) -> str:
    """The line said above the first case's report: the failing set as measured, the slip's words as
    the likely cause (the code itself is not compared: another slip may fail the same cases)."""
    alike = slip.get("alike") or [{"name": slip.get("name", ""), "slip": slip.get("slip", "")}]
    if len(alike) == 1:
        return ("Your code fails exactly the cases that a slip the course knows fails, so that slip is the "
                f"likely cause (check that your code has it): {alike[0]['slip']}")
    said = "; or ".join(a["slip"].rstrip(".") for a in alike[:MOST_SAID])
    more = f" (and {len(alike) - MOST_SAID} more)" if len(alike) > MOST_SAID else ""
    return (f"Your code fails exactly the cases that {len(alike)} slips the course knows fail; the likely "
            f"cause is one of them{more}: {said}.")


# How the judge begins a fact it measured on the student's own function (tests/support/relations.hpp,
# grading.hpp's window_cause and epsilon_cause): such a fact comes before any guess of the catalogue's.
MEASURED = re.compile(r"Measured on your (function|answer):")


def say(result) -> None:
    """Puts the known slip's words (result.slip, when set) above the report of the case a student is
    shown first, in the same message: the case still reports one call. Where that report holds a fact
    measured on the student's function, the fact comes first and the catalogue's likely cause after it."""
    if not result.slip:
        return
    first = result.first_problem()
    if first is not None:
        said = words(result.slip)
        if first.messages and MEASURED.search(first.messages[0]):
            first.messages = [first.messages[0].rstrip("\n") + "\n" + said] + list(first.messages[1:])
        else:
            first.messages = [said + ("\n" + first.messages[0] if first.messages else "")] + list(first.messages[1:])


def unsaid(message: str) -> str:
    """A first message without the catalogue's words say() put in it (above the report, or after it)."""
    if message.startswith(SAID) and "\n" in message:
        return message.split("\n", 1)[1]
    at = message.rfind("\n" + SAID)
    return message[:at] if at >= 0 and MEASURED.search(message[:at]) else message

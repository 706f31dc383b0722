"""Self-test: no route of a student's own file to "not graded" (issue 52, item 2).

A step is not graded only from evidence the graded code cannot shape (docs/integrity.md, "Not
graded"). Each fixture of tests/fixtures/hostile/ with a verdict in its `expected.json` is one route a student's file
has to its own "not graded": the words of a full disk in a diagnostic (`#warning`, `#line`, `#pragma
message`, a deprecation, a failing `static_assert`), a global constructor that sleeps, spins or forks,
descriptors closed, put on /dev/full or flooded, a scratch folder filled at start-up. Each is graded
with `./kit check 1 --steps` under bubblewrap and under the user isolation (integrity.isolations: a
part left out is a failure in CI), and must get the student's own verdict, as its `expected.json` says:

  "base"       the partial step the others are compared with: graded, partial, never not graded
  "same"       the very cases and score of `like` (the words change nothing)
  "no_compile" does not compile, with its own diagnostic
  "own"        graded (no case without a verdict), no case passed that `like` fails, no more points
               than `like`; `says`, when given, appears in a message (the start-up is named)

The expectations come from the fixtures and from the base's own grading here, never from a figure
of today's course.
"""

from __future__ import annotations

import json

import pytest

from raykit.status import GRADER_ERROR, NO_COMPILE, NOT_GRADED, PASS
from .fixtures import fixture_dir
from .support import Failed, expect, need_solutions
from .integrity import grade_json, run_modes

KINDS = ("base", "same", "no_compile", "own")


def routes() -> list[tuple[str, dict]]:
    """The fixtures that declare an expectation, the base first."""
    found = []
    for folder in sorted(fixture_dir("hostile").iterdir()):
        spec = folder / "expected.json"
        if not spec.is_file():
            continue
        data = json.loads(spec.read_text())
        if "verdict" not in data:
            continue            # checked in code (checked_by): selftest_hostile_expectations
        if data.get("verdict") not in KINDS:
            raise Failed(f"{spec}: verdict {data.get('verdict')!r} is none of {KINDS}")
        found.append((folder.name, data))
    found.sort(key=lambda r: r[1]["verdict"] != "base")
    if not found or found[0][1]["verdict"] != "base":
        raise Failed("no hostile fixture declares the base (expected.json, verdict \"base\")")
    return found


def _messages(step: dict) -> list[str]:
    out = []
    for c in step["cases"]:
        out += c.get("messages", [])
        first = (c.get("rerun") or {}).get("first") or {}
        out += first.get("messages", [])
    return out


@pytest.mark.security      # of integrity's: may not skip in CI
def selftest_no_own_not_graded(ctx) -> str:
    """Every route a student's file has to its own "not graded" gives the student's own verdict."""
    need_solutions()
    found = routes()

    def one(mode: str) -> str:
        graded: dict[str, dict] = {}
        problems = []
        for name, spec in found:
            _, got, _, _ = grade_json(fixture_dir("hostile") / name, ["01"], mode)
            [step] = got["record"]["steps"]
            graded[name] = step
            cases = {c["name"]: c["status"] for c in step["cases"]}
            points = got["score"]
            without = [n for n, st in cases.items() if st == GRADER_ERROR]
            if step["state"] == NOT_GRADED or without or not got["record"].get("gradable", True):
                problems.append(f"{name}: not graded ({step.get('reason') or step.get('not_graded') or without[:2]})")
                continue
            kind = spec["verdict"]
            like = graded.get(spec.get("like", ""))
            if kind in ("same", "own") and like is None:
                raise Failed(f"{name}: its expected.json names no graded base ({spec.get('like')!r})")
            theirs = {c["name"]: c["status"] for c in like["cases"]} if like else {}
            if kind == "base":
                expect(any(st == PASS for st in cases.values()) and any(st != PASS for st in cases.values()),
                       f"{name} ({mode}): the base is not a partial step: {step['state']}")
            elif kind == "same" and (cases != theirs or points != like["_score"]):
                diff = [f"{n}: {st} (base {theirs.get(n)})" for n, st in cases.items() if theirs.get(n) != st]
                problems.append(f"{name}: {points} points, the base {like['_score']}; {diff[:3]}")
            elif kind == "no_compile" and step["state"] != NO_COMPILE:
                problems.append(f"{name}: {step['state']}, not its own compile error")
            elif kind == "own":
                gained = [n for n, st in cases.items() if st == PASS and theirs.get(n) != PASS]
                if gained or points > like["_score"]:
                    problems.append(f"{name}: {points} points (base {like['_score']}), passes {gained[:3]}")
                if spec.get("says") and not any(spec["says"] in m for m in _messages(step)):
                    problems.append(f"{name}: no message says {spec['says']!r}")
            step["_score"] = points
        expect(not problems, f"{mode}: " + "; ".join(problems))
        states = ", ".join(f"{n} {s['state']} {s['_score']}" for n, s in graded.items())
        return f"{len(graded)} routes, each the student's own verdict ({states})"

    return run_modes(one)


@pytest.mark.quick
def selftest_hostile_expectations(ctx) -> str:
    """Every folder of tests/fixtures/hostile/ says what it expects (issue 56) in its expected.json: a
    verdict (read by the test above), or a checked_by that names the self-tests, MODULE.py::FUNCTION of
    tests/kit/, that check it in code."""
    need_solutions()    # tests/fixtures/ ships in no handout
    from raykit.common import ROOT
    here = ROOT / "tests" / "kit"
    data, code = 0, 0
    for folder in sorted(p for p in fixture_dir("hostile").iterdir() if p.is_dir()):
        where = f"tests/fixtures/hostile/{folder.name}"
        spec = folder / "expected.json"
        expect(spec.is_file(), f"{where}/ has no expected.json: what must it produce?")
        try:
            said = json.loads(spec.read_text())
        except ValueError as e:
            raise Failed(f"{where}/expected.json: not JSON: {e}")
        if "verdict" in said:       # a route to "not graded": its verdict is data (the test above)
            data += 1
            continue
        tests = said.get("checked_by")
        expect(isinstance(tests, list) and tests, f"{where}/expected.json: no checked_by list")
        for t in tests:
            path, _, name = str(t).partition("::")
            source = ROOT / path
            expect(source.parent == here and source.is_file() and name.startswith("selftest_")
                   and f"\ndef {name}(" in source.read_text(),
                   f"{where}/expected.json: checked_by {t!r} is no self-test of tests/kit/")
        code += 1
    return f"{data} hostile fixtures with a verdict as data, {code} checked in code, each naming its test"

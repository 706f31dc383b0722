#!/usr/bin/env python3
"""One kit step's grade as a GitHub Classroom grading step's `result` output.

    python3 tools/classroom/result.py RESULTS.json NN

RESULTS.json is what `./kit check --json RESULTS.json` wrote (Gradescope's format, the kit's one
scale). This writes `result=BASE64` to $GITHUB_OUTPUT (to stdout without it): the JSON that
classroom-resources/autograding-command-grader writes, version 1, but with one entry per case of
step NN that carries points, each scoring 1 or 0, so autograding-grading-reporter gives partial
credit. Its notice "Points X/Y" sums `tests[].score` and the runners' `max_score`; its console table
computes passes / entries x max_score: the two agree because every entry is worth exactly one point
(the optional ★ cases, worth none, are named in the message of the step's last entry instead).

Standard library only; it never fails the workflow itself (exit 0), so the reporter always runs: a
missing or unreadable RESULTS.json becomes an entry with status "error" and what went wrong.
"""

from __future__ import annotations

import base64
import json
import os
import sys

MESSAGE_CHARS = 1500    # per case: what the reporter's annotation and log show


def entry(name: str, passed: bool, message: str, test_code: str = "") -> dict:
    return {"name": name, "status": "pass" if passed else "fail", "score": int(passed),
            "message": message[:MESSAGE_CHARS], "test_code": test_code, "filename": "", "line_no": 0,
            "duration": 0}


def step_result(results: dict, number: str) -> dict:
    number = number.zfill(2)
    tests = [t for t in results.get("tests", []) if f"step{number}" in t.get("tags", [])]
    graded = [t for t in tests if t.get("max_score", 0) > 0]
    starred = [t for t in tests if t.get("max_score", 0) == 0 and "robust" in t.get("tags", [])]
    entries = [entry(t["name"], t["status"] == "passed", t.get("output", "")) for t in graded]
    if not graded:  # the kit could not check the step: one entry worth nothing, with the reason
        why = "; ".join(t.get("output", "") for t in tests) or f"the results have no step {number}"
        return {"version": 1, "status": "error", "max_score": 0, "tests": [
            {**entry(f"Step {number}", False, why), "status": "error"}]}
    if starred:
        passed = sum(t["status"] == "passed" for t in starred)
        entries[-1]["message"] += f"\n(★ robust cases, optional, worth no points: {passed} of {len(starred)} pass)"
    status = "pass" if all(e["status"] == "pass" for e in entries) else "fail"
    return {"version": 1, "status": status, "max_score": len(entries), "tests": entries}


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    path, number = argv
    try:
        with open(path, encoding="utf-8") as f:
            result = step_result(json.load(f), number)
    except (OSError, ValueError, KeyError, TypeError) as e:
        result = {"version": 1, "status": "error", "max_score": 0, "tests": [
            {**entry(f"Step {number}", False, f"./kit check wrote no readable results ({e}); "
                     "see the step that ran it"), "status": "error"}]}
    line = "result=" + base64.b64encode(json.dumps(result).encode()).decode()
    out = os.environ.get("GITHUB_OUTPUT")
    if out:
        with open(out, "a", encoding="utf-8") as f:
            f.write(line + "\n")
    else:
        print(line)
    score = sum(t["score"] for t in result["tests"])
    print(f"step {number.zfill(2)}: {score} of {result['max_score']} points", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

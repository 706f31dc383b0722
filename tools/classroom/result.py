#!/usr/bin/env python3
"""One kit step's grade as a GitHub Classroom grading step's `result` output.

    python3 tools/classroom/result.py RESULTS.json NN

RESULTS.json is what `./kit check --classroom RESULTS.json` wrote: every step's result already in
the form classroom-resources/autograding-grading-reporter reads (the command grader's version 1
JSON, one entry per counted case, rendered by tools/raykit/classroomresults.py from the kit's own
results). This hands step NN's on unchanged: `result=BASE64` to $GITHUB_OUTPUT (to stdout without
it). It reads no display text and computes no score.

Standard library only; it never fails the workflow itself (exit 0), so the reporter always runs: a
missing or unreadable RESULTS.json, or one without step NN, becomes an entry with status "error"
and what went wrong.
"""

from __future__ import annotations

import base64
import json
import os
import sys

FORMAT = "raykit-classroom"     # tools/raykit/classroomresults.py
VERSION = 1


def error(number: str, why: str) -> dict:
    return {"version": 1, "status": "error", "max_score": 0, "tests": [
        {"name": f"Step {number}", "status": "error", "score": 0, "message": why, "test_code": "",
         "filename": "", "line_no": 0, "duration": 0}]}


def step_result(path: str, number: str) -> dict:
    number = number.zfill(2)
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        return error(number, f"./kit check wrote no readable results ({e}); see the step that ran it")
    if not isinstance(data, dict) or data.get("format") != FORMAT or data.get("version") != VERSION:
        return error(number, f"{path} is not ./kit check --classroom's file ({FORMAT} version {VERSION})")
    if data.get("finished") is False:   # the placeholder: the check died before its results
        return error(number, "Not graded: ./kit check stopped before it finished (the grader's fault, not "
                             "your code's); run the workflow again, and tell your instructor if it stays so")
    found = (data.get("runners") or {}).get(number)
    if not isinstance(found, dict) or not isinstance(found.get("tests"), list):
        return error(number, f"the results have no step {number}")
    return found


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    path, number = argv
    result = step_result(path, number)
    line = "result=" + base64.b64encode(json.dumps(result).encode()).decode()
    out = os.environ.get("GITHUB_OUTPUT")
    if out:
        with open(out, "a", encoding="utf-8") as f:
            f.write(line + "\n")
    else:
        print(line)
    score = sum(t.get("score", 0) for t in result["tests"] if isinstance(t, dict))
    print(f"step {number.zfill(2)}: {score} of {result.get('max_score', 0)} points", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

#!/usr/bin/env python3
"""Checks a results.json as PrairieLearn reads it; checks info.json files against its schema.

    python3 check_results.py results FILE...     every problem PrairieLearn would have with FILE
    /usr/bin/python3 check_results.py info SCHEMA FILE...   (needs python3-jsonschema)

The rules for results.json, from PrairieLearn's apps/prairielearn/src/lib/externalGraderCommon.ts
(makeGradingResult, which receives the file wrapped as {succeeded: true, results: FILE}) and
docs/externalGrading.md:
  - the text parses as JSON (NUL bytes aside, which it replaces), an object, at most 1 MB;
  - `score`, unless null, is a number and not NaN, else the job is a grading failure; the docs add that
    a gradable result's score is in [0, 1] and that `gradable: false` needs no score;
  - `format_errors`, when there, is a string or an array (of strings, as the element shows them);
  - the <pl-external-grader-results> element: `points` and `max_points` on every test or on none (else
    no per-test display), `images` entries a data URL string or an object with a string `url`.
The kit's own rule on top: `points` and `max_points` are on every test and 0 <= points <= max_points.
An instructor's test tool (tests/kit/reach.py); the standard library only for `results`.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

LIMIT = 1_000_000


def image_problems(images, where: str) -> list[str]:
    if not isinstance(images, list):
        return [f"{where}images is not an array"]
    found = []
    for i, im in enumerate(images):
        url = im if isinstance(im, str) else im.get("url") if isinstance(im, dict) else None
        if not isinstance(url, str):
            found.append(f"{where}images[{i}] has no string url")
        elif not url.startswith("data:image/") or ";base64," not in url:
            found.append(f"{where}images[{i}] is not a base64 image data URL")
        if isinstance(im, dict) and "label" in im and not isinstance(im["label"], str):
            found.append(f"{where}images[{i}].label is not a string")
    return found


def results_problems(raw: bytes) -> list[str]:
    if len(raw) > LIMIT:
        return [f"{len(raw)} bytes, more than PrairieLearn's 1 MB"]
    try:
        data = json.loads(raw.decode("utf-8").replace("\0", "\ufffd"))
    except (UnicodeDecodeError, ValueError) as e:
        return [f"not JSON: Could not parse the grading results ({e})"]
    if not isinstance(data, dict):
        return ["not a JSON object"]
    found = []
    score = data.get("score")
    gradable = data.get("gradable", True)
    if not isinstance(gradable, bool):
        found.append("gradable is not a boolean")
    if score is not None and (not isinstance(score, (int, float)) or isinstance(score, bool)
                              or math.isnan(score)):
        found.append(f'score "{score}" was not a number')
    elif gradable is not False:
        if score is None:
            found.append("a gradable result has no score")
        elif not 0 <= score <= 1:
            found.append(f"score {score} is outside [0, 1]")
    fe = data.get("format_errors")
    if fe is not None and not isinstance(fe, str) and not (isinstance(fe, list) and all(isinstance(x, str) for x in fe)):
        found.append("format_errors is neither a string nor an array of strings")
    for key in ("message", "output"):
        if key in data and not isinstance(data[key], str):
            found.append(f"{key} is not a string")
    if "images" in data:
        found += image_problems(data["images"], "")
    tests = data.get("tests", [])
    if not isinstance(tests, list):
        return found + ["tests is not an array"]
    for i, t in enumerate(tests):
        w = f"tests[{i}]."
        if not isinstance(t, dict):
            found.append(f"tests[{i}] is not an object")
            continue
        if not isinstance(t.get("name"), str) or not t["name"]:
            found.append(w + "name is missing")
        for key in ("points", "max_points"):
            v = t.get(key)
            if not isinstance(v, (int, float)) or isinstance(v, bool) or math.isnan(v):
                found.append(f"{w}{key} is missing or not a number (the element then shows no points at all)")
        if isinstance(t.get("points"), (int, float)) and isinstance(t.get("max_points"), (int, float)) \
                and not 0 <= t["points"] <= t["max_points"]:
            found.append(f"{w}points {t['points']} not within 0..max_points {t['max_points']}")
        for key in ("description", "message", "output"):
            if key in t and not isinstance(t[key], str):
                found.append(f"{w}{key} is not a string")
        if "images" in t:
            found += image_problems(t["images"], w)
    return found


def info_problems(schema_path: Path, files: list[Path]) -> dict[str, list[str]]:
    import jsonschema  # Debian's python3-jsonschema
    schema = json.loads(schema_path.read_text())
    validator = jsonschema.validators.validator_for(schema)(schema)
    return {str(f): [f"{'/'.join(map(str, e.absolute_path)) or '(top)'}: {e.message}"
                     for e in validator.iter_errors(json.loads(f.read_text()))] for f in files}


def main(argv: list[str]) -> int:
    if len(argv) >= 2 and argv[0] == "results":
        bad = {f: results_problems(Path(f).read_bytes()) for f in argv[1:]}
    elif len(argv) >= 3 and argv[0] == "info":
        bad = info_problems(Path(argv[1]), [Path(f) for f in argv[2:]])
    else:
        print("usage: check_results.py results FILE... | info SCHEMA FILE...", file=sys.stderr)
        return 2
    print(json.dumps(bad))
    return 1 if any(bad.values()) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

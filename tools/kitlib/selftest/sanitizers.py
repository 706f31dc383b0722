"""Self-test: the reference build and its tests under AddressSanitizer and UndefinedBehaviorSanitizer.
Last in the run: the slowest self-test, and left out by --fast."""

from __future__ import annotations

import re

from ..build import workflow
from .harness import Context, Skipped, expect, need_solutions


def selftest_sanitizers(ctx: Context) -> str:
    need_solutions()
    if ctx.fast:
        raise Skipped("--fast leaves out the sanitizer build")
    r = workflow("sanitize")
    tail = (r.stdout + r.stderr)[-4000:]
    expect(r.returncode == 0, f"the ASan + UBSan build or its tests failed:\n{tail}")
    m = re.search(r"tests passed, (\d+) tests failed out of (\d+)", r.stdout)
    expect(m is not None and int(m.group(2)) > 0, "ctest ran no test under the sanitizers")
    return f"ASan + UBSan, {m.group(2)} tests, no finding"


def selftest_student_sanitizers(ctx: Context) -> str:
    """A student's own ./kit check builds their files with ASan, UBSan and GLM's asserts: step 04
    without its axis check (tests/fixtures/ub_axis, reading ray.direction[3]) fails the "axis 3"
    case as a crash that names the call, the sanitizer's reason and the student's line, where a
    plain build may pass it by luck. Checked in a handout, where students run it."""
    import json
    import shutil
    import time

    from ..common import BUILD, ROOT
    from .harness import kit
    need_solutions()
    handout = BUILD / "ub-handout"
    shutil.rmtree(handout, ignore_errors=True)
    r = kit("handout", str(handout), "--committed", timeout=600)
    expect(r.returncode == 0, f"./kit handout failed: {r.stderr[-400:]}")
    shutil.copyfile(ROOT / "tests" / "fixtures" / "ub_axis" / "04_rectangles" / "rect.cpp",
                    handout / "steps" / "04_rectangles" / "rect.cpp")
    import subprocess
    start = time.monotonic()
    p = subprocess.run([str(handout / "kit"), "check", "4", "--results", str(handout / "r.json"), "--quiet"],
                       cwd=handout, capture_output=True, text=True, timeout=900)
    took = time.monotonic() - start
    try:
        data = json.loads((handout / "r.json").read_text())
    except (OSError, ValueError):
        raise AssertionError(f"no results: {p.stderr[-400:]}")
    cases = {c["name"]: c for s in data["steps"] for c in s["cases"]}
    axis = next((c for n, c in cases.items() if "axis of 3" in n), None)
    shutil.rmtree(handout, ignore_errors=True)
    expect(axis is not None, "no case with an axis of 3 in step 04")
    message = " ".join(axis["messages"])
    expect(axis["status"] == "crashed" and "undefined behaviour" in message and "rect.cpp:" in message,
           f"the axis-3 read is not reported as undefined behaviour with its line: {axis['status']}: {message[:300]}")
    return f"the axis-3 read reported: {message[message.find(': ', message.find('inf)')) + 2:][:150]} ({took:.0f} s cold)"


def selftests() -> list:
    return [("the student's own check under the sanitizers", selftest_student_sanitizers),
            ("sanitizers", selftest_sanitizers)]

"""Self-test of ./kit debug: gdb stops in the student's own function (not in the judge's proxy of the
same name) with the case's arguments, and a case name that matches nothing or several is refused."""

from __future__ import annotations

import re
import shutil

from ..common import ROOT
from .harness import Skipped, expect, kit, need_solutions

CASE = "window: a root exactly at tmin counts"


def selftest_debug(ctx) -> str:
    need_solutions()   # tests/fixtures/ is not in a handout
    if shutil.which("gdb") is None:
        raise Skipped("gdb is not installed (apt-get install gdb)")
    wrong = ROOT / "tests" / "fixtures" / "wrong"
    r = kit("debug", "1", CASE, "--steps", str(wrong), "--batch", timeout=600)
    out = r.stdout + r.stderr
    frame = re.search(r"^#0\s+raykit::intersect_unit_sphere \(ray=.*tmin=2, tmax=10\) at (\S+)", out, re.M)
    expect(frame is not None, f"gdb did not stop in the student's intersect_unit_sphere:\n{out[-1500:]}")
    expect("01_unit_sphere/unit_sphere.cpp" in frame.group(1) and "tests/support" not in frame.group(1),
           f"gdb stopped in {frame.group(1)}, not in the student's file")
    r = kit("debug", "1", "no case is called like this", "--steps", str(wrong), "--print", timeout=300)
    expect(r.returncode == 2 and "no case named like" in r.stderr, f"an unknown case: {r.returncode} {r.stderr[-300:]}")
    r = kit("debug", "1", "window", "--steps", str(wrong), "--print", timeout=300)
    expect(r.returncode == 2 and "match 'window'" in r.stderr, f"an ambiguous case: {r.returncode} {r.stderr[-300:]}")
    return "gdb stops in the student's intersect_unit_sphere(tmin=2, tmax=10); unknown and ambiguous case names refused"


def selftests() -> list:
    return [("debugging a case under gdb", selftest_debug)]

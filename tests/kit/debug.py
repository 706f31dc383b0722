"""Self-test of ./kit debug: gdb stops in the student's own function (not in the judge's proxy of the
same name) with the case's arguments, and a case name that matches nothing or several is refused;
with no gdb on the PATH (a Mac), lldb does the same; the case's name and the debugger are checked
before anything is built, and a machine with neither is told its own platform's way to get one."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

from raykit.common import BUILD, ROOT
from .support import Skipped, expect, kit, need_solutions
from .fixtures import fixture_dir

CASE = "window: a root exactly at tmin counts"


def selftest_debug(ctx) -> str:
    need_solutions()   # tests/fixtures/ is not in a handout
    if shutil.which("gdb") is None:
        raise Skipped("gdb is not installed (apt-get install gdb)")
    wrong = fixture_dir("wrong")
    r = kit("debug", "1", CASE, "--steps", str(wrong), "--batch", timeout=600)
    out = r.stdout + r.stderr
    frame = re.search(r"^#0\s+raykit::intersect_unit_sphere \(ray=.*tmin=2, tmax=10\) at (\S+)", out, re.M)
    expect(frame is not None, f"gdb did not stop in the student's intersect_unit_sphere:\n{out[-1500:]}")
    expect("01_unit_sphere/unit_sphere.cpp" in frame.group(1) and "tests/support" not in frame.group(1),
           f"gdb stopped in {frame.group(1)}, not in the student's file")
    # No case named: the one ./kit check shows first. The debugger shows the student's own lines
    # (the objects stay, with the sources where the student keeps them) and prints the arguments.
    start = time.monotonic()
    r = kit("debug", "1", "--steps", str(wrong), "--batch", timeout=600)
    took = time.monotonic() - start
    out = r.stdout + r.stderr
    frame = re.search(r"^#0\s+raykit::(\w+) \(ray=.*\) at (\S+):(\d+)$", out, re.M)
    expect(frame is not None and frame.group(2).endswith("01_unit_sphere/unit_sphere.cpp"),
           f"./kit debug 1 (first failing case) did not stop in the student's file:\n{out[-1500:]}")
    source = Path(frame.group(2)).read_text().splitlines()
    line = int(frame.group(3))
    shown = [l for l in source[max(0, line - 5):line + 5] if len(l.strip()) > 8 and l.strip() in out]
    expect(len(shown) >= 3 and "No such file" not in out,
           f"gdb did not list the student's source around line {line}:\n{out[-1500:]}")
    expect(re.search(r"^ray = .*origin = .*direction = ", out, re.M) is not None,
           f"gdb could not print the argument ray:\n{out[-1500:]}")
    r = kit("debug", "1", "no case is called like this", "--steps", str(wrong), "--print", timeout=300)
    expect(r.returncode == 2 and "no case named like" in r.stderr, f"an unknown case: {r.returncode} {r.stderr[-300:]}")
    r = kit("debug", "1", "window", "--steps", str(wrong), "--print", timeout=300)
    expect(r.returncode == 2 and "match 'window'" in r.stderr, f"an ambiguous case: {r.returncode} {r.stderr[-300:]}")
    return (f"gdb stops in the student's intersect_unit_sphere(tmin=2, tmax=10); the first failing case's "
            f"{frame.group(1)} with its source listed and ray printed ({took:.1f} s, the kit's side built); "
            "unknown and ambiguous case names refused")


def path_without(folder: Path, hidden: set[str], extra: dict[str, str] | None = None) -> str:
    """A PATH of one folder holding a link to every program of this PATH but `hidden` (gdb, apt-get,
    ...), and the scripts of `extra` (a fake `brew`): the kit then sees a machine without them."""
    folder.mkdir(parents=True, exist_ok=True)
    for d in os.environ.get("PATH", "").split(os.pathsep):
        if not d or not os.path.isdir(d):
            continue
        for entry in os.scandir(d):
            link = folder / entry.name
            if entry.name in hidden or link.exists() or link.is_symlink() or not os.access(entry.path, os.X_OK):
                continue
            link.symlink_to(entry.path)
    for name, text in (extra or {}).items():
        (folder / name).write_text(text)
        (folder / name).chmod(0o755)
    return str(folder)


def kit_with(path: str, *args: str, timeout: float = 600) -> subprocess.CompletedProcess:
    return subprocess.run([str(ROOT / "kit"), *args], cwd=ROOT, capture_output=True, text=True, timeout=timeout,
                          env=dict(os.environ, PATH=path))


def stamp() -> tuple:
    """The debug folder's state: every file any compile or link of ./kit debug writes."""
    folder = BUILD / "debug"
    return tuple(sorted((str(p), p.stat().st_mtime_ns) for p in folder.rglob("*") if p.is_file())) if folder.is_dir() else ()


def selftest_debug_lldb(ctx) -> str:
    need_solutions()
    if shutil.which("lldb") is None:
        raise Skipped("lldb is not installed (apt-get install lldb)")
    wrong = fixture_dir("wrong")
    with tempfile.TemporaryDirectory(prefix="raykit-nogdb-") as tmp:
        no_gdb = path_without(Path(tmp) / "bin", {"gdb"})
        r = kit_with(no_gdb, "debug", "1", CASE, "--steps", str(wrong), "--batch", timeout=900)
        out = r.stdout + r.stderr
        expect("lldb stops in your" in out, f"without gdb, ./kit debug did not choose lldb:\n{out[-800:]}")
        frame = re.search(r"frame #0: \S+ answers_step01`raykit::intersect_unit_sphere\(ray=\S+ tmin=2, tmax=10\) "
                          r"at (\S+)", out)
        expect(frame is not None, f"lldb did not stop in the student's intersect_unit_sphere:\n{out[-1500:]}")
        expect(frame.group(1).startswith("unit_sphere.cpp:"), f"lldb stopped in {frame.group(1)}")
        # Neither debugger, no apt, a Homebrew: the unknown case is refused first, then the missing
        # debugger, in Homebrew's words, and nothing is configured or built for either.
        neither = path_without(Path(tmp) / "bare", {"gdb", "lldb", "apt-get", "dpkg-query"},
                               {"brew": "#!/bin/sh\necho " + tmp + "/homebrew\n"})
        before = stamp()
        r = kit_with(neither, "debug", "1", "no case is called like this", "--steps", str(wrong), timeout=300)
        expect(r.returncode == 2 and "no case named like" in r.stderr, f"an unknown case: {r.returncode} {r.stderr[-300:]}")
        r = kit_with(neither, "debug", "1", CASE, "--steps", str(wrong), timeout=300)
        said = r.stderr.strip().splitlines()[-1] if r.stderr.strip() else ""
        expect(r.returncode == 3 and "needs gdb or lldb" in r.stderr and "brew install" in r.stderr
               and "apt-get" not in r.stderr, f"no debugger: {r.returncode} {r.stderr[-400:]}")
        expect(stamp() == before, "./kit debug configured or built before refusing the case or the debugger")
    return ("without gdb, lldb stops in the student's intersect_unit_sphere(tmin=2, tmax=10); an unknown case and "
            f"a missing debugger refused before any build: {said[:90]}")

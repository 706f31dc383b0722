"""The warm-up: while a newcomer reads the first task, the kit's own programs build in the background.

A newcomer's first `./kit check` needs no build (every step is the shipped stub, tests/stubs.json),
so it answers in well under a second. Their second one, after step 01 is written, would build
doctest's main, the grader's support, a judge and a dispatcher before the first verdict: most of a
cold check's CPU, and none of it depends on the student's code. So the first check, when it built
nothing and the build folder is not configured yet, starts `./kit check --warm-up` in the
background: at the lowest priority, it configures build/student and builds the kit's own targets of
every step (raykit_test_support, raykit_platform, test_stepNN, dispatchNN), which also fills the kit cache.

Never two builds in one folder: the warm-up writes its process id to build/student/warm-up.pid,
and every check of that folder first ends it (stop, called by checking.check_steps). What it
finished stays built; Ninja removes what it was in the middle of. Only a student's own check on a
terminal starts one (not --steps, --json, --quiet, a grading, an autograder); RAYKIT_NO_WARMUP=1
turns it off (the self-test does, except where it measures it).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

from .common import ROOT
from .build import Build, build_targets, ensure_configured
from .sandbox import kill_session, session_members

PID_FILE = "warm-up.pid"
LOG_FILE = "warm-up.log"


def wanted(build: Build) -> bool:
    """After a check: whether it should start the warm-up (it built nothing, on a terminal)."""
    return (sys.stdout.isatty() and os.environ.get("RAYKIT_NO_WARMUP") != "1"
            and not (build.binary_dir / "CMakeCache.txt").exists() and not running(build))


def start(build: Build) -> None:
    """Starts the warm-up of `build` in its own session, detached from the terminal."""
    build.binary_dir.mkdir(parents=True, exist_ok=True)
    try:
        with open(build.binary_dir / LOG_FILE, "w") as log:
            proc = subprocess.Popen([str(ROOT / "kit"), "check", "--warm-up"], cwd=ROOT, stdin=subprocess.DEVNULL,
                                    stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
                                    preexec_fn=lambda: os.nice(19))
        (build.binary_dir / PID_FILE).write_text(str(proc.pid))
    except OSError:
        pass        # no warm-up: the next check builds what it needs, as without one


def _pid(build: Build) -> int | None:
    try:
        return int((build.binary_dir / PID_FILE).read_text())
    except (OSError, ValueError):
        return None


def running(build: Build) -> bool:
    pid = _pid(build)
    return pid is not None and bool(session_members(pid))


def stop(build: Build) -> None:
    """Ends the warm-up of `build`, if one runs, and waits until every process of it has ended."""
    pid = _pid(build)
    if pid is None:
        return
    # Its session: python, cmake, ninja and the compilers Ninja starts (each in a process group of
    # its own, all in this session).
    if session_members(pid):
        try:
            os.killpg(pid, signal.SIGTERM)      # python, cmake and ninja; Ninja ends its compilers
        except OSError:
            pass
        deadline = time.monotonic() + 5
        while session_members(pid) and time.monotonic() < deadline:
            time.sleep(0.02)
        kill_session(pid)                       # what is left, at once
    try:
        (build.binary_dir / PID_FILE).unlink()
    except OSError:
        pass


def run(build: Build, steps) -> int:
    """The warm-up itself (./kit check --warm-up): configure, then the kit's own targets, every step."""
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
    start = time.monotonic()
    ensure_configured(build, steps)
    # Step 01's first (what the newcomer checks next), then the others.
    phases = [["raykit_test_support", "raykit_platform", steps[0].target, f"dispatch{steps[0].number}"],
              [t for s in steps[1:] for t in (s.target, f"dispatch{s.number}")]]
    ok, out = True, ""
    for targets in phases:
        if targets:
            ok, out = build_targets(build, targets)
            if not ok:
                print(out[-3000:])
                break
    print(f"warm-up: {'built' if ok else 'could not build'} the kit's own programs of {len(steps)} steps in "
          f"{time.monotonic() - start:.1f} s", flush=True)
    try:
        if _pid(build) == os.getpid():
            (build.binary_dir / PID_FILE).unlink()
    except OSError:
        pass
    return 0 if ok else 1

"""The warm-up: while a newcomer reads the first task, the kit's side builds in the background.

A newcomer's first `./kit check` needs no build (every step is the shipped stub, tests/stubs.json),
so it answers in well under a second. Their second one, after step 01 is written, would first build
the kit's side (bundle.py: the judges, doctest's runner, the dispatchers): most of a cold check's
CPU, and none of it depends on the student's code. So the first check, when it built nothing and
there is no bundle for this kit yet, starts `./kit check --warm-up` in the background at the lowest
priority, which builds the bundle, one step's part after another in course order.

A check that needs the bundle while the warm-up builds it waits for it (the bundle's lock) rather
than starting again: what the warm-up built is kept. Its process id is in build/student/warm-up.pid,
so that no second one starts. Only a student's own check on a terminal starts one (not --steps,
--json, --quiet, a grading, an autograder); RAYKIT_NO_WARMUP=1 turns it off (the self-test does,
except where it measures it).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from contextlib import suppress

from .common import ROOT, load_steps
from . import bundle
from .build import Build, detect_undefined
from .sandbox import session_members

PID_FILE = "warm-up.pid"
LOG_FILE = "warm-up.log"


def wanted(build: Build) -> bool:
    """After a check: whether it should start the warm-up (it built nothing, on a terminal)."""
    if not sys.stdout.isatty() or os.environ.get("RAYKIT_NO_WARMUP") == "1" or running(build):
        return False
    try:
        return bundle.find(detect_undefined()) is None
    except Exception:       # noqa: BLE001 -- no compiler, no cache folder: the check says so when it needs one
        return False


def start(build: Build) -> None:
    """Starts the warm-up of `build` in its own session, detached from the terminal."""
    build.binary_dir.mkdir(parents=True, exist_ok=True)
    with suppress(OSError):  # no warm-up: the next check builds what it needs, as without one
        with open(build.binary_dir / LOG_FILE, "w") as log:
            proc = subprocess.Popen([str(ROOT / "kit"), "check", "--warm-up"], cwd=ROOT, stdin=subprocess.DEVNULL,
                                    stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
                                    preexec_fn=lambda: os.nice(19))
        (build.binary_dir / PID_FILE).write_text(str(proc.pid))


def _pid(build: Build) -> int | None:
    try:
        return int((build.binary_dir / PID_FILE).read_text())
    except (OSError, ValueError):
        return None


def running(build: Build) -> bool:
    pid = _pid(build)
    return pid is not None and bool(session_members(pid))


def run(build: Build) -> int:
    """The warm-up itself (./kit check --warm-up): the bundle built (bundle.ensure)."""
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
    start = time.monotonic()
    ok = True
    try:
        # Step by step in course order, the lock let go between two (bundle.ensure's parts): a check
        # of step 01 started meanwhile waits for step 01's part, not for the whole bundle.
        for step in load_steps():
            bundle.ensure(detect_undefined(), parts=[step.number])
        bundle.ensure(detect_undefined())
    except Exception as e:      # noqa: BLE001 -- said in its log; the next check says it again
        print(e)
        ok = False
    print(f"warm-up: {'built' if ok else 'could not build'} the kit's side in {time.monotonic() - start:.1f} s",
          flush=True)
    with suppress(OSError):
        if _pid(build) == os.getpid():
            (build.binary_dir / PID_FILE).unlink()
    return 0 if ok else 1

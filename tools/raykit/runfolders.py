"""Build folders that two gradings never share (build layer, above the core).

Two runs of the kit at once in one clone (an instructor's two `./kit check --steps` in two terminals,
`./kit grade` beside a check, a `./kit watch` beside a `./kit check`) must never write one folder:
each would compile into, link over and run the other's answers programs, and a student would be
given another's score.

- `private(kind)`: a folder of this run's own under build/runs/, made with mkdtemp (a name no other
  run can have) and removed when the run ends; a check of a `--steps` folder stages the files, compiles,
  links and runs there. What it shares with other runs is only what is addressed by content and
  written whole (the object cache, objcache.py; a grading's verdicts, checking.Verdicts), so a later
  writer replaces a file with the same content and never mixes two. Each folder holds a lock for as
  long as its run lives, so a run that died (killed, a power cut) leaves a folder the next run removes.
- `using(folder, what)`: the one folder a run must share (build/student: the student's own steps/,
  whose objects and answers programs a second check of the same files reuses), held by a lock that
  names who holds it; a second run waits for the first, saying whom it waits for.
"""

from __future__ import annotations

import fcntl
import os
import sys
import threading
import time
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import Iterator

from . import heldtmp
from .common import BUILD

RUNS = BUILD / "runs"


@contextmanager
def private(kind: str) -> Iterator[Path]:
    """A folder of this run's own under build/runs/ (see above), removed when the block ends; the
    folders of runs that died are removed first (heldtmp: each is locked while its run lives)."""
    RUNS.mkdir(parents=True, exist_ok=True)
    heldtmp.sweep(RUNS, "")         # every kind's: the folder is the kit's own
    with heldtmp.held(f"{kind}-", RUNS) as folder:
        yield folder


_held: dict[str, list] = {}        # lock file -> [descriptor, depth]: one process takes a folder once
_held_guard = threading.Lock()


def holder_words() -> str:
    return f"process {os.getpid()} ({' '.join(['./kit'] + sys.argv[1:3])}, since {time.strftime('%H:%M:%S')})"


@contextmanager
def using(folder: Path, what: str = "") -> Iterator[None]:
    """Holds `folder` for this process (a lock file beside it that names the holder) until the block
    ends; waits, saying for whom, while another run holds it. Re-entrant within one process (a check's
    command holds build/student around check_steps, which holds it too)."""
    lock = folder.with_name(f".{folder.name}.lock")
    key = str(lock)
    with _held_guard:
        if key in _held:
            _held[key][1] += 1
            mine = True
        else:
            mine = False
    if mine:
        try:
            yield
        finally:
            with _held_guard:
                _held[key][1] -= 1
        return
    lock.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            try:
                holder = os.pread(fd, 400, 0).decode("utf-8", "replace").strip() or "another run of the kit"
            except OSError:
                holder = "another run of the kit"
            from .common import note, printable
            note(f"kit: {folder.name} is in use by {printable(holder)}; waiting for it to end")
            fcntl.flock(fd, fcntl.LOCK_EX)
        os.ftruncate(fd, 0)
        os.pwrite(fd, (holder_words() + (f": {what}" if what else "") + "\n").encode(), 0)
        with _held_guard:
            _held[key] = [fd, 1]
        try:
            yield
        finally:
            with _held_guard:
                del _held[key]
            with suppress(OSError):
                os.ftruncate(fd, 0)
    finally:
        os.close(fd)

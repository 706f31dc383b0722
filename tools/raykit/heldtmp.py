"""Temporary folders that a killed run does not leave behind (core).

A run's scratch folder (a judge's output, a compile's work, a run's build folder) is removed by the
run when it ends. A run killed with SIGKILL, or by a power cut, cannot: its folder would stay in
/tmp for good. So each folder holds a lock for as long as its run lives (`.held`, flock'd), and the
next run that makes a folder of the same kind removes those whose lock is free.

In a shared folder (/tmp) the sweep touches only what this user owns, never follows a link, and
removes a folder without a lock file only once it is an hour old (one made a moment ago by a run
that has not taken its lock yet, or one left by a kit from before the locks).
"""

from __future__ import annotations

import fcntl
import os
import shutil
import tempfile
import time
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import Iterator

HELD = ".held"          # the lock file inside a folder: locked while its run lives
UNLOCKED_AGE = 3600     # seconds after which a folder with no lock file is taken as left behind
LOCKING_AGE = 10        # seconds after which a lock file that nobody holds is taken as a dead run's
_swept: set[tuple[str, str]] = set()     # once a process: a scan of a busy /tmp costs milliseconds


def sweep(parent: Path, prefix: str) -> None:
    """Removes the folders `prefix`* in `parent` that are this user's and whose run has ended."""
    try:
        entries = list(os.scandir(parent))
    except OSError:
        return
    for e in entries:
        try:
            if (not e.name.startswith(prefix) or not e.is_dir(follow_symlinks=False)
                    or e.stat(follow_symlinks=False).st_uid != os.geteuid()):
                continue
            fd = os.open(os.path.join(e.path, HELD), os.O_RDONLY | os.O_NOFOLLOW | os.O_CLOEXEC)
        except FileNotFoundError:
            with suppress(OSError):
                if time.time() - e.stat(follow_symlinks=False).st_mtime > UNLOCKED_AGE:
                    shutil.rmtree(e.path, ignore_errors=True)
            continue
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            # A run creates its lock file and then locks it: in between, a moment, the lock is free
            # though the run lives. A free lock counts only once the file is older than that.
            left = time.time() - os.fstat(fd).st_mtime > LOCKING_AGE
        except OSError:
            continue                # a live run's
        finally:
            os.close(fd)            # (the lock, when taken, goes with the descriptor)
        if left:
            shutil.rmtree(e.path, ignore_errors=True)


@contextmanager
def held(prefix: str, parent: Path | None = None) -> Iterator[Path]:
    """A new folder `prefix`PID-* in `parent` (the system's temporary folder by default), private to
    this user (mkdtemp's 0700), locked while the block runs and removed when it ends. The folders of
    the same prefix that killed runs left are removed first."""
    parent = Path(parent or tempfile.gettempdir())
    if (str(parent), prefix) not in _swept:
        sweep(parent, prefix)
        _swept.add((str(parent), prefix))
    folder = Path(tempfile.mkdtemp(prefix=f"{prefix}{os.getpid()}-", dir=parent))
    fd = os.open(folder / HELD, os.O_RDWR | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o600)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)
        os.close(fd)

"""Faults of the grader, as opposed to the student's: how the kit names them, and the self-test's
hooks that cause them on purpose.

A step is "not graded" (status.NOT_GRADED, a case GRADER_ERROR) when the kit, the machine or the
accounting failed it: a sandbox that could not start, the judge stopped, a full scratch disk, an
exception of the kit's own. Such a step has no verdict, so it costs no points and earns none; `./kit
grade` checks its submission again, alone, and lists it if it stays so (docs/integrity.md).

The hooks (test only, never set by a platform): RAYKIT_FAULT is a comma-separated list of
KIND@SUBMISSION, where SUBMISSION is the name `./kit grade` gives the child check (RAYKIT_SUBMISSION;
"*" for any), KIND one of

  killed        the child ./kit check kills itself (SIGKILL) right after writing its placeholder record
  hang          the child ./kit check sleeps there instead, until ./kit grade's limit for a submission
                ends it (RAYKIT_FAULT_SUBMISSION_SECONDS, when set, is that limit instead of course.json's)
  judge         the kit's judge is sent SIGABRT as soon as it starts a case (judge#NN: step NN only)
  full-disk     the child's scratch (TMPDIR) is the folder RAYKIT_FAULT_DISK, a disk the test filled

and a KIND ending in "-once" fires in the first process that meets it only (a marker in
RAYKIT_FAULT_MARKS), so the retry alone finds the machine well again.
"""

from __future__ import annotations

import errno
import os
import shutil
import signal
import time
from contextlib import suppress
from pathlib import Path

FAULT_ENV = "RAYKIT_FAULT"
SUBMISSION_ENV = "RAYKIT_SUBMISSION"
MARKS_ENV = "RAYKIT_FAULT_MARKS"
DISK_ENV = "RAYKIT_FAULT_DISK"
SECONDS_ENV = "RAYKIT_FAULT_SUBMISSION_SECONDS"

# The errors of the kit's own writes that mean the machine failed it: a full disk, a quota, a disk
# mounted read-only. Read from the kit's own OSError (its errno), never from what a tool printed: a
# compiler quotes the student's source (`#warning No space left on device`, a `#line` naming a file
# "Read-only file system"), so no word of a diagnostic is the machine's.
MACHINE_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EROFS})


class MachineFault(Exception):
    """The machine failed the kit's own work, by the kit's own evidence: its write's errno, or the
    free space it measured on its own folder's disk (disk_full). The step is not graded."""


def machine_errno(e: BaseException) -> bool:
    """Whether `e` is the kit's own write failing for the machine (MACHINE_ERRNOS)."""
    return isinstance(e, OSError) and e.errno in MACHINE_ERRNOS


def disk_full(folder: Path | str, room: int) -> str:
    """Why the disk of the kit's own `folder` is full, by the kit's own measure (statvfs), or "": read-only,
    no inode free, or less than `room` bytes free for an unprivileged user (the sandbox's ids are)."""
    try:
        st = os.statvfs(folder)
    except OSError as e:
        return f"the kit could not measure its scratch disk ({e.strerror})" if machine_errno(e) else ""
    if st.f_flag & os.ST_RDONLY:
        return "Read-only file system (the kit's scratch disk)"
    if st.f_files > 0 and st.f_favail == 0:
        return "No space left on device (the kit's scratch disk has no inode free)"
    free = st.f_bavail * st.f_frsize
    if free < room:
        return f"No space left on device (the kit's scratch disk has {free // 1024} KiB free)"
    return ""


def usage(folder: Path) -> int:
    """Bytes of the files under `folder` (not following links): what a tool wrote there."""
    total = 0
    for top, dirs, files in os.walk(folder):
        for name in files:
            with suppress(OSError):
                total += os.lstat(os.path.join(top, name)).st_size
    return total


def _items() -> list[tuple[str, str]]:
    return [(kind, target or "*") for item in os.environ.get(FAULT_ENV, "").split(",")
            for kind, _, target in [item.strip().partition("@")] if kind]


def fault(kind: str, step: str = "", name: str | None = None) -> bool:
    """Whether the test asks for the fault `kind` here (in submission `name`, default this process's,
    and step `step` when the hook names one)."""
    name = os.environ.get(SUBMISSION_ENV, "") if name is None else name
    for wanted, target in _items():
        base, once = wanted.removesuffix("-once"), wanted.endswith("-once")
        base, _, only = base.partition("#")
        if base != kind or target not in ("*", name) or (only and only != step):
            continue
        if not once:
            return True
        marks = Path(os.environ.get(MARKS_ENV) or "/nonexistent-raykit-marks")
        mark = marks / f"{wanted}@{target}".replace("/", "_").replace("#", "_")
        try:
            marks.mkdir(parents=True, exist_ok=True)
            fd = os.open(mark, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
            os.write(fd, str(os.getpid()).encode())
            os.close(fd)
            return True
        except FileExistsError:
            try:
                return mark.read_text() == str(os.getpid())
            except OSError:
                return False
        except OSError:
            return False
    return False


def after_placeholder() -> None:
    """The hook `killed`: ./kit check dies here, its placeholder written, as a crash of the kit would."""
    if fault("killed"):
        os.kill(os.getpid(), signal.SIGKILL)
    if fault("hang"):
        time.sleep(24 * 3600)


def abort(pid: int) -> None:
    """The hook `judge`: the judge `pid` aborts (unless it has just ended by itself)."""
    with suppress(ProcessLookupError):
        os.kill(pid, signal.SIGABRT)


def submission_seconds(limit: int) -> int:
    """./kit grade's limit for one submission: course.json's, or the self-test's (SECONDS_ENV)."""
    try:
        return int(os.environ.get(SECONDS_ENV) or limit)
    except ValueError:
        return limit


def child_env(name: str, env: dict[str, str]) -> dict[str, str]:
    """The environment of `./kit grade`'s child check of submission `name`: named (for the hooks and
    the logs), and with the hook `full-disk`, its scratch on the full disk."""
    env = dict(env, **{SUBMISSION_ENV: name})
    if env.get(DISK_ENV) and fault("full-disk", name=name):
        env["TMPDIR"] = env["RAYKIT_KIT_TEMP"] = env[DISK_ENV]      # the kit's own temporary folder too
    return env


def describe(e: BaseException) -> str:
    """An exception of the kit's as one line that names the fault (a full disk: its words)."""
    if isinstance(e, shutil.Error) and e.args and isinstance(e.args[0], list) and e.args[0]:
        first = e.args[0][0]        # (source, target, "[Errno 28] No space left on device: ...")
        if isinstance(first, tuple) and len(first) == 3:
            why = str(first[2]).split("] ", 1)[-1].split(": '", 1)[0]
            return f"{why}, copying the kit's files into its scratch"[:300]
        return str(first)[:300]
    if isinstance(e, MachineFault):
        return str(e)[:300]
    if isinstance(e, OSError) and e.strerror:
        return f"{e.strerror}" + (f" ({e.filename})" if e.filename else "")
    return f"{e.__class__.__name__}: {e}"[:300]


def to_student(reason: str, again: str = "ask your instructor to grade it again") -> str:
    """What a student is told of a step the grader failed, on every platform, in its own words after."""
    return (f"Not graded: the grader could not check this step ({reason}). This is the grader's fault, not "
            f"your code's: no points are taken away for it, and none are given yet; {again}.")

"""Faults of the grader, as opposed to the student's, caused on purpose by the self-test (selftest/faults.py).

The hooks (test only, never set by a platform): RAYKIT_FAULT is a comma-separated list of
KIND@SUBMISSION, where SUBMISSION is the name `./kit grade` gives the child check (RAYKIT_SUBMISSION;
"*" for any), KIND one of

  killed        the child ./kit check kills itself (SIGKILL) right after writing its placeholder record
  judge         the kit's judge is sent SIGABRT as soon as it starts a case (judge#NN: step NN only)
  full-disk     the child's scratch (TMPDIR) is the folder RAYKIT_FAULT_DISK, a disk the test filled

and a KIND ending in "-once" fires in the first process that meets it only (a marker in
RAYKIT_FAULT_MARKS), so the retry alone finds the machine well again.
"""

from __future__ import annotations

import os
import signal
from pathlib import Path

FAULT_ENV = "RAYKIT_FAULT"
SUBMISSION_ENV = "RAYKIT_SUBMISSION"
MARKS_ENV = "RAYKIT_FAULT_MARKS"
DISK_ENV = "RAYKIT_FAULT_DISK"

def _items() -> list[tuple[str, str]]:
    out = []
    for item in os.environ.get(FAULT_ENV, "").split(","):
        kind, _, target = item.strip().partition("@")
        if kind:
            out.append((kind, target or "*"))
    return out


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


def child_env(name: str, env: dict[str, str]) -> dict[str, str]:
    """The environment of `./kit grade`'s child check of submission `name`: named (for the hooks and
    the logs), and with the hook `full-disk`, its scratch on the full disk."""
    env = dict(env, **{SUBMISSION_ENV: name})
    if env.get(DISK_ENV) and fault("full-disk", name=name):
        env["TMPDIR"] = env[DISK_ENV]
    return env

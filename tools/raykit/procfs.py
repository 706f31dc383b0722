"""The kit's one reader of Linux's /proc: processes, their owners, states, sessions and command lines.

The boundary (sandbox/: ending a sandbox user's or a session's processes, reaping orphans) and the
self-tests (leftover processes) ask the same few questions of /proc; they ask them here. Every
function answers for a process that has gone, or a /proc that is not there (macOS), as "nothing":
an empty list, None or "". Standard library only, nothing of the kit: the core layer.
"""

from __future__ import annotations

import os

PROC = "/proc"


def pids() -> list[int]:
    """The ids of every process /proc lists (this one's included)."""
    try:
        return [int(e) for e in os.listdir(PROC) if e.isdigit()]
    except OSError:
        return []


def _read(pid: int, name: str) -> str | None:
    return _read_path(f"{PROC}/{pid}/{name}")


def status(pid: int) -> dict[str, str]:
    """/proc/PID/status as {field: value} (values stripped: "Uid" -> "0\\t0\\t0\\t0"); {} when gone."""
    text = _read(pid, "status")
    if text is None:
        return {}
    return {k: v.strip() for k, _, v in (line.partition(":") for line in text.splitlines()) if _}


def status_fields(pid: int, *names: str) -> dict[str, str]:
    """Only the named fields of /proc/PID/status (not "Name"), from one read, as status() gives them;
    {} when gone. A scan of every process asks two or three of its fifty: building the whole dict was
    most of the kit's CPU in ending a sandbox (docs/performance.md). The kernel escapes a newline in
    the one field a process sets, its name, so "\nUid:" can only start the real line."""
    text = _read(pid, "status")
    if text is None:
        return {}
    found = {}
    for name in names:
        at = text.find(f"\n{name}:")
        if at < 0:
            continue
        end = text.find("\n", at + 1)
        found[name] = text[at + len(name) + 2:end if end >= 0 else len(text)].strip()
    return found


def stat(pid: int) -> list[str]:
    """The fields of /proc/PID/stat after the command's name (which may hold spaces and parentheses):
    [state, ppid, pgrp, session, ...]; [] when gone."""
    text = _read(pid, "stat")
    if text is None or ")" not in text:
        return []
    return text[text.rfind(")") + 2:].split()


def state(pid: int) -> str:
    """The process's state letter ("R", "S", "Z", ...); "" when gone."""
    fields = stat(pid)
    return fields[0] if fields else ""


def started(pid: int) -> float | None:
    """When the process started, in seconds since the machine booted (as uptime() counts); None when gone."""
    fields = stat(pid)
    try:
        return int(fields[19]) / os.sysconf("SC_CLK_TCK")
    except (IndexError, ValueError, OSError):
        return None


def uptime() -> float:
    """Seconds since the machine booted (/proc/uptime); 0 where unknown."""
    try:
        return float((_read_path(f"{PROC}/uptime") or "0").split()[0])
    except (ValueError, IndexError):
        return 0.0


def alive(pid: int) -> bool:
    """Whether the process is there and not a zombie waiting for its parent."""
    return state(pid) not in ("", "Z")


def real_uid(pid: int) -> int | None:
    """The process's real user id; None when gone."""
    uid = status_fields(pid, "Uid").get("Uid", "").split()[:1]
    return int(uid[0]) if uid and uid[0].isdigit() else None


def parent(pid: int) -> int | None:
    fields = stat(pid)
    return int(fields[1]) if len(fields) > 1 and fields[1].lstrip("-").isdigit() else None


def session(pid: int) -> int | None:
    fields = stat(pid)
    return int(fields[3]) if len(fields) > 3 and fields[3].lstrip("-").isdigit() else None


def comm(pid: int) -> str:
    return (_read(pid, "comm") or "").strip()


def cmdline(pid: int) -> str:
    """The command line, its arguments joined by spaces; "" when gone (or a kernel thread)."""
    return (_read(pid, "cmdline") or "").replace("\0", " ").strip()


def cwd(pid: int) -> str:
    try:
        return os.readlink(f"{PROC}/{pid}/cwd")
    except OSError:
        return ""


def sysvipc(kind: str) -> list[str]:
    """The lines of /proc/sysvipc/KIND ("shm", "msg", "sem"): a header, then one per object; [] when
    there is none."""
    return (_read_path(f"{PROC}/sysvipc/{kind}") or "").splitlines()


def mount_points() -> set[str]:
    """Where something is mounted, as this process sees it (/proc/self/mountinfo's fifth field)."""
    lines = (_read_path(f"{PROC}/self/mountinfo") or "").splitlines()
    return {fields[4] for fields in (line.split() for line in lines) if len(fields) > 4}


def _read_path(path: str) -> str | None:
    try:
        with open(path, "rb") as f:
            return f.read().decode("utf-8", "replace")
    except OSError:
        return None


def cpu_flags() -> set[str]:
    """The CPU's feature flags (/proc/cpuinfo's "flags": "fma", "avx2", ...); empty where unknown."""
    text = _read_path(f"{PROC}/cpuinfo") or ""
    return {w for line in text.splitlines() if line.startswith("flags") for w in line.partition(":")[2].split()}

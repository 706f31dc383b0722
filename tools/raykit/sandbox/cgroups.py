"""Control groups for a grading slot (cgroup v2, or v1 as on a plain Debian host run as root): memory and a kill that ends every process at once."""

from __future__ import annotations

import os
import signal
import time
from contextlib import suppress
from pathlib import Path

from .limits import Limits, MiB


def make_cgroups(slot: int, limits: Limits) -> list[str]:
    """Control groups for one grading slot, where the kit can make them: cgroup v2 (memory.max,
    pids.max) or v1 (memory and pids hierarchies). [] when neither can be made (not root, a
    read-only tree in a container): the rlimits still apply."""
    if os.geteuid() != 0 or os.environ.get("RAYKIT_NO_CGROUP") == "1":
        return []
    name = f"raykit-slot{slot}-{os.getpid()}"
    base = Path("/sys/fs/cgroup")
    made: list[str] = []
    try:
        if (base / "cgroup.controllers").is_file():          # v2, unified
            wanted = {"memory", "pids"}
            enabled = set((base / "cgroup.subtree_control").read_text().split())
            if not wanted <= enabled:
                return []
            group = base / name
            group.mkdir()
            made.append(str(group))
            (group / "memory.max").write_text(str(limits.memory_mb * MiB))
            (group / "pids.max").write_text(str(limits.processes * 2))
            return made
        for controller, settings in (("memory", {"memory.limit_in_bytes": limits.memory_mb * MiB}),
                                     ("pids", {"pids.max": limits.processes * 2})):
            top = base / controller
            if not (top / "cgroup.procs").is_file():
                continue
            group = top / name
            group.mkdir()
            made.append(str(group))
            for key, value in settings.items():
                (group / key).write_text(str(value))
            if controller == "memory" and (group / "memory.memsw.limit_in_bytes").is_file():
                with suppress(OSError):
                    (group / "memory.memsw.limit_in_bytes").write_text(str(limits.memory_mb * MiB))
        if not any("/memory/" in g for g in made):
            raise OSError("no memory controller")
        return made
    except OSError:
        for g in made:
            with suppress(OSError):
                os.rmdir(g)
        return []


def kill_cgroup(group: Path) -> None:
    for _ in range(50):
        try:
            pids = [int(p) for p in (group / "cgroup.procs").read_text().split()]
        except (OSError, ValueError):
            return
        if not pids:
            return
        for p in pids:
            with suppress(OSError):
                os.kill(p, signal.SIGKILL)
        time.sleep(0.02)

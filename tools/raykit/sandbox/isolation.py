"""The isolation chosen for a grading (choose): the one object every path from a student's file to a process goes through."""

from __future__ import annotations

import os
import resource
import shutil
import time
from contextlib import suppress
from dataclasses import dataclass, field
from pathlib import Path

from .. import heldtmp
from ..sandbox_slots import RUN_PROCESSES, clear_keyrings, prepare_keyctl, scratch_words, use_kit_temp
from .limits import Limits, MiB
from .ids import COMPILE_UID_OFFSET, claim_uid
from .reaping import become_subreaper, kill_uid, reap_orphans
from .ipc import clean_uid_files
from .cgroups import kill_cgroup, make_cgroups
from .bwrap import bwrap_argv, bwrap_sizes, bwrap_works, install_bwrap
from .runner import _run_tool
from .view import hide_secrets


@dataclass
class Isolation:
    mode: str                   # "bwrap", "user:UID" or "none"
    description: str            # one line for the report
    uid: int = 0                # the dedicated user id the code runs as (0: none taken)
    # The compile's own id: the judge ends every process of `uid` after each case, while the next
    # step's compile may be running (the build is pipelined), so the two never share one.
    compile_uid: int = 0
    limits: Limits = field(default_factory=Limits)
    cgroups: list[str] = field(default_factory=list)    # control group folders the code is put in
    own: bool = False           # the student's own steps: no boundary at all

    @property
    def sandboxed(self) -> bool:
        return self.mode != "none"

    # --- processes inside the boundary ------------------------------------------------------
    def wrapper(self, ro: list[tuple[Path, str]], rw: list[tuple[Path, str]], chdir: str,
                tmpfs: list[tuple[str, int]] = (), use: str = "") -> list[str]:
        """The argv prefix that starts a command inside the boundary: bubblewrap's options, or
        nothing. Inside, the allow-list of the machine (system_view), a fresh /dev, /proc and
        HIDDEN, then `ro` and `rw`, host folders (or files) bound at the paths given, and `tmpfs`,
        sized empty folders. Nothing else of the machine exists there."""
        return bwrap_argv(ro, rw, chdir, tmpfs, use) if self.mode == "bwrap" else []

    def preexec(self, memory_mb: int, uid: int):
        """What a child does between fork and exec to enter the boundary: its own process group,
        the control group, the rlimits, then the dedicated user id `uid` (last: joining a control
        group and lowering limits need the rights it drops)."""
        limits, cgroups = self.limits, list(self.cgroups)
        prepare_keyctl()

        def enter() -> None:
            os.setpgid(0, 0)
            for group in cgroups:
                with suppress(OSError):
                    Path(group, "cgroup.procs").write_text(str(os.getpid()))
            for res, value in ((resource.RLIMIT_AS, memory_mb * MiB), (resource.RLIMIT_CORE, 0),
                               (resource.RLIMIT_FSIZE, limits.file_mb * MiB),
                               (resource.RLIMIT_CPU, limits.cpu_seconds)):
                resource.setrlimit(res, (value, value))
            if uid:
                os.setgroups([])
                os.setgid(uid)
                os.setuid(uid)
                clear_keyrings()        # nothing an earlier compile or run of this id kept there
                resource.setrlimit(resource.RLIMIT_NPROC, (limits.processes, limits.processes))

        return enter

    def run_env(self, answers: Path, scratch: Path) -> dict[str, str]:
        """The environment that tells the judge (remote.cpp) how to start the answers program: the
        same wrapper, user id, limits and control groups as the compile had. `scratch` is the kit's
        folder (sandbox.Scratch); the judge makes each run's own inside it and, where bubblewrap
        cannot size a tmpfs, binds that one where the wrapper names `scratch`."""
        inside = "/tmp/raykit/answers" if self.mode == "bwrap" else str(answers)
        work = "/tmp/raykit/scratch" if self.mode == "bwrap" else str(scratch)
        # RAYKIT_BWRAP_UNSIZED=1: the self-test's way to grade as with a bubblewrap without --size
        # (Debian 11's 0.4.1), whose scratch folder is a host folder bound read-write.
        sized = self.mode == "bwrap" and bwrap_sizes() and os.environ.get("RAYKIT_BWRAP_UNSIZED") != "1"
        prefix = self.wrapper([(answers, inside)], [] if sized else [(scratch, work)], work,
                              [(work, self.limits.scratch_mb * MiB)] if sized else [], use="run")
        limits = self.limits
        # The answers program's own process limit (RUN_PROCESSES): under the user isolation the
        # judge sets it after taking the id; under bubblewrap, which needs processes of its own, the
        # last word of the wrapper sets it (nothing of the student's runs before: static
        # constructors come after the exec). RLIMIT_NPROC counts the processes of the sandbox's user
        # id in its user namespace (kernels >= 5.14), or of its real uid: 1 either way.
        prlimit = shutil.which("prlimit", path="/usr/bin:/bin")
        run_processes = RUN_PROCESSES if self.mode != "bwrap" or prlimit else 0
        if self.mode == "bwrap" and prlimit:
            prefix += [prlimit, f"--nproc={RUN_PROCESSES}:{RUN_PROCESSES}", "--"]
        wrapper_processes = limits.processes if self.mode == "bwrap" else RUN_PROCESSES
        return {"RAYKIT_ISOLATION": self.mode, "RAYKIT_ANSWERS": str(answers), "RAYKIT_SANDBOX_EXE": inside,
                "RAYKIT_SCRATCH": str(scratch), "RAYKIT_SANDBOX_ARGV": "\x1f".join(prefix),
                "RAYKIT_SANDBOX_UID": str(self.uid),
                "RAYKIT_SANDBOX_CGROUPS": ":".join(self.cgroups),
                "RAYKIT_SANDBOX_LIMITS": f"{limits.run_memory_mb * MiB} {wrapper_processes} "
                                         f"{limits.file_mb * MiB} {limits.cpu_seconds} {run_processes}"}

    # --- the compile and the link -----------------------------------------------------------
    def tool(self, kind: str, argv: list[str], cwd: Path, cache=None) -> tuple[int, str]:
        """Runs one compile (`kind` "compile") or link ("link") of the student's answers program inside
        the boundary (checking.build_step): its outputs are copied to where the command names them
        only when they are regular files. The exit status (0 or 1) and the diagnostics, as the
        student's own. `cache`, when given, is the build layer's store of compiled objects
        (objcache.ObjectCache): called as cache(argv, work, source_dir, isolation, wrapper) for a
        compile, it answers fetch(out) and store(out, text); the boundary keeps none of its own."""
        with heldtmp.held("raykit-build-") as work:
            return _run_tool(self, kind, argv, cwd, work, cache)

    def clean_files(self, uid: int) -> None:
        """What `uid` left in the shared temporary folders. Under bubblewrap it has none to write:
        /tmp, /var/tmp and /dev/shm are its own empty mounts, gone with it (and a scan of a busy
        /tmp costs 15 ms a step)."""
        if self.mode != "bwrap":
            clean_uid_files(uid)

    def close(self) -> None:
        for group in self.cgroups:
            kill_cgroup(Path(group))
            with suppress(OSError):
                os.rmdir(group)
        if not (self.uid or self.compile_uid):
            return                  # no id of the sandbox's: nothing of the graded code's to reap
        kill_uid(self.uid, self.compile_uid)        # both ids in one scan of /proc a round
        for uid in (self.uid, self.compile_uid):
            if uid:
                self.clean_files(uid)
        for _ in range(25):     # a process killed a moment ago becomes a zombie a moment later
            if not reap_orphans({self.uid, self.compile_uid}):
                break
            time.sleep(0.02)


NONE_OWN = Isolation("none", "not sandboxed (your own steps: the code runs as you)", own=True)


def choose(wanted: str = "auto", slot: int = 0) -> Isolation:
    """The isolation for a folder the kit did not write: `wanted` is auto, bwrap, user or none."""
    limits = Limits.from_env()
    root = os.geteuid() == 0
    uid = claim_uid(slot) if root and wanted != "none" else 0
    if uid:
        use_kit_temp()      # the kit's own temporary files where graded code cannot fill or list them
    if wanted in ("auto", "bwrap"):
        install_bwrap()
    if wanted in ("auto", "bwrap") and bwrap_works(uid or None):
        iso = Isolation("bwrap", "sandboxed with bubblewrap: only the system's read-only parts and its own files, no network, "
                                 "own process namespace, " + (f"user id {uid}" if uid else "your user id"),
                        uid=uid, limits=limits)
    elif wanted == "bwrap":
        raise RuntimeError("bubblewrap cannot run here (not installed, or namespaces are not allowed)")
    elif wanted in ("auto", "user") and root:
        iso = Isolation(f"user:{uid}", f"sandboxed as the unprivileged user id {uid}: it cannot read the kit's "
                                       "answers nor another sandbox's files; it writes its own folder and, "
                                       "like any user, /tmp (its files there removed after each step); its "
                                       "processes are ended and its keyrings emptied after each case; the "
                                       "network is NOT isolated (bubblewrap could not run here)",
                        uid=uid, limits=limits)
        hide_secrets()
        iso.description += "; " + scratch_words(uid, limits.scratch_mb)
    elif wanted == "user":
        raise RuntimeError("the user isolation needs the kit to run as root")
    elif wanted == "none":
        return Isolation("none", "NOT sandboxed (--isolation none): the code ran with the grader's rights",
                         limits=limits)
    else:
        return Isolation("none", "NOT sandboxed: bubblewrap could not run and the kit is not root, so the "
                                 "code ran with the grader's rights. Install bubblewrap, or grade as root.",
                         limits=limits)
    iso.compile_uid = uid + COMPILE_UID_OFFSET if uid else 0
    become_subreaper()
    iso.cgroups = make_cgroups(slot, limits)
    iso.description += "; limits: " + limits.words() + (
        "; in a control group of " + f"{limits.memory_mb} MiB" if iso.cgroups else "; rlimits only (no control group here)")
    return iso

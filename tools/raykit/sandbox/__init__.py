"""The trust boundary: where a student's code is compiled and run while it is graded.

One object, `Isolation`, holds everything that keeps graded code apart, and every path from a
student's file to a process goes through it:

- the compile and the link of the student's answers program (`Isolation.tool`, called by
  checking.build_step for each): the sources are copied into a fresh folder with the
  kit's public headers beside them, and the compiler runs inside the boundary, where nothing else
  of the kit can be read — not solutions/, the hidden cases, the mutants, .git, the reference's
  objects, nor other students' folders;
- the run of that program by the judge (tests/support/remote.cpp), which gets from `run_env()`
  the same wrapper, user id, limits and control group.

The modes, best first:
- bwrap: bubblewrap, where namespaces are allowed. An allow-list of the machine (system_view: /usr
  and the loader's links, the bits of /etc a compiler needs, the compiler's own folder), fresh /dev,
  /proc, /tmp and /dev/shm, one writable folder, no network, its own PID namespace. When the kit runs as root it first takes a dedicated
  user id, so the sandbox's real user owns nothing (bubblewrap started by root would otherwise map
  its unprivileged user to real uid 0, which still owns every root-owned file and socket);
- user: bubblewrap cannot run but the kit is root (a Docker container, as on Gradescope): the same
  dedicated user id without namespaces. It reads only world-readable files, the kit's own are made
  unreadable to it, and every process of that id is ended after each case. The network stays open;
- none: the student checks their own steps (the code runs as they do), or nothing else is possible,
  which the report says in capitals.

Limits (`Limits`, defaults for a 2-core machine with 2 GiB a grading slot; RAYKIT_LIMITS overrides
them, e.g. "compile_seconds=10,memory_mb=512"): rlimits everywhere (they work in containers), and a
control group on top where the kit can make one (cgroup v2, or v1 as on a plain Debian host run as
root), which also bounds the memory of tmpfs files and lets a timeout end every process at once.
"""

from __future__ import annotations

from .limits import Limits, MiB, SECRET_PARTS  # noqa: F401
from .ids import (COMPILE_UID_OFFSET, FIRST_UID, FIRST_UID_ENV, LOCK_DIRS, UID_CLAIMS, UID_RANGE,  # noqa: F401
                  claim_range, claim_uid, first_uid)
from .reaping import kill_session, kill_uid, session_members  # noqa: F401
from .bwrap import bwrap_works  # noqa: F401
from .runner import SANDBOX_FAILED, copy_regular  # noqa: F401
from .view import Scratch, WithheldFromOthers, hide_secrets  # noqa: F401
from .isolation import Isolation, NONE_OWN, choose  # noqa: F401

# The names the package re-exports: those its users (code, the self-test's scripts, the comments that
# name them) read through it (pyflakes reads them as used).
__all__ = ["Limits", "MiB", "SECRET_PARTS", "COMPILE_UID_OFFSET", "FIRST_UID", "FIRST_UID_ENV", "LOCK_DIRS",
           "UID_CLAIMS", "UID_RANGE", "claim_range", "claim_uid", "first_uid", "kill_session", "kill_uid",
           "session_members", "bwrap_works", "SANDBOX_FAILED", "copy_regular", "Scratch", "WithheldFromOthers",
           "hide_secrets", "Isolation", "NONE_OWN", "choose"]

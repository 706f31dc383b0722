"""Where a student's code runs while it is graded: the isolation the kit can get here.

The judge (a step's test program) starts the student's answers program itself
(tests/support/remote.cpp); this module chooses how, prepares the one folder the
student's code may write, and says in words what was done:

- bwrap: bubblewrap, where namespaces are allowed — a read-only view of the machine
  with the kit, the homes and /tmp hidden, no network, its own PID namespace (every
  process it starts is ended with the case), an unprivileged user id;
- user: when bubblewrap cannot run but the kit runs as root (a Docker container, as
  on Gradescope) — a dedicated unprivileged user id, which can write only its scratch
  folder, cannot read the kit's answers, and whose every process is ended with the case;
- none: neither is possible (say so plainly), or the student grades their own steps.
"""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .common import BUILD, ROOT

# User ids for the "user" isolation, one per parallel grading slot. Never in
# /etc/passwd: nothing but the sandboxed processes ever has them.
FIRST_UID = 64000

# What the sandboxed code must not read even where the machine is readable: the
# kit (solutions, the hidden cases' sources, the reference answers programs), and
# the kit's git history, whose objects hold every committed solution. (In a git
# worktree .git is a file and the objects live in another checkout's folder, which
# the kit does not change: grade from a plain clone or a copy without .git.)
SECRET_PARTS = ["solutions", "tests/hidden", "tests/mutants", "build", ".git"]


@dataclass
class Isolation:
    mode: str           # "bwrap", "user:UID" or "none"
    description: str    # one line for the report

    @property
    def sandboxed(self) -> bool:
        return self.mode != "none"


NONE_OWN = Isolation("none", "not sandboxed (your own steps: the code runs as you)")

_probe: dict[str, bool] = {}


def bwrap_works() -> bool:
    if "bwrap" not in _probe:
        ok = False
        if shutil.which("bwrap"):
            try:
                r = subprocess.run(["bwrap", "--ro-bind", "/", "/", "--dev", "/dev", "--proc", "/proc",
                                    "--unshare-all", "--unshare-user", "--uid", "65534", "--gid", "65534",
                                    "--die-with-parent", "--cap-drop", "ALL", "true"],
                                   capture_output=True, timeout=20)
                ok = r.returncode == 0
            except (OSError, subprocess.TimeoutExpired):
                ok = False
        _probe["bwrap"] = ok
    return _probe["bwrap"]


def install_bwrap() -> None:
    """Installs bubblewrap when it is missing and apt can; without it the isolation falls back."""
    from .common import KitError, note
    from .packages import ensure_packages
    if shutil.which("bwrap") is None:
        try:
            ensure_packages("sandbox")
        except KitError as e:
            note(f"kit: bubblewrap is not installed ({str(e).splitlines()[0]}); grading without it")


def choose(wanted: str = "auto", slot: int = 0) -> Isolation:
    """The isolation for a folder the kit did not write: `wanted` is auto, bwrap, user or none."""
    if wanted in ("auto", "bwrap"):
        install_bwrap()
    if wanted in ("auto", "bwrap") and bwrap_works():
        return Isolation("bwrap", "sandboxed with bubblewrap: read-only system, kit hidden, no network, "
                                  "own process namespace, unprivileged user")
    if wanted == "bwrap":
        raise RuntimeError("bubblewrap cannot run here (not installed, or namespaces are not allowed)")
    if wanted in ("auto", "user") and os.geteuid() == 0:
        uid = claim_uid(slot)
        return Isolation(f"user:{uid}",
                         f"sandboxed as the unprivileged user id {uid}: it writes only a scratch "
                         "folder and cannot read the kit's answers; every process it starts is ended; "
                         "the network is NOT isolated (bubblewrap could not run here)")
    if wanted == "user":
        raise RuntimeError("the user isolation needs the kit to run as root")
    if wanted == "none":
        return Isolation("none", "NOT sandboxed (--isolation none): the code ran with the grader's rights")
    return Isolation("none", "NOT sandboxed: bubblewrap could not run and the kit is not root, so the "
                             "code ran with the grader's rights. Install bubblewrap, or grade as root.")


_claimed: dict[int, object] = {}


def claim_uid(slot: int) -> int:
    """A sandbox user id no other grading on this machine is using.

    After each case every process of the id is killed, so two gradings must never share one
    (two instructors' runs, a batch beside a check). Each id is claimed with an exclusive lock
    on a file, held until this process ends.
    """
    import fcntl
    lock_dir = Path("/run/lock") if Path("/run/lock").is_dir() else Path(tempfile.gettempdir())
    for uid in range(FIRST_UID + slot, FIRST_UID + 4096, 64):
        if uid in _claimed:
            return uid
        f = open(lock_dir / f"raykit-sandbox-{uid}.lock", "w")
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            f.close()
            continue
        _claimed[uid] = f
        return uid
    raise RuntimeError("every sandbox user id is in use by other gradings on this machine")


class Scratch:
    """A fresh folder that the student's code may write, holding a copy of its answers program."""

    def __init__(self, isolation: Isolation, answers: Path | None):
        self.isolation = isolation
        self.path = Path(tempfile.mkdtemp(prefix="raykit-sandbox-"))
        self.answers = None
        if answers is not None and answers.is_file():
            self.answers = self.path / "answers"
            shutil.copy2(answers, self.answers)
            os.chmod(self.answers, 0o755)
        if isolation.mode.startswith("user:"):
            uid = int(isolation.mode[5:])
            os.chown(self.path, uid, uid)
            os.chmod(self.path, 0o700)
            if self.answers is not None:
                os.chown(self.answers, uid, uid)
            hide_secrets()

    def env(self) -> dict[str, str]:
        hidden = [str(ROOT), str(BUILD)]
        home = os.environ.get("HOME")
        if home:
            hidden.append(home)
        return {"RAYKIT_ISOLATION": self.isolation.mode, "RAYKIT_SCRATCH": str(self.path),
                "RAYKIT_HIDE": ":".join(hidden), "RAYKIT_ANSWERS": str(self.answers or "")}

    def close(self) -> None:
        shutil.rmtree(self.path, ignore_errors=True)


def hide_secrets() -> None:
    """Under the user isolation, the answers must not be readable by other users.

    Takes read and search rights from 'others' on the kit's secret folders (the kit
    runs as root here, and nothing but the sandbox is 'other').
    """
    for part in SECRET_PARTS:
        p = ROOT / part
        if p.is_dir():
            mode = p.stat().st_mode
            if mode & (stat.S_IROTH | stat.S_IXOTH):
                os.chmod(p, mode & ~(stat.S_IROTH | stat.S_IWOTH | stat.S_IXOTH))

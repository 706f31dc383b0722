"""What the user isolation must not see: the kit's secret parts and the class's folders closed to others (and put back), and each run's scratch folder."""

from __future__ import annotations

from contextlib import suppress
from typing import TYPE_CHECKING
import json
import os
import shutil
import signal
import stat
import tempfile
from pathlib import Path

from .. import atomic
from ..common import BUILD, ROOT
from ..sandbox_slots import SCRATCH_PREFIX, mount_scratch, sweep_scratch_mounts, unmount
from .limits import MiB, SECRET_PARTS
from .reaping import kill_uid, reap_orphans
from .bwrap import bwrap_works
from .runner import copy_regular

if TYPE_CHECKING:        # annotations only: the higher module imports this one
    from .isolation import Isolation


class Scratch:
    """A step's folder for the runs of the student's code: a copy of its answers program, and the
    parent of the folders those runs work in. The judge (tests/support/remote.cpp) makes a fresh one
    inside it at every start of the answers program, a case re-run alone included (owned by the
    sandbox's user id, mode 0700, removed when that program stops): nothing one run writes is there
    for the next. This folder and the program stay the kit's: with a sandbox id, the folder 0710 and
    the program 0750, both root's with the id's group, so that id alone may cross the one and start
    the other (no other sandbox id may list, read, run or copy them, even knowing the path), and
    nobody but the kit may write or swap anything here (0711 and 0755 without an id, inside a
    folder of the kit's, 0700, that no other user may cross).

    Under the user isolation, where the kit may mount (root with CAP_SYS_ADMIN), the folder is a
    tmpfs of its own, Limits.scratch_mb plus the program's size and sandbox_slots.SCRATCH_INODES
    inodes: the runs' folders and their TMPDIR cannot fill a disk. `mount_note` says why not when
    it is not (a container: Docker's default profile refuses mount)."""

    def __init__(self, isolation: Isolation, answers: Path | None):
        self.isolation = isolation
        self.mount_note = ""
        self.mounted = False
        uid = isolation.uid
        # The folder named for the grading (SCRATCH_PREFIX + its pid: sweep_scratch_mounts, which
        # removes those of gradings that were killed).
        sweep_scratch_mounts(tempfile.gettempdir(), once=True)
        self.top = Path(tempfile.mkdtemp(prefix=f"{SCRATCH_PREFIX}{os.getpid()}-"))
        self.path = self.top
        if not uid:
            # No sandbox id: bubblewrap binds the program and the folder in at paths of its own, and
            # without isolation the program runs as the kit. Nobody else need reach them on the host,
            # so they sit in the grading's folder, left 0700 (mkdtemp): code graded under the user
            # isolation on this kernel (another kit's grading, or a later one beside a killed
            # grading's leftovers) can neither list, read nor run a classmate's program here.
            self.path = self.top / "scratch"
            self.path.mkdir()
        if uid and isolation.mode != "bwrap" and answers is not None and answers.is_file():
            size = isolation.limits.scratch_mb + answers.stat().st_size // MiB + 1
            self.mount_note = mount_scratch(self.path, uid, size)
            self.mounted = not self.mount_note
        os.chmod(self.path, 0o710 if uid else 0o711)
        if uid:
            os.chown(self.path, 0, uid)
        self.answers = None
        if answers is not None and answers.is_file():
            self.answers = self.path / "answers"
            copy_regular(answers, self.answers, 0o750 if uid else 0o755)
            if uid:
                os.chown(self.answers, 0, uid)

    def env(self) -> dict[str, str]:
        if not self.isolation.sandboxed or self.answers is None:
            return {"RAYKIT_ISOLATION": "none", "RAYKIT_SCRATCH": str(self.path),
                    "RAYKIT_ANSWERS": str(self.answers or "")}
        return self.isolation.run_env(self.answers, self.path)

    def between_runs(self) -> None:
        """Before a case re-run alone (runcases.rerun_timeouts), under the user isolation: every
        process of the sandbox's id is ended, its keyrings emptied, and what it wrote to the shared
        temporary folders removed, as after a step. Under bubblewrap those are each start's own."""
        if self.isolation.uid and self.isolation.mode != "bwrap":
            kill_uid(self.isolation.uid)
            self.isolation.clean_files(self.isolation.uid)
            reap_orphans({self.isolation.uid})

    def close(self) -> None:
        if self.isolation.uid:
            kill_uid(self.isolation.uid)
            self.isolation.clean_files(self.isolation.uid)
            reap_orphans({self.isolation.uid})
        if self.mounted:
            unmount(self.path)
        shutil.rmtree(self.top, ignore_errors=True)


def hide_secrets() -> None:
    """Under the user isolation, the kit must not be readable by other users.

    Takes read, write and search rights from 'others' on the kit's root (the kit runs as root here,
    and nothing but the sandbox is 'other'), and on its secret parts too (SECRET_PARTS: the
    reference, every test file, build/ with other students' folders, the bench's reference code,
    the git history), in case the root stays open (a mount whose modes cannot change). Graded code
    needs nothing of the kit: the compile reads its own copy of the headers and the step's files
    in a private folder, the link private copies of the objects, the run a copy of the answers
    program in its scratch folder; the kit's driver runs as root. Users of the machine other than
    the kit's owner and group no longer read the kit either, and the rights are not put back: a
    grading in progress in another slot would be left open, and a kit that graded this way stays
    as closed as it was while grading (its owner and group keep their rights).
    """
    for p in [ROOT] + [ROOT / part for part in SECRET_PARTS]:
        with suppress(OSError):
            if p.exists() and not p.is_symlink():
                mode = p.stat().st_mode
                if mode & 0o007:
                    os.chmod(p, mode & ~0o007)


WITHHELD = BUILD / "withheld-modes.json"     # {path: [mode, pid]}: what to put back should the kit die


def _withheld_read() -> dict:
    try:
        data = json.loads(WITHHELD.read_text())
        return data if isinstance(data, dict) else {}
    except (OSError, ValueError):
        return {}


def _withheld_write(data: dict) -> None:
    with suppress(OSError):
        if data:
            BUILD.mkdir(parents=True, exist_ok=True)
            atomic.write(WITHHELD, json.dumps(data))
        else:
            WITHHELD.unlink(missing_ok=True)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
        return True
    except ProcessLookupError:
        return False
    except OSError:
        return True


def restore_withheld() -> list[str]:
    """Puts back the modes a grading took and could not put back itself (killed by SIGKILL, the
    machine stopped): each recorded path whose grading process is gone. The paths put back."""
    data, done = _withheld_read(), []
    for path, (mode, pid) in list(data.items()):
        if _alive(int(pid)) and int(pid) != os.getpid():
            continue
        with suppress(OSError):
            os.chmod(path, int(mode))
            done.append(path)
        del data[path]
    _withheld_write(data)
    return done


class WithheldFromOthers:
    """While grading as root (where the user isolation may be chosen), the class folder given to
    ./kit grade is made unreadable to 'others', as the sandbox's user ids are, and its mode put back
    after: at the end, on an exception or Ctrl-C (finally), on SIGTERM or SIGHUP (turned into an
    exit), at interpreter exit (atexit), and after SIGKILL by the next grading (restore_withheld,
    from a record in build/). Taken from the folder itself, one mode to put back; from each
    submission in it instead when the folder holds the temporary folder the sandbox works in (a
    class kept in /tmp itself), which the sandbox's user must still cross."""

    def __init__(self, folder: Path, entries: list[Path], isolation: str = "auto"):
        self.paths: list[Path] = []
        self.taken: dict[str, int] = {}
        self.handlers: dict[int, object] = {}
        if os.geteuid() == 0:
            restore_withheld()      # a grading killed before it could put a mode back
        if os.geteuid() != 0 or isolation in ("none", "bwrap") or (isolation == "auto" and bwrap_works()):
            return                  # not the user isolation: bubblewrap shows no class folder at all
        folder = folder.resolve()
        tmp = Path(tempfile.gettempdir()).resolve()
        self.paths = list(entries) if tmp == folder or folder in tmp.parents else [folder]

    def __enter__(self) -> "WithheldFromOthers":
        if not self.paths:
            return self
        import atexit
        atexit.register(self.restore)
        with suppress(ValueError):  # not the main thread: atexit and finally still put them back
            for sig in (signal.SIGTERM, signal.SIGHUP):
                if signal.getsignal(sig) == signal.SIG_DFL:
                    self.handlers[sig] = signal.signal(sig, _exit_on_signal)
        record = _withheld_read()
        for p in self.paths:
            try:
                st = os.lstat(p)
                if stat.S_ISLNK(st.st_mode) or not st.st_mode & 0o007:
                    continue
                record[str(p)] = [stat.S_IMODE(st.st_mode), os.getpid()]
                _withheld_write(record)         # recorded before it is changed
                os.chmod(p, stat.S_IMODE(st.st_mode) & ~0o007)
                self.taken[str(p)] = stat.S_IMODE(st.st_mode)
            except OSError:
                continue
        return self

    def restore(self) -> None:
        record = _withheld_read()
        for path, mode in list(self.taken.items()):
            with suppress(OSError):
                os.chmod(path, mode)
            record.pop(path, None)
            del self.taken[path]
        _withheld_write(record)
        for sig, old in self.handlers.items():
            with suppress(ValueError):
                signal.signal(sig, old)
        self.handlers = {}

    def __exit__(self, *exc) -> None:
        self.restore()


def _exit_on_signal(signum, frame) -> None:
    raise SystemExit(128 + signum)

"""Ending graded code: every process of a sandbox id, or of a session, killed and reaped, the kit made their subreaper."""

from __future__ import annotations

import os
import signal
import time
from contextlib import suppress

from .. import procfs
from ..sandbox_slots import clear_keyrings, prepare_keyctl


def become_subreaper() -> None:
    """Orphans of the graded code (killed sandboxes' processes) are given to this process, which
    reaps them (reap_children), instead of to PID 1, which in some containers never does."""
    with suppress(OSError, AttributeError):
        import ctypes
        ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0)     # PR_SET_CHILD_SUBREAPER


def reap_orphans(uids: set[int]) -> bool:
    """Reaps the graded code's dead orphans given to us (zombies of the sandbox's ids whose parent
    is this process), each by its pid: never waitpid(-1), which could take a build's exit status
    from the subprocess that waits for it. Returns whether a child of ours with one of the ids is
    still there (alive, or a zombie not reaped yet): one scan of /proc answers both."""
    me, wanted = str(os.getpid()), {str(u) for u in uids if u}
    if not wanted:
        return False
    left = False
    for p in procfs.pids():
        fields = procfs.status_fields(p, "State", "PPid", "Uid")    # one read: the same moment
        owner = fields.get("Uid", "").split()[:1]
        if fields.get("PPid") != me or not owner or owner[0] not in wanted:
            continue
        if not fields.get("State", "").startswith("Z"):
            left = True
            continue
        with suppress(ChildProcessError):
            if os.waitpid(p, os.WNOHANG)[0] == 0:
                left = True
    return left


def _owned_by(pid: int, uids: set[str]) -> bool:
    """Whether process `pid` is alive (not a zombie waiting for its parent) with its real user id in `uids`."""
    fields = procfs.status_fields(pid, "State", "Uid")     # one read: owner and state of the same moment
    owner = fields.get("Uid", "").split()[:1]
    return bool(owner) and owner[0] in uids and not fields.get("State", "").startswith("Z")


def _signal_all_as(uid: int) -> None:
    """A helper that takes the id and signals all it may signal (kill -1), and empties the id's keyrings."""
    pid = os.fork()
    if pid == 0:
        try:
            os.setgroups([])
            os.setgid(uid)
            os.setuid(uid)
            with suppress(OSError):  # none left to signal
                os.kill(-1, signal.SIGKILL)
            clear_keyrings()        # what the id's processes kept in its keyrings outlives them
        finally:
            os._exit(0)
    os.waitpid(pid, 0)


def kill_uid(*uids: int) -> None:
    """Ends every process whose real user id is one of `uids`: for each, a helper that takes the id
    and signals all it may signal (kill -1), repeated while any is left (a fork between two rounds),
    and empties the id's keyrings (at least once, with no process left too). One scan of /proc a
    round, for all the ids, after the signals: what decides is that none is left after them."""
    wanted = [u for u in dict.fromkeys(uids) if u]
    if not wanted or os.geteuid() != 0:
        return
    prepare_keyctl()
    names = {str(u) for u in wanted}
    for _ in range(20):
        for uid in wanted:
            _signal_all_as(uid)
        if not any(_owned_by(p, names) for p in procfs.pids()):
            return
        time.sleep(0.02)


def session_members(sid: int) -> list[int]:
    """The live processes of session `sid` but this one: zombies have ended (as in _owned_by), and
    one whose parent never reaps it (PID 1 of a container) would otherwise be waited on for ever."""
    found = []
    for p in procfs.pids():
        if p == os.getpid():
            continue
        fields = procfs.stat(p)         # one read: state and session of the same moment
        if len(fields) > 3 and fields[0] != "Z" and fields[3] == str(sid):
            found.append(p)
    return found


def kill_session(sid: int) -> int:
    """Ends every process of session `sid` (a child started with start_new_session has sid = its
    pid; cmake, ninja and the compilers it starts inherit it), repeated until none is left.
    Returns how many were signalled."""
    ended = 0
    if sid <= 1:
        return 0
    for _ in range(50):
        left = session_members(sid)
        if not left:
            break
        for p in left:
            with suppress(OSError):
                os.kill(p, signal.SIGKILL)
                ended += 1
        time.sleep(0.02)
    return ended

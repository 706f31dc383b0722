"""The sandbox's user ids: one per grading slot, never an id with a name, claimed twice: with a lock
file only root can write (what kits of older code beside this one look at), and with an abstract unix
socket named after the id, which every root file system on the kernel sees."""

from __future__ import annotations

import os
import stat
import sys
from contextlib import suppress

from .. import procfs


# User ids for the sandbox, one per parallel grading slot. Never in /etc/passwd: nothing but the
# sandboxed processes ever has them (an id that has a name there is skipped).
FIRST_UID = 64000
UID_CLAIMS = 32                 # ids FIRST_UID + slot + 64 k, k < UID_CLAIMS, run the code
COMPILE_UID_OFFSET = 64 * UID_CLAIMS    # and each one's compile runs as that id + this
UID_RANGE = 2 * COMPILE_UID_OFFSET      # the ids of one root file system's gradings

# Several root file systems on one kernel (tools/portability/run's chroots) each take their own
# range: RAYKIT_FIRST_UID, FIRST_UID + k * UID_RANGE, set by whoever made the root.
FIRST_UID_ENV = "RAYKIT_FIRST_UID"

# Where the claims on those ids are kept: a folder only root can write (see claim_uid).
LOCK_DIRS = ["/run/raykit", "/var/lib/raykit/locks"]


_claimed: dict[int, int] = {}      # id -> the open lock file that claims it, held until this process ends
_names: dict[str, object] = {}     # abstract socket name -> the bound socket, held until this process ends


# The claim every root sees: a unix socket bound to an abstract name (a name that starts with a
# zero byte). Abstract names live in the network namespace, not in a file system, so a kit in a
# chroot on this kernel (tools/portability/run's roots share the network namespace), or one given
# its own /run, meets the same name; two binds of one name cannot both succeed, and the kernel lets
# go of the name when the socket's last descriptor closes, so a kit that dies frees its ids at once.
# A grading in another network namespace (a container with its own) also has its own PID
# namespace and its own users' processes, which the reaping of this one cannot reach.
NAME_PREFIX = "raykit-sandbox-"


def hold_name(name: str) -> bool:
    """Binds the abstract unix socket `name` and keeps it until this process ends (CLOEXEC: no child
    inherits it). False when another process holds the name; True when this one now does (or did)."""
    import socket
    if name in _names:
        return True
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET | socket.SOCK_CLOEXEC)
    try:
        sock.bind(b"\0" + name.encode())
    except OSError:
        sock.close()
        return False
    _names[name] = sock
    return True


def let_go(name: str) -> None:
    sock = _names.pop(name, None)
    if sock is not None:
        sock.close()


def first_uid() -> int:
    """The first sandbox user id of this root file system: FIRST_UID, or RAYKIT_FIRST_UID where
    several roots share one kernel. Checked: a whole range of its own above FIRST_UID, so two
    roots' ranges are equal or apart, never overlapping; anything else stops the grading (a range
    silently shared is the fault the variable exists to prevent)."""
    text = os.environ.get(FIRST_UID_ENV, "").strip()
    if not text:
        return FIRST_UID
    value = int(text) if text.isdigit() else -1
    if value < FIRST_UID or (value - FIRST_UID) % UID_RANGE or value + UID_RANGE > 2 ** 31:
        raise RuntimeError(f"{FIRST_UID_ENV}={text!r}: not a range of sandbox user ids (it must be "
                           f"{FIRST_UID} + k * {UID_RANGE}, below 2^31)")
    return value


def claim_uid(slot: int) -> int:
    """A sandbox user id no other grading on this machine is using.

    After each case every process of the id is killed, so two gradings must never share one
    (two instructors' runs, a batch beside a check). Each id is claimed with an exclusive lock on a
    file in a folder only root can write (_lock_folder), held until this process ends; graded code
    can neither open those files nor put anything in their place. The lock file is seen only in
    this root file system, so the id is also claimed by name where every root on the kernel sees it
    (hold_name: an abstract unix socket, raykit-sandbox-UID), and both claims are needed: a kit of
    older code beside this one looks only at the file, a kit in another root only at the name. An id
    with a live process is passed over too (_in_use: what is left of an earlier grading, or a kit of
    older code in another root). RAYKIT_FIRST_UID still gives a root a range of its own, but two
    roots on the default range no longer share an id.

    Graded code under the user isolation shares the network namespace and can bind such a name
    itself: it can make an id look taken (the next one is claimed; its processes, and so the name,
    end after each case: when every id is refused by its name alone, the claim waits up to a minute),
    never make a taken id look free.
    """
    import time
    first = first_uid()
    for _ in range(NAME_WAITS):
        uid, unopened, named = _claim_once(first, slot)
        if uid:
            return uid
        if not named:
            break
        time.sleep(0.5)         # a name held by a case's processes is free once the case ends
    if unopened:
        raise RuntimeError(f"no sandbox user id could be claimed: {unopened} of the lock files in "
                           f"{os.environ.get('RAYKIT_LOCK_DIR') or 'the claims folder'} could not be opened")
    raise RuntimeError("every sandbox user id is in use by other gradings on this machine")


NAME_WAITS = 120         # tries, half a second apart, while some id is refused by its name alone


def _claim_once(first: int, slot: int) -> tuple[int, int, int]:
    """One pass over the slot's ids: (the id claimed or 0, lock files that could not be opened, ids
    whose lock file was free but whose name was held)."""
    import fcntl
    folder = _lock_folder()
    unopened = named = 0
    try:
        for uid in range(first + slot % 64, first + COMPILE_UID_OFFSET, 64):
            if uid in _claimed:
                return uid, 0, 0
            if _has_name(uid) or _has_name(uid + COMPILE_UID_OFFSET):
                continue
            fd = _lock_file(folder, f"raykit-sandbox-{uid}.lock")
            if fd is None:
                unopened += 1
                continue
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                os.close(fd)
                continue
            if not hold_name(f"{NAME_PREFIX}{uid}"):
                os.close(fd)            # claimed in another root file system on this kernel
                named += 1
                continue
            if _in_use(uid):
                let_go(f"{NAME_PREFIX}{uid}")
                os.close(fd)            # closing the only descriptor lets go of the lock
                continue
            _claimed[uid] = fd
            _note_claim(uid)
            return uid, 0, 0
    finally:
        os.close(folder)
    return 0, unopened, named


def claim_range(limit: int = 15) -> tuple[int, int]:
    """For a tool that makes another root file system on this kernel (tools/portability/run): a
    range of sandbox user ids of its own, the first one for RAYKIT_FIRST_UID (range 0 is this
    root's, FIRST_UID). Claimed like an id, by a lock file and by an abstract name every root sees
    (raykit-range-K), until this process ends. Returns (first id, lock fd)."""
    import fcntl
    folder = _lock_folder()
    try:
        for k in range(1, limit + 1):
            fd = _lock_file(folder, f"raykit-range-{k}.lock")
            if fd is None:
                continue
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                os.close(fd)
                continue
            if not hold_name(f"raykit-range-{k}"):
                os.close(fd)
                continue
            return FIRST_UID + k * UID_RANGE, fd
    finally:
        os.close(folder)
    raise RuntimeError(f"every one of {limit} ranges of sandbox user ids is in use")


_DIR_FLAGS = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC


def _lock_folder() -> int:
    """The folder of the claims, open: reached from / one name at a time without following a link,
    made mode 0700 where it is missing, and checked once open to be a folder of root's that no one
    else may write or read (fixed to 0700 when root's own with looser rights). RAYKIT_LOCK_DIR names
    another one (the self-test's second root file system), checked the same way."""
    named = os.environ.get("RAYKIT_LOCK_DIR")
    errors = []
    for path in [named] if named else LOCK_DIRS:
        parts = [p for p in path.split("/") if p]
        if not path.startswith("/") or not parts or any(p in (".", "..") for p in parts):
            raise RuntimeError(f"RAYKIT_LOCK_DIR={path!r}: not an absolute path")
        fd = os.open("/", _DIR_FLAGS)
        try:
            for i, part in enumerate(parts):
                if i == len(parts) - 1 or (named is None and i > 0):
                    with suppress(FileExistsError):
                        os.mkdir(part, 0o700, dir_fd=fd)
                inner = os.open(part, _DIR_FLAGS, dir_fd=fd)
                os.close(fd)
                fd = inner
            st = os.fstat(fd)
            if st.st_uid != os.geteuid():
                raise RuntimeError(f"{path} is not root's (owner {st.st_uid}): sandbox user ids cannot be claimed "
                                   "safely; remove it")
            if stat.S_IMODE(st.st_mode) != 0o700:
                os.fchmod(fd, 0o700)
            return fd
        except OSError as e:
            os.close(fd)
            errors.append(f"{path}: {e.strerror or e}")
        except BaseException:
            os.close(fd)
            raise
    raise RuntimeError("no folder for the claims on sandbox user ids (" + "; ".join(errors) + ")")


def _lock_file(folder: int, name: str) -> int | None:
    """The lock file `name` in the claims' folder, open for reading and writing (never truncated,
    never through a link): a regular file of root's, mode 0600, with no other name. Anything else
    found there (only root can have put it) is removed and the file made anew. None when that fails."""
    flags = os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NONBLOCK
    for _ in range(3):
        try:
            fd = os.open(name, flags, 0o600, dir_fd=folder)
        except OSError:
            fd = -1                     # a link (ELOOP), a folder (EISDIR), a socket (ENXIO), or no room
            try:
                if stat.S_ISREG(os.stat(name, dir_fd=folder, follow_symlinks=False).st_mode):
                    return None         # another grading's lock file may be this one: never removed
            except OSError:
                return None
        if fd >= 0:
            st = os.fstat(fd)
            if stat.S_ISREG(st.st_mode) and st.st_uid == os.geteuid() and st.st_nlink == 1:
                if stat.S_IMODE(st.st_mode) != 0o600:
                    os.fchmod(fd, 0o600)
                return fd
            os.close(fd)
        try:
            os.unlink(name, dir_fd=folder)      # the entry itself, never what a link names
        except IsADirectoryError:
            try:
                os.rmdir(name, dir_fd=folder)
            except OSError:
                return None
        except FileNotFoundError:
            pass
        except OSError:
            return None
    return None


def _has_name(uid: int) -> bool:
    """Whether `uid` is a known user's (nobody is 65534, inside the ids of slot 62)."""
    import pwd
    try:
        pwd.getpwuid(uid)
        return True
    except KeyError:
        return False


def _note_claim(uid: int) -> None:
    """Writes the id to RAYKIT_UID_FILE (./kit grade ends its processes on a timeout): the file's
    own name never followed as a link, only into a folder no one else may write, and only over a
    regular file of root's with no other name."""
    target = os.environ.get("RAYKIT_UID_FILE")
    if not target:
        return
    try:
        parent = os.open(os.path.dirname(os.path.abspath(target)), os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
        try:
            st = os.fstat(parent)
            if st.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
                raise OSError(f"its folder may be written by others (mode {oct(stat.S_IMODE(st.st_mode))})")
            fd = os.open(os.path.basename(target), os.O_WRONLY | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC |
                         os.O_NONBLOCK, 0o644, dir_fd=parent)
            try:
                st = os.fstat(fd)
                if not stat.S_ISREG(st.st_mode) or st.st_uid != os.geteuid() or st.st_nlink != 1:
                    raise OSError("it is not a regular file of the kit's own")
                os.ftruncate(fd, 0)
                os.write(fd, str(uid).encode())
            finally:
                os.close(fd)
        finally:
            os.close(parent)
    except OSError as e:
        sys.stderr.write(f"raykit: RAYKIT_UID_FILE {target} not written: {e}\n")


def _in_use(uid: int) -> bool:
    """Whether any task has the id, zombies included: they count against RLIMIT_NPROC, and where
    PID 1 never reaps (some containers) a fork bomb's would make the sandbox unable to start."""
    ids = {uid, uid + COMPILE_UID_OFFSET}
    # One read of each status file (procfs.real_uid): a process that ends between two reads once gave
    # an empty second one (an IndexError that left one submission of a class of 60 not graded).
    return any(procfs.real_uid(p) in ids for p in procfs.pids())

"""What keeps one sandbox user id's runs apart from another's under the user isolation, where no
namespace does it (sandbox/ holds the boundary itself):

- the kit's own temporary files (the compile's private folders, the steps' scratch folders, the
  judge's records and ledgers) in a folder of root's outside /tmp (`kit_temp`), which graded code
  may write like any user: filling /tmp never takes a classmate's grading down with it, as long as
  /tmp is not the same disk (on most machines it is: a full disk is then every grading's fault);
- each step's scratch folder a size- and inode-limited tmpfs (`mount_scratch`) where the kit may
  mount one (root with CAP_SYS_ADMIN: not in Docker's default profile, so not on Gradescope nor
  PrairieLearn, where the folder stays on the container's disk, bounded only per file);
- the kernel keyrings of a sandbox id emptied (`clear_keyrings`) at each start and each end of
  its processes: they outlive them otherwise;
- the answers program may start no process or thread (`RUN_PROCESSES`): its CPU is the only CPU.
"""

from __future__ import annotations

import ctypes
import os
import platform
import shutil
import stat
import time
from pathlib import Path

from . import procfs

MiB = 1 << 20

# Processes and threads the answers program may have: itself. A fork or a thread fails with EAGAIN,
# so no CPU is spent where the judge's budget (the program's own CPU time) does not see it. The
# compile keeps Limits.processes (the driver starts cc1plus, as and ld).
RUN_PROCESSES = 1

# The kit's temporary folder when it grades as root: root's, mode 0711 (a sandbox id crosses it to
# its own folders, which are 0710 root:ID or its own 0700), never /tmp.
KIT_TEMP_DIRS = ["/var/lib/raykit-work", "/run/raykit-work"]
KIT_TEMP_ENV = "RAYKIT_KIT_TEMP"

# A step's scratch tmpfs: the copy of the answers program, and the runs' folders in SCRATCH_MB of
# Limits (the program's size is added), at most SCRATCH_INODES files and folders.
SCRATCH_INODES = 2048
SCRATCH_PREFIX = "raykit-sandbox-"


def kit_temp() -> str | None:
    """The kit's temporary folder outside /tmp, made when missing: a folder of root's that no one
    else may write. None when none can be made (the kit then keeps the system's)."""
    if os.geteuid() != 0:
        return None
    for path in KIT_TEMP_DIRS:
        try:
            os.makedirs(path, 0o711, exist_ok=True)
            st = os.lstat(path)
            if not stat.S_ISDIR(st.st_mode) or st.st_uid != 0:
                continue
            if stat.S_IMODE(st.st_mode) != 0o711:
                os.chmod(path, 0o711)
            return path
        except OSError:
            continue
    return None


def use_kit_temp() -> str | None:
    """Makes the kit's own temporary files (this process's and its children's: CMake, the launcher,
    the judge) go to kit_temp(). Returns the folder, or None when the system's stays."""
    import tempfile
    # RAYKIT_KIT_TEMP: a folder of the grader's own choosing (another disk; the fault self-test's full one).
    folder = os.environ.get(KIT_TEMP_ENV) or kit_temp()
    if folder:
        os.environ["TMPDIR"] = folder
        tempfile.tempdir = folder
        sweep_scratch_mounts(folder)
    return folder


def _mounted(path: str) -> bool:
    return path in procfs.mount_points()


# mount(2) and umount2(2) called from this process, never the mount and umount commands: a command's
# argv, the scratch folder's path, is what every user reads in /proc/PID/cmdline while it runs, and a
# classmate's program under the user isolation looks there (tests/kit/integrity_slots.py, classmate_program).
MS_NOSUID, MS_NODEV, MNT_DETACH = 2, 4, 2


def _mount_libc():
    try:
        return ctypes.CDLL(None, use_errno=True) if platform.system() == "Linux" else None
    except OSError:
        return None


def mount_scratch(folder: Path, uid: int, size_mb: int) -> str:
    """Mounts a tmpfs of `size_mb` MiB and SCRATCH_INODES inodes on `folder`, mode 0710, owner root,
    group `uid` (the sandbox id crosses it, nobody else). "" when done, else why not."""
    libc = _mount_libc()
    if os.geteuid() != 0 or libc is None or os.environ.get("RAYKIT_NO_SCRATCH_MOUNT") == "1":
        return "not root" if os.geteuid() != 0 else "not Linux" if libc is None else "RAYKIT_NO_SCRATCH_MOUNT=1"
    options = f"size={size_mb}m,nr_inodes={SCRATCH_INODES},mode=0710,uid=0,gid={uid}"
    if libc.mount(b"raykit-scratch", os.fsencode(folder), b"tmpfs", MS_NOSUID | MS_NODEV, options.encode()) != 0:
        return f"mount: {os.strerror(ctypes.get_errno())}"
    return ""


def scratch_words(uid: int, scratch_mb: int) -> str:
    """For the report, under the user isolation: whether each step's folder will be a sized tmpfs
    here (a probe mount of one, at once undone), and why not."""
    import tempfile
    probe = Path(tempfile.mkdtemp(prefix=f"{SCRATCH_PREFIX}{os.getpid()}-probe-"))
    try:
        why = mount_scratch(probe, uid, 1)
        unmount(probe)
    finally:
        shutil.rmtree(probe, ignore_errors=True)
    if not why:
        return f"its folder a tmpfs of {scratch_mb} MiB and {SCRATCH_INODES} inodes"
    return f"its folder NOT size-limited (a tmpfs cannot be mounted here: {why.splitlines()[0][:120]})"


def unmount(folder: Path) -> None:
    libc = _mount_libc()
    if libc is None or not _mounted(str(folder)):
        return
    for flags in (0, MNT_DETACH):       # then lazily, should a process still hold it
        if libc.umount2(os.fsencode(folder), flags) == 0:
            return


def _grading_runs(pid: int, path: Path) -> bool:
    """Whether the grading that made `path` still runs: a process `pid` that started before the folder
    was last changed. One that started later has the pid of a grading that died (the kernel gives pids
    again), and the folder is a leftover."""
    started = procfs.started(pid)
    if started is None:
        return False
    try:
        changed = path.lstat().st_mtime
    except OSError:
        return True             # gone, or not ours to judge: left alone
    return time.time() - procfs.uptime() + started <= changed + 1


_swept: set[str] = set()


def sweep_scratch_mounts(folder: str, once: bool = False) -> None:
    """Unmounts and removes the scratch folders a killed grading left in `folder` (their names
    carry the grading's process id: SCRATCH_PREFIX + PID + "-"); with `once`, the first time a
    process asks for that folder only (a scan of a busy /tmp costs milliseconds)."""
    if once and folder in _swept:
        return
    _swept.add(folder)
    try:
        names = os.listdir(folder)
    except OSError:
        return
    for name in names:
        if not name.startswith(SCRATCH_PREFIX):
            continue
        pid = name[len(SCRATCH_PREFIX):].split("-", 1)[0]
        path = Path(folder, name)
        if not pid.isdigit() or _grading_runs(int(pid), path):
            continue
        unmount(path)
        if not _mounted(str(path)):
            shutil.rmtree(path, ignore_errors=True)


# --- keyrings ----------------------------------------------------------------------------------

_SYS_KEYCTL = {"x86_64": 250, "aarch64": 219, "riscv64": 219, "i686": 288, "i386": 288, "armv7l": 311}
_libc = None


def _syscall():
    global _libc
    if _libc is None:
        try:
            _libc = ctypes.CDLL(None, use_errno=True)
        except OSError:
            _libc = False
    return _libc.syscall if _libc else None


def prepare_keyctl() -> None:
    """Loads what clear_keyrings needs before a fork (a preexec function should not load a library)."""
    _syscall()


def clear_keyrings() -> None:
    """For the calling process, after it took a sandbox id: a fresh session keyring of its own, and
    the id's user, user-session and persistent keyrings emptied (platform::clear_keyrings in C++ does
    the same for the judge). Nothing when the system has no keyctl or refuses it."""
    nr = _SYS_KEYCTL.get(platform.machine())
    call = _syscall()
    if nr is None or call is None or not platform.system() == "Linux":
        return
    join, clear, persistent = 1, 7, 22
    call(nr, join, None)
    for ring in (-4, -5):           # KEY_SPEC_USER_KEYRING, KEY_SPEC_USER_SESSION_KEYRING
        call(nr, clear, ctypes.c_long(ring))
    got = call(nr, persistent, ctypes.c_long(-1), ctypes.c_long(-3))
    if got > 0:
        call(nr, clear, ctypes.c_long(got))

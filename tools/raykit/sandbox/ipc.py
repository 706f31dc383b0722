"""What a sandbox id leaves behind outside its processes: files in the shared writable folders, System V IPC objects."""

from __future__ import annotations

import os
import shutil
import subprocess
from contextlib import suppress

from .. import procfs


# Where any user may leave something that outlives its processes: the shared temporary folders,
# the lock folder and POSIX message queues (mounted at /dev/mqueue where they are).
SHARED_WRITABLE = ("/tmp", "/var/tmp", "/dev/shm", "/run/lock", "/var/lock", "/dev/mqueue")


def clean_uid_files(uid: int) -> None:
    """Removes what the sandbox's user id left where any user may write (the user isolation can,
    like any user), and its System V shared memory, queues and semaphores: nothing one run leaves
    reaches the next (a case re-run alone, the next step, the next student)."""
    if not uid or os.geteuid() != 0:
        return
    clean_uid_ipc(uid)
    for top in SHARED_WRITABLE:
        try:
            entries = list(os.scandir(top))
        except OSError:
            continue
        for e in entries:
            with suppress(OSError):
                if e.stat(follow_symlinks=False).st_uid != uid:
                    continue
                if e.is_dir(follow_symlinks=False):
                    shutil.rmtree(e.path, ignore_errors=True)
                else:
                    os.unlink(e.path)


def clean_uid_ipc(uid: int) -> None:
    """Removes the System V IPC objects `uid` owns (no IPC namespace under the user isolation), as
    /proc/sysvipc lists them, with util-linux's ipcrm where it is installed."""
    ipcrm = shutil.which("ipcrm")
    if ipcrm is None:
        return
    for kind, flag in (("shm", "-m"), ("msg", "-q"), ("sem", "-s")):
        lines = procfs.sysvipc(kind)
        if not lines:
            continue
        header = lines[0].split()
        if "uid" not in header or ("shmid" not in header and "msqid" not in header and "semid" not in header):
            continue
        key_col = header.index(next(h for h in header if h in ("shmid", "msqid", "semid")))
        uid_col = header.index("uid")
        for line in lines[1:]:
            fields = line.split()
            if len(fields) > max(key_col, uid_col) and fields[uid_col] == str(uid):
                subprocess.run([ipcrm, flag, fields[key_col]], capture_output=True, timeout=10)

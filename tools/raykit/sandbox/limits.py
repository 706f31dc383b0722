"""What graded code may use (Limits) and what the boundary shows it of the machine: the numbers and lists every part of the sandbox reads."""

from __future__ import annotations

import os
from dataclasses import asdict, dataclass


# What the user isolation must not read in the kit. hide_secrets takes "others" rights from the
# kit's root itself, which closes all of it; these are closed too, in case the root cannot be changed
# (a read-only or foreign-owned mount) or is opened to others again by hand.
SECRET_PARTS = ["solutions", "tests", "build", "bench", ".git"]


# Bubblewrap shows graded code an allow-list of the machine, nothing else (issue 32: a deny-list of
# folders showed a class kept under /opt, and another copy of the kit, to every submission):
# - SYSTEM, read-only: the programs and libraries the compile and the run need;
# - SYSTEM_LINKS: the top folders a merged-/usr system has as links into /usr (Debian 12), or as
#   folders of their own (Debian 11 may have either): made the same links, or bound, as here;
# - SYSTEM_ETC, read-only: /etc's parts the compiler and loader read (c++ is /etc/alternatives/c++;
#   the loader finds libstdc++ through ld.so.cache), and the compiler's own folder when it is
#   outside them (CXX=/opt/gcc-13/bin/g++ shows /opt/gcc-13);
# - the boundary's own files (Isolation.wrapper's ro, rw and tmpfs), a fresh /dev and /proc;
# - HIDDEN, writable and empty: what programs expect to write, each a small tmpfs of its own.
SYSTEM = ["/usr"]
SYSTEM_LINKS = ["/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32"]
SYSTEM_ETC = ["/etc/alternatives", "/etc/ld.so.cache"]
HIDDEN = ["/tmp", "/dev/shm"]

MiB = 1 << 20
HIDDEN_TMPFS_BYTES = 4 * MiB        # each hidden folder's tmpfs, where bubblewrap can size one


@dataclass
class Limits:
    """What graded code may use. Compile: one compile or link of the student's files. Run: the
    answers program and what it starts. The call limit (remote.cpp, RAYKIT_CALL_SECONDS) is apart."""

    compile_seconds: float = 60.0       # wall time of one compile or link, then its processes are killed
    compile_memory_mb: int = 1536       # address space of each compiler process (RLIMIT_AS)
    run_memory_mb: int = 1024           # address space of each process of the answers program
    memory_mb: int = 2048               # the slot's control group, when there is one (all of the above)
    processes: int = 64                 # a compile's processes and threads at once (RLIMIT_NPROC or pids.max);
                                        # the answers program has sandbox_slots.RUN_PROCESSES (itself)
    file_mb: int = 16                   # any one file written (RLIMIT_FSIZE)
    scratch_mb: int = 64                # the run's writable folder in all (bubblewrap: a sized tmpfs)
    cpu_seconds: int = 60               # CPU time of any one process (RLIMIT_CPU)
    output_kb: int = 32                 # what a compile may print, kept for the report

    @classmethod
    def from_env(cls) -> "Limits":
        limits = cls()
        text = os.environ.get("RAYKIT_LIMITS", "")
        for item in filter(None, (p.strip() for p in text.split(","))):
            key, _, value = item.partition("=")
            if not hasattr(limits, key):
                raise ValueError(f"RAYKIT_LIMITS: no limit {key!r}; the limits are "
                                 + ", ".join(asdict(limits)))
            setattr(limits, key, type(getattr(limits, key))(value))
        return limits

    def words(self) -> str:
        return (f"compile {self.compile_seconds:g} s, {self.compile_memory_mb} MiB a process and {self.processes} "
                f"processes; run {self.run_memory_mb} MiB, one process and no thread of its own, files of at most "
                f"{self.file_mb} MiB, scratch {self.scratch_mb} MiB, {self.cpu_seconds} s of CPU a process")

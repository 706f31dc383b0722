"""The trust boundary: where a student's code is compiled and run while it is graded.

One object, `Isolation`, holds everything that keeps graded code apart, and every path from a
student's file to a process goes through it:

- the compile and the link of the student's answers program (CMake calls `tools/kitlib/launch.py`
  for them, which calls `Isolation.run_tool`): the sources are copied into a fresh folder with the
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

import json
import os
import resource
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

from . import atomic, procfs
from .common import BUILD, ROOT
from .sandbox_slots import RUN_PROCESSES, SCRATCH_PREFIX, clear_keyrings, mount_scratch, prepare_keyctl, \
    scratch_words, unmount, use_kit_temp

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

    # --- the spec the launcher reads back (tools/kitlib/launch.py) -------------------------
    def spec(self) -> str:
        return json.dumps({"mode": self.mode, "uid": self.uid, "compile_uid": self.compile_uid,
                           "limits": asdict(self.limits),
                           "cgroups": self.cgroups, "description": self.description})

    @classmethod
    def from_spec(cls, text: str) -> "Isolation":
        d = json.loads(text)
        return cls(d["mode"], d["description"], uid=d["uid"], compile_uid=d["compile_uid"],
                   limits=Limits(**d["limits"]), cgroups=d["cgroups"])

    # --- processes inside the boundary ------------------------------------------------------
    def wrapper(self, ro: list[tuple[Path, str]], rw: list[tuple[Path, str]], chdir: str,
                tmpfs: list[tuple[str, int]] = (), use: str = "") -> list[str]:
        """The argv prefix that starts a command inside the boundary: bubblewrap's options, or
        nothing. Inside, the allow-list of the machine (system_view), a fresh /dev, /proc and
        HIDDEN, then `ro` and `rw`, host folders (or files) bound at the paths given, and `tmpfs`,
        sized empty folders. Nothing else of the machine exists there."""
        if self.mode != "bwrap":
            return []
        argv = ["bwrap"] + system_view() + ["--dev", "/dev", "--proc", "/proc"]
        for h in HIDDEN:
            if bwrap_sizes():       # an empty folder, and no room to fill memory through it
                argv += ["--size", str(HIDDEN_TMPFS_BYTES)]
            argv += ["--tmpfs", h]
        for host, inside in ro:
            argv += ["--ro-bind", str(host), inside]
        for host, inside in rw:
            argv += ["--bind", str(host), inside]
        for inside, size in tmpfs:
            if bwrap_sizes():
                argv += ["--size", str(size)]
            argv += ["--tmpfs", inside]
        if use and os.environ.get("RAYKIT_BREAK_SANDBOX") == use:   # the self-test: a sandbox that cannot start
            argv += ["--ro-bind", "/nonexistent-raykit-selftest", "/nonexistent-raykit-selftest"]
        # The root itself read-only (bubblewrap makes it a tmpfs the sandbox's user owns): nothing to
        # write but the folders above.
        argv += ["--remount-ro", "/"]
        argv += ["--chdir", chdir, "--unshare-all", "--unshare-user", "--uid", "65534", "--gid", "65534",
                 "--die-with-parent", "--new-session", "--cap-drop", "ALL", "--"]
        return argv

    def preexec(self, memory_mb: int, uid: int):
        """What a child does between fork and exec to enter the boundary: its own process group,
        the control group, the rlimits, then the dedicated user id `uid` (last: joining a control
        group and lowering limits need the rights it drops)."""
        limits, cgroups = self.limits, list(self.cgroups)
        prepare_keyctl()

        def enter() -> None:
            os.setpgid(0, 0)
            for group in cgroups:
                try:
                    Path(group, "cgroup.procs").write_text(str(os.getpid()))
                except OSError:
                    pass
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
    def run_tool(self, kind: str, argv: list[str], cwd: Path, cache=None) -> int:
        """Runs one compile (`kind` "compile") or link ("link") command of the student's answers
        program inside the boundary, as CMake gave it; its outputs are copied to where CMake wants
        them only when they are regular files. Returns the exit status; prints the diagnostics.
        `cache`, when given, is the build layer's store of compiled objects (objcache.ObjectCache):
        called as cache(argv, work, source_dir, isolation, wrapper) for a compile, it answers fetch(out)
        and store(out, text); the boundary keeps none of its own."""
        status, text = self.tool(kind, argv, cwd, cache)
        sys.stdout.write(text)
        sys.stdout.flush()
        return status

    def tool(self, kind: str, argv: list[str], cwd: Path, cache=None) -> tuple[int, str]:
        """`run_tool` for a caller in the kit's own process (checking.build_answers): the exit
        status (0 or 1) and the diagnostics, as the student's own."""
        work = Path(tempfile.mkdtemp(prefix="raykit-build-"))
        try:
            return _run_tool(self, kind, argv, cwd, work, cache)
        finally:
            shutil.rmtree(work, ignore_errors=True)

    def clean_files(self, uid: int) -> None:
        """What `uid` left in the shared temporary folders. Under bubblewrap it has none to write:
        /tmp, /var/tmp and /dev/shm are its own empty mounts, gone with it (and a scan of a busy
        /tmp costs 15 ms a step)."""
        if self.mode != "bwrap":
            clean_uid_files(uid)

    def close(self) -> None:
        for group in self.cgroups:
            kill_cgroup(Path(group))
            try:
                os.rmdir(group)
            except OSError:
                pass
        for uid in (self.uid, self.compile_uid):
            if uid:
                kill_uid(uid)
                self.clean_files(uid)
        if not (self.uid or self.compile_uid):
            return                  # no id of the sandbox's: nothing of the graded code's to reap
        for _ in range(25):     # a process killed a moment ago becomes a zombie a moment later
            reap_orphans({self.uid, self.compile_uid})
            if not any(procfs.parent(p) == os.getpid() and procfs.real_uid(p) in (self.uid, self.compile_uid)
                       for p in procfs.pids()):
                break
            time.sleep(0.02)


NONE_OWN = Isolation("none", "not sandboxed (your own steps: the code runs as you)", own=True)

_probe: dict[str, bool] = {}


def system_view() -> list[str]:
    """Bubblewrap's options that show the allow-list of the machine (SYSTEM, SYSTEM_LINKS,
    SYSTEM_ETC, the compiler's folder), read-only, each as it is here, and hide inside it the kit
    and its build/ should they lie there (a kit kept in /usr/local/src). Computed once a process."""
    if "view" in _view:
        return list(_view["view"])
    argv: list[str] = []
    shown: list[str] = []
    for path in SYSTEM:
        if os.path.isdir(path) and not os.path.islink(path):
            argv += ["--ro-bind", path, path]
            shown.append(path)
    for path in SYSTEM_LINKS:
        if os.path.islink(path):                    # merged /usr: /lib -> usr/lib, as here
            argv += ["--symlink", os.readlink(path), path]
        elif os.path.isdir(path):
            argv += ["--ro-bind", path, path]
            shown.append(path)
    for path in SYSTEM_ETC:
        if os.path.lexists(path):
            argv += ["--ro-bind", path, path]
    for folder in compiler_folders(shown):
        argv += ["--ro-bind", folder, folder]
        shown.append(folder)
    for secret in sorted({str(ROOT), str(BUILD), os.path.realpath(ROOT), os.path.realpath(BUILD)}):
        if any(secret == s or secret.startswith(s.rstrip("/") + "/") for s in shown) and os.path.isdir(secret):
            argv += ["--tmpfs", secret]
    _view["view"] = argv
    return list(argv)


_view: dict[str, list[str]] = {}


def compiler_folders(shown: list[str]) -> list[str]:
    """The install folders of the compiler that lie outside the folders `shown`: the one named by
    CXX (what CMake takes when it first configures a build folder) and the one a build folder was
    configured with (CMakeCache.txt in the working folder: the launcher runs in the build folder),
    each the folder above its bin/ (its libexec/, lib/ and include/ beside it), else its own folder.
    A compiler under /usr needs nothing more."""
    import shlex
    found: list[str] = []
    try:
        words = shlex.split(os.environ.get("CXX", ""))
    except ValueError:
        words = []
    try:
        if Path.cwd() != BUILD and BUILD not in Path.cwd().parents:
            raise OSError("not a build folder of the kit")
        with open("CMakeCache.txt", errors="replace") as cache:
            for line in cache:
                if line.startswith("CMAKE_CXX_COMPILER:"):
                    words.append(line.split("=", 1)[1].strip())
    except OSError:
        pass
    for word in words:
        exe = shutil.which(word)
        if not exe:
            continue
        real = Path(os.path.realpath(exe))
        # Never a top folder (/opt), nor one that holds the kit, a home or the temporary folder.
        kept = [Path(p).resolve() for p in (ROOT, os.environ.get("HOME") or "/", tempfile.gettempdir())]
        for folder in ([real.parent.parent] if real.parent.name == "bin" else []) + [real.parent]:
            text = str(folder)
            if len(folder.parts) < 3 or any(k == folder or folder in k.parents for k in kept):
                continue
            if not any(text == s or text.startswith(s.rstrip("/") + "/") for s in shown + found):
                found.append(text)
            break
    return found


def bwrap_sizes() -> bool:
    """Whether this bubblewrap knows --size (0.5 and later; Debian 11 has 0.4.1)."""
    if "size" not in _probe:
        try:
            r = subprocess.run(["bwrap", "--help"], capture_output=True, text=True, timeout=10)
            _probe["size"] = "--size" in r.stdout + r.stderr
        except (OSError, subprocess.TimeoutExpired):
            _probe["size"] = False
    return _probe["size"]


def _drop_to(uid: int):
    def drop() -> None:
        os.setgroups([])
        os.setgid(uid)
        os.setuid(uid)
    return drop


def bwrap_works(uid: int | None = None) -> bool:
    """Whether bubblewrap starts here as the sandbox will start it: as `uid` when the kit is root
    (the first sandbox id by default), else as the kit's own user."""
    if uid is None and os.geteuid() == 0:
        uid = first_uid()
    key = f"bwrap{uid}"
    if key not in _probe:
        ok = False
        if shutil.which("bwrap"):
            probe = Isolation("bwrap", "", uid or 0).wrapper([], [], "/")
            # Three tries, a minute each: on a machine at a load of 20 a start can take long, and a
            # grading of another kit's that ends every process of this id can kill a probe. Only a
            # bubblewrap that never starts is one that cannot (issue 46: a probe that said "no" once
            # under load skipped every bubblewrap security test).
            for _ in range(3):
                try:
                    r = subprocess.run(probe + ["true"], capture_output=True, timeout=60,
                                       preexec_fn=_drop_to(uid) if uid else None)
                except (OSError, subprocess.TimeoutExpired):
                    continue
                if r.returncode == 0:
                    ok = True
                    break
                if r.returncode > 0 and r.stderr.strip():
                    break           # bubblewrap said why it cannot: no point in asking again
        _probe[key] = ok
    return _probe[key]


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


_claimed: dict[int, int] = {}      # id -> the open lock file that claims it, held until this process ends


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
    can neither open those files nor put anything in their place. An id with a live process is
    passed over (_in_use: a grading in another root file system on this kernel that was given the
    same range, or what is left of an earlier one). Gradings in different root file systems are
    kept apart by their ranges (first_uid), which the graded code cannot change either.
    """
    import fcntl
    first = first_uid()
    folder = _lock_folder()
    unopened = 0
    try:
        for uid in range(first + slot % 64, first + COMPILE_UID_OFFSET, 64):
            if uid in _claimed:
                return uid
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
            if _in_use(uid):
                os.close(fd)            # closing the only descriptor lets go of the lock
                continue
            _claimed[uid] = fd
            _note_claim(uid)
            return uid
    finally:
        os.close(folder)
    if unopened:
        raise RuntimeError(f"no sandbox user id could be claimed: {unopened} of the lock files in "
                           f"{os.environ.get('RAYKIT_LOCK_DIR') or 'the claims folder'} could not be opened")
    raise RuntimeError("every sandbox user id is in use by other gradings on this machine")


def claim_range(limit: int = 15) -> tuple[int, int]:
    """For a tool that makes another root file system on this kernel (tools/portability/run): a
    range of sandbox user ids of its own, the first one for RAYKIT_FIRST_UID (range 0 is this
    root's, FIRST_UID). Claimed like an id, until this process ends. Returns (first id, lock fd)."""
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
                    try:
                        os.mkdir(part, 0o700, dir_fd=fd)
                    except FileExistsError:
                        pass
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


def become_subreaper() -> None:
    """Orphans of the graded code (killed sandboxes' processes) are given to this process, which
    reaps them (reap_children), instead of to PID 1, which in some containers never does."""
    try:
        import ctypes
        ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0)     # PR_SET_CHILD_SUBREAPER
    except (OSError, AttributeError):
        pass


def reap_orphans(uids: set[int]) -> None:
    """Reaps the graded code's dead orphans given to us (zombies of the sandbox's ids whose parent
    is this process), each by its pid: never waitpid(-1), which could take a build's exit status
    from the subprocess that waits for it."""
    me, wanted = str(os.getpid()), {str(u) for u in uids if u}
    if not wanted:
        return
    for p in procfs.pids():
        fields = procfs.status(p)         # one read: state, parent and owner of the same moment
        if (fields.get("State", "").startswith("Z") and fields.get("PPid") == me
                and fields.get("Uid", "").split()[:1] and fields["Uid"].split()[0] in wanted):
            try:
                os.waitpid(p, os.WNOHANG)
            except ChildProcessError:
                pass


class Scratch:
    """A step's folder for the runs of the student's code: a copy of its answers program, and the
    parent of the folders those runs work in. The judge (tests/support/remote.cpp) makes a fresh one
    inside it at every start of the answers program, a case re-run alone included (owned by the
    sandbox's user id, mode 0700, removed when that program stops): nothing one run writes is there
    for the next. This folder and the program stay the kit's: with a sandbox id, the folder 0710 and
    the program 0750, both root's with the id's group, so that id alone may cross the one and start
    the other (no other sandbox id may list, read, run or copy them, even knowing the path), and
    nobody but the kit may write or swap anything here (0711 and 0755 without an id).

    Under the user isolation, where the kit may mount (root with CAP_SYS_ADMIN), the folder is a
    tmpfs of its own, Limits.scratch_mb plus the program's size and sandbox_slots.SCRATCH_INODES
    inodes: the runs' folders and their TMPDIR cannot fill a disk. `mount_note` says why not when
    it is not (a container: Docker's default profile refuses mount)."""

    def __init__(self, isolation: Isolation, answers: Path | None):
        self.isolation = isolation
        self.mount_note = ""
        self.mounted = False
        uid = isolation.uid
        self.path = Path(tempfile.mkdtemp(prefix=f"{SCRATCH_PREFIX}{os.getpid()}-"))
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
        """Before a case re-run alone (checking.rerun_timeouts), under the user isolation: every
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
        shutil.rmtree(self.path, ignore_errors=True)


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
        try:
            if p.exists() and not p.is_symlink():
                mode = p.stat().st_mode
                if mode & 0o007:
                    os.chmod(p, mode & ~0o007)
        except OSError:
            pass


# --- the class folder under the user isolation ---------------------------------------------------

WITHHELD = BUILD / "withheld-modes.json"     # {path: [mode, pid]}: what to put back should the kit die


def _withheld_read() -> dict:
    try:
        data = json.loads(WITHHELD.read_text())
        return data if isinstance(data, dict) else {}
    except (OSError, ValueError):
        return {}


def _withheld_write(data: dict) -> None:
    try:
        if data:
            BUILD.mkdir(parents=True, exist_ok=True)
            atomic.write(WITHHELD, json.dumps(data))
        else:
            WITHHELD.unlink(missing_ok=True)
    except OSError:
        pass


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
        try:
            os.chmod(path, int(mode))
            done.append(path)
        except OSError:
            pass
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
        try:
            for sig in (signal.SIGTERM, signal.SIGHUP):
                if signal.getsignal(sig) == signal.SIG_DFL:
                    self.handlers[sig] = signal.signal(sig, _exit_on_signal)
        except ValueError:
            pass                    # not the main thread: atexit and finally still put them back
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
            try:
                os.chmod(path, mode)
            except OSError:
                pass
            record.pop(path, None)
            del self.taken[path]
        _withheld_write(record)
        for sig, old in self.handlers.items():
            try:
                signal.signal(sig, old)
            except ValueError:
                pass
        self.handlers = {}

    def __exit__(self, *exc) -> None:
        self.restore()


def _exit_on_signal(signum, frame) -> None:
    raise SystemExit(128 + signum)


# --- processes ---------------------------------------------------------------------------------

def _owned_by(pid: int, uid: int) -> bool:
    """Whether process `pid` is alive (not a zombie waiting for its parent) with real user id `uid`."""
    fields = procfs.status(pid)         # one read: owner and state of the same moment
    return fields.get("Uid", "").split()[:1] == [str(uid)] and not fields.get("State", "").startswith("Z")


def kill_uid(uid: int) -> None:
    """Ends every process whose real user id is `uid`: a helper that takes the id and signals all
    it may signal (kill -1), repeated while any is left (a fork between two rounds), and empties the
    id's keyrings (at least once, with no process left too)."""
    if not uid or os.geteuid() != 0:
        return
    prepare_keyctl()
    for round in range(20):
        left = [p for p in procfs.pids() if _owned_by(p, uid)]
        if not left and round:
            return
        pid = os.fork()
        if pid == 0:
            try:
                os.setgroups([])
                os.setgid(uid)
                os.setuid(uid)
                try:
                    os.kill(-1, signal.SIGKILL)
                except OSError:         # none left to signal
                    pass
                clear_keyrings()        # what the id's processes kept in its keyrings outlives them
            finally:
                os._exit(0)
        os.waitpid(pid, 0)
        if left:
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
            try:
                os.kill(p, signal.SIGKILL)
                ended += 1
            except OSError:
                pass
        time.sleep(0.02)
    return ended


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
            try:
                if e.stat(follow_symlinks=False).st_uid != uid:
                    continue
                if e.is_dir(follow_symlinks=False):
                    shutil.rmtree(e.path, ignore_errors=True)
                else:
                    os.unlink(e.path)
            except OSError:
                pass


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


# --- control groups ----------------------------------------------------------------------------

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
                try:
                    (group / "memory.memsw.limit_in_bytes").write_text(str(limits.memory_mb * MiB))
                except OSError:
                    pass
        if not any("/memory/" in g for g in made):
            raise OSError("no memory controller")
        return made
    except OSError:
        for g in made:
            try:
                os.rmdir(g)
            except OSError:
                pass
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
            try:
                os.kill(p, signal.SIGKILL)
            except OSError:
                pass
        time.sleep(0.02)


# --- files leaving the boundary ----------------------------------------------------------------

def copy_regular(src: Path, dst: Path, mode: int = 0o644, limit: int = 256 * MiB) -> None:
    """Copies `src` to `dst` only when it is a regular file (opened without following a link) of
    at most `limit` bytes: what the student's side wrote never makes the kit read another file."""
    fd = os.open(src, os.O_RDONLY | os.O_NOFOLLOW)
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise OSError(f"{src.name} is not a regular file")
        if st.st_size > limit:
            raise OSError(f"{src.name} is larger than {limit // MiB} MiB")
        dst.parent.mkdir(parents=True, exist_ok=True)
        with atomic.replacing(dst, mode, sync=False) as out:    # nothing planted is written through
            while True:
                chunk = os.read(fd, 1 << 20)
                if not chunk:
                    break
                out.write(chunk)
    finally:
        os.close(fd)


def _run_tool(iso: Isolation, kind: str, argv: list[str], cwd: Path, work: Path, cache=None) -> tuple[int, str]:
    from .common import printable
    limits = iso.limits
    uid = iso.compile_uid
    os.chmod(work, 0o750)
    if uid:
        os.chown(work, 0, uid)              # the sandbox's group may read, nobody else may enter
    (work / "in").mkdir()
    out = work / "out"
    out.mkdir()
    if uid:
        os.chown(out, uid, uid)
    if kind == "compile":       # a link needs no headers
        shutil.copytree(ROOT / "include", work / "include")
    inside = work                         # the same paths inside bubblewrap: W is bound at W
    mapping: list[tuple[str, str]] = [(str(work / "include"), str(ROOT / "include")), (str(out) + "/", "")]
    new = list(argv)
    copies: list[tuple[Path, Path, int]] = []   # (from out/, to where CMake wants it, mode)
    dep_files: list[Path] = []

    def real(p: str) -> Path:
        path = Path(p)
        return path if path.is_absolute() else cwd / path

    i = 0
    while i < len(new):
        a = new[i]
        if kind == "link" and a.startswith("-Wl,--dependency-file="):
            # The linker's list of its inputs (CMake 3.27+, unless CMAKE_LINK_DEPENDS_USE_LINKER is
            # off, as CMakeLists.txt sets it for these links): the link here reads private copies,
            # so the list is left out and one that names no extra input is written where the
            # build tool reads it (the link's own inputs are tracked by its rule).
            dep_files.append(real(a.split("=", 1)[1]))
            del new[i]
            continue
        if a in ("-o", "-MF") and i + 1 < len(new):
            target = real(new[i + 1])
            local = out / (target.name if a == "-o" else target.name + ".d")
            new[i + 1] = str(local)
            copies.append((local, target, 0o755 if kind == "link" and a == "-o" else 0o644))
            i += 2
            continue
        for flag in ("-I", "-isystem"):
            # Relative to the build folder, as the build tool gives them (CMake 3.18 writes -I../../include).
            if a == flag and i + 1 < len(new) and real(new[i + 1]).resolve() == (ROOT / "include").resolve():
                new[i + 1] = str(work / "include")
            elif a.startswith(flag) and a != flag and a[len(flag):] and \
                    real(a[len(flag):]).resolve() == (ROOT / "include").resolve():
                new[i] = flag + str(work / "include")
        i += 1
    local_dir = work / "src"
    if kind == "compile":
        src = real(new[new.index("-c") + 1])
        step_dir = src.parent
        local_dir = work / "src" / step_dir.name
        local_dir.mkdir(parents=True)
        for f in step_dir.iterdir():              # the step's own files: what it may include
            if f.is_file() and not f.is_symlink():
                copy_regular(f, local_dir / f.name, limit=4 * MiB)
        new[new.index("-c") + 1] = str(local_dir / src.name)
        mapping.append((str(local_dir), str(step_dir)))
    else:
        for j, a in enumerate(new):
            if j == 0 or a.startswith("-") or not (a.endswith(".o") or a.endswith(".a")):
                continue
            if j > 0 and new[j - 1] == "-o":
                continue
            p = real(a)
            if p.is_file():
                local = work / "in" / f"{j}_{p.name}"
                copy_regular(p, local)
                new[j] = str(local)
    env = {"PATH": "/usr/local/bin:/usr/bin:/bin", "LANG": "C.UTF-8", "HOME": str(out), "TMPDIR": str(out)}
    prefix = iso.wrapper([(work, str(inside))], [(out, str(out))], str(out), use=kind)
    memory = limits.compile_memory_mb if kind == "compile" else max(limits.compile_memory_mb, 1024)
    cached = cache(new, work, local_dir, iso, prefix) if cache is not None and kind == "compile" else None
    if cached is not None and cached.fetch(out):
        return _finish(kind, iso, cached.text, 0, False, 0, mapping, copies, memory)
    if kind == "compile":       # the step header precompiled, beside it (studentpch.py; after the key)
        from . import studentpch
        try:
            source = (local_dir / src.name).read_text(errors="replace")
        except OSError:
            source = ""
        for gch, name in studentpch.for_compile(list(argv), source, cwd):
            # A hard link (no copy) where build/ and the private folder share a file system. Not a
            # bind: bubblewrap opens its sources as the sandbox's user, who cannot read build/.
            target = work / "include" / name
            try:
                os.link(gch, target)
            except OSError:
                try:
                    shutil.copyfile(gch, target)
                except OSError:         # no room: the compile reads the header itself
                    target.unlink(missing_ok=True)
    start = time.monotonic()
    proc = subprocess.Popen(prefix + new, cwd=out, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, preexec_fn=iso.preexec(memory, uid))
    kept = bytearray()
    total = 0
    timed_out = False
    os.set_blocking(proc.stdout.fileno(), False)
    while True:
        try:
            chunk = proc.stdout.read(65536)
        except BlockingIOError:
            chunk = None
        if chunk:
            total += len(chunk)
            room = limits.output_kb * 1024 - len(kept)
            if room > 0:
                kept += chunk[:room]
            continue
        if proc.poll() is not None and chunk == b"":
            break
        if proc.poll() is not None and chunk is None:
            time.sleep(0.01)
            continue
        if time.monotonic() - start > limits.compile_seconds:
            timed_out = True
            break
        time.sleep(0.01)
    _end_group(proc)
    proc.wait()
    text = kept.decode("utf-8", "replace")
    if proc.returncode != 0 and not timed_out and prefix and not _starts(prefix, iso, out, env, uid):
        # Not the student's compile error: the sandbox itself does not start (checked with a program
        # that does nothing). The kit reports the step as not graded, the grader's fault.
        return 1, f"{SANDBOX_FAILED} ({iso.mode}): {printable(text.strip()[:300])}\n"
    if cached is not None and proc.returncode == 0 and not timed_out:
        cached.store(out, text)
    status, text = _finish(kind, iso, text, proc.returncode, timed_out, total, mapping, copies, memory)
    for dep in dep_files if status == 0 else []:
        made = next((str(target) for _, target, mode in copies if mode == 0o755), "")
        try:
            dep.parent.mkdir(parents=True, exist_ok=True)
            dep.write_text(f"{made}:\n")
        except OSError:
            pass
    return status, text


def _finish(kind: str, iso: Isolation, text: str, status: int, timed_out: bool, total: int,
            mapping: list[tuple[str, str]], copies: list[tuple[Path, Path, int]], memory: int) -> tuple[int, str]:
    """The compile's or link's diagnostics, as the student's own, and its outputs copied back."""
    from .common import printable
    limits = iso.limits
    kept = text.encode()
    total = max(total, len(kept))
    for local, shown in mapping:
        text = text.replace(local, shown)
    text = printable(text)
    if total > len(kept):
        text += f"\n(the compiler printed {total} bytes; the first {len(kept)} are shown)\n"
    if timed_out:
        text += (f"\nraykit: the {kind} of your code took over {limits.compile_seconds:g} s and was "
                 "stopped (the limit of one compile).\n")
        status = 1
    elif status != 0 and status < 0:
        text += (f"\nraykit: the {kind} of your code was stopped by signal {-status} (limits: "
                 f"{limits.compile_memory_mb} MiB of memory, {limits.cpu_seconds} s of CPU).\n")
    elif status != 0 and any(w in text for w in ("memory exhausted", "Cannot allocate memory", "out of memory")):
        text += f"\nraykit: the compiler ran out of the {memory} MiB it may use.\n"
    if status == 0:
        for local, target, mode in copies:
            try:
                if local.name.endswith(".d") and local.is_file():
                    body = local.read_bytes()[:4 * MiB].decode("utf-8", "replace")
                    for loc, shown in mapping:
                        body = body.replace(loc, shown)
                    target.parent.mkdir(parents=True, exist_ok=True)
                    target.write_text(body)
                else:
                    copy_regular(local, target, mode)
            except OSError as e:
                text += f"\nraykit: the {kind} made no usable {target.name} ({e}).\n"
                status = 1
    return (0 if status == 0 else 1), text


SANDBOX_FAILED = "raykit: the grader's sandbox could not start"


def _starts(prefix: list[str], iso: Isolation, cwd: Path, env: dict[str, str], uid: int) -> bool:
    """Whether the sandbox starts /bin/true as it was to start the compiler."""
    true = "/bin/true" if os.path.exists("/bin/true") else "/usr/bin/true"
    try:
        r = subprocess.run(prefix + [true], cwd=cwd, env=env, stdin=subprocess.DEVNULL, capture_output=True,
                           timeout=30, preexec_fn=iso.preexec(iso.limits.compile_memory_mb, uid))
        return r.returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


def _end_group(proc: subprocess.Popen) -> None:
    """Ends the compile's process group (what the compiler driver started). Not the user id's or the
    control group's other processes: the build runs compiles in parallel under one id. Whatever
    a compile could leave is ended with the submission (Isolation.close)."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except OSError:
        pass

"""The compile and the link of a student's answers program inside the boundary (Isolation.run_tool), and the files that leave it."""

from __future__ import annotations

from contextlib import suppress
from typing import TYPE_CHECKING
import os
import shutil
import signal
import stat
import subprocess
import time
from pathlib import Path

from .. import atomic, faults
from ..common import ROOT
from .limits import MiB

if TYPE_CHECKING:        # annotations only: the higher module imports this one
    from .isolation import Isolation


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
    from ..common import printable
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
                try:
                    copy_regular(f, local_dir / f.name, limit=4 * MiB)
                except OSError as e:
                    if faults.machine_errno(e):
                        raise faults.MachineFault(f"{e.strerror}, copying the step's files into the kit's "
                                                  "scratch") from e
                    # The student's file (too large, not a regular file): their compile error, not the kit's.
                    return 1, printable(f"raykit: {f.name} cannot be compiled: {e}\n")
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
        from .. import studentpch
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
    returncode, text, total, timed_out = _run_once(prefix + new, out, env, iso, memory, uid)
    if returncode != 0 and not timed_out and prefix and not _starts(prefix, iso, out, env, uid):
        # Not the student's compile error: the sandbox itself does not start (checked with a program
        # that does nothing). The kit reports the step as not graded, the grader's fault.
        return 1, f"{SANDBOX_FAILED} ({iso.mode}): {printable(text.strip()[:300])}\n"
    if returncode != 0 and not timed_out and uid:
        # A sandbox id's processes can be ended by a signal the kit did not send (another grading's
        # reaping that took the same id: issue 52), and the compiler driver then fails as it does on
        # an error (exit 1, "signal terminated program cc1plus"), in words the student's file can also
        # make it print, and its text varies between runs anyway (the assembler's temporary names,
        # the memory figures; a file can even #include /dev/urandom). So no word decides: a failed
        # compile or link under a sandbox id is run once more and the second result is the one kept.
        # A success is the code's (a signal never makes a compile succeed); a second failure is the
        # code's own too, since a kill twice in a row at the same compile is what the claims by name
        # (ids.py) exist to prevent. A compile stopped at its own time limit is not run again.
        for entry in out.iterdir():
            if entry.is_dir() and not entry.is_symlink():
                shutil.rmtree(entry, ignore_errors=True)
            else:
                entry.unlink(missing_ok=True)
        returncode, text, total, timed_out = _run_once(prefix + new, out, env, iso, memory, uid)
    if returncode != 0 and not timed_out:
        # A full disk is the kit's own measure of its own folder's disk, never a word the compiler
        # printed (it quotes the student's source). What the compile itself wrote (out/) is the
        # student's: at most a few files of file_mb each, so a disk with less room than one of them
        # left after the compile ended is the machine's, whatever the compile wrote.
        full = faults.disk_full(work, iso.limits.file_mb * MiB)
        if full and faults.usage(out) < iso.limits.file_mb * MiB:
            raise faults.MachineFault(f"{full}, in the {kind} of the step")
    if cached is not None and returncode == 0 and not timed_out:
        cached.store(out, text)
    status, text = _finish(kind, iso, text, returncode, timed_out, total, mapping, copies, memory)
    for dep in dep_files if status == 0 else []:
        made = next((str(target) for _, target, mode in copies if mode == 0o755), "")
        with suppress(OSError):
            dep.parent.mkdir(parents=True, exist_ok=True)
            dep.write_text(f"{made}:\n")
    return status, text


def _run_once(argv: list[str], out: Path, env: dict[str, str], iso: Isolation, memory: int,
              uid: int) -> tuple[int, str, int, bool]:
    """One run of the compiler or linker in the boundary: its exit status, the first output_kb of what
    it printed, how many bytes it printed, and whether the kit stopped it at its time limit."""
    limits = iso.limits
    start = time.monotonic()
    proc = subprocess.Popen(argv, cwd=out, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
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
    proc.stdout.close()
    return proc.returncode, kept.decode("utf-8", "replace"), total, timed_out


def _finish(kind: str, iso: Isolation, text: str, status: int, timed_out: bool, total: int,
            mapping: list[tuple[str, str]], copies: list[tuple[Path, Path, int]], memory: int) -> tuple[int, str]:
    """The compile's or link's diagnostics, as the student's own, and its outputs copied back."""
    from ..common import printable
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
                if faults.machine_errno(e):     # the kit's own write into its build folder
                    raise faults.MachineFault(f"{e.strerror}, writing the {kind}'s output into the kit's "
                                              "build folder") from e
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
    with suppress(OSError):
        os.killpg(proc.pid, signal.SIGKILL)

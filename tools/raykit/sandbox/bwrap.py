"""Bubblewrap: whether it works here, and the allow-list of the machine it shows graded code (system_view)."""

from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from contextlib import suppress
from pathlib import Path

from ..common import BUILD, ROOT
from .limits import HIDDEN, HIDDEN_TMPFS_BYTES, SYSTEM, SYSTEM_ETC, SYSTEM_LINKS
from .ids import first_uid


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
    with suppress(OSError):
        if Path.cwd() != BUILD and BUILD not in Path.cwd().parents:
            raise OSError("not a build folder of the kit")
        with open("CMakeCache.txt", errors="replace") as cache:
            for line in cache:
                if line.startswith("CMAKE_CXX_COMPILER:"):
                    words.append(line.split("=", 1)[1].strip())
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


def bwrap_argv(ro: list[tuple[Path, str]], rw: list[tuple[Path, str]], chdir: str,
               tmpfs: list[tuple[str, int]] = (), use: str = "") -> list[str]:
    """Bubblewrap's argv prefix (Isolation.wrapper): the allow-list of the machine (system_view), a fresh
    /dev, /proc and HIDDEN, then `ro` and `rw`, host folders (or files) bound at the paths given, and
    `tmpfs`, sized empty folders. Nothing else of the machine exists there."""
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


def bwrap_works(uid: int | None = None) -> bool:
    """Whether bubblewrap starts here as the sandbox will start it: as `uid` when the kit is root
    (the first sandbox id by default), else as the kit's own user."""
    if uid is None and os.geteuid() == 0:
        uid = first_uid()
    key = f"bwrap{uid}"
    if key not in _probe:
        ok = False
        if shutil.which("bwrap"):
            probe = bwrap_argv([], [], "/")
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
    from ..common import KitError, note
    from ..packages import ensure_packages
    if shutil.which("bwrap") is None:
        try:
            ensure_packages("sandbox")
        except KitError as e:
            note(f"kit: bubblewrap is not installed ({str(e).splitlines()[0]}); grading without it")

"""The build layer's store of compiled student objects, by content (ObjectCache).

The same files compiled the same way (copies of the stubs or of a solution across a class) are
compiled once per build/ folder. The boundary runs the compile (sandbox.Isolation.tool) and asks the
cache it is handed (checking.build_step hands it this one) whether the object is known; what decides
a hit is decided here. The kit's own objects are not compiled by a check at all (bundle.py). Dependency
files are read with compilers.dependencies and the compiler named with compilers.compiler_identity.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import stat
import tempfile
from contextlib import suppress
from pathlib import Path

from .common import BUILD, ROOT
from .compilers import compiler_identity, dependencies
from .sandbox import MiB, SECRET_PARTS, Isolation


class ObjectCache:
    """Compiled objects by content: the same files compiled the same way (copies of the stubs or of
    a solution across a class) are compiled once per build/ folder. An entry is reused only where
    the compile would give the same result, so its key holds everything that decides it:

    - the command (the private folder's name aside), every file of the step's folder, the kit's
      headers (the private folder's inputs: a superset of what its dependency file can name there) and
      the compiler's identity (compilers.compiler_identity: the program `c++` leads to, its size and
      time, so an upgraded compiler misses);
    - the boundary, which decides what the compile could read: its kind (bwrap, user, none), the
      bubblewrap command (what is hidden and bound), under the user isolation the rights "others"
      have on the kit's secret parts, and the compile's limits. An object compiled with
      --isolation none, which may have read the answers, is never given to a sandboxed compile;
    - apart from the key, every other input the compile's dependency file names (the headers it read
      outside its private folder, the system's: the C++ library, GLM; read with compilers.dependencies,
      the kit's one depfile reader), with their size, time, inode and rights: checked when the entry
      is fetched, so an upgraded header is compiled anew.

    Written by the grader from a compile that succeeded, read only by the grader (build/ is out of
    the sandbox's reach); files are read and written without following links. RAYKIT_NO_OBJCACHE=1
    turns it off. The boundary (sandbox.Isolation.tool) is given this class by its caller (checking.py)
    and keeps no cache of its own."""

    ROOT_DIR = BUILD / "objcache"
    DEPS = "deps.json"

    def __init__(self, argv: list[str], work: Path, src: Path, iso: Isolation, prefix: list[str]):
        self.work = str(work)
        self.text = ""
        self.dir: Path | None = None
        self.stale = False          # an entry is there, made before a header it read changed
        if os.environ.get("RAYKIT_NO_OBJCACHE") == "1":
            return
        h = hashlib.sha256(b"raykit-objcache-3\0")
        h.update(json.dumps([a.replace(self.work, "@W@") for a in argv]).encode())
        kind = iso.mode.split(":")[0]
        boundary = {"kind": kind, "wrapper": [a.replace(self.work, "@W@") for a in prefix],
                    "limits": [iso.limits.compile_seconds, iso.limits.compile_memory_mb, iso.limits.cpu_seconds,
                               iso.limits.file_mb]}
        try:
            if kind == "user":
                boundary["others"] = {part: stat.S_IMODE(os.lstat(ROOT / part).st_mode) & 0o7
                                      for part in SECRET_PARTS if os.path.lexists(ROOT / part)}
            h.update(json.dumps(boundary, sort_keys=True).encode())
            h.update(compiler_identity(argv[0]).encode() + b"\0")
            for folder in (src, work / "include"):
                for f in sorted(folder.rglob("*")):
                    if f.is_file():
                        h.update(str(f.relative_to(work)).encode() + b"\0" + f.read_bytes() + b"\0")
        except OSError:
            return
        key = h.hexdigest()
        self.dir = self.ROOT_DIR / key[:2] / key

    # --- the headers read from outside the private folder ---------------------------------
    @staticmethod
    def _identity(path: str) -> list | None:
        try:
            st = os.stat(path)
        except OSError:
            return None
        return [st.st_size, st.st_mtime_ns, st.st_ino, stat.S_IMODE(st.st_mode)]

    def _outside(self, out: Path, depfiles: list[bytes]) -> list | None:
        """[path, identity] of every file the compile read outside its private folder, or None when
        one cannot be told (then the entry is not kept)."""
        seen: dict[str, list] = {}
        for body in depfiles:
            for name in dependencies(body.decode("utf-8", "replace")):
                path = os.path.normpath(name if os.path.isabs(name) else os.path.join(str(out), name))
                if path == self.work or path.startswith(self.work + "/") or path in seen:
                    continue
                ident = self._identity(path)
                if ident is None:
                    return None
                seen[path] = ident
        return [[p, i] for p, i in sorted(seen.items())]

    # --- the entries ----------------------------------------------------------------------
    def fetch(self, out: Path) -> bool:
        if self.dir is None or not (self.dir / "done").is_file():
            return False
        try:
            recorded = json.loads((self.dir / self.DEPS).read_text())
            if any(self._identity(path) != ident for path, ident in recorded):
                self.stale = True       # a header it read has changed since (an upgrade)
                return False
            for f in self.dir.iterdir():
                if f.name in ("done", "text", self.DEPS):
                    continue
                data = f.read_bytes()
                if f.name.endswith(".d"):
                    data = data.replace(b"@W@", self.work.encode())
                fd = os.open(out / f.name, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
                try:
                    os.write(fd, data)
                finally:
                    os.close(fd)
            self.text = (self.dir / "text").read_text().replace("@W@", self.work)
        except (OSError, ValueError, TypeError):
            return False
        return True

    def store(self, out: Path, text: str) -> None:
        if self.dir is None:
            return
        if self.stale:              # replaced by this compile's, which read the headers as they are now
            old = self.dir.with_name(f".{self.dir.name}.stale.{os.getpid()}")
            with suppress(OSError):
                os.rename(self.dir, old)
            shutil.rmtree(old, ignore_errors=True)
        if self.dir.exists():
            return
        tmp = None
        try:
            # A name of this compile's own (two threads of one check, or two checks, may store the
            # same object at once): made whole there, then renamed in; the later rename loses.
            self.dir.parent.mkdir(parents=True, exist_ok=True)
            kept: dict[str, bytes] = {}
            for f in out.iterdir():
                if f.suffix not in (".o", ".d"):
                    continue
                fd = os.open(f, os.O_RDONLY | os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NONBLOCK)
                try:
                    st = os.fstat(fd)
                    if not stat.S_ISREG(st.st_mode) or st.st_size > 64 * MiB:
                        continue
                    data = b""
                    while len(data) <= 64 * MiB:
                        chunk = os.read(fd, 1 << 20)
                        if not chunk:
                            break
                        data += chunk
                finally:
                    os.close(fd)
                kept[f.name] = data
            outside = self._outside(out, [d for n, d in kept.items() if n.endswith(".d")])
            if outside is None or not any(n.endswith(".d") for n in kept):
                return                  # what it read cannot be told: not kept
            tmp = Path(tempfile.mkdtemp(prefix=f".{self.dir.name}.", dir=self.dir.parent))
            for name, data in kept.items():
                if name.endswith(".d"):
                    data = data.replace(self.work.encode(), b"@W@")
                (tmp / name).write_bytes(data)
            (tmp / self.DEPS).write_text(json.dumps(outside))
            (tmp / "text").write_text(text.replace(self.work, "@W@"))
            (tmp / "done").write_text("")
            os.rename(tmp, self.dir)
        except OSError:
            if tmp is not None:
                shutil.rmtree(tmp, ignore_errors=True)

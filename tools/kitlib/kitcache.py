"""The kit's own objects, compiled once per kit version and kept across build folders.

A cold `./kit check` spends most of its compile time on files the student never touches: doctest's
main, the judges, the dispatchers (measured: about two thirds of the CPU of a cold check of the five
solutions). They are the same for every build folder of the same kit on the same compiler, so CMake
runs their compiles through this launcher (CXX_COMPILER_LAUNCHER of the kit's own targets only, set
when RAYKIT_KIT_CACHE names a folder): a `git clean` of build/, a second handout or a grading slot
gets them from the cache instead of the compiler.

Never for a student's file: only the kit's targets (raykit_test_support, raykit_platform,
dispatchNN, test_stepNN) are given this launcher, and their command lines read only the kit's files and
the system's headers.

How an entry is found (the "direct" way of a compiler cache): the first key is the compiler (its real
path, size and time stamp), the working folder, the command line and the environment variables that
change what the compiler reads. Under it, each entry lists every file the compile read (from its
dependency file) with the SHA-256 of its content; an entry is used only when every one of those files
still has that content. So an edited header, a new GLM or another compiler misses, and compiles.

A first build with an empty cache has nothing to find and would only store, at one Python start per
compile: the kit configures such a folder without this launcher and, after each build, stores what
it compiled itself (fill, called by kitlib/build.py's fill_kit_cache: one process for all, each
header hashed once), under the key the launcher computes, with the files Ninja recorded as read.

Usage (by CMake, not by hand):  python3 -S kitcache.py CACHE_DIR COMPILER ARGS...
Any trouble with the cache (unwritable, damaged, full disk) falls back to running the compiler.
Set RAYKIT_KIT_CACHE_LOG to a file to have a line appended per compile: "hit OBJ" or "miss OBJ".
Standard library only: it runs with -S. It runs once per compile of the kit's own files, so it imports
only os, sys and hashlib (no json, subprocess or shutil, which took 35 ms of its 55 ms start):
an entry's manifest is a line per file read, and the compiler is started with posix_spawn.
"""

from __future__ import annotations

import hashlib
import os
import sys

VERSION = b"raykit-kitcache-2\0"
MANIFEST = "manifest"       # "SHA256 PATH" per line: every file the compile read
ENV_READ = ("CPATH", "CPLUS_INCLUDE_PATH", "C_INCLUDE_PATH", "GCC_EXEC_PREFIX", "COMPILER_PATH", "SOURCE_DATE_EPOCH")
MAX_BYTES = 2 << 30        # the cache is pruned to half of this, oldest first, when it grows past it
MAX_OBJECT = 256 << 20


def option(args: list[str], name: str) -> str | None:
    for i, a in enumerate(args[:-1]):
        if a == name:
            return args[i + 1]
    return None


def which(program: str) -> str:
    """`program` as the shell finds it on PATH (shutil.which, without importing shutil)."""
    if "/" in program:
        return program
    for folder in os.environ.get("PATH", os.defpath).split(os.pathsep):
        candidate = os.path.join(folder or ".", program)
        if os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
    return program


def compiler_identity(compiler: str) -> str:
    """The compiler as a cache key sees it (kitcache and objcache): the program the name leads to, through
    PATH and every link (/usr/bin/c++ -> g++-12), with its size and time stamp, which an upgrade changes.
    OSError when there is no such program."""
    real = os.path.realpath(which(compiler))
    st = os.stat(real)
    return f"{real}\0{st.st_size}\0{st.st_mtime_ns}"


def first_key(compiler: str, args: list[str], cwd: str | None = None) -> str:
    """The key of a compile run in `cwd` (the launcher's own folder, where the build tool started it)."""
    h = hashlib.sha256(VERSION)
    h.update(f"{compiler_identity(compiler)}\0{cwd or os.getcwd()}\0".encode())
    h.update(f"{len(args)}\0".encode() + "\0".join(args).encode())
    h.update("\0".join(f"{v}={os.environ[v]}" for v in ENV_READ if v in os.environ).encode())
    return h.hexdigest()


def file_hash(path: str, memo: dict | None = None) -> str | None:
    """The SHA-256 of a file's content; None when it cannot be read. `memo` keeps those already
    read by this process (the fill hashes the headers the kit's compiles share once)."""
    if memo is not None:
        if path not in memo:
            memo[path] = file_hash(path)
        return memo[path]
    try:
        with open(path, "rb") as f:
            return hashlib.sha256(f.read()).hexdigest()
    except OSError:
        return None


def dependencies(depfile_text: str) -> list[str]:
    """The prerequisites of a Make-style dependency file (GCC's and Clang's -MD, with or without -MP),
    the kit's one reader of them (kitcache, objcache): after each rule's colon, the names, a backslash
    at a line's end a continuation (LF or CRLF), `\\ ` an escaped space, `\\#` a `#`, `$$` a `$`.
    The empty rules -MP adds for each header (`header.hpp:`) name nothing more."""
    text = depfile_text.replace("\\\r\n", " ").replace("\\\n", " ")
    deps: list[str] = []
    for line in text.splitlines():
        _, sep, rest = line.partition(": ")
        if not sep:
            continue                  # an empty rule (-MP's `header.hpp:`), a blank line
        word, i = "", 0
        while i < len(rest):
            c = rest[i]
            if c == "\\" and rest[i + 1:i + 2] in (" ", "#", "\\"):
                word += rest[i + 1]
                i += 2
                continue
            if c == "$" and rest[i + 1:i + 2] == "$":
                word += "$"
                i += 2
                continue
            if c.isspace():
                if word:
                    deps.append(word)
                word = ""
            else:
                word += c
            i += 1
        if word:
            deps.append(word)
    return deps


def log(what: str, out: str) -> None:
    path = os.environ.get("RAYKIT_KIT_CACHE_LOG")
    if path:
        try:
            with open(path, "a") as f:
                f.write(f"{what} {out}\n")
        except OSError:
            pass


def copy(source: str, target: str) -> None:
    """The bytes of `source` into `target`, made afresh (shutil.copyfile, without importing shutil)."""
    with open(source, "rb") as f:
        data = f.read()
    with open(target, "wb") as f:
        f.write(data)


def remove_tree(path: str) -> None:
    """Removes a cache entry's folder (files only, one level), ignoring what cannot be removed."""
    try:
        for name in os.listdir(path):
            try:
                os.unlink(os.path.join(path, name))
            except OSError:
                pass
        os.rmdir(path)
    except OSError:
        pass


def read_manifest(path: str) -> list[tuple[str, str]]:
    """An entry's files and their hashes; ValueError when the manifest is damaged."""
    with open(path) as f:
        lines = f.read().split("\n")
    if not lines or lines[-1] != "":
        raise ValueError("not a whole manifest")
    pairs = []
    for line in lines[:-1]:
        digest, sep, name = line.partition(" ")
        if not sep or len(digest) != 64 or not name:
            raise ValueError(f"damaged manifest line: {line!r}")
        pairs.append((name, digest))
    if not pairs:
        raise ValueError("an empty manifest")
    return pairs


def lookup(bucket: str, out: str, depfile: str | None) -> bool:
    """Copies a matching entry's object (and dependency file) into place; whether one matched."""
    try:
        names = sorted(os.listdir(bucket))
    except OSError:
        return False
    for name in names:
        entry = os.path.join(bucket, name)
        try:
            if not all(file_hash(p) == digest for p, digest in read_manifest(os.path.join(entry, MANIFEST))):
                continue
            tmp = f"{out}.kitcache.{os.getpid()}"
            copy(os.path.join(entry, "object"), tmp)
            os.replace(tmp, out)
            if depfile:
                copy(os.path.join(entry, "depfile"), depfile)
            with open(os.path.join(entry, "stderr"), "rb") as f:
                sys.stderr.buffer.write(f.read())
            os.utime(os.path.join(entry, MANIFEST))     # recently used: pruned last
            return True
        except (OSError, ValueError):
            continue
    return False


def store(cache: str, bucket: str, out: str, text: str, stderr: bytes, memo: dict | None = None,
          pruned: bool = True) -> bool:
    """Keeps the object `out` under `bucket`, with `text` (its dependency file) and what the compile
    printed: an entry per set of files read and their contents. Whether it is (now) in the cache.
    `pruned` False leaves the cache's size to the caller (a fill prunes once, after all its stores)."""
    try:
        if os.path.getsize(out) > MAX_OBJECT:
            return False
        deps = [(os.path.abspath(p), file_hash(os.path.abspath(p), memo)) for p in dependencies(text)]
        if not deps or any(d is None or "\n" in p for p, d in deps):
            return False
        manifest = "".join(f"{d} {p}\n" for p, d in deps)
        digest = hashlib.sha256(manifest.encode()).hexdigest()[:32]
        entry = os.path.join(bucket, digest)
        if os.path.isdir(entry):
            return True
        tmp = os.path.join(bucket, f".{digest}.{os.getpid()}")
        os.makedirs(tmp)
        copy(out, os.path.join(tmp, "object"))
        with open(os.path.join(tmp, "depfile"), "w") as f:
            f.write(text)
        with open(os.path.join(tmp, "stderr"), "wb") as f:
            f.write(stderr)
        with open(os.path.join(tmp, MANIFEST), "w") as f:
            f.write(manifest)
        try:
            os.rename(tmp, entry)
        except OSError:
            remove_tree(tmp)    # another compile stored the same entry first
        if pruned:
            prune(cache)
        return os.path.isdir(entry)
    except (OSError, ValueError):
        return False


def depfile_text(out: str, deps: list[str]) -> str:
    """A dependency file naming `deps` for `out`, escaped as dependencies() reads it (and Ninja)."""
    def escaped(name: str) -> str:
        return name.replace("\\", "\\\\").replace(" ", "\\ ").replace("#", "\\#").replace("$", "$$")
    return escaped(out) + ":" + "".join(f" \\\n  {escaped(d)}" for d in deps) + "\n"


def fill(cache: str, cwd: str, command: list[str], deps: list[str], memo: dict) -> bool:
    """Stores an object a build compiled without this launcher, under the key the launcher would have
    given its compile: `command` as the build tool ran it in `cwd`, `deps` the files it read (the
    build tool's record, absolute). The fill of a first build (kitlib/build.py, fill_kit_cache): one
    process for all the kit's compiles instead of one launcher each; it prunes the cache once, after
    the last fill, not here. Whether it is in the cache."""
    out, depfile = option(command, "-o"), option(command, "-MF")
    if out is None or depfile is None or "-c" not in command or not deps:
        return False
    try:
        key = first_key(command[0], command[1:], cwd)
        bucket = os.path.join(cache, key[:2], key)
        os.makedirs(cache, mode=0o700, exist_ok=True)
        os.makedirs(bucket, exist_ok=True)
    except OSError:
        return False
    return store(cache, bucket, os.path.join(cwd, out), depfile_text(out, deps), b"", memo, pruned=False)


FORMER_MANIFEST = "manifest.json"   # an entry of raykit-kitcache-1: never found again, pruned first


def prune(cache: str) -> None:
    """Keeps the cache under MAX_BYTES: past it, the least recently used entries go until half is left
    (an entry of a former version first: no key of this one leads to it)."""
    entries, total = [], 0
    for root, dirs, files in os.walk(cache):
        if MANIFEST in files or FORMER_MANIFEST in files:
            size = sum(os.path.getsize(os.path.join(root, f)) for f in files)
            used = os.path.getmtime(os.path.join(root, MANIFEST)) if MANIFEST in files else 0.0
            entries.append((used, size, root))
            total += size
            dirs[:] = []
    if total <= MAX_BYTES:
        return
    for _, size, root in sorted(entries):
        remove_tree(root)
        total -= size
        if total <= MAX_BYTES // 2:
            break


def run(command: list[str]) -> tuple[int, bytes]:
    """Runs the compiler, its standard error captured (subprocess.run, without importing subprocess)."""
    read, write = os.pipe()
    try:
        pid = os.posix_spawn(which(command[0]), command, os.environ,
                             file_actions=[(os.POSIX_SPAWN_DUP2, write, 2), (os.POSIX_SPAWN_CLOSE, read)])
    except OSError as e:
        os.close(read)
        os.close(write)
        return 127, f"kitcache.py: cannot run {command[0]}: {e.strerror}\n".encode()
    os.close(write)
    chunks = []
    while True:
        chunk = os.read(read, 65536)
        if not chunk:
            break
        chunks.append(chunk)
    os.close(read)
    _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status), b"".join(chunks)


def main(argv: list[str]) -> int:
    if len(argv) < 3:
        print("kitcache.py: usage: kitcache.py CACHE_DIR COMPILER ARGS...", file=sys.stderr)
        return 2
    cache, command = argv[1], argv[2:]
    out, depfile = option(command, "-o"), option(command, "-MF")
    cacheable = out is not None and depfile is not None and "-c" in command
    bucket = None
    if cacheable:
        try:
            key = first_key(command[0], command[1:])
            bucket = os.path.join(cache, key[:2], key)
            if lookup(bucket, out, depfile):
                log("hit", out)
                return 0
        except OSError:
            bucket = None
    returncode, stderr = run(command)
    sys.stderr.buffer.write(stderr)
    if returncode == 0 and bucket is not None:
        log("miss", out)
        try:
            os.makedirs(cache, mode=0o700, exist_ok=True)     # the kit's user only (common.kit_cache_dir)
            os.makedirs(bucket, exist_ok=True)
            with open(depfile) as f:
                store(cache, bucket, out, f.read(), stderr)
        except OSError:
            pass
    return returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv))

"""Precompiled step headers for the graded compile of a student's file.

A stub starts with the step's header (`#include "raykit/unit_sphere.hpp"`), and most of a graded
compile is spent reading what that header brings in (GLM, the standard library): 1.9 of 2.4 s of
CPU for the six files of the solutions, measured with GCC 12. GCC's own mechanism removes that work
without changing what the file means: when an `#include` comes before any C++ token and a file
`HEADER.gch` lies beside the header it names, built by the same compiler with the same options, GCC
reads that instead; if anything differs (another first include, a macro defined before it, other
options), it silently reads the header as usual. So a student's file compiles exactly as it would
without it, only sooner.

The kit builds one such file per step header, from the kit's own public headers and outside the
sandbox (nothing of a student's goes in), keyed by the compiler and the options of the compile it
serves (the compiler named as the kit's caches name it, compilers.compiler_identity), and kept in
build/student-pch/ with the list of every file it read (from its dependency file, read by the kit's
one parser, compilers.dependencies), each with its size and time, as the object cache records the
headers a compile read outside its folder (objcache.py): a changed header, GLM or compiler makes it
be built again. Size and time, not content: the list is checked at every graded compile. The graded
compile sees it beside the header in its private include folder, hard-linked there (copied where
links cannot be made).

Building the six costs about 3 s of CPU, so they are built only where many compiles follow:
RAYKIT_STUDENT_PCH=build (set by ./kit grade and by the autograders' set-up); otherwise those already
built are used; "off" uses none (to measure without them). GCC only: Clang does not look for them.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import subprocess
import threading
from contextlib import suppress
from pathlib import Path

from . import atomic
from .common import BUILD, ROOT
from .compilers import compiler_identity, dependencies

ENV = "RAYKIT_STUDENT_PCH"
STORE = BUILD / "student-pch"
FIRST_INCLUDE = re.compile(r'^\s*#\s*include\s*"(raykit/[A-Za-z0-9_./-]+\.hpp)"', re.M)

_headers: list[str] | None = None
_gcc: dict[str, bool] = {}
_lock = threading.Lock()


def step_headers() -> list[str]:
    """The header each shipped stub includes first (include/raykit/..., relative to include/)."""
    global _headers
    if _headers is None:
        found = set()
        for stub in sorted((ROOT / "steps").glob("*/*.cpp")):
            with suppress(OSError):
                m = FIRST_INCLUDE.search(stub.read_text(errors="replace"))
                if m and (ROOT / "include" / m.group(1)).is_file():
                    found.add(m.group(1))
        _headers = sorted(found)
    return _headers


def options_of(argv: list[str]) -> list[str]:
    """The compile's options without its input, output and dependency file: what the header is
    compiled with, so that GCC finds the result valid for this compile."""
    kept, skip = [], False
    for a in argv[1:]:
        if skip:
            skip = False
            continue
        if a in ("-c", "-o", "-MT", "-MF", "-MQ"):
            skip = True
            continue
        if a in ("-MD", "-MMD"):
            continue
        kept.append(a)
    return kept


def _absolute(options: list[str], cwd: Path) -> list[str]:
    """The options with their include folders made absolute: CMake 3.18 writes them relative to the
    build folder (-I../../include), which names the same folder from every build/NAME, so the key
    stays one per compiler and options, not one per build folder."""
    out, flag = [], None
    for a in options:
        if flag:
            out.append(os.path.normpath(os.path.join(cwd, a)))
            flag = None
            continue
        if a in ("-I", "-isystem", "-iquote"):
            flag = a
        else:
            for f in ("-isystem", "-iquote", "-I"):
                if a.startswith(f) and len(a) > len(f):
                    a = f + os.path.normpath(os.path.join(cwd, a[len(f):]))
                    break
        out.append(a)
    return out


def _is_gcc(compiler: str) -> bool:
    if compiler not in _gcc:
        try:
            r = subprocess.run([compiler, "-dM", "-E", "-x", "c++", os.devnull], capture_output=True, text=True,
                               timeout=30)
            _gcc[compiler] = r.returncode == 0 and "__GNUC__" in r.stdout and "__clang__" not in r.stdout
        except (OSError, subprocess.TimeoutExpired):
            _gcc[compiler] = False
    return _gcc[compiler]


def _deps_current(deps_file: Path) -> bool:
    try:
        deps = json.loads(deps_file.read_text())
        return bool(deps) and all((st.st_size, st.st_mtime_ns) == (size, mtime)
                                  for path, size, mtime in deps for st in [os.stat(path)])
    except (OSError, ValueError, TypeError):
        return False


def _build(compiler: str, options: list[str], header: str, gch: Path, cwd: Path) -> bool:
    gch.parent.mkdir(parents=True, exist_ok=True)
    # The compile's folder, where its relative paths start: a check's first compile comes before its
    # build folder is made (the compile itself runs in a private one), and a compiler started in a
    # folder that is not there fails: the first step of every fresh build folder went without.
    cwd.mkdir(parents=True, exist_ok=True)
    tmp = gch.with_name(f".{gch.name}.{os.getpid()}.{id(options)}")
    dep = tmp.with_suffix(".d")
    try:
        r = subprocess.run([compiler, *options, "-x", "c++-header", str(ROOT / "include" / header),
                            "-o", str(tmp), "-MD", "-MF", str(dep)], capture_output=True, timeout=300, cwd=cwd)
        if r.returncode != 0 or not tmp.is_file():
            return False
        # The options' paths are the build folder's.
        deps = [[path, st.st_size, st.st_mtime_ns] for p in dependencies(dep.read_text(errors="replace"))
                for path in [os.path.abspath(os.path.join(cwd, p))] for st in [os.stat(path)]]
        os.chmod(tmp, 0o644)        # read by the compile's own user id, through its private folder
        os.replace(tmp, gch)
        atomic.write(gch.with_name(gch.name + ".deps.json"), json.dumps(deps))
        return True
    except (OSError, subprocess.TimeoutExpired):
        return False
    finally:
        tmp.unlink(missing_ok=True)
        dep.unlink(missing_ok=True)


def for_compile(argv: list[str], source: str, cwd: Path) -> list[tuple[Path, str]]:
    """The precompiled header a compile `argv` (as CMake gave it, run in `cwd`) of a file `source`
    (its text) may use: the one of the step header the file includes first, as (file, its name
    relative to include/, e.g. "raykit/rect.hpp.gch"); GCC still decides whether it applies. Built
    when missing and RAYKIT_STUDENT_PCH is "build"; none when it is "off", or for a compiler other
    than GCC."""
    mode = os.environ.get(ENV, "")
    first = FIRST_INCLUDE.search(source)
    if mode == "off" or not argv or first is None or first.group(1) not in step_headers():
        return []
    compiler = argv[0]
    options = options_of(argv)
    try:
        named = json.dumps([compiler_identity(compiler), _absolute(options, cwd)])
        key = hashlib.sha256(named.encode()).hexdigest()[:24]
    except OSError:
        return []
    folder = STORE / key
    if (not folder.is_dir() and mode != "build") or not _is_gcc(compiler):
        return []
    header = first.group(1)
    gch = folder / (header + ".gch")
    with _lock:         # the compiles of one check run in threads: one build of each header
        current = gch.is_file() and _deps_current(gch.with_name(gch.name + ".deps.json"))
        if not current and mode == "build":
            current = _build(compiler, options, header, gch, cwd)
    return [(gch, header + ".gch")] if current else []

"""The compiler as the kit's caches see it: its identity, and what a compile read (its dependency file).

The bundle (bundle.py), the student's object cache (objcache.py) and the precompiled step header
(studentpch.py) key what they keep by the compiler's identity and check it against the files a
compile read; both answers are given here, once.
"""

from __future__ import annotations

import os
import shutil


def compiler_identity(name: str) -> str:
    """The compiler as a cache key sees it: the program the name leads to, through PATH and every
    link (/usr/bin/c++ -> g++-12), with its size and time stamp, which an upgrade changes. OSError
    when there is no such program."""
    found = name if "/" in name else shutil.which(name)
    if found is None:
        raise OSError(f"no compiler {name} on PATH")
    real = os.path.realpath(found)
    st = os.stat(real)
    return f"{real}\0{st.st_size}\0{st.st_mtime_ns}"


def dependencies(depfile_text: str) -> list[str]:
    """The prerequisites of a Make-style dependency file (GCC's and Clang's -MD, with or without -MP),
    the kit's one reader of them (objcache, studentpch): after each rule's colon, the names, a backslash
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

"""What judged a grading: every input that can change a verdict or a point, file by file.

`./kit grade` hashes these once per grading (not per submission), keeps the list, sealed under the
secret (secret.seal), beside its records as `json/.judged-by.json` (a name no student's record can
take: ./kit grade skips folders whose name starts with a dot), and hands the list's digest to each check
it starts (ENV), which writes it into its record as `grader.cases` (record.grader). The merge of several
machines' gradings (report/merge.py) compares the lists and names the first file that differs.

    {"format": "raykit-judged-by", "version": 1,
     "secret": "<secret.fingerprint>", "digest": "<16 hex>",
     "compiler": "/usr/bin/x86_64-linux-gnu-g++-12, 1020288 bytes, modified 2023-05-09 ...; CXXFLAGS=...",
     "files": {"course.json": "<sha256>", "include/raykit/scenes/cornell_box.inc": "<sha256>", ...},
     "mac": "..."}

What it covers (INPUTS): course.json (the scale, weights, limits); CMake's files (how the judges and the
student's code are compiled); include/ (the kit's headers, the scene); solutions/ (the reference answers);
tests/ (the cases, their judges and support, the hidden families); the kit's own Python (tools/raykit
and tools/kitlib: how a check builds, runs, judges and scores, and how a grading runs the checks), and
the compiler with the settings CMake reads from the environment (bundle.ENV_READ). Which files: those git tracks or would track (kitfiles.kit_files: a file
added and not ignored counts; build output, caches and tests/hidden/secret.key do not).

Left out, as they decide no verdict nor point: the self-test (tests/kit/), the class report
and this merge (tools/kitlib/report/: they read a grading, judge nothing), the mutants' signatures
(tests/mutants/signatures.json: the report's slip names, written by `./kit report --signatures`), the
steps' handout (steps/: what a student starts from; the submission brings its own files), the docs.
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from pathlib import Path

from . import secret as secret_file
from .common import ROOT, KitError

FORMAT = "raykit-judged-by"
VERSION = 1
FILE_NAME = ".judged-by.json"
ENV = "RAYKIT_JUDGED_BY"        # the digest, from ./kit grade to each of its checks
COMPILER = "the compiler"       # how a refusal names the compiler entry

INPUTS = ("course.json", "CMakeLists.txt", "CMakePresets.json", "cmake/", "include/", "solutions/", "tests/",
          "tools/raykit/", "tools/kitlib/")
LEFT_OUT = ("tests/kit/", "tools/kitlib/report/", "tests/hidden/secret.key",
            "tests/mutants/signatures.json")


def _chosen(rel: str) -> bool:
    def under(prefixes) -> bool:
        return any(rel == p or (p.endswith("/") and rel.startswith(p)) for p in prefixes)
    parts = rel.split("/")
    return under(INPUTS) and not under(LEFT_OUT) and "__pycache__" not in parts and not rel.endswith(".pyc") \
        and parts[0] != "build"


def files(root: Path = ROOT) -> list[str]:
    """The inputs' paths, relative to the kit, sorted: git's files (tracked, or new and not ignored), else,
    in a copy that is no clone (an autograder's), every file under the inputs."""
    from .kitfiles import is_clone, kit_files
    if root == ROOT and is_clone():
        found = kit_files()
    else:
        found = [p.relative_to(root) for top in INPUTS for p in ([root / top] if not top.endswith("/") else
                 (root / top).rglob("*")) if p.is_file()]
    return sorted({p.as_posix() for p in found if _chosen(p.as_posix()) and (root / p).is_file()})


def compiler() -> str:
    """The compiler CMake takes, as the bundle's key names it (the program it leads to, its size and
    time), with what CMake reads from the environment."""
    from .bundle import ENV_READ, compiler as cxx
    from .compilers import compiler_identity
    try:
        real, size, mtime = compiler_identity(cxx()).split("\0")
    except OSError as e:
        raise KitError(f"no C++ compiler to grade with: {e}")
    when = time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime(int(mtime) / 1e9))
    settings = [f"{n}={os.environ[n]}" for n in ENV_READ if os.environ.get(n)]
    return f"{real}, {size} bytes, modified {when} UTC" + ("; " + " ".join(settings) if settings else "")


def digest(entries: dict[str, str], compiler_text: str) -> str:
    h = hashlib.sha256(b"raykit-judged-by-1\0")
    h.update(compiler_text.encode("utf-8", "surrogateescape") + b"\0")
    for rel in sorted(entries):
        h.update(rel.encode("utf-8", "surrogateescape") + b"\0" + entries[rel].encode() + b"\0")
    return h.hexdigest()[:16]


def build(root: Path = ROOT) -> dict:
    """This copy of the kit's list, unsealed."""
    entries = {}
    for rel in files(root):
        try:
            entries[rel] = hashlib.sha256((root / rel).read_bytes()).hexdigest()
        except OSError as e:
            raise KitError(f"{rel}: cannot read it to name what judges this grading ({e.strerror})")
    text = compiler()
    return {"format": FORMAT, "version": VERSION, "secret": secret_file.fingerprint(), "digest": digest(entries, text),
            "compiler": text, "files": entries}


def current_digest() -> str:
    """The digest a check writes into its record: the grading's (ENV), else this copy's, computed now."""
    return os.environ.get(ENV) or build()["digest"]


def write(folder: Path, manifest: dict, key: bytes) -> Path:
    from . import atomic
    path = folder / FILE_NAME
    try:
        atomic.write(path, json.dumps(secret_file.seal(manifest, key), indent=1, ensure_ascii=False) + "\n")
    except OSError as e:
        raise KitError(f"{path}: cannot write it ({e.strerror})")
    return path


def read(path: Path) -> dict | None:
    """A manifest as written (its seal unchecked), None when there is none; KitError when it is not one."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as e:
        raise KitError(f"{path}: not the list of what judged a grading ({e.__class__.__name__})")
    if not (isinstance(data, dict) and data.get("format") == FORMAT and data.get("version") == VERSION
            and isinstance(data.get("files"), dict)):
        raise KitError(f"{path}: not the list of what judged a grading (format {FORMAT} version {VERSION})")
    return data


def first_difference(a: dict, b: dict) -> tuple[str, str] | None:
    """The first input two lists disagree on, and how: ("include/x.inc", "differs" | "only in the first" |
    "only in the second"); the compiler first. None when they agree."""
    if a.get("compiler") != b.get("compiler"):
        return COMPILER, "differs"
    fa, fb = a["files"], b["files"]
    for rel in sorted(set(fa) | set(fb)):
        if rel not in fb:
            return rel, "only in the first"
        if rel not in fa:
            return rel, "only in the second"
        if fa[rel] != fb[rel]:
            return rel, "differs"
    return None

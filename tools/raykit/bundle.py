"""The kit's side, built once per machine: the bundle.

Everything a check runs that never holds a student's code (the judges with doctest's runner, the
reporter and the remote calls; the dispatchers; the platform layer; the stand-ins; the reference's
answers programs, and with them the hidden cases) is one CMake build of the kit alone
(CMakeLists.txt, RAYKIT_BUNDLE; the "bundle" preset). It is built into a folder named by the hash of
what it is made of (key()): the kit's sources that go into it, the compiler (the program `c++` or
$CXX leads to, its size and time) and the options that change it. A student's `rm -rf build`, a
second handout or a grading slot find it there; an edited header or another compiler makes another.

A check then compiles the student's files alone, with the command the bundle's probe was compiled
with (the flags a student's file gets, from compile_commands.json, with their file put in the
probe's place), and links them with the bundle's objects for the step (raykit-bundle.json: the
dispatcher, the platform layer, the stand-ins). No build folder is configured for a check, and the
build tool's rules are never read.

A grader's image carries it prebuilt (prebuild(): PrairieLearn's, in the course's private
serverFilesCourse/raykit-bundle/, built by the public grading image's own toolchain; Gradescope's, in
the private image's cache, by tools/gradescope/setup.sh): a job then finds it by its key and compiles
the student's files alone. A prebuilt bundle is used read-only and only under its own key, at the
folder it was built in, with the packages it was built with: a job whose toolchain or course differs
builds its own and says why (built(), in the kit's record and each grader's results).

The bundle is built by whoever needs it first: the warm-up (warmup.py), the autograders' set-up
(tools/gradescope/setup.sh, by grading the solutions), CI, or a check. One build at a time per key
(a lock file); a finished bundle is marked `ready` last, so a half-built one is never used, and one
whose build failed is built again from nothing. A check holds the bundle it uses (a shared lock on
its `in-use` file) until it ends; the least recently used bundles beyond a few are removed, each
only when no check of any copy of the kit holds it (its exclusive lock taken). The folder is
readable by its user only: a grading's judges hold the hidden cases and its reference answers
programs the reference's code (sandbox/: the graded code runs as another user, or where the folder
does not exist).
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shlex
import shutil
import time
from contextlib import suppress
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from .common import BUILD, KitError, ROOT, Step
from .compilers import compiler_identity
from .relocate import cache_entries
from .secret import SECRET_FILE
from .status import FAILED

VERSION = b"raykit-bundle-1\0"
RECIPE = "raykit-bundle.json"
READY = "ready"
IN_USE = "in-use"       # locked shared by every process that uses the bundle, exclusively to prune it
KEEP = 4                # bundles kept on a machine, the most recently used
ENV_READ = ("CXX", "CXXFLAGS", "LDFLAGS", "CMAKE_PREFIX_PATH", "CPATH", "CPLUS_INCLUDE_PATH", "RAYKIT_LINKER")
# The packages whose headers the bundle's programs are compiled with, by their CMake package's folder
# in the bundle's CMakeCache.txt: an upgrade rewrites the files there, which changes the folder's time,
# and the bundle is built again (a new compiler changes the key itself).
PACKAGE_DIRS = ("glm_DIR", "doctest_DIR")
PREBUILT_ENV = "RAYKIT_PREBUILT_BUNDLE"     # a folder of a bundle prebuilt for a grader (prebuild()), used read-only
PREBUILT_NOTE = "raykit-prebuilt.json"      # in it: what the bundle was built for (key, compiler, sources)
STUDENT_ONLY = "student files only"
BUILT_HERE = "kit side built in this job"
_built: list[str] = []      # what this process built of the kit's side, each with why (built())
_prebuilt_miss: list[str] = []      # why a prebuilt bundle named by PREBUILT_ENV was not used


def cache_root() -> Path:
    """RAYKIT_BUNDLE_DIR, else $XDG_CACHE_HOME/raykit/bundles or ~/.cache/raykit/bundles, made
    readable by its user only; where no such folder can be made (a home that cannot be written, as in
    some graders' containers), build/bundles in the kit, which graded code never sees either."""
    named = os.environ.get("RAYKIT_BUNDLE_DIR")
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "raykit" / "bundles"
    for folder in ([Path(named)] if named else [base, BUILD / "bundles"]):
        try:
            folder.mkdir(parents=True, exist_ok=True, mode=0o700)
            folder.chmod(0o700)
            if folder.parent.name == "raykit":
                folder.parent.chmod(0o700)
            if os.access(folder, os.W_OK | os.X_OK):
                return folder
        except (OSError, RuntimeError):
            continue
    raise KitError(f"the kit's bundle has no folder to live in (tried {named or base} and {BUILD / 'bundles'})",
                   FAILED)


def compiler() -> str:
    """The compiler CMake takes: $CXX, else `c++` on PATH."""
    return os.environ.get("CXX") or "c++"


def hidden_here() -> bool:
    """Whether the bundle holds the reference and the hidden cases (a grading's, the instructor's):
    solutions/ and tests/hidden/ are here (checking.hidden_cases_here)."""
    return (ROOT / "solutions").is_dir() and (ROOT / "tests" / "hidden").is_dir()


def shipped(f: Path) -> bool:
    """Whether `f` is a file a clone of the kit has: not one the kit writes itself among the sources
    (the instructor's secret, made by the first check that draws hidden cases; compiled Python; an
    atomic write's temporary file, atomic.py), none of which the bundle is made of (the hidden
    cases' seed reaches the judge at run time, RAYKIT_SEED: the secret is compiled into nothing).
    The self-test checks this against git: every tracked file of sources() is kept, every ignored
    one left out."""
    return not (f == SECRET_FILE or "__pycache__" in f.parts or f.suffix in (".tmp", ".pyc"))


def sources(hidden: bool) -> list[Path]:
    """Every file the bundle is made of: CMake's, the kit's headers, the judges and their support, and
    with the reference the hidden cases and the solutions. Not the steps, the fixtures or the tools,
    nor what the kit writes itself (shipped()): a fresh clone's first check does not change the key."""
    files = [ROOT / "CMakeLists.txt", ROOT / "CMakePresets.json"]
    folders = [ROOT / "cmake", ROOT / "include", ROOT / "tests" / "support"]
    folders += sorted(p for p in (ROOT / "tests").glob("[0-9][0-9]_*") if p.is_dir())
    if hidden:
        folders += [ROOT / "tests" / "hidden", ROOT / "solutions"]
    for folder in folders:
        files += sorted(p for p in folder.rglob("*") if p.is_file() and shipped(p))
    return files


def key(sanitize: bool, hidden: bool | None = None) -> str:
    hidden = hidden_here() if hidden is None else hidden
    h = hashlib.sha256(VERSION)
    h.update(f"sanitize={sanitize}\0hidden={hidden}\0".encode())
    # What CMake reads from the environment at a first configure, and the linker asked for.
    for name in ENV_READ:
        h.update(f"{name}={os.environ.get(name, '')}\0".encode())
    try:
        h.update(compiler_identity(compiler()).encode() + b"\0")
    except OSError as e:
        raise KitError(f"no C++ compiler to build with: {e}", FAILED) from e
    for f in sources(hidden):
        h.update(str(f.relative_to(ROOT)).encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()[:24]


@dataclass
class Bundle:
    """A built bundle: its folder and its recipe (raykit-bundle.json)."""
    folder: Path
    recipe: dict

    def judge(self, step: Step) -> Path:
        return Path(self.recipe["steps"][step.number]["judge"])

    def kit_objects(self, step: Step) -> list[str]:
        return list(self.recipe["steps"][step.number]["kit_objects"])

    def own_needs(self, step: Step) -> list[str]:
        """The folders of the student's own steps this step's answers program links (a handout, or a
        needed step the kit has no stand-in for)."""
        return list(self.recipe["steps"][step.number]["own_needs"])

    def compile_command(self, use: str, source: Path, out: Path) -> list[str]:
        """How a student's file is compiled (`use`: "check", their own; "grade", a graded one): the
        probe's command with the file and the object put in its place, and a dependency file beside
        the object (the object cache reads what the compile read). A bundle built from another copy
        of the same kit (a second handout: the key holds the content, not the place) names that
        copy's folders: they are this kit's here."""
        built_from = self.recipe.get("source_root", "")
        here = str(ROOT)
        argv = [a.replace(built_from + "/", here + "/") if built_from and built_from != here else a
                for a in self._probes()[use]]
        argv[argv.index("-o") + 1] = str(out)
        argv[argv.index("-c") + 1] = str(source)
        return argv[:1] + ["-MD", "-MF", str(out) + ".d"] + argv[1:]

    def link_command(self, objects: list[str], out: Path) -> list[str]:
        return [self.recipe["compiler"], *self.recipe["link_flags"], *objects, "-o", str(out)]

    def _probes(self) -> dict[str, list[str]]:
        if "_argv" not in self.recipe:
            entries = json.loads((self.folder / "compile_commands.json").read_text())
            found = {}
            for use, obj in self.recipe["probes"].items():
                for e in entries:
                    if "command" in e and os.path.basename(obj) not in e["command"]:
                        continue        # not the probe's: no need to split its words (0.06 s a check)
                    argv = e["arguments"] if "arguments" in e else shlex.split(e["command"])
                    out = argv[argv.index("-o") + 1] if "-o" in argv[:-1] else ""
                    if out and os.path.normpath(os.path.join(e["directory"], out)) == os.path.normpath(obj):
                        found[use] = argv
            if set(found) != set(self.recipe["probes"]):
                raise KitError(f"the kit's bundle in {self.folder} has no probe's command (built by another CMake?)",
                               FAILED)
            self.recipe["_argv"] = found
        return self.recipe["_argv"]


def _marks(folder: Path, parts: list[str] | None) -> list[Path]:
    """The marks that say the bundle in `folder` can serve `parts` (step numbers; None: every step):
    `ready` (all of it built), else each part's own `ready-NN`."""
    if parts is None or (folder / READY).is_file():
        return [folder / READY]
    return [folder / f"{READY}-{n}" for n in parts]


def _load(folder: Path, parts: list[str] | None = None) -> Bundle | None:
    """The bundle in `folder` when it is built (the steps `parts` of it at least) and the packages it
    was built with are unchanged."""
    if any(_load_mark(mark) is None for mark in _marks(folder, parts)):
        return None
    try:
        return Bundle(folder, json.loads((folder / RECIPE).read_text()))
    except (OSError, ValueError):
        return None


def _mtime(path: str) -> int | None:
    try:
        return os.stat(path).st_mtime_ns
    except OSError:
        return None


def _packages(folder: Path) -> dict[str, int | None]:
    return {path: _mtime(path) for name, path in cache_entries(folder / "CMakeCache.txt").items()
            if name in PACKAGE_DIRS}


def find(sanitize: bool) -> Bundle | None:
    """The bundle for this kit and compiler when it is built; None otherwise (not held: to look only)."""
    k = key(sanitize)
    return _prebuilt(k, None) or _load(_own_folder(cache_root(), k, None))


def built() -> dict:
    """What this process built of the kit's side, from its own doing (never from the graded code's):
    {"built": STUDENT_ONLY} when it built nothing of it (a bundle found ready: prebuilt, or built by
    an earlier job or check), else {"built": BUILT_HERE, "why": "..."}, why the bundle was not there."""
    if not _built:
        return {"built": STUDENT_ONLY}
    return {"built": BUILT_HERE, "why": "; ".join(dict.fromkeys(_prebuilt_miss + _built))}


def _prebuilt(k: str, parts: list[str] | None) -> Bundle | None:
    """The bundle prebuilt for this job (PREBUILT_ENV's folder) when it is this kit's under this
    toolchain: its key, the folder it was built in, the packages it was built with. Never written to
    (a course's files, copied into each job). None otherwise, and why is kept for built()."""
    where = os.environ.get(PREBUILT_ENV)
    if not where:
        return None
    folder = Path(where) / k
    found = _load(folder, parts)
    if found is not None and all(p.startswith(str(folder) + "/") for s in found.recipe.get("steps", {}).values()
                                 for p in [s.get("judge", "")] + list(s.get("kit_objects", []))):
        missing = _missing_files(Path(where), folder)
        if not missing:
            return found
        why = (f"the bundle prebuilt in {folder} lacks {len(missing)} of its files or has them changed ({missing[0]}, "
               "...): was it committed whole? (its .gitignore keeps the course's from leaving files out)")
    else:
        why = _prebuilt_mismatch(Path(where), k, folder, found)
    if why not in _prebuilt_miss:
        _prebuilt_miss.append(why)
    return None


def _prebuilt_mismatch(where: Path, k: str, folder: Path, found: Bundle | None) -> str:
    """Why the prebuilt bundle in `where` cannot serve this job (its key `k`), in the instructor's words."""
    try:
        note = json.loads((where / PREBUILT_NOTE).read_text())
        if not isinstance(note, dict):
            raise ValueError
    except (OSError, ValueError):
        return f"no bundle prebuilt for this course in {where} (graders/raykit/README.md says how to build it)"
    if note.get("key") != k:
        differ = []
        if note.get("compiler") != _compiler_words():
            differ.append(f"the compiler (prebuilt with {note.get('compiler')}; this job's {_compiler_words()})")
        if note.get("env") != _env_read():
            differ.append("the compiler's settings (CXX, CXXFLAGS, ...)")
        if note.get("sources") != _sources_digest():
            differ.append("the course's sources (the kit changed after the bundle was built)")
        return (f"the bundle prebuilt in {where} is for another toolchain or course (key {note.get('key')}, this "
                f"job's {k}): " + ("; ".join(differ) or "its options") + " differ")
    if found is not None:
        return (f"the bundle prebuilt in {folder} was built in {note.get('folder')}: it names that folder's files "
                f"(build it where the job finds it)")
    return (f"the bundle prebuilt in {folder} is incomplete, or its packages (GLM, doctest) are not this image's "
            "(the image was built again after it)")


def _missing_files(where: Path, folder: Path) -> list[str]:
    """The files PREBUILT_NOTE lists (each with its size) that `folder` lacks or holds at another size."""
    try:
        listed = json.loads((where / PREBUILT_NOTE).read_text())["files"]
    except (OSError, ValueError, KeyError, TypeError):
        return [PREBUILT_NOTE]
    missing = []
    for rel, size in listed.items():
        try:
            if (folder / rel).stat().st_size != size:
                missing.append(rel)
        except OSError:
            missing.append(rel)
    return missing


def _compiler_words() -> str:
    try:
        return compiler_identity(compiler()).replace("\0", ", ")
    except OSError:
        return "no compiler"


def _env_read() -> dict:
    return {name: os.environ.get(name, "") for name in ENV_READ}


def _sources_digest() -> str:
    h = hashlib.sha256()
    for f in sources(hidden_here()):
        h.update(str(f.relative_to(ROOT)).encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()[:24]


def prebuild(target: Path, sanitize: bool) -> Bundle:
    """Builds the whole bundle into `target` (emptied first) for a grader: PrairieLearn's job, which
    finds it through PREBUILT_ENV at this same path (the bundle names its own folder's files), and
    writes PREBUILT_NOTE, what it was built for, so a job that differs says how."""
    if target.exists():
        shutil.rmtree(target)
    target.mkdir(parents=True, mode=0o700)
    saved = os.environ.get("RAYKIT_BUNDLE_DIR")
    os.environ["RAYKIT_BUNDLE_DIR"] = str(target)
    try:
        found = ensure(sanitize)
    finally:
        if saved is None:
            os.environ.pop("RAYKIT_BUNDLE_DIR", None)
        else:
            os.environ["RAYKIT_BUNDLE_DIR"] = saved
    (target / f"{found.folder.name}.lock").unlink(missing_ok=True)
    note = {"key": found.folder.name, "folder": str(found.folder), "sanitize": sanitize, "hidden": hidden_here(),
            "compiler": _compiler_words(), "env": _env_read(),
            "sources": _sources_digest(), "built": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            "files": {p.relative_to(found.folder).as_posix(): p.stat().st_size
                      for p in sorted(found.folder.rglob("*")) if p.is_file() and p.name != IN_USE}}
    (target / PREBUILT_NOTE).write_text(json.dumps(note, indent=1) + "\n")
    # A course's own .gitignore (*.o, CMakeFiles/, ...) must not leave a file of it out of the commit.
    (target / ".gitignore").write_text("# raykit's prebuilt bundle: every file of it is committed\n!*\n!*/\n")
    return found


def ensure(sanitize: bool, starting: Callable[[], None] | None = None, parts: list[str] | None = None) -> Bundle:
    """The bundle for this kit and compiler, built first when there is none (one build at a time per
    key: a second caller waits for the first's); `starting()` is called before it builds. It is held
    (a shared lock on its IN_USE file) until this process ends: another copy of the kit pruning this
    machine's bundles leaves it alone while a check here links with it and runs its judges.
    `parts`: the steps (numbers) the caller needs, built alone when the bundle is not whole yet (a
    check of step 01 waits for step 01's judge, not for all five; the warm-up builds the rest). KitError
    when it cannot be built: the kit's fault or the machine's, never a student's."""
    k = key(sanitize)
    found = _prebuilt(k, parts)
    if found is not None:
        return found
    root = cache_root()
    folder = _own_folder(root, k, parts)
    found = _use(folder, parts)
    if found is not None:
        _touch(folder)
        return found
    if starting is not None:
        starting()
    lock = _locked(root / f"{k}.lock", fcntl.LOCK_EX)
    try:
        found = _use(folder, parts)     # built by the caller we waited for
        if found is None:
            _build(folder, sanitize, parts)
            found = _use(folder, parts)
            if found is None:
                raise KitError(f"the kit's bundle in {folder} was built but has no recipe", FAILED)
    finally:
        os.close(lock)
    _prune(root, keep=folder)
    return found


def _own_folder(root: Path, k: str, parts: list[str] | None) -> Path:
    """The folder of the bundle KEY: root/KEY, shared by every copy of the same kit (the key holds the
    content, not the place). But a part still to build there is built by Ninja in the folder CMake
    configured, whose checks read the source folder it was configured from: where that copy of the kit
    is gone (a handout made in a temporary folder), the build would stop. Such a bundle is finished by
    this copy in a folder of its own, root/KEY-PLACE (pruned like any other)."""
    folder = root / k
    try:
        made_from = json.loads((folder / RECIPE).read_text()).get("source_root", "")
    except (OSError, ValueError, AttributeError):
        return folder                   # not configured yet: built here, from this copy
    if not made_from or made_from == str(ROOT) or Path(made_from).is_dir():
        return folder
    if all(mark.is_file() for mark in _marks(folder, parts)):
        return folder                   # nothing left to build: the gone copy does not matter
    return root / f"{k}-{hashlib.sha256(str(ROOT).encode()).hexdigest()[:8]}"


_held: dict[str, int] = {}      # a bundle's folder: the descriptor of its shared lock, held till the end


def _locked(path: Path, how: int) -> int:
    """A descriptor of `path` (made if need be) with flock `how` taken, on the file that is at `path`
    once it is taken (a prune may remove the file while a caller waits for it: then the new one's).
    OSError when `how` is non-blocking and another holds a lock that conflicts, or the file cannot be
    opened."""
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC | os.O_NOFOLLOW, 0o600)
        except FileNotFoundError:
            raise
        except OSError:                 # a folder this process cannot write: the file, if it is there
            fd = os.open(path, os.O_RDONLY | os.O_CLOEXEC | os.O_NOFOLLOW)
        try:
            fcntl.flock(fd, how)
            mine, there = os.fstat(fd), os.stat(path, follow_symlinks=False)
            if (mine.st_dev, mine.st_ino) == (there.st_dev, there.st_ino):
                return fd
        except FileNotFoundError:
            pass
        except BaseException:
            os.close(fd)
            raise
        os.close(fd)                    # removed while we waited: the one there now


def _use(folder: Path, parts: list[str] | None = None) -> Bundle | None:
    """The ready bundle in `folder` (the steps `parts` of it at least), held by this process (its
    IN_USE file locked shared) until it ends; None when it is not ready (and then not held)."""
    if str(folder) in _held:
        return _load(folder, parts)
    if not all(mark.is_file() for mark in _marks(folder, parts)):
        return None
    try:
        fd = _locked(folder / IN_USE, fcntl.LOCK_SH)
    except FileNotFoundError:
        return None                     # pruned a moment ago: built anew
    except OSError:
        return _load(folder, parts)     # a folder this process cannot write (an image's): used as it is
    found = _load(folder, parts)
    if found is None:
        os.close(fd)
        return None
    _held[str(folder)] = fd
    return found


CONFIGURED = "configured"    # CMake has configured the folder (and with what packages): parts build on it


def _build(folder: Path, sanitize: bool, parts: list[str] | None = None) -> None:
    """Builds the bundle in `folder`: all of it (then marked `ready`), or the steps `parts` alone
    (each marked `ready-NN`: its judge, the reference's answers program it runs, and the kit's objects
    its answers program links, by their CMake targets). A folder whose configure did not finish, or
    was made with other packages, is built from nothing; Ninja finishes a build that stopped half way."""
    from .build import Build, build_targets, configure
    began = time.monotonic()
    b = Build("bundle", folder, ROOT / "steps", ROOT / "steps", preset="bundle", tools=False, sanitize_student=sanitize)
    configured = folder / CONFIGURED
    if _load_mark(configured) is None or not (folder / RECIPE).is_file():
        if folder.exists():
            shutil.rmtree(folder)      # a build that failed or stopped half way: from nothing
        extra = {"RAYKIT_HIDDEN": "ON" if hidden_here() else "OFF"}
        if os.environ.get("RAYKIT_LINKER"):
            extra["RAYKIT_LINKER"] = os.environ["RAYKIT_LINKER"]
        configure(b, extra=extra)
        configured.write_text(json.dumps({"packages": _packages(folder)}) + "\n")
    targets = ["all"] if parts is None else _targets(folder, parts)
    _built.append(("the kit's side" if parts is None else f"the kit's side of step {', '.join(parts)}")
                  + " was not built on this machine yet")
    ok, out = build_targets(b, targets)
    if not ok:
        raise KitError(f"the kit's bundle does not build (a kit bug, or the machine's):\n{out[-3000:]}", FAILED)
    mark = json.dumps({"seconds": round(time.monotonic() - began, 1), "packages": _packages(folder)}) + "\n"
    for path in _marks(folder, parts):
        path.write_text(mark)


def _load_mark(path: Path) -> dict | None:
    """A mark's content when its packages are unchanged since."""
    try:
        mark = json.loads(path.read_text())
        return None if any(_mtime(p) != when for p, when in mark["packages"].items()) else mark
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None


def _targets(folder: Path, parts: list[str]) -> list[str]:
    """The CMake targets the steps `parts` need: each judge (which depends on the reference's answers
    program it runs) and the object libraries of the kit's objects its answers program links, named
    by their folder (CMakeFiles/TARGET.dir/...)."""
    recipe = json.loads((folder / RECIPE).read_text())
    targets: list[str] = []
    for n in parts:
        step = recipe["steps"][n]
        targets.append(Path(step["judge"]).name)
        for obj in step["kit_objects"]:
            dirs = [p for p in Path(obj).parts if p.endswith(".dir")]
            if dirs:
                targets.append(dirs[0][:-len(".dir")])
    return list(dict.fromkeys(targets))


def _touch(folder: Path) -> None:
    """Marks the bundle used now (the prune keeps the most recently used)."""
    for mark in [folder / READY] if (folder / READY).is_file() else folder.glob(f"{READY}-*"):
        with suppress(OSError):
            os.utime(mark)


def _prune(root: Path, keep: Path) -> None:
    """The bundles beyond the KEEP most recently used go (an older kit's, another compiler's); a
    bundle being built (its lock held) or in use (a check of any copy of the kit on this machine holds
    its IN_USE file's lock shared: it links with its objects and runs its judges) stays."""
    def used(p: Path) -> float:
        times = []
        for mark in [p / READY, *p.glob(f"{READY}-*")]:
            with suppress(OSError):
                times.append(mark.stat().st_mtime)
        return max(times, default=0.0)
    folders = sorted((p for p in root.iterdir() if p.is_dir() and p != keep), key=used, reverse=True)
    for old in folders[KEEP - 1:]:
        if str(old) in _held:
            continue                    # this process's own (a check of both sanitizer settings)
        try:
            building = _locked(root / f"{old.name}.lock", fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            continue
        try:
            in_use = _locked(old / IN_USE, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(building)
            continue
        try:
            shutil.rmtree(old, ignore_errors=True)      # IN_USE too: a check waiting for it looks again
            (root / f"{old.name}.lock").unlink(missing_ok=True)    # a builder waiting opens it anew
        finally:
            os.close(in_use)
            os.close(building)

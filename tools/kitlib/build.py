"""Builds: a build folder and the steps folder it compiles, CMake's configure and presets, Ninja, the
kit's object cache. Above the boundary (sandbox/, whose spec a graded build carries) and the core
(common.py); the judge (checking.py) and the commands build through it."""

from __future__ import annotations

import filecmp
import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

from . import atomic, kitcache
from .common import BUILD, KitError, QUICK_TIER, ROOT, Step, load_steps, printable, say
from .relocate import forget_moved_build
from .sandbox import Isolation, Limits
from .status import FAILED


@dataclass
class Build:
    """A build folder and the steps folder it compiles."""

    name: str                   # student, reference, sanitize, submission
    binary_dir: Path
    steps_dir: Path             # what is compiled (for a submission: the staging copy)
    shown_dir: Path             # what the user named (for messages)
    preset: str | None = None
    # Whether CMake also configures the render tool, the benchmark, the docs, properties and fuzz
    # targets (RAYKIT_TOOLS). A build that only checks steps leaves them out: its configure takes
    # about 1 s instead of 8 (measured here), which a student waits for on a cold ./kit check.
    tools: bool = True
    # A submission's build: the student's files are compiled and linked inside the trust boundary
    # (RAYKIT_BOUNDARY; sandbox/), whose spec the build tool is given in RAYKIT_BOUNDARY_SPEC.
    boundary: bool = False
    spec: str = ""
    # A student's files under UBSan and GLM's asserts (RAYKIT_CHECK_SANITIZE): their own check and a
    # graded submission alike, so the two never disagree on a crash (CMakeLists.txt).
    sanitize_student: bool = False
    # The submission's name on the platform that graded it, for the hidden cases' seed (secret.py).
    identity: str = ""

    @property
    def reference_needs(self) -> bool:
        """Whether the reference is here (a grading): a step that needs another then runs on a stand-in
        for it that the judge scripts from the reference's program (tests/support/standin.hpp), never on
        the reference's code itself nor on the student's own earlier step."""
        return (ROOT / "solutions").is_dir()

    def exe(self, step: Step) -> Path:
        return self.binary_dir / step.target


def detect_undefined() -> bool:
    """Whether a student's files are built with the sanitizer (RAYKIT_NO_CHECK_SANITIZE=1: not, to
    measure without it): one answer for the check and the grade."""
    return os.environ.get("RAYKIT_NO_CHECK_SANITIZE") != "1"


def preset_build(name: str) -> Build:
    steps_dir = ROOT / ("steps" if name == "student" else "solutions")
    return Build(name, BUILD / name, steps_dir, steps_dir, preset=name, tools=name != "student",
                 sanitize_student=name == "student" and detect_undefined())


def tools_build(build: Build) -> Build:
    """The same steps in a build folder of its own, with the tools configured (render, bench): a
    checking build stays without them, and neither reconfigures the other."""
    return Build(f"{build.name}-tools", build.binary_dir.with_name(build.binary_dir.name + "-tools"),
                 build.steps_dir, build.shown_dir, preset=build.preset, tools=True)




def submission_build(source: Path, slot: str = "submission") -> Build:
    """Grades a copy of `source` (never modified) in a build folder reused across submissions.

    Only files that changed are rewritten, so grading many submissions rebuilds
    just the steps that differ.
    """
    staging = BUILD / f"{slot}-src"
    for step in load_steps():
        for f in step.files:
            src, dst = source / step.folder / f, staging / step.folder / f
            if src.is_file():
                dst.parent.mkdir(parents=True, exist_ok=True)
                if not dst.exists() or not filecmp.cmp(src, dst, shallow=False):
                    shutil.copyfile(src, dst)
            elif dst.exists():
                dst.unlink()
    return Build(slot, BUILD / slot, staging, source, tools=False, boundary=True, sanitize_student=detect_undefined())


def kit_cache_dir() -> Path | None:
    """Where the kit's own compiled objects are kept across build folders (tools/kitlib/kitcache.py):
    RAYKIT_KIT_CACHE_DIR, else $XDG_CACHE_HOME/raykit/objects or ~/.cache/raykit/objects; None when
    RAYKIT_NO_KIT_CACHE=1 or no such folder can be made (then every build compiles them itself)."""
    if os.environ.get("RAYKIT_NO_KIT_CACHE") == "1":
        return None
    named = os.environ.get("RAYKIT_KIT_CACHE_DIR")
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "raykit" / "objects"
    folder = Path(named) if named else base
    try:
        # Only the kit's user may read it: a grading's judges hold the hidden cases, and under the user
        # isolation the graded code runs as another user of the same machine (sandbox/).
        folder.mkdir(parents=True, exist_ok=True, mode=0o700)
        folder.chmod(0o700)
        if not os.access(folder, os.W_OK | os.X_OK):
            return None
    except (OSError, RuntimeError):
        return None
    return folder




def configure(build: Build, quiet: bool = True) -> None:
    """Runs `cmake --preset PRESET -S -B` for `build` (a submission: the "submission" preset) with the
    kit's own settings on top (-D: the steps folder, the tools, the boundary, the sanitizer). The
    presets (CMakePresets.json) are the one place the builds are described; -B puts the folder where
    the kit wants it."""
    if os.environ.get(QUICK_TIER) == "1":
        raise KitError(f"configuring {build.binary_dir.name}: a self-test of the quick tier builds nothing "
                       '(take its @tier("quick") off)')
    variables = {"RAYKIT_STEPS_DIR": str(build.steps_dir)}
    variables["RAYKIT_TOOLS"] = variables["RAYKIT_CTEST"] = "ON" if build.tools else "OFF"
    variables["RAYKIT_BOUNDARY"] = "ON" if build.boundary else "OFF"
    variables["RAYKIT_CHECK_SANITIZE"] = "ON" if build.sanitize_student and not build.tools else "OFF"
    variables["RAYKIT_PYTHON"] = sys.executable
    cache = build.binary_dir / "CMakeCache.txt"
    has_ninja = shutil.which("ninja") is not None or shutil.which("ninja-build") is not None
    # The presets ask for Ninja; without it, CMake's default (Makefiles) rather than a failure. An
    # existing build folder keeps the generator it has.
    gen = ["-G", "Unix Makefiles"] if not has_ninja and not cache.is_file() else []
    ninja_folder = has_ninja and (not cache.is_file() or "CMAKE_GENERATOR:INTERNAL=Ninja\n" in cache.read_text(errors="replace"))
    cache_dir = kit_cache_dir() if not build.tools else None
    # An empty kit cache (a newcomer, a fresh grader image): the launcher would miss on every compile
    # and only store; with Ninja the build runs without it and fill_kit_cache stores what it built,
    # one process for all instead of one per compile (0.04 s of CPU each). A folder keeps what it was
    # configured with until it is configured again.
    filling = cache_dir is not None and ninja_folder and not any(cache_dir.iterdir())
    variables["RAYKIT_KIT_CACHE"] = str(cache_dir) if cache_dir is not None and not filling else ""
    forget_moved_build(build.binary_dir)    # a moved kit
    cmd = ["cmake", "--preset", build.preset or "submission", "-S", str(ROOT), "-B", str(build.binary_dir), *gen,
           *(f"-D{k}={v}" for k, v in sorted(variables.items()))]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise KitError(f"cmake could not configure {build.binary_dir}:\n{r.stdout[-3000:]}{r.stderr[-3000:]}", FAILED)
    mark = build.binary_dir / FILL_MARK
    if filling:
        atomic.write(mark, f"{cache_dir}\n")
    else:
        mark.unlink(missing_ok=True)
    if not quiet:
        say(r.stdout)


FILL_MARK = "raykit-kitcache-fill.txt"   # the kit cache to fill, then a line per object stored
# The kit's own targets, the only ones whose objects the kit cache keeps: CMakeLists.txt writes them,
# a line each, as it gives them the launcher (raykit_kit_cached).
KIT_CACHED_TARGETS = "raykit-kit-cached.txt"
_hashes: dict = {}      # each header's hash, read once a process


def kit_object_pattern(build: Build) -> re.Pattern | None:
    """What an object of one of the kit's own targets is called in `build` (Ninja's output path);
    None where the configure wrote no list of them."""
    try:
        targets = (build.binary_dir / KIT_CACHED_TARGETS).read_text().split()
    except OSError:
        return None
    if not targets:
        return None
    return re.compile(r"CMakeFiles/(" + "|".join(map(re.escape, targets)) + r")\.dir/.+\.o")


def fill_kit_cache(build: Build, targets: list[str]) -> int:
    """After a build of a folder configured with an empty kit cache (configure): stores the kit's
    objects it compiled, each under the key its compile would have had through the launcher
    (kitcache.fill), with the files Ninja recorded that it read. An object already stored (its time
    and size in the mark) is not stored again. How many were stored."""
    mark = build.binary_dir / FILL_MARK
    try:
        cache, *done = mark.read_text().splitlines()
    except (OSError, ValueError):
        return 0
    ninja, kit_object = ninja_of(build), kit_object_pattern(build)
    # RAYKIT_NO_KIT_CACHE: the cache turned off since the configure.
    if not ninja or not kit_object or os.environ.get("RAYKIT_NO_KIT_CACHE") == "1":
        return 0
    r = subprocess.run([ninja, "-t", "commands", *targets], cwd=build.binary_dir, capture_output=True, text=True)
    fresh: dict[str, tuple[list[str], str]] = {}
    for line in r.stdout.splitlines() if r.returncode == 0 else []:
        try:
            argv = shlex.split(line)
        except ValueError:
            continue
        out = kitcache.option(argv, "-o")
        if out and "-c" in argv and kit_object.fullmatch(out):
            try:
                st = (build.binary_dir / out).stat()
            except OSError:
                continue
            seen = f"{st.st_mtime_ns} {st.st_size} {out}"
            if seen not in done:
                fresh[out] = (argv, seen)
    if not fresh:
        return 0
    r = subprocess.run([ninja, "-t", "deps", *fresh], cwd=build.binary_dir, capture_output=True, text=True)
    deps: dict[str, list[str]] = {}
    current = None
    for line in r.stdout.splitlines() if r.returncode == 0 else []:
        if line and not line[0].isspace():     # "OUT: #deps N, deps mtime T (VALID)"
            name, _, state = line.partition(": #deps")
            current = name if state.rstrip().endswith("(VALID)") else None
            if current:
                deps[current] = []
        elif line.strip() and current:
            deps[current].append(os.path.join(build.binary_dir, line.strip()))
    cwd = os.path.realpath(build.binary_dir)    # the folder as the launcher sees it (os.getcwd())
    stored = [seen for out, (argv, seen) in fresh.items()
              if deps.get(out) and kitcache.fill(cache, cwd, argv, deps[out], _hashes)]
    if stored:
        kitcache.prune(cache)       # once for the whole fill (a launcher prunes after its own store)
        atomic.write(mark, "\n".join([cache, *done, *stored]) + "\n")
    return len(stored)


def workflow(name: str, env: dict | None = None) -> subprocess.CompletedProcess:
    """Preset NAME configured (configure()), built and tested: what `cmake --preset NAME`, `cmake --build
    --preset NAME` and `ctest --preset NAME` do by hand. stdout holds ctest's summary line; `env` is ctest's."""
    build = preset_build(name)
    try:
        configure(build)
    except KitError as e:
        return subprocess.CompletedProcess([name], 1, "", str(e))
    r = subprocess.run(["cmake", "--build", str(build.binary_dir)], cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        return r
    return subprocess.run(["ctest", "--output-on-failure"], cwd=build.binary_dir, capture_output=True, text=True,
                          env=env)


def build_target(build: Build, target: str) -> tuple[bool, str]:
    return build_targets(build, [target])


NINJA_PROGRESS = re.compile(r"^\[(\d+)/(\d+)\] ")


_ninja_of: dict[Path, str | None] = {}


def ninja_of(build: Build) -> str | None:
    """The Ninja program CMake chose for a configured Ninja build (CMAKE_MAKE_PROGRAM), else None."""
    if _ninja_of.get(build.binary_dir) is None:      # asked again until the build is configured
        found = None
        if (build.binary_dir / "build.ninja").is_file():
            try:
                for line in (build.binary_dir / "CMakeCache.txt").read_text(errors="replace").splitlines():
                    if line.startswith("CMAKE_MAKE_PROGRAM:"):
                        found = line.split("=", 1)[1].strip() or None
                        break
            except OSError:
                pass
            found = found if found and os.access(found, os.X_OK) else (shutil.which("ninja") or shutil.which("ninja-build"))
        _ninja_of[build.binary_dir] = found
    return _ninja_of[build.binary_dir]


def build_targets(build: Build, targets: list[str], progress=None) -> tuple[bool, str]:
    """Builds `targets` in one call of the build tool (in parallel; with Ninja, -k 0 goes on past a
    failure so every target that can be built is). `progress(done, total)` follows Ninja's count.
    Ninja is called directly where CMake generated for it: `cmake --build` would only start it, at
    20 ms of CPU a call, five calls a check (and Ninja itself runs CMake again when a CMakeLists.txt
    changed)."""
    if os.environ.get(QUICK_TIER) == "1":
        raise KitError(f"building {', '.join(targets)[:80]}: a self-test of the quick tier builds nothing "
                       '(take its @tier("quick") off)')
    ninja = ninja_of(build)
    if ninja:
        cmd = [ninja, *(["-k", "0"] if len(targets) > 1 else []), *targets]     # run in the build folder
        level = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", "")     # honoured as cmake --build would
        if level.isdigit() and int(level) > 0:
            cmd[1:1] = ["-j", level]
    else:
        cmd = ["cmake", "--build", str(build.binary_dir), "--target", *targets]
    env = None
    if build.boundary:
        # Built outside a check (./kit debug --steps, which runs the code under gdb with your rights
        # anyway): the boundary's copy and limits, without a sandbox.
        spec = build.spec or Isolation("none", "not sandboxed", limits=Limits.from_env()).spec()
        env = dict(os.environ, RAYKIT_BOUNDARY_SPEC=spec)
    proc = subprocess.Popen(cmd, cwd=build.binary_dir if ninja else ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, errors="replace", env=env)
    lines = []
    built_something = False
    for line in proc.stdout:
        lines.append(line)
        m = NINJA_PROGRESS.match(line)
        if m:
            built_something = True
            if progress:
                progress(int(m.group(1)), int(m.group(2)))
    proc.wait()
    if built_something:
        fill_kit_cache(build, targets)
    if build.boundary:      # the launcher's own command lines say nothing to a student
        lines = [l for l in lines if "tools/kitlib/launch.py" not in l]
    return proc.returncode == 0, shown_text(build, "".join(lines))


def shown_text(build: Build, text: str) -> str:
    """A build's diagnostics as the user reads them: the staging copy's paths replaced by the folder
    they named, control characters made visible."""
    if build.steps_dir != build.shown_dir:
        text = text.replace(str(build.steps_dir), str(build.shown_dir))
    return printable(text)


def ensure_configured(build: Build, all_steps: list[Step]) -> None:
    """Configures `build` once per build folder and set of present step files: the targets CMake
    makes depend on which files exist; after that, the build tool re-runs CMake when its inputs change."""
    present = "\n".join(f"{s.folder}/{f}" for s in all_steps for f in s.files
                         if (build.steps_dir / s.folder / f).is_file())
    stamp = build.binary_dir / "raykit-configured.txt"
    key = (f"{build.steps_dir}\ntools {build.tools}\nboundary {build.boundary}\n"
           f"sanitize {build.sanitize_student}\n{present}\n")
    cache = build.binary_dir / "CMakeCache.txt"
    if not cache.is_file() or not stamp.is_file() or stamp.read_text(errors="replace") != key:
        configure(build)
        stamp.write_text(key)

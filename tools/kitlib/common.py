"""Shared pieces of the kit's driver: where things are, the steps, packages, builds."""

from __future__ import annotations

import filecmp
import json
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

from .status import FAILED, USAGE

ROOT = Path(__file__).resolve().parents[2]
BUILD = ROOT / "build"


class KitError(Exception):
    """A problem the user can fix: printed as one clear message, exit status `code`."""

    def __init__(self, message: str, code: int = USAGE):
        super().__init__(message)
        self.code = code


# --- terminal ------------------------------------------------------------------

_COLOR = sys.stdout.isatty() and os.environ.get("NO_COLOR") is None and os.environ.get("TERM") != "dumb"


def paint(text: str, style: str) -> str:
    codes = {"green": "32", "red": "31", "yellow": "33", "bold": "1", "dim": "2", "cyan": "36"}
    if not _COLOR:
        return text
    return f"\033[{codes[style]}m{text}\033[0m"


def say(text: str = "") -> None:
    print(text, flush=True)


def note(text: str) -> None:
    print(paint(text, "dim"), file=sys.stderr, flush=True)


# C0 controls but tab and newline, DEL, and the C1 controls (U+0080-U+009F): an escape sequence
# in a student's output could clear the instructor's screen, forge a score or write the clipboard.
# Also lone surrogates: a file name that is not UTF-8 reaches Python as U+DC80-U+DCFF (one per byte,
# 0x9b, a C1 CSI, among them), which no UTF-8 file or terminal can take.
_CONTROLS = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\ud800-\udfff]")


def _shown(m: re.Match) -> str:
    code = ord(m.group())
    if 0xdc80 <= code <= 0xdcff:        # the byte a file name had (os.fsdecode's surrogateescape)
        return f"\\x{code - 0xdc00:02x}"
    return f"\\x{code:02x}" if code <= 0xff else f"\\u{code:04x}"


def printable(text: str) -> str:
    """`text` from outside the kit (a student's output, exception text, compiler diagnostics, a
    student's name) as data: control characters shown as visible escapes, never sent raw. The one
    filter for what the kit prints or writes from a student: the terminal, the CSV files of ./kit
    grade, the report's pages (report/pages.py), file names (student_file_name below)."""
    return _CONTROLS.sub(_shown, text.replace("\r\n", "\n"))


def student_file_name(name: str) -> str:
    """A student's name as the name of a file the kit writes for them (their results JSON, their saved
    files): printable(), tab and newline shown too. printable() of the name gives the same file name,
    so the report finds a student's files from the name in the CSV."""
    return printable(name).replace("\t", "\\x09").replace("\n", "\\x0a")


# --- steps -------------------------------------------------------------------

@dataclass
class Step:
    """One numbered step, described by tests/NN_topic/step.json."""

    folder: str                 # "01_unit_sphere"
    title: str
    files: list[str]
    needs: list[str]
    lecture: str                # "lectures/01-unit-sphere.md"
    functions: list[str] = field(default_factory=list)

    @property
    def number(self) -> str:
        return self.folder[:2]

    @property
    def target(self) -> str:
        return f"test_step{self.number}"


def load_steps() -> list[Step]:
    steps = []
    for manifest in sorted((ROOT / "tests").glob("[0-9][0-9]_*/step.json")):
        data = json.loads(manifest.read_text())
        steps.append(Step(folder=manifest.parent.name, title=data["title"], files=data["files"],
                          needs=data.get("needs", []), lecture=data["lecture"],
                          functions=data.get("functions", [])))
    return steps


def select_steps(steps: list[Step], wanted: list[str]) -> list[Step]:
    """Steps named by number ("1", "01") or folder; all of them when none is named."""
    if not wanted:
        return steps
    chosen = []
    for w in wanted:
        match = [s for s in steps if w == s.folder or (w.isdigit() and int(w) == int(s.number))]
        if not match:
            known = ", ".join(str(int(s.number)) for s in steps)
            raise KitError(f"there is no step {w!r}; the steps are {known}")
        if match[0] not in chosen:
            chosen.append(match[0])
    return sorted(chosen, key=lambda s: s.number)


def prerequisites(step: Step, steps: list[Step]) -> list[Step]:
    """The steps `step` links, directly or through another, in course order."""
    by_number = {s.number: s for s in steps}
    found: set[str] = set()
    todo = list(step.needs)
    while todo:
        n = todo.pop()
        if n not in found:
            found.add(n)
            todo += by_number[n].needs
    return [s for s in steps if s.number in found]


def stage_on_reference(target: Path, step: Step, steps: list[Step], files: Path) -> Path:
    """A steps folder at `target`: the reference answers of the steps `step` needs and of `step`
    itself, with the files in `files` (a stub, a mutant's changed files) laid over the latter."""
    shutil.rmtree(target, ignore_errors=True)
    for s in prerequisites(step, steps) + [step]:
        shutil.copytree(ROOT / "solutions" / s.folder, target / s.folder)
    shutil.copytree(files, target / step.folder, dirs_exist_ok=True)
    return target


def writable_parent(shown: str, target: Path) -> None:
    """Raises KitError, naming `shown` (the path as the user wrote it), when `target` cannot be
    created: its folder is missing or not writable. Checked before any work, never after it."""
    parent = target.resolve().parent
    if not parent.is_dir():
        raise KitError(f"{shown}: folder {parent} does not exist")
    if not os.access(parent, os.W_OK):
        raise KitError(f"{shown}: cannot write in {parent}")


# --- builds ----------------------------------------------------------------------

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
    # (RAYKIT_BOUNDARY; sandbox.py), whose spec the build tool is given in RAYKIT_BOUNDARY_SPEC.
    boundary: bool = False
    spec: str = ""
    # A student's own check: their files under ASan, UBSan and GLM's asserts (RAYKIT_CHECK_SANITIZE).
    sanitize_student: bool = False
    # The submission's name on the platform that graded it, for the hidden cases' seed (secret.py).
    identity: str = ""

    @property
    def reference_needs(self) -> bool:
        """Whether a step that needs another is graded on the reference's code for it."""
        return (ROOT / "solutions").is_dir()

    def exe(self, step: Step) -> Path:
        return self.binary_dir / step.target


def preset_build(name: str) -> Build:
    steps_dir = ROOT / ("steps" if name == "student" else "solutions")
    return Build(name, BUILD / name, steps_dir, steps_dir, preset=name, tools=name != "student",
                 sanitize_student=name == "student" and os.environ.get("RAYKIT_NO_CHECK_SANITIZE") != "1")


def tools_build(build: Build) -> Build:
    """The same steps in a build folder of its own, with the tools configured (render, bench): a
    checking build stays without them, and neither reconfigures the other."""
    return Build(f"{build.name}-tools", build.binary_dir.with_name(build.binary_dir.name + "-tools"),
                 build.steps_dir, build.shown_dir, preset=build.preset, tools=True)


def resolve_steps_dir(path: str) -> Path:
    """A student's steps folder, or a whole copy of the kit that holds one."""
    p = Path(path).expanduser()
    if not p.exists():
        raise KitError(f"--steps {path}: no such folder")
    if not p.is_dir():
        raise KitError(f"--steps {path}: not a folder")
    p = p.resolve()
    steps = load_steps()
    if not any((p / s.folder).is_dir() for s in steps) and (p / "steps").is_dir():
        p = p / "steps"
    if not any((p / s.folder).is_dir() for s in steps):
        names = ", ".join(s.folder for s in steps)
        raise KitError(f"--steps {path}: holds none of the step folders ({names})")
    return p


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
    return Build(slot, BUILD / slot, staging, source, tools=False, boundary=True)


def preset_settings(name: str) -> tuple[str | None, Path, dict[str, str]]:
    """The generator, build folder and cache variables of configure preset `name`, read from
    CMakePresets.json with its `inherits` resolved.

    Why not `cmake --preset`: presets need CMake 3.19 (this file's version 6 needs 3.25) and
    Debian 11 ships 3.18. The presets stay the one place the builds are described (IDEs and
    `cmake --workflow` read them too); the kit passes the same settings as -G and -D options.
    """
    data = json.loads((ROOT / "CMakePresets.json").read_text())
    presets = {p["name"]: p for p in data.get("configurePresets", [])}
    if name not in presets:
        raise KitError(f"CMakePresets.json has no configure preset {name!r}", FAILED)
    chain, todo = [], [name]
    while todo:                       # this preset, then what it inherits, nearest first
        p = presets[todo.pop(0)]
        chain.append(p)
        parents = p.get("inherits", [])
        todo += [parents] if isinstance(parents, str) else parents
    generator, binary_dir, variables = None, None, {}
    for p in reversed(chain):         # the farthest ancestor first, so nearer ones override
        generator = p.get("generator", generator)
        binary_dir = p.get("binaryDir", binary_dir)
        for key, value in p.get("cacheVariables", {}).items():
            if isinstance(value, dict):   # {"type": "BOOL", "value": "ON"}
                value = value.get("value", "")
            variables[key] = str(value).replace("${sourceDir}", str(ROOT))
    folder = Path(binary_dir.replace("${sourceDir}", str(ROOT))) if binary_dir else BUILD / name
    return generator, folder, variables


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
        # isolation the graded code runs as another user of the same machine (sandbox.py).
        folder.mkdir(parents=True, exist_ok=True, mode=0o700)
        folder.chmod(0o700)
        if not os.access(folder, os.W_OK | os.X_OK):
            return None
    except (OSError, RuntimeError):
        return None
    return folder


def configure(build: Build, quiet: bool = True) -> None:
    """Runs `cmake -S -B` for `build` with its preset's settings (a submission: the base preset's
    and its own steps folder). Works from CMake 3.18: no --preset."""
    generator, _, variables = preset_settings(build.preset or "base")
    variables["RAYKIT_STEPS_DIR"] = str(build.steps_dir)
    variables["RAYKIT_TOOLS"] = variables["RAYKIT_CTEST"] = "ON" if build.tools else "OFF"
    variables["RAYKIT_BOUNDARY"] = "ON" if build.boundary else "OFF"
    variables["RAYKIT_CHECK_SANITIZE"] = "ON" if build.sanitize_student and not build.tools else "OFF"
    variables["RAYKIT_PYTHON"] = sys.executable
    variables["RAYKIT_KIT_CACHE"] = str(kit_cache_dir() or "") if not build.tools else ""
    gen = []
    if generator == "Ninja" and shutil.which("ninja") is None and shutil.which("ninja-build") is None:
        generator = None              # CMake's default (Makefiles) rather than a failure
    cache = build.binary_dir / "CMakeCache.txt"
    from .relocate import forget_moved_build; forget_moved_build(build.binary_dir)    # noqa: E702 a moved kit
    if generator and not cache.is_file():
        gen = ["-G", generator]       # an existing build folder keeps the generator it has
    cmd = ["cmake", "-S", str(ROOT), "-B", str(build.binary_dir), *gen,
           *(f"-D{k}={v}" for k, v in sorted(variables.items()))]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise KitError(f"cmake could not configure {build.binary_dir}:\n{r.stdout[-3000:]}{r.stderr[-3000:]}", FAILED)
    if not quiet:
        say(r.stdout)


def workflow(name: str) -> subprocess.CompletedProcess:
    """What `cmake --workflow --preset NAME` does (configure, build, test), without presets:
    the same settings, through configure(). stdout holds ctest's summary line."""
    build = preset_build(name)
    try:
        configure(build)
    except KitError as e:
        return subprocess.CompletedProcess([name], 1, "", str(e))
    r = subprocess.run(["cmake", "--build", str(build.binary_dir)], cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        return r
    return subprocess.run(["ctest", "--output-on-failure"], cwd=build.binary_dir, capture_output=True, text=True)


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
        from .sandbox import Isolation, Limits
        spec = build.spec or Isolation("none", "not sandboxed", limits=Limits.from_env()).spec()
        env = dict(os.environ, RAYKIT_BOUNDARY_SPEC=spec)
    proc = subprocess.Popen(cmd, cwd=build.binary_dir if ninja else ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, errors="replace", env=env)
    lines = []
    for line in proc.stdout:
        lines.append(line)
        m = NINJA_PROGRESS.match(line)
        if m and progress:
            progress(int(m.group(1)), int(m.group(2)))
    proc.wait()
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

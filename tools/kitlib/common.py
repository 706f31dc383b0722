"""Shared pieces of the kit's driver: where things are, the steps, packages, builds."""

from __future__ import annotations

import filecmp
import json
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BUILD = ROOT / "build"


class KitError(Exception):
    """A problem the user can fix: printed as one clear message, exit status `code`."""

    def __init__(self, message: str, code: int = 2):
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


# --- packages --------------------------------------------------------------------

# Debian package names each command needs. The first ./kit call installs what is
# missing (apt-get, non-interactive, with sudo when not root).
PACKAGES = {
    "build": ["cmake", "ninja-build", "g++", "libglm-dev", "doctest-dev", "libstb-dev", "pkg-config"],
    "sandbox": ["bubblewrap"],     # grading a folder the kit did not write (sandbox.py)
}


def missing_packages(names: list[str]) -> list[str]:
    if shutil.which("dpkg-query") is None:
        return []
    missing = []
    for name in names:
        r = subprocess.run(["dpkg-query", "-W", "-f=${Status}", name], capture_output=True, text=True)
        if r.returncode != 0 or "install ok installed" not in r.stdout:
            missing.append(name)
    return missing


APT_LISTS = Path("/var/lib/apt/lists")
APT_LISTS_MAX_AGE = 24 * 3600       # seconds: older package lists are refreshed before installing


def apt_lists_stale(lists: Path = APT_LISTS, max_age: float = APT_LISTS_MAX_AGE) -> bool:
    """True when apt has no package lists (a fresh container or minbase system) or the newest is
    older than `max_age`: installing from them would fail on versions the mirror no longer has."""
    try:
        ages = [p.stat().st_mtime for p in lists.iterdir() if p.name.endswith("Packages")
                or "_Packages." in p.name]
    except OSError:
        return True
    return not ages or time.time() - max(ages) > max_age


def apt_failure(stderr: str, names: list[str]) -> str:
    """One line naming the package apt could not install and why, from apt-get's own words."""
    errors = [l[2:].strip() for l in stderr.splitlines() if l.startswith("E:")]
    for name in names:
        for e in errors:
            if re.search(rf"(^|[\s'\"]){re.escape(name)}($|[\s'\":])", e):
                return f"{name}: {e}"
    # "Depends: ... but it is not going to be installed" lines name the package first.
    for l in stderr.splitlines():
        m = re.match(r"\s*(\S+) : Depends: (.*)", l)
        if m and m.group(1) in names:
            return f"{m.group(1)}: depends on {m.group(2).strip()}"
    if errors:
        return errors[-1]
    tail = [l for l in stderr.strip().splitlines() if l.strip()]
    return tail[-1] if tail else "apt-get failed without a message"


def ensure_packages(*groups: str) -> None:
    """Installs the Debian packages of `groups` that are missing, once, with apt-get.

    Root installs directly, anyone else through `sudo -n` (never a password prompt: the kit may
    run in CI or an editor). Without apt, or without the right to install, the user gets the one
    command to run. A failed install names the package and apt's reason.
    """
    names: list[str] = []
    for g in groups:
        names += [n for n in PACKAGES[g] if n not in names]
    missing = missing_packages(names)
    if not missing:
        return
    command = f"sudo apt-get update && sudo apt-get install -y {' '.join(missing)}"
    if shutil.which("apt-get") is None:
        raise KitError(f"missing packages: {' '.join(missing)}; install them (Debian names) and run ./kit again", 3)
    if os.geteuid() == 0:
        sudo: list[str] = []
    elif shutil.which("sudo") and subprocess.run(["sudo", "-n", "true"], capture_output=True).returncode == 0:
        sudo = ["sudo", "-n"]
    else:
        raise KitError(f"the kit needs {' '.join(missing)} and cannot install them (not root, no "
                       f"sudo without a password). Run:\n  {command}\nthen ./kit again", 3)
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    if apt_lists_stale():
        note("kit: updating the package lists (apt-get update)")
        up = subprocess.run(sudo + ["apt-get", "update", "-q"], env=env, capture_output=True, text=True)
        if up.returncode != 0:
            raise KitError(f"apt-get update failed: {apt_failure(up.stderr, [])}\nFix that, then run:\n"
                           f"  {command}", 3)
    note(f"kit: installing {' '.join(missing)} (once)")
    ok = subprocess.run(sudo + ["apt-get", "install", "-y", "-q", "--no-install-recommends"] + missing,
                        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if ok.returncode != 0:
        raise KitError(f"could not install the packages the kit needs.\n  {apt_failure(ok.stderr, missing)}\n"
                       f"Once that is fixed, run:\n  {command}", 3)


# --- builds ----------------------------------------------------------------------

@dataclass
class Build:
    """A build folder and the steps folder it compiles."""

    name: str                   # student, reference, sanitize, submission
    binary_dir: Path
    steps_dir: Path             # what is compiled (for a submission: the staging copy)
    shown_dir: Path             # what the user named (for messages)
    preset: str | None = None

    @property
    def reference_needs(self) -> bool:
        """Whether a step that needs another is graded on the reference's code for it."""
        return (ROOT / "solutions").is_dir()

    def exe(self, step: Step) -> Path:
        return self.binary_dir / step.target


def preset_build(name: str) -> Build:
    steps_dir = ROOT / ("steps" if name == "student" else "solutions")
    return Build(name, BUILD / name, steps_dir, steps_dir, preset=name)


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
    return Build(slot, BUILD / slot, staging, source)


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
        raise KitError(f"CMakePresets.json has no configure preset {name!r}", 1)
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


def configure(build: Build, quiet: bool = True) -> None:
    """Runs `cmake -S -B` for `build` with its preset's settings (a submission: the base preset's
    and its own steps folder). Works from CMake 3.18: no --preset."""
    generator, _, variables = preset_settings(build.preset or "base")
    variables["RAYKIT_STEPS_DIR"] = str(build.steps_dir)
    gen = []
    if generator == "Ninja" and shutil.which("ninja") is None and shutil.which("ninja-build") is None:
        generator = None              # CMake's default (Makefiles) rather than a failure
    cache = build.binary_dir / "CMakeCache.txt"
    if generator and not cache.is_file():
        gen = ["-G", generator]       # an existing build folder keeps the generator it has
    cmd = ["cmake", "-S", str(ROOT), "-B", str(build.binary_dir), *gen,
           *(f"-D{k}={v}" for k, v in sorted(variables.items()))]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise KitError(f"cmake could not configure {build.binary_dir}:\n{r.stdout[-3000:]}{r.stderr[-3000:]}", 1)
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
    r = subprocess.run(["cmake", "--build", str(build.binary_dir), "--target", target],
                       cwd=ROOT, capture_output=True, text=True)
    out = r.stdout + r.stderr
    if build.steps_dir != build.shown_dir:
        out = out.replace(str(build.steps_dir), str(build.shown_dir))
    return r.returncode == 0, out


def run(cmd: list[str], **kw) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, cwd=kw.pop("cwd", ROOT), **kw)

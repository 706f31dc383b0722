"""Builds: a build folder and the steps folder it compiles, CMake's configure and presets, Ninja. Above
the boundary (sandbox/) and the core (common.py); the bundle (bundle.py), the judge (checking.py) and
the commands build through it."""

from __future__ import annotations

import filecmp
import os
import re
import shutil
import subprocess
from contextlib import suppress
from dataclasses import dataclass
from pathlib import Path

from .common import BUILD, KitError, QUICK_TIER, ROOT, Step, load_steps, printable
from .relocate import cache_entries, forget_moved_build
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
    # (sandbox/) by checking.build_step, as a graded file is ("grade": bundle.Bundle.compile_command).
    boundary: bool = False
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


def submission_build(source: Path, slot: str = "submission", folder: Path | None = None) -> Build:
    """Grades a copy of `source` (never modified) in a build folder: build/SLOT, or `folder` (a run's
    own, runfolders.private: what ./kit check --steps uses, so two checks at once never share one).

    Only files that changed are rewritten, so grading many submissions rebuilds
    just the steps that differ.
    """
    staging = (folder / "src") if folder is not None else BUILD / f"{slot}-src"
    for step in load_steps():
        for f in step.files:
            src, dst = source / step.folder / f, staging / step.folder / f
            if src.is_file():
                dst.parent.mkdir(parents=True, exist_ok=True)
                if not dst.exists() or not filecmp.cmp(src, dst, shallow=False):
                    shutil.copyfile(src, dst)
            elif dst.exists():
                dst.unlink()
    return Build(slot, (folder / "build") if folder is not None else BUILD / slot, staging, source, tools=False,
                 boundary=True, sanitize_student=detect_undefined())


def _not_in_quick_tier(doing: str) -> None:
    if os.environ.get(QUICK_TIER) == "1":
        raise KitError(f'{doing}: a self-test of the quick tier builds nothing (take its quick marker off)')


def configure(build: Build, extra: dict[str, str] | None = None) -> None:
    """Runs `cmake --preset PRESET -S -B` for `build` (a submission: the "submission" preset) with the
    kit's own settings on top (-D: the steps folder, the tools, the sanitizer, then `extra`). The
    presets (CMakePresets.json) are the one place the builds are described; -B puts the folder where
    the kit wants it."""
    _not_in_quick_tier(f"configuring {build.binary_dir.name}")
    variables = {"RAYKIT_STEPS_DIR": str(build.steps_dir)}
    variables["RAYKIT_TOOLS"] = variables["RAYKIT_CTEST"] = "ON" if build.tools else "OFF"
    variables["RAYKIT_CHECK_SANITIZE"] = "ON" if build.sanitize_student and not build.tools else "OFF"
    variables.update(extra or {})
    cache = build.binary_dir / "CMakeCache.txt"
    has_ninja = shutil.which("ninja") is not None or shutil.which("ninja-build") is not None
    # The presets ask for Ninja; without it, CMake's default (Makefiles) rather than a failure. An
    # existing build folder keeps the generator it has.
    gen = ["-G", "Unix Makefiles"] if not has_ninja and not cache.is_file() else []
    forget_moved_build(build.binary_dir)    # a moved kit
    cmd = ["cmake", "--preset", build.preset or "submission", "-S", str(ROOT), "-B", str(build.binary_dir), *gen,
           *(f"-D{k}={v}" for k, v in sorted(variables.items()))]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise KitError(f"cmake could not configure {build.binary_dir}:\n{r.stdout[-3000:]}{r.stderr[-3000:]}", FAILED)


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
            with suppress(OSError):
                found = cache_entries(build.binary_dir / "CMakeCache.txt").get("CMAKE_MAKE_PROGRAM") or None
            found = found if found and os.access(found, os.X_OK) else (shutil.which("ninja") or shutil.which("ninja-build"))
        _ninja_of[build.binary_dir] = found
    return _ninja_of[build.binary_dir]


def build_targets(build: Build, targets: list[str], progress=None) -> tuple[bool, str]:
    """Builds `targets` in one call of the build tool (in parallel; with Ninja, -k 0 goes on past a
    failure so every target that can be built is). `progress(done, total)` follows Ninja's count.
    Ninja is called directly where CMake generated for it: `cmake --build` would only start it, at
    20 ms of CPU a call, five calls a check (and Ninja itself runs CMake again when a CMakeLists.txt
    changed)."""
    _not_in_quick_tier(f"building {', '.join(targets)[:80]}")
    ninja = ninja_of(build)
    if ninja:
        cmd = [ninja, *(["-k", "0"] if len(targets) > 1 else []), *targets]     # run in the build folder
        level = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", "")     # honoured as cmake --build would
        if level.isdigit() and int(level) > 0:
            cmd[1:1] = ["-j", level]
    else:
        cmd = ["cmake", "--build", str(build.binary_dir), "--target", *targets]
    proc = subprocess.Popen(cmd, cwd=build.binary_dir if ninja else ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, errors="replace")
    lines = []
    for line in proc.stdout:
        lines.append(line)
        m = NINJA_PROGRESS.match(line)
        if m and progress:
            progress(int(m.group(1)), int(m.group(2)))
    proc.wait()
    return proc.returncode == 0, shown_text(build, "".join(lines))


def shown_text(build: Build, text: str) -> str:
    """A build's diagnostics as the user reads them: the staging copy's paths replaced by the folder
    they named, control characters made visible."""
    if build.steps_dir != build.shown_dir:
        text = text.replace(str(build.steps_dir), str(build.shown_dir))
    return printable(text)


"""./kit render: pictures of the course's scenes, from the solutions or from a student's steps.

Each step has its own small program in tools/render (raykit_render_stepNN), linked with that step's
code, so a step that does not compile or is not written yet costs only its own scenes. With --steps,
every picture is compared with the reference picture of the same size and a diff image is written
beside it.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

from .. import atomic
from ..common import BUILD, ROOT, KitError, load_steps, note, paint, resolve_steps_dir, say
from ..build import Build, tools_build, build_target, configure, preset_build, submission_build

from ..packages import ensure_packages
from ..status import FAILED, OK, USAGE

DEFAULT_SIZE = (256, 256)
MAX_SIDE = 4096                 # pixels a side; raykit_render_stepNN enforces the same limit
RENDER_SECONDS = 60.0           # one picture; a student's endless loop is stopped after this
DOCS_IMAGES = ROOT / "docs" / "images"
TEST_DATA = ROOT / "tests" / "05_cornell_box" / "reference_render.hpp"
TEST_SIZE = (48, 32)
NO_SOLUTIONS = "this copy of the kit has no solutions/ folder. Render your own code with:\n  ./kit render --steps steps"
DOCS_SIZE_ONLY = (f"this copy has no solutions/, so the only reference pictures are those in docs/images, at "
                  f"{DEFAULT_SIZE[0]}x{DEFAULT_SIZE[1]}; drop --size")

# Exit statuses of raykit_render_stepNN (tools/render/tool.hpp).
NOT_WRITTEN, THREW, CANNOT_WRITE = 3, 4, 5


@dataclass
class Scene:
    name: str
    step: str                   # the step whose code draws it
    shadings: list[str]         # "flat" first
    about: str

    def images(self) -> list[tuple[str, str]]:
        """(shading, file name without .png) for each picture of the scene."""
        return [(s, self.name if s == "flat" else f"{self.name}-{s}") for s in self.shadings]


def available_scenes() -> list[Scene]:
    """The course's scenes, in step order, from the manifest of each step of this kit:
    tests/NN_topic/step.json, "scenes": [{"name", "shadings" ("flat" first), "about"}], drawn by
    tools/render/render_stepNN.cpp."""
    return [Scene(entry["name"], step.number, list(entry["shadings"]), entry["about"]) for step in load_steps()
            for entry in json.loads((ROOT / "tests" / step.folder / "step.json").read_text()).get("scenes", [])]


def parse_size(text: str) -> tuple[int, int]:
    m = re.fullmatch(r"\s*([+-]?\d+)\s*[xX]\s*([+-]?\d+)\s*", text)
    if not m:
        raise KitError(f"--size {text}: write the size as WIDTHxHEIGHT, e.g. 256x256")
    w, h = int(m.group(1)), int(m.group(2))
    for side, value in (("width", w), ("height", h)):
        if not 1 <= value <= MAX_SIDE:
            raise KitError(f"--size {text}: the {side} is {value} pixels; each side must be between 1 and "
                           f"{MAX_SIDE} pixels")
    return w, h


def select_scenes(names: list[str]) -> list[Scene]:
    scenes = available_scenes()
    if not names:
        return scenes
    chosen = []
    for n in names:
        match = [s for s in scenes if s.name == n]
        if not match:
            known = ", ".join(s.name for s in scenes)
            raise KitError(f"there is no scene {n!r}; the scenes are: {known}")
        if match[0] not in chosen:
            chosen.append(match[0])
    return chosen


def prepare_out(path: Path, shown: str) -> Path:
    """An existing or new folder that we can write in, or a clear error."""
    if path.exists() and not path.is_dir():
        raise KitError(f"--out {shown}: this is a file, not a folder")
    if not path.exists():
        try:
            path.mkdir(parents=True)
        except OSError as e:
            raise KitError(f"--out {shown}: cannot create the folder ({e.strerror})") from None
    try:
        with tempfile.NamedTemporaryFile(dir=path, prefix=".raykit-write-test-"):
            pass
    except OSError as e:
        raise KitError(f"--out {shown}: cannot write in this folder ({e.strerror})") from None
    return path


# --- building and running the renderers ------------------------------------------------

def renderer(build: Build, step: str) -> Path:
    return build.binary_dir / "tools" / "render" / f"raykit_render_step{step}"


def imgdiff(build: Build) -> Path:
    return build.binary_dir / "tools" / "render" / "raykit_imgdiff"


def build_renderers(build: Build, steps: list[str]) -> dict[str, str]:
    """Builds raykit_render_stepNN for each step; returns {step: why it cannot render} for failures."""
    configure(build)
    all_steps = {s.number: s for s in load_steps()}
    problems: dict[str, str] = {}
    for nn in steps:
        # Every program links step 05 too: its view_ray shoots the view rays (tools/render/tool.hpp).
        chain = list(dict.fromkeys([nn] + all_steps[nn].needs + ["05"] + all_steps["05"].needs))
        missing = [f"{all_steps[n].folder}/{f}" for n in chain for f in all_steps[n].files
                   if not (build.steps_dir / all_steps[n].folder / f).is_file()]
        if missing:
            problems[nn] = f"{missing[0]} is missing"
            continue
        ok, out = build_target(build, f"raykit_render_step{nn}")
        if not ok:
            errors = [line for line in out.splitlines() if "error" in line][:3]
            problems[nn] = "it does not compile (./kit check shows why)" + "".join(f"\n      {e}" for e in errors)
    ok, out = build_target(build, "raykit_imgdiff")
    if not ok:
        raise KitError(f"could not build the image comparer:\n{out[-2000:]}", FAILED)
    return problems


def render_one(exe: Path, scene: str, shading: str, size: tuple[int, int], target: Path) -> str | None:
    """Renders one picture to `target`; returns None, or why it could not."""
    tmp = target.with_name(target.name + ".tmp")
    cmd = [str(exe), scene, shading, str(size[0]), str(size[1]), str(target)]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            stdin=subprocess.DEVNULL, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=RENDER_SECONDS)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return f"stopped after {RENDER_SECONDS:g} s: an endless loop?"
    finally:
        tmp.unlink(missing_ok=True)     # left only by a stop or a crash in the middle of writing
    message = (err or out).strip().splitlines()
    first = message[0] if message else ""
    if proc.returncode == 0:
        return None
    if proc.returncode == NOT_WRITTEN:
        name = re.search(r"raykit::not_implemented: (\w+)", first)
        what = name.group(1) if name else first
        # Name the step that is missing, which need not be the scene's: every program draws with step
        # 05's view_ray and render (tools/render/tool.hpp, render_step04.cpp).
        owner = next((s for s in load_steps() if what in s.functions), None)
        if owner is None:
            return f"not written yet ({what})"
        return (f"step {owner.number}'s {what} is not written yet ({owner.folder}/)"
                + (": every picture is drawn with your step 05's view rays and render loop"
                   if owner.number == "05" else ""))
    if proc.returncode == THREW:
        return first
    if proc.returncode == CANNOT_WRITE:
        raise KitError(first or f"cannot write {target}", FAILED)
    if proc.returncode < 0:
        sig = -proc.returncode
        what = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else f"signal {sig}"
        return f"the code crashed ({what})"
    return f"the renderer failed (exit status {proc.returncode}): {first}"


@dataclass
class Difference:
    """How a picture differs from its reference, pixel by pixel (tools/render/imgdiff.cpp)."""
    differing: int              # pixels of another colour, of the three kinds below
    edge: int                   # the colour of a neighbour in the reference: an edge one pixel off
    total: int                  # pixels in the picture
    level: int                  # every channel within one level of 255: rounding of a smooth shading
    upside_down: int = -1       # pixels beyond one level from the reference turned upside down (-1: not told)
    mirrored: int = -1          # the same, from the reference mirrored left to right

    @property
    def other(self) -> int:
        """Pixels of a colour the reference has nowhere near: never rounding."""
        return self.differing - self.edge - self.level


def compare(diff_exe: Path, reference: Path, picture: Path, diff: Path) -> Difference:
    """Counts the pixels of `picture` that differ from `reference`, by kind; writes the diff image `diff`."""
    r = subprocess.run([str(diff_exe), str(reference), str(picture), str(diff)], capture_output=True,
                       text=True, timeout=120)
    diff.with_name(diff.name + ".tmp").unlink(missing_ok=True)
    if r.returncode != 0:
        raise KitError(f"could not compare {picture} with {reference}: {r.stderr.strip()}", FAILED)
    return Difference(*(int(n) for n in r.stdout.split()))


# What a correct answer may change in a picture, measured with raykit_imgdiff's counts (GCC 12): every
# scene at 256x256, 512x384 and 97x61, drawn by correct code written four other ways than the solutions:
# the textbook quadratic of tests/fixtures/textbook (steps 01 and 02), the half-b form in float, lecture
# 03's rewrite in float, and a step 05 whose view rays are unit vectors built from a [-1, 1] film:
#   - pixels one colour level off (of 255) in the normals pictures: at most 30 of 196608 (spheres-normals
#     at 512x384) and 20 of 65536 (at 256x256), 0.031 % at most: a normal whose 8-bit value lands near
#     a .5 rounds the other way when the hit point moves by an ulp, whatever formula found it;
#   - edges moved by a pixel, or any other colour: none.
# The mutants of steps 02 and 05 (tests/mutants/), drawn the same way at 256x256 and 97x61: those of
# step 02 that change a picture at all give at least 3116 pixels of another colour; some of step 05 only
# move edges, 12 pixels at the fewest (light_coordinates_swapped at 97x61), so no moved edge is accepted.
# Seven of step 02's sixteen and one of step 05's thirteen leave every picture as it is (a tangent, a NaN
# radius, a zero direction, an origin inside: no view ray of these scenes is such a case); the grader
# catches those, the pictures cannot.
# Accepted: one-level pixels only, at most 1 in 256 of the picture (0.39 %, 12 times the worst measured).
LEVEL_SHARE = 256


def level_bound(total: int) -> int:
    """How many pixels one colour level off a correct answer may have in a picture of `total` pixels."""
    return max(1, total // LEVEL_SHARE)


def within_rounding(d: Difference) -> bool:
    """Whether the differences are only what rounding does to a correct answer (see LEVEL_SHARE)."""
    return d.other == 0 and d.edge == 0 and d.level <= level_bound(d.total)


def verdict(d: Difference, picture: Path, reference: Path, diff: Path, accepted: bool) -> list[str]:
    """The lines that say how `picture` differs from `reference`, and whether that is accepted."""
    if accepted:
        lines = [f"  {paint('✓', 'green')} {picture}  matches the reference but for {d.level} of {d.total} "
                 f"pixels one colour level off (of 255)",
                 f"      accepted (up to {level_bound(d.total)}): where a shading's value sits on a rounding "
                 "boundary of the 8-bit colour, any correct float answer may tip it either way"]
    else:
        kinds = [f"{n} {what}" for n, what in ((d.other, "of another colour (magenta): a region drawn in "
                                                "another colour, missing or added, not a moved edge"),
                                               (d.edge, "an edge moved by a pixel (yellow)"),
                                               (d.level, "one colour level off (cyan)")) if n]
        # A picture that is the reference turned over is named as such, not by its pixels' kinds (upside
        # down, the Cornell box is mostly moved edges: its walls are nearly symmetric).
        turned = [what for n, what in ((d.upside_down, "upside down: row 0 is the top of the image "
                                        "(lecture 05, section 6)"),
                                       (d.mirrored, "mirrored left to right: right = forward x up, not up x "
                                        "forward (lecture 05, section 5); in a scene symmetric but for its "
                                        "colours, the same as colours swapped left for right (section 3)"))
                  if 0 <= n <= level_bound(d.total)]
        if turned:
            lines = [f"  {paint('✗', 'red')} {picture}  is the reference turned {turned[0]}",
                     f"      {d.differing} of {d.total} pixels differ from the reference as it stands"]
        else:
            lines = [f"  {paint('✗', 'red')} {picture}  {d.differing} of {d.total} pixels differ from the "
                     "reference: " + ", ".join(kinds)]
            if d.other == 0 and d.edge == 0:
                lines.append(f"      more one-level pixels than rounding alone makes (at most "
                             f"{level_bound(d.total)}): a shading computed slightly differently everywhere?")
            elif d.other == 0:
                lines.append("      only edges moved: a camera shifted by half a pixel, or an object a little off "
                             "(the correct answers measured never move one)")
    return lines + [f"      reference {reference}", f"      marked in {diff}"]


def render_reference(scenes: list[Scene], size: tuple[int, int], out: Path) -> dict[str, Path]:
    """Renders the scenes with the solutions into `out`; {image name: path}."""
    if not (ROOT / "solutions").is_dir():
        raise KitError(NO_SOLUTIONS, USAGE)
    build = preset_build("reference")
    problems = build_renderers(build, sorted({s.step for s in scenes}))
    if problems:
        nn, why = next(iter(problems.items()))
        raise KitError(f"the reference solution of step {nn} cannot render: {why}", FAILED)
    written = {}
    for scene in scenes:
        for shading, name in scene.images():
            path = out / f"{name}.png"
            problem = render_one(renderer(build, scene.step), scene.name, shading, size, path)
            if problem:
                raise KitError(f"the reference solution could not render {name}: {problem}", FAILED)
            written[name] = path
    return written


def reference_pictures(scenes: list[Scene], size: tuple[int, int]) -> dict[str, Path]:
    """The reference pictures to compare a student's with: rendered from the solutions when this copy has
    them, else the committed docs/images (at their size only)."""
    if (ROOT / "solutions").is_dir():
        folder = BUILD / "render" / "reference-cache"
        folder.mkdir(parents=True, exist_ok=True)
        return render_reference(scenes, size, folder)
    if size != DEFAULT_SIZE:
        raise KitError(DOCS_SIZE_ONLY, USAGE)
    return {name: DOCS_IMAGES / f"{name}.png" for s in scenes for _, name in s.images()
            if (DOCS_IMAGES / f"{name}.png").is_file()}


# --- the reference picture of step 05's suite ------------------------------------------------

def test_data_text(rows: list[str]) -> str:
    """tests/05_cornell_box/reference_render.hpp for the letter picture `rows`."""
    body = "".join(f'    "{r}",\n' for r in rows)
    return (
        f"// The empty Cornell box at {len(rows[0])} x {len(rows)} pixels, rendered by the reference solution:\n"
        "// one letter a pixel, W white, R red, G green, L light, . black (nothing hit).\n"
        "// Written by ./kit render --refresh; ./kit test checks that it is up to date.\n"
        "#pragma once\n\n"
        "namespace cornell_reference {\n\n"
        f"constexpr int width = {len(rows[0])};\n"
        f"constexpr int height = {len(rows)};\n"
        "constexpr const char* rows[height] = {\n"
        f"{body}"
        "};\n\n"
        "}  // namespace cornell_reference\n")


def fresh_test_data() -> str:
    """step 05's reference picture, rendered now by the solutions, as the header's text."""
    build = preset_build("reference")
    problems = build_renderers(build, ["05"])
    if problems:
        raise KitError(f"the reference solution of step 05 cannot render: {problems['05']}", FAILED)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "cornell_box.txt"
        problem = render_one(renderer(build, "05"), "cornell_box", "flat", TEST_SIZE, path)
        if problem:
            raise KitError(f"the reference solution could not render the Cornell box: {problem}", FAILED)
        return test_data_text(path.read_text().splitlines())


# --- the command ---------------------------------------------------------------------------


def register(p) -> None:
    names = ", ".join(f"{s.name} (step {int(s.step)})" for s in available_scenes())
    p.add_argument("scenes", nargs="*", metavar="SCENE", help=f"what to render (default: all): {names}")
    p.add_argument("--out", metavar="DIR",
                   help="where to write the pictures (default: build/render, or build/render/steps with --steps)")
    p.add_argument("--size", metavar="WxH",
                   help=f"picture size in pixels (default: {DEFAULT_SIZE[0]}x{DEFAULT_SIZE[1]}, at most "
                        f"{MAX_SIDE} a side)")
    p.add_argument("--steps", metavar="DIR",
                   help="render with the code in DIR (e.g. steps) and write beside each picture a diff image "
                        "marking the pixels that differ from the reference")
    p.add_argument("--refresh", action="store_true",
                   help="instructors: re-render the committed reference pictures (docs/images and step 05's "
                        "test picture) with the solutions")


def run(args) -> int:
    ensure_packages("build", "render")   # stb: needed by render only (packages.py)
    if args.refresh:
        if args.scenes or args.out or args.size or args.steps:
            raise KitError("--refresh re-renders every committed reference picture; it takes no other option")
        return refresh()
    size = parse_size(args.size) if args.size else DEFAULT_SIZE
    scenes = select_scenes(args.scenes)
    source = resolve_steps_dir(args.steps) if args.steps else None
    if not (ROOT / "solutions").is_dir():
        # A student's copy of the kit: the committed pictures are the only reference.
        if source is None:
            raise KitError(NO_SOLUTIONS, USAGE)
        if size != DEFAULT_SIZE:
            raise KitError(DOCS_SIZE_ONLY, USAGE)
    default_out = BUILD / "render" / ("steps" if source else "")
    out = prepare_out(Path(args.out).expanduser() if args.out else default_out, args.out or str(default_out))
    if source is None:
        return render_solutions(scenes, size, out)
    return render_steps(scenes, size, out, source)


def render_solutions(scenes: list[Scene], size: tuple[int, int], out: Path) -> int:
    note(f"kit: rendering {len(scenes)} scene(s) at {size[0]}x{size[1]} with the reference solutions")
    for path in render_reference(scenes, size, out).values():
        say(f"  {paint('✓', 'green')} {path}")
    return OK


def render_steps(scenes: list[Scene], size: tuple[int, int], out: Path, source: Path) -> int:
    build = tools_build(submission_build(source))
    note(f"kit: rendering {len(scenes)} scene(s) at {size[0]}x{size[1]} with the code in {source}")
    problems = build_renderers(build, sorted({s.step for s in scenes}))
    references = reference_pictures(scenes, size)
    all_good = True
    for scene in scenes:
        if scene.step in problems:
            all_good = False
            forget(out, scene)
            say(f"  {paint('·', 'yellow')} {scene.name}: skipped, {skip_text(scene, problems[scene.step])}")
            continue
        for shading, name in scene.images():
            picture = out / f"{name}.png"
            problem = render_one(renderer(build, scene.step), scene.name, shading, size, picture)
            if problem:
                forget(out, scene)
                all_good = False
                say(f"  {paint('·', 'yellow')} {name}: skipped, {skip_text(scene, problem)}")
                continue
            reference = references.get(name)
            if reference is None:
                say(f"  {paint('?', 'yellow')} {picture}  (no reference picture to compare with)")
                continue
            diff = out / f"{name}-diff.png"
            d = compare(imgdiff(build), reference, picture, diff)
            if d.differing == 0:
                say(f"  {paint('✓', 'green')} {picture}  matches the reference")
                diff.unlink(missing_ok=True)
                continue
            accepted = within_rounding(d)
            all_good = all_good and accepted
            for line in verdict(d, picture, reference, diff, accepted):
                say(line)
    return OK if all_good else FAILED


def skip_text(scene: Scene, problem: str) -> str:
    """Why a scene is skipped, the step at fault first: the problem's own when it names one."""
    return problem if problem.startswith("step ") else f"step {scene.step}: {problem}"


def forget(out: Path, scene: Scene) -> None:
    """Removes a scene's pictures left by an earlier run, so that none is mistaken for this run's."""
    for _, name in scene.images():
        for stale in (out / f"{name}.png", out / f"{name}-diff.png"):
            stale.unlink(missing_ok=True)


def refresh() -> int:
    scenes = available_scenes()
    DOCS_IMAGES.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=BUILD if BUILD.is_dir() else None) as tmp:
        written = render_reference(scenes, DEFAULT_SIZE, Path(tmp))
        for name, path in written.items():
            atomic.write(DOCS_IMAGES / f"{name}.png", path.read_bytes())
            say(f"  {paint('✓', 'green')} {(DOCS_IMAGES / f'{name}.png').relative_to(ROOT)}")
    atomic.write(TEST_DATA, fresh_test_data())
    say(f"  {paint('✓', 'green')} {TEST_DATA.relative_to(ROOT)}")
    return OK

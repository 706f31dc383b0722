"""./kit test checks for ./kit render, the committed reference pictures and step 05's wrong fixture."""

from __future__ import annotations

import re
import shutil
import tempfile
from pathlib import Path

from raykit.commands import render as cmd_render
from raykit.mutants import MUTANTS, write_answer
from raykit.common import BUILD, ROOT, load_steps
from raykit.build import preset_build, submission_build, tools_build
from raykit.checking import check_steps
from raykit.status import DONE, PARTIAL
from .support import expect, kit, need_solutions
from .fixtures import fixture_dir



def selftest_pictures_current(ctx) -> str:
    """docs/images and step 05's test picture are what the solutions render today."""
    need_solutions()  # these render with, or against, the reference solutions
    scenes = cmd_render.available_scenes()
    stale = []
    with tempfile.TemporaryDirectory() as tmp:
        fresh = cmd_render.render_reference(scenes, cmd_render.DEFAULT_SIZE, Path(tmp))
        diff_exe = cmd_render.imgdiff(preset_build("reference"))
        for name, path in fresh.items():
            committed = cmd_render.DOCS_IMAGES / f"{name}.png"
            if not committed.is_file():
                stale.append(f"{committed.relative_to(ROOT)} is missing")
                continue
            d = cmd_render.compare(diff_exe, committed, path, Path(tmp) / f"{name}-diff.png")
            if d.differing:
                stale.append(f"{committed.relative_to(ROOT)}: {d.differing} of {d.total} pixels differ")
    if cmd_render.fresh_test_data() != cmd_render.TEST_DATA.read_text():
        stale.append(f"{cmd_render.TEST_DATA.relative_to(ROOT)} differs")
    expect(not stale, "the committed reference pictures are not what the solutions render:\n  " +
           "\n  ".join(stale) + "\n  If the change is intended: ./kit render --refresh, look at them, commit.")
    return f"{len(fresh)} pictures in docs/images and step 05's 48x32 picture match a fresh render"


def selftest_wrong_cornell(ctx) -> str:
    """A step 05 that keeps the last hit fails its cases and shows in a diff image."""
    need_solutions()  # these render with, or against, the reference solutions
    all_steps = load_steps()
    steps = [s for s in all_steps if s.number in ("04", "05")]
    r04, r05 = check_steps(submission_build(fixture_dir("cornell_wrong"), "fixtures"), steps, all_steps)
    expect(r04.state == DONE, f"the fixture's (correct) step 04 is graded {r04.state}")
    expect(r05.state == PARTIAL, f"the fixture's step 05 is graded {r05.state}, expected partial")
    failed = {c.name for c in r05.cases if c.status == "fail"}
    for must in ("two objects on one ray with the near one listed first", "a tie goes to the object listed first",
                 "the Cornell box at 48 by 32 pixels matches the reference render"):
        expect(must in failed, f"the fixture's step 05 passes '{must}'")
    with tempfile.TemporaryDirectory() as tmp:
        r = kit("render", "cornell_box", "--steps", str(fixture_dir("cornell_wrong")), "--out", tmp)
        expect(r.returncode == 1, f"./kit render --steps cornell_wrong exited {r.returncode}, expected 1:\n"
                                  f"{r.stdout[-1000:]}{r.stderr[-1000:]}")
        m = re.search(r"(\d+) of (\d+) pixels differ", r.stdout)
        expect(m is not None and int(m.group(1)) > 0, f"no count of differing pixels in:\n{r.stdout[-1000:]}")
        expect((Path(tmp) / "cornell_box-diff.png").is_file(), "no cornell_box-diff.png was written")
        expect(not list(Path(tmp).glob("*.tmp")), "a temporary file was left behind")
    return f"{len(failed)} cases fail, and the diff image marks {m.group(1)} of {m.group(2)} pixels"


def selftest_render_skips(ctx) -> str:
    """Stubs and crashing code are reported and skipped, and leave no picture."""
    need_solutions()  # these render with, or against, the reference solutions
    seen = []
    # Every scene shoots its rays with step 05's view_ray (tools/render/tool.hpp): the crashing step 01
    # is drawn on top of the reference steps 04 and 05.
    crash = Path(tempfile.mkdtemp(dir=BUILD))
    for folder in ("04_rectangles", "05_cornell_box"):
        shutil.copytree(ROOT / "solutions" / folder, crash / folder)
    shutil.copytree(fixture_dir("crash"), crash, dirs_exist_ok=True)
    # Steps 01-04 done, step 05 the stub: the rectangles are drawn with step 05's render loop, and the
    # message names step 05, the step missing, not step 04, the scene's.
    four = Path(tempfile.mkdtemp(dir=BUILD))
    for s in load_steps():
        shutil.copytree(ROOT / ("steps" if s.number == "05" else "solutions") / s.folder, four / s.folder)
    for source, scene, words in [("steps", "cornell_box", "not written yet"),
                                 (str(four), "rectangles", "step 05's render is not written yet"),
                                 (str(crash), "unit_sphere", "crashed"),
                                 (str(fixture_dir("cornell_wrong")), "unit_sphere", "unit_sphere.cpp is missing")]:
        with tempfile.TemporaryDirectory() as tmp:
            r = kit("render", scene, "--steps", source, "--out", tmp)
            expect(r.returncode == 1, f"./kit render {scene} --steps {source} exited {r.returncode}, expected 1")
            expect(words in r.stdout, f"./kit render {scene} --steps {source} does not say '{words}':\n{r.stdout}")
            left = [p.name for p in Path(tmp).iterdir()]
            expect(not left, f"./kit render {scene} --steps {source} left files: {left}")
        expect("step 04: " not in r.stdout or scene != "rectangles",
               f"./kit render rectangles blames step 04 for step 05's stub:\n{r.stdout}")
        seen.append(words.split(" (")[0])
    shutil.rmtree(crash, ignore_errors=True)
    shutil.rmtree(four, ignore_errors=True)
    return "reported and skipped, no file left: " + ", ".join(seen)




def selftest_rounding_rule(ctx) -> str:
    """The rule of what a correct answer may change, on the counts measured (cmd_render.LEVEL_SHARE)."""
    D = cmd_render.Difference
    cases = [  # (differing, edge, total, level), accepted?
        (D(20, 0, 65536, 20), True),        # the textbook step 02, spheres-normals at 256x256
        (D(30, 0, 196608, 30), True),       # the same at 512x384
        (D(12, 12, 5917, 0), False),        # step 05 light_coordinates_swapped at 97x61: edges only
        (D(372, 372, 65536, 0), False),     # step 05 pixel_corner, spheres: edges only
        (D(300, 0, 65536, 300), False),     # one level off, but far more than rounding makes
        (D(1, 0, 65536, 0), False),         # a single pixel of another colour
    ]
    for d, want in cases:
        expect(cmd_render.within_rounding(d) == want,
               f"{d} is {'accepted' if not want else 'refused'}, expected the opposite")
    return f"{len(cases)} measured differences judged as intended"


def _steps_folder(work: Path, own: dict[str, Path]) -> Path:
    """A steps folder with the reference's steps 01, 02, 04 and 05 but for the folders in `own`."""
    for s in load_steps():
        if s.number in ("01", "02", "04", "05"):
            shutil.copytree(own.get(s.number, ROOT / "solutions" / s.folder), work / s.folder)
    return work


def selftest_render_tolerance(ctx) -> str:
    """A textbook step 02 renders as accepted; single pixels show in the diff; real slips still fail."""
    need_solutions()  # these render with, or against, the reference solutions
    steps = {s.number: s for s in load_steps()}
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="render-tolerance-"))
    try:
        textbook = _steps_folder(work / "textbook", {n: fixture_dir("textbook") / steps[n].folder for n in ("01", "02")})
        out = work / "out-textbook"
        r = kit("render", "spheres", "--steps", str(textbook), "--out", str(out))
        expect(r.returncode == 0, f"./kit render spheres with the textbook step 02 exited {r.returncode}, "
                                  f"expected 0 (it passes the basic tier):\n{r.stdout[-1500:]}{r.stderr[-500:]}")
        m = re.search(r"spheres-normals\.png  matches the reference but for (\d+) of (\d+) pixels one colour level",
                      r.stdout)
        refs = re.findall(r"^\s+reference (.+\.png)$", r.stdout, re.M)
        summary = "the textbook step 02 matches exactly"
        if m:
            n = int(m.group(1))
            expect("accepted" in r.stdout, f"the accepted difference is not said to be accepted:\n{r.stdout}")
            expect(refs and all(Path(p).is_file() for p in refs), f"no reference picture's path printed:\n{r.stdout}")
            # Rings: the diff image marks many more pixels than differ. Compare it with the diff of the
            # reference with itself (the backdrop alone) to count the marked pixels.
            diff_exe = cmd_render.imgdiff(tools_build(submission_build(textbook)))
            backdrop, marked = work / "backdrop.png", out / "spheres-normals-diff.png"
            cmd_render.compare(diff_exe, Path(refs[0]), Path(refs[0]), backdrop)
            marks = cmd_render.compare(diff_exe, backdrop, marked, work / "marks.png").differing
            expect(marks >= 20 * n, f"{n} differing pixels make only {marks} marked pixels in {marked.name}: "
                                    "a single pixel is not visible")
            summary = f"the textbook step 02 accepted with {n} pixels one level off, {marks} pixels marked"
        # Real slips still fail: one of step 02 (a wrong root, seen in the normals) and one of step 05
        # (rays through pixel corners: every edge moves, and nothing else).
        caught = []
        for nn, name, scene in (("02", "far_root_preferred", "spheres"), ("05", "pixel_corner", "cornell_box"),
                                ("05", "light_after_ceiling", "cornell_box")):
            step = steps[nn]
            answer = write_answer(step, MUTANTS / step.folder / f"{name}.patch", work / name / "answer")
            folder = _steps_folder(work / name / "steps", {nn: answer})
            r = kit("render", scene, "--steps", str(folder), "--out", str(work / name / "out"))
            expect(r.returncode == 1 and "pixels differ from the reference" in r.stdout,
                   f"./kit render {scene} with the mutant {nn}/{name} exited {r.returncode}, expected 1:\n"
                   f"{r.stdout[-1500:]}")
            if name == "light_after_ceiling":   # the light is gone whole: a region, not a moved edge
                other = re.search(r"(\d+) of another colour", r.stdout)
                expect(other is not None and int(other.group(1)) >= 50 and "an edge moved" not in r.stdout,
                       f"a missing light is not called a region of another colour:\n{r.stdout[-1200:]}")
            caught.append(f"{nn}/{name}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return summary + "; mutants " + ", ".join(caught) + " still fail"


def selftest_render_arguments(ctx) -> str:
    need_solutions()  # these render with, or against, the reference solutions
    with tempfile.TemporaryDirectory() as tmp:
        a_file = Path(tmp) / "a_file"
        a_file.write_text("not a folder\n")
        new = Path(tmp) / "new"
        cases = [
            (["render", "no_such_scene", "--out", str(new)], "no scene 'no_such_scene'"),
            (["render", "--size", "0x64", "--out", str(new)], "between 1 and"),
            (["render", "--size", "100000x100000", "--out", str(new)], "between 1 and"),
            (["render", "--size", "big", "--out", str(new)], "WIDTHxHEIGHT"),
            (["render", "--out", str(a_file)], "is a file"),
            (["render", "--out", "/proc/raykit-cannot-exist"], "cannot create the folder"),
            (["render", "--out", "/proc"], "cannot write in this folder"),
            (["render", "--steps", "/nonexistent/folder", "--out", str(new)], "no such folder"),
            (["render", "--refresh", "--size", "8x8"], "takes no other option"),
        ]
        for args, words in cases:
            r = kit(*args, timeout=120)
            expect(r.returncode == 2, f"./kit {' '.join(args)} exited {r.returncode}, expected 2:\n{r.stderr[-500:]}")
            expect(words in r.stderr, f"./kit {' '.join(args)}: the message lacks '{words}': {r.stderr[-300:]}")
        expect(not new.exists(), "a refused command created its --out folder")
        expect(a_file.read_text() == "not a folder\n", "a refused command changed a file")
    return f"{len(cases)} bad commands: a clear message, exit 2, nothing written"

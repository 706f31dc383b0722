"""./kit test checks for ./kit render, the committed reference pictures and step 05's wrong fixture."""

from __future__ import annotations

import re
import shutil
import tempfile
from pathlib import Path

from ..commands import render as cmd_render
from ..common import BUILD, ROOT, load_steps, preset_build, submission_build
from ..checking import check_steps
from .harness import expect, kit, need_solutions

WRONG_05 = ROOT / "tests" / "fixtures" / "cornell_wrong"


def check_pictures_current(ctx) -> str:
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
            differing, _, total = cmd_render.compare(diff_exe, committed, path, Path(tmp) / f"{name}-diff.png")
            if differing:
                stale.append(f"{committed.relative_to(ROOT)}: {differing} of {total} pixels differ")
    if cmd_render.fresh_test_data() != cmd_render.TEST_DATA.read_text():
        stale.append(f"{cmd_render.TEST_DATA.relative_to(ROOT)} differs")
    expect(not stale, "the committed reference pictures are not what the solutions render:\n  " +
           "\n  ".join(stale) + "\n  If the change is intended: ./kit render --refresh, look at them, commit.")
    return f"{len(fresh)} pictures in docs/images and step 05's 48x32 picture match a fresh render"


def check_wrong_cornell(ctx) -> str:
    """A step 05 that keeps the last hit fails its cases and shows in a diff image."""
    need_solutions()  # these render with, or against, the reference solutions
    all_steps = load_steps()
    steps = [s for s in all_steps if s.number in ("04", "05")]
    r04, r05 = check_steps(submission_build(WRONG_05, "fixtures"), steps, all_steps)
    expect(r04.state == "done", f"the fixture's (correct) step 04 is graded {r04.state}")
    expect(r05.state == "partial", f"the fixture's step 05 is graded {r05.state}, expected partial")
    failed = {c.name for c in r05.cases if c.status == "fail"}
    for must in ("two objects on one ray with the near one listed first", "a tie goes to the object listed first",
                 "the Cornell box at 48 by 32 pixels matches the reference render"):
        expect(must in failed, f"the fixture's step 05 passes '{must}'")
    with tempfile.TemporaryDirectory() as tmp:
        r = kit("render", "cornell_box", "--steps", str(WRONG_05), "--out", tmp)
        expect(r.returncode == 1, f"./kit render --steps {WRONG_05.name} exited {r.returncode}, expected 1:\n"
                                  f"{r.stdout[-1000:]}{r.stderr[-1000:]}")
        m = re.search(r"(\d+) of (\d+) pixels differ", r.stdout)
        expect(m is not None and int(m.group(1)) > 0, f"no count of differing pixels in:\n{r.stdout[-1000:]}")
        expect((Path(tmp) / "cornell_box-diff.png").is_file(), "no cornell_box-diff.png was written")
        expect(not list(Path(tmp).glob("*.tmp")), "a temporary file was left behind")
    return f"{len(failed)} cases fail, and the diff image marks {m.group(1)} of {m.group(2)} pixels"


def check_render_skips(ctx) -> str:
    """Stubs and crashing code are reported and skipped, and leave no picture."""
    need_solutions()  # these render with, or against, the reference solutions
    seen = []
    # Every scene shoots its rays with step 05's view_ray (tools/render/tool.hpp): the crashing step 01
    # is drawn on top of the reference steps 04 and 05.
    crash = Path(tempfile.mkdtemp(dir=BUILD))
    for folder in ("04_rectangles", "05_cornell_box"):
        shutil.copytree(ROOT / "solutions" / folder, crash / folder)
    shutil.copytree(ROOT / "tests" / "fixtures" / "crash", crash, dirs_exist_ok=True)
    for source, scene, words in [("steps", "cornell_box", "not written yet"),
                                 (str(crash), "unit_sphere", "crashed"),
                                 ("tests/fixtures/cornell_wrong", "unit_sphere", "unit_sphere.cpp is missing")]:
        with tempfile.TemporaryDirectory() as tmp:
            r = kit("render", scene, "--steps", source, "--out", tmp)
            expect(r.returncode == 1, f"./kit render {scene} --steps {source} exited {r.returncode}, expected 1")
            expect(words in r.stdout, f"./kit render {scene} --steps {source} does not say '{words}':\n{r.stdout}")
            left = [p.name for p in Path(tmp).iterdir()]
            expect(not left, f"./kit render {scene} --steps {source} left files: {left}")
        seen.append(words.split(" (")[0])
    shutil.rmtree(crash, ignore_errors=True)
    return "reported and skipped, no file left: " + ", ".join(seen)


def check_render_arguments(ctx) -> str:
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


def checks() -> list:
    return [
        ("reference pictures are current", check_pictures_current),
        ("a wrong step 05 fails and shows in a diff", check_wrong_cornell),
        ("render skips what cannot be drawn", check_render_skips),
        ("render command line errors", check_render_arguments),
    ]

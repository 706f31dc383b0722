"""Self-test of ./kit refresh (kitlib/commands/refresh.py): which self-tests a change touches, and a
plan that rewrites nothing on a kit whose records are current."""

from __future__ import annotations

import json

import pytest

from raykit.common import ROOT, load_steps
from .support import Failed, expect, kit, need_solutions


@pytest.mark.quick
def selftest_touched(ctx) -> str:
    from kitlib.commands.refresh import touched_tests
    steps = [s.number for s in load_steps()]
    first, last = steps[0], steps[-1]
    # The step that draws the Cornell box: the one whose step.json lists the scene (05 in the kit; an
    # instructor's step 06 after it does not draw it).
    drawn = [s.folder[:2] for s in load_steps()
             if any(e.get("name") == "cornell_box" for e in json.loads((ROOT / "tests" / s.folder / "step.json")
                                                                       .read_text()).get("scenes", []))]
    expect(len(drawn) == 1, f"the steps whose step.json lists the scene cornell_box: {drawn}")
    box = drawn[0]
    cases = {
        (f"tests/{load_steps()[0].folder}/test_x.cpp",): [["--step", first]],
        (f"solutions/{load_steps()[-1].folder}/render.cpp", f"tests/hidden/{first}_x.cpp"): [["--step", first],
                                                                                            ["--step", last]],
        ("course.json",): [["course", "customised"]],
        ("include/raykit/scenes/cornell_box.inc",): [["--step", box], ["lectures:scene tables", "render", "pictures",
                                                                      "slips:turned render", "customised"]],
        ("lectures/01-unit-sphere.md",): [["lectures", "slides"]],
        ("tools/raykit/course.py", "course.json"): [[]],
        ("docs/images/cornell_box.png",): [],
        ("tests/kit/draws.py",): [["draws"]],
        ("tests/kit/conftest.py",): [[]],
    }
    for paths, want in cases.items():
        got = touched_tests(list(paths))
        expect(got == want, f"a change to {list(paths)} runs {got}, not {want}")
    return f"{len(cases)} changes, each with its self-tests (a step's with --step, the kit's code with all)"


def selftest_plan_current(ctx) -> str:
    need_solutions()
    r = kit("refresh", "--plan", "--no-test", timeout=1800)
    expect(r.returncode == 0, f"./kit refresh --plan: exit {r.returncode}\n{r.stdout[-800:]}{r.stderr[-800:]}")
    stale = [l for l in r.stdout.splitlines() if "stale" in l]
    expect(not stale, f"on the kit as committed, ./kit refresh finds stale records: {stale}")
    current = [l for l in r.stdout.splitlines() if l.strip().startswith("current")]
    return f"the committed kit: {len(current)} records current, nothing to rewrite"


OLD_FORMS = [
    # (what the instructor's step.json had, the field the refusal must name)
    ({"functions": ["intersect_plane"]}, '"functions" entry 0'),
    ({"functions": [{"name": "intersect_plane", "returns": "float"}]}, '"parameters"'),
    ({"files": "plane.cpp"}, '"files"'),
    ({"needs": [4]}, '"needs"'),
    ({"summary": None}, '"summary"'),
    ({"lecture": "lectures/99-nothing.md"}, '"lecture"'),
    ({"runs_without": ["5. The camera"]}, '"runs_without"'),
    ({"scenes": [{"name": "disc"}]}, '"scenes"'),
    ({"tests": []}, '"tests" is not a field'),
    ({"files": ["plane.cpp", "disc.cpp"]}, "'disc.cpp': there is no "),
]


@pytest.mark.quick
def selftest_manifest_form(ctx) -> str:
    """Issue 55 item 2: a step.json of an older form is refused by ./kit course and ./kit refresh
    before anything builds, with its field named; the kit's own manifests and the template pass."""
    import contextlib
    import io
    import tempfile
    from pathlib import Path
    from types import SimpleNamespace

    from kitlib import manifest
    from kitlib.commands import course as course_command
    from kitlib.commands import refresh
    from raykit.common import KitError
    from .fixtures import fixture_dir
    numbers = [s.number for s in load_steps()]
    mine = [line for p in manifest.manifests() for line in manifest.problems(p, numbers)]
    expect(not mine, f"the kit's own step.json files are refused: {mine}")
    template = next(fixture_dir("new_step").glob("tests/*/step.json"))
    expect(not manifest.problems(template, numbers + [template.parent.name[:2]]),
           f"the template's step.json is refused: {manifest.problems(template, numbers)}")
    good = json.loads(template.read_text())
    with tempfile.TemporaryDirectory() as tmp:
        import shutil
        shutil.copytree(fixture_dir("new_step"), Path(tmp) / "kit")     # the template's tree: its stub, reference, lecture
        path = Path(tmp) / "kit" / template.relative_to(fixture_dir("new_step"))
        here = numbers + [template.parent.name[:2]]
        expect(not manifest.problems(path, here), f"the template's step.json, copied: {manifest.problems(path, here)}")
        for change, words in OLD_FORMS:
            path.write_text(json.dumps({**good, **{k: v for k, v in change.items() if v is not None}}
                                       if None not in change.values()
                                       else {k: v for k, v in good.items() if k not in change}))
            said = manifest.problems(path, here)
            expect(said and all(words in line or "is missing" in line and None in change.values() for line in said),
                   f"step.json with {json.dumps(change)}: the refusal does not name {words} alone: {said}")
        # Both commands refuse it before they read a step: ./kit course, ./kit refresh.
        path.write_text(json.dumps(dict(good, functions=["intersect_plane"])))
        real = manifest.manifests
        manifest.manifests = lambda root=ROOT: real(root) + [path]
        try:
            for name, call in (("./kit course", lambda: course_command.run(SimpleNamespace(file=None, results=None,
                                                                                         build=False))),
                               ("./kit refresh", lambda: refresh.run(SimpleNamespace(plan=True, no_test=True,
                                                                                     since="HEAD")))):
                out = io.StringIO()
                try:
                    with contextlib.redirect_stdout(out):
                        call()
                    raise Failed(f"{name} accepts a step.json whose functions are names: {out.getvalue()[-400:]}")
                except KitError as e:
                    expect('"functions" entry 0' in str(e) and "older form" in str(e) and not out.getvalue(),
                           f"{name}'s refusal does not name the field before anything else: {e}")
        finally:
            manifest.manifests = real
    return (f"the kit's {len(numbers)} manifests and the template pass; {len(OLD_FORMS)} older or wrong forms "
            "refused with their field; ./kit course and ./kit refresh refuse before anything else")


@pytest.mark.quick
def selftest_refresh_stops(ctx) -> str:
    """Issue 55 item 2: the first regenerator that fails stops ./kit refresh, which says the tool's own
    error (here a CMake-like one, among lines of progress), and runs nothing after it."""
    import contextlib
    import io
    import sys
    import tempfile
    from pathlib import Path
    from types import SimpleNamespace

    from kitlib.commands import refresh
    need_solutions()
    with tempfile.TemporaryDirectory() as tmp:
        ran = Path(tmp) / "ran"
        error = "CMake Error at CMakeLists.txt:244 (raykit_manifest_list): raykit: tests/06_disc/step.json: no \"files\""
        failing = [sys.executable, "-c", "import sys; print('configuring ...'); print('-- a line of progress'); "
                   f"print({error!r}, file=sys.stderr); print('-- Configuring incomplete, errors occurred!'); "
                   "sys.exit(1)"]
        after = [sys.executable, "-c", f"open({str(ran)!r}, 'w').write('ran')"]
        no = [sys.executable, "-c", "import sys; sys.exit(1)"]
        saved = refresh.REGENERATORS
        refresh.REGENERATORS = [refresh.Regenerator("a broken build", no, failing),
                                refresh.Regenerator("what reads it", no, after)]
        out = io.StringIO()
        try:
            with contextlib.redirect_stdout(out):
                code = refresh.run(SimpleNamespace(plan=False, no_test=True, since="HEAD"))
        finally:
            refresh.REGENERATORS = saved
        text = out.getvalue()
        failed = text[text.find("FAILED"):]
        expect(code != 0 and "FAILED    a broken build" in text and error in failed,
               f"./kit refresh does not stop with the tool's error: exit {code}:\n{text}")
        expect(not ran.exists() and "what reads it" not in text,
               f"./kit refresh ran the next regenerator after a failure:\n{text}")
    return "the first failure stops the refresh, its CMake error said again under FAILED; nothing after it ran"

"""Self-test of ./kit refresh (kitlib/commands/refresh.py): which self-tests a change touches, and a
plan that rewrites nothing on a kit whose records are current."""

from __future__ import annotations

import json

from ..common import ROOT, load_steps
from .harness import expect, kit, need_solutions, tier


@tier("quick")
def selftest_touched(ctx) -> str:
    from ..commands.refresh import touched_tests
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
        ("include/raykit/scenes/cornell_box.inc",): [["--step", box], ["lectures:scene file", "render", "pictures",
                                                                      "slips:a render turned over", "customised"]],
        ("lectures/01-unit-sphere.md",): [["lectures", "slides"]],
        ("tools/kitlib/course.py", "course.json"): [[]],
        ("docs/images/cornell_box.png",): [],
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


def selftests():
    return [("refresh: the self-tests a change touches", selftest_touched),
            ("refresh: nothing stale in the committed kit", selftest_plan_current)]

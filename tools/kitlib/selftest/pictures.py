"""Self-test: the picture of a failing case (picture.py, and the judge's figure behind it).

- a wrong step 01 (a mutant: the far root tried first) graded as a student's work: the failing case's
  SVG exists, parses as XML, and holds the expected t as a green label and the student's as a red one;
  `./kit check` prints its path and --json carries it with its summary. The reference, graded the same
  way, leaves no picture behind (so the check cannot pass on stale files);
- picture.py on degenerate figures (a ray through the centre, a zero direction, an infinite tmax, NaN
  answers and inputs, huge numbers, garbage): a picture or a PictureError that says why, never a crash;
- the gallery of pitfalls (docs/pitfalls.md): every expected hit of the table lies on its shape, every
  picture is drawn, and the page shows each one.
"""

from __future__ import annotations

import json
import re
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

from .. import picture
from ..common import BUILD, ROOT, load_steps
from .harness import Failed, expect, kit, need_solutions

WORK = BUILD / "selftest-pictures"
SVG = "{http://www.w3.org/2000/svg}"
CASE = "window: the nearer of two roots"      # far_root_preferred answers 4 where 2 is expected


def labels(path: Path) -> dict:
    """{fill colour: [texts]} of an SVG's <text> elements; raises Failed when it is not XML."""

    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        raise Failed(f"{path}: not a readable SVG ({e})")
    if root.tag != SVG + "svg" or root.get("width") != str(picture.WIDTH):
        raise Failed(f"{path}: its root is {root.tag} of width {root.get('width')}, not an <svg> {picture.WIDTH} wide")
    out: dict = {}
    for t in root.iter(SVG + "text"):
        out.setdefault(t.get("fill", ""), []).append("".join(t.itertext()))
    return out


def grade_json(steps_dir: Path, report: Path):
    report.unlink(missing_ok=True)
    r = kit("check", "1", "--steps", str(steps_dir), "--json", str(report))
    result = json.loads(report.read_text())["extra_data"]["steps"][0] if report.is_file() else None
    return r, result


def selftest_failing_case(ctx) -> str:
    from ..commands.mutant import MUTANTS, write_answer

    need_solutions()
    step = next(s for s in load_steps() if s.number == "01")
    wrong = write_answer(step, MUTANTS / step.folder / "far_root_preferred.patch", WORK / "wrong" / step.folder)
    r, result = grade_json(wrong.parent, WORK / "wrong.json")
    expect(r.returncode == 1 and result is not None, f"./kit check 1 on a wrong step: exit {r.returncode}, "
           f"no JSON" if result is None else f"./kit check 1 on a wrong step: exit {r.returncode}")
    case = next((c for c in result["cases"] if c["name"] == CASE), None)
    expect(case is not None and case["status"] == "fail", f"the mutant does not fail {CASE!r}")
    path = Path(case.get("picture") or "")
    expect(bool(case.get("picture")) and path.is_file(),
           f"--json names no picture of {CASE!r} that exists ({case.get('picture')!r}; "
           f"summary {case.get('picture_summary')!r})")
    expect(path.resolve().is_relative_to(BUILD.resolve()), f"{path} is not under build/")
    expect(f"picture: {path.relative_to(ROOT)}" in r.stdout or "picture: build/pictures/step01/" in r.stdout,
           "./kit check 1 does not print the picture's path under the failing case")
    summary = case.get("picture_summary") or ""
    expect("expected t=2" in summary and "got t=4" in summary and "window [0, inf]" in summary,
           f"the picture's summary does not say what it shows: {summary!r}")
    found = labels(path)
    expect("t = 2" in found.get(picture.EXPECTED_COLOUR, []), f"{path}: no expected label 't = 2' (green)")
    expect("t = 4" in found.get(picture.GOT_COLOUR, []), f"{path}: no label of the answer 't = 4' (red)")
    expect(any(CASE in t for ts in found.values() for t in ts), f"{path}: its title does not name the case")
    drawn = sum(1 for c in result["cases"] if c.get("picture"))
    leaked = [c["name"] for c in result["cases"] if c["tier"] == "hidden" and c.get("picture")]
    expect(not leaked, "a hidden case's picture (its inputs) is shown without --reveal: " + ", ".join(leaked))
    # The reference graded the same way: every case passes, and no picture of the last run is left.
    right = WORK / "right" / step.folder
    shutil.rmtree(right.parent, ignore_errors=True)
    shutil.copytree(ROOT / "solutions" / step.folder, right)
    r2, result2 = grade_json(right.parent, WORK / "right.json")
    expect(r2.returncode == 0 and "picture:" not in r2.stdout, "./kit check 1 on the reference prints a picture")
    left = sorted(path.parent.glob("*.svg"))
    expect(not left, f"pictures of the last run are left in {path.parent}: {', '.join(p.name for p in left)}")
    return f"{drawn} pictures of a wrong step 01, the expected and the given t labelled; none for the reference"


def sphere(o, d, window=None, expected=None, got=None, centre=(5, -2, 3), radius=2):
    f = {"function": "intersect_sphere" if window else "sphere_roots",
         "ray": {"origin": list(o), "direction": list(d)}, "sphere": {"center": list(centre), "radius": radius},
         "expected": expected, "got": got}
    if window:
        f["window"] = list(window)
    return f


def roots(count, t0=0, t1=0):
    return {"count": count, "t": [t0, t1]}


WIDE = {"axis": 2, "offset": 5, "lo": [-3, -1], "hi": [3, 1]}

# (name, figure, what the picture's text must hold, or None when it must refuse with a PictureError)
DEGENERATE = [
    ("ray along the centre", sphere((-1, -2, 3), (2, 0, 0), None, roots(2, 2, 4), roots(2, 4, 4)),
     "any plane holding it"),
    ("zero direction", sphere((0.5, 0, 0), (0, 0, 0), None, roots(0), roots(2, "NaN", "NaN"), (0, 0, 0), 1),
     "the direction is zero"),
    ("inf tmax", sphere((-1, -2, 3), (2, 0, 0), (0, "inf"), 2, 4), "window [0, inf]"),
    ("NaN answer", sphere((-1, -2, 3), (2, 0, 0), (0, "inf"), 2, "NaN"), "got t = NaN"),
    ("a count of 7", sphere((-1, -2, 3), (2, 0, 0), None, roots(2, 2, 4), roots(7, 1, 2)), "count 7"),
    ("empty window", sphere((-1, -2, 3), (2, 0, 0), (4, 2), None, 2), "the window is empty"),
    ("radius 0", sphere((-1, -2, 3), (2, 0, 0), None, roots(0), roots(1, 3, 3), radius=0), "no sphere to draw"),
    ("origin a million away", sphere((-1e6, 0.5, 0), (1, 0, 0), (0, "inf"), 999999.125, 1e30, (0, 0, 0), 1),
     "far outside the view"),
    ("tiny sphere", sphere((0, 0, 0), (1e-30, 0, 0), (0, "inf"), 1e30, None, (1, 0, 0), 1e-7), "t = 1e+30"),
    ("rectangle, parallel ray", {"function": "intersect_rect", "ray": {"origin": [-10, 0, 5], "direction": [1, 0, 0]},
                                 "rect": WIDE, "window": [0, "inf"], "expected": None, "got": 0},
     "the ray is parallel to it"),
    ("rectangle, ray along the normal", {"function": "intersect_rect", "ray": {"origin": [0, 0, 0], "direction": [0, 0, 1]},
                                         "rect": WIDE, "window": ["-inf", "inf"], "expected": 5, "got": "NaN"},
     "the ray is a point"),
    ("rectangle, zero direction", {"function": "intersect_rect", "ray": {"origin": [0, 0, 0], "direction": [0, 0, 0]},
                                   "rect": WIDE, "window": [0, "inf"], "expected": None, "got": 1},
     "the direction is zero"),
    ("a unit sphere 1e30 away", sphere((0, 0, 0), (1, 0, 0), (0, "inf"), 1e30, None, (1e30, 0, 0), 1), None),
    ("NaN in the ray", sphere(("NaN", 0, 0), (1, 0, 0), (0, "inf"), None, 1), None),
    ("inf in the centre", sphere((0, 0, 0), (1, 0, 0), (0, "inf"), None, 1, ("inf", 0, 0)), None),
    ("rectangle axis 7", {"function": "intersect_rect", "ray": {"origin": [0, 0, 0], "direction": [0, 0, 1]},
                          "rect": dict(WIDE, axis=7), "window": [0, "inf"], "expected": None, "got": 5}, None),
    ("no ray", {"function": "sphere_roots", "expected": roots(0), "got": roots(0)}, None),
    ("a vector of 2", sphere((0, 0), (1, 0, 0), None, roots(0), roots(0)), None),
    ("text for a number", sphere((0, 0, "zero"), (1, 0, 0), None, roots(0), roots(0)), None),
    ("not an object", ["a", "list"], None),
]


def selftest_degenerate(ctx) -> str:
    folder = WORK / "degenerate"
    shutil.rmtree(folder, ignore_errors=True)
    drawn = refused = 0
    for name, figure, must_hold in DEGENERATE:
        path = folder / (picture.slug(name) + ".svg")
        try:
            summary = picture.write(figure, name, path)
        except picture.PictureError as e:
            expect(must_hold is None, f"{name}: refused ({e}), a picture was expected")
            expect(len(str(e)) > 10 and not path.exists(), f"{name}: refused without a reason, or left a file")
            refused += 1
            continue
        except Exception as e:  # the point of the check: name the crash
            raise Failed(f"picture.py crashed on '{name}': {type(e).__name__}: {e}")
        expect(must_hold is not None, f"{name}: drew a picture of input it should refuse")
        texts = " ".join(t for ts in labels(path).values() for t in ts)
        expect(must_hold in texts or must_hold in summary, f"{name}: the picture does not say {must_hold!r}")
        drawn += 1
    # The grading's side: a broken figure gives a case no picture and a reason, never an exception.

    class FakeCase:
        name, tier, status = "a case", "basic", "fail"
        figure = {"function": "sphere_roots", "ray": {"origin": ["NaN", 0, 0], "direction": [1, 0, 0]}}
        picture = picture_summary = ""

    class FakeResult:
        step = next(iter(load_steps()))
        cases = [FakeCase()]

    picture.draw_results([FakeResult()], folder / "results")
    expect(FakeResult.cases[0].picture == "" and FakeResult.cases[0].picture_summary.startswith("no picture:"),
           "draw_results on an unreadable figure does not say why there is no picture")
    return f"{drawn} degenerate figures drawn, {refused} refused with a reason, none crashed"


def selftest_gallery(ctx) -> str:
    for name, title, f in picture.PITFALLS:
        case = picture.Case(f)
        for t in case.expected["ts"]:
            p = case.point(t)
            if case.sphere is not None:
                centre, radius = case.sphere
                off = abs(picture.norm(picture.sub(p, centre)) - radius)
            else:
                axis, offset, lo, hi = case.rect
                u, v = [p[i] for i in range(3) if i != axis]
                off = abs(p[axis] - offset) + (0 if lo[0] <= u <= hi[0] and lo[1] <= v <= hi[1] else 1)
            expect(off < 1e-9, f"pitfall {name}: the expected t = {t} is not on the shape ({off} away)")
        expect(case.expected["ts"] != case.got["ts"], f"pitfall {name}: the wrong answer is the expected one")
        if case.window is not None:
            tmin, tmax = case.window
            inside = [t for t in case.expected["ts"] if tmin <= t <= tmax]
            expect(inside == case.expected["ts"], f"pitfall {name}: the expected t is outside its window")
    folder = WORK / "gallery"
    shutil.rmtree(folder, ignore_errors=True)
    paths = picture.write_gallery(folder)
    for p in paths:
        labels(p)
    page = (ROOT / "docs" / "pitfalls.md").read_text()
    shown = {p.name for p in paths}
    linked = set(re.findall(r"\]\(pitfalls/([^)\s]+\.svg)", page))
    expect(linked == shown, f"docs/pitfalls.md shows {sorted(linked)}, the table draws {sorted(shown)}")
    return f"{len(paths)} pitfalls drawn, their expected hits on the shapes, each shown in docs/pitfalls.md"


def selftests():
    return [("pictures: a failing case", selftest_failing_case),
            ("pictures: degenerate input", selftest_degenerate),
            ("pictures: the pitfall gallery", selftest_gallery)]

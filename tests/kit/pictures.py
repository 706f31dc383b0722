"""Self-test: the picture of a failing case (picture/, and the judge's figure behind it).

- a wrong step 01 (a mutant: the far root tried first) graded as a student's work: the failing case's
  SVG exists, parses as XML, and holds the expected t as a green label and the student's as a red one;
  the terminal shows it in characters too (picture.sketch: the origin o, E expected, X the answer);
  `./kit check` prints its path and --json carries it with its summary. The reference, graded the same
  way, leaves no picture behind (so the check cannot pass on stale files);
- picture/ on degenerate figures (a ray through the centre, a zero direction, an infinite tmax, NaN
  answers and inputs, huge numbers, garbage): a picture or a PictureError that says why, never a crash;
- the gallery of pitfalls (docs/pitfalls.md): every expected hit of the table lies on its shape, every
  picture is drawn, and the page shows each one;
- every picture the suite can produce (each sphere and rectangle case of steps 01-04 failed at its
  first check by a submission whose every answer is off, a float textbook step 02 whose ★ answers are
  a few ulps off, and the figures above): no two labels overlap, none leaves the picture or its
  panel; and the exact geometry: pbrt's far ray that misses is drawn outside the circle, and a
  note says in words what a fraction of a pixel cannot show.
"""

from __future__ import annotations

import json
import re
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from raykit import picture
from raykit.common import BUILD, ROOT, load_steps
from . import check
from .support import Failed, expect, kit, need_solutions
from .fixtures import fixture_dir

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
    r = kit("check", "1", "--steps", str(steps_dir), "--results", str(report))
    result = json.loads(report.read_text())["steps"][0] if report.is_file() else None
    return r, result


def selftest_failing_case(ctx) -> str:
    from raykit.mutants import MUTANTS, write_answer

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
    # The picture in characters too, under the case (a terminal with no picture viewer): the ray's row
    # holds the expected answer E and the student's X, inside the frame.
    sketch = [l for l in r.stdout.splitlines() if re.match(r"^\s+\|.*\|$", l)]
    expect(len(sketch) == picture.SKETCH_ROWS and any("E" in l and "X" in l and "o" in l for l in sketch)
           and "# the sphere" in r.stdout,
           f"./kit check 1 draws no picture in characters with o, E and X under the case:\n{r.stdout[-2500:]}")
    summary = case.get("picture_summary") or ""
    expect("expected a hit at t = 2" in summary and "got a hit at t = 4" in summary and "window [0, inf]" in summary,
           f"the picture's summary does not say what it shows: {summary!r}")
    found = labels(path)
    expect("t = 2" in found.get(picture.EXPECTED_COLOUR, []), f"{path}: no expected label 't = 2' (green)")
    expect("t = 4" in found.get(picture.GOT_COLOUR, []), f"{path}: no label of the answer 't = 4' (red)")
    expect(any(CASE in t for ts in found.values() for t in ts), f"{path}: its title does not name the case")
    drawn = sum(1 for c in result["cases"] if c.get("picture"))
    leaked = [c["name"] for c in result["cases"] if c["tier"] == "hidden" and c.get("picture")]
    expect(not leaked, "a hidden case's picture (its inputs) is shown without --reveal: " + ", ".join(leaked))
    # Checking another folder leaves the student's own pictures alone (each folder has its own).
    expect(path.resolve().is_relative_to(picture.pictures_folder(BUILD, wrong.parent).resolve()),
           f"./kit check --steps {wrong.parent} drew into {path.parent}, not that folder's own pictures folder")
    own = BUILD / "pictures" / "step01" / "the-students-own.svg"
    own.parent.mkdir(parents=True, exist_ok=True)
    own.write_text("<svg/>")
    # The reference graded in the same folder: every case passes, and no picture of the last run is left.
    right = wrong
    for f in step.files:
        shutil.copyfile(ROOT / "solutions" / step.folder / f, right / f)
    r2, result2 = grade_json(right.parent, WORK / "right.json")
    expect(own.is_file(), f"./kit check --steps DIR deleted {own}, a picture of the student's own steps")
    own.unlink()
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


@pytest.mark.quick
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
            raise Failed(f"picture/ crashed on '{name}': {type(e).__name__}: {e}")
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


@pytest.mark.quick
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


def label_problems(path: Path) -> list:
    """What is wrong with the labels of an SVG: two that overlap, one outside the picture, or outside
    the panel (clip rectangle) it is drawn in. Boxes from picture.text_box, the drawing's own measure."""
    root = ET.parse(path).getroot()
    width, height = float(root.get("width")), float(root.get("height"))
    clips = {c.get("id"): c.find(SVG + "rect") for c in root.iter(SVG + "clipPath")}
    boxes, problems = [], []

    def visit(node, clip, size):
        size = float(node.get("font-size", size))
        ref = re.fullmatch(r"url\(#(\w+)\)", node.get("clip-path", ""))
        if ref:
            r = clips[ref.group(1)]
            clip = (float(r.get("x")), float(r.get("y")), float(r.get("x")) + float(r.get("width")),
                    float(r.get("y")) + float(r.get("height")))
        if node.tag == SVG + "text":
            text = "".join(node.itertext())
            box = picture.text_box(float(node.get("x")), float(node.get("y")), text, size,
                                   node.get("text-anchor", "start"), node.get("font-weight") == "bold")
            frame = clip or (0, 0, width, height)
            if not (frame[0] <= box[0] and box[2] <= frame[2] and frame[1] <= box[1] and box[3] <= frame[3]):
                problems.append(f"{text!r} leaves {'its panel' if clip else 'the picture'}")
            for other, b in boxes:
                if picture.overlap(box, b):
                    problems.append(f"{text!r} overlaps {other!r}")
            boxes.append((text, box))
        for child in node:
            visit(child, clip, size)

    visit(root, None, 16.0)
    return problems


# A submission whose every answer is off: each sphere and rectangle case fails at its first check, so
# its figure is drawn. The reference's code with its functions renamed, and wrappers that move each
# answer: a root or hit 0.5 further, a miss made a hit at t = 1.
OFF_HEADERS = {"01": "raykit/unit_sphere.hpp", "02": "raykit/general_sphere.hpp",
               "03": "raykit/unit_direction.hpp", "04": "raykit/rect.hpp"}
OFF_WRAPPERS = {
    "Roots": "Roots r = reference_{name}({args}); if (r.count == 0) return Roots{{2, {{1.0f, 2.0f}}}}; "
             "r.t[0] += 0.5f; r.t[1] += 0.5f; return r;",
    "std::optional<float>": "const std::optional<float> h = reference_{name}({args}); "
                            "return h ? std::optional<float>(*h + 0.5f) : std::optional<float>(1.0f);",
}
# The textbook formula in float (a fixture: never in a handout): its ★ cases fail by a few ulps or a
# flipped count.


def write_off(folder: Path) -> None:
    """Steps 01-04 of the reference, every answer moved (OFF_WRAPPERS)."""
    for step in load_steps():
        if step.number not in OFF_HEADERS:
            continue
        functions = check.REMOTE_LINE.findall(check.remote_lines([step])[step.number])
        expect(bool(functions), f"CMake derives no function of step {step.number} (step.json's \"functions\")")
        text = [f'#include "{OFF_HEADERS[step.number]}"', "#include <optional>"]
        text += [f"#define {name} reference_{name}" for _, name, _, _ in functions]
        for f in step.files:
            text.append((ROOT / "solutions" / step.folder / f).read_text())
        text += [f"#undef {name}" for _, name, _, _ in functions]
        text.append("namespace raykit {")
        for ret, name, params, args in functions:
            text.append(f"{ret} {name}({params}) {{ {OFF_WRAPPERS[ret].format(name=name, args=args)} }}")
        text.append("}  // namespace raykit")
        out = folder / step.folder / step.files[0]
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text("\n".join(text) + "\n")


def far_miss_figure() -> dict:
    """pbrt's far ray that misses the tiny sphere by 6.5e-6 (tests/02_general_sphere/test_robust.cpp),
    the float inputs as the judge sends them: their shortest text."""
    return sphere((30000, -40000, 120000), (-30000.008, 40000.01, -120000.01), None, roots(0),
                  roots(1, 0.9999999, 0.9999999), (0, 0, 0), 0.01)


def selftest_labels(ctx) -> str:
    need_solutions()
    folder = WORK / "labels"
    shutil.rmtree(folder, ignore_errors=True)
    # The exact geometry first: the miss drawn as a miss, the thin gap said in words.
    case = picture.Case(far_miss_figure())
    x, y, y2 = picture.line_and_centre(case.origin, case.direction, case.sphere[0])
    radius = case.sphere[1]
    expect(y > radius and y2 > picture.Fraction(radius) ** 2,
           f"pbrt's far miss: the line is drawn {y!r} from the centre, inside the radius {radius!r}")
    path = folder / "far-miss.svg"
    summary = picture.write(far_miss_figure(), "far miss", path)
    texts = " ".join(t for ts in labels(path).values() for t in ts)
    expect("outside the radius: it misses" in texts, f"{path}: no note that the ray misses by less than a pixel")
    expect("expected no roots, got 1 root: t = 0.9999999" in summary, f"the far miss's caption: {summary!r}")
    # Every picture the kit draws: the degenerate figures, the gallery, and the suite's cases.
    pictures = [path]
    for name, figure, must_hold in DEGENERATE:
        if must_hold is not None:
            p = folder / "degenerate" / (picture.slug(name) + ".svg")
            picture.write(figure, name, p)
            pictures.append(p)
    pictures += picture.write_gallery(folder / "gallery")
    off, textbook = folder / "off", folder / "textbook"
    write_off(off)
    (textbook / "02_general_sphere").mkdir(parents=True)
    shutil.copyfile(fixture_dir("textbook/02_general_sphere/general_sphere.cpp"), textbook / "02_general_sphere" / "general_sphere.cpp")
    drawn = {}
    for steps_dir, numbers in ((off, ["1", "2", "3", "4"]), (textbook, ["2"])):
        report = folder / f"{steps_dir.name}.json"
        r = kit("check", *numbers, "--steps", str(steps_dir), "--reveal", "--results", str(report))
        expect(report.is_file(), f"./kit check {' '.join(numbers)} --steps {steps_dir}: no JSON (exit "
               f"{r.returncode}): {r.stdout[-800:]}{r.stderr[-800:]}")
        cases = [c for s in json.loads(report.read_text())["steps"] for c in s["cases"]]
        failed_figures = [c for c in cases if c.get("picture_summary") and not c.get("picture")
                          and not re.search(r"holds NaN or inf|axis is not 0, 1 or 2", c["picture_summary"])]
        expect(not failed_figures, "a case's figure was not drawn: " + "; ".join(
            f"{c['name']}: {c['picture_summary']}" for c in failed_figures[:3]))
        drawn[steps_dir.name] = [Path(c["picture"]) for c in cases if c.get("picture")]
        pictures += drawn[steps_dir.name]
    expect(len(drawn["off"]) >= 40, f"the all-wrong submission drew {len(drawn['off'])} pictures, not one per "
           "sphere and rectangle case")
    expect(all(str(picture.pictures_folder(BUILD, off)) in str(p) for p in drawn["off"]),
           "./kit check --steps DIR does not draw into DIR's own pictures folder")
    problems = [f"{p.name}: {why}" for p in pictures for why in label_problems(p)]
    expect(not problems, f"{len(problems)} label problem(s): " + "; ".join(problems[:6]))
    return (f"{len(pictures)} pictures ({len(drawn['off'])} of an all-wrong steps 01-04, {len(drawn['textbook'])} "
            "of a float textbook step 02): no label overlaps another or leaves its panel; pbrt's far miss "
            "drawn outside the circle, its 0.1-pixel gap said in words")

"""./kit docs: the course as a website that reads offline.

Doxygen turns the shared headers (the API reference), the lectures, the step
tasks and the benchmark's reading into HTML; this module writes the front page
(the course's table of contents, from tests/NN_topic/step.json) and finishes
the pages Doxygen leaves network-dependent:
- formulas: MathJax 3, pinned in docs/package.json, installed once with npm
  into build/docs/npm and copied next to the pages;
- Doxygen 1.9.4 adds a <script> from polyfill.io to every page: removed;
- SVG figures come out as <object>, and figures without alt text: rewritten as
  <img> with the caption as alt text.

The student site never reads solutions/; `--instructor` builds a second site
with one more page that lists them.

Layout: build/docs/student/html/index.html, build/docs/instructor/html/index.html.
"""

from __future__ import annotations

import html
import json
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

from raykit import picture
from ..decks import build as build_decks
from raykit.common import BUILD, ROOT, KitError, Step, load_steps, say
from ..webtools import copy_parts, ensure_docs_tools, npm_package, page_id, swap_in
from raykit.status import FAILED, OK

DOCS = ROOT / "docs"
OUT = BUILD / "docs"
AWESOME = Path("/usr/share/doxygen-awesome-css")
# What the pages load of MathJax: the TeX-to-SVG bundle, the TeX extensions it
# loads on demand (\color, \cancel, ...) and its menu. Nothing else is needed.
MATHJAX_FILES = ["es5/tex-svg.js", "es5/input/tex/extensions", "es5/ui"]
IMAGE_SUFFIXES = (".png", ".svg", ".jpg", ".jpeg")
PITFALLS_PAGE = DOCS / "pitfalls.md"     # its pictures are drawn at each build (picture.PITFALLS)
LAB = DOCS / "lab"                      # the ray-sphere lab, copied into the site as lab/ (not its check/)
SLIDES = ROOT / "lectures" / "slides"   # the decks, built into the site as slides/ (kitlib/decks.py)
# Links the lectures and task pages make to the lab and the decks, as the site's pages reach them.
SITE_LINKS = [(re.compile(r'href="(?:\.\./)+docs/lab/index\.html"'), 'href="lab/index.html"'),
              (re.compile(r'href="(?:\.\./)*(?:lectures/)?slides/(\d\d-[\w-]+)\.md"'), r'href="slides/\1.html"')]


# --- what the site is made of ---------------------------------------------------------

def title_of(path: Path, fallback: str) -> str:
    """The Markdown file's first-level heading."""
    for line in path.read_text(encoding="utf-8", errors="replace").splitlines():
        m = re.match(r"#\s+(.+?)\s*(\{#[^}]*\})?\s*#*\s*$", line)
        if m:
            return m.group(1)
        if line.strip():
            break
    return fallback


def images_in(folder: Path) -> list[Path]:
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES and p.is_file())


@dataclass
class StepPages:
    step: Step
    lecture: Path | None        # lectures/NN-topic.md, when written
    task: Path | None           # steps/NN_topic/README.md, when written
    image: Path | None          # the reference render: step.json "image", its first scene, NN*.png or <topic>.png
    headers: dict[str, str]     # function -> header that declares it


@dataclass
class Content:
    steps: list[StepPages]
    other_lectures: list[Path]
    headers: list[Path]
    images: list[Path]
    bench_readings: list[Path]
    bench_plots: list[Path]
    solutions: list[Path] = field(default_factory=list)   # instructor build only

    def summary(self) -> str:
        parts = [f"{len(self.steps)} steps",
                 f"{sum(s.lecture is not None for s in self.steps) + len(self.other_lectures)} lectures",
                 f"{sum(s.task is not None for s in self.steps)} tasks",
                 f"API of {len(self.headers)} headers", f"{len(self.images)} images",
                 "benchmark" if self.bench_readings or self.bench_plots else "no benchmark yet"]
        if self.solutions:
            parts.append(f"{len(self.solutions)} solution files")
        return ", ".join(parts)


def is_step_image(image: Path, step: Step) -> bool:
    """docs/images/NN-anything.png, or named after the step's folder or topic (rectangles.png)."""
    stem = image.stem.replace("-", "_")
    return bool(re.match(rf"{step.number}(?!\d)", stem)) or stem in (step.folder, step.folder[3:])


def declaring_header(function: str, headers: list[Path]) -> str | None:
    """The header that declares `function` (comments that merely name it do not count)."""
    pattern = re.compile(rf"\b{re.escape(function)}\s*\(")
    for h in headers:
        code = re.sub(r"//.*", "", h.read_text(encoding="utf-8", errors="replace"))
        if pattern.search(code):
            return h.relative_to(ROOT / "include").as_posix()
    return None


def gather(instructor: bool) -> Content:
    """Finds what exists today: any lecture, task, image or reading may still be missing."""
    headers = sorted((ROOT / "include" / "raykit").glob("*.hpp"))
    images = images_in(DOCS / "images")
    steps, used = [], set()
    for s in load_steps():
        lecture = ROOT / s.lecture
        task = ROOT / "steps" / s.folder / "README.md"
        manifest = json.loads((ROOT / "tests" / s.folder / "step.json").read_text())
        # The picture named in the manifest, else its first scene's render, else one named after the step.
        named = [manifest["image"]] if manifest.get("image") else []
        named += [f"{sc['name']}.png" for sc in manifest.get("scenes", [])[:1]]
        named = [DOCS / "images" / n for n in named if (DOCS / "images" / n).is_file()]
        image = named[0] if named else next((p for p in images if is_step_image(p, s)), None)
        steps.append(StepPages(s, lecture if lecture.is_file() else None, task if task.is_file() else None,
                               image, {f: declaring_header(f, headers) for f in s.functions}))
        used.add(lecture.resolve())
    others = [p for p in sorted((ROOT / "lectures").glob("*.md")) if p.resolve() not in used]
    bench = DOCS / "bench"
    solutions = [p for s in load_steps() for p in (ROOT / "solutions" / s.folder / f for f in s.files)
                 if instructor and p.is_file()]
    # The benchmark's reading (docs/bench.md, which the lectures cite) first, then its generated table.
    readings = [p for p in [DOCS / "bench.md"] if p.is_file()] + (sorted(bench.glob("*.md")) if bench.is_dir() else [])
    return Content(steps, others, headers, images, readings, images_in(bench), solutions)


# --- the generated pages -----------------------------------------------------------

def brief_of(header: Path) -> str:
    m = re.search(r"^///\s*\\brief\s+(.+)$", header.read_text(encoding="utf-8", errors="replace"), re.M)
    return m.group(1).strip() if m else ""


def label(text: str) -> str:
    """Text for \\ref name "text", which ends at the next double quote."""
    return text.replace('"', "'")


def front_page(c: Content, instructor: bool) -> str:
    """The course's table of contents, in Doxygen Markdown."""
    out = [
        "raykit: a first course in ray tracing {#mainpage}",
        "======================================",
        "",
        "From one ray and one sphere to an empty Cornell box, one step at a time. Each step has a "
        "lecture to read, a task that says what to write, and tests that grade it: edit the step's "
        "file, then run `./kit check N`, which also names the lecture section to reread when a "
        "case fails.",
        "",
    ]
    if instructor:
        out += ["\\note Instructor edition: this site shows the reference solutions "
                "(\\ref solutions \"Solutions\"). Give students the site that `./kit docs` writes "
                "without `--instructor`.", ""]
    out += ["## The steps", ""]
    for sp in c.steps:
        s = sp.step
        out += [f"### Step {s.number}: {s.title}", ""]
        out.append(f"- **Lecture:** \\ref {page_id(sp.lecture)} \"{label(title_of(sp.lecture, s.title))}\""
                   if sp.lecture else f"- **Lecture:** not written yet (`{s.lecture}`)")
        out.append(f"- **Task:** \\ref {page_id(sp.task)} \"steps/{s.folder}/README.md\": what to write, in which "
                   "order, how to check it" if sp.task else
                   f"- **Task:** `steps/{s.folder}/README.md` (not written yet)")
        files = ", ".join(f"`steps/{s.folder}/{f}`" for f in s.files)
        where = sorted({h for h in sp.headers.values() if h})
        declared = f", declared in {', '.join(f'`{h}`' for h in where)}" if where else ""
        fns = ", ".join(f"\\ref raykit::{f} \"{f}()\"" for f in s.functions)
        out.append(f"- **Write:** {fns} in {files}{declared}" if s.functions else f"- **Write:** {files}")
        if s.needs:
            out.append(f"- **Builds on:** step {', step '.join(s.needs)}")
        out += [f"- **Check:** `./kit check {int(s.number)}`", ""]
        if sp.image:
            out += [f"\\image html {sp.image.name} \"Step {s.number}: the reference image\" width=360px", ""]
    if c.other_lectures:
        out += ["## More lectures", ""]
        out += [f"- \\ref {page_id(p)} \"{label(title_of(p, p.stem))}\"" for p in c.other_lectures]
        out.append("")
    if PITFALLS_PAGE.is_file():
        out += ["## Classic pitfalls, drawn", "",
                f"- \\ref {page_id(PITFALLS_PAGE)} \"{label(title_of(PITFALLS_PAGE, 'Classic pitfalls'))}\": "
                "a tangent, an origin inside, a sphere behind, the window's ends, a ray parallel to a "
                "rectangle, drawn the way `./kit check` draws a failing case", ""]
    if LAB.is_dir() or SLIDES.is_dir():
        out += ["## Play and present", ""]
        if LAB.is_dir():
            out.append('- <a href="lab/index.html">The ray–sphere lab</a>: drag the ray and the sphere (or type '
                       "them, or move them with the arrow keys) and watch the roots, the window and lecture 03's "
                       "figure; every formula in float32 and in double, with its error in ulps against the exact "
                       "roots; presets from the graded cases")
        if SLIDES.is_dir():
            out.append('- <a href="slides/index.html">The slide decks</a>: one per lecture, for presenting '
                       "(S shows the speaker notes); `./kit slides --pdf` also prints them")
        out.append("")
    out += ["## The API", "",
            "Every type and function a step uses or asks you to write, with its contract: units, "
            "preconditions, the closed window \\f$t_\\min \\le t \\le t_\\max\\f$, what a tangent "
            "returns. The headers are in `include/raykit/`; read them, do not edit them.", ""]
    for h in c.headers:
        out.append(f"- \\ref {h.name} \"raykit/{h.name}\": {brief_of(h)}")
    out += ["", "All of it on one page: the namespace \\ref raykit.", ""]
    if c.bench_readings or c.bench_plots:
        out += ["## The benchmark", ""]
        out += [f"- \\ref {page_id(p)} \"{label(title_of(p, 'Benchmark'))}\"" for p in c.bench_readings]
        out.append("")
        for p in c.bench_plots:
            out += [f"\\image html {p.name} \"The benchmark's plot\" width=640px", ""]
    if c.images:
        out += ["## Rendered images", "", "All of them on one page: \\ref rendered_images.", ""]
    if instructor:
        out += ["## For instructors", "", "- \\ref solutions", ""]
    return "\n".join(out) + "\n"


def images_page(c: Content) -> str:
    out = ["Rendered images {#rendered_images}", "===============", "",
           "The images the kit renders with the reference solutions: what a finished step draws.", ""]
    for p in c.images:
        out += [f"\\image html {p.name} \"{p.stem}\"", ""]
    return "\n".join(out) + "\n"


def solutions_page(c: Content) -> str:
    out = ["Solutions {#solutions}", "=========", "",
           "The reference solutions, for instructors. The student site does not have this page.", ""]
    for p in c.solutions:
        rel = p.relative_to(ROOT / "solutions").as_posix()
        out += [f"## solutions/{rel}", "", f"\\include {rel}", ""]
    return "\n".join(out) + "\n"


NAMESPACE_DOC = """/// \\namespace raykit
/// \\brief Everything the course declares: rays, roots, spheres, the functions
/// a student writes and the stub marker. All in `include/raykit/`.
"""


# --- running Doxygen -------------------------------------------------------------

def mathjax_root() -> Path:
    """The MathJax package, installed once into build/docs/npm at the version docs/package-lock.json pins."""
    return npm_package("mathjax", "es5/tex-svg.js", "typesets the formulas")


def doxyfile(out: Path, gen: Path, c: Content, instructor: bool) -> str:
    def q(p: Path | str) -> str:
        return '"' + str(p).replace('"', '\\"') + '"'

    # The side bar lists the pages in this order: each step's lecture and task, then the rest.
    inputs = [ROOT / "include" / "raykit", gen / "namespace.dox", gen / "index.md"]
    for sp in c.steps:
        inputs += [p for p in (sp.lecture, sp.task) if p]
    inputs += c.other_lectures + c.bench_readings
    if PITFALLS_PAGE.is_file():
        inputs.append(PITFALLS_PAGE)
    inputs += [p for p in (gen / "images.md", gen / "solutions.md") if p.is_file()]
    image_path = [p for p in (ROOT / "lectures" / "figures", DOCS / "images", DOCS / "bench", gen / "pitfalls")
                  if p.is_dir()]
    styles = [AWESOME / "doxygen-awesome.css", AWESOME / "doxygen-awesome-sidebar-only.css",
              DOCS / "raykit.css"]
    values = {
        "ROOT": str(ROOT), "OUTPUT": str(out), "PYTHON": sys.executable,
        "BRIEF": "Ray tracing, first lecture" + (" (instructor edition)" if instructor else ""),
        "INPUT": " ".join(q(p) for p in inputs),
        "IMAGE_PATH": " ".join(q(p) for p in image_path),
        "EXAMPLE_PATH": q(ROOT / "solutions") if instructor else "",
        "WARN_LOGFILE": str(out / "warnings.log"),
        "STYLESHEETS": " ".join(q(p) for p in styles if p.is_file()),
    }
    text = (DOCS / "Doxyfile.in").read_text()
    for k, v in values.items():
        text = text.replace(f"@{k}@", v)
    left = re.findall(r"@[A-Z_]+@", text)
    if left:
        raise KitError(f"docs/Doxyfile.in: no value for {', '.join(sorted(set(left)))}", FAILED)
    return text


# --- finishing the pages --------------------------------------------------------

POLYFILL = re.compile(r'[ \t]*<script[^>]*src="https?://[^"]*polyfill[^"]*"[^>]*>\s*</script>\n?')
SVG_OBJECT = re.compile(
    r'<object type="image/svg\+xml" data="([^"]+)"([^>]*)>\s*</object>(\s*<div class="caption">\s*(.*?)\s*</div>)?',
    re.S)
SIZE = re.compile(r'\s(?:width|height)="[^"]*"')


IMG_WITHOUT_ALT = re.compile(r'<img src="([^"]+)" alt=""([^>]*)/>(\s*<div class="caption">\s*(.*?)\s*</div>)', re.S)


def alt_text(caption: str) -> str:
    return html.escape(re.sub(r"<[^>]+>", "", html.unescape(caption)), quote=True)


def svg_as_img(m: re.Match) -> str:
    size = "".join(SIZE.findall(m.group(2)))
    return f'<img src="{m.group(1)}" alt="{alt_text(m.group(4) or "")}"{size}/>' + (m.group(3) or "")


def caption_as_alt(m: re.Match) -> str:
    return f'<img src="{m.group(1)}" alt="{alt_text(m.group(4))}"{m.group(2)}/>' + m.group(3)


def finish_html(site: Path, mathjax: Path) -> None:
    for page in site.glob("*.html"):
        text = page.read_text(encoding="utf-8")
        # Figures get their caption as alt text, for screen readers and broken links.
        new = IMG_WITHOUT_ALT.sub(caption_as_alt, SVG_OBJECT.sub(svg_as_img, POLYFILL.sub("", text)))
        for pattern, target in SITE_LINKS:
            new = pattern.sub(target, new)
        if new != text:
            page.write_text(new, encoding="utf-8")
    copy_parts(mathjax, MATHJAX_FILES, site / "mathjax")


@dataclass
class Site:
    variant: str            # student or instructor
    html: Path              # the folder with index.html
    warnings: list[str]
    content: Content

    @property
    def index(self) -> Path:
        return self.html / "index.html"


def build_site(instructor: bool = False) -> Site:
    """Writes the site into build/docs/<variant>/; the old one is replaced only when the new one is whole."""
    if instructor and not (ROOT / "solutions").is_dir():
        raise KitError("--instructor: this copy of the kit has no solutions/ folder (a student handout?)")
    ensure_docs_tools()
    variant = "instructor" if instructor else "student"
    content = gather(instructor)
    mathjax = mathjax_root()
    final = OUT / variant
    work = OUT / f"{variant}.new"
    shutil.rmtree(work, ignore_errors=True)
    gen = work / "pages"
    gen.mkdir(parents=True)
    (gen / "index.md").write_text(front_page(content, instructor), encoding="utf-8")
    (gen / "namespace.dox").write_text(NAMESPACE_DOC, encoding="utf-8")
    if PITFALLS_PAGE.is_file():
        picture.write_gallery(gen / "pitfalls")
    if content.images:
        (gen / "images.md").write_text(images_page(content), encoding="utf-8")
    if instructor:
        (gen / "solutions.md").write_text(solutions_page(content), encoding="utf-8")
    try:
        (work / "Doxyfile").write_text(doxyfile(work, gen, content, instructor), encoding="utf-8")
        r = subprocess.run(["doxygen", str(work / "Doxyfile")], cwd=ROOT, capture_output=True, text=True)
        log = work / "warnings.log"
        warnings = [l for l in (log.read_text(errors="replace").splitlines() if log.is_file() else [])
                    if l.strip()]
        if r.returncode != 0 or not (work / "html" / "index.html").is_file():
            raise KitError("doxygen failed:\n" + "\n".join((r.stdout + r.stderr).splitlines()[-20:]
                                                            + warnings[:20]), FAILED)
        finish_html(work / "html", mathjax)
        if LAB.is_dir():
            shutil.copytree(LAB, work / "html" / "lab", ignore=shutil.ignore_patterns("check"))
        if SLIDES.is_dir():
            build_decks(work / "html" / "slides")
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    swap_in(work, final)
    doxyfile_run = final / "Doxyfile"      # kept to rerun by hand: say where things are now
    doxyfile_run.write_text(doxyfile_run.read_text().replace(str(work), str(final)))
    # Doxygen repeats some warnings (once per page that shows the member): each once.
    warnings = list(dict.fromkeys(w.replace(str(work), str(final)).replace(str(ROOT) + "/", "")
                                  for w in warnings))
    return Site(variant, final / "html", warnings, content)


# --- the command ---------------------------------------------------------------------



def register(p) -> None:
    p.add_argument("--instructor", action="store_true",
                   help="the instructor's site: also the reference solutions (never give it to students)")
    p.add_argument("--strict", action="store_true",
                   help="exit 1 when Doxygen warns (an undocumented declaration, a broken reference)")


def rel(path: Path) -> str:
    try:
        return os.path.relpath(path)
    except ValueError:
        return str(path)


def run(args) -> int:
    site = build_site(instructor=args.instructor)
    say(f"raykit docs ({site.variant}): {site.content.summary()}")
    if site.warnings:
        say(f"Doxygen warned {len(site.warnings)} time(s):")
        for w in site.warnings[:20]:
            say(f"  {w}")
    say(f"Open {rel(site.index)} in a browser; it reads offline.")
    return FAILED if args.strict and site.warnings else OK

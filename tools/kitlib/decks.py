"""./kit slides: a slide deck per lecture, from lectures/slides/NN-*.md, as offline HTML (and PDF).

The decks are Markdown kept beside the lectures. A deck is slides separated by a line `---`; a slide's
speaker notes start at a line `Note:` and run to its end. reveal.js's markdown plugin turns it into
slides (headings, paragraphs, lists, tables, fenced code, `**bold**`, `*em*`, `code`, links); this module
does what the plugin lacks: formulas as `$...$` and `$$...$$` (typeset by MathJax 3, offline), a figure
on a line of its own (`![alt](../figures/x.svg)`, copied beside the deck), the first slide as the title,
and step-by-step reveals (reveal.js fragments): a list item written `+ ...` instead of `- ...`, and a
display formula written `+$$...$$`, appear one at a time. A link to the ray-sphere lab
(`../../docs/lab/index.html#preset`) is checked to exist and points at the copy of the lab the deck
folder carries (`lab/`), so a deck opens the lab on that preset offline.

The deck runs on reveal.js, pinned with MathJax in docs/package.json and installed by npm into
build/docs/npm once (as ./kit docs does); both are copied next to the decks, so the folder reads offline
and can be zipped or put on a course page. Layout: build/slides/index.html, build/slides/NN-topic.html,
and with --pdf build/slides/NN-topic.pdf (headless Chromium prints reveal.js's print view, one page
a slide, 1280x720). Keys in a deck: arrows, S for the speaker view with the notes, F full screen.
"""

from __future__ import annotations

import html
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

from raykit import atomic
from raykit.common import BUILD, ROOT, KitError
from raykit.status import FAILED, SETUP, USAGE
from .webtools import copy_parts, ensure_docs_tools, npm_package, swap_in

SOURCES = ROOT / "lectures" / "slides"
OUT = BUILD / "slides"
WIDTH, HEIGHT = 1280, 720
REVEAL_FILES = ["dist/reveal.css", "dist/reset.css", "dist/reveal.js", "dist/theme/white.css",
                "dist/plugin/notes.js", "dist/plugin/markdown.js", "LICENSE"]
MATHJAX_FILES = ["es5/tex-svg.js", "es5/input/tex/extensions", "LICENSE"]


# --- Markdown, the subset the decks use ----------------------------------------------------------------

@dataclass
class Slide:
    body: list[str]         # Markdown lines
    notes: str              # the speaker notes, one paragraph
    title: bool             # the first slide


def split_deck(text: str) -> list[Slide]:
    chunks, current, fence = [], [], False
    for line in text.splitlines():
        if line.startswith("```"):
            fence = not fence
        if line.strip() == "---" and not fence:
            chunks.append(current)
            current = []
        else:
            current.append(line)
    chunks.append(current)
    slides = []
    for i, chunk in enumerate(chunks):
        body, notes, in_notes = [], [], False
        for line in chunk:
            if line.startswith("Note:"):
                in_notes = True
                line = line[len("Note:"):]
            (notes if in_notes else body).append(line)
        slides.append(Slide(body, " ".join(l.strip() for l in notes if l.strip()), i == 0))
    return [s for s in slides if any(l.strip() for l in s.body)]


MATH = re.compile(r"\$\$(.+?)\$\$|\$(?!\s)([^$\n]+?)(?<!\s)\$", re.S)
LINK = re.compile(r"\[([^\]]+)\]\(([^)\s]+)\)")
LAB = ROOT / "docs" / "lab"
LAB_LINK = re.compile(r"^(?:\.\./)+docs/lab/index\.html(#[\w-]+)?$")


def link_target(url: str) -> str:
    """A deck's link as the built deck reaches it: the lab's copy beside the decks, anything else as it is."""
    m = LAB_LINK.match(url)
    return f"lab/index.html{m.group(1) or ''}" if m else url



IMAGE = re.compile(r"!\[([^\]]*)\]\(([^)\s]+)\)\s*$")
FRAGMENT = re.compile(r"^(\s*)(\+|\d+\.\+)\s+")       # `+ item`, `1.+ item`: shown one at a time
# The plugin's own mark (`<!-- .element: class="fragment" -->`) cannot serve: at an item's start marked
# reads it as a block of HTML (the item's Markdown left unread), at its end it lands on the item's last
# inline element (a <strong>, a <code>). So an empty <span> marks the item, and the deck's script makes
# it the item's class.
FRAGMENT_MARK = '<span class="fragment-item"></span>'


def as_text(tex: str) -> str:
    """A formula with its delimiters, every sign as an HTML character reference: the markdown plugin
    (marked) reads it as plain text (no emphasis, no escapes, no table cell ends), the browser shows
    it as written, and MathJax typesets it."""
    return "".join(c if c.isalnum() or c == " " else f"&#{ord(c)};" for c in tex)


def formulas(text: str) -> str:
    r"""A line's `$...$` and `$$...$$` as \(...\) and \[...\], shielded from the plugin; code spans kept."""
    parts = re.split(r"(`[^`]+`)", text)
    return "".join(p if p.startswith("`") else MATH.sub(
        lambda m: as_text(r"\[" + m.group(1) + r"\]") if m.group(1) is not None else as_text(r"\(" + m.group(2) + r"\)"),
        LINK.sub(lambda m: f"[{m.group(1)}]({link_target(m.group(2))})", p)) for p in parts)


def slide_class(slide: Slide) -> str:
    """The title, a Ponder slide (its question large), or a figure alone (drawn large, for legible
    labels)."""
    if slide.title:
        return "title"
    shown = [l.strip() for l in slide.body if l.strip()]
    heading = next((l for l in shown if l.startswith("#")), "")
    if re.match(r"##\s+Ponder\b", heading):
        return "ponder"
    rest = [l for l in shown if not l.startswith("#")]
    return "figure-only" if len(rest) == 1 and IMAGE.match(rest[0]) else ""


def plugin_markdown(slide: Slide, media: dict[str, Path], source: Path) -> str:
    """A slide as reveal.js's markdown plugin reads it, with what the plugin lacks done here: formulas
    shielded (formulas()), `+` items and `+$$` formulas as fragments, a figure on a line of its own
    copied beside the deck (noted in `media`, name -> file) and shown as a <figure>, the lab's links
    pointed at its copy beside the decks, the slide's class."""
    out, i, lines = [], 0, slide.body
    cls = slide_class(slide)
    if cls:
        out.append(f'<!-- .slide: class="{cls}" -->')
    while i < len(lines):
        line, s = lines[i], lines[i].strip()
        if s.startswith("```"):             # a code block, as it is
            out.append(line)
            i += 1
            while i < len(lines) and not lines[i].strip().startswith("```"):
                if lines[i].strip() == "---":
                    raise KitError(f"{source.relative_to(ROOT)}: a line --- in a code block would end the slide", FAILED)
                out.append(lines[i])
                i += 1
            if i < len(lines):
                out.append(lines[i])
        elif s.startswith("$$") or s.startswith("+$$"):      # a display formula, on lines of its own
            frag = s.startswith("+")
            s = s.lstrip("+")
            formula = [s]
            while not (formula[-1].endswith("$$") and (len(formula) > 1 or len(s) > 2)) and i + 1 < len(lines):
                i += 1
                formula.append(lines[i].strip())
            out += ["", f'<div class="display{" fragment" if frag else ""}">{formulas(" ".join(formula))}</div>', ""]
        elif m := IMAGE.match(s):
            src = (source.parent / m.group(2)).resolve()
            if not src.is_file():
                raise KitError(f"{source.relative_to(ROOT)}: the figure {m.group(2)} does not exist", FAILED)
            media[src.name] = src
            out += ["", f'<figure><img src="media/{html.escape(src.name, quote=True)}" '
                        f'alt="{html.escape(m.group(1), quote=True)}"></figure>', ""]
        elif m := FRAGMENT.match(line):
            bullet = "-" if m.group(2) == "+" else m.group(2)[:-1]
            out.append(f"{m.group(1)}{bullet} {FRAGMENT_MARK}{formulas(line[m.end():])}")
        else:
            out.append(formulas(line))
        i += 1
    if slide.notes:
        out += ["", "Note: " + formulas(slide.notes)]
    return "\n".join(out)


# --- the decks -----------------------------------------------------------------------------------------

STYLE = """
.reveal { font-size: 40px; }
.reveal .slides section { padding: 0 24px; box-sizing: border-box; }
.reveal h1 { font-size: 1.9em; text-transform: none; }
.reveal h2 { font-size: 1.35em; text-transform: none; margin-bottom: 0.6em; }
.reveal h1, .reveal h2, .reveal h3 { font-family: sans-serif; letter-spacing: 0; }
.reveal .slides section { text-align: left; }
.reveal .slides section.title { text-align: center; }
.reveal ul, .reveal ol { display: block; margin-left: 1.2em; }
.reveal li { margin: 0.25em 0; }
.reveal table { font-size: 0.8em; margin: 0.4em 0; }
.reveal figure { margin: 0; text-align: center; }
.reveal figure img { height: 420px; max-width: 100%; object-fit: contain; margin: 0; background: #fff; }
.reveal .display { margin: 0.5em 0; text-align: center; }
.reveal code { font-size: 0.9em; background: #f2f2f2; padding: 0 0.15em; }
.reveal .ponder h2 { color: #b0302a; }
.reveal .ponder p { font-size: 1.25em; margin-top: 1.2em; }
.reveal .slide-number { font-size: 22px; left: 8px; right: auto; }
.reveal pre { font-size: 0.62em; width: 100%; box-shadow: none; margin: 0.3em 0; }
.reveal pre code { max-height: none; padding: 0.4em 0.6em; line-height: 1.3; }
.reveal a { color: #1a5fb4; text-decoration: underline; }
.reveal .lab { font-size: 0.7em; }
.reveal section.figure-only figure img { height: 560px; }
"""


def deck_html(title: str, slides: list[Slide], media: dict[str, Path], source: Path) -> str:
    """The deck: its slides in one Markdown section that reveal.js's markdown plugin splits at the lines
    `---` and at `Note:`, MathJax typesetting the slides after the plugin and before reveal.js lays them
    out (reveal.js starts its plugins one after the other, in the order given)."""
    text = "\n\n---\n\n".join(plugin_markdown(s, media, source) for s in slides)
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{html.escape(title)}</title>
<link rel="stylesheet" href="reveal/dist/reset.css">
<link rel="stylesheet" href="reveal/dist/reveal.css">
<link rel="stylesheet" href="reveal/dist/theme/white.css">
<style>{STYLE}</style>
</head>
<body>
<div class="reveal"><div class="slides">
<section data-markdown data-separator="^---$" data-separator-notes="^Note:"><textarea data-template>
{html.escape(text, quote=False)}
</textarea></section>
</div></div>
<script src="reveal/dist/reveal.js"></script>
<script src="reveal/dist/plugin/markdown.js"></script>
<script src="reveal/dist/plugin/notes.js"></script>
<script>
window.MathJax = {{ tex: {{ inlineMath: [["\\\\(", "\\\\)"]], displayMath: [["\\\\[", "\\\\]"]] }},
                   svg: {{ fontCache: "global" }}, startup: {{ typeset: false }} }};
</script>
<script src="mathjax/es5/tex-svg.js"></script>
<script>
// After the markdown plugin made the slides, before reveal.js lays them out (it sizes the slides with
// the formulas in them): the `+` items made fragments, the formulas typeset.
const Typeset = {{ id: "typeset", init: () => {{
  document.querySelectorAll("li > span.fragment-item:first-child").forEach(mark => {{
    mark.parentNode.classList.add("fragment");
    mark.remove();
  }});
  return MathJax.startup.promise.then(() => MathJax.typesetPromise());
}} }};
window.deckReady = Reveal.initialize({{ width: {WIDTH}, height: {HEIGHT}, margin: 0.04, hash: true,
  slideNumber: "c/t", center: true, transition: "none", pdfSeparateFragments: false,
  plugins: [RevealMarkdown, Typeset, RevealNotes] }});
</script>
</body>
</html>
"""


def index_html(decks: list[tuple[str, str]]) -> str:
    items = "\n".join(f'<li><a href="{html.escape(f)}">{html.escape(t)}</a>'
                      f'{f" (<a href={chr(34)}{html.escape(f[:-5])}.pdf{chr(34)}>PDF</a>)" if (OUT / (f[:-5] + ".pdf")).is_file() else ""}</li>'
                      for f, t in decks)
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>raykit: the slide decks</title>
<style>body {{ font-family: sans-serif; margin: 2em; max-width: 50em; }} li {{ margin: 0.4em 0; }}</style></head>
<body><h1>raykit: the slide decks</h1>
<p>One deck per lecture, for presenting. Keys: the arrows, <kbd>S</kbd> for the speaker view with the notes,
<kbd>F</kbd> for full screen, <kbd>Esc</kbd> for the overview. Everything here reads offline.</p>
<ul>
{items}
</ul></body></html>
"""


def deck_sources() -> list[Path]:
    return sorted(SOURCES.glob("[0-9][0-9]-*.md")) if SOURCES.is_dir() else []


def deck_title(slides: list[Slide], fallback: str) -> str:
    for line in slides[0].body if slides else []:
        m = re.match(r"#\s+(.+)", line.strip())
        if m:
            return re.sub(r"[*`$]", "", m.group(1))
    return fallback


def build(out: Path = OUT, sources: list[Path] | None = None) -> list[Path]:
    """Writes every deck (or those of `sources`) into `out` with reveal.js, MathJax and the figures beside
    them; the decks' paths."""
    sources = deck_sources() if sources is None else sources
    if not sources:
        raise KitError(f"no decks in {SOURCES.relative_to(ROOT)} (NN-topic.md)", USAGE)
    ensure_docs_tools()
    reveal = npm_package("reveal.js", "dist/reveal.js", "runs the slide decks")
    mathjax = npm_package("mathjax", "es5/tex-svg.js", "typesets the formulas")
    work = out.with_name(out.name + ".new")
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    try:
        media: dict[str, Path] = {}
        decks = []
        for src in sources:
            slides = split_deck(src.read_text(encoding="utf-8"))
            if not slides:
                raise KitError(f"{src.relative_to(ROOT)}: no slides", FAILED)
            title = deck_title(slides, src.stem)
            (work / f"{src.stem}.html").write_text(deck_html(title, slides, media, src), encoding="utf-8")
            decks.append((f"{src.stem}.html", title))
        for name, path in media.items():
            (work / "media").mkdir(exist_ok=True)
            shutil.copyfile(path, work / "media" / name)
        labs = [(src, lab) for src in sources for m in LINK.finditer(src.read_text(encoding="utf-8"))
                if (lab := LAB_LINK.match(m.group(2)))]
        for src, lab in labs:
            if not (LAB / "index.html").is_file():
                raise KitError(f"{src.relative_to(ROOT)}: links the lab, and docs/lab/index.html is missing", FAILED)
            if lab.group(1) and f'id: "{lab.group(1)[1:]}"' not in (LAB / "lab.js").read_text(encoding="utf-8"):
                raise KitError(f"{src.relative_to(ROOT)}: the lab has no preset {lab.group(1)[1:]}", FAILED)
        if labs:
            shutil.copytree(LAB, work / "lab", ignore=shutil.ignore_patterns("check"))
        copy_parts(reveal, REVEAL_FILES, work / "reveal")
        copy_parts(mathjax, MATHJAX_FILES, work / "mathjax")
        (work / "index.html").write_text(index_html(decks), encoding="utf-8")
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    swap_in(work, out)
    return [out / f for f, _ in decks]


def print_pdfs(decks: list[Path]) -> list[Path]:
    """Each deck printed by headless Chromium from reveal.js's print view: one 1280x720 page a slide.
    Over the DevTools protocol, once the deck's `deckReady` has settled: Chromium's --print-to-pdf prints
    when its virtual time runs out, ready or not (CONTRIBUTING, "The docs")."""
    from . import browser
    from raykit.packages import ensure_packages
    ensure_packages("browser")
    chromium = browser.find_chromium()
    if chromium is None:
        raise KitError("--pdf needs Chromium: sudo apt-get install chromium", SETUP)
    import base64
    written = []
    with browser.Browser(chromium, WIDTH, HEIGHT) as b:
        for deck in decks:
            b.open(deck.as_uri() + "?print-pdf")
            b.evaluate("window.deckReady.then(() => new Promise(r => setTimeout(r, 300)))", timeout=60)
            data = b.call("Page.printToPDF", session=True, timeout=120, printBackground=True,
                          paperWidth=WIDTH / 96, paperHeight=HEIGHT / 96, marginTop=0, marginBottom=0,
                          marginLeft=0, marginRight=0, preferCSSPageSize=True)["data"]
            pdf = deck.with_suffix(".pdf")
            atomic.write(pdf, base64.b64decode(data))
            written.append(pdf)
    return written



"""Self-test of ./kit slides: the decks of lectures/slides/ built and shown in headless Chromium.

- the decks' shape, read from the Markdown: every slide but the title has speaker notes that name a
  lecture and a section; a "Ponder" slide asks a question and the next slide is not another Ponder (the
  answer follows it); the last slide names the step's `./kit check N`;
- in Chromium at 1280x720, offline: every slide of every deck is shown, and every element of it must lie
  inside the slide's 1280x720 box, no element may scroll (a table or code wider than its box), MathJax
  must have typeset the formulas with no error and no raw TeX left; no console error, no request to
  the network. A screenshot of each slide lands in build/slides-screenshots/;
- the measure can fail: a deck with a slide too long for the box must be caught.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

from ..common import BUILD, ROOT, KitError
from .. import decks as cmd_slides
from ..packages import ensure_packages
from .harness import Failed, Skipped, expect

SCREENSHOTS = BUILD / "slides-screenshots"     # beside the decks: ./kit slides replaces build/slides whole

MEASURE = """(() => {
  const box = document.querySelector('.reveal .slides').getBoundingClientRect();
  const scale = Reveal.getScale();
  const s = Reveal.getCurrentSlide();
  const out = [];
  const r0 = s.getBoundingClientRect();
  for (const e of [s, ...s.querySelectorAll('*')]) {
    if (e.closest('aside.notes') || e.closest('mjx-assistive-mml')) continue;
    const r = e.getBoundingClientRect();
    if (r.width === 0 && r.height === 0) continue;
    const tag = e.tagName.toLowerCase() + (e.className && typeof e.className === 'string' ? '.' + e.className : '');
    if (r.left < box.left - 1 || r.right > box.right + 1 || r.top < box.top - 1 || r.bottom > box.bottom + 1)
      out.push(`${tag} reaches outside the slide (${Math.round((r.bottom - box.top) / scale)} px down, ` +
               `${Math.round((r.right - box.left) / scale)} px across, of 1280x720)`);
    if (!['svg', 'mjx-container'].includes(e.tagName.toLowerCase()) && e.tagName !== 'SECTION' &&
        (e.scrollWidth > e.clientWidth + 2 && getComputedStyle(e).overflowX !== 'visible'))
      out.push(`${tag} scrolls sideways`);
  }
  const text = s.innerText;
  const raw = (text.match(/\\\\\\(|\\\\\\[|\\$[^$\\s]/g) || []).length;
  return { problems: out, math: s.querySelectorAll('mjx-container').length,
           errors: s.querySelectorAll('mjx-merror, [data-mjx-error]').length, raw,
           index: Reveal.getIndices().h, total: Reveal.getTotalSlides() };
})()"""


def structure_problems(path: Path) -> tuple[list[str], int]:
    slides = cmd_slides.split_deck(path.read_text(encoding="utf-8"))
    problems, name = [], path.name
    step = re.match(r"(\d\d)-", name)
    for i, s in enumerate(slides, 1):
        heading = next((l.strip() for l in s.body if l.strip().startswith("#")), "")
        if not s.notes:
            problems.append(f"{name} slide {i} ({heading}): no speaker notes")
        elif not re.search(r"[Ll]ecture \d\d", s.notes) or not re.search(r"§|section|introduction", s.notes):
            problems.append(f"{name} slide {i} ({heading}): the notes name no lecture section")
        if re.match(r"##\s+Ponder\b", heading):
            if "?" not in " ".join(s.body):
                problems.append(f"{name} slide {i}: a Ponder slide without a question")
            nxt = slides[i] if i < len(slides) else None
            nxt_heading = next((l.strip() for l in nxt.body if l.strip().startswith("#")), "") if nxt else ""
            if nxt is None or re.match(r"##\s+Ponder\b", nxt_heading):
                problems.append(f"{name} slide {i}: a Ponder slide with no answer on the next slide")
    if step and f"./kit check {int(step.group(1))}" not in " ".join(slides[-1].body):
        problems.append(f"{name}: the last slide does not name `./kit check {int(step.group(1))}`")
    return problems, len(slides)


def selftest_structure(ctx) -> str:
    decks = cmd_slides.deck_sources()
    if not decks:
        raise Skipped("no decks in lectures/slides/")
    problems, count = [], 0
    for d in decks:
        p, n = structure_problems(d)
        problems += p
        count += n
    lectures = sorted((ROOT / "lectures").glob("[0-9][0-9]-*.md"))
    missing = [l.name for l in lectures if not l.stem.endswith("appendix")
               and not (cmd_slides.SOURCES / l.name).is_file()]
    expect(not missing, f"lectures without a deck: {missing}")
    expect(not problems, "\n  ".join(problems))
    return f"{len(decks)} decks, {count} slides: notes with their lecture section, Ponder before its answer, the step's command last"


def _browser():
    from .. import browser
    try:
        ensure_packages("browser")
    except KitError as e:
        raise Skipped(f"Chromium is not installed and could not be ({str(e).splitlines()[0]})")
    chromium = browser.find_chromium()
    if chromium is None:
        raise Skipped("no chromium on the PATH (sudo apt-get install chromium)")
    return browser, chromium


def show_decks(browser, chromium: str, decks: list[Path], shots: Path | None) -> tuple[list[str], int, int]:
    from .lab import attach_log
    problems, slides, formulas = [], 0, 0
    with browser.Browser(chromium, cmd_slides.WIDTH, cmd_slides.HEIGHT) as b:
        errors = attach_log(b)
        for deck in decks:
            b.open(deck.as_uri())
            b.evaluate("window.deckReady", timeout=60)
            total = b.evaluate("Reveal.getTotalSlides()")
            for i in range(total):
                r = b.evaluate(f"(Reveal.slide({i}), new Promise(r => requestAnimationFrame(() => r(null))))"
                               f".then(() => {MEASURE})")
                where = f"{deck.name} slide {i + 1}"
                problems += [f"{where}: {p}" for p in r["problems"][:3]]
                if r["errors"]:
                    problems.append(f"{where}: MathJax could not read {r['errors']} formula(s)")
                if r["raw"]:
                    problems.append(f"{where}: raw TeX left in the text")
                formulas += r["math"]
                slides += 1
                if shots:
                    b.screenshot(shots / f"{deck.stem}-{i + 1:02d}.png", whole_page=False)
            offline = [u for u in b.requests if not u.startswith(("file:", "data:", "about:"))]
            if offline:
                problems.append(f"{deck.name}: asks the network for {offline[:3]}")
        if errors:
            problems.append(f"console errors: {errors[:3]}")
    return problems, slides, formulas


def selftest_browser(ctx) -> str:
    if not cmd_slides.deck_sources():
        raise Skipped("no decks in lectures/slides/")
    browser, chromium = _browser()
    decks = cmd_slides.build()
    shutil.rmtree(SCREENSHOTS, ignore_errors=True)
    SCREENSHOTS.mkdir(parents=True)
    try:
        problems, slides, formulas = show_decks(browser, chromium, decks, SCREENSHOTS)
    except browser.BrowserError as e:
        raise Failed(f"headless Chromium: {e}") from None
    expect(not problems, "\n  ".join(problems))
    expect(formulas > 0, "no formula typeset in any deck")
    return (f"{len(decks)} decks, {slides} slides at 1280x720 with nothing outside the box, {formulas} formulas "
            f"typeset, offline; screenshots in {SCREENSHOTS.relative_to(ROOT)}")


def selftest_overflow_caught(ctx) -> str:
    """A slide with too much on it must be reported."""
    if not cmd_slides.deck_sources():
        raise Skipped("no decks in lectures/slides/")
    browser, chromium = _browser()
    work = BUILD / "slides-selftest"
    shutil.rmtree(work, ignore_errors=True)
    src = work / "src"
    src.mkdir(parents=True)
    long = "\n".join(f"- point {i}: $t_{i} = {i}$" for i in range(30))
    (src / "99-overflow.md").write_text(f"# A title\n\nNote: Lecture 99, §1.\n\n---\n\n## Too much\n\n{long}\n\n"
                                        "Note: Lecture 99, §1.\n", encoding="utf-8")
    decks = cmd_slides.build(work / "out", sources=[src / "99-overflow.md"])
    try:
        problems, _, _ = show_decks(browser, chromium, decks, None)
    except browser.BrowserError as e:
        raise Failed(f"headless Chromium: {e}") from None
    expect(any("slide 2" in p and "outside" in p for p in problems),
           f"a slide of 30 lines was not reported as overflowing: {problems}")
    shutil.rmtree(work, ignore_errors=True)
    return f"a slide of 30 lines is caught: {problems[0]}"


def selftests() -> list:
    return [
        ("slides: decks have notes, Ponder answers and the step's command", selftest_structure),
        ("slides: every slide fits 1280x720 in a browser, offline", selftest_browser),
        ("slides: an overflowing slide is caught", selftest_overflow_caught),
    ]

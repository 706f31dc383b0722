"""What a slide deck may claim: only what its lecture and its step's cases say.

The decks of lectures/slides/ are short retellings of the lectures, written by hand. These rules tie
the claims of a deck that have one source to that source, so that a deck cannot drift from it:

- **tiers**: a list item marked ★ (or on a slide whose heading carries ★) must not name a case that the step's suite
  (tests/NN_*/cases.json) has only in the basic tier (the zero direction listed under "Bad input ★");
- **claims about all the cases**: "no case", "every case", "all the cases" must say which tier they are
  about, basic or ★, as the lectures do (one ★ case of step 02 puts a sphere at the world origin);
- **numbers**: every number of a deck, in its text and notes, appears in its lecture, in a lecture its
  notes name, or in a case name of its step (small counts from 0 to 12 are left out);
- **sections**: every "Lecture NN, §k" of the notes names a section that exists, and a title after it
  is that section's title;
- **fractions**: a denominator written as a product without brackets (`-b/2a`, `h/2F`) reads as
  (−b/2)·a; the lectures write −b/(2a);
- **who passes the ★ cases**: a sentence that ties the ★ cases of a step to lecture 03's float rewrites
  must name the exceptions its suite records (tests/NN_*/test_robust.cpp, `graded_forms`: the ★ cases
  those rewrites do not pass), by name or as "K of the N" (two ★ cases of step 02 need a wider type).

Each rule reports the deck, the slide and the source it disagrees with.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from raykit.common import ROOT
from kitlib import decks

LECTURES = ROOT / "lectures"
TESTS = ROOT / "tests"

SMALL = 12          # numbers up to this one are counts and indices, too common to tie to a source


def lecture_for(deck: Path) -> Path:
    return LECTURES / deck.name


def lecture_files(deck: Path, notes: str) -> list[Path]:
    """The deck's lecture, the lectures its notes name, and lecture 03's appendix when named."""
    files = [lecture_for(deck)]
    for n in sorted(set(re.findall(r"[Ll]ecture (\d\d)", notes))):
        files += sorted(p for p in LECTURES.glob(f"{n}-*.md") if not p.stem.endswith("appendix"))
    if re.search(r"appendix", notes, re.I):
        files += sorted(LECTURES.glob("*-appendix.md"))
    return [f for f in dict.fromkeys(files) if f.is_file()]


def cases_for(deck: Path) -> list[dict]:
    step = deck.name[:2]
    found = sorted(TESTS.glob(f"{step}_*/cases.json"))
    return json.loads(found[0].read_text(encoding="utf-8")) if found else []


def plain(text: str) -> str:
    """Markdown and TeX reduced to words: no emphasis, no backticks, no `$`."""
    text = re.sub(r"[*`$]", "", text)
    return re.sub(r"\s+", " ", text).strip()


def words(text: str) -> str:
    return " ".join(re.findall(r"[a-z0-9']+|[<>=]+", plain(text).lower()))


def heading(slide: decks.Slide) -> str:
    return next((l.strip() for l in slide.body if l.strip().startswith("#")), "")


def list_items(slide: decks.Slide) -> list[str]:
    item = r"^\s*(-|\+|\d+\.\+?)\s+"
    return [re.sub(item, "", l) for l in slide.body if re.match(item, l)]


# --- the rules ------------------------------------------------------------------------------------------

def tier_problems(deck: Path, slides: list[decks.Slide], cases: list[dict]) -> list[str]:
    robust = [words(c["name"]) for c in cases if c.get("tier") != "basic"]
    out = []
    for i, s in enumerate(slides, 1):
        starred = "★" in heading(s)
        for item in list_items(s):
            if not (starred or item.lstrip().startswith("★")):
                continue        # a slide of both tiers marks its ★ items one by one
            phrase = words(re.split(r":|,|\(", item.lstrip().lstrip("★"))[0])
            if len(phrase.split()) < 2:
                continue
            in_basic = [c for c in cases if c.get("tier") == "basic" and f" {phrase} " in f" {words(c['name'])} "]
            if in_basic and not any(f" {phrase} " in f" {r} " for r in robust):
                out.append(f"{deck.name} slide {i} ({plain(heading(s))}) lists \"{plain(item)}\" under ★, but "
                           f"the step's case \"{in_basic[0]['name']}\" is basic (tests/{deck.name[:2]}_*/cases.json)")
    return out


ALL_CASES = re.compile(r"\b(no|every|all(?: the)?|each) cases?\b", re.I)
TIER_WORD = re.compile(r"basic|★|robust", re.I)


def quantifier_problems(deck: Path, slides: list[decks.Slide]) -> list[str]:
    out = []
    for i, s in enumerate(slides, 1):
        for part in s.body + [s.notes]:
            for sentence in re.split(r"(?<=[.;:!?])\s+", part):
                for m in ALL_CASES.finditer(sentence):
                    around = sentence[max(0, m.start() - 40): m.end() + 60]
                    if not TIER_WORD.search(around):
                        out.append(f"{deck.name} slide {i} ({plain(heading(s))}): \"{plain(sentence)}\" says "
                                   f"\"{m.group(0)}\" without its tier (basic or ★); the step's cases come in both")
    return out


NUMBER = re.compile(r"(?<![\w.])(\d+(?:[  ]\d{3})*(?:\.\d+)?)(?![\w])")
NOT_A_CLAIM = re.compile(r"[Ll]ecture \d\d|§\s?\d+|[Ss]teps? \d\d(?:,? and \d\d)?|steps?/\d\d_\w+|\./kit \w+ \d|"
                         r"sections? \d+(?: (?:and|to) \d+)?|\b\d\d-[a-z][\w-]*")


def numbers_in(text: str) -> set[str]:
    text = NOT_A_CLAIM.sub(" ", text)
    out = set()
    for m in NUMBER.finditer(text):
        n = re.sub(r"[  ]", "", m.group(1))
        value = float(n)
        if value == int(value) and value <= SMALL:
            continue
        out.add(n.rstrip("0").rstrip(".") if "." in n else n)
    return out


def number_problems(deck: Path, slides: list[decks.Slide], cases: list[dict]) -> list[str]:
    out = []
    for i, s in enumerate(slides, 1):
        sources = lecture_files(deck, s.notes)
        known = set()
        for f in sources:
            known |= numbers_in(f.read_text(encoding="utf-8"))
        for c in cases:
            known |= numbers_in(c["name"])
        for n in sorted(numbers_in("\n".join(s.body) + "\n" + s.notes) - known):
            out.append(f"{deck.name} slide {i} ({plain(heading(s))}): the number {n} is in neither "
                       f"{', '.join(f.name for f in sources)} nor the step's case names")
    return out


SECTION_REF = re.compile(r"[Ll]ecture (\d\d)(?: appendix)?,? (?:the exercise \()?§\s?(\d+|[A-D])"
                         r"(?: ([A-Z][^,.;()]*?))?(?=[,.;()]| and | to |$)")


def sections_of(path: Path) -> dict[str, str]:
    return {m.group(1): m.group(2).strip() for m in
            re.finditer(r"^## ([0-9A-D]+)\. (.+)$", path.read_text(encoding="utf-8"), re.M)}


def section_problems(deck: Path, slides: list[decks.Slide]) -> list[str]:
    out = []
    for i, s in enumerate(slides, 1):
        for m in SECTION_REF.finditer(s.notes):
            appendix = "appendix" in m.group(0)
            files = sorted(p for p in LECTURES.glob(f"{m.group(1)}-*.md") if p.stem.endswith("appendix") == appendix)
            if not files:
                out.append(f"{deck.name} slide {i}: \"{m.group(0)}\" names a lecture that does not exist")
                continue
            secs = sections_of(files[0])
            num, title = m.group(2), (m.group(3) or "").strip()
            if num not in secs:
                out.append(f"{deck.name} slide {i}: \"{m.group(0)}\": {files[0].name} has no section {num}")
            elif title and not secs[num].lower().startswith(title.lower()):
                out.append(f"{deck.name} slide {i}: \"{m.group(0)}\": section {num} of {files[0].name} is "
                           f"\"{secs[num]}\"")
    return out


BARE_DENOMINATOR = re.compile(r"/\s*\d+\s*(?:[A-Za-z]|\\[A-Za-z]+)")


def fraction_problems(deck: Path, slides: list[decks.Slide]) -> list[str]:
    out = []
    for i, s in enumerate(slides, 1):
        text = "\n".join(s.body) + "\n" + s.notes
        for m in decks.MATH.finditer(text):
            formula = m.group(1) or m.group(2)
            for b in BARE_DENOMINATOR.finditer(formula):
                out.append(f"{deck.name} slide {i}: \"{formula.strip()}\" divides by a product without brackets "
                           f"(\"{b.group(0)}\"); the lectures write −b/(2a)")
        for b in re.finditer(r"[\w)]\s*/\s*\d+[A-Za-z]\b", re.sub(decks.MATH, " ", text)):
            out.append(f"{deck.name} slide {i}: \"{b.group(0)}\" divides by a product without brackets; "
                       f"the lectures write −b/(2a)")
    return out


GRADED = re.compile(r'TEST_CASE\("((?:[^"\\]|\\.)*)".*?graded_forms\(\{([^}]*)\}', re.S)


def rewrite_exceptions() -> dict[str, tuple[int, list[str]]]:
    """Step -> (its ★ cases that say who passes them, those lecture 03's float rewrites do not pass)."""
    out = {}
    for suite in sorted(TESTS.glob("[0-9][0-9]_*/test_robust.cpp")):
        graded = GRADED.findall(suite.read_text(encoding="utf-8"))
        if graded:
            out[suite.parent.name[:2]] = (len(graded), [n for n, forms in graded if "float_rewrites" not in forms])
    return out


STEPS_NAMED = re.compile(r"\bsteps? (\d\d)((?:(?:,| and) \d\d)*)")


def passing_problems(deck: Path, slides: list[decks.Slide], exceptions: dict) -> list[str]:
    out = []
    for i, s in enumerate(slides, 1):
        text = plain(" ".join(s.body) + " " + s.notes)
        for sentence in re.split(r"(?<=[.;!?])\s+", text):
            if "★" not in sentence or not re.search(r"rewrit", sentence, re.I):
                continue
            for m in STEPS_NAMED.finditer(sentence):
                for step in [m.group(1)] + re.findall(r"\d\d", m.group(2)):
                    total, failed = exceptions.get(step, (0, []))
                    if not failed:
                        continue
                    counted = f"{total - len(failed)} of the {total}" in text
                    named = all(name in text for name in failed)
                    if not (counted or named):
                        out.append(f"{deck.name} slide {i} ({plain(heading(s))}): \"{sentence}\" ties the ★ cases of "
                                   f"step {step} to the float rewrites, but {len(failed)} of its {total} are not passed "
                                   f"by them ({'; '.join(failed)}: tests/{step}_*/test_robust.cpp)")
    return out


def problems(deck: Path) -> list[str]:
    slides = decks.split_deck(deck.read_text(encoding="utf-8"))
    cases = cases_for(deck)
    return (tier_problems(deck, slides, cases) + quantifier_problems(deck, slides) +
            number_problems(deck, slides, cases) + section_problems(deck, slides) +
            fraction_problems(deck, slides) + passing_problems(deck, slides, rewrite_exceptions()))

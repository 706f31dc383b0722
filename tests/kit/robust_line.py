"""Self-test: a done step's ★ cases in one calm line, one lecture section per case, no cure in a message.

- `./kit check` on a step that is done but fails ★ cases prints one line for them (how many pass, which
  sections to read) and no case; `--all` shows the cases;
- every case's pointer names one section (no "sections 5 and 6" in a heading used as a pointer), and a
  message that names a lecture section names one that exists;
- no failure message in tests/ writes the cure as a formula ("compute the discriminant as ..."): it
  says what goes wrong, and the pointer says where to read.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from raykit.common import ROOT, load_steps
from raykit.robust_line import where
from .support import expect, kit, need_solutions
from .fixtures import fixture_dir


# Phrases that hand over the cure instead of naming the trouble. Each matched a message before the
# messages were rewritten (the samples in selftest_no_cure_in_messages), and none of the lecture pointers.
CURES = [
    ("compute ... as <formula>", re.compile(r"\bcompute\b[^.:]*\bas\b", re.I)),
    ("the length of a difference or cross product, |f - ...| or |f x d|",
     re.compile(r"\|\s*[A-Za-z]\w*\s*(?:-|x|\+)\s*[^|]*[A-Za-z]\s*\|")),   # not a worked |t - 2|
    ("the root pair q = ..., c / q, sign(h)", re.compile(r"\bq\s*=|\bc\s*/\s*q\b|\bsign\(h\)|copysign")),
    ("take the root that ...", re.compile(r"\btake the root\b", re.I)),
    ("use <name> = <formula>", re.compile(r"\buse\s+\w+\s*=", re.I)),
]

SAMPLES = [  # the messages as they were: the check must find a cure in each
    "Far away, h^2 and a c are nearly equal and their difference loses its digits: compute the "
    "discriminant as a (1 - |o - (h/a) d|^2) (lecture 03, sections 5 and 6).",
    "read the discriminant geometrically, a r^2 - |f x d|^2 (Lagrange's identity)",
    "take the root that adds terms of the same sign, q = -(h + sign(h) sqrt(disc)), and get the other from c / q.",
    "The sphere is centred at (0, 5, 0); the x axis passes 5 units from it. Use f = o - c, not o.",
]

LITERALS = re.compile(r'(?:"(?:[^"\\\n]|\\.)*"\s*)+')
PART = re.compile(r'"((?:[^"\\\n]|\\.)*)"')
MENTION = re.compile(r"\blecture (\d+),? sections? (\d+(?:(?:, | and )\d+)*)", re.I)


def messages(path: Path) -> list[str]:
    """The string literals of a C++ file, adjacent ones joined, comments dropped."""
    text = re.sub(r"//[^\n]*", "", path.read_text())
    return ["".join(PART.findall(m.group(0))) for m in LITERALS.finditer(text)]


def cures(text: str) -> list[str]:
    return [what for what, pattern in CURES if pattern.search(text)]


@pytest.mark.quick
def selftest_no_cure_in_messages(ctx) -> str:
    for sample in SAMPLES:
        expect(cures(sample), f"the check finds no cure in a message that gives one: {sample!r}")
    files = sorted(p for d in ("tests/0*", "tests/hidden", "tests/support") for p in ROOT.glob(f"{d}/*.[ch]pp")
                   if p.name not in ("exact_answers.cpp", "reference_roots.hpp"))
    headings = {}
    for lecture in (ROOT / "lectures").glob("*.md"):
        number = lecture.name.split("-")[0]
        headings[number] = {h.split(".")[0] for h in re.findall(r"^##\s+(\S+)", lecture.read_text(), re.M)}
    bad, seen = [], 0
    for path in files:
        for text in messages(path):
            seen += 1
            for what in cures(text):
                bad.append(f"{path.relative_to(ROOT)}: a message gives the cure ({what}): {text[:100]!r}")
            for m in MENTION.finditer(text):
                for n in re.findall(r"\d+", m.group(2)):
                    if n not in headings.get(m.group(1), set()):
                        bad.append(f"{path.relative_to(ROOT)}: a message names lecture {m.group(1)}, section {n}, "
                                   "which does not exist")
    expect(seen > 100, f"only {seen} string literals read in {len(files)} files: the check reads nothing")
    expect(not bad, "\n  ".join(bad[:10]))
    return f"{seen} messages in {len(files)} files: none writes the cure, every section named exists"


@pytest.mark.quick
def selftest_one_section_each(ctx) -> str:
    """Every case's pointer names one section: a heading used as a pointer names no other sections."""

    bad, n = [], 0
    for step in load_steps():
        for path in sorted((ROOT / "tests" / step.folder).glob("test_*.cpp")):
            for pointer in re.findall(r'doctest::description\("([^"]*)"\)', path.read_text()):
                n += 1
                if re.search(r"\bsections\b|\blecture\b|\(", pointer):
                    bad.append(f"{path.relative_to(ROOT)}: '{pointer}' points to more than one section")
    expect(n > 0, "no doctest::description found: the check reads nothing")
    expect(not bad, "\n  ".join(sorted(set(bad))[:10]))
    # The check can fail: the pointer step 01's ★ cases had.
    expect(re.search(r"\bsections\b|\blecture\b|\(", "6. Far and grazing rays (lecture 03 sections 5 and 6)"),
           "the check accepts a pointer that names three sections")
    return f"{n} pointers, one section each"


@pytest.mark.quick
def selftest_words(ctx) -> str:
    cases = [("lectures/03-unit-direction.md", ["5. Cancellation in the discriminant", "6. Cancellation in the roots",
                                                "5. Cancellation in the discriminant"], "lecture 03, sections 5 and 6"),
             ("lectures/01-unit-sphere.md", ["6. Far and grazing rays"], "lecture 01, section 6"),
             ("lectures/02-general-sphere.md", ["7. The robust cases", "4. The roots", "10. X"],
              "lecture 02, sections 4, 7 and 10")]
    for lecture, pointers, want in cases:
        got = where(lecture, pointers)
        expect(got == want, f"where({lecture!r}, {pointers}) gives {got!r}, expected {want!r}")
    return f"{len(cases)} section lists in words"


def selftest_done_step_is_calm(ctx) -> str:
    """The textbook step 01 is done and fails its 3 ★ cases: one line, no case; --all shows them."""

    need_solutions()  # the fixture's steps are graded on top of the reference
    r = kit("check", "1", "--steps", str(fixture_dir("textbook")))
    expect(r.returncode == 0, f"./kit check 1 --steps textbook exited {r.returncode}:\n{r.stdout[-1500:]}")
    line = re.search(r"^\s*step 01: (★ robust (\d+) of (\d+), optional: lecture 01, section 6)$", r.stdout, re.M)
    expect(line is not None and line.group(2) != line.group(3),
           f"no line 'step 01: ★ robust k of n, optional: lecture 01, section 6' (k < n) in:\n{r.stdout[-1500:]}")
    expect("✗" not in r.stdout and "expected" not in r.stdout,
           f"a done step shows a failing ★ case without --all:\n{r.stdout[-1500:]}")
    every = kit("check", "1", "--all", "--steps", str(fixture_dir("textbook")))
    shown = len(re.findall(r"✗ ★ the unit sphere|✗ ★ grazing rays", every.stdout))   # ★ cases are marked
    failing = int(line.group(3)) - int(line.group(2))
    expect(shown == failing, f"--all shows {shown} ★ cases, {failing} fail:\n{every.stdout[-1500:]}")
    return f"done: '{line.group(1)}' and no case; --all shows the {failing}"

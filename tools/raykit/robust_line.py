"""The ★ robust tier of a done step in one calm line: "★ robust 0 of 3, optional: lecture 03, sections 5 and 6".

A student who has finished a step should not meet a red block of optional cases: the scoreboard says
how many ★ cases pass and where to read, and `./kit check N --all` shows the cases themselves.
"""

from __future__ import annotations

import re


def lecture_number(lecture: str) -> str:
    """"lectures/03-unit-direction.md" -> "03" (the file name's number; the path itself if it has none)."""
    m = re.match(r"(\d+)-", lecture.rsplit("/", 1)[-1])
    return m.group(1) if m else lecture


def section_number(pointer: str) -> str:
    """A case's pointer, "5. Cancellation in the discriminant" -> "5" (a heading without a number: itself)."""
    m = re.match(r"\s*([0-9A-Z]+)\.\s", pointer)
    return m.group(1) if m else pointer.strip()


def in_words(numbers: list[str]) -> str:
    """["5"] -> "section 5"; ["5", "6"] -> "sections 5 and 6"; three or more: "sections 4, 5 and 6"."""
    if len(numbers) == 1:
        return f"section {numbers[0]}"
    return "sections " + ", ".join(numbers[:-1]) + f" and {numbers[-1]}"


def where(lecture: str, pointers: list[str]) -> str:
    """The lecture sections the cases point to, in order of the lecture, each once."""
    numbers = list(dict.fromkeys(section_number(p) for p in pointers if p))
    numbers.sort(key=lambda n: (0, int(n), "") if n.isdigit() else (1, 0, n))
    return f"lecture {lecture_number(lecture)}" + (f", {in_words(numbers)}" if numbers else "")


def robust_line(result) -> str:
    """One line for a step's ★ robust tier: passed of total and, while some fail, where to read."""
    cases = result.tier("robust")
    passed = result.passed("robust")
    line = f"★ robust {passed} of {len(cases)}"
    failing = [c.lecture for c in cases if c.status != "pass"]
    if failing:
        line += f", optional: {where(result.step.lecture, failing)}"
    return line

#!/usr/bin/env python3
"""Doxygen input filter: GitHub's Markdown math, rewritten as Doxygen formulas.

The lectures are written for GitHub, which reads `$...$` (inline) and `$$...$$`
or a ```` ```math ```` fence (display). Doxygen 1.9 reads only `\\f$...\\f$` and
`\\f[...\\f]`. Doxygen runs this script on every Markdown file it reads
(FILTER_PATTERNS) and parses what it prints, so the files themselves stay
GitHub Markdown.

Rules, close to what GitHub and pandoc do:
- `$$` opens or closes a display formula, which may span lines;
- `$x$` is inline math when the opening `$` is not followed by a space and the
  closing one is not preceded by a space nor followed by a digit, on one line
  ("costs $5 or $6" stays text);
- `` $`x`$ `` is GitHub's other inline form;
- `\\$` is a literal dollar (Doxygen reads `\\$` the same way);
- nothing changes inside code: fenced blocks and `code spans`.

Three smaller fixes for Doxygen on the same lines:
- **bold** or *italics* that start with a formula become <b> or <em> (Doxygen
  would print the asterisks);
- a figure's relative path keeps only the file name, which Doxygen looks up in
  IMAGE_PATH (it would keep ../docs/images/x.png as is, pointing nowhere);
- a step's task (steps/NN_topic/README.md) gets ": the task" after its title,
  which is often its lecture's title too.

Every line stays on its line, so Doxygen's warnings point to the right line of
the original file.

Usage: math_filter.py FILE (prints the translation), or --selftest.
"""

from __future__ import annotations

import re
import sys

FENCE = re.compile(r"^( {0,3})(`{3,}|~{3,})\s*([^`\s]*)")


def _closing_dollar(line: str, start: int) -> int:
    """Index of the `$` that closes an inline formula opened just before `start`, or -1."""
    i = start
    while i < len(line):
        c = line[i]
        if c == "\\":
            i += 2
            continue
        if c == "$":
            if line.startswith("$$", i):
                return -1                       # a display delimiter: not ours
            before_ok = i > start and not line[i - 1].isspace()
            after_ok = i + 1 >= len(line) or not line[i + 1].isdigit()
            return i if before_ok and after_ok else -1
        i += 1
    return -1


def _code_span_end(line: str, i: int) -> int:
    """If a code span starts at `i` (a run of backticks), the index just after it; else -1."""
    n = len(line[i:]) - len(line[i:].lstrip("`"))
    run = "`" * n
    j = i + n
    while True:
        k = line.find(run, j)
        if k < 0:
            return -1
        end = k + n
        if end >= len(line) or line[end] != "`":
            return end
        j = end + len(line[end:]) - len(line[end:].lstrip("`"))


class Translator:
    """Translates a Markdown text line by line; a display formula may span lines."""

    def __init__(self) -> None:
        self.in_display = False
        self.close = "$$"                       # what ends the display formula
        self.fence: str | None = None           # the fence that opened a code block
        self.math_fence = False

    def line(self, line: str) -> str:
        m = FENCE.match(line)
        if self.fence is not None:
            if m and m.group(2)[0] == self.fence[0] and len(m.group(2)) >= len(self.fence) \
                    and not line[m.end():].strip():
                self.fence = None
                if self.math_fence:
                    self.math_fence = False
                    return m.group(1) + "\\f]" + line[m.end():]
            return line
        if m and not self.in_display:
            self.fence = m.group(2)
            if m.group(3) == "math":
                self.math_fence = True
                return m.group(1) + "\\f[" + line[m.end():]
            return line
        return self.text(line)

    def text(self, line: str) -> str:
        was_display = self.in_display
        out = self.formulas(line)
        if was_display or self.in_display or "\\f[" in out:
            return out
        return local_images_by_name(emphasis_around_formulas(out))

    def formulas(self, line: str) -> str:
        out: list[str] = []
        i = 0
        while i < len(line):
            c = line[i]
            if self.in_display:
                if line.startswith(self.close, i):
                    out.append("\\f]")
                    self.in_display = False
                    i += len(self.close)
                elif c == "\\":
                    out.append(line[i:i + 2])
                    i += 2
                else:
                    out.append(c)
                    i += 1
            elif line.startswith("\\f$", i) and line.find("\\f$", i + 3) > 0:
                end = line.find("\\f$", i + 3) + 3     # already Doxygen's: keep it
                out.append(line[i:end])
                i = end
            elif line.startswith("\\f[", i):
                out.append("\\f[")
                self.in_display, self.close = True, "\\f]"
                i += 3
            elif c == "\\" and i + 1 < len(line):
                out.append(line[i:i + 2])
                i += 2
            elif c == "`":
                end = _code_span_end(line, i)
                if end < 0:
                    run = len(line[i:]) - len(line[i:].lstrip("`"))
                    out.append(line[i:i + run])
                    i += run
                else:
                    out.append(line[i:end])
                    i = end
            elif line.startswith("$$", i):
                out.append("\\f[")
                self.in_display, self.close = True, "$$"
                i += 2
            elif line.startswith("$`", i) and line.find("`$", i + 2) > 0:
                end = line.find("`$", i + 2)
                out.append("\\f$" + line[i + 2:end] + "\\f$")
                i = end + 2
            elif c == "$" and i + 1 < len(line) and not line[i + 1].isspace():
                end = _closing_dollar(line, i + 1)
                if end < 0:
                    out.append(c)
                    i += 1
                else:
                    out.append("\\f$" + line[i + 1:end] + "\\f$")
                    i = end + 1
            else:
                out.append(c)
                i += 1
        return "".join(out)


# Doxygen opens **bold** or *italics* only before a letter or a few signs, not
# before the backslash of \f$: "**$t$ counts**" would stay literal asterisks.
# HTML tags say the same thing and Doxygen passes them through.
EMPHASIS = [
    (re.compile(r"(?<![*\\])\*\*(\\f\$.*?[^\s*])\*\*(?!\*)"), r"<b>\1</b>"),
    (re.compile(r"(?<![_\w\\])__(\\f\$.*?[^\s_])__(?![_\w])"), r"<b>\1</b>"),
    (re.compile(r"(?<![*\\])\*(\\f\$[^*]*?[^\s*])\*(?!\*)"), r"<em>\1</em>"),
    (re.compile(r"(?<![_\w\\])_(\\f\$[^_]*?\\f\$[^_]*?)_(?![_\w])"), r"<em>\1</em>"),
]


def emphasis_around_formulas(line: str) -> str:
    for pattern, html in EMPHASIS:
        line = pattern.sub(html, line)
    return line


# A figure's path is relative to the Markdown file, for GitHub:
# ![a figure](figures/01-x.svg), ![a render](../docs/images/x.png). Doxygen finds
# an image by its name in IMAGE_PATH and copies it next to the pages, but keeps
# a path with ../ as it is, which then points nowhere: keep the name only.
IMAGE = re.compile(r"(!\[[^\]]*\]\()(?![a-zA-Z][a-zA-Z0-9+.-]*:|/)([^()\s]*/)([^/()\s]+\.(?:png|svg|jpe?g|gif))"
                   r"(?=[\s)])", re.I)


def local_images_by_name(line: str) -> str:
    return IMAGE.sub(r"\1\3", line)


def translate(text: str) -> str:
    t = Translator()
    return "".join(t.line(l[:-1]) + "\n" if l.endswith("\n") else t.line(l)
                   for l in text.splitlines(keepends=True))


# Each pair: GitHub Markdown, what Doxygen must read. `./kit test` runs these.
EXAMPLES = [
    ("a ray $\\mathbf{o} + t\\mathbf{d}$ here", "a ray \\f$\\mathbf{o} + t\\mathbf{d}\\f$ here"),
    ("$$a = b$$", "\\f[a = b\\f]"),
    ("$$\nt = \\frac{1}{2}\n$$\n", "\\f[\nt = \\frac{1}{2}\n\\f]\n"),
    ("it costs $5 or $6", "it costs $5 or $6"),
    ("a literal \\$ and $x$", "a literal \\$ and \\f$x\\f$"),
    ("code `$x$` stays", "code `$x$` stays"),
    ("```cpp\nint $x$;\n```\n", "```cpp\nint $x$;\n```\n"),
    ("```math\nx^2\n```\n", "\\f[\nx^2\n\\f]\n"),
    ("inline $`x^2`$ form", "inline \\f$x^2\\f$ form"),
    ("$t_\\min \\le t$ and $a$", "\\f$t_\\min \\le t\\f$ and \\f$a\\f$"),
    ("| $\\Delta < 0$ | miss |", "| \\f$\\Delta < 0\\f$ | miss |"),
    ("$ not math $", "$ not math $"),
    ("Doxygen's own \\f$x\\f$ and \\f[y\\f] stay", "Doxygen's own \\f$x\\f$ and \\f[y\\f] stay"),
    ("- **$t$ counts steps.** Then", "- <b>\\f$t\\f$ counts steps.</b> Then"),
    ("*$x$ is small* and **bold** and $a*b$", "<em>\\f$x\\f$ is small</em> and **bold** and \\f$a*b\\f$"),
    ("![A render](../docs/images/box.png) and ![f](figures/01-a.svg \"t\")",
     "![A render](box.png) and ![f](01-a.svg \"t\")"),
    ("![web](https://example.org/a/b.png) ![same](c.png)", "![web](https://example.org/a/b.png) ![same](c.png)"),
    ("$$\\begin{aligned} a &= b \\\\ c &= d \\end{aligned}$$",
     "\\f[\\begin{aligned} a &= b \\\\ c &= d \\end{aligned}\\f]"),
]


TASK = re.compile(r"(^|/)steps/\d\d_[^/]+/README\.md$")


def retitle_task(text: str, path: str) -> str:
    """A step's task (steps/NN_topic/README.md) often has its lecture's title; the side bar
    of the site lists both, so the task's page says what it is. Only its first line changes."""
    if not TASK.search(path.replace("\\", "/")):
        return text
    first, newline, rest = text.partition("\n")
    m = re.match(r"#[ \t]+(.+?)[ \t#]*$", first)
    if not m or "{#" in first:
        return text
    return f"# {m.group(1)}: the task" + newline + rest


def selftest() -> list[str]:
    """The examples that translate wrongly, as messages (empty when all are right)."""
    bad = []
    for source, expected in EXAMPLES:
        got = translate(source)
        if got != expected:
            bad.append(f"{source!r} became {got!r}, expected {expected!r}")
        elif got.count("\n") != source.count("\n"):
            bad.append(f"{source!r}: the line count changed")
    for path, expected in [("steps/01_unit_sphere/README.md", "# Step 01: the task\nText"),
                           ("lectures/01-unit-sphere.md", "# Step 01\nText")]:
        got = retitle_task("# Step 01\nText", path)
        if got != expected:
            bad.append(f"the title of {path} became {got!r}, expected {expected!r}")
    return bad


def main(argv: list[str]) -> int:
    if argv[1:] == ["--selftest"]:
        bad = selftest()
        print("\n".join(bad) or f"math_filter: {len(EXAMPLES)} examples translate as expected")
        return 1 if bad else 0
    if len(argv) != 2:
        print("usage: math_filter.py FILE | --selftest", file=sys.stderr)
        return 2
    with open(argv[1], encoding="utf-8") as f:
        text = f.read()
    sys.stdout.write(translate(retitle_task(text, argv[1])))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

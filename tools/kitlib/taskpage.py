"""A step's task (steps/NN_topic/README.md) as a PrairieLearn question page: HTML, not Markdown source.

The task is written for GitHub and for a student who has the whole kit. A PrairieLearn student has
only the question page, so the task marks what only the kit's copy has:

    <!-- kit only -->             lines up to <!-- /kit only --> are left out here (./kit check,
    ...                           ./kit debug, the lab, the lectures' files, ./kit render)
    <!-- /kit only -->
    <!-- prairielearn: TEXT -->   TEXT, a line of Markdown, is shown here only (GitHub hides comments)

and the rest is translated, line by line, from the small part of GitHub's Markdown the tasks use:
headings, paragraphs, ordered and bulleted lists (nested by indentation), fenced code (as
<pl-code>), pipe tables (a header row, its |---| line, then rows), `code`, **bold**, *italics*, links (only http(s) ones stay links: a path into the kit
points at nothing there), figures (the file is copied beside the question, in clientFilesQuestion/,
and shown from PrairieLearn's URL for it), and math: `$x$` and `$$x$$` (docs/math_filter.py's rules)
become MathJax's `\\(x\\)` and `\\[x\\]`, which PrairieLearn's pages typeset. The page is a Mustache
template to PrairieLearn, so a `{{` in a formula is written `{ {` (the same TeX).
"""

from __future__ import annotations

import html
import itertools
import re
from pathlib import Path

KIT_ONLY = re.compile(r"^\s*<!--\s*kit only\s*-->\s*$")
KIT_ONLY_END = re.compile(r"^\s*<!--\s*/kit only\s*-->\s*$")
PL_ONLY = re.compile(r"^\s*<!--\s*prairielearn:\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^\s*(`{3,}|~{3,})\s*([\w+-]*)\s*$")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
ITEM = re.compile(r"^(\s*)(\d+[.)]|[-*+])\s+(.*)$")
TABLE_RULE = re.compile(r"^\s*\|?\s*:?-{3,}:?\s*(\|\s*:?-{3,}:?\s*)*\|?\s*$")
FIGURE_URL = "{{options.client_files_question_url}}/"


def for_prairielearn(text: str) -> list[str]:
    """The task's lines as a PrairieLearn student reads them: kit-only blocks out, PL-only lines in."""
    lines, skipping = [], False
    for n, line in enumerate(text.splitlines(), 1):
        if KIT_ONLY.match(line):
            if skipping:
                raise ValueError(f"line {n}: <!-- kit only --> inside another")
            skipping = True
        elif KIT_ONLY_END.match(line):
            if not skipping:
                raise ValueError(f"line {n}: <!-- /kit only --> without its opening")
            skipping = False
        elif not skipping:
            m = PL_ONLY.match(line)
            lines.append(m.group(1) if m else line)
    if skipping:
        raise ValueError("<!-- kit only --> never closed")
    return lines


def kit_paths_out(text: str) -> str:
    """The kit's text as a PrairieLearn student reads it: a lecture by its number, a step file by its name
    (their paths exist only in the kit's copy)."""
    text = re.sub(r"`?lectures/(\d\d)[\w-]*\.md`?", r"lecture \1", text)
    return re.sub(r"steps/\d\d_\w+/", "", text)


def _closing_dollar(line: str, start: int) -> int:
    """The `$` closing an inline formula opened just before `start` (docs/math_filter.py's rule), or -1."""
    i = start
    while i < len(line):
        if line[i] == "\\":
            i += 2
            continue
        if line[i] == "$":
            if line.startswith("$$", i):
                return -1
            before_ok = i > start and not line[i - 1].isspace()
            after_ok = i + 1 >= len(line) or not line[i + 1].isdigit()
            return i if before_ok and after_ok else -1
        i += 1
    return -1


def _tex(formula: str) -> str:
    return html.escape(formula.replace("{{", "{ {").replace("}}", "} }"), quote=False)


class Page:
    """Translates one task; `figures` collects (source file, name) pairs to copy beside the question."""

    def __init__(self, source: Path):
        self.source = source
        self.figures: list[tuple[Path, str]] = []
        self.dropped_links: list[str] = []

    def inline(self, text: str) -> str:
        kept: list[str] = []

        def keep(piece: str) -> str:
            kept.append(piece)
            return f"\x00{len(kept) - 1}\x00"

        out, i = [], 0
        while i < len(text):
            c = text[i]
            if c == "`":
                run = len(text[i:]) - len(text[i:].lstrip("`"))
                end = text.find("`" * run, i + run)
                if end >= 0:
                    out.append(keep(f"<code>{html.escape(text[i + run:end].strip(), quote=False)}</code>"))
                    i = end + run
                    continue
            elif c == "\\" and text.startswith("\\$", i):
                out.append("$")
                i += 2
                continue
            elif text.startswith("$$", i):
                end = text.find("$$", i + 2)
                if end >= 0:
                    out.append(keep(f"\\[{_tex(text[i + 2:end])}\\]"))
                    i = end + 2
                    continue
            elif c == "$" and i + 1 < len(text) and not text[i + 1].isspace():
                end = _closing_dollar(text, i + 1)
                if end >= 0:
                    out.append(keep(f"\\({_tex(text[i + 1:end])}\\)"))
                    i = end + 1
                    continue
            out.append(c)
            i += 1
        s = html.escape("".join(out), quote=False)
        s = re.sub(r"!\[([^\]]*)\]\(([^)\s]+)\)", lambda m: self.figure(m.group(1), m.group(2)), s)
        s = re.sub(r"\[([^\]]+)\]\(([^)\s]+)\)", lambda m: self.link(m.group(1), m.group(2)), s)
        s = re.sub(r"\*\*(?=\S)(.+?)(?<=\S)\*\*", r"<strong>\1</strong>", s)
        s = re.sub(r"(?<![\w*])\*(?=\S)(.+?)(?<=\S)\*(?![\w*])", r"<em>\1</em>", s)
        return re.sub("\x00(\\d+)\x00", lambda m: kept[int(m.group(1))], s)

    def link(self, words: str, url: str) -> str:
        target = html.unescape(url)
        if re.match(r"https?://", target):
            return f'<a href="{html.escape(target)}" target="_blank" rel="noopener">{words}</a>'
        self.dropped_links.append(target)
        return words

    def figure(self, alt: str, url: str) -> str:
        path = (self.source.parent / html.unescape(url)).resolve()
        if re.match(r"https?://", html.unescape(url)) or not path.is_file():
            self.dropped_links.append(html.unescape(url))
            return alt
        self.figures.append((path, path.name))
        return (f'<img src="{FIGURE_URL}{html.escape(path.name)}" alt="{alt}" '
                f'style="max-width: 100%">')

    @staticmethod
    def rows(lines: list[str], start: int) -> list[str]:
        """A table's body: the lines from `start` that begin with |."""
        return list(itertools.takewhile(lambda line: line.lstrip().startswith("|"), lines[start:]))

    def table(self, head: str, body: list[str]) -> str:
        def cells(row: str) -> list[str]:
            row = row.strip()
            row = row[1:] if row.startswith("|") else row
            row = row[:-1] if row.endswith("|") and not row.endswith("\\|") else row
            return [c.strip() for c in re.split(r"(?<!\\)\|", row)]
        top = "".join(f"<th>{self.inline(c)}</th>" for c in cells(head))
        rest = "".join("<tr>" + "".join(f"<td>{self.inline(c)}</td>" for c in cells(r)) + "</tr>" for r in body)
        return f'<table class="table table-sm table-bordered w-auto"><thead><tr>{top}</tr></thead><tbody>{rest}</tbody></table>'

    def render(self, lines: list[str]) -> str:
        out: list[str] = []
        para: list[str] = []
        lists: list[tuple[int, str]] = []      # (indent, "ol" | "ul"), outermost first
        item: list[str] | None = None

        def flush_para() -> None:
            if para:
                out.append(f"<p>{self.inline(' '.join(para))}</p>")
                para.clear()

        def flush_item() -> None:
            nonlocal item
            if item is not None:
                out.append(self.inline(" ".join(item)))
                item = None

        def close_lists(to: int = 0) -> None:
            flush_item()
            while len(lists) > to:
                out.append(f"</li></{lists.pop()[1]}>")

        i, blank = 0, False
        while i < len(lines):
            line = lines[i]
            after_blank, blank = blank, False
            fence = FENCE.match(line)
            if fence:
                flush_para(), close_lists()
                body, i = [], i + 1
                while i < len(lines) and not lines[i].strip().startswith(fence.group(1)):
                    body.append(lines[i])
                    i += 1
                language = fence.group(2) or "text"
                out.append(f'<pl-code language="{html.escape(language)}">{html.escape(chr(10).join(body), quote=False)}'
                           "</pl-code>")
                i += 1
                continue
            if line.strip() == "$$":
                flush_para(), flush_item()
                body, i = [], i + 1
                while i < len(lines) and lines[i].strip() != "$$":
                    body.append(lines[i].strip())
                    i += 1
                out.append(f"<p>\\[{_tex(' '.join(body))}\\]</p>")
                i += 1
                continue
            if not line.strip():
                flush_para()
                blank = True
                i += 1
                continue
            if line.lstrip().startswith("|") and i + 1 < len(lines) and TABLE_RULE.match(lines[i + 1]):
                flush_para(), close_lists()
                out.append(self.table(lines[i], [r for r in self.rows(lines, i + 2)]))
                i += 2 + len(self.rows(lines, i + 2))
                continue
            heading = HEADING.match(line)
            m = ITEM.match(line)
            if heading:
                flush_para(), close_lists()
                level = min(len(heading.group(1)) + 2, 6)
                out.append(f"<h{level}>{self.inline(heading.group(2))}</h{level}>")
            elif m:
                flush_para()
                indent, kind = len(m.group(1)), "ol" if m.group(2)[0].isdigit() else "ul"
                flush_item()
                while lists and indent < lists[-1][0]:
                    out.append(f"</li></{lists.pop()[1]}>")
                if lists and indent == lists[-1][0] and kind != lists[-1][1]:
                    out.append(f"</li></{lists.pop()[1]}>")
                if not lists or indent > lists[-1][0]:
                    lists.append((indent, kind))
                    out.append(f"<{kind}><li>")
                else:
                    out.append("</li><li>")
                item = [m.group(3)]
            elif lists and (line.startswith(" ") or item is not None and not after_blank):
                if item is None:
                    item = []
                item.append(line.strip())
            else:
                close_lists()
                para.append(line.strip())
            i += 1
        flush_para(), close_lists()
        return "\n".join(out)


def task_html(readme: Path) -> tuple[str, list[tuple[Path, str]], list[str]]:
    """The task's HTML for PrairieLearn, the figures to copy beside it, and the links left as text."""
    page = Page(readme)
    text = page.render([kit_paths_out(line) for line in for_prairielearn(readme.read_text())])
    return text, page.figures, page.dropped_links

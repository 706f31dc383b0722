"""The picture whole: the SVG of a figure (title, summary, panels, legend, notes), its first view
in characters for a terminal (`sketch`), and the file written whole (`write`)."""

from __future__ import annotations

import math
import re
from pathlib import Path

from .. import atomic
from .basics import (EXPECTED_COLOUR, GOT_COLOUR, RAY_COLOUR, WIDTH, WINDOW_COLOUR, escape, finite, fmt_point,
                     norm, text_width, wrap_px)
from .case import Case, summary_of
from .panel import Panel
from .shapes import rect_panels, sphere_panels


# --- the picture ---------------------------------------------------------------------------------

def render(figure: dict, title: str) -> tuple:
    """(svg text, one-line summary) of a figure; raises PictureError when it cannot be drawn."""
    case = Case(figure)
    line = summary_of(case)
    titles = wrap_px(title, 15, WIDTH - 20, bold=True)
    if len(titles) > 2:
        titles = titles[:1] + [shorten_px(" ".join(titles[1:]), 15, WIDTH - 20, bold=True)]
    head = wrap_px(line, 12.5, WIDTH - 20)
    first = 22 + 19 * (len(titles) - 1)         # the baseline of the summary's first line, less 22
    top = first + 30 + 17 * len(head) - 9
    panels = sphere_panels(case, top) if case.sphere is not None else rect_panels(case, top)
    notes = list(dict.fromkeys(n for p in panels for n in p.notes + [
        f"{label}, at {fmt_point(q)}, is far outside the view: the view shows the shape and the hits"
        for label, q in p.off]))
    y = panels[-1].bottom + 26
    legend, legend_height = legend_svg(y, case.window is not None)
    y += legend_height + 4
    note_lines = [l for n in notes for l in wrap_px("note: " + n, 12.5, WIDTH - 20)]
    height = y + 17 * len(note_lines) + 10
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height:.0f}" '
           f'viewBox="0 0 {WIDTH} {height:.0f}" font-family="DejaVu Sans, Arial, sans-serif">',
           f'<title>{escape(title)}</title>',
           f'<desc>{escape(line)}</desc>',
           '<defs><marker id="arrow" viewBox="0 0 10 10" refX="8" refY="5" markerWidth="7" markerHeight="7" '
           f'orient="auto-start-reverse"><path d="M0,0L10,5L0,10z" fill="{RAY_COLOUR}"/></marker></defs>',
           f'<rect width="{WIDTH}" height="{height:.0f}" fill="white"/>',
           ]
    out += [f'<text x="10" y="{22 + 19 * i}" font-size="15" font-weight="bold">{escape(l)}</text>'
            for i, l in enumerate(titles)]
    out += [f'<text x="10" y="{first + 22 + 17 * i}" font-size="12.5" fill="#333">{escape(l)}</text>'
            for i, l in enumerate(head)]
    out += [p.svg() for p in panels]
    out.append(legend)
    out += [f'<text x="10" y="{y + 17 * i}" font-size="12.5" fill="#8a3b00">{escape(l)}</text>'
            for i, l in enumerate(note_lines)]
    out.append("</svg>")
    return "\n".join(out) + "\n", line


def render_all(figure: dict, title: str) -> tuple:
    """(svg, summary, sketch): the picture, its line, and its first view in characters (sketch)."""
    case = Case(figure)
    svg, line = render(figure, title)
    panels = sphere_panels(case, 0.0) if case.sphere is not None else rect_panels(case, 0.0)
    return svg, line, sketch(panels[0], case)


SKETCH_COLUMNS, SKETCH_ROWS = 52, 12


def sketch(panel: Panel, case: Case) -> list:
    """The panel's view in characters, for a terminal with no picture viewer: the shape's outline #,
    the ray (t >= 0) as - | / \\ by its slope and its line behind the origin as '.', the window's
    stretch as = when the ray is level, the origin o, the centre +, the expected answers E, the
    student's X (* where both fall in one character). A character is about twice as tall as wide, so
    a cell is 1 by 2 of the view's units, and a circle stays round."""
    x0, x1, y0, y1 = panel.view
    cols, rows = SKETCH_COLUMNS, SKETCH_ROWS
    cell = max((x1 - x0) / cols, (y1 - y0) / (2 * rows))
    mx, my = (x0 + x1) / 2, (y0 + y1) / 2
    left, top = mx - cell * cols / 2, my + cell * rows      # the grid's top left corner, in the view
    grid = [[" "] * cols for _ in range(rows)]

    def cell_of(p):
        if not finite(*p):
            return None
        across, down = p[0] - left, top - p[1]
        i, j = math.floor(across / cell), math.floor(down / (2 * cell))
        return (i, j) if 0 <= i < cols and 0 <= j < rows else None

    def put(p, ch, over=" "):
        at = cell_of(p)
        if at is not None and grid[at[1]][at[0]] in over:
            grid[at[1]][at[0]] = ch

    kind, where, size = panel.shape
    for j in range(rows):           # the outline: the cells the boundary crosses
        for i in range(cols):
            bx0, bx1 = left + i * cell, left + (i + 1) * cell
            by1, by0 = top - j * 2 * cell, top - (j + 1) * 2 * cell
            if kind == "circle" and size > 0:
                cx, cy = where
                near = math.hypot(max(bx0 - cx, 0, cx - bx1), max(by0 - cy, 0, cy - by1))
                far = max(math.hypot(x - cx, y - cy) for x in (bx0, bx1) for y in (by0, by1))
                if near <= size <= far:
                    grid[j][i] = "#"
            elif kind == "rect":
                (ax, ay), (cx, cy) = where[0], where[2]
                lo_x, hi_x, lo_y, hi_y = min(ax, cx), max(ax, cx), min(ay, cy), max(ay, cy)
                overlaps = bx0 <= hi_x and lo_x <= bx1 and by0 <= hi_y and lo_y <= by1
                inside = lo_x < bx0 and bx1 < hi_x and lo_y < by0 and by1 < hi_y
                if overlaps and not inside:
                    grid[j][i] = "#"
    o2, d2, at = panel.ray
    moving = norm(d2) > 0
    # No line to draw: either there is no ray, or the view looks straight along it (a ray at a
    # rectangle face on), where it is the one point o.
    ray_char = ("(none: the direction is not finite)" if not finite(*case.direction)
                else "(seen end-on: it runs straight into the picture at o)" if norm(case.direction) > 0
                else "(none: the direction is zero)")
    if moving:
        slope = d2[1] / d2[0] * 0.5 if d2[0] != 0 else math.inf   # rows per column, a row 2 units
        ray_char = "-" if abs(slope) < 0.3 else "|" if abs(slope) > 2.5 else "/" if slope > 0 else "\\"
        span = panel.clip(o2, d2, -math.inf, math.inf)
        if span is not None:
            a, b = span
            count = 6 * (cols + rows)
            window = case.window if case.window is not None and case.window[0] <= case.window[1] else None
            for k in range(count + 1):
                t = a + (b - a) * k / count
                if t < 0:
                    put(at(t), ".")
                elif window and window[0] <= t <= window[1] and ray_char == "-":
                    put(at(t), "=", over=" .")
                else:
                    put(at(t), ray_char, over=" .")
    if kind == "circle":
        put(where, "+", over=" .-|/\\=")
    marks: dict = {}
    for who, a in (("E", case.expected), ("X", case.got)):
        for t in a["ts"]:
            c = cell_of(at(t)) if math.isfinite(t) else None
            if c is not None:
                marks[c] = "*" if marks.get(c, who) != who else who
    c = cell_of(at(0.0))
    if c is not None:
        grid[c[1]][c[0]] = "o"
    for (i, j), ch in marks.items():
        grid[j][i] = ch
    lines = ["      |" + "".join(r) + "|" for r in grid]
    shape = "# the sphere, + its centre" if kind == "circle" else "# the rectangle, face on"
    window = "; = the window" if case.window is not None and moving and ray_char == "-" else ""
    return (["      +" + "-" * cols + "+"] + lines + ["      +" + "-" * cols + "+",
            f"      {shape}; o the origin; the ray {ray_char}{window}; E expected, X yours, * both in one character"])


def legend_svg(y: float, window: bool) -> tuple:
    """(svg, height): the marks and what they mean, each placed after the last, on as many lines as
    the width needs."""
    keys = [(lambda x, y: f'<circle cx="{x + 6}" cy="{y - 4}" r="6" fill="{EXPECTED_COLOUR}"/>', 20, "expected"),
            (lambda x, y: f'<path d="M{x},{y - 11}L{x + 14},{y + 3}M{x},{y + 3}L{x + 14},{y - 11}" '
                          f'stroke="{GOT_COLOUR}" stroke-width="3"/>', 20, "your answer"),
            (lambda x, y: f'<line x1="{x}" y1="{y - 4}" x2="{x + 30}" y2="{y - 4}" stroke="{RAY_COLOUR}" '
                          f'stroke-width="2" marker-end="url(#arrow)"/>', 38, "the ray")]
    if window:
        keys.append((lambda x, y: f'<line x1="{x}" y1="{y - 4}" x2="{x + 30}" y2="{y - 4}" '
                                  f'stroke="{WINDOW_COLOUR}" stroke-width="9" opacity="0.7"/>', 38,
                     "window [tmin, tmax]"))
    else:
        keys.append((lambda x, y: "", 0, "roots of the whole line (no window)"))
    out, x, top = ['<g>'], 10.0, y
    for mark, room, text in keys:
        w = room + text_width(text, 12.5)
        if x > 10 and x + w > WIDTH - 10:
            x, y = 10.0, y + 20
        out += [mark(x, y), f'<text x="{x + room:.1f}" y="{y}" font-size="12.5">{escape(text)}</text>']
        x += w + 22
    return "".join(out + ["</g>"]), y - top + 18


def shorten_px(text: str, size: float, width: float, bold: bool = False) -> str:
    while text_width(text, size, bold) > width and len(text) > 1:
        text = text[:-2] + "…"
    return text


def slug(name: str) -> str:
    """A file name for a case: lower case words joined by '-', at most 80 characters."""
    s = re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")
    return (s[:80].rstrip("-") or "case")


def write(figure: dict, title: str, path: Path, sketch_out: list | None = None) -> str:
    """Writes the picture to `path` whole (atomic.write), returns its summary.
    Raises PictureError when it cannot be drawn, OSError when it cannot be written. `sketch_out`, a
    list, receives the picture's first view in characters (sketch)."""
    svg, line, lines = render_all(figure, title)
    if sketch_out is not None:
        sketch_out[:] = lines
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic.write(path, svg)
    return line

"""Charts as SVG text: the one drawing path of the kit's charts.

The class report's histograms and stacked bars (report/plots.py) and the benchmark's log-log plot
(bench_report.plot_svg) are drawn here or from the pieces here, by hand, with the standard library
only: a student's `./kit bench` draws its plot on a Mac as on Debian, and the report needs no second
Python with a plotting package. Text stays text (small, searchable pages), in one font stack; its
width is estimated from the number of characters (CHAR_WIDTH of the font size, on the wide side for
Helvetica, Arial and DejaVu Sans), which is what the legends and the bars' labels are laid out by.
"""

from __future__ import annotations

import math

FONT = "Helvetica, Arial, 'DejaVu Sans', sans-serif"
CHAR_WIDTH = 0.62            # an estimate of a character's width, as a share of the font size
INK, GRID, MUTED = "#222", "#e3e3e3", "#444"
BAR = "#1f4e99"


def esc(text: str) -> str:
    """Text for an SVG element or attribute."""
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def text_width(text: str, size: float) -> float:
    return CHAR_WIDTH * size * len(text)


def svg_open(width: float, height: float, size: float = 11) -> str:
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
            f'viewBox="0 0 {width:.0f} {height:.0f}" font-family="{FONT}" font-size="{size:g}">'
            f'<rect width="{width:.0f}" height="{height:.0f}" fill="white"/>')


def marker(shape: str, x: float, y: float, r: float, fill: str, stroke: str, width: float) -> str:
    """A point of a scatter plot: "circle", "square" or "diamond"."""
    style = f'fill="{fill}" stroke="{stroke}" stroke-width="{width}"'
    if shape == "square":
        return f'<rect x="{x - r:.1f}" y="{y - r:.1f}" width="{2 * r:.1f}" height="{2 * r:.1f}" {style}/>'
    if shape == "diamond":
        q = r * 1.3
        return f'<path d="M{x:.1f},{y - q:.1f} L{x + q:.1f},{y:.1f} L{x:.1f},{y + q:.1f} L{x - q:.1f},{y:.1f} Z" {style}/>'
    return f'<circle cx="{x:.1f}" cy="{y:.1f}" r="{r:.1f}" {style}/>'


# --- axes ------------------------------------------------------------------------------------------

def ticks_125(lo: float, hi: float) -> list[float]:
    """1, 2, 5 times powers of ten between lo and hi (a log axis)."""
    out = []
    for e in range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1):
        out += [m * 10.0 ** e for m in (1, 2, 5) if lo <= m * 10.0 ** e <= hi]
    return out


def decades(lo: float, hi: float) -> tuple[int, int]:
    """The powers of ten around [lo, hi], at least one decade apart (a log axis's ends)."""
    a, b = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
    return a, max(b, a + 1)


def linear_ticks(top: float, most: int = 6, integer: bool = False) -> list[float]:
    """Ticks from 0 to at least `top` at 1, 2 or 5 times a power of ten, at most `most` + 1 of them;
    whole numbers only when `integer` (counts of students)."""
    top = max(top, 1.0 if integer else 1e-9)
    step = 10.0 ** math.floor(math.log10(top / most))
    for m in (1, 2, 5, 10):
        if top / (m * step) <= most:
            step *= m
            break
    if integer:
        step = max(1.0, round(step))
    n = math.ceil(top / step - 1e-9)
    return [i * step for i in range(n + 1)]


def number(x: float) -> str:
    return f"{x:.0f}" if abs(x - round(x)) < 1e-9 else f"{x:g}"


# --- the report's charts ----------------------------------------------------------------------------

def hist(values: list[float], bins: list[float], xlabel: str, ylabel: str = "", width: float = 600,
         height: float = 260) -> str:
    """A histogram: a bar per bin, [bins[i], bins[i+1]), the last bin closed (a value at the top end
    counts, as 100 % does)."""
    counts = [0] * (len(bins) - 1)
    for v in values:
        for i in range(len(counts)):
            if bins[i] <= v < bins[i + 1] or (i == len(counts) - 1 and v == bins[-1]):
                counts[i] += 1
                break
    ticks = linear_ticks(max(counts, default=0), 5, integer=True)
    ml, mr, mt, mb = 48, 14, 12, 44
    iw, ih = width - ml - mr, height - mt - mb
    lo, hi = bins[0], bins[-1]

    def px(x: float) -> float:
        return ml + (x - lo) / (hi - lo) * iw if hi > lo else ml

    def py(c: float) -> float:
        return mt + ih - c / ticks[-1] * ih

    s = [svg_open(width, height)]
    for t in ticks:
        s.append(f'<path d="M{ml},{py(t):.1f} h{iw}" stroke="{GRID}"/>')
        s.append(f'<text x="{ml - 5}" y="{py(t) + 4:.1f}" text-anchor="end">{number(t)}</text>')
    for i, c in enumerate(counts):
        if c:
            x0, x1 = px(bins[i]), px(bins[i + 1])
            s.append(f'<rect x="{x0 + 0.5:.1f}" y="{py(c):.1f}" width="{max(x1 - x0 - 1, 0.5):.1f}" '
                     f'height="{py(0) - py(c):.1f}" fill="{BAR}"><title>{number(bins[i])} to {number(bins[i + 1])}: '
                     f'{c}</title></rect>')
    s.append(f'<path d="M{ml},{mt + ih} h{iw}" stroke="{INK}"/>')
    every = max(1, math.ceil(len(bins) / 11))        # a label on at most eleven bin edges
    for i, b in enumerate(bins):
        if i % every == 0 or i == len(bins) - 1:
            s.append(f'<path d="M{px(b):.1f},{mt + ih} v4" stroke="{INK}"/>')
            s.append(f'<text x="{px(b):.1f}" y="{mt + ih + 16}" text-anchor="middle">{esc(number(b))}</text>')
    s.append(f'<text x="{ml + iw / 2:.1f}" y="{height - 8}" text-anchor="middle" fill="{MUTED}">{esc(xlabel)}</text>')
    if ylabel:
        s.append(f'<text transform="translate(13,{mt + ih / 2:.1f}) rotate(-90)" text-anchor="middle" '
                 f'fill="{MUTED}">{esc(ylabel)}</text>')
    s.append("</svg>")
    return "".join(s)


def stacked_bars(labels: list[str], series: list, xlabel: str, width: float = 600, bar: float = 22) -> str:
    """Horizontal bars, one a label, each cut into segments, one a series [name, colour, values]; the
    legend below, on as many lines as the names need."""
    size = 11
    ml = 12 + max((text_width(l, size) for l in labels), default=0)
    mr, mt = 16, 10
    iw = width - ml - mr
    totals = [sum(vals[i] for _, _, vals in series) for i in range(len(labels))]
    ticks = linear_ticks(max(totals, default=0), 6, integer=True)
    # the legend's lines
    lines, line, x = [], [], 0.0
    for name, colour, _ in series:
        w = 18 + text_width(name, size) + 16
        if line and x + w > width - 20:
            lines.append(line)
            line, x = [], 0.0
        line.append((name, colour, x))
        x += w
    if line:
        lines.append(line)
    ih = bar * len(labels) * 1.45
    height = mt + ih + 40 + 18 * len(lines) + 6

    def px(v: float) -> float:
        return ml + v / ticks[-1] * iw

    s = [svg_open(width, height, size)]
    for t in ticks:
        s.append(f'<path d="M{px(t):.1f},{mt} v{ih:.1f}" stroke="{GRID}"/>')
        s.append(f'<text x="{px(t):.1f}" y="{mt + ih + 15:.1f}" text-anchor="middle">{number(t)}</text>')
    for i, label in enumerate(labels):
        y = mt + bar * 1.45 * i + bar * 0.225
        s.append(f'<text x="{ml - 6:.1f}" y="{y + bar / 2 + 4:.1f}" text-anchor="end">{esc(label)}</text>')
        left = 0.0
        for name, colour, values in series:
            v = values[i]
            if v:
                s.append(f'<rect x="{px(left):.1f}" y="{y:.1f}" width="{px(left + v) - px(left):.1f}" '
                         f'height="{bar}" fill="{colour}" stroke="white"><title>{esc(label)}, {esc(name)}: '
                         f'{number(v)}</title></rect>')
            left += v
    s.append(f'<path d="M{ml},{mt} v{ih:.1f}" stroke="{INK}"/>')
    s.append(f'<text x="{ml + iw / 2:.1f}" y="{mt + ih + 32:.1f}" text-anchor="middle" fill="{MUTED}">'
             f'{esc(xlabel)}</text>')
    for k, entries in enumerate(lines):
        ly = mt + ih + 52 + 18 * k
        used = entries[-1][2] + 18 + text_width(entries[-1][0], size)
        ox = max(10.0, (width - used) / 2)
        for name, colour, x in entries:
            s.append(f'<rect x="{ox + x:.1f}" y="{ly - 9}" width="12" height="12" fill="{colour}"/>')
            s.append(f'<text x="{ox + x + 17:.1f}" y="{ly + 1}">{esc(name)}</text>')
    s.append("</svg>")
    return "".join(s)


def draw(chart: dict) -> str:
    """One chart from its description: {"kind": "hist", "values", "bins", "xlabel", "ylabel"} or
    {"kind": "bars", "labels", "series": [[name, colour, values]], "xlabel"}."""
    if chart["kind"] == "hist":
        return hist(chart["values"], chart["bins"], chart["xlabel"], chart.get("ylabel", ""))
    if chart["kind"] == "bars":
        return stacked_bars(chart["labels"], chart["series"], chart["xlabel"])
    raise ValueError(f"no chart of kind {chart['kind']!r}")

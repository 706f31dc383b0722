"""A picture of one sphere or rectangle case: what the ray, the shape and the answers look like.

The judge records the geometry of a case's first failing check (tests/support/case_figure.hpp): the
function called, the ray, the sphere or rectangle, the window [tmin, tmax] when the function has one,
the expected answer and the student's. This module draws it as an SVG and says in one line what the
picture shows. Standard library only.

How a 3-D case becomes a flat picture:
- a sphere: the plane that holds the ray and the sphere's centre cuts the sphere in a great circle
  (same centre, same radius), and the ray lies in that plane, so the picture is exact, not a
  projection. Its axes: x along the ray's direction, y towards the centre. When the centre is on the
  ray's line any plane holding the line will do; with a zero direction, any plane through the origin
  and the centre.
- a rectangle: two views. Face on (the plane seen from its normal): the rectangle as it is, the ray
  projected onto the plane. Side on (the plane holding the ray and the normal): the rectangle is a
  segment at its offset, and the ray is drawn exactly, which is where a ray parallel to the plane, or
  nearly so, shows why it misses.

The t of each answer is placed on the ray at o + t d. A number too large or too small to fit beside
the shape (an origin a million units away, a t of 1e30) is not drawn to scale: the view is the shape
and the hits, and what lies outside it is named in a note on the picture.
"""

from __future__ import annotations

import math
import re
import struct
from fractions import Fraction
from pathlib import Path


def escape(text: str) -> str:
    """Text for an SVG element's content: &, < and > as entities. Not xml.sax.saxutils.escape, which
    imports urllib.request (and with it http.client, ssl and email) into every ./kit check, for three
    replacements."""
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


from . import atomic

WIDTH = 600                 # px; every text is at least 12 px at this width
PANEL_MAX_HEIGHT = 420
PANEL_MIN_HEIGHT = 220
FAR = 20.0                  # a point more than FAR view sizes from the shape is named, not drawn
NEARLY_PARALLEL = 0.05      # |d[axis]| / |d| below this: the ray runs (nearly) along the rectangle's plane

EXPECTED_COLOUR = "#1b7f3b"
GOT_COLOUR = "#c62828"
WINDOW_COLOUR = "#f2a900"
RAY_COLOUR = "#1f4e99"
SHAPE_COLOUR = "#555555"

AXES = "xyz"


class PictureError(ValueError):
    """The figure cannot be drawn; the message says why, for the student."""


# --- numbers and vectors -------------------------------------------------------------------------

def f32(x: float) -> float:
    """x rounded to the nearest float. The judge's inputs and answers are floats, sent as their shortest
    text ("-30000.008"): read as a double, that text is another number (-30000.008, not the float
    -30000.0078125), and a ray that misses by 6e-6 would be drawn through the sphere."""
    if not math.isfinite(x):
        return x
    try:
        return struct.unpack("<f", struct.pack("<f", x))[0]
    except OverflowError:               # beyond the largest float
        return math.copysign(math.inf, x)


def num(value) -> float:
    """A number of the judge's JSON (a float): a number, or "inf", "-inf", "NaN" as text."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise PictureError(f"{value!r} is not a number")
    try:
        return f32(float(value))
    except ValueError:
        raise PictureError(f"{value!r} is not a number") from None


def ulps_apart(a: float, b: float) -> int:
    """How many floats lie between a and b, plus one (0 when equal)."""
    def key(x):
        i = struct.unpack("<i", struct.pack("<f", x))[0]
        return i if i >= 0 else -(i & 0x7fffffff)
    return abs(key(a) - key(b))


def vec(value, n: int = 3) -> tuple:
    if not isinstance(value, list) or len(value) != n:
        raise PictureError(f"{value!r} is not a vector of {n} numbers")
    return tuple(num(v) for v in value)


def fmt(x: float) -> str:
    """Short text of a number: 2, 0.5, 1e+30, inf, NaN."""
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    if x == int(x) and abs(x) < 1e7:
        return str(int(x))
    if f32(x) == x:          # a float: its shortest text, as the judge's text prints it
        for digits in range(1, 10):
            text = f"{x:.{digits}g}"
            if f32(float(text)) == x:
                return text
    return repr(x)           # the shortest text that reads back as the same number


def fmt_vec(v) -> str:
    return "(" + ", ".join(fmt(c) for c in v) + ")"


def fmt_point(v) -> str:
    """A point the picture computed (o + t d, in doubles): 7 significant digits, about a float's."""
    return "(" + ", ".join(fmt(c) if not math.isfinite(c) or c == int(c) else format(c, ".7g") for c in v) + ")"


def add(a, b):
    return tuple(p + q for p, q in zip(a, b))


def sub(a, b):
    return tuple(p - q for p, q in zip(a, b))


def scale(a, s: float):
    return tuple(p * s for p in a)


def inner(a, b) -> float:
    return sum(p * q for p, q in zip(a, b))


def norm(a) -> float:
    return math.hypot(*a)


def unit(a):
    n = norm(a)
    return scale(a, 1.0 / n) if n > 0 and math.isfinite(n) else None


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def perpendicular(u):
    """A unit vector at right angles to unit vector u: crossed with the axis u leans on least."""
    k = min(range(3), key=lambda i: abs(u[i]))
    axis = tuple(1.0 if i == k else 0.0 for i in range(3))
    return unit(cross(u, axis))


def finite(*values) -> bool:
    return all(math.isfinite(v) for v in values)


# --- the size of a text ---------------------------------------------------------------------------
#
# The advance widths of DejaVu Sans and DejaVu Sans Bold (the pictures' first font), in thousandths of
# an em, for the characters ' ' to '~'; any other character counts a full em. A fallback font
# (Arial) is narrower, so a layout that fits these widths fits it too.

_ADVANCE = {False: (
    318, 401, 460, 838, 636, 950, 780, 275, 390, 390, 500, 838, 318, 361, 318, 337, 636, 636, 636,
    636, 636, 636, 636, 636, 636, 636, 337, 337, 838, 838, 838, 531, 1000, 684, 686, 698, 770, 632,
    575, 775, 752, 295, 295, 656, 557, 863, 748, 787, 603, 787, 695, 635, 611, 732, 684, 989, 685,
    611, 685, 390, 337, 390, 838, 500, 500, 613, 635, 550, 635, 615, 352, 635, 634, 278, 278, 579,
    278, 974, 634, 612, 635, 635, 411, 521, 392, 634, 592, 818, 592, 592, 525, 636, 337, 636, 838,
), True: (
    348, 456, 521, 838, 696, 1002, 872, 306, 457, 457, 523, 838, 380, 415, 380, 365, 696, 696, 696,
    696, 696, 696, 696, 696, 696, 696, 400, 400, 838, 838, 838, 580, 1000, 774, 762, 734, 830, 683,
    683, 821, 837, 372, 372, 775, 637, 995, 837, 850, 733, 850, 770, 720, 682, 812, 774, 1103, 771,
    724, 725, 457, 365, 457, 838, 500, 500, 675, 716, 593, 716, 678, 435, 716, 712, 343, 343, 665,
    343, 1042, 712, 687, 716, 716, 493, 595, 478, 712, 652, 924, 645, 652, 582, 712, 365, 712, 838,
)}


def text_width(text: str, size: float, bold: bool = False) -> float:
    table = _ADVANCE[bold]
    return size / 1000 * sum(table[ord(c) - 32] if 32 <= ord(c) < 127 else 1000 for c in text)


def text_box(x: float, y: float, text: str, size: float, anchor: str = "start", bold: bool = False) -> tuple:
    """(x0, y0, x1, y1) of a text whose baseline starts, is centred or ends (anchor) at (x, y)."""
    w = text_width(text, size, bold)
    x0 = x - w / 2 if anchor == "middle" else x - w if anchor == "end" else x
    return (x0, y - 0.76 * size, x0 + w, y + 0.24 * size)


def overlap(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def wrap_px(text: str, size: float, width: float, bold: bool = False) -> list:
    """The text in lines no wider than `width` pixels at font size `size` (a word longer than a line
    is cut with an ellipsis). A bracket's contents stay on one line: "[0, inf]" is not broken."""
    text = re.sub(r"\[[^\]]*\]", lambda m: m.group(0).replace(" ", "\u00a0"), text)
    out, line = [], ""
    for word in text.split(" "):
        if not word:
            continue
        while text_width(word, size, bold) > width:
            cut = len(word) - 1
            while cut > 1 and text_width(word[:cut] + "…", size, bold) > width:
                cut -= 1
            word = word[:cut] + "…"
        joined = f"{line} {word}" if line else word
        if line and text_width(joined, size, bold) > width:
            out.append(line)
            line = word
        else:
            line = joined
    return out + ([line] if line else [])


# --- what a case says ----------------------------------------------------------------------------

class Case:
    """The figure of one case, read and checked."""

    def __init__(self, figure: dict):
        if not isinstance(figure, dict):
            raise PictureError("the case has no geometry")
        self.function = str(figure.get("function", ""))
        ray = figure.get("ray")
        if not isinstance(ray, dict):
            raise PictureError("the case has no ray")
        self.origin, self.direction = vec(ray.get("origin")), vec(ray.get("direction"))
        self.sphere = self.rect = None
        if "rect" in figure:
            r = figure["rect"]
            if not isinstance(r, dict):
                raise PictureError("the rectangle is not readable")
            axis = num(r.get("axis"))
            self.rect = (int(axis) if axis in (0, 1, 2) else -1, num(r.get("offset")),
                         vec(r.get("lo"), 2), vec(r.get("hi"), 2))
        elif "sphere" in figure:
            s = figure["sphere"]
            if not isinstance(s, dict):
                raise PictureError("the sphere is not readable")
            self.sphere = (vec(s.get("center")), num(s.get("radius")))
        elif "unit_sphere" in self.function:
            self.sphere = ((0.0, 0.0, 0.0), 1.0)      # step 01: the unit sphere at the origin
        else:
            raise PictureError("the case has neither a sphere nor a rectangle")
        window = figure.get("window")
        self.window = None if window is None else vec(window, 2)
        self.roots = self.window is None     # *_roots: every root of the whole line, no window
        self.expected = self.answer(figure.get("expected"))
        self.got = self.answer(figure.get("got"))

    def answer(self, value) -> dict:
        """{"ts": the t values, "count": count as sent (roots) or None, "valid": contract kept}."""
        if self.roots:
            if not isinstance(value, dict):
                raise PictureError("an answer of roots is not readable")
            count = num(value.get("count"))
            ts = vec(value.get("t"), 2)
            if count not in (0, 1, 2):
                return {"ts": [], "count": count, "valid": False}
            return {"ts": list(ts[:int(count)] if count != 1 else ts[:1]), "count": int(count), "valid": True}
        if value is None:
            return {"ts": [], "count": None, "valid": True}
        return {"ts": [num(value)], "count": None, "valid": True}

    def point(self, t: float):
        return add(self.origin, scale(self.direction, t))


def answer_text(case: Case, a: dict) -> str:
    """An answer in the words of the judge's text (tests/support/grading.hpp: show), so the picture's
    caption reads as the failure it draws: "2 roots: t = 1 and 3", "no roots", "a hit at t = 2"."""
    if not a["valid"]:
        return f"count {fmt(a['count'])} (not 0, 1 or 2)"
    ts = a["ts"]
    if not ts:
        return "no roots" if case.roots else "no hit"
    if case.roots:
        return f"1 root: t = {fmt(ts[0])}" if a["count"] == 1 else f"2 roots: t = {fmt(ts[0])} and {fmt(ts[1])}"
    return f"a hit at t = {fmt(ts[0])}"


def direction_text(d) -> str:
    """'+x' for a unit axis direction, else the vector."""
    for i in range(3):
        if abs(d[i]) == 1 and all(d[j] == 0 for j in range(3) if j != i):
            return ("+" if d[i] > 0 else "-") + AXES[i]
    return fmt_vec(d)


def shape_text(case: Case) -> str:
    if case.rect is not None:
        axis, offset, lo, hi = case.rect
        if axis < 0:
            return "a rectangle with no valid axis"
        u, v = [AXES[i] for i in range(3) if i != axis]
        return (f"rectangle {AXES[axis]} = {fmt(offset)}, {u} in [{fmt(lo[0])}, {fmt(hi[0])}], "
                f"{v} in [{fmt(lo[1])}, {fmt(hi[1])}]")
    centre, radius = case.sphere
    if "unit_sphere" in case.function:
        return "unit sphere"
    return f"sphere at {fmt_vec(centre)} radius {fmt(radius)}"


def summary(figure: dict) -> str:
    """One line: what the picture shows (raises PictureError when the figure is not readable)."""
    case = Case(figure)
    return summary_of(case)


def summary_of(case: Case) -> str:
    where = "roots of the whole line" if case.roots else \
        f"window [{fmt(case.window[0])}, {fmt(case.window[1])}]"
    got = answer_text(case, case.got)
    return (f"ray from {fmt_vec(case.origin)} along {direction_text(case.direction)}, {shape_text(case)}, "
            f"{where}: expected {answer_text(case, case.expected)}, got {got}")


# --- a panel: world coordinates (y up) to pixels ---------------------------------------------------

class Panel:
    """One view: a 2-D box of the world drawn into a box of the picture, with one scale for x and y."""

    def __init__(self, title: str, core: list, extra: list, top: float, width: float = WIDTH):
        self.title = title
        self.notes: list[str] = []
        pts = [p for p in core if finite(*p)]
        lo_x, hi_x, lo_y, hi_y = bounds(pts) if pts else (-1.0, 1.0, -1.0, 1.0)
        size = max(hi_x - lo_x, hi_y - lo_y)
        if not size > 0:
            size = max(1.0, abs(lo_x), abs(lo_y)) * 1.0 if pts else 2.0
            size = size if size > 0 and math.isfinite(size) else 2.0
        cx, cy = (lo_x + hi_x) / 2, (lo_y + hi_y) / 2
        lo_x, hi_x, lo_y, hi_y = min(lo_x, cx - size / 2), max(hi_x, cx + size / 2), \
            min(lo_y, cy - size / 10), max(hi_y, cy + size / 10)
        # What else fits without shrinking the shape to a dot; the rest is named, not drawn.
        self.off: list[tuple] = []
        for label, p, where in extra:
            if not finite(*p):
                continue
            if abs(p[0] - cx) <= FAR * size and abs(p[1] - cy) <= FAR * size:
                lo_x, hi_x = min(lo_x, p[0]), max(hi_x, p[0])
                lo_y, hi_y = min(lo_y, p[1]), max(hi_y, p[1])
            elif label:         # the answers say so themselves when they fall outside
                self.off.append((label, where))
        pad_x, pad_y = 0.12 * (hi_x - lo_x), 0.12 * (hi_y - lo_y)
        self.view = (lo_x - pad_x, hi_x + pad_x, lo_y - pad_y, hi_y + pad_y)
        vw, vh = self.view[1] - self.view[0], self.view[3] - self.view[2]
        # A shape of size 2 at 1e30 has no width in doubles (1e30 + 1 == 1e30): nothing to draw to scale.
        if not (vw > 0 and vh > 0 and math.isfinite(vw) and math.isfinite(vh)
                and vw > 1e-9 * max(abs(lo_x), abs(hi_x)) and vh > 1e-9 * max(abs(lo_y), abs(hi_y))):
            raise PictureError(f"the shape, {fmt(size)} across at {fmt_point((cx, cy))} in the picture's plane, "
                               "is too small beside its coordinates to draw to scale")
        self.title_lines = wrap_px(title, 13, width - 20.0)
        self.left, self.top, self.width = 10.0, top + 22.0 + 16 * (len(self.title_lines) - 1), width - 20.0
        # One scale for both axes (a circle stays round), the height kept between its limits:
        # the view grows in the short direction to fill the panel.
        self.height = min(max(vh * self.width / vw, PANEL_MIN_HEIGHT), PANEL_MAX_HEIGHT)
        self.scale = min(self.width / vw, self.height / vh)
        grow_x, grow_y = (self.width / self.scale - vw) / 2, (self.height / self.scale - vh) / 2
        self.view = (self.view[0] - grow_x, self.view[1] + grow_x, self.view[2] - grow_y, self.view[3] + grow_y)
        self.offset_x = self.left
        self.items: list[str] = []
        self.labels: list[tuple] = []     # the boxes of the labels placed (x0, y0, x1, y1)
        self.marks: list[tuple] = []      # the boxes of the marks (answers, origin, centre): labels avoid them

    @property
    def bottom(self) -> float:
        return self.top + self.height

    def px(self, p) -> tuple:
        return (self.offset_x + (p[0] - self.view[0]) * self.scale,
                self.top + (self.view[3] - p[1]) * self.scale)

    def inside(self, p) -> bool:
        return finite(*p) and self.view[0] <= p[0] <= self.view[1] and self.view[2] <= p[1] <= self.view[3]

    def clip(self, a, b, t0: float, t1: float):
        """The part of the line a + s b, s in [t0, t1] (either may be infinite), inside the view:
        (s_start, s_end) or None. Found by search, not by solving for where the line crosses the
        view's sides: that is step 04's formula, and no code that ships outside steps/ may compute it.
        The part inside a box is one interval of s (the box is convex): sample the stretch of the line
        that can reach the view, then narrow down each end by bisection."""
        length = norm(b)
        if not length > 0 or not math.isfinite(length):
            return None
        x0, x1, y0, y1 = self.view
        middle = ((x0 + x1) / 2, (y0 + y1) / 2)
        nearest = inner(sub(middle, a), b) / (length * length)   # the s closest to the view's middle
        reach = math.hypot(x1 - x0, y1 - y0) / length
        lo, hi = max(t0, nearest - reach), min(t1, nearest + reach)
        if not lo <= hi:
            return None
        n = 200     # a chord shorter than 1/200 of the searched stretch (a corner grazed) is not drawn
        ss = [lo + (hi - lo) * i / n for i in range(n + 1)]
        flags = [self.inside(add(a, scale(b, v))) for v in ss]
        if not any(flags):
            return None
        first, last = flags.index(True), n - flags[::-1].index(True)
        return (self._edge(a, b, ss[first - 1], ss[first]) if first > 0 else ss[first],
                self._edge(a, b, ss[last + 1], ss[last]) if last < n else ss[last])

    def _edge(self, a, b, outside: float, inside: float) -> float:
        """Bisection between a parameter outside the view and one inside, to far below a pixel."""
        for _ in range(60):
            mid = (outside + inside) / 2
            if self.inside(add(a, scale(b, mid))):
                inside = mid
            else:
                outside = mid
        return inside

    def line(self, a, b, t0, t1, colour, width, dash="", opacity=1.0, arrow=False) -> bool:
        s = self.clip(a, b, t0, t1)
        if s is None:
            return False
        (x0, y0), (x1, y1) = self.px(add(a, scale(b, s[0]))), self.px(add(a, scale(b, s[1])))
        extra = f' stroke-dasharray="{dash}"' if dash else ""
        extra += f' opacity="{opacity}"' if opacity != 1.0 else ""
        extra += ' marker-end="url(#arrow)"' if arrow else ""
        self.items.append(f'<line x1="{x0:.2f}" y1="{y0:.2f}" x2="{x1:.2f}" y2="{y1:.2f}" stroke="{colour}" '
                          f'stroke-width="{width}" stroke-linecap="round"{extra}/>')
        return True

    def mark(self, x: float, y: float, r: float) -> None:
        self.marks.append((x - r, y - r, x + r, y + r))

    def fits(self, box) -> bool:
        x0, y0, x1, y1 = box
        return (self.left + 2 <= x0 and x1 <= self.left + self.width - 2 and self.top + 2 <= y0
                and y1 <= self.bottom - 2 and not any(overlap(box, b) for b in self.labels + self.marks))

    def label(self, x: float, y: float, text: str, colour="#222", size=13, weight="normal", spots=None) -> bool:
        """Writes `text` near pixel (x, y), at the first of `spots` ((dx, dy, anchor) from the point, dy
        to the baseline) whose box lies inside the panel and clear of every label and mark placed
        before. None fits: nothing is written and False returned, and the caller says it in a note."""
        bold = weight == "bold"
        for dx, dy, anchor in (spots or around()):
            box = text_box(x + dx, y + dy, text, size, anchor, bold)
            if self.fits(box):
                self.labels.append(box)
                self.items.append(f'<text x="{x + dx:.1f}" y="{y + dy:.1f}" fill="{colour}" font-size="{size}" '
                                  f'text-anchor="{anchor}" font-weight="{weight}">{escape(text)}</text>')
                return True
        return False

    def svg(self) -> str:
        clip_id = f"c{int(self.top)}"
        n = len(self.title_lines)
        head = [f'<text x="{self.left}" y="{self.top - 7 - 16 * (n - 1 - i):.1f}" font-size="13" fill="#444">'
                f'{escape(line)}</text>' for i, line in enumerate(self.title_lines)]
        head += [f'<rect x="{self.left}" y="{self.top:.1f}" width="{self.width}" height="{self.height:.1f}" '
                f'fill="#fbfbf8" stroke="#bbb"/>',
                f'<clipPath id="{clip_id}"><rect x="{self.left}" y="{self.top:.1f}" width="{self.width}" '
                f'height="{self.height:.1f}"/></clipPath>', f'<g clip-path="url(#{clip_id})">']
        return "\n".join(head + self.items + ["</g>"])


def around(gap: float = 8.0) -> list:
    """The places a label may take around its point, nearest first: above, below, right, left, then
    the same further out."""
    out = []
    for k in range(4):
        g = gap + 15 * k
        out += [(0, -g, "middle"), (0, g + 10, "middle"), (g, 5, "start"), (-g, 5, "end"),
                (g, -g, "start"), (-g, -g, "end"), (g, g + 10, "start"), (-g, g + 10, "end")]
    return out


def bounds(points: list) -> tuple:
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    return min(xs), max(xs), min(ys), max(ys)


# --- drawing the ray, the window and the answers in a panel ----------------------------------------

ABOVE = [(0, -12, "middle"), (0, -27, "middle"), (12, -12, "start"), (-12, -12, "end"), (0, -42, "middle"),
         (12, -27, "start"), (-12, -27, "end")]
BELOW = [(0, 22, "middle"), (0, 37, "middle"), (12, 22, "start"), (-12, 22, "end"), (0, 52, "middle"),
         (12, 37, "start"), (-12, 37, "end")]


def draw_ray(panel: Panel, o2, d2, case: Case, at) -> None:
    """The line faint, the ray (t >= 0) solid with an arrow, the window thick, the answers marked and
    labelled, then the origin's and the window's labels where room is left.
    `at(t)` is the point of the panel at parameter t (o2 + t d2)."""
    moving = norm(d2) > 0
    window_labels = []
    if moving:
        panel.line(o2, d2, -math.inf, math.inf, RAY_COLOUR, 1, dash="4 4", opacity=0.6)
        if case.window is not None:
            tmin, tmax = case.window
            if tmin <= tmax:
                if not panel.line(o2, d2, tmin, tmax, WINDOW_COLOUR, 9, opacity=0.7):
                    panel.notes.append(f"the window [{fmt(tmin)}, {fmt(tmax)}] lies outside the view")
                for t, name in ((tmin, "tmin"), (tmax, "tmax")):
                    p = at(t)
                    if math.isfinite(t) and panel.inside(p):
                        window_labels.append((panel.px(p), f"{name} = {fmt(t)}"))
            else:
                panel.notes.append(f"the window is empty: tmin = {fmt(tmin)} > tmax = {fmt(tmax)}")
        panel.line(o2, d2, 0.0, math.inf, RAY_COLOUR, 2, arrow=True)
    origin = None
    if panel.inside(o2):
        x, y = origin = panel.px(o2)
        panel.items.append(f'<circle cx="{x:.2f}" cy="{y:.2f}" r="4" fill="{RAY_COLOUR}"/>')
        panel.mark(x, y, 5)
        if moving:      # a short arrow of fixed size from the origin: the direction, whatever |d|
            u = unit((d2[0], -d2[1]))
            panel.items.append(f'<line x1="{x:.2f}" y1="{y:.2f}" x2="{x + 34 * u[0]:.2f}" y2="{y + 34 * u[1]:.2f}" '
                               f'stroke="{RAY_COLOUR}" stroke-width="3" marker-end="url(#arrow)"/>')
    mark_answers(panel, case, at)
    if origin is not None:
        x, y = origin
        if not panel.label(x, y, "o", colour=RAY_COLOUR, weight="bold",
                           spots=[(-8, -6, "end"), (-8, 14, "end"), (0, -10, "middle"), (0, 20, "middle")] + around(12)):
            panel.notes.append(f"the origin o is the blue dot at {fmt_vec(case.origin)}")
    for (x, y), text in window_labels:     # above the answers' labels, the thick stroke's end
        if not panel.label(x, y, text, colour="#9a6b00", size=12,
                           spots=[(4, -32, "start"), (-4, -32, "end"), (4, -47, "start"), (-4, -47, "end")] + around(20)):
            panel.notes.append(f"the window's {text} (no room for its label in the view)")


def mark_answers(panel: Panel, case: Case, at) -> None:
    """A green dot for each expected t, a red cross for each of the student's; then their labels,
    expected above the ray and the student's below where there is room. Two answers closer than a
    few pixels cannot be told apart: a note says how far apart they are, in ulps and in units."""
    shown = []      # (who, t, x, y)
    for who, a, colour in (("expected", case.expected, EXPECTED_COLOUR), ("got", case.got, GOT_COLOUR)):
        for t in a["ts"]:
            p = at(t)
            if not math.isfinite(t):
                panel.notes.append(f"{who} t = {fmt(t)}: no point to draw")
                continue
            if not panel.inside(p):
                if all(math.isfinite(c) for c in p):
                    panel.notes.append(f"{who} t = {fmt(t)} is at {fmt_point(case.point(t))}, outside the view")
                else:
                    panel.notes.append(f"{who} t = {fmt(t)}: no point to draw")
                continue
            x, y = panel.px(p)
            if any(q[0] == who and q[1] == t for q in shown):
                continue            # the same root twice (a tangent): one mark, its label says so
            if who == "expected":
                panel.items.append(f'<circle cx="{x:.2f}" cy="{y:.2f}" r="6" fill="{colour}"/>')
            else:
                panel.items.append(f'<path d="M{x - 7:.2f},{y - 7:.2f}L{x + 7:.2f},{y + 7:.2f}'
                                   f'M{x - 7:.2f},{y + 7:.2f}L{x + 7:.2f},{y - 7:.2f}" stroke="{colour}" '
                                   f'stroke-width="3"/>')
            panel.mark(x, y, 7)
            shown.append((who, t, x, y))
    for who, t, x, y in shown:
        a = case.expected if who == "expected" else case.got
        twice = sum(1 for v in a["ts"] if v == t) > 1
        text = f"t = {fmt(t)}" + (" (twice)" if twice else "")
        spots = (ABOVE + BELOW if who == "expected" else BELOW + ABOVE) + around(30)
        if not panel.label(x, y, text, colour=EXPECTED_COLOUR if who == "expected" else GOT_COLOUR,
                           weight="bold", spots=spots):
            panel.notes.append(f"{'expected' if who == 'expected' else 'your'} t = {fmt(t)} is marked without "
                               "its label (no room beside the other marks)")
    for who, t, x, y in shown:
        if who != "got":
            continue
        near = [(math.hypot(x - ex, y - ey), e) for w, e, ex, ey in shown if w == "expected" and e != t]
        if near and not any(w == "expected" and e == t for w, e, _, _ in shown):
            dist, e = min(near)
            if dist < 4:
                panel.notes.append(f"your t = {fmt(t)} and the expected t = {fmt(e)} are {ulps_apart(t, e)} ulps "
                                   f"apart ({abs(t - e):.2g}), {dist:.1f} pixels in this picture: their marks "
                                   "cover each other")


def extras(case: Case, at) -> list:
    """What a view shows when it fits beside the shape: (label for a note, point of the view, 3-D point).
    The student's answers have no label: mark_answers names them when they fall outside."""
    out = [("the origin", at(0.0), case.origin)]
    out += [(None, at(t), None) for t in case.got["ts"] if math.isfinite(t)]
    if case.window is not None:
        out += [(f"the window's {name} = {fmt(t)}", at(t), case.point(t))
                for name, t in zip(("tmin", "tmax"), case.window) if math.isfinite(t)]
    return out


# --- the two kinds of case ----------------------------------------------------------------------

def line_and_centre(o, d, centre):
    """Where the sphere's centre lies beside the ray's line, exactly: (x, y, y2), with x = |d| t of the
    foot of the perpendicular from the centre, y its distance from the line, y2 = y^2 as a Fraction.
    From the float inputs in rational arithmetic, rounded once at the end: the judge's expected
    answers are exact too, so a ray the judge says misses is drawn outside the circle, however thin
    the gap (in doubles, |f|^2 - h^2/a loses every digit of a 0.01 gap at 130000 units)."""
    f = [Fraction(c) - Fraction(p) for c, p in zip(centre, o)]
    dd = [Fraction(v) for v in d]
    a = sum(v * v for v in dd)
    h = sum(p * q for p, q in zip(f, dd))
    y2 = sum(v * v for v in f) - h * h / a
    return float(h / a) * math.sqrt(float(a)), math.sqrt(float(y2)), y2


def sphere_panels(case: Case, top: float) -> list:
    centre, radius = case.sphere
    o, d = case.origin, case.direction
    if not finite(*o, *d, *centre, radius):
        raise PictureError("the ray or the sphere holds NaN or inf: there is no picture of it")
    notes = []
    dn = norm(d)
    r = abs(radius)
    gap = None
    if dn > 0:
        x, y, y2 = line_and_centre(o, d, centre)
        c2 = (x, y)
        title = "the plane holding the ray and the centre (x along the ray)"
        if y2 == 0:
            notes.append("the ray's line passes through the centre: any plane holding it would do")
        gap = (y - r, y2 - Fraction(r) ** 2)
        at = lambda t: (t * dn, 0.0)        # noqa: E731  on the ray's line, exactly o + t d
    else:
        notes.append("the direction is zero: there is no ray, only its origin")
        # The plane holding the origin and the centre, x as the world's x wherever it can be, so the
        # picture's left and right are the world's.
        u = (1.0, 0.0, 0.0)
        w = unit(sub(sub(centre, o), scale(u, inner(sub(centre, o), u)))) or (0.0, 1.0, 0.0)
        q = sub(centre, o)
        c2 = (inner(q, u), inner(q, w))
        title = "the plane holding the origin and the centre (x to the right, as the world's x)"
        at = lambda t: (0.0, 0.0)           # noqa: E731
    core = [(c2[0] - r, c2[1] - r), (c2[0] + r, c2[1] + r)]
    core += [at(t) for t in case.expected["ts"] if math.isfinite(t)]
    panel = Panel(title, core, extras(case, at), top)
    panel.notes += notes
    panel.shape, panel.ray = ("circle", c2, r if radius > 0 else 0.0), ((0.0, 0.0), (dn, 0.0), at)
    cx, cy = panel.px(c2)
    if radius > 0:
        panel.items.append(f'<circle cx="{cx:.2f}" cy="{cy:.2f}" r="{r * panel.scale:.2f}" fill="#e8eef7" '
                           f'stroke="{SHAPE_COLOUR}" stroke-width="2"/>')
        panel.items.append(f'<circle cx="{cx:.2f}" cy="{cy:.2f}" r="2.5" fill="{SHAPE_COLOUR}"/>')
    else:
        panel.notes.append(f"radius {fmt(radius)}: no sphere to draw, only its centre")
        panel.items.append(f'<circle cx="{cx:.2f}" cy="{cy:.2f}" r="3" fill="{SHAPE_COLOUR}"/>')
    panel.mark(cx, cy, 3)
    draw_ray(panel, (0.0, 0.0), (dn, 0.0), case, at)
    if gap is not None and radius > 0 and abs(gap[0]) * panel.scale < 3:
        # Too thin to see: say in words on which side of the surface the line passes.
        side = ("touches the sphere: its distance from the centre is the radius, exactly" if gap[1] == 0 else
                f"passes {format(c2[1], '.8g')} from the centre, {abs(gap[0]):.2g} "
                + ("outside the radius: it misses" if gap[1] > 0 else "inside the radius: it cuts the sphere")
                + f", by {abs(gap[0]) / r:.2g} of the radius, {abs(gap[0]) * panel.scale:.1f} pixels here")
        panel.notes.insert(0, "the ray's line " + side)
    panel.label(cx, cy, "centre", colour=SHAPE_COLOUR, size=12, spots=[(0, 16, "middle"), (0, -8, "middle")]
                + around(10))
    return [panel]


def rect_panels(case: Case, top: float) -> list:
    axis, offset, lo, hi = case.rect
    o, d = case.origin, case.direction
    if axis < 0:
        raise PictureError("the rectangle's axis is not 0, 1 or 2: it describes no rectangle")
    if not finite(*o, *d, offset, *lo, *hi):
        raise PictureError("the ray or the rectangle holds NaN or inf: there is no picture of it")
    iu, iv = [i for i in range(3) if i != axis]
    corners = [(lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])]
    names = (AXES[iu], AXES[iv])
    # Face on: (u, v) coordinates; the ray projected (its component along the normal dropped).
    o2, d2 = (o[iu], o[iv]), (d[iu], d[iv])

    def face(t):
        return (o2[0] + t * d2[0], o2[1] + t * d2[1])

    core = list(corners) + [face(t) for t in case.expected["ts"] if math.isfinite(t)]
    extra = extras(case, face)
    panels = []
    front = Panel(f"face on: the plane {AXES[axis]} = {fmt(offset)}, {names[0]} to the right, {names[1]} up; "
                  "the ray projected", core, extra, top)
    draw_rect(front, corners, lo, hi)
    if norm(d2) == 0:
        front.notes.append("face on, the ray is a point: it runs along the plane's normal")
    draw_ray(front, o2, d2, case, face)
    front.shape, front.ray = ("rect", corners, None), (o2, d2, face)
    rect_labels(front, corners, lo, hi)
    panels.append(front)
    # Side on: horizontal along the ray's in-plane direction h, vertical along the normal.
    h = unit(d2) or (1.0, 0.0)
    o_s, d_s = (inner(o2, h), o[axis]), (inner(d2, h), d[axis])

    def side(t):
        return (o_s[0] + t * d_s[0], o_s[1] + t * d_s[1])

    extent = [inner(c, h) for c in corners]
    seg = ((min(extent), offset), (max(extent), offset))
    core = [seg[0], seg[1]] + [side(t) for t in case.expected["ts"] if math.isfinite(t)]
    extra = extras(case, side)
    dn = norm(d)
    parallel = dn > 0 and abs(d[axis]) <= NEARLY_PARALLEL * dn
    horizontal = names[0] if h == (1.0, 0.0) else names[1] if h == (0.0, 1.0) else "along the ray"
    sideways = Panel(f"side on: {horizontal} to the right, {AXES[axis]} up; the rectangle edge-on"
                     + (" (the ray is parallel to it)" if d[axis] == 0 and dn > 0 else
                        " (the ray is nearly parallel to it)" if parallel else ""),
                     core, extra, front.bottom + 40)
    a, b = sideways.px(seg[0]), sideways.px(seg[1])
    sideways.items.append(f'<line x1="{a[0]:.2f}" y1="{a[1]:.2f}" x2="{b[0]:.2f}" y2="{b[1]:.2f}" '
                          f'stroke="{SHAPE_COLOUR}" stroke-width="5"/>')
    draw_ray(sideways, o_s, d_s, case, side)
    sideways.label(*b, f"{AXES[axis]} = {fmt(offset)}", colour=SHAPE_COLOUR, size=12,
                   spots=[(0, 18, "end"), (0, -8, "end"), (0, 18, "start"), (0, -8, "start")] + around(20))
    panels.append(sideways)
    if dn == 0:
        front.notes.append("the direction is zero: there is no ray, only its origin")
    return panels


def draw_rect(panel: Panel, corners, lo, hi) -> None:
    pts = [panel.px(c) for c in corners]
    if not (lo[0] <= hi[0] and lo[1] <= hi[1]):
        panel.notes.append("lo is greater than hi: the rectangle is empty (drawn dashed)")
    path = " ".join(f"{x:.2f},{y:.2f}" for x, y in pts)
    dash = "" if lo[0] <= hi[0] and lo[1] <= hi[1] else ' stroke-dasharray="6 4"'
    panel.items.append(f'<polygon points="{path}" fill="#e8eef7" stroke="{SHAPE_COLOUR}" stroke-width="2"{dash}/>')


def rect_labels(panel: Panel, corners, lo, hi) -> None:
    """The corners' labels, after the answers': below lo and above hi, else wherever there is room."""
    for corner, text, spots in ((corners[0], f"lo {fmt_vec(lo)}", [(0, 16, "start"), (0, 16, "end"), (0, -6, "start")]),
                                (corners[2], f"hi {fmt_vec(hi)}", [(0, -6, "end"), (0, -6, "start"), (0, 16, "end")])):
        x, y = panel.px(corner)
        if not panel.label(x, y, text, colour=SHAPE_COLOUR, size=12, spots=spots + around(20)):
            panel.notes.append(f"the rectangle's corner {text}")


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
    notes = []
    for p in panels:
        notes += p.notes
        notes += [f"{label}, at {fmt_point(q)}, is far outside the view: the view shows the shape and the hits"
                  for label, q in p.off]
    notes = list(dict.fromkeys(notes))
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
        out.append(mark(x, y))
        out.append(f'<text x="{x + room:.1f}" y="{y}" font-size="12.5">{escape(text)}</text>')
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


# --- the pictures of a grading ----------------------------------------------------------------------

def pictures_folder(build: Path, steps_dir=None, slot: int = 0) -> Path:
    """Where `./kit check` draws: build/pictures/ for the student's own steps/, and for `--steps DIR`
    a folder of that DIR's own, build/pictures-of/<DIR as a name>/, so checking another folder never
    replaces the pictures of the student's steps, nor those of a third folder."""
    if not steps_dir:
        return build / ("pictures" if slot == 0 else f"pictures-{slot}")
    name = re.sub(r"[^a-z0-9]+", "-", str(Path(steps_dir).resolve()).lower()).strip("-")
    return build / "pictures-of" / (name[-80:].strip("-") or "steps")      # the path's end tells folders apart


def draw_results(results, folder: Path, reveal: bool = False) -> int:
    """Draws every failing case of `results` (grade.StepResult) that recorded a figure into
    folder/stepNN/<case>.svg, and sets each case's picture (the path) and picture_summary.

    Each graded step's folder is emptied first, so what is there is this run's. A hidden case is drawn
    only with `reveal`: its picture would show its inputs. A figure that cannot be drawn gets no
    picture and a summary that says why; this never raises. Returns the number of pictures written."""
    written = 0
    for r in results:
        step_dir = folder / f"step{r.step.number}"
        if step_dir.is_dir():
            for old in step_dir.glob("*.svg"):
                old.unlink()
        used: set[str] = set()
        for c in r.cases:
            figure = getattr(c, "figure", None)
            if c.status == "pass" or not figure or (c.tier == "hidden" and not reveal):
                continue
            name = slug(c.name)
            while name in used:        # two names that differ only in punctuation
                name += "-2"
            used.add(name)
            path = step_dir / f"{name}.svg"
            title = f"Step {r.step.number} · {c.name}"
            try:
                drawn: list = []
                c.picture_summary = write(figure, title, path, drawn)
                c.sketch = drawn            # the picture in characters, for the terminal
                c.picture = str(path)
                written += 1
            except PictureError as e:
                c.picture, c.picture_summary = "", f"no picture: {e}"
            except OSError as e:
                c.picture, c.picture_summary = "", f"no picture: cannot write {path} ({e.strerror})"
    return written


# --- the gallery of classic pitfalls (docs/pitfalls.md) ------------------------------------------------
#
# Each is a case of a step's suite, with the wrong answer the slip gives; the expected answers are the
# suite's (the self-test checks each lies on the shape). `./kit docs` draws them, so they never go stale.

INF = "inf"
_THROUGH = {"origin": [-3, 0, 0], "direction": [1, 0, 0]}     # step 01's ray through the centre: roots 2 and 4
_WIDE = {"axis": 2, "offset": 5, "lo": [-3, -1], "hi": [3, 1]}  # step 04's rectangle z = 5

PITFALLS = [
    ("tangent", "A tangent is a hit",
     {"function": "intersect_unit_sphere", "ray": {"origin": [-2, 1, 0], "direction": [1, 0, 0]},
      "window": [0, INF], "expected": 2, "got": None}),
    ("origin-inside", "Origin inside the sphere: the hit is ahead",
     {"function": "intersect_unit_sphere", "ray": {"origin": [0, 0, 0], "direction": [0, 0, 1]},
      "window": [0, INF], "expected": 1, "got": -1}),
    ("sphere-behind", "A sphere behind the ray is no hit",
     {"function": "intersect_unit_sphere", "ray": {"origin": [3, 0, 0], "direction": [1, 0, 0]},
      "window": [0, INF], "expected": None, "got": -4}),
    ("window-ends", "The window is closed: a root at tmin counts",
     {"function": "intersect_unit_sphere", "ray": _THROUGH, "window": [2, 10], "expected": 2, "got": 4}),
    ("window-tmax", "Both roots beyond tmax: no hit",
     {"function": "intersect_unit_sphere", "ray": _THROUGH, "window": [0, 1], "expected": None, "got": 2}),
    ("rect-parallel", "A ray lying in the rectangle's plane is no hit",
     {"function": "intersect_rect", "ray": {"origin": [-10, 0, 5], "direction": [1, 0, 0]}, "rect": _WIDE,
      "window": [0, INF], "expected": None, "got": 0}),
]


def write_gallery(folder: Path) -> list:
    """Draws every pitfall into folder/pitfall-<name>.svg; returns the paths."""
    paths = []
    for name, title, figure in PITFALLS:
        path = folder / f"pitfall-{name}.svg"
        write(figure, title, path)
        paths.append(path)
    return paths

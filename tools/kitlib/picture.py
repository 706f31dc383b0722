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
import os
import re
from pathlib import Path
from xml.sax.saxutils import escape

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

def num(value) -> float:
    """A number of the judge's JSON: a number, or "inf", "-inf", "NaN" as text."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise PictureError(f"{value!r} is not a number")
    try:
        return float(value)
    except ValueError:
        raise PictureError(f"{value!r} is not a number") from None


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
    if not a["valid"]:
        return f"count {fmt(a['count'])} (not 0, 1 or 2)"
    ts = a["ts"]
    if not ts:
        return "no roots" if case.roots else "no hit"
    if case.roots and a["count"] == 1:
        return f"t={fmt(ts[0])} (one root)"
    return " and ".join(f"t={fmt(t)}" for t in ts)


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
    exp = case.expected["ts"]
    if case.got["valid"] and len(case.got["ts"]) < len(exp) and case.got["ts"]:
        got += " only"
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
        self.left, self.top, self.width = 10.0, top + 22.0, width - 20.0
        # One scale for both axes (a circle stays round), the height kept between its limits:
        # the view grows in the short direction to fill the panel.
        self.height = min(max(vh * self.width / vw, PANEL_MIN_HEIGHT), PANEL_MAX_HEIGHT)
        self.scale = min(self.width / vw, self.height / vh)
        grow_x, grow_y = (self.width / self.scale - vw) / 2, (self.height / self.scale - vh) / 2
        self.view = (self.view[0] - grow_x, self.view[1] + grow_x, self.view[2] - grow_y, self.view[3] + grow_y)
        self.offset_x = self.left
        self.items: list[str] = []

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

    def text(self, p, label: str, colour="#222", dy=0.0, anchor="middle", size=13, weight="normal"):
        """A label at world point p, moved dy pixels down."""
        x, y = self.px(p)
        self.text_at(x, y, label, colour, dy, anchor, size, weight)

    def text_at(self, x, y, label: str, colour="#222", dy=0.0, anchor="middle", size=13, weight="normal"):
        """A label at pixel (x, y), kept inside the panel."""
        x = min(max(x, self.left + 4), self.left + self.width - 4)
        if anchor == "start":       # about 7 px a character at 12-13 px: keep the whole label inside
            x = min(x, self.left + self.width - 4 - 7 * len(label))
        elif anchor == "middle":
            half = 3.6 * len(label)
            x = min(max(x, self.left + half), self.left + self.width - half)
        self.items.append(f'<text x="{x:.1f}" y="{y + dy:.1f}" fill="{colour}" font-size="{size}" '
                          f'text-anchor="{anchor}" font-weight="{weight}">{escape(label)}</text>')

    def svg(self) -> str:
        clip_id = f"c{int(self.top)}"
        head = [f'<text x="{self.left}" y="{self.top - 7:.1f}" font-size="13" fill="#444">{escape(self.title)}</text>',
                f'<rect x="{self.left}" y="{self.top:.1f}" width="{self.width}" height="{self.height:.1f}" '
                f'fill="#fbfbf8" stroke="#bbb"/>',
                f'<clipPath id="{clip_id}"><rect x="{self.left}" y="{self.top:.1f}" width="{self.width}" '
                f'height="{self.height:.1f}"/></clipPath>', f'<g clip-path="url(#{clip_id})">']
        return "\n".join(head + self.items + ["</g>"])


def bounds(points: list) -> tuple:
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    return min(xs), max(xs), min(ys), max(ys)


# --- drawing the ray, the window and the answers in a panel ----------------------------------------

def draw_ray(panel: Panel, o2, d2, case: Case, at) -> None:
    """The line faint, the ray (t >= 0) solid with an arrow, the window thick, the answers marked.
    `at(t)` is the point of the panel at parameter t (o2 + t d2)."""
    moving = norm(d2) > 0
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
                        x, y = panel.px(p)      # above the answers' labels (expected above, got below)
                        panel.text_at(x + 4, y, f"{name} = {fmt(t)}", colour="#9a6b00", dy=-32, anchor="start",
                                      size=12)
            else:
                panel.notes.append(f"the window is empty: tmin = {fmt(tmin)} > tmax = {fmt(tmax)}")
        panel.line(o2, d2, 0.0, math.inf, RAY_COLOUR, 2, arrow=True)
    if panel.inside(o2):
        x, y = panel.px(o2)
        panel.items.append(f'<circle cx="{x:.2f}" cy="{y:.2f}" r="4" fill="{RAY_COLOUR}"/>')
        panel.text_at(x - 7, y, "o", colour=RAY_COLOUR, dy=-6, anchor="end", weight="bold")
        if moving:      # a short arrow of fixed size from the origin: the direction, whatever |d|
            u = unit((d2[0], -d2[1]))
            panel.items.append(f'<line x1="{x:.2f}" y1="{y:.2f}" x2="{x + 34 * u[0]:.2f}" y2="{y + 34 * u[1]:.2f}" '
                               f'stroke="{RAY_COLOUR}" stroke-width="3" marker-end="url(#arrow)"/>')
    mark_answers(panel, case, at)


def mark_answers(panel: Panel, case: Case, at) -> None:
    placed: list[tuple] = []
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
            if who == "expected":
                panel.items.append(f'<circle cx="{x:.2f}" cy="{y:.2f}" r="6" fill="{colour}"/>')
            else:
                panel.items.append(f'<path d="M{x - 7:.2f},{y - 7:.2f}L{x + 7:.2f},{y + 7:.2f}'
                                   f'M{x - 7:.2f},{y + 7:.2f}L{x + 7:.2f},{y - 7:.2f}" stroke="{colour}" '
                                   f'stroke-width="3"/>')
            # Expected above the ray, the student's below; a second label at the same place moves on.
            near = sum(1 for q in placed if abs(q[0] - x) < 40 and q[2] == who)
            dy = (-14 - 15 * near) if who == "expected" else (24 + 15 * near)
            panel.text_at(x, y, f"t = {fmt(t)}", colour=colour, dy=dy, weight="bold")
            placed.append((x, y, who))


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

def sphere_panels(case: Case, top: float) -> list:
    centre, radius = case.sphere
    o, d = case.origin, case.direction
    if not finite(*o, *d, *centre, radius):
        raise PictureError("the ray or the sphere holds NaN or inf: there is no picture of it")
    notes = []
    u = unit(d)
    if u is None:
        notes.append("the direction is zero: there is no ray, only its origin")
        u = unit(sub(centre, o)) or (1.0, 0.0, 0.0)
    w = unit(sub(sub(centre, o), scale(u, inner(sub(centre, o), u))))
    # An offset this small (in doubles, from float inputs) is rounding: the centre is on the ray's line, any plane holding it will do.
    if w is None or norm(sub(sub(centre, o), scale(u, inner(sub(centre, o), u)))) <= 1e-12 * max(
            norm(sub(centre, o)), abs(radius), 1e-30):
        w = perpendicular(u)
        if norm(d) > 0:
            notes.append("the ray's line passes through the centre: any plane holding it would do")

    def flat(p):
        q = sub(p, o)
        return (inner(q, u), inner(q, w))

    c2 = flat(centre)
    dn = norm(d)
    r = abs(radius)
    core = [(c2[0] - r, c2[1] - r), (c2[0] + r, c2[1] + r)]
    core += [flat(case.point(t)) for t in case.expected["ts"] if math.isfinite(t)]
    extra = extras(case, lambda t: flat(case.point(t)))
    title = "the plane holding the ray and the centre (x along the ray)"
    panel = Panel(title, core, extra, top)
    panel.notes += notes
    if radius > 0:
        x, y = panel.px(c2)
        panel.items.append(f'<circle cx="{x:.2f}" cy="{y:.2f}" r="{r * panel.scale:.2f}" fill="#e8eef7" '
                           f'stroke="{SHAPE_COLOUR}" stroke-width="2"/>')
        panel.items.append(f'<circle cx="{x:.2f}" cy="{y:.2f}" r="2.5" fill="{SHAPE_COLOUR}"/>')
        panel.text(c2, "centre", colour=SHAPE_COLOUR, dy=16, size=12)
    else:
        panel.notes.append(f"radius {fmt(radius)}: no sphere to draw, only its centre")
        x, y = panel.px(c2)
        panel.items.append(f'<circle cx="{x:.2f}" cy="{y:.2f}" r="3" fill="{SHAPE_COLOUR}"/>')
    draw_ray(panel, (0.0, 0.0), (dn, 0.0), case, lambda t: (t * dn, 0.0))
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
    sideways.text(seg[1], f"{AXES[axis]} = {fmt(offset)}", colour=SHAPE_COLOUR, dy=18, anchor="end", size=12)
    draw_ray(sideways, o_s, d_s, case, side)
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
    panel.text(corners[0], f"lo {fmt_vec(lo)}", colour=SHAPE_COLOUR, dy=16, anchor="start", size=12)
    panel.text(corners[2], f"hi {fmt_vec(hi)}", colour=SHAPE_COLOUR, dy=-6, anchor="end", size=12)


# --- the picture ---------------------------------------------------------------------------------

def wrap(text: str, width: int = 84) -> list:
    out, line = [], ""
    # A bracket's contents stay on one line: "[0, inf]" is not broken after its comma.
    text = re.sub(r"\[[^\]]*\]", lambda m: m.group(0).replace(" ", "\u00a0"), text)
    for word in text.split(" "):
        if not word:
            continue
        if line and len(line) + 1 + len(word) > width:
            out.append(line)
            line = word
        else:
            line = f"{line} {word}" if line else word
    return out + ([line] if line else [])


def render(figure: dict, title: str) -> tuple:
    """(svg text, one-line summary) of a figure; raises PictureError when it cannot be drawn."""
    case = Case(figure)
    line = summary_of(case)
    titles = wrap(title, 64)[:2]
    head = wrap(line, 88)
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
    legend = y
    y += 22
    note_lines = [l for n in notes for l in wrap("note: " + n, 88)]
    height = y + 17 * len(note_lines) + 10
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height:.0f}" '
           f'viewBox="0 0 {WIDTH} {height:.0f}" font-family="DejaVu Sans, Arial, sans-serif">',
           f'<title>{escape(title)}</title>',
           f'<desc>{escape(line)}</desc>',
           '<defs><marker id="arrow" viewBox="0 0 10 10" refX="8" refY="5" markerWidth="7" markerHeight="7" '
           f'orient="auto-start-reverse"><path d="M0,0L10,5L0,10z" fill="{RAY_COLOUR}"/></marker></defs>',
           f'<rect width="{WIDTH}" height="{height:.0f}" fill="white"/>',
           ]
    out += [f'<text x="10" y="{22 + 19 * i}" font-size="15" font-weight="bold">{escape(shorten(l, 70))}</text>'
            for i, l in enumerate(titles)]
    out += [f'<text x="10" y="{first + 22 + 17 * i}" font-size="12.5" fill="#333">{escape(l)}</text>'
            for i, l in enumerate(head)]
    out += [p.svg() for p in panels]
    out.append(legend_svg(legend, case.window is not None))
    out += [f'<text x="10" y="{y + 17 * i}" font-size="12.5" fill="#8a3b00">{escape(l)}</text>'
            for i, l in enumerate(note_lines)]
    out.append("</svg>")
    return "\n".join(out) + "\n", line


def legend_svg(y: float, window: bool) -> str:
    """One line: the marks and what they mean, each placed after the last."""
    keys = [(lambda x: f'<circle cx="{x + 6}" cy="{y - 4}" r="6" fill="{EXPECTED_COLOUR}"/>', "expected"),
            (lambda x: f'<path d="M{x},{y - 11}L{x + 14},{y + 3}M{x},{y + 3}L{x + 14},{y - 11}" '
                       f'stroke="{GOT_COLOUR}" stroke-width="3"/>', "your answer"),
            (lambda x: f'<line x1="{x}" y1="{y - 4}" x2="{x + 30}" y2="{y - 4}" stroke="{RAY_COLOUR}" '
                       f'stroke-width="2" marker-end="url(#arrow)"/>', "the ray")]
    if window:
        keys.append((lambda x: f'<line x1="{x}" y1="{y - 4}" x2="{x + 30}" y2="{y - 4}" '
                               f'stroke="{WINDOW_COLOUR}" stroke-width="9" opacity="0.7"/>', "window [tmin, tmax]"))
    else:
        keys.append((lambda x: "", "roots of the whole line (no window)"))
    out, x = ['<g font-size="12.5">'], 10
    for mark, text in keys:
        drawn = mark(x)
        out.append(drawn)
        tx = x + (38 if "line" in drawn else 20 if drawn else 0)
        out.append(f'<text x="{tx}" y="{y}">{escape(text)}</text>')
        x = tx + 7 * len(text) + 22
    return "".join(out + ["</g>"])


def shorten(text: str, n: int) -> str:
    return text if len(text) <= n else text[:n - 1] + "…"


def slug(name: str) -> str:
    """A file name for a case: lower case words joined by '-', at most 80 characters."""
    s = re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")
    return (s[:80].rstrip("-") or "case")


def write(figure: dict, title: str, path: Path) -> str:
    """Writes the picture to `path` whole (a temporary file renamed), returns its summary.
    Raises PictureError when it cannot be drawn, OSError when it cannot be written."""
    svg, line = render(figure, title)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(svg, encoding="utf-8")
        tmp.replace(path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return line


# --- the pictures of a grading ----------------------------------------------------------------------

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
                c.picture_summary = write(figure, title, path)
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

"""A panel, one view of the picture: world coordinates (y up) to pixels, lines clipped to the view by
search, labels placed clear of each other; and the ray, its window and the answers drawn in it."""

from __future__ import annotations

import math

from .basics import (EXPECTED_COLOUR, FAR, GOT_COLOUR, PANEL_MAX_HEIGHT, PANEL_MIN_HEIGHT, PictureError,
                     RAY_COLOUR, WIDTH, WINDOW_COLOUR, add, escape, finite, fmt, fmt_point, fmt_vec, inner, norm,
                     overlap, scale, sub, text_box, ulps_apart, unit, wrap_px)
from .case import Case


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
            p = at(t) if math.isfinite(t) else (math.nan, math.nan)
            if not panel.inside(p):
                panel.notes.append(f"{who} t = {fmt(t)} is at {fmt_point(case.point(t))}, outside the view"
                                   if finite(*p) else f"{who} t = {fmt(t)}: no point to draw")
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

"""What a case says: the judge's figure read and checked (`Case`), and its one-line summary in the
words of the judge's text."""

from __future__ import annotations

from .basics import AXES, PictureError, add, fmt, fmt_vec, num, scale, vec


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

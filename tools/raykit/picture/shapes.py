"""The two kinds of case as panels: a sphere in the plane holding the ray and its centre, a rectangle
face on and side on (the package's docstring says how a 3-D case becomes a flat picture)."""

from __future__ import annotations

import math
from fractions import Fraction

from .basics import (AXES, NEARLY_PARALLEL, PictureError, SHAPE_COLOUR, finite, fmt, fmt_vec, inner, norm, scale,
                     sub, unit)
from .case import Case
from .panel import Panel, around, draw_ray, extras


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

"""The picture's parts that know nothing of a case: its sizes and colours, its error, numbers and
vectors (a float as the judge sends it, its short text, a point), and the size of a text in pixels.
Standard library only."""

from __future__ import annotations

import math
import re
import struct


def escape(text: str) -> str:
    """Text for an SVG element's content: &, < and > as entities. Not xml.sax.saxutils.escape, which
    imports urllib.request (and with it http.client, ssl and email) into every ./kit check, for three
    replacements."""
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


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

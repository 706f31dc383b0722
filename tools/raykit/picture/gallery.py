"""The gallery of classic pitfalls (docs/pitfalls.md): a table of cases with the wrong answer each
slip gives, drawn by `./kit docs`."""

from __future__ import annotations

from pathlib import Path

from .drawing import write


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

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

The parts, each importing only those above it in this list:
- basics.py: the sizes and colours, PictureError, numbers and vectors, the size of a text;
- case.py: the figure read and checked (Case), its one-line summary;
- panel.py: one view (Panel): world to pixels, clipping, labels; the ray, window and answers in it;
- shapes.py: the sphere's panel and the rectangle's two;
- drawing.py: the SVG whole (render), its sketch in characters, write;
- grading.py: the pictures of a grading (pictures_folder, draw_results);
- gallery.py: the pitfalls of docs/pitfalls.md (PITFALLS, write_gallery).
The package re-exports the names its users read through it (`picture.render`, ...). A name is
looked up in the part that defines it: a test that replaces one sets it there (picture.drawing.write),
not on the package.
"""

from __future__ import annotations

from fractions import Fraction  # noqa: F401  (the self-test reads picture.Fraction, as before the split)

from .basics import (EXPECTED_COLOUR, GOT_COLOUR, WIDTH, PictureError, norm, overlap, sub,  # noqa: F401
                     text_box)
from .case import Case  # noqa: F401
from .shapes import line_and_centre  # noqa: F401
from .drawing import render, render_all, SKETCH_ROWS, sketch, slug, write  # noqa: F401
from .grading import pictures_folder, draw_results  # noqa: F401
from .gallery import PITFALLS, write_gallery  # noqa: F401

# The names the package re-exports, those its users read through it (pyflakes reads them as used).
__all__ = ["Fraction", "EXPECTED_COLOUR", "GOT_COLOUR", "WIDTH", "PictureError", "norm", "overlap", "sub",
           "text_box", "Case", "line_and_centre", "render", "render_all", "SKETCH_ROWS", "sketch", "slug", "write",
           "pictures_folder", "draw_results", "PITFALLS", "write_gallery"]

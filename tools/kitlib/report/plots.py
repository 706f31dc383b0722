"""The report's charts: the scores' histograms and the steps' stacked bars, drawn as SVG by the kit's
one drawing path (charts.py), so the report needs nothing beyond the standard library to draw them."""

from __future__ import annotations

from .. import charts


def draw(descriptions: list[dict]) -> tuple[list[str], str]:
    """(one SVG per chart, "") or ([], why there are none): a chart's description charts.draw cannot read
    is the kit's fault, said on the page instead of a chart."""
    try:
        return [charts.draw(c) for c in descriptions], ""
    except (KeyError, TypeError, ValueError, ZeroDivisionError) as e:
        return [], f"no charts: a chart could not be drawn ({type(e).__name__}: {e})"

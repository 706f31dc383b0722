"""The pictures of a grading: where `./kit check` draws them, and every failing case of a run drawn
into its step's folder."""

from __future__ import annotations

import re
from pathlib import Path

from .basics import PictureError
from .drawing import slug, write


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

"""Gradings of one class done on several machines (or by several TAs), merged into one grading folder:
one grades.csv, one json/, one files/, from which `./kit report` writes one report.

    ./kit report MACHINE_A/grading MACHINE_B/grading --out DIR      DIR/grading/ and DIR/index.html

Two gradings merge only when they could have been one: the same columns (the same steps and course),
and every results record drawn with the same secret and judged by the same cases and scale
(record.grader). A student graded on two machines is kept once when both gave the same grade, and
refused when they differ: which one is right is for the instructor to decide, not for the order of the
folders. Nothing is written unless all of it can be.
"""

from __future__ import annotations

import csv
import io
import shutil
import tempfile
from pathlib import Path

from .. import record as results_record
from ..common import KitError, printable, student_file_name
from .grading import Grading, load

# Columns that say where and how a grading ran, not what it gave: they may differ between two
# machines that gave the same grade.
_WHERE = {"isolation", "note"}


def _csv_rows(path: Path) -> tuple[list[str], list[dict]]:
    with path.open(newline="") as f:
        reader = csv.DictReader(f)
        return list(reader.fieldnames or []), list(reader)


def _key(row: dict, key: str, columns: list[str]) -> str:
    """The student a row is about: its folder's name, or for a roster's student who submitted
    nothing, the roster's columns."""
    return row.get(key) or "\x1f".join(row.get(c, "") for c in columns if c != key)


def _grade(row: dict) -> dict:
    return {k: v for k, v in row.items() if k not in _WHERE}


def _graders(g: Grading) -> set[tuple[str, str]]:
    return {(s.data.get("grader", {}).get("secret", "?"), s.data.get("grader", {}).get("cases", "?"))
            for s in g.students if s.data is not None}


def merge(folders: list[Path], target: Path) -> list[str]:
    """Merges the gradings in `folders` into the grading folder `target` (made anew); notes to say."""
    if len(folders) < 2:
        raise KitError("merging needs two gradings or more")
    gradings = [load(f) for f in folders]
    notes = [f"{printable(str(g.folder))}: {p}" for g in gradings for p in g.problems]
    columns, _ = _csv_rows(gradings[0].csv_path)
    key = "student" if "student" in columns else "submission"
    for g in gradings[1:]:
        other, _ = _csv_rows(g.csv_path)
        if other != columns:
            only = [c for c in other if c not in columns] + [c for c in columns if c not in other]
            raise KitError(f"{g.csv_path} and {gradings[0].csv_path} have other columns "
                           f"({', '.join(only[:4]) or 'in another order'}): graded with another course or "
                           "step list, they cannot be one class's grading")

    # One secret and one set of cases for all: otherwise the hidden inputs or the verdicts differ.
    seen: dict[tuple[str, str], Path] = {}
    for g in gradings:
        for grader in _graders(g):
            seen.setdefault(grader, g.folder)
    if len({s for s, _ in seen}) > 1:
        where = ", ".join(f"{printable(str(f))} ({s})" for (s, _), f in sorted(seen.items()))
        raise KitError("these gradings drew their hidden inputs with different secrets: " + where + ". Copy "
                       "tests/hidden/secret.key from one machine to the others (docs/instructors.md: one course, several "
                       "machines) and grade again there")
    if len({c for _, c in seen}) > 1:
        where = ", ".join(f"{printable(str(f))} ({c})" for (_, c), f in sorted(seen.items()))
        raise KitError("these gradings were judged by different cases, scales or references: " + where +
                       ". Grade with the same copy of the kit (same course.json, tests/ and solutions/)")

    rows: dict[str, tuple[dict, Grading]] = {}
    order: list[str] = []
    for g in gradings:
        _, own = _csv_rows(g.csv_path)
        for row in own:
            who = _key(row, key, columns)
            if who not in rows:
                rows[who] = (row, g)
                order.append(who)
                continue
            kept, first = rows[who]
            if not row.get(key) and kept.get(key):
                continue                # on the roster here, submitted and graded there
            if row.get(key) and not kept.get(key):
                rows[who] = (row, g)
                continue
            if _grade(row) != _grade(kept):
                raise KitError(f"{printable(row.get(key) or who)} was graded on two machines with different "
                               f"results: {printable(str(first.csv_path))} says {kept.get('earned')} of "
                               f"{kept.get('maximum')} ({kept.get('status')}), {printable(str(g.csv_path))} "
                               f"{row.get('earned')} of {row.get('maximum')} ({row.get('status')}); remove the "
                               "row you do not want from one CSV, then merge again")
            notes.append(f"{printable(row.get(key) or who)}: graded on two machines alike, kept once")

    if key == "student":
        order.sort()                    # as ./kit grade orders its rows; a roster keeps its own order
    staging = Path(tempfile.mkdtemp(prefix=".merging-", dir=target.parent))
    try:
        (staging / "json").mkdir()
        text = io.StringIO()
        writer = csv.DictWriter(text, fieldnames=columns)     # as ./kit grade writes it
        writer.writeheader()
        for who in order:
            row, g = rows[who]
            writer.writerow(row)
            name = row.get(key)
            if not name:
                continue
            record = (g.folder / "json" if (g.folder / "json").is_dir() else g.folder) / f"{student_file_name(name)}.json"
            if record.is_file():
                results_record.read(record)         # a record, or the merge stops here
                shutil.copyfile(record, staging / "json" / record.name)
            if g.files is not None and (g.files / student_file_name(name)).is_dir():
                shutil.copytree(g.files / student_file_name(name), staging / "files" / student_file_name(name))
        (staging / "grades.csv").write_bytes(text.getvalue().encode("utf-8"))
        shutil.rmtree(target, ignore_errors=True)
        staging.rename(target)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return notes

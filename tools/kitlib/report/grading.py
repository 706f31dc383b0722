"""A saved grading, read back: the CSV of ./kit grade and each student's results JSON.

A grading folder holds grades.csv (or one other .csv), the students' JSON in json/ (STUDENT.json, the
Gradescope format of ./kit check --json), and, when the submissions were given, the step files each
one was graded on in files/STUDENT/NN_topic/ (for the similarity section).
"""

from __future__ import annotations

import csv
import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path

from fractions import Fraction

from raykit import course as course_file
from raykit import record as results_record
from raykit.common import KitError, Step, printable, student_file_name


@dataclass
class Student:
    name: str
    row: dict                           # the CSV row
    data: dict | None = None            # its results record (raykit/record.py), when it was graded
    page: str = ""                      # students/<page>.html

    @property
    def earned(self):
        return _number(self.row.get("earned"))

    @property
    def maximum(self):
        return _number(self.row.get("maximum"))

    def points(self):
        """(points earned without the extra credit, the maximum, extra credit earned, extra credit the
        course offered), exact, for a student with a total: from their record, else (nothing
        submitted, no steps) the CSV's 0 of the maximum; None without a total (not graded)."""
        if self.earned is None or not self.maximum:
            return None
        if self.data is None or not self.data.get("score_exact"):
            return Fraction(str(self.earned)), Fraction(str(self.maximum)), Fraction(0), Fraction(0)
        extra, possible = results_record.extra_credit(self.data)
        return (Fraction(self.data["score_exact"]) - extra, Fraction(self.data["max_score_exact"]), extra, possible)

    def shown(self, exact_text, fallback="") -> str:
        """A number of this student's record on its course's decimals, as the CSV writes it (course.shown):
        108.90, never 108.9."""
        if exact_text in (None, ""):
            return str(fallback)
        decimals = (self.data or {}).get("rounding", course_file.load().decimals)
        return course_file.Course(decimals=decimals).shown(Fraction(str(exact_text)))

    def steps(self) -> list[dict]:
        return (self.data or {}).get("steps", [])

    def step(self, number: str) -> dict | None:
        return next((s for s in self.steps() if s.get("step") == number), None)


@dataclass
class Grading:
    folder: Path
    csv_path: Path
    students: list[Student]
    files: Path | None                  # files/STUDENT/NN_topic/..., or None
    problems: list[str] = field(default_factory=list)     # disagreements between the CSV and the JSON


def _number(text):
    try:
        value = float(text)
    except (TypeError, ValueError):
        return None
    return int(value) if value == int(value) else value


def page_name(name: str, used: set) -> str:
    base = re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("._") or "student"
    page, n = base, 2
    while page.lower() in used:
        page, n = f"{base}_{n}", n + 1
    used.add(page.lower())
    return page


# A row's status when ./kit grade kept no record of it (commands/grade.py): nothing is missing then.
NOT_GRADED = ("not submitted", "nothing submitted", "no steps", "not graded", "timed out")


def load(folder: Path) -> Grading:
    if not folder.is_dir():
        raise KitError(f"{folder}: no such folder (a saved grading: grades.csv and json/)")
    csv_path = folder / "grades.csv"
    if not csv_path.is_file():
        found = sorted(folder.glob("*.csv"))
        if len(found) != 1:
            raise KitError(f"{folder}: holds {'no' if not found else len(found)} .csv files; a saved grading "
                           "holds grades.csv (./kit grade --out) and json/ (./kit grade --json-dir)")
        csv_path = found[0]
    json_dir = folder / "json" if (folder / "json").is_dir() else folder
    try:
        with csv_path.open(newline="") as f:
            rows = list(csv.DictReader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise KitError(f"{csv_path}: cannot read it ({e})")
    # ./kit grade names each row's folder in "student"; with --roster, in "submission", after the
    # roster's own columns (empty for a student on it who submitted nothing).
    key = "student" if rows and "student" in rows[0] else "submission"
    if not rows or key not in rows[0] or "earned" not in rows[0]:
        raise KitError(f"{csv_path}: not a CSV of ./kit grade (no student or submission column and earned "
                       "column, or no rows)")
    students, problems, used = [], [], set()
    for row in rows:
        folder_name = row[key]
        if not folder_name:     # on the roster, nothing submitted: named by the roster's first filled column
            s = Student(next((v for k, v in row.items() if v and k != key), "(unnamed)"), row)
            s.page = page_name(s.name, used)
            students.append(s)
            continue
        s = Student(folder_name, row)
        path = json_dir / f"{student_file_name(s.name)}.json"
        if path.is_file():
            try:
                s.data = results_record.read(path)
            except KitError as e:
                problems.append(f"{path.name}: {str(e).split(': ', 1)[-1]}; left out")
                s.data = None
            if s.data is not None and not results_record.finished(s.data):
                s.data = None       # a placeholder: no result (the CSV says "not graded")
        ungraded = row.get("status") == "not graded"     # no total: the CSV says so where it would be
        if s.data is not None and not ungraded and (s.data.get("score") != s.earned or s.data.get("max_score") != s.maximum):
            problems.append(f"{s.name}: the CSV says {s.earned} / {s.maximum}, the record "
                            f"{s.data.get('score')} / {s.data.get('max_score')}")
        if s.data is None and s.earned is not None and row.get("status") not in NOT_GRADED:
            problems.append(f"{s.name}: graded in the CSV, but {path.name} is missing: no details")
        s.page = page_name(s.name, used)
        students.append(s)
    files = folder / "files" if (folder / "files").is_dir() else None
    return Grading(folder, csv_path, students, files, problems)


def save_files(students: dict[str, Path], steps: list[Step], target: Path, work: Path) -> list[str]:
    """Copies each student's step files (as ./kit grade finds them in their upload) to target/STUDENT/
    (the name as common.student_file_name writes it), their control characters shown (common.printable)."""
    from raykit.submissions import NotFound, locate

    notes = []
    shutil.rmtree(target, ignore_errors=True)
    for name, upload in students.items():
        try:
            found = locate(upload, work, steps)
        except NotFound:
            continue
        except Exception as e:          # an upload the grading already reported on: no files, say so
            notes.append(f"{name}: its files could not be read ({e})")
            continue
        for s in steps:
            for f in s.files:
                src = found.steps_dir / s.folder / f
                if src.is_file():
                    folder = target / student_file_name(name) / s.folder
                    folder.mkdir(parents=True, exist_ok=True)
                    # For the comparison and the report's pages: the code with its control characters
                    # shown as text, so that no one's `cat` of the saved grading replays them.
                    text = src.read_bytes().decode("utf-8", errors="surrogateescape")
                    (folder / f).write_text(printable(text), encoding="utf-8")
    shutil.rmtree(work, ignore_errors=True)
    return notes

"""Gradings of one class done on several machines (or by several TAs), merged into one grading folder,
file for file what one machine's `./kit grade --report` writes: grades.csv, grades-cases.csv, json/
(each student's record and .judged-by.json), files/; from which `./kit report` writes one report.

    ./kit report MACHINE_A/grading MACHINE_B/grading --out DIR      DIR/grading/ and DIR/index.html

Two gradings merge only when they could have been one (_same_judge): the same columns (the same steps
and course); one secret, the one this copy of the kit holds; the same inputs that can change a verdict
or a point (judgedby.py: the refusal names the first file that differs, or the compiler); every list
and record sealed under that secret (secret.seal: a record edited, or written from another, is refused
by its name). A student graded on two machines is kept once when both gave the same grade, and refused
when they differ: which one is right is for the instructor to decide, not for the order of the folders.
Nothing is written unless all of it can be.

What may differ from one machine's grading of the whole class, as it says how a grading ran, not what it
gave (PER_RUN): in grades.csv the columns isolation and note; in a record its execution_time, isolation,
what it built of the kit's side (built, built_why),
each step's isolation and cost (CPU and wait measured), each case's runs, and the seal over them.
"""

from __future__ import annotations

import csv
import os
import shutil
import tempfile
from pathlib import Path

from raykit import judgedby
from raykit import record as results_record
from raykit import secret as secret_file
from raykit.common import KitError, printable, student_file_name
from .grading import Grading, load
from . import rows as rows_file
from .make import CASES, GRADES

# Columns that say where and how a grading ran, not what it gave: they may differ between two
# machines that gave the same grade.
_WHERE = {"isolation", "note"}
PER_RUN = {"csv": sorted(_WHERE), "record": ["execution_time", "isolation", "mac", "built", "built_why"],
           "step": ["isolation", "cost"], "case": ["runs"]}


def _csv_rows(path: Path) -> tuple[list[str], list[dict]]:
    with path.open(newline="") as f:
        reader = csv.DictReader(f)
        return list(reader.fieldnames or []), list(reader)


def _key(row: dict, key: str, columns: list[str]) -> str:
    """The student a row is about: its folder's name; with a roster (key "submission"), the roster's own
    columns (those before "submission"), whether the student submitted here or not, and for a folder on
    no one's line, its name."""
    if key != "submission":
        return row.get(key) or ""
    named = "\x1f".join(row.get(c, "") for c in columns[:columns.index(key)])
    return named if named.strip("\x1f") else "\x00" + row.get(key, "")


def _grade(row: dict) -> dict:
    return {k: v for k, v in row.items() if k not in _WHERE}


def _records(g: Grading) -> Path:
    return g.folder / "json" if (g.folder / "json").is_dir() else g.folder


def _manifest(g: Grading) -> tuple[dict, Path]:
    path = _records(g) / judgedby.FILE_NAME
    manifest = judgedby.read(path)
    if manifest is None:
        raise KitError(f"refused: {printable(str(g.folder))} holds no list of what judged it ({judgedby.FILE_NAME} "
                       "beside its records: graded with an older kit, or not with ./kit grade --report / --json-dir); "
                       "grade it again with this kit")
    return manifest, path


def _where(g: Grading) -> str:
    return printable(str(g.folder))


def _same_judge(gradings: list[Grading]) -> list[dict]:
    """Refuses (KitError) unless every grading was drawn with one secret, the one this copy of the kit
    holds, and judged by the same inputs (judgedby.py), every list and record sealed under that secret;
    the refusal names the first file that differs, or the record whose seal fails. The lists."""
    found = [_manifest(g) for g in gradings]
    # One secret for all: otherwise the hidden inputs differ.
    seen: dict[str, Grading] = {}
    for g, (m, _) in zip(gradings, found):
        seen.setdefault(str(m.get("secret") or "none"), g)
        for s in g.students:
            if s.data is not None:
                seen.setdefault(str(s.data.get("grader", {}).get("secret") or "none"), g)
    if len(seen) > 1:
        where = ", ".join(f"{_where(g)} ({fp})" for fp, g in sorted(seen.items()))
        raise KitError("refused: these gradings drew their hidden inputs with different secrets: " + where + ". Copy "
                       "tests/hidden/secret.key from one machine to the others (docs/instructors.md: one course, several "
                       "machines) and grade again there")
    theirs = next(iter(seen))
    key = secret_file.existing()
    if key is None or secret_file.fingerprint_of(key) != theirs:
        raise KitError(f"refused: these gradings were drawn with secret {theirs}, and this copy of the kit holds "
                       f"{'none' if key is None else 'another (' + secret_file.fingerprint_of(key) + ')'}: their "
                       "seals can be checked only under theirs. Merge on a machine that graded them, or copy its "
                       "tests/hidden/secret.key here")
    for m, path in found:
        if not secret_file.sealed(m, key):
            raise KitError(f"refused: {printable(str(path))}: its seal does not match its content under the secret "
                           "(edited or written by hand); grade that half again")
    # One copy of the kit's inputs for all: the first one that differs, named.
    first, _ = found[0]
    for g, (m, _) in zip(gradings[1:], found[1:]):
        diff = judgedby.first_difference(first, m)
        if diff is None:
            continue
        what, how = diff
        a, b = _where(gradings[0]), _where(g)
        if what == judgedby.COMPILER:
            said = f"the compiler differs between {a} ({first.get('compiler')}) and {b} ({m.get('compiler')})"
        elif how == "differs":
            said = f"{what} differs between {a} and {b}"
        else:
            said = f"{what} is in the copy of the kit that graded {a if how == 'only in the first' else b}, not in {b if how == 'only in the first' else a}'s"
        raise KitError(f"refused: {printable(said)}: the two would judge some submission differently. Grade both "
                       "halves with one copy of the course (copy course.json, include/, tests/, solutions/ and the "
                       "kit from one machine to the other; after changing the course, ./kit refresh), then grade "
                       "that half again")
    # Every record sealed, and judged by its grading's own inputs.
    for g, (m, _) in zip(gradings, found):
        for s in g.students:
            if s.data is None:
                continue
            path = _records(g) / f"{student_file_name(s.name)}.json"
            if not secret_file.sealed(s.data, key):
                raise KitError(f"refused: {printable(str(path))}: its seal does not match its content under the "
                               "secret (edited, copied from another record or written by hand); grade that "
                               "student again")
            if s.data.get("grader", {}).get("cases") != m.get("digest"):
                raise KitError(f"refused: {printable(str(path))} was judged by another copy of the kit "
                               f"({s.data.get('grader', {}).get('cases')}) than the rest of {_where(g)} "
                               f"({m.get('digest')}); grade that student again")
    return [m for m, _ in found]


def _borne_out(g: Grading, columns: list[str], key: str) -> None:
    """Refuses (KitError) a row of g's CSV that its sealed record does not give, cell for cell, as ./kit grade
    writes it (report/rows.record_row), the per-run columns aside; or a row with points and no record."""
    from raykit.common import load_steps
    from .grading import NOT_GRADED
    steps = load_steps()
    for s in g.students:
        name = s.row.get(key)
        if not name:
            continue
        if s.data is None:
            if s.row.get("status") not in NOT_GRADED or s.earned not in (None, 0):
                raise KitError(f"refused: {printable(str(g.csv_path))}: {printable(name)} is {s.row.get('status')} "
                               f"with {s.row.get('earned')} points, but has no record to bear it out")
            continue
        derived = rows_file.record_row({"student": name}, dict(s.data), steps)
        for c in columns:
            if c in _WHERE or c in ("student", "submission") or c not in derived:
                continue
            if rows_file.csv_safe(derived[c]) != s.row.get(c, ""):
                raise KitError(f"refused: {printable(str(g.csv_path))}: {printable(name)}'s {c} is "
                               f"{printable(str(s.row.get(c)))}, its sealed record gives {printable(str(derived[c]))}")


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
    _same_judge(gradings)
    case_columns: list[str] | None = None
    cases: dict[Path, dict[str, list[dict]]] = {}
    for g in gradings:
        path = g.folder / CASES
        if not path.is_file():
            raise KitError(f"refused: {printable(str(g.folder))} holds no {CASES} (graded with an older kit, or "
                           "not with ./kit grade --report); grade it again")
        own, rows_ = _csv_rows(path)
        if case_columns is None:
            case_columns = own
        elif own != case_columns:
            raise KitError(f"{path} has other columns than {gradings[0].folder / CASES}: graded with another course "
                           "or roster")
        for row in rows_:
            cases.setdefault(g.folder, {}).setdefault(row.get("submission", ""), []).append(row)
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
            if row.get(key):
                notes.append(f"{printable(row.get(key) or who)}: graded on two machines alike, kept once")

    for g in gradings:      # a row its own sealed record does not bear out (after the rows two machines differ on)
        _borne_out(g, columns, key)
    if key == "student":
        order.sort()                    # as ./kit grade orders its rows
    else:                               # the roster's own order, then the folders on no one's line, sorted
        order = [w for w in order if not w.startswith("\x00")] + sorted(w for w in order if w.startswith("\x00"))
    staging = Path(tempfile.mkdtemp(prefix=".merging-", dir=target.parent))
    try:
        mask = os.umask(0)
        os.umask(mask)
        staging.chmod(0o777 & ~mask)        # as ./kit grade's folders, not mkdtemp's 0700
        (staging / "json").mkdir()
        shutil.copyfile(_records(gradings[0]) / judgedby.FILE_NAME, staging / "json" / judgedby.FILE_NAME)
        # The cases as ./kit grade orders them: by submission, whatever the roster's order.
        graded_by = {row[key]: g for row, g in rows.values() if row.get(key)}
        case_rows = [c for name in sorted(graded_by) for c in cases.get(graded_by[name].folder, {}).get(name, [])]
        for who in order:
            row, g = rows[who]
            name = row.get(key)
            if not name:
                continue
            record = _records(g) / f"{student_file_name(name)}.json"
            if record.is_file():
                results_record.read(record)         # a record, or the merge stops here
                shutil.copyfile(record, staging / "json" / record.name)
            if g.files is not None and (g.files / student_file_name(name)).is_dir():
                shutil.copytree(g.files / student_file_name(name), staging / "files" / student_file_name(name))
        # Written as ./kit grade writes them (rows_file.csv_text): the same bytes for the same rows.
        (staging / GRADES).write_bytes(rows_file.csv_text(columns, [rows[who][0] for who in order]).encode("utf-8"))
        (staging / CASES).write_bytes(rows_file.csv_text(case_columns or [], case_rows).encode("utf-8"))
        shutil.rmtree(target, ignore_errors=True)
        staging.rename(target)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return notes

"""Making the class report: the grading saved beside it (from ./kit grade --report, or a saved
grading and its uploads for ./kit report) and the pages written (pages.py). Below both commands,
which import it."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

from raykit.common import BUILD, KitError, load_steps, printable, say, writable_parent
from raykit.packages import ensure_packages
from raykit.status import OK
from .grading import load, save_files
from .pages import build


def uploads(submissions: Path) -> dict[str, Path]:
    """Each upload of the class by the student's name, as ./kit grade writes it in the CSV (printable)."""
    return {printable(p.stem if p.is_file() else p.name): p for p in sorted(submissions.iterdir())
            if not p.name.startswith(".") and (p.is_dir() or (p.is_file() and p.suffix.lower() == ".zip"))}


def save_submissions(submissions: Path, names: list[str], folder: Path) -> None:
    found = uploads(submissions)
    for note in save_files({n: found[n] for n in names if n in found}, load_steps(), folder / "files",
                           BUILD / "report-upload"):
        say(f"  {printable(note)}")


def write_report(folder: Path, out: Path) -> int:
    writable_parent(f"--out {out}", out)
    if out.exists() and not out.is_dir():
        raise KitError(f"--out {out}: is a file, not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise KitError(f"--out {out}: cannot make the folder ({e.strerror})")
    try:    # sim_c++: without it the report says what it left out, and goes on
        ensure_packages("report")
    except KitError as e:
        say(f"  note: {str(e).splitlines()[0]}")
    start = time.monotonic()
    try:
        summary = build(folder, out)
    except OSError as e:
        raise KitError(f"--out {out}: cannot write the report ({e.strerror}: {e.filename})")
    say(f"wrote {out / 'index.html'} and {summary['students']} student pages in {time.monotonic() - start:.1f} s")
    for note in summary["notes"]:
        say(f"  note: {printable(note)}")
    return OK


# What a grading folder holds (./kit grade --report DIR writes them in DIR/grading/, the merge of several
# machines' gradings in OUT/grading/, report/merge.py): the CSV, the long CSV of cases, each student's
# record and the list of what judged them in json/, each student's files in files/.
GRADES, CASES = "grades.csv", "grades-cases.csv"


def from_grade(args, csv_path: Path, json_dir: Path, cases_path: Path | None = None) -> int:
    """./kit grade --report DIR: keeps the grading in DIR/grading/ and writes the report in DIR."""
    from raykit.judgedby import FILE_NAME
    out = Path(args.report)
    grading = out / "grading"
    (grading / "json").mkdir(parents=True, exist_ok=True)
    shutil.copyfile(csv_path, grading / GRADES)
    if cases_path is not None and cases_path.is_file():
        shutil.copyfile(cases_path, grading / CASES)
    if json_dir.resolve() != (grading / "json").resolve():
        for p in [*json_dir.glob("*.json"), json_dir / FILE_NAME]:
            if p.is_file():
                shutil.copyfile(p, grading / "json" / p.name)
    save_submissions(Path(args.submissions), [s.name for s in load(grading).students], grading)
    return write_report(grading, out)

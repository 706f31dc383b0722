"""./kit report GRADING_DIR: the class report of a saved grading, offline HTML.

    ./kit grade SUBMISSIONS --report DIR      grades, saves the grading in DIR/grading/, writes DIR/index.html
    ./kit report GRADING_DIR --out DIR        the report of a saved grading (grades.csv, json/, files/)
    ./kit report A B ... --out DIR            gradings of one class from several machines, merged into
                                              DIR/grading/ (report/merge.py), and their one report
    ./kit report --signatures                 grades every mutant, writes tests/mutants/signatures.json

DIR/index.html is for the instructor: scores, cases by failure rate, the slips the mutant library
recognises, incidents, similar submissions. DIR/students/NAME.html is one student's own page, which
names no other student. Everything is in the files: no script, font or picture is fetched.
"""

from __future__ import annotations

import shutil
import time
from pathlib import Path

from raykit.common import BUILD, ROOT, KitError, load_steps, say, select_steps, writable_parent
from ..report import signatures
from ..report.grading import load
from ..report.make import save_submissions, write_report
from ..report.merge import merge
from raykit.status import FAILED, OK


def register(p) -> None:
    p.add_argument("grading", metavar="GRADING_DIR", nargs="*",
                   help="a saved grading: grades.csv, json/ (./kit grade --json-dir) and, for the similarity "
                        "section, files/ (written by ./kit grade --report); several: one class graded on "
                        "several machines, merged into OUT/grading/ first")
    p.add_argument("--out", metavar="DIR", help="the report's folder (default: build/report)")
    p.add_argument("--submissions", metavar="DIR",
                   help="the class's uploads, to compare the submissions (saved into GRADING_DIR/files/)")
    p.add_argument("--signatures", action="store_true",
                   help="grade every mutant of tests/mutants/ and write tests/mutants/signatures.json")
    p.add_argument("--step", metavar="N", action="append", default=[],
                   help="with --signatures: only this step's mutants (repeatable); the others' are kept")


def run(args) -> int:
    if args.signatures:
        if args.grading:
            raise KitError("--signatures takes no GRADING_DIR")
        if not (ROOT / "solutions").is_dir():
            raise KitError("the signatures are computed from solutions/, which this copy of the kit does not have")
        start = time.monotonic()
        numbers = [s.number for s in select_steps(load_steps(), args.step)] if args.step else None
        data = signatures.compute(lambda line: say("  " + line), numbers)
        signatures.write(data)
        say(f"wrote {signatures.FILE.relative_to(ROOT)}: {len(data['mutants'])} mutants in "
            f"{time.monotonic() - start:.0f} s")
        for p in data["problems"]:
            say(f"  not recorded: {p}")
        return FAILED if data["problems"] else OK
    if not args.grading:
        raise KitError("give a saved grading folder (./kit report GRADING_DIR) or --signatures")
    out = Path(args.out) if args.out else BUILD / "report"
    if len(args.grading) > 1:
        if args.submissions:
            raise KitError("--submissions takes one grading; merge gradings that each saved their files "
                           "(./kit grade --report)")
        folders = [Path(g) for g in args.grading]
        if any(out.resolve() == f.resolve() or out.resolve() in f.resolve().parents for f in folders):
            raise KitError(f"--out {out}: is one of the gradings to merge, or holds one")
        writable_parent(f"--out {out}", out)
        made = not out.exists()
        out.mkdir(parents=True, exist_ok=True)
        try:
            notes = merge(folders, out / "grading")
        except KitError:
            if made:            # a refused merge leaves nothing behind, not even its folder
                shutil.rmtree(out, ignore_errors=True)
            raise
        for note in notes:
            say(f"  note: {note}")
        say(f"merged {len(folders)} gradings into {out / 'grading' / 'grades.csv'}")
        return write_report(out / "grading", out)
    folder = Path(args.grading[0])
    if args.submissions:
        submissions = Path(args.submissions)
        if not submissions.is_dir():
            raise KitError(f"--submissions {args.submissions}: no such folder")
        names = [s.name for s in load(folder).students]
        save_submissions(submissions, names, folder)
    return write_report(folder, out)

"""./kit grade SUBMISSIONS: batch grading of a class into a CSV table, on one scale.

Each submission is graded by a child ./kit (so nothing one does can stop the batch),
in its own build folder and sandbox slot, several at a time (-j).
"""

from __future__ import annotations

import csv
import io
import json
import os
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from ..status import CRASHED, DONE, STATE_WORDS, THREW, TIMED_OUT
from ..common import BUILD, ROOT, KitError, csv_cell, load_steps, printable, say
from ..packages import ensure_packages
from ..sandbox import kill_session, kill_uid
from ..submissions import NotFound, locate
from ..status import OK

SUBMISSION_SECONDS = 600    # a whole submission; each case already has its own limit


def register(p) -> None:
    p.add_argument("submissions", metavar="SUBMISSIONS_DIR",
                   help="one folder or .zip per student, holding the steps at any depth (a steps folder, a "
                        "copy of the kit, loose NN_topic/ folders)")
    p.add_argument("--out", metavar="FILE", default=str(BUILD / "grades.csv"),
                   help="the CSV to write (default: build/grades.csv)")
    p.add_argument("-j", "--jobs", type=int, default=os.cpu_count() or 1, metavar="N",
                   help="submissions graded at once (default: the number of cores)")
    p.add_argument("--isolation", choices=["auto", "bwrap", "user", "none"], default="auto",
                   help="how the graded code is kept apart (default: auto)")
    p.add_argument("--json-dir", metavar="DIR", help="also keep each student's results.json (Gradescope format) here")
    p.add_argument("--report", metavar="DIR", help="also write the class report (./kit report) in DIR, the grading in DIR/grading/")


def columns(steps) -> list[str]:
    cols = ["student", "earned", "maximum", "percent", "status"]
    for s in steps:
        cols += [f"step{s.number}_state", f"step{s.number}_earned", f"step{s.number}_maximum",
                 f"step{s.number}_robust", f"step{s.number}_robust_total"]
    return cols + ["isolation", "note"]


def grade_one(folder: Path, steps, report: Path, slot: int = 0, isolation: str = "auto") -> dict:
    """Grades one submission in a child ./kit process, so nothing it does can stop the batch."""
    row = {"student": folder.stem if folder.is_file() else folder.name}
    report.unlink(missing_ok=True)
    try:
        found = locate(folder, BUILD / f"grade-upload-{slot}", steps)
    except NotFound as e:
        return dict(row, status="no steps", note=str(e)[:300])
    uid_file = BUILD / f"grade-uid-{slot}"
    uid_file.unlink(missing_ok=True)
    # Its own session: on a timeout, every process of it (cmake, ninja, the compilers) is ended,
    # and so is every process of the sandbox's user id, so nothing outlives its submission.
    proc = subprocess.Popen([str(ROOT / "kit"), "check", "--steps", str(found.steps_dir), "--json", str(report),
                             "--quiet", "--slot", str(slot), "--isolation", isolation],
                            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace",
                            start_new_session=True, env=dict(os.environ, RAYKIT_UID_FILE=str(uid_file)))
    try:
        _, stderr = proc.communicate(timeout=SUBMISSION_SECONDS)
        timed_out = False
    except subprocess.TimeoutExpired:
        timed_out = True
    kill_session(proc.pid)
    if proc.poll() is None:
        proc.kill()
    if timed_out:
        proc.communicate()
    try:
        kill_uid(int(uid_file.read_text()))
    except (OSError, ValueError):
        pass
    if timed_out:
        return dict(row, status="timed out", note=f"grading took over {SUBMISSION_SECONDS} s")
    r = subprocess.CompletedProcess(proc.args, proc.returncode, "", stderr)
    if not report.exists():
        message = (r.stderr.strip().splitlines() or ["no result"])[-1]
        return dict(row, status="not graded", note=message.removeprefix("kit: "))
    data = json.loads(report.read_text())
    row["earned"] = data["score"]
    row["maximum"] = data["extra_data"]["max_score"]
    row["percent"] = f"{100 * row['earned'] / row['maximum']:.1f}" if row["maximum"] else ""
    by_number = {s["step"]: s for s in data["extra_data"]["steps"]}
    row["status"] = "complete" if all(s["state"] == DONE for s in by_number.values()) else "incomplete"
    row["isolation"] = next((s["isolation"] for s in by_number.values() if s.get("isolation")), "")
    notes = []
    for s in steps:
        res = by_number.get(s.number)
        if res is None:
            continue
        row[f"step{s.number}_state"] = STATE_WORDS.get(res["state"], res["state"])
        row[f"step{s.number}_earned"] = res["earned"]
        row[f"step{s.number}_maximum"] = res["maximum"]
        row[f"step{s.number}_robust"] = res["robust"]["passed"]
        row[f"step{s.number}_robust_total"] = res["robust"]["total"]
        bad = sorted({c["status"] for c in res["cases"] if c["status"] in (CRASHED, TIMED_OUT, THREW)})
        if bad:
            notes.append(f"step {s.number}: {' '.join(bad)}")
    row["note"] = "; ".join(notes)
    return row


def run(args) -> int:
    ensure_packages("build")
    root = Path(args.submissions)
    if not root.is_dir():
        raise KitError(f"{args.submissions}: no such folder")
    out = Path(args.out)
    if out.is_dir() or not out.parent.resolve().is_dir():
        raise KitError(f"--out {args.out}: cannot write a file there")
    if not os.access(out.parent.resolve(), os.W_OK):
        raise KitError(f"--out {args.out}: folder is not writable")
    json_dir = Path(args.json_dir) if args.json_dir else Path(args.report) / "grading" / "json" if args.report else None
    if json_dir is not None:
        json_dir.mkdir(parents=True, exist_ok=True)
    steps = load_steps()
    if any((root / s.folder).is_dir() for s in steps) or (root / "steps").is_dir():
        raise KitError(f"{args.submissions}: this looks like one student's steps (it holds "
                       f"{'steps/' if (root / 'steps').is_dir() else 'NN_topic/ folders'}); ./kit grade takes a "
                       "folder with one folder or .zip per student. For one student: ./kit check --steps DIR")
    # One submission per folder or .zip, named after it; the steps may be at any depth inside.
    folders = sorted(p for p in root.iterdir() if not p.name.startswith(".") and
                     (p.is_dir() or (p.is_file() and p.suffix.lower() == ".zip")))
    if not folders:
        raise KitError(f"{args.submissions}: holds no submission folders or .zip files")
    start = time.monotonic()
    BUILD.mkdir(exist_ok=True)
    jobs = max(1, min(args.jobs, len(folders)))
    done = [0]

    def one(item: tuple[int, Path]) -> dict:
        i, folder = item
        slot = i % jobs
        report = BUILD / f"grade-one-{slot}.json"
        row = grade_one(folder, steps, report, slot, args.isolation)
        if json_dir is not None and report.exists():
            (json_dir / f"{row['student']}.json").write_text(report.read_text())
        done[0] += 1
        print(f"[{done[0]}/{len(folders)}] {printable(folder.name)}: {row.get('status')} "
              f"{row.get('earned', '')}/{row.get('maximum', '')}", file=sys.stderr, flush=True)
        return row

    # Slot k serves submissions k, k + jobs, ...: one build folder and one sandbox user each.
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        by_slot = [[(i, f) for i, f in enumerate(folders) if i % jobs == k] for k in range(jobs)]
        rows_by_slot = list(pool.map(lambda items: [one(item) for item in items], by_slot))
    rows = sorted((r for slot_rows in rows_by_slot for r in slot_rows), key=lambda r: r["student"])
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=columns(steps), restval="")
    writer.writeheader()
    writer.writerows([{k: csv_cell(v) for k, v in r.items()} for r in rows])   # formulas stay text
    tmp = out.with_name(f".{out.name}.{os.getpid()}.tmp")
    tmp.write_text(text.getvalue())
    tmp.replace(out)
    say(f"graded {len(rows)} submissions in {time.monotonic() - start:.0f} s: {out}")
    width = max(len(printable(r["student"])) for r in rows)
    for r in rows:
        say(f"  {printable(r['student']).ljust(width)}  {str(r.get('earned', '-')).rjust(4)} / {str(r.get('maximum', '-')).ljust(4)} "
            f"{r.get('status', '')}  {printable(str(r.get('note', '')))}")
    if args.report:     # the class report, from the grading just saved (commands/report.py)
        from .report import from_grade
        return from_grade(args, out, json_dir)
    return OK

"""./kit grade SUBMISSIONS: batch grading, one submission at a time, into a CSV table."""

from __future__ import annotations

import csv
import io
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from common import BUILD, ROOT, KitError, ensure_packages, load_steps, say

HELP = "grade every student's steps folder under a directory and write a CSV summary"
SUBMISSION_SECONDS = 600    # a whole submission; each case already has its own limit


def register(p) -> None:
    p.add_argument("submissions", metavar="SUBMISSIONS_DIR",
                   help="one folder per student, each a steps folder or a copy of the kit")
    p.add_argument("--out", metavar="FILE", default="grades.csv", help="the CSV to write (default: grades.csv)")
    p.add_argument("--json-dir", metavar="DIR", help="also keep each student's results.json (Gradescope format) here")


def columns(steps) -> list[str]:
    cols = ["student", "score", "max_score", "status"]
    for s in steps:
        cols += [f"step{s.number}_state", f"step{s.number}_basic", f"step{s.number}_basic_total",
                 f"step{s.number}_robust", f"step{s.number}_robust_total"]
    return cols + ["note"]


def grade_one(folder: Path, steps, report: Path) -> dict:
    """Grades one submission in a child ./kit process, so nothing it does can stop the batch."""
    row = {"student": folder.name}
    report.unlink(missing_ok=True)
    try:
        r = subprocess.run([str(ROOT / "kit"), "check", "--steps", str(folder), "--json", str(report), "--quiet"],
                           cwd=ROOT, capture_output=True, text=True, timeout=SUBMISSION_SECONDS)
    except subprocess.TimeoutExpired:
        return dict(row, status="timed out", note=f"grading took over {SUBMISSION_SECONDS} s")
    if not report.exists():
        message = (r.stderr.strip().splitlines() or ["no result"])[-1]
        return dict(row, status="not graded", note=message.removeprefix("kit: "))
    data = json.loads(report.read_text())
    row["score"] = data["score"]
    row["max_score"] = sum(t["max_score"] for t in data["tests"])
    by_number = {s["step"]: s for s in data["extra_data"]["steps"]}
    row["status"] = "complete" if all(s["state"] == "done" for s in by_number.values()) else "incomplete"
    notes = []
    for s in steps:
        res = by_number.get(s.number)
        if res is None:
            continue
        row[f"step{s.number}_state"] = res["state"]
        row[f"step{s.number}_basic"] = res["basic"]["passed"]
        row[f"step{s.number}_basic_total"] = res["basic"]["total"]
        row[f"step{s.number}_robust"] = res["robust"]["passed"]
        row[f"step{s.number}_robust_total"] = res["robust"]["total"]
        bad = sorted({c["status"] for c in res["cases"] if c["status"] in ("crashed", "timed_out", "threw")})
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
    json_dir = Path(args.json_dir) if args.json_dir else None
    if json_dir is not None:
        json_dir.mkdir(parents=True, exist_ok=True)
    folders = sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith("."))
    if not folders:
        raise KitError(f"{args.submissions}: holds no submission folders")
    steps = load_steps()
    rows = []
    start = time.monotonic()
    BUILD.mkdir(exist_ok=True)
    for i, folder in enumerate(folders, 1):
        print(f"[{i}/{len(folders)}] {folder.name} ...", end="", flush=True, file=sys.stderr)
        report = BUILD / "grade-one.json"
        row = grade_one(folder, steps, report)
        if json_dir is not None and report.exists():
            (json_dir / f"{folder.name}.json").write_text(report.read_text())
        rows.append(row)
        print(f" {row.get('status')} {row.get('score', '')}", file=sys.stderr)
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=columns(steps), restval="")
    writer.writeheader()
    writer.writerows(rows)
    tmp = out.with_name(f".{out.name}.{os.getpid()}.tmp")
    tmp.write_text(text.getvalue())
    tmp.replace(out)
    say(f"graded {len(rows)} submissions in {time.monotonic() - start:.0f} s: {out}")
    width = max(len(r["student"]) for r in rows)
    for r in rows:
        say(f"  {r['student'].ljust(width)}  {str(r.get('score', '-')).rjust(4)} / {str(r.get('max_score', '-')).ljust(4)} "
            f"{r.get('status', '')}  {r.get('note', '')}")
    return 0

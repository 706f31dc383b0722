"""./kit grade SUBMISSIONS: batch grading of a class into a CSV table, on one scale.

Each submission is graded by a child ./kit (so nothing one does can stop the batch),
in its own build folder and sandbox slot, several at a time (-j).
"""

from __future__ import annotations

import csv
import io
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

from raykit import atomic
from raykit import course as course_file
from raykit import faults
from raykit import judgedby
from raykit import secret as secret_file
from raykit import studentpch
from raykit import record as results_record

from raykit.checking import VERDICTS_ENV
from raykit.common import BUILD, ROOT, KitError, load_steps, printable, say, student_file_name
from raykit.packages import ensure_packages
from raykit.sandbox import WithheldFromOthers, kill_session, kill_uid
from ..report.make import from_grade
from ..report.rows import NOT_GRADED_WORDS, csv_text, record_row
from raykit.submissions import NotFound, locate
from raykit.status import FAILED, NOTHING_SUBMITTED, OK

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
    p.add_argument("--json-dir", metavar="DIR", help="also keep each student's results record here (the kit's own format, raykit/record.py: "
                        "every case, hidden inputs included)")
    p.add_argument("--report", metavar="DIR", help="also write the class report (./kit report) in DIR, the grading in DIR/grading/")
    p.add_argument("--roster", metavar="CSV",
                   help="the class list (any columns, one naming each student's folder or .zip): one row per "
                        "student on it, submitted or not, its columns first")
    p.add_argument("--roster-key", metavar="COLUMN",
                   help="the roster's column that names the folder or .zip (default: the one that matches most)")
    p.add_argument("--cases", metavar="FILE",
                   help="the long CSV, one row per student and case (default: OUT with -cases before .csv)")
    p.add_argument("--new-secret", action="store_true",
                   help="make the hidden cases' secret (tests/hidden/secret.key) even though the folder graded into "
                        "holds a grading drawn with another one (docs/instructors.md: one course, several machines)")


def columns(steps) -> list[str]:
    """The grades CSV: the total rounded once (course.json's decimals) and exact, then each step. With
    extra credit (course.json), "earned" is the total with it, "extra_credit" what of it is extra credit,
    and "percent" the points without it of the maximum, as the terminal's "(88 %)" says (empty
    extra_credit: the course has none)."""
    cols = ["student", "earned", "maximum", "percent", "extra_credit", "status"]
    for s in steps:
        cols += [f"step{s.number}_state", f"step{s.number}_earned", f"step{s.number}_maximum",
                 f"step{s.number}_robust", f"step{s.number}_robust_total"]
    return cols + ["earned_exact", "isolation", "note"]


CASE_COLUMNS = ["submission", "step", "case", "tier", "group", "status", "points", "earned"]


def write_file(out: Path, text: str) -> None:
    """Written whole or not at all (atomic.write)."""
    try:
        atomic.write(out, text)
    except OSError as e:
        raise KitError(f"{out}: cannot write it ({e.strerror})")


@dataclass
class Roster:
    columns: list[str]
    rows: list[dict]
    key: str


def _norm(name: str) -> str:
    return " ".join(name.strip().lower().split())


def read_roster(path: Path, names: list[str], key: str | None = None) -> Roster:
    """The class list at `path` (a CSV with a header, separated by , ; or tab); `key` is the column
    that names each student's folder or .zip, by default the one matching most of `names`."""
    try:
        text = path.read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise KitError(f"--roster {path}: no such file")
    except (OSError, UnicodeDecodeError) as e:
        raise KitError(f"--roster {path}: cannot read it as UTF-8 text ({e.__class__.__name__})")
    try:
        dialect = csv.Sniffer().sniff(text[:4096], delimiters=",;\t")
    except csv.Error:
        dialect = csv.excel
    rows = list(csv.reader(io.StringIO(text), dialect))
    rows = [r for r in rows if any(cell.strip() for cell in r)]
    if len(rows) < 2:
        raise KitError(f"--roster {path}: expected a header line and one line per student")
    header = [h.strip() for h in rows[0]]
    if any(not h for h in header) or len(set(header)) != len(header):
        raise KitError(f"--roster {path}: every column needs a name of its own in the header line ({rows[0]})")
    kit_columns = set(CASE_COLUMNS) | {"student", "earned", "maximum", "percent", "extra_credit", "status", "earned_exact",
                                       "isolation", "note"}
    clash = next((c for c in header if c in kit_columns or re.match(r"step\d\d_", c)), None)
    if clash:
        raise KitError(f"--roster {path}: the column {clash!r} is one the kit writes; rename it")
    students = []
    for n, r in enumerate(rows[1:], 2):
        if len(r) > len(header):
            raise KitError(f"--roster {path}: line {n} has {len(r)} cells, the header {len(header)}")
        students.append({h: (r[i].strip() if i < len(r) else "") for i, h in enumerate(header)})
    wanted = {_norm(n) for n in names}
    if key is not None:
        if key not in header:
            raise KitError(f"--roster-key {key}: no such column in {path} (columns: {', '.join(header)})")
    else:
        exact = set(names)
        rank = {h: (sum(_norm(s[h]) in wanted for s in students), sum(s[h] in exact for s in students))
                for h in header}
        key = max(header, key=lambda h: rank[h])
        if not rank[key][0]:
            raise KitError(f"--roster {path}: no column names a submission folder or .zip (e.g. "
                           f"{', '.join(sorted(names)[:3])}); say which with --roster-key COLUMN")
        tied = [h for h in header if rank[h] == rank[key]]
        if len(tied) > 1:
            raise KitError(f"--roster {path}: the columns {', '.join(map(repr, tied))} match the folders "
                           "equally well; say which with --roster-key COLUMN")
    seen: dict[str, int] = {}
    for s in students:
        k = _norm(s[key])
        if k and k in seen:
            raise KitError(f"--roster {path}: {s[key]!r} is listed twice in column {key!r}")
        seen[k] = 1
    return Roster(header, students, key)


def with_roster(roster: Roster, rows: list[dict], steps) -> tuple[list[str], list[dict], list[str], list[str]]:
    """The grades table with the roster: its columns first, one row per student on it (a student
    with no folder gets status "not submitted" and 0), then the folders on no one's line. Returns
    the columns, the rows, the students not submitted and the folders not on the roster."""
    cols = roster.columns + ["submission"] + columns(steps)[1:]
    by_name = {_norm(r["student"]): r for r in rows}
    maxima = {r.get("maximum") for r in rows if r.get("maximum") not in (None, "")}
    maximum = maxima.pop() if len(maxima) == 1 else ""
    out, missing, matched = [], [], set()
    for s in roster.rows:
        r = by_name.get(_norm(s[roster.key])) if s[roster.key] else None
        if r is None:
            missing.append(s[roster.key] or "(a line with no " + roster.key + ")")
            out.append(dict(s, submission="", earned=0, maximum=maximum, percent="0.0" if maximum else "",
                            status="not submitted",
                            note=f"no folder or .zip named {s[roster.key]!r}" if s[roster.key] else
                            f"no {roster.key} on the roster"))
        else:
            matched.add(_norm(r["student"]))
            out.append(dict({k: v for k, v in r.items() if k != "student"}, **s, submission=r["student"]))
    unknown = [r["student"] for r in rows if _norm(r["student"]) not in matched]
    for r in rows:
        if _norm(r["student"]) not in matched:
            out.append(dict({k: v for k, v in r.items() if k != "student"}, submission=r["student"],
                            note="not on the roster" + ("; " + r["note"] if r.get("note") else "")))
    return cols, out, missing, unknown


def grade_one(folder: Path, steps, report: Path, slot: int = 0, isolation: str = "auto") -> dict:
    """Grades one submission in a child ./kit process, so nothing it does can stop the batch."""
    row = {"student": folder.stem if folder.is_file() else folder.name}
    report.unlink(missing_ok=True)
    try:
        found = locate(folder, BUILD / f"grade-upload-{slot}", steps)
    except NotFound as e:
        return dict(row, status=NOTHING_SUBMITTED, note=str(e))     # the student's: 0, not "not graded"
    uid_file = BUILD / f"grade-uid-{slot}"
    uid_file.unlink(missing_ok=True)
    # Its own session: on a timeout, every process of it (cmake, ninja, the compilers) is ended,
    # and so is every process of the sandbox's user id, so nothing outlives its submission.
    proc = subprocess.Popen([str(ROOT / "kit"), "check", "--steps", str(found.steps_dir), "--results", str(report),
                             "--quiet", "--slot", str(slot), "--isolation", isolation],
                            cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace",
                            start_new_session=True,
                            env=faults.child_env(row["student"], dict(os.environ, RAYKIT_UID_FILE=str(uid_file))))
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
        # Every case and step has its own limit: a whole submission past this one is a stuck or
        # overloaded grader (its placeholder written, nothing after), so it is graded again alone.
        return dict(row, status="timed out", note=f"grading took over {SUBMISSION_SECONDS} s", _retry=True)
    r = subprocess.CompletedProcess(proc.args, proc.returncode, "", stderr)
    if not report.exists():
        message = (r.stderr.strip().splitlines() or ["no result"])[-1].removeprefix("kit: ")
        if "Traceback (most recent call last)" in r.stderr:
            # The kit itself failed: its whole report kept for whoever fixes it, and named in the note.
            log = BUILD / "grade-logs" / f"{student_file_name(row['student'])}.txt"
            try:
                log.parent.mkdir(parents=True, exist_ok=True)
                log.write_text(printable(r.stderr), encoding="utf-8")
                message += f" (the kit failed, not the submission; its report: {log})"
            except OSError:
                pass
        return dict(row, status=NOT_GRADED_WORDS, note=message, _retry=True)
    try:
        data = results_record.read(report)
    except KitError as e:
        return dict(row, status=NOT_GRADED_WORDS, note=f"the kit wrote no usable record ({e})", _retry=True)
    if not results_record.finished(data):
        # Only the placeholder: the check died after writing it (a full disk, a crash, a kill). Not
        # the student's 0 of 0: not graded, with how it ended.
        how = (f"killed by {signal_name(-r.returncode)}" if r.returncode < 0 else f"exit status {r.returncode}")
        last = (r.stderr.strip().splitlines() or [""])[-1].removeprefix("kit: ")[:300]
        return dict(row, status=NOT_GRADED_WORDS, _retry=True,
                    note=f"the kit's check stopped before it finished ({how})" + (f": {last}" if last else ""))
    return record_row(row, data, steps, found.notes)


def signal_name(number: int) -> str:
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def run(args) -> int:
    ensure_packages("build")
    root = Path(args.submissions)
    if not root.is_dir():
        raise KitError(f"{args.submissions}: no such folder")
    out = Path(args.out)
    if out.is_dir():
        raise KitError(f"--out {args.out}: is a folder, not a file")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)     # a folder that does not exist yet is made
    except OSError as e:
        raise KitError(f"--out {args.out}: cannot make its folder ({e.strerror})")
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
    global SUBMISSION_SECONDS      # the course's limit for one submission (course.json time_limits)
    SUBMISSION_SECONDS = faults.submission_seconds(int(course_file.load().limits["submission_seconds"]))
    roster = None
    if args.roster:
        roster = read_roster(Path(args.roster), [f.stem if f.is_file() else f.name for f in folders], args.roster_key)
    elif args.roster_key:
        raise KitError("--roster-key names a column of --roster CSV: give the roster too")
    cases_out = Path(args.cases) if args.cases else out.with_name(out.stem + "-cases" + (out.suffix or ".csv"))
    if cases_out.resolve() == out.resolve() or cases_out.is_dir() or not cases_out.parent.resolve().is_dir():
        raise KitError(f"--cases {cases_out}: cannot write the cases CSV there")
    start = time.monotonic()
    BUILD.mkdir(exist_ok=True)
    # The secret that draws the hidden inputs (one line saying which), and what judges this grading,
    # hashed once for every check (judgedby.py): kept sealed beside the records for a merge to compare.
    key = _the_secret(args, json_dir)
    manifest = judgedby.build()
    os.environ[judgedby.ENV] = manifest["digest"]
    if json_dir is not None and key is not None:
        judgedby.write(json_dir, manifest, key)
    jobs = max(1, min(args.jobs, len(folders)))
    # The verdicts of this grading by content (checking.Verdicts): a step whose files another
    # submission already had is judged once. Its own folder, gone when the grading ends.
    verdicts = Path(tempfile.mkdtemp(prefix="grade-verdicts-", dir=BUILD))
    os.environ[VERDICTS_ENV] = str(verdicts)
    # Many compiles follow: the step headers precompiled once for all of them (studentpch.py).
    os.environ.setdefault(studentpch.ENV, "build")
    try:
        # Under the user isolation the graded code runs as another user of this machine: the class
        # folder is closed to it while the class is graded (sandbox/), then opened as it was.
        with WithheldFromOthers(root, folders, args.isolation):
            return _grade(args, folders, steps, roster, out, cases_out, json_dir, jobs, start, key)
    finally:
        os.environ.pop(VERDICTS_ENV, None)
        os.environ.pop(judgedby.ENV, None)
        shutil.rmtree(verdicts, ignore_errors=True)


def _named_secrets(folders: list[Path]) -> dict[str, Path]:
    """The secrets (by fingerprint) the gradings already in `folders` were drawn with: their list of what
    judged them (judgedby.FILE_NAME), else their records' grader."""
    named: dict[str, Path] = {}
    for folder in folders:
        path = folder / judgedby.FILE_NAME
        try:
            manifest = judgedby.read(path)
        except KitError:
            manifest = None
        if manifest and manifest.get("secret"):
            named.setdefault(str(manifest["secret"]), path)
        for record in sorted(folder.glob("*.json")) if folder.is_dir() else []:
            try:
                fp = results_record.read(record).get("grader", {}).get("secret")
            except (KitError, AttributeError):
                continue
            if fp:
                named.setdefault(str(fp), record)
                break
    return named


def _the_secret(args, json_dir: Path | None) -> bytes | None:
    """The hidden cases' secret for this grading, its fingerprint said in one line. Made when there is
    none, with a warning (a TA who forgot to copy it draws other inputs); refused when the folder graded
    into (--json-dir, --report's grading/json/) holds a grading drawn with another secret, unless
    --new-secret. None where this copy grades no hidden case (no solutions/ or tests/hidden/)."""
    from raykit.bundle import hidden_here
    if not hidden_here():
        say("secret: none (this copy of the kit grades no hidden cases)")
        return None
    targets = [p for p in {json_dir, Path(args.report) / "grading" / "json" if args.report else None} if p is not None]
    key = secret_file.existing()
    if key is not None:
        if args.new_secret:
            raise KitError(f"--new-secret: {secret_file.SECRET_FILE} exists already (fingerprint "
                           f"{secret_file.fingerprint_of(key)}); delete it first to start a new draw for every "
                           "submission")
        fp = secret_file.fingerprint_of(key)
        pinned = os.environ.get(secret_file.SECRET_ENV)
        say(f"secret: fingerprint {fp} ({secret_file.SECRET_ENV if pinned else secret_file.SECRET_FILE.relative_to(ROOT)})")
        other = {f: p for f, p in _named_secrets(targets).items() if f != fp}
        for f, p in other.items():
            say(f"  warning: {printable(str(p))} was drawn with another secret ({f}); this grading replaces it")
        return key
    named = _named_secrets(targets)
    if named and not args.new_secret:
        where = "; ".join(f"{printable(str(p))} names secret {f}" for f, p in named.items())
        raise KitError(f"no secret in {secret_file.SECRET_FILE.relative_to(ROOT)}, and the folder graded into holds "
                       f"a grading drawn with another ({where}). Copy tests/hidden/secret.key from the machine "
                       "that made it (docs/instructors.md: one course, several machines), or, to start a new draw on purpose, "
                       "grade with --new-secret")
    key = secret_file.secret()
    fp = secret_file.fingerprint_of(key)
    say(f"secret: fingerprint {fp} ({secret_file.SECRET_FILE.relative_to(ROOT)}, made now)")
    print(f"warning: this copy of the kit had no secret, so it made a new one ({fp}). Its hidden inputs differ "
          f"from any other machine's: if another machine grades this class, copy its tests/hidden/secret.key "
          f"here instead (mode 0600), delete this one and grade again (docs/instructors.md: one course, several machines)",
          file=sys.stderr, flush=True)
    return key


def _grade(args, folders, steps, roster, out, cases_out, json_dir, jobs, start, key) -> int:
    done = [0]

    def one(item: tuple[int, Path], slot: int | None = None, again: bool = False) -> dict:
        i, folder = item
        slot = i % jobs if slot is None else slot
        report = BUILD / f"grade-one-{slot}.json"
        row = grade_one(folder, steps, report, slot, args.isolation)
        if json_dir is not None:    # a finished record only: a placeholder is no result (record.finished)
            kept = json_dir / f"{student_file_name(row['student'])}.json"
            kept.unlink(missing_ok=True)
            try:
                data = results_record.read(report)
                if results_record.finished(data):
                    # Sealed under the secret (secret.seal): the merge refuses a record edited or written by hand.
                    atomic.write(kept, json.dumps(secret_file.seal(data, key) if key is not None else data, indent=1,
                                                  ensure_ascii=False))
            except KitError:
                pass
        done[0] += 0 if again else 1
        print(f"[{'again, alone' if again else f'{done[0]}/{len(folders)}'}] {printable(folder.name)}: "
              f"{row.get('status')} {row.get('earned', '')}/{row.get('maximum', '')}", file=sys.stderr, flush=True)
        return row

    # Slot k serves submissions k, k + jobs, ...: one build folder and one sandbox user each.
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        by_slot = [[(i, f) for i, f in enumerate(folders) if i % jobs == k] for k in range(jobs)]
        rows_by_slot = list(pool.map(lambda items: [(item, one(item)) for item in items], by_slot))
    # A submission the grader failed (its check died, left only its placeholder, or a step has no
    # verdict) is graded once more, alone (-j 1: no neighbour's load, its disk or its ids), before it is
    # listed as not graded (docs/integrity.md).
    rows = []
    for item, row in (pair for slot_rows in rows_by_slot for pair in slot_rows):
        if row.pop("_retry", False):
            first = row.get("note", "")
            row = one(item, slot=0, again=True)
            if row.pop("_retry", False):
                row["note"] = (row.get("note") or first) + "; so also when graded again alone"
            else:
                row["note"] = "; ".join(n for n in (row.get("note"), f"graded again alone, as the first "
                                                    f"grading was not: {first}") if n)
        rows.append(row)
    rows.sort(key=lambda r: r["student"])
    case_rows = [dict(c, submission=r["student"], student=r["student"]) for r in rows
                 for c in r.pop("_cases", None) or ([{"step": "", "case": "", "tier": "", "group": "", "points": "",
                                                       "status": NOT_GRADED_WORDS, "earned": NOT_GRADED_WORDS}]
                                                     if r.get("status") in (NOT_GRADED_WORDS, "timed out") else [])]
    # No blank score: a submission with no steps scores 0 of the one maximum; one the grader failed
    # says "not graded" where its score would be (never 0, nor "0 of 0"), and its note says why.
    maxima = {r["maximum"] for r in rows if r.get("maximum") not in (None, "")}
    for r in rows:
        if r.get("earned") in (None, "") and len(maxima) == 1:
            r.update(maximum=next(iter(maxima)))
            if r.get("status") in (NOT_GRADED_WORDS, "timed out"):
                r.update(earned=NOT_GRADED_WORDS, percent="")
            else:
                r.update(earned=0, percent="0.0")
    cols, missing, unknown = columns(steps), [], []
    if roster is not None:
        cols, rows, missing, unknown = with_roster(roster, rows, steps)
        ids = {r["submission"]: {k: r.get(k, "") for k in roster.columns} for r in rows if r.get("submission")}
        case_rows = [dict(ids.get(c["submission"], {}), **c) for c in case_rows]
    id_cols = roster.columns if roster is not None else []
    write_file(out, csv_text(cols, rows))
    write_file(cases_out, csv_text(id_cols + CASE_COLUMNS, case_rows))
    say(f"graded {len(folders)} submissions in {time.monotonic() - start:.0f} s: {out} (cases: {cases_out})")
    shown = [r.get("submission", r.get("student", "")) or r.get(roster.key, "") if roster else r["student"]
             for r in rows]
    shown = [printable(str(n)) for n in shown]
    width = max(len(n) for n in shown)
    for n, r in zip(shown, rows):
        say(f"  {n.ljust(width)}  {str(r.get('earned', '-')).rjust(6)} / {str(r.get('maximum', '-')).ljust(6)} "
            f"{r.get('status', '')}  {printable(str(r.get('note', '')))}")
    skipped = [r for r in rows if r.get("note") and "left out" in r["note"]]
    if missing:
        say(f"not submitted ({len(missing)}): {printable(', '.join(missing))}")
    if unknown:
        say(f"on no one's roster line ({len(unknown)}), graded but not matched: {printable(', '.join(unknown))}")
    if skipped:
        say(f"uploads with files left out ({len(skipped)}): "
            + printable(", ".join(r.get("submission") or r.get("student", "") for r in skipped)) + " (see their note)")
    empty = [r for r in rows if r.get("status") == NOTHING_SUBMITTED]
    if empty:   # the students': 0 points, each with what was wrong with the upload; the exit status stays
        say(f"nothing submitted ({len(empty)}, 0 points each): "
            + printable(", ".join(r.get("submission") or r.get("student", "") for r in empty)))
        for r in empty:
            say(f"  {printable(r.get('submission') or r.get('student', ''))}: {printable(str(r.get('note', '')))}")
    not_graded = [r for r in rows if r.get("status") in (NOT_GRADED_WORDS, "timed out")]
    if not_graded:
        say(f"not graded ({len(not_graded)}): "
            + printable(", ".join(r.get("submission") or r.get("student", "") for r in not_graded)))
        for r in not_graded:    # each with its reason; the grader's faults are its to fix, then grade again
            say(f"  {printable(r.get('submission') or r.get('student', ''))}: {printable(str(r.get('note', '')))}")
        say("  (the grader's fault, not the students': no points were taken; fix the cause, then grade "
            "these again: docs/integrity.md, \"Not graded\")")
    # The grading is not whole while the grader failed some submission: the exit status says so too
    # (FAILED), after every file is written, so a script does not publish it as it is.
    faulty = any(r.get("status") in (NOT_GRADED_WORDS, "timed out") for r in not_graded)
    if args.report:     # the class report, from the grading just saved (commands/report.py)
        return from_grade(args, out, json_dir, cases_out) or (FAILED if faulty else OK)
    return FAILED if faulty else OK

"""Self-test of "not graded" (raykit/faults.py): the grader's faults, caused on purpose, cost no student
a point on any output.

A class of copies of the reference, each with a comment of its own (so no verdict is shared between
them, checking.Verdicts), is graded by `./kit grade` with the faults of faults.py's hooks: a child check
killed once after writing its placeholder (the retry alone grades it), one killed every time, one whose
scratch is a disk the test filled (a tmpfs of its own, as root), one whose judge aborts in the last
step. Then `./kit check` alone, with each platform's output, under the same faults. What each output
must say is drawn from the course as it is: its steps and their points (course.json, the recorded case
lists), never totals written here.
"""

from __future__ import annotations

import base64
import csv
import html
import json
import os
import shutil
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest

from raykit import course as course_file
from raykit.cases import StepResult
from raykit.checking import recorded_cases
from raykit.common import BUILD, ROOT, load_steps, student_file_name
from raykit.status import DONE
from . import scale
from .support import Failed, Skipped, expect, need_solutions, partly_skipped

WORK = BUILD / "faults-test"
DISK = WORK / "disk"
DISK_BYTES = 256 * 1024
HANG_SECONDS = 60       # ./kit grade's limit for a submission in the hang test: a retry alone fits in it


def _maxima() -> dict[str, Fraction]:
    """Each step's points on the course's scale, from course.json and the recorded case lists."""
    out = {}
    for s in load_steps():
        cases = recorded_cases(s)
        if cases is None:
            raise Skipped(f"no recorded case list for step {s.number} (./kit check --record)")
        out[s.number] = StepResult(s, DONE, cases).maximum
    return out


def _class(names: list[str]) -> Path:
    klass = WORK / "class"
    shutil.rmtree(klass, ignore_errors=True)
    for name in names:
        for s in load_steps():
            for f in s.files:
                target = klass / name / s.folder / f
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_text((ROOT / "solutions" / s.folder / f).read_text() + f"\n// {name}'s copy\n")
    return klass


def _full_disk() -> Path:
    """A tmpfs of its own, filled but for one page: the scratch folder Python still accepts, where the
    kit's first copies then fail with "No space left on device"."""
    if os.geteuid() != 0:
        raise Skipped("mounting a small disk to fill needs root", need="root")
    _unmount()
    DISK.mkdir(parents=True, exist_ok=True)
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={DISK_BYTES},mode=1777", "tmpfs", str(DISK)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise Skipped(f"cannot mount a tmpfs here ({r.stderr.strip()[:200]})", need="root")
    with open(DISK / "filler", "wb") as f:
        f.write(b"\0" * (DISK_BYTES - 4096))
    return DISK


def _unmount() -> None:
    if DISK.is_dir() and os.path.ismount(DISK):
        subprocess.run(["umount", "-l", str(DISK)], capture_output=True)


def _env(faults: str, **extra: str) -> dict[str, str]:
    marks = WORK / "marks"
    shutil.rmtree(marks, ignore_errors=True)
    return dict(os.environ, RAYKIT_FAULT=faults, RAYKIT_FAULT_MARKS=str(marks), RAYKIT_FAULT_DISK=str(DISK),
                RAYKIT_NO_WARMUP="1", **extra)


def selftest_grade(ctx) -> str:
    """./kit grade under four faults: each CSV, the not-graded list and the class report say "not graded"
    with the reason, never a score; the one killed once is graded again alone and gets its points."""
    need_solutions()
    course = course_file.load()
    maxima = _maxima()
    last = load_steps()[-1].number
    total = course.shown(sum(maxima.values(), Fraction(0)))
    try:        # the full disk needs a tmpfs of its own: as root, where mounting is allowed
        _full_disk()
        disk, skipped = True, ""
    except Skipped as e:
        disk, skipped = False, partly_skipped(e.need, f"the full disk left out: {e}")
    names = ["alice", "bob", "carol", "dave", "erin"] if disk else ["alice", "bob", "carol", "erin"]
    klass = _class(names)
    out = WORK / "out"
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    try:
        r = subprocess.run([str(ROOT / "kit"), "grade", str(klass), "-j", "2", "--out", str(out / "grades.csv"),
                            "--report", str(out / "report")], cwd=ROOT, capture_output=True, text=True, timeout=1800,
                           env=_env(f"killed-once@bob,killed@carol,full-disk@dave,judge#{last}@erin"))
    finally:
        _unmount()
    said = r.stdout + r.stderr
    expect(r.returncode == 1 and (out / "grades.csv").is_file(),
           f"./kit grade exited {r.returncode}, not 1 (written, but not whole): {said[-800:]}")
    rows = {row["student"]: row for row in csv.DictReader((out / "grades.csv").open())}
    problems = []

    def check(ok: bool, what: str) -> None:
        if not ok:
            problems.append(what)

    # Full marks on the course as set: the maximum, and the extra credit a copy of the solutions passes on
    # top when a group is extra credit (scale.py), from each one's record (--report keeps them).
    records = {}
    for j in (out / "report" / "grading" / "json").glob("*.json"):
        if j.name.startswith("."):
            continue        # the grading's list of inputs (.judged-by.json), not a student's record
        try:
            records[j.stem] = json.loads(j.read_text())     # named student_file_name(who)
        except ValueError:
            pass
    full = {w: scale.shown(scale.full_total(rec)) for w, rec in records.items() if rec.get("steps")}
    for who in ("alice", "bob"):
        row = rows[who]
        mine = records.get(student_file_name(who))
        short = scale.record_short_of_full(mine) if mine else "no record kept"
        want = full.get(student_file_name(who))
        check(row["status"] == "complete" and not short and row["earned"] == want and row["maximum"] == total,
              f"{who}: {row['status']} {row['earned']} of {row['maximum']}, not complete {want} of {total}"
              + (f" ({short})" if short else ""))
    check("again" in rows["bob"]["note"] and "alone" in rows["bob"]["note"],
          f"bob (killed once): the note does not say it was graded again alone: {rows['bob']['note']!r}")
    faulty = [(w, words) for w, words in (("carol", "SIGKILL"), ("dave", "No space left on device"),
                                         ("erin", f"step {last}")) if w in names]
    for who, words in faulty:
        row = rows[who]
        check(row["status"] == "not graded" and row["earned"] == "not graded" and row["percent"] == "",
              f"{who}: status {row['status']!r}, earned {row['earned']!r}, percent {row['percent']!r}, not "
              "\"not graded\" with no score")
        check(words in row["note"], f"{who}: the note does not give the reason ({words!r}): {row['note']!r}")
        check(row["maximum"] == total, f"{who}: maximum {row['maximum']!r}, not the course's {total}")
    erin = rows["erin"]
    check(erin[f"step{last}_state"] == "not graded" and erin[f"step{last}_earned"] == "not graded",
          f"erin's step {last}: {erin[f'step{last}_state']!r}, {erin[f'step{last}_earned']!r}")
    # Her other steps have full marks: their maxima, and the extra credit her record shows they passed.
    erins = {st["step"]: st for st in records.get(student_file_name("erin"), {}).get("steps", [])}
    for s, points in maxima.items():
        if s != last:
            want = points + (scale.bonus(erins[s]["cases"]) if s in erins else 0)
            short = scale.short_of_full(erins[s]) if s in erins else f"no step {s} in her record"
            check(erin[f"step{s}_earned"] == course.shown(want) and not short,
                  f"erin's step {s}: {erin[f'step{s}_earned']!r}, not {course.shown(want)} ({course.shown(points)} and "
                  f"its extra credit), though only step {last} failed" + (f": {short}" if short else ""))
    zero = [w for w, row in rows.items() if row["maximum"] in ("0", "") or row["status"] == "complete" and row["earned"] != full.get(student_file_name(w))]
    check(not zero, f"a submission with steps reads 0 of 0 or complete short of the total: {zero}")
    listed = next((line for line in said.splitlines() if line.strip().startswith("not graded (")), "")
    check(listed.strip().startswith(f"not graded ({len(faulty)})") and all(w in listed for w, _ in faulty),
          f"the not-graded list: {listed!r}")
    for who, words in faulty:
        check(any(line.strip().startswith(f"{who}:") and words in line for line in said.splitlines()),
              f"{who} is not listed with its reason ({words!r}) under \"not graded\"")
    cases = list(csv.DictReader((out / "grades-cases.csv").open()))
    check(any(c["submission"] == "erin" and c["step"] == last and c["earned"] == "not graded" for c in cases),
          f"the cases CSV gives no erin step {last} case as not graded")
    check(any(c["submission"] == "carol" and c["status"] == "not graded" for c in cases),
          "the cases CSV says nothing of carol, not graded")
    check(not any(c["submission"] == "erin" and c["step"] == last and c["status"] == "crashed" for c in cases),
          f"the cases CSV has erin's step {last} crashed (the judge's abort as the student's crash)")
    report = out / "report"
    index = html.unescape((report / "index.html").read_text())     # the text, whatever the escaping's form
    check("Not graded" in index and all(w in index for w in [w for w, _ in faulty if w != "erin"]
                                         + [f"step {last}: the kit's test program"]),
          "the class report's incidents have no \"Not graded\" group naming carol, dave and erin's step")
    check(f"{len(faulty)} not graded" in index, "the class report's first line does not count those not graded")
    page = next((p for p in (report / "students").glob("erin*.html")), None)
    text = page.read_text() if page else ""
    check("Not graded yet" in text and "Your score" not in text, "erin's page gives a score, or no \"not graded\"")
    page = next((p for p in (report / "students").glob("carol*.html")), None)
    check(page is not None and "not graded" in page.read_text(), "carol's page does not say \"not graded\"")
    kept = report / "grading" / "json" / "carol.json"
    check(not kept.exists(), "carol's placeholder was kept as her record")
    # A check that hangs once after its placeholder: ended by the submission's limit, graded again alone.
    hung = WORK / "hung"
    shutil.rmtree(hung, ignore_errors=True)
    hung.mkdir(parents=True)
    shutil.copytree(klass / "bob", hung / "frank")
    r2 = subprocess.run([str(ROOT / "kit"), "grade", str(hung), "-j", "1", "--out", str(out / "hung.csv"),
                         "--json-dir", str(out / "hung-json")], cwd=ROOT,
                        capture_output=True, text=True, timeout=900,
                        env=_env("hang-once@frank", RAYKIT_FAULT_SUBMISSION_SECONDS=str(HANG_SECONDS)))
    frank = next(csv.DictReader((out / "hung.csv").open()), {}) if (out / "hung.csv").is_file() else {}
    # Full marks on the course as set, from his record: the maximum and the extra credit he passed.
    kept = out / "hung-json" / f"{student_file_name('frank')}.json"
    franks = json.loads(kept.read_text()) if kept.is_file() else None
    short = scale.record_short_of_full(franks) if franks and franks.get("steps") else "no record kept"
    want = scale.shown(scale.full_total(franks)) if not short else total
    check(r2.returncode == 0 and frank.get("status") == "complete" and frank.get("earned") == want and not short
          and "over" in frank.get("note", "") and "alone" in frank.get("note", ""),
          f"frank (hung once): exit {r2.returncode}, {frank.get('status')} {frank.get('earned')}, note "
          f"{frank.get('note')!r}, not complete {want} of {total} after a retry alone" + (f" ({short})" if short else ""))
    if problems:
        raise Failed("; ".join(problems) + f"\n./kit grade said:\n{said[-1500:]}")
    return (f"killed once, hung once: graded again alone, {total} of {total}; killed, {'full disk, ' if disk else ''}judge aborted in step {last}: "
            f"\"not graded\" with the reason in the CSV, the cases CSV, the list and the report"
            + (f"; {skipped}" if skipped else ""))


def _check(name: str, env: dict[str, str]) -> tuple[subprocess.CompletedProcess, dict]:
    folder = WORK / "platforms" / name
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    files = {k: folder / f"{k}.json" for k in ("results", "json", "prairielearn", "classroom")}
    argv = [str(ROOT / "kit"), "check", "--steps", str(WORK / "class" / name), "--slot", "7"]
    for k, p in files.items():
        argv += [f"--{k}", str(p)]
    r = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, timeout=900, env=dict(env, RAYKIT_SUBMISSION=name))
    data = {}
    for k, p in files.items():
        try:
            data[k] = json.loads(p.read_text())
        except (OSError, ValueError):
            data[k] = None
    return r, data


def _classroom_step(path: Path, number: str) -> dict:
    r = subprocess.run([sys.executable, str(ROOT / "tools" / "classroom" / "result.py"), str(path), number],
                       capture_output=True, text=True, env={k: v for k, v in os.environ.items() if k != "GITHUB_OUTPUT"})
    return json.loads(base64.b64decode(r.stdout.strip().removeprefix("result=")))


def selftest_platforms(ctx) -> str:
    """./kit check alone under the judge's abort, a full disk and a kill after the placeholder: Gradescope's
    results.json takes no point away and asks for a regrade, PrairieLearn's is gradable: false, Classroom's
    runner is an error, the terminal says "not graded", the record carries each reason as data."""
    need_solutions()
    course = course_file.load()
    maxima = _maxima()
    last = load_steps()[-1].number
    if not (WORK / "class" / "erin").is_dir():
        _class(["alice", "bob", "carol", "dave", "erin"])
    problems = []
    who_dir = {"judge aborted": "erin", "full disk": "dave"}

    def check(ok: bool, what: str) -> None:
        if not ok:
            problems.append(what)

    def platforms(who: str, data: dict, missed: set[str]) -> None:
        rec, gs, pl, cl = data["results"], data["json"], data["prairielearn"], data["classroom"]
        if not all((rec, gs, pl, cl)):
            check(False, f"{who}: an output is missing or unreadable: {[k for k, v in data.items() if not v]}")
            return
        said = {n["step"] for n in rec.get("not_graded", [])}
        check(said == missed and rec.get("gradable") is False and rec.get("finished") is True,
              f"{who}: the record's not_graded {sorted(said)}, gradable {rec.get('gradable')}, not {sorted(missed)}, false")
        check(all(s.get("not_graded") for s in rec["steps"] if s["step"] in missed),
              f"{who}: a not-graded step of the record carries no reason")
        for s in rec["steps"]:
            if s["step"] not in missed:
                check(s["state"] == DONE, f"{who}: step {s['step']} is {s['state']}, though only {sorted(missed)} failed")
        tagged = {t["tags"][0].removeprefix("step") for t in gs["tests"] if "not_graded" in t.get("tags", [])}
        check(tagged == missed, f"{who}: Gradescope's not-graded tests are for steps {sorted(tagged)}, not {sorted(missed)}")
        lost = [t["name"] for t in gs["tests"] if t["status"] == "failed" and t.get("max_score", 0) > 0]
        check(not lost, f"{who}: Gradescope takes points away: {lost[:3]}")
        # The graded steps' full marks: their maxima, and the extra credit their cases passed (scale.py).
        graded = sum((p for n, p in maxima.items() if n not in missed), Fraction(0)) + sum(
            (scale.bonus(s["cases"]) for s in rec["steps"] if s["step"] not in missed), Fraction(0))
        check(scale.exact(gs["score"]) == course.rounded(graded),
              f"{who}: Gradescope's score {gs['score']}, not the graded steps' {course.shown(graded)}")
        check(gs["output"].startswith("NOT GRADED") and "regrade" in gs["output"].lower(),
              f"{who}: Gradescope's output does not open with NOT GRADED and a regrade: {gs['output'][:200]!r}")
        check(pl.get("gradable") is False and pl.get("format_errors") and "score" not in pl,
              f"{who}: PrairieLearn's results are not gradable: false with format_errors: {str(pl)[:200]}")
        v = subprocess.run([sys.executable, str(ROOT / "tools/prairielearn/check_results.py"), "results",
                            str(WORK / "platforms" / who_dir[who] / "prairielearn.json")], capture_output=True, text=True)
        check(v.returncode == 0, f"{who}: PrairieLearn would not read its results as they are: {v.stdout[:300]}")
        for n, runner in cl["runners"].items():
            want = "error" if n in missed else "pass"
            check(runner["status"] == want and (runner["max_score"] == 0) == (n in missed),
                  f"{who}: Classroom's step {n} runner is {runner['status']} of {runner['max_score']}, not {want}")
        check(cl["max_score"] == sum(r["max_score"] for r in cl["runners"].values()),
              f"{who}: Classroom's Points X/Y counts a not-graded step")

    # The judge aborts in the last step.
    r, data = _check("erin", _env(f"judge#{last}@erin"))
    platforms("judge aborted", data, {last})
    title = load_steps()[-1].title
    row = next((line for line in r.stdout.splitlines() if line.strip().startswith(f"{last}  {title}")), "")
    check("not graded" in row and "✗" not in row and "in 1 case" not in row and "case(s)" not in row,
          f"the terminal's step {last} row: {row.strip()!r}")
    check(f"not graded: step {last}" in r.stdout, "the terminal's score line does not say which step is not graded")
    # A full scratch disk: every step it builds is not graded, none a student's failure.
    try:
        _full_disk()
        disk, skipped = True, ""
    except Skipped as e:
        disk, skipped = False, partly_skipped(e.need, f"the full disk left out: {e}")
    missed = set()
    if disk:
        try:
            r, data = _check("dave", _env("", TMPDIR=str(DISK), RAYKIT_KIT_TEMP=str(DISK)))
        finally:
            _unmount()
        missed = {n["step"] for n in (data["results"] or {}).get("not_graded", [])}
        check(bool(missed), f"a full disk: no step is not graded; the check said {(r.stdout + r.stderr)[-600:]!r}")
    if missed:
        platforms("full disk", data, missed)
        reasons = [n["reason"] for n in data["results"]["not_graded"]]
        check(all("No space left on device" in w for w in reasons), f"a full disk: reasons {reasons[:2]}")
    # Killed after its placeholder: what each platform finds says "not graded", never 0 of 0.
    r, data = _check("carol", _env("killed@carol"))
    rec, gs = data["results"], data["json"]
    check(r.returncode < 0, f"the killed check exited {r.returncode}")
    check(bool(rec) and rec.get("finished") is False and not rec.get("steps"),
          f"the placeholder record does not say finished: false: {str(rec)[:200]}")
    check(bool(gs) and gs["tests"] and all("not_graded" in t.get("tags", []) and t["max_score"] == 0 for t in gs["tests"])
          and gs["output"].startswith("NOT GRADED"), f"Gradescope's placeholder: {str(gs)[:300]}")
    for s in load_steps():
        step = _classroom_step(WORK / "platforms" / "carol" / "classroom.json", s.number)
        check(step["status"] == "error" and "Not graded" in step["tests"][0]["message"],
              f"Classroom's step {s.number} from the placeholder: {str(step)[:200]}")
    if problems:
        raise Failed("; ".join(problems))
    return (f"judge aborted in step {last}, " + (f"full disk (steps {', '.join(sorted(missed))}), " if disk else "")
            + "killed: Gradescope "
            "0 of 0 a step and NOT GRADED, PrairieLearn gradable: false, Classroom error, terminal and record say why"
            + (f"; {skipped}" if skipped else ""))


def selftest_busy_machine(ctx) -> str:
    """The step's wall-clock backstop running out while the student's code is within its budget and held
    under half the time (a busy machine) leaves the rest of the cases not graded; once the code has spent
    its budget, they are its timeouts."""
    need_solutions()
    from collections import Counter
    from raykit import bundle, runcases
    from raykit.build import detect_undefined
    step = load_steps()[0]
    build = BUILD / "submission-7"
    judge = bundle.ensure(detect_undefined()).judge(step)      # the kit's side: the judge
    if not (build / f"answers_step{step.number}").is_file():
        if not (WORK / "class" / "alice").is_dir():
            _class(["alice"])
        _check("alice", dict(os.environ, RAYKIT_NO_WARMUP="1"))
    got = {}
    for name, cpu in (("within", 1000.0), ("spent", 0.0)):
        cases = runcases.list_cases(judge)
        ledger = WORK / f"ledger-{name}"
        ledger.unlink(missing_ok=True)
        budget = runcases.Budget(cpu, 1000.0, 24.0, ledger)
        env = dict(RAYKIT_SEED="1", RAYKIT_ANSWERS=str(build / f"answers_step{step.number}"), **budget.env())
        runcases.run_cases(judge, cases, env, 30, 0.0, budget=budget)    # no time at all
        got[name] = Counter(c.status for c in cases)
    expect(got["within"]["grader_error"] > 0 and not got["within"]["not_run"],
           f"the step's time ran out, the code within its budget: {dict(got['within'])}, no case not graded")
    # Its budget spent, the cases left are the student's timeouts (runcases.STEP_TIME_OUT), not run again.
    expect(not got["spent"]["grader_error"] and not got["spent"]["not_run"] and got["spent"]["timed_out"],
           f"the code's budget spent: {dict(got['spent'])}, a case not graded or left without a verdict")
    return (f"a step given no time: {got['within']['grader_error']} of {sum(got['within'].values())} cases not graded "
            f"with the budget unspent; with it spent, none ({dict(got['spent'])})")


@pytest.mark.quick
def selftest_killed_run_leaves_no_folder(ctx) -> str:
    """A run killed by SIGKILL cannot remove its scratch folder (a judge's output, a compile's work,
    build/runs/): the next run of the same kind does (raykit/heldtmp.py), and only that: a live run's
    folder, a recent folder with no lock, a link and another prefix's folder stay."""
    import signal
    import tempfile
    import time
    from raykit import heldtmp
    with tempfile.TemporaryDirectory(prefix="raykit-selftest-held-") as tmp:
        parent = Path(tmp)
        hold = ("import sys, time\nfrom pathlib import Path\nfrom raykit import heldtmp\n"
                "with heldtmp.held('raykit-judge-', Path(sys.argv[1])) as f:\n"
                "    print(f, flush=True)\n    time.sleep(120)\n")
        env = dict(os.environ, PYTHONPATH=str(ROOT / "tools"))
        runs = [subprocess.Popen([sys.executable, "-c", hold, tmp], stdout=subprocess.PIPE, text=True, env=env)
                for _ in range(2)]
        try:
            killed, live = (Path(r.stdout.readline().strip()) for r in runs)
            runs[0].send_signal(signal.SIGKILL)
            runs[0].wait()
            expect(killed.is_dir(), f"the killed run's folder {killed.name} was not there to sweep")
            # A lock file just made, not locked yet (a run between creating and locking it): kept.
            racing = parent / "raykit-judge-racing"
            racing.mkdir()
            (racing / heldtmp.HELD).touch()
            aged = time.time() - heldtmp.LOCKING_AGE - 5
            os.utime(killed / heldtmp.HELD, (aged, aged))
            unlocked = parent / "raykit-judge-unlocked"
            unlocked.mkdir()
            other = parent / "raykit-build-other"
            other.mkdir()
            (parent / "raykit-judge-link").symlink_to(other)
            with heldtmp.held("raykit-judge-", parent) as mine:
                expect(mine.is_dir() and mine.name.startswith(f"raykit-judge-{os.getpid()}-"),
                       f"the new folder is {mine}")
            expect(not killed.exists(), f"the killed run's folder {killed.name} was left")
            expect(not mine.exists(), "the run's own folder was not removed when it ended")
            for kept in (live, racing, unlocked, other, parent / "raykit-judge-link"):
                expect(os.path.lexists(kept), f"{kept.name} was removed, though it is not a dead run's")
            old = time.time() - heldtmp.UNLOCKED_AGE - 60
            os.utime(unlocked, (old, old))
            heldtmp.sweep(parent, "raykit-judge-")
            expect(not unlocked.exists(), "a folder with no lock, older than an hour, was left")
        finally:
            for r in runs:
                r.kill()
                r.wait()
    return ("a killed run's folder is removed by the next run; a live run's, one whose lock is being taken, a new "
            "one without a lock, a link and another kind's stay")

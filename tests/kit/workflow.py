"""Self-test of the course workflow: batch grading and Gradescope JSON."""

from __future__ import annotations

import csv
import json
import shutil
import zipfile

from raykit.mutants import MUTANTS, write_answer
from raykit.common import BUILD, ROOT, load_steps, student_file_name
from raykit.record import is_record
from raykit.status import DONE
from . import scale
from .support import expect, kit, need_solutions
from .fixtures import fixture_dir

# Gradescope's documented results.json fields (gradescope-autograders.readthedocs.io, "Autograder
# Specifications"): anything else is a mistake on our side.
TOP_FIELDS = {"score": (int, float), "execution_time": (int, float), "output": str, "output_format": str,
              "test_output_format": str, "test_name_format": str, "visibility": str,
              "stdout_visibility": str, "extra_data": dict, "tests": list, "leaderboard": list}
TEST_FIELDS = {"score": (int, float), "max_score": (int, float), "status": str, "name": str,
               "name_format": str, "number": str, "output": str, "output_format": str, "tags": list,
               "visibility": str, "extra_data": dict}
VISIBILITY = {"hidden", "after_due_date", "after_published", "visible"}


def validate_gradescope(data: dict) -> list[str]:
    problems = []
    for key, value in data.items():
        if key not in TOP_FIELDS:
            problems.append(f"unknown top-level field {key!r}")
        elif not isinstance(value, TOP_FIELDS[key]):
            problems.append(f"{key} has type {type(value).__name__}")
    if "score" not in data and not all("score" in t for t in data.get("tests", [])):
        problems.append("no score at the top nor on every test")
    for key in ("visibility", "stdout_visibility"):
        if key in data and data[key] not in VISIBILITY:
            problems.append(f"{key} = {data[key]!r}")
    for t in data.get("tests", []):
        for key, value in t.items():
            if key not in TEST_FIELDS:
                problems.append(f"test field {key!r} is not documented")
            elif not isinstance(value, TEST_FIELDS[key]):
                problems.append(f"test {t.get('name')!r}: {key} has type {type(value).__name__}")
        if t.get("status") not in (None, "passed", "failed"):
            problems.append(f"test {t.get('name')!r}: status {t['status']!r}")
        if t.get("visibility", "visible") not in VISIBILITY:
            problems.append(f"test {t.get('name')!r}: visibility {t['visibility']!r}")
    return problems


def selftest_batch_grading(ctx) -> str:
    need_solutions()
    step = load_steps()[0]
    root = BUILD / "grade-test"
    shutil.rmtree(root, ignore_errors=True)
    wrong = write_answer(step, MUTANTS / step.folder / "open_window.patch", BUILD / "grade-test-mutant" / step.folder)
    sources = {"alice": ROOT / "solutions", "bob": wrong.parent,
               "carol": fixture_dir("crash"), "dave": fixture_dir("hang")}
    for student, src in sources.items():
        dst = root / student / step.folder
        dst.mkdir(parents=True)
        for f in step.files:
            shutil.copyfile((src / step.folder / f) if (src / step.folder).is_dir() else src / f, dst / f)
    (root / "erin").mkdir()  # submitted nothing usable
    # frank zips his whole kit; gina exports the repository: the steps at some depth.
    nested = root / "gina" / "raykit-main" / "steps" / step.folder
    nested.mkdir(parents=True)
    for f in step.files:
        shutil.copyfile(ROOT / "solutions" / step.folder / f, nested / f)
    with zipfile.ZipFile(root / "frank.zip", "w") as z:
        for f in step.files:
            z.write(ROOT / "solutions" / step.folder / f, f"raykit/steps/{step.folder}/{f}")
    out, jsons = BUILD / "grade-test.csv", BUILD / "grade-test-json"
    shutil.rmtree(jsons, ignore_errors=True)
    r = kit("grade", str(root), "--out", str(out), "--json-dir", str(jsons), "-j", "2", timeout=900)
    expect(r.returncode == 0, f"./kit grade exited {r.returncode}: {r.stderr[-800:]}")
    rows = {row["student"]: row for row in csv.DictReader(out.open())}
    n = step.number
    expect(set(rows) == {"alice", "bob", "carol", "dave", "erin", "frank", "gina"}, f"CSV rows: {sorted(rows)}")
    a, b, c, d, e, f_, g = (rows[k] for k in ("alice", "bob", "carol", "dave", "erin", "frank", "gina"))
    # Full marks and the counted points on the course as set, from each one's record (scale.py): with a
    # group as extra credit, alice earns her step's maximum and the extra credit on top, and bob's slip
    # loses counted points whatever his ★ cases earn.
    mine = {who: json.loads((jsons / f"{student_file_name(who)}.json").read_text()) for who in ("alice", "bob")}
    [a_step], [b_step] = ([s for s in mine[w]["steps"] if s["step"] == n] for w in ("alice", "bob"))
    short = scale.short_of_full(a_step)
    expect(a[f"step{n}_state"] == DONE and not short
           and a[f"step{n}_earned"] == scale.shown(scale.maximum(a_step) + scale.bonus(a_step["cases"])),
           f"alice: {short or 'the CSV says ' + a[f'step{n}_earned'] + ' of ' + a[f'step{n}_maximum']}: {a}")
    expect(b[f"step{n}_state"] == "some cases fail" and scale.base(b_step) < scale.maximum(b_step)
           and scale.exact(b[f"step{n}_earned"]) == scale.rounded(scale.earned(b_step)),
           f"bob (open window): {scale.shown(scale.base(b_step))} counted of {b[f'step{n}_maximum']}: {b}")
    expect("crashed" in c["note"] and c[f"step{n}_state"] == "some cases fail", f"carol (crash): {c}")
    expect("timed_out" in d["note"] and d[f"step{n}_state"] == "some cases fail", f"dave (hang): {d}")
    expect(e["status"] == "nothing submitted" and "No step files found" in e["note"], f"erin (empty): {e}")
    for row in (f_, g):
        expect(row[f"step{n}_state"] == DONE, f"{row['student']} (zipped or nested solutions): {row}")
    graded = [a, b, c, d, f_, g]
    expect(len({row["maximum"] for row in graded}) == 1, "the maximum differs between students: one scale broken")
    expect(float(a["earned"]) > float(b["earned"]) > 0, "scores do not order alice > bob > 0")
    # --json-dir keeps the kit's own record of each student (raykit/record.py); Gradescope's format is
    # what ./kit check --json writes, for the same grading.
    records = sorted(p for p in jsons.glob("*.json") if not p.name.startswith("."))   # .judged-by.json aside
    expect(len(records) == 6, "a record per graded student is missing")
    not_records = [j.name for j in records if not is_record(json.loads(j.read_text()))]
    expect(not not_records, f"--json-dir holds files that are not the kit's records: {not_records}")
    gradescope_file = BUILD / "grade-test-gradescope.json"
    kit("check", str(int(n)), "--steps", str(root / "bob"), "--quiet", "--json", str(gradescope_file), timeout=900)
    expect(gradescope_file.is_file(), "./kit check --json wrote no results.json")
    problems = validate_gradescope(json.loads(gradescope_file.read_text()))
    expect(not problems, "results.json does not follow Gradescope's fields: " + "; ".join(problems[:5]))
    shutil.rmtree(root, ignore_errors=True)
    return ("correct, wrong, crashing, looping, empty, zipped and nested submissions graded two at a time: "
            "right CSV rows on one scale; a record each; Gradescope's results.json valid")

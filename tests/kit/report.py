"""Self-test of ./kit report: a synthetic class, graded by ./kit grade -j 2 --report, read back.

The class (steps 01 and 02 only: they build in seconds; the others are missing, which costs no
build): 10 copies of the solutions, 20 submissions with one mutant's slip each, 5 with two slips in
different steps, 3 stubs or partial (one does not compile), and a pair of near-copies: the textbook
fixture and a disguised copy of it (identifiers renamed, functions reordered, comments changed).

It checks: the mutants' signatures (tests/mutants/signatures.json) are not stale; every one-slip
student is matched exactly to their slip or to one with the same signature, every two-slip student
to both; the near-copies are the first pair and the solution copies are grouped, not paired; the
CSV, the index and the student pages agree on every score; a student's page names no other student;
the index and a student page open in headless Chromium with no console error, no broken image and
no network request (screenshots in build/report-test/).

The similarity section alone (a few seconds, no grading): eleven students, nine handing in one
file (an older text of the reference, from git, else today's with code of its own), two pairs of
real copies of a step file; the real pairs first, the shared file once as a group (#35 item 2).
"""

from __future__ import annotations

import csv
import json
import os
import re
import shutil
import subprocess
import time
from pathlib import Path

import pytest

from raykit.common import BUILD, ROOT, load_steps
from . import scale
from .support import Failed, Skipped, chromium_or_skip, expect, kit, need_solutions
from .fixtures import fixture_dir

WORK = BUILD / "report-test"
STEPS = ("01", "02")


def _signatures():
    from kitlib.report import signatures
    sigs, notes = signatures.load()
    return sigs, notes


@pytest.mark.quick
@pytest.mark.step
def selftest_signatures_fresh(ctx) -> str:
    need_solutions()
    from raykit.mutants import patches
    from kitlib.report import signatures
    sigs, notes = _signatures()
    expect(not notes, "tests/mutants/signatures.json: " + "; ".join(notes))
    total = sum(len(patches(s)) for s in load_steps())
    empty = [s.key for s in sigs if not s.fails]
    expect(not empty, f"mutants whose signature fails no basic case (not caught): {empty[:5]}")
    # The staleness check can fail: a changed patch changes its fingerprint.
    step = load_steps()[0]
    patch = patches(step)[0]
    copy = WORK / "changed.patch"
    copy.parent.mkdir(parents=True, exist_ok=True)
    copy.write_bytes(patch.read_bytes() + b"\n")
    expect(signatures.fingerprint(step, copy) != signatures.fingerprint(step, patch),
           "a changed patch keeps its fingerprint: a stale signature would go unnoticed")
    # Matching: exact, near (one case more), and nothing for a set far from every signature.
    s0 = sigs[0]
    others = [x for x in sigs if x.step == s0.step]
    m = signatures.match(s0.fails, others)
    expect(m.kind == "exact" and s0 in m.signatures, f"{s0.key}'s own signature does not match it exactly")
    names = {c for x in others for c in x.fails}
    extra = sorted(names - s0.fails)
    if extra and len(s0.fails) >= 3:
        near = signatures.match(s0.fails | {extra[0]}, others)
        expect(near.kind in ("near", "exact") and near.distance <= 1, f"one case more than {s0.key}: {near.kind}")
    far = signatures.match(frozenset({"no such case 1", "no such case 2"}), others)
    expect(far.kind == "none", f"two unknown cases matched {far.kind}")
    return f"{len(sigs)} of {total} mutants have a current signature; exact, near and no match found"


def _disguise(text: str) -> str:
    """The same code in another dress: comments rewritten, locals renamed, functions in reverse order."""
    text = re.sub(r"//[^\n]*", "// worked this out myself", text)
    for name in sorted(set(re.findall(r"\b(?:const )?(?:float|double|int|Roots|glm::vec3) (\w+) =", text))):
        text = re.sub(rf"(?<![.\w]){name}\b", f"my_{name}", text)
    blocks = list(re.finditer(r"^[A-Za-z][^\n]*\)\s*\{\n.*?^\}\n", text, re.S | re.M))
    if len(blocks) > 1:
        pieces = [text[:blocks[0].start()]]
        for i, b in enumerate(reversed(blocks)):
            pieces.append(b.group(0))
            nxt = blocks[i + 1].start() if i + 1 < len(blocks) else None
            pieces.append(text[blocks[i].end():nxt] if nxt is not None else text[blocks[-1].end():])
        text = "".join(pieces)
    return text


def _make_class(root: Path) -> dict:
    from raykit.mutants import write_answer
    steps = {s.number: s for s in load_steps()}
    s1, s2 = steps["01"], steps["02"]
    sigs, _ = _signatures()
    by_step = {n: [s for s in sigs if s.step == n and s.fails] for n in STEPS}
    if not all(by_step.values()):
        raise Failed("steps 01 and 02 need mutants with recorded signatures (./kit report --signatures)")
    shutil.rmtree(root, ignore_errors=True)
    plan = {"copies": [], "one": {}, "two": {}, "odd": [], "pair": ()}

    def put(name: str, step, source: Path | None = None, mutant=None, text: dict | None = None) -> None:
        target = root / name / step.folder
        if mutant is not None:
            write_answer(step, ROOT / "tests" / "mutants" / step.folder / f"{mutant.name}.patch", target)
            return
        target.mkdir(parents=True, exist_ok=True)
        for f in step.files:
            if text is not None:
                (target / f).write_text(text[f])
            else:
                shutil.copyfile(source / f, target / f)

    sol = lambda s: ROOT / "solutions" / s.folder
    stub = lambda s: ROOT / "steps" / s.folder
    n = 0

    def name(kind: str) -> str:
        nonlocal n
        n += 1
        return f"st{n:02d}-{kind}"

    for _ in range(10):
        who = name("copy")
        put(who, s1, sol(s1)), put(who, s2, sol(s2))
        plan["copies"].append(who)
    for i in range(20):
        who = name("slip")
        number = STEPS[i % 2]
        mutant = by_step[number][(i // 2) % len(by_step[number])]
        other = s2 if number == "01" else s1
        put(who, steps[number], mutant=mutant)
        put(who, other, sol(other))
        plan["one"][who] = [mutant]
    for i in range(5):
        who = name("twoslips")
        m1 = by_step["01"][-1 - i % len(by_step["01"])]
        m2 = by_step["02"][-1 - i % len(by_step["02"])]
        put(who, s1, mutant=m1), put(who, s2, mutant=m2)
        plan["two"][who] = [m1, m2]
    who = name("stubs")
    put(who, s1, stub(s1)), put(who, s2, stub(s2))
    plan["odd"].append(who)
    who = name("partial")
    put(who, s1, sol(s1)), put(who, s2, stub(s2))
    plan["odd"].append(who)
    who = name("nocompile")
    put(who, s1, fixture_dir("no_compile") / s1.folder), put(who, s2, sol(s2))
    plan["odd"].append(who)
    textbook = fixture_dir("textbook")
    own, disguised = name("own"), name("other")
    for s in (s1, s2):
        put(own, s, textbook / s.folder)
        put(disguised, s, text={f: _disguise((textbook / s.folder / f).read_text()) for f in s.files})
    plan["pair"] = (own, disguised)
    return plan


def _slip_problems(plan: dict, matches: dict) -> list[str]:
    """The slip students not matched exactly to their slip, or to one with the same signature."""
    problems = []
    for who, wanted in list(plan["one"].items()) + list(plan["two"].items()):
        for mutant in wanted:
            got = matches.get((who, mutant.step))
            if got is None:
                problems.append(f"{who}: step {mutant.step} ({mutant.key}) has no failing basic case in the grading")
                continue
            fails, m = got
            if not (m.kind == "exact" and any(s.fails == mutant.fails for s in m.signatures)):
                problems.append(f"{who} ({mutant.key}): matched {m.kind} {[s.key for s in m.signatures][:3]}, "
                                f"distance {m.distance}")
    return problems


def _scores_in(index: str) -> dict:
    return {m.group(1): m.group(2) for m in re.finditer(r'data-score="([^"]+)">([^<]*)<', index)}


def selftest_class_report(ctx) -> str:
    need_solutions()
    from kitlib.report import signatures
    plan = _make_class(WORK / "class")
    out = WORK / "report"
    shutil.rmtree(out, ignore_errors=True)
    csv_path = WORK / "grades.csv"
    start = time.monotonic()
    r = kit("grade", str(WORK / "class"), "-j", "2", "--out", str(csv_path), "--report", str(out), timeout=1800)
    elapsed = time.monotonic() - start
    expect(r.returncode == 0 and (out / "index.html").is_file(),
           f"./kit grade --report: exit status {r.returncode}: {(r.stderr.strip().splitlines() or ['?'])[-1]}")
    report_line = next((l for l in r.stdout.splitlines() + r.stderr.splitlines() if "student pages in" in l), "")

    # The slips, read back from the saved grading the way the page is made.
    from kitlib.report.grading import load
    from kitlib.report.pages import analyse
    sigs, _ = signatures.load()
    g = load(out / "grading")
    problems = _slip_problems(plan, analyse(g, sigs))
    expect(not problems, "slips not recognised:\n  " + "\n  ".join(problems))

    # The check can fail: with one slip's recorded signature one case short, its student is not matched to it.
    victim, [mutant] = next((w, m) for w, m in plan["one"].items()
                            if sum(x.step == m[0].step and x.fails == m[0].fails for x in sigs) == 1)
    wrong = [signatures.Signature(x.key, x.step, x.name, x.slip, x.lecture, frozenset(sorted(x.fails)[1:]))
             if x.key == mutant.key else x for x in sigs]
    missed = _slip_problems({"one": {victim: [mutant]}, "two": {}}, analyse(g, wrong))
    expect(missed, f"{victim} still matched {mutant.key} exactly when its signature lacks a case")

    index = (out / "index.html").read_text(encoding="utf-8")
    expect("not a verdict" in index, "the index does not say the slips are not a verdict")
    expect("reason to look, not a" in index, "the index does not say similarity is not a proof")
    pairs = re.findall(r'data-pair="([^"|]+)\|([^"]+)"', index)
    expect(pairs, "no similar pair listed: " + (re.search(r'id="similar".{0,600}', index, re.S) or [""])[0][:600])
    expect(set(pairs[0]) == set(plan["pair"]), f"the first pair is {pairs[0]}, not the near-copies {plan['pair']}")
    copies = set(plan["copies"])
    flagged = [p for p in pairs if set(p) <= copies]
    expect(not flagged, f"copies of the solutions flagged as a pair: {flagged[:3]}")
    m = re.search(r"<b>Copies of the solutions</b>[^:]*: (\d+)", index)
    expect(m and int(m.group(1)) >= len(copies), f"the solution copies are not grouped: {m and m.group(0)}")

    # The scores: the CSV, the index and each student's page agree.
    with csv_path.open(newline="") as f:
        rows = {row["student"]: row for row in csv.DictReader(f)}
    shown = _scores_in(index)
    students = sorted(rows)
    expect(len(students) == 40, f"the CSV has {len(students)} students, not 40")
    for who in students:
        row = rows[who]
        expect(shown.get(who) == f"{row['earned']} / {row['maximum']}",
               f"{who}: the CSV says {row['earned']} / {row['maximum']}, the index {shown.get(who)}")
        st = next(s for s in g.students if s.name == who)
        text = (out / "students" / f"{st.page}.html").read_text(encoding="utf-8")
        m = re.search(r'data-earned="([^"]*)" data-maximum="([^"]*)"', text)
        expect(m and (m.group(1), m.group(2)) == (row["earned"], row["maximum"]),
               f"{who}: the CSV says {row['earned']} / {row['maximum']}, the student page {m and m.groups()}")
        named = [o for o in students if o != who and o in text]
        expect(not named, f"{who}'s page names other students: {named[:3]}")
    one = next(iter(plan["two"]))
    one_page = out / "students" / f"{next(s.page for s in g.students if s.name == one)}.html"
    text = one_page.read_text(encoding="utf-8")
    expect(text.count("fits exactly") >= 2 and text.count("<li>Step") >= 2, f"{one}'s page does not name both slips")

    shots = _browser(out / "index.html", one_page)
    return (f"40 students graded and reported in {elapsed:.0f} s ({report_line.strip() or 'report time not printed'}); "
            f"{len(plan['one']) + len(plan['two'])} slip students matched, the near-copies first of "
            f"{len(pairs)} pairs; scores agree; {shots}")


# --- similar submissions: a class that shares one file --------------------------------------------

def _edited(text: str, every: int, tag: str) -> str:
    """A real copy that was worked on a little: every `every`-th statement line followed by one of its own."""
    out, n = [], 0
    for line in text.splitlines():
        out.append(line)
        if line.rstrip().endswith(";") and not line.lstrip().startswith(("return", "#", "//")):
            n += 1
            if n % every == 0:
                indent = line[:len(line) - len(line.lstrip())]
                out.append(f"{indent}volatile int {tag}_{n} = {n} * {len(out)} + {tag}_seen++;")
    return "\n".join(out) + "\n"


def _shared_text(step, f: str) -> tuple[str, str]:
    """The file most of the class shares: the oldest text of the reference in git's history when it is
    not today's (the issue's case: an older handout's answer), else today's with code of its own added."""
    import subprocess
    path = f"solutions/{step.folder}/{f}"
    today = (ROOT / path).read_text()
    log = subprocess.run(["git", "-C", str(ROOT), "log", "--format=%h", "--", path], capture_output=True, text=True)
    commits = log.stdout.split() if log.returncode == 0 else []
    if commits:
        old = subprocess.run(["git", "-C", str(ROOT), "show", f"{commits[-1]}:{path}"], capture_output=True, text=True)
        if old.returncode == 0 and old.stdout != today:
            return old.stdout, f"{path} as of {commits[-1]}"
    extra = "".join(f"static int shared_helper_{i}(int v) {{ int w = v * {i} + {i * i}; return w % {i + 7}; }}\n"
                    for i in range(1, 40))
    return today + extra, "today's reference with helpers of its own"


def selftest_similar_groups(ctx) -> str:
    """Eleven students: nine hand in one file (byte for byte, one with its comments changed, one with a
    line more), and two pairs are real copies of each other's step file, one of them inside the group.
    The two pairs must be listed first, the shared file once as a group and never as pairs."""
    need_solutions()
    import shutil as _shutil
    if _shutil.which("sim_c++") is None:
        raise Skipped("sim_c++ is not installed (sudo apt-get install similarity-tester)")
    from kitlib.report import similar
    from kitlib.report.pages import similar_section
    steps = load_steps()
    textbook = fixture_dir("textbook")
    own = [s for s in steps if len(s.files) == 1 and (textbook / s.folder / s.files[0]).is_file()]
    if len(own) < 2:
        raise Failed("tests/fixtures/textbook/ holds fewer than two steps' own answers")
    last = steps[-1]
    big = max(last.files, key=lambda f: len((ROOT / "solutions" / last.folder / f).read_text()))
    shared, origin = _shared_text(last, big)
    root = WORK / "similar"
    shutil.rmtree(root, ignore_errors=True)
    names = [f"st{i:02d}" for i in range(1, 12)]

    def put(who: str, step, f: str, text: str) -> None:
        target = root / who / step.folder / f
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text)

    group = names[:9]
    for i, who in enumerate(names):
        for s in steps:                     # everyone: today's solutions, set aside
            for f in s.files:
                put(who, s, f, (ROOT / "solutions" / s.folder / f).read_text())
        if who in group:
            text = shared
            if i == 3:
                text = "// my own header comment\n" + re.sub(r"(?m)^ {4}", "\t", shared)
            if i == 4:
                text = shared + "static const int one_line_more = 42;\n"
            put(who, last, big, text)
    real = [(names[1], names[6], own[0]), (names[9], names[10], own[1])]    # one pair inside the group
    for a, b, s in real:
        f = s.files[0]
        text = (textbook / s.folder / f).read_text()
        put(a, s, f, text)
        put(b, s, f, _edited(_disguise(text), 4, "b"))

    start = time.monotonic()
    sim = similar.compare(root, names, steps)
    elapsed = time.monotonic() - start
    expect(sim.available, sim.note)
    listed = [(p.a, p.b, p.score) for p in sim.pairs]
    wanted = [{a, b} for a, b, _ in real]
    expect(len(listed) >= 2 and [set(p[:2]) for p in listed[:2]] in (wanted, wanted[::-1]),
           f"the two real copies {[tuple(w) for w in wanted]} are not the first pairs: {listed[:6]}")
    inside = [p for p in listed if p[0] in group and p[1] in group and (p[0], p[1]) != tuple(sorted(real[0][:2]))]
    expect(not inside, f"pairs of the group's members listed: {inside[:4]} ({len(inside)})")
    key = f"{last.folder}/{big}"
    groups = [g for g in getattr(sim, "groups", []) if g.key == key]
    expect(len(groups) == 1 and groups[0].members == sorted(group),
           f"{key} shared by {group} is not one group of them: {[(g.key, g.members) for g in groups]}")
    scores = {frozenset(p[:2]): p[2] for p in listed}
    for a, b, s in real:
        score = scores[frozenset((a, b))]
        expect(similar.SHOWN <= score < 100, f"{a} and {b}: {score} %, not a copy worked on a little")
    html = similar_section(sim, {})
    expect(html.count(f'data-group="{key}"') == 1, f"{key} is not shown once as a group")
    rows = re.findall(r'data-pair="([^"|]+)\|([^"]+)"', html)
    expect([set(r) for r in rows[:2]] in (wanted, wanted[::-1]), f"the page's first pairs are {rows[:2]}")
    expect(all(n in html for n in group), "the group's members are not all named")
    old_like = ""
    if "as of" in origin:
        expect(groups[0].share >= similar.REFERENCE_LIKE and "as of" in groups[0].source,
               f"the group's file, {origin}, is not recognised as a version of the reference: "
               f"{groups[0].share} % of {groups[0].source or 'none'}")
        old_like = f", recognised as {groups[0].share} % of {groups[0].source}"
    shutil.rmtree(root, ignore_errors=True)
    return (f"11 students, {key} shared by 9 ({origin}{old_like}): one group; the real copies first "
            f"({', '.join(f'{a}/{b} {s} %' for a, b, s in listed[:2])}), {len(listed)} pairs in all; "
            f"compared in {elapsed:.1f} s")


def _browser(*pages_: Path) -> str:
    browser, chromium = chromium_or_skip()

    class Watching(browser.Browser):
        def __enter__(self):
            super().__enter__()
            self.logged: list[str] = []
            self.call("Runtime.enable", session=True)
            self.call("Log.enable", session=True)
            return self

        def _dispatch(self, message: dict) -> None:
            method, params = message.get("method"), message.get("params", {})
            if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
                self.logged.append("console: " + " ".join(str(a.get("value", a.get("description", "")))
                                                          for a in params.get("args", [])))
            elif method == "Runtime.exceptionThrown":
                self.logged.append("exception: " + str(params.get("exceptionDetails", {}).get("text")))
            elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
                self.logged.append("log: " + str(params["entry"].get("text")))
            super()._dispatch(message)

    problems, shots = [], []
    try:
        with Watching(chromium) as b:
            for p in pages_:
                b.logged.clear()
                b.open(p.resolve().as_uri())
                broken = b.evaluate("Array.from(document.images).filter(i => !i.complete || !i.naturalWidth).length")
                offline = [u for u in b.requests if not u.startswith(("file:", "data:", "about:"))]
                if b.logged:
                    problems.append(f"{p.name}: {b.logged[:3]}")
                if offline:
                    problems.append(f"{p.name}: asks the network for {offline[:3]}")
                if broken:
                    problems.append(f"{p.name}: {broken} image(s) do not load")
                shot = WORK / f"{p.stem}.png"
                b.screenshot(shot)
                shots.append(shot)
    except browser.BrowserError as e:
        raise Failed(f"headless Chromium: {e}") from None
    expect(not problems, "\n  ".join(problems))
    return "opened in Chromium offline, no console error; screenshots " + ", ".join(
        str(s.relative_to(ROOT)) if s.is_relative_to(ROOT) else str(s) for s in shots)


@pytest.mark.quick
def selftest_crash_kind(ctx) -> str:
    """The report's incidents are grouped by the record's data (a case's "incident": the function
    called, the signal), never by words of its message: a message that names another function and
    another signal, in a student's output or a translation, does not move a crash to another group."""
    from kitlib.report.pages import crash_kind
    from raykit.status import CRASHED, STATUS_WORDS, TIMED_OUT
    misleading = ["Your code crashed in fake_function(1, 2): it was killed by SIGBUS, a bad memory access."]
    found = [crash_kind({"status": CRASHED, "messages": misleading,
                         "incident": {"function": "intersect_unit_sphere", "signal": "SIGSEGV"}})[0],
             crash_kind({"status": TIMED_OUT, "messages": misleading,
                         "incident": {"function": "render", "signal": ""}})[0],
             crash_kind({"status": CRASHED, "messages": misleading})[0]]
    want = [f"{STATUS_WORDS[CRASHED]} SIGSEGV in intersect_unit_sphere()", f"{STATUS_WORDS[TIMED_OUT]} in render()",
            STATUS_WORDS[CRASHED]]
    expect(found == want, f"crash kinds {found}, expected {want}")
    return "grouped by the record's function and signal: " + "; ".join(found)


# --- one class, several machines ------------------------------------------------------------------

def _merge_class(root: Path) -> dict[str, list[str]]:
    """Four students on steps 01 and 02 (they build in seconds), split between two machines: a and b."""
    from raykit.mutants import patches, write_answer
    steps = [s for s in load_steps() if s.number in STEPS]
    shutil.rmtree(root, ignore_errors=True)
    plan = {"a": ["full", "slip"], "b": ["partial", "stubs"]}
    for machine, students in plan.items():
        for who in students:
            for n, s in enumerate(steps):
                target = root / machine / who / s.folder
                if who == "slip" and n == 0 and patches(s):
                    write_answer(s, patches(s)[0], target)
                elif who == "stubs" or (who == "partial" and n > 0):
                    shutil.copytree(ROOT / "steps" / s.folder, target)
                else:
                    shutil.copytree(ROOT / "solutions" / s.folder, target)
    return plan


def _grades(path: Path) -> list[dict]:
    """A CSV's rows as grades: without the columns that say where a grading ran."""
    with path.open(newline="") as f:
        return [{k: v for k, v in row.items() if k not in ("isolation", "note")} for row in csv.DictReader(f)]


def selftest_merge(ctx) -> str:
    need_solutions()
    from raykit.secret import SECRET_ENV
    work = WORK / "merge"
    shutil.rmtree(work, ignore_errors=True)     # an earlier run's gradings and copies
    plan = _merge_class(work / "class")
    (work / "class" / "all").mkdir()
    for machine in plan:
        for who in plan[machine]:
            shutil.copytree(work / "class" / machine / who, work / "class" / "all" / who)
    start = time.monotonic()
    for name in ["a", "b", "all"]:
        r = kit("grade", str(work / "class" / name), "-j", "2", "--out", str(work / f"{name}.csv"),
                "--report", str(work / name), timeout=1200)
        expect((work / name / "grading" / "grades.csv").is_file(),
               f"./kit grade {name}: exit {r.returncode}: {(r.stderr.strip().splitlines() or ['?'])[-1]}")
    graded = time.monotonic() - start
    merged = work / "merged"
    r = kit("report", str(work / "a" / "grading"), str(work / "b" / "grading"), "--out", str(merged))
    expect(r.returncode == 0, f"./kit report A B: exit {r.returncode}: {(r.stderr + r.stdout)[-600:]}")
    one, two = _grades(work / "all" / "grading" / "grades.csv"), _grades(merged / "grading" / "grades.csv")
    expect(one == two, f"merged from two machines:\n  {two}\none machine:\n  {one}")
    expect(sorted(p.name for p in (merged / "grading" / "json").iterdir()) ==
           sorted(p.name for p in (work / "all" / "grading" / "json").iterdir()), "the merged json/ differs")
    shown = _scores_in((merged / "index.html").read_text(encoding="utf-8"))
    expect(shown == {row["student"]: f"{row['earned']} / {row['maximum']}" for row in one},
           f"the merged report shows {shown}")

    # Refused, with nothing written: another secret on one machine; one student graded differently on two.
    refusals = []
    before = (merged / "grading" / "grades.csv").read_bytes()
    r = kit("grade", str(work / "class" / "b"), "-j", "2", "--out", str(work / "other.csv"), "--report",
            str(work / "other"), timeout=1200, env={SECRET_ENV: "ab" * 32})
    r = kit("report", str(work / "a" / "grading"), str(work / "other" / "grading"), "--out", str(merged))
    expect(r.returncode != 0 and "different secrets" in r.stderr and "secret.key" in r.stderr,
           f"gradings drawn with two secrets were merged: exit {r.returncode}, {r.stderr[-400:]}")
    refusals.append("two secrets")
    shutil.rmtree(work / "a2", ignore_errors=True)      # a run that stopped short leaves it behind
    shutil.copytree(work / "a" / "grading", work / "a2")
    rows = (work / "a2" / "grades.csv").read_text().splitlines(keepends=True)
    victim = next(i for i, l in enumerate(rows) if l.startswith("full,"))
    cells = rows[victim].split(",")
    cells[1] = scale.shown(scale.exact(cells[1]) - 1)     # a point less, on the course's decimals ("30.88")
    rows[victim] = ",".join(cells)
    (work / "a2" / "grades.csv").write_text("".join(rows))
    r = kit("report", str(work / "a" / "grading"), str(work / "a2"), "--out", str(merged))
    expect(r.returncode != 0 and "full" in r.stderr and "different results" in r.stderr,
           f"a student graded two ways was merged: exit {r.returncode}, {r.stderr[-400:]}")
    refusals.append("one student graded two ways")
    expect((merged / "grading" / "grades.csv").read_bytes() == before, "a refused merge changed the merged grading")
    r = kit("report", str(work / "a" / "grading"), str(work / "all" / "grading"), "--out", str(merged))
    expect(r.returncode == 0 and _grades(merged / "grading" / "grades.csv") == one,
           f"the same students graded alike on two machines were not kept once: {r.stderr[-300:]}")
    # With the class list (its own order, one student who submitted nothing): each machine grades its half
    # against the whole roster; the merge equals one machine's grading file for file.
    students = [who for machine in plan for who in plan[machine]]
    roster = work / "roster.csv"
    roster.write_text("name,login\n" + "".join(f"Student {who.title()},{who}\n" for who in reversed(students))
                      + "Nobody Here,absent\n")
    for name in ["a", "b", "all"]:
        r = kit("grade", str(work / "class" / name), "-j", "2", "--out", str(work / f"{name}-roster.csv"),
                "--roster", str(roster), "--report", str(work / f"{name}-roster"), timeout=1200)
        expect((work / f"{name}-roster" / "grading" / "grades.csv").is_file(),
               f"./kit grade {name} --roster: exit {r.returncode}: {(r.stderr.strip().splitlines() or ['?'])[-1]}")
    r = kit("report", str(work / "a-roster" / "grading"), str(work / "b-roster" / "grading"), "--out",
            str(work / "merged-roster"))
    expect(r.returncode == 0, f"./kit report A B (with a roster): exit {r.returncode}: {(r.stderr + r.stdout)[-600:]}")
    files, same = _file_for_file(work / "all-roster" / "grading", work / "merged-roster" / "grading")
    return (f"{sum(map(len, plan.values()))} students graded on two machines (2 + 2) and on one, in {graded:.0f} s: "
            f"the merge equals the one machine's grading (CSV, records, report's scores); with a roster, file for "
            f"file ({files} files, {same} byte for byte); refused: " + ", ".join(refusals) + "; alike rows kept once")


# --- two TAs, two clones of the kit, one class ----------------------------------------------------------

def _in_clone(clone: Path, env: dict, *args: str, timeout: float = 1200) -> subprocess.CompletedProcess:
    """./kit ARGS in a clone of the kit, with the clone's own environment (its cache, its id range, no
    pinned secret: its tests/hidden/secret.key, as on a TA's machine)."""
    return subprocess.run([str(clone / "kit"), *args], cwd=clone, env=env, capture_output=True, text=True,
                          timeout=timeout)


def _clone_env(cache: Path, first_uid: int | None) -> dict:
    from raykit.judgedby import ENV as JUDGED_ENV
    from raykit.sandbox.ids import FIRST_UID_ENV
    from raykit.secret import SECRET_ENV
    env = {k: v for k, v in os.environ.items()
           if k not in (SECRET_ENV, JUDGED_ENV, "RAYKIT_BUNDLE_DIR", FIRST_UID_ENV)}
    env["XDG_CACHE_HOME"] = str(cache)
    if first_uid is not None:
        env[FIRST_UID_ENV] = str(first_uid)
    return env


def _put_secret(clone: Path, hex_text: str) -> None:
    path = clone / "tests" / "hidden" / "secret.key"
    path.unlink(missing_ok=True)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "w") as f:
        f.write(hex_text + "\n")


def _without_per_run(path: Path):
    """A grading folder's file as what it says of the grades: the fields that say how a grading ran
    (report/merge.PER_RUN) left out; any other file, its bytes."""
    from kitlib.report.merge import PER_RUN
    if path.suffix == ".csv":
        with path.open(newline="") as f:
            return [{k: v for k, v in row.items() if k not in PER_RUN["csv"]} for row in csv.DictReader(f)]
    if path.suffix == ".json" and not path.name.startswith("."):
        data = json.loads(path.read_text(encoding="utf-8"))
        for k in PER_RUN["record"]:
            data.pop(k, None)
        for step in data.get("steps", []):
            for k in PER_RUN["step"]:
                step.pop(k, None)
            for case in step.get("cases", []):
                for k in PER_RUN["case"]:
                    case.pop(k, None)
        return data
    return path.read_bytes()


def _file_for_file(one: Path, merged: Path) -> tuple[int, int]:
    """Fails unless the two grading folders hold the same files, each the same but for the per-run
    fields; (files, files equal byte for byte)."""
    def listing(root: Path) -> list[str]:
        return sorted(p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file())
    a, b = listing(one), listing(merged)
    expect(a == b, f"the merged grading's files differ from one machine's: only merged "
                   f"{sorted(set(b) - set(a))[:5]}, only one machine's {sorted(set(a) - set(b))[:5]}")
    same = 0
    for rel in a:
        if (one / rel).read_bytes() == (merged / rel).read_bytes():
            same += 1
            continue
        x, y = _without_per_run(one / rel), _without_per_run(merged / rel)
        if x != y:
            where = ""
            if isinstance(x, list) and isinstance(y, list):
                where = next((f"row {i + 2}: {r} / {t}" for i, (r, t) in enumerate(zip(x, y)) if r != t),
                             f"{len(x)} rows / {len(y)}")
            raise Failed(f"{rel} differs between one machine's grading and the merge beyond the per-run fields "
                         f"{where[:600]}")
    return len(a), same


def _changed_scene(clone: Path) -> str:
    """Changes a colour of the clone's scene file (a TA's clone with an edit never refreshed): its path."""
    scene = sorted((clone / "include" / "raykit" / "scenes").glob("*.inc"))
    expect(bool(scene), f"no scene file in {clone}/include/raykit/scenes/")
    text = scene[0].read_text()
    m = re.search(r"(?m)^RAYKIT_SCENE_COLOR\((\w+),\s*([0-9.]+)f", text)
    if m:
        value = float(m.group(2)) + (0.07 if float(m.group(2)) <= 0.9 else -0.07)
        text = text[:m.start(2)] + f"{value:.2f}" + text[m.end(2):]
    else:
        text += "\n#define RAYKIT_TA_EDIT 1\n"
    scene[0].write_text(text)
    return scene[0].relative_to(clone).as_posix()


def _seal_hunt(work: Path, secret_hex: str, who: str, folder: str) -> str:
    """hostile/seal_key's record in a grading: it ran (said how many processes it looked at) and printed
    neither the grading's secret, nor the key derived from it that seals the records, nor the self-test's
    secret variable."""
    from raykit.secret import SECRET_ENV, _mac_key
    banned = {"the secret": secret_hex[:32], "the sealing key": _mac_key(bytes.fromhex(secret_hex)).hex()[:32],
              "the self-test's secret variable": SECRET_ENV}
    record = json.loads((work / folder / "grading" / "json" / "seal_key.json").read_text())
    text = json.dumps(record)
    looked = re.findall(r"seal: looked at (\d+) processes", text)
    expect(bool(looked), f"{who}: hostile/seal_key never reported its hunt: {text[:300]}")
    found = [name for name, value in banned.items() if value in text]
    expect(not found, f"{who}: graded code read {', '.join(found)}: "
                      + "; ".join(re.findall(r"seal: [^\\\"]{0,160}", text))[:600])
    return f"{who} {looked[0]} processes"


def selftest_merge_clones(ctx) -> str:
    """Two TAs grade halves of a class on two clones of the kit (each its own cache, sandbox id range and
    copy of the secret), one under each isolation there is; the merge equals one machine's grading of the
    whole class file for file, but for the fields report/merge.PER_RUN names. A TA without the secret is
    refused a new one where the folder graded into names another, warned elsewhere; a clone with a changed
    scene file, a record whose score was edited and a forged list of inputs are refused, by name."""
    need_solutions()
    from raykit.sandbox.ids import FIRST_UID, UID_RANGE
    from raykit.secret import SECRET_ENV
    from .integrity import isolations
    from .newstep import scratch_kit
    modes, skipped = isolations()
    expect(bool(modes), "no isolation to grade under here: " + "; ".join(skipped))
    work = WORK / "clones"
    shutil.rmtree(work, ignore_errors=True)
    start = time.monotonic()
    plan = _merge_class(work / "class")
    # A submission that hunts for the secret that seals the records (hostile/seal_key), with B's half in
    # the two gradings of B not compared with another (what it prints, the processes it sees, is the
    # machine's at that moment): one under each isolation.
    (work / "class" / "all").mkdir()
    for machine in plan:
        for who in plan[machine]:
            shutil.copytree(work / "class" / machine / who, work / "class" / "all" / who)
    shutil.copytree(work / "class" / "b", work / "class" / "b-hunt")
    shutil.copytree(fixture_dir("hostile") / "seal_key", work / "class" / "b-hunt" / "seal_key")
    kit_a, kit_b = scratch_kit(work / "kit-a"), scratch_kit(work / "kit-b")
    env_a = _clone_env(work / "cache-a", None)
    env_b = _clone_env(work / "cache-b", FIRST_UID + 2 * UID_RANGE)
    secret = os.environ[SECRET_ENV]
    _put_secret(kit_a, secret)
    iso_a, iso_b = modes[0], modes[-1]

    def grade(kit_dir: Path, env: dict, half: str, out: str, isolation: str, *more: str) -> subprocess.CompletedProcess:
        r = _in_clone(kit_dir, env, "grade", str(work / "class" / half), "-j", "2", "--out", str(work / f"{out}.csv"),
                      "--report", str(work / out), "--isolation", isolation, *more)
        return r

    def merged_by_a(*folders: str, out: str = "merged") -> subprocess.CompletedProcess:
        return _in_clone(kit_a, env_a, "report", *[str(work / f / "grading") for f in folders], "--out", str(work / out))

    r = grade(kit_a, env_a, "a", "A", iso_a)
    expect((work / "A" / "grading" / "grades.csv").is_file(), f"TA A's grading: exit {r.returncode}: {r.stderr[-600:]}")
    fp = re.search(r"(?m)^secret: fingerprint ([0-9a-f]+)", r.stdout)
    expect(bool(fp) and "warning" not in r.stderr, f"TA A's grading did not say its secret in one line, or warned: "
                                                   f"{r.stdout[:300]} {r.stderr[-300:]}")
    fp = fp.group(1)

    # TA B forgot to copy the secret. Into a folder that holds A's grading: refused, nothing made.
    shutil.copytree(work / "A", work / "B-over-A")
    before = (work / "B-over-A" / "grading" / "grades.csv").read_bytes()
    r = grade(kit_b, env_b, "b", "B-over-A", iso_b)
    expect(r.returncode != 0 and "secret.key" in r.stderr and "--new-secret" in r.stderr and fp in r.stderr,
           f"a TA without the secret, grading into a folder of secret {fp}, was not refused: exit {r.returncode}: "
           f"{r.stderr[-400:]}")
    expect(not (kit_b / "tests" / "hidden" / "secret.key").exists(), "the refused grading made a secret all the same")
    expect((work / "B-over-A" / "grading" / "grades.csv").read_bytes() == before, "the refused grading wrote its CSV")
    # Into a folder of its own: a new secret, with a warning naming it; the merge refuses the two.
    r = grade(kit_b, env_b, "b-hunt", "B-new", iso_a)
    made = re.search(r"(?m)^secret: fingerprint ([0-9a-f]+) .*made now", r.stdout)
    expect(bool(made) and made.group(1) != fp and "warning" in r.stderr and made.group(1) in r.stderr,
           f"a TA without the secret was not warned of the one made: exit {r.returncode}: {r.stdout[:300]} "
           f"{r.stderr[-400:]}")
    r = merged_by_a("A", "B-new")
    expect(r.returncode != 0 and "different secrets" in r.stderr and not (work / "merged").exists(),
           f"gradings of two secrets were merged: exit {r.returncode}: {r.stderr[-400:]}")
    hunted = [_seal_hunt(work, (kit_b / "tests" / "hidden" / "secret.key").read_text().strip(), f"B ({iso_a})", "B-new")]
    refusals = ["a new secret where the folder named another (made with --new-secret, which refuses one in place)",
                "two secrets"]
    # Asked for (--new-secret), over the folder that names another: made, with the warning (a class of one
    # upload with no steps: nothing to build). Refused while a secret exists.
    (kit_b / "tests" / "hidden" / "secret.key").unlink()
    (work / "class" / "nosteps" / "eve").mkdir(parents=True)
    (work / "class" / "nosteps" / "eve" / "README.txt").write_text("no steps here\n")
    r = grade(kit_b, env_b, "nosteps", "B-over-A", iso_b, "--new-secret")
    asked = re.search(r"(?m)^secret: fingerprint ([0-9a-f]+) .*made now", r.stdout)
    expect(bool(asked) and asked.group(1) != fp and "warning" in r.stderr,
           f"--new-secret over a folder naming {fp} made no secret: exit {r.returncode}: {r.stdout[:300]} {r.stderr[-300:]}")
    r = grade(kit_b, env_b, "nosteps", "B-over-A", iso_b, "--new-secret")
    expect(r.returncode != 0 and "exists already" in r.stderr,
           f"--new-secret with a secret in place was not refused: exit {r.returncode}: {r.stderr[-300:]}")

    # B copies A's secret and grades its half again; A grades the whole class alone, for comparison.
    (kit_b / "tests" / "hidden" / "secret.key").unlink()
    _put_secret(kit_b, secret)
    r = grade(kit_b, env_b, "b", "B", iso_b)
    expect(f"secret: fingerprint {fp} " in r.stdout and "warning" not in r.stderr and
           (work / "B" / "grading" / "grades.csv").is_file(), f"TA B with A's secret: exit {r.returncode}: "
                                                               f"{r.stdout[:300]} {r.stderr[-400:]}")
    r = grade(kit_a, env_a, "all", "ALL", iso_a)
    expect((work / "ALL" / "grading" / "grades.csv").is_file(), f"one machine's grading: exit {r.returncode}: {r.stderr[-600:]}")
    graded = time.monotonic() - start
    r = merged_by_a("A", "B")
    expect(r.returncode == 0, f"./kit report A B: exit {r.returncode}: {(r.stderr + r.stdout)[-600:]}")
    files, same = _file_for_file(work / "ALL" / "grading", work / "merged" / "grading")
    one = _grades(work / "ALL" / "grading" / "grades.csv")
    shown = _scores_in((work / "merged" / "index.html").read_text(encoding="utf-8"))
    expect(shown == {row["student"]: f"{row['earned']} / {row['maximum']}" for row in one},
           f"the merged report shows {shown}")
    before = (work / "merged" / "grading" / "grades.csv").read_bytes()

    # A record with its score edited (its grader kept, the CSV made to agree): refused by name.
    shutil.copytree(work / "B", work / "forged")
    rows = _grades(work / "forged" / "grading" / "grades.csv")
    victim = next(r["student"] for r in rows if r["status"] != "not graded" and scale.exact(r["earned"]) < scale.exact(r["maximum"]))
    record_path = work / "forged" / "grading" / "json" / f"{victim}.json"
    record = json.loads(record_path.read_text())
    record["score_exact"] = str(scale.exact(record["score_exact"]) + 1)
    record["score"] = float(scale.shown(scale.exact(record["score_exact"])))
    record["score"] = int(record["score"]) if record["score"] == int(record["score"]) else record["score"]
    record_path.write_text(json.dumps(record, indent=1, ensure_ascii=False))
    text = (work / "forged" / "grading" / "grades.csv").read_text()
    old_row = next(l for l in text.splitlines() if l.startswith(victim + ","))
    cells = old_row.split(",")
    cells[1] = scale.shown(scale.exact(record["score_exact"]))
    (work / "forged" / "grading" / "grades.csv").write_text(text.replace(old_row, ",".join(cells)))
    r = merged_by_a("A", "forged")
    expect(r.returncode != 0 and f"{victim}.json" in r.stderr and "seal" in r.stderr,
           f"a record with its score edited was merged: exit {r.returncode}: {r.stderr[-400:]}")
    refusals.append(f"{victim}.json's score edited")
    # A CSV cell its sealed record does not give (a step's points raised, the total left): refused, named.
    shutil.rmtree(work / "forged")
    shutil.copytree(work / "B", work / "forged")
    path = work / "forged" / "grading" / "grades.csv"
    with path.open(newline="") as f:
        table = list(csv.reader(f))
    column = next(c for c in table[0] if c.startswith("step") and c.endswith("_earned"))
    line = next(r for r in table[1:] if r[table[0].index("status")] != "not graded")
    line[table[0].index(column)] = scale.shown(scale.exact(line[table[0].index(column)] or "0") + 1)
    with path.open("w", newline="") as f:
        csv.writer(f).writerows(table)
    r = merged_by_a("A", "forged")
    expect(r.returncode != 0 and f"{line[0]}'s {column}" in r.stderr and "sealed record" in r.stderr,
           f"a CSV whose {column} its record does not give was merged: exit {r.returncode}: {r.stderr[-400:]}")
    refusals.append(f"{line[0]}'s {column} raised in the CSV")

    # TA B's clone with a changed scene file, never refreshed: refused, the file named.
    scene = _changed_scene(kit_b)
    r = grade(kit_b, env_b, "b-hunt", "B-scene", iso_b)
    expect((work / "B-scene" / "grading" / "grades.csv").is_file(), f"the changed clone's grading: exit {r.returncode}: "
                                                                   f"{r.stderr[-600:]}")
    hunted.append(_seal_hunt(work, secret, f"B ({iso_b})", "B-scene"))
    r = merged_by_a("A", "B-scene")
    expect(r.returncode != 0 and f"{scene} differs" in r.stderr,
           f"a grading by a clone with a changed {scene} was merged, or the refusal did not name it: exit "
           f"{r.returncode}: {r.stderr[-500:]}")
    refusals.append(f"{scene} changed on one clone")
    # ... nor with its list of inputs edited to hide the change.
    from raykit.judgedby import FILE_NAME
    listed = work / "B-scene" / "grading" / "json" / FILE_NAME
    theirs, ours = json.loads(listed.read_text()), json.loads((work / "A" / "grading" / "json" / FILE_NAME).read_text())
    theirs["files"][scene] = ours["files"][scene]
    theirs["digest"] = ours["digest"]
    listed.write_text(json.dumps(theirs, indent=1))
    r = merged_by_a("A", "B-scene")
    expect(r.returncode != 0 and FILE_NAME in r.stderr and "seal" in r.stderr,
           f"a list of inputs edited to hide {scene} was merged: exit {r.returncode}: {r.stderr[-400:]}")
    refusals.append("its list of inputs edited")
    expect((work / "merged" / "grading" / "grades.csv").read_bytes() == before, "a refused merge changed the merged grading")
    shutil.rmtree(work / "kit-a", ignore_errors=True)
    shutil.rmtree(work / "kit-b", ignore_errors=True)
    return (f"{sum(map(len, plan.values()))} students, halves graded on two clones (A {iso_a}, B {iso_b}, ids from "
            f"{FIRST_UID + 2 * UID_RANGE}), the whole on A, in {graded:.0f} s: the merge equals it file for file "
            f"({files} files, {same} byte for byte, the rest but for per-run fields); hostile/seal_key found no secret "
            f"nor sealing key ({', '.join(hunted)}); refused: "
            + ", ".join(refusals) + (f" ({'; '.join(skipped)})" if skipped else ""))


@pytest.mark.quick
def selftest_loop_no_slip(ctx) -> str:
    """A step that timed out is matched to no slip, whatever it failed (issue 46 item 7); the same failing
    cases answered wrongly are matched to the slip whose signature they are."""
    from kitlib.report import signatures
    from kitlib.report.grading import Grading, Student
    from kitlib.report.pages import analyse
    sigs, _ = signatures.load()
    expect(bool(sigs), "no mutant signature recorded (./kit report --signatures)")
    sig = sigs[0]

    def student(name: str, failing: str) -> Student:
        cases = [{"name": n, "tier": "basic", "status": failing} for n in sorted(sig.fails)]
        cases.append({"name": "a case that passes", "tier": "basic", "status": "pass"})
        data = {"steps": [{"step": sig.step, "state": "partial", "cases": cases}]}
        return Student(name, {"student": name}, data)

    g = Grading(WORK, WORK / "none.csv", [student("wrong", "fail"), student("looping", "timed_out"),
                                          student("budget", "not_run")], None)
    found = analyse(g, sigs)
    wrong = found.get(("wrong", sig.step))
    expect(wrong is not None and wrong[1].kind == "exact" and sig in wrong[1].signatures,
           f"wrong answers on {sig.name}'s cases are not matched to it: {wrong}")
    for who in ("looping", "budget"):
        expect((who, sig.step) not in found, f"a step whose cases {'timed out' if who == 'looping' else 'never ran'} "
                                             f"was matched to a slip: {[m.name for m in found[(who, sig.step)][1].signatures] if (who, sig.step) in found else ''}")
    return (f"{len(sig.fails)} failing cases of step {sig.step}: answered wrongly, matched to {sig.name}; "
            "timed out or never run, matched to nothing")


@pytest.mark.quick
def selftest_extra_credit(ctx) -> str:
    """#46 item 2 and item 7's last point, in the report (no build, a few seconds): a class graded on the
    kit's course.json with ★ made extra credit (records of each step's recorded cases, the CSV written
    by ./kit grade's own record_row) is reported with its histogram and "at the maximum" on the points
    without the extra credit (a student with a core slip carried past the maximum by ★ is not at it, and
    no one falls outside the histogram's 100 %), the extra credit apart (its own sentence and chart), and
    every score on the course's decimals as the CSV writes them (108.90, not 108.9)."""
    from fractions import Fraction
    from raykit import course as course_file
    from raykit import record as results_record
    from raykit.checking import recorded_cases
    from kitlib.commands.grade import columns, csv_text, record_row
    from kitlib.report.grading import load
    from kitlib.report.pages import build, class_scores
    from .course import extra_credit_course, kit_results
    need_solutions()
    steps = [s for s in load_steps() if recorded_cases(s)]
    if not steps:
        raise Skipped("no step has a recorded case list (tests/NN_topic/cases.json)")
    course = extra_credit_course([s.number for s in load_steps()])
    with course_file.using(course):
        first = steps[0]
        core = next(c.name for c in recorded_cases(first) if course.group(c.tier, c.name) == "core")
        stars = {s.number: [c.name for c in recorded_cases(s) if course.extra_credit(course.group(c.tier, c.name))]
                 for s in steps}
        everyone = {"textbook": {s.number: {"robust"} for s in steps}, "complete": {},
                    "slip-carried": {first.number: {core}}}
        # A slip with some ★ cases whose total shows a trailing zero on the course's decimals (108.90).
        for s in steps:
            for k in range(1, len(stars[s.number]) + 1):
                fail = {n.number: {"robust"} for n in steps if n.number != s.number}
                fail[s.number] = set(stars[s.number][k:]) | fail.get(s.number, set())
                fail[first.number] = fail.get(first.number, set()) | {core}
                if s.number != first.number:
                    fail[first.number] |= {"robust"}
                total = sum((r.earned for r in kit_results(course, steps, fail)), Fraction(0))
                if "." in course.shown(total) and course.shown(total).endswith("0"):
                    everyone["slip-trailing-zero"] = fail
                    break
            if "slip-trailing-zero" in everyone:
                break
        everyone["slip-no-star"] = {**{s.number: {"robust"} for s in steps}, first.number: {core, "robust"}}
        folder = WORK / "extra-credit" / "grading"
        shutil.rmtree(folder.parent, ignore_errors=True)
        (folder / "json").mkdir(parents=True)
        rows, want_at_max, want_some = [], 0, 0
        for name, fail in everyone.items():
            rs = kit_results(course, steps, fail)
            data = results_record.make(rs, 1.0)
            results_record.write(folder / "json" / f"{name}.json", data)
            rows.append(record_row({"student": name}, data, steps))
            # Expected from the cases: at the maximum when no counted case fails; extra credit when a ★ passes.
            want_at_max += all(c.status == "pass" for r in rs for c in r.cases if not course.extra_credit(c.group))
            want_some += any(c.status == "pass" for r in rs for c in r.cases if course.extra_credit(c.group))
        (folder / "grades.csv").write_text(csv_text(columns(steps), rows))
        out = WORK / "extra-credit" / "report"
        build(folder, out)
        g = load(folder)
        scores = class_scores(g)
        index = (out / "index.html").read_text(encoding="utf-8")
        expect(len(scores["percents"]) == len(everyone) and max(scores["percents"]) <= 100,
               f"the histogram holds {len(scores['percents'])} of {len(everyone)} students, up to "
               f"{max(scores['percents'] or [0]):.1f} % (a student past 100 % is left out of its bins)")
        expect(f'data-at-maximum="{want_at_max}"' in index,
               f"'at the maximum' is not {want_at_max} (the students with no counted case failed): "
               + (re.search(r"data-at-maximum=\"\d+\">[^<]*", index) or [""])[0])
        expect(f'data-extra-credit="{want_some}"' in index and index.count("<img") >= 3,
               f"the extra credit is not shown apart ({want_some} earned some; a sentence and a chart): "
               + (re.search(r'data-extra-credit="[^<]*', index) or ["no sentence"])[0])
        with (folder / "grades.csv").open(newline="") as f:
            csv_rows = {row["student"]: row for row in csv.DictReader(f)}
        shown = _scores_in(index)
        for st in g.students:
            row = csv_rows[st.name]
            expect(shown.get(st.name) == f"{row['earned']} / {row['maximum']}",
                   f"{st.name}: the CSV says {row['earned']} / {row['maximum']}, the report {shown.get(st.name)}")
            text = (out / "students" / f"{st.page}.html").read_text(encoding="utf-8")
            m = re.search(r'data-earned="([^"]*)" data-maximum="([^"]*)"', text)
            expect(m and m.groups() == (row["earned"], row["maximum"]),
                   f"{st.name}: the CSV says {row['earned']} / {row['maximum']}, their page {m and m.groups()}")
        trailing = csv_rows.get("slip-trailing-zero", {}).get("earned", "")
    return (f"{course.source}: {len(everyone)} students, {want_at_max} at the maximum without the extra credit, "
            f"{want_some} with some apart; the histogram holds all, up to {max(scores['percents']):.0f} %; "
            + (f"'{trailing}' on the CSV and the report alike" if trailing else
               "no score with a trailing zero on this course (the decimals compared as they are)"))


@pytest.mark.quick
def selftest_charts(ctx) -> str:
    """The report's charts (charts.py, the kit's one drawing path) say what their data says: each bar of a
    histogram counts the values of its bin, a value at the top end in the last bin; each stacked segment is
    as long as its value on the axis; names are escaped; a description charts.py cannot read is said on the
    page, not raised. Read back from the SVG's own elements (each bar carries its count in a title)."""
    from kitlib import charts
    from kitlib.report import plots
    values = [0, 4.9, 5, 50, 99.9, 100, 100]
    svg = charts.hist(values, list(range(0, 101, 5)), "score <%>", "students")
    counts = {m.group(1): int(m.group(2)) for m in re.finditer(r"<title>(\d+ to \d+): (\d+)</title>", svg)}
    expect(counts == {"0 to 5": 2, "5 to 10": 1, "50 to 55": 1, "95 to 100": 3},
           f"histogram bars {counts}, expected 0-5: 2, 5-10: 1, 50-55: 1, 95-100: 3 (100 in the last bin)")
    expect("score &lt;%&gt;" in svg and "score <%>" not in svg, "the axis label is not escaped")
    bars = charts.stacked_bars(["step 01", "step 02"], [["done", "#0a0", [3, 0]], ["not started", "#999", [1, 4]]],
                               "students")
    widths = {m.group(2): float(m.group(1)) for m in
              re.finditer(r'width="([\d.]+)" height="[\d.]+" fill="[^"]+" stroke="white"><title>([^<]+)</title>', bars)}
    unit = widths["step 01, done: 3"] / 3
    expect(abs(widths["step 01, not started: 1"] - unit) < 0.2 and abs(widths["step 02, not started: 4"] - 4 * unit) < 0.2,
           f"segments not proportional to their values: {widths}")
    expect("step 02, done" not in bars, "a zero segment was drawn")
    svgs, why = plots.draw([{"kind": "pie", "xlabel": "x"}])
    expect(not svgs and "no charts" in why, f"an unknown chart kind gave {svgs!r}, {why!r}")
    return (f"a histogram of {len(values)} values in {len(counts)} bars, stacked bars in proportion, names escaped, "
            f"an unreadable description said on the page ({why[:40]}…)")


# Student-controlled text on the pages: a name that is a tag, messages and a note that close the element
# they are in and open a script. None may reach a page as markup (the templates' autoescape).
HOSTILE_HTML = ('<img src=x onerror=alert(1)>"\'', '</pre><script>alert(2)</script>',
                '"><script>alert(3)</script><b title="')


def _markup_of(text: str) -> tuple[list[str], list[str]]:
    """The start tags of a page and the attributes that run script, as a browser's parser reads them."""
    from html.parser import HTMLParser
    tags, scripts = [], []

    class Reader(HTMLParser):
        def handle_starttag(self, tag, attrs):
            tags.append(tag)
            scripts.extend(f"{tag} {k}" for k, _ in attrs if k.startswith("on"))

    Reader().feed(text)
    return tags, scripts


@pytest.mark.quick
def selftest_pages_escaped(ctx) -> str:
    """The report's pages show what a student controls as text (issue 56): a student named with a tag,
    case messages and a compiler's line that close a <pre> and open a script, a note in the CSV that
    ends an attribute. Read back with an HTML parser: no script element, no on* attribute, no <img>
    but the charts' and pictures' own; and no template turns the escaping off."""
    from raykit import course as course_file
    from raykit import record as results_record
    from kitlib.commands.grade import columns, csv_text, record_row
    from kitlib.report import pages
    from raykit.status import NOTHING_SUBMITTED
    from .course import kit_results
    steps = load_steps()
    course = course_file.load()
    folder = WORK / "escaped" / "grading"
    shutil.rmtree(folder.parent, ignore_errors=True)
    (folder / "json").mkdir(parents=True)
    name, message, note = HOSTILE_HTML
    rs = kit_results(course, steps[:1], {steps[0].number: {"core", "robust"}})
    data = json.loads(json.dumps(results_record.make(rs, 1.0)))
    for case in data["steps"][0]["cases"]:
        case["messages"] = [message + m for m in case.get("messages") or []] or case.get("messages")
        case["lecture"] = note if case.get("status") != "pass" else case.get("lecture")
    data["steps"][0]["title"] = message
    next(c for c in data["steps"][0]["cases"] if c.get("status") != "pass")["status"] = "crashed"   # an incident
    results_record.write(folder / "json" / f"{name}.json", data)
    rows = [record_row({"student": name}, data, steps),
            {"student": message.replace("/", "|"), "status": NOTHING_SUBMITTED, "note": note}]
    (folder / "grades.csv").write_text(csv_text(columns(steps), rows))
    out = WORK / "escaped" / "report"
    pages.build(folder, out)
    written = [out / "index.html", *sorted((out / "students").glob("*.html"))]
    expect(len(written) == 3, f"the report wrote {len(written) - 1} student pages, not 2")
    problems = []
    for page in written:
        text = page.read_text(encoding="utf-8")
        tags, scripts = _markup_of(text)
        if "script" in tags or scripts:
            problems.append(f"{page.name}: {tags.count('script')} script element(s), attributes {scripts[:3]}")
        said = "&lt;img src=x" if page != written[-1] else "&gt;&lt;script&gt;alert(3)"     # the last: the note's
        if said not in text:
            problems.append(f"{page.name}: {said!r} (a name, or the note) is not shown as text")
    expect(not problems, "student text reached a page as markup:\n  " + "\n  ".join(problems))
    shown = "<pre>&lt;/pre&gt;&lt;script&gt;alert(2)"
    expect(shown in written[0].read_text(encoding="utf-8") and shown in written[1].read_text(encoding="utf-8"),
           "a case's message is not shown as text in its <pre> on the index (an incident) and the student's page")
    off = [t.name for t in pages.TEMPLATES.iterdir() if re.search(r"\|\s*safe\b|autoescape\s+false", t.read_text())]
    expect(not off, f"templates that turn the escaping off: {off}")
    expect(pages.templates().autoescape is True, "the report's templates are not autoescaped")
    shutil.rmtree(folder.parent, ignore_errors=True)
    return (f"{len(HOSTILE_HTML)} hostile texts (a name, messages, a note) shown as text on {len(written)} pages: "
            "no script element, no on* attribute")

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
"""

from __future__ import annotations

import csv
import re
import shutil
import time
from pathlib import Path

from ..common import BUILD, ROOT, KitError, load_steps
from .harness import Failed, Skipped, expect, kit, need_solutions

WORK = BUILD / "report-test"
STEPS = ("01", "02")


def _signatures():
    from ..report import signatures
    sigs, notes = signatures.load()
    return sigs, notes


def selftest_signatures_fresh(ctx) -> str:
    need_solutions()
    from ..commands.mutant import patches
    from ..report import signatures
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
    from ..commands.mutant import write_answer
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
    put(who, s1, ROOT / "tests" / "fixtures" / "no_compile" / s1.folder), put(who, s2, sol(s2))
    plan["odd"].append(who)
    textbook = ROOT / "tests" / "fixtures" / "textbook"
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
    from ..report import signatures
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
    from ..report.grading import load
    from ..report.pages import analyse
    sigs, _ = signatures.load()
    g = load(out / "grading")
    problems = _slip_problems(plan, analyse(g, load_steps(), sigs))
    expect(not problems, "slips not recognised:\n  " + "\n  ".join(problems))

    # The check can fail: with one slip's recorded signature one case short, its student is not matched to it.
    victim, [mutant] = next((w, m) for w, m in plan["one"].items()
                            if sum(x.step == m[0].step and x.fails == m[0].fails for x in sigs) == 1)
    wrong = [signatures.Signature(x.key, x.step, x.name, x.slip, x.lecture, frozenset(sorted(x.fails)[1:]))
             if x.key == mutant.key else x for x in sigs]
    missed = _slip_problems({"one": {victim: [mutant]}, "two": {}}, analyse(g, load_steps(), wrong))
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


def _browser(*pages_: Path) -> str:
    from .. import browser
    from ..packages import ensure_packages
    try:
        ensure_packages("browser")
    except KitError as e:
        raise Skipped(f"Chromium is not installed and could not be ({str(e).splitlines()[0]})")
    chromium = browser.find_chromium()
    if chromium is None:
        raise Skipped("no chromium on the PATH (sudo apt-get install chromium)")

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


def selftests():
    return [("report: the mutants' signatures are current", selftest_signatures_fresh),
            ("report: a synthetic class's report", selftest_class_report)]

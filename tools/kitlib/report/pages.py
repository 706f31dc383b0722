"""The report's pages: DIR/index.html (the class, for the instructor) and DIR/students/NAME.html.

Plain HTML and CSS, no script: every chart and picture is an SVG inside the page (a data: URL), so
the folder reads offline, prints, and can be sent as it is. A student's page is made from that
student's results alone and names no other student.
"""

from __future__ import annotations

import base64
import html
import re
import shutil
import time
from collections import Counter, defaultdict
from fractions import Fraction
from pathlib import Path

from raykit import atomic
from raykit import course as course_file
from raykit import picture
from raykit import record as results_record
from raykit.common import load_steps, prerequisites, printable
from raykit.status import NOTHING_SUBMITTED_STATES, NOT_GRADED, OLD_BROKEN, CRASHED, DONE, MISSING, NO_COMPILE, NOT_STARTED, PARTIAL, PASS, STATE_WORDS, STATUS_WORDS, THREW, TIMED_OUT, NO_ANSWER, WAITING
from . import grading as grading_mod
from . import plots, signatures, similar

MOST_FAILED = 3             # cases drawn beside the table
PICTURES_PER_STEP = 8       # on a student's page
RUN_LINES = 40              # lines of a matching run shown side by side

STATE_COLOURS = [(DONE, "#2e7d32"), (PARTIAL, "#f2a900"), (NOT_STARTED, "#9e9e9e"), (NO_COMPILE, "#c62828"),
                 (MISSING, "#6d4c41"), (WAITING, "#90a4ae"), (NOT_GRADED, "#f9a825")]

NOT_A_VERDICT = ("This list is not a verdict on any student: a set of failing cases can fit a slip by chance, "
                 "and a slip can be made in ways no mutant has. It is a map of what the class may have "
                 "misunderstood, to look at and teach from.")

CSS = """
body{font-family:"DejaVu Sans",Arial,sans-serif;max-width:72rem;margin:1.5rem auto;padding:0 1rem;color:#222;line-height:1.4}
h1{font-size:1.6rem}h2{font-size:1.3rem;border-bottom:2px solid #1f4e99;margin-top:2.2rem}h3{font-size:1.08rem;margin-top:1.4rem}
table{border-collapse:collapse;margin:.6rem 0;font-size:.9rem}th,td{border:1px solid #ccc;padding:.2rem .45rem;vertical-align:top;text-align:left}
th{background:#eef2f8}td.n{text-align:right;font-variant-numeric:tabular-nums}
.note{background:#fff6e0;border-left:4px solid #f2a900;padding:.4rem .7rem;margin:.6rem 0}
.warn{background:#fdecea;border-left:4px solid #c62828;padding:.4rem .7rem}
pre{background:#f6f6f6;padding:.4rem;overflow-x:auto;font-size:.8rem;white-space:pre-wrap;margin:.2rem 0}
.pair{display:grid;grid-template-columns:1fr 1fr;gap:.5rem}.pair pre{white-space:pre;font-size:.72rem}
.state-done{color:#2e7d32}.state-partial{color:#9a6700}.state-no_compile{color:#c62828}
figure{margin:.5rem 0;display:inline-block;vertical-align:top}figcaption{font-size:.8rem;color:#555;max-width:600px}
img.chart{max-width:100%}.cards{display:grid;grid-template-columns:repeat(auto-fill,minmax(30rem,1fr));gap:1rem}
.cards img{width:100%;height:auto}nav a{margin-right:.8rem}
@media print{nav{display:none}h2{page-break-before:auto}.pair pre,pre{font-size:.65rem}}
"""


def e(text) -> str:
    """Any text on a page, escaped as HTML and its control characters shown (common.printable): a
    student's name, output and code, a check's name. Every text of the pages passes here."""
    return html.escape(printable(str(text)), quote=True)


def svg_img(svg: str, alt: str, cls: str = "") -> str:
    data = base64.b64encode(svg.encode("utf-8")).decode("ascii")
    c = f' class="{cls}"' if cls else ""
    return f'<img{c} alt="{e(alt)}" src="data:image/svg+xml;base64,{data}">'


def page(title: str, body: list[str]) -> str:
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>{e(title)}</title><style>{CSS}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n")


def failing_basic(step: dict) -> frozenset:
    return frozenset(c["name"] for c in step.get("cases", []) if c.get("tier") == "basic" and c.get("status") != PASS)


def draw_case(case: dict, title: str) -> str:
    figure = case.get("figure")
    if not isinstance(figure, dict):
        return ""
    try:
        svg, line = picture.render(figure, title)
    except (picture.PictureError, KeyError, TypeError, ValueError, ZeroDivisionError):
        return ""
    return f"<figure>{svg_img(svg, line)}</figure>"      # the picture says in words what it shows


# --- what the class did ----------------------------------------------------------------------------



def analyse(g, steps, sigs):
    by_step = defaultdict(list)
    for s in sigs:
        by_step[s.step].append(s)
    matches = {}        # (student, step) -> (fails, Match)
    for st in g.students:
        for res in st.steps():
            if res.get("state") != PARTIAL:
                continue
            if any(c.get("status") in NO_ANSWER for c in res.get("cases", [])):
                continue
            fails = failing_basic(res)
            if fails:
                matches[(st.name, res["step"])] = (fails, signatures.match(fails, by_step.get(res["step"], [])))
    return matches


_QUOTED = re.compile(r"[‘'\"«][^’'\"»]*[’'\"»]")


def compile_kind(detail: str) -> tuple[str, str]:
    """The kind of a build's first diagnostic (its words, names and numbers left out) and the line."""
    for line in detail.splitlines():
        m = re.search(r"\b(?:fatal )?error: (.*)", line)
        if m:
            kind = re.sub(r"\d+", "N", _QUOTED.sub("‘…’", m.group(1))).strip()
            return kind[:160], line.strip()[:400]
    first = next((l.strip() for l in detail.splitlines() if l.strip()), "no message")
    return "no compiler error line (a link error?)", first[:400]


def crash_kind(case: dict) -> tuple[str, str]:
    """A crash, time-out or throw grouped by what the record says of it (the case's "incident": the
    function called, the signal), never by its message's words; and the message, as an example."""
    text = " ".join(case.get("messages") or [])
    incident = case.get("incident") if isinstance(case.get("incident"), dict) else {}
    what = STATUS_WORDS.get(case.get("status"), case.get("status"))
    parts = [what]
    if incident.get("signal") and case.get("status") == CRASHED:
        parts.append(incident["signal"])
    parts.append(f"in {incident['function']}()" if incident.get("function") else "")
    return " ".join(p for p in parts if p), text[:400]


def incidents(g):
    """{section title: {kind: [(student, step, example)]}}"""
    out = {"Does not compile": defaultdict(list), "Crashed": defaultdict(list),
           "Threw an exception": defaultdict(list), "Timed out": defaultdict(list),
           "Run again after a timeout": defaultdict(list), "Not graded": defaultdict(list),
           "Nothing submitted": defaultdict(list)}
    for st in g.students:
        if st.data is None:
            status = st.row.get("status") or "not graded"
            section = "Nothing submitted" if status in NOTHING_SUBMITTED_STATES else "Not graded"
            out[section][status].append((st.name, "", st.row.get("note", "")))
            continue
        for number, why in results_record.not_graded(st.data):   # the grader's fault, from the record's data
            out["Not graded"][f"step {number}: {why[:160]}"].append((st.name, number, why))
        for res in st.steps():
            if res.get("state") == NO_COMPILE:
                kind, line = compile_kind(res.get("detail", ""))
                out["Does not compile"][kind].append((st.name, res["step"], line))
            seen = set()
            for c in res.get("cases", []):
                section = {CRASHED: "Crashed", THREW: "Threw an exception", TIMED_OUT: "Timed out"}.get(c.get("status"))
                if section:
                    kind, text = crash_kind(c)
                    if (section, kind) not in seen:         # once per student and step
                        seen.add((section, kind))
                        out[section][f"step {res['step']}: {kind}"].append((st.name, res["step"], text))
                rerun = c.get("rerun") if c.get("runs", 1) > 1 else None
                if isinstance(rerun, dict):     # the record keeps both runs (runcases.rerun_timeouts)
                    first = rerun.get("first") or {}
                    kind = (f"step {res['step']}: {STATUS_WORDS.get(first.get('status'), first.get('status'))}, "
                            f"then {STATUS_WORDS.get(c.get('status'), c.get('status'))}")
                    out["Run again after a timeout"][kind].append(
                        (st.name, res["step"], f"{c['name']}: {' '.join(first.get('messages') or [])[:300]}"))
    return {k: v for k, v in out.items() if v}


# --- the index -------------------------------------------------------------------------------------

def class_scores(g) -> dict:
    """The class's scores, from each student's record (Student.points): the histogram's percentages
    and "at the maximum" on the points without the extra credit (#46: the ★ points carried a student
    with a bug to "the maximum", and put others past the histogram's 100 %), and the extra credit
    apart: how many earned some, all of it, and were carried to the maximum or past it by it."""
    points = [p for p in (st.points() for st in g.students) if p is not None]
    percents = [float(100 * base / maximum) for base, maximum, _, _ in points]
    at_maximum = sum(base >= maximum for base, maximum, _, _ in points)
    possible = max((p for _, _, _, p in points), default=Fraction(0))
    extras = [extra for _, _, extra, _ in points]
    earned_some = sum(x > 0 for x in extras)
    full = sum(extra >= p > 0 for _, _, extra, p in points)
    carried = sum(base < maximum <= base + extra for base, maximum, extra, _ in points)
    course = course_file.load()
    words = (f"Extra credit, on top of the points (not in the histogram above): {earned_some} of {len(points)} "
             f"students earned some, {full} all {course.shown(possible)} points of it; it took {carried} student"
             f"{'' if carried == 1 else 's'} with points missing to the maximum or past it.") if possible else ""
    top = float(possible)
    chart = {"kind": "hist", "values": [float(x) for x in extras], "bins": [top * i / 10 for i in range(11)],
             "xlabel": "extra credit earned (points, on top of the maximum)", "ylabel": "students"}
    return {"percents": percents, "at_maximum": at_maximum, "possible": possible, "earned_some": earned_some,
            "full": full, "carried": carried, "words": words, "chart": chart}


def case_worth(course, step: str, case: dict) -> tuple[bool, str]:
    """Whether a recorded case counts in the step's points, and its weight and points as the report
    shows them beside it ("2 → 0.43", "1/10 → +0.02 extra", "0 → 0"): its record's group and points, the
    weight as the course gives it (its own, by name or section, else its group's)."""
    group = case.get("group") or course.group(case.get("tier", ""), case.get("name", ""))
    weight = course.case_weight(step, group, case.get("name", ""), case.get("lecture", ""))
    try:
        points = Fraction(str(case.get("points", "0")))
    except (ValueError, ZeroDivisionError):
        points = Fraction(0)
    extra = course.extra_credit(group)
    counted = not extra and not course.optional(group)
    return counted, (f"{course_file.exact_text(weight)} → " + ("+" if extra else "") + course.shown(points)
                     + (" extra" if extra else ""))


def link(st) -> str:
    return f'<a href="students/{e(st.page)}.html">{e(st.name)}</a>'


def build(folder: Path, out: Path) -> dict:
    start = time.monotonic()
    g = grading_mod.load(folder)
    steps = load_steps()
    sigs, notes = signatures.load()
    notes = g.problems + notes
    matches = analyse(g, steps, sigs)
    names = {st.name: st for st in g.students}
    graded = [st for st in g.students if st.data is not None]

    ungraded = [st for st in g.students if st.row.get("status") in ("not graded", "timed out")]
    body = [f"<h1>Class report</h1><p>{len(g.students)} submissions, {len(graded) - sum(st.data is not None for st in ungraded)} "
            f"graded" + (f", <b>{len(ungraded)} not graded</b> (the grader's fault: see Incidents, then grade them "
                         "again)" if ungraded else "") + "; grading "
            f"<code>{e(g.csv_path)}</code>; written {time.strftime('%Y-%m-%d %H:%M')}.</p>",
            '<nav><a href="#scores">Scores</a><a href="#cases">Cases</a><a href="#slips">Slips</a>'
            '<a href="#incidents">Incidents</a><a href="#similar">Similar submissions</a><a href="#students">Students</a></nav>']
    for n in notes:
        body.append(f'<p class="note">{e(n)}</p>')

    # 1. scores
    scores = class_scores(g)
    percents = scores["percents"]
    counts = {s.number: Counter() for s in steps}
    extra = {s.number: Counter() for s in steps}
    robust = {s.number: [0, 0] for s in steps}
    for st in graded:
        for res in st.steps():
            n = res.get("step")
            if n not in counts:
                continue
            counts[n][res.get("state")] += 1
            statuses = {c.get("status") for c in res.get("cases", []) if c.get("tier") != "robust"}
            for bad in (CRASHED, TIMED_OUT, THREW):
                extra[n][bad] += bad in statuses
            if res.get("state") == DONE and res.get("robust", {}).get("total"):
                robust[n][1] += 1
                robust[n][0] += res["robust"]["passed"] == res["robust"]["total"]
    charts = [{"kind": "hist", "values": percents, "bins": list(range(0, 101, 5)),
               "xlabel": "score (% of the maximum" + (", extra credit aside)" if scores["possible"] else ")"),
               "ylabel": "students"},
              {"kind": "bars", "labels": [f"step {s.number}" for s in steps], "xlabel": "students",
               "height": 2.2 + 0.25 * len(steps),
               "series": [[STATE_WORDS[k], colour, [counts[s.number][k] for s in steps]] for k, colour in STATE_COLOURS
                          if any(counts[s.number][k] for s in steps)]}]
    if scores["possible"]:      # the extra credit apart: its own chart, after the others
        charts.append(scores["chart"])
    svgs, why = plots.draw(charts)
    if why:
        notes.append(why)
    body.append('<h2 id="scores">1. Scores</h2>')
    if percents:
        srt = sorted(percents)
        body.append(f"<p>On the course's scale ({e(course_file.load().scale_words())}): "
                    f"median {srt[len(srt) // 2]:.0f} %, lowest {srt[0]:.0f} %, highest {srt[-1]:.0f} %, "
                    f'<span data-at-maximum="{scores["at_maximum"]}">{scores["at_maximum"]} of {len(percents)} '
                    f"at the maximum</span>" + (" (the points without the extra credit)" if scores["possible"] else "")
                    + ".</p>")
    if svgs:
        body.append(svg_img(svgs[0], "histogram of the scores", "chart"))
    else:
        body.append(f'<p class="note">{e(why)}</p>')
    if scores["possible"]:
        body.append(f'<p data-extra-credit="{scores["earned_some"]}">{e(scores["words"])}</p>')
        if len(svgs) > 2:
            body.append(svg_img(svgs[2], "histogram of the extra credit earned", "chart"))
    head = "".join(f"<th>{e(STATE_WORDS[k])}</th>" for k, _ in STATE_COLOURS)
    rows = []
    for s in steps:
        cells = "".join(f'<td class="n">{counts[s.number][k]}</td>' for k, _ in STATE_COLOURS)
        bad = "".join(f'<td class="n">{extra[s.number][k]}</td>' for k in (CRASHED, TIMED_OUT))
        rob = f"{robust[s.number][0]} of {robust[s.number][1]}" if robust[s.number][1] else "–"
        rows.append(f"<tr><td>{e(s.number)} {e(s.title)}</td>{cells}{bad}<td class=\"n\">{rob}</td></tr>")
    body.append(f"<table><tr><th>step</th>{head}<th>a case crashed</th><th>a case timed out</th>"
                f"<th>★ all passed (of those done)</th></tr>{''.join(rows)}</table>")
    if len(svgs) > 1:
        body.append(svg_img(svgs[1], "the steps' states", "chart"))

    # 2. cases by failure rate
    course = course_file.load()
    star = ("★ cases are extra credit, on top of a step's points" if course.extra_credit("robust")
            else "★ cases are optional and count for nothing" if course.optional("robust")
            else "★ cases count like the others")
    body.append('<h2 id="cases">2. The cases, by failure rate</h2><p>Among the students whose step ran (some cases '
                f'fail, or done). Hidden cases are drawn with a seed per grading; {e(star)}. Each step lists its '
                f'counted cases first, then the others; “weight → points” is a case\'s weight and what it is worth '
                f'on the course\'s scale ({e(course.scale_words())}).</p>')
    case_rows = []          # (rate, step, lecture, name, tier, failed, ran, example case, counted, worth)
    for s in steps:
        failed, ran, lecture, tier, example, worth = Counter(), Counter(), {}, {}, {}, {}
        for st in graded:
            res = st.step(s.number)
            if not res or res.get("state") not in (PARTIAL, DONE):
                continue
            for c in res.get("cases", []):
                ran[c["name"]] += 1
                lecture[c["name"]], tier[c["name"]] = c.get("lecture", ""), c.get("tier", "")
                worth.setdefault(c["name"], case_worth(course, s.number, c))
                if c.get("status") != PASS:
                    failed[c["name"]] += 1
                    if c["name"] not in example and c.get("figure"):
                        example[c["name"]] = c
        for name in ran:
            case_rows.append((failed[name] / ran[name], s, lecture[name], name, tier[name], failed[name], ran[name],
                              example.get(name), *worth[name]))
    # The pictures: the most-failed basic cases, the same for every student (a hidden case is a set of
    # random draws, and fails more often for having more of them; it is in the tables below).
    top = sorted((r for r in case_rows if r[5] and r[4] == "basic"), key=lambda r: (-r[0], r[1].number, r[3]))[:MOST_FAILED]
    if top:
        body.append("<h3>The most-failed basic cases</h3><p>Each picture is the case as one of the students who fail "
                    "it answered it (“your answer” is that student's).</p><div class=\"cards\">")
        for r in top:
            drawn = draw_case(r[7], f"Step {r[1].number} · {r[3]}") if r[7] else ""
            body.append(f"<div><p><b>Step {e(r[1].number)} · {e(r[3])}</b> ({e(r[2])}): failed by "
                        f"{r[5]} of {r[6]} ({100 * r[0]:.0f} %).</p>{drawn or '<p>(no picture for this case)</p>'}</div>")
        body.append("</div>")
    for s in steps:
        mine = [r for r in case_rows if r[1] is s]
        if not mine:
            continue
        body.append(f"<h3>Step {e(s.number)}: {e(s.title)}</h3>")
        passed_by_all = sum(1 for r in mine if not r[5])
        lines = []
        # The counted cases first, then the ★ ones (extra credit or optional): issue 55, the ★ cases, failed
        # more often, stood above the ones that make the grade.
        for counted in (True, False):
            by_lecture = defaultdict(list)
            for r in mine:
                if r[5] and r[8] == counted:
                    by_lecture[r[2]].append(r)
            if by_lecture and not counted:
                lines.append(f'<tr><td colspan="6"><b>not counted in the points</b>: {e(star)}</td></tr>')
            for lec, rs in sorted(by_lecture.items(), key=lambda kv: -max(r[0] for r in kv[1])):
                for i, r in enumerate(sorted(rs, key=lambda r: -r[0])):
                    first = f'<td rowspan="{len(rs)}">{e(lec)}</td>' if i == 0 else ""
                    lines.append(f"<tr>{first}<td>{e(r[3])}</td><td>{e(r[4])}</td><td class=\"n\">{e(r[9])}</td>"
                                 f"<td class=\"n\">{r[5]} / {r[6]}</td><td class=\"n\">{100 * r[0]:.0f} %</td></tr>")
        if lines:
            body.append(f"<table><tr><th>lecture section</th><th>case</th><th>tier</th><th>weight → points</th>"
                        f"<th>failed</th><th>rate</th></tr>{''.join(lines)}</table>")
        body.append(f"<p>{passed_by_all} of {len(mine)} cases passed by every student whose step ran.</p>")

    # 3. slips
    body.append(f'<h2 id="slips">3. The slips</h2><p class="note">{e(NOT_A_VERDICT)}</p>'
                f"<p>Each student's failing basic cases in a step are compared with the cases each mutant of "
                f"<code>tests/mutants/</code> fails ({len(sigs)} mutants): an exact match, or a near one (the "
                f"distance is the number of cases in one set and not the other). Mutants that fail the same cases "
                f"are shown together.</p>")
    fits = defaultdict(list)        # (step, signature) -> [(student, kind, distance)]
    unmatched = defaultdict(list)   # (step, fails) -> [student]
    by_sig = {}
    for (name, number), (fails, m) in sorted(matches.items()):
        if m.kind == "none":
            unmatched[(number, fails)].append(name)
            continue
        for sig_set in {s.fails for s in m.signatures}:
            fits[(number, sig_set)].append((name, m.kind, m.distance))
            by_sig[(number, sig_set)] = [s for s in sigs if s.step == number and s.fails == sig_set]
    rows = []
    for key in sorted(fits, key=lambda k: (k[0], -len(fits[k]))):
        group = by_sig[key]
        slips = "<br>".join(f"{e(s.slip)} <small>({e(s.name)})</small>" for s in group)
        exact = [n for n, k, _ in fits[key] if k == "exact"]
        near = [(n, d) for n, k, d in fits[key] if k == "near"]
        who = ", ".join(link(names[n]) for n in exact)
        who_near = ", ".join(f"{link(names[n])} ({d})" for n, d in near)
        rows.append(f"<tr><td>{e(key[0])}</td><td>{slips}</td><td>{e(group[0].lecture)}</td>"
                    f"<td class=\"n\">{len(exact)}</td><td>{who}</td><td class=\"n\">{len(near)}</td><td>{who_near}</td></tr>")
    if rows:
        body.append("<table><tr><th>step</th><th>slip (mutant)</th><th>lecture section</th><th>exact</th><th>students</th>"
                    f"<th>near</th><th>students (distance)</th></tr>{''.join(rows)}</table>")
    else:
        body.append("<p>No student's failing cases fit a slip.</p>")
    if unmatched:
        body.append("<h3>Patterns that fit no slip</h3><p>A student marked * has an earlier step this one builds on "
                    "that is not done: the pattern may come from there. Two slips in one step fit no single mutant.</p>"
                    "<table><tr><th>step</th><th>students</th><th>failing basic cases</th></tr>")
        step_of = {s.number: s for s in steps}

        def upstream(name: str, number: str) -> str:
            st = names[name]
            needs = prerequisites(step_of[number], steps) if number in step_of else []
            return "*" if any((st.step(p.number) or {}).get("state") != DONE for p in needs) else ""

        for (number, fails), who in sorted(unmatched.items(), key=lambda kv: (kv[0][0], -len(kv[1]))):
            shown = sorted(fails)
            cases = "<br>".join(e(c) for c in shown[:12]) + (f"<br>… and {len(shown) - 12} more" if len(shown) > 12 else "")
            body.append(f"<tr><td>{e(number)}</td><td>{', '.join(link(names[n]) + upstream(n, number) for n in who)}</td>"
                        f"<td>{cases}</td></tr>")
        body.append("</table>")

    # 4. incidents
    body.append('<h2 id="incidents">4. Incidents</h2>')
    found = incidents(g)
    if not found:
        body.append("<p>None: every submission compiled, and no case crashed, threw or timed out.</p>")
    for section, kinds in found.items():
        body.append(f"<h3>{e(section)}</h3><table><tr><th>kind</th><th>students</th><th>example</th></tr>")
        for kind, items in sorted(kinds.items(), key=lambda kv: -len(kv[1])):
            who = ", ".join(link(names[n]) if n in names else e(n) for n, _, _ in items)
            body.append(f"<tr><td>{e(kind)}</td><td>{len(items)}: {who}</td><td><pre>{e(items[0][2])}</pre></td></tr>")
        body.append("</table>")

    # 5. similar submissions
    body.append('<h2 id="similar">5. Similar submissions</h2><p class="note">Similarity is a reason to look, not a '
                'proof: short answers to the same exercise look alike, and a student may have had help that was '
                'allowed. Look at the code before drawing any conclusion.</p>')
    sim = similar.compare(g.files, [st.name for st in graded], steps)
    if not sim.available:
        body.append(f'<p class="note">Not compared: {e(sim.note)}.</p>')
        notes.append(f"similar submissions not compared: {sim.note}")
    else:
        body.extend(similar_section(sim, names))

    # 6. the students
    body.append('<h2 id="students">6. The students</h2><p>Each page is for the student alone: it names no other '
                'student and can be sent as it is.</p><table><tr><th>student</th><th>score</th><th>%</th><th>status</th>'
                + "".join(f"<th>step {e(s.number)}</th>" for s in steps) + "</tr>")
    for st in g.students:
        cells = "".join(f"<td>{e(st.row.get(f'step{s.number}_state', ''))}</td>" for s in steps)
        score = (f"{st.shown((st.data or {}).get('score_exact'), st.row.get('earned'))} / "
                 f"{st.shown((st.data or {}).get('max_score_exact'), st.row.get('maximum'))}" if st.earned is not None else "–")
        body.append(f'<tr><td>{link(st)}</td><td class="n" data-score="{e(st.name)}">{e(score)}</td>'
                    f'<td class="n">{e(st.row.get("percent", ""))}</td><td>{e(st.row.get("status", ""))}'
                    f'{" — " + e(st.row["note"]) if st.row.get("note") else ""}</td>{cells}</tr>')
    body.append("</table>")

    # the student pages
    target_students = out / "students"
    out.mkdir(parents=True, exist_ok=True)
    tmp = out / f".students.{time.time_ns()}"
    tmp.mkdir()
    by_student = defaultdict(dict)
    for (name, number), fm in matches.items():
        by_student[name][number] = fm
    for st in g.students:
        (tmp / f"{st.page}.html").write_text(student_page(st, steps, by_student.get(st.name, {})), encoding="utf-8")
    shutil.rmtree(target_students, ignore_errors=True)
    tmp.replace(target_students)
    body.append(f"<p><small>Written in {time.monotonic() - start:.1f} s by <code>./kit report</code>.</small></p>")
    atomic.write(out / "index.html", page("Class report", body))
    return {"students": len(g.students), "notes": notes, "pairs": [(p.a, p.b, p.score) for p in sim.pairs],
            "copies": sim.copies, "fits": {k: v for k, v in fits.items()}, "matches": matches}



def similar_section(sim, names: dict) -> list[str]:
    """The similar submissions' section (after its heading): the files set aside, the groups, the pairs."""
    def who(n: str) -> str:
        return link(names[n]) if n in names else e(n)

    body = [f"<p>Compared with Debian's similarity-tester (<code>sim_c++</code>: layout, comments and "
            f"identifiers' names do not count), step file by step file, with the stub's lines and the "
            f"#include lines left out: {sim.compared} submissions. A file made for {similar.REFERENCE_LIKE} % "
            f"or more of the reference answer's material (today's or an older text of it: "
            f"{sum(sim.versions.values())} versions of {len(sim.versions)} files) is a copy of the solutions, "
            f"one made for as much of an older stub is unfinished; both are set aside, and two such files are not "
            f"compared.</p>",
            f"<p><b>Copies of the solutions</b> (every file compared is {similar.REFERENCE_LIKE} % or more "
            f"the reference; they resemble each other through it, which says nothing): {len(sim.copies)}"
            f"{': ' + ', '.join(who(n) for n in sim.copies) if sim.copies else ''}.</p>"]
    aside = [g for g in sim.groups if g.source and g.share >= similar.REFERENCE_LIKE]
    shared = [g for g in sim.groups if g not in aside]
    if sim.groups:
        body.append(f"<p><b>Shared files</b>: a file that {similar.GROUP_MIN} or more students hand in the same "
                    f"(comments and layout aside, or {similar.GROUP_SAME} % both ways) is one group, not a pair "
                    f"of each two of them. Pairs below count only what two students share beyond their groups.</p>")
    if shared:
        body.append("<p>Made of no version of the reference or the stub: ask where each came from (an older "
                    "handout, a web page, a tutor).</p><table><tr><th>file</th><th>students</th><th>texts</th>"
                    "<th>made of</th></tr>")
        for g in shared:
            made = f"{g.share} % {e(g.source)}" if g.source else "no version of the reference or stub"
            body.append(f'<tr data-group="{e(g.key)}"><td>{e(g.key)}</td><td>{len(g.members)}: '
                        f'{", ".join(who(n) for n in g.members)}</td><td class="n">{g.texts}</td><td>{made}</td></tr>')
        body.append("</table>")
    for g in aside:
        body.append(f'<details data-group="{e(g.key)}"><summary>{e(g.key)}: {len(g.members)} students hand in '
                    f"{g.share} % {e(g.source)} ({g.texts} text{'s' if g.texts != 1 else ''}; set aside)</summary>"
                    f'<p>{", ".join(who(n) for n in g.members)}</p></details>')
    if sim.pairs:
        body.append(f"<p>{len(sim.pairs)} pairs share {similar.SHOWN} % or more of a file, every one listed, "
                    f"the most alike first.</p>"
                    "<table><tr><th>rank</th><th>submissions</th><th>share</th><th>files (A in B / B in A)</th></tr>")
        for i, p in enumerate(sim.pairs, 1):
            files = "<br>".join(f"{e(k)}: {a} % / {b} %" for k, (a, b) in sorted(p.files.items()))
            body.append(f'<tr data-pair="{e(p.a)}|{e(p.b)}"><td class="n">{i}</td><td>{who(p.a)} and '
                        f"{who(p.b)}</td><td class=\"n\">{p.score} %</td><td>{files}</td></tr>")
        body.append("</table>")
        for p in sim.pairs[:3]:
            body.append(f"<h3>{e(p.a)} and {e(p.b)}: {e(p.best)}, the matching runs</h3>")
            for (a0, a1), (b0, b1), tokens in p.runs[:4]:
                left = "\n".join(p.lines[0][a0 - 1:min(a1, a0 - 1 + RUN_LINES)])
                right = "\n".join(p.lines[1][b0 - 1:min(b1, b0 - 1 + RUN_LINES)])
                body.append(f"<p>{tokens} tokens: lines {a0}–{a1} and {b0}–{b1}</p><div class=\"pair\">"
                            f"<pre>{e(left)}</pre><pre>{e(right)}</pre></div>")
    else:
        body.append(f"<p>No pair of submissions shares {similar.SHOWN} % or more outside the reference and the "
                    f"groups.</p>")
    return body

# --- a student's page ------------------------------------------------------------------------------

def student_page(st, steps, matches: dict) -> str:
    body = [f"<h1>{e(st.name)}: your results</h1>"]
    if st.data is None:
        status = st.row.get("status", "")
        if status in NOTHING_SUBMITTED_STATES:      # the student's: no file of a step was found or could be read
            body.append(f"<p>Nothing submitted: {e(st.row.get('note', '') or 'no step files were found in the upload')}"
                        f" Your score is 0 of {e(st.row.get('maximum', ''))}.</p>")
        else:
            body.append(f"<p>Your submission was not graded: {e(status)}. {e(st.row.get('note', ''))}</p>")
        return page(f"{st.name}: results", body)
    earned = st.shown(st.data.get("score_exact"), st.data.get("score"))       # as the CSV writes it
    maximum = st.shown(st.data.get("max_score_exact"), st.data.get("max_score"))
    missed = results_record.not_graded(st.data)
    if missed:      # no total: it would read as the student's; each step the grader failed, and why
        body.append(f'<p class="total" data-earned="" data-maximum="{e(maximum)}"><b>Not graded yet</b>: the '
                    f"grader could not check {len(missed)} step(s), its fault, not yours; no points were taken "
                    "for them, and your instructor will grade them again.</p><ul>"
                    + "".join(f"<li>Step {e(n)}: {e(why)}</li>" for n, why in missed) + "</ul>")
    else:
        extra, possible = results_record.extra_credit(st.data)
        total = Fraction(st.data["score_exact"]) if st.data.get("score_exact") else None
        said = (f"<b>{e(st.shown(course_file.exact_text(total - extra)))} of {e(maximum)}</b> + "
                f"{e(st.shown(course_file.exact_text(extra)))} extra credit (of {e(st.shown(course_file.exact_text(possible)))} "
                f"possible), {e(earned)} in all" if possible and total is not None else f"<b>{e(earned)} of {e(maximum)}</b>")
        body.append(f'<p class="total" data-earned="{e(earned)}" data-maximum="{e(maximum)}">Your score: '
                    f"{said} on the course's scale ({e(course_file.load().scale_words())}).</p>")
    rows = []
    for res in st.steps():
        rob = res.get("robust", {})
        if res.get("state") in (NOT_GRADED, OLD_BROKEN):
            rows.append(f'<tr><td>{e(res.get("step"))} {e(res.get("title", ""))}</td><td class="state-not_graded">'
                        f'not graded</td><td class="n">— / {e(st.shown(res.get("maximum_exact"), res.get("maximum")))}</td>'
                        '<td class="n">—</td></tr>')
            continue
        rows.append(f'<tr><td>{e(res.get("step"))} {e(res.get("title", ""))}</td>'
                    f'<td class="state-{e(res.get("state"))}">{e(STATE_WORDS.get(res.get("state"), res.get("state")))}</td>'
                    f'<td class="n">{e(st.shown(res.get("earned_exact"), res.get("earned")))} / '
                    f'{e(st.shown(res.get("maximum_exact"), res.get("maximum")))}</td>'
                    f'<td class="n">{e(rob.get("passed", 0))} / {e(rob.get("total", 0))}</td></tr>')
    body.append("<h2>Scoreboard</h2><table><tr><th>step</th><th>state</th><th>points</th><th>★ robust</th></tr>"
                + "".join(rows) + "</table>")
    if matches:
        body.append('<h2>Slips that fit your failing cases</h2><p class="note">This is not a verdict: the kit '
                    "knows some common slips and which cases each one fails. Your failing cases look like the "
                    "slip below; it may be something else. Read the lecture section it names.</p><ul>")
        for number, (fails, m) in sorted(matches.items()):
            if m.kind == "none":
                body.append(f"<li>Step {e(number)}: your failing cases fit none of the slips the kit knows.</li>")
                continue
            how = "exactly" if m.kind == "exact" else f"nearly ({m.distance} case{'s' if m.distance > 1 else ''} differ)"
            if len(m.signatures) > 1:
                how += f", as do {len(m.signatures)} slips that fail the same cases"
            slips = "; or: ".join(f"{e(s.slip)} (lecture section: {e(s.lecture)})" for s in m.signatures)
            body.append(f"<li>Step {e(number)}: fits {how}: {slips}</li>")
        body.append("</ul>")
    for res in st.steps():
        state = res.get("state")
        tiers = {"basic": 0, "hidden": 1, "robust": 2}
        # The counted cases first, then those that are not (★: extra credit or optional), issue 55.
        bad = sorted((c for c in res.get("cases", []) if c.get("status") != PASS),
                     key=lambda c: (not case_worth(course_file.load(), res["step"], c)[0], tiers.get(c.get("tier"), 3)))
        if state == NO_COMPILE:
            body.append(f"<h2>Step {e(res['step'])}: does not compile</h2><pre>{e(res.get('detail', '')[:4000])}</pre>")
            continue
        if state in (NOT_STARTED, MISSING, WAITING, NOT_GRADED, OLD_BROKEN, DONE) and not (state == DONE and bad):
            continue
        body.append(f"<h2>Step {e(res['step'])}: {len(bad)} case(s) to look at</h2>")
        drawn = 0
        for c in bad:
            hidden = c.get("tier") == "hidden"
            mark = {"robust": " ★", "hidden": " (hidden)"}.get(c.get("tier"), "")
            _, worth = case_worth(course_file.load(), res["step"], c)
            body.append(f"<h3>{e(c['name'])}{e(mark)}: {e(STATUS_WORDS.get(c.get('status'), c.get('status')))} "
                        f"<span class=\"note\">(weight → points: {e(worth)})</span></h3>")
            if hidden:
                body.append(f"<p>{e(course_file.hidden_note())}</p>")
                continue
            for msg in (c.get("messages") or [])[:2]:
                body.append(f"<pre>{e(msg[:3000])}</pre>")
            if c.get("lecture"):
                body.append(f"<p>Read the lecture's section “{e(c['lecture'])}”.</p>")
            if drawn < PICTURES_PER_STEP and c.get("figure"):
                pic = draw_case(c, f"Step {res['step']} · {c['name']}")
                if pic:
                    body.append(pic)
                    drawn += 1
    return page(f"{st.name}: results", body)

"""The report's pages: DIR/index.html (the class, for the instructor) and DIR/students/NAME.html.

Plain HTML and CSS, no script: every chart and picture is an SVG inside the page (a data: URL), so
the folder reads offline, prints, and can be sent as it is. A student's page is made from that
student's results alone and names no other student.

The data is gathered here; the markup is in templates/ (jinja2, Debian's python3-jinja2: the
instructor's side only, never imported by a student's command). Every value a template writes is
escaped as HTML (autoescape) after common.printable() showed its control characters: a student's
name, output, code and file names reach these pages.
"""

from __future__ import annotations

import base64
import re
import shutil
import sys
import time
from collections import Counter, defaultdict
from fractions import Fraction
from pathlib import Path

from raykit import atomic
from raykit import course as course_file
from raykit import picture
from raykit import record as results_record
from raykit.common import KitError, load_steps, prerequisites, printable
from raykit.status import NOTHING_SUBMITTED_STATES, NOT_GRADED, OLD_BROKEN, CRASHED, DONE, MISSING, NO_COMPILE, NOT_STARTED, PARTIAL, PASS, SETUP, STATE_WORDS, STATUS_WORDS, THREW, TIMED_OUT, NO_ANSWER, WAITING
from . import grading as grading_mod
from . import plots, signatures, similar

MOST_FAILED = 3             # cases drawn beside the table
PICTURES_PER_STEP = 8       # on a student's page
RUN_LINES = 40              # lines of a matching run shown side by side
TEMPLATES = Path(__file__).resolve().parent / "templates"

STATE_COLOURS = [(DONE, "#2e7d32"), (PARTIAL, "#f2a900"), (NOT_STARTED, "#9e9e9e"), (NO_COMPILE, "#c62828"),
                 (MISSING, "#6d4c41"), (WAITING, "#90a4ae"), (NOT_GRADED, "#f9a825")]

NOT_A_VERDICT = ("This list is not a verdict on any student: a set of failing cases can fit a slip by chance, "
                 "and a slip can be made in ways no mutant has. It is a map of what the class may have "
                 "misunderstood, to look at and teach from.")


def _jinja():
    """jinja2, from the Python running the kit or, where that is not Debian's own (pyenv, a venv),
    from Debian's python3-jinja2 (pure Python; markupsafe's own fallback where its compiled part is
    for another Python)."""
    try:
        import jinja2
        return jinja2
    except ImportError:
        pass
    debian = Path("/usr/lib/python3/dist-packages")
    if (debian / "jinja2").is_dir() and str(debian) not in sys.path:
        sys.path.append(str(debian))
        return _jinja()
    raise KitError("./kit report needs jinja2: sudo apt-get install python3-jinja2", SETUP)


_ENV = None


def templates():
    """The pages' templates, autoescaped. Each value is shown by printable() first; markup the kit made
    (a macro's, an SVG's data) passes as it is."""
    global _ENV
    if _ENV is None:
        jinja2 = _jinja()
        from markupsafe import Markup

        def shown(value):
            if isinstance(value, Markup):
                return value
            return printable(str(value))

        _ENV = jinja2.Environment(loader=jinja2.FileSystemLoader(str(TEMPLATES)), autoescape=True,
                                  finalize=shown, undefined=jinja2.StrictUndefined, trim_blocks=True,
                                  lstrip_blocks=True)
    return _ENV


def render(template: str, **data) -> str:
    return templates().get_template(template).render(**data) + "\n"


def failing_basic(step: dict) -> frozenset:
    return frozenset(c["name"] for c in step.get("cases", []) if c.get("tier") == "basic" and c.get("status") != PASS)


def base64_svg(svg: str) -> str:
    return base64.b64encode(svg.encode("utf-8")).decode("ascii")


def draw_case(case: dict, title: str) -> dict | None:
    """A case's picture: {"data": the SVG in base64, "line": what it shows, in words}, or None."""
    figure = case.get("figure")
    if not isinstance(figure, dict):
        return None
    try:
        svg, line = picture.render(figure, title)
    except (picture.PictureError, KeyError, TypeError, ValueError, ZeroDivisionError):
        return None
    return {"data": base64_svg(svg), "line": line}


# --- what the class did ----------------------------------------------------------------------------

def analyse(g, sigs):
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
    out = {section: defaultdict(list) for section in ("Does not compile", "Crashed", "Threw an exception", "Timed out",
                                                      "Run again after a timeout", "Not graded", "Nothing submitted")}
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


def step_counts(graded, steps):
    """Per step: how many students are in each state, how many had a case crash, time out or throw (the
    ★ cases aside), and of those done, how many passed every ★ case (and of how many that had some)."""
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
    return counts, extra, robust


def case_rates(graded, steps, course) -> list[dict]:
    """Each case of each step that ran: how many students whose step ran (partial or done) failed it."""
    rows = []
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
            counted, shown = worth[name]
            rows.append({"rate": failed[name] / ran[name], "step": s, "lecture": lecture[name], "name": name,
                         "tier": tier[name], "failed": failed[name], "ran": ran[name], "example": example.get(name),
                         "counted": counted, "worth": shown})
    return rows


def case_tables(case_rows, steps) -> list[dict]:
    """Per step, its failed cases by lecture section (the most-failed section first): the counted cases
    first, then the ★ ones (extra credit or optional) — issue 55: the ★ cases, failed more often, stood
    above the ones that make the grade."""
    tables = []
    for s in steps:
        mine = [r for r in case_rows if r["step"] is s]
        if not mine:
            continue
        groups = []
        for counted in (True, False):
            by_lecture = defaultdict(list)
            for r in mine:
                if r["failed"] and r["counted"] == counted:
                    by_lecture[r["lecture"]].append(r)
            if by_lecture:
                groups.append((counted, [(lec, sorted(rs, key=lambda r: -r["rate"])) for lec, rs in
                                         sorted(by_lecture.items(), key=lambda kv: -max(r["rate"] for r in kv[1]))]))
        tables.append({"step": s, "groups": groups, "passed_by_all": sum(1 for r in mine if not r["failed"]),
                       "cases": len(mine)})
    return tables


def slip_fits(matches, sigs):
    """The students whose failing basic cases fit a slip, per (step, the slip's cases), exactly or nearly;
    and the patterns that fit none, per (step, cases)."""
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
    rows = [{"step": key[0], "group": by_sig[key], "exact": [n for n, k, _ in fits[key] if k == "exact"],
             "near": [(n, d) for n, k, d in fits[key] if k == "near"]}
            for key in sorted(fits, key=lambda k: (k[0], -len(fits[k])))]
    return fits, rows, unmatched


def build(folder: Path, out: Path) -> dict:
    start = time.monotonic()
    g = grading_mod.load(folder)
    steps = load_steps()
    sigs, notes = signatures.load()
    notes = g.problems + notes
    shown_notes = list(notes)
    matches = analyse(g, sigs)
    names = {st.name: st for st in g.students}
    graded = [st for st in g.students if st.data is not None]
    ungraded = [st for st in g.students if st.row.get("status") in ("not graded", "timed out")]
    course = course_file.load()

    # 1. scores
    scores = class_scores(g)
    percents = scores["percents"]
    if percents:
        srt = sorted(percents)
        scores.update(median=srt[len(srt) // 2], lowest=srt[0], highest=srt[-1])
    counts, extra, robust = step_counts(graded, steps)
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
    state_rows = [{"step": s, "counts": [counts[s.number][k] for k, _ in STATE_COLOURS],
                   "crashed": extra[s.number][CRASHED], "timed_out": extra[s.number][TIMED_OUT],
                   "robust": f"{robust[s.number][0]} of {robust[s.number][1]}" if robust[s.number][1] else "–"}
                  for s in steps]

    # 2. cases by failure rate
    star = ("★ cases are extra credit, on top of a step's points" if course.extra_credit("robust")
            else "★ cases are optional and count for nothing" if course.optional("robust")
            else "★ cases count like the others")
    case_rows = case_rates(graded, steps, course)
    # The pictures: the most-failed basic cases, the same for every student (a hidden case is a set of
    # random draws, and fails more often for having more of them; it is in the tables below).
    top = sorted((r for r in case_rows if r["failed"] and r["tier"] == "basic"),
                 key=lambda r: (-r["rate"], r["step"].number, r["name"]))[:MOST_FAILED]
    for r in top:
        r["picture"] = draw_case(r["example"], f"Step {r['step'].number} · {r['name']}") if r["example"] else None

    # 3. slips
    fits, fit_rows, unmatched = slip_fits(matches, sigs)
    step_of = {s.number: s for s in steps}

    def upstream(name: str, number: str) -> str:
        st = names[name]
        needs = prerequisites(step_of[number], steps) if number in step_of else []
        return "*" if any((st.step(p.number) or {}).get("state") != DONE for p in needs) else ""

    unmatched_rows = [{"step": number, "who": [(n, upstream(n, number)) for n in who], "cases": sorted(fails)[:12],
                       "more": max(len(fails) - 12, 0)}
                      for (number, fails), who in sorted(unmatched.items(), key=lambda kv: (kv[0][0], -len(kv[1])))]

    # 4. incidents
    found = [(section, sorted(kinds.items(), key=lambda kv: -len(kv[1]))) for section, kinds in incidents(g).items()]

    # 5. similar submissions
    sim = similar.compare(g.files, [st.name for st in graded], steps)
    if not sim.available:
        notes.append(f"similar submissions not compared: {sim.note}")

    # 6. the students
    student_rows = [{"st": st, "score": (f"{st.shown((st.data or {}).get('score_exact'), st.row.get('earned'))} / "
                                         f"{st.shown((st.data or {}).get('max_score_exact'), st.row.get('maximum'))}"
                                         if st.earned is not None else "–")} for st in g.students]

    # the student pages
    target_students = out / "students"
    out.mkdir(parents=True, exist_ok=True)
    tmp = out / f".students.{time.time_ns()}"
    tmp.mkdir()
    by_student = defaultdict(dict)
    for (name, number), fm in matches.items():
        by_student[name][number] = fm
    for st in g.students:
        (tmp / f"{st.page}.html").write_text(student_page(st, by_student.get(st.name, {})), encoding="utf-8")
    shutil.rmtree(target_students, ignore_errors=True)
    tmp.replace(target_students)

    index = render("index.html.j2", title="Class report", students=g.students, names=names,
                   graded_count=len(graded) - sum(st.data is not None for st in ungraded), not_graded=len(ungraded),
                   csv_path=g.csv_path, written=time.strftime('%Y-%m-%d %H:%M'), notes=shown_notes,
                   scores=scores, scale_words=course.scale_words(), charts=[base64_svg(x) for x in svgs], charts_why=why,
                   state_words=[STATE_WORDS[k] for k, _ in STATE_COLOURS], state_rows=state_rows, star=star,
                   top=top, case_tables=case_tables(case_rows, steps), not_a_verdict=NOT_A_VERDICT,
                   mutants=len(sigs), fits=fit_rows, unmatched=unmatched_rows, incidents=found,
                   **similar_data(sim), steps=steps, student_rows=student_rows, elapsed=time.monotonic() - start)
    atomic.write(out / "index.html", index)
    return {"students": len(g.students), "notes": notes, "pairs": [(p.a, p.b, p.score) for p in sim.pairs],
            "copies": sim.copies, "fits": {k: v for k, v in fits.items()}, "matches": matches}


def similar_data(sim) -> dict:
    """What the similar submissions' section shows: the groups set aside (a version of the reference)
    and the others, and the first pairs' matching runs side by side."""
    aside = [g for g in sim.groups if g.source and g.share >= similar.REFERENCE_LIKE]
    runs = [{"pair": p, "shown": [(tokens, a0, a1, b0, b1, "\n".join(p.lines[0][a0 - 1:min(a1, a0 - 1 + RUN_LINES)]),
                                   "\n".join(p.lines[1][b0 - 1:min(b1, b0 - 1 + RUN_LINES)]))
                                  for (a0, a1), (b0, b1), tokens in p.runs[:4]]}
            for p in sim.pairs[:3]]
    return {"sim": sim, "similar": similar, "aside": aside, "shared": [g for g in sim.groups if g not in aside],
            "runs": runs}


def similar_section(sim, names: dict) -> str:
    """The similar submissions' section alone (after its heading), as the index shows it."""
    return templates().get_template("similar.html.j2").render(names=names, **similar_data(sim))


# --- a student's page ------------------------------------------------------------------------------

def student_page(st, matches: dict) -> str:
    data = {"title": f"{st.name}: results", "st": st, "graded": st.data is not None,
            "nothing_submitted": st.row.get("status", "") in NOTHING_SUBMITTED_STATES}
    if st.data is None:     # nothing submitted (no file of a step found or read) is the student's; else not graded
        return render("student.html.j2", **data)
    course = course_file.load()
    data["earned"] = st.shown(st.data.get("score_exact"), st.data.get("score"))       # as the CSV writes it
    data["maximum"] = st.shown(st.data.get("max_score_exact"), st.data.get("max_score"))
    data["scale_words"] = course.scale_words()
    data["missed"] = results_record.not_graded(st.data)
    data["extra"] = None
    if not data["missed"]:
        extra, possible = results_record.extra_credit(st.data)
        total = Fraction(st.data["score_exact"]) if st.data.get("score_exact") else None
        if possible and total is not None:
            data["extra"] = {"base": st.shown(course_file.exact_text(total - extra)),
                             "earned": st.shown(course_file.exact_text(extra)),
                             "possible": st.shown(course_file.exact_text(possible))}
    data["scoreboard"] = [{"step": res.get("step"), "title": res.get("title", ""), "state": res.get("state"),
                           "not_graded": res.get("state") in (NOT_GRADED, OLD_BROKEN),
                           "state_words": STATE_WORDS.get(res.get("state"), res.get("state")),
                           "earned": st.shown(res.get("earned_exact"), res.get("earned")),
                           "maximum": st.shown(res.get("maximum_exact"), res.get("maximum")),
                           "robust_passed": res.get("robust", {}).get("passed", 0),
                           "robust_total": res.get("robust", {}).get("total", 0)} for res in st.steps()]
    data["slips"] = [{"step": number, "kind": m.kind, "distance": m.distance, "signatures": m.signatures}
                     for number, (fails, m) in sorted(matches.items())]
    shown_steps = []
    tiers = {"basic": 0, "hidden": 1, "robust": 2}
    for res in st.steps():
        state = res.get("state")
        # The counted cases first, then those that are not (★: extra credit or optional), issue 55.
        bad = sorted((c for c in res.get("cases", []) if c.get("status") != PASS),
                     key=lambda c: (not case_worth(course, res["step"], c)[0], tiers.get(c.get("tier"), 3)))
        if state == NO_COMPILE:
            shown_steps.append({"step": res["step"], "detail": res.get("detail", "")[:4000]})
            continue
        if state in (NOT_STARTED, MISSING, WAITING, NOT_GRADED, OLD_BROKEN, DONE) and not (state == DONE and bad):
            continue
        cases, drawn = [], 0
        for c in bad:
            shown = {"name": c["name"], "mark": {"robust": " ★", "hidden": " (hidden)"}.get(c.get("tier"), ""),
                     "status_words": STATUS_WORDS.get(c.get("status"), c.get("status")),
                     "worth": case_worth(course, res["step"], c)[1], "hidden": c.get("tier") == "hidden",
                     "messages": [m[:3000] for m in (c.get("messages") or [])[:2]], "lecture": c.get("lecture"),
                     "picture": None}
            if not shown["hidden"] and drawn < PICTURES_PER_STEP and c.get("figure"):
                shown["picture"] = draw_case(c, f"Step {res['step']} · {c['name']}")
                drawn += shown["picture"] is not None
            cases.append(shown)
        shown_steps.append({"step": res["step"], "detail": None, "cases": cases})
    data["steps"] = shown_steps
    data["hidden_note"] = course_file.hidden_note()
    return render("student.html.j2", **data)

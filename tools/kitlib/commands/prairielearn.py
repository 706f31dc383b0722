"""./kit prairielearn OUT --image USER/NAME: what a course adds to its PrairieLearn repository to grade the
kit's steps, ready to sync.

    OUT/questions/raykit/NN_topic/    one externally graded question per step: info.json (gradingMethod
                                      External, externalGradingOptions), question.html (the task rendered
                                      for PrairieLearn by taskpage.py, the scale, the hidden cases, the
                                      headers it implements, the hints, a <pl-file-editor> per step file
                                      pre-filled with the stub), the stubs, the task's figures in
                                      clientFilesQuestion/, tests/grade.py (the entry point)
    OUT/courseInstances/INSTANCE/infoCourseInstance.json
                                      the course instance (uuid from its name, published from today
                                      until 180 days after the due date, course.json's timezone); not
                                      written when --course DIR already has courseInstances/INSTANCE/
    OUT/questions/raykit/NN_topic_extra_credit/
                                      a step's extra-credit cases (course.json: a group's "extra_credit"),
                                      a question of their own worth those points: PrairieLearn's bonus
                                      points come from questions above the assessment's maxPoints
    OUT/courseInstances/INSTANCE/assessments/raykit/infoAssessment.json
                                      the assessment: one zone, a question per step worth the step's
                                      points on course.json's scale and one per step's extra credit
                                      (maxPoints the steps' points, maxBonusPoints the extra credit), and
                                      access rules from course.json's due date: full credit until it,
                                      then open to read and closed to submissions (without one: full
                                      credit while the instance is published)
    OUT/serverFilesCourse/raykit/     the instructor's kit, solutions included: students never see
                                      serverFilesCourse, so the hidden cases run
    OUT/serverFilesCourse/raykit-bundle/
                                      the kit's side prebuilt for the image (tools/raykit/bundle.py: the
                                      judges, the reference, the hidden cases), filled by graders/raykit/
                                      build.sh (tools/prairielearn/prebuild.py run in the image): private,
                                      as the kit is; until then it holds a README and each job builds its own
    OUT/graders/raykit/Dockerfile     the grading image (tools/prairielearn/Dockerfile): public, the toolchain
                                      alone (its build context holds nothing else); build.sh, which builds it
                                      and then the bundle with it; README.md: how to build it for
                                      linux/amd64, push it under --image and sync the course
    OUT/infoCourse.json               with --new-course NAME, a whole course's (OUT is then its repository):
                                      the topic and tags the questions use declared; with --course DIR,
                                      DIR's own with those it lacks added (copy it over DIR's)
    OUT/README-raykit.md              what to copy, and the lines to add to the course's infoCourse.json:
                                      the topic and tags the questions use (PrairieLearn wants them
                                      declared there), also printed; with --course DIR only those DIR's
                                      infoCourse.json lacks

Each question's page also shows the definitions its functions take (the kit's headers the step's
contract includes, read from include/raykit/: Ray, Roots, Sphere, Rect, Camera, Canvas, Scene, ...),
the scene of a step whose contract has one (include/raykit/scenes/NAME.inc, as lecture 05's tables
give it), and its lecture: a link into the docs site `./kit docs` builds when --docs-url says where
it is hosted, else the lecture's file named as plain text.

The entry point runs tools/prairielearn/grade.py from the copied kit (`./kit check NN --steps ...
--prairielearn FILE`) and writes /grade/results/results.json as PrairieLearn reads it. Copy OUT's
folders into the course repository (questions/raykit/ may go under any questions/ subfolder if the
assessment's ids follow).
"""

from __future__ import annotations

import html
import importlib.util
import json
import re
import shutil
import uuid
from datetime import date, datetime, timedelta
from pathlib import Path

from fractions import Fraction

from raykit import course as course_file
from raykit import secret
from raykit.checking import recorded_cases
from raykit.common import ROOT, KitError, load_steps, say, writable_parent
from raykit.kitfiles import kit_files, platform_excluded as not_shipped
from raykit.plresults import HIDDEN_NOTE
from raykit.status import OK
from ..taskpage import FIGURE_URL, Page, kit_paths_out as for_prairielearn, task_html
from ..webtools import page_id

# The job's budget. Measured with `sudo tools/portability/reach prairielearn --step NN --root trixie`: the
# grading image built from its Dockerfile in a debootstrap root, a cold job (a fresh copy of the kit, no
# build folder, an empty cache) at /grade under PrairieLearn's limits (cgroup v1: 0.9 CPU, 2 GiB, 1024
# pids; no network), on the shared 2-core build machine (2026-12-03):
#   step 05 (the slowest: it links step 04's reference)  25.8 s of CPU, 72 s of wall time at a load of 9
#   step 02                                              22.0 s of CPU, 112 s of wall time at a load of 15
# Alone on a CPU the quota makes a job last its CPU time / 0.9, about 29 s; the wall times above are a
# machine shared by seven times more work than it has cores. Earlier, on the host at a load of 0.2 to 1:
# step 05 12.5 to 14.5 s. The timeout covers the worst wall time measured with a margin (1.6 times it,
# 6 times a job alone); RAYKIT_BUDGET, 10 s less, makes the kit stop first and write "not gradable"
# (no attempt lost) rather than let PrairieLearn kill the job (a failure the student sees).
# Those jobs built the kit's side themselves. With it prebuilt (graders/raykit/build.sh, prebuild.py) a job
# compiles only the student's files: step 05's solution took 2.0 to 2.7 s of CPU and steps 01-04 under 1 s
# (the self-test's /grade layout without Docker, an empty cache, both isolations, load 9 to 14, 2026-12-07);
# the timeout still covers a job whose bundle does not match and is built in it.
MEASURED_SECONDS = {"05": (25.8, 72), "02": (22.0, 112)}     # step: (CPU seconds, wall seconds), cold, loaded
TIMEOUT = 180
NAMESPACE = uuid.UUID("6f1c2d8e-4b0a-4f5e-9a43-72a1c0de5b1e")   # the kit's: uuids stay the same per step
ENTRY = '''#!/usr/bin/env python3
"""PrairieLearn's entry point for step {number}: the kit in /grade/serverFilesCourse/raykit grades it."""
import os
import sys

GRADE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))     # /grade in PrairieLearn's job
GRADER = "/grade/serverFilesCourse/raykit/tools/prairielearn/grade.py".replace("/grade", GRADE, 1)
os.execv(sys.executable, [sys.executable, GRADER, "{number}", GRADE{part}])
'''
BUNDLE_FOLDER = "raykit-bundle"     # serverFilesCourse/raykit-bundle/: the kit's side, prebuilt (prebuild.py)
BUNDLE_PLACEHOLDER = """# The kit's side, prebuilt for the grading image (private): not built yet

`graders/raykit/build.sh` builds the grading image and then, in it, the kit's side into this folder
(tools/prairielearn/prebuild.py). Until then each job builds it itself (about 20 s of CPU more a job)
and its results say so ("built": "kit side built in this job").
"""


def register(p) -> None:
    p.add_argument("out", metavar="OUT", help="an empty or new folder to write the questions, the assessment, the kit and the image into")
    p.add_argument("--image", required=True, metavar="USER/NAME",
                   help="the grading image's Docker Hub name, as you will push it (e.g. yourname/raykit-grader): "
                        "every info.json names it; graders/raykit/README.md says how to build and push it")
    p.add_argument("--instance", default="raykit", metavar="NAME",
                   help="the course instance the assessment goes in: OUT/courseInstances/NAME/assessments/raykit/ "
                        "(default raykit; use your instance's folder name). Its infoCourseInstance.json is written "
                        "too, unless --course DIR has that instance already")
    p.add_argument("--course", metavar="DIR",
                   help="your PrairieLearn course repository (the folder of its infoCourse.json), read only: an "
                        "instance it has is not written again, and only the topic and tags its infoCourse.json "
                        "lacks are listed to add")
    p.add_argument("--new-course", metavar="NAME",
                   help="write a whole course from empty: OUT/infoCourse.json too (NAME is the course's short name, "
                        "e.g. \"CS 419\"), declaring the questions' topic and tags; OUT is then the course's repository")
    p.add_argument("--docs-url", metavar="URL",
                   help="where the docs site ./kit docs builds (build/docs/student/html/) is hosted, "
                        "e.g. https://example.edu/raykit/: each question links its lecture's page there "
                        "(without it, the page names the lecture's file)")
    p.add_argument("--timeout", type=int, default=TIMEOUT,
                   help=f"seconds per grading job (default {TIMEOUT}: 1.6 times the slowest cold job measured under "
                        "PrairieLearn's limits on a loaded machine; at most 600)")


def step_points(step, course) -> tuple[Fraction, Fraction, Fraction, int]:
    """The step's points, the extra credit its cases can add, the points its hidden cases hold and how
    many they are, from its recorded cases (the judge's list, kept current by ./kit check --record;
    the self-test fails while it is stale)."""
    cases = recorded_cases(step)
    if cases is None:
        raise KitError(f"step {step.number}: no tests/{step.folder}/cases.json; run ./kit check {int(step.number)} --record")
    cases = [c for c in cases if c.tier != "hidden" or course.hidden_enabled]
    groups = [course.group(c.tier, c.name) for c in cases]
    weights = course.weights_of(step.number, [(c.tier, c.name, c.lecture) for c in cases])
    shares = course.shares(step.number, groups, weights)
    bonus = sum((p for p, g in zip(shares, groups) if course.extra_credit(g)), Fraction(0))
    hidden = sum((p for p, g in zip(shares, groups) if g == "hidden"), Fraction(0))
    return course.step_maximum(step.number, groups, weights), bonus, hidden, groups.count("hidden")


def question_id(step, extra: bool = False) -> str:
    """A step's question, or (extra) the question of its extra-credit cases."""
    return f"raykit/{step.folder}" + ("_extra_credit" if extra else "")


# The topic and tags the questions use, as infoCourse.json declares them (PrairieLearn's schema: a
# name and one of its colours each).
TOPIC = {"name": "Ray tracing", "color": "purple1", "description": "raykit: ray tracing, one step at a time"}
TAGS = [{"name": "raykit", "color": "purple2", "description": "a step of the raykit ray-tracing kit"},
        {"name": "c++", "color": "gray1", "description": "written in C++"},
        {"name": "externally graded", "color": "gray2", "description": "graded in a Docker image of its own"}]


def step_tag(step) -> dict:
    return {"name": f"step{step.number}", "color": "blue1", "description": f"raykit step {step.number}: {step.title}"}


def declarations(steps) -> dict[str, list[dict]]:
    """What infoCourse.json must declare for the questions: {"topics": [...], "tags": [...]}."""
    return {"topics": [TOPIC], "tags": TAGS[:1] + [step_tag(s) for s in steps] + TAGS[1:]}


def info_json(step, image: str, timeout: int, extra: bool = False) -> dict:
    return {
        "uuid": str(uuid.uuid5(NAMESPACE, question_id(step, extra))),
        "title": f"raykit step {step.number}" + (" ★ extra credit" if extra else "") + f": {step.title}",
        "topic": TOPIC["name"],
        "tags": [TAGS[0]["name"], step_tag(step)["name"]] + [t["name"] for t in TAGS[1:]],
        "type": "v3",
        "singleVariant": True,
        "gradingMethod": "External",
        "externalGradingOptions": {
            "image": image,
            "entrypoint": "/grade/tests/grade.py",
            "serverFilesCourse": ["raykit/", f"{BUNDLE_FOLDER}/"],
            "timeout": timeout,
            "environment": {"RAYKIT_BUDGET": str(max(timeout - 10, 10))},
        },
    }


def pl_number(value: Fraction) -> int | float:
    """Points for PrairieLearn, which multiplies them by each job's score: whole as they are, else to 6
    decimals (not the course's 2, which would make the questions' sum drift from the exact total)."""
    return value.numerator if value.denominator == 1 else round(float(value), 6)


def assessment_json(steps, course, points: dict) -> dict:
    """The assessment: a question per step, worth its points on the course's scale, and one for each
    step's extra credit, worth those points. PrairieLearn's way with bonus points (its docs, "Assessment
    points"): maxPoints, the steps' points, make 100 %; maxBonusPoints, the extra credit, may be earned
    above it, from questions of their own (a question's score is 0 to 100 % of its points, so a step's
    question cannot hold its bonus without a complete step reading as less than 100 %)."""
    maximum = sum((points[s.number][0] for s in steps), Fraction(0))
    bonus = sum((points[s.number][1] for s in steps), Fraction(0))
    data = {
        "uuid": str(uuid.uuid5(NAMESPACE, "raykit/assessment")),
        "type": "Homework",
        "title": "raykit: ray tracing, one step at a time",
        "set": "Homework",
        "number": "1",
        "text": html.escape(f"Each question is one step of the kit, worth its points on the course's scale "
                            f"({course.scale_words()}); Save & Grade runs its cases.", quote=False),
        "maxPoints": pl_number(maximum),
        "zones": [{"title": "The steps",
                   "questions": [{"id": question_id(s, extra), "autoPoints": pl_number(points[s.number][extra]),
                                  "maxAutoPoints": pl_number(points[s.number][extra])}
                                 for s in steps for extra in (False, True) if not extra or points[s.number][1]]}],
    }
    if bonus:
        data["maxBonusPoints"] = pl_number(bonus)
    data["allowAccess"] = access_rules(course)
    return data


def access_rules(course) -> list[dict]:
    """The assessment's access rules (PrairieLearn's allowAccess, dates in the instance's timezone):
    full credit until course.json's due date, then open to read, closed to submissions; without a due
    date, full credit whenever the course instance is published."""
    if not course.due_date:
        return [{"comment": "course.json gives no due date: full credit while the instance is published",
                 "credit": 100}]
    due = datetime.fromisoformat(course.due_date)
    return [{"comment": "until course.json's due date", "credit": 100, "endDate": course.due_date},
            {"comment": "after it: the work and its grades can be read, nothing submitted",
             "startDate": (due + timedelta(seconds=1)).strftime("%Y-%m-%dT%H:%M:%S"), "active": False}]


def instance_json(name: str, course, today: date) -> dict:
    """A course instance to hold the assessment: published from `today` until 180 days after the due
    date (a year from today without one), in course.json's timezone when it names one."""
    end = (datetime.fromisoformat(course.due_date) + timedelta(days=180) if course.due_date
           else datetime.combine(today, datetime.min.time()) + timedelta(days=365))
    data = {"uuid": str(uuid.uuid5(NAMESPACE, f"raykit/courseInstances/{name}")),
            "longName": name if name != "raykit" else "raykit: ray tracing",
            "comment": "written by raykit's ./kit prairielearn; edit the publishing dates as you like"}
    if course.timezone:
        data["timezone"] = course.timezone
    data["publishing"] = {"startDate": f"{today.isoformat()}T00:00:01",
                          "endDate": end.strftime("%Y-%m-%dT23:59:59")}
    return data


def lecture_words(step, docs_url: str | None = None) -> str:
    """The step's lecture: a link to its page on the hosted docs site, or, without --docs-url (or
    before the lecture is written), its name and file as plain text: never a link to nothing."""
    words = f"lecture {step.number}, <em>{html.escape(step.title)}</em>"
    lecture = ROOT / step.lecture
    if not lecture.is_file():
        return words
    if docs_url:
        href = html.escape(docs_url.rstrip("/") + "/" + page_id(lecture) + ".html")
        return f'<a href="{href}" target="_blank" rel="noopener">{words}</a>'
    return f"{words} (the kit's lecture file <code>{html.escape(lecture.name)}</code>)"


def contract_headers(step) -> list[str]:
    """The raykit headers the step's files include: the contracts of its functions."""
    found = [h for f in step.files
             for h in re.findall(r'#include "(raykit/[a-z_]+\.hpp)"', (ROOT / "steps" / step.folder / f).read_text())]
    return [h for h in dict.fromkeys(found) if h != "raykit/not_implemented.hpp"]


def shared_headers(contracts: list[str]) -> list[str]:
    """The kit's headers the contracts include, at any depth, each after those it includes: where the
    types the step's functions take (Ray, Roots, Sphere, Rect, Camera, Canvas, Scene, ...) are defined."""
    found: list[str] = []

    def visit(h: str) -> None:
        for inc in re.findall(r'^#include "(raykit/[a-z_]+\.hpp)"', (ROOT / "include" / h).read_text(), re.M):
            if inc not in found and inc not in contracts:
                visit(inc)
                if inc not in found:
                    found.append(inc)
    for h in contracts:
        visit(h)
    return found


def defined_names(header: str) -> list[str]:
    """The types and functions a kit header defines or declares, for the line that introduces it."""
    code = re.sub(r"//.*", "", (ROOT / "include" / header).read_text())
    names = re.findall(r"^\s*(?:struct|class)\s+(\w+)\s*[:{]|^\s*using\s+(\w+)\s*=|"
                       r"^(?:inline\s+)?[\w:<>]+[&*]?\s+(\w+)\([^;]*\)\s*[{;]", code, re.M)
    return [n for group in names for n in group if n]


def scene_html(contracts: list[str]) -> str:
    """The scene of a contract that has one (include/raykit/scenes/NAME.inc beside raykit/NAME.hpp), as
    lecture 05's tables give it (docs/scene_tables.py writes those tables from the same file)."""
    parts = []
    for h in contracts:
        inc = ROOT / "include" / "raykit" / "scenes" / (Path(h).stem + ".inc")
        if not inc.is_file():
            continue
        spec = importlib.util.spec_from_file_location("raykit_scene_tables", ROOT / "docs" / "scene_tables.py")
        tables = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(tables)
        try:
            blocks = tables.blocks(tables.read(inc))
        except tables.SceneError as e:
            raise KitError(f"{inc.relative_to(ROOT)}: {e}")
        page = Page(inc)
        parts += ["<h4>The scene</h4>",
                  f"<p>The numbers your <code>{html.escape(Path(h).stem)}</code> model takes, from the kit's scene "
                  f"file <code>{html.escape(inc.name)}</code> (the lecture's tables are written from it). The objects, "
                  "in list order, each as a <code>Rect</code> (axis, offset, lo, hi: its definition is below) with its "
                  "colour:</p>",
                  page.render(blocks["rects"].splitlines()),
                  "<p>The colours (red, green, blue):</p>", page.render(blocks["colors"].splitlines()),
                  page.render(blocks["camera"].splitlines())]
    return "\n".join(parts)


def hints_html(step) -> str:
    path = ROOT / "tests" / step.folder / "hints.md"
    if not path.is_file():
        return ""
    hints = [h.strip() for h in re.split(r"^---\s*$", path.read_text(), flags=re.M) if h.strip()]
    return "\n".join(f'<details><summary>Hint {n}</summary><p style="white-space: pre-line">'
                     f'{html.escape(for_prairielearn(hint), quote=False)}</p></details>'
                     for n, hint in enumerate(hints, 1))


def question_html(step, course, points, docs_url: str | None = None) -> tuple[str, list]:
    """The question's page and the figures to copy beside it (clientFilesQuestion/)."""
    maximum, bonus, hidden, hidden_cases = points
    task, figures, _dropped = task_html(ROOT / "steps" / step.folder / "README.md")
    files = ", ".join(f"<code>{html.escape(f)}</code>" for f in step.files)
    worth = (f"This question is worth the step's {course.shown(maximum)} points ({html.escape(course.scale_words())})."
             + (f" Its extra-credit cases, {course.shown(bonus)} points on top, are counted by a question of their "
                f"own beside this one, <em>raykit step {step.number} ★ extra credit</em> (submit the same code there; "
                "the assessment counts its points above its total)." if bonus else ""))
    hidden_text = (f" {hidden_cases} of its cases ({course.shown(hidden)} points) are hidden: random inputs of the "
                   f"visible cases' families, drawn for each submission. A failed hidden case names its family; "
                   f"{html.escape(HIDDEN_NOTE.split('; ', 1)[1])}" if hidden_cases and course.hidden_enabled else "")
    parts = ["<pl-question-panel>", task,
             "<h4>Here, on PrairieLearn</h4>",
             f"<p>Your {'file is' if len(step.files) == 1 else 'files are'} {files}: write {'it' if len(step.files) == 1 else 'them'} "
             f"in the editor{'s' if len(step.files) > 1 else ''} below, then <strong>Save &amp; Grade</strong>: every case runs, "
             "and each one that fails says what was called, what was expected and what your code gave, with the "
             "section to read of the step's lecture and, for the first failing one, a picture.</p>",
             f"<p><strong>Read</strong> {lecture_words(step, docs_url)}.</p>",
             f"<p>{worth}{hidden_text}</p>"]
    parts += headers_html(step)
    hints = hints_html(step)
    if hints:
        parts += ["<p>Stuck? The hints, one at a time:</p>", hints]
    parts.append("</pl-question-panel>")
    return with_editors(step, parts), figures


def headers_html(step) -> list[str]:
    """The step's scene, its contract's headers and the kit's definitions they include (struct Ray and
    the rest), as both of a step's questions show them."""
    def shown(h: str, summary: str) -> list[str]:
        return [f"<details><summary>{summary}</summary>", '<pl-code language="cpp">',
                html.escape(for_prairielearn((ROOT / "include" / h).read_text()), quote=False), "</pl-code></details>"]
    headers = contract_headers(step)
    parts = [scene_html(headers)]
    for h in headers:
        parts += shown(h, f"The contract: <code>{h}</code> (read it: what your functions must do)")
    shared = shared_headers(headers)
    if shared:
        parts.append("<p>The definitions your functions take, as the kit's headers give them (the contract "
                     "includes them for you):</p>")
    for h in shared:
        names = ", ".join(f"<code>{n}</code>" for n in defined_names(h))
        parts += shown(h, f"Shared definitions: <code>{h}</code>{' (' + names + ')' if names else ''}")
    return parts


def extra_question_html(step, course, points) -> str:
    """The page of a step's extra-credit question: what it counts, the step's files to submit again."""
    maximum, bonus = points[0], points[1]
    files = ", ".join(f"<code>{html.escape(f)}</code>" for f in step.files)
    parts = ["<pl-question-panel>",
             f"<p>The extra credit of step {step.number}, <em>{html.escape(step.title)}</em>: its extra-credit cases "
             f"({html.escape(' and '.join(g if g != 'robust' else 'the ★ tier' for g in course_file.GROUPS if course.extra_credit(g)))}), worth {course.shown(bonus)} points on top of the step's {course.shown(maximum)}. "
             "The assessment counts them above its total (its bonus points): missing them takes nothing away.</p>",
             f"<p>Submit here the same {files} as in the step's own question (its page has the task); "
             "<strong>Save &amp; Grade</strong> runs the step's cases and counts the extra-credit ones.</p>",
             *headers_html(step),       # the same definitions as the step's own page (issue 55)
             "</pl-question-panel>"]
    return with_editors(step, parts)


def with_editors(step, parts: list[str]) -> str:
    """A question's page: its panel (`parts`), then an editor per step file and the grader's results."""
    parts += [f'<pl-file-editor file-name="{f}" source-file-name="{f}" ace-mode="ace/mode/c_cpp"></pl-file-editor>'
              for f in step.files]
    parts += ["<pl-submission-panel>", "  <pl-external-grader-results></pl-external-grader-results>",
              "  <pl-file-preview></pl-file-preview>", "</pl-submission-panel>", ""]
    return template_safe("\n".join(parts))


def template_safe(page: str) -> str:
    """question.html is a Mustache template to PrairieLearn: every {{ or }} but the figures' URL becomes
    an entity pair the browser shows as the same characters."""
    url = FIGURE_URL.rstrip("/")
    return url.join(k.replace("{{", "{&#123;").replace("}}", "}&#125;") for k in page.split(url))


DOCKERFILE = ROOT / "tools" / "prairielearn" / "Dockerfile"


def image_readme(image: str) -> str:
    return f"""# The grading image

PrairieLearn pulls its grading images from Docker Hub, public. `Dockerfile` here is the kit's
(`tools/prairielearn/Dockerfile`): Debian 13 (`debian:13`, Docker Hub's official image) with the kit's
build packages and Python, nothing of the course (its build context, this folder, holds only this
README, the Dockerfile and build.sh). Build it for the graders' machines (x86-64), with the kit's side
built by it into the course's private files, then push the image under the name every question's
`info.json` names (`./kit prairielearn --image {image}`). From the folder that holds `graders/` and
`serverFilesCourse/` (this output, before you copy it into the course; or the course's repository):

    graders/raykit/build.sh
    docker login && docker push {image}:latest

build.sh runs `docker build --platform linux/amd64 -t {image}:latest graders/raykit`, then the image
once, without network, with `serverFilesCourse/` mounted where a job finds it
(`/grade/serverFilesCourse`), to build the kit's side (the judges, the reference, the hidden cases:
tools/raykit/bundle.py) into `serverFilesCourse/raykit-bundle/` with the image's own compiler. Commit
that folder with the course (about 10 MB): it is private, as the kit beside it is, and PrairieLearn
copies it into each job, which then compiles only the student's files (about 2 s of CPU instead of
about 20; its results say `"built": "student files only"`). Run build.sh again after any change to the
kit or a new image: a job whose image or kit differs from the bundle's builds its own and says why
(`"built_why"`), so it is slower, never wrong.

Then in PrairieLearn: the course's **Sync** page, *Sync* beside the image (PrairieLearn caches it), and
**Sync** the course itself after copying `questions/`, `courseInstances/` and `serverFilesCourse/` into its
repository and adding the topic and tags to its `infoCourse.json` (`README-raykit.md` beside `graders/`
lists them).

Without Docker, the kit checks the same image another way: `sudo tools/portability/reach prairielearn
--root trixie` builds this Dockerfile's root with debootstrap (as Debian's official images are built),
runs its RUN lines in it, and grades a cold job there under PrairieLearn's limits.

The limits PrairieLearn's graders give a job: 2 GiB of memory, 0.9 of a CPU, 1024 processes, no network,
the question's `timeout` (compile time included). bubblewrap cannot run under Docker's default seccomp
profile, so the kit grades as a user id of its own there.
"""


BUILD_SH = """#!/bin/sh
# Builds the public grading image, then the kit's side with it into the course's private files
# (graders/raykit/README.md). Run from the folder of graders/ and serverFilesCourse/.
set -eu
[ -d serverFilesCourse/raykit ] || {{ echo "build.sh: run it from the folder of graders/ and serverFilesCourse/ (no serverFilesCourse/raykit here)" >&2; exit 2; }}
docker build --platform linux/amd64 -t {image}:latest graders/raykit
docker run --rm --platform linux/amd64 --network none \\
    -v "$(pwd)/serverFilesCourse:/grade/serverFilesCourse" {image}:latest \\
    python3 /grade/serverFilesCourse/raykit/tools/prairielearn/prebuild.py
"""


def new_course_json(name: str, steps, course) -> dict:
    """infoCourse.json of a course from empty (--new-course NAME): the name, a title, course.json's
    timezone when it names one, and the topic and tags the questions use, declared."""
    data = {"uuid": str(uuid.uuid5(NAMESPACE, f"raykit/infoCourse/{name}")), "name": name,
            "title": "Ray tracing, one step at a time (raykit)",
            "comment": "written by raykit's ./kit prairielearn --new-course; edit the name and title as you like"}
    if course.timezone:
        data["timezone"] = course.timezone
    data.update(declarations(steps))
    return data


def with_declarations(info: dict, missing: dict[str, list[dict]]) -> dict:
    """The course's own infoCourse.json (--course DIR) with the entries it lacks added at the end of
    their lists; the rest as it was."""
    data = dict(info)
    for key, entries in missing.items():
        if entries:
            data[key] = list(data.get(key) or []) + entries
    return data


def read_course(folder: str) -> tuple[Path, dict]:
    """--course DIR: the course repository and its infoCourse.json; KitError when it is not one."""
    where = Path(folder).expanduser()
    info = where / "infoCourse.json"
    if not info.is_file():
        raise KitError(f"--course {folder}: no infoCourse.json there; give the folder of your PrairieLearn "
                       "course's repository (or leave --course out)")
    try:
        data = json.loads(info.read_text())
    except (OSError, ValueError) as e:
        raise KitError(f"--course {folder}: infoCourse.json cannot be read ({e})")
    if not isinstance(data, dict):
        raise KitError(f"--course {folder}: infoCourse.json is not a JSON object")
    return where, data


def their_timezone(course_dir: Path, instance: str, info: dict) -> str | None:
    """The timezone an existing instance's dates are read in: its own, else its course's."""
    try:
        data = json.loads((course_dir / "courseInstances" / instance / "infoCourseInstance.json").read_text())
    except (OSError, ValueError):
        data = {}
    zone = data.get("timezone") if isinstance(data, dict) else None
    return zone or info.get("timezone")


def undeclared(wanted: dict[str, list[dict]], info: dict | None) -> dict[str, list[dict]]:
    """The entries of `wanted` that the course's infoCourse.json (None: not known) does not declare."""
    if info is None:
        return wanted
    have = {key: {e.get("name") for e in info.get(key) or [] if isinstance(e, dict)} for key in wanted}
    return {key: [e for e in entries if e["name"] not in have[key]] for key, entries in wanted.items()}


def declaration_lines(missing: dict[str, list[dict]]) -> list[str]:
    """The lines to add to infoCourse.json: one JSON object a line, commas between them."""
    lines = []
    for key, entries in missing.items():
        if not entries:
            continue
        lines.append(f'  add to infoCourse.json\'s "{key}" list (a comma between these and its other entries; '
                     f'start the list, "{key}": [ ... ], if it has none):')
        lines += [f"    {json.dumps(e, ensure_ascii=False)}{',' if i < len(entries) - 1 else ''}"
                  for i, e in enumerate(entries)]
    return lines


def setup_readme(args, instance_note: str, lines: list[str], access: str, info_note: str = "") -> str:
    declare = (f"`infoCourse.json` here: {info_note}.\n" if info_note and not lines else
               f"`infoCourse.json` here is {info_note}; or add these entries to yours by hand:\n\n```\n"
               + "\n".join(lines) + "\n```\n" if info_note else"The questions' topic and tags must be declared in the course's `infoCourse.json`: PrairieLearn "
               "expects every topic and tag a question uses declared there, and its sync flags those that are "
               "not. Add these entries:\n\n```\n"
               + "\n".join(lines) + "\n```\n" if lines else
               "The questions' topic and tags are declared in the course's `infoCourse.json` already.\n")
    lecture = (f"Each question links its lecture on {args.docs_url} (the site `./kit docs` builds in "
               "`build/docs/student/html/`: publish that folder there)." if args.docs_url else
               "Each question names its lecture's file; with `--docs-url URL` (where the site `./kit docs` "
               "builds is published) it links the lecture's page instead.")
    copy = ("This folder is a whole course (`--new-course`): make it the course's repository (`infoCourse.json`, "
            "`questions/`, `courseInstances/`, `serverFilesCourse/`), then build and push the grading image as "
            "`graders/raykit/README.md` says. This file and `graders/` are not part of the course."
            if getattr(args, "new_course", None) is not None else
            "Run `graders/raykit/build.sh` here first (it builds the image and, with it, the kit's side into "
            "`serverFilesCourse/raykit-bundle/`). Copy `questions/`, `courseInstances/` and `serverFilesCourse/` into "
            "the course repository (merging with what is there)" + (", and `infoCourse.json` over the course's own" if info_note else "")
            + ", then build and push the grading image as `graders/raykit/README.md` says. This file and "
            "`graders/` are not part of the course.")
    return f"""# raykit for PrairieLearn: what to copy, what to add

{copy}

## The course instance

{instance_note}

## infoCourse.json

{declare}
## Access

{access}

## Lectures

{lecture}
"""


def write_question(staging: Path, step, info: dict, page: str, figures: list, extra: bool = False) -> None:
    """A question's folder: info.json, question.html, its figures, the step's stubs and the entry point."""
    q = staging / "questions" / question_id(step, extra)
    (q / "tests").mkdir(parents=True)
    (q / "info.json").write_text(json.dumps(info, indent=2) + "\n")
    (q / "question.html").write_text(page)
    for path, name in figures:
        (q / "clientFilesQuestion").mkdir(exist_ok=True)
        shutil.copyfile(path, q / "clientFilesQuestion" / name)
    for f in step.files:
        shutil.copyfile(ROOT / "steps" / step.folder / f, q / f)
    entry = q / "tests" / "grade.py"
    entry.write_text(ENTRY.format(number=step.number, part=', "--extra-credit"' if extra else ""))
    entry.chmod(0o755)


def run(args) -> int:
    if not (ROOT / "solutions").is_dir():
        raise KitError("this is a student handout (no solutions/): ./kit prairielearn runs in the instructor's kit")
    if not 1 <= args.timeout <= 600:
        raise KitError(f"--timeout {args.timeout}: seconds, 1 to 600 (PrairieLearn's limit)")
    if not re.fullmatch(r"[a-z0-9]+([._-][a-z0-9]+)*/[a-z0-9]+([._-][a-z0-9]+)*(:[\w][\w.-]*)?", args.image) \
            or args.image.startswith("your-dockerhub-user/"):
        raise KitError(f"--image {args.image}: not a Docker Hub image name of yours (USER/NAME in lower case, "
                       "like jdoe/raykit-grader)")
    if not re.fullmatch(r"[A-Za-z0-9][\w.-]*", args.instance):
        raise KitError(f"--instance {args.instance}: a course instance's folder name (letters, digits, . _ -)")
    if args.docs_url is not None and not re.fullmatch(r"https?://[^\s\"'<>]+", args.docs_url):
        raise KitError(f"--docs-url {args.docs_url}: the http(s) address where the docs site is hosted, "
                       "like https://example.edu/raykit/")
    new_course = getattr(args, "new_course", None)
    if new_course is not None and args.course:
        raise KitError("--new-course writes a course from empty; --course DIR adds to the course you have: one of them")
    if new_course is not None and not new_course.strip():
        raise KitError("--new-course NAME: the course's short name, e.g. \"CS 419\"")
    course_dir, course_info = read_course(args.course) if args.course else (None, None)
    has_instance = bool(course_dir and (course_dir / "courseInstances" / args.instance / "infoCourseInstance.json").is_file())
    course = course_file.load()
    zone = their_timezone(course_dir, args.instance, course_info) if has_instance else None
    zone_note = (f"PrairieLearn reads the due date {course.due_date} in {zone}, the timezone of {course_dir}'s "
                 f"instance {args.instance}" + (f", not course.json's {course.timezone}" if course.timezone else "")
                 if course.due_date and zone and zone != course.timezone else "")
    out = Path(args.out).expanduser()
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise KitError(f"{args.out}: exists and is not an empty folder; choose a new one")
    if ROOT == out.resolve() or ROOT in out.resolve().parents and (ROOT / "build") not in out.resolve().parents:
        raise KitError(f"{args.out}: cannot live inside the kit (except under build/)")
    try:                                    # a missing folder is made, as --out does everywhere
        out.resolve().parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise KitError(f"{args.out}: cannot make its folder ({e.strerror or e})")
    writable_parent(args.out, out)
    image = args.image
    steps = load_steps()
    points = {s.number: step_points(s, course) for s in steps}
    staging = out.resolve().parent / f".{out.name}.partial"
    shutil.rmtree(staging, ignore_errors=True)
    try:
        for step in steps:
            page, figures = question_html(step, course, points[step.number], args.docs_url)
            write_question(staging, step, info_json(step, image, args.timeout), page, figures)
            if points[step.number][1]:      # its extra credit: a question of its own (assessment_json)
                write_question(staging, step, info_json(step, image, args.timeout, extra=True),
                               extra_question_html(step, course, points[step.number]), [], extra=True)
        assessment = staging / "courseInstances" / args.instance / "assessments" / "raykit"
        assessment.mkdir(parents=True)
        if has_instance:
            instance_note = (f"`{course_dir}` has `courseInstances/{args.instance}/` already: the assessment goes "
                             "into it, and no `infoCourseInstance.json` is written here (the course's stays).")
        else:
            (staging / "courseInstances" / args.instance / "infoCourseInstance.json").write_text(
                json.dumps(instance_json(args.instance, course, date.today()), indent=2) + "\n")
            instance_note = (f"`courseInstances/{args.instance}/infoCourseInstance.json` makes the instance the "
                             "assessment goes in, published from today until "
                             + ("180 days after the due date" if course.due_date else "a year from today")
                             + (f" ({course_dir} has no such instance)." if course_dir else
                                ". If your course has this instance already, do not copy that file (yours stays); "
                                "`--course DIR` checks for you."))
        missing = undeclared(declarations(steps), course_info)
        lines = declaration_lines(missing)
        info_note = ""
        if new_course is not None:      # a course from empty: its infoCourse.json declares them
            (staging / "infoCourse.json").write_text(json.dumps(new_course_json(new_course.strip(), steps, course),
                                                                indent=2, ensure_ascii=False) + "\n")
            lines, info_note = [], "written whole (--new-course): OUT is the course's repository"
        elif course_info is not None and lines:     # the course's own, with what it lacks added
            (staging / "infoCourse.json").write_text(json.dumps(with_declarations(course_info, missing), indent=2,
                                                                ensure_ascii=False) + "\n")
            info_note = (f"{course_dir}'s own with the topic and tags it lacks added: copy it over "
                         f"{course_dir}/infoCourse.json")
        (assessment / "infoAssessment.json").write_text(json.dumps(assessment_json(steps, course, points), indent=2) + "\n")
        kit = staging / "serverFilesCourse" / "raykit"
        for rel in kit_files():
            if not not_shipped(rel) and (ROOT / rel).is_file() and ROOT / rel != secret.SECRET_FILE:
                (kit / rel).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(ROOT / rel, kit / rel)
        # The hidden cases' secret (raykit/secret.py): the kit's own, so ./kit check --identity
        # prairielearn:VARIANT here draws what the job drew.
        secret.copy_into(kit / secret.SECRET_FILE.relative_to(ROOT))
        (staging / "serverFilesCourse" / BUNDLE_FOLDER).mkdir()
        (staging / "serverFilesCourse" / BUNDLE_FOLDER / "README.md").write_text(BUNDLE_PLACEHOLDER)
        # The image's build context: the Dockerfile, the script and its README, nothing of the kit's.
        (staging / "graders" / "raykit").mkdir(parents=True)
        shutil.copyfile(DOCKERFILE, staging / "graders" / "raykit" / "Dockerfile")
        (staging / "graders" / "raykit" / "README.md").write_text(image_readme(image))
        build_sh = staging / "graders" / "raykit" / "build.sh"
        build_sh.write_text(BUILD_SH.format(image=image))
        build_sh.chmod(0o755)
        access = (f"Full credit until the due date, {course.due_date}"
                  + (f" ({course.timezone})" if course.timezone else " (the course's timezone)")
                  + ", from course.json; afterwards the assessment can be read, not submitted to."
                  if course.due_date else
                  "course.json gives no due date (`\"due\": {\"date\": \"2027-03-14T23:59:00\", \"timezone\": ...}`): "
                  "the assessment is open for full credit while the course instance is published.")
        access += f" Note: {zone_note}." if zone_note else ""
        (staging / "README-raykit.md").write_text(setup_readme(args, instance_note, lines, access, info_note))
        if out.exists():
            out.rmdir()
        staging.replace(out)
    except ValueError as e:         # a task's kit-only markers (taskpage.py)
        shutil.rmtree(staging, ignore_errors=True)
        raise KitError(f"a step's task (steps/NN_topic/README.md): {e}")
    except OSError as e:
        shutil.rmtree(staging, ignore_errors=True)
        raise KitError(f"{args.out}: cannot write it ({e.strerror or e})")
    total = sum((points[s.number][0] for s in steps), Fraction(0))
    bonus = sum((points[s.number][1] for s in steps), Fraction(0))
    extras = sum(bool(points[s.number][1]) for s in steps)
    say(f"wrote {out}: {len(steps) + extras} questions in questions/raykit/"
        + (f" ({extras} of them the steps' extra credit)" if extras else "") + ", the assessment in "
        f"courseInstances/{args.instance}/assessments/raykit/ ({course.shown(total)} points"
        + (f", {course.shown(bonus)} of extra credit" if bonus else "") + "),")
    say(f"  the kit in serverFilesCourse/raykit/, the grading image in graders/raykit/ (timeout {args.timeout} s; image {image});")
    say("  graders/raykit/build.sh builds the image and, with it, the kit's side into serverFilesCourse/raykit-bundle/")
    say(f"  course instance {args.instance}: " + (f"{course_dir} has it; its infoCourseInstance.json is left as it is"
                                                  if has_instance else "infoCourseInstance.json written"
                                                  + ("" if course_dir or new_course is not None else
                                                     " (if your course has this instance, do not copy that file)")))
    say("  access: " + (f"full credit until {course.due_date}" + (f" {course.timezone}" if course.timezone else "")
                        + ", then closed to submissions" if course.due_date
                        else "no due date in course.json: full credit while the instance is published"))
    if zone_note:
        say(f"  note: {zone_note}")
    if info_note:
        say(f"  infoCourse.json: {info_note}")
    if lines:
        say("  the questions' topic and tags, which PrairieLearn wants declared"
            + (" (added in OUT/infoCourse.json):" if info_note else
               " (--new-course NAME writes a whole course's infoCourse.json; --course DIR yours with them added):"))
        say("\n".join(lines))
    elif new_course is None:
        say(f"  the questions' topic and tags: declared in {course_dir}/infoCourse.json already")
    say(f"  next: {out}/README-raykit.md (what to copy), graders/raykit/README.md (build, push, sync)")
    return OK

"""./kit prairielearn OUT --image USER/NAME: what a course adds to its PrairieLearn repository to grade the
kit's steps, ready to sync.

    OUT/questions/raykit/NN_topic/    one externally graded question per step: info.json (gradingMethod
                                      External, externalGradingOptions), question.html (the task rendered
                                      for PrairieLearn by taskpage.py, the scale, the hidden cases, the
                                      headers it implements, the hints, a <pl-file-editor> per step file
                                      pre-filled with the stub), the stubs, the task's figures in
                                      clientFilesQuestion/, tests/grade.py (the entry point)
    OUT/courseInstances/INSTANCE/assessments/raykit/infoAssessment.json
                                      the assessment: one zone, a question per step worth the step's
                                      points on course.json's scale (plus its extra credit, which
                                      maxBonusPoints puts above maxPoints, the steps' points)
    OUT/serverFilesCourse/raykit/     the instructor's kit, solutions included: students never see
                                      serverFilesCourse, so the hidden cases run
    OUT/graders/raykit/Dockerfile     the grading image (tools/prairielearn/Dockerfile), and README.md: how to
                                      build it for linux/amd64, push it under --image and sync the course

The entry point runs tools/prairielearn/grade.py from the copied kit (`./kit check NN --steps ...
--prairielearn FILE`) and writes /grade/results/results.json as PrairieLearn reads it. Copy OUT's
folders into the course repository (questions/raykit/ may go under any questions/ subfolder if the
assessment's ids follow).
"""

from __future__ import annotations

import html
import json
import re
import shutil
import uuid
from pathlib import Path

from fractions import Fraction

from .. import course as course_file
from .. import secret
from ..checking import recorded_cases
from ..common import ROOT, KitError, load_steps, say, writable_parent
from ..kitfiles import kit_files, platform_excluded as not_shipped
from ..plresults import HIDDEN_NOTE
from ..status import OK
from ..taskpage import FIGURE_URL, kit_paths_out as for_prairielearn, task_html

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
MEASURED_SECONDS = {"05": (25.8, 72), "02": (22.0, 112)}     # step: (CPU seconds, wall seconds), cold, loaded
TIMEOUT = 180
NAMESPACE = uuid.UUID("6f1c2d8e-4b0a-4f5e-9a43-72a1c0de5b1e")   # the kit's: uuids stay the same per step
ENTRY = '''#!/usr/bin/env python3
"""PrairieLearn's entry point for step {number}: the kit in /grade/serverFilesCourse/raykit grades it."""
import os
import sys

GRADER = "/grade/serverFilesCourse/raykit/tools/prairielearn/grade.py"
os.execv(sys.executable, [sys.executable, GRADER, "{number}", "/grade"])
'''


def register(p) -> None:
    p.add_argument("out", metavar="OUT", help="an empty or new folder to write the questions, the assessment, the kit and the image into")
    p.add_argument("--image", required=True, metavar="USER/NAME",
                   help="the grading image's Docker Hub name, as you will push it (e.g. yourname/raykit-grader): "
                        "every info.json names it; graders/raykit/README.md says how to build and push it")
    p.add_argument("--instance", default="raykit", metavar="NAME",
                   help="the course instance the assessment goes in: OUT/courseInstances/NAME/assessments/raykit/ "
                        "(default raykit; use your instance's folder name)")
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
    groups = [course.group(c.tier, c.name) for c in cases
              if c.tier != "hidden" or course.hidden_enabled]
    shares = course.shares(step.number, groups)
    bonus = sum((p for p, g in zip(shares, groups) if course.extra_credit(g)), Fraction(0))
    hidden = sum((p for p, g in zip(shares, groups) if g == "hidden"), Fraction(0))
    return course.step_maximum(step.number, groups), bonus, hidden, groups.count("hidden")


def question_id(step) -> str:
    return f"raykit/{step.folder}"


def info_json(step, image: str, timeout: int) -> dict:
    return {
        "uuid": str(uuid.uuid5(NAMESPACE, f"raykit/{step.folder}")),
        "title": f"raykit step {step.number}: {step.title}",
        "topic": "Ray tracing",
        "tags": ["raykit", f"step{step.number}", "c++", "externally graded"],
        "type": "v3",
        "singleVariant": True,
        "gradingMethod": "External",
        "externalGradingOptions": {
            "image": image,
            "entrypoint": "/grade/tests/grade.py",
            "serverFilesCourse": ["raykit/"],
            "timeout": timeout,
            "environment": {"RAYKIT_BUDGET": str(max(timeout - 10, 10))},
        },
    }


def pl_number(value: Fraction) -> int | float:
    """Points for PrairieLearn, which multiplies them by each job's score: whole as they are, else to 6
    decimals (not the course's 2, which would make the questions' sum drift from the exact total)."""
    return value.numerator if value.denominator == 1 else round(float(value), 6)


def assessment_json(steps, course, points: dict) -> dict:
    """The assessment: a question per step, worth its points on the course's scale and its extra credit."""
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
                   "questions": [{"id": question_id(s), "autoPoints": pl_number(sum(points[s.number][:2])),
                                  "maxAutoPoints": pl_number(sum(points[s.number][:2]))} for s in steps]}],
    }
    if bonus:
        data["maxBonusPoints"] = pl_number(bonus)
    return data


def lecture_words(step) -> str:
    return f"lecture {step.number}, <em>{html.escape(step.title)}</em>"


def hints_html(step) -> str:
    path = ROOT / "tests" / step.folder / "hints.md"
    if not path.is_file():
        return ""
    hints = [h.strip() for h in re.split(r"^---\s*$", path.read_text(), flags=re.M) if h.strip()]
    parts = []
    for n, hint in enumerate(hints, 1):
        text = html.escape(for_prairielearn(hint), quote=False)
        parts.append(f'<details><summary>Hint {n}</summary><p style="white-space: pre-line">{text}</p></details>')
    return "\n".join(parts)


def question_html(step, course, points) -> tuple[str, list]:
    """The question's page and the figures to copy beside it (clientFilesQuestion/)."""
    maximum, bonus, hidden, hidden_cases = points
    task, figures, _dropped = task_html(ROOT / "steps" / step.folder / "README.md")
    files = ", ".join(f"<code>{html.escape(f)}</code>" for f in step.files)
    worth = (f"This question is worth the step's {course.shown(maximum)} points"
             + (f" and {course.shown(bonus)} of extra credit, which the assessment counts above its total" if bonus else "")
             + f" ({html.escape(course.scale_words())}).")
    hidden_text = (f" {hidden_cases} of its cases ({course.shown(hidden)} points) are hidden: random inputs of the "
                   f"visible cases' families, drawn for each submission. A failed hidden case names its family; "
                   f"{html.escape(HIDDEN_NOTE.split('; ', 1)[1])}" if hidden_cases and course.hidden_enabled else "")
    parts = ["<pl-question-panel>", task,
             "<h4>Here, on PrairieLearn</h4>",
             f"<p>Your {'file is' if len(step.files) == 1 else 'files are'} {files}: write {'it' if len(step.files) == 1 else 'them'} "
             f"in the editor{'s' if len(step.files) > 1 else ''} below, then <strong>Save &amp; Grade</strong>: every case runs, "
             "and each one that fails says what was called, what was expected and what your code gave, with the "
             f"lecture section to read ({lecture_words(step)}) and, for the first failing one, a picture.</p>",
             f"<p>{worth}{hidden_text}</p>"]
    headers = []
    for f in step.files:
        for h in re.findall(r'#include "(raykit/[a-z_]+\.hpp)"', (ROOT / "steps" / step.folder / f).read_text()):
            if h not in headers and h != "raykit/not_implemented.hpp":
                headers.append(h)
    for h in headers:
        parts += [f"<details><summary>The contract: <code>{h}</code> (read it: what your functions must do)</summary>",
                  '<pl-code language="cpp">', html.escape(for_prairielearn((ROOT / "include" / h).read_text()), quote=False),
                  "</pl-code></details>"]
    hints = hints_html(step)
    if hints:
        parts += ["<p>Stuck? The hints, one at a time:</p>", hints]
    parts.append("</pl-question-panel>")
    for f in step.files:
        parts.append(f'<pl-file-editor file-name="{f}" source-file-name="{f}" ace-mode="ace/mode/c_cpp"></pl-file-editor>')
    parts += ["<pl-submission-panel>", "  <pl-external-grader-results></pl-external-grader-results>",
              "  <pl-file-preview></pl-file-preview>", "</pl-submission-panel>", ""]
    return template_safe("\n".join(parts)), figures


def template_safe(page: str) -> str:
    """question.html is a Mustache template to PrairieLearn: every {{ or }} but the figures' URL becomes
    an entity pair the browser shows as the same characters."""
    url = FIGURE_URL.rstrip("/")
    keep = page.split(url)
    safe = [k.replace("{{", "{&#123;").replace("}}", "}&#125;") for k in keep]
    return url.join(safe)


DOCKERFILE = ROOT / "tools" / "prairielearn" / "Dockerfile"


def image_readme(image: str) -> str:
    return f"""# The grading image

PrairieLearn pulls its grading images from Docker Hub. `Dockerfile` here is the kit's
(`tools/prairielearn/Dockerfile`): Debian 13 (`debian:13`, Docker Hub's official image) with the kit's
build packages and Python. Build it for the graders' machines (x86-64) and push it under the name every
question's `info.json` names (`./kit prairielearn --image {image}`):

    docker build --platform linux/amd64 -t {image}:latest graders/raykit
    docker login && docker push {image}:latest

Then in PrairieLearn: the course's **Sync** page, *Sync* beside the image (PrairieLearn caches it), and
**Sync** the course itself after copying `questions/`, `courseInstances/` and `serverFilesCourse/` into its
repository.

Without Docker, the kit checks the same image another way: `sudo tools/portability/reach prairielearn
--root trixie` builds this Dockerfile's root with debootstrap (as Debian's official images are built),
runs its RUN lines in it, and grades a cold job there under PrairieLearn's limits.

The limits PrairieLearn's graders give a job: 2 GiB of memory, 0.9 of a CPU, 1024 processes, no network,
the question's `timeout` (compile time included). bubblewrap cannot run under Docker's default seccomp
profile, so the kit grades as a user id of its own there.
"""


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
    course = course_file.load()
    steps = load_steps()
    points = {s.number: step_points(s, course) for s in steps}
    staging = out.resolve().parent / f".{out.name}.partial"
    shutil.rmtree(staging, ignore_errors=True)
    try:
        for step in steps:
            q = staging / "questions" / question_id(step)
            (q / "tests").mkdir(parents=True)
            (q / "info.json").write_text(json.dumps(info_json(step, image, args.timeout), indent=2) + "\n")
            page, figures = question_html(step, course, points[step.number])
            (q / "question.html").write_text(page)
            for path, name in figures:
                (q / "clientFilesQuestion").mkdir(exist_ok=True)
                shutil.copyfile(path, q / "clientFilesQuestion" / name)
            for f in step.files:
                shutil.copyfile(ROOT / "steps" / step.folder / f, q / f)
            entry = q / "tests" / "grade.py"
            entry.write_text(ENTRY.format(number=step.number))
            entry.chmod(0o755)
        assessment = staging / "courseInstances" / args.instance / "assessments" / "raykit"
        assessment.mkdir(parents=True)
        (assessment / "infoAssessment.json").write_text(json.dumps(assessment_json(steps, course, points), indent=2) + "\n")
        kit = staging / "serverFilesCourse" / "raykit"
        for rel in kit_files():
            if not not_shipped(rel) and (ROOT / rel).is_file() and ROOT / rel != secret.SECRET_FILE:
                (kit / rel).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(ROOT / rel, kit / rel)
        # The hidden cases' secret (kitlib/secret.py): the kit's own, so ./kit check --identity
        # prairielearn:VARIANT here draws what the job drew.
        secret.copy_into(kit / secret.SECRET_FILE.relative_to(ROOT))
        (staging / "graders" / "raykit").mkdir(parents=True)
        shutil.copyfile(DOCKERFILE, staging / "graders" / "raykit" / "Dockerfile")
        (staging / "graders" / "raykit" / "README.md").write_text(image_readme(image))
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
    say(f"wrote {out}: {len(steps)} questions in questions/raykit/, the assessment in "
        f"courseInstances/{args.instance}/assessments/raykit/ ({course.shown(total)} points"
        + (f", {course.shown(bonus)} of extra credit" if bonus else "") + "),")
    say(f"  the kit in serverFilesCourse/raykit/, the grading image in graders/raykit/ (timeout {args.timeout} s; image {image})")
    say("  next: graders/raykit/README.md (build, push, sync)")
    return OK

"""./kit prairielearn OUT: what a course adds to its PrairieLearn repository to grade the kit's steps.

    OUT/questions/raykit/NN_topic/    one externally graded question per step: info.json (gradingMethod
                                      External, externalGradingOptions), question.html (the task, the
                                      headers it implements, a <pl-file-editor> per step file pre-filled
                                      with the stub), the stubs, tests/grade.py (the entry point)
    OUT/serverFilesCourse/raykit/     the instructor's kit, solutions included: students never see
                                      serverFilesCourse, so the hidden cases run
    OUT/graders/raykit/Dockerfile     the grading image (packages.py's build group), and README.md: how to
                                      build it for linux/amd64, push it to Docker Hub and sync the course

The entry point runs tools/prairielearn/grade.py from the copied kit (`./kit check NN --steps ... --json`)
and writes /grade/results/results.json as PrairieLearn reads it. Copy OUT's three folders into the
course repository (questions/raykit/ may go under any questions/ subfolder).
"""

from __future__ import annotations

import html
import json
import re
import shutil
import uuid
from pathlib import Path

from ..kitfiles import kit_files, platform_excluded as not_shipped
from .. import secret
from ..common import ROOT, KitError, load_steps, say, writable_parent
from ..packages import PACKAGES
from ..status import OK

# Measured (sudo tools/portability/reach prairielearn): step 05, the slowest (it links step 04), graded
# cold with its solution in a fresh copy of the kit under PrairieLearn's limits (cgroup v1: 0.9 CPU,
# 2 GiB, 1024 pids; unshare -n) took 33.1 s and 25.7 s of wall time (14 s of CPU, 307 MiB at most) on
# the shared 2-core build machine at a load of 5 to 7; step 01 21 s. In a fresh Debian 13 root at /grade
# with the image's packages (where bubblewrap cannot run and the kit grades as a user id of its own, as
# in Docker): 28.1 s, 12.6 s of CPU, 375 MiB. Again once the compile was sandboxed too (trust boundary)
# and untouched steps needed no build, on the same machine at a load of 0.2 to 1: step 05 12.5, 14.5
# and 12.8 s (11 to 13 s of CPU, at most 387 MiB), step 01 9.3 s. A question's timeout stays twice the
# slowest run measured, every step.
MEASURED_SECONDS = 33
TIMEOUT = 2 * MEASURED_SECONDS
NAMESPACE = uuid.UUID("6f1c2d8e-4b0a-4f5e-9a43-72a1c0de5b1e")   # the kit's: uuids stay the same per step
ENTRY = '''#!/usr/bin/env python3
"""PrairieLearn's entry point for step {number}: the kit in /grade/serverFilesCourse/raykit grades it."""
import os
import sys

GRADER = "/grade/serverFilesCourse/raykit/tools/prairielearn/grade.py"
os.execv(sys.executable, [sys.executable, GRADER, "{number}", "/grade"])
'''


def register(p) -> None:
    p.add_argument("out", metavar="OUT", help="an empty or new folder to write the questions, the kit and the image into")
    p.add_argument("--image", default="your-dockerhub-user/raykit-grader",
                   help="the grading image's Docker Hub name, as info.json names it (default: a placeholder to replace)")
    p.add_argument("--timeout", type=int, default=TIMEOUT,
                   help=f"seconds per grading job (default {TIMEOUT}: twice a cold step 05 under PrairieLearn's limits; at most 600)")


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


def question_html(step) -> str:
    task = (ROOT / "steps" / step.folder / "README.md").read_text()
    # The task is the kit's: where it says ./kit check (hint, debug), PrairieLearn has Save & Grade.
    task = ("Here, \"Save & Grade\" does what the task below calls ./kit check: every case, and for the\n"
            "first failing one its input, the expected and actual answer, and a picture of it. (./kit hint\n"
            "and ./kit debug are in the kit's own copy, not here.)\n\n" + task)
    # The task as text in a <pl-code> block: PrairieLearn's own example shows entities decoded there,
    # while how <markdown> treats C++'s <float> and & inside code spans is not documented.
    parts = ["<pl-question-panel>", '<pl-code language="markdown">', html.escape(task, quote=False), "</pl-code>"]
    headers = []
    for f in step.files:
        for h in re.findall(r'#include "(raykit/[a-z_]+\.hpp)"', (ROOT / "steps" / step.folder / f).read_text()):
            if h not in headers and h != "raykit/not_implemented.hpp":
                headers.append(h)
    for h in headers:
        parts += [f"<details><summary>The contract: <code>include/{h}</code></summary>",
                  '<pl-code language="cpp">', html.escape((ROOT / "include" / h).read_text(), quote=False),
                  "</pl-code></details>"]
    parts.append("</pl-question-panel>")
    for f in step.files:
        parts.append(f'<pl-file-editor file-name="{f}" source-file-name="{f}" ace-mode="ace/mode/c_cpp"></pl-file-editor>')
    parts += ["<pl-submission-panel>", "  <pl-external-grader-results></pl-external-grader-results>",
              "  <pl-file-preview></pl-file-preview>", "</pl-submission-panel>", ""]
    return "\n".join(parts)


def dockerfile() -> str:
    # bubblewrap: installed so the kit does not try to fetch it per job (no network); Docker's seccomp
    # profile stops it, and the kit grades as a user id of its own (passwd's useradd) instead.
    packages = " ".join(PACKAGES["build"] + PACKAGES["sandbox"] + ["python3", "passwd"])
    return f"""# The grading image of raykit's PrairieLearn questions (written by ./kit prairielearn).
# Ubuntu 24.04, as PrairieLearn's own prairielearn/grader-c. The kit itself is not in the image: it comes
# with every job from serverFilesCourse/raykit/, so a change to the kit needs a sync, not a new image.
FROM ubuntu:24.04
ARG DEBIAN_FRONTEND=noninteractive
RUN apt-get update \\
    && apt-get install -y --no-install-recommends {packages} \\
    && apt-get clean && rm -rf /var/lib/apt/lists/*
ENV LANG=C.UTF-8 NO_COLOR=1
"""


def image_readme(image: str) -> str:
    return f"""# The grading image

PrairieLearn pulls its grading images from Docker Hub. Build this one for the graders' machines
(x86-64) and push it under your account:

    docker build --platform linux/amd64 -t {image}:latest graders/raykit
    docker login && docker push {image}:latest

Then in PrairieLearn: the course's **Sync** page, *Sync* beside the image (PrairieLearn caches it), and
**Sync** the course itself after copying `questions/` and `serverFilesCourse/` into its repository. Each
question's `info.json` names the image (`externalGradingOptions.image`: `./kit prairielearn --image NAME`).

The limits PrairieLearn's graders give a job: 2 GiB of memory, 0.9 of a CPU, 1024 processes, no network,
the question's `timeout` (compile time included). bubblewrap cannot run under Docker's default seccomp
profile, so the kit grades as a user id of its own there.
"""


def run(args) -> int:
    if not (ROOT / "solutions").is_dir():
        raise KitError("this is a student handout (no solutions/): ./kit prairielearn runs in the instructor's kit")
    if not 1 <= args.timeout <= 600:
        raise KitError(f"--timeout {args.timeout}: seconds, 1 to 600 (PrairieLearn's limit)")
    if not re.fullmatch(r"[a-z0-9][a-z0-9._/-]*(:[\w.-]+)?", args.image):
        raise KitError(f"--image {args.image}: not a Docker image name (lower case, like user/raykit-grader)")
    out = Path(args.out).expanduser()
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise KitError(f"{args.out}: exists and is not an empty folder; choose a new one")
    writable_parent(args.out, out)
    if ROOT == out.resolve() or ROOT in out.resolve().parents and (ROOT / "build") not in out.resolve().parents:
        raise KitError(f"{args.out}: cannot live inside the kit (except under build/)")
    image = args.image
    staging = out.resolve().parent / f".{out.name}.partial"
    shutil.rmtree(staging, ignore_errors=True)
    steps = load_steps()
    try:
        for step in steps:
            q = staging / "questions" / "raykit" / step.folder
            (q / "tests").mkdir(parents=True)
            (q / "info.json").write_text(json.dumps(info_json(step, image, args.timeout), indent=2) + "\n")
            (q / "question.html").write_text(question_html(step))
            for f in step.files:
                shutil.copyfile(ROOT / "steps" / step.folder / f, q / f)
            entry = q / "tests" / "grade.py"
            entry.write_text(ENTRY.format(number=step.number))
            entry.chmod(0o755)
        kit = staging / "serverFilesCourse" / "raykit"
        for rel in kit_files():
            if not not_shipped(rel) and (ROOT / rel).is_file() and ROOT / rel != secret.SECRET_FILE:
                (kit / rel).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(ROOT / rel, kit / rel)
        # The hidden cases' secret (kitlib/secret.py): the kit's own, so ./kit check --identity
        # prairielearn:VARIANT here draws what the job drew.
        secret.copy_into(kit / secret.SECRET_FILE.relative_to(ROOT))
        (staging / "graders" / "raykit").mkdir(parents=True)
        (staging / "graders" / "raykit" / "Dockerfile").write_text(dockerfile())
        (staging / "graders" / "raykit" / "README.md").write_text(image_readme(image))
        if out.exists():
            out.rmdir()
        staging.replace(out)
    except OSError as e:
        shutil.rmtree(staging, ignore_errors=True)
        raise KitError(f"{args.out}: cannot write it ({e.strerror or e})")
    say(f"wrote {out}: {len(steps)} questions in questions/raykit/, the kit in serverFilesCourse/raykit/,")
    say(f"  the grading image in graders/raykit/ (timeout {args.timeout} s; image {image})")
    say(f"  next: graders/raykit/README.md (build, push, sync)")
    return OK

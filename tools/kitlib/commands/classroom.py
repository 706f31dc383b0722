"""./kit classroom DIR: GitHub Classroom's autograding workflow in a students' template repository.

DIR is a handout (`./kit handout DIR`), the repository a Classroom assignment starts from. This writes
DIR/.github/workflows/classroom.yml in the form Classroom's own editor generates (on push, the
permissions it asks for, one job on ubuntu-latest, one step per test, then the reporter with
`runners:`), with two differences that give partial credit per case on the kit's one scale:

- the packages are installed, and every step checked, once (`./kit check --classroom FILE`, which
  renders every step's result from the kit's own results: raykit/classroomresults.py);
- each kit step's grading step is a `run:` step handing its step's result on as its own `result`
  output (tools/classroom/result.py), in the command grader's version 1 format: one entry per counted
  case, 1 or 0 points, so the reporter's "Points X/Y" is the kit's own score (where each counted case
  is worth a point, as by default), and its console table (passes x max_score / entries) says the same.

What Classroom's grade is worth: the student owns the repository and its workflow, and the check runs
their steps unsandboxed and without hidden cases (a handout has none), as ./kit check does on their
laptop. Re-grade the final commits with ./kit grade or Gradescope (docs/instructors.md, "Where to grade").
"""

from __future__ import annotations

import json
from pathlib import Path

from raykit import atomic
from raykit.common import KitError, load_steps, say, writable_parent
from raykit.packages import PACKAGES
from raykit.status import OK

WORKFLOW = Path(".github/workflows/classroom.yml")
RESULTS = "build/classroom-results.json"
REPORTER = "classroom-resources/autograding-grading-reporter@v1"


def register(p) -> None:
    p.add_argument("dir", metavar="DIR", help="the students' template repository: a handout (./kit handout DIR)")
    p.add_argument("--timeout", type=int, default=15, metavar="MIN",
                   help="minutes the job may take (default 15; a cold check takes 1 to 3 on GitHub's runners)")


def quoted(text: str) -> str:
    """A YAML scalar in double quotes (JSON's string syntax is a subset of YAML's)."""
    return json.dumps(text, ensure_ascii=False)


def workflow(steps, timeout: int = 15) -> str:
    packages = " ".join(PACKAGES["build"])     # ubuntu-latest has cmake and g++; apt skips them
    ids = [f"step{s.number}" for s in steps]
    lines = [
        "# Written by ./kit classroom: partial credit per case, the kit's own score (tools/classroom/result.py).",
        "# The student's own steps run here, unsandboxed, without hidden cases: re-grade final commits",
        "# with ./kit grade or Gradescope.",
        "name: Autograding Tests",
        "'on':",
        "- push",
        "- repository_dispatch",
        "permissions:",
        "  checks: write",
        "  actions: read",
        "  contents: read",
        "jobs:",
        "  run-autograding-tests:",
        "    runs-on: ubuntu-latest",
        "    if: github.actor != 'github-classroom[bot]'",
        f"    timeout-minutes: {timeout}",
        "    steps:",
        "    - name: Checkout code",
        "      uses: actions/checkout@v4",
        "    - name: Install the packages",
        f"      run: sudo apt-get update -q && sudo apt-get install -y -q --no-install-recommends {packages}",
        "    - name: Check every step",
        f"      run: mkdir -p build && (./kit check --classroom {RESULTS} || true)",
    ]
    for s, i in zip(steps, ids):
        lines += [
            f"    - name: {quoted(f'Step {s.number}: {s.title}')}",
            f"      id: {i}",
            f"      run: python3 tools/classroom/result.py {RESULTS} {s.number}",
        ]
    lines += [
        "    - name: Autograding Reporter",
        f"      uses: {REPORTER}",
        "      env:",
    ]
    lines += [f"        {i.upper()}_RESULTS: \"${{{{steps.{i}.outputs.result}}}}\"" for i in ids]
    lines += ["      with:", f"        runners: {','.join(ids)}", ""]
    return "\n".join(lines)


def run(args) -> int:
    target = Path(args.dir).expanduser()
    if not target.is_dir():
        raise KitError(f"{args.dir}: no such folder; write the handout first (./kit handout {args.dir})")
    if not (target / "kit").is_file() or not (target / "steps").is_dir():
        raise KitError(f"{args.dir}: not a copy of the kit (no ./kit or steps/); write it with ./kit handout")
    if not all((target / f).is_file() for f in ("tools/classroom/result.py", "tools/raykit/classroomresults.py")):
        raise KitError(f"{args.dir}: has no tools/classroom/result.py or raykit/classroomresults.py (a handout "
                       "from an older kit); write it again")
    if (target / "solutions").exists():
        raise KitError(f"{args.dir}: has solutions/; Classroom's template repository must be a handout "
                       "(students can read every file of it)")
    if args.timeout < 1 or args.timeout > 360:
        raise KitError(f"--timeout {args.timeout}: minutes, 1 to 360 (GitHub's limit is 6 hours)")
    out = target / WORKFLOW
    writable_parent(str(WORKFLOW), target)
    steps = load_steps()
    out.parent.mkdir(parents=True, exist_ok=True)
    try:
        atomic.write(out, workflow(steps, args.timeout))
    except OSError as e:
        raise KitError(f"{out}: cannot write it ({e.strerror})")
    say(f"wrote {out}: {len(steps)} grading steps (partial credit per case), then the reporter")
    say("  commit it to the template repository; Classroom's grade is only as trustworthy as the")
    say("  student's repository: re-grade final commits with ./kit grade or Gradescope")
    return OK

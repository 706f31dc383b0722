"""Self-test: the kit where courses grade: GitHub Classroom, PrairieLearn, a machine without apt.

  - classroom: a handout with ./kit classroom's workflow, run as the runner would
    (tools/classroom/simulate.py: every `run:` step in the repository with only PATH and HOME, then the
    real autograding-grading-reporter from ../shared/third_party/, npm-installed into build/), for the
    stubs, one slip and the solutions: its "Points X/Y" and its console table's total equal the kit's own
    score; every `with:` key is among the action's action.yml inputs, and a wrong key is caught.
Needs ../shared/third_party/ (skipped without it: a user's clone has none), node and npm, and Debian's
python3-yaml (/usr/bin/python3). The full form, in a Debian 13 root as a user with sudo, is by hand:
tools/portability/reach (its docstring).
"""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

from ..common import BUILD, ROOT, load_steps
from .harness import Failed, Skipped, expect, kit, need_solutions

THIRD_PARTY = ROOT.parent / "shared" / "third_party"
WORK = BUILD / "reach"
SYSTEM_PYTHON = "/usr/bin/python3"      # Debian's, which sees python3-yaml and python3-jsonschema
SLIP = ("01_unit_sphere", "a_assumed_one")   # the one-slip repository: step 01 with this mutant


def need_third_party(*parts: str) -> Path:
    path = THIRD_PARTY.joinpath(*parts)
    if not path.exists():
        raise Skipped(f"needs {path} (the real clients' files; a user's clone has none)")
    return path


def need_system_python(*modules: str) -> None:
    probe = subprocess.run([SYSTEM_PYTHON, "-c", "import " + ", ".join(modules)], capture_output=True)
    if probe.returncode != 0:
        raise Skipped(f"needs {SYSTEM_PYTHON} with {', '.join(modules)} (Debian: "
                      + " ".join(f"python3-{m}" for m in modules) + ")")


def make_handout(target: Path) -> Path:
    shutil.rmtree(target, ignore_errors=True)
    r = kit("handout", str(target))
    expect(r.returncode == 0, f"./kit handout failed:\n{r.stdout[-500:]}{r.stderr[-1500:]}")
    return target


def fill(steps_dir: Path, form: str) -> None:
    """Puts the stubs back (they are the handout's), the solutions, or the solutions with one slip."""
    for step in load_steps():
        for f in step.files:
            src = ROOT / ("steps" if form == "stubs" else "solutions") / step.folder / f
            shutil.copyfile(src, steps_dir / step.folder / f)
    if form == "slip":
        folder, name = SLIP
        patch = ROOT / "tests" / "mutants" / folder / f"{name}.patch"
        r = subprocess.run(["patch", "-s", "-p3", "-d", str(steps_dir / folder), "-i", str(patch)],
                           capture_output=True, text=True)
        expect(r.returncode == 0, f"the mutant {folder}/{name} does not apply: {r.stdout}{r.stderr}")


def reporter() -> Path:
    src = need_third_party("github-classroom", "autograding-grading-reporter")
    if not shutil.which("node") or not shutil.which("npm"):
        raise Skipped("needs node and npm (Debian: nodejs npm) to run the real reporter")
    copy = WORK / "reporter"
    if not (copy / "node_modules" / "@actions" / "core").is_dir():
        shutil.rmtree(copy, ignore_errors=True)
        shutil.copytree(src, copy)
        r = subprocess.run(["npm", "install", "--omit=dev", "--no-audit", "--no-fund"], cwd=copy,
                           capture_output=True, text=True, timeout=300)
        if r.returncode != 0:
            raise Skipped(f"npm install of the reporter failed (no registry?): {r.stderr.strip()[-300:]}")
    return copy


def simulate(repo: Path, rep: Path) -> dict:
    r = subprocess.run([SYSTEM_PYTHON, str(ROOT / "tools/classroom/simulate.py"), str(repo), str(rep)],
                       capture_output=True, text=True, timeout=1200)
    expect(r.returncode == 0, f"simulate.py failed: {r.stderr[-1500:]}")
    return json.loads(r.stdout)


def selftest_classroom(ctx) -> str:
    need_solutions()
    need_system_python("yaml")
    rep = reporter()
    # A wrong `with:` key is caught (so the real check below can fail).
    bad = WORK / "bad-workflow"
    (bad / ".github/workflows").mkdir(parents=True, exist_ok=True)
    (bad / ".github/workflows/classroom.yml").write_text(
        "jobs:\n  j:\n    runs-on: ubuntu-latest\n    steps:\n"
        "    - uses: classroom-resources/autograding-grading-reporter@v1\n"
        "      with:\n        runners: a\n        max-score: 3\n")
    expect(any("max-score" in p for p in simulate(bad, rep)["problems"]),
           "a reporter step with an unknown with: key (max-score) was not caught")
    repo = make_handout(WORK / "classroom-repo")
    r = kit("classroom", str(repo))
    expect(r.returncode == 0, f"./kit classroom failed: {r.stdout}{r.stderr}")
    seen = []
    for form in ("stubs", "slip", "complete"):
        fill(repo / "steps", form)
        got = simulate(repo, rep)
        expect(not got["problems"], f"{form}: " + "; ".join(got["problems"])[:2000])
        results = json.loads((repo / "build/classroom-results.json").read_text())
        kit_score = (results["score"], results["extra_data"]["max_score"])
        expect((got["points"], got["max"]) == kit_score,
               f"{form}: the reporter says {got['notice']!r}, the kit {kit_score[0]}/{kit_score[1]}")
        expect(got["table"] == [got["points"], got["max"]],
               f"{form}: the reporter's table totals {got['table']}, its notice {got['notice']!r}")
        seen.append(f"{form} {got['points']:g}/{got['max']:g}")
    scores = [float(s.split()[1].split("/")[0]) for s in seen]
    expect(scores[0] == 0 and 0 < scores[1] < scores[2] and scores[2] == float(seen[2].split("/")[1]),
           f"stubs, one slip, solutions should read 0, between, full: {', '.join(seen)}")
    return "the real reporter's Points equal the kit's score: " + ", ".join(seen)


def selftests():
    return [("classroom: the real reporter's Points X/Y is the kit's score", selftest_classroom)]

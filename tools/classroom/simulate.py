#!/usr/bin/env python3
"""Runs a repository's .github/workflows/classroom.yml as GitHub's runner would, with the real reporter.

    python3 tools/classroom/simulate.py REPO REPORTER [--install]

REPO is a students' repository (a handout with `./kit classroom`); REPORTER a copy of
classroom-resources/autograding-grading-reporter with its node_modules (`npm install --omit=dev`).
The workflow is read as YAML (PyYAML, as Debian's python3-yaml has it), every `with:` key of a
`uses:` step is checked against that action's action.yml inputs where this machine has the action
(REPORTER's), each `run:` step runs in REPO with bash -e, the runner's PATH and HOME and its own
$GITHUB_OUTPUT (the "Install the packages" step only with --install), and the reporter runs with the
env and inputs the runner would give it: `${{steps.ID.outputs.result}}` substituted, `with:` keys as
INPUT_ variables. It prints one JSON line: {"points": X, "max": Y, "table": [X, Y], "notice": TEXT,
"problems": [...]}. An instructor's test tool, not used by the workflow itself.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

EXPR = re.compile(r"\$\{\{\s*steps\.([A-Za-z0-9_-]+)\.outputs\.([A-Za-z0-9_-]+)\s*\}\}")
NOTICE = re.compile(r"::notice title=Autograding complete::Points ([\d.]+)/([\d.]+)")
TOTAL = re.compile(r"│\s*Total:\s*│\s*([\d.]+)\s*│\s*([\d.]+)\s*│")


def load_yaml(path: Path):
    try:
        import yaml  # Debian's python3-yaml
    except ImportError:
        raise SystemExit("simulate: needs PyYAML (Debian: python3-yaml; run with /usr/bin/python3)")
    return yaml.safe_load(path.read_text())


def action_inputs(action_yml: Path) -> set[str]:
    return set((load_yaml(action_yml).get("inputs") or {}).keys())


def outputs(path: Path) -> dict[str, str]:
    """$GITHUB_OUTPUT's name=value lines (the heredoc form name<<EOF is not used by the kit)."""
    found = {}
    for line in path.read_text().splitlines():
        if "=" in line:
            k, v = line.split("=", 1)
            found[k] = v
    return found


def simulate(repo: Path, reporter: Path, install: bool = False) -> dict:
    wf = load_yaml(repo / ".github/workflows/classroom.yml")
    problems: list[str] = []
    jobs = wf.get("jobs") or {}
    if len(jobs) != 1:
        problems.append(f"{len(jobs)} jobs, Classroom's form has one")
    job = next(iter(jobs.values()))
    wanted = {"checks": "write", "actions": "read", "contents": "read"}   # what Classroom's form asks
    if (wf.get("permissions") or {}) != wanted:
        problems.append(f"permissions {wf.get('permissions')}, Classroom's form has {wanted}")
    triggers = wf.get("on", wf.get(True))   # YAML 1.1 reads a bare `on` as true
    if "push" not in (triggers or []):
        problems.append(f"not run on push: on {triggers}")
    if job.get("runs-on") != "ubuntu-latest":
        problems.append(f"runs-on {job.get('runs-on')}")
    known = {"classroom-resources/autograding-grading-reporter": action_inputs(reporter / "action.yml")}
    env0 = {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": os.environ.get("HOME", "/root")}
    step_outputs: dict[str, dict[str, str]] = {}
    notice = ""
    table = None
    points = maximum = None
    with tempfile.TemporaryDirectory(prefix="classroom-") as tmp:
        for n, step in enumerate(job.get("steps") or []):
            uses = step.get("uses")
            with_ = step.get("with") or {}
            if uses:
                name = uses.split("@")[0]
                if name in known:
                    bad = sorted(set(with_) - known[name])
                    if bad:
                        problems.append(f"{uses}: with: {', '.join(bad)} not among its inputs")
                    required = {k for k, v in (load_yaml(reporter / "action.yml")["inputs"]).items()
                                if v.get("required")}
                    if required - set(with_):
                        problems.append(f"{uses}: required input(s) {', '.join(sorted(required - set(with_)))} missing")
                elif with_:
                    problems.append(f"{uses}: with: keys {sorted(with_)} cannot be checked here (no action.yml)")
                if name != "classroom-resources/autograding-grading-reporter":
                    continue  # actions/checkout: REPO is the checkout
                env = dict(env0)
                for k, v in (step.get("env") or {}).items():
                    env[k] = EXPR.sub(lambda m: step_outputs.get(m.group(1), {}).get(m.group(2), ""), str(v))
                for k, v in with_.items():
                    env[f"INPUT_{k.upper()}"] = str(v)
                r = subprocess.run(["node", "src/main.js"], cwd=reporter, env=env, capture_output=True, text=True)
                log = r.stdout + r.stderr
                m = NOTICE.search(log)
                if m:
                    notice, points, maximum = m.group(0), float(m.group(1)), float(m.group(2))
                t = TOTAL.search(log)
                if t:
                    table = [float(t.group(1)), float(t.group(2))]
                if not m:
                    problems.append("the reporter printed no 'Points X/Y' notice:\n" + log[-2000:])
                continue
            if "run" not in step:
                continue
            if step.get("name") == "Install the packages" and not install:
                continue
            out = Path(tmp) / f"output{n}"
            out.touch()
            env = dict(env0, GITHUB_OUTPUT=str(out), CI="true", GITHUB_ACTIONS="true")
            r = subprocess.run(["bash", "-e", "-c", step["run"]], cwd=repo, env=env, capture_output=True, text=True)
            if r.returncode != 0:
                problems.append(f"step {step.get('name')!r} exited {r.returncode}: {(r.stdout + r.stderr)[-800:]}")
            if step.get("id"):
                step_outputs[step["id"]] = outputs(out)
    return {"points": points, "max": maximum, "table": table, "notice": notice, "problems": problems}


def main(argv: list[str]) -> int:
    args = [a for a in argv if not a.startswith("--")]
    if len(args) != 2:
        print("usage: simulate.py REPO REPORTER [--install]", file=sys.stderr)
        return 2
    print(json.dumps(simulate(Path(args[0]), Path(args[1]), "--install" in argv)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

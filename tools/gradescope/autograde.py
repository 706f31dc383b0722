#!/usr/bin/env python3
"""Gradescope's per-submission run: find the steps, grade them, always leave a results.json.

Called by run_autograder (this folder), from the kit unpacked in /autograder/source:
  1. tools/kitlib/submissions.py finds the step files at any depth of /autograder/submission
     (a zipped kit, a steps/ folder, loose NN_topic/ folders, the .cpp files) and copies them
     into a clean folder;
  2. `./kit check --steps THAT --json PRIVATE` grades them; the kit sandboxes the student code;
  3. the kit's JSON is checked and only then written to /autograder/results/results.json.

Why the detour through a private file: student code runs while the kit works. Anything it
writes to results/ is overwritten at the end, and the kit runs in its own PID namespace where
the system allows one, so no process of it outlives the grading to forge the file afterwards
(without one, its process group is killed).

Every path out of here writes a valid results.json: no step files, a kit that fails or hangs,
a JSON file that is not Gradescope's; each becomes a failed test that says why.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

AUTOGRADER = Path(os.environ.get("RAYKIT_AUTOGRADER_ROOT", "/autograder"))
SOURCE = AUTOGRADER / "source"
SUBMISSION = AUTOGRADER / "submission"
RESULTS = AUTOGRADER / "results" / "results.json"
KIT_SECONDS = 30 * 60           # all steps; Gradescope's own limit is set per assignment

sys.path.insert(0, str(SOURCE / "tools" / "kitlib"))


def failed(reason: str, name: str = "Autograder", output: str = "") -> dict:
    """A results.json with one failed test carrying `reason`: never an empty file."""
    return {"score": 0, "output": output or reason, "visibility": "visible", "stdout_visibility": "hidden",
            "tests": [{"name": name, "score": 0, "max_score": 1, "status": "failed",
                       "visibility": "visible", "output": reason}]}


def write_results(data: dict) -> None:
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    tmp = RESULTS.with_name(f".results.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(data, indent=2, ensure_ascii=False))
    os.replace(tmp, RESULTS)


def pid_namespace_works() -> bool:
    """True when `unshare` may start a PID namespace here (root on a normal host; often not in
    a Docker container, which is what Gradescope runs)."""
    if shutil.which("unshare") is None:
        return False
    try:
        r = subprocess.run(["unshare", "--pid", "--fork", "--kill-child", "--mount-proc", "true"],
                           capture_output=True, timeout=20)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return r.returncode == 0


def run_kit(steps_dir: Path, json_path: Path) -> tuple[int, str]:
    cmd = [str(SOURCE / "kit"), "check", "--steps", str(steps_dir), "--json", str(json_path), "--quiet"]
    if pid_namespace_works():
        # The kit is process 1 of its namespace: when it ends, the kernel kills all that is left.
        cmd = ["unshare", "--pid", "--fork", "--kill-child", "--mount-proc"] + cmd
    with tempfile.TemporaryFile() as log:
        proc = subprocess.Popen(cmd, cwd=SOURCE, stdout=log, stderr=log, stdin=subprocess.DEVNULL,
                                start_new_session=True)
        try:
            code = proc.wait(timeout=KIT_SECONDS)
        except subprocess.TimeoutExpired:
            code = -1
        try:
            os.killpg(proc.pid, signal.SIGKILL)     # whatever stayed in its process group
        except ProcessLookupError:
            pass
        proc.wait()
        log.seek(0)
        text = log.read().decode("utf-8", "replace")
    if code == -1:
        text += f"\nThe grading did not finish within {KIT_SECONDS // 60} minutes and was stopped."
    return code, text


def usable(data: object) -> str:
    """Why `data` is not a results.json worth handing to Gradescope, or "" when it is."""
    if not isinstance(data, dict):
        return "the kit's results are not a JSON object"
    tests = data.get("tests")
    if not isinstance(tests, list) or not tests:
        return "the kit's results hold no test"
    if not isinstance(data.get("score", 0), (int, float)):
        return "the kit's results have no numeric score"
    return ""


def grade() -> dict:
    from submissions import NotFound, locate

    work = Path(tempfile.mkdtemp(prefix="raykit-autograder-"))
    os.chmod(work, 0o755)       # the kit's sandbox may read the copy as another user
    try:
        try:
            found = locate(SUBMISSION, work / "upload")
        except NotFound as e:
            return failed(str(e), "Your upload")
        where = f"Graded {', '.join(found.steps)} from {found.source} ({found.layout})."
        if found.notes:
            where += " Left out: " + "; ".join(found.notes[:5]) + "."
        private = work / "private"
        private.mkdir(mode=0o700)
        json_path = private / "results.json"
        code, log = run_kit(found.steps_dir, json_path)
        try:
            data = json.loads(json_path.read_text())
            problem = usable(data)
        except (OSError, ValueError) as e:
            data, problem = None, f"the kit wrote no readable results ({e.__class__.__name__})"
        if problem:
            tail = "\n".join(log.strip().splitlines()[-30:])
            return failed(f"The autograder could not grade this upload: {problem} (./kit check exit "
                          f"status {code}).\n{where}\n{tail}".strip())
        data["output"] = (where + "\n" + str(data.get("output", ""))).strip()
        return data
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main() -> int:
    start = time.monotonic()
    try:
        data = grade()
    except Exception as e:      # noqa: BLE001 -- whatever happens, Gradescope gets a result
        data = failed(f"The autograder itself failed: {e.__class__.__name__}: {e}")
    data.setdefault("execution_time", round(time.monotonic() - start, 3))
    write_results(data)
    return 0


if __name__ == "__main__":
    sys.exit(main())

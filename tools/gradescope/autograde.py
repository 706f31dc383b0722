#!/usr/bin/env python3
"""Gradescope's per-submission run: find the steps, grade them, always leave a results.json.

Called by run_autograder (this folder), from the kit unpacked in /autograder/source:
  1. tools/raykit/submissions.py finds the step files at any depth of /autograder/submission
     (a zipped kit, a steps/ folder, loose NN_topic/ folders, the .cpp files) and copies them
     into a clean folder;
  2. `./kit check --steps THAT --json PRIVATE` grades them; the kit sandboxes the student code;
  3. the kit's JSON is checked and only then written to /autograder/results/results.json.

Why the detour through a private file: student code runs while the kit works. Anything it
writes to results/ is overwritten at the end, and no process of it outlives the grading to
forge the file afterwards: the kit ends every process of the sandbox after each case (its own
PID namespace under bubblewrap, its own user id otherwise), the kit runs in a session of its
own, which is ended with it, and this process is a child subreaper, so a process that detached
itself (fork, setsid) is handed to us and killed before we write.

No PID namespace around the kit: `unshare --pid` without its own /proc made bubblewrap fail
inside it ("open /proc/N/ns/ns failed", shown to students as their own timeouts) and made the
judge's clean-up look up namespace-local PIDs in the outer /proc.

Every path out of here writes a valid results.json: no step files, a kit that fails or hangs,
a JSON file that is not Gradescope's; each becomes a failed test that says why.
"""

from __future__ import annotations

import ctypes
import json
import os
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time
from pathlib import Path

AUTOGRADER = Path(os.environ.get("RAYKIT_AUTOGRADER_ROOT", "/autograder"))
SOURCE = AUTOGRADER / "source"
SUBMISSION = AUTOGRADER / "submission"
RESULTS = AUTOGRADER / "results" / "results.json"
METADATA = AUTOGRADER / "submission_metadata.json"     # the due dates and the submission's id
PR_SET_CHILD_SUBREAPER = 36    # <linux/prctl.h>
KIT_SECONDS = 30 * 60           # all steps; Gradescope's own limit is set per assignment

sys.path.insert(0, str(SOURCE / "tools"))       # the kit's driver packages, raykit and kitlib


def failed(reason: str, name: str = "Autograder", output: str = "") -> dict:
    """A results.json with one failed test carrying `reason`: never an empty file."""
    return {"score": 0, "output": output or reason, "visibility": "visible", "stdout_visibility": "hidden",
            "tests": [{"name": name, "score": 0, "max_score": 1, "status": "failed",
                       "visibility": "visible", "output": reason}]}


def not_graded(reason: str) -> dict:
    """The grader's own failure (the kit died, hung or wrote nothing usable): a test worth 0 of 0, so no
    point is taken away, that says "not graded" and asks for a regrade (raykit/faults.py)."""
    words = (f"NOT GRADED: {reason}\nThis is the grader's fault, not your code's: no points are taken away, "
             "and none are given yet; ask for a regrade (Request Regrade on this page), or submit again.")
    return {"score": 0, "output": words, "visibility": "visible", "stdout_visibility": "hidden",
            "tests": [{"name": "Not graded — the autograder failed", "score": 0, "max_score": 0,
                       "status": "failed", "visibility": "visible", "output": words, "tags": ["not_graded"]}],
            "extra_data": {"gradable": False}}


def write_results(data: dict) -> None:
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    tmp = RESULTS.with_name(f".results.{os.getpid()}.tmp")
    tmp.write_text(json.dumps(data, indent=2, ensure_ascii=False))
    os.replace(tmp, RESULTS)


def become_subreaper() -> bool:
    """Makes this process the one orphans of its descendants are given to (Linux 3.4+), so a
    process the graded code detached with fork and setsid is still ours to find and end."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def children() -> list[int]:
    me, found = os.getpid(), []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat_line = Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            # The fields after the command (which may hold spaces) start at the last ')'.
            fields = stat_line[stat_line.rfind(")") + 2:].split()
            if len(fields) > 1 and int(fields[1]) == me:
                found.append(int(entry))
    return found


def end_descendants() -> int:
    """Kills and reaps every process left below us until none is left; returns how many."""
    ended, quiet_rounds = 0, 0
    while quiet_rounds < 3:
        left = children()
        quiet_rounds = 0 if left else quiet_rounds + 1
        for pid in left:
            try:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                ended += 1
            except (ProcessLookupError, ChildProcessError):
                pass
        time.sleep(0.05)
    return ended


def submission_identity(metadata_path: Path) -> str:
    """Gradescope's id of this submission, for the hidden cases' seed (raykit/secret.py): every
    submission, the same bytes again included, draws its own inputs; a re-grade of it the same."""
    try:
        metadata = json.loads(metadata_path.read_text())
    except (OSError, ValueError):
        return ""
    sid = metadata.get("id") if isinstance(metadata, dict) else None
    return f"gradescope:{sid}" if isinstance(sid, (int, str)) and str(sid).strip() else ""


class Closed:
    """/autograder closed to every user but root while the graded code runs: the submission's
    metadata (with every earlier result of this student), the kit in source/ and the results
    folder. The graded code needs none of it (the kit copies what it may read). The modes are put
    back afterwards, whatever happens."""

    def __init__(self, paths: list[Path]):
        self.saved: list[tuple[Path, int]] = []
        for p in paths:
            try:
                st = os.lstat(p)
            except OSError:
                continue
            if stat.S_ISLNK(st.st_mode):
                continue
            self.saved.append((p, stat.S_IMODE(st.st_mode)))
            os.chmod(p, stat.S_IMODE(st.st_mode) & 0o700)

    def restore(self) -> None:
        for p, mode in reversed(self.saved):
            try:
                os.chmod(p, mode)
            except OSError:
                pass


def run_kit(steps_dir: Path, json_path: Path) -> tuple[int, str]:
    cmd = [str(SOURCE / "kit"), "check", "--steps", str(steps_dir), "--json", str(json_path), "--quiet"]
    from raykit.gradescope import reveal_options    # course.json's visibility; --reveal after the due date
    cmd += reveal_options(METADATA)
    identity = submission_identity(METADATA)
    if identity:
        cmd += ["--identity", identity]
    if os.environ.get("RAYKIT_AUTOGRADER_ISOLATION") in ("bwrap", "user"):     # the self-test's seam
        cmd += ["--isolation", os.environ["RAYKIT_AUTOGRADER_ISOLATION"]]
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
        from raykit.sandbox import kill_session
        kill_session(proc.pid)                      # and in its session (cmake, ninja, compilers)
        stray = end_descendants()                   # and whatever left it (we are its subreaper)
        log.seek(0)
        text = log.read().decode("utf-8", "replace")
    if code == -1:
        text += f"\nThe grading did not finish within {KIT_SECONDS // 60} minutes and was stopped."
    if stray:
        text += f"\n{stray} process(es) the graded code left running were stopped."
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
    from raykit.submissions import NotFound, locate

    work = Path(tempfile.mkdtemp(prefix="raykit-autograder-"))     # 0700: the sandbox reads its own copies
    try:
        try:
            found = locate(SUBMISSION, work / "upload")
        except NotFound as e:
            return failed(f"Nothing submitted: {e}", "Your upload: nothing submitted")   # the student's, not "not graded"
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
            return not_graded(f"The autograder could not grade this upload: {problem} (./kit check exit "
                              f"status {code}).\n{where}\n{tail}".strip())
        data["output"] = (where + "\n" + str(data.get("output", ""))).strip()
        return data
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main() -> int:
    start = time.monotonic()
    become_subreaper()
    closed = Closed([METADATA, AUTOGRADER]) if os.geteuid() == 0 else None
    try:
        data = grade()
    except Exception as e:      # noqa: BLE001 -- whatever happens, Gradescope gets a result
        data = not_graded(f"The autograder itself failed: {e.__class__.__name__}: {e}")
    finally:
        if closed is not None:
            closed.restore()
    data.setdefault("execution_time", round(time.monotonic() - start, 3))
    write_results(data)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Self-test: the kit's own latencies, as a student meets them, on a pseudo-terminal.

- first output: a cold `./kit check` in a handout whose steps/ hold the solutions (its build folder
  from nothing), until it prints;
- first verdict: the same run, until step 01's row shows its verdict;
- cold check: the same run, until it ends (every step configured, built and checked);
- edit to verdict: step 01's file changed, `./kit check 1` again, until it ends.

The figures depend on the machine and its load: they are reported beside the goals of issue 13
(first output within 1 s, step 01 within 8 s, all within 15 s cold, edit to verdict 1.5 s on a
quiet 2-core machine), never asserted against a clock. The self-test fails only when the run
itself goes wrong (no table, a solution step not done).
"""

from __future__ import annotations

import os
import re
import shutil
import time

from ..common import BUILD, ROOT
from .harness import Context, Failed, Screen, expect, kit, need_solutions

ANSI = re.compile(r"\033\[[0-9;]*[A-Za-z]")
HANDOUT_DIR = BUILD / "latency-handout"


def run_check(kit_dir, *args: str) -> tuple[Screen, dict]:
    """`kit_dir`/kit check ARGS on a pseudo-terminal; the times of its first output, of step 01's
    verdict and of its end."""
    screen = Screen([str(kit_dir / "kit"), "check", *args], cwd=kit_dir)
    marks: dict[str, float] = {}
    try:
        while screen.proc.poll() is None or "end" not in marks:
            text = ANSI.sub("", screen.text).replace("\r", "\n")
            if "output" not in marks and text.strip():
                marks["output"] = time.monotonic() - screen.started
            if "01" not in marks and re.search(r"^\s*01\s.*(done|cases|not started)", text, re.M):
                marks["01"] = time.monotonic() - screen.started
            if screen.proc.poll() is not None:
                time.sleep(0.1)                 # the last bytes from the terminal
                marks["end"] = time.monotonic() - screen.started
            time.sleep(0.02)
            if time.monotonic() - screen.started > 900:
                raise Failed("./kit check ran over 15 minutes")
    finally:
        screen.close()
    return screen, marks


def selftest_latency(ctx: Context) -> str:
    """Measured where students run the kit: a handout (no solutions/, so no hidden cases and no
    reference build), its build folder from nothing: first with the stubs as shipped (a newcomer's
    first check), then with step 01 written (its first verdict), then every step written."""
    need_solutions()
    shutil.rmtree(HANDOUT_DIR, ignore_errors=True)
    r = kit("handout", str(HANDOUT_DIR), "--committed", timeout=600)
    expect(r.returncode == 0, f"./kit handout failed:\n{r.stdout[-800:]}{r.stderr[-800:]}")
    screen, fresh = run_check(HANDOUT_DIR)
    expect("not started" in screen.text and "Next: step 01" in ANSI.sub("", screen.text),
           f"a newcomer's first check does not say what to do next:\n{screen.text[-800:]}")
    expect(not (HANDOUT_DIR / "build" / "student" / "CMakeCache.txt").exists(),
           "the untouched stubs were built: their state should come from tests/stubs.json")
    first = ctx.steps[0]
    for f in first.files:
        shutil.copyfile(ROOT / "solutions" / first.folder / f, HANDOUT_DIR / "steps" / first.folder / f)
    screen, one = run_check(HANDOUT_DIR, "1")
    expect(screen.proc.returncode == 0, f"step 01 written: exit {screen.proc.returncode}:\n{screen.text[-800:]}")
    shutil.rmtree(HANDOUT_DIR / "build", ignore_errors=True)
    for step in ctx.steps:
        for f in step.files:
            shutil.copyfile(ROOT / "solutions" / step.folder / f, HANDOUT_DIR / "steps" / step.folder / f)
    load = os.getloadavg()[0]
    screen, cold = run_check(HANDOUT_DIR)
    expect(screen.proc.returncode == 0, f"the cold check of the solutions exited {screen.proc.returncode}:\n"
           f"{screen.text[-1500:]}")
    expect("01" in cold, "step 01's row never showed a verdict")
    expect("building the test program" in screen.text, "no progress line while building")
    # An edit: a comment changes the file, so the step is rebuilt and checked again.
    step = ctx.steps[0]
    f = HANDOUT_DIR / "steps" / step.folder / step.files[0]
    f.write_text(f.read_text() + "\n// edited\n")
    screen, edit = run_check(HANDOUT_DIR, "1")
    expect(screen.proc.returncode == 0, f"step 01 after the edit exited {screen.proc.returncode}")
    shutil.rmtree(HANDOUT_DIR, ignore_errors=True)
    return (f"a student's ./kit check in a handout, on a terminal: a newcomer's first check (the stubs) "
            f"{fresh['end']:.2f} s (goal 2); step 01 written, its first verdict cold {one['end']:.1f} s (goal 6); "
            f"all steps written, cold: first output {cold['output']:.2f} s (goal 1), step 01's verdict "
            f"{cold['01']:.1f} s, all steps {cold['end']:.1f} s (goal 10); edit to verdict {edit['end']:.1f} s "
            f"(goal 1); load average {load:.1f} at the start")


def selftest_recorded(ctx: Context) -> str:
    """tests/stubs.json holds the committed stubs' hashes, and each tests/NN_topic/cases.json (with
    tests/hidden/cases.json) the cases its judge lists: else an untouched step would be scored on
    a stale list. `./kit check --record` writes them."""
    need_solutions()
    import json
    import subprocess
    from ..checking import HIDDEN_CASES_FILE, STUBS_FILE, ensure_configured, file_hash, list_cases
    from ..common import build_targets, preset_build
    stubs = json.loads(STUBS_FILE.read_text())
    stale = []
    for step in ctx.steps:
        for f in step.files:
            rel = f"steps/{step.folder}/{f}"
            shown = subprocess.run(["git", "show", f"HEAD:{rel}"], cwd=ROOT, capture_output=True)
            data = shown.stdout if shown.returncode == 0 else (ROOT / rel).read_bytes()
            import hashlib
            if stubs.get(f"{step.folder}/{f}") != hashlib.sha256(data).hexdigest():
                stale.append(rel)
    build = preset_build("student")
    ensure_configured(build, ctx.steps)
    ok, out = build_targets(build, [s.target for s in ctx.steps])
    expect(ok, f"the judges do not build: {out[-500:]}")
    hidden = json.loads(HIDDEN_CASES_FILE.read_text())
    for step in ctx.steps:
        listed = [(c.name, c.tier, c.lecture) for c in list_cases(build.exe(step))]
        visible = json.loads((ROOT / "tests" / step.folder / "cases.json").read_text())
        recorded = [(c["name"], c["tier"], c["lecture"]) for c in visible + hidden.get(step.number, [])]
        if sorted(listed) != sorted(recorded):
            stale.append(f"tests/{step.folder}/cases.json")
    del file_hash
    expect(not stale, "stale: " + ", ".join(stale) + ". Run ./kit check --record and commit what it writes.")
    return f"the stubs' hashes and {len(ctx.steps)} case lists are current"


def selftests() -> list:
    return [("recorded stubs and case lists", selftest_recorded), ("latency figures", selftest_latency)]

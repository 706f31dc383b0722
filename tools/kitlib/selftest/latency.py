"""Self-test: the kit's own latencies, as figures (measured, not asserted against a clock).

- cold check: a build folder from nothing, every step configured, built and graded;
- first verdict: the same cold run, until step 01's verdict is known;
- edit to verdict: one step's file changed, that step rebuilt and graded again.

The figures depend on the machine and its load; they are reported, never a pass/fail
threshold. The check fails only when grading itself goes wrong.
"""

from __future__ import annotations

import shutil
import time

from ..common import BUILD, ROOT, submission_build
from ..checking import check_steps
from ..sandbox import choose
from .harness import Context, expect, need_solutions


def check_latency(ctx: Context) -> str:
    need_solutions()
    source = BUILD / "latency-src"
    shutil.rmtree(source, ignore_errors=True)
    shutil.copytree(ROOT / "solutions", source)
    shutil.rmtree(BUILD / "latency", ignore_errors=True)
    isolation = choose("auto")
    one = [s for s in ctx.steps if s.number == "01"]

    start = time.monotonic()
    [r1] = check_steps(submission_build(source, "latency"), one, ctx.steps, isolation)
    first = time.monotonic() - start
    expect(r1.state == "done", f"step 01 of the solutions graded {r1.state}")
    results = check_steps(submission_build(source, "latency"), ctx.steps, ctx.steps, isolation)
    cold = time.monotonic() - start
    expect(all(r.state == "done" for r in results), "a solution step is not done in the cold run")

    # An edit: a comment changes the file, so the step is rebuilt and graded again.
    f = source / one[0].folder / one[0].files[0]
    f.write_text(f.read_text() + "\n// edited\n")
    start = time.monotonic()
    [r1] = check_steps(submission_build(source, "latency"), one, ctx.steps, isolation)
    edit = time.monotonic() - start
    expect(r1.state == "done", "step 01 after the edit is not done")
    shutil.rmtree(source, ignore_errors=True)
    return (f"cold check of all steps {cold:.1f} s (step 01's verdict after {first:.1f} s), "
            f"edit to verdict for step 01 {edit:.1f} s, graded code {isolation.mode}")


def checks() -> list:
    return [("latency figures", check_latency)]

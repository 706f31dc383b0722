"""Self-test: the ★ robust tier tells a careful textbook answer from a robust one.

tests/fixtures/textbook/ holds, for each sphere step, the textbook formula written with every rule
of the contract (b^2 - 4ac, (-b -+ sqrt) / 2a, |L|^2 - t_m^2). Graded like a student's work, each
must pass the whole basic tier and fail part of the robust tier, while the reference solutions pass
both (checked by "solutions pass every case"). The scoreboard must show the two tiers apart.
"""

from __future__ import annotations

from ..common import ROOT, load_steps, submission_build
from ..checking import check_steps
from ..status import DONE
from .harness import Failed, expect, kit, need_solutions

TEXTBOOK = ROOT / "tests" / "fixtures" / "textbook"


def selftest_textbook_fails_robust(ctx) -> str:
    need_solutions()   # a handout has neither solutions/ nor tests/fixtures/
    steps = load_steps()
    chosen = [s for s in steps if (TEXTBOOK / s.folder).is_dir()]
    expect(any(s.number == "02" for s in chosen), "tests/fixtures/textbook/ has no answer for step 02")
    results = check_steps(submission_build(TEXTBOOK, "fixtures"), chosen, steps)
    summary = []
    for r in results:
        basic, robust = r.tier("basic"), r.tier("robust")
        where = f"textbook step {r.step.number}"
        expect(r.state == DONE, f"{where}: graded {r.state}, expected done (it is a correct answer)")
        problem = r.first_problem("basic")
        expect(problem is None, f"{where}: basic case '{problem.name if problem else ''}' does not pass")
        expect(bool(robust), f"{where}: step {r.step.number} has no robust tier")
        failed = [c for c in robust if c.status != "pass"]
        if not failed:
            raise Failed(f"{where}: passes every robust case; the robust tier does not test robustness")
        for c in failed:
            expect(c.status == "fail", f"{where}: robust case '{c.name}' is {c.status}, expected a wrong answer")
        summary.append(f"step {r.step.number} basic {len(basic)}/{len(basic)}, robust "
                       f"{r.passed('robust')}/{len(robust)}")
    r = kit("check", "2", "--steps", str(TEXTBOOK))
    expect(r.returncode == 0, f"./kit check 2 on the textbook answer exited {r.returncode}, expected 0 (done)")
    expect("done" in r.stdout and "★ robust" in r.stdout,
           f"the scoreboard does not show the basic and robust tiers apart:\n{r.stdout[-1500:]}")
    return "textbook formula: " + "; ".join(summary)


def selftests():
    return [("robust tier catches the textbook formula", selftest_textbook_fails_robust)]

"""./kit test: the kit's self-test, for instructors and CI.

Every self-test prints one line: passed with a summary, failed with the reason, or skipped with
why; the run ends with "N passed, M failed, K skipped" and exits non-zero when anything failed.
The self-tests live in kitlib/selftest/, one module per command or concern.
"""

from __future__ import annotations

import os

from raykit.packages import ensure_packages, instructor_groups
from raykit.common import KitError, load_steps, say
from raykit.status import OK
from ..selftest.harness import MODULES, Context, collect, run_all



def register(p) -> None:
    p.add_argument("--fast", action="store_true", help="skip the slow self-tests (the sanitizer build, fuzzing)")
    p.add_argument("--quick", action="store_true",
                   help="only the quick tier: the self-tests that build and grade nothing (about half a minute)")
    p.add_argument("--step", metavar="N",
                   help="everything a change to step N needs, on that step alone: its cases against the solutions "
                        "and the stubs, the recorded case lists, its mutants, the mutants' signatures, its hints', "
                        "lecture's and slides' claims, lecture 05's scene tables (minutes, not the whole run)")
    p.add_argument("-j", "--jobs", type=int, default=1, metavar="N",
                   help="run the quick tier's self-tests (which build and measure nothing) in N processes, the "
                        "others after them one at a time (default 1)")
    p.add_argument("--list", action="store_true",
                   help="print the names of the self-tests the other options choose, one a line, and run nothing")
    p.add_argument("-k", dest="words", default="", metavar="WORDS",
                   help="run only the self-tests whose names hold WORDS (case ignored)")
    p.add_argument("modules", nargs="*", metavar="MODULE",
                   help=f"run only these modules of kitlib/selftest/ (of: {', '.join(MODULES)}); "
                        "MODULE:WORDS only its self-tests whose names hold WORDS")


def prepare() -> None:
    """The packages and environment of a self-test run (./kit test's, and unittest's in
    tools/test_selftests.py)."""
    ensure_packages(*instructor_groups())
    # No background warm-up from the checks the self-test runs on a terminal (raykit/warmup.py):
    # it would build beside the measured ones. The latency test turns it on where it measures it.
    os.environ["RAYKIT_NO_WARMUP"] = "1"


def run(args) -> int:
    unknown = [m for m in args.modules if m.partition(":")[0] not in MODULES]
    if unknown:
        raise KitError(f"no self-test module {', '.join(unknown)}; the modules are {', '.join(MODULES)}")
    if args.jobs < 1:
        raise KitError(f"-j {args.jobs}: at least 1")
    steps = None
    if args.step is not None:
        if args.quick:
            raise KitError("--step and --quick: choose one")
        wanted = args.step.zfill(2)
        steps = [s for s in load_steps() if s.number == wanted]
        if not steps:
            raise KitError(f"--step {args.step}: no such step (the steps are {', '.join(s.number for s in load_steps())})")
    if args.list:
        chosen = collect(args.modules, args.words, args.quick, step=steps is not None)
        for name, _ in chosen:
            say(name)
        say(f"{len(chosen)} self-tests")
        return OK
    if steps:
        counts = {m: len(collect([m], step=True)) for m in MODULES}
        say(f"self-test of step {steps[0].number} ({steps[0].title}): " + ", ".join(
            f"{m}: {n}" for m, n in counts.items() if n) + " self-tests")
    prepare()
    if steps:
        return run_all(Context(fast=args.fast, steps=steps), args.modules, args.words, step=True, jobs=args.jobs)
    return run_all(Context(fast=args.fast), args.modules, args.words, args.quick, jobs=args.jobs)

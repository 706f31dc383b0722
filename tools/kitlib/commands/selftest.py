"""./kit test: the kit's self-test, for instructors and CI: thin words over pytest.

The self-tests are a pytest suite, tests/kit/ (its conftest.py says how it runs): one module per
command or concern. This command turns its options into pytest's and runs pytest (Debian's
python3-pytest and python3-pytest-xdist, packages.py's "selftest" group): every self-test prints one
line, passed with its summary, failed or skipped with why; pytest's summary at the end says the
failures and skips again and counts them, and the exit status is non-zero when anything failed.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

from raykit.packages import ensure_packages, instructor_groups
from raykit.common import ROOT, KitError, load_steps, say
from raykit.status import FAILED, OK

SUITE = ROOT / "tests" / "kit"
# pytest's exit statuses (pytest.ExitCode): the tests failed; none was collected
TESTS_FAILED, NO_TESTS = 1, 5


def modules() -> list[str]:
    """The modules of tests/kit/ that hold self-tests, in the suite's file order."""
    return sorted(p.stem for p in SUITE.glob("*.py")
                  if re.search(r"^def selftest_\w+\(", p.read_text(), flags=re.M))


def register(p) -> None:
    p.add_argument("--fast", action="store_true", help="skip the slow self-tests (the sanitizer build, fuzzing)")
    p.add_argument("--quick", action="store_true",
                   help="only the quick tier (pytest -m quick): the self-tests that build and grade nothing (a minute)")
    p.add_argument("--step", metavar="N",
                   help="everything a change to step N needs, on that step alone (pytest -m step, RAYKIT_SELFTEST_STEP=N): its "
                        "cases against the solutions and the stubs, the recorded case lists, its mutants, the mutants' "
                        "signatures, its hints', lecture's and slides' claims, lecture 05's scene tables")
    p.add_argument("-j", "--jobs", type=int, default=None, metavar="N",
                   help="pytest-xdist's -n N: the quick tier's self-tests spread over N processes, the others one "
                        "after another in one of them (default: 2 with --quick, else 1)")
    p.add_argument("--list", action="store_true",
                   help="print the self-tests the other options choose, one a line, and run nothing")
    p.add_argument("-k", dest="words", default="", metavar="WORDS",
                   help="run only the self-tests whose names hold WORDS (case ignored; pytest's -k)")
    p.add_argument("modules", nargs="*", metavar="MODULE",
                   help="run only these modules of tests/kit/ (see --list); MODULE:WORDS only its self-tests whose "
                        "names hold WORDS")


def prepare() -> None:
    """The packages and environment of a self-test run (tests/kit/conftest.py calls it once a run)."""
    ensure_packages(*instructor_groups())
    # No background warm-up from the checks the self-test runs on a terminal (raykit/warmup.py):
    # it would build beside the measured ones. The latency test turns it on where it measures it.
    os.environ["RAYKIT_NO_WARMUP"] = "1"


def keyword(words: str) -> str:
    """WORDS as one pytest -k keyword: a self-test's name is its function's, words joined by _."""
    found = re.sub(r"\W+", "_", words.strip().lower(), flags=re.ASCII).strip("_")
    if not found or found in ("and", "or", "not"):
        raise KitError(f"{words!r}: name a self-test by the words of its name (./kit test --list shows them)")
    return found


def pytest_python() -> str:
    """A Python with pytest and xdist: this one, or Debian's (/usr/bin/python3, where apt installs them)."""
    probe = "import pytest, xdist"
    for python in dict.fromkeys([sys.executable, "/usr/bin/python3"]):
        if Path(python).is_file() and subprocess.run([python, "-c", probe], capture_output=True).returncode == 0:
            return python
    raise KitError("./kit test needs pytest and pytest-xdist (Debian: apt-get install python3-pytest "
                   "python3-pytest-xdist)")


def pytest_args(args) -> list[str]:
    """./kit test's options as pytest's."""
    known = modules()
    unknown = [m for m in args.modules if m.partition(":")[0] not in known]
    if unknown:
        raise KitError(f"no self-test module {', '.join(unknown)}; the modules are {', '.join(known)}")
    jobs = args.jobs if args.jobs is not None else (2 if args.quick else 1)
    if jobs < 1:
        raise KitError(f"-j {jobs}: at least 1")
    argv: list[str] = []      # pytest.ini's addopts come first (no cache folder, the summary of failures and skips)
    if args.step is not None:
        if args.quick:
            raise KitError("--step and --quick: choose one")
        if not any(s.number == args.step.zfill(2) for s in load_steps()):
            raise KitError(f"--step {args.step}: no such step (the steps are {', '.join(s.number for s in load_steps())})")
        argv += ["-m", "step"]
    elif args.quick:
        argv += ["-m", "quick"]
    chosen = [m.partition(":") for m in args.modules]
    argv += [str((SUITE / f"{name}.py").relative_to(ROOT)) for name in dict.fromkeys(n for n, _, _ in chosen)] \
        or [str(SUITE.relative_to(ROOT))]
    keywords = []
    if any(words for _, _, words in chosen):
        keywords.append(" or ".join(f"({name}.py and {keyword(words)})" if words else f"{name}.py"
                                    for name, _, words in chosen))
    if args.words:
        keywords.append(keyword(args.words))
    if keywords:
        argv += ["-k", " and ".join(f"({k})" for k in keywords)]
    if args.list:
        return argv + ["--collect-only", "-q"]
    return argv + (["-n", str(jobs)] if jobs > 1 else []) + ["-v"]


def run(args) -> int:
    argv = pytest_args(args)
    if not args.list:
        prepare()
    python = pytest_python()
    say(f"./kit test: {Path(python).name} -m pytest {' '.join(argv)}")
    env = dict(os.environ, RAYKIT_SELFTEST_STEP=args.step or "", RAYKIT_SELFTEST_FAST="1" if args.fast else "")
    r = subprocess.run([python, "-m", "pytest", *argv], cwd=ROOT, env=env)
    if r.returncode == NO_TESTS:
        raise KitError("no self-test matches " + " ".join(args.modules + ([f"-k {args.words!r}"] if args.words else [])))
    return OK if r.returncode == 0 else FAILED

"""The self-test's harness: what a self-test may raise, the context they share, and the run.

A self-test is a function `fn(ctx) -> str` that returns a one-line summary when the kit does what
it should, raises `Failed` with the reason when it does not, and raises `Skipped` with the reason
when it does not apply here (a handout has no solutions/, --fast leaves out a slow build). Each
module of this package lists its self-tests in `selftests() -> [(name, fn)]`; `MODULES` orders the
modules. A self-test of a tier (the quick one of --quick, the step one of --step N) says so next to
its function, `@tier("quick")`. A skip is counted as a skip, never as a pass.

Security tests (every self-test of SECURITY_MODULES, and any marked with `security`) may not skip
in CI (CI=true): there a skip is a failure unless the machine truly cannot do what the test needs
and .ci/run says so, in CANNOT_ENV (e.g. "root bwrap", each printed with its reason). A skip names
what it needs (`Skipped(reason, need="bwrap")`); a security test that runs in part (under one
isolation of two) reports the part it leaves out through `partly_skipped`, under the same rule.
"""

from __future__ import annotations

import hashlib
import importlib
import inspect
import os
import pty
import subprocess
import sys
import threading
import time
import traceback
import unittest
from dataclasses import dataclass, field

from raykit.cases import StepResult
from raykit.common import BUILD, QUICK_TIER, ROOT, KitError, load_steps, paint, say
from raykit.secret import SECRET_ENV
from raykit.status import FAILED, OK

# The order of ./kit test: the grading first (later self-tests reuse its builds), the slowest last.
MODULES = ["layers", "ci", "lint", "check", "course", "bench", "debug", "docs", "fuzz", "handout", "hint", "integrity",
           "boundary", "latency", "lectures", "mutant", "render", "pictures", "robust", "robust_line", "grade", "faults", "report",
           "workflow", "newstep", "customised", "watch", "reach", "sanitizers", "lab", "slides", "slips", "draws", "refresh"]

# The tiers a self-test may belong to, marked next to it with @tier(...):
# - "quick" (./kit test --quick, which .ci/run runs first): the self-tests that build and grade
#   nothing, a few seconds each, about half a minute in all. While it runs, configuring or building
#   anything raises (common.QUICK_TIER), so a test that starts to build is named, not slowly tolerated.
# - "step" (./kit test --step N): everything a change to step N needs, in minutes, run on that step
#   alone (ctx.steps): its cases against the solutions and the stubs, its case names and manifest, the
#   recorded stubs and case lists, its mutants, the mutants' signatures, its hints' and lecture's
#   sections, the header rules its cases ask, its slides, lecture 05's scene tables.
# A self-test without a marker runs in the whole run only (every self-test runs there).
TIERS = ("quick", "step")


def tier(*names: str):
    """Puts a self-test in the tiers `names` (of TIERS): `@tier("quick")` above its function, or
    `@tier("quick", "step")`. collect() fails on a marked function its module's selftests() leaves out."""
    unknown = [n for n in names if n not in TIERS]
    if unknown or not names:
        raise ValueError(f"@tier({', '.join(map(repr, names))}): the tiers are {', '.join(TIERS)}")

    def mark(fn):
        fn.tiers = frozenset(getattr(fn, "tiers", ())) | frozenset(names)
        return fn
    return mark


def tiers_of(fn) -> frozenset:
    """The tiers a self-test is marked with (empty: the whole run only)."""
    return getattr(fn, "tiers", frozenset())


@dataclass
class Context:
    fast: bool
    steps: list = field(default_factory=load_steps)
    reference: list[StepResult] | None = None


class Failed(Exception):
    """The kit does not do what the self-test expects; the message says what happened."""


class Skipped(Exception):
    """The self-test does not apply here; the message says why, `need` what the machine lacks for it
    (words of NEEDS, space-separated; "" when it is not the machine's doing)."""

    def __init__(self, reason: str, need: str = ""):
        super().__init__(reason)
        self.need = need


# --- security tests in CI ------------------------------------------------------------------------
SECURITY_MODULES = ("integrity", "boundary")
CANNOT_ENV = "RAYKIT_CI_CANNOT"     # set by .ci/run: what this machine cannot do, words of NEEDS
NEEDS = {"root": "the kit runs as root (the user isolation, Gradescope's flow, sandbox user ids)",
         "bwrap": "bubblewrap can start a sandbox here"}
_running = {"security": False}      # whether the self-test running now is a security test


def security(fn):
    """Marks a self-test of another module as a security test (see the module's docstring)."""
    fn.security = True
    return fn


def in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() in ("true", "1", "yes")


def skip_refused(need: str) -> str:
    """Why a skip of the security test running now fails here, or "" when it may skip."""
    if not (_running["security"] and in_ci()):
        return ""
    declared = set(os.environ.get(CANNOT_ENV, "").split())
    wanted = set(need.split())
    if wanted and wanted <= declared:
        return ""
    missing = " ".join(sorted(wanted - declared))
    return ("a security test may not skip in CI" + (f": .ci/run does not say this machine cannot do "
            f"'{missing}' ({CANNOT_ENV}={os.environ.get(CANNOT_ENV, '')!r})" if wanted else
            " for a reason that is not the machine's"))


def partly_skipped(need: str, reason: str) -> str:
    """`reason`, for a security test that leaves out a part it cannot run here; in CI, unless .ci/run
    declares `need`, it fails instead (Failed)."""
    refused = skip_refused(need)
    if refused:
        raise Failed(f"{reason}: {refused}")
    return reason


def need_solutions() -> None:
    # The self-test is never shipped in a handout and ./kit test refuses to run in one (cli.py), so
    # this guards only a kit whose solutions/ was removed by hand.
    if not (ROOT / "solutions").is_dir():
        raise Skipped("needs solutions/ (this is a student handout)")


def expect(condition: bool, message: str) -> None:
    if not condition:
        raise Failed(message)


def kit(*args: str, timeout: float = 600, env: dict | None = None) -> subprocess.CompletedProcess:
    """./kit ARGS; `env`: variables set for it on top of this process's."""
    return subprocess.run([str(ROOT / "kit"), *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout, env=dict(os.environ, **env) if env else None)


def last_lines(text: str, count: int) -> str:
    """The last `count` lines of `text`, each whole (a message cut mid-word says nothing)."""
    lines = text.rstrip().splitlines()
    return "\n".join((["..."] if len(lines) > count else []) + lines[-count:])


def said(r: subprocess.CompletedProcess, lines: int = 12) -> str:
    """What a command said, for a self-test's failure: its exit status, the last `lines` lines of its
    output, each whole, and its whole error output (the command's own reason, never cut)."""
    out = last_lines(r.stdout or "", lines)
    return (f"exit {r.returncode}" + (f"; its errors:\n{r.stderr.rstrip()}" if (r.stderr or "").strip() else "")
            + (f"\nits output ends:\n{out}" if out else ""))


CLEAR = "\033[2J"       # a terminal's "erase the screen"


class Screen:
    """A child process on a pseudo-terminal, and everything it has written to it."""

    def __init__(self, argv: list[str], cwd=ROOT):
        self.name = "./kit " + " ".join(argv[1:3])
        self.started = time.monotonic()
        self.master, slave = pty.openpty()
        self.proc = subprocess.Popen(argv, cwd=cwd, stdin=slave, stdout=slave, stderr=slave,
                                     start_new_session=True, close_fds=True)
        os.close(slave)
        self.text = ""
        self.lock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        while True:
            try:
                data = os.read(self.master, 65536)
            except OSError:
                return
            if not data:
                return
            with self.lock:
                self.text += data.decode(errors="replace")

    def last(self) -> str:
        """What the screen shows now: the text after the last clear."""
        with self.lock:
            return self.text.rsplit(CLEAR, 1)[-1]

    def wait_for(self, words: str, seconds: float) -> float:
        start = time.monotonic()
        while time.monotonic() - start < seconds:
            if words in self.last():
                return time.monotonic() - start
            if self.proc.poll() is not None:
                raise Failed(f"{self.name} exited {self.proc.returncode}: {self.last()[-600:]}")
            time.sleep(0.05)
        raise Failed(f"{self.name} did not show {words!r} within {seconds:g} s; the screen:\n{self.last()[-800:]}")

    def press(self, key: str) -> None:
        os.write(self.master, key.encode())

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
        self.proc.wait(timeout=10)
        os.close(self.master)


def collect(modules: list[str] | None = None, words: str = "", quick: bool = False, step: bool = False) -> list:
    """The self-tests of `modules` (default: all), in order. A module may be named MODULE:WORDS to
    take only its self-tests whose names hold WORDS; `words` does the same across all modules
    (case ignored); `quick` keeps only the quick tier's (@tier("quick")), `step` only the step tier's."""
    found = []
    for entry in modules or MODULES:
        name, _, only = entry.partition(":")
        module = importlib.import_module(f"{__package__}.{name}")
        tests = module.selftests()
        stray = unlisted_markers(module, tests)
        if stray:
            raise KitError(f"{name}: @tier marks functions its selftests() does not list: {', '.join(stray)}")
        if name in SECURITY_MODULES:
            tests = [(n, security(fn)) for n, fn in tests]
        for wanted, asked in (("quick", quick), ("step", step)):
            if asked:
                tests = [(n, fn) for n, fn in tests if wanted in tiers_of(fn)]
        for want in (only, words):
            if want:
                tests = [(n, fn) for n, fn in tests if want.lower() in n.lower()]
        found += tests
    return found


def unlisted_markers(module, tests: list) -> list[str]:
    """The functions marked with @tier in `module` (and in the modules its listed self-tests come
    from) that its selftests() does not list: a marker that selects nothing, a test renamed or dropped."""
    listed = {id(fn) for _, fn in tests}
    sources = {module.__name__: module}
    for _, fn in tests:
        origin = sys.modules.get(getattr(fn, "__module__", "") or "")
        if origin is not None:
            sources.setdefault(origin.__name__, origin)
    return sorted(f"{source}.{fn.__name__}" for source, m in sources.items() for fn in vars(m).values()
                  if inspect.isfunction(fn) and fn.__module__ == source and tiers_of(fn) and id(fn) not in listed)


def judge(ctx: Context, fn) -> tuple[str, str]:
    """Runs one self-test: ("passed", its summary), ("skipped", why) or ("failed", why), under the
    rule of security tests in CI (a skip it may not take is a failure)."""
    _running["security"] = bool(getattr(fn, "security", False))
    try:
        return "passed", fn(ctx)
    except Skipped as e:
        refused = skip_refused(e.need)
        if refused:
            return "failed", f"skipped ({e}), but {refused}"
        return "skipped", str(e)
    except (Failed, KitError) as e:
        return "failed", str(e)
    except Exception:  # a bug in the self-test itself: still report and go on
        return "failed", f"the self-test itself failed\n{traceback.format_exc()}"
    finally:
        _running["security"] = False


class Lines(unittest.TestResult):
    """unittest's result of a ./kit test run, as ./kit test prints it: one line a self-test as it ends
    (passed with its summary and time, skipped with why, failed with why), the failures kept for the
    recap. What a test returned (its summary) comes in its `outcome`."""

    def __init__(self) -> None:
        super().__init__()
        self.lines: list[str] = []          # the failures' lines, for the recap
        self.counts = {"passed": 0, "failed": 0, "skipped": 0}
        self.began = 0.0

    def startTest(self, test) -> None:
        super().startTest(test)
        self.began = time.monotonic()

    def addSuccess(self, test) -> None:
        super().addSuccess(test)
        self.counts["passed"] += 1
        say(f"{paint('✓', 'green')} {test.name}: {test.outcome} ({time.monotonic() - self.began:.1f} s)")

    def addSkip(self, test, reason: str) -> None:
        super().addSkip(test, reason)
        self.counts["skipped"] += 1
        say(f"{paint('-', 'dim')} {test.name}: skipped, {reason}")

    def addFailure(self, test, err) -> None:
        super().addFailure(test, err)
        self._failed(test, str(err[1]))

    def addError(self, test, err) -> None:      # judge() turns every exception into an outcome: a bug here
        super().addError(test, err)
        self._failed(test, "the harness itself failed\n" + "".join(traceback.format_exception(*err)))

    def _failed(self, test, why: str) -> None:
        self.counts["failed"] += 1
        line = f"{paint('✗', 'red')} {test.name}: {why}"
        say(line)
        self.lines.append(line)


def judged(case: unittest.TestCase, ctx: Context, fn, label: str = "") -> str:
    """judge() inside a unittest case (./kit test's SelfTestCase, tools/test_selftests.py's classes):
    a skip is the case's skip, a failure its failure (after `label`, when given); else the summary."""
    outcome, detail = judge(ctx, fn)
    if outcome == "skipped":
        case.skipTest(detail)
    if outcome == "failed":
        case.fail(f"{label}: {detail}" if label else detail)
    return detail


class SelfTestCase(unittest.TestCase):
    """One self-test as a unittest case: judge() runs it, a skip is unittest's skip and a failure its
    failure, under CI's rule for security tests."""

    def __init__(self, ctx: Context, name: str, fn) -> None:
        super().__init__("run_selftest")
        self.ctx, self.name, self.fn, self.outcome = ctx, name, fn, ""

    def run_selftest(self) -> None:
        self.outcome = judged(self, self.ctx, self.fn)

    def id(self) -> str:
        return self.name

    def __str__(self) -> str:
        return self.name


def run_one(ctx: Context, name: str, fn, failures: list[str] | None = None) -> str:
    """Runs one self-test through unittest and prints its line; "passed", "failed" or "skipped". A
    failure's line is also appended to `failures`, for the recap at the end of the run."""
    result = Lines()
    SelfTestCase(ctx, name, fn).run(result)
    if failures is not None:
        failures += result.lines
    return next(k for k, n in result.counts.items() if n)


_shared: dict = {}      # what the worker processes of _in_processes inherit (fork): no pickling of tests


def _share(index: int) -> tuple[dict, list[str]]:
    """A worker's share of the quick tier: every jobs-th self-test from `index`, through unittest."""
    ctx, tests, jobs = _shared["ctx"], _shared["tests"], _shared["jobs"]
    os.environ[QUICK_TIER] = "1"
    result = Lines()
    unittest.TestSuite(SelfTestCase(ctx, n, fn) for n, fn in tests[index::jobs]).run(result)
    sys.stdout.flush()
    return result.counts, result.lines


def _in_processes(ctx: Context, tests: list, jobs: int) -> list[tuple[dict, list[str]]]:
    """The quick tier's self-tests shared among `jobs` forked processes, each printing its lines as
    its tests end; their counts and failures, for the recap."""
    import multiprocessing
    if not tests:
        return []
    _shared.update(ctx=ctx, tests=tests, jobs=jobs)
    saved = os.environ.get(QUICK_TIER)
    sys.stdout.flush()
    try:
        with multiprocessing.get_context("fork").Pool(jobs) as pool:
            return pool.map(_share, range(jobs))
    finally:
        _shared.clear()
        if saved is None:
            os.environ.pop(QUICK_TIER, None)


# The recap at the end of a run keeps at most RECAP_LINES lines of a failure, and about RECAP_TOTAL
# in all (two a failure at least): a log read from its tail (CI shows the last lines of a long run)
# still names each failure and why.
RECAP_LINES = 12
RECAP_TOTAL = 48


def recap(failures: list[str]) -> None:
    """Says each failure again, shortened, just above the run's last line."""
    if not failures:
        return
    keep = max(2, min(RECAP_LINES, RECAP_TOTAL // len(failures)))
    say()
    say(f"failed ({len(failures)}):")
    for line in failures:
        lines = line.splitlines()
        say("\n".join(lines[:keep]))
        if len(lines) > keep:
            say(f"  ... {len(lines) - keep} more lines above")


def prepare() -> None:
    """What a run of self-tests sets up before the first (./kit test's, and unittest's in
    tools/test_selftests.py)."""
    BUILD.mkdir(exist_ok=True)      # the self-tests work in build/, which a fresh clone has not made yet
    # One secret for the self-test's hidden draws (raykit/secret.py): the same inputs on every run.
    os.environ.setdefault(SECRET_ENV, hashlib.sha256(b"raykit self-test secret").hexdigest())


def run_all(ctx: Context, modules: list[str] | None = None, words: str = "", quick: bool = False,
            step: bool = False, jobs: int = 1) -> int:
    """Runs the self-tests of `modules` (default: all; see collect), one line each; the exit status
    is FAILED when any failed. With `jobs` > 1, the quick tier's among them (they build nothing and
    measure nothing: common.QUICK_TIER) run first, shared among that many processes; the others
    after, one at a time (they share build folders, sandbox ids and the machine's time)."""
    chosen = collect(modules, words, quick, step)
    prepare()
    if quick:
        os.environ[QUICK_TIER] = "1"
    if not chosen:
        asked = " ".join(list(modules or []) + ([f"-k {words!r}"] if words else []))
        raise KitError(f"no self-test matches {asked}")
    counts = {"passed": 0, "failed": 0, "skipped": 0}
    lines: list[str] = []
    if jobs > 1:
        apart = [(n, fn) for n, fn in chosen if "quick" in tiers_of(fn)]
        chosen = [(n, fn) for n, fn in chosen if "quick" not in tiers_of(fn)]
        for got, failed in _in_processes(ctx, apart, jobs):
            for k in counts:
                counts[k] += got[k]
            lines += failed
    # unittest runs them (a suite in ./kit test's order; a later self-test may reuse an earlier one's
    # builds), Lines prints them as they end.
    result = Lines()
    unittest.TestSuite(SelfTestCase(ctx, name, fn) for name, fn in chosen).run(result)
    for k in counts:
        counts[k] += result.counts[k]
    recap(lines + result.lines)
    say()
    say(f"selftest: {counts['passed']} passed, {counts['failed']} failed, {counts['skipped']} skipped")
    return FAILED if counts["failed"] else OK

"""The self-test's harness: what a self-test may raise, the context they share, and the run.

A self-test is a function `fn(ctx) -> str` that returns a one-line summary when the kit does what
it should, raises `Failed` with the reason when it does not, and raises `Skipped` with the reason
when it does not apply here (a handout has no solutions/, --fast leaves out a slow build). Each
module of this package lists its self-tests in `selftests() -> [(name, fn)]`; `MODULES` orders the
modules. A skip is counted as a skip, never as a pass.

Security tests (every self-test of SECURITY_MODULES, and any marked with `security`) may not skip
in CI (CI=true): there a skip is a failure unless the machine truly cannot do what the test needs
and .ci/run says so, in CANNOT_ENV (e.g. "root bwrap", each printed with its reason). A skip names
what it needs (`Skipped(reason, need="bwrap")`); a security test that runs in part (under one
isolation of two) reports the part it leaves out through `partly_skipped`, under the same rule.
"""

from __future__ import annotations

import hashlib
import importlib
import os
import pty
import subprocess
import threading
import time
import traceback
from dataclasses import dataclass, field

from ..cases import StepResult
from ..common import BUILD, QUICK_TIER, ROOT, KitError, load_steps, paint, say
from ..secret import SECRET_ENV
from ..status import FAILED, OK

# The order of ./kit test: the grading first (later self-tests reuse its builds), the slowest last.
MODULES = ["layers", "ci", "check", "course", "bench", "debug", "docs", "fuzz", "handout", "hint", "integrity",
           "boundary", "latency", "lectures", "mutant", "render", "pictures", "robust", "robust_line", "grade", "faults", "report",
           "workflow", "newstep", "customised", "watch", "reach", "sanitizers", "lab", "slides", "slips", "draws", "refresh"]

HANDOUT = not (ROOT / "solutions").is_dir()

# The quick tier (./kit test --quick, which .ci/run runs first): the self-tests that build and grade
# nothing, a few seconds each, about half a minute in all. While it runs, configuring or building
# anything raises (common.QUICK_TIER), so a test that starts to build is named, not slowly tolerated.
QUICK = {
    "check": ["shipped stubs are 'not started'", "a handout's lectures point to what it has",
              "one verdict on every standard library: a step's missing includes",
              "numbers read the same on every standard library"],
    "course": ["course: the default scale", "course: weights, exact", "course: bad course files",
               "course: Gradescope's ★ and compile-error views", "course: Gradescope's tests add up to each step's points", "course: ★ as extra credit",
               "course: Gradescope's extra credit on the kit's course",
               "course: the scale table's example of extra credit against a bug",
               "course: reveal after the due date", "course: ./kit course", "course: step 05 runs without step 04",
               "course: a handout's total line", "course: launch.json from the steps"],
    "bench": ["bench roofline model", "bench: the front compares like with like", "bench: the student's summary",
              "bench: every figure of the reading is generated"],
    "draws": ["draws: the hidden draw follows the code, not its comments"],
    "refresh": ["refresh: the self-tests a change touches"],
    "reach": ["prairielearn: a complete course: instance, declared topic and tags, due date, definitions, lectures",
              "prairielearn: extra credit as the assessment's bonus points, a complete step 1"],
    "docs": ["docs: math filter", "docs: an npm install the network failed is tried once more",
             "docs: the student loop's GitHub workflow (macOS, Ubuntu) names what the kit has"],
    "handout": ["handout: no step code"],
    "hint": ["hint order: what fails first"],
    "mutant": ["fixtures kept as patches apply, a broken one is named"],
    "layers": ["layers: imports go downwards, no cycle", "layers: one atomic write", "layers: one /proc reader",
               "layers: the kit's modules compiled once, into its cache"],
    "ci": ["ci: a skipped security test fails in CI", "ci: failures said again at the end"],
    "lectures": ["numbers quoted from the benchmark are current", "★ grading figures are current",
                 "the pitfalls' pictures are committed and current", "lecture 05's tables are the scene file's",
                 "hints point to lecture sections that exist", "every rule a header states has a case",
                 "the README's step table is the steps' manifests'"],
    "pictures": ["pictures: degenerate input", "pictures: the pitfall gallery"],
    "robust_line": ["★ lines: sections in words", "★ pointers: one section each",
                    "messages name the trouble, not the cure"],
    "grade": ["uploads: step files found at any depth, only they"],
    "report": ["report: the charts say what their data says",
               "report: the mutants' signatures are current", "report: crashes grouped by the record, not by words",
               "report: extra credit apart, scores on the CSV's decimals",
               "report: a looping step is matched to no slip"],
    "slips": ["slips: waiting step's next command", "slips: a ray seen end-on",
              "slips: the picture and refusals come after direct cases",
              "slips: every platform leads with the terminal's case"],
    "slides": ["slides: decks have notes, Ponder answers and the step's command",
               "slides: a deck says what its lecture and its step's cases say"],
}

# ./kit test --step N: everything a change to step N needs, in minutes, run on that step alone
# (ctx.steps): its cases against the solutions and the stubs, its case names and manifest, the recorded
# stubs and case lists, its mutants, the mutants' signatures, its hints' and lecture's sections, the
# header rules its cases ask, its slides, lecture 05's scene tables. Named here, next to QUICK, so a
# renamed self-test fails loudly (collect checks the names).
STEP = {
    "check": ["solutions pass every case", "shipped stubs are 'not started'", "case names and lecture pointers",
              "step functions and manifests"],
    "latency": ["recorded stubs and case lists"],
    "mutant": ["mutants are caught"],
    "report": ["report: the mutants' signatures are current"],
    "lectures": ["lecture 05's tables are the scene file's", "hints point to lecture sections that exist",
                 "every rule a header states has a case", "the README's step table is the steps' manifests'"],
    "hint": ["hints"],
    "slides": ["slides: decks have notes, Ponder answers and the step's command",
               "slides: a deck says what its lecture and its step's cases say"],
}


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
    if HANDOUT:
        raise Skipped("needs solutions/ (this is a student handout)")


def expect(condition: bool, message: str) -> None:
    if not condition:
        raise Failed(message)


def kit(*args: str, timeout: float = 600, env: dict | None = None) -> subprocess.CompletedProcess:
    """./kit ARGS; `env`: variables set for it on top of this process's."""
    return subprocess.run([str(ROOT / "kit"), *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout, env=dict(os.environ, **env) if env else None)


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
    (case ignored); `quick` keeps only the quick tier's (QUICK), `step` only those of STEP."""
    found = []
    for entry in modules or MODULES:
        name, _, only = entry.partition(":")
        tests = importlib.import_module(f"{__package__}.{name}").selftests()
        if name in SECURITY_MODULES:
            tests = [(n, security(fn)) for n, fn in tests]
        for tier, table in (("QUICK", QUICK), ("STEP", STEP)):
            if tier == "QUICK" and not quick or tier == "STEP" and not step:
                continue
            missing = [n for n in table.get(name, []) if n not in {t for t, _ in tests}]
            if missing:
                raise KitError(f"harness.{tier} names self-tests {name} does not have: {missing}")
            tests = [(n, fn) for n, fn in tests if n in table.get(name, [])]
        for want in (only, words):
            if want:
                tests = [(n, fn) for n, fn in tests if want.lower() in n.lower()]
        found += tests
    return found


def run_one(ctx: Context, name: str, fn, failures: list[str] | None = None) -> str:
    """Runs one self-test and prints its line; "passed", "failed" or "skipped". A failure's line is
    also appended to `failures`, for the recap at the end of the run."""
    start = time.monotonic()
    _running["security"] = bool(getattr(fn, "security", False))

    def failed(line: str) -> str:
        say(line)
        if failures is not None:
            failures.append(line)
        return "failed"
    try:
        detail = fn(ctx)
        say(f"{paint('✓', 'green')} {name}: {detail} ({time.monotonic() - start:.1f} s)")
        return "passed"
    except Skipped as e:
        refused = skip_refused(e.need)
        if refused:
            return failed(f"{paint('✗', 'red')} {name}: skipped ({e}), but {refused}")
        say(f"{paint('-', 'dim')} {name}: skipped, {e}")
        return "skipped"
    except (Failed, KitError) as e:
        return failed(f"{paint('✗', 'red')} {name}: {e}")
    except Exception:  # a bug in the self-test itself: still report and go on
        return failed(f"{paint('✗', 'red')} {name}: the self-test itself failed\n{traceback.format_exc()}")
    finally:
        _running["security"] = False


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


def run_all(ctx: Context, modules: list[str] | None = None, words: str = "", quick: bool = False,
            step: bool = False) -> int:
    """Runs the self-tests of `modules` (default: all; see collect), one line each; the exit status
    is FAILED when any failed."""
    counts = {"passed": 0, "failed": 0, "skipped": 0}
    chosen = collect(modules, words, quick, step)
    BUILD.mkdir(exist_ok=True)      # the self-tests work in build/, which a fresh clone has not made yet
    # One secret for the self-test's hidden draws (kitlib/secret.py): the same inputs on every run.
    os.environ.setdefault(SECRET_ENV, hashlib.sha256(b"raykit self-test secret").hexdigest())
    if quick:
        os.environ[QUICK_TIER] = "1"
    if not chosen:
        asked = " ".join(list(modules or []) + ([f"-k {words!r}"] if words else []))
        raise KitError(f"no self-test matches {asked}")
    failures: list[str] = []
    for name, fn in chosen:
        counts[run_one(ctx, name, fn, failures)] += 1
    recap(failures)
    say()
    say(f"selftest: {counts['passed']} passed, {counts['failed']} failed, {counts['skipped']} skipped")
    return FAILED if counts["failed"] else OK

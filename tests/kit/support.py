"""What the self-tests share: what a self-test may raise, the kit's context, the rule of security
tests in CI, and helpers to run ./kit and read what it said. pytest runs them (conftest.py).

A self-test is a function `selftest_NAME(ctx)` of a module of tests/kit/; it returns a one-line
summary when the kit does what it should (`-v` prints it), raises `Failed` (an AssertionError, or
`expect(condition, message)`) with the reason when it does not, and `Skipped` (pytest's skip) with
the reason when it does not apply here (a handout has no solutions/, --fast leaves out a slow build).
A skip is counted as a skip, never as a pass.

Security tests (marked `security`: every self-test of integrity.py, integrity_slots.py and
boundary.py, and any marked so elsewhere) may not skip in CI (CI=true): there a skip is a failure
unless the machine truly cannot do what the test needs and .ci/run says so, in CANNOT_ENV (e.g.
"root bwrap", each printed with its reason). A skip names what it needs (`Skipped(reason,
need="bwrap")`); a security test that runs in part (under one isolation of two) reports the part it
leaves out through `partly_skipped`, under the same rule. conftest.py's hook applies the rule.
"""

from __future__ import annotations

import hashlib
import os
import pty
import subprocess
import shutil
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from raykit.cases import StepResult
from raykit.common import BUILD, ROOT, load_steps
from raykit.secret import SECRET_ENV


@dataclass
class Context:
    fast: bool
    steps: list = field(default_factory=load_steps)
    reference: list[StepResult] | None = None


class Failed(AssertionError):
    """The kit does not do what the self-test expects; the message says what happened. pytest reports
    it as the test's failure."""


class Skipped(pytest.skip.Exception):
    """The self-test does not apply here (pytest's skip); the message says why, `need` what the machine
    lacks for it (words of NEEDS, space-separated; "" when it is not the machine's doing)."""

    def __init__(self, reason: str, need: str = ""):
        super().__init__(reason)
        self.need = need

    def __str__(self) -> str:
        return self.msg or ""


# --- security tests in CI ------------------------------------------------------------------------
CANNOT_ENV = "RAYKIT_CI_CANNOT"     # set by .ci/run: what this machine cannot do, words of NEEDS
NEEDS = {"root": "the kit runs as root (the user isolation, Gradescope's flow, sandbox user ids)",
         "bwrap": "bubblewrap can start a sandbox here"}
_running = {"security": False}      # whether the self-test running now is a security test (conftest.py sets it)


def in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() in ("true", "1", "yes")


def skip_refused(need: str, security: bool | None = None) -> str:
    """Why a skip of a security test (`security`; None: the test running now) fails here, or "" when
    it may skip."""
    if not ((_running["security"] if security is None else security) and in_ci()):
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


def chromium_or_skip():
    """(kitlib.browser, the Chromium it drives) for a self-test in a browser: installed when it can be
    (packages.py's "browser"), else the test is skipped, naming what is missing."""
    from kitlib import browser
    from raykit.common import KitError
    from raykit.packages import ensure_packages
    try:
        ensure_packages("browser")
    except KitError as e:
        raise Skipped(f"Chromium is not installed and could not be ({str(e).splitlines()[0]})")
    found = browser.find_chromium()
    if found is None:
        raise Skipped("no chromium on the PATH (sudo apt-get install chromium)")
    return browser, found


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


def committed_steps(dest: Path) -> Path:
    """steps/ as committed (the stubs a handout ships) written to DEST/steps, which it returns: a test of
    the stubs reads this copy, never the working tree's steps/, where an instructor may keep answers. In
    a copy of the kit without git history, steps/ as it is."""
    from kitlib.commands import handout as cmd_handout
    steps = dest / "steps"
    shutil.rmtree(steps, ignore_errors=True)
    try:
        files = cmd_handout.committed_steps()
    except Exception:       # noqa: BLE001 -- no git, or not a repository: a copy of the kit
        shutil.copytree(ROOT / "steps", steps)
        return steps
    for name, data in files.items():
        path = dest / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    return steps


def prepare() -> None:
    """What a run of self-tests sets up before the first (conftest.py, once a process)."""
    BUILD.mkdir(exist_ok=True)      # the self-tests work in build/, which a fresh clone has not made yet
    # One secret for the self-test's hidden draws (raykit/secret.py): the same inputs on every run.
    os.environ.setdefault(SECRET_ENV, hashlib.sha256(b"raykit self-test secret").hexdigest())

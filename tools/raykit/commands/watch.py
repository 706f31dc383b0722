"""./kit watch [N]: check the step being worked on at every save, until q or Ctrl-C.

The screen is redrawn after each check (not appended to). The step shown is the one whose file was
saved last; a step stays on screen until its ★ robust cases pass too, or the student presses n.
Saves are seen by each file's size and modification time; every CONTENT_SECONDS the contents are
compared as well, so an editor or a network folder that keeps the time stamp is noticed (and said).
Keys: r re-check now, n next step, q quit.

Each check runs in a process of its own (`Check`), so a save, a key or q while it runs stops it at once,
with every process it started (a build, a judge, a student's endless loop), and the next check starts
from the file as saved: a fix is checked when it is saved, not after the check of the broken file ends.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import select
import signal
import subprocess
import sys
import termios
import time
import tty
from contextlib import suppress
from pathlib import Path

from .. import picture, studentpch
from ..checking import LastCheck, OneResult, check_steps
from ..sandbox import NONE_OWN
from ..common import BUILD, ROOT, load_steps, paint, resolve_steps_dir, say, select_steps
from ..build import preset_build, submission_build
from ..packages import ensure_packages
from ..scoreboard import rel, scoreboard
from ..status import DONE, OK

CONTENT_SECONDS = 2.0


def register(p) -> None:
    p.add_argument("number", nargs="?", metavar="N", help="the step to start with (default: the first not done)")
    p.add_argument("--steps", metavar="DIR", help="watch the steps in DIR instead of steps/")
    # How often the files' stamps are looked at: a save waits half of it on average before its check
    # starts. A look is a stat of each step's files, nothing more.
    p.add_argument("--interval", type=float, default=0.1, help=argparse.SUPPRESS)


def stamps(source: Path, step) -> tuple:
    """A step's files as (size, modification time) pairs: what a save changes."""
    out = []
    for f in step.files:
        try:
            st = (source / step.folder / f).stat()
            out.append((st.st_size, st.st_mtime_ns))
        except FileNotFoundError:
            out.append(None)
    return tuple(out)


def digest(source: Path, step) -> str:
    h = hashlib.sha256()
    for f in step.files:
        try:
            h.update((source / step.folder / f).read_bytes())
        except OSError:
            h.update(b"\0missing")
    return h.hexdigest()


class Keys:
    """Single key presses from the terminal, without waiting (cbreak mode, restored on exit).
    Without a terminal (a pipe), the characters written to it count the same."""

    def __init__(self):
        self.fd = sys.stdin.fileno() if sys.stdin and not sys.stdin.closed else None
        self.saved = None
        self.open = self.fd is not None

    def __enter__(self):
        if self.fd is not None and os.isatty(self.fd):
            self.saved = termios.tcgetattr(self.fd)
            tty.setcbreak(self.fd)
        return self

    def __exit__(self, *exc):
        if self.saved is not None:
            termios.tcsetattr(self.fd, termios.TCSADRAIN, self.saved)

    def get(self, timeout: float) -> str:
        if not self.open:
            time.sleep(timeout)
            return ""
        ready, _, _ = select.select([self.fd], [], [], timeout)
        if not ready:
            return ""
        data = os.read(self.fd, 1)
        if not data:                # end of input: keep watching the files
            self.open = False
        return data.decode(errors="replace").lower()


def descendants(pid: int) -> list[int]:
    """Every process below `pid`, children first found first (`ps`: Linux and macOS alike)."""
    try:
        out = subprocess.run(["ps", "-A", "-o", "pid=", "-o", "ppid="], capture_output=True, text=True,
                             timeout=10).stdout
    except (OSError, subprocess.TimeoutExpired):
        return []
    children: dict[int, list[int]] = {}
    for line in out.splitlines():
        words = line.split()
        if len(words) == 2 and words[0].isdigit() and words[1].isdigit():
            children.setdefault(int(words[1]), []).append(int(words[0]))
    found, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            if child not in found:
                found.append(child)
                todo.append(child)
    return found


class Check:
    """One step's check in a child process of its own, which can be stopped whole; its result comes
    back through the last-check store (checking.LastCheck), as ./kit hint reads it."""

    def __init__(self, build, step, all_steps):
        self.build, self.step, self.all_steps = build, step, all_steps
        folder = BUILD / "watch-checks"       # (BUILD / "watch" is --steps's build folder)
        folder.mkdir(parents=True, exist_ok=True)
        self.path = folder / f"check-{os.getpid()}.json"
        self.path.unlink(missing_ok=True)
        sys.stdout.flush()
        self.pid = os.fork()
        if self.pid == 0:       # the child: check, keep the result, leave without Python's clean-up
            code = 1
            try:
                os.setsid()
                [result] = check_steps(build, [step], all_steps)
                OneResult(self.path, build, all_steps).store(result, everything=True)
                LastCheck(build, all_steps, NONE_OWN).keep([result])      # for ./kit hint
                code = 0
            except BaseException as e:          # noqa: BLE001: said, then the parent says it failed
                print(f"kit: the check stopped: {e}", file=sys.stderr)
            finally:
                os._exit(code)
        self.status: int | None = None

    def done(self) -> bool:
        if self.status is None:
            pid, status = os.waitpid(self.pid, os.WNOHANG)
            if pid == self.pid:
                self.status = status
        return self.status is not None

    def result(self):
        if self.status != 0:
            return None
        found = OneResult(self.path, self.build, self.all_steps).load(self.step)
        self.path.unlink(missing_ok=True)
        return found

    def stop(self) -> None:
        """Ends the check and everything it started (a judge's answers program runs in a process
        group of its own, so the group of the check alone would leave a student's loop running)."""
        if self.done():
            return
        for pid in [self.pid] + descendants(self.pid):
            with suppress(OSError):
                os.kill(pid, signal.SIGKILL)
        os.waitpid(self.pid, 0)
        self.status = -1


def clear() -> None:
    if sys.stdout.isatty():
        print("\033[2J\033[H", end="")


def banner_text(passed: list, current) -> str:
    """"Step 01 is done, ★ cases included. On to step 02.", naming the steps found done already after
    it: the first step of `passed` is the one the save (or key) had checked."""
    first, rest = passed[0], passed[1:]
    text = f"Step {first.number} is done, ★ cases included."
    if len(rest) == 1:
        text += f" Step {rest[0].number} was done already."
    elif rest:
        text += f" Steps {rest[0].number} to {rest[-1].number} were done already."
    return text + f" On to step {current.number}."


def run(args) -> int:
    ensure_packages("build")
    # Every save compiles the step's file again: the step headers precompiled (studentpch.py) are built
    # the first time one is needed, here as in ./kit grade, so that a save's compile no longer reads
    # GLM and the standard library (step 01: about 0.35 s of CPU a save without, 0.14 s with; step 05
    # 1.1 and 0.6 s, a check in a handout with docs/watch_latency.py's saves, at load 16; CPU, so the
    # load matters less than for the wall time). "off" in the environment still wins.
    os.environ.setdefault(studentpch.ENV, "build")
    if not args.steps:
        return _watch(args, None)
    # A folder of this session's own (runfolders.py): a second watch, or a check, of another folder
    # never stages its files where this one compiles.
    from .. import runfolders
    with runfolders.private("watch") as folder:
        return _watch(args, folder)


def _watch(args, folder) -> int:
    all_steps = load_steps()
    source = resolve_steps_dir(args.steps) if args.steps else ROOT / "steps"

    def build():
        return submission_build(source, "watch", folder) if args.steps else preset_build("student")

    def later(step):
        return next((s for s in all_steps if s.number > step.number), None)

    say(paint("./kit watch: checking your steps ...", "dim"))
    if args.number:
        current = select_steps(all_steps, [args.number])[0]
    else:
        results = check_steps(build(), all_steps, all_steps)
        current = next((r.step for r in results if r.state != DONE), all_steps[-1])
    seen = {s.number: stamps(source, s) for s in all_steps}
    contents = {s.number: digest(source, s) for s in all_steps}
    last_content_look = time.monotonic()
    blind = False
    banner = ""
    passed: list = []       # the steps found complete one after another since the last save or key
    due = True
    running: Check | None = None
    stopped = False         # the check before was stopped by a save or a key
    with Keys() as keys:
        try:
            while True:
                if due:
                    due = False
                    if running is not None:
                        running.stop()
                    clear()
                    say(paint(f"./kit watch · step {current.number} · {time.strftime('%H:%M:%S')} · checking ...", "dim"))
                    if passed:      # the save's verdict, at once: not after the next step's check
                        say(paint(banner_text(passed, current), "green"))
                    if stopped:
                        say(paint("(the check that was running stopped: this one checks the files as saved)", "dim"))
                        stopped = False
                    running = Check(build(), current, all_steps)
                if running is not None and running.done():
                    check, running = running, None
                    result = check.result()
                    if result is None:
                        [result] = check_steps(build(), [current], all_steps)     # the child failed: here
                    picture.draw_results([result], picture.pictures_folder(BUILD, args.steps and source), False)
                    robust = result.tier("robust")
                    complete = result.state == DONE and result.passed("robust") == len(robust)
                    if complete and later(current):
                        # On to the next step; one already done is passed over, and the banner names
                        # the step that was checked for the save first, not the last one passed over.
                        passed.append(current)
                        current = later(current)
                        due = True
                        continue
                    if passed:
                        banner = banner_text(passed, current)
                        passed = []
                    clear()
                    say(paint(f"./kit watch · step {current.number} · {time.strftime('%H:%M:%S')}", "dim"))
                    if banner:
                        say(paint(banner, "green"))
                        banner = ""
                    say()
                    scoreboard([result], source, watching=True)
                    say()
                    if result.state == DONE and not complete:
                        say(paint(f"Step {current.number} is done. Its ★ cases are optional: work on them, "
                                  "or press n for the next step.", "green"))
                    if blind:
                        say(paint("Saves did not change the files' time stamps here (a network folder or an "
                                  f"editor that keeps them): the contents are compared every {CONTENT_SECONDS:g} s; "
                                  "press r to re-check at once.", "yellow"))
                    keys_line = "save to re-check · r re-check now · " + ("n next step · " if later(current) else "") \
                        + "q quit"
                    say(paint(f"watching {rel(source)}/ · {keys_line}", "dim"))
                key = keys.get(args.interval)
                if key == "q":
                    break
                # A save or a key starts a new run of steps passed (a run it stops names none of them).
                if key == "r":
                    due, passed = True, []
                elif key == "n" and later(current):
                    current, due, passed = later(current), True, []
                for s in all_steps:               # the step whose file was saved becomes the current one
                    now = stamps(source, s)
                    if now != seen[s.number]:
                        seen[s.number] = now
                        contents[s.number] = digest(source, s)
                        current, due, passed = s, True, []
                if time.monotonic() - last_content_look >= CONTENT_SECONDS:
                    last_content_look = time.monotonic()
                    for s in all_steps:
                        d = digest(source, s)
                        if d != contents[s.number]:
                            contents[s.number] = d
                            current, due, blind, passed = s, True, True, []
                if due and running is not None:
                    stopped = True
        except KeyboardInterrupt:
            pass
        finally:
            if running is not None:
                running.stop()
    say("\nstopped watching.")
    return OK

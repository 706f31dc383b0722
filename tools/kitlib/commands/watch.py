"""./kit watch [N]: regrade the current step whenever a step file changes, until Ctrl-C."""

from __future__ import annotations

import sys
import time
from pathlib import Path

from ..scoreboard import rel, scoreboard
from ..common import ROOT, load_steps, paint, preset_build, resolve_steps_dir, say, select_steps, submission_build
from ..packages import ensure_packages
from ..checking import check_steps
from ..status import DONE, OK



def register(p) -> None:
    p.add_argument("number", nargs="?", metavar="N", help="the step to start with (default: the first not done)")
    p.add_argument("--steps", metavar="DIR", help="watch the steps in DIR instead of steps/")
    p.add_argument("--interval", type=float, default=0.25, help=argparse_hidden())


def argparse_hidden():
    import argparse
    return argparse.SUPPRESS


def snapshot(source: Path, steps) -> tuple:
    """What changed is judged by each step file's size and modification time."""
    state = []
    for s in steps:
        for f in s.files:
            p = source / s.folder / f
            try:
                st = p.stat()
                state.append((str(p), st.st_mtime_ns, st.st_size))
            except FileNotFoundError:
                state.append((str(p), None, None))
    return tuple(state)


def clear() -> None:
    if sys.stdout.isatty():
        print("\033[2J\033[H", end="")


def run(args) -> int:
    ensure_packages("build")
    all_steps = load_steps()
    source = resolve_steps_dir(args.steps) if args.steps else ROOT / "steps"

    def build():
        return submission_build(source, "watch") if args.steps else preset_build("student")

    if args.number:
        current = select_steps(all_steps, [args.number])[0]
    else:
        results = check_steps(build(), all_steps, all_steps)
        current = next((r.step for r in results if r.state != DONE), all_steps[-1])
    seen = None
    try:
        while True:
            now = snapshot(source, all_steps)
            if now != seen:
                seen = now
                clear()
                say(paint(f"./kit watch · step {current.number} · {time.strftime('%H:%M:%S')} · grading ...", "dim"))
                [result] = check_steps(build(), [current], all_steps)
                clear()
                scoreboard([result], source)
                if result.state == DONE:
                    later = [s for s in all_steps if s.number > current.number]
                    if later:
                        say(paint(f"\nStep {current.number} is done. Moving on to step {later[0].number}.", "green"))
                        current = later[0]
                        seen = None
                        continue
                say(paint(f"\nwatching {rel(source)}/{current.folder}/ · save a file to regrade · Ctrl-C to stop",
                          "dim"))
            time.sleep(args.interval)
    except KeyboardInterrupt:
        say("\nstopped watching.")
        return OK

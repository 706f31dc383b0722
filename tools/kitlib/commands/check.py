"""./kit check: check the student's steps (kitlib/checking.py) and print the scoreboard
(kitlib/scoreboard.py); --json writes Gradescope's format (kitlib/gradescope.py)."""

from __future__ import annotations

import argparse
import time

from ..checking import check_steps
from .. import picture
from ..common import BUILD, KitError, load_steps, preset_build, resolve_steps_dir, select_steps, submission_build
from ..gradescope import write_json
from ..packages import ensure_packages
from ..sandbox import NONE_OWN, choose
from ..scoreboard import LiveProgress, scoreboard
from ..status import DONE, FAILED, OK


def register(p) -> None:
    p.add_argument("numbers", nargs="*", metavar="N", help="step numbers (default: all)")
    p.add_argument("--steps", metavar="DIR", help="check the steps in DIR instead of steps/ (DIR is not modified)")
    p.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    p.add_argument("--quiet", action="store_true", help="print nothing; the exit status tells")
    p.add_argument("--isolation", choices=["auto", "bwrap", "user", "none"],
                   help="how the graded code is kept apart (default: auto with --steps, none for your own steps/)")
    p.add_argument("--hidden-visibility", default=None,  # None: course.json's hidden.visibility
                   choices=["hidden", "after_due_date", "after_published", "visible"],
                   help="Gradescope visibility of the hidden cases in --json (default: course.json's)")
    p.add_argument("--reveal", action="store_true", help="show the inputs of failed hidden cases (instructors)")
    p.add_argument("--all", action="store_true", help="list every failing case of the steps, grouped by function")
    p.add_argument("--slot", type=int, default=0, help=argparse.SUPPRESS)  # ./kit grade -j: build folder and sandbox


def run(args) -> int:
    all_steps = load_steps()
    steps = select_steps(all_steps, args.numbers)
    if args.steps:
        source = resolve_steps_dir(args.steps)
        build = submission_build(source, "submission" if args.slot == 0 else f"submission-{args.slot}")
    else:
        build = preset_build("student")
        source = build.steps_dir
    wanted = args.isolation or ("auto" if args.steps else "none")
    try:
        isolation = NONE_OWN if wanted == "none" and not args.steps else choose(wanted, args.slot)
    except RuntimeError as e:
        raise KitError(f"--isolation {wanted}: {e}")
    if args.json:  # fail early on a path we cannot write, before any building
        write_json(args.json, [], 0.0, args.hidden_visibility, args.reveal)
    # The table's heading at once, each step's row as soon as it is checked (a cold build takes a while).
    live = None if args.quiet else LiveProgress(source, steps)
    ensure_packages("build")
    start = time.monotonic()
    try:
        results = check_steps(build, steps, all_steps, isolation, live)
    finally:
        if live:
            live.close()
    if not args.quiet:      # a picture per failing sphere or rectangle case (not for class grading)
        picture.draw_results(results, BUILD / ("pictures" if args.slot == 0 else f"pictures-{args.slot}"),
                             args.reveal)
    if args.json:
        write_json(args.json, results, time.monotonic() - start, args.hidden_visibility, args.reveal)
    if not args.quiet:
        scoreboard(results, source, args.all, args.reveal, table_shown=True)
    return OK if all(r.state == DONE for r in results) else FAILED

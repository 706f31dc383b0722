"""./kit check: check the student's steps (raykit/checking.py) and print the scoreboard
(raykit/scoreboard.py); --results writes the kit's own record (raykit/record.py), --json
Gradescope's format (raykit/gradescope.py), --prairielearn and --classroom those platforms'
(raykit/plresults.py, raykit/classroomresults.py), all from the same results."""

from __future__ import annotations

import argparse
import time

from ..checking import check_steps
from .. import classroomresults, faults, picture, plresults, record, runfolders, warmup
from ..common import BUILD, ROOT, KitError, load_steps, say, note, printable, resolve_steps_dir, select_steps
from ..build import preset_build, submission_build
from ..submissions import NotFound, locate
from ..gradescope import write_json
from ..packages import ensure_packages
from ..sandbox import NONE_OWN, choose
from ..scoreboard import LiveProgress, scoreboard
from ..status import DONE, FAILED, OK


def register(p) -> None:
    p.add_argument("numbers", nargs="*", metavar="N", help="step numbers (default: all)")
    p.add_argument("--steps", metavar="DIR", help="check the steps in DIR instead of steps/ (DIR is not modified)")
    p.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    p.add_argument("--results", metavar="FILE",
                   help="also write the kit's own results record (raykit/record.py): every case, hidden "
                        "inputs included; for the grader's side only")
    p.add_argument("--prairielearn", metavar="FILE",
                   help="also write the results in PrairieLearn's external-grader format (raykit/plresults.py)")
    p.add_argument("--prairielearn-part", choices=["step", "extra"], default="step",
                   help="which question --prairielearn grades: the step's points (default), or its extra-credit "
                        "cases alone (the step's extra-credit question of ./kit prairielearn)")
    p.add_argument("--classroom", metavar="FILE",
                   help="also write each step's GitHub Classroom result, for tools/classroom/result.py "
                        "(raykit/classroomresults.py)")
    p.add_argument("--identity", default="", metavar="TEXT",
                   help="the submission's name on its platform (e.g. gradescope:ID), part of the hidden "
                        "cases' seed (raykit/secret.py)")
    p.add_argument("--quiet", action="store_true", help="print nothing; the exit status tells")
    p.add_argument("--isolation", choices=["auto", "bwrap", "user", "none"],
                   help="how the graded code is kept apart (default: auto with --steps, none for your own steps/)")
    p.add_argument("--hidden-visibility", default=None,  # None: course.json's hidden.visibility
                   choices=["hidden", "after_due_date", "after_published", "visible"],
                   help="Gradescope visibility of the hidden cases in --json (default: course.json's)")
    p.add_argument("--reveal", action="store_true", help="show the inputs of failed hidden cases (instructors)")
    p.add_argument("--all", action="store_true", help="list every failing case of the steps, grouped by function")
    p.add_argument("--record", action="store_true",
                   help="instructors: record the stubs' hashes and every judge's cases (tests/stubs.json, "
                        "tests/NN_topic/cases.json; of the steps named, else all), so untouched steps are checked without a build")
    p.add_argument("--slot", type=int, default=0, help=argparse.SUPPRESS)  # ./kit grade -j: build folder and sandbox
    p.add_argument("--warm-up", action="store_true", help=argparse.SUPPRESS)  # raykit/warmup.py, in the background


def record_cases(numbers: list[str]) -> int:
    """Records the stubs' hashes and the case lists of the steps named (all when none is: a new
    step's `./kit check N --record` builds only its own judge)."""
    from .. import bundle
    from ..build import detect_undefined
    from ..checking import hidden_cases_here, record
    if not hidden_cases_here():
        raise KitError("--record needs solutions/ and tests/hidden/ (the instructor's copy)")
    ensure_packages("build")
    all_steps = load_steps()
    steps = select_steps(all_steps, numbers)
    kit = bundle.ensure(detect_undefined())
    for path in record(kit, steps, all_steps):
        say(f"wrote {path.relative_to(ROOT)}")
    return OK


def run(args) -> int:
    if args.record:
        return record_cases(args.numbers)
    all_steps = load_steps()
    if args.warm_up:
        return warmup.run(preset_build("student"))
    if args.steps:
        # A folder of this run's own (runfolders.py): two checks at once in one clone never share one.
        with runfolders.private("check") as folder:
            return checked(args, all_steps, folder)
    with runfolders.using(BUILD / "student", "./kit check"):   # steps/: one check at a time
        return checked(args, all_steps, None)


def checked(args, all_steps, folder) -> int:
    steps = select_steps(all_steps, args.numbers)
    if args.steps:
        # One file finder for every folder the kit did not write (here, ./kit grade, the
        # autograders): it copies regular files only, so a link to the kit's answers never
        # reaches the build, and it caps the files and the time it spends.
        shown = resolve_steps_dir(args.steps)
        try:
            found = locate(shown, folder / "upload", all_steps)
        except NotFound as e:
            raise KitError(f"--steps {args.steps}: {e}")
        for n in found.notes:
            note(f"kit: {printable(n)}")
        source = found.steps_dir
        build = submission_build(source, "submission" if args.slot == 0 else f"submission-{args.slot}", folder)
        build.shown_dir = display = shown
        build.identity = args.identity
    else:
        build = preset_build("student")
        source = display = build.steps_dir
    wanted = args.isolation or ("auto" if args.steps else "none")
    try:
        isolation = NONE_OWN if wanted == "none" and not args.steps else choose(wanted, args.slot)
    except RuntimeError as e:
        raise KitError(f"--isolation {wanted}: {e}")
    if args.json:  # fail early on a path we cannot write, before any building
        write_json(args.json, [], 0.0, args.hidden_visibility, args.reveal)
    if args.results:    # the placeholder: a record that says it is none (finished: false)
        record.write(args.results, record.make([], 0.0, finished=False))
    if args.classroom:
        classroomresults.write(args.classroom, [])
    faults.after_placeholder()      # the self-test's killed check (raykit/faults.py)
    # The table's heading at once, each step's row as soon as it is checked (a cold build takes a while).
    live = None if args.quiet else LiveProgress(display, steps)
    ensure_packages("build")
    start = time.monotonic()
    try:
        results = check_steps(build, steps, all_steps, isolation, live)
    finally:
        if live:
            live.close()
        isolation.close()       # every process the graded code left, its control group, its files
    if not args.quiet:      # a picture per failing sphere or rectangle case (not for class grading)
        picture.draw_results(results, picture.pictures_folder(BUILD, args.steps and display, args.slot),
                             args.reveal)
    elapsed = time.monotonic() - start
    if args.results:
        record.write(args.results, record.make(results, elapsed, args.identity))
    if args.json:
        write_json(args.json, results, elapsed, args.hidden_visibility, args.reveal)
    if args.prairielearn:
        plresults.write(args.prairielearn, results, str(display) if args.steps else "", args.prairielearn_part)
    if args.classroom:
        classroomresults.write(args.classroom, results)
    if not args.quiet:
        scoreboard(results, display, args.all, args.reveal, table_shown=True)
    if not args.quiet and not args.json and not args.prairielearn and not args.classroom:
        from ..checking import LastCheck       # for ./kit hint: the same files need no new run
        LastCheck(build, all_steps, isolation).keep(results)
    if not args.steps and not args.quiet and not args.json and not args.classroom and warmup.wanted(build):
        warmup.start(build)     # nothing was built: the kit's side, while the task is read
        if warmup.running(build):
            note("(the kit's own test programs are building in the background while you read the task, "
                 "so your first check of a step you wrote comes sooner)")
    return OK if all(r.state == DONE for r in results) else FAILED

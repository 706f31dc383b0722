"""./kit course: the course's scale (course.json, read by raykit/course.py) as a table: each step's
cases per group, their points, and the total to enter in Gradescope."""

from __future__ import annotations

from pathlib import Path

from raykit import course as course_file
from raykit import record as results_record
from raykit.common import KitError, load_steps, say
from raykit.status import OK


def register(p) -> None:
    p.add_argument("--file", metavar="FILE", help="read this course file instead of course.json (to try a scale)")
    p.add_argument("--results", metavar="FILE",
                   help="take the cases from a results record of ./kit check --results")
    p.add_argument("--build", action="store_true",
                   help="list the cases from the steps' test programs, built now, instead of their records "
                        "(tests/NN_topic/cases.json, written by ./kit check --record)")


def cases_from_results(path: Path) -> dict[str, list[tuple[str, str, str]]]:
    try:
        data = results_record.read(path)
        return {s["step"]: [(c["tier"], c["name"], c.get("lecture", "")) for c in s["cases"]] for s in data["steps"]}
    except (KeyError, TypeError) as e:
        raise KitError(f"--results {path}: a record without its cases ({e.__class__.__name__})")


def cases_recorded(steps) -> dict[str, list[tuple[str, str]]] | None:
    """The steps' cases as recorded (tests/NN_topic/cases.json, tests/hidden/cases.json): no build, so
    the first ./kit course of a fresh clone answers at once. None when a step has no record."""
    from raykit.checking import recorded_cases
    found = {}
    for s in steps:
        cases = recorded_cases(s)
        if cases is None:
            return None
        found[s.number] = [(c.tier, c.name, c.lecture) for c in cases]
    return found


def cases_from_build(steps) -> dict[str, list[tuple[str, str]]]:
    """The kit's side (bundle.py: no student code), built once, and its judges' cases."""
    from raykit import bundle
    from raykit.build import detect_undefined
    from raykit.runcases import list_cases
    from raykit.packages import ensure_packages
    ensure_packages("build")
    kit = bundle.ensure(detect_undefined(), lambda: say(
        f"building the kit's side once (the test programs of {len(steps)} steps) to list their cases ..."))
    return {s.number: [(c.tier, c.name, c.lecture) for c in list_cases(kit.judge(s))] for s in steps}


def run(args) -> int:
    from .. import manifest
    manifest.check()        # every step's step.json of the current form, a wrong field named
    steps = load_steps()
    numbers = [s.number for s in steps]
    course = course_file.read(Path(args.file), numbers) if args.file else course_file.load()
    if args.file and not Path(args.file).is_file():
        raise KitError(f"--file {args.file}: no such file")
    found = (cases_from_results(Path(args.results)) if args.results
             else None if args.build else cases_recorded(steps)) or cases_from_build(steps)
    for line in course_file.table(course, [(s.number, s.title, found.get(s.number, [])) for s in steps]):
        say(line)
    unmatched = [f"steps.{s.number}.weights {k!r}" for s in steps
                 for k in course.unmatched_weights(s.number, found.get(s.number, []))]
    if unmatched:
        raise KitError(f"{course.source}: {', '.join(unmatched)} gives no counted case its weight: a case's "
                       "name as the table's step lists it, or \"section N\" of the step's lecture")
    return OK

"""./kit hint N: the step's hints, one more each time (a nudge first, then the formula; never code).

The first hint given is the one about the lecture section the first failing case points to (taken from
the last ./kit check when the step's files are the same as then, checking.LastCheck; else the step's
cases are run for that, as ./kit check N would; the first failing case is the one ./kit check shows,
StepResult.first_problem: of the section whose cases fail in the largest share); of two hints about that section, the one that names
the function the case called comes before one that names none, and one about another function of the
step comes last (a tie in find_intersection gets the strict-comparison hint, not the listing order's).
Then the rest in their fixed order. A hint's section is
what it cites, "(section 4)" or "(sections 2 and 3)"; a hint about another lecture's sections
("lecture 03, sections 5 and 6") is not tied to them.
"""

from __future__ import annotations

import re

from ..common import BUILD, ROOT, KitError, load_steps, paint, say, select_steps
from ..status import NOT_GRADED, DONE, FAILED, MISSING, NOT_STARTED, NO_COMPILE, OK, PARTIAL, WAITING

# "section 4", "sections 5 and 6", "sections 2, 3 and 4", "section 2. The ray meets the sphere".
SECTION = re.compile(r"\bsections?\s+(\d+(?:\s*(?:,|and|to)\s*\d+)*)", re.I)
OTHER_LECTURE = re.compile(r"lecture\s+\d+,?\s+sections?\s+\d+(?:\s*(?:,|and|to)\s*\d+)*", re.I)


def register(p) -> None:
    p.add_argument("number", metavar="N", help="the step number")
    p.add_argument("--all", action="store_true", help="show every hint so far and the next one")
    p.add_argument("--reset", action="store_true", help="start again from the first hint")
    p.add_argument("--no-run", action="store_true",
                   help="do not run the step's cases to find what fails: the hints in their fixed order")
    p.add_argument("--steps", metavar="DIR", help="look at the steps in DIR instead of steps/ (DIR is not modified)")


def load_hints(step) -> list[str]:
    path = ROOT / "tests" / step.folder / "hints.md"
    if not path.is_file():
        return []
    parts = re.split(r"^---\s*$", path.read_text(), flags=re.M)
    return [p.strip() for p in parts if p.strip()]


def hint_sections(hint: str) -> set[str]:
    """The numbers of the step's lecture sections a hint cites (another lecture's are left out)."""
    text = OTHER_LECTURE.sub("", hint)
    numbers: set[str] = set()
    for m in SECTION.finditer(text):
        bounds = re.findall(r"\d+", m.group(1))
        if " to " in m.group(1) and len(bounds) == 2:      # "sections 4 to 6"
            numbers.update(str(n) for n in range(int(bounds[0]), int(bounds[1]) + 1))
        else:
            numbers.update(bounds)
    return numbers


def section_of(pointer: str) -> str:
    """A case's pointer, "4. What the discriminant says" -> "4" ("" when it has no number)."""
    m = re.match(r"\s*(\d+)\.", pointer or "")
    return m.group(1) if m else ""


def names(hint: str, functions) -> set:
    return {f for f in functions if re.search(rf"\b{re.escape(f)}\b", hint)}


def choose(hints: list[str], shown: list[int], section: str, function: str = "", functions=()) -> int | None:
    """The next hint (1-based): of those not yet shown that cite `section`, the first that names
    `function` (the failing case's), else the first that names none of the step's `functions`, else
    the first; with none citing it, the first not yet shown. None when every hint has been shown."""
    unseen = [i for i in range(1, len(hints) + 1) if i not in shown]
    if not unseen:
        return None
    if section:
        tied = [i for i in unseen if section in hint_sections(hints[i - 1])]
        if tied:
            def rank(i):
                named = names(hints[i - 1], functions)
                return 0 if function in named else 1 if not named else 2
            return min(tied, key=lambda i: (rank(i) if function else 0, i))
    return unseen[0]


def read_state(path, count: int) -> list[int]:
    """The hints shown so far, in the order shown ("shown 5,1"). An older kit wrote how many: "2" is [1, 2]."""
    try:
        text = path.read_text().strip()
    except OSError:
        return []
    numbers = [int(n) for n in re.findall(r"\d+", text)]
    if not text.startswith("shown") and len(numbers) == 1:
        numbers = list(range(1, numbers[0] + 1))
    return [n for n in dict.fromkeys(numbers) if 1 <= n <= count]


def write_state(path, order: list[int]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("shown " + ",".join(map(str, order)) + "\n")


def first_failing(step, steps_dir: str | None):
    """The first case of `step` that fails (basic, then hidden, then ★), or None: from the last ./kit
    check when the step's files are the same as then (checking.LastCheck), else by running its cases.
    The third value says which."""
    from ..common import resolve_steps_dir     # imported here: ./kit hint --no-run builds nothing
    from ..build import preset_build, submission_build
    from ..packages import ensure_packages
    from ..sandbox import NONE_OWN, choose as isolation_for
    from contextlib import ExitStack
    from .. import runfolders
    ensure_packages("build")
    with ExitStack() as held:
        if steps_dir:  # a folder the kit did not write: as ./kit check --steps, in a folder of its own
            folder = held.enter_context(runfolders.private("hint"))
            build = submission_build(resolve_steps_dir(steps_dir), "submission", folder)
            isolation = isolation_for("auto", 0)
        else:
            held.enter_context(runfolders.using(BUILD / "student", "./kit hint"))
            build, isolation = preset_build("student"), NONE_OWN
        return _first_failing(step, build, isolation)


def _first_failing(step, build, isolation):
    from ..checking import LastCheck, check_steps
    result = LastCheck(build, load_steps(), isolation).load(step)
    reused = result is not None
    if result is None:
        say(paint(f"kit: running step {step.number}'s cases to see what fails (--no-run: the hints in order)", "dim"))
        [result] = check_steps(build, [step], load_steps(), isolation)
    else:
        say(paint(f"kit: step {step.number}'s files are as your last ./kit check saw them: its first failing case "
                  "is taken from there", "dim"))
    tiers = ("basic", "hidden", "robust") if result.state in (PARTIAL, DONE) else ()
    return result.state, next((c for t in tiers if (c := result.first_problem(t)) is not None), None), reused


def run(args) -> int:
    [step] = select_steps(load_steps(), [args.number])
    hints = load_hints(step)
    if not hints:
        raise KitError(f"step {step.number} has no hints yet; read {step.lecture}", FAILED)
    state = BUILD / "hints" / step.number
    if args.reset:
        state.unlink(missing_ok=True)
        say(f"Hints for step {step.number} start again from the first.")
        return OK
    shown = read_state(state, len(hints))
    if len(shown) == len(hints) and not args.all:
        say(paint(f"No hint is left: you have seen all {len(hints)} hints of step {step.number}. The lecture, "
                  f"{step.lecture}, has the rest; ./kit hint {int(step.number)} --all shows them again, "
                  f"--reset starts over.", "dim"))
        return OK
    case, why = None, ""
    if not args.no_run and len(shown) < len(hints):
        # On stdout, as the hint is: piped or redirected, the two keep their order.
        try:
            status, case, _ = first_failing(step, args.steps)
        except KitError:
            raise          # a mistake the user can fix (--steps names no folder): say so
        except Exception as e:  # a hint must still come when the grading cannot run
            status, why = NOT_GRADED, f"the cases could not run ({e})"
        if case is None and not why:
            why = {NOT_STARTED: "nothing written yet", NO_COMPILE: "the code does not compile",
                   MISSING: "a file is missing", WAITING: "an earlier step comes first",
                   DONE: "every case passes"}.get(status, status)
    section = section_of(case.lecture) if case is not None else ""
    from ..scoreboard import function_of
    function = function_of(case) if case is not None else ""
    nxt = choose(hints, shown, section, function, step.functions)
    last = nxt is None
    if last:
        nxt = shown[-1] if shown else len(hints)
    order = shown + ([nxt] if nxt not in shown else [])
    for i in (order if args.all else [nxt]):
        # Numbered in the order this student was given them, which the section of the failing case
        # chooses: "Hint 3 of 5" for the first one seen, beside "4 hints left", read as a miscount.
        say(paint(f"Hint {order.index(i) + 1} of {len(hints)} · step {step.number}, {step.title}", "bold"))
        if i == nxt and section and section in hint_sections(hints[i - 1]):
            say(paint(f"(your first failing case, \"{case.name}\", points to section \"{case.lecture}\")", "dim"))
        say(hints[i - 1])
        say()
    if case is not None and section and not (section in hint_sections(hints[nxt - 1])):
        say(paint(f"Your first failing case, \"{case.name}\", points to section \"{case.lecture}\" of "
                  f"{step.lecture}; no hint left is about it.", "dim"))
    elif why and not args.no_run:
        say(paint(f"({why}: the hints in their order)", "dim"))
    if len(order) < len(hints):
        left = len(hints) - len(order)
        say(paint(f"{left} hint{'s' if left > 1 else ''} left: run ./kit hint {int(step.number)} again for the next one.",
                  "dim"))
    else:
        say(paint(f"That was the last hint. The lecture, {step.lecture}, has the rest.", "dim"))
    write_state(state, order)
    return OK

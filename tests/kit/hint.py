"""Self-test: every step has hints, given one at a time, that never contain code; the first is about what fails."""

from __future__ import annotations

import re

import pytest

from raykit.commands.hint import choose, hint_sections, load_hints
from raykit.common import load_steps
from .support import Failed, expect, kit, need_solutions

CODE = re.compile(r";\s*$|[{}]|\bfor\s*\(|\bif\s*\(", re.M)


@pytest.mark.step
def selftest_hints(ctx) -> str:
    counts = []
    for step in ctx.steps:
        hints = load_hints(step)
        expect(len(hints) >= 3, f"step {step.number} has {len(hints)} hints, at least 3 are expected")
        for i, h in enumerate(hints, 1):
            m = CODE.search(h)
            if m:
                raise Failed(f"step {step.number} hint {i} looks like code ({m.group(0)!r}): hints give the idea, not the code")
        counts.append(len(hints))
    n = str(int(ctx.steps[0].number))
    first = kit("hint", n, "--reset")
    one, two = kit("hint", n), kit("hint", n)
    kit("hint", n, "--reset")
    expect(first.returncode == 0 and one.returncode == 0 and "Hint 1 of" in one.stdout and "Hint 2 of" in two.stdout
           and "Hint 1 of" not in two.stdout, "./kit hint does not give one more hint per call")
    return "hints per step: " + ", ".join(map(str, counts)) + "; one more per call; no code in any"


@pytest.mark.quick
def selftest_hint_choice(ctx) -> str:
    """The first hint is the one about the section of the first failing case, then the fixed order."""

    hints = ["a (section 2)", "b (sections 3 and 4)", "c (section 4)", "d (lecture 03, section 5)", "e"]
    cases = [([], "4", 2), ([2], "4", 3), ([2, 3], "4", 1), ([], "5", 1), ([], "", 1), ([1, 2, 3, 4, 5], "4", None)]
    for shown, section, want in cases:
        got = choose(hints, shown, section)
        expect(got == want, f"after hints {shown}, a failure in section {section or '(none)'} gives hint {got}, "
                            f"expected {want}")
    expect(hint_sections("(sections 4 to 6, and lecture 03, sections 7 and 8)") == {"4", "5", "6"},
           "the sections a hint cites are read wrong")
    # Two hints about the failing section: the one naming the failing function first, then one naming
    # none, one about another function last. Step 05's tie in find_intersection (section 4): the
    # strict-comparison hint, not the listing-order one, which names no function.
    named = ["a (section 4)", "render does it (section 4)", "find_hit does it (section 4)"]
    functions = ["render", "find_hit"]
    for function, want in (("find_hit", 3), ("render", 2), ("other", 1), ("", 1)):
        got = choose(named, [], "4", function, functions)
        expect(got == want, f"a failure of {function or '(no function)'} in section 4 gives hint {got}, expected {want}")
    step5 = next(s for s in load_steps() if s.number == "05")
    hints5 = load_hints(step5)
    got = choose(hints5, [], "4", "find_intersection", step5.functions)
    expect(got is not None and "find_intersection" in hints5[got - 1],
           f"step 05's tie in find_intersection gets hint {got}: {hints5[(got or 1) - 1][:80]!r}")
    return f"{len(cases) + 5} choices as intended (step 05's tie: hint {got}, about find_intersection)"


def selftest_hint_looks_at_failure(ctx) -> str:
    """A step 01 whose window is open fails a case of section 5: the first hint is the window's, not hint 1."""
    import shutil
    import tempfile
    from pathlib import Path

    from raykit.mutants import MUTANTS, write_answer
    from raykit.common import BUILD

    need_solutions()  # the mutant is the reference with one slip
    step = load_steps()[0]
    hints = load_hints(step)
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="hint-"))
    n = str(int(step.number))

    def said(number: int, run) -> bool:
        """Whether `run` printed hint `number` of the file (its first line): the header counts the
        hints this student has been given, not their place in the file."""
        return hints[number - 1].strip().splitlines()[0] in run.stdout

    try:
        write_answer(step, MUTANTS / step.folder / "open_window.patch", work / step.folder)
        # Files of this run's own (the last check is kept by content: an earlier run of this self-test
        # left one for the same files), so the first hint has no last check to take.
        answer = next(p for p in (work / step.folder).iterdir() if p.suffix == ".cpp")
        answer.write_text(answer.read_text() + f"\n// {work.name}\n")
        tied = [i for i, h in enumerate(hints, 1) if "5" in hint_sections(h)]
        expect(tied and tied[0] != 1, f"step {step.number}: no hint but the first cites section 5: the check "
                                      "cannot tell the two orders apart")
        kit("hint", n, "--reset")
        first, second = kit("hint", n, "--steps", str(work)), kit("hint", n, "--steps", str(work))
        running, shown = first.stdout.find("kit: running step"), first.stdout.find("Hint ")
        expect(0 <= running < shown, "piped, ./kit hint does not print 'kit: running step ...' before the hint:\n"
               + first.stdout[:400])
        expect(first.returncode == 0 and f"Hint 1 of {len(hints)}" in first.stdout and said(tied[0], first)
               and "points to section \"5." in first.stdout,
               f"with the window open (a case of section 5 fails), ./kit hint {n} gave:\n{first.stdout}{first.stderr}")
        expect(second.returncode == 0 and f"Hint 2 of {len(hints)}" in second.stdout and said(1, second),
               f"the second ./kit hint {n} does not go on with the fixed order:\n{second.stdout}")
        plain = kit("hint", n, "--no-run")
        expect("Hint 3 of" in plain.stdout and said(2, plain), f"--no-run after hints {tied[0]} and 1 does not give hint 2:\n{plain.stdout}")
        # After a ./kit check of the same files, the hint takes the failing case from it: no run.
        kit("check", n, "--steps", str(work))
        kit("hint", n, "--reset")
        reused = kit("hint", n, "--steps", str(work))
        expect("kit: running step" not in reused.stdout and "as your last ./kit check saw them" in reused.stdout
               and f"Hint 1 of {len(hints)}" in reused.stdout and said(tied[0], reused),
               f"after ./kit check, ./kit hint {n} ran the cases again or chose another hint:\n{reused.stdout}")
        source = next(p for p in (work / step.folder).iterdir() if p.suffix == ".cpp")
        source.write_text(source.read_text() + "\nint raykit_selftest_changed = 1;\n")
        kit("hint", n, "--reset")
        changed = kit("hint", n, "--steps", str(work))
        expect("kit: running step" in changed.stdout, f"a changed file reused the last check:\n{changed.stdout}")
    finally:
        kit("hint", n, "--reset")
        shutil.rmtree(work, ignore_errors=True)
    return (f"an open window fails in section 5: hint {tied[0]} first, then 1, 2; piped, the progress line first; "
            "after ./kit check the same files' case is reused, a changed file is run")


def selftest_hint_end(ctx) -> str:
    """Once every hint is shown: "No hint is left", the hints not printed again, no "run again"."""
    step = load_steps()[0]
    n, count = str(int(step.number)), len(load_hints(step))
    kit("hint", n, "--reset")
    try:
        runs = [kit("hint", n, "--no-run") for _ in range(count + 1)]
    finally:
        kit("hint", n, "--reset")
    again = [i + 1 for i, r in enumerate(runs) if "again for the next one" in r.stdout]
    expect(again == list(range(1, count)), f"'run ./kit hint {n} again' printed after runs {again} of {count + 1} "
           f"({count} hints)")
    expect("That was the last hint" in runs[count - 1].stdout, "the last hint does not say it is the last")
    end = runs[count]
    expect(end.returncode == 0 and "No hint is left" in end.stdout and "Hint " not in end.stdout,
           f"./kit hint {n} after all {count} hints:\n{end.stdout}")
    return f"{count} hints, 'again' after the first {count - 1} only, then 'No hint is left'"

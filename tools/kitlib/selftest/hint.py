"""Self-test: every step has hints, given one at a time, that never contain code; the first is about what fails."""

from __future__ import annotations

import re

from ..commands.hint import choose, hint_sections, load_hints
from ..common import load_steps
from .harness import Failed, expect, kit, need_solutions

CODE = re.compile(r";\s*$|[{}]|\bfor\s*\(|\bif\s*\(", re.M)


def selftest_hints(ctx) -> str:
    counts = []
    for step in load_steps():
        hints = load_hints(step)
        expect(len(hints) >= 3, f"step {step.number} has {len(hints)} hints, at least 3 are expected")
        for i, h in enumerate(hints, 1):
            m = CODE.search(h)
            if m:
                raise Failed(f"step {step.number} hint {i} looks like code ({m.group(0)!r}): hints give the idea, not the code")
        counts.append(len(hints))
    n = str(int(load_steps()[0].number))
    first = kit("hint", n, "--reset")
    one, two = kit("hint", n), kit("hint", n)
    kit("hint", n, "--reset")
    expect(first.returncode == 0 and one.returncode == 0 and "Hint 1 of" in one.stdout and "Hint 2 of" in two.stdout
           and "Hint 1 of" not in two.stdout, "./kit hint does not give one more hint per call")
    return "hints per step: " + ", ".join(map(str, counts)) + "; one more per call; no code in any"


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
    return f"{len(cases)} choices as intended"


def selftest_hint_looks_at_failure(ctx) -> str:
    """A step 01 whose window is open fails a case of section 5: the first hint is the window's, not hint 1."""
    import shutil
    import tempfile
    from pathlib import Path

    from ..commands.mutant import MUTANTS, write_answer
    from ..common import BUILD

    need_solutions()  # the mutant is the reference with one slip
    step = load_steps()[0]
    hints = load_hints(step)
    work = Path(tempfile.mkdtemp(dir=BUILD, prefix="hint-"))
    n = str(int(step.number))
    try:
        write_answer(step, MUTANTS / step.folder / "open_window.patch", work / step.folder)
        tied = [i for i, h in enumerate(hints, 1) if "5" in hint_sections(h)]
        expect(tied and tied[0] != 1, f"step {step.number}: no hint but the first cites section 5: the check "
                                      "cannot tell the two orders apart")
        kit("hint", n, "--reset")
        first, second = kit("hint", n, "--steps", str(work)), kit("hint", n, "--steps", str(work))
        expect(first.returncode == 0 and f"Hint {tied[0]} of {len(hints)}" in first.stdout
               and "points to section \"5." in first.stdout,
               f"with the window open (a case of section 5 fails), ./kit hint {n} gave:\n{first.stdout}{first.stderr}")
        expect(second.returncode == 0 and f"Hint 1 of {len(hints)}" in second.stdout,
               f"the second ./kit hint {n} does not go on with the fixed order:\n{second.stdout}")
        plain = kit("hint", n, "--no-run")
        expect("Hint 2 of" in plain.stdout, f"--no-run after hints {tied[0]} and 1 does not give hint 2:\n{plain.stdout}")
    finally:
        kit("hint", n, "--reset")
        shutil.rmtree(work, ignore_errors=True)
    return f"an open window fails in section 5: hint {tied[0]} first, then 1, 2"


def selftests():
    return [("hints", selftest_hints), ("hint order: what fails first", selftest_hint_choice),
            ("hint looks at the failing case", selftest_hint_looks_at_failure)]

"""Self-test: every step has hints, given one at a time, that never contain code."""

from __future__ import annotations

import re

from ..commands.hint import load_hints
from ..common import load_steps
from .harness import Failed, expect, kit

CODE = re.compile(r";\s*$|[{}]|\bfor\s*\(|\bif\s*\(", re.M)


def check_hints(ctx) -> str:
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


def checks():
    return [("hints", check_hints)]

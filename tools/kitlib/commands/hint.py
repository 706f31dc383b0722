"""./kit hint N: the step's hints, one more each time (a nudge first, then the formula; never code)."""

from __future__ import annotations

import re

from ..common import BUILD, ROOT, KitError, load_steps, paint, say, select_steps
from ..status import FAILED, OK



def register(p) -> None:
    p.add_argument("number", metavar="N", help="the step number")
    p.add_argument("--all", action="store_true", help="show every hint so far and the next one")
    p.add_argument("--reset", action="store_true", help="start again from the first hint")


def load_hints(step) -> list[str]:
    path = ROOT / "tests" / step.folder / "hints.md"
    if not path.is_file():
        return []
    parts = re.split(r"^---\s*$", path.read_text(), flags=re.M)
    return [p.strip() for p in parts if p.strip()]


def run(args) -> int:
    [step] = select_steps(load_steps(), [args.number])
    hints = load_hints(step)
    if not hints:
        raise KitError(f"step {step.number} has no hints yet; read {step.lecture}", FAILED)
    state = BUILD / "hints" / step.number
    shown = 0 if args.reset or not state.exists() else int(state.read_text() or 0)
    if args.reset:
        state.unlink(missing_ok=True)
        say(f"Hints for step {step.number} start again from the first.")
        return OK
    nxt = min(shown + 1, len(hints))
    first = 1 if args.all else nxt
    for i in range(first, nxt + 1):
        say(paint(f"Hint {i} of {len(hints)} · step {step.number}, {step.title}", "bold"))
        say(hints[i - 1])
        say()
    if nxt < len(hints):
        say(paint(f"Run ./kit hint {int(step.number)} again for the next one.", "dim"))
    else:
        say(paint(f"That was the last hint. The lecture, {step.lecture}, has the rest.", "dim"))
    state.parent.mkdir(parents=True, exist_ok=True)
    state.write_text(str(nxt))
    return OK

"""./kit reset N: put step N's shipped stub back, keeping the student's file beside it."""

from __future__ import annotations

import shutil
import subprocess
import sys
import time
from pathlib import Path

from .. import atomic
from ..common import ROOT, KitError, load_steps, say, select_steps
from ..status import FAILED, OK


# Where a handout keeps the stubs it shipped (written by ./kit handout); in the
# instructor's clone the committed version in git is the shipped one.
SHIPPED = ROOT / "tools" / "stubs"


def register(p) -> None:
    p.add_argument("number", metavar="N", help="the step to reset")
    p.add_argument("--yes", action="store_true", help="do not ask")


def shipped_stub(rel: str) -> bytes:
    copy = SHIPPED / Path(rel).relative_to("steps")
    if copy.is_file():
        return copy.read_bytes()
    if (ROOT / ".git").exists() and shutil.which("git"):
        r = subprocess.run(["git", "show", f"HEAD:{rel}"], cwd=ROOT, capture_output=True)
        if r.returncode == 0:
            return r.stdout
    raise KitError(f"cannot find the shipped version of {rel} (no {SHIPPED.relative_to(ROOT)}/ and no git)", FAILED)


def run(args) -> int:
    [step] = select_steps(load_steps(), [args.number])
    files = [f"steps/{step.folder}/{f}" for f in step.files]
    stubs = {rel: shipped_stub(rel) for rel in files}
    changed = [rel for rel in files if not (ROOT / rel).is_file() or (ROOT / rel).read_bytes() != stubs[rel]]
    if not changed:
        say(f"step {step.number} is already the shipped stub; nothing to do")
        return OK
    if not args.yes:
        if not sys.stdin.isatty():
            raise KitError("not asking without a terminal: add --yes to reset " + ", ".join(changed))
        answer = input(f"Put the stub back in {', '.join(changed)}? Your file is kept beside it. [y/N] ")
        if answer.strip().lower() not in ("y", "yes"):
            say("nothing changed")
            return FAILED
    stamp = time.strftime("%Y%m%d-%H%M%S")
    for rel in changed:
        target = ROOT / rel
        if target.is_file():
            backup = target.with_name(f"{target.name}.bak-{stamp}")
            shutil.copy2(target, backup)
            say(f"kept your {rel} as {backup.relative_to(ROOT)}")
        atomic.write(target, stubs[rel])
        say(f"{rel}: the shipped stub is back")
    say(f"Next: ./kit check {int(step.number)}")
    return OK

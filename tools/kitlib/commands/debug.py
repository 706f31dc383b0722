"""./kit debug N [CASE]: run one case of a step under gdb, stopped in the student's own function,
built without optimisation and with debug information.

The judge (test_stepNN) never runs the student's code itself: it starts the answers program as a
child and sends it each call. So gdb follows the child across fork and exec, then sets breakpoints
on the step's functions (the judge's own functions of the same name are only proxies). The call's
time limit is lifted while debugging, or the judge would end a paused child after 2 s.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
from pathlib import Path

from ..checking import check_steps, ensure_configured, list_cases, submission_seed
from ..common import BUILD, KitError, load_steps, resolve_steps_dir, say, select_steps
from ..build import Build, build_targets, preset_build, submission_build
from ..packages import ensure_packages
from ..status import FAILED, OK, PASS, SETUP

NO_LIMIT_SECONDS = "86400"


def register(p) -> None:
    p.add_argument("number", metavar="N", help="the step")
    p.add_argument("case", nargs="?", metavar="CASE",
                   help="the case's name, or a part of it (default: the step's first failing case)")
    p.add_argument("--steps", metavar="DIR", help="debug the steps in DIR instead of steps/ (DIR is not modified)")
    p.add_argument("--batch", action="store_true", help=argparse.SUPPRESS)  # the self-test: stop, bt, end
    p.add_argument("--print", action="store_true", dest="print_only",
                   help="print the gdb command instead of running it (for an IDE or a script)")


def gdb_script(functions: list[str]) -> str:
    lines = ["set pagination off", "set confirm off",
             "set follow-fork-mode child", "set detach-on-fork on", "set breakpoint pending on",
             "catch exec", "run",          # stops once the answers program (your code) has started
             "delete"]
    lines += [f"break raykit::{f}" for f in functions]
    lines += ["echo \\n[raykit] Stopped in your code. bt: where; p NAME: a value; n: next line; "
              "s: step in; c: continue; q: quit.\\n", "continue"]
    return "\n".join(lines) + "\n"


def pick_case(exe: Path, wanted: str | None, build, step, all_steps) -> str:
    names = [c.name for c in list_cases(exe) if c.tier != "hidden"]
    if wanted:
        exact = [n for n in names if n == wanted]
        found = exact or [n for n in names if wanted.lower() in n.lower()]
        if not found:
            raise KitError(f"step {step.number} has no case named like {wanted!r}; ./kit check "
                           f"{int(step.number)} --all lists the failing ones")
        if len(found) > 1:
            raise KitError(f"{len(found)} cases of step {step.number} match {wanted!r}: "
                           + "; ".join(found[:5]) + ("; ..." if len(found) > 5 else "") + ". Name one of them.")
        return found[0]
    [result] = check_steps(build, [step], all_steps)
    failing = [c for c in result.cases if c.status != PASS and c.tier != "hidden"]
    if not failing:
        raise KitError(f"every case of step {step.number} passes; name a case to debug it anyway", FAILED)
    return failing[0].name


def run(args) -> int:
    ensure_packages("build", "debug")
    all_steps = load_steps()
    [step] = select_steps(all_steps, [args.number])
    # Its own build folder without optimisation (preset "debug"): every variable can be printed and
    # every line stepped through; a --steps folder is staged first, as ./kit check --steps does.
    staged = submission_build(resolve_steps_dir(args.steps), "debug") if args.steps else preset_build("student")
    build = Build("debug", BUILD / "debug-build", staged.steps_dir, staged.shown_dir, preset="debug", tools=False)
    ensure_configured(build, all_steps)
    ok, _ = build_targets(build, [step.target, f"answers_step{step.number}"])
    if not ok:
        raise KitError(f"step {step.number} does not build; ./kit check {int(step.number)} shows why", FAILED)
    case = pick_case(build.exe(step), args.case, build, step, all_steps)
    script = build.binary_dir / f"step{step.number}.gdb"
    script.parent.mkdir(parents=True, exist_ok=True)
    script.write_text(gdb_script(step.functions))
    env = dict(os.environ, RAYKIT_CALL_SECONDS=NO_LIMIT_SECONDS, RAYKIT_SEED=submission_seed(build, step))
    batch = ["-batch", "-ex", "bt"] if args.batch else []
    argv = ["gdb", "-q", *batch[:1], "-x", str(script), *batch[1:], "--args", str(build.exe(step)), f"--test-case={case}",
            "--no-breaks=true"]
    if args.print_only:
        say(f"RAYKIT_CALL_SECONDS={NO_LIMIT_SECONDS} " + " ".join(a if " " not in a else repr(a) for a in argv))
        return OK
    if shutil.which("gdb") is None:
        raise KitError("gdb is not on the PATH; install it: sudo apt-get install gdb", SETUP)
    say(f"Debugging step {step.number}, case \"{case}\": gdb stops in your "
        + ", ".join(step.functions) + ".")
    sys.stdout.flush()
    os.execvpe("gdb", argv, env)
    return OK  # not reached: gdb replaced this process

"""./kit debug N [CASE]: run one case of a step under gdb, or lldb where there is no gdb (a Mac),
stopped in the student's own function, built without optimisation and with debug information.

The judge (test_stepNN) never runs the student's code itself: it starts the answers program as a
child and sends it each call. So the debugger follows the child across fork and exec, then sets
breakpoints on the step's functions (the judge's own functions of the same name are only proxies).
LLDB on Linux follows the fork and stops at the exec but does not load the new program's symbols:
the debug build links the answers program at a fixed address (RAYKIT_DEBUGGER_NO_PIE), and the
script loads them there. The call's time limit is lifted while debugging, or the judge would end a
paused child after 2 s. The case's name and the debugger are checked before anything is built.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
from pathlib import Path

from ..checking import check_steps, ensure_configured, list_cases, recorded_cases, submission_seed
from ..common import BUILD, KitError, load_steps, resolve_steps_dir, say, select_steps
from ..build import Build, build_targets, preset_build, submission_build
from ..packages import ensure_packages, family, has_apt, install_line
from ..status import FAILED, OK, PASS, SETUP

NO_LIMIT_SECONDS = "86400"
DEBUGGERS = ("gdb", "lldb")
STOPPED = ("[raykit] Stopped in your code. bt: where; p NAME: a value; n: next line; s: step in; "
           "c: continue; q: quit.")


def register(p) -> None:
    p.add_argument("number", metavar="N", help="the step")
    p.add_argument("case", nargs="?", metavar="CASE",
                   help="the case's name, or a part of it (default: the step's first failing case)")
    p.add_argument("--steps", metavar="DIR", help="debug the steps in DIR instead of steps/ (DIR is not modified)")
    p.add_argument("--batch", action="store_true", help=argparse.SUPPRESS)  # the self-test: stop, bt, end
    p.add_argument("--print", action="store_true", dest="print_only",
                   help="print the debugger's command instead of running it (for an IDE or a script)")
    p.add_argument("--debugger", choices=DEBUGGERS,
                   help="gdb or lldb (default: gdb where it is installed, else lldb)")


def gdb_script(functions: list[str]) -> str:
    lines = ["set pagination off", "set confirm off",
             "set follow-fork-mode child", "set detach-on-fork on", "set breakpoint pending on",
             "catch exec", "run",          # stops once the answers program (your code) has started
             "delete"]
    lines += [f"break raykit::{f}" for f in functions]
    lines += [f"echo \\n{STOPPED}\\n", "continue"]
    return "\n".join(lines) + "\n"


def lldb_script(functions: list[str], answers: Path) -> str:
    """The same stops as gdb_script's, for LLDB: follow the judge's child; at its exec, load the
    answers program's symbols at its fixed address (no PIE), then break in the student's functions
    of that program only."""
    lines = ["settings set target.process.follow-fork-mode child",
             "settings set target.process.stop-on-exec true",
             "process launch",          # stops at the exec of the answers program (your code)
             f"target modules add {answers}",
             f"target modules load --file {answers.name} --slide 0"]
    lines += [f"breakpoint set --shlib {answers.name} --name raykit::{f}" for f in functions]
    lines += ["continue"]
    return "\n".join(lines) + "\n"


def choose_debugger(wanted: str | None) -> str:
    """gdb where it is, else lldb; with apt and neither, gdb is installed. Without, the student's own
    platform's way to get one is named (Apple's lldb comes with the command line tools)."""
    if wanted:
        if shutil.which(wanted) is None:
            raise KitError(f"{wanted} is not on the PATH; {install_words(wanted)}", SETUP)
        return wanted
    for name in DEBUGGERS:
        if shutil.which(name):
            return name
    if has_apt():
        ensure_packages("debug")        # gdb, with apt-get (or the one command to run)
        if shutil.which("gdb"):
            return "gdb"
    raise KitError(f"./kit debug needs gdb or lldb, and neither is on the PATH; {install_words(None)}", SETUP)


def install_words(name: str | None) -> str:
    if family() == "brew" and sys.platform == "darwin":
        return "lldb comes with Apple's command line tools: xcode-select --install"
    return "install one: " + install_line(name or "gdb", name or "gdb")


def match_case(names: list[str], wanted: str, step) -> str:
    exact = [n for n in names if n == wanted]
    found = exact or [n for n in names if wanted.lower() in n.lower()]
    if not found:
        raise KitError(f"step {step.number} has no case named like {wanted!r}; ./kit check "
                       f"{int(step.number)} --all lists the failing ones")
    if len(found) > 1:
        raise KitError(f"{len(found)} cases of step {step.number} match {wanted!r}: "
                       + "; ".join(found[:5]) + ("; ..." if len(found) > 5 else "") + ". Name one of them.")
    return found[0]


def pick_case(exe: Path, wanted: str | None, build, step, all_steps) -> str:
    names = [c.name for c in list_cases(exe) if c.tier != "hidden"]
    if wanted:
        return match_case(names, wanted, step)
    [result] = check_steps(build, [step], all_steps)
    failing = [c for c in result.cases if c.status != PASS and c.tier != "hidden"]
    if not failing:
        raise KitError(f"every case of step {step.number} passes; name a case to debug it anyway", FAILED)
    return failing[0].name


def run(args) -> int:
    all_steps = load_steps()
    [step] = select_steps(all_steps, [args.number])
    # Before the build (half a minute cold): the case's name, from the step's recorded cases, and
    # the debugger (--print runs none).
    recorded = recorded_cases(step)
    if args.case and recorded is not None:
        match_case([c.name for c in recorded if c.tier != "hidden"], args.case, step)
    if args.print_only:     # for an IDE: the command, whichever debugger it will run
        debugger = args.debugger or next((d for d in DEBUGGERS if shutil.which(d)), "gdb")
    else:
        debugger = choose_debugger(args.debugger)
    ensure_packages("build")
    # Its own build folder without optimisation (preset "debug"): every variable can be printed and
    # every line stepped through; a --steps folder is staged first, as ./kit check --steps does.
    staged = submission_build(resolve_steps_dir(args.steps), "debug") if args.steps else preset_build("student")
    build = Build("debug", BUILD / "debug-build", staged.steps_dir, staged.shown_dir, preset="debug", tools=False)
    ensure_configured(build, all_steps)
    ok, _ = build_targets(build, [step.target, f"answers_step{step.number}"])
    if not ok:
        raise KitError(f"step {step.number} does not build; ./kit check {int(step.number)} shows why", FAILED)
    case = pick_case(build.exe(step), args.case, build, step, all_steps)
    answers = build.binary_dir / f"answers_step{step.number}"
    script = build.binary_dir / f"step{step.number}.{debugger}"
    script.parent.mkdir(parents=True, exist_ok=True)
    script.write_text(gdb_script(step.functions) if debugger == "gdb" else lldb_script(step.functions, answers))
    env = dict(os.environ, RAYKIT_CALL_SECONDS=NO_LIMIT_SECONDS, RAYKIT_SEED=submission_seed(build, step))
    judge = [str(build.exe(step)), f"--test-case={case}", "--no-breaks=true"]
    if debugger == "gdb":
        batch = ["-batch", "-ex", "bt"] if args.batch else []
        argv = ["gdb", "-q", *batch[:1], "-x", str(script), *batch[1:], "--args", *judge]
    else:
        batch = ["--batch", "-o", "bt"] if args.batch else []
        argv = ["lldb", *batch[:1], "-s", str(script), *batch[1:], "--", *judge]
    if args.print_only:
        say(f"RAYKIT_CALL_SECONDS={NO_LIMIT_SECONDS} " + " ".join(a if " " not in a else repr(a) for a in argv))
        return OK
    say(f"Debugging step {step.number}, case \"{case}\": {debugger} stops in your "
        + ", ".join(step.functions) + ".")
    if debugger == "lldb":
        say(STOPPED.replace("p NAME", "v NAME"))
    sys.stdout.flush()
    os.execvpe(debugger, argv, env)
    return OK  # not reached: the debugger replaced this process

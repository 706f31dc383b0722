"""./kit debug N [CASE]: run one case of a step under gdb, or lldb where there is no gdb (a Mac),
stopped in the student's own function, built without optimisation and with debug information.

The case is the one ./kit check shows first (StepResult.first_problem), or the one named. The judge
(test_stepNN) never runs the student's code itself: it sends each call to the answers program. So the
case is first run as usual with the judge recording its calls (RAYKIT_CALL_LOG, remote.cpp), and then
the answers program alone replays them under the debugger (`answers_stepNN --replay FILE`): one
process, no fork to follow (LLDB on macOS follows none), breakpoints on the step's functions, and
quitting the debugger is just quitting. The case's name and the debugger are checked before anything
is built.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
from pathlib import Path

from ..checking import check_steps, recorded_cases, submission_seed
from ..runcases import list_cases
from ..common import BUILD, KitError, load_steps, resolve_steps_dir, say, select_steps
from ..build import Build, build_targets, ensure_configured, preset_build, submission_build
from ..packages import ensure_packages, family, has_apt, install_line
from ..status import FAILED, OK, PASS, SETUP

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
    lines = ["set pagination off", "set confirm off", "set breakpoint pending on"]
    lines += [f"break raykit::{f}" for f in functions]
    lines += [f"echo \\n{STOPPED}\\n", "run"]
    return "\n".join(lines) + "\n"


def lldb_script(functions: list[str]) -> str:
    lines = [f"breakpoint set --name raykit::{f}" for f in functions]
    lines += ["process launch"]
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
    """The case named, or the one ./kit check shows first: its first problem, basic, then ★."""
    names = [c.name for c in list_cases(exe) if c.tier != "hidden"]
    if wanted:
        return match_case(names, wanted, step)
    [result] = check_steps(build, [step], all_steps)
    for tier in ("basic", "robust"):
        case = result.first_problem(tier)
        if case is not None and case.tier != "hidden":
            return case.name
    raise KitError(f"every case of step {step.number} passes; name a case to debug it anyway", FAILED)


def record_calls(build, step, case: str, log: Path) -> int:
    """Runs the case as ./kit check would and records its calls of the student's code in `log`; how many."""
    log.unlink(missing_ok=True)
    env = dict(os.environ, RAYKIT_CALL_LOG=str(log), RAYKIT_SEED=submission_seed(build, step))
    subprocess.run([str(build.exe(step)), f"--test-case={case}", "--no-breaks=true"], env=env,
                   stdin=subprocess.DEVNULL, capture_output=True, timeout=600)
    data = log.read_bytes() if log.is_file() else b""
    count, at = 0, 0
    while at + 4 <= len(data):
        at += 4 + int.from_bytes(data[at:at + 4], sys.byteorder)
        count += 1
    return count


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
    log = build.binary_dir / f"step{step.number}.calls"
    if record_calls(build, step, case, log) == 0:
        raise KitError(f"the case \"{case}\" calls none of your code: nothing to debug", FAILED)
    script = build.binary_dir / f"step{step.number}.{debugger}"
    script.parent.mkdir(parents=True, exist_ok=True)
    script.write_text(gdb_script(step.functions) if debugger == "gdb" else lldb_script(step.functions))
    program = [str(answers), "--replay", str(log)]
    if debugger == "gdb":
        batch = ["-batch", "-ex", "bt"] if args.batch else []
        argv = ["gdb", "-q", *batch[:1], "-x", str(script), *batch[1:], "--args", *program]
    else:
        batch = ["--batch", "-o", "bt"] if args.batch else []
        argv = ["lldb", *batch[:1], "-s", str(script), *batch[1:], "--", *program]
    if args.print_only:
        say(" ".join(a if " " not in a else repr(a) for a in argv))
        return OK
    say(f"Debugging step {step.number}, case \"{case}\" (its calls of your code, replayed in one program): "
        f"{debugger} stops in your " + ", ".join(step.functions) + ".")
    if debugger == "lldb":
        say(STOPPED.replace("p NAME", "v NAME"))
    sys.stdout.flush()
    os.execvp(debugger, argv)
    return OK  # not reached: the debugger replaced this process

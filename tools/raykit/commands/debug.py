"""./kit debug N [CASE]: run one case of a step under gdb, or lldb where there is no gdb (a Mac),
stopped in the student's own function, built without optimisation and with debug information.

The case is the one ./kit check shows first (StepResult.first_problem), or the one named. The judge
(test_stepNN) never runs the student's code itself: it sends each call to the answers program. So the
case is first run as usual with the judge recording its calls (RAYKIT_CALL_LOG, remote.cpp), and then
the answers program alone replays them under the debugger (`answers_stepNN --replay FILE`): one
process, no fork to follow (LLDB on macOS follows none), breakpoints on the step's functions, and
quitting the debugger is just quitting. The case's name and the debugger are checked before anything
is built.

The program is the bundle's dispatcher (bundle.py: the kit's side, already built for ./kit check)
linked with the student's files compiled without optimisation and with full debug information, from
where they are (their own folder: the debugger shows their lines) into build/debug/, which stays: the
debugger reads the objects' information and the sources after this process has gone. No CMake
configure, no build of a judge: the bundle's judge records the calls.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from .. import bundle
from ..build import Build, detect_undefined, preset_build
from ..checking import LastCheck, check_steps, recorded_cases, submission_seed
from ..common import BUILD, ROOT, KitError, load_steps, map_in_threads, resolve_steps_dir, say, select_steps
from ..packages import ensure_packages, family, has_apt, install_line
from ..runcases import list_cases
from ..sandbox import NONE_OWN
from ..status import FAILED, OK, SETUP

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
    return "\n".join(["set pagination off", "set confirm off", "set breakpoint pending on"]
                     + [f"break raykit::{f}" for f in functions] + [f"echo \\n{STOPPED}\\n", "run"]) + "\n"


def lldb_script(functions: list[str]) -> str:
    return "\n".join([f"breakpoint set --name raykit::{f}" for f in functions] + ["process launch"]) + "\n"


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


BUGGY_FLAGS = re.compile(r"^-(O[0-9sgz]?|g[0-9]?|ggdb[0-9]?|gline-tables-only|gmlt)$")
DEBUG_FLAGS = ["-O0", "-g3", "-fno-omit-frame-pointer"]


def debug_command(kit: bundle.Bundle, source: Path, out: Path) -> list[str]:
    """The check's own command for a student's file (the same warnings, standard, sanitizer and
    no-contraction rule, so what is debugged computes what was checked), without its optimisation
    and line-tables-only information: every variable can be printed and every line stepped."""
    argv = [a for a in kit.compile_command("check", source, out) if not BUGGY_FLAGS.match(a)]
    return argv[:1] + DEBUG_FLAGS + argv[1:]


def build_debug(kit: bundle.Bundle, step, steps_dir: Path, folder: Path) -> Path:
    """The step's answers program for the debugger, in `folder`; a KitError naming the compile error."""
    by_folder = {s.folder: s for s in load_steps()}
    sources = [(step.folder, f) for f in step.files] + [(need, f) for need in kit.own_needs(step)
                                                         for f in by_folder[need].files]
    missing = [f"{d}/{f}" for d, f in sources if not (steps_dir / d / f).is_file()]
    if missing:
        raise KitError(f"{missing[0]} is missing; ./kit check {int(step.number)} says what to write", FAILED)
    commands = [debug_command(kit, steps_dir / d / f, folder / "objects" / d / (f + ".o")) for d, f in sources]
    for argv in commands:
        Path(argv[argv.index("-o") + 1]).parent.mkdir(parents=True, exist_ok=True)

    def compile_one(argv: list[str]) -> subprocess.CompletedProcess:
        return subprocess.run(argv, cwd=folder, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                              errors="replace")

    compiled = map_in_threads(compile_one, commands, os.cpu_count() or 1)
    failed = next((c for c in compiled if c.returncode != 0), None)
    if failed is not None:
        sys.stderr.write(failed.stderr)
        raise KitError(f"step {step.number} does not compile; ./kit check {int(step.number)} shows why", FAILED)
    answers = folder / f"answers_step{step.number}"
    link = subprocess.run(kit.link_command([c[c.index("-o") + 1] for c in commands] + kit.kit_objects(step), answers),
                          cwd=folder, stdin=subprocess.DEVNULL, capture_output=True, text=True, errors="replace")
    if link.returncode != 0:
        sys.stderr.write(link.stderr)
        raise KitError(f"step {step.number} does not link; ./kit check {int(step.number)} shows why", FAILED)
    return answers


def pick_case(judge: Path, wanted: str | None, check: Build, step, all_steps) -> str:
    """The case named, or the one ./kit check shows first: its first problem, basic, then ★; taken
    from the student's last check of the same files when there is one, as ./kit hint does."""
    names = [c.name for c in list_cases(judge) if c.tier != "hidden"]
    if wanted:
        return match_case(names, wanted, step)
    result = LastCheck(check, all_steps, NONE_OWN).load(step)
    if result is None:
        say(f"kit: running step {step.number}'s cases to find the first that fails")
        [result] = check_steps(check, [step], all_steps)
    case = result.first_problem("basic") or result.first_problem("robust")     # never a hidden one
    if case is None:
        raise KitError(f"every case of step {step.number} passes; name a case to debug it anyway", FAILED)
    return case.name


def record_calls(judge: Path, answers: Path, seed: str, case: str, log: Path) -> int:
    """Runs the case as ./kit check would, with the debug program as the student's, and records its
    calls of the student's code in `log`; how many."""
    log.unlink(missing_ok=True)
    env = dict(os.environ, RAYKIT_CALL_LOG=str(log), RAYKIT_SEED=seed, RAYKIT_ANSWERS=str(answers))
    subprocess.run([str(judge), f"--test-case={case}", "--no-breaks=true"], env=env,
                   stdin=subprocess.DEVNULL, capture_output=True, timeout=600)
    data = log.read_bytes() if log.is_file() else b""
    count, at = 0, 0
    while at + 4 <= len(data):
        at += 4 + int.from_bytes(data[at:at + 4], sys.byteorder)
        count += 1
    return count


def batch_commands(debugger: str) -> list[str]:
    """What --batch (the self-test) asks once stopped: where, the source around, the arguments."""
    if debugger == "gdb":
        return ["bt 3", "list", "info args"]
    return ["bt 3", "source list", "frame variable"]


def run(args) -> int:
    all_steps = load_steps()
    [step] = select_steps(all_steps, [args.number])
    # Before any build: the case's name, from the step's recorded cases, and the debugger (--print
    # runs none).
    recorded = recorded_cases(step)
    if args.case and recorded is not None:
        match_case([c.name for c in recorded if c.tier != "hidden"], args.case, step)
    if args.print_only:     # for an IDE: the command, whichever debugger it will run
        debugger = args.debugger or next((d for d in DEBUGGERS if shutil.which(d)), "gdb")
    else:
        debugger = choose_debugger(args.debugger)
    ensure_packages("build")
    steps_dir = resolve_steps_dir(args.steps) if args.steps else ROOT / "steps"
    # The student's own check of these files (their first failing case, the hidden cases' seed):
    # steps/ is their usual build; another folder is checked as their own code too (it runs as them
    # under the debugger anyway), in a folder of its own.
    check = (preset_build("student") if not args.steps else
             Build("debug-check", BUILD / "debug-check", steps_dir, steps_dir, tools=False,
                   sanitize_student=detect_undefined()))
    kit = bundle.ensure(detect_undefined(), lambda: say("kit: building the kit's side, once for this machine"))
    folder = BUILD / "debug"
    folder.mkdir(parents=True, exist_ok=True)
    answers = build_debug(kit, step, steps_dir, folder)
    judge = kit.judge(step)
    case = pick_case(judge, args.case, check, step, all_steps)
    log = folder / f"step{step.number}.calls"
    if record_calls(judge, answers, submission_seed(check, step), case, log) == 0:
        raise KitError(f"the case \"{case}\" calls none of your code: nothing to debug", FAILED)
    script = folder / f"step{step.number}.{debugger}"
    script.write_text(gdb_script(step.functions) if debugger == "gdb" else lldb_script(step.functions))
    program = [str(answers), "--replay", str(log)]
    extra = batch_commands(debugger) if args.batch else []
    if debugger == "gdb":
        argv = ["gdb", "-q", *(["-batch"] if args.batch else []), "-x", str(script),
                *[w for c in extra for w in ("-ex", c)], "--args", *program]
    else:
        argv = ["lldb", *(["--batch"] if args.batch else []), "-s", str(script),
                *[w for c in extra for w in ("-o", c)], "--", *program]
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

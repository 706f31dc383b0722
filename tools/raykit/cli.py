"""raykit's command line: ./kit COMMAND [options].

COMMANDS is the one table of commands: their order in ./kit help, who they are for, and the module
(raykit/commands/NAME.py) that does the work, with
    def register(parser): ...   # add its arguments
    def run(args) -> int: ...   # do the work, return an exit status (raykit/status.py)
Only the module of the command being run is imported.

The words, one meaning each: *check* runs a student's steps' cases and scores them (./kit check,
./kit watch); *grade* checks every submission of a class into grades (./kit grade, Gradescope);
the *self-test* is the kit testing itself (./kit test).
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import sys
from dataclasses import dataclass

from .common import ROOT, KitError
from .status import FAILED, INTERRUPTED, OK, USAGE

STUDENT, INSTRUCTOR = "students", "instructors"


@dataclass(frozen=True)
class Command:
    name: str
    module: str         # PACKAGE/commands/MODULE.py
    audience: str       # STUDENT or INSTRUCTOR
    help: str
    package: str = "raykit"     # raykit: the student's runtime; kitlib: the instructor's toolchain


# The student's commands: this package (tools/raykit) is all a handout ships of the driver. The
# instructor's toolchain (tools/kitlib) adds its commands to these in its own table (kitlib/cli.py),
# and ./kit runs that one where tools/kitlib is there.
COMMANDS = [
    Command("check", "check", STUDENT, "check your steps: every case, your score, and what to do next"),
    Command("watch", "watch", STUDENT, "check the step you work on at every save, and move on when it is done"),
    Command("hint", "hint", STUDENT, "show the next hint for step N (first a nudge, then the formula, never the code)"),
    Command("debug", "debug", STUDENT, "run one case of step N under gdb (or lldb), stopped in your own function"),
    Command("reset", "reset", STUDENT, "put a step's shipped stub back (your file is kept as NAME.cpp.bak-TIME)"),
    Command("render", "render", STUDENT, "render the course's scenes to PNG, from the solutions or, with --steps, from your code"),
]

# The instructor's commands by name only, so that a student's copy says where one runs rather than
# that it does not exist (the layers self-test holds this list to kitlib/cli.py's table).
ELSEWHERE = ("docs", "bench", "test", "course", "grade", "report", "handout", "exact", "refresh", "mutant", "slides",
             "autograder", "classroom", "prairielearn")


def available(commands: list[Command] = COMMANDS) -> list[Command]:
    """The commands of `commands` this copy of the kit has and offers: a handout has no tools/kitlib,
    and an instructor's kit without solutions/ offers the students' commands alone."""
    return [c for c in commands if _here(c) and (not handout() or c.audience == STUDENT)]


def _here(c: Command) -> bool:
    return (ROOT / "tools" / c.package / "commands" / f"{c.module}.py").is_file()


class Parser(argparse.ArgumentParser):
    def parse_known_args(self, args=None, namespace=None):
        # argparse reads a value that starts with '-' as an option ("--size -5x10": "expected one
        # argument"). Glue such a value to its option, so the command says what is wrong with it.
        takes_value = {o for a in self._actions if a.nargs is None for o in a.option_strings}
        glued: list[str] = []
        for token in list(sys.argv[1:] if args is None else args):
            if glued and glued[-1] in takes_value and re.match(r"-[\d.]", token):
                glued[-1] += "=" + token
            else:
                glued.append(token)
        return super().parse_known_args(glued, namespace)

    def error(self, message):  # usage errors: clear message, usage, exit status USAGE
        self.print_usage(sys.stderr)
        print(f"kit: {message}", file=sys.stderr)
        sys.exit(USAGE)


def handout() -> bool:
    return not (ROOT / "solutions").is_dir()   # a student's copy: no solutions/


def overview(commands: list[Command]) -> str:
    """./kit help: the commands by audience, from the table alone (no command module is imported)."""
    lines = ["usage: ./kit COMMAND [options]    (./kit COMMAND -h: its options)", "",
             "raykit: a first ray tracing course kit."]
    for audience in (STUDENT, INSTRUCTOR):
        listed = [f"  {c.name:<11} {c.help}" for c in available(commands) if c.audience == audience]
        lines += ["", f"For {audience}:"] + listed if listed else []     # a handout: no instructors' part
    lines += ["", "Start with ./kit check." + ("" if handout() else " Instructors: ./kit test verifies the whole kit.")]
    return "\n".join(lines)


def build_parser(chosen: str | None, commands: list[Command] = COMMANDS) -> Parser:
    """The parser; only `chosen`'s module is imported to add its options, and only its sub-parser is
    made (20 of them cost 40 ms of every command's start); with no command chosen, all of them, for
    the message that lists them."""
    p = Parser(prog="./kit", description="raykit: a first ray tracing course kit.", add_help=False)
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for c in available(commands):
        if chosen is not None and c.name != chosen:
            continue
        shown = c.help if c.audience == STUDENT else f"{c.audience}: {c.help}"
        sp = sub.add_parser(c.name, help=shown, description=shown)
        if c.name == chosen:
            importlib.import_module(f"{c.package}.commands.{c.module}").register(sp)
    sub.add_parser("help", help="show the commands")
    return p


def main(argv: list[str], table: list[Command] = COMMANDS) -> int:
    """./kit ARGV with the commands of `table`: the students' (python3 -m raykit), or with the
    instructor's added (python3 -m kitlib, which passes its own table)."""
    try:
        if not argv or argv[0] in ("help", "-h", "--help"):
            print(overview(table))
            return OK
        commands = {c.name: c for c in available(table)}
        if argv[0] not in commands and argv[0] in {c.name for c in table} | set(ELSEWHERE):
            raise KitError(f"{argv[0]} is an instructor's command and this is a student's copy of the kit "
                           "(no solutions/); run it in the instructor's kit")
        chosen = argv[0] if argv[0] in commands else None
        args = build_parser(chosen, table).parse_args(argv)
        c = commands[args.command]
        return importlib.import_module(f"{c.package}.commands.{c.module}").run(args)
    except KitError as e:
        print(f"kit: {e}", file=sys.stderr)
        return e.code
    except KeyboardInterrupt:
        print("kit: interrupted", file=sys.stderr)
        return INTERRUPTED
    except BrokenPipeError:  # ./kit check | head: the reader has gone, nothing left to say
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return FAILED

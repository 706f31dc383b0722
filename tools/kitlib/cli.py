"""raykit's command line: ./kit COMMAND [options].

Each command lives in a module cmd_NAME.py with
    HELP = "one line"
    def register(parser): ...   # add its arguments
    def run(args) -> int: ...   # do the work, return the exit status
and is found here by name, so adding a command touches no other file.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import KitError  # noqa: E402

# The order of commands in ./kit help: the student's first, then the instructor's (marked as such).
STUDENT = ["check", "watch", "hint", "reset", "render", "docs", "bench"]
ORDER = STUDENT + ["test", "grade", "handout", "exact", "mutant"]


class Parser(argparse.ArgumentParser):
    def error(self, message):  # usage errors: clear message, usage, exit status 2
        self.print_usage(sys.stderr)
        print(f"kit: {message}", file=sys.stderr)
        sys.exit(2)


def commands() -> dict:
    found = {p.stem[4:]: p for p in HERE.glob("cmd_*.py")}
    names = [n for n in ORDER if n in found] + sorted(n for n in found if n not in ORDER)
    return {n: importlib.import_module(f"cmd_{n}") for n in names}


def build_parser(mods: dict) -> argparse.ArgumentParser:
    handout = not (HERE.parents[1] / "solutions").is_dir()   # a student's copy: no solutions/
    epilog = "Start with ./kit check." + ("" if handout else " Instructors: ./kit test verifies the whole kit.")
    p = Parser(prog="./kit", description="raykit: a first ray tracing course kit.", epilog=epilog)
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for name, mod in mods.items():
        shown = mod.HELP
        if name not in STUDENT and "instructor" not in shown:
            shown = "instructors: " + shown
        mod.register(sub.add_parser(name, help=shown, description=mod.HELP))
    sub.add_parser("help", help="show this help")
    return p


def main(argv: list[str]) -> int:
    mods = commands()
    parser = build_parser(mods)
    args = parser.parse_args(argv)
    if args.command in (None, "help"):
        parser.print_help()
        return 0
    try:
        return mods[args.command].run(args)
    except KitError as e:
        print(f"kit: {e}", file=sys.stderr)
        return e.code
    except KeyboardInterrupt:
        print("kit: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # ./kit check | head: the reader has gone, nothing left to say
        import os
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

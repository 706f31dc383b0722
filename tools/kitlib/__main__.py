"""python3 -m kitlib COMMAND ...: what ./kit runs in the instructor's kit (with tools/ on PYTHONPATH):
the students' commands (raykit) and the instructor's (kitlib/cli.py)."""

import sys

from raykit import pycache

pycache.install()       # before any other of the kit's modules loads

from .cli import main  # noqa: E402

sys.exit(main(sys.argv[1:]))

"""python3 -m raykit COMMAND ...: what ./kit runs in a student's copy of the kit, which has no
tools/kitlib (with tools/ on PYTHONPATH): the students' commands alone."""

import sys

from . import pycache

pycache.install()       # before any other of the kit's modules loads

from .cli import main  # noqa: E402

sys.exit(main(sys.argv[1:]))

"""python3 -m kitlib COMMAND ...: what ./kit runs (with tools/ on PYTHONPATH)."""

import sys

from . import pycache

pycache.install()       # before any other of the kit's modules loads

from .cli import main  # noqa: E402

sys.exit(main(sys.argv[1:]))

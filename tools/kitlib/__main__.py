"""python3 -m kitlib COMMAND ...: what ./kit runs (with tools/ on PYTHONPATH)."""

import sys

from .cli import main

sys.exit(main(sys.argv[1:]))

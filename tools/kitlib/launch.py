#!/usr/bin/env python3
"""The compiler and linker launcher of a submission build: CMake runs every compile and link of the
student's answers program as `launch.py compile|link COMMAND...` (RULE_LAUNCH_COMPILE and
RULE_LAUNCH_LINK, set when RAYKIT_BOUNDARY is on), and this runs COMMAND inside the trust boundary
that `./kit` chose, read from RAYKIT_BOUNDARY_SPEC (sandbox.Isolation.spec()), with the build's
store of compiled objects (objcache.ObjectCache).

Without that variable it refuses: a build folder that compiles a submission is only ever built by
the kit, which always says how to keep the code apart.
"""

import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from kitlib import pycache  # noqa: E402

pycache.install()       # the kit's modules compiled once, into the kit's cache folder

from kitlib.objcache import ObjectCache  # noqa: E402
from kitlib.sandbox import Isolation  # noqa: E402


def main(argv: list[str]) -> int:
    if len(argv) < 2 or argv[0] not in ("compile", "link"):
        print("usage: launch.py compile|link COMMAND...", file=sys.stderr)
        return 2
    spec = os.environ.get("RAYKIT_BOUNDARY_SPEC")
    if not spec:
        print("raykit: this build folder compiles a submission inside the grader's sandbox; "
              "build it through ./kit (./kit check --steps DIR), not by hand.", file=sys.stderr)
        return 2
    return Isolation.from_spec(spec).run_tool(argv[0], argv[1:], Path.cwd(), cache=ObjectCache)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

#!/usr/bin/env python3
"""Builds the kit's side for PrairieLearn's jobs, in the grading image, into the course's private files.

    docker run --rm --network none -v "$PWD/serverFilesCourse:/grade/serverFilesCourse" IMAGE \\
        python3 /grade/serverFilesCourse/raykit/tools/prairielearn/prebuild.py

(graders/raykit/build.sh runs it right after `docker build`.) The public image holds the toolchain
alone: the bundle (tools/raykit/bundle.py) holds the compiled reference and the hidden cases, so it is
built here into serverFilesCourse/raykit-bundle/, which PrairieLearn copies into every job beside the
kit (students never see serverFilesCourse). It is built where a job finds it, by the image's own
compiler and packages, from the kit as it stands; a job whose image or kit differs (its key) builds
its own and its results say why. Standard library only.
"""

from __future__ import annotations

import sys
from pathlib import Path

KIT = Path(__file__).resolve().parents[2]
TARGET = KIT.parent / "raykit-bundle"


def main(argv: list[str]) -> int:
    if argv:
        print("usage: prebuild.py (no arguments: it builds into the folder beside the kit, raykit-bundle/)",
              file=sys.stderr)
        return 2
    sys.path.insert(0, str(KIT / "tools"))
    from raykit import bundle
    from raykit.build import detect_undefined
    from raykit.common import KitError
    from raykit.packages import ensure_packages
    if not bundle.hidden_here():
        print(f"prebuild.py: {KIT} has no solutions/ and tests/hidden/: not the instructor's kit", file=sys.stderr)
        return 1
    try:
        ensure_packages("build")
        found = bundle.prebuild(TARGET, detect_undefined())
    except KitError as e:
        print(f"prebuild.py: {e}", file=sys.stderr)
        return 1
    readme = TARGET / "README.md"
    readme.write_text(README)
    size = sum(f.stat().st_size for f in TARGET.rglob("*") if f.is_file())
    print(f"prebuild.py: the kit's side built in {found.folder} ({size / 2**20:.1f} MiB), for this image's compiler "
          f"({bundle._compiler_words()}); commit serverFilesCourse/raykit-bundle/ with the course")
    return 0


README = """# The kit's side, prebuilt for the grading image (private)

Built by `graders/raykit/build.sh` (tools/prairielearn/prebuild.py, run in the grading image): the
judges, the reference's answers programs and the hidden cases, compiled. It holds the reference: keep
it in serverFilesCourse/ (never in the public image). A job uses it when the image and the kit are
those it was built for, and compiles only the student's files; otherwise the job builds its own and
its results say why ("built_why"). Build it again after a new image or a change to the kit.
"""


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

"""./kit autograder OUT.zip: the zip Gradescope takes as a programming assignment's autograder."""

from __future__ import annotations

import stat
import time
import zipfile
from pathlib import Path

from raykit import atomic, secret
from raykit.kitfiles import kit_files, platform_excluded as excluded
from raykit.common import ROOT, KitError, say, writable_parent
from raykit.status import FAILED, OK


AT_ROOT = {"setup.sh": "tools/gradescope/setup.sh", "run_autograder": "tools/gradescope/run_autograder"}


def register(p) -> None:
    p.add_argument("out", metavar="OUT.zip", help="the zip to write (replaced when it exists)")


def add(z: zipfile.ZipFile, src: Path, name: str) -> None:
    """Adds `src` as `name`, keeping its executable bit (./kit, run_autograder) and nothing else
    of the machine (owner, exact time): two runs on the same files differ only in dates."""
    info = zipfile.ZipInfo(name, date_time=time.localtime(src.stat().st_mtime)[:6])
    info.compress_type = zipfile.ZIP_DEFLATED
    mode = 0o755 if src.stat().st_mode & stat.S_IXUSR else 0o644
    info.external_attr = (stat.S_IFREG | mode) << 16
    z.writestr(info, src.read_bytes())


def run(args) -> int:
    out = Path(args.out).expanduser()
    if out.suffix.lower() != ".zip":
        raise KitError(f"{args.out}: the autograder must be a .zip file (Gradescope takes nothing else)")
    if out.is_dir():
        raise KitError(f"{args.out}: is a folder, not a file")
    writable_parent(args.out, out)
    for name, src in AT_ROOT.items():
        if not (ROOT / src).is_file():
            raise KitError(f"{src} is missing: the kit is incomplete", FAILED)
    files = sorted(rel for rel in kit_files() if not excluded(rel) and (ROOT / rel).is_file()
                   and rel.as_posix() not in AT_ROOT and ROOT / rel != secret.SECRET_FILE)
    key = secret.secret()       # made now when this kit has none yet
    with atomic.replacing(out) as f:
        with zipfile.ZipFile(f, "w") as z:
            for name, src in AT_ROOT.items():
                add(z, ROOT / src, name)
            for rel in files:
                add(z, ROOT / rel, rel.as_posix())
            # The hidden cases' secret (raykit/secret.py), the kit's own: ./kit check --identity
            # gradescope:ID here draws what Gradescope drew for submission ID. Mode 0600.
            info = zipfile.ZipInfo(secret.SECRET_FILE.relative_to(ROOT).as_posix(), date_time=time.localtime()[:6])
            info.external_attr = (stat.S_IFREG | 0o600) << 16
            z.writestr(info, key.hex() + "\n")
    size = out.stat().st_size
    say(f"wrote {out} ({len(files) + len(AT_ROOT)} files, {size / 1e6:.1f} MB)")
    say("  Gradescope: a programming assignment, Configure Autograder, upload this zip (any Ubuntu LTS base image).")
    say("  Students upload their steps/ folder, the NN_topic/ folders, their files, or a zip of the kit.")
    return OK

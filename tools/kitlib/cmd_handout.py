"""./kit handout DIR: a copy of the kit for students, without anything that reveals the answers."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

from common import ROOT, KitError, say

HELP = "write a copy of the kit for students: no solutions, mutants or answer-revealing fixtures"

# Paths (relative to the kit) that never go into a handout: the answers, and everything built from them.
EXCLUDED = ["solutions", "tests/mutants", "tests/fixtures", "build", ".git", "docs/instructor"]


def register(p) -> None:
    p.add_argument("dir", metavar="DIR", help="where to write the handout (must not exist, or be empty)")


def kit_files() -> list[Path]:
    """The kit's files: what git tracks when this is a clone, else everything but build output."""
    if (ROOT / ".git").exists() and shutil.which("git"):
        r = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                           cwd=ROOT, capture_output=True, text=True)
        if r.returncode == 0:
            return [Path(p) for p in r.stdout.split("\0") if p]
    return [p.relative_to(ROOT) for p in ROOT.rglob("*") if p.is_file()]


def excluded(rel: Path) -> bool:
    s = rel.as_posix()
    return any(s == e or s.startswith(e + "/") for e in EXCLUDED) or "__pycache__" in rel.parts


def strip_instructor_parts(text: str) -> str:
    """Drops README sections between <!-- instructor --> and <!-- /instructor -->."""
    return re.sub(r"<!-- instructor -->.*?<!-- /instructor -->\n?", "", text, flags=re.S)


def run(args) -> int:
    target = Path(args.dir).expanduser()
    if target.exists() and (not target.is_dir() or any(target.iterdir())):
        raise KitError(f"{args.dir}: exists and is not an empty folder; choose a new one")
    parent = target.resolve().parent
    if not parent.is_dir():
        raise KitError(f"{args.dir}: folder {parent} does not exist")
    if not os.access(parent, os.W_OK):
        raise KitError(f"{args.dir}: cannot write in {parent}")
    inside = ROOT == target.resolve() or ROOT in target.resolve().parents
    if inside and (ROOT / "build") not in target.resolve().parents:
        raise KitError(f"{args.dir}: a handout cannot live inside the kit")
    staging = parent / f".{target.name}.partial"
    shutil.rmtree(staging, ignore_errors=True)
    count = 0
    try:
        for rel in kit_files():
            if excluded(rel) or not (ROOT / rel).is_file():
                continue
            dst = staging / rel
            dst.parent.mkdir(parents=True, exist_ok=True)
            if rel.as_posix() == "README.md":
                dst.write_text(strip_instructor_parts((ROOT / rel).read_text()))
                shutil.copymode(ROOT / rel, dst)
            else:
                shutil.copy2(ROOT / rel, dst)
            count += 1
        if target.exists():
            target.rmdir()
        staging.rename(target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    say(f"wrote a student handout of {count} files to {target}")
    say("  left out: " + ", ".join(EXCLUDED[:4]))
    say(f"  students start with: cd {target} && ./kit check")
    return 0

"""The kit's own files, as git knows them: what a handout, the autograder's zip and PrairieLearn's
copy of the kit are made from (commands/handout.py, autograder.py, prairielearn.py import it; it
imports none of them)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from .common import ROOT

# Never in an instructor's copy handed to a platform (the autograder's zip, PrairieLearn's
# serverFilesCourse/): build output, git's store, Python's caches. The solutions stay.
PLATFORM_EXCLUDED = ["build", ".git"]


def platform_excluded(rel: Path) -> bool:
    s = rel.as_posix()
    return any(s == e or s.startswith(e + "/") for e in PLATFORM_EXCLUDED) or "__pycache__" in rel.parts \
        or rel.suffix == ".pyc"


def git(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["git", *args], cwd=ROOT, capture_output=True)


def is_clone() -> bool:
    return (ROOT / ".git").exists() and shutil.which("git") is not None and \
        git("rev-parse", "--verify", "-q", "HEAD").returncode == 0


def kit_files() -> list[Path]:
    """The kit's files: what git tracks (and new files it does not ignore), else everything."""
    if is_clone():
        r = git("ls-files", "-z", "--cached", "--others", "--exclude-standard")
        if r.returncode == 0:
            return [Path(p) for p in r.stdout.decode().split("\0") if p]
    return [p.relative_to(ROOT) for p in ROOT.rglob("*") if p.is_file()]

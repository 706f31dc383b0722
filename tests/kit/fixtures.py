"""The grader's fixtures (tests/fixtures/, README there) as the self-tests read them: fixture_dir(NAME).

A fixture file that is a solution's file with one slip is kept as a patch against it, as the mutants
are: tests/fixtures/<fixture>/NN_topic/FILE.patch stands for NN_topic/FILE, the file
solutions/NN_topic/FILE with the patch applied (mutants.read_diff, mutants.apply_patch). Its first
line is "Fixture: <what the file is>", then a unified diff of that one file (none: the solution's file
as it is). Every other file of a fixture is kept whole and copied as it is.

fixture_dir("slips/negative_t_dropped") gives build/fixtures/slips/negative_t_dropped: the whole
top-level fixture folder (here slips/) is written under build/, as other test builds are (graded code
reaches build/ no more than tests/), rebuilt only when one of its inputs changed (each file of the
folder, and the solution file each patch applies to, hashed), and swapped in whole. A patch that no
longer applies to its solution raises KitError naming the fixture's file.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import sys
import tempfile
from pathlib import Path

from raykit import atomic
from raykit.common import BUILD, ROOT, KitError, load_steps
from raykit.mutants import SOLUTIONS, Mutant, PatchError, apply_patch, read_diff

FIXTURES = ROOT / "tests" / "fixtures"
WORK = BUILD / "fixtures"
HEADER = "Fixture: "
FORMAT = "1"                        # bumped when what a fixture's patch turns into changes
_STEP = re.compile(r"^[0-9][0-9]_[a-z0-9_]+$")


def is_patch(path: Path) -> bool:
    """A fixture's file kept as a patch: FILE.patch in a step's folder (slips/c_plus_one.patch, a
    mutant-format patch at the top of slips/, is a file of the fixture, copied as it is)."""
    return path.suffix == ".patch" and _STEP.match(path.parent.name) is not None and "." in path.stem


def patched_text(patch: Path, fixtures: Path = FIXTURES) -> str:
    """The file a fixture's patch stands for; KitError naming the patch when it cannot be made."""
    name = patch.relative_to(fixtures)
    folder, file_name = patch.parent.name, patch.stem
    where = f"the fixture {'tests/fixtures/' if fixtures == FIXTURES else ''}{name.as_posix()}"
    steps = {s.folder: s for s in load_steps()}
    if folder not in steps:
        raise KitError(f"{where}: {folder} is no step of the kit")
    source = SOLUTIONS / folder / file_name
    lines = patch.read_text().splitlines()
    if not lines or not lines[0].startswith(HEADER):
        raise KitError(f"{where}: its first line must be {HEADER}<what the file is>")
    mutant = Mutant(steps[folder], name.as_posix(), lines[0][len(HEADER):], [])
    try:
        read_diff(lines, 1, mutant)
        if set(mutant.files) - {file_name}:
            raise PatchError(f"it changes {', '.join(sorted(set(mutant.files) - {file_name}))}, "
                             f"not solutions/{folder}/{file_name} alone")
        if not source.is_file():
            raise PatchError(f"solutions/{folder}/{file_name} does not exist")
        return apply_patch(mutant)[file_name] if mutant.files else source.read_text()
    except PatchError as e:
        raise KitError(f"{where} no longer applies to solutions/{folder}/{file_name}: {e}; "
                       f"write the fixture again on the solution (see tests/fixtures/README.md)") from None


def _inputs(top: Path) -> str:
    """The hash of everything the materialised folder is made of."""
    h = hashlib.sha256(f"fixtures {FORMAT}\n".encode())
    for p in sorted(top.rglob("*")):
        if not p.is_file():
            continue
        h.update(f"{p.relative_to(top).as_posix()}\n".encode() + p.read_bytes())
        if is_patch(p):
            source = SOLUTIONS / p.parent.name / p.stem
            h.update(b"solution\n" + (source.read_bytes() if source.is_file() else b"(none)"))
    return h.hexdigest()


def _write(top: Path, dst: Path, fixtures: Path) -> None:
    for p in sorted(top.rglob("*")):
        if not p.is_file():
            continue
        rel = p.relative_to(top)
        if is_patch(p):
            out = dst / rel.parent / p.stem
            out.parent.mkdir(parents=True, exist_ok=True)
            out.write_text(patched_text(p, fixtures))
        else:
            (dst / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(p, dst / rel)


def fixture_dir(name: str | os.PathLike, fixtures: Path = FIXTURES, work: Path = WORK) -> Path:
    """build/fixtures/<name>: the fixture tests/fixtures/<name> (a folder or a file in one) as the
    tests read it, patches applied. Its top-level folder is written whole, again only when its inputs
    changed, and put in place by renames, so a reader sees the old folder or the new one. (`fixtures`
    and `work`: another tree of fixtures and its build folder, for the self-test of a broken patch.)"""
    rel = Path(name)
    if rel.is_absolute() or ".." in rel.parts or not rel.parts:
        raise KitError(f"no fixture {name}: name one under tests/fixtures/")
    top = fixtures / rel.parts[0]
    if not top.is_dir():
        raise KitError(f"no fixture tests/fixtures/{rel.parts[0]} (a handout has none)")
    dst = work / rel.parts[0]
    stamp = work / f"{rel.parts[0]}.inputs"
    digest = _inputs(top)
    if not (dst.is_dir() and stamp.is_file() and stamp.read_text().strip() == digest):
        work.mkdir(parents=True, exist_ok=True)
        fresh = Path(tempfile.mkdtemp(prefix=f".{rel.parts[0]}.", dir=work))
        old = fresh.with_name(fresh.name + ".old")
        try:
            _write(top, fresh / "tree", fixtures)
            if dst.exists():
                os.rename(dst, old)
            try:
                os.rename(fresh / "tree", dst)
            except OSError:
                if not dst.is_dir():            # not another self-test that put the same folder first
                    raise
            atomic.write(stamp, digest + "\n")
        finally:
            shutil.rmtree(fresh, ignore_errors=True)
            shutil.rmtree(old, ignore_errors=True)
    out = work / rel
    if not out.exists():
        raise KitError(f"no fixture tests/fixtures/{rel.as_posix()} (nor a patch for it)")
    return out


if __name__ == "__main__":
    # For a shell (CI, a maintainer): prints the materialised path of each fixture named.
    #   ./kit check 1 --steps "$(PYTHONPATH=tools:tests python3 -m kit.fixtures missing_include)"
    try:
        for arg in sys.argv[1:]:
            print(fixture_dir(arg))
    except KitError as e:
        sys.exit(f"error: {e}")

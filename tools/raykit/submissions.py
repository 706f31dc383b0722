"""Finding a student's steps in whatever they uploaded.

Students upload in many shapes: the kit's `steps/` folder, the `NN_topic/` folders inside it,
a whole copy of the kit (zipped or not, as `raykit-main/steps/`), a folder of their own around
any of these (`dave/raykit-main/steps/`), or just the `.cpp` files. `locate()` finds the step
files at any depth and copies them, and only them, into a clean folder `./kit check --steps`
grades.

Why a copy and not the upload itself: the copy holds regular files only, each step's own file
names, nothing else. A symbolic link to the kit's solutions, a 2 GB file or a zip that writes
outside its folder never reaches the build.

Used by the Gradescope autograder (tools/gradescope/) and by batch grading. As a command (with tools/ on PYTHONPATH):
    python3 -m raykit.submissions UPLOAD WORKDIR
prints the folder to grade (exit 0) or what it found and what it expected (exit 1).
"""

from __future__ import annotations

import os
import shutil
import stat
import sys
import threading
import time
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

from .common import Step, load_steps, printable
from .status import FAILED, OK, USAGE

MAX_FILE_BYTES = 1 << 20            # a step's source file larger than this is not a student's
MAX_ZIP_BYTES = 200 << 20           # unpacked size of all zips of one upload together
MAX_ZIP_ENTRIES = 20000
ZIP_DEPTH = 2                       # a zip inside a zip is unpacked; deeper ones are not
SKIPPED_DIRS = {"__MACOSX", ".git", "build", "node_modules", "__pycache__"}
MAX_UPLOAD_FILES = 20000            # files and folders looked at in all, zips' entries included
MAX_UPLOAD_SECONDS = 20.0           # time spent looking

_budget = threading.local()         # per locate() call: ./kit grade runs several at once


def _spend(n: int = 1) -> None:
    """Counts `n` more files or folders looked at; NotFound once the upload's budget is spent (a
    682 KB upload of nested zips of empty entries unpacks to 200,000 files: bytes are no measure)."""
    b = getattr(_budget, "value", None)
    if b is None:
        return
    b[0] -= n
    if b[0] < 0:
        raise NotFound(f"The upload holds more than {MAX_UPLOAD_FILES} files and folders (zips' entries "
                       "included), so it was not read. Upload your steps/ folder or its .cpp files only.")
    if time.monotonic() > b[1]:
        raise NotFound(f"Reading the upload took over {MAX_UPLOAD_SECONDS:g} s, so it was not read. "
                       "Upload your steps/ folder or its .cpp files only.")


class NotFound(Exception):
    """The upload holds no step files: the message says what it holds and what was expected."""


@dataclass
class Located:
    steps_dir: Path                 # the clean copy to grade
    source: str                     # where the files came from, relative to the upload
    layout: str                     # "steps folder", "step folders", "loose files"
    steps: list[str] = field(default_factory=list)      # step folders found, e.g. ["01_unit_sphere"]
    notes: list[str] = field(default_factory=list)      # files left out and why


def expected_text(steps: list[Step]) -> str:
    example = ", ".join(f"{s.folder}/{s.files[0]}" for s in steps[:2])
    return (f"Expected your steps/ folder, or the step folders in it ({example}, ...), "
            f"or a .zip of either, or the step files themselves ({', '.join(f for s in steps for f in s.files)}).")


def _unzip(archive: Path, into: Path, budget: list[int]) -> list[str]:
    """Unpacks `archive` into `into`, refusing entries that would leave it, links and special
    files, and stopping at the shared byte budget. Returns notes on what was refused."""
    notes = []
    try:
        with zipfile.ZipFile(archive) as z:
            infos = z.infolist()
            if len(infos) > MAX_ZIP_ENTRIES:
                return [f"{archive.name}: {len(infos)} entries, more than the {MAX_ZIP_ENTRIES} read"]
            for info in infos:
                _spend()
                name = info.filename.replace("\\", "/")
                parts = [p for p in name.split("/") if p not in ("", ".")]
                mode = info.external_attr >> 16
                if not parts or ".." in parts or name.startswith("/") or ":" in parts[0]:
                    notes.append(f"{archive.name}: skipped {name!r} (a path outside the zip)")
                    continue
                if info.is_dir():
                    continue
                # Only a type the zip states counts: many zips store permission bits alone.
                if stat.S_IFMT(mode) not in (0, stat.S_IFREG):
                    notes.append(f"{archive.name}: skipped {name!r} (a link or special file)")
                    continue
                if info.file_size > budget[0]:
                    notes.append(f"{archive.name}: stopped at {name!r}, the upload unpacks to more than "
                                 f"{MAX_ZIP_BYTES >> 20} MB")
                    break
                budget[0] -= info.file_size
                target = into.joinpath(*parts)
                target.parent.mkdir(parents=True, exist_ok=True)
                with z.open(info) as src, open(target, "wb") as dst:
                    shutil.copyfileobj(src, dst)
    except (zipfile.BadZipFile, OSError, RuntimeError, NotImplementedError) as e:
        notes.append(f"{archive.name}: not a zip file we can read ({e})")
    return notes


def _walk(top: Path):
    """Folders under `top` (itself included), never following links, skipping tool folders."""
    for here, dirs, _files in os.walk(top, followlinks=False):
        _spend(1 + len(dirs) + len(_files))
        dirs[:] = sorted(d for d in dirs if d not in SKIPPED_DIRS and not d.startswith("."))
        yield Path(here)


def _regular(path: Path) -> bool:
    """A regular file reached through no link: neither it nor a folder on its way is a symbolic
    link (a linked `01_unit_sphere/` could point at the kit's own solutions)."""
    try:
        st = os.lstat(path)
    except OSError:
        return False
    return stat.S_ISREG(st.st_mode) and os.path.realpath(path) == os.path.abspath(path)


def _unpack_zips(upload: Path, work: Path) -> tuple[list[Path], list[str]]:
    """Every zip in the upload (and in those zips, ZIP_DEPTH deep) unpacked under work/unzipped."""
    roots, notes, budget = [], [], [MAX_ZIP_BYTES]
    todo = [(upload, 0)]
    count = 0
    while todo:
        top, depth = todo.pop(0)
        if depth >= ZIP_DEPTH:
            continue
        for folder in _walk(top):
            for f in sorted(folder.iterdir()):
                if f.suffix.lower() == ".zip" and _regular(f):
                    count += 1
                    into = work / "unzipped" / f"{count}_{f.stem}"
                    notes += _unzip(f, into, budget)
                    roots.append(into)
                    todo.append((into, depth + 1))
    return roots, notes


def _candidates(top: Path, steps: list[Step]):
    """(folder, step folders in it that hold at least one of their files) for every folder."""
    for folder in _walk(top):
        found = [s.folder for s in steps
                 if any(_regular(folder / s.folder / f) for f in s.files)]
        if found:
            yield folder, found


def _describe(upload: Path, limit: int = 12) -> str:
    shown = []
    for folder in _walk(upload):
        for p in sorted(folder.iterdir()):
            if p.name in SKIPPED_DIRS or p.name.startswith("."):
                continue
            rel = p.relative_to(upload).as_posix() + ("/" if p.is_dir() else "")
            shown.append(rel)
            if len(shown) >= limit:
                return ", ".join(shown) + ", ..."
    return ", ".join(shown) if shown else "nothing (an empty upload)"


def _copy_step_files(pairs: list[tuple[Path, Path]], notes: list[str], shown_from: Path) -> int:
    copied = 0
    for src, dst in pairs:
        rel = src.relative_to(shown_from).as_posix() if shown_from in src.parents else src.name
        if not _regular(src):
            notes.append(f"{rel}: left out (a link or not a regular file)")
            continue
        if src.stat().st_size > MAX_FILE_BYTES:
            notes.append(f"{rel}: left out (larger than {MAX_FILE_BYTES >> 20} MB)")
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(src, dst, follow_symlinks=False)
        copied += 1
    return copied


def locate(upload: Path, work: Path, steps: list[Step] | None = None) -> Located:
    """Finds the step files in `upload` (a folder or a .zip) and copies them to `work`/steps.

    The folder holding the most step folders wins, then one named `steps`, then the shallowest:
    a whole kit copy has tests/fixtures/crash/01_unit_sphere/ and maybe solutions/ beside steps/,
    and it is steps/ the student wrote. Without step folders, step files found anywhere by name
    (each file name belongs to one step) are used. Raises NotFound when there is neither.

    The messages (NotFound's, the notes, the source) name what the student named: their control
    characters are shown as text (common.printable) before they reach a CSV, a page or a terminal.
    """
    _budget.value = [MAX_UPLOAD_FILES, time.monotonic() + MAX_UPLOAD_SECONDS]
    try:
        found = _locate(upload, work, steps)
    except NotFound as e:
        raise NotFound(printable(str(e))) from None
    finally:
        _budget.value = None
    found.source, found.notes = printable(found.source), [printable(n) for n in found.notes]
    return found


def _locate(upload: Path, work: Path, steps: list[Step] | None) -> Located:
    steps = steps if steps is not None else load_steps()
    upload, work = upload.resolve(), work.resolve()   # so that a link is only ever inside the upload
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    out = work / "steps"
    notes: list[str] = []
    if upload.is_file():
        if upload.suffix.lower() != ".zip":
            raise NotFound(f"The upload {upload.name} is a single file, not a folder or a .zip. "
                           + expected_text(steps))
        single = work / "upload"
        single.mkdir()
        shutil.copyfile(upload, single / upload.name)
        upload = single
    elif not upload.is_dir():
        raise NotFound(f"There is no upload at {upload}. " + expected_text(steps))
    zip_roots, notes = _unpack_zips(upload, work)

    def shown(p: Path) -> str:
        for base, label in [(upload, "")] + [(z, f"{z.name.split('_', 1)[1]}.zip:") for z in zip_roots]:
            if p == base or base in p.parents:
                rel = p.relative_to(base).as_posix()
                return label + ("" if rel == "." else rel + "/") or "./"
        return str(p)

    best = None
    for top in [upload] + zip_roots:
        for folder, found in _candidates(top, steps):
            depth = len(folder.relative_to(top).parts)
            rank = (len(found), folder.name == "steps", folder.name != "solutions", -depth)
            if best is None or rank > best[0]:
                best = (rank, folder, found)
    if best is not None:
        _, folder, found = best
        pairs = [(folder / s.folder / f, out / s.folder / f)
                 for s in steps if s.folder in found for f in s.files
                 if os.path.lexists(folder / s.folder / f)]
        _copy_step_files(pairs, notes, upload if upload in folder.parents or folder == upload else folder)
        # Step folders not counted because their files are links (to the kit's answers, say): say so.
        notes += [f"{s.folder}/{f}: left out (a link or not a regular file)" for s in steps
                  if s.folder not in found for f in s.files
                  if os.path.lexists(folder / s.folder / f) and not _regular(folder / s.folder / f)]
        layout = "steps folder" if folder.name == "steps" else "step folders"
        return Located(out, shown(folder) or "./", layout, found, notes)

    # No NN_topic/ folders: the step files themselves, anywhere, matched by name.
    by_name = {f: s for s in steps for f in s.files}
    pairs, seen = [], {}
    for top in [upload] + zip_roots:
        for folder in _walk(top):
            for f in sorted(folder.iterdir()):
                if f.name in by_name and f.name not in seen:
                    seen[f.name] = f
                    pairs.append((f, out / by_name[f.name].folder / f.name))
                elif f.name in by_name:
                    notes.append(f"{shown(f.parent)}{f.name}: a second {f.name}, left out "
                                 f"(graded: {shown(seen[f.name].parent)}{f.name})")
    if pairs and _copy_step_files(pairs, notes, upload):
        found = sorted({by_name[src.name].folder for src, _ in pairs if (out / by_name[src.name].folder).is_dir()})
        return Located(out, "./", "loose files", found, notes)
    raise NotFound(f"No step files found. Your upload holds: {_describe(upload)}. " + expected_text(steps)
                   + ("" if not notes else " (" + "; ".join(notes[:3]) + ")"))


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print("usage: submissions.py UPLOAD WORKDIR", file=sys.stderr)
        return USAGE
    try:
        found = locate(Path(argv[0]), Path(argv[1]))
    except NotFound as e:
        print(e)
        return FAILED
    print(found.steps_dir)
    print(f"found {', '.join(found.steps)} in {found.source} ({found.layout})", file=sys.stderr)
    for n in found.notes:
        print(f"note: {n}", file=sys.stderr)
    return OK


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

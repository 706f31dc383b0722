"""Self-test of submissions.py: the step files are found in every upload layout, and only they.

No build: each layout is made from the solutions' (or, in a handout, the stubs') file names in a
scratch folder, located, and the clean copy compared file by file with what went in.
"""

from __future__ import annotations

import os
import shutil
import zipfile
from pathlib import Path

from ..common import BUILD, ROOT, load_steps
from .harness import expect, need_solutions


def _source() -> Path:
    return ROOT / "solutions" if (ROOT / "solutions").is_dir() else ROOT / "steps"


def _same(found: Path, source: Path, folders: list[str]) -> list[str]:
    """Differences between the clean copy and the step files of `folders` in `source`."""
    problems = []
    for s in load_steps():
        for f in s.files:
            want = source / s.folder / f if s.folder in folders else None
            got = found / s.folder / f
            if want is None and got.exists():
                problems.append(f"{s.folder}/{f} copied but not in the upload")
            elif want is not None and (not got.is_file() or got.read_bytes() != want.read_bytes()):
                problems.append(f"{s.folder}/{f} missing or changed")
    extra = [p.relative_to(found).as_posix() for p in found.rglob("*")
             if p.is_file() and p.name not in {f for s in load_steps() for f in s.files}]
    return problems + [f"{e}: not a step file, copied" for e in extra]


def selftest_layouts(ctx) -> str:
    from ..submissions import NotFound, locate

    need_solutions()    # its uploads are made of the solutions and the fixtures

    steps = load_steps()
    folders = [s.folder for s in steps]
    src = _source()
    root = BUILD / "submissions-test"
    shutil.rmtree(root, ignore_errors=True)
    uploads: dict[str, Path] = {}

    def steps_copy(target: Path) -> Path:
        for s in steps:
            for f in s.files:
                (target / s.folder).mkdir(parents=True, exist_ok=True)
                shutil.copyfile(src / s.folder / f, target / s.folder / f)
        return target

    uploads["loose step folders"] = steps_copy(root / "loose")
    uploads["a steps/ folder"] = steps_copy(root / "steps-folder" / "steps").parent
    nested = steps_copy(root / "nested" / "dave" / "raykit-main" / "steps").parents[2]
    (nested / "dave" / "raykit-main" / "notes.txt").write_text("not a step file\n")
    uploads["dave/raykit-main/steps/"] = nested
    # A whole kit beside its steps: tests/ and fixtures hold NN_topic folders too; steps/ must win.
    kit = root / "kit" / "raykit"
    steps_copy(kit / "steps")
    shutil.copytree(ROOT / "tests" / "fixtures" / "crash", kit / "tests" / "fixtures" / "crash")
    # ... and an old copy of one step at the top, shallower than steps/: the most steps win.
    shutil.copytree(ROOT / "tests" / "fixtures" / "crash", kit.parent, dirs_exist_ok=True)
    uploads["a kit with fixtures beside steps/"] = kit.parent
    zipped = root / "zipped"
    zipped.mkdir()
    with zipfile.ZipFile(zipped / "raykit-main.zip", "w") as z:
        for i, p in enumerate(sorted((kit / "steps").rglob("*"))):
            if p.is_file():   # z.write stores the file type, writestr by name permission bits only
                name = f"raykit-main/steps/{p.relative_to(kit / 'steps').as_posix()}"
                z.write(p, name) if i % 2 else z.writestr(name, p.read_bytes())
        z.writestr("../outside.cpp", "escape attempt\n")
    uploads["a zipped kit"] = zipped
    loose = root / "files"
    loose.mkdir()
    for s in steps:
        for f in s.files:
            shutil.copyfile(src / s.folder / f, loose / f)
    uploads["the .cpp files alone"] = loose

    for label, upload in uploads.items():
        found = locate(upload, root / "work" / label.replace("/", "_").replace(" ", "_"))
        problems = _same(found.steps_dir, src, folders)
        expect(not problems, f"{label}: {'; '.join(problems[:3])}")
    expect(not list(root.rglob("outside.cpp")), "a zip entry '../outside.cpp' was written out")

    # A linked step folder (pointing at the kit's own answers) and a linked file are left out.
    linked = root / "linked"
    steps_copy(linked)
    first = steps[0]
    shutil.rmtree(linked / first.folder)
    os.symlink(src / first.folder, linked / first.folder)
    second = linked / steps[1].folder / steps[1].files[0]
    second.unlink()
    os.symlink(src / steps[1].folder / steps[1].files[0], second)
    found = locate(linked, root / "work" / "linked")
    expect(not (found.steps_dir / first.folder).exists(), "a linked step folder was followed")
    expect(not second.exists() or not (found.steps_dir / steps[1].folder / steps[1].files[0]).exists(),
           "a linked step file was copied")
    expect(any("link" in n for n in found.notes), f"no note about the link: {found.notes}")

    empty = root / "nothing"
    empty.mkdir()
    (empty / "readme.txt").write_text("sorry\n")
    try:
        locate(empty, root / "work" / "nothing")
        expect(False, "an upload without step files was accepted")
    except NotFound as e:
        expect("readme.txt" in str(e) and "Expected" in str(e), f"the message: {e}")
    shutil.rmtree(root, ignore_errors=True)
    return f"{len(uploads)} layouts found, links and a zip escape refused, an empty upload explained"


def selftests():
    return [("uploads: step files found at any depth, only they", selftest_layouts)]

"""A moved or copied kit: a build folder whose CMakeCache.txt was made for another path.

CMake refuses such a folder ("The current CMakeCache.txt directory ... is different from the
directory ... where CMakeCache.txt was created"). A build folder inside the kit's build/ is the
kit's own, so it is emptied and configured again (one line says so); any other is left alone, and
one line says what to do.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from .common import BUILD, ROOT, KitError, note


def cache_paths(cache: Path) -> tuple[str, str]:
    """The build folder and the source folder a CMakeCache.txt was made for ("" when not said)."""
    made_in = source = ""
    try:
        for line in cache.read_text(errors="replace").splitlines():
            if line.startswith("CMAKE_CACHEFILE_DIR:"):
                made_in = line.split("=", 1)[1].strip()
            elif line.startswith("CMAKE_HOME_DIRECTORY:"):
                source = line.split("=", 1)[1].strip()
    except OSError:
        pass
    return made_in, source


def _same(a: str, b: Path) -> bool:
    try:
        return Path(a).resolve() == b.resolve()
    except OSError:
        return False


def forget_moved_build(binary_dir: Path, source: Path = ROOT) -> bool:
    """Before configuring `binary_dir`: when its cache belongs to another path, empties it (a folder
    under the kit's build/) or raises KitError with the one thing to do. True when it emptied it."""
    cache = binary_dir / "CMakeCache.txt"
    if not cache.is_file():
        return False
    made_in, made_for = cache_paths(cache)
    if (not made_in or _same(made_in, binary_dir)) and (not made_for or _same(made_for, source)):
        return False
    was = made_for if made_for and not _same(made_for, source) else made_in
    if BUILD.resolve() in binary_dir.resolve().parents:
        note(f"{binary_dir}: made for {was} (the kit was moved or copied): building it again here")
        shutil.rmtree(binary_dir)
        return True
    raise KitError(f"{binary_dir} was configured for {was}, not for this copy of the kit: remove it "
                   f"(rm -r {binary_dir}) and run the command again")

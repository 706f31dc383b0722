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


def cache_entries(cache: Path) -> dict[str, str]:
    """A CMakeCache.txt's entries, NAME:TYPE=VALUE, as NAME -> VALUE (stripped). OSError when it cannot
    be read."""
    lines = cache.read_text(errors="replace").splitlines()
    return {name: value.split("=", 1)[1].strip() for name, _, value in (l.partition(":") for l in lines)
            if "=" in value}


def cache_paths(cache: Path) -> tuple[str, str]:
    """The build folder and the source folder a CMakeCache.txt was made for ("" when not said)."""
    try:
        found = cache_entries(cache)
    except OSError:
        found = {}
    return found.get("CMAKE_CACHEFILE_DIR", ""), found.get("CMAKE_HOME_DIRECTORY", "")


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

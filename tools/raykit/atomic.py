"""A file written whole or not at all: the kit's one way to replace a file (core layer).

    write(path, data)                 str (UTF-8) or bytes
    with replacing(path) as f: ...    a binary file to write into (a zip, a stream copy)

The data goes to a new temporary file beside `path`, made with a random name and O_CREAT | O_EXCL |
O_NOFOLLOW (tempfile.mkstemp), so a link or file planted at a name the kit would use is never
written through; it is flushed and fsynced, given `mode` (default: what a plain open() would give
under the umask), then renamed over `path` with os.replace, which replaces a link standing at `path`
rather than following it, and the folder is fsynced so the rename outlives a crash. Whatever goes
wrong, the temporary file is removed, `path` is as it was, and the error (OSError) is raised.
`sync=False` leaves out the two fsyncs, for a copy into a working folder that no crash needs to
find again (sandbox.copy_regular: every compile's inputs).
"""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager, suppress
from pathlib import Path
from typing import BinaryIO, Iterator

_UMASK = os.umask(0o022)    # read once, put back at once (the kit is one thread while it imports)
os.umask(_UMASK)
DEFAULT_MODE = 0o666 & ~_UMASK


@contextmanager
def replacing(path: str | os.PathLike, mode: int | None = None, sync: bool = True) -> Iterator[BinaryIO]:
    target = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            yield f
            f.flush()
            if sync:
                os.fsync(f.fileno())
            os.fchmod(f.fileno(), DEFAULT_MODE if mode is None else mode)
        os.replace(tmp, target)
    except BaseException:
        with suppress(OSError):
            os.unlink(tmp)
        raise
    if not sync:
        return
    try:
        folder = os.open(target.parent, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError:
        return
    try:
        os.fsync(folder)
    except OSError:
        pass        # a file system that cannot sync a folder: the rename is done all the same
    finally:
        os.close(folder)


def write(path: str | os.PathLike, data: str | bytes, mode: int | None = None) -> None:
    with replacing(path, mode) as f:
        f.write(data.encode("utf-8") if isinstance(data, str) else data)

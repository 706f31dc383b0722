"""The instructor's secret and the hidden cases' seed.

Hidden cases draw random inputs (tests/hidden/). Their seed must be something no student can
know or steer, yet the same when one submission is graded again:

    seed = HMAC-SHA256(secret, step folder, identity, SHA-256 of each of the step's files)[:16 hex]

- `secret`: 256 random bits made once per instructor's copy of the kit, in tests/hidden/secret.key
  (mode 0600, listed in .gitignore, never in a handout). `./kit autograder` and `./kit
  prairielearn` put the kit's own secret into what they write, so `./kit check --identity ...`
  on the instructor's machine draws what the platform drew. Graded code never reads it: under
  bubblewrap the kit is not in its view, under the user isolation tests/ and the file are closed
  to other users.
- `identity`: the submission's name on the platform that graded it: Gradescope's submission id
  ("gradescope:ID", a resubmission of the same bytes draws new inputs), PrairieLearn's variant
  ("prairielearn:SEED"); empty for `./kit check` and `./kit grade`, where the files alone name
  the submission (a student never sees a result of those before it is final, and copies judged
  once by content stay judged once).
- the files' hashes, of their code only (`code_only`: comments gone, white space folded): a changed
  line of code is another submission, a changed comment or indentation is not. Two students with the
  same code, or one who only re-comments a file, meet the same hidden inputs, so one bug gets one
  hidden mark within a course (issue 46: a comment moved 3 to 6 hidden results in a class of 46). The
  price: nothing a student can see, since the secret alone makes the draw.

64 bits of seed (the judge reads it as one unsigned 64-bit number, tests/hidden/hidden.hpp); a
file searched to meet a given seed needs the secret, which the search cannot have.
"""

from __future__ import annotations

import hashlib
import hmac
import json
import os
import secrets as random_source
import stat
from pathlib import Path

from .common import ROOT, KitError

SECRET_FILE = ROOT / "tests" / "hidden" / "secret.key"
SECRET_BYTES = 32
SEED_HEX = 16


def _read(path: Path) -> bytes | None:
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_CLOEXEC)
    except FileNotFoundError:
        return None
    except OSError as e:
        raise KitError(f"{path}: cannot read the hidden cases' secret ({e.strerror})")
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise KitError(f"{path}: the hidden cases' secret is not a regular file")
        if st.st_mode & 0o077:
            os.fchmod(fd, 0o600)        # only its owner reads it, whatever the zip's modes were
        text = os.read(fd, 4096).decode("ascii", "replace").strip()
    finally:
        os.close(fd)
    try:
        key = bytes.fromhex(text)
    except ValueError:
        raise KitError(f"{path}: the hidden cases' secret is not hexadecimal; delete it to make a new one")
    if len(key) < 16:
        raise KitError(f"{path}: the hidden cases' secret has {len(key) * 8} bits, fewer than 128; "
                       "delete it to make a new one")
    return key


def write_new(path: Path, key: bytes | None = None) -> bytes:
    """A new secret at `path` (`key`, or a fresh one), never over an existing file, mode 0600."""
    key = key or random_source.token_bytes(SECRET_BYTES)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o600)
    try:
        os.write(fd, key.hex().encode() + b"\n")
    finally:
        os.close(fd)
    return key


# The self-test's own secret (tests/kit/support.prepare sets it): its gradings draw the same hidden inputs on
# every run and every machine, so a self-test's verdict never hangs on a random draw. Nothing graded
# sees it (the judge's environment is the grader's; the compile and the answers program get their own).
SECRET_ENV = "RAYKIT_SELFTEST_SECRET"


def secret(path: Path = SECRET_FILE) -> bytes:
    """The kit's secret, made on first use (the self-test's, while it runs)."""
    pinned = os.environ.get(SECRET_ENV)
    if pinned:
        try:
            return bytes.fromhex(pinned)
        except ValueError:
            raise KitError(f"{SECRET_ENV}: not hexadecimal")
    key = _read(path)
    if key is not None:
        return key
    try:
        return write_new(path)
    except FileExistsError:     # another grading made it a moment ago
        key = _read(path)
        if key is None:
            raise KitError(f"{path}: the hidden cases' secret vanished while it was read")
        return key
    except OSError as e:
        raise KitError(f"{path}: cannot make the hidden cases' secret ({e.strerror})")


def existing(path: Path = SECRET_FILE) -> bytes | None:
    """The kit's secret (the self-test's, while it runs), or None when there is none yet; never makes one."""
    return secret() if os.environ.get(SECRET_ENV) else _read(path)


def fingerprint_of(key: bytes) -> str:
    return hmac.new(key, b"raykit-secret-fingerprint-1", hashlib.sha256).hexdigest()[:16]


def fingerprint(path: Path = SECRET_FILE) -> str:
    """A name for the secret that reveals nothing of it (an HMAC of a fixed text under it), for a results
    record to say which secret drew its hidden inputs: gradings merged from several machines must share
    one (report/merge.py). Empty when there is no secret yet; never makes one."""
    key = existing(path)
    return fingerprint_of(key) if key is not None else ""


# --- the seal of what a grading keeps (a results record, a grading's manifest) -------------------------
#
# Each record ./kit grade keeps, and the manifest of what judged it (judgedby.py), carries under "mac" an
# HMAC-SHA256 of its own content (canonical(): every field but "mac", keys sorted, no spaces, UTF-8) under
# a key derived from the secret. Whoever holds one record (a student's own, a TA's copy) learns nothing
# that seals another, or the same with another score. Only the kit's own processes compute it: the
# grading's parent (commands/grade.py) and the merge; no environment, file or argument of a graded
# process holds the secret or this key (docs/integrity.md).
MAC_FIELD = "mac"


def _mac_key(key: bytes) -> bytes:
    return hmac.new(key, b"raykit-seal-key-1", hashlib.sha256).digest()


def canonical(data: dict) -> bytes:
    """What the seal covers: the record without its seal, serialised one way only."""
    return json.dumps({k: v for k, v in data.items() if k != MAC_FIELD}, sort_keys=True, separators=(",", ":"),
                      ensure_ascii=False, allow_nan=True).encode("utf-8", "surrogatepass")


def seal(data: dict, key: bytes) -> dict:
    """`data` with its seal under the secret `key`."""
    return dict(data, **{MAC_FIELD: hmac.new(_mac_key(key), canonical(data), hashlib.sha256).hexdigest()})


def sealed(data: dict, key: bytes) -> bool:
    """Whether `data` carries the seal of its own content under `key`."""
    mac = data.get(MAC_FIELD)
    return isinstance(mac, str) and hmac.compare_digest(
        mac, hmac.new(_mac_key(key), canonical(data), hashlib.sha256).hexdigest())


def copy_into(target: Path) -> None:
    """Puts the kit's secret at `target` (inside an autograder's copy of the kit), mode 0600."""
    target.unlink(missing_ok=True)
    write_new(target, secret())


def code_only(data: bytes) -> bytes:
    """A C++ file's tokens without its comments, each run of white space one space (none at the ends):
    what the compiler reads, so that a comment or a re-indentation draws no other hidden inputs.
    String and character literals are kept byte for byte (a `//` inside one is no comment); a
    backslash-newline joins lines as the preprocessor does. Anything it cannot read (an unfinished
    literal or comment) is kept as it is: a file that does not compile draws on its bytes."""
    text = data.replace(b"\\\r\n", b"").replace(b"\\\n", b"")
    out = bytearray()
    i, n = 0, len(text)
    pending_space = False

    def emit(chunk: bytes) -> None:
        nonlocal pending_space
        if pending_space and out:
            out.append(0x20)
        pending_space = False
        out.extend(chunk)

    while i < n:
        c = text[i]
        if c in b" \t\r\n\f\v":
            pending_space = True
            i += 1
        elif text.startswith(b"//", i):
            end = text.find(b"\n", i)
            i = n if end < 0 else end
            pending_space = True
        elif text.startswith(b"/*", i):
            end = text.find(b"*/", i + 2)
            if end < 0:
                return data
            i = end + 2
            pending_space = True
        elif c in b"\"'":
            j = i + 1
            while j < n and text[j] != c:
                if text[j] == 0x5C:        # a backslash escapes the next byte
                    j += 1
                elif text[j] == 0x0A:
                    return data
                j += 1
            if j >= n:
                return data
            emit(text[i:j + 1])
            i = j + 1
        else:
            j = i + 1
            while j < n and text[j] not in b" \t\r\n\f\v\"'" and not text.startswith(b"//", j) \
                    and not text.startswith(b"/*", j):
                j += 1
            emit(text[i:j])
            i = j
    return bytes(out)


def hidden_seed(step_folder: str, files: list[bytes | None], identity: str = "", key: bytes | None = None) -> str:
    """The seed of one step's hidden cases for one submission (see the module's text)."""
    mac = hmac.new(key if key is not None else secret(), digestmod=hashlib.sha256)
    mac.update(b"raykit-hidden-seed-3\0")
    mac.update(step_folder.encode() + b"\0" + identity.encode("utf-8", "surrogateescape") + b"\0")
    for data in files:
        mac.update(hashlib.sha256(code_only(data)).digest() if data is not None else b"\0missing")
    return mac.hexdigest()[:SEED_HEX]

"""The kit's core: where things are, errors and the terminal, the steps. Every other module may
import it; it imports none of the kit's (builds are build.py's)."""

from __future__ import annotations

import json
import os
import re
import shutil
import sys
import threading
from dataclasses import dataclass, field
from pathlib import Path

from .status import USAGE

ROOT = Path(__file__).resolve().parents[2]
BUILD = ROOT / "build"


class KitError(Exception):
    """A problem the user can fix: printed as one clear message, exit status `code`."""

    def __init__(self, message: str, code: int = USAGE):
        super().__init__(message)
        self.code = code


# --- terminal ------------------------------------------------------------------

_COLOR = sys.stdout.isatty() and os.environ.get("NO_COLOR") is None and os.environ.get("TERM") != "dumb"


def paint(text: str, style: str) -> str:
    codes = {"green": "32", "red": "31", "yellow": "33", "bold": "1", "dim": "2", "cyan": "36"}
    if not _COLOR:
        return text
    return f"\033[{codes[style]}m{text}\033[0m"


def say(text: str = "") -> None:
    print(text, flush=True)


def note(text: str) -> None:
    print(paint(text, "dim"), file=sys.stderr, flush=True)


# C0 controls but tab and newline, DEL, and the C1 controls (U+0080-U+009F): an escape sequence
# in a student's output could clear the instructor's screen, forge a score or write the clipboard.
# Also lone surrogates: a file name that is not UTF-8 reaches Python as U+DC80-U+DCFF (one per byte,
# 0x9b, a C1 CSI, among them), which no UTF-8 file or terminal can take.
_CONTROLS = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\ud800-\udfff]")


def _shown(m: re.Match) -> str:
    code = ord(m.group())
    if 0xdc80 <= code <= 0xdcff:        # the byte a file name had (os.fsdecode's surrogateescape)
        return f"\\x{code - 0xdc00:02x}"
    return f"\\x{code:02x}" if code <= 0xff else f"\\u{code:04x}"


def printable(text: str) -> str:
    """`text` from outside the kit (a student's output, exception text, compiler diagnostics, a
    student's name) as data: control characters shown as visible escapes, never sent raw. The one
    filter for what the kit prints or writes from a student: the terminal, the CSV files of ./kit
    grade, the report's pages (report/pages.py), file names (student_file_name below)."""
    return _CONTROLS.sub(_shown, text.replace("\r\n", "\n"))


def student_file_name(name: str) -> str:
    """A student's name as the name of a file the kit writes for them (their results JSON, their saved
    files): printable(), tab and newline shown too. printable() of the name gives the same file name,
    so the report finds a student's files from the name in the CSV."""
    return printable(name).replace("\t", "\\x09").replace("\n", "\\x0a")


# --- steps -------------------------------------------------------------------

@dataclass
class Step:
    """One numbered step, described by tests/NN_topic/step.json."""

    folder: str                 # "01_unit_sphere"
    title: str
    files: list[str]
    needs: list[str]
    lecture: str                # "lectures/01-unit-sphere.md"
    functions: list[str] = field(default_factory=list)
    # "header:function:condition" -> the cases that ask each "no answer" rule its header states
    contract: dict[str, list[str]] = field(default_factory=dict)

    @property
    def number(self) -> str:
        return self.folder[:2]

    @property
    def target(self) -> str:
        return f"test_step{self.number}"


def load_steps() -> list[Step]:
    return [Step(folder=manifest.parent.name, title=data["title"], files=data["files"], needs=data.get("needs", []),
                 lecture=data["lecture"], contract=data.get("contract", {}),
                 functions=[f["name"] if isinstance(f, dict) else f for f in data.get("functions", [])])
            for manifest in sorted((ROOT / "tests").glob("[0-9][0-9]_*/step.json"))
            for data in [json.loads(manifest.read_text())]]


def select_steps(steps: list[Step], wanted: list[str]) -> list[Step]:
    """Steps named by number ("1", "01") or folder; all of them when none is named."""
    if not wanted:
        return steps
    chosen = []
    for w in wanted:
        match = [s for s in steps if w == s.folder or (w.isdigit() and int(w) == int(s.number))]
        if not match:
            known = ", ".join(str(int(s.number)) for s in steps)
            raise KitError(f"there is no step {w!r}; the steps are {known}")
        if match[0] not in chosen:
            chosen.append(match[0])
    return sorted(chosen, key=lambda s: s.number)


def prerequisites(step: Step, steps: list[Step]) -> list[Step]:
    """The steps `step` links, directly or through another, in course order; only those of `steps`
    (a self-test of one step passes that step alone)."""
    by_number = {s.number: s for s in steps}
    found: set[str] = set()
    todo = list(step.needs)
    while todo:
        n = todo.pop()
        if n not in found and n in by_number:
            found.add(n)
            todo += by_number[n].needs
    return [s for s in steps if s.number in found]


def stage_on_reference(target: Path, step: Step, steps: list[Step], files: Path) -> Path:
    """A steps folder at `target`: the reference answers of the steps `step` needs and of `step`
    itself, with the files in `files` (a stub, a mutant's changed files) laid over the latter."""
    shutil.rmtree(target, ignore_errors=True)
    for s in prerequisites(step, steps) + [step]:
        shutil.copytree(ROOT / "solutions" / s.folder, target / s.folder)
    shutil.copytree(files, target / step.folder, dirs_exist_ok=True)
    return target


def writable_parent(shown: str, target: Path) -> None:
    """Raises KitError, naming `shown` (the path as the user wrote it), when `target` cannot be
    created: its folder is missing or not writable. Checked before any work, never after it."""
    parent = target.resolve().parent
    if not parent.is_dir():
        raise KitError(f"{shown}: folder {parent} does not exist")
    if not os.access(parent, os.W_OK):
        raise KitError(f"{shown}: cannot write in {parent}")

def resolve_steps_dir(path: str) -> Path:
    """A student's steps folder, or a whole copy of the kit that holds one."""
    p = Path(path).expanduser()
    if not p.exists():
        raise KitError(f"--steps {path}: no such folder")
    if not p.is_dir():
        raise KitError(f"--steps {path}: not a folder")
    p = p.resolve()
    steps = load_steps()
    if not any((p / s.folder).is_dir() for s in steps) and (p / "steps").is_dir():
        p = p / "steps"
    if not any((p / s.folder).is_dir() for s in steps):
        names = ", ".join(s.folder for s in steps)
        raise KitError(f"--steps {path}: holds none of the step folders ({names})")
    return p


QUICK_TIER = "RAYKIT_SELFTEST_QUICK"    # set by ./kit test --quick: its self-tests build nothing


# concurrent.futures' ThreadPoolExecutor would do what these two do, but importing it imports
# `logging` too: 55 ms of CPU at every start of ./kit check (measured, Python 3.11), for two loops.

def map_in_threads(function, items: list, workers: int) -> list:
    """function(item) for every item, in up to `workers` threads at once; the results in the
    items' order. An exception in any call is raised here, once every call has ended."""
    results: list = [None] * len(items)
    errors: list[BaseException] = []
    indexes = iter(range(len(items)))
    lock = threading.Lock()

    def work() -> None:
        while True:
            with lock:
                i = next(indexes, None)
            if i is None:
                return
            try:
                results[i] = function(items[i])
            except BaseException as e:      # raised again by the caller's thread, below
                errors.append(e)

    threads = [threading.Thread(target=work) for _ in range(max(1, min(workers, len(items))))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]
    return results


class InOrder:
    """Calls run one at a time in a background thread, each after the one given before it, while
    the caller goes on (the judge of one step while the next step builds). finish() waits for
    every call and raises the first exception any raised."""

    def __init__(self) -> None:
        self._last: threading.Thread | None = None
        self._errors: list[BaseException] = []

    def submit(self, function, *args) -> None:
        before = self._last

        def run() -> None:
            if before is not None:
                before.join()
            try:
                function(*args)
            except BaseException as e:
                self._errors.append(e)

        self._last = threading.Thread(target=run)
        self._last.start()

    def finish(self, raising: bool = True) -> None:
        if self._last is not None:
            self._last.join()
        if self._errors and raising:
            raise self._errors[0]


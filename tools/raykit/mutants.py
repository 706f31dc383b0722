"""Mutants: a wrong answer with one realistic slip, kept as tests/mutants/NN_topic/NAME.patch against
solutions/ (the format is commands/mutant.py's to write; here it is read, applied and graded). Below
`./kit mutant` and the class report's signatures (report/signatures.py), which both import it."""

from __future__ import annotations

import difflib
import json
import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path

from .common import BUILD, ROOT, KitError, Step, load_steps, stage_on_reference

MUTANTS = ROOT / "tests" / "mutants"
SOLUTIONS = ROOT / "solutions"
WORK = BUILD / "mutants"            # the instructor's copies, one folder per mutant
# One line of context around each change: enough to place a hunk exactly, and two slips in the
# same line of the reference share no more than the lines they both remove.
CONTEXT_LINES = 1
GRADE_SECONDS = 900                 # one mutant, build included

_HEADER = re.compile(r"^Slip: (?P<slip>.+?)\s+Caught by: (?P<cases>.*)$")
_HUNK = re.compile(r"^@@ -(\d+)(?:,(\d+))? \+(\d+)(?:,(\d+))? @@")
_NAME = re.compile(r"^[a-z0-9][a-z0-9_]*$")


class PatchError(Exception):
    """A patch that cannot be read or no longer fits the reference answer."""


@dataclass
class Hunk:
    start: int                      # 1-based line of the old text where it begins
    old: list[str]                  # context and removed lines, as the reference has them
    new: list[str]                  # context and added lines


@dataclass
class Mutant:
    step: Step
    name: str
    slip: str
    cases: list[str]                # the cases that must catch it (at least one of them fails)
    files: dict[str, list[Hunk]] = field(default_factory=dict)   # file name in the step -> hunks

    @property
    def path(self) -> Path:
        return MUTANTS / self.step.folder / f"{self.name}.patch"


# --- the patch format ------------------------------------------------------------

def header_line(slip: str, cases: list[str]) -> str:
    named = ", ".join(f'"{c}"' for c in cases) if cases else "(no case yet)"
    return f"Slip: {slip} Caught by: {named}"


def write_patch(step: Step, slip: str, cases: list[str], changed: dict[str, str]) -> str:
    """The patch text: the header, then one unified diff per file whose text differs from the reference."""
    if "\n" in slip or '"' in slip:
        raise KitError("--slip must be one line without double quotes")
    out = [header_line(slip, cases) + "\n"]
    for file_name in sorted(changed):
        ref = (SOLUTIONS / step.folder / file_name).read_text()
        rel = f"solutions/{step.folder}/{file_name}"
        out += difflib.unified_diff(ref.splitlines(keepends=True), changed[file_name].splitlines(keepends=True),
                                    fromfile=f"a/{rel}", tofile=f"b/{rel}", n=CONTEXT_LINES)
    return "".join(out)


def read_patch(path: Path, step: Step) -> Mutant:
    """Parses tests/mutants/NN_topic/NAME.patch; raises PatchError saying what is wrong with it."""
    lines = path.read_text().splitlines()
    m = _HEADER.match(lines[0]) if lines else None
    if not m:
        raise PatchError('its first line must be: Slip: <the slip>. Caught by: "<case>", ...')
    mutant = Mutant(step, path.stem, m.group("slip"), re.findall(r'"([^"]+)"', m.group("cases")))
    read_diff(lines, 1, mutant)
    if not mutant.files:
        raise PatchError("it changes nothing: no diff after the header")
    return mutant


def read_diff(lines: list[str], first: int, mutant: Mutant) -> None:
    """Reads the unified diffs of lines[first:] (files of the mutant's step in solutions/) into
    mutant.files; raises PatchError saying what is wrong. Also read by the grader's fixtures kept as
    patches (tests/kit/fixtures.py)."""
    step = mutant.step
    prefix = f"solutions/{step.folder}/"
    i, hunks = first, None
    while i < len(lines):
        line = lines[i]
        if line.startswith("--- "):
            target = lines[i + 1][4:].split("\t")[0] if i + 1 < len(lines) and lines[i + 1].startswith("+++ ") else ""
            target = target[2:] if target.startswith("b/") else target
            if not target.startswith(prefix) or "/" in target[len(prefix):]:
                raise PatchError(f"line {i + 2}: it changes {target or '?'}, not a file of {prefix}")
            hunks = mutant.files.setdefault(target[len(prefix):], [])
            i += 2
        elif _HUNK.match(line) and hunks is not None:
            start, old_n, _, new_n = (int(g) if g is not None else 1 for g in _HUNK.match(line).groups())
            hunk = Hunk(start, [], [])
            i += 1
            while (len(hunk.old) < old_n or len(hunk.new) < new_n) and i < len(lines):
                body = lines[i]
                if body.startswith("\\"):       # "\ No newline at end of file"
                    i += 1
                    continue
                kind, text = (body[:1] or " "), body[1:]
                if kind not in " -+":
                    raise PatchError(f"line {i + 1}: a hunk line must start with ' ', '-' or '+'")
                if kind in " -":
                    hunk.old.append(text)
                if kind in " +":
                    hunk.new.append(text)
                i += 1
            if len(hunk.old) != old_n or len(hunk.new) != new_n:
                raise PatchError(f"the hunk at line {start} is cut short")
            hunks.append(hunk)
        elif line.strip():
            raise PatchError(f"line {i + 1}: not part of a unified diff: {line[:60]!r}")
        else:
            i += 1


def _find(lines: list[str], block: list[str], near: int) -> int:
    """Where `block` stands in `lines`, the place nearest `near` (0-based), or -1. Like patch(1), a
    hunk may have moved (the reference grew elsewhere), but its lines must match exactly: no fuzz."""
    places = [k for k in range(len(lines) - len(block) + 1) if lines[k:k + len(block)] == block]
    return min(places, key=lambda k: abs(k - near)) if places else -1


def apply_patch(mutant: Mutant) -> dict[str, str]:
    """The mutant's files: the reference files its patch changes, with the patch applied."""
    out = {}
    for file_name, hunks in mutant.files.items():
        source = SOLUTIONS / mutant.step.folder / file_name
        if not source.is_file():
            raise PatchError(f"solutions/{mutant.step.folder}/{file_name} does not exist")
        lines = source.read_text().splitlines()
        shift = 0
        for n, hunk in enumerate(hunks, 1):
            at = _find(lines, hunk.old, hunk.start - 1 + shift)
            if at < 0:
                raise PatchError(f"hunk {n} (line {hunk.start}) no longer matches solutions/"
                                 f"{mutant.step.folder}/{file_name}: the lines it changes have changed")
            lines[at:at + len(hunk.old)] = hunk.new
            shift += len(hunk.new) - len(hunk.old)
        out[file_name] = "\n".join(lines) + "\n"
    return out


def reference_with(step: Step, files: dict[str, str], folder: Path) -> Path:
    """`folder` made anew: the step's reference files, with `files` ({name: text}) in their place."""
    shutil.rmtree(folder, ignore_errors=True)
    shutil.copytree(SOLUTIONS / step.folder, folder)
    for file_name, text in files.items():
        (folder / file_name).write_text(text)
    return folder


def write_answer(step: Step, patch: Path, folder: Path) -> Path:
    """Writes the mutant's whole answer to the step into `folder`: the reference files, with the
    patched ones in their place (for a self-test that needs a wrong answer as files)."""
    return reference_with(step, apply_patch(read_patch(patch, step)), folder)


def patches(step: Step) -> list[Path]:
    folder = MUTANTS / step.folder
    return sorted(folder.glob("*.patch")) if folder.is_dir() else []


# --- grading a mutant -------------------------------------------------------------

def grade_files(step: Step, files: dict[str, str], work: Path) -> tuple[int, dict | None]:
    """Grades the mutant's files (laid over the reference answers) the way a student's work is
    graded: `./kit check N --steps DIR --json F`. Returns the exit status and the step's result."""
    import subprocess

    changed = work / "changed"
    shutil.rmtree(changed, ignore_errors=True)
    changed.mkdir(parents=True)
    for file_name, text in files.items():
        (changed / file_name).write_text(text)
    staged = stage_on_reference(work / "steps", step, load_steps(), changed)
    report = work / "result.json"
    report.unlink(missing_ok=True)
    try:
        r = subprocess.run([str(ROOT / "kit"), "check", str(int(step.number)), "--steps", str(staged),
                            "--results", str(report), "--quiet"], cwd=ROOT, capture_output=True, text=True,
                           timeout=GRADE_SECONDS)
    except subprocess.TimeoutExpired:
        return -1, None     # the grader limits every case; a build that never ends is reported as not caught
    result = json.loads(report.read_text())["steps"][0] if report.exists() else None
    return r.returncode, result


def failing_cases(result: dict | None) -> list[str]:
    """The basic cases the mutant fails, in the suite's order."""
    return [c["name"] for c in (result or {}).get("cases", []) if c["tier"] == "basic" and c["status"] != "pass"]

"""The mutants' signatures: which basic cases each mutant of tests/mutants/ fails, recorded as data.

A signature is computed by grading the mutant the way a student's work is graded (commands/mutant.py,
grade_files), which takes a build per step; so the signatures are written once, by
`./kit report --signatures`, to tests/mutants/signatures.json, and the report only reads them. Each
entry keeps a fingerprint of what the signature depends on (the patch, the step's reference answer
and its tests): when one of them changes, the entry is stale and the self-test says so.

Only the basic tier counts: it is the same for every student, while the hidden cases are drawn with
a seed per grading and the ★ tier is optional.

A student's failing basic cases F, in one step, match a mutant's signature S exactly when F = S, and
nearly when the distance |F △ S| (the cases in one set and not in the other) is small beside the
two sets (at most NEAR_SHARE of |F ∪ S|, at least 1); otherwise the pattern fits no slip.
"""

from __future__ import annotations

import hashlib
import json
import re
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from raykit import atomic
from raykit.common import ROOT, Step, load_steps
from raykit.mutants import PatchError, apply_patch, failing_cases, grade_files, patches, read_patch

FILE = ROOT / "tests" / "mutants" / "signatures.json"
NEAR_SHARE = 1 / 3


@dataclass(frozen=True)
class Signature:
    key: str                # "01_unit_sphere/open_window"
    step: str               # "01"
    name: str
    slip: str
    lecture: str            # the lecture section most of its failing cases belong to
    fails: frozenset


def fingerprint(step: Step, patch: Path) -> str:
    """A hash of what a mutant's signature depends on: its patch, the step's reference files and tests
    (tests/NN_topic/, its Markdown and step.json's lines for README's table aside)."""
    h = hashlib.sha256(patch.read_bytes())
    for folder in (ROOT / "solutions" / step.folder, ROOT / "tests" / step.folder):
        for p in sorted(folder.rglob("*")) if folder.is_dir() else []:
            if p.is_file() and p.suffix != ".md":      # a hint or a README changes no case
                data = p.read_bytes()
                if p.name == "step.json":               # nor does the README's summary of the step
                    data = DOC_LINES.sub(b"", data)
                h.update(str(p.relative_to(ROOT)).encode() + b"\0" + data)
    return h.hexdigest()[:16]


# step.json's keys that only describe the step for README's table (docs/readme_steps.py), one line each.
DOC_LINES = re.compile(rb'(?m)^[ \t]*"(?:summary|picture_note)": "(?:[^"\\\n]|\\.)*",[ \t]*\r?\n')


def compute(progress=print, numbers: list[str] | None = None) -> dict:
    """Grades every mutant (of the steps `numbers` only, keeping the other steps' recorded signatures)
    and returns the file's content. Takes a build per mutant."""
    from raykit.common import BUILD

    entries, problems = {}, []
    if numbers:
        try:
            entries = {k: e for k, e in json.loads(FILE.read_text())["mutants"].items()
                       if isinstance(e, dict) and e.get("step") not in numbers}
        except (OSError, ValueError, KeyError, TypeError, AttributeError):
            entries = {}
    work = BUILD / "mutant-signatures"
    for step in load_steps():
        if numbers and step.number not in numbers:
            continue
        for path in patches(step):
            key = f"{step.folder}/{path.stem}"
            try:
                mutant = read_patch(path, step)
                files = apply_patch(mutant)
            except PatchError as e:
                problems.append(f"{key}: {e}")
                continue
            _, result = grade_files(step, files, work)
            fails = failing_cases(result)
            # Its lecture section: that of the cases its patch names (made for this slip), else the most common.
            cases = (result or {}).get("cases", [])
            lectures = (Counter(c["lecture"] for c in cases if c["name"] in mutant.cases and c["name"] in fails)
                        or Counter(c["lecture"] for c in cases if c["name"] in fails))
            entries[key] = {"step": step.number, "slip": mutant.slip,
                            "lecture": lectures.most_common(1)[0][0] if lectures else "",
                            "fails": fails, "fingerprint": fingerprint(step, path)}
            progress(f"{key}: {len(fails)} basic case(s) fail")
    return {"about": "which basic cases each mutant fails; written by ./kit report --signatures",
            "mutants": entries, "problems": problems}


def write(data: dict, target: Path = FILE) -> None:
    atomic.write(target, json.dumps(data, indent=1, ensure_ascii=False, sort_keys=True) + "\n")


def load(target: Path = FILE) -> tuple[list[Signature], list[str]]:
    """The signatures recorded, and the notes to show: mutants without one, stale ones."""

    try:
        data = json.loads(target.read_text())
        recorded = data["mutants"]
    except (OSError, ValueError, KeyError, TypeError):
        recorded = {}
    out, missing, stale = [], [], []
    for step in load_steps():
        for path in patches(step):
            key = f"{step.folder}/{path.stem}"
            e = recorded.get(key)
            if not isinstance(e, dict) or not isinstance(e.get("fails"), list):
                missing.append(key)
                continue
            if e.get("fingerprint") != fingerprint(step, path):
                stale.append(key)
            out.append(Signature(key, step.number, path.stem, str(e.get("slip", "")), str(e.get("lecture", "")),
                                 frozenset(e["fails"])))
    notes = []
    if missing:
        notes.append(f"{len(missing)} mutant(s) have no recorded signature and are left out "
                     f"({', '.join(missing[:6])}{', ...' if len(missing) > 6 else ''}): ./kit report --signatures")
    if stale:
        notes.append(f"{len(stale)} signature(s) were recorded before their patch, reference or tests changed "
                     f"({', '.join(stale[:6])}{', ...' if len(stale) > 6 else ''}): ./kit report --signatures")
    return out, notes


@dataclass
class Match:
    kind: str               # "exact", "near" or "none"
    distance: int
    signatures: list        # the mutants at that distance (several may share a signature)


def match(fails: frozenset, signatures: list[Signature]) -> Match:
    """The mutants of the step whose signature is nearest the failing basic cases: all those at the
    smallest distance, when it is 0 (exact) or small beside the sets (near), else none."""
    if not signatures or not fails:
        return Match("none", 0, [])
    best = min(len(fails ^ s.fails) for s in signatures)
    nearest = [s for s in signatures if len(fails ^ s.fails) == best]
    if best == 0:
        return Match("exact", 0, nearest)
    nearest = [s for s in nearest if best <= max(1, int(NEAR_SHARE * len(fails | s.fails))) and fails & s.fails]
    return Match("near", best, nearest) if nearest else Match("none", best, [])

"""Similar submissions, found by Debian's similarity-tester (sim_c++), per step file.

sim_c++ compares token streams: layout, comments and the names of identifiers do not count, so a
copy with renamed variables and new comments still matches, and functions moved around still match
run by run. Before the comparison each student's file loses the lines of the shipped stub (the
signatures and comments every student starts from) and its #include lines (the kit's headers), each
replaced by an empty line so that sim's line numbers are the file's own.

Every submission resembles the reference answer in part, because the answer is short and a correct
one looks much like any other. A file made mostly of the reference's material (REFERENCE_LIKE per
cent or more of it, as sim_c++ measures) is a copy of the solutions, and two such files are not
compared: they are grouped and counted. The other pairs are ranked by the smaller of their two shares
(how much of A is in B, how much of B is in A). Similarity is a reason to look, not a proof.

Three passes of sim_c++ per step file keep a class of hundreds fast: every file against the reference
alone (-S, the reference an "old" file); all files at once (-a), which names for each file the files
its runs are found in, but credits each run to one of them; then each pair so named on its own (-a -e,
exact shares both ways). Comparing every pair on its own from the start (-e) takes seconds per step
file for 300 students, quadratic in their number.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from ..common import ROOT, Step, student_file_name

REFERENCE_LIKE = 80     # per cent of a student's file found in the reference
SHOWN = 30              # a pair is listed from this share on
REFERENCE = "(reference)"

_PERCENT = re.compile(r"^(.+?) consists for (\d+) % of (.+?) material$")
_TOKENS = re.compile(r"^File (.+?): (\d+) tokens, (\d+) lines$")
_RUN = re.compile(r"^(.+?): line (\d+)-(\d+)\s*\|(.+?): line (\d+)-(\d+)\s*\[(\d+)\]")


@dataclass
class Pair:
    a: str
    b: str
    score: int                              # the best file's smaller share, per cent
    files: dict = field(default_factory=dict)   # "NN_topic/file" -> (share of a in b, share of b in a)
    runs: list = field(default_factory=list)    # (lines of a, lines of b, tokens) of the best file
    best: str = ""
    lines: tuple = ((), ())                     # the best file's lines, of a and of b


@dataclass
class Similarity:
    available: bool
    note: str = ""
    compared: int = 0                       # students with at least one file compared
    reference_like: dict = field(default_factory=dict)     # "NN_topic/file" -> [students]
    copies: list = field(default_factory=list)             # students whose every file is reference-like
    pairs: list = field(default_factory=list)              # Pair, best first


def strip(text: str, stub: set) -> str:
    lines = []
    for line in text.splitlines():
        s = line.strip()
        lines.append("" if (s in stub or s.startswith("#include")) else line)
    return "\n".join(lines) + "\n"


def _sim(args: list[str], files: list, timeout: float = 300) -> str:
    r = subprocess.run(["sim_c++", *args, "-i"], input="\n".join(str(f) for f in files) + "\n",
                       capture_output=True, text=True, timeout=timeout)
    return r.stdout


def compare(files_root: Path | None, names: list[str], steps: list[Step], shown: int = 10) -> Similarity:
    if files_root is None:
        return Similarity(False, "the submissions' files were not saved with this grading: run ./kit report "
                                 "GRADING_DIR --submissions SUBMISSIONS (or ./kit grade --report)")
    if shutil.which("sim_c++") is None:
        return Similarity(False, "sim_c++ is not installed (Debian's similarity-tester): "
                                 "sudo apt-get install similarity-tester")
    result = Similarity(True)
    shares: dict[tuple, dict] = {}          # (a, b) -> {file: (a in b, b in a)}
    like_by_student: dict[str, list[bool]] = {}
    texts: dict[tuple, str] = {}
    with tempfile.TemporaryDirectory(prefix="raykit-sim-") as tmp:
        work = Path(tmp)
        for step in steps:
            for f in step.files:
                key = f"{step.folder}/{f}"
                stub_path = ROOT / "steps" / step.folder / f
                stub = {l.strip() for l in stub_path.read_text(errors="replace").splitlines()} if stub_path.is_file() else set()
                stub.discard("")
                who: dict[str, str] = {}
                paths = []
                for i, name in enumerate([REFERENCE] + names):
                    src = (ROOT / "solutions" / step.folder / f) if name == REFERENCE else \
                        files_root / student_file_name(name) / step.folder / f
                    if not src.is_file():
                        continue
                    text = strip(src.read_text(errors="replace"), stub)
                    if not text.strip():
                        continue
                    path = work / str(i) / step.folder / f
                    path.parent.mkdir(parents=True, exist_ok=True)
                    path.write_text(text)
                    who[str(path)] = name
                    paths.append(path)
                    texts[(name, key)] = text
                students = [p for p in paths if who[str(p)] != REFERENCE]
                refs = [p for p in paths if who[str(p)] == REFERENCE]
                if not students:
                    continue
                # How much of each file is the reference's material: every file against the reference alone.
                of_ref = {}
                if refs:
                    for line in _sim(["-p", "-S", "-t", "1"], students + ["/"] + refs).splitlines():
                        m = _PERCENT.match(line.strip())
                        if m and m.group(1) in who:
                            of_ref[who[m.group(1)]] = int(m.group(2))
                present = [who[str(p)] for p in students]
                like = {n for n in present if of_ref.get(n, 0) >= REFERENCE_LIKE}
                result.reference_like[key] = sorted(like)
                for n in present:
                    like_by_student.setdefault(n, []).append(n in like)
                # The candidates: sim_c++ -a names, for each file, the files its runs are found in (fast, but
                # each run is credited to one file); each candidate pair is then measured on its own (-a -e).
                path_of = {who[str(p)]: p for p in students}
                candidates = set()
                for line in _sim(["-p", "-a", "-s", "-t", str(SHOWN)], students).splitlines():
                    m = _PERCENT.match(line.strip())
                    if m and m.group(1) in who and m.group(3) in who:
                        a, b = sorted((who[m.group(1)], who[m.group(3)]))
                        if a != b and not (a in like and b in like):
                            candidates.add((a, b))
                for a, b in sorted(candidates):
                    both = {}
                    for line in _sim(["-p", "-a", "-e", "-s", "-t", "1"], [path_of[a], path_of[b]]).splitlines():
                        m = _PERCENT.match(line.strip())
                        if m and m.group(1) in who:
                            both[who[m.group(1)]] = int(m.group(2))
                    ab, ba = both.get(a, 0), both.get(b, 0)
                    if min(ab, ba) > 0:
                        shares.setdefault((a, b), {})[key] = (ab, ba)
        result.compared = len(like_by_student)
        result.copies = sorted(n for n, flags in like_by_student.items() if flags and all(flags))
        pairs = []
        for (a, b), by_file in shares.items():
            best = max(by_file, key=lambda k: min(by_file[k]))
            score = min(by_file[best])
            if score >= SHOWN:
                pairs.append(Pair(a, b, score, by_file, best=best))
        pairs.sort(key=lambda p: (-p.score, -sum(min(v) for v in p.files.values()), p.a, p.b))
        result.pairs = pairs[:shown]
        for p in result.pairs:
            p.runs = runs(work, texts[(p.a, p.best)], texts[(p.b, p.best)], p.best)
            p.lines = tuple(_original(files_root, n, p.best).splitlines() for n in (p.a, p.b))
    return result


def _original(files_root: Path, name: str, key: str) -> str:
    path = ROOT / "solutions" / key if name == REFERENCE else files_root / student_file_name(name) / key
    return path.read_text(errors="replace")


def runs(work: Path, a_text: str, b_text: str, key: str) -> list[tuple]:
    """The matching runs of two files: ((first, last) line of a, (first, last) line of b, tokens)."""
    a, b = work / "pair" / "a" / Path(key).name, work / "pair" / "b" / Path(key).name
    for p, t in ((a, a_text), (b, b_text)):
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(t)
    out = []
    for line in _sim(["-s", "-n"], [a, b]).splitlines():
        m = _RUN.match(line.strip())
        if m and m.group(1) == str(a) and m.group(4) == str(b):
            out.append(((int(m.group(2)), int(m.group(3))), (int(m.group(5)), int(m.group(6))), int(m.group(7))))
    return sorted(out, key=lambda r: -r[2])

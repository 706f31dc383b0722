"""Similar submissions, found by Debian's similarity-tester (sim_c++), per step file.

sim_c++ compares token streams: layout, comments and the names of identifiers do not count, so a
copy with renamed variables and new comments still matches, and functions moved around still match
run by run. Before the comparison each student's file loses the lines of the shipped stub (the
signatures and comments every student starts from) and its #include lines (the kit's headers), each
replaced by an empty line so that sim's line numbers are the file's own.

Three things are set apart before any pair is ranked, step file by step file:

- A file made mostly of a version of the reference (REFERENCE_LIKE per cent or more of it, as sim_c++
  measures) is a copy of the solutions: today's solutions/ and, when the kit is a git clone, every
  older text of that file in solutions/'s history (a course that handed out an older answer sees its
  copies recognised). Every submission resembles the reference in part, because the answer is short.
  A file made mostly of an older text of the stub (steps/) is set aside the same way.
- A file that GROUP_MIN or more students share, byte for byte or nearly (GROUP_SAME per cent or more
  both ways, comments and layout aside), is one group: reported once with its members, never paired
  among them. A group is a reason to ask where the file came from (an older handout, a web page, a
  tutor), not a ranking of nine students against each other.
- Two reference-like files are not compared: they resemble each other through the reference.

The other pairs are ranked by the smaller of their two shares (how much of A is in B, how much of B
is in A) of their best file, counting only the files they do not share as members of one group: what
two students share beyond the groups. A student whose file is close to a group's is paired with the
group, once. Every pair from SHOWN per cent on is listed, however many there are. Similarity is a
reason to look, not a proof.

sim_c++ runs a few times per step file and keeps a class of hundreds fast: the distinct texts once
(identical files are compared once), against the reference's versions (-S -e); all distinct texts at
once (-a), which names for each file the file its runs are found in; then each pair so named on its
own (-a -e, exact shares both ways). Comparing every pair on its own from the start (-e) takes
seconds per step file for 300 students, quadratic in their number.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from raykit.common import ROOT, Step, student_file_name

REFERENCE_LIKE = 80     # per cent of a student's file found in a version of the reference (or the stub)
SHOWN = 30              # a pair is listed from this share on
GROUP_MIN = 3           # students sharing one file (byte for byte or nearly) that make a group
GROUP_SAME = 95         # per cent both ways: "nearly" the same file

_PERCENT = re.compile(r"^(.+?) consists for (\d+) % of (.+?) material$")
_RUN = re.compile(r"^(.+?): line (\d+)-(\d+)\s*\|(.+?): line (\d+)-(\d+)\s*\[(\d+)\]")
_COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)


@dataclass
class Group:
    key: str                                # "NN_topic/file"
    members: list                           # students, sorted
    texts: int = 1                          # distinct texts among them (1: the same file, comments and layout aside)
    source: str = ""                        # the version of the reference or stub it is made of, if any
    share: int = 0                          # per cent of it found in that version

    @property
    def label(self) -> str:
        return f"the group sharing {self.key} ({len(self.members)} students)"


@dataclass
class Pair:
    a: str
    b: str                                  # a student, or a Group's label
    score: int                              # the best file's smaller share, per cent
    files: dict = field(default_factory=dict)   # "NN_topic/file" -> (share of a in b, share of b in a)
    runs: list = field(default_factory=list)    # (lines of a, lines of b, tokens) of the best file
    best: str = ""
    lines: tuple = ((), ())                     # the best file's lines, of a and of b
    group: Group | None = None                  # when b is a group


@dataclass
class Similarity:
    available: bool
    note: str = ""
    compared: int = 0                       # students with at least one file compared
    reference_like: dict = field(default_factory=dict)     # "NN_topic/file" -> [students]
    stub_like: dict = field(default_factory=dict)          # "NN_topic/file" -> [students]
    versions: dict = field(default_factory=dict)           # "NN_topic/file" -> versions of the reference compared
    copies: list = field(default_factory=list)             # students whose every file is reference-like
    groups: list = field(default_factory=list)             # Group, largest first
    pairs: list = field(default_factory=list)              # Pair, best first


def strip(text: str, stub: set) -> str:
    return "\n".join("" if line.strip() in stub or line.strip().startswith("#include") else line
                     for line in text.splitlines()) + "\n"


def same_text(text: str) -> str:
    """The text with comments and layout left out: two files alike in this are one file."""
    return " ".join(_COMMENT.sub(" ", text).split())


def _sim(args: list[str], files: list, timeout: float = 300) -> str:
    r = subprocess.run(["sim_c++", *args, "-i"], input="\n".join(str(f) for f in files) + "\n",
                       capture_output=True, text=True, timeout=timeout)
    return r.stdout


def _percents(args: list[str], files: list) -> list[tuple[str, int, str]]:
    """sim_c++'s lines "A consists for N % of B material", as (A, N, B)."""
    found = (_PERCENT.match(line.strip()) for line in _sim(args, files).splitlines())
    return [(m.group(1), int(m.group(2)), m.group(3)) for m in found if m]


def versions(path: str) -> list[tuple[str, str]]:
    """Today's text of a file of the kit (path relative to ROOT) and, when the kit is a git clone, every
    older text in its history, newest first: [(label, text)], texts distinct."""
    out, seen = [], set()
    today = ROOT / path
    if today.is_file():
        text = today.read_text(errors="replace")
        out.append((f"{path} (today's)", text))
        seen.add(text)
    try:
        log = subprocess.run(["git", "-C", str(ROOT), "log", "--format=%H %h %ad", "--date=short", "--", path],
                             capture_output=True, text=True, timeout=30)
        commits = [l.split() for l in log.stdout.splitlines() if l.strip()] if log.returncode == 0 else []
        if commits:
            batch = subprocess.run(["git", "-C", str(ROOT), "cat-file", "--batch"],
                                   input="".join(f"{full}:{path}\n" for full, _, _ in commits).encode(),
                                   capture_output=True, timeout=30).stdout
            pos = 0
            for full, short, day in commits:
                end = batch.index(b"\n", pos)
                header = batch[pos:end].split()
                pos = end + 1
                if len(header) < 3 or header[1] != b"blob":
                    continue
                size = int(header[2])
                text = batch[pos:pos + size].decode(errors="replace")
                pos += size + 1
                if text not in seen:
                    seen.add(text)
                    out.append((f"{path} as of {short} ({day})", text))
    except (OSError, subprocess.SubprocessError, ValueError):
        pass
    return out


class _Union:
    def __init__(self):
        self.up = {}

    def find(self, x):
        self.up.setdefault(x, x)
        while self.up[x] != x:
            self.up[x] = self.up[self.up[x]]
            x = self.up[x]
        return x

    def join(self, a, b):
        self.up[self.find(a)] = self.find(b)


def _exact(a: Path, b: Path) -> tuple[int, int]:
    """(share of a in b, share of b in a), per cent, the two files compared on their own."""
    both = {first: pct for first, pct, _ in _percents(["-p", "-a", "-e", "-s", "-t", "1"], [a, b])}
    return both.get(str(a), 0), both.get(str(b), 0)


def compare(files_root: Path | None, names: list[str], steps: list[Step]) -> Similarity:
    if files_root is None:
        return Similarity(False, "the submissions' files were not saved with this grading: run ./kit report "
                                 "GRADING_DIR --submissions SUBMISSIONS (or ./kit grade --report)")
    if shutil.which("sim_c++") is None:
        return Similarity(False, "sim_c++ is not installed (Debian's similarity-tester): "
                                 "sudo apt-get install similarity-tester")
    result = Similarity(True)
    shares: dict[tuple, dict] = {}          # (a, b) -> {file: (a in b, b in a)}
    pair_group: dict[tuple, Group] = {}
    like_by_student: dict[str, list[bool]] = {}
    texts: dict[tuple, str] = {}            # (student or group label, file) -> stripped text
    originals: dict[tuple, str] = {}        # (student or group label, file) -> whose file to show
    with tempfile.TemporaryDirectory(prefix="raykit-sim-") as tmp:
        work = Path(tmp)
        for step in steps:
            for f in step.files:
                key = f"{step.folder}/{f}"
                stub_path = ROOT / "steps" / step.folder / f
                stub = {l.strip() for l in stub_path.read_text(errors="replace").splitlines()} if stub_path.is_file() else set()
                stub.discard("")
                # The students' texts, identical ones (comments and layout aside) written once.
                members: dict[str, list[str]] = {}      # same_text -> students
                first: dict[str, str] = {}              # same_text -> stripped text
                for name in names:
                    src = files_root / student_file_name(name) / step.folder / f
                    if not src.is_file():
                        continue
                    text = strip(src.read_text(errors="replace"), stub)
                    if not text.strip():
                        continue
                    texts[(name, key)] = text
                    originals[(name, key)] = name
                    s = same_text(text)
                    members.setdefault(s, []).append(name)
                    first.setdefault(s, text)
                if not members:
                    continue
                path_of, of = {}, {}                    # same_text -> path; str(path) -> same_text
                for i, s in enumerate(members):
                    path = work / step.folder / f"t{i}" / f
                    path.parent.mkdir(parents=True, exist_ok=True)
                    path.write_text(first[s])
                    path_of[s], of[str(path)] = path, s
                # How much of each text is a version of the reference's (or the stub's) material.
                refs, ref_label = [], {}
                old = [(label, strip(text, stub), "reference") for label, text in versions(f"solutions/{key}")]
                old += [(label, strip(text, stub), "stub") for label, text in versions(f"steps/{key}")
                        if not label.endswith("(today's)")]   # today's stub is left out of every file already
                result.versions[key] = sum(kind == "reference" for _, _, kind in old)
                for j, (label, text, kind) in enumerate(old):
                    if not text.strip():
                        continue
                    path = work / step.folder / f"r{j}" / f
                    path.parent.mkdir(parents=True, exist_ok=True)
                    path.write_text(text)
                    refs.append(path)
                    ref_label[str(path)] = (label, kind)
                best_ref: dict[str, tuple] = {}         # same_text -> (per cent, label, kind)
                if refs:
                    for a, pct, b in _percents(["-p", "-S", "-e", "-t", "1"], list(path_of.values()) + ["/"] + refs):
                        if a in of and b in ref_label and pct > best_ref.get(of[a], (-1,))[0]:
                            best_ref[of[a]] = (pct, *ref_label[b])
                like = {s for s, (pct, _, kind) in best_ref.items() if pct >= REFERENCE_LIKE and kind == "reference"}
                stubby = {s for s, (pct, _, kind) in best_ref.items() if pct >= REFERENCE_LIKE and kind == "stub"}
                result.reference_like[key] = sorted(n for s in like for n in members[s])
                result.stub_like[key] = sorted(n for s in stubby for n in members[s])
                for s, who in members.items():
                    for n in who:
                        like_by_student.setdefault(n, []).append(s in like)
                # Groups: the texts nearly the same (GROUP_SAME both ways), GROUP_MIN students or more.
                near = _Union()
                named = [(of[a], of[b], pct)
                         for a, pct, b in _percents(["-p", "-a", "-s", "-t", str(SHOWN)], list(path_of.values()))
                         if a in of and b in of and a != b]
                measured = {}
                for s, t, pct in named:
                    if pct >= GROUP_SAME:
                        measured[tuple(sorted((s, t)))] = ab = _exact(path_of[s], path_of[t])
                        if min(ab) >= GROUP_SAME:
                            near.join(s, t)
                clusters: dict[str, list[str]] = {}
                for s in members:
                    clusters.setdefault(near.find(s), []).append(s)
                group_of: dict[str, Group] = {}         # same_text -> its group
                ones = []                               # the texts paired: one per group, every other one
                for cluster in clusters.values():
                    who = sorted(n for s in cluster for n in members[s])
                    if len(who) < GROUP_MIN:
                        continue
                    main = max(cluster, key=lambda s: (len(members[s]), s))
                    g = Group(key, who, len(cluster))
                    if main in best_ref:
                        g.share, g.source = best_ref[main][0], best_ref[main][1]
                    result.groups.append(g)
                    texts[(g.label, key)] = first[main]
                    originals[(g.label, key)] = members[main][0]
                    ones.append(main)
                    for s in cluster:
                        group_of[s] = g
                # The pairs, among one text per group and every other text.
                ones += [s for s in members if s not in group_of]
                aside = like | stubby
                party = lambda s: [group_of[s].label] if s in group_of else members[s]
                for s in ones:                          # the same file, two students (too few for a group)
                    if s not in group_of and s not in aside and len(members[s]) > 1:
                        who = sorted(members[s])
                        for i, a in enumerate(who):
                            for b in who[i + 1:]:
                                shares.setdefault((a, b), {})[key] = (100, 100)
                one_path = {str(path_of[s]): s for s in ones}
                found = [tuple(sorted((one_path[a], one_path[b])))
                         for a, _, b in _percents(["-p", "-a", "-s", "-t", str(SHOWN)], [path_of[s] for s in ones])
                         if a in one_path and b in one_path]
                candidates = {(s, t) for s, t in found if s != t and not (s in aside and t in aside)}
                for s, t in sorted(candidates):
                    ab = measured.get((s, t)) or _exact(path_of[s], path_of[t])
                    if min(ab) <= 0:
                        continue
                    for a in party(s):
                        for b in party(t):
                            if a in names and b not in names:
                                pair, value = (a, b), ab
                            elif b in names and a not in names:
                                pair, value = (b, a), ab[::-1]
                            else:
                                pair, value = tuple(sorted((a, b))), ab if a <= b else ab[::-1]
                            shares.setdefault(pair, {})[key] = value
                            for x in (group_of.get(s), group_of.get(t)):
                                if x is not None:
                                    pair_group[pair] = x
        result.compared = len(like_by_student)
        result.copies = sorted(n for n, flags in like_by_student.items() if flags and all(flags))
        result.groups.sort(key=lambda g: (-len(g.members), g.key))
        best = {pair: max(by_file, key=lambda k: min(by_file[k])) for pair, by_file in shares.items()}
        pairs = [Pair(a, b, min(by_file[best[a, b]]), by_file, best=best[a, b], group=pair_group.get((a, b)))
                 for (a, b), by_file in shares.items() if min(by_file[best[a, b]]) >= SHOWN]
        result.pairs = sorted(pairs, key=lambda p: (-p.score, -sum(min(v) for v in p.files.values()), p.a, p.b))
        for p in result.pairs:
            p.runs = runs(work, texts[(p.a, p.best)], texts[(p.b, p.best)], p.best)
            p.lines = tuple(_original(files_root, originals[(n, p.best)], p.best).splitlines() for n in (p.a, p.b))
    return result


def _original(files_root: Path, name: str, key: str) -> str:
    return (files_root / student_file_name(name) / key).read_text(errors="replace")


def runs(work: Path, a_text: str, b_text: str, key: str) -> list[tuple]:
    """The matching runs of two files: ((first, last) line of a, (first, last) line of b, tokens)."""
    a, b = work / "pair" / "a" / Path(key).name, work / "pair" / "b" / Path(key).name
    for p, t in ((a, a_text), (b, b_text)):
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(t)
    found = (_RUN.match(line.strip()) for line in _sim(["-s", "-n"], [a, b]).splitlines())
    out = [((int(m.group(2)), int(m.group(3))), (int(m.group(5)), int(m.group(6))), int(m.group(7)))
           for m in found if m and m.group(1) == str(a) and m.group(4) == str(b)]
    return sorted(out, key=lambda r: -r[2])

"""The CPU of grading a class whose files no one else wrote, attributed process by process:
revisions of the kit side by side, interleaved in one run (the order reversed every round),
several rounds, medians (cold_check.py's way).

    sudo python3 docs/grade_cost.py [--rounds N] [--students N] [-j N] [--isolation MODE]
                                    [--new-step] [--write docs/performance.md] REV [REV ...]

Each REV (a commit, a branch, HEAD) is cloned from this repository into a temporary folder with a
kit cache of its own (XDG_CACHE_HOME), filled by one grading that is not counted: the kit's side is
built, as on an instructor's machine that has graded before (the kit's cache and its build/ kept). A round writes, for each revision, a
class of --students submissions, each the solutions with every .cpp given one line of code of its
own (so no two share a verdict, an object or a hidden draw, in any round), and runs `./kit grade
CLASS -j N` on it. What is counted is the CPU (user + system) of every process the grading ran,
read with getrusage(RUSAGE_CHILDREN), divided by the number of submissions.

Attribution: as root, the kernel's process accounting (acct(2)) is switched on for the grading and
every process it started (its descendants by parent id, the sandboxed ones too) is charged to a
row by the name of its program: the compiler, the linker, bubblewrap, the answers program, the
judge, the reference's answers program, the kit's Python. The acct clock ticks at 100 Hz, so each
process's figure is rounded; the rows' sum is shown beside the getrusage total. Without root, the
totals alone. The machine's load makes every figure larger: the load average is printed beside.

--new-step adds a sixth step to every revision's clone before its warm-up: the kit's own template
(tests/fixtures/new_step/, as `./kit test newstep` writes it: the step's files, its reference and its
stub), its cases recorded (`./kit check 06 --record`) and committed, each revision with its own
template. The class then holds six steps (issue 55: an instructor's six-step course).

--write FILE replaces the part of FILE between the lines `<!-- grade_cost:ISOLATION:begin -->` and
`<!-- grade_cost:ISOLATION:end -->` (ISOLATION: --isolation's value, with -six after it for
--new-step) with the table. Bad input: a
message and exit 2.
"""

from __future__ import annotations

import argparse
import ctypes
import json
import os
import resource
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cold_check              # beside this script: its checkout of a revision

ROOT = Path(__file__).resolve().parent.parent
ACCT = struct.Struct("<BBHIIIIIIf8H16s")          # struct acct_v3, 64 bytes
MARK = "<!-- grade_cost:{}:{} -->"
NAMES: dict[str, str] = {}      # a revision as the table names it: a branch or HEAD with its commit

# A row by the program's name (the kernel keeps its first 15 characters).
ROWS = [
    ("compile (cc1plus, as)", lambda c: c in ("cc1plus", "cc1", "as")),
    ("compiler driver (c++)", lambda c: c in ("c++", "g++", "gcc", "cc", "clang++", "clang") or c.startswith(("g++-", "x86_64-linux-gn"))),
    ("link (collect2, ld)", lambda c: c in ("collect2", "ld", "ld.gold", "ld.bfd", "ld.lld", "mold")),
    ("sandbox start (bwrap, prlimit)", lambda c: c in ("bwrap", "prlimit")),
    ("answers process (student's code)", lambda c: c == "answers" or c.startswith(("answers_step", "raykit-answers"))),
    ("judge (test_stepNN)", lambda c: c.startswith("test_step")),
    ("reference process", lambda c: c.startswith("reference_an")),
    ("kit's Python", lambda c: c.startswith("python")),
    ("build tool (cmake, ninja)", lambda c: c in ("cmake", "ninja", "make", "gmake")),
]


def fail(message: str) -> None:
    print(f"grade_cost: {message}", file=sys.stderr)
    sys.exit(2)


def row_of(comm: str) -> str:
    for name, test in ROWS:
        if test(comm):
            return name
    return "other"


def comp_t(v: int) -> float:
    """A comp_t (13 bits of mantissa, 3 of base-8 exponent) in seconds at AHZ = 100."""
    return ((v & 0x1FFF) << (3 * (v >> 13))) / 100.0


class Accounting:
    """acct(2) on a file of its own for the duration of a `with`; records() the processes that ended."""

    def __init__(self, path: Path):
        self.path = path
        self.libc = ctypes.CDLL(None, use_errno=True)
        self.on = False

    def __enter__(self) -> "Accounting":
        self.path.write_bytes(b"")
        if os.geteuid() == 0:
            self.on = self.libc.acct(str(self.path).encode()) == 0
        return self

    def __exit__(self, *exc) -> None:
        if self.on:
            self.libc.acct(None)

    def records(self) -> list[dict]:
        data = self.path.read_bytes() if self.on else b""
        out = []
        for i in range(0, len(data) - ACCT.size + 1, ACCT.size):
            f = ACCT.unpack_from(data, i)
            if f[1] & 0x7F != 3:
                continue
            out.append({"pid": f[6], "ppid": f[7], "cpu": comp_t(f[10]) + comp_t(f[11]),
                        "comm": f[18].split(b"\0")[0].decode("ascii", "replace")})
        return out


def descendants(records: list[dict], root: int) -> list[dict]:
    ours = {root}
    changed = True
    while changed:
        changed = False
        for r in records:
            if r["ppid"] in ours and r["pid"] not in ours:
                ours.add(r["pid"])
                changed = True
    return [r for r in records if r["pid"] in ours]


def clone(rev: str, where: Path) -> Path:
    folder = cold_check.checkout(rev, where, fail)
    short = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=folder, capture_output=True, text=True).stdout.strip()
    NAMES[rev] = rev if short.startswith(rev) or rev.startswith(short) else f"{rev} ({short})"
    return folder


def add_new_step(kit: Path, cache: Path) -> None:
    """The revision's own step template written into its clone as step 06, its cases recorded and
    committed (the bundle's key holds what git tracks)."""
    template = kit / "tests" / "fixtures" / "new_step"
    if not template.is_dir():
        fail(f"{kit.name} has no step template (tests/fixtures/new_step/)")
    for f in sorted(template.rglob("*")):
        if f.is_file():
            target = kit / f.relative_to(template)
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(f, target)
    r = subprocess.run(["./kit", "check", "06", "--record"], cwd=kit, env=kit_env(cache),
                       capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"./kit check 06 --record in {kit} exited {r.returncode}:\n{(r.stdout + r.stderr)[-1500:]}")
    for args in (["add", "-A"], ["-c", "user.name=grade_cost", "-c", "user.email=grade_cost@raykit.invalid",
                                 "-c", "commit.gpgsign=false", "commit", "-q", "-m", "step 06 from the template"]):
        r = subprocess.run(["git", *args], cwd=kit, capture_output=True, text=True)
        if r.returncode != 0:
            fail(f"git {args[0]} in {kit}: {r.stderr.strip()}")


def kit_env(cache: Path) -> dict[str, str]:
    env = dict(os.environ, XDG_CACHE_HOME=str(cache), RAYKIT_NO_WARMUP="1", RAYKIT_SELFTEST_SECRET="ab" * 32)
    for name in ("RAYKIT_KIT_CACHE_DIR", "RAYKIT_BUNDLE_DIR", "PYTHONPYCACHEPREFIX", "RAYKIT_PYCACHE"):
        env.pop(name, None)
    return env


def write_class(kit: Path, where: Path, students: int, tag: str) -> None:
    """`students` submissions of `kit`'s solutions, each .cpp with a line of code no other file has."""
    shutil.rmtree(where, ignore_errors=True)
    for s in range(students):
        for step in sorted((kit / "solutions").iterdir()):
            if not step.is_dir():
                continue
            for f in sorted(step.glob("*.cpp")):
                target = where / f"student{s:02d}" / "steps" / step.name / f.name
                target.parent.mkdir(parents=True, exist_ok=True)
                unique = f"{tag}_{s}_{f.stem}".replace("-", "_").replace(".", "_")
                target.write_text(f.read_text() + f"\n[[maybe_unused]] static const int raykit_own_{unique} = {s};\n")


def one_run(kit: Path, cache: Path, klass: Path, jobs: int, isolation: str, log: Path) -> dict:
    env = kit_env(cache)
    out = klass.parent / "grades.csv"
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    load = os.getloadavg()[0]
    start = time.monotonic()
    with Accounting(log) as acct:
        proc = subprocess.Popen(["./kit", "grade", str(klass), "-j", str(jobs), "--isolation", isolation,
                                 "--out", str(out)], cwd=kit, env=env, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
        stdout, stderr = proc.communicate()
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if proc.returncode != 0:
        fail(f"./kit grade in {kit} exited {proc.returncode}:\n{(stdout + stderr)[-1500:]}")
    text = out.read_text()
    if "not graded" in text or "NOT graded" in text:
        fail(f"./kit grade in {kit}: a submission was not graded:\n{text[-1500:]}")
    rows: dict[str, list[float]] = {}
    others: dict[str, float] = {}
    comms: dict[str, list] = {}
    for r in descendants(acct.records(), proc.pid):
        comms.setdefault(r["comm"], [0.0, 0])
        comms[r["comm"]][0] += r["cpu"]
        comms[r["comm"]][1] += 1
        name = row_of(r["comm"])
        rows.setdefault(name, [0.0, 0])
        rows[name][0] += r["cpu"]
        rows[name][1] += 1
        if name == "other":
            others[r["comm"]] = others.get(r["comm"], 0.0) + r["cpu"]
    return {"cpu": round(cpu, 2), "wall": round(wall, 2), "load": round(load, 2), "rows": rows,
            "others": {k: round(v, 2) for k, v in sorted(others.items(), key=lambda kv: -kv[1])[:6]},
            "comms": {k: [round(v[0], 2), v[1]] for k, v in sorted(comms.items(), key=lambda kv: -kv[1][0])}}


def table(revs: list[str], runs: dict[str, list[dict]], students: int, command: str) -> str:
    names = [n for n, _ in ROWS] + ["other"]
    present = [n for n in names if any(n in r["rows"] for rs in runs.values() for r in rs)]
    head = "| per submission | " + " | ".join(f"{NAMES.get(rev, rev)}: CPU s | processes" for rev in revs) + " |"
    lines = [head, "|---|" + "---:|---:|" * len(revs)]

    def med(rs: list[dict], name: str, i: int) -> float:
        return statistics.median(r["rows"].get(name, [0.0, 0])[i] for r in rs) / students

    for n in present:
        lines.append(f"| {n} | " + " | ".join(f"{med(runs[rev], n, 0):.2f} | {med(runs[rev], n, 1):.0f}"
                                               for rev in revs) + " |")
    acct_sum = {rev: statistics.median(sum(v[0] for v in r["rows"].values()) for r in runs[rev]) / students
                for rev in revs}
    lines.append("| sum of the rows (acct) | " + " | ".join(f"{acct_sum[rev]:.2f} | " for rev in revs) + " |")
    lines.append("| **total, getrusage** | " + " | ".join(
        f"**{statistics.median(r['cpu'] for r in runs[rev]) / students:.2f}** | " for rev in revs) + " |")
    first = statistics.median(r["cpu"] for r in runs[revs[0]])
    each = "; ".join(f"{NAMES.get(rev, rev)}: " + ", ".join(f"{r['cpu'] / students:.2f}" for r in runs[rev]) +
                     f" (x{statistics.median(r['cpu'] for r in runs[rev]) / first:.2f})" for rev in revs)
    loads = [r["load"] for rs in runs.values() for r in rs]
    walls = "; ".join(f"{rev}: {statistics.median(r['wall'] for r in runs[rev]) / students:.2f} s" for rev in revs)
    return ("\n".join(lines) + f"\n\n`{command}`, {len(runs[revs[0]])} rounds interleaved, {students} unique "
            f"submissions a round, medians. CPU per submission, each run: {each}. Wall per submission, "
            f"median: {walls}. Load average {min(loads):.1f}-{max(loads):.1f}.\n")


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("revs", nargs="+", metavar="REV", help="revisions to compare (commits, branches)")
    p.add_argument("--rounds", type=int, default=3, help="rounds, each grading every revision once (3)")
    p.add_argument("--students", type=int, default=2, help="unique submissions in each class (2)")
    p.add_argument("-j", "--jobs", type=int, default=2, help="./kit grade -j (2)")
    p.add_argument("--isolation", choices=["auto", "bwrap", "user", "none"], default="auto")
    p.add_argument("--new-step", action="store_true",
                   help="a six-step course: the template's step 06 added to every revision (issue 55)")
    p.add_argument("--write", metavar="FILE", help="put the table in FILE between its grade_cost markers")
    args = p.parse_args(argv)
    if args.rounds < 1 or args.students < 1 or args.jobs < 1:
        p.error("--rounds, --students and -j must be at least 1")
    marker = f"{args.isolation}-six" if args.new_step else args.isolation
    begin, end = MARK.format(marker, "begin"), MARK.format(marker, "end")
    try:
        written = Path(args.write).read_text() if args.write else begin + end
    except OSError as e:
        fail(f"{args.write}: {e.strerror}")
    if begin not in written or end not in written:
        fail(f"{args.write} has no {begin} ... {end} lines to write between")
    command = f"./kit grade CLASS -j {args.jobs} --isolation {args.isolation}" + (
        " (six steps: the template's step 06 added)" if args.new_step else "")
    with tempfile.TemporaryDirectory(prefix="grade-cost-") as tmp:
        work = Path(tmp)
        folders = {rev: clone(rev, work) for rev in args.revs}
        caches = {rev: work / f"cache-{rev.replace('/', '_')}" for rev in args.revs}
        for rev in args.revs:
            caches[rev].mkdir()
            if args.new_step:
                add_new_step(folders[rev], caches[rev])
            # As many as are graded at once: each grading slot's own folders are filled too.
            write_class(folders[rev], work / "class", max(args.jobs, args.students), f"warm_{rev}")
            one_run(folders[rev], caches[rev], work / "class", args.jobs, args.isolation, work / "acct")
        runs: dict[str, list[dict]] = {rev: [] for rev in args.revs}
        for round_ in range(args.rounds):
            order = args.revs if round_ % 2 == 0 else list(reversed(args.revs))
            for rev in order:
                write_class(folders[rev], work / "class", args.students, f"r{round_}_{rev}")
                run = one_run(folders[rev], caches[rev], work / "class", args.jobs, args.isolation, work / "acct")
                runs[rev].append(run)
                print(json.dumps({"round": round_ + 1, "rev": rev, **run}), flush=True)
    text = table(args.revs, runs, args.students, command)
    print("\n" + text)
    if args.write:
        target = Path(args.write)
        old = target.read_text()
        head, rest = old.split(begin, 1)
        _, tail = rest.split(end, 1)
        target.write_text(f"{head}{begin}\n{text}{end}{tail}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

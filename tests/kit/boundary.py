"""Self-test of the trust boundary (sandbox/): hostile submissions from the first byte the compiler
reads, graded as an instructor grades them, with the harm checked, not argued.

- compile: a step that #includes, __has_include's or .incbin's the kit's answers does not compile,
  with its own diagnostic, and scores like the stubs: under every isolation, in ./kit grade and in
  the Gradescope flow;
- compile bombs (/dev/zero, a slow constexpr loop) end within the stated limits, leave no compiler
  behind, and the next student of the same ./kit grade -j 2 scores as alone;
- run bombs: a background thread's memory, a fork bomb, a filled scratch folder, files left in the
  shared temporary folders; root's files and sockets; a child that lingers past its case;
- output is data: escapes shown as text, CSV formulas neutralised; links and zip bombs refused;
- the kit's own state: links planted where sandbox user ids are claimed are never followed, claims
  graded code can reach do not stop two gradings, and an object compiled outside the sandbox (or
  before a system header changed) is never reused inside it;
- the Gradescope flow gives one submission one score, run after run, equal to ./kit grade's;
- load never fails correct code: the reference graded cold beside two busy loops gets the maximum;
- grader images (#53 item 3): the public PrairieLearn image's build context holds nothing of the course
  (no COPY, no solution, secret or bundle; a spoiled context is caught); a PrairieLearn job laid out as
  PrairieLearn lays it out, with the bundle prebuilt beside the kit by prebuild.py (the image's step),
  compiles only the student's files and says so, under every isolation, and hostile/read_answers reads
  nothing of the prebuilt bundle or the job's folder there; a job whose course or toolchain differs from
  the prebuilt bundle's builds its own and says why; a Gradescope job with the bundle built before it
  (setup.sh's) says it compiled the student's files only, one with none built says the kit's side too.

The heavy forms (the Gradescope flow five times; the slow compile at the default 60 s limit) run
with RAYKIT_SELFTEST_FULL=1; CI runs the small forms.
"""

from __future__ import annotations

import atexit
import csv
import json
import os
import re
import shutil
import socket
import stat
import subprocess
import sys
import tempfile
import threading
import time
import zipfile
from pathlib import Path

import pytest

from raykit import procfs
from raykit.common import BUILD, ROOT
from raykit.sandbox import COMPILE_UID_OFFSET, Limits
from raykit.sandbox_slots import RUN_PROCESSES
from raykit.status import NO_COMPILE
from . import scale
from .support import Failed, Skipped, expect, need_solutions
from .integrity import isolations, one_slip_folder, printed, processes_named, run_modes
from .fixtures import fixture_dir

pytestmark = pytest.mark.security      # conftest.py: may not skip in CI

FULL = os.environ.get("RAYKIT_SELFTEST_FULL") == "1"
WORK = BUILD / "selftest-boundary"
UID_FILE = WORK / "claimed-uid"
claimed: set[int] = set()       # the sandbox user ids this self-test's gradings took (not another run's)


def note_uid(path: Path = UID_FILE) -> None:
    try:
        uid = int(path.read_text())
    except (OSError, ValueError):
        return
    claimed.update({uid, uid + COMPILE_UID_OFFSET})


def with_uid_file(env: dict | None) -> dict:
    WORK.mkdir(parents=True, exist_ok=True)
    UID_FILE.unlink(missing_ok=True)
    return dict(env or os.environ, RAYKIT_UID_FILE=str(UID_FILE))


def check(folder: Path, numbers: list[str], mode: str, limits: str = "", slot: int = 0,
          quiet: bool = True) -> tuple[int, dict, str, float]:
    """`./kit check NUMBERS --steps FOLDER --json F --isolation MODE`, with RAYKIT_LIMITS set:
    exit status, the JSON, what it printed, seconds."""
    WORK.mkdir(parents=True, exist_ok=True)
    target = WORK / f"results-{os.getpid()}-{slot}.json"
    record_path = target.with_suffix(".record.json")
    target.unlink(missing_ok=True)
    record_path.unlink(missing_ok=True)
    env = with_uid_file(dict(os.environ, RAYKIT_LIMITS=limits) if limits else None)
    start = time.monotonic()
    r = subprocess.run([str(ROOT / "kit"), "check", *[str(int(n)) for n in numbers], "--steps", str(folder),
                        "--json", str(target), "--results", str(record_path), "--isolation", mode, "--slot", str(slot)]
                       + (["--quiet"] if quiet else []),
                       cwd=ROOT, capture_output=True, text=True, timeout=1800, env=env, errors="replace")
    took = time.monotonic() - start
    note_uid()
    if not target.is_file() or not record_path.is_file():
        raise Failed(f"./kit check --steps {folder.name} ({mode}) exited {r.returncode} without results: "
                     f"{(r.stderr or r.stdout)[-600:]}")
    data = dict(json.loads(target.read_text()), record=json.loads(record_path.read_text()))
    return r.returncode, data, r.stdout + r.stderr, took


def templated(name: str) -> Path:
    """A fixture with @ROOT@ replaced by the kit's folder, as a student would write the path."""
    src = fixture_dir("hostile") / name
    dst = WORK / "fixtures" / name
    shutil.rmtree(dst, ignore_errors=True)
    for f in src.rglob("*"):
        if f.is_file():
            out = dst / f.relative_to(src)
            out.parent.mkdir(parents=True, exist_ok=True)
            out.write_text(f.read_text().replace("@ROOT@", str(ROOT)))
    return dst


def sandbox_processes(before: float | None = None) -> list[str]:
    """Live processes of the sandbox user ids this self-test's gradings took (run or compile); with
    `before` (procfs.uptime()), only those started before it: once a grading has ended and released its
    id, another kit on the machine may claim the id and start processes of its own."""
    found = []
    for p in procfs.pids():
        fields = procfs.status(p)
        uid = fields.get("Uid", "").split()[:1]
        if uid and int(uid[0]) in claimed and not fields.get("State", "").startswith("Z"):
            start = procfs.started(p)
            if before is not None and start is not None and start > before:
                continue
            found.append(f"{p} uid {uid[0]} {fields.get('Name', '')}")
    return found


def no_leftovers(what: str) -> None:
    """None of the gradings' processes is alive after it: each killed one may take a while to end on a
    loaded machine (issue 46: three checks said 'left' at a load of 20), so they get 10 s to go; a
    process that really stayed is there after them too."""
    deadline = time.monotonic() + 10
    ended = procfs.uptime()     # the grading is over: what starts later is not its
    while True:
        time.sleep(0.3)
        left = sandbox_processes(ended) + processes_named("rk-linger")
        if not left or time.monotonic() > deadline:
            break
    expect(not left, f"{what}: processes left after grading: {left[:5]}")


# --- the compile ------------------------------------------------------------------------------

# What the compiler says of a file outside the boundary: absent (bubblewrap) or unreadable (the user isolation).
STEALERS = {"include_answers": ("No such file", "Permission denied"),
            "incbin_secrets": ("file not found", "Permission denied")}


def selftest_compile_boundary(ctx, committed_steps) -> str:
    need_solutions()
    _, stubs, _, _ = check(committed_steps, ["01"], isolations()[0][0] if isolations()[0] else "none")

    def one(mode: str) -> str:
        for name, words in STEALERS.items():
            rc, got, _, _ = check(templated(name), ["01"], mode)
            [step] = got["record"]["steps"]
            expect(step["state"] == NO_COMPILE, f"{name} ({mode}): {step['state']}, {got['score']} points: "
                                                "the kit's answers were reachable from the compile")
            expect(any(w in step["detail"] for w in words) and "unit_sphere.cpp" in step["detail"],
                   f"{name} ({mode}): the diagnostic is not the student's own: {step['detail'][-300:]!r}")
            expect(got["score"] == stubs["score"] and rc == 1,
                   f"{name} ({mode}): {got['score']} points, the stubs {stubs['score']}")
        no_leftovers(f"compile boundary ({mode})")
        return f"{', '.join(STEALERS)}: do not compile, {stubs['score']} points like the stubs"

    summary = run_modes(one)
    # ./kit grade and the Gradescope flow: the same answer-stealer scores like an empty upload.
    subs = WORK / "grade-stealers"
    shutil.rmtree(subs, ignore_errors=True)
    for name in STEALERS:
        shutil.copytree(templated(name), subs / name)
    rows = grade_class(subs)
    bad = {n: r["earned"] for n, r in rows.items() if r["earned"] not in ("0", "")}
    expect(not bad, f"./kit grade: answer-stealers earned points: {bad}")
    gs = [gradescope(templated(name))["score"] for name in STEALERS]
    expect(all(s == 0 for s in gs), f"the Gradescope flow: answer-stealers scored {gs}")
    return summary + f"; ./kit grade 0 and 0; Gradescope {gs}"


def selftest_compile_bombs(ctx) -> str:
    need_solutions()
    seconds = Limits().compile_seconds if FULL else 8.0
    limits = f"compile_seconds={seconds:g}"

    def one(mode: str) -> str:
        parts = []
        # Which limit stops a bomb first depends on the machine's load (a slow one meets the time
        # limit before the memory limit): any of them, named, is the boundary holding.
        stopped = ("ran out of", "took over", "was stopped by signal")
        for name in ("compile_bomb_zero", "compile_bomb_slow"):
            rc, got, _, took = check(fixture_dir("hostile") / name, ["01"], mode, limits)
            [step] = got["record"]["steps"]
            expect(step["state"] == NO_COMPILE and any(w in step["detail"] for w in stopped),
                   f"{name} ({mode}): {step['state']}; {step['detail'][-300:]!r}")
            expect(took < seconds + 60, f"{name} ({mode}): the grading took {took:.0f} s, the limit is {seconds:g} s")
            no_leftovers(f"{name} ({mode})")
            parts.append(f"{name} stopped ({took:.0f} s)")
        return ", ".join(parts)

    summary = run_modes(one)
    # ./kit grade -j 2: a bomb beside the solutions; the solutions score as alone.
    subs = WORK / "grade-bombs"
    shutil.rmtree(subs, ignore_errors=True)
    shutil.copytree(fixture_dir("hostile") / "compile_bomb_slow", subs / "a_bomb")
    shutil.copytree(ROOT / "solutions", subs / "b_solutions")
    rows = grade_class(subs, ["-j", "2"], limits)
    _, alone, _, _ = check(ROOT / "solutions", [s.number for s in ctx.steps], isolations()[0][0])
    expect(scale.exact(rows["b_solutions"]["earned"]) == scale.exact(alone["score"]),   # "131.30" is 131.3
           f"./kit grade -j 2: the solutions beside a compile bomb earned {rows['b_solutions']['earned']}, "
           f"alone {alone['score']}")
    no_leftovers("./kit grade -j 2 with a compile bomb")
    return summary + f"; ./kit grade -j 2: the solutions beside it {alone['score']} as alone"


# --- the run ----------------------------------------------------------------------------------

def numbers_in(text: str, pattern: str) -> list[int]:
    return [int(m) for m in re.findall(pattern, text)]


def selftest_run_bombs(ctx) -> str:
    need_solutions()
    limits = Limits()
    memory = 384

    def one(mode: str) -> str:
        _, base, _, _ = check(fixture_dir("hostile") / "always_miss", ["01"], mode)
        parts = []
        _, got, _, _ = check(fixture_dir("hostile") / "memory_hog", ["01"], mode, f"run_memory_mb={memory}")
        most = max(numbers_in(printed(got), r"memory_hog: (\d+) MiB so far") or [0])
        expect("memory_hog: a thread started" in printed(got) or "memory_hog: no thread" in printed(got),
               f"memory_hog ({mode}): did not run")
        expect(most < memory, f"memory_hog ({mode}): its thread touched {most} MiB, the limit is {memory} MiB")
        parts.append(f"memory {most} MiB < {memory}")
        _, forks, _, _ = check(fixture_dir("hostile") / "fork_bomb", ["01"], mode)
        started = max(numbers_in(printed(forks), r"fork_bomb: started (\d+)") or [-1])
        # The answers program may start no process at all (sandbox_slots.RUN_PROCESSES, itself).
        expect(started == RUN_PROCESSES - 1, f"fork_bomb ({mode}): started {started} children, the answers "
                                             f"program may start {RUN_PROCESSES - 1}")
        parts.append(f"forks {started}")
        _, fill, _, _ = check(fixture_dir("hostile") / "fill_scratch", ["01"], mode)
        text = printed(fill)
        wrote = max(numbers_in(text, r"wrote (\d+) MiB") or [-1])
        big = max(numbers_in(text, r"one file reached (\d+) MiB") or [-1])
        expect(wrote >= 0, f"fill_scratch ({mode}): did not run: {text[:200]!r}")
        expect(big <= limits.file_mb, f"fill_scratch ({mode}): one file of {big} MiB, the limit is {limits.file_mb}")
        if mode == "bwrap":
            expect(wrote <= limits.scratch_mb, f"fill_scratch (bwrap): wrote {wrote} MiB, the scratch limit is "
                                               f"{limits.scratch_mb} MiB")
        left = [str(p) for d in ("/tmp", "/var/tmp", "/dev/shm") for p in Path(d).glob("raykit-hostile-*")]
        expect(not left, f"fill_scratch ({mode}): files left in the shared temporary folders: {left}")
        parts.append(f"scratch {wrote} MiB, largest file {big} MiB, nothing left")
        for name, data in (("memory_hog", got), ("fork_bomb", forks), ("fill_scratch", fill)):
            expect(data["score"] == base["score"], f"{name} ({mode}): {data['score']} points, always_miss "
                                                   f"{base['score']}")
        no_leftovers(f"run bombs ({mode})")
        return ", ".join(parts)

    return run_modes(one)


class RootSocket:
    """A root-owned Unix socket (mode 0600) that records who connected (SO_PEERCRED uids)."""

    def __init__(self, path: str):
        self.path, self.peers = path, []
        Path(path).unlink(missing_ok=True)
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.sock.bind(path)
        os.chmod(path, 0o600)
        self.sock.listen(16)
        self.sock.settimeout(0.2)
        self.stop = False
        self.thread = threading.Thread(target=self.serve, daemon=True)
        self.thread.start()

    def serve(self) -> None:
        import struct
        while not self.stop:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                continue
            cred = conn.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, struct.calcsize("3i"))
            self.peers.append(struct.unpack("3i", cred)[1])
            conn.close()

    def close(self) -> None:
        self.stop = True
        self.thread.join()
        self.sock.close()
        Path(self.path).unlink(missing_ok=True)


def selftest_root_secrets(ctx) -> str:
    need_solutions()
    if os.geteuid() != 0:
        raise Skipped("needs root: the attack is on what root owns", need="root")
    servers = [RootSocket(p) for p in ("/run/raykit-hostile.sock", "/tmp/raykit-hostile.sock") if Path(p).parent.is_dir()]

    def one(mode: str) -> str:
        _, got, _, _ = check(fixture_dir("hostile") / "root_secrets", ["01"], mode)
        text = printed(got)
        expect("root_secrets:" in text, f"root_secrets ({mode}): did not run")
        leaks = sorted({l for l in text.splitlines() if "could" in l})
        expect(not leaks, f"root_secrets ({mode}): " + "; ".join(leaks))
        peers = [p for s in servers for p in s.peers]
        expect(not peers, f"root_secrets ({mode}): a root-only socket saw connections from uids {peers}")
        return "/etc/shadow and root's sockets denied"

    try:
        return run_modes(one)
    finally:
        for s in servers:
            s.close()


def selftest_lingering_child(ctx) -> str:
    """A child detached in every call lives no longer than its case: the process list is sampled
    while grading, each rk-lingerchild's lifetime measured."""
    need_solutions()

    def one(mode: str) -> str:
        seen: dict[str, list[float]] = {}
        done = threading.Event()

        def sample() -> None:
            while not done.is_set():
                now = time.monotonic()
                for p in processes_named("rk-lingerchild"):
                    seen.setdefault(p.split()[0], [now, now])[1] = now
                time.sleep(0.05)

        watcher = threading.Thread(target=sample, daemon=True)
        watcher.start()
        try:
            _, got, _, took = check(fixture_dir("hostile") / "lingering_child", ["01"], mode)
        finally:
            done.set()
            watcher.join()
        # Under every isolation the answers program may start no process (sandbox_slots.RUN_PROCESSES):
        # the fork is refused; were it allowed, no child may outlive its case.
        refused = "lingering_child: fork refused" in printed(got)
        expect("lingering_child: started one" in printed(got) or refused, f"lingering_child ({mode}): did not run")
        longest = max((b - a for a, b in seen.values()), default=0.0)
        expect(longest < 3.0, f"lingering_child ({mode}): a child lived {longest:.1f} s of a {took:.0f} s grading")
        no_leftovers(f"lingering_child ({mode})")
        return ("the fork refused; " if refused else "") + f"{len(seen)} children seen, the longest-lived {longest:.2f} s"

    summary = run_modes(one)
    if os.geteuid() == 0:
        watched: dict[str, list[float]] = {}
        done = threading.Event()

        def sample() -> None:
            while not done.is_set():
                now = time.monotonic()
                for p in processes_named("rk-lingerchild"):
                    watched.setdefault(p.split()[0], [now, now])[1] = now
                time.sleep(0.05)

        watcher = threading.Thread(target=sample, daemon=True)
        watcher.start()
        try:
            data = gradescope(fixture_dir("hostile") / "lingering_child")
        finally:
            done.set()
            watcher.join()
        longest = max((b - a for a, b in watched.values()), default=0.0)
        expect(longest < 3.0, f"lingering_child (Gradescope): a child lived {longest:.1f} s")
        # It compiled and ran: a never-hit answer passes the cases that expect a miss.
        expect(data.get("score", 0) > 0, f"lingering_child (Gradescope): did not run: {str(data)[:300]}")
        no_leftovers("lingering_child (Gradescope)")
        summary += f"; Gradescope flow: the longest-lived child {longest:.2f} s"
    return summary


# --- output, links, uploads -----------------------------------------------------------------

RAW_CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f]")


def selftest_output_is_data(ctx) -> str:
    need_solutions()
    modes, _ = isolations()
    mode = modes[0] if modes else "none"
    rc, got, shown, _ = check(fixture_dir("hostile") / "escapes", ["01"], mode, quiet=False)
    expect("escapes:" in printed(got), "escapes: did not run")
    expect("escapes:" in shown, "escapes: its output is not shown under the failing case")
    raw = RAW_CONTROL.findall(shown)
    expect(not raw, f"escapes: control characters reached the terminal: {sorted(set(raw))!r}")
    subs = WORK / "grade-names"
    shutil.rmtree(subs, ignore_errors=True)
    formula = '=HYPERLINK("http://example.invalid/"&B2,"dave")'
    for name in (formula, "\x1b[2Jeve", "+bob", "-carol", "@dan"):
        shutil.copytree(fixture_dir("hostile") / "always_miss", subs / name)
    csv_path = WORK / "names.csv"
    r = subprocess.run([str(ROOT / "kit"), "grade", str(subs), "--out", str(csv_path), "-j", "2"], cwd=ROOT,
                       capture_output=True, text=True, timeout=1800, errors="replace")
    expect(r.returncode == 0, f"./kit grade exited {r.returncode}: {r.stderr[-400:]}")
    cells = [row[0] for row in list(csv.reader(csv_path.open()))[1:]]
    unsafe = [c for c in cells if c[:1] in "=+-@\t\r"]
    expect(not unsafe and len(cells) == 5, f"grades.csv: cells a spreadsheet runs: {unsafe} (of {cells})")
    raw = RAW_CONTROL.findall(r.stdout + r.stderr)
    expect(not raw, f"./kit grade printed control characters: {sorted(set(raw))!r}")
    return f"escapes shown as text; {len(cells)} hostile names written as text in grades.csv"


def selftest_links_and_uploads(ctx) -> str:
    need_solutions()
    link = WORK / "linked"
    shutil.rmtree(link, ignore_errors=True)
    (link / "01_unit_sphere").mkdir(parents=True)
    (link / "01_unit_sphere" / "unit_sphere.cpp").symlink_to(ROOT / "solutions" / "01_unit_sphere" / "unit_sphere.cpp")
    r = subprocess.run([str(ROOT / "kit"), "check", "1", "--steps", str(link), "--quiet"], cwd=ROOT,
                       capture_output=True, text=True, timeout=600)
    expect(r.returncode != 0 and "link" in r.stderr, f"--steps with a linked step file: exit {r.returncode}, "
                                                      f"{r.stderr[-300:]!r}")
    # A zip of zips of empty entries: 14 x 15,000 files from about 2 MB.
    bomb = WORK / "grade-zipbomb"
    shutil.rmtree(bomb, ignore_errors=True)
    bomb.mkdir(parents=True)
    inner = WORK / "inner.zip"
    with zipfile.ZipFile(inner, "w") as z:
        for i in range(15000):
            z.writestr(f"e{i}", b"")
    with zipfile.ZipFile(bomb / "mallory.zip", "w") as z:
        for i in range(14):
            z.write(inner, f"in{i}.zip")
    shutil.copytree(link, bomb / "linda", symlinks=True)
    start = time.monotonic()
    rows = grade_class(bomb)
    took = time.monotonic() - start
    expect("more than" in rows["mallory"]["note"] and rows["mallory"]["earned"] == "",
           f"the zip bomb: {rows['mallory']}")
    expect(rows["linda"]["earned"] in ("", "0"), f"a linked step file earned {rows['linda']['earned']} in ./kit grade")
    expect(took < 120, f"./kit grade of a zip bomb took {took:.0f} s")
    return f"a linked step refused by --steps and ./kit grade; a zip bomb refused ({took:.1f} s for the class)"


# --- flows ------------------------------------------------------------------------------------

def grade_class(subs: Path, extra: list[str] = (), limits: str = "") -> dict[str, dict]:
    out = WORK / f"{subs.name}.csv"
    env = dict(os.environ, RAYKIT_LIMITS=limits) if limits else None
    r = subprocess.run([str(ROOT / "kit"), "grade", str(subs), "--out", str(out), *extra], cwd=ROOT,
                       capture_output=True, text=True, timeout=3600, env=env, errors="replace")
    for f in BUILD.glob("grade-uid-*"):
        note_uid(f)
    expect(r.returncode == 0 and out.is_file(), f"./kit grade {subs.name} exited {r.returncode}: {r.stderr[-500:]}")
    return {row["student"]: row for row in csv.DictReader(out.open())}


# The flow's /autograder stand-in: a folder of its own per self-test run (a fixed name in /tmp is
# one graded code under the user isolation could make first), removed when the run ends.
_unpacked: list[Path] = []


def gradescope(upload: Path, metadata: dict | None = None, isolation: str = "") -> dict:
    """The Gradescope flow as its documentation describes it: the zip of `./kit autograder`
    unpacked in source/ (once per self-test run; its build folder kept between uploads, as an
    image's is), the upload in submission/, `metadata` as submission_metadata.json (root's, mode
    0644, as Gradescope leaves it), run_autograder as root, results/results.json read."""
    if not _unpacked or not (_unpacked[-1] / "source" / "kit").is_file():     # made anew once per self-test run
        ag = Path(tempfile.mkdtemp(prefix="raykit-selftest-autograder-"))
        os.chmod(ag, 0o755)
        atexit.register(shutil.rmtree, ag, True)
        _unpacked.append(ag)
    ag = _unpacked[-1]
    if not (ag / "source" / "kit").is_file():
        r = subprocess.run([str(ROOT / "kit"), "autograder", str(ag / "autograder.zip")], cwd=ROOT,
                           capture_output=True, text=True, timeout=600)
        expect(r.returncode == 0, f"./kit autograder failed: {r.stderr[-400:]}")
        with zipfile.ZipFile(ag / "autograder.zip") as z:
            z.extractall(ag / "source")
        for f in (ag / "source").rglob("*"):
            if f.is_file() and (f.name in ("kit", "run_autograder", "setup.sh") or f.suffix == ".py"):
                f.chmod(0o755)
    shutil.rmtree(ag / "submission", ignore_errors=True)
    shutil.rmtree(ag / "results", ignore_errors=True)
    shutil.copytree(upload, ag / "submission")
    meta = ag / "submission_metadata.json"
    meta.unlink(missing_ok=True)
    if metadata is not None:
        meta.write_text(json.dumps(metadata))
        meta.chmod(0o644)
    ag.chmod(0o755)
    r = subprocess.run(["bash", str(ag / "source" / "run_autograder")], cwd=ag,
                       env=with_uid_file(dict(os.environ, RAYKIT_AUTOGRADER_ROOT=str(ag),
                                              RAYKIT_AUTOGRADER_ISOLATION=isolation)), capture_output=True,
                       text=True, timeout=3600)
    note_uid()
    try:
        return json.loads((ag / "results" / "results.json").read_text())
    except (OSError, ValueError) as e:
        raise Failed(f"the Gradescope flow wrote no results.json ({e}): {r.stdout[-300:]}{r.stderr[-300:]}")


def selftest_gradescope_repeatable(ctx) -> str:
    need_solutions()
    if os.geteuid() != 0:
        raise Skipped("Gradescope runs the autograder as root", need="root")
    runs = 5 if FULL else 2
    folder = one_slip_folder()
    scores = [gradescope(folder)["score"] for _ in range(runs)]
    no_leftovers("the Gradescope flow")
    subs = WORK / "grade-one-slip"
    shutil.rmtree(subs, ignore_errors=True)
    shutil.copytree(folder, subs / "dave")
    graded = float(grade_class(subs)["dave"]["earned"])
    expect(len(set(scores)) == 1 and scores[0] == graded,
           f"the same submission scored {scores} in {runs} Gradescope runs, {graded:g} in ./kit grade")
    return f"{runs} runs: {scores}, ./kit grade {graded:g}" + ("" if FULL else " (5 runs with RAYKIT_SELFTEST_FULL=1)")


def hidden_inputs(record: dict) -> list[str]:
    """The inputs of the failed hidden draws a record names ("draw 3 of 24: ray ...")."""
    found = []
    for s in record["steps"]:
        for c in s["cases"]:
            if c["tier"] == "hidden":
                for m in c["messages"]:
                    found += [x.split("\n")[0][:60] for x in re.findall(r"draw \d+ of \d+: ([^\n]+)", m)]
    return found


def selftest_gradescope_hidden_stay_hidden(ctx) -> str:
    """Two submissions in a row on Gradescope, the second handed the first's results in
    submission_metadata.json as Gradescope does, by a submission that reads every file it can
    name and prints it (tests/fixtures/hostile/replay_results): no results.json carries a hidden
    input, the reference's answer or the seed; the code reads neither the metadata nor the
    secret; each submission id draws its own inputs and a re-grade of one id (./kit check
    --identity gradescope:ID, the kit's secret is the zip's) reproduces its score."""
    need_solutions()
    if os.geteuid() != 0:
        raise Skipped("Gradescope runs the autograder as root", need="root")
    upload = fixture_dir("hostile") / "replay_results"
    base = {"created_at": "2026-09-01T10:00:00+00:00",
            "assignment": {"due_date": "2099-01-01T00:00:00+00:00", "title": "raykit"},
            "users": [{"email": "eve@example.edu", "name": "Eve"}]}
    modes, _ = isolations()
    expect("user" in modes, "the user isolation (Gradescope's, in its container) cannot be tried here")
    done = []
    for mode in modes:
        done.append(f"{mode}: " + gradescope_two_submissions(upload, base, mode))
    return "; ".join(done)


def gradescope_two_submissions(upload: Path, base: dict, mode: str) -> str:
    first = gradescope(upload, dict(base, id=9001, previous_submissions=[]), mode)
    second = gradescope(upload, dict(base, id=9002, previous_submissions=[
        {"submission_time": "2026-09-01T10:00:00+00:00", "score": first["score"], "results": first}]), mode)
    # What each submission drew, from the kit's own record of the same grading here.
    records = {}
    for sid in (9001, 9002):
        target = WORK / f"replay-{sid}.record.json"
        target.unlink(missing_ok=True)
        r = subprocess.run([str(ROOT / "kit"), "check", "1", "--steps", str(upload), "--quiet", "--results",
                            str(target), "--identity", f"gradescope:{sid}", "--isolation", mode], cwd=ROOT,
                           capture_output=True, text=True, timeout=1200, env=with_uid_file(None))
        note_uid()
        expect(target.is_file(), f"./kit check --identity gradescope:{sid}: no record ({r.stderr[-300:]})")
        records[sid] = json.loads(target.read_text())
    inputs = {sid: hidden_inputs(rec) for sid, rec in records.items()}
    expect(all(inputs.values()), f"the always-miss answers failed no hidden draw, so nothing is checked: {inputs}")
    seeds = {sid: {s["seed"] for s in rec["steps"]} for sid, rec in records.items()}
    expect(seeds[9001] != seeds[9002] and set(inputs[9001]) != set(inputs[9002]),
           f"two submissions of the same bytes drew the same hidden inputs (seeds {seeds})")
    for name, data in (("first", first), ("second", second)):
        text = json.dumps(data)
        leaked = [x for sid in inputs for x in inputs[sid] if x in text]
        expect(not leaked, f"{mode}: the {name} results.json carries hidden inputs: {leaked[:3]}")
        expect(not any(seed in text for sid in seeds for seed in seeds[sid]),
               f"{mode}: the {name} results.json names a seed")
        # What the platform keeps is this run's folder (other runs' folders in /tmp are no part of
        # this grading's platform, and other worktrees of a shared machine leave some).
        ours = [line for line in text.split("\\n") if "replay:" in line
                and (str(_unpacked[-1]) + "/" in line or "/autograder/" in line or "secret.key" in line)]
        if ours:
            raise Failed(f"{mode}: the graded code read what the platform keeps: {ours[0][:300]}")
        expect("steps" not in data.get("extra_data", {}), f"{mode}: the {name} results.json holds the kit's record")
    expect(first["score"] == records[9001]["score"] and second["score"] == records[9002]["score"],
           f"{mode}: scores {first['score']}, {second['score']} on Gradescope; re-graded here with the same ids "
           f"{records[9001]['score']}, {records[9002]['score']}; the first said: {first.get('output', '')[-600:]}")
    meta = stat.S_IMODE(os.stat(_unpacked[-1] / "submission_metadata.json").st_mode)
    expect(meta == 0o644, f"{mode}: submission_metadata.json left with mode {meta:o}, not put back to 644")
    return (f"{len(inputs[9001])} + {len(inputs[9002])} failed hidden draws in 2 submissions, none in either "
            f"results.json, metadata and secret unread, scores {first['score']} and {second['score']} as re-graded")


def selftest_sandbox_failure(ctx) -> str:
    """A sandbox that cannot start (RAYKIT_BREAK_SANDBOX gives bubblewrap a path that does not
    exist, at the compile or at the run) is the grader's error: the step is not graded, and no case
    reads as the student's timeout, crash or compile error."""
    need_solutions()
    from raykit.sandbox import bwrap_works
    if not bwrap_works():
        raise Skipped("bubblewrap cannot run here", need="bwrap")
    parts = []
    WORK.mkdir(parents=True, exist_ok=True)     # run alone, no earlier self-test has made it
    for where in ("compile", "run"):
        slot = 8
        shutil.rmtree(BUILD / f"submission-{slot}", ignore_errors=True)
        env = dict(os.environ, RAYKIT_BREAK_SANDBOX=where, RAYKIT_NO_OBJCACHE="1")
        target = WORK / "broken.json"
        target.unlink(missing_ok=True)
        subprocess.run([str(ROOT / "kit"), "check", "1", "--steps", str(ROOT / "solutions"), "--results", str(target),
                        "--isolation", "bwrap", "--slot", str(slot), "--quiet"], cwd=ROOT, capture_output=True,
                       timeout=900, env=env)
        shutil.rmtree(BUILD / f"submission-{slot}", ignore_errors=True)
        shutil.rmtree(BUILD / f"submission-{slot}-src", ignore_errors=True)
        expect(target.is_file(), f"a sandbox that cannot start at the {where}: no results")
        [step] = json.loads(target.read_text())["steps"]
        statuses = {c["status"] for c in step["cases"]}
        expect(step["state"] == "not_graded" and statuses == {"grader_error"} and "grader" in step["detail"]
               and step.get("not_graded"),
               f"a sandbox that cannot start at the {where}: {step['state']}, {statuses}, {step['detail'][:200]!r}")
        parts.append(f"at the {where}: not graded, the grader's fault")
    return "; ".join(parts)


def selftest_load(ctx) -> str:
    """The reference, its build folder from nothing, graded beside two busy loops: the maximum."""
    need_solutions()
    modes, _ = isolations()
    mode = modes[0] if modes else "none"
    slot = 9
    shutil.rmtree(BUILD / f"submission-{slot}", ignore_errors=True)
    busy = [subprocess.Popen(["python3", "-c", "while True: pass"]) for _ in range(2)]
    try:
        load = os.getloadavg()[0]
        _, got, _, took = check(ROOT / "solutions", [s.number for s in ctx.steps], mode, slot=slot)
        load = max(load, os.getloadavg()[0])
    finally:
        for p in busy:
            p.kill()
            p.wait()
        shutil.rmtree(BUILD / f"submission-{slot}", ignore_errors=True)
        shutil.rmtree(BUILD / f"submission-{slot}-src", ignore_errors=True)
    # Full marks on the course as set: each step's maximum, and any extra credit on top (scale.py).
    bad = [w for w in (scale.short_of_full(s) for s in got["record"]["steps"]) if w]
    full = scale.rounded(scale.full_total(got["record"]))
    expect(scale.exact(got["score"]) == full and not bad,
           f"the reference under load ({mode}): {got['score']} of {got['extra_data']['max_score']}, full marks "
           f"{scale.shown(full)}: {'; '.join(bad)}")
    return f"{got['score']} of {got['extra_data']['max_score']} cold beside two busy loops ({mode}, {took:.0f} s, load {load:.1f})"


CLAIM = """import os, sys, time
from raykit import sandbox
try:
    print(sandbox.claim_uid(int(sys.argv[2])), flush=True)
except RuntimeError as e:
    print("refused:", e, flush=True)
    sys.exit(0)
time.sleep(float(sys.argv[1]))
"""


def selftest_uid_claims(ctx) -> str:
    """Two gradings on one kernel in two root file systems (a chroot has /run of its own, so two
    lock folders): given a range each, as tools/portability/run gives its chroots, or both on the
    default range, they claim different sandbox user ids even while neither runs any process of its
    id (after each case one ends every process of its id, which must never be the other's); an id
    that has a live process is passed over. A RAYKIT_FIRST_UID that is not a range is refused."""
    if os.geteuid() != 0:
        raise Skipped("sandbox user ids are claimed only when grading as root", need="root")
    from raykit.sandbox import FIRST_UID_ENV, UID_RANGE, claim_range
    env = dict(os.environ, PYTHONPATH=str(ROOT / "tools"))
    env.pop(FIRST_UID_ENV, None)
    slot = str(CLAIM_SLOTS[0])
    folders = [Path(tempfile.mkdtemp(prefix="raykit-locks-")) for _ in range(2)]

    def claim(folder: Path, seconds: str = "0", **extra: str) -> subprocess.Popen:
        return subprocess.Popen(["python3", "-c", CLAIM, seconds, slot], stdout=subprocess.PIPE, text=True,
                                env=dict(env, RAYKIT_LOCK_DIR=str(folder), **extra))

    try:
        first, held = claim_range()         # what tools/portability/run holds for one chroot
        try:
            a_proc = claim(folders[0], "5", **{FIRST_UID_ENV: str(first)})
            try:
                a = int(a_proc.stdout.readline())
                b_proc = claim(folders[1])
                b = int(b_proc.communicate(timeout=60)[0].strip() or -1)
            finally:
                a_proc.kill()
                a_proc.wait()
        finally:
            os.close(held)
        expect(a >= first and 0 < b < first and a != b,
               f"two roots given their own ranges claimed {a} (range from {first}) and {b}")
        ranged = (a, b)
        # No ranges and no process of the id (between two cases): the claim's abstract name, which
        # every root on the kernel sees, keeps the second root off the first's id (issue 52).
        a_proc = claim(folders[0], "5")
        try:
            a = int(a_proc.stdout.readline())
            b = int(claim(folders[1]).communicate(timeout=120)[0].strip() or -1)
        finally:
            a_proc.kill()
            a_proc.wait()
        expect(a != b and b > 0, f"two roots on the default range, no process of either id, both claimed {a}")
        bare = (a, b)
        # No ranges: the first root's grading runs a case as its id, the second passes it over.
        a_proc = claim(folders[0], "5")
        runner = None
        try:
            a = int(a_proc.stdout.readline())
            runner = subprocess.Popen(["sleep", "30"], user=a, group=a, extra_groups=[])
            b = int(claim(folders[1]).communicate(timeout=60)[0].strip() or -1)
        finally:
            if runner is not None:
                runner.kill()
                runner.wait()
            a_proc.kill()
            a_proc.wait()
        expect(a != b and b > 0, f"a second root claimed {b}, whose processes the first root's grading runs")
        again = int(claim(folders[0]).communicate(timeout=60)[0].strip() or -1)
        expect(again == a, f"id {a} not free again once its grading ended (got {again})")
        refused = []
        for bad in ("64001", "abc", "0", str(first + UID_RANGE // 2)):
            said = claim(folders[0], **{FIRST_UID_ENV: bad}).communicate(timeout=60)[0]
            expect(said.startswith("refused:"), f"{FIRST_UID_ENV}={bad} was taken: claimed {said.strip()}")
            refused.append(bad)
    finally:
        for f in folders:
            shutil.rmtree(f, ignore_errors=True)
    return (f"with ranges: {ranged[0]} and {ranged[1]}; without, by name alone: {bare[0]} and {bare[1]}; "
            f"without: {a} (a live process) passed over for {b}; "
            f"{FIRST_UID_ENV} {', '.join(refused)} refused")


# --- the claims on sandbox user ids, and the compiled objects kept ----------------------------
# Graded code under the user isolation runs as a sandbox user id in the machine's own /run/lock,
# /tmp and network namespace: whatever the kit's claims are made of must be out of its reach. The
# traps are laid only for the ids of slots no other self-test or ./kit grade uses, so a grading of
# another checkout on this machine never meets them.

CLAIM_SLOTS = (40, 41)
OLD_LOCKS = Path("/run/lock")       # where the claims were: world-writable (sticky)
NEW_LOCKS = Path("/run/raykit")     # where they are: root's alone
SQUATTER_SLOT = 42                  # its first id: the squatter's, graded code of another grading


def slot_uids(slot: int) -> list[int]:
    from raykit.sandbox import UID_CLAIMS, first_uid
    return [first_uid() + slot % 64 + 64 * k for k in range(UID_CLAIMS)]


def lock_names(slot: int) -> list[str]:
    return [f"raykit-sandbox-{u}.lock" for u in slot_uids(slot)]


def as_sandbox_user(script: str, *args: str) -> subprocess.Popen:
    """`python3 -c SCRIPT ARGS` as a sandbox user id, no groups: what graded code is."""
    uid = slot_uids(SQUATTER_SLOT)[0]
    return subprocess.Popen(["python3", "-c", script, *args], user=uid, group=uid, extra_groups=[],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, cwd="/")


PLANT = """import os, sys
canary, folder = sys.argv[1], sys.argv[2]
made = 0
for name in sys.argv[3:]:
    try:
        os.symlink(canary, os.path.join(folder, name))
        made += 1
    except OSError as e:
        print("plant:", name, e)
print("planted", made, flush=True)
"""


def remove_entries(folder: Path, names: list[str]) -> None:
    for name in names:
        try:
            os.unlink(folder / name)        # a link itself, never what it names
        except FileNotFoundError:
            pass
        except OSError:
            pass


def selftest_lock_links(ctx) -> str:
    """Links planted where the kit claims its sandbox user ids, to a file of root's (course.json
    stands for it): graded code makes them in /run/lock as a sandbox user id; in the kit's own folder
    only root could. A grading that claims those ids leaves the file as it was, and grades."""
    need_solutions()
    if os.geteuid() != 0:
        raise Skipped("sandbox user ids are claimed only when grading as root", need="root")
    modes, _ = isolations()
    slot = CLAIM_SLOTS[0]
    names = lock_names(slot)
    WORK.mkdir(parents=True, exist_ok=True)
    canary = WORK / "canary-course.json"
    body = b'{"title": "a canary in place of course.json: a grading must never write here"}\n'
    canary.write_bytes(body)
    os.chmod(canary, 0o644)
    parts = []
    try:
        remove_entries(OLD_LOCKS, names)            # this self-test's own, from an earlier run
        planter = as_sandbox_user(PLANT, str(canary), str(OLD_LOCKS), *names)
        out, _ = planter.communicate(timeout=60)
        expect(f"planted {len(names)}" in out, f"graded code could not plant its links in {OLD_LOCKS}: {out[-300:]}")
        parts.append(f"{len(names)} links in {OLD_LOCKS} by uid {slot_uids(SQUATTER_SLOT)[0]}")
        NEW_LOCKS.mkdir(mode=0o700, exist_ok=True)
        remove_entries(NEW_LOCKS, names)
        for name in names:                          # as root: the only one who can write there
            os.symlink(canary, NEW_LOCKS / name)
        parts.append(f"{len(names)} in {NEW_LOCKS} by root")
        rc, got, shown, took = check(fixture_dir("hostile") / "always_miss", ["01"], modes[0] if modes else "user", slot=slot)
        after = canary.read_bytes() if canary.is_file() and not canary.is_symlink() else b"(gone)"
        expect(after == body, f"a grading followed a planted link and wrote the canary: {after[:80]!r}")
        [step] = got["record"]["steps"]
        expect(step["state"] not in ("broken", "not_graded", NO_COMPILE) and rc == 1,
               f"the grading beside the links: {step['state']}, exit {rc}: {step['detail'][-200:]!r}")
        claimed_here = [u for u in slot_uids(slot) if u in claimed]
        expect(claimed_here, f"the grading did not claim an id of slot {slot} (claimed: {sorted(claimed)})")
        kept = NEW_LOCKS / f"raykit-sandbox-{claimed_here[0]}.lock"
        st = os.lstat(kept)
        expect(stat_regular_root(st),
               f"{kept}: not a regular file of root's, mode 0600: {oct(st.st_mode)} uid {st.st_uid}")
        return (f"{', '.join(parts)}: the canary unchanged, step 01 graded ({got['score']} points, "
                f"id {claimed_here[0]}, {took:.0f} s)")
    finally:
        remove_entries(OLD_LOCKS, names)
        remove_entries(NEW_LOCKS, [n for n in names if (NEW_LOCKS / n).is_symlink()])


def stat_regular_root(st: os.stat_result) -> bool:
    import stat as st_
    return st_.S_ISREG(st.st_mode) and st.st_uid == 0 and st_.S_IMODE(st.st_mode) == 0o600


SQUAT = """import fcntl, os, socket, sys, time
held, names, locks, denied = [], 0, 0, 0
for uid in sys.argv[1:]:
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        s.bind("\\0raykit-sandbox-" + uid)
        held.append(s)
        names += 1
    except OSError:
        s.close()
    for folder in ("/run/lock", "/run/raykit"):
        try:
            fd = os.open(os.path.join(folder, "raykit-sandbox-%s.lock" % uid), os.O_RDONLY | os.O_CREAT, 0o644)
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            held.append(fd)
            locks += 1
        except OSError:
            denied += 1
print("squatter: %d names, %d locks held, %d denied" % (names, locks, denied), flush=True)
time.sleep(600)
"""


def selftest_claim_squatters(ctx) -> str:
    """Graded code under the user isolation shares the machine's network namespace and /run/lock:
    a process of a sandbox user id takes every claim it can reach, on every id two other gradings
    would claim (what a submission's code can do while the next one is graded in ./kit grade -j 2).
    Both gradings still claim an id each, and grade."""
    need_solutions()
    if os.geteuid() != 0:
        raise Skipped("sandbox user ids are claimed only when grading as root", need="root")
    modes, _ = isolations()
    mode = modes[0] if modes else "user"
    uids = [str(u) for slot in CLAIM_SLOTS for u in slot_uids(slot)]
    names = [n for slot in CLAIM_SLOTS for n in lock_names(slot)]
    remove_entries(OLD_LOCKS, names)
    squatter = as_sandbox_user(SQUAT, *uids)
    try:
        said = squatter.stdout.readline().strip()
        expect(said.startswith("squatter:"), f"the squatter did not start: {said!r}")
        procs = []
        for slot in CLAIM_SLOTS:
            target = WORK / f"squatted-{slot}.json"
            target.unlink(missing_ok=True)
            uid_file = WORK / f"squatted-uid-{slot}"
            uid_file.unlink(missing_ok=True)
            procs.append((slot, target, uid_file, subprocess.Popen(
                [str(ROOT / "kit"), "check", "1", "--steps", str(fixture_dir("hostile") / "always_miss"), "--results", str(target),
                 "--isolation", mode, "--slot", str(slot), "--quiet"], cwd=ROOT, stdout=subprocess.PIPE,
                stderr=subprocess.STDOUT, text=True, errors="replace",
                env=dict(os.environ, RAYKIT_UID_FILE=str(uid_file)))))
        got, ids = {}, {}
        for slot, target, uid_file, proc in procs:
            out, _ = proc.communicate(timeout=1800)
            note_uid(uid_file)
            expect("every sandbox user id is in use" not in out and target.is_file(),
                   f"slot {slot} beside the squatter: exit {proc.returncode}, no results: {out[-400:]}")
            [step] = json.loads(target.read_text())["steps"]
            expect(step["state"] not in ("broken", "not_graded", NO_COMPILE),
                   f"slot {slot}: {step['state']} {step['detail'][-200:]!r}")
            got[slot] = step["earned"]
            ids[slot] = int(uid_file.read_text())
        expect(len(set(ids.values())) == 2, f"two gradings in parallel claimed the same id: {ids}")
        expect(len(set(got.values())) == 1, f"the same submission scored differently in parallel: {got}")
        expect(squatter.poll() is None, "the squatter ended before the gradings did: it proved nothing")
        return (f"{said}; two gradings in parallel claimed ids {sorted(ids.values())} and scored "
                f"{got[CLAIM_SLOTS[0]]} each")
    finally:
        squatter.kill()
        squatter.wait()
        remove_entries(OLD_LOCKS, names)


def selftest_cache_isolation(ctx) -> str:
    """A compile's object is reused only where the same compile would give it: a step that
    #includes the answers compiles with --isolation none (it may read them there), and the same
    folder then graded inside each sandbox still does not compile. And a compile is not reused once
    a system header it read has changed (as when GLM is upgraded)."""
    need_solutions()
    modes, skipped = isolations()
    if not modes:
        raise Skipped("; ".join(skipped), need="bwrap root")
    slot = CLAIM_SLOTS[0]
    folder = templated("include_answers")
    _, loose, _, _ = check(folder, ["01"], "none", slot=slot)
    [step] = loose["record"]["steps"]
    expect(step["state"] != NO_COMPILE, f"include_answers did not compile even with --isolation none: it proves "
                                        f"nothing: {step['detail'][-200:]!r}")
    parts = [f"none: {loose['score']} points (it read the answers)"]
    for mode in modes:
        rc, got, _, _ = check(folder, ["01"], mode, slot=slot)
        [step] = got["record"]["steps"]
        expect(step["state"] == NO_COMPILE and got["score"] == 0 and rc == 1,
               f"include_answers ({mode}) after a compile with --isolation none: {step['state']}, "
               f"{got['score']} points, reported as {step['isolation'][:60]!r}")
        parts.append(f"{mode}: does not compile, 0 points")
    return "; ".join(parts)


def selftest_stale_header(ctx) -> str:
    """The build layer's object cache (objcache.ObjectCache, handed to the boundary's compile): a
    header from outside the kit (a folder given with -isystem, as GLM's is), which only the compile's
    dependency file names (written with -MP, as CMake's Ninja rules do not, so the kit's one reader,
    compilers.dependencies, must skip its empty rules), changed with its size kept: the next compile
    of the same file is not served from the cache; nor is one after the compiler changed."""
    from raykit.compilers import dependencies
    mp = "o.o: s.cpp /a\\ b/x.hpp \\\n /sys/h$$.hpp\n\n/a\\ b/x.hpp:\n\n/sys/h$$.hpp:\n"
    expect(dependencies(mp) == ["s.cpp", "/a b/x.hpp", "/sys/h$.hpp"],
           f"an -MP dependency file read as {dependencies(mp)}")
    return stale_system_header()


def stale_system_header() -> str:
    """A header from outside the kit changed with its size kept: the next compile of the same file
    is not served from the cache; a changed compiler is not either."""
    from raykit.objcache import ObjectCache
    from raykit.sandbox import Isolation
    work = WORK / "stale-header"
    shutil.rmtree(work, ignore_errors=True)
    (work / "sys").mkdir(parents=True)
    (work / "step").mkdir()
    header = work / "sys" / "fakeglm.hpp"
    src = work / "step" / "use.cpp"
    src.write_text("#include <fakeglm.hpp>\nstatic_assert(FAKEGLM_VERSION == 1, \"the header changed\");\n"
                   "int use() { return FAKEGLM_VERSION; }\n")
    # The compiler through a script that counts its runs: the cache must still serve an unchanged compile.
    runs = work / "runs"
    compiler = work / "c++"
    compiler.write_text(f"#!/bin/sh\necho run >> {runs}\nexec {shutil.which('c++') or 'c++'} \"$@\"\n")
    compiler.chmod(0o755)
    argv = [str(compiler), "-isystem", str(work / "sys"), "-std=c++17", "-MD", "-MP", "-MT", "use.o", "-MF",
            str(work / "use.o.d"), "-o", str(work / "use.o"), "-c", str(src)]
    iso = Isolation("none", "")
    saved = os.environ.pop("RAYKIT_NO_OBJCACHE", None)
    try:
        header.write_text("#define FAKEGLM_VERSION 1\n")
        status, text = iso.tool("compile", argv, work, ObjectCache)
        expect(status == 0, f"the header's first version did not compile: {text[-300:]}")
        status, _ = iso.tool("compile", argv, work, ObjectCache)
        expect(status == 0, "the same compile again failed")
        expect(runs.read_text().count("run") == 1, "the same compile with nothing changed was not served "
                                                   "from the cache: the check below would prove nothing")
        header.write_text("#define FAKEGLM_VERSION 2\n")        # the same size, a new time
        os.utime(header, ns=(time.time_ns() + 10**9, time.time_ns() + 10**9))
        status, text = iso.tool("compile", argv, work, ObjectCache)
        expect(status != 0 and "the header changed" in text,
               "a compile was served from the cache after a system header it read changed "
               f"(status {status})")
        # Back to a header the file compiles with: compiled again, and that entry then serves.
        header.write_text("#define FAKEGLM_VERSION 1\n")
        os.utime(header, ns=(time.time_ns() + 2 * 10**9, time.time_ns() + 2 * 10**9))
        before = runs.read_text().count("run")
        for _ in range(2):
            status, text = iso.tool("compile", argv, work, ObjectCache)
            expect(status == 0, f"the header's first version again did not compile: {text[-300:]}")
        expect(runs.read_text().count("run") == before + 1,
               "after a header changed, the entry made anew does not serve the next compile")
        # Another compiler behind the same name (an upgrade): compiled again.
        compiler.write_text(compiler.read_text() + "# upgraded\n")
        status, _ = iso.tool("compile", argv, work, ObjectCache)
        expect(status == 0 and runs.read_text().count("run") == before + 2,
               "a compile was served from the cache after the compiler changed")
    finally:
        if saved is not None:
            os.environ["RAYKIT_NO_OBJCACHE"] = saved
        shutil.rmtree(work, ignore_errors=True)
    return ("-MP dependency file read; an unchanged compile served from the cache, a changed system header "
            "that only the dependency file names compiled again (and its entry made anew), a changed compiler too")


PUBLIC_CONTEXT = {"Dockerfile", "README.md", "build.sh"}     # graders/raykit/: the public image's build context


def context_problems(context: Path, kit: Path) -> list[str]:
    """What in the public image's build context (`context`, graders/raykit/) is not public: a file
    other than PUBLIC_CONTEXT, a COPY or ADD in the Dockerfile (the image takes nothing from the
    course: the toolchain alone), a file holding the secret, a solution's text or a bundle's file
    (the private copy of the kit `kit`, serverFilesCourse/raykit/, gives them)."""
    found = [f"{p.relative_to(context)}: not among {sorted(PUBLIC_CONTEXT)}"
             for p in sorted(context.rglob("*")) if p.relative_to(context).as_posix() not in PUBLIC_CONTEXT]
    docker = (context / "Dockerfile").read_text() if (context / "Dockerfile").is_file() else ""
    found += [f"Dockerfile: {line.strip()}" for line in re.sub(r"\\\n", " ", docker).splitlines()
              if re.match(r"\s*(COPY|ADD)\b", line, re.I)]
    secrets = [(kit / "tests" / "hidden" / "secret.key").read_bytes().strip()]
    secrets += [f.read_bytes().strip() for f in sorted((kit / "solutions").rglob("*.cpp"))]
    for p in sorted(context.rglob("*")):
        if p.is_file():
            data = p.read_bytes()
            if data.startswith(b"\x7fELF") or b"raykit-bundle.json" in data:
                found.append(f"{p.relative_to(context)}: a compiled program or a bundle's recipe")
            found += [f"{p.relative_to(context)}: holds the secret or a solution" for x in secrets
                      if x and x in data][:1]
    return found


def pl_job(pristine: Path, grade: Path, step, files: dict[str, str], mode: str, edit=None) -> tuple[dict, float]:
    """A PrairieLearn job as PrairieLearn lays it out (/grade: serverFilesCourse/ and its copy shared/,
    tests/ of the question, student/, data/data.json) at `grade`, made afresh from `pristine` (the prebuilt bundle
    names its own folder's files, so it is always at the same place), `edit(grade)` applied, then the
    question's entry point run as the image runs it, with an empty home (a job's cache starts empty):
    results.json and the CPU time of the job (its processes, waited for)."""
    import resource
    shutil.rmtree(grade, ignore_errors=True)
    shutil.copytree(pristine, grade, symlinks=True)
    shutil.copytree(grade / "questions" / step.folder / "tests", grade / "tests")
    shutil.rmtree(grade / "questions")
    # PrairieLearn copies serverFilesCourse/ twice: also to /grade/shared (externalGraderCommon.ts).
    shutil.copytree(grade / "serverFilesCourse", grade / "shared", symlinks=True)
    (grade / "student").mkdir()
    (grade / "data").mkdir()
    (grade / "data" / "data.json").write_text(json.dumps({"variant_seed": 53}))
    for name, text in files.items():
        (grade / "student" / name).write_text(text)
    # The modes a git checkout and PrairieLearn's copy leave (git keeps none of a folder's, and only
    # a file's executable bit): whatever the kit or prebuild.py closed on this machine is open there.
    for path in [grade, *grade.rglob("*")]:
        if not path.is_symlink():
            path.chmod(0o755 if path.is_dir() or path.stat().st_mode & 0o100 else 0o644)
    if edit is not None:
        edit(grade)
    home = Path(tempfile.mkdtemp(prefix="raykit-selftest-pl-home-"))
    env = {k: v for k, v in os.environ.items() if k not in ("XDG_CACHE_HOME", "RAYKIT_BUNDLE_DIR", "RAYKIT_PREBUILT_BUNDLE")}
    env.update(HOME=str(home), RAYKIT_AUTOGRADER_ISOLATION=mode)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        r = subprocess.run([sys.executable, str(grade / "tests" / "grade.py")], capture_output=True, text=True,
                           env=with_uid_file(env), timeout=1800)
    finally:
        shutil.rmtree(home, ignore_errors=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    note_uid()
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    expect(r.returncode == 0, f"the PrairieLearn job ({step.number}, {mode}) exited {r.returncode}: {r.stderr[-800:]}")
    try:
        return json.loads((grade / "results" / "results.json").read_text()), cpu
    except (OSError, ValueError) as e:
        raise Failed(f"the PrairieLearn job ({step.number}, {mode}) wrote no results.json ({e}): {r.stderr[-800:]}")


def selftest_grader_images(ctx) -> str:
    need_solutions()
    from raykit.bundle import BUILT_HERE, PREBUILT_NOTE, STUDENT_ONLY
    modes, skipped = isolations()
    expect(bool(modes), "no isolation to grade under here: " + "; ".join(skipped))
    # Out of the kit (whose root a grading under the user isolation closes to other users for good,
    # which would hide the job from graded code whatever grade.py does, and the control below would
    # prove nothing): a folder of its own per run, open as a job's parents are.
    work = Path(tempfile.mkdtemp(prefix="raykit-selftest-images-"))
    os.chmod(work, 0o755)
    atexit.register(shutil.rmtree, work, True)
    out = work / "out"
    r = subprocess.run([str(ROOT / "kit"), "prairielearn", str(out), "--image", "raykit-selftest/raykit-grader"],
                       cwd=ROOT, capture_output=True, text=True, timeout=600)
    expect(r.returncode == 0, f"./kit prairielearn failed: {r.stdout[-600:]}{r.stderr[-600:]}")
    kit_copy = out / "serverFilesCourse" / "raykit"
    # The public image: its build context holds the toolchain's recipe alone, and the check sees a leak.
    context = out / "graders" / "raykit"
    problems = context_problems(context, kit_copy)
    expect(not problems, f"the public image's build context holds what is not public: {problems}")
    spoiled = work / "spoiled"
    shutil.copytree(context, spoiled)
    with open(spoiled / "Dockerfile", "a") as f:
        f.write("COPY serverFilesCourse/raykit /raykit\n")
    shutil.copyfile(kit_copy / "tests" / "hidden" / "secret.key", spoiled / "key")
    caught = context_problems(spoiled, kit_copy)
    expect(len(caught) >= 3, f"the context check missed a COPY, a stray file or the secret: {caught}")
    build_sh = (context / "build.sh").read_text()
    expect(re.search(r"docker build [^\n]* graders/raykit\s*$", build_sh, re.M)
           and "/grade/serverFilesCourse" in build_sh and "prebuild.py" in build_sh,
           f"build.sh does not build the image from graders/raykit alone and then prebuild.py in it: {build_sh}")
    infos = [json.loads(p.read_text()) for p in sorted(out.glob("questions/raykit/*/info.json"))]
    expect(all("raykit-bundle/" in i["externalGradingOptions"]["serverFilesCourse"] for i in infos)
           and (out / "serverFilesCourse" / "raykit-bundle").is_dir(),
           "info.json does not bring serverFilesCourse/raykit-bundle/ into the job, or the folder is not written")
    # The image's step: prebuild.py in the job's own layout, then a pristine job folder to copy.
    pristine, grade = work / "pristine", work / "grade"
    grade.mkdir(parents=True)
    shutil.copytree(out / "serverFilesCourse", grade / "serverFilesCourse", symlinks=True)
    shutil.copytree(out / "questions" / "raykit", grade / "questions")
    b = subprocess.run([sys.executable, str(grade / "serverFilesCourse/raykit/tools/prairielearn/prebuild.py")],
                       capture_output=True, text=True, timeout=3600,
                       env={k: v for k, v in os.environ.items() if k != "RAYKIT_BUNDLE_DIR"})
    expect(b.returncode == 0 and (grade / "serverFilesCourse/raykit-bundle" / PREBUILT_NOTE).is_file(),
           f"prebuild.py failed: {b.stdout[-600:]}{b.stderr[-800:]}")
    grade.rename(pristine)
    # Committed whole whatever the course's .gitignore says (git keeps what the job gets).
    repo = work / "course-repo"
    shutil.copytree(pristine / "serverFilesCourse" / "raykit-bundle", repo / "serverFilesCourse" / "raykit-bundle",
                    symlinks=True)
    (repo / ".gitignore").write_text("*.o\n*.json\nCMakeFiles/\nbuild/\nready\n")
    subprocess.run(["git", "init", "-q", str(repo)], check=True, capture_output=True)
    listed = subprocess.run(["git", "-C", str(repo), "ls-files", "--others", "--exclude-standard"],
                            capture_output=True, text=True, check=True).stdout.split()
    listed = [f for f in listed if f.startswith("serverFilesCourse/")]
    files = [p for p in (repo / "serverFilesCourse").rglob("*") if p.is_file()]
    expect(len(listed) == len(files), f"a course's .gitignore (*.o, *.json, CMakeFiles/) leaves {len(files) - len(listed)} "
           f"of the prebuilt bundle's {len(files)} files out of a commit")
    (repo / "serverFilesCourse" / "raykit-bundle" / ".gitignore").unlink()     # the control: without its own
    bare = subprocess.run(["git", "-C", str(repo), "ls-files", "--others", "--exclude-standard"],
                          capture_output=True, text=True, check=True).stdout.split()
    expect(len([f for f in bare if f.startswith("serverFilesCourse/")]) < len(files) - 1,
           "without the bundle's own .gitignore the course's still commits every file: the check above proves nothing")
    last, first = ctx.steps[-1], ctx.steps[0]
    solution = lambda s: {f: (ROOT / "solutions" / s.folder / f).read_text() for f in s.files}
    hostile = lambda name: {f: (fixture_dir("hostile") / name / first.folder / f).read_text() for f in first.files}
    costs = []
    for mode in modes:
        full, cpu = pl_job(pristine, grade, last, solution(last), mode)
        expect(full.get("score") == 1 and full.get("built") == STUDENT_ONLY and "built_why" not in full
               and "your files only" in full.get("output", ""),
               f"step {last.number}'s solution with the prebuilt bundle ({mode}): score {full.get('score')}, "
               f"built {full.get('built')!r} ({full.get('built_why')}), output {full.get('output', '')[-120:]!r}")
        costs.append(f"{mode} {cpu:.1f} s")
        base, _ = pl_job(pristine, grade, first, hostile("always_miss"), mode)
        got, _ = pl_job(pristine, grade, first, hostile("read_answers"), mode)
        shown = "\n".join(t.get("output", "") for t in got.get("tests", []))
        expect(got.get("built") == STUDENT_ONLY, f"read_answers ({mode}): built {got.get('built')!r}")
        expect("could read" not in shown and got.get("score") == base.get("score"),
               f"read_answers in a PrairieLearn job ({mode}) read the kit's answers (score {got.get('score')}, "
               f"always_miss {base.get('score')}): {[l for l in shown.splitlines() if 'could read' in l][:4]}")
    # The control: with the job's folder left open (grade.py's closing taken out), the user isolation's
    # graded code reads the prebuilt bundle: the attack works, and the check above can fail.
    def left_open(g: Path) -> None:
        entry = g / "serverFilesCourse/raykit/tools/prairielearn/grade.py"
        text = entry.read_text()
        expect("os.chmod(grade_dir, mode & ~0o007)" in text, "grade.py no longer closes the job's folder as this test knows")
        entry.write_text(text.replace("os.chmod(grade_dir, mode & ~0o007)", "pass"))

    control = ""
    if "user" in modes:
        got, _ = pl_job(pristine, grade, first, hostile("read_answers"), "user", left_open)
        shown = "\n".join(t.get("output", "") for t in got.get("tests", []))
        expect("raykit-bundle" in shown, "read_answers, the job's folder left open (user): it did not read the "
               f"prebuilt bundle, so the check above proves nothing: {shown[:300]!r}")
        control = "; read_answers reads it where the job's folder is left open (user)"
    # A job whose course (first isolation) or toolchain (the other, or the same) is not the bundle's.
    def course_changed(g: Path) -> None:
        with open(g / "serverFilesCourse/raykit/include/raykit/ray.hpp", "a") as f:
            f.write("// the course changed after the bundle was built\n")

    def other_toolchain(g: Path) -> None:
        folder = g / "serverFilesCourse/raykit-bundle"
        note = json.loads((folder / PREBUILT_NOTE).read_text())
        (folder / note["key"]).rename(folder / "0123456789abcdef01234567")
        note.update(key="0123456789abcdef01234567", compiler="/usr/bin/another-g++, 1, 1")
        (folder / PREBUILT_NOTE).write_text(json.dumps(note))

    def file_left_out(g: Path) -> None:
        folder = g / "serverFilesCourse/raykit-bundle"
        note = json.loads((folder / PREBUILT_NOTE).read_text())
        (folder / note["key"] / next(f for f in note["files"] if f.endswith(".o"))).unlink()

    rebuilt = []
    for mode, edit, words in [(modes[0], course_changed, "the course's sources"),
                              (modes[-1], other_toolchain, "the compiler"),
                              (modes[0], file_left_out, "lacks 1 of its files")]:
        got, cpu = pl_job(pristine, grade, first, solution(first), mode, edit)
        expect(got.get("score") == 1 and got.get("built") == BUILT_HERE and words in got.get("built_why", "")
               and "the grader's own side" in got.get("output", ""),
               f"a job with a mismatched bundle ({edit.__name__}, {mode}): score {got.get('score')}, built "
               f"{got.get('built')!r}, why {got.get('built_why')!r}, output {got.get('output', '')[-100:]!r}")
        rebuilt.append(f"{edit.__name__.replace('_', ' ')} ({mode}) {cpu:.1f} s")
    shutil.rmtree(work, ignore_errors=True)
    # Gradescope: the bundle setup.sh builds (its check of every solution) serves a job, which says so.
    setup = (ROOT / "tools/gradescope/setup.sh").read_text()
    expect(re.search(r"^[^#\n]*\./kit check --steps solutions", setup, re.M),
           "tools/gradescope/setup.sh does not build the kit's side by checking every solution")
    from raykit import bundle
    from raykit.build import detect_undefined
    bundle.ensure(detect_undefined())      # what setup.sh's check leaves in the image's cache
    upload = WORK / "images-upload"
    shutil.rmtree(upload, ignore_errors=True)
    shutil.copytree(ROOT / "solutions" / first.folder, upload / first.folder)
    for mode in modes:
        data = gradescope(upload, isolation=mode)
        extra = data.get("extra_data", {})
        expect(extra.get("built") == STUDENT_ONLY and "your files only" in data.get("output", ""),
               f"a Gradescope job with the bundle built ({mode}): built {extra.get('built')!r} "
               f"({extra.get('built_why')}), output {data.get('output', '')[-200:]!r}")
    empty = Path(tempfile.mkdtemp(prefix="raykit-selftest-no-bundle-"))
    saved = os.environ.get("RAYKIT_BUNDLE_DIR")
    os.environ["RAYKIT_BUNDLE_DIR"] = str(empty)
    try:
        data = gradescope(upload, isolation=modes[0])
    finally:
        if saved is None:
            os.environ.pop("RAYKIT_BUNDLE_DIR", None)
        else:
            os.environ["RAYKIT_BUNDLE_DIR"] = saved
        shutil.rmtree(empty, ignore_errors=True)
        shutil.rmtree(upload, ignore_errors=True)
    extra = data.get("extra_data", {})
    expect(extra.get("built") == BUILT_HERE and data.get("score", 0) > 0,
           f"a Gradescope job with no bundle built: built {extra.get('built')!r}, score {data.get('score')}")
    return (f"public context clean (a spoiled one caught); the bundle committed whole past a course's .gitignore; PrairieLearn, step {last.number} solved, prebuilt: student "
            f"files only, CPU {', '.join(costs)}; read_answers as always_miss{control}; mismatch rebuilt and said why: "
            f"{'; '.join(rebuilt)}; Gradescope: student files only ({', '.join(modes)}), kit side without a bundle"
            + (f" ({'; '.join(skipped)})" if skipped else ""))


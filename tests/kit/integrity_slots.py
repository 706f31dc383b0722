"""Self-test of grading's integrity, part two (issue 43): what one submission's processes may spend,
keep or reach beyond its own run, under each sandbox the machine allows (integrity.isolations):

- fork_budget: a correct step whose calls work in a forked child (and try a thread) while the
  caller waits is refused the child: its cases fail as its own fault, with the limit named, and it
  scores no better than the same code computed in-process (slow_correct);
- keyring_rerun: inputs kept in the sandbox id's kernel keyrings reach neither the ★ case re-run
  alone after the hidden cases nor the next student graded in the same slot;
- classmate_program: graded beside a classmate by `./kit grade -j 2`, a step that looks through
  /proc and the temporary folders for the classmate's answers program learns no path of this kit's
  and can read, list or start nothing of it (a relay would need a process: refused too);
- fill_tmp: a step that fills every temporary folder it may write leaves a classmate graded at the
  same time with the classmate's true score, its own folder stopped at its limit where there is one;
- two kits: two copies of the kit grading on one machine at once take different sandbox ids, and
  each grades its submission right;
- two roots: the same with the second kit in a root of its own as far as the claims go (its own
  /run, as a chroot has), both on the default range of ids: each claims an id the other does not
  have, and neither's reaping makes the other's solutions a student's fault.

Each prints what it managed to do; the checks read that output from the kit's record.
"""

from __future__ import annotations

import csv
import json
import os
import re
import shutil
import subprocess
import tempfile
import threading
import time
from pathlib import Path

import pytest

from raykit import procfs
from raykit.common import BUILD, ROOT
from raykit.sandbox import Limits
from raykit.sandbox_slots import KIT_TEMP_DIRS
from .support import Skipped, expect, need_solutions
from .integrity import blamed_on_kit, grade_json, isolations, printed, run_modes, statuses
from .fixtures import fixture_dir

pytestmark = pytest.mark.security      # conftest.py: may not skip in CI

LIMIT_WORDS = "may not start processes or threads"


def messages(data: dict) -> list[str]:
    return [m for s in data["record"]["steps"] for c in s["cases"] for m in c["messages"]]


def selftest_fork_budget(ctx) -> str:
    def one(mode: str) -> str:
        _, slow, _, _ = grade_json(fixture_dir("hostile") / "slow_correct", ["01"], mode)
        _, forked, _, _ = grade_json(fixture_dir("hostile") / "fork_budget", ["01"], mode)
        out = printed(forked)
        expect("fork_budget: fork refused: Resource temporarily unavailable" in out,
               f"fork_budget ({mode}): the fork was not refused: {out[:300]!r}")
        expect("fork_budget: child answered" not in out and "fork_budget: thread started" not in out,
               f"fork_budget ({mode}): a child or a thread ran: {out[:300]!r}")
        expect("fork_budget: thread refused" in out, f"fork_budget ({mode}): no thread was tried: {out[:300]!r}")
        expect(forked["score"] <= slow["score"],
               f"fork_budget ({mode}): {forked['score']} points, the same code in-process {slow['score']}")
        named = [m for m in messages(forked) if LIMIT_WORDS in m]
        expect(bool(named), f"fork_budget ({mode}): no message names the limit: {messages(forked)[:2]}")
        expect(not blamed_on_kit(forked), f"fork_budget ({mode}): blamed on the kit: {blamed_on_kit(forked)[:2]}")
        bad = [f"{n}: {st}" for _, n, st in statuses(forked) if st not in ("threw", "fail", "timed_out", "crashed")]
        expect(not bad, f"fork_budget ({mode}): cases not failed as the student's: {bad[:4]}")
        return (f"fork and thread refused (EAGAIN), {forked['score']} points (in-process {slow['score']}), "
                f"{len(named)} messages name the limit")

    need_solutions()
    return run_modes(one)


KEY_NOW = re.compile(r"keyring_rerun: now ([RW](?: [0-9a-f]{8})+)")
KEY_FOUND = re.compile(r"keyring_rerun: found ([RW](?: [0-9a-f]{8})+)")


def selftest_keyring_rerun(ctx) -> str:
    """The oracle is the fixture's record: the inputs it printed as "now" in the hidden cases must be
    in no visible or ★ case's output or message, nor anywhere in the next grading in the same slot."""
    def one(mode: str) -> str:
        _, first, _, _ = grade_json(fixture_dir("hostile") / "keyring_rerun", ["01"], mode)
        [step] = first["record"]["steps"]
        if not any(c["tier"] == "hidden" for c in step["cases"]):
            raise Skipped("no hidden cases here, so nothing to keep")
        hidden = {h for c in step["cases"] if c["tier"] == "hidden" for h in KEY_NOW.findall(c["output"])}
        shown = "\n".join(x for c in step["cases"] if c["tier"] != "hidden" for x in [c["output"], *c["messages"]])
        expect(len(hidden) >= 24, f"keyring_rerun ({mode}): only {len(hidden)} hidden inputs recorded; did it run?")
        [far] = [c for c in step["cases"] if "10000 units" in c["name"]]
        expect(far["status"] == "timed_out" and far.get("runs") == 2 and "holds" in far["output"],
               f"keyring_rerun ({mode}): the ★ case was not re-run after timing out: {far['status']}, "
               f"{far['output'][:200]!r}")
        leaked = sorted(h for h in hidden if h in shown)
        expect(not leaked, f"keyring_rerun ({mode}): {len(leaked)} of {len(hidden)} hidden inputs shown in a visible "
                           f"or ★ case, e.g. {leaked[:2]}")
        # The next student in the same slot (the same sandbox id: slot 0, claimed again).
        _, second, _, _ = grade_json(fixture_dir("hostile") / "keyring_rerun", ["01"], mode, cache=False)
        found = set(KEY_FOUND.findall(printed(second)))
        carried = sorted(found & hidden)
        expect(not carried, f"keyring_rerun ({mode}): the next grading in the slot found {len(carried)} of the "
                            f"previous one's {len(hidden)} hidden inputs in its keyrings, e.g. {carried[:2]}")
        holds = sorted({l for l in printed(second).splitlines() if "holds" in l})
        return f"none of {len(hidden)} hidden inputs shown, none in the next grading ({'; '.join(holds)})"

    need_solutions()
    return run_modes(one)


def grade_together(subs: dict[str, Path], mode: str) -> tuple[dict[str, dict], dict[str, dict], float]:
    """`./kit grade CLASS -j 2 --isolation MODE` of the folders `subs` (student -> step folders):
    the CSV's rows and each student's record, by name, and the seconds it took."""
    klass = Path(tempfile.mkdtemp(prefix="raykit-integrity-together-"))
    try:
        for name, folder in subs.items():
            shutil.copytree(folder, klass / "class" / name)
        start = time.monotonic()
        r = subprocess.run([str(ROOT / "kit"), "grade", str(klass / "class"), "--out", str(klass / "grades.csv"),
                            "--json-dir", str(klass / "json"), "--isolation", mode, "-j", "2"], cwd=ROOT,
                           capture_output=True, text=True, timeout=1800, errors="replace")
        took = time.monotonic() - start
        expect(r.returncode == 0, f"./kit grade -j 2 ({mode}) exited {r.returncode}: {r.stderr[-500:]}")
        rows = {row["student"]: row for row in csv.DictReader((klass / "grades.csv").open())}
        records = {p.stem: {"record": rec, "score": rec["score"]}
                   for p in (klass / "json").glob("*.json") if not p.name.startswith(".")   # .judged-by.json aside
                   for rec in [json.loads(p.read_text())]}
    finally:
        shutil.rmtree(klass, ignore_errors=True)
    expect(set(subs) <= set(records), f"./kit grade -j 2 ({mode}): records for {sorted(records)} only")
    return rows, records, took


def ours(line: str) -> bool:
    """Whether a line of classmate_program names a path of this kit's gradings (other kits on the
    machine, with their own folders, are not this test's to judge)."""
    return any(top in line for top in [*KIT_TEMP_DIRS, str(ROOT)])


def selftest_classmate_program(ctx) -> str:
    def one(mode: str) -> str:
        _, base, _, _ = grade_json(fixture_dir("hostile") / "always_miss", ["01"], mode)
        _, records, took = grade_together({"a_spy": fixture_dir("hostile") / "classmate_program",
                                           "b_victim": fixture_dir("hostile") / "slow_correct"}, mode)
        out = printed(records["a_spy"])
        expect("classmate_program: saw" in out, f"classmate_program ({mode}): its output is not in the record")
        # Under bubblewrap the one command line it sees is its own sandbox's (bubblewrap's init): its own
        # program's path. Under the user isolation a compile's command line shows the compile's folder
        # (root's, 0750, the compile id's group): learnt, not reachable, and not an answers program.
        harm = sorted({l for l in out.splitlines() if ours(l) and (re.search(r": could (read|run|list) ", l) or (
            mode != "bwrap" and "learnt" in l and "raykit-sandbox" in l))})
        expect(not harm, f"classmate_program ({mode}): it reached a classmate: " + "; ".join(harm[:5]))
        learnt = len({l for l in out.splitlines() if ours(l) and "learnt" in l})
        refused = "relay: fork Resource temporarily unavailable" in out
        expect(refused, f"classmate_program ({mode}): its relay's fork was not refused")
        expect(records["a_spy"]["score"] == base["score"],
               f"classmate_program ({mode}): {records['a_spy']['score']} points, always_miss {base['score']}")
        seen = max([int(n) for n in re.findall(r"saw (\d+) other answers programs", out)] or [0])
        if mode == "user":      # the classmate's program ran beside it: a test that saw none proves little
            expect(seen >= 1, "classmate_program (user): saw no other answers program while it looked")
        return (f"saw {seen} other answers programs, none of this kit's readable, runnable or listable, no "
                f"answers program's path learnt ({learnt} other paths of this kit's seen), relay refused ({took:.0f} s)")

    need_solutions()
    return run_modes(one)


FILLED = re.compile(r"fill_tmp: (its folder|TMPDIR|/tmp|/var/tmp|/dev/shm) wrote (\d+) MiB \(([^)]*)\), made (\d+)")


def selftest_fill_tmp(ctx) -> str:
    def one(mode: str) -> str:
        _, alone, _, _ = grade_json(ROOT / "solutions", ["01"], mode)
        alice = BUILD / "integrity-alice-01"
        shutil.rmtree(alice, ignore_errors=True)
        shutil.copytree(ROOT / "solutions" / "01_unit_sphere", alice / "01_unit_sphere")
        _, records, took = grade_together({"a_fill": fixture_dir("hostile") / "fill_tmp", "b_alice": alice}, mode)
        out = printed(records["a_fill"])
        filled = {where: (int(mb), why, int(files)) for where, mb, why, files in FILLED.findall(out)}
        expect("its folder" in filled, f"fill_tmp ({mode}): did not run: {out[:300]!r}")
        expect(records["b_alice"]["score"] == alone["score"],
               f"fill_tmp ({mode}): the classmate beside it scored {records['b_alice']['score']}, alone {alone['score']}")
        mb, why, files = filled["its folder"]
        limit = Limits().scratch_mb
        bounded = mode == "bwrap" or (mb <= limit and "No space" in why)
        if mode == "bwrap":
            expect(mb <= limit, f"fill_tmp (bwrap): wrote {mb} MiB in its folder, the limit is {limit} MiB")
        left = [str(p) for d in ("/tmp", "/var/tmp", "/dev/shm") for p in Path(d).glob("raykit-hostile-*")]
        expect(not left, f"fill_tmp ({mode}): files left in the shared temporary folders: {left[:4]}")
        shared = ", ".join(f"{w} {filled[w][0]} MiB" for w in ("/tmp", "/var/tmp", "/dev/shm") if w in filled)
        return (f"classmate {records['b_alice']['score']} as alone; its folder {mb} MiB and {files} files "
                f"({'stopped: ' + why if bounded else 'NOT size-limited here'}); {shared} (its own caps) "
                f"[{took:.0f} s]")

    need_solutions()
    return run_modes(one)


# --- two kits on one machine (issue 43, item 5) ------------------------------------------------

def copy_of_kit(target: Path) -> None:
    """The kit's files as git tracks them, and the changes not yet committed, without build/."""
    names = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                           capture_output=True, check=True).stdout.split(b"\0")
    for raw in filter(None, names):
        name = raw.decode()
        src = ROOT / name
        if name.startswith("build/") or not src.is_file():
            continue
        (target / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(src, target / name)


USER_ID = re.compile(r"user id (\d+)")


def selftest_two_kits(ctx) -> str:
    """Two copies of the kit (two courses on one machine) grade at the same time, each as root
    under each isolation: their sandbox ids differ, and each grades the solutions' steps 01-02 right
    (done): neither ends the other's processes nor takes its id."""
    need_solutions()
    modes, skipped = isolations()
    if os.geteuid() != 0:
        raise Skipped("sandbox ids are taken only as root", need="root")
    other = Path(tempfile.mkdtemp(prefix="raykit-selftest-kitB-"))
    parts = []
    try:
        copy_of_kit(other)
        for mode in modes:
            results: dict[str, tuple[int, dict, str]] = {}
            spans: dict[str, tuple[float, float]] = {}

            def grade(name: str, kit_root: Path) -> None:
                out = Path(tempfile.mkdtemp(prefix=f"raykit-two-kits-{name}-"))
                began = time.monotonic()
                try:
                    # Compiled anew (no object cache), so that the two gradings overlap for seconds.
                    r = subprocess.run([str(kit_root / "kit"), "check", "1", "2", "--steps", str(ROOT / "solutions"),
                                        "--json", str(out / "gs.json"), "--results", str(out / "rec.json"),
                                        "--isolation", mode, "--quiet"], cwd=kit_root, capture_output=True,
                                       text=True, timeout=1800, errors="replace",
                                       env=dict(os.environ, RAYKIT_NO_OBJCACHE="1"))
                    spans[name] = (began, time.monotonic())
                    rec = json.loads((out / "rec.json").read_text()) if (out / "rec.json").is_file() else {}
                    results[name] = (r.returncode, rec, r.stderr[-400:])
                finally:
                    shutil.rmtree(out, ignore_errors=True)

            if mode == modes[0]:
                grade("B", other)        # kit B's first build, alone, so that the two then grade together
            start = time.monotonic()
            threads = [threading.Thread(target=grade, args=(n, r)) for n, r in (("A", ROOT), ("B", other))]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            took = time.monotonic() - start
            ids, scores = {}, {}
            for name, (rc, rec, err) in results.items():
                expect(rc == 0 and rec, f"two kits ({mode}): kit {name} exited {rc}: {err}")
                found = {int(i) for step in rec["steps"] for i in USER_ID.findall(step.get("isolation", ""))}
                expect(len(found) == 1, f"two kits ({mode}): kit {name}'s record names sandbox ids {sorted(found)}")
                ids[name] = found.pop()
                scores[name] = (rec["score"], [step["state"] for step in rec["steps"]])
            overlap = min(spans["A"][1], spans["B"][1]) - max(spans["A"][0], spans["B"][0])
            expect(overlap > 0, f"two kits ({mode}): the two gradings did not run at the same time")
            expect(ids["A"] != ids["B"], f"two kits ({mode}): both graded as sandbox id {ids['A']}")
            expect(scores["A"] == scores["B"] and set(scores["A"][1]) == {"done"},
                   f"two kits ({mode}): the solutions' steps 01-02 scored {scores}")
            parts.append(f"{mode}: ids {ids['A']} and {ids['B']}, both {scores['A'][0]} points, done, "
                         f"{overlap:.0f} s at the same time [{took:.0f} s]")
    finally:
        shutil.rmtree(other, ignore_errors=True)
    return "; ".join(parts + skipped)


OTHER_ROOT = ("mount -t tmpfs -o mode=0700,size=1m raykit-other-root /run/raykit && "
              "mount -t tmpfs -o mode=0700,size=1m raykit-other-root /var/lib/raykit/locks && exec \"$0\" \"$@\"")


def shield_held_ids() -> list:
    """Abstract names bound, for as long as the list lives, for every sandbox id whose lock file in
    this root is held by another grading (a kit of older code on a shared machine, which binds no
    name): the kit this test puts in a root of its own, which cannot see those files, passes them
    over instead of ending that grading's processes."""
    import fcntl
    import socket
    from raykit.sandbox import COMPILE_UID_OFFSET, FIRST_UID, LOCK_DIRS
    held = []
    for uid in range(FIRST_UID, FIRST_UID + COMPILE_UID_OFFSET):
        for folder in LOCK_DIRS:
            try:
                fd = os.open(f"{folder}/raykit-sandbox-{uid}.lock", os.O_RDONLY | os.O_NOFOLLOW | os.O_CLOEXEC)
            except OSError:
                continue
            try:
                fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
                busy = False
            except OSError:
                busy = True
            finally:
                os.close(fd)
            if busy:
                sock = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET | socket.SOCK_CLOEXEC)
                try:
                    sock.bind(f"\0raykit-sandbox-{uid}".encode())
                    held.append(sock)
                except OSError:
                    sock.close()    # a kit of this code: it holds the name itself
    return held


def selftest_two_roots(ctx) -> str:
    """Two kits on one kernel whose claim folders cannot see each other's (the second in a mount
    namespace with empty tmpfs over /run/raykit and /var/lib/raykit/locks: exactly what a chroot's
    own /run gives), each on the default range of sandbox ids (no RAYKIT_FIRST_UID), grade the
    solutions at the same time under each isolation: they claim different ids, and every step is
    done or not graded, never a crash, a compile error or a failure of the student's."""
    need_solutions()
    modes, skipped = isolations()
    if os.geteuid() != 0:
        raise Skipped("sandbox ids are taken only as root", need="root")
    if shutil.which("unshare") is None or shutil.which("mount") is None:
        raise Skipped("util-linux's unshare and mount are needed to give a kit its own /run", need="root")
    for folder in ("/run/raykit", "/var/lib/raykit/locks"):
        os.makedirs(folder, 0o700, exist_ok=True)
    other = Path(tempfile.mkdtemp(prefix="raykit-selftest-rootB-"))
    numbers = [str(int(s.number)) for s in ctx.steps]
    parts = []
    try:
        copy_of_kit(other)
        for mode in modes:
            results: dict[str, tuple[int, dict, str]] = {}

            def grade(name: str, kit_root: Path, own_root: bool) -> None:
                out = Path(tempfile.mkdtemp(prefix=f"raykit-two-roots-{name}-"))
                try:
                    argv = [str(kit_root / "kit"), "check", *numbers, "--steps", str(ROOT / "solutions"),
                            "--results", str(out / "rec.json"), "--isolation", mode, "--quiet"]
                    if own_root:
                        argv = ["unshare", "-m", "--propagation", "private", "sh", "-c", OTHER_ROOT] + argv
                    env = dict(os.environ, RAYKIT_NO_OBJCACHE="1")   # compiled anew: the two overlap
                    env.pop("RAYKIT_FIRST_UID", None)
                    env.pop("RAYKIT_LOCK_DIR", None)
                    r = subprocess.run(argv, cwd=kit_root, capture_output=True, text=True, timeout=1800,
                                       errors="replace", env=env)
                    rec = json.loads((out / "rec.json").read_text()) if (out / "rec.json").is_file() else {}
                    results[name] = (r.returncode, rec, r.stderr[-400:])
                finally:
                    shutil.rmtree(out, ignore_errors=True)

            if mode == modes[0]:
                grade("B", other, False)    # kit B's own first build, alone
            shield = shield_held_ids()
            threads = [threading.Thread(target=grade, args=a) for a in (("A", ROOT, False), ("B", other, True))]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            for sock in shield:
                sock.close()
            ids, states = {}, {}
            for name, (rc, rec, err) in results.items():
                expect(bool(rec), f"two roots ({mode}): kit {name} exited {rc} without a record: {err}")
                found = {int(i) for step in rec["steps"] for i in USER_ID.findall(step.get("isolation", ""))}
                ids[name] = sorted(found)
                states[name] = {step["step"]: step["state"] for step in rec["steps"]}
                wrong = {n: st for n, st in states[name].items() if st not in ("done", "not_graded")}
                expect(not wrong, f"two roots ({mode}): kit {name} gave the solutions {wrong} (ids {ids})")
            expect(not set(ids["A"]) & set(ids["B"]), f"two roots ({mode}): both graded as sandbox ids {ids['A']}")
            parts.append(f"{mode}: ids {ids['A']} and {ids['B']}, states A {sorted(set(states['A'].values()))}, "
                         f"B {sorted(set(states['B'].values()))}")
    finally:
        shutil.rmtree(other, ignore_errors=True)
    return "; ".join(parts + skipped)


# --- signals the kit did not send (issue 52, item 4) -------------------------------------------

class ForeignReaper:
    """What another grading's reaping does to this one when both hold one sandbox id: SIGKILL to
    the first compiler process (cc1plus) of the grading's compile id, and to its first answers
    process, each once. Only processes of the id the grading wrote to its RAYKIT_UID_FILE: no other
    kit's on the machine."""

    def __init__(self, uid_file: Path):
        self.uid_file, self.killed, self.stop = uid_file, {"compile": 0, "answers": 0}, threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self) -> None:
        import signal
        from raykit.sandbox import COMPILE_UID_OFFSET
        uid = None
        while not self.stop.is_set() and not all(self.killed.values()):
            if uid is None:
                try:
                    uid = int(self.uid_file.read_text().strip())
                except (OSError, ValueError):
                    time.sleep(0.005)
                    continue
            for pid in procfs.pids():
                owner = procfs.real_uid(pid)
                kind = ("compile" if owner == uid + COMPILE_UID_OFFSET and procfs.comm(pid) == "cc1plus" else
                        "answers" if owner == uid and procfs.comm(pid).startswith("answers") else "")
                if kind and not self.killed[kind]:
                    try:
                        os.kill(pid, signal.SIGKILL)
                        self.killed[kind] += 1
                    except OSError:
                        pass
            time.sleep(0.003)

    def end(self) -> dict:
        self.stop.set()
        self.thread.join()
        return self.killed


def selftest_unsent_signals(ctx) -> str:
    """A process of the step killed by a signal the kit did not send is never the student's crash or
    compile error: the solutions' steps 01-02, graded while a reaper kills their first compiler and
    their first answers process (what a grading sharing the id did), come out done or not graded
    under each isolation. And the kit's evidence is not a free pass: hostile/self_kill, whose every
    call raises SIGKILL on itself, crashes like the code it is (never not graded), scores no more than
    always_miss, and has at most three cases run once more."""
    need_solutions()
    if os.geteuid() != 0:
        raise Skipped("sandbox ids are taken only as root", need="root")
    modes, skipped = isolations()
    numbers = [str(int(s.number)) for s in ctx.steps[:2]]
    parts = []
    for mode in modes:
        for attempt in range(3):    # a loaded machine may hide a short-lived process from the reaper
            held = Path(tempfile.mkdtemp(prefix="raykit-unsent-"))
            try:
                reaper = ForeignReaper(held / "uid")
                r = subprocess.run([str(ROOT / "kit"), "check", *numbers, "--steps", str(ROOT / "solutions"),
                                    "--results", str(held / "rec.json"), "--isolation", mode, "--quiet"],
                                   cwd=ROOT, capture_output=True, text=True, timeout=1800, errors="replace",
                                   env=dict(os.environ, RAYKIT_NO_OBJCACHE="1", RAYKIT_UID_FILE=str(held / "uid")))
                killed = reaper.end()
                expect((held / "rec.json").is_file(),
                       f"unsent signals ({mode}): exited {r.returncode}: {r.stderr[-400:]}")
                rec = json.loads((held / "rec.json").read_text())
            finally:
                shutil.rmtree(held, ignore_errors=True)
            if all(killed.values()):
                break
        expect(all(killed.values()), f"unsent signals ({mode}): in 3 tries the reaper found nothing to kill "
                                     f"({killed}): the test proves nothing")
        states = {st["step"]: st["state"] for st in rec["steps"]}
        wrong = {n: st for n, st in states.items() if st not in ("done", "not_graded")}
        expect(not wrong, f"unsent signals ({mode}): the solutions graded {wrong} after a SIGKILL the kit did "
                          f"not send ({killed})")
        _, base, _, _ = grade_json(fixture_dir("hostile") / "always_miss", ["01"], mode)
        _, got, _, _ = grade_json(fixture_dir("hostile") / "self_kill", ["01"], mode)
        [step] = got["record"]["steps"]
        expect(step["state"] != "not_graded", f"self_kill ({mode}): not graded ({step.get('reason')}): a free attempt")
        expect(got["score"] <= base["score"], f"self_kill ({mode}): {got['score']}, always_miss {base['score']}")
        crashed = sum(c["status"] == "crashed" for c in step["cases"])
        again = sum(c.get("runs", 1) > 1 for c in step["cases"])
        expect(crashed and again <= 3, f"self_kill ({mode}): {crashed} cases crashed, {again} run again")
        reasons = "; ".join(f"step {m['step']} not graded: {m.get('reason', '')[:160]}"
                            for m in rec.get("not_graded", []))
        parts.append(f"{mode}: solutions {sorted(set(states.values()))}{' (' + reasons + ')' if reasons else ''} with {killed['compile']} compiler and "
                     f"{killed['answers']} answers process killed; self_kill {step['state']}, {crashed} crashed, "
                     f"{again} run again")
    return "; ".join(parts + skipped)

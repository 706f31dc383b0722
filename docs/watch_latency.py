"""Save to verdict under `./kit watch`, as a student sees it: on a pseudo-terminal.

    python3 docs/watch_latency.py [--rounds N] [--steps 1,2,5] [--settle S] [REV ...]

A student's copy of the kit is made (`./kit handout --committed`, in a temporary folder), one per
step N, with steps/ holding this repository's solutions up to step N and the shipped stubs after it,
and `./kit watch N` runs in each on a pseudo-terminal (Python's pty), as a student runs it (the warm-up
off: RAYKIT_NO_WARMUP, so that no build of it runs beside the rounds; the kit's side built in a
folder of the run's own, RAYKIT_BUNDLE_DIR, one per revision). After the watch has shown
its first verdict, each round saves the step's first file with one harmless line of code of its own
(a new `[[maybe_unused]]` constant: the compiler sees new code, so no cache can answer for it) and
times, from the save:

- seen: the screen is cleared and says "checking ...": the watch noticed the save (its polling);
- verdict: the step's verdict is on the screen: its scoreboard, ending "watching ... save to re-check",
  or, when the save completed the step, "Step N is done", which the watch shows while it checks the
  next step.

Each save completes step N, and the watch moves on to step N+1, not started; step 05, the last, stays.

With REVs (commits, branches), each is cloned from this repository and measured the same way, its
handouts made by its own kit; without, the working tree is. Rounds are interleaved: one watch per
revision and step stays open, one is saved at a time, every watch once a round, the order reversed
every other round; several rounds, medians. The load average (1 minute) at each save is
printed beside the figures: a loaded machine makes every one of them larger, and the goal of issue
53 (1 s for steps 01 to 04, 2 s for step 05) is for 2 cores at load 2.

--write FILE puts the table in FILE between the lines `<!-- watch_latency:begin -->` and
`<!-- watch_latency:end -->`. Bad input: a message and exit 2. A watch that shows no verdict within --timeout seconds: a message
and exit 1.
"""

from __future__ import annotations

import argparse
import os
import pty
import re
import select
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ANSI = re.compile(r"\033\[[0-9;?]*[A-Za-z]")
CLEAR = "\033[2J"
BEGIN, END = "<!-- watch_latency:begin -->", "<!-- watch_latency:end -->"
DONE_LINE = re.compile(r"watching .*save to re-check")


def fail(message: str, code: int = 2) -> None:
    print(f"watch_latency: {message}", file=sys.stderr)
    sys.exit(code)


class Watch:
    """`kit watch N` on a pseudo-terminal, in a handout; its output read as it comes."""

    def __init__(self, kit: Path, number: str, env: dict):
        self.pid, self.fd = pty.fork()
        if self.pid == 0:
            os.chdir(kit)
            os.execve(str(kit / "kit"), [str(kit / "kit"), "watch", number], env)
        self.out = ""

    def read(self, timeout: float) -> bool:
        """Reads what the watch has written within `timeout` seconds; False once it is gone."""
        ready, _, _ = select.select([self.fd], [], [], timeout)
        if ready:
            try:
                data = os.read(self.fd, 65536)
            except OSError:
                return False
            if not data:
                return False
            self.out += data.decode(errors="replace")
        return True

    def screen(self) -> str:
        """The text since the last clear of the screen, without colours."""
        return ANSI.sub("", self.out[self.out.rfind(CLEAR):] if CLEAR in self.out else self.out)

    def wait_verdict(self, since: int, timeout: float, started: float, number: str
                     ) -> tuple[float | None, float | None]:
        """Waits for a cleared screen saying "checking" after offset `since`, then for step `number`'s
        verdict: the scoreboard's last line, or the line saying the step is done (shown while the next
        step's check runs); returns the two times from `started` (None: not seen)."""
        done = re.compile(rf"Step {number} is done")
        seen = verdict = None
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if not self.read(0.005):
                break
            tail = self.out[since:]
            if seen is None and "checking ..." in ANSI.sub("", tail):
                seen = time.monotonic() - started
            if seen is not None:
                last = tail.rfind(CLEAR)
                screen = ANSI.sub("", tail[last:]) if last >= 0 else ""
                if done.search(screen) or DONE_LINE.search(screen) and "checking ..." not in screen:
                    verdict = time.monotonic() - started
                    break
        return seen, verdict

    def close(self) -> None:
        try:
            os.write(self.fd, b"q")
            end = time.monotonic() + 5
            while time.monotonic() < end and self.read(0.1):
                pass
        except OSError:
            pass
        try:
            os.kill(self.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
        try:
            os.waitpid(self.pid, 0)
        except ChildProcessError:
            pass
        os.close(self.fd)


def clone(rev: str, where: Path) -> Path:
    """This repository at `rev`, in a folder of its own under `where`."""
    folder = where / ("rev-" + rev.replace("/", "_"))
    r = subprocess.run(["git", "clone", "-q", str(ROOT), str(folder)], capture_output=True, text=True)
    if r.returncode == 0:
        r = subprocess.run(["git", "checkout", "-q", rev], cwd=folder, capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"cannot check out {rev}: {r.stderr.strip()}")
    return folder


def handouts(kit: Path, where: Path, numbers: list[str], env: dict) -> dict[str, Path]:
    """A student's copy of `kit` per step N, solved up to step N."""
    where.mkdir(parents=True, exist_ok=True)
    handout = where / "handout"
    r = subprocess.run([str(kit / "kit"), "handout", str(handout), "--committed"], cwd=kit, env=env,
                       capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"./kit handout failed in {kit}:\n{r.stdout[-1500:]}{r.stderr[-1500:]}", 1)
    kits = {}
    for n in numbers:       # a handout for each watch: a watch looks at every step's files, and holds its build
        kits[n] = where / f"kit-{n}"
        shutil.copytree(handout, kits[n], symlinks=True)
        for folder in sorted((kit / "solutions").iterdir()):
            # Solved up to step N, the shipped stubs after it: a save of step N passes it, and the watch
            # moves on to step N+1, not started, and stays there (solutions throughout would run every
            # later step's check too before the screen settles).
            if folder.is_dir() and folder.name[:2] <= n:
                for f in folder.iterdir():
                    shutil.copyfile(f, kits[n] / "steps" / folder.name / f.name)
    return kits


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("revs", nargs="*", metavar="REV",
                    help="revisions to compare, each cloned from this repository (default: the working tree)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--steps", default="1,2,3,4,5", help="the steps to time, e.g. 1,5")
    ap.add_argument("--settle", type=float, default=1.5, help="seconds between a verdict and the next save")
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("--write", metavar="FILE", help=f"put the table in FILE between its lines {BEGIN} and {END}")
    args = ap.parse_args(argv)
    if args.rounds < 1:
        fail("--rounds must be 1 or more")
    if args.settle < 0 or args.timeout <= 0:
        fail("--settle must be 0 or more and --timeout more than 0")
    try:
        written = Path(args.write).read_text() if args.write else BEGIN + END
    except OSError as e:
        fail(f"{args.write}: {e.strerror}")
    if BEGIN not in written or END not in written or written.index(BEGIN) > written.index(END):
        fail(f"{args.write} has no {BEGIN} ... {END} lines to write between")
    folders = {p.name[:2]: p for p in sorted((ROOT / "solutions").iterdir()) if p.is_dir()}
    try:
        numbers = [f"{int(n):02d}" for n in args.steps.split(",")]
    except ValueError:
        fail(f"--steps {args.steps}: numbers separated by commas")
    unknown = [n for n in numbers if n not in folders]
    if unknown:
        fail(f"no step {', '.join(unknown)} in {ROOT / 'solutions'}")

    # Ended by a signal: the watches and the temporary folder go too (the finally below).
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
    env = dict(os.environ, TERM="xterm", COLUMNS="120", LINES="60", RAYKIT_NO_WARMUP="1")
    work = Path(tempfile.mkdtemp(prefix="watch-latency-"))
    labels = args.revs or ["working tree"]
    watches: dict[tuple[str, str], Watch] = {}
    times: dict[tuple[str, str], list[tuple[float, float, float]]] = {}
    try:
        kits = {}
        for i, label in enumerate(labels):
            kit = clone(label, work) if args.revs else ROOT
            kits[label] = handouts(kit, work / f"kits-{i}", numbers, env)
        order = [(label, n) for label in labels for n in numbers]
        for key in order:       # each watch's first check (the build folder from nothing) is not timed
            label, n = key
            # The kit's side (bundle.py) in a folder per revision: a machine keeps its few most recently
            # used bundles, and the revisions measured here, with what else runs on the machine, would
            # otherwise push one another's out between two saves (a student's kit has one).
            own = dict(env, RAYKIT_BUNDLE_DIR=str(work / f"bundles-{labels.index(label)}"))
            w = watches[key] = Watch(kits[label][n], n, own)
            times[key] = []
            seen, verdict = w.wait_verdict(0, args.timeout * 5, time.monotonic(), n)
            if verdict is None:
                fail(f"{label}, step {n}: the watch showed no first verdict:\n{w.screen()[-2000:]}", 1)
        for rnd in range(args.rounds):
            for key in (order if rnd % 2 == 0 else order[::-1]):      # interleaved, the order reversed each round
                label, n = key
                w = watches[key]
                end = time.monotonic() + args.settle
                while time.monotonic() < end:   # whatever it still had to say
                    w.read(0.05)
                target = next(f for f in sorted((kits[label][n] / "steps" / folders[n].name).iterdir())
                              if f.suffix == ".cpp")
                since = len(w.out)
                load = os.getloadavg()[0]
                started = time.monotonic()
                with open(target, "a") as f:
                    f.write(f"[[maybe_unused]] static const int watch_latency_{rnd}_{os.getpid()} = {rnd};\n")
                seen, verdict = w.wait_verdict(since, args.timeout, started, n)
                if verdict is None:
                    fail(f"{label}, step {n}, round {rnd + 1}: no verdict within {args.timeout:g} s:\n"
                         f"{w.screen()[-2000:]}", 1)
                times[key].append((seen, verdict, load))
                print(f"{label}, step {n}, round {rnd + 1}: seen {seen:.2f} s, verdict {verdict:.2f} s, "
                      f"load {load:.2f}", flush=True)
    finally:
        for w in watches.values():
            w.close()
        shutil.rmtree(work, ignore_errors=True)

    lines = [f"Save to verdict under `./kit watch`, {args.rounds} rounds, interleaved, {os.cpu_count()} cores; "
             "medians (min-max); `seen`: the watch's screen says it is checking.", "",
             "| revision | step | seen | verdict | load (1 min) |", "|---|---|--:|--:|--:|"]
    for key in order:
        s = [t[0] for t in times[key]]
        v = [t[1] for t in times[key]]
        lo = [t[2] for t in times[key]]
        lines.append(f"| {key[0]} | {key[1]} | {statistics.median(s):.2f} s | {statistics.median(v):.2f} s "
                     f"({min(v):.2f}-{max(v):.2f}) | {statistics.median(lo):.2f} ({min(lo):.2f}-{max(lo):.2f}) |")
    print("\n" + "\n".join(lines))
    if args.write:
        text = Path(args.write).read_text()
        head, tail = text[:text.index(BEGIN) + len(BEGIN)], text[text.index(END):]
        tmp = Path(args.write).with_name(Path(args.write).name + ".tmp")
        tmp.write_text(head + "\n" + "\n".join(lines) + "\n" + tail)
        os.replace(tmp, args.write)
        print(f"wrote the table into {args.write}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

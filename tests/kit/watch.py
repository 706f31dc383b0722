"""Self-test of ./kit watch, driven through a pseudo-terminal as a student's terminal would drive it:
the screen is redrawn per check, a save is checked, the step stays until its ★ cases pass or n is
pressed, a finished step moves on by itself (its banner naming the step checked, not a step done
already that it passed over), a save the time stamps miss is still seen (and said),
r re-checks, q quits, and "Then run: ./kit check" never appears."""

from __future__ import annotations

import os
import shutil
import subprocess
import time

from raykit.common import BUILD, ROOT, load_steps
from .support import CLEAR, Failed, Screen, expect, need_solutions
from .fixtures import fixture_dir


def processes_with(word: str | tuple[str, ...]) -> list[int]:
    """The processes whose command line holds `word` (every one of them, for several; ps: Linux and
    macOS alike)."""
    words = (word,) if isinstance(word, str) else word
    out = subprocess.run(["ps", "-A", "-o", "pid=", "-o", "args="], capture_output=True, text=True).stdout
    return [int(l.split(None, 1)[0]) for l in out.splitlines()
            if all(w in l for w in words) and l.split(None, 1)[0].isdigit()]


def wait_for_process(word: str | tuple[str, ...], seconds: float) -> list[int]:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        found = processes_with(word)
        if found:
            return found
        time.sleep(0.1)
    return []


def alive(pid: int) -> bool:
    """Whether `pid` runs (a zombie is dead)."""
    from raykit import procfs
    return procfs.alive(pid)


def selftest_watch(ctx) -> str:
    need_solutions()
    steps = load_steps()
    s1, s2 = steps[0], steps[1]
    folder = BUILD / "watch-test"
    shutil.rmtree(folder, ignore_errors=True)
    shutil.copytree(ROOT / "steps", folder)
    screen = Screen([str(ROOT / "kit"), "watch", "1", "--steps", str(folder)])
    notes = []
    try:
        screen.wait_for("not started", 300)
        # An endless loop saved, then, while its check runs, a textbook answer (done, ★ cases failing, so
        # the step stays on screen): the loop's check is stopped with its looping program, and the
        # answer saved is what the screen shows.
        for f in s1.files:
            shutil.copyfile(fixture_dir("hang") / s1.folder / f, folder / s1.folder / f)
        # The watch's own program, in its run folder (build/runs/watch-PID-XXXX/, runfolders.py).
        looping = wait_for_process((str(BUILD / "runs") + "/watch-", f"/answers_step{s1.number}"), 240)
        expect(looping, "the endless loop's check never started its answers program")
        for f in s1.files:
            shutil.copyfile(fixture_dir("textbook") / s1.folder / f, folder / s1.folder / f)
        screen.wait_for("the check that was running stopped", 60)
        took = screen.wait_for("press n for the next step", 240)
        notes.append(f"a save during an endless loop's check: stopped, the fix's verdict {took:.1f} s later")
        expect(not any(alive(pid) for pid in looping), f"the stopped check left its program running: {looping}")
        expect(f"step {s1.number}" in screen.last(), "the screen after the save is not step 01's")
        # A save the time stamps miss: same size, the old modification time put back.
        target = folder / s1.folder / s1.files[0]
        st = target.stat()
        text = target.read_text()
        marker = text.replace(" ", "\t", 1)        # same length, one character different
        expect(len(marker) == len(text) and marker != text, "could not make an edit of the same size")
        target.write_text(marker)
        os.utime(target, ns=(st.st_atime_ns, st.st_mtime_ns))
        took = screen.wait_for("time stamps", 30)
        notes.append(f"a save with its old time stamp seen in {took:.1f} s")
        # n: the next step, here not started.
        screen.press("n")
        screen.wait_for(f"watch · step {s2.number}", 120)
        screen.wait_for("not started", 120)
        # A save of step 01's file while step 02 is shown brings step 01 back.
        target.write_text(text)
        screen.wait_for(f"watch · step {s1.number}", 120)
        # The reference answer passes the ★ cases too: the watch moves on by itself, past step 02 done
        # already, and the banner names the step it checked for the save, 01, not the step passed over.
        s3 = steps[2]
        for f in s2.files:
            shutil.copyfile(ROOT / "solutions" / s2.folder / f, folder / s2.folder / f)
        screen.wait_for(f"Step {s2.number} is done, ★ cases included. On to step {s3.number}", 180)
        for f in s1.files:
            shutil.copyfile(ROOT / "solutions" / s1.folder / f, folder / s1.folder / f)
        banner = f"Step {s1.number} is done, ★ cases included. Step {s2.number} was done already. On to step {s3.number}"
        try:
            screen.wait_for(banner, 120)
        except Failed:
            raise Failed(f"the banner does not name step {s1.number}, the step saved:\n{screen.last()[-600:]}")
        # r re-checks at once: the time on the header changes.
        before = screen.text.count(CLEAR)
        screen.press("r")
        deadline = time.monotonic() + 60
        while screen.text.count(CLEAR) < before + 2 and time.monotonic() < deadline:
            time.sleep(0.05)
        expect(screen.text.count(CLEAR) >= before + 2, "r did not re-check (no redraw)")
        expect("Then run: ./kit check" not in screen.text, "watch printed 'Then run: ./kit check N'")
        expect(screen.text.count(CLEAR) >= 4, "the screen was appended to, not redrawn")
        screen.press("q")
        try:
            code = screen.proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            raise Failed("q did not end ./kit watch")
        expect(code == 0, f"q ended ./kit watch with exit status {code}")
    finally:
        screen.close()
        shutil.rmtree(folder, ignore_errors=True)
    return ("on a pseudo-terminal: redrawn per check, a check stopped by a save, stays on a done step until "
            "★ or n, moves on by itself, r and q work, no 'Then run'; " + ", ".join(notes))

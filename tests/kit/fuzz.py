"""Self-test: libFuzzer runs against the reference solutions, with the property oracles.

Every input a run once found (tests/fuzz/regressions/<target>/) is replayed first. Then each target is
fuzzed from an empty corpus with a fixed seed and a fixed number of inputs, so that this self-test gives
the same verdict on every run and on every machine: a finding is reproduced by running it again.
RAYKIT_SELFTEST_FULL=1 fuzzes for longer with a fresh seed each time, to look for new findings; what it
finds is committed to the regressions.
"""

from __future__ import annotations

import os
import random
import shutil
import subprocess
import tempfile

from raykit.common import BUILD, ROOT, KitError
from raykit.build import configure, preset_build

from .support import Failed, Skipped, expect, need_solutions

RUNS_PER_TARGET = 3_000_000          # about 2 s each on the CI machine
SEED = 1
FULL_SECONDS_PER_TARGET = 300
REGRESSIONS = ROOT / "tests" / "fuzz" / "regressions"


def selftest_fuzz(ctx) -> str:
    need_solutions()
    if ctx.fast:
        raise Skipped("--fast")
    if shutil.which("clang++") is None:
        raise Skipped("clang++ is not installed (apt-get install clang libclang-rt-14-dev)")
    try:
        configure(preset_build("fuzz"))
    except KitError as e:
        raise Failed(f"configuring the fuzz build failed:\n{str(e)[-1500:]}")
    r = subprocess.run(["cmake", "--build", str(BUILD / "fuzz")], cwd=ROOT, capture_output=True, text=True)
    expect(r.returncode == 0, f"building the fuzz targets failed:\n{(r.stdout + r.stderr)[-1500:]}")
    targets = sorted((BUILD / "fuzz" / "tests" / "fuzz").glob("fuzz_*"))
    targets = [t for t in targets if t.is_file() and t.stat().st_mode & 0o111]
    expect(bool(targets), "no fuzz target was built")
    full = os.environ.get("RAYKIT_SELFTEST_FULL") == "1"
    seed = random.randrange(1, 2**31) if full else SEED
    (BUILD / "fuzz-corpus").mkdir(parents=True, exist_ok=True)     # libFuzzer's -artifact_prefix must exist
    runs, replayed = [], 0
    for exe in targets:
        known = sorted(p for p in (REGRESSIONS / exe.name).glob("*") if p.is_file())
        if known:
            r = subprocess.run([str(exe), *map(str, known)], cwd=BUILD, capture_output=True, text=True, timeout=120)
            if r.returncode != 0:
                raise Failed(f"{exe.name} fails again on an input found before ({REGRESSIONS.relative_to(ROOT)}/"
                             f"{exe.name}):\n  " + "\n  ".join(_finding(r.stderr)))
            replayed += len(known)
        # libFuzzer refuses to start when its artifact folder is missing (a fresh clone has none), and
        # then reads as a finding: the folder is made before the run, not after a failure.
        (BUILD / "fuzz-corpus").mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(prefix="raykit-fuzz-") as corpus:
            budget = [f"-max_total_time={FULL_SECONDS_PER_TARGET}"] if full else [f"-runs={RUNS_PER_TARGET}"]
            r = subprocess.run([str(exe), f"-seed={seed}", *budget, "-print_final_stats=1",
                                f"-artifact_prefix={BUILD / 'fuzz-corpus'}/", corpus],
                               cwd=BUILD, capture_output=True, text=True, timeout=FULL_SECONDS_PER_TARGET * 3)
        if r.returncode != 0:
            raise Failed(f"{exe.name} found a failing input (seed {seed}; the input is in build/fuzz-corpus/; "
                         f"add it to {REGRESSIONS.relative_to(ROOT)}/{exe.name}/ once understood):\n  "
                         + "\n  ".join(_finding(r.stderr)))
        executed = next((l.rsplit(":", 1)[1].strip() for l in r.stderr.splitlines()
                         if l.startswith("stat::number_of_executed_units")), "?")
        runs.append(f"{exe.name.removeprefix('fuzz_')} {executed}")
    how = (f"{FULL_SECONDS_PER_TARGET} s each, seed {seed}" if full else
           f"seed {seed}, {RUNS_PER_TARGET:,} inputs each ({FULL_SECONDS_PER_TARGET} s and a fresh seed with "
           "RAYKIT_SELFTEST_FULL=1)")
    return (f"{replayed} earlier findings replayed; {how}; no finding: " + ", ".join(runs) + " inputs")


def _finding(stderr: str) -> list[str]:
    return [l for l in stderr.splitlines() if "property broken" in l or "ERROR" in l or "o = (" in l][:6]

"""Self-test: libFuzzer runs against the reference solutions, with the property oracles."""

from __future__ import annotations

import shutil
import subprocess

from ..common import BUILD, ROOT, KitError
from ..build import configure, preset_build

from .harness import Failed, Skipped, expect, need_solutions

SECONDS_PER_TARGET = 15


def selftest_fuzz(ctx) -> str:
    need_solutions()
    if ctx.fast:
        raise Skipped("--fast")
    if shutil.which("clang++") is None:
        raise Skipped("clang++ is not installed (apt-get install clang libclang-rt-14-dev)")
    try:
        configure(preset_build("fuzz"))   # the preset's settings, without --preset (CMake 3.18)
    except KitError as e:
        raise Failed(f"configuring the fuzz build failed:\n{str(e)[-1500:]}")
    r = subprocess.run(["cmake", "--build", str(BUILD / "fuzz")], cwd=ROOT, capture_output=True, text=True)
    expect(r.returncode == 0, f"building the fuzz targets failed:\n{(r.stdout + r.stderr)[-1500:]}")
    targets = sorted((BUILD / "fuzz" / "tests" / "fuzz").glob("fuzz_*"))
    targets = [t for t in targets if t.is_file() and t.stat().st_mode & 0o111]
    expect(bool(targets), "no fuzz target was built")
    runs = []
    for exe in targets:
        corpus = BUILD / "fuzz-corpus" / exe.name
        corpus.mkdir(parents=True, exist_ok=True)
        r = subprocess.run([str(exe), f"-max_total_time={SECONDS_PER_TARGET}", "-print_final_stats=1",
                            f"-artifact_prefix={BUILD / 'fuzz-corpus'}/", str(corpus)],
                           cwd=BUILD, capture_output=True, text=True, timeout=SECONDS_PER_TARGET * 4 + 60)
        if r.returncode != 0:
            lines = [l for l in r.stderr.splitlines() if "property broken" in l or "ERROR" in l or "o = (" in l]
            raise Failed(f"{exe.name} found a failing input:\n  " + "\n  ".join(lines[:6]))
        executed = next((l.rsplit(":", 1)[1].strip() for l in r.stderr.splitlines()
                         if l.startswith("stat::number_of_executed_units")), "?")
        runs.append(f"{exe.name.removeprefix('fuzz_')} {executed}")
    return f"{SECONDS_PER_TARGET} s each, no finding: " + ", ".join(runs) + " inputs"


def selftests():
    return [("fuzzing the reference solutions", selftest_fuzz)]

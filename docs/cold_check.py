"""The CPU of a cold `./kit check`, measured the bench's way: revisions of the kit side by side,
interleaved in one run (the order reversed every round), several rounds, medians.

    python3 docs/cold_check.py [--rounds N] [--steps 1|all] [--kit-side-built] REV [REV ...]

Each REV (a commit, a branch, HEAD) is cloned from this repository into a temporary folder and
its steps are written from its own solutions (step 01 only, or every step with --steps all).
A round runs `./kit check 1` (or `./kit check`) once in each clone, as a newcomer without the
warm-up would: a fresh build/ folder, an empty kit cache (a fresh XDG_CACHE_HOME), no compiled
Python beside the sources. With --kit-side-built, the machine has run the kit before: each clone
keeps its own cache folder across rounds (the bundle, or an older kit's cache of its objects, and its
compiled Python), filled by one run that is not counted, and each counted run starts from a fresh
build/ only (a `rm -rf build`, a second handout, a grading slot). What is counted is the CPU (user + system) of every process the
check ran, read with getrusage(RUSAGE_CHILDREN); the wall time and the load average are printed
beside it, since a loaded machine makes every figure larger. Bad input: a message and exit 2.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def fail(message: str) -> None:
    print(f"cold_check: {message}", file=sys.stderr)
    sys.exit(2)


def checkout(rev: str, where: Path, fail=fail) -> Path:
    """REV cloned from this repository into a folder of `where` (docs/grade_cost.py's too), with the
    shared folder beside it that a clone looks for; `fail` says why not."""
    folder = where / rev.replace("/", "_")
    r = subprocess.run(["git", "clone", "-q", str(ROOT), str(folder)], capture_output=True, text=True)
    if r.returncode == 0:
        r = subprocess.run(["git", "checkout", "-q", rev], cwd=folder, capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"cannot check out {rev}: {r.stderr.strip()}")
    shared = ROOT.parent / "shared"
    if shared.is_dir() and not (where / "shared").exists():
        (where / "shared").symlink_to(shared)
    return folder


def clone(rev: str, where: Path, all_steps: bool) -> Path:
    folder = checkout(rev, where)
    for step in sorted((folder / "solutions").iterdir()):
        if step.is_dir() and (all_steps or step.name.startswith("01_")):
            for f in step.glob("*.cpp"):
                shutil.copy(f, folder / "steps" / step.name / f.name)
    return folder


def one_run(folder: Path, command: list[str], kept_cache: Path | None = None) -> dict:
    shutil.rmtree(folder / "build", ignore_errors=True)
    for cache in folder.joinpath("tools").rglob("__pycache__"):
        shutil.rmtree(cache, ignore_errors=True)
    with tempfile.TemporaryDirectory(prefix="cold-cache-") as fresh:
        home = str(kept_cache) if kept_cache else fresh
        # One secret for every clone (the self-test's pinned one): the hidden draws, and so the work
        # the judges do, are the same in each revision's run (a clone makes a secret of its own).
        env = dict(os.environ, XDG_CACHE_HOME=home, RAYKIT_NO_WARMUP="1", RAYKIT_SELFTEST_SECRET="ab" * 32)
        for name in ("RAYKIT_KIT_CACHE_DIR", "RAYKIT_BUNDLE_DIR", "PYTHONPYCACHEPREFIX", "RAYKIT_PYCACHE"):
            env.pop(name, None)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        load = os.getloadavg()[0]
        start = time.monotonic()
        r = subprocess.run(command, cwd=folder, env=env, capture_output=True, text=True)
        wall = time.monotonic() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if r.returncode != 0:
        fail(f"{' '.join(command)} in {folder} exited {r.returncode}:\n{(r.stdout + r.stderr)[-1500:]}")
    return {"cpu": round(cpu, 2), "wall": round(wall, 2), "load": round(load, 2)}


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("revs", nargs="+", metavar="REV", help="revisions to compare (commits, branches)")
    p.add_argument("--rounds", type=int, default=5, help="rounds, each running every revision once (5)")
    p.add_argument("--steps", choices=["1", "all"], default="1", help="step 01 written, or every step (1)")
    p.add_argument("--kit-side-built", action="store_true",
                   help="the kit's side already built on the machine: only build/ is fresh in each run")
    args = p.parse_args(argv)
    if args.rounds < 1:
        p.error("--rounds must be at least 1")
    command = ["./kit", "check", "1"] if args.steps == "1" else ["./kit", "check"]
    with tempfile.TemporaryDirectory(prefix="cold-check-") as tmp:
        folders = {rev: clone(rev, Path(tmp), args.steps == "all") for rev in args.revs}
        runs: dict[str, list[dict]] = {rev: [] for rev in args.revs}
        caches = {rev: (Path(tmp) / f"cache-{rev.replace('/', '_')}") if args.kit_side_built else None
                  for rev in args.revs}
        for rev, cache in caches.items():
            if cache is not None:
                cache.mkdir()
                one_run(folders[rev], command, cache)      # fills it; not counted
        for round_ in range(args.rounds):
            order = args.revs if round_ % 2 == 0 else list(reversed(args.revs))
            for rev in order:
                run = one_run(folders[rev], command, caches[rev])
                runs[rev].append(run)
                print(json.dumps({"round": round_ + 1, "rev": rev, **run}), flush=True)
    first = statistics.median(r["cpu"] for r in runs[args.revs[0]])
    what = "kit's side built, fresh build/" if args.kit_side_built else "cold"
    print(f"\n{what}: `{' '.join(command)}`, {args.rounds} rounds interleaved; CPU seconds, median (all runs):")
    for rev, rs in runs.items():
        cpu = statistics.median(r["cpu"] for r in rs)
        each = ", ".join("%.2f" % r["cpu"] for r in rs)
        loads = [r["load"] for r in rs]
        print(f"  {rev:>12}  {cpu:6.2f}  x{cpu / first:.3f}  ({each}; load {min(loads):.1f}-{max(loads):.1f})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

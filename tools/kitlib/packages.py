"""The Debian packages the kit needs, in one table, and their installation with apt-get."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import time
from pathlib import Path

from .common import KitError, note
from .status import SETUP

# Debian package names each command needs. The first ./kit call installs what is
# missing (apt-get, non-interactive, with sudo when not root).
PACKAGES = {
    "build": ["cmake", "ninja-build", "g++", "libglm-dev", "doctest-dev", "libstb-dev", "pkg-config"],
    "sandbox": ["bubblewrap"],          # grading a folder the kit did not write (sandbox.py)
    "debug": ["gdb"],                   # ./kit debug
    # ./kit bench: Google Benchmark is needed; Embree (the comparison) and Google Highway (the
    # vector rows; Debian 12 and later) are installed when they can be, and skipped with a note.
    "bench": ["libbenchmark-dev"],
    "bench-embree": ["libembree-dev"],
    "bench-hwy": ["libhwy-dev"],
    "docs": ["doxygen", "graphviz", "doxygen-awesome-css"],
    # npm installs MathJax for ./kit docs. Node.js from elsewhere (nodesource) ships its own npm and
    # conflicts with Debian's npm package: this group is installed only when no npm is on the PATH.
    "node": ["nodejs", "npm"],
    "report": ["similarity-tester", "python3-matplotlib"],   # ./kit report: sim_c++, and its charts
    "browser": ["chromium"],            # the browser self-test of the docs
    "fuzz": ["clang", "libclang-rt-14-dev"],   # the fuzzing self-test (libFuzzer)
}


def instructor_groups() -> list[str]:
    """Every group ./kit test uses: all of them, Node.js only where npm is missing."""
    return [g for g in PACKAGES if g != "node" or shutil.which("npm") is None]


def missing_packages(names: list[str]) -> list[str]:
    if shutil.which("dpkg-query") is None:
        return []
    missing = []
    for name in names:
        r = subprocess.run(["dpkg-query", "-W", "-f=${Status}", name], capture_output=True, text=True)
        if r.returncode != 0 or "install ok installed" not in r.stdout:
            missing.append(name)
    return missing


APT_LISTS = Path("/var/lib/apt/lists")
APT_LISTS_MAX_AGE = 24 * 3600       # seconds: older package lists are refreshed before installing


def apt_lists_stale(lists: Path = APT_LISTS, max_age: float = APT_LISTS_MAX_AGE) -> bool:
    """True when apt has no package lists (a fresh container or minbase system) or the newest is
    older than `max_age`: installing from them would fail on versions the mirror no longer has."""
    try:
        ages = [p.stat().st_mtime for p in lists.iterdir() if p.name.endswith("Packages")
                or "_Packages." in p.name]
    except OSError:
        return True
    return not ages or time.time() - max(ages) > max_age


def apt_failure(stderr: str, names: list[str]) -> str:
    """One line naming the package apt could not install and why, from apt-get's own words."""
    errors = [l[2:].strip() for l in stderr.splitlines() if l.startswith("E:")]
    for name in names:
        for e in errors:
            if re.search(rf"(^|[\s'\"]){re.escape(name)}($|[\s'\":])", e):
                return f"{name}: {e}"
    # "Depends: ... but it is not going to be installed" lines name the package first.
    for l in stderr.splitlines():
        m = re.match(r"\s*(\S+) : Depends: (.*)", l)
        if m and m.group(1) in names:
            return f"{m.group(1)}: depends on {m.group(2).strip()}"
    if errors:
        return errors[-1]
    tail = [l for l in stderr.strip().splitlines() if l.strip()]
    return tail[-1] if tail else "apt-get failed without a message"


def ensure_packages(*groups: str) -> None:
    """Installs the Debian packages of `groups` that are missing, once, with apt-get.

    Root installs directly, anyone else through `sudo -n` (never a password prompt: the kit may
    run in CI or an editor). Without apt, or without the right to install, the user gets the one
    command to run. A failed install names the package and apt's reason.
    """
    names: list[str] = []
    for g in groups:
        names += [n for n in PACKAGES[g] if n not in names]
    missing = missing_packages(names)
    if not missing:
        return
    command = f"sudo apt-get update && sudo apt-get install -y {' '.join(missing)}"
    if shutil.which("apt-get") is None:
        raise KitError(f"missing packages: {' '.join(missing)}; install them (Debian names) and run ./kit again", SETUP)
    if os.geteuid() == 0:
        sudo: list[str] = []
    elif shutil.which("sudo") and subprocess.run(["sudo", "-n", "true"], capture_output=True).returncode == 0:
        sudo = ["sudo", "-n"]
    else:
        raise KitError(f"the kit needs {' '.join(missing)} and cannot install them (not root, no "
                       f"sudo without a password). Run:\n  {command}\nthen ./kit again", SETUP)
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    if apt_lists_stale():
        note("kit: updating the package lists (apt-get update)")
        up = subprocess.run(sudo + ["apt-get", "update", "-q"], env=env, capture_output=True, text=True)
        if up.returncode != 0:
            raise KitError(f"apt-get update failed: {apt_failure(up.stderr, [])}\nFix that, then run:\n"
                           f"  {command}", SETUP)
    note(f"kit: installing {' '.join(missing)} (once)")
    ok = subprocess.run(sudo + ["apt-get", "install", "-y", "-q", "--no-install-recommends"] + missing,
                        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if ok.returncode != 0:
        raise KitError(f"could not install the packages the kit needs.\n  {apt_failure(ok.stderr, missing)}\n"
                       f"Once that is fixed, run:\n  {command}", SETUP)

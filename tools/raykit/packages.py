"""The packages the kit needs, in one table, and their installation with apt-get.

PACKAGES names them as Debian does, per group. Where there is no apt or dpkg (macOS with Homebrew, a
Linux without apt, MSYS2), OTHER_MANAGERS gives each Debian name's Homebrew, vcpkg and MSYS2 names and
how to find it installed: the kit looks wherever CMake can (CMAKE_PREFIX_PATH, Homebrew's prefix as
`brew --prefix` says and its usual places /opt/homebrew and /usr/local, vcpkg's installed/<triplet>
under $VCPKG_ROOT, MacPorts' /opt/local, /usr), installs nothing, names what is missing with the
student's own platform's package manager only (Homebrew on a Mac or where `brew` is, MSYS2 on
Windows, the plain names elsewhere; never Debian's names), and passes the prefixes it found to CMake
in CMAKE_PREFIX_PATH. stb (two headers) is needed only by ./kit render ("render" group), never by
./kit check.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from .common import KitError, note
from .status import SETUP

# Debian package names each command needs, per group, with who needs them: the one list. The first
# ./kit call installs what is missing of its command's groups (apt-get, non-interactive, with sudo when
# not root); ./kit test installs every group but those of CI_ONLY first; .ci/run installs all of them
# (`python3 -m raykit.packages --ci`, from tools/, prints the list) and has none of its own.
PACKAGES = {
    "build": ["cmake", "ninja-build", "g++", "libglm-dev", "doctest-dev", "libstb-dev"],   # every command
    "render": ["libstb-dev"],           # ./kit render's PNG reader and writer, two headers (in "build" too where apt is)
    "sandbox": ["bubblewrap"],          # grading a folder the kit did not write (sandbox/)
    "debug": ["gdb"],                   # ./kit debug
    # ./kit debug where there is no gdb (a Mac); the self-tests debug (lldb) and reach (mac) use it here.
    "lldb": ["lldb"],
    # ./kit bench: Google Benchmark is needed; Embree (the comparison) and Google Highway (the
    # vector rows; Debian 12 and later, found with pkg-config) are installed when they can be, and
    # skipped with a note.
    "bench": ["libbenchmark-dev"],
    "bench-embree": ["libembree-dev"],
    "bench-hwy": ["libhwy-dev", "pkg-config"],
    "docs": ["doxygen", "graphviz", "doxygen-awesome-css"],
    # npm installs MathJax for ./kit docs. Node.js from elsewhere (nodesource) ships its own npm and
    # conflicts with Debian's npm package: this group is installed only when no npm is on the PATH.
    "node": ["nodejs", "npm"],
    # ./kit report: sim_c++, and jinja2 for its pages' templates (its charts are drawn by charts.py)
    "report": ["similarity-tester", "python3-jinja2"],
    "browser": ["chromium"],            # the browser self-test of the docs, the slides' PDF, the lab
    "fuzz": ["clang", "libclang-rt-14-dev"],   # the fuzzing self-test (libFuzzer)
    # A Mac's standard library on Linux (clang++ -stdlib=libc++): the self-tests check (portable by
    # construction, one verdict on libc++ and libstdc++) and reach (mac).
    "libcxx": ["clang", "libc++-dev", "libc++abi-dev"],
    # Debian's own python3 with YAML and JSON Schema: the self-tests docs (the workflows parse) and
    # reach (Classroom's workflow, PrairieLearn's schemas), which run /usr/bin/python3.
    "schemas": ["python3", "python3-yaml", "python3-jsonschema"],
    # The linters, the self-test lint: pyflakes on the kit's Python, clang-format on the student-side C++.
    "lint": ["pyflakes3", "clang-format"],
    # ./kit test: the self-test (tests/kit/) is a pytest suite; xdist runs its quick tier in processes.
    "selftest": ["python3-pytest", "python3-pytest-xdist"],
    # tools/portability/run (CI, and by hand): fresh Debian roots. Not a ./kit command's.
    "portability": ["debootstrap"],
}
# Groups ./kit test does not install: they serve a tool outside the kit's commands.
CI_ONLY = ["portability"]


def instructor_groups() -> list[str]:
    """Every group ./kit test uses: all of them but CI_ONLY, Node.js only where npm is missing."""
    return [g for g in PACKAGES if g not in CI_ONLY and (g != "node" or shutil.which("npm") is None)]


def ci_packages() -> list[str]:
    """Every package of every group, once, in the table's order: what .ci/run installs (Node.js only
    where npm is missing, as for ./kit test)."""
    groups = instructor_groups() + CI_ONLY
    return list(dict.fromkeys(n for g in groups for n in PACKAGES[g]))


@dataclass(frozen=True)
class Elsewhere:
    """A Debian package as other package managers name it, and how to see it is installed."""
    what: str           # what it is, in the messages of a machine without apt
    brew: str           # Homebrew formula ("" when it has none)
    vcpkg: str          # vcpkg port ("" for a tool vcpkg does not ship)
    msys2: str          # MSYS2 (UCRT64) package
    probe: str          # "tool:NAME|NAME", "compiler", "cmake:PACKAGE" (a CMake config), "header:FILE"
    render_only: bool = False   # needed by ./kit render, not by ./kit check


OTHER_MANAGERS = {
    "cmake": Elsewhere("CMake", "cmake", "", "mingw-w64-ucrt-x86_64-cmake", "tool:cmake"),
    "ninja-build": Elsewhere("Ninja", "ninja", "", "mingw-w64-ucrt-x86_64-ninja", "tool:ninja|make"),
    "g++": Elsewhere("a C++17 compiler", "", "", "mingw-w64-ucrt-x86_64-gcc", "compiler"),
    "libglm-dev": Elsewhere("GLM", "glm", "glm", "mingw-w64-ucrt-x86_64-glm", "cmake:glm"),
    "doctest-dev": Elsewhere("doctest", "doctest", "doctest", "mingw-w64-ucrt-x86_64-doctest", "cmake:doctest"),
    # Two headers, stb_image.h and stb_image_write.h (the kit compiles their implementation), in a
    # prefix's include/ (Homebrew taps, vcpkg, a copied folder) or include/stb/ (Debian).
    "libstb-dev": Elsewhere("stb's headers (stb_image.h, stb_image_write.h)", "", "stb",
                            "mingw-w64-ucrt-x86_64-stb", "header:stb_image_write.h", True),
}
# Where CMake and Homebrew put packages, searched after $CMAKE_PREFIX_PATH, Homebrew's own prefix
# and vcpkg's, in this order.
PREFIXES = ["/opt/homebrew", "/usr/local", "/opt/local", "/usr"]
STB_PAGE = "https://github.com/nothings/stb"


def has_apt() -> bool:
    return shutil.which("dpkg-query") is not None and shutil.which("apt-get") is not None


def family() -> str:
    """Whose package names a message gives: "brew" on macOS or wherever Homebrew's `brew` is,
    "msys2" on Windows (MSYS2's shell), "apt" where apt is, else "plain" (a Linux without apt)."""
    if sys.platform == "darwin" or shutil.which("brew"):
        return "brew"
    if sys.platform in ("win32", "cygwin", "msys") or os.environ.get("MSYSTEM"):
        return "msys2"
    return "apt" if has_apt() else "plain"


_brew_prefix: list[Path | None] = []


def brew_prefix() -> Path | None:
    """Homebrew's prefix: $HOMEBREW_PREFIX, else what `brew --prefix` says (a home folder's
    Homebrew, a Linux one), asked once."""
    if os.environ.get("HOMEBREW_PREFIX"):
        return Path(os.environ["HOMEBREW_PREFIX"])
    if not _brew_prefix:
        found = None
        brew = shutil.which("brew")
        if brew:
            try:
                r = subprocess.run([brew, "--prefix"], capture_output=True, text=True, timeout=30)
                line = r.stdout.strip().splitlines()[-1] if r.returncode == 0 and r.stdout.strip() else ""
                found = Path(line) if line.startswith("/") else None
            except (OSError, subprocess.TimeoutExpired):
                found = None
        _brew_prefix.append(found)
    return _brew_prefix[0]


def vcpkg_prefixes() -> list[Path]:
    """vcpkg's installed/<triplet> folders under $VCPKG_ROOT (or $VCPKG_INSTALLATION_ROOT)."""
    root = os.environ.get("VCPKG_ROOT") or os.environ.get("VCPKG_INSTALLATION_ROOT")
    if not root:
        return []
    return sorted(p for p in (Path(root) / "installed").glob("*") if (p / "include").is_dir())


def prefixes() -> list[Path]:
    found = [Path(p) for p in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep) if p]
    brew = brew_prefix()
    found += ([brew] if brew else []) + vcpkg_prefixes()
    return [p for p in dict.fromkeys(found + [Path(p) for p in PREFIXES]) if p.is_dir()]


def cmake_config_prefix(package: str) -> Path | None:
    """The prefix holding `package`'s CMake config file, where find_package(CONFIG) looks
    (<prefix>/{lib,lib64,lib/<arch>,share}/cmake/<name>*/ and <prefix>/share/<name>*/)."""
    names = {f"{package}Config.cmake", f"{package.lower()}-config.cmake"}
    for prefix in prefixes():
        for pattern in ("lib/cmake/*/", "lib64/cmake/*/", "lib/*/cmake/*/", "share/cmake/*/", "share/*/cmake/",
                        "share/*/", "lib/cmake/"):
            for folder in prefix.glob(pattern):
                if folder.name.lower().startswith(package.lower()) or pattern.endswith("cmake/"):
                    if any((folder / n).is_file() for n in names):
                        return prefix
    return None


def header_prefix(name: str) -> Path | None:
    """The prefix whose include/ or include/stb/ holds the header `name` (stb's layouts: Homebrew
    taps and vcpkg put stb's headers in include/, Debian in include/stb/), as CMake's find_path
    with PATH_SUFFIXES stb finds it (tools/render/CMakeLists.txt)."""
    for prefix in prefixes():
        for folder in (prefix / "include", prefix / "include" / "stb"):
            if (folder / name).is_file():
                return prefix
    return None


def probe(elsewhere: Elsewhere) -> Path | bool:
    kind, _, what = elsewhere.probe.partition(":")
    if kind == "tool":
        return any(shutil.which(t) for t in what.split("|"))
    if kind == "compiler":
        cxx = os.environ.get("CXX", "")
        return bool(cxx and shutil.which(cxx.split()[0])) or any(shutil.which(c) for c in ("c++", "g++", "clang++"))
    if kind == "cmake":
        return cmake_config_prefix(what) or False
    if kind == "header":
        return header_prefix(what) or False
    raise ValueError(elsewhere.probe)


def install_line(debian: str, brew: str) -> str:
    """The one command that installs a tool on this machine, in its own package manager's words
    (`debian` and `brew` are the tool's names there; MSYS2's is Homebrew's, prefixed)."""
    kind = family()
    if kind == "brew":
        return f"brew install {brew}"
    if kind == "msys2":
        return f"pacman -S mingw-w64-ucrt-x86_64-{brew}"
    if kind == "apt":
        return f"sudo apt-get install {debian}"
    return f"install {brew} with your system's package manager"


def install_hint(missing: list[str]) -> str:
    """The commands that install `missing` (Debian names) with the package manager of this
    machine (family()): Homebrew's words on a Mac, MSYS2's on Windows, plain ones on a
    Linux without apt; vcpkg's (which runs everywhere) after them."""
    kind = family()
    rows = [OTHER_MANAGERS[n] for n in missing]
    lines = []
    if kind == "msys2":
        lines.append(f"  pacman -S {' '.join(r.msys2 for r in rows)}")
    elif kind == "brew":
        brew = [r.brew for r in rows if r.brew]
        if brew:
            lines.append(f"  brew install {' '.join(brew)}")
        if "g++" in missing:
            lines.append("  a C++17 compiler: " + ("xcode-select --install (Apple clang)" if sys.platform == "darwin"
                                                   else "brew install llvm, or your system's clang++ or g++"))
        if "libstb-dev" in missing:
            where = brew_prefix()
            lines.append(f"  stb has no Homebrew formula: copy stb_image.h and stb_image_write.h from {STB_PAGE} "
                         f"into {where / 'include' if where else '$(brew --prefix)/include'}/")
    else:
        lines.append("  with your system's package manager: " + ", ".join(r.what for r in rows))
        if "libstb-dev" in missing:
            lines.append(f"  (stb's two headers, from {STB_PAGE}, may also be copied into any prefix's include/ "
                         "named in CMAKE_PREFIX_PATH)")
    vcpkg = [r.vcpkg for r in rows if r.vcpkg]
    if vcpkg and kind != "msys2":
        lines.append(f"  or vcpkg: vcpkg install {' '.join(vcpkg)} (found under $VCPKG_ROOT/installed/<triplet>)")
    return "\n".join(lines)


def ensure_elsewhere(names: list[str]) -> None:
    """Without apt: finds the packages of `names`, installs nothing, names what is missing, and
    puts the prefixes where the libraries were found into CMAKE_PREFIX_PATH for CMake."""
    missing, found = [], []
    for name in names:
        row = OTHER_MANAGERS.get(name)
        if row is None:
            continue            # a Debian-only extra (the sandbox, the docs): its command says so
        where = probe(row)
        if not where:
            missing.append(name)
        elif isinstance(where, Path) and str(where) not in ("/usr", "/"):
            found.append(str(where))
    if found:
        current = [p for p in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep) if p]
        os.environ["CMAKE_PREFIX_PATH"] = os.pathsep.join(dict.fromkeys(current + found))
    if missing:
        words = ", ".join(OTHER_MANAGERS[n].what for n in missing)
        looked = ", ".join(str(p) for p in prefixes()) or "none of the usual prefixes exists"
        raise KitError(f"the kit needs {words}, and there is no apt here to install "
                       f"{'it' if len(missing) == 1 else 'them'}. Install with:\n{install_hint(missing)}\n"
                       f"then run ./kit again (looked for in $CMAKE_PREFIX_PATH and {looked})", SETUP)


def missing_packages(names: list[str]) -> list[str]:
    if shutil.which("dpkg-query") is None or not names:
        return []
    # One dpkg-query for all of them (one a package took 0.4 s of every ./kit check): it prints
    # the packages it knows, and exits non-zero when one is unknown, which is then missing too.
    r = subprocess.run(["dpkg-query", "-W", "-f=${Package}\t${Status}\n", *names], capture_output=True, text=True)
    installed = {name.split(":")[0] for name, _, status in (line.partition("\t") for line in r.stdout.splitlines())
                 if "install ok installed" in status}
    return [n for n in names if n not in installed]


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
    names = list(dict.fromkeys(n for g in groups for n in PACKAGES[g]))
    if not has_apt():   # macOS, or a Linux without apt: look, never install; stb only for render
        render = "render" in groups
        ensure_elsewhere([n for n in names if n not in OTHER_MANAGERS or render
                          or not OTHER_MANAGERS[n].render_only])
        return
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


def main(argv: list[str]) -> int:
    import argparse
    p = argparse.ArgumentParser(prog="python3 -m raykit.packages",
                                description="The Debian packages the kit needs (tools/raykit/packages.py).")
    p.add_argument("--ci", action="store_true", help="every package .ci/run installs, one a line")
    p.add_argument("--groups", action="store_true", help="each group and its packages")
    args = p.parse_args(argv)
    if args.groups:
        for g, names in PACKAGES.items():
            print(f"{g}: {' '.join(names)}")
    else:
        print("\n".join(ci_packages()))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

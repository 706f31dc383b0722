"""Self-test: the linters CI runs, and CI's one package list.

- pyflakes (Debian's pyflakes3) on every Python file of the kit: no unused import or name, no undefined
  name, no f-string without a placeholder. A package that re-exports its parts names them in __all__.
- clang-format (the root's .clang-format) on the student-side C++: the committed stubs of steps/ (as a
  handout ships them, never the working tree's, where an instructor may keep answers) and solutions/.
  The style is the one the kit's files were written in, so the check passes without reformatting them,
  and a reformatted solution would change the bundle's key and could stop the mutants' patches applying.
- README.md is a door: at most 150 lines of at most 120 characters, pointing to the pages behind it.
- .ci/run has no package list of its own: it installs what tools/raykit/packages.py prints; GitHub's
  workflow .github/workflows/ci.yml runs it as is (not run here: no GitHub runner).

Each check is shown to fail on a planted flaw. Builds nothing: the quick tier.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

from raykit.common import ROOT
from .support import Skipped, expect, need_solutions

FORMAT = ROOT / ".clang-format"


def python_files() -> list[Path]:
    """The kit's Python: every .py file, and the scripts whose first line runs python, outside build/."""
    skip = {"build", ".git", "node_modules", "__pycache__"}
    found = []
    for p in sorted(ROOT.rglob("*")):
        rel = p.relative_to(ROOT)
        if not p.is_file() or skip & set(rel.parts) or rel.parts[0] in ("steps", "solutions"):
            continue
        if p.suffix == ".py":
            found.append(p)
        elif not p.suffix and p.stat().st_size < 1_000_000:
            with p.open("rb") as f:
                if re.match(rb"#!\S*(python3?|env python3?)\b", f.readline()):
                    found.append(p)
    return found


def pyflakes(paths: list[Path]) -> subprocess.CompletedProcess:
    return subprocess.run(["pyflakes3", *map(str, paths)], capture_output=True, text=True, timeout=300)


@pytest.mark.quick
def selftest_pyflakes(ctx) -> str:
    """pyflakes finds nothing in the kit's Python; an unused import and an undefined name planted in a
    scratch file are found."""
    if shutil.which("pyflakes3") is None:
        raise Skipped("pyflakes3 is not installed (packages.py's lint group; ./kit test installs it)")
    files = python_files()
    expect(len(files) > 50 and any(p.name == "cli.py" for p in files),
           f"found only {len(files)} Python files of the kit")
    r = pyflakes(files)
    found = [line.replace(str(ROOT) + "/", "") for line in r.stdout.splitlines() if line.strip()]
    expect(r.returncode == 0 and not found, f"pyflakes3 ({len(found)}): " + "\n  ".join(found[:20] or [r.stderr[-400:]]))
    with tempfile.TemporaryDirectory() as tmp:
        planted = Path(tmp) / "planted.py"
        planted.write_text("import os\n\n\ndef f():\n    return undefined_name\n")
        r = pyflakes([planted])
        expect(r.returncode != 0 and "'os' imported but unused" in r.stdout and "undefined_name" in r.stdout,
               f"pyflakes3 missed a planted unused import and undefined name: {r.stdout}{r.stderr}")
    return f"{len(files)} Python files clean; a planted unused import and undefined name found"


def committed_stubs() -> dict[str, bytes]:
    """steps/'s C++ as committed (as a handout ships it), or as it is where there is no git history."""
    from kitlib.commands import handout as cmd_handout
    try:
        files = cmd_handout.committed_steps()
    except Exception:       # no git, or not a repository: a copy of the kit
        files = {p.relative_to(ROOT).as_posix(): p.read_bytes() for p in sorted((ROOT / "steps").rglob("*"))
                 if p.is_file()}
    return {k: v for k, v in files.items() if k.endswith((".cpp", ".hpp", ".h"))}


def format_problems(name: str, data: bytes) -> str:
    """clang-format's complaint about `data` as the file `name` under the kit's .clang-format, "" if none."""
    r = subprocess.run(["clang-format", "--dry-run", "--Werror", f"--style=file:{FORMAT}",
                        f"--assume-filename={ROOT / name}"], input=data, capture_output=True, timeout=60)
    if r.returncode == 0:
        return ""
    err = r.stderr.decode(errors="replace").replace("<stdin>", name)
    return err.strip().splitlines()[0] if err.strip() else f"clang-format exit {r.returncode}"


@pytest.mark.quick
def selftest_clang_format(ctx) -> str:
    """The committed stubs and the solutions are as .clang-format says (clang-format --dry-run --Werror);
    a stub with its spacing changed is caught."""
    need_solutions()
    if shutil.which("clang-format") is None:
        raise Skipped("clang-format is not installed (packages.py's lint group; ./kit test installs it)")
    expect(FORMAT.is_file(), "no .clang-format at the kit's root")
    files = committed_stubs()
    stubs = len(files)
    files.update({p.relative_to(ROOT).as_posix(): p.read_bytes() for p in sorted((ROOT / "solutions").rglob("*"))
                  if p.is_file() and p.suffix in (".cpp", ".hpp", ".h")})
    expect(stubs > 0 and len(files) > stubs, f"{stubs} stubs and {len(files) - stubs} solution files found")
    bad = [f"{name}: {why}" for name, data in files.items() if (why := format_problems(name, data))]
    expect(not bad, "not as .clang-format says (clang-format -i FILE fixes it):\n  " + "\n  ".join(bad[:10]))
    name, data = next(iter(files.items()))
    spoiled = re.sub(rb"\) \{", b"){", data, count=1)
    expect(spoiled != data and format_problems(name, spoiled), f"a planted '){{' in {name} is not caught")
    return f"{stubs} committed stubs and {len(files) - stubs} solution files as .clang-format says; a planted slip caught"


def named(code: str, every: set[str]) -> list[str]:
    """The packages of `every` that `code` names as words (python3 aside: .ci/run installs it first, to
    read the list)."""
    return sorted(n for n in every - {"python3"} if re.search(rf"(?<![\w.+-]){re.escape(n)}(?![\w.+-])", code))


@pytest.mark.quick
def selftest_ci_packages(ctx) -> str:
    """.ci/run installs the list tools/raykit/packages.py prints and names no package of its own; the
    list holds every group's packages (a group added is installed by CI without touching .ci/run)."""
    from raykit import packages
    run = ROOT / ".ci" / "run"
    if not run.is_file():
        raise Skipped("no .ci/run here")
    code = "\n".join(line.split("#", 1)[0] for line in run.read_text().splitlines())
    expect("raykit.packages --ci" in code, ".ci/run does not install from tools/raykit/packages.py")
    every = {n for names in packages.PACKAGES.values() for n in names}
    own = named(code, every)
    expect(not own, f".ci/run names packages of its own: {', '.join(own)} (put them in packages.py)")
    listed = set(packages.ci_packages())
    missing = sorted(every - listed - ({"nodejs", "npm"} if shutil.which("npm") else set()))
    expect(not missing, f"python3 -m raykit.packages --ci leaves out {', '.join(missing)}")
    r = subprocess.run(["python3", "-B", "-m", "raykit.packages", "--ci"], cwd=ROOT / "tools", capture_output=True,
                       text=True, timeout=60)
    expect(r.returncode == 0 and set(r.stdout.split()) == listed,
           f"python3 -m raykit.packages --ci printed {r.stdout[:200]!r} {r.stderr[-300:]}")
    planted = code + "\napt-get install -y libc++-dev g++ lldb  # a list of its own\n"
    expect(named(planted, every) == ["g++", "libc++-dev", "lldb"],
           f"a list planted in .ci/run is read as {named(planted, every)}")
    flow = ROOT / ".github" / "workflows" / "ci.yml"      # GitHub's way in: .ci/run as is (not run here)
    text = flow.read_text() if flow.is_file() else ""
    expect(re.search(r"^\s*run: \.ci/run\s*$", text, re.M) and "NOT RUN" in text,
           f"{flow.relative_to(ROOT)} does not run .ci/run, or does not say it is not run here")
    return (f".ci/run installs the {len(listed)} packages packages.py prints, and names none of its own; "
            "ci.yml runs it")


README_LINES, README_WIDTH = 150, 120
README_LINKS = ["docs/students.md", "docs/instructors.md", "docs/integrity.md", "CONTRIBUTING.md"]


def readme_problems(text: str) -> list[str]:
    """What keeps a README from being a door: its length, its long lines, a page it must point to."""
    lines = text.splitlines()
    found = [f"{len(lines)} lines (at most {README_LINES})"] if len(lines) > README_LINES else []
    found += [f"line {i} has {len(line)} characters (at most {README_WIDTH})"
              for i, line in enumerate(lines, 1) if len(line) > README_WIDTH]
    found += [f"no link to {page}" for page in README_LINKS if f"]({page}" not in text]
    found += [f"{page} does not exist" for page in README_LINKS if not (ROOT / page).is_file()]
    found += ["the quick start does not offer ./kit test --quick"] if "./kit test --quick" not in text else []
    return found


@pytest.mark.quick
def selftest_readme_door(ctx) -> str:
    """README.md is a door (issue 56): at most 150 lines of at most 120 characters, pointing to the
    students' and instructors' pages, integrity and CONTRIBUTING, and offering ./kit test --quick; a
    long line and a lost link planted in a copy are caught."""
    text = (ROOT / "README.md").read_text()
    bad = readme_problems(text)
    expect(not bad, "README.md: " + "; ".join(bad))
    planted = text.replace("](docs/instructors.md", "](docs/manual.md") + "x" * (README_WIDTH + 1) + "\n"
    caught = readme_problems(planted)
    expect(len(caught) >= 2, f"a long line and a lost link planted in the README: {caught}")
    return f"{len(text.splitlines())} lines, none over {README_WIDTH} characters, the four pages linked"

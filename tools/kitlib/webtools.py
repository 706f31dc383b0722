"""The web pages' tools: Doxygen, and the npm packages the site and the decks use (MathJax,
reveal.js), installed once into build/docs/npm at the versions docs/package-lock.json pins. Below
both `./kit docs` (commands/docs.py) and the decks (decks.py), which import it; it imports neither.
Also the site's page names (page_id), which ./kit prairielearn links to."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

from raykit.common import BUILD, ROOT, KitError, note
from raykit.packages import ensure_packages, install_line
from raykit.status import FAILED, SETUP

DOCS = ROOT / "docs"
NPM_DIR = BUILD / "docs" / "npm"
NPM_ATTEMPTS = 2


def page_id(path: Path) -> str:
    """The name Doxygen 1.9 gives the page of a Markdown file: md_ and its path, non-word characters as _
    (the site's page is this and .html)."""
    rel = path.resolve().relative_to(ROOT).with_suffix("")
    return "md_" + re.sub(r"[^A-Za-z0-9_\x80-\uffff]", "_", rel.as_posix())


def ensure_docs_tools() -> None:
    ensure_packages("docs")
    if shutil.which("npm") is None:
        ensure_packages("node")
        if shutil.which("npm") is None:
            raise KitError(f"npm is not on the PATH; install it: {install_line('nodejs npm', 'node')}", SETUP)
    if shutil.which("doxygen") is None:
        raise KitError(f"doxygen is not on the PATH; install it: {install_line('doxygen', 'doxygen')}", SETUP)


def pinned_versions() -> dict[str, str]:
    """The npm packages docs/package-lock.json pins at the top of node_modules, and their versions."""
    lock = json.loads((DOCS / "package-lock.json").read_text())
    return {k[len("node_modules/"):]: v["version"] for k, v in lock["packages"].items()
            if k.startswith("node_modules/") and k.count("node_modules/") == 1}


def npm_package(name: str, needed: str, what: str) -> Path:
    """A package of docs/package.json (MathJax, reveal.js), installed once into build/docs/npm at the
    versions docs/package-lock.json pins; `needed` is a file it must have."""
    wanted = pinned_versions()
    root = NPM_DIR / "node_modules" / name

    def installed(pkg: str) -> str | None:
        try:
            return json.loads((NPM_DIR / "node_modules" / pkg / "package.json").read_text())["version"]
        except (OSError, ValueError, KeyError):
            return None

    if all(installed(p) == v for p, v in wanted.items()) and (root / needed).is_file():
        return root
    NPM_DIR.mkdir(parents=True, exist_ok=True)
    for f in ("package.json", "package-lock.json"):
        shutil.copyfile(DOCS / f, NPM_DIR / f)
    versions = ", ".join(f"{p} {v}" for p, v in sorted(wanted.items()))
    note(f"kit: installing {versions} with npm into {NPM_DIR.relative_to(ROOT)} (once)")
    # Twice at most: npm retries each request itself, but an install the network failed anyway is
    # tried once more before a docs build (or CI) fails on it.
    for attempt in range(NPM_ATTEMPTS):
        r = subprocess.run(["npm", "ci", "--no-audit", "--no-fund", "--ignore-scripts", "--loglevel=error"],
                           cwd=NPM_DIR, capture_output=True, text=True)
        if r.returncode == 0 and (root / needed).is_file():
            return root
        if attempt + 1 < NPM_ATTEMPTS:
            said = (r.stdout + r.stderr).strip().splitlines()
            note(f"kit: npm failed ({said[-1] if said else f'exit {r.returncode}'}); trying once more")
    raise KitError(f"npm could not install {name}, which {what} "
                   f"(it needs the npm registry once):\n{(r.stdout + r.stderr)[-1500:]}", FAILED)


def copy_parts(package: Path, parts: list[str], dest: Path) -> None:
    """The files and folders `parts` of an npm package, copied into `dest` under the same paths."""
    for rel in parts:
        src, dst = package / rel, dest / rel
        dst.parent.mkdir(parents=True, exist_ok=True)
        (shutil.copytree if src.is_dir() else shutil.copyfile)(src, dst)


def swap_in(work: Path, final: Path) -> None:
    """The folder `work` becomes `final`; the old one stays whole until the new one is."""
    old = final.with_name(final.name + ".old")
    shutil.rmtree(old, ignore_errors=True)
    if final.exists():
        final.rename(old)
    work.rename(final)
    shutil.rmtree(old, ignore_errors=True)

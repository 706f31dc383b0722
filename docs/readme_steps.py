#!/usr/bin/env python3
"""README.md's table of the steps, written from the steps' manifests (tests/NN_topic/step.json).

Each row is a step: its number, what the student writes (step.json's "summary", else its title) and the
picture it takes part in (its first scene's docs/images/SCENE.png, the one the docs' front page shows;
a step without a scene says so). The header names the step whose `render` draws every picture. The
table sits between `<!-- readme_steps.py -->` and `<!-- /readme_steps.py -->` in README.md; a step
added as CONTRIBUTING.md says gets its row from this script, and `./kit test` fails while the table
and the manifests disagree.

    python3 docs/readme_steps.py           rewrite the table
    python3 docs/readme_steps.py --check   exit 1, saying so, if a rewrite would change it
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
BLOCK = re.compile(r"(<!-- readme_steps\.py -->\n)(.*?)(<!-- /readme_steps\.py -->)", re.S)


def manifests(root: Path = ROOT) -> list[tuple[str, dict]]:
    return [(p.parent.name, json.loads(p.read_text())) for p in sorted((root / "tests").glob("[0-9][0-9]_*/step.json"))]


def table(root: Path = ROOT) -> str:
    steps = manifests(root)
    drawer = next((folder[:2] for folder, m in steps if "render" in [f["name"] if isinstance(f, dict) else f for f in m.get("functions", [])]), None)
    header = ("its picture" + (f" (drawn with your step {drawer}'s camera and loop, so once step "
                               f"{drawer} is written)" if drawer else ""))
    lines = [f"| step | what you write | {header} |", "|---|---|---|"]
    links = []
    for folder, m in steps:
        what = m.get("summary") or m["title"]
        scenes = m.get("scenes") or []
        image = root / "docs" / "images" / f"{scenes[0]['name']}.png" if scenes else None
        # The picture by reference, its path below the table: a row stays within the README's 120 columns.
        picture = (f"![{scenes[0].get('about') or m['title']}][step-{folder[:2]}]" if image and image.is_file()
                   else m.get("picture_note") or "(no picture of its own)")
        if image and image.is_file():
            links.append(f"[step-{folder[:2]}]: docs/images/{image.name}")
        lines.append(f"| {folder[:2]} | {what} | {picture} |")
    return "\n".join(lines + ([""] + links if links else [])) + "\n"


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--check", action="store_true", help="exit 1 if the table is stale; write nothing")
    args = p.parse_args(argv)
    text = README.read_text()
    m = BLOCK.search(text)
    if not m:
        print(f"{README.name}: no <!-- readme_steps.py --> ... <!-- /readme_steps.py --> block", file=sys.stderr)
        return 2
    new = text[:m.start(2)] + table() + text[m.end(2):]
    if args.check:
        if new != text:
            print("README.md's step table is stale: run python3 docs/readme_steps.py", file=sys.stderr)
            return 1
        return 0
    if new != text:
        README.write_text(new)
        print("rewrote README.md's step table")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

#!/usr/bin/env python3
"""Lecture 05's tables of the empty Cornell box, written from the scene file.

include/raykit/scenes/cornell_box.inc holds the box's numbers once; the solution's colours and camera,
the step 05 suites, the renderer's palette and these tables read it. This script rewrites the blocks
between `<!-- scene_tables.py: NAME -->` and `<!-- /scene_tables.py -->` in lectures/05-cornell-box.md:
`rects` (the six Rects and their colours), `colors` (the flat colours) and `camera` (its sentence).

    python3 docs/scene_tables.py           rewrite the blocks
    python3 docs/scene_tables.py --check   exit 1, naming the stale blocks, if a rewrite would change them
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "include" / "raykit" / "scenes" / "cornell_box.inc"
LECTURE = ROOT / "lectures" / "05-cornell-box.md"
BLOCK = re.compile(r"(<!-- scene_tables\.py: (\w+) -->\n)(.*?)(<!-- /scene_tables\.py -->)", re.S)


class SceneError(Exception):
    pass


def number(text: str) -> str:
    """A float literal as the lecture writes it: 548.8f -> 548.8, 556.0f -> 556, 1.0f -> 1."""
    t = text.strip().rstrip("fF")
    try:
        value = float(t)
    except ValueError:
        raise SceneError(f"{SCENE.name}: not a number: {text!r}") from None
    return f"{value:.6g}"


def read(path: Path = SCENE) -> dict:
    colors, objects, camera = {}, [], None
    for n, line in enumerate(path.read_text().splitlines(), 1):
        m = re.match(r"\s*RAYKIT_SCENE_(COLOR|OBJECT|CAMERA)\((.*)\)\s*$", line)
        if not m or line.lstrip().startswith("#"):
            continue
        kind, args = m.group(1), [a.strip() for a in re.split(r",(?=(?:[^\"]*\"[^\"]*\")*[^\"]*$)", m.group(2))]
        if kind == "COLOR" and len(args) == 4 and args[0] != "name":
            colors[args[0]] = [number(a) for a in args[1:]]
        elif kind == "OBJECT" and len(args) == 8 and args[0].startswith('"'):
            objects.append({"name": args[0].strip('"'), "axis": args[1], "offset": number(args[2]),
                            "lo": (number(args[3]), number(args[4])), "hi": (number(args[5]), number(args[6])),
                            "color": args[7]})
        elif kind == "CAMERA" and len(args) == 11 and not args[0].startswith("e"):
            camera = [number(a) for a in args]
        elif args and args[0] not in ("name", "label") and not args[0].startswith("e"):
            raise SceneError(f"{path.name}:{n}: unreadable entry: {line.strip()}")
    if not colors or len(objects) != 6 or camera is None:
        raise SceneError(f"{path.name}: expected colours, six objects and a camera; found {len(colors)} colours, "
                         f"{len(objects)} objects, {'a' if camera else 'no'} camera")
    for o in objects:
        if o["color"] not in colors:
            raise SceneError(f"{path.name}: {o['name']} has the colour {o['color']}, which is not defined")
    return {"colors": colors, "objects": objects, "camera": camera}


def blocks(scene: dict) -> dict[str, str]:
    rows = ["| name | axis | offset | lo | hi | colour |", "|---|---|---|---|---|---|"]
    for o in scene["objects"]:
        c = o["color"] if o["color"] != "light" else "(" + ", ".join(scene["colors"]["light"]) + ")"
        rows.append(f"| `\"{o['name']}\"` | {o['axis']} | {o['offset']} | ({o['lo'][0]}, {o['lo'][1]}) | "
                    f"({o['hi'][0]}, {o['hi'][1]}) | {c} |")
    colors = ["| surface | red | green | blue |", "|---|---|---|---|"]
    colors += [f"| {name} | {' | '.join(f'{float(v):.2f}' if name != 'light' else v for v in rgb)} |"
               for name, rgb in scene["colors"].items()]
    e = scene["camera"]
    camera = (f"The camera: position $({e[0]}, {e[1]}, {e[2]})$, looking along $({e[3]}, {e[4]}, {e[5]})$ with "
              f"up $({e[6]}, {e[7]}, {e[8]})$, focal length\n{e[9]} and a film of ${e[10]} \\times {e[10]}$ (metres).")
    return {"rects": "\n".join(rows) + "\n", "colors": "\n".join(colors) + "\n", "camera": camera + "\n"}


def rewritten(text: str, fresh: dict[str, str]) -> tuple[str, list[str]]:
    """The lecture's text with every block rewritten, and the names of the blocks that changed."""
    changed, seen = [], set()

    def sub(m):
        name = m.group(2)
        if name not in fresh:
            raise SceneError(f"{LECTURE.name}: unknown block {name!r}")
        seen.add(name)
        if m.group(3) != fresh[name]:
            changed.append(name)
        return m.group(1) + fresh[name] + m.group(4)

    out = BLOCK.sub(sub, text)
    missing = sorted(set(fresh) - seen)
    if missing:
        raise SceneError(f"{LECTURE.name}: no block for {', '.join(missing)}")
    return out, changed


def stale(scene_path: Path = SCENE, lecture: Path = LECTURE) -> list[str]:
    return rewritten(lecture.read_text(), blocks(read(scene_path)))[1]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="only say which blocks are stale (exit 1 if any)")
    args = ap.parse_args(argv)
    try:
        text = LECTURE.read_text()
        out, changed = rewritten(text, blocks(read()))
    except (SceneError, OSError) as e:
        print(f"scene_tables.py: {e}", file=sys.stderr)
        return 2
    if args.check:
        if changed:
            print(f"scene_tables.py: stale in {LECTURE.relative_to(ROOT)}: {', '.join(changed)}")
            return 1
        return 0
    if changed:
        tmp = LECTURE.with_suffix(".md.tmp")
        tmp.write_text(out)
        tmp.replace(LECTURE)
    print(f"scene_tables.py: {len(changed)} of 3 blocks rewritten in {LECTURE.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The pictures of docs/pitfalls.md, committed so that they show on a forge's web view and in a checkout.

    python3 docs/pitfall_pictures.py           # draw them into docs/pitfalls/ (after a change to the drawing)
    python3 docs/pitfall_pictures.py --check   # exit 1 when a committed picture differs from a fresh drawing

They are drawn by tools/raykit/picture/gallery.py (write_gallery, the table PITFALLS), as `./kit docs` draws
them into its site; tests/kit/lectures.py runs --check. Python 3.9, standard library only.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDER = ROOT / "docs" / "pitfalls"


def stale(folder: Path = FOLDER) -> list[str]:
    """The pictures of the gallery that are missing from `folder` or differ from a fresh drawing, and
    the files in `folder` that the gallery no longer draws."""
    sys.path.insert(0, str(ROOT / "tools"))
    from raykit import picture  # noqa: E402

    with tempfile.TemporaryDirectory() as tmp:
        fresh = {p.name: p.read_bytes() for p in picture.write_gallery(Path(tmp))}
    old = {p.name: p.read_bytes() for p in folder.glob("*.svg")} if folder.is_dir() else {}
    return sorted(n for n in fresh if old.get(n) != fresh[n]) + sorted(n for n in old if n not in fresh)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", action="store_true", help="exit 1 when a committed picture is stale")
    args = ap.parse_args(argv)
    bad = stale()
    if args.check:
        if bad:
            print("pitfall_pictures.py: stale in docs/pitfalls/: " + ", ".join(bad) +
                  " (run python3 docs/pitfall_pictures.py)", file=sys.stderr)
            return 1
        return 0
    sys.path.insert(0, str(ROOT / "tools"))
    from raykit import picture  # noqa: E402
    FOLDER.mkdir(parents=True, exist_ok=True)
    drawn = {p.name for p in picture.write_gallery(FOLDER)}
    for p in FOLDER.glob("*.svg"):
        if p.name not in drawn:
            p.unlink()
    print(f"pitfall_pictures.py: {len(drawn)} pictures in docs/pitfalls/" + (f", {len(bad)} changed" if bad else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())

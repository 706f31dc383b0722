"""./kit slides [--pdf]: the lectures' slide decks as offline HTML (the work is in kitlib/decks.py,
which ./kit docs uses too, so that a handout's docs site has the decks without this command)."""

from __future__ import annotations

import os

from raykit.common import say
from ..decks import OUT, SOURCES, build, deck_title, index_html, print_pdfs, split_deck
from raykit.status import OK


def register(p) -> None:
    p.add_argument("--pdf", action="store_true",
                   help="also print each deck to PDF with headless Chromium (one page a slide)")


def run(args) -> int:
    decks = build()
    say(f"raykit slides: {len(decks)} decks in {os.path.relpath(OUT)}")
    if args.pdf:
        pdfs = print_pdfs(decks)
        titles = [(d.name, deck_title(split_deck((SOURCES / f"{d.stem}.md").read_text(encoding="utf-8")), d.stem))
                  for d in decks]
        (OUT / "index.html").write_text(index_html(titles), encoding="utf-8")
        say(f"PDF: {', '.join(os.path.relpath(p) for p in pdfs)}")
    say(f"Open {os.path.relpath(OUT / 'index.html')} in a browser (S: the speaker notes); it reads offline.")
    return OK

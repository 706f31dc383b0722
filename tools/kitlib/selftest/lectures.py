"""Self-test: what the lectures and hints quote is current.

- every figure the lectures quote from the benchmark sits in a block that docs/bench_numbers.py writes
  from the committed run (docs/bench/results.json), and every block matches the run;
- every lecture section a hint names exists, by number and, where the hint gives it, by title.

(Each case's own lecture pointer is checked by "case names and lecture pointers" in selftest/check.py.)
"""

from __future__ import annotations

import contextlib
import copy
import io
import importlib.util
import json
import re
import tempfile
from pathlib import Path

from ..common import ROOT, load_steps
from .harness import Failed, Skipped, expect

GENERATOR = ROOT / "docs" / "bench_numbers.py"


def _generator():
    spec = importlib.util.spec_from_file_location("bench_numbers", GENERATOR)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def selftest_bench_numbers(ctx) -> str:
    if not GENERATOR.is_file() or not (ROOT / "docs" / "bench" / "results.json").is_file():
        raise Skipped("no docs/bench_numbers.py or no committed benchmark run here")
    bn = _generator()
    files = [p for p in bn.FILES if p.is_file()]
    try:
        stale = bn.run_files(bn.RESULTS, files, check=True)
    except bn.Stale as e:
        raise Failed(f"docs/bench_numbers.py cannot read the committed run: {e}") from None
    expect(not stale, "text quoting the benchmark does not match docs/bench/results.json "
                      f"(run python3 docs/bench_numbers.py): {', '.join(stale)}")
    blocks = sum(1 for p in files for line in p.read_text().split("\n") if bn.BEGIN.match(line))
    expect(blocks >= 4, f"only {blocks} generated blocks found in {', '.join(p.name for p in files)}")

    # The check must be able to fail: a run whose timings moved makes every timing block stale.
    data = json.loads(bn.RESULTS.read_text())
    moved = copy.deepcopy(data)
    for r in moved["results"]:
        r["cpu_ns"] = [1.5 * t for t in r.get("cpu_ns") or []]
    run = bn.Run(moved)
    changed = [b for p in files for b in bn.fill(p.read_text(), run, p.name)[1]]
    expect(len(changed) >= 3, f"timings 1.5 times slower changed only {changed}: the blocks do not follow the run")

    # Bad input: a clear message, exit 2, and no file touched.
    before = {p: p.read_text() for p in files}
    with tempfile.TemporaryDirectory() as tmp:
        broken = Path(tmp) / "results.json"
        broken.write_text('{"meta": {}, "families": [')
        for bad in (broken, Path(tmp) / "missing.json"):
            err = io.StringIO()
            with contextlib.redirect_stderr(err):
                code = bn.main(["--results", str(bad)])
            expect(code == 2 and "bench_numbers.py: " in err.getvalue(),
                   f"bench_numbers.py --results {bad.name} exited {code} ({err.getvalue().strip()!r}), "
                   "expected 2 and a message")
    expect(all(p.read_text() == t for p, t in before.items()), "bench_numbers.py changed a file on bad input")
    return f"{blocks} generated blocks current with docs/bench/results.json; stale when the run moves; bad input exits 2"


# "section 4", "sections 5 and 6", "section 2. The ray meets the sphere" (a title starts with a capital).
SECTION = re.compile(r"\bsections?\s+(\d+(?:\s*(?:,|and|to)\s*\d+)*)(?:\. ([A-Z][^)\n]*))?", re.I)


def selftest_hint_sections(ctx) -> str:
    bad, seen = [], 0
    for step in load_steps():
        hints = ROOT / "tests" / step.folder / "hints.md"
        lecture = ROOT / step.lecture
        if not hints.is_file() or not lecture.is_file():
            continue
        headings = [h.strip() for h in re.findall(r"^#+\s+(.*)$", lecture.read_text(), re.M)]
        numbers = {h.split(".")[0] for h in headings if re.match(r"\d+\.", h)}
        text = hints.read_text()
        # Only what a hint says about its own lecture: drop "lecture 03, sections 5 and 6" and the like.
        text = re.sub(r"lecture\s+\d+,?\s+sections?\s+[\d ,andto]+", "", text, flags=re.I)
        for m in SECTION.finditer(text):
            seen += 1
            for n in re.findall(r"\d+", m.group(1)):
                if n not in numbers:
                    bad.append(f"step {step.number}: a hint cites section {n}, which {step.lecture} does not have")
            if m.group(2):
                title = f"{m.group(1).strip()}. {m.group(2).strip()}"
                if title not in headings:
                    bad.append(f"step {step.number}: a hint cites '{title}', not a heading of {step.lecture}")
    expect(seen > 0, "no hint cites a lecture section: the check reads nothing")
    expect(not bad, "\n  ".join(bad[:10]))
    return f"{seen} section pointers in the hints name sections that exist"


def selftests():
    return [("numbers quoted from the benchmark are current", selftest_bench_numbers),
            ("hints point to lecture sections that exist", selftest_hint_sections)]

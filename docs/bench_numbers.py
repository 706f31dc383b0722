#!/usr/bin/env python3
"""The benchmark's figures that the lectures and the reading quote, generated from the committed run.

Text that quotes `docs/bench/results.json` does not type the numbers: it holds a block

    <!-- bench_numbers.py: NAME -->
    (generated lines)
    <!-- /bench_numbers.py -->

and this script writes the lines between the two markers from the run. Run it after every new
committed run (`./kit bench --out docs/bench`):

    python3 docs/bench_numbers.py            # rewrite the blocks in place
    python3 docs/bench_numbers.py --check    # exit 1 and name every stale block; change nothing

Never edit a block by hand: the self-test ("numbers quoted from the benchmark are current",
tools/kitlib/selftest/lectures.py) runs --check. Python 3.9, standard library only.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import statistics
import sys
import tempfile
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "docs" / "bench" / "results.json"
# The files whose blocks this script owns. A block name unknown here is an error, not skipped.
FILES = [ROOT / "lectures" / "03-appendix.md", ROOT / "docs" / "bench.md"]

BEGIN = re.compile(r"^<!-- bench_numbers\.py: ([a-z0-9-]+) -->$")
END = "<!-- /bench_numbers.py -->"


class Stale(Exception):
    """Input this script cannot use: missing or malformed results, a broken block."""


# --- reading the run -----------------------------------------------------------------------

class Run:
    """The committed run, indexed by variant and family."""

    def __init__(self, data: dict) -> None:
        try:
            self.meta = data["meta"]
            self.families = [f for f in data["families"] if f.get("group") == "sphere"]
            self.labels = {v["id"]: v["label"] for v in data["variants"]}
            self.rows = {(r["variant"], r["family"]): r for r in data["results"]}
        except (KeyError, TypeError) as e:
            raise Stale(f"results.json lacks {e}: is it a file written by ./kit bench?") from None
        if not self.families:
            raise Stale("results.json has no sphere family")

    def row(self, variant: str, family: str) -> dict:
        r = self.rows.get((variant, family))
        if r is None:
            raise Stale(f"results.json has no result for variant '{variant}' on family '{family}'")
        return r

    def ns(self, variant: str, family: str) -> float:
        # The median CPU time per ray, as the table (tools/kitlib/bench_report.py) shows it.
        times = self.row(variant, family).get("cpu_ns") or []
        if not times:
            raise Stale(f"variant '{variant}' was not timed on family '{family}'")
        return statistics.median(times)

    def stat(self, variant: str, family: str, key: str) -> float:
        value = self.row(variant, family).get(key)
        if not isinstance(value, (int, float)) or math.isnan(value):
            raise Stale(f"variant '{variant}' on family '{family}' has no number for '{key}'")
        return float(value)

    def family(self, fid: str) -> dict:
        for f in self.families:
            if f["id"] == fid:
                return f
        raise Stale(f"results.json has no family '{fid}'")


def load(path: Path) -> Run:
    try:
        return Run(json.loads(path.read_text()))
    except OSError as e:
        raise Stale(f"cannot read {path}: {e.strerror}") from None
    except json.JSONDecodeError as e:
        raise Stale(f"{path} is not JSON: {e}") from None


# --- formatting, as the benchmark's table does -----------------------------------------------

def ns(x: float) -> str:
    return f"{x:.1f}"


def ulps(x: float) -> str:
    if x < 10:
        return f"{x:.2f}"
    if x < 1e5:
        return f"{x:,.0f}".replace(",", " ")
    # Superscript digits, not TeX: the docs build must not meet a formula it was not told about.
    mantissa, exponent = f"{x:.1e}".split("e")
    return f"{mantissa}·10" + str(int(exponent)).translate(SUPERSCRIPT)


SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
WORDS = ["no", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten", "eleven", "twelve"]


def count(n: int) -> str:
    return WORDS[n] if 0 <= n < len(WORDS) else str(n)


def paragraph(text: str) -> list:
    """One paragraph, wrapped as the hand-written lines around it are."""
    return textwrap.wrap(text, width=100, break_on_hyphens=False)


def span(values: list, fmt) -> str:
    lo, hi = fmt(min(values)), fmt(max(values))
    return lo if lo == hi else f"{lo} to {hi}"


# --- the blocks ------------------------------------------------------------------------------

# The variants the lectures discuss, in the order of lecture 03 and its appendix.
LECTURE_VARIANTS = [
    ("textbook_f32", "the textbook formula (step 02, section 4), float"),
    ("half-b_f32", "half-b, float"),
    ("stable_f32", "the rewrite of lecture 03, sections 5 and 6, float"),
    ("half-b_f32_in_f64", "half-b computed in double, rounded to float once"),
    ("stable_f32_in_f64", "the rewrite computed in double"),
    ("kit", "the kit's step 02 reference, as graded (checks and calls included)"),
]


def where(run: Run) -> str:
    m = run.meta
    return (f"{m.get('cpu', 'an unknown CPU')}, GCC {m.get('compiler', '?')} `{m.get('flags', '?')}`, "
            f"one core, {m.get('batch', '?')} rays per timed pass, median of {m.get('repetitions', '?')} passes")


def block_lecture03_table(run: Run) -> list:
    fams = [f["id"] for f in run.families]
    lines = paragraph(f"Measured by `./kit bench` ({where(run)}); each range runs over the {count(len(fams))} "
                      f"families of rays, from the lowest to the highest family's figure.") + ["",
             "| variant | ns per ray | p99 error, ulps | largest error, ulps | misclassified rays, worst family |",
             "|---|--:|--:|--:|--:|"]
    for vid, words in LECTURE_VARIANTS:
        t = [run.ns(vid, f) for f in fams]
        p99 = [run.stat(vid, f, "ulps_p99") for f in fams]
        worst = max(run.stat(vid, f, "ulps_max") for f in fams)
        # As the benchmark counts them: wrong hit-or-miss calls among the rays outside the tangent band.
        bad = max((run.stat(vid, f, "misclassified"), run.stat(vid, f, "rays") - run.stat(vid, f, "in_band"))
                  for f in fams)
        share = 100 * bad[0] / bad[1] if bad[1] else 0.0
        bad_text = "0" if bad[0] == 0 else (f"{share:.2g} %" if share >= 0.01 else f"{bad[0]:.0f} rays")
        lines.append(f"| {words} | {span(t, ns)} | {span(p99, ulps)} | {ulps(worst)} | {bad_text} |")
    return lines


def _compare(run: Run, fast: str, slow: str) -> tuple:
    fams = [f["id"] for f in run.families]
    a = [run.ns(fast, f) for f in fams]
    b = [run.ns(slow, f) for f in fams]
    extra = [100 * (y / x - 1) for x, y in zip(a, b)]
    return a, b, extra


def block_lecture03_cost(run: Run) -> list:
    fams = [f["id"] for f in run.families]
    _, _, extra = _compare(run, "half-b_f32", "stable_f32")
    huge = run.family("huge")
    p99 = run.stat("stable_f32", "huge", "ulps_p99")
    worst = run.stat("stable_f32", "huge", "ulps_max")
    far = [f["id"] for f in run.families if f["id"].startswith("far")]
    far_p99 = max(run.stat("stable_f32", f, "ulps_p99") for f in far)
    lines = paragraph(f"On the same rays the float rewrite took {span(extra, lambda x: f'{x:.0f}')} % more time than "
             f"half-b in float, family by family ({count(len(fams))} families). It stayed within p99 "
             f"{ulps(far_p99)} ulps on every far family, but on \"{huge['label']}\" "
             f"({huge['description']}) it was off by p99 {ulps(p99)} ulps, at worst {ulps(worst)}.")
    return lines


def block_lecture03_double(run: Run) -> list:
    fams = [f["id"] for f in run.families]
    dbl, flt, _ = _compare(run, "half-b_f32_in_f64", "stable_f32")
    worst = max(run.stat("half-b_f32_in_f64", f, "ulps_max") for f in fams)
    faster = max(dbl) < min(flt)
    verdict = "less than" if faster else ("overlapping" if min(dbl) <= max(flt) else "more than")
    return paragraph(f"Half-b in double, rounded to float once, took {span(dbl, ns)} ns per ray ({verdict} the float "
            f"rewrite's {span(flt, ns)} ns) and was within {ulps(worst)} ulps of the exact root on every "
            f"family.")


def block_bench_double_inside(run: Run) -> list:
    fams = [f["id"] for f in run.families]
    dbl, flt, _ = _compare(run, "half-b_f32_in_f64", "stable_f32")
    stable_dbl = [run.ns("stable_f32_in_f64", f) for f in fams]
    if max(dbl) < min(flt):
        head = (f"And on this CPU it is cheap: half-b with double inside takes {span(dbl, ns)} ns per ray "
                f"(the medians of the {count(len(fams))} families), less than the stable form in float "
                f"({span(flt, ns)} ns), because it does two divides instead of three and scalar double adds "
                f"and multiplies cost what float ones do.")
    else:
        head = (f"On this CPU half-b with double inside takes {span(dbl, ns)} ns per ray (the medians of the "
                f"{count(len(fams))} families) against {span(flt, ns)} ns for the stable form in float.")
    stable_worst = max(run.stat("stable_f32_in_f64", f, "ulps_max") for f in fams)
    # "Correctly rounded" only for what is within half an ulp on every ray; otherwise the bound it keeps.
    accuracy = (f"correctly rounded on all {count(len(fams))} families (within half an ulp)" if stable_worst <= 0.5
                else f"within {ulps(stable_worst)} ulps on all {count(len(fams))} families")
    return paragraph(head + f" The stable form with double inside is {accuracy}, but slower "
                     f"({span(stable_dbl, ns)} ns): its three divides are double ones.")


BLOCKS = {
    "lecture03-table": block_lecture03_table,
    "lecture03-cost": block_lecture03_cost,
    "lecture03-double": block_lecture03_double,
    "bench-double-inside": block_bench_double_inside,
}


# --- filling the blocks ----------------------------------------------------------------------

def fill(text: str, run: Run, name: str = "text") -> tuple:
    """Returns (new text, names of the blocks whose content changed)."""
    lines = text.split("\n")
    out, changed, i = [], [], 0
    while i < len(lines):
        m = BEGIN.match(lines[i])
        out.append(lines[i])
        i += 1
        if not m:
            continue
        block = m.group(1)
        if block not in BLOCKS:
            raise Stale(f"{name}: unknown block '{block}' (known: {', '.join(sorted(BLOCKS))})")
        start = i
        while i < len(lines) and lines[i] != END:
            if BEGIN.match(lines[i]):
                raise Stale(f"{name}: block '{block}' is not closed before the next one")
            i += 1
        if i == len(lines):
            raise Stale(f"{name}: block '{block}' has no closing line '{END}'")
        new = BLOCKS[block](run)
        if lines[start:i] != new:
            changed.append(block)
        out.extend(new)
        out.append(END)
        i += 1
    return "\n".join(out), changed


def write_atomically(path: Path, text: str) -> None:
    # A half-written lecture is worse than a stale one: write beside it, then rename.
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def run_files(results: Path, files: list, check: bool) -> list:
    """Fills or checks every block; returns the stale blocks as 'file: name'."""
    run = load(results)
    stale, updates = [], []
    for path in files:
        if not path.is_file():
            continue  # a handout or a checkout without this page
        text = path.read_text()
        new, changed = fill(text, run, path.name)
        stale += [f"{path.name}: {b}" for b in changed]
        if changed and not check:
            updates.append((path, new))
    for path, new in updates:  # every file was read and understood before any is written
        write_atomically(path, new)
    return stale


def main(argv: list | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--check", action="store_true", help="change nothing; exit 1 when a block is stale")
    p.add_argument("--results", type=Path, default=RESULTS, help="the run to read (default: %(default)s)")
    args = p.parse_args(argv)
    try:
        stale = run_files(args.results, FILES, args.check)
    except Stale as e:
        print(f"bench_numbers.py: {e}", file=sys.stderr)
        return 2
    if args.check and stale:
        print("stale, run python3 docs/bench_numbers.py: " + ", ".join(stale), file=sys.stderr)
        return 1
    print(("stale: " if args.check else "rewrote: ") + (", ".join(stale) if stale else "nothing, every block is current"))
    return 0


if __name__ == "__main__":
    sys.exit(main())

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

Both also name every figure with a unit (ns, GFLOP/s, ulps, %, ×, "times", "a tenth of", a load
average, "p99 N") typed outside a block, and exit 1 on one: such a figure is either generated here
or reworded without a number. `./kit refresh` runs this script when a block is stale.

Never edit a block by hand: the self-tests ("numbers quoted from the benchmark are current",
tests/kit/lectures.py; "bench: every figure of the reading is generated",
tests/kit/bench.py) run the check. Python 3.9, standard library only; the roofline
and the Pareto fronts come from tools/kitlib/bench_report.py, as in the benchmark's own table.
"""

from __future__ import annotations

import argparse
import importlib.util
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
            self.data = data
            self.meta = data["meta"]
            self.peak = data.get("peak") or {}
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


# Never broken across lines: inline math (the docs' math filter reads it one line at a time), code
# spans, and a number's groups of digits ("52 936").
UNBREAKABLE = re.compile(r"\$[^$\n]+\$|`[^`\n]+`|\d(?: \d{3})+\b|[\d.]+ %")
HOLD = "\x00"


def paragraph(text: str, **indent) -> list:
    """One paragraph, wrapped as the hand-written lines around it are."""
    held = UNBREAKABLE.sub(lambda m: m.group(0).replace(" ", HOLD), text)
    lines = textwrap.wrap(held, width=100, break_on_hyphens=False, **indent)
    return [line.replace(HOLD, " ") for line in lines]


def span(values: list, fmt) -> str:
    if not values:
        raise Stale("a figure the text quotes has no row in results.json (a run without Embree or Highway?)")
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


# --- the reading of the benchmark (docs/bench.md) and the appendix, generated -----------------
#
# Each block below is a paragraph (or a list, or a table) of docs/bench.md or of lecture 03's appendix
# with every figure read from the run, and every word that compares two figures ("less than",
# "thousands of ulps", "the same answers") decided by them. The text around the blocks carries no
# figure with a unit: typed_figures() below finds one, and the self-test fails on it.

_REPORT = []


def _report():
    """The benchmark's own report module (tools/kitlib/bench_report.py): the roofline and the Pareto front
    are computed as the table computes them, not a second time here. Loaded once, and compiled without
    leaving a __pycache__ beside the kit's sources (the kit keeps its bytecode in its own cache)."""
    if _REPORT:
        return _REPORT[0]
    path = ROOT / "tools" / "kitlib" / "bench_report.py"
    if not path.is_file():
        raise Stale(f"no {path.relative_to(ROOT)}: the roofline and the fronts cannot be computed")
    # Imported as part of its package (tools/kitlib), whose modules it imports in turn (charts.py).
    if str(path.parents[1]) not in sys.path:
        sys.path.insert(0, str(path.parents[1]))
    was, sys.dont_write_bytecode = sys.dont_write_bytecode, True
    try:
        module = importlib.import_module("kitlib.bench_report")
    finally:
        sys.dont_write_bytecode = was
    _REPORT.append(module)
    return module


def star_bound() -> int:
    """The ★ cases' bound in ulps, as docs/robust_numbers.py (which grades by it) states it."""
    path = ROOT / "docs" / "robust_numbers.py"
    m = re.search(r"^BOUND = (\d+)$", path.read_text(), re.M) if path.is_file() else None
    if m is None:
        raise Stale("docs/robust_numbers.py states no BOUND: the ★ cases' bound is unknown")
    return int(m.group(1))


def pct(x: float) -> str:
    """A share in per cent, two significant figures (45 %, 5.4 %, 0.15 %)."""
    if x == 0:
        return "0 %"
    return f"{x:.0f} %" if x >= 10 else f"{x:.2g} %"


def ns2(x: float) -> str:
    """Times under a nanosecond and a half keep two decimals: the vector rows."""
    return f"{x:.2f}" if x < 1.5 else f"{x:.1f}"


def times(x: float) -> str:
    return f"{x:.1f}"


def ulps_of(x: float) -> str:
    """An error bound that must not round below the figure: 0.5008 is 'within 0.51', not 0.50."""
    if x < 1:
        return f"{math.ceil(x * 1000 - 1e-9) / 1000:.3f}"
    return f"{math.ceil(x * 100 - 1e-9) / 100:.2f}" if x < 10 else ulps(x)


def magnitude(x: float) -> str:
    for limit, word in ((1e6, "millions"), (1e3, "thousands"), (1e2, "hundreds"), (10, "tens")):
        if x >= limit:
            return word
    return "a few"


def wrap(text: str, bullet: bool = False) -> list:
    if not bullet:
        return paragraph(text)
    return paragraph(text, initial_indent="- ", subsequent_indent="  ")


class Reading:
    """What the blocks of the reading ask of the run, in the words of docs/bench.md."""

    def __init__(self, run: Run) -> None:
        self.run = run
        self.fids = [f["id"] for f in run.families]
        self.far = [f for f in self.fids if f.startswith("far_")]
        self.pbrt = [f for f in self.fids if f.startswith("pbrt_")]
        self.ground = [f for f in self.fids if f.startswith("ground_")]
        # The families of sections 3 and 4: neither pbrt's ranges nor the ground.
        self.first = [f for f in self.fids if f not in self.pbrt and f not in self.ground]

    def has(self, v: str, f: str) -> bool:
        return (v, f) in self.run.rows

    def ns(self, v: str, fams=None) -> list:
        return [self.run.ns(v, f) for f in (fams or self.fids) if self.has(v, f)]

    def stat(self, v: str, key: str, fams=None) -> list:
        return [self.run.stat(v, f, key) for f in (fams or self.fids) if self.has(v, f)]

    def share(self, v: str, f: str) -> float:
        """Misclassified rays, in per cent of those outside the tangent band (as the table counts)."""
        judged = self.run.stat(v, f, "rays") - self.run.stat(v, f, "in_band")
        return 100 * self.run.stat(v, f, "misclassified") / judged if judged else 0.0

    def shares(self, v: str, fams=None) -> list:
        return [self.share(v, f) for f in (fams or self.fids) if self.has(v, f)]

    def ratios(self, slow: str, fast: str, fams=None) -> list:
        """Family by family, the median time of `slow` over that of `fast`."""
        fams = [f for f in (fams or self.fids) if self.has(slow, f) and self.has(fast, f)]
        return [self.run.ns(slow, f) / self.run.ns(fast, f) for f in fams]

    def flops(self, v: str, f: str = "typical") -> float:
        return self.run.stat(v, f, "flops")

    def target(self, isa: str) -> dict:
        for t in self.run.peak.get("vector_targets") or []:
            if t["isa"] == isa:
                return t
        raise Stale(f"results.json has no peak rates for {isa}")

    def same_errors(self, a: str, b: str, fams=None) -> bool:
        keys = ("misclassified", "ulps_median", "ulps_p99", "ulps_max")
        return all(self.run.row(a, f).get(k) == self.run.row(b, f).get(k)
                   for f in (fams or self.fids) if self.has(a, f) and self.has(b, f) for k in keys)

    def points(self):
        report = _report()
        pts = report.points(self.run.data)
        report.mark_pareto(pts)
        return report, pts

    def roofline_shares(self, variants: list, fams=None) -> list:
        """Family by family, the roofline as a share of the median time, in per cent (the table's column)."""
        report = _report()
        vmap = {v["id"]: v for v in self.run.data["variants"]}
        fmap = {f["id"]: f for f in self.run.data["families"]}
        out = []
        for v in variants:
            for f in fams or self.fids:
                if not self.has(v, f):
                    continue
                raw = self.run.row(v, f)
                p = report.Point(vmap[v], fmap[f], raw, ns=list(raw.get("cpu_ns") or []))
                bound = p.roofline_ns(self.run.peak)
                if bound is not None and p.timed:
                    out.append(100 * bound / p.ns_median)
        if not out:
            raise Stale(f"no roofline for {', '.join(variants)}: no flop counts or no peak rates in the run")
        return out


def label(run: Run, fid: str) -> str:
    return run.family(fid)["label"]


def radii(fid: str) -> str:
    """far_1e3 -> "$10^3$ radii", far_3e4 -> "$3\\cdot10^4$ radii": the far families as the text names them."""
    m = re.fullmatch(r"far_(\d)e(\d+)", fid)
    if m is None:
        raise Stale(f"family '{fid}' is not a far family")
    k, e = m.groups()
    return (f"$10^{e}$" if k == "1" else f"${k}\\cdot10^{e}$") + " radii"


def half_rate(rate: float) -> str:
    return "half the float rate" if abs(rate - 2) < 0.1 else f"{1 / rate:.2f} times the float rate"


FORMULATIONS = [
    ("textbook", r"$a = \mathbf{d}\cdot\mathbf{d}$, $b = 2\,\mathbf{f}\cdot\mathbf{d}$, $c = \mathbf{f}\cdot\mathbf{f} - r^2$, "
                 r"$t = (-b \mp \sqrt{b^2 - 4ac})/2a$"),
    ("half-b", r"$h = \mathbf{f}\cdot\mathbf{d}$, $t = (-h \mp \sqrt{h^2 - ac})/a$"),
    ("unit-dir", r"$\hat{\mathbf{d}} = \mathbf{d}/\lvert\mathbf{d}\rvert$, then $a = 1$; divide the roots by "
                 r"$\lvert\mathbf{d}\rvert$"),
    ("geometric", r"$t_m = (\mathbf{c} - \mathbf{o})\cdot\hat{\mathbf{d}}$, $\ell_m^2 = \lvert\mathbf{c} - "
                  r"\mathbf{o}\rvert^2 - t_m^2$, $t = t_m \mp \sqrt{r^2 - \ell_m^2}$"),
    ("stable", r"$\mathbf{l} = \mathbf{f} - (h/a)\,\mathbf{d}$, $D = a\,(r^2 - \mathbf{l}\cdot\mathbf{l})$, "
               r"$q = -(h + \operatorname{sign}(h)\sqrt{D})$, $t = q/a,\ c/q$"),
    ("lagrange", r"$\mathbf{g} = \mathbf{f}\times\mathbf{d}$, $D = a\,r^2 - \mathbf{g}\cdot\mathbf{g}$, "
                 r"$t = (-h \mp \sqrt{D})/a$"),
    ("exact-float", r"lagrange in float only, with float-float $\mathbf{f}$, $a$, $h$, $\mathbf{g}$, $c$ and $D$ "
                    r"(section 6)"),
]


def block_bench_formulations(run: Run) -> list:
    """The formulations and their flops as the counting number type counted them in float on *typical*."""
    lines = ["| name | roots | flops |", "|---|---|--:|"]
    for name, roots in FORMULATIONS:
        lines.append(f"| {name} | {roots} | {run.stat(name + '_f32', 'typical', 'flops'):.0f} |")
    return lines


def block_bench_peaks(run: Run) -> list:
    m, p, r = run.meta, run.peak, Reading(run)
    if not p.get("scalar_gflops_f32"):
        raise Stale("results.json has no peak rates")
    x3, x2 = r.target("AVX3"), r.target("AVX2")
    scalar = [v["id"] for v in run.data["variants"] if v.get("group") == "sphere" and (v.get("lanes") or 1) == 1
              and v["formulation"] not in ("kit", "embree", "student")]
    share = r.roofline_shares(scalar)
    cpu = m.get("cpu", "an unknown CPU") + (f", {m['cpu_id']}" if m.get("cpu_id") else "")
    verdict = ("none is limited by arithmetic" if max(share) < 70 else "some come close to their arithmetic's limit")
    return paragraph(
        f"**The roofline.** Measured on the spot: one core of this machine ({cpu}) does "
        f"{p['scalar_gflops_f32']:.1f} GFLOP/s of scalar adds and multiplies, {p['vector_gflops_f32']:.0f} GFLOP/s in "
        f"float with AVX2 and FMA ({p['vector_gflops_f64']:.0f} in double) and {x3['gflops_f32']:.0f} with AVX-512 "
        f"({x3['gflops_f64']:.0f} in double), a float divide every {p['div_ns_f32']:.2f} ns and a square root every "
        f"{p['sqrt_ns_f32']:.2f} ns ({p['div_ns_f64']:.2f} and {p['sqrt_ns_f64']:.2f} ns in double); with AVX-512, per "
        f"lane, a divide every {x3['div_ns_f32']:.3f} ns and a square root every {x3['sqrt_ns_f32']:.3f} ns "
        f"({x3['div_ns_f64']:.3f} and {x3['sqrt_ns_f64']:.3f} ns in double), and a conversion between float and "
        f"double every {x3['cvt_ns']:.3f} ns ({x2['cvt_ns']:.3f} with AVX2). The *roofline* column is the least time "
        f"the counted work needs at those rates, as a share of the measured time: the adds and multiplies at the FMA "
        f"rate (in a vector row, as instructions: a fused multiply-add, a lone add and a lone multiply take one "
        f"instruction of the FMA units each, the measured rate's two flops), the divides and the square roots at the divider's, and for double lanes on float rays one conversion "
        f"per input and per result (section 6), whichever of these takes longest; two that take turns on one unit "
        f"add up, as far as a loop of both measures (section 6). Every scalar formulation sits at "
        f"{span(share, lambda x: f'{x:.0f}')} %: {verdict}.")


def block_bench_far(run: Run) -> list:
    r = Reading(run)
    tb = "textbook_f32"
    p99 = r.stat(tb, "ulps_p99", r.far)
    s = {f: pct(r.share(tb, f)) for f in r.far}
    far_words = (", ".join(f"{s[f]} at {radii(f)}" for f in r.far[:-1]) + f" and {s[r.far[-1]]} at {radii(r.far[-1])}"
                 ).replace(" at ", " of the rays at ", 1)
    return paragraph(
        f"Close up, every formulation is usable: on *typical* the textbook form's p99 is "
        f"{ulps(run.stat(tb, 'typical', 'ulps_p99'))} ulps, {ns(run.ns(tb, 'typical'))} ns per ray. Far away they are "
        f"not. The textbook form in float misclassifies {far_words}, and the roots it does return are "
        f"{magnitude(min(p99))} of ulps off (p99 {span(p99, ulps)}).")


def block_bench_half_b(run: Run) -> list:
    r = Reading(run)
    same = r.same_errors("half-b_f32", "textbook_f32")
    ratio = r.ratios("half-b_f32", "textbook_f32")
    worst = max(abs(x - 1) for x in ratio) * 100
    extra = [run.ns(v, f) - run.ns("half-b_f32", f) for v in ("unit-dir_f32", "geometric_f32") for f in r.fids]
    more = [max(r.shares(v, ["far_1e3"])) for v in ("unit-dir_f32", "geometric_f32")]
    answers = ("gives **bit for bit the same answers** as the textbook form (the factors 2 and 4 are exact in "
               "binary)" if same else "gives nearly the same answers as the textbook form")
    return paragraph(
        f"Half-b {answers}, and its median time is within {worst:.0f} % of the textbook form's on every family: use "
        f"it if you use either. Normalising the direction first (unit-dir) or going the geometric way costs a square "
        f"root and a divide more ({'up to' if min(extra) > 0 else 'on most families; up to'} {ns(max(extra))} ns "
        "in the median) and is no more accurate: both still "
        f"subtract two numbers of size $|\\mathbf{{f}}|^2$ ({span(more, pct)} misclassified at $10^3$ radii, against "
        f"the textbook form's {pct(r.share('textbook_f32', 'far_1e3'))}).")


def block_bench_stable(run: Run) -> list:
    r = Reading(run)
    st = "stable_f32"
    near = r.far + ["tiny", "off_centre"]
    n = {f: int(run.stat(st, f, "misclassified")) for f in r.far}
    rays = int(run.meta.get("rays") or run.stat(st, "typical", "rays"))
    counts = [("nothing" if n[f] == 0 else f"{n[f]} rays") + f" at {radii(f)}" for f in r.far]
    return paragraph(
        f"The stable form keeps the error at p99 {ulps(max(r.stat(st, 'ulps_p99', near)))} ulps or less on every far "
        f"family, on *tiny* and on *off-centre*, and {ulps(run.stat(st, 'grazing', 'ulps_p99'))} on *grazing*; of "
        f"{rays} rays per family it misclassifies {', '.join(counts[:-1])} and {counts[-1]}, where the line's own distance from the centre, "
        f"computed in float, is uncertain by more than the $10^{{-4}}\\,r$ band. It costs "
        f"{r.flops(st):.0f} flops against half-b's {r.flops('half-b_f32'):.0f}: {span(r.ns(st), ns)} ns per ray "
        f"against {span(r.ns('half-b_f32'), ns)} (the medians of the {count(len(r.fids))} families).")


def block_bench_float_limits(run: Run) -> list:
    def p99(v, f):
        return ulps(run.stat(v, f, "ulps_p99"))
    return wrap(
        "**huge**: the camera is 0.1 to 10 units above a sphere of radius $10^4$, so $c = \\mathbf{f}\\cdot\\mathbf{f}"
        " - r^2$ subtracts two numbers near $10^8$ (a float's spacing there is 8) to find one near $2rH$. The near root"
        f" is $c/q$ and inherits the loss: p99 {p99('stable_f32', 'huge')} ulps for the stable form, "
        f"{p99('textbook_f32', 'huge')} for the textbook one, {p99('embree_sphere', 'huge')} for Embree. The ground "
        "families (section 5) are the same case at radius $10^3$ and at the Earth's.", bullet=True) + wrap(
        "**origin inside**: an origin near the surface makes $c$ small by the same subtraction: stable p99 "
        f"{p99('stable_f32', 'inside')} ulps, largest error {ulps(run.stat('stable_f32', 'inside', 'ulps_max'))}.",
        bullet=True)


IN_DOUBLE = ["half-b_f32_in_f64", "stable_f32_in_f64", "half-b-pair_f32_in_f64", "lagrange_f32_in_f64"]


def block_bench_double_accuracy(run: Run) -> list:
    r = Reading(run)
    fams = r.first
    p99 = max(x for v in IN_DOUBLE for x in r.stat(v, "ulps_p99", fams))
    worst = max(((run.stat(v, f, "ulps_max"), v, f) for v in IN_DOUBLE for f in fams if r.has(v, f)))
    mis = sum(run.stat(v, f, "misclassified") for v in IN_DOUBLE for f in fams if r.has(v, f))
    rounded = ("correctly rounded on at least 99 % of the rays" if p99 <= 0.5
               else "within a few ulps on 99 % of the rays")
    return paragraph(
        f"Computed in double and rounded to float once at the end, every formulation tried this way is {rounded} of "
        f"the {count(len(fams))} families above (p99 at most {p99:.5f} ulps), misclassifies "
        f"{'no ray there' if mis == 0 else f'{mis:.0f} rays there'}, and is at worst {worst[0]:.5f} ulps off "
        f"({run.labels[worst[1]]}, on *{label(run, worst[2])}*): double's 29 extra bits absorb every cancellation "
        "these rays produce, including $c$ on the huge sphere.")


def block_bench_pbrt(run: Run) -> list:
    r = Reading(run)
    hb = "half-b_f32_in_f64"
    e = [f"**{pct(r.share(hb, f))}** for $e = {f.split('_e')[1]}$" for f in r.pbrt]  # of the judged rays
    lg = "lagrange_f32_in_f64"
    mis = sum(r.stat(lg, "misclassified"))
    return paragraph(
        f"Of the rays outside the $10^{{-5}}\\,r$ tangent band, half-b with double inside misclassifies "
        f"{', '.join(e[:-1])} and {e[-1]}; the float stable form {span(r.shares('stable_f32', r.pbrt), pct)}. The "
        f"**Lagrange form** with double inside misclassifies {'**none**' if mis == 0 else f'{mis:.0f} rays'}, on these "
        f"and on every other family, and every root is within {ulps_of(max(r.stat(lg, 'ulps_max')))} ulps, with p99 at "
        f"most {max(r.stat(lg, 'ulps_p99')):.5f} ulps on every family.")


def block_bench_lagrange_cost(run: Run) -> list:
    r = Reading(run)
    lg, hb = "lagrange_f32_in_f64", "half-b_f32_in_f64"
    diff = [run.ns(lg, f) - run.ns(hb, f) for f in r.fids]
    lo, hi = min(diff), max(diff)
    moves = (f"from {ns(-lo)} ns less to {ns(hi)} ns more" if lo < 0 else f"from {ns(lo)} to {ns(hi)} ns more")
    e8 = r.pbrt[-1]
    return paragraph(
        f"It costs {r.flops(lg) - r.flops(hb):.0f} flops more than half-b ({r.flops(lg):.0f} against "
        f"{r.flops(hb):.0f}): inlined, {span(r.ns(lg), ns)} ns per ray against {span(r.ns(hb), ns)} ns, {moves} in the "
        f"median, family by family. The same form in float only is not enough ({pct(r.share('lagrange_f32', e8))} "
        f"misclassified at $e = {e8.split('_e')[1]}$): it is the float-float version of section 6 that is.")


FLOAT_SCALAR = ["textbook_f32", "half-b_f32", "unit-dir_f32", "geometric_f32", "stable_f32", "lagrange_f32"]


def block_bench_ground(run: Run) -> list:
    r = Reading(run)
    small, earth = r.ground
    near = lambda f: span([run.stat(v, f, "ulps_p99") for v in FLOAT_SCALAR], ulps)
    dbl = max(x for v in IN_DOUBLE for x in r.stat(v, "ulps_max", r.ground))
    band = run.stat("lagrange_f32_in_f64", earth, "in_band") / run.stat("lagrange_f32_in_f64", earth, "rays") * 100
    return paragraph(
        "**The ground.** A camera 1 to 2 units above a sphere of radius $10^3$ or $6.4\\cdot10^6$ (the Earth in metres)"
        " makes $c = |\\mathbf{f}|^2 - r^2$ a tiny difference of two numbers near $r^2$: the forms in float are off by "
        f"p99 {near(small)} ulps on the smaller sphere and {near(earth)} on the Earth, and all forms in double inside "
        f"stay within {ulps_of(dbl)} ulps. On the Earth, {pct(band)} of these rays pass within $10^{{-5}}\\,r$ of a "
        "tangent (the horizon dips only $7\\cdot10^{-4}$ rad) and are not judged: the band is relative to the radius, "
        "and $10^{-5}$ of the Earth's is 64 m.")


def block_bench_double_results(run: Run) -> list:
    far = Reading(run).far[-1]
    tb = run.stat("textbook_f64", far, "ulps_p99")
    return paragraph(
        "The double variants with double results tell the same story in double ulps: the textbook form's p99 is "
        f"{ulps(tb)} double ulps at {radii(far)} (a relative error of the order of "
        f"{tb * 2.0 ** -52:.0e}), the stable form's {ulps(run.stat('stable_f64', far, 'ulps_p99'))}.")


def block_bench_embree_sphere(run: Run) -> list:
    r = Reading(run)
    fams = [f for f in r.first if f not in ("huge", "inside") and r.has("embree_sphere", f)]
    return paragraph(
        f"Embree's sphere points have first-hit p99 {span(r.stat('embree_sphere', 'ulps_p99', fams), ulps)} ulps on "
        f"the {count(len(fams))} families of sections 3 and 4 other than *huge* and *origin inside*, where the stable "
        f"form has {span(r.stat('stable_f32', 'ulps_p99', fams), ulps)}; like it, they lose on those two and on the "
        "ground, and they cost "
        f"{span(r.ns('embree_sphere'), lambda x: f'{x:.0f}')} ns per ray: `rtcIntersect1` pays for a general scene "
        "traversal that a single sphere does not need. (It is not run on the pbrt families, whose every ray has its "
        "own sphere.)")


REF_X8, REF_X4 = "lagrange_f32_in_f64_x8_AVX3", "lagrange_f32_in_f64_x4_AVX2"
FF_X16, FF_X8 = "exact-float_f32_x16_AVX3", "exact-float_f32_x8_AVX2"


def narrower(r: "Reading", x4: str, x8: str) -> str:
    """How the AVX2 reference's times compare with AVX-512's, family by family, in words."""
    pairs = [(r.run.ns(x4, f), r.run.ns(x8, f)) for f in r.fids if r.has(x4, f) and r.has(x8, f)]
    faster = sum(a < b for a, b in pairs)
    if faster == len(pairs):
        return "faster than with AVX-512 on every family, on this CPU"
    if faster == 0:
        return "slower than with AVX-512 on every family"
    return f"faster than with AVX-512 on {faster} of the {len(pairs)} families, on this CPU"


def block_bench_lanes(run: Run) -> list:
    r = Reading(run)
    x8, x4 = REF_X8, REF_X4
    speed = r.ratios("kit", x8)
    inlined = r.ratios("lagrange_f32_in_f64", x8)
    mis = sum(r.stat(x8, "misclassified"))
    hb16, st16 = "half-b_f32_x16_AVX3", "stable_f32_x16_AVX3"
    far4 = r.far[1]
    earth = r.ground[-1]
    half = r.ratios(x8, st16)
    ff = r.ratios(FF_X16, x8)
    x3 = r.target("AVX3")
    flops = r.flops(FF_X16) / r.flops(x8)
    rate = x3["gflops_f32"] / x3["gflops_f64"]
    out = wrap(
        "**The reference, vectorized**: the Lagrange form in double lanes, float in and out, one divide ($1/a$) and "
        f"one square root per ray. With AVX-512 (8 doubles) it takes **{span(r.ns(x8), ns2)} ns per ray against "
        f"{span(r.ns('kit'), ns)} ns** for the kit's scalar function: **{span(speed, times)} times the rays per "
        f"second** ({span(inlined, times)} times its formulation inlined into one call per ray), and it is **within "
        f"{ulps_of(max(r.stat(x8, 'ulps_max')))} ulps on all {count(len(r.fids))} families**: p99 at most "
        f"{max(r.stat(x8, 'ulps_p99')):.2f} ulps, {'nothing' if mis == 0 else f'{mis:.0f} rays'} misclassified. With "
        f"AVX2 (4 doubles) {span(r.ns(x4), ns2)} ns: {narrower(r, x4, x8)}.", bullet=True)
    out += wrap(
        f"**Float lanes are faster and wrong far away.** Half-b in 16 float lanes takes {span(r.ns(hb16), ns2)} ns and "
        f"the stable form {span(r.ns(st16), ns2)} ns, but they keep the errors of their formulas: half-b in float "
        f"lanes misclassifies {pct(r.share(hb16, far4))} of the rays at {radii(far4)} (one ray at a "
        f"time, {pct(r.share('half-b_f32', far4))}); the stable form stays within p99 "
        f"{ulps(run.stat(st16, far4, 'ulps_p99'))} ulps there but misclassifies up to "
        f"{pct(max(r.shares(st16, r.pbrt)))} on pbrt's ranges and is off by p99 {ulps(run.stat(st16, earth, 'ulps_p99'))}"
        f" ulps on the Earth. The double lanes take {span(half, times)} times the stable float lanes' time, family by "
        "family: the price of double's half-width lanes is time, not accuracy.", bullet=True)
    ffmax = max(r.stat(FF_X16, "ulps_max"))
    ffmis = sum(r.stat(FF_X16, "misclassified"))
    out += wrap(
        "**The float-float form** (`exact-float` in the table, a name, not a promise: its roots are within "
        f"{ulps_of(ffmax)} ulps, not all correctly rounded): the Lagrange form in float, with $\\mathbf{{f}}$, $a$, $h$, "
        "$\\mathbf{f}\\times\\mathbf{d}$, $c$ and the discriminant carried as float-float pairs by error-free "
        "transformations (TwoSum; TwoProduct by fused multiply-add; dot products as in Ogita, Rump and Oishi, "
        "\"Accurate sum and dot product\", SIAM J. Sci. Comput., 2005; products of float-floats after Dekker, \"A "
        "floating-point technique for extending the available precision\", Numer. Math., 1971; the cross product "
        "keeping both product errors, as Kahan's FMA algorithm for $ad - bc$), one Newton step on the square root and "
        f"one remainder correction per quotient. It is **within {ulps_of(ffmax)} ulps on every family** (p99 "
        f"{span(r.stat(FF_X16, 'ulps_p99'), ulps)} ulps, {'nothing' if ffmis == 0 else f'{ffmis:.0f} rays'} "
        f"misclassified) with no double anywhere, and costs {r.flops(FF_X16):.0f} flops per ray against the double "
        f"lanes' {r.flops(x8):.0f}. In 16 float lanes it takes **{span(r.ns(FF_X16), ns2)} ns per ray: "
        f"{span(ff, times)} times the double lanes** (with AVX2, {span(r.ns(FF_X8), ns2)} ns against "
        f"{span(r.ns(x4), ns2)}). On this CPU double is the "
        + ("cheaper" if min(ff) > 1 else "not always the cheaper")
        + f" way to answers this close, because a vector double multiply-add runs at {half_rate(rate)} "
        f"(the measured FMA peaks with AVX-512: {x3['gflops_f32']:.0f} and {x3['gflops_f64']:.0f} GFLOP/s). (One ray "
        "at a time, in the kit's scalar build without `-mfma`, every `std::fma` is a call into the C library, and the "
        f"same form takes {span(r.ns('exact-float_f32'), lambda x: f'{x:.0f}')} ns per ray: the scalar row is there "
        "for its errors, which are those of the vector rows, not for its time.)", bullet=True)
    out += wrap(
        "**When double's half lanes stop mattering, and when they start.** Here a vector double multiply-add runs at "
        f"{half_rate(rate)}, so the double form should win by the factor of {flops:.1f} in flops "
        f"divided by {rate:.1f} in rate, {flops / rate:.1f}; measured, {span(ff, times)} (the double lanes also pay "
        "their conversions, and a divide and a square root that take longer per lane in double than in float; the "
        "flop count weighs neither). On a GPU where double runs at 1/32 or 1/64 of the float rate, the "
        f"same arithmetic predicts the opposite: the float-only form would be {32 / flops:.0f} to {64 / flops:.0f} "
        "times faster than double there. (Measured here: the CPU only.)", bullet=True)
    return out


def block_bench_choice(run: Run) -> list:
    r = Reading(run)
    lg = "lagrange_f32_in_f64"
    slower = [100 * (x - 1) for x in r.ratios(lg, "half-b_f32")]
    cheap = ["textbook_f32", "half-b_f32", "unit-dir_f32", "geometric_f32"]
    bad = [r.share(v, f) for v in cheap for f in r.far]
    return wrap(
        "**A float ray tracer on a CPU, one ray at a time** (this kit): the Lagrange form in double, rounded to "
        f"float. Within {ulps_of(max(r.stat(lg, 'ulps_max')))} ulps at every scale measured, and "
        f"{statistics.median(slower):.0f} % slower than half-b in float in the median family "
        f"({span(slower, lambda x: f'{x:.0f}')} %, family by family).", bullet=True) + wrap(
        "**Many rays at once on a CPU**: the same form in double lanes; "
        f"{span(r.ratios('kit', REF_X8), times)} times the scalar function's speed with AVX-512, "
        f"{span(r.ratios('kit', REF_X4), times)} with AVX2.", bullet=True) + wrap(
        "**Float only** (a GPU with slow double, or inputs that must stay in float registers): the float-float form "
        f"for answers within {ulps_of(max(r.stat(FF_X16, 'ulps_max')))} ulps; the stable form when a few ulps and "
        "rare misclassifications at extreme scales are acceptable. Neither plain float form can save a huge sphere "
        "seen from close by.", bullet=True) + wrap(
        "**Never**: the textbook, half-b, unit-dir or geometric forms in float when a sphere can be a thousand radii "
        f"or more from the ray's origin: they misclassify {span(bad, pct)} of the rays there.", bullet=True)


def _ref_costs(run: Run, isa: str) -> dict:
    """The vectorized reference's roofline terms on `isa`, ns per ray on *typical*: its adds and multiplies,
    its conversions, its divides and its square roots, and how much each pair that may compete for a unit
    was measured to share (bench_report.Point.roofline_ns combines them so)."""
    t = Reading(run).target(isa)
    row = run.row(REF_X8 if isa == "AVX3" else REF_X4, "typical")
    if t.get("shared_div_sqrt") is None or t.get("shared_fma_cvt") is None:
        raise Stale(f"results.json has no measured overlap of the {isa} units (a run before it was measured)")
    add_mul = row["flops"] - row["div"] - row["sqrt"]
    if row.get("fma") is None:
        raise Stale("results.json has no count of fused multiply-adds (a run before it was counted)")
    return {"row": row, "add_mul": (add_mul - row["fma"]) * 2 / t["gflops_f64"], "instructions": add_mul - row["fma"],
            "cvt": (row.get("cvt") or 0) * t["cvt_ns"], "div": row["div"] * t["div_ns_f64"],
            "sqrt": row["sqrt"] * t["sqrt_ns_f64"], "shared_div_sqrt": t["shared_div_sqrt"],
            "shared_fma_cvt": t["shared_fma_cvt"]}


def block_bench_vector_roofline(run: Run) -> list:
    r = Reading(run)
    c = _ref_costs(run, "AVX3")
    row, combined = c["row"], _report().combined
    units = combined(c["add_mul"], c["cvt"], c["shared_fma_cvt"])
    divider = combined(c["div"], c["sqrt"], c["shared_div_sqrt"])
    pct = lambda x: f"{100 * x:.0f} %"
    beside = lambda x: "they take turns" if x >= 0.5 else "they run mostly beside each other"
    return paragraph(
        f"With AVX-512 the reference's roofline has four terms per ray: its {row['flops'] - row['div'] - row['sqrt']:.0f} "
        f"adds and multiplies, {c['instructions']:.0f} instructions once fused, take {c['add_mul']:.2f} ns at the FMA "
        "units' pace; a kernel that takes float rays and computes "
        "in double must widen each of the ten float arrays it reads and narrow each of the three it writes, and its "
        f"{row.get('cvt') or 0:.0f} conversions take {c['cvt']:.2f} ns; its divide and its square root take "
        f"{c['div']:.2f} and {c['sqrt']:.2f} ns at the divider's pace. Timed in one loop, divides and square roots "
        f"add {pct(c['shared_div_sqrt'])} of the shorter's time to the longer's ({beside(c['shared_div_sqrt'])}), "
        f"multiply-adds and conversions {pct(c['shared_fma_cvt'])} ({beside(c['shared_fma_cvt'])}). So the "
        + ("divider sets the roofline" if divider >= units else "multiply-adds and conversions set the roofline")
        + f": {max(units, divider):.2f} ns per ray, against {span(r.ns(REF_X8), ns2)} measured.")


def block_bench_vector_reference(run: Run) -> list:
    r = Reading(run)
    on3 = r.roofline_shares([REF_X8])
    on2 = r.roofline_shares([REF_X4])
    worst = min(r.fids, key=lambda f: r.roofline_shares([REF_X8], [f])[0])
    ff3, ff2 = r.roofline_shares([FF_X16]), r.roofline_shares([FF_X8])
    load = (run.meta.get("load_avg") or [None])[0]
    at = f" (load average {load:.2f} at its start)" if isinstance(load, (int, float)) else ""
    return paragraph(
        f"**Where the vectorized reference stands.** It reaches **{span(on3, lambda x: f'{x:.1f}')} %** of its "
        f"roofline with AVX-512 in the committed run{at}, the least on *{label(run, worst)}*, and "
        f"{span(on2, lambda x: f'{x:.0f}')} % with AVX2, at {span(r.ratios('kit', REF_X8), times)} times the scalar "
        "function's rays per second (AVX-512). The conversions belong to the contract (float rays in, float roots "
        "out, double inside), and no formulation in double lanes can skip them; where they set the pace, a renderer "
        "that tests many rays against one sphere would load the centre and the radius once and save four of the "
        "ten widenings. The "
        f"float-float form has no conversions and {r.flops(FF_X16) / r.flops(REF_X8):.1f} times the arithmetic, and "
        f"reaches {span(ff3, lambda x: f'{x:.0f}')} % of its roofline with AVX-512 and "
        f"{span(ff2, lambda x: f'{x:.0f}')} % with AVX2, which arithmetic sets. Every vector row with a roofline "
        f"reaches at least {min(vector_shares(run, 'AVX3')):.0f} % of it with AVX-512 and "
        f"{min(vector_shares(run, 'AVX2')):.0f} % with AVX2, on every family.")


def vector_shares(run: Run, isa: str) -> list:
    """The roofline shares (per cent) of every vector row of `isa` with a roofline, on every family."""
    r = Reading(run)
    ids = [v["id"] for v in run.data["variants"] if (v.get("lanes") or 1) > 1 and v.get("isa") == isa]
    shares = []
    for v in ids:
        for f in r.fids:
            try:
                shares += r.roofline_shares([v], [f])
            except Stale:       # a row without a roofline (no flop count) or not run on this family
                pass
    if not shares:
        raise Stale(f"results.json has no {isa} row with a roofline")
    return shares


def block_bench_front_units(run: Run) -> list:
    d, f = run.stat("textbook_f64", "typical", "ulps_p99"), run.stat("lagrange_f32", "typical", "ulps_p99")
    return paragraph(
        "A variant is on its family's Pareto front when no other variant is at least as fast (median), at least as "
        "accurate (p99) and misclassifies no more rays, and better in one of these. A front only compares like with "
        "like. Scalar and vector variants have a front each. So do results counted in float ulps (float results, "
        "float in and out with double inside included) and results counted in double ulps (the double variants): a "
        f"float ulp is $2^{{29}}$ double ulps, so on *typical* the textbook form's p99 of {ulps(d)} double ulps "
        f"(double results) is far more accurate than the Lagrange form's {ulps(f)} float ulps (float results), and "
        "comparing the raw numbers would call it worse. A double row is therefore never marked dominated by a float "
        "row, nor a float row by a double one. In the plot each front is a staircase of its own: dashed for scalar "
        "float results, dash-dotted grey for scalar double results, dotted for the vector rows.")


def block_bench_reference(run: Run) -> list:
    r = Reading(run)
    lg, hb = "lagrange_f32_in_f64", "half-b_f32_in_f64"
    diff = [run.ns(lg, f) - run.ns(hb, f) for f in r.fids]
    lo, hi = min(diff), max(diff)
    moves = (f"from {ns(-lo)} ns less to {ns(hi)} ns more" if lo < 0 else f"from {ns(lo)} to {ns(hi)} ns more")
    _, pts = r.points()
    on = [p.family["id"] for p in pts if p.vid == hb and p.pareto and p.family["id"] in r.fids]
    e6, e8 = r.pbrt[-2:]
    among = [f"e = {f.split('_e')[1]}" for f in (e6, e8) if f in on]
    worst_pbrt = max(r.shares(hb, r.pbrt))
    mis = sum(r.stat(lg, "misclassified"))
    return paragraph(
        "The first version of this benchmark measured the kit's reference of the time — the stable form in float — "
        "and found it off the front of every hard family; the second made it half-b in double, which was on the front "
        "of every family measured then. pbrt's ranges then showed half-b in double misclassifying up to "
        f"{pct(worst_pbrt)} of the rays, so the reference changed again: step 02's `sphere_roots` "
        "(`solutions/02_general_sphere/general_sphere.cpp`) now computes the discriminant by Lagrange's identity in "
        "double, $a r^2 - |\\mathbf{f}\\times\\mathbf{d}|^2$, and rounds each root to float once. It is within "
        f"{ulps_of(max(r.stat(lg, 'ulps_max')))} ulps on all {count(len(r.fids))} families and misclassifies "
        f"{'nothing' if mis == 0 else f'{mis:.0f} rays'}; the price is {moves} per ray in the median than half-b in "
        f"double, family by family. Half-b in double is on the scalar front of {count(len(on))} families in this run"
        + (f", pbrt's {' and '.join(among)} among them, where it misclassifies "
           f"{' and '.join(pct(r.share(hb, f)) for f in (e6, e8) if f in on)} of the rays: a faster variant that "
           "misclassifies more is not dominated, so the front alone does not choose between them" if among else "")
        + ". The reference takes the form that misclassifies nothing: a reference that is wrong on "
        f"{pct(r.share(hb, e8))} of pbrt's own test rays is not one.")


def block_bench_kit_function(run: Run) -> list:
    r = Reading(run)
    lg = "lagrange_f32_in_f64"
    pack = [run.ns("kit", f) - run.ns(lg, f) for f in r.fids]
    same = r.same_errors("kit", lg)
    return paragraph(
        "The kit's function itself, as a student's code is called — two calls across library boundaries and its "
        f"checks for a radius that is no radius and a direction that is no direction — takes {span(r.ns('kit'), ns)} "
        f"ns and returns {'the same answers' if same else 'answers of the same accuracy'}: "
        f"{ns(statistics.median(pack))} ns of packaging over its formulation in the median family "
        f"({span(pack, ns)} ns).")


BOX_COLUMNS = ["brute_force", "call_plain", "call_optional", "kit_rect", "kit_scene", "embree_quads",
               "brute_force_x16_AVX3", "embree_quads_x16"]
BOX_ROWS = [("box_camera", "camera"), ("box_bounce", "bounce"), ("rect_camera", "camera, back wall alone")]


def block_bench_box_table(run: Run) -> list:
    def cell(v, f):
        return f"{ns2(run.ns(v, f))} ns" if (v, f) in run.rows else "—"
    lines = ["| rays | brute force, 6 rectangles | one call per rectangle, `bool` | one call per rectangle, "
             "`std::optional` | kit `intersect_rect` ×6 | kit `find_intersection` | Embree quads | brute force, 16 "
             "lanes | Embree, `rtcIntersect16` | error p99, brute force / Embree | they disagree by |",
             "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"]
    for f, name in BOX_ROWS:
        b = run.row("brute_force", f)
        lines.append(f"| {name} | " + " | ".join(cell(v, f) for v in BOX_COLUMNS)
                     + f" | {ulps(b['ulps_p99'])} / {ulps(run.stat('embree_quads', f, 'ulps_p99'))} ulps"
                     + f" | at most {b['vs_embree_max']:.0f} ulps |")
    return lines


BOX = ["box_camera", "box_bounce"]


def block_bench_box_embree(run: Run) -> list:
    r = Reading(run)
    faster = r.ratios("embree_quads", "brute_force", BOX)
    better = all(run.stat("brute_force", f, "ulps_p99") < run.stat("embree_quads", f, "ulps_p99") for f in BOX)
    return paragraph(
        f"Brute force is {span(faster, times)} times faster than Embree on the box here"
        + (" and more accurate" if better else "")
        + ": one subtraction and one divide per rectangle, where Embree splits each quad into two triangles and solves "
        "for the hit with more arithmetic. A bounding volume hierarchy pays off when it lets a ray skip most of the "
        "scene; six rectangles are less work to test than to skip.")


def block_bench_box_calls(run: Run) -> list:
    r = Reading(run)
    kit = r.ratios("kit_rect", "brute_force", BOX) + r.ratios("kit_scene", "brute_force", BOX)
    over = all(run.ns(v, f) > run.ns("embree_quads", f) for v in ("kit_rect", "kit_scene") for f in BOX)
    per_call = lambda v: [(run.ns(v, f) - run.ns("brute_force", f)) / 6 for f in BOX]
    same = r.same_errors("kit_rect", "brute_force", BOX) and r.same_errors("kit_scene", "brute_force", BOX)
    apart = [run.stat("brute_force", f, "vs_embree_max") for f in BOX]
    return paragraph(
        "How the loop is written matters as much as the arithmetic, and the table takes the kit's own loop apart. "
        f"The kit's step 04 and 05 functions give {'the same hits (same errors' if same else 'hits of the same accuracy ('}"
        f", at most {span(apart, lambda x: f'{x:.0f}')} ulps from Embree) but take {span(kit, times)} times as long "
        f"as the benchmark's loop{', and more than Embree' if over else ''}. The two middle columns run the "
        "benchmark's own rectangle test behind one out-of-line call per rectangle: returning a `bool` (with $t$ by "
        f"reference) it costs {span(per_call('call_plain'), ns)} ns per call more than the inlined loop in this run; "
        f"returning a `std::optional<float>`, the kit's interface, {span(per_call('call_optional'), ns)} ns per call.")


def block_bench_box_lanes(run: Run) -> list:
    r = Reading(run)
    packets = r.ns("embree_quads_x8", BOX) + r.ns("embree_quads_x16", BOX)
    return paragraph(
        f"With 16 float lanes it takes {span(r.ns('brute_force_x16_AVX3', BOX), ns2)} ns per ray on the whole box, "
        f"against {span(r.ns('brute_force', BOX), ns)} ns for the scalar loop ({span(r.ns('brute_force_x8_AVX2', BOX), ns2)}"
        " ns with 8 lanes). Embree's packet queries on the same quads (`rtcIntersect8` and `rtcIntersect16`, every "
        f"lane active) take {span(packets, lambda x: f'{x:.0f}')} ns per ray against "
        f"{span(r.ns('embree_quads', BOX), lambda x: f'{x:.0f}')} for its one-ray query here: its packets share a "
        "traversal, which six quads hardly need.")


def block_bench_box_claim(run: Run) -> list:
    r = Reading(run)
    plain = all(run.ns("call_plain", f) < run.ns("embree_quads", f) for f in BOX)
    return paragraph(
        "So the claim, measured: brute force over six rectangles, written as a renderer writes its inner loop, is "
        f"{span(r.ratios('embree_quads', 'brute_force', BOX), times)} times faster than Embree on this scene "
        f"({span(r.ratios('embree_quads_x16', 'brute_force_x16_AVX3', BOX), times)} times, 16 rays at a time against "
        "Embree's 16-ray packets)"
        + (", and stays faster with one call per rectangle as long as the call returns plainly. " if plain
           else ". Behind one call per rectangle it is not always faster. ")
        + 
        "The kit keeps `std::optional<float>` in its interface because it reads as the contract (\"a hit, or none\") "
        "to a student; a renderer built on these steps would inline the test or return a plain value.")


def block_bench_times(run: Run) -> list:
    load = run.meta.get("load_avg") or []
    spread = sorted(100 * (max(r["cpu_ns"]) / statistics.median(r["cpu_ns"]) - 1)
                    for r in run.data["results"] if r.get("cpu_ns"))
    if len(load) < 3 or not spread:
        raise Stale("results.json has no load average or no timed row")
    typical, tail = statistics.median(spread), spread[int(0.9 * (len(spread) - 1))]
    return wrap(
        f"**Times** were taken on a shared {run.meta.get('cpus', '?')}-core virtual machine, the committed run with "
        f"a load average of {load[0]:.2f} at its start ({load[1]:.2f} and {load[2]:.2f} over five and fifteen "
        f"minutes). Within the run, a row's slowest repetition is {typical:.0f} % above its median in the median "
        f"row, and {tail:.0f} % or more in one row of ten: compare medians, not single repetitions, and take "
        "differences of that size for noise. On a busier machine, read the min column. A change of host is not noise "
        "either (section 8): the table's first line names the processor's family and model.", bullet=True)


def block_bench_timed_pass(run: Run) -> list:
    """How one timed pass is made, from the run's own settings: the batch, its size in float (ten inputs a
    ray), the repetitions and the least time of each."""
    m = run.meta
    if not all(isinstance(m.get(k), (int, float)) for k in ("batch", "repetitions", "min_time")):
        raise Stale("results.json has no batch, repetitions or min_time")
    kib = m["batch"] * 10 * 4 / 1024
    return wrap(
        f"**The time.** Google Benchmark times one pass over the first {m['batch']} rays of a family "
        f"({kib:.0f} KiB in float: in cache; too many for the branch predictor to learn), {m['repetitions']} "
        f"repetitions of at least {1000 * m['min_time']:g} ms each, the repetitions of all variants interleaved at "
        "random (a fixed shuffle, made by the benchmark itself). Every variant is one out-of-line call per ray, "
        "like the kit's step functions, and writes its answer to memory. The table shows the median CPU time per ray "
        "with the fastest and slowest repetition.")


def block_lecture03_earth(run: Run) -> list:
    r = Reading(run)
    rows = [v for v, _ in LECTURE_VARIANTS if run.labels.get(v, "").endswith(", float") and v.endswith("_f32")]
    tops = {max(r.fids, key=lambda f: run.stat(v, f, "ulps_p99")) for v in rows}
    top = max(x for v in rows for x in r.stat(v, "ulps_p99"))
    where_ = (f"is one family: \"{label(run, tops.pop())}\" of `docs/bench.md`" if len(tops) == 1
              else "comes from the ground families of `docs/bench.md`")
    return paragraph(
        f"The top of every float row's p99 range, about {ulps(top)} ulps, {where_} (a sphere of radius "
        "$6.4\\cdot10^6$ seen from 1 to 2 units above it, looking just below the horizon), where "
        "$c' = \\mathbf{f}\\cdot\\mathbf{f} - r^2$ itself cancels. The ★ case \"the ground seen from a metre or two "
        "up\" of step 02 is drawn from the ground families.")


def block_lecture03_pbrt(run: Run) -> list:
    r = Reading(run)
    e8 = r.pbrt[-1]
    return paragraph(
        "The other cure is to compute in `double`, which has 29 more bits to lose. For half-b that is not always "
        f"enough: on pbrt's test ranges (\"{label(run, e8)}\" in the table above, origins up to "
        f"$10^{e8.split('_e')[1]}$ away from spheres as small as $10^{{-4}}$) $h^2$ and $ac'$ agree in more bits than "
        f"double has, and half-b in double still misclassifies {pct(r.share('half-b_f32_in_f64', e8))} of the rays "
        "(`docs/bench.md`, section 5). Lagrange's form of lecture 03, section 5, $a r^2 - |\\mathbf{f} \\times "
        "\\mathbf{d}|^2$, in double misclassifies "
        + ("none" if sum(r.stat("lagrange_f32_in_f64", "misclassified")) == 0 else "a few")
        + ": each product of two floats is exact in double, so it cancels only near a real tangent.")


def block_appendix_leg_cross(run: Run) -> list:
    r = Reading(run)
    fams = r.far[:2]
    bound = star_bound()
    leg, cross = "stable_f32", "lagrange_f32"
    def figs(v, key):
        return " and ".join(ulps(run.stat(v, f, key)) for f in fams)
    worst = [run.stat(v, f, "ulps_max") for v in (leg, cross) for f in fams]
    over = sum(1 for x in worst if x > bound)
    p99 = [run.stat(v, f, "ulps_p99") for v in (leg, cross) for f in fams]
    alike = "nearly the same" if max(p99) <= 1.2 * min(p99) else "different"
    order = "of the same order" if max(worst) <= 3 * min(worst) else "of different sizes"
    verdict = ("every one of these worst rays lies over" if over == len(worst) else
               "none of these worst rays lies over" if over == 0 else
               f"{count(over)} of these {count(len(worst))} worst rays lie over")
    return paragraph(
        "Lecture 03, section 5, gives two careful readings of the discriminant: the leg "
        "$r^2 - |\\mathbf{f} - h\\,\\mathbf{d}|^2$ and Lagrange's form $a r^2 - |\\mathbf{f} \\times \\mathbf{d}|^2$. "
        "The benchmark measures both in float on the same rays, against 113-bit roots of the same float inputs: the "
        "leg with the root pair of section 6 (its row *stable, float*, with $\\mathbf{f} - (h/a)\\,\\mathbf{d}$ for a "
        "direction of any length) and the cross product with the roots "
        "$(-h \\mp \\sqrt{D})/a$ (its row *lagrange, float*). The rays are its families "
        + " and ".join(f"*{label(run, f)}*" for f in fams)
        + f" (a unit sphere {' or '.join(radii(f).replace(' radii', '') for f in fams)} radii away, give or take a "
        f"tenth, two rays in three hit), {run.meta.get('rays', '?')} rays each from a fixed seed "
        f"(`bench/families.cpp`; `./kit bench` makes them again). On them the two have {alike} p99 error "
        f"({figs(leg, 'ulps_p99')} ulps for the leg, {figs(cross, 'ulps_p99')} for the cross product) and worst rays "
        f"{order}: {figs(leg, 'ulps_max')} ulps for the leg, {figs(cross, 'ulps_max')} for the cross product. "
        f"So on random rays {verdict} the ★ cases' bound of {bound} ulps (section B). The bound is a judgement on the "
        "rays of the ★ cases, not a promise for every ray a float can hold; which of those cases these forms pass, "
        "and what no float form reaches, is in section B.")


def block_appendix_lanes(run: Run) -> list:
    r = Reading(run)
    share = [100 / x for x in r.ratios("kit", REF_X8)]
    ff = r.ratios(FF_X16, REF_X8)
    return paragraph(
        "**The float/double trade-off can flip.** A double is twice as wide as a float, so a vector holds half as "
        "many: 4 doubles against 8 floats in AVX2. Scalar code does not see that (one number per instruction either "
        "way), which is why the kit's reference computes in double. In lanes the price is real, but on the CPU it is "
        "still the cheaper way to roots that misclassify no ray and stay within about an ulp: the benchmark "
        "(`./kit bench`, read in `docs/bench.md`, section 6) runs the reference, in double lanes, in "
        f"{span(share, lambda x: f'{x:.0f}')} % of the scalar reference's time, and a float-only form brought within "
        f"{ulps_of(max(r.stat(FF_X16, 'ulps_max')))} ulps by error-free transformations (each product and sum kept as a "
        f"float plus its rounding error) in {span(ff, times)} times the double lanes' time. These lanes are compiled "
        "for AVX2 and AVX-512, both with the fused multiply-add, and built with contraction off like the rest of the "
        "kit: the double lanes call it for their sums of products (fewer instructions, one rounding fewer), and the "
        "float-only form for its error-free products, since the rounding error $e$ of a product $p = a b$ is exactly "
        "`fma(a, b, -p)` (lecture 03, section 4). A GPU changes the "
        "arithmetic: there, double often runs at 1/32 or 1/64 of the float rate, so the float-only form, with "
        f"{r.flops(FF_X16) / r.flops(REF_X8):.1f} times as many float operations as the double lanes, becomes the "
        "faster way to answers that accurate.")


BLOCKS = {
    "lecture03-table": block_lecture03_table,
    "lecture03-earth": block_lecture03_earth,
    "lecture03-cost": block_lecture03_cost,
    "lecture03-pbrt": block_lecture03_pbrt,
    "lecture03-double": block_lecture03_double,
    "appendix-leg-cross": block_appendix_leg_cross,
    "appendix-lanes": block_appendix_lanes,
    "bench-formulations": block_bench_formulations,
    "bench-peaks": block_bench_peaks,
    "bench-far": block_bench_far,
    "bench-half-b": block_bench_half_b,
    "bench-stable": block_bench_stable,
    "bench-float-limits": block_bench_float_limits,
    "bench-double-accuracy": block_bench_double_accuracy,
    "bench-double-inside": block_bench_double_inside,
    "bench-pbrt": block_bench_pbrt,
    "bench-lagrange-cost": block_bench_lagrange_cost,
    "bench-ground": block_bench_ground,
    "bench-double-results": block_bench_double_results,
    "bench-embree-sphere": block_bench_embree_sphere,
    "bench-lanes": block_bench_lanes,
    "bench-choice": block_bench_choice,
    "bench-vector-roofline": block_bench_vector_roofline,
    "bench-vector-reference": block_bench_vector_reference,
    "bench-front-units": block_bench_front_units,
    "bench-reference": block_bench_reference,
    "bench-kit-function": block_bench_kit_function,
    "bench-box-table": block_bench_box_table,
    "bench-box-embree": block_bench_box_embree,
    "bench-box-calls": block_bench_box_calls,
    "bench-box-lanes": block_bench_box_lanes,
    "bench-box-claim": block_bench_box_claim,
    "bench-times": block_bench_times,
    "bench-timed-pass": block_bench_timed_pass,
}


# --- figures typed by hand ---------------------------------------------------------------------
#
# Outside a generated block (this script's, or another generator's such as docs/robust_numbers.py),
# the files above carry no figure with a unit: a time, a rate, an error, a share, a ratio, a load. Each
# pattern below is one way such a figure is written; the self-test (tests/kit/bench.py)
# plants each of them in a copy of the text and checks that it is found.

ANY_BEGIN = re.compile(r"^<!-- ([a-z_]+\.py): ([a-z0-9-]+) -->$")
ANY_END = re.compile(r"^<!-- /([a-z_]+\.py) -->$")
_WORD = (r"(?:one|two|three|four|five|six|seven|eight|nine|ten|eleven|twelve|thirteen|fourteen|fifteen|"
         r"sixteen|twenty|thirty|forty|fifty|hundred)")
_NUM = r"(?:TEXNUM|\d{1,3}(?:[ \u202f\u00a0]\d{3})+(?:\.\d+)?|\d+(?:\.\d+)?)"
_RANGE = rf"{_NUM}(?:\s*(?:to|–|-|and|or|/|→)\s*{_NUM})*"
_UNIT = r"(?:ns\b|µs\b|ms\b|s\b|min\b|[KMG]iB\b|[KMG]B\b|[MG]Hz\b|GFLOP/s|flops?\b|(?:double\s+|float\s+)?ulps?\b|\s?%|\s?per\s?cent\b|\s?×|x\b|times\b)"
FIGURE = re.compile("|".join([
    rf"(?<![\w.\-^{{}}])~?{_RANGE}\s*{_UNIT}",                                    # 7.1 to 9.4 ns, 45 %, 2.2×
    rf"\b{_WORD}\s+(?:times\b|ulps?\b|%|per\s?cent\b)",                             # about three times
    r"\b(?:a|one|two|three)\s+(?:half|halves|third|thirds|quarter|quarters|fifth|fifths|tenth|tenths)\s+(?:of|as)\b",
    r"\band\s+a\s+half\b",                                                          # an ulp and a half
    rf"\bload\s+average\b[^.;\d]{{0,30}}{_NUM}",                                    # load average 2.2
    rf"\b(?:p99|median|maximum|max|largest\s+error)\s+(?:of\s+)?(?:about\s+)?{_NUM}",  # p99 53000
]))


def defined_figures() -> list:
    """Figures that are definitions, not measurements, each allowed only as this exact phrase: the ★ cases'
    bound (as docs/robust_numbers.py grades by it) and the size of a float ulp in double ulps."""
    return [f"The bound is **{star_bound()} ulps**", "a float ulp is $2^{29}$ double ulps"]


def _blank(m) -> str:
    return "CODE" + "\n" * m.group(0).count("\n")


def typed_figures(text: str, defined: list | None = None) -> list:
    """(line, figure) for every figure with a unit outside a generated block, a code fence or an HTML
    comment. Figures may be split across lines; the line is where the figure starts."""
    kept, inside, fence = [], None, False
    for line in text.split("\n"):
        if line.startswith("```"):
            fence = not fence
            kept.append("")
        elif fence:
            kept.append("")
        elif ANY_BEGIN.match(line):
            inside = ANY_BEGIN.match(line).group(1)
            kept.append("")
        elif ANY_END.match(line):
            inside = None
            kept.append("")
        else:
            kept.append("" if inside else line)
    body = "\n".join(kept)
    for phrase in defined_figures() if defined is None else defined:
        body = body.replace(phrase, "DEFINED")
    body = re.sub(r"<!--.*?-->", _blank, body, flags=re.S)
    body = re.sub(r"`[^`]*`", _blank, body)
    body = re.sub(r"\$[^$\n]*\d[^$\n]*\$", "TEXNUM", body)
    return [(body.count("\n", 0, m.start()) + 1, " ".join(m.group(0).split())) for m in FIGURE.finditer(body)]


def typed_in_files(files: list) -> list:
    """'file:line: figure' for every typed figure in the files."""
    out = []
    for path in files:
        if path.is_file():
            out += [f"{path.name}:{n}: {fig}" for n, fig in typed_figures(path.read_text())]
    return out


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
        typed = typed_in_files(FILES)
    except Stale as e:
        print(f"bench_numbers.py: {e}", file=sys.stderr)
        return 2
    if typed:
        # Not something this script can rewrite: the figure must move into a block, or go.
        print("figures typed by hand outside a generated block (generate them or reword without a number):\n  "
              + "\n  ".join(typed), file=sys.stderr)
    if args.check and stale:
        print("stale, run python3 docs/bench_numbers.py: " + ", ".join(stale), file=sys.stderr)
        return 1
    print(("stale: " if args.check else "rewrote: ") + (", ".join(stale) if stale else "nothing, every block is current"))
    return 1 if typed else 0


if __name__ == "__main__":
    sys.exit(main())

"""The benchmark's report: statistics, the Pareto front, the table, the CSV and the plot.

raykit_bench (bench/main.cpp) writes raw results as JSON: per variant and ray
family, the error statistics and the time of every repetition. This module turns
them into what people read. Nothing here measures anything.
"""

from __future__ import annotations

import csv
import io
import math
import statistics
from dataclasses import dataclass, field

from . import charts

# --- one measured point ------------------------------------------------------------


@dataclass
class Point:
    """One variant on one family of rays."""

    variant: dict
    family: dict
    raw: dict
    ns: list[float] = field(default_factory=list)        # CPU ns per ray, each repetition
    ns_real: list[float] = field(default_factory=list)   # wall-clock ns per ray
    pareto: bool = False
    dominated_by: list[str] = field(default_factory=list)

    @property
    def vid(self) -> str:
        return self.variant["id"]

    @property
    def timed(self) -> bool:
        return bool(self.ns)

    @property
    def ns_median(self) -> float:
        return statistics.median(self.ns) if self.ns else math.nan

    @property
    def ns_min(self) -> float:
        return min(self.ns) if self.ns else math.nan

    @property
    def ns_max(self) -> float:
        return max(self.ns) if self.ns else math.nan

    def ulps(self, which: str) -> float:
        v = self.raw.get(f"ulps_{which}")
        return math.inf if v is None else float(v)  # null: an infinite or NaN answer

    @property
    def lanes(self) -> int:
        return int(self.variant.get("lanes") or 1)

    @property
    def regime(self) -> str:
        """"scalar" (one call per ray) or "vector" (many rays per operation)."""
        return "vector" if self.lanes > 1 else "scalar"

    @property
    def result_type(self) -> str:
        """The type the error is counted in ("float" or "double"): a float ulp is 2^29 double ulps, so
        raw ulps compare only within one result type."""
        return self.variant.get("ulp_of") or self.variant["precision"]

    @property
    def judged(self) -> int:
        return self.raw["rays"] - self.raw["in_band"]

    @property
    def misclassified_share(self) -> float:
        return self.raw["misclassified"] / self.judged if self.judged else 0.0

    def roofline_ns(self, peak: dict) -> float | None:
        """The roofline: the least time this arithmetic needs on one core. The
        adds and multiplies at the peak rate, the divides and the square roots
        each at the divider's pace, and for double lanes on float rays one
        conversion per input and per result at the measured conversion rate
        (arithmetic the flop count does not see and the form cannot skip).
        Scalar variants at the scalar rates; a vector variant at the rates
        measured with its own vectors, per lane. There the rate is measured
        with fused multiply-adds (two flops each), and the adds and multiplies
        count as instructions: a fused pair, a lone add and a lone multiply
        take one each (the count's "fma" says how many pairs were fused). A run
        from before that count takes each flop at the FMA rate, which credits
        a lone add with half an instruction: optimistic.

        Terms on different units bound the time each on its own: the bound is
        the longest. Two terms that compete for one unit add up instead, and a
        vector target measures how much (shared_*, 0 to 1: what a loop of both
        kernels adds of the shorter one's time to the longer one's): divides
        with square roots (one divider on the cores measured so far), and the
        multiply-adds with the conversions. A run or a term without that
        measurement (scalar rates, runs before it) counts 0: the longest term,
        the optimistic bound."""
        flops = self.raw.get("flops")
        if flops is None or not peak:
            return None
        wide = self.variant["precision"] != "float"
        kind = "f64" if wide else "f32"
        cvt_ns = 0.0
        shared_units, shared_divider = 0.0, 0.0
        if self.lanes > 1:
            target = next((t for t in peak.get("vector_targets") or [] if t["isa"] == self.variant.get("isa")), None)
            if target is None:
                return None
            rate, div_ns, sqrt_ns = target[f"gflops_{kind}"], target[f"div_ns_{kind}"], target[f"sqrt_ns_{kind}"]
            cvt_ns = target.get("cvt_ns") or 0.0
            shared_units = target.get("shared_fma_cvt") or 0.0
            shared_divider = target.get("shared_div_sqrt") or 0.0
        else:
            rate = peak[f"scalar_gflops_{kind}"]
            div_ns = peak[f"div_ns_{kind}"]
            sqrt_ns = peak[f"sqrt_ns_{kind}"]
        if not rate:
            return None
        add_mul = flops - self.raw["div"] - self.raw["sqrt"]
        arith_ns = add_mul / rate
        fused = self.raw.get("fma")
        if self.lanes > 1 and fused is not None:
            # The vector rate is measured with FMAs, two flops an instruction. A lone add or multiply
            # takes an instruction of the same units too, not half of one: the time is the
            # instructions (an FMA, an add, a multiply: one each) at half the flop rate.
            arith_ns = (add_mul - fused) * 2 / rate
        return max(combined(arith_ns, (self.raw.get("cvt") or 0) * cvt_ns, shared_units),
                   combined(self.raw["div"] * div_ns, self.raw["sqrt"] * sqrt_ns, shared_divider))


def combined(a: float, b: float, shared: float) -> float:
    """Two terms of the roofline: the longer, plus the measured share of the shorter (0 to 1) that the
    two do not overlap."""
    return max(a, b) + min(max(shared, 0.0), 1.0) * min(a, b)


def points(data: dict) -> list[Point]:
    variants = {v["id"]: v for v in data["variants"]}
    families = {f["id"]: f for f in data["families"]}
    return [Point(variants[r["variant"]], families[r["family"]], r, list(r.get("cpu_ns") or []),
                  list(r.get("real_ns") or [])) for r in data["results"]]


def merge_student(data: dict, student: dict | None, status: str, label: str) -> None:
    """Adds the student's sphere function to the reference run as variant "student".

    The student's code runs in its own process (its functions have the same
    names as the kit's), timed apart from the reference run, so its times are
    put on the reference run's scale: both runs time the same calibration loop
    (a fixed amount of arithmetic), and the student's times are multiplied by
    the ratio of its medians."""
    variant = {"id": "student", "formulation": "student", "label": label, "precision": "float",
               "group": "sphere", "ulp_of": "float", "lanes": 1, "isa": "", "status": status,
               "note": "built from steps/"}
    if student is not None:
        for v in student["variants"]:
            if v["id"] == "kit":
                variant["status"] = v["status"]
                variant["note"] = "your code in steps/: " + v["note"]
        ref_cal, own_cal = data["meta"].get("calibration_ns"), student["meta"].get("calibration_ns")
        k = ref_cal / own_cal if ref_cal and own_cal else None
        known = {f["id"] for f in data["families"]}
        skipped = sorted({r["family"] for r in student["results"] if r["family"] not in known})
        for r in student["results"]:
            if r["variant"] != "kit" or r["family"] not in known:  # a family the reference run lacks
                continue
            row = dict(r, variant="student")
            if k is not None:
                row["cpu_ns"] = [t * k for t in r["cpu_ns"]]
                row["real_ns"] = [t * k for t in r.get("real_ns") or []]
            else:
                row["cpu_ns"], row["real_ns"] = [], []
            data["results"].append(row)
        if skipped:
            variant["note"] += f"; not shown (the reference run has no such family): {', '.join(skipped)}"
        if k is not None:
            variant["note"] += (f"; timed in its own process, times scaled by the calibration loop's ratio between "
                                f"the runs (x{k:.2f})")
        else:
            variant["note"] += "; not timed on the reference run's scale (no calibration in one of the runs)"
    data["variants"].append(variant)


# --- the Pareto front ----------------------------------------------------------------


def dominates(a: Point, b: Point) -> bool:
    """a is at least as fast, as accurate (p99) and misclassifies no more rays than
    b, and better in one of them."""
    ka = (a.ns_median, a.ulps("p99"), a.raw["misclassified"])
    kb = (b.ns_median, b.ulps("p99"), b.raw["misclassified"])
    return all(x <= y for x, y in zip(ka, kb)) and ka != kb


def front_key(p: Point) -> tuple[str, str, str]:
    """The front a point belongs to: its family, its regime and its result type."""
    return p.family["id"], p.regime, p.result_type


def mark_pareto(pts: list[Point]) -> None:
    """One front per family, regime and result type: scalar variants (one call per
    ray) are compared with each other, vector variants (a batch per call) likewise,
    and a variant whose error is counted in float ulps only with others counted in
    float ulps, double with double (a float ulp is 2^29 double ulps: a raw p99
    compared across the two says nothing)."""
    by_family: dict[tuple[str, str, str], list[Point]] = {}
    for p in pts:
        if p.timed:
            by_family.setdefault(front_key(p), []).append(p)
    for group in by_family.values():
        for p in group:
            p.dominated_by = [q.vid for q in group if q is not p and dominates(q, p)]
            p.pareto = not p.dominated_by


def clearly_faster(a: Point, b: Point) -> bool:
    """a's slowest repetition beats b's fastest: faster beyond the noise."""
    return a.ns_max < b.ns_min


# --- formatting ------------------------------------------------------------------------


def fmt_ulps(x: float) -> str:
    if math.isinf(x) or math.isnan(x):
        return "inf"
    if x < 10:
        return f"{x:.2f}"
    if x < 1e5:
        return f"{x:.0f}"
    return f"{x:.1e}"


def fmt_ns(x: float) -> str:
    return "-" if math.isnan(x) else (f"{x:.1f}" if x < 100 else f"{x:.0f}")


def fmt_share(p: Point) -> str:
    if p.raw["misclassified"] == 0:
        return "0"
    s = 100 * p.misclassified_share
    return f"{s:.2g}%" if s >= 0.01 else f"{p.raw['misclassified']} rays"


def fmt_opt(x: float | None, spec: str) -> str:
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, spec)


def precision_word(v: dict) -> str:
    return {"float": "float", "double": "double", "float, double inside": "f in, d inside"}.get(
        v["precision"], v["precision"])


def family_groups(data: dict, pts: list[Point]):
    """(family, its points: the scalar variants first, each in the variants' order) for each family
    that has points, in the families' order."""
    order = {v["id"]: i for i, v in enumerate(data["variants"])}
    for fam in data["families"]:
        group = sorted((p for p in pts if p.family["id"] == fam["id"]), key=lambda p: (p.lanes > 1, order.get(p.vid, 99)))
        if group:
            yield fam, group


def peak_line(data: dict) -> str:
    p = data.get("peak") or {}
    m = data["meta"]
    if not p.get("scalar_gflops_f32"):
        return f"CPU: {m['cpu']}"
    vec = (f", {p['vector_isa']} {p['vector_gflops_f32']:.0f} GFLOP/s float / {p['vector_gflops_f64']:.0f} double"
           if p.get("vector_gflops_f32") else "")
    cpu_id = f" ({m['cpu_id']})" if m.get("cpu_id") else ""
    line = (f"CPU: {m['cpu']}{cpu_id}, {m['cpus']} cores. One core's peak: scalar add/multiply "
            f"{p['scalar_gflops_f32']:.1f} GFLOP/s{vec}; a divide takes {p['div_ns_f32']:.2f} ns (float) / "
            f"{p['div_ns_f64']:.2f} ns (double), a square root {p['sqrt_ns_f32']:.2f} / {p['sqrt_ns_f64']:.2f} ns "
            f"when many are in flight.")
    for t in p.get("vector_targets") or []:
        line += (f" {t['isa']} ({t['lanes_f32']} floats, {t['lanes_f64']} doubles): FMA {t['gflops_f32']:.0f} / "
                 f"{t['gflops_f64']:.0f} GFLOP/s, per lane a divide {t['div_ns_f32']:.3f} / {t['div_ns_f64']:.3f} ns, "
                 f"a square root {t['sqrt_ns_f32']:.3f} / {t['sqrt_ns_f64']:.3f} ns"
                 + (f", a float-double conversion {t['cvt_ns']:.3f} ns." if t.get("cvt_ns") else "."))
    if m.get("highway") and not p.get("vector_targets"):
        line += f" Vector rows: {m['highway']}."
    return line


def compiler_text(meta: dict) -> str:
    """"GCC 12.2.0": the compiler's __VERSION__, named. GCC's is the bare number; Clang's names itself."""
    v = str(meta.get("compiler", "")).strip()
    return f"GCC {v}" if v[:1].isdigit() else v


def subtitle(data: dict) -> str:
    """One short line under the plot's title: the machine and the settings."""
    m, p = data["meta"], data.get("peak") or {}
    peak = (f"; one core's peak {p['scalar_gflops_f32']:.1f} GFLOP/s scalar, {p['vector_gflops_f32']:.0f} with "
            f"{p['vector_isa']} (float)" if p.get("scalar_gflops_f32") and p.get("vector_gflops_f32") else "")
    return (f"{m['cpu']}{peak}; {compiler_text(m)} {m['flags']}; {m['rays']} rays per family, "
            f"{m['repetitions']} repetitions")


def table_text(data: dict, pts: list[Point], statuses: list[str]) -> str:
    """The terminal table: one block per family."""
    peak = data.get("peak") or {}
    out = io.StringIO()
    w = out.write
    m = data["meta"]
    w(f"{peak_line(data)}\n")
    w(f"Compiled with {compiler_text(m)} {m['flags']}; {m['rays']} rays per family, {m['repetitions']} timed "
      f"repetitions of {m['batch']} rays each (median [min-max] of CPU time).\n")
    w("Error: in ulps of the result type against float128, over the rays both call a hit; rays within "
      f"{m['tangent_band']:g} r of a tangent (the family's band where it says so) or {m['edge_band']:g} of an "
      "edge are not judged.\n")
    w("◆ on the speed/error Pareto front of its family (median time, p99 error, misclassified rays). A front "
      "compares like with like: scalar and vector variants have a front each, and float results (float ulps) and "
      "double results (double ulps) have a front each, so a double row is never marked dominated by a float row "
      "or the other way round.\n")
    header = (f"  {'':2}{'variant':<34}{'type':<15}{'ns/ray':>7} {'[min-max]':<13}{'median':>8}{'p99':>8}"
              f"{'max':>8}  {'misclassified':>13}{'flops':>7}{'roofl.':>7}\n")
    for fam, group in family_groups(data, pts):
        hard = " (hard)" if fam.get("hard") else ""
        band = f" Tangent band {fam['tangent_band']:g} r." if fam.get("tangent_band") else ""
        w(f"\n{fam['label']}{hard}: {fam['description']}.{band}\n")
        w(header)
        regime = "scalar"
        for p in group:
            if p.regime != regime:
                regime = p.regime
                w(f"  {'':2}vector: a batch of rays per call, rays as a structure of arrays (its own ◆ front)\n")
            mark = "◆" if p.pareto else " "
            span = f"[{fmt_ns(p.ns_min)}-{fmt_ns(p.ns_max)}]" if p.timed else ""
            bound = p.roofline_ns(peak)
            pct = f"{100 * bound / p.ns_median:.0f}%" if bound and p.timed else "-"
            flops = fmt_opt(p.raw.get("flops"), ".0f")
            w(f"  {mark} {p.variant['label'][:33]:<34}{precision_word(p.variant):<15}{fmt_ns(p.ns_median):>7} "
              f"{span:<13}{fmt_ulps(p.ulps('median')):>8}{fmt_ulps(p.ulps('p99')):>8}{fmt_ulps(p.ulps('max')):>8}"
              f"  {fmt_share(p):>13}{flops:>7}{pct:>7}\n")
            if p.variant["group"] == "box" and p.raw.get("vs_embree_compared"):
                w(f"      {'':34}hit distance vs Embree: median {fmt_ulps(p.raw['vs_embree_median'])}, "
                  f"p99 {fmt_ulps(p.raw['vs_embree_p99'])}, max {fmt_ulps(p.raw['vs_embree_max'])} ulps\n")
    w("\nroofline: the least time the counted arithmetic needs on one core (adds and multiplies at the peak rate, "
      "divides and square roots at the divider's pace, and for double lanes on float rays the widening of each "
      "input and narrowing of each result at the conversion pace: scalar rates for scalar variants, the rates of "
      "their own vectors for vector ones, where an FMA, a lone add and a lone multiply take one instruction each; "
      "the slowest of these), as a share of the measured time; 100% would be "
      "the machine's limit.\n")
    for s in statuses:
        w(s + "\n")
    return out.getvalue()


def student_summary(data: dict, pts: list[Point]) -> list[str]:
    """A few lines after the tables: the student's step on each family, its rank among the scalar
    variants by speed and by p99 error, its time beside the kit's reference (variant "kit"), whether
    it is on the front; then its worst error. Empty when the student's step was not measured."""
    mine = {p.family["id"]: p for p in pts if p.vid == "student"}
    if not mine:
        return []
    label = next((v["label"] for v in data["variants"] if v["id"] == "student"), "your step")
    out = [f"{label}, in short (rank among the scalar variants of each family, 1 the best; by error only among "
           f"those with the same result type):"]
    width = max(len(f["label"]) for f in data["families"] if f["id"] in mine)
    for fam in data["families"]:
        p = mine.get(fam["id"])
        if p is None:
            continue
        rivals = [q for q in pts if q.family["id"] == fam["id"] and q.regime == "scalar"]
        kit = next((q for q in rivals if q.vid == "kit"), None)
        timed = [q for q in rivals if q.timed]
        speed = (f"{fmt_ns(p.ns_median)} ns/ray, rank {1 + sum(q.ns_median < p.ns_median for q in timed)} of "
                 f"{len(timed)}" if p.timed else "not timed")
        if kit is not None and kit.timed and p.timed:
            speed += f" (the kit's {fmt_ns(kit.ns_median)})"
        alike = [q for q in rivals if q.result_type == p.result_type]   # ulps of one type only
        error = (f"p99 {fmt_ulps(p.ulps('p99'))} {p.result_type} ulps, rank "
                 f"{1 + sum(q.ulps('p99') < p.ulps('p99') for q in alike)} of {len(alike)} {p.result_type} results"
                 + (f" (the kit's {fmt_ulps(kit.ulps('p99'))})" if kit is not None else ""))
        wrong = f", {fmt_share(p)} of the rays misclassified" if p.raw.get("misclassified") else ""
        out.append(f"  {'◆' if p.pareto else ' '} {fam['label']:<{width}}  {speed}; {error}{wrong}")
    worst = max(mine.values(), key=lambda p: p.ulps("max"))
    out.append(f"  worst error: {fmt_ulps(worst.ulps('max'))} ulps, on {worst.family['label']}"
               + (f"; {sum(p.raw.get('misclassified', 0) for p in mine.values())} rays misclassified in all"
                  if any(p.raw.get("misclassified") for p in mine.values()) else "; no ray misclassified"))
    return out


CSV_FIELDS = ["group", "family", "family_label", "hard", "variant", "label", "formulation", "precision",
              "lanes", "isa", "ulp_of", "rays", "in_band", "compared", "misclassified", "misclassified_share", "ulps_median",
              "ulps_p99", "ulps_max", "ns_median", "ns_min", "ns_max", "ns_real_median", "repetitions", "flops",
              "div", "sqrt", "cvt", "roofline_ns", "gflops", "pareto", "dominated_by", "vs_embree_median", "vs_embree_p99",
              "vs_embree_max"]


def csv_text(data: dict, pts: list[Point]) -> str:
    peak = data.get("peak") or {}
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=CSV_FIELDS, lineterminator="\n")
    writer.writeheader()

    def num(x, digits=4):
        if x is None:
            return ""
        if isinstance(x, float) and (math.isinf(x) or math.isnan(x)):
            return "inf" if math.isinf(x) else ""
        return f"{x:.{digits}g}" if isinstance(x, float) else str(x)

    for p in pts:
        flops = p.raw.get("flops")
        row = {"group": p.variant["group"], "family": p.family["id"], "family_label": p.family["label"],
               "hard": int(bool(p.family.get("hard"))), "variant": p.vid, "label": p.variant["label"],
               "lanes": p.lanes, "isa": p.variant.get("isa") or "", "misclassified_share": num(p.misclassified_share),
               "ns_median": num(p.ns_median), "ns_min": num(p.ns_min), "ns_max": num(p.ns_max),
               "ns_real_median": num(statistics.median(p.ns_real) if p.ns_real else math.nan),
               "repetitions": len(p.ns), "roofline_ns": num(p.roofline_ns(peak)),
               "gflops": num(flops / p.ns_median if flops is not None and p.timed else None),
               "pareto": int(p.pareto), "dominated_by": " ".join(p.dominated_by)}
        row.update({k: p.variant[k] for k in ("formulation", "precision", "ulp_of")})
        row.update({k: p.raw[k] for k in ("rays", "in_band", "compared", "misclassified")})
        row.update({f"ulps_{k}": num(p.ulps(k)) for k in ("median", "p99", "max")})
        row.update({k: num(p.raw.get(k)) for k in ("flops", "div", "sqrt", "cvt", "vs_embree_median", "vs_embree_p99",
                                                   "vs_embree_max")})
        writer.writerow(row)
    return out.getvalue()


def markdown_table(data: dict, pts: list[Point]) -> str:
    """The same numbers as the terminal table, for the docs."""
    peak = data.get("peak") or {}
    lines = ["<!-- written by ./kit bench; do not edit -->", "", peak_line(data), ""]
    m = data["meta"]
    lines.append(f"Compiled with {compiler_text(m)} `{m['flags']}`; {m['rays']} rays per family; "
                 f"{m['repetitions']} timed repetitions of {m['batch']} rays (median, min and max of CPU time). "
                 f"Errors in ulps of the result type against float128; ◆ marks the Pareto front, one front for "
                 f"the float results and one for the double results (a float ulp is 2^29 double ulps), scalar "
                 f"and vector apart.")
    for fam, group in family_groups(data, pts):
        band = fam.get("tangent_band")
        lines += ["", f"### {fam['label']}{' (hard)' if fam.get('hard') else ''}", "",
                  fam["description"] + "." + (f" Tangent band {band:g} r." if band else ""), "",
                  "| | variant | type | ns/ray | min-max | median | p99 | max | misclassified | flops | roofline |",
                  "|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|"]
        regime = "scalar"
        for p in group:
            if p.regime != regime:
                regime = p.regime
                lines.append("| | **vector**: a batch of rays per call (own front) | | | | | | | | | |")
            bound = p.roofline_ns(peak)
            pct = f"{100 * bound / p.ns_median:.0f}%" if bound and p.timed else "-"
            lines.append(
                f"| {'◆' if p.pareto else ''} | {p.variant['label']} | {precision_word(p.variant)} | "
                f"{fmt_ns(p.ns_median)} | {fmt_ns(p.ns_min)}-{fmt_ns(p.ns_max)} | {fmt_ulps(p.ulps('median'))} | "
                f"{fmt_ulps(p.ulps('p99'))} | {fmt_ulps(p.ulps('max'))} | {fmt_share(p)} | "
                f"{fmt_opt(p.raw.get('flops'), '.0f')} | {pct} |")
    return "\n".join(lines) + "\n"


# --- the plot ------------------------------------------------------------------------

COLOURS = {
    "textbook": "#d62728", "half-b": "#ff7f0e", "unit-dir": "#bcbd22", "geometric": "#8c564b",
    "stable": "#1f77b4", "lagrange": "#6a3d9a", "exact-float": "#17becf", "kit": "#000000", "student": "#e377c2", "embree": "#2ca02c",
    "brute force": "#1f77b4",
}
SHAPES = {"float": "circle", "double": "square", "float, double inside": "diamond"}
# One staircase per front (regime, result type): float ulps and double ulps are never joined.
FRONT_STYLES = {("scalar", "float"): ("#333", "4,3"), ("scalar", "double"): ("#999", "8,3,2,3"),
                ("vector", "float"): ("#6a3d9a", "1.5,2.5"), ("vector", "double"): ("#c5b0d5", "1.5,2.5")}


def short_name(v: dict) -> str:
    """A few characters for a point's label in the plot."""
    special = {"kit": "kit", "student": "yours", "embree": "Embree", "brute force": "brute force"}
    lanes = f" ×{v['lanes']}" if (v.get("lanes") or 1) > 1 else ""
    if v["formulation"] in special:
        return special[v["formulation"]] + lanes
    return (v["formulation"] + {"float": " f", "double": " d", "float, double inside": " f/d"}.get(v["precision"], "")
            + lanes)


def plot_svg(data: dict, pts: list[Point]) -> str:
    """ns/ray against p99 error, log-log, one panel per family, the Pareto front as
    a dashed staircase, the kit's reference ringed."""
    fams = [f for f in data["families"] if any(p.family["id"] == f["id"] and p.timed for p in pts)]
    timed = [p for p in pts if p.timed]
    floor = 0.1  # errors below 0.1 ulp are drawn at 0.1
    cols, pw, ph = 3, 330, 250
    ml, mr, mt, mb = 58, 12, 30, 40
    legend_h = 118
    rows = max(1, math.ceil(len(fams) / cols))
    width, height = cols * pw + 20, legend_h + rows * ph + 10
    xs = [p.ns_min for p in timed] + [p.ns_max for p in timed]
    # One time axis for every panel, a little wider than the data.
    x0, x1 = (math.log10(max(min(xs), 1e-3) / 1.15), math.log10(max(xs) * 1.15)) if xs else (0.0, 2.0)
    s = [charts.svg_open(width, height),
         '<text x="10" y="20" font-size="15" font-weight="bold">Speed against error: ns per ray (CPU time, '
         'median, bar min-max) against p99 error in ulps of the result type</text>',
         f'<text x="10" y="38" fill="#444">{charts.esc(subtitle(data))}</text>']
    # legend
    lx, ly = 10, 58
    for i, (name, colour) in enumerate([(k, v) for k, v in COLOURS.items() if k != "brute force"]):
        x = lx + (i % 10) * 98
        s.append(charts.marker("circle", x + 5, ly, 5, colour, colour, 1))
        label = {"kit": "kit reference", "student": "your step", "embree": "Embree"}.get(name, name)
        s.append(f'<text x="{x + 14}" y="{ly + 4}">{charts.esc(label)}</text>')
    ly += 20
    for i, (name, shape) in enumerate(SHAPES.items()):
        x = lx + i * 200
        s.append(charts.marker(shape, x + 5, ly, 5, "#888", "#888", 1))
        word = {"float": "float (float ulps)", "double": "double (double ulps)",
                "float, double inside": "float in/out, double inside"}[name]
        s.append(f'<text x="{x + 14}" y="{ly + 4}">{word}</text>')
    s.append(charts.marker("circle", lx + 605, ly, 5, "white", "#888", 1.5))
    s.append(f'<text x="{lx + 614}" y="{ly + 4}">hollow: misclassifies some rays</text>')
    ly += 20
    s.append(f'<path d="M{lx},{ly} h24" stroke="#333" stroke-dasharray="4,3" fill="none"/>')
    s.append(f'<text x="{lx + 30}" y="{ly + 4}">scalar front, float results</text>')
    s.append(f'<path d="M{lx + 205},{ly} h24" stroke="#999" stroke-width="1.2" stroke-dasharray="8,3,2,3" '
             f'fill="none"/>')
    s.append(f'<text x="{lx + 235}" y="{ly + 4}">scalar front, double results</text>')
    s.append(f'<path d="M{lx + 415},{ly} h24" stroke="#6a3d9a" stroke-width="1.2" stroke-dasharray="1.5,2.5" '
             f'fill="none"/>')
    s.append(f'<text x="{lx + 445}" y="{ly + 4}">vector front</text>')
    s.append(charts.marker("circle", lx + 530, ly, 5, "#888", "#888", 1))
    s.append(f'<circle cx="{lx + 530}" cy="{ly}" r="1.4" fill="#000"/>')
    s.append(f'<text x="{lx + 540}" y="{ly + 4}">vector: a batch of rays per call</text>')
    s.append(f'<circle cx="{lx + 750}" cy="{ly}" r="9" fill="none" stroke="#000" stroke-width="1.2"/>')
    s.append(f'<text x="{lx + 764}" y="{ly + 4}">the kit\'s reference solution</text>')
    ly += 18
    s.append(f'<text x="{lx}" y="{ly + 4}" fill="#444">Errors below {floor} ulp are drawn at {floor}; '
             f'Embree\'s sphere error is that of its first hit only. A front joins only points of one result type: '
             f'a float ulp is 2^29 double ulps.</text>')

    for k, fam in enumerate(fams):
        ox, oy = 10 + (k % cols) * pw, legend_h + (k // cols) * ph
        group = [p for p in timed if p.family["id"] == fam["id"]]
        ys = [max(p.ulps("p99"), floor) for p in group if not math.isinf(p.ulps("p99"))]
        y0, y1 = charts.decades(min(ys) if ys else floor, max(ys) if ys else 1)
        iw, ih = pw - ml - mr, ph - mt - mb

        def px(ns: float) -> float:
            return ox + ml + (math.log10(ns) - x0) / (x1 - x0) * iw

        def py(u: float) -> float:
            u = max(u, floor)
            return oy + mt + ih - (math.log10(u) - y0) / (y1 - y0) * ih

        title = fam["label"] + (" (hard)" if fam.get("hard") else "")
        s.append(f'<text x="{ox + ml}" y="{oy + 18}" font-weight="bold">{charts.esc(title)}</text>')
        s.append(f'<rect x="{ox + ml}" y="{oy + mt}" width="{iw}" height="{ih}" fill="#fafafa" stroke="#999"/>')
        for v in charts.ticks_125(10 ** x0, 10 ** x1):
            x = px(v)
            s.append(f'<path d="M{x:.1f},{oy + mt} v{ih}" stroke="#e3e3e3"/>')
            s.append(f'<text x="{x:.1f}" y="{oy + mt + ih + 14}" text-anchor="middle">{v:g}</text>')
        for e in range(y0, y1 + 1):
            y = py(10 ** e)
            s.append(f'<path d="M{ox + ml},{y:.1f} h{iw}" stroke="#e3e3e3"/>')
            s.append(f'<text x="{ox + ml - 4}" y="{y + 4:.1f}" text-anchor="end">{10 ** e:g}</text>')
        s.append(f'<text x="{ox + ml + iw / 2}" y="{oy + mt + ih + 30}" text-anchor="middle" fill="#444">'
                 f'ns per ray</text>')
        s.append(f'<text transform="translate({ox + 14},{oy + mt + ih / 2}) rotate(-90)" text-anchor="middle" '
                 f'fill="#444">p99 error, ulps</text>')
        # the fronts, scalar and vector: a staircase through each one's points, fastest first
        for (regime, kind), (colour, dash) in FRONT_STYLES.items():
            front = sorted((p for p in group if p.pareto and p.regime == regime and p.result_type == kind
                            and not math.isinf(p.ulps("p99"))), key=lambda p: p.ns_median)
            if front:
                d = f"M{px(front[0].ns_median):.1f},{oy + mt}"
                d += f" V{py(front[0].ulps('p99')):.1f}"
                for a in front[1:]:
                    d += f" H{px(a.ns_median):.1f} V{py(a.ulps('p99')):.1f}"
                d += f" H{ox + ml + iw}"
                s.append(f'<path d="{d}" stroke="{colour}" stroke-width="1.2" stroke-dasharray="{dash}" fill="none"/>')
        labels: list[tuple[Point, float, float]] = []
        for p in sorted(group, key=lambda p: p.pareto):
            u = p.ulps("p99")
            y = py(u) if not math.isinf(u) else oy + mt + 4
            colour = COLOURS.get(p.variant["formulation"], "#777")
            s.append(f'<path d="M{px(p.ns_min):.1f},{y:.1f} H{px(p.ns_max):.1f}" stroke="{colour}" '
                     f'stroke-opacity="0.6"/>')
            fill = "white" if p.raw["misclassified"] else colour
            shape = SHAPES.get(p.variant["precision"], "circle")
            s.append(charts.marker(shape, px(p.ns_median), y, 4.5 if p.pareto else 3.5, fill, colour,
                             1.5 if p.raw["misclassified"] else 0.8)
                     .replace("/>", f"><title>{charts.esc(p.variant['label'])}: {fmt_ns(p.ns_median)} ns, p99 "
                                    f"{fmt_ulps(u)} ulps, {fmt_share(p)} misclassified</title></"
                                    + ("rect>" if shape == "square" else "path>" if shape == "diamond"
                                       else "circle>")))
            if p.lanes > 1:  # a dot in the middle: many rays per call
                s.append(f'<circle cx="{px(p.ns_median):.1f}" cy="{y:.1f}" r="1.4" fill="#000"/>')
            if p.pareto or p.vid in ("kit", "kit_rect", "kit_scene", "student", "stable_f32"):
                labels.append((p, px(p.ns_median), y))
            if p.vid in ("kit", "kit_rect", "kit_scene"):
                s.append(f'<circle cx="{px(p.ns_median):.1f}" cy="{y:.1f}" r="9" fill="none" stroke="#000" '
                         f'stroke-width="1.2"/>')
        s += _place_labels(labels, (ox + ml, oy + mt, ox + ml + iw, oy + mt + ih))
    s.append("</svg>")
    return "\n".join(s) + "\n"


def _place_labels(labels: list, box: tuple) -> list[str]:
    """Puts each label next to its point where it overlaps no other label and no
    marker, trying right, left, above and below; the kit's own first."""
    left, top, right, bottom = box
    taken = [(x - 5, y - 5, x + 5, y + 5) for _, x, y in labels]   # the markers
    out = []
    order = sorted(labels, key=lambda t: t[0].vid not in ("kit", "kit_rect", "kit_scene", "student"))
    for p, x, y in order:
        name = short_name(p.variant)
        w, h = 5.4 * len(name), 10
        for dx, dy, anchor in ((9, 3.5, "start"), (-9, 3.5, "end"), (4, -8, "start"), (4, 15, "start"),
                               (-4, -8, "end"), (-4, 15, "end")):
            x0 = x + dx if anchor == "start" else x + dx - w
            rect = (x0, y + dy - 8, x0 + w, y + dy - 8 + h)
            inside = rect[0] >= left and rect[2] <= right and rect[1] >= top and rect[3] <= bottom
            clear = all(rect[2] < a or rect[0] > c or rect[3] < b or rect[1] > d
                        for a, b, c, d in taken if not (a == x - 5 and b == y - 5))
            if inside and clear:
                taken.append(rect)
                out.append(f'<text x="{x + dx:.1f}" y="{y + dy:.1f}" font-size="9.5" text-anchor="{anchor}" '
                           f'fill="#222">{charts.esc(name)}</text>')
                break
    return out

"""./kit test checks for ./kit bench: it runs in quick mode and its output parses.

No check judges a time: the machine may be busy. The errors, though, are
deterministic (fixed seeds, same code), so a few facts about them are checked,
facts that only hold when the float128 yardstick and the ulp measure work.
"""

from __future__ import annotations

import csv
import importlib.util
import json
import math
import re
import subprocess
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from kitlib.commands import bench as cmd_bench
from raykit.common import ROOT
from raykit.status import NOT_STARTED
from .support import Failed, Skipped, expect, kit

SPHERE_FAMILIES = {"typical", "far_1e3", "far_1e4", "far_3e4", "tiny", "huge", "off_centre", "grazing", "inside",
                   "pbrt_e4", "pbrt_e6", "pbrt_e8", "ground_1e3", "ground_earth"}
FORMULATIONS = {"textbook", "half-b", "unit-dir", "geometric", "stable", "lagrange"}


def within_one_ulp_everywhere(rows: dict, variant: str) -> list[str]:
    """The families on which `variant` misses the bar: p99 over 1 ulp, or a ray misclassified."""
    bad = []
    for fam in sorted(SPHERE_FAMILIES):
        row = rows.get((fam, variant))
        if row is None:
            bad.append(f"{fam} (no row)")
        elif int(row["misclassified"]) or _number(row, "ulps_p99") > 1.0:
            bad.append(f"{fam} (p99 {row['ulps_p99']}, {row['misclassified']} misclassified)")
    return bad


def _rows(path: Path) -> dict[tuple[str, str], dict]:
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    expect(rows and set(cmd_bench.report.CSV_FIELDS) <= set(rows[0]), f"{path.name}: missing columns")
    return {(r["family"], r["variant"]): r for r in rows}


def _number(row: dict, key: str) -> float:
    try:
        return float(row[key])
    except ValueError:
        raise Failed(f"results.csv: {row['variant']} on {row['family']}: {key} = '{row[key]}' is not a number")


def selftest_quick_run(ctx) -> str:
    with tempfile.TemporaryDirectory() as tmp:
        r = kit("bench", "--quick", "--out", tmp, timeout=900)
        expect(r.returncode == 0, f"./kit bench --quick exited {r.returncode}:\n{(r.stdout + r.stderr)[-3000:]}")
        out = Path(tmp)
        for name in cmd_bench.OUTPUTS:
            expect((out / name).is_file(), f"./kit bench --quick wrote no {name}")
        expect(not list(out.glob("*.tmp")), "a temporary file was left behind")
        rows = _rows(out / "results.csv")

        # Every formulation, in float and double, on every sphere family, timed.
        for fam in SPHERE_FAMILIES:
            for f in FORMULATIONS:
                for suffix in ("_f32", "_f64"):
                    row = rows.get((fam, f + suffix))
                    expect(row is not None, f"results.csv has no row for {f + suffix} on {fam}")
                    ns = _number(row, "ns_median")
                    expect(math.isfinite(ns) and ns > 0, f"{f + suffix} on {fam}: ns_median {ns}")
                    expect(_number(row, "ulps_p99") >= 0, f"{f + suffix} on {fam}: negative error")
        expect(("typical", "kit") in rows, "the kit's reference was not measured")
        expect(("box_camera", "brute_force") in rows, "the Cornell box was not measured")

        # Facts about the errors (not the times) that a broken yardstick would miss.
        far_text, far_stable = rows[("far_1e4", "textbook_f32")], rows[("far_1e4", "stable_f32")]
        # (Not none: on the committed full run the stable form misclassifies a few rays in 10^4.)
        expect(_number(far_text, "misclassified_share") > 0.1 and _number(far_stable, "misclassified_share") < 1e-3,
               "1e4 radii away, the textbook form in float must misclassify many rays and the stable form almost none")
        expect(_number(far_stable, "ulps_p99") < 10 < _number(far_text, "ulps_p99"),
               "1e4 radii away, the stable form must stay within a few ulps and the textbook form must not")
        rounded = _number(rows[("typical", "half-b_f32_in_f64")], "ulps_max")
        expect(rounded <= 0.5 + 1e-3, f"a double result rounded to float must be within half an ulp, got {rounded}")
        # At pbrt's scales h^2 - a c loses even in double; the Lagrange form does not.
        expect(int(rows[("pbrt_e8", "half-b_f32_in_f64")]["misclassified"]) > 0,
               "on pbrt's ranges (e = 8), half-b in double must misclassify rays")
        bad = within_one_ulp_everywhere(rows, "lagrange_f32_in_f64")
        expect(not bad, f"the Lagrange form in double (the reference) is not within 1 ulp (p99) on: {', '.join(bad)}")
        bad = within_one_ulp_everywhere(rows, "exact-float_f32")
        expect(not bad, f"the float-float form (exact-float) is not within 1 ulp (p99) on: {', '.join(bad)}")
        expect("lanes" in next(iter(rows.values())), "results.csv has no lanes column")

        # The vector rows, where Highway is there: the reference and the float-float form stay within 1 ulp,
        # and half-b in float lanes fails far away as it does one ray at a time.
        vector = sorted({v for (_, v) in rows if v.startswith("lagrange_f32_in_f64_x")})
        meta = json.loads((out / "results.json").read_text())["meta"]
        if "not found" not in meta.get("highway", "not found"):
            expect(vector, f"Highway is there ({meta['highway']}) but no vector row was measured")
        for v in vector:
            lanes, isa = v[len("lagrange_f32_in_f64_x"):].split("_", 1)
            floats = f"_x{2 * int(lanes)}_{isa}"  # as many floats as doubles fit twice
            for name in (v, "exact-float_f32" + floats):
                bad = within_one_ulp_everywhere(rows, name)
                expect(not bad, f"{name} is not within 1 ulp (p99) on: {', '.join(bad)}")
            expect(int(rows[("far_1e4", "half-b_f32" + floats)]["misclassified"]) > 0,
                   f"1e4 radii away, half-b in float lanes ({isa}) must misclassify rays")

        data = json.loads((out / "results.json").read_text())
        student = next(v for v in data["variants"] if v["id"] == "student")
        expect(student["status"] == NOT_STARTED,
               f"the shipped stub must show as not started in the benchmark, got '{student['status']}'")
        expect("not started" in r.stdout, "the table does not say the student's step is not started")

        svg = ET.parse(out / "plot.svg").getroot()
        expect(svg.tag.endswith("svg"), "plot.svg is not an SVG")
        texts = {t.text for t in svg.iter() if t.tag.endswith("text")}
        missing = [f["label"] for f in data["families"] if not any((t or "").startswith(f["label"]) for t in texts)]
        expect(not missing, f"plot.svg has no panel for: {', '.join(missing)}")

        # Remaking the outputs from results.json measures nothing and changes nothing.
        again = out / "again"
        again.mkdir()
        r2 = kit("bench", "--from", str(out / "results.json"), "--out", str(again), timeout=120)
        expect(r2.returncode == 0, f"./kit bench --from exited {r2.returncode}: {r2.stderr[-500:]}")
        expect((again / "results.csv").read_text() == (out / "results.csv").read_text(),
               "./kit bench --from results.json does not remake the same results.csv")

        # Comparing a run with itself: every error identical.
        lines = cmd_bench.compare(rows_as_csv(out), rows_as_csv(again))
        expect(f"errors identical in {len(rows)}" in lines[0], f"--compare with itself: {lines[0]}")
    return (f"{len(rows)} rows; CSV, JSON, Markdown and SVG parse; student step 'not started'; reference and "
            f"float-float form within 1 ulp (p99) on {len(SPHERE_FAMILIES)} families ({len(vector)} vector widths)")


def rows_as_csv(out: Path) -> dict:
    return cmd_bench.read_csv(out / "results.csv")


def selftest_bad_input(ctx, bench_exe) -> str:
    exe = bench_exe
    for args, words in [(["--rays=abc"], "whole number"), (["--rays=-5"], "whole number"),
                        (["--min-time=0"], "seconds"), (["--min-time=nan"], "seconds"),
                        (["--bogus"], "unknown option"), (["--out="], "file name"), (["--quick=3"], "no value")]:
        r = subprocess.run([str(exe), *args], capture_output=True, text=True, timeout=30)
        expect(r.returncode == 2, f"raykit_bench {' '.join(args)} exited {r.returncode}, expected 2")
        expect(words in r.stderr, f"raykit_bench {' '.join(args)}: message lacks '{words}': {r.stderr[-200:]}")
    with tempfile.TemporaryDirectory() as tmp:
        blocker = Path(tmp) / "file"
        blocker.write_text("")
        for args, words in [(["--out", str(blocker)], "not a folder"),
                            (["--out", str(Path(tmp) / "no" / "such")], "does not exist"),
                            (["--compare", str(Path(tmp) / "missing.csv")], "No such file"),
                            (["--compare", str(blocker)], "not a results.csv"),
                            (["--from", str(blocker)], "not JSON"),
                            (["--from", str(Path(tmp) / "missing.json")], "No such file")]:
            r = kit("bench", *args, timeout=60)
            expect(r.returncode == 2, f"./kit bench {' '.join(args)} exited {r.returncode}, expected 2")
            expect(words in r.stderr, f"./kit bench {' '.join(args)}: message lacks '{words}': {r.stderr[-300:]}")
        r = subprocess.run([str(exe), "--smoke", f"--out={Path(tmp) / 'no' / 'such.json'}"], capture_output=True,
                           text=True, timeout=120)
        expect(r.returncode == 1 and "cannot write" in r.stderr, "an unwritable --out must fail with a message")
    return "bad options and folders: message and exit 2, nothing written"


@pytest.mark.quick
def selftest_roofline_model(ctx) -> str:
    """The roofline of a vector row takes the slowest of its resources, the float <-> double conversions of
    double lanes on float rays included; a row without a conversion count (runs from before they were counted)
    keeps the old bound. Made-up rates, so each term is the slowest in turn. Then terms that share a unit, as
    measured: divides and square roots that take turns add up, conversions that half-overlap the
    multiply-adds add half of the shorter term; a run without that measurement keeps the longest term. A
    vector row whose fused multiply-adds are counted takes its adds and multiplies as instructions (a lone
    add a whole one); a scalar row does not."""
    target = {"isa": "AVX3", "gflops_f32": 200.0, "gflops_f64": 100.0, "div_ns_f32": 0.05, "div_ns_f64": 0.15,
              "sqrt_ns_f32": 0.08, "sqrt_ns_f64": 0.25, "cvt_ns": 0.04}
    peak = {"scalar_gflops_f32": 13.0, "scalar_gflops_f64": 13.0, "div_ns_f32": 0.7, "div_ns_f64": 1.1,
            "sqrt_ns_f32": 1.3, "sqrt_ns_f64": 2.1, "vector_targets": [target]}

    def bound(precision: str, flops: float, div: float, sqrt: float, cvt=None, lanes: int = 8, fma=None) -> float:
        raw = {"flops": flops, "div": div, "sqrt": sqrt}
        if cvt is not None:
            raw["cvt"] = cvt
        if fma is not None:
            raw["fma"] = fma
        variant = {"id": "x", "precision": precision, "lanes": lanes, "isa": "AVX3"}
        return cmd_bench.report.Point(variant, {"id": "f"}, raw).roofline_ns(peak)

    wide = "float, double inside"
    cases = [  # (what, computed, expected)
        ("conversions the slowest", bound(wide, 36, 1, 1, cvt=13), 13 * 0.04),
        ("flops the slowest", bound(wide, 102, 1, 1, cvt=13), 100 / 100.0),
        ("square roots the slowest", bound(wide, 36, 1, 3, cvt=1), 3 * 0.25),
        ("no conversion count", bound(wide, 36, 1, 1), 34 / 100.0),
        ("float lanes, no conversions", bound("float", 28, 2, 1, cvt=0, lanes=16), 25 / 200.0),
        ("scalar: the scalar rates", bound("float", 27, 1, 1, cvt=13, lanes=1), 25 / 13.0),
        # With the fused pairs counted, a vector row's adds and multiplies are instructions at half the flop
        # rate: 100 flops of which 20 pairs fused are 80 instructions, 160 flops' time.
        ("instructions: lone adds take a slot each", bound("float", 102, 1, 1, cvt=0, lanes=16, fma=20),
         80 * 2 / 200.0),
        ("instructions: all fused, as the flop rate", bound("float", 102, 1, 1, cvt=0, lanes=16, fma=50),
         100 / 200.0),
        ("scalar: the fused count changes nothing", bound("float", 27, 1, 1, cvt=0, lanes=1, fma=5), 25 / 13.0),
    ]
    # The same target, with its units' overlaps measured.
    target.update(shared_div_sqrt=1.0, shared_fma_cvt=0.5)
    cases += [
        ("a divider shared by divides and roots", bound(wide, 36, 1, 3, cvt=1), 0.15 + 3 * 0.25),
        ("conversions half beside the FMAs", bound(wide, 36, 1, 1, cvt=13), 13 * 0.04 + 0.5 * 34 / 100.0),
        ("scalar rows: no overlap measured", bound("float", 27, 1, 1, cvt=13, lanes=1), 25 / 13.0),
    ]
    target.update(shared_div_sqrt=None, shared_fma_cvt=None)    # null in a run's JSON: not measured
    cases.append(("overlaps not measured", bound(wide, 36, 1, 3, cvt=1), 3 * 0.25))
    for what, got, want in cases:
        expect(got is not None and abs(got - want) < 1e-9 * max(1.0, want),
               f"roofline, {what}: {got} ns, expected {want} ns")
    return (f"{len(cases)} roofline cases: flops, divides, square roots and conversions, each the slowest in turn, "
            "and terms that share a unit as measured")


@pytest.mark.quick
def selftest_front_like_with_like(ctx) -> str:
    """The Pareto front compares like with like: a row whose error is counted in double ulps is never marked
    dominated by one counted in float ulps, nor the other way round (a float ulp is 2^29 double ulps). A
    made-up family where raw ulps would cross the two: a float row faster and fewer (float) ulps than a double
    row, a double row faster and fewer (double) ulps than a float row; and, within one type, rows that do
    dominate (float, double inside counts in float ulps, so it meets the float rows)."""
    report = cmd_bench.report

    def variant(vid: str, precision: str, ulp_of: str, lanes: int = 1) -> dict:
        return {"id": vid, "label": vid, "formulation": vid.split("_")[0], "precision": precision, "group": "sphere",
                "ulp_of": ulp_of, "lanes": lanes, "isa": "AVX2" if lanes > 1 else "", "status": "ok", "note": ""}

    rows = [  # (variant, ns, p99 ulps in its own result type, misclassified)
        (variant("lagrange_f32", "float", "float"), 4.0, 3.6, 0),
        (variant("textbook_f64", "double", "double"), 6.0, 28.9, 0),     # raw: "dominated" by lagrange_f32
        (variant("stable_f64", "double", "double"), 4.0, 0.5, 0),        # raw: "dominates" the float rows
        (variant("half-b_f32_in_f64", "float, double inside", "float"), 4.5, 0.5, 0),
        (variant("textbook_f32", "float", "float"), 7.0, 40.0, 3),       # dominated, by float rows only
        (variant("half-b_f64", "double", "double"), 8.0, 30.0, 0),       # dominated, by double rows only
        (variant("stable_f32_x8_AVX2", "float", "float", lanes=8), 1.0, 90.0, 0),
        (variant("half-b_f32_in_f64_x4_AVX2", "float, double inside", "float", lanes=4), 2.0, 0.5, 0),
    ]
    meta = {"cpu": "made up", "compiler": "12.2.0", "flags": "-O2", "rays": 1000, "repetitions": 3, "batch": 100}
    data = {"meta": meta, "variants": [v for v, *_ in rows],
            "families": [{"id": "typical", "label": "typical", "description": "made up"}],
            "results": [{"variant": v["id"], "family": "typical", "rays": 1000, "in_band": 0, "compared": 1000,
                         "misclassified": mis, "ulps_median": u / 2, "ulps_p99": u, "ulps_max": 2 * u,
                         "cpu_ns": [ns, ns, ns], "real_ns": [ns, ns, ns]} for v, ns, u, mis in rows]}
    pts = report.points(data)
    report.mark_pareto(pts)
    kind = {p.vid: p.variant["ulp_of"] for p in pts}
    crossed = [f"{p.vid} ({kind[p.vid]}) by {q} ({kind[q]})" for p in pts for q in p.dominated_by if kind[q] != kind[p.vid]]
    expect(not crossed, "the Pareto front compares float ulps with double ulps: marked dominated "
                        + "; ".join(crossed))
    want = {"lagrange_f32": [], "textbook_f64": ["stable_f64"], "stable_f64": [], "half-b_f32_in_f64": [],
            "textbook_f32": ["lagrange_f32", "half-b_f32_in_f64"], "half-b_f64": ["textbook_f64", "stable_f64"],
            "stable_f32_x8_AVX2": [], "half-b_f32_in_f64_x4_AVX2": []}
    got = {p.vid: sorted(p.dominated_by) for p in pts}
    wrong = [f"{vid}: dominated by {got[vid] or 'nothing'}, expected {sorted(w) or 'nothing'}"
             for vid, w in want.items() if got[vid] != sorted(w)]
    expect(not wrong, "the fronts within one result type are wrong: " + "; ".join(wrong))
    # The CSV and the Markdown table say the same.
    marked = {r["variant"]: r["pareto"] == "1" for r in csv.DictReader(report.csv_text(data, pts).splitlines())}
    expect(marked == {vid: not w for vid, w in want.items()}, f"results.csv marks the front as {marked}")
    table = report.markdown_table(data, pts)
    diamonds = {vid for vid in want if any(l.startswith(f"| ◆ | {vid} |") for l in table.splitlines())}
    expect(diamonds == {vid for vid, w in want.items() if not w}, f"table.md marks {sorted(diamonds)} with ◆")
    return (f"{len(rows)} made-up rows: no row marked dominated across float and double ulps; within a type "
            f"the front is as expected in the CSV and the table")


@pytest.mark.quick
def selftest_student_summary(ctx) -> str:
    """After the tables, a short summary of the student's step: one line per family (rank by speed
    and by p99 error, the kit's figures beside), its worst error; the compiler named ("GCC 12.2.0").
    From the committed run (docs/bench/results.json) with the textbook float rows as the student's."""
    data = json.loads((ROOT / "docs" / "bench" / "results.json").read_text())
    data["results"] = [r for r in data["results"] if r["variant"] != "student"]
    data["results"] += [dict(r, variant="student") for r in data["results"] if r["variant"] == "textbook_f32"]
    families = {r["family"] for r in data["results"] if r["variant"] == "student"}
    with tempfile.TemporaryDirectory() as tmp:
        source = Path(tmp) / "in.json"
        source.write_text(json.dumps(data))
        r = kit("bench", "--from", str(source), "--out", str(Path(tmp) / "out"))
    expect(r.returncode == 0, f"./kit bench --from exited {r.returncode}:\n{(r.stdout + r.stderr)[-1500:]}")
    tail = r.stdout.split(", in short (rank among the scalar variants")[-1]
    lines = [l for l in tail.splitlines() if "ns/ray, rank" in l and "the kit's" in l]
    expect(", in short" in r.stdout and len(lines) == len(families) and "worst error:" in tail,
           f"no summary of the student's step with a line per family ({len(families)}):\n{r.stdout[-2000:]}")
    compiler = str(data["meta"]["compiler"])
    expect(not compiler[:1].isdigit() or f"Compiled with GCC {compiler}" in r.stdout,
           f"the table does not name the compiler: 'Compiled with {compiler}'")
    return f"the student's step summed up in {len(lines)} family lines and its worst error; 'GCC {compiler}'"


# --- the reading's figures (docs/bench.md, lecture 03's appendix) --------------------------------

GENERATOR = ROOT / "docs" / "bench_numbers.py"

# One figure of each kind a hand might type, and where it goes: into the text between two blocks.
PLANTED = ["It takes 7.3 ns per ray.", "It misclassifies 45 % of the rays.", "The peak is 12.7 GFLOP/s.",
           "The worst rays were 17 and 19 ulps off.", "It runs 2.2× faster.", "It costs about three times as much.",
           "It takes less than a tenth of the time.", "Within an ulp and a half.", "At a load average of 2.2.",
           "The textbook form's p99 53000 is large.", "It takes 11.2 to\n13.6 times as long.",
           "It costs 37 flops against 26.", "The bound is **15 ulps**.", "It took 29.5 s of user time.",
           "Each repetition lasts 3 ms.", "The rays fill 160 KiB.", "The core runs at 3.2 GHz."]


def _bench_numbers():
    spec = importlib.util.spec_from_file_location("bench_numbers_selftest", GENERATOR)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.quick
def selftest_reading_generated(ctx) -> str:
    """Every figure with a unit in docs/bench.md and lecture 03's appendix sits in a generated block, and every
    block is what the committed run (docs/bench/results.json) gives. Then the check is shown to fail: each
    figure of PLANTED typed between two blocks of a copy is found, and a block edited by hand in a copy is
    stale; every block the generator knows is used somewhere."""
    if not GENERATOR.is_file() or not (ROOT / "docs" / "bench" / "results.json").is_file():
        raise Skipped("no docs/bench_numbers.py or no committed benchmark run here")
    bn = _bench_numbers()
    files = [p for p in bn.FILES if p.is_file()]
    expect(any(p.name == "bench.md" for p in files), "docs/bench.md is missing")
    typed = bn.typed_in_files(files)
    expect(not typed, f"{len(typed)} figures typed by hand outside a generated block (generate them in "
                      "docs/bench_numbers.py or reword without a number):\n  " + "\n  ".join(typed[:20]))
    try:
        stale = bn.run_files(bn.RESULTS, files, check=True)
    except bn.Stale as e:
        raise Failed(f"docs/bench_numbers.py cannot read the committed run: {e}") from None
    expect(not stale, "generated blocks differ from the committed run (run python3 docs/bench_numbers.py): "
                      + ", ".join(stale))
    used = {bn.BEGIN.match(l).group(1) for p in files for l in p.read_text().split("\n") if bn.BEGIN.match(l)}
    expect(used == set(bn.BLOCKS), f"blocks the generator writes but no text holds: {sorted(set(bn.BLOCKS) - used)}")

    # The check can fail. A typed figure between two blocks of a copy of the reading:
    reading = next(p for p in files if p.name == "bench.md")
    text = reading.read_text()
    cut = text.index(bn.END) + len(bn.END)          # just after the first block
    missed = []
    for figure in PLANTED:
        found = bn.typed_figures(text[:cut] + "\n" + figure + "\n" + text[cut:])
        if not found:
            missed.append(figure)
    expect(not missed, f"typed figures not found: {missed}")
    # ... and a block edited by hand, in a temporary copy run through the same check as the real files.
    with tempfile.TemporaryDirectory() as tmp:
        copy = Path(tmp) / reading.name
        lines = text.split("\n")
        first = next(i for i, l in enumerate(lines) if bn.BEGIN.match(l))
        name = bn.BEGIN.match(lines[first]).group(1)
        end = lines.index(bn.END, first)
        edit = next((i for i in range(first + 1, end) if re.search(r"\d", lines[i])), None)
        expect(edit is not None, f"block '{name}' has no digit to change")
        lines[edit] = re.sub(r"\d", lambda m: str((int(m.group(0)) + 1) % 10), lines[edit], count=1)
        copy.write_text("\n".join(lines))
        stale = bn.run_files(bn.RESULTS, [copy], check=True)
        expect(stale == [f"{copy.name}: {name}"], f"a digit changed by hand in block '{name}' gave stale = {stale}")
        expect(copy.read_text() == "\n".join(lines), "the check changed the copy")
    blocks = sum(1 for p in files for l in p.read_text().split("\n") if bn.BEGIN.match(l))
    return (f"{blocks} generated blocks current with the committed run, no typed figure in "
            f"{', '.join(p.name for p in files)}; {len(PLANTED)} planted figures and a hand-edited block caught")

"""./kit bench: speed against error, side by side.

Builds bench/ (raykit_bench) in the reference build, and in the student build
to measure the student's own sphere function; runs both; prints the table and
writes results.csv, results.json, table.md and plot.svg (default: build/bench/).
"""

from __future__ import annotations

import csv
import json
import math
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from raykit import atomic
from .. import bench_report as report
from raykit.common import ROOT, KitError, load_steps, note, paint, say
from raykit.build import Build, build_targets, configure, preset_build, tools_build
from raykit.packages import ensure_packages
from raykit.status import FAILED, OK

TARGET = "raykit_bench"
COMMITTED = ROOT / "docs" / "bench" / "results.json"
DEFAULT_OUT = ROOT / "build" / "bench"
OUTPUTS = ("results.csv", "results.json", "table.md", "plot.svg")



def register(p) -> None:
    p.add_argument("--quick", action="store_true", help="fewer rays and repetitions (the first run builds the benchmark first, and says so)")
    p.add_argument("--out", metavar="DIR", help=f"where to write {', '.join(OUTPUTS)} (default build/bench)")
    p.add_argument("--compare", metavar="CSV", help="compare with an earlier results.csv: same errors, times "
                                                     "within the noise?")
    p.add_argument("--no-student", action="store_true", help="do not build or measure your own step")
    p.add_argument("--from", dest="source", metavar="JSON", help="measure nothing: remake the table, CSV and plot "
                                                                 "from a results.json written earlier")


# --- running raykit_bench --------------------------------------------------------------


class Progress:
    """One line that updates in place on a terminal, a line per phase otherwise."""

    def __init__(self) -> None:
        self.tty = sys.stderr.isatty()
        self.last_phase = None
        self.start = time.monotonic()

    def show(self, text: str, phase: str) -> None:
        elapsed = time.monotonic() - self.start
        line = f"bench: {text}  ({elapsed:.0f} s)"
        if self.tty:
            sys.stderr.write("\r\033[K" + line)
            sys.stderr.flush()
        elif phase != self.last_phase:
            print(line, file=sys.stderr, flush=True)
        self.last_phase = phase

    def done(self) -> None:
        if self.tty:
            sys.stderr.write("\r\033[K")
            sys.stderr.flush()


PHASES = {"setup": "making rays", "error": "error pass", "peak": "measuring the CPU's peak", "speed": "timing"}


def run_bench(exe: Path, args: list[str], timeout: float, who: str, progress: Progress) -> tuple[dict | None, str]:
    """Runs raykit_bench; returns (its JSON, "") or (None, what went wrong)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "bench.json"
        proc = subprocess.Popen([str(exe), *args, f"--out={out}"], stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True,
                                start_new_session=True)
        timed_out = threading.Event()

        def kill() -> None:
            timed_out.set()
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass

        timer = threading.Timer(timeout, kill)
        timer.start()
        other: list[str] = []
        try:
            for line in proc.stderr:
                parts = line.rstrip("\n").split(" ", 4)
                if len(parts) >= 4 and parts[0] == "progress":
                    phase, done, total = parts[1], parts[2], parts[3]
                    what = parts[4] if len(parts) > 4 else ""
                    progress.show(f"{who}: {PHASES.get(phase, phase)} {done}/{total} {what}", f"{who}{phase}")
                elif len(other) < 200:
                    other.append(line.rstrip("\n"))
            proc.wait()
        finally:
            timer.cancel()
        if timed_out.is_set():
            return None, f"timed out after {timeout:.0f} s"
        if proc.returncode < 0:
            sig = signal.Signals(-proc.returncode).name if -proc.returncode in signal.Signals._value2member_map_ \
                else str(-proc.returncode)
            return None, f"crashed ({sig})" + (": " + other[-1] if other else "")
        if proc.returncode != 0:
            return None, f"exited with status {proc.returncode}" + (":\n  " + "\n  ".join(other[-8:]) if other else "")
        try:
            return json.loads(out.read_text()), ""
        except (OSError, json.JSONDecodeError) as e:
            return None, f"wrote no readable results ({e})"


def build_bench(build: Build, progress: "Progress | None" = None, what: str = "the benchmark") -> tuple[bool, str]:
    """Configures `build` and builds raykit_bench with only the step libraries it links, saying what is
    being built and how far along it is (Ninja's count) while the user waits."""
    where = os.path.relpath(build.binary_dir, ROOT)
    if progress:
        progress.show(f"configuring {what} ({where})", f"configure-{where}")
    configure(build)

    def compiled(done: int, total: int) -> None:
        # Ninja's "[0/N]" lines re-check the build's inputs; a log (no terminal) gets a line a quarter.
        if progress and done > 0:
            progress.show(f"building {what}: {done} of {total} compile and link steps ({where})",
                          f"build-{where}-{4 * done // total}")

    ok, out = build_targets(build, [TARGET], progress=compiled)
    if not ok and ("unknown target" in out or f"'{TARGET}'" in out and "no such" in out.lower()):
        cache = build.binary_dir / "CMakeCache.txt"
        why = "Google Benchmark or __float128 support was not found when CMake configured " + str(build.binary_dir)
        if cache.is_file() and "benchmark_DIR:PATH=benchmark_DIR-NOTFOUND" in cache.read_text(errors="replace"):
            why = "CMake did not find Google Benchmark (Debian package libbenchmark-dev)"
        return False, why
    return ok, out


def student_label(step: int) -> str:
    return f"your step 0{step}" + (", ray moved to the unit sphere" if step == 1 else "")


def student_subject(progress: Progress, run_args: list[str], timeout: float) -> tuple[dict | None, str, str]:
    """Builds and runs the student's sphere function. Returns (JSON, status, label)."""
    build = tools_build(preset_build("student"))
    # The bench measures step 02's sphere_roots, or step 01's until step 02 exists.
    label = student_label(2 if any(s.number == "02" for s in load_steps()) else 1)
    ok, out = build_bench(build, progress, "the benchmark of your step")
    if not ok:
        errors = [l.strip() for l in out.splitlines() if "error:" in l][:1]
        return None, "does not compile" + (f" (first error: {errors[0]})" if errors else ""), label
    data, problem = run_bench(build.binary_dir / "bench" / TARGET, ["--subject-only", *run_args], timeout,
                              "your step", progress)
    if data is None:
        return None, problem, label
    return data, "", student_label(data["meta"]["sphere_step"])


def status_lines(data: dict) -> list[str]:
    lines = []
    for v in data["variants"]:
        if v["status"] == "ok":
            if v["id"] == "kit" and v["note"]:
                lines.append(f"kit reference: {v['note']}.")
            continue
        words = {"absent": "not built in", "not_started": "not started (the stub throws raykit::not_implemented)"}
        lines.append(f"{v['label']}: {words.get(v['status'], v['status'])}"
                     + (f" ({v['note']})" if v["status"] == "absent" and v["note"] else "") + ".")
    lines.append(f"Embree: {data['meta']['embree']}.")
    if data["meta"].get("highway"):
        lines.append(f"Vectors: {data['meta']['highway']}.")
    return lines


def within_one_ulp(p: report.Point) -> bool:
    """The bar the vector rows are held to: p99 within 1 ulp and nothing misclassified outside the band."""
    return p.raw["misclassified"] == 0 and p.ulps("p99") <= 1.0


def accuracy_words(p: report.Point) -> str:
    """What a row's errors are, in words a student reads right: "correctly rounded" only when every judged
    root is within half an ulp, "within N ulps" (the largest error) when the bar holds, and what fails it
    otherwise. Never "exact": a float root is at best the exact root rounded."""
    if p.raw["misclassified"]:
        return f"{report.fmt_share(p)} misclassified"
    if p.ulps("max") <= 0.5:
        return "correctly rounded"
    if report.fmt_ulps(p.ulps("max")) == "0.50":   # over half an ulp, by less than the digits show
        return "just over half an ulp at worst"
    if within_one_ulp(p):
        return f"within {report.fmt_ulps(p.ulps('max'))} ulps"
    return f"p99 {report.fmt_ulps(p.ulps('p99'))} ulps, over 1"


def vector_verdict(pts: list[report.Point], peak: dict) -> list[str]:
    """The reference scalar and vectorized, and the float-float form (exact-float), on every sphere family."""
    lines: list[str] = []
    shares: list[float] = []
    speedups: list[float] = []
    fams: dict[str, list[report.Point]] = {}
    for p in pts:
        if p.variant["group"] == "sphere" and p.timed:
            fams.setdefault(p.family["id"], []).append(p)
    for group in fams.values():
        kit = next((p for p in group if p.vid == "kit"), None)
        vec = sorted((p for p in group if p.variant["formulation"] == "lagrange" and p.lanes > 1),
                     key=lambda p: p.ns_median)
        eft = sorted((p for p in group if p.variant["formulation"] == "exact-float" and p.lanes > 1),
                     key=lambda p: p.ns_median)
        if kit is None or not vec:
            continue
        v = vec[0]
        bound = v.roofline_ns(peak)
        speedup = kit.ns_median / v.ns_median
        speedups.append(speedup)
        roof = ""
        if bound:
            shares.append(100 * bound / v.ns_median)
            roof = f", {shares[-1]:.1f} % of its roofline"
        line = (f"  {group[0].family['label']}: kit {report.fmt_ns(kit.ns_median)} ns "
                f"({accuracy_words(kit)}), {v.variant['label']} {v.ns_median:.2f} ns "
                f"({accuracy_words(v)}{roof}): {speedup:.1f}x")
        if eft:
            e = eft[0]
            line += (f"; float-float {e.ns_median:.2f} ns ({accuracy_words(e)}, "
                     f"p99 {report.fmt_ulps(e.ulps('p99'))}, {e.ns_median / v.ns_median:.1f}x the double lanes)")
        lines.append(line)
    if speedups:
        share = f", {min(shares):.1f} to {max(shares):.1f} % of its roofline" if shares else ""
        lines.append(f"  over {len(speedups)} families: the vectorized reference runs {min(speedups):.1f} to "
                     f"{max(speedups):.1f} times the scalar function's rays per second{share}")
    return lines


# The formulation solutions/02_general_sphere/general_sphere.cpp computes: the benchmark also times it
# inlined into one call like every other formulation, so it can be judged on equal terms. The kit's
# packaged function pays for two calls across libraries and its input guards on top.
KIT_FORMULATION = "lagrange_f32_in_f64"


def reference_verdict(pts: list[report.Point]) -> list[str]:
    """Where the kit's reference sits on each hard family's front."""
    lines = []
    for p in pts:
        if p.vid != "kit" or not p.family.get("hard") or not p.timed:
            continue
        fam = p.family["label"]
        if p.pareto:
            lines.append(f"  {fam}: on the front")
            continue
        same = next((q for q in pts if q.family is p.family and q.vid == KIT_FORMULATION), None)
        if same is not None and same.pareto and same.ulps("p99") == p.ulps("p99"):
            lines.append(f"  {fam}: its formulation ({same.variant['label']}) is on the front "
                         f"({report.fmt_ns(same.ns_median)} ns, p99 {report.fmt_ulps(same.ulps('p99'))}); "
                         f"the packaged function, two calls and its input checks, takes "
                         f"{report.fmt_ns(p.ns_median)} ns with the same answers")
            continue
        by = [q for q in pts if q.family is p.family and q.vid in p.dominated_by]
        clear = [q for q in by if report.clearly_faster(q, p)]
        names = ", ".join(f"{q.variant['label']} ({report.fmt_ns(q.ns_median)} ns, p99 {report.fmt_ulps(q.ulps('p99'))})"
                          for q in by)
        lines.append(f"  {fam}: dominated by {names}; {'beyond' if clear else 'within'} the timing noise "
                     f"(kit: {report.fmt_ns(p.ns_median)} ns, p99 {report.fmt_ulps(p.ulps('p99'))})")
    return lines


# --- writing ------------------------------------------------------------------------


def out_dir(arg: str | None) -> Path:
    if arg is None:
        return DEFAULT_OUT
    p = Path(arg).expanduser()
    if p.exists() and not p.is_dir():
        raise KitError(f"--out {arg}: not a folder")
    if not p.exists() and not p.parent.is_dir():
        raise KitError(f"--out {arg}: folder {p.parent} does not exist")
    return p


# --- comparing two runs -------------------------------------------------------------------


def read_csv(path: Path) -> dict[tuple[str, str], dict]:
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        raise KitError(f"--compare {path}: {e.strerror}")
    if not rows or not {"family", "variant", "ns_median", "ulps_p99"} <= set(rows[0]):
        raise KitError(f"--compare {path}: not a results.csv written by ./kit bench")
    return {(r["family"], r["variant"]): r for r in rows}


def compare(old: dict, new: dict) -> list[str]:
    """Errors must match exactly (same rays, same code); times should agree within
    the spread of the repetitions."""
    lines, ratios, outside = [], [], []
    same_errors = 0
    for key, n in new.items():
        o = old.get(key)
        if o is None:
            continue
        if all(o[k] == n[k] for k in ("ulps_median", "ulps_p99", "ulps_max", "misclassified")):
            same_errors += 1
        else:
            lines.append(f"  error changed: {key[1]} on {key[0]}: p99 {o['ulps_p99']} -> {n['ulps_p99']}")
        try:
            on, nn = float(o["ns_median"]), float(n["ns_median"])
            lo, hi = min(float(o["ns_min"]), float(n["ns_min"])), max(float(o["ns_max"]), float(n["ns_max"]))
        except ValueError:
            continue
        ratios.append(nn / on)
        if not (float(o["ns_min"]) <= nn <= float(o["ns_max"]) or float(n["ns_min"]) <= on <= float(n["ns_max"])):
            outside.append((abs(math.log(nn / on)), key, on, nn, lo, hi))
    common_keys = len(set(old) & set(new))
    ratios.sort()
    head = [f"compared with the earlier run: {common_keys} rows in both; errors identical in {same_errors}."]
    if ratios:
        head.append(f"  time ratio new/old: median {ratios[len(ratios) // 2]:.3f}, "
                    f"range {ratios[0]:.2f} to {ratios[-1]:.2f}; {len(ratios) - len(outside)} of {len(ratios)} "
                    f"medians fall inside the other run's min-max.")
    for _, key, on, nn, lo, hi in sorted(outside, reverse=True)[:5]:
        head.append(f"  outside: {key[1]} on {key[0]}: {on:.2f} -> {nn:.2f} ns")
    return head + lines[:10]


# --- the command ----------------------------------------------------------------------


def measure(args) -> dict:
    """Builds and runs raykit_bench (and the student's), returns the merged results."""
    ensure_packages("build", "bench")
    progress = Progress()
    run_args = ["--quick"] if args.quick else []
    timeout = 120 if args.quick else 600
    try:
        ensure_packages("bench-embree")
    except KitError:
        note("kit: Embree (libembree-dev) could not be installed; the comparison with Embree is skipped")
    try:
        ensure_packages("bench-hwy")
    except KitError:
        note("kit: Google Highway (libhwy-dev) could not be installed; the vector rows are skipped")

    ref = preset_build("reference")
    ok, out = build_bench(ref, progress, "the benchmark and the reference steps it times")
    if not ok:
        progress.done()
        raise KitError(f"the benchmark does not build: {out[-3000:]}", FAILED)

    student, student_status, student_label = None, "not measured (--no-student)", "your step"
    if not args.no_student:
        student, student_status, student_label = student_subject(progress, run_args, timeout)

    data, problem = run_bench(ref.binary_dir / "bench" / TARGET, run_args, timeout, "kit", progress)
    progress.done()
    if data is None:
        raise KitError(f"raykit_bench {problem}", FAILED)
    report.merge_student(data, student, student_status or "ok", student_label)
    return data


def load(path: str) -> dict:
    try:
        data = json.loads(Path(path).read_text())
    except OSError as e:
        raise KitError(f"--from {path}: {e.strerror}")
    except json.JSONDecodeError:
        raise KitError(f"--from {path}: not JSON")
    if not isinstance(data, dict) or not {"meta", "variants", "families", "results"} <= set(data):
        raise KitError(f"--from {path}: not a results.json written by ./kit bench")
    return data


def run(args) -> int:
    target = out_dir(args.out)
    old = read_csv(Path(args.compare)) if args.compare else None
    data = load(args.source) if args.source else measure(args)

    pts = report.points(data)
    report.mark_pareto(pts)
    say(report.table_text(data, pts, status_lines(data)))
    verdict = reference_verdict(pts)
    if verdict:
        say(paint("The kit's reference on the hard families:", "bold"))
        say("\n".join(verdict))
    lanes = vector_verdict(pts, data.get("peak") or {})
    if lanes:
        say(paint("The reference, scalar (the kit's function) and vectorized (the fastest lanes), and the "
                  "float-float form (exact-float):", "bold"))
        say("\n".join(lanes))

    summary = report.student_summary(data, pts)
    if summary:
        say()
        say(paint(summary[0], "bold"))
        say("\n".join(summary[1:]))

    target.mkdir(parents=True, exist_ok=True)
    outputs = {"results.json": json.dumps(data, indent=1) + "\n", "results.csv": report.csv_text(data, pts),
               "table.md": report.markdown_table(data, pts), "plot.svg": report.plot_svg(data, pts)}
    for name, text in outputs.items():
        atomic.write(target / name, text)
    shown = os.path.relpath(target, Path.cwd()) if str(target).startswith(str(Path.cwd())) else str(target)
    say(f"\nwrote {', '.join(shown + '/' + n for n in OUTPUTS)}")
    if target.resolve() == COMMITTED.parent.resolve() and (ROOT / "docs" / "bench_numbers.py").is_file():
        # docs/bench.md and lecture 03's appendix quote this run in generated blocks, now stale.
        say("docs/bench.md and lecture 03's appendix quote this run: python3 docs/bench_numbers.py (or ./kit refresh) "
            "rewrites their figures")

    if old is not None:
        new = read_csv(target / "results.csv")
        say()
        for line in compare(old, new):
            say(line)
    return OK

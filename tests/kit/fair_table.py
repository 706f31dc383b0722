"""The fairness table: every form the lectures teach, in float and in double, compiled with and without
fused multiply-adds, graded on many hidden draws; the failures per tier.

A basic or hidden case that fails one of these forms is a knife's edge, not a test (issue 34): the forms
are right by the basic tier's tolerance. ★ failures are expected (that is what the ★ tier is for) and
are counted, not judged. The forms are tests/fixtures/fair/<form>/, each written in `using real = float;`;
this module grades each as it is and a copy with `real` = double, each also compiled with contraction
allowed and FMA instructions (a prologue of pragmas, since the kit's own flags say -ffp-contract=off, and
a probe checks the prologue does fuse). The self-test "fair verdicts" (selftest/robust.py) runs it on a
few draws; a maintainer runs the full table by hand:

    PYTHONPATH=tools:tests python3 -m kit.fair_table --seeds 100

which prints a Markdown table: form, step, type, contraction, then for each tier the failures: basic
(cases), hidden (case x draw pairs, of how many), ★ (cases).
"""

from __future__ import annotations

import argparse
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from raykit import procfs
from raykit import bundle
from raykit.build import Build, detect_undefined, submission_build
from raykit.checking import build_step, judge_step
from raykit.common import ROOT, load_steps
from raykit.sandbox import NONE_OWN
from .fixtures import fixture_dir

# Folder -> what it is, per step (step 03's file holds the shortcut and the geometric form).
FORMS = {
    "textbook": {"01": "textbook", "02": "textbook", "03": "shortcut + geometric, as printed"},
    "half_b": {"01": "half-b", "02": "half-b"},
    "rewrite_pair": {"01": "rewrite, stable pair", "02": "rewrite, stable pair",
                     "03": "shortcut + geometric, rewrite, stable pair"},
    "rewrite_no_pair": {"01": "rewrite, plain pair", "02": "rewrite, plain pair",
                        "03": "shortcut + geometric, rewrite, plain pair"},
}
REAL_LINE = "using real = float;"
# Contraction allowed and FMA instructions, whatever the kit's command line says (a pragma overrides
# -ffp-contract=off for the functions after it). On x86-64 the FMA instructions are a target option;
# on ARM64 they are always there.
FUSED_GCC_X86 = '#pragma GCC optimize("fp-contract=fast")\n#pragma GCC target("fma")\n'
FUSED_GCC_ARM = '#pragma GCC optimize("fp-contract=fast")\n'
PROBE = r"""
#include <cstdio>
__attribute__((noinline)) float f(float a, float b, float c) { return a * b + c; }
int main() {
    volatile float a = 1.0f + 0x1p-12f, c = -(1.0f + 0x1p-11f);
    std::printf("%a\n", f(a, a, c));   // 0x1p-24 fused, 0x0p+0 rounded twice
}
"""


def fma_prologue() -> str | None:
    """The prologue that makes a file's functions fuse, or None where this machine cannot run FMA."""
    machine = platform.machine().lower()
    if machine in ("aarch64", "arm64"):
        return FUSED_GCC_ARM
    if machine in ("x86_64", "amd64") and "fma" in procfs.cpu_flags():
        return FUSED_GCC_X86
    return None


def probe_fuses(prologue: str) -> bool:
    """Whether `prologue` makes a*b + c one fused multiply-add under the kit's -ffp-contract=off."""
    cxx = shutil.which("g++") or shutil.which("c++")
    if cxx is None:
        return False
    with tempfile.TemporaryDirectory(prefix="raykit-fma-probe-") as tmp:
        src, exe = Path(tmp) / "p.cpp", Path(tmp) / "p"
        src.write_text(prologue + PROBE)
        r = subprocess.run([cxx, "-std=c++17", "-O2", "-ffp-contract=off", str(src), "-o", str(exe)],
                           capture_output=True, text=True, timeout=120)
        if r.returncode != 0:
            return False
        return subprocess.run([str(exe)], capture_output=True, text=True, timeout=30).stdout.strip() == "0x1p-24"


def make_variant(form: str, real: str, prologue: str | None, dst: Path) -> None:
    """tests/fixtures/fair/<form>/ copied to `dst`, computing in `real`, fused when `prologue` is given."""
    if dst.exists():
        shutil.rmtree(dst)
    for src in sorted((fixture_dir("fair") / form).glob("*/*.cpp")):
        text = src.read_text()
        if REAL_LINE not in text:
            raise SystemExit(f"{src.relative_to(ROOT)} has no line '{REAL_LINE}'")
        text = text.replace(REAL_LINE, f"using real = {real};")
        if prologue:
            text = prologue + text
        out = dst / src.parent.name / src.name
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(text)


@dataclass
class Row:
    form: str
    step: str
    real: str
    fused: bool
    basic: set[str] = field(default_factory=set)            # failing basic cases (the same on every draw)
    hidden: list[tuple[int, str]] = field(default_factory=list)   # (draw, case) that failed
    hidden_runs: int = 0                                     # hidden case x draw pairs graded
    robust: set[str] = field(default_factory=set)           # failing ★ cases
    robust_total: int = 0
    basic_total: int = 0
    messages: dict[str, str] = field(default_factory=dict)  # a failing case -> its first message


def grade_variant(folder: Path, form: str, real: str, fused: bool, seeds: int, slot: str) -> list[Row]:
    """Grades the steps `folder` holds on `seeds` hidden draws (identities fair:0, fair:1, ...)."""
    steps = load_steps()
    chosen = [s for s in steps if (folder / s.folder).is_dir()]
    build: Build = submission_build(folder, slot)
    kit_side = bundle.ensure(detect_undefined())
    rows = []
    for step in chosen:
        row = Row(FORMS[form][step.number], step.number, real, fused)
        built = build_step(build, step, kit_side, NONE_OWN)
        for k in range(seeds):
            build.identity = f"fair:{k}"
            # The basic and ★ cases draw nothing: graded once; the hidden ones on every draw.
            result = judge_step(build, step, built, {}, NONE_OWN, None if k == 0 else {"hidden"})
            if not result.cases:
                raise SystemExit(f"{form} {real} step {step.number}: not graded ({result.state}): {result.detail[:600]}")
            for c in result.cases:
                failed = c.status != "pass"
                if failed and c.name not in row.messages:
                    row.messages[c.name] = " ".join(c.messages)[:300]
                if c.tier == "hidden":
                    row.hidden_runs += 1
                    if failed:
                        row.hidden.append((k, c.name))
                elif k == 0 and c.tier == "basic":
                    row.basic_total += 1
                    if failed:
                        row.basic.add(c.name)
                elif k == 0 and c.tier == "robust":
                    row.robust_total += 1
                    if failed:
                        row.robust.add(c.name)
        rows.append(row)
    return rows


def measure(seeds: int, forms: list[str] | None = None, fused_too: bool = True,
            progress=None) -> tuple[list[Row], str]:
    """Every form x type x contraction graded on `seeds` draws; and a note on the contraction."""
    prologue = fma_prologue() if fused_too else None
    note = ""
    if fused_too and prologue is None:
        note = "this CPU has no FMA: the fused columns were not run"
    elif prologue is not None and not probe_fuses(prologue):
        note, prologue = "the compiler did not fuse a*b + c under the prologue: the fused columns were not run", None
    rows = []
    with tempfile.TemporaryDirectory(prefix="raykit-fair-table-") as tmp:
        for form in forms or list(FORMS):
            for real in ("float", "double"):
                for fused in ([False, True] if prologue else [False]):
                    folder = Path(tmp) / f"{form}-{real}-{'fma' if fused else 'off'}"
                    make_variant(form, real, prologue if fused else None, folder)
                    started = time.monotonic()
                    got = grade_variant(folder, form, real, fused, seeds, f"fair-table-{form}")
                    rows += got
                    if progress:
                        progress(f"{form} {real} {'fma' if fused else 'off'}: "
                                 + ", ".join(f"step {r.step} basic {len(r.basic)} hidden {len(r.hidden)} "
                                             f"★ {len(r.robust)}" for r in got)
                                 + f" ({time.monotonic() - started:.0f} s)")
    return rows, note


def unfair(rows: list[Row]) -> list[str]:
    """A line for every basic or hidden failure: each is a fairness bug."""
    out = []
    for r in rows:
        where = f"{r.form} (step {r.step}, {r.real}, {'FMA' if r.fused else 'no contraction'})"
        for name in sorted(r.basic):
            out.append(f"{where}: basic '{name}': {r.messages.get(name, '')}")
        for k, name in r.hidden[:3]:
            out.append(f"{where}: hidden '{name}' on draw fair:{k}: {r.messages.get(name, '')}")
    return out


def table(rows: list[Row], seeds: int) -> str:
    lines = [f"| form | step | type | contraction | basic failed | hidden failed (of case x draws, {seeds} draws) "
             "| ★ failed |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r.form} | {r.step} | {r.real} | {'-ffp-contract=fast, FMA' if r.fused else 'off'} "
                     f"| {len(r.basic)} of {r.basic_total} | {len(r.hidden)} of {r.hidden_runs} "
                     f"| {len(r.robust)} of {r.robust_total} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python3 -m kit.fair_table", description=__doc__.split("\n\n")[0])
    p.add_argument("--seeds", type=int, default=100, help="hidden draws per form (default 100)")
    p.add_argument("--form", action="append", choices=list(FORMS), help="only this form (repeatable)")
    p.add_argument("--no-fma", action="store_true", help="leave out the fused columns")
    args = p.parse_args(argv)
    if not (ROOT / "solutions").is_dir():
        print("the fairness table needs the instructor's copy (solutions/, tests/hidden/)", file=sys.stderr)
        return 2
    started = time.monotonic()
    rows, note = measure(args.seeds, args.form, not args.no_fma, progress=lambda s: print(s, file=sys.stderr, flush=True))
    print(table(rows, args.seeds))
    if note:
        print(f"\n{note}")
    bad = unfair(rows)
    print(f"\n{len(bad)} basic or hidden failures ({time.monotonic() - started:.0f} s)")
    for line in bad[:40]:
        print("  " + line)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The figures of the ★ robust grading, measured: lecture 03's appendix B and robust_grading.hpp.

    python3 docs/robust_numbers.py --measure   # grade every form, write docs/robust_numbers.json (minutes)
    python3 docs/robust_numbers.py             # rewrite the generated blocks from docs/robust_numbers.json
    python3 docs/robust_numbers.py --check     # exit 1 when a block or the measurement is stale

--measure builds each way of writing steps 01-03 that the kit grades (the reference solutions, the
textbook formula, tests/fixtures/forms/) with `./kit`'s own build, runs each ★ case's judge alone with
RAYKIT_SHOW_ULPS=1 (tests/support/robust_grading.hpp prints every check's distance and the exact answer)
and stores every distance, with a digest of the files the figures depend on. Then the text between
`robust_numbers.py: NAME` markers in FILES is generated from that record, never typed by hand;
tests/kit/lectures.py runs --check (the blocks match the record, and the record's digest
matches today's suites, exact answers and forms). Python 3.9, standard library only.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "docs" / "robust_numbers.json"
FILES = [ROOT / "lectures" / "03-appendix.md", ROOT / "tests" / "support" / "robust_grading.hpp"]
STEPS = {"01": "01_unit_sphere", "02": "02_general_sphere", "03": "03_unit_direction"}
FIXTURES = ROOT / "tests" / "fixtures"
# form -> folder, per step: what the appendix's table compares.
FORMS = {
    "reference": {n: ROOT / "solutions" for n in STEPS},
    "textbook": {n: FIXTURES / "textbook" for n in STEPS},
    "float_leg": {"02": FIXTURES / "forms" / "float_leg"},
    "float_cross": {"02": FIXTURES / "forms" / "float_cross"},
    "double_textbook": {"02": FIXTURES / "forms" / "double_inside"},
}
COUNT = -1  # a check whose number of roots (or hit or miss) is wrong
BEGIN = re.compile(r"^(?:<!-- |// )robust_numbers\.py: ([\w-]+)(?: -->)?$")
END = re.compile(r"^(?:<!-- |// )/robust_numbers\.py(?: -->)?$")


class Stale(Exception):
    pass


def digest() -> str:
    """The files the figures depend on: the ★ suites, their exact answers, the grading, the forms."""
    paths = []
    for folder in STEPS.values():
        paths += [ROOT / "tests" / folder / "test_robust.cpp", ROOT / "tests" / folder / "exact_answers.cpp"]
        paths += [ROOT / "solutions" / folder, FIXTURES / "textbook" / folder]
    # The forms' folders of steps 01-03 only: a form of another step (forms/object_space/04_rectangles)
    # has no ★ figure here.
    paths += [d / folder for d in sorted((FIXTURES / "forms").iterdir()) for folder in STEPS.values()
              if (d / folder).is_dir()]
    paths += [ROOT / "tests" / "support" / "ulps.hpp"]
    h = hashlib.sha256()
    for p in paths:
        # A fixture's file kept as a patch (tests/fixtures/README.md) counts by its patch.
        for f in sorted([*p.rglob("*.cpp"), *p.rglob("*.cpp.patch")]) if p.is_dir() else [p]:
            if f.is_file():
                h.update(str(f.relative_to(ROOT)).encode() + b"\0" + f.read_bytes())
    return h.hexdigest()[:16]


# ---- measuring ---------------------------------------------------------------------------------

LINE = re.compile(r"^ulps\s+(\S+)(?: ulps)?\s\s(.*?)  exact: (.*)$")


def parse(stderr: str) -> list[tuple[int, list[float]]]:
    """(distance or COUNT, the exact roots or hit) of each logged check."""
    out = []
    for line in stderr.splitlines():
        m = LINE.match(line)
        if m:
            n = COUNT if m.group(1) == "NaN" else int(m.group(1))
            text = re.sub(r"\(count \d\)|t\[\d\]|^\d root", "", m.group(3))
            exact = sorted({float(x) for x in re.findall(r"-?(?:inf|\d+(?:\.\d*)?(?:e[-+]?\d+)?)", text)})
            out.append((n, exact))
    return out


def measure() -> dict:
    sys.path[:0] = [str(ROOT / "tools"), str(ROOT / "tests")]
    from raykit.build import build_targets, configure, submission_build  # noqa: E402
    from kit.fixtures import fixture_dir  # noqa: E402

    record = {"digest": digest(), "forms": {}}
    for form, by_step in FORMS.items():
        record["forms"][form] = {}
        for number, folder in by_step.items():
            if folder.is_relative_to(FIXTURES):     # a fixture, as the tests read it (patches applied)
                folder = fixture_dir(folder.relative_to(FIXTURES))
            build = submission_build(folder, "robust-numbers")
            configure(build)
            ok, log = build_targets(build, [f"test_step{number}", f"answers_step{number}"])
            if not ok:
                raise Stale(f"{folder.relative_to(ROOT)}: step {number} does not build:\n{log[-2000:]}")
            judge = build.binary_dir / f"test_step{number}"
            names = subprocess.run([str(judge), "-ts=robust", "--list-test-cases", "--no-version"],
                                   capture_output=True, text=True, cwd=build.binary_dir).stdout
            cases = [n.strip() for n in names.splitlines() if n.strip() and not n.startswith(("[doctest]", "=="))]
            record["forms"][form][number] = {}
            for case in cases:
                r = subprocess.run([str(judge), "-ts=robust", f"-tc={case}", "--no-version"], capture_output=True,
                                   text=True, cwd=build.binary_dir, env={**os.environ, "RAYKIT_SHOW_ULPS": "1"},
                                   timeout=120)
                record["forms"][form][number][case] = parse(r.stderr)
            print(f"robust_numbers.py: {form} step {number}: {len(cases)} ★ cases", file=sys.stderr)
    return record


# ---- the figures ---------------------------------------------------------------------------------

BOUND = 16


def thousands(n: int) -> str:
    return f"{n:,}".replace(",", "\u202f") if n >= 10000 else str(n)


class Figures:
    def __init__(self, record: dict):
        self.r = record["forms"]

    def checks(self, form, step):
        return self.r[form].get(step, {})

    def worst(self, form, step, case) -> int:
        """A case's worst check: its largest distance, or COUNT when a count was wrong."""
        ns = [n for n, _ in self.checks(form, step)[case]]
        return COUNT if COUNT in ns else max(ns, default=0)

    def passes(self, form, step, case) -> bool:
        w = self.worst(form, step, case)
        return w != COUNT and w <= BOUND

    def roots(self) -> list[float]:
        return [abs(t) for step in STEPS for checks in self.checks("reference", step).values()
                for _, exact in checks for t in exact]

    def largest_passing(self, form, step) -> int:
        return max((self.worst(form, step, c) for c in self.checks(form, step) if self.passes(form, step, c)),
                   default=0)

    def failed(self, step):
        return [c for c in self.checks("textbook", step) if not self.passes("textbook", step, c)]

    def textbook_worst(self, step) -> str:
        ws = [self.worst("textbook", step, c) for c in self.failed(step)]
        nums = sorted(w for w in ws if w != COUNT)
        text = f"{thousands(nums[0])} to {thousands(nums[-1])}" if len(nums) > 1 else \
            (thousands(nums[0]) if nums else "")
        if COUNT in ws:
            text += (", or " if text else "") + "a wrong count"
        return text

    def least_wrong(self, step) -> tuple[int, str]:
        """The smallest distance over the bound of a single textbook check, and its case."""
        best = (None, "")
        for case in self.failed(step):
            for n, _ in self.checks("textbook", step)[case]:
                if n > BOUND and (best[0] is None or n < best[0]):
                    best = (n, case)
        return best

    def textbook_passed(self, step) -> list[tuple[str, int]]:
        """(case, worst distance) of the cases the textbook passes; step 03's two functions as one case."""
        out: dict[str, int] = {}
        for c in self.checks("textbook", step):
            if self.passes("textbook", step, c):
                name = re.sub(r"^(?:shortcut|geometric): ", "", c)
                out[name] = max(out.get(name, 0), self.worst("textbook", step, c))
        return sorted(out.items())


def blocks(fig: Figures) -> dict[str, str]:
    roots = fig.roots()
    careful = max(fig.largest_passing(f, "02") for f in ("float_leg", "float_cross", "double_textbook"))
    ref = {s: fig.largest_passing("reference", s) for s in STEPS}
    least = {s: fig.least_wrong(s) for s in STEPS}
    lw = min((v for v in least.values() if v[0] is not None), key=lambda v: v[0])
    worst_fail = min(n for s in STEPS for c in fig.failed(s) for n in [fig.worst("textbook", s, c)] if n != COUNT)
    passed02 = fig.textbook_passed("02")
    passed03 = fig.textbook_passed("03")
    fails = {f: [c for c in fig.checks(f, "02") if not fig.passes(f, "02", c)]
             for f in ("float_leg", "float_cross", "double_textbook")}
    n02 = len(fig.checks("reference", "02"))

    def cases(names):
        return " and ".join(f'"{n}"' for n in names)

    out = {}
    out["appendix-range"] = (
        f"Ulps, not an absolute tolerance, because the exact roots and hits that the robust cases of steps 01 to 03\n"
        f"compare with ({len(roots)} of them) range from about {min(roots):.2g} to {thousands(round(max(roots)))}: "
        f"a fixed tolerance\nwould be far too loose for the one and far too tight for the other.")
    rows = [
        "| answer | step 01 | step 02 | step 03 |",
        "|---|---|---|---|",
        f"| the reference solutions (step 02's computes in double, section A) | {ref['01']} | {ref['02']} | {ref['03']} |",
        f"| lecture 03's float rewrites (the leg, the cross product), on the {n02 - len(fails['float_leg'])} ★ "
        f"cases of step 02 they pass | — | {max(fig.largest_passing('float_leg', '02'), fig.largest_passing('float_cross', '02'))} | — |",
        f"| the textbook formula computed in double, on the {n02 - len(fails['double_textbook'])} it passes | — | "
        f"{fig.largest_passing('double_textbook', '02')} | — |",
        "| the textbook formula: the worst ray of each case it fails | "
        + " | ".join(fig.textbook_worst(s) for s in STEPS) + " |",
        "| the textbook formula: the least wrong single ray over the bound | "
        + " | ".join(thousands(least[s][0]) if least[s][0] else "—" for s in STEPS) + " |",
        f"| the textbook formula, on the cases it passes ({cases(c for c, _ in passed02)}) | — | "
        + " and ".join(str(w) for _, w in passed02) + " | " + " and ".join(str(w) for _, w in passed03) + " |",
    ]
    out["appendix-table"] = "\n".join(rows)
    out["appendix-forms"] = (
        f"Not every careful answer passes every case. The float rewrites fail {cases(fails['float_leg'])}; the\n"
        f"textbook formula computed in double fails {cases(fails['double_textbook'])} (each case's message names "
        f"the forms\nthat pass it). On the cases they pass, these forms are at most {careful} ulps off; the reference "
        f"solutions, on every\nrobust case, at most {max(ref.values())} (step {max(ref, key=lambda k: (ref[k], k))} in "
        f"the table above).")
    out["appendix-margin"] = (
        f"Against the textbook formula the bound has two margins, and both matter. Each case the textbook fails,\n"
        f"it fails by at least {thousands(worst_fail)} ulps on its worst ray, or with a wrong count: "
        f"{worst_fail / BOUND:.0f} times the bound or more. But a case\n"
        f"is failed by any one ray over the bound, and the least wrong such ray is only {lw[0]} ulps off (in "
        f"\"{lw[1]}\"): {lw[0] / BOUND:.3g} times\nthe bound. That second figure is the safety margin that counts: "
        f"a formula a little better than the textbook\nwould start passing rays before it passed whole cases.")
    out["grading-bound"] = (
        f"/// The largest distance, in ulps, between a robust answer and the exact root of the same inputs\n"
        f"/// rounded to float. Measured on the robust inputs (docs/robust_numbers.py): the reference solutions\n"
        f"/// are at most {max(ref.values())} ulps off; lecture 03's float rewrites and the textbook formula in "
        f"double, on\n/// the cases they pass, at most {careful}. The textbook formula "
        f"(tests/fixtures/textbook/) is off by at least\n/// {worst_fail} on the worst ray of every case it fails "
        f"(or gets the number of roots wrong), but its least\n/// wrong single ray over the bound is {lw[0]} ulps "
        f"off: the margin that counts is {lw[0] / BOUND:.3g} times. Lecture 03's\n/// appendix, section B.")
    return out


def fill(text: str, generated: dict[str, str], where: str) -> tuple[str, list[str]]:
    """The text with every block replaced by its generated content, and the names of blocks that changed."""
    lines, out, changed, i = text.split("\n"), [], [], 0
    while i < len(lines):
        m = BEGIN.match(lines[i])
        out.append(lines[i])
        i += 1
        if not m:
            continue
        name = m.group(1)
        if name not in generated:
            raise Stale(f"{where}: unknown block {name}")
        j = i
        while j < len(lines) and not END.match(lines[j]):
            j += 1
        if j == len(lines):
            raise Stale(f"{where}: block {name} has no end marker")
        old = "\n".join(lines[i:j])
        if old != generated[name]:
            changed.append(f"{where}:{name}")
        out += generated[name].split("\n")
        i = j
    return "\n".join(out), changed


def run_files(record: dict, files: list[Path], check: bool) -> list[str]:
    generated = blocks(Figures(record))
    stale = []
    for p in files:
        new, changed = fill(p.read_text(), generated, p.name)
        stale += changed
        if changed and not check:
            p.write_text(new)
    return stale


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--measure", action="store_true", help="grade every form again and rewrite the record")
    ap.add_argument("--check", action="store_true", help="exit 1 when a block or the record is stale")
    ap.add_argument("--record", type=Path, default=RECORD)
    args = ap.parse_args(argv)
    try:
        if args.measure:
            args.record.write_text(json.dumps(measure(), indent=0, sort_keys=True) + "\n")
        try:
            record = json.loads(args.record.read_text())
            record["forms"]["reference"]
        except (OSError, ValueError, KeyError, TypeError) as e:
            raise Stale(f"cannot read {args.record}: {e}") from None
        if args.check and record.get("digest") != digest():
            print(f"robust_numbers.py: {args.record.name} was measured on other suites or forms than today's: "
                  "run python3 docs/robust_numbers.py --measure", file=sys.stderr)
            return 1
        stale = run_files(record, FILES, args.check)
    except Stale as e:
        print(f"robust_numbers.py: {e}", file=sys.stderr)
        return 2
    if args.check and stale:
        print("robust_numbers.py: stale: " + ", ".join(stale) + " (run python3 docs/robust_numbers.py)",
              file=sys.stderr)
        return 1
    if stale:
        print("robust_numbers.py: rewrote " + ", ".join(stale))
    return 0


if __name__ == "__main__":
    sys.exit(main())

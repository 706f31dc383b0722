"""./kit exact: the exact answers the suites compare with, precomputed from the instructor's copy.

The ★ robust cases (and step 03's check against step 02) compare a student's roots with the exact roots
of the same float inputs. A handout must not carry the code that computes them
(tests/support/reference_roots.hpp), so each step that asks for them has a generated data file,
tests/NN_topic/exact_answers.cpp: every (input -> exact answer) its cases ask for, keyed by the inputs'
bit patterns (tests/support/exact_answers.hpp explains the two builds).

The data is recorded, not typed: the reference build's test programs run every case with
RAYKIT_EXACT_RECORD set, and the interface appends each answer it computes. After adding or changing a
case that asks for exact answers:   ./kit exact --refresh   and commit the files it names.
Without --refresh the command only checks that the committed files are what a regeneration writes.
"""

from __future__ import annotations

import os
import subprocess
import tempfile
from pathlib import Path

from raykit.common import ROOT, KitError, Step, load_steps, say
from raykit.build import build_target, configure, preset_build

from raykit.packages import ensure_packages
from raykit.status import FAILED, OK, USAGE


DATA = "exact_answers.cpp"
INTERFACE = ("exact_answers.hpp", "robust_grading.hpp")   # a suite including either asks for answers
RUN_SECONDS = 300.0


def register(p) -> None:
    p.add_argument("--refresh", action="store_true",
                   help="rewrite tests/NN_topic/exact_answers.cpp from the reference solutions' build")


def data_file(step: Step, root: Path = ROOT) -> Path:
    return root / "tests" / step.folder / DATA


def users(steps: list[Step]) -> list[Step]:
    """The steps whose suites include the exact-answer interface."""
    return [s for s in steps if any(f'/{name}"' in p.read_text() for p in (ROOT / "tests" / s.folder).glob("*.cpp")
                                    if p.name != DATA for name in INTERFACE)]


# --- the data file's text ----------------------------------------------------------

def _entries(lines: list[str]) -> tuple[list[tuple], list[tuple]]:
    """Parses recorded lines ("roots KEY... count t0 t1 SUSPECTS", "hit KEY... hit t") into sorted, unique entries."""
    roots, hits = set(), set()
    for line in lines:
        words = line.replace(",", " ").split()
        if not words:
            continue
        values = tuple(int(w, 0) for w in words[1:])
        if words[0] == "roots" and len(values) == 28:
            roots.add(values)
        elif words[0] == "hit" and len(values) == 14:
            hits.add(values)
        else:
            raise KitError(f"unreadable line recorded by a test program: {line!r}", FAILED)
    return sorted(roots), sorted(hits)


def _hex(values) -> str:
    return ", ".join(f"0x{v:08x}" for v in values)


def data_text(step: Step, lines: list[str]) -> str:
    """The C++ data file for `step` from its recorded lines; the same lines give the same bytes."""
    roots, hits = _entries(lines)
    rel = f"tests/{step.folder}/{DATA}"
    out = [f"// Step {step.number}'s exact answers: every (input -> exact answer) its suites ask",
           "// tests/support/exact_answers.hpp for. GENERATED from the instructor's copy by",
           "//     ./kit exact --refresh",
           "// Do not edit: ./kit test checks that regenerating gives these bytes. Keys are the float",
           "// inputs' bit patterns: origin, direction, centre, radius (then tmin, tmax for a hit). A roots",
           "// entry ends with what the usual wrong formulas give (a = 1, c' in float, the textbook",
           "// formula and the shortcut in float, the textbook formula in double), from which a failure's",
           "// cause is measured.",
           "",
           '#include "../support/exact_answers.hpp"',
           "",
           "namespace raykit::exact {",
           "",
           "namespace {",
           ""]
    if roots:
        out.append("const RootsEntry roots[] = {")
        out += [f"    {{{{{_hex(e[:10])}}}, {e[10]}, {{{_hex(e[11:13])}}}, {{"
                + ", ".join(f"{{{e[i]}, {{{_hex(e[i + 1:i + 3])}}}}}" for i in (13, 16, 19, 22, 25)) + "}},"
                for e in roots]
        out += ["};", ""]
    if hits:
        out.append("const HitEntry hits[] = {")
        out += [f"    {{{{{_hex(e[:12])}}}, {e[12]}, 0x{e[13]:08x}}}," for e in hits]
        out += ["};", ""]
    out += ["}  // namespace",
            "",
            f"const Table table{{{'roots' if roots else 'nullptr'}, {len(roots)}, "
            f"{'hits' if hits else 'nullptr'}, {len(hits)}, \"{rel}\"}};",
            "",
            "}  // namespace raykit::exact",
            ""]
    return "\n".join(out)


# --- recording -----------------------------------------------------------------------

def recorded(build, step: Step) -> list[str]:
    """Runs every case of the step's reference test program and returns what it recorded."""
    # The judge (test_stepNN) asks the answers program for the step functions' answers.
    for target in (f"answers_step{step.number}", step.target):
        ok, out = build_target(build, target)
        if not ok:
            raise KitError(f"the reference build of step {step.number} does not compile:\n{out[-3000:]}", FAILED)
    with tempfile.TemporaryDirectory(prefix="raykit-exact-") as tmp:
        log = Path(tmp) / "record.txt"
        env = dict(os.environ, RAYKIT_EXACT_RECORD=str(log))
        try:
            r = subprocess.run([str(build.exe(step)), "--no-colors", "--test-suite-exclude=hidden"], env=env,
                               cwd=tmp, capture_output=True,
                               text=True, timeout=RUN_SECONDS)
        except subprocess.TimeoutExpired:
            raise KitError(f"step {step.number}'s reference test program ran over {RUN_SECONDS:g} s", FAILED) from None
        if r.returncode < 0 or not log.is_file():
            raise KitError(f"step {step.number}'s reference test program recorded nothing (exit status "
                           f"{r.returncode}):\n{(r.stdout + r.stderr)[-2000:]}", FAILED)
        return log.read_text().splitlines()


def fresh_texts(prepare: bool = False) -> dict[Path, str]:
    """{data file: the text a regeneration writes}, from the reference solutions.

    `prepare` first writes an empty table for a step that has none yet, so that its test program links.
    """
    if not (ROOT / "solutions").is_dir() or not (ROOT / "tests" / "support" / "reference_roots.hpp").is_file():
        raise KitError("./kit exact needs the instructor's copy of the kit (solutions/ and "
                       "tests/support/reference_roots.hpp); a handout only reads the committed data", USAGE)
    ensure_packages("build")
    chosen = users(load_steps())
    if prepare:
        for s in chosen:
            if not data_file(s).is_file():
                data_file(s).write_text(data_text(s, []))
    build = preset_build("reference")
    configure(build)
    return {data_file(s): data_text(s, recorded(build, s)) for s in chosen}


def stale(texts: dict[Path, str], root: Path = ROOT) -> list[str]:
    """The data files (under `root`) whose bytes differ from a regeneration's, relative to the kit."""
    mine = {path: root / path.relative_to(ROOT) for path in texts}
    return [path.relative_to(ROOT).as_posix() for path, text in texts.items()
            if not mine[path].is_file() or mine[path].read_text() != text]


def run(args) -> int:
    texts = fresh_texts(prepare=args.refresh)
    changed = stale(texts)
    counts = {p.relative_to(ROOT).as_posix(): t.count("\n    {") for p, t in texts.items()}
    if args.refresh:
        for path, text in texts.items():
            if path.relative_to(ROOT).as_posix() in changed:
                path.write_text(text)
        for rel, n in counts.items():
            say(f"  {rel}: {n} answers{' (rewritten)' if rel in changed else ''}")
        say("rewritten: " + ", ".join(changed) + "; commit them" if changed else "the data was up to date")
        return OK
    if changed:
        say("stale: " + ", ".join(changed) + "\n  regenerate with: ./kit exact --refresh (then commit)")
        return FAILED
    say("up to date: " + ", ".join(f"{rel} ({n} answers)" for rel, n in counts.items()))
    return OK

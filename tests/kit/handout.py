"""Self-test: a student handout carries no answers, is made from the committed stubs, and grades on its own.

Four checks:
  - the scan: a fresh handout has no step code outside steps/ (cmd_handout.SCAN_PATTERNS, on top of
    matching the reference solutions' lines), and the scanner is shown to catch every pattern by planting
    its example in a scratch copy of a shipped file;
  - the stubs: in a scratch clone of the kit with a solution copied into steps/, ./kit handout refuses and
    names the file, --committed ships the stub, --from-working-tree ships an edit with a warning but never
    a solution; inside a handout the command refuses;
  - the handout grades: stubs "not started", a mutant caught, the solutions done with every ★ case passing
    from the precomputed data, the textbook formula failing ★ cases, a stale table reported as such;
  - the ★ data is fresh: regenerating tests/NN_topic/exact_answers.cpp gives the committed bytes.
"""

from __future__ import annotations

import os
import json
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

from kitlib.commands import handout as cmd_handout
from raykit.mutants import patches, write_answer
from raykit.common import BUILD, ROOT, load_steps
from .support import Failed, expect, kit, need_solutions
from .fixtures import fixture_dir

TARGET = BUILD / "handout-test"


def _make_handout(target: Path = TARGET):
    shutil.rmtree(target, ignore_errors=True)
    r = kit("handout", str(target), "--committed")     # the committed stubs, whatever steps/ holds
    expect(r.returncode == 0, f"./kit handout failed:\n{r.stdout[-500:]}{r.stderr[-1500:]}")
    return r


def _secrets() -> set[str]:
    """Lines of the solutions that are not in the committed stubs."""
    lines: set[str] = set()
    for step in load_steps():
        stub = "".join(subprocess.run(["git", "show", f"HEAD:steps/{step.folder}/{f}"], cwd=ROOT,
                                      capture_output=True, text=True).stdout for f in step.files)
        lines |= cmd_handout.answer_lines(step, stub)
    return lines


@pytest.mark.quick
def selftest_scan(ctx) -> str:
    need_solutions()
    _make_handout()
    for gone in cmd_handout.EXCLUDED:
        expect(not (TARGET / gone).exists(), f"the handout contains {gone}")
    # Named as well as listed: ./kit bench is the instructor's (issue 56), so no part of bench/ ships.
    expect(not (TARGET / "bench").exists(), "the handout contains bench/ (./kit bench is the instructor's)")
    # 1. The scan for step code, on every file outside steps/.
    found = cmd_handout.scan_tree(TARGET)
    if found:
        first = next(iter(found))
        raise Failed(f"the handout's {first} holds step code: {', '.join(found[first])}")
    scanned = sum(1 for p in TARGET.rglob("*") if p.is_file() and p.relative_to(TARGET).parts[0] != "steps"
                  and cmd_handout.code_of(p, "") is not None)
    # 2. No line of a solution where one could slip in unnoticed: what students read and edit (the kit's
    #    code in tests/ and include/ shares generic lines with the solutions, a loop over the pixels say;
    #    the scan above covers it).
    secrets = _secrets()
    for path in [p for d in ("steps", "lectures", "docs") for p in (TARGET / d).rglob("*")] + list(TARGET.glob("*.md")):
        if path.is_file() and path.suffix in (".cpp", ".hpp", ".md", ".txt", ".json", ".html"):
            text = path.read_text(errors="replace")
            leaked = [line for line in secrets if line in text]
            if leaked:
                raise Failed(f"{path.relative_to(TARGET)} contains a solution line: {leaked[0]!r}")
    # 3. The scanner catches each pattern: planted as code in a scratch copy of a shipped file, never as a
    #    comment (the headers explain formulas in words).
    host = TARGET / "tools" / "render" / "tool.cpp"
    expect(host.is_file(), "the handout has no tools/render/tool.cpp to plant step code in")
    text = host.read_text()
    missed, noisy = [], []
    with tempfile.TemporaryDirectory() as tmp:
        scratch = Path(tmp) / "tools" / "render" / "tool.cpp"
        scratch.parent.mkdir(parents=True)
        for p in cmd_handout.SCAN_PATTERNS:
            scratch.write_text(text + f"\nnamespace planted {{\nvoid f() {{ {p.example} }}\n}}\n")
            if p.name not in cmd_handout.scan_tree(Path(tmp)).get("tools/render/tool.cpp", []):
                missed.append(p.name)
            scratch.write_text(text + f"\n// {p.example}\n/* {p.example} */\n")
            if cmd_handout.scan_tree(Path(tmp)):
                noisy.append(p.name)
        for line in cmd_handout.NOT_STEP_CODE:
            scratch.write_text(text + f"\nnamespace planted {{\nvoid f() {{ {line} }}\n}}\n")
            if cmd_handout.scan_tree(Path(tmp)):
                noisy.append(line)
    expect(not missed, "the scan misses planted step code: " + "; ".join(missed))
    expect(not noisy, "the scan flags a comment or code that is no step's: " + "; ".join(noisy))
    # 4. The README shows only what a student has.
    readme = (TARGET / "README.md").read_text()
    for word in ("./kit test", "solutions/", "tests/mutants", "tests/fixtures", "CONTRIBUTING", "instructor"):
        expect(word not in readme, f"the handout's README mentions {word!r}")
    return (f"{scanned} code files scanned, no step code and no solution line; each of the "
            f"{len(cmd_handout.SCAN_PATTERNS)} patterns caught when planted, none in a comment, none of "
            f"{len(cmd_handout.NOT_STEP_CODE)} look-alikes; README for students")


def _scratch_kit(where: Path) -> Path:
    """A git clone-like copy of the kit as it is now (its HEAD = the working tree), without build output."""
    kit_dir = where / "kit"
    for rel in cmd_handout.kit_files():
        src = ROOT / rel
        if rel.parts[0] in ("build", ".git") or not src.is_file():
            continue
        (kit_dir / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(src, kit_dir / rel)
    env = dict(os.environ, GIT_AUTHOR_NAME="kit", GIT_AUTHOR_EMAIL="kit@localhost", GIT_COMMITTER_NAME="kit",
               GIT_COMMITTER_EMAIL="kit@localhost")
    for cmd in (["init", "-q"], ["add", "-A"], ["commit", "-q", "-m", "scratch"]):
        subprocess.run(["git", *cmd], cwd=kit_dir, env=env, check=True, capture_output=True)
    return kit_dir


def selftest_from_committed_stubs(ctx) -> str:
    need_solutions()
    step = next(s for s in load_steps() if s.number == "02")
    rel = f"steps/{step.folder}/{step.files[0]}"
    with tempfile.TemporaryDirectory(dir=BUILD) as tmp:
        kit_dir = _scratch_kit(Path(tmp))

        def handout(*args):
            return subprocess.run([str(kit_dir / "kit"), "handout", *args], cwd=kit_dir, capture_output=True,
                                  text=True, timeout=300)

        stub = (kit_dir / rel).read_bytes()
        shutil.copyfile(kit_dir / "solutions" / step.folder / step.files[0], kit_dir / rel)
        out = Path(tmp) / "out"
        out.mkdir()
        r = handout(str(out / "a"))
        expect(r.returncode == 2 and rel in r.stderr and not (out / "a").exists(),
               f"with a solution in {rel}, ./kit handout exited {r.returncode} (expected 2, naming the file, "
               f"writing nothing):\n{r.stderr[-800:]}")
        r = handout(str(out / "b"), "--committed")
        expect(r.returncode == 0, f"./kit handout --committed failed:\n{r.stderr[-800:]}")
        expect((out / "b" / rel).read_bytes() == stub, f"./kit handout --committed did not ship the stub of {rel}")
        r = handout(str(out / "c"), "--from-working-tree")
        expect(r.returncode != 0 and ("reference solution" in r.stderr or "no stub" in r.stderr)
               and not (out / "c").exists(),
               f"./kit handout --from-working-tree shipped a solution (exit {r.returncode}):\n{r.stderr[-800:]}")
        edited = stub + b"\n// A note the instructor added to the stub.\n"
        (kit_dir / rel).write_bytes(edited)
        r = handout(str(out / "d"), "--from-working-tree")
        expect(r.returncode == 0 and "warning" in r.stderr and rel in r.stderr,
               f"./kit handout --from-working-tree with an edited stub: exit {r.returncode}, no warning naming "
               f"{rel}:\n{r.stderr[-800:]}")
        expect((out / "d" / rel).read_bytes() == edited, "--from-working-tree did not ship the working tree's file")
        r = subprocess.run([str(out / "b" / "kit"), "handout", str(out / "e")], cwd=out / "b", capture_output=True,
                           text=True, timeout=120)
        expect(r.returncode == 2 and "handout" in r.stderr and not (out / "e").exists(),
               f"./kit handout inside a handout exited {r.returncode}, expected 2:\n{r.stderr[-500:]}")
        # A solution committed into steps/ by mistake: HEAD itself holds the answer.
        shutil.copyfile(kit_dir / "solutions" / step.folder / step.files[0], kit_dir / rel)
        subprocess.run(["git", "-c", "user.name=kit", "-c", "user.email=kit@localhost", "commit", "-q", "-am",
                        "oops"], cwd=kit_dir, check=True, capture_output=True)
        r = handout(str(out / "f"))
        expect(r.returncode == 1 and "no stub" in r.stderr and not (out / "f").exists(),
               f"with a solution committed into {rel}, ./kit handout exited {r.returncode}:\n{r.stderr[-500:]}")
    return ("a solution in steps/: refused naming the file, --committed ships the stub, --from-working-tree "
            "refuses the solution and ships an edit with a warning; a committed solution refused; refused inside "
            "a handout")


def _board(stdout: str) -> dict[str, str]:
    """{step number: its scoreboard line}."""
    return {m.group(1): m.group(0) for m in re.finditer(r"^\s*(\d\d)\s+\S.*$", stdout, re.M)}


def selftest_handout_grades(ctx) -> str:
    need_solutions()
    _make_handout()
    steps = load_steps()

    def check(*args):
        return subprocess.run([str(TARGET / "kit"), "check", *args], cwd=TARGET, capture_output=True,
                              text=True, timeout=900)

    def put(folder: Path, step):
        for f in step.files:
            if (folder / f).is_file():
                shutil.copyfile(folder / f, TARGET / "steps" / step.folder / f)

    r = check()
    board = _board(r.stdout)
    for s in steps:
        line = board.get(s.number, "")
        expect("not started" in line or (s.needs and "needs" in line),
               f"handout: step {s.number}'s stub is not 'not started': {line!r}\n{r.stdout[-800:]}")
    first = steps[0]
    mutant = patches(first)[0]
    put(write_answer(first, mutant, BUILD / "handout-mutant"), first)
    r = check(str(int(first.number)))
    expect(r.returncode == 1 and "done" not in _board(r.stdout).get(first.number, "done"),
           f"handout: a wrong answer ({mutant.stem}) is not caught:\n{r.stdout[-800:]}")
    for s in steps:
        put(ROOT / "solutions" / s.folder, s)
    r = check()
    expect(r.returncode == 0, f"handout: the solutions are not all done:\n{r.stdout[-1500:]}")
    robust = 0
    for s in steps:
        line = _board(r.stdout).get(s.number, "")
        m = re.search(r"★ robust (\d+) of (\d+)", line)
        expect("done" in line and (m is None or m.group(1) == m.group(2)),
               f"handout: step {s.number} with the solution is not done with every ★ case: {line!r}")
        robust += int(m.group(2)) if m else 0
    # The ★ tier from data still tells a textbook formula from a robust one.
    textbook = fixture_dir("textbook")
    two = next(s for s in steps if s.number == "02")
    put(textbook / two.folder, two)
    r = check("2")
    m = re.search(r"★ robust (\d+) of (\d+)", _board(r.stdout).get("02", ""))
    expect(m is not None and int(m.group(1)) < int(m.group(2)),
           f"handout: the textbook step 02 passes every ★ case graded from the data:\n{r.stdout[-1000:]}")
    textbook_score = f"{m.group(1)} of {m.group(2)}"
    put(ROOT / "solutions" / two.folder, two)
    # A table without the entry a case asks for: the case fails and says the data is stale.
    data = TARGET / "tests" / first.folder / "exact_answers.cpp"
    original = data.read_text()
    try:
        entry = re.search(r"\{\{(0x[0-9a-f]{8})", original)
        expect(entry is not None, f"{data.relative_to(TARGET)} has no entry")
        flipped = f"0x{int(entry.group(1), 16) ^ 0x00400000:08x}"  # millions of ulps away: no snapping
        data.write_text(original.replace("{{" + entry.group(1), "{{" + flipped, 1))
        r = check(str(int(first.number)), "--all")     # a done step's ★ cases show with --all
        m = re.search(r"★ robust (\d+) of (\d+)", _board(r.stdout).get(first.number, ""))
        expect("older than this case" in r.stdout and m is not None and int(m.group(1)) < int(m.group(2)),
               f"handout: a table without the entry a ★ case asks for is not reported:\n{r.stdout[-1500:]}")
    finally:
        data.write_text(original)
    # ./kit help in the handout: the students' commands, no instructor's command (the self-test included).
    from kitlib.cli import COMMANDS, INSTRUCTOR, STUDENT
    r = subprocess.run([str(TARGET / "kit"), "help"], cwd=TARGET, capture_output=True, text=True, timeout=60)
    listed = re.findall(r"^  (\w+)\s", r.stdout, re.M)
    students = [c.name for c in COMMANDS if c.audience == STUDENT]
    expect(listed == students and "instructors" not in r.stdout,
           f"handout: ./kit help lists {listed}, not the students' commands {students} alone")
    for c in (c for c in COMMANDS if c.audience == INSTRUCTOR):
        r = subprocess.run([str(TARGET / "kit"), c.name, "x"], cwd=TARGET, capture_output=True, text=True, timeout=60)
        expect(r.returncode == 2 and "instructor's command" in r.stderr, f"handout: ./kit {c.name} says {r.stderr[-300:]}")
    # Only the student's package of the driver (tools/raykit), whole: no module of the instructor's
    # (tools/kitlib: the self-test, the instructor's commands), no autograder.
    shipped = {p.relative_to(TARGET).as_posix() for p in TARGET.rglob("*") if p.is_file()}
    instructor = [p for p in shipped if p.startswith(("tools/kitlib/", "tests/kit/", "pytest.ini", "tools/gradescope/", "tools/portability/"))]
    expect(not instructor, f"handout: ships the instructor's {sorted(instructor)[:4]}")
    runtime = {p.relative_to(ROOT).as_posix() for p in (ROOT / "tools" / "raykit").rglob("*.py")
               if "__pycache__" not in p.parts}
    missing = sorted(runtime - shipped)
    expect(not missing, f"handout: lacks modules of the student's runtime: {missing[:4]}")
    from kitlib.commands.handout import SCAN_PATTERNS
    planted = [(p, pat.name) for p in sorted(shipped) if not p.startswith("steps/") for pat in SCAN_PATTERNS
               if pat.example in (TARGET / p).read_text(errors="replace")]     # steps/ holds the solutions now
    expect(not planted, f"handout: {planted[:1]} ships a scan example (a line of step code)")
    launch = json.loads(re.sub(r"^\s*//.*$", "", (TARGET / ".vscode" / "launch.json").read_text(), flags=re.M))
    options = next(i["options"] for i in launch["inputs"] if i["id"] == "step")
    expect(options == [s.number for s in steps], f"handout: launch.json offers steps {options}")
    shutil.rmtree(TARGET, ignore_errors=True)
    return (f"stubs not started, {mutant.stem} caught, solutions done with {robust} ★ cases from the data, "
            f"textbook step 02 ★ {textbook_score}, a stale entry reported; only the students' side ships")


def selftest_exact_data_fresh(ctx) -> str:
    need_solutions()
    from kitlib.commands import exact as cmd_exact

    texts = cmd_exact.fresh_texts()
    stale = cmd_exact.stale(texts)
    expect(not stale, "stale: " + ", ".join(stale) + "; run ./kit exact --refresh and commit")
    # The comparison is byte for byte: one changed digit in a scratch copy is reported.
    path, text = next(iter(texts.items()))
    with tempfile.TemporaryDirectory() as tmp:
        copy = Path(tmp) / path.relative_to(ROOT)
        copy.parent.mkdir(parents=True)
        copy.write_text(text.replace("0x", "0X", 1))
        expect(cmd_exact.stale({path: text}, Path(tmp)) == [path.relative_to(ROOT).as_posix()],
               "a changed data file is not reported stale")
    answers = sum(t.count("\n    {") for t in texts.values())
    return f"{len(texts)} data files, {answers} exact answers, regenerated byte for byte; a changed one is caught"

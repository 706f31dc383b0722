"""Self-test: a student handout leaves the answers out, and grades on its own."""

from __future__ import annotations

import shutil
import subprocess

from cmd_mutant import patches, write_answer
from common import BUILD, ROOT, load_steps


def _answer_lines(step) -> set[str]:
    """Lines of the reference solution that are not in the stub: what a handout must not contain."""
    lines: set[str] = set()
    for f in step.files:
        stub = {l.strip() for l in (ROOT / "steps" / step.folder / f).read_text().splitlines()}
        for line in (ROOT / "solutions" / step.folder / f).read_text().splitlines():
            line = line.strip()
            if len(line) > 24 and line not in stub and not line.startswith(("//", "#include")):
                lines.add(line)
    return lines


def check_handout(ctx) -> str:
    from cmd_test import Failed, expect, kit, need_solutions

    need_solutions()
    target = BUILD / "handout-test"
    shutil.rmtree(target, ignore_errors=True)
    r = kit("handout", str(target))
    expect(r.returncode == 0, f"./kit handout failed: {r.stderr[-500:]}")
    for gone in ("solutions", "tests/mutants", "tests/fixtures", ".git", "build"):
        expect(not (target / gone).exists(), f"the handout contains {gone}/")
    secrets = set()
    for step in load_steps():
        secrets |= _answer_lines(step)
    # Where an answer could slip in unnoticed: what students read and edit (the kit's own code in
    # tests/ and include/ shares generic lines with the solutions, such as a constant's definition).
    for path in [p for d in ("steps", "lectures", "docs") for p in (target / d).rglob("*")] + list(target.glob("*.md")):
        if path.is_file() and path.suffix in (".cpp", ".hpp", ".md", ".txt", ".json", ".html"):
            text = path.read_text(errors="replace")
            leaked = [l for l in secrets if l in text]
            if leaked:
                raise Failed(f"{path.relative_to(target)} contains a solution line: {leaked[0]!r}")

    def check(*args):
        return subprocess.run([str(target / "kit"), "check", *args], cwd=target, capture_output=True,
                              text=True, timeout=600)

    step = load_steps()[0]
    r = check(str(int(step.number)))
    expect(r.returncode == 1 and "not started" in r.stdout, f"handout: a fresh step is not 'not started':\n{r.stdout[-800:]}")
    mutant = patches(step)[0]
    answer = write_answer(step, mutant, BUILD / "handout-mutant")
    for f in step.files:
        shutil.copyfile(answer / f, target / "steps" / step.folder / f)
    r = check(str(int(step.number)))
    expect(r.returncode == 1 and "of" in r.stdout, f"handout: a wrong answer ({mutant.stem}) is not caught")
    for f in step.files:
        shutil.copyfile(ROOT / "solutions" / step.folder / f, target / "steps" / step.folder / f)
    r = check(str(int(step.number)))
    expect(r.returncode == 0 and "done" in r.stdout, f"handout: the right answer is not 'done':\n{r.stdout[-800:]}")
    r = subprocess.run([str(target / "kit"), "test", "--fast"], cwd=target, capture_output=True, text=True, timeout=900)
    expect(r.returncode == 0, f"the handout's own ./kit test failed:\n{r.stdout[-1500:]}")
    shutil.rmtree(target, ignore_errors=True)
    return ("no solution line in the copy; "
            f"step {step.number}: stub not started, {mutant.stem} caught, solution done; its ./kit test passes")


def checks():
    return [("student handout", check_handout)]

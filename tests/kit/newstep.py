"""Self-test: a new step, added the way CONTRIBUTING.md says and in no other way, works.

A scratch copy of the kit (the files git knows, as `./kit handout` lists them, in a git repository
of its own under build/newstep-kit/) gets a toy step 06, "A plane": the files of the template
tests/fixtures/new_step/, each at the path it has there, and every one of them a path that
CONTRIBUTING.md's "## A step" or "## A mutant" names (checked first: a template file CONTRIBUTING
does not name fails this self-test, so the template can hold nothing else). Then, in the copy, with
CONTRIBUTING's commands only:

- `./kit check 6 --record`, and a commit (the handout ships the committed stubs);
- `./kit check 6` on the stub: "not started", exit 1;
- the mutants, each `./kit mutant new 6 NAME`, one slip in the copy (SLIPS), `./kit mutant save 6 NAME
  --slip ... --caught-by CASE`; then `./kit report --signatures --step 6`; a commit;
- `./kit handout DIR`: step 06's stub and lecture ship, its solution and mutants do not, and the
  handout's own `./kit check 6` says "not started";
- the rules `./kit test` enforces on a step, run on step 06 in the copy (rules_here): case names and
  lecture headings, the judge's functions derived from step.json, the recorded stubs and case lists, hints (at
  least 3, no code, their section pointers), every rule of the header asked by a case, the slide
  deck's shape, the mutants (at least 8, each caught by its named case) and their signatures; and
  the docs: step 06 on the front page with its lecture, task and function, the student and the
  instructor site built by Doxygen without a warning, no line of a solution in the student's (the
  browser check of the pages is not run here);
- the solution copied into steps/: `./kit check 6` says "done", exit 0.

`./kit test --fast` leaves out the Doxygen builds and the second grading of the mutants (50-56 s
instead of 65-100 s, measured on the shared 2-core machine with the kit cache warm). What each rule said is kept in build/newstep-rules.jsonl.

The template is step 06; in a kit that already has a step 06 (an instructor's own, or this template
added as CONTRIBUTING says) it is added as the next free number, its paths and the words naming its
number renumbered (numbered()), so a customised kit's ./kit test passes here too.

It can fail: RAYKIT_NEWSTEP_DROP=tests/06_plane/hints.md (a comma-separated list of template
paths) leaves those files out of the step, as if CONTRIBUTING's list lacked them.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from raykit.common import BUILD, ROOT
from .support import Failed, expect, need_solutions
from .fixtures import fixture_dir

COPY = BUILD / "newstep-kit"
RULES_LOG = BUILD / "newstep-rules.jsonl"     # what each rule said, kept after the copy is gone
# The template is written as step 06 (TEMPLATE_NUMBER); a kit whose instructor added steps of their
# own (a step 06 of theirs, or this very template) gets it as the next free number instead: its paths
# and the words that name its number are renumbered in the copy (numbered()). use() sets these.
TEMPLATE_NUMBER = "06"
NUMBER, FOLDER = TEMPLATE_NUMBER, f"{TEMPLATE_NUMBER}_plane"
SOLUTION = f"solutions/{FOLDER}/plane.cpp"


def use(number: str) -> None:
    global NUMBER, FOLDER, SOLUTION
    NUMBER, FOLDER = number, f"{number}_plane"
    SOLUTION = f"solutions/{FOLDER}/plane.cpp"


def free_number() -> str:
    """The number the kit's next step takes: one more than its last (06 in the kit as shipped)."""
    from raykit.common import load_steps
    taken = [int(s.number) for s in load_steps()]
    taken += [int(p.name[:2]) for p in (ROOT / "tests").glob("[0-9][0-9]_*") if p.is_dir()]
    return f"{max(taken, default=0) + 1:02d}"


def numbered(rel: Path, text: str, number: str) -> tuple[Path, str]:
    """A template file's path and text for step `number`: its folders, its lecture's name and the
    words that name the step (Step 06, Lecture 06, ./kit check 6) renumbered."""
    if number == TEMPLATE_NUMBER:
        return rel, text
    t = TEMPLATE_NUMBER
    swaps = [(f"{t}_plane", f"{number}_plane"), (f"{t}-plane", f"{number}-plane"), (f"Step {t}", f"Step {number}"),
             (f"step {t}", f"step {number}"), (f"Lecture {t}", f"Lecture {number}"),
             (f"check {int(t)}`", f"check {int(number)}`"), (f"check {int(t)}\n", f"check {int(number)}\n")]
    path = rel.as_posix()
    for a, b in swaps:
        path, text = path.replace(a, b), text.replace(a, b)
    return Path(path), text

# The mutants: (name, the reference's text, the slip's text, the slip in one line, the case made for it).
SLIPS = [
    ("parallel_not_guarded", "    if (speed == 0.0f) return std::nullopt;\n", "",
     "a ray parallel to the plane is divided by zero.", "a ray parallel to the plane beside it is no hit"),
    ("gap_reversed", "offset - glm::dot(normal, ray.origin);", "glm::dot(normal, ray.origin) - offset;",
     "the gap is taken the wrong way round.", "a ray straight at the plane z = 5 hits it at t = 5"),
    ("offset_ignored", "offset - glm::dot(normal, ray.origin);", "-glm::dot(normal, ray.origin);",
     "the plane is taken through the origin.", "a ray straight at the plane z = 5 hits it at t = 5"),
    ("speed_from_origin", "glm::dot(normal, ray.direction);", "glm::dot(normal, ray.origin + ray.direction);",
     "the speed along the normal adds the origin.", "a longer direction takes fewer steps"),
    ("tmin_open", "!(tmin <= t && t <= tmax)", "!(tmin < t && t <= tmax)",
     "the window is open at tmin.", "a hit exactly at tmin counts"),
    ("tmax_open", "!(tmin <= t && t <= tmax)", "!(tmin <= t && t < tmax)",
     "the window is open at tmax.", "a hit exactly at tmax counts"),
    ("tmax_ignored", "!(tmin <= t && t <= tmax)", "!(tmin <= t)",
     "tmax is never tested.", "a hit after tmax is no hit"),
    ("nan_accepted", "!(tmin <= t && t <= tmax)", "(t < tmin || t > tmax)",
     "the window test lets a NaN t through.", "a NaN origin is no hit"),
]

# The sections of CONTRIBUTING.md whose paths a step may have.
SECTIONS = ("## A step", "## A mutant")


def contributing_paths(text: str) -> list[re.Pattern]:
    """The file paths CONTRIBUTING's step and mutant sections name, as patterns: NN_topic, NN-topic,
    stepNN, <file>, SLIP and * stand for any name."""
    parts = re.split(r"^(## .*)$", text, flags=re.M)
    body = "".join(parts[i + 1] for i in range(1, len(parts) - 1, 2) if parts[i].strip() in SECTIONS)
    found = []
    for span in re.findall(r"`([^`\s]+/[^`\s]*)`", body):
        p = re.escape(span)
        for word, stands in ((r"NN_topic", r"\d\d_[a-z0-9_]+"), (r"NN\-topic", r"\d\d-[a-z0-9-]+"),
                             (r"stepNN", r"step\d\d"), (r"SLIP", r"[a-z0-9_]+"), (r"\*", r"[^/]*")):
            p = p.replace(word, stands)
        p = re.sub(r"<[^>]*>", r"[^/]+", p)
        found.append(re.compile(p))
    return found


def template_files() -> list[Path]:
    dropped = {d.strip() for d in os.environ.get("RAYKIT_NEWSTEP_DROP", "").split(",") if d.strip()}
    files = sorted(p.relative_to(fixture_dir("new_step")) for p in fixture_dir("new_step").rglob("*") if p.is_file())
    return [f for f in files if f.as_posix() not in dropped]


def scratch_kit(where: Path) -> Path:
    """A copy of the kit's files (tracked, or new and not ignored: handout.kit_files) at `where`, in a
    git repository of its own, so that git in it never reads the kit's own history."""
    from kitlib.commands.handout import kit_files
    shutil.rmtree(where, ignore_errors=True)
    for rel in kit_files():
        if rel.parts[0] == "build":
            continue
        src, dst = ROOT / rel, where / rel
        if src.is_file() or src.is_symlink():
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst, follow_symlinks=False)
    git(where, "init", "-q")
    commit(where, "the kit")
    return where


def git(where: Path, *args: str) -> subprocess.CompletedProcess:
    r = subprocess.run(["git", "-c", "user.name=raykit selftest", "-c", "user.email=selftest@raykit.invalid",
                        "-c", "commit.gpgsign=false", *args], cwd=where, capture_output=True, text=True)
    expect(r.returncode == 0, f"git {' '.join(args)} in {where}: {r.stderr[-400:]}")
    return r


def commit(where: Path, message: str) -> None:
    git(where, "add", "-A")
    git(where, "commit", "-q", "--allow-empty", "-m", message)


def run_kit(where: Path, *args: str, timeout: float = 900) -> subprocess.CompletedProcess:
    return subprocess.run([str(where / "kit"), *args], cwd=where, capture_output=True, text=True, timeout=timeout)


def said(r: subprocess.CompletedProcess) -> str:
    """What a command said, long output shortened by whole lines (its first 8 and last 30), never mid-word."""
    lines = (r.stdout + r.stderr).strip().splitlines()
    return "\n".join(lines if len(lines) <= 40 else lines[:8] + ["..."] + lines[-30:])


def selftest_new_step(ctx) -> str:
    need_solutions()
    start = time.monotonic()
    times = {}

    def lap(name: str) -> None:
        nonlocal start
        times[name] = time.monotonic() - start
        start = time.monotonic()

    use(free_number())
    # 0. The template holds only what CONTRIBUTING names.
    patterns = contributing_paths((ROOT / "CONTRIBUTING.md").read_text())
    files = template_files()
    unnamed = [f.as_posix() for f in files if not any(p.fullmatch(f.as_posix()) for p in patterns)]
    expect(not unnamed, "the template has files CONTRIBUTING.md's \"## A step\" does not name: " + ", ".join(unnamed))
    kit_dir = scratch_kit(COPY)
    for f in files:
        rel, text = numbered(f, (fixture_dir("new_step") / f).read_text(), NUMBER)
        (kit_dir / rel).parent.mkdir(parents=True, exist_ok=True)
        (kit_dir / rel).write_text(text)
    lap("copy")

    # 1. Record, commit, the stub is not started.
    r = run_kit(kit_dir, "check", NUMBER, "--record")
    expect(r.returncode == 0, f"./kit check {NUMBER} --record on the new step exited {r.returncode}:\n{said(r)}")
    commit(kit_dir, f"step {NUMBER}")
    lap("record")
    r = run_kit(kit_dir, "check", NUMBER)
    expect(r.returncode == 1 and "not started" in r.stdout,
           f"./kit check {NUMBER} on the new step's stub: exit {r.returncode}, not 'not started':\n{said(r)}")
    lap("stub")

    # 2. The mutants, CONTRIBUTING's way.
    reference = (kit_dir / SOLUTION).read_text()
    for name, old, new, slip, case in SLIPS:
        expect(reference.count(old) == 1, f"the template's {SOLUTION} no longer has, once, the line slip {name} changes")
        r = run_kit(kit_dir, "mutant", "new", NUMBER, name)
        copy = kit_dir / "build" / "mutants" / FOLDER / name / "plane.cpp"
        expect(r.returncode == 0 and copy.is_file(), f"./kit mutant new {NUMBER} {name}: exit {r.returncode}\n{said(r)}")
        copy.write_text(copy.read_text().replace(old, new, 1))
        r = run_kit(kit_dir, "mutant", "save", NUMBER, name, "--slip", slip, "--caught-by", case)
        expect(r.returncode == 0, f"./kit mutant save {NUMBER} {name}: exit {r.returncode}\n{said(r)}")
    r = run_kit(kit_dir, "report", "--signatures", "--step", NUMBER)
    expect(r.returncode == 0, f"./kit report --signatures --step {NUMBER}: exit {r.returncode}\n{said(r)}")
    commit(kit_dir, f"step {NUMBER}'s mutants and their signatures")
    lap("mutants")

    # 3. The handout.
    handout = kit_dir / "build" / "newstep-handout"
    r = run_kit(kit_dir, "handout", str(handout))
    expect(r.returncode == 0, f"./kit handout with step {NUMBER}: exit {r.returncode}\n{said(r)}")
    stub = kit_dir / "steps" / FOLDER / "plane.cpp"
    shipped = handout / "steps" / FOLDER / "plane.cpp"
    expect(shipped.is_file() and shipped.read_text() == stub.read_text(), f"the handout's step {NUMBER} is not its stub")
    for gone in ("solutions", f"tests/mutants/{FOLDER}"):
        expect(not (handout / gone).exists(), f"the handout has {gone}")
    expect((handout / "tests" / FOLDER / "test_plane.cpp").is_file() and (handout / "lectures" / f"{NUMBER}-plane.md").is_file(),
           f"the handout lacks step {NUMBER}'s suite or its lecture")
    r = run_kit(handout, "check", NUMBER)
    expect(r.returncode == 1 and "not started" in r.stdout, f"the handout's ./kit check {NUMBER}: exit {r.returncode}\n{said(r)}")
    shutil.rmtree(handout, ignore_errors=True)
    lap("handout")

    # 4. The rules ./kit test enforces on a step, on step 06 in the copy.
    r = subprocess.run([sys.executable, "-c", "import sys; sys.path[:0] = ['tools', 'tests']; "
                        "from kit import newstep; sys.exit(newstep.rules_here())"],
                       cwd=kit_dir, capture_output=True, text=True, timeout=1800,
                       env=dict(os.environ, RAYKIT_NEWSTEP_FAST="1" if ctx.fast else "", RAYKIT_NEWSTEP_NUMBER=NUMBER))
    lines = [json.loads(l) for l in r.stdout.splitlines() if l.startswith("{")]
    RULES_LOG.write_text("".join(json.dumps(l, ensure_ascii=False) + "\n" for l in lines))
    bad = [f"{l['rule']}: {l['failed']}" for l in lines if "failed" in l]
    expect(lines and r.returncode == 0 and not bad,
           "the rules of ./kit test on the new step:\n  " + ("\n  ".join(bad) if bad else said(r)))
    lap("rules")

    # 5. The solution in steps/: done.
    shutil.copyfile(kit_dir / SOLUTION, stub)
    r = run_kit(kit_dir, "check", NUMBER)
    expect(r.returncode == 0 and "done" in r.stdout, f"./kit check {NUMBER} with the solution in steps/: exit "
           f"{r.returncode}\n{said(r)}")
    lap("solution")
    shutil.rmtree(COPY, ignore_errors=True)
    spent = ", ".join(f"{k} {v:.0f} s" for k, v in times.items())
    return (f"step {NUMBER} from {len(files)} template files, all named by CONTRIBUTING: stub not started, "
            f"{len(SLIPS)} mutants saved, handout ships the stub only, {len(lines)} rules hold, solution done ({spent})")


# --- run inside the copy ----------------------------------------------------------------

def rules_here() -> int:
    """In the scratch copy (ROOT is the copy): each rule of ./kit test that a step must keep, run on
    step NUMBER; one JSON line per rule. The exit status is 1 when one fails."""
    from raykit.common import load_steps
    from raykit.build import build_target, configure, preset_build
    from kitlib.commands import docs
    from . import check, hint, latency, lectures, mutant, slides
    from . import docs as docs_tests
    from .support import Context, Skipped, committed_steps

    use(os.environ.get("RAYKIT_NEWSTEP_NUMBER") or TEMPLATE_NUMBER)
    steps = [s for s in load_steps() if s.number == NUMBER]
    ctx = Context(fast=True, steps=steps)

    def reference_judge(c) -> str:
        build = preset_build("reference")
        configure(build)
        ok, out = build_target(build, steps[0].target)
        expect(ok, f"the reference build of step {NUMBER}'s judge fails (-Werror):\n{out[-1500:]}")
        return "built with warnings as errors"

    def front_page(c) -> str:
        page = docs.front_page(docs.gather(False), False)
        heading = f"### Step {NUMBER}: {steps[0].title}"
        expect(heading in page, f"the docs' front page has no {heading!r}")
        section = re.split(r"\n##", page.split(heading, 1)[1], maxsplit=1)[0]
        want = ["**Lecture:** \\ref", f"\"steps/{FOLDER}/README.md\"", "\\ref raykit::intersect_plane",
                "declared in `raykit/plane.hpp`"]
        missing = [w for w in want if w not in section]
        expect(not missing, f"the docs' front page lacks, for step {NUMBER}: {missing}:\n{section}")
        return f"step {NUMBER} listed with its lecture, task and function"

    def signed(c) -> str:
        # report.selftest_signatures_fresh's rule, on this step's mutants only (another step's stale
        # signatures are that step's business, and ./kit test report names them).
        from raykit.mutants import patches
        from kitlib.report import signatures
        recorded = json.loads(signatures.FILE.read_text())["mutants"]
        bad = []
        for path in patches(steps[0]):
            key = f"{FOLDER}/{path.stem}"
            e = recorded.get(key)
            if not isinstance(e, dict) or not e.get("fails"):
                bad.append(f"{key}: no signature, or one that fails no basic case")
            elif e.get("fingerprint") != signatures.fingerprint(steps[0], path):
                bad.append(f"{key}: recorded before its patch, reference or tests changed")
        expect(not bad, "; ".join(bad) + ": ./kit report --signatures --step " + NUMBER)
        return f"{len(patches(steps[0]))} signatures current"

    # The session fixtures (conftest.py) the rules take, made here as the fixtures make them.
    def kit_side():
        from raykit import bundle
        from raykit.build import detect_undefined
        return bundle.ensure(detect_undefined())

    def case_names(c) -> str:
        return check.selftest_case_names_and_lectures(c, kit_side())

    def no_solutions(c) -> str:
        with tempfile.TemporaryDirectory(prefix="raykit-newstep-steps-") as tmp:
            return docs_tests.selftest_no_solutions(c, committed_steps(Path(tmp)))

    rules = [("the reference judge builds", reference_judge),
             ("case names and lecture headings", case_names),
             ("the judge's functions from step.json", check.selftest_remote_lists),
             ("recorded stubs and case lists", latency.selftest_recorded),
             ("hints", hint.selftest_hints),
             ("hints' section pointers", lectures.selftest_hint_sections),
             ("every rule of a header has a case", lectures.selftest_contract_clauses),
             ("slide decks", slides.selftest_structure),
             ("mutants caught", mutant.selftest_mutants),
             ("mutant signatures current", signed),
             ("the docs' front page", front_page),
             ("the docs build without a warning", docs_tests.selftest_site_builds),
             ("no solution line in the student docs", no_solutions)]
    if os.environ.get("RAYKIT_NEWSTEP_FAST") == "1":
        # --fast: no Doxygen, and the mutants are not graded again (`./kit mutant save --caught-by`
        # graded each, and failed unless its named case caught it).
        slow = {"mutants caught", "the docs build without a warning", "no solution line in the student docs"}
        rules = [(n, f) for n, f in rules if n not in slow]
    failed = False
    for name, fn in rules:
        try:
            print(json.dumps({"rule": name, "passed": fn(ctx)}), flush=True)
        except (Failed, Skipped, Exception) as e:
            failed = True
            print(json.dumps({"rule": name, "failed": f"{type(e).__name__}: {e}"}), flush=True)
    return 1 if failed else 0

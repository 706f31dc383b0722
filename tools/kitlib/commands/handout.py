"""./kit handout DIR: a copy of the kit for students, without anything that computes the answers.

What goes out:
  - steps/: the shipped stubs, as git's HEAD has them (never an instructor's experiment in the working
    tree): a changed step file makes the command refuse, naming it; --committed ships HEAD's stubs
    anyway, --from-working-tree the working tree's files (with a warning; never a solution's line);
  - everything else the kit tracks, except what EXCLUDED lists: the solutions, the mutants and fixtures
    (answers with one slip), the property oracles and fuzz targets, the exact-root helper, the
    benchmark (./kit bench is the instructor's, issue 56), and the instructor's tools.
Nothing outside steps/ may compute what a step asks for: every code file that would ship is scanned for
step code (SCAN_PATTERNS below) and the command refuses when one matches.
"""

from __future__ import annotations

import io
import json
import re
import shutil
import tokenize
from dataclasses import dataclass
from pathlib import Path

from raykit import course as course_file
from raykit.kitfiles import git, is_clone, kit_files
from raykit.includes import code_only
from raykit.common import ROOT, KitError, load_steps, note, say, writable_parent
from raykit.status import FAILED, OK


# Paths (relative to the kit) that never go into a handout.
EXCLUDED = [
    "solutions", "tests/mutants", "tests/fixtures",        # answers, and answers with one slip
    "tests/properties", "tests/fuzz",                      # oracles and fuzz targets run on the solutions
    "tests/hidden",                                        # the hidden cases (graded against the solutions)
    "tests/support/reference_roots.hpp",                   # the exact roots: a handout has the data instead
    "bench",                                               # the benchmark: ./kit bench is the instructor's
    "tools/kitlib",                                        # the instructor's toolchain: grading, the platforms,
                                                           # the report, docs, slides, exact data, self-test
    "docs/lab/check",                                      # the lab's C++ check: a textbook root function
    "docs/trials",                                         # student trials: a trial student's solutions, slips
    # docs/lab/lab.js ships on purpose: the lab is for students. It is JavaScript, which no step can link
    # and the scan does not read, and every formula it evaluates is printed in lectures 01-03.
    "CONTRIBUTING.md",                                     # how to change the kit: solutions, mutants, data
    "docs/instructors.md", "docs/performance.md",          # the instructor's manual; the kit's own costs
    "tools/gradescope", "tools/portability",               # the autograder; the check in bare Debian roots
    "tests/kit", "pytest.ini",                             # the kit's self-test (pytest), which stays out
    ".ci", "build", ".git", "docs/instructor",            # the kit's own CI, build output, history
    ".github/workflows/student-loop.yml",                  # the instructor's CI on GitHub's runners (needs solutions/)
    ".github/workflows/ci.yml",                            # .ci/run on GitHub's runners (needs .ci/)
]

README_BLOCK = re.compile(r"<!-- instructor -->.*?<!-- /instructor -->\n?", re.S)
README_LINE = "<!-- instructor line -->"


def register(p) -> None:
    p.add_argument("dir", metavar="DIR", help="where to write the handout (must not exist, or be empty)")
    how = p.add_mutually_exclusive_group()
    how.add_argument("--committed", action="store_true",
                     help="ship the committed stubs even when steps/ has uncommitted changes (left as they are)")
    how.add_argument("--from-working-tree", action="store_true",
                     help="ship steps/ as it is in the working tree, not as committed (with a warning); "
                          "a file holding a line of a solution is still refused")


# --- the scan for step code ---------------------------------------------------------------------------
#
# Each pattern is looked for in a code file's text with its comments and string literals removed (the
# headers' documentation and the failure messages explain formulas in words, which is the lecture's
# job) and all white space removed (so `b * b - 4 * a * c` and `b*b-4*a*c` read the same). Markdown is
# not scanned: the lectures teach the formulas; what must not ship is code that computes them.

_ID = r"[A-Za-z_][\w.]*(?:\[\w+\])?"          # a name, a member or an element: b, ray.direction, o[axis]
_NUM_HALF = r"(?:0?\.5f?|\.5f?|0\.50*f?)"
_IN_PARENS = r"[^()]|\([^()]*\)"            # one character of a parenthesised expression, or a call in it
# A vector's dot product with itself, or one written out component by component (any two vectors), but
# not as the whole argument of a square root: sqrt(dot(v, v)) is a length, which any vector code takes.
_NOT_LENGTH = r"(?<!sqrt\()(?<!sqrt\(glm::)(?<!sqrt\(std::)"
_DOT = (rf"{_NOT_LENGTH}\bdot\((\w[\w.]*),\1\)|\blength2\(|"
        rf"{_NOT_LENGTH}\b(\w*)x\*(\w*)x\+\2y\*\3y\+\2z\*\3z\b|"
        rf"{_NOT_LENGTH}\b([\w.]+)\.x\*([\w.]+)\.x\+\4\.y\*\5\.y\+\4\.z\*\5\.z\b|"
        rf"{_NOT_LENGTH}\b(\w+)\[0\]\*(\w+)\[0\]\+\6\[1\]\*\7\[1\]\+\6\[2\]\*\7\[2\]")


@dataclass
class Pattern:
    name: str
    regex: re.Pattern
    example: str        # a line of step code it must catch (the self-test plants it)


SCAN_PATTERNS = [
    Pattern("discriminant b*b - 4*a*c",
            re.compile(rf"\b({_ID})\*\1-4(?:\.0*f?)?\*\(?{_ID}\*{_ID}"),
            "const float disc = b * b - 4.0f * a * c;"),
    Pattern("discriminant h*h - a*c",
            re.compile(rf"\b({_ID})\*\1-\(?{_ID}\*{_ID}\b"),
            "const float disc = h * h - a * c;"),
    Pattern("quadratic coefficient dot(x, x) near a square root",
            re.compile(rf"(?:{_DOT}).{{0,1500}}?\bsqrt\b|\bsqrt\b.{{0,1500}}?(?:{_DOT})", re.S),
            "const float a = glm::dot(d, d); const float s = std::sqrt(h * h - a * c);"),
    Pattern("roots (-b - sqrt(disc)) / (2a)",
            re.compile(r"\(-[\w.]+[-+](?:(?:std::)?sqrt\((?:[^()]|\([^()]*\))*\)|[\w.]+)\)/"),
            "const float t0 = (-b - std::sqrt(disc)) / (2.0f * a);"),
    Pattern("root pair q = -(b + sign(b) sqrt(...))",
            re.compile(rf"=-\(({_ID})\+(?:\w+::)?(?:sign|copysign)\w*\(|=-\(({_ID})\+\(\2[<>]=?0\.?0*f?\?|"
                       rf"\bcopysign\w*\((?:std::)?sqrt"),
            "const float q = -(b + std::copysign(std::sqrt(disc), b)) / 2.0f;"),
    Pattern("second root c / q",
            re.compile(r"\b\w+/q\b(?!\w)"),
            "const float t1 = c / q;"),
    Pattern("plane parameter (k - o[axis]) / d[axis]",
            re.compile(rf"\((?=(?:{_IN_PARENS})*?(?:offset|\w\[[\w.]+\]|component\())(?:{_IN_PARENS})*?-"
                       rf"(?:{_IN_PARENS})*?\)/|\(({_ID})-([\w.]+)\.([xyz])\)/([\w.]+)\.\3\b"),
            "const float t = (rect.offset - ray.origin[rect.axis]) / ray.direction[rect.axis];"),
    Pattern("camera basis cross(forward, up)",
            re.compile(r"\bcross\([\w.]*(?:forward|fwd|look|\bf)\w*,[\w.]*(?:up|\bu)\w*\)|"
                       r"\bcross\([\w.]*(?:up|\bu)\w*,[\w.]*(?:forward|fwd|look|\bf)\w*\)"),
            "const glm::vec3 right = glm::cross(camera.forward, camera.up);"),
    Pattern("pixel centre (i + 0.5f)",
            re.compile(rf"(?:\w|\))\+{_NUM_HALF}\)|\({_NUM_HALF}\+(?:\w|static_cast)"),
            "const float x = (static_cast<float>(i) + 0.5f) / static_cast<float>(camera.width);"),
]

# Kit code that looks like a step's but is not: the scan must let it through (the self-test checks).
NOT_STEP_CODE = [
    "const float length = std::sqrt(glm::dot(v, v));",
    "const glm::vec3 n = glm::normalize(point_at(ray, t) - sphere.center);",
    "const glm::vec3 side = glm::normalize(glm::cross(o, glm::vec3(0.1f, 0.2f, 1)));",
    "for (int i = 0; i < width; ++i) canvas.at(i, j) = color;",
    "const float film_height = 2.0f * std::tan(glm::radians(fov) / 2.0f);",
    "const float mid = (lo + hi) / 2.0f;",
]

CPP_SUFFIXES = {".cpp", ".hpp", ".h", ".cc", ".cxx", ".hh", ".inc", ".c", ".in"}


def strip_python(text: str) -> str:
    """Python text without comments and string literals (docstrings included)."""
    try:
        return " ".join(" " if tok.type in (tokenize.COMMENT, tokenize.STRING) else tok.string
                        for tok in tokenize.generate_tokens(io.StringIO(text).readline))
    except (tokenize.TokenError, IndentationError, SyntaxError):
        return re.sub(r"#.*", "", text)


def code_of(path: Path, text: str) -> str | None:
    """The code to scan in a file (no comments, strings or white space), or None when it is not code."""
    if path.suffix in CPP_SUFFIXES:
        code = code_only(text)
    elif path.suffix == ".py":
        code = strip_python(text)
    elif path.name == "CMakeLists.txt" or path.suffix == ".cmake":
        code = re.sub(r"#.*", "", text)
    else:
        return None
    return re.sub(r"\s+", "", code)


def scan_text(path: Path, text: str) -> list[str]:
    """The names of the step-code patterns found in one file."""
    code = code_of(path, text)
    return [] if code is None else [p.name for p in SCAN_PATTERNS if p.regex.search(code)]


def scan_tree(root: Path) -> dict[str, list[str]]:
    """{file relative to root: patterns found} for every code file under root outside steps/."""
    found = {}
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root)
        if not path.is_file() or rel.parts[0] == "steps" or "__pycache__" in rel.parts:
            continue
        hits = scan_text(path, path.read_text(errors="replace"))
        if hits:
            found[rel.as_posix()] = hits
    return found


# --- what goes out ------------------------------------------------------------------------------

def launch_json(text: str) -> str:
    """.vscode/launch.json with its list of steps written from tests/NN_topic/step.json."""
    options = json.dumps([s.number for s in load_steps()])
    return re.sub(r'("id": "step",[^\n]*"options": )\[[^\]]*\]', lambda m: m.group(1) + options, text)


def excluded(rel: Path) -> bool:
    s = rel.as_posix()
    return any(s == e or s.startswith(e + "/") for e in EXCLUDED) or "__pycache__" in rel.parts


def committed_steps() -> dict[str, bytes]:
    """{path under steps/: its bytes at HEAD}."""
    r = git("ls-tree", "-r", "-z", "--name-only", "HEAD", "--", "steps")
    if r.returncode != 0:
        raise KitError(f"git ls-tree failed: {r.stderr.decode().strip()}", FAILED)
    files = {}
    for name in (p for p in r.stdout.decode().split("\0") if p):
        blob = git("show", f"HEAD:{name}")
        if blob.returncode != 0:
            raise KitError(f"git show HEAD:{name} failed: {blob.stderr.decode().strip()}", FAILED)
        files[name] = blob.stdout
    return files


def changed_steps() -> list[str]:
    """Files under steps/ whose working-tree state differs from HEAD (changed, new or deleted)."""
    r = git("status", "--porcelain", "-z", "--untracked-files=all", "--", "steps")
    if r.returncode != 0:
        raise KitError(f"git status failed: {r.stderr.decode().strip()}", FAILED)
    entries = [e for e in r.stdout.decode().split("\0") if e]
    return sorted({e[3:] for e in entries if len(e) > 3 and e[3:].startswith("steps/")})


def answer_lines(step, stub_text: str) -> set[str]:
    """Lines of the reference solution that are not in the stub: what a handout must not contain."""
    stub = {line.strip() for line in stub_text.splitlines()}
    path = ROOT / "solutions" / step.folder
    solution = [line.strip() for f in step.files if (path / f).is_file()
                for line in (path / f).read_text().splitlines()]
    return {line for line in solution
            if len(line) > 24 and line not in stub and not line.startswith(("//", "#include"))}


def strip_instructor_parts(text: str) -> str:
    """README without the <!-- instructor --> ... <!-- /instructor --> blocks and the marked lines."""
    text = README_BLOCK.sub("", text)
    return "".join(line for line in text.splitlines(keepends=True) if README_LINE not in line)


def student_steps(from_working_tree: bool, committed: bool = False) -> dict[str, bytes]:
    """{path under steps/: bytes} to ship."""
    if from_working_tree:
        files = {p.relative_to(ROOT).as_posix(): p.read_bytes() for p in sorted((ROOT / "steps").rglob("*"))
                 if p.is_file() and "__pycache__" not in p.parts}
        if is_clone():
            changed = changed_steps()
            if changed:
                note("kit: warning: shipping steps/ from the working tree, which differs from the committed "
                     "stubs in: " + ", ".join(changed))
        else:
            note("kit: warning: shipping steps/ from the working tree (not a git clone: nothing to compare with)")
        return files
    if not is_clone():
        raise KitError("this copy of the kit is not a git clone, so the committed stubs cannot be told from "
                       "edits in steps/. Run it in a clone, or ship steps/ as it is with --from-working-tree")
    changed = changed_steps()
    if changed and not committed:
        raise KitError("steps/ differs from the committed stubs in: " + ", ".join(changed) +
                       "\n  A handout ships the committed stubs: put them back (git checkout -- steps; git clean "
                       "-n steps lists new files), or ship the committed stubs anyway with --committed, or these "
                       "files with --from-working-tree")
    if changed:
        note("kit: shipping the committed stubs; left as they are in steps/: " + ", ".join(changed))
    return committed_steps()


def check_no_answers(steps_files: dict[str, bytes]) -> None:
    """Refuses a steps/ that carries a line of a reference solution, or a step file that is no stub."""
    for step in load_steps():
        for f in step.files:
            rel = f"steps/{step.folder}/{f}"
            text = steps_files.get(rel, b"").decode(errors="replace")
            if rel in steps_files and "not_implemented_yet(" not in text:
                # Every stub leaves at least one function to write (CONTRIBUTING.md, "A step"); a file
                # without one was answered, whether committed that way or not.
                raise KitError(f"{rel} is no stub: it has no not_implemented_yet(...) left; a handout ships "
                               f"stubs only", FAILED)
            committed = git("show", f"HEAD:{rel}").stdout.decode(errors="replace") if is_clone() else ""
            leaked = sorted(line for line in answer_lines(step, committed or text) if line in text)
            if leaked:
                raise KitError(f"{rel} holds a line of the reference solution ({leaked[0]!r}); a handout ships "
                               f"stubs only", FAILED)


# A path in a lecture's code span: `solutions/02_general_sphere/general_sphere.cpp`,
# `RAYKIT_SHOW_ULPS=1 build/reference/test_step02 -ts=robust`.
_POINTER = re.compile(r"(?<![\w/.])((?:solutions|tests|tools|build|bench|include|docs|lectures|steps|cmake)/[\w./-]*)")
_SPAN = re.compile(r"`([^`\n]+)`")
INSTRUCTOR_ONLY = ", in the instructor's copy of the kit only"


def mark_missing_pointers(text: str, has) -> tuple[str, int]:
    """A lecture for the handout: each code span naming a file or folder the handout lacks (`has(rel)`
    is False; build/reference/ never exists in one) is followed by INSTRUCTOR_ONLY, so a student
    does not look for it. Returns (text, how many spans were marked)."""
    marked = 0

    def missing(path: str) -> bool:
        rel = path.rstrip("/.")
        return rel.startswith("build/reference") or (not rel.startswith("build/") and not has(rel))

    def one(m: re.Match) -> str:
        nonlocal marked
        after = m.string[m.end():m.end() + len(INSTRUCTOR_ONLY)]
        if after == INSTRUCTOR_ONLY or not any(missing(p) for p in _POINTER.findall(m.group(1))):
            return m.group(0)
        marked += 1
        return m.group(0) + INSTRUCTOR_ONLY
    # Not inside $...$ formulas: lines only, spans in them.
    out = "".join(_SPAN.sub(one, line) if "`" in line else line for line in text.splitlines(keepends=True))
    return out, marked


def run(args) -> int:
    if not (ROOT / "solutions").is_dir():
        raise KitError("this is a student handout (it has no solutions/): ./kit handout runs in the "
                       "instructor's copy of the kit")
    target = Path(args.dir).expanduser()
    if target.exists() and (not target.is_dir() or any(target.iterdir())):
        raise KitError(f"{args.dir}: exists and is not an empty folder; choose a new one")
    writable_parent(args.dir, target)
    inside = ROOT == target.resolve() or ROOT in target.resolve().parents
    if inside and (ROOT / "build") not in target.resolve().parents:
        raise KitError(f"{args.dir}: a handout cannot live inside the kit")
    steps_files = student_steps(args.from_working_tree, args.committed)
    check_no_answers(steps_files)

    staging = target.resolve().parent / f".{target.name}.partial"
    shutil.rmtree(staging, ignore_errors=True)
    try:
        count = 0
        for rel in kit_files():
            if excluded(rel) or rel.parts[0] == "steps" or not (ROOT / rel).is_file():
                continue
            dst = staging / rel
            dst.parent.mkdir(parents=True, exist_ok=True)
            if rel.as_posix() == "README.md":
                dst.write_text(strip_instructor_parts((ROOT / rel).read_text()))
                shutil.copymode(ROOT / rel, dst)
            elif rel.as_posix() == "course.json":    # with the hidden cases' count (raykit/course.py)
                dst.write_text(course_file.handout_text())
            elif rel.as_posix() == ".vscode/launch.json":    # its list of steps, from the steps
                dst.write_text(launch_json((ROOT / rel).read_text()))
            else:
                shutil.copy2(ROOT / rel, dst)
            count += 1
        # The lectures' pointers to files a handout lacks say where those files are.
        shipped = {r.as_posix() for r in kit_files() if not excluded(r)} | set(steps_files)
        folders = {"/".join(f.split("/")[:i]) for f in shipped for i in range(1, f.count("/") + 1)}
        for lecture in sorted((staging / "lectures").glob("*.md")):
            text, marked = mark_missing_pointers(lecture.read_text(), lambda rel: rel in shipped or rel in folders)
            if marked:
                lecture.write_text(text)
        for rel, data in steps_files.items():
            (staging / rel).parent.mkdir(parents=True, exist_ok=True)
            (staging / rel).write_bytes(data)
            count += 1
            if rel.endswith(".cpp"):
                # The shipped stub again, for ./kit reset (a handout has no git history).
                keep = staging / "tools" / "stubs" / Path(rel).relative_to("steps")
                keep.parent.mkdir(parents=True, exist_ok=True)
                keep.write_bytes(data)
        found = scan_tree(staging)
        if found:
            first = next(iter(found))
            raise KitError(f"{first} would ship step code ({', '.join(found[first])})" +
                           (f", and {len(found) - 1} more file(s)" if len(found) > 1 else "") +
                           ". Move it out of the handout (kitlib/commands/handout.py, EXCLUDED) or remove the code", FAILED)
        if target.exists():
            target.rmdir()
        staging.rename(target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    source = "the working tree (--from-working-tree)" if args.from_working_tree else "the committed stubs (HEAD)"
    say(f"wrote a student handout of {count} files to {target}")
    say(f"  steps/ from {source}")
    say("  left out: solutions, mutants, fixtures, property tests, fuzz targets, exact-root code, the benchmark")
    say(f"  students start with: cd {target} && ./kit check")
    return OK

"""Self-test: the kit where courses grade: GitHub Classroom, PrairieLearn, a machine without apt.

  - classroom: a handout with ./kit classroom's workflow, run as the runner would
    (tools/classroom/simulate.py: every `run:` step in the repository with only PATH and HOME, then the
    real autograding-grading-reporter from ../shared/third_party/, npm-installed into build/), for the
    stubs, one slip and the solutions: its "Points X/Y" and its console table's total equal the kit's own
    score; every `with:` key is among the action's action.yml inputs, and a wrong key is caught.
  - prairielearn: ./kit prairielearn's info.json files validate against PrairieLearn's real
    infoQuestion.json schema and its infoAssessment.json against infoAssessment.json (python3-jsonschema),
    the assessment holds a question per step worth the step's points and extra credit on course.json's
    scale (maxPoints their sum); each question's page is HTML with MathJax's delimiters and nothing a
    PrairieLearn student lacks (no Markdown fence or $, no ./kit, no lecture path, no lab, no link into
    the kit, every figure copied beside it), its editors name the step's files and its entry point the
    grader in serverFilesCourse; the image's Dockerfile installs packages.py's build and sandbox groups;
    tools/prairielearn/grade.py on a /grade-like folder
    writes results.json that passes tools/prairielearn/check_results.py (externalGraderCommon.ts's
    rules): the solutions score 1 on every step, the stubs 0, one slip in between with the picture of a
    failing case, a compile error 0 with its diagnostic; both checkers are shown to catch a wrong file.
  - noapt: without apt or dpkg, packages.ensure_packages looks in a Homebrew-like prefix: GLM and
    doctest found there (and the prefix passed to CMake in CMAKE_PREFIX_PATH), stb not needed by the
    check but named for ./kit render, doctest removed is named with `brew install doctest`. The full
    form (a Debian root without apt, clang and libc++) is by hand: tools/portability/reach noapt.
  - mac: a handout as a Mac student meets it, as far as Linux can play one: user nobody, clang and libc++
    only, no apt, sudo, gdb or g++ on the PATH, GLM, doctest and stb's headers in a Homebrew prefix in a
    home folder that a fake `brew --prefix` names: ./kit check 1 done (GLM and doctest from that prefix),
    ./kit render's picture matches (stb from that prefix), ./kit debug stops under lldb in the student's
    function. Needs clang, libc++ and lldb.
Needs ../shared/third_party/ (skipped without it: a user's clone has none), node and npm, and Debian's
python3-yaml (/usr/bin/python3). The full form, in a Debian 13 root as a user with sudo, is by hand:
tools/portability/reach (its docstring).
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

from .. import course as course_file
from ..common import BUILD, ROOT, load_steps
from .harness import Skipped, expect, kit, need_solutions

THIRD_PARTY = ROOT.parent / "shared" / "third_party"
WORK = BUILD / "reach"
SYSTEM_PYTHON = "/usr/bin/python3"      # Debian's, which sees python3-yaml and python3-jsonschema
SLIP = ("01_unit_sphere", "a_assumed_one")   # the one-slip repository: step 01 with this mutant


def need_third_party(*parts: str) -> Path:
    path = THIRD_PARTY.joinpath(*parts)
    if not path.exists():
        raise Skipped(f"needs {path} (the real clients' files; a user's clone has none)")
    return path


def need_system_python(*modules: str) -> None:
    probe = subprocess.run([SYSTEM_PYTHON, "-c", "import " + ", ".join(modules)], capture_output=True)
    if probe.returncode != 0:
        raise Skipped(f"needs {SYSTEM_PYTHON} with {', '.join(modules)} (Debian: "
                      + " ".join(f"python3-{m}" for m in modules) + ")")


def make_handout(target: Path) -> Path:
    shutil.rmtree(target, ignore_errors=True)
    r = kit("handout", str(target))
    expect(r.returncode == 0, f"./kit handout failed:\n{r.stdout[-500:]}{r.stderr[-1500:]}")
    return target


def fill(steps_dir: Path, form: str) -> None:
    """Puts the stubs back (they are the handout's), the solutions, or the solutions with one slip."""
    for step in load_steps():
        for f in step.files:
            src = ROOT / ("steps" if form == "stubs" else "solutions") / step.folder / f
            shutil.copyfile(src, steps_dir / step.folder / f)
    if form == "slip":
        folder, name = SLIP
        patch = ROOT / "tests" / "mutants" / folder / f"{name}.patch"
        r = subprocess.run(["patch", "-s", "-p3", "-d", str(steps_dir / folder), "-i", str(patch)],
                           capture_output=True, text=True)
        expect(r.returncode == 0, f"the mutant {folder}/{name} does not apply: {r.stdout}{r.stderr}")


def reporter() -> Path:
    src = need_third_party("github-classroom", "autograding-grading-reporter")
    if not shutil.which("node") or not shutil.which("npm"):
        raise Skipped("needs node and npm (Debian: nodejs npm) to run the real reporter")
    copy = WORK / "reporter"
    if not (copy / "node_modules" / "@actions" / "core").is_dir():
        shutil.rmtree(copy, ignore_errors=True)
        shutil.copytree(src, copy)
        r = subprocess.run(["npm", "install", "--omit=dev", "--no-audit", "--no-fund"], cwd=copy,
                           capture_output=True, text=True, timeout=300)
        if r.returncode != 0:
            raise Skipped(f"npm install of the reporter failed (no registry?): {r.stderr.strip()[-300:]}")
    return copy


def simulate(repo: Path, rep: Path) -> dict:
    r = subprocess.run([SYSTEM_PYTHON, str(ROOT / "tools/classroom/simulate.py"), str(repo), str(rep)],
                       capture_output=True, text=True, timeout=1200)
    expect(r.returncode == 0, f"simulate.py failed: {r.stderr[-1500:]}")
    return json.loads(r.stdout)


def selftest_classroom(ctx) -> str:
    need_solutions()
    need_system_python("yaml")
    rep = reporter()
    # A wrong `with:` key is caught (so the real check below can fail).
    bad = WORK / "bad-workflow"
    (bad / ".github/workflows").mkdir(parents=True, exist_ok=True)
    (bad / ".github/workflows/classroom.yml").write_text(
        "jobs:\n  j:\n    runs-on: ubuntu-latest\n    steps:\n"
        "    - uses: classroom-resources/autograding-grading-reporter@v1\n"
        "      with:\n        runners: a\n        max-score: 3\n")
    expect(any("max-score" in p for p in simulate(bad, rep)["problems"]),
           "a reporter step with an unknown with: key (max-score) was not caught")
    # Classroom's points are one a counted case: the kit's own score too where the course gives each
    # counted case one point (the default scale), the number of counted cases passed otherwise.
    course = course_file.load()
    one_point_a_case = all(p is None for p in course.points.values()) and all(
        course.weight(g) in (0, 1) for g in course.weights)
    repo = make_handout(WORK / "classroom-repo")
    r = kit("classroom", str(repo))
    expect(r.returncode == 0, f"./kit classroom failed: {r.stdout}{r.stderr}")
    seen = []
    for form in ("stubs", "slip", "complete"):
        fill(repo / "steps", form)
        got = simulate(repo, rep)
        expect(not got["problems"], f"{form}: " + "; ".join(got["problems"])[:2000])
        results = json.loads((repo / "build/classroom-results.json").read_text())
        kit_score = (results["score"], results["max_score"])      # counted cases passed, of all of them
        expect((got["points"], got["max"]) == kit_score,
               f"{form}: the reporter says {got['notice']!r}, the kit {kit_score[0]}/{kit_score[1]}")
        if one_point_a_case:    # then Points is the kit's score on its own scale too
            expect(kit_score == (results["kit_score"], results["kit_max_score"]),
                   f"{form}: {kit_score[0]}/{kit_score[1]} cases, but the kit's score is "
                   f"{results['kit_score']}/{results['kit_max_score']} where every counted case is worth a point")
        expect(got["table"] == [got["points"], got["max"]],
               f"{form}: the reporter's table totals {got['table']}, its notice {got['notice']!r}")
        seen.append(f"{form} {got['points']:g}/{got['max']:g}")
    scores = [float(s.split()[1].split("/")[0]) for s in seen]
    expect(scores[0] == 0 and 0 < scores[1] < scores[2] and scores[2] == float(seen[2].split("/")[1]),
           f"stubs, one slip, solutions should read 0, between, full: {', '.join(seen)}")
    return "the real reporter's Points equal the kit's score: " + ", ".join(seen)


PL_SCHEMA = ("prairielearn", "apps", "prairielearn", "src", "schemas", "schemas", "infoQuestion.json")
PL_ASSESSMENT_SCHEMA = PL_SCHEMA[:-1] + ("infoAssessment.json",)
# What a PrairieLearn student does not have, as a question page would point at it.
PL_ABSENT = {"a Markdown fence": r"```", "a Markdown formula": r"(?<!\\)\$", "./kit": r"\./kit\b",
             "a lecture's file": r"lectures/", "the lab": r"\blab\b", "a step's folder": r"steps/\d\d_",
             "raw HTML shown as text": r"&lt;a |&lt;/a&gt;", "a link into the kit": r'href="(?!https?://)'}


def question_problems(page: str, q: Path) -> list[str]:
    """What is wrong with a generated question.html for a PrairieLearn student (the contract's C++ aside)."""
    prose = re.sub(r'<pl-code language="cpp">.*?</pl-code>', "", page, flags=re.S)
    found = [f"{what}: {m.group(0)!r} in …{prose[max(m.start() - 60, 0):m.end() + 20]!r}"
             for what, rx in PL_ABSENT.items() for m in [re.search(rx, prose)] if m]
    for src in re.findall(r'src="\{\{options.client_files_question_url\}\}/([^"]+)"', page):
        if not (q / "clientFilesQuestion" / src).is_file():
            found.append(f"figure {src} not in clientFilesQuestion/")
    if re.search(r"\{\{(?!options\.client_files_question_url\}\})", page):
        found.append("a {{ PrairieLearn's Mustache would read")
    return found


def _checker():
    import importlib.util
    spec = importlib.util.spec_from_file_location("pl_check_results", ROOT / "tools/prairielearn/check_results.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def pl_grade(step, files: dict[str, str], name: str) -> dict:
    """Grades `files` as PrairieLearn's job would (GRADE/student/NAME), returns results.json, checked."""
    grade = WORK / "pl-jobs" / f"{name}-{step.number}"
    shutil.rmtree(grade, ignore_errors=True)
    (grade / "student").mkdir(parents=True)
    for f, text in files.items():
        (grade / "student" / f).write_text(text)
    r = subprocess.run([str(ROOT / "tools/prairielearn/grade.py"), step.number, str(grade)],
                       capture_output=True, text=True, timeout=900)
    expect(r.returncode == 0, f"{name} step {step.number}: grade.py exited {r.returncode}: {r.stderr[-1500:]}")
    raw = (grade / "results" / "results.json").read_bytes()
    problems = _checker().results_problems(raw)
    expect(not problems, f"{name} step {step.number}: results.json: {'; '.join(problems)[:1500]}")
    return json.loads(raw)


def selftest_prairielearn(ctx) -> str:
    need_solutions()
    schema = need_third_party(*PL_SCHEMA)
    need_system_python("jsonschema")
    out = WORK / "prairielearn"
    shutil.rmtree(out, ignore_errors=True)
    r = kit("prairielearn", str(out))
    expect(r.returncode != 0 and "--image" in r.stderr, f"./kit prairielearn without --image: {r.stdout}{r.stderr}")
    r = kit("prairielearn", str(out), "--image", "your-dockerhub-user/raykit-grader")
    expect(r.returncode != 0 and "--image" in r.stderr, f"./kit prairielearn took the placeholder image: {r.stdout}{r.stderr}")
    r = kit("prairielearn", str(out), "--image", "raykit-selftest/raykit-grader", "--instance", "Fall")
    expect(r.returncode == 0, f"./kit prairielearn failed: {r.stdout}{r.stderr}")
    summary = assessment_checks(ctx, out, need_third_party(*PL_ASSESSMENT_SCHEMA))
    infos = sorted(out.glob("questions/raykit/*/info.json"))
    expect(len(infos) == len(ctx.steps), f"{len(infos)} info.json files for {len(ctx.steps)} steps")
    bad_info = WORK / "bad-info.json"
    bad_info.write_text(json.dumps({**json.loads(infos[0].read_text()), "uuid": "raykit-01",
                                    "externalGradingOptions": {"image": "x", "timeout": "60"}}))
    v = subprocess.run([SYSTEM_PYTHON, str(ROOT / "tools/prairielearn/check_results.py"), "info", str(schema),
                        *map(str, infos), str(bad_info)], capture_output=True, text=True)
    found = json.loads(v.stdout or "{}")
    expect(len(found.get(str(bad_info), [])) >= 2, f"the schema check missed a bad uuid and timeout: {v.stdout}{v.stderr}")
    wrong = {f: p for f, p in found.items() if p and f != str(bad_info)}
    expect(not wrong, f"info.json against infoQuestion.json: {wrong}")
    for step in ctx.steps:
        q = out / "questions" / "raykit" / step.folder
        editors = re.findall(r'<pl-file-editor file-name="([^"]+)" source-file-name="([^"]+)"', (q / "question.html").read_text())
        expect(sorted(e[0] for e in editors) == sorted(step.files) and all((q / e[1]).is_file() for e in editors),
               f"step {step.number}: question.html's editors {editors}, the step's files {step.files}")
        entry = (q / "tests" / "grade.py").read_text()
        grader = re.search(r'"/grade/serverFilesCourse/(raykit/[^"]+)"', entry)
        expect(grader and (out / "serverFilesCourse" / grader.group(1)).is_file(),
               f"step {step.number}: tests/grade.py runs no grader of serverFilesCourse/: {entry}")
    expect((out / "serverFilesCourse/raykit/solutions").is_dir(), "serverFilesCourse/raykit/ has no solutions/ (no hidden cases)")
    # The results checker catches what PrairieLearn rejects.
    checker = _checker()
    for wrong_file in ('{"score": "1"}', '{"score": 1.5}', '{"score": 1, "tests": [{"name": "a", "points": 1}]}',
                       '{"score": 0, "images": ["http://x/a.png"]}', "{" + '"output": "' + "x" * 1_000_001 + '"}'):
        expect(checker.results_problems(wrong_file.encode()), f"check_results passed a bad file: {wrong_file[:80]}")
    read = lambda folder, step: {f: (ROOT / folder / step.folder / f).read_text() for f in step.files}
    scores = {}
    for step in ctx.steps:
        full = pl_grade(step, read("solutions", step), "solutions")
        expect(full["score"] == 1, f"step {step.number}: the solutions score {full['score']}: {full['message']}")
        stub = pl_grade(step, read("steps", step), "stubs")
        expect(stub["score"] == 0, f"step {step.number}: the stubs score {stub['score']}: {stub['message']}")
        scores[step.number] = (full["score"], stub["score"])
    first = ctx.steps[0]
    folder, name = SLIP
    slipped = WORK / "pl-slip"
    shutil.rmtree(slipped, ignore_errors=True)
    (slipped / folder).mkdir(parents=True)
    for f in first.files:
        shutil.copyfile(ROOT / "solutions" / folder / f, slipped / folder / f)
    fill_patch = subprocess.run(["patch", "-s", "-p3", "-d", str(slipped / folder), "-i",
                                 str(ROOT / "tests/mutants" / folder / f"{name}.patch")], capture_output=True, text=True)
    expect(fill_patch.returncode == 0, f"the mutant {name} does not apply: {fill_patch.stderr}")
    slip = pl_grade(first, {f: (slipped / folder / f).read_text() for f in first.files}, "slip")
    expect(0 < slip["score"] < 1, f"one slip scores {slip['score']}, not between 0 and 1")
    hidden = [t for t in slip["tests"] if "(hidden)" in t["name"]]
    leaked = [t["name"] for t in hidden if re.search(r"draw \d+ of \d+|expected|got ", t["message"]) or t["output"]]
    expect(hidden and not leaked, f"one slip: {len(hidden)} hidden tests; these show an input, an answer or "
           f"output on PrairieLearn, which never reveals them: {leaked[:3]}")
    expect(slip.get("images") and slip["images"][0]["url"].startswith("data:image/svg+xml;base64,"),
           "one slip: no picture of its first failing visible case")
    broken = {f: t.replace("return", "retrun", 1) for f, t in read("solutions", first).items()}
    nc = pl_grade(first, broken, "no-compile")
    expect(nc["score"] == 0 and nc.get("gradable", True) and "error" in nc["message"],
           f"a compile error: score {nc['score']}, message {nc['message']!r}")
    return (f"{len(infos)} info.json and the assessment valid ({summary}); solutions 1, stubs 0 on every step; one slip {slip['score']:.3f} "
            f"({len(slip['tests'])} tests, a picture); compile error 0: {nc['message'].splitlines()[-1][:60]}")


def assessment_checks(ctx, out: Path, schema: Path) -> str:
    """The assessment against PrairieLearn's schema and the course's scale; the pages; the image."""
    from fractions import Fraction
    from .. import course as course_file
    from ..commands.prairielearn import pl_number, step_points
    from ..packages import PACKAGES
    path = out / "courseInstances" / "Fall" / "assessments" / "raykit" / "infoAssessment.json"
    expect(path.is_file(), f"no assessment at {path.relative_to(out)}")
    bad = WORK / "bad-assessment.json"
    bad.write_text(json.dumps({**json.loads(path.read_text()), "type": "Quiz", "maxPoints": -1}))
    v = subprocess.run([SYSTEM_PYTHON, str(ROOT / "tools/prairielearn/check_results.py"), "info", str(schema),
                        str(path), str(bad)], capture_output=True, text=True)
    found = json.loads(v.stdout or "{}")
    expect(len(found.get(str(bad), [])) >= 2, f"the schema check missed a bad type and maxPoints: {v.stdout}{v.stderr}")
    expect(not found.get(str(path)), f"infoAssessment.json against PrairieLearn's schema: {found.get(str(path))}")
    data = json.loads(path.read_text())
    course = course_file.load()
    questions = {q["id"]: q for z in data["zones"] for q in z["questions"]}
    want = {s.number: step_points(s, course) for s in ctx.steps}
    total = sum((w[0] for w in want.values()), Fraction(0))
    bonus = sum((w[1] for w in want.values()), Fraction(0))
    for s in ctx.steps:
        q = questions.get(f"raykit/{s.folder}")
        worth = pl_number(want[s.number][0] + want[s.number][1])
        expect(q and q["autoPoints"] == worth and q.get("maxAutoPoints", worth) == worth,
               f"step {s.number}: the assessment gives {q}, the course {worth} points (with its extra credit)")
        expect((out / "questions" / "raykit" / s.folder / "info.json").is_file(), f"the assessment names "
               f"raykit/{s.folder}, which is no question")
        page = out / "questions" / "raykit" / s.folder / "question.html"
        problems = question_problems(page.read_text(), page.parent)
        expect(not problems, f"step {s.number}'s question.html: {'; '.join(problems)}")
        expect("\\(" in page.read_text() or "$" not in (ROOT / "steps" / s.folder / "README.md").read_text(),
               f"step {s.number}'s task has formulas and its page no MathJax \\( \\)")
    expect(data["maxPoints"] == pl_number(total) and data.get("maxBonusPoints", 0) == pl_number(bonus)
           and abs(sum(q["autoPoints"] for q in questions.values()) - float(total + bonus)) < 1e-4,
           f"maxPoints {data['maxPoints']}, maxBonusPoints {data.get('maxBonusPoints')}: the course's steps make "
           f"{course.shown(total)} and {course.shown(bonus)} of extra credit")
    caught = question_problems("<p>see `lectures/01-x.md` and run ./kit check 1, $t$ &lt;a href=</p>", out)
    expect(len(caught) >= 4, f"the page check missed a lecture path, ./kit, a $ or raw HTML: {caught}")
    docker = (out / "graders" / "raykit" / "Dockerfile").read_text()
    apt = re.search(r"apt-get install -y --no-install-recommends ([^\\\n]*)", docker)
    missing = [p for p in PACKAGES["build"] + PACKAGES["sandbox"] + ["python3", "passwd"]
               if not apt or p not in apt.group(1).split()]
    expect(not missing and re.search(r"^FROM debian:\d+$", docker, re.M),
           f"graders/raykit/Dockerfile: not FROM debian:N, or its apt line misses {missing}")
    from ..commands.prairielearn import MEASURED_SECONDS, TIMEOUT
    options = [json.loads(i.read_text())["externalGradingOptions"] for i in out.glob("questions/raykit/*/info.json")]
    expect(all(o["image"] == "raykit-selftest/raykit-grader" for o in options), "an info.json does not name --image")
    slowest = max(wall for _, wall in MEASURED_SECONDS.values())
    expect(all(o["timeout"] == TIMEOUT and int(o["environment"]["RAYKIT_BUDGET"]) < TIMEOUT for o in options)
           and 1.5 * slowest <= TIMEOUT <= 600,
           f"the job's timeout {TIMEOUT} s against the slowest cold job measured, {slowest} s (1.5 times it at "
           f"least, 600 at most), and the kit's budget below it: {options[0]}")
    return (f"{len(questions)} questions, {data['maxPoints']} points"
            + (f" + {data['maxBonusPoints']} extra credit" if bonus else "") + ", pages clean")


def selftest_noapt(ctx) -> str:
    import os
    from unittest import mock
    from .. import packages
    from ..common import KitError
    prefix = WORK / "homebrew"
    shutil.rmtree(prefix, ignore_errors=True)
    for name in ("glm", "doctest"):
        (prefix / "lib/cmake" / name).mkdir(parents=True)
        (prefix / "lib/cmake" / name / f"{name}Config.cmake").write_text("# a stand-in: only its place is probed\n")
    env = {"CMAKE_PREFIX_PATH": "", "PKG_CONFIG_LIBDIR": str(prefix / "none"), "PKG_CONFIG_PATH": ""}

    def attempt(*groups, kind="brew"):
        packages._brew_prefix.clear()
        with mock.patch.object(packages, "has_apt", lambda: False), mock.patch.object(packages, "family", lambda: kind), \
                mock.patch.object(packages, "PREFIXES", [str(prefix)]), mock.patch.dict(os.environ, env):
            try:
                packages.ensure_packages(*groups)
                return "", os.environ.get("CMAKE_PREFIX_PATH", "")
            except KitError as e:
                return str(e), ""
    error, path = attempt("build")
    expect(not error and path == str(prefix), f"GLM and doctest in {prefix}: {error or 'CMAKE_PREFIX_PATH=' + path}")
    error, _ = attempt("build", "render")
    expect("stb_image_write.h" in error and "vcpkg install stb" in error and "no Homebrew formula" in error,
           f"./kit render without stb: {error!r}")
    shutil.rmtree(prefix / "lib/cmake/doctest")
    error, _ = attempt("build")
    expect("brew install doctest" in error and "glm" not in error.split("\n")[1],
           f"doctest removed: the message should name brew install doctest only: {error!r}")
    # Each platform's own words only: no Debian name, no MSYS2 line beside Homebrew's, no Homebrew
    # beside MSYS2's, neither on a Linux without apt.
    words = {kind: attempt("build", "render", kind=kind)[0] for kind in ("brew", "msys2", "plain")}
    for kind, text in words.items():
        expect("-dev" not in text and "apt-get" not in text, f"{kind}: a Debian name in {text!r}")
        expect(("pacman" in text) == (kind == "msys2") and ("brew install" in text) == (kind == "brew"),
               f"{kind}: another platform's lines in {text!r}")
    for kind, want in (("brew", "brew install doxygen"), ("msys2", "pacman -S mingw-w64-ucrt-x86_64-doxygen"),
                       ("apt", "sudo apt-get install doxygen"), ("plain", "install doxygen with your system's")):
        with mock.patch.object(packages, "family", lambda: kind):
            line = packages.install_line("doxygen", "doxygen")
        expect(line.startswith(want), f"{kind}: one tool's install line is {line!r}, not {want!r}")
    return f"found in a Homebrew-like prefix; stb needed only by render; then: {error.splitlines()[1].strip()}"


MAC_CASE = "window: a root exactly at tmin counts"


def selftest_mac_like(ctx) -> str:
    """The Done-when of #36, as far as Linux can play a Mac: a handout checked, rendered and debugged
    by an unprivileged user (nobody, when the self-test runs as root) with clang and libc++ only
    (no g++ on the PATH), no apt, dpkg, sudo or gdb, and GLM, doctest and stb's two headers in a
    Homebrew-style prefix in a home folder that only a `brew --prefix` on the PATH names. Step 01
    (the reference, then a window slip) and the steps its pictures need are the student's."""
    import os
    import tempfile
    from .debug import path_without
    need_solutions()
    for tool in ("clang++", "lldb"):
        if shutil.which(tool) is None:
            raise Skipped(f"needs {tool} (.ci/run installs clang, libc++-dev and lldb)")
    sources = {"glm": Path("/usr/include/glm"), "glm-cmake": Path("/usr/share/cmake/glm"),
               "doctest": Path("/usr/include/doctest"), "doctest-cmake": Path("/usr/lib/cmake/doctest"),
               "stb": Path("/usr/include/stb")}
    absent = [str(p) for p in sources.values() if not p.is_dir()]
    if absent:
        raise Skipped(f"needs Debian's GLM, doctest and stb to copy into the fake Homebrew prefix: {absent}")
    tmp = Path(tempfile.mkdtemp(prefix="raykit-mac-"))
    try:
        tmp.chmod(0o755)
        home, kit_dir = tmp / "home", tmp / "kit"
        brew = home / "homebrew"
        (brew / "include").mkdir(parents=True)
        shutil.copytree(sources["glm"], brew / "include" / "glm")
        shutil.copytree(sources["doctest"], brew / "include" / "doctest")
        shutil.copytree(sources["glm-cmake"], brew / "share" / "cmake" / "glm")
        shutil.copytree(sources["doctest-cmake"], brew / "lib" / "cmake" / "doctest")
        for cfg in list((brew / "share" / "cmake").rglob("*.cmake")) + list((brew / "lib" / "cmake").rglob("*.cmake")):
            cfg.write_text(cfg.read_text().replace("/usr/include", str(brew / "include")))
        for header in ("stb_image.h", "stb_image_write.h"):     # a Homebrew tap's layout: include/
            shutil.copyfile(sources["stb"] / header, brew / "include" / header)
        make_handout(kit_dir)
        for folder in ("01_unit_sphere", "04_rectangles", "05_cornell_box"):
            for f in (ROOT / "solutions" / folder).glob("*.cpp"):
                shutil.copyfile(f, kit_dir / "steps" / folder / f.name)
        hidden = {"apt", "apt-get", "apt-cache", "dpkg", "dpkg-query", "sudo", "gdb", "g++", "gcc", "c++", "cc",
                  "bwrap"} | {n for d in os.environ.get("PATH", "").split(os.pathsep) if os.path.isdir(d)
                              for n in os.listdir(d) if re.match(r"(x86_64|aarch64)-linux-gnu-g(cc|\+\+)|g(cc|\+\+)-\d+$", n)}
        path = path_without(tmp / "bin", hidden | {"python3"},
                            {"brew": f"#!/bin/sh\n[ \"$1\" = --prefix ] && echo {brew}\n"})
        (tmp / "bin" / "python3").symlink_to(SYSTEM_PYTHON if Path(SYSTEM_PYTHON).exists() else shutil.which("python3"))
        root = os.geteuid() == 0
        if root:
            for dirpath, dirnames, filenames in os.walk(tmp):
                for name in dirnames + filenames:
                    os.lchown(os.path.join(dirpath, name), 65534, 65534)
            os.chown(home, 65534, 65534)
        env = {"HOME": str(home), "PATH": path, "LANG": "C.UTF-8", "NO_COLOR": "1", "CXX": "clang++",
               "CXXFLAGS": "-stdlib=libc++ -DRAYKIT_PLATFORM_POSIX", "LDFLAGS": "-stdlib=libc++", "TERM": "dumb"}
        user = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"] if root else []
        seen, times = [], []

        def student(*args: str, timeout: float = 1800) -> subprocess.CompletedProcess:
            import time
            start = time.monotonic()
            r = subprocess.run(user + ["env", "-i", *(f"{k}={v}" for k, v in env.items()), "./kit", *args],
                               cwd=kit_dir, capture_output=True, text=True, timeout=timeout)
            times.append(f"{args[0]} {time.monotonic() - start:.0f} s")
            seen.append(r.stdout + r.stderr)
            return r
        r = student("check", "1")
        expect(r.returncode == 0 and "done" in r.stdout, f"./kit check 1: {r.returncode}\n{seen[-1][-1500:]}")
        cache = (kit_dir / "build" / "student" / "CMakeCache.txt").read_text()
        for line in ("CMAKE_CXX_FLAGS:STRING=-stdlib=libc++", f"glm_DIR:PATH={brew}", f"doctest_DIR:PATH={brew}"):
            expect(line in cache, f"the student's build is not {line!r}")
        r = student("render", "unit_sphere", "--steps", "steps")
        expect(r.returncode == 0 and "matches the reference" in r.stdout, f"./kit render: {r.returncode}\n{seen[-1][-1500:]}")
        stb = [l for l in (kit_dir / "build").glob("*/CMakeCache.txt") if "RAYKIT_STB_INCLUDE_DIR" in l.read_text()]
        expect(stb and f"RAYKIT_STB_INCLUDE_DIR:PATH={brew}/include" in stb[0].read_text(),
               "./kit render did not take stb's headers from the Homebrew prefix")
        shutil.copyfile(ROOT / "tests" / "fixtures" / "wrong" / "01_unit_sphere" / "unit_sphere.cpp",
                        kit_dir / "steps" / "01_unit_sphere" / "unit_sphere.cpp")
        if root:
            os.lchown(kit_dir / "steps" / "01_unit_sphere" / "unit_sphere.cpp", 65534, 65534)
        r = student("debug", "1", MAC_CASE, "--batch")
        frame = re.search(r"frame #0: \S+ answers_step01`raykit::intersect_unit_sphere\(ray=\S+ tmin=2, tmax=10\) "
                          r"at unit_sphere\.cpp", seen[-1])
        expect(frame is not None, f"lldb did not stop in the student's intersect_unit_sphere:\n{seen[-1][-1500:]}")
        return (f"{'nobody' if root else 'this user'}, clang + libc++, no apt/gdb/g++, Homebrew prefix from brew --prefix: "
                f"check 1 done, render matches, lldb stops in intersect_unit_sphere ({', '.join(times)})")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def selftests():
    return [("classroom: the real reporter's Points X/Y is the kit's score", selftest_classroom),
            ("prairielearn: info.json valid, results.json as PrairieLearn reads it, scores 1, 0, between", selftest_prairielearn),
            ("noapt: packages found in a Homebrew-like prefix, the missing one named with brew", selftest_noapt),
            ("mac: a Mac-like student machine checks, renders and debugs (lldb) a step", selftest_mac_like)]

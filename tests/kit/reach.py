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
  - prairielearn, a complete course (#46 item 3; no build, about 8 s): with a due date added to the kit's
    course.json (and bad ones refused, ./kit course showing it), ./kit prairielearn's output with the
    defaults holds the instance --instance raykit names; its info.json, infoAssessment.json and
    infoCourseInstance.json validate against PrairieLearn's schemas; PrairieLearn's example course with
    an infoCourse.json of its own, the entries the command printed (also in OUT/README-raykit.md) and
    OUT copied in validates whole, every question's topic and tags declared, every assessment in an
    instance, every question id a question (and a tag dropped, an instance removed are caught); the
    assessment's allowAccess gives full credit up to course.json's due date and none after (a day late
    is caught), the instance its timezone; each page holds the definition of every kit type its
    contract names, at any depth (found here from include/raykit/, not from the command's list); step
    05's page holds cornell_box.inc's objects, colours and camera; without --docs-url the lecture's
    file is named and nothing links, with it each page links the lecture's page ./kit docs makes (and a
    built site here has). --course: an instance the course has (SectionA) is not written, declared
    entries not printed again, a missing instance written; --course at no course and a --docs-url
    without http(s) are refused.
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

import pytest

from raykit import course as course_file
from raykit.common import BUILD, ROOT, load_steps
from .support import Skipped, expect, kit, need_solutions
from .fixtures import fixture_dir

# ../shared/third_party/ beside the kit's clone, or beside the folder of worktrees it is one of.
THIRD_PARTY = next((p / "shared" / "third_party" for p in (ROOT.parent, ROOT.parent.parent)
                    if (p / "shared" / "third_party").is_dir()), ROOT.parent / "shared" / "third_party")
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
    r = kit("handout", str(target), "--committed")     # the committed stubs, whatever steps/ holds
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
    from raykit import course as course_file
    from kitlib.commands.prairielearn import pl_number, step_points
    from raykit.packages import PACKAGES
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
        worth = pl_number(want[s.number][0])
        expect(q and q["autoPoints"] == worth and q.get("maxAutoPoints", worth) == worth,
               f"step {s.number}: the assessment gives {q}, the course {worth} points")
        x = questions.get(f"raykit/{s.folder}_extra_credit")
        expect((x or {}).get("autoPoints", 0) == pl_number(want[s.number][1]),
               f"step {s.number}'s extra credit: the assessment gives {x}, the course {want[s.number][1]} points")
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
    from kitlib.commands.prairielearn import MEASURED_SECONDS, TIMEOUT
    options = [json.loads(i.read_text())["externalGradingOptions"] for i in out.glob("questions/raykit/*/info.json")]
    expect(all(o["image"] == "raykit-selftest/raykit-grader" for o in options), "an info.json does not name --image")
    slowest = max(wall for _, wall in MEASURED_SECONDS.values())
    expect(all(o["timeout"] == TIMEOUT and int(o["environment"]["RAYKIT_BUDGET"]) < TIMEOUT for o in options)
           and 1.5 * slowest <= TIMEOUT <= 600,
           f"the job's timeout {TIMEOUT} s against the slowest cold job measured, {slowest} s (1.5 times it at "
           f"least, 600 at most), and the kit's budget below it: {options[0]}")
    return (f"{len(questions)} questions, {data['maxPoints']} points"
            + (f" + {data['maxBonusPoints']} extra credit" if bonus else "") + ", pages clean")


# --- a complete PrairieLearn course (#46 item 3) ------------------------------------------------------

PL_SCHEMAS = PL_SCHEMA[:-1]
DOCS_URL = "https://raykit.example.edu/site/"
DUE = {"date": "2027-03-14T23:59", "timezone": "America/Chicago"}


def pl_make(out: Path, course, *options: str) -> str:
    """./kit prairielearn OUT in this process, with `course` as course.json; what it printed."""
    import argparse
    import contextlib
    import io
    from kitlib.commands import prairielearn as cmd
    shutil.rmtree(out, ignore_errors=True)
    parser = argparse.ArgumentParser()
    cmd.register(parser)
    args = parser.parse_args([str(out), "--image", "raykit-selftest/raykit-grader", *options])
    printed = io.StringIO()
    with course_file.using(course), contextlib.redirect_stdout(printed):
        cmd.run(args)
    return printed.getvalue()


def schema_problems(schemas: Path, files: dict[str, list[Path]]) -> list[str]:
    """PrairieLearn's schema named by each key (infoQuestion.json, ...) against its files."""
    found = []
    for schema, paths in files.items():
        if not paths:
            continue
        v = subprocess.run([SYSTEM_PYTHON, str(ROOT / "tools/prairielearn/check_results.py"), "info",
                            str(schemas / schema), *map(str, paths)], capture_output=True, text=True)
        if not v.stdout.strip():
            return [f"check_results.py info {schema}: {v.stderr[-500:]}"]
        found += [f"{Path(f).name} ({f}) against {schema}: {'; '.join(p)}" for f, p in json.loads(v.stdout).items() if p]
    return found


def pl_files(folder: Path) -> dict[str, list[Path]]:
    return {"infoQuestion.json": sorted(folder.glob("questions/**/info.json")),
            "infoAssessment.json": sorted(folder.glob("courseInstances/**/assessments/**/infoAssessment.json")),
            "infoCourseInstance.json": sorted(folder.glob("courseInstances/**/infoCourseInstance.json")),
            "infoCourse.json": [folder / "infoCourse.json"] if (folder / "infoCourse.json").is_file() else []}


def printed_declarations(printed: str) -> dict[str, list[dict]]:
    """The entries ./kit prairielearn printed to add to infoCourse.json, by list."""
    found: dict[str, list[dict]] = {}
    key = None
    for line in printed.splitlines():
        m = re.search(r"""infoCourse\.json's "(\w+)" list""", line)
        if m:
            key = m.group(1)
            found.setdefault(key, [])
        elif key and line.strip().startswith("{"):
            found[key].append(json.loads(line.strip().rstrip(",")))
        else:
            key = None
    return found


def example_course(example: Path, target: Path) -> Path:
    """PrairieLearn's example course with an infoCourse.json (its copy here has none) that declares
    what its own questions use, as a course repository would."""
    shutil.rmtree(target, ignore_errors=True)
    shutil.copytree(example, target)
    infos = [json.loads(p.read_text()) for p in target.glob("questions/**/info.json")]
    topics = sorted({i["topic"] for i in infos})
    tags = sorted({t for i in infos for t in i.get("tags", [])})
    (target / "infoCourse.json").write_text(json.dumps({
        "name": "EX 101", "title": "PrairieLearn's example course", "timezone": "America/Chicago",
        "topics": [{"name": t, "color": "gray1"} for t in topics],
        "tags": [{"name": t, "color": "gray2"} for t in tags]}, indent=2) + "\n")
    return target


def assemble(base: Path, out: Path, printed: str, target: Path) -> Path:
    """A course: `base`, the entries `printed` said to add to its infoCourse.json, OUT's questions and
    course instances copied in as the README says (the kit's copy in serverFilesCourse left out here)."""
    shutil.rmtree(target, ignore_errors=True)
    shutil.copytree(base, target)
    info = json.loads((target / "infoCourse.json").read_text())
    for key, entries in printed_declarations(printed).items():
        info.setdefault(key, []).extend(entries)
    (target / "infoCourse.json").write_text(json.dumps(info, indent=2) + "\n")
    for part in ("questions", "courseInstances"):
        if (out / part).is_dir():
            shutil.copytree(out / part, target / part, dirs_exist_ok=True)
    return target


def course_problems(schemas: Path, course: Path) -> list[str]:
    """What would keep PrairieLearn from syncing the raykit part of `course`: a file its schema
    refuses, an undeclared topic or tag, an assessment in a folder that is no course instance, a
    question id the assessment names that is no question."""
    found = schema_problems(schemas, pl_files(course))
    info = json.loads((course / "infoCourse.json").read_text())
    topics = {t["name"] for t in info.get("topics", [])}
    tags = {t["name"] for t in info.get("tags", [])}
    for q in sorted(course.glob("questions/**/info.json")):
        data = json.loads(q.read_text())
        if data.get("topic") not in topics:
            found.append(f"{q.relative_to(course)}: topic {data.get('topic')!r} is not declared in infoCourse.json")
        found += [f"{q.relative_to(course)}: tag {t!r} is not declared in infoCourse.json"
                  for t in data.get("tags", []) if t not in tags]
    for a in sorted(course.glob("courseInstances/*/assessments/**/infoAssessment.json")):
        instance = a.relative_to(course).parts[1]
        if not (course / "courseInstances" / instance / "infoCourseInstance.json").is_file():
            found.append(f"{a.relative_to(course)}: courseInstances/{instance}/ has no infoCourseInstance.json")
        if "raykit" in a.relative_to(course).parts:     # the kit's assessment, wherever the course lies
            ids = [q["id"] for z in json.loads(a.read_text())["zones"] for q in z["questions"]]
            found += [f"{a.relative_to(course)}: question {i} is not in questions/" for i in ids
                      if not (course / "questions" / i / "info.json").is_file()]
    return found


def access_problems(out: Path, instance: str, course) -> list[str]:
    """The assessment's access rules follow course.json's due date: full credit up to it and none after;
    the course instance written (if any) in its timezone."""
    path = out / "courseInstances" / instance / "assessments" / "raykit" / "infoAssessment.json"
    rules = json.loads(path.read_text()).get("allowAccess", [])
    if not rules:
        return [f"{path.relative_to(out)}: no allowAccess (students cannot open it; due date {course.due_date})"]
    found = []
    credited = [r for r in rules if r.get("credit", 0) > 0 and r.get("active", True)]
    if course.due_date:
        due = course.due_date
        if not any(r.get("credit") == 100 and r.get("endDate") == due and "startDate" not in r for r in credited):
            found.append(f"no rule of full credit up to the due date {due}: {rules}")
        late = [r for r in credited if r.get("endDate", "9999") > due]
        if late:
            found.append(f"credit after the due date {due}: {late}")
        if not any(r.get("startDate", "") > due and r.get("active") is False for r in rules):
            found.append(f"after the due date {due}, no rule that keeps the assessment readable and closed: {rules}")
    elif not any(r.get("credit") == 100 and not {"startDate", "endDate"} & set(r) for r in credited):
        found.append(f"no due date, yet no rule of full credit at any date: {rules}")
    made = out / "courseInstances" / instance / "infoCourseInstance.json"
    if made.is_file() and json.loads(made.read_text()).get("timezone") != course.timezone:
        found.append(f"{made.relative_to(out)}: timezone {json.loads(made.read_text()).get('timezone')!r}, "
                     f"course.json's {course.timezone!r}")
    return found


DEFINES = re.compile(r"^\s*(?:struct|class)\s+(\w+)\s*[:{].*$|^\s*using\s+(\w+)\s*=.*$", re.M)


def kit_definitions() -> dict[str, tuple[str, str]]:
    """Each type include/raykit/*.hpp defines: its header and the line that defines it."""
    found = {}
    for h in sorted((ROOT / "include" / "raykit").glob("*.hpp")):
        for m in DEFINES.finditer(h.read_text()):
            found[m.group(1) or m.group(2)] = (f"raykit/{h.name}", m.group(0).strip())
    return found


def definition_problems(out: Path, steps) -> list[str]:
    """Each page shows the definition of every kit type its contract's code names, and of every type
    those definitions' headers name in turn (Ray, Roots, Sphere, Rect, Camera, Canvas, Scene, ...)."""
    import html as html_module
    defs = kit_definitions()
    code = lambda header: re.sub(r"//.*", "", (ROOT / "include" / header).read_text())
    found = []
    for step in steps:
        headers = {h for f in step.files for h in re.findall(r'#include "(raykit/\w+\.hpp)"',
                                                             (ROOT / "steps" / step.folder / f).read_text())}
        headers.discard("raykit/not_implemented.hpp")
        names, todo = set(), list(headers)
        while todo:
            for name in re.findall(r"\b[A-Z]\w*\b", code(todo.pop())):
                if name in defs and name not in names:
                    names.add(name)
                    todo.append(defs[name][0])
        page = (out / "questions" / "raykit" / step.folder / "question.html").read_text()
        shown = "\n".join(re.findall(r'<pl-code language="cpp">(.*?)</pl-code>', page, re.S))
        missing = sorted(n for n in names if html_module.escape(defs[n][1], quote=False) not in shown)
        if missing:
            found.append(f"step {step.number}'s page lacks the definitions of {', '.join(missing)} "
                         f"({', '.join(sorted({defs[n][0] for n in missing}))})")
    return found


def scene_problems(out: Path, steps) -> list[str]:
    """A step whose contract has a scene file (include/raykit/scenes/NAME.inc) shows each object's name,
    rectangle and colour, the colours and the camera on its page, as the file holds them."""
    found = []
    for step in steps:
        page = (out / "questions" / "raykit" / step.folder / "question.html").read_text()
        for f in step.files:
            for h in re.findall(r'#include "raykit/(\w+)\.hpp"', (ROOT / "steps" / step.folder / f).read_text()):
                inc = ROOT / "include" / "raykit" / "scenes" / f"{h}.inc"
                if not inc.is_file():
                    continue
                text = inc.read_text()
                value = lambda s: float(s.strip().rstrip("fF"))
                rows = {re.sub(r"<[^>]+>", " ", r) for r in re.findall(r"<tr>(.*?)</tr>", page, re.S)}
                row_numbers = lambda key: [[float(x) for x in re.findall(r"-?\d+(?:\.\d+)?", r)] for r in rows if key in r]
                colors = {}
                for m in re.finditer(r"^RAYKIT_SCENE_COLOR\((\w+),([^)]*)\)", text, re.M):
                    colors[m.group(1)] = [value(v) for v in m.group(2).split(",")]
                    if not any(all(any(abs(x - v) < 1e-9 for x in r) for v in colors[m.group(1)]) for r in row_numbers(m.group(1))):
                        found.append(f"step {step.number}: the colour {m.group(1)} {colors[m.group(1)]} is not on its page")
                for m in re.finditer(r'^RAYKIT_SCENE_OBJECT\("([^"]+)",(.*),\s*(\w+)\)', text, re.M):
                    want = [value(v) for v in m.group(2).split(",") if v.strip()]
                    if not any(all(any(abs(x - v) < 1e-9 for x in r) for v in want) for r in row_numbers(f'"{m.group(1)}"')):
                        found.append(f"step {step.number}: the object {m.group(1)!r} ({want}) is not on its page")
                camera = re.search(r"^RAYKIT_SCENE_CAMERA\(([^)]*)\)", text, re.M)
                said = [p for p in re.findall(r"<p>(.*?)</p>", page, re.S) if "camera" in p.lower()]
                numbers = [float(x) for p in said for x in re.findall(r"-?\d+(?:\.\d+)?", p)]
                missing = [v for v in map(value, camera.group(1).split(",")) if not any(abs(x - v) < 1e-9 for x in numbers)]
                if missing:
                    found.append(f"step {step.number}: the camera's numbers {missing} are not on its page")
    return found


def docs_pages() -> dict[str, str]:
    """The lecture pages ./kit docs makes, by step: the names selftest/docs.py checks in a built site."""
    from kitlib.commands import docs as cmd_docs
    return {sp.step.number: cmd_docs.page_id(sp.lecture) + ".html" for sp in cmd_docs.gather(False).steps
            if sp.lecture}


def link_problems(out: Path, steps, docs_url: str | None) -> list[str]:
    """With --docs-url, each page links its lecture's page of the docs site (a page ./kit docs makes,
    and one a built site here has); without it, no link but the lecture's file named in plain text."""
    pages = docs_pages()
    built = BUILD / "docs" / "student" / "html"
    found = []
    for step in steps:
        page = (out / "questions" / "raykit" / step.folder / "question.html").read_text()
        hrefs = re.findall(r'<a [^>]*href="([^"]+)"', page)
        lecture = ROOT / step.lecture
        if docs_url:
            into = [h[len(docs_url):] for h in hrefs if h.startswith(docs_url)]
            if lecture.is_file() and pages.get(step.number) not in into:
                found.append(f"step {step.number}: no link to {docs_url}{pages.get(step.number)} (links: {hrefs})")
            found += [f"step {step.number}: {docs_url}{i} is no page of ./kit docs' site" for i in into
                      if i not in pages.values() or built.is_dir() and not (built / i).is_file()]
        else:
            found += [f"step {step.number}: a link to {h}, with no --docs-url" for h in hrefs
                      if any(p in h for p in pages.values()) or not re.match(r"https?://", h)]
            prose = re.sub(r"<a .*?</a>", "", page, flags=re.S)
            if lecture.is_file() and lecture.name not in prose:
                found.append(f"step {step.number}: its lecture's file {lecture.name} is not named in plain text")
    return found


@pytest.mark.quick
def selftest_prairielearn_complete(ctx) -> str:
    """#46 item 3: ./kit prairielearn makes, with the lines it prints, a course PrairieLearn takes whole."""
    from raykit.common import KitError
    need_solutions()
    schemas = need_third_party(*PL_SCHEMAS)
    example = need_third_party("prairielearn", "exampleCourse")
    need_system_python("jsonschema")
    numbers = [s.number for s in ctx.steps]
    kit_course = json.loads(course_file.COURSE_FILE.read_text()) if course_file.COURSE_FILE.is_file() else {}
    # course.json's due date: read and normalised, refused when it is not one, shown by ./kit course.
    try:
        dated = course_file.parse({**kit_course, "due": DUE}, numbers)
    except KitError as e:
        raise AssertionError(f"course.json with \"due\": {DUE}: refused: {e}")
    undated = course_file.parse({k: v for k, v in kit_course.items() if k != "due"}, numbers)
    expect((getattr(dated, "due_date", None), getattr(dated, "timezone", None)) == ("2027-03-14T23:59:00", DUE["timezone"]),
           f"course.json's due {DUE} read as {getattr(dated, 'due_date', None)}, {getattr(dated, 'timezone', None)}")
    bad = [{"date": "2027-02-30T23:59"}, {"date": "2027-03-14T23:59-05:00"}, {"timezone": "UTC"}, {"date": 20270314}]
    accepted = []
    for entry in bad:
        try:
            course_file.parse({**kit_course, "due": entry}, numbers)
            accepted.append(entry)
        except KitError:
            pass
    expect(not accepted, f"course.json's due: these are not due dates, and were taken: {accepted}")
    table = "\n".join(course_file.table(dated, []))
    expect("2027-03-14T23:59:00 (America/Chicago)" in table, "./kit course does not show the due date")

    base = example_course(example, WORK / "pl-example-course")
    # 1. The defaults (--instance raykit, no --course, no --docs-url), due date set: a course made of
    # the example course, OUT and the printed lines is whole by PrairieLearn's schemas.
    out = WORK / "pl-complete"
    printed = pl_make(out, dated)
    expect((out / "courseInstances" / "raykit" / "infoCourseInstance.json").is_file(),
           "the default --instance raykit names an instance the output does not provide")
    problems = (schema_problems(schemas, pl_files(out)) + access_problems(out, "raykit", dated)
                + definition_problems(out, ctx.steps) + scene_problems(out, ctx.steps) + link_problems(out, ctx.steps, None))
    expect(not problems, "; ".join(problems)[:3000])
    readme = (out / "README-raykit.md").read_text() if (out / "README-raykit.md").is_file() else ""
    declared = printed_declarations(printed)
    expect(declared and printed_declarations(readme) == declared, f"the lines for infoCourse.json: printed "
           f"{declared}, in README-raykit.md {printed_declarations(readme)}")
    course = assemble(base, out, printed, WORK / "pl-assembled")
    problems = course_problems(schemas, course)
    expect(not problems, "the example course + OUT + the printed lines: " + "; ".join(problems)[:3000])
    # The checks catch what they look for: a tag left undeclared, an instance missing, a rule late.
    info = json.loads((course / "infoCourse.json").read_text())
    info["tags"] = [t for t in info["tags"] if t["name"] != f"step{ctx.steps[-1].number}"]
    (course / "infoCourse.json").write_text(json.dumps(info))
    (course / "courseInstances" / "raykit" / "infoCourseInstance.json").unlink(missing_ok=True)
    caught = course_problems(schemas, course)
    expect(len(caught) == 2, f"an undeclared tag and a missing instance: {caught}")
    late = out / "courseInstances" / "raykit" / "assessments" / "raykit" / "infoAssessment.json"
    data = json.loads(late.read_text())
    data["allowAccess"] = [{"credit": 100, "endDate": "2027-03-15T23:59:00"}]
    late.write_text(json.dumps(data))
    expect(len(access_problems(out, "raykit", dated)) >= 2, "full credit a day after the due date was not caught")
    # 2. --course: an instance the course has is not written again, the topic and tags it declares are
    # not printed again; --docs-url links every lecture; no due date: full credit, no dates.
    instructors = assemble(base, out, printed, WORK / "pl-instructors-course")
    again = pl_make(WORK / "pl-in-course", undated, "--instance", "SectionA", "--course", str(instructors),
                    "--docs-url", DOCS_URL)
    out = WORK / "pl-in-course"
    expect(not (out / "courseInstances" / "SectionA" / "infoCourseInstance.json").exists()
           and "SectionA" in again and not printed_declarations(again),
           f"--course with SectionA (which it has) and the tags declared: {again[-800:]}")
    problems = (schema_problems(schemas, pl_files(out)) + access_problems(out, "SectionA", undated)
                + link_problems(out, ctx.steps, DOCS_URL)
                + course_problems(schemas, assemble(instructors, out, again, WORK / "pl-assembled-2")))
    expect(not problems, "; ".join(problems)[:3000])
    fresh = pl_make(WORK / "pl-new-instance", dated, "--instance", "Spring", "--course", str(base))
    paris = course_file.parse({**kit_course, "due": {**DUE, "timezone": "Europe/Paris"}}, numbers)
    moved = pl_make(WORK / "pl-in-course", paris, "--instance", "SectionA", "--course", str(instructors))
    expect("in America/Chicago" in moved and "America/Chicago" not in again,
           f"course.json's Europe/Paris against SectionA's America/Chicago: no note: {moved[-600:]}")
    has = json.loads((base / "infoCourse.json").read_text())
    lacks = {k: [e for e in v if e["name"] not in {d["name"] for d in has.get(k, [])}] for k, v in declared.items()}
    expect((WORK / "pl-new-instance" / "courseInstances" / "Spring" / "infoCourseInstance.json").is_file()
           and printed_declarations(fresh) == {k: v for k, v in lacks.items() if v},
           f"--course without the instance Spring: no infoCourseInstance.json written, or other lines than the "
           f"{sum(map(len, lacks.values()))} entries it lacks: {fresh[-1200:]}")
    for options, what in (((("--course", str(WORK)), "--course at a folder with no infoCourse.json")),
                          (("--docs-url", "raykit.example.edu"), "--docs-url without http(s)://")):
        try:
            pl_make(WORK / "pl-refused", undated, *options)
            raise AssertionError(f"{what}: taken")
        except KitError:
            pass
    return (f"{len(ctx.steps)} questions, the instance, the assessment and infoCourse.json + {sum(map(len, declared.values()))} "
            f"printed entries valid by PrairieLearn's schemas, every topic and tag declared; access until "
            f"{dated.due_date}; each page's definitions, step 05's scene; lectures linked with --docs-url, "
            "named without; --course keeps SectionA and prints nothing declared")


def selftest_noapt(ctx) -> str:
    import os
    from unittest import mock
    from raykit import packages
    from raykit.common import KitError
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
        # The check's compiles and links are the bundle's (tools/raykit/bundle.py), built in the
        # student's own cache folder.
        caches = list((home / ".cache" / "raykit" / "bundles").glob("*/CMakeCache.txt"))
        expect(len(caches) == 1, f"the student's check built {len(caches)} bundles, not one")
        cache = caches[0].read_text()
        for line in ("CMAKE_CXX_FLAGS:STRING=-stdlib=libc++", f"glm_DIR:PATH={brew}", f"doctest_DIR:PATH={brew}"):
            expect(line in cache, f"the student's bundle is not {line!r}")
        r = student("render", "unit_sphere", "--steps", "steps")
        expect(r.returncode == 0 and "matches the reference" in r.stdout, f"./kit render: {r.returncode}\n{seen[-1][-1500:]}")
        stb = [l for l in (kit_dir / "build").glob("*/CMakeCache.txt") if "RAYKIT_STB_INCLUDE_DIR" in l.read_text()]
        expect(stb and f"RAYKIT_STB_INCLUDE_DIR:PATH={brew}/include" in stb[0].read_text(),
               "./kit render did not take stb's headers from the Homebrew prefix")
        shutil.copyfile(fixture_dir("wrong") / "01_unit_sphere" / "unit_sphere.cpp",
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


@pytest.mark.quick
def selftest_prairielearn_extra_credit(ctx) -> str:
    """#46 item 2 on PrairieLearn (no build, a few seconds): on the kit's course.json with ★ made extra
    credit, a step's question is worth the step's points alone, so a complete step scores 1 (it read
    0.9748), and the ★ points are PrairieLearn's bonus points: a question of their own per step with ★
    cases, its points the assessment's maxBonusPoints above maxPoints (PrairieLearn's documented way: a
    submission scores 0 to 1 of its question). The files validate against PrairieLearn's schemas and the
    results against externalGraderCommon.ts's rules (check_results.py); expectations from the course's
    rules on each step's recorded cases."""
    from fractions import Fraction
    from kitlib.commands.prairielearn import pl_number
    from raykit.plresults import prairielearn
    from .course import extra_credit_course, kit_results
    need_solutions()
    schemas = need_third_party(*PL_SCHEMAS)
    need_system_python("jsonschema")
    course = extra_credit_course([s.number for s in ctx.steps])
    out = WORK / "pl-extra-credit"
    printed = pl_make(out, course)
    problems = schema_problems(schemas, pl_files(out))
    expect(not problems, "; ".join(problems)[:2000])
    # Whole in PrairieLearn's example course with the printed lines: every question id a question.
    example = need_third_party("prairielearn", "exampleCourse")
    whole = assemble(example_course(example, WORK / "pl-extra-example"), out, printed, WORK / "pl-extra-assembled")
    problems = course_problems(schemas, whole)
    expect(not problems, "the example course + OUT (extra-credit questions) + the printed lines: "
           + "; ".join(problems)[:2000])
    data = json.loads((out / "courseInstances/raykit/assessments/raykit/infoAssessment.json").read_text())
    questions = {q["id"]: q for z in data["zones"] for q in z["questions"]}
    checker = _checker()
    total, bonus, told = Fraction(0), Fraction(0), []
    with course_file.using(course):
        for s in ctx.steps:
            from raykit.checking import recorded_cases
            cases = recorded_cases(s)
            expect(cases is not None, f"step {s.number} has no recorded cases")
            kept = [(c.tier, c.name, c.lecture) for c in cases if c.tier != "hidden" or course.hidden_enabled]
            groups = [course.group(t, n) for t, n, _ in kept]
            # course.py's rule: a step's points shared by weight among its counted cases, an extra-credit
            # case worth its weight's share on top (each case's weight: its own, else its group's).
            weights = course.weights_of(s.number, kept)
            counted = sum((w for w, g in zip(weights, groups) if not course.extra_credit(g)), Fraction(0))
            extra = sum((w for w, g in zip(weights, groups) if course.extra_credit(g)), Fraction(0))
            given = course.points.get(s.number)
            points, extra = ((counted, extra) if given is None else (given, given * extra / counted) if counted
                             else (Fraction(0), Fraction(0)))
            total, bonus = total + points, bonus + extra
            q, x = questions.get(f"raykit/{s.folder}"), questions.get(f"raykit/{s.folder}_extra_credit")
            expect(q and q["autoPoints"] == q.get("maxAutoPoints") == pl_number(points),
                   f"step {s.number}'s question: {q}; the course gives the step {points} points, its extra credit apart")
            if not extra:
                expect(x is None, f"step {s.number} has no extra-credit case and an extra-credit question {x}")
                continue
            info = out / "questions" / "raykit" / f"{s.folder}_extra_credit"
            expect(x and x["autoPoints"] == x.get("maxAutoPoints") == pl_number(extra) and (info / "info.json").is_file()
                   and "--extra-credit" in (info / "tests" / "grade.py").read_text(),
                   f"step {s.number}'s extra credit ({extra} points): the assessment gives {x}; its question "
                   f"{'is' if (info / 'info.json').is_file() else 'is not'} written")
            problems = question_problems((info / "question.html").read_text(), info)
            expect(not problems, f"step {s.number}'s extra-credit question.html: {'; '.join(problems)}")
            # The results: a complete step without ★ (a textbook solution), with ★, a core slip with ★.
            core = next(c.name for c in cases if course.group(c.tier, c.name) == "core")
            for fail, step_score, extra_score in (({"robust"}, 1, 0), (set(), 1, 1), ({core}, None, 1)):
                [r] = kit_results(course, [s], {s.number: fail})
                mine, theirs = prairielearn([r]), prairielearn([r], part="extra")
                for part, got in (("step", mine), ("extra", theirs)):
                    bad = checker.results_problems(json.dumps(got).encode())
                    expect(not bad, f"step {s.number}, {part} part: PrairieLearn would not read it: {bad}")
                expect((mine["score"] == step_score if step_score is not None else 0 < mine["score"] < 1)
                       and theirs["score"] == extra_score,
                       f"step {s.number}, failing {sorted(fail) or 'nothing'}: the step's question scores "
                       f"{mine['score']} (expected {step_score if step_score is not None else 'between 0 and 1'}), "
                       f"its extra credit {theirs['score']} (expected {extra_score})")
            told.append(f"{s.number}: {course.shown(points)} + {course.shown(extra)}")
    expect(data["maxPoints"] == pl_number(total) and data.get("maxBonusPoints", 0) == pl_number(bonus),
           f"maxPoints {data['maxPoints']}, maxBonusPoints {data.get('maxBonusPoints')}: the course makes {total} "
           f"and {bonus} of extra credit")
    expect(bonus > 0, f"{course.source}: no step has a ★ case worth anything, nothing was tested")
    return (f"{course.source}: maxPoints {data['maxPoints']}, maxBonusPoints {data['maxBonusPoints']}; steps "
            f"{', '.join(told)}; a complete step 1 without ★ and with, its extra credit 0 and 1")


def selftest_prairielearn_from_empty(ctx) -> str:
    """Issue 55 item 5: ./kit prairielearn --new-course NAME writes a whole course (infoCourse.json with the
    questions' topic and tags declared, the instance, the assessment, the questions) whose every file
    PrairieLearn's schemas take and that declares all it uses; --course DIR writes DIR's infoCourse.json
    with what it lacks added, DIR's own entries kept; the two together are refused."""
    from raykit.common import KitError
    need_solutions()
    schemas = need_third_party(*PL_SCHEMAS)
    example = need_third_party("prairielearn", "exampleCourse")
    need_system_python("jsonschema")
    course = course_file.load()
    out = WORK / "pl-from-empty"
    printed = pl_make(out, course, "--new-course", "CS 419")
    files = pl_files(out)
    expect(all(files.values()), f"--new-course: a course without some of its files: "
                                f"{ {k: len(v) for k, v in files.items()} }")
    problems = course_problems(schemas, out)
    expect(not problems, "--new-course: " + "; ".join(problems)[:3000])
    expect(not printed_declarations(printed), f"--new-course still prints entries to add by hand:\n{printed}")
    info = json.loads((out / "infoCourse.json").read_text())
    expect(info.get("name") == "CS 419" and info.get("timezone") == course.timezone,
           f"--new-course's infoCourse.json: name {info.get('name')!r}, timezone {info.get('timezone')!r} "
           f"(course.json's {course.timezone!r})")
    # The check catches a tag left undeclared (so its pass above means something).
    info["tags"] = info["tags"][:-1]
    (out / "infoCourse.json").write_text(json.dumps(info))
    expect(course_problems(schemas, out), "a course with a tag left undeclared passed the check")
    # Added to a course one has: PrairieLearn's example course, which declares none of the kit's tags.
    base = example_course(example, WORK / "pl-example-course")
    theirs = json.loads((base / "infoCourse.json").read_text())
    added_out = WORK / "pl-added"
    pl_make(added_out, course, "--course", str(base), "--instance", "Spring")
    merged = json.loads((added_out / "infoCourse.json").read_text())
    expect(all(merged[k][:len(theirs[k])] == theirs[k] for k in ("topics", "tags"))
           and {k: v for k, v in merged.items() if k not in ("topics", "tags")}
           == {k: v for k, v in theirs.items() if k not in ("topics", "tags")},
           "--course: OUT/infoCourse.json does not keep the course's own entries as they were")
    target = WORK / "pl-added-course"
    shutil.rmtree(target, ignore_errors=True)
    shutil.copytree(base, target)
    for part in ("questions", "courseInstances"):
        shutil.copytree(added_out / part, target / part, dirs_exist_ok=True)
    shutil.copyfile(added_out / "infoCourse.json", target / "infoCourse.json")
    problems = course_problems(schemas, target)
    expect(not problems, "--course, its infoCourse.json copied over: " + "; ".join(problems)[:3000])
    try:
        pl_make(WORK / "pl-both", course, "--new-course", "CS 419", "--course", str(base))
        raise AssertionError("--new-course with --course was taken")
    except KitError as e:
        expect("--new-course" in str(e), f"--new-course with --course: {e}")
    # The extra-credit twin of each step shows the same definitions (struct Ray and the rest) as the step's page.
    from .course import extra_credit_course
    bonus = extra_credit_course([s.number for s in ctx.steps])
    twins = WORK / "pl-twins"
    pl_make(twins, bonus, "--new-course", "CS 419")
    blocks = lambda page: re.findall(r"<summary>((?:The contract|Shared definitions).*?)</summary>", page)
    pairs = [(q, q.parent / q.name.removesuffix("_extra_credit")) for q in sorted((twins / "questions" / "raykit").glob("*_extra_credit"))]
    differ = [q.name for q, own in pairs if blocks((q / "question.html").read_text()) != blocks((own / "question.html").read_text())]
    expect(pairs and not differ, f"extra-credit questions whose definitions differ from their step's page: {differ} "
                                 f"(of {len(pairs)})")
    problems = course_problems(schemas, twins)
    expect(not problems, "--new-course with extra credit: " + "; ".join(problems)[:3000])
    added = len(merged["tags"]) - len(theirs["tags"])
    return (f"--new-course: {sum(len(v) for v in files.values())} files, each valid, every topic and tag declared; "
            f"--course: the example course's infoCourse.json with 1 topic and {added} tags added, valid; {len(pairs)} "
            "extra-credit questions show their step's definitions; both: refused")

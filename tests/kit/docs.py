"""./kit test checks for the documentation (./kit docs).

- the math filter translates GitHub math as Doxygen needs it;
- the site builds without one Doxygen warning (an undocumented declaration, a
  parameter without words, a broken reference), has a page for every lecture
  and task that exists, and loads nothing from the network;
- no line of a reference solution reaches the student site (and the check can
  see one: the instructor site has them);
- in a real browser (headless Chromium, offline), the formulas are typeset, no
  raw TeX is left in the text, and every image loads. Skipped with a message
  when Chromium cannot be installed.
"""

from __future__ import annotations

import html
import importlib.util
import re
from pathlib import Path

import pytest

from kitlib.commands import docs as cmd_docs
from raykit.common import BUILD, ROOT, KitError
from .support import Failed, Skipped, chromium_or_skip, expect, need_solutions

SCREENSHOTS = BUILD / "docs" / "screenshots"


def _math_filter():
    spec = importlib.util.spec_from_file_location("math_filter", ROOT / "docs" / "math_filter.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.quick
def selftest_math_filter(ctx) -> str:
    mf = _math_filter()
    bad = mf.selftest()
    expect(not bad, "docs/math_filter.py:\n  " + "\n  ".join(bad))
    lectures = sorted((ROOT / "lectures").glob("*.md"))
    for p in lectures:
        text = p.read_text(encoding="utf-8")
        out = mf.translate(text)
        expect(out.count("\n") == text.count("\n"), f"{p.name}: the filter changed the number of lines")
        expect(out.count("\\f[") == out.count("\\f]"), f"{p.name}: a $$ display formula is not closed")
    return f"{len(mf.EXAMPLES)} examples, {len(lectures)} lectures keep their lines and close their formulas"


# --- the site, as files -------------------------------------------------------------

def _site(ctx, instructor: bool = False) -> "cmd_docs.Site":
    key = "docs_instructor" if instructor else "docs_student"
    if getattr(ctx, key, None) is None:
        setattr(ctx, key, cmd_docs.build_site(instructor=instructor))
    return getattr(ctx, key)


REMOTE = re.compile(r'<(?:script|link|img|iframe|object)\b[^>]*\b(?:src|href|data)="(?:https?:)?//[^"]*"', re.I)
LOCAL_REF = re.compile(r'<(?:img|script)\b[^>]*\bsrc="([^"#?:]+)"', re.I)


def selftest_site_builds(ctx) -> str:
    site = _site(ctx)
    expect(not site.warnings, f"Doxygen warned {len(site.warnings)} time(s) (document the declaration, "
           "its parameters and its return value in the header):\n  " + "\n  ".join(site.warnings[:15]))
    c = site.content
    wanted = {"index.html": "the front page", "namespaceraykit.html": "the API's namespace page"}
    for sp in c.steps:
        for path, what in ((sp.lecture, "lecture"), (sp.task, "task")):
            if path:
                wanted[cmd_docs.page_id(path) + ".html"] = f"the {what} of step {sp.step.number}"
    for p in c.other_lectures + c.bench_readings:
        wanted[cmd_docs.page_id(p) + ".html"] = p.relative_to(ROOT).as_posix()
    for h in c.headers:
        wanted[h.name.replace("_", "__").replace(".", "_8") + ".html"] = f"the API of {h.name}"
    missing = [f"{what} ({name})" for name, what in wanted.items() if not (site.html / name).is_file()]
    expect(not missing, "pages missing from the site: " + ", ".join(missing))
    expect((site.html / "mathjax" / "es5" / "tex-svg.js").is_file(), "MathJax was not copied into the site")
    problems = []
    pages = sorted(site.html.glob("*.html"))
    for page in pages:
        text = page.read_text(encoding="utf-8", errors="replace")
        problems += [f"{page.name} loads {m.group(0)[:120]}" for m in REMOTE.finditer(text)]
        problems += [f"{page.name}: {m.group(1)} is not in the site" for m in LOCAL_REF.finditer(text)
                     if not (site.html / html.unescape(m.group(1))).is_file()]
    expect(not problems, "the site is not whole offline:\n  " + "\n  ".join(problems[:10]))
    return f"{len(pages)} pages, no warning; {c.summary()}; nothing loaded from the network"


# --- solutions stay out of the student site --------------------------------------------

def _text_of(site_html: Path) -> str:
    parts = []
    for page in site_html.glob("*.html"):
        t = re.sub(r"<[^>]+>", "", page.read_text(encoding="utf-8", errors="replace"))
        parts.append(html.unescape(t))
    return re.sub(r"\s+", " ", "\n".join(parts))


def solution_fingerprints(stubs: Path) -> list[str]:
    """Lines of the solutions that appear nowhere in the stubs (`stubs`: the committed ones) or headers: code
    only a solution has."""
    shared = ""
    for folder in (stubs, ROOT / "include"):
        shared += "\n".join(p.read_text(errors="replace") for p in folder.rglob("*.[ch]pp"))
    shared = re.sub(r"\s+", " ", shared)
    prints = []
    for p in sorted((ROOT / "solutions").rglob("*.cpp")):
        for line in p.read_text(errors="replace").splitlines():
            line = re.sub(r"\s+", " ", line.strip())
            if len(line) >= 24 and line not in shared and not line.startswith("#include"):
                prints.append(line)
    return prints


def selftest_no_solutions(ctx, committed_steps) -> str:
    need_solutions()
    prints = solution_fingerprints(committed_steps)
    expect(prints, "found no line that only the solutions have: the check would prove nothing")
    student = _text_of(_site(ctx).html)
    leaked = [p for p in prints if p in student]
    if leaked:
        raise Failed(f"{len(leaked)} line(s) of solutions/ are in the student site, e.g. {leaked[0]!r}")
    expect(not (_site(ctx).html / "solutions.html").exists(), "the student site has the solutions page")
    instructor = _site(ctx, instructor=True)
    lacking = [p for p in prints if p not in _text_of(instructor.html)]
    if lacking:
        raise Failed(f"the instructor site lacks {len(lacking)} solution line(s), e.g. {lacking[0]!r}")
    return (f"none of {len(prints)} solution-only lines in the student site; all of them in "
            f"{cmd_docs.rel(instructor.index)}")


# --- a real browser ---------------------------------------------------------------

# Runs in the page: what a reader sees. Text inside code and inside typeset
# formulas is not prose; anything TeX-like left elsewhere was not typeset.
INSPECT = r"""
(async () => {
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) await MathJax.startup.promise;
  await Promise.all(Array.from(document.images, i => i.complete ? null :
      new Promise(r => { i.onload = i.onerror = r; })));
  await new Promise(r => setTimeout(r, 300));   // the side bar fills itself in after load
  const skip = 'script, style, pre, code, .fragment, mjx-container, #nav-tree, #MSearchBox, #MSearchResultsWindow';
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  let text = '';
  for (let n = walker.nextNode(); n; n = walker.nextNode())
    if (!n.parentElement.closest(skip)) text += n.nodeValue + ' ';
  const tex = /\\f[$\[\]]|\\[()\[\]]|\$\$|\\(?:frac|mathbf|sqrt|cdot|le|ge|pm|times|min|max|begin|quad|Delta)\b|\$(?=[^\s$])[^$\n]*[^\s$\\]\$(?!\d)/g;
  return {
    math: document.querySelectorAll('mjx-container').length,
    errors: Array.from(document.querySelectorAll('mjx-merror, [data-mjx-error]'),
                       e => e.getAttribute('data-mjx-error') || e.textContent).slice(0, 5),
    raw: (text.match(tex) || []).slice(0, 5),
    images: document.images.length,
    broken: Array.from(document.images).filter(i => !(i.complete && i.naturalWidth > 0))
                 .map(i => i.getAttribute('src')),
    title: document.title,
  };
})()
"""


def pages_to_open(site) -> list[tuple[str, str]]:
    """(file, why): the front page, every lecture and task, the API's namespace page, the
    benchmark, the pitfalls' gallery, the rendered images."""
    c = site.content
    pages = [("index.html", "front page")]
    for sp in c.steps:
        pages += [(cmd_docs.page_id(sp.lecture) + ".html", f"lecture {sp.step.number}")] if sp.lecture else []
        pages += [(cmd_docs.page_id(sp.task) + ".html", f"task {sp.step.number}")] if sp.task else []
    pages += [(cmd_docs.page_id(p) + ".html", p.name) for p in c.other_lectures + c.bench_readings]
    pages.append(("namespaceraykit.html", "API"))
    if cmd_docs.PITFALLS_PAGE.is_file():
        pages.append((cmd_docs.page_id(cmd_docs.PITFALLS_PAGE) + ".html", "pitfalls, drawn"))
    if c.images:
        pages.append(("rendered_images.html", "rendered images"))
    return pages


def selftest_browser(ctx) -> str:
    browser, chromium = chromium_or_skip()
    site = _site(ctx)
    try:
        return _check_pages(browser, chromium, site)
    except browser.BrowserError as e:
        raise Failed(f"headless Chromium: {e}") from None


def _check_pages(browser, chromium: str, site) -> str:
    problems, formulas, images, shots = [], 0, 0, []
    with browser.Browser(chromium) as b:
        for name, why in pages_to_open(site):
            page = site.html / name
            source = page.read_text(encoding="utf-8", errors="replace")
            has_math = bool(re.search(r"\\\(|\\\[", source))
            b.open(page.as_uri())
            r = b.evaluate(INSPECT, timeout=30)
            offline = [u for u in b.requests if not u.startswith(("file:", "data:", "about:"))]
            where = f"{why} ({name})"
            if has_math and r["math"] == 0:
                problems.append(f"{where}: has formulas but MathJax typeset none")
            if r["raw"]:
                problems.append(f"{where}: raw TeX left in the text: {r['raw']}")
            if r["errors"]:
                problems.append(f"{where}: MathJax could not read {r['errors']}")
            if r["broken"]:
                problems.append(f"{where}: images that do not load: {r['broken']}")
            if offline:
                problems.append(f"{where}: asks the network for {offline[:3]}")
            formulas += r["math"]
            images += r["images"] - len(r["broken"])
            shot = SCREENSHOTS / f"{Path(name).stem}.png"
            b.screenshot(shot)
            shots.append(shot)
    expect(not problems, "\n  ".join(problems))
    lectures = sum(1 for sp in site.content.steps if sp.lecture) + len(site.content.other_lectures)
    expect(formulas > 0, "no formula typeset on any page: the header docs have some")
    return (f"{len(shots)} pages offline ({lectures} lectures): {formulas} formulas typeset, "
            f"{images} images loaded; screenshots in {cmd_docs.rel(SCREENSHOTS)}")


STUDENT_LOOP = ROOT / ".github" / "workflows" / "student-loop.yml"
SYSTEM_PYTHON = "/usr/bin/python3"      # Debian's, which sees python3-yaml


def kit_lines(run: str) -> list[list[str]]:
    """The `./kit ...` commands of a workflow step's shell script, each as its words (up to a pipe,
    a redirection or the end of the command)."""
    import shlex
    found = []
    for line in run.splitlines():
        for part in re.split(r"&&|\|\||;", line):
            part = part.strip()
            if part.startswith("./kit "):
                words = shlex.split(part, comments=True)[1:]
                cut = next((i for i, w in enumerate(words) if w in ("|", ">", ">>", "2>&1") or w.startswith(">")),
                           len(words))
                found.append(words[:cut])
    return found


@pytest.mark.quick
def selftest_student_loop_workflow(ctx) -> str:
    """The GitHub Actions workflow that runs the student loop on macOS and Ubuntu runners (#36 item 5;
    not run here): it parses as YAML, runs on both, says it is not run here, and every ./kit line
    names a command the kit has with options that command takes (its own parser reads them); the
    instructors' platform table (docs/instructors.md) names it. A planted unknown command and a wrong
    option are caught."""
    import json
    import subprocess
    from kitlib import cli
    need_solutions()    # the workflow is the instructor's: a handout has none
    probe = subprocess.run([SYSTEM_PYTHON, "-c", "import yaml"], capture_output=True) \
        if Path(SYSTEM_PYTHON).exists() else None
    if probe is None or probe.returncode != 0:
        raise Skipped(f"needs {SYSTEM_PYTHON} with python3-yaml")
    text = STUDENT_LOOP.read_text()
    parsed = subprocess.run([SYSTEM_PYTHON, "-c", "import json, sys, yaml; print(json.dumps(yaml.safe_load(sys.stdin)))"],
                            input=text, capture_output=True, text=True, timeout=60)
    expect(parsed.returncode == 0, f"{STUDENT_LOOP.relative_to(ROOT)} does not parse as YAML: {parsed.stderr[-400:]}")
    flow = json.loads(parsed.stdout)
    expect("NOT RUN" in text, "the workflow does not say it is not run here")
    jobs = list(flow.get("jobs", {}).values())
    expect(len(jobs) == 1, f"one job expected, found {len(jobs)}")
    oses = jobs[0].get("strategy", {}).get("matrix", {}).get("os", [])
    expect(set(oses) == {"macos-latest", "ubuntu-latest"}, f"the runners are {oses}")
    runs = [s["run"] for s in jobs[0]["steps"] if "run" in s]
    lines = [words for run in runs for words in kit_lines(run)]
    names = {c.name for c in cli.COMMANDS}

    def refused(words: list[str]) -> str:
        """Why the kit's parser refuses `words` ("" when it takes them)."""
        if not words or words[0] not in names:
            return f"no command {words[:1]}"
        import contextlib
        import io
        err = io.StringIO()
        try:
            with contextlib.redirect_stderr(err):
                cli.build_parser(words[0]).parse_args(words)
        except SystemExit:
            return err.getvalue().strip().splitlines()[-1] if err.getvalue().strip() else "refused"
        return ""
    bad = [f"./kit {' '.join(w)}: {refused(w)}" for w in lines if refused(w)]
    expect(not bad, "the workflow runs what the kit does not have: " + "; ".join(bad))
    used = sorted({w[0] for w in lines})
    for want in ("check", "render", "debug"):
        expect(want in used, f"the workflow never runs ./kit {want}")
    expect(refused(["chekc"]) and refused(["check", "--no-such-option"]), "the check cannot see a wrong command")
    platforms = ROOT / "docs" / "instructors.md"
    expect(".github/workflows/student-loop.yml" in platforms.read_text(),
           "docs/instructors.md's platform table does not name the workflow")
    return f"parses; macOS and Ubuntu; {len(lines)} ./kit lines ({', '.join(used)}) the kit's parser takes"


@pytest.mark.quick
def selftest_npm_once_more(ctx) -> str:
    """An npm install the network failed is tried once more, and only once: a stand-in npm on the
    PATH (which fails its first N runs, then installs what docs/package-lock.json pins) into a
    scratch folder. Needs no network."""
    import contextlib
    import io
    import os
    import tempfile
    from kitlib import webtools
    pinned = webtools.pinned_versions()
    name = sorted(pinned)[0]
    saved = (webtools.NPM_DIR, os.environ.get("PATH", ""))
    said = []
    with tempfile.TemporaryDirectory(prefix="npm-selftest-", dir=BUILD) as tmp:   # NPM_DIR is under ROOT
        bin_dir = Path(tmp) / "bin"
        bin_dir.mkdir()
        fake = bin_dir / "npm"
        install = "".join(f"mkdir -p node_modules/{p} && printf '{{\"version\": \"{v}\"}}' > "
                          f"node_modules/{p}/package.json && touch node_modules/{p}/needed\n"
                          for p, v in pinned.items())
        fake.write_text("#!/bin/sh\nn=$(cat \"$RUNS\" 2>/dev/null || echo 0); echo $((n + 1)) > \"$RUNS\"\n"
                        "if [ \"$n\" -lt \"$FAILS\" ]; then echo 'npm ERR! code ECONNRESET' >&2; exit 1; fi\n"
                        + install)
        fake.chmod(0o755)
        runs = Path(tmp) / "runs"
        outcome = {}
        try:
            os.environ["PATH"] = f"{bin_dir}{os.pathsep}{saved[1]}"
            for fails in (0, 1, 2):
                webtools.NPM_DIR = Path(tmp) / f"npm-{fails}"
                runs.unlink(missing_ok=True)
                os.environ.update(RUNS=str(runs), FAILS=str(fails))
                notes = io.StringIO()
                try:
                    with contextlib.redirect_stderr(notes):
                        webtools.npm_package(name, "needed", "the self-test needs")
                    outcome[fails] = "installed"
                except KitError as e:
                    outcome[fails] = "failed"
                    said.append(str(e))
                outcome[fails] += f" after {runs.read_text().strip()} run(s)"
                if fails:
                    expect("npm failed (npm ERR! code ECONNRESET); trying once more" in notes.getvalue(),
                           f"the retry is not said: {notes.getvalue()!r}")
        finally:
            webtools.NPM_DIR, os.environ["PATH"] = saved
            for k in ("RUNS", "FAILS"):
                os.environ.pop(k, None)
    want = {0: "installed after 1 run(s)", 1: "installed after 2 run(s)",
            2: f"failed after {webtools.NPM_ATTEMPTS} run(s)"}
    expect(outcome == want, f"npm failing 0, 1, 2 times: {outcome}, expected {want}")
    expect(said and "npm could not install" in said[0] and "ECONNRESET" in said[0],
           f"the failure does not say npm's words: {said}")
    return "a failed install tried once more (one failure: installed; two: the error, with npm's words)"

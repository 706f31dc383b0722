"""Self-test: what the lectures and hints quote is current.

- every figure the lectures quote from the benchmark sits in a block that docs/bench_numbers.py writes
  from the committed run (docs/bench/results.json), and every block matches the run;
- every lecture section a hint names exists, by number and, where the hint gives it, by title;
- every rule a header states for what is no answer ("count == 0 when ...", "... count as a miss",
  "no value when ...", "... describes no sphere", "tmin > tmax is an empty window", "..., or no value")
  has a case that asks it (listed in its step's step.json, "contract"), basic for the headers of steps 01-03.

(Each case's own lecture pointer is checked by "case names and lecture pointers" in selftest/check.py.)
"""

from __future__ import annotations

import contextlib
import copy
import io
import importlib.util
import json
import re
import tempfile
from pathlib import Path

import pytest

from raykit.common import ROOT, load_steps
from .support import Failed, Skipped, expect

GENERATOR = ROOT / "docs" / "bench_numbers.py"
ROBUST_GENERATOR = ROOT / "docs" / "robust_numbers.py"
PITFALL_PICTURES = ROOT / "docs" / "pitfall_pictures.py"
SCENE_TABLES = ROOT / "docs" / "scene_tables.py"
README_STEPS = ROOT / "docs" / "readme_steps.py"


def _generator(path: Path = GENERATOR):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.quick
def selftest_bench_numbers(ctx) -> str:
    if not GENERATOR.is_file() or not (ROOT / "docs" / "bench" / "results.json").is_file():
        raise Skipped("no docs/bench_numbers.py or no committed benchmark run here")
    bn = _generator()
    files = [p for p in bn.FILES if p.is_file()]
    try:
        stale = bn.run_files(bn.RESULTS, files, check=True)
    except bn.Stale as e:
        raise Failed(f"docs/bench_numbers.py cannot read the committed run: {e}") from None
    expect(not stale, "text quoting the benchmark does not match docs/bench/results.json "
                      f"(run python3 docs/bench_numbers.py): {', '.join(stale)}")
    blocks = sum(1 for p in files for line in p.read_text().split("\n") if bn.BEGIN.match(line))
    expect(blocks >= 4, f"only {blocks} generated blocks found in {', '.join(p.name for p in files)}")

    # The check must be able to fail: a run whose timings moved makes every timing block stale.
    data = json.loads(bn.RESULTS.read_text())
    moved = copy.deepcopy(data)
    for r in moved["results"]:
        r["cpu_ns"] = [1.5 * t for t in r.get("cpu_ns") or []]
    run = bn.Run(moved)
    changed = [b for p in files for b in bn.fill(p.read_text(), run, p.name)[1]]
    expect(len(changed) >= 3, f"timings 1.5 times slower changed only {changed}: the blocks do not follow the run")

    # Bad input: a clear message, exit 2, and no file touched.
    before = {p: p.read_text() for p in files}
    with tempfile.TemporaryDirectory() as tmp:
        broken = Path(tmp) / "results.json"
        broken.write_text('{"meta": {}, "families": [')
        for bad in (broken, Path(tmp) / "missing.json"):
            err = io.StringIO()
            with contextlib.redirect_stderr(err):
                code = bn.main(["--results", str(bad)])
            expect(code == 2 and "bench_numbers.py: " in err.getvalue(),
                   f"bench_numbers.py --results {bad.name} exited {code} ({err.getvalue().strip()!r}), "
                   "expected 2 and a message")
    expect(all(p.read_text() == t for p, t in before.items()), "bench_numbers.py changed a file on bad input")
    return f"{blocks} generated blocks current with docs/bench/results.json; stale when the run moves; bad input exits 2"


@pytest.mark.quick
def selftest_robust_numbers(ctx) -> str:
    if not ROBUST_GENERATOR.is_file() or not (ROOT / "solutions").is_dir():
        raise Skipped("no docs/robust_numbers.py or no solutions/ here (a handout)")
    rn = _generator(ROBUST_GENERATOR)
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = rn.main(["--check"])
    expect(code == 0, f"the ★ grading figures are stale: {err.getvalue().strip()}")
    record = json.loads(rn.RECORD.read_text())
    blocks = sum(1 for p in rn.FILES for line in p.read_text().split("\n") if rn.BEGIN.match(line))
    expect(blocks >= 5, f"only {blocks} generated blocks in {', '.join(p.name for p in rn.FILES)}")

    # The check can fail: a measurement with another least wrong textbook ray, and one of other suites.
    moved = copy.deepcopy(record)
    for case, checks in moved["forms"]["textbook"]["02"].items():
        for check in checks:
            if check[0] > rn.BOUND:
                check[0] += 3
    changed = rn.run_files(moved, rn.FILES, check=True)
    expect(any("appendix-table" in c for c in changed) and any("grading-bound" in c for c in changed),
           f"textbook distances 3 ulps larger changed only {changed}: the blocks do not follow the record")
    with tempfile.TemporaryDirectory() as tmp:
        other = Path(tmp) / "record.json"
        other.write_text(json.dumps({**record, "digest": "0" * 16}))
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            code = rn.main(["--check", "--record", str(other)])
        expect(code == 1 and "--measure" in err.getvalue(),
               f"a record of other suites passed --check (exit {code}, {err.getvalue().strip()!r})")
        before = {p: p.read_text() for p in rn.FILES}
        for bad in ("{", None):
            path = Path(tmp) / "bad.json"
            if bad is not None:
                path.write_text(bad)
            else:
                path = Path(tmp) / "missing.json"
            err = io.StringIO()
            with contextlib.redirect_stderr(err):
                code = rn.main(["--record", str(path)])
            expect(code == 2 and "robust_numbers.py: " in err.getvalue(),
                   f"robust_numbers.py --record {path.name} exited {code}, expected 2 and a message")
        expect(all(p.read_text() == t for p, t in before.items()), "robust_numbers.py changed a file on bad input")
    return (f"{blocks} generated blocks current with docs/robust_numbers.json, measured on today's suites and "
            "forms; stale when the measurement moves or the suites change; bad input exits 2")


@pytest.mark.quick
@pytest.mark.step
def selftest_scene_tables(ctx) -> str:
    """Lecture 05's tables are the scene file's (include/raykit/scenes/cornell_box.inc): current, stale when
    a colour changes there, and a broken scene file is a clear error."""
    if not SCENE_TABLES.is_file():
        raise Skipped("no docs/scene_tables.py here")
    st = _generator(SCENE_TABLES)
    bad = st.stale()
    expect(not bad, f"lecture 05's tables are stale: {', '.join(bad)} (run python3 docs/scene_tables.py)")
    with tempfile.TemporaryDirectory() as tmp:
        scene = Path(tmp) / "cornell_box.inc"
        text = st.SCENE.read_text()
        # A colour of the scene as it is (an instructor may have changed any of them): its first
        # component moved by 0.03, the way a course changes a wall's colour.
        colours = re.findall(r"(?m)^RAYKIT_SCENE_COLOR\((\w+),\s*([0-9.]+)f,(.*)\)\s*$", text)
        expect(colours, f"{st.SCENE.name} has no RAYKIT_SCENE_COLOR line")
        name, first, rest = next((c for c in colours if c[0] != "light"), colours[0])
        line = next(l for l in text.splitlines() if l.startswith(f"RAYKIT_SCENE_COLOR({name},"))
        moved = float(first) + (0.03 if float(first) <= 0.9 else -0.03)
        scene.write_text(text.replace(line, f"RAYKIT_SCENE_COLOR({name}, {moved:.2f}f,{rest})"))
        found = st.stale(scene)
        expect(found == ["colors"], f"a changed {name} ({first} to {moved:.2f}) gave the stale blocks {found}, "
                                    f"expected ['colors']")
        dropped = next((l for l in text.splitlines() if l.startswith("RAYKIT_SCENE_OBJECT(")), None)
        expect(dropped is not None, f"{st.SCENE.name} has no RAYKIT_SCENE_OBJECT line")
        scene.write_text(text.replace(dropped, "// " + dropped, 1))
        try:
            st.stale(scene)
            raise Failed("a scene file with five objects was read without an error")
        except st.SceneError as e:
            expect("six objects" in str(e), f"a scene with five objects: {e}")
    return (f"lecture 05's 3 tables current with include/raykit/scenes/cornell_box.inc; a changed {name} is caught; "
            "a scene file without one of its objects is a clear error")


@pytest.mark.quick
def selftest_pitfall_pictures(ctx) -> str:
    if not PITFALL_PICTURES.is_file():
        raise Skipped("no docs/pitfall_pictures.py here")
    pp = _generator(PITFALL_PICTURES)
    bad = pp.stale()
    expect(not bad, f"docs/pitfalls/ is stale: {', '.join(bad)} (run python3 docs/pitfall_pictures.py)")
    page = (ROOT / "docs" / "pitfalls.md").read_text()
    linked = set(re.findall(r"\]\((pitfalls/[^)\s]+\.svg)\)", page))
    missing = sorted(p for p in linked if not (ROOT / "docs" / p).is_file())
    expect(linked and not missing, f"docs/pitfalls.md links pictures that are not committed: {missing}")
    # The check can fail: a committed picture changed by one byte, and one missing.
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for p in pp.FOLDER.glob("*.svg"):
            (folder / p.name).write_bytes(p.read_bytes())
        first = sorted(folder.glob("*.svg"))
        first[0].write_text(first[0].read_text().replace("<svg", "<svg ", 1))
        first[1].unlink()
        found = pp.stale(folder)
        expect(found == sorted([first[0].name, first[1].name]), f"a changed and a missing picture gave {found}")
    return f"{len(linked)} pictures of docs/pitfalls.md committed and current; a changed or missing one is caught"


# "section 4", "sections 5 and 6", "section 2. The ray meets the sphere" (a title starts with a capital).
SECTION = re.compile(r"\bsections?\s+(\d+(?:\s*(?:,|and|to)\s*\d+)*)(?:\. ([A-Z][^)\n]*))?", re.I)


@pytest.mark.quick
@pytest.mark.step
def selftest_hint_sections(ctx) -> str:
    bad, seen = [], 0
    for step in ctx.steps:
        hints = ROOT / "tests" / step.folder / "hints.md"
        lecture = ROOT / step.lecture
        if not hints.is_file() or not lecture.is_file():
            continue
        headings = [h.strip() for h in re.findall(r"^#+\s+(.*)$", lecture.read_text(), re.M)]
        numbers = {h.split(".")[0] for h in headings if re.match(r"\d+\.", h)}
        text = hints.read_text()
        # Only what a hint says about its own lecture: drop "lecture 03, sections 5 and 6" and the like.
        text = re.sub(r"lecture\s+\d+,?\s+sections?\s+[\d ,andto]+", "", text, flags=re.I)
        for m in SECTION.finditer(text):
            seen += 1
            for n in re.findall(r"\d+", m.group(1)):
                if n not in numbers:
                    bad.append(f"step {step.number}: a hint cites section {n}, which {step.lecture} does not have")
            if m.group(2):
                title = f"{m.group(1).strip()}. {m.group(2).strip()}"
                if title not in headings:
                    bad.append(f"step {step.number}: a hint cites '{title}', not a heading of {step.lecture}")
    expect(seen > 0, "no hint cites a lecture section: the check reads nothing")
    expect(not bad, "\n  ".join(bad[:10]))
    return f"{seen} section pointers in the hints name sections that exist"


# ---- every contract clause of include/raykit/*.hpp has a case ------------------------------------

def doc_blocks(text: str) -> list[tuple[str, str]]:
    """(declared name, its /// comment as one line) for every commented declaration of a header."""
    out, buf = [], []
    for line in text.split("\n"):
        s = line.strip()
        if s.startswith("///"):
            buf.append(s[3:].strip())
            continue
        if buf and s:
            m = re.match(r"(?:struct|class)\s+(\w+)", s) or re.search(r"(\w+)\s*\(", s)
            if m and not s.startswith("#"):
                out.append((m.group(1), " ".join(buf)))
            buf = []
    return out


def _norm(text: str) -> str:
    text = text.replace("`", "").replace("**", "")
    text = re.sub(r"(?<=\w)\.(?=\w)", "·", text)  # d.d, f.d: not the end of a sentence
    text = re.sub(r"\\return\s+|\\param\s+\w+\s+", " ", text)
    return re.sub(r"\s+", " ", text).strip()


# One condition per part: "A, or B", "A, an B", "when A, when B or when C", "A, even when B".
_SPLIT = re.compile(r",\s+or\s+|,\s+(?=(?:a|an|so|inputs)\s)|,?\s+or\s+when\s+|,\s+when\s+|,\s+even\s+when\s+", re.I)
_CLAUSES = [re.compile(p, re.I) for p in (
    r"count == 0 when ([^.:;]+)",
    r"(?:^|[.;:]\s*)([^.;:]+?) (?:may )?counts? as a miss",
    r"no value (?:as well )?when ([^.:;]+)",
    r"(tmin > tmax) (?:means|is) an empty window",
    r"(?:^|[.;:]\s*)(?:any \w+; )?([^.;:]+?) describes? no (?:sphere|rectangle)",
)]


def drop_asides(text: str) -> str:
    r"""The text without its parenthesised asides, nested ones included: `(\`dot(n, d)\` is +0 or -0)`
    goes whole, innermost parentheses first (a single `[^)]*` stopped at the first `)`)."""
    while True:
        shorter = re.sub(r"\s*\([^()]*\)", "", text)
        if shorter == text:
            return text
        text = shorter


def asides_after(text: str, opening: str) -> list[str]:
    """The insides of every balanced `(OPENING ...)` aside in text, nested parentheses kept."""
    found, at = [], text.find("(" + opening)
    while at >= 0:
        depth, i = 0, at
        while i < len(text):
            depth += {"(": 1, ")": -1}.get(text[i], 0)
            if depth == 0:
                found.append(text[at + 1 + len(opening):i])
                break
            i += 1
        at = text.find("(" + opening, at + 1)
    return found


def contract_clauses(text: str) -> list[tuple[str, str]]:
    """(function or type, condition) for every "no answer" rule the header text states, in order."""
    out: list[tuple[str, str]] = []
    for name, comment in doc_blocks(text):
        t = _norm(comment)
        for i, pat in enumerate(_CLAUSES):
            for m in pat.finditer(t):
                if i in (1, 4) and " when " in m.group(1):
                    continue  # a subject that runs over a "when" list belongs to the first pattern
                bare = drop_asides(m.group(1)).strip(" ,.")
                out += [(name, p.strip(" ,.").lower()) for p in _SPLIT.split(bare) if p.strip(" ,.")]
                for extra in asides_after(t[m.start():m.end() + 80], "always for "):
                    out += [(name, e.strip().lower()) for e in re.split(r"\s+or\s+", extra)]
        if re.search(r", or no value\b", t, re.I):
            out.append((name, "nothing in the window"))
    return list(dict.fromkeys(out))


# Headers whose rules must be asked by a basic case (a point), not only by a ★ one.
BASIC_HEADERS = {"unit_sphere.hpp", "general_sphere.hpp", "unit_direction.hpp", "sphere.hpp"}


def suite_cases(sources: dict[str, str]) -> dict[str, set[str]]:
    """Case name -> the tiers ("basic", "robust") it is in, over the given suite sources."""
    cases: dict[str, set[str]] = {}
    for text in sources.values():
        tier = ""
        for m in re.finditer(r'TEST_SUITE_BEGIN\("(\w+)"\)|TEST_CASE\("([^"]*)"', text):
            if m.group(1):
                tier = m.group(1)
            else:
                cases.setdefault(m.group(2), set()).add(tier)
    return cases


def contract_cases() -> dict[str, list[str]]:
    """For each rule a header states, "header:name:condition", the cases that ask it (in any step's
    suites): the `"contract"` of every step's step.json, so a step lists its header's rules in its own
    manifest and nothing here names a step."""
    found: dict[str, list[str]] = {}
    for step in load_steps():
        found.update(step.contract)
    return found


def contract_problems(headers: dict[str, str], sources: dict[str, str],
                      listed: dict[str, list[str]] | None = None) -> tuple[list[str], int]:
    listed = contract_cases() if listed is None else listed
    cases = suite_cases(sources)
    found = {f"{h}:{name}:{cond}" for h, text in headers.items() for name, cond in contract_clauses(text)}
    bad = [f"{k}: a rule of the header that no case asks (add a case and list it in step.json's \"contract\")"
           for k in sorted(found - listed.keys())]
    bad += [f"{k}: listed in a step.json's \"contract\", but no header states it any more"
            for k in sorted(listed.keys() - found)]
    for key in sorted(found & listed.keys()):
        for case in listed[key]:
            if case not in cases:
                bad.append(f"{key}: its case \"{case}\" is in no suite")
            elif key.split(":")[0] in BASIC_HEADERS and "basic" not in cases[case]:
                bad.append(f"{key}: its case \"{case}\" is not a basic case")
    return bad, len(found)


@pytest.mark.quick
@pytest.mark.step
def selftest_contract_clauses(ctx) -> str:
    headers = {p.name: p.read_text() for p in sorted((ROOT / "include" / "raykit").glob("*.hpp"))}
    sources = {str(p): p.read_text() for p in sorted((ROOT / "tests").glob("0*_*/test_*.cpp"))}
    if not sources:
        raise Skipped("no step suites here")
    bad, n = contract_problems(headers, sources)
    expect(n >= 20, f"only {n} rules read from include/raykit/*.hpp: the reader has lost its way")
    expect(not bad, "\n  ".join(bad[:12]))

    # The check must be able to fail: a suite without one of the cases, a header with one more rule.
    key = "unit_sphere.hpp:unit_sphere_roots:inputs containing nan or infinity"
    gone = {p: re.sub(r'TEST_CASE\("a ray holding NaN is no ray: no roots"', 'TEST_CASE("renamed"', t)
            for p, t in sources.items()}
    missing, _ = contract_problems(headers, gone)
    expect(any(key in b and "in no suite" in b for b in missing),
           f"removing the NaN case of step 01 went unnoticed: {missing}")
    more = dict(headers)
    more["unit_sphere.hpp"] = more["unit_sphere.hpp"].replace(
        "no root is ever NaN.", "no root is ever NaN. An origin at the centre counts as a miss.")
    extra, _ = contract_problems(more, sources)
    expect(any("an origin at the centre" in b and "no case asks" in b for b in extra),
           f"a new rule in unit_sphere.hpp went unnoticed: {extra}")
    # An instructor's rule with a nested aside (issue 46): the aside goes whole, the rule stays.
    nested = contract_clauses("/// A disc facing the ray edge-on (`dot(normal, d)` is +0 or -0) counts as a miss.\n"
                              "std::optional<float> intersect_disc(const Ray& ray, const Disc& disc);\n")
    expect(nested == [("intersect_disc", "a disc facing the ray edge-on")],
           f"a rule with nested parentheses read as {nested}")
    return f"{n} rules of include/raykit/*.hpp, each asked by a case (basic for steps 01-03); " \
           "a removed case and an unasked rule are caught; nested parentheses read"


@pytest.mark.quick
@pytest.mark.step
def selftest_readme_steps(ctx) -> str:
    """README.md's step table is the steps' manifests' (docs/readme_steps.py): a row per step, in order,
    and a step added or renamed makes it stale."""
    if not README_STEPS.is_file():
        raise Skipped("no docs/readme_steps.py here")
    rs = _generator(README_STEPS)
    block = rs.BLOCK.search(rs.README.read_text())
    expect(block is not None, "README.md has no <!-- readme_steps.py --> block for the step table")
    want = rs.table()
    expect(block.group(2) == want, "README.md's step table is stale (run python3 docs/readme_steps.py):\n"
           + "\n".join(sorted(set(want.splitlines()) ^ set(block.group(2).splitlines()))))
    rows = re.findall(r"(?m)^\| (\d\d) \|", block.group(2))
    expect(rows == [s.number for s in load_steps()], f"the table's rows {rows}, the steps {[s.number for s in load_steps()]}")
    with tempfile.TemporaryDirectory() as tmp:      # it can fail: one step more in the manifests
        for folder, manifest in rs.manifests():
            (Path(tmp) / "tests" / folder).mkdir(parents=True)
            (Path(tmp) / "tests" / folder / "step.json").write_text(json.dumps(manifest))
        extra = f"{int(rows[-1]) + 1:02d}_extra"
        (Path(tmp) / "tests" / extra).mkdir()
        (Path(tmp) / "tests" / extra / "step.json").write_text(json.dumps({"title": "An extra step", "files": []}))
        grown = rs.table(Path(tmp))
        expect(grown != block.group(2) and f"| {extra[:2]} | An extra step |" in grown,
               "a step added to the manifests leaves the table unchanged")
    return f"{len(rows)} rows, one per step.json, in order; a step added makes it stale"

"""Self-test: the kit's own latencies, as a student meets them, on a pseudo-terminal.

- first output: a cold `./kit check` in a handout whose steps/ hold the solutions (its build folder
  from nothing), until it prints;
- first verdict: the same run, until step 01's row shows its verdict;
- cold check: the same run, until it ends (every step configured, built and checked);
- after a clean: the build folder removed, `./kit check` again: the kit's own objects (doctest's main,
  the judges, the dispatchers) come from the kit cache (tools/kitlib/kitcache.py), the student's
  files compile;
- edit to verdict: step 01's file changed, `./kit check 1` again, until it ends.

The figures depend on the machine and its load: they are reported beside the goals of issue 13
(first output within 1 s, step 01 within 8 s, all within 15 s cold, edit to verdict 1.5 s on a
quiet 2-core machine), never asserted against a clock. The self-test fails only when the run
itself goes wrong (no table, a solution step not done).
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import time
from pathlib import Path

from .. import procfs
from ..common import BUILD, ROOT
from .harness import Context, Failed, Screen, expect, kit, need_solutions, tier

ANSI = re.compile(r"\033\[[0-9;]*[A-Za-z]")
HANDOUT_DIR = BUILD / "latency-handout"


def run_check(kit_dir, *args: str) -> tuple[Screen, dict]:
    """`kit_dir`/kit check ARGS on a pseudo-terminal; the times of its first output, of step 01's
    verdict and of its end."""
    screen = Screen([str(kit_dir / "kit"), "check", *args], cwd=kit_dir)
    marks: dict[str, float] = {}
    try:
        while screen.proc.poll() is None or "end" not in marks:
            text = ANSI.sub("", screen.text).replace("\r", "\n")
            if "output" not in marks and text.strip():
                marks["output"] = time.monotonic() - screen.started
            if "01" not in marks and re.search(r"^\s*01\s.*(done|cases|not started)", text, re.M):
                marks["01"] = time.monotonic() - screen.started
            if screen.proc.poll() is not None:
                time.sleep(0.1)                 # the last bytes from the terminal
                marks["end"] = time.monotonic() - screen.started
            time.sleep(0.02)
            if time.monotonic() - screen.started > 900:
                raise Failed("./kit check ran over 15 minutes")
    finally:
        screen.close()
    return screen, marks


def selftest_latency(ctx: Context) -> str:
    """Measured where students run the kit: a handout (no solutions/, so no hidden cases and no
    reference build), its build folder from nothing: first with the stubs as shipped (a newcomer's
    first check), then with step 01 written (its first verdict), then every step written."""
    need_solutions()
    shutil.rmtree(HANDOUT_DIR, ignore_errors=True)
    # A kit cache of its own, empty: the cold figures are a newcomer's, whose ~/.cache holds nothing yet.
    cache = BUILD / "latency-kit-cache"
    shutil.rmtree(cache, ignore_errors=True)
    saved = os.environ.get("RAYKIT_KIT_CACHE_DIR")
    os.environ["RAYKIT_KIT_CACHE_DIR"] = str(cache)
    try:
        return _latency(ctx)
    finally:
        if saved is None:
            os.environ.pop("RAYKIT_KIT_CACHE_DIR", None)
        else:
            os.environ["RAYKIT_KIT_CACHE_DIR"] = saved
        shutil.rmtree(cache, ignore_errors=True)


def _latency(ctx: Context) -> str:
    r = kit("handout", str(HANDOUT_DIR), "--committed", timeout=600)
    expect(r.returncode == 0, f"./kit handout failed:\n{r.stdout[-800:]}{r.stderr[-800:]}")
    shutil.copytree(HANDOUT_DIR / "steps", HANDOUT_DIR / "steps.orig")     # the stubs, to restore one
    student_build = HANDOUT_DIR / "build" / "student"
    first = ctx.steps[0]

    def write_step01(source: Path) -> None:
        for f in first.files:
            shutil.copyfile(source / first.folder / f, HANDOUT_DIR / "steps" / first.folder / f)

    # The newcomer's first check starts the warm-up (kitlib/warmup.py); step 01 written at once
    # stops it, and its verdict is the cold figure: nothing of the kit built yet.
    os.environ.pop("RAYKIT_NO_WARMUP", None)
    try:
        screen, fresh = run_check(HANDOUT_DIR)
        expect("not started" in screen.text and "Next: step 01" in ANSI.sub("", screen.text),
               f"a newcomer's first check does not say what to do next:\n{screen.text[-800:]}")
        expect((student_build / "warm-up.pid").is_file(), "a newcomer's first check started no warm-up")
        write_step01(ROOT / "solutions")
        screen, one = run_check(HANDOUT_DIR, "1")
        expect(screen.proc.returncode == 0, f"step 01 written: exit {screen.proc.returncode}:\n{screen.text[-800:]}")
        left = warm_up_processes(student_build)
        expect(not left, f"the check did not end the warm-up: {left} still run")
        # Step 01 written after the warm-up has finished (a newcomer reading the task for a minute).
        shutil.rmtree(HANDOUT_DIR / "build", ignore_errors=True)
        shutil.rmtree(os.environ["RAYKIT_KIT_CACHE_DIR"], ignore_errors=True)
        write_step01(HANDOUT_DIR / "steps.orig")
        screen, _ = run_check(HANDOUT_DIR)
        began = time.monotonic()
        while (student_build / "warm-up.pid").is_file() and time.monotonic() - began < 600:
            time.sleep(0.2)
        warm = time.monotonic() - began
        log = (student_build / "warm-up.log").read_text(errors="replace") if (student_build / "warm-up.log").is_file() else ""
        expect("warm-up: built" in log, f"the warm-up did not build the kit's programs:\n{log[-1500:]}")
        write_step01(ROOT / "solutions")
        screen, after_warm = run_check(HANDOUT_DIR, "1")
        expect(screen.proc.returncode == 0, f"step 01 after the warm-up: exit {screen.proc.returncode}:\n"
               f"{screen.text[-800:]}")
    finally:
        os.environ["RAYKIT_NO_WARMUP"] = "1"
    shutil.rmtree(HANDOUT_DIR / "build", ignore_errors=True)
    # The cold figure is a first build's: the kit cache emptied of what step 01's check put in it.
    shutil.rmtree(os.environ["RAYKIT_KIT_CACHE_DIR"], ignore_errors=True)
    for step in ctx.steps:
        for f in step.files:
            shutil.copyfile(ROOT / "solutions" / step.folder / f, HANDOUT_DIR / "steps" / step.folder / f)
    load = os.getloadavg()[0]
    screen, cold = run_check(HANDOUT_DIR)
    expect(screen.proc.returncode == 0, f"the cold check of the solutions exited {screen.proc.returncode}:\n"
           f"{screen.text[-1500:]}")
    expect("01" in cold, "step 01's row never showed a verdict")
    expect("building the test program" in screen.text, "no progress line while building")
    # The kit cache was empty: the build ran without its launcher and the kit filled the cache after it.
    launched = kit_cache_targets(HANDOUT_DIR / "build" / "student")
    expect(not launched, f"with an empty kit cache, the launcher still ran for {sorted(launched)}")
    # A clean of build/ (or a second handout): the kit's own objects come from its cache, each found
    # under the key the launcher computes: the fill's keys are the launcher's.
    shutil.rmtree(HANDOUT_DIR / "build", ignore_errors=True)
    cache_log = BUILD / "latency-kit-cache.log"
    cache_log.unlink(missing_ok=True)
    os.environ["RAYKIT_KIT_CACHE_LOG"] = str(cache_log)
    try:
        screen, clean = run_check(HANDOUT_DIR)
    finally:
        os.environ.pop("RAYKIT_KIT_CACHE_LOG", None)
    expect(screen.proc.returncode == 0, f"the check after a clean of build/ exited {screen.proc.returncode}:\n"
           f"{screen.text[-1500:]}")
    lines = cache_log.read_text().split("\n") if cache_log.is_file() else []
    hits = [l for l in lines if l.startswith("hit ")]
    expect(hits and len(hits) == len([l for l in lines if l]),
           f"after a clean of build/, the kit's own objects were not all from the cache: {lines[:20]}")
    launched = kit_cache_targets(HANDOUT_DIR / "build" / "student")
    expect(launched and all(KIT_OWN.fullmatch(t) for t in launched),
           f"the kit cache's launcher is given to other targets than the kit's own: {sorted(launched)}")
    hit_targets = {m.group(1) for l in hits for m in [re.search(r"CMakeFiles/(\w+)\.dir/", l)] if m}
    expect(hit_targets == launched, f"hits for {sorted(hit_targets)}, the launcher's targets {sorted(launched)}")
    cache_log.unlink(missing_ok=True)
    # An edit: a comment changes the file, so the step is rebuilt and checked again.
    step = ctx.steps[0]
    f = HANDOUT_DIR / "steps" / step.folder / step.files[0]
    f.write_text(f.read_text() + "\n// edited\n")
    screen, edit = run_check(HANDOUT_DIR, "1")
    expect(screen.proc.returncode == 0, f"step 01 after the edit exited {screen.proc.returncode}")
    shutil.rmtree(HANDOUT_DIR, ignore_errors=True)
    return (f"a student's ./kit check in a handout, on a terminal: a newcomer's first check (the stubs) "
            f"{fresh['end']:.2f} s (goal 2); step 01 written at once, its first verdict cold {one['end']:.1f} s (goal 6), "
            f"written after the warm-up ({warm:.0f} s in the background) {after_warm['end']:.1f} s; "
            f"all steps written, cold: first output {cold['output']:.2f} s (goal 1), step 01's verdict "
            f"{cold['01']:.1f} s, all steps {cold['end']:.1f} s (goal 10); the same after a clean of build/, the "
            f"kit's own objects from its cache, {clean['end']:.1f} s; edit to verdict {edit['end']:.1f} s "
            f"(goal 1); load average {load:.1f} at the start")


def warm_up_processes(build_dir: Path) -> list[str]:
    """The command lines of processes left in the handout once its check has ended: the warm-up
    (./kit check --warm-up) or anything working in `build_dir` (cmake, ninja, a compiler)."""
    found = []
    for p in procfs.pids():
        if p == os.getpid():
            continue
        cmd, cwd = procfs.cmdline(p), procfs.cwd(p)
        if not cwd or not procfs.alive(p):
            continue
        if ("--warm-up" in cmd and cwd.startswith(str(HANDOUT_DIR))) or cwd.startswith(str(build_dir)):
            found.append(cmd[:120])
    return found


# The kit's own targets, the only ones CMake may give the kit cache's launcher (CMakeLists.txt,
# raykit_kit_cached): never a target that compiles a student's file (stepobjNN, needobjNN).
KIT_OWN = re.compile(r"raykit_test_support|raykit_platform|dispatch\d\d|test_step\d\d")


def kit_cache_targets(build_dir) -> set[str]:
    """The targets whose compile rule in `build_dir` runs through tools/kitlib/kitcache.py."""
    rules = (build_dir / "CMakeFiles" / "rules.ninja").read_text()
    found = set()
    for m in re.finditer(r"^rule CXX_COMPILER__(\w+)_[A-Za-z]*\n((?:  .*\n)+)", rules, re.M):
        if "kitcache.py" in m.group(2):
            found.add(m.group(1))
    return found


def selftest_kit_cache(ctx: Context) -> str:
    """tools/kitlib/kitcache.py on a small compile: a hit gives the same object, an edited header or a
    damaged entry compiles again, a failing compile stores nothing, and a cache that cannot be written
    only costs the cache."""
    import subprocess
    import tempfile
    from pathlib import Path
    launcher = ROOT / "tools" / "kitlib" / "kitcache.py"
    compiler = shutil.which("c++") or shutil.which("g++") or shutil.which("clang++")
    if compiler is None:
        raise Failed("no C++ compiler on PATH")
    with tempfile.TemporaryDirectory(prefix="raykit-kitcache-") as tmp:
        work, cache, log = Path(tmp) / "w", Path(tmp) / "cache", Path(tmp) / "log"
        work.mkdir()
        (work / "h.hpp").write_text("inline int answer() { return 41; }\n")
        (work / "a.cpp").write_text('#include "h.hpp"\nint f() { return answer() + 1; }\n')

        def compile_(cache_dir=cache) -> tuple[int, str]:
            (work / "a.o").unlink(missing_ok=True)
            r = subprocess.run([sys.executable, "-S", str(launcher), str(cache_dir), compiler, "-MD", "-MT", "a.o",
                                "-MF", "a.o.d", "-O1", "-o", "a.o", "-c", "a.cpp"], cwd=work, capture_output=True,
                               text=True, env=dict(os.environ, RAYKIT_KIT_CACHE_LOG=str(log)))
            said = log.read_text().split()[-2] if log.is_file() and log.read_text().strip() else "none"
            log.unlink(missing_ok=True)
            return r.returncode, said

        expect(compile_() == (0, "miss"), "the first compile was not a miss")
        first = (work / "a.o").read_bytes()
        expect(compile_() == (0, "hit") and (work / "a.o").read_bytes() == first and (work / "a.o.d").is_file(),
               "the second compile was not a hit giving the same object and its dependency file")
        (work / "h.hpp").write_text("inline int answer() { return 42; }\n")
        expect(compile_() == (0, "miss"), "an edited header was not compiled again")
        (work / "h.hpp").write_text("inline int answer() { return 41; }\n")
        expect(compile_() == (0, "hit") and (work / "a.o").read_bytes() == first,
               "the header as it was did not find its old entry")
        for manifest in cache.rglob("manifest"):
            manifest.write_text("{ damaged")
        expect(compile_() == (0, "miss"), "a damaged entry was used, or stopped the compile")
        (work / "a.cpp").write_text("int f() { return undefined_name; }\n")
        before = len(list(cache.rglob("manifest")))
        code, said = compile_()
        expect(code != 0 and said == "none" and len(list(cache.rglob("manifest"))) == before,
               f"a failing compile: exit {code}, logged {said}, or it stored an entry")
        (work / "a.cpp").write_text('#include "h.hpp"\nint f() { return answer() + 1; }\n')
        blocked = Path(tmp) / "not-a-folder"
        blocked.write_text("")
        expect(compile_(blocked)[0] == 0 and (work / "a.o").is_file(), "a cache that cannot be written broke the compile")
        # Past its limit the cache is pruned to half, an entry of a former version (never found again)
        # before the least recently used of this one.
        from .. import kitcache
        former = cache / "zz" / "former" / "entry"
        former.mkdir(parents=True)
        (former / kitcache.FORMER_MANIFEST).write_text("{}")
        (former / "object").write_bytes(b"\0" * 4096)
        current = [p.parent for p in cache.rglob(kitcache.MANIFEST)]
        size = sum(f.stat().st_size for f in cache.rglob("*") if f.is_file())
        limit, kitcache.MAX_BYTES = kitcache.MAX_BYTES, size - 1
        try:
            kitcache.prune(str(cache))
        finally:
            kitcache.MAX_BYTES = limit
        expect(not former.exists() and current and all(p.is_dir() for p in current),
               "a prune kept an entry of a former version, or removed a current one first")
        # The fill (kitcache.fill, after a first build without the launcher): the object compiled
        # by the compiler alone, stored with the files it read, is what the launcher then finds,
        # and a header named with a space in its path is read back as one name.
        filled = Path(tmp) / "filled"
        (work / "my h.hpp").write_text("inline int more() { return 1; }\n")
        (work / "a.cpp").write_text('#include "h.hpp"\n#include "my h.hpp"\nint f() { return answer() + more(); }\n')
        argv = [compiler, "-MD", "-MT", "a.o", "-MF", "a.o.d", "-O1", "-o", "a.o", "-c", "a.cpp"]
        expect(subprocess.run(argv, cwd=work).returncode == 0, "the plain compile failed")
        deps = [str(work / p) for p in kitcache.dependencies((work / "a.o.d").read_text())]
        expect(str(work / "my h.hpp") in deps, f"the dependency file's names, read: {deps}")
        expect(kitcache.fill(str(filled), os.path.realpath(work), argv, deps, {}), "the fill stored nothing")
        alone = (work / "a.o").read_bytes()
        expect(compile_(filled) == (0, "hit") and (work / "a.o").read_bytes() == alone,
               "the launcher did not find what the fill stored, or gave another object")
        stored = next(filled.rglob("depfile")).read_text()
        expect(set(kitcache.dependencies(stored)) == set(deps), f"the stored dependency file reads {stored!r}")
        (work / "my h.hpp").write_text("inline int more() { return 2; }\n")
        expect(compile_(filled) == (0, "miss"), "a header edited since the fill was not compiled again")
    return ("a hit gives the same object; an edited header, a damaged entry compile again; a failing compile "
            "stores nothing; an unwritable cache only costs the cache; a former version's entries pruned first; "
            "what the fill stores, the launcher finds (and misses once a header it read is edited)")


@tier("step")
def selftest_recorded(ctx: Context) -> str:
    """tests/stubs.json holds the committed stubs' hashes, and each tests/NN_topic/cases.json (with
    tests/hidden/cases.json) the cases its judge lists: else an untouched step would be scored on
    a stale list. `./kit check --record` writes them."""
    need_solutions()
    import json
    import subprocess
    from ..checking import HIDDEN_CASES_FILE, STUBS_FILE, ensure_configured, file_hash
    from ..runcases import list_cases
    from ..build import build_targets, preset_build
    stubs = json.loads(STUBS_FILE.read_text())
    stale = []
    for step in ctx.steps:
        for f in step.files:
            rel = f"steps/{step.folder}/{f}"
            shown = subprocess.run(["git", "show", f"HEAD:{rel}"], cwd=ROOT, capture_output=True)
            data = shown.stdout if shown.returncode == 0 else (ROOT / rel).read_bytes()
            import hashlib
            if stubs.get(f"{step.folder}/{f}") != hashlib.sha256(data).hexdigest():
                stale.append(rel)
    build = preset_build("student")
    ensure_configured(build, ctx.steps)
    ok, out = build_targets(build, [s.target for s in ctx.steps])
    expect(ok, f"the judges do not build: {out[-500:]}")
    hidden = json.loads(HIDDEN_CASES_FILE.read_text())
    for step in ctx.steps:
        listed = [(c.name, c.tier, c.lecture) for c in list_cases(build.exe(step))]
        visible = json.loads((ROOT / "tests" / step.folder / "cases.json").read_text())
        recorded = [(c["name"], c["tier"], c["lecture"]) for c in visible + hidden.get(step.number, [])]
        if sorted(listed) != sorted(recorded):
            stale.append(f"tests/{step.folder}/cases.json")
    del file_hash
    expect(not stale, "stale: " + ", ".join(stale) + ". Run ./kit check --record and commit what it writes.")
    return f"the stubs' hashes and {len(ctx.steps)} case lists are current"


def selftests() -> list:
    return [("recorded stubs and case lists", selftest_recorded), ("the kit cache", selftest_kit_cache),
            ("latency figures", selftest_latency)]

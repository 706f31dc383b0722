"""The kit's self-test as pytest runs it: the driver on the path, the markers, the kit's context as a
session fixture, the quick tier's guard and CI's rule for security tests as hooks.

From the kit's root (./kit test says the same in its own words, see commands/selftest.py):

    python3 -m pytest -m quick -n 2 tests/      # the quick tier: builds and grades nothing (a minute)
    RAYKIT_SELFTEST_STEP=3 python3 -m pytest -m step    # what a change to step 03 needs, on step 03 alone
    python3 -m pytest tests/kit/draws.py -v     # one module; -v prints each test's one-line summary
    python3 -m pytest -n 2 tests/               # everything (20 minutes and more)

A self-test is a function `selftest_NAME(ctx)` (pytest.ini's python_functions); a module's tests run
in the order they are written, the modules in ORDER's. Markers (registered below):
- quick: builds and grades nothing, a few seconds (`-m quick`); while one runs, configuring or building
  anything fails (common.QUICK_TIER), so a test that starts to build is named, not slowly tolerated;
- step: everything a change to one step needs (`-m step`; RAYKIT_SELFTEST_STEP=N: ctx.steps is step N alone);
- security: may not skip in CI (support.py's docstring; the hook below);
- serial: shares a machine resource (build folders, sandbox ids, the machine's time) with other
  tests, so under xdist (-n 2) it runs on one worker, one after another. Every test that is not quick
  is serial; the quick ones spread over the workers.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

# What ./kit sets before the driver starts: tools/ on the path, the kit's modules compiled into its cache
# folder and nowhere beside the sources (raykit/pycache.py); the same for the ./kit the tests start.
TOOLS = Path(__file__).resolve().parents[2] / "tools"
os.environ["PYTHONDONTWRITEBYTECODE"] = "1"
sys.dont_write_bytecode = True
os.environ.pop("PYTHONPYCACHEPREFIX", None)
if os.environ.get("XDG_CACHE_HOME") or os.environ.get("HOME"):
    os.environ["RAYKIT_PYCACHE"] = str(Path(os.environ.get("XDG_CACHE_HOME") or Path(os.environ["HOME"]) / ".cache")
                                       / "raykit" / "pycache")
if str(TOOLS) not in sys.path:
    sys.path.insert(0, str(TOOLS))
os.environ["PYTHONPATH"] = os.pathsep.join([str(TOOLS)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep)
                                                          if p and p != str(TOOLS)])

from raykit import pycache  # noqa: E402

pycache.install()

from raykit.common import QUICK_TIER, KitError, load_steps  # noqa: E402

from . import support  # noqa: E402

# The order of a run: the grading first (later self-tests reuse its builds), the slowest last. A module
# not named here runs after these.
ORDER = ["layers", "ci", "lint", "check", "course", "bench", "debug", "docs", "fuzz", "handout", "hint", "integrity",
         "integrity_slots", "own_faults", "boundary", "latency", "lectures", "mutant", "render", "pictures", "robust",
         "robust_line", "grade", "faults", "report", "workflow", "newstep", "customised", "watch", "reach",
         "sanitizers", "lab", "slides", "slips", "draws", "refresh"]

MARKERS = {"quick": "builds and grades nothing, a few seconds (./kit test --quick); building fails while it runs",
           "step": "everything a change to one step needs (./kit test --step N: -m step, RAYKIT_SELFTEST_STEP=N)",
           "security": "a security test: in CI (CI=true) a skip is a failure unless .ci/run declares the need",
           "serial": "shares a machine resource: under xdist, one worker runs these one after another"}
SERIAL_GROUP = "serial"


def pytest_configure(config) -> None:
    for name, text in MARKERS.items():
        config.addinivalue_line("markers", f"{name}: {text}")
    if not hasattr(config, "workerinput"):      # once a run, not once an xdist worker
        from kitlib.commands import selftest as command
        command.prepare()
    else:
        os.environ["RAYKIT_NO_WARMUP"] = "1"
    support.prepare()


def _module(item) -> str:
    return Path(str(item.fspath)).stem


def pytest_pycollect_makeitem(collector, name, obj):
    """A self-test is collected where it is written, not where another module imports it."""
    if name.startswith("selftest_") and callable(obj) and isinstance(collector, pytest.Module):
        module = getattr(getattr(obj, "__wrapped__", obj), "__module__", None)
        if module is not None and module != collector.obj.__name__:
            return []
    return None


@pytest.hookimpl(tryfirst=True)      # before xdist's, which reads the xdist_group marks
def pytest_collection_modifyitems(config, items) -> None:
    rank = {name: i for i, name in enumerate(ORDER)}
    items.sort(key=lambda item: rank.get(_module(item), len(ORDER)))     # stable: a module's own order kept
    for item in items:
        if item.get_closest_marker("quick") is None:
            item.add_marker(pytest.mark.serial)
        if item.get_closest_marker("serial") is not None:
            item.add_marker(pytest.mark.xdist_group(SERIAL_GROUP))


# What ./kit test's --step N and --fast say to the suite (environment variables rather than pytest options:
# a conftest.py below the rootdir adds none that `pytest tests/` knows).
STEP_ENV, FAST_ENV = "RAYKIT_SELFTEST_STEP", "RAYKIT_SELFTEST_FAST"


@pytest.fixture(scope="session")
def ctx() -> support.Context:
    """The kit's context, one a process: ctx.fast (RAYKIT_SELFTEST_FAST=1: leave out the slow builds) and
    ctx.steps (every step, or RAYKIT_SELFTEST_STEP=N's alone)."""
    wanted = os.environ.get(STEP_ENV, "").strip()
    fast = os.environ.get(FAST_ENV, "") not in ("", "0")
    if not wanted:
        return support.Context(fast=fast)
    steps = [s for s in load_steps() if s.number == wanted.zfill(2)]
    if not steps:
        raise KitError(f"{STEP_ENV}={wanted}: no such step (the steps are {', '.join(s.number for s in load_steps())})")
    return support.Context(fast=fast, steps=steps)


@pytest.fixture(scope="session")
def committed_steps(tmp_path_factory) -> Path:
    """steps/ as committed, in a folder of this run's (support.committed_steps): the stubs as shipped,
    whatever answers the working tree's steps/ holds."""
    return support.committed_steps(tmp_path_factory.mktemp("committed"))


@pytest.fixture(scope="session")
def kit_side():
    """The kit's side (bundle.py: every step's judge, no student's code), built once a machine; for a
    self-test that runs the judges themselves."""
    from raykit import bundle
    from raykit.build import detect_undefined
    return bundle.ensure(detect_undefined())


@pytest.fixture(scope="session")
def bench_exe() -> Path:
    """The benchmark of the reference build (build/reference/bench), built once a run, whichever of the
    self-tests that run it comes first."""
    from raykit.build import preset_build
    from kitlib.commands import bench as cmd_bench
    reference = preset_build("reference")
    ok, out = cmd_bench.build_bench(reference)
    if not ok:
        raise support.Failed(f"the benchmark does not build:\n{out[-3000:]}")
    return reference.binary_dir / "bench" / cmd_bench.TARGET


@pytest.fixture(autouse=True)
def _tier_and_rule(request, monkeypatch):
    """The quick tier's guard while a quick test runs; which test is a security test, for partly_skipped."""
    if request.node.get_closest_marker("quick") is not None:
        monkeypatch.setenv(QUICK_TIER, "1")
    support._running["security"] = request.node.get_closest_marker("security") is not None
    yield
    support._running["security"] = False


@pytest.hookimpl(tryfirst=True)
def pytest_pyfunc_call(pyfuncitem):
    """Runs a self-test and keeps the one-line summary it returns (pytest would warn about it)."""
    args = {name: pyfuncitem.funcargs[name] for name in pyfuncitem._fixtureinfo.argnames}
    summary = pyfuncitem.obj(**args)
    if isinstance(summary, str) and summary:
        pyfuncitem.user_properties.append(("summary", summary))
    return True


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """CI's rule: a security test that skips fails, unless .ci/run declares that this machine lacks
    what the skip names (support.skip_refused). The failure says the skip and why it is refused."""
    outcome = yield
    report = outcome.get_result()
    if not report.skipped or call.excinfo is None:
        return
    why = getattr(call.excinfo.value, "msg", None) or str(call.excinfo.value)
    if isinstance(report.longrepr, tuple) and isinstance(call.excinfo.value, support.Skipped):
        report.longrepr = (*report.longrepr[:2], f"Skipped: {why}")      # not "kit.support.Skipped: "
    if item.get_closest_marker("security") is None:
        return
    refused = support.skip_refused(getattr(call.excinfo.value, "need", ""), security=True)
    if refused:
        try:        # a failure as pytest reports one, its reason in the summary at the end
            raise support.Failed(f"skipped ({why}), but {refused}")
        except support.Failed:
            report.longrepr = item.repr_failure(pytest.ExceptionInfo.from_current())
        report.outcome = "failed"


def pytest_report_teststatus(report, config):
    """-v prints a passed test's summary after PASSED."""
    if report.when == "call" and report.passed and config.getoption("verbose") > 0:
        summary = dict(report.user_properties).get("summary")
        if summary:
            return "passed", ".", (f"PASSED ({summary})", {"green": True})
    return None


def pytest_terminal_summary(terminalreporter, exitstatus, config) -> None:
    """The counts in the words ./kit test has always ended with (customised.py and scripts read them)."""
    if config.option.collectonly:
        return
    stats = terminalreporter.stats
    passed = sum(1 for r in stats.get("passed", []) if getattr(r, "when", "") == "call")
    failed = len(stats.get("failed", [])) + len(stats.get("error", []))
    terminalreporter.write_line(f"selftest: {passed} passed, {failed} failed, {len(stats.get('skipped', []))} skipped")

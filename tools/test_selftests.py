"""The kit's self-test (tools/kitlib/selftest/) as Python's unittest sees it: the same self-tests
./kit test runs, collected by the harness, run by it, reported by unittest. From the kit's root:

    python3 -m unittest discover -s tools -p test_selftests.py              # all (20 minutes and more)
    python3 -m unittest discover -s tools -p test_selftests.py -k Quick     # the quick tier (./kit test --quick)
    python3 -m unittest discover -s tools -p test_selftests.py -k Step      # the step tier (./kit test --step N)
    python3 -m unittest discover -s tools -p test_selftests.py -k Draws -k roofline -v

One TestCase class per module of harness.MODULES and tier: `Check` holds check's self-tests of no
tier, `CheckQuick` those marked @tier("quick"), `CheckStep` @tier("step"), `CheckQuickStep` both;
one method per self-test, test_ and its name in snake case (its full name is the method's docstring,
which -v prints). unittest's -k is a case-sensitive substring of "test_selftests.Class.test_name"
(or an fnmatch pattern with *), so -k Quick selects the quick tier's classes and nothing else. The
suite keeps ./kit test's order (a later self-test reuses an earlier one's builds); unittest's own
loading by name (`test_selftests.CheckQuick`) sorts a class's methods instead.

The same run as ./kit test's: its packages and environment (commands/selftest.py's prepare, then
harness.prepare), one harness.Context for the whole process, each test judged by harness.judge, the
rule of security tests in CI included (a skip one may not take is a failure). A pass is unittest's
ok, a Skipped its skip (self.skipTest), a Failed, a KitError or a crash its failure (self.fail). A
quick-tier test runs with the quick tier's guard set (common.QUICK_TIER: building anything fails),
as under --quick. RAYKIT_SELFTEST_FAST=1 is --fast; RAYKIT_SELFTEST_STEP=N runs the step tier's tests
on step N alone (ctx.steps), as --step N does. ./kit test's line per self-test and its recap are
./kit test's: here unittest's report says the same.
"""

from __future__ import annotations

import os
import re
import sys
import unittest
from pathlib import Path

# What ./kit sets before the driver starts: tools/ on the path, the kit's modules compiled into its
# cache folder and nowhere beside the sources (raykit/pycache.py).
TOOLS = Path(__file__).resolve().parent
os.environ["PYTHONDONTWRITEBYTECODE"] = "1"
sys.dont_write_bytecode = True
os.environ.pop("PYTHONPYCACHEPREFIX", None)
if os.environ.get("XDG_CACHE_HOME") or os.environ.get("HOME"):
    os.environ["RAYKIT_PYCACHE"] = str(Path(os.environ.get("XDG_CACHE_HOME") or Path(os.environ["HOME"]) / ".cache")
                                       / "raykit" / "pycache")
else:
    os.environ.pop("RAYKIT_PYCACHE", None)
if str(TOOLS) not in sys.path:
    sys.path.insert(0, str(TOOLS))
os.environ["PYTHONPATH"] = os.pathsep.join([str(TOOLS)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])

from raykit import pycache  # noqa: E402

pycache.install()

from raykit.common import QUICK_TIER, KitError, load_steps  # noqa: E402
from kitlib.selftest import harness  # noqa: E402

_contexts: dict[str, harness.Context] = {}


def context(step_tier: bool) -> harness.Context:
    """The one context of the run (a step tier's test under RAYKIT_SELFTEST_STEP: the one of that
    step), made, with the run's set-up, before the first test that needs it."""
    wanted = os.environ.get("RAYKIT_SELFTEST_STEP", "").strip()
    key = wanted.zfill(2) if step_tier and wanted else ""
    if key not in _contexts:
        if not _contexts:
            from kitlib.commands import selftest as command
            command.prepare()
            harness.prepare()
        fast = os.environ.get("RAYKIT_SELFTEST_FAST", "") not in ("", "0")
        if key:
            steps = [s for s in load_steps() if s.number == key]
            if not steps:
                raise KitError(f"RAYKIT_SELFTEST_STEP={wanted}: no such step "
                               f"(the steps are {', '.join(s.number for s in load_steps())})")
            _contexts[key] = harness.Context(fast=fast, steps=steps)
        else:
            _contexts[key] = harness.Context(fast=fast)
    return _contexts[key]


class SelfTest(unittest.TestCase):
    """A self-test of the harness's collection, run by the harness."""
    module = ""
    tiers: frozenset = frozenset()

    def run_selftest(self, name: str, fn) -> None:
        try:
            ctx = context("step" in self.tiers)
        except KitError as e:
            self.fail(str(e))
        saved = os.environ.get(QUICK_TIER)
        if "quick" in self.tiers:
            os.environ[QUICK_TIER] = "1"
        try:
            harness.judged(self, ctx, fn, name)
        finally:
            if saved is None:
                os.environ.pop(QUICK_TIER, None)
            else:
                os.environ[QUICK_TIER] = saved


def class_name(module: str, tiers: frozenset) -> str:
    return "".join(w.capitalize() for w in module.split("_")) + "".join(t.capitalize() for t in harness.TIERS
                                                                          if t in tiers)


def method_name(name: str) -> str:
    return "test_" + (re.sub(r"\W+", "_", name.lower(), flags=re.ASCII).strip("_") or "unnamed")


def _method(name: str, fn):
    def test(self):
        self.run_selftest(name, fn)
    test.__doc__ = name
    return test


def build() -> list[tuple[type, str]]:
    """The classes (set in this module) and their tests, (class, method) in ./kit test's order."""
    order = []
    classes: dict[str, type] = {}
    for module in harness.MODULES:
        for name, fn in harness.collect([module]):
            tiers = harness.tiers_of(fn) & frozenset(harness.TIERS)
            cname = class_name(module, tiers)
            if cname not in classes:
                classes[cname] = type(cname, (SelfTest,), {"module": module, "tiers": tiers, "__module__": __name__,
                                                          "__doc__": f"{module}'s self-tests"
                                                          + (f" of the tiers {', '.join(sorted(tiers))}" if tiers else
                                                             " of no tier")})
                globals()[cname] = classes[cname]
            cls = classes[cname]
            method = method_name(name)
            if hasattr(cls, method):
                raise KitError(f"two self-tests of {module} read {method} in unittest: {name!r} and "
                               f"{getattr(cls, method).__doc__!r}")
            setattr(cls, method, _method(name, fn))
            order.append((cls, method))
    return order


ORDER = build()


def load_tests(loader: unittest.TestLoader, standard_tests, pattern):
    """unittest's load_tests protocol: every self-test, in ./kit test's order, those -k selects."""
    chosen = {cls: set(loader.getTestCaseNames(cls)) for cls in {cls for cls, _ in ORDER}}
    return unittest.TestSuite(cls(method) for cls, method in ORDER if method in chosen[cls])

"""Self-test of the self-test's CI rule: a skipped security test fails in CI.

conftest.py's hook knows the security tests (marked `security`: every self-test of integrity.py,
integrity_slots.py and boundary.py, and any marked so elsewhere); with CI=true a skip of one is a
failure unless it names what the machine lacks and .ci/run declares exactly that in RAYKIT_CI_CANNOT
(from .ci/cannot, which probes the machine itself and prints each reason). Shown here with forced
skips run by pytest under the suite's own conftest, and .ci/cannot against this machine's facts.
Builds nothing.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from raykit.common import ROOT
from raykit.sandbox import bwrap_works
from .support import CANNOT_ENV, NEEDS, expect

# Forced outcomes, each a security test and a plain one, run under the suite's conftest (-p kit.conftest).
FORCED = '''
import pytest
from kit.support import Failed, Skipped, partly_skipped


def forced_skip(ctx):
    raise Skipped("forced: bubblewrap is missing", need="bwrap")


def forced_part(ctx):
    return partly_skipped("root", "user skipped: forced") + "; bwrap ran"


def forced_other(ctx):
    raise Skipped("forced: no hidden cases here")


def forced_failure(ctx):
    raise Failed("the planted reason\\n" + "\\n".join(f"detail {i}" for i in range(40)))


def as_test(fn):
    def test(ctx):
        return fn(ctx)
    return test


for _name, _fn in list(globals().items()):
    if _name.startswith("forced_"):
        globals()["selftest_security_" + _name[7:]] = pytest.mark.security(as_test(_fn))
        globals()["selftest_plain_" + _name[7:]] = as_test(_fn)
'''


def forced_outcomes(tmp: Path, ci: str, cannot: str) -> tuple[dict[str, str], str]:
    """{test: PASSED/FAILED/SKIPPED} of the forced tests under CI=`ci`, RAYKIT_CI_CANNOT=`cannot`; pytest's output."""
    env = dict(os.environ, CI=ci, **{CANNOT_ENV: cannot})
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "tests"), env.get("PYTHONPATH", "")])
    r = subprocess.run([sys.executable, "-m", "pytest", "-c", str(tmp / "pytest.ini"), "--rootdir", str(tmp),
                        "-p", "kit.conftest", "-p", "no:cacheprovider", "-v", "-rfEs", str(tmp / "forced.py")],
                       cwd=tmp, capture_output=True, text=True, env=env, timeout=300)
    got = dict(re.findall(r"::(selftest_\w+) (PASSED|FAILED|SKIPPED|ERROR)", r.stdout))
    return got, r.stdout + r.stderr


@pytest.mark.quick
def selftest_security_skips(ctx) -> str:
    want = [  # (CI, RAYKIT_CI_CANNOT, test, security?, outcome)
        ("true", "", "skip", True, "FAILED"), ("true", "", "part", True, "FAILED"),
        ("true", "", "other", True, "FAILED"), ("true", "", "skip", False, "SKIPPED"),
        ("true", "bwrap", "skip", True, "SKIPPED"), ("true", "bwrap", "part", True, "FAILED"),
        ("true", "root", "part", True, "PASSED"), ("true", "root bwrap", "other", True, "FAILED"),
        ("", "", "skip", True, "SKIPPED"), ("", "", "part", True, "PASSED"),
    ]
    wrong, outputs = [], {}
    with tempfile.TemporaryDirectory(prefix="raykit-ci-rule-") as tmp:
        (Path(tmp) / "forced.py").write_text(FORCED)
        (Path(tmp) / "pytest.ini").write_text("[pytest]\npython_functions = selftest_*\n")
        for ci, cannot in dict.fromkeys((ci, cannot) for ci, cannot, *_ in want):
            got, outputs[ci, cannot] = forced_outcomes(Path(tmp), ci, cannot)
            for _, _, name, is_security, expected in (w for w in want if w[:2] == (ci, cannot)):
                test = f"selftest_{'security' if is_security else 'plain'}_{name}"
                if got.get(test) != expected:
                    wrong.append(f"CI={ci!r} {CANNOT_ENV}={cannot!r} {test}: {got.get(test)}, expected {expected}")
    expect(not wrong, "; ".join(wrong) + "\npytest said:\n" + outputs["true", ""][-3000:])
    # The refusal says the skip and why; the failures are said again after the last test (CI shows a tail).
    out = outputs["true", ""]
    tail = out[out.rindex("short test summary info"):] if "short test summary info" in out else ""
    expect("FAILED" in tail and "selftest_security_skip" in tail and "skipped (forced: bubblewrap is missing), but "
           "a security test may not skip in CI" in out and "the planted reason" in tail,
           f"the end of pytest's output does not name the refused skip and the failure: {out[-2000:]!r}")
    # Every self-test of the security modules is marked, layers' are not.
    collected = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-m", "security",
                                "-p", "no:cacheprovider", "tests/kit/"], cwd=ROOT, capture_output=True, text=True,
                               timeout=300)
    marked = set(re.findall(r"^tests/kit/(\w+)\.py::(selftest_\w+)", collected.stdout, flags=re.M))
    unmarked = []
    for module in ("integrity", "integrity_slots", "boundary"):
        text = (ROOT / "tests" / "kit" / f"{module}.py").read_text()
        unmarked += [f"{module}.{n}" for n in re.findall(r"^def (selftest_\w+)\(", text, flags=re.M)
                     if (module, n) not in marked]
    expect(marked and not unmarked, f"security tests not marked: {unmarked or collected.stdout[-1000:]}")
    expect(not any(m == "layers" for m, _ in marked), "layers' test marked security")
    # .ci/run declares what .ci/cannot finds, before ./kit test, in CI.
    run = (ROOT / ".ci" / "run").read_text()
    lines = [l.strip() for l in run.splitlines()]
    first_test = next(i for i, l in enumerate(lines) if l.startswith("./kit test"))
    expect(f'{CANNOT_ENV}="$(.ci/cannot)"' in lines[:first_test] and f"export {CANNOT_ENV}" in lines[:first_test]
           and "export CI=true" in lines[:first_test],
           f".ci/run does not set CI=true and {CANNOT_ENV} from .ci/cannot before ./kit test")
    r = subprocess.run([str(ROOT / ".ci" / "cannot")], capture_output=True, text=True, timeout=60)
    words = r.stdout.split()
    expect(r.returncode == 0 and set(words) <= set(NEEDS), f".ci/cannot: exit {r.returncode}, {r.stdout!r}")
    unsaid = [w for w in words if f"cannot: {w} (" not in r.stderr]
    expect(not unsaid, f".ci/cannot declares {unsaid} without saying why: {r.stderr!r}")
    facts = {"root": os.geteuid() != 0, "bwrap": not bwrap_works()}
    expect(all((w in words) == lacks for w, lacks in facts.items()),
           f".ci/cannot says {words}, but here: "
           + ", ".join(f"{w} {'lacking' if v else 'works'}" for w, v in facts.items()))
    return (f"{len(want)} forced skips judged as the rule says, the failures said again at the end; "
            f"{len(marked)} security tests marked; .ci/run declares .ci/cannot's {' '.join(words) or 'nothing'} "
            f"(this machine: {', '.join(w for w, v in facts.items() if not v)} work)")

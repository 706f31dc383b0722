"""Self-test of the self-test's CI rule: a skipped security test fails in CI.

The harness (harness.py) knows the security tests (every self-test of SECURITY_MODULES, or marked
with `security`); with CI=true a skip of one is a failure unless it names what the machine lacks and
.ci/run declares exactly that in RAYKIT_CI_CANNOT (from .ci/cannot, which probes the machine itself
and prints each reason). Shown here with forced skips run through the harness's own run_one, and
.ci/cannot against this machine's facts. Builds nothing.
"""

from __future__ import annotations

import contextlib
import io
import os
import subprocess

from ..common import ROOT
from ..sandbox import bwrap_works
from .harness import (CANNOT_ENV, NEEDS, SECURITY_MODULES, Skipped, collect, expect, partly_skipped, run_one,
                      security)


def forced_skip(_ctx):
    raise Skipped("forced: bubblewrap is missing", need="bwrap")


def forced_part(_ctx):
    return partly_skipped("root", "user skipped: forced") + "; bwrap ran"


def forced_other(_ctx):
    raise Skipped("forced: no hidden cases here")


def outcome(fn, env: dict[str, str]) -> str:
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            return run_one(None, fn.__name__, fn)
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def selftest_security_skips(ctx) -> str:
    secure = {f: security(lambda c, f=f: f(c)) for f in (forced_skip, forced_part, forced_other)}
    for f, s in secure.items():
        s.__name__ = f.__name__
    want = [  # (CI, RAYKIT_CI_CANNOT, test, security?, outcome)
        ("true", "", forced_skip, True, "failed"), ("true", "", forced_part, True, "failed"),
        ("true", "", forced_other, True, "failed"), ("true", "", forced_skip, False, "skipped"),
        ("true", "bwrap", forced_skip, True, "skipped"), ("true", "bwrap", forced_part, True, "failed"),
        ("true", "root", forced_part, True, "passed"), ("true", "root bwrap", forced_other, True, "failed"),
        ("", "", forced_skip, True, "skipped"), ("", "", forced_part, True, "passed"),
    ]
    wrong = []
    for ci, cannot, f, is_security, expected in want:
        got = outcome(secure[f] if is_security else f, {"CI": ci, CANNOT_ENV: cannot})
        if got != expected:
            wrong.append(f"CI={ci!r} {CANNOT_ENV}={cannot!r} {'security ' if is_security else ''}{f.__name__}: "
                         f"{got}, expected {expected}")
    expect(not wrong, "; ".join(wrong))
    # The harness marks every self-test of the security modules, and no other.
    marked = {m: [n for n, fn in collect([m]) if not getattr(fn, "security", False)] for m in SECURITY_MODULES}
    expect(not any(marked.values()), f"security tests not marked: {marked}")
    expect(not any(getattr(fn, "security", False) for _, fn in collect(["layers"])), "layers' test marked security")
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
    return (f"{len(want)} forced skips judged as the rule says; .ci/run declares .ci/cannot's "
            f"{' '.join(words) or 'nothing'} (this machine: {', '.join(w for w, v in facts.items() if not v)} work)")


def selftests():
    return [("ci: a skipped security test fails in CI", selftest_security_skips)]

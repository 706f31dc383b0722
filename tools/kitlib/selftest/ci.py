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

from raykit.common import ROOT
from raykit.sandbox import bwrap_works
from .harness import (CANNOT_ENV, NEEDS, RECAP_LINES, SECURITY_MODULES, Failed, Skipped, collect, expect,
                      partly_skipped, recap, run_one, security, tier)


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


@tier("quick")
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


@tier("quick")
def selftest_recap(_ctx) -> str:
    """CI shows the tail of a long run: every failure is said again just above the last line, with
    its reason, so the tail names what failed even when its first line scrolled away."""
    def long_failure(_c):
        raise Failed("the planted reason\n" + "\n".join(f"detail {i}" for i in range(40)))

    def a_pass(_c):
        return "fine"

    def a_crash(_c):
        raise ValueError("planted bug")
    failures: list[str] = []
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        got = [run_one(None, f.__name__, f, failures) for f in (long_failure, a_pass, a_crash, a_pass)]
        recap(failures)
    expect(got == ["failed", "passed", "failed", "passed"], f"outcomes {got}")
    text = out.getvalue()
    tail = text[text.rindex("a_pass: fine"):]
    expect("failed (2):" in tail and "long_failure: the planted reason" in tail and "a_crash: the self-test itself failed"
           in tail, f"the recap after the last test does not name both failures: {tail!r}")
    expect(f"detail {RECAP_LINES - 2}" in tail and f"detail {RECAP_LINES}" not in tail and "more lines above" in tail,
           f"the recap does not keep {RECAP_LINES} lines of a long failure: {tail!r}")
    many = io.StringIO()
    with contextlib.redirect_stdout(many):
        recap([f"✗ test {i}: reason {i}\nmore {i}\nand more {i}" for i in range(40)])
    said = many.getvalue()
    expect(all(f"test {i}: reason {i}\nmore {i}\n" in said for i in range(40)) and "and more" not in said
           and len(said.splitlines()) <= 3 * 40 + 2,
           f"40 failures: the recap does not keep two lines of each: {said[:300]!r}")
    quiet = io.StringIO()
    with contextlib.redirect_stdout(quiet):
        recap([])
    expect(quiet.getvalue() == "", f"a run without failures has a recap: {quiet.getvalue()!r}")
    return (f"2 failures of 4 said again after the last test, {RECAP_LINES} lines each at most; "
            "40 failures two lines each")


def selftests():
    return [("ci: a skipped security test fails in CI", selftest_security_skips),
            ("ci: failures said again at the end", selftest_recap)]

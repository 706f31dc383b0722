"""Self-test: the reference build and its tests under AddressSanitizer and UndefinedBehaviorSanitizer.
Last in the run: the slowest self-test, and left out by --fast."""

from __future__ import annotations

import re

from ..common import workflow
from .harness import Context, Skipped, expect, need_solutions


def selftest_sanitizers(ctx: Context) -> str:
    need_solutions()
    if ctx.fast:
        raise Skipped("--fast leaves out the sanitizer build")
    r = workflow("sanitize")
    tail = (r.stdout + r.stderr)[-4000:]
    expect(r.returncode == 0, f"the ASan + UBSan build or its tests failed:\n{tail}")
    m = re.search(r"tests passed, (\d+) tests failed out of (\d+)", r.stdout)
    expect(m is not None and int(m.group(2)) > 0, "ctest ran no test under the sanitizers")
    return f"ASan + UBSan, {m.group(2)} tests, no finding"


def selftests() -> list:
    return [("sanitizers", selftest_sanitizers)]

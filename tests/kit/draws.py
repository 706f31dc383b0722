"""Self-test: the hidden cases' draw follows a submission's code, not its comments (issue 46, item 4).

Two students with the same code, or one who only re-comments or re-indents a file, must meet the same
hidden inputs, so that one bug gets one hidden mark within a course; any change to the code itself
still draws anew. The seed is secret.hidden_seed's, here with a fixed key (no file is read or written).
"""

from __future__ import annotations

import pytest

from raykit.secret import code_only, hidden_seed
from .support import expect

KEY = bytes(range(32))

BASE = b"""// step 01, my version
#include "raykit/unit_sphere.hpp"

namespace raykit {
Roots unit_sphere_roots(const Ray& ray) {
    const float a = dot(ray.direction, ray.direction);   // |d|^2
    return solve(a, 2.0f * dot(ray.origin, ray.direction), dot(ray.origin, ray.origin) - 1.0f);
}
}
"""

# The same code: other comments, other indentation and line breaks.
SAME = [
    BASE.replace(b"// |d|^2", b"/* the squared length */"),
    BASE.replace(b"// step 01, my version\n", b""),
    BASE.replace(b"    const float", b"\tconst float").replace(b"\n}\n}", b"\n  }\n}"),
    BASE.replace(b"Roots unit_sphere_roots(const Ray& ray) {", b"Roots unit_sphere_roots(const Ray& ray)\n{"),
]
# Other code: a token changed, a string's text changed (a // inside a string is no comment).
OTHER = [
    BASE.replace(b"- 1.0f", b"- 2.0f"),
    BASE.replace(b"2.0f * dot", b"2.0f*dot"),
    BASE + b'const char* note = "a // b";\n',
]


@pytest.mark.quick
def selftest_draw_follows_code(ctx) -> str:
    seed = hidden_seed("01_unit_sphere", [BASE], key=KEY)
    for i, variant in enumerate(SAME):
        expect(code_only(variant) == code_only(BASE), f"variant {i} (comments, layout): its code reads "
                                                      f"{code_only(variant)[:80]!r}, not the original's")
        expect(hidden_seed("01_unit_sphere", [variant], key=KEY) == seed,
               f"variant {i} changes only comments or layout, yet draws other hidden inputs")
    seeds = {hidden_seed("01_unit_sphere", [v], key=KEY) for v in OTHER}
    expect(seed not in seeds and len(seeds) == len(OTHER), "a change to the code drew the same hidden inputs")
    with_string = code_only(b'const char* s = "x // y"; // gone')
    expect(with_string == b'const char* s = "x // y";', f"a // inside a string was read as a comment: {with_string!r}")
    expect(code_only(b"int a; /* never closed") == b"int a; /* never closed",
           "an unfinished comment is not kept byte for byte")
    expect(hidden_seed("01_unit_sphere", [BASE], identity="gradescope:1", key=KEY) != seed,
           "the identity no longer changes the draw")
    return (f"{len(SAME)} re-commented or re-indented copies draw as the original; {len(OTHER)} code changes "
            "each draw anew; a // in a string stays code")

"""Self-test of the ray-sphere lab (docs/lab/), in headless Chromium.

For each preset the page is loaded and its numbers are read from what it shows (the float32 inputs
beside the fields, the roots and ulps in the table, all printed with 9 digits, which read back to the
same float). A small C++ program (docs/lab/check/lab_check.cpp, built with -ffp-contract=off, linked
with the reference solution of step 02) gets the same float inputs and answers:
  - the page's exact roots equal the 113-bit roots of tests/support/reference_roots.hpp rounded to
    float, and the reference solution's sphere_roots, value for value (the count, and each root to 0
    ulps: +0 and -0 are the same root);
  - every row of the page's table, each of its four formulas in float32 and in double (the double
    rows' roots rounded to float at the end, as the page does), equals bit for bit the same formula in
    C++ (lab_check.cpp, the page's operations in its order; the float32 textbook there is the one the
    lab has always been checked against), count and roots;
  - the page's ulps, on every row, equal tests/support/ulps.hpp's ulp_distance between those roots.
  - the row the page gives to the reference (f × d in double) equals the reference solution's answer;
  - a wrong count reads as a wrong count, never as 0 ulps or 0 units: the ulps cells say "count
    differs", the caption under the picture and the case's computed line ("Here: ...") name the count
    of every row that differs from the exact one, and the exact row shows 0 ulps only where it has roots.
The picture: on the grazing and far presets the float32 textbook roots are drawn apart from the exact
ones (at least 4 px); the distance plot shows the textbook past 16 ulps beyond |f|/r = 2^12 and the
rewrite within them before, its cliff marker sits where the textbook first miscounts on each preset's line
(none where it never does), and its slider moves the origin; on the grazing and ground presets the
magnifier (the float grid around a root) shows a float32 root beyond 16 ulps; every preset keeps the
origin's handle on the picture and draws no line reaching farther than 4e6 px from it (a browser draws
in float32: farther ends move the lines); a drag turns the case into "(modified)"; at 400 px wide the
page is no wider than the window, every text of the picture and the plot is drawn 9 px or more on the
screen, and every cell of the numbers shows inside the window (none scrolled off); on every preset, at 1400 and 400 px wide, in the machine's font and in a
wider one, no two labels of the picture overlap, none is under the magnifier's box, none leaves the picture.
Also: no console error, no request to the network, a screenshot per preset in build/lab/screenshots/.
The checks can fail: a copy of the page whose textbook discriminant, or half b's, skips one float
rounding (what a fused multiply-add does) must be caught.
"""

from __future__ import annotations

import math
import shutil
import struct
import subprocess
from pathlib import Path

from raykit.common import BUILD, ROOT
from .support import Failed, Skipped, chromium_or_skip, expect, need_solutions

LAB = ROOT / "docs" / "lab"
CHECK_SOURCE = LAB / "check" / "lab_check.cpp"
OUT = BUILD / "lab"
SCREENSHOTS = OUT / "screenshots"
INPUTS = ["ox", "oy", "dx", "dy", "cx", "cy", "r"]
ROWS = ["textbook-f64", "halfb-f32", "halfb-f64", "rewrite-f32", "rewrite-f64", "lagrange-f32", "lagrange-f64"]


def f32(text: str) -> float:
    """The float32 a printed number reads back to (9 digits identify a float32)."""
    t = text.strip()
    value = {"inf": math.inf, "-inf": -math.inf, "-0": -0.0}.get(t)
    if value is None:
        try:
            value = float(t)
        except ValueError:
            raise Failed(f"the page shows {text!r} where a number belongs") from None
    return struct.unpack("<f", struct.pack("<f", value))[0]


def bits(x: float) -> int:
    return struct.unpack("<I", struct.pack("<f", x))[0]


def from_bits(b: int) -> float:
    return struct.unpack("<f", struct.pack("<I", b))[0]


def ordered(x: float) -> int:        # tests/support/ulps.hpp's ordered_bits
    b = struct.unpack("<i", struct.pack("<f", x))[0]
    return b if b >= 0 else -(2 ** 31) - b


def build_check() -> Path:
    exe = OUT / "lab_check"
    sources = [CHECK_SOURCE, ROOT / "solutions" / "02_general_sphere" / "general_sphere.cpp",
               ROOT / "tests" / "support" / "reference_roots.hpp", ROOT / "tests" / "support" / "ulps.hpp"]
    if exe.is_file() and all(exe.stat().st_mtime >= s.stat().st_mtime for s in sources):
        return exe
    OUT.mkdir(parents=True, exist_ok=True)
    cmd = ["c++", "-std=c++17", "-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-Wpedantic", "-Werror",
           f"-I{ROOT / 'include'}", f"-I{ROOT / 'tests' / 'support'}", str(sources[0]), str(sources[1]),
           "-o", str(exe)]
    r = subprocess.run(["nice", "-n", "10", *cmd], capture_output=True, text=True)
    if r.returncode != 0:
        raise Failed(f"lab_check.cpp does not build:\n{(r.stdout + r.stderr)[-1500:]}")
    return exe


def cxx_answers(exe: Path, cases: dict[str, dict]) -> dict[str, dict]:
    lines = [" ".join([name] + [f"{bits(c['inputs'][k]):08x}" for k in INPUTS]) for name, c in cases.items()]
    r = subprocess.run([str(exe)], input="\n".join(lines) + "\n", capture_output=True, text=True, timeout=60)
    if r.returncode != 0:
        raise Failed(f"lab_check exited {r.returncode}: {r.stderr.strip()}")
    out = {}
    for line in r.stdout.splitlines():
        head, sol, book, ul, *rows = line.split(" | ")
        name, _, n, t0, t1 = head.split()
        parts = {"exact": (n, t0, t1)}
        for label, text in (("solution", sol), ("textbook", book)):
            _, n2, a, b = text.split()
            parts[label] = (n2, a, b)
        answers = {k: {"count": int(v[0]), "t": [from_bits(int(v[1], 16)), from_bits(int(v[2], 16))]}
                   for k, v in parts.items()}
        answers["ulps"] = [int(u) for u in ul.split()[1:]]
        for row in rows:
            key, n, a, b, u0, u1 = row.split()
            answers[key] = {"count": int(n), "t": [from_bits(int(a, 16)), from_bits(int(b, 16))],
                            "ulps": [int(u0), int(u1)]}
        out[name] = answers
    return out


# The picture's labels, as drawn: every two texts that overlap (more than 1 px each way), every text
# over the magnifier's box that is not part of it, every text reaching out of the picture (640 x 440).
# Boxes are in the picture's coordinates, through any transform (the magnifier is moved as a group).
LAYOUT = """(() => {
  const layer = document.querySelector('#scene-layer'), toLayer = layer.getCTM().inverse();
  const box = (e) => {
    const b = e.getBBox(), m = toLayer.multiply(e.getCTM());
    const pts = [[b.x, b.y], [b.x + b.width, b.y], [b.x, b.y + b.height], [b.x + b.width, b.y + b.height]]
      .map(([x, y]) => [m.a * x + m.c * y + m.e, m.b * x + m.d * y + m.f]);
    const xs = pts.map((p) => p[0]), ys = pts.map((p) => p[1]);
    return [Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)];
  };
  const meet = (p, q) => Math.min(p[2], q[2]) - Math.max(p[0], q[0]) > 1 && Math.min(p[3], q[3]) - Math.max(p[1], q[1]) > 1;
  const labels = Array.from(layer.querySelectorAll('text')).filter((e) => e.textContent.trim());
  const boxes = labels.map(box);
  const out = { overlaps: [], outside: [], underMagnifier: [], labels: labels.length };
  labels.forEach((a, i) => labels.slice(i + 1).forEach((b, j) => {
    if (meet(boxes[i], boxes[i + 1 + j])) out.overlaps.push(a.textContent + ' / ' + b.textContent);
  }));
  labels.forEach((a, i) => {
    const p = boxes[i];
    if (p[0] < 0 || p[1] < 0 || p[2] > 640 || p[3] > 440)
      out.outside.push(a.textContent + ' at [' + p.map((v) => v.toFixed(1)).join(', ') + ']');
  });
  const mag = layer.querySelector('#magnifier rect');
  if (mag) {
    const m = box(mag);
    labels.forEach((a, i) => { if (!a.closest('#magnifier') && meet(m, boxes[i])) out.underMagnifier.push(a.textContent); });
  }
  return out;
})()"""

# On a narrow screen: every text of the picture and of the distance plot, as drawn on the screen (font
# size times the drawing's scale), the plot's texts inside it, and every cell of the numbers that shows
# inside the window and not cut (the table scrolls no column off the screen).
READABLE = """(() => {
  const out = { small: [], outPlot: [], offCells: [], cut: [] };
  for (const e of document.querySelectorAll('#scene text, #distance-plot text')) {
    if (!e.textContent.trim()) continue;
    const svg = e.ownerSVGElement, k = svg.clientWidth / svg.viewBox.baseVal.width;
    const px = parseFloat(getComputedStyle(e).fontSize) * k;
    if (px < 9) out.small.push(e.textContent + ' ' + px.toFixed(1) + ' px');
  }
  const plot = document.querySelector('#distance-plot'), vb = plot.viewBox.baseVal;
  for (const e of plot.querySelectorAll('text')) {
    if (e.getAttribute('transform')) continue;       // the rotated axis title
    const b = e.getBBox();
    if (b.x < 0 || b.y < 0 || b.x + b.width > vb.width || b.y + b.height > vb.height) out.outPlot.push(e.textContent);
  }
  for (const c of document.querySelectorAll('#numbers th, #numbers td')) {
    const r = c.getBoundingClientRect();
    if (!r.width) continue;                           // not shown (the narrow screen's header row)
    if (r.left < -0.5 || r.right > innerWidth + 0.5) out.offCells.push((c.dataset.label || c.textContent.slice(0, 20)) + ': ' + c.textContent.slice(0, 20));
    if (c.scrollWidth > c.clientWidth + 1) out.cut.push(c.textContent.slice(0, 20));
  }
  const box = document.querySelector('.table-box');
  if (box.scrollWidth > box.clientWidth + 1) out.offCells.push('the table scrolls: ' + box.scrollWidth + ' px in ' + box.clientWidth);
  return out;
})()"""

# A font wider than the machine's: the layout must measure what it draws, not assume a font.
WIDE_FONT = ("(() => { const s = document.createElement('style'); s.id = 'wide-font';"
             " s.textContent = '#scene text { font-family: monospace !important; letter-spacing: 1px; }';"
             " document.head.appendChild(s); })()")


def layout_problems(b, where: str) -> tuple[list[str], int]:
    """Loads every preset (each button of the page) and checks its labels: no two overlap, none under the
    magnifier, none out of the picture. The problems, and how many presets were checked."""
    problems = []
    presets = b.evaluate("raykitLab.presets")
    buttons = b.evaluate("Array.from(document.querySelectorAll('#presets button'), (e) => e.dataset.preset)")
    if sorted(presets) != sorted(buttons):
        problems.append(f"{where}: the presets checked {presets} are not the page's buttons {buttons}")
    for name in presets:
        b.evaluate(f"raykitLab.load({name!r})")
        got = b.evaluate(LAYOUT)
        if got["overlaps"]:
            problems.append(f"{where}, {name}: labels overlap in the picture: {got['overlaps'][:3]}")
        if got["underMagnifier"]:
            problems.append(f"{where}, {name}: labels under the magnifier's box: {got['underMagnifier'][:3]}")
        if got["outside"]:
            problems.append(f"{where}, {name}: labels out of the picture: {got['outside'][:3]}")
    return problems, len(presets)


READ = """(() => {
  const text = (sel) => { const e = document.querySelector(sel); return e ? e.textContent : null; };
  const cell = (id) => text(`[data-cell="${id}"]`);
  const out = { inputs: {}, exact: {}, textbook: {}, others: {} };
  for (const k of %s) out.inputs[k] = text(`#f32-${k}`);
  out.exact = { count: cell('exact-count'), t0: cell('exact-t0'), t1: cell('exact-t1') };
  out.textbook = { count: cell('textbook-f32-count'), t0: cell('textbook-f32-t0'), t1: cell('textbook-f32-t1'),
                   u0: cell('textbook-f32-u0'), u1: cell('textbook-f32-u1') };
  out.rows = {};
  for (const key of %s) out.rows[key] = { count: cell(`${key}-count`), t0: cell(`${key}-t0`), t1: cell(`${key}-t1`),
                                          u0: cell(`${key}-u0`), u1: cell(`${key}-u1`) };
  out.caseName = text('#case-name'); out.section = text('#case-section');
  out.gap = text('#float-gap'); out.verdict = text('#case-verdict');
  out.exactUlps = [cell('exact-u0'), cell('exact-u1')];
  // the picture: the origin's handle on it, the float32 textbook roots' distance from the exact ones,
  // and any two labels that overlap
  const o = document.querySelector('#handle-origin');
  out.originOn = [+o.getAttribute('cx'), +o.getAttribute('cy')].every((v, i) => v >= 0 && v <= [640, 440][i]);
  out.magnifier = raykitLab.magnifier();
  // every coordinate drawn lies near the picture: a browser draws in float32, so an end 10^10 px away
  // puts the line hundreds of pixels off where it crosses the picture
  out.farthest = 0;          // over lines and polygons that cross the picture: their farthest point
  for (const e of document.querySelectorAll('#scene-layer line, #scene-layer polygon')) {
    const n = e.tagName === 'polygon' ? e.getAttribute('points').split(/[ ,]+/).map(Number)
      : ['x1', 'y1', 'x2', 'y2'].map((k) => +e.getAttribute(k));
    const pts = [];
    for (let i = 0; i + 1 < n.length; i += 2) pts.push([n[i], n[i + 1]]);
    const inside = pts.some(([x, y]) => x > -50 && x < 690 && y > -50 && y < 490);
    const long = e.tagName === 'line' && Math.hypot(n[2] - n[0], n[3] - n[1]) > 1000;   // it may cross the picture
    if (!inside && !long) continue;
    for (const [x, y] of pts) out.farthest = Math.max(out.farthest, Math.abs(x), Math.abs(y));
  }
  out.textbookPx = Math.max(0, ...raykitLab.marks().filter((m) => m.form === 'textbook').map((m) => m.px));
  out.layout = %s;
  out.overlaps = out.layout.overlaps;
  out.svg = document.querySelectorAll('#scene-layer *').length;
  return out;
})()""" % (str(INPUTS), str(ROWS), LAYOUT)


def attach_log(b) -> list[str]:
    """Every console message of level error and every uncaught exception, from now on."""
    errors: list[str] = []
    original = b._dispatch

    def dispatch(message: dict) -> None:
        method, p = message.get("method"), message.get("params", {})
        if method == "Runtime.exceptionThrown":
            d = p.get("exceptionDetails", {})
            errors.append(d.get("exception", {}).get("description") or d.get("text", "exception"))
        elif method == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            errors.append(" ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", [])))
        elif method == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
            errors.append(p["entry"].get("text", "log error"))
        original(message)

    b._dispatch = dispatch
    b.call("Runtime.enable", session=True)
    b.call("Log.enable", session=True)
    return errors


def read_presets(b, page: Path, shots: bool) -> tuple[dict, list[str]]:
    """Loads `page` and each of its presets; the numbers it shows, and the problems seen."""
    problems = []
    errors = attach_log(b)
    b.open(page.as_uri())
    expect(b.evaluate("document.body.dataset.ready") == "1", f"{page}: the lab did not start")
    presets = b.evaluate("raykitLab.presets")
    cases = {}
    for name in presets:
        b.evaluate(f"raykitLab.load({name!r})")
        shown = b.evaluate(READ)
        if not shown["caseName"] or not shown["section"] or "ecture" not in shown["section"]:
            problems.append(f"{name}: the preset names no case or lecture section")
        if shown["svg"] < 2:
            problems.append(f"{name}: the picture has nothing drawn")
        c = {"inputs": {k: f32(v) for k, v in shown["inputs"].items()}}
        c["exact"] = {"count": int(shown["exact"]["count"]),
                      "t": [f32(shown["exact"][k]) for k in ("t0", "t1")] if shown["exact"]["t0"] != "—" else []}
        tb = shown["textbook"]
        c["textbook"] = {"count": int(tb["count"]), "t": [f32(tb[k]) for k in ("t0", "t1")] if tb["t0"] != "—" else [],
                         "ulps": [tb["u0"], tb["u1"]]}
        c["rows"] = {}
        for key, row in shown["rows"].items():
            c["rows"][key] = {"count": int(row["count"]),
                              "t": [f32(row[k]) for k in ("t0", "t1")] if row["t0"] != "—" else [],
                              "ulps": [row["u0"], row["u1"]]}
        c["picture"] = {"originOn": shown["originOn"], "textbookPx": shown["textbookPx"], "overlaps": shown["overlaps"],
                        "magnifier": shown["magnifier"]}
        c["words"] = {"gap": shown["gap"] or "", "verdict": shown["verdict"] or "", "exactUlps": shown["exactUlps"]}
        if shown["farthest"] > 4e6:          # float32 spacing there: half a pixel
            problems.append(f"{name}: the picture draws a point {shown['farthest']:.3g} px away, where a browser's "
                            "float32 puts what crosses the picture pixels off")
        if not shown["originOn"]:
            problems.append(f"{name}: the origin's handle is off the picture, where no one can drag it")
        if shown["overlaps"]:
            problems.append(f"{name}: labels overlap in the picture: {shown['overlaps'][:3]}")
        if shown["layout"]["underMagnifier"]:
            problems.append(f"{name}: labels under the magnifier's box: {shown['layout']['underMagnifier'][:3]}")
        if shown["layout"]["outside"]:
            problems.append(f"{name}: labels out of the picture: {shown['layout']['outside'][:3]}")
        cases[name] = c
        if shots:
            b.screenshot(SCREENSHOTS / f"{name}.png")
    offline = [u for u in b.requests if not u.startswith(("file:", "data:", "about:"))]
    if offline:
        problems.append(f"asks the network for {offline[:3]}")
    if errors:
        problems.append(f"console errors: {errors[:3]}")
    return cases, problems


def compare(cases: dict, cxx: dict) -> tuple[list[str], int]:
    problems, roots = [], 0
    for name, page in cases.items():
        want = cxx[name]
        ex = page["exact"]
        for ref in ("exact", "solution"):
            w = want[ref]
            if ex["count"] != w["count"]:
                problems.append(f"{name}: the page's exact count {ex['count']}, {ref} {w['count']}")
                continue
            n = {0: 0, 1: 1, 2: 2}[w["count"]]
            for i in range(n):
                if ordered(ex["t"][i]) != ordered(w["t"][i]):
                    problems.append(f"{name}: exact t{i} is {ex['t'][i]!r} on the page, {w['t'][i]!r} from the "
                                    f"{'113-bit reference_roots.hpp' if ref == 'exact' else 'reference solution'}")
                roots += ref == "exact"
        tb, wb = page["textbook"], want["textbook"]
        if tb["count"] != wb["count"]:
            problems.append(f"{name}: the float32 textbook count is {tb['count']} on the page, {wb['count']} in C++")
        else:
            for i in range(wb["count"]):
                if bits(tb["t"][i]) != bits(wb["t"][i]):
                    problems.append(f"{name}: the float32 textbook t{i} is {tb['t'][i]!r} "
                                    f"(0x{bits(tb['t'][i]):08x}) on the page, {wb['t'][i]!r} "
                                    f"(0x{bits(wb['t'][i]):08x}) in C++ with -ffp-contract=off")
            u = want["ulps"]
            if wb["count"] and u[0] >= 0:
                shown = tb["ulps"]
                if shown != [str(u[0]), str(u[1])]:
                    problems.append(f"{name}: the page shows {shown} ulps for the textbook roots, ulps.hpp says {u}")
        for key in ROWS:
            pr, wr = page["rows"][key], want[key]
            if pr["count"] != wr["count"]:
                problems.append(f"{name}: the {key} count is {pr['count']} on the page, {wr['count']} in C++")
                continue
            for i in range(wr["count"]):
                if bits(pr["t"][i]) != bits(wr["t"][i]):
                    problems.append(f"{name}: {key} t{i} is {pr['t'][i]!r} (0x{bits(pr['t'][i]):08x}) on the page, "
                                    f"{wr['t'][i]!r} (0x{bits(wr['t'][i]):08x}) in C++ with -ffp-contract=off")
            if wr["count"] and wr["ulps"][0] >= 0 and pr["ulps"] != [str(u) for u in wr["ulps"]]:
                problems.append(f"{name}: the page shows {pr['ulps']} ulps on the {key} row, ulps.hpp says {wr['ulps']}")
            elif wr["count"] and wr["ulps"][0] < 0 and pr["ulps"] != ["count differs", "count differs"]:
                problems.append(f"{name}: the {key} row's count differs from the exact one and the page shows {pr['ulps']}")
            roots += wr["count"]
        # The row the page gives to the reference (f x d in double) is what the reference solution returns.
        pr, sol = page["rows"]["lagrange-f64"], want["solution"]
        if pr["count"] != sol["count"] or any(bits(pr["t"][i]) != bits(sol["t"][i]) for i in range(sol["count"])):
            problems.append(f"{name}: the reference's row (f × d, double) shows {pr['count']} root(s) {pr['t']}, the "
                            f"reference solution returns {sol['count']} {sol['t'][:sol['count']]}")
        problems += word_problems(name, page)
    return problems, roots


FORM_SHORT = {"textbook": "textbook", "halfb": "half b", "rewrite": "rewrite", "lagrange": "f × d"}
FORM_NAME = {"textbook": "textbook", "halfb": "half b", "rewrite": "leg + root pair", "lagrange": "f × d"}


def word_problems(name: str, page: dict) -> list[str]:
    """A wrong count reads as a wrong count, never as 0 ulps or 0 units: in the ulps cells (compare), in the
    caption under the picture (float32 rows) and in the case's computed line (every row); the exact row shows
    0 ulps only where it has a root."""
    problems, n = [], page["exact"]["count"]
    words = page.get("words", {})
    gap, verdict = words.get("gap", ""), words.get("verdict", "")
    if f"exact count {n}." not in verdict:
        problems.append(f"{name}: the case's line does not give the exact count {n}: {verdict!r}")
    for key, row in [("textbook-f32", page["textbook"]), *page["rows"].items()]:
        form, kind = key.split("-")
        if row["count"] == n:
            continue
        part = verdict.split(f"{'float32' if kind == 'f32' else 'double'}:", 1)[-1]
        if f"{FORM_SHORT[form]} {row['count']} root" not in part or "wrong count" not in part:
            problems.append(f"{name}: {key} counts {row['count']} where the exact count is {n}, and the case's line "
                            f"does not say so: {verdict!r}")
        if kind == "f32" and f"{FORM_NAME[form]} {row['count']} root" not in gap:
            problems.append(f"{name}: {key} counts {row['count']} where the exact count is {n}, and the caption "
                            f"does not say so: {gap!r}")
    want = ["0", "0"] if n else ["—", "—"]
    if words.get("exactUlps") != want:
        problems.append(f"{name}: the exact row shows {words.get('exactUlps')} ulps with {n} root(s)")
    return problems


def selftest_lab(ctx) -> str:
    need_solutions()
    if not CHECK_SOURCE.is_file():
        raise Skipped("docs/lab/check/ is not here (a handout leaves it out)")
    browser, chromium = chromium_or_skip()
    exe = build_check()
    try:
        with browser.Browser(chromium, 1400, 1000) as b:
            cases, problems = read_presets(b, LAB / "index.html", shots=True)
            b.evaluate(WIDE_FONT)
            found, _ = layout_problems(b, "in a wider font (monospace, 1 px apart)")
            problems += found
    except browser.BrowserError as e:
        raise Failed(f"headless Chromium: {e}") from None
    cxx = cxx_answers(exe, cases)
    found, roots = compare(cases, cxx)
    problems += found
    for name in ("grazing", "ground"):
        mag = cases.get(name, {}).get("picture", {}).get("magnifier") or {}
        if not mag.get("ulps", 0) > 16:
            problems.append(f"{name}: the magnifier shows no float32 root beyond 16 ulps ({mag})")
    for name in ("grazing", "far-1000", "far-10000"):
        px = cases.get(name, {}).get("picture", {}).get("textbookPx", 0)
        if px < 4:
            problems.append(f"{name}: the float32 textbook roots are drawn {px:.1f} px from the exact ones, "
                            "too close to see (the float error does not show in the picture)")
    try:
        with browser.Browser(chromium, 400, 900) as b:
            b.open((LAB / "index.html").as_uri())
            # The distance plot, on the far preset's line: the textbook past the ★ bound beyond the cliff
            # (|f|/r = 2^12), lecture 03's rewrite within it before 10^4; the slider moves the origin.
            b.evaluate("raykitLab.load('far-10000')")
            series = b.evaluate("raykitLab.plot()") or {}
            book = [u for v, u in series.get("textbook", []) if 3.7 <= v <= 5]
            rew = [u for v, u in series.get("rewrite", []) if v <= 3.6]
            if not book or min(u if u is not None else math.inf for u in book) <= 16:
                problems.append(f"the distance plot shows the textbook within 16 ulps beyond the cliff: {book[:5]}")
            if not rew or max(u if u is not None else math.inf for u in rew) > 16:
                problems.append(f"the distance plot shows the rewrite beyond 16 ulps before 10^3.6: {rew[-5:]}")
            # The cliff marker, computed for each preset's line: where the textbook first gets the count
            # wrong, between that sample and the one before (no marker when it never does), not fixed at
            # |f|/r = 4096.
            cliffs = []
            for name in b.evaluate("raykitLab.presets"):
                b.evaluate(f"raykitLab.load({name!r})")
                pts = [(v, math.inf if u is None else u) for v, u in (b.evaluate("raykitLab.plot()") or {}).get("textbook", [])]
                xs = b.evaluate("Array.from(document.querySelectorAll('#distance-plot .plot-cliff'), (e) => +e.getAttribute('x1'))")
                width = b.evaluate("document.querySelector('#distance-plot').viewBox.baseVal.width")
                marks = [(x - 44) / (width - 44 - 10) * 7 for x in xs]       # the plot's X(v), inverted
                first = next((i for i, (_, u) in enumerate(pts) if u == math.inf), None)
                if first is None:
                    if marks:
                        problems.append(f"{name}: the distance plot marks a cliff at 10^{marks[0]:.2f} where the textbook "
                                        "never gets the count wrong")
                    continue
                lo = pts[first - 1][0] if first else -math.inf
                hi = pts[first][0]
                cliffs.append(f"{name} 10^{marks[0]:.2f}" if marks else f"{name} none")
                if len(marks) != 1 or not lo - 0.005 < marks[0] <= hi + 0.005:
                    problems.append(f"{name}: the distance plot's cliff marker is at 10^{marks[0] if marks else None}, "
                                    f"the textbook first gets the count wrong between 10^{lo:.2f} and 10^{hi:.2f}")
            b.evaluate("raykitLab.load('far-10000')")
            b.evaluate("(() => { const s = document.querySelector('#log-distance'); s.value = '2';"
                       " s.dispatchEvent(new Event('input')); })()")
            far = b.evaluate("(() => { const s = raykitLab.inputs(); return Math.hypot(s.ox - s.cx, s.oy - s.cy) / s.r; })()")
            if not 90 < far < 110:
                problems.append(f"the distance slider set to 10^2 put the origin {far} radii away")
            # The float32 textbook roots apart from the exact ones on the narrow screen too, in screen pixels.
            for name in ("grazing", "far-1000", "far-10000"):
                b.evaluate(f"raykitLab.load({name!r})")
                px = b.evaluate("(() => { const svg = document.querySelector('#scene-layer').ownerSVGElement;"
                                " const k = svg.getBoundingClientRect().width / svg.viewBox.baseVal.width;"
                                " return k * Math.max(0, ...raykitLab.marks().filter((m) => m.form === 'textbook')"
                                ".map((m) => m.px)); })()") or 0
                if px < 2:
                    problems.append(f"{name}: at 400 px wide the float32 textbook roots are drawn {px:.1f} screen px "
                                    "from the exact ones, too close to see")
            found, _ = layout_problems(b, "at 400 px wide")
            problems += found
            for name in b.evaluate("raykitLab.presets"):
                b.evaluate(f"raykitLab.load({name!r})")
                r = b.evaluate(READABLE)
                if r["small"]:
                    problems.append(f"at 400 px wide, {name}: text drawn under 9 px on the screen: {r['small'][:3]}")
                if r["outPlot"]:
                    problems.append(f"at 400 px wide, {name}: text out of the distance plot: {r['outPlot'][:3]}")
                if r["offCells"]:
                    problems.append(f"at 400 px wide, {name}: {len(r['offCells'])} cells of the numbers off the screen: "
                                    f"{r['offCells'][:3]}")
                if r["cut"]:
                    problems.append(f"at 400 px wide, {name}: cells of the numbers cut: {r['cut'][:3]}")
            b.evaluate(WIDE_FONT)
            found, _ = layout_problems(b, "at 400 px wide in a wider font")
            problems += found
            b.evaluate("document.getElementById('wide-font').remove()")
            for name in ("grazing", "ground"):
                b.evaluate(f"raykitLab.load({name!r})")
                wide = b.evaluate("document.documentElement.scrollWidth")
                if wide > 400:
                    problems.append(f"at 400 px wide the page lays out {wide} px ({name})")
                b.screenshot(SCREENSHOTS / f"{name}-400px.png")
    except browser.BrowserError as e:
        raise Failed(f"headless Chromium: {e}") from None
    expect(len(cases) >= 9, f"only {len(cases)} presets")
    expect(not problems, "\n  ".join(problems))
    far = cases.get("far-10000")
    note = ""
    if far and far["textbook"]["count"] != far["exact"]["count"]:
        note = f"; at 10^4 radii the float32 textbook finds {far['textbook']['count']} root(s), the exact {far['exact']['count']}"
    graze = cases.get("grazing", {}).get("picture", {}).get("textbookPx", 0)
    return (f"{len(cases)} presets, {roots} roots: the exact ones equal reference_roots.hpp and the reference solution, "
            f"all 8 rows (4 formulas, float32 and double) bit for bit as C++ -ffp-contract=off, ulps as ulps.hpp{note}; "
            f"grazing: the float32 textbook roots drawn {graze:.1f} px from the exact ones; origin on the picture in "
            f"every preset, no label over another, under the magnifier or out of the picture (at 1400 and 400 px, "
            f"in the machine's font and a wider one); the cliff marker, where the textbook first miscounts: "
            f"{', '.join(cliffs)}; no wider than 400 px at 400 px, every text there 9 px or more and every cell of the "
            f"numbers on the screen, and the float roots apart there too; "
            f"screenshots in {SCREENSHOTS.relative_to(ROOT)}")


def selftest_lab_keyboard(ctx) -> str:
    """Without a mouse: Tab reaches a handle, the arrow keys move it, typing sets a value exactly; and a drag."""
    browser, chromium = chromium_or_skip()

    def key(b, name: str, code: int) -> None:
        for kind in ("rawKeyDown", "keyUp"):
            b.call("Input.dispatchKeyEvent", session=True, type=kind, key=name, code=name,
                   windowsVirtualKeyCode=code)

    try:
        with browser.Browser(chromium, 1280, 1000) as b:
            errors = attach_log(b)
            b.open((LAB / "index.html").as_uri())
            b.evaluate("raykitLab.load('two-hits')")
            before = b.evaluate("raykitLab.inputs()")
            b.evaluate("document.querySelector('#handle-centre').focus()")
            key(b, "ArrowUp", 38)
            key(b, "ArrowRight", 39)
            after = b.evaluate("raykitLab.inputs()")
            expect(after["cy"] > before["cy"] and after["cx"] > before["cx"],
                   f"the arrow keys did not move the focused centre handle: {before} -> {after}")
            expect(after["ox"] == before["ox"], "the arrow keys moved a handle that was not selected")
            # Typing: the radius field, a value that is not a float, shown rounded to float32.
            b.evaluate("(() => { const i = document.querySelector('#in-r'); i.focus(); i.value = '0.1';"
                       " i.dispatchEvent(new Event('input')); })()")
            shown = b.evaluate("document.querySelector('#f32-r').textContent")
            expect(shown == "0.100000001", f"typing r = 0.1 shows {shown!r} as its float32, not 0.100000001")
            # Tab order: from the origin handle, Tab reaches the direction's tip.
            b.evaluate("document.querySelector('#handle-origin').focus()")
            key(b, "Tab", 9)
            focused = b.evaluate("document.activeElement && document.activeElement.id")
            expect(focused == "handle-tip", f"Tab from the origin handle went to {focused!r}")
            # And with a mouse: drag the radius handle 40 px to the right.
            b.evaluate("raykitLab.load('two-hits')")
            x, y = b.evaluate("(() => { const r = document.querySelector('#handle-radius').getBoundingClientRect();"
                              " return [r.left + r.width / 2, r.top + r.height / 2]; })()")
            r0 = b.evaluate("raykitLab.inputs().r")
            for kind, px, buttons in (("mousePressed", x, 1), ("mouseMoved", x + 20, 1), ("mouseMoved", x + 40, 1),
                                      ("mouseReleased", x + 40, 0)):
                b.call("Input.dispatchMouseEvent", session=True, type=kind, x=px, y=y, button="left",
                       buttons=buttons, clickCount=1)
            r1 = b.evaluate("raykitLab.inputs().r")
            expect(r1 > r0, f"dragging the radius handle 40 px outwards left r at {r0} (now {r1})")
            case = b.evaluate("document.querySelector('#case-name').textContent")
            expect(case.endswith("(modified)"), f"after a drag the case still reads {case!r}, not \"... (modified)\"")
            # The far preset: the origin waits at the picture's edge, and a drag of it moves it by the pointer's movement.
            b.evaluate("raykitLab.load('far-10000')")
            o0 = b.evaluate("raykitLab.inputs()")
            x, y = b.evaluate("(() => { const r = document.querySelector('#handle-origin').getBoundingClientRect();"
                              " return [r.left + r.width / 2, r.top + r.height / 2]; })()")
            for kind, py, buttons in (("mousePressed", y, 1), ("mouseMoved", y + 10, 1), ("mouseMoved", y + 20, 1),
                                      ("mouseReleased", y + 20, 0)):
                b.call("Input.dispatchMouseEvent", session=True, type=kind, x=x, y=py, button="left",
                       buttons=buttons, clickCount=1)
            o1 = b.evaluate("raykitLab.inputs()")
            moved = math.hypot(o1["ox"] - o0["ox"], o1["oy"] - o0["oy"])
            expect(0 < moved < 1, f"dragging the far preset's origin 20 px moved it by {moved} units "
                                  f"(from ({o0['ox']}, {o0['oy']}) to ({o1['ox']}, {o1['oy']}))")
            expect(not errors, f"console errors: {errors[:3]}")
    except browser.BrowserError as e:
        raise Failed(f"headless Chromium: {e}") from None
    return (f"a drag of the radius handle sets r {r0:g} -> {r1:.4g} and the case reads \"(modified)\"; on the 10^4 "
            f"preset a 20 px drag of the origin, waiting at the picture's edge, moves it {moved:.3g} units; arrow keys move the focused handle (centre: "
            f"({before['cx']:g}, {before['cy']:g}) -> ({after['cx']:.3g}, {after['cy']:.3g})), Tab walks the handles, "
            "typed r = 0.1 shows its float32 0.100000001")


def selftest_lab_catches(ctx) -> str:
    """A lab whose textbook discriminant skips a rounding (a fused multiply-add) must fail the check."""
    need_solutions()
    if not CHECK_SOURCE.is_file():
        raise Skipped("docs/lab/check/ is not here (a handout leaves it out)")
    browser, chromium = chromium_or_skip()
    exe = build_check()
    wrong = OUT / "wrong-lab"
    shutil.rmtree(wrong, ignore_errors=True)
    shutil.copytree(LAB, wrong, ignore=shutil.ignore_patterns("check"))
    js = (wrong / "lab.js").read_text(encoding="utf-8")
    caught = []
    # The textbook's discriminant, and half b's (a row the check once left out), each with one rounding skipped.
    for row, line, slip in (("textbook", "const disc = R(R(b * b) - R(R(4 * a) * c));", "const disc = R(b * b - R(4 * a) * c);"),
                            ("halfb-f32", "const d4 = R(R(h * h) - R(a * c));", "const d4 = R(h * h - R(a * c));")):
        fused = js.replace(line, slip)
        expect(fused != js, f"docs/lab/lab.js no longer has the line this test changes: {line}")
        (wrong / "lab.js").write_text(fused, encoding="utf-8")
        try:
            with browser.Browser(chromium, 1280, 1000) as b:
                cases, _ = read_presets(b, wrong / "index.html", shots=False)
        except browser.BrowserError as e:
            raise Failed(f"headless Chromium: {e}") from None
        found = [p for p in compare(cases, cxx_answers(exe, cases))[0] if row in p]
        expect(found, f"a lab that fuses the {row} discriminant passed the check")
        caught.append(found[0])
    return "a lab with a fused discriminant fails, on the textbook row and on half b's: " + "; ".join(caught)


def selftest_browser_restart(ctx) -> str:
    """A Chromium that never answers its first command is started again, not waited on for ever."""
    browser, chromium = chromium_or_skip()
    OUT.mkdir(parents=True, exist_ok=True)
    count = OUT / "fake-chromium-starts"
    count.unlink(missing_ok=True)
    fake = OUT / "fake-chromium"
    # The first start stays silent on the DevTools pipe (a hung start); the second is the real Chromium.
    fake.write_text("#!/bin/sh\n"
                    f"echo start >> '{count}'\n"
                    f"if [ \"$(wc -l < '{count}')\" -eq 1 ]; then exec sleep 600; fi\n"
                    f"exec '{chromium}' \"$@\"\n", encoding="utf-8")
    fake.chmod(0o755)
    try:
        with browser.Browser(str(fake), 400, 300, first_answer_timeout=3) as b:
            value = b.evaluate("6 * 7")
            attempts = b.attempts
    except browser.BrowserError as e:
        raise Failed(f"a Chromium that hung once was not started again: {e}") from None
    starts = len(count.read_text().splitlines())
    expect(value == 42 and attempts == 2 and starts == 2,
           f"value {value!r}, attempts {attempts}, starts {starts} (expected 42 on the second of 2)")
    return "a start that never answered was ended and the second start used (2 starts, the page evaluated 6*7 = 42)"

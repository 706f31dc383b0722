// The ray-sphere lab: a 2D cross-section (the plane through the ray and the centre) whose handles
// can be dragged, typed and moved with the arrow keys, and the numbers of every formula of lectures
// 01-03, in float32 and in double, with their error in ulps against the exact roots of the same
// float inputs.
//
// Float32 arithmetic: Math.fround after every operation, which is what C++ computes for float
// without FMA contraction (-ffp-contract=off): each +, -, *, / and sqrt of two floats is correctly
// rounded, and rounding the exact double result of a float operation to float gives the correctly
// rounded float result (double has more than 2 * 24 + 2 bits).
//
// Exact roots: every input is a float, a dyadic rational m 2^e, so a, h and c' are integers times a
// common power of two, and so is the discriminant h^2 - a c'. BigInt holds them exactly. A root
// (-h -+ sqrt(D)) / a is irrational in general; its nearest float is found by comparing the root
// exactly with the midpoints between floats (squaring both sides: integers only).
"use strict";

(function () {
  const F = Math.fround;

  // --- floats as bits, ordered as in tests/support/ulps.hpp ----------------------------------------
  const buf = new DataView(new ArrayBuffer(8));
  function bitsOf(x) { buf.setFloat32(0, x); return buf.getInt32(0); }
  function fromBits(b) { buf.setInt32(0, b | 0); return buf.getFloat32(0); }
  function hexBits(x) { return "0x" + (bitsOf(x) >>> 0).toString(16).padStart(8, "0"); }
  const INT32_MIN = -2147483648;
  function ordered(x) { const b = bitsOf(x); return b >= 0 ? b : INT32_MIN - b; }
  function fromOrdered(n) { return fromBits(n >= 0 ? n : INT32_MIN - n); }
  // ulp_distance(a, b) of tests/support/ulps.hpp; Infinity for NaN (the C++ gives int64's max).
  function ulps(a, b) {
    if (Number.isNaN(a) || Number.isNaN(b)) return Infinity;
    return Math.abs(ordered(a) - ordered(b));
  }

  // --- exact arithmetic on floats --------------------------------------------------------------------
  // A finite float as [m, e] with x = m 2^e, m a BigInt.
  function dyadic(x) {
    if (x === 0) return [0n, 0];
    buf.setFloat64(0, x);
    const hi = buf.getUint32(0), lo = buf.getUint32(4);
    const sign = hi >>> 31 ? -1n : 1n;
    const bexp = (hi >>> 20) & 0x7ff;
    let m = (BigInt(hi & 0xfffff) << 32n) | BigInt(lo);
    let e;
    if (bexp === 0) { e = -1074; } else { m |= 1n << 52n; e = bexp - 1075; }
    return [sign * m, e];
  }
  const babs = (x) => (x < 0n ? -x : x);
  const bsign = (x) => (x > 0n ? 1 : x < 0n ? -1 : 0);

  // The exact quadratic of |o + t d - c|^2 = r^2 for float inputs (z = 0 in the plane), as
  // integers A, H, C, D = H^2 - A C with a = A 2^(2E) etc.: the roots (-H -+ sqrt D) / A.
  function exactQuadratic(s) {
    const vals = [s.ox, s.oy, s.dx, s.dy, s.cx, s.cy, s.r].map(dyadic);
    let E = Infinity;
    for (const [m, e] of vals) if (m !== 0n) E = Math.min(E, e);
    if (E === Infinity) E = 0;
    const I = vals.map(([m, e]) => m << BigInt(e - E));
    const [ox, oy, dx, dy, cx, cy, r] = I;
    const fx = ox - cx, fy = oy - cy;
    const A = dx * dx + dy * dy, H = fx * dx + fy * dy, C = fx * fx + fy * fy - r * r;
    return { A, H, C, D: H * H - A * C, E };
  }

  // The sign of root - m, with root = (-H + sg sqrt D) / A (A > 0, D >= 0) and m = M 2^k exactly.
  function compareRoot(q, sg, M, k) {
    // root - m has the sign of sg sqrt(D) - (m A + H); scale by 2^max(0,-k) to stay integer.
    let R, D = q.D;
    if (k >= 0) R = (M << BigInt(k)) * q.A + q.H;
    else { const s = BigInt(-k); R = M * q.A + (q.H << s); D = D << (2n * s); }
    const sq = bsign(D - R * R);        // sign of sqrt(D) - |R|
    if (sg > 0) return R < 0n ? 1 : sq;
    return R > 0n ? -1 : -sq;
  }
  function compareRootFloat(q, sg, x) {       // sign of root - x for a float x
    if (x === Infinity) return -1;
    if (x === -Infinity) return 1;
    const [m, e] = dyadic(x);
    return compareRoot(q, sg, m, e);
  }
  function midpoint(x, y) {               // (x + y) / 2 exactly, as [M, k]
    const [m1, e1] = dyadic(x), [m2, e2] = dyadic(y);
    const e = Math.min(e1, e2);
    return [(m1 << BigInt(e1 - e)) + (m2 << BigInt(e2 - e)), e - 1];
  }
  // The float nearest the root (ties to even), starting from a guess.
  function roundRoot(q, sg, guess) {
    let n = ordered(F(Number.isFinite(guess) ? guess : 0));
    const MAXO = ordered(3.4028234663852886e38);
    const clampO = (v) => Math.max(-MAXO, Math.min(MAXO, v));
    // Bracket: lo <= root <= hi with floats lo, hi, by galloping, then bisect.
    let step = 1, lo, hi;
    if (compareRootFloat(q, sg, fromOrdered(n)) >= 0) {
      lo = n; hi = clampO(n + step);
      while (hi < MAXO && compareRootFloat(q, sg, fromOrdered(hi)) > 0) { lo = hi; step *= 2; hi = clampO(hi + step); }
    } else {
      hi = n; lo = clampO(n - step);
      while (lo > -MAXO && compareRootFloat(q, sg, fromOrdered(lo)) < 0) { hi = lo; step *= 2; lo = clampO(lo - step); }
    }
    while (hi - lo > 1) {
      const mid = Math.floor((lo + hi) / 2);
      if (compareRootFloat(q, sg, fromOrdered(mid)) >= 0) lo = mid; else hi = mid;
    }
    if (lo === hi) return fromOrdered(lo);
    const a = fromOrdered(lo), b = fromOrdered(hi);
    if (compareRootFloat(q, sg, a) === 0) return a;
    const [M, k] = midpoint(a, b);
    const c = compareRoot(q, sg, M, k);
    if (c < 0) return a;
    if (c > 0) return b;
    return (ordered(a) & 1) === 0 ? a : b;    // a tie: the even one
  }
  const P2 = (e) => Math.pow(2, e);
  function exactRoots(s) {
    const q = exactQuadratic(s);
    const out = { q, count: 0, t: [], a: Number(q.A) * P2(2 * q.E), h: Number(q.H) * P2(2 * q.E),
                  c: Number(q.C) * P2(2 * q.E), d4: Number(q.D) * P2(4 * q.E) };
    if (!(s.r > 0) || !Number.isFinite(s.r) || q.A <= 0n || q.D < 0n) return out;
    // A double guess; the rounding above makes it exact.
    const a = Number(q.A), h = Number(q.H), sd = Math.sqrt(Number(q.D));
    const scaleGuess = (v) => (Number.isFinite(v) ? v : 0);
    if (q.D === 0n) { out.count = 1; const t = roundRoot(q, 1, scaleGuess(-h / a)); out.t = [t, t]; return out; }
    out.count = 2;
    out.t = [roundRoot(q, -1, scaleGuess((-h - sd) / a)), roundRoot(q, 1, scaleGuess((-h + sd) / a))];
    return out;
  }

  // --- the formulas, in float32 (R = fround) or double (R = identity) -------------------------------
  // Vectors are 3D with z = 0, the same operations in the same order as the C++ with glm::vec3.
  const id = (x) => x;
  function vec(R, s) {
    return { o: [s.ox, s.oy, 0], d: [s.dx, s.dy, 0], c: [s.cx, s.cy, 0], r: s.r };
  }
  function sub3(R, u, v) { return [R(u[0] - v[0]), R(u[1] - v[1]), R(u[2] - v[2])]; }
  function dot3(R, u, v) { return R(R(R(u[0] * v[0]) + R(u[1] * v[1])) + R(u[2] * v[2])); }
  function scale3(R, k, v) { return [R(k * v[0]), R(k * v[1]), R(k * v[2])]; }
  function cross3(R, u, v) {
    return [R(R(u[1] * v[2]) - R(v[1] * u[2])), R(R(u[2] * v[0]) - R(v[2] * u[0])),
            R(R(u[0] * v[1]) - R(v[0] * u[1]))];
  }
  function copysign(x, y) { return (y < 0 || Object.is(y, -0)) ? -Math.abs(x) : Math.abs(x); }
  function countOf(disc) { return disc > 0 ? 2 : disc === 0 ? 1 : 0; }   // NaN: 0
  function sorted(t0, t1) {
    if (Number.isNaN(t0) || Number.isNaN(t1)) return null;
    return t0 > t1 ? [t1, t0] : [t0, t1];
  }
  function result(a, h, c, d4, count, t) {
    if (count === 0 || t === null) return { a, h, c, d4, count: 0, t: [] };
    return { a, h, c, d4, count, t };
  }

  // Lecture 01: b = 2 f.d, b^2 - 4 a c', t = (-b -+ sqrt(b^2 - 4 a c')) / 2a.
  function textbook(R, s) {
    const v = vec(R, s), f = sub3(R, v.o, v.c);
    const a = dot3(R, v.d, v.d);
    const b = R(2 * dot3(R, f, v.d));
    const c = R(dot3(R, f, f) - R(v.r * v.r));
    const disc = R(R(b * b) - R(R(4 * a) * c));
    const h = R(b / 2), d4 = R(disc / 4);
    if (!(a > 0) || !(s.r > 0)) return result(a, h, c, d4, 0, null);
    const n = countOf(disc);
    if (n === 0) return result(a, h, c, d4, 0, null);
    const sq = R(Math.sqrt(disc)), den = R(2 * a);
    if (n === 1) { const t = R(R(-b) / den); return result(a, h, c, d4, 1, [t, t]); }
    return result(a, h, c, d4, 2, sorted(R(R(-b - sq) / den), R(R(-b + sq) / den)));
  }
  // Lecture 01, section 3: the half b, h = f.d, D/4 = h^2 - a c', t = (-h -+ sqrt(D/4)) / a.
  function halfB(R, s) {
    const v = vec(R, s), f = sub3(R, v.o, v.c);
    const a = dot3(R, v.d, v.d), h = dot3(R, f, v.d);
    const c = R(dot3(R, f, f) - R(v.r * v.r));
    const d4 = R(R(h * h) - R(a * c));
    if (!(a > 0) || !(s.r > 0)) return result(a, h, c, d4, 0, null);
    const n = countOf(d4);
    if (n === 0) return result(a, h, c, d4, 0, null);
    if (n === 1) { const t = R(R(-h) / a); return result(a, h, c, d4, 1, [t, t]); }
    const sq = R(Math.sqrt(d4));
    return result(a, h, c, d4, 2, sorted(R(R(-h - sq) / a), R(R(-h + sq) / a)));
  }
  // Lecture 03, sections 5 and 6: D/4 = a (r^2 - |f - (h/a) d|^2), then q = -(h + sign(h) sqrt),
  // t = q / a and c' / q.
  function rewrite(R, s) {
    const v = vec(R, s), f = sub3(R, v.o, v.c);
    const a = dot3(R, v.d, v.d), h = dot3(R, f, v.d);
    const c = R(dot3(R, f, f) - R(v.r * v.r));
    if (!(a > 0) || !(s.r > 0)) return result(a, h, c, NaN, 0, null);
    const leg = sub3(R, f, scale3(R, R(h / a), v.d));
    const d4 = R(a * R(R(v.r * v.r) - dot3(R, leg, leg)));
    const n = countOf(d4);
    if (n === 0) return result(a, h, c, d4, 0, null);
    if (n === 1) { const t = R(R(-h) / a); return result(a, h, c, d4, 1, [t, t]); }
    const qq = R(-R(h + copysign(R(Math.sqrt(d4)), h)));
    return result(a, h, c, d4, 2, sorted(R(qq / a), R(c / qq)));
  }
  // Lagrange's identity D/4 = a r^2 - |f x d|^2, then t = (-h -+ sqrt(D/4)) / a. The reference
  // (solutions/02) computes exactly this in double, rounding each root to float at the end: the
  // double row is the reference's answer. The float32 row is the same formula in float32, which the
  // reference never computes.
  function lagrange(R, s) {
    const v = vec(R, s), f = sub3(R, v.o, v.c);
    const a = dot3(R, v.d, v.d), h = dot3(R, f, v.d);
    const c = R(dot3(R, f, f) - R(v.r * v.r));
    if (!(a > 0) || !(s.r > 0)) return result(a, h, c, NaN, 0, null);
    const g = cross3(R, f, v.d);
    const d4 = R(R(a * R(v.r * v.r)) - dot3(R, g, g));
    const n = countOf(d4);
    if (n === 0) return result(a, h, c, d4, 0, null);
    if (n === 1) { const t = R(R(-h) / a); return result(a, h, c, d4, 1, [t, t]); }
    const sq = R(Math.sqrt(d4));
    return result(a, h, c, d4, 2, sorted(R(R(-h - sq) / a), R(R(-h + sq) / a)));
  }
  const FORMS = [
    { id: "textbook", name: "textbook", where: "lecture 01, §3", fn: textbook, side: -1, short: "textbook" },
    { id: "halfb", name: "half b", where: "lecture 01, §3", fn: halfB, side: -1, short: "half b" },
    { id: "rewrite", name: "leg + root pair", where: "lecture 03, §5–6", fn: rewrite, side: 1, short: "rewrite" },
    { id: "lagrange", name: "f × d", where: "lecture 03, §5; in double, solutions/02", fn: lagrange, side: 1, short: "f × d" },
  ];

  // --- presets: the graded cases (in the plane of the drawing) --------------------------------------
  // The far and grazing cases of tests/01_unit_sphere/test_robust.cpp aim from a 3D origin; here the
  // origin is put in the plane at the same distance, and the ray passes the centre at the same offset.
  function shot2d(ox, oy, missBy, length) {
    const n = Math.hypot(ox, oy), sx = -oy / n, sy = ox / n;     // at right angles to o
    const wx = missBy * sx - ox, wy = missBy * sy - oy, w = Math.hypot(wx, wy);
    return { ox, oy, dx: length * wx / w, dy: length * wy / w };
  }
  const UNIT = { cx: 0, cy: 0, r: 1 };
  const THROUGH = { ox: -3, oy: 0, dx: 1, dy: 0 };
  const PRESETS = [
    { id: "two-hits", title: "Two hits through the centre", kase: "two hits: a ray through the centre enters at t = 2 and leaves at t = 4",
      section: "Lecture 01, §4. What the discriminant says", s: { ...THROUGH, ...UNIT, tmin: 0, tmax: Infinity } },
    { id: "tangent", title: "Tangent", kase: "one hit: a tangent ray touches the sphere once",
      section: "Lecture 01, §4. What the discriminant says", s: { ox: -2, oy: 1, dx: 1, dy: 0, ...UNIT, tmin: 0, tmax: Infinity } },
    { id: "inside", title: "Origin inside", kase: "origin inside but off centre",
      section: "Lecture 01, §3. The quadratic's coefficients", s: { ox: 0.5, oy: 0, dx: 1, dy: 0, ...UNIT, tmin: 0, tmax: Infinity } },
    { id: "behind", title: "Sphere behind", kase: "sphere behind the ray: both roots negative",
      section: "Lecture 01, §5. The closest root in a window", s: { ox: 3, oy: 0, dx: 1, dy: 0, ...UNIT, tmin: 0, tmax: Infinity } },
    { id: "at-tmin", title: "A root exactly at tmin", kase: "window: a root exactly at tmin counts",
      section: "Lecture 01, §5. The closest root in a window", s: { ...THROUGH, ...UNIT, tmin: 2, tmax: 10 } },
    { id: "before-tmin", title: "Near root before tmin", kase: "window: the near root before tmin gives the far root",
      section: "Lecture 01, §5. The closest root in a window", s: { ...THROUGH, ...UNIT, tmin: 3, tmax: 10 } },
    { id: "far-1000", title: "1000 radii away", kase: "the unit sphere seen from 1000 units away (★, in the plane)",
      section: "Lecture 01, §6. Far and grazing rays; lecture 03, §5", s: { ...shot2d(600, -800, 0.6, 1), ...UNIT, tmin: 0, tmax: Infinity } },
    { id: "far-10000", title: "10⁴ radii away", kase: "the unit sphere seen from 10000 units away (★, in the plane)",
      section: "Lecture 01, §6. Far and grazing rays; lecture 03, §5", s: { ...shot2d(6000, -8000, 0.6, 1), ...UNIT, tmin: 0, tmax: Infinity } },
    { id: "grazing", title: "Grazing", kase: "grazing rays near the silhouette of the unit sphere (★, in the plane)",
      section: "Lecture 01, §6. Far and grazing rays; lecture 03, §5", s: { ...shot2d(-960, 200, 0.99, 1), ...UNIT, tmin: 0, tmax: Infinity } },
    { id: "near-root", title: "Tiny root beside a big one", kase: "a tiny root beside a large one (lecture 03's example, in the plane)",
      section: "Lecture 03, §6. Cancellation in the roots", s: { ox: 0.5, oy: 1001, dx: 0, dy: -1, cx: 0, cy: 0, r: 1000, tmin: 0, tmax: Infinity } },
    { id: "ground", title: "The ground from 1 m", kase: "the ground seen from a metre or two up (★ of step 02, in the plane): c′ = f·f − r² cancels",
      section: "Lecture 03, §6 (its last paragraph) and the appendix, §A and §D", view: "near",
      s: { ox: 0, oy: 1, dx: 1, dy: -0.1, cx: 0, cy: -6.4e6, r: 6.4e6, tmin: 0, tmax: Infinity } },
    { id: "pbrt-ranges", title: "pbrt's ranges: 10⁶ away, r = 0.01",
      kase: "a tiny sphere seen from very far on pbrt's test ranges (★ of step 02, in the plane): a float direction cannot aim this finely",
      section: "Lecture 02, §7 The robust cases; lecture 03's appendix, §A", s: { ...shot2d(6e5, -8e5, 0.003, 1), cx: 0, cy: 0, r: 0.01, tmin: 0, tmax: Infinity } },
    { id: "zero-direction", title: "Zero direction", kase: "a zero direction is no ray: no roots",
      section: "Lecture 01, §2. The ray meets the sphere", s: { ox: 0.5, oy: 0, dx: 0, dy: 0, ...UNIT, tmin: 0, tmax: Infinity } },
  ];

  // --- state ----------------------------------------------------------------------------------------
  const FIELDS = ["ox", "oy", "dx", "dy", "cx", "cy", "r", "tmin", "tmax"];
  const state = {};          // the float32 inputs
  let view = { cx: 0, cy: 0, scale: 60 };   // world point at the picture's centre, pixels per unit
  let zoom = "fit";
  const W = 640, H = 440;
  const $ = (sel) => document.querySelector(sel);

  function fmt(x) {
    if (x === undefined) return "";
    if (Number.isNaN(x)) return "NaN";
    if (x === Infinity) return "inf";
    if (x === -Infinity) return "-inf";
    if (Object.is(x, -0)) return "-0";
    return String(Number(x.toPrecision(9)));     // 9 digits: every float32 reads back to itself
  }
  function fmtD(x) {           // a double, 17 digits
    if (!Number.isFinite(x) || x === 0) return fmt(x);
    return String(Number(x.toPrecision(17)));
  }
  function parse(text) {
    const t = text.trim().toLowerCase().replace(/\s+/g, "").replace("∞", "inf");
    if (t === "inf" || t === "+inf" || t === "infinity") return Infinity;
    if (t === "-inf" || t === "-infinity") return -Infinity;
    if (!/^[-+]?(\d+\.?\d*|\.\d+)(e[-+]?\d+)?$/.test(t)) return NaN;
    return Number(t);
  }

  let preset = null;        // the preset loaded last, and its float inputs: "(modified)" once the state leaves them
  function modified() {
    return preset !== null && FIELDS.some((k) => !Object.is(state[k], preset.inputs[k]));
  }
  function set(values, fromTyping) {
    for (const k of FIELDS) if (k in values) state[k] = F(values[k]);
    for (const k of FIELDS) {
      const input = $(`#in-${k}`);
      if (!fromTyping || document.activeElement !== input) input.value = fmt(state[k]);
      input.removeAttribute("aria-invalid");
      $(`#f32-${k}`).textContent = fmt(state[k]);
      $(`#f32-${k}`).title = `float32 bits ${hexBits(state[k])}`;
    }
    update();
  }

  // --- the numbers ----------------------------------------------------------------------------------
  function cell(id, text, cls) {
    for (const el of document.querySelectorAll(`[data-cell="${id}"]`)) {
      el.textContent = text;
      el.className = cls || "";
    }
  }
  function compute() {
    const ex = exactRoots(state);
    const out = { exact: ex, forms: {} };
    for (const form of FORMS) {
      out.forms[form.id] = { f32: form.fn(F, state), f64: form.fn(id, state) };
    }
    return out;
  }
  function closestInWindow(roots) {
    for (const t of roots.t.slice(0, roots.count === 1 ? 1 : 2)) if (state.tmin <= t && t <= state.tmax) return t;
    return null;
  }
  // What each row gets here, computed from the rows themselves: a wrong count is said as a wrong count
  // (never as an error in ulps), a right one with its worst root in ulps.
  function rowVerdict(r, ex) {
    if (r.count !== ex.count) return `${r.count} root${r.count === 1 ? "" : "s"} (wrong count)`;
    if (!ex.count) return "no root, right";
    let u = 0;
    for (let i = 0; i < ex.count; i++) u = Math.max(u, ulps(F(r.t[i]), ex.t[i]));
    return u === Infinity ? "NaN" : `worst root ${u} ulp${u === 1 ? "" : "s"}`;
  }
  function caseVerdict(res) {
    const ex = res.exact;
    const part = (p) => FORMS.map((form) => `${form.short} ${rowVerdict(res.forms[form.id][p], ex)}`).join(", ");
    return `exact count ${ex.count}. float32: ${part("f32")}. double: ${part("f64")}.`;
  }
  function showNumbers(res) {
    const ex = res.exact;
    cell("exact-a", fmtD(ex.a)); cell("exact-h", fmtD(ex.h)); cell("exact-c", fmtD(ex.c)); cell("exact-d4", fmtD(ex.d4));
    cell("exact-count", String(ex.count));
    cell("exact-t0", ex.count ? fmt(ex.t[0]) : "—"); cell("exact-t1", ex.count ? fmt(ex.t[1]) : "—");
    cell("exact-u0", ex.count ? "0" : "—"); cell("exact-u1", ex.count ? "0" : "—");
    const hit = closestInWindow(ex);
    cell("exact-hit", hit === null ? "no hit" : fmt(hit));
    for (const form of FORMS) {
      for (const p of ["f32", "f64"]) {
        const r = res.forms[form.id][p], key = `${form.id}-${p}`;
        const show = p === "f32" ? fmt : fmtD;
        cell(`${key}-a`, show(r.a)); cell(`${key}-h`, show(r.h)); cell(`${key}-c`, show(r.c)); cell(`${key}-d4`, show(r.d4));
        cell(`${key}-count`, String(r.count), r.count === ex.count ? "" : "bad");
        for (const i of [0, 1]) {
          if (!r.count) { cell(`${key}-t${i}`, "—"); cell(`${key}-u${i}`, "—"); continue; }
          const t = F(r.t[i]);            // a kit function returns float: the double forms round at the end
          cell(`${key}-t${i}`, fmt(t));
          if (r.count !== ex.count) { cell(`${key}-u${i}`, "count differs", "bad"); continue; }
          const u = ulps(t, ex.t[i]);
          cell(`${key}-u${i}`, u === Infinity ? "NaN" : String(u), u > 16 ? "bad" : u > 1 ? "warn" : "good");
        }
      }
    }
    const far = Math.hypot(state.ox - state.cx, state.oy - state.cy) / (state.r || 1);
    $("#distance").textContent = `|f| / r = ${fmt(F(far))}`;
    $("#case-verdict").textContent = caseVerdict(res);
  }

  // --- the picture ----------------------------------------------------------------------------------
  const NS = "http://www.w3.org/2000/svg";
  const sx = (x) => W / 2 + (x - view.cx) * view.scale;
  const sy = (y) => H / 2 - (y - view.cy) * view.scale;
  const wx = (px) => view.cx + (px - W / 2) / view.scale;
  const wy = (py) => view.cy - (py - H / 2) / view.scale;
  function el(tag, attrs, parent, text) {
    const e = document.createElementNS(NS, tag);
    for (const k in attrs) e.setAttribute(k, attrs[k]);
    if (text !== undefined) e.textContent = text;
    (parent || $("#scene-layer")).appendChild(e);
    return e;
  }
  function fit() {
    const pts = [[state.ox, state.oy], [state.ox + state.dx, state.oy + state.dy]];
    const r = Number.isFinite(state.r) && state.r > 0 ? state.r : 0;
    pts.push([state.cx - r, state.cy - r], [state.cx + r, state.cy + r]);
    // The window's ends too, when they are finite and not far beyond the rest.
    const near = Math.hypot(state.ox - state.cx, state.oy - state.cy) + r + Math.hypot(state.dx, state.dy);
    for (const t of [state.tmin, state.tmax]) {
      const px = state.ox + t * state.dx, py = state.oy + t * state.dy;
      if (Number.isFinite(px) && Number.isFinite(py) && Math.hypot(px - state.ox, py - state.oy) < 4 * near) pts.push([px, py]);
    }
    let xs = pts.map((p) => p[0]), ys = pts.map((p) => p[1]);
    if (zoom === "sphere") { xs = [state.cx - 1.6 * r, state.cx + 1.6 * r]; ys = [state.cy - 1.6 * r, state.cy + 1.6 * r]; }
    if (zoom === "near") {       // the origin and the first root: for a sphere too big to show whole
      const ex = exactRoots(state), t = ex.count ? ex.t[0] : 1;
      const px = state.ox + t * state.dx, py = state.oy + t * state.dy;
      const s = 0.15 * Math.hypot(px - state.ox, py - state.oy) + 1e-6;
      xs = [state.ox - s, px + s]; ys = [state.oy + s, py - s];
    }
    const x0 = Math.min(...xs), x1 = Math.max(...xs), y0 = Math.min(...ys), y1 = Math.max(...ys);
    const span = Math.max((x1 - x0) / (W - 160), (y1 - y0) / (H - 100), 1e-30);
    view = { cx: (x0 + x1) / 2, cy: (y0 + y1) / 2, scale: 1 / span };
    if (!Number.isFinite(view.scale) || !Number.isFinite(view.cx) || !Number.isFinite(view.cy)) view = { cx: 0, cy: 0, scale: 60 };
  }
  // The ray's points for t in [t0, t1], clipped to the picture.
  // Clipped to the picture in world coordinates (in double) before any pixel is computed: an end
  // 10^10 px away would be drawn hundreds of pixels off (a browser draws in float32).
  function clipped(x0, y0, dx, dy, t0, t1) {
    const box = [[x0, dx, wx(-20), wx(W + 20)], [y0, dy, wy(H + 20), wy(-20)]];
    let a = t0, b = t1;
    for (const [p, d, lo, hi] of box) {
      if (d === 0) { if (p < lo || p > hi) return null; continue; }
      let ta = (lo - p) / d, tb = (hi - p) / d;
      if (ta > tb) [ta, tb] = [tb, ta];
      a = Math.max(a, ta); b = Math.min(b, tb);
    }
    if (!(a <= b)) return null;
    return [sx(x0 + a * dx), sy(y0 + a * dy), sx(x0 + b * dx), sy(y0 + b * dy)];
  }
  function raySegment(t0, t1) {
    const len = Math.hypot(state.dx, state.dy);
    if (!(len > 0)) return null;
    return clipped(state.ox, state.oy, state.dx, state.dy, t0, t1);
  }
  function segment(cls, x0, y0, x1, y1) {       // the world segment from (x0, y0) to (x1, y1), clipped
    const s = clipped(x0, y0, x1 - x0, y1 - y0, 0, 1);
    if (s) el("line", { x1: s[0], y1: s[1], x2: s[2], y2: s[3], class: cls });
  }
  // Labels never overlap, whatever font the machine draws them in: each text is measured as drawn
  // (getBBox, after its class has set the font), then takes the first of its spots whose box meets
  // nothing already placed and lies inside the picture; when none of them is free, spots on rings
  // farther and farther out, with a leader line back to what it names; no label for what is off the
  // picture. What is placed first wins: the handles, the roots and their ticks, the magnifier, the
  // roots' labels, lecture 03's figure.
  let placed = [];
  const EDGE = 2;              // a label keeps this far from the picture's edge
  function overlapArea(box) {
    let area = 0;
    for (const q of placed)
      area += Math.max(0, Math.min(box[2], q[2]) - Math.max(box[0], q[0])) * Math.max(0, Math.min(box[3], q[3]) - Math.max(box[1], q[1]));
    return area;
  }
  function outsideBy(box) {
    return Math.max(0, EDGE - box[0]) + Math.max(0, box[2] - (W - EDGE)) + Math.max(0, EDGE - box[1]) + Math.max(0, box[3] - (H - EDGE));
  }
  // The box a text draws at (0, 0), anchored at its start: its offset from the anchor and its size.
  function measure(e) {
    e.setAttribute("x", 0); e.setAttribute("y", 0); e.setAttribute("text-anchor", "start");
    const b = e.getBBox();
    return { dx: b.x, dy: b.y, w: b.width, h: b.height };
  }
  function label(spots, text, cls, anchorPoint) {
    let [ax, ay] = anchorPoint || (spots.length ? spots[0] : [W / 2, H / 2]);
    if (!(ax >= 0 && ax <= W && ay >= 0 && ay <= H)) return null;     // what it names is off the picture
    const e = el("text", { class: cls || "label" }, undefined, text);
    const m = measure(e);
    const boxAt = (x, y, anchor) => {
      const x0 = x + m.dx - (anchor === "end" ? m.w : anchor === "middle" ? m.w / 2 : 0), y0 = y + m.dy;
      return [x0 - 2, y0 - 1, x0 + m.w + 2, y0 + m.h + 1];
    };
    let best = null;
    const tryAt = (x, y, anchor) => {
      const box = boxAt(x, y, anchor);
      const cost = overlapArea(box) + 1000 * outsideBy(box);
      if (best === null || cost < best.cost) best = { cost, x, y, anchor, box };
      return cost === 0;
    };
    let free = spots.some(([x, y, anchor]) => tryAt(x, y, anchor));
    // Rings around the point, farther and farther out: the box's centre on the ring.
    for (let r = 14; !free && r < Math.hypot(W, H); r += 6) {
      const n = Math.max(12, Math.round(r / 4));
      for (let k = 0; k < n && !free; k++) {
        const th = -Math.PI / 2 + (2 * Math.PI * k) / n;
        const cx = ax + r * Math.cos(th), cy = ay + r * Math.sin(th);
        free = tryAt(cx - m.w / 2 - m.dx, cy - m.h / 2 - m.dy, "start");
      }
    }
    e.setAttribute("x", best.x); e.setAttribute("y", best.y); e.setAttribute("text-anchor", best.anchor || "start");
    const b = best.box;
    const nx = Math.max(b[0], Math.min(b[2], ax)), ny = Math.max(b[1], Math.min(b[3], ay));
    if (Math.hypot(nx - ax, ny - ay) > 24) {        // far from what it names: a leader line to it
      const lead = el("line", { x1: ax, y1: ay, x2: nx, y2: ny, class: "leader" });
      e.parentNode.insertBefore(lead, e);
    }
    placed.push(best.box);
    return e;
  }
  // Spots around a point: right, left, below, above, then further out.
  const around = (x, y, d = 8) => [[x + d, y - d], [x - d, y - d, "end"], [x + d, y + d + 10], [x - d, y + d + 10, "end"],
                                   [x - 4, y - 2.2 * d, "middle"], [x - 4, y + 2.2 * d + 10, "middle"],
                                   [x + 3 * d, y - 3 * d], [x - 3 * d, y + 3 * d + 10, "end"], [x + 3 * d, y + 3 * d + 10],
                                   [x - 3 * d, y - 3 * d, "end"]];
  // Lines of text no wider than `most` pixels, in the class `cls`: the pieces joined by `sep`, as
  // many on a line as fit when measured.
  function wrapText(pieces, sep, cls, most, parent) {
    const probe = el("text", { class: cls }, parent, "");
    const width = (s) => { probe.textContent = s; return probe.getBBox().width; };
    const lines = [];
    for (const p of pieces) {
      const last = lines.length ? lines[lines.length - 1] : null;
      if (last !== null && width(last + sep + p) <= most) lines[lines.length - 1] = last + sep + p;
      else lines.push(p);
    }
    probe.remove();
    return lines;
  }
  // The magnifier: the float32 grid around the exact root that the float32 forms miss most, each form's
  // root drawn on it in ulps (one tick a float when they fit, else a scale). Its texts are measured and
  // wrapped to the picture's width; the box goes to the corner of the picture that covers the fewest of
  // the handles, the roots and their ticks, before any label is placed.
  let lastMagnifier = null;
  function magnifier(res) {
    lastMagnifier = null;
    const ex = res.exact;
    if (!ex.count) return;
    let worst = { i: 0, u: 0 };
    for (const form of FORMS) {
      const r = res.forms[form.id].f32;
      if (r.count !== ex.count) continue;
      for (let i = 0; i < ex.count; i++) {
        const u = ulps(F(r.t[i]), ex.t[i]);
        if (Number.isFinite(u) && u > worst.u) worst = { i, u };
      }
    }
    const M = Math.max(4, Math.ceil(worst.u * 1.25));             // ulps each side
    const shown = [];
    const ticks = [];
    for (const form of FORMS) {
      const r = res.forms[form.id].f32;
      if (r.count !== ex.count) continue;
      const t = F(r.t[worst.i]), o = ordered(t) - ordered(ex.t[worst.i]);
      if (!Number.isFinite(o)) continue;
      ticks.push([form, Math.max(-M, Math.min(M, o))]);
      shown.push(`${form.short} ${o > 0 ? "+" : ""}${o}`);
    }
    const name = ex.count === 1 ? "t" : `t${worst.i}`;
    const gm = el("g", { id: "magnifier" });
    const rect = el("rect", { x: 0, y: 0, width: 0, height: 0, class: "mag-box" }, gm);
    const PAD = 6, most = W - 2 * 10 - 2 * PAD;
    const title = wrapText([`${name} magnified, ±${M} ulps:`, M <= 40 ? "a tick per float" : `a tick per ${Math.pow(10, Math.floor(Math.log10(M)))} ulps`],
                           " ", "mag-text", most, gm);
    const forms = shown.length ? wrapText(shown, " · ", "mag-text", most, gm) : ["no float32 form has this count"];
    // Lay the texts out from the box's top left at (0, 0), line under line, as measured.
    const texts = [];
    let y = PAD, wMax = 0;
    const line = (s) => {
      const e = el("text", { class: "mag-text" }, gm, s), m = measure(e);
      e.setAttribute("x", PAD - m.dx); e.setAttribute("y", y - m.dy);
      texts.push(e); y += m.h; wMax = Math.max(wMax, m.w);
    };
    title.forEach(line);
    const axis = y + 18;                 // the float marks reach 14 px either side of the axis
    y = axis + 18;
    forms.forEach(line);
    const Wm = Math.min(W - 20, Math.max(250, wMax + 2 * PAD)), Hm = y + PAD;
    const mid = Wm / 2;
    const px = (u) => mid + (u / M) * (Wm / 2 - 12);
    el("line", { x1: 8, y1: axis, x2: Wm - 8, y2: axis, class: "mag-axis" }, gm);
    if (M <= 40) {
      for (let u = -M; u <= M; u++) el("line", { x1: px(u), y1: axis - 4, x2: px(u), y2: axis + 4, class: "mag-tick" }, gm);
    } else {
      const stepU = Math.pow(10, Math.floor(Math.log10(M)));
      for (let u = -Math.floor(M / stepU) * stepU; u <= M; u += stepU)
        el("line", { x1: px(u), y1: axis - 5, x2: px(u), y2: axis + 5, class: "mag-tick" }, gm);
    }
    el("circle", { cx: mid, cy: axis, r: 4, class: "root" }, gm);
    for (const [form, o] of ticks)
      el("line", { x1: px(o), y1: axis, x2: px(o), y2: axis + form.side * 14, class: `float-mark mark-${form.id}` }, gm);
    rect.setAttribute("width", Wm); rect.setAttribute("height", Hm);
    // The corner that covers least of what is placed so far (top left when it is free).
    const corners = [[10, 10], [W - 10 - Wm, 10], [10, H - 10 - Hm], [W - 10 - Wm, H - 10 - Hm]];
    let at = corners[0], least = Infinity;
    for (const [x, y0] of corners) {
      const c = overlapArea([x, y0, x + Wm, y0 + Hm]);
      if (c < least) { least = c; at = [x, y0]; }
      if (c === 0) break;
    }
    gm.setAttribute("transform", `translate(${at[0]} ${at[1]})`);
    placed.push([at[0], at[1], at[0] + Wm, at[1] + Hm]);
    lastMagnifier = { root: worst.i, ulps: worst.u, span: M, box: [at[0], at[1], at[0] + Wm, at[1] + Hm] };
  }
  function draw(res) {
    const g = $("#scene-layer");
    while (g.firstChild) g.removeChild(g.firstChild);
    placed = [];
    for (const k in HANDLES) {       // no label under a handle
      const [x, y] = HANDLES[k].get(), [hx, hy] = clampToPicture(sx(x), sy(y));
      placed.push([hx - 10, hy - 10, hx + 10, hy + 10]);
    }
    const ex = res.exact;
    const pr = Math.max(state.r * view.scale, 2);
    // the sphere
    if (pr < 1e5 || !Number.isFinite(pr)) {
      el("circle", { cx: sx(state.cx), cy: sy(state.cy), r: Number.isFinite(pr) ? pr : 0, class: "sphere" });
    } else {     // a circle of more than 10^5 px: the browser draws it badly; draw the arc that crosses the picture
      const th = Math.atan2(view.cy - state.cy, view.cx - state.cx), span = 2 * Math.hypot(W, H) / pr;
      const pts = [];
      for (let i = 0; i <= 64; i++) {
        const a = th - span + (2 * span * i) / 64;
        pts.push([sx(state.cx + state.r * Math.cos(a)), sy(state.cy + state.r * Math.sin(a))]);
      }
      const inward = [Math.cos(th), -Math.sin(th)], far = 4 * Math.hypot(W, H);    // in pixels, y down
      const end = pts[pts.length - 1], start = pts[0];
      pts.push([end[0] - inward[0] * far, end[1] - inward[1] * far], [start[0] - inward[0] * far, start[1] - inward[1] * far]);
      el("polygon", { points: pts.map((q) => q.join(",")).join(" "), class: "sphere" });
    }
    el("circle", { cx: sx(state.cx), cy: sy(state.cy), r: 3, class: "centre-dot" });
    // the whole line, then the window [tmin, tmax] on it
    const line = raySegment(-Infinity, Infinity);
    if (line) el("line", { x1: line[0], y1: line[1], x2: line[2], y2: line[3], class: "line" });
    const ray = raySegment(0, Infinity);
    if (ray) el("line", { x1: ray[0], y1: ray[1], x2: ray[2], y2: ray[3], class: "ray" });
    const win = raySegment(state.tmin, state.tmax);
    if (win) el("line", { x1: win[0], y1: win[1], x2: win[2], y2: win[3], class: "window" });
    // lecture 03's figure: L = c - o, the closest point at t_m, l_m at a right angle, the half chord dt
    const a = state.dx * state.dx + state.dy * state.dy;
    const figLabels = [];        // placed after the roots' labels, which matter more
    if (a > 0) {
      const len = Math.sqrt(a), ux = state.dx / len, uy = state.dy / len;
      const Lx = state.cx - state.ox, Ly = state.cy - state.oy;
      const tmLen = Lx * ux + Ly * uy;                // t_m as a length along the unit direction
      const px = state.ox + tmLen * ux, py = state.oy + tmLen * uy;
      segment("fig-L", state.ox, state.oy, state.cx, state.cy);
      segment("fig-lm", state.cx, state.cy, px, py);
      const lm = Math.hypot(state.cx - px, state.cy - py);
      // the right angle at the closest point
      if (lm * view.scale > 14) {
        const k = 9 / view.scale, nx = (state.cx - px) / lm, ny = (state.cy - py) / lm;
        const q1 = [px - ux * k, py - uy * k], q3 = [px + nx * k, py + ny * k], q2 = [q1[0] + nx * k, q1[1] + ny * k];
        el("polyline", { points: `${sx(q1[0])},${sy(q1[1])} ${sx(q2[0])},${sy(q2[1])} ${sx(q3[0])},${sy(q3[1])}`, class: "fig-right" });
      }
      el("circle", { cx: sx(px), cy: sy(py), r: 3.5, class: "fig-point" });
      if (ex.count > 0) {
        const dt = Math.sqrt(Math.max(state.r * state.r - lm * lm, 0));
        segment("fig-dt", px, py, px + dt * ux, py + dt * uy);
        figLabels.push([[sx(px + dt * ux / 2), sy(py + dt * uy / 2)], "Δt"]);
      }
      figLabels.push([[sx(px), sy(py)], "t_m"]);
      figLabels.push([[(sx(px) + sx(state.cx)) / 2, (sy(py) + sy(state.cy)) / 2], "ℓ_m"]);
      figLabels.push([[(sx(state.ox) + sx(state.cx)) / 2, (sy(state.oy) + sy(state.cy)) / 2], "L", "label dim"]);
    }
    // each formula's float32 roots: a tick across the ray, the textbook's and half b's on one side,
    // the rewrite's and the reference form's on the other, so that a root off the exact one shows
    const len = Math.sqrt(a);
    const marks = [];
    if (len > 0) {
      const nx = -state.dy / len, ny = state.dx / len;      // across the ray, in world axes
      for (const form of FORMS) {
        const r = res.forms[form.id].f32;
        r.t.slice(0, r.count === 1 ? 1 : 2).forEach((t, i) => {
          t = F(t);
          const x = sx(state.ox + t * state.dx), y = sy(state.oy + t * state.dy);
          if (!Number.isFinite(x) || !Number.isFinite(y)) return;
          const k = form.side * 18, kx = nx * k, ky = -ny * k;
          el("line", { x1: x, y1: y, x2: x + kx, y2: y + ky, class: `float-mark mark-${form.id}` });
          placed.push([Math.min(x, x + kx) - 3, Math.min(y, y + ky) - 3, Math.max(x, x + kx) + 3, Math.max(y, y + ky) + 3]);
          const exact = ex.count ? ex.t[Math.min(i, ex.count - 1)] : NaN;
          marks.push({ form: form.id, i, t, x, y, exact,
                       px: Math.hypot(x - sx(state.ox + exact * state.dx), y - sy(state.oy + exact * state.dy)) });
        });
      }
    }
    // the exact roots and the hit
    const hit = closestInWindow(ex);
    const roots = ex.t.slice(0, ex.count === 1 ? 1 : 2).map((t) => [t, sx(state.ox + t * state.dx), sy(state.oy + t * state.dy)]);
    for (const [t, x, y] of roots) {
      el("circle", { cx: x, cy: y, r: 5, class: t === hit ? "root hit" : "root" });
      placed.push([x - 11, y - 11, x + 11, y + 11]);     // the root and its hit ring: no label on them
    }
    if (hit !== null) {
      const x = sx(state.ox + hit * state.dx), y = sy(state.oy + hit * state.dy);
      el("circle", { cx: x, cy: y, r: 10, class: "hit-ring" });
    }
    // then the magnifier, the roots' labels and the figure's, each clear of all placed before it
    magnifier(res);
    roots.forEach(([t, x, y], i) => {
      const spots = around(x, y, 10);
      label(i === 0 ? [spots[3], ...spots] : [spots[0], ...spots], `t${ex.count === 1 ? "" : i} = ${fmt(t)}`, "label root-label", [x, y]);
    });
    for (const [[x, y], text, cls] of figLabels) label(around(x, y), text, cls, [x, y]);
    // how far the textbook's float roots are drawn from the exact ones
    const gaps = FORMS.map((form) => {
      const r = res.forms[form.id].f32;
      if (r.count !== ex.count) return `${form.name} ${r.count} root${r.count === 1 ? "" : "s"} where the exact count is ${ex.count}`;
      if (!ex.count) return `${form.name} no root`;
      const worst = marks.filter((m) => m.form === form.id && Number.isFinite(m.exact))
        .reduce((w, m) => (Math.abs(m.t - m.exact) > Math.abs(w.t - w.exact) ? m : w), { t: 0, exact: 0, px: 0 });
      const gap = Math.abs(worst.t - worst.exact) * len;
      return `${form.name} ${gap > 0 ? `${fmt(F(gap))} (${worst.px.toFixed(1)} px)` : "0"}`;
    });
    $("#float-gap").textContent = `float32 roots from the exact ones, in units: ${gaps.join(", ")}`;
    lastMarks = marks;
    placeHandles();
  }

  // --- handles: drag, type, or move with the arrow keys -------------------------------------------------
  const HANDLES = {
    origin: { name: "ray origin o", get: () => [state.ox, state.oy], put: (x, y) => ({ ox: x, oy: y }) },
    tip: { name: "direction tip o + d", get: () => [state.ox + state.dx, state.oy + state.dy], put: (x, y) => ({ dx: x - state.ox, dy: y - state.oy }) },
    centre: { name: "sphere centre c", get: () => [state.cx, state.cy], put: (x, y) => ({ cx: x, cy: y }) },
    radius: { name: "radius handle", get: () => [state.cx + state.r, state.cy], put: (x, y) => ({ r: Math.max(Math.hypot(x - state.cx, y - state.cy), 1e-6) }) },
  };
  let selected = "origin";
  function placeHandles() {
    for (const k in HANDLES) {
      const h = $(`#handle-${k}`), [x, y] = HANDLES[k].get();
      // A handle off the picture waits at its edge, on the way to it: still reachable, dragged by
      // the pointer's movement like any other.
      let [cx, cy] = clampToPicture(sx(x), sy(y));
      if (k === "tip" && (cx !== sx(x) || cy !== sy(y))) {         // o + d waiting at the same spot of the edge as o: one step inwards, both reachable
        const [ox, oy] = clampToPicture(sx(state.ox), sy(state.oy));
        const gap = Math.hypot(cx - ox, cy - oy);
        if (gap < 22) {
          const mx = W / 2 - ox, my = H / 2 - oy, m = Math.hypot(mx, my) || 1;
          [cx, cy] = [ox + (mx / m) * 24, oy + (my / m) * 24];
        }
      }
      h.setAttribute("cx", cx);
      h.setAttribute("cy", cy);
      h.classList.toggle("offscreen", cx !== sx(x) || cy !== sy(y));
      h.setAttribute("aria-label", `${HANDLES[k].name} at (${fmt(x)}, ${fmt(y)}); arrow keys move it`);
      h.classList.toggle("selected", k === selected);
    }
    // the direction's arrow joins the two handles where they are drawn (at the edge when off the picture)
    const ho = $("#handle-origin"), ht = $("#handle-tip"), hl = $("#handle-line");
    hl.setAttribute("x1", ho.getAttribute("cx")); hl.setAttribute("y1", ho.getAttribute("cy"));
    hl.setAttribute("x2", ht.getAttribute("cx")); hl.setAttribute("y2", ht.getAttribute("cy"));
  }
  function clampToPicture(x, y) {
    const m = 12;
    if (!Number.isFinite(x) || !Number.isFinite(y)) {
      if (Number.isNaN(x) || Number.isNaN(y)) return [m, m];
      x = Math.max(-1e300, Math.min(1e300, x)); y = Math.max(-1e300, Math.min(1e300, y));
    }
    if (x >= m && x <= W - m && y >= m && y <= H - m) return [x, y];
    // along the line from the picture's centre towards the point
    const dx = x - W / 2, dy = y - H / 2;
    const k = Math.min((W / 2 - m) / Math.abs(dx || 1e-300), (H / 2 - m) / Math.abs(dy || 1e-300));
    return [W / 2 + dx * k, H / 2 + dy * k];
  }
  function moveHandle(k, x, y) {
    set(HANDLES[k].put(x, y));
  }
  function select(k) {
    selected = k;
    $("#selected").textContent = HANDLES[k].name;
    placeHandles();
  }
  // --- the distance plot: the same ray moved back along itself, |f| / r from 1 to 10^7 -------------------
  // The line keeps its distance from the centre (in radii) and its direction; only the origin slides
  // back. Each float32 form's worst root error, in ulps, against log10 |f| / r: the textbook loses about
  // 2 log2(|f|/r) bits of 24, and the cliff where its count first goes wrong is computed for the line
  // (near |f|/r = 2^12 through the middle, sooner when grazing); where the rewrite holds shows too.
  // W is the plot's width on the screen (at most 640): it is drawn 1:1, so that its text keeps its size
  // on a narrow screen instead of shrinking with a 640-wide drawing.
  const PLOT = { W: 640, H: 170, left: 44, right: 10, top: 10, bottom: 30, x0: 0, x1: 7, y1: 8 };
  function family(logDist) {
    const len = Math.hypot(state.dx, state.dy);
    if (!(len > 0) || !(state.r > 0) || !Number.isFinite(state.r)) return null;
    const ux = state.dx / len, uy = state.dy / len;
    const fx = state.ox - state.cx, fy = state.oy - state.cy, along = fx * ux + fy * uy;
    const px = fx - along * ux, py = fy - along * uy, miss = Math.hypot(px, py);   // the closest point, from c
    const D = state.r * Math.pow(10, logDist);
    if (!(D > miss)) return null;
    const back = Math.sqrt(D * D - miss * miss);
    return { ...state, ox: state.cx + px - back * ux, oy: state.cy + py - back * uy };
  }
  function errorsAt(s) {
    const rounded = {};
    for (const k of FIELDS) rounded[k] = F(s[k]);
    const ex = exactRoots(rounded), out = {};
    for (const form of FORMS) {
      const r = form.fn(F, rounded);
      if (r.count !== ex.count) { out[form.id] = Infinity; continue; }
      let u = 0;
      for (let i = 0; i < r.count; i++) u = Math.max(u, ulps(F(r.t[i]), ex.t[i]));
      out[form.id] = u;
    }
    return out;
  }
  let plotKey = null, lastPlot = null, lastCliff = null;
  function plot() {
    const svg = $("#distance-plot");
    if (!svg) return;
    const len = Math.hypot(state.dx, state.dy);
    const line = [state.dx / len, state.dy / len, state.r].join(",") + "," +
                (((state.ox - state.cx) * state.dy - (state.oy - state.cy) * state.dx) / (len * state.r)).toPrecision(6);
    const here = Math.log10(Math.hypot(state.ox - state.cx, state.oy - state.cy) / state.r);
    const shown = Math.round(svg.clientWidth || 640);
    if (shown > 0) PLOT.W = Math.max(300, Math.min(640, shown));
    const key = `${line},${PLOT.W}`;
    const X = (v) => PLOT.left + ((v - PLOT.x0) / (PLOT.x1 - PLOT.x0)) * (PLOT.W - PLOT.left - PLOT.right);
    const Y = (u) => PLOT.H - PLOT.bottom - (Math.min(PLOT.y1, Math.log10(u + 1)) / PLOT.y1) * (PLOT.H - PLOT.top - PLOT.bottom);
    if (key !== plotKey) {
      plotKey = key;
      while (svg.firstChild) svg.removeChild(svg.firstChild);
      svg.setAttribute("viewBox", `0 0 ${PLOT.W} ${PLOT.H}`);
      const g = (tag, attrs, text) => el(tag, attrs, svg, text);
      g("rect", { x: 0, y: 0, width: PLOT.W, height: PLOT.H, class: "paper" });
      for (let e = 0; e <= PLOT.y1; e += 2) {
        g("line", { x1: PLOT.left, y1: Y(Math.pow(10, e) - 1), x2: PLOT.W - PLOT.right, y2: Y(Math.pow(10, e) - 1), class: "plot-grid" });
        g("text", { x: PLOT.left - 4, y: Y(Math.pow(10, e) - 1) + 4, "text-anchor": "end", class: "plot-text" }, e === 0 ? "0" : `1e${e}`);
      }
      for (let e = 0; e <= PLOT.x1; e++)         // the last one ends at the plot's edge, not past it
        g("text", { x: e === PLOT.x1 ? PLOT.W - 2 : X(e), y: PLOT.H - PLOT.bottom + 13, "text-anchor": e === PLOT.x1 ? "end" : "middle", class: "plot-text" }, e === 0 ? "1" : `1e${e}`);
      g("text", { x: PLOT.W - PLOT.right, y: PLOT.H - 4, "text-anchor": "end", class: "plot-text" }, "|f| / r, the same line moved back");
      g("text", { x: 2, y: PLOT.top + 2, class: "plot-text", transform: `rotate(90 2 ${PLOT.top + 2})` }, "worst ulps");
      g("line", { x1: PLOT.left, y1: Y(16), x2: PLOT.W - PLOT.right, y2: Y(16), class: "plot-bound" });
      g("text", { x: PLOT.W - PLOT.right - 2, y: Y(16) - 3, "text-anchor": "end", class: "plot-text plot-note" }, "16 ulps, the ★ bound");
      const series = {};
      for (const form of FORMS) series[form.id] = [];
      for (let i = 0; i <= 56; i++) {
        const v = PLOT.x0 + 0.15 + (i / 56) * (PLOT.x1 - PLOT.x0 - 0.15);
        const s = family(v);
        if (!s) continue;
        const err = errorsAt(s);
        for (const form of FORMS) series[form.id].push([v, err[form.id]]);
      }
      // The cliff, computed for this line: where the textbook has lost all its bits and first gets the
      // count wrong (the plot's top), between the first such sample and the one before it, bisected
      // down to 0.01 in log10 |f| / r.
      const book = series.textbook;
      const first = book.findIndex(([, u]) => !Number.isFinite(u));
      let cliff = null;
      if (first >= 0) {
        if (first === 0) cliff = book[0][0];
        else {
          let lo = book[first - 1][0], hi = book[first][0];
          while (hi - lo > 0.01) {
            const mid = (lo + hi) / 2, s = family(mid);
            if (s && Number.isFinite(errorsAt(s).textbook)) lo = mid; else hi = mid;
          }
          cliff = hi;
        }
        g("line", { x1: X(cliff), y1: PLOT.top, x2: X(cliff), y2: PLOT.H - PLOT.bottom, class: "plot-cliff" });
      }
      lastCliff = cliff;
      for (const form of FORMS) {
        const pts = series[form.id].map(([v, u]) => `${X(v)},${Y(Number.isFinite(u) ? u : 1e9)}`).join(" ");
        g("polyline", { points: pts, class: `plot-line mark-${form.id}` });
      }
      if (cliff !== null) {           // over the lines, on a white halo; measured, to stay on the plot
        const at = fmt(Number(Math.pow(10, cliff).toPrecision(2)));
        const t = g("text", { y: PLOT.top + 10, class: "plot-text plot-note" }, `the textbook's count goes wrong at |f|/r ≈ ${at}`);
        const fits = () => {
          const w = t.getBBox().width;
          if (X(cliff) + 3 + w <= PLOT.W - PLOT.right) { t.setAttribute("x", X(cliff) + 3); t.setAttribute("text-anchor", "start"); return true; }
          if (X(cliff) - 3 - w >= 2) { t.setAttribute("x", X(cliff) - 3); t.setAttribute("text-anchor", "end"); return true; }
          return false;
        };
        if (!fits()) { t.textContent = `count wrong at ≈ ${at}`; if (!fits()) { t.setAttribute("x", PLOT.W - PLOT.right); t.setAttribute("text-anchor", "end"); } }
      }
      g("line", { id: "plot-here", class: "plot-here" });
      lastPlot = series;
    }
    const h = svg.querySelector("#plot-here");
    if (h && Number.isFinite(here)) {
      h.setAttribute("x1", X(Math.max(PLOT.x0, Math.min(PLOT.x1, here)))); h.setAttribute("x2", X(Math.max(PLOT.x0, Math.min(PLOT.x1, here))));
      h.setAttribute("y1", PLOT.top); h.setAttribute("y2", PLOT.H - PLOT.bottom);
    }
    const slider = $("#log-distance");
    if (slider && document.activeElement !== slider && Number.isFinite(here)) slider.value = String(here);
  }

  function update(refit) {
    if (refit) fit();
    if (preset) {
      const changed = modified();
      $("#case-name").textContent = preset.kase + (changed ? " (modified)" : "");
      for (const b of document.querySelectorAll("#presets button"))
        b.setAttribute("aria-pressed", String(!changed && b.dataset.preset === preset.id));
    }
    const res = compute();
    lastResult = res;
    showNumbers(res);
    draw(res);
    plot();
  }
  let lastResult = null, lastMarks = [];

  function setupHandles() {
    const svg = $("#scene");
    let dragging = null;
    const toWorld = (ev) => {
      const box = svg.getBoundingClientRect();
      return [wx((ev.clientX - box.left) * W / box.width), wy((ev.clientY - box.top) * H / box.height)];
    };
    for (const k in HANDLES) {
      const h = $(`#handle-${k}`);
      let start = null;          // the pointer's and the handle's world points when the drag began
      h.addEventListener("pointerdown", (ev) => {
        dragging = k; select(k); h.setPointerCapture(ev.pointerId); h.focus(); ev.preventDefault();
        start = { pointer: toWorld(ev), handle: HANDLES[k].get() };
      });
      h.addEventListener("pointermove", (ev) => {
        if (dragging !== k || !start) return;
        const [x, y] = toWorld(ev);
        moveHandle(k, start.handle[0] + (x - start.pointer[0]), start.handle[1] + (y - start.pointer[1]));
      });
      h.addEventListener("pointerup", () => { dragging = null; update(true); });
      h.addEventListener("focus", () => select(k));
      h.addEventListener("keydown", (ev) => {
        const step = (ev.shiftKey ? 10 : ev.altKey ? 0.1 : 1) * 8 / view.scale;
        const dirs = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, 1], ArrowDown: [0, -1] };
        if (!(ev.key in dirs)) return;
        ev.preventDefault();
        const [x, y] = HANDLES[k].get();
        moveHandle(k, x + dirs[ev.key][0] * step, y + dirs[ev.key][1] * step);
      });
    }
  }
  function setupInputs() {
    for (const k of FIELDS) {
      const input = $(`#in-${k}`);
      input.addEventListener("input", () => {
        const v = parse(input.value);
        if (Number.isNaN(v) && input.value.trim().toLowerCase() !== "nan") { input.setAttribute("aria-invalid", "true"); return; }
        set({ [k]: v }, true);
      });
      input.addEventListener("change", () => { set({}); update(true); });
    }
    $("#zoom").addEventListener("change", (ev) => { zoom = ev.target.value; update(true); });
    $("#log-distance").addEventListener("input", (ev) => {
      const s = family(Number(ev.target.value));
      if (s) { set({ ox: s.ox, oy: s.oy }); update(true); }
    });
    const list = $("#presets");
    for (const p of PRESETS) {
      const b = document.createElement("button");
      b.type = "button"; b.textContent = p.title; b.dataset.preset = p.id;
      b.addEventListener("click", () => loadPreset(p.id));
      list.appendChild(b);
    }
  }
  function loadPreset(name) {
    const p = PRESETS.find((q) => q.id === name);
    if (!p) throw new Error(`no preset ${name}`);
    for (const b of document.querySelectorAll("#presets button")) b.setAttribute("aria-pressed", String(b.dataset.preset === name));
    preset = null;
    $("#case-name").textContent = p.kase;
    $("#case-section").textContent = p.section;
    set(p.s);
    zoom = p.view || (Math.hypot(state.ox - state.cx, state.oy - state.cy) > 50 * state.r ? "sphere" : "fit");   // far: look at the sphere
    preset = { id: p.id, kase: p.kase, inputs: { ...state } };
    $("#zoom").value = zoom;
    update(true);
    return name;
  }

  // What the self-test (tools/kitlib/selftest/lab.py) and the curious read: the page's state.
  window.raykitLab = {
    presets: PRESETS.map((p) => p.id),
    load: loadPreset,
    forms: FORMS.map((f) => f.id),
    inputs: () => Object.fromEntries(FIELDS.map((k) => [k, state[k]])),
    exactRoots, ulps, hexBits,
    marks: () => lastMarks,                // the float32 roots drawn: form, root, t, pixels from the exact root
    view: () => ({ ...view }),             // the world point at the picture's centre, pixels per unit
    magnifier: () => lastMagnifier,        // which root it shows, the worst float32 form's ulps, the span, its box
    plot: () => lastPlot,                  // each form's [log10 |f|/r, worst ulps] along the distance plot
    cliff: () => lastCliff,                // log10 |f|/r where the textbook first miscounts (null: never)
    modified,
  };

  // Each cell of the numbers names its column (data-label), for the narrow screen, where the rows are
  // laid out as cards that wrap instead of a table that scrolls its columns off the screen.
  function labelCells() {
    const names = { a: "a", h: "h", c: "c′", d4: "D/4", count: "count", t0: "t0", u0: "t0 ulps", t1: "t1", u1: "t1 ulps" };
    for (const td of document.querySelectorAll("#numbers tbody td")) {
      const id = td.dataset.cell;
      td.dataset.label = id ? names[id.slice(id.lastIndexOf("-") + 1)] || "" : "in";
    }
  }
  document.addEventListener("DOMContentLoaded", () => {
    labelCells();
    setupInputs();
    setupHandles();
    const wanted = (location.hash || "").slice(1);
    loadPreset(PRESETS.some((p) => p.id === wanted) ? wanted : "two-hits");
    // The labels are laid out as measured: again when the fonts change (a font that loads late, the
    // narrow screen's larger labels).
    if (document.fonts && document.fonts.ready) document.fonts.ready.then(() => update());
    window.matchMedia("(max-width: 700px)").addEventListener("change", () => update());
    window.addEventListener("resize", () => plot());        // the plot is drawn at its width on the screen
    document.body.dataset.ready = "1";
  });
})();

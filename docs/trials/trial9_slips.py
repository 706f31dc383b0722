#!/usr/bin/env python3
"""Trial 9: slips a first-year student makes, each one edit of the correct student files.

The correct files are trial 7's, docs/trials/trial7_student/*.cpp.txt, written in a handout from the
task, the contracts and the lectures only (they pass `./kit check` in a handout). Each slip below replaces one exact snippet (which must occur
exactly once) in one file. This list was written and committed before any slip was checked.

    python3 trial9_slips.py --list
    python3 trial9_slips.py --run HANDOUT OUTDIR [SLIP ...]   # one `./kit check N` per slip
"""
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
STUDENT = os.path.join(HERE, "trial7_student")

FILES = {
    "unit_sphere.cpp": "steps/01_unit_sphere/unit_sphere.cpp",
    "general_sphere.cpp": "steps/02_general_sphere/general_sphere.cpp",
    "unit_direction.cpp": "steps/03_unit_direction/unit_direction.cpp",
    "rect.cpp": "steps/04_rectangles/rect.cpp",
    "cornell_box.cpp": "steps/05_cornell_box/cornell_box.cpp",
    "render.cpp": "steps/05_cornell_box/render.cpp",
}

# (id, step, file, old, new, what the student did)
SLIPS = [    # ---- step 01 -------------------------------------------------------------------------
    ("s01_a_length", 1, "unit_sphere.cpp",
     "double a = dx * dx + dy * dy + dz * dz;",
     "double a = glm::length(ray.direction);",
     "a = |d| with glm::length where d.d (glm::dot) belongs"),
    ("s01_swap_reversed", 1, "unit_sphere.cpp",
     "if (t0 > t1) std::swap(t0, t1);",
     "if (t0 < t1) std::swap(t0, t1);",
     "sorting test reversed: swaps when already in order (far root first)"),
    ("s01_tangent_over_2a", 1, "unit_sphere.cpp",
     "float t = static_cast<float>(-b / a);",
     "float t = static_cast<float>(-b / (2 * a));",
     "tangent root -b / (2a) from the full-b form, with the half b"),
    ("s01_t1_c_over_a", 1, "unit_sphere.cpp",
     "double t1 = c / q;",
     "double t1 = c / a;",
     "second root c / a (the product of the roots) instead of c / q"),
    ("s01_loop_two_roots", 1, "unit_sphere.cpp",
     "for (int k = 0; k < r.count; ++k)",
     "for (int k = 0; k < 2; ++k)",
     "window loop over both entries whatever the count (a miss's 0 entries read)"),
    ("s01_no_origin_check", 1, "unit_sphere.cpp",
     "if (!finite3(ray.origin) || !finite3(ray.direction)) return out;",
     "if (!finite3(ray.direction)) return out;",
     "only the direction checked for NaN/infinity, not the origin"),
    ("s01_count_two_unset", 1, "unit_sphere.cpp",
     "    out.count = 2;\n",
     "",
     "two-root branch forgets count = 2 (roots filled, count left 0)"),
    ("s01_q_branches_swapped", 1, "unit_sphere.cpp",
     "double q = b >= 0 ? -(b + s) : -(b - s);",
     "double q = b >= 0 ? -(b - s) : -(b + s);",
     "stable form with its two branches swapped (cancellation, 0/0 on the surface)"),
    # ---- step 02 -------------------------------------------------------------------------
    ("s02_b_from_origin", 2, "general_sphere.cpp",
     "double b = fx * dx + fy * dy + fz * dz;",
     "double b = ray.origin.x * dx + ray.origin.y * dy + ray.origin.z * dz;",
     "b = o.d (step 01's line kept) while c uses f = o - c"),
    ("s02_r_times_2", 2, "general_sphere.cpp",
     "double c = fx * fx + fy * fy + fz * fz - r * r;",
     "double c = fx * fx + fy * fy + fz * fz - r * 2;",
     "r squared typed as r * 2"),
    ("s02_no_upper_bound", 2, "general_sphere.cpp",
     "if (tmin <= r.t[k] && r.t[k] <= tmax) return r.t[k];",
     "if (tmin <= r.t[k]) return r.t[k];",
     "window test forgets tmax"),
    ("s02_point_window_rejected", 2, "general_sphere.cpp",
     "if (!(tmin <= tmax)) return std::nullopt;",
     "if (!(tmin < tmax)) return std::nullopt;",
     "window guard tmin < tmax: a one-point window [t, t] rejected"),
    ("s02_tangent_sign", 2, "general_sphere.cpp",
     "float t = static_cast<float>(-b / a);",
     "float t = static_cast<float>(b / a);",
     "tangent root b / a (minus lost, only in the tangent branch)"),
    ("s02_t1_copy_t0", 2, "general_sphere.cpp",
     "out.t[1] = static_cast<float>(t1);",
     "out.t[1] = static_cast<float>(t0);",
     "copy-paste: t[1] stores t0 (both entries the near root)"),
    ("s02_center_y_typo", 2, "general_sphere.cpp",
     "double fy = double(ray.origin.y) - sphere.center.y;",
     "double fy = double(ray.origin.y) - sphere.center.x;",
     "copy-paste: f.y subtracts center.x"),
    ("s02_inf_radius", 2, "general_sphere.cpp",
     "if (!(sphere.radius > 0) || !std::isfinite(sphere.radius)) return out;",
     "if (!(sphere.radius > 0)) return out;",
     "radius check without isfinite: an infinite radius goes on (NaN roots)"),
    # ---- step 03 -------------------------------------------------------------------------
    ("s03_geo_dt2_plus", 3, "unit_direction.cpp",
     "double dt2 = r * r - lm2;",
     "double dt2 = r * r + lm2;",
     "geometric form: Delta t^2 = r^2 + l_m^2 (sign of Pythagoras)"),
    ("s03_geo_perp_plus", 3, "unit_direction.cpp",
     "double px = Lx - tm * dx, py = Ly - tm * dy, pz = Lz - tm * dz;",
     "double px = Lx + tm * dx, py = Ly + tm * dy, pz = Lz + tm * dz;",
     "geometric form: perpendicular offset L + t_m d instead of L - t_m d"),
    ("s03_geo_lm_sqrt", 3, "unit_direction.cpp",
     "double lm2 = px * px + py * py + pz * pz;",
     "double lm2 = std::sqrt(px * px + py * py + pz * pz);",
     "geometric form: l_m (a length) stored where l_m^2 is used"),
    ("s03_geo_tm_length", 3, "unit_direction.cpp",
     "double tm = Lx * dx + Ly * dy + Lz * dz;",
     "double tm = std::sqrt(Lx * Lx + Ly * Ly + Lz * Lz);",
     "geometric form: t_m = |L| (length) instead of L.d (projection)"),
    ("s03_unit_disc_h_not_squared", 3, "unit_direction.cpp",
     "double disc = h * h - c;",
     "double disc = h - c;",
     "unit-dir form: discriminant h - c' (h not squared)"),
    ("s03_unit_c_distance", 3, "unit_direction.cpp",
     "double c = fx * fx + fy * fy + fz * fz - r * r;",
     "double c = std::sqrt(fx * fx + fy * fy + fz * fz) - r;",
     "unit-dir form: c' = |f| - r (distance outside the sphere) instead of f.f - r^2"),
    ("s03_unit_tangent_no_return", 3, "unit_direction.cpp",
     "        out.t[0] = out.t[1] = static_cast<float>(-h);\n        return out;\n",
     "        out.t[0] = out.t[1] = static_cast<float>(-h);\n",
     "unit-dir tangent branch without return: falls through to count 2"),
    ("s03_unit_behind_exit", 3, "unit_direction.cpp",
     "if (disc < 0) return out;",
     "if (disc < 0 || h > 0) return out;",
     "unit-dir form: no roots when h > 0 (centre 'behind'), roots behind dropped"),
    # ---- step 04 -------------------------------------------------------------------------
    ("s04_v_always_z", 4, "rect.cpp",
     "int va = a == 2 ? 1 : 2;",
     "int va = 2;",
     "v is always z (axis 2's (x, y) case forgotten)"),
    ("s04_window_upper_open", 4, "rect.cpp",
     "if (!(tmin <= t && t <= tmax)) return std::nullopt;",
     "if (!(tmin <= t && t < tmax)) return std::nullopt;",
     "window's upper end excluded (t < tmax)"),
    ("s04_bounds_or", 4, "rect.cpp",
     "rect.lo.x <= u && u <= rect.hi.x && rect.lo.y <= v && v <= rect.hi.y",
     "(rect.lo.x <= u && u <= rect.hi.x) || (rect.lo.y <= v && v <= rect.hi.y)",
     "inside test with || between the u and v ranges (a cross, not a rectangle)"),
    ("s04_t_abs_d", 4, "rect.cpp",
     "float t = (rect.offset - ray.origin[a]) / da;",
     "float t = (rect.offset - ray.origin[a]) / std::abs(da);",
     "t divided by |d_axis| ('a distance is positive')"),
    ("s04_point_normalized_dir", 4, "rect.cpp",
     "glm::vec3 p = ray.origin + t * ray.direction;",
     "glm::vec3 p = ray.origin + t * (ray.direction / std::sqrt(ray.direction.x * ray.direction.x +\n"
     "        ray.direction.y * ray.direction.y + ray.direction.z * ray.direction.z));",
     "hit point o + t d/|d| (direction normalised only in the point)"),
    ("s04_negative_axis", 4, "rect.cpp",
     "if (rect.axis < 0 || rect.axis > 2) return std::nullopt;",
     "if (rect.axis > 2) return std::nullopt;",
     "axis check forgets negative axes"),
    ("s04_int_da", 4, "rect.cpp",
     "float da = ray.direction[a];",
     "int da = ray.direction[a];",
     "d_axis stored in an int (0.5 becomes 0: parallel)"),
    ("s04_t_times_d", 4, "rect.cpp",
     "float t = (rect.offset - ray.origin[a]) / da;",
     "float t = (rect.offset - ray.origin[a]) * da;",
     "t = (offset - o) * d_axis: multiplies where it divides"),
    # ---- step 05 -------------------------------------------------------------------------
    ("s05_back_wall_z", 5, "cornell_box.cpp",
     "Rect{2, 559.2f,",
     "Rect{2, 548.8f,",
     "back wall at z = 548.8 (the height typed for the depth)"),
    ("s05_right_wall_white", 5, "cornell_box.cpp",
     "{548.8f, 559.2f}}, green});",
     "{548.8f, 559.2f}}, white});",
     "right wall painted white (green forgotten)"),
    ("s05_focal_mm", 5, "cornell_box.cpp",
     "c.focal_length = 0.035f;",
     "c.focal_length = 35.0f;",
     "focal length in mm, film height in m (units mixed)"),
    ("s05_eye_xy_swapped", 5, "cornell_box.cpp",
     "glm::vec3(278.0f, 273.0f, -800.0f)",
     "glm::vec3(273.0f, 278.0f, -800.0f)",
     "eye's x and y transposed (273, 278)"),
    ("s05_canvas_at_swapped", 5, "render.cpp",
     "canvas.at(i, j) =",
     "canvas.at(j, i) =",
     "render writes canvas.at(row, column)"),
    ("s05_farthest_wins", 5, "render.cpp",
     "*t < best->t",
     "*t > best->t",
     "closest-hit comparison reversed: the farthest hit wins"),
    ("s05_no_focal_length", 5, "render.cpp",
     "camera.focal_length * camera.forward + ",
     "camera.forward + ",
     "view ray: the film put at distance 1 (focal length forgotten)"),
    ("s05_x_not_centred", 5, "render.cpp",
     "(static_cast<float>(i) + 0.5f) / W - 0.5f) * film_w",
     "(static_cast<float>(i) + 0.5f) / W) * film_w",
     "view ray: x not centred (the - 1/2 forgotten): image shifted sideways"),
]


def apply(text, old, new):
    if text.count(old) != 1:
        raise SystemExit(f"snippet occurs {text.count(old)} times: {old[:60]!r}")
    return text.replace(old, new)


def slipped(slip):
    sid, step, fname, old, new, _ = slip
    with open(os.path.join(STUDENT, fname + ".txt")) as f:
        text = f.read()
    text = apply(text, old, new)
    return text


def restore(handout):
    for fname, rel in FILES.items():
        shutil.copy(os.path.join(STUDENT, fname + ".txt"), os.path.join(handout, rel))


def run(handout, outdir, only):
    os.makedirs(outdir, exist_ok=True)
    for slip in SLIPS:
        sid, step, fname = slip[0], slip[1], slip[2]
        if only and sid not in only:
            continue
        restore(handout)
        with open(os.path.join(handout, FILES[fname]), "w") as f:
            f.write(slipped(slip))
        proc = subprocess.run(["nice", "./kit", "check", str(step)], cwd=handout,
                              capture_output=True, text=True)
        with open(os.path.join(outdir, sid + ".txt"), "w") as f:
            f.write(f"exit {proc.returncode}\n" + proc.stdout + proc.stderr)
        print(sid, "exit", proc.returncode, flush=True)
    restore(handout)


def main(argv):
    if argv[:1] == ["--list"]:
        for s in SLIPS:
            print(f"{s[0]:30} step {s[1]}  {s[5]}")
        for s in SLIPS:
            slipped(s)  # every snippet applies
        print(len(SLIPS), "slips")
    elif argv[:1] == ["--run"] and len(argv) >= 3:
        run(argv[1], argv[2], set(argv[3:]))
    else:
        print(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

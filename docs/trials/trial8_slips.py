#!/usr/bin/env python3
"""Trial 8: slips a first-year student makes, each one edit of the correct student files.

The correct files are trial 7's, docs/trials/trial7_student/*.cpp.txt, written in a handout from the
task, the contracts and the lectures only (they pass `./kit check` in a trial-8 handout). Each slip below replaces one exact snippet (which must occur
exactly once) in one file. This list was written and committed before any slip was checked.

    python3 trial8_slips.py --list
    python3 trial8_slips.py --run HANDOUT OUTDIR [SLIP ...]   # one `./kit check N` per slip
"""

import sys

import slip_runner

SLIPS = [
    # ---- step 01 -------------------------------------------------------------------------
    ("s01_sqrt_negative", 1, "unit_sphere.cpp",
     "    if (disc < 0) return out;\n",
     "",
     "no miss test: a negative discriminant goes on to sqrt (NaN roots, count 2)"),
    ("s01_early_return_loop", 1, "unit_sphere.cpp",
     "return r.t[k];\n",
     "return r.t[k];\n        else return std::nullopt;\n",
     "early return in the window loop: the far root is never tried"),
    ("s01_precedence_t1", 1, "unit_sphere.cpp",
     "    double q = b >= 0 ? -(b + s) : -(b - s);\n    double t0 = q / a;\n    double t1 = c / q;\n",
     "    double t0 = (-b - s) / a;\n    double t1 = -b + s / a;\n",
     "textbook roots with a precedence slip: t1 = -b + s / a"),
    ("s01_window_wrong_index", 1, "unit_sphere.cpp",
     "r.t[k] <= tmax",
     "r.t[0] <= tmax",
     "window test reads t[0] for the upper bound (wrong index reused)"),
    ("s01_tangent_no_div_a", 1, "unit_sphere.cpp",
     "float t = static_cast<float>(-b / a);",
     "float t = static_cast<float>(-b);",
     "tangent root -b, the division by a forgotten"),
    ("s01_normalize_d", 1, "unit_sphere.cpp",
     "double dx = ray.direction.x, dy = ray.direction.y, dz = ray.direction.z;",
     "glm::vec3 n = glm::normalize(ray.direction);\n    double dx = n.x, dy = n.y, dz = n.z;",
     "direction normalised first: roots are distances, not t"),
    ("s01_b_component_typo", 1, "unit_sphere.cpp",
     "double b = ox * dx + oy * dy + oz * dz;",
     "double b = ox * dx + oy * dy + oz * dx;",
     "copy-paste in b: oz * dx instead of oz * dz"),
    ("s01_disc_four_ac", 1, "unit_sphere.cpp",
     "double disc = b * b - a * c;",
     "double disc = b * b - 4 * a * c;",
     "half-b discriminant written with the full form's 4ac"),
    ("s01_tangent_t1_unset", 1, "unit_sphere.cpp",
     "out.t[0] = out.t[1] = t;",
     "out.t[0] = t;",
     "tangent sets t[0] only (t[1] stays 0)"),
    # ---- step 02 -------------------------------------------------------------------------
    ("s02_f_plus_c", 2, "general_sphere.cpp",
     "double fx = double(ray.origin.x) - sphere.center.x;\n"
     "    double fy = double(ray.origin.y) - sphere.center.y;\n"
     "    double fz = double(ray.origin.z) - sphere.center.z;",
     "double fx = double(ray.origin.x) + sphere.center.x;\n"
     "    double fy = double(ray.origin.y) + sphere.center.y;\n"
     "    double fz = double(ray.origin.z) + sphere.center.z;",
     "f = o + c instead of o - c"),
    ("s02_zero_radius_allowed", 2, "general_sphere.cpp",
     "if (!(sphere.radius > 0) || !std::isfinite(sphere.radius)) return out;",
     "if (sphere.radius < 0 || !std::isfinite(sphere.radius)) return out;",
     "radius check < 0: a radius of 0 is treated as a sphere"),
    ("s02_window_or", 2, "general_sphere.cpp",
     "if (tmin <= r.t[k] && r.t[k] <= tmax)",
     "if (tmin <= r.t[k] || r.t[k] <= tmax)",
     "window test with || instead of &&"),
    ("s02_dz_copy_y", 2, "general_sphere.cpp",
     "dz = ray.direction.z;",
     "dz = ray.direction.y;",
     "copy-paste: dz read from direction.y"),
    ("s02_a_dot_f", 2, "general_sphere.cpp",
     "double a = dx * dx + dy * dy + dz * dz;",
     "double a = fx * fx + fy * fy + fz * fz;",
     "a = f.f instead of d.d (wrong variable)"),
    ("s02_int_radius", 2, "general_sphere.cpp",
     "double r = sphere.radius;",
     "int r = sphere.radius;",
     "radius stored in an int"),
    ("s02_q_branch_sign", 2, "general_sphere.cpp",
     "double q = b >= 0 ? -(b + s) : -(b - s);",
     "double q = b >= 0 ? -(b + s) : (b - s);",
     "stable form: the minus of the b < 0 branch forgotten"),
    ("s02_tangent_epsilon", 2, "general_sphere.cpp",
     "if (disc == 0) {",
     "if (std::abs(disc) < 1e-6) {",
     "tangent test with an epsilon (|disc| < 1e-6) instead of == 0"),
    # ---- step 03 -------------------------------------------------------------------------
    ("s03_unit_disc_4c", 3, "unit_direction.cpp",
     "double disc = h * h - c;",
     "double disc = h * h - 4 * c;",
     "unit-dir form: discriminant h^2 - 4c (the full form's 4 kept)"),
    ("s03_unit_q_over_c", 3, "unit_direction.cpp",
     "double t1 = c / q;",
     "double t1 = q / c;",
     "unit-dir form: second root q / c instead of c / q"),
    ("s03_geo_tm_not_squared", 3, "unit_direction.cpp",
     "    double px = Lx - tm * dx, py = Ly - tm * dy, pz = Lz - tm * dz;\n"
     "    double lm2 = px * px + py * py + pz * pz;",
     "    double lm2 = Lx * Lx + Ly * Ly + Lz * Lz - tm;",
     "geometric form: l_m^2 = |L|^2 - t_m (t_m not squared)"),
    ("s03_geo_py_typo", 3, "unit_direction.cpp",
     "py = Ly - tm * dy",
     "py = Ly - tm * dx",
     "geometric form: copy-paste dx for dy in the perpendicular offset"),
    ("s03_geo_dt_not_sqrt", 3, "unit_direction.cpp",
     "double dt = std::sqrt(dt2);",
     "double dt = dt2;",
     "geometric form: Delta t = r^2 - l_m^2, the square root forgotten"),
    ("s03_unit_q_no_branch", 3, "unit_direction.cpp",
     "double q = h >= 0 ? -(h + s) : -(h - s);",
     "double q = -(h + s);",
     "unit-dir form: q = -(h + s) for every sign of h"),
    ("s03_geo_tangent_minus_tm", 3, "unit_direction.cpp",
     "out.t[0] = out.t[1] = static_cast<float>(tm);",
     "out.t[0] = out.t[1] = static_cast<float>(-tm);",
     "geometric tangent root -t_m (copied from the unit-dir form's -h)"),
    ("s03_unit_tangent_count_unset", 3, "unit_direction.cpp",
     "        out.count = 1;\n        out.t[0] = out.t[1] = static_cast<float>(-h);",
     "        out.t[0] = out.t[1] = static_cast<float>(-h);",
     "unit-dir tangent: count left at 0"),
    # ---- step 04 -------------------------------------------------------------------------
    ("s04_da_hardcoded_z", 4, "rect.cpp",
     "float da = ray.direction[a];",
     "float da = ray.direction.z;",
     "d_axis hard-coded as direction.z (the lecture's z example)"),
    ("s04_uv_both_from_u", 4, "rect.cpp",
     "float u = p[ua], v = p[va];",
     "float u = p[ua], v = p[ua];",
     "copy-paste: v read from p[ua]"),
    ("s04_point_no_origin", 4, "rect.cpp",
     "glm::vec3 p = ray.origin + t * ray.direction;",
     "glm::vec3 p = t * ray.direction;",
     "hit point t d, the origin forgotten"),
    ("s04_int_t", 4, "rect.cpp",
     "float t = (rect.offset",
     "int t = (rect.offset",
     "t stored in an int"),
    ("s04_demorgan_window", 4, "rect.cpp",
     "if (!(tmin <= t && t <= tmax)) return std::nullopt;",
     "if (t < tmin && t > tmax) return std::nullopt;",
     "window test negated without De Morgan (&& kept): never rejects"),
    ("s04_precedence_t", 4, "rect.cpp",
     "float t = (rect.offset - ray.origin[a]) / da;",
     "float t = rect.offset - ray.origin[a] / da;",
     "precedence: offset - o / d"),
    ("s04_axis_check_off_by_one", 4, "rect.cpp",
     "rect.axis > 2",
     "rect.axis > 3",
     "axis check off by one: axis 3 accepted"),
    ("s04_normalize_dir", 4, "rect.cpp",
     "    float da = ray.direction[a];\n"
     "    if (da == 0.0f) return std::nullopt;\n"
     "    float t = (rect.offset - ray.origin[a]) / da;\n"
     "    if (!(tmin <= t && t <= tmax)) return std::nullopt;\n"
     "    glm::vec3 p = ray.origin + t * ray.direction;",
     "    glm::vec3 d = ray.direction / std::sqrt(ray.direction.x * ray.direction.x +\n"
     "        ray.direction.y * ray.direction.y + ray.direction.z * ray.direction.z);\n"
     "    float da = d[a];\n"
     "    if (da == 0.0f) return std::nullopt;\n"
     "    float t = (rect.offset - ray.origin[a]) / da;\n"
     "    if (!(tmin <= t && t <= tmax)) return std::nullopt;\n"
     "    glm::vec3 p = ray.origin + t * d;",
     "direction normalised first: t is a distance, not the ray parameter"),
    # ---- step 05 -------------------------------------------------------------------------
    ("s05_loop_le_height", 5, "render.cpp",
     "for (int j = 0; j < camera.height; ++j)",
     "for (int j = 0; j <= camera.height; ++j)",
     "render loop j <= height: one row past the canvas"),
    ("s05_loop_starts_at_1", 5, "render.cpp",
     "for (int i = 0; i < camera.width; ++i)",
     "for (int i = 1; i < camera.width; ++i)",
     "render loop starts at column 1: column 0 never painted"),
    ("s05_last_hit_wins", 5, "render.cpp",
     "if (t && (!best || *t < best->t)) best",
     "if (t) best",
     "closest-hit test dropped: the last object hit wins"),
    ("s05_int_half_y", 5, "render.cpp",
     "const float y = (0.5f - (static_cast<float>(j) + 0.5f) / H)",
     "const float y = (1 / 2 - (static_cast<float>(j) + 0.5f) / H)",
     "integer 1 / 2 in the row's offset (y = -(j + 1/2) / H * h)"),
    ("s05_tmax_1000", 5, "render.cpp",
     "find_intersection(ray, scene, 0.0f, std::numeric_limits<float>::infinity());",
     "find_intersection(ray, scene, 0.0f, 1000.0f);",
     "render window [0, 1000] (a 'far enough' distance; t is not a distance here)"),
    ("s05_dir_is_point", 5, "render.cpp",
     "return Ray{camera.eye, dir};",
     "return Ray{camera.eye, camera.eye + dir};",
     "view ray direction is the film point p, not p - e"),
    ("s05_film_w_inverted", 5, "render.cpp",
     "camera.film_height * W / H;",
     "camera.film_height * H / W;",
     "film width h * H / W (aspect ratio inverted)"),
    ("s05_find_ignores_tmin", 5, "render.cpp",
     "intersect_rect(ray, scene.objects[k].shape, tmin, tmax)",
     "intersect_rect(ray, scene.objects[k].shape, 0.0f, tmax)",
     "find_intersection passes 0 instead of its tmin"),
    ("s05_light_lo_hi_swapped", 5, "cornell_box.cpp",
     "{213.0f, 227.0f}, {343.0f, 332.0f}",
     "{343.0f, 332.0f}, {213.0f, 227.0f}",
     "light's corners in the wrong order (lo > hi)"),
]


if __name__ == "__main__":
    sys.exit(slip_runner.main(sys.argv[1:], SLIPS, __doc__))

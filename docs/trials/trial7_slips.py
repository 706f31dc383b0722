#!/usr/bin/env python3
"""Trial 7: slips a first-year student makes, each one edit of the correct student files.

The correct files are docs/trials/trial7_student/*.cpp.txt, written in a handout from the task,
the contracts and the lectures only. Each slip below replaces one exact snippet (which must occur
exactly once) in one file. This list was written and committed before any slip was checked.

    python3 trial7_slips.py --list
    python3 trial7_slips.py --run HANDOUT OUTDIR [SLIP ...]   # one `./kit check N` per slip
"""

import sys

import slip_runner

SLIPS = [
    # ---- step 01 -------------------------------------------------------------------------
    ("s01_far_root_first", 1, "unit_sphere.cpp",
     "for (int k = 0; k < r.count; ++k) {",
     "for (int k = r.count - 1; k >= 0; --k) {",
     "window loop walks the roots from the far end: returns the far root when both are inside"),
    ("s01_open_window", 1, "unit_sphere.cpp",
     "if (tmin <= r.t[k] && r.t[k] <= tmax) return r.t[k];",
     "if (tmin < r.t[k] && r.t[k] < tmax) return r.t[k];",
     "window ends excluded (< instead of <=)"),
    ("s01_no_sort", 1, "unit_sphere.cpp",
     "    if (t0 > t1) std::swap(t0, t1);\n",
     "",
     "roots not sorted (q/a and c/q come out in either order)"),
    ("s01_tangent_as_two", 1, "unit_sphere.cpp",
     "    if (disc == 0) {\n        float t = static_cast<float>(-b / a);\n        out.count = 1;\n"
     "        out.t[0] = out.t[1] = t;\n        return out;\n    }\n",
     "",
     "no tangent branch: a zero discriminant reports count 2"),
    ("s01_tangent_as_miss", 1, "unit_sphere.cpp",
     "if (disc < 0) return out;",
     "if (disc <= 0) return out;",
     "discriminant <= 0 treated as a miss: tangents lost"),
    ("s01_full_b", 1, "unit_sphere.cpp",
     "double b = ox * dx + oy * dy + oz * dz;",
     "double b = 2 * (ox * dx + oy * dy + oz * dz);",
     "b = 2(o.d) from the textbook form, used in the half-b formulas"),
    ("s01_c_sign", 1, "unit_sphere.cpp",
     "double c = ox * ox + oy * oy + oz * oz - 1.0;",
     "double c = ox * ox + oy * oy + oz * oz + 1.0;",
     "constant term o.o + 1 instead of o.o - 1"),
    ("s01_window_t_positive", 1, "unit_sphere.cpp",
     "if (tmin <= r.t[k] && r.t[k] <= tmax) return r.t[k];",
     "if (r.t[k] >= 0 && r.t[k] <= tmax) return r.t[k];",
     "tests t >= 0 instead of t >= tmin"),
    ("s01_zero_direction", 1, "unit_sphere.cpp",
     "    if (!std::isnormal(ddf)) return out;\n",
     "",
     "no guard for a zero (or too short) direction: 0/0"),
    ("s01_static_result", 1, "unit_sphere.cpp",
     "Roots unit_sphere_roots(const Ray& ray) {\n    Roots out;",
     "Roots unit_sphere_roots(const Ray& ray) {\n    static Roots out;",
     "result kept in a static (a miss returns the previous call's roots)"),
    # ---- step 02 -------------------------------------------------------------------------
    ("s02_origin_not_f", 2, "general_sphere.cpp",
     "double fx = double(ray.origin.x) - sphere.center.x;\n"
     "    double fy = double(ray.origin.y) - sphere.center.y;\n"
     "    double fz = double(ray.origin.z) - sphere.center.z;",
     "double fx = ray.origin.x;\n    double fy = ray.origin.y;\n    double fz = ray.origin.z;",
     "uses o where o - c is needed (centre forgotten)"),
    ("s02_r_not_squared", 2, "general_sphere.cpp",
     "fz * fz - r * r;",
     "fz * fz - r;",
     "constant term uses r, not r^2"),
    ("s02_f_reversed", 2, "general_sphere.cpp",
     "double fx = double(ray.origin.x) - sphere.center.x;\n"
     "    double fy = double(ray.origin.y) - sphere.center.y;\n"
     "    double fz = double(ray.origin.z) - sphere.center.z;",
     "double fx = double(sphere.center.x) - ray.origin.x;\n"
     "    double fy = double(sphere.center.y) - ray.origin.y;\n"
     "    double fz = double(sphere.center.z) - ray.origin.z;",
     "f = c - o instead of o - c (roots come out negated)"),
    ("s02_negative_radius", 2, "general_sphere.cpp",
     "if (!(sphere.radius > 0) || !std::isfinite(sphere.radius)) return out;",
     "if (sphere.radius == 0 || !std::isfinite(sphere.radius)) return out;",
     "only radius 0 rejected: a negative radius is used as if positive"),
    ("s02_a_is_one", 2, "general_sphere.cpp",
     "double a = dx * dx + dy * dy + dz * dz;",
     "double a = 1.0;",
     "assumes a unit direction (a = 1)"),
    ("s02_int_t", 2, "general_sphere.cpp",
     "        if (tmin <= r.t[k] && r.t[k] <= tmax) return r.t[k];",
     "        int t = r.t[k];\n        if (tmin <= t && t <= tmax) return t;",
     "root stored in an int before the window test"),
    # ---- step 03 -------------------------------------------------------------------------
    ("s03_h_sign", 3, "unit_direction.cpp",
     "double q = h >= 0 ? -(h + s) : -(h - s);",
     "double q = h >= 0 ? (h + s) : (h - s);",
     "unit-dir form: t = +h -/+ sqrt (sign of h lost)"),
    ("s03_geo_early_exit", 3, "unit_direction.cpp",
     "    double px = Lx - tm * dx",
     "    if (tm < 0) return out;\n    double px = Lx - tm * dx",
     "geometric form exits early when the centre is behind (t_m < 0)"),
    ("s03_geo_r_not_squared", 3, "unit_direction.cpp",
     "double dt2 = r * r - lm2;",
     "double dt2 = r - lm2;",
     "geometric form: r - l_m^2 instead of r^2 - l_m^2"),
    ("s03_geo_L_reversed", 3, "unit_direction.cpp",
     "double Lx = double(sphere.center.x) - ray.origin.x;\n"
     "    double Ly = double(sphere.center.y) - ray.origin.y;\n"
     "    double Lz = double(sphere.center.z) - ray.origin.z;",
     "double Lx = double(ray.origin.x) - sphere.center.x;\n"
     "    double Ly = double(ray.origin.y) - sphere.center.y;\n"
     "    double Lz = double(ray.origin.z) - sphere.center.z;",
     "geometric form: L = o - c instead of c - o"),
    ("s03_geo_unsorted", 3, "unit_direction.cpp",
     "out.t[0] = static_cast<float>(tm - dt);\n    out.t[1] = static_cast<float>(tm + dt);",
     "out.t[0] = static_cast<float>(tm + dt);\n    out.t[1] = static_cast<float>(tm - dt);",
     "geometric form: roots t_m + dt, t_m - dt (far one first)"),
    ("s03_unitdir_no_radius_check", 3, "unit_direction.cpp",
     "Roots sphere_roots_unit_dir(const Ray& ray, const Sphere& sphere) {\n    Roots out;\n"
     "    if (!finite3(ray.origin) || !finite3(ray.direction) || !finite3(sphere.center)) return out;\n"
     "    if (!(sphere.radius > 0) || !std::isfinite(sphere.radius)) return out;\n",
     "Roots sphere_roots_unit_dir(const Ray& ray, const Sphere& sphere) {\n    Roots out;\n"
     "    if (!finite3(ray.origin) || !finite3(ray.direction) || !finite3(sphere.center)) return out;\n",
     "unit-dir form forgets the radius check (negative radius used via r*r)"),
    # ---- step 04 -------------------------------------------------------------------------
    ("s04_no_axis_check", 4, "rect.cpp",
     "    if (rect.axis < 0 || rect.axis > 2) return std::nullopt;\n",
     "",
     "rule 1 skipped: a bad axis is not rejected"),
    ("s04_cyclic_uv", 4, "rect.cpp",
     "int ua = a == 0 ? 1 : 0;\n    int va = a == 2 ? 1 : 2;",
     "int ua = (a + 1) % 3;\n    int va = (a + 2) % 3;",
     "(u, v) taken cyclically: (z, x) for axis 1 instead of (x, z)"),
    ("s04_strict_edges", 4, "rect.cpp",
     "rect.lo.x <= u && u <= rect.hi.x && rect.lo.y <= v && v <= rect.hi.y",
     "rect.lo.x < u && u < rect.hi.x && rect.lo.y < v && v < rect.hi.y",
     "edges excluded (< instead of <=)"),
    ("s04_copy_paste_bound", 4, "rect.cpp",
     "rect.lo.y <= v && v <= rect.hi.y",
     "rect.lo.y <= v && v <= rect.hi.x",
     "copy-pasted bound: v <= hi.x"),
    ("s04_parallel_epsilon", 4, "rect.cpp",
     "if (da == 0.0f) return std::nullopt;",
     "if (std::abs(da) < 1e-6f) return std::nullopt;",
     "epsilon parallel test rejects short but valid directions"),
    ("s04_t_sign", 4, "rect.cpp",
     "float t = (rect.offset - ray.origin[a]) / da;",
     "float t = (ray.origin[a] - rect.offset) / da;",
     "t = (o - offset)/d: wrong sign"),
    ("s04_window_t_positive", 4, "rect.cpp",
     "if (!(tmin <= t && t <= tmax)) return std::nullopt;",
     "if (t < 0 || t > tmax) return std::nullopt;",
     "tests t >= 0 instead of t >= tmin"),
    # ---- step 05 -------------------------------------------------------------------------
    ("s05_tie_later_wins", 5, "render.cpp",
     "if (t && (!best || *t < best->t))",
     "if (t && (!best || *t <= best->t))",
     "<= in the closest-hit test: on a tie the later object wins"),
    ("s05_first_by_index", 5, "render.cpp",
     "if (t && (!best || *t < best->t))",
     "if (t && !best)",
     "keeps the first object hit in list order, not the closest"),
    ("s05_y_flipped", 5, "render.cpp",
     "const float y = (0.5f - (static_cast<float>(j) + 0.5f) / H) * camera.film_height;",
     "const float y = ((static_cast<float>(j) + 0.5f) / H - 0.5f) * camera.film_height;",
     "row 0 at the bottom: y axis flipped"),
    ("s05_right_up_x_forward", 5, "render.cpp",
     "glm::cross(camera.forward, camera.up)",
     "glm::cross(camera.up, camera.forward)",
     "right = up x forward: image mirrored"),
    ("s05_aspect_int_division", 5, "render.cpp",
     "const float film_w = camera.film_height * W / H;",
     "const float film_w = camera.film_height * (camera.width / camera.height);",
     "aspect ratio by integer division"),
    ("s05_pixel_corner", 5, "render.cpp",
     "const float x = ((static_cast<float>(i) + 0.5f) / W - 0.5f) * film_w;",
     "const float x = (static_cast<float>(i) / W - 0.5f) * film_w;",
     "column i's corner instead of its centre (no + 1/2)"),
    ("s05_ij_swapped", 5, "render.cpp",
     "Ray ray = view_ray(camera, i, j);",
     "Ray ray = view_ray(camera, j, i);",
     "render loop passes (row, column) to view_ray"),
    ("s05_walls_colours_swapped", 5, "cornell_box.cpp",
     "{0.0f, 0.0f}, {548.8f, 559.2f}}, red});\n"
     "    s.objects.push_back({\"right wall\", Rect{0, 0.0f, {0.0f, 0.0f}, {548.8f, 559.2f}}, green});",
     "{0.0f, 0.0f}, {548.8f, 559.2f}}, green});\n"
     "    s.objects.push_back({\"right wall\", Rect{0, 0.0f, {0.0f, 0.0f}, {548.8f, 559.2f}}, red});",
     "left wall green and right wall red"),
    ("s05_light_after_ceiling", 5, "cornell_box.cpp",
     "    s.objects.push_back({\"light\", Rect{1, 548.8f, {213.0f, 227.0f}, {343.0f, 332.0f}}, light});\n",
     "",
     "(with the light re-added after the ceiling) the ceiling wins the tie"),
    ("s05_film_height_for_width", 5, "render.cpp",
     "const float x = ((static_cast<float>(i) + 0.5f) / W - 0.5f) * film_w;",
     "const float x = ((static_cast<float>(i) + 0.5f) / W - 0.5f) * camera.film_height;",
     "x scaled by the film height, not its width (non-square images squashed)"),
    ("s05_background_white", 5, "render.cpp",
     "scene.objects[hit->index].color : background;",
     "scene.objects[hit->index].color : Color(1.0f);",
     "background painted white"),
    ("s05_eye_z_sign", 5, "cornell_box.cpp",
     "glm::vec3(278.0f, 273.0f, -800.0f)",
     "glm::vec3(278.0f, 273.0f, 800.0f)",
     "eye at z = +800 (sign dropped)"),
    ("s05_floor_lo_hi_ranges", 5, "cornell_box.cpp",
     "Rect{1, 0.0f, {0.0f, 0.0f}, {556.0f, 559.2f}}, white",
     "Rect{1, 0.0f, {0.0f, 556.0f}, {0.0f, 559.2f}}, white",
     "floor's lo/hi written as x range and z range"),
]


def slipped(slip):
    text = slip_runner.slipped(slip)
    if slip[0] == "s05_light_after_ceiling":  # the light goes right after the ceiling
        line = ('    s.objects.push_back({"light", Rect{1, 548.8f, {213.0f, 227.0f}, '
                '{343.0f, 332.0f}}, light});\n')
        anchor = '    s.objects.push_back({"back wall"'
        text = slip_runner.apply(text, anchor, line + anchor)
    return text


if __name__ == "__main__":
    sys.exit(slip_runner.main(sys.argv[1:], SLIPS, __doc__, slipped))

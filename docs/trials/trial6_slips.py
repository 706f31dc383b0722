# The trial's slips, invented by the student before reading the kit's catalogue.
# (name, step, file under steps/, old text, new text, what the slip is)
F1 = "01_unit_sphere/unit_sphere.cpp"
F2 = "02_general_sphere/general_sphere.cpp"
F3 = "03_unit_direction/unit_direction.cpp"
F4 = "04_rectangles/rect.cpp"
F5c = "05_cornell_box/cornell_box.cpp"
F5r = "05_cornell_box/render.cpp"
SLIPS = [
 ("full_b_in_half_formula", 1, F1, "float h = glm::dot(o, d);", "float h = 2.0f * glm::dot(o, d);", "b = 2 o.d used in the half-b formula"),
 ("disc_4ac_with_half_b", 1, F1, "float disc = h * h - a * c;", "float disc = h * h - 4.0f * a * c;", "half-b h with the full-b discriminant h^2 - 4ac"),
 ("c_plus_one", 1, F1, "float c = glm::dot(o, o) - 1.0f;", "float c = glm::dot(o, o) + 1.0f;", "c = o.o + 1 (sign of the radius term)"),
 ("roots_unsorted", 1, F1, "r.t[0] = (-h - s) / a;\n    r.t[1] = (-h + s) / a;", "r.t[0] = (-h + s) / a;\n    r.t[1] = (-h - s) / a;", "+sqrt root stored first"),
 ("tangent_counted_twice", 1, F1, "if (disc == 0) {", "if (false && disc == 0) {", "no tangent branch: count 2 for a double root"),
 ("open_window", 1, F1, "if (tmin <= r.t[k] && r.t[k] <= tmax)", "if (tmin < r.t[k] && r.t[k] < tmax)", "window ends excluded"),
 ("near_root_only", 1, F1, "for (int k = 0; k < r.count; ++k) {", "for (int k = 0; k < (r.count > 0 ? 1 : 0); ++k) {", "only t[0] tried (origin inside misses)"),
 ("no_zero_direction_guard", 1, F1, "if (!(a > 0) || !std::isfinite(a)) return r;", "", "no guard for d = 0 (0/0)"),
 ("over_2a_half_b", 1, F1, "r.t[0] = (-h - s) / a;\n    r.t[1] = (-h + s) / a;", "r.t[0] = (-h - s) / (2 * a);\n    r.t[1] = (-h + s) / (2 * a);", "half-b roots divided by 2a"),
 ("sqrt_in_int", 1, F1, "float s = std::sqrt(disc);", "int s = std::sqrt(disc);", "square root kept in an int"),
 ("tmax_ignored", 1, F1, "if (tmin <= r.t[k] && r.t[k] <= tmax)", "if (tmin <= r.t[k])", "window's upper end never checked"),
 ("f_reversed", 2, F2, "glm::vec3 f = ray.origin - sphere.center;", "glm::vec3 f = sphere.center - ray.origin;", "f = c - o instead of o - c"),
 ("r_not_squared", 2, F2, "float c = glm::dot(f, f) - r * r;", "float c = glm::dot(f, f) - r;", "constant term uses r, not r^2"),
 ("negative_radius_accepted", 2, F2, "if (!(r > 0) || !std::isfinite(r)) return out;", "if (r == 0 || !std::isfinite(r)) return out;", "only r == 0 rejected"),
 ("h_from_origin", 2, F2, "float h = glm::dot(f, d);", "float h = glm::dot(ray.origin, d);", "h = o.d (step 01's) instead of f.d"),
 ("a_assumed_one", 2, F2, "float a = glm::dot(d, d);\n    if (!(a > 0) || !std::isfinite(a)) return out;", "float a = 1.0f;\n    if (!(glm::dot(d, d) > 0)) return out;", "a = 1: assumes a unit direction"),
 ("infinite_radius_accepted", 2, F2, "if (!(r > 0) || !std::isfinite(r)) return out;", "if (!(r > 0)) return out;", "guard lets r = inf through"),
 ("geom_lm2_sign", 3, F3, "float lm2 = glm::dot(L, L) - tm * tm;", "float lm2 = tm * tm - glm::dot(L, L);", "l_m^2 = t_m^2 - |L|^2"),
 ("geom_early_exit_behind", 3, F3, "float lm2 = glm::dot(L, L) - tm * tm;", "if (tm < 0) return out;\n    float lm2 = glm::dot(L, L) - tm * tm;", "early exit when t_m < 0"),
 ("unitdir_h_sign", 3, F3, "out.t[0] = -h - s;\n    out.t[1] = -h + s;", "out.t[0] = h - s;\n    out.t[1] = h + s;", "t = h -+ sqrt (sign of h)"),
 ("geom_L_reversed", 3, F3, "glm::vec3 L = sphere.center - ray.origin;", "glm::vec3 L = ray.origin - sphere.center;", "L = o - c (f) in the drawing"),
 ("geom_r_not_squared", 3, F3, "float dt2 = r2 - lm2;", "float dt2 = sphere.radius - lm2;", "dt^2 = r - l_m^2"),
 ("unitdir_c_from_origin", 3, F3, "float c = glm::dot(f, f) - sphere.radius * sphere.radius;", "float c = glm::dot(ray.origin, ray.origin) - sphere.radius * sphere.radius;", "c' = o.o - r^2 (no f)"),
 ("unitdir_full_b", 3, F3, "float h = glm::dot(f, ray.direction);", "float h = 2.0f * glm::dot(f, ray.direction);", "h = 2 f.d (forgets the half-b form)"),
 ("geom_tangent_twice", 3, F3, "if (dt2 == 0) {", "if (false && dt2 == 0) {", "geometric form counts a tangent twice"),
 ("no_axis_check", 4, F4, "if (rect.axis < 0 || rect.axis > 2) return std::nullopt;\n", "", "bad axis not rejected"),
 ("uv_cyclic_order", 4, F4, "const int ua = (a == 0) ? 1 : 0;\n    const int va = (a == 2) ? 1 : 2;", "const int ua = (a + 1) % 3;\n    const int va = (a + 2) % 3;", "(u, v) in cyclic order: (z, x) for axis 1"),
 ("strict_edges", 4, F4, "if (!(rect.lo.x <= u && u <= rect.hi.x)) return std::nullopt;\n    if (!(rect.lo.y <= v && v <= rect.hi.y)) return std::nullopt;", "if (!(rect.lo.x < u && u < rect.hi.x)) return std::nullopt;\n    if (!(rect.lo.y < v && v < rect.hi.y)) return std::nullopt;", "edges excluded"),
 ("t_sign", 4, F4, "const float t = (rect.offset - ray.origin[a]) / da;", "const float t = (ray.origin[a] - rect.offset) / da;", "t = (o - offset)/d"),
 ("no_window", 4, F4, "if (!(tmin <= t && t <= tmax)) return std::nullopt;", "", "window never checked"),
 ("parallel_epsilon", 4, F4, "if (da == 0.0f) return std::nullopt;", "if (std::fabs(da) < 1e-4f) return std::nullopt;", "parallel test with epsilon 1e-4"),
 # As first recorded, this slip deleted the light's line instead of moving it (a slip of the trial's own
 # script: the kit rightly said the light is missing); it now moves the light after the ceiling.
 ("ceiling_before_light", 5, F5c, "    s.objects.push_back({\"light\", Rect{1, 548.8f, {213, 227}, {343, 332}}, light});\n    s.objects.push_back({\"floor\", Rect{1, 0.0f, {0, 0}, {556, 559.2f}}, white});\n    s.objects.push_back({\"ceiling\", Rect{1, 548.8f, {0, 0}, {556, 559.2f}}, white});\n", "    s.objects.push_back({\"floor\", Rect{1, 0.0f, {0, 0}, {556, 559.2f}}, white});\n    s.objects.push_back({\"ceiling\", Rect{1, 548.8f, {0, 0}, {556, 559.2f}}, white});\n    s.objects.push_back({\"light\", Rect{1, 548.8f, {213, 227}, {343, 332}}, light});\n", "light listed after the ceiling"),
 ("walls_swapped", 5, F5c, "Rect{0, 556.0f, {0, 0}, {548.8f, 559.2f}}, red});\n    s.objects.push_back({\"right wall\", Rect{0, 0.0f,", "Rect{0, 0.0f, {0, 0}, {548.8f, 559.2f}}, red});\n    s.objects.push_back({\"right wall\", Rect{0, 556.0f,", "left wall at x = 0, right at 556"),
 ("floor_uv_swapped", 5, F5c, "{\"floor\", Rect{1, 0.0f, {0, 0}, {556, 559.2f}}", "{\"floor\", Rect{1, 0.0f, {0, 0}, {559.2f, 556}}", "floor's hi as (z, x)"),
 ("tie_last_wins", 5, F5r, "*t < best->t", "*t <= best->t", "<= in the closest hit: last on a tie"),
 ("keep_last_hit", 5, F5r, "if (t && (!best || *t < best->t))", "if (t && *t <= tmax)", "compares with tmax, not best.t"),
 ("no_half_pixel", 5, F5r, "const float x = ((i + 0.5f) / W - 0.5f) * wf;\n    const float y = (0.5f - (j + 0.5f) / H) * hf;", "const float x = (i / W - 0.5f) * wf;\n    const float y = (0.5f - j / H) * hf;", "pixel corner, not centre"),
 ("no_aspect", 5, F5r, "const float wf = hf * W / H;", "const float wf = hf;", "film width = film height"),
 ("int_aspect", 5, F5r, "const float wf = hf * W / H;", "const float wf = hf * (camera.width / camera.height);", "aspect ratio in integer division"),
 ("no_row_flip", 5, F5r, "const float y = (0.5f - (j + 0.5f) / H) * hf;", "const float y = ((j + 0.5f) / H - 0.5f) * hf;", "row 0 at the bottom"),
 ("right_reversed", 5, F5r, "glm::cross(camera.forward, camera.up)", "glm::cross(camera.up, camera.forward)", "r = u x g"),
 ("loops_swapped", 5, F5r, "for (int j = 0; j < camera.height; ++j) {\n        for (int i = 0; i < camera.width; ++i) {", "for (int j = 0; j < camera.width; ++j) {\n        for (int i = 0; i < camera.height; ++i) {", "loop bounds swapped (width rows)"),
 ("render_tmax_mm", 5, F5r, "std::numeric_limits<float>::infinity()", "1000.0f", "render window ends at 1000 (a distance in mm)"),
]

// Step 05 grading suite, part 3: view_ray, the ray through a pixel's centre
// (steps/05_cornell_box/render.cpp).
//
// A direction may have any positive length, so each ray is checked by the
// point where it crosses the film: o + d (F / (d . f)), which is the same
// for every positive multiple of d.

#include <cmath>
#include <optional>
#include <string>

#include <doctest/doctest.h>

#include <glm/geometric.hpp>

#include "cornell_checks.hpp"
#include "../support/relations.hpp"
#include "raykit/render.hpp"

using namespace raykit;
using namespace raykit::grading;

namespace {

// Eye (1, 2, 3) looking along -z, up +y, so right is +x. The film is 2 away,
// 2 high and, for 4 x 2 pixels, 4 wide: pixel (i, j) has its centre at
// x = i - 1.5, y = 0.5 - j on the film, which is the plane z = 1.
const Camera wide{{1, 2, 3}, {0, 0, -1}, {0, 1, 0}, 2.0f, 2.0f, 4, 2};

// Measured on the answer: the film point mirrored left to right, or top to bottom, about the film's
// centre, which right = up x forward, or rows counted from the bottom, give. Empty otherwise.
std::string mirror_cause(const Camera& camera, const glm::vec3& expected, const glm::vec3& got) {
    // Offsets from the film's centre split into along up and across it (these cameras' up is a unit
    // vector square to forward), with no camera basis built here: the handout ships this file.
    const glm::vec3 centre = camera.eye + camera.focal_length * camera.forward;
    const glm::vec3 e = expected - centre, g = got - centre;
    const float eu = glm::dot(e, camera.up), gu = glm::dot(g, camera.up);
    const glm::vec3 ea = e - eu * camera.up, ga = g - gu * camera.up;
    const float tol = 1e-4f * (1.0f + glm::length(e));
    const bool across_same = glm::length(ga - ea) <= tol, across_flipped = glm::length(ea) > tol && glm::length(ga + ea) <= tol;
    const bool up_same = std::fabs(gu - eu) <= tol, up_flipped = std::fabs(eu) > tol && std::fabs(gu + eu) <= tol;
    if (across_flipped && up_same)
        return "Your point is the expected one mirrored left to right: your offset across the film grows to the "
               "left as i grows. Either right is taken as up x forward (it must be forward x up), or the offset is "
               "taken as half the width minus the pixel's position, where it is ((i + 0.5) / width - 0.5) times "
               "the film's width (lecture 05, section 5). ";
    if (up_flipped && across_same)
        return "Your point is the expected one mirrored top to bottom: row 0 is the top of the image, so the "
               "offset along up is (0.5 - (j + 0.5) / height) * film_height (lecture 05, section 6). ";
    if (across_flipped && up_flipped)
        return "Your point is the expected one mirrored both ways, left to right and top to bottom: right is "
               "forward x up, row 0 the top (lecture 05, sections 5 and 6). ";
    return "";
}

// Measured on the answer: the film point is a corner of the pixel, half a pixel above the expected
// centre and half a pixel across, on the line of the centre's own offset across the film, which an
// integer 1 / 2 (it is 0) in the pixel's centre gives. Read off the expected point and the pixel's size
// alone, offsets split as mirror_cause's: the handout ships this file, so no pixel centre is computed.
std::string corner_cause(const Camera& camera, const glm::vec3& expected, const glm::vec3& got) {
    const glm::vec3 centre = camera.eye + camera.focal_length * camera.forward;
    const glm::vec3 e = expected - centre, g = got - centre;
    const float eu = glm::dot(e, camera.up), gu = glm::dot(g, camera.up);
    const glm::vec3 ea = e - eu * camera.up, ga = g - gu * camera.up;
    const float pixel_height = camera.film_height / float(camera.height);
    const float pixel_width = pixel_height;     // square pixels
    const float tol = 1e-4f * (1.0f + glm::length(e));
    if (!(std::fabs((gu - eu) - pixel_height / 2) <= tol)) return "";
    const glm::vec3 shift = ga - ea;
    if (!(std::fabs(glm::length(shift) - pixel_width / 2) <= tol)) return "";
    if (glm::length(ea) > tol && !(glm::length(glm::cross(shift, ea)) <= tol * glm::length(ea))) return "";
    return "Your ray passes through a corner of the pixel, half a pixel across and half a pixel up from its "
           "centre: the ray goes through the pixel's centre, half a pixel in from its edges. In C++ 1 / 2 "
           "divides two ints and gives 0; write 0.5f (lecture 05, section 5). ";
}

// The point where view_ray(camera, i, j)'s ray crosses the film (the plane focal_length in front of the
// eye), or nothing when the ray does not start at the eye or point forward.
std::optional<glm::vec3> film_point(const Camera& camera, int i, int j) {
    const Ray ray = view_ray(camera, i, j);
    const float along = glm::dot(ray.direction, camera.forward);
    if (!(glm::length(ray.origin - camera.eye) <= 1e-5f) || !(along > 0.0f)) return std::nullopt;
    return ray.origin + ray.direction * (camera.focal_length / along);
}

// Measured on the function: the film point is half a pixel off the expected one, across the film or along
// up (not both: corner_cause), and the next pixel's point along that way is one pixel from it, as it must
// be: the scale is right and the pixel's centre is not, its + 1/2 left out. A scale slip moves the next
// pixel by other than one pixel, so the two are told apart even where a corner's offset is twice a
// centre's (pixel 0 of 2). Read off the expected point and the pixel's size, as corner_cause.
std::string half_pixel_cause(const Camera& camera, int i, int j, const glm::vec3& expected, const glm::vec3& got) {
    const glm::vec3 centre = camera.eye + camera.focal_length * camera.forward;
    const glm::vec3 e = expected - centre, g = got - centre;
    const float eu = glm::dot(e, camera.up), gu = glm::dot(g, camera.up);
    const glm::vec3 ea = e - eu * camera.up, ga = g - gu * camera.up;
    const float pixel = camera.film_height / float(camera.height);   // square pixels
    const float tol = 1e-4f * (1.0f + glm::length(e));
    const bool up_same = std::fabs(gu - eu) <= tol, up_half = std::fabs(std::fabs(gu - eu) - pixel / 2) <= tol;
    const bool across_same = glm::length(ga - ea) <= tol,
               across_half = std::fabs(glm::length(ga - ea) - pixel / 2) <= tol &&
                             (!(glm::length(ea) > tol) || glm::length(glm::cross(ga - ea, ea)) <= tol * glm::length(ea));
    const bool across = across_half && up_same, along_up = up_half && across_same;
    if (!across && !along_up) return "";
    // The next pixel the same way (the one before, at the last column or row), one pixel away when right.
    const int i2 = across ? (i + 1 < camera.width ? i + 1 : i - 1) : i;
    const int j2 = along_up ? (j + 1 < camera.height ? j + 1 : j - 1) : j;
    if (i2 < 0 || j2 < 0) return "";
    const std::optional<glm::vec3> next = film_point(camera, i2, j2);
    if (!next || !(std::fabs(glm::length(*next - got) - pixel) <= tol)) return "";
    return std::string("Measured on your function: your point is half a pixel ") +
           (across ? "across the film" : "up or down") + " from the expected one, and the next " +
           (across ? "column's" : "row's") + " point is one pixel from yours, so the film's scale is right: "
           "the ray passes through the pixel's corner, not its centre (+ 1/2). The centre of " +
           (across ? "column i is (i + 1/2) / width" : "row j is (j + 1/2) / height") +
           " of the way across the film, half a pixel in from its edge (lecture 05, section 5). ";
}

// Measured on the answer: the film point's offset from the film's centre scaled, across the film only
// (the film's width taken from another length: its height, an inverted aspect) or across and along up
// alike (the film at another distance: the focal length left out or used twice). Empty otherwise.
std::string scale_cause(const Camera& camera, const glm::vec3& expected, const glm::vec3& got) {
    const glm::vec3 centre = camera.eye + camera.focal_length * camera.forward;
    const glm::vec3 e = expected - centre, g = got - centre;
    const float eu = glm::dot(e, camera.up), gu = glm::dot(g, camera.up);
    const glm::vec3 ea = e - eu * camera.up, ga = g - gu * camera.up;
    const float tol = 1e-4f * (1.0f + glm::length(e));
    if (!(glm::length(ea) > tol)) return "";
    const float k = glm::dot(ga, ea) / glm::dot(ea, ea);
    // The aspect ratio in ints: width / height rounded down (2 / 8 = 0) scales the offset across by
    // (its int quotient) / (its real quotient).
    const float ratio = float(camera.width) / float(camera.height);
    const int whole = camera.width / camera.height;
    if (float(whole) != ratio && std::fabs(k - float(whole) / ratio) <= 1e-3f && glm::length(ga - k * ea) <= tol &&
        std::fabs(gu - eu) <= tol)
        return "Your point's offset across the film is " + show(k) + " times the expected one, and its offset "
               "along up is right: that is the film's width computed with width / height in ints, which drops the "
               "fraction (" + std::to_string(camera.width) + " / " + std::to_string(camera.height) + " = " +
               std::to_string(whole) + " in C++). Convert to float before dividing: film_height * float(width) / "
               "float(height) (lecture 05, section 5). ";
    if (!(k > 0.0f) || std::fabs(k - 1.0f) <= 1e-3f || glm::length(ga - k * ea) > tol) return "";
    if (std::fabs(gu - eu) <= tol)
        return "Your point's offset across the film is " + show(k) + " times the expected one, and its offset "
               "along up is right: scale x by the film's width, film_height * width / height, not by its "
               "height or another length (lecture 05, section 5). ";
    if (std::fabs(eu) > tol && std::fabs(gu - k * eu) <= tol)
        return "Your point's offset from the film's centre is " + show(k) + " times the expected one, across and "
               "along up alike: your film is not focal_length in front of the eye. The direction's forward "
               "part is focal_length * forward (lecture 05, sections 5 and 6). ";
    return "";
}

// Measured on the answer: the direction is the film point itself, not the film point minus the eye.
std::string film_point_cause(const Camera& camera, const Ray& ray, const glm::vec3& expected) {
    const float tol = 1e-5f * (1.0f + glm::length(expected));
    if (glm::length(camera.eye) > tol && glm::length(ray.direction - expected) <= tol)
        return "Your direction is the film point itself: a direction is where the ray goes minus where it "
               "starts, the film point minus the eye (lecture 05, section 6). ";
    return "";
}

// Measured on the function (trial 8, issue 54): the film point is half the film off the expected one
// along up, and so is the next row's: every row is shifted by half the film, the 0.5 in the offset left
// out, as an integer 1 / 2 (0 in C++) does. Told apart from a mirror, which in a 2-row image puts row 0
// where the shift does but moves the next row the other way. Along up only: no camera basis is built
// here (the handout ships this file). The formula is written with 0.5, never 1/2, which reads like the
// student's own integer division.
std::string half_film_cause(const Camera& camera, int i, int j, const glm::vec3& expected, const glm::vec3& got) {
    const glm::vec3 centre = camera.eye + camera.focal_length * camera.forward;
    const glm::vec3 e = expected - centre, g = got - centre;
    const float eu = glm::dot(e, camera.up), gu = glm::dot(g, camera.up);
    const glm::vec3 ea = e - eu * camera.up, ga = g - gu * camera.up;
    const float pixel = camera.film_height / float(camera.height);   // square pixels
    const float tol = 1e-4f * (1.0f + glm::length(e));
    if (!(glm::length(ga - ea) <= tol && std::fabs(std::fabs(gu - eu) - camera.film_height / 2) <= tol)) return "";
    // The next row (the one before, at the last): its expected point one pixel down from this one's.
    const int j2 = j + 1 < camera.height ? j + 1 : j - 1;
    if (j2 < 0) return "";
    const std::optional<glm::vec3> next = film_point(camera, i, j2);
    if (!next) return "";
    const glm::vec3 next_expected = expected - float(j2 - j) * pixel * camera.up;
    if (!(glm::length((*next - next_expected) - (got - expected)) <= tol)) return "";
    return "Measured on your function: your point is half the film (" + show(camera.film_height / 2) + ") " +
           (gu < eu ? "down" : "up") + " from the expected one, in row " + std::to_string(j) + " and in row " +
           std::to_string(j2) + " alike: every row is shifted by half the film, as if the 0.5 in the offset along "
           "up were 0. In C++ 1 / 2 divides two ints and gives 0; write 0.5f. The offset along up is "
           "(0.5 - (j + 0.5) / height) * film_height (lecture 05, section 6). ";
}

// Measured on the function (trial 9, issue 54): the film point is half the film's width off the expected
// one across the film, and so is the next column's: every column is shifted by half the film, the - 0.5
// that centres the offset across left out. Told apart from a mirror, which in a 2-column image puts
// column 0 where the shift does but moves the next column the other way. The direction across is read
// off the expected point (left of the centre for i + 0.5 < width / 2): no camera basis is built here.
std::string half_width_cause(const Camera& camera, int i, int j, const glm::vec3& expected, const glm::vec3& got) {
    if (camera.width < 2 || camera.height < 1) return "";
    const glm::vec3 centre = camera.eye + camera.focal_length * camera.forward;
    const glm::vec3 e = expected - centre, g = got - centre;
    const float eu = glm::dot(e, camera.up), gu = glm::dot(g, camera.up);
    const glm::vec3 ea = e - eu * camera.up, ga = g - gu * camera.up;
    const float film_width = camera.film_height * float(camera.width) / float(camera.height);
    const float pixel = camera.film_height / float(camera.height);   // square pixels
    const float tol = 1e-4f * (1.0f + glm::length(e));
    if (!(glm::length(ea) > tol && std::fabs(gu - eu) <= tol &&
          std::fabs(glm::length(ga - ea) - film_width / 2) <= tol))
        return "";
    const glm::vec3 right = glm::normalize(ea) * (2 * i + 1 < camera.width ? -1.0f : 1.0f);
    const int i2 = i + 1 < camera.width ? i + 1 : i - 1;
    const std::optional<glm::vec3> next = film_point(camera, i2, j);
    if (!next) return "";
    const glm::vec3 next_expected = expected + float(i2 - i) * pixel * right;
    if (!(glm::length((*next - next_expected) - (got - expected)) <= tol)) return "";
    const bool to_right = glm::dot(got - expected, right) > 0.0f;
    return "Measured on your function: your point is half the film's width (" + show(film_width / 2) + ") " +
           (to_right ? "right" : "left") + " of the expected one, in column " + std::to_string(i) + " and in column " +
           std::to_string(i2) + " alike: every column is shifted by half the film, as if the - 0.5 that centres "
           "the offset across were left out. The offset across is ((i + 0.5) / width - 0.5) * film_width "
           "(lecture 05, section 5). ";
}

void expect_film_point(const Camera& camera, int i, int j, const glm::vec3& expected, const std::string& why) {
    const Ray ray = view_ray(camera, i, j);
    const std::string call = "view_ray(camera, " + std::to_string(i) + ", " + std::to_string(j) + ")";
    const std::string input = show(camera);
    if (!(glm::length(ray.origin - camera.eye) <= 1e-5f)) {
        FAIL_CHECK(report(call, input, "origin " + show(camera.eye), "origin " + show(ray.origin),
                          "Every view ray starts at the eye."));
        return;
    }
    const float along = glm::dot(ray.direction, camera.forward);
    if (!(along > 0.0f)) {
        FAIL_CHECK(report(call, input, "a direction through " + show(expected), "direction " + show(ray.direction),
                          film_point_cause(camera, ray, expected) +
                              "The ray must point forward, through the film in front of the eye."));
        return;
    }
    const glm::vec3 got = ray.origin + ray.direction * (camera.focal_length / along);
    const bool ok = glm::length(got - expected) <= 1e-5f * (1.0f + glm::length(expected));
    if (!ok) {
        std::string corner = corner_cause(camera, expected, got);
        if (corner.empty()) corner = half_pixel_cause(camera, i, j, expected, got);
        if (corner.empty()) corner = half_film_cause(camera, i, j, expected, got);
        if (corner.empty()) corner = half_width_cause(camera, i, j, expected, got);
        FAIL_CHECK(report(call, input, "a ray through " + show(expected) + " on the film",
                          "a ray through " + show(got) + " (direction " + show(ray.direction) + ")",
                          corner.empty() ? mirror_cause(camera, expected, got) + scale_cause(camera, expected, got) +
                                                   film_point_cause(camera, ray, expected) + why
                                             : corner + first_sentence(why)));
    }
}

}  // namespace

TEST_SUITE_BEGIN("basic");

TEST_CASE("the centre pixel of an odd-sized image looks straight ahead" * doctest::description("6. A view ray per pixel")) {
    const Camera c{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1.0f, 1.0f, 5, 3};
    expect_film_point(c, 2, 1, {0, 0, -1},
                      "Pixel (2, 1) is the middle of a 5 x 3 image: its centre, (2 + 1/2) / 5 = 1/2 across and "
                      "(1 + 1/2) / 3 = 1/2 down, is the film's centre, straight ahead.");
}

TEST_CASE("the top left pixel is up and to the left" * doctest::description("6. A view ray per pixel")) {
    expect_film_point(wide, 0, 0, {-0.5f, 2.5f, 1},
                      "Column 0 is the left, row 0 the top: the centre is 1.5 left (x = -1.5) and 0.5 up "
                      "(y = +0.5) from the film's centre (1, 2, 1). Rows count down from the top.");
}

TEST_CASE("the top right pixel" * doctest::description("6. A view ray per pixel")) {
    expect_film_point(wide, 3, 0, {2.5f, 2.5f, 1},
                      "Column 3 of 4: (3 + 1/2) / 4 - 1/2 = 3/8 of the 4-wide film, 1.5 to the right.");
}

TEST_CASE("the bottom left pixel" * doctest::description("6. A view ray per pixel")) {
    expect_film_point(wide, 0, 1, {-0.5f, 1.5f, 1},
                      "Row 1 of 2 is the bottom row: 1/2 - (1 + 1/2) / 2 = -1/4 of the 2-high film, 0.5 down.");
}

TEST_CASE("the bottom right pixel" * doctest::description("6. A view ray per pixel")) {
    expect_film_point(wide, 3, 1, {2.5f, 1.5f, 1}, "Column 3, row 1: 1.5 right and 0.5 down from the film's centre.");
}

TEST_CASE("the view ray starts at the eye" * doctest::description("6. A view ray per pixel")) {
    const Ray ray = view_ray(wide, 1, 1);
    if (!(glm::length(ray.origin - wide.eye) <= 1e-5f)) {
        FAIL_CHECK(report("view_ray(camera, 1, 1)", show(wide), "origin " + show(wide.eye),
                          "origin " + show(ray.origin), "A pinhole camera's rays all start at the eye."));
    }
}

TEST_CASE("pixels are square whatever the aspect ratio" * doctest::description("5. The camera")) {
    // 2 x 2 pixels on the same film height: the film is 2 wide, not 4, and
    // pixel (0, 0) is 0.5 left, not 1.5.
    const Camera square{{1, 2, 3}, {0, 0, -1}, {0, 1, 0}, 2.0f, 2.0f, 2, 2};
    expect_film_point(square, 0, 0, {0.5f, 2.5f, 1},
                      "The film's width is film_height * width / height: 2 for a 2 x 2 image. Pixel (0, 0) is "
                      "0.5 left and 0.5 up.");
}

TEST_CASE("a wide image sees more to the sides" * doctest::description("5. The camera")) {
    const Camera panorama{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1.0f, 1.0f, 8, 2};
    expect_film_point(panorama, 7, 1, {1.75f, -0.25f, -1},
                      "8 x 2 pixels on a film 1 high: the film is 4 wide, so the last column's centre is "
                      "(7.5 / 8 - 0.5) * 4 = 1.75 to the right. Scale x by the film's width, not its height.");
}

TEST_CASE("a tall image" * doctest::description("5. The camera")) {
    const Camera tall{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1.0f, 4.0f, 2, 8};
    expect_film_point(tall, 0, 7, {-0.25f, -1.75f, -1},
                      "2 x 8 pixels on a film 4 high: the film is 1 wide; pixel (0, 7) is 0.25 left and "
                      "(0.5 - 7.5 / 8) * 4 = -1.75 down.");
}

TEST_CASE("looking along +z the image's left is +x" * doctest::description("5. The camera")) {
    const Camera c{{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, 1.0f, 2.0f, 2, 2};
    expect_film_point(c, 0, 0, {0.5f, 0.5f, 1},
                      "right = forward x up = (0, 0, 1) x (0, 1, 0) = (-1, 0, 0), so the left column is at +x. "
                      "This is the Cornell camera's orientation: swapped red and green walls come from here.");
}

TEST_CASE("a camera looking down uses its own up vector" * doctest::description("5. The camera")) {
    // forward -y, up +z: right = (0, -1, 0) x (0, 0, 1) = (-1, 0, 0).
    const Camera c{{0, 10, 0}, {0, -1, 0}, {0, 0, 1}, 2.0f, 2.0f, 2, 2};
    expect_film_point(c, 1, 0, {-0.5f, 8, 0.5f},
                      "The film is 2 below the eye; up is +z and right = forward x up = (-1, 0, 0). Pixel (1, 0), "
                      "top right, is 0.5 along right and 0.5 along up. Use the camera's vectors, not world axes.");
}

TEST_CASE("the film's size sets the field of view" * doctest::description("5. The camera")) {
    const Camera c{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0.5f, 3.0f, 3, 3};
    expect_film_point(c, 0, 2, {-1, -1, -0.5f},
                      "A film 3 x 3 at distance 0.5: pixel (0, 2), bottom left, has its centre at "
                      "x = (0.5 / 3 - 0.5) * 3 = -1 and y = (0.5 - 2.5 / 3) * 3 = -1.");
}

TEST_SUITE_END();

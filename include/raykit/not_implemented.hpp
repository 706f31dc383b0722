/// \file not_implemented.hpp
/// \brief How a stub says "I have not been written yet".
///
/// Every function a student writes starts life as a stub that calls
/// raykit::not_implemented_yet(). The grader recognises the exception it
/// throws and shows the step as "not started" instead of a wall of failures.
#pragma once

#include <stdexcept>
#include <string>

namespace raykit {

/// Thrown by a stub that the student has not filled in yet.
///
/// The message starts with the marker `raykit::not_implemented`, which is what
/// the grader looks for. Do not catch it in your own code.
struct not_implemented : std::logic_error {
    /// \param function the name of the function that is still a stub.
    explicit not_implemented(const std::string& function)
        : std::logic_error("raykit::not_implemented: " + function + " is not written yet") {}
};

/// Throws raykit::not_implemented for \p function. Delete the call when you
/// write the function's body.
///
/// A stub passes its parameters along, `not_implemented_yet("view_ray", camera, i, j);`,
/// only so that they count as used: the compiler's warning about unused
/// parameters stays quiet without a `(void)x;` line for each, and the stub is
/// one line. They are not read.
///
/// \param function the name of the function that is still a stub, as the
///        grader shows it.
/// \param unused the stub's parameters, any number of any type.
template <typename... Unused>
[[noreturn]] void not_implemented_yet(const char* function, const Unused&... unused) {
    // A fold over the comma operator: each parameter is named once, cast to void.
    ((void)unused, ...);
    throw not_implemented(function);
}

}  // namespace raykit

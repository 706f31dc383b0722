// The answers process: the student's functions and this dispatcher, nothing else.
//
// It reads calls from fd 0, runs them, and writes each answer to fd 3; what the
// student's code prints goes to fd 1 and 2, which the judge reads apart. It
// knows nothing of cases, expected values or verdicts, so there is nothing here
// a student's code could change to pass: whatever it writes is, at most, an answer.
//
// The functions it serves are the step's list (step.json's "functions", and
// those of the steps it needs, with their headers' signatures: CMake writes the
// list, cmake/StepManifest.cmake), included through RAYKIT_REMOTE_LIST.

#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <tuple>
#include <typeinfo>
#include <utility>

#include <cxxabi.h>

#include "raykit/not_implemented.hpp"
#include "fd_io.hpp"
#include "wire.hpp"

// The declarations of every step function: each header of include/raykit/, listed by CMake.
#include RAYKIT_API_HEADERS

namespace {

using namespace raykit;

using wire::read_exact;
using wire::write_exact;

/// Decodes the arguments `f` takes, calls it, encodes what it returns.
template <class R, class... A>
void serve(R (*f)(A...), wire::Reader& in, wire::Writer& out) {
    // A braced list evaluates left to right: the arguments are read in order.
    std::tuple<std::decay_t<A>...> args{wire::get<A>(in)...};
    R result = std::apply(f, args);
    out.raw(wire::Kind::value);
    wire::put(out, result);
}

std::string type_name(const std::type_info& t) {
    int status = 0;
    char* name = abi::__cxa_demangle(t.name(), nullptr, nullptr, &status);
    std::string s = status == 0 && name ? name : t.name();
    std::free(name);
    return s;
}

void answer(const std::string& function, wire::Reader& in, wire::Writer& out) {
#define RAYKIT_REMOTE(ret, name, params, args) \
    if (function == #name) return serve(&raykit::name, in, out);
#include RAYKIT_REMOTE_LIST
#undef RAYKIT_REMOTE
    out.raw(wire::Kind::unknown);
}

}  // namespace

int main() {
    // Line-buffered: what the student prints reaches the judge by the end of the
    // call that printed it, even when a later line crashes.
    std::setvbuf(stdout, nullptr, _IOLBF, 1 << 12);
    // An empty frame first: "ready". The judge times each call from here, so neither the sandbox's
    // start nor the program's own is counted against a call.
    const std::uint32_t ready = 0;
    if (!write_exact(3, reinterpret_cast<const char*>(&ready), sizeof ready)) return 2;
    std::string request;
    for (;;) {
        std::uint32_t size = 0;
        if (!read_exact(0, reinterpret_cast<char*>(&size), sizeof size)) return 0;
        if (size == 0 || size > (16u << 20)) return 2;
        request.resize(size);
        if (!read_exact(0, request.data(), size)) return 2;
        const std::size_t name_size = static_cast<unsigned char>(request[0]);
        if (name_size + 1 > size) return 2;
        const std::string function = request.substr(1, name_size);
        wire::Reader in(request.data() + 1 + name_size, size - 1 - name_size);
        wire::Writer out;
        try {
            answer(function, in, out);
        } catch (const raykit::not_implemented& e) {
            out.bytes.clear();
            out.raw(wire::Kind::not_implemented);
            wire::put(out, std::string(e.what()));
        } catch (const std::exception& e) {
            out.bytes.clear();
            out.raw(wire::Kind::threw);
            std::string what = e.what();
            if (what.size() > 2000) what.resize(2000);
            wire::put(out, type_name(typeid(e)) + " (\"" + what + "\")");
        } catch (...) {
            out.bytes.clear();
            out.raw(wire::Kind::threw);
            wire::put(out, std::string("something that is not a std::exception"));
        }
        std::fflush(stdout);
        std::cout.flush();
        std::cerr.flush();
        const std::uint32_t reply = static_cast<std::uint32_t>(out.bytes.size());
        if (!write_exact(3, reinterpret_cast<const char*>(&reply), sizeof reply) ||
            !write_exact(3, out.bytes.data(), out.bytes.size()))
            return 2;
    }
}

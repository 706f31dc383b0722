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

#include <fcntl.h>
#include <sys/resource.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <tuple>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

#include <cxxabi.h>

#include "raykit/not_implemented.hpp"
#include "fd_io.hpp"
#include "platform.hpp"
#include "standin.hpp"
#include "wire.hpp"

// The declarations of every step function: each header of include/raykit/, listed by CMake.
#include RAYKIT_API_HEADERS

namespace {

using namespace raykit;

using wire::read_exact;
using wire::write_exact;

// ---- every argument in memory of its own size -----------------------------------------------
//
// A student's function gets each argument (and each list inside one: a scene's objects) in memory
// of exactly its size that ends at a guard page (platform::guarded_allocate), so reading past it,
// `(&ray.direction.x)[3]` or `i <= objects.size()`, faults at once in the student's own check and
// in the grade alike, whatever the compiler, the sanitizers or what lay beside it would have given.
// The fault names the argument (fault_note, read by remote.cpp). A read before the start lands in
// the rest of the page: a wrong answer, not a crash.

/// A guard page and the argument (1, 2, ...) whose memory ends where it begins.
struct Fence {
    std::uintptr_t begin, end;
    int argument;
    bool list;      // a list inside the argument (a scene's objects), not the argument itself
};
constexpr std::size_t max_fences = 4096;
Fence fences[max_fences];
std::size_t fence_count = 0;

std::uintptr_t page_after(const void* p, std::size_t size) {
    const std::uintptr_t page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    return (reinterpret_cast<std::uintptr_t>(p) + size + page - 1) / page * page;
}

void fence(const void* p, std::size_t size, int argument, bool list) {
    if (fence_count == max_fences) return;
    const std::uintptr_t begin = page_after(p, size);
    fences[fence_count++] = {begin, begin + static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE)), argument, list};
}

void unfence(const void* p, std::size_t size) {
    const std::uintptr_t begin = page_after(p, size);
    for (std::size_t i = fence_count; i-- > 0;)
        if (fences[i].begin == begin) {
            fences[i] = fences[--fence_count];
            return;
        }
}

struct sigaction previous_segv, previous_bus;

// The main stack, to tell a stack that ran out (an endless recursion) from any other bad access:
// its top is an address of main's frame, its size the soft limit the program started with. A fault
// below the top by most of that limit is the guard below the stack, whatever the platform: POSIX
// gives getrlimit and si_addr on Linux and macOS alike, and nothing needs the stack's exact bounds.
std::uintptr_t stack_top = 0;
std::uintptr_t stack_limit = std::uintptr_t{8} << 20;     // where the limit is infinite: the usual 8 MiB

bool past_the_stack(std::uintptr_t at) {
    if (stack_top == 0 || at >= stack_top) return false;
    const std::uintptr_t depth = stack_top - at;
    return depth > stack_limit / 4 * 3 && depth < stack_limit + (std::uintptr_t{64} << 20);
}

/// `text` then the decimal digits of `n` into `line` at `n_at`; async-signal-safe.
std::size_t put(char* line, std::size_t at, const char* text, std::uintptr_t n = ~std::uintptr_t{0}) {
    for (const char* c = text; *c; ++c) line[at++] = *c;
    if (n == ~std::uintptr_t{0}) return at;
    std::uintptr_t digits = 1;
    while (n / digits >= 10) digits *= 10;
    for (; digits > 0; digits /= 10) line[at++] = static_cast<char>('0' + n / digits % 10);
    return at;
}

/// On a fault in a guard page, says whose (one line on fd 2, "raykit-fault: past argument N"), then
/// lets the signal end the program as it would have: the judge sees the same death either way.
void on_fault(int signal, siginfo_t* info, void*) {
    const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(info->si_addr);
    for (std::size_t i = 0; i < fence_count; ++i) {
        if (at < fences[i].begin || at >= fences[i].end) continue;
        char line[96] = "raykit-fault: past ";
        std::size_t n = std::strlen(line);
        const char* what = fences[i].list ? "a list in argument " : "argument ";
        for (const char* c = what; *c; ++c) line[n++] = *c;
        int a = fences[i].argument, digits = 1;
        while (a / (digits * 10) > 0) digits *= 10;
        for (; digits > 0; digits /= 10) line[n++] = static_cast<char>('0' + a / digits % 10);
        line[n++] = '\n';
        (void)!::write(2, line, n);
        break;
    }
    if (past_the_stack(at)) {   // "raykit-fault: stack 8 MiB", what the calls had used when it ran out
        char line[64];
        std::size_t n = put(line, 0, "raykit-fault: stack ", (stack_top - at) >> 20);
        n = put(line, n, " MiB\n");
        (void)!::write(2, line, n);
    }
    // Back to what was there before (the default: end the program); the access faults again.
    ::sigaction(signal, signal == SIGBUS ? &previous_bus : &previous_segv, nullptr);
}

void watch_faults() {
    // The handler runs on a stack of its own: on the main stack, which a fault at its end has used
    // up, it could not run at all.
    static char handler_stack[64 * 1024];
    stack_t alternate{};
    alternate.ss_sp = handler_stack;
    alternate.ss_size = sizeof handler_stack;
    ::sigaltstack(&alternate, nullptr);
    struct rlimit limit{};
    if (::getrlimit(RLIMIT_STACK, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
        stack_limit = static_cast<std::uintptr_t>(limit.rlim_cur);
    struct sigaction on{};
    on.sa_sigaction = on_fault;
    on.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigemptyset(&on.sa_mask);
    ::sigaction(SIGSEGV, &on, &previous_segv);
    ::sigaction(SIGBUS, &on, &previous_bus);    // macOS reports some guard-page faults as SIGBUS
}

/// While an argument is decoded (its number here), every allocation (a vector's buffer, a long
/// string's) is a guarded one; the student's own allocations never are.
int decoding = 0;
struct Guarded {
    void* p;
    std::size_t size;
};
constexpr std::size_t max_guarded = 4096;
Guarded guarded[max_guarded];
std::size_t guarded_count = 0;

void* allocate(std::size_t size) {
    if (size == 0) size = 1;
    if (decoding > 0 && guarded_count < max_guarded) {
        // The largest power of two dividing the size, up to what `new` promises: an array of T
        // (size n * sizeof(T)) then ends exactly at the guard.
        const std::size_t lowest = size & (~size + 1), most = __STDCPP_DEFAULT_NEW_ALIGNMENT__;
        const std::size_t align = lowest < most ? lowest : most;
        if (void* p = platform::guarded_allocate(size, align)) {
            guarded[guarded_count++] = {p, size};
            fence(p, size, decoding, true);
            return p;
        }
    }
    if (void* p = std::malloc(size)) return p;
    throw std::bad_alloc();
}

void release(void* p) noexcept {
    if (p == nullptr) return;
    for (std::size_t i = guarded_count; i-- > 0;) {
        if (guarded[i].p == p) {
            unfence(p, guarded[i].size);
            platform::guarded_release(p, guarded[i].size);
            guarded[i] = guarded[--guarded_count];
            return;
        }
    }
    std::free(p);
}

}  // namespace

// Set by a stand-in's object when the program has one (standin_04.cpp); constant-initialised, so
// set before any dynamic initialiser may read it.
raykit::standin::Receiver raykit::standin::receiver = nullptr;
// Set by the reference's script answerer (script_04.cpp), never in a student's program.
raykit::standin::LinesServer raykit::standin::lines_server = nullptr;

void* operator new(std::size_t size) { return allocate(size); }
void* operator new[](std::size_t size) { return allocate(size); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }

namespace {

/// One argument's slot: the memory position I of a function's arguments of type T is handed over
/// in, made once (an mmap per call would cost the hidden cases' thousands of calls).
template <class T, std::size_t I>
T* slot() {
    static void* memory = [] {
        void* p = platform::guarded_allocate(sizeof(T), alignof(T));
        if (p != nullptr) fence(p, sizeof(T), static_cast<int>(I) + 1, false);
        return p;
    }();
    if (memory == nullptr) throw std::bad_alloc();
    return static_cast<T*>(memory);
}

/// An argument in its slot, destroyed (its guarded lists given back) when the call is over. (Not a
/// std::unique_ptr with a deleter: <memory> and <algorithm> were a tenth of this file's compile.)
template <class T>
class Held {
public:
    explicit Held(T* p) : p_(p) {}
    Held(Held&& other) noexcept : p_(other.p_) { other.p_ = nullptr; }
    Held(const Held&) = delete;
    Held& operator=(const Held&) = delete;
    Held& operator=(Held&&) = delete;
    ~Held() {
        if (p_ != nullptr) p_->~T();
    }
    T& operator*() const { return *p_; }

private:
    T* p_;
};

template <class T, std::size_t I>
Held<T> hold(wire::Reader& in) {
    decoding = static_cast<int>(I) + 1;
    struct Off {
        ~Off() { decoding = 0; }
    } off;
    return Held<T>(new (slot<T, I>()) T(wire::get<T>(in)));
}

template <class R, class... A, std::size_t... I>
void serve(R (*f)(A...), wire::Reader& in, wire::Writer& out, std::index_sequence<I...>) {
    // A braced list evaluates left to right: the arguments are read in order.
    std::tuple<Held<std::decay_t<A>>...> args{hold<std::decay_t<A>, I>(in)...};
    R result = std::apply([f](auto&... held) { return f(*held...); }, args);
    out.raw(wire::Kind::value);
    wire::put(out, result);
}

/// Decodes the arguments `f` takes, calls it, encodes what it returns.
template <class R, class... A>
void serve(R (*f)(A...), wire::Reader& in, wire::Writer& out) {
    serve(f, in, out, std::index_sequence_for<A...>{});
}

/// "raykit.grid.NAME": NAME(first, i, j) for every (i, j) of a w x h grid, row by row (j outer, as a
/// render's loop goes), their answers as one list: a render case's view rays in one call instead of
/// one a pixel (proxies.cpp). Each call gets its own copy of `first` in its guarded slot, as a call
/// of its own would. Only for a function of (T, int, int); any other says it has none.
template <class R, class C>
void serve_grid(R (*f)(C, int, int), wire::Reader& in, wire::Writer& out) {
    using T = std::decay_t<C>;
    const T first = wire::get<T>(in);
    const int w = wire::get<int>(in), h = wire::get<int>(in);
    if (!in.at_end() || w < 0 || h < 0 || static_cast<long long>(w) * h > wire::max_items)
        throw wire::wire_error("a grid the grader does not ask for");
    std::vector<R> results;
    results.reserve(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            Held<T> held(new (slot<T, 0>()) T(first));
            results.push_back(f(*held, i, j));
        }
    out.raw(wire::Kind::value);
    wire::put(out, results);
}

template <class F>
void serve_grid(F, wire::Reader&, wire::Writer& out) {
    out.raw(wire::Kind::unknown);
}

std::string type_name(const std::type_info& t) {
    int status = 0;
    char* name = abi::__cxa_demangle(t.name(), nullptr, nullptr, &status);
    std::string s = status == 0 && name ? name : t.name();
    std::free(name);
    return s;
}

void answer(const std::string& function, wire::Reader& in, wire::Writer& out) {
    if (function == standin::message) {     // the judge's script for a stand-in (standin.hpp)
        if (standin::receiver == nullptr) return out.raw(wire::Kind::unknown);
        standin::receiver(in);
        out.raw(wire::Kind::value);
        return wire::put(out, 0);
    }
    if (function == standin::lines_message) {   // the reference's answers for a whole script
        if (standin::lines_server == nullptr) return out.raw(wire::Kind::unknown);
        out.raw(wire::Kind::value);
        return standin::lines_server(in, out);
    }
    if (function.rfind("raykit.grid.", 0) == 0) {
#define RAYKIT_REMOTE(ret, name, params, args) \
    if (function == "raykit.grid." #name) return serve_grid(&raykit::name, in, out);
#include RAYKIT_REMOTE_LIST
#undef RAYKIT_REMOTE
        return out.raw(wire::Kind::unknown);
    }
#define RAYKIT_REMOTE(ret, name, params, args) \
    if (function == #name) return serve(&raykit::name, in, out);
#include RAYKIT_REMOTE_LIST
#undef RAYKIT_REMOTE
    out.raw(wire::Kind::unknown);
}

}  // namespace

int main(int argc, char** argv) {
    // Line-buffered: what the student prints reaches the judge by the end of the
    // call that printed it, even when a later line crashes.
    std::setvbuf(stdout, nullptr, _IOLBF, 1 << 12);
    volatile char top = 0;
    stack_top = reinterpret_cast<std::uintptr_t>(&top);
    watch_faults();
    // Calls come on fd 0 and answers go to fd 3, from and to the judge. `--replay FILE`: the calls of
    // one case, recorded by the judge (RAYKIT_CALL_LOG, remote.cpp), from FILE, their answers to
    // nowhere: ./kit debug runs a case in this one process under the debugger, which then needs to
    // follow no fork (LLDB on macOS cannot).
    int calls = 0, answers = 3;
    if (argc == 3 && std::strcmp(argv[1], "--replay") == 0) {
        calls = ::open(argv[2], O_RDONLY | O_CLOEXEC);
        answers = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (calls < 0 || answers < 0) {
            std::fprintf(stderr, "answers: cannot read the recorded calls in %s\n", argv[2]);
            return 2;
        }
    }
    // An empty frame first: "ready". The judge times each call from here, so neither the sandbox's
    // start nor the program's own is counted against a call.
    const std::uint32_t ready = 0;
    if (!write_exact(answers, reinterpret_cast<const char*>(&ready), sizeof ready)) return 2;
    std::string request;
    for (;;) {
        std::uint32_t size = 0;
        if (!read_exact(calls, reinterpret_cast<char*>(&size), sizeof size)) return 0;
        if (size == 0 || size > (16u << 20)) return 2;
        request.resize(size);
        if (!read_exact(calls, request.data(), size)) return 2;
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
        if (!write_exact(answers, reinterpret_cast<const char*>(&reply), sizeof reply) ||
            !write_exact(answers, out.bytes.data(), out.bytes.size()))
            return 2;
    }
}

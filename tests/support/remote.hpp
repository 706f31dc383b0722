// The judge's side of the wire: calls a step function in the answers process
// and brings back its answer, or says exactly which call went wrong.
//
// The test program (the judge) never links a student's code. Each step function
// it calls is a proxy (tests/support/proxies.cpp) that sends the call to a child
// process built from the student's sources plus a dispatcher
// (tests/support/answers_main.cpp), waits at most a set time for the reply, and
// decodes it. A crash, a time-out or a garbled reply becomes an exception naming
// the function and its arguments; the child is started again for the next call.
// What the student's code prints arrives on its own pipe and is kept per case.
//
// Where the child runs is set by the environment, so that ctest can run a test
// program on its own:
//   RAYKIT_ANSWERS            the answers program (default: the one built beside it)
//   RAYKIT_REFERENCE_ANSWERS  the reference's answers program, for hidden cases
//   RAYKIT_ISOLATION          none | bwrap | user:UID   (default none)
//   RAYKIT_SCRATCH            where each start of the child gets a fresh folder, its only writable one (default: a new one)
//   RAYKIT_SANDBOX_ARGV       the wrapper before the program (bubblewrap's options), 0x1f-separated
//   RAYKIT_SANDBOX_EXE        the answers program's path inside the wrapper (bubblewrap binds it there)
//   RAYKIT_SANDBOX_UID        the user id to take before the wrapper starts (0: none)
//   RAYKIT_SANDBOX_CGROUPS    ':'-separated control group folders to join
//   RAYKIT_SANDBOX_LIMITS     "ADDRESS_SPACE PROCESSES FILE_SIZE CPU_SECONDS" (rlimits)
//   RAYKIT_CALL_SECONDS       the CPU-time limit of one call (default 2; wall-clock backstop 4x)
//   RAYKIT_BUDGET, RAYKIT_LEDGER, RAYKIT_BUDGET_NOTE
//                             the step's time budget for the student's code over all its calls, and
//                             the file its totals are kept in (remote.cpp, `Budget`; set by ./kit
//                             check, not for ctest or ./kit debug)
// The boundary's come from tools/raykit/sandbox/, the one place it is defined; the budget's from
// tools/raykit/checking.py.
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "wire.hpp"

namespace raykit::remote {

/// Which answers process a call goes to.
enum class Target { student, reference };

/// How a call went wrong, beyond a wrong answer.
struct Incident {
    std::string status;    ///< "crashed", "timed_out", "threw" or "" (none)
    std::string message;   ///< one sentence for the student, naming the call
    std::string function;  ///< the student's function the call was to (made, or refused once the
                           ///< step's budget was used up)
    std::string signal;    ///< the signal that ended the program ("SIGSEGV"), when one did
};

/// Thrown by a proxy when its call crashed, timed out, threw or replied garbage.
struct CallFailed : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Sends one call and returns the reply's payload (after the kind byte has been
/// checked). Throws CallFailed, or raykit::not_implemented for a stub.
std::string exchange(Target target, const std::string& function, const std::string& arguments,
                     const std::string& shown_arguments);

/// Calls `function` in the answers process with `args` and decodes its result.
template <class R, class... A>
R call(Target target, const char* function, const A&... args) {
    wire::Writer w;
    (wire::put(w, args), ...);
    // The reference's calls (thousands a case in a stand-in's script) are written out as text only
    // when one fails: that text was half of a step 05 judge's CPU (docs/performance.md).
    std::string reply;
    if (target == Target::reference) {
        try {
            reply = exchange(target, function, w.bytes, "...");
        } catch (const CallFailed& e) {
            throw CallFailed(std::string(e.what()) + " [" + function + "(" + wire::args_text(args...) + ")]");
        }
    } else {
        reply = exchange(target, function, w.bytes, wire::args_text(args...));
    }
    wire::Reader r(reply.data(), reply.size());
    try {
        R value = wire::get<R>(r);
        if (!r.at_end()) throw wire::wire_error("the reply is longer than its value");
        return value;
    } catch (const wire::wire_error& e) {
        throw CallFailed(std::string(function) + "(" + wire::args_text(args...) +
                         ") sent back an answer the grader cannot read (" + e.what() + ").");
    }
}

/// One call of the student's code that stands for several the judge could make one by one (a
/// render's view rays: "raykit.grid.view_ray", answers_main.cpp): its payload, or nothing when it
/// failed in any way (crashed, threw, the stub, out of time or budget). A failed attempt is no
/// incident of the case and is not charged to the step's budget, and what it printed is forgotten:
/// the caller then makes the calls one by one, which fail, print and are charged as they always did.
/// After one failure a judge makes no more attempts, so a loop costs the grader one call's limit.
std::optional<std::string> attempt(const std::string& function, const std::string& arguments,
                                   const std::string& shown_arguments);

template <class R, class... A>
std::optional<R> try_call(const char* function, const A&... args) {
    wire::Writer w;
    (wire::put(w, args), ...);
    const std::optional<std::string> reply = attempt(function, w.bytes, wire::args_text(args...));
    if (!reply) return std::nullopt;
    wire::Reader r(reply->data(), reply->size());
    try {
        R value = wire::get<R>(r);
        if (!r.at_end()) return std::nullopt;
        return value;
    } catch (const wire::wire_error&) {
        return std::nullopt;
    }
}

/// The reference solution's answer, for hidden cases (needs RAYKIT_REFERENCE_ANSWERS).
template <class R, class... A>
R reference(const char* function, const A&... args) {
    return call<R>(Target::reference, function, args...);
}

/// The answers programs built beside this test program (set by proxies.cpp at
/// start-up); the environment overrides them.
bool set_built_programs(const char* answers, const char* reference);

/// Whether a reference answers program is there (solutions present).
bool has_reference();

/// Whether `calls` more calls of the student's code may be made to measure a fact about it: each priced
/// at the running case's cheapest call that did not start the answers process (its start-up left out;
/// the machine's queue is never charged), must fit in a tenth of what is left of the step's budget
/// (CPU, waiting) and of the case's time. A sleeper or slow code is not measured; right code,
/// whose calls take microseconds, always is, however loaded the machine.
bool can_afford_calls(int calls);

// ---- per case, for the reporter ---------------------------------------------------

/// A case begins: forget the last case's incident and output. `suite` is its doctest suite (the ★
/// cases, "robust", spend a time budget of their own).
void begin_case(const std::string& suite = "");

/// A case ends: every process the student's code left behind is ended
/// (sandboxed runs), and the case's incident and output are returned.
struct CaseRecord {
    Incident incident;
    std::string output;          ///< what the student's code printed, trimmed
    std::size_t output_bytes = 0;  ///< how much it printed in all
};
CaseRecord end_case();

/// Stops the answers processes (at exit).
void shutdown();

}  // namespace raykit::remote

// The judge's side of the wire (see remote.hpp): starting the answers process,
// in a sandbox when asked, timing each call, and cleaning up after each case.

#include "remote.hpp"

#include <fcntl.h>
#include <ftw.h>
#include <grp.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include <cxxabi.h>

#include "fd_io.hpp"
#include "platform.hpp"
#include "raykit/not_implemented.hpp"

namespace raykit::remote {
namespace {

std::string& built_answers() {
    static std::string path;
    return path;
}
std::string& built_reference() {
    static std::string path;
    return path;
}

using Clock = std::chrono::steady_clock;

constexpr std::size_t kept_output = 4096;         // bytes of output kept per case for the report
constexpr std::size_t output_limit = 1u << 20;    // bytes a student's code may print per case
constexpr std::uint32_t reply_limit = 64u << 20;  // a 4096 x 4096 canvas is 192 MiB: far beyond any case

std::string env(const char* name, const char* fallback = "") {
    const char* v = std::getenv(name);
    return v && *v ? v : fallback;
}

std::string signal_name(int sig) {
    switch (sig) {
        case SIGSEGV: return "SIGSEGV, a bad memory access";
        case SIGABRT: return "SIGABRT, abort() or a failed assert";
        case SIGFPE: return "SIGFPE, an arithmetic trap such as integer division by zero";
        case SIGBUS: return "SIGBUS, a bad memory access";
        case SIGILL: return "SIGILL, an illegal instruction";
        case SIGKILL: return "SIGKILL";
        case SIGXFSZ: return "SIGXFSZ, a file grew beyond the sandbox's limit";
        case SIGXCPU: return "SIGXCPU, the CPU time limit";
        case SIGPIPE: return "SIGPIPE";
        default: return "signal " + std::to_string(sig);
    }
}

std::vector<std::string> split(const std::string& s, char sep);

/// How to start the answers program, as the kit's boundary (tools/raykit/sandbox/) says: the
/// wrapper (bubblewrap's options, or nothing), the user id to take, the control groups to join and
/// the rlimits. The kit builds all of it in one place, for the compile and for this run alike.
struct Settings {
    std::string isolation = env("RAYKIT_ISOLATION", "none");
    std::string scratch = env("RAYKIT_SCRATCH");
    std::vector<std::string> wrapper = split(env("RAYKIT_SANDBOX_ARGV"), '\x1f');
    uid_t uid = static_cast<uid_t>(std::strtoul(env("RAYKIT_SANDBOX_UID", "0").c_str(), nullptr, 10));
    std::vector<std::string> cgroups = split(env("RAYKIT_SANDBOX_CGROUPS"), ':');
    std::string inside_exe = env("RAYKIT_SANDBOX_EXE");   // the answers program's path inside the wrapper
    // "ADDRESS_SPACE PROCESSES FILE_SIZE CPU_SECONDS RUN_PROCESSES": PROCESSES is what spawn() sets
    // after taking the user id (bubblewrap itself needs a few), RUN_PROCESSES what the answers program
    // has (1 under every isolation: it may start no process or thread, sandbox.RUN_PROCESSES).
    unsigned long long memory = 0, processes = 0, file_size = 64ull << 20, cpu = 60, run_processes = 0;
    double call_seconds = std::atof(env("RAYKIT_CALL_SECONDS", "2").c_str());
    Settings() {
        std::istringstream limits(env("RAYKIT_SANDBOX_LIMITS"));
        unsigned long long m = 0, p = 0, f = 0, c = 0, r = 0;
        if (limits >> m >> p >> f >> c) memory = m, processes = p, file_size = f, cpu = c;
        if (limits >> r) run_processes = r;
    }
};

Settings& settings() {
    static Settings s;
    return s;
}

/// Said after a failure whose text (an exception's message, what the program printed as it died)
/// shows a process or thread refused by the sandbox's limit of one: the student's own fault, named.
std::string process_limit_note(const std::string& text) {
    if (settings().run_processes != 1 || text.find("Resource temporarily unavailable") == std::string::npos)
        return "";
    return " Your code may not start processes or threads: the grader runs it as one process with one thread "
           "(a limit of 1), so starting another fails with EAGAIN, \"Resource temporarily unavailable\".";
}

/// Said after a Canvas::at out_of_range (canvas.hpp's message, "Canvas::at(I, J): outside the W x H
/// canvas"): which index ran past which side, read off the message alone.
std::string canvas_note(const std::string& text) {
    int i = 0, j = 0, w = 0, h = 0;
    const std::size_t at = text.find("Canvas::at(");
    if (at == std::string::npos ||
        std::sscanf(text.c_str() + at, "Canvas::at(%d, %d): outside the %d x %d canvas", &i, &j, &w, &h) != 4)
        return "";
    std::string which;
    // Trial 9 (issue 54): canvas.at(j, i), the arguments swapped, with the loops right, sends a row index up
    // to width - 1 (or a column index up to height - 1): past its side but within the other. The message
    // alone cannot tell that from loops bounded by the other side's size, so both are named there.
    bool swap_fits = false;
    if (j >= h) {
        which = "the row j = " + std::to_string(j) + " is past the last row, " + std::to_string(h - 1);
        swap_fits = j < w;
    } else if (i >= w) {
        which = "the column i = " + std::to_string(i) + " is past the last column, " + std::to_string(w - 1);
        swap_fits = i < h;
    } else if (i < 0 || j < 0) {
        which = "an index is negative";
    } else {
        return "";
    }
    return " Here " + which + ": the columns i run from 0 to width - 1 and the rows j from 0 to height - 1, so "
           "a loop bounded by the other side's size (width for the rows, height for the columns) or by <= gets "
           "there" + (swap_fits ? std::string(", or canvas.at(j, i) with its arguments swapped: canvas.at takes "
                                              "the column i first, then the row j (canvas.at(i, j))")
                                : std::string()) + ".";
}

using platform::cpu_seconds;
using platform::first_child;

using platform::queued_seconds;

/// What one call of the student's code cost: its CPU, its time waited and its wall time.
struct CallCost {
    double cpu = 0, waited = 0, wall = 0;
    bool started = false;       // the call started the answers process: its start-up is in the figures
};

/// What the calls of the student's code may cost beyond each call's own limit, and what they cost.
///
/// Set by the kit (tools/raykit/checking.py) for a graded step, never for ctest or ./kit debug:
///   RAYKIT_BUDGET       "CPU WAIT CASE": the step's budget of CPU seconds and of seconds waited
///                       (in a call, neither computing nor queued for a CPU: sleeping, blocked),
///                       over all its cases, and the wall seconds the calls of one case may take
///   RAYKIT_BUDGET_NOTE  what the reference needs, said after the figures
///   RAYKIT_LEDGER       a file of the grader's where the step's totals are kept across the judge's
///                       runs (a restart after a crash, a case run again): "CPU WAIT CALLS CPU★
///                       WAIT★ CALLS★ CASE_WALL SINCE LOOPED", SINCE the steady clock's seconds when a
///                       call in flight began, or 0; LOOPED 1 once a call used up its CPU limit
/// The ★ cases (suite "robust": optional, run first, many calls each) have an account of their own
/// with half the budget, so that they never spend what the scored cases need. Without
/// RAYKIT_BUDGET, only each call's own limit applies.
struct Budget {
    static constexpr double none = 1e300;
    double cpu = none, wait = none, case_wall = none;
    std::string note = env("RAYKIT_BUDGET_NOTE");
    std::string ledger = env("RAYKIT_LEDGER");
    struct Account {
        double cpu = 0, wait = 0;
        long calls = 0;
    };
    Account accounts[2];        // the scored cases', the ★ cases'
    int current = 0;            // the account of the case running
    // A call of this step used up its own CPU limit (an endless loop, or code far too slow): every
    // later call may use only loop_seconds of CPU, as a correct call needs microseconds. An endless
    // loop then costs its step one call's limit and a fraction of a second a case, not the budget.
    bool looped = false;
    static constexpr double loop_seconds = 0.2;
    double case_spent = 0;      // wall seconds of the running case's calls
    // Their CPU and waiting (the machine's queue left out): the case's cheapest call that did not start the answers process (CPU and waiting), or -1 before
    // one: what a call of this code costs, the process's start-up and a one-off stall left out.
    double case_cheapest = -1;
    double case_start = 0;      // the call that started the process, start-up included (a fresh process)
    static constexpr int ledger_line = 200;
    int ledger_fd = -1;

    Budget() {
        std::istringstream limits(env("RAYKIT_BUDGET"));
        double c = 0, w = 0, k = 0;
        if (limits >> c >> w >> k) cpu = c, wait = w, case_wall = k;
        std::ifstream in(ledger);
        Account a, b;
        double case_wall_spent = 0, since = 0;
        int loop = 0;
        if (!ledger.empty() && (in >> a.cpu >> a.wait >> a.calls >> b.cpu >> b.wait >> b.calls)) {
            accounts[0] = a, accounts[1] = b;
            if (in >> case_wall_spent >> since >> loop) looped = loop != 0;
        }
    }
    /// The CPU seconds the next call may use: its own limit, or loop_seconds after a loop.
    double call_limit(double seconds) const { return looped ? std::min(seconds, loop_seconds) : seconds; }
    bool set() const { return cpu < none; }
    const Account& now() const { return accounts[current]; }
    double share() const { return current ? 0.5 : 1.0; }     // the ★ cases': half
    double cpu_left() const { return std::max(0.0, cpu * share() - now().cpu); }
    double wait_left() const { return std::max(0.0, wait * share() - now().wait); }
    double case_left() const { return std::max(0.0, case_wall - case_spent); }
    bool spent() const { return set() && (cpu_left() <= 0 || wait_left() <= 0); }

    void begin_case(const std::string& suite) {
        current = suite == "robust" ? 1 : 0;
        case_spent = 0;
        case_cheapest = -1;
        case_start = 0;
        save();
    }

    void add(const CallCost& cost) {
        accounts[current].cpu += cost.cpu;
        accounts[current].wait += cost.waited;
        ++accounts[current].calls;
        case_spent += cost.wall;
        const double price = cost.cpu + cost.waited;
        if (cost.started) case_start = price;
        else if (case_cheapest < 0 || price < case_cheapest) case_cheapest = price;
        save();
    }

    /// A call of the student's code begins: the grader can tell its time from the judge's own.
    void begin_call() { save(std::chrono::duration<double>(Clock::now().time_since_epoch()).count()); }

    /// Rewritten whole after each call and at each case's start, so the grader reads the totals
    /// (and the current case's share) even if this program is stopped in the next call. One line of
    /// a fixed length, written in place: truncating a file at each call costs a journal's flush.
    void save(double since = 0) {
        if (ledger.empty() || !set()) return;
        if (ledger_fd < 0) ledger_fd = ::open(ledger.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0600);
        if (ledger_fd < 0) return;
        char line[ledger_line + 1];
        const int n = std::snprintf(line, sizeof line, "%.3f %.3f %ld %.3f %.3f %ld %.3f %.3f %d", accounts[0].cpu,
                                    accounts[0].wait, accounts[0].calls, accounts[1].cpu, accounts[1].wait,
                                    accounts[1].calls, case_spent, since, looped ? 1 : 0);
        if (n < 0 || n >= ledger_line) return;
        std::memset(line + n, ' ', static_cast<std::size_t>(ledger_line - n));
        line[ledger_line - 1] = '\n';
        (void)!::pwrite(ledger_fd, line, ledger_line, 0);
    }

    /// Which budget: "this step's time budget", or the ★ cases' one.
    std::string which() const { return current ? "the time budget of this step's ★ cases" : "this step's time budget"; }

    /// The account's figures and its budget, in words, for a message to the student.
    std::string figures() const {
        char text[400];
        std::snprintf(text, sizeof text,
                      "in %ld call%s of %s your code used %.1f s of CPU and waited %.1f s (sleeping or blocked, "
                      "not computing); %s may use %g s of CPU and wait %g s in all",
                      now().calls, now().calls == 1 ? "" : "s", current ? "this step's ★ cases" : "this step",
                      now().cpu, now().wait, current ? "they" : "a step", cpu * share(), wait * share());
        return std::string(text) + (note.empty() ? "" : ", and " + note);
    }
};

Budget& budget() {
    static Budget b;
    return b;
}

std::string capitalised(std::string text) {
    if (!text.empty() && text[0] >= 'a' && text[0] <= 'z') text[0] = static_cast<char>(text[0] - 'a' + 'A');
    return text;
}

/// A call stopped by the step's budget or the case's time rather than by its own limit.
struct OverBudget : CallFailed {
    using CallFailed::CallFailed;
};

/// What one call of the student's code may take besides its own limit (left of the step's budget
/// and of the case's time), and what it took.
struct CallBounds {
    double cpu = Budget::none, wait = Budget::none, wall = Budget::none;
};

/// A call stopped by its own CPU limit: it computed without end (the step's later calls get less).
struct CpuTimeout : CallFailed {
    using CallFailed::CallFailed;
};

/// The sandbox itself failed to start (not the student's code): the grader's error.
struct SandboxFailed : CallFailed {
    using CallFailed::CallFailed;
};

/// nftw's callback for stop() and ~Child(): removes one entry, a link itself and never what it names.
int remove_entry(const char* path, const struct stat*, int, struct FTW*) {
    ::remove(path);
    return 0;
}

/// One answers process: its pipes, and the sandbox it lives in.
class Child {
public:
    Child(std::string exe, bool sandboxed) : exe_(std::move(exe)), sandboxed_(sandboxed) {}
    ~Child() {
        stop();
        // A folder made here (no RAYKIT_SCRATCH: the test program run by ctest or by hand) goes with
        // the child; the kit's own folder is the kit's to remove.
        if (own_scratch_) ::nftw(scratch_.c_str(), remove_entry, 16, FTW_DEPTH | FTW_PHYS | FTW_MOUNT);
    }

    bool available() const { return !exe_.empty() && ::access(exe_.c_str(), X_OK) == 0; }
    bool running() const { return pid_ > 0; }
    /// The signal that ended the program at the last died() ("SIGSEGV"), or "".
    const std::string& last_signal() const { return signal_; }

    /// Sends a request, returns the reply body, or throws CallFailed (OverBudget when `bounds`, not
    /// the call's own `seconds`, stopped it); `cost` says what the call took, whatever happened.
    std::string exchange(const std::string& request, const std::string& call, double seconds,
                         const CallBounds& bounds = {}, CallCost* cost = nullptr);

    /// Ends every process of this child and the child itself.
    void stop();

    /// Ends the processes the student's code started, keeping the answers process
    /// where the isolation allows it; at worst, the child itself is stopped too.
    void reap_leftovers();

    std::string output;          // printed during the current case (first kept_output bytes)
    std::size_t output_case = 0; // bytes printed during the current case

private:
    void start();
    int take_ready();
    std::string not_started(const std::string& call);
    bool sandbox_starts();
    void drain_output();
    std::string died(const std::string& call);
    pid_t measured_pid();

    std::string exe_;
    bool sandboxed_;
    pid_t pid_ = -1;
    pid_t answers_pid_ = 0;     // the answers program itself (under bubblewrap, a grandchild)
    bool ready_ = false;        // its "ready" frame came: start-up (constructors, the loader) is over
    std::size_t ready_have_ = 0;    // bytes of that frame read so far
    std::uint32_t ready_frame_ = 1;
    double charged_cpu_ = 0;    // the answers process's CPU seconds already charged to a call
    int req_ = -1, rep_ = -1, out_ = -1;
    std::string scratch_;       // RAYKIT_SCRATCH: the kit's folder, which the student's code cannot write
    std::string run_;           // the current answers process's own folder, fresh at each start (start())
    bool own_scratch_ = false;  // scratch_ was made by start() (no RAYKIT_SCRATCH): removed with the child
    std::string signal_;        // what ended the program at the last died(), as last_signal() says
};

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> parts;
    std::stringstream in(s);
    std::string part;
    while (std::getline(in, part, sep))
        if (!part.empty()) parts.push_back(part);
    return parts;
}

/// Forks and execs `argv` (the wrapper, then the program) inside the boundary: own process group,
/// the control groups, the rlimits, then the dedicated user id; fds 0-3 as given.
pid_t spawn(std::vector<std::string> argv, const std::string& dir, int in, int out, int reply, bool bounded) {
    Settings& cfg = settings();
    // Outside bubblewrap the program is started by its path, but shown under a fixed name: argv is
    // what any user reads in /proc/PID/cmdline, while /proc/PID/exe, cwd and environ are closed to
    // other user ids. No sandbox id learns where another's program or folder is.
    const bool wrapped = argv[0] == "bwrap";
    const std::string exe = argv[0];
    if (bounded && !wrapped) argv[0] = "raykit-answers";
    std::vector<char*> args;
    for (std::string& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    std::string home = "HOME=" + dir;
    // Temporary files in the run's own folder (under the user isolation a size- and inode-limited
    // tmpfs of the slot's where the kit could mount one); bubblewrap's /tmp is the program's own.
    std::string tmpdir = "TMPDIR=" + dir;
    char path[] = "PATH=/usr/bin:/bin";
    char lang[] = "LANG=C.UTF-8";
    // For a student's files, built with UndefinedBehaviorSanitizer in the check and the grade alike
    // (RAYKIT_CHECK_SANITIZE): stop at the first finding, with a stack. ASAN_OPTIONS for a build
    // that links AddressSanitizer (the kit's own sanitize build): on abort() too, no leak check.
    char asan[] = "ASAN_OPTIONS=halt_on_error=1:abort_on_error=0:exitcode=86:handle_abort=1:detect_leaks=0:"
                  "print_summary=1:allocator_may_return_null=1";
    char ubsan[] = "UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:exitcode=86";
    char* envp[] = {path, lang, home.data(), asan, ubsan, wrapped ? nullptr : tmpdir.data(), nullptr};
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid != 0) return pid;
    ::setpgid(0, 0);
    ::dup2(in, 0);
    ::dup2(out, 1);
    ::dup2(out, 2);
    ::dup2(reply, 3);
    for (int fd = 0; fd <= 3; ++fd) ::fcntl(fd, F_SETFD, 0);
    for (int fd = 4; fd < 1024; ++fd) ::close(fd);
    ::signal(SIGPIPE, SIG_DFL);
    if (bounded) {
        const std::string me = std::to_string(::getpid());
        for (const std::string& group : cfg.cgroups) {
            const int fd = ::open((group + "/cgroup.procs").c_str(), O_WRONLY | O_CLOEXEC);
            if (fd >= 0) {
                (void)!::write(fd, me.data(), me.size());
                ::close(fd);
            }
        }
        // Bounds the sandboxed code cannot raise: no core files, each file it writes, CPU time
        // even if the grader itself were stopped, and its address space.
        const struct rlimit core{0, 0}, fsize{cfg.file_size, cfg.file_size}, cpu{cfg.cpu, cfg.cpu};
        ::setrlimit(RLIMIT_CORE, &core);
        ::setrlimit(RLIMIT_FSIZE, &fsize);
        ::setrlimit(RLIMIT_CPU, &cpu);
        if (cfg.memory) {
            const struct rlimit as{cfg.memory, cfg.memory};
            ::setrlimit(RLIMIT_AS, &as);
        }
        if (cfg.uid != 0) {
            if (::setgroups(0, nullptr) != 0 || ::setgid(cfg.uid) != 0 || ::setuid(cfg.uid) != 0 ||
                ::getuid() != cfg.uid)
                ::_exit(126);
            platform::clear_keyrings();   // nothing an earlier run of this id kept in a keyring
            // Under the user isolation 1: the answers program may start no process or thread (each
            // would be CPU the budget does not see); a fork or a thread fails with EAGAIN. Under
            // bubblewrap bubblewrap's own few, and the program gets 1 from prlimit inside the wrapper.
            if (cfg.processes) {
                const struct rlimit nproc{cfg.processes, cfg.processes};
                ::setrlimit(RLIMIT_NPROC, &nproc);
            }
        }
    }
    if (::chdir(dir.c_str()) != 0) ::_exit(126);
    if (wrapped) platform::exec_on_path("bwrap", args.data(), envp);
    else ::execve(exe.c_str(), args.data(), envp);
    ::_exit(127);
}

void Child::start() {
    Settings& cfg = settings();
    // A program that closes its stdin (the request pipe) must not stop the judge with SIGPIPE at its
    // next request ("not graded"): the write fails with EPIPE instead, and the call is the student's.
    static const bool no_sigpipe = ::signal(SIGPIPE, SIG_IGN) != SIG_ERR;
    (void)no_sigpipe;
    if (scratch_.empty()) {
        scratch_ = cfg.scratch;
        if (scratch_.empty()) {
            const char* tmp = std::getenv("TMPDIR");
            std::string tmpl = std::string(tmp != nullptr && *tmp == '/' ? tmp : "/tmp") + "/raykit-answers-XXXXXX";
            if (::mkdtemp(tmpl.data()) == nullptr) throw CallFailed("the grader could not make a scratch folder");
            scratch_ = tmpl;
            own_scratch_ = true;
        }
    }
    const bool bounded = sandboxed_ && cfg.isolation != "none";
    std::vector<std::string> argv = bounded ? cfg.wrapper : std::vector<std::string>{};
    if (bounded && cfg.isolation == "bwrap" && argv.empty())
        throw SandboxFailed("The grader was told to use bubblewrap but given no sandbox to start: a kit bug.");
    argv.push_back(bounded && !cfg.inside_exe.empty() ? cfg.inside_exe : exe_);
    // Each start of the student's program works in a folder of its own, made here inside the kit's
    // (which the sandbox's user id cannot write, so it cannot swap the entry) and owned by that id,
    // mode 0700; stop() removes it. Nothing a case (or a step, or another student) wrote is there
    // for the next start: a case re-run alone after the hidden cases finds an empty folder. Under
    // bubblewrap without a sized tmpfs the wrapper binds the kit's folder: this one is bound instead.
    std::string dir = scratch_;
    if (sandboxed_) {
        std::string tmpl = scratch_ + "/run-XXXXXX";
        if (::mkdtemp(tmpl.data()) == nullptr)
            throw SandboxFailed("The grader could not make a scratch folder for your code (" +
                                std::string(std::strerror(errno)) + "): the grader's fault, not your code's.");
        run_ = dir = tmpl;
        if (bounded && cfg.uid != 0 && ::chown(run_.c_str(), cfg.uid, cfg.uid) != 0)
            throw SandboxFailed("The grader could not give your code its scratch folder: the grader's fault.");
        if (bounded && cfg.isolation == "bwrap") std::replace(argv.begin(), argv.end(), scratch_, run_);
    }
    int rq[2], rp[2], ou[2];
    if (!platform::open_pipe(rq) || !platform::open_pipe(rp) || !platform::open_pipe(ou))
        throw CallFailed("the grader could not open pipes to your code");
    const pid_t pid = spawn(argv, dir, rq[0], ou[1], rp[1], bounded);
    ::close(rq[0]);
    ::close(rp[1]);
    ::close(ou[1]);
    if (pid < 0) {
        ::close(rq[1]);
        ::close(rp[0]);
        ::close(ou[0]);
        throw CallFailed("the grader could not start your code (fork failed)");
    }
    pid_ = pid;
    req_ = rq[1];
    rep_ = rp[0];
    out_ = ou[0];
    answers_pid_ = sandboxed_ && cfg.isolation == "bwrap" ? 0 : pid_;
    ready_ = false;
    ready_have_ = 0;
    ready_frame_ = 1;
    charged_cpu_ = 0;
    ::fcntl(out_, F_SETFL, ::fcntl(out_, F_GETFL) | O_NONBLOCK);
    ::fcntl(rep_, F_SETFL, ::fcntl(rep_, F_GETFL) | O_NONBLOCK);
    // No wait here: the program's start-up (the sandbox's start, the loader, the constructors of its
    // global variables) is waited for by the call that started it, within that call's limits and
    // charged to the step's budget like the call itself (exchange()).
}

/// Whether the sandbox starts a program that does nothing (/bin/true), as it started the answers
/// program: when it does not, a failed start is the grader's, never the student's.
bool Child::sandbox_starts() {
    Settings& cfg = settings();
    std::vector<std::string> argv = cfg.wrapper;
    argv.push_back(::access("/bin/true", X_OK) == 0 ? "/bin/true" : "/usr/bin/true");
    const int null = ::open("/dev/null", O_RDWR | O_CLOEXEC);
    const pid_t pid = spawn(argv, scratch_, null, null, null, true);
    if (null >= 0) ::close(null);
    if (pid < 0) return false;
    int status = 0;
    for (int i = 0; i < 20000; ++i) {
        const pid_t got = ::waitpid(pid, &status, WNOHANG);
        if (got == pid) return WIFEXITED(status) && WEXITSTATUS(status) == 0;
        ::usleep(1000);
    }
    ::kill(-pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    return false;
}

/// Reads what has come of the answers program's first frame (empty: "ready"): 1 once it is whole,
/// 0 while more is to come, -1 when the pipe closed first or the frame is not empty (not_started()).
/// Under bubblewrap the program's own process is found as soon as it exists, so that its start-up is
/// measured too.
int Child::take_ready() {
    measured_pid();
    while (ready_have_ < sizeof ready_frame_) {
        const ssize_t k = ::read(rep_, reinterpret_cast<char*>(&ready_frame_) + ready_have_,
                                 sizeof ready_frame_ - ready_have_);
        if (k > 0) {
            ready_have_ += static_cast<std::size_t>(k);
            continue;
        }
        return k < 0 && (errno == EAGAIN || errno == EINTR) ? 0 : -1;
    }
    ready_ = ready_frame_ == 0;
    return ready_ ? 1 : -1;
}

/// The process under bubblewrap's init whose CPU time is the student's: found once it exists.
pid_t Child::measured_pid() {
    if (answers_pid_ <= 0 && pid_ > 0 && settings().isolation == "bwrap" && sandboxed_) {
        const pid_t init = first_child(pid_);
        answers_pid_ = init > 0 ? first_child(init) : 0;
    }
    return answers_pid_;
}

/// Why the program ended, or closed its reply pipe, before its "ready" frame: the sandbox's failure
/// (checked with a program that does nothing) or the student's own start-up.
std::string Child::not_started(const std::string& call) {
    const bool bounded = sandboxed_ && settings().isolation != "none";
    std::string printed = output;
    const bool spoke = ready_have_ == sizeof ready_frame_ && ready_frame_ != 0;
    const std::string how = died("the start of your program (before main: a global variable's constructor?), "
                                 "before " + call);
    if (bounded && !spoke && !sandbox_starts())
        throw SandboxFailed("The grader's sandbox could not start (" + settings().isolation +
                            "): this is the grader's fault, not your code's. It said: " +
                            printed.substr(0, 300));
    if (spoke) return "Your program sent something before it was called.";
    return how;
}

void Child::drain_output() {
    if (out_ < 0) return;
    char buf[65536];
    for (;;) {
        const ssize_t n = ::read(out_, buf, sizeof buf);
        if (n == 0) {           // every writer closed it (a program that closed its stdout and stderr)
            ::close(out_);      // poll() would say so at once for ever: a busy loop of the judge's
            out_ = -1;
        }
        if (n <= 0) return;
        const std::size_t k = static_cast<std::size_t>(n);
        if (output.size() < kept_output) output.append(buf, std::min(k, kept_output - output.size()));
        output_case += k;
        if (output_case > output_limit) return;
    }
}

void Child::stop() {
    if (pid_ > 0) {
        ::kill(-pid_, SIGKILL);
        ::kill(pid_, SIGKILL);
        int status = 0;
        ::waitpid(pid_, &status, 0);
        drain_output();
    }
    const std::string mode = settings().isolation;
    if (sandboxed_ && mode.rfind("user:", 0) == 0) {
        // Every process of the sandbox's user id, whatever its group or session:
        // a helper that takes that id and signals everything it may signal.
        const uid_t uid = static_cast<uid_t>(std::strtoul(mode.c_str() + 5, nullptr, 10));
        const pid_t helper = ::fork();
        if (helper == 0) {
            if (::setgroups(0, nullptr) == 0 && ::setgid(uid) == 0 && ::setuid(uid) == 0) {
                ::kill(-1, SIGKILL);
                platform::clear_keyrings();     // and what its processes kept in the id's keyrings
            }
            ::_exit(0);
        }
        if (helper > 0) ::waitpid(helper, nullptr, 0);
    }
    if (!run_.empty()) {
        // The folder is taken back before it is emptied (a process of the sandbox's id that outlived
        // the kill above can no longer enter or add to it), then removed without following links.
        if (::geteuid() == 0) {
            (void)!::chown(run_.c_str(), 0, 0);
            ::chmod(run_.c_str(), 0700);
        }
        ::nftw(run_.c_str(), remove_entry, 16, FTW_DEPTH | FTW_PHYS | FTW_MOUNT);
        run_.clear();
    }
    for (int* fd : {&req_, &rep_, &out_}) {
        if (*fd >= 0) ::close(*fd);
        *fd = -1;
    }
    pid_ = -1;
}

void Child::reap_leftovers() {
    if (pid_ <= 0 || !sandboxed_) return;
    const std::string mode = settings().isolation;
    if (mode != "bwrap") {
        // Under a dedicated user id the answers process cannot be told apart from
        // what it started: end them all; the next call starts a fresh one.
        if (mode.rfind("user:", 0) == 0) stop();
        return;
    }
    // bwrap: the sandbox's PID namespace holds bwrap's init (1), the answers
    // process (2) and whatever the student's code started. End the rest.
    const pid_t init = first_child(pid_);
    if (init > 0) platform::end_namespace_rest(init);
}

/// Whether a line of a stack or a report is in the student's own code (not GLM's, the kit's, the
/// standard library's or the sanitizer's).
bool own_line(const std::string& l) {
    for (const char* kit : {"/glm/", "/include/c++/", "/usr/include/", "answers_main", "wire.hpp", "libsanitizer",
                            "/raykit/not_implemented", "standin_"})
        if (l.find(kit) != std::string::npos) return false;
    return l.find(".cpp:") != std::string::npos;
}

/// Whether a frame is the dispatcher's that called the student's function (answers_main.cpp's serve,
/// std::apply and std::invoke around it, main, the C library's start), by its name, demangled or not
/// (a lambda inside serve may not demangle).
bool grader_frame(const std::string& name, const std::string& shown) {
    for (const char* word : {"answers_main", "(anonymous namespace)::serve", "_GLOBAL__N_15serve",
                             "(anonymous namespace)::answer(", "std::__invoke",
                             "St13__invoke", "St8__invoke", "std::apply", "St5apply", "std::__apply", "St12__apply",
                             "libc.so", "__libc_start"})
        if (shown.find(word) != std::string::npos) return true;
    return name == "main" || name == "_start";
}

/// A sanitizer's stack, as a student reads it: each frame's function demangled (`_ZZN12...` from a
/// frame without debug information), its address left out, the student's own frames marked, and the
/// grader's frames below them (the dispatcher that called the student's function, the C library)
/// said in one line. Every other line is kept as it came.
std::string readable_stack(const std::string& out) {
    std::istringstream lines(out);
    std::string line, result;
    int grader = 0;
    bool in_stack = false;
    auto flush = [&]() {
        if (grader > 0) result += "    (" + std::to_string(grader) + " frame" + (grader == 1 ? "" : "s") +
                                  " of the grader's program that called your code)\n";
        grader = 0;
    };
    while (std::getline(lines, line)) {
        std::size_t hash = line.find_first_not_of(' ');
        const bool frame = hash != std::string::npos && line.compare(hash, 1, "#") == 0 &&
                           line.find(" in ", hash) != std::string::npos && line.find(" 0x", hash) != std::string::npos;
        if (!frame) {
            if (in_stack) flush();
            in_stack = false;
            result += line + "\n";
            continue;
        }
        in_stack = true;
        const std::size_t in = line.find(" in ", hash) + 4;
        const std::size_t end = line.find(' ', in);
        std::string name = line.substr(in, end == std::string::npos ? std::string::npos : end - in);
        std::string rest = end == std::string::npos ? "" : line.substr(end);
        if (name.rfind("_Z", 0) == 0) {
            int status = 0;
            char* plain = abi::__cxa_demangle(name.c_str(), nullptr, nullptr, &status);
            if (status == 0 && plain != nullptr) name = plain;
            std::free(plain);
        }
        const std::string number = line.substr(hash, line.find(' ', hash) - hash);
        const std::string shown = name + rest;
        // The student's: a line of their file, or (a graded build has no line tables) a function of
        // raykit's namespace that is none of the kit's own.
        const bool theirs = own_line(shown) || (name.rfind("raykit::", 0) == 0 && name.rfind("raykit::wire", 0) != 0 &&
                                                name.rfind("raykit::standin", 0) != 0 &&
                                                name.rfind("raykit::platform", 0) != 0 && shown.find("/glm/") == std::string::npos);
        if (theirs) {
            flush();
            result += "    " + number + " " + shown + "   <- your code\n";
        } else if (grader_frame(name, shown)) {
            ++grader;
        } else {
            flush();
            result += "    " + number + " " + shown + "\n";
        }
    }
    if (in_stack) flush();
    if (!out.empty() && out.back() != '\n' && !result.empty()) result.pop_back();
    return result;
}

/// What a sanitizer or an assert said, from the output of the answers program: its one-line reason
/// and the first line of the student's own code on its stack (not GLM's, the kit's or the system's),
/// or "" when the output holds no such report.
std::string sanitizer_finding(const std::string& out) {
    std::istringstream lines(out);
    std::string line, reason, where;
    const auto own = own_line;
    while (std::getline(lines, line)) {
        std::size_t at;
        if (reason.empty() && (at = line.find("runtime error: ")) != std::string::npos) {
            reason = "UndefinedBehaviorSanitizer: " + line.substr(at + 15);
            const std::string file = line.substr(0, at);
            if (own(file)) where = file.substr(0, file.find_last_of(':'));
        } else if (reason.empty() && (at = line.find("ERROR: AddressSanitizer: ")) != std::string::npos) {
            reason = "AddressSanitizer: " + line.substr(at + 25);
            if (const std::size_t on = reason.find(" on "); on != std::string::npos) reason.resize(on);
        } else if (reason.empty() && line.find("Assertion") != std::string::npos && line.find("failed") != std::string::npos) {
            at = line.find("Assertion");
            reason = "an assert in the kit's headers failed: " + line.substr(at);
        } else if (!reason.empty() && where.empty() && line.find(" in ") != std::string::npos && own(line)) {
            where = line.substr(line.find_last_of(' ') + 1);     // FILE:LINE (and :COLUMN, from some compilers)
        }
    }
    if (reason.empty()) return "";
    if (where.size() > 0) {
        const std::size_t slash = where.find_last_of('/');
        const std::size_t steps = where.rfind("/steps/");
        where = steps != std::string::npos ? where.substr(steps + 1) : slash != std::string::npos ? where.substr(slash + 1) : where;
    }
    return reason + (where.empty() ? "" : " (your code, " + where + ")");
}

/// What the answers program said of a fault in a guard page ("argument 2", "a list in argument 2":
/// tests/support/answers_main.cpp), taken out of the output it came in, or "".
std::string fault_note(std::string& out) {
    const std::string tag = "raykit-fault: ";
    const std::size_t at = out.find(tag);
    if (at == std::string::npos || (at > 0 && out[at - 1] != '\n')) return "";
    const std::size_t end = out.find('\n', at);
    const std::string what = out.substr(at + tag.size(), end == std::string::npos ? std::string::npos : end - at - tag.size());
    out.erase(at, end == std::string::npos ? std::string::npos : end + 1 - at);
    return what;
}

std::string Child::died(const std::string& call) {
    int status = 0;
    pid_t got = 0;
    for (int i = 0; i < 200 && (got = ::waitpid(pid_, &status, WNOHANG)) == 0; ++i) ::usleep(1000);
    drain_output();
    std::string how;
    signal_.clear();
    // bwrap passes on the sandboxed program's status; 128+N is a signal.
    const int sig = got != pid_ ? 0
                    : WIFSIGNALED(status) ? WTERMSIG(status)
                    : WIFEXITED(status) && WEXITSTATUS(status) > 128 && WEXITSTATUS(status) < 128 + 65
                        ? WEXITSTATUS(status) - 128
                        : 0;
    if (sig != 0) {
        const std::string name = signal_name(sig);    // "SIGSEGV, a bad memory access"
        how = "it was killed by " + name;
        signal_ = name.substr(0, name.find(','));
    } else if (got == pid_ && WIFEXITED(status)) {
        how = "the program ended (exit status " + std::to_string(WEXITSTATUS(status)) +
              "): does your code call exit() or close the grader's pipes?";
    } else {
        how = "it closed the connection to the grader";
    }
    if (got == pid_) pid_ = -1;
    stop();
    const std::size_t before = output.size();
    const std::string note = fault_note(output);
    // The note is the kit's, not the student's: neither shown nor counted as what their code printed.
    output_case -= std::min<std::size_t>(output_case, before - output.size());
    const bool bad_access = signal_ == "SIGSEGV" || signal_ == "SIGBUS";
    if (bad_access && note.rfind("stack ", 0) == 0)    // the guard below the main stack (answers_main.cpp)
        return "Your code crashed in " + call + ": its stack ran out, " + note.substr(6) +
               " of calls deep (" + how.substr(how.find("SIG")) +
               "): a function that calls itself with no case that ends it, or a local array too big for the stack.";
    const std::string past = note.rfind("past ", 0) == 0 ? note.substr(5) : "";
    if (!past.empty())    // the argument's own memory ended there: the same crash in every build
        return "Your code crashed in " + call + ": it read or wrote past the end of " +
               (past.rfind("a list", 0) == 0 ? "the list in " + past.substr(past.find("argument")) : past) +
               " (" + how.substr(how.find("SIG") == std::string::npos ? 0 : how.find("SIG")) +
               "): memory that is not the argument's, as `(&v.x)[3]` on a 3-vector or a loop to `<= count` reads.";
    const std::string finding = sanitizer_finding(output);
    if (finding.rfind("AddressSanitizer: SEGV", 0) == 0)    // a bad access the sanitizer only saw land
        return "Your code crashed in " + call + ": it was killed by SIGSEGV, a bad memory access (" + finding + ").";
    if (!finding.empty()) return "Your code has undefined behaviour in " + call + ": " + finding + ".";
    return "Your code crashed in " + call + ": " + how + "." + process_limit_note(output);
}

std::string Child::exchange(const std::string& request, const std::string& call, double seconds,
                            const CallBounds& bounds, CallCost* cost) {
    // A call that starts the program is charged its start-up like its own work (the sandbox's
    // start, the loader, the constructors of global variables: all the student's, whatever they do),
    // from the fork on: its wall time against the call's limits and the case's, the program's CPU
    // from its first instruction and its time waited against the step's budget. Under the user
    // isolation every case starts a fresh process, so a start-up that stalls or spins costs each
    // case a call's limit, and the step its budget, as a call would.
    const bool fresh = !running();
    const auto began = Clock::now();
    if (fresh) start();
    const std::uint32_t size = static_cast<std::uint32_t>(request.size());
    std::string framed(reinterpret_cast<const char*>(&size), sizeof size);
    framed += request;
    // What a failure is said to happen in: the call, or the program's start before it.
    auto in = [&]() {
        return ready_ ? call : "the start of your program (before main: a global variable's constructor?), before " + call;
    };

    // The limit is CPU time where it can be read (a loaded machine does not make a call slow), with
    // a wall-clock backstop four times as long for code that waits instead of computing. Time
    // waited (neither computing nor queued for a CPU) also counts against the step's budget, and
    // the call's wall time against the case's (`bounds`): sleeping within each call's own limit
    // costs the grader, so it costs the student too. The CPU charged is the program's since what the
    // last call was charged (0 for a fresh process): whatever ran between two calls (a signal
    // handler, a timer) is charged to the next.
    // The reference's calls (not sandboxed: the kit's own program, no budget) are not measured: six
    // reads of /proc a call were most of a step 05 judge's CPU, whose stand-in scripts ask the
    // reference thousands of times a case (docs/performance.md). Its limit is the wall clock's.
    static const bool cpu_readable = cpu_seconds(::getpid()) >= 0;
    const bool by_cpu = sandboxed_ && cpu_readable;
    const double cpu_start = fresh ? 0.0 : charged_cpu_;
    pid_t measured = by_cpu ? measured_pid() : 0;
    // Queued for a CPU, the answers program or the judge reading its reply: the machine's load.
    auto queued_now = [&]() { return (measured > 0 ? queued_seconds(measured) : 0.0) + queued_seconds(0); };
    const double queued_start = by_cpu ? (fresh ? queued_seconds(0) : queued_now()) : 0;
    // Where CPU time is read, a call that waits (sleeps, blocks) is stopped after `waiting` seconds
    // waited, time queued for a CPU left out: on a loaded machine a loop reaches its CPU limit and is
    // called a loop, however long the queue made it take. The wall clock is a last backstop only.
    const double waiting = std::max(3 * seconds, seconds + 2);
    // The reference, trusted and unmeasured, has the long backstop too: a loaded machine must not
    // make the kit's own answer late.
    const double wall = by_cpu || !sandboxed_ ? std::max(40 * seconds, seconds + 60) : seconds;
    const auto deadline = began + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wall));
    CallCost spent;
    spent.started = fresh;
    auto measure = [&]() {
        spent.wall = std::chrono::duration<double>(Clock::now() - began).count();
        if (by_cpu) {
            if (measured <= 0) measured = measured_pid();
            const double now = measured > 0 ? cpu_seconds(measured) : -1;
            if (now >= 0) {
                spent.cpu = std::max(0.0, now - cpu_start);
                charged_cpu_ = std::max(charged_cpu_, now);
            }
            const double queued = std::max(0.0, queued_now() - queued_start);
            spent.waited = std::max(0.0, spent.wall - spent.cpu - queued);
        }
        if (cost) *cost = spent;
    };
    bool sent = false;
    auto send = [&]() {
        if (!wire::write_exact(req_, framed.data(), framed.size())) {
            measure();
            throw CallFailed(died(call));
        }
        sent = true;
    };
    if (!fresh) send();
    std::string reply;
    std::uint32_t want = 0;
    bool have_size = false;
    char buf[65536];
    // A call to a running program is measured after its first wait, not before it: it has had no
    // time to spend yet (what ran since the last call is charged all the same, by the next reading),
    // and three reads of /proc a call less were a tenth of a step 05 judge's CPU, whose render cases
    // call view_ray once a pixel (docs/performance.md). A limit is still checked every 50 ms.
    bool waited_once = fresh;
    for (;;) {
        if (output_case > output_limit) {
            measure();
            stop();
            throw CallFailed("Your code printed more than " + std::to_string(output_limit >> 20) +
                             " MiB during " + in() + " and was stopped.");
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
        if (waited_once) measure();
        waited_once = true;
        const double used = spent.cpu;
        char limit[32];
        if (by_cpu && used > seconds) {
            stop();
            std::snprintf(limit, sizeof limit, "%g", seconds);
            throw CpuTimeout("Time out: your code computed for " + std::string(limit) + " s of CPU time in " + in() +
                             " without returning. An endless loop?");
        }
        if (by_cpu && spent.waited > waiting) {
            stop();
            std::snprintf(limit, sizeof limit, "%g", waiting);
            throw CallFailed("Time out: your code waited " + std::string(limit) + " s in " + in() +
                             " without returning (sleeping or blocked, not computing).");
        }
        if (left <= 0) {
            stop();
            std::snprintf(limit, sizeof limit, "%g", wall);
            throw CallFailed("Time out: your code did not return from " + in() + " within " + limit +
                             (by_cpu ? " s of wall time (the machine is very busy, or your code is stopped)."
                                     : " s. An endless loop?"));
        }
        if (used > bounds.cpu || spent.waited > bounds.wait || spent.wall > bounds.wall) {
            stop();
            throw OverBudget(used > bounds.cpu ? "cpu" : spent.waited > bounds.wait ? "wait" : "case");
        }
        pollfd fds[2] = {{rep_, POLLIN, 0}, {out_, POLLIN, 0}};
        const int n = ::poll(fds, 2, static_cast<int>(std::min<long long>(left, 50)));
        if (n < 0 && errno != EINTR) {
            measure();
            throw CallFailed(sent ? died(call) : not_started(call));
        }
        if (fds[1].revents) drain_output();
        if (!sent) {
            // Start-up: the "ready" frame, then the request. A program that ends or closes its reply
            // pipe first failed to start: the sandbox's fault or the student's (not_started()).
            if (!fds[0].revents) {
                measured_pid();
                continue;
            }
            const int got = take_ready();
            if (got > 0) send();
            if (got < 0) {
                measure();
                throw CallFailed(not_started(call));
            }
            continue;
        }
        if (!fds[0].revents) continue;
        const ssize_t k = ::read(rep_, buf, sizeof buf);
        if (k == 0 || (k < 0 && errno != EAGAIN && errno != EINTR)) {
            measure();
            throw CallFailed(died(call));
        }
        if (k < 0) continue;
        reply.append(buf, static_cast<std::size_t>(k));
        if (!have_size && reply.size() >= sizeof want) {
            std::memcpy(&want, reply.data(), sizeof want);
            have_size = true;
            if (want > reply_limit) {
                measure();
                stop();
                throw CallFailed(call + " sent back an answer far larger than any case needs.");
            }
        }
        if (have_size && reply.size() >= sizeof want + want) {
            measure();
            if (reply.size() > sizeof want + want) {
                stop();  // more than was asked for: out of step with the requests
                throw CallFailed(call + " sent back more than one answer.");
            }
            drain_output();
            return reply.substr(sizeof want);
        }
    }
}

struct State {
    Child student{env("RAYKIT_ANSWERS", built_answers().c_str()), true};
    Child reference{env("RAYKIT_REFERENCE_ANSWERS", built_reference().c_str()), false};
    Incident incident;
};

State& state() {
    static State s;
    return s;
}

}  // namespace

/// RAYKIT_CALL_LOG: every request to the student's program is also appended to this file, framed as
/// on the wire, for `answers_stepNN --replay FILE` (./kit debug runs a case's calls in one process).
static void log_call(const std::string& request) {
    static const std::string path = env("RAYKIT_CALL_LOG");
    if (path.empty()) return;
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
    if (fd < 0) return;
    const std::uint32_t size = static_cast<std::uint32_t>(request.size());
    std::string framed(reinterpret_cast<const char*>(&size), sizeof size);
    framed += request;
    (void)!::write(fd, framed.data(), framed.size());
    ::close(fd);
}

bool set_built_programs(const char* answers, const char* reference) {
    built_answers() = answers;
    built_reference() = reference;
    return true;
}

bool has_reference() { return state().reference.available(); }

bool can_afford_calls(int calls) {
    const Budget& b = budget();
    // Before a call that did not start the process (a case of one call, under the user isolation),
    // the starting call prices them: its start-up makes that an overestimate, never an underestimate.
    const double price = (b.case_cheapest >= 0 ? b.case_cheapest : b.case_start) * calls;
    if (!b.set()) return price < 1.0;
    return price < 0.1 * std::min({b.cpu_left(), b.wait_left(), b.case_left()});
}

std::string exchange(Target target, const std::string& function, const std::string& arguments,
                     const std::string& shown_arguments) {
    State& s = state();
    Child& child = target == Target::student ? s.student : s.reference;
    const std::string call = function + "(" + shown_arguments + ")";
    if (!child.available()) throw CallFailed("the grader has no program to call " + function + " in");
    if (target == Target::student && !s.incident.message.empty() && s.incident.status != "threw") {
        // An earlier call of this case crashed or hung: the case has failed; do not
        // spend another time limit on it.
        throw CallFailed("Not called: an earlier call in this case already failed.");
    }
    Budget& b = budget();
    if (target == Target::student && b.spent()) {
        // The step's budget is used up: the remaining calls fail without running, the student's.
        const std::string text = "Not called: your code has used up " + b.which() + ", so the remaining cases "
                                 "fail without calling it. " + capitalised(b.figures()) + ".";
        s.incident = {"timed_out", text, function, ""};
        throw CallFailed(text);
    }
    std::string request(1, static_cast<char>(function.size()));
    request += function;
    request += arguments;
    if (target == Target::student) log_call(request);
    const double limit = target == Target::student ? b.call_limit(settings().call_seconds) : settings().call_seconds;
    std::string body;
    CallCost cost;
    try {
        if (target == Target::student) {
            CallBounds bounds;
            if (b.set()) bounds = {b.cpu_left(), b.wait_left(), b.case_left()};
            b.begin_call();
            try {
                body = child.exchange(request, call, limit, bounds, &cost);
            } catch (const CpuTimeout& e) {
                const bool first = !b.looped;
                b.looped = true;
                b.add(cost);
                if (first) throw;
                char words[200];
                std::snprintf(words, sizeof words,
                              " (An earlier call of this step already computed without end, so each later call "
                              "may use %g s of CPU: a correct one needs microseconds.)", limit);
                throw CpuTimeout(std::string(e.what()) + words);
            } catch (const CallFailed&) {
                b.add(cost);
                throw;
            }
            b.add(cost);
        } else {
            body = child.exchange(request, call, 60.0);
        }
    } catch (const OverBudget& e) {
        const std::string kind = e.what();
        std::string text;
        if (kind == "case") {
            char figures[160];
            std::snprintf(figures, sizeof figures, " took %.1f s in all, beyond the %g s a case may take", b.case_spent,
                          b.case_wall);
            text = "Time out: " + call + " was stopped because this case's calls of your code" + figures +
                   ". Each call may keep within its own limit, but a case makes many calls: your code is too "
                   "slow, or it waits (" + b.figures() + ").";
        } else {
            text = "Time out: " + call + " was stopped because your code used up " + b.which() + " " +
                   (kind == "cpu" ? "of CPU" : "for waiting") + ": " + b.figures() + ".";
        }
        s.incident = {"timed_out", text, function, ""};
        throw CallFailed(text);
    } catch (const CallFailed& e) {
        if (target == Target::student) {
            const std::string what = e.what();
            const bool hung = what.rfind("Time out", 0) == 0;
            const bool grader = dynamic_cast<const SandboxFailed*>(&e) != nullptr;
            s.incident = {grader ? "grader_error" : hung ? "timed_out" : "crashed", what, function,
                          grader || hung ? "" : child.last_signal()};
        }
        throw;
    }
    if (body.empty()) throw CallFailed(call + " sent back an empty answer.");
    const auto kind = static_cast<wire::Kind>(body[0]);
    wire::Reader r(body.data() + 1, body.size() - 1);
    switch (kind) {
        case wire::Kind::value: return body.substr(1);
        case wire::Kind::not_implemented: throw raykit::not_implemented(function);
        case wire::Kind::threw: {
            std::string message;
            try {
                message = wire::get<std::string>(r);
            } catch (const wire::wire_error&) {
                message = "(no message)";
            }
            const std::string text = "Your code threw an exception in " + call + ": " + message + process_limit_note(message) + canvas_note(message);
            if (target == Target::student && s.incident.message.empty()) s.incident = {"threw", text, function, ""};
            throw CallFailed(text);
        }
        case wire::Kind::unknown:
            throw CallFailed("the answers program has no function " + function + " (a kit bug: please report it)");
    }
    throw CallFailed(call + " sent back an answer of an unknown kind.");
}

std::optional<std::string> attempt(const std::string& function, const std::string& arguments,
                                   const std::string& shown_arguments) {
    static bool failed = false;
    State& s = state();
    Child& child = s.student;
    Budget& b = budget();
    if (failed || !child.available() || !s.incident.message.empty() || b.spent()) return std::nullopt;
    std::string request(1, static_cast<char>(function.size()));
    request += function;
    request += arguments;
    log_call(request);
    CallBounds bounds;
    if (b.set()) bounds = {b.cpu_left(), b.wait_left(), b.case_left()};
    const std::size_t kept = child.output.size(), printed = child.output_case;
    CallCost cost;
    std::string body;
    b.begin_call();
    try {
        body = child.exchange(request, function + "(" + shown_arguments + ")",
                              b.call_limit(settings().call_seconds), bounds, &cost);
    } catch (const std::exception&) {
        body.clear();
    }
    if (body.empty() || static_cast<wire::Kind>(body[0]) != wire::Kind::value) {
        failed = true;
        child.output.resize(std::min(kept, child.output.size()));
        child.output_case = printed;
        b.save();
        return std::nullopt;
    }
    b.add(cost);
    return body.substr(1);
}


void begin_case(const std::string& suite) {
    State& s = state();
    budget().begin_case(suite);
    s.incident = {};
    s.student.output.clear();
    s.student.output_case = 0;
}

CaseRecord end_case() {
    State& s = state();
    s.student.reap_leftovers();
    CaseRecord r{s.incident, readable_stack(s.student.output), s.student.output_case};
    s.incident = {};
    s.student.output.clear();
    s.student.output_case = 0;
    return r;
}

void shutdown() {
    state().student.stop();
    state().reference.stop();
}

}  // namespace raykit::remote

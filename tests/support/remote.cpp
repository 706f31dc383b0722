// The judge's side of the wire (see remote.hpp): starting the answers process,
// in a sandbox when asked, timing each call, and cleaning up after each case.

#include "remote.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <grp.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "fd_io.hpp"
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

struct Settings {
    std::string isolation = env("RAYKIT_ISOLATION", "none");
    std::string scratch = env("RAYKIT_SCRATCH");
    std::string hide = env("RAYKIT_HIDE");
    double call_seconds = std::atof(env("RAYKIT_CALL_SECONDS", "2").c_str());
};

Settings& settings() {
    static Settings s;
    return s;
}

/// One answers process: its pipes, and the sandbox it lives in.
class Child {
public:
    Child(std::string exe, bool sandboxed) : exe_(std::move(exe)), sandboxed_(sandboxed) {}
    ~Child() { stop(); }

    bool available() const { return !exe_.empty() && ::access(exe_.c_str(), X_OK) == 0; }
    bool running() const { return pid_ > 0; }

    /// Sends a request, returns the reply body, or throws CallFailed.
    std::string exchange(const std::string& request, const std::string& call, double seconds);

    /// Ends every process of this child and the child itself.
    void stop();

    /// Ends the processes the student's code started, keeping the answers process
    /// where the isolation allows it; at worst, the child itself is stopped too.
    void reap_leftovers();

    std::string output;          // printed during the current case (first kept_output bytes)
    std::size_t output_case = 0; // bytes printed during the current case

private:
    void start();
    void drain_output();
    std::string died(const std::string& call);

    std::string exe_;
    bool sandboxed_;
    pid_t pid_ = -1;
    int req_ = -1, rep_ = -1, out_ = -1;
    std::string scratch_;
};

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> parts;
    std::stringstream in(s);
    std::string part;
    while (std::getline(in, part, sep))
        if (!part.empty()) parts.push_back(part);
    return parts;
}

bool inside(const std::string& path, const std::string& dir) {
    return path == dir || (path.size() > dir.size() && path.compare(0, dir.size(), dir) == 0 &&
                           path[dir.size()] == '/');
}

void Child::start() {
    Settings& cfg = settings();
    if (scratch_.empty()) {
        scratch_ = cfg.scratch;
        if (scratch_.empty()) {
            char tmpl[] = "/tmp/raykit-answers-XXXXXX";
            if (::mkdtemp(tmpl) == nullptr) throw CallFailed("the grader could not make a scratch folder");
            scratch_ = tmpl;
        }
    }
    std::vector<std::string> argv;
    const std::string mode = sandboxed_ ? cfg.isolation : "none";
    if (mode == "bwrap") {
        // A read-only view of the machine with the kit, the homes and /tmp hidden,
        // one writable folder, no network, its own PID namespace (so that every
        // process it starts can be found and ended), an unprivileged user id.
        argv = {"bwrap", "--ro-bind", "/", "/", "--dev", "/dev", "--proc", "/proc"};
        std::vector<std::string> hidden = {"/tmp", "/home", "/root", "/autograder"};
        for (const std::string& h : split(cfg.hide, ':')) hidden.push_back(h);
        std::vector<std::string> done;
        for (const std::string& h : hidden) {
            bool covered = false;
            for (const std::string& d : done) covered = covered || inside(h, d);
            struct stat st{};
            if (covered || ::stat(h.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) continue;
            argv.insert(argv.end(), {"--tmpfs", h});
            done.push_back(h);
        }
        argv.insert(argv.end(), {"--bind", scratch_, scratch_, "--chdir", scratch_, "--unshare-all",
                                 "--unshare-user", "--uid", "65534", "--gid", "65534", "--die-with-parent",
                                 "--new-session", "--cap-drop", "ALL", "--", exe_});
    } else {
        argv = {exe_};
    }
    int rq[2], rp[2], ou[2];
    if (::pipe2(rq, O_CLOEXEC) != 0 || ::pipe2(rp, O_CLOEXEC) != 0 || ::pipe2(ou, O_CLOEXEC) != 0)
        throw CallFailed("the grader could not open pipes to your code");
    uid_t uid = 0;
    const bool as_user = mode.rfind("user:", 0) == 0;
    if (as_user) uid = static_cast<uid_t>(std::strtoul(mode.c_str() + 5, nullptr, 10));

    std::vector<char*> args;
    for (std::string& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    std::string home = "HOME=" + scratch_;
    char path[] = "PATH=/usr/bin:/bin";
    char lang[] = "LANG=C.UTF-8";
    char* envp[] = {path, lang, home.data(), nullptr};

    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) throw CallFailed("the grader could not start your code (fork failed)");
    if (pid == 0) {
        ::setpgid(0, 0);
        ::dup2(rq[0], 0);
        ::dup2(ou[1], 1);
        ::dup2(ou[1], 2);
        ::dup2(rp[1], 3);
        for (int fd = 0; fd <= 3; ++fd) ::fcntl(fd, F_SETFD, 0);
        for (int fd = 4; fd < 1024; ++fd) ::close(fd);
        ::signal(SIGPIPE, SIG_DFL);
        if (sandboxed_ && mode != "none") {
            // Bounds a sandboxed child cannot raise: no core files, files it writes
            // at most 64 MiB, CPU time bounded even if the grader itself were stopped.
            const struct rlimit core{0, 0}, fsize{64u << 20, 64u << 20}, cpu{60, 60};
            ::setrlimit(RLIMIT_CORE, &core);
            ::setrlimit(RLIMIT_FSIZE, &fsize);
            ::setrlimit(RLIMIT_CPU, &cpu);
        }
        if (as_user) {
            const struct rlimit nproc{256, 256};
            if (::setgroups(0, nullptr) != 0 || ::setgid(uid) != 0 || ::setuid(uid) != 0 || ::getuid() != uid)
                ::_exit(126);
            ::setrlimit(RLIMIT_NPROC, &nproc);
        }
        if (::chdir(scratch_.c_str()) != 0) ::_exit(126);
        if (argv[0] == "bwrap") ::execvpe("bwrap", args.data(), envp);
        else ::execve(args[0], args.data(), envp);
        ::_exit(127);
    }
    ::close(rq[0]);
    ::close(rp[1]);
    ::close(ou[1]);
    pid_ = pid;
    req_ = rq[1];
    rep_ = rp[0];
    out_ = ou[0];
    ::fcntl(out_, F_SETFL, ::fcntl(out_, F_GETFL) | O_NONBLOCK);
    ::fcntl(rep_, F_SETFL, ::fcntl(rep_, F_GETFL) | O_NONBLOCK);
}

void Child::drain_output() {
    if (out_ < 0) return;
    char buf[65536];
    for (;;) {
        const ssize_t n = ::read(out_, buf, sizeof buf);
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
            if (::setgroups(0, nullptr) == 0 && ::setgid(uid) == 0 && ::setuid(uid) == 0) ::kill(-1, SIGKILL);
            ::_exit(0);
        }
        if (helper > 0) ::waitpid(helper, nullptr, 0);
    }
    for (int* fd : {&req_, &rep_, &out_}) {
        if (*fd >= 0) ::close(*fd);
        *fd = -1;
    }
    pid_ = -1;
}

std::string read_link(const std::string& path) {
    char buf[256];
    const ssize_t n = ::readlink(path.c_str(), buf, sizeof buf - 1);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
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
    std::ifstream children("/proc/" + std::to_string(pid_) + "/task/" + std::to_string(pid_) + "/children");
    pid_t init = 0;
    if (!(children >> init) || init <= 0) return;
    const std::string ns = read_link("/proc/" + std::to_string(init) + "/ns/pid");
    if (ns.empty()) return;
    DIR* proc = ::opendir("/proc");
    if (!proc) return;
    while (const dirent* e = ::readdir(proc)) {
        char* end = nullptr;
        const long pid = std::strtol(e->d_name, &end, 10);
        if (pid <= 0 || *end != '\0') continue;
        if (read_link(std::string("/proc/") + e->d_name + "/ns/pid") != ns) continue;
        std::ifstream status(std::string("/proc/") + e->d_name + "/status");
        std::string line;
        long inner = 0;
        while (std::getline(status, line)) {
            if (line.rfind("NSpid:", 0) == 0) {
                std::istringstream fields(line.substr(6));
                long v;
                while (fields >> v) inner = v;
            }
        }
        if (inner > 2) ::kill(static_cast<pid_t>(pid), SIGKILL);
    }
    ::closedir(proc);
}

std::string Child::died(const std::string& call) {
    int status = 0;
    pid_t got = 0;
    for (int i = 0; i < 200 && (got = ::waitpid(pid_, &status, WNOHANG)) == 0; ++i) ::usleep(1000);
    drain_output();
    std::string how;
    if (got == pid_ && WIFSIGNALED(status)) {
        how = "it was killed by " + signal_name(WTERMSIG(status));
    } else if (got == pid_ && WIFEXITED(status)) {
        // bwrap passes on the sandboxed program's status; 128+N is a signal.
        const int code = WEXITSTATUS(status);
        how = code > 128 && code < 128 + 65 ? "it was killed by " + signal_name(code - 128)
                                            : "the program ended (exit status " + std::to_string(code) +
                                                  "): does your code call exit() or close the grader's pipes?";
    } else {
        how = "it closed the connection to the grader";
    }
    if (got == pid_) pid_ = -1;
    stop();
    return "Your code crashed in " + call + ": " + how + ".";
}

std::string Child::exchange(const std::string& request, const std::string& call, double seconds) {
    if (!running()) start();
    const std::uint32_t size = static_cast<std::uint32_t>(request.size());
    std::string framed(reinterpret_cast<const char*>(&size), sizeof size);
    framed += request;
    if (!wire::write_exact(req_, framed.data(), framed.size())) throw CallFailed(died(call));

    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(seconds));
    std::string reply;
    std::uint32_t want = 0;
    bool have_size = false;
    char buf[65536];
    for (;;) {
        if (output_case > output_limit) {
            stop();
            throw CallFailed("Your code printed more than " + std::to_string(output_limit >> 20) +
                             " MiB during " + call + " and was stopped.");
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
        if (left <= 0) {
            stop();
            char limit[32];
            std::snprintf(limit, sizeof limit, "%g", seconds);
            throw CallFailed("Time out: " + call + " did not return within " + limit + " s. An endless loop?");
        }
        pollfd fds[2] = {{rep_, POLLIN, 0}, {out_, POLLIN, 0}};
        const int n = ::poll(fds, 2, static_cast<int>(std::min<long long>(left, 100)));
        if (n < 0 && errno != EINTR) throw CallFailed(died(call));
        if (fds[1].revents) drain_output();
        if (!fds[0].revents) continue;
        const ssize_t k = ::read(rep_, buf, sizeof buf);
        if (k == 0 || (k < 0 && errno != EAGAIN && errno != EINTR)) throw CallFailed(died(call));
        if (k < 0) continue;
        reply.append(buf, static_cast<std::size_t>(k));
        if (!have_size && reply.size() >= sizeof want) {
            std::memcpy(&want, reply.data(), sizeof want);
            have_size = true;
            if (want > reply_limit) {
                stop();
                throw CallFailed(call + " sent back an answer far larger than any case needs.");
            }
        }
        if (have_size && reply.size() >= sizeof want + want) {
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
    bool timed_out_once = false;
};

State& state() {
    static State s;
    return s;
}

}  // namespace

bool set_built_programs(const char* answers, const char* reference) {
    built_answers() = answers;
    built_reference() = reference;
    return true;
}

bool has_reference() { return state().reference.available(); }

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
    std::string request(1, static_cast<char>(function.size()));
    request += function;
    request += arguments;
    // Once a call has hung, later calls get less time: a student's loop rarely
    // hangs only once, and the whole step has a time budget.
    const double limit = settings().call_seconds * (s.timed_out_once ? 0.25 : 1.0);
    std::string body;
    try {
        body = child.exchange(request, call, target == Target::student ? limit : 60.0);
    } catch (const CallFailed& e) {
        if (target == Target::student) {
            const std::string what = e.what();
            const bool hung = what.rfind("Time out", 0) == 0;
            s.timed_out_once = s.timed_out_once || hung;
            s.incident = {hung ? "timed_out" : "crashed", what};
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
            const std::string text = "Your code threw an exception in " + call + ": " + message;
            if (target == Target::student && s.incident.message.empty()) s.incident = {"threw", text};
            throw CallFailed(text);
        }
        case wire::Kind::unknown:
            throw CallFailed("the answers program has no function " + function + " (a kit bug: please report it)");
    }
    throw CallFailed(call + " sent back an answer of an unknown kind.");
}

void begin_case() {
    State& s = state();
    s.incident = {};
    s.student.output.clear();
    s.student.output_case = 0;
}

CaseRecord end_case() {
    State& s = state();
    s.student.reap_leftovers();
    CaseRecord r{s.incident, s.student.output, s.student.output_case};
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

// The judge's operating-system part (platform.hpp): Linux, and any other POSIX system.
// RAYKIT_PLATFORM_POSIX forces the second on Linux: CI builds it so, as a Mac would.

#include "platform.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>

#if defined(__linux__) && !defined(RAYKIT_PLATFORM_POSIX)
#include <dirent.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#define RAYKIT_PLATFORM_LINUX 1
#endif

namespace raykit::platform {

namespace {

std::size_t page_size() {
    static const std::size_t page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
    return page;
}

// The readable pages an object of `size` bytes takes (at least one), the guard page after them.
std::size_t data_bytes(std::size_t size) {
    const std::size_t page = page_size();
    return std::max<std::size_t>(1, (size + page - 1) / page) * page;
}

}  // namespace

void* guarded_allocate(std::size_t size, std::size_t align) {
    const std::size_t data = data_bytes(size), page = page_size();
    // MAP_ANON: the spelling macOS and Linux share.
    void* base = ::mmap(nullptr, data + page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANON, -1, 0);
    if (base == MAP_FAILED) return nullptr;
    char* end = static_cast<char*>(base) + data;
    if (::mprotect(end, page, PROT_NONE) != 0) {
        ::munmap(base, data + page);
        return nullptr;
    }
    // The object ends at the guard when `align` divides `size` (always so for sizeof(T), alignof(T)).
    const std::uintptr_t at = (reinterpret_cast<std::uintptr_t>(end) - size) & ~(std::uintptr_t{align} - 1);
    return reinterpret_cast<void*>(at);
}

void guarded_release(void* p, std::size_t size) {
    if (p == nullptr) return;
    // The object starts in the first page of its mapping (it takes less than a page more than it needs).
    const std::uintptr_t base = reinterpret_cast<std::uintptr_t>(p) & ~(std::uintptr_t{page_size()} - 1);
    ::munmap(reinterpret_cast<void*>(base), data_bytes(size) + page_size());
}

bool open_pipe(int fds[2]) {
    if (::pipe(fds) != 0) return false;
    for (int i = 0; i < 2; ++i) {
        if (::fcntl(fds[i], F_SETFD, FD_CLOEXEC) != 0) {
            ::close(fds[0]);
            ::close(fds[1]);
            return false;
        }
    }
    return true;
}

void exec_on_path(const char* file, char* const argv[], char* const envp[]) {
    std::string path = "/usr/bin:/bin";
    for (char* const* e = envp; *e; ++e)
        if (std::strncmp(*e, "PATH=", 5) == 0) path = *e + 5;
    std::size_t start = 0;
    while (start <= path.size()) {
        const std::size_t end = path.find(':', start);
        const std::string dir = path.substr(start, end == std::string::npos ? std::string::npos : end - start);
        const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + file;
        ::execve(candidate.c_str(), argv, envp);
        if (end == std::string::npos) break;
        start = end + 1;
    }
}

#if defined(RAYKIT_PLATFORM_LINUX)

namespace {

std::string read_link(const std::string& path) {
    char buf[256];
    const ssize_t n = ::readlink(path.c_str(), buf, sizeof buf - 1);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
}

}  // namespace

double cpu_seconds(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    // getline, not an istreambuf_iterator: a process that dies while its file is read makes the read
    // fail (ESRCH), which libstdc++'s filebuf throws as an exception through an iterator (seen: the
    // call the program crashed in graded "threw"), while a stream function only sets a flag.
    std::string text;
    std::getline(in, text);
    // The fields after the command name (which may hold spaces) start after its last ')'.
    const std::size_t close = text.rfind(')');
    if (close == std::string::npos) return -1;
    std::istringstream fields(text.substr(close + 2));
    std::string f;
    unsigned long long utime = 0, stime = 0;
    for (int i = 3; i <= 15 && fields >> f; ++i) {
        if (i == 14) utime = std::strtoull(f.c_str(), nullptr, 10);
        if (i == 15) stime = std::strtoull(f.c_str(), nullptr, 10);
    }
    const long ticks = ::sysconf(_SC_CLK_TCK);
    return ticks > 0 ? static_cast<double>(utime + stime) / static_cast<double>(ticks) : -1;
}

double queued_seconds(pid_t pid) {
    // The second field of schedstat, in ns (the first is the time on a CPU).
    std::ifstream in(pid > 0 ? "/proc/" + std::to_string(pid) + "/schedstat" : "/proc/thread-self/schedstat");
    unsigned long long on_cpu = 0, queued = 0;
    return (in >> on_cpu >> queued) ? static_cast<double>(queued) / 1e9 : 0;
}

pid_t first_child(pid_t pid) {
    std::ifstream children("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children");
    long c = 0;
    return (children >> c) && c > 0 ? static_cast<pid_t>(c) : 0;
}

void end_namespace_rest(pid_t init) {
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
        long inner = 0;     // the process's id inside the namespace: the last of NSpid's
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

#else   // any other POSIX system: no /proc to read, no bubblewrap to look into

double cpu_seconds(pid_t) { return -1; }

double queued_seconds(pid_t) { return 0; }

pid_t first_child(pid_t) { return 0; }

void end_namespace_rest(pid_t) {}

#endif

}  // namespace raykit::platform

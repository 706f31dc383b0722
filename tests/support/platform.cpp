// The judge's operating-system part (platform.hpp): Linux, and any other POSIX system.
// RAYKIT_PLATFORM_POSIX forces the second on Linux: CI builds it so, as a Mac would.
//
// C and POSIX headers only, no streams or strings: this file is compiled into every judge and
// answers program (one object, CMakeLists.txt's raykit_platform), and with <fstream> and <sstream>
// it took 0.55 s of CPU to compile where it now takes a tenth of that; /proc's files are short lines
// read with read(2) into a fixed buffer.

#include "platform.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#if defined(__linux__) && !defined(RAYKIT_PLATFORM_POSIX)
#include <dirent.h>
#include <sys/syscall.h>
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
    const std::size_t pages = (size + page - 1) / page;
    return (pages > 0 ? pages : 1) * page;
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
    const char* path = "/usr/bin:/bin";
    for (char* const* e = envp; *e; ++e)
        if (std::strncmp(*e, "PATH=", 5) == 0) path = *e + 5;
    char candidate[4096];
    for (const char* dir = path;; ) {
        const char* end = std::strchr(dir, ':');
        const std::size_t n = end ? static_cast<std::size_t>(end - dir) : std::strlen(dir);
        // An empty entry is the current folder; an entry too long for the buffer is skipped.
        const int len = n == 0 ? std::snprintf(candidate, sizeof candidate, "./%s", file)
                               : std::snprintf(candidate, sizeof candidate, "%.*s/%s", static_cast<int>(n), dir, file);
        if (len > 0 && static_cast<std::size_t>(len) < sizeof candidate) ::execve(candidate, argv, envp);
        if (!end) break;
        dir = end + 1;
    }
}

#if defined(RAYKIT_PLATFORM_LINUX)

namespace {

// Reads the start of a /proc file (the lines read here are far shorter than the buffer) into `buf`,
// NUL-terminated; false when it cannot be read (a process that died in between: ESRCH, ENOENT).
bool read_proc(const char* path, char* buf, std::size_t size) {
    const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    std::size_t got = 0;
    while (got + 1 < size) {
        const ssize_t n = ::read(fd, buf + got, size - 1 - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        got += static_cast<std::size_t>(n);
    }
    ::close(fd);
    buf[got] = '\0';
    return got > 0;
}

// The target of the link at `path` in `buf` (NUL-terminated), or "" when it cannot be read.
void read_link(const char* path, char* buf, std::size_t size) {
    const ssize_t n = ::readlink(path, buf, size - 1);
    buf[n > 0 ? n : 0] = '\0';
}

}  // namespace

double cpu_seconds(pid_t pid) {
    char path[64], text[1024];
    std::snprintf(path, sizeof path, "/proc/%d/stat", static_cast<int>(pid));
    if (!read_proc(path, text, sizeof text)) return -1;
    // The fields after the command name (which may hold spaces and parentheses) start after its last
    // ')': field 3 (the state) is the first; utime and stime are fields 14 and 15.
    const char* at = std::strrchr(text, ')');
    if (at == nullptr) return -1;
    at += 1;
    unsigned long long utime = 0, stime = 0;
    for (int field = 3; field <= 15; ++field) {
        while (*at == ' ') ++at;
        if (*at == '\0') return -1;
        char* end = nullptr;
        const unsigned long long v = std::strtoull(at, &end, 10);
        if (field == 14) utime = v;
        if (field == 15) stime = v;
        at = std::strchr(at, ' ');
        if (at == nullptr) return field == 15 ? 0 : -1;
    }
    const long ticks = ::sysconf(_SC_CLK_TCK);
    return ticks > 0 ? static_cast<double>(utime + stime) / static_cast<double>(ticks) : -1;
}

double queued_seconds(pid_t pid) {
    // The second field of schedstat, in ns (the first is the time on a CPU).
    char path[64], text[256];
    if (pid > 0) std::snprintf(path, sizeof path, "/proc/%d/schedstat", static_cast<int>(pid));
    else std::snprintf(path, sizeof path, "/proc/thread-self/schedstat");
    unsigned long long on_cpu = 0, queued = 0;
    if (!read_proc(path, text, sizeof text)) return 0;
    return std::sscanf(text, "%llu %llu", &on_cpu, &queued) == 2 ? static_cast<double>(queued) / 1e9 : 0;
}

pid_t first_child(pid_t pid) {
    char path[96], text[256];
    std::snprintf(path, sizeof path, "/proc/%d/task/%d/children", static_cast<int>(pid), static_cast<int>(pid));
    long c = 0;
    return read_proc(path, text, sizeof text) && std::sscanf(text, "%ld", &c) == 1 && c > 0 ? static_cast<pid_t>(c) : 0;
}

void end_namespace_rest(pid_t init) {
    char path[96], ns[256], other[256];
    std::snprintf(path, sizeof path, "/proc/%d/ns/pid", static_cast<int>(init));
    read_link(path, ns, sizeof ns);
    if (ns[0] == '\0') return;
    DIR* proc = ::opendir("/proc");
    if (!proc) return;
    static char status[8192];  // /proc/PID/status is about 1.5 KB
    while (const dirent* e = ::readdir(proc)) {
        char* end = nullptr;
        const long pid = std::strtol(e->d_name, &end, 10);
        if (pid <= 0 || *end != '\0') continue;
        std::snprintf(path, sizeof path, "/proc/%ld/ns/pid", pid);
        read_link(path, other, sizeof other);
        if (std::strcmp(other, ns) != 0) continue;
        std::snprintf(path, sizeof path, "/proc/%ld/status", pid);
        if (!read_proc(path, status, sizeof status)) continue;
        // The process's id inside the namespace: the last number of the NSpid line.
        long inner = 0;
        const char* line = std::strstr(status, "\nNSpid:");
        if (line != nullptr) {
            const char* at = line + 7;
            while (*at != '\0' && *at != '\n') {
                char* next = nullptr;
                const long v = std::strtol(at, &next, 10);
                if (next == at) break;
                inner = v;
                at = next;
            }
        }
        if (inner > 2) ::kill(static_cast<pid_t>(pid), SIGKILL);
    }
    ::closedir(proc);
}

void clear_keyrings() {
#if defined(SYS_keyctl)
    // <linux/keyctl.h>'s numbers, written here: no libkeyutils, and the header is not on every system.
    constexpr long join_session = 1, clear = 7, get_persistent = 22;
    constexpr long user_keyring = -4, user_session_keyring = -5, session_keyring = -3;
    (void)::syscall(SYS_keyctl, join_session, 0L);  // a new anonymous session keyring: the caller's is left
    (void)::syscall(SYS_keyctl, clear, user_keyring);
    (void)::syscall(SYS_keyctl, clear, user_session_keyring);
    const long persistent = ::syscall(SYS_keyctl, get_persistent, -1L, session_keyring);
    if (persistent > 0) (void)::syscall(SYS_keyctl, clear, persistent);
#endif
}

#else   // any other POSIX system: no /proc to read, no bubblewrap to look into

void clear_keyrings() {}

double cpu_seconds(pid_t) { return -1; }

double queued_seconds(pid_t) { return 0; }

pid_t first_child(pid_t) { return 0; }

void end_namespace_rest(pid_t) {}

#endif

}  // namespace raykit::platform

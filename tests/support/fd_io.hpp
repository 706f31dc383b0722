// Whole reads and writes on a pipe: both ends of the wire (remote.cpp, answers_main.cpp)
// move framed messages, and a short read or write must be finished, not mistaken for the end.
#pragma once

#include <unistd.h>

#include <cerrno>
#include <cstddef>

namespace raykit::wire {

/// Writes all `n` bytes unless the pipe is closed (false).
inline bool write_exact(int fd, const char* p, std::size_t n) {
    while (n > 0) {
        const ssize_t k = ::write(fd, p, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) return false;
        p += k;
        n -= static_cast<std::size_t>(k);
    }
    return true;
}

/// Reads exactly `n` bytes unless the pipe ends first (false).
inline bool read_exact(int fd, char* p, std::size_t n) {
    while (n > 0) {
        const ssize_t k = ::read(fd, p, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) return false;
        p += k;
        n -= static_cast<std::size_t>(k);
    }
    return true;
}

}  // namespace raykit::wire

// What the judge needs of the operating system beyond POSIX and C++17, in one place
// (tests/support/platform.cpp). Everything else of the student-side C++ (the judge, the answers
// program, the kit's support) uses only what macOS and Linux share; CI builds this code as a Mac
// would see it (selftest/check.py, "portable by construction") and fails on a Linux-only call.
//
// Linux reads /proc for a process's CPU time and for bubblewrap's sandbox; elsewhere (a Mac, where
// a student checks their own steps without a sandbox) a call's time is measured on the wall clock
// and there is no sandbox to look into.
#pragma once

#include <sys/types.h>

#include <cstddef>

namespace raykit::platform {

/// A pipe whose two ends are closed on exec (pipe + FD_CLOEXEC: no pipe2 on macOS before 27).
bool open_pipe(int fds[2]);

/// CPU time (user + system) process `pid` has used so far, in seconds; < 0 where it cannot be read.
double cpu_seconds(pid_t pid);

/// Seconds process `pid`'s main thread has spent runnable but waiting for a CPU (the judge's own for
/// 0): time a busy machine takes from a call, not time the call waits; 0 where the system does not say.
double queued_seconds(pid_t pid);

/// The first child of `pid` (bubblewrap's init, then the program it runs), or 0.
pid_t first_child(pid_t pid);

/// Ends every process in the PID namespace of `init` (bubblewrap's) but its first two (bubblewrap's
/// init and the answers program): what the student's code started during a case.
void end_namespace_rest(pid_t init);

/// Empties the kernel keyrings of the calling process's user id that outlive its processes (the
/// user keyring and the user-session keyring; also the persistent keyring where the kernel has one),
/// then gives the process a fresh session keyring of its own, so that it holds no keyring of the
/// user id it came from. Called by the judge after it takes a sandbox's user id, before the answers
/// program starts and again when every process of that id is ended: nothing one run keeps there
/// reaches the next run (a case re-run alone, the next student in the slot). A no-op where the
/// system has no such keyrings (not Linux) or refuses keyctl (Docker's default seccomp profile).
void clear_keyrings();

/// execve of `file` found on the PATH given in `envp` (execvpe is a GNU extension). Returns only
/// when nothing could be started.
void exec_on_path(const char* file, char* const argv[], char* const envp[]);

/// Memory for one object of `size` bytes, aligned to `align` (a power of two that divides `size`),
/// that ends exactly where a page no one may read or write begins (mmap + mprotect): a read or
/// write past its end faults at once, in every build, sanitized or not. The answers program hands
/// each argument of a student's function over in such memory, so that `(&v.x)[3]` or `<= count`
/// is a crash on every machine, never a read of whatever lay beside it. nullptr when the system
/// refuses.
void* guarded_allocate(std::size_t size, std::size_t align);

/// Gives back memory from guarded_allocate; `size` as it was asked for.
void guarded_release(void* p, std::size_t size);

}  // namespace raykit::platform

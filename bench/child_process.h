// Timing a stage of work in a child process of its own, so that neither a
// generator's heap nor an earlier stage's pages count in its time or its peak
// memory, and a reader pays for its fresh pages as a user's process does.
// Shared by the reader benchmarks.
#pragma once
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <chrono>

namespace mbx_bench {

// User + system CPU seconds of this process so far (the scheduler's own
// count: getrusage's moves in clock ticks, too coarse for small files).
inline double cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Wall and CPU time of a step.
struct Timer {
    std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
    double cpu = cpu_seconds();
    void stop(double& wall_out, double& cpu_out) const {
        wall_out = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
        cpu_out = cpu_seconds() - cpu;
    }
};

// Runs `work` in a child process and reads back the trivially copyable
// result it returns; false when the child failed.
template <class Result, class Work>
bool in_child(Work work, Result& out) {
    int fd[2];
    if (pipe(fd) != 0) return false;
    const pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        const Result r = work();
        if (write(fd[1], &r, sizeof r) != sizeof r) _exit(1);
        _exit(0);
    }
    close(fd[1]);
    const bool ok = read(fd[0], &out, sizeof out) == sizeof out;
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return ok && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace mbx_bench

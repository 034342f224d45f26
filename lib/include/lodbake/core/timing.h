// Wall-clock and CPU timing for the per-stage times of reports (never part of any output file).
#pragma once

#include <chrono>
#include <ctime>

namespace lodbake {

using Clock = std::chrono::steady_clock;

// Seconds of wall time since t0.
inline double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// CPU time of the whole process (every thread, user + system) so far, seconds: the figure that
// stays meaningful on a loaded machine.
inline double processCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace lodbake

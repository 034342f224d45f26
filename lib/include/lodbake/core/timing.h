// Wall-clock timing for the per-stage times of reports (never part of any output file).
#pragma once

#include <chrono>

namespace lodbake {

using Clock = std::chrono::steady_clock;

// Seconds of wall time since t0.
inline double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace lodbake

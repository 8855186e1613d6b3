#pragma once
// CPU time of the calling thread, for real-time factors (simulated seconds per CPU second).

#include <ctime>

namespace jawari
{

inline double threadCpuSeconds()
{
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace jawari

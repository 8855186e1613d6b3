// jawari-lockstep: what two cores pay to meet, as strings on one body would have to at every
// internal step if a second core stepped half of them (docs/measurements.md, "A second core on the
// body"). Measures and reports.
//
//   jawari-lockstep [--meetings 300000] [--work NS]
//
// The audio thread hands the worker a step's share and takes its answer back, by two atomic flags
// that each side spins on (no lock, no system call): the handoff a lockstep needs after the strings'
// predictions and after each of the secant's contact solves. Each side then does `work` ns of
// arithmetic (its half of the strings), so the second figure shows what overlaps. Printed: the mean
// time of a meeting, the share of one core that 2.3 meetings a step at 144 kHz (the Sitar's internal
// rate, 1.33 solves a step and the predictions' meeting) would take, and the slowest meetings.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;

// About `ns` nanoseconds of dependent arithmetic; returns its result so that it is not optimised away.
double busyWork(long ns, double seed)
{
    double x = seed;
    const long rounds = ns / 2;  // a dependent multiply-add is some 1-2 ns
    for (long k = 0; k < rounds; ++k)
        x = x * 0.999999 + 1e-9;
    return x;
}

struct Meetings
{
    double meanNs = 0.0;
    std::vector<double> nanoseconds;  // each meeting's, from the handoff to the answer
};

Meetings meet(long count, long workNs)
{
    std::atomic<long> posted{0}, answered{0};
    std::atomic<bool> stop{false};
    double sink = 0.0;
    std::thread worker([&] {
        double x = 1.0;
        long seen = 0;
        while (true)
        {
            long now = posted.load(std::memory_order_acquire);
            while (now == seen && !stop.load(std::memory_order_relaxed))
                now = posted.load(std::memory_order_acquire);
            if (now == seen)
                break;
            seen = now;
            x = busyWork(workNs, x);
            answered.store(seen, std::memory_order_release);
        }
        sink += x;
    });
    Meetings m;
    m.nanoseconds.reserve(size_t(count));
    double x = 2.0;
    const auto start = Clock::now();
    for (long k = 1; k <= count; ++k)
    {
        const auto t0 = Clock::now();
        posted.store(k, std::memory_order_release);
        x = busyWork(workNs, x);
        while (answered.load(std::memory_order_acquire) != k)
        {
        }
        m.nanoseconds.push_back(std::chrono::duration<double, std::nano>(Clock::now() - t0).count());
    }
    m.meanNs = std::chrono::duration<double, std::nano>(Clock::now() - start).count() / double(count);
    stop.store(true);
    worker.join();
    std::printf("%s", sink + x == 0.123 ? " " : "");  // keeps both threads' work
    return m;
}

// What busyWork(ns) takes on this thread alone, on average (ns).
double workAloneNs(long ns)
{
    constexpr int kRounds = 2000;
    double x = 3.0;
    const auto start = Clock::now();
    for (int k = 0; k < kRounds; ++k)
        x = busyWork(ns, x);
    const double each = std::chrono::duration<double, std::nano>(Clock::now() - start).count() / kRounds;
    std::printf("%s", x == 0.123 ? " " : "");
    return each;
}

double percentile(std::vector<double> v, double p)
{
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(p * double(v.size())))];
}
}  // namespace

int main(int argc, char** argv)
{
    long count = 300000, work = -1;
    for (int i = 1; i + 1 < argc; i += 2)
    {
        if (std::strcmp(argv[i], "--meetings") == 0)
            count = std::max(1000L, std::stol(argv[i + 1]));
        else if (std::strcmp(argv[i], "--work") == 0)
            work = std::max(0L, std::stol(argv[i + 1]));
        else
        {
            std::fprintf(stderr, "usage: jawari-lockstep [--meetings 300000] [--work NS]\n");
            return 2;
        }
    }
    if (std::thread::hardware_concurrency() < 2)
        std::printf("jawari-lockstep: one core only; the figures are those of two threads taking turns\n");
    constexpr double kMeetingsPerSecond = 2.3 * 144000.0;
    for (const long w : work >= 0 ? std::vector<long>{work} : std::vector<long>{0, 2000})
    {
        const auto m = meet(count, w);
        const double alone = workAloneNs(w);  // each side's own work, were it not met
        std::printf("work %ld ns a side: a meeting %.0f ns (%.0f ns beyond the work); at 2.3 meetings a step and "
                    "144 kHz, %.1f %% of a core; p99 %.0f ns, p99.9 %.0f ns, slowest %.0f ns\n",
                    w, m.meanNs, m.meanNs - alone, 100.0 * (m.meanNs - alone) * 1e-9 * kMeetingsPerSecond,
                    percentile(m.nanoseconds, 0.99), percentile(m.nanoseconds, 0.999),
                    *std::max_element(m.nanoseconds.begin(), m.nanoseconds.end()));
    }
    return 0;
}

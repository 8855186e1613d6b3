#pragma once
// Counts what a real-time thread never does, on the threads a test marks real-time: allocations (the
// global operator new and glibc's allocator replaced in AllocationCounter.cpp, linked only into the
// binaries that check real-time threads: jawari-realtime-tests, jawari-plugin-tests) and locks
// (LockCounter.h, jawari-realtime-tests only). A mark is per thread: the test's audio thread marks
// itself, and the second core's worker is marked from its task hook (StringWorker::setTaskHookForTesting).

#include <atomic>

namespace jawari::test
{
// What the threads marked with one of these did. It must outlive every thread marked with it.
struct RealtimeCounts
{
    std::atomic<long> allocations{0};
    std::atomic<long> locks{0};
};

// Marks this thread real-time, counting into `counts`, or unmarks it (null). The thread_local mark
// stays inside AllocationCounter.cpp: an extern thread_local reached through GCC's TLS wrapper trips
// UBSan's null check (a false report).
void countOnThisThread(RealtimeCounts* counts);
RealtimeCounts* countsOfThisThread();

// The test's audio thread: its counts, and its allocations alone under the name the tests read.
extern RealtimeCounts audioThreadCounts;
extern std::atomic<long>& allocations;
// Marks this thread (counting into audioThreadCounts) or unmarks it.
void countAllocationsOnThisThread(bool on);

// Zeroes the audio thread's counts and marks this thread for the guard's scope.
struct CountAllocations
{
    CountAllocations()
    {
        audioThreadCounts.allocations = 0;
        audioThreadCounts.locks = 0;
        countAllocationsOnThisThread(true);
    }
    ~CountAllocations() { countAllocationsOnThisThread(false); }
    CountAllocations(const CountAllocations&) = delete;
    CountAllocations& operator=(const CountAllocations&) = delete;
};
}  // namespace jawari::test

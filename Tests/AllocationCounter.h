#pragma once
// Counts allocations made by a thread while it holds a CountAllocations guard. The global operator
// new is replaced in AllocationCounter.cpp, linked only into the binaries that check the audio
// thread (jawari-realtime-tests, jawari-plugin-tests).

#include <atomic>

namespace jawari::test
{
extern std::atomic<long> allocations;
// Whether this thread counts. The thread_local flag stays inside AllocationCounter.cpp: an extern
// thread_local reached through GCC's TLS wrapper trips UBSan's null check (a false report).
void countAllocationsOnThisThread(bool on);

struct CountAllocations
{
    CountAllocations()
    {
        allocations = 0;
        countAllocationsOnThisThread(true);
    }
    ~CountAllocations() { countAllocationsOnThisThread(false); }
    CountAllocations(const CountAllocations&) = delete;
    CountAllocations& operator=(const CountAllocations&) = delete;
};
}  // namespace jawari::test

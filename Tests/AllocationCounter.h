#pragma once
// Counts allocations made by a thread while it holds a CountAllocations guard. The global operator
// new is replaced in AllocationCounter.cpp, linked only into the binaries that check the audio
// thread (jawari-realtime-tests, jawari-plugin-tests).

#include <atomic>

namespace jawari::test
{
extern thread_local bool countingAllocations;
extern std::atomic<long> allocations;

struct CountAllocations
{
    CountAllocations()
    {
        allocations = 0;
        countingAllocations = true;
    }
    ~CountAllocations() { countingAllocations = false; }
    CountAllocations(const CountAllocations&) = delete;
    CountAllocations& operator=(const CountAllocations&) = delete;
};
}  // namespace jawari::test

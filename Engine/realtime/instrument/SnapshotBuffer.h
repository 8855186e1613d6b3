#pragma once
// Hands the newest of a stream of values from the audio thread to the control thread (what the
// editor draws) without locks or allocation. Beside LockFreeExchange, which hands objects the
// other way.

#include <atomic>

namespace jawari
{

// A triple buffer: one writer (RT) publishes the newest value, one reader (CT) reads the newest
// published. No locks, no allocation; the reader never sees a half-written value.
template <typename T>
class SnapshotBuffer
{
public:
    T& back() { return buffers_[back_]; }  // RT: fill, then publish()
    void publish() { back_ = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel) & kIndex; }
    // CT: true and `out` filled when something new was published since the last read.
    bool read(T& out)
    {
        if ((middle_.load(std::memory_order_acquire) & kFresh) == 0)
            return false;
        front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndex;
        out = buffers_[front_];
        return true;
    }

private:
    static constexpr int kIndex = 3, kFresh = 4;
    T buffers_[3]{};
    int back_ = 0, front_ = 1;
    std::atomic<int> middle_{2};
};

}  // namespace jawari

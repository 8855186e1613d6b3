#pragma once
// Hands objects that are expensive to build (a voice with new modes or obstacles) from the control
// thread to the audio thread, and the replaced ones back, without locks or allocation on the audio
// thread (docs/design.md section 6). One producer (control thread), one consumer (audio thread).
//
//   CT: offer(std::make_unique<T>(...))   the newest offer wins; an unclaimed older one is freed here
//   RT: if (T* fresh = exchange.take(&previous))   at a block boundary: fresh becomes current
//       { fresh->takeMotionFrom(*previous); exchange.retire(); }   previous is handed back only now
//   CT: collect()                         frees what the audio thread retired (on a timer)
//
// The audio thread only takes when the retire slot is empty, so it never has to free anything; if
// the control thread has not collected yet, the offer simply waits for the next block.

#include <atomic>
#include <memory>

namespace jawari
{

template <typename T>
class LockFreeExchange
{
public:
    LockFreeExchange() = default;
    LockFreeExchange(const LockFreeExchange&) = delete;
    LockFreeExchange& operator=(const LockFreeExchange&) = delete;
    ~LockFreeExchange()
    {
        delete pending_.exchange(nullptr);
        delete retired_.exchange(nullptr);
        delete held_;
        delete current_;
    }

    // CT.
    void offer(std::unique_ptr<T> next) { delete pending_.exchange(next.release(), std::memory_order_acq_rel); }

    // CT: frees whatever the audio thread has retired. Returns how many objects it freed.
    int collect()
    {
        T* old = retired_.exchange(nullptr, std::memory_order_acq_rel);
        delete old;
        return old != nullptr ? 1 : 0;
    }

    // RT: the newest offered object if there is one (it becomes current), else nullptr. The object
    // it replaces is returned in `previous` and stays alive, untouched by the control thread, until
    // retire(): the caller can carry its state over first.
    T* take(T** previous = nullptr)
    {
        retire();  // in case the last take was not followed by retire()
        if (retired_.load(std::memory_order_acquire) != nullptr)
            return nullptr;  // the control thread has not collected the last one yet
        T* next = pending_.exchange(nullptr, std::memory_order_acq_rel);
        if (next == nullptr)
            return nullptr;
        if (previous != nullptr)
            *previous = current_;
        held_ = current_;
        current_ = next;
        return next;
    }

    // RT: done with the object the last take() replaced: hand it to the control thread to free.
    // (The retire slot is empty here: take() checked it, and only collect() writes it meanwhile,
    // with nullptr.)
    void retire()
    {
        if (held_ != nullptr)
        {
            retired_.store(held_, std::memory_order_release);
            held_ = nullptr;
        }
    }

    T* current() const { return current_; }  // RT
    // CT: no offer waits for the audio thread; nothing retired waits to be collected.
    bool pendingEmpty() const { return pending_.load(std::memory_order_acquire) == nullptr; }
    bool retiredEmpty() const { return retired_.load(std::memory_order_acquire) == nullptr; }

private:
    std::atomic<T*> pending_{nullptr};
    std::atomic<T*> retired_{nullptr};
    T* current_ = nullptr;  // owned by the audio thread
    T* held_ = nullptr;     // replaced by take(), not yet retired
};

}  // namespace jawari

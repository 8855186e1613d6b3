#include "realtime/instrument/StringWorker.h"

#include "realtime/voice/Denormals.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace jawari
{

namespace
{
void cpuRelax()
{
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
}
}  // namespace

StringWorker::~StringWorker()
{
    stop();
}

void StringWorker::start()
{
    if (thread_.joinable())
        return;
    stopping_.store(false);
    running_.store(true, std::memory_order_release);
    thread_ = std::thread([this] { run(); });
}

void StringWorker::stop()
{
    if (!thread_.joinable())
        return;
    running_.store(false, std::memory_order_release);
    stopping_.store(true, std::memory_order_release);
    signal_.fetch_add(1, std::memory_order_release);
    signal_.notify_one();
    thread_.join();
}

bool StringWorker::idle() const
{
    return running() && jobFinished();
}

void StringWorker::post(int count, int samples)
{
    count_ = count < kMaxTasks ? count : kMaxTasks;
    samples_ = samples;
    for (int i = 0; i < count_; ++i)
        state_[size_t(i)].store(unready, std::memory_order_relaxed);
    posted_.fetch_add(1, std::memory_order_release);
    signal_.fetch_add(1, std::memory_order_release);
    signal_.notify_one();  // a futex wake only if the worker sleeps
}

void StringWorker::offer(int i, const Task& task)
{
    tasks_[size_t(i)] = task;
    state_[size_t(i)].store(posted, std::memory_order_release);
    if (const Pace pace = pace_.load(std::memory_order_relaxed); pace != Pace::free)  // tests only
        if (pace == Pace::inStep || i == 0)
            while (state_[size_t(i)].load(std::memory_order_acquire) == posted && running())
                std::this_thread::yield();
}

StringWorker::Outcome StringWorker::collect(int i, std::chrono::steady_clock::time_point deadline)
{
    if (pace_.load(std::memory_order_relaxed) == Pace::inStep)  // tests only
        deadline = std::chrono::steady_clock::time_point::max();
    auto& state = state_[size_t(i)];
    int seen = posted;
    if (state.compare_exchange_strong(seen, takenBack, std::memory_order_acq_rel))
        return Outcome::notStarted;
    while (seen == stepping && std::chrono::steady_clock::now() < deadline)
    {
        cpuRelax();
        seen = state.load(std::memory_order_acquire);
    }
    if (seen == stepping && state.compare_exchange_strong(seen, takenBack, std::memory_order_acq_rel))
        return Outcome::revoked;
    return Outcome::worker;  // done: its writes are visible (acquire)
}

void StringWorker::setTaskHookForTesting(TaskHook hook, void* context)
{
    hookContext_.store(context, std::memory_order_relaxed);
    hook_.store(hook, std::memory_order_release);
}

void StringWorker::waitForJobs(uint32_t jobs) const
{
    while (static_cast<int32_t>(finished_.load(std::memory_order_acquire) - jobs) < 0 && running())
        std::this_thread::sleep_for(std::chrono::microseconds(100));
}

void StringWorker::run()
{
    ScopedFlushDenormals flush;  // as the audio thread steps: the same arithmetic
    uint32_t seen = finished_.load(std::memory_order_acquire);
    while (waitForJob(seen))
    {
        seen = posted_.load(std::memory_order_acquire);
        runJob();
        finished_.store(seen, std::memory_order_release);
    }
}

// Spins for the next job for kSpin (the next chunk usually follows within it), then sleeps until
// a post or stop() changes signal_.
bool StringWorker::waitForJob(uint32_t seen)
{
    const auto spinUntil = std::chrono::steady_clock::now() + kSpin;
    for (unsigned spins = 1;; ++spins)
    {
        const uint32_t signal = signal_.load(std::memory_order_acquire);
        if (stopping_.load(std::memory_order_acquire))
            return false;
        if (posted_.load(std::memory_order_acquire) != seen)
            return true;
        if (spins % 256 != 0 || std::chrono::steady_clock::now() < spinUntil)  // the clock read now and then
            cpuRelax();
        else
            signal_.wait(signal, std::memory_order_acquire);
    }
}

// The tasks in order, each waited for until offered; each claimed by one compare-and-swap, and
// handed back the same way unless the audio thread took it meanwhile.
void StringWorker::runJob()
{
    for (int i = 0; i < count_; ++i)
    {
        auto& state = state_[size_t(i)];
        // The audio thread offers every task of a job right after posting it, before it steps anything.
        while (state.load(std::memory_order_acquire) == unready && !stopping_.load(std::memory_order_acquire))
            cpuRelax();
        int expected = posted;
        if (!state.compare_exchange_strong(expected, stepping, std::memory_order_acq_rel))
            continue;
        if (const TaskHook hook = hook_.load(std::memory_order_acquire))  // tests only
            hook(hookContext_.load(std::memory_order_relaxed));
        while (pace_.load(std::memory_order_acquire) == Pace::held && !stopping_.load(std::memory_order_acquire))
            std::this_thread::yield();
        const Task& task = tasks_[size_t(i)];
        task.voice->processInternal(task.block, samples_, task.second);
        expected = stepping;
        state.compare_exchange_strong(expected, done, std::memory_order_acq_rel);
    }
}

}  // namespace jawari

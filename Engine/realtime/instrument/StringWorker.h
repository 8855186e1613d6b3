#pragma once
// A second core for the instrument's strings (opt-in; docs/design.md section 6, "The second core").
//
// Each chunk, the audio thread opens a job of a share of the sounding strings and offers them one by
// one as tasks, so the worker starts on the first while the audio thread prepares the next. A task is
// a string's voice and blocks of the worker's own to step it into; just before offering it, the
// audio thread copies the voice into a BACKUP of its own (its state, and its tables only when they
// changed). The worker steps the string itself, so a string it keeps from chunk to chunk stays in
// its cache. Each task then ends one of three ways, decided by one compare-and-swap on its state:
//   - the worker finished it: the string is one chunk further on, in the worker's blocks;
//   - the worker had not started it: the audio thread steps the backup, which becomes the string;
//   - the worker is still stepping it: the audio thread spins until a deadline it chooses, then
//     revokes it and steps the backup, which becomes the string; the worker's result is thrown
//     away when it ends.
// The backup is an exact copy, so every outcome is the same arithmetic: the output is bit for bit
// what one thread makes, whoever stepped which string. The audio thread never waits beyond its
// deadline and never blocks: posting is an atomic store (a futex wake when the worker sleeps).
//
// A worker still busy with a revoked task is not idle(), and the audio thread does the whole chunk
// itself until it is. Whatever a task points into (a VoicePack) must outlive it: before freeing
// memory the audio thread has handed over, wait for jobsFinishedBy(postedJobs()) OFF.

#include "realtime/voice/Voice.h"

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

namespace jawari
{

class StringWorker
{
public:
    static constexpr int kMaxTasks = 16;

    struct Task
    {
        Voice* voice = nullptr;  // the string to step
        double* block = nullptr;   // its internal-rate samples
        double* second = nullptr;  // its second pickup's, or null
    };
    enum class Outcome
    {
        worker,      // stepped by the worker: take its blocks
        notStarted,  // the caller steps the original
        revoked      // the worker was late: the caller steps the original
    };

    StringWorker() = default;
    ~StringWorker();  // OFF: stop()
    StringWorker(const StringWorker&) = delete;
    StringWorker& operator=(const StringWorker&) = delete;

    // OFF: starts the worker's thread (running() from then on) / stops it after the job in hand.
    void start();
    void stop();
    bool running() const { return running_.load(std::memory_order_acquire); }

    // RT: the worker runs and has finished every job posted: it may take another.
    bool idle() const;
    // RT: the job posted last is finished (every task done or taken back).
    bool jobFinished() const { return finished_.load(std::memory_order_acquire) == posted_.load(std::memory_order_relaxed); }
    // RT: opens a job of `count` tasks (<= kMaxTasks) of `samples` host samples, each to be offered
    // before it is collected. Only when idle().
    void post(int count, int samples);
    // RT: task i of the job posted last, ready to step (the worker takes the tasks in order and
    // waits for one not yet offered).
    void offer(int i, const Task& task);
    // RT: task i's outcome, waiting for the worker at most until `deadline` if it is stepping it.
    Outcome collect(int i, std::chrono::steady_clock::time_point deadline);

    // OFF: the number of jobs posted so far, and a wait until the worker has finished (or dropped)
    // the first `jobs` of them.
    uint32_t postedJobs() const { return posted_.load(std::memory_order_acquire); }
    void waitForJobs(uint32_t jobs) const;

    // Tests: the worker's pace, whatever the machine's load. inStep: the audio thread waits until the
    // worker has claimed each task it offers, and when collecting one until the worker has finished
    // it: every task is the worker's. held: the audio thread waits until the worker has claimed the
    // job's first task, which the worker then holds, unstepped, until the pace changes: a worker
    // preempted mid-task, whose task the audio thread revokes. free: as in a performance.
    enum class Pace
    {
        free,
        inStep,
        held
    };
    void setPaceForTesting(Pace pace) { pace_.store(pace, std::memory_order_release); }
    // Tests: `hook(context)` runs on the worker's thread in each task it claims, before it steps the
    // string (to mark the thread). Set while the worker is idle; null unsets it.
    using TaskHook = void (*)(void* context);
    void setTaskHookForTesting(TaskHook hook, void* context);
    // How long the worker spins for the next job before it sleeps (it is woken by the next post).
    static constexpr std::chrono::microseconds kSpin{2000};

private:
    enum State : int
    {
        unready,  // posted, not yet offered
        posted,
        stepping,
        done,
        takenBack  // by the audio thread: not started, or revoked
    };
    void run();
    void runJob();
    bool waitForJob(uint32_t seen);  // false: stop

    std::array<Task, kMaxTasks> tasks_{};
    std::array<std::atomic<int>, kMaxTasks> state_{};
    int count_ = 0, samples_ = 0;
    std::atomic<uint32_t> posted_{0};    // jobs posted (the audio thread's)
    std::atomic<uint32_t> finished_{0};  // jobs the worker has finished
    std::atomic<uint32_t> signal_{0};    // changed by each post and by stop(): what a sleeping worker waits on
    std::atomic<bool> running_{false}, stopping_{false};
    std::atomic<Pace> pace_{Pace::free};
    std::atomic<TaskHook> hook_{nullptr};
    std::atomic<void*> hookContext_{nullptr};
    std::thread thread_;
};

}  // namespace jawari

// How the instrument steps its sounding strings through a chunk: each voice alone, the string bank,
// or shared with a second core (StringWorker.h). Every way writes the same samples.

#include "realtime/Instrument.h"

#include <algorithm>
#include <chrono>
#include <utility>

namespace jawari
{

// The worker takes at most all strings but one; post() keeps no more than kMaxTasks.
static_assert(kSlots - 1 <= StringWorker::kMaxTasks, "the second core's tasks must hold a share of every slot");

void Instrument::stepStrings(Sounding& s, int samples)
{
    if (scheduling_ == StringScheduling::bank)
        bank_.process(s.voices.data(), s.blocks.data(), s.count, samples, s.seconds.data());
    else if (worker_ != nullptr && s.count >= 2 && worker_->idle())
        stepWithWorker(s, samples);
    else
        for (int k = 0; k < s.count; ++k)
            s.voices[size_t(k)]->processInternal(s.blocks[size_t(k)], samples, s.seconds[size_t(k)]);
}

// The worker takes the last strings, each as a clone copied here, and steps them from the front of
// its share; the audio thread steps the first ones, then collects the worker's from the back: a
// clone the worker finished becomes the string (its blocks are the string's), and a string the
// worker has not started, or is still stepping after 1.5 times the audio thread's own mean time per
// string, the audio thread steps itself. The shares balance from chunk to chunk: about half each,
// one string more for the worker after a chunk it finished before the audio thread had stepped its
// own, one fewer after a chunk it did not finish.
void Instrument::stepWithWorker(Sounding& s, int samples)
{
    using Clock = std::chrono::steady_clock;
    const int n = s.count;
    workerBias_ = std::clamp(workerBias_, -n / 2, n / 2);
    const int own = std::clamp(n - n / 2 - workerBias_, 1, n - 1);
    const size_t chunkSteps = size_t(kChunk) * size_t(pack_->oversampling);
    std::array<StringWorker::Task, kSlots> tasks{};
    for (int k = own; k < n; ++k)
    {
        const size_t slot = size_t(s.slots[size_t(k)]);
        Voice& clone = *pack_->clones[slot];
        clone = *s.voices[size_t(k)];
        tasks[size_t(k - own)] = {&clone, pack_->workerBlocks.data() + slot * chunkSteps,
                                  pack_->workerSecondBlocks.data() + slot * chunkSteps};
    }
    worker_->post(tasks.data(), n - own, samples);
    const auto start = Clock::now();
    for (int k = 0; k < own; ++k)
        s.voices[size_t(k)]->processInternal(s.blocks[size_t(k)], samples, s.seconds[size_t(k)]);
    const auto patience = (Clock::now() - start) * 3 / (2 * own);
    bool late = false;
    if (worker_->jobFinished())
        ++workerBias_;  // the worker waited for the audio thread
    for (int k = n - 1; k >= own; --k)
    {
        const size_t slot = size_t(s.slots[size_t(k)]);
        const auto outcome = worker_->collect(k - own, Clock::now() + patience);
        if (outcome == StringWorker::Outcome::worker)
        {
            std::swap(pack_->voices[slot], pack_->clones[slot]);
            s.voices[size_t(k)] = pack_->voices[slot].get();
            s.blocks[size_t(k)] = tasks[size_t(k - own)].block;
            s.seconds[size_t(k)] = tasks[size_t(k - own)].second;
            ++activity_.workerStrings;
            continue;
        }
        late = true;
        if (outcome == StringWorker::Outcome::revoked)
            ++activity_.workerRevoked;
        s.voices[size_t(k)]->processInternal(s.blocks[size_t(k)], samples, s.seconds[size_t(k)]);
    }
    if (late)
        --workerBias_;
}

}  // namespace jawari

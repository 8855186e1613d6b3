// How the instrument steps its sounding strings through a chunk: each voice alone, the string bank,
// or shared with a second core (StringWorker.h). Every way writes the same samples.

#include "realtime/Instrument.h"

#include <chrono>
#include <utility>

namespace jawari
{

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

// The worker takes the last half of the sounding strings, each as a clone copied here, and steps
// them from the front of its half; the audio thread steps the first half, then collects the
// worker's from the back: a clone the worker finished becomes the string (its blocks are the
// string's), and a string the worker has not started, or is still stepping after 1.5 times the
// audio thread's own mean time per string, the audio thread steps itself.
void Instrument::stepWithWorker(Sounding& s, int samples)
{
    using Clock = std::chrono::steady_clock;
    const int n = s.count, own = n - n / 2;
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
        if (outcome == StringWorker::Outcome::revoked)
            ++activity_.workerRevoked;
        s.voices[size_t(k)]->processInternal(s.blocks[size_t(k)], samples, s.seconds[size_t(k)]);
    }
}

}  // namespace jawari

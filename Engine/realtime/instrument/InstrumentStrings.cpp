// How the instrument steps its sounding strings through a chunk: each voice alone, the string bank,
// or shared with a second core (StringWorker.h). Every way writes the same samples.

#include "realtime/instrument/Instrument.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace jawari
{

// The worker takes at most all strings but one; post() keeps no more than kMaxTasks.
static_assert(kSlots - 1 <= StringWorker::kMaxTasks, "the second core's tasks must hold a share of every slot");

void Instrument::stepStrings(Sounding& s, int samples)
{
    if (pack_->body)
        stepOnBody(s, samples);
    else if (scheduling_ == StringScheduling::bank)
        bank_.process(s.voices.data(), s.blocks.data(), s.count, samples, s.seconds.data());
    else if (worker_ != nullptr && s.count >= 2 && worker_->idle())
        stepWithWorker(s, samples);
    else
        for (int k = 0; k < s.count; ++k)
            s.voices[size_t(k)]->processInternal(s.blocks[size_t(k)], samples, s.seconds[size_t(k)]);
}

// Every sounding string, the sympathetic strings and the body in lockstep, one internal step at a
// time (SharedBody), on this thread; the body's radiated pressure at each channel (its listeners as
// the stereo width mixes them) into the pack's body blocks, and the share of it the sympathetic
// strings make into theirs. A body left ringing alone steps until it and its sympathetic strings
// are at rest.
void Instrument::stepOnBody(Sounding& s, int samples)
{
    auto& body = *pack_->body;
    body.listenBetween(bodyWidth_);
    body.keepPart(tarafShareHeard_);
    const long steps = long(samples) * pack_->oversampling;
    if (s.count == 0 && body.atRest() && sympathetic_.atRest())
    {
        for (size_t c = 0; c < 2; ++c)
        {
            std::fill(pack_->bodyBlocks[c].begin(), pack_->bodyBlocks[c].begin() + steps, 0.0);
            std::fill(pack_->sympatheticBlocks[c].begin(), pack_->sympatheticBlocks[c].end(), 0.0);
        }
        return;
    }
    // The sympathetic strings can hold no more than the played strings have had between them; while
    // a pluck's pulse still puts energy in, that is not known yet, and their guard is held open.
    double supply = 0.0;
    bool plucking = false;
    for (int i = 0; i < s.count; ++i)
    {
        supply += s.voices[size_t(i)]->energyCeiling();
        plucking = plucking || s.voices[size_t(i)]->pulsing();
    }
    for (int j = 0; j < sympathetic_.count(); ++j)
    {
        sympathetic_.voice(j).holdGuard(plucking);
        sympathetic_.voice(j).allowEnergy(supply);
    }
    std::array<ModalSolver*, kSlots + kMaxSympatheticStrings> solvers{};
    // The sympathetic strings held by their springs alone step as one bank through the chunk.
    const int taraf = sympathetic_.count();
    for (int j = 0; j < taraf; ++j)
        solvers[size_t(s.count + j)] = &sympathetic_.voice(j).solver();
    tarafBanked_ = taraf > 0 && body.bankLinear(solvers.data(), s.count, s.count + taraf);
    for (long k = 0; k < steps; ++k)
        stepBodyOnce(s, k, solvers.data());
    if (tarafBanked_)
        body.unbankLinear(solvers.data());
}

// One internal step k of the chunk, the strings' solvers handed to the body in `solvers`: writes the
// radiated pressure at each channel (Pa) and the sympathetic strings' share of it. A body that has
// run away, or whose played string has, is silenced with every string on it.
void Instrument::stepBodyOnce(Sounding& s, long k, ModalSolver** solvers)
{
    auto& body = *pack_->body;
    const int taraf = sympathetic_.count();
    for (int i = 0; i < s.count; ++i)
        solvers[i] = &s.voices[size_t(i)]->beginOnBody();
    if (!tarafBanked_)
        for (int j = 0; j < taraf; ++j)
            solvers[s.count + j] = &sympathetic_.voice(j).beginOnBody();
    body.step(solvers, s.count + taraf, s.count);
    ++activity_.bodySteps;
    activity_.bodySolves += body.lastEvaluations();
    activity_.bodyTrials += body.lastTrials();
    activity_.bodyResolves += body.lastResolved();
    bool ranAway = false;  // a string's guard restarted it: what it put into the body is no sound
    for (int i = 0; i < s.count; ++i)
    {
        activity_.bodyLivePoints += solvers[i]->livePointCount();
        activity_.bodyContactPoints += solvers[i]->contactCount();
        const long blowUps = s.voices[size_t(i)]->blowUps();
        s.blocks[size_t(i)][k] = s.voices[size_t(i)]->finishOnBody();
        ranAway = ranAway || s.voices[size_t(i)]->blowUps() != blowUps;
    }
    for (int j = 0; j < taraf && !tarafBanked_; ++j)
    {
        const long blowUps = sympathetic_.voice(j).blowUps();
        sympathetic_.voice(j).finishOnBody();  // unheard: the body carries them (the guard still runs)
        ranAway = ranAway || sympathetic_.voice(j).blowUps() != blowUps;
    }
    bool finite = true;
    for (size_t c = 0; c < 2; ++c)
    {
        const double p = body.pressure(int(c)), part = taraf > 0 ? body.partPressure(int(c)) : 0.0;
        pack_->bodyBlocks[c][size_t(k)] = p;
        if (taraf > 0)
            pack_->sympatheticBlocks[c][size_t(k)] = part;
        finite = finite && std::isfinite(p) && std::isfinite(part);
    }
    if (ranAway || !finite)
    {
        silenceBody(s);
        for (int i = 0; i < s.count; ++i)
            s.blocks[size_t(i)][k] = 0.0;  // what they played was moved by the runaway
        for (size_t c = 0; c < 2; ++c)
        {
            pack_->bodyBlocks[c][size_t(k)] = 0.0;
            if (taraf > 0)
                pack_->sympatheticBlocks[c][size_t(k)] = 0.0;
        }
    }
}

// The body and every string on it back at rest, the sympathetic strings' ceilings kept. A string
// that ran away moved the bridge under all the others in its step, and the body left moving would
// hand that energy on; a string restarted from rest (its ceiling 0) would trip its guard again.
void Instrument::silenceBody(Sounding& s)
{
    pack_->body->silence();
    for (int i = 0; i < s.count; ++i)
        s.voices[size_t(i)]->silence();
    for (int j = 0; j < sympathetic_.count(); ++j)
    {
        auto& v = sympathetic_.voice(j);
        const double ceiling = v.energyCeiling();  // still what the played strings have had
        const bool held = std::isinf(v.runawayLimit());
        v.silence();
        v.allowEnergy(ceiling);
        v.holdGuard(held);
    }
}

// The worker takes the last strings and steps them itself, from the front of its share (a string it
// keeps from chunk to chunk stays in its cache); before offering each one the audio thread copies
// it into its backup. The audio thread steps the first strings, then collects
// the worker's from the back: a string the worker finished is done (its blocks are the worker's),
// and one the worker has not started, or is still stepping after 1.5 times the audio thread's own
// mean time per string, the audio thread steps from its backup, which becomes the string.
// The shares balance from chunk to chunk, starting from half each: one string more for the worker
// after a chunk it finished before the audio thread had stepped its own; one fewer after a chunk in
// which it was late, or left two strings or more unstarted (one unstarted string is the slack that
// keeps the worker busy to the end).
void Instrument::stepWithWorker(Sounding& s, int samples)
{
    using Clock = std::chrono::steady_clock;
    const int n = s.count;
    workerBias_ = std::clamp(workerBias_, -n / 2, n / 2);
    const int own = std::clamp(n - n / 2 - workerBias_, 1, n - 1);
    const size_t chunkSteps = size_t(kChunk) * size_t(pack_->oversampling);
    std::array<StringWorker::Task, kSlots> tasks{};
    worker_->post(n - own, samples);
    for (int k = own; k < n; ++k)
    {
        const size_t slot = size_t(s.slots[size_t(k)]);
        *pack_->backups[slot] = *s.voices[size_t(k)];
        tasks[size_t(k - own)] = {s.voices[size_t(k)], pack_->workerBlocks.data() + slot * chunkSteps,
                                  pack_->workerSecondBlocks.data() + slot * chunkSteps};
        worker_->offer(k - own, tasks[size_t(k - own)]);
    }
    const auto start = Clock::now();
    for (int k = 0; k < own; ++k)
        s.voices[size_t(k)]->processInternal(s.blocks[size_t(k)], samples, s.seconds[size_t(k)]);
    const auto patience = (Clock::now() - start) * 3 / (2 * own);
    const bool early = worker_->jobFinished();  // the worker waited for the audio thread
    int unstarted = 0, revoked = 0;
    for (int k = n - 1; k >= own; --k)
    {
        const auto outcome = worker_->collect(k - own, Clock::now() + patience);
        if (outcome == StringWorker::Outcome::worker)
        {
            s.blocks[size_t(k)] = tasks[size_t(k - own)].block;
            s.seconds[size_t(k)] = tasks[size_t(k - own)].second;
            ++activity_.workerStrings;
            continue;
        }
        ++(outcome == StringWorker::Outcome::revoked ? revoked : unstarted);
        const size_t slot = size_t(s.slots[size_t(k)]);
        std::swap(pack_->voices[slot], pack_->backups[slot]);  // the backup is the string
        s.voices[size_t(k)] = pack_->voices[slot].get();
        s.voices[size_t(k)]->processInternal(s.blocks[size_t(k)], samples, s.seconds[size_t(k)]);
    }
    activity_.workerRevoked += revoked;
    activity_.workerUnstarted += unstarted;
    if (early)
        ++workerBias_;
    else if (revoked > 0 || unstarted >= 2)
        --workerBias_;
}

}  // namespace jawari

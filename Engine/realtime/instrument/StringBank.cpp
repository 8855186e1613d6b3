#include "realtime/instrument/StringBank.h"

#include <algorithm>

namespace jawari
{

void StringBank::process(Voice* const* voices, double* const* out, int count, int samples, double* const* second)
{
    count = std::min(count, kMaxStrings);
    for (int first = 0; first < count; first += groupSize_)
        processGroup(voices + first, out + first, second != nullptr ? second + first : nullptr,
                     std::min(groupSize_, count - first), samples);
}

void StringBank::processGroup(Voice* const* voices, double* const* out, double* const* second, int count,
                              int samples)
{
    if (count == 0)
        return;
    const long steps = long(samples) * voices[0]->oversampling();
    for (long k = 0; k < steps; ++k)
    {
        gather(voices, count);
        for (auto& batch : batches_)
            if (batch.count > 0)
                solveContactLanes(batch);
        for (int i = 0; i < count; ++i)
        {
            out[i][k] = voices[i]->finishSample(solutionOf(i));
            if (second != nullptr)
                second[i][k] = voices[i]->secondSample();
        }
    }
}

// Every string's step up to its contact solve; the equations into the lanes, in order. A batch
// takes the exponent of its first equation (the instrument's strings share one); an equation of
// another exponent, or of a bilateral law (closed form), is solved alone at once.
void StringBank::gather(Voice* const* voices, int count)
{
    for (auto& batch : batches_)
        batch.count = 0;
    int batchIndex = 0;
    for (int i = 0; i < count; ++i)
    {
        lane_[size_t(i)] = -1;
        if (i + 1 < count && voices[i + 1]->solver().nextStepPasses())
            voices[i + 1]->solver().prefetchPass();
        ScalarContactRequest request;
        if (!voices[i]->beginSample(request))
            continue;
        auto* batch = &batches_[size_t(batchIndex)];
        if (batch->count == kContactLanes)
            batch = &batches_[size_t(++batchIndex)];
        if (batch->count == 0)
        {
            batch->exponent = request.law.exponent;
            batch->series = request.series;
        }
        if (solve_ == Solve::scalar || request.law.bilateral || request.law.exponent != batch->exponent)
        {
            alone_[size_t(i)] = solveScalarContact(request);
            lane_[size_t(i)] = kMaxStrings + i;  // marks "solved alone"
            continue;
        }
        lane_[size_t(i)] = batchIndex * kContactLanes + batch->count;
        batch->add(request);
    }
}

const ScalarContactSolution* StringBank::solutionOf(int string) const
{
    const int lane = lane_[size_t(string)];
    if (lane < 0)
        return nullptr;
    if (lane >= kMaxStrings)
        return &alone_[size_t(string)];
    return &batches_[size_t(lane / kContactLanes)].solution[lane % kContactLanes];
}

}  // namespace jawari

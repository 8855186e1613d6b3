#pragma once
// The string bank (docs/design.md section 5, "The string bank"): every sounding string of the
// instrument stepped in lockstep, one internal sample at a time. Each string runs its own pass over
// its modes (vectorised over the modes, as a lone voice does); the contact solves of the strings
// whose step has one energy-conserving point are gathered, one string per SIMD lane, and solved
// together (ContactLanes.h), so the latency of the solve's chain of divisions is paid once per step
// for up to kContactLanes strings. Strings with other contact models take their whole step alone.
// Silent strings are simply not passed in. RT: no allocation.

#include "physics/contact/ContactLanes.h"
#include "realtime/voice/Voice.h"

#include <array>

namespace jawari
{

class StringBank
{
public:
    static constexpr int kMaxStrings = 16;

    // How the bank steps its strings: in groups of `groupSize` strings, each group in lockstep
    // through the whole call (a group's arrays stay in the first-level cache), with the group's
    // one-point solves in SIMD lanes or one after the other (independent chains the core overlaps).
    enum class Solve
    {
        lanes,
        scalar
    };
    void configure(int groupSize, Solve solve)  // RT
    {
        groupSize_ = groupSize < 1 ? 1 : (groupSize > kMaxStrings ? kMaxStrings : groupSize);
        solve_ = solve;
    }

    // RT: `samples` host samples of `count` (<= kMaxStrings) voices of one oversampling, at the
    // internal rate and undecimated: voice i's oversampling() x samples values into out[i] (and its
    // second pickup's into second[i], when `second` is given), each what voices[i]->processInternal()
    // would write.
    void process(Voice* const* voices, double* const* out, int count, int samples, double* const* second = nullptr);

private:
    int groupSize_ = kMaxStrings;
    Solve solve_ = Solve::lanes;
    void processGroup(Voice* const* voices, double* const* out, double* const* second, int count, int samples);
    static constexpr int kBatches = (kMaxStrings + kContactLanes - 1) / kContactLanes;
    std::array<ContactLaneBatch, kBatches> batches_;
    std::array<int, kMaxStrings> lane_{};  // the string's lane (batch x kContactLanes + lane), or -1
    std::array<ScalarContactSolution, kMaxStrings> alone_{};  // a string whose law differs from its batch's
    void gather(Voice* const* voices, int count);
    const ScalarContactSolution* solutionOf(int string) const;
};

}  // namespace jawari

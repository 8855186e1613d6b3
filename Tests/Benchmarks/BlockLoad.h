#pragma once
// Per-block processing time as a share of the block's real-time budget: its distribution (a
// histogram, so an hour of 32-sample blocks takes no more memory than a second) and the slowest
// blocks with what the instrument did in them (jawari-soak).

#include "realtime/instrument/Instrument.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace jawari
{

class BlockLoad
{
public:
    static constexpr int kSlowest = 8;

    BlockLoad()
        : histogram_(kBins, 0)
    {}

    // The block `index` took `share` of its budget (1 = all of it) while the instrument did `activity`.
    void add(long index, double share, const InstrumentActivity& activity)
    {
        const int bin = std::clamp(static_cast<int>(share / kBinWidth), 0, kBins - 1);
        ++histogram_[size_t(bin)];
        ++count_;
        most_ = std::max(most_, share);
        if (slowest_.size() < kSlowest || share > slowest_.back().share)
        {
            if (slowest_.size() == kSlowest)
                slowest_.pop_back();
            const Slow s{index, share, activity};
            slowest_.insert(std::upper_bound(slowest_.begin(), slowest_.end(), s,
                                             [](const Slow& a, const Slow& b) { return a.share > b.share; }),
                            s);
        }
    }

    // The share below which a fraction q of the blocks fall (to the histogram's 0.1 % of a budget).
    double percentile(double q) const
    {
        const long wanted = std::max<long>(1, static_cast<long>(q * double(count_) + 0.5));
        long seen = 0;
        for (int b = 0; b < kBins; ++b)
        {
            seen += histogram_[size_t(b)];
            if (seen >= wanted)
                return std::min((b + 1) * kBinWidth, most_);  // the bin's top edge, never above the maximum
        }
        return most_;
    }
    double most() const { return most_; }

    struct Slow
    {
        long index = 0;
        double share = 0.0;
        InstrumentActivity activity;
    };
    const std::vector<Slow>& slowest() const { return slowest_; }

    static std::string describe(const InstrumentActivity& a)
    {
        char text[260];
        std::snprintf(text, sizeof text,
                      "%d notes started, %d pulses, %d drone plucks, %d retunes, %d packs installed, %ld Newton "
                      "iterations (most %d in a step)",
                      a.notesStarted, a.pulses, a.dronePlucks, a.retunes, a.packsInstalled, a.newtonIterations,
                      a.mostIterations);
        std::string line = text;
        if (a.workerStrings > 0 || a.workerRevoked > 0)
        {
            std::snprintf(text, sizeof text, ", %ld strings on the second core, %ld taken back", a.workerStrings,
                          a.workerRevoked);
            line += text;
        }
        return line;
    }

private:
    static constexpr double kBinWidth = 0.001;
    static constexpr int kBins = 20000;  // up to 20 budgets
    std::vector<long> histogram_;
    long count_ = 0;
    double most_ = 0.0;
    std::vector<Slow> slowest_;
};

}  // namespace jawari
